//! Images and their files: the environment-map image, its layouts and
//! conventions, and every file format.
//!
//! * [`EnvImage`]: linear f32 RGB texels tagged with their
//!   [`Representation`] (mapping, atlas, frame); [`RgbImage`], [`Stats`],
//!   size limits.
//! * The named [`Layout`]s, and telling a representation from an image's
//!   size ([`detect`], [`resolve`]): [Layouts](#layouts).
//! * What a file's directions mean ([`Convention`], [`World`],
//!   [`FileAxes`]): [File conventions](#file-conventions).
//! * Cube faces stored turned or mirrored ([`FaceTransforms`],
//!   `--face-transform`).
//! * What envmap writes into a file about its conventions and reads back
//!   ([`FileMetadata`]).
//! * [`load`] and [`save`], by path or in memory, and their options:
//!   [Loading and saving](#loading-and-saving).
//! * GPU textures with mip levels ([`texture`]: KTX2, DDS, KTX 1) and
//!   their [`TexelFormat`]s: [Texel formats](#texel-formats).
//!
//! Every format is a [`FileFormat`], read and written through one registry
//! (`format.rs`): adding one is a new file here implementing its `Codec`,
//! plus one entry in that registry's table (CONTRIBUTING.md).
//!
//! This folder uses only `envmap-core`, the image-file crates and the
//! crate's [`Error`](crate::Error); nothing from `filter`, `scene` or `cli`.
//!
//! # Loading and saving
//!
//! Loading and saving environment maps: the format by extension, the load
//! and save options, and one entry point each ([`load`], [`save`]); each
//! format lives in its own file beside this one.
//!
//! | extension | read | write | file |
//! | --- | --- | --- | --- |
//! | `.png` | 8- or 16-bit grey, grey+alpha, RGB, RGBA; sRGB decoded to linear | 8-bit sRGB RGB after exposure, clamped | `png_jpeg.rs` |
//! | `.jpg`, `.jpeg` | 8-bit grey or RGB (CMYK converted); sRGB decoded to linear | 8-bit sRGB, quality 95, after exposure | `png_jpeg.rs` |
//! | `.hdr` | Radiance RGBE, linear | Radiance RGBE, linear (within RGBE precision, ~1 %) | `hdr.rs` |
//! | `.exr` | R, G, B channels (any of f16, f32, u32) of the first layer that has them; alpha and other channels ignored | f32 RGB (bit for bit), or f16 | `exr.rs` |
//! | six files | a cube by one face's name or a `{face}` pattern | six faces | `faces.rs` |
//! | `.ktx2` | 2D or cube, level 0 (all levels: [`texture::read`]); RGBA16F, RGBA32F, B10G11R11, E5B9G9R9, RGB16F, RGB32F; zstd | one level (`Outputs::stage_texture` for chains) in [`SaveOptions::texture`]'s format | `ktx2.rs` |
//! | `.dds` | 2D or cube (DX10 header), level 0; the same formats but RGB16F | as KTX2, no zstd | `dds.rs` |
//! | `.ktx` | no (written for Filament) | KTX 1 as `cmgen` writes it | `ktx1.rs` |
//!
//! The format is chosen by the extension, case-insensitively; bytes in
//! memory under a name without a known extension, by their first bytes
//! ([`FileFormat::from_bytes`]). Alpha is dropped. Colour profiles and PNG gamma chunks are ignored: 8- and 16-bit
//! files are taken as sRGB and decoded with the exact sRGB EOTF
//! ([`srgb_to_linear`]).
//!
//! ## Six-file cubes
//!
//! A cube can be written as six square files `<stem>_+x.<ext>`, `<stem>_-x.<ext>`,
//! ..., `<stem>_-z.<ext>` (the names of [`CubeFace::name`](envmap_core::CubeFace::name)), each face exactly
//! as GL expects it for `GL_TEXTURE_CUBE_MAP_POSITIVE_X + face`. A path with
//! `{face}` in its file name is a pattern (`sky_{face}.exr`). A six-file cube
//! is loaded from the pattern, from any one of the six names (the siblings
//! are found), or from `<stem>.<ext>` with [`Layout::Faces`]; in memory it
//! becomes a horizontal strip.
//!
//! ## Safe writes
//!
//! Every output goes to a temporary file in the target's directory
//! (`.<name>.<random>.tmp`), which is renamed over the target only once it
//! is complete; an error (a full disk, a missing directory, a target that is
//! a directory) or the cancel flag ([`SaveOptions::cancel`], see
//! [`crate::cancel`]) removes the temporary file and leaves any existing
//! file at the target untouched. Writing over an input file (compared by
//! canonical path, and on Unix by device and inode) is refused unless
//! [`SaveOptions::overwrite_input`] is set.
//!
//! The files of one run (`Outputs`: six cube faces, the demo's images, a
//! bake's directory) are all written to temporary files first and renamed
//! into place together at the end: either every one of them replaces its
//! target, or none does. A rename can still fail midway (a disk error, a
//! target turned into a directory meanwhile): then the targets already
//! replaced are put back as they were, from a second name each existing
//! target was given before the renames began (a hard link, or a copy where
//! the file system has no links), and the error says that none of the run's
//! outputs were written. Only if putting one back fails too does a target
//! stay changed; the error then names the file that holds its old contents.
//! A process killed outright (SIGKILL, a power cut) during the renames can
//! leave some targets new and some old, and one killed while writing leaves
//! its temporary file behind.
//!
//! ## Untrusted files
//!
//! Sizes are checked against [`LoadOptions::max_texels`] from the header,
//! before pixel memory is allocated; corrupt or truncated files give an
//! [`Error`](crate::Error) naming the file, never a panic. NaN and infinite texels are
//! kept or replaced by black as [`LoadOptions::non_finite`] says (see
//! [`NonFinite`]).
//!
//! # File conventions
//!
//! File conventions: what the directions of a file mean.
//!
//! The core's formulas are written once, in its canonical frame (z up,
//! right-handed). A *file* carries conventions of its own, which every tool
//! and engine reads its own way; they are applied once, at the edge between a
//! file and the math, as the image's [`Frame`](envmap_core::Frame) (see
//! [`Representation::frame`](crate::image::Representation::frame)):
//!
//! * a [`World`]: the axes the command's directions are in. The default,
//!   [`World::YUp`], is the GL world (y up, right-handed), the world every
//!   engine and peer tool reads cube files in; [`World::YUpLh`] is the
//!   left-handed y-up world of Direct3D and Unity (z negated); and
//!   [`World::ZUp`] is envmap's canonical frame, the seed's, where every
//!   mapping's formula is applied to the directions as given;
//! * a [`Convention`]: for each mapping, the axes its formulas are applied in
//!   within that world. Every convention keeps the cube in the GL world (the
//!   GL face table applied to (x, y, z) as given, +y face up); they differ in
//!   the latlong, as the tools do, and [`Convention::Envmap`] also fixes the
//!   other mappings (see `Convention::frame_in_world`).
//!
//! ## The latlong presets
//!
//! With φ = 2π(u − ½), θ = πv (u to the right, v down, row 0 at the top),
//! every preset puts +y on the top row; in the GL world:
//!
//! | preset | d(u, v) | image centre | u = 0.75 | mirrored |
//! | --- | --- | --- | --- | --- |
//! | `envmap`, `py360convert`, `cmgen-no-mirror` | (sin θ sin φ, cos θ, sin θ cos φ) | +z | +x | as seen from inside, yes; as a cube map's faces are seen (left-handed), no |
//! | `cmgen`, `filament`, `openexr`, `mitsuba` | (−sin θ sin φ, cos θ, sin θ cos φ) | +z | −x | no |
//! | `blender`, `three`, `gltf-ibl-sampler`, `bevy`, `unity` | (sin θ cos φ, cos θ, sin θ sin φ) | +x | +z | no |
//! | `pbrt` | (−sin θ cos φ, cos θ, −sin θ sin φ) | −x | −z | no |
//!
//! "Mirrored" means that, facing the image centre from inside the sphere with
//! +y up in a right-handed world, u grows to the left. The sources of each
//! preset are in [`Convention::source`] and `docs/conventions.md`.
//!
//! # Layouts
//!
//! Named layouts, and telling an image's representation from its size.
//!
//! | name | layout | mapping | aspect | atlas |
//! | --- | --- | --- | --- | --- |
//! | `latlong` | [`Layout::LatLong`] | latlong | 2:1 | [`Atlas::LATLONG`](envmap_core::Atlas::LATLONG) |
//! | `cross` | [`Layout::Cross`] | cube | 4:3 | [`Atlas::CUBE_HORIZONTAL_CROSS`](envmap_core::Atlas::CUBE_HORIZONTAL_CROSS) |
//! | `vcross` | [`Layout::VCross`] | cube | 3:4 | [`Atlas::CUBE_VERTICAL_CROSS`](envmap_core::Atlas::CUBE_VERTICAL_CROSS) |
//! | `strip` | [`Layout::Strip`] | cube | 6:1 | [`Atlas::CUBE_HORIZONTAL_STRIP`](envmap_core::Atlas::CUBE_HORIZONTAL_STRIP) |
//! | `vstrip` | [`Layout::VStrip`] | cube | 1:6 | [`Atlas::CUBE_VERTICAL_STRIP`](envmap_core::Atlas::CUBE_VERTICAL_STRIP) |
//! | `faces` | [`Layout::Faces`] | cube | six square files | in memory: [`Atlas::CUBE_HORIZONTAL_STRIP`](envmap_core::Atlas::CUBE_HORIZONTAL_STRIP) |
//! | `square` | [`Layout::Square`] | sphere, sphere-gl, angular, octahedral, octahedral-equal-area, fisheye | 1:1 | [`Atlas::SINGLE_SQUARE`](envmap_core::Atlas::SINGLE_SQUARE) |
//! | `side-by-side` | [`Layout::SideBySide`] | paraboloid, dual-fisheye (front left) | 2:1 | [`Atlas::PARABOLOID_SIDE_BY_SIDE`](envmap_core::Atlas::PARABOLOID_SIDE_BY_SIDE) |
//! | `stacked` | [`Layout::Stacked`] | tennisball | 3:2 | [`Atlas::TENNISBALL_STACKED`](envmap_core::Atlas::TENNISBALL_STACKED) |
//! | `3x2` | [`Layout::Grid3x2`] | cube, eac | 3:2 | [`Atlas::CUBE_3X2`](envmap_core::Atlas::CUBE_3X2) |
//! | `v360` | [`Layout::V360`] | eac (its default) | (3n + 4) × (2n + 8) for n × n faces | in memory: [`Atlas::EAC_V360`](envmap_core::Atlas::EAC_V360) |
//! | `dfisheye` | [`Layout::DualFisheye`] | dual-fisheye (its default: back lens left, front right, as v360's `dfisheye`) | 2:1 | [`Atlas::DUAL_FISHEYE_V360`](envmap_core::Atlas::DUAL_FISHEYE_V360) |
//!
//! Every cube layout holds the equi-angular cube map (`eac`) as well, face
//! for face; named alone, a cube layout is read as the cube (`--from eac`
//! reads it as EAC). The `v360` layout is the file ffmpeg's `v360` filter writes and
//! reads as `eac` (YouTube's 360° video frames): −x, +z, +x on top; −y, −z,
//! +y below, −y and +y turned a quarter turn counter-clockwise and −z a
//! quarter turn clockwise; 2 pixels of padding left and right of the image
//! and above and below each row, filled on writing by repeating the row's
//! edge texels. Reading cuts the padding away and turns the faces back, so
//! in memory the faces are GL's, unpadded. Its size is not told by the
//! aspect ratio: name it (`--from eac`, or `--from-layout v360`), or read a
//! file envmap wrote, which says so itself.
//!
//! [`detect`] picks a representation from the aspect ratio alone. Three
//! cases need the caller's word: a 2:1 image is taken as latlong, so a dual
//! paraboloid (two disks side by side, also 2:1) needs its mapping named
//! explicitly (`--from paraboloid`); a square image could be any of five
//! mappings, and a 3:2 image a tennisball or a cube of three faces by two
//! (`3x2`), so [`detect`] refuses them and says how to choose; a v360 EAC
//! file, `(3n + 4) × (2n + 8)`, is refused with the hint `--from eac`. [`resolve`]
//! takes an explicit mapping and/or layout and checks it against the size.
//!
//! # Cube faces stored turned or mirrored
//!
//! Cube faces stored turned or mirrored: the per-face transforms some tools
//! and engines need (cmft's `--posXrotate90` and kin).
//!
//! A [`FaceTransforms`] says, for each face, how the face image in the file
//! is turned or mirrored against the face as GL defines it: on loading, each
//! face is put back into GL's orientation; on saving, each GL face is turned
//! as the file wants it. The operations, on an image seen as displayed (row
//! 0 at the top):
//!
//! | name | does |
//! | --- | --- |
//! | `rot90` | a quarter turn clockwise |
//! | `rot180` | a half turn |
//! | `rot270` | a quarter turn counter-clockwise |
//! | `flipx` | mirrors left and right |
//! | `flipy` | mirrors top and bottom |
//! | `transpose` | mirrors about the main diagonal (rows become columns) |
//!
//! On the command line: `--face-transform +x:rot90,-z:flipx` (faces by any
//! scheme's names, `crate::image::io::FaceNames`; several operations on
//! one face apply in the order given). The vertical cross's −z face, which
//! that layout stores half turned, is the built-in case of `-z:rot180`.
//!
//! # What a file says about itself
//!
//! What envmap writes into a file about its conventions, and reads back.
//!
//! Where a format has a place for text (OpenEXR header attributes, PNG
//! `tEXt` chunks), every file envmap writes says what it holds:
//!
//! | key | value |
//! | --- | --- |
//! | `envmap.mapping` | the mapping's name (`cube`, `latlong`, ...) |
//! | `envmap.layout` | the layout's name (`cross`, `strip`, `faces`, ...) |
//! | `envmap.face` | for one face of a six-file cube: its name (`+x` ... `-z`) |
//! | `envmap.axes` | `convention <name> world <y-up\|y-up-lh\|z-up>`, or `frame` and the nine entries of the file → canonical matrix, column by column |
//! | `Description` (PNG), `comments` (EXR) | the same in words, with where the image's centre and the world's axes land |
//! | `Software` (PNG), `software` (EXR) | `envmap` and its version |
//!
//! Loading reads them back: a file's own mapping, layout and axes are used
//! unless the caller gives others ([`crate::image::io::LoadOptions`]). Radiance
//! HDR and JPEG files carry none (the encoders used have no place for them);
//! `envmap info` then says the default is assumed.
//!
//! # Texel formats
//!
//! GPU texel formats and their packers: what a KTX2, DDS or KTX 1 file's
//! texels are, bit for bit.
//!
//! | format | Vulkan | DXGI | GL | bytes | range | source of the packing |
//! | --- | ---: | ---: | --- | ---: | --- | --- |
//! | [`TexelFormat::Rgba16f`] | 97 | 10 | `GL_RGBA16F` | 8 | ±65504 | IEEE 754 binary16, round to nearest even |
//! | [`TexelFormat::Rgba32f`] | 109 | 2 | `GL_RGBA32F` | 16 | f32 | IEEE 754 binary32, as is |
//! | [`TexelFormat::B10g11r11`] | 122 | 26 | `GL_R11F_G11F_B10F` | 4 | 0 … 65024 (B 64512) | unsigned 11- and 10-bit floats (Vulkan spec §"Fixed-Point/Floating-Point Data Conversions", 5-bit exponent, bias 15), round to nearest even |
//! | [`TexelFormat::E5b9g9r9`] | 123 | 67 | `GL_RGB9_E5` | 4 | 0 … 65408 | `EXT_texture_shared_exponent`, §"Appendix: RGB9E5 shared exponent" |
//! | [`TexelFormat::Rgb16f`] | 90 | – | `GL_RGB16F` | 6 | ±65504 | read only (no DXGI or Metal equivalent) |
//! | [`TexelFormat::Rgb32f`] | 106 | 6 | `GL_RGB32F` | 12 | f32 | read only |
//! | [`TexelFormat::Bc6h`] | 143 | 95 | `GL_COMPRESSED_RGB_BPTC_UNSIGNED_FLOAT` | 16 per 4×4 block | 0 … 65504 | BC6H (Direct3D 11 block compression), lossy: encoded by `block_compression` (a port of Intel's ISPC kernel) at a [`Bc6hQuality`], decoded by `bcdec_rs`; KTX2 and DDS only, with the `bc6h` feature |
//! | [`TexelFormat::Rgbd8`] | (37) | – | `GL_RGBA8` | 4 | 0 … 255 | RGBD, Babylon.js's `toRGBD`/`fromRGBD` (`helperFunctions.fx`), lossy; Babylon.js `.env` files only, as PNG, with the `babylon` feature |
//!
//! BC6H's and RGBD's loss is measured when a bake writes them (BC6H's
//! whenever a file is written): each level's texels
//! decoded from the bytes written, against the texels encoded. A KTX2 file
//! records it in its key/value data (`envmap.bc6h-error`, one line per
//! level: relative RMS, log-space RMSE, the worst texel), which `envmap
//! info` prints; a bake's manifest records it for every file.
//!
//! RGBA formats get alpha 1. Values a format cannot hold are clamped to the
//! nearest value it can, and counted ([`Clamped`]): above the largest
//! finite value (RGBA16F would otherwise turn them into infinity, which GPU
//! filtering spreads as NaN), below zero for the unsigned formats, and NaN
//! (written as 0). RGBA32F stores every f32 as is.

mod atomic;
#[cfg(feature = "babylon")]
pub(crate) mod babylon;
#[cfg(feature = "bc6h")]
pub(crate) mod bc6h;
pub(crate) mod convention;
#[cfg(feature = "dds")]
mod dds;
mod envimage;
#[cfg(feature = "exr")]
mod exr;
pub(crate) mod face_ops;
mod faces;
mod format;
pub(crate) mod framing;
#[cfg(feature = "image")]
mod hdr;
pub(crate) mod io;
#[cfg(feature = "ktx1")]
pub(crate) mod ktx1;
#[cfg(feature = "ktx2")]
mod ktx2;
pub(crate) mod layout;
#[cfg(any(feature = "bc6h", feature = "babylon"))]
pub(crate) mod lossy;
pub(crate) mod metadata;
#[cfg(feature = "image")]
mod png_jpeg;
mod srgb;
pub(crate) mod texel;
pub mod texture;

pub use atomic::*;
pub use convention::*;
pub use envimage::*;
pub use face_ops::*;
pub use faces::*;
pub use format::FileFormat;
pub use io::*;
pub use layout::*;
pub use metadata::*;
pub use srgb::*;
pub use texel::*;
