//! Mip pyramids of an environment map in any representation, and sampling
//! them at a fractional level.
//!
//! # Levels
//!
//! Level 0 is the image. Each next level halves every chart: its height
//! becomes ⌊h/2⌋ (at least 1), as GL's rule for odd sizes has it, and its
//! width follows the chart's shape (a cube face stays square, a latlong
//! 2:1). Each texel of a level is the average of the texels of the level
//! above that it covers, weighted by their exact solid angles
//! (`TexelWeights`): a cube face's 2 × 2 texels by their own solid angles, a
//! latlong's by their rows'. Where a size is odd, a texel covers parts of
//! texels; each part is weighted by the exact solid angle of the part
//! ([`Mapping::solid_angle`](envmap_core::Mapping::solid_angle) of the
//! overlap). So every level keeps the solid-angle-weighted mean of the
//! image, to f32 rounding, and a texel outside every chart (a cross's
//! corners, a disk's) stays black. On a disk
//! chart a texel whose centre is outside the disk holds no value and
//! weighs nothing, so there the mean is kept up to the rim's slivers.
//!
//! # Trilinear sampling
//!
//! [`Trilinear`] samples at a chart point and a fractional level `lod`:
//! bilinear at levels ⌊lod⌋ and ⌊lod⌋ + 1, each with its representation's
//! edge rule (`Sampler`: the cube seamless across faces and corners, the
//! latlong wrapping and crossing its poles, read from a copy of each chart
//! with a one-texel border that holds them), blended as
//! `a + f·(b − a)`, f = lod − ⌊lod⌋. `lod` is clamped to the levels (NaN is
//! level 0). Eight points at a time ([`Trilinear::sample8`]) gives each lane
//! exactly what [`Trilinear::sample`] gives it, bit for bit.

mod bordered;
mod halving;
mod levels;
mod trilinear;

#[cfg(test)]
use bordered::*;
#[cfg(test)]
use halving::*;
pub use levels::*;
pub use trilinear::*;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::filter::weights::TexelWeights;
    use crate::image::{EnvImage, Representation};
    use crate::scene::procedural::{fill, smooth};
    use envmap_core::atlas::{Atlas, Turn};
    use envmap_core::{AnyMapping, ChartUv, Mapping};
    use envmap_simd::Uv8;
    use wide::{f32x8, u32x8};

    #[test]
    fn chart_sizes_halve_by_the_gl_rule_keeping_their_shape() {
        assert_eq!(next_chart_size(512, 512, 1, 1), (256, 256));
        assert_eq!(next_chart_size(5, 5, 1, 1), (2, 2));
        assert_eq!(next_chart_size(1, 1, 1, 1), (1, 1));
        assert_eq!(next_chart_size(14, 7, 2, 1), (6, 3));
        assert_eq!(next_chart_size(6, 2, 3, 1), (3, 1));
    }

    #[test]
    fn a_constant_stays_constant_at_every_level_of_every_mapping() {
        for m in AnyMapping::ALL {
            let repr = Representation::default_for(m);
            let (w, h) = repr
                .atlas
                .image_size_for_cell_width(16 * repr.atlas.cell_aspect_w)
                .unwrap();
            let img = fill(repr, w, h, |_| [2.0, 3.0, 4.0]).unwrap();
            let p = Pyramid::new(img, 1).unwrap();
            assert_eq!(p.levels().last().unwrap().cell_size().1, 1, "{m}");
            for (k, l) in p.levels().iter().enumerate() {
                let s = l.stats();
                for c in 0..3 {
                    let want = [2.0, 3.0, 4.0][c];
                    assert!(
                        (s.sphere_mean[c] - want).abs() < 1e-5 * want,
                        "{m} level {k}: {:?}",
                        s.sphere_mean
                    );
                }
            }
        }
    }

    #[test]
    fn a_sampler_starting_at_a_level_reads_as_the_full_one_from_there() {
        let repr = Representation::default_for(AnyMapping::Cube);
        let (w, h) = repr.atlas.image_size_for_cell_width(32).unwrap();
        let p = Pyramid::new(fill(repr, w, h, smooth).unwrap(), 1).unwrap();
        let (full, from2) = (Trilinear::new(&p), Trilinear::starting_at(&p, 2));
        for chart in 0..6 {
            for k in 0..7 {
                let c = ChartUv::new(chart, (k as f32 + 0.3) / 7.0, (k as f32 * 0.61) % 1.0);
                for lod in [2.0, 2.3, 3.7, 5.0, 10.0] {
                    let (a, b) = (full.sample(c, lod), from2.sample(c, lod));
                    assert_eq!(a.map(f32::to_bits), b.map(f32::to_bits), "{c:?} {lod}");
                }
                // Finer than its first level: read at the first.
                let (a, b) = (full.sample(c, 2.0), from2.sample(c, 0.5));
                assert_eq!(a.map(f32::to_bits), b.map(f32::to_bits), "{c:?}");
            }
        }
    }

    /// Each texel of a level against the solid-angle-weighted mean of the
    /// four texels above it, summed in f64 from the map and its weights:
    /// the f32 sums with weights rounded to f32 stay within 4 f32 roundings
    /// of it (measured worst: printed), on every mapping whose size halves
    /// evenly, with positive and negative values, charts stored turned.
    #[test]
    fn a_level_is_the_f64_weighted_mean_to_a_few_f32_roundings() {
        use envmap_core::atlas::Atlas;
        let mut reprs: Vec<Representation> =
            AnyMapping::ALL.map(Representation::default_for).to_vec();
        reprs.push(Representation {
            atlas: Atlas::CUBE_VERTICAL_CROSS,
            ..Representation::default_for(AnyMapping::Cube)
        });
        let mut worst = (0.0f64, String::new());
        for repr in reprs {
            let m = repr.mapping;
            let (w, h) = repr
                .atlas
                .image_size_for_cell_width(16 * repr.atlas.cell_aspect_w)
                .unwrap();
            let img = fill(repr, w, h, |d| {
                [d.x * 3.0 + d.y, 0.25 + d.z * d.z, 1e3 * (1.5 + d.x * d.y)]
            })
            .unwrap();
            let (cw, ch) = img.cell_size();
            let weights = TexelWeights::new(m, cw, ch);
            let level = downsample(&img, &weights).unwrap();
            assert_eq!(level.cell_size(), (cw / 2, ch / 2), "{m}");
            for chart in 0..m.chart_count() {
                let (Some(above), Some(got)) = (img.chart_image(chart), level.chart_image(chart))
                else {
                    continue;
                };
                for j in 0..ch / 2 {
                    for i in 0..cw / 2 {
                        let taps = [(0, 0), (1, 0), (0, 1), (1, 1)]
                            .map(|(di, dj)| (2 * i + di, 2 * j + dj))
                            .map(|(x, y)| {
                                (
                                    weights.get(chart, x, y),
                                    above.pixels[(y * cw + x) as usize],
                                )
                            });
                        let sum: f64 = taps.iter().map(|t| t.0).sum();
                        if sum == 0.0 {
                            continue;
                        }
                        let g = got.pixels[(j * (cw / 2) + i) as usize];
                        for (c, &g) in g.iter().enumerate() {
                            let want: f64 =
                                taps.iter().map(|t| t.0 * f64::from(t.1[c])).sum::<f64>() / sum;
                            let size: f64 = taps
                                .iter()
                                .map(|t| t.0 * f64::from(t.1[c]).abs())
                                .sum::<f64>()
                                / sum;
                            let err = (f64::from(g) - want).abs() / size;
                            if err > worst.0 {
                                worst = (err, format!("{m} chart {chart} ({i}, {j}) channel {c}"));
                            }
                        }
                    }
                }
            }
        }
        println!("worst {:.2e} of the taps' size at {}", worst.0, worst.1);
        assert!(worst.0 <= 4.0 * f64::from(f32::EPSILON), "{worst:?}");
    }

    #[test]
    fn a_chart_stored_turned_halves_as_the_same_chart_stored_upright() {
        // The vertical cross stores −z turned by half a turn; the strip
        // stores every face upright. A level of one is the other's,
        // chart for chart, texel for texel.
        use envmap_core::atlas::Atlas;
        let cross = Representation {
            atlas: Atlas::CUBE_VERTICAL_CROSS,
            ..Representation::default_for(AnyMapping::Cube)
        };
        let (w, h) = cross.atlas.image_size_for_cell_width(48).unwrap();
        let a = fill(cross, w, h, |d| {
            [d.x.max(0.0) * 3.0 + d.y, d.z * d.z, 1.0 + d.x * d.y]
        })
        .unwrap();
        let b = a.relayout(Atlas::CUBE_HORIZONTAL_STRIP).unwrap();
        assert!((0..6).any(|c| cross.atlas.cell_of(c).unwrap().turn == Turn::Half));
        let weights = TexelWeights::new(AnyMapping::Cube, 48, 48);
        let (la, lb) = (
            downsample(&a, &weights).unwrap(),
            downsample(&b, &weights).unwrap(),
        );
        for chart in 0..6 {
            assert_eq!(
                la.chart_image(chart),
                lb.chart_image(chart),
                "chart {chart}"
            );
        }
    }

    #[test]
    fn a_level_made_into_another_atlas_holds_the_same_charts() {
        // The vertical cross's −z is stored turned, the strip's upright:
        // its level made into the strip is the level made in the cross.
        use envmap_core::atlas::Atlas;
        let cross = Representation {
            atlas: Atlas::CUBE_VERTICAL_CROSS,
            ..Representation::default_for(AnyMapping::Cube)
        };
        let (w, h) = cross.atlas.image_size_for_cell_width(16).unwrap();
        let a = fill(cross, w, h, smooth).unwrap();
        let weights = TexelWeights::new(AnyMapping::Cube, 16, 16);
        let own = downsample(&a, &weights).unwrap();
        let strip = downsample_to(&a, &weights, Atlas::CUBE_HORIZONTAL_STRIP).unwrap();
        for chart in 0..6 {
            assert_eq!(
                own.chart_image(chart),
                strip.chart_image(chart),
                "chart {chart}"
            );
        }
    }

    /// Maps whose levels the bordered tests make: (representation, chart
    /// width, the levels' atlas if not the map's, whether every level
    /// halves evenly): turned charts, a change of atlas, sizes that turn
    /// odd on the way down (40: 20, 10, 5, 2, 1; 24: 12, 6, 3, 1; 36: 18,
    /// 9, ...), the non-cube edge rules and a disk map; and a cube whose
    /// first level is made by every thread (more than `SMALL_LEVEL` texels)
    /// and the rest on one.
    fn level_cases() -> [(Representation, u32, Option<Atlas>, bool); 9] {
        let strip = Atlas::CUBE_HORIZONTAL_STRIP;
        let cube = |atlas| Representation {
            atlas,
            ..Representation::default_for(AnyMapping::Cube)
        };
        let other = Representation::default_for;
        [
            (cube(Atlas::CUBE_VERTICAL_CROSS), 32, Some(strip), true),
            (cube(Atlas::CUBE_HORIZONTAL_CROSS), 40, Some(strip), false),
            (cube(Atlas::CUBE_VERTICAL_CROSS), 24, None, false),
            (cube(Atlas::CUBE_HORIZONTAL_CROSS), 256, None, true),
            (other(AnyMapping::LatLong), 64, None, true),
            (other(AnyMapping::Octahedral), 24, None, false),
            (other(AnyMapping::Octahedral), 16, None, true),
            (other(AnyMapping::Tennisball), 36, None, false),
            (other(AnyMapping::SphereMap), 32, None, false),
        ]
    }

    #[test]
    fn levels_halved_into_their_borders_are_the_levels_bordered_afterwards() {
        for (repr, cell, atlas, _) in level_cases() {
            let m = repr.mapping;
            let atlas = atlas.unwrap_or(repr.atlas);
            let (w, h) = repr.atlas.image_size_for_cell_width(cell).unwrap();
            let map = fill(repr, w, h, |d| {
                [d.x.max(0.0) * 3.0 + d.y, d.z * d.z, 1.0 + d.x * d.y]
            })
            .unwrap();
            let (cw, ch) = map.cell_size();
            let weights = TexelWeights::new(m, cw, ch);
            let made = Pyramid::below(&map, &weights, atlas).unwrap();
            let mut want = Pyramid::new(downsample_to(&map, &weights, atlas).unwrap(), 1).unwrap();
            want.ready_from(0);
            assert_eq!(made.len(), want.len(), "{m} {cell}");
            assert!(made.ready == want.ready, "{m} {cell}");
            // A disk map's levels are read in place: kept as images, and
            // only those.
            match m.has_disk_charts() {
                true => assert!(made == want, "{m} {cell}"),
                false => assert!(made.levels.is_empty(), "{m} {cell}: an image kept"),
            }
        }
    }

    /// Levels made again in place for a second map of the same geometry
    /// are, bit for bit, the levels `below` makes of it, turned charts and
    /// a change of atlas included; where sizes turn odd or the map is a
    /// disk, nothing is made in place and the levels are left as they were.
    #[test]
    fn levels_remade_in_place_are_the_levels_made_anew() {
        const { assert!(6 * 128 * 128 > SMALL_LEVEL && 6 * 64 * 64 < SMALL_LEVEL) };
        for (repr, cell, atlas, even) in level_cases() {
            let m = repr.mapping;
            let atlas = atlas.unwrap_or(repr.atlas);
            let (w, h) = repr.atlas.image_size_for_cell_width(cell).unwrap();
            let first = fill(repr, w, h, |d| [d.x.max(0.0) * 3.0 + d.y, d.z * d.z, 1.0]).unwrap();
            let second = fill(repr, w, h, |d| [d.y * d.y, 2.0 - d.x, d.z.min(0.0)]).unwrap();
            let (cw, ch) = first.cell_size();
            let weights = TexelWeights::new(m, cw, ch);
            let mut levels = Pyramid::below(&first, &weights, atlas).unwrap();
            let sizes = levels.chart_sizes();
            let above: Vec<TexelWeights> = sizes[..sizes.len() - 1]
                .iter()
                .map(|&(w, h)| TexelWeights::new(m, w, h))
                .collect();
            let made = levels.remake_below(&second, &weights, &above);
            assert_eq!(made, even, "{m} {cell}");
            let want = if even { &second } else { &first };
            assert!(
                levels == Pyramid::below(want, &weights, atlas).unwrap(),
                "{m} {cell}"
            );
            // Weights of another size: nothing made.
            let wrong = TexelWeights::new(m, cw / 2, ch / 2);
            assert!(!levels.remake_below(&first, &wrong, &above), "{m} {cell}");
        }
    }

    /// A smooth map of `m`, charts 32 texels wide, and its pyramid from one
    /// level down.
    fn smooth_and_below(m: AnyMapping) -> (EnvImage, Pyramid) {
        let repr = Representation::default_for(m);
        let (w, h) = repr
            .atlas
            .image_size_for_cell_width(32 * repr.atlas.cell_aspect_w)
            .unwrap();
        let base = fill(repr, w, h, smooth).unwrap();
        let (cw, ch) = base.cell_size();
        let below = downsample(&base, &TexelWeights::new(m, cw, ch)).unwrap();
        (base, Pyramid::new(below, 1).unwrap())
    }

    #[test]
    fn ready_levels_read_as_the_sampler_that_makes_its_own_copies() {
        for m in [AnyMapping::Cube, AnyMapping::LatLong, AnyMapping::SphereMap] {
            let (base, below) = smooth_and_below(m);
            let mut ready = below.clone();
            ready.ready_from(0);
            assert_eq!(
                ready.ready.iter().all(Option::is_some),
                !m.has_disk_charts()
            );
            let (own, borrowed) = (
                Trilinear::over(&base, &below),
                Trilinear::over(&base, &ready),
            );
            assert_eq!(ready.len() + 1, own.levels(), "{m}");
            for chart in 0..m.chart_count() {
                for k in 0..9 {
                    let c = ChartUv::new(chart, (k as f32 + 0.3) / 9.0, (k as f32 * 0.61) % 1.0);
                    for lod in [0.0, 0.4, 1.0, 2.5, 9.0] {
                        assert_eq!(own.sample(c, lod), borrowed.sample(c, lod), "{m} {c:?}");
                    }
                }
            }
        }
    }

    /// The queue that samples batches some batches after asking for their
    /// texels puts every batch where it belongs, bit for bit what sampling
    /// each batch at once gives: more batches than the queue holds, short
    /// batches, lanes at different levels, a drain with a part-full queue.
    #[test]
    fn queued_batches_read_as_batches_read_at_once() {
        let (base, mut below) = smooth_and_below(AnyMapping::Cube);
        below.ready_from(0);
        let tri = Trilinear::over(&base, &below);
        let batches = 2 * TRILINEAR_AHEAD + 5;
        let mut want = vec![[0.0f32; 3]; 8 * batches];
        let mut got = vec![[f32::NAN; 3]; 8 * batches];
        let mut queue = TrilinearAhead::default();
        for b in 0..batches {
            let chart = u32x8::new(core::array::from_fn(|k| ((b + k) % 6) as u32));
            let u = f32x8::new(core::array::from_fn(|k| ((b * 8 + k) as f32 * 0.137) % 1.0));
            let v = f32x8::new(core::array::from_fn(|k| ((b * 5 + k) as f32 * 0.291) % 1.0));
            let lod = f32x8::new(core::array::from_fn(|k| ((b + 3 * k) % 11) as f32 * 0.45));
            let q = Uv8 { chart, u, v };
            // Every seventh batch is short.
            let n = if b % 7 == 3 { 5 } else { 8 };
            want[8 * b..8 * b + n].copy_from_slice(&tri.sample8(&q, lod)[..n]);
            queue.push(&tri, q, lod, (8 * b, n), &mut got);
        }
        queue.drain(&tri, &mut got);
        for (k, (g, w)) in got.iter().zip(&want).enumerate() {
            if k % 8 >= 5 && (k / 8) % 7 == 3 {
                assert!(g[0].is_nan(), "lane {k} beyond its batch was written");
                continue;
            }
            assert_eq!(g.map(f32::to_bits), w.map(f32::to_bits), "lane {k}");
        }
    }

    #[test]
    fn a_sampler_over_a_base_and_the_pyramid_below_reads_as_the_full_one() {
        for m in [AnyMapping::Cube, AnyMapping::LatLong, AnyMapping::SphereMap] {
            let (base, below) = smooth_and_below(m);
            let p = Pyramid::new(base.clone(), 1).unwrap();
            let (full, over) = (Trilinear::new(&p), Trilinear::over(&base, &below));
            assert_eq!(full.levels(), over.levels(), "{m}");
            for chart in 0..m.chart_count() {
                for k in 0..9 {
                    let c = ChartUv::new(chart, (k as f32 + 0.3) / 9.0, (k as f32 * 0.61) % 1.0);
                    for lod in [0.0, 0.4, 1.0, 2.5, 9.0] {
                        let (a, b) = (full.sample(c, lod), over.sample(c, lod));
                        for i in 0..3 {
                            assert!((a[i] - b[i]).abs() < 1e-5, "{m} {c:?} {lod}: {a:?} {b:?}");
                        }
                    }
                }
            }
        }
    }
}
