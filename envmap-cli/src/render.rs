//! `envmap render`: a mirror object in an environment.

use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::time::Instant;

use clap::Args;
use envmap_core::glam::Vec3;
use envmap_core::AnyMapping;

use crate::args::{
    load_error, output_size, parse_convention, parse_mapping, parse_mode, parse_vec3, parse_world,
    warn_replaced, CliResult, WriteFlags,
};
use envmap_render::bake;
use envmap_render::bake::{Preset, Target};
use envmap_render::filter::bake::BakeOptions;
use envmap_render::filter::Filter;
use envmap_render::image::Representation;
use envmap_render::image::{load_detailed, LoadOptions, NonFinite, SaveOptions};
use envmap_render::image::{Convention, FileAxes, World};
use envmap_render::instruments::Oracle;
use envmap_render::scene::Builtin;
use envmap_render::scene::Material;
use envmap_render::scene::Mesh;
use envmap_render::scene::{
    light_table, Camera, EnvSource, Mode, Progress, RenderOptions, Renderer, Shading,
};
use envmap_render::scene::{LevelBlend, LitEnvironment};

#[derive(Args)]
pub(crate) struct RenderArgs {
    /// Output image (.png, .exr, .hdr).
    pub(crate) output: PathBuf,
    /// The environment: a file, a built-in (sky, room), or what `envmap bake` wrote: its directory (manifest.json beside the maps) or its KTX2 / DDS specular chain, read as the lit maps of a --material instead of baking them.
    #[arg(long, default_value = "sky")]
    pub(crate) env: String,
    /// For a built-in environment: the representation to store it in (default cube).
    #[arg(long, value_parser = parse_mapping)]
    pub(crate) mapping: Option<AnyMapping>,
    /// For a built-in environment: its size (a cube's face edge, any other atlas's width).
    #[arg(long, default_value_t = 512)]
    pub(crate) env_size: u32,
    /// For an environment file: its mapping, when the aspect ratio does not say.
    #[arg(long, value_parser = parse_mapping)]
    pub(crate) from: Option<AnyMapping>,
    #[command(flatten)]
    pub(crate) from_lens: crate::args::FromLensFlags,
    /// For a built-in environment: look it up exactly instead of through a map (the reference).
    #[arg(long)]
    pub(crate) analytic: bool,
    /// The object: teapot, sphere or torus.
    #[arg(long, default_value = "teapot")]
    pub(crate) object: String,
    /// per-pixel (seed 000) or per-vertex (seed 002) lookups.
    #[arg(long, value_parser = parse_mode, default_value = "per-pixel")]
    pub(crate) mode: Mode,
    /// Image width and height in pixels.
    #[arg(long, default_value_t = 640)]
    pub(crate) width: u32,
    /// Image height in pixels.
    #[arg(long, default_value_t = 480)]
    pub(crate) height: u32,
    /// Camera position x,y,z in the world of --frame (default: 0,4,9.5 in the GL world, in front of the teapot and a little above).
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub(crate) eye: Option<Vec3>,
    /// The point looked at x,y,z (default: 0,1.4,0 in the GL world).
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub(crate) target: Option<Vec3>,
    /// The world of --eye and --target and of the environment file's conventions: y-up (the GL world), y-up-lh or z-up (envmap's canonical frame, where the teapot stands on z = 0).
    #[arg(long, value_parser = parse_world)]
    pub(crate) frame: Option<World>,
    /// The environment file's conventions (see `envmap convert --help`; default: what the file says, else envmap); built-in environments are stored in them too.
    #[arg(long, value_parser = parse_convention)]
    pub(crate) convention: Option<Convention>,
    /// Vertical field of view in degrees.
    #[arg(long, default_value_t = 35.0)]
    pub(crate) fov: f32,
    /// Supersampling: N×N sub-pixels per pixel.
    #[arg(long, default_value_t = 2)]
    pub(crate) samples: u32,
    /// Texture filter: nearest or bilinear.
    #[arg(long, default_value = "bilinear")]
    pub(crate) filter: Filter,
    /// Plain bilinear lookups in the map itself, as seed 000 does: no mip level chosen from each reflected ray's footprint (the default reads a mip pyramid of the map trilinearly there, per pixel with the bilinear filter).
    #[arg(long)]
    pub(crate) no_mip: bool,
    /// Schlick Fresnel reflectance at normal incidence (e.g. 0.04 glass, 0.9 metal); default: perfect mirror.
    #[arg(long)]
    pub(crate) fresnel: Option<f32>,
    /// The material: mirror (the default: the plain reflection, with --fresnel), chrome, gold, plastic, rubber, diffuse (glTF metallic-roughness presets); shaded by the split sum from maps baked on the fly.
    #[arg(long)]
    pub(crate) material: Option<String>,
    /// Base colour r,g,b (linear), over the material's.
    #[arg(long, value_parser = parse_vec3)]
    pub(crate) base_color: Option<Vec3>,
    /// Perceptual roughness 0..1 (GGX alpha = roughness²), over the material's.
    #[arg(long)]
    pub(crate) roughness: Option<f32>,
    /// Metallic 0..1, over the material's.
    #[arg(long)]
    pub(crate) metallic: Option<f32>,
    /// Filament's multiscatter energy compensation on the split sum.
    #[arg(long)]
    pub(crate) multiscatter: bool,
    /// Read the specular chain along R itself, not along the lobe's dominant direction mix(R, N, roughness²) (Filament's and Frostbite's default, which is closer to the reference for rough metals).
    #[arg(long)]
    pub(crate) no_dominant_direction: bool,
    /// Render the ground truth instead: the rendering integral of the full GGX + Lambert BRDF by Monte Carlo per pixel (--reference-samples per lobe), the environment looked up exactly (--analytic built-ins) or in the full-resolution map.
    #[arg(long)]
    pub(crate) reference: bool,
    /// Render the exact split sum instead: per pixel, the prefiltered integral at the material's own roughness by brute force over every texel of the environment (not a baked chain), the DFG integral at the pixel's own N·V and roughness, and the exact irradiance; what the split sum's maps are measured against. Slow (an integral over the whole map per pixel).
    #[arg(long, conflicts_with = "reference")]
    pub(crate) exact_split_sum: bool,
    /// Samples per pixel and per lobe of --reference.
    #[arg(long, default_value_t = 256)]
    pub(crate) reference_samples: u32,
    /// Face size of the level 0 of the specular chain baked for a material (envmap's own chain: levels spaced by their lobes, each as large as its lobe needs up to 1.5 × this size, the smallest 16²; the irradiance map is 32², the DFG table 128² with N·V and roughness of 0 and 1 exact).
    #[arg(long, default_value_t = 256)]
    pub(crate) bake_size: u32,
    /// Shade as an engine does: bake the chain its `envmap bake --target` preset makes (bevy, gltf: the linear rule down to 2²; filament: its rule down to 16²; babylon: its rule down to 1²; gltf-ibl: α = 2^k/size down to 1²; level 0 at --bake-size) and blend its levels as its shader does (linear in its lod); with --env DIR, read the bake's chain that way. The DFG table stays envmap's.
    #[arg(long, value_parser = parse_target)]
    pub(crate) engine: Option<Target>,
    /// Exposure in stops for PNG output.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub(crate) exposure: f32,
    #[command(flatten)]
    pub(crate) write: WriteFlags,
    /// Largest environment image accepted, in millions of texels.
    #[arg(long, default_value_t = 268)]
    pub(crate) max_megatexels: u64,
}

pub(crate) fn run(a: &RenderArgs, stop: &AtomicBool) -> CliResult {
    if a.width == 0 || a.height == 0 || u64::from(a.width) * u64::from(a.height) > 1 << 26 {
        return Err(format!(
            "--width {} --height {}: between 1 and 64 Mpixels",
            a.width, a.height
        )
        .into());
    }
    if a.samples == 0 || a.samples > 8 {
        return Err("--samples must be between 1 and 8".into());
    }
    if a.fresnel.is_some_and(|f| !(0.0..=1.0).contains(&f)) {
        return Err("--fresnel must be between 0 and 1".into());
    }
    let given = (a.frame.is_some() || a.convention.is_some()).then(|| {
        FileAxes::Convention(
            a.convention.unwrap_or_default(),
            a.frame.unwrap_or_default(),
        )
    });
    let axes = given.unwrap_or_default();
    let builtin = a.env.parse::<Builtin>().ok();
    // A bake's directory or chain: the lit maps as baked; level 0 (the
    // sharpest) is the environment seen behind the object and in a mirror.
    let baked = match builtin {
        None if bake::is_candidate(Path::new(&a.env)) => bake::open(
            Path::new(&a.env),
            given,
            a.max_megatexels.saturating_mul(1_000_000),
            Some(stop),
        )
        .map_err(|e| load_error(&e))?,
        _ => None,
    };
    if let Some(b) = &baked {
        note!("{}", b.description);
        if a.analytic {
            return Err("--analytic needs a built-in environment (sky, room), not a bake".into());
        }
    }
    let env = match builtin {
        _ if baked.is_some() => baked.as_ref().map(|b| b.env.levels()[0].clone()),
        Some(b) if !a.analytic => {
            let mapping = a.mapping.unwrap_or(AnyMapping::Cube);
            let repr = Representation::for_file(mapping, axes);
            let (w, h) = output_size(&repr, a.env_size)?;
            Some(b.image(repr, w, h)?)
        }
        Some(_) => None,
        None => {
            if a.analytic {
                return Err(format!(
                    "--analytic needs a built-in environment (sky, room), not '{}'",
                    a.env
                )
                .into());
            }
            let opts = {
                let mut o = LoadOptions::default();
                o.mapping = a.from_lens.apply(a.from)?;
                o.axes = given;
                o.non_finite = NonFinite::Zero;
                o.max_texels = a.max_megatexels.saturating_mul(1_000_000);
                o.cancel = Some(stop);
                o
            };
            let loaded = load_detailed(&a.env, &opts).map_err(|e| {
                if Path::new(&a.env).exists() {
                    load_error(&e)
                } else {
                    format!("{e} (built-in environments: sky, room)")
                }
            })?;
            warn_replaced(Path::new(&a.env), loaded.replaced);
            Some(loaded.image)
        }
    };
    let lift = Vec3::new(0.0, 0.0, 1.4);
    let mut mesh = match a.object.to_ascii_lowercase().as_str() {
        "teapot" => Mesh::teapot(10),
        "sphere" => Mesh::sphere(1.5, 128, 64),
        "torus" => Mesh::torus(1.5, 0.55, 128, 48),
        other => {
            return Err(
                format!("unknown object '{other}'; expected teapot, sphere or torus").into(),
            )
        }
    };
    if a.object != "teapot" {
        for p in &mut mesh.positions {
            *p += lift;
        }
    }
    // The renderer works in envmap's canonical axes (z up), where the
    // meshes are made; --eye and --target are in the world of --frame.
    let def = Camera::default();
    let world = a.frame.unwrap_or_default().frame();
    let cam = Camera {
        eye: a.eye.map_or(def.eye, |e| world.to_canonical(e)),
        target: a.target.map_or(def.target, |t| world.to_canonical(t)),
        up: Vec3::Z,
        fov_y_deg: a.fov,
    };
    if (cam.eye - cam.target).length() < 1e-6 {
        return Err("--eye and --target must differ".into());
    }
    let material = material(a)?;
    if a.exact_split_sum && material.is_none() {
        return Err("--exact-split-sum needs a --material other than mirror".into());
    }
    if a.exact_split_sum && baked.is_some() {
        return Err(
            "--exact-split-sum integrates the environment itself (a file or a built-in), not the maps of a bake"
                .into(),
        );
    }
    // The map the lit maps are baked from, and the exact split sum
    // integrates: the environment (the analytic built-ins through a cube of
    // --env-size).
    let lit_source = || -> Result<envmap_render::image::EnvImage, crate::Failure> {
        match &env {
            Some(e) => Ok(e.clone()),
            None => {
                let b = builtin.ok_or("no environment")?;
                let repr = Representation::for_file(AnyMapping::Cube, axes);
                let (w, h) = output_size(&repr, a.env_size)?;
                Ok(b.image(repr, w, h)?)
            }
        }
    };
    let exact_source = match (&material, a.exact_split_sum) {
        (Some(_), true) => Some(lit_source()?),
        _ => None,
    };
    let t = Instant::now();
    let oracle = exact_source.as_ref().map(Oracle::bilinear);
    if oracle.is_some() {
        note!(
            "exact split sum: the oracle of the environment in {:.0} ms",
            t.elapsed().as_secs_f64() * 1e3
        );
    }
    // A material other than the mirror: its maps, baked from the
    // environment.
    let lit = match (&material, a.reference || a.exact_split_sum) {
        (Some(_), false) if baked.is_some() => baked.map(|b| match a.engine {
            Some(t) => {
                let rule = Preset::for_target(t, FileAxes::default()).rule;
                b.env.with_blend(LevelBlend::engine(&rule))
            }
            None => b.env,
        }),
        (Some(_), false) => {
            let src = lit_source()?;
            let t = Instant::now();
            // Seconds for envmap's own chain: a spinner (drawn only when
            // standard error is a terminal).
            let spinner = indicatif::ProgressBar::new_spinner();
            spinner.set_message(format!(
                "baking the material's maps from the environment ({}² level 0{})",
                a.bake_size,
                a.engine
                    .map_or(String::new(), |t| format!(", as --target {}", t.name()))
            ));
            spinner.enable_steady_tick(std::time::Duration::from_millis(120));
            let lit = bake_lit(&src, a.bake_size, a.engine, stop);
            spinner.finish_and_clear();
            let lit = lit?;
            let sizes: Vec<u32> = lit.levels().iter().map(|l| l.cell_size().0).collect();
            note!(
                "baked {} levels ({}² … {}²{}) and a 32² irradiance map in {:.0} ms",
                lit.levels().len(),
                sizes[0],
                sizes[sizes.len() - 1],
                a.engine.map_or(String::new(), |t| format!(
                    ", as --target {} makes them",
                    t.name()
                )),
                t.elapsed().as_secs_f64() * 1e3
            );
            Some(lit)
        }
        _ => None,
    };
    let analytic_fn = |d: Vec3| builtin.map_or([0.0; 3], |b| b.radiance(d));
    let source = match &env {
        Some(e) => EnvSource::Map(e),
        None => EnvSource::Analytic(&analytic_fn),
    };
    let light = (material.is_some() && a.reference).then(|| light_table(source, a.filter));
    let shading = match (material, &lit) {
        (Some(m), _) if a.reference => Shading::Reference {
            material: m,
            samples: a.reference_samples.max(1),
            light: light.as_ref(),
            seed: 0,
        },
        (Some(m), _) if oracle.is_some() => Shading::ExactSplitSum {
            oracle: oracle.as_ref().ok_or("no oracle")?,
            material: m,
            multiscatter: a.multiscatter,
            dominant: !a.no_dominant_direction,
        },
        (Some(m), Some(env)) => Shading::SplitSum {
            env,
            material: m,
            multiscatter: a.multiscatter,
            dominant: !a.no_dominant_direction,
        },
        _ => Shading::Mirror,
    };
    let opts = {
        let mut o = RenderOptions::default();
        o.width = a.width;
        o.height = a.height;
        o.mode = a.mode;
        o.samples = a.samples;
        o.filter = a.filter;
        o.fresnel_f0 = a.fresnel;
        o.tint = [1.0; 3];
        o.background = true;
        o.shading = shading;
        o.cancel = Some(stop);
        o.mip = !a.no_mip;
        o.mip_levels = None;
        o.progress = None;
        o
    };
    // The reference takes seconds to minutes: a progress bar (drawn only
    // when standard error is a terminal).
    let slow = a.reference || a.exact_split_sum;
    let bar = if slow {
        let b = indicatif::ProgressBar::new(1);
        b.set_style(
            indicatif::ProgressStyle::with_template(
                "{msg} [{bar:40}] {pos}/{len} bands of rows ({eta})",
            )
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar())
            .progress_chars("=> "),
        );
        b.set_message(if a.reference {
            "reference"
        } else {
            "exact split sum"
        });
        b
    } else {
        indicatif::ProgressBar::hidden()
    };
    let tick = |done: u32, total: u32| {
        bar.set_length(u64::from(total));
        bar.set_position(u64::from(done));
    };
    let opts = {
        let mut o = opts;
        o.progress = slow.then_some(Progress(&tick));
        o
    };
    let t = Instant::now();
    let img = Renderer::new().render(&mesh, source, &cam, &opts)?;
    bar.finish_and_clear();
    let elapsed = t.elapsed();
    let sopts = {
        let mut o = a.write.over(SaveOptions::default());
        o.exposure = a.exposure;
        o.cancel = Some(stop);
        o
    };
    envmap_render::image::write_rgb(&img, &a.output, &sopts)?;
    note!(
        "{} {}×{} ({} triangles, {} lookups, {}×{} samples): {:.0} ms",
        a.output.display(),
        a.width,
        a.height,
        mesh.triangles.len(),
        match a.mode {
            Mode::PerPixel => "per-pixel",
            Mode::PerVertex => "per-vertex",
        },
        a.samples,
        a.samples,
        elapsed.as_secs_f64() * 1e3
    );
    Ok(())
}

/// The material the flags ask for; `None` for the plain mirror.
fn material(a: &RenderArgs) -> Result<Option<Material>, crate::Failure> {
    let named = a.material.as_deref().unwrap_or("mirror");
    let mirror = named.eq_ignore_ascii_case("mirror")
        && a.base_color.is_none()
        && a.roughness.is_none()
        && a.metallic.is_none();
    if mirror && !a.reference {
        if a.multiscatter {
            return Err("--multiscatter is for a --material other than mirror".into());
        }
        return Ok(None);
    }
    let mut m = Material::preset(named)?;
    if let Some(c) = a.base_color {
        m.base_color = c.to_array();
    }
    if let Some(r) = a.roughness {
        m.roughness = r;
    }
    if let Some(x) = a.metallic {
        m.metallic = x;
    }
    let unit = |v: f32| (0.0..=1.0).contains(&v);
    if !unit(m.roughness) || !unit(m.metallic) || !m.base_color.iter().all(|&c| unit(c)) {
        return Err("--roughness, --metallic and --base-color take values between 0 and 1".into());
    }
    Ok(Some(m))
}

/// The maps a split-sum render reads, baked from `src` in its own axes:
/// envmap's own, or the chain of `engine`'s preset read as it reads it.
fn bake_lit(
    src: &envmap_render::image::EnvImage,
    size: u32,
    engine: Option<Target>,
    stop: &AtomicBool,
) -> Result<LitEnvironment, crate::Failure> {
    if !(2..=2048).contains(&size) {
        return Err("--bake-size: between 2 and 2048".into());
    }
    match engine {
        None => Ok(LitEnvironment::bake(src, size, Some(stop))?),
        Some(t) => {
            let preset = Preset::for_target(t, FileAxes::default());
            let mut opts = preset.bake_options(BakeOptions::default());
            opts.size = size;
            opts.irradiance_size = 32;
            opts.dfg_size = 0;
            opts.cancel = Some(stop);
            Ok(LitEnvironment::bake_with(src, &opts)
                .map(|l| l.with_blend(LevelBlend::engine(&preset.rule)))?)
        }
    }
}

fn parse_target(s: &str) -> Result<Target, String> {
    s.parse()
}
