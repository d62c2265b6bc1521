//! Irradiance (`envmap_render::filter::sh`) end to end: y-up bakes, the
//! irradiance maps against the exact cosine convolution, the exact mode's
//! level rule, determinism across thread counts, and Filament's `cmgen`
//! itself (ignored by default; `.ci/run` installs cmgen and runs it, and a
//! missing cmgen fails it):
//!
//! ```sh
//! apt-get install libfilament-tools
//! cargo test --release -p envmap-render --test irradiance -- --ignored --nocapture
//! ```

use std::path::Path;
use std::process::Command;

use envmap_core::glam::Vec3;
use envmap_core::{AnyMapping, Frame};
use envmap_render::filter::pyramid::Pyramid;
use envmap_render::filter::sh::{
    default_irradiance_representation, irradiance_cube, irradiance_map, irradiance_map_exact,
    relative_rms, sinc4_window, ExactLevel, IrradianceScale, Sh9, DEFAULT_EXACT_TOLERANCE,
};
use envmap_render::image::FileAxes;
use envmap_render::image::{load, save, LoadOptions, SaveOptions};
use envmap_render::image::{EnvImage, Representation};
use envmap_render::scene::{fill, smooth, sunny};

mod common;
use common::text;

/// Radiance 1 above the canonical horizon (z > 0), 0 below.
fn step(d: Vec3) -> [f32; 3] {
    if d.z > 0.0 {
        [1.0; 3]
    } else {
        [0.0; 3]
    }
}

/// 1 + a quadratic polynomial of the direction: band-limited to band 2,
/// so its SH9 irradiance has no truncation error at all.
fn quadratic(d: Vec3) -> [f32; 3] {
    let d = d.normalize();
    [
        1.0 + 0.5 * d.x + 0.3 * d.x * d.y,
        1.0 + 0.4 * d.z - 0.2 * (d.x * d.x - d.y * d.y),
        1.0 - 0.3 * d.y + 0.25 * (3.0 * d.z * d.z - 1.0),
    ]
}

fn latlong() -> Representation {
    Representation::for_file(AnyMapping::LatLong, FileAxes::default())
}

/// The default 32² GL irradiance cube's size.
const CUBE: (u32, u32) = (128, 96);

/// The latlong the convolution tests start from: 512 × 256 (the size of
/// the figures in `docs/lighting.md`), or 128 × 64 in an unoptimised
/// build, where the exact convolution over every texel would take minutes.
const SRC: (u32, u32) = if cfg!(debug_assertions) {
    (128, 64)
} else {
    (512, 256)
};

fn exact(p: &Pyramid, level: ExactLevel) -> EnvImage {
    let (w, h) = CUBE;
    let repr = default_irradiance_representation();
    irradiance_map_exact(p, repr, w, h, IrradianceScale::EOverPi, level)
        .unwrap()
        .image
}

#[test]
fn a_y_up_bake_of_a_bright_sky_is_brightest_on_plus_y() {
    // A latlong file in envmap's default conventions (the GL world, y up,
    // top row up) with a bright top half, as a file would load.
    let dir = tempfile::tempdir().unwrap();
    let mut img = EnvImage::new(256, 128, latlong()).unwrap();
    for (y, row) in img.rows_mut().enumerate() {
        row.fill(if y < 64 { [2.0, 3.0, 4.0] } else { [0.1; 3] });
    }
    let path = dir.path().join("sky.exr");
    save(&img, &path, &SaveOptions::default()).unwrap();
    let img = load(&path, &LoadOptions::default()).unwrap();
    let sh = Sh9::project(&img);
    let (a, b) = ([2.0f32, 3.0, 4.0], 0.1f32);
    for maps in [
        irradiance_cube(&sh, IrradianceScale::EOverPi).unwrap(),
        exact(
            &Pyramid::new(img.clone(), 1).unwrap(),
            ExactLevel::default(),
        ),
    ] {
        // The brightest texel of the cube, in every channel, is on the +y
        // face (chart 2), and so is the brightest face on average.
        let faces: Vec<_> = (0..6).map(|k| maps.chart_image(k).unwrap()).collect();
        for c in 0..3 {
            let max = |k: usize| {
                faces[k]
                    .pixels
                    .iter()
                    .map(|p| p[c])
                    .fold(f32::MIN, f32::max)
            };
            let mean = |k: usize| faces[k].pixels.iter().map(|p| f64::from(p[c])).sum::<f64>();
            for k in [0, 1, 3, 4, 5] {
                assert!(
                    max(2) > max(k),
                    "channel {c}: +y {} vs face {k} {}",
                    max(2),
                    max(k)
                );
                assert!(mean(2) > mean(k), "channel {c}: face {k}");
            }
            // E/π straight up is the bright radiance (the step's closed
            // form at n = up), within the texel's offset from the pole.
            let top = faces[2].pixels[16 * 32 + 16][c];
            assert!((top - a[c]).abs() < 0.01 * a[c], "channel {c}: {top}");
        }
    }
    let f = sh.filament_shader_form();
    // The closed form of a two-valued step (bright a above, dark b below):
    // E/π(n) = (a + b)/2 + (a − b)/2 · (n·up), and nothing else.
    for c in 0..3 {
        let (a, b) = (f64::from(a[c]), f64::from(b));
        assert!((f[0][c] - (a + b) / 2.0).abs() < 1e-4 * a, "{}", f[0][c]);
        assert!((f[1][c] - (a - b) / 2.0).abs() < 1e-4 * a, "{}", f[1][c]);
        for (i, fi) in f.iter().enumerate().skip(2) {
            assert!(fi[c].abs() < 1e-4 * a, "sh{i} {}", fi[c]);
        }
    }
}

#[test]
fn irradiance_maps_match_the_exact_convolution_where_sh9_allows() {
    // The oracle: the exact convolution over every texel (level 0) of a
    // 512 × 256 latlong. Truncation is what SH9 leaves out: zero for the
    // band-limited map and the step (whose higher bands all have Â_l = 0
    // or vanish), small for smooth() (under 0.5 %), large for the sun,
    // which SH9 cannot represent (printed, not required). Where truncation
    // is zero, what is left is the two sums' quadrature, of the order of
    // the texel's angle squared: allowed as (π/h)².
    let (w, h) = CUBE;
    let repr = default_irradiance_representation();
    let quadrature = (std::f64::consts::PI / f64::from(SRC.1)).powi(2);
    for (name, f, bound) in [
        ("quadratic", quadratic as fn(Vec3) -> [f32; 3], quadrature),
        ("step", step, quadrature),
        ("smooth", smooth, 5e-3),
        ("sun", sunny, f64::INFINITY),
    ] {
        let img = fill(latlong(), SRC.0, SRC.1, f).unwrap();
        let sh = Sh9::project(&img);
        let oracle = exact(&Pyramid::new(img, 1).unwrap(), ExactLevel::Level(0));
        for scale in [IrradianceScale::E, IrradianceScale::EOverPi] {
            let ours = irradiance_map(&sh, repr, w, h, scale).unwrap();
            let mut want = oracle.clone();
            if scale == IrradianceScale::E {
                for p in want.pixels_mut() {
                    *p = p.map(|v| v * std::f32::consts::PI);
                }
            }
            let e = relative_rms(&ours, &want);
            println!(
                "{name}: SH9 irradiance cube vs exact convolution ({}): {:.3} % relative RMS",
                scale.name(),
                100.0 * e
            );
            assert!(e < bound, "{name}: {e}");
        }
    }
}

#[test]
fn the_exact_modes_level_rule_stays_within_its_tolerance() {
    // Each automatic choice against the full-resolution convolution (a
    // 512 × 256 latlong's level 0): the accepted difference between two
    // successive levels bounds the finer one's error (on smooth maps its
    // error is a fraction of it).
    for (name, f) in [
        ("smooth", smooth as fn(Vec3) -> [f32; 3]),
        ("sun", sunny),
        ("step", step),
    ] {
        let p = Pyramid::new(fill(latlong(), SRC.0, SRC.1, f).unwrap(), 1).unwrap();
        let full = exact(&p, ExactLevel::Level(0));
        for tolerance in [DEFAULT_EXACT_TOLERANCE, 1e-4] {
            let (w, h) = CUBE;
            let repr = default_irradiance_representation();
            let got = irradiance_map_exact(
                &p,
                repr,
                w,
                h,
                IrradianceScale::EOverPi,
                ExactLevel::Auto { tolerance },
            )
            .unwrap();
            let e = relative_rms(&got.image, &full);
            let (cw, ch) = p.level(got.level).cell_size();
            println!(
                "{name}, tolerance {tolerance:.0e}: level {} ({cw}×{ch}), difference to the coarser {:.1e}, error vs level 0 {e:.1e}",
                got.level,
                got.difference.unwrap_or(0.0)
            );
            assert!(e <= tolerance, "{name}: {e}");
            if got.level > 0 {
                assert!(got.difference.unwrap() <= tolerance);
            }
        }
    }
}

#[test]
fn every_result_is_the_same_at_one_and_two_threads() {
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let ll = fill(latlong(), SRC.0, SRC.1, sunny).unwrap();
            let cube = fill(default_irradiance_representation(), 4 * 64, 3 * 64, sunny).unwrap();
            let (a, b) = (Sh9::project(&ll), Sh9::project(&cube));
            let map = irradiance_cube(&a, IrradianceScale::EOverPi).unwrap();
            let p = Pyramid::new(ll, 1).unwrap();
            let ex = exact(&p, ExactLevel::default());
            (a, b, map.into_pixels(), ex.into_pixels())
        })
    };
    let (one, two) = (run(1), run(2));
    let bits = |s: &Sh9| s.coeffs.map(|c| c.map(f64::to_bits));
    assert_eq!(bits(&one.0), bits(&two.0));
    assert_eq!(bits(&one.1), bits(&two.1));
    let fbits = |p: &[[f32; 3]]| p.iter().flatten().map(|v| v.to_bits()).collect::<Vec<_>>();
    assert_eq!(fbits(&one.2), fbits(&two.2));
    assert_eq!(fbits(&one.3), fbits(&two.3));
}

#[test]
fn frames_rotate_the_coefficients_as_they_rotate_the_map() {
    // The same environment (a function of canonical direction) stored in a
    // latlong turned by an arbitrary frame projects to the same canonical
    // coefficients, within the two grids' quadrature difference.
    let f = quadratic;
    let plain = Sh9::project(
        &fill(
            Representation::default_for(AnyMapping::LatLong),
            1024,
            512,
            f,
        )
        .unwrap(),
    );
    let mut turned_repr = Representation::default_for(AnyMapping::LatLong);
    turned_repr.frame = Frame::from_yaw_pitch_roll(0.7, 1.9, -0.4);
    let turned = Sh9::project(&fill(turned_repr, 1024, 512, f).unwrap());
    let l00 = plain.coeffs[0][0];
    for i in 0..9 {
        for c in 0..3 {
            let d = (plain.coeffs[i][c] - turned.coeffs[i][c]).abs() / l00;
            assert!(d < 1e-4, "{i} {c}: {d}");
        }
    }
}

// ---------------------------------------------------------------------------
// Against cmgen
// ---------------------------------------------------------------------------

/// cmgen's `--sh-output` text: nine lines `( r,  g,  b); // L.., ...`.
fn read_cmgen_sh(path: &Path) -> [[f64; 3]; 9] {
    let t = std::fs::read_to_string(path).unwrap();
    let rows: Vec<[f64; 3]> = t
        .lines()
        .filter_map(|l| {
            let inner = l.split_once('(')?.1.split_once(')')?.0;
            let v: Vec<f64> = inner
                .split(',')
                .map(|s| s.trim().parse().unwrap())
                .collect();
            Some([v[0], v[1], v[2]])
        })
        .collect();
    assert_eq!(rows.len(), 9, "{t}");
    core::array::from_fn(|i| rows[i])
}

fn cmgen_sh(dir: &Path, input: &Path, size: u32, window: bool) -> [[f64; 3]; 9] {
    let out = dir.join(format!("sh-{size}-{window}.txt"));
    let mut cmd = Command::new("cmgen");
    cmd.args(["-q", "--no-mirror", "--sh-shader"]);
    if !window {
        cmd.arg("--sh-window=no");
    }
    let o = cmd
        .arg(format!("--size={size}"))
        .arg(format!("--sh-output={}", out.display()))
        .arg(input)
        .output()
        .expect("run cmgen (apt-get install libfilament-tools)");
    assert!(o.status.success(), "{}", text(&o.stderr));
    read_cmgen_sh(&out)
}

/// The agreement asked of cmgen on a float file, relative to sh0. cmgen
/// projects its own cube, which it fills by averaging nearest input texels,
/// shifted by up to one input texel towards u = 1 and v = 1 (peers.md §1):
/// the environment turned by up to δ = 2π/W (W = 2048 here), which moves a
/// band-l coefficient by up to l·δ·|band l|. With |band 1| ≤ ½·sh0 and
/// |band 2| ≤ ¼·sh0 in these maps, that is at most δ·sh0.
const EXR_BOUND: f64 = 2.0 * std::f64::consts::PI / 2048.0;

#[test]
#[ignore = "needs Filament's cmgen (apt-get install libfilament-tools); run with cargo test --release -p envmap-render --test irradiance -- --ignored"]
fn the_filament_form_is_cmgens_sh() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // RGBE: Radiance's decoding is (m + ½)·2^(e − 136), the image crate's
    // m·2^(e − 136), so cmgen reads an .hdr up to ½/128 brighter than
    // envmap does (m ≥ 128): allowed for on top of the EXR bound.
    for (name, f, ext, bound) in [
        ("smooth", smooth as fn(Vec3) -> [f32; 3], "exr", EXR_BOUND),
        ("quadratic", quadratic, "exr", EXR_BOUND),
        ("smooth", smooth, "hdr", EXR_BOUND + 0.5 / 128.0),
    ] {
        // envmap writes the file (envmap's conventions are cmgen
        // --no-mirror's) and projects what it reads back; cmgen projects
        // its own cube of the same file.
        let path = d.join(format!("{name}.{ext}"));
        save(
            &fill(latlong(), 2048, 1024, f).unwrap(),
            &path,
            &SaveOptions::default(),
        )
        .unwrap();
        let ours =
            Sh9::project(&load(&path, &LoadOptions::default()).unwrap()).filament_shader_form();
        for size in [64, 256] {
            let theirs = cmgen_sh(d, &path, size, false);
            let scale = ours[0].iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let mut worst = (0.0, 0, 0);
            for i in 0..9 {
                for c in 0..3 {
                    let e = (ours[i][c] - theirs[i][c]).abs() / scale;
                    if e > worst.0 {
                        worst = (e, i, c);
                    }
                }
            }
            println!(
                "{name}.{ext}, cmgen --size={size}: worst |ours − cmgen| = {:.1e} × sh0 (sh{} channel {})",
                worst.0, worst.1, worst.2
            );
            for i in 0..9 {
                println!(
                    "  sh{i}: ours {:>10.6?}  cmgen {:>10.6?}",
                    ours[i], theirs[i]
                );
            }
            assert!(worst.0 < bound, "{name}.{ext} {size}: {worst:?}");
        }
        // cmgen's default window on this map, as the ratio of its windowed
        // to its plain coefficients: a sinc⁴ window, band by band.
        let plain = cmgen_sh(d, &path, 256, false);
        let auto = cmgen_sh(d, &path, 256, true);
        let ratio = |i: usize| {
            let c = (0..3)
                .max_by(|&a, &b| plain[i][a].abs().total_cmp(&plain[i][b].abs()))
                .unwrap();
            auto[i][c] / plain[i][c]
        };
        let (r1, r2) = (ratio(1), ratio(8));
        // The cutoff that gives band 1's factor, then band 2's from it.
        let (mut lo, mut hi) = (3.0f64, 30.0f64);
        for _ in 0..60 {
            let m = 0.5 * (lo + hi);
            if sinc4_window(1, m) < r1 {
                lo = m;
            } else {
                hi = m;
            }
        }
        println!("{name}: cmgen's default window: band 1 × {r1:.5}, band 2 × {r2:.5}: sinc⁴ of cutoff {lo:.4}, whose band 2 is {:.5}", sinc4_window(2, lo));
        assert!((sinc4_window(2, lo) - r2).abs() < 1e-4);
        assert!((ratio(0) - 1.0).abs() < 1e-6);
    }
}
