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
//! * [`solid_angle::cube_face4`]: a cube face's texel solid angles four at a
//!   time in f64 (the weights of mip levels and integrals).
//! * [`approx`]: the `atan`, `atan2`, `asin`, `acos` and `sin_cos`
//!   approximations behind the tiers, and `atan2_sqrt` (a polar angle from
//!   squares).
//! * [`Mapping8::inverse8_ray`] and [`Mapping8::forward8_ray`]: an inverse
//!   mapping chained into a forward one (as conversions do) without
//!   normalising in between.
//! * One module per mapping ([`latlong`], [`cube`], [`sphere_map`],
//!   [`dual_paraboloid`], [`tennisball`], [`octahedral`], [`angular`]): its
//!   `Mapping8` kernel; [`batch`] holds the batches, [`kernel`] the trait and
//!   the slices.
//!
//! `wide` picks SSE or AVX at compile time: build with
//! `RUSTFLAGS="-C target-cpu=native"` for the full 8-wide speed.
//!
//! Nothing panics, whatever the input, and the crate has no error type: a bad
//! lane gets [`INVALID_CHART`] and NaN coordinates (forward) or a NaN
//! direction (inverse), exactly where the scalar core returns `None`, and
//! leaves the other lanes bit-identical to what they would be alone. Every
//! case is listed in `docs/bad-input.md`.
//!
//! The tiers' bounds, the polynomial degrees and the measured worst errors are
//! in `docs/accuracy.md`; the speed of every kernel in `docs/performance.md`.
#![no_std]
#![forbid(unsafe_code)]
#![cfg_attr(
    not(test),
    deny(clippy::unwrap_used, clippy::expect_used, clippy::panic)
)]

pub mod angular;
pub mod approx;
pub mod batch;
pub mod cube;
pub mod dual_paraboloid;
pub mod eac;
pub mod fisheye;
pub mod kernel;
pub mod latlong;
pub mod octahedral;
pub mod solid_angle;
pub mod sphere_map;
pub mod tennisball;

pub use approx::{Exact, Fast, Fine, Tier};
pub use batch::{Dir8, Uv8, INVALID_CHART, LANES};
pub use kernel::{forward_slice, inverse_slice, Mapping8};
