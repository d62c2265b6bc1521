//! The `envmap` command: convert environment maps between representations,
//! inspect them, and map directions to texture coordinates and back.
//!
//! Exit codes: 0 success; 1 a runtime error (a file that cannot be read,
//! decoded or written, an image above the size limit or fitting no layout,
//! a bad input line); 2 a usage error (unknown command, flag or value,
//! reported by the argument parser). `--help` prints them.

#![deny(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::io::{BufRead, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

use clap::{Args, Parser, Subcommand};
use envmap_core::glam::Vec3;
use envmap_core::{AnyMapping, Frame, Mapping};
use envmap_render::convert::{auto_samples, convert, ConvertOptions};
use envmap_render::environments::Builtin;
use envmap_render::image::{EnvImage, Representation};
use envmap_render::io::{
    load_detailed, save, ExrPrecision, LoadOptions, Loaded, NonFinite, SaveOptions,
};
use envmap_render::layout::Layout;
use envmap_render::mesh::Mesh;
use envmap_render::render::{render, Camera, EnvSource, Mode, RenderOptions};
use envmap_render::sample::Filter;
use envmap_render::text::{MapLines, UnmapLines};
use indicatif::{ProgressBar, ProgressStyle};

/// The exit codes, as `--help` prints them.
const EXIT_STATUS: &str = "Exit status: 0 success; 1 an error while running (a file that \
cannot be read, decoded or written, an image above the size limit or fitting no layout, a bad \
input line); 2 a usage error (an unknown command, flag or value). Errors are one line on \
standard error, naming the file and the problem.";

#[derive(Parser)]
#[command(
    name = "envmap",
    version,
    about = "Environment maps: convert between every representation, inspect, map directions.",
    long_about = None,
    after_help = EXIT_STATUS
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Convert an environment map into another representation.
    ///
    /// Example: envmap convert studio.hdr studio_cube.exr --to cube --layout cross --size 1024
    Convert(ConvertArgs),
    /// Describe an environment map file: size, format, representation, radiance.
    Info(InfoArgs),
    /// Map directions (one `x y z` or `x,y,z` per line) to `chart,u,v` (CSV).
    Map(MapArgs),
    /// Map `chart,u,v` lines (as `map` prints them) back to unit directions `x,y,z`.
    Unmap(UnmapArgs),
    /// Every representation of the built-in sky, a mirror teapot in each, error maps and a report.
    ///
    /// Example: envmap demo --out envmap-demo
    Demo(DemoArgs),
    /// Render a mirror object (teapot, sphere, torus) in an environment.
    ///
    /// Example: envmap render teapot.png --env sky --mapping latlong --mode per-vertex
    Render(RenderArgs),
}

fn parse_vec3(s: &str) -> Result<Vec3, String> {
    let v: Result<Vec<f32>, _> = s.split(',').map(|t| t.trim().parse::<f32>()).collect();
    match v {
        Ok(v) if v.len() == 3 && v.iter().all(|x| x.is_finite()) => Ok(Vec3::new(v[0], v[1], v[2])),
        _ => Err(format!("expected x,y,z (e.g. 0,-9.5,4), got '{s}'")),
    }
}

fn parse_mode(s: &str) -> Result<Mode, String> {
    match s.to_ascii_lowercase().as_str() {
        "per-pixel" | "pixel" => Ok(Mode::PerPixel),
        "per-vertex" | "vertex" => Ok(Mode::PerVertex),
        _ => Err(format!(
            "unknown mode '{s}'; expected per-pixel or per-vertex"
        )),
    }
}

#[derive(Args)]
struct DemoArgs {
    /// Output directory.
    #[arg(long, default_value = "envmap-demo")]
    out: PathBuf,
    /// Texel budget per representation, in thousands.
    #[arg(long, default_value_t = 393)]
    ktexels: u64,
    /// Render width in pixels (height is 3/4 of it).
    #[arg(long, default_value_t = 480)]
    width: u32,
    /// Supersampling of the renders (N×N).
    #[arg(long, default_value_t = 2)]
    samples: u32,
    /// No progress bar.
    #[arg(long, short)]
    quiet: bool,
}

#[derive(Args)]
struct RenderArgs {
    /// Output image (.png, .exr, .hdr).
    output: PathBuf,
    /// The environment: a file, or a built-in: sky, room.
    #[arg(long, default_value = "sky")]
    env: String,
    /// For a built-in environment: the representation to store it in (default cube).
    #[arg(long, value_parser = parse_mapping)]
    mapping: Option<AnyMapping>,
    /// For a built-in environment: its size (a cube's face edge, any other atlas's width).
    #[arg(long, default_value_t = 512)]
    env_size: u32,
    /// For an environment file: its mapping, when the aspect ratio does not say.
    #[arg(long, value_parser = parse_mapping)]
    from: Option<AnyMapping>,
    /// For a built-in environment: look it up exactly instead of through a map (the reference).
    #[arg(long)]
    analytic: bool,
    /// The object: teapot, sphere or torus.
    #[arg(long, default_value = "teapot")]
    object: String,
    /// per-pixel (seed 000) or per-vertex (seed 002) lookups.
    #[arg(long, value_parser = parse_mode, default_value = "per-pixel")]
    mode: Mode,
    /// Image width and height in pixels.
    #[arg(long, default_value_t = 640)]
    width: u32,
    /// Image height in pixels.
    #[arg(long, default_value_t = 480)]
    height: u32,
    /// Camera position x,y,z (z up).
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    eye: Option<Vec3>,
    /// The point looked at x,y,z.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    target: Option<Vec3>,
    /// Vertical field of view in degrees.
    #[arg(long, default_value_t = 35.0)]
    fov: f32,
    /// Supersampling: N×N sub-pixels per pixel.
    #[arg(long, default_value_t = 2)]
    samples: u32,
    /// Texture filter: nearest or bilinear.
    #[arg(long, default_value = "bilinear")]
    filter: Filter,
    /// Schlick Fresnel reflectance at normal incidence (e.g. 0.04 glass, 0.9 metal); default: perfect mirror.
    #[arg(long)]
    fresnel: Option<f32>,
    /// Exposure in stops for PNG output.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    exposure: f32,
    /// Largest environment image accepted, in millions of texels.
    #[arg(long, default_value_t = 268)]
    max_megatexels: u64,
}

/// The mapping names the command accepts.
fn parse_mapping(s: &str) -> Result<AnyMapping, String> {
    s.parse::<AnyMapping>().map_err(|e| e.to_string())
}

fn parse_layout(s: &str) -> Result<Layout, String> {
    s.parse::<Layout>().map_err(|e| e.to_string())
}

fn parse_frame(s: &str) -> Result<Frame, String> {
    match s.to_ascii_lowercase().as_str() {
        "z-up" | "zup" | "z-up-rh" => Ok(Frame::Z_UP_RH),
        "y-up" | "yup" | "y-up-rh" | "gl" | "gltf" => Ok(Frame::Y_UP_RH),
        "y-up-lh" | "d3d" | "unity" => Ok(Frame::Y_UP_LH),
        _ => Err(format!(
            "unknown frame '{s}'; expected z-up, y-up (OpenGL, glTF) or y-up-lh (Direct3D, Unity)"
        )),
    }
}

/// `yaw,pitch,roll` in degrees.
fn parse_rotation(s: &str) -> Result<Frame, String> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    let v: Result<Vec<f32>, _> = parts.iter().map(|p| p.parse::<f32>()).collect();
    match v {
        Ok(v) if v.len() == 3 && v.iter().all(|x| x.is_finite()) => Ok(Frame::from_yaw_pitch_roll(
            v[0].to_radians(),
            v[1].to_radians(),
            v[2].to_radians(),
        )),
        _ => Err(format!(
            "expected yaw,pitch,roll in degrees (e.g. 90,0,0), got '{s}'"
        )),
    }
}

#[derive(Args)]
struct ConvertArgs {
    /// Input file (.png, .jpg, .hdr, .exr; a six-file cube by one face's name).
    input: PathBuf,
    /// Output file (.png, .hdr, .exr); `{face}` in the name, or --layout faces, writes six files.
    output: PathBuf,
    /// Output mapping: latlong, cube, sphere, sphere-gl, paraboloid, tennisball, octahedral, octahedral-equal-area.
    #[arg(long, value_parser = parse_mapping)]
    to: AnyMapping,
    /// Output layout (cube: cross, vcross, strip, vstrip, faces); default: the mapping's own.
    #[arg(long, value_parser = parse_layout)]
    layout: Option<Layout>,
    /// Face edge of a cube, width of any other atlas, in texels (default: about the input's texel count).
    #[arg(long)]
    size: Option<u32>,
    /// Input mapping, when the aspect ratio does not say (e.g. a square image).
    #[arg(long, value_parser = parse_mapping)]
    from: Option<AnyMapping>,
    /// Input layout, when the aspect ratio does not say.
    #[arg(long, value_parser = parse_layout)]
    from_layout: Option<Layout>,
    /// Axis convention of the input's directions.
    #[arg(long, value_parser = parse_frame, default_value = "z-up")]
    from_frame: Frame,
    /// Axis convention of the output's directions.
    #[arg(long, value_parser = parse_frame, default_value = "z-up")]
    to_frame: Frame,
    /// Reconstruction filter: nearest or bilinear.
    #[arg(long, default_value = "bilinear")]
    filter: Filter,
    /// Sub-samples per output texel side (N×N); default: automatic from the size ratio.
    #[arg(long)]
    samples: Option<u32>,
    /// Rotation on the way, yaw,pitch,roll in degrees (about z, y, x).
    #[arg(long, value_parser = parse_rotation, allow_hyphen_values = true)]
    rotate: Option<Frame>,
    /// Worker threads (default: one per core).
    #[arg(long)]
    threads: Option<usize>,
    /// Exposure in stops for 8-bit outputs (PNG).
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    exposure: f32,
    /// Write OpenEXR as 16-bit half floats.
    #[arg(long)]
    half: bool,
    /// Allow the output to replace the input file.
    #[arg(long)]
    overwrite_input: bool,
    /// Largest image accepted, in millions of texels.
    #[arg(long, default_value_t = 268)]
    max_megatexels: u64,
    /// No progress bar or summary.
    #[arg(long, short)]
    quiet: bool,
}

#[derive(Args)]
struct InfoArgs {
    /// The file.
    file: PathBuf,
    /// Mapping, when the aspect ratio does not say.
    #[arg(long, value_parser = parse_mapping)]
    from: Option<AnyMapping>,
    /// Layout, when the aspect ratio does not say.
    #[arg(long, value_parser = parse_layout)]
    layout: Option<Layout>,
    /// Largest image accepted, in millions of texels.
    #[arg(long, default_value_t = 268)]
    max_megatexels: u64,
}

#[derive(Args)]
struct MapArgs {
    /// The mapping.
    #[arg(long, value_parser = parse_mapping)]
    mapping: AnyMapping,
    /// Axis convention of the input directions.
    #[arg(long, value_parser = parse_frame, default_value = "z-up")]
    frame: Frame,
    /// Also print the texel x,y in an atlas of this size (cube: face edge; others: width).
    #[arg(long)]
    size: Option<u32>,
    /// Atlas layout for --size (default: the mapping's own).
    #[arg(long, value_parser = parse_layout)]
    layout: Option<Layout>,
    /// Read from this file instead of standard input.
    input: Option<PathBuf>,
}

#[derive(Args)]
struct UnmapArgs {
    /// The mapping.
    #[arg(long, value_parser = parse_mapping)]
    mapping: AnyMapping,
    /// Axis convention of the output directions.
    #[arg(long, value_parser = parse_frame, default_value = "z-up")]
    frame: Frame,
    /// Read from this file instead of standard input.
    input: Option<PathBuf>,
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Convert(a) => run_convert(&a),
        Command::Info(a) => run_info(&a),
        Command::Map(a) => run_map(&a),
        Command::Unmap(a) => run_unmap(&a),
        Command::Render(a) => run_render(&a),
        Command::Demo(a) => run_demo(&a),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("envmap: error: {e}");
            ExitCode::from(1)
        }
    }
}

type CliResult = Result<(), String>;

/// A load error's message, with how to raise the size limit when that is
/// what stopped it.
fn load_error(e: &envmap_render::Error) -> String {
    fn too_large(e: &envmap_render::Error) -> bool {
        match e {
            envmap_render::Error::TooLarge { .. } => true,
            envmap_render::Error::InFile { source, .. } => too_large(source),
            _ => false,
        }
    }
    if too_large(e) {
        format!("{e} (raise the limit with --max-megatexels)")
    } else {
        e.to_string()
    }
}

/// Says on standard error how many NaN or infinite texels loading replaced.
fn warn_replaced(path: &Path, n: u64) {
    if n > 0 {
        eprintln!(
            "envmap: warning: {}: {n} texel{} with NaN or infinite values replaced by black",
            path.display(),
            if n == 1 { "" } else { "s" }
        );
    }
}

/// The image size for `--size` in a representation: a cube's face edge, any
/// other atlas's width.
fn output_size(repr: &Representation, size: u32) -> Result<(u32, u32), String> {
    let atlas = repr.atlas;
    // The image width must be a whole number of cells whose height is whole.
    let (step, what) = if repr.mapping == AnyMapping::Cube {
        (atlas.cell_aspect_w, "face edge")
    } else {
        (atlas.cols * atlas.cell_aspect_w, "width")
    };
    let cell = if repr.mapping == AnyMapping::Cube {
        Some(size)
    } else {
        size.is_multiple_of(atlas.cols).then_some(size / atlas.cols)
    };
    cell.and_then(|c| atlas.image_size_for_cell_width(c))
        .ok_or_else(|| {
            let lower = size / step * step;
            let upper = lower + step;
            let suggest = if lower == 0 {
                format!("{upper}")
            } else {
                format!("{lower} or {upper}")
            };
            format!(
                "--size {size}: a {} in the {} layout needs a {what} divisible by {step}; try {suggest}",
                repr.mapping, atlas.name
            )
        })
}

/// Default `--size`: about as many texels as the input.
fn default_size(repr: &Representation, input_texels: u64) -> u32 {
    let a = repr.atlas;
    let (aw, ah) = (
        f64::from(a.cols * a.cell_aspect_w),
        f64::from(a.rows * a.cell_aspect_h),
    );
    // width × height = texels with width : height = aw : ah
    let width = (input_texels as f64 * aw / ah).sqrt();
    let unit = f64::from(a.cols * a.cell_aspect_w);
    let cells = (width / unit).round().max(1.0);
    let width = (cells * unit) as u32;
    if repr.mapping == AnyMapping::Cube {
        width / a.cols
    } else {
        width
    }
}

fn output_representation(a: &ConvertArgs) -> Result<(Representation, bool), String> {
    let layout = a.layout.unwrap_or_else(|| {
        if a.output.to_string_lossy().contains("{face}") && a.to == AnyMapping::Cube {
            Layout::Faces
        } else {
            Layout::for_mapping(a.to)[0]
        }
    });
    if !Layout::for_mapping(a.to).contains(&layout) {
        let names: Vec<&str> = Layout::for_mapping(a.to).iter().map(|l| l.name()).collect();
        return Err(format!(
            "--layout {}: {} has no such layout; its layouts: {}",
            layout.name(),
            a.to,
            names.join(", ")
        ));
    }
    let six = layout.is_six_files();
    Ok((
        Representation::new(a.to, layout.atlas(), a.to_frame).map_err(|e| e.to_string())?,
        six,
    ))
}

fn run_convert(a: &ConvertArgs) -> CliResult {
    if let Some(n) = a.threads {
        if n == 0 {
            return Err("--threads must be at least 1".into());
        }
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build_global()
            .map_err(|e| format!("--threads {n}: {e}"))?;
    }
    if a.samples == Some(0) || a.samples.is_some_and(|s| s > 16) {
        return Err("--samples must be between 1 and 16".into());
    }
    let t0 = Instant::now();
    let opts = LoadOptions {
        mapping: a.from,
        layout: a.from_layout,
        frame: a.from_frame,
        max_texels: a.max_megatexels.saturating_mul(1_000_000),
        non_finite: NonFinite::Zero,
    };
    let loaded = load_detailed(&a.input, &opts).map_err(|e| load_error(&e))?;
    warn_replaced(&a.input, loaded.replaced);
    let Loaded {
        image: src,
        files: inputs,
        ..
    } = loaded;
    let t_load = t0.elapsed();
    let (repr, six) = output_representation(a)?;
    let in_texels = u64::from(src.width()) * u64::from(src.height());
    let size = a.size.unwrap_or_else(|| default_size(&repr, in_texels));
    if size == 0 {
        return Err("--size must be at least 1".into());
    }
    let (w, h) = output_size(&repr, size)?;
    let need = EnvImage::memory_bytes_for(w, h);
    if u64::from(w) * u64::from(h) > a.max_megatexels.saturating_mul(1_000_000) {
        return Err(format!(
            "output {w}×{h} ({:.1} Mtexels, {:.1} GiB) exceeds --max-megatexels {}",
            f64::from(w) * f64::from(h) / 1e6,
            need as f64 / f64::from(1u32 << 30),
            a.max_megatexels
        ));
    }
    let copts = ConvertOptions {
        filter: a.filter,
        samples: a.samples,
        rotation: a.rotate,
    };
    let samples = a
        .samples
        .unwrap_or_else(|| auto_samples(in_texels, u64::from(w) * u64::from(h)));
    let bar = if a.quiet {
        ProgressBar::hidden()
    } else {
        let b = ProgressBar::new(u64::from(h));
        b.set_style(
            ProgressStyle::with_template("{msg} [{bar:40}] {pos}/{len} rows ({eta})")
                .unwrap_or_else(|_| ProgressStyle::default_bar())
                .progress_chars("=> "),
        );
        b.set_message("converting");
        b
    };
    let done = AtomicU64::new(0);
    let tick = |k: u32| {
        let n = done.fetch_add(u64::from(k), Ordering::Relaxed) + u64::from(k);
        if n.is_multiple_of(64) {
            bar.set_position(n);
        }
    };
    let t1 = Instant::now();
    let out = convert(&src, repr, w, h, &copts, Some(&tick)).map_err(|e| e.to_string())?;
    let t_convert = t1.elapsed();
    // The input is no longer needed: free it before encoding, which may
    // need buffers of its own.
    let (src_w, src_h, src_mapping) = (src.width(), src.height(), src.mapping());
    drop(src);
    bar.finish_and_clear();
    let sopts = SaveOptions {
        exposure: a.exposure,
        exr_precision: if a.half {
            ExrPrecision::F16
        } else {
            ExrPrecision::F32
        },
        six_files: six,
        inputs,
        overwrite_input: a.overwrite_input,
    };
    let t2 = Instant::now();
    let written = save(&out, &a.output, &sopts).map_err(|e| e.to_string())?;
    let t_save = t2.elapsed();
    if !a.quiet {
        eprintln!(
            "{} {}×{} {} -> {} {}×{} {} ({}, {}×{} samples): load {:.0} ms, convert {:.0} ms, save {:.0} ms",
            a.input.display(),
            src_w,
            src_h,
            src_mapping,
            written
                .first()
                .map_or_else(|| a.output.display().to_string(), |p| p.display().to_string()),
            w,
            h,
            repr.mapping,
            match a.filter {
                Filter::Nearest => "nearest",
                Filter::Bilinear => "bilinear",
            },
            samples,
            samples,
            t_load.as_secs_f64() * 1e3,
            t_convert.as_secs_f64() * 1e3,
            t_save.as_secs_f64() * 1e3,
        );
    }
    Ok(())
}

fn run_info(a: &InfoArgs) -> CliResult {
    let opts = LoadOptions {
        mapping: a.from,
        layout: a.layout,
        max_texels: a.max_megatexels.saturating_mul(1_000_000),
        ..LoadOptions::default()
    };
    let loaded = load_detailed(&a.file, &opts).map_err(|e| load_error(&e))?;
    let img = &loaded.image;
    let repr = img.representation();
    let s = img.stats();
    let mut out = std::io::stdout().lock();
    let p = |out: &mut dyn Write, k: &str, v: String| writeln!(out, "{k:<16} {v}");
    let files: Vec<String> = loaded
        .files
        .iter()
        .map(|f| f.display().to_string())
        .collect();
    let r = (|| -> std::io::Result<()> {
        p(&mut out, "file", files.join(", "))?;
        p(
            &mut out,
            "dimensions",
            format!("{} × {}", img.width(), img.height()),
        )?;
        p(
            &mut out,
            "pixel format",
            format!("{:?}, {}", loaded.source.format, loaded.source.pixel_format),
        )?;
        p(&mut out, "mapping", repr.mapping.to_string())?;
        let (cw, ch) = img.cell_size();
        p(
            &mut out,
            "layout",
            format!(
                "{} ({} chart{} of {cw} × {ch})",
                repr.atlas.name,
                repr.mapping.chart_count(),
                if repr.mapping.chart_count() == 1 {
                    ""
                } else {
                    "s"
                }
            ),
        )?;
        p(
            &mut out,
            "texels",
            format!(
                "{} in charts (of {} in the image)",
                s.texels,
                u64::from(img.width()) * u64::from(img.height())
            ),
        )?;
        p(
            &mut out,
            "radiance min",
            format!(
                "{:.6} {:.6} {:.6} (luminance {:.6})",
                s.min[0], s.min[1], s.min[2], s.min_luminance
            ),
        )?;
        p(
            &mut out,
            "radiance max",
            format!(
                "{:.6} {:.6} {:.6} (luminance {:.6})",
                s.max[0], s.max[1], s.max[2], s.max_luminance
            ),
        )?;
        p(
            &mut out,
            "radiance mean",
            format!(
                "{:.6} {:.6} {:.6} (luminance {:.6}; over the sphere, by solid angle)",
                s.sphere_mean[0], s.sphere_mean[1], s.sphere_mean[2], s.sphere_mean_luminance
            ),
        )?;
        p(
            &mut out,
            "texel mean",
            format!(
                "{:.6} {:.6} {:.6} (luminance {:.6}; every texel counted once)",
                s.mean[0], s.mean[1], s.mean[2], s.mean_luminance
            ),
        )?;
        p(&mut out, "NaN texels", s.nan.to_string())?;
        p(&mut out, "Inf texels", s.inf.to_string())?;
        let mib = |b: u64| b as f64 / f64::from(1u32 << 20);
        let held = EnvImage::memory_bytes_for(img.width(), img.height());
        p(
            &mut out,
            "memory",
            format!("{:.1} MiB as linear f32 RGB", mib(held)),
        )?;
        p(
            &mut out,
            "conversion",
            format!(
                "needs about {:.1} MiB at the default output size: this image plus an output \
                 of as many texels, 12 bytes each (another --size: {:.1} MiB plus 12 bytes \
                 per output texel)",
                mib(2 * held),
                mib(held)
            ),
        )?;
        Ok(())
    })();
    r.map_err(|e| format!("<stdout>: {e}"))
}

/// Lines of the input (a file or standard input), with its display name.
fn read_lines(input: Option<&Path>) -> Result<(String, Vec<String>), String> {
    match input {
        Some(p) => {
            let text = std::fs::read_to_string(p)
                .map_err(|e| format!("{}: cannot read: {e}", p.display()))?;
            Ok((
                p.display().to_string(),
                text.lines().map(str::to_owned).collect(),
            ))
        }
        None => {
            let mut lines = Vec::new();
            for l in std::io::stdin().lock().lines() {
                lines.push(l.map_err(|e| format!("<stdin>: cannot read: {e}"))?);
            }
            Ok(("<stdin>".to_owned(), lines))
        }
    }
}

fn run_map(a: &MapArgs) -> CliResult {
    let (name, lines) = read_lines(a.input.as_deref())?;
    let atlas = match a.layout {
        Some(l) if !Layout::for_mapping(a.mapping).contains(&l) || l.is_six_files() => {
            return Err(format!(
                "--layout {}: not a single-image layout of {}",
                l.name(),
                a.mapping
            ));
        }
        Some(l) => l.atlas(),
        None => a.mapping.atlas(),
    };
    let size = match a.size {
        Some(n) => {
            let repr = Representation::new(a.mapping, atlas, a.frame).map_err(|e| e.to_string())?;
            Some(output_size(&repr, n)?)
        }
        None => None,
    };
    let parser = MapLines::new(a.mapping, a.frame, atlas, size);
    write_rows(&name, &lines, parser.header(), |l| parser.line(l))
}

fn run_unmap(a: &UnmapArgs) -> CliResult {
    let (name, lines) = read_lines(a.input.as_deref())?;
    let parser = UnmapLines::new(a.mapping, a.frame);
    write_rows(&name, &lines, parser.header(), |l| parser.line(l))
}

/// Prints `header`, then the row of each line that gives one; stops at the
/// first bad line with an error naming it (`<name>:<line>: ...`).
fn write_rows(
    name: &str,
    lines: &[String],
    header: &str,
    row: impl Fn(&str) -> envmap_render::Result<Option<String>>,
) -> CliResult {
    let stdout = std::io::stdout();
    let mut out = BufWriter::new(stdout.lock());
    let io = |e: std::io::Error| format!("<stdout>: {e}");
    writeln!(out, "{header}").map_err(io)?;
    for (k, line) in lines.iter().enumerate() {
        match row(line) {
            Ok(Some(r)) => writeln!(out, "{r}").map_err(io)?,
            Ok(None) => {}
            Err(e) => return Err(format!("{name}:{}: {e}", k + 1)),
        }
    }
    out.flush().map_err(io)
}

fn run_render(a: &RenderArgs) -> CliResult {
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
    let builtin = a.env.parse::<Builtin>().ok();
    let env = match builtin {
        Some(b) if !a.analytic => {
            let repr = Representation::default_for(a.mapping.unwrap_or(AnyMapping::Cube));
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
                non_finite: NonFinite::Zero,
                max_texels: a.max_megatexels.saturating_mul(1_000_000),
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
    let def = Camera::default();
    let cam = Camera {
        eye: a.eye.unwrap_or(def.eye),
        target: a.target.unwrap_or(def.target),
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
    };
    let t = Instant::now();
    let analytic_fn = |d: Vec3| builtin.map_or([0.0; 3], |b| b.radiance(d));
    let img = match &env {
        Some(e) => render(&mesh, EnvSource::Map(e), &cam, &opts),
        None => render(&mesh, EnvSource::Analytic(&analytic_fn), &cam, &opts),
    };
    let elapsed = t.elapsed();
    let sopts = SaveOptions {
        exposure: a.exposure,
        ..SaveOptions::default()
    };
    envmap_render::io::write_rgb(&img, &a.output, &sopts).map_err(|e| e.to_string())?;
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

fn run_demo(a: &DemoArgs) -> CliResult {
    if a.ktexels == 0
        || a.ktexels > 100_000
        || a.width < 16
        || a.width > 8192
        || a.samples == 0
        || a.samples > 8
    {
        return Err("--ktexels 1..100000, --width 16..8192, --samples 1..8".into());
    }
    let opts = envmap_render::demo::DemoOptions {
        out: a.out.clone(),
        texels: a.ktexels * 1000,
        width: a.width,
        samples: a.samples,
        ..envmap_render::demo::DemoOptions::default()
    };
    let bar = if a.quiet {
        ProgressBar::hidden()
    } else {
        let b = ProgressBar::new(1);
        b.set_style(
            ProgressStyle::with_template("{msg:>24} [{bar:30}] {pos}/{len} ({elapsed})")
                .unwrap_or_else(|_| ProgressStyle::default_bar())
                .progress_chars("=> "),
        );
        b
    };
    let t = Instant::now();
    let rows = envmap_render::demo::run(&opts, &|done, total, what| {
        bar.set_length(u64::from(total));
        bar.set_position(u64::from(done));
        bar.set_message(what.to_owned());
    })
    .map_err(|e| e.to_string())?;
    bar.finish_and_clear();
    print!("{}", envmap_render::demo::report_table(&rows));
    println!(
        "\nwrote {} ({} images and report.md) in {:.1} s",
        a.out.display(),
        1 + 5 * rows.len(),
        t.elapsed().as_secs_f64()
    );
    Ok(())
}
