//! Refit every polynomial of `envmap_simd::approx` and print the Rust source
//! of `envmap-simd/src/approx/coeffs.rs` on stdout, the error of each fit on
//! stderr:
//!
//! ```text
//! cargo run --release -p envmap-bench --bin envmap-fit > envmap-simd/src/approx/coeffs.rs
//! ```
//!
//! With `--degrees`, print instead (on stdout) the minimax error each
//! polynomial reaches for a range of term counts, the table the tiers'
//! degrees were chosen from.
#![forbid(unsafe_code)]

use envmap_bench::remez::{approx_fits, fit_all, minimax, render_coeffs_rs, Problem};
use std::process::ExitCode;

fn degrees() -> ExitCode {
    println!(
        "{:<12} {:>5} {:>7}  minimax error (f64 coefficients)",
        "polynomial", "terms", "degree"
    );
    for spec in approx_fits() {
        for free in 1..=10 {
            let p = Problem {
                free,
                ..spec.problem
            };
            let degree = p.parity.power(p.fixed.len() + free - 1);
            match minimax(&p) {
                Ok(fit) => println!(
                    "{:<12} {:>5} {:>7}  {:.3e}",
                    spec.name,
                    p.fixed.len() + free,
                    degree,
                    fit.max_error
                ),
                Err(e) => println!(
                    "{:<12} {:>5} {:>7}  ({e})",
                    spec.name,
                    p.fixed.len() + free,
                    degree
                ),
            }
        }
    }
    ExitCode::SUCCESS
}

fn main() -> ExitCode {
    if std::env::args().any(|a| a == "--degrees") {
        return degrees();
    }
    let results = match fit_all() {
        Ok(r) => r,
        Err((name, e)) => {
            eprintln!("envmap-fit: fitting {name} failed: {e}");
            return ExitCode::FAILURE;
        }
    };
    eprintln!(
        "{:<12} {:>6} {:>8} {:>12} {:>12} {:>12}  at x",
        "polynomial", "weight", "degree", "f64 fit", "levelled", "f32 coeffs"
    );
    for r in &results {
        let p = &r.spec.problem;
        eprintln!(
            "{:<12} {:>6} {:>8} {:>12.3e} {:>12.3e} {:>12.3e}  {:.6}",
            r.spec.name,
            match p.weight {
                envmap_bench::remez::ErrorWeight::Absolute => "abs",
                envmap_bench::remez::ErrorWeight::Relative => "rel",
            },
            p.parity.power(p.fixed.len() + p.free - 1),
            r.fit.exact.max_error,
            r.fit.exact.levelled_error,
            r.fit.max_error,
            r.fit.max_error_at,
        );
    }
    print!("{}", render_coeffs_rs(&results));
    ExitCode::SUCCESS
}
