//! Benchmarks, accuracy sweeps, timing and the minimax fitter.
//!
//! * [`accuracy`] and [`mapping_accuracy`]: worst-case errors of the
//!   approximations and of every mapping against `f64` references (the
//!   `envmap-tests` accuracy tests assert the tier bounds on them;
//!   `envmap-report` prints them).
//! * [`timing`]: median-of-passes timing on fresh random input.
//! * [`report`]: the rows `envmap-report` measures, and their checks.
//! * [`plot`]: the accuracy-versus-speed chart.
//! * [`tune`]: minimax fits at a range of degrees, measured.
//! * [`remez`]: the minimax fitter behind `envmap_simd::approx`'s coefficients.
//!
//! Two binaries: `envmap-report` (every function, mapping and tier timed and
//! swept in one run; `--quick`, `--json`, `--check`, `--plot`, `--tune`) and
//! `envmap-fit` (reprints the committed coefficients). Four criterion benches:
//! `approx`, `mappings`, `convert` and `render` (`cargo bench -p envmap-bench`,
//! with `RUSTFLAGS="-C target-cpu=native"` for full speed).
//!
//! The figures they produce, with their commands and dates, are in
//! `docs/performance.md` (speed) and `docs/accuracy.md` (errors, `--tune`).
#![forbid(unsafe_code)]

pub mod accuracy;
pub mod mapping_accuracy;
pub mod plot;
pub mod remez;
pub mod report;
pub mod timing;
pub mod tune;
