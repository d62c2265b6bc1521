//! KTX 1 files (Khronos, "KTX File Format Specification" 1.1), written as
//! Filament's `cmgen` writes them: cube maps (or 2D images) with their mip
//! levels, for `Texture` loaders that still read KTX 1 (Filament's
//! `KtxBundle`, `ktxreader`).
//!
//! Layout (§"File Structure"): the identifier «KTX 11»\r\n\x1A\n,
//! endianness `0x04030201`, then `glType`, `glTypeSize`, `glFormat`,
//! `glInternalFormat`, `glBaseInternalFormat` of `gl_format`,
//! `pixelWidth`, `pixelHeight`, `pixelDepth` 0, `numberOfArrayElements` 0,
//! `numberOfFaces` 6 or 1, `numberOfMipmapLevels`, `bytesOfKeyValueData`;
//! the key/value pairs, each `{u32 size, key NUL value}` padded to 4 bytes;
//! then per level, largest first, `imageSize` (the bytes of **one face** for
//! a cube that is not an array, §"imageSize") and the faces in GL order,
//! each padded to 4 bytes (our texels are 4 bytes or more, so rows and
//! faces need no padding). Rows run top-down, faces exactly as
//! `glTexImage2D(GL_TEXTURE_CUBE_MAP_POSITIVE_X + i)` takes them.

use std::path::Path;

use crate::error::{Error, Result};
use crate::image::format::{Codec, Contents, Source};
use crate::image::texel::{Clamped, TexelFormat};
use crate::image::texture::{no_zstd, Texture, TextureOptions};

/// KTX 1's codec: written, not read.
pub(crate) struct Ktx1;

impl Codec for Ktx1 {
    fn read(&self, path: &Path, _src: Source<'_>, _max_texels: u64) -> Result<Contents> {
        Err(ktx1_is_written(path))
    }

    fn write_chain(&self, tex: &Texture, opts: TextureOptions) -> Result<(Vec<u8>, Clamped)> {
        no_zstd(opts, "KTX 1")?;
        encode(tex, opts.format, &[])
    }
}

/// The error for reading a KTX 1 file.
pub(crate) fn ktx1_is_written(path: &Path) -> Error {
    Error::Decode {
        path: path.to_path_buf(),
        format: "KTX 1",
        message: "KTX 1 files are written (for Filament), not read; read its KTX2 or DDS twin"
            .into(),
    }
}

/// The file identifier: «KTX 11»\r\n\x1A\n.
pub(crate) const IDENTIFIER: [u8; 12] = [
    0xAB, 0x4B, 0x54, 0x58, 0x20, 0x31, 0x31, 0xBB, 0x0D, 0x0A, 0x1A, 0x0A,
];

/// The GL enums of a format: `glType`, `glTypeSize`, `glFormat`,
/// `glInternalFormat`, `glBaseInternalFormat` (OpenGL 4.6 tables 8.2, 8.3,
/// 8.12; R11F_G11F_B10F as `cmgen` writes it).
#[must_use]
pub(crate) const fn gl_format(format: TexelFormat) -> [u32; 5] {
    const GL_RGB: u32 = 0x1907;
    const GL_RGBA: u32 = 0x1908;
    match format {
        // GL_HALF_FLOAT, GL_RGBA16F
        TexelFormat::Rgba16f => [0x140B, 2, GL_RGBA, 0x881A, GL_RGBA],
        // GL_FLOAT, GL_RGBA32F
        TexelFormat::Rgba32f => [0x1406, 4, GL_RGBA, 0x8814, GL_RGBA],
        // As cmgen writes it, and as Filament's KTX 1 reader (ktxreader)
        // needs it: glType GL_R11F_G11F_B10F (0x8C3A, which that reader maps
        // to UINT_10F_11F_11F_REV; it has no case for the GL type enum
        // 0x8C3B), glTypeSize 1, glFormat GL_RGB, internal and base internal
        // format GL_R11F_G11F_B10F.
        TexelFormat::B10g11r11 => [0x8C3A, 1, GL_RGB, 0x8C3A, 0x8C3A],
        // GL_UNSIGNED_INT_5_9_9_9_REV, GL_RGB9_E5
        TexelFormat::E5b9g9r9 => [0x8C3E, 4, GL_RGB, 0x8C3D, GL_RGB],
        // GL_HALF_FLOAT, GL_RGB16F
        TexelFormat::Rgb16f => [0x140B, 2, GL_RGB, 0x881B, GL_RGB],
        // GL_FLOAT, GL_RGB32F
        TexelFormat::Rgb32f => [0x1406, 4, GL_RGB, 0x8815, GL_RGB],
        // Compressed: glType and glFormat 0, glTypeSize 1,
        // GL_COMPRESSED_RGB_BPTC_UNSIGNED_FLOAT (not written: see `encode`).
        TexelFormat::Bc6h => [0, 1, 0, 0x8E8F, GL_RGB],
        // GL_UNSIGNED_BYTE, GL_RGBA8 (not written: see `encode`).
        TexelFormat::Rgbd8 => [0x1401, 1, GL_RGBA, 0x8058, GL_RGBA],
    }
}

/// The KTX 1 file of `tex` in `format` with `key_values` (written in the
/// order given, key NUL-terminated, value as given: cmgen writes its `sh`
/// text without a terminating NUL); returns the bytes and what packing
/// clamped.
///
/// # Errors
///
/// A format envmap does not write.
pub(crate) fn encode(
    tex: &Texture,
    format: TexelFormat,
    key_values: &[(&str, &[u8])],
) -> Result<(Vec<u8>, Clamped)> {
    if format == TexelFormat::Bc6h {
        return Err(Error::unsupported(
            "KTX 1 files are written uncompressed (rgba16f, rgba32f, rg11b10f, rgb9e5); \
             BC6H goes in KTX2 or DDS",
        ));
    }
    if format == TexelFormat::Rgbd8 {
        return Err(Error::unsupported(crate::image::texel::RGBD_IN_ENV));
    }
    if !format.is_writable() {
        return Err(Error::unsupported(format!(
            "{} is read only; write one of {}",
            format.name(),
            TexelFormat::NAMES
        )));
    }
    let mut kvd = Vec::new();
    for (k, v) in key_values {
        let len = k.len() + 1 + v.len();
        kvd.extend_from_slice(&(len as u32).to_le_bytes());
        kvd.extend_from_slice(k.as_bytes());
        kvd.push(0);
        kvd.extend_from_slice(v);
        kvd.resize(kvd.len().next_multiple_of(4), 0);
    }
    let (w, h) = tex.size();
    let faces = tex.kind().faces();
    let (levels, clamped) = tex.pack(format);
    let mut out = Vec::with_capacity(64 + kvd.len() + levels.iter().map(Vec::len).sum::<usize>());
    out.extend_from_slice(&IDENTIFIER);
    let gl = gl_format(format);
    for v in [
        0x0403_0201,
        gl[0],
        gl[1],
        gl[2],
        gl[3],
        gl[4],
        w,
        h,
        0,
        0,
        faces as u32,
        levels.len() as u32,
        kvd.len() as u32,
    ] {
        out.extend_from_slice(&u32::to_le_bytes(v));
    }
    out.extend_from_slice(&kvd);
    for level in &levels {
        // One face's bytes for a (non-array) cube, the whole image otherwise.
        let image_size = level.len() / faces;
        out.extend_from_slice(&(image_size as u32).to_le_bytes());
        for face in level.chunks_exact(image_size) {
            out.extend_from_slice(face);
            out.resize(out.len().next_multiple_of(4), 0);
        }
    }
    Ok((out, clamped))
}
