//! Latitude-longitude mapping, eight directions at a time.
//!
//! The formula of [`envmap_core::latlong`]: u = atan2(y, x)/2π wrapped into
//! [0, 1), v = atan2(√(x² + y²), z)/π; inverse (sin θ cos φ, sin θ sin φ,
//! cos θ) with φ = 2πu, θ = πv. `atan2` and `sin_cos` come from the tier `T`.
//! The forward kernel skips normalisation (both angles are scale-invariant)
//! and scales by an exact power of two instead, so it agrees with the core to
//! within the tier's bound rather than bit for bit.

use core::f32::consts::{PI, TAU};

use envmap_core::LatLong;
use wide::{f32x8, u32x8};

use crate::approx::Tier;
use crate::batch::{finish, scale_pow2, valid_direction, Dir8, Uv8};
use crate::kernel::{chart_below, in_unit_square, mask_dir, Mapping8};

/// u and v of eight directions: φ from `d` as given, θ from `n`, the same
/// directions scaled (if at all) by a power of two so that `x² + y²`
/// neither overflows nor underflows.
#[inline(always)]
fn angles<T: Tier>(d: &Dir8, n: &Dir8) -> (f32x8, f32x8) {
    let phi = T::atan2_finite(d.y, d.x);
    let u = phi * f32x8::splat(1.0 / TAU) + f32x8::ZERO;
    let neg = u.simd_lt(f32x8::ZERO);
    let u = neg.select(u + f32x8::ONE, u);
    let u = u.simd_ge(f32x8::ONE).select(f32x8::ZERO, u);
    let theta = T::atan2_sqrt(n.x * n.x + n.y * n.y, n.z, n.z * n.z);
    // θ is +0 or positive (ρ is), so only the upper clamp can apply.
    let v = (theta * f32x8::splat(1.0 / PI)).fast_min(f32x8::ONE);
    (u, v)
}

impl Mapping8 for LatLong {
    #[inline]
    fn forward8<T: Tier>(&self, d: Dir8) -> Uv8 {
        let valid = valid_direction(&d);
        // No normalisation: both angles are scale-invariant, and an exact
        // power-of-two scaling keeps √(x² + y²) free of overflow and underflow.
        // φ from the components as given, as the core does: the scaling
        // could flush x and y of a direction near a pole into denormals.
        let (u, v) = angles::<T>(&d, &scale_pow2(&d));
        finish(valid, u32x8::ZERO, u, v)
    }

    /// Directions whose largest component is between 1/2 and 2 need no
    /// scaling (`forward8` would scale them by a power of two, exactly, so
    /// the angles are the same bits unless `x² + y²` underflows), and a NaN
    /// lane is found by its sum.
    #[inline]
    fn forward8_ray<T: Tier>(&self, d: Dir8) -> Uv8 {
        let sum = d.x + d.y + d.z;
        let (u, v) = angles::<T>(&d, &d);
        finish(sum.simd_eq(sum), u32x8::ZERO, u, v)
    }

    #[inline]
    fn inverse8<T: Tier>(&self, c: Uv8) -> Dir8 {
        let valid = in_unit_square(c.u, c.v) & chart_below(&c, 1);
        let (sp, cp) = T::sin_cos(f32x8::splat(TAU) * c.u);
        let (st, ct) = T::sin_cos(f32x8::splat(PI) * c.v);
        mask_dir(valid, Dir8::new(st * cp, st * sp, ct))
    }
}
