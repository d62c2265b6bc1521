//! The accuracy-versus-speed report: every approximation and every mapping
//! at every tier, timed in one process beside `std`, the scalar core,
//! `wide`'s own functions and a plain copy of the same bytes, with its worst
//! error against an `f64` reference.
//!
//! ```text
//! RUSTFLAGS="-C target-cpu=native" cargo run --release -p envmap-bench --bin envmap-report
//! cargo run --release -p envmap-bench --bin envmap-report -- --quick --json
//! cargo run --release -p envmap-bench --bin envmap-report -- --plot docs/accuracy-speed.png
//! cargo run --release -p envmap-bench --bin envmap-report -- --tune atan2 --degrees 3..15
//! cargo run --release -p envmap-bench --bin envmap-report -- --check report.jsonl
//! ```
#![forbid(unsafe_code)]

use std::io::Write as _;
use std::process::ExitCode;

use clap::Parser;
use envmap_bench::accuracy::Density;
use envmap_bench::report::{self, Settings};
use envmap_bench::{plot, tune};

/// Measure envmap's approximations and mappings: speed and worst error.
#[derive(Parser, Debug)]
#[command(name = "envmap-report", version)]
struct Args {
    /// Seconds instead of about a minute: fewer passes, sparse sweeps, small images.
    #[arg(long)]
    quick: bool,
    /// Sweep every f32 of each function's reduced domain and 16× more mapping
    /// points (about twenty minutes).
    #[arg(long)]
    exhaustive: bool,
    /// One JSON object per line instead of Markdown tables.
    #[arg(long)]
    json: bool,
    /// Also draw the accuracy-versus-speed chart into this PNG file.
    #[arg(long, value_name = "FILE.png")]
    plot: Option<String>,
    /// TrueType font for the chart's text (default: DejaVu Sans where installed).
    #[arg(long, value_name = "FILE.ttf")]
    font: Option<String>,
    /// Timed passes per measurement (default: 101, or 7 with --quick).
    #[arg(long)]
    passes: Option<usize>,
    /// Fit this function (atan, atan2, asin, acos) at each of --degrees and
    /// measure each polynomial instead of the report.
    #[arg(long, value_name = "FUNCTION")]
    tune: Option<String>,
    /// Degrees for --tune, as LO..HI (odd degrees in between are fitted).
    #[arg(long, default_value = "3..15")]
    degrees: String,
    /// Latlong width for --tune's error in texels.
    #[arg(long, default_value_t = 8192.0)]
    width: f64,
    /// Error budget for --tune, as a fraction of a texel at --width (1/64 = 0.015625).
    #[arg(long, default_value_t = 1.0 / 64.0)]
    texel_budget: f64,
    /// Check a JSON-lines report (from --json) for completeness and exit.
    #[arg(long, value_name = "FILE")]
    check: Option<String>,
}

fn parse_degrees(s: &str) -> Option<std::ops::RangeInclusive<i32>> {
    let (a, b) = s.split_once("..")?;
    let b = b.trim_start_matches('=');
    Some(a.trim().parse().ok()?..=b.trim().parse().ok()?)
}

fn run_tune(args: &Args, function: &str, density: Density, passes: usize) -> ExitCode {
    let Some(degrees) = parse_degrees(&args.degrees) else {
        eprintln!(
            "envmap-report: --degrees wants LO..HI, got {}",
            args.degrees
        );
        return ExitCode::from(2);
    };
    let rows = match tune::tune(function, degrees, density, passes) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("envmap-report: {e}");
            return ExitCode::from(2);
        }
    };
    let w = args.width;
    println!(
        "| degree | fit error (reduced) | max abs err (rad) | max ULP | texels at {w} wide | ns per value |"
    );
    println!("| ---: | ---: | ---: | ---: | ---: | ---: |");
    for r in &rows {
        println!(
            "| {} | {:.2e} | {:.2e} | {} | {:.5} | {:.3} |",
            r.degree,
            r.fit_error,
            r.max_abs_err,
            r.max_ulp,
            tune::texels(r.max_abs_err, w),
            r.ns
        );
    }
    let budget = args.texel_budget;
    match rows
        .iter()
        .find(|r| tune::texels(r.max_abs_err, w) <= budget)
    {
        Some(r) => println!(
            "\n{function} to {budget} texel at {w} wide: degree {}, {:.3} ns per value \
             (worst {:.2e} rad = {:.5} texel)",
            r.degree,
            r.ns,
            r.max_abs_err,
            tune::texels(r.max_abs_err, w)
        ),
        None => {
            println!("\n{function} to {budget} texel at {w} wide: no degree in range is enough")
        }
    }
    ExitCode::SUCCESS
}

fn main() -> ExitCode {
    let args = Args::parse();
    if let Some(path) = &args.check {
        let text = match std::fs::read_to_string(path) {
            Ok(t) => t,
            Err(e) => {
                eprintln!("envmap-report: {path}: {e}");
                return ExitCode::FAILURE;
            }
        };
        return match report::check_json_lines(&text) {
            Ok(n) => {
                println!("{path}: {n} rows, every function, mapping and tier present");
                ExitCode::SUCCESS
            }
            Err(e) => {
                eprintln!("envmap-report: {path}: {e}");
                ExitCode::FAILURE
            }
        };
    }
    let mut s = if args.quick {
        Settings::quick()
    } else {
        Settings::full()
    };
    if args.exhaustive {
        s.density = Density::Exhaustive;
        s.mapping_points = 1 << 21;
    }
    if let Some(p) = args.passes {
        s.passes = p.max(1);
    }
    if let Some(f) = &args.tune {
        return run_tune(&args, f, s.density, s.passes);
    }
    let mut rows = report::functions(&s);
    rows.extend(report::mappings(&s));
    rows.extend(report::convert_and_render(&s));
    let mut out = std::io::stdout().lock();
    let written = if args.json {
        rows.iter()
            .try_for_each(|r| writeln!(out, "{}", r.to_json()))
    } else {
        write!(out, "{}", report::markdown(&rows))
    };
    if let Err(e) = written.and_then(|()| out.flush()) {
        eprintln!("envmap-report: writing the report: {e}");
        return ExitCode::FAILURE;
    }
    if let Some(path) = &args.plot {
        let text = plot::register_font(args.font.as_deref());
        if !text {
            eprintln!("envmap-report: no font found (--font FILE.ttf); drawing without text");
        }
        if let Err(e) = plot::draw(path, &rows, text) {
            eprintln!("envmap-report: {path}: {e}");
            return ExitCode::FAILURE;
        }
    }
    ExitCode::SUCCESS
}
