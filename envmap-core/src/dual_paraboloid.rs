//! Dual paraboloid mapping (Heidrich & Seidel 1998): two disks, front and back.
//!
//! # Formula
//!
//! Seed `000` ("Paraboloid Mapping") prints (u', v') = (rx, ry) / (rz ± 1),
//! +1 for the front hemisphere, −1 for the back one. Taken literally the back
//! disk is (rx, ry)/(rz − 1) = −(rx, ry)/(1 − rz): both coordinates negated,
//! a half turn. envmap picks the sign convention in which **the two rims meet
//! at the same (u, v)**, so a direction on the equator has the same
//! coordinates in both disks and the back disk is the front one's mirror
//! image through the z = 0 plane:
//!
//! ```text
//! chart 0 (front, rz ≥ 0, sign bit clear):  (u', v') = (rx, ry) / (1 + rz)
//! chart 1 (back,  rz ≤ 0, sign bit set):    (u', v') = (rx, ry) / (1 − rz)
//! seed, back chart as printed:              (u', v') = (rx, ry) / (rz − 1) = −(ours)
//! (u, v) = (u'/2 + 1/2, v'/2 + 1/2)
//! inverse, r² = u'² + v'² ≤ 1:  R = (2u', 2v', ±(1 − r²)) / (1 + r²)
//! ```
//!
//! Each disk is a stereographic projection of its hemisphere: the equator is
//! the rim r = 1, the pole (±z) the centre.
//!
//! # Axes, seams and ties
//!
//! u along +x, v along +y in both disks. The seam is the equator z = 0 (the
//! two rims); a direction with z = ±0 goes to the chart its sign bit picks
//! (+0 front, −0 back) and has the same (u, v) in both. The corners outside
//! the disks hold no direction.
//!
//! # Area element
//!
//! dΩ = 4 du' dv' / (1 + r²)², from 4 at the centre to 1 on the rim.

use glam::Vec3;

use crate::atlas::Atlas;
use crate::direction::normalize_direction;
use crate::mapping::{in_unit_disk, ChartUv, Mapping};
use crate::math;

/// The front chart (z ≥ 0).
pub const FRONT: u32 = 0;
/// The back chart (z ≤ 0).
pub const BACK: u32 = 1;

/// The dual paraboloid mapping; see the [module docs](self).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct DualParaboloid;

impl DualParaboloid {
    /// Forward mapping; see the [module docs](self).
    ///
    /// ```
    /// use envmap_core::DualParaboloid;
    /// use glam::Vec3;
    /// let c = DualParaboloid::forward(Vec3::new(1.0, 0.0, 0.0)).unwrap();
    /// assert_eq!((c.chart, c.u, c.v), (0, 1.0, 0.5));
    /// let c = DualParaboloid::forward(Vec3::NEG_Z).unwrap();
    /// assert_eq!((c.chart, c.u, c.v), (1, 0.5, 0.5));
    /// ```
    #[inline]
    #[must_use]
    pub fn forward(dir: Vec3) -> Option<ChartUv> {
        let r = normalize_direction(dir)?;
        let back = r.z.is_sign_negative();
        let den = 1.0 + r.z.abs();
        let u = math::clamp01(0.5 * (r.x / den) + 0.5);
        let v = math::clamp01(0.5 * (r.y / den) + 0.5);
        Some(ChartUv::new(u32::from(back), u, v))
    }

    /// Inverse mapping; `None` outside the disk, for NaN or a chart above 1.
    #[inline]
    #[must_use]
    pub fn inverse(c: ChartUv) -> Option<Vec3> {
        if c.chart > 1 || !in_unit_disk(c.u, c.v) {
            return None;
        }
        let (x, y) = (2.0 * c.u - 1.0, 2.0 * c.v - 1.0);
        let r2 = x * x + y * y;
        let z = (1.0 - r2).max(0.0);
        let z = if c.chart == BACK { -z } else { z };
        let d = Vec3::new(2.0 * x, 2.0 * y, z) / (1.0 + r2);
        Some(d / math::sqrt(d.length_squared()))
    }
}

impl Mapping for DualParaboloid {
    fn name(&self) -> &'static str {
        "paraboloid"
    }
    fn chart_count(&self) -> u32 {
        2
    }
    fn forward(&self, dir: Vec3) -> Option<ChartUv> {
        Self::forward(dir)
    }
    fn inverse(&self, c: ChartUv) -> Option<Vec3> {
        Self::inverse(c)
    }
    fn in_chart(&self, chart: u32, u: f32, v: f32) -> bool {
        chart < 2 && in_unit_disk(u, v)
    }
    fn solid_angle(&self, chart: u32, u0: f64, u1: f64, v0: f64, v1: f64) -> f64 {
        if chart >= 2 {
            return 0.0;
        }
        crate::solid_angle::paraboloid(u0, u1, v0, v1)
    }
    fn atlas(&self) -> Atlas {
        Atlas::PARABOLOID_SIDE_BY_SIDE
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn poles_and_equator() {
        let c = DualParaboloid::forward(Vec3::Z).unwrap();
        assert_eq!((c.chart, c.u, c.v), (FRONT, 0.5, 0.5));
        let c = DualParaboloid::forward(Vec3::NEG_Z).unwrap();
        assert_eq!((c.chart, c.u, c.v), (BACK, 0.5, 0.5));
        // Equator: same (u, v) in both charts.
        let a = DualParaboloid::forward(Vec3::new(0.6, 0.8, 0.0)).unwrap();
        let b = DualParaboloid::forward(Vec3::new(0.6, 0.8, -0.0)).unwrap();
        assert_eq!((a.chart, b.chart), (FRONT, BACK));
        assert_eq!((a.u, a.v), (b.u, b.v));
        assert_eq!((a.u, a.v), (0.8, 0.9));
    }

    #[test]
    fn seed_back_chart_is_a_half_turn_of_ours() {
        let r = Vec3::new(0.3, -0.2, -0.5).normalize();
        let ours = DualParaboloid::forward(r).unwrap();
        let seed_u = 0.5 * (r.x / (r.z - 1.0)) + 0.5;
        let seed_v = 0.5 * (r.y / (r.z - 1.0)) + 0.5;
        assert!((seed_u - (1.0 - ours.u)).abs() < 1e-6);
        assert!((seed_v - (1.0 - ours.v)).abs() < 1e-6);
    }

    #[test]
    fn bad_input() {
        assert_eq!(DualParaboloid::forward(Vec3::ZERO), None);
        assert_eq!(DualParaboloid::inverse(ChartUv::new(2, 0.5, 0.5)), None);
        assert_eq!(DualParaboloid::inverse(ChartUv::new(0, 0.0, 0.0)), None);
    }
}
