//! Perspective views: what a pinhole camera sees, a rectangle of the plane one unit in front
//! of it (py360convert's `e2p`, ffmpeg v360's `flat`).
//!
//! # Formula
//!
//! The gnomonic (rectilinear) projection onto the plane z = 1, the cube face's law with a
//! field of view of one's choosing: a camera looking along +z, +x to the right of its image
//! and +y up. H is the horizontal field of view and the image `w × h` texels, square texels,
//! so the vertical field of view V has tan(V/2) = tan(H/2)·h/w:
//!
//! ```text
//! (u, v) = (½ + ½ (x/z) / tan(H/2),  ½ − ½ (y/z) / tan(V/2))      for z > 0
//! inverse:  normalize((2u − 1) tan(H/2),  (1 − 2v) tan(V/2),  1)
//! ```
//!
//! A direction outside the view (z ≤ 0, or beyond the rectangle's edges) is not seen:
//! [`Perspective::forward`] gives `None` for it. Whoever converts a view must say what such
//! directions hold.
//!
//! # Area element and solid angles
//!
//! A rectangle of (u, v) is a rectangle of the plane z = 1, whose solid angle is the cube
//! face's, in closed form ([`crate::solid_angle::perspective`]).
//!
//! # Where it is available
//!
//! This scalar mapping and its exact solid angles; `AnyMapping`, the eight-wide kernels and the
//! command do not take it yet.

use glam::Vec3;

use crate::atlas::{Atlas, Cell, Turn};
use crate::direction::normalize_direction;
use crate::mapping::{in_unit_square, ChartUv, Mapping};
use crate::math;

/// A perspective view of a given horizontal field of view and image aspect ratio; see the
/// [module docs](self).
///
/// The field of view is held in thousandths of a degree and the aspect ratio in lowest
/// terms, so that two views compare equal (and hash alike) when they print alike.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Perspective {
    h_fov_millidegrees: u32,
    aspect_w: u32,
    aspect_h: u32,
}

/// The one cell of a view's atlas.
const VIEW_CELLS: &[Cell] = &[Cell {
    chart: 0,
    col: 0,
    row: 0,
    turn: Turn::None,
}];

const fn gcd(a: u32, b: u32) -> u32 {
    let (mut a, mut b) = (a, b);
    while b != 0 {
        let t = a % b;
        a = b;
        b = t;
    }
    a
}

impl Perspective {
    /// A view of horizontal field of view `h_fov_degrees` (rounded to a thousandth of a degree)
    /// over an image `width × height` texels (only their ratio counts); `None` unless the
    /// field of view is in (0°, 180°) and both sizes are positive.
    ///
    /// ```
    /// use envmap_core::perspective::Perspective;
    /// use envmap_core::Mapping;
    /// use glam::Vec3;
    /// let p = Perspective::new(90.0, 1920, 1080).unwrap();
    /// // Straight ahead is the image's centre; 45° to the right its right edge.
    /// let c = p.forward(Vec3::Z).unwrap();
    /// assert_eq!((c.u, c.v), (0.5, 0.5));
    /// assert!((p.forward(Vec3::new(1.0, 0.0, 1.0)).unwrap().u - 1.0).abs() < 1e-6);
    /// // Behind the camera: not seen.
    /// assert!(p.forward(Vec3::NEG_Z).is_none());
    /// assert_eq!(p.aspect(), (16, 9));
    /// ```
    #[must_use]
    pub fn new(h_fov_degrees: f64, width: u32, height: u32) -> Option<Perspective> {
        if !(h_fov_degrees > 0.0 && h_fov_degrees < 180.0) || width == 0 || height == 0 {
            return None;
        }
        let h_fov_millidegrees = libm::round(h_fov_degrees * 1000.0) as u32;
        if h_fov_millidegrees == 0 || h_fov_millidegrees >= 180_000 {
            return None;
        }
        let g = gcd(width, height);
        Some(Perspective {
            h_fov_millidegrees,
            aspect_w: width / g,
            aspect_h: height / g,
        })
    }

    /// The horizontal field of view, in degrees.
    #[must_use]
    pub fn h_fov_degrees(self) -> f64 {
        f64::from(self.h_fov_millidegrees) / 1000.0
    }

    /// The vertical field of view, in degrees: 2 atan(tan(H/2)·h/w).
    #[must_use]
    pub fn v_fov_degrees(self) -> f64 {
        2.0 * libm::atan(self.tangents_f64().1).to_degrees()
    }

    /// The image's aspect ratio `(w, h)`, in lowest terms.
    #[must_use]
    pub const fn aspect(self) -> (u32, u32) {
        (self.aspect_w, self.aspect_h)
    }

    /// tan(H/2) and tan(V/2) in f64.
    fn tangents_f64(self) -> (f64, f64) {
        let half = f64::from(self.h_fov_millidegrees) * (core::f64::consts::PI / 360_000.0);
        let tx = libm::tan(half);
        (tx, tx * f64::from(self.aspect_h) / f64::from(self.aspect_w))
    }

    /// tan(H/2) and tan(V/2), the half-width and half-height of the view on the plane z = 1.
    #[must_use]
    pub fn tangents(self) -> (f32, f32) {
        let (tx, ty) = self.tangents_f64();
        (tx as f32, ty as f32)
    }

    /// Forward mapping: the image point; `None` for a direction outside the view, and for
    /// NaN, ±Inf or zero.
    #[must_use]
    pub fn forward(self, dir: Vec3) -> Option<ChartUv> {
        let d = normalize_direction(dir)?;
        if d.z <= 0.0 {
            return None;
        }
        let (tx, ty) = self.tangents();
        let u = 0.5 + 0.5 * (d.x / d.z) / tx;
        let v = 0.5 - 0.5 * (d.y / d.z) / ty;
        // Directions on the rectangle's edges, whose coordinates round a few ulps past them,
        // are kept (clamped).
        let slack = 4.0 * f32::EPSILON;
        let inside = |t: f32| (-slack..=1.0 + slack).contains(&t);
        (inside(u) && inside(v)).then(|| ChartUv::new(0, u.clamp(0.0, 1.0), v.clamp(0.0, 1.0)))
    }

    /// Inverse mapping: `None` for a chart other than 0 or a point outside `[0, 1]²` (or NaN).
    #[must_use]
    pub fn inverse(self, c: ChartUv) -> Option<Vec3> {
        if c.chart != 0 || !in_unit_square(c.u, c.v) {
            return None;
        }
        let (tx, ty) = self.tangents();
        let d = Vec3::new((2.0 * c.u - 1.0) * tx, (1.0 - 2.0 * c.v) * ty, 1.0);
        Some(d / math::sqrt(d.length_squared()))
    }

    /// The solid angle the view sees, in steradians: the whole rectangle's,
    /// 4 atan(tan(H/2) tan(V/2) / √(1 + tan²(H/2) + tan²(V/2))).
    #[must_use]
    pub fn seen_solid_angle(self) -> f64 {
        let (tx, ty) = self.tangents_f64();
        4.0 * libm::atan(tx * ty / libm::sqrt(1.0 + tx * tx + ty * ty))
    }
}

impl Mapping for Perspective {
    fn name(&self) -> &'static str {
        "perspective"
    }
    fn chart_count(&self) -> u32 {
        1
    }
    fn forward(&self, dir: Vec3) -> Option<ChartUv> {
        Perspective::forward(*self, dir)
    }
    fn inverse(&self, c: ChartUv) -> Option<Vec3> {
        Perspective::inverse(*self, c)
    }
    fn solid_angle(&self, chart: u32, u0: f64, u1: f64, v0: f64, v1: f64) -> f64 {
        if chart != 0 {
            return 0.0;
        }
        let (tx, ty) = self.tangents_f64();
        crate::solid_angle::perspective(tx, ty, u0, u1, v0, v1)
    }
    /// One cell of the view's aspect ratio.
    fn atlas(&self) -> Atlas {
        Atlas {
            name: "view",
            cols: 1,
            rows: 1,
            cell_aspect_w: self.aspect_w,
            cell_aspect_h: self.aspect_h,
            cells: VIEW_CELLS,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn views() -> impl Iterator<Item = Perspective> {
        [
            (90.0, 1, 1),
            (60.0, 16, 9),
            (120.0, 4, 3),
            (170.0, 2, 1),
            (10.0, 3, 4),
        ]
        .into_iter()
        .map(|(f, w, h)| Perspective::new(f, w, h).unwrap())
    }

    #[test]
    fn round_trips_and_unseen_directions() {
        let mut worst = 0.0f64;
        for p in views() {
            let (tx, ty) = p.tangents_f64();
            for i in 0..4000u32 {
                let z = 1.0 - (2.0 * f64::from(i) + 1.0) / 4000.0;
                let r = libm::sqrt(1.0 - z * z);
                let phi = 2.399_963_229_728_653 * f64::from(i);
                let d = glam::DVec3::new(r * libm::cos(phi), r * libm::sin(phi), z);
                let (a, b) = (d.x / d.z, d.y / d.z);
                let margin = 1e-5;
                let seen =
                    d.z > 0.0 && a.abs() < tx * (1.0 - margin) && b.abs() < ty * (1.0 - margin);
                let unseen =
                    d.z <= 0.0 || a.abs() > tx * (1.0 + margin) || b.abs() > ty * (1.0 + margin);
                let c = p.forward(d.as_vec3());
                if unseen {
                    assert!(c.is_none(), "{p:?} {d}");
                }
                if seen {
                    let c = c.unwrap_or_else(|| panic!("{p:?} {d}"));
                    let back = p.inverse(c).unwrap().as_dvec3();
                    let e = libm::atan2(back.cross(d).length(), back.dot(d));
                    worst = worst.max(e);
                    assert!(e < 1e-6, "{p:?} {d}: {e}");
                }
            }
        }
        #[cfg(feature = "std")]
        std::println!("perspective round trip: worst {worst:.2e} rad");
    }

    #[test]
    fn edges_axes_and_bad_input() {
        let p = Perspective::new(90.0, 2, 1).unwrap();
        assert!((p.v_fov_degrees() - 2.0 * libm::atan(0.5).to_degrees()).abs() < 1e-9);
        // Up is the image's top; the corners invert to the rectangle's corners and back.
        let c = p.forward(Vec3::new(0.0, 0.25, 1.0)).unwrap();
        assert!((c.v - 0.25).abs() < 1e-6, "{c:?}");
        for (u, v) in [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0), (0.5, 0.0)] {
            let d = p.inverse(ChartUv::new(0, u, v)).unwrap();
            let c = p.forward(d).unwrap();
            assert!(
                (c.u - u).abs() < 1e-6 && (c.v - v).abs() < 1e-6,
                "{u} {v}: {c:?}"
            );
        }
        for d in [
            Vec3::NAN,
            Vec3::ZERO,
            Vec3::X,
            Vec3::NEG_Z,
            Vec3::new(1.0, 0.0, 0.9),
        ] {
            assert!(p.forward(d).is_none(), "{d}");
        }
        assert!(p.inverse(ChartUv::new(1, 0.5, 0.5)).is_none());
        assert!(p.inverse(ChartUv::new(0, 1.5, 0.5)).is_none());
        assert!(p.inverse(ChartUv::new(0, f32::NAN, 0.5)).is_none());
        for (f, w, h) in [
            (0.0, 1, 1),
            (180.0, 1, 1),
            (-5.0, 1, 1),
            (f64::NAN, 1, 1),
            (90.0, 0, 1),
        ] {
            assert!(Perspective::new(f, w, h).is_none(), "{f} {w} {h}");
        }
        assert_eq!(
            Perspective::new(90.0, 1920, 1080)
                .unwrap()
                .atlas()
                .cell_aspect_w,
            16
        );
    }

    /// The texels of a view total the rectangle's solid angle; a 90° square view is a cube
    /// face, texel for texel.
    #[test]
    fn solid_angles() {
        for p in views() {
            let (aw, ah) = p.aspect();
            let (w, h) = (aw * 8, ah * 8);
            let mut total = 0.0;
            for j in 0..h {
                for i in 0..w {
                    total += p.texel_solid_angle(0, i, j, w, h);
                }
            }
            let want = p.seen_solid_angle();
            assert!(
                (total - want).abs() < 1e-12 * want,
                "{p:?}: {total} vs {want}"
            );
        }
        let face = Perspective::new(90.0, 1, 1).unwrap();
        for (i, j) in [(0, 0), (3, 5), (7, 7)] {
            let a = face.texel_solid_angle(0, i, j, 8, 8);
            let b = crate::Cube.texel_solid_angle(4, i, j, 8, 8);
            assert!((a - b).abs() < 1e-15, "{a} {b}");
        }
    }
}
