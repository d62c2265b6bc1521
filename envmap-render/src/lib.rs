//! Environment-map images and their I/O.
//!
//! * [`image`]: [`EnvImage`], linear f32 RGB texels tagged with their
//!   [`Representation`] (mapping, atlas layout, frame).
//! * [`layout`]: named layouts ([`Layout`]) and telling a representation from
//!   an image's size ([`layout::detect`], [`layout::resolve`]).
//! * [`io`]: loading and saving PNG, JPEG, Radiance HDR and OpenEXR, cubes as
//!   six files, with atomic writes ([`io::load`], [`io::save`]).
//! * [`sample`]: nearest and bilinear sampling with each representation's
//!   edge rule ([`sample::Sampler`]).
//! * [`convert`]: any representation to any other, one generic loop
//!   ([`convert::convert`]).
//! * [`procedural`]: environments defined by a function of direction.
//! * [`text`]: the line formats of `envmap map` and `envmap unmap`.
//! * [`error`]: the crate's [`Error`], whose messages name the file.
#![forbid(unsafe_code)]
#![cfg_attr(
    not(test),
    deny(clippy::unwrap_used, clippy::expect_used, clippy::panic)
)]

pub mod convert;
pub mod demo;
pub mod environments;
pub mod error;
pub mod image;
pub mod io;
pub mod layout;
pub mod mesh;
pub mod procedural;
pub mod render;
pub mod sample;
pub mod text;

pub use crate::error::{Error, Result};
pub use crate::image::{EnvImage, Representation, RgbImage, Stats};
pub use crate::io::{load, save, LoadOptions, NonFinite, SaveOptions};
pub use crate::layout::Layout;
