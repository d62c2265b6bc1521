//! Render speed: a mirror teapot, per pixel and per vertex, in the built-in
//! sky stored as a 6×1024² cube map, 1920×1080, bilinear, one sample per
//! pixel, per pixel on one and two threads and per vertex on two, beside a
//! plain copy of the output image's bytes; per pixel with mip-aware lookups
//! on two threads (`per-pixel-mip`: the map's pyramid built inside each
//! render by a renderer reused from frame to frame, into the memory of the
//! levels it built for the previous one, and read trilinearly at each
//! reflection's footprint; `per-pixel-mip-prebuilt`: from levels made once;
//! `mip-levels`: the levels alone, into new memory, and
//! `mip-levels-rebuilt` into the memory of the last); and lit: glossy plastic at
//! roughness 0.5 by the split sum on two threads, from that sky's maps
//! (baked once, outside the timing): `plastic-r0.5-split-sum` reads the
//! mip chain `envmap bake` makes by default (512² down to 2², linear rule,
//! blended linearly as engines do, the 128² DFG table at texel centres),
//! `plastic-r0.5-envmap-chain` the chain envmap's renderer bakes
//! (`LitEnvironment::bake` at 512²: levels spaced by their lobes, blended
//! in 1/α, the DFG table on the edges grid), both with a 32² irradiance
//! map. Every case renders with one [`Renderer`] reused from iteration to
//! iteration, as a program drawing frame after frame does.
//!
//! ```text
//! RUSTFLAGS="-C target-cpu=native" cargo bench -p envmap-bench --bench render
//! ```

mod common;

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use envmap_core::AnyMapping;
use envmap_render::image::Representation;
use envmap_render::scene::Builtin;
use envmap_render::scene::Mesh;
use envmap_render::scene::{Camera, EnvSource, Mode, RenderOptions, Renderer};

fn bench(c: &mut Criterion) {
    let env = Builtin::Sky
        .image(Representation::default_for(AnyMapping::Cube), 4096, 3072)
        .unwrap();
    let mesh = Mesh::teapot(10);
    let cam = Camera::default();
    let (width, height) = (1920, 1080);
    let mut g = c.benchmark_group("render/teapot1920x1080-cube1024");
    g.sample_size(20);
    g.throughput(Throughput::Elements(u64::from(width * height)));
    let pixels = vec![[0.5f32; 3]; (width * height) as usize];
    let mut copy = pixels.clone();
    g.bench_function("copy-output", |b| {
        b.iter(|| copy.copy_from_slice(black_box(&pixels)))
    });
    // The mip levels made once, as a program rendering one map many times
    // would (the `per-pixel-mip` case builds them in every render).
    let levels = envmap_render::scene::MipLevels::new(&env).expect("mip levels");
    // What the `per-pixel-mip` case adds to the prebuilt one: the levels.
    let pool = common::pool(2);
    g.bench_function("mip-levels/2-threads", |b| {
        b.iter(|| {
            pool.install(|| envmap_render::scene::MipLevels::new(black_box(&env)).expect("levels"))
        })
    });
    // Levels made again for each render into the memory of the last
    // (`MipLevels::rebuild`), as for a map that changes between frames.
    let mut again = levels.clone();
    g.bench_function("mip-levels-rebuilt/2-threads", |b| {
        b.iter(|| pool.install(|| again.rebuild(black_box(&env)).expect("levels")))
    });
    for (name, mode, threads, mip, prebuilt) in [
        ("per-pixel", Mode::PerPixel, 1, false, false),
        ("per-pixel", Mode::PerPixel, 2, false, false),
        ("per-pixel-mip", Mode::PerPixel, 2, true, false),
        ("per-pixel-mip-prebuilt", Mode::PerPixel, 2, true, true),
        ("per-vertex", Mode::PerVertex, 2, false, false),
    ] {
        let pool = common::pool(threads);
        let opts = {
            let mut o = RenderOptions::default();
            o.width = width;
            o.height = height;
            o.mode = mode;
            o.samples = 1;
            o.mip = mip;
            o.mip_levels = prebuilt.then_some(&levels);
            o
        };
        let mut renderer = Renderer::new();
        g.bench_function(format!("{name}/{threads}-threads"), |b| {
            b.iter(|| {
                pool.install(|| {
                    renderer
                        .render(&mesh, EnvSource::Map(black_box(&env)), &cam, &opts)
                        .expect("render")
                })
            })
        });
    }
    // Lit: the split sum from the sky's bake, as engines read a mip chain
    // and as envmap's renderer reads its own.
    use envmap_render::filter::bake::BakeOptions;
    use envmap_render::scene::{LevelBlend, LitEnvironment};
    let mip = LitEnvironment::bake_with(&env, &BakeOptions::default())
        .expect("bake")
        .with_blend(LevelBlend::Roughness);
    let own = LitEnvironment::bake(&env, 512, None).expect("bake");
    let pool = common::pool(2);
    for (name, lit) in [
        ("plastic-r0.5-split-sum/2-threads", &mip),
        ("plastic-r0.5-envmap-chain/2-threads", &own),
    ] {
        let opts = {
            let mut o = RenderOptions::default();
            o.width = width;
            o.height = height;
            o.samples = 1;
            o.shading = envmap_render::scene::Shading::SplitSum {
                env: lit,
                material: envmap_render::scene::Material {
                    roughness: 0.5,
                    ..envmap_render::scene::Material::default()
                },
                multiscatter: false,
                dominant: true,
            };
            o
        };
        let mut renderer = Renderer::new();
        g.bench_function(name, |b| {
            b.iter(|| {
                pool.install(|| {
                    renderer
                        .render(&mesh, EnvSource::Map(black_box(&env)), &cam, &opts)
                        .expect("render")
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
