//! `envmap convert`: one representation into another.

use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::Instant;

use clap::Args;
use envmap_core::{AnyMapping, Frame};
use indicatif::{ProgressBar, ProgressStyle};

use crate::args::{
    load_error, output_size, parse_convention, parse_face_names, parse_face_transforms, parse_fov,
    parse_layout, parse_lens, parse_mapping, parse_rotation, parse_world, set_threads,
    warn_clamped, warn_replaced, with_lens, CliResult, FromLensFlags, TextureFlags, WriteFlags,
};
use envmap_render::filter::pyramid::Pyramid;
use envmap_render::filter::Filter;
use envmap_render::filter::{auto_samples, convert, coverage, ConvertOptions, Streamed};
use envmap_render::image::texture::Texture;
use envmap_render::image::FaceNames;
use envmap_render::image::FaceTransforms;
use envmap_render::image::FileFormat;
use envmap_render::image::Layout;
use envmap_render::image::Outputs;
use envmap_render::image::{
    load_detailed, save, ExrPrecision, LoadOptions, Loaded, NonFinite, SaveOptions,
};
use envmap_render::image::{texture::TextureOptions, EnvImage, Representation};
use envmap_render::image::{Convention, FileAxes, World};

#[derive(Args)]
pub(crate) struct ConvertArgs {
    /// Input file (.png, .jpg, .hdr, .exr, .ktx2, .dds: level 0; a six-file cube by one face's name).
    pub(crate) input: PathBuf,
    /// Output file (.png, .jpg, .hdr, .exr, .ktx2, .dds, .ktx); `{face}` in the name, or --layout faces, writes six files.
    pub(crate) output: PathBuf,
    /// Output mapping: latlong, cube, sphere, sphere-gl, paraboloid, tennisball, octahedral, octahedral-equal-area, angular (light-probe), eac (the equi-angular cube map), fisheye (one lens looking at the latlong's centre), dual-fisheye (two back to back, side by side; dfisheye).
    #[arg(long, value_parser = parse_mapping)]
    pub(crate) to: AnyMapping,
    /// Field of view of each lens of a fisheye output, in degrees (default 180; up to 360 for one lens).
    #[arg(long, value_parser = parse_fov)]
    pub(crate) fov: Option<f64>,
    /// Lens law of a fisheye output: equidistant (r ∝ θ, the default, as v360's fisheye) or equisolid (r ∝ sin(θ/2), equal-area).
    #[arg(long, value_parser = parse_lens)]
    pub(crate) lens: Option<envmap_core::Lens>,
    #[command(flatten)]
    pub(crate) from_lens: FromLensFlags,
    /// Write where the output's directions are seen by the input (a fisheye under 360° sees part of the sphere) as an 8-bit PNG: white seen, black unseen, grey the fraction of a texel seen.
    #[arg(long)]
    pub(crate) mask: Option<PathBuf>,
    /// Output layout (cube: cross, vcross, strip, vstrip, 3x2, faces; eac: v360, ffmpeg's and YouTube's padded 3×2 with turned faces, or any cube layout); default: the mapping's own.
    #[arg(long, value_parser = parse_layout)]
    pub(crate) layout: Option<Layout>,
    /// Face edge of a cube, width of any other atlas, in texels (default: about the input's texel count).
    #[arg(long)]
    pub(crate) size: Option<u32>,
    /// Input mapping, when the aspect ratio does not say (e.g. a square image).
    #[arg(long, value_parser = parse_mapping)]
    pub(crate) from: Option<AnyMapping>,
    /// Input layout, when the aspect ratio does not say.
    #[arg(long, value_parser = parse_layout)]
    pub(crate) from_layout: Option<Layout>,
    /// The world the input file's conventions are in: y-up (the GL world), y-up-lh, or z-up (envmap's canonical frame: the mapping's formula on the directions as given).
    /// Default: what the input file says of itself (files envmap wrote), else y-up.
    #[arg(long, value_parser = parse_world)]
    pub(crate) from_frame: Option<World>,
    /// The world the output file's conventions are in (as --from-frame; default y-up).
    #[arg(long, value_parser = parse_world)]
    pub(crate) to_frame: Option<World>,
    /// File conventions of both files: envmap (the default: cube files in the GL world, a latlong as cmgen --no-mirror and py360convert read it), cmgen, py360convert, blender, three, gltf-ibl-sampler, bevy, unity, pbrt.
    #[arg(long, value_parser = parse_convention)]
    pub(crate) convention: Option<Convention>,
    /// File conventions of the input only (overrides --convention).
    #[arg(long, value_parser = parse_convention)]
    pub(crate) from_convention: Option<Convention>,
    /// File conventions of the output only (overrides --convention).
    #[arg(long, value_parser = parse_convention)]
    pub(crate) to_convention: Option<Convention>,
    /// Names of an output cube's six files: +x (sky_+x.exr ...), px (px nx py ny pz nz), posx (posx negx ...), words (right left top bottom front back), index (0 ... 5), frblud (R L U D F B); default: the scheme of a face name in OUT, else +x.
    #[arg(long, value_parser = parse_face_names)]
    pub(crate) face_names: Option<FaceNames>,
    /// How the input cube's faces are turned against GL's, e.g. +x:rot90,-z:flipx (ops rot90, rot180, rot270, flipx, flipy, transpose).
    #[arg(long, value_parser = parse_face_transforms, allow_hyphen_values = true)]
    pub(crate) from_face_transform: Option<FaceTransforms>,
    /// How to turn the output cube's faces against GL's (as --from-face-transform).
    #[arg(long, value_parser = parse_face_transforms, allow_hyphen_values = true)]
    pub(crate) face_transform: Option<FaceTransforms>,
    /// Reconstruction filter: nearest, bilinear, or cubic (Catmull-Rom clamped to each point's 2×2 neighbourhood, so a sun does not ring: for outputs finer than the input).
    #[arg(long, default_value = "bilinear")]
    pub(crate) filter: Filter,
    /// Sub-samples per output texel side (N×N); default: automatic from the size ratio.
    #[arg(long)]
    pub(crate) samples: Option<u32>,
    /// Rotation on the way, yaw,pitch,roll in degrees (about z, y, x).
    #[arg(long, value_parser = parse_rotation, allow_hyphen_values = true)]
    pub(crate) rotate: Option<Frame>,
    /// Worker threads (default: one per core).
    #[arg(long)]
    pub(crate) threads: Option<usize>,
    /// Exposure in stops for 8-bit outputs (PNG).
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub(crate) exposure: f32,
    /// Write OpenEXR as 16-bit half floats.
    #[arg(long)]
    pub(crate) half: bool,
    #[command(flatten)]
    pub(crate) texture: TextureFlags,
    #[command(flatten)]
    pub(crate) write: WriteFlags,
    /// For .ktx2, .dds and .ktx outputs: add the mip chain, each level the solid-angle-weighted 2×2 box filter of the one above (the bake's pyramid), down to 1×1 for a cube (a 2D chain stops where a level's size leaves the ⌊W/2ᵖ⌋ × ⌊H/2ᵖ⌋ rule).
    #[arg(long)]
    pub(crate) mips: bool,
    /// Allow the output to replace the input file.
    #[arg(long)]
    pub(crate) overwrite_input: bool,
    /// Largest image accepted, in millions of texels.
    #[arg(long, default_value_t = 268)]
    pub(crate) max_megatexels: u64,
    /// No progress bar or summary.
    #[arg(long, short)]
    pub(crate) quiet: bool,
    /// Print each stage (loading, converting, saving) on standard error as it begins.
    #[arg(long, short)]
    pub(crate) verbose: bool,
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
    if repr.mapping.has_cube_faces() {
        width / a.cols
    } else {
        width
    }
}

/// The input file's axes, as the flags give them; `None` when no flag
/// says (the file's own word, else the default).
fn input_axes(a: &ConvertArgs) -> Option<FileAxes> {
    let convention = a.from_convention.or(a.convention);
    if convention.is_none() && a.from_frame.is_none() {
        return None;
    }
    Some(FileAxes::Convention(
        convention.unwrap_or_default(),
        a.from_frame.unwrap_or_default(),
    ))
}

/// The output file's axes, as the flags give them.
fn output_axes(a: &ConvertArgs) -> FileAxes {
    FileAxes::Convention(
        a.to_convention.or(a.convention).unwrap_or_default(),
        a.to_frame.unwrap_or_default(),
    )
}

fn output_representation(a: &ConvertArgs) -> Result<(Representation, bool), crate::Failure> {
    let to = with_lens(a.to, a.lens, a.fov, "--fov and --lens")?;
    let layout = a.layout.unwrap_or_else(|| {
        if a.output.to_string_lossy().contains("{face}") && to.has_cube_faces() {
            Layout::Faces
        } else {
            Layout::for_mapping(to)[0]
        }
    });
    if !Layout::for_mapping(to).contains(&layout) {
        let names: Vec<&str> = Layout::for_mapping(to).iter().map(|l| l.name()).collect();
        return Err(format!(
            "--layout {}: {} has no such layout; its layouts: {}",
            layout.name(),
            to,
            names.join(", ")
        )
        .into());
    }
    let six = layout.is_six_files();
    Ok((
        Representation::new(to, layout.atlas(), output_axes(a).frame(to))?,
        six,
    ))
}

pub(crate) fn run(a: &ConvertArgs, stop: &AtomicBool) -> CliResult {
    set_threads(a.threads)?;
    if a.samples == Some(0) || a.samples.is_some_and(|s| s > 16) {
        return Err("--samples must be between 1 and 16".into());
    }
    let is_texture = FileFormat::from_path(&a.output).is_ok_and(FileFormat::is_texture);
    if !is_texture && (a.mips || a.texture.format.is_some() || a.texture.zstd.is_some()) {
        return Err(format!(
            "{}: --mips, --format and --zstd are for .ktx2, .dds and .ktx outputs",
            a.output.display()
        )
        .into());
    }
    let mut texture_summary = None;
    let stage = |what: String| {
        if a.verbose {
            note!("envmap: {what}");
        }
    };
    stage(format!("loading {}", a.input.display()));
    let t0 = Instant::now();
    let from = a.from_lens.apply(a.from)?;
    let (repr, six) = output_representation(a)?;
    let opts = {
        let mut o = LoadOptions::default();
        o.mapping = from;
        o.layout = a.from_layout;
        o.axes = input_axes(a);
        o.face_transforms = a.from_face_transform.unwrap_or_default();
        o.max_texels = a.max_megatexels.saturating_mul(1_000_000);
        o.non_finite = NonFinite::Zero;
        o.cancel = Some(stop);
        o
    };
    let loaded = load_detailed(&a.input, &opts).map_err(|e| load_error(&e))?;
    warn_replaced(&a.input, loaded.replaced);
    let Loaded {
        image: src,
        files: inputs,
        ..
    } = loaded;
    let t_load = t0.elapsed();
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
        )
        .into());
    }
    let copts = {
        let mut o = ConvertOptions::default();
        o.filter = a.filter;
        o.samples = a.samples;
        o.rotation = a.rotate;
        o.cancel = Some(stop);
        o
    };
    // What the input sees of the output, when it does not see everything or a mask is asked.
    let seen = if !src.mapping().covers_sphere() || a.mask.is_some() {
        stage("measuring what the input sees".to_owned());
        Some(coverage(src.representation(), repr, w, h, &copts)?)
    } else {
        None
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
    let sopts = {
        let mut o = a.write.over(SaveOptions::default());
        o.exposure = a.exposure;
        o.exr_precision = if a.half {
            ExrPrecision::F16
        } else {
            ExrPrecision::F32
        };
        o.six_files = six;
        o.inputs = inputs;
        o.overwrite_input = a.overwrite_input;
        o.face_names = a.face_names;
        o.face_transforms = a.face_transform.unwrap_or_default();
        o.content = None;
        o.texture = a.texture.over(TextureOptions::default());
        o.cancel = Some(stop);
        o
    };
    let (src_mapping, (src_w, src_h)) = (
        src.mapping(),
        src.representation().file_size(src.width(), src.height()),
    );
    // The sizes the summary names are the files' (v360's EAC pads its rows).
    let (file_w, file_h) = repr.file_size(w, h);
    let src_axes = envmap_render::image::identify(src_mapping, src.representation().frame);
    let streams = matches!(FileFormat::from_path(&a.output), Ok(FileFormat::Exr));
    let (times, written) = if streams {
        // OpenEXR is written as the rows are made: no whole converted image
        // in memory, and the conversion overlaps the compression and writes.
        stage(format!(
            "converting to {} {w}×{h} and saving {}",
            repr.mapping,
            a.output.display()
        ));
        let t1 = Instant::now();
        let stream = Streamed::new(&src, repr, w, h, &copts, Some(&tick))?;
        let mut run = Outputs::new(&sopts);
        run.stage_streamed(&stream, &a.output, &sopts)?;
        bar.finish_and_clear();
        let written = run.commit()?;
        let t = t1.elapsed().as_secs_f64() * 1e3;
        (format!("convert and save {t:.0} ms"), written)
    } else {
        stage(format!("converting to {} {w}×{h}", repr.mapping));
        let t1 = Instant::now();
        let out = convert(&src, repr, w, h, &copts, Some(&tick))?;
        let t_convert = t1.elapsed();
        // The input is no longer needed: free it before encoding, which may
        // need buffers of its own.
        drop(src);
        bar.finish_and_clear();
        stage(format!("saving {}", a.output.display()));
        let t2 = Instant::now();
        let written = if is_texture {
            let levels = if a.mips {
                Pyramid::new(out, 1)?.into_levels()
            } else {
                vec![out]
            };
            let tex = Texture::from_env(&levels).map_err(|e| e.in_file(&a.output).to_string())?;
            let mut run = Outputs::new(&sopts);
            let clamped = run.stage_texture(&tex, &a.output, sopts.texture)?;
            warn_clamped(&a.output, sopts.texture.format, clamped);
            texture_summary = Some(format!(
                "{} level{}, {}{}",
                tex.level_count(),
                if tex.level_count() == 1 { "" } else { "s" },
                sopts.texture.format.name(),
                sopts
                    .texture
                    .zstd
                    .map(|l| format!(", zstd {l}"))
                    .unwrap_or_default()
            ));
            run.commit()?
        } else {
            save(&out, &a.output, &sopts)?
        };
        let (c, s) = (
            t_convert.as_secs_f64() * 1e3,
            t2.elapsed().as_secs_f64() * 1e3,
        );
        (format!("convert {c:.0} ms, save {s:.0} ms"), written)
    };
    if let (Some(path), Some(c)) = (&a.mask, &seen) {
        let mask = envmap_render::image::RgbImage {
            width: w,
            height: h,
            pixels: c.texels.iter().map(|&t| [t; 3]).collect(),
        };
        let mut o = SaveOptions::default();
        o.inputs = sopts.inputs.clone();
        envmap_render::image::write_rgb(&mask, path, &o).map_err(|e| format!("--mask: {e}"))?;
    }
    if !a.quiet {
        note!(
            "{} {}×{} {} -> {} {}×{} {} ({}, {}×{} samples): load {:.0} ms, {}",
            a.input.display(),
            src_w,
            src_h,
            src_mapping,
            written.first().map_or_else(
                || a.output.display().to_string(),
                |p| p.display().to_string()
            ),
            file_w,
            file_h,
            repr.mapping,
            match a.filter {
                Filter::Nearest => "nearest",
                Filter::Bilinear => "bilinear",
                Filter::Cubic => "cubic",
            },
            samples,
            samples,
            t_load.as_secs_f64() * 1e3,
            times,
        );
        if let Some(t) = &texture_summary {
            note!("  texture: {t}");
        }
        if let Some(c) = &seen {
            note!(
                "  coverage: the input sees {:.2} % of the output's directions{}",
                100.0 * c.fraction,
                if c.fraction < 1.0 {
                    " (black elsewhere; --mask writes where)"
                } else {
                    ""
                }
            );
        }
        note!("  input axes:  {}", src_axes.describe(src_mapping));
        note!("  output axes: {}", output_axes(a).describe(repr.mapping));
    }
    Ok(())
}
