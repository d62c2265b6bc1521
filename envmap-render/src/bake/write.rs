//! The bake directory's writer: every file of a [`Bake`] as a [`Preset`]
//! names it, staged into one [`Outputs`] run: to a directory together
//! ([`write()`]) or into memory ([`in_memory`]), by the same code.

use std::path::{Path, PathBuf};
use std::sync::{Mutex, PoisonError};
use std::time::Instant;

use super::manifest::{dfg_axes, filament_sh_key, filament_sh_txt, manifest, sh_json, Lossy};
use super::preset::{Preset, Target};
use crate::error::{Error, Result};
use crate::filter::bake::{
    bake_owned, bake_owned_streaming, chain_sizes, Bake, BakeOptions, LevelReport,
};
use crate::filter::dfg::DfgTable;
use crate::filter::sh::IrradianceScale;
use crate::image::io::{ExrPrecision, SaveOptions};
use crate::image::texture::{Texture, TextureKind, TextureOptions, Upload};
use crate::image::{Clamped, EnvImage, FileFormat, MemoryFile, Outputs};

/// Where a bake came from, for its manifest.
#[derive(Clone, Debug, Default, PartialEq)]
#[non_exhaustive]
pub struct Provenance {
    /// The input, as a user would name it (a file, or a built-in).
    pub input: String,
    /// Seconds spent loading it.
    pub load_seconds: f64,
    /// Seconds the bake took.
    pub bake_seconds: f64,
}

impl Provenance {
    /// `input` with no timings.
    #[must_use]
    pub fn new(input: impl Into<String>) -> Self {
        Self {
            input: input.into(),
            ..Self::default()
        }
    }
}

/// What [`Baked::write`](super::Baked::write) wrote.
#[derive(Clone, Debug, Default)]
pub struct Written {
    /// The files, in the order they were staged.
    pub files: Vec<PathBuf>,
    /// Per texture file, what packing its texel format clamped.
    pub clamped: Vec<(PathBuf, Clamped)>,
}

/// What [`Baked::files`](super::Baked::files) made: the files
/// [`Baked::write`](super::Baked::write) would have written to a directory,
/// each by its name in that directory.
#[derive(Clone, Debug, Default)]
pub struct BakeFiles {
    /// Each file: its name in the directory and its bytes.
    pub files: Vec<MemoryFile>,
    /// Per texture file, what packing its texel format clamped.
    pub clamped: Vec<(PathBuf, Clamped)>,
}

impl BakeFiles {
    /// The bytes of the file named `name` (as in the directory: `specular.ktx2`).
    #[must_use]
    pub fn get(&self, name: &str) -> Option<&[u8]> {
        self.files
            .iter()
            .find(|f| f.path.file_name().is_some_and(|n| n == name))
            .map(|f| f.bytes.as_slice())
    }
}

/// Writes every file of `bake` into directory `dir` (created if missing,
/// removed again if it was created and a write fails), all renamed into
/// place together at the end ([`Outputs`]); `save`'s inputs are never
/// overwritten and its cancel flag stops the run. The files: the chain,
/// the irradiance map, the DFG tables, `sh.json`, `manifest.json`, and
/// for KTX 1 Filament's `<dir>_ibl.ktx`, `<dir>_skybox.ktx` and `sh.txt`
/// (see the [module docs](super)).
///
/// # Errors
///
/// The preset's [`Preset::check`]; the directory cannot be made; any
/// encoding or write error (nothing is left half-written);
/// [`Error::Cancelled`].
pub(crate) fn write(
    dir: &Path,
    bake: &Bake,
    opts: &BakeOptions,
    preset: &Preset,
    provenance: &Provenance,
    save: &SaveOptions,
) -> Result<Written> {
    in_new_dir(dir, preset, || {
        let mut run = Outputs::new(save);
        let clamped =
            Files::new(dir, opts, preset, save).stage(&mut run, bake, provenance, false)?;
        let files = run.commit()?;
        Ok(Written { files, clamped })
    })
}

/// What [`bake_into`] made and how long it took.
#[derive(Clone, Debug)]
#[non_exhaustive]
pub(crate) struct BakedInto {
    /// The bake.
    pub bake: Bake,
    /// The files written.
    pub written: Written,
    /// Seconds of the bake, the levels' files written beside it included
    /// (the manifest's `bake_seconds`).
    pub bake_seconds: f64,
    /// Seconds after the bake: the other files staged, all renamed into
    /// place.
    pub write_seconds: f64,
}

/// Bakes `src` ([`bake_owned`]) and writes every file of the bake into
/// `dir` as [`write()`] writes them, an OpenEXR chain's levels each while
/// the next is made ([`bake_owned_streaming`]): the levels' files are
/// written beside the bake instead of after it, so that writing them adds
/// little to the bake's time (`docs/performance.md`). Returns the bake and
/// what was written ([`BakedInto`]); the manifest's bake time (`provenance.bake_seconds`) is
/// measured here, the levels' files written beside it included. The bake
/// is [`bake_owned`]'s, bit for bit, and the files are [`write()`]'s (an
/// OpenEXR file's header attributes in the order the `exr` crate writes
/// them, which changes from run to run); as there, nothing is left
/// half-written when the bake or a write fails or is cancelled
/// (`opts.cancel`, `save.cancel`).
///
/// # Errors
///
/// As [`bake_owned`] and [`write()`].
pub(crate) fn bake_into(
    dir: &Path,
    src: EnvImage,
    opts: &BakeOptions,
    preset: &Preset,
    provenance: &Provenance,
    save: &SaveOptions,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<BakedInto> {
    let n = chain_sizes(opts)?.len();
    in_new_dir(dir, preset, || {
        let files = Files::new(dir, opts, preset, save);
        let run = Mutex::new(Outputs::new(save));
        let streams = preset.container == FileFormat::Exr;
        let sink = |k: usize, level: &EnvImage, report: &LevelReport| {
            let mut run = run.lock().unwrap_or_else(PoisonError::into_inner);
            files.stage_level(&mut run, (k, n), level, report)
        };
        let t = Instant::now();
        let bake = if streams {
            bake_owned_streaming(src, opts, progress, &sink)?
        } else {
            bake_owned(src, opts, progress)?
        };
        let bake_seconds = t.elapsed().as_secs_f64();
        let t = Instant::now();
        let provenance = Provenance {
            bake_seconds,
            ..provenance.clone()
        };
        let mut run = run.into_inner().unwrap_or_else(PoisonError::into_inner);
        let clamped = files.stage(&mut run, &bake, &provenance, streams)?;
        let files = run.commit()?;
        Ok(BakedInto {
            bake,
            written: Written { files, clamped },
            bake_seconds,
            write_seconds: t.elapsed().as_secs_f64(),
        })
    })
}

/// `write_files` run for directory `dir` (created if missing, removed again
/// if it was created and `write_files` fails), after the preset's check.
fn in_new_dir<T>(
    dir: &Path,
    preset: &Preset,
    write_files: impl FnOnce() -> Result<T>,
) -> Result<T> {
    preset.check()?;
    let created = !dir.exists();
    std::fs::create_dir_all(dir).map_err(|e| Error::write(dir, e))?;
    let result = write_files();
    if result.is_err() && created {
        let _ = std::fs::remove_dir(dir);
    }
    result
}

/// The files [`write()`] writes to a directory named `dir` (whose name gives
/// KTX 1 files theirs, as cmgen's), made in memory: nothing on disk is read
/// or written. Their bytes equal the files' (the same encoders, through
/// [`Outputs::in_memory`]).
///
/// # Errors
///
/// As [`write()`], but for the file system's.
pub(crate) fn in_memory(
    dir: &Path,
    bake: &Bake,
    opts: &BakeOptions,
    preset: &Preset,
    provenance: &Provenance,
) -> Result<BakeFiles> {
    preset.check()?;
    let mut run = Outputs::in_memory(opts.cancel);
    let save = SaveOptions {
        cancel: opts.cancel,
        ..SaveOptions::default()
    };
    let clamped = Files::new(dir, opts, preset, &save).stage(&mut run, bake, provenance, false)?;
    let name = |p: PathBuf| p.strip_prefix(dir).map(Path::to_path_buf).unwrap_or(p);
    let files = run
        .into_memory()?
        .into_iter()
        .map(|f| MemoryFile {
            path: name(f.path),
            bytes: f.bytes,
        })
        .collect();
    let clamped = clamped.into_iter().map(|(p, c)| (name(p), c)).collect();
    Ok(BakeFiles { files, clamped })
}

/// A bake's maps as an engine uploads them, in the preset's texel format.
#[derive(Clone, Debug)]
pub struct EngineTextures {
    /// The specular chain: a cube, level k at the preset rule's roughness
    /// for k (the manifest's `perceptual_roughness`).
    pub specular: Option<Upload>,
    /// The irradiance cube (E/π unless the bake's options say E).
    pub irradiance: Option<Upload>,
}

/// The texels of `bake`'s chain and irradiance map in `preset.texture`'s
/// format, per level and face, as [`Texture::upload`] lays them out (the
/// cube in the bake's axes: `preset.axes`); no file is made. The format's
/// Vulkan, wgpu and DXGI names are on [`crate::image::TexelFormat`].
///
/// # Errors
///
/// Levels that do not make a texture (a chain that does not halve).
pub(crate) fn engine_textures(bake: &Bake, preset: &Preset) -> Result<EngineTextures> {
    let format = preset.texture.format;
    let upload = |levels: &[EnvImage]| Texture::from_env(levels).map(|t| t.upload(format));
    Ok(EngineTextures {
        specular: bake.chain.as_ref().map(|c| upload(&c.levels)).transpose()?,
        irradiance: bake
            .irradiance
            .as_ref()
            .map(|i| upload(std::slice::from_ref(&i.image)))
            .transpose()?,
    })
}

/// A KTX 1 file with key/value pairs (cmgen's `sh`).
fn ktx1_with_keys(
    tex: &Texture,
    preset: &Preset,
    kv: &[(&str, &[u8])],
    path: &Path,
) -> Result<(Vec<u8>, Clamped)> {
    #[cfg(feature = "ktx1")]
    {
        crate::image::ktx1::encode(tex, preset.texture.format, kv).map_err(|e| e.in_file(path))
    }
    #[cfg(not(feature = "ktx1"))]
    {
        let _ = (tex, preset, kv);
        FileFormat::Ktx
            .codec(path)
            .map(|_| (Vec::new(), Clamped::default()))
    }
}

/// The files of one bake directory: where, how baked, in what preset,
/// saved how; what stages them.
struct Files<'p> {
    dir: &'p Path,
    opts: &'p BakeOptions<'p>,
    preset: &'p Preset,
    /// The options of the image files (the preset's six files or not).
    save: SaveOptions<'p>,
}

impl<'p> Files<'p> {
    fn new(
        dir: &'p Path,
        opts: &'p BakeOptions<'p>,
        preset: &'p Preset,
        save: &SaveOptions<'p>,
    ) -> Self {
        Self {
            dir,
            opts,
            preset,
            save: SaveOptions {
                six_files: preset.layout.is_six_files(),
                ..save.clone()
            },
        }
    }

    /// Stages an image of an OpenEXR bake (a level, the irradiance map) in
    /// the preset's layout, described by `content`. An image in another
    /// atlas is written from its faces as the writer asks for rows: no copy
    /// of it is made.
    fn stage_exr(
        &self,
        run: &mut Outputs<'_>,
        img: &EnvImage,
        stem: &str,
        content: String,
    ) -> Result<()> {
        let o = SaveOptions {
            content: Some(content),
            ..self.save.clone()
        };
        let path = self.dir.join(file_name(self.preset, stem));
        let atlas = self.preset.layout.atlas();
        if self.preset.layout.is_six_files() || img.representation().atlas == atlas {
            run.stage_image(img, path, &o)
        } else {
            run.stage_streamed(&img.in_atlas(atlas)?, path, &o)
        }
    }

    /// Stages level `k` of `n` of an OpenEXR bake's chain.
    fn stage_level(
        &self,
        run: &mut Outputs<'_>,
        (k, n): (usize, usize),
        level: &EnvImage,
        report: &LevelReport,
    ) -> Result<()> {
        let content = format!(
            "GGX-prefiltered radiance (split sum, N = V = R): level {k} of {n}, perceptual roughness {:.4} (alpha = roughness^2), rule {}",
            report.roughness,
            self.opts.rule.name()
        );
        self.stage_exr(run, level, &format!("specular_{k}"), content)
    }

    /// Stages every file of `bake` into `run`, each at `dir`/name, but for
    /// an OpenEXR chain's levels when `levels_staged` (they were, as they
    /// were made: [`bake_into`]); returns what packing clamped per texture
    /// file.
    fn stage(
        &self,
        run: &mut Outputs<'_>,
        bake: &Bake,
        provenance: &Provenance,
        levels_staged: bool,
    ) -> Result<Vec<(PathBuf, Clamped)>> {
        let (dir, opts, preset) = (self.dir, self.opts, self.preset);
        let mut lossy = Vec::new();
        let clamped_total = if preset.container == FileFormat::Exr {
            self.stage_exr_maps(run, bake, levels_staged)?;
            Vec::new()
        } else {
            self.stage_textures(run, bake, &mut lossy)?
        };
        if let Some(t) = &bake.dfg {
            self.stage_dfg(run, t)?;
        }
        run.stage_bytes(
            dir.join("sh.json"),
            sh_json(preset, bake, opts.axes).as_bytes(),
        )?;
        run.stage_bytes(
            dir.join("manifest.json"),
            manifest(dir, preset, provenance, bake, opts, &lossy).as_bytes(),
        )?;
        Ok(clamped_total)
    }

    /// Stages an OpenEXR bake's images: the chain's levels (unless
    /// `levels_staged`) and the irradiance map, each described by what it
    /// holds.
    fn stage_exr_maps(
        &self,
        run: &mut Outputs<'_>,
        bake: &Bake,
        levels_staged: bool,
    ) -> Result<()> {
        if let Some(chain) = bake.chain.as_ref().filter(|_| !levels_staged) {
            let n = chain.levels.len();
            for (k, (level, r)) in chain.levels.iter().zip(&chain.reports).enumerate() {
                self.stage_level(run, (k, n), level, r)?;
            }
        }
        if let Some(irr) = &bake.irradiance {
            let content = match self.opts.irradiance_scale {
                IrradianceScale::EOverPi => {
                    "irradiance E/pi (the radiance a white Lambertian surface reflects)".to_owned()
                }
                IrradianceScale::E => "irradiance E (not divided by pi)".to_owned(),
            };
            self.stage_exr(run, &irr.image, "irradiance", content)?;
        }
        Ok(())
    }

    /// Stages a texture container's files (KTX 1, KTX2, DDS): the
    /// specular chain, KTX 1's skybox, the irradiance map, KTX 1's
    /// `sh.txt` and glTF's LUT; returns what packing clamped per file.
    fn stage_textures(
        &self,
        run: &mut Outputs<'_>,
        bake: &Bake,
        lossy: &mut Vec<Lossy>,
    ) -> Result<Vec<(PathBuf, Clamped)>> {
        let (dir, preset) = (self.dir, self.preset);
        let mut clamped_total: Vec<(PathBuf, Clamped)> = Vec::new();
        let ext = preset.container.extension();
        let sh_key = filament_sh_key(bake, preset);
        if matches!(preset.container, FileFormat::Env | FileFormat::Gltf) {
            // One file: the chain, with the irradiance polynomial inside.
            if let Some(chain) = &bake.chain {
                let name = texture_name(dir, preset, preset.specular);
                clamped_total.push(self.stage_env(run, bake, &chain.levels, &name, lossy)?);
            }
            return Ok(clamped_total);
        }
        if let Some(chain) = &bake.chain {
            let kv: Vec<(&str, &[u8])> = if preset.container == FileFormat::Ktx {
                vec![("sh", sh_key.as_bytes())]
            } else {
                Vec::new()
            };
            let name = texture_name(dir, preset, preset.specular);
            clamped_total.push(self.stage_texture_file(run, &chain.levels, &name, &kv, lossy)?);
            if preset.container == FileFormat::Ktx {
                let name = texture_name(dir, preset, "skybox");
                let c = self.stage_texture_file(run, &chain.levels[..1], &name, &[], lossy)?;
                clamped_total.push(c);
            }
        }
        if let Some(irr) = &bake.irradiance {
            let name = texture_name(dir, preset, preset.irradiance);
            let levels = std::slice::from_ref(&irr.image);
            clamped_total.push(self.stage_texture_file(run, levels, &name, &[], lossy)?);
        }
        if preset.container == FileFormat::Ktx {
            run.stage_bytes(dir.join("sh.txt"), filament_sh_txt(bake, preset).as_bytes())?;
        }
        if let (Some(t), Some(Target::Gltf)) = (&bake.dfg, preset.target) {
            // glTF-IBL-Sampler's LUT: R = scale, G = bias, N·V across,
            // roughness down (row 0 = roughness 0.5/size, or 0 on the edges
            // grid: the manifest's `dfg.grid`). A table is not compressed:
            // with BC6H maps it is RGBA16F.
            let lut = Texture::new(TextureKind::Flat, vec![vec![t.single_scatter_image()]])?;
            let path = dir.join(format!("lut_ggx.{ext}"));
            let format = match preset.texture.format {
                crate::image::TexelFormat::Bc6h => crate::image::TexelFormat::Rgba16f,
                f => f,
            };
            let c = run.stage_texture(
                &lut,
                &path,
                TextureOptions {
                    format,
                    zstd: None,
                    ..preset.texture
                },
            )?;
            clamped_total.push((path, c));
        }
        Ok(clamped_total)
    }

    /// Stages `levels` as the texture file `name` in the preset's
    /// container (KTX 1 with the key/value pairs `kv`); returns its path
    /// and what packing clamped.
    fn stage_texture_file(
        &self,
        run: &mut Outputs<'_>,
        levels: &[EnvImage],
        name: &str,
        kv: &[(&str, &[u8])],
        lossy: &mut Vec<Lossy>,
    ) -> Result<(PathBuf, Clamped)> {
        let preset = self.preset;
        let tex = Texture::from_env(levels)?;
        let path = self.dir.join(name);
        let clamped = if preset.container == FileFormat::Ktx {
            let (bytes, c) = ktx1_with_keys(&tex, preset, kv, &path)?;
            run.stage_bytes(&path, &bytes)?;
            c
        } else if preset.texture.format == crate::image::TexelFormat::Bc6h {
            // Lossy: the bytes written are read back (the texels decoded by
            // bcdec_rs) and measured against the levels.
            let (bytes, c) = crate::image::texture::encode(&tex, &path, preset.texture)?;
            run.stage_bytes(&path, &bytes)?;
            #[cfg(feature = "bc6h")]
            {
                let back = crate::image::texture::decode(&path, &bytes, u64::MAX)?;
                lossy.push(Lossy {
                    file: name.to_owned(),
                    levels: crate::image::lossy::measure(
                        &back.texture,
                        &tex,
                        crate::image::TexelFormat::Bc6h.max_value(),
                    ),
                    clipped: Vec::new(),
                });
            }
            #[cfg(not(feature = "bc6h"))]
            let _ = &lossy;
            c
        } else {
            run.stage_texture(&tex, &path, preset.texture)?
        };
        Ok((path, clamped))
    }

    /// Stages the chain `levels` as the Babylon.js `.env` file `name`, with
    /// the irradiance polynomial of the bake's SH (in the cube's axes), or
    /// as a glTF image-based light with that SH; measures what RGBD lost:
    /// the energy above the file's ceiling counted, and each level as the
    /// file holds it (a `.env` read back; a glTF light's PNGs decoded and
    /// raised to 2.2, as Babylon.js shows them) compared with the levels.
    fn stage_env(
        &self,
        run: &mut Outputs<'_>,
        bake: &Bake,
        levels: &[EnvImage],
        name: &str,
        lossy: &mut Vec<Lossy>,
    ) -> Result<(PathBuf, Clamped)> {
        let path = self.dir.join(name);
        #[cfg(feature = "babylon")]
        {
            use crate::image::babylon;
            let tex = Texture::from_env(levels)?;
            let sh = match self.preset.sh_window {
                Some(w) => bake.sh.windowed(w),
                None => bake.sh,
            }
            .in_frame(self.opts.axes.frame(envmap_core::AnyMapping::Cube));
            let gltf = self.preset.container == FileFormat::Gltf;
            let e = if gltf {
                babylon::encode_gltf(&tex, &sh)
            } else {
                babylon::encode(&tex, &sh, babylon::DEFAULT_LOD_SCALE)
            }
            .map_err(|e| e.in_file(&path))?;
            run.stage_bytes(&path, &e.bytes)?;
            let back = match e.seen {
                Some(seen) => seen,
                None => crate::image::texture::decode(&path, &e.bytes, u64::MAX)?.texture,
            };
            lossy.push(Lossy {
                file: name.to_owned(),
                levels: crate::image::lossy::measure(&back, &tex, babylon::ceiling(gltf)),
                clipped: e.clipped,
            });
            Ok((path, e.clamped))
        }
        #[cfg(not(feature = "babylon"))]
        {
            let _ = (run, bake, levels, lossy);
            self.preset
                .container
                .codec(&path)
                .map(|_| (path.clone(), Clamped::default()))
        }
    }

    /// Stages the DFG table's two OpenEXR files (single scatter and
    /// Filament's multiscatter form) in f32, each described with its axes.
    fn stage_dfg(&self, run: &mut Outputs<'_>, t: &DfgTable) -> Result<()> {
        let (x, y) = dfg_axes(t);
        let axes = format!("{x}, {y}; height-correlated Smith GGX");
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
                ..self.save.clone()
            };
            run.stage_rgb(&image, self.dir.join(file), &o)?;
        }
        Ok(())
    }
}

/// The file of a texture container: `<stem>.<ext>`, or for KTX 1 (cmgen's
/// names) `<dir>_<stem>.ktx` with `<dir>` the output directory's name
/// without its extension.
pub(super) fn texture_name(dir: &Path, preset: &Preset, stem: &str) -> String {
    let ext = preset.container.extension();
    if preset.container == FileFormat::Ktx {
        let dir = dir
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
pub(super) fn level_file(dir: &Path, preset: &Preset, k: usize) -> String {
    if preset.container == FileFormat::Exr {
        file_name(preset, &format!("specular_{k}"))
    } else {
        super::read::level_entry(&texture_name(dir, preset, preset.specular), k)
    }
}

/// A file's name in the output directory (`{face}` for six files).
pub(super) fn file_name(preset: &Preset, stem: &str) -> String {
    if preset.layout.is_six_files() {
        format!("{stem}_{{face}}.exr")
    } else {
        format!("{stem}.exr")
    }
}
