//! The bake directory's writer: every file of a [`Bake`] as a [`Preset`]
//! names it, staged into one [`Outputs`] run: to a directory together
//! ([`write()`]) or into memory ([`in_memory`]), by the same code.

use std::path::{Path, PathBuf};
use std::sync::{Mutex, PoisonError};
use std::time::Instant;

use envmap_core::AnyMapping;

use super::preset::{Preset, Target};
use crate::error::{Error, Result};
use crate::filter::bake::{
    bake_owned, bake_owned_streaming, chain_sizes, Bake, BakeOptions, Irradiance, LevelReport,
    SpecularChain,
};
use crate::filter::dfg::{DfgGrid, DfgTable};
use crate::filter::sh::{IrradianceScale, NAMES};
use crate::image::convention::FileAxes;
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
            .in_frame(self.opts.axes.frame(AnyMapping::Cube));
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
fn texture_name(dir: &Path, preset: &Preset, stem: &str) -> String {
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
fn level_file(dir: &Path, preset: &Preset, k: usize) -> String {
    if preset.container == FileFormat::Exr {
        file_name(preset, &format!("specular_{k}"))
    } else {
        super::read::level_entry(&texture_name(dir, preset, preset.specular), k)
    }
}

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
pub(crate) fn filament_sh_key(b: &Bake, preset: &Preset) -> String {
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
pub(crate) fn filament_sh_txt(b: &Bake, preset: &Preset) -> String {
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

/// A file's name in the output directory (`{face}` for six files).
fn file_name(preset: &Preset, stem: &str) -> String {
    if preset.layout.is_six_files() {
        format!("{stem}_{{face}}.exr")
    } else {
        format!("{stem}.exr")
    }
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
pub(crate) fn sh_json(preset: &Preset, b: &Bake, axes: FileAxes) -> String {
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
pub(crate) fn manifest(
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
pub(crate) struct Lossy {
    /// The file's name in the bake's directory.
    file: String,
    /// Each level's error, the file's texels decoded against the levels.
    #[cfg(any(feature = "bc6h", feature = "babylon"))]
    levels: Vec<crate::image::lossy::LevelError>,
    /// RGBD: each level's fraction of its energy above 255 (empty for
    /// BC6H).
    #[cfg_attr(not(any(feature = "bc6h", feature = "babylon")), allow(dead_code))]
    clipped: Vec<f64>,
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
fn dfg_axes(t: &DfgTable) -> (String, String) {
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
