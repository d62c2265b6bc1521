//! The samplers on bad chart points: every mapping's image sampled, one
//! point at a time and eight at a time, at chart numbers out of range
//! (including `INVALID_CHART`), at u, v outside `[0, 1]`, NaN and ±Inf, and
//! on the edges. Nothing may panic or read outside the image; a point
//! outside every chart gives black; lanes of `sample8` equal `sample`.

use envmap_core::{AnyMapping, ChartUv, Mapping};
use envmap_render::filter::sample::{Filter, Sampler};
use envmap_render::image::Representation;
use envmap_render::scene::{fill, smooth};
use envmap_simd::{Uv8, INVALID_CHART};

const COORDS: [f32; 12] = [
    0.0,
    -0.0,
    0.5,
    1.0,
    0.999_999_94,
    1.000_000_1,
    -1e-30,
    2.0,
    1e30,
    f32::NAN,
    f32::INFINITY,
    f32::NEG_INFINITY,
];

#[test]
fn samplers_on_bad_chart_points() {
    for m in AnyMapping::ALL {
        let repr = Representation::default_for(m);
        let (w, h) = repr.atlas.image_size_for_cell_width(12).unwrap();
        let img = fill(repr, w, h, smooth).unwrap();
        let sampler = Sampler::new(&img);
        let n = m.chart_count();
        let mut points = Vec::new();
        for chart in [0, n - 1, n, 7, INVALID_CHART] {
            for u in COORDS {
                for v in COORDS {
                    points.push(ChartUv::new(chart, u, v));
                }
            }
        }
        for filter in [Filter::Nearest, Filter::Bilinear] {
            for chunk in points.chunks(8) {
                let eight = sampler.sample8(&Uv8::from_partial(chunk), filter);
                for (k, c) in chunk.iter().enumerate() {
                    let one = sampler.sample(*c, filter);
                    assert_eq!(
                        one.map(f32::to_bits),
                        eight[k].map(f32::to_bits),
                        "{m} {filter:?} {c:?}"
                    );
                    assert!(one.iter().all(|x| x.is_finite()), "{m} {filter:?} {c:?}");
                    if c.chart >= n || c.u.is_nan() || c.v.is_nan() {
                        assert_eq!(one, [0.0; 3], "{m} {filter:?} {c:?}");
                    }
                }
            }
        }
    }
}
