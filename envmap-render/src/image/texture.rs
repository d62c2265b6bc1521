//! GPU textures with mip levels: what KTX2, DDS and KTX 1 files hold, in
//! memory ([`Texture`]), and the one place those files are written and read
//! (`stage_texture`, [`read`]).
//!
//! A texture is a 2D image or a cube (six faces in GL order +X, −X, +Y,
//! −Y, +Z, −Z, each with its first texel top-left, exactly as GL and Vulkan
//! select them: KTX2's `rd` orientation), with levels largest first, level
//! `p` being ⌊W/2ᵖ⌋ × ⌊H/2ᵖ⌋ (at least 1). A chain may stop before 1×1.
//!
//! The formats, one file each: `ktx2.rs` (KTX 2.0, read and write),
//! `dds.rs` (DDS with the DX10 header, read and write), `ktx1.rs` (KTX 1 as
//! Filament's `cmgen` writes it, write only). Texel formats and their
//! packers are in [Texel formats](crate::image#texel-formats).

use std::path::Path;

use envmap_core::{AnyMapping, Atlas};

use crate::error::{Error, Result};
use crate::image::envimage::{EnvImage, RgbImage};
use crate::image::format::{self, Contents, FileFormat};
use crate::image::layout::{resolve, Representation};
use crate::image::texel::{Bc6hQuality, Clamped, TexelFormat};

/// Whether a texture is a plain 2D image or a cube.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum TextureKind {
    /// One image per level.
    Flat,
    /// Six square faces per level, in GL order.
    Cube,
}

impl TextureKind {
    /// Images per level: 1 or 6.
    #[must_use]
    pub const fn faces(self) -> usize {
        match self {
            TextureKind::Flat => 1,
            TextureKind::Cube => 6,
        }
    }
}

/// A 2D or cube texture with its levels, largest first (see the
/// [module docs](self)).
#[derive(Clone, Debug, PartialEq)]
pub struct Texture {
    kind: TextureKind,
    levels: Vec<Vec<RgbImage>>,
    /// What the texels' directions mean, as envmap's `envmap.*` keys
    /// ([`crate::image::metadata`]): the mapping, a 2D texture's layout,
    /// the axes; sorted by key. Empty for a texture made of plain images.
    tags: Vec<(String, String)>,
}

/// The size of level `p` of a `w`×`h` texture: ⌊w/2ᵖ⌋ × ⌊h/2ᵖ⌋, at least 1.
#[cfg_attr(feature = "instruments", visibility::make(pub))]
#[must_use]
pub(crate) fn level_size(w: u32, h: u32, p: usize) -> (u32, u32) {
    let s = |v: u32| {
        u32::try_from(p)
            .ok()
            .and_then(|p| v.checked_shr(p))
            .unwrap_or(0)
            .max(1)
    };
    (s(w), s(h))
}

/// The number of levels of a full chain of a `w`×`h` texture: down to 1×1.
#[cfg_attr(feature = "instruments", visibility::make(pub))]
#[must_use]
pub(crate) fn full_chain(w: u32, h: u32) -> usize {
    (32 - w.max(h).max(1).leading_zeros()) as usize
}

impl Texture {
    /// A texture of `levels` (largest first; one image per level for
    /// [`TextureKind::Flat`], six faces in GL order for a cube).
    ///
    /// # Errors
    ///
    /// No levels; a level of the wrong size (level `p` must be
    /// `level_size` of level 0), the wrong number of images, non-square
    /// cube faces, more levels than the full chain, or a pixel count that
    /// does not match an image's size.
    pub fn new(kind: TextureKind, levels: Vec<Vec<RgbImage>>) -> Result<Self> {
        let Some(first) = levels.first().and_then(|l| l.first()) else {
            return Err(Error::dimensions("a texture needs at least one level"));
        };
        let (w, h) = (first.width, first.height);
        if kind == TextureKind::Cube && w != h {
            return Err(Error::dimensions(format!(
                "cube faces must be square; level 0 is {w}×{h}"
            )));
        }
        if levels.len() > full_chain(w, h) {
            return Err(Error::dimensions(format!(
                "{} levels given; a {w}×{h} texture has at most {}",
                levels.len(),
                full_chain(w, h)
            )));
        }
        for (p, level) in levels.iter().enumerate() {
            let (lw, lh) = level_size(w, h, p);
            if level.len() != kind.faces() {
                return Err(Error::dimensions(format!(
                    "level {p} has {} images; a {} texture needs {}",
                    level.len(),
                    if kind == TextureKind::Cube {
                        "cube"
                    } else {
                        "2D"
                    },
                    kind.faces()
                )));
            }
            for img in level {
                if (img.width, img.height) != (lw, lh)
                    || img.pixels.len() != lw as usize * lh as usize
                {
                    return Err(Error::dimensions(format!(
                        "level {p} must be {lw}×{lh}; an image given is {}×{} with {} texels",
                        img.width,
                        img.height,
                        img.pixels.len()
                    )));
                }
            }
        }
        Ok(Self {
            kind,
            levels,
            tags: Vec::new(),
        })
    }

    /// What the texels' directions mean, as a file states it: envmap's
    /// `envmap.mapping`, `envmap.layout` (2D textures) and `envmap.axes`
    /// keys, sorted by key ([`crate::image::metadata`]). KTX2 files carry
    /// them in their key/value data; DDS has no place for them. Empty for a
    /// texture of plain images, or a file that does not say.
    #[must_use]
    pub(crate) fn tags(&self) -> &[(String, String)] {
        &self.tags
    }

    /// `self` stating `tags` (only envmap's `envmap.*` keys are kept,
    /// sorted by key).
    #[must_use]
    pub(crate) fn with_tags(mut self, tags: &[(String, String)]) -> Self {
        let mut t: Vec<(String, String)> = tags
            .iter()
            .filter(|(k, _)| k.starts_with("envmap."))
            .cloned()
            .collect();
        t.sort();
        self.tags = t;
        self
    }

    /// A texture of environment maps, largest first: cubes become six faces
    /// per level (in the image's own axes, GL order), any other
    /// representation one 2D image per level, its atlas as stored. Levels
    /// after the first one whose size breaks the ⌊W/2ᵖ⌋ rule are dropped
    /// (a chain may stop early); see [`Texture::new`] for the errors.
    ///
    /// # Errors
    ///
    /// As [`Texture::new`]; no images.
    pub fn from_env(levels: &[EnvImage]) -> Result<Self> {
        let Some(first) = levels.first() else {
            return Err(Error::dimensions("a texture needs at least one level"));
        };
        let cube = first.mapping() == AnyMapping::Cube;
        let kind = if cube {
            TextureKind::Cube
        } else {
            TextureKind::Flat
        };
        let (w, h) = if cube {
            first.cell_size()
        } else {
            (first.width(), first.height())
        };
        let mut out = Vec::with_capacity(levels.len());
        for (p, img) in levels.iter().enumerate() {
            let size = if cube {
                img.cell_size()
            } else {
                (img.width(), img.height())
            };
            if p > 0 && size != level_size(w, h, p) {
                break;
            }
            if cube {
                let faces = (0..6)
                    .map(|f| {
                        img.chart_image(f)
                            .ok_or_else(|| Error::layout("a cube image without six faces"))
                    })
                    .collect::<Result<Vec<_>>>()?;
                out.push(faces);
            } else {
                out.push(vec![RgbImage {
                    width: img.width(),
                    height: img.height(),
                    pixels: img.pixels().to_vec(),
                }]);
            }
        }
        // What the directions mean: a cube's faces are GL's, so its axes
        // say it all; a 2D texture keeps its mapping and layout too.
        let repr = first.representation();
        let layout = if cube { None } else { repr.layout() };
        let mut tags = crate::image::metadata::tags(repr, layout, None);
        if cube {
            tags.retain(|(k, _)| k != crate::image::metadata::LAYOUT);
        }
        Ok(Self::new(kind, out)?.with_tags(&tags))
    }

    /// 2D or cube.
    #[must_use]
    pub fn kind(&self) -> TextureKind {
        self.kind
    }

    /// Level 0's size (of one face for a cube).
    #[must_use]
    pub fn size(&self) -> (u32, u32) {
        let f = &self.levels[0][0];
        (f.width, f.height)
    }

    /// The levels, largest first: each one image, or six faces.
    #[must_use]
    pub fn levels(&self) -> &[Vec<RgbImage>] {
        &self.levels
    }

    /// The number of levels.
    #[must_use]
    pub fn level_count(&self) -> usize {
        self.levels.len()
    }

    /// Level `p` as an environment map: a cube as a horizontal strip in
    /// `axes`' frame, a 2D image in the representation its size says
    /// ([`resolve`], or `mapping` if given).
    ///
    /// # Errors
    ///
    /// `p` out of range; a 2D level whose size fits no (or not the given)
    /// mapping.
    pub(crate) fn level_image(
        &self,
        p: usize,
        mapping: Option<AnyMapping>,
        frame: impl Fn(AnyMapping) -> envmap_core::Frame,
    ) -> Result<EnvImage> {
        let level = self.levels.get(p).ok_or_else(|| {
            Error::dimensions(format!(
                "level {p} asked for; the texture has {}",
                self.levels.len()
            ))
        })?;
        match self.kind {
            TextureKind::Cube => {
                let w = level[0].width;
                let repr = Representation::new(
                    AnyMapping::Cube,
                    Atlas::CUBE_HORIZONTAL_STRIP,
                    frame(AnyMapping::Cube),
                )?;
                let mut img = EnvImage::new_with_limit(6 * w, w, repr, u64::MAX)?;
                for (f, face) in level.iter().enumerate() {
                    img.set_chart_image(f as u32, face)?;
                }
                Ok(img)
            }
            TextureKind::Flat => {
                let i = &level[0];
                let (m, atlas) = resolve(i.width, i.height, mapping, None)?;
                let repr = Representation::new(m, atlas, frame(m))?;
                EnvImage::from_pixels(i.width, i.height, i.pixels.clone(), repr)
            }
        }
    }

    /// Level `p` as one plain image: a cube's six faces side by side (a
    /// horizontal strip, +X … −Z), a 2D level as it is.
    #[must_use]
    pub(crate) fn level_rgb(&self, p: usize) -> Option<RgbImage> {
        let level = self.levels.get(p)?;
        if self.kind == TextureKind::Flat {
            return Some(level[0].clone());
        }
        let w = level[0].width as usize;
        let mut pixels = Vec::with_capacity(6 * w * w);
        for y in 0..w {
            for face in level {
                pixels.extend_from_slice(&face.pixels[y * w..(y + 1) * w]);
            }
        }
        Some(RgbImage {
            width: 6 * w as u32,
            height: w as u32,
            pixels,
        })
    }

    /// Every level's texels packed in `format`, in level order; each level's
    /// images (faces) one after the other, rows top-down, tightly packed.
    /// Returns the packed levels and what was clamped.
    #[must_use]
    pub fn pack(&self, format: TexelFormat) -> (Vec<Vec<u8>>, Clamped) {
        let mut clamped = Clamped::default();
        let levels = (0..self.levels.len())
            .map(|p| {
                let mut out = vec![0u8; self.level_len(p, format)];
                let quality = Bc6hQuality::default();
                clamped.add(self.pack_level_into(p, format, quality, &mut out));
                out
            })
            .collect();
        (levels, clamped)
    }

    /// The texels an engine uploads, in `format`: per level (largest
    /// first), per face (GL order +X, −X, +Y, −Y, +Z, −Z: the layer order of
    /// a Vulkan, wgpu, D3D or GL cube), rows top-down, tightly packed, as
    /// KTX2 and DDS files hold them; no file is made. The format's names
    /// for each API are [`TexelFormat::vk_name`], [`TexelFormat::wgpu_name`]
    /// and [`TexelFormat::dxgi_name`]. BC6H is encoded at the default
    /// [`Bc6hQuality`].
    #[must_use]
    pub fn upload(&self, format: TexelFormat) -> Upload {
        self.upload_at(format, Bc6hQuality::default())
    }

    /// [`Texture::upload`], BC6H encoded at `quality`.
    #[cfg_attr(feature = "instruments", visibility::make(pub))]
    #[must_use]
    pub(crate) fn upload_at(&self, format: TexelFormat, quality: Bc6hQuality) -> Upload {
        let mut clamped = Clamped::default();
        let levels = self
            .levels
            .iter()
            .map(|faces| {
                let (width, height) = faces.first().map_or((0, 0), |f| (f.width, f.height));
                let faces = faces
                    .iter()
                    .map(|img| {
                        let (w, h) = (img.width, img.height);
                        let mut out = vec![0u8; format.image_bytes(w, h)];
                        clamped.add(format.pack_image_into(&img.pixels, (w, h), quality, &mut out));
                        out
                    })
                    .collect();
                UploadLevel {
                    width,
                    height,
                    faces,
                }
            })
            .collect();
        Upload {
            kind: self.kind,
            format,
            levels,
            clamped,
        }
    }

    /// The bytes of level `p` in `format` (all its faces).
    #[must_use]
    pub(crate) fn level_len(&self, p: usize, format: TexelFormat) -> usize {
        self.levels.get(p).map_or(0, |l| {
            l.iter()
                .map(|i| format.image_bytes(i.width, i.height))
                .sum::<usize>()
        })
    }

    /// Packs level `p` (its faces one after the other) into `out`, which
    /// holds exactly [`Texture::level_len`] bytes, BC6H at `quality`;
    /// returns what was clamped.
    ///
    /// # Panics
    ///
    /// If `out` has another length.
    pub(crate) fn pack_level_into(
        &self,
        p: usize,
        format: TexelFormat,
        quality: Bc6hQuality,
        out: &mut [u8],
    ) -> Clamped {
        assert_eq!(out.len(), self.level_len(p, format), "level length");
        let mut clamped = Clamped::default();
        let mut at = 0;
        for img in &self.levels[p] {
            let (w, h) = (img.width, img.height);
            let n = format.image_bytes(w, h);
            clamped.add(format.pack_image_into(&img.pixels, (w, h), quality, &mut out[at..at + n]));
            at += n;
        }
        clamped
    }
}

/// A texture's texels as an engine uploads them ([`Texture::upload`]).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Upload {
    /// A cube (six faces per level) or a 2D texture (one).
    pub kind: TextureKind,
    /// The texel format of every byte below.
    pub format: TexelFormat,
    /// The levels, largest first.
    pub levels: Vec<UploadLevel>,
    /// What packing into `format` clamped (see
    /// [Texel formats](crate::image#texel-formats)).
    pub clamped: Clamped,
}

/// One level of an [`Upload`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct UploadLevel {
    /// Width of each face, in texels.
    pub width: u32,
    /// Height of each face, in texels.
    pub height: u32,
    /// Each face's bytes (GL order for a cube), rows top-down.
    pub faces: Vec<Vec<u8>>,
}

impl UploadLevel {
    /// Every face's bytes one after the other (what a KTX2 or DDS level
    /// holds, and what `wgpu::Queue::write_texture` takes for a whole cube
    /// level at `bytes_per_row` = width × the format's bytes; for BC6H,
    /// ⌈width / 4⌉ × 16, a row of blocks).
    #[cfg_attr(not(feature = "instruments"), allow(dead_code))]
    #[cfg_attr(feature = "instruments", visibility::make(pub))]
    #[must_use]
    pub(crate) fn concatenated(&self) -> Vec<u8> {
        self.faces.concat()
    }
}

/// Bytes of level `p` of a `kind` texture of `w`×`h` in `format`, or `None`
/// if that overflows.
#[cfg_attr(not(feature = "instruments"), allow(dead_code))]
#[cfg_attr(feature = "instruments", visibility::make(pub))]
#[must_use]
pub(crate) fn level_bytes(
    kind: TextureKind,
    w: u32,
    h: u32,
    p: usize,
    format: TexelFormat,
) -> Option<u64> {
    let (lw, lh) = level_size(w, h, p);
    let b = format.block();
    u64::from(lw.div_ceil(b))
        .checked_mul(u64::from(lh.div_ceil(b)))?
        .checked_mul(kind.faces() as u64)?
        .checked_mul(format.bytes() as u64)
}

/// Checks a texture header's size against `max_texels` (all levels and
/// faces together) before anything is allocated; returns the total.
///
/// # Errors
///
/// [`Error::TooLarge`] (level 0's size, all the texels) past the limit.
#[cfg_attr(not(feature = "instruments"), allow(dead_code))]
#[cfg_attr(feature = "instruments", visibility::make(pub))]
pub(crate) fn check_texels(
    kind: TextureKind,
    w: u32,
    h: u32,
    levels: usize,
    max_texels: u64,
) -> Result<u64> {
    let mut total = 0u64;
    for p in 0..levels {
        let (lw, lh) = level_size(w, h, p);
        let texels = u64::from(lw).saturating_mul(u64::from(lh));
        total = total.saturating_add(texels.saturating_mul(kind.faces() as u64));
    }
    if total > max_texels {
        return Err(Error::TooLarge {
            width: u64::from(w),
            height: u64::from(h),
            texels: total,
            limit: max_texels,
        });
    }
    Ok(total)
}

/// What a texture file holds besides its texels, for `envmap info`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TextureInfo {
    /// The container: `"KTX2"`, `"DDS"`, `"KTX 1"`.
    pub container: &'static str,
    /// The texel format.
    pub format: TexelFormat,
    /// 2D or cube.
    pub kind: TextureKind,
    /// Level 0's size (of one face).
    pub size: (u32, u32),
    /// Levels stored.
    pub levels: usize,
    /// The supercompression: `None`, or e.g. `"zstd"`.
    pub supercompression: Option<&'static str>,
    /// The orientation the file states (KTX2 `KTXorientation`), if any.
    pub orientation: Option<String>,
    /// The program that wrote it (KTX2 `KTXwriter`), if it says.
    pub writer: Option<String>,
    /// Every key/value entry (KTX), in file order.
    pub key_values: Vec<(String, String)>,
    /// Bytes each level takes in the file, largest level first.
    pub level_bytes: Vec<u64>,
}

impl TextureInfo {
    /// One line: "KTX2 cube 512×512, 10 levels (full chain), rgb9e5
    /// (E5B9G9R9_UFLOAT_PACK32), zstd".
    #[must_use]
    pub fn summary(&self) -> String {
        let (w, h) = self.size;
        let kind = match self.kind {
            TextureKind::Cube => "cube",
            TextureKind::Flat => "2D",
        };
        let full = full_chain(w, h);
        let chain = if self.levels == full {
            "full chain".to_owned()
        } else {
            let (lw, lh) = level_size(w, h, self.levels.saturating_sub(1));
            format!("down to {lw}×{lh}")
        };
        format!(
            "{} {kind} {w}×{h}, {} level{} ({chain}), {} ({}){}",
            self.container,
            self.levels,
            if self.levels == 1 { "" } else { "s" },
            self.format.name(),
            self.format.vk_name(),
            self.supercompression
                .map(|s| format!(", {s}"))
                .unwrap_or_default()
        )
    }
}

/// A texture file read: its texture and what it says about itself.
#[derive(Clone, Debug, PartialEq)]
pub struct TextureFile {
    /// The texels.
    pub texture: Texture,
    /// The rest.
    pub info: TextureInfo,
}

/// How to write a texture file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub struct TextureOptions {
    /// The texel format. Default RGBA16F (every engine loads it; DDS and
    /// KTX2 alike).
    pub format: TexelFormat,
    /// KTX2 only: Zstandard supercompression at this level (1–22), each
    /// level its own frame; `None` (the default) for none.
    pub zstd: Option<i32>,
    /// BC6H only: how hard the encoder searches (default
    /// [`Bc6hQuality::VeryFast`]).
    pub bc6h: Bc6hQuality,
}

impl Default for TextureOptions {
    fn default() -> Self {
        Self {
            format: TexelFormat::Rgba16f,
            zstd: None,
            bc6h: Bc6hQuality::VeryFast,
        }
    }
}

/// Reads a KTX2 or DDS file (by extension) through the format registry:
/// checks its size on disk against the limit before reading it, then
/// decodes every level.
///
/// # Errors
///
/// Unreadable files, another extension (KTX 1 is written, not read), what
/// the container's decoder finds wrong, a texture above `max_texels`;
/// [`Error::Cancelled`].
pub fn read(
    path: &Path,
    max_texels: u64,
    cancel: Option<&std::sync::atomic::AtomicBool>,
) -> Result<TextureFile> {
    crate::cancel::check(cancel)?;
    let format = chain_format(path)?;
    let src = format::open(path, cancel)?;
    chain(path, format::read(path, format, src, max_texels)?)
}

/// Decodes a KTX2 or DDS file's `bytes` (the container from `path`'s
/// extension, which also names it in errors), as [`read`] does a file.
///
/// # Errors
///
/// As [`read`].
pub fn decode(path: &Path, bytes: &[u8], max_texels: u64) -> Result<TextureFile> {
    let format = chain_format(path)?;
    chain(
        path,
        format::read(path, format, format::memory(bytes, None), max_texels)?,
    )
}

/// The texture format `path` names; an error for another.
fn chain_format(path: &Path) -> Result<FileFormat> {
    match FileFormat::from_path(path) {
        Ok(f) if f.is_texture() => Ok(f),
        _ => Err(Error::unsupported(format!(
            "{}: not a KTX2 or DDS file name",
            path.display()
        ))),
    }
}

/// The chain a file held.
fn chain(path: &Path, contents: Contents) -> Result<TextureFile> {
    match contents {
        Contents::Chain(t) => Ok(t),
        Contents::Image(..) => Err(Error::unsupported(format!(
            "{}: not a KTX2 or DDS file name",
            path.display()
        ))),
    }
}

/// The bytes of `tex` as the file `path` names (KTX2, DDS or KTX 1 by
/// extension), and what packing clamped.
///
/// # Errors
///
/// Another extension; what the format's encoder refuses.
pub fn encode(tex: &Texture, path: &Path, opts: TextureOptions) -> Result<(Vec<u8>, Clamped)> {
    let format = FileFormat::from_path(path)
        .map_err(|_| Error::unsupported("not a KTX2, DDS or KTX file name").in_file(path))?;
    format
        .codec(path)?
        .write_chain(tex, opts)
        .map_err(|e| e.in_file(path))
}

/// An error unless `opts` asks for no supercompression (a container
/// without it).
#[cfg(any(feature = "dds", feature = "ktx1"))]
pub(crate) fn no_zstd(opts: TextureOptions, container: &str) -> Result<()> {
    match opts.zstd {
        Some(_) => Err(Error::options(format!(
            "{container} has no supercompression; zstd is for KTX2"
        ))),
        None => Ok(()),
    }
}
