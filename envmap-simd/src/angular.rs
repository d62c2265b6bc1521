//! Angular map (Debevec's light probe), eight directions at a time.
//!
//! The formula of [`envmap_core::angular`]: θ = atan2(√(x² + y²), z),
//! (u', v') = (θ/π)·(x, y)/√(x² + y²); inverse (sin θ·u'/ρ, sin θ·v'/ρ,
//! cos θ) with θ = πρ. The polar angle comes from the tier's `atan2_sqrt`
//! on the direction scaled by a power of two (as the latlong's does), the
//! inverse's sine and cosine from its `sin_cos`, evaluated at π(1 − ρ) in the
//! outer half of the disk as the core does. The azimuth is taken from x and
//! y as given, divided by the larger of |x|, |y|, exactly as the core takes
//! it, so the singular direction −z and its neighbourhood land on the same
//! rim points; x = y = ±0 takes the azimuth of +x.

use core::f32::consts::PI;

use envmap_core::Angular;
use wide::{f32x8, u32x8};

use crate::approx::Tier;
use crate::batch::{finish, scale_pow2, valid_direction, Dir8, Uv8};
use crate::kernel::{azimuth, chart_below, clamp01, in_unit_disk, mask_dir, unit, Mapping8};

impl Mapping8 for Angular {
    #[inline]
    fn forward8<T: Tier>(&self, d: Dir8) -> Uv8 {
        let valid = valid_direction(&d);
        // The azimuth from the components as given (the power-of-two
        // scaling below could flush x and y of a direction next to ±z).
        let (px, py, len) = azimuth(&d);
        // The polar angle, scale-invariant, from the direction scaled so
        // that x² + y² and z² neither overflow nor underflow harmfully.
        let n = scale_pow2(&d);
        let theta = T::atan2_sqrt(n.x * n.x + n.y * n.y, n.z, n.z * n.z);
        let rho = (theta * f32x8::splat(1.0 / PI)).fast_min(f32x8::ONE);
        let k = rho / len;
        let half = f32x8::splat(0.5);
        let u = clamp01(half * (k * px) + half);
        let v = clamp01(half * (k * py) + half);
        finish(valid, u32x8::ZERO, u, v)
    }

    #[inline]
    fn inverse8<T: Tier>(&self, c: Uv8) -> Dir8 {
        let valid = in_unit_disk(c.u, c.v) & chart_below(&c, 1);
        let two = f32x8::splat(2.0);
        let (x, y) = (two * c.u - f32x8::ONE, two * c.v - f32x8::ONE);
        let rho = (x * x + y * y).sqrt().fast_min(f32x8::ONE);
        let half = f32x8::splat(0.5);
        let outer = rho.simd_gt(half);
        let q = outer.select(f32x8::ONE - rho, rho);
        let (s, cq) = T::sin_cos(f32x8::splat(PI) * q);
        let cz = outer.select(-cq, cq);
        let k = rho.simd_gt(f32x8::ZERO).select(s / rho, f32x8::splat(PI));
        mask_dir(valid, unit(k * x, k * y, cz))
    }
}
