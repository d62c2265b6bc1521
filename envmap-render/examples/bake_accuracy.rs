//! The specular chain of a real-size bake against the exact integral, on
//! a subset of each level's texels (the exact sum over the 1024² base for
//! every texel of a 512² chain would take hours): relative RMS error and
//! bias per level, for each sample count asked.
//!
//! ```text
//! cargo run --release -p envmap-render --example bake_accuracy -- IN|sky|room [SIZE] [TEXELS]
//! ```
//!
//! SIZE is level 0's face (default 512), TEXELS the texels checked per
//! level (default 600, spread over the six faces by a fixed hash).
//! `SAMPLES` (comma-separated) sets the counts tried at every level
//! (default: the bake's own choice).
use std::time::Instant;

use envmap_core::{AnyMapping, Atlas};
use envmap_render::convert::{convert, ConvertOptions};
use envmap_render::environments::Builtin;
use envmap_render::filter::bake::{chain_sizes, measure_level, BakeOptions};
use envmap_render::filter::pyramid::{Pyramid, Trilinear};
use envmap_render::filter::specular::{
    exact_level, prefilter_level, split_bright, LevelJob, Method,
};
use envmap_render::image::{FileAxes, Representation};
use envmap_render::io::{load, LoadOptions, NonFinite};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let input = args.get(1).map_or("sky", String::as_str);
    let size: u32 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(512);
    let per_level: u32 = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(600);
    let cube = Representation::new(
        AnyMapping::Cube,
        Atlas::CUBE_HORIZONTAL_STRIP,
        FileAxes::default().frame(AnyMapping::Cube),
    )
    .unwrap();
    let src = match input {
        "sky" | "room" => {
            let b: Builtin = input.parse().unwrap();
            b.image(cube, 6 * 1024, 1024).unwrap()
        }
        path => load(
            path,
            &LoadOptions {
                non_finite: NonFinite::Zero,
                ..LoadOptions::default()
            },
        )
        .unwrap(),
    };
    let opts = BakeOptions {
        size,
        ..BakeOptions::default()
    };
    let sizes = chain_sizes(&opts).unwrap();
    let t = Instant::now();
    let mut base = convert(&src, cube, 6 * 1024, 1024, &ConvertOptions::default(), None).unwrap();
    let bright = split_bright(&mut base, opts.bright_max).unwrap();
    let rest = Pyramid::new(base, 1).unwrap();
    let sampler = Trilinear::new(&rest);
    println!(
        "{input}: base 6×1024², {} bright texels ({:.2} % of the energy), prepared in {:.2} s",
        bright.report.texels,
        100.0 * bright.report.energy_share,
        t.elapsed().as_secs_f64()
    );
    let sweep: Option<Vec<u32>> = std::env::var("SAMPLES")
        .ok()
        .map(|v| v.split(',').map(|s| s.parse().unwrap()).collect());
    println!(
        "| level | size | roughness | samples | rel. RMS | bias | sampled (s) | exact level |"
    );
    println!("| ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |");
    for (k, &s) in sizes.iter().enumerate().skip(1) {
        let r = opts.rule.roughness(k, sizes.len());
        let el = exact_level(&rest, r);
        let counts = sweep
            .clone()
            .unwrap_or_else(|| vec![opts.quality.samples(r)]);
        for n in counts {
            let t = Instant::now();
            let job = LevelJob {
                rest: &rest,
                sampler: &sampler,
                bright: &bright,
                roughness: r,
                method: Method::Sampled { samples: n },
                lod_bias: opts.lod_bias,
                level: k as u32,
                cancel: None,
            };
            let img = prefilter_level(&job, cube, 6 * s, s).unwrap();
            let secs = t.elapsed().as_secs_f64();
            let m = measure_level(&rest, &bright, r, &img, per_level, k as u32).unwrap();
            println!(
                "| {k} | {s} | {r:.3} | {n} | {:.3} % | {:+.3} % | {secs:.3} | {el} |",
                100.0 * m.relative_rms,
                100.0 * m.bias
            );
        }
    }
}
