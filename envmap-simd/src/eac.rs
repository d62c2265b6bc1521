//! Equi-angular cube map, eight directions at a time, within each tier's
//! bound of [`envmap_core::Eac`].
//!
//! The face and its coordinates `(sc, tc, |ma|)` are the cube's, selected
//! branch-free and bit for bit as the core selects them
//! ([`crate::cube`]). Forward: `u = ½ + (2/π)·atan(sc/|ma|)` with the tier's
//! [`atan`](crate::approx::atan), clamped to `[0, 1]` as the core clamps it.
//! Inverse: with `a = π/4·(2u − 1)` and `b = π/4·(2v − 1)`, the face's point
//! `(tan a, tan b, 1)` is written as `2·(sin a cos b, sin b cos a, cos a cos b)`
//! (the same ray, scaled by `2 cos a cos b ∈ [1, 2]`) from the tier's
//! [`sin_cos`](crate::approx::sin_cos), so no tangent is needed; its largest
//! component is the major axis's, `2 cos a cos b`, in `[1, 2]` up to rounding
//! (within the `[½, 2]` that [`Mapping8::inverse8_ray`] asks).
//!
//! Errors against the core: the tier's `atan` error times `2/π` in `u` and
//! `v`; in direction, the tier's `sin_cos` error (the ray's components are
//! products of sines and cosines of angles up to π/4). Measured over 16 000
//! directions and a 33² grid of each face (`cargo test -p envmap-simd --lib
//! eac -- --nocapture`, which asserts bounds on them):
//!
//! | tier | forward, worst \|Δu\| or \|Δv\| | inverse, worst angle |
//! | --- | ---: | ---: |
//! | [`Exact`](crate::Exact) | 1.2e-7 | 9.9e-8 rad |
//! | [`Fine`](crate::Fine) | 2.4e-7 | 7.5e-7 rad |
//! | [`Fast`](crate::Fast) | 5.2e-5 | 1.2e-5 rad |

use core::f32::consts::{FRAC_2_PI, FRAC_PI_4};

use envmap_core::Eac;
use wide::f32x8;

use crate::approx::Tier;
use crate::batch::{finish, Dir8, Uv8};
use crate::cube::{rows8, select8};
use crate::kernel::Mapping8;

/// Forward mapping of eight directions at tier `T`.
#[inline]
#[must_use]
pub fn forward8<T: Tier>(d: Dir8) -> Uv8 {
    let (face, sc, tc, ma, valid) = select8(d);
    let half = f32x8::splat(0.5);
    let k = f32x8::splat(FRAC_2_PI);
    let unit = |x: f32x8| x.max(f32x8::ZERO).min(f32x8::ONE);
    let u = unit(half + k * T::atan(sc / ma));
    let v = unit(half + k * T::atan(tc / ma));
    finish(valid, face, u, v)
}

/// The inverse mapping's ray at tier `T`: `2·(sin a cos b, sin b cos a,
/// cos a cos b)` placed by the face table, unnormalised; invalid lanes
/// (face > 5, NaN, outside `[0, 1]²`) give NaN. [`inverse8`] is this divided
/// by its length.
#[inline]
#[must_use]
pub fn ray8<T: Tier>(c: Uv8) -> Dir8 {
    let q = f32x8::splat(FRAC_PI_4);
    let two = f32x8::splat(2.0);
    let one = f32x8::ONE;
    let (sa, ca) = T::sin_cos(q * (two * c.u - one));
    let (sb, cb) = T::sin_cos(q * (two * c.v - one));
    let two_ca = two * ca;
    rows8(c, two_ca * cb, two * sa * cb, sb * two_ca)
}

/// Inverse mapping of eight chart points to unit directions at tier `T`;
/// invalid lanes (face > 5, NaN, outside `[0, 1]²`) give NaN.
#[inline]
#[must_use]
pub fn inverse8<T: Tier>(c: Uv8) -> Dir8 {
    let r = ray8::<T>(c);
    let len = (r.x * r.x + r.y * r.y + r.z * r.z).sqrt();
    Dir8::new(r.x / len, r.y / len, r.z / len)
}

impl Mapping8 for Eac {
    #[inline]
    fn forward8<T: Tier>(&self, d: Dir8) -> Uv8 {
        forward8::<T>(d)
    }
    #[inline]
    fn inverse8<T: Tier>(&self, c: Uv8) -> Dir8 {
        inverse8::<T>(c)
    }
    /// The face table's row, unnormalised: see [`ray8`].
    #[inline]
    fn inverse8_ray<T: Tier>(&self, c: Uv8) -> Dir8 {
        ray8::<T>(c)
    }
}

#[cfg(test)]
mod tests {
    extern crate std;

    use super::*;
    use crate::{Exact, Fast, Fine, INVALID_CHART};
    use envmap_core::{ChartUv, CubeFace};
    use glam::Vec3;
    use std::vec::Vec;

    /// Directions over the sphere (a Fibonacci lattice) at several
    /// magnitudes, with the faces' axes, edges and corners.
    fn directions() -> Vec<Vec3> {
        let n = 16_000;
        let golden = core::f32::consts::PI * (3.0 - 5f32.sqrt());
        let mut d: Vec<Vec3> = (0..n)
            .map(|i| {
                let z = 1.0 - (2.0 * i as f32 + 1.0) / n as f32;
                let r = (1.0 - z * z).sqrt();
                let (s, c) = (golden * i as f32).sin_cos();
                Vec3::new(r * c, r * s, z) * [1.0, 1e-30, 1e30, 3.5][i % 4]
            })
            .collect();
        for f in CubeFace::ALL {
            d.push(f.axis());
        }
        d.extend([
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(-1.0, 0.0, 1.0),
            Vec3::new(1.0, -1.0, -1.0),
            Vec3::new(-0.0, 0.0, -1.0),
        ]);
        d
    }

    fn batches(d: &[Vec3]) -> impl Iterator<Item = (Dir8, &[Vec3])> {
        d.chunks_exact(8)
            .map(|c| (Dir8::from_vec3s(c.try_into().unwrap()), c))
    }

    /// Worst |u − u_core|, |v − v_core| of `forward8::<T>`; every chart the
    /// core's.
    fn forward_error<T: Tier>() -> f32 {
        let d = directions();
        let mut worst = 0.0f32;
        for (b, lanes) in batches(&d) {
            let uv = forward8::<T>(b);
            for (k, dir) in lanes.iter().enumerate() {
                let want = Eac::forward(*dir).unwrap();
                assert_eq!(uv.chart.as_array()[k], want.chart, "{dir}");
                worst = worst
                    .max((uv.u.as_array()[k] - want.u).abs())
                    .max((uv.v.as_array()[k] - want.v).abs());
            }
        }
        worst
    }

    /// Worst angle between `inverse8::<T>` and the core's inverse over a
    /// grid of every face, corners and edges included.
    fn inverse_error<T: Tier>() -> f32 {
        let mut pts = Vec::new();
        for chart in 0..6 {
            for i in 0..=32 {
                for j in 0..=32 {
                    pts.push(ChartUv::new(chart, i as f32 / 32.0, j as f32 / 32.0));
                }
            }
        }
        pts.truncate(pts.len() / 8 * 8);
        let mut worst = 0.0f32;
        for c in pts.chunks_exact(8) {
            let b = Uv8::from_chart_uvs(c.try_into().unwrap());
            let d = inverse8::<T>(b);
            let r = ray8::<T>(b);
            for (k, p) in c.iter().enumerate() {
                let got = Vec3::new(d.x.as_array()[k], d.y.as_array()[k], d.z.as_array()[k]);
                let want = Eac::inverse(*p).unwrap();
                worst = worst.max(got.cross(want).length().atan2(got.dot(want)));
                let ray = Vec3::new(r.x.as_array()[k], r.y.as_array()[k], r.z.as_array()[k]);
                let big = ray.abs().max_element();
                assert!((0.5..=2.0).contains(&big), "{p:?}: {ray}");
            }
        }
        worst
    }

    #[test]
    fn within_each_tiers_bound_of_the_core() {
        let f = [
            forward_error::<Exact>(),
            forward_error::<Fine>(),
            forward_error::<Fast>(),
        ];
        let i = [
            inverse_error::<Exact>(),
            inverse_error::<Fine>(),
            inverse_error::<Fast>(),
        ];
        std::eprintln!("eac forward |Δu| exact/fine/fast {f:?}; inverse angle (rad) {i:?}");
        // u: the tier's atan bound times 2/π (Exact: a few ulp of u).
        assert!(f[0] < 2e-7, "{f:?}");
        assert!(f[1] < 2e-6 * FRAC_2_PI + 1e-7, "{f:?}");
        assert!(f[2] < 1e-4 * FRAC_2_PI + 1e-7, "{f:?}");
        // Directions: the tier's sin_cos bound, a few times.
        assert!(i[0] < 5e-7, "{i:?}");
        assert!(i[1] < 6e-6, "{i:?}");
        assert!(i[2] < 3e-4, "{i:?}");
    }

    #[test]
    fn bad_lanes() {
        let d = Dir8::from_vec3s(&[
            Vec3::ZERO,
            Vec3::new(f32::NAN, 0.0, 1.0),
            Vec3::new(0.0, f32::INFINITY, 1.0),
            Vec3::Z,
            Vec3::NEG_X,
            Vec3::new(1e-45, 0.0, 0.0),
            Vec3::new(0.0, -0.0, -0.0),
            Vec3::Y,
        ]);
        let uv = forward8::<Exact>(d);
        let charts = uv.chart.to_array();
        for k in [0, 1, 2, 6] {
            assert_eq!(charts[k], INVALID_CHART);
            assert!(uv.u.as_array()[k].is_nan());
        }
        assert_eq!((charts[3], charts[4], charts[5], charts[7]), (4, 1, 0, 2));
        let c = Uv8::from_chart_uvs(&[
            ChartUv::new(6, 0.5, 0.5),
            ChartUv::new(0, 1.5, 0.5),
            ChartUv::new(0, f32::NAN, 0.5),
            ChartUv::new(4, 0.5, 0.5),
            ChartUv::new(4, 0.0, 1.0),
            ChartUv::new(1, 1.0, 0.0),
            ChartUv::new(2, 0.25, 0.75),
            ChartUv::new(5, 0.5, 0.5),
        ]);
        let d = inverse8::<Fast>(c);
        for k in 0..3 {
            assert!(d.x.as_array()[k].is_nan() && d.z.as_array()[k].is_nan());
        }
        assert_eq!(d.z.as_array()[3], 1.0);
        assert_eq!(d.z.as_array()[7], -1.0);
    }
}
