//! GPU texture files of a 512² specular chain (a cube, the full chain of
//! ten levels down to 1×1, already in memory): writing it as KTX2 RGB9E5
//! with Zstandard supercompression at [`ZSTD_LEVEL`] and as uncompressed
//! KTX2 RGBA16F, and as DDS RGBA16F; reading each of those files back from
//! its bytes. On two threads (KTX2 packs and compresses the levels in
//! parallel; DDS is serial).
//!
//! The chain is not baked here: every level is the same smooth sky
//! (0.01 … 50, a sun of about 10⁴) sampled at that level's size, which is
//! as smooth as a prefiltered chain and keeps the setup cheap. Each file
//! read is made (and its size printed) when its benchmark first runs.
//!
//! ```text
//! RUSTFLAGS="-C target-cpu=native" cargo bench -p envmap-bench --bench texture
//! ```

mod common;

use std::hint::black_box;
use std::path::Path;
use std::sync::OnceLock;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use envmap_render::image::texture::{self, full_chain, level_size};
use envmap_render::image::{
    texture::{Texture, TextureKind, TextureOptions},
    RgbImage, TexelFormat,
};
use glam::Vec3;

/// Face size of level 0.
const SIZE: u32 = 512;
/// The Zstandard level of the RGB9E5 file: the default of `--zstd` and of
/// the presets (`DEFAULT_ZSTD` of `envmap bake`); higher levels make
/// smaller files far more slowly.
const ZSTD_LEVEL: i32 = 3;

/// The direction through the centre of texel (`x`, `y`) of cube face
/// `face` (GL order +X, −X, +Y, −Y, +Z, −Z, first texel top-left) of `w`².
fn direction(face: usize, x: u32, y: u32, w: u32) -> Vec3 {
    let s = 2.0 * (x as f32 + 0.5) / w as f32 - 1.0;
    let t = 2.0 * (y as f32 + 0.5) / w as f32 - 1.0;
    let d = match face {
        0 => Vec3::new(1.0, -t, -s),
        1 => Vec3::new(-1.0, -t, s),
        2 => Vec3::new(s, 1.0, t),
        3 => Vec3::new(s, -1.0, -t),
        4 => Vec3::new(s, -t, 1.0),
        _ => Vec3::new(-s, -t, -1.0),
    };
    d.normalize()
}

/// A sky: a blue gradient from a bright horizon (about 50) to the zenith,
/// dark ground (0.01 … 0.3), and a sun of about 10⁴, 1° across.
fn sky(d: Vec3) -> [f32; 3] {
    let sun = Vec3::new(0.4, 0.5, 0.77).normalize();
    if d.dot(sun) > 0.5f32.to_radians().cos() {
        return [1.2e4, 1.1e4, 0.9e4];
    }
    let glow = 10.0 * d.dot(sun).max(0.0).powi(32);
    if d.y >= 0.0 {
        let h = 1.0 - d.y;
        let h4 = h * h * h * h;
        [
            1.0 + 40.0 * h4 + glow,
            2.0 + 42.0 * h4 + glow,
            6.0 + 44.0 * h4 + 0.8 * glow,
        ]
    } else {
        let g = 0.01 + 0.29 * (1.0 + d.y).powi(8);
        [g * 1.1, g, g * 0.8]
    }
}

/// The cube of `size`² faces with its full chain, every level [`sky`].
fn chain(size: u32) -> Texture {
    let levels = (0..full_chain(size, size))
        .map(|p| {
            let (w, _) = level_size(size, size, p);
            (0..6)
                .map(|face| RgbImage {
                    width: w,
                    height: w,
                    pixels: (0..w)
                        .flat_map(|y| (0..w).map(move |x| sky(direction(face, x, y, w))))
                        .collect(),
                })
                .collect()
        })
        .collect();
    Texture::new(TextureKind::Cube, levels).expect("a full chain")
}

/// Bytes of a file to read, made when first asked for (a filter may skip
/// its benchmark), with its size printed once.
fn file<'a>(cell: &'a OnceLock<Vec<u8>>, name: &str, make: impl FnOnce() -> Vec<u8>) -> &'a [u8] {
    cell.get_or_init(|| {
        let bytes = make();
        eprintln!("{name}: {} bytes", bytes.len());
        bytes
    })
}

fn bench(c: &mut Criterion) {
    let pool = common::pool(2);
    let tex = chain(SIZE);
    let texels: u64 = tex
        .levels()
        .iter()
        .flatten()
        .map(|i| i.pixels.len() as u64)
        .sum();
    let rgb9e5_zstd = {
        let mut o = TextureOptions::default();
        o.format = TexelFormat::E5b9g9r9;
        o.zstd = Some(ZSTD_LEVEL);
        o
    };
    let rgba16f = {
        let mut o = TextureOptions::default();
        o.format = TexelFormat::Rgba16f;
        o.zstd = None;
        o
    };
    let (ktx2_zstd, ktx2_half, dds_half) = (OnceLock::new(), OnceLock::new(), OnceLock::new());

    let mut g = c.benchmark_group("ktx2_write");
    g.throughput(Throughput::Elements(texels));
    g.sample_size(20);
    g.bench_function("rgb9e5_zstd", |b| {
        b.iter(|| {
            pool.install(|| {
                texture::encode(black_box(&tex), Path::new("chain.ktx2"), rgb9e5_zstd)
                    .expect("KTX2")
            })
        })
    });
    g.sample_size(20);
    g.bench_function("rgba16f", |b| {
        b.iter(|| {
            pool.install(|| {
                texture::encode(black_box(&tex), Path::new("chain.ktx2"), rgba16f).expect("KTX2")
            })
        })
    });
    g.finish();

    let mut g = c.benchmark_group("ktx2_read");
    g.sample_size(20);
    g.throughput(Throughput::Elements(texels));
    let path = Path::new("chain.ktx2");
    g.bench_function("rgb9e5_zstd", |b| {
        let bytes = file(
            &ktx2_zstd,
            &format!("KTX2 RGB9E5 + zstd {ZSTD_LEVEL}"),
            || {
                pool.install(|| {
                    texture::encode(&tex, Path::new("chain.ktx2"), rgb9e5_zstd)
                        .expect("KTX2")
                        .0
                })
            },
        );
        b.iter(|| pool.install(|| texture::decode(path, black_box(bytes), u64::MAX).expect("KTX2")))
    });
    g.bench_function("rgba16f", |b| {
        let bytes = file(&ktx2_half, "KTX2 RGBA16F", || {
            texture::encode(&tex, Path::new("chain.ktx2"), rgba16f)
                .expect("KTX2")
                .0
        });
        b.iter(|| pool.install(|| texture::decode(path, black_box(bytes), u64::MAX).expect("KTX2")))
    });
    g.finish();

    let mut g = c.benchmark_group("dds_write");
    g.sample_size(20);
    g.throughput(Throughput::Elements(texels));
    g.bench_function("rgba16f", |b| {
        b.iter(|| {
            pool.install(|| {
                texture::encode(black_box(&tex), Path::new("chain.dds"), {
                    let mut o = TextureOptions::default();
                    o.format = TexelFormat::Rgba16f;
                    o.zstd = None;
                    o
                })
                .expect("DDS")
            })
        })
    });
    g.finish();

    let mut g = c.benchmark_group("dds_read");
    g.sample_size(20);
    g.throughput(Throughput::Elements(texels));
    let path = Path::new("chain.dds");
    g.bench_function("rgba16f", |b| {
        let bytes = file(&dds_half, "DDS RGBA16F", || {
            texture::encode(&tex, Path::new("chain.dds"), {
                let mut o = TextureOptions::default();
                o.format = TexelFormat::Rgba16f;
                o.zstd = None;
                o
            })
            .expect("DDS")
            .0
        });
        b.iter(|| pool.install(|| texture::decode(path, black_box(bytes), u64::MAX).expect("DDS")))
    });
    g.finish();
}

criterion_group! {
    name = benches;
    config = common::config();
    targets = bench
}
criterion_main!(benches);
