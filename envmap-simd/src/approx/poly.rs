//! Polynomial evaluation and the constants the reductions share.

use wide::{f32x8, u32x8};

/// `π/2` rounded to `f32`, and the rest: `PIO2_HI + PIO2_LO` is `π/2` to
/// about 2⁻⁵⁰.
pub(crate) const PIO2_HI: f32 = core::f32::consts::FRAC_PI_2;
/// See [`PIO2_HI`].
pub(crate) const PIO2_LO: f32 = (core::f64::consts::FRAC_PI_2 - PIO2_HI as f64) as f32;
/// `π` rounded to `f32`, and the rest.
pub(crate) const PI_HI: f32 = core::f32::consts::PI;
/// See [`PI_HI`].
pub(crate) const PI_LO: f32 = (core::f64::consts::PI - PI_HI as f64) as f32;
/// `π/4` rounded to `f32` (also `atan2` of two positive infinities), and
/// the rest.
pub(crate) const PIO4: f32 = core::f32::consts::FRAC_PI_4;
/// See [`PIO4`].
pub(crate) const PIO4_LO: f32 = (core::f64::consts::FRAC_PI_4 - PIO4 as f64) as f32;
/// `3π/4` rounded to `f32` (`atan2(±∞, −∞)`).
pub(crate) const PIO4_3: f32 = (3.0 * core::f64::consts::FRAC_PI_4) as f32;

/// The sign bit of every lane.
pub(crate) const SIGN: u32x8 = u32x8::splat(0x8000_0000);

/// Horner's scheme in `u`, coefficients lowest power first (no
/// coefficients: the zero polynomial).
#[inline(always)]
pub(crate) fn horner(u: f32x8, c: &[f32]) -> f32x8 {
    let Some((last, rest)) = c.split_last() else {
        return f32x8::ZERO;
    };
    let mut acc = f32x8::splat(*last);
    for &k in rest.iter().rev() {
        acc = acc.mul_add(u, f32x8::splat(k));
    }
    acc
}

/// An odd polynomial `z·P(z²)`, or `z + z³·P(z²)` when the leading
/// coefficient is fixed to one (the relative-error fits of the exact tier,
/// which then return tiny arguments unchanged). `u` is `z²` (the caller may
/// have it exactly).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Odd {
    /// Leading coefficient fixed to one (not stored in `coeffs`).
    pub(crate) lead_one: bool,
    /// Coefficients of `P`, lowest power first.
    pub(crate) coeffs: &'static [f32],
}

impl Odd {
    #[inline(always)]
    pub(crate) fn eval(&self, z: f32x8, u: f32x8) -> f32x8 {
        let p = horner(u, self.coeffs);
        if self.lead_one {
            z.mul_add(u * p, z)
        } else {
            z * p
        }
    }
}

impl Odd {
    /// The polynomial as an unrounded sum `head + tail`: `(z, z³·P(z²))` when
    /// the leading coefficient is one, else `(z·P(z²), 0)`. Adding `head`
    /// to a constant first and `tail` last saves a rounding where the
    /// constant nearly cancels `head`.
    #[inline(always)]
    pub(crate) fn eval_split(&self, z: f32x8, u: f32x8) -> (f32x8, f32x8) {
        let p = horner(u, self.coeffs);
        if self.lead_one {
            (z, z * (u * p))
        } else {
            (z * p, f32x8::ZERO)
        }
    }
}

/// `(base_hi + head) + (base_lo + tail)` with the first sum made exact
/// (Fast2Sum: needs `|base_hi| ≥ |head|` or `base_hi = 0`), so the result is
/// rounded once, at the end.
#[inline(always)]
pub(crate) fn add_compensated(base_hi: f32x8, base_lo: f32x8, head: f32x8, tail: f32x8) -> f32x8 {
    let s = base_hi + head;
    let err = (base_hi - s) + head;
    s + ((base_lo + tail) + err)
}

/// Flip the sign of `v` where `mask` (all ones / all zeros per lane) is set.
#[inline(always)]
pub(crate) fn negate_where(v: f32x8, mask: f32x8) -> f32x8 {
    v ^ (mask & f32x8::from_bits(SIGN))
}

/// The lanes of `mask` selected from `v`, zero elsewhere.
#[inline(always)]
pub(crate) fn keep(mask: f32x8, v: f32) -> f32x8 {
    mask & f32x8::splat(v)
}
