//! Argument parsers and helpers the subcommands share.

use std::path::Path;

use envmap_core::glam::Vec3;
use envmap_core::{AnyMapping, Fisheye, Frame, Lens};

use envmap_render::image::FaceNames;
use envmap_render::image::FaceTransforms;
use envmap_render::image::Layout;
use envmap_render::image::Representation;
use envmap_render::image::{Convention, World};
use envmap_render::scene::Mode;

pub(crate) type CliResult = Result<(), crate::Failure>;

pub(crate) fn parse_vec3(s: &str) -> Result<Vec3, String> {
    let v: Result<Vec<f32>, _> = s.split(',').map(|t| t.trim().parse::<f32>()).collect();
    match v {
        Ok(v) if v.len() == 3 && v.iter().all(|x| x.is_finite()) => Ok(Vec3::new(v[0], v[1], v[2])),
        _ => Err(format!("expected x,y,z (e.g. 0,-9.5,4), got '{s}'")),
    }
}

pub(crate) fn parse_mode(s: &str) -> Result<Mode, String> {
    match s.to_ascii_lowercase().as_str() {
        "per-pixel" | "pixel" => Ok(Mode::PerPixel),
        "per-vertex" | "vertex" => Ok(Mode::PerVertex),
        _ => Err(format!(
            "unknown mode '{s}'; expected per-pixel or per-vertex"
        )),
    }
}

/// The mapping names the command accepts.
pub(crate) fn parse_mapping(s: &str) -> Result<AnyMapping, String> {
    s.parse::<AnyMapping>().map_err(|e| e.to_string())
}

/// `--lens`, `--from-lens`: a fisheye's law.
pub(crate) fn parse_lens(s: &str) -> Result<Lens, String> {
    Lens::from_name(s)
        .ok_or_else(|| format!("unknown lens '{s}'; expected {}", Lens::NAMES.join(" or ")))
}

/// `--fov`, `--from-fov`: a fisheye's field of view per lens, in degrees.
pub(crate) fn parse_fov(s: &str) -> Result<f64, String> {
    match s.trim_end_matches('°').parse::<f64>() {
        Ok(f) if f > 0.0 && f <= 360.0 => Ok(f),
        _ => Err(format!(
            "expected a field of view in degrees, above 0 and at most 360 (e.g. 190), got '{s}'"
        )),
    }
}

/// The input's fisheye lens, for a file whose own metadata does not say it.
#[derive(clap::Args, Clone, Copy, Debug, Default)]
pub(crate) struct FromLensFlags {
    /// Field of view of each lens of a fisheye input (--from fisheye or dual-fisheye), in degrees (default 180, as ffmpeg's v360; files envmap wrote say theirs).
    #[arg(long, value_parser = parse_fov)]
    pub(crate) from_fov: Option<f64>,
    /// Lens law of a fisheye input: equidistant (r ∝ θ, the default, as v360's fisheye) or equisolid (r ∝ sin(θ/2): equal-area, most real fisheye lenses).
    #[arg(long, value_parser = parse_lens)]
    pub(crate) from_lens: Option<Lens>,
}

impl FromLensFlags {
    /// `--from` with the lens these flags give.
    pub(crate) fn apply(&self, from: Option<AnyMapping>) -> Result<Option<AnyMapping>, String> {
        match from {
            Some(m) => with_lens(
                m,
                self.from_lens,
                self.from_fov,
                "--from-fov and --from-lens",
            )
            .map(Some),
            None if self.from_fov.is_some() || self.from_lens.is_some() => Err(
                "--from-fov and --from-lens need --from fisheye or --from dual-fisheye".to_owned(),
            ),
            None => Ok(None),
        }
    }
}

/// `m` with a fisheye's lens law and field of view set where given; an error naming `flags`
/// when they are given for a mapping that is not a fisheye.
pub(crate) fn with_lens(
    m: AnyMapping,
    lens: Option<Lens>,
    fov: Option<f64>,
    flags: &str,
) -> Result<AnyMapping, String> {
    match m {
        AnyMapping::Fisheye(f) => Fisheye::new(
            lens.unwrap_or(f.lens()),
            fov.unwrap_or(f.fov_degrees()),
            f.is_dual(),
        )
        .map(AnyMapping::Fisheye)
        .ok_or_else(|| format!("{flags}: a field of view above 0° and at most 360°")),
        _ if lens.is_some() || fov.is_some() => {
            Err(format!("{flags} are for fisheye and dual-fisheye, not {m}"))
        }
        _ => Ok(m),
    }
}

pub(crate) fn parse_layout(s: &str) -> Result<Layout, String> {
    s.parse::<Layout>().map_err(|e| e.to_string())
}

/// `--frame`, `--from-frame`, `--to-frame`: the world (y-up, y-up-lh, z-up).
pub(crate) fn parse_world(s: &str) -> Result<World, String> {
    s.parse::<World>().map_err(|e| e.to_string())
}

/// `--convention`: a preset of file conventions.
pub(crate) fn parse_convention(s: &str) -> Result<Convention, String> {
    s.parse::<Convention>().map_err(|e| e.to_string())
}

/// `--face-names`: a naming scheme of a cube's six files.
pub(crate) fn parse_face_names(s: &str) -> Result<FaceNames, String> {
    s.parse::<FaceNames>().map_err(|e| e.to_string())
}

/// `--face-transform`: `face:op[,face:op...]`.
pub(crate) fn parse_face_transforms(s: &str) -> Result<FaceTransforms, String> {
    s.parse::<FaceTransforms>().map_err(|e| e.to_string())
}

/// `yaw,pitch,roll` in degrees.
pub(crate) fn parse_rotation(s: &str) -> Result<Frame, String> {
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

/// A load error's message, with how to raise the size limit when that is
/// what stopped it.
pub(crate) fn load_error(e: &envmap_render::Error) -> String {
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
pub(crate) fn warn_replaced(path: &Path, n: u64) {
    if n > 0 {
        note!(
            "envmap: warning: {}: {n} texel{} with NaN or infinite values replaced by black",
            path.display(),
            if n == 1 { "" } else { "s" }
        );
    }
}

/// The image size for `--size` in a representation: a cube's or EAC's face edge, any
/// other atlas's width.
pub(crate) fn output_size(repr: &Representation, size: u32) -> Result<(u32, u32), String> {
    let atlas = repr.atlas;
    // The image width must be a whole number of cells whose height is whole.
    let (step, what) = if repr.mapping.has_cube_faces() {
        (atlas.cell_aspect_w, "face edge")
    } else {
        (atlas.cols * atlas.cell_aspect_w, "width")
    };
    let cell = if repr.mapping.has_cube_faces() {
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

/// The flags of GPU texture outputs (`.ktx2`, `.dds`, `.ktx`), shared by
/// `convert` and `bake`.
#[derive(clap::Args, Clone, Copy, Debug)]
pub(crate) struct TextureFlags {
    /// Texel format of .ktx2, .dds and .ktx outputs: rgba16f (the default), rgba32f, rg11b10f (B10G11R11), rgb9e5 (E5B9G9R9), bc6h (BC6H_UFLOAT_BLOCK: one byte per texel, lossy; .ktx2 and .dds only, each level's error measured and written in the manifest and the .ktx2's key/value data).
    #[arg(long, value_parser = parse_texel_format)]
    pub(crate) format: Option<envmap_render::image::TexelFormat>,
    /// Zstandard supercompression of .ktx2 outputs, each level its own frame; an optional level 1 (fastest) to 22 (smallest), default 3 (higher levels make smaller files far more slowly: docs/performance.md).
    #[arg(long, num_args = 0..=1, default_missing_value = "3", require_equals = false)]
    pub(crate) zstd: Option<i32>,
    /// No Zstandard supercompression, even where a --target would use it.
    #[arg(long, conflicts_with = "zstd")]
    pub(crate) no_zstd: bool,
    /// How hard the BC6H encoder searches (--format bc6h): very-fast (the default), fast, basic, slow, very-slow: Intel's ISPC presets, each searching more of every block; all but very-slow encode again at very-slow the blocks that decode more than about 3 % off (docs/engines.md has the errors and times).
    #[arg(long, value_parser = parse_bc6h_quality)]
    pub(crate) bc6h_quality: Option<envmap_render::image::Bc6hQuality>,
}

impl TextureFlags {
    /// The options these flags give over `base` (a preset's, or the
    /// defaults).
    pub(crate) fn over(
        &self,
        base: envmap_render::image::texture::TextureOptions,
    ) -> envmap_render::image::texture::TextureOptions {
        let mut o = base;
        o.format = self.format.unwrap_or(base.format);
        o.bc6h = self.bc6h_quality.unwrap_or(base.bc6h);
        o.zstd = if self.no_zstd {
            None
        } else {
            self.zstd.or(base.zstd)
        };
        o
    }
}

/// How files are written, shared by `convert`, `bake` and `render`.
#[derive(clap::Args, Clone, Copy, Debug)]
pub(crate) struct WriteFlags {
    /// Compression of .exr outputs: auto (the default: f32 uncompressed but for the lines through a cube cross's empty cells, which rle takes to a few bytes; rle for f16), none, rle, zips, zip, piz, pxr24 (lossy for f32), b44, b44a (lossy, f16 only). auto writes a cube cross at half the size of none for a little more write time; rle on every line costs more; the other lossless codecs shrink a real f32 photograph by a part at many times the write time (docs/performance.md).
    #[arg(long, value_parser = parse_exr_compression)]
    pub(crate) exr_compression: Option<envmap_render::image::ExrCompression>,
    /// When outputs are flushed to the disk before they are renamed into place: replacing (the default: when an existing file is replaced, so that a power loss cannot leave neither), always, never. Every output is written to a temporary file and renamed either way.
    #[arg(long, value_parser = parse_sync)]
    pub(crate) sync: Option<envmap_render::image::SyncPolicy>,
}

impl WriteFlags {
    /// `base` with these flags' choices.
    pub(crate) fn over<'a>(
        &self,
        base: envmap_render::image::SaveOptions<'a>,
    ) -> envmap_render::image::SaveOptions<'a> {
        let mut o = base;
        o.exr_compression = self.exr_compression.unwrap_or(o.exr_compression);
        o.sync = self.sync.unwrap_or(o.sync);
        o
    }
}

/// `--exr-compression`: a codec's name.
pub(crate) fn parse_exr_compression(
    s: &str,
) -> Result<envmap_render::image::ExrCompression, String> {
    s.parse().map_err(|e: envmap_render::Error| e.to_string())
}

/// `--sync`: a sync policy's name.
pub(crate) fn parse_sync(s: &str) -> Result<envmap_render::image::SyncPolicy, String> {
    s.parse().map_err(|e: envmap_render::Error| e.to_string())
}

/// `--format`: a texel format's name.
pub(crate) fn parse_texel_format(s: &str) -> Result<envmap_render::image::TexelFormat, String> {
    envmap_render::image::TexelFormat::parse(s).map_err(|e| e.to_string())
}

/// `--bc6h-quality`: a BC6H encoder setting by its name.
pub(crate) fn parse_bc6h_quality(s: &str) -> Result<envmap_render::image::Bc6hQuality, String> {
    envmap_render::image::Bc6hQuality::parse(s).map_err(|e| e.to_string())
}

/// One line saying what packing clamped, or nothing when nothing was.
pub(crate) fn warn_clamped(
    path: &Path,
    format: envmap_render::image::TexelFormat,
    c: envmap_render::image::Clamped,
) {
    if !c.is_empty() {
        note!(
            "warning: {}: {} ({}): {}",
            path.display(),
            format.name(),
            format.vk_name(),
            c.describe(format)
        );
    }
}

/// `--threads N`: the global worker pool's size (default: one per core).
pub(crate) fn set_threads(threads: Option<usize>) -> Result<(), String> {
    if let Some(n) = threads {
        if n == 0 {
            return Err("--threads must be at least 1".into());
        }
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build_global()
            .map_err(|e| format!("--threads {n}: {e}"))?;
    }
    Ok(())
}
