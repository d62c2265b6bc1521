//! Irradiance speed: the SH9 projection of a 4096×2048 latlong (the smooth
//! test environment, f32 RGB, 100 MB) on one and on two threads, beside a
//! plain copy of the input's bytes (the memory floor), and of a 6×1024²
//! cube on two threads; then the 32² irradiance cube from the SH, and by
//! exact cosine convolution over the input's pyramid (the automatic level
//! rule at its default tolerance, which takes the 128 × 64 level of this
//! map, and the 512 × 256 level alone), on two threads.
//!
//! ```text
//! RUSTFLAGS="-C target-cpu=native" cargo bench -p envmap-bench --bench sh
//! ```

mod common;

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use envmap_core::{AnyMapping, Atlas, Frame};
use envmap_render::filter::pyramid::Pyramid;
use envmap_render::filter::sh::{
    default_irradiance_representation, irradiance_cube, irradiance_map_exact, ExactLevel,
    IrradianceScale, Sh9,
};
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
    let mut g = c.benchmark_group("sh/project-latlong4096");
    g.sample_size(20);
    g.throughput(Throughput::Elements(4096 * 2048));
    let mut copy = vec![[0.0f32; 3]; src.pixels().len()];
    g.bench_function("copy-input", |b| {
        b.iter(|| copy.copy_from_slice(black_box(src.pixels())))
    });
    for threads in [1, 2] {
        let p = common::pool(threads);
        g.bench_function(format!("sh9/{threads}-threads"), |b| {
            b.iter(|| p.install(|| Sh9::project(black_box(&src))))
        });
    }
    g.finish();

    let cube_repr = Representation::new(
        AnyMapping::Cube,
        Atlas::CUBE_HORIZONTAL_STRIP,
        Frame::Y_UP_RH,
    )
    .unwrap();
    let cube = fill(cube_repr, 6 * 1024, 1024, smooth).unwrap();
    let mut g = c.benchmark_group("sh/project-cube1024");
    g.sample_size(20);
    g.throughput(Throughput::Elements(6 * 1024 * 1024));
    let p2 = common::pool(2);
    g.bench_function("sh9/2-threads", |b| {
        b.iter(|| p2.install(|| Sh9::project(black_box(&cube))))
    });
    g.finish();

    let sh = Sh9::project(&src);
    let pyramid = Pyramid::new(src, 1).unwrap();
    let out = default_irradiance_representation();
    let mut g = c.benchmark_group("sh/irradiance-cube32");
    g.sample_size(10);
    g.throughput(Throughput::Elements(6 * 32 * 32));
    g.bench_function("from-sh/2-threads", |b| {
        b.iter(|| p2.install(|| irradiance_cube(black_box(&sh), IrradianceScale::EOverPi)))
    });
    for (name, level) in [
        ("exact-auto", ExactLevel::default()),
        ("exact-512x256", ExactLevel::Level(3)),
    ] {
        g.bench_function(format!("{name}/2-threads"), |b| {
            b.iter(|| {
                p2.install(|| {
                    irradiance_map_exact(
                        black_box(&pyramid),
                        out,
                        128,
                        96,
                        IrradianceScale::EOverPi,
                        level,
                    )
                    .unwrap()
                })
            })
        });
    }
    g.finish();
}

criterion_group! {
    name = benches;
    config = common::config();
    targets = bench
}
criterion_main!(benches);
