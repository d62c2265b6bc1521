//! `sin` and `cos` together.
//!
//! Quadrant reduction: `q = round(|x|·2/π)` (by the `1.5·2²³` rounding trick,
//! which also leaves `q mod 4` in the low bits), `r = |x| − q·π/2` by
//! Cody–Waite with `π/2` split into parts whose leading ones have 12
//! significant bits, so `q·part` is exact for `q ≤ 2¹²` even without FMA;
//! then `sin r` and `cos r` on `[−π/4, π/4]` by minimax polynomials (see
//! [`coeffs`](super::coeffs)), swapped and negated by quadrant, and the sign of
//! `x` put back on `sin` last (`sin(±0) = ±0`). Non-finite `x` gives NaN.
//!
//! Beyond the documented range the reduced argument is clamped to
//! `[−π/4, π/4]` (slightly widened), so `(sin, cos)` always stays a point
//! within the polynomial's error of the unit circle, just no longer at the
//! right angle.

use super::poly::{horner, Odd, SIGN};
use wide::{f32x8, u32x8};

/// `π/2` as `f64`, the source of the splits below.
const PIO2: f64 = core::f64::consts::FRAC_PI_2;
/// `π/2 − PIO2`, the bits of `π/2` beyond `f64`: `π/2 =
/// 1.57079632679489661923132169163975144…` and `PIO2 =
/// 1.57079632679489655799898173427209258…`.
const PIO2_LO: f64 = 6.123_233_995_736_766e-17;
/// Keep the 12 leading significant bits of an `f32`.
const fn top12(v: f32) -> f32 {
    f32::from_bits(v.to_bits() & 0xFFFF_F000)
}
/// `π/2` to 12 significant bits.
const CW1: f32 = top12(PIO2 as f32);
/// The next 12 bits (four-part split).
const CW2: f32 = top12((PIO2 - CW1 as f64) as f32);
/// The next 12 bits (four-part split).
const CW3: f32 = top12((PIO2 - CW1 as f64 - CW2 as f64) as f32);
/// The rest (four-part split).
const CW4: f32 = ((PIO2 - CW1 as f64 - CW2 as f64 - CW3 as f64) + PIO2_LO) as f32;
/// Everything after [`CW1`] (two-part split).
const CW2_ONLY: f32 = (PIO2 - CW1 as f64) as f32;
/// `1.5·2²³`: adding it rounds to an integer kept in the low mantissa bits.
const ROUNDER: f32 = 12_582_912.0;
/// Clamp for the reduced argument (only reached beyond the accurate range).
const R_MAX: f32 = 0.786;

/// How `cos` is evaluated.
#[derive(Clone, Copy, Debug)]
pub(crate) enum CosPoly {
    /// `1 − r²/2 + r⁴·P(r²)`.
    OneMinusHalf(&'static [f32]),
    /// `1 + r²·P(r²)`.
    OnePlus(&'static [f32]),
}

/// One tier's `sin_cos` kernel.
#[derive(Clone, Copy, Debug)]
pub(crate) struct SinCos {
    /// `sin(r)` on `[0, π/4]`.
    pub(crate) sin: Odd,
    /// `cos(r)` on `[0, π/4]`.
    pub(crate) cos: CosPoly,
    /// Four-part Cody–Waite split (else two parts).
    pub(crate) four_part: bool,
}

impl SinCos {
    #[inline(always)]
    pub(crate) fn sin_cos(&self, x: f32x8) -> (f32x8, f32x8) {
        let a = x.abs();
        let j = a.mul_add(f32x8::FRAC_2_PI, f32x8::splat(ROUNDER));
        let q = j.to_bits();
        let qf = j - f32x8::splat(ROUNDER);
        let mut r = qf.mul_neg_add(f32x8::splat(CW1), a);
        if self.four_part {
            // The first three products are exact (12-bit parts, q < 2¹²) and
            // so are the first two differences; the third is kept with its
            // rounding error (Fast2Sum) so that r is rounded only once.
            r = qf.mul_neg_add(f32x8::splat(CW2), r);
            let p3 = qf * f32x8::splat(CW3);
            let r3 = r - p3;
            let e3 = (r - r3) - p3;
            r = r3 + qf.mul_neg_add(f32x8::splat(CW4), e3);
        } else {
            r = qf.mul_neg_add(f32x8::splat(CW2_ONLY), r);
        }
        let r = r
            .fast_max(f32x8::splat(-R_MAX))
            .fast_min(f32x8::splat(R_MAX));
        let u = r * r;
        let s = self.sin.eval(r, u);
        let c = match self.cos {
            CosPoly::OneMinusHalf(k) => {
                // 1 − u/2 split into its rounded value and the (exact) rest.
                let half_u = f32x8::HALF * u;
                let w = f32x8::ONE - half_u;
                let rest = (f32x8::ONE - w) - half_u;
                w + (u * u).mul_add(horner(u, k), rest)
            }
            CosPoly::OnePlus(k) => u.mul_add(horner(u, k), f32x8::ONE),
        };
        let swap = (q & u32x8::ONE).simd_eq(u32x8::ONE);
        let sin = swap.select(c, s);
        let cos = swap.select(s, c);
        let sin_sign = ((q << 30) ^ x.to_bits()) & SIGN;
        let cos_sign = ((q + u32x8::ONE) << 30) & SIGN;
        let sin = f32x8::from_bits(sin.to_bits() ^ sin_sign);
        let cos = f32x8::from_bits(cos.to_bits() ^ cos_sign);
        let finite = x.is_finite();
        (
            finite.select(sin, f32x8::NAN),
            finite.select(cos, f32x8::NAN),
        )
    }
}
