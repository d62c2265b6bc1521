//! KTX2 and DDS texture files, checked against outside readers and the
//! facts of `/work/shared/reference/ktx2-dds.md` (§1.1–1.8, §5):
//!
//! * KTX2 as written by `ktx2::encode`, parsed back with the independent
//!   `ktx2` crate: header, level index and alignment, DFD (byte for byte
//!   against the crate's own generator), key/value data, level contents
//!   (zstd decompressed with the `zstd` crate), then decoded by envmap;
//! * the worked example of §1.4 (a 256² cube with 9 levels);
//! * DDS as written by `dds::encode`, read back with `ddsfile`: DX10 header,
//!   cube flags, face-major data, then decoded by envmap;
//! * whole files through `save` and `load_detailed`;
//! * bad files: every prefix, broken offsets, foreign DFDs, unsupported
//!   features, size limits, corrupt zstd data: errors naming the file,
//!   never panics.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::Path;

use envmap_core::{AnyMapping, Atlas, Frame};
use envmap_render::image::load_detailed;
use envmap_render::image::texture::{self, full_chain, level_size};
use envmap_render::image::FileFormat;
use envmap_render::image::{
    texture::{Texture, TextureKind, TextureOptions},
    RgbImage, TexelFormat, DEFAULT_MAX_TEXELS,
};
use envmap_render::{
    image::{save, EnvImage, LoadOptions, Representation, SaveOptions},
    Error,
};

// ---------------------------------------------------------------------------
// Test textures

/// A deterministic, well-mixed 64-bit hash (splitmix64).
fn mix(mut x: u64) -> u64 {
    x = x.wrapping_add(0x9e37_79b9_7f4a_7c15);
    x = (x ^ (x >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    x = (x ^ (x >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    x ^ (x >> 31)
}

/// A positive value in [2⁻⁸, 2⁸) with all 23 mantissa bits drawn from the
/// hash of (face, level, texel, channel): different everywhere, within
/// every writable format's range, and not exactly representable in the
/// small formats.
fn value(face: usize, level: usize, texel: usize, channel: usize) -> f32 {
    let key =
        ((face as u64) << 56) | ((level as u64) << 48) | ((texel as u64) << 2) | channel as u64;
    let h = mix(key);
    let exponent = (h >> 60) as u32 + 119; // 2^-8 .. 2^7
    let mantissa = (h as u32) & 0x7f_ffff;
    f32::from_bits((exponent << 23) | mantissa)
}

/// A `kind` texture of level-0 size `size` with `levels` levels of
/// [`value`]s.
fn texture(kind: TextureKind, size: (u32, u32), levels: usize) -> Texture {
    let levels = (0..levels)
        .map(|p| {
            let (w, h) = level_size(size.0, size.1, p);
            (0..kind.faces())
                .map(|f| RgbImage {
                    width: w,
                    height: h,
                    pixels: (0..(w * h) as usize)
                        .map(|i| [0, 1, 2].map(|c| value(f, p, i, c)))
                        .collect(),
                })
                .collect()
        })
        .collect();
    Texture::new(kind, levels).expect("a valid test texture")
}

/// A `kind` texture of `size` with `levels` levels, all texels zero.
fn zero_texture(kind: TextureKind, size: (u32, u32), levels: usize) -> Texture {
    let levels = (0..levels)
        .map(|p| {
            let (w, h) = level_size(size.0, size.1, p);
            vec![
                RgbImage {
                    width: w,
                    height: h,
                    pixels: vec![[0.0; 3]; (w * h) as usize],
                };
                kind.faces()
            ]
        })
        .collect();
    Texture::new(kind, levels).expect("a valid test texture")
}

/// Level-0 size of the test textures: 16×8 for 2D, 16² faces for a cube.
fn test_size(kind: TextureKind) -> (u32, u32) {
    match kind {
        TextureKind::Flat => (16, 8),
        TextureKind::Cube => (16, 16),
    }
}

/// The level counts tested: one level, the full chain, a chain stopping
/// early after 3 levels.
fn level_counts(size: (u32, u32)) -> [usize; 3] {
    [1, full_chain(size.0, size.1), 3]
}

/// `pixels` packed in `format` (nothing may need clamping).
fn packed(format: TexelFormat, pixels: &[[f32; 3]]) -> Vec<u8> {
    let mut out = Vec::new();
    let clamped = format.pack(pixels, &mut out);
    assert!(
        clamped.is_empty(),
        "test values clamped in {format:?}: {clamped:?}"
    );
    out
}

/// What a `format` file holds of `pixels`: exactly them for RGBA32F, their
/// packer round trip (`unpack(pack(x))`) otherwise.
fn stored(format: TexelFormat, pixels: &[[f32; 3]]) -> Vec<[f32; 3]> {
    let q = format.unpack(&packed(format, pixels));
    if format == TexelFormat::Rgba32f {
        assert_eq!(q, pixels, "RGBA32F packing is not the identity");
    }
    q
}

/// Level `p`'s bytes as the spec lays them out: faces in order, each one
/// packed row by row.
fn level_bytes_of(tex: &Texture, p: usize, format: TexelFormat) -> Vec<u8> {
    tex.levels()[p]
        .iter()
        .flat_map(|face| packed(format, &face.pixels))
        .collect()
}

/// Checks a decoded texture against the original, level by level and face
/// by face, within the format's precision (see [`stored`]).
fn assert_same_texels(got: &Texture, original: &Texture, format: TexelFormat, what: &str) {
    assert_eq!(got.kind(), original.kind(), "{what}: kind");
    assert_eq!(got.size(), original.size(), "{what}: size");
    assert_eq!(got.level_count(), original.level_count(), "{what}: levels");
    for (p, (gl, ol)) in got.levels().iter().zip(original.levels()).enumerate() {
        assert_eq!(gl.len(), ol.len(), "{what}: level {p} faces");
        for (f, (g, o)) in gl.iter().zip(ol).enumerate() {
            assert_eq!(
                (g.width, g.height),
                (o.width, o.height),
                "{what}: level {p} face {f} size"
            );
            let want = stored(format, &o.pixels);
            if let Some(i) = (0..want.len()).find(|&i| g.pixels[i] != want[i]) {
                panic!(
                    "{what}: level {p} face {f} texel {i}: decoded {:?}, expected {:?} (original {:?})",
                    g.pixels[i], want[i], o.pixels[i]
                );
            }
            assert_eq!(
                g.pixels.len(),
                want.len(),
                "{what}: level {p} face {f} texels"
            );
        }
    }
    // The comparison above is not vacuous: the test values are not all
    // representable in the lossy formats.
    if format != TexelFormat::Rgba32f {
        let lossy = original
            .levels()
            .iter()
            .flatten()
            .any(|o| stored(format, &o.pixels) != o.pixels);
        assert!(lossy, "{what}: every test value is exact in {format:?}");
    }
}

fn u32_at(b: &[u8], at: usize) -> u32 {
    u32::from_le_bytes(b[at..at + 4].try_into().unwrap())
}

fn put_u32(b: &mut [u8], at: usize, v: u32) {
    b[at..at + 4].copy_from_slice(&v.to_le_bytes());
}

fn put_u64(b: &mut [u8], at: usize, v: u64) {
    b[at..at + 8].copy_from_slice(&v.to_le_bytes());
}

// ---------------------------------------------------------------------------
// KTX2: what the reference says each format needs

/// typeSize by the spec (§1.2): 2 for RGBA16F, 4 for RGBA32F and the
/// `_PACK32` formats, whatever the supercompression.
fn spec_type_size(format: TexelFormat) -> u32 {
    match format {
        TexelFormat::Rgba16f => 2,
        _ => 4,
    }
}

/// Level alignment without supercompression (§1.4): lcm(texel bytes, 4).
fn spec_alignment(format: TexelFormat) -> usize {
    match format {
        TexelFormat::Rgba16f => 8,
        TexelFormat::Rgba32f => 16,
        _ => 4,
    }
}

/// Texel bytes (§1.2).
fn spec_texel_bytes(format: TexelFormat) -> usize {
    match format {
        TexelFormat::Rgba16f => 8,
        TexelFormat::Rgba32f => 16,
        _ => 4,
    }
}

/// The `ktx2` crate's format of ours.
fn crate_format(format: TexelFormat) -> ::ktx2::Format {
    match format {
        TexelFormat::Rgba16f => ::ktx2::Format::R16G16B16A16_SFLOAT,
        TexelFormat::Rgba32f => ::ktx2::Format::R32G32B32A32_SFLOAT,
        TexelFormat::B10g11r11 => ::ktx2::Format::B10G11R11_UFLOAT_PACK32,
        TexelFormat::E5b9g9r9 => ::ktx2::Format::E5B9G9R9_UFLOAT_PACK32,
        TexelFormat::Bc6h => ::ktx2::Format::BC6H_UFLOAT_BLOCK,
        f => panic!("{f:?} is not written"),
    }
}

/// The DFD section as a file holds it (dfdTotalSize, then the one basic
/// block), generated by the `ktx2` crate; and the crate's typeSize.
fn crate_dfd(format: TexelFormat) -> (Vec<u8>, u32) {
    let (basic, type_size) = ::ktx2::dfd::Basic::from_format(crate_format(format))
        .unwrap_or_else(|e| panic!("ktx2 crate cannot describe {format:?}: {e:?}"));
    let block = ::ktx2::dfd::Block::Basic(basic).to_vec();
    let mut out = ((block.len() + 4) as u32).to_le_bytes().to_vec();
    out.extend_from_slice(&block);
    (out, type_size)
}

/// The DFD words of the reference's table (§1.5), written out by hand.
fn table_dfd_words(format: TexelFormat) -> Vec<u32> {
    const ONE: u32 = 0x3F80_0000;
    const MINUS_ONE: u32 = 0xBF80_0000;
    let (total, w2, bytes, samples): (u32, u32, u32, Vec<[u32; 4]>) = match format {
        TexelFormat::Rgba16f => (
            92,
            0x0058_0002,
            8,
            [0xC00F_0000, 0xC10F_0010, 0xC20F_0020, 0xCF0F_0030]
                .map(|s| [s, 0, MINUS_ONE, ONE])
                .to_vec(),
        ),
        TexelFormat::Rgba32f => (
            92,
            0x0058_0002,
            16,
            [0xC01F_0000, 0xC11F_0020, 0xC21F_0040, 0xCF1F_0060]
                .map(|s| [s, 0, MINUS_ONE, ONE])
                .to_vec(),
        ),
        TexelFormat::B10g11r11 => (
            76,
            0x0048_0002,
            4,
            [0x800A_0000, 0x810A_000B, 0x8209_0016]
                .map(|s| [s, 0, 0, ONE])
                .to_vec(),
        ),
        TexelFormat::E5b9g9r9 => (
            124,
            0x0078_0002,
            4,
            vec![
                [0x0008_0000, 0, 0, 8448],
                [0x2004_001B, 0, 15, 31],
                [0x0108_0009, 0, 0, 8448],
                [0x2104_001B, 0, 15, 31],
                [0x0208_0012, 0, 0, 8448],
                [0x2204_001B, 0, 15, 31],
            ],
        ),
        // KDFS 1.4 §5.6 and its BC6H example: colour model BC6H (133),
        // texel block 4×4×1 (stored as 3, 3, 0, 0), one 128-bit unsigned
        // float sample.
        TexelFormat::Bc6h => (44, 0x0028_0002, 16, vec![[0x807F_0000, 0, 0, ONE]]),
        f => panic!("{f:?} is not written"),
    };
    let (model, dims) = if format == TexelFormat::Bc6h {
        (0x0001_0185, 0x0303)
    } else {
        (0x0001_0101, 0)
    };
    let mut words = vec![total, 0, w2, model, dims, bytes, 0];
    words.extend(samples.into_iter().flatten());
    words
}

fn words_of(bytes: &[u8]) -> Vec<u32> {
    bytes
        .chunks_exact(4)
        .map(|c| u32::from_le_bytes(c.try_into().unwrap()))
        .collect()
}

/// The key/value entries of a KVD section, checking the layout as it goes:
/// each entry's length, key NUL value NUL, zero padding to 4 bytes, the sum
/// rule Σ ceil4(len) + 4n = kvdByteLength.
fn parse_kvd(kvd: &[u8]) -> Vec<(String, String)> {
    let mut out = Vec::new();
    let mut at = 0;
    let mut sum = 0;
    while at < kvd.len() {
        let len = u32_at(kvd, at) as usize;
        let body = &kvd[at + 4..at + 4 + len];
        let nul = body.iter().position(|&c| c == 0).expect("key NUL");
        assert_eq!(body[len - 1], 0, "value not NUL-terminated: {body:?}");
        let key = std::str::from_utf8(&body[..nul]).unwrap().to_owned();
        let value = std::str::from_utf8(&body[nul + 1..len - 1])
            .unwrap()
            .to_owned();
        assert!(!value.contains('\0'), "NUL inside value {value:?}");
        let end = (at + 4 + len).next_multiple_of(4);
        assert!(
            kvd[at + 4 + len..end].iter().all(|&b| b == 0),
            "entry {key:?}: padding not zero"
        );
        sum += len.next_multiple_of(4) + 4;
        out.push((key, value));
        at = end;
    }
    assert_eq!(at, kvd.len(), "KVD does not end at an entry's end");
    assert_eq!(sum, kvd.len(), "kvdByteLength breaks the sum rule");
    out
}

fn writer() -> String {
    format!("envmap {}", env!("CARGO_PKG_VERSION"))
}

// ---------------------------------------------------------------------------
// KTX2: one file, checked end to end

/// Writes one KTX2 file and checks all of §1.1–1.8 on it, then decodes it.
fn check_ktx2(format: TexelFormat, kind: TextureKind, levels: usize, zstd: bool) {
    let what = format!("{format:?} {kind:?} {levels} levels zstd={zstd}");
    let size = test_size(kind);
    let (w, h) = size;
    let faces = kind.faces();
    let tex = texture(kind, size, levels);
    let opts = {
        let mut o = TextureOptions::default();
        o.format = format;
        o.zstd = zstd.then_some(3);
        o
    };
    let (bytes, clamped) =
        texture::encode(&tex, Path::new("t.ktx2"), opts).unwrap_or_else(|e| panic!("{what}: {e}"));
    assert!(clamped.is_empty(), "{what}: clamped {clamped:?}");

    // The identifier and header, through the ktx2 crate.
    assert_eq!(&bytes[..12], &::ktx2::MAGIC, "{what}: identifier");
    let reader =
        ::ktx2::Reader::new(&bytes[..]).unwrap_or_else(|e| panic!("{what}: ktx2 crate: {e:?}"));
    let hd = reader.header();
    assert_eq!(
        hd.format.map(|f| f.value()),
        Some(format.vk_format()),
        "{what}: vkFormat"
    );
    assert_eq!(hd.type_size, spec_type_size(format), "{what}: typeSize");
    assert_eq!(
        (hd.pixel_width, hd.pixel_height),
        (w, h),
        "{what}: pixel size"
    );
    assert_eq!(hd.pixel_depth, 0, "{what}: pixelDepth");
    assert_eq!(hd.layer_count, 0, "{what}: layerCount");
    assert_eq!(hd.face_count as usize, faces, "{what}: faceCount");
    assert_eq!(hd.level_count as usize, levels, "{what}: levelCount");
    let scheme = if zstd {
        Some(::ktx2::SupercompressionScheme::Zstandard)
    } else {
        None
    };
    assert_eq!(
        hd.supercompression_scheme, scheme,
        "{what}: supercompressionScheme"
    );
    assert_eq!(
        u32_at(&bytes, 44),
        if zstd { 2 } else { 0 },
        "{what}: scheme word"
    );
    assert_eq!(
        (hd.index.sgd_byte_offset, hd.index.sgd_byte_length),
        (0, 0),
        "{what}: sgd"
    );

    // The DFD: right after the level index, 4-aligned; byte for byte the
    // ktx2 crate's own.
    let index_end = 80 + 24 * levels;
    let dfd_offset = index_end.next_multiple_of(4);
    assert_eq!(
        hd.index.dfd_byte_offset as usize, dfd_offset,
        "{what}: dfdByteOffset"
    );
    assert!(
        bytes[index_end..dfd_offset].iter().all(|&b| b == 0),
        "{what}: padding"
    );
    let (want_dfd, crate_type_size) = crate_dfd(format);
    assert_eq!(
        crate_type_size,
        spec_type_size(format),
        "{what}: the crate's typeSize"
    );
    let dfd_len = hd.index.dfd_byte_length as usize;
    assert_eq!(dfd_len, want_dfd.len(), "{what}: dfdByteLength");
    assert_eq!(
        &bytes[dfd_offset..dfd_offset + dfd_len],
        &want_dfd[..],
        "{what}: DFD bytes"
    );
    assert_eq!(reader.dfd_blocks().len(), 1, "{what}: DFD blocks");
    assert_eq!(
        reader.basic_dfd(),
        Some(
            &::ktx2::dfd::Basic::from_format(crate_format(format))
                .unwrap()
                .0
        ),
        "{what}: DFD as the crate parses it"
    );

    // The key/value data: directly after the DFD; sorted; exactly the two
    // entries.
    let kvd_offset = dfd_offset + dfd_len;
    assert_eq!(
        hd.index.kvd_byte_offset as usize, kvd_offset,
        "{what}: kvdByteOffset"
    );
    let kvd_len = hd.index.kvd_byte_length as usize;
    let entries = parse_kvd(&bytes[kvd_offset..kvd_offset + kvd_len]);
    assert!(
        entries.windows(2).all(|e| e[0].0 < e[1].0),
        "{what}: KVD not sorted"
    );
    assert_eq!(
        entries,
        vec![
            ("KTXorientation".to_owned(), "rd".to_owned()),
            ("KTXwriter".to_owned(), writer()),
        ],
        "{what}: KVD entries"
    );
    assert!(entries[1].1.starts_with("envmap "), "{what}: KTXwriter");
    let crate_kv: Vec<(String, Vec<u8>)> = reader
        .key_value_data()
        .map(|(k, v)| (k.to_owned(), v.to_vec()))
        .collect();
    assert_eq!(
        crate_kv,
        vec![
            ("KTXorientation".to_owned(), b"rd\0".to_vec()),
            (
                "KTXwriter".to_owned(),
                format!("{}\0", writer()).into_bytes()
            ),
        ],
        "{what}: KVD through the ktx2 crate"
    );
    assert_eq!(
        reader.writer(),
        Some(format!("{}\0", writer()).as_str()),
        "{what}: writer()"
    );

    // The level index: largest level first, data smallest first, each
    // level at align(previous end), the first one at align(end of KVD).
    let align = if zstd { 1 } else { spec_alignment(format) };
    let index: Vec<::ktx2::LevelIndex> = (0..levels)
        .map(|p| {
            ::ktx2::LevelIndex::from_bytes(
                bytes[80 + 24 * p..80 + 24 * (p + 1)].try_into().unwrap(),
            )
        })
        .collect();
    let raw_len = |p: usize| {
        let (lw, lh) = level_size(w, h, p);
        (faces * lw as usize * lh as usize * spec_texel_bytes(format)) as u64
    };
    for (p, e) in index.iter().enumerate() {
        assert_eq!(
            e.uncompressed_byte_length,
            raw_len(p),
            "{what}: level {p} uncompressedByteLength"
        );
        assert_eq!(
            e.uncompressed_byte_length % faces as u64,
            0,
            "{what}: level {p} faces"
        );
        if !zstd {
            assert_eq!(e.byte_length, raw_len(p), "{what}: level {p} byteLength");
        }
        if p > 0 {
            assert!(
                index[p - 1].uncompressed_byte_length > e.uncompressed_byte_length,
                "{what}: level {p} is not smaller than level {}",
                p - 1
            );
            assert!(
                index[p - 1].byte_offset > e.byte_offset,
                "{what}: level {p} is not stored before level {}",
                p - 1
            );
        }
    }
    let mut at = kvd_offset + kvd_len;
    for p in (0..levels).rev() {
        let want = at.next_multiple_of(align);
        assert_eq!(
            index[p].byte_offset as usize, want,
            "{what}: level {p} byteOffset"
        );
        assert!(
            bytes[at..want].iter().all(|&b| b == 0),
            "{what}: padding before level {p}"
        );
        at = want + index[p].byte_length as usize;
    }
    assert_eq!(
        bytes.len(),
        at,
        "{what}: the file does not end at the end of level 0"
    );
    // The crate's level view is the same.
    let crate_levels: Vec<_> = reader.levels().collect();
    assert_eq!(crate_levels.len(), levels, "{what}: crate levels");
    for (p, l) in crate_levels.iter().enumerate() {
        let off = l.data.as_ptr() as usize - bytes.as_ptr() as usize;
        assert_eq!(
            (off as u64, l.data.len() as u64, l.uncompressed_byte_length),
            (
                index[p].byte_offset,
                index[p].byte_length,
                index[p].uncompressed_byte_length
            ),
            "{what}: crate level {p}"
        );
    }

    // Level contents: the faces in order, packed; under zstd each level
    // decompresses to the bytes of the uncompressed file's level.
    let plain = if zstd {
        Some(
            texture::encode(&tex, Path::new("t.ktx2"), {
                let mut o = TextureOptions::default();
                o.format = format;
                o.zstd = None;
                o
            })
            .unwrap()
            .0,
        )
    } else {
        None
    };
    for (p, e) in index.iter().enumerate() {
        let data = &bytes[e.byte_offset as usize..(e.byte_offset + e.byte_length) as usize];
        let raw = if zstd {
            assert_eq!(
                &data[..4],
                &[0x28, 0xB5, 0x2F, 0xFD],
                "{what}: level {p} zstd magic"
            );
            let raw =
                zstd::stream::decode_all(data).unwrap_or_else(|e| panic!("{what}: level {p}: {e}"));
            let plain = plain.as_ref().unwrap();
            let pe = ::ktx2::LevelIndex::from_bytes(
                plain[80 + 24 * p..80 + 24 * (p + 1)].try_into().unwrap(),
            );
            assert_eq!(
                raw,
                plain[pe.byte_offset as usize..(pe.byte_offset + pe.byte_length) as usize],
                "{what}: level {p} decompressed vs the uncompressed file"
            );
            raw
        } else {
            data.to_vec()
        };
        assert_eq!(
            raw.len() as u64,
            e.uncompressed_byte_length,
            "{what}: level {p} length"
        );
        assert!(
            raw == level_bytes_of(&tex, p, format),
            "{what}: level {p} bytes are not the faces packed in order"
        );
    }

    // envmap's own reader.
    let file = texture::decode(Path::new("t.ktx2"), &bytes, DEFAULT_MAX_TEXELS)
        .unwrap_or_else(|e| panic!("{what}: decode: {e}"));
    let info = &file.info;
    assert_eq!(info.container, "KTX2", "{what}");
    assert_eq!(info.format, format, "{what}");
    assert_eq!(info.kind, kind, "{what}");
    assert_eq!(info.size, size, "{what}");
    assert_eq!(info.levels, levels, "{what}");
    assert_eq!(info.supercompression, zstd.then_some("zstd"), "{what}");
    assert_eq!(info.orientation.as_deref(), Some("rd"), "{what}");
    assert_eq!(info.writer, Some(writer()), "{what}");
    assert_eq!(
        info.level_bytes,
        index.iter().map(|e| e.byte_length).collect::<Vec<_>>(),
        "{what}: info.level_bytes"
    );
    assert_same_texels(&file.texture, &tex, format, &what);
}

/// Every kind × chain × supercompression of one format.
fn check_ktx2_format(format: TexelFormat) {
    for kind in [TextureKind::Flat, TextureKind::Cube] {
        for levels in level_counts(test_size(kind)) {
            for zstd in [false, true] {
                check_ktx2(format, kind, levels, zstd);
            }
        }
    }
}

/// RGBA16F (97): 2D and cube, 1/full/3 levels, with and without zstd:
/// header, level index, DFD, KVD, level bytes and the round trip.
#[test]
fn ktx2_rgba16f_files_match_the_spec_and_round_trip() {
    check_ktx2_format(TexelFormat::Rgba16f);
}

/// RGBA32F (109): as above, the round trip exact.
#[test]
fn ktx2_rgba32f_files_match_the_spec_and_round_trip() {
    check_ktx2_format(TexelFormat::Rgba32f);
}

/// B10G11R11 (122): as above.
#[test]
fn ktx2_b10g11r11_files_match_the_spec_and_round_trip() {
    check_ktx2_format(TexelFormat::B10g11r11);
}

/// E5B9G9R9 (123): as above.
#[test]
fn ktx2_e5b9g9r9_files_match_the_spec_and_round_trip() {
    check_ktx2_format(TexelFormat::E5b9g9r9);
}

/// The `ktx2` crate's generated DFD for each writable format equals the
/// table of the reference (§1.5) word for word, and so does envmap's
/// `ktx2::dfd`: the two independent sources agree.
#[test]
fn ktx2_crate_dfd_and_envmap_dfd_equal_the_reference_table() {
    for format in TexelFormat::WRITABLE {
        let table = table_dfd_words(format);
        let (crate_bytes, _) = crate_dfd(format);
        assert_eq!(
            words_of(&crate_bytes),
            table,
            "{format:?}: ktx2 crate vs table"
        );
        assert_eq!(
            words_of(&envmap_dfd(format)),
            table,
            "{format:?}: envmap vs table"
        );
    }
}

// ---------------------------------------------------------------------------
// The worked example of §1.4

/// The offsets of a 256² cube with 9 levels (§1.4): RGBA16F DFD at 296
/// (92 bytes), KVD at 388 (52 bytes), first (1×1) level at 440 (48 bytes),
/// level 0 at 1 049 000 (3 145 728 bytes), file 4 194 728 bytes; RGBA32F
/// first level at 448; RGB9E5 DFD 124 bytes, first level at 472, file
/// 2 097 616 bytes.
#[test]
fn ktx2_worked_example_256_cube_with_9_levels() {
    let tex = zero_texture(TextureKind::Cube, (256, 256), 9);
    let level = |b: &[u8], p: usize| {
        let e =
            ::ktx2::LevelIndex::from_bytes(b[80 + 24 * p..80 + 24 * (p + 1)].try_into().unwrap());
        (e.byte_offset, e.byte_length, e.uncompressed_byte_length)
    };
    assert_eq!(
        writer(),
        "envmap 0.1.0",
        "the example assumes this KTXwriter"
    );

    let (b, _) = texture::encode(&tex, Path::new("t.ktx2"), {
        let mut o = TextureOptions::default();
        o.format = TexelFormat::Rgba16f;
        o.zstd = None;
        o
    })
    .unwrap();
    assert_eq!([u32_at(&b, 48), u32_at(&b, 52)], [296, 92], "RGBA16F DFD");
    assert_eq!([u32_at(&b, 56), u32_at(&b, 60)], [388, 52], "RGBA16F KVD");
    assert_eq!(level(&b, 8), (440, 48, 48), "RGBA16F 1×1 level");
    assert_eq!(
        level(&b, 0),
        (1_049_000, 3_145_728, 3_145_728),
        "RGBA16F level 0"
    );
    assert_eq!(b.len(), 4_194_728, "RGBA16F file size");
    ::ktx2::Reader::new(&b[..]).expect("ktx2 crate reads it");

    let (b, _) = texture::encode(&tex, Path::new("t.ktx2"), {
        let mut o = TextureOptions::default();
        o.format = TexelFormat::Rgba32f;
        o.zstd = None;
        o
    })
    .unwrap();
    assert_eq!([u32_at(&b, 48), u32_at(&b, 52)], [296, 92], "RGBA32F DFD");
    assert_eq!([u32_at(&b, 56), u32_at(&b, 60)], [388, 52], "RGBA32F KVD");
    assert_eq!(level(&b, 8), (448, 96, 96), "RGBA32F 1×1 level");
    assert!(b[440..448].iter().all(|&x| x == 0), "RGBA32F mipPadding");
    // 448 + 6·16·(4⁹ − 1)/3, every level a multiple of 16 bytes.
    assert_eq!(b.len(), 448 + 96 * 87_381, "RGBA32F file size");

    let (b, _) = texture::encode(&tex, Path::new("t.ktx2"), {
        let mut o = TextureOptions::default();
        o.format = TexelFormat::E5b9g9r9;
        o.zstd = None;
        o
    })
    .unwrap();
    assert_eq!([u32_at(&b, 48), u32_at(&b, 52)], [296, 124], "RGB9E5 DFD");
    assert_eq!([u32_at(&b, 56), u32_at(&b, 60)], [420, 52], "RGB9E5 KVD");
    assert_eq!(level(&b, 8), (472, 24, 24), "RGB9E5 1×1 level");
    assert_eq!(b.len(), 2_097_616, "RGB9E5 file size");
}

// ---------------------------------------------------------------------------
// DDS

/// The DXGI numbers of the reference (§5).
fn spec_dxgi(format: TexelFormat) -> u32 {
    match format {
        TexelFormat::Rgba16f => 10,
        TexelFormat::Rgba32f => 2,
        TexelFormat::B10g11r11 => 26,
        TexelFormat::E5b9g9r9 => 67,
        f => panic!("{f:?} is not written"),
    }
}

/// Writes one DDS file, reads it back with `ddsfile` (DX10 header, array
/// size, cube misc flag, mip count, pitch, face-major data), then decodes
/// it with envmap.
fn check_dds(format: TexelFormat, kind: TextureKind, levels: usize) {
    use ddsfile::{Caps, D3D10ResourceDimension, MiscFlag};
    let what = format!("DDS {format:?} {kind:?} {levels} levels");
    let size = test_size(kind);
    let cube = kind == TextureKind::Cube;
    let faces = kind.faces();
    let tex = texture(kind, size, levels);
    let (bytes, clamped) = texture::encode(&tex, Path::new("t.dds"), {
        let mut o = TextureOptions::default();
        o.format = format;
        o.zstd = None;
        o
    })
    .unwrap_or_else(|e| panic!("{what}: {e}"));
    assert!(clamped.is_empty(), "{what}: clamped {clamped:?}");
    let d = ddsfile::Dds::read(&bytes[..]).unwrap_or_else(|e| panic!("{what}: ddsfile: {e}"));
    assert_eq!((d.header.width, d.header.height), size, "{what}: size");
    let h10 = d.header10.as_ref().expect("a DX10 header");
    assert_eq!(
        h10.dxgi_format as u32,
        spec_dxgi(format),
        "{what}: dxgiFormat"
    );
    assert_eq!(
        u32_at(&bytes, 128),
        spec_dxgi(format),
        "{what}: dxgiFormat word"
    );
    assert_eq!(
        h10.resource_dimension,
        D3D10ResourceDimension::Texture2D,
        "{what}: dimension"
    );
    assert_eq!(h10.array_size, 1, "{what}: arraySize (cubes, not faces)");
    assert_eq!(
        h10.misc_flag.contains(MiscFlag::TEXTURECUBE),
        cube,
        "{what}: TEXTURECUBE"
    );
    assert_eq!(
        d.get_num_mipmap_levels() as usize,
        levels,
        "{what}: mip count"
    );
    assert_eq!(d.get_num_array_layers() as usize, faces, "{what}: layers");
    assert!(
        d.header.caps.contains(Caps::TEXTURE),
        "{what}: caps TEXTURE"
    );
    if levels > 1 {
        assert!(
            // dwFlags, after the magic and dwSize: DDSD_MIPMAPCOUNT.
            u32_at(&bytes, 8) & 0x2_0000 != 0,
            "{what}: MIPMAPCOUNT"
        );
        assert!(
            d.header.caps.contains(Caps::COMPLEX | Caps::MIPMAP),
            "{what}: caps COMPLEX|MIPMAP"
        );
    }
    if cube {
        assert!(
            d.header.caps.contains(Caps::COMPLEX),
            "{what}: caps COMPLEX"
        );
    }
    assert_eq!(
        d.header.pitch,
        Some(size.0 * spec_texel_bytes(format) as u32),
        "{what}: pitch"
    );
    // Face-major: each face with its whole chain, largest level first.
    let mut total = 0;
    for f in 0..faces {
        let want: Vec<u8> = tex
            .levels()
            .iter()
            .flat_map(|l| packed(format, &l[f].pixels))
            .collect();
        total += want.len();
        let got = d
            .get_data(f as u32)
            .unwrap_or_else(|e| panic!("{what}: face {f}: {e}"));
        assert!(
            got == &want[..],
            "{what}: face {f}'s chain is not contiguous in order"
        );
    }
    assert_eq!(d.data.len(), total, "{what}: data length");
    assert_eq!(bytes.len(), 148 + total, "{what}: file length");

    let file = texture::decode(Path::new("t.dds"), &bytes, DEFAULT_MAX_TEXELS)
        .unwrap_or_else(|e| panic!("{what}: decode: {e}"));
    assert_eq!(file.info.container, "DDS", "{what}");
    assert_eq!(file.info.format, format, "{what}");
    assert_eq!(file.info.kind, kind, "{what}");
    assert_eq!(file.info.size, size, "{what}");
    assert_eq!(file.info.levels, levels, "{what}");
    assert_same_texels(&file.texture, &tex, format, &what);
}

/// Every writable format × 2D/cube × 1/full/3 levels as DDS: the header
/// `ddsfile` reads, face-major data, and the round trip through
/// `texture::decode`.
#[test]
fn dds_files_have_the_dx10_header_face_major_data_and_round_trip() {
    // BC6H is lossy: `dds_and_ktx2_bc6h_files_decode_as_bcdec_decodes_their_blocks`.
    for format in TexelFormat::WRITABLE
        .into_iter()
        .filter(|&f| f != TexelFormat::Bc6h)
    {
        for kind in [TextureKind::Flat, TextureKind::Cube] {
            for levels in level_counts(test_size(kind)) {
                check_dds(format, kind, levels);
            }
        }
    }
}

/// A DDS cube has caps2 CUBEMAP with all six face bits (0xFE00), a 2D
/// image none of them (§5).
#[test]
fn dds_cube_caps2_has_cubemap_and_all_six_face_bits() {
    for format in TexelFormat::WRITABLE {
        for kind in [TextureKind::Flat, TextureKind::Cube] {
            for levels in level_counts(test_size(kind)) {
                let tex = texture(kind, test_size(kind), levels);
                let (bytes, _) = texture::encode(&tex, Path::new("t.dds"), {
                    let mut o = TextureOptions::default();
                    o.format = format;
                    o.zstd = None;
                    o
                })
                .unwrap();
                // magic, then the header: caps2 is its 28th word.
                let caps2 = u32_at(&bytes, 4 + 27 * 4);
                let want = if kind == TextureKind::Cube { 0xFE00 } else { 0 };
                assert_eq!(
                    caps2 & 0xFE00,
                    want,
                    "{format:?} {kind:?} {levels} levels: caps2 is {caps2:#x}"
                );
            }
        }
    }
}

// ---------------------------------------------------------------------------
// Whole files

/// A cube in a horizontal cross whose faces hold distinct values.
fn cross_cube(face: u32) -> EnvImage {
    let repr = Representation::new(
        AnyMapping::Cube,
        Atlas::CUBE_HORIZONTAL_CROSS,
        Frame::IDENTITY,
    )
    .unwrap();
    let (w, h) = Atlas::CUBE_HORIZONTAL_CROSS
        .image_size_for_cell_width(face)
        .unwrap();
    let mut img = EnvImage::new(w, h, repr).unwrap();
    for f in 0..6 {
        for j in 0..face {
            for i in 0..face {
                let t = (j * face + i) as usize;
                assert!(img.set_chart_texel(
                    f,
                    i,
                    j,
                    [0, 1, 2].map(|c| value(f as usize, 0, t, c))
                ));
            }
        }
    }
    img
}

/// `save` writes a cube EnvImage (given as a cross) to `x.ktx2` (plain and
/// zstd) and `x.dds` in RGBA32F, and `load_detailed` reads each back as a
/// cube horizontal strip with every face's texels exactly equal; the
/// default format (RGBA16F) reads back as the binary16 round trip.
#[test]
fn save_and_load_detailed_round_trip_a_cube_through_ktx2_and_dds() {
    let dir = tempfile::tempdir().unwrap();
    let img = cross_cube(8);
    let f32_opts = |zstd| {
        let mut o = TextureOptions::default();
        o.format = TexelFormat::Rgba32f;
        o.zstd = zstd;
        o
    };
    let cases: [(&str, TextureOptions, FileFormat); 4] = [
        ("x.ktx2", f32_opts(None), FileFormat::Ktx2),
        ("x_zstd.ktx2", f32_opts(Some(3)), FileFormat::Ktx2),
        ("x.dds", f32_opts(None), FileFormat::Dds),
        ("x16.ktx2", TextureOptions::default(), FileFormat::Ktx2),
    ];
    for (name, texture, container) in cases {
        let path = dir.path().join(name);
        let opts = {
            let mut o = SaveOptions::default();
            o.texture = texture;
            o
        };
        let written = save(&img, &path, &opts).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(written, vec![path.clone()], "{name}");
        let loaded =
            load_detailed(&path, &LoadOptions::default()).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(loaded.source.format, container, "{name}");
        assert_eq!(loaded.files, vec![path.clone()], "{name}");
        let got = &loaded.image;
        assert_eq!(got.mapping(), AnyMapping::Cube, "{name}");
        assert_eq!(*got.atlas(), Atlas::CUBE_HORIZONTAL_STRIP, "{name}");
        assert_eq!((got.width(), got.height()), (48, 8), "{name}");
        for f in 0..6 {
            let want = img.chart_image(f).unwrap();
            let face = got.chart_image(f).unwrap();
            assert_eq!(
                face.pixels,
                stored(texture.format, &want.pixels),
                "{name}: face {f}"
            );
        }
    }
}

// ---------------------------------------------------------------------------
// Bad files

const BAD_KTX2: &str = "bad/sample.ktx2";
const BAD_DDS: &str = "bad/sample.dds";

/// A texture decoder: `ktx2::decode` or `texture::decode`.
type Decode =
    fn(&Path, &[u8], u64) -> envmap_render::Result<envmap_render::image::texture::TextureFile>;

/// Decodes `bytes` with `decode` as the file `name`; it must fail, without
/// panicking, with a message naming the file. Returns the error.
fn decode_error(decode: Decode, name: &str, bytes: &[u8], what: &str) -> Error {
    let r = catch_unwind(AssertUnwindSafe(|| {
        decode(Path::new(name), bytes, DEFAULT_MAX_TEXELS)
    }))
    .unwrap_or_else(|_| panic!("{what}: decode panicked"));
    let e = match r {
        Ok(_) => panic!("{what}: decoded without an error"),
        Err(e) => e,
    };
    let m = e.to_string();
    assert!(
        m.starts_with(name),
        "{what}: message does not name the file: {m}"
    );
    e
}

/// [`decode_error`] for KTX2 bytes, named [`BAD_KTX2`].
fn ktx2_error(bytes: &[u8], what: &str) -> Error {
    decode_error(texture::decode, BAD_KTX2, bytes, what)
}

/// [`decode_error`] for DDS bytes, named [`BAD_DDS`].
fn dds_error(bytes: &[u8], what: &str) -> Error {
    decode_error(texture::decode, BAD_DDS, bytes, what)
}

fn assert_mentions(e: &Error, words: &[&str], what: &str) {
    let m = e.to_string();
    for w in words {
        assert!(m.contains(w), "{what}: {m:?} does not mention {w:?}");
    }
}

/// A small valid KTX2: an 8² RGBA16F cube with 3 levels, with or without
/// zstd.
fn small_ktx2(zstd: bool) -> Vec<u8> {
    let tex = texture(TextureKind::Cube, (8, 8), 3);
    let bytes = texture::encode(&tex, Path::new("t.ktx2"), {
        let mut o = TextureOptions::default();
        o.format = TexelFormat::Rgba16f;
        o.zstd = zstd.then_some(3);
        o
    })
    .unwrap()
    .0;
    texture::decode(Path::new("good.ktx2"), &bytes, DEFAULT_MAX_TEXELS)
        .expect("the unbroken file decodes");
    bytes
}

/// Byte offset of level `p`'s index entry.
fn level_entry(p: usize) -> usize {
    80 + 24 * p
}

/// Every prefix of a valid KTX2 file (lengths 0 … len − 1), plain and zstd,
/// is an error naming the file.
#[test]
fn ktx2_every_prefix_is_an_error_naming_the_file() {
    for zstd in [false, true] {
        let bytes = small_ktx2(zstd);
        for len in 0..bytes.len() {
            ktx2_error(
                &bytes[..len],
                &format!("zstd={zstd}: prefix of {len} bytes"),
            );
        }
    }
}

/// A level offset pointing past the end of the file (or overflowing with
/// its length) is an error naming the level.
#[test]
fn ktx2_level_offset_past_the_end_is_an_error() {
    for zstd in [false, true] {
        let good = small_ktx2(zstd);
        let mut b = good.clone();
        put_u64(&mut b, level_entry(0), good.len() as u64);
        let e = ktx2_error(&b, "level 0 at the end of the file");
        assert_mentions(&e, &["level 0", "past the end"], "offset past the end");
        let mut b = good.clone();
        put_u64(&mut b, level_entry(2), u64::MAX - 3);
        let e = ktx2_error(&b, "level 2 offset near u64::MAX");
        assert_mentions(&e, &["level 2"], "overflowing offset");
        let mut b = good.clone();
        put_u32(&mut b, 48, good.len() as u32 - 10); // dfdByteOffset
        let e = ktx2_error(&b, "DFD past the end");
        assert_mentions(&e, &["Data Format Descriptor"], "DFD past the end");
    }
}

/// The Data Format Descriptor envmap writes for `format`, read from a KTX2
/// file it wrote (bytes 48 and 52 of the header: its offset and length).
fn envmap_dfd(format: TexelFormat) -> Vec<u8> {
    let tex = Texture::new(
        TextureKind::Flat,
        vec![vec![RgbImage {
            width: 1,
            height: 1,
            pixels: vec![[0.5; 3]],
        }]],
    )
    .unwrap();
    let opts = {
        let mut o = TextureOptions::default();
        o.format = format;
        o.zstd = None;
        o
    };
    let (bytes, _) = texture::encode(&tex, Path::new("t.ktx2"), opts).unwrap();
    let off = u32_at(&bytes, 48) as usize;
    let len = u32_at(&bytes, 52) as usize;
    bytes[off..off + len].to_vec()
}

/// An RGBA16F file whose DFD is RGBA32F's (same length, other samples and
/// bytesPlane0), or whose DFD has any one sample byte changed, is refused
/// naming the Data Format Descriptor.
#[test]
fn ktx2_dfd_not_describing_the_vkformat_is_an_error() {
    let good = small_ktx2(false);
    let off = u32_at(&good, 48) as usize;
    let len = u32_at(&good, 52) as usize;
    let other = envmap_dfd(TexelFormat::Rgba32f);
    assert_eq!(other.len(), len);
    let mut b = good.clone();
    b[off..off + len].copy_from_slice(&other);
    let e = ktx2_error(&b, "vkFormat 97 with the DFD of 109");
    assert_mentions(&e, &["Data Format Descriptor", "97"], "DFD of 109");
    // Every byte of the four samples (28 bytes in: total, header, size,
    // model, dims, planes) changed by its lowest bit.
    for i in 28..len {
        let mut b = good.clone();
        b[off + i] ^= 0x01;
        let e = ktx2_error(&b, &format!("DFD byte {i} changed"));
        assert_mentions(&e, &["Data Format Descriptor"], &format!("DFD byte {i}"));
    }
}

/// The L (linear) qualifier of a sample is exempt from the DFD check (the
/// spec's revision note): setting it on every sample still decodes.
#[test]
fn ktx2_dfd_linear_qualifier_is_accepted() {
    let good = small_ktx2(false);
    let off = u32_at(&good, 48) as usize;
    let mut b = good.clone();
    for s in 0..4 {
        b[off + 28 + 16 * s + 3] |= 0x10;
    }
    assert_ne!(b, good);
    texture::decode(Path::new("l.ktx2"), &b, DEFAULT_MAX_TEXELS).expect("L bit accepted");
}

/// levelCount above the full chain (5 for an 8² cube, whose chain is 4) is
/// refused naming levelCount.
#[test]
fn ktx2_level_count_above_the_chain_is_an_error() {
    let mut b = small_ktx2(false);
    put_u32(&mut b, 40, 5);
    let e = ktx2_error(&b, "levelCount 5");
    assert_mentions(&e, &["levelCount 5"], "levelCount above the chain");
}

/// faceCount 6 with pixelWidth ≠ pixelHeight is refused as non-square.
#[test]
fn ktx2_cube_with_non_square_faces_is_an_error() {
    let mut b = small_ktx2(false);
    put_u32(&mut b, 24, 4); // pixelHeight
    let e = ktx2_error(&b, "8×4 cube");
    assert_mentions(&e, &["non-square"], "non-square cube");
}

/// A bare header claiming a 65536×65536 2D texture (2³² texels at level 0)
/// with its full 17 levels, or a cube of that size, fails the size limit
/// (Error::TooLarge, "above the limit") before anything past the header is
/// read: the file is only 80 bytes.
#[test]
fn ktx2_huge_header_fails_the_size_limit_before_reading_levels() {
    for (faces, mult) in [(1u32, 1u64), (6, 6)] {
        let mut b = b"\xABKTX 20\xBB\r\n\x1A\n".to_vec();
        for v in [97, 2, 65536, 65536, 0, 0, faces, 17, 0] {
            b.extend_from_slice(&u32::to_le_bytes(v));
        }
        b.resize(80, 0);
        let start = std::time::Instant::now();
        let e = ktx2_error(&b, &format!("65536² × {faces} faces"));
        assert!(
            start.elapsed().as_secs() < 5,
            "the size check took {:?}",
            start.elapsed()
        );
        assert_mentions(&e, &["above the limit"], "huge header");
        let inner = match &e {
            Error::InFile { source, .. } => &**source,
            other => other,
        };
        // Σ 4^k for k = 0..16, times the faces.
        let all = (4u64.pow(17) - 1) / 3 * mult;
        assert!(
            matches!(inner, Error::TooLarge { width: 65536, height: 65536, texels, limit }
                if *texels == all && *limit == DEFAULT_MAX_TEXELS),
            "not TooLarge with every level's texels: {e:?}"
        );
    }
}

/// Headers of the largest sizes a u32 holds (2³¹ and 2³² − 1 texels a side,
/// as a cube and as 2D, one level and the full chain) fail the size limit
/// too: the texel count saturates instead of overflowing (a fuzzed 2³¹
/// cube once overflowed the sum in debug builds).
#[test]
fn ktx2_and_dds_headers_at_u32_sizes_fail_the_size_limit() {
    for size in [1u32 << 31, u32::MAX] {
        for (faces, levels) in [(6u32, 1u32), (6, 32), (1, 1), (1, 32)] {
            let mut b = b"\xABKTX 20\xBB\r\n\x1A\n".to_vec();
            for v in [97, 2, size, size, 0, 0, faces, levels, 0] {
                b.extend_from_slice(&u32::to_le_bytes(v));
            }
            b.resize(80, 0);
            let e = ktx2_error(&b, &format!("{size}² × {faces}, {levels} levels"));
            assert_mentions(&e, &["above the limit"], "u32-sized header");
        }
    }
}

/// Unsupported features are refused with a message naming them: vkFormat 0
/// with BasisLZ (Basis), BC6H (vkFormat 143, BCn), layerCount 2 (array),
/// pixelDepth 4 (3D), ZLIB (scheme 3), and a typeSize other than the
/// format's (1 under zstd, as some writers put).
#[test]
fn ktx2_unsupported_features_are_named() {
    let good = small_ktx2(false);
    let patched = |edits: &[(usize, u32)]| {
        let mut b = good.clone();
        for &(at, v) in edits {
            put_u32(&mut b, at, v);
        }
        b
    };
    // (header word offset, value) edits, and the words the message needs.
    type Edits<'a> = &'a [(usize, u32)];
    let cases: [(Edits, &[&str]); 6] = [
        (&[(12, 0), (16, 1), (44, 1)], &["Basis"]),
        (&[(12, 145), (16, 1)], &["BCn", "145"]),
        (&[(32, 2)], &["array", "layerCount 2"]),
        (&[(28, 4)], &["3D", "pixelDepth 4"]),
        (&[(44, 3)], &["ZLIB"]),
        (&[(16, 1), (44, 2)], &["typeSize"]),
    ];
    for (edits, words) in cases {
        let what = format!("{edits:?}");
        let e = ktx2_error(&patched(edits), &what);
        assert_mentions(&e, words, &what);
    }
}

/// Corrupt zstd levels: a broken frame magic, a frame cut short (its
/// byteLength reduced), and an uncompressedByteLength not matching the
/// level are errors naming the level; flipping any single byte of the
/// smallest level never panics (zstd frames carry no checksum here, so some
/// flips decode to other texels: those must still give a whole texture).
#[test]
fn ktx2_corrupt_zstd_levels_are_errors_not_panics() {
    let good = small_ktx2(true);
    let entry = |b: &[u8], p: usize| {
        ::ktx2::LevelIndex::from_bytes(b[level_entry(p)..level_entry(p) + 24].try_into().unwrap())
    };
    let l0 = entry(&good, 0);
    let mut b = good.clone();
    b[l0.byte_offset as usize] ^= 0xFF;
    let e = ktx2_error(&b, "level 0 zstd magic broken");
    assert_mentions(&e, &["level 0", "zstd"], "broken magic");

    let mut b = good.clone();
    put_u64(&mut b, level_entry(0) + 8, l0.byte_length - 1);
    let e = ktx2_error(&b, "level 0 zstd frame cut short");
    assert_mentions(&e, &["level 0", "zstd"], "frame cut short");

    let mut b = good.clone();
    put_u64(
        &mut b,
        level_entry(1) + 16,
        entry(&good, 1).uncompressed_byte_length + 8,
    );
    let e = ktx2_error(&b, "level 1 uncompressedByteLength + 8");
    assert_mentions(
        &e,
        &["level 1", "uncompressedByteLength"],
        "wrong uncompressed length",
    );

    let l2 = entry(&good, 2);
    for i in 0..l2.byte_length as usize {
        let mut b = good.clone();
        b[l2.byte_offset as usize + i] ^= 0x5A;
        let r = catch_unwind(AssertUnwindSafe(|| {
            texture::decode(Path::new(BAD_KTX2), &b, DEFAULT_MAX_TEXELS)
        }))
        .unwrap_or_else(|_| panic!("level 2 byte {i} flipped: decode panicked"));
        match r {
            Ok(f) => {
                assert_eq!(f.texture.level_count(), 3, "byte {i}");
                assert_eq!(f.texture.levels()[2][5].pixels.len(), 4, "byte {i}");
            }
            Err(e) => assert!(e.to_string().starts_with(BAD_KTX2), "byte {i}: {e}"),
        }
    }
}

/// A small valid DDS: an 8² RGBA16F cube with 3 levels.
fn small_dds() -> Vec<u8> {
    let tex = texture(TextureKind::Cube, (8, 8), 3);
    let bytes = texture::encode(&tex, Path::new("t.dds"), {
        let mut o = TextureOptions::default();
        o.format = TexelFormat::Rgba16f;
        o.zstd = None;
        o
    })
    .unwrap()
    .0;
    texture::decode(Path::new("good.dds"), &bytes, DEFAULT_MAX_TEXELS)
        .expect("the unbroken file decodes");
    bytes
}

/// Every prefix of a valid DDS cube (lengths 0 … len − 1) is an error
/// naming the file.
#[test]
fn dds_every_prefix_is_an_error_naming_the_file() {
    let bytes = small_dds();
    for len in 0..bytes.len() {
        dds_error(&bytes[..len], &format!("prefix of {len} bytes"));
    }
}

/// A DX10 header with BC7_UNORM (DXGI 98) is refused naming the format.
#[test]
fn dds_bc7_is_refused_naming_the_format() {
    let mut b = small_dds();
    put_u32(&mut b, 128, 98);
    let e = dds_error(&b, "BC7");
    assert_mentions(&e, &["98", "BC7"], "BC7");
}

/// A header claiming 65536×65536 faces fails the size limit (TooLarge,
/// "above the limit") before the (short) data is looked at.
#[test]
fn dds_huge_header_fails_the_size_limit() {
    let mut b = small_dds();
    put_u32(&mut b, 12, 65536); // height
    put_u32(&mut b, 16, 65536); // width
    let e = dds_error(&b, "65536² cube");
    assert_mentions(&e, &["above the limit"], "huge DDS");
    let inner = match &e {
        Error::InFile { source, .. } => &**source,
        other => other,
    };
    let all = 6 * (65536u64 * 65536 + 32768 * 32768 + 16384 * 16384);
    assert!(
        matches!(inner, Error::TooLarge { texels, .. } if *texels == all),
        "not TooLarge with all the texels: {e:?}"
    );
}

/// Every preset's files say the axes their cubes are in where the container
/// has room (KTX2 key/value data, OpenEXR attributes), and loading them
/// back puts every texel where the bake put it: level 0 read from the file
/// and converted to a latlong in envmap's axes equals the bake's own level 0
/// converted the same way, bit for bit. Bevy's cube is in its world with z
/// negated: read as the GL world (as before the file said so) it comes back
/// mirrored front to back, which the check catches. DDS has no place for
/// the axes: a DDS file loads in the default GL world, and `envmap info`
/// says so.
#[test]
fn every_presets_files_say_their_axes_and_load_back_in_them() {
    use envmap_render::bake::{Baker, Preset, Target};
    use envmap_render::image::FileAxes;
    use envmap_render::image::FileFormat;
    use envmap_render::{
        filter::{convert, ConvertOptions},
        image::load_from_memory,
    };
    let src = envmap_render::scene::fill(
        Representation::default_for(AnyMapping::LatLong),
        64,
        32,
        |d| [d.x.max(0.0) + 0.1, d.y.max(0.0) + 0.1, d.z.max(0.0) + 0.1],
    )
    .expect("source");
    let latlong = |img: &EnvImage| {
        convert(
            img,
            Representation::default_for(AnyMapping::LatLong),
            32,
            16,
            &ConvertOptions::default(),
            None,
        )
        .expect("convert")
    };
    let mut cases: Vec<(String, Preset)> = Vec::new();
    for t in [Target::Bevy, Target::Gltf] {
        cases.push((
            t.name().to_owned(),
            Preset::for_target(t, FileAxes::default()),
        ));
    }
    cases.push(("default".to_owned(), Preset::default()));
    let mut dds = Preset::for_target(Target::Bevy, FileAxes::default());
    dds.container = FileFormat::Dds;
    dds.texture.zstd = None;
    dds.texture.format = TexelFormat::Rgba16f;
    cases.push(("bevy-dds".to_owned(), dds));
    for (label, mut preset) in cases {
        preset.size = 8;
        preset.irradiance_size = 0;
        preset.dfg_size = 0;
        let container = preset.container;
        let baked = Baker::with_preset(preset).bake(&src).expect("bake");
        let level0 = &baked.bake().chain.as_ref().expect("chain").levels[0];
        let files = baked.files("ibl").expect("files");
        let (name, bytes) = files
            .files
            .iter()
            .find(|f| {
                let n = f.path.to_string_lossy();
                n.starts_with("specular") && !n.ends_with(".json")
            })
            .map(|f| (f.path.to_string_lossy().into_owned(), f.bytes.clone()))
            .expect("a specular file");
        let loaded = load_from_memory(&bytes, &name, &LoadOptions::default()).expect("load");
        let frame = loaded.image.representation().frame;
        if container == FileFormat::Dds {
            // No place to say: the GL world, whatever the bake's axes.
            assert_eq!(
                frame,
                Representation::for_file(AnyMapping::Cube, FileAxes::default()).frame,
                "{label}"
            );
            continue;
        }
        assert_eq!(
            frame,
            level0.representation().frame,
            "{label}: the axes read back"
        );
        let (a, b) = (latlong(&loaded.image), latlong(level0));
        // RGB9E5's step is at most 1/256 of a texel's largest channel (here
        // under 1.2), so packing moves a value by under 0.0024; RGBA16F and
        // f32 by far less. A mirrored map moves these texels by 0.1 to 1.
        let close = a.pixels().iter().zip(b.pixels()).all(|(x, y)| {
            x.iter()
                .zip(y)
                .all(|(u, v)| (u - v).abs() <= 5e-3 * v.abs().max(1.0))
        });
        assert!(close, "{label}: texels where the bake put them");
    }
}
