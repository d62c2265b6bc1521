//! The registry of file formats: one [`FileFormat`] for every file envmap
//! reads or writes, plain images and texture chains alike, and the one
//! interface every format's file implements ([`Codec`]).
//!
//! A format is recognised by its file name's extension
//! ([`FileFormat::from_path`]) or by its first bytes
//! ([`FileFormat::from_bytes`]). Reading gives [`Contents`]: an image
//! (PNG, JPEG, Radiance, OpenEXR) or a chain of levels (KTX2, DDS).
//! [`load`](crate::image::io::load) takes a chain's level 0,
//! [`texture::read`](crate::image::texture::read) the whole chain, and the
//! bake reader either; all three read through [`read`] here, so there is
//! one way to read a file, whatever the container.
//!
//! # Adding a format
//!
//! One new file in this folder, behind its Cargo feature, with a unit
//! value implementing [`Codec`] (read; write an image or write a chain;
//! optionally the size from the header alone), and one entry in the
//! `registry!` table at the end of this file: its variant, name,
//! extensions, first bytes, feature, what it holds and its codec.
//! [`FileFormat`], its names and extensions, the choice by name or bytes,
//! the feature check and every read and write then follow from the table.

#[cfg(any(feature = "ktx2", feature = "dds", feature = "babylon"))]
use std::borrow::Cow;
use std::fs::File;
#[cfg(any(feature = "ktx2", feature = "dds", feature = "babylon"))]
use std::io::Read as _;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::Path;
use std::sync::atomic::AtomicBool;

use crate::cancel::{self, Cancellable};
use crate::error::{Error, Result};
use crate::image::atomic::TempWriter;
use crate::image::envimage::RgbImage;
use crate::image::io::{SaveOptions, SourceFormat, View};
use crate::image::texel::Clamped;
use crate::image::texture::{Texture, TextureFile, TextureOptions};

/// What a format's files hold.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Holds {
    /// One image in 8- or 16-bit sRGB.
    Srgb,
    /// One image in linear floating point.
    Linear,
    /// A GPU texture: a 2D image or a cube, with its mip levels.
    Chain,
}

/// What a file held, read whole.
#[cfg_attr(
    not(any(
        feature = "image",
        feature = "exr",
        feature = "ktx2",
        feature = "dds",
        feature = "babylon"
    )),
    allow(dead_code)
)]
pub(crate) enum Contents {
    /// A plain image, and what the file held.
    #[cfg_attr(not(any(feature = "image", feature = "exr")), allow(dead_code))]
    Image(RgbImage, SourceFormat),
    /// A texture with its levels (KTX2, DDS).
    #[cfg_attr(
        not(any(feature = "ktx2", feature = "dds", feature = "babylon")),
        allow(dead_code)
    )]
    Chain(TextureFile),
}

/// One format's reader and writer. Each format's file has a unit value
/// implementing it, named in the registry.
pub(crate) trait Codec: Sync {
    /// Reads the file from `src` (named `path` in errors), refusing an image
    /// above `max_texels` before allocating its texels.
    fn read(&self, path: &Path, src: Source<'_>, max_texels: u64) -> Result<Contents>;

    /// The size of the image the file holds (a cube chain's level 0 as its
    /// faces side by side), from as little of it as the format allows. By
    /// default the file is read whole.
    fn dimensions(&self, path: &Path, src: Source<'_>) -> Result<(u32, u32)> {
        match self.read(path, src, u64::MAX)? {
            Contents::Image(rgb, _) => Ok((rgb.width, rgb.height)),
            Contents::Chain(t) => Ok(level0_size(&t)),
        }
    }

    /// Encodes a plain image into `out`. A chain format writes textures
    /// only.
    fn write_image(
        &self,
        path: &Path,
        view: View<'_>,
        opts: &SaveOptions,
        out: &mut TempWriter<'_>,
    ) -> Result<()> {
        let _ = (view, opts, out);
        Err(Error::usage("texture files are staged whole (Outputs::stage_texture)").in_file(path))
    }

    /// The bytes of a texture with its levels, and what packing clamped. An
    /// image format writes images only.
    fn write_chain(&self, tex: &Texture, opts: TextureOptions) -> Result<(Vec<u8>, Clamped)> {
        let _ = (tex, opts);
        Err(Error::unsupported("not a KTX2, DDS or KTX file name"))
    }
}

/// Level 0's size as a plain image: a cube's faces side by side.
pub(crate) fn level0_size(t: &TextureFile) -> (u32, u32) {
    let (w, h) = t.texture.size();
    match t.texture.kind() {
        crate::image::texture::TextureKind::Cube => (6 * w, h),
        crate::image::texture::TextureKind::Flat => (w, h),
    }
}

/// A comma-separated list without its last ", ".
const fn trimmed(list: &'static str) -> &'static str {
    list.split_at(list.len() - 2).0
}

macro_rules! registry {
    ($(
        $(#[$doc:meta])*
        $variant:ident: $name:literal, [$($ext:literal),+], $magic:literal, $feature:literal, $holds:ident, $codec:path;
    )+) => {
        /// A file format envmap reads or writes, chosen by the file name's
        /// extension or recognised by the file's first bytes. Each lives in
        /// its own file behind the Cargo feature [`FileFormat::feature`]
        /// names, and is read and written through the one registry of
        /// formats (adding one: CONTRIBUTING.md).
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
        pub enum FileFormat {
            $( $(#[$doc])* $variant, )+
        }

        impl FileFormat {
            /// Every format, in the registry's order.
            pub const ALL: &'static [FileFormat] = &[$(FileFormat::$variant),+];

            /// The accepted extensions, as listed in error messages.
            pub const EXTENSIONS: &'static str = trimmed(concat!($($($ext, ", "),+),+));

            /// The format's usual name (`"PNG"`, `"OpenEXR"`, ...).
            #[must_use]
            pub const fn name(self) -> &'static str {
                match self { $(FileFormat::$variant => $name,)+ }
            }

            /// The file name extensions of the format, lower case, the one
            /// envmap writes first.
            #[must_use]
            pub const fn extensions(self) -> &'static [&'static str] {
                match self { $(FileFormat::$variant => &[$($ext),+],)+ }
            }

            /// The Cargo feature of `envmap-render` that reads and writes the
            /// format: `image` (PNG, JPEG, Radiance), `exr`, `ktx2`, `dds`, `ktx1`.
            #[must_use]
            pub const fn feature(self) -> &'static str {
                match self { $(FileFormat::$variant => $feature,)+ }
            }

            /// The bytes every file of the format starts with.
            const fn magic(self) -> &'static [u8] {
                match self { $(FileFormat::$variant => $magic,)+ }
            }

            /// What the format's files hold.
            pub(crate) const fn holds(self) -> Holds {
                match self { $(FileFormat::$variant => Holds::$holds,)+ }
            }

            /// The format's codec, if this build has it.
            fn codec_if_enabled(self) -> Option<&'static dyn Codec> {
                match self {
                    $(FileFormat::$variant => {
                        #[cfg(feature = $feature)]
                        { Some(&$codec) }
                        #[cfg(not(feature = $feature))]
                        { None }
                    })+
                }
            }
        }
    };
}

impl FileFormat {
    /// The format of a path's extension (case-insensitive); an error naming
    /// the file and the accepted extensions otherwise.
    pub fn from_path(path: &Path) -> Result<FileFormat> {
        let ext = path.extension().map(|e| e.to_string_lossy().into_owned());
        ext.as_deref()
            .and_then(|e| e.parse().ok())
            .ok_or_else(|| Error::UnknownExtension {
                path: path.to_path_buf(),
                extension: ext,
                accepted: Self::EXTENSIONS,
            })
    }

    /// The format whose files start as `head` does (a file's first 16 bytes
    /// are enough), if one does.
    #[must_use]
    pub fn from_bytes(head: &[u8]) -> Option<FileFormat> {
        Self::ALL
            .iter()
            .copied()
            .find(|f| head.starts_with(f.magic()))
    }

    /// The extension envmap writes for the format (`"exr"`, `"ktx2"`, ...).
    #[must_use]
    pub const fn extension(self) -> &'static str {
        self.extensions()[0]
    }

    /// Whether the format is a GPU texture file with mip levels (KTX2, DDS,
    /// KTX 1; see [`crate::image::texture`]).
    #[must_use]
    pub const fn is_texture(self) -> bool {
        matches!(self.holds(), Holds::Chain)
    }

    /// Whether the format stores linear floating-point values (Radiance,
    /// OpenEXR, the texture files) rather than 8- or 16-bit sRGB.
    #[must_use]
    pub const fn is_float(self) -> bool {
        !matches!(self.holds(), Holds::Srgb)
    }

    /// The format's codec, or [`Error::FormatDisabled`] for `path` when
    /// this build leaves the format out.
    pub(crate) fn codec(self, path: &Path) -> Result<&'static dyn Codec> {
        self.codec_if_enabled()
            .ok_or_else(|| Error::FormatDisabled {
                path: path.to_path_buf(),
                format: self.name(),
                feature: self.feature(),
            })
    }
}

impl std::str::FromStr for FileFormat {
    type Err = Error;

    /// The format one of whose extensions `s` is (case-insensitive, no dot).
    fn from_str(s: &str) -> Result<Self> {
        let lower = s.to_ascii_lowercase();
        Self::ALL
            .iter()
            .copied()
            .find(|f| f.extensions().contains(&lower.as_str()))
            .ok_or_else(|| Error::UnknownExtension {
                path: s.into(),
                extension: Some(s.to_owned()),
                accepted: Self::EXTENSIONS,
            })
    }
}

/// An error decoding `path` as `format`.
pub(crate) fn decode_error(path: &Path, format: FileFormat, message: impl ToString) -> Error {
    Error::Decode {
        path: path.to_path_buf(),
        format: format.name(),
        message: message.to_string(),
    }
}

/// Runs a decoder, turning a panic inside it into an error naming the file.
fn guarded<T>(path: &Path, format: FileFormat, f: impl FnOnce() -> Result<T>) -> Result<T> {
    catch_unwind(AssertUnwindSafe(f)).unwrap_or_else(|_| {
        Err(decode_error(
            path,
            format,
            "the decoder failed on this file (corrupt data)",
        ))
    })
}

/// What the readers read: the file (or the caller's bytes), failing once
/// the cancel flag is set.
pub(crate) type Source<'a> = Cancellable<'a, Input<'a>>;

/// A reader's bytes: a file, or a buffer in memory
/// ([`load_from_memory`](crate::image::io::load_from_memory)).
#[derive(Debug)]
pub(crate) enum Input<'a> {
    /// An open file.
    File(File),
    /// The caller's bytes.
    Memory(std::io::Cursor<&'a [u8]>),
}

impl std::io::Read for Input<'_> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        match self {
            Input::File(f) => f.read(buf),
            Input::Memory(m) => m.read(buf),
        }
    }
}

impl std::io::Seek for Input<'_> {
    fn seek(&mut self, pos: std::io::SeekFrom) -> std::io::Result<u64> {
        match self {
            Input::File(f) => f.seek(pos),
            Input::Memory(m) => m.seek(pos),
        }
    }
}

/// Opens `path` for reading (a directory is an error).
pub(crate) fn open<'a>(path: &Path, cancel: Option<&'a AtomicBool>) -> Result<Source<'a>> {
    let file = File::open(path).map_err(|e| Error::read(path, e))?;
    let file = match file.metadata() {
        Ok(m) if m.is_dir() => Err(Error::read(
            path,
            std::io::Error::new(std::io::ErrorKind::InvalidInput, "is a directory"),
        )),
        _ => Ok(file),
    }?;
    Ok(Cancellable::new(Input::File(file), cancel))
}

/// The caller's bytes as a source.
pub(crate) fn memory<'a>(bytes: &'a [u8], cancel: Option<&'a AtomicBool>) -> Source<'a> {
    Cancellable::new(Input::Memory(std::io::Cursor::new(bytes)), cancel)
}

/// The largest file a texture within `max_texels` can be: every texel at
/// 16 bytes, plus 1 MiB for headers and metadata. Larger files are refused
/// before they are read.
#[cfg(any(feature = "ktx2", feature = "dds", feature = "babylon"))]
pub(crate) fn max_file_bytes(max_texels: u64) -> u64 {
    max_texels.saturating_mul(16).saturating_add(1 << 20)
}

/// The whole of a texture file's bytes (borrowed when they are in memory),
/// refusing a file larger than any texture within `max_texels` can be
/// before reading it.
#[cfg(any(feature = "ktx2", feature = "dds", feature = "babylon"))]
pub(crate) fn whole<'a>(
    path: &Path,
    format: FileFormat,
    src: Source<'a>,
    max_texels: u64,
) -> Result<Cow<'a, [u8]>> {
    let cancel = src.flag();
    let input = src.into_inner();
    let len = match &input {
        Input::File(f) => f.metadata().map_err(|e| Error::read(path, e))?.len(),
        Input::Memory(m) => m.get_ref().len() as u64,
    };
    if len > max_file_bytes(max_texels) {
        return Err(decode_error(
            path,
            format,
            format!(
                "the file is {len} bytes, more than any texture within the limit of {max_texels} texels can be"
            ),
        ));
    }
    let bytes = match input {
        Input::Memory(m) => Cow::Borrowed(*m.get_ref()),
        Input::File(f) => {
            let mut bytes = Vec::new();
            let read = Cancellable::new(f, cancel)
                .read_to_end(&mut bytes)
                .map_err(|e| Error::read(path, e));
            cancel::or_cancelled(read, cancel)?;
            Cow::Owned(bytes)
        }
    };
    cancel::check(cancel)?;
    Ok(bytes)
}

/// Reads the file `src` (named `path`) as `format`, through the format's
/// codec: the one way every file is read. Refuses an image above
/// `max_texels` before allocating it; [`Error::Cancelled`] once the
/// source's flag is set.
pub(crate) fn read(
    path: &Path,
    format: FileFormat,
    src: Source<'_>,
    max_texels: u64,
) -> Result<Contents> {
    let cancel = src.flag();
    cancel::check(cancel)?;
    let codec = format.codec(path)?;
    let read = guarded(path, format, || codec.read(path, src, max_texels));
    cancel::or_cancelled(read, cancel)
}

/// The size of the image in the file `path` names, from its header where
/// the format allows.
pub(crate) fn dimensions(path: &Path) -> Result<(u32, u32)> {
    let format = FileFormat::from_path(path)?;
    let codec = format.codec(path)?;
    let src = open(path, None)?;
    guarded(path, format, || codec.dimensions(path, src))
}

registry! {
    /// PNG (`.png`): 8- or 16-bit sRGB.
    Png: "PNG", ["png"], b"\x89PNG\r\n\x1a\n", "image", Srgb, crate::image::png_jpeg::PNG;
    /// JPEG (`.jpg`, `.jpeg`): 8-bit sRGB.
    Jpeg: "JPEG", ["jpg", "jpeg"], b"\xFF\xD8\xFF", "image", Srgb, crate::image::png_jpeg::JPEG;
    /// Radiance RGBE (`.hdr`): linear floating point, shared exponent.
    Hdr: "Radiance HDR", ["hdr"], b"#?", "image", Linear, crate::image::hdr::Hdr;
    /// OpenEXR (`.exr`): linear f16 or f32.
    Exr: "OpenEXR", ["exr"], b"\x76\x2F\x31\x01", "exr", Linear, crate::image::exr::Exr;
    /// KTX 2.0 (`.ktx2`): GPU texture with mip levels.
    Ktx2: "KTX2", ["ktx2"], b"\xABKTX 20\xBB\r\n\x1A\n", "ktx2", Chain, crate::image::ktx2::Ktx2;
    /// DDS (`.dds`): GPU texture with mip levels, DX10 header.
    Dds: "DDS", ["dds"], b"DDS ", "dds", Chain, crate::image::dds::Dds;
    /// KTX 1 (`.ktx`): GPU texture with mip levels, as Filament reads it
    /// (written only).
    Ktx: "KTX 1", ["ktx"], b"\xABKTX 11\xBB\r\n\x1A\n", "ktx1", Chain, crate::image::ktx1::Ktx1;
    /// Babylon.js environment (`.env`): an RGBD cube chain as PNG, with
    /// its irradiance polynomial.
    Env: "Babylon.js .env", ["env"], b"\x86\x16\x87\x96\xF6\xD6\x96\x36", "babylon", Chain, crate::image::babylon::ENV;
    /// glTF 2.0 (`.gltf`) holding one image-based light
    /// (`EXT_lights_image_based`, as Babylon.js's loader reads it), its
    /// images inside as `data:` URIs.
    Gltf: "glTF (EXT_lights_image_based)", ["gltf"], b"{\"asset\":", "babylon", Chain, crate::image::babylon::GLTF;
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_format_is_found_by_each_extension_and_by_its_first_bytes() {
        assert_eq!(
            FileFormat::EXTENSIONS,
            "png, jpg, jpeg, hdr, exr, ktx2, dds, ktx, env, gltf"
        );
        for &f in FileFormat::ALL {
            for ext in f.extensions() {
                let upper = format!("x.{}", ext.to_ascii_uppercase());
                assert_eq!(FileFormat::from_path(Path::new(&upper)).ok(), Some(f));
            }
            let mut head = f.magic().to_vec();
            head.extend_from_slice(&[0; 8]);
            assert_eq!(FileFormat::from_bytes(&head), Some(f), "{}", f.name());
        }
        assert_eq!(FileFormat::from_bytes(b"GIF89a"), None);
        assert!(FileFormat::from_path(Path::new("x.gif")).is_err());
        assert!(FileFormat::from_path(Path::new("exr")).is_err());
    }
}
