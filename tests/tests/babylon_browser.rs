//! Babylon.js, in headless Chromium, shows what envmap's `.env` files hold.
//!
//! envmap bakes `--target babylon` for the built-in sky and for a real
//! HDRI with a sun (`test-data/hdri/park.exr`, written as Radiance first so
//! that Babylon.js's own prefilter reads the same file). `tests/browser/run.mjs`
//! loads them into Babylon.js (npm `@babylonjs/core`) in Debian's Chromium
//! (WebGL2 on SwiftShader) and reads back linear f32 renders; this test
//! measures them:
//!
//! - (a) the skybox against envmap's own render of the same view (level 0
//!   of the chain it wrote, before RGBD, looked up bilinearly in the
//!   direction each pixel sees), with a mirrored and a turned map as
//!   negative controls;
//! - (b) lit spheres (metal and plastic, roughness 0 to 1) against envmap's
//!   split sum at Babylon.js's roughness rule: the prefiltered radiance at
//!   α = r² + 0.0005 (Babylon.js's `convertRoughnessToAverageSlope`), the
//!   DFG integral, E/π from the SH;
//! - (c) the same metal spheres lit by Babylon.js's own prefiltering of the
//!   same Radiance file (`HDRCubeTexture`, `prefilterOnLoad`), both against
//!   that split sum.
//!
//! `.ci/run` installs Chromium (`apt-get install chromium`) and the npm
//! packages (`npm ci --prefix tests/browser`) and runs it; it fails, not
//! skips, without them.

use std::path::{Path, PathBuf};
use std::process::Command;

use envmap_core::{AnyMapping, Frame};
use envmap_render::bake::{Baker, Preset, Target};
use envmap_render::filter::bake::BakeOptions;
use envmap_render::filter::dfg::dfg_integral;
use envmap_render::filter::sample::{Filter, Sampler};
use envmap_render::filter::sh::{IrradianceScale, Sh9};
use envmap_render::filter::specular::RoughnessRule;
use envmap_render::image::{
    load, save, EnvImage, FileAxes, LoadOptions, Representation, SaveOptions,
};
use envmap_render::scene::Builtin;
use glam::Vec3;

/// Size of the skybox views and of the sphere images.
const VIEW: u32 = 160;
/// (b) The bound on the spheres' relative RMS against envmap's split sum
/// read through the chain it wrote as Babylon.js reads it, for roughness
/// 0.4 and above, and below (the sun's reflection, sharp and clipped at
/// 255, crosses texels there): what is left is Babylon.js's DFG table
/// against the DFG integral, RGBD's 8 bits, binary16 texels after
/// Babylon.js expands them, and the GPU's filtering.
const CHAIN_BOUND: f64 = 0.015;
/// See [`CHAIN_BOUND`].
const CHAIN_BOUND_SHARP: f64 = 0.08;
/// The spheres' roughness values.
const ROUGHNESS: [f32; 6] = [0.0, 0.2, 0.4, 0.6, 0.8, 1.0];

/// One environment: its name, its source, the bake's level 0 and SH.
struct Env {
    name: &'static str,
    source: EnvImage,
    /// The chain's levels (level 0 first), as baked, before RGBD.
    levels: Vec<EnvImage>,
    level0: EnvImage,
    sh: Sh9,
    /// Whether Babylon.js prefilters it too (a Radiance file beside it).
    hdr: bool,
    /// The file Babylon.js loads, and how: "env" or "gltf".
    file: String,
    kind: &'static str,
    /// Babylon.js's lodGenerationScale for it.
    scale: f32,
    /// The largest value the file holds: RGBD's 255 in a `.env`, 255^2.2
    /// in a glTF light (written so for Babylon.js's loader).
    ceiling: f32,
}

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// Bakes `src` for Babylon.js into `data/NAME.env`, or with `gltf` into
/// `data/NAME.gltf` (`--target gltf-ibl`).
fn bake(name: &'static str, source: EnvImage, data: &Path, hdr: bool, gltf: bool) -> Env {
    let target = if gltf {
        Target::GltfIbl
    } else {
        Target::Babylon
    };
    let baked = Baker::for_target(target)
        .input_name(name)
        .bake(&source)
        .expect("bake");
    let files = baked.files("out").expect("files");
    let (kind, scale) = if gltf { ("gltf", 1.0) } else { ("env", 0.8) };
    let bytes = files
        .get(&format!("environment.{kind}"))
        .expect("the environment file");
    std::fs::write(data.join(format!("{name}.{kind}")), bytes).expect("write");
    let bake = baked.into_bake();
    let levels = bake.chain.as_ref().expect("chain").levels.clone();
    Env {
        name,
        source,
        level0: levels[0].clone(),
        levels,
        sh: bake.sh,
        hdr,
        file: format!("/data/{name}.{kind}"),
        kind,
        scale,
        ceiling: if gltf { 255f32.powf(2.2) } else { 255.0 },
    }
}

/// The direction in envmap's GL world (y up, right-handed) of a direction
/// in Babylon.js's (y up, left-handed): z negated.
fn to_gl(d: Vec3) -> Vec3 {
    Vec3::new(d.x, d.y, -d.z)
}

/// `img` looked up bilinearly in the canonical direction `c`.
fn lookup(s: &Sampler<'_>, img: &EnvImage, c: Vec3) -> [f32; 3] {
    let local = img.representation().frame.from_canonical(c);
    match img.mapping().forward(local) {
        Some(uv) => s.sample(uv, Filter::Bilinear),
        None => [f32::NAN; 3],
    }
}

/// The f32 RGBA image `path` (rows top-down), as RGB.
fn read_f32(path: &Path) -> Vec<[f32; 3]> {
    let b = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    b.chunks_exact(16)
        .map(|t| {
            let f = |i: usize| f32::from_le_bytes([t[i], t[i + 1], t[i + 2], t[i + 3]]);
            [f(0), f(4), f(8)]
        })
        .collect()
}

/// PSNR in dB of `got` against `want` after the display transform
/// clamp(v / white, 0, 1)^(1/2.2) (peak 1).
fn psnr(got: &[[f32; 3]], want: &[[f32; 3]], white: f32) -> f64 {
    let t = |v: f32| f64::from((v / white).clamp(0.0, 1.0)).powf(1.0 / 2.2);
    let mut se = 0.0;
    for (g, w) in got.iter().zip(want) {
        for k in 0..3 {
            se += (t(g[k]) - t(w[k])).powi(2);
        }
    }
    let mse = se / (3 * got.len()) as f64;
    -10.0 * mse.log10()
}

/// The camera's pixel directions (Babylon.js's world): a pinhole at the
/// origin with vertical field of view `fov`, looking at `dir` with `up`,
/// rows top-down.
fn view_dirs(dir: Vec3, up: Vec3, fov: f32) -> Vec<Vec3> {
    let f = dir.normalize();
    // Babylon.js is left-handed: right = up × forward.
    let r = up.cross(f).normalize();
    let u = f.cross(r);
    let t = (fov / 2.0).tan();
    let n = VIEW as f32;
    (0..VIEW * VIEW)
        .map(|k| {
            let (i, j) = ((k % VIEW) as f32, (k / VIEW) as f32);
            let x = (2.0 * (i + 0.5) / n - 1.0) * t;
            let y = (1.0 - 2.0 * (j + 0.5) / n) * t;
            (f + x * r + y * u).normalize()
        })
        .collect()
}

/// The views of the skybox: forward, up-vector.
fn views() -> Vec<([f32; 3], [f32; 3])> {
    vec![
        ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0]),
        ([0.0, 0.2, 1.0], [0.0, 1.0, 0.0]),
        ([-1.0, 0.5, -0.3], [0.0, 1.0, 0.0]),
        ([0.3, -1.0, 0.2], [0.0, 0.0, 1.0]),
        ([0.2, 1.0, -0.1], [1.0, 0.0, 0.0]),
    ]
}

fn views_json() -> Vec<serde_json::Value> {
    views()
        .iter()
        .map(|(d, u)| serde_json::json!({"dir": d, "up": u}))
        .collect()
}

/// PSNR of Babylon.js's own skybox of `name`.hdr (HDRCubeTexture) against
/// `img` looked up at Babylon.js's directions taken as the GL world's (z
/// not negated: how HDRCubeTexture orients a latlong), over all views.
fn own_skybox_psnr(name: &str, img: &EnvImage, out: &Path) -> f64 {
    let s = Sampler::new(img);
    let white = 3.0 * mean(img);
    let (mut got, mut want) = (Vec::new(), Vec::new());
    for (k, (dir, up)) in views().into_iter().enumerate() {
        got.extend(read_f32(&out.join(format!("{name}_ownsky_{k}.f32"))));
        let dirs = view_dirs(Vec3::from(dir), Vec3::from(up), std::f32::consts::FRAC_PI_2);
        want.extend(
            dirs.iter()
                .map(|&d| lookup(&s, img, Frame::Y_UP_RH.to_canonical(d))),
        );
    }
    psnr(&got, &want, white)
}

/// (a): the skybox of each view against envmap's render of the same view
/// from level 0, and the two controls over all views together (one view
/// alone can be symmetric: a plain ground); returns the worst view's PSNR
/// and the controls'.
fn skybox(env: &Env, out: &Path) -> (f64, f64, f64) {
    let s = Sampler::new(&env.level0);
    let white = 3.0 * mean(&env.level0);
    let mut worst = f64::INFINITY;
    let (mut all_got, mut all_mirror, mut all_turn) = (Vec::new(), Vec::new(), Vec::new());
    for (k, (dir, up)) in views().into_iter().enumerate() {
        let got = read_f32(&out.join(format!("{}_sky_{k}.f32", env.name)));
        let dirs = view_dirs(Vec3::from(dir), Vec3::from(up), std::f32::consts::FRAC_PI_2);
        // What Babylon.js's skybox shows: the file's texels, with RGBD's
        // 255 ceiling.
        let shown = |c: Vec3| lookup(&s, &env.level0, c).map(|v| v.clamp(0.0, env.ceiling));
        let canon = |d: Vec3| Frame::Y_UP_RH.to_canonical(to_gl(d));
        let want: Vec<[f32; 3]> = dirs.iter().map(|&d| shown(canon(d))).collect();
        let p = psnr(&got, &want, white);
        println!(
            "{} skybox view {k}: {p:.2} dB against envmap's render",
            env.name
        );
        worst = worst.min(p);
        all_mirror.extend(
            dirs.iter()
                .map(|&d| shown(canon(Vec3::new(-d.x, d.y, d.z)))),
        );
        all_turn.extend(
            dirs.iter()
                .map(|&d| shown(canon(Vec3::new(d.z, d.y, -d.x)))),
        );
        all_got.extend(got);
    }
    let mirrored = psnr(&all_got, &all_mirror, white);
    let turned = psnr(&all_got, &all_turn, white);
    println!(
        "{} skybox controls over all views: mirrored {mirrored:.2} dB, turned {turned:.2} dB",
        env.name
    );
    (worst, mirrored, turned)
}

/// The mean radiance of `img` over its texels (all channels).
fn mean(img: &EnvImage) -> f32 {
    let p = img.pixels();
    (p.iter().map(|t| f64::from(t[0] + t[1] + t[2])).sum::<f64>() / (3 * p.len()) as f64) as f32
}

/// envmap's split sum of a sphere pixel at Babylon.js's roughness rule:
/// the prefiltered radiance `ld` along R, F0·A + B from the DFG integral
/// at (N·V, r), and for a dielectric E/π·base·(1 − 0.04) (Babylon.js's
/// legacy energy conservation of the diffuse).
fn shade(ld: [f32; 3], e_pi: [f32; 3], nv: f32, r: f32, base: [f32; 3], metallic: f32) -> [f32; 3] {
    let (a, b) = dfg_integral(f64::from(nv), f64::from(r));
    core::array::from_fn(|k| {
        let f0 = 0.04 * (1.0 - metallic) + base[k] * metallic;
        let spec = f64::from(ld[k]) * (f64::from(f0) * a + b);
        let diffuse = f64::from(e_pi[k] * base[k] * 0.96 * (1.0 - metallic));
        (spec + diffuse) as f32
    })
}

/// The pixels of a sphere image that the test compares: inside 0.9 of the
/// radius (the silhouette's tessellated edge left out), with N (Babylon.js's
/// world), N·V and R.
fn sphere_pixels() -> Vec<(usize, Vec3, f32, Vec3)> {
    let n = VIEW as f32;
    (0..(VIEW * VIEW) as usize)
        .filter_map(|k| {
            let x = 2.0 * ((k as u32 % VIEW) as f32 + 0.5) / n - 1.0;
            let y = 1.0 - 2.0 * ((k as u32 / VIEW) as f32 + 0.5) / n;
            let rr = x * x + y * y;
            (rr < 0.81).then(|| {
                let nrm = Vec3::new(x, y, -(1.0 - rr).sqrt());
                let v = Vec3::new(0.0, 0.0, -1.0);
                let nv = nrm.dot(v);
                (k, nrm, nv, 2.0 * nv * nrm - v)
            })
        })
        .collect()
}

/// The prefiltered radiance of `src` at perceptual roughness `r`: level 1
/// of a two-level chain (level 0 is the input resampled) at a size its
/// lobe needs, 256² below r = 0.1 and 64² above.
fn prefiltered(src: &EnvImage, r: f32) -> EnvImage {
    let mut preset = Preset::default();
    preset.size = if r < 0.1 { 512 } else { 128 };
    preset.rule = RoughnessRule::Custom(vec![0.0, r]);
    preset.irradiance_size = 0;
    preset.dfg_size = 0;
    let mut o = BakeOptions::default();
    o.levels = Some(2);
    let baked = Baker::with_preset(preset)
        .options(o)
        .bake(src)
        .expect("prefilter");
    baked.into_bake().chain.expect("chain").levels.remove(1)
}

/// The chain `levels` read as Babylon.js reads it at roughness `r`: lod =
/// scale·log2(size·α), α = r² + 0.0005, clamped to the chain, the two
/// levels around it blended linearly, each bilinearly, texels clipped at
/// the file's ceiling; with `gamma`, `levels` hold texels raised to 1/2.2
/// ([`gamma_levels`]) and the result is raised to 2.2, as Babylon.js reads
/// a glTF light.
fn chain_lookup(
    (levels, samplers): (&[EnvImage], &[Sampler<'_>]),
    (scale, ceiling, gamma): (f32, f32, bool),
    r: f32,
    c: Vec3,
) -> [f32; 3] {
    // Babylon.js filters a glTF light's texels raised to 1/2.2, then
    // raises the result to 2.2: the levels given are those texels.
    let ceiling = if gamma {
        ceiling.powf(1.0 / 2.2)
    } else {
        ceiling
    };
    let size = levels[0].cell_size().0 as f32;
    let alpha = r * r + 0.0005;
    let lod = (scale * (size * alpha).log2()).clamp(0.0, (levels.len() - 1) as f32);
    let k = (lod.floor() as usize).min(levels.len() - 1);
    let t = lod - k as f32;
    let at = |i: usize| lookup(&samplers[i], &levels[i], c).map(|v| v.clamp(0.0, ceiling));
    let a = at(k);
    let v = if t == 0.0 || k + 1 >= levels.len() {
        a
    } else {
        let b = at(k + 1);
        core::array::from_fn(|i| a[i] + t * (b[i] - a[i]))
    };
    if gamma {
        v.map(|x| x.powf(2.2))
    } else {
        v
    }
}

/// `levels` with every texel raised to 1/2.2: what Babylon.js's texture of
/// a glTF light holds and filters (its gamma-space default; see
/// `envmap_render::image::babylon::encode_gltf`).
fn gamma_levels(levels: &[EnvImage]) -> Vec<EnvImage> {
    levels
        .iter()
        .map(|l| {
            let mut g = l.clone();
            for t in g.pixels_mut() {
                *t = t.map(|v| v.max(0.0).powf(1.0 / 2.2));
            }
            g
        })
        .collect()
}

/// Relative RMS of `got` against `want` over the pixels `want` lists, and
/// over those whose reflected radiance RGBD holds (`ld` under 255 in every
/// channel: the sun's reflection left out, which a `.env` clips).
fn rel_rms(got: &[[f32; 3]], want: &[(usize, [f32; 3], bool)]) -> (f64, f64) {
    let (mut num, mut den, mut num_held, mut den_held) = (0.0, 0.0, 0.0, 0.0);
    for &(k, w, held) in want {
        for c in 0..3 {
            let (d, r) = (f64::from(got[k][c] - w[c]).powi(2), f64::from(w[c]).powi(2));
            num += d;
            den += r;
            if held {
                num_held += d;
                den_held += r;
            }
        }
    }
    ((num / den).sqrt(), (num_held / den_held).sqrt())
}

#[test]
#[ignore = "needs Debian's chromium and tests/browser's npm packages, which .ci/run installs; run: npm ci --prefix tests/browser && cargo test --release -p envmap-tests --test babylon_browser -- --ignored --nocapture"]
fn babylon_shows_envmaps_env_files() {
    let dir = tempfile::tempdir().expect("tempdir");
    if std::env::var_os("ENVMAP_BABYLON_DEBUG").is_some() {
        println!("work directory: {}", dir.path().display());
    }
    let data = dir.path().join("data");
    let out = dir.path().join("out");
    std::fs::create_dir_all(&data).unwrap();
    // The built-in sky, as `envmap bake sky` evaluates it, and park.exr
    // through a Radiance file (what Babylon.js's HDRCubeTexture reads).
    let repr = Representation::for_file(AnyMapping::Cube, FileAxes::default());
    let (w, h) = repr.atlas.image_size_for_cell_width(1024).unwrap();
    let sky = Builtin::Sky.image(repr, w, h).unwrap();
    let park_exr = load(
        repo().join("test-data/hdri/park.exr"),
        &LoadOptions::default(),
    )
    .unwrap();
    save(&park_exr, data.join("park.hdr"), &SaveOptions::default()).unwrap();
    let park = load(data.join("park.hdr"), &LoadOptions::default()).unwrap();
    let envs = [
        bake("sky", sky, &data, false, false),
        bake("park", park.clone(), &data, true, false),
        // The glTF light (EXT_lights_image_based) through Babylon.js's
        // glTF loader.
        bake("park_gltf", park, &data, false, true),
    ];

    // The jobs: skyboxes, spheres by envmap's file, spheres by Babylon.js's
    // own prefiltering.
    let mut jobs = Vec::new();
    for e in &envs {
        let views = views_json();
        jobs.push(serde_json::json!({
            "name": format!("{}_sky", e.name), "fn": "skybox", "kind": e.kind, "env": e.file,
            "fov": std::f32::consts::FRAC_PI_2, "width": VIEW, "height": VIEW, "views": views,
        }));
        for (mat, base, metallic) in [
            ("metal", [1.0, 1.0, 1.0], 1.0),
            ("plastic", [0.5, 0.5, 0.5], 0.0),
        ] {
            jobs.push(serde_json::json!({
                "name": format!("{}_{mat}", e.name), "fn": "spheres", "kind": e.kind,
                "env": e.file, "width": VIEW, "height": VIEW,
                "roughness": ROUGHNESS, "metallic": metallic, "base": base,
            }));
        }
        if e.hdr {
            jobs.push(serde_json::json!({
                "name": format!("{}_ownsky", e.name), "fn": "skybox", "kind": "hdr", "size": 256,
                "env": format!("/data/{}.hdr", e.name), "fov": std::f32::consts::FRAC_PI_2,
                "width": VIEW, "height": VIEW, "views": views_json(),
            }));
            jobs.push(serde_json::json!({
                "name": format!("{}_own", e.name), "fn": "spheres", "kind": "hdr", "size": 256,
                "env": format!("/data/{}.hdr", e.name), "width": VIEW, "height": VIEW,
                "roughness": ROUGHNESS, "metallic": 1.0, "base": [1.0, 1.0, 1.0],
            }));
        }
    }
    // The picture in docs/gallery (ENVMAP_GALLERY=PATH copies it there).
    jobs.push(serde_json::json!({
        "name": "gallery", "fn": "gallery", "env": "/data/park.env", "width": 960, "height": 540,
        "fov": 1.0, "eye": [0.0, 0.9, -9.0], "target": [0.0, 0.3, 0.0],
        "roughness": [0.0, 0.25, 0.5, 0.75, 1.0],
    }));
    let job = serde_json::json!({"data": data, "out": out, "jobs": jobs});
    let job_file = dir.path().join("job.json");
    std::fs::write(&job_file, job.to_string()).unwrap();
    let t = std::time::Instant::now();
    let status = Command::new("node")
        .arg(repo().join("tests/browser/run.mjs"))
        .arg(&job_file)
        .status()
        .expect("node (Node.js) runs: install it, then `npm ci --prefix tests/browser`");
    assert!(status.success(), "the browser run failed: {status}");
    println!("browser run: {:.1} s", t.elapsed().as_secs_f64());
    let picture = std::fs::read(out.join("gallery.png")).expect("the gallery picture");
    assert_eq!(&picture[..8], b"\x89PNG\r\n\x1a\n");
    if let Some(p) = std::env::var_os("ENVMAP_GALLERY") {
        std::fs::write(&p, &picture).expect("ENVMAP_GALLERY");
    }

    // (a) The skybox.
    let mut failures = Vec::new();
    for e in &envs {
        let (worst, mirrored, turned) = skybox(e, &out);
        if worst < 40.0 {
            failures.push(format!(
                "{}: skybox {worst:.2} dB against envmap's render, want 40",
                e.name
            ));
        }
        if mirrored >= 25.0 || turned >= 25.0 {
            failures.push(format!(
                "{}: the controls give {mirrored:.2} dB (mirrored) and {turned:.2} dB (turned), want under 25",
                e.name
            ));
        }
    }

    // Babylon.js's HDRCubeTexture reads a latlong as envmap does, but
    // looks its cube up at the direction in its left-handed world as if it
    // were the GL world's: the environment mirrored in z against the .env
    // envmap writes (which shows it as envmap renders it). Its skybox
    // against envmap's reading seen that way (its conversion samples the
    // nearest texel, and is not filtered):
    let own_sky = own_skybox_psnr("park", &envs[1].source, &out);
    // The glTF light shows what the .env shows: the same faces.
    println!("park.hdr as Babylon.js's HDRCubeTexture shows it, against envmap's reading mirrored in z: {own_sky:.2} dB");
    if own_sky < 25.0 {
        failures.push(format!(
            "Babylon.js's own reading of park.hdr: {own_sky:.2} dB against envmap's mirrored in z"
        ));
    }

    // (b) and (c) The spheres, against envmap's split sum at Babylon.js's
    // roughness rule.
    let pixels = sphere_pixels();
    let mut worst_chain = 0f64;
    for e in &envs {
        for (k, &r) in ROUGHNESS.iter().enumerate() {
            let alpha = r * r + 0.0005;
            let pre = prefiltered(&e.source, alpha.sqrt());
            let s = Sampler::new(&pre);
            let canon = |d: Vec3| Frame::Y_UP_RH.to_canonical(to_gl(d));
            let mut line = format!("{} r = {r:.1}:", e.name);
            let mut results = Vec::new();
            let gltf = e.kind == "gltf";
            let read_levels = if gltf {
                gamma_levels(&e.levels)
            } else {
                e.levels.clone()
            };
            let samplers: Vec<Sampler<'_>> = read_levels.iter().map(Sampler::new).collect();
            for (mat, base, metallic) in
                [("metal", [1.0f32; 3], 1.0f32), ("plastic", [0.5; 3], 0.0)]
            {
                let got = read_f32(&out.join(format!("{}_{mat}_{k}.f32", e.name)));
                // (b) envmap's split sum through the chain it wrote, read at
                // Babylon.js's rule.
                let chain: Vec<(usize, [f32; 3], bool)> = pixels
                    .iter()
                    .map(|&(p, n, nv, rdir)| {
                        let ld = chain_lookup(
                            (&read_levels, &samplers),
                            (e.scale, e.ceiling, gltf),
                            r,
                            canon(rdir),
                        );
                        let e_pi = e.sh.irradiance_at(canon(n), IrradianceScale::EOverPi);
                        (p, shade(ld, e_pi, nv, r, base, metallic), true)
                    })
                    .collect();
                let (by_chain, _) = rel_rms(&got, &chain);
                // Where a reflection crosses the sun's edge (255 beside
                // about 1), the GPU's filter weights and binary16 texels
                // make the largest differences: r < 0.4 reads levels 0–3.
                let bound = if r < 0.4 {
                    CHAIN_BOUND_SHARP
                } else {
                    CHAIN_BOUND
                };
                if by_chain > bound {
                    failures.push(format!(
                        "{} {mat} r = {r}: {:.2} % against envmap's split sum through its chain, bound {:.1} %",
                        e.name,
                        100.0 * by_chain,
                        100.0 * bound
                    ));
                }
                worst_chain = worst_chain.max(by_chain);
                // (c) the exact split sum at Babylon.js's α.
                let want: Vec<(usize, [f32; 3], bool)> = pixels
                    .iter()
                    .map(|&(p, n, nv, rdir)| {
                        let ld = lookup(&s, &pre, canon(rdir));
                        let e_pi = e.sh.irradiance_at(canon(n), IrradianceScale::EOverPi);
                        let held = ld.iter().all(|&v| v < 255.0);
                        (p, shade(ld, e_pi, nv, r, base, metallic), held)
                    })
                    .collect();
                let (err, held) = rel_rms(&got, &want);
                if std::env::var_os("ENVMAP_BABYLON_DEBUG").is_some() {
                    let mut img = vec![0f32; 4 * (VIEW * VIEW) as usize];
                    for &(p, w, _) in &want {
                        img[4 * p..4 * p + 3].copy_from_slice(&w);
                    }
                    let bytes: Vec<u8> = img.iter().flat_map(|v| v.to_le_bytes()).collect();
                    std::fs::write(out.join(format!("{}_{mat}_{k}_want.f32", e.name)), bytes)
                        .unwrap();
                }
                line += &format!(
                    " {mat}: {:.2} % against the chain's split sum, {:.2} % against the exact ({:.2} % where R misses the sun);",
                    100.0 * by_chain,
                    100.0 * err,
                    100.0 * held
                );
                results.push((mat, err, want));
            }
            if e.hdr {
                // Babylon.js's own prefilter, against the same split sum in
                // its orientation (z not negated).
                let own: Vec<(usize, [f32; 3], bool)> = pixels
                    .iter()
                    .map(|&(p, n, nv, rdir)| {
                        let ld = lookup(&s, &pre, Frame::Y_UP_RH.to_canonical(rdir));
                        let e_pi = e.sh.irradiance_at(
                            Frame::Y_UP_RH.to_canonical(n),
                            IrradianceScale::EOverPi,
                        );
                        (
                            p,
                            shade(ld, e_pi, nv, r, [1.0; 3], 1.0),
                            ld.iter().all(|&v| v < 255.0),
                        )
                    })
                    .collect();
                let got = read_f32(&out.join(format!("{}_own_{k}.f32", e.name)));
                let (err, held) = rel_rms(&got, &own);
                line += &format!(
                    ", metal by Babylon.js's own prefilter {:.2} % ({:.2} %)",
                    100.0 * err,
                    100.0 * held
                );
            }
            println!("{line}");
        }
    }
    println!(
        "spheres: worst {:.2} % against envmap's split sum through its chain",
        100.0 * worst_chain
    );
    if std::env::var_os("ENVMAP_BABYLON_DEBUG").is_some() {
        let _ = dir.keep();
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
