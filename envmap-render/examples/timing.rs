//! Times one conversion: `cargo run --release -p envmap-render --example timing`.
use std::time::Instant;

use envmap_core::{AnyMapping, Atlas, Frame};
use envmap_render::convert::{convert, ConvertOptions};
use envmap_render::image::Representation;
use envmap_render::procedural::{fill, smooth};
use envmap_render::sample::Filter;

fn main() {
    let only_nearest = std::env::args().any(|a| a == "nearest");
    let sw: u32 = std::env::var("SRC_W")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(4096);
    let src = fill(
        Representation::default_for(AnyMapping::LatLong),
        sw,
        sw / 2,
        smooth,
    )
    .unwrap();
    let filters: &[Filter] = if only_nearest {
        &[Filter::Nearest]
    } else {
        &[Filter::Nearest, Filter::Bilinear]
    };
    for &filter in filters {
        for to in [AnyMapping::Cube, AnyMapping::LatLong] {
            let repr = if to == AnyMapping::Cube {
                Representation::new(to, Atlas::CUBE_HORIZONTAL_STRIP, Frame::IDENTITY).unwrap()
            } else {
                Representation::default_for(to)
            };
            let (w, h) = if to == AnyMapping::Cube {
                (6144, 1024)
            } else {
                (4096, 2048)
            };
            let opts = ConvertOptions {
                filter,
                samples: Some(1),
                rotation: None,
            };
            for _ in 0..if only_nearest { 6 } else { 2 } {
                let t = Instant::now();
                let out = convert(&src, repr, w, h, &opts, None).unwrap();
                println!(
                    "{filter:?} latlong -> {to}: {:.1} ms ({})",
                    t.elapsed().as_secs_f64() * 1e3,
                    out.pixels().len()
                );
            }
        }
    }
}
