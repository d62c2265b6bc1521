//! A bake measured against the input itself: every level of the specular
//! chain, the irradiance map and the SH9 against the oracle
//! ([`envmap_render::instruments`]: the input as loaded, piecewise
//! constant over its own texels, never the bake's base cube or pyramid):
//! relative RMS error and bias per level, on a subset of each level's texels.
//!
//! ```text
//! cargo run --release -p envmap-render --example bake_accuracy -- IN|sky|room|smooth|smooth-sun|small-sun [SIZE] [TEXELS]
//! ```
//!
//! SIZE is level 0's face (default 512), TEXELS the texels checked per
//! level (default 1536, spread over the six faces by a fixed hash).
//! Environment variables:
//!
//! * `CONVERGE=1`: the oracle again at half its tolerance; prints the
//!   largest change of any level's error (the oracle's own convergence).
//! * `CHAIN=DIR`: measure a chain made elsewhere instead of baking: DIR holds
//!   `levels.txt` (lines `k size roughness`) and `level<k>.exr` (cubes in
//!   envmap's default axes), as `envmap-bench/scripts/cmgen-chain.sh` writes.
//! * `SAMPLES=N`: samples per texel at every sampled level.
//! * `WRITE=FILE`: save the input (e.g. `smooth`, `small-sun`: the
//!   benchmark's 4096 × 2048 maps) to FILE and exit, for whole-process
//!   timings.
//! * `EXACT=1`: the bake's `--exact` mode (slow at large sizes).
//! * `LOD_BIAS=B`: the sampled levels' FIS level bias.
//! * `SPLIT=N`: at most N texels split (`--split`).
use std::time::Instant;

use envmap_core::{AnyMapping, Atlas, Mapping};
use envmap_render::filter::bake::{bake, measure_irradiance, measure_level, BakeOptions};
use envmap_render::filter::sh::IrradianceScale;
use envmap_render::image::{load, LoadOptions, NonFinite};
use envmap_render::image::{EnvImage, FileAxes, Representation};
use envmap_render::instruments::Oracle;
use envmap_render::scene::Builtin;
use envmap_render::scene::{fill, small_sun, smooth, sunny};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let input = args.get(1).map_or("sky", String::as_str);
    let size: u32 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(512);
    let per_level: u32 = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(1536);
    let cube = Representation::new(
        AnyMapping::Cube,
        Atlas::CUBE_HORIZONTAL_STRIP,
        FileAxes::default().frame(AnyMapping::Cube),
    )
    .unwrap();
    let latlong = Representation::default_for(AnyMapping::LatLong);
    let src = match input {
        "sky" | "room" => {
            let b: Builtin = input.parse().unwrap();
            b.image(cube, 6 * 1024, 1024).unwrap()
        }
        "smooth" => fill(latlong, 4096, 2048, smooth).unwrap(),
        "smooth-sun" => fill(latlong, 4096, 2048, sunny).unwrap(),
        "small-sun" => fill(latlong, 4096, 2048, small_sun).unwrap(),
        path => load(path, &{
            let mut o = LoadOptions::default();
            o.non_finite = NonFinite::Zero;
            o
        })
        .unwrap_or_else(|e| panic!("{path}: {e}")),
    };
    if let Ok(out) = std::env::var("WRITE") {
        envmap_render::image::save(&src, std::path::Path::new(&out), &Default::default())
            .unwrap_or_else(|e| panic!("{out}: {e}"));
        println!("wrote {out}");
        return;
    }
    let t = Instant::now();
    let oracle = Oracle::new(&src);
    println!(
        "{input}: {}×{} {}, oracle built in {:.2} s (tolerance {})",
        src.width(),
        src.height(),
        src.mapping().name(),
        t.elapsed().as_secs_f64(),
        oracle.tolerance()
    );
    let finer = std::env::var("CONVERGE")
        .is_ok()
        .then(|| Oracle::new(&src).with_tolerance(oracle.tolerance() / 2.0));

    // The levels to measure: (k, roughness, image).
    let mut levels = Vec::new();
    let mut summary_extra = String::new();
    let mut irradiance = None;
    if let Ok(dir) = std::env::var("CHAIN") {
        let list = std::fs::read_to_string(format!("{dir}/levels.txt"))
            .unwrap_or_else(|e| panic!("{dir}/levels.txt: {e}"));
        for line in list.lines().filter(|l| !l.trim().is_empty()) {
            let f: Vec<&str> = line.split_whitespace().collect();
            let k: usize = f[0].parse().unwrap();
            let r: f32 = f[2].parse().unwrap();
            let path = format!("{dir}/level{k}.exr");
            let img =
                load(&path, &LoadOptions::default()).unwrap_or_else(|e| panic!("{path}: {e}"));
            let (w, h) = (img.width(), img.height());
            let img = EnvImage::from_pixels(w, h, img.into_pixels(), cube)
                .unwrap_or_else(|e| panic!("{path}: {e}"));
            levels.push((k, r, "external", 0, img));
        }
        println!("chain from {dir}: {} levels", levels.len());
    } else {
        let opts = {
            let mut o = BakeOptions::default();
            o.size = size;
            o.samples = std::env::var("SAMPLES").ok().map(|s| s.parse().unwrap());
            o.exact = std::env::var("EXACT").is_ok();
            o.bright_max = std::env::var("SPLIT").map_or(16384, |s| s.parse().unwrap());
            o.lod_bias = std::env::var("LOD_BIAS").map_or(0.0, |s| s.parse().unwrap());
            o
        };
        let t = Instant::now();
        let b = bake(&src, &opts, &|_, _| {}).unwrap();
        let secs = t.elapsed().as_secs_f64();
        let chain = b.chain.unwrap();
        println!(
            "baked in {secs:.2} s: base {}², {} bright texels ({} points, {:.2} % of the energy)",
            chain.base_size,
            chain.bright.texels,
            chain.bright.points,
            100.0 * chain.bright.energy_share,
        );
        let e = &chain.energy;
        summary_extra = format!(
            "; split {} texels, {:.2} % of the energy; negative share R {:.3} % G {:.3} % B {:.3} %; bake {secs:.2} s",
            chain.bright.texels,
            100.0 * chain.bright.energy_share,
            100.0 * e.negative_share()[0],
            100.0 * e.negative_share()[1],
            100.0 * e.negative_share()[2],
        );
        println!(
            "energy per channel: input {:?}, base {:?}, split {:?}: gap {:.2e} (footprint {}×{}); negative share {:?}",
            e.input.map(|v| (v * 1e4).round() / 1e4),
            e.base.map(|v| (v * 1e4).round() / 1e4),
            e.split.map(|v| (v * 1e4).round() / 1e4),
            e.gap(),
            e.footprint_samples,
            e.footprint_samples,
            e.negative_share().map(|v| (v * 1e5).round() / 1e5),
        );
        for (k, (img, rep)) in chain.levels.into_iter().zip(&chain.reports).enumerate() {
            levels.push((k, rep.roughness, rep.method, rep.samples, img));
        }
        irradiance = b
            .irradiance
            .map(|i| (i.method, i.image, opts.irradiance_scale));
        let sh = oracle.sh9(2);
        let (mut se, mut ss) = (0.0, 0.0);
        for (a, e) in b.sh.coeffs.iter().zip(&sh.coeffs) {
            for (x, y) in a.iter().zip(e) {
                se += (x - y) * (x - y);
                ss += y * y;
            }
        }
        println!(
            "SH9 against the oracle (texels split 2×2): {:.2e} relative",
            (se / ss).sqrt()
        );
    }
    println!("| level | size | roughness | method | samples | rel. RMS | bias | oracle (s) |");
    println!("| ---: | ---: | ---: | --- | ---: | ---: | ---: | ---: |");
    let mut worst_change = 0.0f64;
    // The worst level by relative RMS and by |bias|: (value, level).
    let (mut worst_rms, mut worst_bias) = ((0.0f64, 0usize), (0.0f64, 0usize));
    for (k, r, method, samples, img) in &levels {
        if *r <= 0.0 {
            continue;
        }
        let m = measure_level(&oracle, *r, img, per_level, *k as u32).unwrap();
        println!(
            "| {k} | {} | {r:.3} | {method} | {samples} | {:.3} % | {:+.3} % | {:.2} |",
            img.cell_size().0,
            100.0 * m.relative_rms,
            100.0 * m.bias,
            m.seconds
        );
        if m.relative_rms > worst_rms.0 {
            worst_rms = (m.relative_rms, *k);
        }
        if m.bias.abs() > worst_bias.0.abs() {
            worst_bias = (m.bias, *k);
        }
        if let Some(f) = &finer {
            let m2 = measure_level(f, *r, img, per_level, *k as u32).unwrap();
            worst_change = worst_change
                .max((m2.relative_rms - m.relative_rms).abs())
                .max((m2.bias - m.bias).abs());
        }
    }
    if let Some((method, map, scale)) = &irradiance {
        let m = measure_irradiance(&oracle, map, *scale, per_level, 99);
        let what = match scale {
            IrradianceScale::E => "E",
            IrradianceScale::EOverPi => "E/π",
        };
        println!(
            "irradiance ({method}, {what}, {}²): {:.3} % relative RMS, bias {:+.3} %",
            map.cell_size().0,
            100.0 * m.relative_rms,
            100.0 * m.bias
        );
    }
    println!(
        "summary: worst level {:.3} % RMS (level {}), worst bias {:+.3} % (level {}){}",
        100.0 * worst_rms.0,
        worst_rms.1,
        100.0 * worst_bias.0,
        worst_bias.1,
        summary_extra
    );
    if finer.is_some() {
        println!(
            "oracle convergence: at half the tolerance every level's error moves by at most {:.4} %",
            100.0 * worst_change
        );
    }
}
