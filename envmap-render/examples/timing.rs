//! Times one conversion, latlong 4096×2048 → cube 6×1024² (a horizontal
//! strip), one sample per texel unless `SAMPLES` says otherwise, into a reused
//! output image:
//!
//! ```text
//! cargo run --release -p envmap-render --example timing [nearest] [latlong] [zero]
//! ```
//!
//! `nearest` uses the nearest filter instead of bilinear; `latlong` converts
//! into a latlong of the input's size instead of the cube; `zero` reads a
//! never-written (all-zero) input, whose pages are all the one zero page, so
//! the difference from a real input is the time spent waiting for memory. Prints the median
//! and minimum of `ITERS` runs (default 10). `RAYON_NUM_THREADS` sets the
//! thread count, `EDGE` the cube's face edge (default 1024) and `SAMPLES`
//! the sub-samples per texel side (default 1; `auto` or any other word for
//! the automatic choice).
use std::time::Instant;

use envmap_core::{AnyMapping, Atlas, Frame};
use envmap_render::filter::sample::Filter;
use envmap_render::filter::{convert_into, ConvertOptions};
use envmap_render::image::{EnvImage, Representation};
use envmap_render::scene::{fill, smooth};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let has = |a: &str| args.iter().any(|x| x == a);
    let filter = if has("nearest") {
        Filter::Nearest
    } else {
        Filter::Bilinear
    };
    let to_latlong = has("latlong");
    let iters: usize = std::env::var("ITERS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(10)
        .max(1);
    let latlong = Representation::default_for(AnyMapping::LatLong);
    let src = if has("zero") {
        EnvImage::new(4096, 2048, latlong)
    } else {
        fill(latlong, 4096, 2048, smooth)
    }
    .expect("the input fits the size limit");
    let (repr, w, h) = if to_latlong {
        (latlong, 4096, 2048)
    } else {
        let strip = Atlas::CUBE_HORIZONTAL_STRIP;
        let repr = Representation::new(AnyMapping::Cube, strip, Frame::IDENTITY)
            .expect("the strip is a cube layout");
        let e: u32 = std::env::var("EDGE")
            .ok()
            .and_then(|v| v.parse().ok())
            .unwrap_or(1024);
        (repr, 6 * e, e)
    };
    let mut out = EnvImage::new(w, h, repr).expect("the output fits the size limit");
    let opts = {
        let mut o = ConvertOptions::default();
        o.filter = filter;
        o.samples = match std::env::var("SAMPLES") {
            Ok(v) => v.parse().ok(),
            Err(_) => Some(1),
        };
        o.rotation = None;
        o.cancel = None;
        o
    };
    let mut ms: Vec<f64> = (0..iters)
        .map(|_| {
            let t = Instant::now();
            convert_into(&src, &mut out, &opts, None).expect("conversion");
            t.elapsed().as_secs_f64() * 1e3
        })
        .collect();
    ms.sort_by(f64::total_cmp);
    println!(
        "{filter:?} latlong 4096×2048 -> {} {w}×{h}: median {:.1} ms, min {:.1} ms ({iters} runs)",
        repr.mapping,
        ms[ms.len() / 2],
        ms[0]
    );
}
