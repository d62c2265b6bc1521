//! `envmap info`: what is in a file.

use std::io::Write;
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;

use clap::Args;
use envmap_core::{AnyMapping, Mapping};

use crate::args::{
    load_error, parse_convention, parse_face_transforms, parse_layout, parse_mapping, parse_world,
    CliResult,
};
use envmap_render::image::texture::{level_size, TextureFile, TextureKind};
use envmap_render::image::EnvImage;
use envmap_render::image::FaceTransforms;
use envmap_render::image::FileFormat;
use envmap_render::image::Layout;
use envmap_render::image::{load_detailed, LoadOptions};
use envmap_render::image::{Convention, FileAxes, World};

#[derive(Args)]
pub(crate) struct InfoArgs {
    /// The file.
    pub(crate) file: PathBuf,
    /// Mapping, when the aspect ratio does not say.
    #[arg(long, value_parser = parse_mapping)]
    pub(crate) from: Option<AnyMapping>,
    #[command(flatten)]
    pub(crate) from_lens: crate::args::FromLensFlags,
    /// Layout, when the aspect ratio does not say.
    #[arg(long, value_parser = parse_layout)]
    pub(crate) layout: Option<Layout>,
    /// The world the file's conventions are in: y-up (the GL world), y-up-lh or z-up; default: what the file says of itself, else y-up.
    #[arg(long, value_parser = parse_world)]
    pub(crate) frame: Option<World>,
    /// The file's conventions (see `envmap convert --help`); default: what the file says, else envmap.
    #[arg(long, value_parser = parse_convention)]
    pub(crate) convention: Option<Convention>,
    /// How the cube's faces are turned against GL's (see `envmap convert --help`).
    #[arg(long, value_parser = parse_face_transforms, allow_hyphen_values = true)]
    pub(crate) face_transform: Option<FaceTransforms>,
    /// Largest image accepted, in millions of texels.
    #[arg(long, default_value_t = 268)]
    pub(crate) max_megatexels: u64,
}

pub(crate) fn run(a: &InfoArgs, stop: &AtomicBool) -> CliResult {
    let given = (a.frame.is_some() || a.convention.is_some()).then(|| {
        FileAxes::Convention(
            a.convention.unwrap_or_default(),
            a.frame.unwrap_or_default(),
        )
    });
    let opts = {
        let mut o = LoadOptions::default();
        o.mapping = a.from_lens.apply(a.from)?;
        o.layout = a.layout;
        o.axes = given;
        o.face_transforms = a.face_transform.unwrap_or_default();
        o.max_texels = a.max_megatexels.saturating_mul(1_000_000);
        o.cancel = Some(stop);
        o
    };
    let loaded = load_detailed(&a.file, &opts).map_err(|e| load_error(&e))?;
    // A GPU texture's levels, format and metadata (the rest below is of level 0).
    let texture = match FileFormat::from_path(&a.file) {
        Ok(f) if f.is_texture() => Some(
            envmap_render::image::texture::read(&a.file, opts.max_texels, Some(stop))
                .map_err(|e| load_error(&e))?,
        ),
        _ => None,
    };
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
            match repr.file_size(img.width(), img.height()) {
                (w, h) if (w, h) == (img.width(), img.height()) => format!("{w} × {h}"),
                (w, h) => format!(
                    "{w} × {h} in the file; {} × {} without the layout's padding",
                    img.width(),
                    img.height()
                ),
            },
        )?;
        p(
            &mut out,
            "pixel format",
            format!("{:?}, {}", loaded.source.format, loaded.source.pixel_format),
        )?;
        if let Some(t) = &texture {
            texture_lines(&mut out, t)?;
        }
        p(&mut out, "mapping", repr.mapping.to_string())?;
        if let AnyMapping::Fisheye(f) = repr.mapping {
            let seen = repr.mapping.seen_solid_angle() / (4.0 * std::f64::consts::PI);
            p(
                &mut out,
                "lens",
                format!(
                    "{}, {}° per lens (sees {:.1} % of the sphere{})",
                    f.lens(),
                    f.fov_degrees(),
                    100.0 * seen,
                    if f.covers_sphere() {
                        ""
                    } else {
                        "; black where unseen"
                    }
                ),
            )?;
        }
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
        if let Some((_, c)) = loaded
            .source
            .tags
            .iter()
            .find(|(k, _)| k == envmap_render::image::FileMetadata::CONTENT_KEY)
        {
            p(&mut out, "content", c.clone())?;
        }
        let whence = match (given, loaded.metadata.axes) {
            (Some(_), _) => "as given",
            (None, Some(_)) => "as the file says",
            (None, None) if loaded.source.format == FileFormat::Dds => {
                "the default: a DDS file has no place to say; a bake's manifest.json beside it does (frame_to_canonical)"
            }
            (None, None) => "the default: the file does not say",
        };
        p(
            &mut out,
            "axes",
            format!(
                "{} ({whence})",
                envmap_render::image::identify(repr.mapping, repr.frame).describe(repr.mapping)
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
        p(
            &mut out,
            "negative texels",
            if s.negative == 0 {
                "0".to_owned()
            } else {
                format!(
                    "{} (no light is negative: lossy compression rings around bright texels; convert keeps them, bake integrates them as given and clamps its outputs at zero)",
                    s.negative
                )
            },
        )?;
        if s.negative > 0 {
            let e = envmap_render::filter::weights::channel_energy(img);
            let share: Vec<String> = (0..3)
                .map(|c| {
                    let pos = e.total[c] - e.negative[c];
                    let v = if pos > 0.0 { -e.negative[c] / pos } else { 0.0 };
                    format!("{:.4} %", 100.0 * v)
                })
                .collect();
            p(
                &mut out,
                "negative energy",
                format!(
                    "R {} G {} B {} (Σ Ω·L of the negative values over that of the positive ones, per channel)",
                    share[0], share[1], share[2]
                ),
            )?;
        }
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
    r.map_err(|e| format!("<stdout>: {e}").into())
}

/// The lines about a texture file: container, format, orientation, writer,
/// key/value entries, and each level's size and bytes.
fn texture_lines(out: &mut dyn Write, t: &TextureFile) -> std::io::Result<()> {
    let i = &t.info;
    let p = |out: &mut dyn Write, k: &str, v: String| writeln!(out, "{k:<16} {v}");
    p(out, "texture", i.summary())?;
    p(
        out,
        "texel format",
        format!(
            "{} ({}; vkFormat {}{}), largest value {}",
            i.format.name(),
            i.format.vk_name(),
            i.format.vk_format(),
            i.format
                .dxgi_format()
                .map(|d| format!(", DXGI {d}"))
                .unwrap_or_default(),
            i.format.max_value()
        ),
    )?;
    p(
        out,
        "orientation",
        match (&i.orientation, i.kind) {
            (Some(o), _) => format!("{o} (as the file says)"),
            (None, TextureKind::Cube) => {
                "rd: faces +X, -X, +Y, -Y, +Z, -Z as GL selects them, first texel top-left (the format's rule)".to_owned()
            }
            (None, TextureKind::Flat) => "rd: first texel top-left (the format's rule)".to_owned(),
        },
    )?;
    p(
        out,
        "writer",
        i.writer.clone().unwrap_or_else(|| "not stated".to_owned()),
    )?;
    for (k, v) in &i.key_values {
        if k == "envmap.bc6h-error" {
            // One line per level: what BC6H lost when envmap wrote it.
            for line in v.lines() {
                p(out, "BC6H error", line.to_owned())?;
            }
        } else if k != "KTXorientation" && k != "KTXwriter" {
            p(out, "key/value", format!("{k} = {v:?}"))?;
        }
    }
    if i.format == envmap_render::image::TexelFormat::Bc6h
        && !i.key_values.iter().any(|(k, _)| k == "envmap.bc6h-error")
    {
        p(
            out,
            "BC6H error",
            "not recorded in this file (envmap records it in KTX2 files it writes, and a bake's manifest.json for DDS too)".to_owned(),
        )?;
    }
    let (w, h) = i.size;
    let faces = if i.kind == TextureKind::Cube {
        " × 6 faces"
    } else {
        ""
    };
    for (level, bytes) in i.level_bytes.iter().enumerate() {
        let (lw, lh) = level_size(w, h, level);
        p(
            out,
            &format!("level {level}"),
            format!("{lw} × {lh}{faces}, {bytes} bytes in the file"),
        )?;
    }
    Ok(())
}
