//! Dual paraboloid mapping, eight directions at a time.
//!
//! The formula of [`envmap_core::dual_paraboloid`]: (u', v') = (x, y)/(1 + |z|),
//! chart from z's sign bit; inverse (2u', 2v', ±(1 − r²))/(1 + r²). No
//! trigonometry: every tier runs the same code.

use envmap_core::DualParaboloid;
use wide::{f32x8, u32x8};

use crate::approx::Tier;
use crate::batch::{finish, normalize, valid_direction, Dir8, Uv8};
use crate::kernel::{chart_below, clamp01, in_unit_disk, mask_dir, unit, Mapping8};

impl Mapping8 for DualParaboloid {
    #[inline]
    fn forward8<T: Tier>(&self, d: Dir8) -> Uv8 {
        let valid = valid_direction(&d);
        let r = normalize(&d);
        let chart = r.z.to_bits() >> 31;
        let den = f32x8::ONE + r.z.abs();
        let half = f32x8::splat(0.5);
        let u = clamp01(half * (r.x / den) + half);
        let v = clamp01(half * (r.y / den) + half);
        finish(valid, chart, u, v)
    }

    #[inline]
    fn inverse8<T: Tier>(&self, c: Uv8) -> Dir8 {
        let valid = in_unit_disk(c.u, c.v) & chart_below(&c, 2);
        let two = f32x8::splat(2.0);
        let (x, y) = (two * c.u - f32x8::ONE, two * c.v - f32x8::ONE);
        let r2 = x * x + y * y;
        let z = (f32x8::ONE - r2).max(f32x8::ZERO);
        let back = f32x8::from_bits(c.chart.simd_eq(u32x8::ONE));
        let z = back.select(-z, z);
        let k = f32x8::ONE + r2;
        mask_dir(valid, unit(two * x / k, two * y / k, z / k))
    }
}
