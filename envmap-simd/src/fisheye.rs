//! Fisheye lenses, eight directions at a time.
//!
//! The formula of [`envmap_core::fisheye`]: θ = atan2(√(x² + y²), ±z) from the lens's axis,
//! r = θ/k (equidistant) or sin(θ/2)/sin(k/2) (equisolid), k half the field of view; the
//! point (½ ± ½ r x/ρ, ½ − ½ r y/ρ). Directions beyond the field of view are invalid lanes
//! ([`INVALID_CHART`](crate::INVALID_CHART) and NaN), as the core gives `None` for them. The
//! polar angle comes from the tier's `atan2_sqrt` on the direction scaled by a power of two, and
//! the azimuth from x and y divided by the larger of |x|, |y|, as the angular map's kernel
//! takes them; the inverse's angles from the tier's `sin_cos` and `asin`.

use core::f32::consts::PI;

use envmap_core::{Fisheye, Lens};
use wide::{f32x8, u32x8};

use crate::approx::Tier;
use crate::batch::{finish, scale_pow2, valid_direction, Dir8, Uv8};
use crate::kernel::{azimuth, chart_below, clamp01, in_unit_disk, mask_dir, unit, Mapping8};

impl Mapping8 for Fisheye {
    #[inline]
    fn forward8<T: Tier>(&self, d: Dir8) -> Uv8 {
        let valid = valid_direction(&d);
        // The back lens (chart 1) takes z < 0 (−0 stays in front, as in the core).
        let back = if self.is_dual() {
            d.z.simd_lt(f32x8::ZERO)
        } else {
            f32x8::ZERO
        };
        let side = back.select(-f32x8::ONE, f32x8::ONE);
        let (px, py, len) = azimuth(&d);
        let n = scale_pow2(&d);
        let axial = side * n.z;
        let theta = T::atan2_sqrt(n.x * n.x + n.y * n.y, axial, axial * axial);
        let k = self.half_fov();
        // Every lane, for lenses that cover the sphere (whatever the tier's rounding of θ).
        let seen = theta.simd_le(f32x8::splat(self.seen_limit()));
        let r = match self.lens() {
            Lens::Equidistant => theta * f32x8::splat(1.0 / k),
            Lens::Equisolid => {
                let (s, _) = T::sin_cos(f32x8::splat(0.5) * theta);
                s * f32x8::splat(1.0 / self.half_fov_sin_half())
            }
        }
        .fast_min(f32x8::ONE);
        let q = r / len;
        let half = f32x8::splat(0.5);
        let u = clamp01(half * (side * q * px) + half);
        let v = clamp01(half - half * (q * py));
        let chart = back.to_bits() & u32x8::ONE;
        finish(valid & seen, chart, u, v)
    }

    #[inline]
    fn inverse8<T: Tier>(&self, c: Uv8) -> Dir8 {
        let charts = if self.is_dual() { 2 } else { 1 };
        let valid = in_unit_disk(c.u, c.v) & chart_below(&c, charts);
        let back = f32x8::from_bits(c.chart.simd_eq(u32x8::ONE));
        let side = back.select(-f32x8::ONE, f32x8::ONE);
        let two = f32x8::splat(2.0);
        let (a, b) = (two * c.u - f32x8::ONE, f32x8::ONE - two * c.v);
        let r = (a * a + b * b).sqrt().fast_min(f32x8::ONE);
        let k = self.half_fov();
        let theta = match self.lens() {
            Lens::Equidistant => r * f32x8::splat(k),
            Lens::Equisolid => {
                let sk = f32x8::splat(self.half_fov_sin_half());
                two * T::asin((r * sk).fast_min(f32x8::ONE))
            }
        };
        let (s, ct) = T::sin_cos(theta.fast_min(f32x8::splat(PI)));
        let q = r.simd_gt(f32x8::ZERO).select(s / r, f32x8::ZERO);
        mask_dir(valid, unit(side * q * a, q * b, side * ct))
    }
}
