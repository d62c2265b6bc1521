//! The committed coefficients of `envmap_simd::approx` are the fitter's.
//!
//! Reruns the Remez fitter of `envmap-bench` for every polynomial and checks
//! that `envmap-simd/src/approx/coeffs.rs` holds exactly those polynomials,
//! each coefficient within one `f32` ULP of the refit (the slack is for `f64`
//! library functions that differ in the last bit between platforms). To
//! change a coefficient, change the fit and regenerate the file:
//!
//! ```text
//! cargo run --release -p envmap-bench --bin envmap-fit > envmap-simd/src/approx/coeffs.rs
//! ```

use envmap_bench::remez::{approx_fits, fit_all, minimax, ErrorWeight, Parity, Problem};
use envmap_simd::approx::coeffs;

/// Distance in representable `f32` values (`±0` both 0).
fn ulps(a: f32, b: f32) -> u64 {
    let ord = |v: f32| {
        let bits = v.to_bits();
        let m = i64::from(bits & 0x7FFF_FFFF);
        if bits >> 31 == 1 {
            -m
        } else {
            m
        }
    };
    (ord(a) - ord(b)).unsigned_abs()
}

#[test]
fn committed_coefficients_are_the_refit_ones() {
    let refit = fit_all().unwrap_or_else(|(name, e)| panic!("fitting {name}: {e}"));
    let committed: Vec<&str> = coeffs::ALL.iter().map(|(n, _)| *n).collect();
    let fitted: Vec<&str> = refit.iter().map(|r| r.spec.name).collect();
    assert_eq!(
        committed, fitted,
        "coeffs.rs lists other polynomials than the fitter"
    );
    for (r, (name, stored)) in refit.iter().zip(coeffs::ALL) {
        assert_eq!(
            stored.len(),
            r.fit.coeffs.len(),
            "{name}: {} coefficients committed, the fit has {}",
            stored.len(),
            r.fit.coeffs.len()
        );
        for (k, (&c, &f)) in stored.iter().zip(&r.fit.coeffs).enumerate() {
            assert!(
                ulps(c, f) <= 1,
                "{name}[{k}]: committed {c:e} ({:#010x}), refit {f:e} ({:#010x})",
                c.to_bits(),
                f.to_bits()
            );
        }
        println!(
            "{name}: {} coefficients match; error {:.3e} (f64 fit {:.3e})",
            stored.len(),
            r.fit.max_error,
            r.fit.exact.max_error
        );
    }
}

#[test]
fn every_fit_equioscillates() {
    for spec in approx_fits() {
        let fit = minimax(&spec.problem).unwrap();
        // The minimax property: the levelled error is the maximum error.
        let gap = (fit.max_error - fit.levelled_error).abs() / fit.max_error;
        assert!(
            gap < 1e-4,
            "{}: levelled {:e} but max {:e}",
            spec.name,
            fit.levelled_error,
            fit.max_error
        );
    }
}

#[test]
fn the_fitter_finds_known_minimax_polynomials() {
    // The best constant for x² on [1, 3] is the midrange 5, error 4.
    fn square(x: f64) -> f64 {
        x * x
    }
    let p = Problem {
        f: square,
        lo: 1.0,
        hi: 3.0,
        parity: Parity::Even,
        fixed: &[],
        free: 1,
        weight: ErrorWeight::Absolute,
    };
    let fit = minimax(&p).unwrap();
    assert!((fit.coeffs[0] - 5.0).abs() < 1e-9, "{:?}", fit.coeffs);
    assert!((fit.max_error - 4.0).abs() < 1e-9, "{}", fit.max_error);

    // Chebyshev: the best line for u² on [0, 1] is u − 1/8, error 1/8; as an
    // even polynomial in x that is x⁴ ≈ −1/8 + x² on [0, 1].
    fn quartic(x: f64) -> f64 {
        x.powi(4)
    }
    let p = Problem {
        f: quartic,
        lo: 0.0,
        hi: 1.0,
        free: 2,
        ..p
    };
    let fit = minimax(&p).unwrap();
    assert!((fit.coeffs[0] + 0.125).abs() < 1e-8, "{:?}", fit.coeffs);
    assert!((fit.coeffs[1] - 1.0).abs() < 1e-8, "{:?}", fit.coeffs);
    assert!((fit.max_error - 0.125).abs() < 1e-8, "{}", fit.max_error);
}
