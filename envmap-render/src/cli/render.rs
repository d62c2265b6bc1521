//! `envmap render`: a mirror object in an environment.

use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::time::Instant;

use clap::Args;
use envmap_core::glam::Vec3;
use envmap_core::AnyMapping;

use crate::cli::args::{
    load_error, output_size, parse_convention, parse_mapping, parse_mode, parse_vec3, parse_world,
    warn_replaced, CliResult,
};
use crate::filter::sample::Filter;
use crate::image::convention::{Convention, FileAxes, World};
use crate::image::io::{load_detailed, LoadOptions, NonFinite, SaveOptions};
use crate::image::Representation;
use crate::scene::environments::Builtin;
use crate::scene::mesh::Mesh;
use crate::scene::render::{render, Camera, EnvSource, Mode, RenderOptions};

#[derive(Args)]
pub(crate) struct RenderArgs {
    /// Output image (.png, .exr, .hdr).
    pub(crate) output: PathBuf,
    /// The environment: a file, or a built-in: sky, room.
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
    /// Schlick Fresnel reflectance at normal incidence (e.g. 0.04 glass, 0.9 metal); default: perfect mirror.
    #[arg(long)]
    pub(crate) fresnel: Option<f32>,
    /// Exposure in stops for PNG output.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub(crate) exposure: f32,
    /// Largest environment image accepted, in millions of texels.
    #[arg(long, default_value_t = 268)]
    pub(crate) max_megatexels: u64,
}

pub(crate) fn run(a: &RenderArgs, stop: &AtomicBool) -> CliResult {
    if a.width == 0 || a.height == 0 || u64::from(a.width) * u64::from(a.height) > 1 << 26 {
        return Err(format!(
            "--width {} --height {}: between 1 and 64 Mpixels",
            a.width, a.height
        ));
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
    let env = match builtin {
        Some(b) if !a.analytic => {
            let mapping = a.mapping.unwrap_or(AnyMapping::Cube);
            let repr = Representation::for_file(mapping, axes);
            let (w, h) = output_size(&repr, a.env_size)?;
            Some(b.image(repr, w, h).map_err(|e| e.to_string())?)
        }
        Some(_) => None,
        None => {
            if a.analytic {
                return Err(format!(
                    "--analytic needs a built-in environment (sky, room), not '{}'",
                    a.env
                ));
            }
            let opts = LoadOptions {
                mapping: a.from,
                axes: given,
                non_finite: NonFinite::Zero,
                max_texels: a.max_megatexels.saturating_mul(1_000_000),
                cancel: Some(stop),
                ..LoadOptions::default()
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
            return Err(format!(
                "unknown object '{other}'; expected teapot, sphere or torus"
            ))
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
    let opts = RenderOptions {
        width: a.width,
        height: a.height,
        mode: a.mode,
        samples: a.samples,
        filter: a.filter,
        fresnel_f0: a.fresnel,
        tint: [1.0; 3],
        background: true,
        cancel: Some(stop),
    };
    let t = Instant::now();
    let analytic_fn = |d: Vec3| builtin.map_or([0.0; 3], |b| b.radiance(d));
    let img = match &env {
        Some(e) => render(&mesh, EnvSource::Map(e), &cam, &opts),
        None => render(&mesh, EnvSource::Analytic(&analytic_fn), &cam, &opts),
    }
    .map_err(|e| e.to_string())?;
    let elapsed = t.elapsed();
    let sopts = SaveOptions {
        exposure: a.exposure,
        cancel: Some(stop),
        ..SaveOptions::default()
    };
    crate::image::io::write_rgb(&img, &a.output, &sopts).map_err(|e| e.to_string())?;
    eprintln!(
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
