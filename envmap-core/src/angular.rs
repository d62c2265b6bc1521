//! Angular map (Debevec's light probe): a disk whose radius is proportional to
//! the angle from the view axis.
//!
//! # Formula
//!
//! P. Debevec, "Rendering Synthetic Objects into Real Scenes", SIGGRAPH 1998,
//! and his Light Probe Image Gallery page (the format of HDRShop's light
//! probes): for a unit direction D, `(u', v') = (Dx·r, Dy·r)` with
//! `r = (1/π)·acos(Dz)/√(Dx² + Dy²)`, the centre being +z. The distance from
//! the centre is the angle from +z over π (the azimuthal equidistant
//! projection). envmap computes the angle as `atan2(√(x² + y²), z)`, which
//! equals `acos(z)` on unit vectors but keeps its accuracy next to ±z (the
//! rounding of z alone puts `acos(z)` up to 3e-4 rad off there):
//!
//! ```text
//! θ = atan2(√(x² + y²), z) ∈ [0, π],   ρ = θ/π ∈ [0, 1]
//! (u', v') = ρ·(x, y)/√(x² + y²)
//! (u, v) = (u'/2 + 1/2, v'/2 + 1/2)
//! inverse: ρ = √(u'² + v'²) ≤ 1, θ = πρ,
//!          R = (sin θ·u'/ρ, sin θ·v'/ρ, cos θ)   (sin θ/ρ → π as ρ → 0)
//! ```
//!
//! # Axes and the singular direction
//!
//! The view axis is z, as in the [sphere maps](crate::sphere_map): the centre
//! (½, ½) is +z, u grows along +x and v along +y (v grows downwards, so +y
//! lies below the centre in the image; a file's own orientation is a
//! [`Frame`](crate::Frame)'s business). Directions at right angles to the
//! axis (z = 0) lie on the circle of radius ½ around the centre: +x at
//! (¾, ½), +y at (½, ¾).
//!
//! The direction −z is singular: every point of the rim ρ = 1 inverts to it.
//! **Forward** maps that exact direction to the rim point (u, v) = (1, ½)
//! (u' = 1, v' = 0), the sphere map's rule; more generally a direction whose
//! x and y are both ±0 takes the azimuth of +x (for +z, ρ = 0 and that is
//! the centre). Any other direction, however close to −z, lands on or next
//! to the rim at its own azimuth: the azimuth is taken from x and y as given,
//! divided by the larger of |x|, |y|, so it keeps full accuracy whatever
//! their size (denormals included). **Inverse** of any rim point gives −z.
//! The corners outside the disk hold no direction (`inverse` gives `None`,
//! [`Mapping::in_chart`] is false).
//!
//! # Accuracy near the rim
//!
//! Unlike a sphere map's, the rim does not squeeze its neighbourhood: an
//! angular distance β from −z sits at 1 − ρ = β/π from the rim, so the f32
//! resolution of (u, v) costs the same angle there as anywhere in the outer
//! half of the disk. Next to the rim, `inverse` evaluates sin θ as
//! sin(π(1 − ρ)) and cos θ as −cos(π(1 − ρ)) (1 − ρ is exact in f32 for
//! ρ ≥ ½), so that the direction keeps its relative accuracy as θ → π.
//!
//! # Area element
//!
//! dΩ = sin θ dθ dφ with θ = πρ and ρ dρ dφ = du' dv':
//! dΩ = π sin(πρ)/ρ du' dv' = 4π sin(πρ)/ρ du dv inside the disk (from π²
//! at the centre to 0 on the rim; the whole disk: 2π² ∫₀¹ sin(πρ) dρ = 4π).

use core::f32::consts::PI;

use glam::Vec3;

use crate::atlas::Atlas;
use crate::direction::normalize_direction;
use crate::mapping::{in_unit_disk, ChartUv, Mapping};
use crate::math;

/// The angular map (Debevec's light probe); see the [module docs](self).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Angular;

impl Angular {
    /// Forward mapping; see the [module docs](self).
    ///
    /// ```
    /// use envmap_core::Angular;
    /// use glam::Vec3;
    /// // The view axis is the centre, the directions at right angles to it
    /// // the circle of radius ½, and −z the rim point (1, ½).
    /// let c = Angular::forward(Vec3::Z).unwrap();
    /// assert_eq!((c.u, c.v), (0.5, 0.5));
    /// let c = Angular::forward(Vec3::X).unwrap();
    /// assert_eq!((c.u, c.v), (0.75, 0.5));
    /// let c = Angular::forward(Vec3::NEG_Z).unwrap();
    /// assert_eq!((c.u, c.v), (1.0, 0.5));
    /// ```
    #[inline]
    #[must_use]
    pub fn forward(dir: Vec3) -> Option<ChartUv> {
        let r = normalize_direction(dir)?;
        // The azimuth from x and y as given, scaled by the larger magnitude
        // (division, so denormals keep their ratio and nothing is squared at
        // its own scale); x = y = ±0 takes the azimuth of +x.
        let a = dir.x.abs().max(dir.y.abs());
        let (px, py) = if a == 0.0 {
            (1.0, 0.0)
        } else {
            (dir.x / a, dir.y / a)
        };
        // 1 ≤ len ≤ √2: the larger of |px|, |py| is 1.
        let len = math::sqrt(px * px + py * py);
        // √(rx² + ry²) without squaring rx and ry at their own scale.
        let sin_theta = r.x.abs().max(r.y.abs()) * len;
        let theta = math::atan2(sin_theta, r.z);
        let rho = (theta / PI).min(1.0);
        let k = rho / len;
        let u = math::clamp01(0.5 * (k * px) + 0.5);
        let v = math::clamp01(0.5 * (k * py) + 0.5);
        Some(ChartUv::new(0, u, v))
    }

    /// Inverse mapping; `None` outside the disk, for NaN or a chart other than 0.
    ///
    /// ```
    /// use envmap_core::{Angular, ChartUv};
    /// use glam::Vec3;
    /// let d = Angular::inverse(ChartUv::new(0, 0.5, 0.75)).unwrap();
    /// assert!((d - Vec3::Y).length() < 1e-6);
    /// // Every rim point is −z.
    /// assert_eq!(Angular::inverse(ChartUv::new(0, 0.5, 0.0)).unwrap().z, -1.0);
    /// ```
    #[inline]
    #[must_use]
    pub fn inverse(c: ChartUv) -> Option<Vec3> {
        if c.chart != 0 || !in_unit_disk(c.u, c.v) {
            return None;
        }
        let (x, y) = (2.0 * c.u - 1.0, 2.0 * c.v - 1.0);
        // At most 1 + 2ε inside the disk (`in_unit_disk` allows for rounding).
        let rho = math::sqrt(x * x + y * y).min(1.0);
        // sin θ and cos θ for θ = πρ; in the outer half from the exact 1 − ρ,
        // so that sin θ keeps its relative accuracy as θ → π.
        let (s, c) = if rho <= 0.5 {
            math::sin_cos(PI * rho)
        } else {
            let (s, c) = math::sin_cos(PI * (1.0 - rho));
            (s, -c)
        };
        // sin(πρ)/ρ → π as ρ → 0 (ρ is 0 or at least 2⁻²⁴ here).
        let k = if rho > 0.0 { s / rho } else { PI };
        let d = Vec3::new(k * x, k * y, c);
        Some(d / math::sqrt(d.length_squared()))
    }
}

impl Mapping for Angular {
    fn name(&self) -> &'static str {
        "angular"
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
    fn in_chart(&self, chart: u32, u: f32, v: f32) -> bool {
        chart == 0 && in_unit_disk(u, v)
    }
    fn solid_angle(&self, chart: u32, u0: f64, u1: f64, v0: f64, v1: f64) -> f64 {
        if chart != 0 {
            return 0.0;
        }
        crate::solid_angle::angular(u0, u1, v0, v1)
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
        let c = Angular::forward(Vec3::Z).unwrap();
        assert_eq!((c.u, c.v), (0.5, 0.5));
        assert_eq!(Angular::inverse(c).unwrap(), Vec3::Z);
        // The 90° ring: radius ½.
        for (d, u, v) in [
            (Vec3::X, 0.75, 0.5),
            (Vec3::NEG_X, 0.25, 0.5),
            (Vec3::Y, 0.5, 0.75),
            (Vec3::NEG_Y, 0.5, 0.25),
        ] {
            let c = Angular::forward(d).unwrap();
            assert_eq!((c.u, c.v), (u, v), "{d}");
            let back = Angular::inverse(c).unwrap();
            assert!((back - d).length() < 1e-7, "{d}: {back}");
        }
        // The singular direction: the documented rim point, and every rim
        // point inverts to it.
        let c = Angular::forward(Vec3::NEG_Z).unwrap();
        assert_eq!((c.u, c.v), (1.0, 0.5));
        for (u, v) in [(1.0, 0.5), (0.0, 0.5), (0.5, 0.0), (0.5, 1.0)] {
            let d = Angular::inverse(ChartUv::new(0, u, v)).unwrap();
            assert_eq!(d, Vec3::NEG_Z, "{u} {v}");
        }
    }

    #[test]
    fn near_singular_direction_goes_to_the_rim_at_its_azimuth() {
        let c = Angular::forward(Vec3::new(0.0, -1e-20, -1.0)).unwrap();
        assert_eq!((c.u, c.v), (0.5, 0.0));
        let c = Angular::forward(Vec3::new(-1e-45, 0.0, -1.0)).unwrap();
        assert_eq!((c.u, c.v), (0.0, 0.5));
        // x = y = ±0: the azimuth of +x, for either sign.
        let c = Angular::forward(Vec3::new(-0.0, -0.0, -3.0)).unwrap();
        assert_eq!((c.u, c.v), (1.0, 0.5));
    }

    #[test]
    fn corners_are_outside() {
        assert_eq!(Angular::inverse(ChartUv::new(0, 0.0, 0.0)), None);
        assert!(!Angular.in_chart(0, 0.05, 0.05));
        assert!(Angular.in_chart(0, 0.5, 0.5));
    }

    #[test]
    fn bad_input() {
        assert_eq!(Angular::forward(Vec3::ZERO), None);
        assert_eq!(Angular::forward(Vec3::splat(f32::NAN)), None);
        assert_eq!(Angular::inverse(ChartUv::new(0, f32::NAN, 0.5)), None);
        assert_eq!(Angular::inverse(ChartUv::new(1, 0.5, 0.5)), None);
    }
}
