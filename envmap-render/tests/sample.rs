//! The eight-lane sampler against the scalar one, bit for bit, in every
//! representation and layout, on points inside charts, on their edges, out
//! of range and NaN; the cubic filter's accuracy on a smooth map against the
//! exact function, and its clamp around a sun.

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
        for filter in [Filter::Nearest, Filter::Bilinear, Filter::Cubic] {
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

/// A smooth function of the direction, with second and third derivatives.
fn smooth(d: envmap_core::glam::Vec3) -> f32 {
    1.0 + 0.5 * d.x + 0.3 * d.y * d.z + 0.2 * d.z * d.z * d.x
}

/// Upsampling a smooth map: cubic's error against the exact function, at
/// random points of a latlong, a cube and an EAC map of a few texels, is
/// well below bilinear's away from face edges (third order against
/// second), and not above it within two texels of one, where the taps
/// across the edge are the neighbouring face's nearest texels (the edge
/// rule), not a regular grid.
#[test]
fn cubic_is_closer_than_bilinear_on_smooth_maps() {
    let mut rng = SplitMix64::new(11);
    for (repr, cell) in [
        (Representation::default_for(AnyMapping::LatLong), 64),
        (Representation::default_for(AnyMapping::Cube), 16),
        (Representation::default_for(AnyMapping::Eac), 16),
    ] {
        let m = repr.mapping;
        let (w, h) = repr.atlas.image_size_for_cell_width(cell).unwrap();
        let mut img = EnvImage::new(w, h, repr).unwrap();
        let (cw, ch) = img.cell_size();
        for chart in 0..m.chart_count() {
            for j in 0..ch {
                for i in 0..cw {
                    let c = envmap_core::ChartUv::new(
                        chart,
                        (i as f32 + 0.5) / cw as f32,
                        (j as f32 + 0.5) / ch as f32,
                    );
                    let f = smooth(m.inverse(c).unwrap());
                    img.set_chart_texel(chart, i, j, [f; 3]);
                }
            }
        }
        let sampler = Sampler::new(&img);
        // [interior, within two texels of a face edge]: (bilinear, cubic, count).
        let mut sq = [[0.0f64; 3]; 2];
        for _ in 0..40_000 {
            let d = rng.direction().normalize();
            let c = m.forward(d).unwrap();
            let exact = f64::from(smooth(d));
            let b = f64::from(sampler.sample(c, Filter::Bilinear)[0]);
            let k = f64::from(sampler.sample(c, Filter::Cubic)[0]);
            let margin = 2.0 / cw as f32;
            let edge =
                m != AnyMapping::LatLong && [c.u, c.v].iter().any(|&t| t.min(1.0 - t) < margin);
            let s = &mut sq[usize::from(edge)];
            s[0] += (b - exact).powi(2);
            s[1] += (k - exact).powi(2);
            s[2] += 1.0;
        }
        let rms = |s: [f64; 3], k: usize| (s[k] / s[2].max(1.0)).sqrt();
        let (b, c) = (rms(sq[0], 0), rms(sq[0], 1));
        println!(
            "{m}: RMS error bilinear {b:.2e}, cubic {c:.2e}; within two texels of a face edge \
             bilinear {:.2e}, cubic {:.2e}",
            rms(sq[1], 0),
            rms(sq[1], 1)
        );
        assert!(c < 0.25 * b, "{m}: cubic {c:e} vs bilinear {b:e}");
        if m != AnyMapping::LatLong {
            assert!(rms(sq[1], 1) <= rms(sq[1], 0), "{m} at the edges");
        }
    }
}

/// A sun (one texel of 50 000 in a sky of 1): the cubic samples around it
/// stay within the range of the four texels each reads bilinearly, so
/// nothing rings: never below the sky, never above the sun, and exactly the
/// sky where the sun is not among those four (the spline alone goes to
/// 1 − 0.0703·50 000 there).
#[test]
fn cubic_does_not_ring_around_a_sun() {
    let repr = Representation::default_for(AnyMapping::LatLong);
    let mut img = EnvImage::new(64, 32, repr).unwrap();
    for p in img.pixels_mut() {
        *p = [1.0; 3];
    }
    img.set(20, 12, [50_000.0; 3]);
    let sampler = Sampler::new(&img);
    let mut peak = 0.0f32;
    for j in 0..200 {
        for i in 0..200 {
            let u = (18.0 + 5.0 * i as f32 / 200.0) / 64.0;
            let v = (10.0 + 5.0 * j as f32 / 200.0) / 32.0;
            let s = sampler.sample(envmap_core::ChartUv::new(0, u, v), Filter::Cubic)[0];
            assert!((1.0..=50_000.0).contains(&s), "({u}, {v}): {s}");
            // The bilinear footprint: texels floor(x) and floor(x) + 1.
            let (x, y) = (u * 64.0 - 0.5, v * 32.0 - 0.5);
            let touches = (x.floor() as i32..=x.floor() as i32 + 1).contains(&20)
                && (y.floor() as i32..=y.floor() as i32 + 1).contains(&12);
            if !touches {
                assert_eq!(s, 1.0, "({u}, {v})");
            }
            peak = peak.max(s);
        }
    }
    assert!(peak > 40_000.0, "{peak}");
}

/// Upsampling a sky with a sun four times by the cubic filter keeps its
/// energy (the mean over the sphere, by solid angle) as bilinear does: the
/// sun is spread bilinearly, not by the spline with its lobes cut.
#[test]
fn cubic_upsampling_keeps_a_suns_energy() {
    use envmap_render::filter::{convert, ConvertOptions};
    let repr = Representation::default_for(AnyMapping::LatLong);
    let mut img = EnvImage::new(64, 32, repr).unwrap();
    for (k, p) in img.pixels_mut().iter_mut().enumerate() {
        let y = (k / 64) as f32 / 32.0;
        *p = [1.0 + y, 0.5 + 0.25 * y, 0.2];
    }
    img.set(20, 12, [50_000.0, 40_000.0, 30_000.0]);
    let mean = |i: &EnvImage| i.stats().sphere_mean;
    let before = mean(&img);
    for filter in [Filter::Bilinear, Filter::Cubic] {
        let mut opts = ConvertOptions::default();
        opts.filter = filter;
        opts.samples = Some(1);
        let up = convert(&img, repr, 256, 128, &opts, None).unwrap();
        let after = mean(&up);
        for k in 0..3 {
            let rel = after[k] / before[k] - 1.0;
            println!("{filter:?} channel {k}: energy {rel:+.2e}");
            assert!(rel.abs() < 1e-3, "{filter:?} channel {k}: {rel:e}");
        }
        assert!(
            up.stats().min.iter().all(|&m| m >= 0.2 - 1e-6),
            "{:?}",
            up.stats().min
        );
    }
}
