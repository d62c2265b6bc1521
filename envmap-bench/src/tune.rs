//! Choosing a polynomial degree: fit `atan` (for `atan`/`atan2`) or `asin`
//! (for `asin`/`acos`) with the project's own minimax fitter at each degree,
//! then measure each fitted polynomial's worst error over the same sweep as
//! the tiers and its speed in the fine tier's reduction.
//!
//! Errors are also given in texels of a latlong map `width` texels wide:
//! `u = atan2/2π` over `width` texels and `v = acos/π` over `width/2`, so
//! one radian is `width/2π` texels either way.

use std::hint::black_box;
use std::sync::RwLock;

use wide::f32x8;

use crate::accuracy::{function_stats, Density, Function, Kernel};
use crate::remez::{approx_fits, minimax_f32, Problem};
use crate::timing::{ns_per_element, uniform};

/// The coefficients the error sweep's kernels read.
static COEFFS: RwLock<Vec<f32>> = RwLock::new(Vec::new());

const HALF_PI: f32 = std::f32::consts::FRAC_PI_2;
const PI: f32 = std::f32::consts::PI;

/// `x·P(x²)` with `P`'s coefficients `c`, lowest power first.
#[inline]
fn odd_poly(c: &[f32], x: f32x8) -> f32x8 {
    let x2 = x * x;
    let mut acc = f32x8::splat(c[c.len() - 1]);
    for &k in c[..c.len() - 1].iter().rev() {
        acc = acc.mul_add(x2, f32x8::splat(k));
    }
    acc * x
}

fn sign_of(v: f32x8, s: f32x8) -> f32x8 {
    let sign = f32x8::from_bits(s.to_bits() & wide::u32x8::splat(0x8000_0000));
    f32x8::from_bits(v.abs().to_bits() | sign.to_bits())
}

fn atan_with(c: &[f32], x: f32x8) -> f32x8 {
    let a = x.abs();
    let inv = a.simd_gt(f32x8::ONE);
    let z = inv.select(f32x8::ONE / a, a);
    let p = odd_poly(c, z);
    sign_of(inv.select(f32x8::splat(HALF_PI) - p, p), x)
}

fn atan2_with(c: &[f32], y: f32x8, x: f32x8) -> f32x8 {
    let (ax, ay) = (x.abs(), y.abs());
    let z = ax.min(ay) / ax.max(ay);
    let p = odd_poly(c, z);
    let p = ay.simd_gt(ax).select(f32x8::splat(HALF_PI) - p, p);
    let p = x.simd_lt(f32x8::ZERO).select(f32x8::splat(PI) - p, p);
    sign_of(p, y)
}

fn asin_with(c: &[f32], x: f32x8) -> f32x8 {
    let a = x.abs();
    let big = a.simd_gt(f32x8::splat(0.5));
    let z = big.select(((f32x8::ONE - a) * f32x8::splat(0.5)).sqrt(), a);
    let p = odd_poly(c, z);
    sign_of(big.select(f32x8::splat(HALF_PI) - (p + p), p), x)
}

fn acos_with(c: &[f32], x: f32x8) -> f32x8 {
    let a = x.abs();
    let big = a.simd_gt(f32x8::splat(0.5));
    let z = big.select(((f32x8::ONE - a) * f32x8::splat(0.5)).sqrt(), a);
    let p = odd_poly(c, z);
    let small = f32x8::splat(HALF_PI) - sign_of(p, x);
    let neg = x.simd_lt(f32x8::ZERO);
    let large = neg.select(f32x8::splat(PI) - (p + p), p + p);
    big.select(large, small)
}

fn read() -> Vec<f32> {
    COEFFS
        .read()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
        .clone()
}

/// One degree's result.
#[derive(Clone, Debug)]
pub struct TuneRow {
    /// Degree of the odd polynomial.
    pub degree: i32,
    /// The minimax error the fitter reached on the reduced interval (`f32`
    /// coefficients).
    pub fit_error: f64,
    /// Worst absolute error of the whole function over the sweep, radians.
    pub max_abs_err: f64,
    /// Worst error in ULP.
    pub max_ulp: u64,
    /// Median ns per value.
    pub ns: f64,
}

/// The functions [`tune`] knows.
pub const TUNABLE: [&str; 4] = ["atan", "atan2", "asin", "acos"];

/// Fits, sweeps and times `function` at every odd degree in `degrees`.
///
/// # Errors
///
/// An unknown function, or the fitter's error at some degree.
pub fn tune(
    function: &str,
    degrees: std::ops::RangeInclusive<i32>,
    density: Density,
    passes: usize,
) -> Result<Vec<TuneRow>, String> {
    let (spec_name, f) = match function {
        "atan" => ("ATAN_FINE", Function::Atan),
        "atan2" => ("ATAN_FINE", Function::Atan2),
        "asin" => ("ASIN_FINE", Function::Asin),
        "acos" => ("ASIN_FINE", Function::Acos),
        _ => return Err(format!("cannot tune {function}; one of {TUNABLE:?}")),
    };
    let spec = approx_fits()
        .into_iter()
        .find(|s| s.name == spec_name)
        .ok_or("fit missing")?;
    let mut rows = Vec::new();
    for degree in degrees.filter(|d| d % 2 == 1 && *d >= 1) {
        let free = usize::try_from((degree + 1) / 2).map_err(|e| e.to_string())?;
        let p = Problem {
            free,
            ..spec.problem
        };
        let fit = minimax_f32(&p).map_err(|e| format!("degree {degree}: {e}"))?;
        *COEFFS
            .write()
            .unwrap_or_else(std::sync::PoisonError::into_inner) = fit.coeffs.clone();
        let kernel = match f {
            Function::Atan => Kernel::Unary(|x| atan_with(&read(), x)),
            Function::Atan2 => Kernel::Binary(|y, x| atan2_with(&read(), y, x)),
            Function::Asin => Kernel::Unary(|x| asin_with(&read(), x)),
            _ => Kernel::Unary(|x| acos_with(&read(), x)),
        };
        let st = function_stats(f, kernel, density);
        let c = fit.coeffs.clone();
        let n = 4096;
        let (lo, hi) = if matches!(f, Function::Asin | Function::Acos) {
            (-1.0, 1.0)
        } else {
            (-10.0, 10.0)
        };
        let mut out = vec![f32x8::ZERO; n / 8];
        let ns = ns_per_element(
            passes,
            n,
            |pass| {
                let a = uniform(pass as u64 ^ 0x7E, n, lo, hi);
                let b = uniform(pass as u64 ^ 0x7F, n, lo, hi);
                let to8 = |v: &[f32]| -> Vec<f32x8> {
                    v.chunks_exact(8)
                        .map(|c| f32x8::new(c.try_into().unwrap_or([0.0; 8])))
                        .collect()
                };
                (to8(&a), to8(&b))
            },
            |(a, b)| {
                for ((o, &y), &x) in out.iter_mut().zip(a).zip(b) {
                    *o = match f {
                        Function::Atan => atan_with(&c, y),
                        Function::Atan2 => atan2_with(&c, y, x),
                        Function::Asin => asin_with(&c, y),
                        _ => acos_with(&c, y),
                    };
                }
                black_box(&out);
            },
        );
        rows.push(TuneRow {
            degree,
            fit_error: fit.max_error,
            max_abs_err: st.max_abs,
            max_ulp: st.max_ulp,
            ns,
        });
    }
    Ok(rows)
}

/// Radians to texels of a latlong map `width` texels wide.
#[must_use]
pub fn texels(rad: f64, width: f64) -> f64 {
    rad * width / std::f64::consts::TAU
}
