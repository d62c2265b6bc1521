// The built-in environments, usable wherever an environment file is
// (`--env sky`, `--env room`): no file needed.

use std::fmt;
use std::str::FromStr;

use envmap_core::glam::Vec3;
use envmap_core::{AnyMapping, Atlas, Frame};

use crate::error::{Error, Result};
use crate::image::{EnvImage, Representation};
use crate::scene::procedural;

const BLACK: [f32; 3] = [0.0; 3];

/// `d` scaled to unit length, or `None` for a zero or non-finite `d`. Scales
/// by the largest component first, so huge and tiny finite vectors work too.
#[inline]
fn unit(d: Vec3) -> Option<Vec3> {
    if !d.is_finite() {
        return None;
    }
    let m = d.abs().max_element();
    if m == 0.0 {
        return None;
    }
    let d = d / m;
    Some(d / d.length())
}

#[inline]
fn lerp3(a: [f32; 3], b: [f32; 3], t: f32) -> [f32; 3] {
    [
        a[0] + (b[0] - a[0]) * t,
        a[1] + (b[1] - a[1]) * t,
        a[2] + (b[2] - a[2]) * t,
    ]
}

#[inline]
fn add_scaled(a: [f32; 3], b: [f32; 3], s: f32) -> [f32; 3] {
    [a[0] + b[0] * s, a[1] + b[1] * s, a[2] + b[2] * s]
}

// ---------------------------------------------------------------------------
// Sky
// ---------------------------------------------------------------------------

/// The default sun's elevation above the horizon, in degrees.
pub const SUN_ELEVATION_DEG: f32 = 35.0;
/// The default sun's azimuth, in degrees from +x towards +y.
pub const SUN_AZIMUTH_DEG: f32 = 40.0;
/// The default sun disk's angular radius, in degrees (the real sun's is about
/// 0.27°; this one is larger so that it covers a few texels).
pub const SUN_RADIUS_DEG: f32 = 0.6;
/// The default sun disk's radiance (linear RGB, warm white).
pub const SUN_RADIANCE: [f32; 3] = [5000.0, 4700.0, 4200.0];

/// The unit direction at `elevation_deg` above the horizon and `azimuth_deg`
/// from +x towards +y (z up).
///
/// ```
/// use envmap_render::scene::direction_from_angles;
/// let d = direction_from_angles(90.0, 0.0);
/// assert!((d.z - 1.0).abs() < 1e-6);
/// ```
#[must_use]
pub fn direction_from_angles(elevation_deg: f32, azimuth_deg: f32) -> Vec3 {
    let (se, ce) = elevation_deg.to_radians().sin_cos();
    let (sa, ca) = azimuth_deg.to_radians().sin_cos();
    Vec3::new(ce * ca, ce * sa, se)
}

/// The constants of `sky_with`; [`SkyParams::default`] is the sky of
/// [`sky`]. Colours are linear RGB radiances.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SkyParams {
    /// Direction towards the sun's centre (normalised on use). Default:
    /// elevation 35°, azimuth 40° (`direction_from_angles`).
    pub sun_direction: Vec3,
    /// The sun disk's angular radius in degrees. Default 0.6°.
    pub sun_radius_deg: f32,
    /// The sun disk's radiance. Default [`SUN_RADIANCE`].
    pub sun_radiance: [f32; 3],
    /// The peak of the glow added around the sun, falling off as
    /// `exp(−θ² / w²)` with the angle θ from the sun's centre. Default
    /// (30, 26, 20).
    pub glow_radiance: [f32; 3],
    /// The glow's width `w` in degrees. Default 3°.
    pub glow_width_deg: f32,
    /// The peak of a second, wider and fainter halo. Default (0.8, 0.7, 0.5).
    pub halo_radiance: [f32; 3],
    /// The halo's width in degrees. Default 20°.
    pub halo_width_deg: f32,
    /// The sky's colour at the zenith. Default (0.10, 0.25, 0.75).
    pub zenith: [f32; 3],
    /// The sky's colour at the horizon, also the haze the ground fades into.
    /// Default (0.85, 0.92, 1.05).
    pub horizon: [f32; 3],
    /// Height of the eye above the ground plane: a downward ray `d` hits the
    /// ground at `d · eye_height / −d.z`. Default 1.
    pub eye_height: f32,
    /// Side of a checker square on the ground. Default 1.
    pub checker_size: f32,
    /// The light squares' colour (those whose integer coordinates sum to an
    /// even number). Default 0.55 grey.
    pub ground_light: [f32; 3],
    /// The dark squares' colour. Default 0.12 grey.
    pub ground_dark: [f32; 3],
    /// The ground fades into the horizon colour as `exp(−t / fog_distance)`
    /// with the distance `t` along the ray. Default 25.
    pub fog_distance: f32,
}

impl Default for SkyParams {
    fn default() -> Self {
        SkyParams {
            sun_direction: direction_from_angles(SUN_ELEVATION_DEG, SUN_AZIMUTH_DEG),
            sun_radius_deg: SUN_RADIUS_DEG,
            sun_radiance: SUN_RADIANCE,
            glow_radiance: [30.0, 26.0, 20.0],
            glow_width_deg: 3.0,
            halo_radiance: [0.8, 0.7, 0.5],
            halo_width_deg: 20.0,
            zenith: [0.10, 0.25, 0.75],
            horizon: [0.85, 0.92, 1.05],
            eye_height: 1.0,
            checker_size: 1.0,
            ground_light: [0.55; 3],
            ground_dark: [0.12; 3],
            fog_distance: 25.0,
        }
    }
}

/// `exp(−θ²/w²)` written with `1 − cos`, which is θ²/2 for small angles.
#[inline]
fn falloff(one_minus_cos: f32, width_deg: f32) -> f32 {
    let w = 1.0 - width_deg.to_radians().cos();
    if w > 0.0 {
        (-one_minus_cos / w).exp()
    } else {
        0.0
    }
}

/// The default sky ([`SkyParams::default`]) along `d`; see `sky_with`.
#[must_use]
pub fn sky(d: Vec3) -> [f32; 3] {
    sky_with(&SkyParams::default(), d)
}

/// The sky `p` along `d` (world axes, z up; need not be unit length).
///
/// Above the horizon (`z ≥ 0`): `horizon` blended towards `zenith` by
/// `1 − (1 − z)³`, plus the glow and halo around the sun; inside the sun disk
/// (angle to the sun below `sun_radius_deg`, and `z ≥ 0`) the radiance is
/// `sun_radiance` exactly. Below it (`z < 0`): the checker square hit on the
/// plane `eye_height` below the eye, blended into `horizon` plus glow and
/// halo by its distance, so the two halves meet continuously at the horizon.
/// Black for a zero or non-finite `d`.
#[must_use]
pub(crate) fn sky_with(p: &SkyParams, d: Vec3) -> [f32; 3] {
    let Some(d) = unit(d) else {
        return BLACK;
    };
    let sun = p.sun_direction.normalize_or_zero();
    let one_minus_cos = (1.0 - d.dot(sun)).clamp(0.0, 2.0);
    let glow = add_scaled(
        [0.0; 3],
        p.glow_radiance,
        falloff(one_minus_cos, p.glow_width_deg),
    );
    let glow = add_scaled(
        glow,
        p.halo_radiance,
        falloff(one_minus_cos, p.halo_width_deg),
    );
    let haze = [
        p.horizon[0] + glow[0],
        p.horizon[1] + glow[1],
        p.horizon[2] + glow[2],
    ];
    if d.z >= 0.0 {
        if sun != Vec3::ZERO && one_minus_cos <= 1.0 - p.sun_radius_deg.to_radians().cos() {
            return p.sun_radiance;
        }
        let s = 1.0 - d.z;
        let w = 1.0 - s * s * s;
        let base = lerp3(p.horizon, p.zenith, w);
        return [base[0] + glow[0], base[1] + glow[1], base[2] + glow[2]];
    }
    // Distance along the ray to the ground plane.
    let t = p.eye_height / -d.z;
    let visible = if p.fog_distance > 0.0 {
        (-t / p.fog_distance).exp()
    } else {
        0.0
    };
    let draw = visible > 1e-7 && p.checker_size > 0.0;
    if !draw {
        return haze;
    }
    let cx = (d.x * t / p.checker_size).floor();
    let cy = (d.y * t / p.checker_size).floor();
    let ground = if (cx + cy).rem_euclid(2.0) < 1.0 {
        p.ground_light
    } else {
        p.ground_dark
    };
    lerp3(haze, ground, visible)
}

// ---------------------------------------------------------------------------
// Room
// ---------------------------------------------------------------------------

/// The room's corner at minimum x, y, z, relative to the eye: the room is
/// 8 (x) × 6 (y) × 3 (z) units with the eye at its centre, 1.5 above the
/// floor.
pub const ROOM_MIN: Vec3 = Vec3::new(-4.0, -3.0, -1.5);
/// The room's corner at maximum x, y, z, relative to the eye.
pub const ROOM_MAX: Vec3 = Vec3::new(4.0, 3.0, 1.5);

/// The +x wall's colour (red).
pub const WALL_POS_X: [f32; 3] = [0.65, 0.12, 0.10];
/// The −x wall's colour (green).
pub const WALL_NEG_X: [f32; 3] = [0.12, 0.50, 0.15];
/// The +y wall's colour (blue); this wall holds the window.
pub const WALL_POS_Y: [f32; 3] = [0.12, 0.20, 0.60];
/// The −y wall's colour (yellow).
pub const WALL_NEG_Y: [f32; 3] = [0.70, 0.60, 0.12];
/// The ceiling's colour (off-white).
pub const CEILING: [f32; 3] = [0.75, 0.75, 0.72];
/// The floor's two tile colours (light and dark wood), in a checker of
/// [`FLOOR_TILE`]-unit tiles aligned with the room's walls.
pub const FLOOR_TILES: [[f32; 3]; 2] = [[0.45, 0.30, 0.18], [0.22, 0.14, 0.09]];
/// The floor tiles' side.
pub const FLOOR_TILE: f32 = 1.0;
/// Width of the grout lines between floor tiles (centred on the tile edges).
pub const GROUT_WIDTH: f32 = 0.04;
/// The grout's colour.
pub const GROUT: [f32; 3] = [0.60, 0.60, 0.58];

/// The ceiling lights as `[x_min, x_max, y_min, y_max]` on the ceiling
/// (z = [`ROOM_MAX`].z): a long one over +x and a small square one over −x,+y,
/// placed asymmetrically so that a mirrored or rotated face shows.
pub const LIGHTS: [[f32; 4]; 2] = [[0.75, 2.75, -0.6, 0.6], [-2.5, -1.5, 0.4, 1.4]];
/// The ceiling lights' radiance.
pub const LIGHT_RADIANCE: [f32; 3] = [20.0, 19.0, 17.0];

/// The window in the +y wall as `[x_min, x_max, z_min, z_max]`: through it
/// the [`sky`] is seen, at infinity, along the same direction (so its horizon
/// is at the eye's height and the sun is not in view).
pub const WINDOW: [f32; 4] = [-3.0, -0.5, -0.5, 1.0];

#[inline]
fn inside(a: f32, b: f32, r: [f32; 4]) -> bool {
    a >= r[0] && a <= r[1] && b >= r[2] && b <= r[3]
}

/// The radiance seen from the room's centre (the eye) along `d` (world axes,
/// z up): the ray is intersected with the room's six planes ([`ROOM_MIN`],
/// [`ROOM_MAX`]) and the nearest hit gives the surface. Walls are flat
/// colours ([`WALL_POS_X`] ...), the floor is tiled ([`FLOOR_TILES`]), the
/// ceiling carries two lights ([`LIGHTS`]) and the +y wall a window
/// ([`WINDOW`]) showing [`sky`]. Discontinuous at the room's edges and the
/// edges of tiles, lights and window. Black for a zero or non-finite `d`.
#[must_use]
pub fn room(d: Vec3) -> [f32; 3] {
    let Some(d) = unit(d) else {
        return BLACK;
    };
    // Distance to the plane the ray meets on each axis (infinite if parallel).
    let dist = |c: f32, lo: f32, hi: f32| {
        if c > 0.0 {
            hi / c
        } else if c < 0.0 {
            lo / c
        } else {
            f32::INFINITY
        }
    };
    let tx = dist(d.x, ROOM_MIN.x, ROOM_MAX.x);
    let ty = dist(d.y, ROOM_MIN.y, ROOM_MAX.y);
    let tz = dist(d.z, ROOM_MIN.z, ROOM_MAX.z);
    if tz <= tx && tz <= ty {
        let p = d * tz;
        if d.z > 0.0 {
            if LIGHTS.iter().any(|&r| inside(p.x, p.y, r)) {
                LIGHT_RADIANCE
            } else {
                CEILING
            }
        } else {
            floor_tile(p.x, p.y)
        }
    } else if ty <= tx {
        if d.y > 0.0 {
            let p = d * ty;
            if inside(p.x, p.z, WINDOW) {
                sky(d)
            } else {
                WALL_POS_Y
            }
        } else {
            WALL_NEG_Y
        }
    } else if d.x > 0.0 {
        WALL_POS_X
    } else {
        WALL_NEG_X
    }
}

/// The floor's colour at `(x, y)`: checker tiles with grout lines.
#[inline]
fn floor_tile(x: f32, y: f32) -> [f32; 3] {
    let (u, v) = (x / FLOOR_TILE, y / FLOOR_TILE);
    let half = 0.5 * GROUT_WIDTH / FLOOR_TILE;
    let near_edge = |a: f32| {
        let f = a - a.round();
        f.abs() < half
    };
    if near_edge(u) || near_edge(v) {
        return GROUT;
    }
    let k = (u.floor() + v.floor()).rem_euclid(2.0);
    FLOOR_TILES[usize::from(k >= 1.0)]
}

/// The room captured as seed `002` describes: six views rendered from the
/// eye, one per GL cube face (`face_size × face_size` each, the direction
/// through each texel's centre evaluated with [`room`]), laid out as a
/// horizontal cross ([`Atlas::CUBE_HORIZONTAL_CROSS`], world axes as the
/// cube's, so the +z face is the ceiling). Used as an environment map, and
/// converted to any other representation, this is the two-pass method.
///
/// # Errors
///
/// If the image would be empty or too large (`face_size` 0 or huge).
#[cfg_attr(not(feature = "instruments"), allow(dead_code))]
#[cfg_attr(feature = "instruments", visibility::make(pub))]
pub(crate) fn room_cube(face_size: u32) -> Result<EnvImage> {
    let repr = Representation::new(
        AnyMapping::Cube,
        Atlas::CUBE_HORIZONTAL_CROSS,
        Frame::IDENTITY,
    )?;
    let (Some(w), Some(h)) = (face_size.checked_mul(4), face_size.checked_mul(3)) else {
        let (w, h) = (4 * u64::from(face_size), 3 * u64::from(face_size));
        return Err(Error::TooLarge {
            width: w,
            height: h,
            texels: w * h,
            limit: crate::image::DEFAULT_MAX_TEXELS,
        });
    };
    procedural::fill(repr, w, h, room)
}

// ---------------------------------------------------------------------------
// By name
// ---------------------------------------------------------------------------

/// A built-in environment, by name (`--env sky`, `--env room`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Builtin {
    /// [`sky`].
    Sky,
    /// [`room`].
    Room,
}

impl Builtin {
    /// Every built-in environment.
    pub const ALL: [Builtin; 2] = [Builtin::Sky, Builtin::Room];

    /// The name on the command line: `"sky"` or `"room"`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Builtin::Sky => "sky",
            Builtin::Room => "room",
        }
    }

    /// The exact radiance along `d` (world axes, z up).
    #[must_use]
    pub fn radiance(self, d: Vec3) -> [f32; 3] {
        match self {
            Builtin::Sky => sky(d),
            Builtin::Room => room(d),
        }
    }

    /// The environment evaluated at every texel centre of a `width × height`
    /// image in `repr` ([`procedural::fill`]). For the room this evaluates
    /// [`room`] directly; `room_cube` gives its six-view capture instead.
    ///
    /// # Errors
    ///
    /// If the size does not suit `repr` or is too large.
    pub fn image(self, repr: Representation, width: u32, height: u32) -> Result<EnvImage> {
        match self {
            Builtin::Sky => procedural::fill(repr, width, height, sky),
            Builtin::Room => procedural::fill(repr, width, height, room),
        }
    }
}

impl fmt::Display for Builtin {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Builtin {
    type Err = Error;

    /// `"sky"` or `"room"`, case-insensitive.
    fn from_str(s: &str) -> Result<Self> {
        Builtin::ALL
            .into_iter()
            .find(|b| s.eq_ignore_ascii_case(b.name()))
            .ok_or_else(|| Error::UnknownName {
                what: "environment",
                name: s.to_owned(),
                expected: "sky, room".to_owned(),
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn finite_non_negative(c: [f32; 3]) -> bool {
        c.iter().all(|v| v.is_finite() && *v >= 0.0)
    }

    fn lum(c: [f32; 3]) -> f32 {
        0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]
    }

    /// Directions on a latitude–longitude grid including both poles and
    /// the horizon with both signs of zero.
    fn sweep() -> Vec<Vec3> {
        let mut v = Vec::new();
        for i in 0..=360 {
            let el = (i as f32 / 360.0 - 0.5) * std::f32::consts::PI;
            for j in 0..720 {
                let az = j as f32 / 720.0 * std::f32::consts::TAU;
                let (se, ce) = el.sin_cos();
                v.push(Vec3::new(ce * az.cos(), ce * az.sin(), se));
            }
        }
        for j in 0..720 {
            let az = j as f32 / 720.0 * std::f32::consts::TAU;
            v.push(Vec3::new(az.cos(), az.sin(), 0.0));
            v.push(Vec3::new(az.cos(), az.sin(), -0.0));
            v.push(Vec3::new(az.cos(), az.sin(), -1e-30));
            v.push(Vec3::new(az.cos(), az.sin(), -1e-7));
        }
        v.extend([
            Vec3::Z,
            -Vec3::Z,
            Vec3::new(0.0, 0.0, 1e-30),
            Vec3::new(1e30, -1e30, 1e30),
            Vec3::new(1e-40, 0.0, -1e-40),
        ]);
        v
    }

    #[test]
    fn sky_finite_non_negative_everywhere() {
        for d in sweep() {
            let c = sky(d);
            assert!(finite_non_negative(c), "{d:?} -> {c:?}");
            assert!(lum(c) > 0.0, "{d:?} -> {c:?}");
        }
    }

    #[test]
    fn sky_sun_is_hdr_and_sharp() {
        let p = SkyParams::default();
        let s = p.sun_direction;
        assert!((s.length() - 1.0).abs() < 1e-6);
        assert!((s.z - SUN_ELEVATION_DEG.to_radians().sin()).abs() < 1e-6);
        assert!(sky(s).iter().all(|&v| v > 1000.0), "{:?}", sky(s));
        // Inside the disk, just below its radius.
        let axis = s.cross(Vec3::Z).normalize();
        let rot = |deg: f32| envmap_core::glam::Quat::from_axis_angle(axis, deg.to_radians()) * s;
        assert!(sky(rot(0.55)).iter().all(|&v| v > 1000.0));
        let c = sky(rot(2.0));
        assert!(c.iter().all(|&v| v < 100.0), "{c:?}");
        assert!(lum(c) > lum(sky(rot(10.0))), "glow falls off");
        // Far from the sun the sky is of ordinary brightness.
        assert!(sky(-s + Vec3::new(0.0, 0.0, 1.5)).iter().all(|&v| v < 2.0));
    }

    #[test]
    fn sky_gradient_horizon_paler_zenith_bluer() {
        // Away from the sun (azimuth 220°).
        let h = sky(direction_from_angles(0.5, 220.0));
        let z = sky(Vec3::Z);
        assert!(lum(h) > lum(z));
        assert!(z[2] / z[0] > h[2] / h[0], "zenith deeper blue");
    }

    #[test]
    fn sky_checker_alternates_below_horizon() {
        // Eye 1 above the plane: direction (x, y, −1) hits (x, y).
        let a = sky(Vec3::new(0.5, 0.5, -1.0));
        let b = sky(Vec3::new(1.5, 0.5, -1.0));
        let c = sky(Vec3::new(1.5, 1.5, -1.0));
        let e = sky(Vec3::new(-0.5, 0.5, -1.0));
        assert_ne!(a, b);
        assert_ne!(b, c);
        assert_ne!(a, e);
        // Diagonal neighbours at the same distance are the same grey (up to
        // the sun's faint halo, which depends on azimuth).
        let close = |p: [f32; 3], q: [f32; 3]| (0..3).all(|k| (p[k] - q[k]).abs() < 1e-3);
        assert!(close(a, sky(Vec3::new(-0.5, -0.5, -1.0))));
        assert!(close(b, sky(Vec3::new(-1.5, -0.5, -1.0))));
        assert!(!close(a, b));
        // Light square at (0, 0).
        assert!(lum(a) > lum(b));
    }

    #[test]
    fn sky_continuous_at_horizon() {
        for j in 0..36 {
            let az = (j * 10) as f32;
            let above = sky(direction_from_angles(0.001, az));
            let below = sky(direction_from_angles(-0.001, az));
            for k in 0..3 {
                assert!(
                    (above[k] - below[k]).abs() < 1e-3,
                    "{az}: {above:?} {below:?}"
                );
            }
        }
    }

    #[test]
    fn bad_input_is_black() {
        for d in [
            Vec3::ZERO,
            Vec3::NAN,
            Vec3::new(f32::NAN, 0.0, 1.0),
            Vec3::new(f32::INFINITY, 0.0, 0.0),
            Vec3::new(0.0, f32::NEG_INFINITY, 1.0),
        ] {
            assert_eq!(sky(d), BLACK);
            assert_eq!(room(d), BLACK);
            for b in Builtin::ALL {
                assert_eq!(b.radiance(d), BLACK);
            }
        }
    }

    #[test]
    fn room_walls_distinct_colours() {
        let walls = [
            (Vec3::X, WALL_POS_X),
            (-Vec3::X, WALL_NEG_X),
            (Vec3::Y, WALL_POS_Y),
            (-Vec3::Y, WALL_NEG_Y),
        ];
        for (d, c) in walls {
            assert_eq!(room(d), c, "{d:?}");
        }
        for (i, a) in walls.iter().enumerate() {
            for b in &walls[i + 1..] {
                assert_ne!(a.1, b.1);
            }
        }
        assert_eq!(room(Vec3::Z), CEILING);
        assert!(FLOOR_TILES.contains(&room(-Vec3::Z)) || room(-Vec3::Z) == GROUT);
    }

    #[test]
    fn room_floor_tiles_alternate() {
        let z = ROOM_MIN.z;
        let a = room(Vec3::new(0.5, 0.5, z));
        let b = room(Vec3::new(1.5, 0.5, z));
        let g = room(Vec3::new(1.0, 0.5, z));
        assert!(FLOOR_TILES.contains(&a) && FLOOR_TILES.contains(&b));
        assert_ne!(a, b);
        assert_eq!(g, GROUT);
    }

    #[test]
    fn room_lights_bright() {
        for r in LIGHTS {
            let d = Vec3::new(0.5 * (r[0] + r[1]), 0.5 * (r[2] + r[3]), ROOM_MAX.z);
            assert_eq!(room(d), LIGHT_RADIANCE);
            assert!(lum(room(d)) > 10.0);
        }
    }

    #[test]
    fn room_window_shows_sky() {
        for (x, z) in [(-1.75, 0.25), (-2.9, 0.9), (-0.6, -0.4)] {
            let d = Vec3::new(x, ROOM_MAX.y, z);
            let (r, s) = (room(d), sky(d));
            for k in 0..3 {
                assert!((r[k] - s[k]).abs() <= 1e-5 * s[k].abs().max(1.0), "{d:?}");
            }
        }
        // Below the eye the window shows the sky's ground.
        let d = Vec3::new(-1.75, ROOM_MAX.y, -0.4);
        assert!(lum(room(d)) < lum(room(Vec3::new(-1.75, ROOM_MAX.y, 0.4))));
        // Beside the window, the wall.
        assert_eq!(room(Vec3::new(-3.2, ROOM_MAX.y, 0.25)), WALL_POS_Y);
        assert_eq!(room(Vec3::new(-1.75, ROOM_MAX.y, 1.2)), WALL_POS_Y);
    }

    #[test]
    fn room_finite_everywhere() {
        for d in sweep() {
            let c = room(d);
            assert!(finite_non_negative(c) && lum(c) > 0.0, "{d:?} -> {c:?}");
        }
    }

    #[test]
    fn room_cube_faces_filled_and_oriented() {
        let n = 8;
        let img = room_cube(n).unwrap();
        assert_eq!((img.width(), img.height()), (4 * n, 3 * n));
        for face in 0..6 {
            for j in 0..n {
                for i in 0..n {
                    let c = img.chart_texel(face, i, j).unwrap();
                    assert!(
                        finite_non_negative(c) && lum(c) > 0.0,
                        "face {face} ({i}, {j})"
                    );
                }
            }
        }
        // GL faces: +x 0, −x 1, +y 2, −y 3, +z 4, −z 5. The centre-adjacent
        // texels of each wall face show that wall.
        let mid = n / 2;
        assert_eq!(img.chart_texel(0, mid, mid), Some(WALL_POS_X));
        assert_eq!(img.chart_texel(1, mid, mid), Some(WALL_NEG_X));
        assert_eq!(img.chart_texel(3, mid, mid), Some(WALL_NEG_Y));
        // The ceiling face holds the long light.
        let bright = (0..n)
            .flat_map(|j| (0..n).map(move |i| (i, j)))
            .filter(|&(i, j)| lum(img.chart_texel(4, i, j).unwrap()) > 10.0)
            .count();
        assert!(bright > 0);
        // Matches the analytic room at each texel's direction.
        let exact = Builtin::Room
            .image(*img.representation(), 4 * n, 3 * n)
            .unwrap();
        assert_eq!(exact.pixels(), img.pixels());
        assert!(room_cube(0).is_err());
    }

    #[test]
    fn builtin_names_round_trip() {
        for b in Builtin::ALL {
            assert_eq!(b.name().parse::<Builtin>().unwrap(), b);
            assert_eq!(b.to_string().parse::<Builtin>().unwrap(), b);
        }
        assert_eq!("SKY".parse::<Builtin>().unwrap(), Builtin::Sky);
        let e = "beach".parse::<Builtin>().unwrap_err().to_string();
        assert!(
            e.contains("beach") && e.contains("sky") && e.contains("room"),
            "{e}"
        );
    }

    #[test]
    fn builtin_image_latlong() {
        let repr = Representation::default_for(AnyMapping::LatLong);
        let img = Builtin::Sky.image(repr, 64, 32).unwrap();
        assert!(img.pixels().iter().all(|&c| finite_non_negative(c)));
        let peak = img.pixels().iter().map(|&c| lum(c)).fold(0.0, f32::max);
        assert!(peak > 1.0);
    }
}
