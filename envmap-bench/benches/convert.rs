//! Conversion speed: latlong 4096×2048 → cube 6×1024², bilinear, one sample
//! per texel, f32 RGB, on one and on two threads, beside a plain copy of the
//! input's bytes; on two threads also with a cancel flag given (never set),
//! which the conversion checks once per band of rows.
//!
//! ```text
//! RUSTFLAGS="-C target-cpu=native" cargo bench -p envmap-bench --bench convert
//! ```

mod common;

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use envmap_core::{AnyMapping, Atlas, Frame};
use envmap_render::filter::sample::Filter;
use envmap_render::filter::{convert, convert_into, ConvertOptions};
use envmap_render::image::Representation;
use envmap_render::scene::{fill, smooth};

fn bench(c: &mut Criterion) {
    let src = fill(
        Representation::default_for(AnyMapping::LatLong),
        4096,
        2048,
        smooth,
    )
    .unwrap();
    let repr = Representation::new(
        AnyMapping::Cube,
        Atlas::CUBE_HORIZONTAL_STRIP,
        Frame::IDENTITY,
    )
    .unwrap();
    let opts = {
        let mut o = ConvertOptions::default();
        o.filter = Filter::Bilinear;
        o.samples = Some(1);
        o.rotation = None;
        o.cancel = None;
        o
    };
    let mut g = c.benchmark_group("convert/latlong4096-cube1024");
    g.sample_size(20);
    g.throughput(Throughput::Elements(6 * 1024 * 1024));
    let mut copy = vec![[0.0f32; 3]; src.pixels().len()];
    g.bench_function("copy-input", |b| {
        b.iter(|| copy.copy_from_slice(black_box(src.pixels())))
    });
    // The conversion itself writes into a reused output image (as a tool
    // converting many maps would); "alloc" also makes a fresh output.
    let mut out = convert(&src, repr, 6144, 1024, &opts, None).unwrap();
    for threads in [1, 2] {
        let pool = common::pool(threads);
        g.bench_function(format!("bilinear/{threads}-threads"), |b| {
            b.iter(|| {
                pool.install(|| {
                    convert_into(black_box(&src), &mut out, &opts, None).expect("conversion")
                })
            })
        });
    }
    let pool = common::pool(2);
    let never = std::sync::atomic::AtomicBool::new(false);
    let with_flag = {
        let mut o = opts;
        o.cancel = Some(&never);
        o
    };
    g.bench_function("bilinear-cancel-flag/2-threads", |b| {
        b.iter(|| {
            pool.install(|| {
                convert_into(black_box(&src), &mut out, &with_flag, None).expect("conversion")
            })
        })
    });
    g.bench_function("bilinear-alloc/2-threads", |b| {
        b.iter(|| pool.install(|| convert(black_box(&src), repr, 6144, 1024, &opts, None).unwrap()))
    });
    g.finish();
}

criterion_group! {
    name = benches;
    config = common::config();
    targets = bench
}
criterion_main!(benches);
