//! Benchmarks, accuracy sweeps and the minimax fitter.
#![forbid(unsafe_code)]

pub mod remez;
