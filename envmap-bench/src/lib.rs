//! Benchmarks, accuracy sweeps and the minimax fitter.
//!
//! * [`accuracy`] and [`mapping_accuracy`]: worst-case errors of the
//!   approximations and of every mapping against `f64` references (the
//!   `envmap-tests` accuracy tests assert the tier bounds on them).
//! * [`remez`]: the minimax fitter behind `envmap_simd::approx`'s coefficients.
#![forbid(unsafe_code)]

pub mod accuracy;
pub mod mapping_accuracy;
pub mod remez;
