//! The lighting bake of a 4096×2048 latlong (the smooth test environment,
//! already in memory): the default 512² GGX specular chain (linear rule,
//! nine levels down to 2², default quality), the SH9, the 32² irradiance
//! cube and the 128² DFG table, on two threads; and the chain alone; that
//! chain encoded in BC6H at each quality (beside the bake that made it); the
//! same bake of that map with a 0.5° sun of 100 000 ([`small_sun`]); and
//! the exact mode of a 64² chain from a 256² cube; and what `envmap render
//! --material` bakes from the smooth map on the fly, beside a plain mip
//! chain of the same size.
//!
//! ```text
//! RUSTFLAGS="-C target-cpu=native" cargo bench -p envmap-bench --bench bake
//! ```

mod common;

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use envmap_core::AnyMapping;
use envmap_render::filter::bake::{bake, specular_chain, BakeOptions};
use envmap_render::image::texture::Texture;
use envmap_render::image::{Bc6hQuality, FileAxes, Representation, TexelFormat};
use envmap_render::scene::LitEnvironment;
use envmap_render::scene::{fill, small_sun, smooth};

fn bench(c: &mut Criterion) {
    let pool = common::pool(2);
    let src = fill(
        Representation::default_for(AnyMapping::LatLong),
        4096,
        2048,
        smooth,
    )
    .unwrap();
    let mut g = c.benchmark_group("bake/latlong4096");
    g.sample_size(10);
    let opts = BakeOptions::default();
    g.bench_function("chain512+sh9+irradiance32+dfg128/2-threads", |b| {
        b.iter(|| pool.install(|| bake(black_box(&src), &opts, &|_, _| {}).expect("bake")))
    });
    g.bench_function("chain512/2-threads", |b| {
        b.iter(|| {
            pool.install(|| specular_chain(black_box(&src), &opts, &|_, _| {}).expect("chain"))
        })
    });
    // The chain above, encoded in BC6H (every level, every face) at each
    // quality: against the bake in the same run.
    let chain = pool.install(|| specular_chain(&src, &opts, &|_, _| {}).expect("chain"));
    let tex = Texture::from_env(&chain.levels).expect("texture");
    for q in Bc6hQuality::ALL {
        g.bench_function(format!("bc6h-{}-chain512/2-threads", q.name()), |b| {
            b.iter(|| pool.install(|| black_box(&tex).upload_at(TexelFormat::Bc6h, q)))
        });
    }
    g.finish();

    // What `envmap render --material` bakes on the fly at its default
    // `--bake-size 256` (`LitEnvironment::bake`: levels spaced by their
    // lobes, a 128² DFG table on the edges grid), beside a plain mip chain
    // (the linear rule down to 2², a 64² DFG table at texel centres), both
    // with a 32² irradiance map.
    let mut g = c.benchmark_group("bake/render-latlong4096");
    g.sample_size(10);
    let before = {
        let mut o = BakeOptions::default();
        o.size = 256;
        o.dfg_size = 64;
        o
    };
    g.bench_function("mip-chain256+dfg64/2-threads", |b| {
        b.iter(|| {
            pool.install(|| LitEnvironment::bake_with(black_box(&src), &before).expect("bake"))
        })
    });
    g.bench_function("envmap-chain256+dfg128-edges/2-threads", |b| {
        b.iter(|| pool.install(|| LitEnvironment::bake(black_box(&src), 256, None).expect("bake")))
    });
    g.finish();

    let sun = fill(
        Representation::default_for(AnyMapping::LatLong),
        4096,
        2048,
        small_sun,
    )
    .unwrap();
    let mut g = c.benchmark_group("bake/latlong4096-sun");
    g.sample_size(10);
    g.bench_function("chain512+sh9+irradiance32+dfg128/2-threads", |b| {
        b.iter(|| pool.install(|| bake(black_box(&sun), &opts, &|_, _| {}).expect("bake")))
    });
    g.finish();

    let cube = fill(
        Representation::for_file(AnyMapping::Cube, FileAxes::default()),
        4 * 256,
        3 * 256,
        smooth,
    )
    .unwrap();
    let mut g = c.benchmark_group("bake/exact-cube256");
    g.sample_size(10);
    let exact = {
        let mut o = BakeOptions::default();
        o.size = 64;
        o.exact = true;
        o
    };
    g.bench_function("chain64/2-threads", |b| {
        b.iter(|| {
            pool.install(|| specular_chain(black_box(&cube), &exact, &|_, _| {}).expect("chain"))
        })
    });
    g.finish();
}

criterion_group! {
    name = benches;
    config = common::config();
    targets = bench
}
criterion_main!(benches);
