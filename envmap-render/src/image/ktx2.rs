//! KTX 2.0 files (Khronos, `ktxspec.adoc` v2.0): 2D textures and cube maps
//! with their mip levels, uncompressed or with Zstandard supercompression
//! (scheme 2), written and read.
//!
//! What is written, in file order (§"File Structure"):
//!
//! * the 12-byte identifier, the nine header words (`vkFormat`, `typeSize`
//!   as [`TexelFormat::type_size`] — kept under zstd, `pixelWidth`,
//!   `pixelHeight`, `pixelDepth` 0, `layerCount` 0, `faceCount` 1 or 6,
//!   `levelCount` the levels stored, never 0, `supercompressionScheme` 0 or
//!   2) and the index;
//! * the level index, largest level first;
//! * the Data Format Descriptor: one basic block, colour model RGBSDA,
//!   primaries BT.709, transfer linear, straight alpha, one sample per
//!   channel (RGB9E5: mantissa and exponent per channel), bounds as
//!   §"Data Format Descriptor" and the Khronos Data Format Specification
//!   1.4 give them ([`dfd`]);
//! * the key/value data: `KTXorientation` = `rd`, `KTXwriter` =
//!   `envmap <version>` and, for a texture of environment maps, what its
//!   directions mean: `envmap.mapping`, `envmap.layout` (2D) and
//!   `envmap.axes` ([`crate::image::metadata`]; a Bevy cube's z-negated
//!   world, say), sorted, each entry padded to 4 bytes with zeros; reading
//!   gives them back ([`Texture::tags`]);
//! * the levels, smallest first, each starting at the next multiple of
//!   lcm(texel size, 4) with zero padding (8 for RGBA16F, 16 for RGBA32F,
//!   4 for the packed formats); under zstd each level is one frame, no
//!   padding (alignment 1), compressed in parallel.
//!
//! Inside a level: faces +X, −X, +Y, −Y, +Z, −Z, rows top-down, tightly
//! packed (§"levelImages").
//!
//! Reading accepts the writable formats and R16G16B16_SFLOAT (90) and
//! R32G32B32_SFLOAT (106), with or without zstd; Basis Universal, BCn,
//! ETC, ASTC, depth formats, array textures, 3D and 1D textures are
//! refused with an error naming the feature. The DFD must describe the
//! `vkFormat` (primaries and the L qualifier aside). Every offset and length
//! is checked against the file before use, and the texel count against the
//! limit before any level is decoded.

mod read;

pub(crate) use read::decode;
#[cfg(feature = "bc6h")]
use read::decompress;

use std::path::Path;

use crate::par::*;

use crate::error::{Error, Result};
#[cfg(any(feature = "bc6h", test))]
use crate::image::envimage::RgbImage;
use crate::image::format::{whole, Codec, Contents, FileFormat, Source};
use crate::image::texel::{Clamped, TexelFormat};
use crate::image::texture::{Texture, TextureOptions};

/// KTX2's codec.
pub(crate) struct Ktx2;

impl Codec for Ktx2 {
    fn read(&self, path: &Path, src: Source<'_>, max_texels: u64) -> Result<Contents> {
        let bytes = whole(path, FileFormat::Ktx2, src, max_texels)?;
        decode(path, &bytes, max_texels).map(Contents::Chain)
    }

    fn write_chain(&self, tex: &Texture, opts: TextureOptions) -> Result<(Vec<u8>, Clamped)> {
        encode(tex, opts)
    }
}

/// The file identifier: «KTX 20»\r\n\x1A\n.
pub(crate) const IDENTIFIER: [u8; 12] = [
    0xAB, 0x4B, 0x54, 0x58, 0x20, 0x32, 0x30, 0xBB, 0x0D, 0x0A, 0x1A, 0x0A,
];

const HEADER_LEN: usize = 80;
const LEVEL_ENTRY: usize = 24;

/// The DFD sample qualifiers (KDFS §"Sample information"): float, signed,
/// exponent, linear.
const Q_FLOAT: u32 = 0x80;
const Q_SIGNED: u32 = 0x40;
const Q_EXPONENT: u32 = 0x20;
const Q_LINEAR: u32 = 0x10;
/// 1.0 and −1.0 as f32 bits: the bounds of float samples.
const ONE: u32 = 0x3F80_0000;
const MINUS_ONE: u32 = 0xBF80_0000;

/// One DFD sample: bit offset, bit length, channel id (R 0, G 1, B 2,
/// A 15) with qualifiers, lower and upper.
fn sample(offset: u32, bits: u32, channel: u32, lower: u32, upper: u32) -> [u32; 4] {
    [
        offset | ((bits - 1) << 16) | (channel << 24),
        0,
        lower,
        upper,
    ]
}

/// The Data Format Descriptor of `format`, as bytes (dfdTotalSize
/// included): one Khronos basic block (KDFS 1.4 §5), colour model RGBSDA,
/// primaries BT.709, transfer linear, straight alpha, texel block 1×1,
/// bytesPlane0 the texel size (BC6H: colour model BC6H, texel block 4×4,
/// bytesPlane0 16, one 128-bit unsigned-float sample), and the samples of `ktxspec` §"Data Format
/// Descriptor" (signed floats bounded by −1.0 and 1.0, unsigned by 0 and
/// 1.0; RGB9E5's mantissas 0 and 8448 = 256·2^(16−15)·… — 1.0 as mantissa
/// 256 at exponent 16 — and its exponents 15 and 31, the KDFS example
/// `exampledescriptor_e5b9g9r9`).
#[must_use]
pub(crate) fn dfd(format: TexelFormat) -> Vec<u8> {
    let float_rgba = |bits: u32, n: u32| {
        (0..n)
            .map(|i| {
                let ch = if i == 3 { 15 } else { i };
                sample(i * bits, bits, ch | Q_FLOAT | Q_SIGNED, MINUS_ONE, ONE)
            })
            .collect::<Vec<_>>()
    };
    let samples = match format {
        TexelFormat::Rgba16f => float_rgba(16, 4),
        TexelFormat::Rgba32f => float_rgba(32, 4),
        TexelFormat::Rgb16f => float_rgba(16, 3),
        TexelFormat::Rgb32f => float_rgba(32, 3),
        TexelFormat::B10g11r11 => vec![
            sample(0, 11, Q_FLOAT, 0, ONE),
            sample(11, 11, 1 | Q_FLOAT, 0, ONE),
            sample(22, 10, 2 | Q_FLOAT, 0, ONE),
        ],
        TexelFormat::E5b9g9r9 => (0..3)
            .flat_map(|c| {
                [
                    sample(9 * c, 9, c, 0, 8448),
                    sample(27, 5, c | Q_EXPONENT, 15, 31),
                ]
            })
            .collect(),
        // The whole 128-bit block as one unsigned-float colour sample
        // (KDFS 1.4 §5.6 and its BC6H example).
        TexelFormat::Bc6h => vec![sample(0, 128, Q_FLOAT, 0, ONE)],
        // Four 8-bit unorm channels (never written: see
        // `check_write_options`).
        TexelFormat::Rgbd8 => (0..4)
            .map(|i| sample(8 * i, 8, if i == 3 { 15 } else { i }, 0, 255))
            .collect(),
    };
    // Colour model RGBSDA (1), or BC6H (133) with its 4×4×1 texel block
    // (stored as dimensions − 1); primaries BT.709 and transfer linear.
    let (model, dims) = match format {
        TexelFormat::Bc6h => (133, 0x0303),
        _ => (1, 0),
    };
    let n = samples.len() as u32;
    let block = 24 + 16 * n;
    let mut words = vec![
        4 + block,
        0,
        2 | (block << 16),
        model | 0x0001_0100,
        dims,
        format.bytes() as u32,
        0,
    ];
    words.extend(samples.into_iter().flatten());
    words.iter().flat_map(|w| w.to_le_bytes()).collect()
}

/// The key/value data: each entry `{u32 length, key, NUL, value, NUL}`
/// padded with zeros to 4 bytes, sorted by key (§"Key/Value Data").
fn key_values(entries: &[(&str, &str)]) -> Vec<u8> {
    let mut sorted = entries.to_vec();
    sorted.sort_by(|a, b| a.0.cmp(b.0));
    let mut out = Vec::new();
    for (k, v) in sorted {
        let len = k.len() + 1 + v.len() + 1;
        out.extend_from_slice(&(len as u32).to_le_bytes());
        out.extend_from_slice(k.as_bytes());
        out.push(0);
        out.extend_from_slice(v.as_bytes());
        out.push(0);
        out.resize(out.len().next_multiple_of(4), 0);
    }
    out
}

/// lcm(texel or block size, 4): the alignment of every level without
/// supercompression (§"mipPadding").
#[must_use]
pub(crate) fn level_alignment(format: TexelFormat) -> usize {
    let t = format.bytes();
    let gcd = |mut a: usize, mut b: usize| {
        while b != 0 {
            (a, b) = (b, a % b);
        }
        a
    };
    t / gcd(t, 4) * 4
}

/// What `KTXwriter` says: `envmap` and its version.
#[must_use]
pub(crate) fn writer_name() -> String {
    format!("envmap {}", env!("CARGO_PKG_VERSION"))
}

/// The KTX2 file of `tex` in `opts.format`, zstd-compressed if
/// `opts.zstd` says; returns the bytes and what packing clamped.
///
/// # Errors
///
/// A read-only format, or a zstd level outside 1–22.
pub(crate) fn encode(tex: &Texture, opts: TextureOptions) -> Result<(Vec<u8>, Clamped)> {
    let format = opts.format;
    check_write_options(opts)?;
    let n = tex.level_count();
    let raw_lens: Vec<usize> = (0..n).map(|p| tex.level_len(p, format)).collect();
    // Under zstd each level is packed, then compressed as one frame (by
    // several workers for the large levels); without, the levels are
    // packed straight into their place in the file.
    let (compressed, clamped) = match opts.zstd {
        None => (None, Clamped::default()),
        Some(level) => {
            let (frames, clamped) = compress_levels(tex, opts, &raw_lens, level)?;
            (Some(frames), clamped)
        }
    };
    // BC6H is lossy: its levels are packed first (unless zstd did), read
    // back by the independent decoder and measured, and the error goes in
    // the key/value data.
    #[cfg(feature = "bc6h")]
    let (compressed, mut clamped, errors) = match (format, compressed) {
        (TexelFormat::Bc6h, c) => {
            let (raw, c2): (Vec<Vec<u8>>, Clamped) = match &c {
                Some(frames) => (
                    frames
                        .iter()
                        .zip(&raw_lens)
                        .map(|(z, &n)| decompress(z, n).unwrap_or_default())
                        .collect(),
                    clamped,
                ),
                None => {
                    let mut all = Clamped::default();
                    let raw = (0..n)
                        .map(|p| {
                            let mut out = vec![0u8; raw_lens[p]];
                            all.add(tex.pack_level_into(p, format, opts.bc6h, &mut out));
                            out
                        })
                        .collect();
                    (raw, all)
                }
            };
            let errors = bc6h_errors(tex, &raw);
            let stored = c.unwrap_or_else(|| raw.clone());
            (Some(stored), c2, Some(errors))
        }
        (_, c) => (c, clamped, None),
    };
    #[cfg(not(feature = "bc6h"))]
    let (errors, mut clamped): (Option<String>, _) = (None, clamped);
    let stored_lens: Vec<usize> = match &compressed {
        Some(c) => c.iter().map(Vec::len).collect(),
        None => raw_lens.clone(),
    };
    let dfd = dfd(format);
    let kvd = file_key_values(tex, errors.as_deref());
    let align = if opts.zstd.is_some() {
        1
    } else {
        level_alignment(format)
    };
    let layout = Layout::new(n, dfd.len(), kvd.len(), align, &stored_lens);
    // Zeroed: the padding between sections must be zeros.
    let mut out = vec![0u8; layout.len];
    let head = head_bytes(
        tex,
        format,
        opts.zstd.is_some(),
        &layout,
        &stored_lens,
        &raw_lens,
    );
    out[..head.len()].copy_from_slice(&head);
    out[layout.dfd_offset..layout.kvd_offset].copy_from_slice(&dfd);
    out[layout.kvd_offset..layout.kvd_offset + kvd.len()].copy_from_slice(&kvd);
    for p in 0..n {
        let at = layout.levels[p];
        let dst = &mut out[at..at + stored_lens[p]];
        match &compressed {
            Some(c) => dst.copy_from_slice(&c[p]),
            None => clamped.add(tex.pack_level_into(p, format, opts.bc6h, dst)),
        }
    }
    Ok((out, clamped))
}

/// Refuses what [`encode`] cannot write before any work is done: a
/// read-only format, zstd in a build without it, a zstd level zstd lacks.
fn check_write_options(opts: TextureOptions) -> Result<()> {
    let format = opts.format;
    if format == TexelFormat::Bc6h && !format.is_writable() {
        return Err(Error::unsupported(crate::image::texel::NO_BC6H));
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
    #[cfg(not(feature = "zstd"))]
    if opts.zstd.is_some() {
        return Err(Error::unsupported(NO_ZSTD));
    }
    if let Some(l) = opts.zstd {
        if !(1..=22).contains(&l) {
            return Err(Error::options(format!(
                "zstd level {l}: levels 1 (fastest) to 22 (smallest) exist"
            )));
        }
    }
    Ok(())
}

/// Each level of `tex` packed in `opts.format` and compressed as one zstd
/// frame at `level`, largest level first, with what packing clamped.
/// Level 0 (three quarters of the bytes) is compressed by zstd's own
/// workers, the others on the pool meanwhile.
fn compress_levels(
    tex: &Texture,
    opts: TextureOptions,
    raw_lens: &[usize],
    level: i32,
) -> Result<(Vec<Vec<u8>>, Clamped)> {
    let n = raw_lens.len();
    let one = |p: usize| {
        let mut raw = vec![0u8; raw_lens[p]];
        let c = tex.pack_level_into(p, opts.format, opts.bc6h, &mut raw);
        compress(&raw, level).map(|z| (z, c))
    };
    let (first, rest) = crate::par::join(
        || one(0),
        || {
            (1..n)
                .into_par_iter()
                .map(one)
                .collect::<std::io::Result<Vec<_>>>()
        },
    );
    let all = std::iter::once(first)
        .chain(rest.map_or_else(|e| vec![Err(e)], |v| v.into_iter().map(Ok).collect()))
        .collect::<std::io::Result<Vec<_>>>()
        .map_err(|e| Error::codec("KTX2", format!("zstd compression failed: {e}")))?;
    let mut clamped = Clamped::default();
    let frames = all
        .into_iter()
        .map(|(z, c)| {
            clamped.add(c);
            z
        })
        .collect();
    Ok((frames, clamped))
}

/// The key/value data a written file carries: its orientation, its
/// writer, and the texture's own tags.
fn file_key_values(tex: &Texture, bc6h_error: Option<&str>) -> Vec<u8> {
    let writer = writer_name();
    let mut entries = vec![("KTXorientation", "rd"), ("KTXwriter", writer.as_str())];
    entries.extend(tex.tags().iter().map(|(k, v)| (k.as_str(), v.as_str())));
    if let Some(e) = bc6h_error {
        entries.push((BC6H_ERROR, e));
    }
    key_values(&entries)
}

/// The key/value entry that holds a BC6H file's error per level, as
/// written: the decoded texels against the texels they were encoded from.
pub(crate) const BC6H_ERROR: &str = "envmap.bc6h-error";

/// Each level's BC6H error, one `level p: ...` line each, from the packed
/// levels `raw` decoded by `bcdec_rs`, against `tex`.
#[cfg(feature = "bc6h")]
fn bc6h_errors(tex: &Texture, raw: &[Vec<u8>]) -> String {
    let decoded: Vec<Vec<RgbImage>> = tex
        .levels()
        .iter()
        .zip(raw)
        .map(|(faces, bytes)| {
            let mut at = 0;
            faces
                .iter()
                .map(|f| {
                    let n = TexelFormat::Bc6h.image_bytes(f.width, f.height);
                    let b = bytes.get(at..at + n).unwrap_or_default();
                    at += n;
                    RgbImage {
                        width: f.width,
                        height: f.height,
                        pixels: TexelFormat::Bc6h.unpack_image(b, (f.width, f.height)),
                    }
                })
                .collect()
        })
        .collect();
    tex.levels()
        .iter()
        .zip(&decoded)
        .enumerate()
        .map(|(p, (r, d))| {
            format!(
                "level {p}: {}",
                crate::image::lossy::measure_level(d, r, TexelFormat::Bc6h.max_value()).describe()
            )
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// Where each section of a written file starts, and the file's length.
struct Layout {
    dfd_offset: usize,
    dfd_len: usize,
    kvd_offset: usize,
    kvd_len: usize,
    /// Each level's offset, largest level first.
    levels: Vec<usize>,
    len: usize,
}

impl Layout {
    /// The sections in file order: header and level index, DFD, key/value
    /// data, then the levels smallest first, each at the next multiple of
    /// `align`.
    fn new(n: usize, dfd_len: usize, kvd_len: usize, align: usize, stored_lens: &[usize]) -> Self {
        let dfd_offset = (HEADER_LEN + LEVEL_ENTRY * n).next_multiple_of(4);
        let kvd_offset = dfd_offset + dfd_len;
        let mut levels = vec![0usize; n];
        let mut at = kvd_offset + kvd_len;
        for p in (0..n).rev() {
            at = at.next_multiple_of(align);
            levels[p] = at;
            at += stored_lens[p];
        }
        Self {
            dfd_offset,
            dfd_len,
            kvd_offset,
            kvd_len,
            levels,
            len: at,
        }
    }
}

/// The identifier, the header words, the section index and the level
/// index of a file laid out as `layout`.
fn head_bytes(
    tex: &Texture,
    format: TexelFormat,
    zstd: bool,
    layout: &Layout,
    stored_lens: &[usize],
    raw_lens: &[usize],
) -> Vec<u8> {
    let (w, h) = tex.size();
    let faces = tex.kind().faces() as u32;
    let n = layout.levels.len();
    let mut head = Vec::with_capacity(layout.dfd_offset);
    head.extend_from_slice(&IDENTIFIER);
    let scheme = u32::from(zstd) * 2;
    for v in [
        format.vk_format(),
        format.type_size(),
        w,
        h,
        0,
        0,
        faces,
        n as u32,
        scheme,
    ] {
        head.extend_from_slice(&v.to_le_bytes());
    }
    for v in [
        layout.dfd_offset,
        layout.dfd_len,
        layout.kvd_offset,
        layout.kvd_len,
    ] {
        head.extend_from_slice(&(v as u32).to_le_bytes());
    }
    head.extend_from_slice(&[0; 16]); // sgdByteOffset, sgdByteLength
    for p in 0..n {
        for v in [layout.levels[p], stored_lens[p], raw_lens[p]] {
            head.extend_from_slice(&(v as u64).to_le_bytes());
        }
    }
    head
}

/// One level as one zstd frame at `level`; levels above 1 MiB are split
/// among the worker threads (zstd's own multithreading: still one frame,
/// jobs of at least 1 MiB).
#[cfg(feature = "zstd")]
fn compress(raw: &[u8], level: i32) -> std::io::Result<Vec<u8>> {
    use zstd::zstd_safe::CParameter;
    let workers = crate::par::current_num_threads().min(raw.len() >> 20) as u32;
    let mut c = zstd::bulk::Compressor::new(level)?;
    if workers > 1 {
        c.set_parameter(CParameter::NbWorkers(workers))?;
        c.set_parameter(CParameter::JobSize(1 << 20))?;
    }
    c.compress(raw)
}

/// Without the `zstd` feature: an error saying so.
#[cfg(not(feature = "zstd"))]
fn compress(_raw: &[u8], _level: i32) -> std::io::Result<Vec<u8>> {
    Err(std::io::Error::other(NO_ZSTD))
}

/// What a build without the `zstd` feature says of zstd supercompression.
#[cfg(not(feature = "zstd"))]
const NO_ZSTD: &str =
    "zstd supercompression needs envmap-render's `zstd` feature (on by default; this build has it off)";

#[cfg(test)]
mod tests {
    use super::*;

    /// Without the `bc6h` feature BC6H is refused before any work, with
    /// the reason, and a BC6H file is not read.
    #[cfg(not(feature = "bc6h"))]
    #[test]
    fn bc6h_without_its_feature_is_refused_with_the_reason() {
        let tex = Texture::new(
            crate::image::texture::TextureKind::Flat,
            vec![vec![RgbImage {
                width: 4,
                height: 4,
                pixels: vec![[1.0; 3]; 16],
            }]],
        )
        .unwrap();
        let mut o = TextureOptions::default();
        o.format = TexelFormat::Bc6h;
        let e = encode(&tex, o).unwrap_err().to_string();
        assert!(e.contains("`bc6h` feature"), "{e}");
        assert!(!TexelFormat::Bc6h.is_writable());
        assert_eq!(TexelFormat::from_vk_format(143), None);
        assert!(read::unsupported_format(143).contains("`bc6h` feature"));
    }

    #[test]
    fn dfd_words_match_the_spec_table() {
        let words = |f| {
            dfd(f)
                .chunks_exact(4)
                .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
                .collect::<Vec<_>>()
        };
        let w = words(TexelFormat::Rgba16f);
        assert_eq!(w[0], 92);
        assert_eq!(w[2], 0x0058_0002);
        assert_eq!(w[3], 0x0001_0101);
        assert_eq!(w[5], 8);
        assert_eq!(
            [w[7], w[11], w[15], w[19]],
            [0xC00F_0000, 0xC10F_0010, 0xC20F_0020, 0xCF0F_0030]
        );
        assert_eq!([w[9], w[10]], [MINUS_ONE, ONE]);
        let w = words(TexelFormat::Rgba32f);
        assert_eq!(
            [w[7], w[11], w[15], w[19]],
            [0xC01F_0000, 0xC11F_0020, 0xC21F_0040, 0xCF1F_0060]
        );
        let w = words(TexelFormat::B10g11r11);
        assert_eq!((w[0], w[2]), (76, 0x0048_0002));
        assert_eq!(
            [w[7], w[11], w[15]],
            [0x800A_0000, 0x810A_000B, 0x8209_0016]
        );
        assert_eq!([w[9], w[10]], [0, ONE]);
        let w = words(TexelFormat::E5b9g9r9);
        assert_eq!((w[0], w[2]), (124, 0x0078_0002));
        assert_eq!(
            [w[7], w[11], w[15], w[19], w[23], w[27]],
            [
                0x0008_0000,
                0x2004_001B,
                0x0108_0009,
                0x2104_001B,
                0x0208_0012,
                0x2204_001B
            ]
        );
        assert_eq!([w[9], w[10], w[13], w[14]], [0, 8448, 15, 31]);
    }

    #[test]
    fn alignment_is_lcm_of_texel_and_4() {
        assert_eq!(level_alignment(TexelFormat::Rgba16f), 8);
        assert_eq!(level_alignment(TexelFormat::Rgba32f), 16);
        assert_eq!(level_alignment(TexelFormat::B10g11r11), 4);
        assert_eq!(level_alignment(TexelFormat::E5b9g9r9), 4);
        assert_eq!(level_alignment(TexelFormat::Rgb16f), 12);
    }

    #[test]
    fn key_values_are_sorted_and_padded() {
        let kvd = key_values(&[("KTXwriter", "envmap 0.1.0"), ("KTXorientation", "rd")]);
        // 4 + 18 ("KTXorientation\0rd\0") → 24; 4 + 23 → 28 (27 padded).
        assert_eq!(kvd.len(), 24 + 28);
        assert_eq!(&kvd[4..18], b"KTXorientation");
        assert_eq!(read::u32_at(&kvd, 0), 18);
        assert_eq!(read::u32_at(&kvd, 24), 23);
        assert_eq!(kvd[51], 0);
    }
}
