//! Shared helpers for envmap's cross-crate tests.
#![forbid(unsafe_code)]
