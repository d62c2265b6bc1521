//! What BC6H costs a baked chain: for each HDRI, the 512² specular chain of
//! `envmap bake --target bevy`, encoded at every quality by envmap's encoder
//! (`block_compression`, a Rust port of Intel's ISPC kernel) and, for
//! comparison, by Intel's ISPC kernel itself (`intel_tex_2`, prebuilt);
//! every level decoded by `bcdec_rs` (envmap's decoder, independent of
//! both encoders) and measured
//! against the uncompressed level: relative RMS (%), per level, and the
//! encoding time of the whole chain on all threads beside the bake's.
//!
//! ```text
//! cargo run --release -p envmap-bench --bin envmap-bc6h [-- [--size N] [--quick] FILE.exr ...]
//! ```
//!
//! With no file, the committed HDRIs in `test-data/hdri`. `--quick`: the
//! fastest and default qualities only.

use std::path::PathBuf;
use std::time::Instant;

use envmap_render::bake::{Baker, Target};
use envmap_render::image::texture::Texture;
use envmap_render::image::{load, Bc6hQuality, LoadOptions, RgbImage, TexelFormat};
use envmap_render::instruments::lossy_level_error;
use rayon::prelude::*;

// intel_tex_2's prebuilt kernels include C++ (its ASTC part), which needs
// the C++ runtime at link time.
#[link(name = "stdc++")]
extern "C" {}

/// A face encoded by Intel's kernel (`intel_tex_2`): binary16 RGBA padded
/// to whole blocks by repeating the last row and column, rows of blocks
/// in parallel.
fn intel(face: &RgbImage, settings: &intel_tex_2::bc6h::EncodeSettings) -> Vec<u8> {
    let (w, h) = (face.width as usize, face.height as usize);
    let w4 = w.div_ceil(4) * 4;
    let rows = h.div_ceil(4);
    (0..rows)
        .into_par_iter()
        .flat_map_iter(|by| {
            let mut strip = vec![0u8; w4 * 4 * 8];
            for y in 0..4 {
                let sy = (by * 4 + y).min(h - 1);
                for x in 0..w4 {
                    let t = face.pixels[sy * w + x.min(w - 1)];
                    let at = (y * w4 + x) * 8;
                    for k in 0..4 {
                        let v = if k == 3 {
                            1.0
                        } else {
                            t[k].clamp(0.0, 65504.0)
                        };
                        let b = half::f16::from_f32(v).to_le_bytes();
                        strip[at + 2 * k..at + 2 * k + 2].copy_from_slice(&b);
                    }
                }
            }
            let surface = intel_tex_2::RgbaSurface {
                data: &strip,
                width: w4 as u32,
                height: 4,
                stride: (w4 * 8) as u32,
            };
            intel_tex_2::bc6h::compress_blocks(settings, &surface)
        })
        .collect()
}

fn intel_settings(q: Bc6hQuality) -> intel_tex_2::bc6h::EncodeSettings {
    use intel_tex_2::bc6h::*;
    match q {
        Bc6hQuality::VeryFast => very_fast_settings(),
        Bc6hQuality::Fast => fast_settings(),
        Bc6hQuality::Basic => basic_settings(),
        Bc6hQuality::Slow => slow_settings(),
        Bc6hQuality::VerySlow => very_slow_settings(),
    }
}

/// Each level's (relative RMS, log RMSE, worst) of `faces` (per level, per
/// face, the blocks) against `tex`, measured as a bake's manifest measures
/// BC6H (`instruments::lossy_level_error`, the reference clamped to
/// [0, 65504] as the encoders clamp it).
fn level_errors(tex: &Texture, faces: &[Vec<Vec<u8>>]) -> Vec<(f64, f64, f64)> {
    tex.levels()
        .iter()
        .zip(faces)
        .map(|(level, blocks)| {
            let decoded: Vec<RgbImage> = level
                .iter()
                .zip(blocks)
                .map(|(f, b)| RgbImage {
                    width: f.width,
                    height: f.height,
                    pixels: TexelFormat::Bc6h.unpack_image(b, (f.width, f.height)),
                })
                .collect();
            lossy_level_error(&decoded, level, TexelFormat::Bc6h.max_value())
        })
        .collect()
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut size = 512u32;
    let mut quick = false;
    let mut files: Vec<PathBuf> = Vec::new();
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        match a.as_str() {
            "--size" => size = args.next().ok_or("--size N")?.parse()?,
            "--quick" => quick = true,
            _ => files.push(a.into()),
        }
    }
    if files.is_empty() {
        let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../test-data/hdri");
        let mut v: Vec<PathBuf> = std::fs::read_dir(&dir)?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|e| e == "exr" || e == "hdr"))
            .collect();
        v.sort();
        files = v;
    }
    let qualities: Vec<Bc6hQuality> = if quick {
        vec![Bc6hQuality::VeryFast, Bc6hQuality::Basic]
    } else {
        Bc6hQuality::ALL.to_vec()
    };
    println!(
        "BC6H of the {size}² chain of `envmap bake --target bevy`, {} threads; relative RMS (%) per level, decoded by bcdec_rs",
        rayon::current_num_threads()
    );
    for file in &files {
        let src = load(file, &LoadOptions::default())?;
        let t = Instant::now();
        let baked = Baker::for_target(Target::Bevy).size(size).bake(&src)?;
        let bake_s = t.elapsed().as_secs_f64();
        let chain = baked.bake().chain.as_ref().ok_or("no chain")?;
        let tex = Texture::from_env(&chain.levels)?;
        println!(
            "\n{}: bake {bake_s:.3} s, {} levels",
            file.display(),
            tex.level_count()
        );
        for q in &qualities {
            let t = Instant::now();
            let up = tex.upload_at(TexelFormat::Bc6h, *q);
            let ours_s = t.elapsed().as_secs_f64();
            let ours: Vec<Vec<Vec<u8>>> = up.levels.into_iter().map(|l| l.faces).collect();
            let settings = intel_settings(*q);
            let t = Instant::now();
            let theirs: Vec<Vec<Vec<u8>>> = tex
                .levels()
                .iter()
                .map(|l| l.iter().map(|f| intel(f, &settings)).collect())
                .collect();
            let intel_s = t.elapsed().as_secs_f64();
            for (name, secs, blocks) in [
                ("block_compression", ours_s, &ours),
                ("intel_tex_2", intel_s, &theirs),
            ] {
                let e = level_errors(&tex, blocks);
                let levels: Vec<String> =
                    e.iter().map(|x| format!("{:5.2}", 100.0 * x.0)).collect();
                let worst_level = e.iter().map(|x| x.0).fold(0.0, f64::max);
                println!(
                    "  {name:17} {:9} {secs:7.3} s  max {:5.2} %  levels {}",
                    q.name(),
                    100.0 * worst_level,
                    levels.join(" ")
                );
            }
        }
    }
    Ok(())
}
