//! Shared criterion configuration.

use criterion::Criterion;

/// Criterion's defaults, with its HTML report's charts when a font for their
/// text is found (plotters draws text through ab_glyph here, which needs a
/// font registered; see `envmap_bench::plot::register_font`), without the
/// charts otherwise.
pub(crate) fn config() -> Criterion {
    let c = Criterion::default();
    if envmap_bench::plot::register_font(None) {
        c
    } else {
        c.without_plots()
    }
}

/// A rayon pool of `threads` workers, for timing one thread count.
#[allow(dead_code)] // each bench file compiles this module on its own
pub(crate) fn pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("a thread pool")
}
