//! Mip-aware mirror lookups: the level follows the reflected ray's
//! footprint, a constant environment is unchanged by them, and a mirror
//! teapot at one sample per pixel comes closer to its supersampled
//! reference than plain bilinear lookups do.
//!
//! ```text
//! cargo test --release -p envmap-cli --test mip -- --nocapture
//! ```

use envmap_core::glam::Vec3;
use envmap_core::AnyMapping;
use envmap_render::image::linear_to_srgb;
use envmap_render::image::RgbImage;
use envmap_render::image::{EnvImage, Representation};
use envmap_render::scene::Builtin;
use envmap_render::scene::Material;
use envmap_render::scene::Mesh;
use envmap_render::scene::{fill, psnr, smooth};
use envmap_render::scene::{Camera, EnvSource, RenderOptions, Renderer, Shading};

mod common;
use common::{envmap, text};

fn cube(b: Builtin, face: u32) -> EnvImage {
    b.image(
        Representation::default_for(AnyMapping::Cube),
        4 * face,
        3 * face,
    )
    .unwrap()
}

fn teapot(env: EnvSource<'_>, samples: u32, mip: bool, background: bool) -> RgbImage {
    let opts = {
        let mut o = RenderOptions::default();
        o.width = 320;
        o.height = 240;
        o.samples = samples;
        o.mip = mip;
        o.background = background;
        o
    };
    Renderer::new()
        .render(&Mesh::teapot(10), env, &Camera::default(), &opts)
        .unwrap()
}

fn displayed(img: &RgbImage) -> Vec<[f32; 3]> {
    img.pixels
        .iter()
        .map(|p| p.map(|c| linear_to_srgb(c.clamp(0.0, 1.0))))
        .collect()
}

/// PSNR (displayed values, peak 1) of the 1-sample renders without and with
/// mip against the 4 × 4-supersampled plain one, over the teapot's pixels.
fn before_after(name: &str, env: &EnvImage) -> (f64, f64) {
    let reference = displayed(&teapot(EnvSource::Map(env), 4, false, true));
    let mask: Vec<bool> = teapot(EnvSource::Map(env), 1, false, false)
        .pixels
        .iter()
        .map(|p| p.iter().any(|c| *c > 0.0))
        .collect();
    let before = displayed(&teapot(EnvSource::Map(env), 1, false, true));
    let after = displayed(&teapot(EnvSource::Map(env), 1, true, true));
    let (b, a) = (
        psnr(&before, &reference, |k| mask[k], 1.0),
        psnr(&after, &reference, |k| mask[k], 1.0),
    );
    println!(
        "{name}: 1 spp bilinear {b:.2} dB, 1 spp mip {a:.2} dB ({:+.2} dB) vs 4x4 bilinear, {} teapot pixels",
        a - b,
        mask.iter().filter(|m| **m).count()
    );
    (b, a)
}

#[test]
fn mip_lookups_bring_one_sample_closer_to_the_supersampled_teapot() {
    let mut gains = Vec::new();
    for (name, b, face) in [
        ("sky cube 512²", Builtin::Sky, 512),
        ("sky cube 1024²", Builtin::Sky, 1024),
        ("room cube 512²", Builtin::Room, 512),
    ] {
        let env = cube(b, face);
        let (before, after) = before_after(name, &env);
        gains.push((name, after - before));
    }
    // The gain asked is 3 dB each (the gains themselves: docs/cli.md).
    for (name, g) in gains {
        assert!(g > 3.0, "{name}: {g:+.2} dB");
    }
}

/// The same against the sky itself, looked up exactly at 4 × 4 samples per
/// pixel: the map's own resolution now counts too.
#[test]
fn mip_lookups_bring_one_sample_closer_to_the_analytic_sky() {
    let sky = |d: Vec3| Builtin::Sky.radiance(d);
    let reference = displayed(&teapot(EnvSource::Analytic(&sky), 4, false, true));
    let mask: Vec<bool> = teapot(EnvSource::Analytic(&sky), 1, false, false)
        .pixels
        .iter()
        .map(|p| p.iter().any(|c| *c > 0.0))
        .collect();
    let env = cube(Builtin::Sky, 512);
    let before = displayed(&teapot(EnvSource::Map(&env), 1, false, true));
    let after = displayed(&teapot(EnvSource::Map(&env), 1, true, true));
    let (b, a) = (
        psnr(&before, &reference, |k| mask[k], 1.0),
        psnr(&after, &reference, |k| mask[k], 1.0),
    );
    println!(
        "sky cube 512² vs the analytic sky at 4x4: 1 spp bilinear {b:.2} dB, 1 spp mip {a:.2} dB ({:+.2} dB)",
        a - b
    );
    assert!(a - b > 3.0, "{b} → {a}");
}

/// Every level of a constant map is that constant, so mip-aware lookups
/// change nothing there, on the object or behind it.
#[test]
fn a_constant_environment_renders_the_same_with_and_without_mip() {
    for m in [
        AnyMapping::Cube,
        AnyMapping::LatLong,
        AnyMapping::Octahedral,
    ] {
        let repr = Representation::default_for(m);
        let (w, h) = repr
            .atlas
            .image_size_for_cell_width(64 * repr.atlas.cell_aspect_w)
            .unwrap();
        let env = fill(repr, w, h, |_| [0.25, 0.5, 0.75]).unwrap();
        let plain = teapot(EnvSource::Map(&env), 1, false, true);
        let mip = teapot(EnvSource::Map(&env), 1, true, true);
        let worst = plain
            .pixels
            .iter()
            .zip(&mip.pixels)
            .flat_map(|(a, b)| (0..3).map(move |c| (a[c] - b[c]).abs()))
            .fold(0.0f32, f32::max);
        assert!(worst < 1e-5, "{m}: {worst}");
    }
}

/// On a smooth map the mip-aware mirror differs from the plain one only a
/// little (its filtering); a material's shading (split sum or reference)
/// never reads the mirror's lookups, so the option leaves its object alone
/// bit for bit (which keeps the split sum at roughness 0 equal to the plain
/// mirror, `tests/lit.rs`).
#[test]
fn mip_leaves_a_smooth_mirror_close_and_materials_alone() {
    let env = fill(
        Representation::default_for(AnyMapping::Cube),
        4 * 128,
        3 * 128,
        smooth,
    )
    .unwrap();
    let plain = teapot(EnvSource::Map(&env), 1, false, false);
    let mip = teapot(EnvSource::Map(&env), 1, true, false);
    let p = psnr(
        &plain.pixels,
        &mip.pixels,
        |k| plain.pixels[k] != [0.0; 3],
        1.0,
    );
    println!("smooth cube 128²: plain vs mip mirror {p:.1} dB");
    assert!(p > 35.0, "{p}");
    let lit = |mip: bool| {
        let opts = {
            let mut o = RenderOptions::default();
            o.width = 80;
            o.height = 60;
            o.mip = mip;
            o.background = false;
            o.shading = Shading::Reference {
                material: Material::default(),
                samples: 2,
                light: None,
                seed: 0,
            };
            o
        };
        Renderer::new()
            .render(
                &Mesh::teapot(6),
                EnvSource::Map(&env),
                &Camera::default(),
                &opts,
            )
            .unwrap()
    };
    assert_eq!(lit(false).pixels, lit(true).pixels);
}

/// `envmap render` reads mip-aware by default and plainly with `--no-mip`:
/// both run, and give different pictures of the same scene.
#[test]
fn the_no_mip_flag_parses_and_changes_the_picture() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let common = [
        "--env",
        "sky",
        "--env-size",
        "256",
        "--width",
        "80",
        "--height",
        "60",
        "--samples",
        "1",
    ];
    let run = |out: &str, extra: &[&str]| {
        let args: Vec<&str> = ["render", out]
            .into_iter()
            .chain(common)
            .chain(extra.iter().copied())
            .collect();
        let o = envmap(&args, d);
        assert!(o.status.success(), "{args:?}: {}", text(&o.stderr));
        std::fs::read(d.join(out)).unwrap()
    };
    let (mip, plain) = (run("mip.exr", &[]), run("plain.exr", &["--no-mip"]));
    assert_ne!(mip, plain);
    assert_eq!(plain, run("plain2.exr", &["--no-mip"]));
}

/// A mirror that shrinks the map reads only its levels: in a cube map
/// checkered texel by texel (512² faces), a 40 × 30 view of the teapot
/// turns through several texels from one pixel to the next everywhere on
/// it, so every one of its pixels is a level's grey (about ½, the weighted
/// mean of 2 × 2 texels), never the base's black or white, while the plain
/// lookups show the checks. A lookup on the object whose footprint were
/// not measured (taken as 0, level 0) would show them too. A view this
/// small measures every footprint (its background is not kept at the
/// base); the render's list of the lookups on the object, used where it
/// is, has its own test (`the_lookups_on_the_object_are_listed_and_measured`).
#[test]
fn every_lookup_on_a_shrinking_mirror_reads_the_levels() {
    let repr = Representation::default_for(AnyMapping::Cube);
    let n = 512;
    let mut env = EnvImage::new(4 * n, 3 * n, repr).unwrap();
    let width = env.width() as usize;
    for (k, p) in env.pixels_mut().iter_mut().enumerate() {
        let (x, y) = (k % width, k / width);
        *p = [((x + y) % 2) as f32; 3];
    }
    let white = fill(repr, 4 * 8, 3 * 8, |_| [1.0; 3]).unwrap();
    let draw = |env: &EnvImage, mip: bool, background: bool| {
        let opts = {
            let mut o = RenderOptions::default();
            o.width = 40;
            o.height = 30;
            o.mip = mip;
            o.background = background;
            o
        };
        Renderer::new()
            .render(
                &Mesh::teapot(6),
                EnvSource::Map(env),
                &Camera::default(),
                &opts,
            )
            .unwrap()
            .pixels
    };
    let on_object: Vec<bool> = draw(&white, false, false)
        .iter()
        .map(|p| p[0] > 0.0)
        .collect();
    let count = on_object.iter().filter(|&&o| o).count();
    assert!(count > 200, "{count} teapot pixels");
    let off_grey = |img: &[[f32; 3]]| {
        img.iter()
            .zip(&on_object)
            .filter(|&(p, &o)| o && (p[0] - 0.5).abs() > 0.05)
            .count()
    };
    let (plain, mip) = (draw(&env, false, true), draw(&env, true, true));
    assert!(
        off_grey(&plain) > count / 4,
        "{} of {count}",
        off_grey(&plain)
    );
    assert_eq!(off_grey(&mip), 0, "of {count} teapot pixels");
}

/// Levels made beforehand render exactly what the render would build; a
/// set made from another map's size is not used (the render builds its own).
#[test]
fn prebuilt_mip_levels_render_the_same() {
    use envmap_render::scene::MipLevels;
    let env = cube(Builtin::Sky, 64);
    let other = cube(Builtin::Sky, 32);
    let (own, wrong) = (
        MipLevels::new(&env).unwrap(),
        MipLevels::new(&other).unwrap(),
    );
    assert!(own.fits(&env) && !wrong.fits(&env));
    let renderer = &mut Renderer::new();
    let built = draw_mip(renderer, &env, None);
    assert_eq!(draw_mip(renderer, &env, Some(&own)), built);
    assert_eq!(draw_mip(renderer, &env, Some(&wrong)), built);
}

/// A small mip-aware render of the teapot in `env` by `renderer`, from
/// `levels` if given.
fn draw_mip(
    renderer: &mut Renderer,
    env: &EnvImage,
    levels: Option<&envmap_render::scene::MipLevels>,
) -> Vec<[f32; 3]> {
    renderer
        .render(
            &Mesh::teapot(6),
            EnvSource::Map(env),
            &Camera::default(),
            &{
                let mut o = RenderOptions::default();
                o.width = 80;
                o.height = 60;
                o.mip = true;
                o.mip_levels = levels;
                o
            },
        )
        .unwrap()
        .pixels
}

/// Levels made again for another map of the same geometry (in place) or of
/// another size or one whose levels turn odd (anew) render what levels made
/// for that map render, bit for bit, and so does a renderer that builds its
/// own (into the levels it built for its last render, or anew: a renderer
/// new to the map).
#[test]
fn rebuilt_mip_levels_render_as_levels_made_anew() {
    use envmap_render::scene::MipLevels;
    let (sky, room) = (cube(Builtin::Sky, 64), cube(Builtin::Room, 64));
    let small = cube(Builtin::Room, 32);
    // 48² faces: 24, 12, 6, 3, 1: levels that cannot be made in place.
    let odd = cube(Builtin::Sky, 48);
    let (reused, given) = (&mut Renderer::new(), &mut Renderer::new());
    let mut levels = MipLevels::new(&sky).unwrap();
    assert_eq!(
        draw_mip(given, &sky, Some(&levels)),
        draw_mip(reused, &sky, None)
    );
    for env in [&room, &sky, &small, &room, &odd, &odd, &sky] {
        levels.rebuild(env).unwrap();
        assert!(levels.fits(env));
        let fresh = MipLevels::new(env).unwrap();
        let again = draw_mip(given, env, Some(&levels));
        let anew = draw_mip(given, env, Some(&fresh));
        assert!(again == anew, "rebuilt levels render otherwise");
        assert!(again == draw_mip(reused, env, None));
        assert!(again == draw_mip(&mut Renderer::new(), env, None));
    }
}
