//! The bake directory's reader: a [`LitEnvironment`] from the files
//! [`super::Baked::write`] (`envmap bake`) wrote, or a KTX2 / DDS chain on its own.
//!
//! * **A bake directory** (or any chain file in one): `manifest.json` says
//!   where each level of the specular chain is (`specular_k.exr`, or level
//!   k of `specular.ktx2` / `.dds`), each level's perceptual roughness, the
//!   irradiance map's file and whether it holds E or E/π (or, for the
//!   engines lit by SH alone, `sh.json`, whose irradiance is taken), and the axes the
//!   cube files are in (`frame_to_canonical`: the file axes' x, y, z as
//!   columns in envmap's z-up axes; OpenEXR files also say so themselves,
//!   and older manifests without the field are read through the files'
//!   own tags). The DFG table is computed again at the manifest's size: it
//!   depends on nothing but its size and grid (quadrature in f64), and the
//!   renderer builds it on the edges grid whatever grid the bake's
//!   `dfg.exr` is on ([`DfgGrid::Edges`]: N·V and roughness of 0 and 1
//!   read exactly; on the same grid it equals the file to the last bit of
//!   its f32 texels).
//! * **A chain file alone** (a `.ktx2` or `.dds` cube with more than one
//!   level and no manifest beside it naming it): the texture states no
//!   roughness, so level k of n is taken at roughness k/(n − 1), the linear
//!   rule of `envmap bake`'s default, glTF-IBL-Sampler and Bevy (a printed
//!   note says so); the irradiance map is made from level 0's SH9
//!   projection (as `envmap bake` makes it by default); the axes are the
//!   caller's (default: envmap's).
//!
//! KTX 1 files (Filament's) are written, not read: load the KTX2 or DDS
//! twin, or the source.

use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

use envmap_core::glam::{Mat3, Vec3};
use envmap_core::{AnyMapping, Frame};
use serde_json::Value;

use crate::error::{Error, Result};
use crate::filter::dfg::{DfgGrid, DfgTable};
use crate::filter::sh::{irradiance_map, IrradianceScale, Sh9, DEFAULT_IRRADIANCE_SIZE};
use crate::filter::specular::RoughnessRule;
use crate::image::io::{load_detailed, LoadOptions};
use crate::image::texture;
use crate::image::FileFormat;
use crate::image::{EnvImage, FileAxes, Representation};
use crate::scene::lit::LitEnvironment;

/// The DFG table's size when the manifest names none (`envmap bake`'s default).
const DEFAULT_DFG_SIZE: u32 = 64;

/// What [`open`] found.
#[derive(Clone, Debug)]
pub struct OpenedLit {
    /// The maps.
    pub env: LitEnvironment,
    /// Where they came from and what was assumed, one line for a user.
    pub description: String,
}

/// The manifest of a bake directory `path`, or the one beside chain file
/// `path` if it names that file as its specular chain.
fn manifest_for(path: &Path) -> Option<PathBuf> {
    if path.is_dir() {
        return Some(path.join("manifest.json"));
    }
    let dir = path.parent().filter(|d| !d.as_os_str().is_empty());
    let m = dir.map_or_else(
        || PathBuf::from("manifest.json"),
        |d| d.join("manifest.json"),
    );
    let name = path.file_name()?.to_string_lossy().into_owned();
    let text = std::fs::read_to_string(&m).ok()?;
    let v: Value = serde_json::from_str(&text).ok()?;
    let first = v["specular"]["levels"][0]["file"].as_str()?;
    (chain_file(first).0 == name).then_some(m)
}

/// How a manifest names level `k` held inside texture file `file`:
/// `"specular.ktx2 (level 3)"` (what `envmap bake` writes, and
/// what the manifest reader reads back).
#[must_use]
pub(crate) fn level_entry(file: &str, k: usize) -> String {
    format!("{file}{LEVEL_SEP}{k})")
}

/// Between a texture file's name and its level number in a manifest entry.
const LEVEL_SEP: &str = " (level ";

/// A manifest level's `file`: `"specular_3.exr"`, or [`level_entry`]'s
/// `"specular.ktx2 (level 3)"`.
fn chain_file(s: &str) -> (&str, Option<usize>) {
    if let Some((file, rest)) = s.split_once(LEVEL_SEP) {
        if let Some(k) = rest.strip_suffix(')').and_then(|k| k.parse().ok()) {
            return (file, Some(k));
        }
    }
    (s, None)
}

/// The format `path`'s extension names, if any.
fn format_of(path: &Path) -> Option<FileFormat> {
    FileFormat::from_path(path).ok()
}

/// Whether `path` is what [`open`] reads: a directory, or a `.ktx2` / `.dds`
/// file (a chain if it has more than one level or a manifest names it).
#[cfg_attr(not(feature = "instruments"), allow(dead_code))]
#[cfg_attr(feature = "instruments", visibility::make(pub))]
#[must_use]
pub(crate) fn is_candidate(path: &Path) -> bool {
    path.is_dir() || matches!(format_of(path), Some(FileFormat::Ktx2 | FileFormat::Dds))
}

/// The lit maps at `path`; see the [module docs](crate::bake). `Ok(None)` when
/// `path` is a texture file of one level that no manifest names: an
/// environment to bake from, not a chain. `axes` are the cube files' axes
/// where nothing says them (a chain file alone; default envmap's).
///
/// # Errors
///
/// A directory without `manifest.json`; a manifest that is not JSON or
/// lacks the specular levels, their roughness, or both the irradiance map
/// and `sh.json` (a bake with `--sh-only`); a KTX 1 chain; any file
/// that cannot be read; levels in different axes or of decreasing
/// roughness; [`Error::Cancelled`].
pub fn open(
    path: &Path,
    axes: Option<FileAxes>,
    max_texels: u64,
    cancel: Option<&AtomicBool>,
) -> Result<Option<OpenedLit>> {
    match manifest_for(path) {
        Some(m) => from_manifest(&m, axes, max_texels, cancel).map(Some),
        None => alone(path, axes, max_texels, cancel),
    }
}

fn bad(path: &Path, message: impl Into<String>) -> Error {
    Error::Decode {
        path: path.to_path_buf(),
        format: "envmap bake manifest",
        message: message.into(),
    }
}

/// The frame a manifest states, if it does.
fn manifest_frame(m: &Value) -> Option<Frame> {
    let cols = m["frame_to_canonical"].as_array()?;
    if cols.len() != 3 {
        return None;
    }
    let col = |c: &Value| -> Option<Vec3> {
        let a = c.as_array()?;
        (a.len() == 3).then_some(())?;
        Some(Vec3::new(
            a[0].as_f64()? as f32,
            a[1].as_f64()? as f32,
            a[2].as_f64()? as f32,
        ))
    };
    Frame::from_mat3(Mat3::from_cols(
        col(&cols[0])?,
        col(&cols[1])?,
        col(&cols[2])?,
    ))
}

/// Loads one map the manifest names: an OpenEXR file (its tags say its
/// layout and axes; `frame` overrides them when the manifest states it), or
/// level `level` of a texture file in `frame` (or `axes`).
struct Files<'a> {
    dir: PathBuf,
    manifest: &'a Path,
    frame: Option<Frame>,
    axes: Option<FileAxes>,
    max_texels: u64,
    cancel: Option<&'a AtomicBool>,
    /// The last texture file read, kept for its other levels.
    texture: Option<(PathBuf, texture::TextureFile)>,
}

impl Files<'_> {
    fn load(&mut self, entry: &str) -> Result<EnvImage> {
        let (file, level) = chain_file(entry);
        let path = self.dir.join(file);
        if format_of(&path) == Some(FileFormat::Ktx) {
            return Err(bad(
                self.manifest,
                format!("{file}: KTX 1 files (Filament's) are written, not read; bake again with --container ktx2 or exr"),
            ));
        }
        let frame = self
            .frame
            .or_else(|| self.axes.map(|a| a.frame(AnyMapping::Cube)));
        if format_of(&path).is_some_and(FileFormat::is_texture) {
            let t = match self.texture.take() {
                Some((p, t)) if p == path => t,
                _ => texture::read(&path, self.max_texels, self.cancel)?,
            };
            let Some(frame) = frame else {
                return Err(bad(
                    self.manifest,
                    "it does not state the files' axes (frame_to_canonical; written by envmap 0.1.0 from this version on): give them with --convention / --frame",
                ));
            };
            let image = t
                .texture
                .level_image(level.unwrap_or(0), Some(AnyMapping::Cube), |_| frame)
                .map_err(|e| e.in_file(&path));
            self.texture = Some((path, t));
            return image;
        }
        let opts = LoadOptions {
            axes: frame.map(FileAxes::Frame).or(self.axes),
            max_texels: self.max_texels,
            cancel: self.cancel,
            ..LoadOptions::default()
        };
        Ok(load_detailed(&path, &opts)?.image)
    }
}

fn from_manifest(
    manifest: &Path,
    axes: Option<FileAxes>,
    max_texels: u64,
    cancel: Option<&AtomicBool>,
) -> Result<OpenedLit> {
    let text = std::fs::read_to_string(manifest).map_err(|e| {
        if e.kind() == std::io::ErrorKind::NotFound {
            bad(
                manifest,
                "no such file: not a directory `envmap bake` wrote (or give the environment itself)",
            )
        } else {
            Error::read(manifest, e)
        }
    })?;
    let m: Value = serde_json::from_str(&text).map_err(|e| bad(manifest, e.to_string()))?;
    let levels = m["specular"]["levels"]
        .as_array()
        .filter(|l| !l.is_empty())
        .ok_or_else(|| {
            bad(
                manifest,
                "no specular levels (a bake with --sh-only?): bake the chain first",
            )
        })?;
    let dir = manifest
        .parent()
        .map_or_else(PathBuf::new, Path::to_path_buf);
    let mut files = Files {
        dir,
        manifest,
        frame: manifest_frame(&m),
        axes,
        max_texels,
        cancel,
        texture: None,
    };
    let mut images = Vec::with_capacity(levels.len());
    let mut roughness = Vec::with_capacity(levels.len());
    for (k, l) in levels.iter().enumerate() {
        let (Some(file), Some(r)) = (l["file"].as_str(), l["perceptual_roughness"].as_f64()) else {
            return Err(bad(
                manifest,
                format!("specular level {k} lacks its file or perceptual_roughness"),
            ));
        };
        images.push(files.load(file)?);
        roughness.push(r as f32);
    }
    let irr = &m["irradiance"];
    let (irradiance, scale, irr_file, value) =
        match (irr["file"].as_str(), irr["value"].as_str()) {
            (Some(irr_file), Some(value)) => {
                let scale = match value {
                    "E" => IrradianceScale::E,
                    "E/pi" => IrradianceScale::EOverPi,
                    other => {
                        return Err(bad(
                            manifest,
                            format!("irradiance value '{other}': expected E or E/pi"),
                        ))
                    }
                };
                (files.load(irr_file)?, scale, irr_file, value)
            }
            _ => match m["sh"]["file"].as_str() {
                // The engines that light by SH alone (Babylon.js, glTF
                // lights): the irradiance of the SH the bake wrote.
                Some(sh_file) => (
                    sh_irradiance(&files.dir.join(sh_file), images[0].representation().frame)?,
                    IrradianceScale::EOverPi,
                    sh_file,
                    "E/pi from the SH",
                ),
                None => return Err(bad(
                    manifest,
                    "no irradiance map and no SH (a bake with --irradiance-size 0 and no sh.json?)",
                )),
            },
        };
    let dfg_size = m["dfg"]["size"]
        .as_u64()
        .and_then(|s| u32::try_from(s).ok())
        .unwrap_or(DEFAULT_DFG_SIZE);
    let dfg = DfgTable::on_grid(dfg_size.max(2), DfgGrid::Edges, cancel).map_err(|e| match e {
        Error::Cancelled => e,
        e => bad(manifest, format!("dfg size {dfg_size}: {e}")),
    })?;
    let description = format!(
        "{}: {} specular levels ({}² … {}², roughness {} … {}), irradiance {} ({}), DFG {}²",
        manifest.display(),
        images.len(),
        images[0].cell_size().0,
        images[images.len() - 1].cell_size().0,
        roughness[0],
        roughness[roughness.len() - 1],
        irr_file,
        value,
        dfg_size
    );
    let env = LitEnvironment::new(images, roughness, irradiance, scale, dfg)
        .map_err(|e| bad(manifest, e.to_string()))?;
    Ok(OpenedLit { env, description })
}

/// The irradiance (E/π) of the radiance SH in `sh.json` at `path`
/// (`canonical_radiance`, envmap's axes), as a cube of
/// [`DEFAULT_IRRADIANCE_SIZE`]² in the axes `frame`.
fn sh_irradiance(path: &Path, frame: Frame) -> Result<EnvImage> {
    let bad = |message: String| Error::Decode {
        path: path.to_path_buf(),
        format: "envmap sh.json",
        message,
    };
    let text = std::fs::read_to_string(path).map_err(|e| Error::read(path, e))?;
    let v: Value = serde_json::from_str(&text).map_err(|e| bad(e.to_string()))?;
    let c = &v["canonical_radiance"]["coefficients"];
    let mut sh = Sh9::default();
    for (i, name) in crate::filter::sh::NAMES.iter().enumerate() {
        for ch in 0..3 {
            sh.coeffs[i][ch] = c[*name][ch].as_f64().ok_or_else(|| {
                bad(format!(
                    "canonical_radiance.coefficients.{name} lacks three numbers"
                ))
            })?;
        }
    }
    let repr = Representation::new(
        AnyMapping::Cube,
        envmap_core::Atlas::CUBE_HORIZONTAL_STRIP,
        frame,
    )?;
    irradiance_map(
        &sh,
        repr,
        6 * DEFAULT_IRRADIANCE_SIZE,
        DEFAULT_IRRADIANCE_SIZE,
        IrradianceScale::EOverPi,
    )
}

/// A chain file with no manifest naming it; see the [module docs](self).
fn alone(
    path: &Path,
    axes: Option<FileAxes>,
    max_texels: u64,
    cancel: Option<&AtomicBool>,
) -> Result<Option<OpenedLit>> {
    if !matches!(format_of(path), Some(FileFormat::Ktx2 | FileFormat::Dds)) {
        return Ok(None);
    }
    let t = texture::read(path, max_texels, cancel)?;
    let n = t.texture.level_count();
    if n < 2 {
        return Ok(None);
    }
    if t.texture.kind() != texture::TextureKind::Cube {
        return Err(Error::Decode {
            path: path.to_path_buf(),
            format: format_of(path).map_or("texture", FileFormat::name),
            message: format!(
                "{n} levels of a 2D texture: a specular chain is read from a cube map"
            ),
        });
    }
    let frame = axes.unwrap_or_default().frame(AnyMapping::Cube);
    let images = (0..n)
        .map(|k| {
            t.texture
                .level_image(k, Some(AnyMapping::Cube), |_| frame)
                .map_err(|e| e.in_file(path))
        })
        .collect::<Result<Vec<_>>>()?;
    let roughness = (0..n)
        .map(|k| RoughnessRule::Linear.roughness(k, n))
        .collect();
    crate::cancel::check(cancel)?;
    let sh = Sh9::project(&images[0]);
    let repr = Representation::new(
        AnyMapping::Cube,
        envmap_core::Atlas::CUBE_HORIZONTAL_STRIP,
        frame,
    )?;
    let irradiance = irradiance_map(
        &sh,
        repr,
        6 * DEFAULT_IRRADIANCE_SIZE,
        DEFAULT_IRRADIANCE_SIZE,
        IrradianceScale::EOverPi,
    )?;
    let dfg = DfgTable::on_grid(DEFAULT_DFG_SIZE, DfgGrid::Edges, cancel)?;
    let description = format!(
        "{}: {n} levels ({}² … {}²) with no manifest naming them: level k taken at roughness k/{} (the linear rule); irradiance from level 0's SH9; DFG {DEFAULT_DFG_SIZE}²",
        path.display(),
        images[0].cell_size().0,
        images[n - 1].cell_size().0,
        n - 1
    );
    let env = LitEnvironment::new(images, roughness, irradiance, IrradianceScale::EOverPi, dfg)?;
    Ok(Some(OpenedLit { env, description }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn level_entries_read_back() {
        assert_eq!(
            chain_file(&level_entry("specular.ktx2", 3)),
            ("specular.ktx2", Some(3))
        );
        assert_eq!(chain_file("specular_3.exr"), ("specular_3.exr", None));
        assert_eq!(chain_file("odd (level x)"), ("odd (level x)", None));
    }
}
