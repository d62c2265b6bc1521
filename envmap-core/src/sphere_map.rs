//! Sphere map (the image of a mirror ball), in the class and OpenGL conventions.
//!
//! # Formula
//!
//! Seed `000` ("Spherical texture environment map"): the normal N of the mirror
//! ball that reflects the view direction into R is half-way between R and the
//! vector V towards the viewer, and the map is N's projection along the view axis:
//!
//! ```text
//! class convention  (eye looks along +z, V = (0, 0, −1)):
//!     (u', v') = (rx, ry) / √(rx² + ry² + (rz − 1)²)
//! OpenGL GL_SPHERE_MAP (eye looks along −z, V = (0, 0, +1)):
//!     (u', v') = (rx, ry) / √(rx² + ry² + (rz + 1)²)
//! both: (u, v) = (u'/2 + 1/2, v'/2 + 1/2)
//! ```
//!
//! The inverse reflects V about the ball normal N = (u', v', ±√(1 − r²)),
//! r² = u'² + v'² ≤ 1, N facing the viewer:
//!
//! ```text
//! R = 2(N·V)N − V = (2u'√(1 − r²), 2v'√(1 − r²), σ(1 − 2r²)),  σ = −1 class, +1 OpenGL
//! ```
//!
//! The seed's **short cut** when the normal is known ([`uv_from_normal`]):
//! (u', v') = (nx, ny).
//!
//! # Axes and the singular direction
//!
//! The image is the mirror ball as the viewer sees it: u along +x; v along +y.
//! In the class convention (x right, y down, z forward, like a camera) +y is
//! down in the image; in OpenGL's (y up) v grows with +y as GL's t does, so
//! with row 0 uploaded first the image shows +y at the bottom.
//!
//! The direction straight away from the viewer, −V (class: +z; OpenGL: −z), is
//! singular: every point of the rim r = 1 inverts to it. **Forward** maps that
//! exact direction to the rim point (u, v) = (1, ½) (u' = 1, v' = 0); nearby
//! directions land near the rim at their own azimuth. **Inverse** of any rim
//! point gives −V. The centre (½, ½) is V itself (the viewer's own reflection).
//! The corners outside the disk hold no direction (`inverse` gives `None`,
//! [`Mapping::in_chart`] is false).
//!
//! # Accuracy near the rim
//!
//! The map compresses the hemisphere behind the ball into a thin ring: an
//! angular distance β from −V sits at 1 − r ≈ β²/8 from the rim, so f32
//! resolution in (u, v) limits round trips to about 1e-7 · 8/β rad there.
//! The property tests state the bound as a function of β.
//!
//! # Area element
//!
//! dΩ = 4 du' dv' (the map is equal-area within the disk, a Lambert azimuthal
//! projection): every texel fully inside the disk has the same solid angle.

use glam::Vec3;

use crate::atlas::Atlas;
use crate::direction::normalize_direction;
use crate::mapping::{in_unit_disk, ChartUv, Mapping};
use crate::math;

/// Which way the eye looks in the sphere map's frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum SphereConvention {
    /// The class convention of seed `000`: the eye looks along +z, V = (0, 0, −1);
    /// the singular direction is +z.
    #[default]
    EyeAlongPosZ,
    /// OpenGL's `GL_SPHERE_MAP`: the eye looks along −z, V = (0, 0, +1);
    /// the singular direction is −z.
    EyeAlongNegZ,
}

impl SphereConvention {
    /// σ = V.z: −1 for the class convention, +1 for OpenGL.
    #[inline]
    #[must_use]
    pub const fn sigma(self) -> f32 {
        match self {
            SphereConvention::EyeAlongPosZ => -1.0,
            SphereConvention::EyeAlongNegZ => 1.0,
        }
    }
}

/// The sphere map; see the [module docs](self).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct SphereMap {
    /// The eye convention.
    pub convention: SphereConvention,
}

impl SphereMap {
    /// The class convention (eye along +z).
    pub const CLASS: SphereMap = SphereMap {
        convention: SphereConvention::EyeAlongPosZ,
    };
    /// OpenGL's `GL_SPHERE_MAP` (eye along −z).
    pub const OPENGL: SphereMap = SphereMap {
        convention: SphereConvention::EyeAlongNegZ,
    };

    /// Forward mapping; see the [module docs](self).
    ///
    /// ```
    /// use envmap_core::SphereMap;
    /// use glam::Vec3;
    /// // The viewer's own direction maps to the centre ...
    /// let c = SphereMap::CLASS.forward(Vec3::NEG_Z).unwrap();
    /// assert_eq!((c.u, c.v), (0.5, 0.5));
    /// // ... and a direction at right angles to the view axis halfway out.
    /// let c = SphereMap::OPENGL.forward(Vec3::X).unwrap();
    /// assert!((c.u - (0.5 + 0.5 * core::f32::consts::FRAC_1_SQRT_2)).abs() < 1e-6);
    /// ```
    #[inline]
    #[must_use]
    pub fn forward(self, dir: Vec3) -> Option<ChartUv> {
        let r = normalize_direction(dir)?;
        let sigma = self.convention.sigma();
        // h = rz + σ = σ(1 + σ rz), without cancellation near the singular
        // direction (σ rz → −1), where 1 + w = (rx² + ry²) / (1 − w).
        let w = sigma * r.z;
        let one_plus_w = if w < 0.0 {
            (r.x * r.x + r.y * r.y) / (1.0 - w)
        } else {
            1.0 + w
        };
        // Scale before squaring: rx, ry may be tiny (down to denormals).
        let s = r.x.abs().max(r.y.abs()).max(one_plus_w);
        if s == 0.0 {
            return Some(ChartUv::new(0, 1.0, 0.5));
        }
        let (x, y, h) = (r.x / s, r.y / s, one_plus_w / s);
        let m = math::sqrt(x * x + y * y + h * h);
        let u = math::clamp01(0.5 * (x / m) + 0.5);
        let v = math::clamp01(0.5 * (y / m) + 0.5);
        Some(ChartUv::new(0, u, v))
    }

    /// Inverse mapping; `None` outside the disk, for NaN or a chart other than 0.
    #[inline]
    #[must_use]
    pub fn inverse(self, c: ChartUv) -> Option<Vec3> {
        if c.chart != 0 || !in_unit_disk(c.u, c.v) {
            return None;
        }
        let (x, y) = (2.0 * c.u - 1.0, 2.0 * c.v - 1.0);
        let r2 = x * x + y * y;
        let nz = math::sqrt((1.0 - r2).max(0.0));
        let d = Vec3::new(
            2.0 * x * nz,
            2.0 * y * nz,
            self.convention.sigma() * (1.0 - 2.0 * r2),
        );
        Some(d / math::sqrt(d.length_squared()))
    }
}

/// The seed's short cut: sphere-map coordinates straight from the mirror
/// ball's surface normal, (u', v') = (nx, ny), u = u'/2 + 1/2, v = v'/2 + 1/2.
///
/// For a normal facing the viewer this equals
/// `forward(reflect_view(n, V))` in either convention. `n` need not be unit;
/// `None` for NaN, ±Inf or zero.
///
/// ```
/// use envmap_core::{reflect_view, sphere_map::uv_from_normal, SphereMap};
/// use glam::Vec3;
/// let n = Vec3::new(0.3, -0.4, 0.5).normalize(); // faces the OpenGL viewer (+z)
/// let a = uv_from_normal(n).unwrap();
/// let b = SphereMap::OPENGL.forward(reflect_view(n, Vec3::Z)).unwrap();
/// assert!((a.u - b.u).abs() < 1e-6 && (a.v - b.v).abs() < 1e-6);
/// ```
#[inline]
#[must_use]
pub fn uv_from_normal(n: Vec3) -> Option<ChartUv> {
    let n = normalize_direction(n)?;
    Some(ChartUv::new(
        0,
        math::clamp01(0.5 * n.x + 0.5),
        math::clamp01(0.5 * n.y + 0.5),
    ))
}

impl Mapping for SphereMap {
    fn name(&self) -> &'static str {
        match self.convention {
            SphereConvention::EyeAlongPosZ => "sphere",
            SphereConvention::EyeAlongNegZ => "sphere-gl",
        }
    }
    fn chart_count(&self) -> u32 {
        1
    }
    fn forward(&self, dir: Vec3) -> Option<ChartUv> {
        SphereMap::forward(*self, dir)
    }
    fn inverse(&self, c: ChartUv) -> Option<Vec3> {
        SphereMap::inverse(*self, c)
    }
    fn in_chart(&self, chart: u32, u: f32, v: f32) -> bool {
        chart == 0 && in_unit_disk(u, v)
    }
    fn solid_angle(&self, chart: u32, u0: f64, u1: f64, v0: f64, v1: f64) -> f64 {
        if chart != 0 {
            return 0.0;
        }
        crate::solid_angle::sphere_map(u0, u1, v0, v1)
    }
    fn atlas(&self) -> Atlas {
        Atlas::SINGLE_SQUARE
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn known_points() {
        for (m, toward, away) in [
            (SphereMap::CLASS, Vec3::NEG_Z, Vec3::Z),
            (SphereMap::OPENGL, Vec3::Z, Vec3::NEG_Z),
        ] {
            let c = m.forward(toward).unwrap();
            assert_eq!((c.u, c.v), (0.5, 0.5));
            assert_eq!(m.inverse(c).unwrap(), toward);
            // The singular direction: the documented rim point.
            let c = m.forward(away).unwrap();
            assert_eq!((c.u, c.v), (1.0, 0.5));
            // Every rim point inverts to it.
            for (u, v) in [(1.0, 0.5), (0.0, 0.5), (0.5, 0.0), (0.5, 1.0)] {
                let d = m.inverse(ChartUv::new(0, u, v)).unwrap();
                assert!((d - away).length() < 1e-6, "{u} {v} {d}");
            }
            // Perpendicular directions sit at r = √2/2.
            let c = m.forward(Vec3::Y).unwrap();
            let r = 2.0 * c.v - 1.0;
            assert!((r - core::f32::consts::FRAC_1_SQRT_2).abs() < 1e-6);
            assert!((c.u - 0.5).abs() < 1e-7);
        }
    }

    #[test]
    fn near_singular_direction_goes_to_the_rim_at_its_azimuth() {
        let c = SphereMap::CLASS
            .forward(Vec3::new(0.0, -1e-20, 1.0))
            .unwrap();
        assert_eq!((c.u, c.v), (0.5, 0.0));
        let c = SphereMap::OPENGL
            .forward(Vec3::new(1e-38, 0.0, -1.0))
            .unwrap();
        assert_eq!((c.u, c.v), (1.0, 0.5));
    }

    #[test]
    fn corners_are_outside() {
        assert_eq!(SphereMap::CLASS.inverse(ChartUv::new(0, 0.0, 0.0)), None);
        assert!(!SphereMap::CLASS.in_chart(0, 0.05, 0.05));
        assert!(SphereMap::CLASS.in_chart(0, 0.5, 0.5));
    }

    #[test]
    fn bad_input() {
        assert_eq!(SphereMap::CLASS.forward(Vec3::ZERO), None);
        assert_eq!(SphereMap::CLASS.forward(Vec3::splat(f32::NAN)), None);
        assert_eq!(
            SphereMap::CLASS.inverse(ChartUv::new(0, f32::NAN, 0.5)),
            None
        );
        assert_eq!(uv_from_normal(Vec3::ZERO), None);
    }
}
