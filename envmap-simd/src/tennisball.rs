//! Tennisball mapping (with the corrected chart 1), eight directions at a time.
//!
//! The formula of [`envmap_core::tennisball`]: chart 0 when (c ≥ 0 and
//! |b| ≤ √2/2) or (c ≤ 0 and |a| ≥ √2/2), (θ, φ) = (asin b, atan2(a, c));
//! otherwise chart 1, (asin a, atan2(b, −c)); u = φ/(3π/2) + ½,
//! v = ½ − θ/(π/2). Both charts are evaluated with one `asin` and one `atan2`
//! on blended arguments.

use core::f32::consts::{FRAC_1_SQRT_2, FRAC_PI_2, FRAC_PI_4, PI};

use envmap_core::Tennisball;
use wide::{f32x8, u32x8};

use crate::approx::Tier;
use crate::batch::{finish, normalize, valid_direction, Dir8, Uv8};
use crate::kernel::{chart_below, clamp01, in_unit_square, mask_dir, Mapping8};

impl Mapping8 for Tennisball {
    #[inline]
    fn forward8<T: Tier>(&self, d: Dir8) -> Uv8 {
        let valid = valid_direction(&d);
        let n = normalize(&d);
        let (a, b, c) = (n.x, n.y, n.z);
        let s = f32x8::splat(FRAC_1_SQRT_2);
        let zero = f32x8::ZERO;
        let c0 = (c.simd_ge(zero) & b.abs().simd_le(s)) | (c.simd_le(zero) & a.abs().simd_ge(s));
        let theta = T::asin(c0.select(b, a));
        let phi = T::atan2_finite(c0.select(a, b), c0.select(c, -c));
        let lim = f32x8::splat(FRAC_PI_4);
        let theta = theta.max(-lim).min(lim);
        let plim = f32x8::splat(3.0 * FRAC_PI_4);
        let phi = phi.max(-plim).min(plim);
        let half = f32x8::splat(0.5);
        let u = clamp01(phi / f32x8::splat(1.5 * PI) + half);
        let v = clamp01(half - theta / f32x8::splat(FRAC_PI_2));
        let chart = c0.to_bits().select(u32x8::ZERO, u32x8::ONE);
        finish(valid, chart, u, v)
    }

    #[inline]
    fn inverse8<T: Tier>(&self, c: Uv8) -> Dir8 {
        let valid = in_unit_square(c.u, c.v) & chart_below(&c, 2);
        let half = f32x8::splat(0.5);
        let phi = (c.u - half) * f32x8::splat(1.5 * PI);
        let theta = (half - c.v) * f32x8::splat(FRAC_PI_2);
        let (sp, cp) = T::sin_cos(phi);
        let (st, ct) = T::sin_cos(theta);
        let c0 = f32x8::from_bits(c.chart.simd_eq(u32x8::ZERO));
        let d = Dir8::new(
            c0.select(ct * sp, st),
            c0.select(st, ct * sp),
            c0.select(ct * cp, -(ct * cp)),
        );
        mask_dir(valid, d)
    }
}
