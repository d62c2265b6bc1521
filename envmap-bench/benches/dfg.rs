//! The DFG (split-sum BRDF) table at its default size, 128², single and
//! multiscatter from one f64 quadrature per texel, on one and on two
//! threads.
//!
//! ```text
//! RUSTFLAGS="-C target-cpu=native" cargo bench -p envmap-bench --bench dfg
//! ```

mod common;

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use envmap_render::filter::dfg::{DfgTable, DEFAULT_SIZE};

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("dfg/128");
    g.sample_size(20);
    g.throughput(Throughput::Elements(u64::from(DEFAULT_SIZE * DEFAULT_SIZE)));
    for threads in [1, 2] {
        let pool = common::pool(threads);
        g.bench_function(format!("table/{threads}-threads"), |b| {
            b.iter(|| pool.install(|| DfgTable::new(black_box(DEFAULT_SIZE)).expect("table")))
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
