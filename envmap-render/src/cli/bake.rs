//! `envmap bake`: image-based lighting from one environment map.

use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::sync::Mutex;
use std::time::Instant;

use clap::Args;
use envmap_core::glam::{Mat3, Vec3};
use envmap_core::{AnyMapping, Frame};
use indicatif::{ProgressBar, ProgressStyle};

use crate::cli::args::{
    load_error, parse_convention, parse_layout, parse_mapping, parse_world, set_threads,
    warn_clamped, warn_replaced, CliResult, TextureFlags,
};
use crate::filter::bake::{bake, chain_sizes, Bake, BakeOptions, Quality};
use crate::filter::sh::{IrradianceScale, ShWindow, NAMES};
use crate::filter::specular::RoughnessRule;
use crate::image::convention::{Convention, FileAxes, World};
use crate::image::io::{load_detailed, ExrPrecision, LoadOptions, NonFinite, Outputs, SaveOptions};
use crate::image::ktx1;
use crate::image::layout::Layout;
use crate::image::{Clamped, TexelFormat, Texture, TextureKind, TextureOptions};
use crate::image::{EnvImage, Representation};
use crate::scene::environments::Builtin;

#[derive(Args)]
pub(crate) struct BakeArgs {
    /// The environment: a file (.hdr, .exr, .png, .jpg; a six-file cube by one face's name), or a built-in: sky, room.
    pub(crate) input: String,
    /// Output directory (created if missing; every file of the bake is renamed into it together at the end).
    #[arg(long)]
    pub(crate) out: PathBuf,
    /// Engine preset: bevy (E5B9G9R9 + zstd KTX2: 512² specular, 32² diffuse), gltf (glTF-IBL-Sampler's RGBA16F KTX2 outputs and BRDF LUT), filament (cmgen's KTX 1 files: <dir>_ibl.ktx, <dir>_skybox.ktx, sh.txt). Sets the format, sizes, levels, roughness rule and orientation; any flag given still overrides its part. See docs/engines.md.
    #[arg(long, value_parser = parse_target)]
    pub(crate) target: Option<Target>,
    /// Container of the maps: exr (the default without --target: one file per level), ktx2, dds (the whole chain in one file), ktx (KTX 1).
    #[arg(long, value_parser = parse_container)]
    pub(crate) container: Option<Container>,
    #[command(flatten)]
    pub(crate) texture: TextureFlags,
    /// --target filament: do not mirror the cube (cmgen mirrors by default: its files hold the environment seen with x negated, which Filament's shaders undo; --no-mirror matches cmgen --no-mirror).
    #[arg(long)]
    pub(crate) no_mirror: bool,
    /// Face size of the specular chain's level 0 (default 512; 256 for --target filament, as cmgen).
    #[arg(long)]
    pub(crate) size: Option<u32>,
    /// Number of levels (default: down to --min-size).
    #[arg(long)]
    pub(crate) levels: Option<usize>,
    /// Face size of the smallest level (default: 2 for linear, 16 for filament, 8 for unity).
    #[arg(long)]
    pub(crate) min_size: Option<u32>,
    /// Mip↔roughness rule: linear (glTF-IBL-Sampler, Bevy; the default), filament (the default of --target filament), unity, or roughness values per level (0,0.2,0.5,1).
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
    /// The irradiance cube by the exact cosine convolution of the input instead of from the SH9, which cannot hold a sun or a window (3–8 % on real HDRIs; exact: under 0.01 %).
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
    /// Measure each level, the irradiance map and the SH9 against the exact integrals of the input itself (piecewise constant over its own texels, by adaptive quadrature) on this many texels of each, and report the error (about a second per 1000 texels of a level for a 512×256 input).
    #[arg(long, default_value_t = 0)]
    pub(crate) check: u32,
    /// Size of the DFG table (0: none; default 128, none for --target bevy and filament, whose engines ship their own).
    #[arg(long)]
    pub(crate) dfg_size: Option<u32>,
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

/// `--target`: an engine's preset.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Target {
    /// Bevy's `EnvironmentMapLight`: E5B9G9R9 + zstd KTX2 cubes.
    Bevy,
    /// glTF-IBL-Sampler's outputs: RGBA16F KTX2 cubes and the BRDF LUT.
    Gltf,
    /// Filament's `cmgen --deploy`: KTX 1, R11F_G11F_B10F, `sh` key.
    Filament,
}

fn parse_target(s: &str) -> Result<Target, String> {
    match s.to_ascii_lowercase().as_str() {
        "bevy" => Ok(Target::Bevy),
        "gltf" | "gltf-ibl-sampler" | "khronos" => Ok(Target::Gltf),
        "filament" | "cmgen" => Ok(Target::Filament),
        _ => Err(format!("{s}: expected bevy, gltf or filament")),
    }
}

/// `--container`: how the maps are stored.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Container {
    /// One OpenEXR file (or six) per level.
    Exr,
    /// One KTX2 file per map, every level inside.
    Ktx2,
    /// One DDS file per map.
    Dds,
    /// One KTX 1 file per map (Filament).
    Ktx,
}

impl Container {
    fn extension(self) -> &'static str {
        match self {
            Container::Exr => "exr",
            Container::Ktx2 => "ktx2",
            Container::Dds => "dds",
            Container::Ktx => "ktx",
        }
    }
}

fn parse_container(s: &str) -> Result<Container, String> {
    match s.to_ascii_lowercase().as_str() {
        "exr" => Ok(Container::Exr),
        "ktx2" => Ok(Container::Ktx2),
        "dds" => Ok(Container::Dds),
        "ktx" | "ktx1" => Ok(Container::Ktx),
        _ => Err(format!("{s}: expected exr, ktx2, dds or ktx")),
    }
}

/// What a bake makes, once the preset and the flags are put together.
#[derive(Clone, Debug)]
struct Plan {
    size: u32,
    rule: RoughnessRule,
    min_size: Option<u32>,
    irradiance_size: u32,
    sh_window: Option<ShWindow>,
    dfg_size: u32,
    container: Container,
    texture: TextureOptions,
    axes: FileAxes,
    /// Filament's cube mirrored as cmgen's default (x negated).
    mirrored: bool,
    /// The file names: specular chain, irradiance map.
    specular: &'static str,
    irradiance: &'static str,
}

/// The GL world with x negated: the axes of cmgen's default (mirrored)
/// cube files (`CubemapUtils::mirrorCubemap` samples the source at
/// (−x, y, z)).
fn mirrored_gl() -> FileAxes {
    let m = Frame::Y_UP_RH.matrix() * Mat3::from_diagonal(Vec3::new(-1.0, 1.0, 1.0));
    FileAxes::Frame(Frame::from_mat3(m).unwrap_or(Frame::Y_UP_RH))
}

/// The preset of `a.target` with every flag given laid over it.
fn plan(a: &BakeArgs) -> Result<Plan, String> {
    let convention = a.convention.unwrap_or_default();
    let gl = FileAxes::Convention(convention, a.to_frame);
    let base = match a.target {
        None => Plan {
            size: 512,
            rule: RoughnessRule::Linear,
            min_size: None,
            irradiance_size: 32,
            sh_window: None,
            dfg_size: crate::filter::dfg::DEFAULT_SIZE,
            container: Container::Exr,
            texture: TextureOptions::default(),
            axes: gl,
            mirrored: false,
            specular: "specular",
            irradiance: "irradiance",
        },
        // Bevy's shipped maps (pisa_*_rgb9e5_zstd.ktx2) and its runtime
        // generator: 512² specular with roughness = mip / (mips − 1), 32²
        // diffuse, one level; E5B9G9R9 + zstd; a standard KTX cube (Bevy
        // negates z itself when it samples).
        Some(Target::Bevy) => Plan {
            size: 512,
            rule: RoughnessRule::Linear,
            min_size: None,
            irradiance_size: 32,
            sh_window: None,
            dfg_size: 0,
            container: Container::Ktx2,
            texture: TextureOptions {
                format: TexelFormat::E5b9g9r9,
                zstd: Some(DEFAULT_ZSTD),
            },
            axes: gl,
            mirrored: false,
            specular: "specular",
            irradiance: "diffuse",
        },
        // glTF-IBL-Sampler (lib/source/lib.cpp): RGBA16F through libktx,
        // ⌊log2 size⌋ levels (down to 2×2) at roughness i/(n − 1), the
        // Lambertian map, the GGX BRDF LUT.
        Some(Target::Gltf) => Plan {
            size: 512,
            rule: RoughnessRule::Linear,
            min_size: Some(2),
            irradiance_size: 32,
            sh_window: None,
            dfg_size: crate::filter::dfg::DEFAULT_SIZE,
            container: Container::Ktx2,
            texture: TextureOptions::default(),
            axes: gl,
            mirrored: false,
            specular: "specular",
            irradiance: "diffuse",
        },
        // cmgen --deploy (tools/cmgen): 256², levels down to 16² at
        // lod = (n − 1)·r·(2 − r), R11F_G11F_B10F KTX 1, the SH in the `sh`
        // key (auto-windowed), mirrored unless --no-mirror.
        Some(Target::Filament) => Plan {
            size: 256,
            rule: RoughnessRule::Filament,
            min_size: Some(16),
            irradiance_size: 0,
            sh_window: Some(ShWindow::Cmgen),
            dfg_size: 0,
            container: Container::Ktx,
            texture: TextureOptions {
                format: TexelFormat::B10g11r11,
                zstd: None,
            },
            axes: if a.no_mirror { gl } else { mirrored_gl() },
            mirrored: !a.no_mirror,
            specular: "ibl",
            irradiance: "irradiance",
        },
    };
    if a.no_mirror && a.target != Some(Target::Filament) {
        return Err("--no-mirror is for --target filament".into());
    }
    let container = a.container.unwrap_or(base.container);
    let texture = a.texture.over(base.texture);
    if container == Container::Exr && (a.texture.format.is_some() || a.texture.zstd.is_some()) {
        return Err("--format and --zstd are for --container ktx2, dds or ktx".into());
    }
    if container != Container::Ktx2 && texture.zstd.is_some() {
        return Err(format!(
            "--zstd: only KTX2 has supercompression (the container is {})",
            container.extension()
        ));
    }
    Ok(Plan {
        size: a.size.unwrap_or(base.size),
        rule: a.roughness_rule.clone().unwrap_or(base.rule),
        min_size: a.min_size.or(base.min_size),
        irradiance_size: a.irradiance_size.unwrap_or(base.irradiance_size),
        sh_window: a.sh_window.map_or(base.sh_window, |w| w.0),
        dfg_size: a.dfg_size.unwrap_or(base.dfg_size),
        container,
        texture,
        ..base
    })
}

/// The zstd level of the presets that supercompress: zstd's own default (`--zstd 19` gives files about 36 % smaller for seconds more; docs/performance.md).
pub(crate) const DEFAULT_ZSTD: i32 = 3;

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
fn source(a: &BakeArgs, stop: &AtomicBool) -> Result<(EnvImage, String, Vec<PathBuf>), String> {
    if let Ok(b) = a.input.parse::<Builtin>() {
        if a.env_size == 0 || a.env_size > 4096 {
            return Err("--env-size must be between 1 and 4096".into());
        }
        let repr = Representation::for_file(AnyMapping::Cube, FileAxes::default());
        let (w, h) = repr
            .atlas
            .image_size_for_cell_width(a.env_size)
            .ok_or("--env-size: no such cube")?;
        let img = b.image(repr, w, h).map_err(|e| e.to_string())?;
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
    let opts = LoadOptions {
        mapping: a.from,
        axes,
        non_finite: NonFinite::Zero,
        max_texels: a.max_megatexels.saturating_mul(1_000_000),
        cancel: Some(stop),
        ..LoadOptions::default()
    };
    let loaded = load_detailed(&a.input, &opts).map_err(|e| {
        if Path::new(&a.input).exists() {
            load_error(&e)
        } else {
            format!("{e} (built-in environments: sky, room)")
        }
    })?;
    warn_replaced(Path::new(&a.input), loaded.replaced);
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
    if plan.dfg_size > crate::filter::dfg::MAX_SIZE {
        return Err(format!(
            "--dfg-size: at most {}",
            crate::filter::dfg::MAX_SIZE
        ));
    }
    if a.clamp.is_some_and(|c| !(c > 0.0 && c.is_finite())) {
        return Err("--clamp must be a positive luminance".into());
    }
    if !Layout::for_mapping(AnyMapping::Cube).contains(&a.layout) {
        return Err(format!(
            "--layout {}: not a cube layout (cross, vcross, strip, vstrip, faces)",
            a.layout
        ));
    }
    let opts = BakeOptions {
        size: plan.size,
        levels: a.levels,
        min_size: plan.min_size,
        rule: plan.rule.clone(),
        quality: a.quality,
        samples: a.samples,
        exact: a.exact,
        exact_irradiance: a.exact_irradiance,
        clamp: a.clamp,
        axes: plan.axes,
        irradiance_size: plan.irradiance_size,
        irradiance_scale: a.irradiance_scale,
        sh_window: plan.sh_window,
        sh_only: a.sh_only,
        dfg_size: plan.dfg_size,
        bright_max: a.split,
        check: a.check,
        cancel: Some(stop),
        ..BakeOptions::default()
    };
    // Bad sizes and levels before any loading.
    let sizes = chain_sizes(&opts).map_err(|e| e.to_string())?;
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
    let t1 = Instant::now();
    let baked = bake(&src, &opts, &progress).map_err(|e| e.to_string())?;
    let t_bake = t1.elapsed();
    drop(src);
    if let Ok(b) = bar.lock() {
        b.finish_and_clear();
    }
    // Every file into the directory together.
    let created = !a.out.exists();
    std::fs::create_dir_all(&a.out)
        .map_err(|e| format!("{}: cannot create: {e}", a.out.display()))?;
    let mut clamped_total: Vec<(PathBuf, Clamped)> = Vec::new();
    let written = (|| -> Result<Vec<PathBuf>, String> {
        let sopts = SaveOptions {
            six_files: a.layout.is_six_files(),
            inputs: inputs.clone(),
            cancel: Some(stop),
            ..SaveOptions::default()
        };
        let mut run = Outputs::new(&sopts);
        let mut stage = |img: &EnvImage, stem: &str, content: String| -> Result<(), String> {
            let img = if a.layout.is_six_files() {
                img.clone()
            } else {
                img.relayout(a.layout.atlas()).map_err(|e| e.to_string())?
            };
            let o = SaveOptions {
                content: Some(content),
                ..sopts.clone()
            };
            run.stage_image(&img, a.out.join(file_name(a, stem)), &o)
                .map_err(|e| e.to_string())
        };
        if plan.container == Container::Exr {
            if let Some(chain) = &baked.chain {
                let n = chain.levels.len();
                for (k, (level, r)) in chain.levels.iter().zip(&chain.reports).enumerate() {
                    let content = format!(
                        "GGX-prefiltered radiance (split sum, N = V = R): level {k} of {n}, perceptual roughness {:.4} (alpha = roughness^2), rule {}",
                        r.roughness,
                        opts.rule.name()
                    );
                    stage(level, &format!("specular_{k}"), content)?;
                }
            }
            if let Some(irr) = &baked.irradiance {
                let content = match a.irradiance_scale {
                    IrradianceScale::EOverPi => {
                        "irradiance E/pi (the radiance a white Lambertian surface reflects)"
                            .to_owned()
                    }
                    IrradianceScale::E => "irradiance E (not divided by pi)".to_owned(),
                };
                stage(&irr.image, "irradiance", content)?;
            }
        } else {
            let mut texture = |levels: &[EnvImage], name: &str, kv: &[(&str, &[u8])]| {
                let tex = Texture::from_env(levels).map_err(|e| e.to_string())?;
                let path = a.out.join(name);
                let clamped = if plan.container == Container::Ktx {
                    let (bytes, c) = ktx1::encode(&tex, plan.texture.format, kv)
                        .map_err(|e| e.in_file(&path).to_string())?;
                    run.stage_bytes(&path, &bytes).map_err(|e| e.to_string())?;
                    c
                } else {
                    run.stage_texture(&tex, &path, plan.texture)
                        .map_err(|e| e.to_string())?
                };
                clamped_total.push((path, clamped));
                Ok::<(), String>(())
            };
            let ext = plan.container.extension();
            let sh_key = filament_sh_text(&baked, &plan);
            if let Some(chain) = &baked.chain {
                let kv: Vec<(&str, &[u8])> = if plan.container == Container::Ktx {
                    vec![("sh", sh_key.as_bytes())]
                } else {
                    Vec::new()
                };
                texture(&chain.levels, &texture_name(a, &plan, plan.specular), &kv)?;
                if plan.container == Container::Ktx {
                    texture(&chain.levels[..1], &texture_name(a, &plan, "skybox"), &[])?;
                }
            }
            if let Some(irr) = &baked.irradiance {
                texture(
                    std::slice::from_ref(&irr.image),
                    &texture_name(a, &plan, plan.irradiance),
                    &[],
                )?;
            }
            if plan.container == Container::Ktx {
                run.stage_bytes(
                    a.out.join("sh.txt"),
                    filament_sh_txt(&baked, &plan).as_bytes(),
                )
                .map_err(|e| e.to_string())?;
            }
            if let (Some(t), Some(Target::Gltf)) = (&baked.dfg, a.target) {
                // glTF-IBL-Sampler's LUT: R = scale, G = bias, N·V across,
                // roughness down (row 0 = roughness 0.5/size).
                let lut = Texture::new(TextureKind::Flat, vec![vec![t.single_scatter_image()]])
                    .map_err(|e| e.to_string())?;
                let path = a.out.join(format!("lut_ggx.{ext}"));
                let c = run
                    .stage_texture(
                        &lut,
                        &path,
                        TextureOptions {
                            zstd: None,
                            ..plan.texture
                        },
                    )
                    .map_err(|e| e.to_string())?;
                clamped_total.push((path, c));
            }
        }
        if let Some(t) = &baked.dfg {
            let axes = format!(
                "column i: N.V = (i + 0.5)/{0}, row j from the top: perceptual roughness (j + 0.5)/{0}; height-correlated Smith GGX",
                t.size()
            );
            for (file, form, image) in [
                (
                    "dfg.exr",
                    "DFG single scatter: R = scale, G = bias (F0 scale + bias)",
                    t.single_scatter_image(),
                ),
                (
                    "dfg_multiscatter.exr",
                    "DFG multiscatter (Filament): R = bias, G = scale + bias",
                    t.multiscatter_image(),
                ),
            ] {
                let o = SaveOptions {
                    exr_precision: ExrPrecision::F32,
                    content: Some(format!("{form}; {axes}")),
                    ..sopts.clone()
                };
                run.stage_rgb(&image, a.out.join(file), &o)
                    .map_err(|e| e.to_string())?;
            }
        }
        run.stage_bytes(
            a.out.join("sh.json"),
            sh_json(&plan, &baked, opts.axes).as_bytes(),
        )
        .map_err(|e| e.to_string())?;
        let manifest = manifest(
            a,
            &plan,
            &name,
            &baked,
            &opts,
            t_load.as_secs_f64(),
            t_bake.as_secs_f64(),
        );
        run.stage_bytes(a.out.join("manifest.json"), manifest.as_bytes())
            .map_err(|e| e.to_string())?;
        run.commit().map_err(|e| e.to_string())
    })();
    let written = match written {
        Ok(w) => {
            for (path, c) in &clamped_total {
                warn_clamped(path, plan.texture.format, *c);
            }
            w
        }
        Err(e) => {
            if created {
                let _ = std::fs::remove_dir(&a.out);
            }
            return Err(e);
        }
    };
    if !a.quiet {
        summary(
            a,
            &name,
            &baked,
            written.len(),
            t_load.as_secs_f64(),
            t_bake.as_secs_f64(),
        );
    }
    Ok(())
}

/// The file of a texture container: `<stem>.<ext>`, or for KTX 1 (cmgen's
/// names) `<dir>_<stem>.ktx` with `<dir>` the output directory's name
/// without its extension.
fn texture_name(a: &BakeArgs, plan: &Plan, stem: &str) -> String {
    let ext = plan.container.extension();
    if plan.container == Container::Ktx {
        let dir = a
            .out
            .file_stem()
            .map(|d| d.to_string_lossy().into_owned())
            .filter(|d| !d.is_empty() && d != "." && d != "..")
            .unwrap_or_else(|| "envmap".to_owned());
        format!("{dir}_{stem}.{ext}")
    } else {
        format!("{stem}.{ext}")
    }
}

/// Where level `k` of the chain is, for the manifest.
fn level_file(a: &BakeArgs, plan: &Plan, k: usize) -> String {
    if plan.container == Container::Exr {
        file_name(a, &format!("specular_{k}"))
    } else {
        crate::scene::lit_files::level_entry(&texture_name(a, plan, plan.specular), k)
    }
}

/// Filament's pre-scaled SH (E/π, y up) of the bake, windowed as the plan
/// says, in the cube files' axes: cmgen's mirroring negates x, flipping the
/// three terms odd in x (L11, L2-2, L21).
fn filament_sh(b: &Bake, plan: &Plan) -> [[f64; 3]; 9] {
    let sh = match plan.sh_window {
        Some(w) => b.sh.windowed(w),
        None => b.sh,
    };
    let mut f = sh.filament_shader_form();
    if plan.mirrored {
        for i in [3, 4, 7] {
            f[i] = f[i].map(|v| -v);
        }
    }
    f
}

/// C's `%g` (6 significant digits), as cmgen prints floats into its `sh` key.
fn format_g(v: f32) -> String {
    if v == 0.0 {
        return if v.is_sign_negative() { "-0" } else { "0" }.to_owned();
    }
    let e = f64::from(v).abs().log10().floor() as i32;
    // Rounding to 6 digits can carry into the next power of ten.
    let sci = format!("{:.5e}", v);
    let exp: i32 = sci
        .split('e')
        .nth(1)
        .and_then(|x| x.parse().ok())
        .unwrap_or(e);
    let trim = |s: String| {
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_owned()
        } else {
            s
        }
    };
    if !(-4..6).contains(&exp) {
        let (m, _) = sci.split_once('e').unwrap_or((&sci, ""));
        format!(
            "{}e{}{:02}",
            trim(m.to_owned()),
            if exp < 0 { '-' } else { '+' },
            exp.abs()
        )
    } else {
        trim(format!("{:.*}", (5 - exp).max(0) as usize, v))
    }
}

/// The `sh` key of cmgen's KTX 1 files: nine lines `r g b`, L00 … L22, `%g`
/// of the f32 values, each line ended by `\n`.
fn filament_sh_text(b: &Bake, plan: &Plan) -> String {
    filament_sh(b, plan)
        .iter()
        .map(|c| {
            format!(
                "{} {} {}\n",
                format_g(c[0] as f32),
                format_g(c[1] as f32),
                format_g(c[2] as f32)
            )
        })
        .collect()
}

/// cmgen's `sh.txt`: `(r, g, b); // L00, irradiance, pre-scaled base` per
/// line, `%18.15f`.
fn filament_sh_txt(b: &Bake, plan: &Plan) -> String {
    filament_sh(b, plan)
        .iter()
        .zip(NAMES)
        .map(|(c, n)| {
            format!(
                "({:18.15}, {:18.15}, {:18.15}); // {n}, irradiance, pre-scaled base\n",
                c[0], c[1], c[2]
            )
        })
        .collect()
}

/// A file's name in the output directory (`{face}` for six files).
fn file_name(a: &BakeArgs, stem: &str) -> String {
    if a.layout.is_six_files() {
        format!("{stem}_{{face}}.exr")
    } else {
        format!("{stem}.exr")
    }
}

/// Three values for a summary line.
fn triple(v: [f64; 3]) -> String {
    format!("{:.5} {:.5} {:.5}", v[0], v[1], v[2])
}

/// The table printed at the end.
fn summary(a: &BakeArgs, name: &str, b: &Bake, files: usize, load: f64, work: f64) {
    eprintln!(
        "{name} -> {} ({files} files): load {:.0} ms, bake {:.0} ms",
        a.out.display(),
        load * 1e3,
        work * 1e3
    );
    if let Some(chain) = &b.chain {
        eprintln!(
            "| level | size | roughness | method | samples | clamped | ms | error (expected{}) |",
            if a.check > 0 { "; measured, bias" } else { "" }
        );
        eprintln!("| ---: | ---: | ---: | --- | ---: | ---: | ---: | ---: |");
        for (k, r) in chain.reports.iter().enumerate() {
            let expected = estimated_error(r)
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
            eprintln!(
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
        eprintln!("preparation: {}", prep.join(", "));
        eprintln!(
            "bright texels split from the input and summed by a tree over their parts: {} as {} points ({:.2} % of the energy; largest absolute channel above {:.3})",
            chain.bright.texels,
            chain.bright.points,
            100.0 * chain.bright.energy_share,
            chain.bright.threshold
        );
        let e = &chain.energy;
        let neg = e.negative_share();
        eprintln!(
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
            eprintln!(
                "clamp: {} texels above luminance {} compressed, {:.3} % of the energy removed",
                c.texels,
                c.threshold,
                100.0 * c.energy_removed
            );
        }
    }
    if let Some(c) = &b.checked {
        if let Some(m) = c.irradiance {
            eprintln!(
                "irradiance against the input's exact integral: {:.2} % relative RMS, bias {:+.3} % ({} texels)",
                100.0 * m.relative_rms,
                100.0 * m.bias,
                m.texels
            );
        }
        eprintln!(
            "SH9 against the input's exact projection: {:.1e} relative",
            c.sh9
        );
    }
    if let Some(irr) = &b.irradiance {
        eprintln!(
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
    eprintln!("{}", rest.join(", "));
}

/// The frame's matrix as rows, for the JSON files.
fn frame_rows(frame: envmap_core::Frame) -> [[f32; 3]; 3] {
    let m = frame.matrix().transpose();
    [
        m.x_axis.to_array(),
        m.y_axis.to_array(),
        m.z_axis.to_array(),
    ]
}

/// Coefficients as `{ "L00": [r, g, b], ... }`.
fn named(c: &[[f64; 3]; 9]) -> serde_json::Value {
    let map: serde_json::Map<String, serde_json::Value> = NAMES
        .iter()
        .zip(c)
        .map(|(n, v)| ((*n).to_owned(), serde_json::json!(v)))
        .collect();
    serde_json::Value::Object(map)
}

/// `sh.json`: the coefficients, their basis, frame and kind.
fn sh_json(plan: &Plan, b: &Bake, axes: FileAxes) -> String {
    let frame = axes.frame(AnyMapping::Cube);
    let windowed = match plan.sh_window {
        Some(w) => b.sh.windowed(w),
        None => b.sh,
    };
    let out = windowed.in_frame(frame);
    let m = serde_json::json!({
        "basis": "real spherical harmonics, bands 0-2, Ramamoorthi & Hanrahan 2001 (no Condon-Shortley phase): Y00 = 0.282095, Y1m = 0.488603 (y, z, x), Y2-2 = 1.092548 xy, Y2-1 = 1.092548 yz, Y20 = 0.315392 (3z^2 - 1), Y21 = 1.092548 xz, Y22 = 0.546274 (x^2 - y^2)",
        "order": NAMES,
        "axes": axes.describe(AnyMapping::Cube),
        "frame_rows": frame_rows(frame),
        "frame_note": "coefficients are in the axes of the cube files (x, y, z as the files' face names say); canonical: envmap's z-up right-handed axes",
        "window": match plan.sh_window {
            None => serde_json::json!("none"),
            Some(_) => match b.sh_cutoff {
                Some(cutoff) => serde_json::json!({
                    "kind": "sinc^4 (Filament CubemapSH::sincWindow; Sloan 2017)",
                    "cutoff_bands": cutoff,
                }),
                None => serde_json::json!("auto: none applied (the irradiance is non-negative without one)"),
            },
        },
        "radiance": {
            "meaning": "L_lm = integral of L(w) Y_lm(w) dw (radiance coefficients)",
            "coefficients": named(&out.coeffs),
        },
        "irradiance": {
            "meaning": "E_lm = A_l L_lm, A = (pi, 2pi/3, pi/4): sum of E_lm Y_lm(n) is the irradiance E(n), not divided by pi",
            "value": "E",
            "coefficients": named(&out.irradiance().coeffs),
        },
        "canonical_radiance": {
            "meaning": "radiance coefficients in envmap's canonical axes (z up, right-handed)",
            "coefficients": named(&windowed.coeffs),
        },
        "filament": {
            "meaning": "Filament's pre-scaled shader form (cmgen --sh-shader, the sh of its KTX and sh.txt), GL axes (y up, cmgen --no-mirror): E(n)/pi = sh0 + sh1 y + sh2 z + sh3 x + sh4 yx + sh5 yz + sh6 (3z^2 - 1) + sh7 zx + sh8 (x^2 - y^2)",
            "value": "E/pi",
            "sh": windowed.filament_shader_form(),
        },
    });
    serde_json::to_string_pretty(&m).unwrap_or_default()
}

/// The manifest: the input, the conventions, the rule, every level.
fn manifest(
    a: &BakeArgs,
    plan: &Plan,
    name: &str,
    b: &Bake,
    opts: &BakeOptions,
    load: f64,
    work: f64,
) -> String {
    let specular = b.chain.as_ref().map(|chain| {
        let levels: Vec<serde_json::Value> = chain
            .reports
            .iter()
            .enumerate()
            .map(|(k, r)| {
                serde_json::json!({
                    "level": k,
                    "file": level_file(a, plan, k),
                    "size": r.size,
                    "perceptual_roughness": r.roughness,
                    "alpha": r.roughness * r.roughness,
                    "method": r.method,
                    "samples": r.samples,
                    "exact_source_level": r.source_level,
                    "expected_relative_rms_error_smooth_light": estimated_error(r),
                    "measured": r.measured.map(|m| serde_json::json!({
                        "texels": m.texels,
                        "relative_rms_error": m.relative_rms,
                        "bias": m.bias,
                        "seconds": m.seconds,
                        "against": "the oracle: the input as given, piecewise constant over its own texels, by adaptive quadrature (envmap_render::filter::oracle)",
                    })),
                    "texels_clamped_at_zero": r.clamped,
                    "seconds": r.seconds,
                })
            })
            .collect();
        serde_json::json!({
            "integral": "LD(R) = ∫ L(l) D(h) (n·l)⁺ dl / ∫ D(h) (n·l)⁺ dl, N = V = R, GGX D, alpha = roughness²",
            "value": "radiance (the prefiltered radiance LD, same units as the input)",
            "roughness_rule": opts.rule.name(),
            "roughness_rule_formula": opts.rule.formula(),
            "base_cube_size": chain.base_size,
            "fis_lod_bias": opts.lod_bias,
            "bright_texels": {
                "count": chain.bright.texels,
                "points": chain.bright.points,
                "energy_share": chain.bright.energy_share,
                "energy_per_channel": chain.bright.energy,
                "threshold": chain.bright.threshold,
                "rule": format!("split from the input's own texels before any resampling: largest absolute channel above both its solid-angle-weighted 99th percentile and 4 × its solid-angle mean, at most {} texels (the largest); each cut into parts at most 1/4 of the narrowest level's lobe across, each part with its exact solid angle; added to every level by a tree over the parts (Barnes-Hut: a node added whole at its centre when at most 1/16 of the lobe across, or 1/32 of its distance from the lobe)", opts.bright_max),
            },
            "energy": {
                "unit": "Σ Ω·L per channel (R, G, B) over texels with their exact solid angles",
                "input": chain.energy.input,
                "input_negative": chain.energy.negative,
                "negative_share": chain.energy.negative_share(),
                "negative_policy": "negative texels (lossy compression's ringing) are kept: every integral is of the data as given, so they cancel the overshoots they ring with; outputs are clamped at zero and counted (texels_clamped_at_zero)",
                "base_cube": chain.energy.base,
                "split": chain.energy.split,
                "relative_gap": chain.energy.gap(),
                "base_cube_method": format!("footprint average: each texel the mean of the input's bilinear reconstruction over {0}×{0} points of its footprint", chain.energy.footprint_samples),
            },
            "clamp": chain.clamp.map(|c| serde_json::json!({
                "luminance": c.threshold,
                "texels": c.texels,
                "energy_removed": c.energy_removed,
            })),
            "preparation_seconds": chain.stages.iter().map(|(n, t)| serde_json::json!({"stage": n, "seconds": t})).collect::<Vec<_>>(),
            "levels": levels,
        })
    });
    let m = serde_json::json!({
        "envmap": crate::image::metadata::software(),
        "input": name,
        "axes": opts.axes.describe(AnyMapping::Cube),
        "frame_to_canonical": frame_columns(opts.axes.frame(AnyMapping::Cube)),
        "frame_to_canonical_note": "the cube files' x, y and z axes as columns in envmap's canonical axes (z up, right-handed); what `envmap render --env DIR` reads",
        "layout": if plan.container == Container::Exr { a.layout.name() } else { "one texture file per map: faces +X, -X, +Y, -Y, +Z, -Z, first texel top-left (KTX orientation rd), levels largest first" },
        "container": plan.container.extension(),
        "target": a.target.map(|t| format!("{t:?}").to_ascii_lowercase()),
        "texel_format": (plan.container != Container::Exr).then(|| plan.texture.format.vk_name()),
        "zstd_level": plan.texture.zstd,
        "mirrored": plan.mirrored.then_some("x negated, as cmgen's default (Filament's shaders expect it)"),
        "seconds": { "load": load, "bake": work },
        "specular": specular,
        "irradiance": b.irradiance.as_ref().map(|i| serde_json::json!({
            "file": if plan.container == Container::Exr { file_name(a, "irradiance") } else { texture_name(a, plan, plan.irradiance) },
            "size": i.image.cell_size().0,
            "value": opts.irradiance_scale.name(),
            "value_note": "E/pi is the outgoing radiance of a white Lambertian surface (what engines expect); E = pi × that",
            "method": i.method,
            "exact_source_level": i.source_level,
            "texels_clamped_at_zero": i.clamped,
            "measured": b.checked.and_then(|c| c.irradiance).map(|m| serde_json::json!({
                "texels": m.texels,
                "relative_rms_error": m.relative_rms,
                "bias": m.bias,
                "against": "the oracle's E (scaled as value says) of the input itself",
            })),
        })),
        "sh": {
            "file": "sh.json",
            "window": plan.sh_window.map(|_| b.sh_cutoff),
            "measured_relative_error": b.checked.map(|c| c.sh9),
        },
        "dfg": b.dfg.as_ref().map(|t| serde_json::json!({
            "files": {
                "dfg.exr": "single scatter: R = scale, G = bias (F0·scale + bias)",
                "dfg_multiscatter.exr": "Filament's multiscatter form: R = bias, G = scale + bias",
            },
            "size": t.size(),
            "x": "column i: N·V = (i + 0.5) / size",
            "y": "row j from the top: perceptual roughness = (j + 0.5) / size",
            "visibility": "height-correlated Smith GGX",
            "precision": "computed in f64 by quadrature, stored as f32",
        })),
        "stages_seconds": b.stages.iter().map(|(n, t)| serde_json::json!({"stage": n, "seconds": t})).collect::<Vec<_>>(),
    });
    serde_json::to_string_pretty(&m).unwrap_or_default()
}

/// A frame's matrix as three columns (the file axes in canonical ones).
fn frame_columns(f: envmap_core::Frame) -> [[f32; 3]; 3] {
    let m = f.matrix();
    [
        m.x_axis.to_array(),
        m.y_axis.to_array(),
        m.z_axis.to_array(),
    ]
}

/// The relative RMS error a level's method is measured to have
/// (`docs/lighting.md`): 0 for the resampled and exact levels.
fn estimated_error(r: &crate::filter::bake::LevelReport) -> Option<f64> {
    (r.method == "sampled").then(|| crate::filter::bake::estimated_error(r.roughness, r.samples))
}

#[cfg(test)]
mod tests {
    use super::format_g;

    /// `%g` as C prints it (cmgen's `sh` key), on the values of a cmgen file.
    #[test]
    fn format_g_prints_as_c_does() {
        for (v, want) in [
            (1.00391_f32, "1.00391"),
            (0.503_906, "0.503906"),
            (-1.003_54e-7, "-1.00354e-07"),
            (8.364_38e-11, "8.36438e-11"),
            (0.0, "0"),
            (-0.0, "-0"),
            (0.028_810_7, "0.0288107"),
            (123_456.0, "123456"),
            (1_234_567.0, "1.23457e+06"),
            (999_999.5, "1e+06"),
            (0.000_1, "0.0001"),
            (0.000_012_5, "1.25e-05"),
            (2.5, "2.5"),
        ] {
            assert_eq!(format_g(v), want, "{v}");
        }
    }
}
