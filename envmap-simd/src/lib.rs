//! envmap's mappings eight directions at a time.
#![no_std]
#![forbid(unsafe_code)]

pub mod approx;
