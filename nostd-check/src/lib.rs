//! Proof that `envmap-core` and `envmap-simd` need no `std`.
//!
//! This crate is `#![no_std]` and defines its own `#[panic_handler]`. If any
//! crate in its dependency graph pulled in `std`, the build fails with
//! "duplicate lang item `panic_impl`". It is built as a `staticlib` so that
//! the whole graph is linked into one artefact and nothing can be left out.
#![no_std]
#![forbid(unsafe_code)]

extern crate envmap_core;
extern crate envmap_simd;

use core::panic::PanicInfo;

/// The panic handler that would clash with std's.
#[panic_handler]
fn panic(_info: &PanicInfo<'_>) -> ! {
    loop {}
}
