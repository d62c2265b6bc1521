//! Latitude-longitude (polar spherical, Blinn & Newell 1976) mapping.
//!
//! # Formula
//!
//! Seed `000` ("Polar spherical texture environment map") prints
//!
//! ```text
//! (u, v) = ( atan(y / x) / 2π , acos(z) / π )
//! ```
//!
//! **Erratum.** `atan(y / x)` loses the quadrant (it only spans half a turn)
//! and divides by zero on the y–z plane. envmap uses the four-quadrant
//! `atan2(y, x)`, wrapped into `[0, 1)`, and computes the polar angle as
//! `atan2(√(x² + y²), z)`, which equals `acos(z)` for unit vectors but keeps
//! its absolute accuracy near the poles (acos(z) there is off by up to
//! 3e-4 rad, from the rounding of z alone):
//!
//! ```text
//! φ = atan2(y, x) ∈ (−π, π],   u = φ / 2π, plus 1 if negative   ∈ [0, 1)
//! θ = atan2(√(x² + y²), z) ∈ [0, π],   v = θ / π                ∈ [0, 1]
//! inverse: (x, y, z) = (sin θ cos φ, sin θ sin φ, cos θ) with φ = 2πu, θ = πv
//! ```
//!
//! # Axes
//!
//! z is the pole: `v = 0` (the top row) is +z, `v = 1` is −z. `u = 0` (the
//! left edge) is +x; u grows towards +y (`u = 1/4` is +y, `1/2` is −x, `3/4`
//! is −y). Y-up data goes through a [`Frame`](crate::Frame).
//!
//! # Seams and singular points
//!
//! The seam is the half plane y = 0, x > 0 (u = 0 ≡ 1): directions just below
//! it (y < 0) land near u = 1. The poles (x = y = 0) map to u = 0 (atan2(0, 0)
//! is 0, or π for x = −0: u = 1/2) and v = 0 or 1; every u on the top or bottom
//! edge inverts to the same pole. φ is computed from x and y as given, not
//! normalised, so u keeps full accuracy however close to a pole the direction
//! lies (x and y a factor 2⁻¹⁰⁰ below z, denormals included).
//!
//! # Area element
//!
//! dΩ = sin θ dθ dφ = 2π² sin(πv) du dv.

use glam::Vec3;

use crate::atlas::Atlas;
use crate::direction::normalize_direction;
use crate::mapping::{in_unit_square, ChartUv, Mapping};
use crate::math;
use core::f32::consts::{PI, TAU};

/// The latitude-longitude mapping; see the [module docs](self) for the formula.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct LatLong;

impl LatLong {
    /// Forward mapping; see the [module docs](self).
    ///
    /// ```
    /// use envmap_core::LatLong;
    /// use glam::Vec3;
    /// let c = LatLong::forward(Vec3::Y).unwrap();
    /// assert_eq!((c.u, c.v), (0.25, 0.5));
    /// ```
    #[inline]
    #[must_use]
    pub fn forward(dir: Vec3) -> Option<ChartUv> {
        let d = normalize_direction(dir)?;
        // φ from the components as given (atan2 is scale-invariant and exact
        // for any finite pair): normalising first would flush x and y of a
        // direction very close to a pole into denormals and lose their ratio.
        let phi = math::atan2(dir.y, dir.x);
        // `+ 0.0` turns a −0 (from y = −0) into +0.
        let mut u = phi / TAU + 0.0;
        if u < 0.0 {
            u += 1.0;
            // A tiny negative φ rounds up to exactly 1: wrap it to the seam.
            if u >= 1.0 {
                u = 0.0;
            }
        }
        let rho = math::sqrt(d.x * d.x + d.y * d.y);
        let theta = math::atan2(rho, d.z);
        let v = math::clamp01(theta / PI);
        Some(ChartUv::new(0, u, v))
    }

    /// Inverse mapping; `None` outside `[0, 1]²`, for NaN or a chart other than 0.
    ///
    /// ```
    /// use envmap_core::{ChartUv, LatLong};
    /// let d = LatLong::inverse(ChartUv::new(0, 0.5, 0.5)).unwrap();
    /// assert!((d - glam::Vec3::NEG_X).length() < 1e-6);
    /// ```
    #[inline]
    #[must_use]
    pub fn inverse(c: ChartUv) -> Option<Vec3> {
        if c.chart != 0 || !in_unit_square(c.u, c.v) {
            return None;
        }
        let (sp, cp) = math::sin_cos(TAU * c.u);
        let (st, ct) = math::sin_cos(PI * c.v);
        Some(Vec3::new(st * cp, st * sp, ct))
    }
}

impl Mapping for LatLong {
    fn name(&self) -> &'static str {
        "latlong"
    }
    fn chart_count(&self) -> u32 {
        1
    }
    fn forward(&self, dir: Vec3) -> Option<ChartUv> {
        Self::forward(dir)
    }
    fn inverse(&self, c: ChartUv) -> Option<Vec3> {
        Self::inverse(c)
    }
    fn solid_angle(&self, chart: u32, u0: f64, u1: f64, v0: f64, v1: f64) -> f64 {
        if chart != 0 {
            return 0.0;
        }
        crate::solid_angle::latlong(u0, u1, v0, v1)
    }
    fn atlas(&self) -> Atlas {
        Atlas::LATLONG
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: Vec3, b: Vec3) -> bool {
        (a - b).length() < 1e-6
    }

    #[test]
    fn axes() {
        let cases = [
            (Vec3::X, 0.0, 0.5),
            (Vec3::Y, 0.25, 0.5),
            (Vec3::NEG_X, 0.5, 0.5),
            (Vec3::NEG_Y, 0.75, 0.5),
            (Vec3::Z, 0.0, 0.0),
            (Vec3::NEG_Z, 0.0, 1.0),
        ];
        for (d, u, v) in cases {
            let c = LatLong::forward(d).unwrap();
            assert_eq!((c.chart, c.u, c.v), (0, u, v), "{d}");
            assert!(close(LatLong::inverse(c).unwrap(), d), "{d}");
        }
    }

    #[test]
    fn seed_quadrant_erratum() {
        // atan(y/x) would give the same u for (1, 1) and (−1, −1).
        let a = LatLong::forward(Vec3::new(1.0, 1.0, 0.0)).unwrap();
        let b = LatLong::forward(Vec3::new(-1.0, -1.0, 0.0)).unwrap();
        assert_eq!(a.u, 0.125);
        assert_eq!(b.u, 0.625);
    }

    #[test]
    fn just_below_seam_wraps_into_range() {
        let c = LatLong::forward(Vec3::new(1.0, -1e-30, 0.0)).unwrap();
        assert!(c.u < 1.0 && c.u >= 0.0);
    }

    #[test]
    fn poles_invert_from_any_u() {
        for u in [0.0, 0.3, 1.0] {
            assert!(close(
                LatLong::inverse(ChartUv::new(0, u, 0.0)).unwrap(),
                Vec3::Z
            ));
            assert!(close(
                LatLong::inverse(ChartUv::new(0, u, 1.0)).unwrap(),
                Vec3::NEG_Z
            ));
        }
    }

    #[test]
    fn bad_input() {
        assert_eq!(LatLong::forward(Vec3::ZERO), None);
        assert_eq!(LatLong::forward(Vec3::new(f32::NAN, 0.0, 1.0)), None);
        assert_eq!(LatLong::forward(Vec3::new(f32::INFINITY, 0.0, 1.0)), None);
        assert_eq!(LatLong::inverse(ChartUv::new(0, f32::NAN, 0.5)), None);
        assert_eq!(LatLong::inverse(ChartUv::new(0, 1.5, 0.5)), None);
        assert_eq!(LatLong::inverse(ChartUv::new(1, 0.5, 0.5)), None);
    }
}
