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
//! | [`Eac`] | [`eac`] | 6 faces | Brown 2017 (Google); ffmpeg `v360`'s `eac` |
//! | [`SphereMap`] | [`sphere_map`] | 1 disk | seed `000`, class and `GL_SPHERE_MAP` conventions |
//! | [`DualParaboloid`] | [`dual_paraboloid`] | 2 disks | seed `000`; Heidrich & Seidel 1998 |
//! | [`Angular`] | [`angular`] | 1 disk | Debevec 1998 (the light probe; `acos` replaced by `atan2`) |
//! | [`Tennisball`] | [`tennisball`] | 2 strips (3:1) | seed `000` (coverage erratum fixed) |
//! | [`Octahedral`] | [`octahedral`] | 1 square | Engelhardt & Dachsbacher 2008 |
//! | [`EqualAreaOctahedral`] | [`octahedral`] | 1 square | Clarberg 2008; pbrt-v4 |
//! | [`Fisheye`] | [`fisheye`] | 1 or 2 disks | Kannala & Brandt 2006: equidistant and equisolid lenses, field of view up to 360° |
//! | [`Perspective`] | [`perspective`] | 1 rectangle | the gnomonic projection (a pinhole camera's view), any field of view under 180° and aspect ratio |
//!
//! Also: the two reflection formulas ([`reflect_view`], [`reflect_incident`]),
//! axis conventions ([`Frame`], [`Framed`]), atlas layouts ([`Atlas`]), texel
//! addressing ([`texel`]) and exact texel solid angles ([`solid_angle`]).
//! [`shaders`] holds the same mappings, and the lighting lookups an engine
//! needs with envmap's bake, as WGSL, GLSL and HLSL.
//! [`AnyMapping`] (in [`any`]) picks one of them at run time.
//!
//! Nothing panics, whatever the input, and the crate has no error type: a bad
//! direction or chart point (NaN, infinite, zero, out of range, outside a disk)
//! gives `None` from [`Mapping::forward`] or [`Mapping::inverse`] (as does a direction a
//! [`Fisheye`] does not see), and
//! [`texel::texel_index`] clamps any `u`. Every case, with what `envmap-simd`
//! gives beside it, is in `docs/bad-input.md`; the `envmap-tests` crate checks
//! each for every mapping.
//!
//! Conventions (axes, frame presets, every layout drawn, cube ties, image
//! coordinates, reflection) are in `docs/conventions.md`; accuracy and round
//! trips in `docs/accuracy.md`.
//!
//! `#![no_std]`, no unsafe code, no allocation. Math goes through `libm`, or
//! `std` with the `std` feature.
#![no_std]
#![forbid(unsafe_code)]
#![cfg_attr(
    not(test),
    deny(clippy::unwrap_used, clippy::expect_used, clippy::panic)
)]

#[cfg(any(test, feature = "std"))]
extern crate std;

pub mod angular;
pub mod any;
pub mod atlas;
pub mod cube;
mod direction;
pub mod dual_paraboloid;
pub mod eac;
pub mod fisheye;
pub mod frame;
pub mod latlong;
mod mapping;
mod math;
pub mod octahedral;
pub mod perspective;
mod reflect;
pub mod shaders;
pub mod solid_angle;
pub mod sphere_map;
pub mod tennisball;
pub mod texel;

pub use angular::Angular;
pub use any::AnyMapping;
pub use atlas::Atlas;
pub use cube::{Cube, CubeFace};
pub use direction::normalize_direction;
pub use dual_paraboloid::DualParaboloid;
pub use eac::Eac;
pub use fisheye::{Fisheye, Lens};
pub use frame::{Frame, Framed};
pub use latlong::LatLong;
pub use mapping::{ChartUv, Mapping};
pub use octahedral::{EqualAreaOctahedral, Octahedral};
pub use perspective::Perspective;
pub use reflect::{reflect_incident, reflect_view};
pub use sphere_map::{SphereConvention, SphereMap};
pub use tennisball::Tennisball;

/// Re-export of the `glam` version this crate's API uses.
pub use glam;
