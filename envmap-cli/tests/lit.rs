//! Lit renders: the split sum from baked maps against closed forms, against
//! the mirror it must reduce to, and against the Monte Carlo reference;
//! `envmap render --material` and `--reference`.

mod common;

use envmap_core::glam::Vec3;
use envmap_core::AnyMapping;
use envmap_render::filter::bake::{bake, BakeOptions};
use envmap_render::filter::sh::IrradianceScale;
use envmap_render::image::FileAxes;
use envmap_render::image::{EnvImage, Representation, RgbImage};
use envmap_render::scene::LitEnvironment;
use envmap_render::scene::Material;
use envmap_render::scene::Mesh;
use envmap_render::scene::{fill, psnr, smooth};
use envmap_render::scene::{Camera, EnvSource, Mode, RenderOptions, Renderer, Shading};

/// `f` in a cube of `face`² texels (GL axes) and its bake at `size`.
fn baked(f: impl Fn(Vec3) -> [f32; 3] + Sync, face: u32, size: u32) -> (EnvImage, LitEnvironment) {
    baked_to(f, face, size, None)
}

/// As [`baked`], the chain stopping at `min_size`.
fn baked_to(
    f: impl Fn(Vec3) -> [f32; 3] + Sync,
    face: u32,
    size: u32,
    min_size: Option<u32>,
) -> (EnvImage, LitEnvironment) {
    let repr = Representation::default_for(AnyMapping::Cube);
    let (w, h) = repr.atlas.image_size_for_cell_width(face).unwrap();
    let env = fill(repr, w, h, f).unwrap();
    let opts = {
        let mut o = BakeOptions::default();
        o.size = size;
        o.min_size = min_size;
        o.axes = FileAxes::Frame(env.representation().frame);
        o.irradiance_size = 32;
        o.dfg_size = 64;
        o
    };
    let b = bake(&env, &opts, &|_, _| {}).unwrap();
    let chain = b.chain.unwrap();
    let roughness = chain.reports.iter().map(|r| r.roughness).collect();
    let lit = LitEnvironment::new(
        chain.levels,
        roughness,
        b.irradiance.unwrap().image,
        IrradianceScale::EOverPi,
        b.dfg.unwrap(),
    )
    .unwrap();
    (env, lit)
}

fn mat(base: f32, metallic: f32, roughness: f32) -> Material {
    Material::new([base; 3], metallic, roughness)
}

fn sphere() -> Mesh {
    let mut m = Mesh::sphere(1.5, 96, 48);
    for p in &mut m.positions {
        *p += Vec3::new(0.0, 0.0, 1.4);
    }
    m
}

fn cam() -> Camera {
    Camera {
        eye: Vec3::new(0.0, -7.0, 1.4),
        target: Vec3::new(0.0, 0.0, 1.4),
        up: Vec3::Z,
        fov_y_deg: 30.0,
    }
}

fn draw(env: EnvSource<'_>, shading: Shading<'_>, size: u32) -> RgbImage {
    draw_in(env, shading, size, Mode::PerPixel)
}

fn draw_in(env: EnvSource<'_>, shading: Shading<'_>, size: u32, mode: Mode) -> RgbImage {
    let opts = {
        let mut o = RenderOptions::default();
        o.width = size;
        o.height = size;
        o.mode = mode;
        o.samples = 1;
        o.background = false;
        o.shading = shading;
        o
    };
    Renderer::new()
        .render(&sphere(), env, &cam(), &opts)
        .unwrap()
}

/// A white Lambertian sphere in a constant environment L reflects L
/// everywhere: the diffuse term (white minus black, the specular terms being
/// equal) is L at every pixel, which checks that the map holds E/π and that
/// it is used as such.
#[test]
fn a_white_diffuse_sphere_in_a_constant_sky_is_that_sky() {
    let l = 0.7f32;
    let (env, lit) = baked(|_| [l; 3], 32, 32);
    let s = lit.sampler();
    for d in [
        Vec3::X,
        Vec3::Z,
        -Vec3::Z,
        Vec3::new(0.3, -0.5, 0.8).normalize(),
    ] {
        let e = s.irradiance_over_pi(d);
        assert!(e.iter().all(|&x| (x - l).abs() < 1e-4 * l), "{d}: {e:?}");
    }
    let white = draw(
        EnvSource::Map(&env),
        Shading::SplitSum {
            env: &lit,
            material: mat(1.0, 0.0, 1.0),
            multiscatter: false,
            dominant: true,
        },
        48,
    );
    let black = draw(
        EnvSource::Map(&env),
        Shading::SplitSum {
            env: &lit,
            material: mat(0.0, 0.0, 1.0),
            multiscatter: false,
            dominant: true,
        },
        48,
    );
    let mut hits = 0;
    for (a, b) in white.pixels.iter().zip(&black.pixels) {
        if a == &[0.0; 3] {
            continue;
        }
        hits += 1;
        for c in 0..3 {
            assert!((a[c] - b[c] - l).abs() < 1e-4, "{a:?} {b:?}");
        }
    }
    assert!(hits > 900, "{hits}");
}

/// Under the upper-hemisphere step (L = 1 for z > 0, else 0) a white
/// Lambertian surface at angle θ from +z reflects E/π = (1 + cos θ)/2.
#[test]
fn the_hemisphere_step_gives_the_closed_form_along_a_meridian() {
    let (_, lit) = baked(|d| [if d.z > 0.0 { 1.0 } else { 0.0 }; 3], 64, 16);
    let s = lit.sampler();
    let mut worst = 0f32;
    for k in 0..=36 {
        let t = (k as f32 * 5.0).to_radians();
        let n = Vec3::new(t.sin(), 0.0, t.cos());
        let got = s.irradiance_over_pi(n)[0];
        let want = (1.0 + t.cos()) / 2.0;
        worst = worst.max((got - want).abs());
    }
    // The map is 32² texels, bilinear, of an SH9 irradiance (exact for
    // this band-limited E) over a 64² source.
    assert!(worst < 4e-3, "worst {worst}");
}

/// At roughness 1, GGX with N = V = R has a constant D, so the prefiltered
/// radiance is the cosine-weighted average of the environment: E/π.
#[test]
fn roughness_one_is_the_cosine_weighted_average() {
    // Down to 8² faces: bilinear on the 2² faces of a full chain cannot
    // hold even a smooth function between its four texel centres.
    let (_, lit) = baked_to(smooth, 64, 32, Some(8));
    let s = lit.sampler();
    // At the last level's texel centres (no interpolation in the level).
    let last = lit.levels().last().unwrap();
    let frame = last.representation().frame;
    let (w, _) = last.cell_size();
    let mut worst = 0f32;
    for face in 0..6 {
        for j in 0..w {
            for i in 0..w {
                let c = envmap_core::ChartUv::new(
                    face,
                    (i as f32 + 0.5) / w as f32,
                    (j as f32 + 0.5) / w as f32,
                );
                let d = frame.to_canonical(AnyMapping::Cube.inverse(c).unwrap());
                let a = s.specular(d, 1.0);
                let b = s.irradiance_over_pi(d);
                for c in 0..3 {
                    worst = worst.max((a[c] - b[c]).abs() / b[c]);
                }
            }
        }
    }
    println!("roughness 1 vs E/pi: worst relative difference {worst:.5}");
    // The chain's last level is sampled (its error ≤ 0.5 %) and the
    // irradiance is SH9 (0.14 % truncation on this map).
    assert!(worst < 0.012, "worst relative difference {worst}");
}

/// A white metal at roughness 0 by the split sum is the mirror render (F0 =
/// 1, the DFG's scale + bias 1, the chain's level 0 the map resampled).
#[test]
fn the_split_sum_at_roughness_zero_is_the_mirror() {
    let (env, lit) = baked(smooth, 64, 64);
    let mirror = draw(EnvSource::Map(&env), Shading::Mirror, 64);
    let split = draw(
        EnvSource::Map(&env),
        Shading::SplitSum {
            env: &lit,
            material: mat(1.0, 1.0, 0.0),
            multiscatter: false,
            dominant: true,
        },
        64,
    );
    let p = psnr(
        &mirror.pixels,
        &split.pixels,
        |k| mirror.pixels[k] != [0.0; 3],
        1.0,
    );
    println!("mirror vs split sum at roughness 0: {p:.1} dB");
    assert!(p > 45.0, "{p}");
}

/// The split sum against the Monte Carlo reference, per roughness and
/// material, on a smooth environment: the PSNR (peak 1) of each, and a
/// floor each must stay above. The reference has 4096 samples per lobe (no
/// light sampling: the environment is smooth);
/// its noise is printed from a 512-sample render (PSNR of that against it;
/// 4096 samples are about 9 dB less noisy again).
#[test]
fn the_split_sum_is_close_to_the_reference() {
    let (_, lit) = baked(smooth, 64, 64);
    let exact = smooth;
    for (name, metallic, base, floor) in [("plastic", 0.0, 0.8, 47.0), ("metal", 1.0, 0.9, 34.0)] {
        for r in [0.25f32, 0.5, 0.75, 1.0] {
            let m = mat(base, metallic, r);
            let split_at = |dominant| {
                draw(
                    EnvSource::Analytic(&exact),
                    Shading::SplitSum {
                        env: &lit,
                        material: m,
                        multiscatter: false,
                        dominant,
                    },
                    40,
                )
            };
            let (split, along_r) = (split_at(true), split_at(false));
            let reference = draw(
                EnvSource::Analytic(&exact),
                Shading::Reference {
                    material: m,
                    samples: 512,
                    light: None,
                    seed: 0,
                },
                40,
            );
            let finer = draw(
                EnvSource::Analytic(&exact),
                Shading::Reference {
                    material: m,
                    samples: 4096,
                    light: None,
                    seed: 0,
                },
                40,
            );
            let hit = |k: usize| reference.pixels[k] != [0.0; 3];
            let p = psnr(&finer.pixels, &split.pixels, hit, 1.0);
            let noise = psnr(&finer.pixels, &reference.pixels, hit, 1.0);
            let p_r = psnr(&finer.pixels, &along_r.pixels, hit, 1.0);
            println!(
                "{name} roughness {r}: split sum vs reference {p:.1} dB ({p_r:.1} dB along R; reference noise at 512 samples: {noise:.1} dB)"
            );
            assert!(p > floor, "{name} {r}: {p:.1} dB");
        }
    }
}

#[test]
fn render_takes_materials_and_the_reference_from_the_command_line() {
    use common::{envmap, text};
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let small = [
        "--width",
        "32",
        "--height",
        "24",
        "--env-size",
        "32",
        "--bake-size",
        "16",
    ];
    let mut args = vec![
        "render",
        "gold.png",
        "--material",
        "gold",
        "--roughness",
        "0.4",
    ];
    args.extend(small);
    let o = envmap(&args, d);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(text(&o.stderr).contains("baked"), "{}", text(&o.stderr));
    let mut args = vec![
        "render",
        "ref.png",
        "--material",
        "plastic",
        "--reference",
        "--analytic",
        "--reference-samples",
        "4",
    ];
    args.extend(small);
    let o = envmap(&args, d);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(d.join("gold.png").exists() && d.join("ref.png").exists());
    for (flag, value, says) in [
        ("--material", "velvet", "mirror, chrome, gold"),
        ("--roughness", "2", "between 0 and 1"),
    ] {
        let o = envmap(
            &[
                "render", "x.png", flag, value, "--width", "8", "--height", "8",
            ],
            d,
        );
        assert!(!o.status.success());
        assert!(text(&o.stderr).contains(says), "{}", text(&o.stderr));
    }
    let o = envmap(&["render", "x.png", "--multiscatter"], d);
    assert!(
        text(&o.stderr).contains("--multiscatter is for"),
        "{}",
        text(&o.stderr)
    );
}

/// Per vertex (seed `002`), the lookup points are interpolated across each
/// triangle: in a constant sky that changes nothing; in the smooth one it
/// stays close to per pixel on the sphere's fine mesh, but not equal.
#[test]
fn per_vertex_lit_interpolates_the_lookups() {
    let m = mat(0.8, 0.5, 0.3);
    for (f, exact) in [
        (
            &(|_: Vec3| [0.6f32; 3]) as &(dyn Fn(Vec3) -> [f32; 3] + Sync),
            true,
        ),
        (&smooth, false),
    ] {
        let (env, lit) = baked(f, 32, 32);
        let shading = Shading::SplitSum {
            env: &lit,
            material: m,
            multiscatter: false,
            dominant: true,
        };
        let a = draw_in(EnvSource::Map(&env), shading, 48, Mode::PerPixel);
        let b = draw_in(EnvSource::Map(&env), shading, 48, Mode::PerVertex);
        let p = psnr(&a.pixels, &b.pixels, |k| a.pixels[k] != [0.0; 3], 1.0);
        println!(
            "per vertex vs per pixel ({}): {p:.1} dB",
            if exact { "constant" } else { "smooth" }
        );
        if exact {
            assert!(p > 100.0, "{p}");
        } else {
            assert!(p > 25.0 && p < 100.0, "{p}");
        }
    }
}

/// `envmap render --env DIR` reads the maps `envmap bake` wrote into DIR
/// (OpenEXR files, or KTX2 chains) and renders what the same chain baked on
/// the fly renders (`--engine gltf`: the linear rule down to 2², which is
/// also `envmap bake`'s default, read as glTF viewers read it); a KTX2
/// chain alone is read by the linear rule; a directory that is not a bake,
/// or a bake without a chain, is refused by name.
#[test]
fn render_reads_the_maps_bake_wrote() {
    use common::{envmap, text};
    use envmap_render::image::read_rgb;
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let small = [
        "--width",
        "64",
        "--height",
        "48",
        "--material",
        "plastic",
        "--engine",
        "gltf",
    ];
    let run = |args: &[&str]| {
        let o = envmap(args, d);
        assert!(o.status.success(), "{args:?}: {}", text(&o.stderr));
        text(&o.stderr)
    };
    for (out, extra) in [("exr", &[][..]), ("gltf", &["--target", "gltf"][..])] {
        let mut args = vec![
            "bake",
            "sky",
            "--env-size",
            "32",
            "--size",
            "32",
            "--out",
            out,
        ];
        args.extend(extra);
        run(&args);
    }
    let mut fly = vec!["render", "fly.exr", "--env-size", "32", "--bake-size", "32"];
    fly.extend(small);
    assert!(run(&fly).contains("baked"));
    let fly = read_rgb(&d.join("fly.exr"), u64::MAX, None).unwrap().0;
    let got = |out: &str, env: &str, extra: &[&str]| {
        let mut args = vec!["render", out, "--env", env];
        args.extend(small);
        args.extend(extra);
        let said = run(&args);
        let img = read_rgb(&d.join(out), u64::MAX, None).unwrap().0;
        let db = psnr(&img.pixels, &fly.pixels, |_| true, 1.0);
        println!("{env}: {db:.1} dB against the maps baked on the fly");
        (said, db)
    };
    // OpenEXR levels are half floats: ~11 bits.
    let (said, db) = got("exr.exr", "exr", &[]);
    assert!(said.contains("manifest.json: 5 specular levels"), "{said}");
    assert!(db > 60.0, "{db}");
    // RGBA16F KTX2 in the glTF axes the manifest states.
    let (said, db) = got("gltf.exr", "gltf", &[]);
    assert!(said.contains("diffuse.ktx2"), "{said}");
    assert!(db > 60.0, "{db}");
    // The chain file alone: the linear rule (glTF's own) and its axes as
    // given; irradiance from level 0's SH9 instead of the source's.
    std::fs::copy(d.join("gltf/specular.ktx2"), d.join("alone.ktx2")).unwrap();
    let (said, db) = got("alone.exr", "alone.ktx2", &["--convention", "gltf"]);
    assert!(said.contains("the linear rule"), "{said}");
    assert!(db > 60.0, "{db}");
    // The chain in the bake's directory is read through its manifest.
    let (said, _) = got("in_dir.exr", "gltf/specular.ktx2", &[]);
    assert!(said.contains("manifest.json"), "{said}");

    std::fs::create_dir(d.join("empty")).unwrap();
    run(&["bake", "sky", "--env-size", "8", "--sh-only", "--out", "sh"]);
    // Broken manifests: not JSON, a level's file missing, an absurd DFG size.
    let manifest = std::fs::read_to_string(d.join("exr/manifest.json")).unwrap();
    for (dir, text) in [
        ("notjson", "{ not json".to_owned()),
        (
            "missing",
            manifest.replace("specular_2.exr", "specular_9.exr"),
        ),
        ("hugedfg", {
            let mut m: serde_json::Value = serde_json::from_str(&manifest).unwrap();
            m["dfg"]["size"] = serde_json::json!(4_000_000_000u64);
            m.to_string()
        }),
    ] {
        std::fs::create_dir(d.join(dir)).unwrap();
        for f in std::fs::read_dir(d.join("exr")).unwrap() {
            let f = f.unwrap().path();
            std::fs::copy(&f, d.join(dir).join(f.file_name().unwrap())).unwrap();
        }
        std::fs::write(d.join(dir).join("manifest.json"), text).unwrap();
    }
    for (env, says) in [
        ("empty", "not a directory `envmap bake` wrote"),
        ("sh", "no specular levels"),
        (
            "notjson",
            "notjson/manifest.json: cannot decode envmap bake manifest",
        ),
        ("missing", "specular_9.exr"),
        ("hugedfg", "dfg size 4000000000"),
    ] {
        let o = envmap(&["render", "x.png", "--env", env, "--material", "gold"], d);
        assert!(!o.status.success());
        assert!(text(&o.stderr).contains(says), "{}", text(&o.stderr));
        assert!(!d.join("x.png").exists());
    }
}

/// Eight at a time, the split sum is the one-at-a-time split sum (the
/// batched mappings round differently: within 10⁻⁵ relative).
#[test]
fn shade8_is_shade_lane_by_lane() {
    let (_, lit) = baked(smooth, 32, 32);
    let ls = lit.sampler();
    let mut rng = envmap_render::instruments::Pcg32::new(1);
    let mut rnd = || rng.next_f32() * 2.0 - 1.0;
    let mut worst = 0.0f32;
    for r in [0.0f32, 0.3, 0.55, 1.0] {
        for (metallic, multiscatter, dominant) in [(0.0, false, true), (1.0, true, false)] {
            let m = mat(0.7, metallic, r);
            for lanes in [1usize, 5, 8] {
                let n: Vec<Vec3> = (0..lanes)
                    .map(|_| Vec3::new(rnd(), rnd(), rnd()).normalize_or(Vec3::Z))
                    .collect();
                let v: Vec<Vec3> = n
                    .iter()
                    .map(|n| (*n + 0.8 * Vec3::new(rnd(), rnd(), rnd())).normalize_or(*n))
                    .collect();
                let mut out = [[0.0f32; 3]; 8];
                ls.shade8(&m, &n, &v, multiscatter, dominant, &mut out);
                for k in 0..lanes {
                    let one = ls.shade(&m, n[k], v[k], multiscatter, dominant);
                    for c in 0..3 {
                        let e = (out[k][c] - one[c]).abs() / one[c].abs().max(1e-3);
                        worst = worst.max(e);
                    }
                }
            }
        }
    }
    println!("shade8 vs shade: worst relative difference {worst:e}");
    assert!(worst < 1e-5, "{worst}");
}
