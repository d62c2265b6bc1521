//! The eight-lane sampler against the scalar one, bit for bit, in every
//! representation and layout, on points inside charts, on their edges, out
//! of range and NaN.

use envmap_core::{AnyMapping, Atlas, Frame, Mapping};
use envmap_render::filter::sample::{Filter, Sampler};
use envmap_render::image::{EnvImage, Representation};
use envmap_simd::Uv8;
use envmap_tests::SplitMix64;
use wide::{f32x8, u32x8};

/// Uniform in [lo, hi).
fn range(rng: &mut SplitMix64, lo: f32, hi: f32) -> f32 {
    lo + (hi - lo) * ((rng.next_u64() >> 40) as f32 / (1u64 << 24) as f32)
}

/// Every mapping in its default layout, and the cube in every cube layout
/// (the vertical cross stores −z turned half a turn).
fn representations() -> Vec<Representation> {
    let mut all: Vec<_> = AnyMapping::ALL
        .iter()
        .map(|&m| Representation::default_for(m))
        .collect();
    for atlas in [
        Atlas::CUBE_HORIZONTAL_CROSS,
        Atlas::CUBE_VERTICAL_CROSS,
        Atlas::CUBE_HORIZONTAL_STRIP,
        Atlas::CUBE_VERTICAL_STRIP,
    ] {
        all.push(Representation::new(AnyMapping::Cube, atlas, Frame::IDENTITY).unwrap());
    }
    all
}

/// A coordinate: mostly inside [0, 1], some exactly on the edges or on
/// texel centres and boundaries, some outside, a few NaN.
fn coordinate(rng: &mut SplitMix64, texels: u32) -> f32 {
    match rng.next_u64() % 16 {
        0 => 0.0,
        1 => 1.0,
        2 => f32::NAN,
        3 => range(rng, -0.2, 0.0),
        4 => range(rng, 1.0, 1.2),
        5 => (rng.next_u64() % u64::from(texels)) as f32 / texels as f32,
        6 => ((rng.next_u64() % u64::from(texels)) as f32 + 0.5) / texels as f32,
        7 => range(rng, 0.0, 1.5 / texels as f32),
        8 => range(rng, 1.0 - 1.5 / texels as f32, 1.0),
        _ => range(rng, 0.0, 1.0),
    }
}

#[test]
fn eight_lanes_equal_the_scalar_sampler_bit_for_bit() {
    let mut rng = SplitMix64::new(7);
    for repr in representations() {
        // 24 is a multiple of 3, as the tennisball's cells need.
        let (w, h) = repr.atlas.image_size_for_cell_width(24).unwrap();
        let mut img = EnvImage::new(w, h, repr).unwrap();
        for p in img.pixels_mut() {
            *p = [
                range(&mut rng, 0.0, 4.0),
                range(&mut rng, 0.0, 4.0),
                range(&mut rng, 0.0, 4.0),
            ];
        }
        let sampler = Sampler::new(&img);
        let (cw, ch) = img.cell_size();
        let charts = repr.mapping.chart_count();
        for filter in [Filter::Nearest, Filter::Bilinear] {
            for _ in 0..4000 {
                let chart: [u32; 8] = core::array::from_fn(|_| match rng.next_u64() % 20 {
                    0 => charts,
                    1 => u32::MAX,
                    _ => (rng.next_u64() % u64::from(charts)) as u32,
                });
                let u: [f32; 8] = core::array::from_fn(|_| coordinate(&mut rng, cw));
                let v: [f32; 8] = core::array::from_fn(|_| coordinate(&mut rng, ch));
                let q = Uv8::new(u32x8::new(chart), f32x8::new(u), f32x8::new(v));
                let eight = sampler.sample8(&q, filter);
                // Into a shorter slice: those lanes, and nothing past them.
                let len = (rng.next_u64() % 8) as usize + 1;
                let mut dst = vec![[-7.0f32; 3]; len + 1];
                sampler.sample8_into(&q, filter, &mut dst[..len]);
                for k in 0..len {
                    assert_eq!(dst[k].map(f32::to_bits), eight[k].map(f32::to_bits));
                }
                assert_eq!(dst[len], [-7.0; 3], "sample8_into wrote past its slice");
                for k in 0..8 {
                    let one = sampler.sample(q.lane_raw(k), filter);
                    assert_eq!(
                        eight[k].map(f32::to_bits),
                        one.map(f32::to_bits),
                        "{} in {:?}, {filter:?}: lane {k} at chart {} ({}, {}): {:?} vs {:?}",
                        repr.mapping,
                        repr.atlas,
                        chart[k],
                        u[k],
                        v[k],
                        eight[k],
                        one
                    );
                }
            }
        }
    }
}
