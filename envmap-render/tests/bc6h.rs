//! BC6H files: KTX2 and DDS hold what the formats say (read back by the
//! `ktx2` and `ddsfile` crates), envmap's decoding is `bcdec_rs`'s of the
//! blocks those crates find, every level's error is recorded, and clamping
//! is counted.

use std::path::Path;

use envmap_render::bake::{Baker, Preset, Target};
use envmap_render::image::texture::TextureOptions;
use envmap_render::image::texture::{self, full_chain, level_size, Texture, TextureKind};
use envmap_render::image::FileAxes;
use envmap_render::image::{Bc6hQuality, Representation, RgbImage, TexelFormat};
use envmap_render::scene::Builtin;

/// A smooth HDR test texture: a gradient over three decades, different
/// per face and level, with a bright spot.
fn smooth(kind: TextureKind, (w, h): (u32, u32), levels: usize) -> Texture {
    let levels = (0..levels)
        .map(|p| {
            let (lw, lh) = level_size(w, h, p);
            (0..kind.faces())
                .map(|f| RgbImage {
                    width: lw,
                    height: lh,
                    pixels: (0..lh)
                        .flat_map(|y| {
                            (0..lw).map(move |x| {
                                let (u, v) =
                                    ((x as f32 + 0.5) / lw as f32, (y as f32 + 0.5) / lh as f32);
                                let base = 10f32.powf(3.0 * u - 1.0) * (1.0 + f as f32 * 0.1);
                                let spot = if (u - 0.7).abs() < 0.1 && (v - 0.3).abs() < 0.1 {
                                    500.0
                                } else {
                                    0.0
                                };
                                [
                                    base + spot,
                                    base * (0.5 + 0.5 * v) + spot,
                                    base * 0.3 + 0.1 * v,
                                ]
                            })
                        })
                        .collect(),
                })
                .collect()
        })
        .collect();
    Texture::new(kind, levels).unwrap()
}

fn options(format: TexelFormat, zstd: Option<i32>) -> TextureOptions {
    let mut o = TextureOptions::default();
    o.format = format;
    o.zstd = zstd;
    o
}

/// The `w`×`h` image of BC6H `blocks` as `bcdec_rs` decodes them.
fn bcdec(blocks: &[u8], (w, h): (u32, u32)) -> Vec<[f32; 3]> {
    let (w, h) = (w as usize, h as usize);
    let bw = w.div_ceil(4);
    assert_eq!(
        blocks.len(),
        bw * h.div_ceil(4) * 16,
        "{w}×{h}: block bytes"
    );
    let mut out = vec![[f32::NAN; 3]; w * h];
    for (b, block) in blocks.chunks_exact(16).enumerate() {
        let mut px = [0f32; 48];
        bcdec_rs::bc6h_float(block, &mut px, 12, false);
        for y in 0..4 {
            for x in 0..4 {
                let (tx, ty) = ((b % bw) * 4 + x, (b / bw) * 4 + y);
                if tx < w && ty < h {
                    let k = 3 * (4 * y + x);
                    out[ty * w + tx] = [px[k], px[k + 1], px[k + 2]];
                }
            }
        }
    }
    out
}

fn assert_same_bits(a: &[[f32; 3]], b: &[[f32; 3]], what: &str) {
    assert_eq!(a.len(), b.len(), "{what}: texels");
    for (i, (x, y)) in a.iter().zip(b).enumerate() {
        assert_eq!(
            x.map(f32::to_bits),
            y.map(f32::to_bits),
            "{what}: texel {i}"
        );
    }
}

/// KTX2: vkFormat 143, typeSize 1, each level one 16-byte block per 4×4
/// texels of each face (2×2 and 1×1 levels one block), as the `ktx2`
/// crate reads them; envmap decodes each face as `bcdec_rs` decodes those
/// blocks, and the zstd file decodes the same.
#[test]
fn ktx2_bc6h_levels_are_whole_blocks_that_decode_as_bcdec_decodes_them() {
    for (kind, size) in [(TextureKind::Flat, (16, 8)), (TextureKind::Cube, (16, 16))] {
        let n = full_chain(size.0, size.1);
        let tex = smooth(kind, size, n);
        let what = format!("{kind:?}");
        let (bytes, clamped) =
            texture::encode(&tex, Path::new("t.ktx2"), options(TexelFormat::Bc6h, None)).unwrap();
        assert!(clamped.is_empty(), "{what}: {clamped:?}");
        let reader = ktx2::Reader::new(&bytes[..]).unwrap();
        let hd = reader.header();
        assert_eq!(hd.format, Some(ktx2::Format::BC6H_UFLOAT_BLOCK), "{what}");
        assert_eq!(hd.type_size, 1, "{what}: typeSize");
        assert_eq!(hd.level_count as usize, n, "{what}");
        let ours = texture::decode(Path::new("t.ktx2"), &bytes, 1 << 20).unwrap();
        assert_eq!(ours.info.format, TexelFormat::Bc6h);
        for (p, level) in reader.levels().enumerate() {
            let (lw, lh) = level_size(size.0, size.1, p);
            let face = TexelFormat::Bc6h.image_bytes(lw, lh);
            assert_eq!(face, lw.div_ceil(4) as usize * lh.div_ceil(4) as usize * 16);
            assert_eq!(
                level.data.len(),
                face * kind.faces(),
                "{what}: level {p} bytes"
            );
            // Levels start on 16-byte boundaries: lcm(16, 4).
            let start = level.data.as_ptr() as usize - bytes.as_ptr() as usize;
            assert_eq!(start % 16, 0, "{what}: level {p} at {start}");
            for (f, blocks) in level.data.chunks_exact(face).enumerate() {
                let want = bcdec(blocks, (lw, lh));
                let got = &ours.texture.levels()[p][f].pixels;
                assert_same_bits(got, &want, &format!("{what} level {p} face {f}"));
            }
        }
        let (z, _) = texture::encode(
            &tex,
            Path::new("t.ktx2"),
            options(TexelFormat::Bc6h, Some(3)),
        )
        .unwrap();
        let zback = texture::decode(Path::new("t.ktx2"), &z, 1 << 20).unwrap();
        assert_eq!(
            zback.texture.levels(),
            ours.texture.levels(),
            "{what}: zstd"
        );
    }
}

/// DDS: DXGI_FORMAT_BC6H_UF16 (95) in the DX10 header, face-major data of
/// whole blocks as `ddsfile` reads it, decoded as `bcdec_rs` decodes it.
#[test]
fn dds_bc6h_files_hold_face_major_blocks_that_decode_as_bcdec_decodes_them() {
    for (kind, size) in [(TextureKind::Flat, (16, 8)), (TextureKind::Cube, (16, 16))] {
        let n = full_chain(size.0, size.1);
        let tex = smooth(kind, size, n);
        let what = format!("{kind:?}");
        let (bytes, _) =
            texture::encode(&tex, Path::new("t.dds"), options(TexelFormat::Bc6h, None)).unwrap();
        let d = ddsfile::Dds::read(&bytes[..]).unwrap();
        let h10 = d.header10.as_ref().expect("a DX10 header");
        assert_eq!(h10.dxgi_format as u32, 95, "{what}");
        let ours = texture::decode(Path::new("t.dds"), &bytes, 1 << 20).unwrap();
        let mut at = 0;
        for f in 0..kind.faces() {
            for p in 0..n {
                let (lw, lh) = level_size(size.0, size.1, p);
                let len = TexelFormat::Bc6h.image_bytes(lw, lh);
                let want = bcdec(&d.data[at..at + len], (lw, lh));
                at += len;
                let got = &ours.texture.levels()[p][f].pixels;
                assert_same_bits(got, &want, &format!("{what} face {f} level {p}"));
            }
        }
        assert_eq!(at, d.data.len(), "{what}: data length");
    }
}

/// The KTX2 file records each level's error in `envmap.bc6h-error`, one
/// line per level, and a slower setting is no worse on the whole.
#[test]
fn ktx2_bc6h_files_record_each_levels_error() {
    let tex = smooth(TextureKind::Cube, (32, 32), 6);
    let (bytes, _) =
        texture::encode(&tex, Path::new("t.ktx2"), options(TexelFormat::Bc6h, None)).unwrap();
    let back = texture::decode(Path::new("t.ktx2"), &bytes, 1 << 20).unwrap();
    let text = back
        .info
        .key_values
        .iter()
        .find(|(k, _)| k == "envmap.bc6h-error")
        .map(|(_, v)| v.clone())
        .expect("the error key");
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 6, "{text}");
    for (p, l) in lines.iter().enumerate() {
        assert!(l.starts_with(&format!("level {p}: rel. RMS ")), "{l}");
    }
}

/// Components outside BC6H's range are clamped to [0, 65504] and counted
/// (NaN written as 0), once per texel (not per padding copy).
#[test]
fn bc6h_clamps_to_the_half_range_and_counts() {
    let pixels = vec![
        [-1.0, 1e6, f32::NAN],
        [1.0, 2.0, 3.0],
        [f32::INFINITY, 0.5, -0.0],
    ];
    let tex = Texture::new(
        TextureKind::Flat,
        vec![vec![RgbImage {
            width: 3,
            height: 1,
            pixels,
        }]],
    )
    .unwrap();
    let (bytes, c) =
        texture::encode(&tex, Path::new("t.ktx2"), options(TexelFormat::Bc6h, None)).unwrap();
    assert_eq!((c.below, c.above, c.nan), (1, 2, 1), "{c:?}");
    let back = texture::decode(Path::new("t.ktx2"), &bytes, 1 << 20).unwrap();
    for t in &back.texture.levels()[0][0].pixels {
        for v in t {
            assert!((0.0..=65504.0).contains(v), "{t:?}");
        }
    }
}

/// KTX 1 (Filament's) is written uncompressed: a bake for Filament in
/// BC6H is refused with the reason, and nothing is written.
#[test]
fn ktx1_refuses_bc6h_with_the_reason() {
    let repr = Representation::default_for(envmap_core::AnyMapping::LatLong);
    let sky = Builtin::Sky.image(repr, 64, 32).unwrap();
    let mut preset = Preset::for_target(Target::Filament, FileAxes::default());
    preset.size = 16;
    preset.texture = options(TexelFormat::Bc6h, None);
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("f");
    let e = match Baker::with_preset(preset).bake_into(sky, &out) {
        Ok(_) => panic!("a Filament bake in BC6H was written"),
        Err(e) => e.to_string(),
    };
    assert!(e.contains("BC6H goes in KTX2 or DDS"), "{e}");
    assert!(!out.exists(), "{e}: a directory was left");
}

/// The quality names parse, and an unknown one lists them.
#[test]
fn bc6h_quality_names() {
    for q in Bc6hQuality::ALL {
        assert_eq!(Bc6hQuality::parse(q.name()).unwrap(), q);
    }
    assert_eq!(
        Bc6hQuality::parse("very_slow").unwrap(),
        Bc6hQuality::VerySlow
    );
    let e = Bc6hQuality::parse("best").unwrap_err().to_string();
    assert!(e.contains("very-fast, fast, basic, slow, very-slow"), "{e}");
}

/// The built-in sky's chain as `envmap bake --format bc6h` writes it: the
/// manifest's error per level is what decoding the file's blocks with
/// `bcdec_rs` (read by the `ktx2` crate) gives against the uncompressed
/// chain, and no level comes back exact.
#[test]
fn the_manifest_gives_each_levels_error_as_decoding_the_file_measures_it() {
    let repr = Representation::default_for(envmap_core::AnyMapping::LatLong);
    let sky = Builtin::Sky.image(repr, 256, 128).unwrap();
    let mut preset = Preset::for_target(Target::Bevy, FileAxes::default());
    preset.size = 64;
    preset.texture = options(TexelFormat::Bc6h, None);
    let baked = Baker::with_preset(preset).bake(&sky).unwrap();
    let files = baked.files("b").unwrap();
    let manifest: serde_json::Value =
        serde_json::from_slice(files.get("manifest.json").unwrap()).unwrap();
    let c = &manifest["compression"];
    assert_eq!(c["format"], "BC6H_UFLOAT_BLOCK", "{c}");
    assert_eq!(c["quality"], "very-fast", "{c}");
    let spec = c["files"]
        .as_array()
        .unwrap()
        .iter()
        .find(|f| f["file"] == "specular.ktx2")
        .expect("specular.ktx2");
    let levels = spec["levels"].as_array().unwrap();
    let chain = &baked.bake().chain.as_ref().unwrap().levels;
    assert_eq!(levels.len(), chain.len(), "{spec}");
    let bytes = files.get("specular.ktx2").unwrap();
    let reader = ktx2::Reader::new(bytes).unwrap();
    let tex = Texture::from_env(chain).unwrap();
    for ((p, level), (faces, l)) in reader
        .levels()
        .enumerate()
        .zip(tex.levels().iter().zip(levels))
    {
        let w = faces[0].width;
        let face = TexelFormat::Bc6h.image_bytes(w, w);
        let (mut num, mut den) = (0.0f64, 0.0f64);
        for (f, blocks) in faces.iter().zip(level.data.chunks_exact(face)) {
            for (d, r) in bcdec(blocks, (w, w)).iter().zip(&f.pixels) {
                for k in 0..3 {
                    let r = f64::from(r[k].clamp(0.0, 65504.0));
                    num += (f64::from(d[k]) - r).powi(2);
                    den += r * r;
                }
            }
        }
        let ours = (num / den).sqrt();
        let recorded = l["relative_rms"].as_f64().unwrap();
        assert!(
            (ours - recorded).abs() <= 1e-9 * ours.max(1e-12),
            "level {p}: the manifest says {recorded}, decoding says {ours}"
        );
        assert!(ours > 0.0, "level {p}: exact?");
    }
}
