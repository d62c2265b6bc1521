//! Conversions between every pair of representations, measured against the
//! exact values of a procedural environment.

use envmap_core::cube::{face_direction, CubeFace};
use envmap_core::glam::Vec3;
use envmap_core::texel::texel_center;
use envmap_core::{AnyMapping, Atlas, Frame, Mapping};
use envmap_render::filter::sample::Filter;
use envmap_render::filter::{convert, ConvertOptions};
use envmap_render::image::{EnvImage, Representation};
use envmap_render::scene::{fill, psnr, smooth};

/// Image size for a representation with cells `cell` texels wide (the
/// tennisball needs a multiple of 3).
fn size(repr: &Representation, cell: u32) -> (u32, u32) {
    let cell = if repr.atlas.cell_aspect_w == 3 {
        cell / 3 * 3
    } else {
        cell
    };
    repr.atlas.image_size_for_cell_width(cell).unwrap()
}

fn covered(img: &EnvImage) -> impl Fn(usize) -> bool + '_ {
    let (w, h) = (img.width(), img.height());
    let repr = *img.representation();
    move |k| {
        let (x, y) = ((k as u32) % w, (k as u32) / w);
        repr.atlas.texel_to_chart(x, y, w, h).is_some_and(|t| {
            repr.mapping
                .in_chart(t.chart, texel_center(t.i, t.w), texel_center(t.j, t.h))
        })
    }
}

/// The PSNR bound every pair must reach at these sizes (input cells 192
/// texels wide, output 96, bilinear, automatic supersampling); the smooth
/// environment spans about 1, so 50 dB is an RMS error of 0.3 % of it
/// (the measured PSNR of each pair: `docs/accuracy.md`).
const MIN_PSNR_DB: f64 = 50.0;

/// From a sphere map the bound is lower: the neighbourhood of its singular
/// direction is squeezed into the outermost ring, so any output that samples
/// that neighbourhood finely (a latlong's top rows, for the class
/// convention's +z) sees the rim's lack of resolution: a latlong output
/// most, everything else less, but the angular map with the GL sphere map
/// ([`MIN_PSNR_SPHERE_GL_TO_ANGULAR_DB`]).
const MIN_PSNR_FROM_SPHERE_DB: f64 = 38.0;

/// From the GL sphere map into the angular map, both singular at −z: the
/// angular map gives −z's neighbourhood the most texels of any output (the
/// 0.31 rad around −z are its outer tenth of radius, 19 % of its texels,
/// against 10 % of a latlong's rows), and the sphere map squeezes those
/// 0.31 rad into the outer 1.2 texels of its 96-texel radius. The ratio of
/// those texel shares puts it 10·log10(0.19/0.10) = 2.8 dB below
/// sphere-gl -> latlong. (The class sphere map's singular direction, +z, is
/// the angular map's centre, and meets the general bound.)
const MIN_PSNR_SPHERE_GL_TO_ANGULAR_DB: f64 = 35.0;

/// From one 180° fisheye into the class sphere map: the sphere map's singular direction (its
/// whole rim) is the lens's axis, so its outer ring of texels, each averaging a wide piece of
/// the view around the axis against the exact value at its centre, is where the error is (up
/// to 0.07 next to the rim, as for every input into the sphere map); and only the half of the
/// sphere map that the lens sees is compared, so that ring weighs twice as much in the RMS:
/// 10·log10(2) = 3 dB below the other inputs' 52–55 dB.
const MIN_PSNR_FISHEYE_TO_SPHERE_DB: f64 = 47.0;

/// Where `to`'s texel `k` looks, in `from`'s axes: its centre and those of its corners that
/// are inside the chart; empty outside every chart.
fn looks_at(to: &EnvImage, from: &Representation, k: usize) -> Vec<Vec3> {
    let (w, h) = (to.width(), to.height());
    let repr = to.representation();
    let (x, y) = ((k as u32) % w, (k as u32) / w);
    let Some(t) = repr.atlas.texel_to_chart(x, y, w, h) else {
        return Vec::new();
    };
    let (u0, v0) = (t.i as f32 / t.w as f32, t.j as f32 / t.h as f32);
    let (u1, v1) = ((t.i + 1) as f32 / t.w as f32, (t.j + 1) as f32 / t.h as f32);
    let centre = (texel_center(t.i, t.w), texel_center(t.j, t.h));
    [centre, (u0, v0), (u1, v0), (u0, v1), (u1, v1)]
        .into_iter()
        .filter_map(|(u, v)| {
            repr.mapping
                .inverse(envmap_core::ChartUv::new(t.chart, u, v))
        })
        .map(|d| from.frame.matrix().transpose() * (repr.frame.matrix() * d))
        .collect()
}

#[test]
fn every_pair_against_exact_values() {
    let mut worst = (f64::INFINITY, String::new());
    let mut failures = Vec::new();
    for from in AnyMapping::ALL {
        let rin = Representation::default_for(from);
        let (w, h) = size(&rin, 192);
        let src = fill(rin, w, h, smooth).unwrap();
        for to in AnyMapping::ALL {
            let rout = Representation::default_for(to);
            let (ow, oh) = size(&rout, 96);
            let got = convert(&src, rout, ow, oh, &ConvertOptions::default(), None).unwrap();
            let want = fill(rout, ow, oh, smooth).unwrap();
            // From a fisheye that sees part of the sphere: compared on the texels it sees
            // whole (centre and corners three of its texels inside the rim, where the
            // bilinear footprint is whole); black on those it does not see at all.
            let margin = 3.0 * std::f64::consts::PI / f64::from(w.min(h));
            let inside = covered(&want);
            let seen = |k: usize| {
                inside(k)
                    && looks_at(&want, &rin, k)
                        .into_iter()
                        .all(|d| envmap_tests::past_rim(from, d).is_none_or(|p| p < -margin))
            };
            for (k, px) in got.pixels().iter().enumerate() {
                let dirs = looks_at(&want, &rin, k);
                let unseen = !dirs.is_empty()
                    && dirs
                        .into_iter()
                        .all(|d| envmap_tests::past_rim(from, d).is_some_and(|p| p > margin));
                if unseen && *px != [0.0; 3] {
                    failures.push(format!("{from} -> {to}: texel {k} unseen but {px:?}"));
                    break;
                }
            }
            let p = psnr(got.pixels(), want.pixels(), seen, 1.0);
            println!("{from:>22} -> {to:<22} {p:6.1} dB");
            if p < worst.0 {
                worst = (p, format!("{from} -> {to}"));
            }
            let bound = match (from, to) {
                (AnyMapping::SphereMapGl, AnyMapping::Angular) => MIN_PSNR_SPHERE_GL_TO_ANGULAR_DB,
                (AnyMapping::SphereMap | AnyMapping::SphereMapGl, _) => MIN_PSNR_FROM_SPHERE_DB,
                (AnyMapping::Fisheye(f), AnyMapping::SphereMap) if !f.covers_sphere() => {
                    MIN_PSNR_FISHEYE_TO_SPHERE_DB
                }
                _ => MIN_PSNR_DB,
            };
            if p < bound {
                failures.push(format!("{from} -> {to}: {p:.1} dB"));
            }
        }
    }
    println!("worst: {:.1} dB ({})", worst.0, worst.1);
    assert!(failures.is_empty(), "{failures:#?}");
}

#[test]
fn latlong_cube_latlong_round_trip() {
    let rl = Representation::default_for(AnyMapping::LatLong);
    let src = fill(rl, 512, 256, smooth).unwrap();
    for layout in [
        Atlas::CUBE_HORIZONTAL_CROSS,
        Atlas::CUBE_VERTICAL_CROSS,
        Atlas::CUBE_HORIZONTAL_STRIP,
        Atlas::CUBE_VERTICAL_STRIP,
    ] {
        let rc = Representation::new(AnyMapping::Cube, layout, Frame::IDENTITY).unwrap();
        let (cw, ch) = layout.image_size_for_cell_width(128).unwrap();
        let cube = convert(&src, rc, cw, ch, &ConvertOptions::default(), None).unwrap();
        let back = convert(&cube, rl, 512, 256, &ConvertOptions::default(), None).unwrap();
        let p = psnr(back.pixels(), src.pixels(), |_| true, 1.0);
        println!("latlong -> cube ({}) -> latlong: {p:.1} dB", layout.name);
        assert!(p > 45.0, "{}: {p:.1} dB", layout.name);
    }
}

/// Encodes the direction itself as the colour, so a texel's value says which
/// direction it was sampled from.
fn direction_colour(d: Vec3) -> [f32; 3] {
    let d = d.normalize();
    [d.x, d.y, d.z]
}

#[test]
fn cube_texels_follow_the_gl_face_table() {
    let rl = Representation::default_for(AnyMapping::LatLong);
    let src = fill(rl, 2048, 1024, direction_colour).unwrap();
    let rc = Representation::new(
        AnyMapping::Cube,
        Atlas::CUBE_HORIZONTAL_STRIP,
        Frame::IDENTITY,
    )
    .unwrap();
    let n = 16;
    let cube = convert(&src, rc, 6 * n, n, &ConvertOptions::default(), None).unwrap();
    for face in CubeFace::ALL {
        for j in 0..n {
            for i in 0..n {
                let sc = 2.0 * texel_center(i, n) - 1.0;
                let tc = 2.0 * texel_center(j, n) - 1.0;
                let want = face_direction(face, sc, tc).normalize();
                let got = cube.pixels()[(j * 6 * n + face as u32 * n + i) as usize];
                let got = Vec3::from(got);
                assert!(
                    (got - want).length() < 2e-3,
                    "face {} texel ({i}, {j}): {got} vs {want}",
                    face.name()
                );
            }
        }
    }
}

/// Across every cube edge, the texels on both sides continue smoothly: the
/// difference across the edge is no larger than between neighbours inside a face.
#[test]
fn no_seams_across_cube_edges_or_the_latlong_wrap() {
    let rl = Representation::default_for(AnyMapping::LatLong);
    let src = fill(rl, 1024, 512, smooth).unwrap();
    let n = 64u32;
    let rc = Representation::new(
        AnyMapping::Cube,
        Atlas::CUBE_HORIZONTAL_STRIP,
        Frame::IDENTITY,
    )
    .unwrap();
    let cube = convert(&src, rc, 6 * n, n, &ConvertOptions::default(), None).unwrap();
    // For each face's right edge texel (i = n−1), find the texel across the
    // edge by following the face plane one texel further, then compare the
    // jump with the smooth function's own change over one texel.
    let px =
        |face: u32, i: u32, j: u32| Vec3::from(cube.pixels()[(j * 6 * n + face * n + i) as usize]);
    let mut worst: f32 = 0.0;
    for face in CubeFace::ALL {
        for j in 0..n {
            for (i, di) in [(n - 1, 1i32), (0, -1)] {
                let sc = 2.0 * ((i as f32 + di as f32 + 0.5) / n as f32) - 1.0;
                let tc = 2.0 * texel_center(j, n) - 1.0;
                let d = face_direction(face, sc, tc);
                let p = envmap_core::Cube::forward(d).unwrap();
                assert_ne!(p.chart, face as u32);
                let other = px(
                    p.chart,
                    envmap_core::texel::texel_index(p.u, n),
                    envmap_core::texel::texel_index(p.v, n),
                );
                let jump = (px(face as u32, i, j) - other).abs().max_element();
                let inner = (px(face as u32, i, j) - px(face as u32, (i as i32 - di) as u32, j))
                    .abs()
                    .max_element();
                worst = worst.max(jump - 2.0 * inner);
                assert!(
                    jump <= 2.0 * inner + 1e-3,
                    "face {} j {j}: jump {jump} inner {inner}",
                    face.name()
                );
            }
        }
    }
    println!("worst excess jump across a cube edge: {worst:e}");
    // The latlong wrap: column 0 and column w−1 are neighbours.
    let ll = convert(&cube, rl, 256, 128, &ConvertOptions::default(), None).unwrap();
    for y in 0..128u32 {
        let a = Vec3::from(ll.pixels()[(y * 256) as usize]);
        let b = Vec3::from(ll.pixels()[(y * 256 + 255) as usize]);
        let c = Vec3::from(ll.pixels()[(y * 256 + 1) as usize]);
        assert!(
            (a - b).abs().max_element() <= 2.0 * (a - c).abs().max_element() + 1e-3,
            "row {y}"
        );
    }
}

#[test]
fn nearest_and_explicit_samples_work() {
    let rl = Representation::default_for(AnyMapping::LatLong);
    let src = fill(rl, 256, 128, smooth).unwrap();
    let ro = Representation::default_for(AnyMapping::Octahedral);
    for (filter, samples) in [(Filter::Nearest, Some(1)), (Filter::Bilinear, Some(3))] {
        let opts = {
            let mut o = ConvertOptions::default();
            o.filter = filter;
            o.samples = samples;
            o.rotation = None;
            o.cancel = None;
            o
        };
        let got = convert(&src, ro, 64, 64, &opts, None).unwrap();
        let want = fill(ro, 64, 64, smooth).unwrap();
        let p = psnr(got.pixels(), want.pixels(), |_| true, 1.0);
        assert!(p > 30.0, "{filter:?} {samples:?}: {p:.1} dB");
    }
}

#[test]
fn rotation_on_the_way() {
    // Rotating by yaw 90° about +z: output direction d reads the input at Rz·d.
    let rl = Representation::default_for(AnyMapping::LatLong);
    let src = fill(rl, 512, 256, direction_colour).unwrap();
    let rot = Frame::from_yaw_pitch_roll(std::f32::consts::FRAC_PI_2, 0.0, 0.0);
    let opts = {
        let mut o = ConvertOptions::default();
        o.rotation = Some(rot);
        o
    };
    let got = convert(&src, rl, 512, 256, &opts, None).unwrap();
    let want = fill(rl, 512, 256, |d| direction_colour(rot.to_canonical(d))).unwrap();
    let p = psnr(got.pixels(), want.pixels(), |_| true, 1.0);
    assert!(p > 45.0, "{p:.1} dB");
}

/// A z-up latlong converted to a cube for GL (y up): the cube's +y face shows
/// the latlong's top row (the sky), its +z face what the latlong has at −y.
#[test]
fn frames_put_up_where_each_convention_has_it() {
    let rl = Representation::default_for(AnyMapping::LatLong);
    let src = fill(rl, 512, 256, direction_colour).unwrap();
    let rc = Representation::new(
        AnyMapping::Cube,
        Atlas::CUBE_HORIZONTAL_STRIP,
        Frame::Y_UP_RH,
    )
    .unwrap();
    let n = 9; // odd, so the middle texel is the face centre
    let cube = convert(&src, rc, 6 * n, n, &ConvertOptions::default(), None).unwrap();
    let centre =
        |face: u32| Vec3::from(cube.pixels()[((n / 2) * 6 * n + face * n + n / 2) as usize]);
    // GL +y face (2) sees world +z (up); GL +z (4) sees world −y.
    assert!(
        (centre(2) - Vec3::new(0.0, 0.0, 1.0)).length() < 1e-2,
        "{}",
        centre(2)
    );
    assert!(
        (centre(4) - Vec3::new(0.0, -1.0, 0.0)).length() < 1e-2,
        "{}",
        centre(4)
    );
    // And fill agrees: the same cube made directly.
    let direct = fill(rc, 6 * n, n, direction_colour).unwrap();
    let p = psnr(cube.pixels(), direct.pixels(), |_| true, 1.0);
    assert!(p > 40.0, "{p:.1} dB");
}

/// The conversion texel by texel with the scalar core and the scalar
/// sampler: for each output texel inside a chart, its N×N sub-samples inside
/// the chart, inverse-mapped, forward-mapped into the input and sampled, then
/// averaged (black where none is inside).
fn reference(src: &EnvImage, repr: Representation, w: u32, h: u32, n: u32) -> Vec<[f32; 3]> {
    use envmap_core::atlas::Turn;
    use envmap_core::ChartUv;
    use envmap_render::filter::sample::Sampler;
    let shape = EnvImage::new(w, h, repr).unwrap();
    let (cw, ch) = shape.cell_size();
    let sampler = Sampler::new(src);
    let mut out = vec![[0.0f32; 3]; (w * h) as usize];
    for y in 0..h {
        for x in 0..w {
            let Some(cell) = repr.atlas.cell_at(x / cw, y / ch) else {
                continue;
            };
            let (lx, ly) = (x % cw, y % ch);
            let (i, j) = match cell.turn {
                Turn::Half => (cw - 1 - lx, ch - 1 - ly),
                Turn::None => (lx, ly),
            };
            let at = |k: u32, a: u32, len: u32| {
                ((f64::from(k) + (f64::from(a) + 0.5) / f64::from(n)) / f64::from(len)) as f32
            };
            let (mut acc, mut count) = ([0.0f32; 3], 0u32);
            for b in 0..n {
                for a in 0..n {
                    let (u, v) = (at(i, a, cw), at(j, b, ch));
                    if !repr.mapping.in_chart(cell.chart, u, v) {
                        continue;
                    }
                    count += 1;
                    let d = repr.mapping.inverse(ChartUv::new(cell.chart, u, v));
                    let Some(q) = d.and_then(|d| src.mapping().forward(d)) else {
                        continue;
                    };
                    let s = sampler.sample(q, Filter::Bilinear);
                    for (c, s) in acc.iter_mut().zip(s) {
                        *c += s;
                    }
                }
            }
            if count > 0 {
                out[(y * w + x) as usize] = acc.map(|c| c / count as f32);
            }
        }
    }
    out
}

/// Sizes that are not multiples of eight (the lanes) or of the tile width,
/// every kind of chart (a cross's empty cells, the vertical cross's
/// half-turned face, disks, the tennisball's strips) and one, two and three
/// sub-samples per side: every texel lands where the texel-by-texel
/// reference puts it, with the same value up to the eight-lane kernels'
/// error (fine tier).
#[test]
fn odd_sizes_and_sub_samples_match_a_texel_by_texel_reference() {
    let rin = Representation::default_for(AnyMapping::LatLong);
    let src = fill(rin, 192, 96, smooth).unwrap();
    let cube = |atlas| Representation::new(AnyMapping::Cube, atlas, Frame::IDENTITY).unwrap();
    let cases = [
        (cube(Atlas::CUBE_HORIZONTAL_CROSS), 37, 1),
        (cube(Atlas::CUBE_VERTICAL_CROSS), 21, 2),
        (Representation::default_for(AnyMapping::SphereMap), 45, 1),
        (Representation::default_for(AnyMapping::SphereMapGl), 29, 3),
        (Representation::default_for(AnyMapping::Angular), 43, 2),
        (
            Representation::default_for(AnyMapping::DualParaboloid),
            35,
            2,
        ),
        (Representation::default_for(AnyMapping::LatLong), 74, 1),
        (Representation::default_for(AnyMapping::Tennisball), 39, 2),
        (
            Representation::default_for(AnyMapping::EqualAreaOctahedral),
            41,
            3,
        ),
    ];
    for (repr, cell, n) in cases {
        let (w, h) = repr.atlas.image_size_for_cell_width(cell).unwrap();
        let opts = {
            let mut o = ConvertOptions::default();
            o.samples = Some(n);
            o
        };
        let got = convert(&src, repr, w, h, &opts, None).unwrap();
        let want = reference(&src, repr, w, h, n);
        let (mut worst, mut at) = (0.0f32, 0);
        for (k, (g, e)) in got.pixels().iter().zip(&want).enumerate() {
            let d = (0..3).map(|c| (g[c] - e[c]).abs()).fold(0.0, f32::max);
            if d > worst {
                (worst, at) = (d, k);
            }
        }
        println!(
            "{} {w}×{h}, {n}×{n}: worst {worst:.2e} at ({}, {})",
            repr.mapping,
            at as u32 % w,
            at as u32 / w
        );
        assert!(
            worst < 1e-5,
            "{} {w}×{h}, {n}×{n}: {worst:.2e} at texel ({}, {})",
            repr.mapping,
            at as u32 % w,
            at as u32 / w
        );
    }
}
