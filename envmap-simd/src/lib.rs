//! envmap's mappings eight directions at a time, with the accuracy chosen by the caller.
//!
//! * [`Dir8`] and [`Uv8`]: struct-of-arrays batches (`wide::f32x8`), loaded
//!   from `&[Vec3]`, `&[[f32; 3]]` or separate x/y/z slices with a
//!   shuffle-based transpose.
//! * [`Mapping8`]: every mapping of `envmap-core`, forward and inverse, as an
//!   8-wide branch-free kernel at an accuracy tier ([`Exact`], [`Fine`],
//!   [`Fast`]); the cube selects faces bit-identically to the scalar core.
//! * [`forward_slice`] and [`inverse_slice`]: any length, into caller-provided
//!   output; no threads and no allocation, so engines call them from their own
//!   job systems.
//! * [`approx`]: the `atan`, `atan2`, `asin`, `acos` and `sin_cos`
//!   approximations behind the tiers.
//!
//! `wide` picks SSE or AVX at compile time: build with
//! `RUSTFLAGS="-C target-cpu=native"` for the full 8-wide speed.
#![no_std]
#![forbid(unsafe_code)]

pub mod approx;
pub mod batch;
pub mod cube;
pub mod dual_paraboloid;
pub mod kernel;
pub mod latlong;
pub mod octahedral;
pub mod sphere_map;
pub mod tennisball;

pub use approx::{Exact, Fast, Fine, Tier};
pub use batch::{Dir8, Uv8, INVALID_CHART, LANES};
pub use kernel::{forward_slice, inverse_slice, Mapping8};
