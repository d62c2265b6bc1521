//! `atan` and `atan2`.
//!
//! Both reduce to `atan(z)` for `z` in `[0, 1]`, evaluated by an odd minimax
//! polynomial (see [`coeffs`](super::coeffs)):
//!
//! * `atan(x)`: `z = |x|` if `|x| ≤ 1`, else `z = 1/|x|` and
//!   `atan|x| = π/2 − atan(z)`; the sign of `x` is put back last, so
//!   `atan(±0) = ±0` and `atan(±∞) = ±π/2`.
//! * `atan2(y, x)`: `z = min(|x|, |y|) / max(|x|, |y|)` (never overflows or
//!   underflows spuriously: the quotient is at most one and only flushes to
//!   zero when the true angle is below the smallest `f32`), then the octant
//!   is rebuilt as `p`, `π/2 − p`, `π − p` or `π/2 + p`, and the sign of `y`
//!   put back last.
//!
//! The exact tier adds `π/2` and `π` as a two-part `hi + lo` constant, with
//! the polynomial kept as `z + z³·P(z²)` unsummed and the sum of the large
//! parts made exact (Fast2Sum), so the result is rounded once at the end.

use super::poly::{
    add_compensated, keep, negate_where, Odd, PIO2_HI, PIO2_LO, PIO4, PIO4_3, PI_HI, PI_LO,
};
use wide::f32x8;

/// One tier's `atan` kernel.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Atan {
    /// `atan(z) ≈ poly(z)` on `[0, 1]`.
    pub(crate) poly: Odd,
    /// Add `π/2` and `π` in two parts (`hi + lo`).
    pub(crate) split: bool,
}

impl Atan {
    #[inline(always)]
    pub(crate) fn atan(&self, x: f32x8) -> f32x8 {
        let one = f32x8::ONE;
        let t = x.abs();
        let big = t.simd_gt(one);
        let z = big.select(one / t, t);
        let r = if self.split {
            // π/2 − (head + tail), rounded once.
            let (head, tail) = self.poly.eval_split(z, z * z);
            add_compensated(
                keep(big, PIO2_HI),
                keep(big, PIO2_LO),
                negate_where(head, big),
                negate_where(tail, big),
            )
        } else {
            let p = self.poly.eval(z, z * z);
            big.select(f32x8::splat(PIO2_HI) - p, p)
        };
        r.flip_signs(x)
    }

    #[inline(always)]
    pub(crate) fn atan2(&self, y: f32x8, x: f32x8) -> f32x8 {
        self.atan2_impl::<true>(y, x)
    }

    /// `atan2` for finite arguments: the same result without the ±Inf and
    /// NaN handling (unspecified for such lanes).
    #[inline(always)]
    pub(crate) fn atan2_finite(&self, y: f32x8, x: f32x8) -> f32x8 {
        self.atan2_impl::<false>(y, x)
    }

    /// `atan2(√y2, x)` for `y2 ≥ 0` (a square) and finite `x` with
    /// `x2 = x²`, none of them overflowing: the quotient of the squares,
    /// `min/max`, is `z²` of `atan2_finite`'s `z`, so the polynomial in `z²`
    /// starts right after the division while `z = √(z²)` is taken beside
    /// it, instead of a square root before the division. The exact tier
    /// (split polynomials) takes `atan2_finite(√y2, x)` itself.
    #[inline(always)]
    pub(crate) fn atan2_sqrt(&self, y2: f32x8, x: f32x8, x2: f32x8) -> f32x8 {
        if self.split {
            return self.atan2_finite(y2.sqrt(), x);
        }
        let swap = y2.simd_gt(x2);
        let num = swap.select(x2, y2);
        // den = 0 only when num = 0 too: as in `atan2_impl`.
        let den = swap
            .select(y2, x2)
            .fast_max(f32x8::splat(f32::from_bits(1)));
        let u = num / den;
        let xneg = x.is_sign_negative();
        let minus = swap ^ xneg;
        let base_hi = swap.select(f32x8::splat(PIO2_HI), keep(xneg, PI_HI));
        negate_where(self.poly.eval(u.sqrt(), u), minus) + base_hi
    }

    #[inline(always)]
    fn atan2_impl<const SPECIAL: bool>(&self, y: f32x8, x: f32x8) -> f32x8 {
        let ax = x.abs();
        let ay = y.abs();
        let swap = ay.simd_gt(ax);
        let num = swap.select(ax, ay);
        let den = swap.select(ay, ax);
        // Both infinite: the angle is an odd multiple of π/4, set exactly
        // below; both zero: 0/0, the angle is 0 or π.
        let both_inf = if SPECIAL {
            ax.is_inf() & ay.is_inf()
        } else {
            f32x8::ZERO
        };
        let z = if SPECIAL {
            (both_inf | den.simd_eq(f32x8::ZERO)).select(f32x8::ZERO, num / den)
        } else {
            // den = 0 only when num = 0 too: dividing by the smallest
            // subnormal instead gives the same +0, and leaves every other
            // quotient as it is.
            num / den.fast_max(f32x8::splat(f32::from_bits(1)))
        };
        let xneg = x.is_sign_negative();
        // |angle| = base ± p with base 0, π/2 or π.
        let minus = swap ^ xneg;
        let base_hi = swap.select(f32x8::splat(PIO2_HI), keep(xneg, PI_HI));
        let base_hi = if SPECIAL {
            both_inf.select(
                xneg.select(f32x8::splat(PIO4_3), f32x8::splat(PIO4)),
                base_hi,
            )
        } else {
            base_hi
        };
        let r = if self.split {
            let (head, tail) = self.poly.eval_split(z, z * z);
            let base_lo = swap.select(f32x8::splat(PIO2_LO), keep(xneg, PI_LO));
            let base_lo = (!both_inf) & base_lo;
            add_compensated(
                base_hi,
                base_lo,
                negate_where(head, minus),
                negate_where(tail, minus),
            )
        } else {
            negate_where(self.poly.eval(z, z * z), minus) + base_hi
        };
        if !SPECIAL {
            return r.flip_signs(y);
        }
        // A NaN in either argument can hide behind the zero quotient above.
        let nan = x.is_nan() | y.is_nan();
        nan.select(x + y, r.flip_signs(y))
    }
}
