//! `envmap bake`: image-based lighting from one environment map.

use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::sync::Mutex;
use std::time::Instant;

use clap::Args;
use envmap_core::AnyMapping;
use indicatif::{ProgressBar, ProgressStyle};

use crate::args::{
    load_error, parse_convention, parse_layout, parse_mapping, parse_world, set_threads,
    warn_clamped, warn_replaced, CliResult, TextureFlags, WriteFlags,
};
use envmap_render::bake::{Baker, Preset, Target};
use envmap_render::filter::bake::{chain_sizes, Bake, BakeOptions, Quality};
use envmap_render::filter::dfg::DfgGrid;
use envmap_render::filter::sh::{IrradianceScale, ShWindow};
use envmap_render::filter::specular::RoughnessRule;
use envmap_render::image::FileFormat;
use envmap_render::image::Layout;
use envmap_render::image::{load_detailed, LoadOptions, NonFinite, SaveOptions};
use envmap_render::image::{Convention, FileAxes, World};
use envmap_render::image::{EnvImage, Representation};
use envmap_render::scene::Builtin;

#[derive(Args)]
pub(crate) struct BakeArgs {
    /// The environment: a file (.hdr, .exr, .png, .jpg; a six-file cube by one face's name), or a built-in: sky, room.
    pub(crate) input: String,
    /// Output directory (created if missing; every file of the bake is renamed into it together at the end).
    #[arg(long)]
    pub(crate) out: PathBuf,
    /// Engine preset: bevy (E5B9G9R9 + zstd KTX2: 512² specular, 32² diffuse, the cube in Bevy's world with z negated, as Bevy samples it), gltf (glTF-IBL-Sampler's RGBA16F KTX2 outputs and BRDF LUT), filament (cmgen's KTX 1 files: <dir>_ibl.ktx, <dir>_skybox.ktx, sh.txt), babylon (Babylon.js's environment.env: RGBD PNG levels down to 1×1 at its roughness rule and the irradiance polynomial, in its left-handed world; 256²), gltf-ibl (environment.gltf: glTF's EXT_lights_image_based, as Babylon.js's glTF loader reads it). Sets the format, sizes, levels, roughness rule and orientation; any flag given still overrides its part. See docs/engines.md.
    #[arg(long, value_parser = parse_target)]
    pub(crate) target: Option<Target>,
    /// Container of the maps: exr (the default without --target: one file per level), ktx2, dds (the whole chain in one file), ktx (KTX 1), env (Babylon.js; a full chain, no irradiance map), gltf (EXT_lights_image_based; the same).
    #[arg(long, value_parser = parse_container)]
    pub(crate) container: Option<FileFormat>,
    #[command(flatten)]
    pub(crate) texture: TextureFlags,
    #[command(flatten)]
    pub(crate) write: WriteFlags,
    /// --target filament: do not mirror the cube (cmgen mirrors by default: its files hold the environment seen with x negated, which Filament's shaders undo; --no-mirror matches cmgen --no-mirror).
    #[arg(long)]
    pub(crate) no_mirror: bool,
    /// Face size of the specular chain's level 0 (default 512; 256 for --target filament, as cmgen).
    #[arg(long)]
    pub(crate) size: Option<u32>,
    /// Number of levels (default: down to --min-size).
    #[arg(long)]
    pub(crate) levels: Option<usize>,
    /// Face size of the smallest level (default: 2 for linear, 16 for filament, 8 for unity, 1 for babylon).
    #[arg(long)]
    pub(crate) min_size: Option<u32>,
    /// Mip↔roughness rule: linear (glTF-IBL-Sampler, Bevy; the default), filament (the default of --target filament), unity, babylon (α = 2^(level/0.8)/size, level 0 unfiltered: Babylon.js's), log2 (α = 2^level/size: a glTF light's in Babylon.js), or roughness values per level (0,0.2,0.5,1).
    #[arg(long)]
    pub(crate) roughness_rule: Option<RoughnessRule>,
    /// Samples per texel of the sampled levels (overrides --quality).
    #[arg(long)]
    pub(crate) samples: Option<u32>,
    /// Sample counts: draft, default, high.
    #[arg(long, default_value = "default")]
    pub(crate) quality: Quality,
    /// Every level by the exact sum over a fine enough source level (slow at large sizes).
    #[arg(long)]
    pub(crate) exact: bool,
    /// The irradiance cube by the exact cosine convolution of the input instead of from the SH9, which cannot hold a sun or a window (docs/lighting.md).
    #[arg(long)]
    pub(crate) exact_irradiance: bool,
    /// Face size of the irradiance cube (0: none; default 32, none for --target filament, which uses the SH).
    #[arg(long)]
    pub(crate) irradiance_size: Option<u32>,
    /// What the irradiance map stores: e-over-pi (E/π, what engines expect; the default) or e (E).
    #[arg(long, value_parser = parse_scale, default_value = "e-over-pi")]
    pub(crate) irradiance_scale: IrradianceScale,
    /// Only the spherical harmonics (sh.json and the manifest): no chain, no maps, no table.
    #[arg(long)]
    pub(crate) sh_only: bool,
    /// Deringing of the SH (and of the irradiance map made from it): none (the default), auto (the sinc⁴ window that keeps the irradiance non-negative), cmgen (cmgen's default, which windows every map: auto's cutoff, at most 12.7675), or a cutoff in bands.
    /// Default none; cmgen for --target filament.
    #[arg(long, value_parser = parse_window)]
    pub(crate) sh_window: Option<Window>,
    /// Measure each level, the irradiance map and the SH9 against the exact integrals of the input itself (piecewise constant over its own texels, by adaptive quadrature) on this many texels of each, and report the error (slow: docs/lighting.md gives the cost).
    #[arg(long, default_value_t = 0)]
    pub(crate) check: u32,
    /// Size of the DFG table (0: none; default 128, none for --target bevy and filament, whose engines ship their own).
    #[arg(long)]
    pub(crate) dfg_size: Option<u32>,
    /// Where the DFG table's texels sit: texel-centres (the default: column i at N·V = (i + 0.5)/size, row j at roughness (j + 0.5)/size, what Filament and glTF viewers sample at (N·V, roughness)) or edges (i/(size − 1), j/(size − 1): N·V and roughness of 0 and 1 read exactly; sample at ((size − 1)·x + 0.5)/size). The manifest says which.
    #[arg(long, value_parser = parse_dfg_grid)]
    pub(crate) dfg_grid: Option<DfgGrid>,
    /// At most this many of the input's brightest texels (a sun, lamps, windows, and what rings around them: the brightest 1 % of the sphere by the largest absolute channel, where it exceeds 4 × the map's mean) are split out and summed to every output texel by a tree over their parts (0: none).
    #[arg(long, default_value_t = 16384)]
    pub(crate) split: usize,
    /// Compress texels above this luminance before filtering, and report what that changed (off by default).
    #[arg(long)]
    pub(crate) clamp: Option<f32>,
    /// Layout of the chain's EXR files: cross (default), vcross, strip, vstrip, faces (six files per level).
    #[arg(long, value_parser = parse_layout, default_value = "cross")]
    pub(crate) layout: Layout,
    /// The input's mapping, when its aspect ratio does not say.
    #[arg(long, value_parser = parse_mapping)]
    pub(crate) from: Option<AnyMapping>,
    #[command(flatten)]
    pub(crate) from_lens: crate::args::FromLensFlags,
    /// The world the input file's conventions are in (default: what the file says, else y-up).
    #[arg(long, value_parser = parse_world)]
    pub(crate) from_frame: Option<World>,
    /// The world of the outputs: y-up (the GL world, the default), y-up-lh, z-up.
    #[arg(long, value_parser = parse_world, default_value = "y-up")]
    pub(crate) to_frame: World,
    /// File conventions (see `envmap convert --help`); default: what the input says, else envmap.
    #[arg(long, value_parser = parse_convention)]
    pub(crate) convention: Option<Convention>,
    /// For a built-in environment: the face size of the cube it is evaluated into.
    #[arg(long, default_value_t = 1024)]
    pub(crate) env_size: u32,
    /// Worker threads (default: one per core).
    #[arg(long)]
    pub(crate) threads: Option<usize>,
    /// Largest input accepted, in millions of texels.
    #[arg(long, default_value_t = 268)]
    pub(crate) max_megatexels: u64,
    /// No progress bar or summary.
    #[arg(long, short)]
    pub(crate) quiet: bool,
}

fn parse_target(s: &str) -> Result<Target, String> {
    s.parse()
}

fn parse_container(s: &str) -> Result<FileFormat, String> {
    match s.to_ascii_lowercase().as_str() {
        "exr" => Ok(FileFormat::Exr),
        "ktx2" => Ok(FileFormat::Ktx2),
        "dds" => Ok(FileFormat::Dds),
        "ktx" | "ktx1" => Ok(FileFormat::Ktx),
        "env" => Ok(FileFormat::Env),
        "gltf" => Ok(FileFormat::Gltf),
        _ => Err(format!("{s}: expected exr, ktx2, dds, ktx, env or gltf")),
    }
}

/// The preset of `a.target` with every flag given laid over it.
fn plan(a: &BakeArgs) -> Result<Preset, crate::Failure> {
    let convention = a.convention.unwrap_or_default();
    let gl = FileAxes::Convention(convention, a.to_frame);
    let base = match a.target {
        None => {
            let mut p = Preset::default();
            p.axes = gl;
            p
        }
        Some(Target::Filament) if a.no_mirror => {
            Preset::for_target(Target::Filament, gl).unmirrored(gl)
        }
        Some(t) => Preset::for_target(t, gl),
    };
    if a.no_mirror && a.target != Some(Target::Filament) {
        return Err("--no-mirror is for --target filament".into());
    }
    let container = a.container.unwrap_or(base.container);
    let texture = a.texture.over(base.texture);
    if container == FileFormat::Exr && (a.texture.format.is_some() || a.texture.zstd.is_some()) {
        return Err("--format and --zstd are for --container ktx2, dds or ktx".into());
    }
    if container != FileFormat::Ktx2 && texture.zstd.is_some() {
        return Err(format!(
            "--zstd: only KTX2 has supercompression (the container is {})",
            container.extension()
        )
        .into());
    }
    let mut p = base;
    p.size = a.size.unwrap_or(p.size);
    p.rule = a.roughness_rule.clone().unwrap_or(p.rule);
    p.min_size = a.min_size.or(p.min_size);
    p.irradiance_size = a.irradiance_size.unwrap_or(p.irradiance_size);
    p.sh_window = a.sh_window.map_or(p.sh_window, |w| w.0);
    p.dfg_size = a.dfg_size.unwrap_or(p.dfg_size);
    p.dfg_grid = a.dfg_grid.unwrap_or(p.dfg_grid);
    p.container = container;
    p.texture = texture;
    p.layout = a.layout;
    Ok(p)
}

/// `--dfg-grid`: texel-centres or edges.
fn parse_dfg_grid(s: &str) -> Result<DfgGrid, String> {
    s.parse().map_err(|e: envmap_render::Error| e.to_string())
}

/// `--sh-window`: none, auto, or a cutoff.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Window(pub(crate) Option<ShWindow>);

fn parse_window(s: &str) -> Result<Window, String> {
    match s.to_ascii_lowercase().as_str() {
        "none" | "no" | "off" => Ok(Window(None)),
        "auto" => Ok(Window(Some(ShWindow::Auto))),
        "cmgen" => Ok(Window(Some(ShWindow::Cmgen))),
        v => match v.parse::<f64>() {
            Ok(c) if c.is_finite() && c > 0.0 => Ok(Window(Some(ShWindow::Sinc4 { cutoff: c }))),
            _ => Err(format!(
                "{s}: expected none, auto, cmgen, or a positive cutoff in bands"
            )),
        },
    }
}

fn parse_scale(s: &str) -> Result<IrradianceScale, String> {
    match s.to_ascii_lowercase().as_str() {
        "e-over-pi" | "e/pi" | "eoverpi" => Ok(IrradianceScale::EOverPi),
        "e" => Ok(IrradianceScale::E),
        _ => Err(format!("{s}: expected e-over-pi (E/π) or e")),
    }
}

/// The source: a file or a built-in.
fn source(
    a: &BakeArgs,
    stop: &AtomicBool,
) -> Result<(EnvImage, String, Vec<PathBuf>), crate::Failure> {
    if let Ok(b) = a.input.parse::<Builtin>() {
        if a.env_size == 0 || a.env_size > 4096 {
            return Err("--env-size must be between 1 and 4096".into());
        }
        let repr = Representation::for_file(AnyMapping::Cube, FileAxes::default());
        let (w, h) = repr
            .atlas
            .image_size_for_cell_width(a.env_size)
            .ok_or("--env-size: no such cube")?;
        let img = b.image(repr, w, h)?;
        return Ok((
            img,
            format!("built-in {} (a cube of {}² faces)", b.name(), a.env_size),
            Vec::new(),
        ));
    }
    let axes = (a.from_frame.is_some() || a.convention.is_some()).then(|| {
        FileAxes::Convention(
            a.convention.unwrap_or_default(),
            a.from_frame.unwrap_or_default(),
        )
    });
    let opts = {
        let mut o = LoadOptions::default();
        o.mapping = a.from_lens.apply(a.from)?;
        o.axes = axes;
        o.non_finite = NonFinite::Zero;
        o.max_texels = a.max_megatexels.saturating_mul(1_000_000);
        o.cancel = Some(stop);
        o
    };
    let loaded = load_detailed(&a.input, &opts).map_err(|e| {
        if Path::new(&a.input).exists() {
            load_error(&e)
        } else {
            format!("{e} (built-in environments: sky, room)")
        }
    })?;
    warn_replaced(Path::new(&a.input), loaded.replaced);
    let m = loaded.image.mapping();
    if !m.covers_sphere() {
        note!(
            "envmap: warning: {}: a {m} sees {:.1} % of the sphere; the lighting takes the rest as black",
            a.input,
            100.0 * m.seen_solid_angle() / (4.0 * std::f64::consts::PI)
        );
    }
    Ok((loaded.image, a.input.clone(), loaded.files))
}

pub(crate) fn run(a: &BakeArgs, stop: &AtomicBool) -> CliResult {
    set_threads(a.threads)?;
    if a.samples == Some(0) {
        return Err("--samples must be at least 1".into());
    }
    let plan = plan(a)?;
    if plan.irradiance_size > 2048 {
        return Err("--irradiance-size: at most 2048".into());
    }
    if plan.dfg_size > envmap_render::filter::dfg::MAX_SIZE {
        return Err(format!(
            "--dfg-size: at most {}",
            envmap_render::filter::dfg::MAX_SIZE
        )
        .into());
    }
    if a.clamp.is_some_and(|c| !(c > 0.0 && c.is_finite())) {
        return Err("--clamp must be a positive luminance".into());
    }
    if !Layout::for_mapping(AnyMapping::Cube).contains(&a.layout) {
        let names: Vec<&str> = Layout::for_mapping(AnyMapping::Cube)
            .iter()
            .map(|l| l.name())
            .collect();
        return Err(format!(
            "--layout {}: not a cube layout ({})",
            a.layout,
            names.join(", ")
        )
        .into());
    }
    let mut over = BakeOptions::default();
    over.levels = a.levels;
    over.quality = a.quality;
    over.samples = a.samples;
    over.exact = a.exact;
    over.exact_irradiance = a.exact_irradiance;
    over.clamp = a.clamp;
    over.irradiance_scale = a.irradiance_scale;
    over.sh_only = a.sh_only;
    over.bright_max = a.split;
    over.check = a.check;
    over.cancel = Some(stop);
    let baker = Baker::with_preset(plan.clone()).options(over);
    // Bad sizes and levels before any loading.
    let sizes = chain_sizes(&baker.bake_options())?;
    let t0 = Instant::now();
    let (src, name, inputs) = source(a, stop)?;
    let t_load = t0.elapsed();
    let bar = if a.quiet {
        ProgressBar::hidden()
    } else {
        let b = ProgressBar::new(sizes.len() as u64);
        b.set_style(
            ProgressStyle::with_template("{msg:>28} [{bar:30}] {pos}/{len} levels ({elapsed})")
                .unwrap_or_else(|_| ProgressStyle::default_bar())
                .progress_chars("=> "),
        );
        b
    };
    let bar = Mutex::new(bar);
    let progress = |k: usize, n: usize| {
        if let Ok(b) = bar.lock() {
            b.set_length(n as u64);
            b.set_position(k as u64);
            b.set_message(format!(
                "specular level {k} ({}²)",
                sizes.get(k).copied().unwrap_or(0)
            ));
        }
    };
    let save = {
        let mut o = a.write.over(SaveOptions::default());
        o.inputs = inputs.clone();
        o.cancel = Some(stop);
        o
    };
    // The bake takes the input (its working copy is the input itself) and
    // writes each level of an OpenEXR chain while it makes the next.
    let done = baker
        .input_name(&name)
        .load_seconds(t_load.as_secs_f64())
        .save_options(save)
        .progress(&progress)
        .bake_into(src, &a.out);
    if let Ok(b) = bar.lock() {
        b.finish_and_clear();
    }
    let done = done?;
    let Some((written, write_seconds)) = done.written() else {
        return Err("the bake wrote no files".into());
    };
    for (path, c) in &written.clamped {
        warn_clamped(path, plan.texture.format, *c);
    }
    if !a.quiet {
        summary(
            a,
            &plan,
            &name,
            done.bake(),
            written.files.len(),
            [t_load.as_secs_f64(), done.bake_seconds(), write_seconds],
        );
    }
    Ok(())
}

/// Three values for a summary line.
fn triple(v: [f64; 3]) -> String {
    format!("{:.5} {:.5} {:.5}", v[0], v[1], v[2])
}

/// The table printed at the end.
///
/// `times`: the seconds spent loading, baking (an OpenEXR chain's levels
/// written beside it) and writing the rest.
fn summary(a: &BakeArgs, plan: &Preset, name: &str, b: &Bake, files: usize, times: [f64; 3]) {
    let [load, work, write] = times.map(|t| t * 1e3);
    let beside = if plan.container == FileFormat::Exr && b.chain.is_some() {
        " (its levels' files written beside it)"
    } else {
        ""
    };
    note!(
        "{name} -> {} ({files} files): load {load:.0} ms, bake {work:.0} ms{beside}, write {write:.0} ms",
        a.out.display(),
    );
    if let Some(chain) = &b.chain {
        note!(
            "| level | size | roughness | method | samples | clamped | ms | error (expected{}) |",
            if a.check > 0 { "; measured, bias" } else { "" }
        );
        note!("| ---: | ---: | ---: | --- | ---: | ---: | ---: | ---: |");
        for (k, r) in chain.reports.iter().enumerate() {
            let expected = r
                .estimated_error()
                .map(|e| format!("{:.2} %", 100.0 * e))
                .unwrap_or_else(|| "not sampled".to_owned());
            let measured = r
                .measured
                .map(|m| {
                    format!(
                        "; {:.2} %, {:+.3} %",
                        100.0 * m.relative_rms,
                        100.0 * m.bias
                    )
                })
                .unwrap_or_default();
            note!(
                "| {k} | {} | {:.3} | {}{} | {} | {} | {:.0} | {expected}{measured} |",
                r.size,
                r.roughness,
                r.method,
                r.source_level
                    .map(|l| format!(" (source level {l})"))
                    .unwrap_or_default(),
                r.samples,
                r.clamped,
                r.seconds * 1e3
            );
        }
        let prep: Vec<String> = chain
            .stages
            .iter()
            .map(|(n, t)| format!("{n} {:.0} ms", t * 1e3))
            .collect();
        note!("preparation: {}", prep.join(", "));
        note!(
            "bright texels split from the input and summed by a tree over their parts: {} as {} points ({:.2} % of the energy; largest absolute channel above {:.3})",
            chain.bright.texels,
            chain.bright.points,
            100.0 * chain.bright.energy_share,
            chain.bright.threshold
        );
        let e = &chain.energy;
        let neg = e.negative_share();
        note!(
            "energy (Σ Ω·L, R G B): input {}, base cube {}, split {}: they add up within {:.1e}; negative texels {:.3} % / {:.3} % / {:.3} % of the positive energy (kept: the integral of the data as given)",
            triple(e.input),
            triple(e.base),
            triple(e.split),
            e.gap(),
            100.0 * neg[0],
            100.0 * neg[1],
            100.0 * neg[2]
        );
        if let Some(c) = chain.clamp {
            note!(
                "clamp: {} texels above luminance {} compressed, {:.3} % of the energy removed",
                c.texels,
                c.threshold,
                100.0 * c.energy_removed
            );
        }
    }
    if let Some(c) = &b.checked {
        if let Some(m) = c.irradiance {
            note!(
                "irradiance against the input's exact integral: {:.2} % relative RMS, bias {:+.3} % ({} texels)",
                100.0 * m.relative_rms,
                100.0 * m.bias,
                m.texels
            );
        }
        note!(
            "SH9 against the input's exact projection: {:.1e} relative",
            c.sh9
        );
    }
    if let Some(irr) = &b.irradiance {
        note!(
            "irradiance: {}² cube of {} from {}{}, {} texels clamped at zero",
            irr.image.cell_size().0,
            a.irradiance_scale.name(),
            irr.method,
            irr.source_level
                .map(|l| format!(" (source level {l})"))
                .unwrap_or_default(),
            irr.clamped
        );
    }
    let rest: Vec<String> = b
        .stages
        .iter()
        .map(|(n, t)| format!("{n} {:.0} ms", t * 1e3))
        .collect();
    note!("{}", rest.join(", "));
}
