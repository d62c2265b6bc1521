//! `asin` and `acos`.
//!
//! Both reduce to `asin(z)` for `z` in `[0, 1/2]`, evaluated by an odd
//! minimax polynomial (see [`coeffs`](super::coeffs)):
//!
//! * `|x| ≤ 1/2`: `z = |x|`, `asin x = ±asin z`, `acos x = π/2 ∓ asin z`;
//! * `|x| > 1/2`: `z = √((1 − |x|)/2)` (`1 − |x|` and the halving are exact),
//!   `asin|x| = π/2 − 2·asin z`, `acos x = 2·asin z` for `x > 0` and
//!   `π − 2·asin z` for `x < 0`. This keeps `acos` accurate next to `±1`,
//!   where `acos x ≈ √(2(1 − |x|))` has no cancellation.
//!
//! `|x| > 1` (and `±∞`) gives the square root of a negative number, NaN. The
//! sign of `x` is put back last, so `asin(±0) = ±0`. The exact tier adds
//! `π/2` and `π` as a two-part `hi + lo` sum.

use super::poly::{
    add_compensated, keep, negate_where, Odd, PIO2_HI, PIO2_LO, PIO4, PIO4_LO, PI_HI,
};
use wide::f32x8;

/// One tier's `asin`/`acos` kernel.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Asin {
    /// `asin(z) ≈ poly(z)` on `[0, 1/2]`.
    pub(crate) poly: Odd,
    /// Add `π/2` and `π` in two parts (`hi + lo`).
    pub(crate) split: bool,
}

impl Asin {
    /// `(big, z, u)`: lanes with `|x| > 1/2`, the reduced argument and its
    /// square.
    #[inline(always)]
    fn reduce(x: f32x8) -> (f32x8, f32x8, f32x8) {
        let a = x.abs();
        let big = a.simd_gt(f32x8::HALF);
        let t = (f32x8::ONE - a) * f32x8::HALF;
        let z = big.select(t.sqrt(), a);
        let u = big.select(t, a * a);
        (big, z, u)
    }

    #[inline(always)]
    pub(crate) fn asin(&self, x: f32x8) -> f32x8 {
        let (big, z, u) = Self::reduce(x);
        let r = if self.split {
            // big: π/2 − 2·(head + tail) = 2·(π/4 − head − tail), rounded once.
            let (head, tail) = self.poly.eval_split(z, u);
            let r = add_compensated(
                keep(big, PIO4),
                keep(big, PIO4_LO),
                negate_where(head, big),
                negate_where(tail, big),
            );
            r * big.select(f32x8::splat(2.0), f32x8::ONE)
        } else {
            let p = self.poly.eval(z, u);
            big.select(f32x8::splat(PIO2_HI) - (p + p), p)
        };
        r.flip_signs(x)
    }

    #[inline(always)]
    pub(crate) fn acos(&self, x: f32x8) -> f32x8 {
        let (big, z, u) = Self::reduce(x);
        let xneg = x.is_sign_negative();
        // acos x = base ± asin-part: base π/2 (small), 0 (big, x > 0) or
        // π (big, x < 0), and the asin part doubled in the big lanes.
        let minus = !(big ^ xneg);
        if self.split {
            // As (base' ± (head + tail))·k, rounded once: base' = π/2, k = 1
            // (small); base' = 0, k = 2 (big, x > 0); base' = π/2, k = 2
            // (big, x < 0).
            let (head, tail) = self.poly.eval_split(z, u);
            let zero_base = big & !xneg;
            let r = add_compensated(
                (!zero_base) & f32x8::splat(PIO2_HI),
                (!zero_base) & f32x8::splat(PIO2_LO),
                negate_where(head, minus),
                negate_where(tail, minus),
            );
            r * big.select(f32x8::splat(2.0), f32x8::ONE)
        } else {
            let p = self.poly.eval(z, u);
            let q = negate_where(big.select(p + p, p), minus);
            let base_hi = big.select(keep(xneg, PI_HI), f32x8::splat(PIO2_HI));
            q + base_hi
        }
    }
}
