//! Worst-case error of the `f32x8` functions of `envmap_simd::approx` (or
//! of any function with the same signature: `wide`'s, `std`'s lane by lane)
//! against the `f64` functions, over sweeps of their domains.
//!
//! A sweep visits every `stride`-th `f32` bit pattern of each reduced domain
//! ([`Density`]), plus the neighbourhoods of the reduction boundaries and of
//! the zeros of the results; `atan2` also gets angles × radii from denormal
//! to `f32::MAX`, every pair of binary exponents with random mantissas, and
//! every reduced quotient in each octant reconstruction. [`Stats`] keeps the
//! worst absolute error, the worst distance in ULP and where each occurs.
//!
//! `envmap-tests`' `approx_accuracy` test asserts the tier bounds on these
//! sweeps; `envmap-report` prints them beside the timings.

use std::sync::Mutex;

use envmap_simd::approx::{self, Tier};
use wide::f32x8;

/// How densely a sweep samples each domain.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Density {
    /// Every 65 521st `f32` and fewer `atan2` pairs: well under a second per
    /// function, for smoke runs.
    Quick,
    /// Every 1021st `f32`: a few seconds for every function and tier.
    Dense,
    /// Every `f32` of each reduced domain: about twenty minutes on two cores.
    Exhaustive,
}

impl Density {
    /// [`Density::Exhaustive`] if the environment variable
    /// `ENVMAP_EXTENSIVE` is `1`, else [`Density::Dense`].
    #[must_use]
    pub fn from_env() -> Self {
        if std::env::var("ENVMAP_EXTENSIVE").is_ok_and(|v| v == "1") {
            Density::Exhaustive
        } else {
            Density::Dense
        }
    }

    /// Stride through the bit patterns of a domain.
    #[must_use]
    pub fn stride(self) -> u32 {
        match self {
            Density::Quick => 65_521,
            Density::Dense => 1021,
            Density::Exhaustive => 1,
        }
    }
}

/// Position of `v` on the line of representable `f32` (`±0` both 0).
#[must_use]
pub fn ordinal(v: f32) -> i64 {
    let b = v.to_bits();
    let m = i64::from(b & 0x7FFF_FFFF);
    if b >> 31 == 1 {
        -m
    } else {
        m
    }
}

/// Distance in ULP between `got` and the reference rounded to `f32`;
/// `u64::MAX` if exactly one of them is NaN.
#[must_use]
pub fn ulp_distance(got: f32, reference: f64) -> u64 {
    let r = reference as f32;
    match (got.is_nan(), r.is_nan()) {
        (true, true) => 0,
        (false, false) => (ordinal(got) - ordinal(r)).unsigned_abs(),
        _ => u64::MAX,
    }
}

/// Error in units of the `f32` spacing at the (unrounded) reference.
#[must_use]
pub fn ulp_fraction(got: f32, reference: f64) -> f64 {
    let e = ((reference.abs().to_bits() >> 52) as i32 - 1023).max(-126);
    abs_error(got, reference) / 2f64.powi(e - 23)
}

/// `|got − reference|`; 0 if both are NaN, infinite if exactly one is.
#[must_use]
pub fn abs_error(got: f32, reference: f64) -> f64 {
    match (got.is_nan(), reference.is_nan()) {
        (true, true) => 0.0,
        (false, false) => (f64::from(got) - reference).abs(),
        _ => f64::INFINITY,
    }
}

/// Worst errors of one sweep and where they occur (arguments `(x, 0)` for
/// unary functions, `(y, x)` for `atan2`).
#[derive(Clone, Copy, Debug)]
pub struct Stats {
    /// Largest absolute error.
    pub max_abs: f64,
    /// Where [`Stats::max_abs`] occurs.
    pub abs_at: (f32, f32),
    /// Largest distance in ULP from the reference rounded to `f32`.
    pub max_ulp: u64,
    /// Where [`Stats::max_ulp`] occurs.
    pub ulp_at: (f32, f32),
    /// Largest error in units of the `f32` spacing at the unrounded reference.
    pub max_ulp_fraction: f64,
    /// Points measured.
    pub count: u64,
}

impl Stats {
    /// No points yet.
    pub const EMPTY: Stats = Stats {
        max_abs: 0.0,
        abs_at: (0.0, 0.0),
        max_ulp: 0,
        ulp_at: (0.0, 0.0),
        max_ulp_fraction: 0.0,
        count: 0,
    };

    /// Adds one point.
    pub fn add(&mut self, arg: (f32, f32), got: f32, reference: f64) {
        self.count += 1;
        let a = abs_error(got, reference);
        if a > self.max_abs {
            self.max_abs = a;
            self.abs_at = arg;
        }
        self.max_ulp_fraction = self.max_ulp_fraction.max(ulp_fraction(got, reference));
        let u = ulp_distance(got, reference);
        if u > self.max_ulp {
            self.max_ulp = u;
            self.ulp_at = arg;
        }
    }

    /// Adds another sweep's points.
    pub fn merge(&mut self, o: &Stats) {
        self.count += o.count;
        self.max_ulp_fraction = self.max_ulp_fraction.max(o.max_ulp_fraction);
        if o.max_abs > self.max_abs {
            self.max_abs = o.max_abs;
            self.abs_at = o.abs_at;
        }
        if o.max_ulp > self.max_ulp {
            self.max_ulp = o.max_ulp;
            self.ulp_at = o.ulp_at;
        }
    }
}

/// A one-argument function of eight lanes.
pub type Unary = fn(f32x8) -> f32x8;
/// A two-argument function of eight lanes (`atan2(y, x)`).
pub type Binary = fn(f32x8, f32x8) -> f32x8;

/// Evaluates `f` on `xs` (any length, the last batch padded) and adds the
/// errors against `reference` to `stats`.
pub fn run_unary(stats: &mut Stats, f: Unary, reference: fn(f64) -> f64, xs: &[f32]) {
    for chunk in xs.chunks(8) {
        let mut lanes = [0.0_f32; 8];
        lanes[..chunk.len()].copy_from_slice(chunk);
        let got = f(f32x8::new(lanes)).to_array();
        for (i, &x) in chunk.iter().enumerate() {
            stats.add((x, 0.0), got[i], reference(f64::from(x)));
        }
    }
}

/// `f` on up to eight `(y, x)` pairs at once (unused lanes get zeros); lane
/// `i` of the result belongs to `pairs[i]`.
#[must_use]
pub fn apply_binary(f: Binary, pairs: &[(f32, f32)]) -> [f32; 8] {
    let mut ys = [0.0_f32; 8];
    let mut xs = [0.0_f32; 8];
    for (i, &(y, x)) in pairs.iter().take(8).enumerate() {
        ys[i] = y;
        xs[i] = x;
    }
    f(f32x8::new(ys), f32x8::new(xs)).to_array()
}

/// [`run_unary`] for a two-argument function on `(y, x)` pairs.
pub fn run_binary(stats: &mut Stats, f: Binary, reference: fn(f64, f64) -> f64, ps: &[(f32, f32)]) {
    for chunk in ps.chunks(8) {
        let got = apply_binary(f, chunk);
        for (i, &(y, x)) in chunk.iter().enumerate() {
            stats.add((y, x), got[i], reference(f64::from(y), f64::from(x)));
        }
    }
}

/// Runs `work(lo, hi)` over `[lo, hi)` split across threads, merging stats.
fn parallel(lo: u64, hi: u64, work: impl Fn(u64, u64) -> Stats + Sync) -> Stats {
    let threads = std::thread::available_parallelism().map_or(2, |n| n.get()) as u64;
    let pieces = threads * 8;
    let total = Mutex::new(Stats::EMPTY);
    let next = Mutex::new(0_u64);
    std::thread::scope(|s| {
        for _ in 0..threads {
            s.spawn(|| loop {
                let k = {
                    let mut n = next
                        .lock()
                        .unwrap_or_else(std::sync::PoisonError::into_inner);
                    let k = *n;
                    *n += 1;
                    k
                };
                if k >= pieces {
                    break;
                }
                let a = lo + (hi - lo) * k / pieces;
                let b = lo + (hi - lo) * (k + 1) / pieces;
                let st = work(a, b);
                total
                    .lock()
                    .unwrap_or_else(std::sync::PoisonError::into_inner)
                    .merge(&st);
            });
        }
    });
    total
        .into_inner()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// Every `stride`-th `f32` of `[lo, hi]` (both non-negative), with the sign
/// bit set if `negative`.
///
/// # Panics
///
/// If `lo` is negative or above `hi`.
#[must_use]
pub fn sweep_bits(
    f: Unary,
    reference: fn(f64) -> f64,
    (lo, hi, negative): (f32, f32, bool),
    stride: u32,
) -> Stats {
    assert!(lo >= 0.0 && hi >= lo);
    let sign = if negative { 0x8000_0000 } else { 0 };
    parallel(
        u64::from(lo.to_bits()),
        u64::from(hi.to_bits()) + 1,
        |a, b| {
            let mut st = Stats::EMPTY;
            let mut buf = Vec::with_capacity(4096);
            // Align to the global stride so the pieces tile the same sample set.
            let mut bits = a.div_ceil(u64::from(stride)) * u64::from(stride);
            while bits < b {
                buf.push(f32::from_bits(bits as u32 | sign));
                if buf.len() == 4096 {
                    run_unary(&mut st, f, reference, &buf);
                    buf.clear();
                }
                bits += u64::from(stride);
            }
            run_unary(&mut st, f, reference, &buf);
            st
        },
    )
}

/// The `f32` values within `k` steps of each of `centres` (both signs).
#[must_use]
pub fn neighbourhoods(centres: &[f64], k: i32) -> Vec<f32> {
    let mut out = Vec::new();
    for &c in centres {
        for sign in [1.0, -1.0] {
            let mid = (sign * c) as f32;
            let mut v = mid;
            for _ in 0..k {
                v = v.next_down();
            }
            for _ in 0..=2 * k {
                out.push(v);
                v = v.next_up();
            }
        }
    }
    out
}

fn unary_sweep(
    f: Unary,
    reference: fn(f64) -> f64,
    ranges: &[(f32, f32, bool)],
    special: &[f32],
    density: Density,
) -> Stats {
    let mut st = Stats::EMPTY;
    for &r in ranges {
        st.merge(&sweep_bits(f, reference, r, density.stride()));
    }
    let mut extra = Stats::EMPTY;
    run_unary(&mut extra, f, reference, special);
    st.merge(&extra);
    st
}

/// The functions measured.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Function {
    /// `atan(x)`.
    Atan,
    /// `atan2(y, x)`.
    Atan2,
    /// `asin(x)`.
    Asin,
    /// `acos(x)`.
    Acos,
    /// `sin(x)` (from `sin_cos`).
    Sin,
    /// `cos(x)` (from `sin_cos`).
    Cos,
}

impl Function {
    /// Every function, in table order.
    pub const ALL: [Function; 6] = [
        Function::Atan,
        Function::Atan2,
        Function::Asin,
        Function::Acos,
        Function::Sin,
        Function::Cos,
    ];

    /// Lower-case name (`"atan2"`).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Function::Atan => "atan",
            Function::Atan2 => "atan2",
            Function::Asin => "asin",
            Function::Acos => "acos",
            Function::Sin => "sin",
            Function::Cos => "cos",
        }
    }

    /// Whether it takes two arguments.
    #[must_use]
    pub fn binary(self) -> bool {
        self == Function::Atan2
    }
}

/// An implementation of one [`Function`].
#[derive(Clone, Copy, Debug)]
pub enum Kernel {
    /// A one-argument function.
    Unary(Unary),
    /// `atan2(y, x)`.
    Binary(Binary),
}

/// `atan` at tier `T`, as a plain function.
#[must_use]
pub fn atan_of<T: Tier>(v: f32x8) -> f32x8 {
    approx::atan::<T>(v)
}
/// `asin` at tier `T`, as a plain function.
#[must_use]
pub fn asin_of<T: Tier>(v: f32x8) -> f32x8 {
    approx::asin::<T>(v)
}
/// `acos` at tier `T`, as a plain function.
#[must_use]
pub fn acos_of<T: Tier>(v: f32x8) -> f32x8 {
    approx::acos::<T>(v)
}
/// `sin` (from `sin_cos`) at tier `T`, as a plain function.
#[must_use]
pub fn sin_of<T: Tier>(v: f32x8) -> f32x8 {
    approx::sin_cos::<T>(v).0
}
/// `cos` (from `sin_cos`) at tier `T`, as a plain function.
#[must_use]
pub fn cos_of<T: Tier>(v: f32x8) -> f32x8 {
    approx::sin_cos::<T>(v).1
}

/// `f`'s implementation at tier `T` of `envmap_simd::approx`.
#[must_use]
pub fn tier_kernel<T: Tier>(f: Function) -> Kernel {
    match f {
        Function::Atan => Kernel::Unary(atan_of::<T>),
        Function::Atan2 => Kernel::Binary(approx::atan2::<T>),
        Function::Asin => Kernel::Unary(asin_of::<T>),
        Function::Acos => Kernel::Unary(acos_of::<T>),
        Function::Sin => Kernel::Unary(sin_of::<T>),
        Function::Cos => Kernel::Unary(cos_of::<T>),
    }
}

/// `wide`'s own `f32x8` implementation of `f`.
#[must_use]
pub fn wide_kernel(f: Function) -> Kernel {
    match f {
        Function::Atan => Kernel::Unary(f32x8::atan),
        Function::Atan2 => Kernel::Binary(f32x8::atan2),
        Function::Asin => Kernel::Unary(f32x8::asin),
        Function::Acos => Kernel::Unary(f32x8::acos),
        Function::Sin => Kernel::Unary(|v| v.sin_cos().0),
        Function::Cos => Kernel::Unary(|v| v.sin_cos().1),
    }
}

/// `std`'s scalar `f32` function applied lane by lane.
#[must_use]
pub fn std_kernel(f: Function) -> Kernel {
    match f {
        Function::Atan => Kernel::Unary(|v| f32x8::new(v.to_array().map(f32::atan))),
        Function::Atan2 => Kernel::Binary(|y, x| {
            let (y, x) = (y.to_array(), x.to_array());
            f32x8::new(core::array::from_fn(|i| y[i].atan2(x[i])))
        }),
        Function::Asin => Kernel::Unary(|v| f32x8::new(v.to_array().map(f32::asin))),
        Function::Acos => Kernel::Unary(|v| f32x8::new(v.to_array().map(f32::acos))),
        Function::Sin => Kernel::Unary(|v| f32x8::new(v.to_array().map(f32::sin))),
        Function::Cos => Kernel::Unary(|v| f32x8::new(v.to_array().map(f32::cos))),
    }
}

/// The worst errors of `kernel`, an implementation of `f`, over the sweep of
/// `f`'s domain at `density`.
///
/// Domains: `atan` every `f32` (both signs, `±∞`); `asin`, `acos` `[−1, 1]`;
/// `sin`, `cos` `[−`[`approx::SIN_COS_RANGE`]`, …]`; `atan2` as described in
/// the module documentation.
///
/// # Panics
///
/// If `kernel` takes a different number of arguments than `f`.
#[must_use]
pub fn function_stats(f: Function, kernel: Kernel, density: Density) -> Stats {
    match (f, kernel) {
        (Function::Atan2, Kernel::Binary(k)) => atan2_stats(k, density),
        (Function::Atan, Kernel::Unary(k)) => {
            // Odd function: all of x ≥ 0 (every finite f32 and +∞) and x ≤ 0.
            let mut special = neighbourhoods(&[1.0, 0.5, 2.0, 1e-20, 1e20, 16_777_216.0], 200);
            special.extend([
                f32::INFINITY,
                f32::NEG_INFINITY,
                f32::MAX,
                f32::MIN_POSITIVE,
            ]);
            unary_sweep(
                k,
                f64::atan,
                &[(0.0, f32::INFINITY, false), (0.0, f32::INFINITY, true)],
                &special,
                density,
            )
        }
        (Function::Asin | Function::Acos, Kernel::Unary(k)) => {
            let special = neighbourhoods(&[0.5, 1.0, 0.0, 1e-30, 0.25, 0.75, 0.99], 300);
            let special: Vec<f32> = special.into_iter().filter(|v| v.abs() <= 1.0).collect();
            let reference = if f == Function::Asin {
                f64::asin
            } else {
                f64::acos
            };
            unary_sweep(
                k,
                reference,
                &[(0.0, 1.0, false), (0.0, 1.0, true)],
                &special,
                density,
            )
        }
        (Function::Sin | Function::Cos, Kernel::Unary(k)) => {
            let reference = if f == Function::Sin {
                f64::sin
            } else {
                f64::cos
            };
            let r = approx::SIN_COS_RANGE;
            unary_sweep(
                k,
                reference,
                &[(0.0, r, false), (0.0, r, true)],
                &quarter_pi_neighbourhoods(density),
                density,
            )
        }
        _ => panic!("{}: kernel of the wrong arity", f.name()),
    }
}

/// Multiples of π/4 over the accurate range of `sin_cos`: the reduction
/// boundaries and the zeros, closely up to 2π, more loosely beyond.
fn quarter_pi_neighbourhoods(density: Density) -> Vec<f32> {
    let near: Vec<f64> = (0..=8)
        .map(|k| f64::from(k) * std::f64::consts::FRAC_PI_4)
        .collect();
    let far_step = if density == Density::Quick { 97 } else { 1 };
    let far: Vec<f64> = (9..8192)
        .step_by(far_step)
        .map(|k| f64::from(k) * std::f64::consts::FRAC_PI_4)
        .collect();
    let mut v = neighbourhoods(&near, 300);
    v.extend(neighbourhoods(&far, 20));
    v.retain(|x| x.abs() <= approx::SIN_COS_RANGE);
    v
}

/// A small deterministic generator (SplitMix64).
#[derive(Clone, Debug)]
pub struct SplitMix64(pub u64);

impl SplitMix64 {
    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// A uniform number in `[0, 1)` with 53 random bits.
    pub fn next_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1_u64 << 53) as f64
    }
}

fn atan2_stats(f: Binary, density: Density) -> Stats {
    let mut st = Stats::EMPTY;
    // Angles × radii, including denormal and huge radii.
    let angles = match density {
        Density::Quick => 2_000,
        Density::Dense => 20_000,
        Density::Exhaustive => 400_000,
    };
    let radii = [
        1e-45, 3e-44, 1e-41, 1e-39, 1.2e-38, 1e-30, 1e-10, 1e-3, 1.0, 7.0, 1e10, 1e30, 1e38, 3.4e38,
    ];
    let mut ps = Vec::new();
    for k in 0..angles {
        let theta =
            -std::f64::consts::PI + std::f64::consts::TAU * f64::from(k) / f64::from(angles);
        let (s, c) = theta.sin_cos();
        for &r in &radii {
            let p = ((r * s) as f32, (r * c) as f32);
            if p.0.is_finite() && p.1.is_finite() {
                ps.push(p);
            }
        }
    }
    // Unrelated magnitudes: every exponent pair, random mantissas and signs
    // (the ratio spans 2^±276, so it underflows and saturates).
    let mut rng = SplitMix64(0x5EED_A7A2);
    let (reps, step) = match density {
        Density::Quick => (1, 8),
        Density::Dense => (2, 2),
        Density::Exhaustive => (40, 1),
    };
    for ey in (-149..=127).step_by(step) {
        for ex in (-149..=127).step_by(step) {
            for _ in 0..reps {
                let m = |rng: &mut SplitMix64, e: i32| {
                    let v = (1.0 + rng.next_f64()) * 2f64.powi(e);
                    let v = if rng.next_u64() & 1 == 1 { -v } else { v };
                    v as f32
                };
                ps.push((m(&mut rng, ey), m(&mut rng, ex)));
            }
        }
    }
    let chunk = ps.len().div_ceil(64).max(8);
    let parts = Mutex::new(Stats::EMPTY);
    std::thread::scope(|s| {
        for piece in ps.chunks(chunk) {
            let parts = &parts;
            s.spawn(move || {
                let mut st = Stats::EMPTY;
                run_binary(&mut st, f, f64::atan2, piece);
                parts
                    .lock()
                    .unwrap_or_else(std::sync::PoisonError::into_inner)
                    .merge(&st);
            });
        }
    });
    st.merge(
        &parts
            .into_inner()
            .unwrap_or_else(std::sync::PoisonError::into_inner),
    );
    // The reduced argument z = min/max over every stride-th f32 in [0, 1],
    // in each of the octant reconstructions p, π/2 − p, π − p and π/2 + p
    // (the quotient is then exact, so the polynomial and the reconstruction
    // are tested on their own).
    let stride = u64::from(density.stride());
    let tail = parallel(0, u64::from(1.0_f32.to_bits()) + 1, |a, b| {
        let mut st = Stats::EMPTY;
        let mut buf = Vec::with_capacity(4096);
        let mut bits = a.div_ceil(stride) * stride;
        while bits < b {
            let t = f32::from_bits(bits as u32);
            buf.extend([(t, 1.0), (1.0, t), (t, -1.0), (1.0, -t)]);
            if buf.len() >= 4096 {
                run_binary(&mut st, f, f64::atan2, &buf);
                buf.clear();
            }
            bits += stride;
        }
        run_binary(&mut st, f, f64::atan2, &buf);
        st
    });
    st.merge(&tail);
    st
}
