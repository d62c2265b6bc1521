//! DDS files (Microsoft, "DDS_HEADER", "DDS_HEADER_DXT10", "DDS file layout
//! for cubic environment maps"): 2D images and cube maps with mip levels,
//! written and read, the container through the `ddsfile` crate.
//!
//! Written: the `DDS ` magic, the 124-byte header (pitch, mip count, caps
//! `TEXTURE|COMPLEX|MIPMAP`, a cube's `CUBEMAP` and six face bits), the DX10
//! header (the DXGI format of [`TexelFormat::dxgi_format`], resource
//! dimension `TEXTURE2D`, misc flag `TEXTURECUBE` for a cube, arraySize 1:
//! the number of cubes, not faces; alpha mode unknown), then the texels
//! **face-major**: +X with its whole chain largest first, then −X, and so
//! on (a 2D image is one "face"). Rows run top-down, tightly packed; faces
//! keep GL's orientation, the same as KTX2's.
//!
//! Read: those four formats and R32G32B32_FLOAT by their DXGI number, and
//! header-only files of the legacy FourCC codes 113 (A16B16G16R16F) and 116
//! (A32B32G32R32F). Block-compressed formats (BC6H, ...), arrays, volume
//! and 1D textures are refused with an error naming the feature; the data
//! length is checked against the header before anything is decoded.

use std::path::Path;

use ddsfile::{AlphaMode, Caps2, D3D10ResourceDimension, DxgiFormat, NewDxgiParams};

use crate::error::{Error, Result};
use crate::image::envimage::RgbImage;
use crate::image::format::{whole, Codec, Contents, FileFormat, Source};
use crate::image::texel::{Clamped, TexelFormat};
use crate::image::texture::{
    check_texels, full_chain, level_bytes, level_size, no_zstd, Texture, TextureFile, TextureInfo,
    TextureKind, TextureOptions,
};

/// DDS's codec.
pub(crate) struct Dds;

impl Codec for Dds {
    fn read(&self, path: &Path, src: Source<'_>, max_texels: u64) -> Result<Contents> {
        let bytes = whole(path, FileFormat::Dds, src, max_texels)?;
        decode(path, &bytes, max_texels).map(Contents::Chain)
    }

    fn write_chain(&self, tex: &Texture, opts: TextureOptions) -> Result<(Vec<u8>, Clamped)> {
        no_zstd(opts, "DDS")?;
        encode(tex, opts)
    }
}

/// The `ddsfile` format of a texel format.
fn dxgi(format: TexelFormat) -> Option<DxgiFormat> {
    Some(match format {
        TexelFormat::Rgba16f => DxgiFormat::R16G16B16A16_Float,
        TexelFormat::Rgba32f => DxgiFormat::R32G32B32A32_Float,
        TexelFormat::B10g11r11 => DxgiFormat::R11G11B10_Float,
        TexelFormat::E5b9g9r9 => DxgiFormat::R9G9B9E5_SharedExp,
        TexelFormat::Rgb32f => DxgiFormat::R32G32B32_Float,
        TexelFormat::Bc6h => DxgiFormat::BC6H_UF16,
        TexelFormat::Rgb16f | TexelFormat::Rgbd8 => return None,
    })
}

/// The DDS file of `tex` in `opts.format` (BC6H at `opts.bc6h`); returns
/// the bytes and what packing clamped.
///
/// # Errors
///
/// A format DDS has no DXGI number for (RGB16F) or envmap does not write.
pub(crate) fn encode(tex: &Texture, opts: TextureOptions) -> Result<(Vec<u8>, Clamped)> {
    let format = opts.format;
    if format == TexelFormat::Bc6h && !format.is_writable() {
        return Err(Error::unsupported(crate::image::texel::NO_BC6H));
    }
    if format == TexelFormat::Rgbd8 {
        return Err(Error::unsupported(crate::image::texel::RGBD_IN_ENV));
    }
    let dxgi_format = dxgi(format)
        .filter(|_| format.is_writable())
        .ok_or_else(|| {
            Error::unsupported(format!(
                "{} cannot be written as DDS; write one of {}",
                format.name(),
                TexelFormat::NAMES
            ))
        })?;
    let (w, h) = tex.size();
    let cube = tex.kind() == TextureKind::Cube;
    let n = tex.level_count();
    let mut dds = ddsfile::Dds::new_dxgi(NewDxgiParams {
        height: h,
        width: w,
        depth: None,
        format: dxgi_format,
        mipmap_levels: Some(n as u32),
        array_layers: cube.then_some(6),
        // ddsfile leaves caps2 to the caller: a cube needs CUBEMAP and
        // all six face bits (0xFE00) for readers that look only there.
        caps2: cube.then_some(Caps2::CUBEMAP | Caps2::CUBEMAP_ALLFACES),
        is_cubemap: cube,
        resource_dimension: D3D10ResourceDimension::Texture2D,
        alpha_mode: AlphaMode::Unknown,
    })
    .map_err(|e| Error::codec("DDS", format!("DDS header: {e}")))?;
    // Face-major: each face with its chain.
    let mut data = Vec::with_capacity(dds.data.len());
    let mut clamped = Clamped::default();
    for face in 0..tex.kind().faces() {
        for level in tex.levels() {
            let img = &level[face];
            let at = data.len();
            data.resize(at + format.image_bytes(img.width, img.height), 0);
            clamped.add(format.pack_image_into(
                &img.pixels,
                (img.width, img.height),
                opts.bc6h,
                &mut data[at..],
            ));
        }
    }
    if data.len() != dds.data.len() {
        return Err(Error::codec(
            "DDS",
            format!(
                "DDS layout: {} bytes of texels for a header that holds {}",
                data.len(),
                dds.data.len()
            ),
        ));
    }
    dds.data = data;
    let mut out = Vec::with_capacity(dds.data.len() + 148);
    dds.write(&mut out)
        .map_err(|e| Error::codec("DDS", format!("DDS: {e}")))?;
    Ok((out, clamped))
}

/// Reads a DDS file's bytes; errors name `path`.
///
/// # Errors
///
/// [`Error::Decode`] for anything malformed or unsupported (see the
/// [module docs](self)); [`Error::TooLarge`] above `max_texels`, before
/// decoding.
pub(crate) fn decode(path: &Path, bytes: &[u8], max_texels: u64) -> Result<TextureFile> {
    let fail = |m: String| Error::Decode {
        path: path.to_path_buf(),
        format: "DDS",
        message: m,
    };
    let dds =
        ddsfile::Dds::read(bytes).map_err(|e| fail(format!("the header does not parse: {e}")))?;
    let hd = &dds.header;
    let (w, h) = (hd.width, hd.height);
    let (format, kind, n) = check_header(&dds).map_err(fail)?;
    check_texels(kind, w, h, n, max_texels).map_err(|e| e.in_file(path))?;
    let level_lens: Vec<u64> = (0..n)
        .map(|p| level_bytes(TextureKind::Flat, w, h, p, format).unwrap_or(u64::MAX))
        .collect();
    let per_face: u64 = level_lens.iter().fold(0u64, |a, &b| a.saturating_add(b));
    let need = per_face.saturating_mul(kind.faces() as u64);
    if (dds.data.len() as u64) < need {
        return Err(fail(format!(
            "the texel data is cut short: {} of {need} bytes",
            dds.data.len()
        )));
    }
    let levels = face_major_levels(&dds.data, format, kind, (w, h), &level_lens);
    let texture = Texture::new(kind, levels).map_err(|e| e.in_file(path))?;
    Ok(TextureFile {
        texture,
        info: TextureInfo {
            container: "DDS",
            format,
            kind,
            size: (w, h),
            levels: n,
            supercompression: None,
            orientation: None,
            writer: None,
            key_values: Vec::new(),
            level_bytes: level_lens.iter().map(|l| l * kind.faces() as u64).collect(),
        },
    })
}

/// The texel format, the kind and the level count of a parsed file,
/// refusing (in this order) an empty image, a volume, a format envmap
/// does not read, a cube it cannot, and more levels than the size has.
fn check_header(
    dds: &ddsfile::Dds,
) -> std::result::Result<(TexelFormat, TextureKind, usize), String> {
    let hd = &dds.header;
    let (w, h) = (hd.width, hd.height);
    if w == 0 || h == 0 {
        return Err(format!("a {w}×{h} image is empty"));
    }
    if hd.depth.is_some_and(|d| d > 1) || hd.caps2.contains(Caps2::VOLUME) {
        return Err("volume (3D) textures are not supported".into());
    }
    let (format, cube) = match &dds.header10 {
        Some(h10) => dx10_format(h10)?,
        None => (legacy_format(hd)?, hd.caps2.contains(Caps2::CUBEMAP)),
    };
    let kind = if cube {
        if w != h {
            return Err(format!("a cube with non-square {w}×{h} faces"));
        }
        if hd.caps2 & Caps2::CUBEMAP_ALLFACES != Caps2::CUBEMAP_ALLFACES && dds.header10.is_none() {
            return Err("a cube without all six faces is not supported".into());
        }
        TextureKind::Cube
    } else {
        TextureKind::Flat
    };
    let n = hd.mip_map_count.unwrap_or(1).max(1) as usize;
    if n > full_chain(w, h) {
        return Err(format!(
            "mip count {n} is more than the {} levels of a {w}×{h} chain",
            full_chain(w, h)
        ));
    }
    Ok((format, kind, n))
}

/// The texel format of a DX10 header and whether it is a cube: a 2D
/// texture (or one cube) in a DXGI format envmap reads.
fn dx10_format(h10: &ddsfile::Header10) -> std::result::Result<(TexelFormat, bool), String> {
    let number = h10.dxgi_format as u32;
    let format = TexelFormat::from_dxgi_format(number).ok_or_else(|| {
        format!(
            "DXGI format {number} ({:?}) is not supported; envmap reads R16G16B16A16_FLOAT (10), \
             R32G32B32A32_FLOAT (2), R11G11B10_FLOAT (26), R9G9B9E5_SHAREDEXP (67), R32G32B32_FLOAT (6) \
             and, with the `bc6h` feature, BC6H_UF16 (95)",
            h10.dxgi_format
        )
    })?;
    if h10.resource_dimension != D3D10ResourceDimension::Texture2D {
        return Err(format!(
            "resource dimension {:?} is not supported (2D textures and cubes only)",
            h10.resource_dimension
        ));
    }
    if h10.array_size != 1 {
        return Err(format!(
            "array textures (arraySize {}) are not supported",
            h10.array_size
        ));
    }
    let cube = h10.misc_flag.contains(ddsfile::MiscFlag::TEXTURECUBE);
    Ok((format, cube))
}

/// The texel format of a file without a DX10 header: only the legacy
/// FourCC codes of the two float formats.
fn legacy_format(hd: &ddsfile::Header) -> std::result::Result<TexelFormat, String> {
    let fourcc = hd.spf.fourcc.as_ref().map(|f| f.0);
    match fourcc {
        Some(113) => Ok(TexelFormat::Rgba16f),
        Some(116) => Ok(TexelFormat::Rgba32f),
        Some(code) => {
            let text: String = code
                .to_le_bytes()
                .iter()
                .map(|&c| if c.is_ascii_graphic() { c as char } else { '?' })
                .collect();
            Err(format!(
                "FourCC {code} ({text:?}) is not supported (block-compressed or other legacy \
                 formats); envmap reads DX10-header files and FourCC 113 and 116"
            ))
        }
        None => Err(
            "bitmask (8-bit) pixel formats are not supported; envmap reads float formats".into(),
        ),
    }
}

/// The levels of face-major texel data (each face with its whole chain,
/// largest level first), regrouped level by level; `data` holds at least
/// the bytes of `level_lens` for every face.
fn face_major_levels(
    data: &[u8],
    format: TexelFormat,
    kind: TextureKind,
    (w, h): (u32, u32),
    level_lens: &[u64],
) -> Vec<Vec<RgbImage>> {
    let mut levels: Vec<Vec<RgbImage>> = vec![Vec::with_capacity(kind.faces()); level_lens.len()];
    let mut at = 0usize;
    for _ in 0..kind.faces() {
        for (p, &len) in level_lens.iter().enumerate() {
            let (lw, lh) = level_size(w, h, p);
            let bytes = &data[at..at + len as usize];
            at += len as usize;
            levels[p].push(RgbImage {
                width: lw,
                height: lh,
                pixels: format.unpack_image(bytes, (lw, lh)),
            });
        }
    }
    levels
}
