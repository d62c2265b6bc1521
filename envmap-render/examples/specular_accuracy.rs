//! The sampled specular levels against the exact sum, level by level:
//! relative RMS error and bias (mean signed error over mean) for a source
//! environment, over a range of sample counts and FIS biases.
//!
//! ```text
//! cargo run --release -p envmap-render --example specular_accuracy [sky|room|smooth] [BASE] [OUT]
//! ```
//!
//! BASE is the source cube's face (default 128), OUT the chain's level 0
//! (default 64). `SAMPLES` (comma-separated, default 64,256) and `BIAS`
//! (default 0,0.5,1) choose what to sweep.
use std::time::Instant;

use envmap_core::{AnyMapping, Atlas};
use envmap_render::filter::pyramid::Pyramid;
use envmap_render::filter::specular::{
    exact_level, prefilter_level, split_bright, LevelJob, Method, RoughnessRule,
};
use envmap_render::filter::{convert, ConvertOptions};
use envmap_render::image::{FileAxes, Representation};
use envmap_render::scene::Builtin;
use envmap_render::scene::{fill, smooth};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let env = args.get(1).map_or("smooth", String::as_str);
    let base: u32 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(128);
    let out: u32 = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(64);
    let list = |v: &str, d: &str| -> Vec<f32> {
        std::env::var(v)
            .unwrap_or_else(|_| d.to_owned())
            .split(',')
            .map(|s| s.parse().unwrap())
            .collect()
    };
    let sweep_n = list("SAMPLES", "64,256");
    let sweep_b = list("BIAS", "0,0.5,1");
    let ll = Representation::for_file(AnyMapping::LatLong, FileAxes::default());
    let src = match env {
        "sky" => Builtin::Sky.image(ll, 8 * base, 4 * base).unwrap(),
        "room" => Builtin::Room.image(ll, 8 * base, 4 * base).unwrap(),
        _ => fill(ll, 8 * base, 4 * base, smooth).unwrap(),
    };
    let cube = Representation::new(
        AnyMapping::Cube,
        Atlas::CUBE_HORIZONTAL_STRIP,
        FileAxes::default().frame(AnyMapping::Cube),
    )
    .unwrap();
    let mut base_img =
        convert(&src, cube, 6 * base, base, &ConvertOptions::default(), None).unwrap();
    let bright = split_bright(&mut base_img, 4096, f64::INFINITY).unwrap();
    println!(
        "{env}: base 6×{base}², bright texels {} ({:.2} % of the energy, threshold {:.1})",
        bright.report.texels,
        100.0 * bright.report.energy_share,
        bright.report.threshold
    );
    let rest = Pyramid::new(base_img, 1).unwrap();
    let sampler = envmap_render::filter::pyramid::Trilinear::new(&rest);
    let levels = (out as f32).log2() as usize; // down to 2×2
    for k in 1..levels {
        let size = out >> k;
        let r = RoughnessRule::Linear.roughness(k, levels);
        let el = exact_level(&rest, r);
        let t = Instant::now();
        let job = LevelJob {
            rest: &rest,
            sampler: &sampler,
            bright: &bright,
            roughness: r,
            method: Method::Exact { level: el },
            lod_bias: 0.0,
            level: k as u32,
            cancel: None,
        };
        let exact = prefilter_level(&job, cube, 6 * size, size).unwrap();
        let te = t.elapsed().as_secs_f64();
        for &n in &sweep_n {
            for &b in &sweep_b {
                let t = Instant::now();
                let got = prefilter_level(
                    &LevelJob {
                        method: Method::Sampled { samples: n as u32 },
                        lod_bias: b,
                        ..job
                    },
                    cube,
                    6 * size,
                    size,
                )
                .unwrap();
                let ts = t.elapsed().as_secs_f64();
                let (mut se, mut ss, mut sd, mut sm) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
                for (a, e) in got.pixels().iter().zip(exact.pixels()) {
                    for c in 0..3 {
                        let d = f64::from(a[c]) - f64::from(e[c]);
                        se += d * d;
                        ss += f64::from(e[c]) * f64::from(e[c]);
                        sd += d;
                        sm += f64::from(e[c]);
                    }
                }
                println!(
                    "level {k} ({size}², r {r:.3}): exact at level {el} {te:.2} s | N {n:>5} bias {b:.1}: rel RMS {:.3} %, bias {:+.3} %, {ts:.3} s",
                    100.0 * (se / ss).sqrt(),
                    100.0 * sd / sm
                );
            }
        }
    }
}
