//! Images and their files: the environment-map image type, its layouts, and
//! every file format, one file per format.
//!
//! * `envimage.rs`: [`EnvImage`] (linear f32 RGB texels tagged with their
//!   [`Representation`]), [`RgbImage`], [`Stats`], size limits.
//! * [`layout`]: [`Representation`] (mapping, atlas, frame), the named
//!   [`Layout`]s, and telling a representation from an image's size
//!   ([`layout::detect`], [`layout::resolve`]).
//! * [`convention`]: what a file's directions mean ([`Convention`],
//!   [`World`], [`FileAxes`]): cube files in the GL world, the latlong
//!   presets of every tool.
//! * [`face_ops`]: cube faces stored turned or mirrored
//!   (`--face-transform`).
//! * [`metadata`]: what envmap writes into a file about its conventions
//!   (OpenEXR attributes, PNG text) and reads back.
//! * [`io`]: the format by extension, load and save options, [`io::load`] and
//!   [`io::save`].
//! * One file per format: `png_jpeg.rs`, `hdr.rs`, `exr.rs`, and
//!   `faces.rs` for cubes as six files; the GPU texture files with mip
//!   levels `ktx2.rs`, `dds.rs` and `ktx1.rs`, around [`texture::Texture`]
//!   and the texel formats and packers of [`texel`]; `srgb.rs` holds the sRGB transfer
//!   functions and `atomic.rs` the safe-write helper every output goes
//!   through (a temporary file renamed into place).
//!
//! Every format is a [`FileFormat`], read and written through one registry
//! (`format.rs`): adding one is a new file here implementing its `Codec`,
//! plus one entry in that registry's table (CONTRIBUTING.md).
//!
//! This folder uses only `envmap-core`, the image-file crates and the
//! crate's [`Error`](crate::Error); nothing from `filter`, `scene` or `cli`.

mod atomic;
pub mod convention;
#[cfg(feature = "dds")]
mod dds;
mod envimage;
#[cfg(feature = "exr")]
mod exr;
pub mod face_ops;
mod faces;
mod format;
#[cfg(feature = "image")]
mod hdr;
pub mod io;
#[cfg(feature = "ktx1")]
pub(crate) mod ktx1;
#[cfg(feature = "ktx2")]
mod ktx2;
pub mod layout;
pub mod metadata;
#[cfg(feature = "image")]
mod png_jpeg;
mod srgb;
pub mod texel;
pub mod texture;

pub use convention::{Convention, FileAxes, World};
pub use envimage::{
    luminance, EnvImage, InAtlas, RgbImage, RowSource, Stats, BYTES_PER_TEXEL, DEFAULT_MAX_TEXELS,
};
pub use format::FileFormat;
pub use layout::{Layout, Representation};
pub use texel::{Clamped, TexelFormat};
pub use texture::{
    Texture, TextureFile, TextureInfo, TextureKind, TextureOptions, Upload, UploadLevel,
};
