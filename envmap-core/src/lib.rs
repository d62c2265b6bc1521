//! Environment-map parameterizations with exact inverses.
//!
//! Every representation is an **atlas of charts**: a [`Mapping`] turns a
//! direction into a point `(chart, u, v)` of its texture ([`Mapping::forward`])
//! and back ([`Mapping::inverse`]), with u, v ∈ [0, 1] (u right, v down).
//! Because every representation has both, converting any representation into
//! any other is one generic loop, and the property tests of the `envmap-tests`
//! crate prove the round trips.
//!
//! | mapping | module | charts | source |
//! | --- | --- | --- | --- |
//! | [`LatLong`] | [`latlong`] | 1 (2:1) | Blinn & Newell 1976; seed `000` (quadrant erratum fixed) |
//! | [`Cube`] | [`cube`] | 6 faces | seed `000`; OpenGL / Vulkan face table |
//! | [`SphereMap`] | [`sphere_map`] | 1 disk | seed `000`, class and `GL_SPHERE_MAP` conventions |
//! | [`DualParaboloid`] | [`dual_paraboloid`] | 2 disks | seed `000`; Heidrich & Seidel 1998 |
//! | [`Tennisball`] | [`tennisball`] | 2 strips (3:1) | seed `000` (coverage erratum fixed) |
//! | [`Octahedral`] | [`octahedral`] | 1 square | Engelhardt & Dachsbacher 2008 |
//! | [`EqualAreaOctahedral`] | [`octahedral`] | 1 square | Clarberg 2008; pbrt-v4 |
//!
//! Also: the two reflection formulas ([`reflect_view`], [`reflect_incident`]),
//! axis conventions ([`Frame`], [`Framed`]), atlas layouts ([`Atlas`]), texel
//! addressing ([`texel`]) and exact texel solid angles ([`solid_angle`]).
//!
//! # Bad input
//!
//! Nothing panics, whatever the input. The crate has no error type: bad input
//! gives `None` (the `envmap-simd` column is there for comparison; the
//! `envmap-tests` crate checks every row for every mapping):
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
//!
//! `#![no_std]`, no unsafe code, no allocation. Math goes through `libm`, or
//! `std` with the `std` feature.
#![no_std]
#![forbid(unsafe_code)]
#![cfg_attr(
    not(test),
    deny(clippy::unwrap_used, clippy::expect_used, clippy::panic)
)]

#[cfg(feature = "std")]
extern crate std;

pub mod any;
pub mod atlas;
pub mod cube;
mod direction;
pub mod dual_paraboloid;
pub mod frame;
pub mod latlong;
mod mapping;
mod math;
pub mod octahedral;
mod reflect;
pub mod solid_angle;
pub mod sphere_map;
pub mod tennisball;
pub mod texel;

pub use any::AnyMapping;
pub use atlas::Atlas;
pub use cube::{Cube, CubeFace};
pub use direction::normalize_direction;
pub use dual_paraboloid::DualParaboloid;
pub use frame::{Frame, Framed};
pub use latlong::LatLong;
pub use mapping::{ChartUv, Mapping};
pub use octahedral::{EqualAreaOctahedral, Octahedral};
pub use reflect::{reflect_incident, reflect_view};
pub use sphere_map::{SphereConvention, SphereMap};
pub use tennisball::Tennisball;

/// Re-export of the `glam` version this crate's API uses.
pub use glam;
