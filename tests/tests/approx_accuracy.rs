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

use envmap_bench::accuracy::{
    acos_of, apply_binary, asin_of, atan_of, cos_of, function_stats, run_binary, sin_of,
    tier_kernel, Density, Function, Stats,
};
use envmap_simd::approx::{self, Exact, Fast, Fine, Tier};
use envmap_tests::SplitMix64;
use std::fmt;
use wide::f32x8;

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

/// The sweep of `f` at tier `T` (dense, or every `f32` with `ENVMAP_EXTENSIVE=1`).
fn stats<T: Tier>(f: Function) -> Stats {
    function_stats(f, tier_kernel::<T>(f), Density::from_env())
}

macro_rules! accuracy_tests {
    ($($name:ident: $function:expr, $label:literal, $binary:literal;)*) => {
        $(
            mod $name {
                use super::*;
                #[test]
                fn exact() {
                    check::<Exact>($label, $binary, stats::<Exact>($function));
                }
                #[test]
                fn fine() {
                    check::<Fine>($label, $binary, stats::<Fine>($function));
                }
                #[test]
                fn fast() {
                    check::<Fast>($label, $binary, stats::<Fast>($function));
                }
            }
        )*
    };
}

accuracy_tests! {
    atan: Function::Atan, "atan", false;
    atan2: Function::Atan2, "atan2", true;
    asin: Function::Asin, "asin", false;
    acos: Function::Acos, "acos", false;
    sin: Function::Sin, "sin", false;
    cos: Function::Cos, "cos", false;
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
        let got = apply_binary(approx::atan2::<T>, chunk);
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
    let mut rng = SplitMix64::new(0x0A11_1A7E ^ T::NAME.len() as u64);
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
                core::array::from_fn(|_| ((rng.next_f64() * 2.0 - 1.0) * scale) as f32);
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
        let ys: [f32; 8] = core::array::from_fn(|_| ((rng.next_f64() * 2.0 - 1.0) * 10.0) as f32);
        let xs: [f32; 8] = core::array::from_fn(|_| ((rng.next_f64() * 2.0 - 1.0) * 10.0) as f32);
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
    let mut rng = SplitMix64::new(0xB1C0_5EED);
    let mut xs: Vec<f32> = (0..20_000)
        .map(|_| {
            let lo = f64::from(approx::SIN_COS_RANGE).log2();
            let v = 2f64.powf(lo + rng.next_f64() * (127.9 - lo)) as f32;
            if rng.next_u64() & 1 == 1 {
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

/// `atan2_sqrt(y2, x, x²)` against `f64` `atan2(√y2, x)`, over angles ×
/// radii from 2⁻⁴⁰ to 2⁴⁰ and pairs of unrelated magnitudes from 2⁻⁴⁰ to
/// 2⁴⁰ (the function's domain), with `x²` rounded to `f32` as a caller
/// computes it; bounds as for the other functions.
fn atan2_sqrt_sweep<T: Tier>() {
    let mut pairs: Vec<(f32, f32)> = Vec::new();
    let angles = 20_000;
    for k in 0..=angles {
        // Polar angles from 0 to π: y = r·sin θ ≥ 0.
        let theta = std::f64::consts::PI * f64::from(k) / f64::from(angles);
        let (s, c) = theta.sin_cos();
        for e in [-40, -30, -20, -3, 0, 1, 7, 20, 30, 39] {
            let r = 2f64.powi(e) * 1.3;
            let (y, x) = (r * s, r * c);
            pairs.push(((y * y) as f32, x as f32));
        }
    }
    let mut rng = SplitMix64::new(0xA7A2_5077);
    for ey in -40..40 {
        for ex in -40..40 {
            let m = |rng: &mut SplitMix64, e: i32| (1.0 + rng.next_f64()) * 2f64.powi(e);
            let (y, x) = (m(&mut rng, ey), m(&mut rng, ex));
            let x = if rng.next_u64() & 1 == 1 { -x } else { x };
            pairs.push(((y * y) as f32, x as f32));
        }
    }
    let mut stats = Stats::EMPTY;
    run_binary(
        &mut stats,
        |y2, x| approx::atan2_sqrt::<T>(y2, x, x * x),
        |y2, x| y2.sqrt().atan2(x),
        &pairs,
    );
    check::<T>("atan2_sqrt", true, stats);
}

#[test]
fn atan2_sqrt_exact() {
    atan2_sqrt_sweep::<Exact>();
}
#[test]
fn atan2_sqrt_fine() {
    atan2_sqrt_sweep::<Fine>();
}
#[test]
fn atan2_sqrt_fast() {
    atan2_sqrt_sweep::<Fast>();
}
