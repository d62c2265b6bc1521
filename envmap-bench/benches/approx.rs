//! Speed of `envmap_simd::approx`: every function at every tier on 4096
//! random inputs, beside `std`'s scalar `f32` functions (a plain loop),
//! `wide`'s own `f32x8` versions and a plain copy of the same bytes (the
//! memory floor).
//!
//! ```text
//! cargo bench -p envmap-bench --bench approx -- --warm-up-time 1 --measurement-time 2
//! RUSTFLAGS="-C target-cpu=native" cargo bench -p envmap-bench --bench approx -- --warm-up-time 1 --measurement-time 2
//! ```

mod common;

use criterion::{criterion_group, criterion_main, BenchmarkGroup, Criterion, Throughput};
use envmap_simd::approx::{self, Exact, Fast, Fine, Tier};
use std::hint::black_box;
use wide::f32x8;

const N: usize = 4096;

/// `N` pseudo-random values in `[lo, hi)` (SplitMix64), as `f32x8` batches.
fn inputs(seed: u64, lo: f32, hi: f32) -> Vec<f32x8> {
    let mut state = seed;
    let mut next = || {
        state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        lo + (hi - lo) * ((z >> 40) as f32 / (1u64 << 24) as f32)
    };
    (0..N / 8)
        .map(|_| f32x8::new(core::array::from_fn(|_| next())))
        .collect()
}

fn scalars(v: &[f32x8]) -> Vec<f32> {
    v.iter().flat_map(|b| b.to_array()).collect()
}

fn unary<F: Fn(f32x8) -> f32x8>(
    g: &mut BenchmarkGroup<'_, criterion::measurement::WallTime>,
    id: &str,
    xs: &[f32x8],
    f: F,
) {
    g.bench_function(id, |b| {
        b.iter(|| {
            let mut acc = f32x8::ZERO;
            for &x in black_box(xs) {
                acc += f(x);
            }
            black_box(acc)
        });
    });
}

fn scalar_unary(
    g: &mut BenchmarkGroup<'_, criterion::measurement::WallTime>,
    xs: &[f32],
    f: fn(f32) -> f32,
) {
    g.bench_function("std", |b| {
        b.iter(|| {
            let mut acc = 0.0_f32;
            for &x in black_box(xs) {
                acc += f(x);
            }
            black_box(acc)
        });
    });
}

/// The memory floor: a plain copy of the inputs' bytes.
fn copy(g: &mut BenchmarkGroup<'_, criterion::measurement::WallTime>, inputs: &[&[f32x8]]) {
    let mut out: Vec<Vec<f32x8>> = inputs.iter().map(|v| vec![f32x8::ZERO; v.len()]).collect();
    g.bench_function("copy", |b| {
        b.iter(|| {
            for (o, i) in out.iter_mut().zip(inputs) {
                o.copy_from_slice(black_box(i));
            }
            black_box(&out);
        });
    });
}

fn tiers_unary(
    c: &mut Criterion,
    name: &str,
    xs: &[f32x8],
    wide_fn: Option<fn(f32x8) -> f32x8>,
    std_fn: Option<fn(f32) -> f32>,
    f: [fn(f32x8) -> f32x8; 3],
) {
    let mut g = c.benchmark_group(format!("approx/{name}"));
    g.throughput(Throughput::Elements(N as u64));
    for (tier, f) in [Exact::NAME, Fine::NAME, Fast::NAME].into_iter().zip(f) {
        unary(&mut g, tier, xs, f);
    }
    if let Some(w) = wide_fn {
        unary(&mut g, "wide", xs, w);
    }
    if let Some(s) = std_fn {
        scalar_unary(&mut g, &scalars(xs), s);
    }
    copy(&mut g, &[xs]);
    g.finish();
}

fn atan_of<T: Tier>(x: f32x8) -> f32x8 {
    approx::atan::<T>(x)
}
fn asin_of<T: Tier>(x: f32x8) -> f32x8 {
    approx::asin::<T>(x)
}
fn acos_of<T: Tier>(x: f32x8) -> f32x8 {
    approx::acos::<T>(x)
}
fn sin_cos_of<T: Tier>(x: f32x8) -> f32x8 {
    let (s, c) = approx::sin_cos::<T>(x);
    s + c
}

fn bench(c: &mut Criterion) {
    let xs = inputs(1, -20.0, 20.0);
    tiers_unary(
        c,
        "atan",
        &xs,
        Some(f32x8::atan),
        Some(f32::atan),
        [atan_of::<Exact>, atan_of::<Fine>, atan_of::<Fast>],
    );
    let xs = inputs(2, -1.0, 1.0);
    tiers_unary(
        c,
        "asin",
        &xs,
        Some(f32x8::asin),
        Some(f32::asin),
        [asin_of::<Exact>, asin_of::<Fine>, asin_of::<Fast>],
    );
    tiers_unary(
        c,
        "acos",
        &xs,
        Some(f32x8::acos),
        Some(f32::acos),
        [acos_of::<Exact>, acos_of::<Fine>, acos_of::<Fast>],
    );
    let xs = inputs(3, -std::f32::consts::TAU, std::f32::consts::TAU);
    tiers_unary(
        c,
        "sin_cos",
        &xs,
        Some(|x: f32x8| {
            let (s, c) = x.sin_cos();
            s + c
        }),
        Some(|x: f32| {
            let (s, c) = x.sin_cos();
            s + c
        }),
        [sin_cos_of::<Exact>, sin_cos_of::<Fine>, sin_cos_of::<Fast>],
    );

    // atan2 takes two inputs.
    let ys = inputs(4, -10.0, 10.0);
    let xs = inputs(5, -10.0, 10.0);
    let mut g = c.benchmark_group("approx/atan2");
    g.throughput(Throughput::Elements(N as u64));
    let binary = |g: &mut BenchmarkGroup<'_, _>, id: &str, f: fn(f32x8, f32x8) -> f32x8| {
        g.bench_function(id, |b| {
            b.iter(|| {
                let mut acc = f32x8::ZERO;
                for (&y, &x) in black_box(&ys).iter().zip(black_box(&xs)) {
                    acc += f(y, x);
                }
                black_box(acc)
            });
        });
    };
    binary(&mut g, Exact::NAME, approx::atan2::<Exact>);
    binary(&mut g, Fine::NAME, approx::atan2::<Fine>);
    binary(&mut g, Fast::NAME, approx::atan2::<Fast>);
    binary(&mut g, "wide", f32x8::atan2);
    let (sy, sx) = (scalars(&ys), scalars(&xs));
    g.bench_function("std", |b| {
        b.iter(|| {
            let mut acc = 0.0_f32;
            for (&y, &x) in black_box(&sy).iter().zip(black_box(&sx)) {
                acc += y.atan2(x);
            }
            black_box(acc)
        });
    });
    copy(&mut g, &[&ys, &xs]);
    g.finish();
}

criterion_group! {
    name = benches;
    config = common::config();
    targets = bench
}
criterion_main!(benches);
