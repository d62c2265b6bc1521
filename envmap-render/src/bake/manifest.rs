//! What a bake directory says about itself: the manifest (input,
//! conventions, rule, every level and what it measured), `sh.json`, and
//! the SH forms cmgen writes (its KTX `sh` key and `sh.txt`).

use std::path::Path;

use envmap_core::AnyMapping;

use super::preset::{Preset, Target};
use super::write::{file_name, level_file, texture_name, Provenance};
use crate::filter::bake::{Bake, BakeOptions, Irradiance, LevelReport, SpecularChain};
use crate::filter::dfg::{DfgGrid, DfgTable};
use crate::filter::sh::NAMES;
use crate::image::convention::FileAxes;
use crate::image::FileFormat;

/// Filament's pre-scaled SH (E/π, y up) of the bake, windowed as the plan
/// says, in the cube files' axes: cmgen's mirroring negates x, flipping the
/// three terms odd in x (L11, L2-2, L21).
fn filament_sh(b: &Bake, preset: &Preset) -> [[f64; 3]; 9] {
    let sh = match preset.sh_window {
        Some(w) => b.sh.windowed(w),
        None => b.sh,
    };
    let mut f = sh.filament_shader_form();
    if preset.mirrored {
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
pub(super) fn filament_sh_key(b: &Bake, preset: &Preset) -> String {
    filament_sh(b, preset)
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
pub(super) fn filament_sh_txt(b: &Bake, preset: &Preset) -> String {
    filament_sh(b, preset)
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
pub(super) fn sh_json(preset: &Preset, b: &Bake, axes: FileAxes) -> String {
    let frame = axes.frame(AnyMapping::Cube);
    let windowed = match preset.sh_window {
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
        "window": match preset.sh_window {
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
pub(super) fn manifest(
    dir: &Path,
    preset: &Preset,
    provenance: &Provenance,
    b: &Bake,
    opts: &BakeOptions,
    lossy: &[Lossy],
) -> String {
    let specular = b
        .chain
        .as_ref()
        .map(|chain| specular_json(dir, preset, chain, opts));
    let m = serde_json::json!({
        "envmap": crate::image::metadata::software(),
        "input": provenance.input,
        "axes": opts.axes.describe(AnyMapping::Cube),
        "frame_to_canonical": frame_columns(opts.axes.frame(AnyMapping::Cube)),
        "frame_to_canonical_note": "the cube files' x, y and z axes as columns in envmap's canonical axes (z up, right-handed); what `envmap render --env DIR` reads",
        "layout": if preset.container == FileFormat::Exr { preset.layout.name() } else { "one texture file per map: faces +X, -X, +Y, -Y, +Z, -Z, first texel top-left (KTX orientation rd), levels largest first" },
        "container": preset.container.extension(),
        "target": preset.target.map(Target::name),
        "texel_format": (preset.container != FileFormat::Exr).then(|| preset.texture.format.vk_name()),
        "zstd_level": preset.texture.zstd,
        "compression": lossy_json(preset, lossy),
        "mirrored": preset.mirrored.then_some("x negated, as cmgen's default (Filament's shaders expect it)"),
        "seconds": { "load": provenance.load_seconds, "bake": provenance.bake_seconds },
        "specular": specular,
        "irradiance": b.irradiance.as_ref().map(|i| irradiance_json(dir, preset, b, i, opts)),
        "sh": {
            "file": "sh.json",
            "window": preset.sh_window.map(|_| b.sh_cutoff),
            "measured_relative_error": b.checked.map(|c| c.sh9),
        },
        "dfg": b.dfg.as_ref().map(dfg_json),
        "stages_seconds": b.stages.iter().map(|(n, t)| serde_json::json!({"stage": n, "seconds": t})).collect::<Vec<_>>(),
    });
    serde_json::to_string_pretty(&m).unwrap_or_default()
}

/// What a lossy texel format lost in one file: each level's error.
pub(super) struct Lossy {
    /// The file's name in the bake's directory.
    pub(super) file: String,
    /// Each level's error, the file's texels decoded against the levels.
    #[cfg(any(feature = "bc6h", feature = "babylon"))]
    pub(super) levels: Vec<crate::image::lossy::LevelError>,
    /// RGBD: each level's fraction of its energy above 255 (empty for
    /// BC6H).
    #[cfg_attr(not(any(feature = "bc6h", feature = "babylon")), allow(dead_code))]
    pub(super) clipped: Vec<f64>,
}

/// The manifest's `compression` entry: for BC6H and RGBD, each file's
/// error per level (`null` for the formats that only round).
fn lossy_json(preset: &Preset, lossy: &[Lossy]) -> Option<serde_json::Value> {
    use crate::image::TexelFormat;
    let format = preset.texture.format;
    if !matches!(format, TexelFormat::Bc6h | TexelFormat::Rgbd8) || lossy.is_empty() {
        return None;
    }
    let files: Vec<serde_json::Value> = lossy
        .iter()
        .map(|l| {
            #[cfg(any(feature = "bc6h", feature = "babylon"))]
            let levels: Vec<serde_json::Value> = l
                .levels
                .iter()
                .enumerate()
                .map(|(p, e)| {
                    let mut v = serde_json::json!({
                        "level": p,
                        "relative_rms": e.rel_rms,
                        "log_rmse": e.log_rmse,
                        "worst_relative": e.worst,
                        "worst_texel": { "face": e.worst_at.0, "x": e.worst_at.1, "y": e.worst_at.2 },
                        "worst_texel_value": e.worst_value,
                    });
                    if let Some(c) = l.clipped.get(p) {
                        v["clipped_energy"] = serde_json::json!(c);
                    }
                    v
                })
                .collect();
            #[cfg(not(any(feature = "bc6h", feature = "babylon")))]
            let levels: Vec<serde_json::Value> = Vec::new();
            serde_json::json!({ "file": l.file, "levels": levels })
        })
        .collect();
    let measures = serde_json::json!({
        "relative_rms": "sqrt(sum (d - r)^2) / sqrt(sum r^2) over every component of the level",
        "log_rmse": "sqrt(mean (ln(1 + d) - ln(1 + r))^2) over every component",
        "worst_relative": "the texel whose largest channel difference |d - r| is largest relative to its largest channel (at least 2^-14)",
    });
    let mut v = if format == TexelFormat::Bc6h {
        serde_json::json!({
            "format": "BC6H_UFLOAT_BLOCK",
            "quality": preset.texture.bc6h.name(),
            "encoder": "block_compression (a Rust port of Intel's ISPC BC6H kernel)",
            "decoder": "bcdec_rs (a Rust port of bcdec), reading the bytes written",
            "error_against": "each level's texels before compression, clamped to [0, 65504] as the encoder clamps them",
        })
    } else {
        serde_json::json!({
            "format": "RGBD in 8-bit RGBA PNG (Babylon.js toRGBD: D = floor(max(255/max(r,g,b), 1))/255, rgb = (c D)^(1/2.2), a = D)",
            "decoder": "envmap's .env reader (Babylon.js fromRGBD: rgb^2.2 / a), reading the bytes written",
            "error_against": "each level's texels, clamped to [0, 255] as RGBD clamps them",
            "clipped_energy": "per level, the fraction of its radiant energy (value x solid angle, summed over channels and texels) above 255, which RGBD cannot hold and which is lost (a sun); the irradiance polynomial is made from the unclipped source",
        })
    };
    if let (Some(o), Some(m)) = (v.as_object_mut(), measures.as_object()) {
        o.extend(m.clone());
        o.insert("files".into(), serde_json::json!(files));
    }
    Some(v)
}

/// The manifest's `specular` entry: what the chain's levels hold, how
/// they were made (rule, bright texels, energy, clamp) and every level.
fn specular_json(
    dir: &Path,
    preset: &Preset,
    chain: &SpecularChain,
    opts: &BakeOptions,
) -> serde_json::Value {
    let levels: Vec<serde_json::Value> = chain
        .reports
        .iter()
        .enumerate()
        .map(|(k, r)| level_json(dir, preset, k, r))
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
}

/// The manifest's entry for level `k` of the chain: its file, size,
/// roughness, how it was made and, when checked, its measured error.
fn level_json(dir: &Path, preset: &Preset, k: usize, r: &LevelReport) -> serde_json::Value {
    serde_json::json!({
        "level": k,
        "file": level_file(dir, preset, k),
        "size": r.size,
        "perceptual_roughness": r.roughness,
        "alpha": r.roughness * r.roughness,
        "method": r.method,
        "samples": r.samples,
        "exact_source_level": r.source_level,
        "expected_relative_rms_error_smooth_light": r.estimated_error(),
        "measured": r.measured.map(|m| serde_json::json!({
            "texels": m.texels,
            "relative_rms_error": m.relative_rms,
            "bias": m.bias,
            "seconds": m.seconds,
            "against": "the oracle: the input as given, piecewise constant over its own texels, by adaptive quadrature (envmap_render::instruments::Oracle)",
        })),
        "texels_clamped_at_zero": r.clamped,
        "seconds": r.seconds,
    })
}

/// The manifest's `irradiance` entry: the map's file, size, scale, how
/// it was made and, when checked, its measured error.
fn irradiance_json(
    dir: &Path,
    preset: &Preset,
    b: &Bake,
    i: &Irradiance,
    opts: &BakeOptions,
) -> serde_json::Value {
    serde_json::json!({
        "file": if preset.container == FileFormat::Exr { file_name(preset, "irradiance") } else { texture_name(dir, preset, preset.irradiance) },
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
    })
}

/// The manifest's `dfg` entry: the two files, the table's grid and axes,
/// and how to sample it.
fn dfg_json(t: &DfgTable) -> serde_json::Value {
    serde_json::json!({
        "files": {
            "dfg.exr": "single scatter: R = scale, G = bias (F0·scale + bias)",
            "dfg_multiscatter.exr": "Filament's multiscatter form: R = bias, G = scale + bias",
        },
        "size": t.size(),
        "grid": t.grid().name(),
        "x": dfg_axes(t).0,
        "y": dfg_axes(t).1,
        "lookup": match t.grid() {
            DfgGrid::TexelCentres => "sample the texture at (N·V, roughness) with linear filtering".to_owned(),
            DfgGrid::Edges => format!("sample the texture at ((size - 1)·x + 0.5) / size = ({} x + 0.5) / {} for x = N·V and x = roughness, with linear filtering: N·V and roughness of 0 and 1 are exact", t.size() - 1, t.size()),
        },
        "visibility": "height-correlated Smith GGX",
        "precision": "computed in f64 by quadrature, stored as f32",
    })
}

/// Where a DFG table's columns and rows sit, in words (its grid).
pub(super) fn dfg_axes(t: &DfgTable) -> (String, String) {
    let n = t.size();
    match t.grid() {
        DfgGrid::TexelCentres => (
            format!("column i: N.V = (i + 0.5)/{n}"),
            format!("row j from the top: perceptual roughness (j + 0.5)/{n}"),
        ),
        DfgGrid::Edges => (
            format!("column i: N.V = i/{}", n - 1),
            format!("row j from the top: perceptual roughness j/{}", n - 1),
        ),
    }
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
