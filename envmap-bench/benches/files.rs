//! Whole jobs with files, as `envmap convert` and `envmap bake` run them
//! (the library calls the commands make, in this process), on two threads:
//!
//! * `files/convert-exr`: a 4096×2048 float EXR (the smooth test map, 100
//!   MB, written uncompressed as envmap writes f32) converted to a 6×1024²
//!   cube cross (151 MB uncompressed, 77 MB as the default `auto` writes
//!   it: its empty cells' lines RLE-compressed) and saved as EXR: `load`, `convert`, `save` alone
//!   and the three in a row (`total`); `streamed` is the job as `envmap
//!   convert` runs it (load, then the cube converted as its blocks are
//!   written, never whole in memory). Each save writes a new file (the
//!   previous one is removed outside the timing), as a user's job does.
//! * `files/save-cube-exr`: that cube saved with `auto` and each lossless
//!   codec (the file sizes are printed once).
//! * `files/hdr-to-ktx2`: the same map as Radiance `.hdr` to an RGBA16F
//!   KTX2 cube of 1024² (load, convert, save).
//! * `files/bake`: the default bake (512² chain, SH9, 32² irradiance, DFG)
//!   of the EXR file in memory (`in-memory`: the map already loaded, no
//!   file written) and as `envmap bake FILE --out DIR` runs it (`with-files`:
//!   load, the loaded map given to the bake, each level's file written
//!   while the next level is made, then the rest: `bake::bake_into`);
//!   `then-files` writes every file after the bake instead (`bake_owned`
//!   then `bake::write`).
//!
//! On jemalloc, as the `envmap` command runs.
//!
//! ```text
//! cargo bench -p envmap-bench --bench files
//! RUSTFLAGS="-C target-cpu=native" cargo bench -p envmap-bench --bench files
//! ```

mod common;

#[cfg(not(target_env = "msvc"))]
#[global_allocator]
static ALLOCATOR: tikv_jemallocator::Jemalloc = tikv_jemallocator::Jemalloc;

use std::hint::black_box;
use std::path::{Path, PathBuf};

use criterion::{criterion_group, criterion_main, BatchSize, Criterion};
use envmap_core::AnyMapping;
use envmap_render::bake::Baker;
use envmap_render::filter::{convert, ConvertOptions, Streamed};
use envmap_render::image::{load, save, ExrCompression, LoadOptions, Outputs, SaveOptions};
use envmap_render::image::{EnvImage, FileAxes, Representation};
use envmap_render::scene::{fill, smooth};

/// A scratch directory, removed when dropped.
struct Scratch(PathBuf);

impl Scratch {
    fn new() -> Self {
        let dir = std::env::temp_dir().join(format!("envmap-bench-files-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("scratch directory");
        Self(dir)
    }

    fn path(&self, name: &str) -> PathBuf {
        self.0.join(name)
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// The cube cross of `src` at 1024², as `envmap convert --to cube --size
/// 1024` makes it.
fn to_cube(src: &EnvImage) -> EnvImage {
    let repr = Representation::for_file(AnyMapping::Cube, FileAxes::default());
    convert(src, repr, 4096, 3072, &ConvertOptions::default(), None).expect("convert")
}

/// Removes `path` (outside the timing): every save writes a new file.
fn fresh(path: &Path) {
    let _ = std::fs::remove_file(path);
}

fn bench(c: &mut Criterion) {
    let pool = common::pool(2);
    let scratch = Scratch::new();
    let src = fill(
        Representation::for_file(AnyMapping::LatLong, FileAxes::default()),
        4096,
        2048,
        smooth,
    )
    .expect("map");
    let exr = scratch.path("smooth4096.exr");
    let hdr = scratch.path("smooth4096.hdr");
    save(&src, &exr, &SaveOptions::default()).expect("exr");
    save(&src, &hdr, &SaveOptions::default()).expect("hdr");
    let loaded = load(&exr, &LoadOptions::default()).expect("load");
    let cube = pool.install(|| to_cube(&loaded));
    let out = scratch.path("cube.exr");

    let mut g = c.benchmark_group("files/convert-exr");
    g.sample_size(10);
    g.bench_function("load/2-threads", |b| {
        b.iter(|| pool.install(|| load(black_box(&exr), &LoadOptions::default()).expect("load")))
    });
    g.bench_function("convert/2-threads", |b| {
        b.iter(|| pool.install(|| to_cube(black_box(&loaded))))
    });
    g.bench_function("save/2-threads", |b| {
        b.iter_batched(
            || fresh(&out),
            |()| pool.install(|| save(black_box(&cube), &out, &SaveOptions::default())),
            BatchSize::PerIteration,
        )
    });
    g.bench_function("total/2-threads", |b| {
        b.iter_batched(
            || fresh(&out),
            |()| {
                pool.install(|| {
                    let m = load(black_box(&exr), &LoadOptions::default()).expect("load");
                    let cube = to_cube(&m);
                    drop(m);
                    save(&cube, &out, &SaveOptions::default()).expect("save")
                })
            },
            BatchSize::PerIteration,
        )
    });
    g.bench_function("streamed/2-threads", |b| {
        b.iter_batched(
            || fresh(&out),
            |()| {
                pool.install(|| {
                    let m = load(black_box(&exr), &LoadOptions::default()).expect("load");
                    let repr = Representation::for_file(AnyMapping::Cube, FileAxes::default());
                    let opts = ConvertOptions::default();
                    let stream = Streamed::new(&m, repr, 4096, 3072, &opts, None).expect("stream");
                    let save_opts = SaveOptions::default();
                    let mut run = Outputs::new(&save_opts);
                    run.stage_streamed(&stream, &out, &save_opts).expect("save");
                    run.commit().expect("commit")
                })
            },
            BatchSize::PerIteration,
        )
    });
    g.finish();

    let mut g = c.benchmark_group("files/save-cube-exr");
    g.sample_size(10);
    for codec in [
        ExrCompression::Auto,
        ExrCompression::None,
        ExrCompression::Rle,
        ExrCompression::Zips,
        ExrCompression::Zip,
        ExrCompression::Piz,
    ] {
        let opts = {
            let mut o = SaveOptions::default();
            o.exr_compression = codec;
            o
        };
        fresh(&out);
        save(&cube, &out, &opts).expect("save");
        let size = std::fs::metadata(&out).map_or(0, |m| m.len());
        println!(
            "files/save-cube-exr/{}: {:.1} MB",
            codec.name(),
            size as f64 / 1e6
        );
        g.bench_function(format!("{}/2-threads", codec.name()), |b| {
            b.iter_batched(
                || fresh(&out),
                |()| pool.install(|| save(black_box(&cube), &out, &opts)),
                BatchSize::PerIteration,
            )
        });
    }
    g.finish();

    let ktx2 = scratch.path("cube.ktx2");
    let mut g = c.benchmark_group("files/hdr-to-ktx2");
    g.sample_size(10);
    g.bench_function("total/2-threads", |b| {
        b.iter_batched(
            || fresh(&ktx2),
            |()| {
                pool.install(|| {
                    let m = load(black_box(&hdr), &LoadOptions::default()).expect("load");
                    let cube = to_cube(&m);
                    drop(m);
                    save(&cube, &ktx2, &SaveOptions::default()).expect("save")
                })
            },
            BatchSize::PerIteration,
        )
    });
    g.finish();

    let baker = Baker::new().input_name("smooth4096.exr");
    let dir = scratch.path("ibl");
    let mut g = c.benchmark_group("files/bake");
    g.sample_size(10);
    // The map given to the bake as `envmap bake` gives it (its copy made
    // outside the timing).
    g.bench_function("in-memory/2-threads", |b| {
        b.iter_batched(
            || loaded.clone(),
            |m| pool.install(|| baker.bake(m).expect("bake")),
            BatchSize::PerIteration,
        )
    });
    // Load, then `job`: a new directory each time, as a user's job makes.
    let mut with_load = |name: &str, job: &(dyn Fn(EnvImage) + Sync)| {
        g.bench_function(name, |b| {
            b.iter_batched(
                || {
                    let _ = std::fs::remove_dir_all(&dir);
                },
                |()| {
                    pool.install(|| {
                        job(load(black_box(&exr), &LoadOptions::default()).expect("load"));
                    })
                },
                BatchSize::PerIteration,
            )
        });
    };
    with_load("with-files/2-threads", &|m| {
        baker.bake_into(m, &dir).expect("bake into");
    });
    with_load("then-files/2-threads", &|m| {
        baker.bake(m).expect("bake").write(&dir).expect("write");
    });
    g.finish();
}

criterion_group! {
    name = benches;
    config = common::config();
    targets = bench
}
criterion_main!(benches);
