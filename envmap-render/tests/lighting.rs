//! Image-based lighting against closed forms and against itself: the mip
//! pyramid keeps the mean, trilinear sampling is one path in scalar and
//! eight lanes, a constant environment stays constant at every roughness,
//! one bright texel gives the GGX lobe, the sampled levels are within their
//! bound of the exact sum, the same bytes at any thread count, and bad
//! input gives a clear result.

use envmap_core::glam::Vec3;
use envmap_core::texel::texel_center;
use envmap_core::{AnyMapping, Atlas, ChartUv, Mapping};
use envmap_render::filter::bake::{measure_level, specular_chain, BakeOptions};
use envmap_render::filter::pyramid::{Pyramid, Trilinear};
use envmap_render::filter::specular::{
    exact_level, ggx_d, prefilter_level, split_bright, Bright, LevelJob, Method,
};
use envmap_render::filter::weights::TexelWeights;
use envmap_render::image::{EnvImage, FileAxes, Representation};
use envmap_render::instruments::{Oracle, Pcg32};
use envmap_render::scene::Builtin;
use envmap_render::scene::{fill, smooth};
use envmap_simd::Uv8;
use wide::{f32x8, u32x8};

fn cube_repr() -> Representation {
    Representation::new(
        AnyMapping::Cube,
        Atlas::CUBE_HORIZONTAL_STRIP,
        FileAxes::default().frame(AnyMapping::Cube),
    )
    .unwrap()
}

/// Σ Ω·L over every texel of `img`, per channel, in f64.
fn weighted_sum(img: &EnvImage) -> [f64; 3] {
    let m = img.mapping();
    let (cw, ch) = img.cell_size();
    let w = TexelWeights::new(m, cw, ch);
    let mut s = [0.0f64; 3];
    for chart in 0..m.chart_count() {
        let face = img.chart_image(chart).unwrap();
        for j in 0..ch {
            for i in 0..cw {
                let o = w.get(chart, i, j);
                let p = face.pixels[(j * cw + i) as usize];
                for (acc, v) in s.iter_mut().zip(p) {
                    *acc += o * f64::from(v);
                }
            }
        }
    }
    s
}

/// Σ Ω over every texel of `img`.
fn total_weight(img: &EnvImage) -> f64 {
    let (cw, ch) = img.cell_size();
    TexelWeights::new(img.mapping(), cw, ch).total()
}

#[test]
fn the_pyramid_keeps_the_solid_angle_weighted_mean_at_every_level() {
    // Powers of two and odd sizes, every mapping without disk charts (a
    // disk's rim texels whose centres are outside hold nothing: there the
    // mean is kept up to those slivers, checked more loosely). The weights
    // are TexelWeights', the ones the pyramid uses.
    for m in AnyMapping::ALL {
        for cell in [16u32, 13] {
            let a = m.atlas();
            let repr = Representation::default_for(m);
            let (w, h) = (
                a.cols * cell * a.cell_aspect_w,
                a.rows * cell * a.cell_aspect_h,
            );
            let img = fill(repr, w, h, smooth).unwrap();
            let (want, wt0) = (weighted_sum(&img), total_weight(&img));
            let p = Pyramid::new(img, 1).unwrap();
            assert!(p.len() >= 4, "{m} {cell}");
            for (k, l) in p.levels().iter().enumerate() {
                let (got, wt) = (weighted_sum(l), total_weight(l));
                for c in 0..3 {
                    if m.has_disk_charts() && l.cell_size().0 < 8 {
                        // A disk a few texels across is mostly rim.
                        continue;
                    }
                    if m.has_disk_charts() {
                        // The mean over the texels that hold a direction:
                        // each level leaves out other slivers of the rim,
                        // where a disk crowds the directions next to its
                        // singular one (most at small sizes).
                        let rel = (got[c] / wt - want[c] / wt0).abs() / (want[c] / wt0);
                        assert!(rel < 3e-2, "{m} cell {cell} level {k}: {rel:e}");
                    } else {
                        let rel = (got[c] - want[c]).abs() / want[c];
                        assert!(rel < 2e-6, "{m} cell {cell} level {k}: {rel:e}");
                    }
                }
            }
        }
    }
}

#[test]
fn trilinear_eight_lanes_equal_its_scalar_path_bit_for_bit() {
    let mut rng = Pcg32::new(12345);
    let mut next = || rng.next_u32();
    for m in AnyMapping::ALL {
        let repr = Representation::default_for(m);
        let a = repr.atlas;
        let (w, h) = (a.cols * 24 * a.cell_aspect_w, a.rows * 24 * a.cell_aspect_h);
        let p = Pyramid::new(fill(repr, w, h, smooth).unwrap(), 1).unwrap();
        let t = Trilinear::new(&p);
        for _ in 0..400 {
            let lanes: [ChartUv; 8] = core::array::from_fn(|_| {
                let chart = next() % (m.chart_count() + 1); // sometimes out of range
                let u = (next() % 1200) as f32 / 1000.0 - 0.1; // sometimes outside [0, 1]
                let v = (next() % 1200) as f32 / 1000.0 - 0.1;
                let u = if next() % 50 == 0 { f32::NAN } else { u };
                ChartUv::new(chart, u, v)
            });
            let lods: [f32; 8] = core::array::from_fn(|_| match next() % 10 {
                0 => f32::NAN,
                1 => -1.0,
                2 => 99.0,
                _ => (next() % 8000) as f32 / 1000.0,
            });
            let q = Uv8::new(
                u32x8::new(lanes.map(|c| c.chart)),
                f32x8::new(lanes.map(|c| c.u)),
                f32x8::new(lanes.map(|c| c.v)),
            );
            let eight = t.sample8(&q, f32x8::new(lods));
            let shared = t.sample8_at(&q, lods[3]);
            for k in 0..8 {
                let one = t.sample(lanes[k], lods[k]);
                assert_eq!(
                    eight[k].map(f32::to_bits),
                    one.map(f32::to_bits),
                    "{m} {:?} {}",
                    lanes[k],
                    lods[k]
                );
                let s = t.sample(lanes[k], lods[3]);
                let [r, g, b, _] = shared[k].to_array();
                assert_eq!([r, g, b].map(f32::to_bits), s.map(f32::to_bits), "{m}");
            }
        }
    }
}

/// A small prepared source: base cube of `base`² faces from `f`.
fn prepared(base: u32, f: impl Fn(Vec3) -> [f32; 3] + Sync) -> (Pyramid, Bright) {
    let mut img = fill(cube_repr(), 6 * base, base, f).unwrap();
    let bright = split_bright(&mut img, 4096, f64::INFINITY).unwrap();
    (Pyramid::new(img, 1).unwrap(), bright)
}

fn level(
    p: &Pyramid,
    t: &Trilinear<'_>,
    b: &Bright,
    r: f32,
    method: Method,
    size: u32,
) -> EnvImage {
    let job = LevelJob {
        rest: p,
        sampler: t,
        bright: b,
        roughness: r,
        method,
        lod_bias: 0.0,
        level: 1,
        cancel: None,
    };
    prefilter_level(&job, cube_repr(), 6 * size, size).unwrap()
}

#[test]
fn a_constant_environment_stays_constant_at_every_roughness() {
    let (p, b) = prepared(32, |_| [2.0, 3.0, 4.0]);
    assert_eq!(b.report.texels, 0);
    let t = Trilinear::new(&p);
    for r in [0.05, 0.25, 0.5, 0.75, 1.0] {
        for method in [
            Method::Exact {
                level: exact_level(&p, r),
            },
            Method::Sampled { samples: 64 },
        ] {
            let img = level(&p, &t, &b, r, method, 8);
            for px in img.pixels() {
                for (c, want) in [2.0f32, 3.0, 4.0].iter().enumerate() {
                    assert!(
                        (px[c] - want).abs() < 2e-5 * want,
                        "r {r} {method:?}: {px:?}"
                    );
                }
            }
        }
    }
}

#[test]
fn one_bright_texel_gives_the_ggx_lobe() {
    // One texel of +z (GL) a thousand times the rest (black): split out and
    // added exactly, LD(R) ∝ D(h)·(n·l) with c = R·l. Its shape against D.
    let base = 64;
    let mut img = fill(cube_repr(), 6 * base, base, |_| [0.0; 3]).unwrap();
    assert!(img.set_chart_texel(4, 37, 30, [1000.0; 3]));
    let b = split_bright(&mut img, 4096, f64::INFINITY).unwrap();
    assert_eq!(b.report.texels, 1);
    assert!((b.report.energy_share - 1.0).abs() < 1e-12);
    let p = Pyramid::new(img, 1).unwrap();
    let t = Trilinear::new(&p);
    let ld = b.dirs[0];
    let n = 16;
    let dir = |chart: u32, i: u32, j: u32| {
        AnyMapping::Cube
            .inverse(ChartUv::new(chart, texel_center(i, n), texel_center(j, n)))
            .unwrap()
    };
    for r in [0.2f32, 0.4, 0.7, 1.0] {
        let alpha = f64::from(r * r);
        let img = level(&p, &t, &b, r, Method::Sampled { samples: 64 }, n);
        let z = envmap_render::filter::specular::lobe_normalizer(alpha);
        let ol = f64::from(b.omega_l[0][0]);
        let mut peak = 0.0f64;
        for chart in 0..6 {
            for j in 0..n {
                for i in 0..n {
                    let (d, l) = (dir(chart, i, j), ld);
                    let c = f64::from(d.x) * f64::from(l.x)
                        + f64::from(d.y) * f64::from(l.y)
                        + f64::from(d.z) * f64::from(l.z);
                    let want = if c > 0.0 {
                        ol * ggx_d((1.0 + c) / 2.0, alpha) * c / z
                    } else {
                        0.0
                    };
                    let got = f64::from(img.chart_texel(chart, i, j).unwrap()[0]);
                    peak = peak.max(want);
                    assert!(
                        // f32 evaluation, with room to spare.
                        (got - want).abs() <= 1e-4 * want.max(1e-3),
                        "r {r} at {chart},{i},{j}: {got} vs {want}"
                    );
                }
            }
        }
        assert!(peak > 0.0);
    }
}

/// Relative RMS and bias of `a` against `b`.
fn error(a: &EnvImage, b: &EnvImage) -> (f64, f64) {
    let (mut se, mut ss, mut sd, mut sm) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for (p, q) in a.pixels().iter().zip(b.pixels()) {
        for c in 0..3 {
            let d = f64::from(p[c]) - f64::from(q[c]);
            se += d * d;
            ss += f64::from(q[c]).powi(2);
            sd += d;
            sm += f64::from(q[c]);
        }
    }
    ((se / ss).sqrt(), sd / sm)
}

#[test]
fn sampled_levels_are_within_their_bound_of_the_exact_sum() {
    // The built-in sky (a sun, split out) and room (sharp edges, lights),
    // at a base of 128² and a chain from 64²: every level within 1 %
    // relative RMS of the exact sum (the bound the bake states for sharp
    // environments).
    for env in [Builtin::Sky, Builtin::Room] {
        let src = env.image(cube_repr(), 6 * 128, 128).unwrap();
        let opts = {
            let mut o = BakeOptions::default();
            o.size = 64;
            o
        };
        let chain = specular_chain(&src, &opts, &|_, _| {}).unwrap();
        let exact = specular_chain(
            &src,
            &{
                let mut o = opts.clone();
                o.exact = true;
                o
            },
            &|_, _| {},
        )
        .unwrap();
        for (k, (a, b)) in chain.levels.iter().zip(&exact.levels).enumerate() {
            let (rms, bias) = error(a, b);
            println!(
                "{}: level {k} ({}², r {:.3}, {}): {:.3} % RMS, {:+.3} % bias",
                env.name(),
                chain.reports[k].size,
                chain.reports[k].roughness,
                chain.reports[k].method,
                100.0 * rms,
                100.0 * bias
            );
            assert!(rms < 0.01, "{} level {k}: {rms} {bias}", env.name());
        }
    }
}

#[test]
fn the_same_bytes_at_one_and_two_threads() {
    let src = Builtin::Sky.image(cube_repr(), 6 * 64, 64).unwrap();
    let opts = {
        let mut o = BakeOptions::default();
        o.size = 32;
        o
    };
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| specular_chain(&src, &opts, &|_, _| {}).unwrap())
    };
    let (a, b) = (run(1), run(2));
    for (x, y) in a.levels.iter().zip(&b.levels) {
        let bits = |i: &EnvImage| {
            i.pixels()
                .iter()
                .flat_map(|p| p.map(f32::to_bits))
                .collect::<Vec<_>>()
        };
        assert_eq!(bits(x), bits(y));
    }
}

#[test]
fn bad_input_gives_a_clear_result() {
    let opts = {
        let mut o = BakeOptions::default();
        o.size = 16;
        o
    };
    // Negative texels (a lossy EXR's ringing beside a sun): integrated as
    // they are, outputs clamped at zero and counted.
    let ringing = fill(cube_repr(), 6 * 128, 128, |d| {
        let d = d.normalize();
        let c = d.dot(Vec3::new(0.0, 0.0, 1.0));
        if c > 0.9995 {
            [3e4; 3]
        } else if c > 0.998 {
            [-3894.0; 3]
        } else {
            [0.2; 3]
        }
    })
    .unwrap();
    let chain = specular_chain(
        &ringing,
        &{
            let mut o = BakeOptions::default();
            o.size = 64;
            o
        },
        &|_, _| {},
    )
    .unwrap();
    let clamped: u64 = chain.reports.iter().map(|r| r.clamped).sum();
    assert!(clamped > 0, "{:?}", chain.reports);
    for l in &chain.levels {
        assert!(l
            .pixels()
            .iter()
            .flatten()
            .all(|c| c.is_finite() && *c >= 0.0));
    }
    // NaN and infinite texels: refused, with the count.
    let mut nan = fill(cube_repr(), 6 * 8, 8, |_| [1.0; 3]).unwrap();
    nan.set(3, 3, [f32::NAN, 0.0, 0.0]);
    nan.set(4, 3, [f32::INFINITY, 0.0, 0.0]);
    let e = specular_chain(&nan, &opts, &|_, _| {})
        .unwrap_err()
        .to_string();
    assert!(e.contains("2 texels"), "{e}");
    // All black: black, no NaN.
    let black = fill(cube_repr(), 6 * 8, 8, |_| [0.0; 3]).unwrap();
    let chain = specular_chain(&black, &opts, &|_, _| {}).unwrap();
    assert!(chain
        .levels
        .iter()
        .all(|l| l.pixels().iter().flatten().all(|c| *c == 0.0)));
    // A 1×1 cube as the source.
    let tiny = fill(cube_repr(), 6, 1, |d| {
        if d.z > 0.0 {
            [1.0; 3]
        } else {
            [0.5; 3]
        }
    })
    .unwrap();
    let chain = specular_chain(&tiny, &opts, &|_, _| {}).unwrap();
    assert_eq!(chain.levels.len(), 4);
    assert!(chain
        .levels
        .iter()
        .all(|l| l.pixels().iter().flatten().all(|c| c.is_finite())));
    // A sun of 10⁶: no inf or NaN anywhere, the energy kept: each level's
    // mean over the sphere equals the source's within the output texels'
    // own quadrature error.
    let sun = fill(cube_repr(), 6 * 64, 64, |d| {
        if d.normalize().dot(Vec3::new(0.3, 0.2, 0.93).normalize()) > 0.999 {
            [1e6; 3]
        } else {
            [0.1; 3]
        }
    })
    .unwrap();
    let chain = specular_chain(
        &sun,
        &{
            let mut o = BakeOptions::default();
            o.size = 32;
            o
        },
        &|_, _| {},
    )
    .unwrap();
    assert!(
        chain.bright.texels > 0 && chain.bright.energy_share > 0.5,
        "{:?}",
        chain.bright
    );
    for l in &chain.levels {
        assert!(l
            .pixels()
            .iter()
            .flatten()
            .all(|c| c.is_finite() && *c >= 0.0));
    }
    // The mean over the sphere of LD is the source's (∫ w(R·l) dR is the
    // same Z for every l), up to the output texels' own quadrature of LD.
    let mean = |img: &EnvImage| weighted_sum(img)[0] / total_weight(img);
    let source = mean(&sun);
    for (k, l) in chain.levels.iter().enumerate() {
        let rel = mean(l) / source - 1.0;
        println!(
            "sun 1e6: level {k} (roughness {:.2}): mean {rel:+.4} relative to the source's",
            chain.reports[k].roughness
        );
        // A 2² level has only 24 texels for a lobe around a sun: a looser
        // bound there.
        let bound = if chain.reports[k].size >= 4 {
            0.005
        } else {
            0.02
        };
        assert!(rel.abs() < bound, "level {k}: {rel}");
    }
    // Sizes that are not powers of two: each level halves (⌊n/2⌋).
    let chain = specular_chain(
        &sun,
        &{
            let mut o = BakeOptions::default();
            o.size = 24;
            o
        },
        &|_, _| {},
    )
    .unwrap();
    let sizes: Vec<u32> = chain.reports.iter().map(|r| r.size).collect();
    assert_eq!(sizes, [24, 12, 6, 3]);
}

#[test]
fn measure_level_agrees_with_the_full_comparison_and_sees_a_wrong_level() {
    // A sampled level of the sky measured against the oracle of its input on
    // a subset of its texels, against the same level compared with the
    // exact sum at every texel: the subset's error is the same size; a
    // level made 10 % too bright reads a bias of +10 %.
    let src = fill(cube_repr(), 6 * 64, 64, |d| Builtin::Sky.radiance(d)).unwrap();
    let oracle = Oracle::new(&src);
    let (p, b) = prepared(64, |d| Builtin::Sky.radiance(d));
    let t = Trilinear::new(&p);
    let r = 0.4;
    let sampled = level(&p, &t, &b, r, Method::Sampled { samples: 64 }, 16);
    let exact = level(
        &p,
        &t,
        &b,
        r,
        Method::Exact {
            level: exact_level(&p, r),
        },
        16,
    );
    let (full, _) = error(&sampled, &exact);
    let m = measure_level(&oracle, r, &sampled, 6 * 16 * 16, 1).unwrap();
    assert!(m.texels > 1000, "{m:?}");
    assert!(
        m.relative_rms > 0.25 * full && m.relative_rms < 4.0 * full && full > 0.0,
        "subset {m:?}, full {full}"
    );
    let mut bright = sampled.clone();
    for px in bright.pixels_mut() {
        *px = px.map(|c| c * 1.1);
    }
    let m = measure_level(&oracle, r, &bright, 200, 2).unwrap();
    assert!((m.bias - 0.1).abs() < 0.01, "{m:?}");
}
