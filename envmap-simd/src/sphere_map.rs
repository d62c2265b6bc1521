//! Sphere maps (class and OpenGL conventions), eight directions at a time.
//!
//! The formula of [`envmap_core::sphere_map`], with the same cancellation-free
//! evaluation near the singular direction; no trigonometry, so every tier runs
//! the same code and agrees with the core to an ulp or two.

use envmap_core::SphereMap;
use wide::{f32x8, u32x8};

use crate::approx::Tier;
use crate::batch::{finish, normalize, valid_direction, Dir8, Uv8};
use crate::kernel::{chart_below, clamp01, in_unit_disk, mask_dir, unit, Mapping8};

impl Mapping8 for SphereMap {
    #[inline]
    fn forward8<T: Tier>(&self, d: Dir8) -> Uv8 {
        let valid = valid_direction(&d);
        let r = normalize(&d);
        let sigma = f32x8::splat(self.convention.sigma());
        let w = sigma * r.z;
        let one_plus_w = w
            .simd_lt(f32x8::ZERO)
            .select((r.x * r.x + r.y * r.y) / (f32x8::ONE - w), f32x8::ONE + w);
        let s = r.x.abs().max(r.y.abs()).max(one_plus_w);
        let (x, y, h) = (r.x / s, r.y / s, one_plus_w / s);
        let m = (x * x + y * y + h * h).sqrt();
        let half = f32x8::splat(0.5);
        let singular = s.simd_eq(f32x8::ZERO);
        let u = singular.select(f32x8::ONE, clamp01(half * (x / m) + half));
        let v = singular.select(half, clamp01(half * (y / m) + half));
        finish(valid, u32x8::ZERO, u, v)
    }

    #[inline]
    fn inverse8<T: Tier>(&self, c: Uv8) -> Dir8 {
        let valid = in_unit_disk(c.u, c.v) & chart_below(&c, 1);
        let two = f32x8::splat(2.0);
        let (x, y) = (two * c.u - f32x8::ONE, two * c.v - f32x8::ONE);
        let r2 = x * x + y * y;
        let nz = (f32x8::ONE - r2).max(f32x8::ZERO).sqrt();
        let sigma = f32x8::splat(self.convention.sigma());
        let d = unit(two * x * nz, two * y * nz, sigma * (f32x8::ONE - two * r2));
        mask_dir(valid, d)
    }
}
