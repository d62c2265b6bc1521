//! Babylon.js `.env` files: what envmap writes it reads back (RGBD's
//! precision aside), the manifest says what Babylon.js's loader checks,
//! and a bad file is an error naming it, never a panic.

use std::path::Path;

use envmap_render::image::texture::{self, level_size, Texture, TextureKind, TextureOptions};
use envmap_render::image::{RgbImage, TexelFormat};

/// A cube chain down to 1×1 over two decades, different per face.
fn chain(size: u32) -> Texture {
    let n = size.trailing_zeros() as usize + 1;
    let levels = (0..n)
        .map(|p| {
            let (w, h) = level_size(size, size, p);
            (0..6)
                .map(|f| RgbImage {
                    width: w,
                    height: h,
                    pixels: (0..w * h)
                        .map(|k| {
                            let (x, y) = ((k % w) as f32 / w as f32, (k / w) as f32 / h as f32);
                            let v = 10f32.powf(2.0 * x - 0.5) * (1.0 + 0.2 * f as f32);
                            [v, v * (0.3 + 0.7 * y), 0.05 + 0.1 * y]
                        })
                        .collect(),
                })
                .collect()
        })
        .collect();
    Texture::new(TextureKind::Cube, levels).unwrap()
}

fn env_path() -> &'static Path {
    Path::new("t.env")
}

/// The manifest and the images: magic, NUL-terminated JSON, version 2,
/// `6·(log2 w + 1)` images laid end to end after it, each a PNG.
#[test]
fn the_file_is_laid_out_as_babylons_loader_reads_it() {
    let tex = chain(16);
    let (bytes, clamped) = texture::encode(&tex, env_path(), TextureOptions::default()).unwrap();
    assert!(clamped.is_empty(), "{clamped:?}");
    assert_eq!(
        &bytes[..8],
        &[0x86, 0x16, 0x87, 0x96, 0xF6, 0xD6, 0x96, 0x36]
    );
    let nul = bytes[8..].iter().position(|&b| b == 0).unwrap() + 8;
    let m: serde_json::Value = serde_json::from_slice(&bytes[8..nul]).unwrap();
    assert_eq!(m["version"], 2);
    assert_eq!(m["width"], 16);
    assert_eq!(m["imageType"], "image/png");
    assert_eq!(
        m["specular"]["lodGenerationScale"].as_f64().unwrap() as f32,
        0.8
    );
    let mips = m["specular"]["mipmaps"].as_array().unwrap();
    assert_eq!(mips.len(), 6 * 5);
    let data = &bytes[nul + 1..];
    let mut at = 0;
    for (k, im) in mips.iter().enumerate() {
        let (pos, len) = (
            im["position"].as_u64().unwrap() as usize,
            im["length"].as_u64().unwrap() as usize,
        );
        assert_eq!(pos, at, "image {k} follows the one before");
        assert_eq!(&data[pos..pos + 8], b"\x89PNG\r\n\x1a\n", "image {k}");
        at += len;
    }
    assert_eq!(at, data.len());
    for t in ["x", "y", "z", "xx", "yy", "zz", "yz", "zx", "xy"] {
        assert_eq!(m["irradiance"][t].as_array().unwrap().len(), 3, "{t}");
    }
}

/// Read back, every texel is within RGBD's precision of what was written:
/// 0.6 % of its largest channel above 1 (and an 8-bit gamma-2.2 step
/// below), faces in place (not flipped), levels in order.
#[test]
fn what_is_written_is_read_back_within_rgbds_precision() {
    let tex = chain(16);
    let (bytes, _) = texture::encode(&tex, env_path(), TextureOptions::default()).unwrap();
    let back = texture::decode(env_path(), &bytes, u64::MAX).unwrap();
    assert_eq!(back.info.container, "Babylon.js .env");
    assert_eq!(back.info.format, TexelFormat::Rgbd8);
    assert_eq!(back.texture.level_count(), 5);
    assert_within_rgbd(&tex, &back.texture, 2.2);
}

/// Every texel of `back` within RGBD's precision of `tex`'s, its texels
/// stored as RGBD with the 8-bit gamma `g`: above 1, 0.6 %·(g/2.2) of the
/// texel's largest channel; below, half an 8-bit step of c^(1/g) back
/// through ^g. Faces in place, levels in order.
fn assert_within_rgbd(tex: &Texture, back: &Texture, g: f32) {
    for (p, (a, b)) in tex.levels().iter().zip(back.levels()).enumerate() {
        for (f, (fa, fb)) in a.iter().zip(b).enumerate() {
            for (k, (x, y)) in fa.pixels.iter().zip(&fb.pixels).enumerate() {
                let m = x[0].max(x[1]).max(x[2]);
                for c in 0..3 {
                    let tol = if m >= 1.0 {
                        0.006 * g / 2.2 * m
                    } else {
                        let v = x[c].max(0.0).powf(1.0 / g);
                        ((v + 0.5 / 255.0).powf(g) - v.powf(g)).max(1e-6)
                    };
                    assert!(
                        (x[c] - y[c]).abs() <= tol * 1.01,
                        "level {p} face {f} texel {k} channel {c}: {} read back as {}",
                        x[c],
                        y[c]
                    );
                }
            }
        }
    }
}

/// RGBD holds 0 … 255: brighter components are clamped and counted.
#[test]
fn components_above_255_are_clamped_and_counted() {
    let mut tex = chain(4);
    let levels: Vec<Vec<RgbImage>> = tex
        .levels()
        .iter()
        .map(|faces| {
            faces
                .iter()
                .map(|f| {
                    let mut f = f.clone();
                    f.pixels[0] = [1000.0, 2.0, 3.0];
                    f
                })
                .collect()
        })
        .collect();
    tex = Texture::new(TextureKind::Cube, levels).unwrap();
    let (bytes, clamped) = texture::encode(&tex, env_path(), TextureOptions::default()).unwrap();
    assert_eq!(clamped.above, 6 * 3, "one component per face per level");
    let back = texture::decode(env_path(), &bytes, u64::MAX).unwrap();
    let t = back.texture.levels()[0][0].pixels[0];
    assert!((t[0] - 255.0).abs() < 2.0, "{t:?}");
}

/// What Babylon.js cannot load is refused before anything is written: a
/// 2D texture, a size that is not a power of two, a chain that stops
/// before 1×1; and zstd.
#[test]
fn textures_babylon_cannot_load_are_refused() {
    let flat = Texture::new(
        TextureKind::Flat,
        vec![vec![RgbImage {
            width: 2,
            height: 1,
            pixels: vec![[1.0; 3]; 2],
        }]],
    )
    .unwrap();
    let e = texture::encode(&flat, env_path(), TextureOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("holds a cube map"), "{e}");
    let mut short = chain(8).levels().to_vec();
    short.pop();
    let short = Texture::new(TextureKind::Cube, short).unwrap();
    let e = texture::encode(&short, env_path(), TextureOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("every level down to 1×1"), "{e}");
    let odd = Texture::new(
        TextureKind::Cube,
        vec![(0..6)
            .map(|_| RgbImage {
                width: 3,
                height: 3,
                pixels: vec![[1.0; 3]; 9],
            })
            .collect()],
    )
    .unwrap();
    let e = texture::encode(&odd, env_path(), TextureOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("power-of-two"), "{e}");
    let mut o = TextureOptions::default();
    o.zstd = Some(3);
    let e = texture::encode(&chain(4), env_path(), o)
        .unwrap_err()
        .to_string();
    assert!(e.contains("no supercompression"), "{e}");
}

/// A damaged file is an error naming it and what is wrong: truncated
/// anywhere, no NUL, bad JSON, a wrong image count, an image past the end,
/// a corrupt PNG, WebP images, a newer version.
#[test]
fn damaged_files_are_errors_naming_the_file() {
    let (good, _) = texture::encode(&chain(4), env_path(), TextureOptions::default()).unwrap();
    let nul = good[8..].iter().position(|&b| b == 0).unwrap() + 8;
    let manifest = std::str::from_utf8(&good[8..nul]).unwrap().to_owned();
    let with = |m: &str| {
        let mut b = good[..8].to_vec();
        b.extend_from_slice(m.as_bytes());
        b.extend_from_slice(&good[nul..]);
        b
    };
    let mut cases: Vec<(String, Vec<u8>, &str)> = vec![
        ("no NUL".into(), good[..nul].to_vec(), "NUL"),
        ("bad JSON".into(), with("{not json"), "not JSON"),
        (
            "WebP".into(),
            with(&manifest.replace("image/png", "image/webp")),
            "image/webp",
        ),
        (
            "version 3".into(),
            with(&manifest.replace("\"version\":2", "\"version\":3")),
            "version 3",
        ),
        (
            "width 8".into(),
            with(&manifest.replace("\"width\":4", "\"width\":8")),
            "lists 18 images",
        ),
    ];
    for cut in [9, nul + 1, nul + 40, good.len() - 1] {
        cases.push((format!("cut at {cut}"), good[..cut].to_vec(), ""));
    }
    let mut corrupt = good.clone();
    for b in &mut corrupt[nul + 20..nul + 60] {
        *b ^= 0x5A;
    }
    cases.push(("corrupt PNG".into(), corrupt, "level 0 face 0"));
    for (name, bytes, want) in cases {
        let e = texture::decode(env_path(), &bytes, u64::MAX)
            .err()
            .unwrap_or_else(|| panic!("{name}: read"))
            .to_string();
        assert!(e.starts_with("t.env: "), "{name}: {e}");
        assert!(e.contains(want), "{name}: {e}");
    }
    // A texture over the limit is refused before its images are decoded.
    let e = texture::decode(env_path(), &good, 10)
        .unwrap_err()
        .to_string();
    assert!(e.contains("10"), "{e}");
}

fn gltf_path() -> &'static Path {
    Path::new("t.gltf")
}

/// The glTF light: one `EXT_lights_image_based` light selected by the
/// scene, `6·(log2 w + 1)` PNG images inside as `data:` URIs, nine
/// irradiance coefficients; read back, every texel is within the
/// precision of RGBD of c^(1/2.2) raised to 2.2 again (twice RGBD's
/// relative step, 1.32 % above 1) of what was written.
#[test]
fn a_gltf_light_is_laid_out_for_babylons_loader_and_read_back() {
    let tex = chain(16);
    let path = gltf_path();
    let (bytes, clamped) = texture::encode(&tex, path, TextureOptions::default()).unwrap();
    assert!(clamped.is_empty(), "{clamped:?}");
    let doc: serde_json::Value = serde_json::from_slice(&bytes).unwrap();
    assert_eq!(doc["asset"]["version"], "2.0");
    assert_eq!(doc["extensionsUsed"][0], "EXT_lights_image_based");
    assert_eq!(
        doc["scenes"][0]["extensions"]["EXT_lights_image_based"]["light"],
        0
    );
    let light = &doc["extensions"]["EXT_lights_image_based"]["lights"][0];
    assert_eq!(light["specularImageSize"], 16);
    assert_eq!(light["specularImages"].as_array().unwrap().len(), 5);
    assert_eq!(light["irradianceCoefficients"].as_array().unwrap().len(), 9);
    let images = doc["images"].as_array().unwrap();
    assert_eq!(images.len(), 6 * 5);
    assert!(images.iter().all(|i| i["uri"]
        .as_str()
        .unwrap()
        .starts_with("data:image/png;base64,")));
    let back = texture::decode(path, &bytes, u64::MAX).unwrap();
    assert_eq!(back.info.container, "glTF (EXT_lights_image_based)");
    assert_eq!(back.texture.level_count(), 5);
    // RGBD of c^(1/2.2): the 8-bit gamma is 2.2·2.2 = 4.84.
    assert_within_rgbd(&tex, &back.texture, 4.84);
}

/// A glTF file envmap cannot read is an error naming it and the problem.
#[test]
fn damaged_gltf_files_are_errors_naming_the_file() {
    let (good, _) = texture::encode(&chain(4), gltf_path(), TextureOptions::default()).unwrap();
    let good = String::from_utf8(good).unwrap();
    let first = good.find("data:image/png;base64,").unwrap();
    let cases = [
        ("not JSON", format!("{}x", &good[..good.len() - 1]), "JSON"),
        (
            "no light",
            good.replace("\"lights\"", "\"lamps\""),
            "no EXT_lights_image_based light",
        ),
        (
            "size 8",
            good.replace("\"specularImageSize\":4", "\"specularImageSize\":8"),
            "3 specular levels",
        ),
        (
            "outside file",
            format!("{}face.png{}", &good[..first], &good[first + 22..]),
            "outside files",
        ),
        (
            "bad base64",
            format!("{}!!!!{}", &good[..first + 22], &good[first + 26..]),
            "base64",
        ),
    ];
    for (name, text, want) in cases {
        let e = texture::decode(gltf_path(), text.as_bytes(), u64::MAX)
            .err()
            .unwrap_or_else(|| panic!("{name}: read"))
            .to_string();
        assert!(e.starts_with("t.gltf: "), "{name}: {e}");
        assert!(e.contains(want), "{name}: {e}");
    }
}
