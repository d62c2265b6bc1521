//! Proof that `envmap-core` and `envmap-simd` need no `std`, and the two
//! used as a `no_std` engine uses them.
//!
//! This crate is `#![no_std]` and defines its own `#[panic_handler]`. If any
//! crate in its dependency graph pulled in `std`, the build fails with
//! "duplicate lang item `panic_impl`". It is built as a `staticlib` so that
//! the whole graph is linked into one artefact and nothing can be left out;
//! the public functions below are compiled into it (a staticlib keeps every
//! public item), so the scalar and batch APIs are proven usable without
//! `std`, not only linkable.
#![no_std]
#![forbid(unsafe_code)]

use core::panic::PanicInfo;

use envmap_core::glam::Vec3;
use envmap_core::{AnyMapping, ChartUv, LatLong};
use envmap_simd::{forward_slice, inverse_slice, Fine};

/// The panic handler that would clash with std's.
#[panic_handler]
fn panic(_info: &PanicInfo<'_>) -> ! {
    loop {}
}

/// The texel of a `size`² cube face that direction (x, y, z) reads, as
/// (face, column, row), with the core's scalar mapping; `None` for a zero
/// or non-finite direction.
pub fn cube_texel(x: f32, y: f32, z: f32, size: u32) -> Option<(u32, u32, u32)> {
    let c = AnyMapping::Cube.forward(Vec3::new(x, y, z))?;
    let at = |t: f32| ((t * size as f32) as u32).min(size.saturating_sub(1));
    Some((c.chart, at(c.u), at(c.v)))
}

/// Latlong coordinates of a batch of directions, eight at a time at the
/// `Fine` tier, into the caller's buffer (no allocation); the count mapped.
pub fn latlong_batch(dirs: &[Vec3], out: &mut [ChartUv]) -> usize {
    forward_slice::<_, Fine>(&LatLong, dirs, out)
}

/// The directions of a batch of latlong points, eight at a time.
pub fn latlong_directions(coords: &[ChartUv], out: &mut [Vec3]) -> usize {
    inverse_slice::<_, Fine>(&LatLong, coords, out)
}

/// The functions above, kept in the library's object code (a staticlib
/// drops what nothing reaches): compiled, monomorphised and linked without
/// `std`, not only type-checked.
type Keep = (
    fn(f32, f32, f32, u32) -> Option<(u32, u32, u32)>,
    fn(&[Vec3], &mut [ChartUv]) -> usize,
    fn(&[ChartUv], &mut [Vec3]) -> usize,
);

#[used]
static KEEP: Keep = (cube_texel, latlong_batch, latlong_directions);
