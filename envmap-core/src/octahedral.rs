//! Octahedral maps: the plain one (Engelhardt & Dachsbacher 2008) and the
//! equal-area one (Clarberg 2008, as used by pbrt-v4).
//!
//! Both unfold the sphere onto the square [−1, 1]² (u' = 2u − 1, v' = 2v − 1):
//! the upper hemisphere (z ≥ 0) fills the inner diamond |u'| + |v'| ≤ 1 around
//! +z at the centre, the lower hemisphere the four corner triangles, with −z
//! at the four corners.
//!
//! # Octahedral (Engelhardt & Dachsbacher, "Octahedron Environment Maps", VMV 2008)
//!
//! ```text
//! p = R / (|rx| + |ry| + |rz|)                             (onto the octahedron)
//! (u', v') = (px, py)                                      if rz ≥ 0
//! (u', v') = ((1 − |py|)·sgn px, (1 − |px|)·sgn py)        if rz < 0 (fold)
//! inverse: z = 1 − |u'| − |v'|;  (x, y) = (u', v') if z ≥ 0,
//!          else ((1 − |v'|)·sgn u', (1 − |u'|)·sgn v');  R = normalize(x, y, z)
//! ```
//!
//! `sgn` takes the sign bit (copysign), so signed zeros count: on the lower
//! hemisphere's folds x = ±0 and y = ±0 the two signs give the two images of
//! the same direction on the square's edge. Area element:
//! dΩ = du' dv' / |p|³ with p the unnormalised inverse.
//!
//! # Equal-area octahedral (Clarberg, "Fast Equal-Area Mapping of the (Hemi)Sphere using SIMD", JGT 2008; pbrt-v4 `EqualAreaSphereToSquare`)
//!
//! ```text
//! r = √(1 − |rz|)  (computed as √((rx² + ry²) / (1 + |rz|)), no cancellation at the poles)
//! φ = (2/π)·atan(min(|rx|,|ry|) / max(|rx|,|ry|)), then φ ← 1 − φ if |rx| < |ry|
//! v' = φ r,  u' = r − v'
//! if rz < 0: (u', v') ← (1 − v', 1 − u')
//! u' ← copysign(u', rx), v' ← copysign(v', ry)
//! inverse: d = 1 − |u'| − |v'|, r = 1 − |d|, φ = ((|v'| − |u'|)/r + 1)·π/4,
//!          z = copysign(1 − r², d), (x, y) = (copysign(cos φ, u'), copysign(sin φ, v'))·r√(2 − r²)
//! ```
//!
//! Every region's solid angle is 4π times its area in (u, v).
//!
//! # Seams
//!
//! Both maps are continuous inside the square, including across the diamond
//! (the equator). The square's outer edges are seams: (u', ±1) and (−u', ±1)
//! are the same direction, as are (±1, v') and (±1, −v'); the four corners are
//! all −z.

use glam::Vec3;

use crate::atlas::Atlas;
use crate::direction::normalize_direction;
use crate::mapping::{in_unit_square, ChartUv, Mapping};
use crate::math::{self, copysign};
use core::f32::consts::{FRAC_2_PI, FRAC_PI_4};

/// The octahedral map (Engelhardt & Dachsbacher 2008); see the [module docs](self).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Octahedral;

/// The equal-area octahedral map (Clarberg 2008, pbrt-v4); see the [module docs](self).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct EqualAreaOctahedral;

#[inline]
fn to_uv(x: f32, y: f32) -> ChartUv {
    ChartUv::new(
        0,
        math::clamp01(0.5 * x + 0.5),
        math::clamp01(0.5 * y + 0.5),
    )
}

impl Octahedral {
    /// Forward mapping; see the [module docs](self).
    ///
    /// ```
    /// use envmap_core::Octahedral;
    /// use glam::Vec3;
    /// let c = Octahedral::forward(Vec3::new(1.0, 1.0, 0.0)).unwrap();
    /// assert_eq!((c.u, c.v), (0.75, 0.75));
    /// ```
    #[inline]
    #[must_use]
    pub fn forward(dir: Vec3) -> Option<ChartUv> {
        let d = normalize_direction(dir)?;
        let p = d / (d.x.abs() + d.y.abs() + d.z.abs());
        let (x, y) = if p.z < 0.0 {
            (
                copysign(1.0 - p.y.abs(), p.x),
                copysign(1.0 - p.x.abs(), p.y),
            )
        } else {
            (p.x, p.y)
        };
        Some(to_uv(x, y))
    }

    /// Inverse mapping; `None` outside `[0, 1]²`, for NaN or a chart other than 0.
    #[inline]
    #[must_use]
    pub fn inverse(c: ChartUv) -> Option<Vec3> {
        if c.chart != 0 || !in_unit_square(c.u, c.v) {
            return None;
        }
        let (x, y) = (2.0 * c.u - 1.0, 2.0 * c.v - 1.0);
        let z = 1.0 - x.abs() - y.abs();
        let d = if z < 0.0 {
            Vec3::new(copysign(1.0 - y.abs(), x), copysign(1.0 - x.abs(), y), z)
        } else {
            Vec3::new(x, y, z)
        };
        Some(d / math::sqrt(d.length_squared()))
    }
}

impl EqualAreaOctahedral {
    /// Forward mapping; see the [module docs](self).
    ///
    /// ```
    /// use envmap_core::EqualAreaOctahedral;
    /// use glam::Vec3;
    /// let c = EqualAreaOctahedral::forward(Vec3::Z).unwrap();
    /// assert_eq!((c.u, c.v), (0.5, 0.5));
    /// let c = EqualAreaOctahedral::forward(Vec3::X).unwrap();
    /// assert_eq!((c.u, c.v), (1.0, 0.5));
    /// ```
    #[inline]
    #[must_use]
    pub fn forward(dir: Vec3) -> Option<ChartUv> {
        let d = normalize_direction(dir)?;
        let (ax, ay, az) = (d.x.abs(), d.y.abs(), d.z.abs());
        let r = math::sqrt((ax * ax + ay * ay) / (1.0 + az));
        let (hi, lo) = if ax >= ay { (ax, ay) } else { (ay, ax) };
        let mut phi = if hi == 0.0 {
            0.0
        } else {
            math::atan(lo / hi) * FRAC_2_PI
        };
        if ax < ay {
            phi = 1.0 - phi;
        }
        let mut v = phi * r;
        let mut u = r - v;
        if d.z < 0.0 {
            (u, v) = (1.0 - v, 1.0 - u);
        }
        Some(to_uv(copysign(u, d.x), copysign(v, d.y)))
    }

    /// Inverse mapping; `None` outside `[0, 1]²`, for NaN or a chart other than 0.
    #[inline]
    #[must_use]
    pub fn inverse(c: ChartUv) -> Option<Vec3> {
        if c.chart != 0 || !in_unit_square(c.u, c.v) {
            return None;
        }
        let (u, v) = (2.0 * c.u - 1.0, 2.0 * c.v - 1.0);
        let (au, av) = (u.abs(), v.abs());
        let sum = au + av;
        let signed_distance = 1.0 - sum;
        // r = 1 − |1 − sum|, written to keep full precision near both poles.
        let r = if signed_distance >= 0.0 {
            sum
        } else {
            2.0 - sum
        };
        let phi = if r == 0.0 {
            FRAC_PI_4
        } else {
            ((av - au) / r + 1.0) * FRAC_PI_4
        };
        let z = copysign(1.0 - r * r, signed_distance);
        let (sp, cp) = math::sin_cos(phi);
        let k = r * math::sqrt((2.0 - r * r).max(0.0));
        let d = Vec3::new(copysign(cp, u) * k, copysign(sp, v) * k, z);
        Some(d / math::sqrt(d.length_squared()))
    }
}

macro_rules! square_mapping {
    ($ty:ty, $name:literal, $sa:path) => {
        impl Mapping for $ty {
            fn name(&self) -> &'static str {
                $name
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
                $sa(u0, u1, v0, v1)
            }
            fn atlas(&self) -> Atlas {
                Atlas::SINGLE_SQUARE
            }
        }
    };
}

square_mapping!(Octahedral, "octahedral", crate::solid_angle::octahedral);
square_mapping!(
    EqualAreaOctahedral,
    "octahedral-equal-area",
    crate::solid_angle::equal_area_octahedral
);

#[cfg(test)]
mod tests {
    use super::*;

    fn axes_check(fwd: fn(Vec3) -> Option<ChartUv>, inv: fn(ChartUv) -> Option<Vec3>) {
        let cases = [
            (Vec3::Z, 0.5, 0.5),
            (Vec3::X, 1.0, 0.5),
            (Vec3::NEG_X, 0.0, 0.5),
            (Vec3::Y, 0.5, 1.0),
            (Vec3::NEG_Y, 0.5, 0.0),
        ];
        for (d, u, v) in cases {
            let c = fwd(d).unwrap();
            assert!(
                (c.u - u).abs() < 1e-6 && (c.v - v).abs() < 1e-6,
                "{d} {c:?}"
            );
            assert!((inv(c).unwrap() - d).length() < 1e-6, "{d}");
        }
        // −z: a corner; all four corners invert to it.
        let c = fwd(Vec3::NEG_Z).unwrap();
        assert!(c.u == 0.0 || c.u == 1.0, "{c:?}");
        assert!(c.v == 0.0 || c.v == 1.0, "{c:?}");
        for (u, v) in [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)] {
            let d = inv(ChartUv::new(0, u, v)).unwrap();
            assert!((d - Vec3::NEG_Z).length() < 1e-6);
        }
    }

    #[test]
    fn octahedral_axes() {
        axes_check(Octahedral::forward, Octahedral::inverse);
    }

    #[test]
    fn equal_area_axes() {
        axes_check(EqualAreaOctahedral::forward, EqualAreaOctahedral::inverse);
    }

    #[test]
    fn octahedral_edge_seam() {
        // (u', 1) and (−u', 1) are the same direction.
        let a = Octahedral::inverse(ChartUv::new(0, 0.2, 1.0)).unwrap();
        let b = Octahedral::inverse(ChartUv::new(0, 0.8, 1.0)).unwrap();
        assert!((a - b).length() < 1e-6);
        let a = EqualAreaOctahedral::inverse(ChartUv::new(0, 0.2, 1.0)).unwrap();
        let b = EqualAreaOctahedral::inverse(ChartUv::new(0, 0.8, 1.0)).unwrap();
        assert!((a - b).length() < 1e-6);
    }

    #[test]
    fn bad_input() {
        assert_eq!(Octahedral::forward(Vec3::ZERO), None);
        assert_eq!(EqualAreaOctahedral::forward(Vec3::NAN), None);
        assert_eq!(Octahedral::inverse(ChartUv::new(0, 2.0, 0.5)), None);
        assert_eq!(
            EqualAreaOctahedral::inverse(ChartUv::new(1, 0.5, 0.5)),
            None
        );
    }
}
