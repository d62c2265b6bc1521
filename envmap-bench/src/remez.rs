//! A Remez exchange minimax fitter (in `f64`) for odd and even polynomials,
//! and the list of every polynomial `envmap_simd::approx` uses.
//!
//! # The problem
//!
//! Given a function `f` on `[lo, hi]`, a [`Parity`] (odd: powers `x, x³, x⁵…`;
//! even: `1, x², x⁴…`), some leading coefficients held fixed (for example the
//! `1` of `atan(x) ≈ x + x³·P(x²)`) and a number of free coefficients, find the
//! free coefficients that minimise the largest weighted error
//! `w(x)·(p(x) − f(x))` over the interval, where `w = 1` ([`ErrorWeight::Absolute`])
//! or `w = 1/|f|` ([`ErrorWeight::Relative`]).
//!
//! # The algorithm
//!
//! The classic multi-point exchange: start from a reference of `n + 1`
//! Chebyshev points (`n` free coefficients), solve the linear system that makes
//! the weighted error equal `±E` with alternating signs on the reference,
//! locate the alternating extrema of the new error curve (a dense
//! Chebyshev-spaced scan refined by golden-section search), take them as the
//! next reference and repeat until the extrema are level (equioscillation).
//!
//! [`minimax_f32`] then makes the result `f32`-aware: it rounds the
//! coefficients to `f32` one at a time, lowest power first, refitting the
//! remaining higher-power coefficients after each rounding so that they absorb
//! the rounding error, and finally tries the neighbouring `f32` values of the
//! last coefficient.
//!
//! [`approx_fits`] lists every polynomial of every tier in
//! `envmap_simd::approx`; the `envmap-fit` binary refits them all and prints
//! `envmap-simd/src/approx/coeffs.rs` ([`render_coeffs_rs`]).

use core::fmt::Write as _;

/// Which powers of `x` a polynomial uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Parity {
    /// `c₀·x + c₁·x³ + c₂·x⁵ + …`
    Odd,
    /// `c₀ + c₁·x² + c₂·x⁴ + …`
    Even,
}

impl Parity {
    /// The power of `x` of the coefficient with index `k`.
    #[must_use]
    pub fn power(self, k: usize) -> i32 {
        let base: i32 = match self {
            Parity::Odd => 1,
            Parity::Even => 0,
        };
        base.saturating_add(i32::try_from(k).unwrap_or(i32::MAX).saturating_mul(2))
    }
}

/// How the error `p(x) − f(x)` is weighted.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ErrorWeight {
    /// Minimise `max |p − f|`.
    Absolute,
    /// Minimise `max |p − f| / |f|`.
    Relative,
}

/// One minimax problem.
#[derive(Clone, Copy, Debug)]
pub struct Problem<'a> {
    /// The function to approximate.
    pub f: fn(f64) -> f64,
    /// Lower end of the interval. `0` is allowed (the fit starts at `1e-6·hi`
    /// then; an odd polynomial, or one whose constant term is fixed to `f(0)`,
    /// is exact there anyway).
    pub lo: f64,
    /// Upper end of the interval.
    pub hi: f64,
    /// Odd or even powers.
    pub parity: Parity,
    /// Leading (lowest-power) coefficients held fixed, for example `[1.0]`
    /// for `x + x³·P(x²)` or `[1.0, -0.5]` for `1 − x²/2 + x⁴·P(x²)`.
    pub fixed: &'a [f64],
    /// Number of free coefficients after the fixed ones.
    pub free: usize,
    /// Absolute or relative error.
    pub weight: ErrorWeight,
}

/// The result of a fit.
#[derive(Clone, Debug, PartialEq)]
pub struct Fit {
    /// The free coefficients, lowest power first.
    pub coeffs: Vec<f64>,
    /// The weighted error the exchange levelled out at (`|E|` of the last
    /// linear solve).
    pub levelled_error: f64,
    /// The largest weighted error found by a dense scan of the interval, and
    /// where it occurs.
    pub max_error: f64,
    /// Argument of [`Fit::max_error`].
    pub max_error_at: f64,
    /// Exchange iterations used.
    pub iterations: usize,
}

/// A fit whose coefficients are `f32`.
#[derive(Clone, Debug, PartialEq)]
pub struct Fit32 {
    /// The unrounded (`f64`) minimax fit.
    pub exact: Fit,
    /// The free coefficients rounded to `f32` by the sequential procedure.
    pub coeffs: Vec<f32>,
    /// The largest weighted error of the `f32` coefficients (polynomial
    /// evaluated in `f64`), from a dense scan.
    pub max_error: f64,
    /// Argument of [`Fit32::max_error`].
    pub max_error_at: f64,
}

/// Why a fit failed.
#[derive(Clone, Debug, PartialEq)]
pub enum RemezError {
    /// The problem is malformed (empty interval, no free coefficient).
    BadProblem(&'static str),
    /// The reference system was singular.
    Singular,
    /// The error curve had fewer alternations than needed (the function is
    /// already matched, or the problem violates the Haar condition).
    TooFewExtrema {
        /// Alternating extrema found.
        found: usize,
        /// Extrema needed (`free + 1`).
        needed: usize,
    },
}

impl core::fmt::Display for RemezError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            RemezError::BadProblem(why) => write!(f, "bad problem: {why}"),
            RemezError::Singular => write!(f, "singular reference system"),
            RemezError::TooFewExtrema { found, needed } => {
                write!(
                    f,
                    "error curve has {found} alternating extrema, {needed} needed"
                )
            }
        }
    }
}

impl std::error::Error for RemezError {}

impl Problem<'_> {
    fn start(&self) -> f64 {
        if self.lo == 0.0 {
            self.hi * 1e-6
        } else {
            self.lo
        }
    }

    /// Value of the polynomial with the fixed coefficients and the given free
    /// ones at `x` (Horner in `x²`, in `f64`).
    #[must_use]
    pub fn eval(&self, free: &[f64], x: f64) -> f64 {
        let x2 = x * x;
        let mut acc = 0.0;
        for &c in free.iter().rev().chain(self.fixed.iter().rev()) {
            acc = acc * x2 + c;
        }
        match self.parity {
            Parity::Odd => acc * x,
            Parity::Even => acc,
        }
    }

    fn fixed_part(&self, x: f64) -> f64 {
        self.eval(&[], x)
    }

    fn weight_at(&self, x: f64) -> f64 {
        match self.weight {
            ErrorWeight::Absolute => 1.0,
            ErrorWeight::Relative => 1.0 / (self.f)(x).abs(),
        }
    }

    /// Weighted error `w(x)·(p(x) − f(x))` of the given free coefficients.
    #[must_use]
    pub fn error(&self, free: &[f64], x: f64) -> f64 {
        let fx = (self.f)(x);
        let e = self.eval(free, x) - fx;
        match self.weight {
            ErrorWeight::Absolute => e,
            ErrorWeight::Relative => {
                if fx == 0.0 {
                    0.0
                } else {
                    e / fx.abs()
                }
            }
        }
    }

    /// Largest weighted error over the interval (dense Chebyshev-spaced scan
    /// refined around the worst point) and where it occurs.
    #[must_use]
    pub fn max_error(&self, free: &[f64]) -> (f64, f64) {
        let grid = self.grid();
        let mut best = (0.0_f64, grid[0]);
        let mut best_i = 0;
        for (i, &x) in grid.iter().enumerate() {
            let e = self.error(free, x).abs();
            if e > best.0 {
                best = (e, x);
                best_i = i;
            }
        }
        let (x, e) = self.refine(free, &grid, best_i);
        if e > best.0 {
            (e, x)
        } else {
            best
        }
    }

    fn grid(&self) -> Vec<f64> {
        let (a, b) = (self.start(), self.hi);
        let n = 1024 * (self.free + 2);
        (0..=n)
            .map(|k| {
                let t = (1.0 - (core::f64::consts::PI * k as f64 / n as f64).cos()) / 2.0;
                (a + (b - a) * t).clamp(a, b)
            })
            .collect()
    }

    /// Golden-section search for the largest `|error|` between the grid
    /// neighbours of `grid[i]`.
    fn refine(&self, free: &[f64], grid: &[f64], i: usize) -> (f64, f64) {
        let mut lo = grid[i.saturating_sub(1)];
        let mut hi = grid[(i + 1).min(grid.len() - 1)];
        let g = |x: f64| self.error(free, x).abs();
        let r = (5.0_f64.sqrt() - 1.0) / 2.0;
        let mut c = hi - r * (hi - lo);
        let mut d = lo + r * (hi - lo);
        let (mut gc, mut gd) = (g(c), g(d));
        for _ in 0..60 {
            if gc > gd {
                hi = d;
                d = c;
                gd = gc;
                c = hi - r * (hi - lo);
                gc = g(c);
            } else {
                lo = c;
                c = d;
                gc = gd;
                d = lo + r * (hi - lo);
                gd = g(d);
            }
        }
        let mut best = (grid[i], g(grid[i]));
        for x in [c, d] {
            let e = g(x);
            if e > best.1 {
                best = (x, e);
            }
        }
        best
    }
}

/// Solve `a·x = b` (row-major square `a`) by Gaussian elimination with row
/// equilibration and partial pivoting.
fn solve(mut a: Vec<Vec<f64>>, mut b: Vec<f64>) -> Result<Vec<f64>, RemezError> {
    let n = b.len();
    for (row, rhs) in a.iter_mut().zip(b.iter_mut()) {
        let s = row.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        if s == 0.0 {
            return Err(RemezError::Singular);
        }
        row.iter_mut().for_each(|v| *v /= s);
        *rhs /= s;
    }
    for col in 0..n {
        // col < n, so the range is not empty.
        let piv = (col..n)
            .max_by(|&i, &j| a[i][col].abs().total_cmp(&a[j][col].abs()))
            .unwrap_or(col);
        if a[piv][col] == 0.0 {
            return Err(RemezError::Singular);
        }
        a.swap(col, piv);
        b.swap(col, piv);
        let (upper, lower) = a.split_at_mut(col + 1);
        let pivot_row = &upper[col];
        for (offset, row) in lower.iter_mut().enumerate() {
            let m = row[col] / pivot_row[col];
            if m != 0.0 {
                for (v, p) in row[col..].iter_mut().zip(&pivot_row[col..]) {
                    *v -= m * p;
                }
                b[col + 1 + offset] -= m * b[col];
            }
        }
    }
    let mut x = vec![0.0; n];
    for row in (0..n).rev() {
        let s: f64 = (row + 1..n).map(|k| a[row][k] * x[k]).sum();
        x[row] = (b[row] - s) / a[row][row];
    }
    Ok(x)
}

/// Weighted errors this small are rounding noise of the `f64` evaluation of
/// `f` and the polynomial, not part of the error curve: they neither start
/// a new alternation nor count as converged-away differences.
const NOISE: f64 = 1e-15;

/// Alternating extrema of the error curve: one per maximal run of equal sign,
/// refined by golden-section search. Returns `(x, signed error)` pairs.
fn alternating_extrema(p: &Problem<'_>, free: &[f64], grid: &[f64]) -> Vec<(f64, f64)> {
    let errs: Vec<f64> = grid.iter().map(|&x| p.error(free, x)).collect();
    let mut out: Vec<(f64, f64)> = Vec::new();
    let mut run_best: Option<usize> = None;
    for i in 0..grid.len() {
        let e = errs[i];
        if e.abs() <= NOISE {
            continue;
        }
        match run_best {
            Some(j) if errs[j].signum() == e.signum() => {
                if e.abs() > errs[j].abs() {
                    run_best = Some(i);
                }
            }
            Some(j) => {
                out.push(refined(p, free, grid, j, errs[j]));
                run_best = Some(i);
            }
            None => run_best = Some(i),
        }
    }
    if let Some(j) = run_best {
        out.push(refined(p, free, grid, j, errs[j]));
    }
    out
}

fn refined(p: &Problem<'_>, free: &[f64], grid: &[f64], i: usize, e: f64) -> (f64, f64) {
    let (x, _) = p.refine(free, grid, i);
    let ex = p.error(free, x);
    if ex.signum() == e.signum() && ex.abs() >= e.abs() {
        (x, ex)
    } else {
        (grid[i], e)
    }
}

/// Fit the free coefficients of `p` by the Remez exchange (coefficients in
/// `f64`).
///
/// # Errors
///
/// [`RemezError`] if the problem is malformed or the exchange breaks down.
pub fn minimax(p: &Problem<'_>) -> Result<Fit, RemezError> {
    let n = p.free;
    if n == 0 {
        return Err(RemezError::BadProblem("no free coefficient"));
    }
    if p.hi <= p.lo || p.lo < 0.0 {
        return Err(RemezError::BadProblem("need 0 <= lo < hi"));
    }
    let (a, b) = (p.start(), p.hi);
    let grid = p.grid();
    // Initial reference: the n + 1 Chebyshev nodes (roots) mapped to [a, b].
    // They are interior points: an odd polynomial (or one with a fixed
    // constant term) is exact at x = 0, so a reference point there would make
    // the system degenerate. The exchange moves points onto the ends when the
    // extrema are there.
    let mut reference: Vec<f64> = (0..=n)
        .map(|i| {
            let t = (core::f64::consts::PI * (2 * (n - i) + 1) as f64 / (2 * n + 2) as f64).cos();
            a + (b - a) * (1.0 + t) / 2.0
        })
        .collect();
    let first = p.fixed.len();
    let mut coeffs = vec![0.0; n];
    let mut levelled = 0.0;
    let mut iterations = 0;
    for iter in 1..=100 {
        iterations = iter;
        let rows: Vec<Vec<f64>> = reference
            .iter()
            .enumerate()
            .map(|(i, &x)| {
                let mut row: Vec<f64> = (0..n).map(|j| x.powi(p.parity.power(first + j))).collect();
                let s = if i % 2 == 0 { 1.0 } else { -1.0 };
                row.push(s / p.weight_at(x));
                row
            })
            .collect();
        let rhs: Vec<f64> = reference
            .iter()
            .map(|&x| (p.f)(x) - p.fixed_part(x))
            .collect();
        let sol = solve(rows, rhs)?;
        coeffs.copy_from_slice(&sol[..n]);
        levelled = sol[n].abs();
        let mut ext = alternating_extrema(p, &coeffs, &grid);
        if ext.len() < n + 1 {
            return Err(RemezError::TooFewExtrema {
                found: ext.len(),
                needed: n + 1,
            });
        }
        while ext.len() > n + 1 {
            if ext[0].1.abs() < ext[ext.len() - 1].1.abs() {
                ext.remove(0);
            } else {
                ext.pop();
            }
        }
        let hi_e = ext.iter().fold(0.0_f64, |m, e| m.max(e.1.abs()));
        let lo_e = ext.iter().fold(f64::INFINITY, |m, e| m.min(e.1.abs()));
        reference = ext.iter().map(|e| e.0).collect();
        if hi_e - lo_e <= 1e-7 * hi_e + 4.0 * NOISE {
            break;
        }
    }
    let (max_error, max_error_at) = p.max_error(&coeffs);
    Ok(Fit {
        coeffs,
        levelled_error: levelled,
        max_error,
        max_error_at,
        iterations,
    })
}

/// The `f32` values next to `v` (`k` steps up or down, `k` may be negative).
fn f32_step(v: f32, k: i32) -> f32 {
    let mut r = v;
    for _ in 0..k.unsigned_abs() {
        r = if k > 0 { r.next_up() } else { r.next_down() };
    }
    r
}

/// Fit `p` and round the coefficients to `f32`, `f32`-aware: coefficients are
/// rounded lowest power first, and after each rounding the remaining higher
/// coefficients are refitted (Remez, with the rounded ones held fixed) so
/// that they compensate; finally the last coefficient is moved to whichever
/// of its eight nearest `f32` neighbours (or itself) gives the smallest
/// maximum error.
///
/// # Errors
///
/// [`RemezError`] if any of the fits fails.
pub fn minimax_f32(p: &Problem<'_>) -> Result<Fit32, RemezError> {
    let exact = minimax(p)?;
    let mut fixed: Vec<f64> = p.fixed.to_vec();
    let mut rounded: Vec<f32> = Vec::with_capacity(p.free);
    let mut current = exact.coeffs.clone();
    for k in 0..p.free {
        let c = current[0] as f32;
        rounded.push(c);
        fixed.push(f64::from(c));
        if k + 1 < p.free {
            let sub = Problem {
                fixed: &fixed,
                free: p.free - k - 1,
                ..*p
            };
            current = minimax(&sub)?.coeffs;
        }
    }
    let as_f64 = |c: &[f32]| c.iter().map(|&v| f64::from(v)).collect::<Vec<f64>>();
    let mut best = p.max_error(&as_f64(&rounded));
    let last = rounded.len() - 1;
    let base = rounded[last];
    let mut best_c = base;
    for k in [-4, -3, -2, -1, 1, 2, 3, 4] {
        rounded[last] = f32_step(base, k);
        let e = p.max_error(&as_f64(&rounded));
        if e.0 < best.0 {
            best = e;
            best_c = rounded[last];
        }
    }
    rounded[last] = best_c;
    Ok(Fit32 {
        exact,
        coeffs: rounded,
        max_error: best.0,
        max_error_at: best.1,
    })
}

/// One polynomial of `envmap_simd::approx` with the problem it solves.
#[derive(Clone, Copy, Debug)]
pub struct ApproxFit {
    /// Name of the constant in `coeffs.rs`.
    pub name: &'static str,
    /// What the polynomial approximates (one line of documentation).
    pub what: &'static str,
    /// The minimax problem.
    pub problem: Problem<'static>,
}

fn sin(x: f64) -> f64 {
    x.sin()
}
fn cos(x: f64) -> f64 {
    x.cos()
}
fn atan(x: f64) -> f64 {
    x.atan()
}
fn asin(x: f64) -> f64 {
    x.asin()
}

const ONE: &[f64] = &[1.0];
const ONE_MINUS_HALF: &[f64] = &[1.0, -0.5];
const NONE: &[f64] = &[];

/// Every polynomial used by every tier of `envmap_simd::approx`.
///
/// Intervals come from the reductions: `atan` on `[0, 1]` (larger arguments
/// use `π/2 − atan(1/x)`), `asin` on `[0, 1/2]` (larger ones use
/// `π/2 − 2·asin(√((1−x)/2))`, so its absolute error is doubled there and the
/// absolute fits aim at half the tier's budget), `sin` and `cos` on
/// `[0, π/4]` after quadrant reduction.
#[must_use]
pub fn approx_fits() -> Vec<ApproxFit> {
    use ErrorWeight::{Absolute, Relative};
    use Parity::{Even, Odd};
    let quarter_pi = core::f64::consts::FRAC_PI_4;
    let fit = |name, what, f, hi, parity, fixed, free, weight| ApproxFit {
        name,
        what,
        problem: Problem {
            f,
            lo: 0.0,
            hi,
            parity,
            fixed,
            free,
            weight,
        },
    };
    vec![
        fit(
            "ATAN_EXACT",
            "atan(x) ≈ x + x³·P(x²) on [0, 1], relative error",
            atan,
            1.0,
            Odd,
            ONE,
            8,
            Relative,
        ),
        fit(
            "ATAN_FINE",
            "atan(x) ≈ x·P(x²) on [0, 1], absolute error",
            atan,
            1.0,
            Odd,
            NONE,
            7,
            Absolute,
        ),
        fit(
            "ATAN_FAST",
            "atan(x) ≈ x·P(x²) on [0, 1], absolute error",
            atan,
            1.0,
            Odd,
            NONE,
            4,
            Absolute,
        ),
        fit(
            "ASIN_EXACT",
            "asin(x) ≈ x + x³·P(x²) on [0, 1/2], relative error",
            asin,
            0.5,
            Odd,
            ONE,
            5,
            Relative,
        ),
        fit(
            "ASIN_FINE",
            "asin(x) ≈ x·P(x²) on [0, 1/2], absolute error",
            asin,
            0.5,
            Odd,
            NONE,
            4,
            Absolute,
        ),
        fit(
            "ASIN_FAST",
            "asin(x) ≈ x·P(x²) on [0, 1/2], absolute error",
            asin,
            0.5,
            Odd,
            NONE,
            3,
            Absolute,
        ),
        fit(
            "SIN_EXACT",
            "sin(x) ≈ x + x³·P(x²) on [0, π/4], relative error",
            sin,
            quarter_pi,
            Odd,
            ONE,
            3,
            Relative,
        ),
        fit(
            "COS_EXACT",
            "cos(x) ≈ 1 − x²/2 + x⁴·P(x²) on [0, π/4], relative error",
            cos,
            quarter_pi,
            Even,
            ONE_MINUS_HALF,
            3,
            Relative,
        ),
        fit(
            "SIN_FINE",
            "sin(x) ≈ x·P(x²) on [0, π/4], absolute error (fine and fast tiers)",
            sin,
            quarter_pi,
            Odd,
            NONE,
            3,
            Absolute,
        ),
        fit(
            "COS_FINE",
            "cos(x) ≈ 1 + x²·P(x²) on [0, π/4], absolute error",
            cos,
            quarter_pi,
            Even,
            ONE,
            3,
            Absolute,
        ),
        fit(
            "COS_FAST",
            "cos(x) ≈ 1 + x²·P(x²) on [0, π/4], absolute error",
            cos,
            quarter_pi,
            Even,
            ONE,
            2,
            Absolute,
        ),
    ]
}

/// A refitted [`ApproxFit`].
#[derive(Clone, Debug)]
pub struct FitResult {
    /// The polynomial.
    pub spec: ApproxFit,
    /// Its fit.
    pub fit: Fit32,
}

/// Refit every polynomial of [`approx_fits`].
///
/// # Errors
///
/// The first [`RemezError`], with the name of the polynomial.
pub fn fit_all() -> Result<Vec<FitResult>, (&'static str, RemezError)> {
    approx_fits()
        .into_iter()
        .map(|spec| {
            minimax_f32(&spec.problem)
                .map(|fit| FitResult { spec, fit })
                .map_err(|e| (spec.name, e))
        })
        .collect()
}

fn describe_weight(w: ErrorWeight) -> &'static str {
    match w {
        ErrorWeight::Absolute => "absolute",
        ErrorWeight::Relative => "relative",
    }
}

/// The text of `envmap-simd/src/approx/coeffs.rs` for the given fits.
#[must_use]
pub fn render_coeffs_rs(results: &[FitResult]) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "//! Polynomial coefficients of [`crate::approx`], lowest power first.\n\
         //!\n\
         //! Generated by the project's own Remez fitter (`envmap-bench/src/remez.rs`):\n\
         //!\n\
         //! ```text\n\
         //! cargo run --release -p envmap-bench --bin envmap-fit > envmap-simd/src/approx/coeffs.rs\n\
         //! ```\n\
         //!\n\
         //! Do not edit by hand: `tests/tests/approx_fit.rs` refits every polynomial\n\
         //! and fails if a coefficient here differs from the refit by more than one\n\
         //! `f32` ULP. Each error below is the polynomial's own (coefficients as\n\
         //! stored, evaluated exactly); `f32` evaluation and the argument reductions\n\
         //! add to it (see the functions' documentation for the measured totals)."
    );
    for r in results {
        let p = &r.spec.problem;
        let _ = writeln!(s);
        let _ = writeln!(s, "/// {}.", r.spec.what);
        let _ = writeln!(s, "///");
        let fixed = if p.fixed.is_empty() {
            String::new()
        } else {
            format!(" after the fixed {:?}", p.fixed.to_vec())
        };
        let _ = writeln!(
            s,
            "/// Coefficients of x^{}, x^{}, … (lowest power first){fixed}.",
            p.parity.power(p.fixed.len()),
            p.parity.power(p.fixed.len() + 1),
        );
        let _ = writeln!(
            s,
            "/// Minimax {} error {:.3e} with `f64` coefficients ({} exchanges),\n\
             /// {:.3e} (at x = {:.6}) with these `f32` ones.",
            describe_weight(p.weight),
            r.fit.exact.max_error,
            r.fit.exact.iterations,
            r.fit.max_error,
            r.fit.max_error_at,
        );
        let _ = writeln!(
            s,
            "pub const {}: [f32; {}] = [",
            r.spec.name,
            r.fit.coeffs.len()
        );
        let values: Vec<String> = r.fit.coeffs.iter().map(|c| format!("{c:?},")).collect();
        let width = values.iter().map(String::len).max().unwrap_or(0);
        for (v, c) in values.iter().zip(&r.fit.coeffs) {
            let _ = writeln!(s, "    {v:<width$} // 0x{:08x}", c.to_bits());
        }
        let _ = writeln!(s, "];");
    }
    let _ = writeln!(s);
    let _ = writeln!(
        s,
        "/// Every polynomial above by name, for the test that refits them."
    );
    let _ = writeln!(s, "pub const ALL: [(&str, &[f32]); {}] = [", results.len());
    for r in results {
        let _ = writeln!(s, "    (\"{0}\", &{0}),", r.spec.name);
    }
    let _ = writeln!(s, "];");
    s
}
