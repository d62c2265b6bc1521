// Loading and saving environment maps: the format by extension, the load
// and save options, and one entry point each ([`load`], [`save`]); each
// format lives in its own file beside this one.

#[cfg(feature = "image")]
use std::io::BufReader;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

#[cfg(feature = "image")]
use ::image::{DynamicImage, ImageDecoder, ImageReader};
use envmap_core::{AnyMapping, Atlas};

use crate::cancel;
use crate::error::{Error, Result};
use crate::image::atomic::TempWriter;
use crate::image::convention::FileAxes;
#[cfg(feature = "image")]
use crate::image::envimage::check_size;
use crate::image::envimage::{EnvImage, RgbImage, RowSource, DEFAULT_MAX_TEXELS};
use crate::image::face_ops::FaceTransforms;
use crate::image::format::{self, Contents, FileFormat};
#[cfg(feature = "image")]
use crate::image::format::{decode_error, Source};
use crate::image::framing::Framing;
use crate::image::layout::{resolve, Layout, Representation};
use crate::image::metadata::FileMetadata;
use crate::image::texel::Clamped;
use crate::image::texture::{self, Texture, TextureKind, TextureOptions};
use crate::image::{faces, metadata};
use crate::par::*;

use crate::image::atomic::{MemoryFile, Outputs};
pub(crate) use crate::image::faces::is_face_pattern;
use crate::image::faces::FaceNames;

/// Sample type of OpenEXR output.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ExrPrecision {
    /// 32-bit float: every value kept bit for bit.
    #[default]
    F32,
    /// 16-bit half float: half the size; values above 65504 become infinite.
    F16,
}

/// How OpenEXR output is compressed. On f32 radiance, RLE shrinks only
/// runs of equal values (the empty half of a cube cross) and the other
/// lossless codecs save a part of a real photograph at many times the time
/// of an uncompressed write; on f16, RLE and ZIP shrink smooth maps several
/// times over. Sizes and times: `docs/performance.md`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ExrCompression {
    /// The default: for f32 samples, uncompressed scan lines (written and
    /// read at memory speed), except that the scan lines through an atlas's
    /// empty cells (the corners of a cube cross) are RLE-compressed, which
    /// takes their empty part to a few bytes: the file is then an RLE file
    /// whose other lines are stored raw (as OpenEXR stores any block a
    /// codec does not shrink): half the size of an uncompressed cross, for a
    /// little more save time when the page cache is warm, and less when the
    /// kernel must find fresh pages for the file (`docs/performance.md`).
    /// [`ExrCompression::Rle`] for f16 (lossless,
    /// fast, and it does shrink half floats).
    #[default]
    Auto,
    /// Uncompressed scan lines.
    None,
    /// Run-length encoding (lossless).
    Rle,
    /// zlib per scan line (lossless; OpenEXR's `ZIPS`).
    Zips,
    /// zlib per 16 scan lines (lossless; OpenEXR's `ZIP`, its library's
    /// own default).
    Zip,
    /// Wavelet and Huffman (lossless; OpenEXR's `PIZ`, good on noisy
    /// photographs).
    Piz,
    /// f32 rounded to 24 bits, then zlib (lossy for f32, lossless for f16).
    Pxr24,
    /// 4×4 blocks of f16 at a fixed rate (lossy; f32 is stored
    /// uncompressed).
    B44,
    /// B44 with flat blocks stored smaller (lossy; f32 uncompressed).
    B44a,
}

impl ExrCompression {
    /// Every choice: the lossless ones first, then the lossy.
    pub const ALL: [ExrCompression; 9] = [
        ExrCompression::Auto,
        ExrCompression::None,
        ExrCompression::Rle,
        ExrCompression::Zips,
        ExrCompression::Zip,
        ExrCompression::Piz,
        ExrCompression::Pxr24,
        ExrCompression::B44,
        ExrCompression::B44a,
    ];

    /// The name on the command line (and OpenEXR's, lower case).
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            ExrCompression::Auto => "auto",
            ExrCompression::None => "none",
            ExrCompression::Rle => "rle",
            ExrCompression::Zips => "zips",
            ExrCompression::Zip => "zip",
            ExrCompression::Piz => "piz",
            ExrCompression::Pxr24 => "pxr24",
            ExrCompression::B44 => "b44",
            ExrCompression::B44a => "b44a",
        }
    }

    /// What [`ExrCompression::Auto`] stands for at `precision` for an image
    /// without empty cells (an f32 cube cross is RLE with its full lines
    /// stored raw: see [`ExrCompression::Auto`]); any other choice is
    /// itself.
    #[must_use]
    pub const fn resolve(self, precision: ExrPrecision) -> ExrCompression {
        match (self, precision) {
            (ExrCompression::Auto, ExrPrecision::F32) => ExrCompression::None,
            (ExrCompression::Auto, ExrPrecision::F16) => ExrCompression::Rle,
            (c, _) => c,
        }
    }
}

impl std::str::FromStr for ExrCompression {
    type Err = Error;

    fn from_str(s: &str) -> Result<Self> {
        let lower = s.to_ascii_lowercase();
        Self::ALL
            .into_iter()
            .find(|c| c.name() == lower || (lower == "uncompressed" && *c == ExrCompression::None))
            .ok_or_else(|| Error::UnknownName {
                what: "EXR compression",
                name: s.to_owned(),
                expected: Self::ALL.map(Self::name).join(", "),
            })
    }
}

/// When a finished output is flushed to the disk (`fsync`) before it is
/// renamed into place. Every output is written to a temporary file and
/// renamed, so an error, an interrupt or a crash of the program never
/// leaves half a file; syncing also covers a crash of the whole machine
/// (power loss), at the cost of waiting for the disk, which for a large
/// file can take longer than the rest of a conversion.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum SyncPolicy {
    /// The default: sync when the output replaces an existing file, so that
    /// a power loss can never leave neither the old file nor the new one; a
    /// new file is not synced (a power loss can at worst lose the new file,
    /// as with any program that does not sync).
    #[default]
    Replacing,
    /// Sync every output.
    Always,
    /// Sync nothing (the operating system writes the files back when it
    /// will; scratch outputs, benchmarks).
    Never,
}

impl SyncPolicy {
    /// The name on the command line.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            SyncPolicy::Replacing => "replacing",
            SyncPolicy::Always => "always",
            SyncPolicy::Never => "never",
        }
    }
}

impl std::str::FromStr for SyncPolicy {
    type Err = Error;

    fn from_str(s: &str) -> Result<Self> {
        match s.to_ascii_lowercase().as_str() {
            "replacing" => Ok(SyncPolicy::Replacing),
            "always" => Ok(SyncPolicy::Always),
            "never" => Ok(SyncPolicy::Never),
            _ => Err(Error::UnknownName {
                what: "sync policy",
                name: s.to_owned(),
                expected: "replacing, always, never".to_owned(),
            }),
        }
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
    /// The `envmap.*` text the file holds (OpenEXR attributes, PNG text
    /// chunks), key and value, sorted by key; see [`crate::image`].
    pub tags: Vec<(String, String)>,
}

/// How to load an environment map.
#[derive(Clone, Copy, Debug)]
#[non_exhaustive]
pub struct LoadOptions<'a> {
    /// The mapping, if known; detected from the aspect ratio otherwise
    /// (see [`crate::image::layout::resolve`]).
    pub mapping: Option<AnyMapping>,
    /// The layout, if known; [`Layout::Faces`] loads six files.
    pub layout: Option<Layout>,
    /// The file's axes; `None` for the ones the file states
    /// ([`crate::image`]) or, where it states none, the default,
    /// [`FileAxes::default`] (envmap's convention in the GL world: see
    /// [`crate::image`]). A mapping or layout the file states is
    /// likewise used where [`LoadOptions::mapping`] and
    /// [`LoadOptions::layout`] are `None`.
    pub axes: Option<FileAxes>,
    /// Largest image accepted, in texels (all six faces together for a
    /// six-file cube); checked before allocating.
    pub max_texels: u64,
    /// What to do with texels that hold a NaN or infinite value.
    pub non_finite: NonFinite,
    /// For a cube: how the file's faces are turned or mirrored against
    /// GL's (undone on loading); see [`crate::image`].
    pub face_transforms: FaceTransforms,
    /// Stops loading once set ([`Error::Cancelled`]); see [`crate::cancel`].
    pub cancel: Option<&'a AtomicBool>,
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

impl Default for LoadOptions<'_> {
    fn default() -> Self {
        Self {
            mapping: None,
            layout: None,
            axes: None,
            max_texels: DEFAULT_MAX_TEXELS,
            non_finite: NonFinite::Keep,
            face_transforms: FaceTransforms::default(),
            cancel: None,
        }
    }
}

/// How to save an environment map.
#[derive(Clone, Debug)]
#[non_exhaustive]
pub struct SaveOptions<'a> {
    /// Exposure in stops for 8-bit outputs (PNG, JPEG): values are scaled by
    /// 2^`exposure` before encoding. Float outputs keep their values.
    pub exposure: f32,
    /// Sample type of OpenEXR output.
    pub exr_precision: ExrPrecision,
    /// Compression of OpenEXR output.
    pub exr_compression: ExrCompression,
    /// When outputs are synced to the disk before they are renamed into
    /// place.
    pub sync: SyncPolicy,
    /// Write a cube as six files (also implied by `{face}` in the file name).
    pub six_files: bool,
    /// The files the image was read from: writing over one of them is
    /// refused unless [`overwrite_input`](SaveOptions::overwrite_input) is set.
    pub inputs: Vec<PathBuf>,
    /// Allow writing over a file listed in [`inputs`](SaveOptions::inputs).
    pub overwrite_input: bool,
    /// The names of a cube's six files; `None` for the scheme of a face
    /// name in the path given (`sky_px.exr`), else [`FaceNames::Signs`].
    pub face_names: Option<FaceNames>,
    /// For a cube: how to turn or mirror each face against GL's in the
    /// file; see [`crate::image`].
    pub face_transforms: FaceTransforms,
    /// What the values are, when more than radiance (for example
    /// "irradiance E/pi"): written as the `envmap.content` tag and at
    /// the end of the file's description. `None` (the default) for none.
    pub content: Option<String>,
    /// The texel format and supercompression of KTX2, DDS and KTX 1
    /// outputs.
    pub texture: TextureOptions,
    /// Stops writing once set: the output being written is removed and
    /// nothing is renamed into place ([`Error::Cancelled`]); see
    /// [`crate::cancel`].
    pub cancel: Option<&'a AtomicBool>,
}

impl Default for SaveOptions<'_> {
    fn default() -> Self {
        Self {
            exposure: 0.0,
            exr_precision: ExrPrecision::F32,
            exr_compression: ExrCompression::Auto,
            sync: SyncPolicy::Replacing,
            six_files: false,
            inputs: Vec::new(),
            overwrite_input: false,
            face_names: None,
            face_transforms: FaceTransforms::default(),
            content: None,
            texture: TextureOptions::default(),
            cancel: None,
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
    /// What the file said about itself ([`crate::image`]); its
    /// axes were used unless [`LoadOptions::axes`] gave others.
    pub metadata: FileMetadata,
}

/// Replaces texels with a NaN or infinite component by black, as `policy`
/// says; returns how many were replaced.
pub(super) fn apply_non_finite(pixels: &mut [[f32; 3]], policy: NonFinite) -> u64 {
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

/// The size of an image file, from its header alone.
pub(crate) fn read_dimensions(path: &Path) -> Result<(u32, u32)> {
    format::dimensions(path)
}

/// Reads an image file as linear RGB, with no representation attached (a
/// texture file's level 0).
///
/// Refuses images above `max_texels` before allocating their pixels; stops
/// with [`Error::Cancelled`] once `cancel` is set.
#[cfg_attr(feature = "instruments", visibility::make(pub))]
pub(crate) fn read_rgb(
    path: &Path,
    max_texels: u64,
    cancel: Option<&AtomicBool>,
) -> Result<(RgbImage, SourceFormat)> {
    cancel::check(cancel)?;
    let format = FileFormat::from_path(path)?;
    let src = format::open(path, cancel)?;
    read_level0(path, format, src, max_texels)
}

/// Reads `src` (named `path`) as `format`: an image as it is, a texture's
/// level 0.
fn read_level0(
    path: &Path,
    format: FileFormat,
    src: format::Source<'_>,
    max_texels: u64,
) -> Result<(RgbImage, SourceFormat)> {
    Ok(match format::read(path, format, src, max_texels)? {
        Contents::Image(rgb, source) => (rgb, source),
        Contents::Chain(t) => texture_level0(t, format),
    })
}

/// Loads an environment map from a file's bytes already in memory (an
/// asset packed in a game, a download): the format from `name`'s extension
/// (`"studio.hdr"`), which also names it in errors, or, when `name` has no
/// extension envmap knows, from the bytes themselves; everything else as
/// [`load_detailed`] (the representation from `opts`, the file's own tags,
/// else its aspect ratio). Nothing on disk is read. A six-file cube is not
/// read this way (load each face and assemble them, or use files).
///
/// ```
/// use envmap_render::image::{load_from_memory, LoadOptions};
/// // A 2 × 1 Radiance file: a latlong of two texels.
/// let mut hdr = b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 1 +X 2\n".to_vec();
/// hdr.extend_from_slice(&[128, 128, 128, 129, 128, 128, 128, 129]);
/// let loaded = load_from_memory(&hdr, "tiny.hdr", &LoadOptions::default())?;
/// assert_eq!((loaded.image.width(), loaded.image.height()), (2, 1));
/// assert_eq!(loaded.image.pixels()[0], [1.0, 1.0, 1.0]);
/// // The same bytes under a name that says nothing: recognised by their start.
/// let again = load_from_memory(&hdr, "download", &LoadOptions::default())?;
/// assert_eq!(again.image.pixels(), loaded.image.pixels());
/// # Ok::<(), envmap_render::Error>(())
/// ```
///
/// # Errors
///
/// As [`load_detailed`]: an unknown extension on bytes of no known format,
/// a file that does not decode or is larger than `opts.max_texels`, a size
/// no mapping fits, [`Error::Cancelled`].
pub fn load_from_memory(bytes: &[u8], name: &str, opts: &LoadOptions) -> Result<Loaded> {
    let path = Path::new(name);
    cancel::check(opts.cancel)?;
    let format = match FileFormat::from_path(path) {
        Ok(f) => f,
        Err(e) => FileFormat::from_bytes(bytes).ok_or(e)?,
    };
    let src = format::memory(bytes, opts.cancel);
    let (rgb, source) = read_level0(path, format, src, opts.max_texels)?;
    let mut loaded = finish_load(path, rgb, source, opts)?;
    loaded.files.clear();
    Ok(loaded)
}

/// The size of a PNG, JPEG or Radiance file from its header.
#[cfg(feature = "image")]
pub(super) fn image_dimensions(
    path: &Path,
    src: Source<'_>,
    format: FileFormat,
) -> Result<(u32, u32)> {
    ImageReader::with_format(BufReader::new(src), image_format(format))
        .into_dimensions()
        .map_err(|e| decode_error(path, format, e))
}

#[cfg(feature = "image")]
fn image_format(format: FileFormat) -> ::image::ImageFormat {
    match format {
        FileFormat::Png => ::image::ImageFormat::Png,
        FileFormat::Jpeg => ::image::ImageFormat::Jpeg,
        // The `image` crate reads Radiance; nothing else reaches it.
        _ => ::image::ImageFormat::Hdr,
    }
}

/// Level 0 of a texture file as a plain image (a cube as a horizontal
/// strip, stated in the tags), with what the file held.
fn texture_level0(t: texture::TextureFile, format: FileFormat) -> (RgbImage, SourceFormat) {
    let mut tags = Vec::new();
    if t.texture.kind() == TextureKind::Cube {
        tags.push((metadata::MAPPING.to_owned(), AnyMapping::Cube.to_string()));
        tags.push((metadata::LAYOUT.to_owned(), Layout::Strip.name().to_owned()));
        // The file's axes (a KTX2 of envmap's says them); its faces are
        // read as a strip whatever its mapping key says.
        tags.extend(
            t.texture
                .tags()
                .iter()
                .filter(|(k, _)| k == metadata::AXES)
                .cloned(),
        );
    } else {
        tags.extend(t.texture.tags().iter().cloned());
    }
    let pixel_format = format!("{} (level 0 read)", t.info.summary());
    let image = t.texture.level_rgb(0).unwrap_or_default();
    (
        image,
        SourceFormat {
            format,
            pixel_format,
            tags,
        },
    )
}

/// Decodes a PNG, JPEG or Radiance file with the `image` crate, after
/// checking its size from the header against `max_texels`.
#[cfg(feature = "image")]
pub(super) fn decode_with_image(
    path: &Path,
    file: Source<'_>,
    format: FileFormat,
    max_texels: u64,
) -> Result<DynamicImage> {
    let err = |e: ::image::ImageError| decode_error(path, format, e);
    let reader = ImageReader::with_format(BufReader::new(file), image_format(format));
    let mut decoder = reader.into_decoder().map_err(err)?;
    let (width, height) = decoder.dimensions();
    if width == 0 || height == 0 {
        return Err(decode_error(path, format, "the image is empty"));
    }
    check_size(width, height, 1, max_texels).map_err(|e| e.in_file(path))?;
    // Our own limit is checked; let the decoder allocate what this size needs.
    let mut limits = ::image::Limits::no_limits();
    limits.max_alloc = Some(decoder.total_bytes().saturating_add(64 << 20));
    decoder.set_limits(limits).map_err(err)?;
    DynamicImage::from_decoder(decoder).map_err(err)
}

/// Interleaved samples with `channels` per texel → RGB (grey replicated,
/// alpha dropped).
#[cfg(feature = "image")]
pub(super) fn expand<T: Copy>(raw: &[T], channels: usize, f: impl Fn(T) -> f32) -> Vec<[f32; 3]> {
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

/// Whether a load of `path` with `opts` reads six face files.
fn loads_six_files(path: &Path, opts: &LoadOptions) -> bool {
    match opts.layout {
        Some(l) => l.is_six_files(),
        None => {
            opts.mapping.is_none_or(|m| m == AnyMapping::Cube) && faces::names_a_face_file(path)
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
/// aspect ratio ([`crate::image::layout::resolve`]). A six-file cube is read when
/// `opts.layout` is [`Layout::Faces`], or (with no layout given and no
/// mapping other than cube) when the file name is a `{face}` pattern or
/// one of the six names; see the [module docs](super).
pub fn load_detailed(path: impl AsRef<Path>, opts: &LoadOptions) -> Result<Loaded> {
    let path = path.as_ref();
    if loads_six_files(path, opts) {
        return faces::load_six(path, opts);
    }
    let (rgb, source) = read_rgb(path, opts.max_texels, opts.cancel)?;
    finish_load(path, rgb, source, opts)
}

/// A decoded file made an [`EnvImage`]: non-finite texels, the
/// representation (the caller's, the file's, the aspect ratio's), the face
/// transforms.
fn finish_load(
    path: &Path,
    mut rgb: RgbImage,
    source: SourceFormat,
    opts: &LoadOptions,
) -> Result<Loaded> {
    let replaced = apply_non_finite(&mut rgb.pixels, opts.non_finite);
    let metadata = FileMetadata::from_tags(&source.tags);
    let (w, h) = (rgb.width, rgb.height);
    // What the caller says first; if it says nothing, what the file says
    // of itself (if that fits the size); then the aspect ratio.
    let (stated, stated_layout) = if opts.mapping.is_none() && opts.layout.is_none() {
        (
            metadata.mapping,
            metadata.layout.filter(|l| !l.is_six_files()),
        )
    } else {
        (opts.mapping, opts.layout)
    };
    // A layout whose files are framed (v360's EAC: turned, padded), named
    // or the default of a named mapping whose size it fits: resolved by the
    // size inside the frame.
    let framed_layout = stated_layout.or_else(|| {
        stated.map(|m| Layout::for_mapping(m)[0]).filter(|l| {
            Framing::of(&l.atlas()).is_some_and(|f| f.inner_size(&l.atlas(), w, h).is_ok())
        })
    });
    let framing = framed_layout.and_then(|l| Framing::of(&l.atlas()).map(|f| (f, l.atlas())));
    let (w, h) = match framing {
        Some((f, atlas)) => f.inner_size(&atlas, w, h).map_err(|e| e.in_file(path))?,
        None => (w, h),
    };
    let (mapping, atlas) = resolve(w, h, stated, framed_layout.or(stated_layout))
        .or_else(|e| {
            if opts.mapping.is_none() && opts.layout.is_none() && !metadata.is_empty() {
                resolve(w, h, None, None)
            } else {
                Err(e)
            }
        })
        .map_err(|e| e.in_file(path))?;
    let repr = Representation {
        mapping,
        atlas,
        frame: opts
            .axes
            .or(metadata.axes)
            .unwrap_or_default()
            .frame(mapping),
    };
    let image = match framing {
        Some((f, _)) => f.unframed(&rgb, repr),
        None => EnvImage::from_rgb(rgb, repr),
    }
    .map_err(|e| e.in_file(path))?;
    let image = opts
        .face_transforms
        .apply(image, false)
        .map_err(|e| e.in_file(path))?;
    Ok(Loaded {
        image,
        source,
        files: vec![path.to_path_buf()],
        replaced,
        metadata,
    })
}

// ---------------------------------------------------------------------------
// Writing

/// A borrowed RGB image to encode.
#[derive(Clone, Copy)]
#[cfg_attr(not(any(feature = "exr", feature = "image")), allow(dead_code))]
pub(crate) struct View<'a> {
    pub(crate) width: u32,
    pub(crate) height: u32,
    pub(crate) pixels: &'a [[f32; 3]],
    /// Instead of `pixels` (then empty): the rows made on demand, for a
    /// format that writes rows as it goes (OpenEXR); see
    /// [`Outputs::stage_streamed`]. Only OpenEXR reads it.
    #[cfg_attr(not(feature = "exr"), allow(dead_code))]
    pub(crate) stream: Option<&'a dyn RowSource>,
    /// The atlas the texels are laid out in, if the image is an
    /// environment map (where its empty cells are: OpenEXR's `auto`
    /// compresses only the rows that cross one).
    #[cfg_attr(not(feature = "exr"), allow(dead_code))]
    pub(crate) atlas: Option<Atlas>,
    /// What the file says about itself where its format has a place
    /// ([`crate::image::metadata`]): the `envmap.*` tags and a description.
    pub(crate) tags: &'a [(String, String)],
    pub(crate) description: &'a str,
}

/// Saves an environment map; returns the files written (one, or six faces
/// in GL order).
///
/// The format follows the extension. A cube is written as six files when
/// [`SaveOptions::six_files`] is set or the file name is a `{face}` pattern;
/// otherwise the image is written in its atlas as is. Writes are atomic
/// and refuse to replace an input; see the [module docs](super).
pub fn save(image: &EnvImage, path: impl AsRef<Path>, opts: &SaveOptions) -> Result<Vec<PathBuf>> {
    let mut run = Outputs::new(opts);
    run.stage_image(image, path, opts)?;
    run.commit()
}

/// The files [`save`] would write to `path`, made in memory: nothing on
/// disk is read or written. `path` names them and chooses the format by its
/// extension; a cube as six files gives six, in GL order.
///
/// # Errors
///
/// As [`save`], but for the file system's.
pub fn save_to_memory(
    image: &EnvImage,
    path: impl AsRef<Path>,
    opts: &SaveOptions,
) -> Result<Vec<MemoryFile>> {
    let mut run = Outputs::in_memory(opts.cancel);
    run.stage_image(image, path, opts)?;
    run.into_memory()
}

/// Writes a plain RGB image (atomically, refusing to replace an input, as
/// [`save`] does).
pub fn write_rgb(image: &RgbImage, path: impl AsRef<Path>, opts: &SaveOptions) -> Result<()> {
    let mut run = Outputs::new(opts);
    run.stage_rgb(image, path, opts)?;
    run.commit().map(drop)
}

#[cfg_attr(not(feature = "instruments"), allow(unreachable_pub, dead_code))]
impl<'a> Outputs<'a> {
    /// An empty run for outputs saved with `opts` (its inputs, whether they
    /// may be overwritten, its cancel flag).
    #[must_use]
    pub fn new(opts: &SaveOptions<'a>) -> Self {
        Self::with(&opts.inputs, opts.overwrite_input, opts.cancel).with_sync(opts.sync)
    }

    /// Stages `image` as [`save`] writes it (one file, or six faces).
    pub fn stage_image(
        &mut self,
        image: &EnvImage,
        path: impl AsRef<Path>,
        opts: &SaveOptions,
    ) -> Result<()> {
        let path = path.as_ref();
        let format = FileFormat::from_path(path)?;
        let turned;
        let image = if opts.face_transforms.is_identity() || !image.mapping().has_cube_faces() {
            image
        } else {
            turned = opts.face_transforms.apply(image.clone(), true)?;
            &turned
        };
        if format.is_texture() {
            if opts.six_files || is_face_pattern(path) {
                return Err(Error::unsupported(format!(
                    "a {} file holds a whole cube; it is not written as six files",
                    format.name()
                ))
                .in_file(path));
            }
            let tex =
                Texture::from_env(std::slice::from_ref(image)).map_err(|e| e.in_file(path))?;
            return self.stage_texture(&tex, path, opts.texture).map(drop);
        }
        if opts.six_files || is_face_pattern(path) {
            return faces::stage(self, image, path, format, opts);
        }
        let repr = image.representation();
        let (tags, description) = metadata::with_content(
            metadata::tags(repr, None, None),
            metadata::description(repr, None, None),
            opts.content.as_deref(),
        );
        let framed = Framing::of(&repr.atlas)
            .map(|f| f.framed(image))
            .transpose()
            .map_err(|e| e.in_file(path))?;
        let view = match &framed {
            Some(rgb) => View {
                width: rgb.width,
                height: rgb.height,
                pixels: &rgb.pixels,
                stream: None,
                atlas: None,
                tags: &tags,
                description: &description,
            },
            None => View {
                width: image.width(),
                height: image.height(),
                pixels: image.pixels(),
                stream: None,
                atlas: Some(repr.atlas),
                tags: &tags,
                description: &description,
            },
        };
        self.stage_with(path, |out| encode(path, format, view, opts, out))
    }

    /// Stages a plain RGB image as [`write_rgb`] writes it.
    pub fn stage_rgb(
        &mut self,
        image: &RgbImage,
        path: impl AsRef<Path>,
        opts: &SaveOptions,
    ) -> Result<()> {
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
        if format.is_texture() {
            let tex = Texture::new(TextureKind::Flat, vec![vec![image.clone()]])
                .map_err(|e| e.in_file(path))?;
            return self.stage_texture(&tex, path, opts.texture).map(drop);
        }
        let (tags, description) =
            metadata::with_content(Vec::new(), String::new(), opts.content.as_deref());
        let view = View {
            width: image.width,
            height: image.height,
            pixels: &image.pixels,
            stream: None,
            atlas: None,
            tags: &tags,
            description: &description,
        };
        self.stage_with(path, |out| encode(path, format, view, opts, out))
    }
}

#[cfg_attr(not(feature = "instruments"), allow(unreachable_pub, dead_code))]
impl<'a> Outputs<'a> {
    /// Stages the image `stream` makes (a conversion as it runs,
    /// `convert::Streamed`; an image in another atlas,
    /// [`EnvImage::in_atlas`]), as [`Outputs::stage_image`] would stage it
    /// once made: an OpenEXR file (one file, its cube faces not turned) is
    /// written as the rows are made, a batch of scan-line blocks at a time,
    /// so the image is never whole in memory; every other file is made
    /// whole first and staged as usual.
    ///
    /// # Errors
    ///
    /// As [`Outputs::stage_image`].
    pub fn stage_streamed(
        &mut self,
        stream: &dyn RowSource,
        path: impl AsRef<Path>,
        opts: &SaveOptions,
    ) -> Result<()> {
        let path = path.as_ref();
        let format = FileFormat::from_path(path)?;
        let repr = *stream.representation();
        let streams = format == FileFormat::Exr
            && cfg!(feature = "exr")
            && !opts.six_files
            && !is_face_pattern(path)
            && (opts.face_transforms.is_identity() || !repr.mapping.has_cube_faces())
            && Framing::of(&repr.atlas).is_none();
        if !streams {
            let mut image = EnvImage::new(stream.width(), stream.height(), repr)?;
            let w = stream.width() as usize;
            let band = 16 * w;
            image
                .pixels_mut()
                .par_chunks_mut(band)
                .enumerate()
                .for_each(|(k, rows)| stream.rows((k * 16) as u32, rows));
            return self.stage_image(&image, path, opts);
        }
        let (tags, description) = metadata::with_content(
            metadata::tags(&repr, None, None),
            metadata::description(&repr, None, None),
            opts.content.as_deref(),
        );
        let view = View {
            width: stream.width(),
            height: stream.height(),
            pixels: &[],
            stream: Some(stream),
            atlas: Some(repr.atlas),
            tags: &tags,
            description: &description,
        };
        self.stage_with(path, |out| encode(path, format, view, opts, out))
    }
}

#[cfg_attr(not(feature = "instruments"), allow(unreachable_pub, dead_code))]
impl Outputs<'_> {
    /// Stages a texture with its levels as a KTX2, DDS or KTX 1 file (by
    /// the extension), in `opts`' texel format; returns what packing
    /// clamped (see [`crate::image`]).
    ///
    /// # Errors
    ///
    /// Another extension; what the format refuses; write errors.
    pub fn stage_texture(
        &mut self,
        tex: &Texture,
        path: impl AsRef<Path>,
        opts: TextureOptions,
    ) -> Result<Clamped> {
        let path = path.as_ref();
        let (bytes, clamped) = texture::encode(tex, path, opts)?;
        self.stage_bytes(path, &bytes)?;
        Ok(clamped)
    }
}

/// Encodes `view` in `format` into `out`, through the format's codec.
pub(super) fn encode(
    path: &Path,
    format: FileFormat,
    view: View<'_>,
    opts: &SaveOptions,
    out: &mut TempWriter<'_>,
) -> Result<()> {
    format.codec(path)?.write_image(path, view, opts, out)
}

/// An encoder's error: a write error when it was I/O, an encoding one otherwise.
#[cfg(feature = "image")]
pub(super) fn encode_error(path: &Path, format: FileFormat, e: ::image::ImageError) -> Error {
    match e {
        ::image::ImageError::IoError(io) => Error::write(path, io),
        other => Error::Encode {
            path: path.to_path_buf(),
            format: format.name(),
            message: other.to_string(),
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
            "a.tiff: unknown image extension \".tiff\"; accepted: png, jpg, jpeg, hdr, exr, ktx2, dds, ktx, env, gltf"
        );
        let e = FileFormat::from_path(Path::new("sky"))
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("sky: no file extension"), "{e}");
    }
}
