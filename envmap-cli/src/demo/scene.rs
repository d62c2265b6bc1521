//! `envmap demo`: every representation of the built-in sky, a mirror teapot
//! rendered with each (per pixel and per vertex), error heat maps against the
//! exact reference, and a report comparing them at an equal texel budget.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::time::Instant;

use envmap_core::glam::Vec3;
use envmap_core::texel::texel_center;
use envmap_core::{AnyMapping, Mapping};

use envmap_render::image::{linear_to_srgb, Outputs, SaveOptions};
use envmap_render::image::{FileAxes, Representation, RgbImage};
use envmap_render::scene::Builtin;
use envmap_render::scene::Mesh;
use envmap_render::scene::{Camera, EnvSource, Mode, RenderOptions, Renderer};
use envmap_render::{Error, Result};

/// What the demo makes.
#[derive(Clone, Debug)]
pub(crate) struct DemoOptions<'a> {
    /// Output directory (created if missing).
    pub out: PathBuf,
    /// Texel budget per representation (all charts together).
    pub texels: u64,
    /// Rendered image width (height is 3/4 of it).
    pub width: u32,
    /// Supersampling of the renders (N×N).
    pub samples: u32,
    /// Exposure in stops of the PNGs.
    pub exposure: f32,
    /// Render the lit section ([`crate::demo::lit`]).
    pub lit: bool,
    /// Samples per pixel and per strategy of the lit section's references.
    pub reference_samples: u32,
    /// Face size of the cubes the lit section bakes from.
    pub lit_env_size: u32,
    /// Face size of the lit section's specular chains.
    pub lit_bake_size: u32,
    /// Stops the demo once set ([`Error::Cancelled`]): nothing of this run
    /// is written; see [`envmap_render::cancel`].
    pub cancel: Option<&'a AtomicBool>,
}

impl Default for DemoOptions<'_> {
    fn default() -> Self {
        Self {
            out: PathBuf::from("envmap-demo"),
            texels: 6 * 256 * 256,
            width: 480,
            samples: 2,
            exposure: -1.0,
            lit: true,
            reference_samples: 64,
            lit_env_size: 256,
            lit_bake_size: 128,
            cancel: None,
        }
    }
}

/// One representation's row of the report.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct DemoRow {
    /// The representation.
    pub mapping: AnyMapping,
    /// Image size of the atlas.
    pub size: (u32, u32),
    /// Texels inside a chart whose centre the chart owns.
    pub texels: u64,
    /// Largest over smallest texel solid angle (over those texels).
    pub solid_angle_ratio: f64,
    /// PSNR (dB) of the per-pixel render against the reference over the
    /// teapot's pixels, on the displayed (exposed, clamped, sRGB) values.
    pub psnr_per_pixel: f64,
    /// PSNR (dB) of the per-vertex render against the reference.
    pub psnr_per_vertex: f64,
    /// Seconds to build the map and render both images.
    pub seconds: f64,
}

/// The atlas size for `mapping` closest to `texels` texels.
pub(crate) fn size_for_budget(mapping: AnyMapping, texels: u64) -> (u32, u32) {
    let a = mapping.atlas();
    let (aw, ah) = (
        f64::from(a.cols * a.cell_aspect_w),
        f64::from(a.rows * a.cell_aspect_h),
    );
    let unit = a.cols * a.cell_aspect_w;
    // Count only texels inside charts: a cross fills 6 of its 12 cells, a
    // disk π/4 of its square.
    let mut fill = a.cells.len() as f64 / f64::from(a.cols * a.rows);
    if mapping.has_disk_charts() {
        fill *= std::f64::consts::FRAC_PI_4;
    }
    let width = (texels as f64 / fill * aw / ah).sqrt();
    let cells = (width / f64::from(unit)).round().max(1.0) as u32;
    a.image_size_for_cell_width(cells * a.cell_aspect_w)
        .unwrap_or((unit, a.rows * a.cell_aspect_h))
}

/// Texel count inside charts and max/min texel solid angle, over the texels
/// whose centre the chart owns (a tennisball strip's boundary texels own only
/// a sliver, which would make the ratio meaningless).
fn texel_stats(mapping: AnyMapping, w: u32, h: u32) -> (u64, f64) {
    let atlas = mapping.atlas();
    let (mut n, mut lo, mut hi) = (0u64, f64::INFINITY, 0.0f64);
    for y in 0..h {
        for x in 0..w {
            let Some(t) = atlas.texel_to_chart(x, y, w, h) else {
                continue;
            };
            let c =
                envmap_core::ChartUv::new(t.chart, texel_center(t.i, t.w), texel_center(t.j, t.h));
            if !mapping.in_chart(c.chart, c.u, c.v) {
                continue;
            }
            let owned = mapping
                .inverse(c)
                .and_then(|d| mapping.forward(d))
                .is_some_and(|back| back.chart == c.chart);
            if !owned {
                continue;
            }
            let sa = mapping.texel_solid_angle(t.chart, t.i, t.j, t.w, t.h);
            if sa > 0.0 {
                n += 1;
                lo = lo.min(sa);
                hi = hi.max(sa);
            }
        }
    }
    (n, if n > 0 { hi / lo } else { 0.0 })
}

/// Display values: exposure, clamp, sRGB.
pub(crate) fn displayed(img: &RgbImage, exposure: f32) -> Vec<[f32; 3]> {
    let k = 2f32.powf(exposure);
    img.pixels
        .iter()
        .map(|p| p.map(|c| linear_to_srgb((c * k).clamp(0.0, 1.0))))
        .collect()
}

pub(crate) fn psnr_displayed(a: &[[f32; 3]], b: &[[f32; 3]], mask: &[bool]) -> f64 {
    envmap_render::scene::psnr(a, b, |k| mask[k], 1.0)
}

/// A heat map of |a − b| on displayed values: black (0) to red, yellow, white (≥ 0.25).
pub(crate) fn heat_map(a: &[[f32; 3]], b: &[[f32; 3]], mask: &[bool], w: u32, h: u32) -> RgbImage {
    let pixels = a
        .iter()
        .zip(b)
        .zip(mask)
        .map(|((p, q), &inside)| {
            if !inside {
                return [0.02; 3];
            }
            let e = (0..3).map(|c| (p[c] - q[c]).abs()).fold(0.0f32, f32::max);
            let t = (e / 0.25).clamp(0.0, 1.0);
            // Linear values that display as the ramp.
            let ramp = [
                (3.0 * t).min(1.0),
                (3.0 * t - 1.0).clamp(0.0, 1.0),
                (3.0 * t - 2.0).clamp(0.0, 1.0),
            ];
            ramp.map(envmap_render::image::srgb_to_linear)
        })
        .collect();
    RgbImage {
        width: w,
        height: h,
        pixels,
    }
}

pub(crate) fn save_png(
    run: &mut Outputs<'_>,
    img: &RgbImage,
    path: &Path,
    exposure: f32,
) -> Result<()> {
    let opts = {
        let mut o = SaveOptions::default();
        o.exposure = exposure;
        o
    };
    run.stage_rgb(img, path, &opts)
}

/// What the demo measured: the report's tables.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct DemoReport {
    /// One row per representation.
    pub rows: Vec<DemoRow>,
    /// The lit section's rows (empty without [`DemoOptions::lit`]).
    pub lit: Vec<crate::demo::lit::LitRow>,
    /// The number of images written.
    pub images: usize,
}

/// Runs the demo; `progress(done, total, what)` is called as it goes.
/// Returns the report's tables; writes the images and `report.md` into
/// `opts.out` (created if missing), all of them renamed into place together
/// at the end ([`Outputs`]): after an error or a cancellation none of them
/// is, and a directory the run created is removed again.
pub(crate) fn run(opts: &DemoOptions, progress: &dyn Fn(u32, u32, &str)) -> Result<DemoReport> {
    let created = !opts.out.exists();
    std::fs::create_dir_all(&opts.out).map_err(|source| Error::Write {
        path: opts.out.clone(),
        source,
    })?;
    let result = run_in(opts, progress);
    if result.is_err() && created {
        // Empty again, as nothing was renamed into it: leave no trace.
        let _ = std::fs::remove_dir(&opts.out);
    }
    result
}

fn run_in(opts: &DemoOptions, progress: &dyn Fn(u32, u32, &str)) -> Result<DemoReport> {
    let mut run = Outputs::with(&[], false, opts.cancel);
    // The representations, then the lit section's steps.
    let lit_steps = if opts.lit { 5 } else { 0 };
    // Every mapping that holds the whole sky (a one-lens fisheye sees half of it).
    let mappings: Vec<AnyMapping> = AnyMapping::ALL
        .into_iter()
        .filter(|m| m.covers_sphere())
        .collect();
    let total = mappings.len() as u32 + 1 + lit_steps;
    let mesh = Mesh::teapot(10);
    let cam = Camera::default();
    let (w, h) = (opts.width.max(16), (opts.width.max(16) * 3 / 4).max(12));
    let ropts = {
        let mut o = RenderOptions::default();
        o.width = w;
        o.height = h;
        o.samples = opts.samples.clamp(1, 8);
        o.cancel = opts.cancel;
        o
    };
    progress(0, total, "reference");
    let sky = |d: Vec3| Builtin::Sky.radiance(d);
    // One renderer draws every picture, its memory kept between them.
    let mut renderer = Renderer::new();
    let reference = renderer.render(&mesh, EnvSource::Analytic(&sky), &cam, &ropts)?;
    save_png(
        &mut run,
        &reference,
        &opts.out.join("teapot_reference.png"),
        opts.exposure,
    )?;
    let ref_disp = displayed(&reference, opts.exposure);
    // The object's pixels: where a render without background is not black
    // (the sky has no black). PSNR and heat maps cover the teapot only, so
    // the background, the same map seen directly, does not drown it.
    let silhouette = renderer.render(&mesh, EnvSource::Analytic(&sky), &cam, &{
        let mut o = ropts;
        o.background = false;
        o
    })?;
    let mask: Vec<bool> = silhouette
        .pixels
        .iter()
        .map(|p| p.iter().any(|c| *c > 0.0))
        .collect();
    let mut rows = Vec::new();
    for (k, &m) in mappings.iter().enumerate() {
        progress(k as u32 + 1, total, m.name());
        let t = Instant::now();
        let (aw, ah) = size_for_budget(m, opts.texels);
        let env = Builtin::Sky.image(Representation::for_file(m, FileAxes::default()), aw, ah)?;
        let pp = renderer.render(&mesh, EnvSource::Map(&env), &cam, &ropts)?;
        let pv = renderer.render(&mesh, EnvSource::Map(&env), &cam, &{
            let mut o = ropts;
            o.mode = Mode::PerVertex;
            o
        })?;
        let seconds = t.elapsed().as_secs_f64();
        let name = m.name();
        // The atlas as an environment map file, saying what it holds.
        run.stage_image(&env, opts.out.join(format!("atlas_{name}.png")), &{
            let mut o = SaveOptions::default();
            o.exposure = opts.exposure - 1.0;
            o
        })?;
        save_png(
            &mut run,
            &pp,
            &opts.out.join(format!("teapot_{name}_per_pixel.png")),
            opts.exposure,
        )?;
        save_png(
            &mut run,
            &pv,
            &opts.out.join(format!("teapot_{name}_per_vertex.png")),
            opts.exposure,
        )?;
        let (ppd, pvd) = (displayed(&pp, opts.exposure), displayed(&pv, opts.exposure));
        save_png(
            &mut run,
            &heat_map(&ppd, &ref_disp, &mask, w, h),
            &opts.out.join(format!("error_{name}_per_pixel.png")),
            0.0,
        )?;
        save_png(
            &mut run,
            &heat_map(&pvd, &ref_disp, &mask, w, h),
            &opts.out.join(format!("error_{name}_per_vertex.png")),
            0.0,
        )?;
        let (texels, ratio) = texel_stats(m, aw, ah);
        rows.push(DemoRow {
            mapping: m,
            size: (aw, ah),
            texels,
            solid_angle_ratio: ratio,
            psnr_per_pixel: psnr_displayed(&ppd, &ref_disp, &mask),
            psnr_per_vertex: psnr_displayed(&pvd, &ref_disp, &mask),
            seconds,
        });
    }
    let lit = if opts.lit {
        let step = std::cell::Cell::new(mappings.len() as u32 + 1);
        crate::demo::lit::run(opts, &mut run, &|what| {
            progress(step.get(), total, what);
            step.set(step.get() + 1);
        })?
    } else {
        Vec::new()
    };
    progress(total, total, "report");
    let mut report = report_markdown(opts, &rows, w, h);
    if opts.lit {
        report.push_str(&crate::demo::lit::lit_markdown(opts, &lit));
    }
    run.stage_bytes(opts.out.join("report.md"), report.as_bytes())?;
    let images = run.targets().count().saturating_sub(1);
    run.commit()?;
    Ok(DemoReport { rows, lit, images })
}

/// The report table as Markdown.
#[must_use]
pub(crate) fn report_table(rows: &[DemoRow]) -> String {
    let mut s = String::from(
        "| representation | atlas | texels (owned) | max/min texel solid angle | PSNR per pixel (dB) | PSNR per vertex (dB) | time (s) |\n| --- | --- | ---: | ---: | ---: | ---: | ---: |\n",
    );
    for r in rows {
        let _ = writeln!(
            s,
            "| {} | {}×{} | {} | {:.2} | {:.1} | {:.1} | {:.2} |",
            r.mapping,
            r.size.0,
            r.size.1,
            r.texels,
            r.solid_angle_ratio,
            r.psnr_per_pixel,
            r.psnr_per_vertex,
            r.seconds
        );
    }
    s
}

fn report_markdown(opts: &DemoOptions, rows: &[DemoRow], w: u32, h: u32) -> String {
    format!(
        "# envmap demo\n\nThe built-in sky (sun, glow, checkered ground) stored in every representation at about {} texels, \
         and a mirror Utah teapot rendered with each at {w}×{h} ({}×{} supersampling), per pixel (seed 000) and per vertex \
         (seed 002). PSNR is measured over the teapot's pixels against a reference render that evaluates the sky exactly at each \
         reflection direction, on the displayed values (exposure {} stops, clamped, sRGB). Images: `atlas_*.png`, `teapot_*_per_pixel.png`, \
         `teapot_*_per_vertex.png`, `error_*.png` (heat maps: black 0, red, yellow, white ≥ 0.25), `teapot_reference.png`.\n\n{}",
        opts.texels,
        opts.samples,
        opts.samples,
        opts.exposure,
        report_table(rows)
    )
}
