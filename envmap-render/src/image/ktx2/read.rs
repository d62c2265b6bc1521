//! Reading a KTX 2.0 file: the header, the index, the Data Format
//! Descriptor checked against `vkFormat`, the key/value data and the
//! levels, every offset and length checked against the file before use.

use std::path::Path;

#[cfg(not(feature = "zstd"))]
use super::NO_ZSTD;
use super::{dfd, HEADER_LEN, IDENTIFIER, LEVEL_ENTRY, Q_LINEAR};
use crate::error::{Error, Result};
use crate::image::envimage::RgbImage;
use crate::image::texel::TexelFormat;
use crate::image::texture::{
    check_texels, full_chain, level_bytes, level_size, Texture, TextureFile, TextureInfo,
    TextureKind,
};
use crate::par::*;

/// One zstd frame decoded, its size known.
#[cfg(feature = "zstd")]
pub(super) fn decompress(data: &[u8], want: usize) -> std::result::Result<Vec<u8>, String> {
    zstd::bulk::decompress(data, want).map_err(|e| e.to_string())
}

/// Without the `zstd` feature: an error saying so.
#[cfg(not(feature = "zstd"))]
pub(super) fn decompress(_data: &[u8], _want: usize) -> std::result::Result<Vec<u8>, String> {
    Err(NO_ZSTD.to_owned())
}

pub(super) fn u32_at(b: &[u8], at: usize) -> u32 {
    u32::from_le_bytes([b[at], b[at + 1], b[at + 2], b[at + 3]])
}

fn u64_at(b: &[u8], at: usize) -> u64 {
    u64::from(u32_at(b, at)) | (u64::from(u32_at(b, at + 4)) << 32)
}

/// The slice `[offset, offset + len)` of `b`, or an error naming `what`.
fn section<'b>(
    b: &'b [u8],
    offset: u64,
    len: u64,
    what: &str,
) -> std::result::Result<&'b [u8], String> {
    let end = offset.checked_add(len);
    match end {
        Some(end) if end <= b.len() as u64 => Ok(&b[offset as usize..end as usize]),
        _ => Err(format!(
            "the {what} (bytes {offset}..{}) runs past the end of the file ({} bytes)",
            offset.saturating_add(len),
            b.len()
        )),
    }
}

/// Why a `vkFormat` envmap does not read is not read: a name for the
/// feature.
pub(super) fn unsupported_format(vk: u32) -> String {
    let what = match vk {
        0 => "VK_FORMAT_UNDEFINED (Basis Universal or another universal format)".to_owned(),
        124..=130 => format!("a depth/stencil format (vkFormat {vk})"),
        143 => "BC6H_UFLOAT_BLOCK (143), which needs envmap-render's `bc6h` feature (on by default; this build has it off),".to_owned(),
        131..=146 => format!("a BCn block-compressed format (vkFormat {vk})"),
        147..=156 => format!("an ETC2/EAC block-compressed format (vkFormat {vk})"),
        157..=184 | 1_000_066_000..=1_000_066_013 => {
            format!("an ASTC block-compressed format (vkFormat {vk})")
        }
        _ => format!("vkFormat {vk}"),
    };
    format!(
        "{what} is not supported; envmap reads R16G16B16A16_SFLOAT (97), R32G32B32A32_SFLOAT (109), \
         B10G11R11_UFLOAT_PACK32 (122), E5B9G9R9_UFLOAT_PACK32 (123), R16G16B16_SFLOAT (90), R32G32B32_SFLOAT (106) \
         and, with the `bc6h` feature, BC6H_UFLOAT_BLOCK (143)"
    )
}

/// Checks a file's DFD against the one `format` has (primaries, the alpha
/// flag and the L qualifier may differ; bytesPlane0 may be 0 under
/// supercompression, as older writers left it).
fn check_dfd(
    found: &[u8],
    format: TexelFormat,
    supercompressed: bool,
) -> std::result::Result<(), String> {
    let want = dfd(format);
    let mismatch = || {
        format!(
            "the Data Format Descriptor does not describe vkFormat {} ({})",
            format.vk_format(),
            format.vk_name()
        )
    };
    if found.len() < want.len() {
        return Err(mismatch());
    }
    let (fw, ww) = (|i| u32_at(found, 4 * i), |i| u32_at(&want, 4 * i));
    // Total size, block header, block size: exact.
    if fw(0) != ww(0) || fw(1) != ww(1) || fw(2) != ww(2) {
        return Err(mismatch());
    }
    // Colour model and transfer exact; primaries and flags free.
    if fw(3) & 0x00ff_00ff != ww(3) & 0x00ff_00ff {
        return Err(format!(
            "{}: colour model {} and transfer function {} (envmap reads linear RGB only)",
            mismatch(),
            fw(3) & 0xff,
            (fw(3) >> 16) & 0xff
        ));
    }
    if fw(4) != ww(4) || (fw(5) != ww(5) && !(supercompressed && fw(5) == 0)) || fw(6) != 0 {
        return Err(mismatch());
    }
    for i in 7..ww(0) as usize / 4 {
        let (mut f, w) = (fw(i), ww(i));
        if (i - 7) % 4 == 0 {
            f &= !(Q_LINEAR << 24);
        }
        if f != w {
            return Err(mismatch());
        }
    }
    Ok(())
}

/// The key/value entries of a KTX2 key/value section, in file order
/// (value without its terminating NUL). Malformed entries end the list
/// with an error.
fn parse_key_values(kvd: &[u8]) -> std::result::Result<Vec<(String, String)>, String> {
    let mut out = Vec::new();
    let mut at = 0usize;
    while at + 4 <= kvd.len() {
        let len = u32_at(kvd, at) as usize;
        let body = kvd
            .get(at + 4..(at + 4).saturating_add(len))
            .ok_or("a key/value entry runs past the key/value data")?;
        let nul = body
            .iter()
            .position(|&c| c == 0)
            .ok_or("a key/value entry has no NUL after its key")?;
        let key = String::from_utf8_lossy(&body[..nul]).into_owned();
        let value = &body[nul + 1..];
        let value = value.strip_suffix(&[0]).unwrap_or(value);
        out.push((key, String::from_utf8_lossy(value).into_owned()));
        at = (at + 4 + len).next_multiple_of(4);
    }
    Ok(out)
}

/// Reads a KTX2 file's bytes; errors name `path`.
///
/// # Errors
///
/// [`Error::Decode`] for anything malformed or unsupported (see the
/// [module docs](self)); [`Error::TooLarge`] above `max_texels` (all
/// levels and faces), before decoding.
pub(crate) fn decode(path: &Path, bytes: &[u8], max_texels: u64) -> Result<TextureFile> {
    decode_inner(bytes, max_texels).map_err(|e| match e {
        Failure::Message(m) => Error::Decode {
            path: path.to_path_buf(),
            format: "KTX2",
            message: m,
        },
        Failure::Error(e) => e.in_file(path),
    })
}

enum Failure {
    Message(String),
    Error(Error),
}

impl From<String> for Failure {
    fn from(m: String) -> Self {
        Failure::Message(m)
    }
}

impl From<&str> for Failure {
    fn from(m: &str) -> Self {
        Failure::Message(m.to_owned())
    }
}

/// Decodes a file's bytes: the header checked, then the texel count
/// against the limit, then the level index, the DFD and the key/value data
/// against the file, and only then the levels.
fn decode_inner(b: &[u8], max_texels: u64) -> std::result::Result<TextureFile, Failure> {
    let hd = parse_header(b)?;
    let (w, hgt) = hd.size;
    let (kind, format, n, zstd) = (hd.kind, hd.format, hd.levels, hd.zstd);
    check_texels(kind, w, hgt, n, max_texels).map_err(Failure::Error)?;
    let index = section(
        b,
        HEADER_LEN as u64,
        (LEVEL_ENTRY * n) as u64,
        "level index",
    )?;
    let dfd_bytes = section(b, hd.dfd.0, hd.dfd.1, "Data Format Descriptor")?;
    check_dfd(dfd_bytes, format, zstd)?;
    let kvd = section(b, hd.kvd.0, hd.kvd.1, "key/value data")?;
    let key_values = parse_key_values(kvd)?;
    let find = |k: &str| {
        key_values
            .iter()
            .find(|(key, _)| key == k)
            .map(|(_, v)| v.clone())
    };
    let orientation = find("KTXorientation");
    let writer = find("KTXwriter");
    let flips = orientation_flips(orientation.as_deref(), kind)?;
    let spans = level_spans(b, index, &hd)?;
    let levels = spans
        .par_iter()
        .enumerate()
        .map(|(p, &(data, want))| decode_level(&hd, p, data, want, flips))
        .collect::<std::result::Result<Vec<_>, String>>()?;
    let level_lens = spans.iter().map(|(d, _)| d.len() as u64).collect();
    let texture = Texture::new(kind, levels)
        .map_err(Failure::Error)?
        .with_tags(&key_values);
    Ok(TextureFile {
        texture,
        info: TextureInfo {
            container: "KTX2",
            format,
            kind,
            size: (w, hgt),
            levels: n,
            supercompression: zstd.then_some("zstd"),
            orientation,
            writer,
            key_values,
            level_bytes: level_lens,
        },
    })
}

/// What a file's header says, checked: a texture envmap reads.
struct Header {
    format: TexelFormat,
    kind: TextureKind,
    size: (u32, u32),
    /// The levels stored (`levelCount`, 0 read as 1).
    levels: usize,
    zstd: bool,
    /// The DFD's offset and length, not yet checked against the file.
    dfd: (u64, u64),
    /// The key/value data's offset and length, not yet checked.
    kvd: (u64, u64),
}

/// Reads the identifier and the header words, refusing, in the words'
/// order, what envmap does not read.
fn parse_header(b: &[u8]) -> std::result::Result<Header, String> {
    if b.len() < 12 || b[..12] != IDENTIFIER {
        return Err("not a KTX 2.0 file (the identifier «KTX 20» is missing)".into());
    }
    if b.len() < HEADER_LEN {
        return Err(format!("the header is cut short: {} of 80 bytes", b.len()));
    }
    let h = |i: usize| u32_at(b, 12 + 4 * i);
    let (vk, type_size, w, hgt, depth, layers, faces, level_count, scheme) =
        (h(0), h(1), h(2), h(3), h(4), h(5), h(6), h(7), h(8));
    let format = TexelFormat::from_vk_format(vk).ok_or_else(|| unsupported_format(vk))?;
    if type_size != format.type_size() {
        return Err(format!(
            "typeSize is {type_size}; {} has {}",
            format.vk_name(),
            format.type_size()
        ));
    }
    if depth != 0 {
        return Err(format!(
            "3D textures (pixelDepth {depth}) are not supported"
        ));
    }
    if layers != 0 {
        return Err(format!(
            "array textures (layerCount {layers}) are not supported"
        ));
    }
    if w == 0 || hgt == 0 {
        return Err(format!(
            "a {w}×{hgt} texture ({}) is not supported",
            if w == 0 { "no width" } else { "1D" }
        ));
    }
    let kind = match faces {
        1 => TextureKind::Flat,
        6 if w == hgt => TextureKind::Cube,
        6 => return Err(format!("faceCount 6 with non-square {w}×{hgt} faces")),
        _ => return Err(format!("faceCount {faces}; 1 or 6 are valid")),
    };
    let n = (level_count as usize).max(1);
    if n > full_chain(w, hgt) {
        return Err(format!(
            "levelCount {level_count} is more than the {} levels of a {w}×{hgt} chain",
            full_chain(w, hgt)
        ));
    }
    let zstd = supercompression(scheme)?;
    Ok(Header {
        format,
        kind,
        size: (w, hgt),
        levels: n,
        zstd,
        dfd: (u64::from(h(9)), u64::from(h(10))),
        kvd: (u64::from(h(11)), u64::from(h(12))),
    })
}

/// Whether `supercompressionScheme` is Zstandard (2) rather than none
/// (0); the schemes envmap does not read are refused by name.
fn supercompression(scheme: u32) -> std::result::Result<bool, String> {
    match scheme {
        0 => Ok(false),
        2 => Ok(true),
        1 => Err("BasisLZ supercompression (scheme 1) is not supported".into()),
        3 => Err(
            "ZLIB supercompression (scheme 3) is not supported; envmap reads none or Zstandard"
                .into(),
        ),
        s => Err(format!("unknown supercompression scheme {s}")),
    }
}

/// Which axes `KTXorientation` reverses (x, y) against top-left first;
/// a cube must be `rd`, as the spec requires.
fn orientation_flips(
    orientation: Option<&str>,
    kind: TextureKind,
) -> std::result::Result<(bool, bool), String> {
    match orientation.map(str::as_bytes) {
        None | Some(b"rd") => Ok((false, false)),
        Some([x @ (b'r' | b'l'), y @ (b'd' | b'u'), ..]) if kind == TextureKind::Flat => {
            Ok((*x == b'l', *y == b'u'))
        }
        Some(o) => Err(format!(
            "KTXorientation {:?} is not supported for {} (envmap reads rd{})",
            String::from_utf8_lossy(o),
            if kind == TextureKind::Cube {
                "a cube"
            } else {
                "this texture"
            },
            if kind == TextureKind::Cube {
                ", which the spec requires of cubes"
            } else {
                ", ru, ld, lu"
            }
        )),
    }
}

/// Each level's stored bytes and its length once decompressed, from the
/// level index, each length checked against the header's texture and
/// each span against the file.
fn level_spans<'b>(
    b: &'b [u8],
    index: &[u8],
    hd: &Header,
) -> std::result::Result<Vec<(&'b [u8], u64)>, String> {
    let (w, hgt) = hd.size;
    let (kind, format) = (hd.kind, hd.format);
    let mut spans = Vec::with_capacity(hd.levels);
    for p in 0..hd.levels {
        let e = &index[LEVEL_ENTRY * p..];
        let (off, len, raw) = (u64_at(e, 0), u64_at(e, 8), u64_at(e, 16));
        let want = level_bytes(kind, w, hgt, p, format).ok_or("a level's size overflows")?;
        if raw != want {
            return Err(format!(
                "level {p}: uncompressedByteLength is {raw}; a {}×{} {} level of {} is {want} bytes",
                level_size(w, hgt, p).0,
                level_size(w, hgt, p).1,
                if kind == TextureKind::Cube { "cube" } else { "2D" },
                format.vk_name()
            ));
        }
        if !hd.zstd && len != want {
            return Err(format!("level {p}: byteLength is {len}, expected {want}"));
        }
        let data = section(b, off, len, &format!("level {p}"))?;
        spans.push((data, want));
    }
    Ok(spans)
}

/// Level `p`'s faces from its stored bytes (`want` bytes once
/// decompressed), turned top-left first by `flips`.
fn decode_level(
    hd: &Header,
    p: usize,
    data: &[u8],
    want: u64,
    (flip_x, flip_y): (bool, bool),
) -> std::result::Result<Vec<RgbImage>, String> {
    let raw;
    let data = if hd.zstd {
        raw = decompress(data, want as usize)
            .map_err(|e| format!("level {p}: the zstd data does not decode: {e}"))?;
        if raw.len() as u64 != want {
            return Err(format!(
                "level {p}: the zstd data holds {} bytes, expected {want}",
                raw.len()
            ));
        }
        &raw[..]
    } else {
        data
    };
    let (lw, lh) = level_size(hd.size.0, hd.size.1, p);
    let face_bytes = hd.format.image_bytes(lw, lh);
    Ok(data
        .chunks_exact(face_bytes)
        .map(|f| {
            let mut img = RgbImage {
                width: lw,
                height: lh,
                pixels: hd.format.unpack_image(f, (lw, lh)),
            };
            flip(&mut img, flip_x, flip_y);
            img
        })
        .collect::<Vec<_>>())
}

/// Turns an image stored with other axes (`l`: right to left, `u`: bottom
/// up) to the top-left-first order.
fn flip(img: &mut RgbImage, x: bool, y: bool) {
    let w = img.width as usize;
    if x {
        for row in img.pixels.chunks_exact_mut(w) {
            row.reverse();
        }
    }
    if y {
        let h = img.height as usize;
        for j in 0..h / 2 {
            let (top, bottom) = img.pixels.split_at_mut((h - 1 - j) * w);
            top[j * w..(j + 1) * w].swap_with_slice(&mut bottom[..w]);
        }
    }
}
