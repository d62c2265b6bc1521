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
//!   approximations behind the tiers, and `atan2_sqrt` (a polar angle from
//!   squares).
//! * [`Mapping8::inverse8_ray`] and [`Mapping8::forward8_ray`]: an inverse
//!   mapping chained into a forward one (as conversions do) without
//!   normalising in between.
//!
//! `wide` picks SSE or AVX at compile time: build with
//! `RUSTFLAGS="-C target-cpu=native"` for the full 8-wide speed.
//!
//! # Bad input
//!
//! Nothing panics, whatever the input. The crate has no error type: a bad
//! lane gets [`INVALID_CHART`] and NaN coordinates (forward) or a NaN
//! direction (inverse), exactly where the scalar core returns `None`, and
//! leaves the other lanes bit-identical to what they would be alone:
//!
//! | input | scalar core (`Mapping`) | SIMD (`Mapping8`, slices), every tier |
//! | --- | --- | --- |
//! | direction with a NaN (either sign) or ±Inf component | `forward` → `None` | `INVALID_CHART`, u = v = NaN |
//! | the zero vector, any signs of zero | `forward` → `None` | `INVALID_CHART`, u = v = NaN |
//! | denormal, tiny (1e-30) or huge (1e30, `f32::MAX`) components, any length | a valid chart, u, v in `[0, 1]` inside its domain (no overflow or underflow) | the same chart; u, v within the tier's bound (bit for bit for cube, sphere maps, paraboloid, octahedral) |
//! | `-0.0` components | their sign counts where it picks a side (cube faces, seams) | bit-identical choice |
//! | chart ≥ `chart_count` (including `INVALID_CHART`) | `inverse` → `None` | direction (NaN, NaN, NaN) |
//! | u or v NaN, ±Inf, below 0 or above 1 (`-0.0` counts as 0) | `inverse` → `None` | direction (NaN, NaN, NaN) |
//! | u, v in `[0, 1]` but outside a disk chart (sphere map, paraboloid corners) | `inverse` → `None` | direction (NaN, NaN, NaN) |
//! | a batch mixing good and bad lanes | — | every lane bit-identical to that input alone |
//! | any u (NaN, ±Inf, `1.0`, out of range) in `texel::texel_index(u, n)` | an index in `[0, n − 1]` (`1.0` → `n − 1`, NaN → 0) | — |
//! | any u in `texel::bilinear_footprint(u, n)` | indices in `[−1, n]` (u clamped to `[0, 1]`; NaN, ±Inf → `(0, 1, 0.0)`) | — |
#![no_std]
#![forbid(unsafe_code)]
#![cfg_attr(
    not(test),
    deny(clippy::unwrap_used, clippy::expect_used, clippy::panic)
)]

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
