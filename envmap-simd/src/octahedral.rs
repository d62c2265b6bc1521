//! Octahedral and equal-area octahedral maps, eight directions at a time.
//!
//! The formulas of [`envmap_core::octahedral`]. The plain map needs no
//! trigonometry (every tier runs the same code); the equal-area map uses the
//! tier's `atan` forward and `sin_cos` inverse.

use core::f32::consts::{FRAC_2_PI, FRAC_PI_4};

use envmap_core::{EqualAreaOctahedral, Octahedral};
use wide::{f32x8, u32x8};

use crate::approx::Tier;
use crate::batch::{finish, normalize, valid_direction, Dir8, Uv8};
use crate::kernel::{chart_below, clamp01, in_unit_square, mask_dir, unit, Mapping8};

#[inline]
fn to_uv(valid: f32x8, x: f32x8, y: f32x8) -> Uv8 {
    let half = f32x8::splat(0.5);
    finish(
        valid,
        u32x8::ZERO,
        clamp01(half * x + half),
        clamp01(half * y + half),
    )
}

impl Mapping8 for Octahedral {
    #[inline]
    fn forward8<T: Tier>(&self, d: Dir8) -> Uv8 {
        let valid = valid_direction(&d);
        let n = normalize(&d);
        let l1 = n.x.abs() + n.y.abs() + n.z.abs();
        let (px, py, pz) = (n.x / l1, n.y / l1, n.z / l1);
        let lower = pz.simd_lt(f32x8::ZERO);
        let fx = (f32x8::ONE - py.abs()).copysign(px);
        let fy = (f32x8::ONE - px.abs()).copysign(py);
        to_uv(valid, lower.select(fx, px), lower.select(fy, py))
    }

    #[inline]
    fn inverse8<T: Tier>(&self, c: Uv8) -> Dir8 {
        let valid = in_unit_square(c.u, c.v) & chart_below(&c, 1);
        let two = f32x8::splat(2.0);
        let (x, y) = (two * c.u - f32x8::ONE, two * c.v - f32x8::ONE);
        let z = f32x8::ONE - x.abs() - y.abs();
        let lower = z.simd_lt(f32x8::ZERO);
        let fx = (f32x8::ONE - y.abs()).copysign(x);
        let fy = (f32x8::ONE - x.abs()).copysign(y);
        mask_dir(valid, unit(lower.select(fx, x), lower.select(fy, y), z))
    }
}

impl Mapping8 for EqualAreaOctahedral {
    #[inline]
    fn forward8<T: Tier>(&self, d: Dir8) -> Uv8 {
        let valid = valid_direction(&d);
        let n = normalize(&d);
        let (ax, ay, az) = (n.x.abs(), n.y.abs(), n.z.abs());
        let r = ((ax * ax + ay * ay) / (f32x8::ONE + az)).sqrt();
        let hi = ax.max(ay);
        let lo = ax.min(ay);
        let pole = hi.simd_eq(f32x8::ZERO);
        let phi = pole.select(f32x8::ZERO, T::atan(lo / hi) * f32x8::splat(FRAC_2_PI));
        let phi = ax.simd_lt(ay).select(f32x8::ONE - phi, phi);
        let v = phi * r;
        let u = r - v;
        let lower = n.z.simd_lt(f32x8::ZERO);
        let (u, v) = (
            lower.select(f32x8::ONE - v, u),
            lower.select(f32x8::ONE - u, v),
        );
        to_uv(valid, u.copysign(n.x), v.copysign(n.y))
    }

    #[inline]
    fn inverse8<T: Tier>(&self, c: Uv8) -> Dir8 {
        let valid = in_unit_square(c.u, c.v) & chart_below(&c, 1);
        let two = f32x8::splat(2.0);
        let (u, v) = (two * c.u - f32x8::ONE, two * c.v - f32x8::ONE);
        let (au, av) = (u.abs(), v.abs());
        let sum = au + av;
        let sd = f32x8::ONE - sum;
        let r = sd.simd_ge(f32x8::ZERO).select(sum, two - sum);
        let q = f32x8::splat(FRAC_PI_4);
        let phi = r
            .simd_eq(f32x8::ZERO)
            .select(q, ((av - au) / r + f32x8::ONE) * q);
        let z = (f32x8::ONE - r * r).copysign(sd);
        let (sp, cp) = T::sin_cos(phi);
        let k = r * (two - r * r).max(f32x8::ZERO).sqrt();
        mask_dir(valid, unit(cp.copysign(u) * k, sp.copysign(v) * k, z))
    }
}
