//! Fisheye lenses: equidistant and equisolid, a field of view up to 360°, one lens or two back
//! to back (the raw frames of 360° cameras).
//!
//! # Formula
//!
//! θ is the angle of a direction from the lens's axis, φ its azimuth about the axis, and r the
//! distance of its image point from the image circle's centre, 1 on the circle; F is the full
//! field of view (the circle is θ = F/2). The two lens laws are those of J. Kannala and
//! S. Brandt, "A generic camera model and calibration method for conventional, wide-angle, and
//! fish-eye lenses" (IEEE TPAMI 28(8), 2006), table 1, scaled so that the circle is r = 1:
//!
//! ```text
//! equidistant (f·θ; ffmpeg v360's `fisheye`):        r = θ / (F/2)
//! equisolid (2f·sin(θ/2); equal-area, most real fisheye lenses and all-sky cameras):
//!                                                     r = sin(θ/2) / sin(F/4)
//! ```
//!
//! At F = 360° the equidistant lens is the angular map's law (Debevec's light probe) and the
//! equisolid lens the mirror ball's (the sphere map), about +z.
//!
//! # Axes, charts and what a lens does not see
//!
//! One lens looks along +z, with +x to the right of its image and +y up:
//! `u = ½ + ½ r x/ρ`, `v = ½ − ½ r y/ρ` (ρ = √(x² + y²)); the image circle is the disk inscribed
//! in the chart's square. Two lenses (`dual`) are chart 0, looking along +z as above, and
//! chart 1 looking along −z, whose image has −x to the right (seen from inside, as its camera
//! sees): `u = ½ − ½ r x/ρ`. A direction goes to the lens whose hemisphere it is in (z ≥ 0, −0
//! included: chart 0). Each lens has the field of view F, so two lenses of more than 180° overlap
//! around the equator and only the nearer one is read; two of less than 180° leave a band
//! around the equator unseen.
//!
//! A direction beyond the field of view is not seen: [`Fisheye::forward`] gives `None` for it,
//! as for a NaN or zero direction. Whoever converts a fisheye image must say what such
//! directions hold.
//!
//! # Where it is available
//!
//! Everywhere a mapping is: [`AnyMapping::Fisheye`](crate::AnyMapping::Fisheye) (with
//! [`Fisheye::SINGLE`] and [`Fisheye::DUAL`] in `AnyMapping::ALL`), the eight-wide kernels of
//! `envmap-simd`, and the `envmap` command (`--to fisheye --fov 190`, `--from dual-fisheye`).
//! A fisheye that does not cover the sphere ([`Fisheye::covers_sphere`]) is the one mapping
//! whose forward mapping leaves directions without a point.
//!
//! # Area element and solid angles
//!
//! In disk coordinates (x', y') = (2u − 1, 2v − 1), ρ' their radius and k = F/2:
//! equidistant, θ = kρ', so dΩ = sin θ dθ dφ = k sin(kρ')/ρ' dx' dy'; equisolid,
//! Ω(θ) = 4π sin²(θ/2) = 4π sin²(k/2) ρ'², so dΩ = 4 sin²(k/2) dx' dy', uniform (the lens is
//! equal-area). A lens's disk totals 2π(1 − cos k). Texel solid angles are exact
//! ([`crate::solid_angle::fisheye`]).
//!
//! Two lenses of more than 180° each own only their hemisphere (the directions `forward`
//! sends to them): the disk of radius ρ₀ = (π/2)/k (equidistant) or sin(π/4)/sin(k/2)
//! (equisolid) around the centre. Scaled by 1/ρ₀ that disk is the image circle of a 180°
//! lens of the same law (the density scales to the same form), so its solid angles are a
//! 180° lens's on the rectangle scaled about the centre, and the atlas totals 4π.

use core::f32::consts::PI;

use glam::Vec3;

use crate::atlas::Atlas;
use crate::direction::normalize_direction;
use crate::mapping::{in_unit_disk, ChartUv, Mapping};
use crate::math;

/// A fisheye lens's law: how the angle from the axis becomes the image radius.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Lens {
    /// r ∝ θ (ffmpeg v360's `fisheye`, the angular map at 360°).
    #[default]
    Equidistant,
    /// r ∝ sin(θ/2): equal-area (most real fisheye lenses, all-sky cameras).
    Equisolid,
}

impl Lens {
    /// Both laws, in the order of [`Lens::NAMES`].
    pub const ALL: [Lens; 2] = [Lens::Equidistant, Lens::Equisolid];

    /// The names the command line and file metadata use.
    pub const NAMES: [&'static str; 2] = ["equidistant", "equisolid"];

    /// The law's name: `equidistant` or `equisolid`.
    #[must_use]
    pub const fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }

    /// The law named `name` (case-insensitive; `equal-area` is the equisolid law), if any.
    #[must_use]
    pub fn from_name(name: &str) -> Option<Lens> {
        if name.eq_ignore_ascii_case("equal-area") {
            return Some(Lens::Equisolid);
        }
        Lens::ALL
            .into_iter()
            .find(|l| l.name().eq_ignore_ascii_case(name))
    }
}

impl core::fmt::Display for Lens {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.name())
    }
}

/// One fisheye lens or two back to back; see the [module docs](self).
///
/// The field of view is held in thousandths of a degree, so that two lenses compare equal
/// (and hash alike) when their fields of view print alike.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Fisheye {
    lens: Lens,
    fov_millidegrees: u32,
    dual: bool,
}

impl Default for Fisheye {
    /// [`Fisheye::SINGLE`]: one equidistant lens of 180°.
    fn default() -> Self {
        Fisheye::SINGLE
    }
}

impl Fisheye {
    /// One equidistant lens of 180° looking along +z: ffmpeg v360's `fisheye` with its
    /// default field of view; what `fisheye` means without `--fov`.
    pub const SINGLE: Fisheye = Fisheye {
        lens: Lens::Equidistant,
        fov_millidegrees: 180_000,
        dual: false,
    };

    /// Two equidistant lenses of 180° back to back, side by side: ffmpeg v360's `dfisheye`
    /// with its default field of view; what `dual-fisheye` means without `--fov`.
    pub const DUAL: Fisheye = Fisheye {
        lens: Lens::Equidistant,
        fov_millidegrees: 180_000,
        dual: true,
    };

    /// Whether every direction is seen: two lenses of 180° or more, or one of 360°.
    #[must_use]
    pub const fn covers_sphere(self) -> bool {
        if self.dual {
            self.fov_millidegrees >= 180_000
        } else {
            self.fov_millidegrees >= 360_000
        }
    }

    /// The solid angle the lenses see, in steradians: 2π(1 − cos k) per lens (k half the
    /// field of view), 4π for two lenses of 180° or more.
    #[must_use]
    pub fn seen_solid_angle(self) -> f64 {
        let tau = 2.0 * core::f64::consts::PI;
        if self.covers_sphere() {
            return 2.0 * tau;
        }
        let k = f64::from(self.fov_millidegrees) * (core::f64::consts::PI / 360_000.0);
        f64::from(self.chart_count()) * tau * (1.0 - libm::cos(k))
    }

    /// A fisheye of `lens` with the full field of view `fov_degrees` (rounded to a thousandth
    /// of a degree), two lenses back to back if `dual`; `None` unless the field of view is in
    /// (0°, 360°].
    ///
    /// ```
    /// use envmap_core::fisheye::{Fisheye, Lens};
    /// use envmap_core::Mapping;
    /// use glam::Vec3;
    /// let f = Fisheye::new(Lens::Equidistant, 190.0, true).unwrap();
    /// assert_eq!(f.chart_count(), 2);
    /// // Straight ahead: the front lens's centre.
    /// let c = f.forward(Vec3::Z).unwrap();
    /// assert_eq!((c.chart, c.u, c.v), (0, 0.5, 0.5));
    /// // One lens of 180° does not see behind it.
    /// let one = Fisheye::new(Lens::Equidistant, 180.0, false).unwrap();
    /// assert!(one.forward(Vec3::NEG_Z).is_none());
    /// assert!(Fisheye::new(Lens::Equisolid, 0.0, false).is_none());
    /// ```
    #[must_use]
    pub fn new(lens: Lens, fov_degrees: f64, dual: bool) -> Option<Fisheye> {
        if !(fov_degrees > 0.0 && fov_degrees <= 360.0) {
            return None;
        }
        let fov_millidegrees = libm::round(fov_degrees * 1000.0) as u32;
        (fov_millidegrees > 0).then_some(Fisheye {
            lens,
            fov_millidegrees,
            dual,
        })
    }

    /// The lens and its field of view as file metadata and `envmap info` write them,
    /// `"equidistant 190"` (degrees per lens); [`Fisheye::from_lens_text`] reads it back.
    #[must_use]
    pub fn lens_text(self) -> LensText {
        LensText(self)
    }

    /// A fisheye of the kind of `self` (one lens or two) with the lens and field of view of
    /// `text` as [`Fisheye::lens_text`] writes it (`"equisolid 190"`); `None` if it does not
    /// parse or the field of view is not in (0°, 360°].
    #[must_use]
    pub fn from_lens_text(self, text: &str) -> Option<Fisheye> {
        let mut words = text.split_whitespace();
        let lens = Lens::from_name(words.next()?)?;
        let fov: f64 = words.next()?.trim_end_matches('°').parse().ok()?;
        if words.next().is_some() {
            return None;
        }
        Fisheye::new(lens, fov, self.dual)
    }

    /// The lens law.
    #[must_use]
    pub const fn lens(self) -> Lens {
        self.lens
    }

    /// The full field of view of each lens, in degrees.
    #[must_use]
    pub fn fov_degrees(self) -> f64 {
        f64::from(self.fov_millidegrees) / 1000.0
    }

    /// Whether there are two lenses back to back.
    #[must_use]
    pub const fn is_dual(self) -> bool {
        self.dual
    }

    /// Half the field of view, k = F/2, in radians: the angle from the axis of the image
    /// circle.
    #[must_use]
    pub fn half_fov(self) -> f32 {
        (f64::from(self.fov_millidegrees) * (core::f64::consts::PI / 360_000.0)) as f32
    }

    /// The largest angle from the axis a lens sees, k·(1 + 4ε): the rim, and the directions
    /// its points invert to, whose angle rounds up to a few ulps past k (their image radius
    /// is clamped to 1). Infinite for lenses that cover the sphere: every direction.
    #[must_use]
    pub fn seen_limit(self) -> f32 {
        if self.covers_sphere() {
            f32::INFINITY
        } else {
            self.half_fov() * (1.0 + 4.0 * f32::EPSILON)
        }
    }

    /// sin(k/2) = sin(F/4): the equisolid law's divisor, r = sin(θ/2)/sin(k/2).
    #[must_use]
    pub fn half_fov_sin_half(self) -> f32 {
        math::sin(0.5 * self.half_fov())
    }

    /// Forward mapping: the lens (chart) and the image point; `None` for a direction the
    /// lenses do not see, and for NaN, ±Inf or zero.
    #[must_use]
    pub fn forward(self, dir: Vec3) -> Option<ChartUv> {
        let d = normalize_direction(dir)?;
        // The hemisphere from z as given (normalising can flush a tiny z to −0).
        let back = self.dual && dir.z < 0.0;
        let (axial, side) = if back { (-d.z, -1.0) } else { (d.z, 1.0) };
        let rho = math::sqrt(d.x * d.x + d.y * d.y);
        let theta = math::atan2(rho, axial);
        if theta > self.seen_limit() {
            return None;
        }
        let k = self.half_fov();
        let r = match self.lens {
            Lens::Equidistant => theta / k,
            Lens::Equisolid => math::sin(0.5 * theta) / self.half_fov_sin_half(),
        }
        .min(1.0);
        let chart = u32::from(back);
        // The azimuth from the components as given, divided by the larger of |x|, |y| (the
        // normalised ones can underflow next to the axis); on the axis the azimuth of +x,
        // which matters only for a 360° lens looking away (θ = π, r = 1: a rim point).
        let a = dir.x.abs().max(dir.y.abs());
        let (x, y) = if a == 0.0 {
            (1.0, 0.0)
        } else {
            (dir.x / a, dir.y / a)
        };
        let s = 0.5 * r / math::sqrt(x * x + y * y);
        Some(ChartUv::new(
            chart,
            (0.5 + side * s * x).clamp(0.0, 1.0),
            (0.5 - s * y).clamp(0.0, 1.0),
        ))
    }

    /// Inverse mapping: `None` for a chart the fisheye lacks, NaN, or a point outside the
    /// image circle.
    #[must_use]
    pub fn inverse(self, c: ChartUv) -> Option<Vec3> {
        if c.chart >= self.chart_count() || !in_unit_disk(c.u, c.v) {
            return None;
        }
        let (side, axial) = if c.chart == 1 {
            (-1.0, -1.0)
        } else {
            (1.0, 1.0)
        };
        let (a, b) = (2.0 * c.u - 1.0, 1.0 - 2.0 * c.v);
        let r = math::sqrt(a * a + b * b).min(1.0);
        let k = self.half_fov();
        let theta = match self.lens {
            Lens::Equidistant => r * k,
            Lens::Equisolid => 2.0 * math::asin((r * self.half_fov_sin_half()).min(1.0)),
        };
        let (sin_t, cos_t) = math::sin_cos(theta.min(PI));
        if r == 0.0 {
            return Some(Vec3::new(0.0, 0.0, axial));
        }
        let s = sin_t / r;
        let d = Vec3::new(side * s * a, s * b, axial * cos_t);
        Some(d / math::sqrt(d.length_squared()))
    }

    const fn chart_count(self) -> u32 {
        if self.dual {
            2
        } else {
            1
        }
    }
}

/// [`Fisheye::lens_text`]: the lens law and the field of view in degrees, `"equidistant 190"`.
#[derive(Clone, Copy, Debug)]
pub struct LensText(Fisheye);

impl core::fmt::Display for LensText {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "{} {}", self.0.lens.name(), self.0.fov_degrees())
    }
}

impl Mapping for Fisheye {
    fn name(&self) -> &'static str {
        if self.dual {
            "dual-fisheye"
        } else {
            "fisheye"
        }
    }
    fn chart_count(&self) -> u32 {
        Fisheye::chart_count(*self)
    }
    fn forward(&self, dir: Vec3) -> Option<ChartUv> {
        Fisheye::forward(*self, dir)
    }
    fn inverse(&self, c: ChartUv) -> Option<Vec3> {
        Fisheye::inverse(*self, c)
    }
    fn in_chart(&self, chart: u32, u: f32, v: f32) -> bool {
        chart < Fisheye::chart_count(*self) && in_unit_disk(u, v)
    }
    fn solid_angle(&self, chart: u32, u0: f64, u1: f64, v0: f64, v1: f64) -> f64 {
        if chart >= Fisheye::chart_count(*self) {
            return 0.0;
        }
        let k = f64::from(self.fov_millidegrees) * (core::f64::consts::PI / 360_000.0);
        let half_pi = core::f64::consts::FRAC_PI_2;
        if !(self.dual && k > half_pi) {
            return crate::solid_angle::fisheye(self.lens, k, u0, u1, v0, v1);
        }
        // Two overlapping lenses: each owns the disk of radius ρ₀ (its hemisphere), which
        // scaled by 1/ρ₀ is a 180° lens's image circle (module docs).
        let rho0 = match self.lens {
            Lens::Equidistant => half_pi / k,
            Lens::Equisolid => libm::sin(0.25 * core::f64::consts::PI) / libm::sin(0.5 * k),
        };
        let scale = |t: f64| 0.5 + (t - 0.5) / rho0;
        crate::solid_angle::fisheye(
            self.lens,
            half_pi,
            scale(u0),
            scale(u1),
            scale(v0),
            scale(v1),
        )
    }
    fn atlas(&self) -> Atlas {
        if self.dual {
            Atlas::DUAL_FISHEYE_V360
        } else {
            Atlas::SINGLE_SQUARE
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lenses() -> impl Iterator<Item = Fisheye> {
        [Lens::Equidistant, Lens::Equisolid]
            .into_iter()
            .flat_map(|lens| {
                [90.0, 180.0, 190.0, 250.0, 360.0]
                    .into_iter()
                    .flat_map(move |fov| {
                        [false, true]
                            .into_iter()
                            .map(move |dual| Fisheye::new(lens, fov, dual).unwrap())
                    })
            })
    }

    fn directions(n: u32) -> impl Iterator<Item = Vec3> {
        let golden = PI * (3.0 - math::sqrt(5.0));
        (0..n).map(move |i| {
            let z = 1.0 - (2.0 * i as f32 + 1.0) / n as f32;
            let r = math::sqrt(1.0 - z * z);
            let (s, c) = math::sin_cos(golden * i as f32);
            let scale = [1.0, 1e-30, 1e30, 3.5][i as usize % 4];
            Vec3::new(r * c, r * s, z) * scale
        })
    }

    fn angle(a: Vec3, b: Vec3) -> f32 {
        let (a, b) = (
            normalize_direction(a).unwrap(),
            normalize_direction(b).unwrap(),
        );
        math::atan2(a.cross(b).length(), a.dot(b))
    }

    /// What the lenses see: the angle from the nearer lens's axis within F/2.
    fn seen(f: Fisheye, d: Vec3) -> Option<bool> {
        let d = normalize_direction(d).unwrap();
        let axis = if f.is_dual() && d.z < 0.0 { -d.z } else { d.z };
        let theta = math::atan2(math::sqrt(d.x * d.x + d.y * d.y), axis);
        let k = f.half_fov();
        // Within a few ulps of the circle the answer may go either way.
        if (theta - k).abs() < 1e-5 {
            None
        } else {
            Some(theta < k)
        }
    }

    #[test]
    fn directions_round_trip_and_unseen_ones_have_no_point() {
        let mut worst = 0.0f32;
        for f in lenses() {
            for d in directions(4000) {
                let c = f.forward(d);
                match seen(f, d) {
                    Some(false) => assert!(c.is_none(), "{f:?} {d} {c:?}"),
                    Some(true) => {
                        let c = c.unwrap_or_else(|| panic!("{f:?} {d}"));
                        assert!(f.in_chart(c.chart, c.u, c.v), "{f:?} {d} {c:?}");
                        let back = f.inverse(c).unwrap();
                        let e = angle(back, d);
                        // At 360° the equisolid lens is the sphere map, whose inverse's
                        // asin is ill-conditioned at the rim, the direction opposite the
                        // axis: as for the sphere maps, the bound grows like 1/β there (β
                        // the angle from that direction).
                        let n = normalize_direction(d).unwrap();
                        let beta = math::atan2(math::sqrt(n.x * n.x + n.y * n.y), -n.z);
                        let bound = match f.lens() {
                            Lens::Equisolid if f.fov_degrees() == 360.0 => 1.5e-6 + 2e-6 / beta,
                            _ => 1.5e-6,
                        };
                        worst = worst.max(e);
                        assert!(e < bound, "{f:?} {d}: {e}");
                    }
                    None => {}
                }
            }
        }
        #[cfg(feature = "std")]
        std::println!("fisheye direction round trip: worst {worst:.2e} rad");
    }

    #[test]
    fn axes_and_bad_input() {
        let f = Fisheye::new(Lens::Equidistant, 180.0, true).unwrap();
        // 45° right of ahead: halfway to the circle, to the right.
        let c = f.forward(Vec3::new(1.0, 0.0, 1.0)).unwrap();
        assert_eq!(c.chart, 0);
        assert!(
            (c.u - 0.75).abs() < 1e-6 && (c.v - 0.5).abs() < 1e-6,
            "{c:?}"
        );
        // Up is the image's top.
        let c = f.forward(Vec3::new(0.0, 1.0, 1.0)).unwrap();
        assert!(
            (c.u - 0.5).abs() < 1e-6 && (c.v - 0.25).abs() < 1e-6,
            "{c:?}"
        );
        // Behind, to the right (+x): the back lens sees +x on its left.
        let c = f.forward(Vec3::new(1.0, 0.0, -1.0)).unwrap();
        assert_eq!(c.chart, 1);
        assert!((c.u - 0.25).abs() < 1e-6, "{c:?}");
        for d in [Vec3::NAN, Vec3::ZERO, Vec3::new(f32::INFINITY, 0.0, 1.0)] {
            assert!(f.forward(d).is_none());
        }
        assert!(f.inverse(ChartUv::new(2, 0.5, 0.5)).is_none());
        assert!(f.inverse(ChartUv::new(0, 0.0, 0.0)).is_none());
        assert!(f.inverse(ChartUv::new(0, f32::NAN, 0.5)).is_none());
        let one = Fisheye::new(Lens::Equisolid, 180.0, false).unwrap();
        assert!(one.inverse(ChartUv::new(1, 0.5, 0.5)).is_none());
        // Equisolid: 60° from the axis at r = sin 30° / sin 45°.
        let (s, c60) = math::sin_cos(PI / 3.0);
        let c = one.forward(Vec3::new(s, 0.0, c60)).unwrap();
        let r = 0.5 / core::f32::consts::FRAC_1_SQRT_2;
        assert!((c.u - (0.5 + 0.5 * r)).abs() < 1e-6, "{c:?}");
        for fov in [0.0, -1.0, 360.1, f64::NAN] {
            assert!(
                Fisheye::new(Lens::Equidistant, fov, false).is_none(),
                "{fov}"
            );
        }
        assert_eq!(Fisheye::default().fov_degrees(), 180.0);
        // The lens text round trips, and refuses what is not a lens.
        let f = Fisheye::new(Lens::Equisolid, 190.5, true).unwrap();
        let text = std::format!("{}", f.lens_text());
        assert_eq!(text, "equisolid 190.5");
        assert_eq!(Fisheye::DUAL.from_lens_text(&text), Some(f));
        assert_eq!(
            Fisheye::SINGLE
                .from_lens_text("EQUAL-AREA 90°")
                .map(|f| f.lens()),
            Some(Lens::Equisolid)
        );
        for bad in [
            "",
            "equidistant",
            "fisheye 190",
            "equidistant 0",
            "equidistant 400",
            "equidistant 190 x",
        ] {
            assert_eq!(Fisheye::SINGLE.from_lens_text(bad), None, "{bad}");
        }
    }

    /// A lens's texels total its cap, 2π(1 − cos(F/2)), or its hemisphere, 2π, when two
    /// lenses overlap; at 360° the equidistant lens's solid
    /// angles are the angular map's and the equisolid lens's the sphere map's (the same laws).
    #[test]
    fn solid_angles_total_the_caps() {
        use crate::{Angular, SphereMap};
        for f in lenses() {
            let k = f.fov_degrees().to_radians() / 2.0;
            let owned = if f.is_dual() {
                k.min(core::f64::consts::FRAC_PI_2)
            } else {
                k
            };
            let cap = 2.0 * core::f64::consts::PI * (1.0 - libm::cos(owned));
            let n = 24;
            let mut total = 0.0;
            for j in 0..n {
                for i in 0..n {
                    total += f.texel_solid_angle(0, i, j, n, n);
                }
            }
            assert!(
                (total - cap).abs() < 1e-12 * cap.max(1.0),
                "{f:?}: {total} vs {cap}"
            );
            assert_eq!(f.solid_angle(f.chart_count(), 0.0, 1.0, 0.0, 1.0), 0.0);
        }
        let eq = Fisheye::new(Lens::Equidistant, 360.0, false).unwrap();
        let es = Fisheye::new(Lens::Equisolid, 360.0, false).unwrap();
        for (u0, u1, v0, v1) in [
            (0.1, 0.3, 0.2, 0.25),
            (0.0, 0.5, 0.5, 1.0),
            (0.9, 1.0, 0.4, 0.6),
        ] {
            let a = Angular.solid_angle(0, u0, u1, v0, v1);
            assert!((eq.solid_angle(0, u0, u1, v0, v1) - a).abs() <= 1e-15 * a.max(1.0));
            let m = SphereMap::OPENGL.solid_angle(0, u0, u1, v0, v1);
            assert!((es.solid_angle(0, u0, u1, v0, v1) - m).abs() <= 1e-14 * m.max(1.0));
        }
    }

    /// Texel solid angles against the area element integrated by a midpoint rule (64² and
    /// 32² points per texel, extrapolated), on texels inside the circle (one lens each, where
    /// it owns the whole circle).
    #[test]
    fn solid_angles_match_the_area_element() {
        for f in lenses().filter(|f| !f.is_dual()) {
            let k = f.fov_degrees().to_radians() / 2.0;
            let density = |x: f64, y: f64| {
                let rho = libm::sqrt(x * x + y * y);
                match f.lens() {
                    Lens::Equidistant if rho == 0.0 => k * k,
                    Lens::Equidistant => k * libm::sin(k * rho) / rho,
                    Lens::Equisolid => 4.0 * libm::sin(k / 2.0) * libm::sin(k / 2.0),
                }
            };
            let n = 16u32;
            for (i, j) in [(8, 8), (3, 8), (5, 4), (2, 6)] {
                let (u0, v0) = (f64::from(i) / f64::from(n), f64::from(j) / f64::from(n));
                let h = 1.0 / f64::from(n);
                let midpoint = |m: u32| {
                    let step = h / f64::from(m);
                    let mut sum = 0.0;
                    for b in 0..m {
                        for a in 0..m {
                            let u = u0 + (f64::from(a) + 0.5) * step;
                            let v = v0 + (f64::from(b) + 0.5) * step;
                            sum += density(2.0 * u - 1.0, 2.0 * v - 1.0);
                        }
                    }
                    sum * 4.0 * step * step
                };
                // Richardson: the midpoint rule's h² error term cancels.
                let expected = (4.0 * midpoint(64) - midpoint(32)) / 3.0;
                let got = f.texel_solid_angle(0, i, j, n, n);
                assert!(
                    (got - expected).abs() < 1e-6 * expected,
                    "{f:?} ({i}, {j}): {got} vs {expected}"
                );
            }
        }
    }
}
