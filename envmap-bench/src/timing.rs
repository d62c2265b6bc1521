//! Median-of-passes timing on fresh random input.
//!
//! Each timed pass first makes its input (untimed: a fresh pseudo-random
//! batch, so neither the caches nor the branch predictor see the same data
//! twice in a row), then times one run of the kernel over it with
//! [`Instant`]; the result is the median over the passes, per element. One
//! untimed pass warms up first.

use std::hint::black_box;
use std::time::Instant;

use envmap_core::glam::Vec3;
use envmap_core::{AnyMapping, ChartUv};

use crate::accuracy::SplitMix64;

/// The median of `v` (the mean of the middle two for an even count); NaN for
/// an empty slice.
#[must_use]
pub fn median(v: &mut [f64]) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    let k = v.len() / 2;
    if v.len() % 2 == 1 {
        v[k]
    } else {
        0.5 * (v[k - 1] + v[k])
    }
}

/// Times `passes` runs of `run` on inputs made by `fresh(pass)` and returns
/// the median time of one run in nanoseconds divided by `n`.
///
/// `fresh` is called before every pass (pass numbers from 0; one extra
/// untimed warm-up pass first) and is not timed; `run` gets the input and is
/// timed as a whole. Inputs and outputs go through [`black_box`].
pub fn ns_per_element<I>(
    passes: usize,
    n: usize,
    mut fresh: impl FnMut(usize) -> I,
    mut run: impl FnMut(&I),
) -> f64 {
    let input = fresh(usize::MAX);
    run(black_box(&input));
    drop(input);
    let mut times = Vec::with_capacity(passes);
    for pass in 0..passes {
        let input = fresh(pass);
        let input = black_box(input);
        let t = Instant::now();
        run(&input);
        times.push(t.elapsed().as_secs_f64());
        black_box(&input);
    }
    median(&mut times) * 1e9 / n as f64
}

/// `n` pseudo-random values uniform in `[lo, hi)` from `seed`.
#[must_use]
pub fn uniform(seed: u64, n: usize, lo: f32, hi: f32) -> Vec<f32> {
    let mut rng = SplitMix64(seed);
    (0..n)
        .map(|_| lo + (hi - lo) * ((rng.next_u64() >> 40) as f32 / (1u64 << 24) as f32))
        .collect()
}

/// `n` pseudo-random directions from `seed`: uniform in the unit ball less a
/// small ball around the origin (so of random length, as callers pass them).
#[must_use]
pub fn directions(seed: u64, n: usize) -> Vec<Vec3> {
    let mut rng = SplitMix64(seed);
    let mut unit = || (rng.next_u64() >> 40) as f32 / (1u64 << 24) as f32 * 2.0 - 1.0;
    let mut v = Vec::with_capacity(n);
    while v.len() < n {
        let d = Vec3::new(unit(), unit(), unit());
        let l = d.length_squared();
        if l > 1e-4 && l <= 1.0 {
            v.push(d);
        }
    }
    v
}

/// The forward images under `m` of [`directions`]`(seed, n)`: valid chart
/// points spread as real lookups are.
#[must_use]
pub fn chart_points(m: AnyMapping, seed: u64, n: usize) -> Vec<ChartUv> {
    directions(seed, n)
        .iter()
        .map(|d| m.forward(*d).unwrap_or_default())
        .collect()
}
