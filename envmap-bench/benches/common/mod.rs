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
