//! Environment-map images and their files, filtering and conversion, the
//! lighting bake and the renderer. The `envmap` command is the crate
//! `envmap-cli`, a thin shell over this one.
//!
//! The crate is four folders by concern, each using only the ones above it:
//!
//! | folder | what lives there | may use |
//! | --- | --- | --- |
//! | [`image`] | [`image::EnvImage`] and its [`image::Representation`], layouts, every file format (`io`: PNG/JPEG, Radiance HDR, OpenEXR, six-file cubes, safe writes) | `envmap-core` |
//! | [`filter`] | sampling with each representation's edge rule (`filter::sample`), the one conversion loop ([`filter::convert`]) | `image`, `envmap-simd` |
//! | [`scene`] | built-in environments, procedural environments, meshes, the renderer, the demo | `image`, `filter` |
//! | [`bake`] | the one way to bake ([`bake::Baker`]), the engines' presets, a bake's files written to a directory or into memory, and read back | `image`, `filter`, `scene` |
//!
//! [`Error`] (in `error.rs`) is shared by all of them: every message names
//! the file it concerns.
//!
//! Each job has one path, at most one module below the root:
//!
//! | job | written as |
//! | --- | --- |
//! | load a map (a path, or bytes) | [`image::load`], [`image::load_from_memory`] |
//! | save a map (a path, or bytes) | [`image::save`], [`image::save_to_memory`] |
//! | convert | [`filter::convert`] (or [`filter::convert_into`], streamed to a file) |
//! | bake | [`bake::Baker`]`::for_target(..).bake(&image)` |
//! | write a bake's files | [`bake::Baked::write`] (a directory), [`bake::Baked::files`] (memory), [`bake::Baked::textures`] (upload-ready) |
//! | read a bake back | [`bake::open`] |
//! | render, and save the picture | [`scene::Renderer`]`::new().render(..)` (kept from frame to frame), [`image::write_rgb`] |
//!
//! Features, all on by default: the file formats `exr`, `image` (PNG, JPEG, Radiance),
//! `ktx2`, `zstd` (KTX2 supercompression; a C compiler), `dds`, `ktx1`, and
//! `parallel` (rayon; without it the same results on the calling thread).
//! An engine sets `default-features = false` and adds what it reads and
//! writes: the in-memory core is always there (`docs/embedding.md`). A file
//! of a format left out gives [`Error::FormatDisabled`].
//! Off by default, `instruments` makes the measuring instruments public
//! (`instruments`: the oracle, the exact split sum and the Monte Carlo
//! reference; `filter::weights`, `filter::sample`, `filter::pyramid`; and the bake's and the renderer's inner steps) for the
//! command's `--check` and `--reference`, the benchmarks and the tests; they
//! may change in any release.
//!
//! Conventions (axes, frames, layouts, image coordinates) are in
//! `docs/conventions.md`; speed in `docs/performance.md`; what bad input gives
//! in `docs/bad-input.md`; the command's flags in `docs/cli.md`.
#![forbid(unsafe_code)]
#![cfg_attr(
    not(test),
    deny(clippy::unwrap_used, clippy::expect_used, clippy::panic)
)]

pub mod bake;
pub mod cancel;
mod error;
pub mod filter;
pub mod image;
pub mod instruments;
mod par;
pub mod scene;

pub use crate::error::{Error, Result};

// The README's Rust examples run as doctests (`cargo test --doc`).
#[cfg(doctest)]
#[doc = include_str!("../../README.md")]
struct ReadmeDoctests;
