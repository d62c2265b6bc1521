//! Engine-ready files from the command line: `envmap bake --target
//! bevy|gltf|filament`, `envmap convert --mips` into KTX2 and DDS, `envmap
//! info` and `envmap render --env` on them; each output read back by an
//! independent parser (the `ktx2` crate, `ddsfile`) or by the KTX 1 layout
//! cmgen writes.

mod common;

use std::path::Path;

use common::{entries, envmap, text};
use envmap_render::image::{unpack_b10g11r11, TexelFormat};

fn ok(o: &std::process::Output) -> String {
    assert!(
        o.status.success(),
        "status {:?}\n{}",
        o.status,
        text(&o.stderr)
    );
    text(&o.stderr)
}

fn bake(d: &Path, out: &str, extra: &[&str]) -> String {
    let mut args = vec![
        "bake",
        "sky",
        "--out",
        out,
        "--env-size",
        "64",
        "--quality",
        "draft",
    ];
    args.extend_from_slice(extra);
    ok(&envmap(&args, d))
}

#[test]
fn bevy_target_writes_rgb9e5_zstd_ktx2_cubes() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    bake(d, "bevy", &["--target", "bevy", "--size", "32"]);
    let out = d.join("bevy");
    assert_eq!(
        entries(&out),
        ["diffuse.ktx2", "manifest.json", "sh.json", "specular.ktx2"]
    );
    for (file, levels, size) in [("specular.ktx2", 5, 32), ("diffuse.ktx2", 1, 32)] {
        let bytes = std::fs::read(out.join(file)).unwrap();
        let r = ktx2::Reader::new(&bytes[..]).unwrap();
        let h = r.header();
        assert_eq!(
            h.format,
            Some(ktx2::Format::E5B9G9R9_UFLOAT_PACK32),
            "{file}"
        );
        assert_eq!(h.type_size, 4);
        assert_eq!(
            (h.pixel_width, h.pixel_height, h.face_count),
            (size, size, 6)
        );
        assert_eq!(h.level_count, levels, "{file}");
        assert_eq!(
            h.supercompression_scheme,
            Some(ktx2::SupercompressionScheme::Zstandard)
        );
        assert!(r.writer().unwrap().starts_with("envmap "));
    }
    let m: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("manifest.json")).unwrap()).unwrap();
    assert_eq!(m["container"], "ktx2");
    assert_eq!(m["target"], "bevy");
    assert_eq!(m["texel_format"], "E5B9G9R9_UFLOAT_PACK32");
    assert_eq!(m["specular"]["roughness_rule"], "linear");
    assert_eq!(
        m["specular"]["levels"][2]["file"],
        "specular.ktx2 (level 2)"
    );
    assert_eq!(m["irradiance"]["value"], "E/pi");
}

#[test]
fn gltf_target_writes_rgba16f_chain_to_2x2_and_the_lut() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    bake(
        d,
        "gltf",
        &["--target", "gltf", "--size", "32", "--dfg-size", "16"],
    );
    let out = d.join("gltf");
    let names = entries(&out);
    for f in ["specular.ktx2", "diffuse.ktx2", "lut_ggx.ktx2", "dfg.exr"] {
        assert!(names.contains(&f.to_owned()), "{names:?}");
    }
    let bytes = std::fs::read(out.join("specular.ktx2")).unwrap();
    let r = ktx2::Reader::new(&bytes[..]).unwrap();
    let h = r.header();
    assert_eq!(h.format, Some(ktx2::Format::R16G16B16A16_SFLOAT));
    assert_eq!(h.supercompression_scheme, None);
    // glTF-IBL-Sampler's ⌊log2 32⌋ = 5 levels: 32 … 2.
    assert_eq!(h.level_count, 5);
    let bytes = std::fs::read(out.join("lut_ggx.ktx2")).unwrap();
    let r = ktx2::Reader::new(&bytes[..]).unwrap();
    let h = r.header();
    assert_eq!((h.pixel_width, h.pixel_height, h.face_count), (16, 16, 1));
    // The LUT's scale + bias at the smoothest, most head-on entry is near 1
    // (F0 = 1 reflects everything), its bias near 0.
    let level = r.levels().next().unwrap();
    let px = TexelFormat::Rgba16f.unpack(level.data);
    let head_on = px[15];
    assert!((head_on[0] + head_on[1] - 1.0).abs() < 0.02, "{head_on:?}");
    assert!(head_on[1] < 0.02, "{head_on:?}");
}

/// The KTX 1 header words after the identifier.
fn ktx1_header(bytes: &[u8]) -> Vec<u32> {
    assert_eq!(&bytes[..12], b"\xABKTX 11\xBB\r\n\x1A\n");
    bytes[12..64]
        .chunks_exact(4)
        .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect()
}

/// Level 0's six faces of a KTX 1 R11F_G11F_B10F cube of `w`² faces.
fn ktx1_faces(bytes: &[u8], w: usize) -> Vec<Vec<[f32; 3]>> {
    let h = ktx1_header(bytes);
    let mut at = 64 + h[12] as usize;
    let size = u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap()) as usize;
    assert_eq!(size, w * w * 4, "imageSize is one face's bytes");
    at += 4;
    (0..6)
        .map(|f| {
            bytes[at + f * size..at + (f + 1) * size]
                .chunks_exact(4)
                .map(|c| unpack_b10g11r11(u32::from_le_bytes([c[0], c[1], c[2], c[3]])))
                .collect()
        })
        .collect()
}

#[test]
fn filament_target_writes_cmgen_files_mirrored_by_default() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    bake(d, "fil.ext", &["--target", "filament", "--size", "32"]);
    bake(
        d,
        "plain",
        &["--target", "filament", "--size", "32", "--no-mirror"],
    );
    let out = d.join("fil.ext");
    // cmgen's names: the output directory's name without its extension.
    assert_eq!(
        entries(&out),
        [
            "fil_ibl.ktx",
            "fil_skybox.ktx",
            "manifest.json",
            "sh.json",
            "sh.txt"
        ]
    );
    let ibl = std::fs::read(out.join("fil_ibl.ktx")).unwrap();
    let sky = std::fs::read(out.join("fil_skybox.ktx")).unwrap();
    let h = ktx1_header(&ibl);
    // endianness, glType, glTypeSize, glFormat, glInternalFormat,
    // glBaseInternalFormat, width, height, depth, array elements, faces,
    // levels (32 → 16: the filament rule's 16² floor), as cmgen writes them.
    assert_eq!(
        &h[..12],
        &[
            0x0403_0201,
            0x8C3A,
            1,
            0x1907,
            0x8C3A,
            0x8C3A,
            32,
            32,
            0,
            0,
            6,
            2
        ]
    );
    let s = ktx1_header(&sky);
    assert_eq!((s[11], s[12]), (1, 0), "one level, no key/value data");
    // The sh key: nine lines of three numbers, no NUL after the text.
    let kv_len = u32::from_le_bytes(ibl[64..68].try_into().unwrap()) as usize;
    assert_eq!(&ibl[68..71], b"sh\0");
    let sh = std::str::from_utf8(&ibl[71..68 + kv_len]).unwrap();
    let lines: Vec<&str> = sh.split_terminator('\n').collect();
    assert_eq!(lines.len(), 9, "{sh:?}");
    assert!(sh.ends_with('\n'));
    for l in &lines {
        let v: Vec<f32> = l.split(' ').map(|t| t.parse().unwrap()).collect();
        assert_eq!(v.len(), 3, "{l}");
    }
    let txt = std::fs::read_to_string(out.join("sh.txt")).unwrap();
    assert_eq!(txt.lines().count(), 9);
    assert!(txt
        .lines()
        .next()
        .unwrap()
        .ends_with("// L00, irradiance, pre-scaled base"));
    // The sky level 0 is the skybox, byte for byte.
    let sky_data = &sky[64..];
    assert_eq!(
        &ibl[64 + h[12] as usize..64 + h[12] as usize + sky_data.len()],
        sky_data
    );
    // Mirrored: the +X face holds the unmirrored −X face flipped left to
    // right, and so on for every face (x negated).
    let plain = std::fs::read(d.join("plain").join("plain_skybox.ktx")).unwrap();
    let (m, p) = (ktx1_faces(&sky, 32), ktx1_faces(&plain, 32));
    let partner = [1, 0, 2, 3, 4, 5];
    let mut worst = 0f32;
    for f in 0..6 {
        for y in 0..32 {
            for x in 0..32 {
                let a = m[f][y * 32 + x];
                let b = p[partner[f]][y * 32 + 31 - x];
                for c in 0..3 {
                    worst = worst.max((a[c] - b[c]).abs() / b[c].abs().max(1e-3));
                }
            }
        }
    }
    // Within one step of the 5-bit mantissa (values one rounding apart).
    assert!(worst <= 1.0 / 32.0, "worst relative difference {worst}");
    // The SH terms odd in x change sign with the mirror, the others stay.
    let plain_sh = std::fs::read_to_string(d.join("plain").join("sh.txt")).unwrap();
    let first = |s: &str, i: usize| -> f64 {
        s.lines().nth(i).unwrap()[1..]
            .split(',')
            .next()
            .unwrap()
            .trim()
            .parse()
            .unwrap()
    };
    for i in 0..9 {
        let (a, b) = (first(&txt, i), first(&plain_sh, i));
        let want = if [3, 4, 7].contains(&i) { -b } else { b };
        assert!(
            (a - want).abs() <= 1e-6 * (1.0 + b.abs()),
            "L{i}: {a} vs {b}"
        );
    }
}

#[test]
fn convert_writes_mip_chains_that_info_lists_and_render_reads() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    ok(&envmap(
        &[
            "bake",
            "sky",
            "--out",
            "b",
            "--size",
            "16",
            "--env-size",
            "32",
            "--quality",
            "draft",
            "--irradiance-size",
            "0",
            "--dfg-size",
            "0",
        ],
        d,
    ));
    for (out, extra) in [
        ("c.ktx2", vec!["--format", "rgb9e5", "--zstd", "3"]),
        ("c.dds", vec!["--format", "rg11b10f"]),
    ] {
        let mut args = vec![
            "convert",
            "b/specular_0.exr",
            out,
            "--to",
            "cube",
            "--size",
            "16",
            "--mips",
        ];
        args.extend(extra);
        let err = ok(&envmap(&args, d));
        assert!(err.contains("texture: 5 levels"), "{err}");
        let o = envmap(&["info", out], d);
        let info = ok(&o);
        let info = format!("{info}{}", text(&o.stdout));
        assert!(info.contains("16 × 16 × 6 faces"), "{info}");
        assert!(info.contains("level 4          1 × 1 × 6 faces"), "{info}");
        assert!(info.contains("mapping          cube"), "{info}");
        let r = envmap(
            &[
                "render", "r.png", "--env", out, "--width", "32", "--height", "24",
            ],
            d,
        );
        ok(&r);
        assert!(d.join("r.png").exists());
    }
    let dds = std::fs::read(d.join("c.dds")).unwrap();
    let f = ddsfile::Dds::read(&dds[..]).unwrap();
    assert_eq!(f.get_num_mipmap_levels(), 5);
    assert_eq!(f.get_num_array_layers(), 6);
}

#[test]
fn texture_flags_are_refused_where_they_mean_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let o = envmap(
        &["bake", "sky", "--out", "x", "--container", "dds", "--zstd"],
        d,
    );
    assert!(!o.status.success());
    assert!(
        text(&o.stderr).contains("only KTX2 has supercompression"),
        "{}",
        text(&o.stderr)
    );
    let o = envmap(&["bake", "sky", "--out", "x", "--no-mirror"], d);
    assert!(text(&o.stderr).contains("--no-mirror is for --target filament"));
    let o = envmap(&["bake", "sky", "--out", "x", "--format", "rgb9e5"], d);
    assert!(text(&o.stderr).contains("--format and --zstd are for --container"));
    let o = envmap(&["bake", "sky", "--out", "x", "--target", "unreal"], d);
    assert!(text(&o.stderr).contains("expected bevy, gltf, filament, babylon or gltf-ibl"));
    assert!(!d.join("x").exists(), "nothing written");
    std::fs::write(d.join("a.ktx"), b"not read").unwrap();
    let o = envmap(&["info", "a.ktx"], d);
    assert!(
        text(&o.stderr).contains("KTX 1 files are written"),
        "{}",
        text(&o.stderr)
    );
}

/// A baked chain written as KTX2 (every format, with and without zstd) and
/// DDS and read back is the same image level by level: exactly the
/// format's own rounding of each texel (`unpack(pack(x))`), which is within
/// the format's precision of the bake.
#[test]
fn a_baked_chain_survives_export_and_import_within_the_format_precision() {
    use envmap_render::filter::bake::{specular_chain, BakeOptions, Quality};
    use envmap_render::image::texture::{self, Texture, TextureKind, TextureOptions};
    use envmap_render::scene::Builtin;
    let repr = envmap_render::image::Representation::default_for(envmap_core::AnyMapping::Cube);
    let (w, h) = repr.atlas.image_size_for_cell_width(32).unwrap();
    let src = Builtin::Sky.image(repr, w, h).unwrap();
    let opts = {
        let mut o = BakeOptions::default();
        o.size = 16;
        o.quality = Quality::Draft;
        o
    };
    let chain = specular_chain(&src, &opts, &|_, _| {}).unwrap();
    let tex = Texture::from_env(&chain.levels).unwrap();
    assert_eq!((tex.kind(), tex.level_count()), (TextureKind::Cube, 4));
    // BC6H is lossy, its error measured apart (envmap-render's `bc6h` tests).
    for format in TexelFormat::WRITABLE
        .into_iter()
        .filter(|&f| f != TexelFormat::Bc6h)
    {
        for zstd in [None, Some(3)] {
            let (bytes, clamped) = texture::encode(&tex, Path::new("c.ktx2"), {
                let mut o = TextureOptions::default();
                o.format = format;
                o.zstd = zstd;
                o
            })
            .unwrap();
            assert!(clamped.is_empty(), "{format:?} {clamped:?}");
            let back = texture::decode(Path::new("c.ktx2"), &bytes, 1 << 20).unwrap();
            let dds_back = (zstd.is_none())
                .then(|| {
                    let (b, _) = texture::encode(&tex, Path::new("c.dds"), {
                        let mut o = TextureOptions::default();
                        o.format = format;
                        o.zstd = None;
                        o
                    })
                    .unwrap();
                    texture::decode(Path::new("c.dds"), &b, 1 << 20).unwrap()
                })
                .into_iter();
            for file in std::iter::once(back).chain(dds_back) {
                for (k, (a, b)) in tex.levels().iter().zip(file.texture.levels()).enumerate() {
                    for (fa, fb) in a.iter().zip(b) {
                        let mut packed = Vec::new();
                        let _ = format.pack(&fa.pixels, &mut packed);
                        assert_eq!(fb.pixels, format.unpack(&packed), "{format:?} level {k}");
                        // And within the format's precision of the bake.
                        for (x, y) in fa.pixels.iter().zip(&fb.pixels) {
                            let max = x[0].max(x[1]).max(x[2]);
                            for c in 0..3 {
                                let bound = match format {
                                    TexelFormat::E5b9g9r9 => max * 2f32.powi(-9),
                                    TexelFormat::B10g11r11 if c == 2 => x[c] * 2f32.powi(-6),
                                    _ => x[c] * format.relative_precision(),
                                };
                                assert!(
                                    (x[c] - y[c]).abs() <= bound * 1.0001 + 1e-6,
                                    "{format:?} level {k}: {x:?} -> {y:?}"
                                );
                            }
                        }
                    }
                }
            }
        }
    }
}

/// `envmap bake --target bevy --format bc6h`: a BC6H KTX2 chain whose
/// manifest gives each level's error; `envmap info` prints the error the
/// file records, level by level; a DDS bake records it in the manifest;
/// `--target filament --format bc6h` is refused with the reason.
#[test]
fn bake_writes_bc6h_and_reports_each_levels_error() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let o = envmap(
        &[
            "bake",
            "sky",
            "--out",
            "b",
            "--target",
            "bevy",
            "--size",
            "32",
            "--format",
            "bc6h",
            "--bc6h-quality",
            "fast",
        ],
        d,
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    let m: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("b/manifest.json")).unwrap()).unwrap();
    assert_eq!(m["texel_format"], "BC6H_UFLOAT_BLOCK");
    assert_eq!(m["compression"]["quality"], "fast");
    let files = m["compression"]["files"].as_array().unwrap();
    let spec = files.iter().find(|f| f["file"] == "specular.ktx2").unwrap();
    assert_eq!(spec["levels"].as_array().unwrap().len(), 5, "{spec}");
    let info = envmap(&["info", "b/specular.ktx2"], d);
    let out = text(&info.stdout);
    assert!(info.status.success(), "{}", text(&info.stderr));
    assert!(
        out.contains("bc6h (BC6H_UFLOAT_BLOCK; vkFormat 143, DXGI 95)"),
        "{out}"
    );
    for p in 0..5 {
        assert!(
            out.contains(&format!("BC6H error       level {p}: rel. RMS ")),
            "{out}"
        );
    }
    let o = envmap(
        &[
            "bake",
            "sky",
            "--out",
            "c",
            "--container",
            "dds",
            "--size",
            "16",
            "--format",
            "bc6h",
        ],
        d,
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    let m: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("c/manifest.json")).unwrap()).unwrap();
    assert!(
        m["compression"]["files"][0]["levels"][0]["relative_rms"]
            .as_f64()
            .unwrap()
            > 0.0
    );
    let info = envmap(&["info", "c/specular.dds"], d);
    assert!(
        text(&info.stdout).contains("not recorded in this file"),
        "{}",
        text(&info.stdout)
    );
    let o = envmap(
        &[
            "bake", "sky", "--out", "f", "--target", "filament", "--format", "bc6h",
        ],
        d,
    );
    assert!(!o.status.success());
    assert!(
        text(&o.stderr).contains("BC6H goes in KTX2 or DDS"),
        "{}",
        text(&o.stderr)
    );
    assert!(!d.join("f").exists(), "nothing written");
}

/// `--target babylon` writes one `.env` (every level down to 1×1, at
/// Babylon.js's rule), the manifest reports what RGBD lost per level (the
/// sky's sun is clipped at 255 in the sharp levels, not in the rough
/// ones), and `envmap info` reads the file back.
#[test]
fn bake_for_babylon_writes_an_env_file_and_reports_what_rgbd_clips() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let o = envmap(
        &[
            "bake", "sky", "--out", "b", "--target", "babylon", "--size", "32",
        ],
        d,
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    let names: Vec<String> = std::fs::read_dir(d.join("b"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert!(names.contains(&"environment.env".to_owned()), "{names:?}");
    assert_eq!(
        names.len(),
        3,
        "environment.env, manifest.json, sh.json: {names:?}"
    );
    let env = std::fs::read(d.join("b/environment.env")).unwrap();
    assert_eq!(&env[..8], &[0x86, 0x16, 0x87, 0x96, 0xF6, 0xD6, 0x96, 0x36]);
    let m: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("b/manifest.json")).unwrap()).unwrap();
    assert_eq!(m["target"], "babylon");
    assert_eq!(m["container"], "env");
    let levels = m["specular"]["levels"].as_array().unwrap();
    assert_eq!(levels.len(), 6, "32² down to 1×1");
    // Level k ≥ 1 at α = 2^(k/0.8)/32, at most 1; level 0 unfiltered.
    for (k, l) in levels.iter().enumerate() {
        let r = l["perceptual_roughness"].as_f64().unwrap();
        let want = if k == 0 {
            0.0
        } else {
            (2f64.powf(k as f64 / 0.8) / 32.0).min(1.0).sqrt()
        };
        assert!((r - want).abs() < 1e-6, "level {k}: {r} against {want}");
    }
    let c = &m["compression"]["files"][0]["levels"];
    let clipped0 = c[0]["clipped_energy"].as_f64().unwrap();
    let clipped_last = c[5]["clipped_energy"].as_f64().unwrap();
    assert!(clipped0 > 0.01, "the sun is clipped at level 0: {clipped0}");
    assert_eq!(clipped_last, 0.0);
    assert!(c[3]["relative_rms"].as_f64().unwrap() < 0.01, "{c}");
    let info = envmap(&["info", "b/environment.env"], d);
    let out = text(&info.stdout);
    assert!(info.status.success(), "{}", text(&info.stderr));
    assert!(
        out.contains("Babylon.js .env cube 32×32, 6 levels (full chain), rgbd"),
        "{out}"
    );
    assert!(out.contains("babylon.irradiance"), "{out}");
    assert!(out.contains("y up, left-handed"), "{out}");
    // The bake lights a render as Babylon.js reads it, its diffuse from the SH.
    let r = envmap(
        &[
            "render",
            "r.png",
            "--env",
            "b",
            "--engine",
            "babylon",
            "--object",
            "sphere",
            "--material",
            "chrome",
            "--roughness",
            "0.5",
            "--width",
            "32",
            "--height",
            "32",
        ],
        d,
    );
    let said = format!("{}{}", text(&r.stdout), text(&r.stderr));
    assert!(r.status.success(), "{said}");
    assert!(
        said.contains("irradiance sh.json (E/pi from the SH)"),
        "{said}"
    );
}

/// `--target gltf-ibl` writes one self-contained glTF file holding an
/// `EXT_lights_image_based` light: the chain at α = 2^k/size, every image
/// inside, and `envmap info` reads it back.
#[test]
fn bake_for_gltf_writes_an_image_based_light_that_info_reads() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let o = envmap(
        &[
            "bake", "sky", "--out", "g", "--target", "gltf-ibl", "--size", "32",
        ],
        d,
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    let gltf: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("g/environment.gltf")).unwrap())
            .unwrap();
    assert_eq!(gltf["extensionsUsed"][0], "EXT_lights_image_based");
    let light = &gltf["extensions"]["EXT_lights_image_based"]["lights"][0];
    assert_eq!(light["specularImageSize"], 32);
    assert_eq!(light["specularImages"].as_array().unwrap().len(), 6);
    assert_eq!(gltf["images"].as_array().unwrap().len(), 36);
    let m: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("g/manifest.json")).unwrap()).unwrap();
    assert_eq!(m["target"], "gltf-ibl");
    assert_eq!(m["container"], "gltf");
    for (k, l) in m["specular"]["levels"]
        .as_array()
        .unwrap()
        .iter()
        .enumerate()
    {
        let r = l["perceptual_roughness"].as_f64().unwrap();
        let want = if k == 0 {
            0.0
        } else {
            (2f64.powi(k as i32) / 32.0).min(1.0).sqrt()
        };
        assert!((r - want).abs() < 1e-6, "level {k}: {r} against {want}");
    }
    let info = envmap(&["info", "g/environment.gltf"], d);
    let out = text(&info.stdout);
    assert!(info.status.success(), "{}", text(&info.stderr));
    assert!(
        out.contains("glTF (EXT_lights_image_based) cube 32×32, 6 levels"),
        "{out}"
    );
    assert!(out.contains("gltf.irradianceCoefficients"), "{out}");
}
