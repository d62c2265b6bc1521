//! Every mapping, forward and inverse: the scalar core, the SIMD kernels at
//! each tier, a plain std-math scalar latlong (both ways), and a plain copy of the same
//! bytes (the memory floor), on fresh random input, in batches of 4096 (fits
//! in L1/L2) and 2^22 (does not fit in any cache).
//!
//! ```text
//! cargo bench -p envmap-bench --bench mappings
//! RUSTFLAGS="-C target-cpu=native" cargo bench -p envmap-bench --bench mappings
//! ENVMAP_BENCH_SIZES=4096 cargo bench -p envmap-bench --bench mappings -- forward/latlong
//! ```

mod common;

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use envmap_bench::report::{std_latlong_forward, std_latlong_inverse};
use envmap_bench::timing::directions;
use envmap_core::glam::Vec3;
use envmap_core::{AnyMapping, ChartUv};
use envmap_simd::{forward_slice, inverse_slice, Exact, Fast, Fine};

fn sizes() -> Vec<usize> {
    match std::env::var("ENVMAP_BENCH_SIZES") {
        Ok(s) => s.split(',').filter_map(|x| x.trim().parse().ok()).collect(),
        Err(_) => vec![4096, 1 << 22],
    }
}

fn forward(c: &mut Criterion) {
    for n in sizes() {
        // The same inputs on every run.
        let dirs = directions(0x2545_F491_4F6C_DD1D, n);
        let mut out = vec![ChartUv::default(); n];
        let mut copy_out = vec![Vec3::ZERO; n];
        for m in AnyMapping::ALL {
            let mut g = c.benchmark_group(format!("forward/{m}"));
            g.throughput(Throughput::Elements(n as u64));
            if n > 100_000 {
                g.sample_size(10);
            }
            g.bench_function(BenchmarkId::new("copy", n), |b| {
                b.iter(|| copy_out.copy_from_slice(black_box(&dirs)))
            });
            g.bench_function(BenchmarkId::new("scalar", n), |b| {
                b.iter(|| {
                    for (d, o) in black_box(&dirs).iter().zip(out.iter_mut()) {
                        *o = m.forward(*d).unwrap_or_default();
                    }
                })
            });
            g.bench_function(BenchmarkId::new("exact", n), |b| {
                b.iter(|| forward_slice::<_, Exact>(&m, black_box(&dirs), &mut out))
            });
            g.bench_function(BenchmarkId::new("fine", n), |b| {
                b.iter(|| forward_slice::<_, Fine>(&m, black_box(&dirs), &mut out))
            });
            g.bench_function(BenchmarkId::new("fast", n), |b| {
                b.iter(|| forward_slice::<_, Fast>(&m, black_box(&dirs), &mut out))
            });
            if m == AnyMapping::LatLong {
                g.bench_function(BenchmarkId::new("std", n), |b| {
                    b.iter(|| std_latlong_forward(black_box(&dirs), &mut out))
                });
            }
            g.finish();
        }
    }
}

fn inverse(c: &mut Criterion) {
    for n in sizes() {
        let dirs = directions(0x9E37_79B9_7F4A_7C15, n);
        let mut out = vec![Vec3::ZERO; n];
        let mut copy_out = vec![ChartUv::default(); n];
        for m in AnyMapping::ALL {
            // Inputs are the forward images of random directions: valid chart points.
            let coords: Vec<ChartUv> = dirs
                .iter()
                .map(|d| m.forward(*d).unwrap_or_default())
                .collect();
            let mut g = c.benchmark_group(format!("inverse/{m}"));
            g.throughput(Throughput::Elements(n as u64));
            if n > 100_000 {
                g.sample_size(10);
            }
            g.bench_function(BenchmarkId::new("copy", n), |b| {
                b.iter(|| copy_out.copy_from_slice(black_box(&coords)))
            });
            g.bench_function(BenchmarkId::new("scalar", n), |b| {
                b.iter(|| {
                    for (p, o) in black_box(&coords).iter().zip(out.iter_mut()) {
                        *o = m.inverse(*p).unwrap_or(Vec3::NAN);
                    }
                })
            });
            g.bench_function(BenchmarkId::new("exact", n), |b| {
                b.iter(|| inverse_slice::<_, Exact>(&m, black_box(&coords), &mut out))
            });
            g.bench_function(BenchmarkId::new("fine", n), |b| {
                b.iter(|| inverse_slice::<_, Fine>(&m, black_box(&coords), &mut out))
            });
            g.bench_function(BenchmarkId::new("fast", n), |b| {
                b.iter(|| inverse_slice::<_, Fast>(&m, black_box(&coords), &mut out))
            });
            if m == AnyMapping::LatLong {
                g.bench_function(BenchmarkId::new("std", n), |b| {
                    b.iter(|| std_latlong_inverse(black_box(&coords), &mut out))
                });
            }
            g.finish();
        }
    }
}

criterion_group! {
    name = benches;
    config = common::config()
        .warm_up_time(std::time::Duration::from_millis(500))
        .measurement_time(std::time::Duration::from_secs(2));
    targets = forward, inverse
}
criterion_main!(benches);
