//! Tennisball mapping: two latitude-longitude strips that cover each other's poles and seams.
//!
//! # Formula, as printed in seed `000` ("Tennisball map")
//!
//! ```text
//! R = (a, b, c)
//! C1: (θ, φ) = (asin b, atan2(a, −c))
//! C2: (θ, φ) = (asin a, atan2(b, −c))
//! chart C1 when (c ≥ 0 and |b| ≤ √2/2) or (c ≤ 0 and |a| ≥ √2/2), else C2
//! ranges: −π/4 ≤ θ ≤ π/4,  −3π/4 ≤ φ ≤ 3π/4
//! ```
//!
//! **Erratum.** As printed, both charts measure longitude from −z, so both
//! leave out the same wedge around +z: R = (0, 0, 1) gets φ = π in either
//! chart, and with the printed selection rule about 18 % of uniformly random
//! directions fall outside the printed ranges ([`seed_printed_angles`] keeps
//! the printed version so the tests can show this).
//!
//! # Formula, as corrected here
//!
//! Chart 1 measures its longitude from +z instead; chart 2 and the selection
//! rule are unchanged:
//!
//! ```text
//! C1 (chart 0): (θ, φ) = (asin b, atan2(a, c))      ← was atan2(a, −c)
//! C2 (chart 1): (θ, φ) = (asin a, atan2(b, −c))
//! inverse C1: (a, b, c) = (cos θ sin φ, sin θ, cos θ cos φ)
//! inverse C2: (a, b, c) = (sin θ, cos θ sin φ, −cos θ cos φ)
//! ```
//!
//! With this, every direction lands inside the printed ranges under the
//! printed selection rule. Proof, with s = √2/2 and a² + b² + c² = 1: C1 with
//! c ≥ 0, |b| ≤ s: |θ| ≤ π/4 and |φ| ≤ π/2. C1 with c ≤ 0, |a| ≥ s: b² ≤ 1 − a²
//! ≤ ½ so |θ| ≤ π/4, and |c| ≤ s ≤ |a| puts atan2(a, c) within 3π/4 of 0. C2
//! with c > 0: then |b| > s, so |a| < s and |c| < |b|, giving π/2 < |φ| < 3π/4.
//! C2 with c ≤ 0: |a| < s and −c ≥ 0, so |φ| ≤ π/2. The property tests check
//! this on random directions, the axes and the boundaries.
//!
//! # Layout, axes and ownership
//!
//! Each chart is a 3:1 strip, φ across and θ down:
//! u = (φ + 3π/4) / (3π/2), v = (π/4 − θ) / (π/2) (θ = +π/4 on the top row).
//! The strips are stacked, chart 0 on top (a 3:2 image).
//!
//! Every point of a strip inverts to a direction, but each strip also covers
//! part of the other's region: chart 0 **owns** (is selected for) the
//! directions with |φ| ≤ π/2, plus those with |φ| > π/2 and
//! cos θ |sin φ| ≥ √2/2; chart 1 owns the same shape in its own coordinates.
//! `forward(inverse(c)) = c` holds where the chart owns `inverse(c)`; elsewhere
//! forward answers in the other chart. The overlap lets a filter read across a
//! chart's boundary without leaving the chart.
//!
//! # Area element
//!
//! dΩ = cos θ dθ dφ within the owned region.

use glam::Vec3;

use crate::atlas::Atlas;
use crate::direction::normalize_direction;
use crate::mapping::{in_unit_square, ChartUv, Mapping};
use crate::math;
use core::f32::consts::{FRAC_1_SQRT_2, FRAC_PI_2, FRAC_PI_4, PI};

const PHI_MAX: f32 = 3.0 * FRAC_PI_4;
const PHI_SPAN: f32 = 1.5 * PI;

/// Whether the seed's selection rule picks chart C1 (chart 0) for the unit
/// vector (a, b, c).
#[inline]
#[must_use]
pub fn selects_chart_0(a: f32, b: f32, c: f32) -> bool {
    (c >= 0.0 && b.abs() <= FRAC_1_SQRT_2) || (c <= 0.0 && a.abs() >= FRAC_1_SQRT_2)
}

/// The corrected chart and angles (chart, θ, φ) of a direction, before they
/// become (u, v); `None` for NaN, ±Inf or zero.
///
/// θ and φ are clamped to the ranges (they can only leave them by a rounding
/// error of an ulp or so at the chart boundaries).
#[inline]
#[must_use]
pub fn angles(dir: Vec3) -> Option<(u32, f32, f32)> {
    let (chart, theta, phi) = raw_angles(dir)?;
    Some((
        chart,
        theta.clamp(-FRAC_PI_4, FRAC_PI_4),
        phi.clamp(-PHI_MAX, PHI_MAX),
    ))
}

/// The corrected angles without clamping (for tests of the range proof).
#[inline]
#[must_use]
pub fn raw_angles(dir: Vec3) -> Option<(u32, f32, f32)> {
    let d = normalize_direction(dir)?;
    let (a, b, c) = (d.x, d.y, d.z);
    if selects_chart_0(a, b, c) {
        Some((0, math::asin(b), math::atan2(a, c)))
    } else {
        Some((1, math::asin(a), math::atan2(b, -c)))
    }
}

/// The seed's formulas **as printed** (chart 0 with atan2(a, −c)), unclamped.
///
/// Kept to document the erratum: for (0, 0, 1) it gives φ = π, outside the
/// printed range. Do not use for mapping.
#[inline]
#[must_use]
pub fn seed_printed_angles(dir: Vec3) -> Option<(u32, f32, f32)> {
    let d = normalize_direction(dir)?;
    let (a, b, c) = (d.x, d.y, d.z);
    if selects_chart_0(a, b, c) {
        Some((0, math::asin(b), math::atan2(a, -c)))
    } else {
        Some((1, math::asin(a), math::atan2(b, -c)))
    }
}

/// Whether (θ, φ) of a chart lies in the region that chart owns.
#[inline]
#[must_use]
pub fn owns(theta: f32, phi: f32) -> bool {
    phi.abs() <= FRAC_PI_2 || math::cos(theta) * math::sin(phi).abs() >= FRAC_1_SQRT_2
}

/// The tennisball mapping; see the [module docs](self).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Tennisball;

impl Tennisball {
    /// Forward mapping; see the [module docs](self).
    ///
    /// ```
    /// use envmap_core::Tennisball;
    /// use glam::Vec3;
    /// // +z is the centre of chart 0 (the printed formula put it at φ = π).
    /// let c = Tennisball::forward(Vec3::Z).unwrap();
    /// assert_eq!((c.chart, c.u, c.v), (0, 0.5, 0.5));
    /// ```
    #[inline]
    #[must_use]
    pub fn forward(dir: Vec3) -> Option<ChartUv> {
        let (chart, theta, phi) = angles(dir)?;
        let u = math::clamp01(phi / PHI_SPAN + 0.5);
        let v = math::clamp01(0.5 - theta / FRAC_PI_2);
        Some(ChartUv::new(chart, u, v))
    }

    /// Inverse mapping; `None` outside `[0, 1]²`, for NaN or a chart above 1.
    #[inline]
    #[must_use]
    pub fn inverse(c: ChartUv) -> Option<Vec3> {
        if c.chart > 1 || !in_unit_square(c.u, c.v) {
            return None;
        }
        let phi = (c.u - 0.5) * PHI_SPAN;
        let theta = (0.5 - c.v) * FRAC_PI_2;
        let (sp, cp) = math::sin_cos(phi);
        let (st, ct) = math::sin_cos(theta);
        Some(if c.chart == 0 {
            Vec3::new(ct * sp, st, ct * cp)
        } else {
            Vec3::new(st, ct * sp, -ct * cp)
        })
    }
}

impl Mapping for Tennisball {
    fn name(&self) -> &'static str {
        "tennisball"
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
    fn solid_angle(&self, chart: u32, u0: f64, u1: f64, v0: f64, v1: f64) -> f64 {
        if chart >= 2 {
            return 0.0;
        }
        crate::solid_angle::tennisball(u0, u1, v0, v1)
    }
    fn atlas(&self) -> Atlas {
        Atlas::TENNISBALL_STACKED
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn seed_erratum_plus_z() {
        let (chart, _, phi) = seed_printed_angles(Vec3::Z).unwrap();
        assert_eq!(chart, 0);
        assert!((phi - PI).abs() < 1e-6, "printed formula: φ = π at +z");
        let (chart, theta, phi) = angles(Vec3::Z).unwrap();
        assert_eq!((chart, theta, phi), (0, 0.0, 0.0));
    }

    #[test]
    fn axes() {
        // (direction, chart, u, v)
        let cases = [
            (Vec3::Z, 0, 0.5, 0.5),
            (Vec3::X, 0, 5.0 / 6.0, 0.5),
            (Vec3::NEG_X, 0, 1.0 / 6.0, 0.5),
            (Vec3::Y, 1, 1.0 / 6.0 + 2.0 / 3.0, 0.5),
            (Vec3::NEG_Y, 1, 1.0 / 6.0, 0.5),
            (Vec3::NEG_Z, 1, 0.5, 0.5),
        ];
        for (d, chart, u, v) in cases {
            let c = Tennisball::forward(d).unwrap();
            assert_eq!(c.chart, chart, "{d}");
            assert!(
                (c.u - u).abs() < 1e-6 && (c.v - v).abs() < 1e-6,
                "{d} {c:?}"
            );
            assert!((Tennisball::inverse(c).unwrap() - d).length() < 1e-6, "{d}");
        }
    }

    #[test]
    fn ownership_matches_selection_at_strip_centres() {
        for chart in 0..2 {
            let d = Tennisball::inverse(ChartUv::new(chart, 0.5, 0.5)).unwrap();
            assert_eq!(Tennisball::forward(d).unwrap().chart, chart);
        }
        // Far ends of a strip at its top row belong to the other chart.
        let d = Tennisball::inverse(ChartUv::new(0, 0.02, 0.02)).unwrap();
        assert_eq!(Tennisball::forward(d).unwrap().chart, 1);
    }

    #[test]
    fn bad_input() {
        assert_eq!(Tennisball::forward(Vec3::ZERO), None);
        assert_eq!(Tennisball::inverse(ChartUv::new(2, 0.5, 0.5)), None);
        assert_eq!(Tennisball::inverse(ChartUv::new(0, 0.5, f32::NAN)), None);
    }
}
