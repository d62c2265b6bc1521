//! Loading and saving environment maps: PNG, JPEG, Radiance HDR, OpenEXR,
//! and cubes as six files.
//!
//! | extension | read | write |
//! | --- | --- | --- |
//! | `.png` | 8- or 16-bit grey, grey+alpha, RGB, RGBA; sRGB decoded to linear | 8-bit sRGB RGB after exposure, clamped |
//! | `.jpg`, `.jpeg` | 8-bit grey or RGB (CMYK converted); sRGB decoded to linear | 8-bit sRGB, quality 95, after exposure |
//! | `.hdr` | Radiance RGBE, linear | Radiance RGBE, linear (within RGBE precision, ~1 %) |
//! | `.exr` | R, G, B channels (any of f16, f32, u32) of the first layer that has them; alpha and other channels ignored | f32 RGB (bit for bit), or f16 |
//!
//! The format is chosen by the extension, case-insensitively. Alpha is
//! dropped. Colour profiles and PNG gamma chunks are ignored: 8- and 16-bit
//! files are taken as sRGB and decoded with the exact sRGB EOTF
//! ([`srgb_to_linear`]).
//!
//! # Six-file cubes
//!
//! A cube can be written as six square files `<stem>_+x.<ext>`, `<stem>_-x.<ext>`,
//! ..., `<stem>_-z.<ext>` (the names of [`CubeFace::name`]), each face exactly
//! as GL expects it for `GL_TEXTURE_CUBE_MAP_POSITIVE_X + face`. A path with
//! `{face}` in its file name is a pattern (`sky_{face}.exr`). A six-file cube
//! is loaded from the pattern, from any one of the six names (the siblings
//! are found), or from `<stem>.<ext>` with [`Layout::Faces`]; in memory it
//! becomes a horizontal strip.
//!
//! # Safe writes
//!
//! Every output goes to a temporary file in the target's directory, which is
//! renamed over the target only once it is complete; an error (a full disk,
//! a missing directory, a target that is a directory) removes the temporary
//! file and leaves any existing file at the target untouched. Six-file
//! outputs write all six temporary files before renaming any. Writing over
//! an input file (compared by canonical path, and on Unix by device and
//! inode) is refused unless [`SaveOptions::overwrite_input`] is set.
//!
//! # Untrusted files
//!
//! Sizes are checked against [`LoadOptions::max_texels`] from the header,
//! before pixel memory is allocated; corrupt or truncated files give an
//! [`Error`] naming the file, never a panic. NaN and infinite texels are
//! kept or replaced by black as [`LoadOptions::non_finite`] says (see
//! [`NonFinite`]).

use std::fs::{self, File};
use std::io::{BufReader, BufWriter, Seek, SeekFrom, Write};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use envmap_core::{AnyMapping, CubeFace, Frame};
use image::{DynamicImage, ImageDecoder, ImageEncoder, ImageReader};
use tempfile::NamedTempFile;

use crate::error::{Error, Result};
use crate::image::{check_size, EnvImage, Representation, RgbImage, DEFAULT_MAX_TEXELS};
use crate::layout::{resolve, Layout};

/// An image file format, chosen by extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum FileFormat {
    /// PNG (`.png`): 8- or 16-bit sRGB.
    Png,
    /// JPEG (`.jpg`, `.jpeg`): 8-bit sRGB.
    Jpeg,
    /// Radiance RGBE (`.hdr`): linear floating point, shared exponent.
    Hdr,
    /// OpenEXR (`.exr`): linear f16 or f32.
    Exr,
}

impl FileFormat {
    /// The accepted extensions, as listed in error messages.
    pub const EXTENSIONS: &'static str = "png, jpg, jpeg, hdr, exr";

    /// The format of a path's extension (case-insensitive); an error naming
    /// the file and the accepted extensions otherwise.
    pub fn from_path(path: &Path) -> Result<FileFormat> {
        let ext = path.extension().map(|e| e.to_string_lossy().into_owned());
        let format = match ext.as_deref().map(str::to_ascii_lowercase).as_deref() {
            Some("png") => FileFormat::Png,
            Some("jpg" | "jpeg") => FileFormat::Jpeg,
            Some("hdr") => FileFormat::Hdr,
            Some("exr") => FileFormat::Exr,
            _ => {
                return Err(Error::UnknownExtension {
                    path: path.to_path_buf(),
                    extension: ext,
                    accepted: Self::EXTENSIONS,
                })
            }
        };
        Ok(format)
    }

    /// The format's usual name (`"PNG"`, `"OpenEXR"`, ...).
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            FileFormat::Png => "PNG",
            FileFormat::Jpeg => "JPEG",
            FileFormat::Hdr => "Radiance HDR",
            FileFormat::Exr => "OpenEXR",
        }
    }

    /// Whether the format stores linear floating-point values (HDR, EXR)
    /// rather than 8- or 16-bit sRGB.
    #[must_use]
    pub const fn is_float(self) -> bool {
        matches!(self, FileFormat::Hdr | FileFormat::Exr)
    }
}

/// What a file held, for reporting (`envmap info`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SourceFormat {
    /// The container format.
    pub format: FileFormat,
    /// The stored pixels, e.g. `"16-bit sRGB RGBA (alpha dropped)"` or
    /// `"f16 RGBA (channels R, G, B, A; A ignored)"`.
    pub pixel_format: String,
}

/// How to load an environment map.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LoadOptions {
    /// The mapping, if known; detected from the aspect ratio otherwise
    /// (see [`crate::layout::resolve`]).
    pub mapping: Option<AnyMapping>,
    /// The layout, if known; [`Layout::Faces`] loads six files.
    pub layout: Option<Layout>,
    /// The axis convention to tag the image with.
    pub frame: Frame,
    /// Largest image accepted, in texels (all six faces together for a
    /// six-file cube); checked before allocating.
    pub max_texels: u64,
    /// What to do with texels that hold a NaN or infinite value.
    pub non_finite: NonFinite,
}

/// What loading does with texels that hold a NaN or an infinite component
/// (only OpenEXR can store them; 8-bit, 16-bit and RGBE files cannot).
///
/// Sampling and conversion do not single such texels out: a bilinear filter
/// or a sub-sample average that touches one gives NaN or infinity, so one
/// bad texel of an input spreads over every output texel whose footprint
/// covers it. [`NonFinite::Zero`] stops that at load time; `envmap info`
/// loads with [`NonFinite::Keep`] to count them, and `envmap convert` and
/// `envmap render` load with [`NonFinite::Zero`] and say how many texels
/// they replaced.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum NonFinite {
    /// Keep the values as stored (so that files round-trip bit for bit);
    /// [`EnvImage::stats`] counts them.
    #[default]
    Keep,
    /// Replace every texel that has a NaN or infinite component by black
    /// (all three components 0); [`Loaded::replaced`] counts them.
    Zero,
}

impl Default for LoadOptions {
    fn default() -> Self {
        Self {
            mapping: None,
            layout: None,
            frame: Frame::IDENTITY,
            max_texels: DEFAULT_MAX_TEXELS,
            non_finite: NonFinite::Keep,
        }
    }
}

/// Sample type of OpenEXR output.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ExrPrecision {
    /// 32-bit float: every value kept bit for bit.
    #[default]
    F32,
    /// 16-bit half float: half the size; values above 65504 become infinite.
    F16,
}

/// How to save an environment map.
#[derive(Clone, Debug, PartialEq)]
pub struct SaveOptions {
    /// Exposure in stops for 8-bit outputs (PNG, JPEG): values are scaled by
    /// 2^`exposure` before encoding. Float outputs keep their values.
    pub exposure: f32,
    /// Sample type of OpenEXR output.
    pub exr_precision: ExrPrecision,
    /// Write a cube as six files (also implied by `{face}` in the file name).
    pub six_files: bool,
    /// The files the image was read from: writing over one of them is
    /// refused unless [`overwrite_input`](SaveOptions::overwrite_input) is set.
    pub inputs: Vec<PathBuf>,
    /// Allow writing over a file listed in [`inputs`](SaveOptions::inputs).
    pub overwrite_input: bool,
}

impl Default for SaveOptions {
    fn default() -> Self {
        Self {
            exposure: 0.0,
            exr_precision: ExrPrecision::F32,
            six_files: false,
            inputs: Vec::new(),
            overwrite_input: false,
        }
    }
}

/// A loaded environment map with where it came from.
#[derive(Clone, Debug, PartialEq)]
pub struct Loaded {
    /// The image.
    pub image: EnvImage,
    /// The file format and pixel format read (of the first face, for six files).
    pub source: SourceFormat,
    /// The files read: one, or the six faces in GL order.
    pub files: Vec<PathBuf>,
    /// Texels replaced by black under [`NonFinite::Zero`] (over all the
    /// image, inside the charts or not); 0 under [`NonFinite::Keep`].
    pub replaced: u64,
}

/// Replaces texels with a NaN or infinite component by black, as `policy`
/// says; returns how many were replaced.
fn apply_non_finite(pixels: &mut [[f32; 3]], policy: NonFinite) -> u64 {
    if policy == NonFinite::Keep {
        return 0;
    }
    let mut n = 0;
    for p in pixels
        .iter_mut()
        .filter(|p| !p.iter().all(|c| c.is_finite()))
    {
        *p = [0.0; 3];
        n += 1;
    }
    n
}

// ---------------------------------------------------------------------------
// sRGB transfer functions

/// The exact sRGB EOTF (IEC 61966-2-1): encoded value in `[0, 1]` → linear.
///
/// `c / 12.92` up to 0.04045, `((c + 0.055) / 1.055)^2.4` above; computed
/// in f64 and rounded once. `srgb_to_linear(128.0 / 255.0)` is 0.2158605 (to 7 digits).
#[must_use]
pub fn srgb_to_linear(c: f32) -> f32 {
    let c = f64::from(c);
    let l = if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    };
    l as f32
}

/// The sRGB OETF: linear → encoded value in `[0, 1]` (clamped; NaN → 0).
#[must_use]
pub fn linear_to_srgb(l: f32) -> f32 {
    if l.is_nan() {
        return 0.0;
    }
    let l = f64::from(l.clamp(0.0, 1.0));
    let c = if l <= 0.003_130_8 {
        12.92 * l
    } else {
        1.055 * l.powf(1.0 / 2.4) - 0.055
    };
    c as f32
}

/// Linear → 8-bit sRGB code: the code whose exact EOTF value is nearest in
/// the encoded domain (the decision points are the EOTF of the half codes).
/// Clamps; NaN and negative values give 0, `+∞` gives 255. Every code `k`
/// maps back to itself: `linear_to_srgb8(srgb_to_linear(k / 255)) == k`.
#[must_use]
pub fn linear_to_srgb8(l: f32) -> u8 {
    // Count of thresholds ≤ l: 0 for NaN (every comparison is false).
    srgb8_thresholds().partition_point(|&t| t <= l) as u8
}

fn srgb8_thresholds() -> &'static [f32; 255] {
    static T: OnceLock<[f32; 255]> = OnceLock::new();
    T.get_or_init(|| {
        let mut t = [0.0f32; 255];
        for (k, v) in t.iter_mut().enumerate() {
            *v = srgb_to_linear((k as f32 + 0.5) / 255.0);
        }
        t
    })
}

fn srgb8_lut() -> &'static [f32; 256] {
    static T: OnceLock<[f32; 256]> = OnceLock::new();
    T.get_or_init(|| {
        let mut t = [0.0f32; 256];
        for (k, v) in t.iter_mut().enumerate() {
            *v = srgb_to_linear(k as f32 / 255.0);
        }
        t
    })
}

fn srgb16_lut() -> &'static [f32] {
    static T: OnceLock<Vec<f32>> = OnceLock::new();
    T.get_or_init(|| {
        (0..=u16::MAX)
            .map(|k| srgb_to_linear(f32::from(k) / 65535.0))
            .collect()
    })
}

// ---------------------------------------------------------------------------
// Six-file names

/// The placeholder for the face name in a six-file pattern.
pub const FACE_PLACEHOLDER: &str = "{face}";

/// Whether the file name holds a [`FACE_PLACEHOLDER`] pattern.
#[must_use]
pub fn is_face_pattern(path: &Path) -> bool {
    path.file_name()
        .is_some_and(|n| n.to_string_lossy().contains(FACE_PLACEHOLDER))
}

/// The face a file name names by its `_+x` ... `_-z` suffix, if any.
#[must_use]
pub fn face_of_name(path: &Path) -> Option<CubeFace> {
    let stem = path.file_stem()?.to_str()?;
    CubeFace::ALL.into_iter().find(|f| {
        stem.strip_suffix(f.name())
            .is_some_and(|s| s.ends_with('_'))
    })
}

/// The six face files of a cube, in GL order (+x, −x, +y, −y, +z, −z).
///
/// `path` may be a pattern (`sky_{face}.exr` → `sky_+x.exr`, ...), one of the
/// six names (`sky_-y.exr` → its siblings), or a plain name (`sky.exr` →
/// `sky_+x.exr`, ...).
pub fn face_paths(path: &Path) -> Result<[PathBuf; 6]> {
    let bad = || Error::layout("cannot name six cube faces after this path").in_file(path);
    let name = path.file_name().and_then(|n| n.to_str()).ok_or_else(bad)?;
    let dir = path.parent().unwrap_or(Path::new(""));
    let names: Vec<String> = if name.contains(FACE_PLACEHOLDER) {
        CubeFace::ALL
            .iter()
            .map(|f| name.replace(FACE_PLACEHOLDER, f.name()))
            .collect()
    } else {
        let stem = path.file_stem().and_then(|s| s.to_str()).ok_or_else(bad)?;
        let ext = path.extension().and_then(|s| s.to_str()).ok_or_else(bad)?;
        let base = match face_of_name(path) {
            Some(f) => &stem[..stem.len() - f.name().len() - 1],
            None => stem,
        };
        CubeFace::ALL
            .iter()
            .map(|f| format!("{base}_{}.{ext}", f.name()))
            .collect()
    };
    Ok(std::array::from_fn(|i| dir.join(&names[i])))
}

// ---------------------------------------------------------------------------
// Reading

fn decode_error(path: &Path, format: FileFormat, message: impl ToString) -> Error {
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

fn open(path: &Path) -> Result<File> {
    let file = File::open(path).map_err(|e| Error::read(path, e))?;
    match file.metadata() {
        Ok(m) if m.is_dir() => Err(Error::read(
            path,
            std::io::Error::new(std::io::ErrorKind::InvalidInput, "is a directory"),
        )),
        _ => Ok(file),
    }
}

/// The size of an image file, from its header alone.
pub fn read_dimensions(path: &Path) -> Result<(u32, u32)> {
    let format = FileFormat::from_path(path)?;
    let file = open(path)?;
    guarded(path, format, || match format {
        FileFormat::Exr => {
            let meta = exr::meta::MetaData::read_from_buffered(BufReader::new(file), false)
                .map_err(|e| decode_error(path, format, e))?;
            let header = rgb_header(path, &meta)?;
            exr_size(path, header)
        }
        _ => {
            let reader = ImageReader::with_format(BufReader::new(file), image_format(format));
            reader
                .into_dimensions()
                .map_err(|e| decode_error(path, format, e))
        }
    })
}

/// Reads an image file as linear RGB, with no representation attached.
///
/// Refuses images above `max_texels` before allocating their pixels.
pub fn read_rgb(path: &Path, max_texels: u64) -> Result<(RgbImage, SourceFormat)> {
    let format = FileFormat::from_path(path)?;
    let file = open(path)?;
    guarded(path, format, || match format {
        FileFormat::Exr => read_exr(path, file, max_texels),
        _ => read_with_image(path, file, format, max_texels),
    })
}

fn image_format(format: FileFormat) -> image::ImageFormat {
    match format {
        FileFormat::Png => image::ImageFormat::Png,
        FileFormat::Jpeg => image::ImageFormat::Jpeg,
        FileFormat::Hdr => image::ImageFormat::Hdr,
        FileFormat::Exr => image::ImageFormat::OpenExr,
    }
}

fn read_with_image(
    path: &Path,
    file: File,
    format: FileFormat,
    max_texels: u64,
) -> Result<(RgbImage, SourceFormat)> {
    let err = |e: image::ImageError| decode_error(path, format, e);
    let reader = ImageReader::with_format(BufReader::new(file), image_format(format));
    let mut decoder = reader.into_decoder().map_err(err)?;
    let (width, height) = decoder.dimensions();
    if width == 0 || height == 0 {
        return Err(decode_error(path, format, "the image is empty"));
    }
    check_size(width, height, 1, max_texels).map_err(|e| e.in_file(path))?;
    // Our own limit is checked; let the decoder allocate what this size needs.
    let mut limits = image::Limits::no_limits();
    limits.max_alloc = Some(decoder.total_bytes().saturating_add(64 << 20));
    decoder.set_limits(limits).map_err(err)?;
    let decoded = DynamicImage::from_decoder(decoder).map_err(err)?;
    let pixel_format = |desc: &str| match format {
        FileFormat::Hdr => "RGBE (shared 8-bit exponent), linear".to_owned(),
        _ => desc.to_owned(),
    };
    let source = |desc: &str| SourceFormat {
        format,
        pixel_format: pixel_format(desc),
    };
    // Float RGB (what the HDR decoder gives): the decoder's buffer becomes
    // the texels as it is, so loading needs no second copy of the image.
    let decoded = match decoded {
        DynamicImage::ImageRgb32F(b) => {
            let raw = b.into_raw();
            let pixels = bytemuck::allocation::try_cast_vec::<f32, [f32; 3]>(raw)
                .unwrap_or_else(|(_, raw)| expand(&raw, 3, |v| v));
            let rgb = RgbImage {
                width,
                height,
                pixels,
            };
            return Ok((rgb, source("32-bit float RGB")));
        }
        other => other,
    };

    let l8 = |v: u8| srgb8_lut()[usize::from(v)];
    let l16 = |v: u16| srgb16_lut()[usize::from(v)];
    let lin = |v: f32| v;
    let (pixels, desc) = match &decoded {
        DynamicImage::ImageLuma8(b) => (expand(b.as_raw(), 1, l8), "8-bit sRGB grey"),
        DynamicImage::ImageLumaA8(b) => (
            expand(b.as_raw(), 2, l8),
            "8-bit sRGB grey+alpha (alpha dropped)",
        ),
        DynamicImage::ImageRgb8(b) => (expand(b.as_raw(), 3, l8), "8-bit sRGB RGB"),
        DynamicImage::ImageRgba8(b) => {
            (expand(b.as_raw(), 4, l8), "8-bit sRGB RGBA (alpha dropped)")
        }
        DynamicImage::ImageLuma16(b) => (expand(b.as_raw(), 1, l16), "16-bit sRGB grey"),
        DynamicImage::ImageLumaA16(b) => (
            expand(b.as_raw(), 2, l16),
            "16-bit sRGB grey+alpha (alpha dropped)",
        ),
        DynamicImage::ImageRgb16(b) => (expand(b.as_raw(), 3, l16), "16-bit sRGB RGB"),
        DynamicImage::ImageRgba16(b) => (
            expand(b.as_raw(), 4, l16),
            "16-bit sRGB RGBA (alpha dropped)",
        ),
        DynamicImage::ImageRgba32F(b) => (
            expand(b.as_raw(), 4, lin),
            "32-bit float RGBA (alpha dropped)",
        ),
        other if format.is_float() => (expand(other.to_rgb32f().as_raw(), 3, lin), "float RGB"),
        other => (expand(other.to_rgb16().as_raw(), 3, l16), "sRGB RGB"),
    };
    Ok((
        RgbImage {
            width,
            height,
            pixels,
        },
        source(desc),
    ))
}

/// Interleaved samples with `channels` per texel → RGB (grey replicated,
/// alpha dropped).
fn expand<T: Copy>(raw: &[T], channels: usize, f: impl Fn(T) -> f32) -> Vec<[f32; 3]> {
    if channels < 3 {
        raw.chunks_exact(channels)
            .map(|p| {
                let v = f(p[0]);
                [v, v, v]
            })
            .collect()
    } else {
        raw.chunks_exact(channels)
            .map(|p| [f(p[0]), f(p[1]), f(p[2])])
            .collect()
    }
}

fn exr_has(header: &exr::meta::header::Header, name: &str) -> bool {
    header.channels.list.iter().any(|c| c.name.eq(name))
}

/// The first layer (header) with R, G and B channels.
fn rgb_header<'m>(
    path: &Path,
    meta: &'m exr::meta::MetaData,
) -> Result<&'m exr::meta::header::Header> {
    meta.headers
        .iter()
        .find(|h| exr_has(h, "R") && exr_has(h, "G") && exr_has(h, "B"))
        .ok_or_else(|| {
            let mut found: Vec<String> = Vec::new();
            for h in &meta.headers {
                for c in &h.channels.list {
                    found.push(c.name.to_string());
                }
            }
            Error::MissingChannels {
                path: path.to_path_buf(),
                found: if found.is_empty() {
                    "none".to_owned()
                } else {
                    found.join(", ")
                },
            }
        })
}

fn exr_size(path: &Path, header: &exr::meta::header::Header) -> Result<(u32, u32)> {
    let size = header.layer_size;
    match (u32::try_from(size.width()), u32::try_from(size.height())) {
        (Ok(w), Ok(h)) if w > 0 && h > 0 => Ok((w, h)),
        _ => Err(decode_error(
            path,
            FileFormat::Exr,
            format!("the layer is {}×{}", size.width(), size.height()),
        )),
    }
}

fn sample_name(t: exr::meta::attribute::SampleType) -> &'static str {
    match t {
        exr::meta::attribute::SampleType::F16 => "f16",
        exr::meta::attribute::SampleType::F32 => "f32",
        exr::meta::attribute::SampleType::U32 => "u32",
    }
}

fn read_exr(path: &Path, file: File, max_texels: u64) -> Result<(RgbImage, SourceFormat)> {
    use exr::prelude::{ReadChannels, ReadLayers, ReadSpecificChannel};

    let format = FileFormat::Exr;
    let err = |e: exr::error::Error| decode_error(path, format, e);
    let mut reader = BufReader::new(file);
    let meta = exr::meta::MetaData::read_from_buffered(&mut reader, false).map_err(err)?;
    let header = rgb_header(path, &meta)?;
    if header.deep {
        return Err(decode_error(path, format, "deep data is not supported"));
    }
    let (width, height) = exr_size(path, header)?;
    let n = check_size(width, height, 1, max_texels).map_err(|e| e.in_file(path))?;

    let channels: Vec<String> = header
        .channels
        .list
        .iter()
        .map(|c| c.name.to_string())
        .collect();
    let types: Vec<&str> = ["R", "G", "B"]
        .iter()
        .filter_map(|n| header.channels.list.iter().find(|c| c.name.eq(n)))
        .map(|c| sample_name(c.sample_type))
        .collect();
    let sample = if types.iter().all(|t| *t == types[0]) {
        types[0].to_owned()
    } else {
        types.join("/")
    };
    let others: Vec<&str> = channels
        .iter()
        .map(String::as_str)
        .filter(|c| !matches!(*c, "R" | "G" | "B"))
        .collect();
    let pixel_format = if others.is_empty() {
        format!("{sample} RGB")
    } else if others == ["A"] {
        format!("{sample} RGBA (alpha dropped)")
    } else {
        format!(
            "{sample} RGB (other channels ignored: {})",
            others.join(", ")
        )
    };

    reader
        .seek(SeekFrom::Start(0))
        .map_err(|e| Error::read(path, e))?;
    let image = exr::prelude::read()
        .no_deep_data()
        .largest_resolution_level()
        .specific_channels()
        .required("R")
        .required("G")
        .required("B")
        .collect_pixels(
            move |size, _| (size.width(), vec![[0.0f32; 3]; n.min(size.area())]),
            |store: &mut (usize, Vec<[f32; 3]>), pos, (r, g, b): (f32, f32, f32)| {
                let i = pos.y() * store.0 + pos.x();
                if let Some(p) = store.1.get_mut(i) {
                    *p = [r, g, b];
                }
            },
        )
        .first_valid_layer()
        .all_attributes()
        .from_buffered(reader)
        .map_err(err)?;
    let layer = image.layer_data;
    let (w, h) = (layer.size.width(), layer.size.height());
    if (w, h) != (width as usize, height as usize) {
        return Err(decode_error(
            path,
            format,
            format!("the layer read is {w}×{h}, its header said {width}×{height}"),
        ));
    }
    Ok((
        RgbImage {
            width,
            height,
            pixels: layer.channel_data.pixels.1,
        },
        SourceFormat {
            format,
            pixel_format,
        },
    ))
}

/// Whether a load of `path` with `opts` reads six face files.
fn loads_six_files(path: &Path, opts: &LoadOptions) -> bool {
    match opts.layout {
        Some(l) => l.is_six_files(),
        None => {
            opts.mapping.is_none_or(|m| m == AnyMapping::Cube)
                && (is_face_pattern(path) || face_of_name(path).is_some())
        }
    }
}

/// Loads an environment map; see [`load_detailed`].
pub fn load(path: impl AsRef<Path>, opts: &LoadOptions) -> Result<EnvImage> {
    load_detailed(path, opts).map(|l| l.image)
}

/// Loads an environment map, with the format read and the files it came from.
///
/// The representation comes from `opts` or, when not given, from the
/// aspect ratio ([`crate::layout::resolve`]). A six-file cube is read when
/// `opts.layout` is [`Layout::Faces`], or (with no layout given and no
/// mapping other than cube) when the file name is a `{face}` pattern or
/// one of the six names; see the [module docs](self).
pub fn load_detailed(path: impl AsRef<Path>, opts: &LoadOptions) -> Result<Loaded> {
    let path = path.as_ref();
    if loads_six_files(path, opts) {
        return load_faces(path, opts);
    }
    let (mut rgb, source) = read_rgb(path, opts.max_texels)?;
    let replaced = apply_non_finite(&mut rgb.pixels, opts.non_finite);
    let (mapping, atlas) =
        resolve(rgb.width, rgb.height, opts.mapping, opts.layout).map_err(|e| e.in_file(path))?;
    let repr = Representation {
        mapping,
        atlas,
        frame: opts.frame,
    };
    let image = EnvImage::from_rgb(rgb, repr).map_err(|e| e.in_file(path))?;
    Ok(Loaded {
        image,
        source,
        files: vec![path.to_path_buf()],
        replaced,
    })
}

fn load_faces(path: &Path, opts: &LoadOptions) -> Result<Loaded> {
    if let Some(m) = opts.mapping.filter(|m| *m != AnyMapping::Cube) {
        return Err(Error::layout(format!("six files hold a cube, not a {m} map")).in_file(path));
    }
    let paths = face_paths(path)?;
    FileFormat::from_path(&paths[0])?;
    for (p, f) in paths.iter().zip(CubeFace::ALL) {
        if !p.is_file() {
            return Err(Error::CubeFaces {
                path: p.clone(),
                message: format!(
                    "face {} of the six-file cube is missing (expected {})",
                    f.name(),
                    name_list(&paths)
                ),
            });
        }
    }
    let mut size = None;
    for (p, f) in paths.iter().zip(CubeFace::ALL) {
        let (w, h) = read_dimensions(p)?;
        if w != h {
            return Err(Error::CubeFaces {
                path: p.clone(),
                message: format!("face {} is {w}×{h}; cube faces must be square", f.name()),
            });
        }
        match size {
            None => size = Some(w),
            Some(s) if s != w => {
                return Err(Error::CubeFaces {
                    path: p.clone(),
                    message: format!(
                        "face {} is {w}×{h}, but face +x ({}) is {s}×{s}; all six faces must be the same size",
                        f.name(),
                        paths[0].display()
                    ),
                })
            }
            Some(_) => {}
        }
    }
    let s = size.unwrap_or(0);
    check_size(s, s, 6, opts.max_texels).map_err(|e| e.in_file(&paths[0]))?;
    let repr = Representation {
        mapping: AnyMapping::Cube,
        atlas: Layout::Faces.atlas(),
        frame: opts.frame,
    };
    let mut image = EnvImage::new_with_limit(6 * s, s, repr, opts.max_texels)
        .map_err(|e| e.in_file(&paths[0]))?;
    let mut source = None;
    let mut replaced = 0;
    for (chart, p) in (0u32..).zip(&paths) {
        let (mut face, src) = read_rgb(p, opts.max_texels)?;
        replaced += apply_non_finite(&mut face.pixels, opts.non_finite);
        if (face.width, face.height) != (s, s) {
            // The header said otherwise a moment ago: the file changed.
            return Err(Error::CubeFaces {
                path: p.clone(),
                message: format!(
                    "face changed size while loading ({}×{})",
                    face.width, face.height
                ),
            });
        }
        image
            .set_chart_image(chart, &face)
            .map_err(|e| e.in_file(p))?;
        source.get_or_insert(src);
    }
    Ok(Loaded {
        image,
        source: source.unwrap_or(SourceFormat {
            format: FileFormat::from_path(&paths[0])?,
            pixel_format: String::new(),
        }),
        files: paths.to_vec(),
        replaced,
    })
}

fn name_list(paths: &[PathBuf]) -> String {
    let names: Vec<String> = paths
        .iter()
        .map(|p| {
            p.file_name()
                .unwrap_or_default()
                .to_string_lossy()
                .into_owned()
        })
        .collect();
    names.join(", ")
}

// ---------------------------------------------------------------------------
// Writing

/// A borrowed RGB image to encode.
#[derive(Clone, Copy)]
struct View<'a> {
    width: u32,
    height: u32,
    pixels: &'a [[f32; 3]],
}

/// Saves an environment map; returns the files written (one, or six faces
/// in GL order).
///
/// The format follows the extension. A cube is written as six files when
/// [`SaveOptions::six_files`] is set or the file name is a `{face}` pattern;
/// otherwise the image is written in its atlas as is. Writes are atomic
/// and refuse to replace an input; see the [module docs](self).
pub fn save(image: &EnvImage, path: impl AsRef<Path>, opts: &SaveOptions) -> Result<Vec<PathBuf>> {
    let path = path.as_ref();
    let format = FileFormat::from_path(path)?;
    if opts.six_files || is_face_pattern(path) {
        if image.mapping() != AnyMapping::Cube {
            return Err(Error::layout(format!(
                "only a cube can be saved as six files; this image is a {} map",
                image.mapping()
            ))
            .in_file(path));
        }
        let paths = face_paths(path)?;
        for p in &paths {
            check_target(p, opts)?;
        }
        let mut temps = Vec::with_capacity(6);
        for (chart, p) in (0u32..).zip(&paths) {
            let face = image
                .chart_image(chart)
                .ok_or_else(|| Error::layout(format!("the image has no face {chart}")))?;
            let view = View {
                width: face.width,
                height: face.height,
                pixels: &face.pixels,
            };
            temps.push(write_temp(p, format, view, opts)?);
        }
        for (temp, p) in temps.into_iter().zip(&paths) {
            persist(temp, p)?;
        }
        return Ok(paths.to_vec());
    }
    check_target(path, opts)?;
    let view = View {
        width: image.width(),
        height: image.height(),
        pixels: image.pixels(),
    };
    let temp = write_temp(path, format, view, opts)?;
    persist(temp, path)?;
    Ok(vec![path.to_path_buf()])
}

/// Writes a plain RGB image (atomically, refusing to replace an input, as
/// [`save`] does).
pub fn write_rgb(image: &RgbImage, path: impl AsRef<Path>, opts: &SaveOptions) -> Result<()> {
    let path = path.as_ref();
    let format = FileFormat::from_path(path)?;
    if u64::try_from(image.pixels.len()).ok()
        != Some(u64::from(image.width) * u64::from(image.height))
        || image.pixels.is_empty()
    {
        return Err(Error::PixelCount {
            width: image.width,
            height: image.height,
            len: image.pixels.len(),
        }
        .in_file(path));
    }
    check_target(path, opts)?;
    let view = View {
        width: image.width,
        height: image.height,
        pixels: &image.pixels,
    };
    let temp = write_temp(path, format, view, opts)?;
    persist(temp, path)
}

/// Checks a target before any encoding: not a directory (so that a six-file
/// write does not fail halfway through its renames), not an input.
fn check_target(target: &Path, opts: &SaveOptions) -> Result<()> {
    if target.is_dir() {
        return Err(Error::write(
            target,
            std::io::Error::new(std::io::ErrorKind::IsADirectory, "is a directory"),
        ));
    }
    check_not_input(target, opts)
}

/// Refuses `target` if it is one of `opts.inputs` (same canonical path, or
/// on Unix the same device and inode) unless overwriting was asked for.
fn check_not_input(target: &Path, opts: &SaveOptions) -> Result<()> {
    if opts.overwrite_input || opts.inputs.is_empty() {
        return Ok(());
    }
    // A target that does not exist cannot be an existing input.
    let Ok(t) = fs::canonicalize(target) else {
        return Ok(());
    };
    let t_meta = fs::metadata(&t).ok();
    for input in &opts.inputs {
        let same_path = fs::canonicalize(input).is_ok_and(|i| i == t);
        let same_file = match (&t_meta, fs::metadata(input).ok()) {
            (Some(a), Some(b)) => same_inode(a, &b),
            _ => false,
        };
        if same_path || same_file {
            return Err(Error::WouldOverwriteInput {
                path: target.to_path_buf(),
            });
        }
    }
    Ok(())
}

#[cfg(unix)]
fn same_inode(a: &fs::Metadata, b: &fs::Metadata) -> bool {
    use std::os::unix::fs::MetadataExt;
    a.dev() == b.dev() && a.ino() == b.ino()
}

#[cfg(not(unix))]
fn same_inode(_: &fs::Metadata, _: &fs::Metadata) -> bool {
    false
}

/// Encodes `view` into a new temporary file beside `path`.
fn write_temp(
    path: &Path,
    format: FileFormat,
    view: View<'_>,
    opts: &SaveOptions,
) -> Result<NamedTempFile> {
    let name = path.file_name().ok_or_else(|| {
        Error::write(
            path,
            std::io::Error::new(std::io::ErrorKind::InvalidInput, "not a file name"),
        )
    })?;
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let mut prefix = std::ffi::OsString::from(".");
    prefix.push(name);
    prefix.push(".");
    let mut builder = tempfile::Builder::new();
    builder.prefix(&prefix).suffix(".tmp");
    #[cfg(unix)]
    {
        // As an ordinary new file: 0666 less the umask (not tempfile's 0600).
        use std::os::unix::fs::PermissionsExt;
        builder.permissions(fs::Permissions::from_mode(0o666));
    }
    if !dir.is_dir() {
        let msg = format!("directory {} does not exist", dir.display());
        let e = std::io::Error::new(std::io::ErrorKind::NotFound, msg);
        return Err(Error::write(path, e));
    }
    let mut temp = builder
        .tempfile_in(dir)
        .map_err(|e| Error::write(path, plain_io_error(e)))?;
    {
        let mut out = BufWriter::with_capacity(1 << 20, temp.as_file_mut());
        encode(path, format, view, opts, &mut out)?;
        out.flush().map_err(|e| Error::write(path, e))?;
    }
    temp.as_file()
        .sync_all()
        .map_err(|e| Error::write(path, e))?;
    // Replacing a file keeps its permissions.
    if let Ok(meta) = fs::metadata(path) {
        if meta.is_file() {
            let _ = temp.as_file().set_permissions(meta.permissions());
        }
    }
    Ok(temp)
}

/// The operating system's error inside one of `tempfile`'s, which adds the
/// temporary file's name (of no interest to the user, who named the target).
fn plain_io_error(e: std::io::Error) -> std::io::Error {
    if e.get_ref().is_none() {
        return e; // a plain operating-system error
    }
    // tempfile's wrapper displays as "<error> at path \"<temporary file>\"".
    let msg = e.to_string();
    let inner = msg
        .rsplit_once(" at path ")
        .map_or(msg.as_str(), |(m, _)| m);
    let code = inner
        .strip_suffix(')')
        .and_then(|m| m.rsplit_once("(os error "))
        .and_then(|(_, n)| n.parse::<i32>().ok());
    match code {
        Some(code) => std::io::Error::from_raw_os_error(code),
        None => std::io::Error::new(e.kind(), inner.to_owned()),
    }
}

/// Renames a finished temporary file over `path`; on failure the temporary
/// file is removed.
fn persist(temp: NamedTempFile, path: &Path) -> Result<()> {
    temp.persist(path)
        .map(drop)
        .map_err(|e| Error::write(path, plain_io_error(e.error)))
}

fn encode<W: Write + Seek>(
    path: &Path,
    format: FileFormat,
    view: View<'_>,
    opts: &SaveOptions,
    out: &mut W,
) -> Result<()> {
    let enc_err = |e: &dyn std::fmt::Display| Error::Encode {
        path: path.to_path_buf(),
        format: format.name(),
        message: e.to_string(),
    };
    // An I/O failure while encoding is a write error, not an encoding one.
    let image_err = |e: image::ImageError| match e {
        image::ImageError::IoError(io) => Error::write(path, io),
        other => enc_err(&other),
    };
    match format {
        FileFormat::Png | FileFormat::Jpeg => {
            let scale = opts.exposure.exp2();
            let bytes: Vec<u8> = view
                .pixels
                .iter()
                .flat_map(|p| p.map(|c| linear_to_srgb8(c * scale)))
                .collect();
            let color = image::ExtendedColorType::Rgb8;
            if format == FileFormat::Png {
                image::codecs::png::PngEncoder::new(out)
                    .write_image(&bytes, view.width, view.height, color)
                    .map_err(image_err)
            } else {
                image::codecs::jpeg::JpegEncoder::new_with_quality(out, 95)
                    .write_image(&bytes, view.width, view.height, color)
                    .map_err(image_err)
            }
        }
        FileFormat::Hdr => {
            // RGBE holds non-negative finite values only.
            let px: Vec<image::Rgb<f32>> = view
                .pixels
                .iter()
                .map(|p| {
                    image::Rgb(p.map(|c| {
                        if c.is_nan() {
                            0.0
                        } else {
                            c.clamp(0.0, f32::MAX)
                        }
                    }))
                })
                .collect();
            image::codecs::hdr::HdrEncoder::new(out)
                .encode(&px, view.width as usize, view.height as usize)
                .map_err(image_err)
        }
        FileFormat::Exr => {
            use exr::prelude::{f16, Encoding, Image, SpecificChannels, Vec2, WritableImage};
            let w = view.width as usize;
            let size = (w, view.height as usize);
            let px = view.pixels;
            let result = match opts.exr_precision {
                ExrPrecision::F32 => Image::from_encoded_channels(
                    size,
                    Encoding::FAST_LOSSLESS,
                    SpecificChannels::rgb(|Vec2(x, y): Vec2<usize>| {
                        let p = px[y * w + x];
                        (p[0], p[1], p[2])
                    }),
                )
                .write()
                .to_buffered(&mut *out),
                ExrPrecision::F16 => Image::from_encoded_channels(
                    size,
                    Encoding::FAST_LOSSLESS,
                    SpecificChannels::rgb(|Vec2(x, y): Vec2<usize>| {
                        let p = px[y * w + x];
                        (
                            f16::from_f32(p[0]),
                            f16::from_f32(p[1]),
                            f16::from_f32(p[2]),
                        )
                    }),
                )
                .write()
                .to_buffered(&mut *out),
            };
            result.map_err(|e| match e {
                exr::error::Error::Io(io) => Error::write(path, io),
                other => enc_err(&other),
            })
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_codes_round_trip() {
        assert!((srgb_to_linear(128.0 / 255.0) - 0.215_860_5).abs() < 1e-7);
        assert_eq!(srgb_to_linear(0.0), 0.0);
        assert_eq!(srgb_to_linear(1.0), 1.0);
        for k in 0..=255u8 {
            let l = srgb_to_linear(f32::from(k) / 255.0);
            assert_eq!(linear_to_srgb8(l), k);
            assert_eq!((linear_to_srgb(l) * 255.0).round() as u8, k);
        }
        assert_eq!(linear_to_srgb8(f32::NAN), 0);
        assert_eq!(linear_to_srgb8(-1.0), 0);
        assert_eq!(linear_to_srgb8(f32::INFINITY), 255);
        assert_eq!(linear_to_srgb8(5000.0), 255);
    }

    #[test]
    fn formats_by_extension() {
        assert_eq!(
            FileFormat::from_path(Path::new("a.PNG")).unwrap(),
            FileFormat::Png
        );
        assert_eq!(
            FileFormat::from_path(Path::new("a.Jpeg")).unwrap(),
            FileFormat::Jpeg
        );
        assert_eq!(
            FileFormat::from_path(Path::new("a.hdr")).unwrap(),
            FileFormat::Hdr
        );
        assert_eq!(
            FileFormat::from_path(Path::new("a.EXR")).unwrap(),
            FileFormat::Exr
        );
        let e = FileFormat::from_path(Path::new("a.tiff"))
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "a.tiff: unknown image extension \".tiff\"; accepted: png, jpg, jpeg, hdr, exr"
        );
        let e = FileFormat::from_path(Path::new("sky"))
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("sky: no file extension"), "{e}");
    }

    #[test]
    fn face_names() {
        let names = |p: &str| -> Vec<String> {
            face_paths(Path::new(p))
                .unwrap()
                .iter()
                .map(|p| p.to_string_lossy().into_owned())
                .collect()
        };
        let expected = [
            "d/sky_+x.exr",
            "d/sky_-x.exr",
            "d/sky_+y.exr",
            "d/sky_-y.exr",
            "d/sky_+z.exr",
            "d/sky_-z.exr",
        ];
        assert_eq!(names("d/sky.exr"), expected);
        assert_eq!(names("d/sky_-y.exr"), expected);
        assert_eq!(names("d/sky_{face}.exr"), expected);
        assert_eq!(names("d/{face}.png")[5], "d/-z.png");
        assert_eq!(face_of_name(Path::new("sky_+z.png")), Some(CubeFace::PosZ));
        assert_eq!(face_of_name(Path::new("sky+z.png")), None);
        assert!(is_face_pattern(Path::new("a/b_{face}.hdr")));
    }
}
