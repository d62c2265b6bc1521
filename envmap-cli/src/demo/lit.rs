//! `envmap demo`'s lit section: materials shaded by the split sum from
//! baked maps, each beside its Monte Carlo reference and the error between
//! them.
//!
//! * **Sphere grids** (`spheres_sky*.png`, `spheres_room*.png`): roughness
//!   0, 0.25, 0.5, 0.75, 1 (columns) of a dielectric (red plastic, top row)
//!   and a metal (gold, bottom row), in the built-in sky and room.
//! * **Teapots** (`teapots_lit*.png`): diffuse, glossy plastic and chrome in
//!   the sky.
//! * **Seed `002`'s lit teapots** (`seed002_lit_teapots.png`): a diffuse lit
//!   teapot, a teapot with reflective and specular maps (glossy metal) and a
//!   diffusely lit one with specular reflective maps (plastic), per vertex
//!   as the seed renders them, from the maps resampled into a latitude map
//!   (top row) and a GL sphere map (bottom row).
//!
//! The maps are baked from a cube of the environment (`LitEnvironment::bake`);
//! the references see the environment exactly (its analytic function),
//! with light sampling. Each reference is two renders of half the samples
//! with independent seeds: their mean is the reference, half their
//! difference estimates its own noise, reported beside the split sum's
//! PSNR so that one can tell the split sum's error from the reference's
//! noise. PSNR is over the object's pixels, on displayed values (exposure,
//! clamp, sRGB), as the rest of the demo.

use std::time::Instant;

use envmap_core::glam::Vec3;
use envmap_core::AnyMapping;

use crate::demo::scene::{displayed, heat_map, psnr_displayed, save_png, DemoOptions};
use envmap_render::filter::{convert, ConvertOptions};
use envmap_render::image::Outputs;
use envmap_render::image::{FileAxes, Representation, RgbImage};
use envmap_render::scene::Builtin;
use envmap_render::scene::LitEnvironment;
use envmap_render::scene::Material;
use envmap_render::scene::Mesh;
use envmap_render::scene::{
    light_table, Camera, EnvSource, Mode, RenderOptions, Renderer, Shading,
};
use envmap_render::Result;

/// The roughness of the sphere grid's columns.
pub(crate) const GRID_ROUGHNESS: [f32; 5] = [0.0, 0.25, 0.5, 0.75, 1.0];

/// One lit render's row of the report.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct LitRow {
    /// What was rendered and where (`"sphere, sky"`, `"teapot, sky"`).
    pub scene: &'static str,
    /// The material's name.
    pub material: &'static str,
    /// Its perceptual roughness.
    pub roughness: f32,
    /// PSNR (dB) of the split sum against the reference.
    pub psnr: f64,
    /// PSNR (dB) of the reference's own noise estimate (half the difference
    /// of its two independent halves) against zero: the split sum's PSNR
    /// cannot be told apart from noise above about this.
    pub reference_noise: f64,
    /// Milliseconds for the split-sum render.
    pub split_ms: f64,
    /// Milliseconds for the reference render (both halves).
    pub reference_ms: f64,
}

/// A material for the grid's rows.
fn grid_material(metal: bool, roughness: f32) -> Material {
    if metal {
        Material::new([1.0, 0.766, 0.336], 1.0, roughness)
    } else {
        Material::new([0.8, 0.05, 0.05], 0.0, roughness)
    }
}

/// Images side by side, `cols` to a row (all the size of the first).
fn tile(images: &[RgbImage], cols: usize) -> RgbImage {
    let (w, h) = (images[0].width as usize, images[0].height as usize);
    let rows = images.len().div_ceil(cols);
    let width = w * cols;
    let mut pixels = vec![[0.0f32; 3]; width * h * rows];
    for (k, img) in images.iter().enumerate() {
        let (cx, cy) = (k % cols, k / cols);
        for y in 0..h {
            let dst = (cy * h + y) * width + cx * w;
            pixels[dst..dst + w].copy_from_slice(&img.pixels[y * w..(y + 1) * w]);
        }
    }
    RgbImage {
        width: width as u32,
        height: (h * rows) as u32,
        pixels,
    }
}

/// What one environment's lit renders need.
struct Scene<'a> {
    name: &'static str,
    analytic: &'a (dyn Fn(Vec3) -> [f32; 3] + Sync),
    lit: LitEnvironment,
    light: envmap_render::instruments::EnvSampling,
}

/// A split-sum render, its reference (two halves) and the row comparing them.
struct Compared {
    split: RgbImage,
    reference: RgbImage,
    error: RgbImage,
    row: LitRow,
}

#[allow(clippy::too_many_arguments)]
fn compare(
    scene: &Scene<'_>,
    what: &'static str,
    name: &'static str,
    m: Material,
    mesh: &Mesh,
    cam: &Camera,
    base: &RenderOptions<'_>,
    opts: &DemoOptions<'_>,
) -> Result<Compared> {
    let env = EnvSource::Analytic(scene.analytic);
    let t = Instant::now();
    let split = Renderer::new().render(mesh, env, cam, &{
        let mut o = *base;
        o.shading = Shading::SplitSum {
            env: &scene.lit,
            material: m,
            multiscatter: false,
            dominant: true,
        };
        o
    })?;
    let split_ms = t.elapsed().as_secs_f64() * 1e3;
    let t = Instant::now();
    let half = |seed| {
        Renderer::new().render(mesh, env, cam, &{
            let mut o = *base;
            o.shading = Shading::Reference {
                material: m,
                samples: (opts.reference_samples / 2).max(1),
                light: Some(&scene.light),
                seed,
            };
            o
        })
    };
    let (a, b) = (half(1)?, half(2)?);
    let reference_ms = t.elapsed().as_secs_f64() * 1e3;
    let reference = RgbImage {
        width: a.width,
        height: a.height,
        pixels: a
            .pixels
            .iter()
            .zip(&b.pixels)
            .map(|(p, q)| [0, 1, 2].map(|c| 0.5 * (p[c] + q[c])))
            .collect(),
    };
    let mask: Vec<bool> = split.pixels.iter().map(|p| *p != [0.0; 3]).collect();
    let (sd, rd) = (
        displayed(&split, opts.exposure),
        displayed(&reference, opts.exposure),
    );
    let (ad, bd) = (displayed(&a, opts.exposure), displayed(&b, opts.exposure));
    // Half the halves' difference: the mean's error, were they Gaussian.
    let half_diff: Vec<[f32; 3]> = ad
        .iter()
        .zip(&bd)
        .map(|(p, q)| [0, 1, 2].map(|c| 0.5 * (p[c] - q[c])))
        .collect();
    let zero = vec![[0.0f32; 3]; half_diff.len()];
    let row = LitRow {
        scene: what,
        material: name,
        roughness: m.roughness,
        psnr: psnr_displayed(&sd, &rd, &mask),
        reference_noise: psnr_displayed(&half_diff, &zero, &mask),
        split_ms,
        reference_ms,
    };
    let error = heat_map(&sd, &rd, &mask, split.width, split.height);
    Ok(Compared {
        split,
        reference,
        error,
        row,
    })
}

/// The lit maps of `lit` resampled into `mapping` (each level, and the
/// source read at roughness 0, at about its cube's texel count), in one
/// representation of envmap's default axes.
fn resampled(lit: &LitEnvironment, mapping: AnyMapping) -> Result<LitEnvironment> {
    let repr = Representation::for_file(mapping, FileAxes::default());
    let to = |img: &envmap_render::image::EnvImage| {
        let (w, h) = crate::demo::scene::size_for_budget(
            mapping,
            u64::from(img.width()) * u64::from(img.height()),
        );
        convert(img, repr, w, h, &ConvertOptions::default(), None)
    };
    let levels = lit.levels().iter().map(to).collect::<Result<Vec<_>>>()?;
    let irradiance = to(lit.irradiance())?;
    let out = LitEnvironment::new(
        levels,
        lit.roughness().to_vec(),
        irradiance,
        lit.irradiance_scale(),
        lit.dfg().clone(),
    )?;
    match lit.source() {
        Some(src) => out.with_source(to(src)?),
        None => Ok(out),
    }
}

/// Renders the lit section into `run` (see the [module docs](self));
/// `progress(what)` names each step.
pub(crate) fn run(
    opts: &DemoOptions<'_>,
    run: &mut Outputs<'_>,
    progress: &dyn Fn(&str),
) -> Result<Vec<LitRow>> {
    let out = |name: &str| opts.out.join(name);
    let width = opts.width.max(16);
    let cell = (width / 5).max(8);
    let base = {
        let mut o = RenderOptions::default();
        o.width = cell;
        o.height = cell;
        o.samples = 1;
        o.background = false;
        o.cancel = opts.cancel;
        o
    };
    let sphere = Mesh::sphere(1.0, 64, 32);
    let sphere_cam = Camera {
        eye: Vec3::new(0.0, -3.6, 0.9),
        target: Vec3::ZERO,
        up: Vec3::Z,
        fov_y_deg: 35.0,
    };
    let sky_fn = |d: Vec3| Builtin::Sky.radiance(d);
    let room_fn = |d: Vec3| Builtin::Room.radiance(d);
    let mut rows = Vec::new();
    let mut sky_lit = None;
    for (b, name, f) in [
        (
            Builtin::Sky,
            "sky",
            &sky_fn as &(dyn Fn(Vec3) -> [f32; 3] + Sync),
        ),
        (Builtin::Room, "room", &room_fn),
    ] {
        progress(&format!("bake {name}"));
        let repr = Representation::for_file(AnyMapping::Cube, FileAxes::default());
        let (w, h) = repr
            .size_for_cell_width(opts.lit_env_size)
            .unwrap_or((6 * 64, 64));
        let src = b.image(repr, w, h)?;
        let lit = LitEnvironment::bake(&src, opts.lit_bake_size, opts.cancel)?;
        let light = light_table(EnvSource::Analytic(f), base.filter);
        let scene = Scene {
            name,
            analytic: f,
            lit,
            light,
        };
        progress(&format!("spheres, {name}"));
        let (mut split, mut reference, mut error) = (Vec::new(), Vec::new(), Vec::new());
        for metal in [false, true] {
            for r in GRID_ROUGHNESS {
                let c = compare(
                    &scene,
                    if name == "sky" {
                        "sphere, sky"
                    } else {
                        "sphere, room"
                    },
                    if metal { "gold (metal)" } else { "red plastic" },
                    grid_material(metal, r),
                    &sphere,
                    &sphere_cam,
                    &base,
                    opts,
                )?;
                split.push(c.split);
                reference.push(c.reference);
                error.push(c.error);
                rows.push(c.row);
            }
        }
        let n = GRID_ROUGHNESS.len();
        save_png(
            run,
            &tile(&split, n),
            &out(&format!("spheres_{}.png", scene.name)),
            opts.exposure,
        )?;
        save_png(
            run,
            &tile(&reference, n),
            &out(&format!("spheres_{}_reference.png", scene.name)),
            opts.exposure,
        )?;
        save_png(
            run,
            &tile(&error, n),
            &out(&format!("error_spheres_{}.png", scene.name)),
            0.0,
        )?;
        if b == Builtin::Sky {
            sky_lit = Some(scene);
        }
    }
    let Some(sky) = sky_lit else {
        return Ok(rows);
    };

    // Teapots in the sky: diffuse, glossy plastic, chrome.
    progress("teapots, sky");
    let teapot = Mesh::teapot(10);
    let cam = Camera::default();
    let tw = (width / 2).max(16);
    let tbase = {
        let mut o = base;
        o.width = tw;
        o.height = (tw * 3 / 4).max(12);
        o
    };
    let (mut split, mut reference, mut error) = (Vec::new(), Vec::new(), Vec::new());
    for name in ["diffuse", "plastic", "chrome"] {
        let m = Material::preset(name)?;
        let c = compare(&sky, "teapot, sky", name, m, &teapot, &cam, &tbase, opts)?;
        split.push(c.split);
        reference.push(c.reference);
        error.push(c.error);
        rows.push(c.row);
    }
    save_png(
        run,
        &tile(&split, 3),
        &out("teapots_lit.png"),
        opts.exposure,
    )?;
    save_png(
        run,
        &tile(&reference, 3),
        &out("teapots_lit_reference.png"),
        opts.exposure,
    )?;
    save_png(run, &tile(&error, 3), &out("error_teapots_lit.png"), 0.0)?;

    // Seed 002's three lit teapots, per vertex, from a latitude map and a
    // GL sphere map.
    progress("seed 002's lit teapots");
    let seed_materials = [
        Material::preset("diffuse")?,
        Material::new([0.9; 3], 1.0, 0.25),
        Material::new([0.8, 0.55, 0.25], 0.0, 0.3),
    ];
    let mut seed = Vec::new();
    for mapping in [AnyMapping::LatLong, AnyMapping::SphereMapGl] {
        let lit = resampled(&sky.lit, mapping)?;
        for m in seed_materials {
            seed.push(
                Renderer::new().render(&teapot, EnvSource::Analytic(&sky_fn), &cam, &{
                    let mut o = tbase;
                    o.mode = Mode::PerVertex;
                    o.background = true;
                    o.samples = opts.samples.clamp(1, 8);
                    o.shading = Shading::SplitSum {
                        env: &lit,
                        material: m,
                        multiscatter: false,
                        dominant: true,
                    };
                    o
                })?,
            );
        }
    }
    save_png(
        run,
        &tile(&seed, 3),
        &out("seed002_lit_teapots.png"),
        opts.exposure,
    )?;
    Ok(rows)
}

/// The lit section's table as Markdown.
#[must_use]
pub(crate) fn lit_table(rows: &[LitRow]) -> String {
    use std::fmt::Write as _;
    let mut s = String::from(
        "| scene | material | roughness | PSNR split sum vs reference (dB) | reference noise (dB) | split sum (ms) | reference (ms) |\n| --- | --- | ---: | ---: | ---: | ---: | ---: |\n",
    );
    for r in rows {
        let _ = writeln!(
            s,
            "| {} | {} | {:.2} | {:.1} | {:.1} | {:.0} | {:.0} |",
            r.scene, r.material, r.roughness, r.psnr, r.reference_noise, r.split_ms, r.reference_ms
        );
    }
    s
}

/// The lit section of `report.md`.
pub(crate) fn lit_markdown(opts: &DemoOptions<'_>, rows: &[LitRow]) -> String {
    format!(
        "\n## Lit\n\nMaterials shaded by the split sum (diffuse = base·(1 − metallic)·E/π, specular = LD·(F0·A + B), the chain read along \
         the dominant direction) from maps baked from a {e}² cube of each environment ({b}² chain to 2², 32² irradiance, 64² DFG), \
         against the Monte Carlo reference ({s} samples per strategy per pixel — cosine, GGX and light sampling by the balance \
         heuristic — the environment evaluated exactly). The reference is two independent halves; \"reference noise\" is the PSNR of \
         half their difference: where the split sum's PSNR comes near it, the reference's noise, not the split sum, limits it. One \
         sample per pixel, exposure {x} stops. Images: `spheres_sky.png`, `spheres_room.png` (columns roughness 0 … 1; top red \
         plastic, bottom gold), their `_reference` and `error_` twins; `teapots_lit.png` (diffuse, plastic, chrome), \
         `teapots_lit_reference.png`, `error_teapots_lit.png`; `seed002_lit_teapots.png` (seed 002's diffuse lit teapot, reflective \
         and specular, diffusely lit with specular reflective maps; per vertex; top from a latitude map, bottom from a GL sphere map).\n\n{}",
        lit_table(rows),
        e = opts.lit_env_size,
        b = opts.lit_bake_size,
        s = opts.reference_samples,
        x = opts.exposure,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tiles_keep_every_image_in_its_place() {
        let img = |v: f32| RgbImage {
            width: 2,
            height: 1,
            pixels: vec![[v; 3]; 2],
        };
        let t = tile(&[img(1.0), img(2.0), img(3.0)], 2);
        assert_eq!((t.width, t.height), (4, 2));
        let firsts: Vec<f32> = t.pixels.iter().map(|p| p[0]).collect();
        assert_eq!(firsts, [1.0, 1.0, 2.0, 2.0, 3.0, 3.0, 0.0, 0.0]);
    }
}
