//! Fast `atan`, `atan2`, `asin`, `acos` and `sin_cos` for [`f32x8`], at three
//! accuracy tiers chosen at compile time.
//!
//! ```
//! use envmap_simd::approx::{self, Exact, Fast};
//! use wide::f32x8;
//!
//! let y = f32x8::splat(1.0);
//! let x = f32x8::splat(-1.0);
//! let precise = approx::atan2::<Exact>(y, x);
//! let quick = approx::atan2::<Fast>(y, x);
//! assert!((precise.to_array()[0] - 3.0 * core::f32::consts::FRAC_PI_4).abs() < 1e-6);
//! assert!((quick.to_array()[0] - 3.0 * core::f32::consts::FRAC_PI_4).abs() < 1e-4);
//! ```
//!
//! | tier      | bound                       | atan/atan2 | asin/acos | sin, cos      |
//! |-----------|-----------------------------|-----------:|----------:|--------------:|
//! | [`Exact`] | 2 ULP                       | degree 17  | degree 11 | degree 7, 8   |
//! | [`Fine`]  | 2·10⁻⁶ rad absolute         | degree 13  | degree 7  | degree 5, 6   |
//! | [`Fast`]  | 10⁻⁴ rad absolute           | degree 7   | degree 5  | degree 5, 4   |
//!
//! Errors are measured against the `f64` function rounded to `f32`; ULP
//! means the distance in representable `f32` values. Each function's
//! documentation gives its reduction and its domain. All functions are
//! branch-free (masks and blends only) and work lane by lane: a NaN lane
//! returns NaN and never changes another lane.
//!
//! The polynomial coefficients are minimax fits made by the project's own
//! Remez fitter ([`coeffs`] says how to regenerate them).
//!
//! # Measuring
//!
//! The worst error of every function and tier, and where it occurs, is
//! printed by
//!
//! ```text
//! ENVMAP_EXTENSIVE=1 cargo test -p envmap-tests --release --test approx_accuracy -- --nocapture
//! ```
//!
//! which sweeps every `f32` of each reduced domain (without
//! `ENVMAP_EXTENSIVE`, every 1021st `f32`), and asserts the tier bounds;
//! both builds, with and without `RUSTFLAGS="-C target-cpu=native"` (AVX2
//! and FMA), must meet them. The figures are in `docs/accuracy.md`, the
//! speed of each tier (`cargo bench -p envmap-bench --bench approx`) in
//! `docs/performance.md`. Build with `RUSTFLAGS="-C target-cpu=native"` for
//! AVX: `wide` picks SSE or AVX at compile time.

mod asin_acos;
mod atan;
pub mod coeffs;
mod poly;
mod sin_cos;

use asin_acos::Asin;
use atan::Atan;
use poly::Odd;
use sin_cos::{CosPoly, SinCos};
use wide::f32x8;

/// [`sin_cos`](fn@sin_cos) meets its tier's bound for `|x| ≤ SIN_COS_RANGE`
/// (`≈ 4096·π/2`, where the leading Cody–Waite product stops being exact).
pub const SIN_COS_RANGE: f32 = 6433.0;

/// An accuracy tier: which polynomials (and how careful a reduction) the
/// functions of this module use. Implemented by [`Exact`], [`Fine`] and
/// [`Fast`]; pick one as a type parameter.
pub trait Tier: Copy + Default + core::fmt::Debug + Send + Sync + 'static {
    /// `"exact"`, `"fine"` or `"fast"`.
    const NAME: &'static str;
    /// Arctangent; see [`atan`](fn@atan).
    fn atan(x: f32x8) -> f32x8;
    /// Four-quadrant arctangent of `y/x`; see [`atan2`](fn@atan2).
    fn atan2(y: f32x8, x: f32x8) -> f32x8;
    /// Arcsine; see [`asin`](fn@asin).
    fn asin(x: f32x8) -> f32x8;
    /// Arccosine; see [`acos`](fn@acos).
    fn acos(x: f32x8) -> f32x8;
    /// Sine and cosine; see [`sin_cos`](fn@sin_cos).
    fn sin_cos(x: f32x8) -> (f32x8, f32x8);
    /// `atan2` for finite arguments only, with the same accuracy; lanes with
    /// NaN or ±Inf give unspecified values. The mapping kernels use it, as
    /// they mask invalid lanes themselves.
    #[inline]
    fn atan2_finite(y: f32x8, x: f32x8) -> f32x8 {
        Self::atan2(y, x)
    }
    /// `atan2(√y2, x)` from `y2 ≥ 0`, `x` and `x2 = x²`; see
    /// [`atan2_sqrt`](fn@atan2_sqrt).
    #[inline]
    fn atan2_sqrt(y2: f32x8, x: f32x8, x2: f32x8) -> f32x8 {
        let _ = x2;
        Self::atan2_finite(y2.sqrt(), x)
    }
}

/// At most 2 ULP from the correctly rounded result (`sin_cos` for
/// `|x| ≤` [`SIN_COS_RANGE`]); two-part `π` constants, compensated sums and
/// a four-part Cody–Waite reduction.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Exact;

/// At most `2·10⁻⁶` rad absolute error.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Fine;

/// At most `10⁻⁴` rad absolute error.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Fast;

const ATAN_EXACT: Atan = Atan {
    poly: Odd {
        lead_one: true,
        coeffs: &coeffs::ATAN_EXACT,
    },
    split: true,
};
const ATAN_FINE: Atan = Atan {
    poly: Odd {
        lead_one: false,
        coeffs: &coeffs::ATAN_FINE,
    },
    split: false,
};
const ATAN_FAST: Atan = Atan {
    poly: Odd {
        lead_one: false,
        coeffs: &coeffs::ATAN_FAST,
    },
    split: false,
};
const ASIN_EXACT: Asin = Asin {
    poly: Odd {
        lead_one: true,
        coeffs: &coeffs::ASIN_EXACT,
    },
    split: true,
};
const ASIN_FINE: Asin = Asin {
    poly: Odd {
        lead_one: false,
        coeffs: &coeffs::ASIN_FINE,
    },
    split: false,
};
const ASIN_FAST: Asin = Asin {
    poly: Odd {
        lead_one: false,
        coeffs: &coeffs::ASIN_FAST,
    },
    split: false,
};
const SIN_COS_EXACT: SinCos = SinCos {
    sin: Odd {
        lead_one: true,
        coeffs: &coeffs::SIN_EXACT,
    },
    cos: CosPoly::OneMinusHalf(&coeffs::COS_EXACT),
    four_part: true,
};
const SIN_COS_FINE: SinCos = SinCos {
    sin: Odd {
        lead_one: false,
        coeffs: &coeffs::SIN_FINE,
    },
    cos: CosPoly::OnePlus(&coeffs::COS_FINE),
    four_part: false,
};
const SIN_COS_FAST: SinCos = SinCos {
    sin: Odd {
        lead_one: false,
        coeffs: &coeffs::SIN_FINE,
    },
    cos: CosPoly::OnePlus(&coeffs::COS_FAST),
    four_part: false,
};

macro_rules! impl_tier {
    ($tier:ty, $name:literal, $atan:ident, $asin:ident, $sin_cos:ident) => {
        impl Tier for $tier {
            const NAME: &'static str = $name;
            #[inline]
            fn atan(x: f32x8) -> f32x8 {
                $atan.atan(x)
            }
            #[inline]
            fn atan2(y: f32x8, x: f32x8) -> f32x8 {
                $atan.atan2(y, x)
            }
            #[inline]
            fn atan2_finite(y: f32x8, x: f32x8) -> f32x8 {
                $atan.atan2_finite(y, x)
            }
            #[inline]
            fn atan2_sqrt(y2: f32x8, x: f32x8, x2: f32x8) -> f32x8 {
                $atan.atan2_sqrt(y2, x, x2)
            }
            #[inline]
            fn asin(x: f32x8) -> f32x8 {
                $asin.asin(x)
            }
            #[inline]
            fn acos(x: f32x8) -> f32x8 {
                $asin.acos(x)
            }
            #[inline]
            fn sin_cos(x: f32x8) -> (f32x8, f32x8) {
                $sin_cos.sin_cos(x)
            }
        }
    };
}

impl_tier!(Exact, "exact", ATAN_EXACT, ASIN_EXACT, SIN_COS_EXACT);
impl_tier!(Fine, "fine", ATAN_FINE, ASIN_FINE, SIN_COS_FINE);
impl_tier!(Fast, "fast", ATAN_FAST, ASIN_FAST, SIN_COS_FAST);

/// Arctangent of each lane, in `[−π/2, π/2]`.
///
/// Reduction: `|x| > 1` uses `atan|x| = π/2 − atan(1/|x|)`, so the polynomial
/// only sees `[0, 1]`; the sign of `x` is restored last. Polynomial (odd, in
/// `x`): exact `x + x³·P(x²)` of degree 17, fine degree 13, fast degree 7.
/// `atan(±0) = ±0`, `atan(±∞) = ±π/2` (exactly `f32` `π/2`), NaN stays NaN.
///
/// Within the tier's bound over every `f32` (both signs, every magnitude,
/// `±∞`); `ENVMAP_EXTENSIVE=1 cargo test -p envmap-tests --release --test
/// approx_accuracy -- --nocapture atan::` prints the worst error per tier.
#[inline]
#[must_use]
pub fn atan<T: Tier>(x: f32x8) -> f32x8 {
    T::atan(x)
}

/// Four-quadrant arctangent of `y/x` per lane, in `[−π, π]`, with every
/// IEEE special case of `std`'s `f32::atan2`.
///
/// Reduction: `z = min(|x|, |y|) / max(|x|, |y|)` in `[0, 1]` (the quotient
/// cannot overflow, and underflows only when the angle itself is below the
/// smallest `f32`, so no rescaling is needed for tiny or huge arguments),
/// `p = atan(z)` by the same polynomial as [`atan`](fn@atan) (exact degree
/// 17, fine 13, fast 7), then the octant: `p`, `π/2 − p`, `π − p` or
/// `π/2 + p`, with the sign of `y` (including `−0`) restored last.
/// `atan2(±0, +0) = ±0`, `atan2(±0, −0) = ±π`, `atan2(±y, ±0) = ±π/2`,
/// `atan2(±∞, −∞) = ±3π/4`, `atan2(±∞, +∞) = ±π/4`, a NaN in either argument
/// gives NaN.
///
/// Within the tier's bound over angles × radii from 10⁻⁴⁵ (denormal) to
/// 3.4·10³⁸, every pair of binary exponents in `[−149, 127]`, and every
/// `f32` quotient `t` in `[0, 1]` as `(t, 1)`, `(1, t)`, `(t, −1)` and
/// `(1, −t)`; `ENVMAP_EXTENSIVE=1 cargo test -p envmap-tests --release
/// --test approx_accuracy -- --nocapture atan2::` prints the worst error.
#[inline]
#[must_use]
pub fn atan2<T: Tier>(y: f32x8, x: f32x8) -> f32x8 {
    T::atan2(y, x)
}

/// `atan2(√y2, x)` of each lane: the angle of a point at distance `√y2`
/// from an axis and at height `x` along it, such as the polar angle of a
/// direction, `atan2(√(x² + y²), z)`, from `y2 = x² + y²`, `z` and
/// `x2 = z²`.
///
/// For `y2 ≥ 0`, `x` and `x2 = x²` finite, with `√y2` and `|x|` at most
/// 2⁴⁰ and the larger of them at least 2⁻⁴⁰, as for the components of a
/// unit direction or of one rescaled by a power of two (elsewhere the
/// squares underflow or overflow and the angle is unspecified).
///
/// The fine and fast tiers divide the squares, `min(y2, x2)/max(y2, x2)`,
/// which is the square `z²` of `atan2`'s reduced argument: the polynomial in
/// `z²` starts right after the division, and `z = √(z²)` is taken beside it,
/// where `atan2(√y2, x)` takes a square root before the division. The exact
/// tier evaluates `atan2(√y2, x)`.
///
/// Within the tier's bound against `f64` `atan2(√y2, x)` over polar angles
/// × radii from 2⁻⁴⁰ to 2⁴⁰ and pairs of unrelated magnitudes, with `x2`
/// rounded to `f32` (the fine and fast tiers' bounds are absolute);
/// `cargo test -p envmap-tests --release --test approx_accuracy --
/// --nocapture atan2_sqrt` prints the worst error.
#[inline]
#[must_use]
pub fn atan2_sqrt<T: Tier>(y2: f32x8, x: f32x8, x2: f32x8) -> f32x8 {
    T::atan2_sqrt(y2, x, x2)
}

/// Arcsine of each lane, in `[−π/2, π/2]`.
///
/// Reduction: `|x| ≤ 1/2` evaluates the polynomial at `|x|`; `|x| > 1/2`
/// uses `asin|x| = π/2 − 2·asin(√((1 − |x|)/2))`. The sign of `x` is
/// restored last. Polynomial (odd): exact `x + x³·P(x²)` of degree 11, fine
/// degree 7, fast degree 5, all fitted on `[0, 1/2]`. `asin(±0) = ±0`,
/// `asin(±1) = ±π/2`, `|x| > 1` and NaN give NaN.
///
/// Within the tier's bound over every `f32` of `[−1, 1]`;
/// `ENVMAP_EXTENSIVE=1 cargo test -p envmap-tests --release --test
/// approx_accuracy -- --nocapture asin::` prints the worst error per tier.
#[inline]
#[must_use]
pub fn asin<T: Tier>(x: f32x8) -> f32x8 {
    T::asin(x)
}

/// Arccosine of each lane, in `[0, π]`.
///
/// Reduction: `|x| ≤ 1/2` uses `π/2 ∓ asin|x|`; `|x| > 1/2` uses
/// `2·asin(√((1 − |x|)/2))` (for `x > 0`) or `π` minus it (for `x < 0`),
/// which stays accurate next to `±1` where `acos` behaves like a square
/// root. Same polynomials as [`asin`](fn@asin) (exact degree 11, fine 7,
/// fast 5). `acos(1) = +0`, `acos(−1) = π`, `|x| > 1` and NaN give NaN.
///
/// Within the tier's bound over every `f32` of `[−1, 1]`;
/// `ENVMAP_EXTENSIVE=1 cargo test -p envmap-tests --release --test
/// approx_accuracy -- --nocapture acos::` prints the worst error per tier.
#[inline]
#[must_use]
pub fn acos<T: Tier>(x: f32x8) -> f32x8 {
    T::acos(x)
}

/// Sine and cosine of each lane, `(sin x, cos x)`.
///
/// Reduction: quadrant `q = round(|x|·2/π)` and `r = |x| − q·π/2` in
/// `[−π/4, π/4]` by Cody–Waite, `π/2` split in four parts (exact tier: three
/// 12-bit parts and the rest, the third difference kept exactly, so `r` is
/// rounded once) or two parts (fine and fast: 12 bits and the rest); the
/// 12-bit parts make `q·part` exact for `q ≤ 2¹²` even without FMA. Then
/// `sin r`, `cos r` swapped and negated by quadrant and the sign of `x` put
/// on `sin`. Polynomials on `[0, π/4]`: exact `sin` degree 7
/// (`r + r³·P(r²)`) and `cos` degree 8 (`1 − r²/2 + r⁴·P(r²)`, the first
/// sum kept exactly); fine `sin` degree 5, `cos` degree 6; fast `sin`
/// degree 5, `cos` degree 4. `sin(±0) = ±0`, `cos(±0) = 1`, `±∞` and NaN
/// give NaN.
///
/// Accuracy holds for `|x| ≤` [`SIN_COS_RANGE`] `= 6433` (about 4096·π/2,
/// far beyond the `[−2π, 2π]` the mappings need). Beyond it the reduction
/// loses exactness and the error grows roughly like `|x|·4·10⁻⁸` (about
/// `4·10⁻³` at `10⁵`), and past `2²²·π/2` the quadrant is meaningless; the
/// reduced argument is clamped to `[−0.786, 0.786]`, so `(sin, cos)` always
/// stays within the polynomials' error of the unit circle.
///
/// Within the tier's bound over every `f32` of `[−6433, 6433]` (ULP is
/// meaningless for the fine and fast tiers next to the zeros of `sin` and
/// `cos`: their bounds are absolute); `ENVMAP_EXTENSIVE=1 cargo test -p
/// envmap-tests --release --test approx_accuracy -- --nocapture sin:: cos::`
/// prints the worst error per tier.
#[inline]
#[must_use]
pub fn sin_cos<T: Tier>(x: f32x8) -> (f32x8, f32x8) {
    T::sin_cos(x)
}
