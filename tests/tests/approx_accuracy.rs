//! Accuracy of `envmap_simd::approx` against the `f64` functions rounded to
//! `f32`, for every function and tier.
//!
//! By default a dense sweep (every 1021st `f32` of each reduced domain plus
//! the neighbourhoods of the reduction boundaries and of the zeros of the
//! results); with `ENVMAP_EXTENSIVE=1` every `f32` of each reduced domain.
//! Each sweep prints its maximum absolute error, its maximum ULP error and
//! the arguments where they occur:
//!
//! ```text
//! cargo test -p envmap-tests --release --test approx_accuracy -- --nocapture
//! ENVMAP_EXTENSIVE=1 cargo test -p envmap-tests --release --test approx_accuracy -- --nocapture
//! ```
//!
//! Bounds asserted: exact tier at most 2 ULP, fine tier at most 2·10⁻⁶ rad,
//! fast tier at most 10⁻⁴ rad (absolute).

use envmap_simd::approx::{self, Exact, Fast, Fine, Tier};
use std::fmt;
use std::sync::Mutex;
use wide::f32x8;

fn extensive() -> bool {
    std::env::var("ENVMAP_EXTENSIVE").is_ok_and(|v| v == "1")
}

/// Stride through the bit patterns of a domain in the default run.
const STRIDE: u32 = 1021;

/// Position of `v` on the line of representable `f32` (`±0` both 0).
fn ordinal(v: f32) -> i64 {
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
fn ulp_distance(got: f32, reference: f64) -> u64 {
    let r = reference as f32;
    match (got.is_nan(), r.is_nan()) {
        (true, true) => 0,
        (false, false) => (ordinal(got) - ordinal(r)).unsigned_abs(),
        _ => u64::MAX,
    }
}

/// Error in units of the `f32` spacing at the (unrounded) reference.
fn ulp_fraction(got: f32, reference: f64) -> f64 {
    let e = ((reference.abs().to_bits() >> 52) as i32 - 1023).max(-126);
    abs_error(got, reference) / 2f64.powi(e - 23)
}

fn abs_error(got: f32, reference: f64) -> f64 {
    match (got.is_nan(), reference.is_nan()) {
        (true, true) => 0.0,
        (false, false) => (f64::from(got) - reference).abs(),
        _ => f64::INFINITY,
    }
}

/// Worst errors of one sweep and where they occur.
#[derive(Clone, Copy, Debug)]
struct Stats {
    max_abs: f64,
    abs_at: (f32, f32),
    max_ulp: u64,
    ulp_at: (f32, f32),
    max_ulp_fraction: f64,
    count: u64,
}

impl Stats {
    const EMPTY: Stats = Stats {
        max_abs: 0.0,
        abs_at: (0.0, 0.0),
        max_ulp: 0,
        ulp_at: (0.0, 0.0),
        max_ulp_fraction: 0.0,
        count: 0,
    };

    fn add(&mut self, arg: (f32, f32), got: f32, reference: f64) {
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

    fn merge(&mut self, o: &Stats) {
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

/// A sweep's result, labelled for printing.
struct Report {
    function: &'static str,
    tier: &'static str,
    binary: bool,
    stats: Stats,
}

impl fmt::Display for Report {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let s = &self.stats;
        let at = |a: (f32, f32)| {
            if self.binary {
                format!("(y, x) = ({:e}, {:e})", a.0, a.1)
            } else {
                format!("x = {:e}", a.0)
            }
        };
        write!(
            f,
            "{:<6} {:<5} max abs {:.3e} at {:<42} max ULP {:>5} at {:<42} \
             (unrounded {:.2}; {} points)",
            self.function,
            self.tier,
            s.max_abs,
            at(s.abs_at),
            s.max_ulp,
            at(s.ulp_at),
            s.max_ulp_fraction,
            s.count
        )
    }
}

/// Assert the tier's bound on a sweep (and print it).
fn check<T: Tier>(function: &'static str, binary: bool, stats: Stats) {
    let report = Report {
        function,
        tier: T::NAME,
        binary,
        stats,
    };
    println!("{report}");
    assert!(stats.count > 0, "{function}: empty sweep");
    match T::NAME {
        "exact" => assert!(stats.max_ulp <= 2, "{report}: more than 2 ULP"),
        "fine" => assert!(stats.max_abs <= 2e-6, "{report}: more than 2e-6 rad"),
        "fast" => assert!(stats.max_abs <= 1e-4, "{report}: more than 1e-4 rad"),
        other => panic!("unknown tier {other}"),
    }
}

type Unary = fn(f32x8) -> f32x8;
type Binary = fn(f32x8, f32x8) -> f32x8;

/// Evaluate `f` on `xs` (any length, the last batch padded) and add the
/// errors against `reference` to `stats`.
fn run_unary(stats: &mut Stats, f: Unary, reference: fn(f64) -> f64, xs: &[f32]) {
    for chunk in xs.chunks(8) {
        let mut lanes = [0.0_f32; 8];
        lanes[..chunk.len()].copy_from_slice(chunk);
        let got = f(f32x8::new(lanes)).to_array();
        for (i, &x) in chunk.iter().enumerate() {
            stats.add((x, 0.0), got[i], reference(f64::from(x)));
        }
    }
}

fn run_binary(stats: &mut Stats, f: Binary, reference: fn(f64, f64) -> f64, ps: &[(f32, f32)]) {
    for chunk in ps.chunks(8) {
        let mut ys = [0.0_f32; 8];
        let mut xs = [0.0_f32; 8];
        for (i, &(y, x)) in chunk.iter().enumerate() {
            ys[i] = y;
            xs[i] = x;
        }
        let got = f(f32x8::new(ys), f32x8::new(xs)).to_array();
        for (i, &(y, x)) in chunk.iter().enumerate() {
            stats.add((y, x), got[i], reference(f64::from(y), f64::from(x)));
        }
    }
}

/// Run `work(lo, hi)` over `[lo, hi)` split across threads, merging stats.
fn parallel(lo: u64, hi: u64, work: impl Fn(u64, u64) -> Stats + Sync) -> Stats {
    let threads = std::thread::available_parallelism().map_or(2, |n| n.get()) as u64;
    let pieces = threads * 8;
    let total = Mutex::new(Stats::EMPTY);
    let next = Mutex::new(0_u64);
    std::thread::scope(|s| {
        for _ in 0..threads {
            s.spawn(|| loop {
                let k = {
                    let mut n = next.lock().unwrap();
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
                total.lock().unwrap().merge(&st);
            });
        }
    });
    total.into_inner().unwrap()
}

/// Every (or every `STRIDE`th) `f32` of `[lo, hi]` (both non-negative), with
/// the sign bit set if `negative`.
fn sweep_bits(f: Unary, reference: fn(f64) -> f64, lo: f32, hi: f32, negative: bool) -> Stats {
    assert!(lo >= 0.0 && hi >= lo);
    let stride = if extensive() { 1 } else { STRIDE };
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
fn neighbourhoods(centres: &[f64], k: i32) -> Vec<f32> {
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
) -> Stats {
    let mut st = Stats::EMPTY;
    for &(lo, hi, neg) in ranges {
        st.merge(&sweep_bits(f, reference, lo, hi, neg));
    }
    let mut extra = Stats::EMPTY;
    run_unary(&mut extra, f, reference, special);
    st.merge(&extra);
    st
}

fn atan_of<T: Tier>(v: f32x8) -> f32x8 {
    approx::atan::<T>(v)
}
fn asin_of<T: Tier>(v: f32x8) -> f32x8 {
    approx::asin::<T>(v)
}
fn acos_of<T: Tier>(v: f32x8) -> f32x8 {
    approx::acos::<T>(v)
}
fn sin_of<T: Tier>(v: f32x8) -> f32x8 {
    approx::sin_cos::<T>(v).0
}
fn cos_of<T: Tier>(v: f32x8) -> f32x8 {
    approx::sin_cos::<T>(v).1
}
fn atan2_of<T: Tier>(y: f32x8, x: f32x8) -> f32x8 {
    approx::atan2::<T>(y, x)
}

fn atan_stats<T: Tier>() -> Stats {
    // Odd function: all of x ≥ 0 (every finite f32 and +∞), the negative half
    // less densely in the default run (the sign is restored exactly).
    let mut special = neighbourhoods(&[1.0, 0.5, 2.0, 1e-20, 1e20, 16777216.0], 200);
    special.extend([
        f32::INFINITY,
        f32::NEG_INFINITY,
        f32::MAX,
        f32::MIN_POSITIVE,
    ]);
    unary_sweep(
        atan_of::<T>,
        f64::atan,
        &[(0.0, f32::INFINITY, false), (0.0, f32::INFINITY, true)],
        &special,
    )
}

fn asin_stats<T: Tier>() -> Stats {
    let special = neighbourhoods(&[0.5, 1.0, 0.0, 1e-30, 0.25, 0.75, 0.99], 300);
    let special: Vec<f32> = special.into_iter().filter(|v| v.abs() <= 1.0).collect();
    unary_sweep(
        asin_of::<T>,
        f64::asin,
        &[(0.0, 1.0, false), (0.0, 1.0, true)],
        &special,
    )
}

fn acos_stats<T: Tier>() -> Stats {
    let special = neighbourhoods(&[0.5, 1.0, 0.0, 1e-30, 0.25, 0.75, 0.99], 300);
    let special: Vec<f32> = special.into_iter().filter(|v| v.abs() <= 1.0).collect();
    unary_sweep(
        acos_of::<T>,
        f64::acos,
        &[(0.0, 1.0, false), (0.0, 1.0, true)],
        &special,
    )
}

/// Multiples of π/4 over the accurate range of `sin_cos`: the reduction
/// boundaries and the zeros, closely up to 2π, more loosely beyond.
fn quarter_pi_neighbourhoods() -> Vec<f32> {
    let near: Vec<f64> = (0..=8)
        .map(|k| f64::from(k) * std::f64::consts::FRAC_PI_4)
        .collect();
    let far: Vec<f64> = (9..8192)
        .map(|k| f64::from(k) * std::f64::consts::FRAC_PI_4)
        .collect();
    let mut v = neighbourhoods(&near, 300);
    v.extend(neighbourhoods(&far, 20));
    v.retain(|x| x.abs() <= approx::SIN_COS_RANGE);
    v
}

fn sin_cos_ranges() -> [(f32, f32, bool); 2] {
    [
        (0.0, approx::SIN_COS_RANGE, false),
        (0.0, approx::SIN_COS_RANGE, true),
    ]
}

fn sin_stats<T: Tier>() -> Stats {
    unary_sweep(
        sin_of::<T>,
        f64::sin,
        &sin_cos_ranges(),
        &quarter_pi_neighbourhoods(),
    )
}

fn cos_stats<T: Tier>() -> Stats {
    unary_sweep(
        cos_of::<T>,
        f64::cos,
        &sin_cos_ranges(),
        &quarter_pi_neighbourhoods(),
    )
}

/// A small deterministic generator (SplitMix64).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1_u64 << 53) as f64
    }
}

fn atan2_stats<T: Tier>() -> Stats {
    let f = atan2_of::<T>;
    let mut st = Stats::EMPTY;
    let dense = !extensive();
    // Angles × radii, including denormal and huge radii.
    let angles = if dense { 20_000 } else { 400_000 };
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
    let mut rng = Rng(0x5EED_A7A2);
    let reps = if dense { 2 } else { 40 };
    for ey in (-149..=127).step_by(if dense { 2 } else { 1 }) {
        for ex in (-149..=127).step_by(if dense { 2 } else { 1 }) {
            for _ in 0..reps {
                let m = |rng: &mut Rng, e: i32| {
                    let v = (1.0 + rng.unit()) * 2f64.powi(e);
                    let v = if rng.next() & 1 == 1 { -v } else { v };
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
                parts.lock().unwrap().merge(&st);
            });
        }
    });
    st.merge(&parts.into_inner().unwrap());
    // The reduced argument z = min/max over every (or every STRIDE-th) f32 in
    // [0, 1], in each of the octant reconstructions p, π/2 − p, π − p and
    // π/2 + p (the quotient is then exact, so the polynomial and the
    // reconstruction are tested on their own).
    let stride = if extensive() { 1 } else { STRIDE };
    let tail = parallel(0, u64::from(1.0_f32.to_bits()) + 1, |a, b| {
        let mut st = Stats::EMPTY;
        let mut buf = Vec::with_capacity(4096);
        let mut bits = a.div_ceil(u64::from(stride)) * u64::from(stride);
        while bits < b {
            let t = f32::from_bits(bits as u32);
            buf.extend([(t, 1.0), (1.0, t), (t, -1.0), (1.0, -t)]);
            if buf.len() >= 4096 {
                run_binary(&mut st, f, f64::atan2, &buf);
                buf.clear();
            }
            bits += u64::from(stride);
        }
        run_binary(&mut st, f, f64::atan2, &buf);
        st
    });
    st.merge(&tail);
    st
}

macro_rules! accuracy_tests {
    ($($name:ident: $stats:ident, $label:literal, $binary:literal;)*) => {
        $(
            mod $name {
                use super::*;
                #[test]
                fn exact() {
                    check::<Exact>($label, $binary, $stats::<Exact>());
                }
                #[test]
                fn fine() {
                    check::<Fine>($label, $binary, $stats::<Fine>());
                }
                #[test]
                fn fast() {
                    check::<Fast>($label, $binary, $stats::<Fast>());
                }
            }
        )*
    };
}

accuracy_tests! {
    atan: atan_stats, "atan", false;
    atan2: atan2_stats, "atan2", true;
    asin: asin_stats, "asin", false;
    acos: acos_stats, "acos", false;
    sin: sin_stats, "sin", false;
    cos: cos_stats, "cos", false;
}

/// Same value bit for bit, or both NaN.
fn same(a: f32, b: f32) -> bool {
    (a.is_nan() && b.is_nan()) || a.to_bits() == b.to_bits()
}

/// Apply `f` to `xs` eight at a time and compare each lane with `want`.
fn expect_unary(what: &str, tier: &str, f: Unary, want: fn(f32) -> f32, xs: &[f32]) {
    for chunk in xs.chunks(8) {
        let mut lanes = [0.0_f32; 8];
        lanes[..chunk.len()].copy_from_slice(chunk);
        let got = f(f32x8::new(lanes)).to_array();
        for (i, &x) in chunk.iter().enumerate() {
            assert!(
                same(got[i], want(x)),
                "{what}::<{tier}>({x:e}) = {:e} ({:#010x}), std gives {:e} ({:#010x})",
                got[i],
                got[i].to_bits(),
                want(x),
                want(x).to_bits()
            );
        }
    }
}

fn special_values<T: Tier>() {
    let tier = T::NAME;
    let nan_neg = f32::from_bits(0xFFC0_0000);
    let nan_payload = f32::from_bits(0x7FC1_2345);
    let zeros_infs_nans = [
        0.0,
        -0.0,
        f32::INFINITY,
        f32::NEG_INFINITY,
        f32::NAN,
        nan_neg,
        nan_payload,
    ];
    expect_unary("atan", tier, atan_of::<T>, f32::atan, &zeros_infs_nans);
    let unit = [
        0.0,
        -0.0,
        1.0,
        -1.0,
        1.0_f32.next_up(),
        (-1.0_f32).next_down(),
        2.0,
        -1e30,
        f32::INFINITY,
        f32::NEG_INFINITY,
        f32::NAN,
        nan_neg,
    ];
    expect_unary("asin", tier, asin_of::<T>, f32::asin, &unit);
    expect_unary("acos", tier, acos_of::<T>, f32::acos, &unit);
    expect_unary("sin", tier, sin_of::<T>, f32::sin, &zeros_infs_nans);
    expect_unary("cos", tier, cos_of::<T>, f32::cos, &zeros_infs_nans);
    // atan2: every pair in which either argument is ±0, ±∞ or NaN.
    let specials = [
        0.0,
        -0.0,
        f32::INFINITY,
        f32::NEG_INFINITY,
        f32::NAN,
        nan_neg,
    ];
    let finite = [
        1.0,
        -1.0,
        3.5e-39,
        -3.5e-39,
        2.5e-45,
        f32::MAX,
        -f32::MAX,
        -7.25,
    ];
    let mut pairs = Vec::new();
    for &a in &specials {
        for &b in specials.iter().chain(&finite) {
            pairs.push((a, b));
            pairs.push((b, a));
        }
    }
    for chunk in pairs.chunks(8) {
        let mut ys = [0.0_f32; 8];
        let mut xs = [0.0_f32; 8];
        for (i, &(y, x)) in chunk.iter().enumerate() {
            ys[i] = y;
            xs[i] = x;
        }
        let got = approx::atan2::<T>(f32x8::new(ys), f32x8::new(xs)).to_array();
        for (i, &(y, x)) in chunk.iter().enumerate() {
            let want = y.atan2(x);
            assert!(
                same(got[i], want),
                "atan2::<{tier}>({y:e}, {x:e}) = {:e}, std gives {want:e}",
                got[i]
            );
        }
    }
}

#[test]
fn special_values_exact() {
    special_values::<Exact>();
}

#[test]
fn special_values_fine() {
    special_values::<Fine>();
}

#[test]
fn special_values_fast() {
    special_values::<Fast>();
}

/// Tiny arguments keep their sign (and, for the exact tier, their value).
fn signed_zeros_and_tiny<T: Tier>() {
    for x in [0.0_f32, 1e-45, 1e-40, 1e-30, 1e-10] {
        for (what, f) in [
            ("atan", atan_of::<T> as Unary),
            ("asin", asin_of::<T>),
            ("sin", sin_of::<T>),
        ] {
            let pos = f(f32x8::splat(x)).to_array()[0];
            let neg = f(f32x8::splat(-x)).to_array()[0];
            assert!(
                pos.is_sign_positive() && neg.is_sign_negative(),
                "{what}(±{x:e})"
            );
            assert_eq!(
                pos.to_bits() | 0x8000_0000,
                neg.to_bits(),
                "{what}(±{x:e}) not odd"
            );
            if T::NAME == "exact" {
                assert_eq!(pos, x, "{what}::<exact>({x:e})");
            }
        }
        // atan2(±tiny, +1) = ±tiny-ish, atan2(±tiny, −1) = ±π.
        let y = f32x8::new([x, -x, x, -x, x, -x, x, -x]);
        let xs = f32x8::new([1.0, 1.0, -1.0, -1.0, 0.0, 0.0, -0.0, -0.0]);
        let got = approx::atan2::<T>(y, xs).to_array();
        for (i, g) in got.iter().enumerate() {
            assert_eq!(
                g.is_sign_negative(),
                i % 2 == 1,
                "atan2 sign, lane {i}: {g:e}"
            );
        }
        assert!(got[2] > 3.0 && got[3] < -3.0, "{got:?}");
    }
}

#[test]
fn signed_zeros_and_tiny_exact() {
    signed_zeros_and_tiny::<Exact>();
}

#[test]
fn signed_zeros_and_tiny_fine() {
    signed_zeros_and_tiny::<Fine>();
}

#[test]
fn signed_zeros_and_tiny_fast() {
    signed_zeros_and_tiny::<Fast>();
}

/// A NaN (or ±∞) in one lane changes nothing in the other seven, bit for bit.
fn nan_lane_isolation<T: Tier>() {
    let mut rng = Rng(0x0A11_1A7E ^ T::NAME.len() as u64);
    let poisons = [
        f32::NAN,
        f32::from_bits(0xFFC0_0000),
        f32::from_bits(0x7FA0_0001), // signalling pattern
        f32::INFINITY,
        f32::NEG_INFINITY,
    ];
    let unary: [(&str, Unary, f64); 5] = [
        ("atan", atan_of::<T>, 100.0),
        ("asin", asin_of::<T>, 1.0),
        ("acos", acos_of::<T>, 1.0),
        ("sin", sin_of::<T>, 7.0),
        ("cos", cos_of::<T>, 7.0),
    ];
    for _ in 0..50 {
        for &(what, f, scale) in &unary {
            let base: [f32; 8] =
                core::array::from_fn(|_| ((rng.unit() * 2.0 - 1.0) * scale) as f32);
            let clean = f(f32x8::new(base)).to_array();
            for lane in 0..8 {
                for &p in &poisons {
                    let mut v = base;
                    v[lane] = p;
                    let got = f(f32x8::new(v)).to_array();
                    for j in (0..8).filter(|&j| j != lane) {
                        assert_eq!(got[j].to_bits(), clean[j].to_bits(), "{what}: lane {j}");
                    }
                    if p.is_nan() {
                        assert!(got[lane].is_nan(), "{what}: NaN lane gave {}", got[lane]);
                    }
                }
            }
        }
        let ys: [f32; 8] = core::array::from_fn(|_| ((rng.unit() * 2.0 - 1.0) * 10.0) as f32);
        let xs: [f32; 8] = core::array::from_fn(|_| ((rng.unit() * 2.0 - 1.0) * 10.0) as f32);
        let clean = approx::atan2::<T>(f32x8::new(ys), f32x8::new(xs)).to_array();
        for lane in 0..8 {
            for &p in &poisons {
                for poison_y in [true, false] {
                    let (mut y, mut x) = (ys, xs);
                    if poison_y {
                        y[lane] = p;
                    } else {
                        x[lane] = p;
                    }
                    let got = approx::atan2::<T>(f32x8::new(y), f32x8::new(x)).to_array();
                    for j in (0..8).filter(|&j| j != lane) {
                        assert_eq!(got[j].to_bits(), clean[j].to_bits(), "atan2: lane {j}");
                    }
                    if p.is_nan() {
                        assert!(got[lane].is_nan(), "atan2: NaN lane gave {}", got[lane]);
                    }
                }
            }
        }
    }
}

#[test]
fn nan_lane_isolation_exact() {
    nan_lane_isolation::<Exact>();
}

#[test]
fn nan_lane_isolation_fine() {
    nan_lane_isolation::<Fine>();
}

#[test]
fn nan_lane_isolation_fast() {
    nan_lane_isolation::<Fast>();
}

/// Past the accurate range `sin_cos` still returns a point within the
/// polynomials' error of the unit circle (the angle is no longer right).
fn beyond_range<T: Tier>() {
    let mut rng = Rng(0xB1C0_5EED);
    let mut xs: Vec<f32> = (0..20_000)
        .map(|_| {
            let lo = f64::from(approx::SIN_COS_RANGE).log2();
            let v = 2f64.powf(lo + rng.unit() * (127.9 - lo)) as f32;
            if rng.next() & 1 == 1 {
                -v
            } else {
                v
            }
        })
        .collect();
    xs.extend([f32::MAX, -f32::MAX, 8_388_608.0, 16_777_216.0, 1e30]);
    for chunk in xs.chunks(8) {
        let mut lanes = [0.0_f32; 8];
        lanes[..chunk.len()].copy_from_slice(chunk);
        let (s, c) = approx::sin_cos::<T>(f32x8::new(lanes));
        for (i, x) in chunk.iter().enumerate() {
            let (s, c) = (s.to_array()[i], c.to_array()[i]);
            let norm = f64::from(s).hypot(f64::from(c));
            assert!(
                s.abs() <= 1.0 && c.abs() <= 1.0 && (norm - 1.0).abs() < 5e-5,
                "sin_cos::<{}>({x:e}) = ({s}, {c})",
                T::NAME,
            );
        }
    }
}

#[test]
fn beyond_range_exact() {
    beyond_range::<Exact>();
}

#[test]
fn beyond_range_fine() {
    beyond_range::<Fine>();
}

#[test]
fn beyond_range_fast() {
    beyond_range::<Fast>();
}

#[test]
fn tier_names() {
    assert_eq!(
        [Exact::NAME, Fine::NAME, Fast::NAME],
        ["exact", "fine", "fast"]
    );
}
