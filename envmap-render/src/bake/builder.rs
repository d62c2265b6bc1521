//! The one way to bake: [`Baker`] chooses the target once, takes any
//! overrides, bakes an input given by value or by reference, and gives a
//! [`Baked`] that writes a directory, gives the files in memory, or gives
//! the textures ready to upload, always with the options it was baked with.

use std::borrow::Cow;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

use super::preset::{Preset, Target};
use super::write::{self, BakeFiles, EngineTextures, Provenance, Written};
use crate::error::Result;
use crate::filter::bake::{Bake, BakeOptions, Quality};
use crate::filter::specular::RoughnessRule;
use crate::image::io::SaveOptions;
use crate::image::{EnvImage, FileAxes};

/// Progress of a bake: `(level, levels)` as each level of the specular
/// chain starts, from any of the bake's threads.
pub type Progress<'a> = &'a (dyn Fn(usize, usize) + Sync);

/// A bake, set up: the target chosen once ([`Baker::new`],
/// [`Baker::for_target`] or a whole [`Preset`] with [`Baker::with_preset`]),
/// then any override, then [`Baker::bake`] (or [`Baker::bake_into`], which
/// writes each file while the bake goes on).
///
/// ```
/// use envmap_render::bake::{Baker, Target};
/// use envmap_render::scene::{fill, smooth};
/// use envmap_render::image::Representation;
/// use envmap_core::AnyMapping;
///
/// let hdri = fill(Representation::default_for(AnyMapping::LatLong), 128, 64, smooth)?;
/// let baked = Baker::for_target(Target::Bevy).size(16).bake(&hdri)?;
/// let files = baked.files("ibl")?;
/// assert_eq!(&files.get("specular.ktx2").expect("the chain")[..12], b"\xABKTX 20\xBB\r\n\x1A\n");
/// let textures = baked.textures()?;
/// assert_eq!(textures.specular.expect("a chain").levels.len(), 4);
/// # Ok::<(), envmap_render::Error>(())
/// ```
#[derive(Clone)]
#[must_use]
pub struct Baker<'a> {
    preset: Preset,
    options: BakeOptions<'a>,
    save: SaveOptions<'a>,
    progress: Option<Progress<'a>>,
    provenance: Provenance,
}

impl std::fmt::Debug for Baker<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Baker")
            .field("preset", &self.preset)
            .field("options", &self.options)
            .field("provenance", &self.provenance)
            .finish_non_exhaustive()
    }
}

impl Default for Baker<'_> {
    fn default() -> Self {
        Self::new()
    }
}

impl<'a> Baker<'a> {
    /// envmap's own bake ([`Preset::default`]): a 512² chain by the linear
    /// rule, one OpenEXR cross per level, a 32² irradiance cube of E/π, the
    /// DFG table, in the GL world.
    pub fn new() -> Self {
        Self::with_preset(Preset::default())
    }

    /// The choices of an engine ([`Preset::for_target`], the cube files in
    /// the GL world as the engine's preset turns it).
    pub fn for_target(target: Target) -> Self {
        Self::with_preset(Preset::for_target(target, FileAxes::default()))
    }

    /// Every choice of `preset` (one made by [`Preset::for_target`] and
    /// changed field by field, say).
    pub fn with_preset(preset: Preset) -> Self {
        Self {
            preset,
            options: BakeOptions::default(),
            save: SaveOptions::default(),
            progress: None,
            provenance: Provenance::default(),
        }
    }

    /// The face size of the chain's level 0 (the preset's otherwise).
    pub fn size(mut self, size: u32) -> Self {
        self.preset.size = size;
        self
    }

    /// The mip ↔ roughness rule (the preset's otherwise).
    pub fn rule(mut self, rule: RoughnessRule) -> Self {
        self.preset.rule = rule;
        self
    }

    /// The sample counts of the sampled levels (default
    /// [`Quality::Default`]).
    pub fn quality(mut self, quality: Quality) -> Self {
        self.options.quality = quality;
        self
    }

    /// Every option the preset does not set (quality, samples, exact
    /// levels, the firefly clamp, checks, ...): `options`' fields, which
    /// replace any set before, except those the preset owns (size, levels'
    /// sizes, rule, irradiance, SH window, DFG table, axes), which stay the
    /// preset's. A cancel flag set before is kept when `options` has none.
    pub fn options(mut self, options: BakeOptions<'a>) -> Self {
        let cancel = self.options.cancel;
        self.options = options;
        self.options.cancel = self.options.cancel.or(cancel);
        self
    }

    /// How the files are written ([`SaveOptions`]: inputs never to be
    /// overwritten, OpenEXR precision and compression, syncing).
    pub fn save_options(mut self, save: SaveOptions<'a>) -> Self {
        self.save = save;
        self
    }

    /// Called as each level of the chain starts.
    pub fn progress(mut self, progress: Progress<'a>) -> Self {
        self.progress = Some(progress);
        self
    }

    /// Stops the bake, and any write of its files, once `flag` is set
    /// ([`crate::Error::Cancelled`]; nothing is left written).
    pub fn cancel(mut self, flag: &'a AtomicBool) -> Self {
        self.options.cancel = Some(flag);
        self.save.cancel = Some(flag);
        self
    }

    /// The input as the manifest names it (a file name, or a built-in).
    pub fn input_name(mut self, name: impl Into<String>) -> Self {
        self.provenance.input = name.into();
        self
    }

    /// The seconds loading the input took, for the manifest.
    pub fn load_seconds(mut self, seconds: f64) -> Self {
        self.provenance.load_seconds = seconds;
        self
    }

    /// The preset as it stands.
    #[must_use]
    pub fn preset(&self) -> &Preset {
        &self.preset
    }

    /// The options the bake runs with: the preset's laid over the rest.
    #[must_use]
    pub fn bake_options(&self) -> BakeOptions<'a> {
        self.preset.bake_options(self.options.clone())
    }

    /// Bakes `src`, given by value (the bake then works in the input's own
    /// memory, never holding it twice) or by reference (it is copied where
    /// the bake changes it). The same result either way, bit for bit.
    ///
    /// # Errors
    ///
    /// A preset whose choices disagree (`Preset::check`); a bad size or
    /// level count; non-finite texels; [`crate::Error::Cancelled`].
    pub fn bake<'s>(&self, src: impl Into<Cow<'s, EnvImage>>) -> Result<Baked<'a>> {
        self.preset.check()?;
        let opts = self.bake_options();
        let t = std::time::Instant::now();
        let bake = crate::filter::bake::bake_input(src.into(), &opts, self.report(), None)?;
        let mut provenance = self.provenance.clone();
        provenance.bake_seconds = t.elapsed().as_secs_f64();
        Ok(Baked {
            bake,
            preset: self.preset.clone(),
            options: opts,
            save: self.save.clone(),
            provenance,
            written: None,
        })
    }

    /// Bakes `src` and writes every file into directory `dir` as
    /// [`Baked::write`] writes them, an OpenEXR chain's level files each
    /// while the next level is made. The bake is [`Baker::bake`]'s, bit for
    /// bit; nothing is left half-written when the bake or a write fails or
    /// is cancelled (a directory this call created is removed again).
    ///
    /// # Errors
    ///
    /// As [`Baker::bake`] and [`Baked::write`].
    pub fn bake_into(&self, src: EnvImage, dir: impl AsRef<Path>) -> Result<Baked<'a>> {
        let opts = self.bake_options();
        let provenance = self.provenance.clone();
        let done = write::bake_into(
            dir.as_ref(),
            src,
            &opts,
            &self.preset,
            &provenance,
            &self.save,
            self.report(),
        )?;
        let mut provenance = provenance;
        provenance.bake_seconds = done.bake_seconds;
        Ok(Baked {
            bake: done.bake,
            preset: self.preset.clone(),
            options: opts,
            save: self.save.clone(),
            provenance,
            written: Some((dir.as_ref().to_path_buf(), done.written, done.write_seconds)),
        })
    }

    fn report(&self) -> Progress<'a> {
        self.progress.unwrap_or(&|_, _| {})
    }
}

/// A finished bake with the choices it was made with: its maps
/// ([`Baked::bake`]), and its files written to a directory
/// ([`Baked::write`]), made in memory ([`Baked::files`]) or laid out for an
/// engine's upload ([`Baked::textures`]). The files name their conventions
/// (axes, E or E/π, which level is which roughness) in `manifest.json` and,
/// where the container has room, in the files themselves.
#[derive(Clone, Debug)]
pub struct Baked<'a> {
    bake: Bake,
    preset: Preset,
    options: BakeOptions<'a>,
    save: SaveOptions<'a>,
    provenance: Provenance,
    written: Option<(PathBuf, Written, f64)>,
}

impl<'a> Baked<'a> {
    /// The maps: the specular chain, the SH9, the irradiance map, the DFG
    /// table, each level's report.
    #[must_use]
    pub fn bake(&self) -> &Bake {
        &self.bake
    }

    /// The maps, taken.
    #[must_use]
    pub fn into_bake(self) -> Bake {
        self.bake
    }

    /// The preset it was baked with.
    #[must_use]
    pub fn preset(&self) -> &Preset {
        &self.preset
    }

    /// Seconds the bake took (the level files written beside it included,
    /// after [`Baker::bake_into`]).
    #[must_use]
    pub fn bake_seconds(&self) -> f64 {
        self.provenance.bake_seconds
    }

    /// What [`Baker::bake_into`] wrote, and the seconds it spent after the
    /// bake; `None` after [`Baker::bake`].
    #[must_use]
    pub fn written(&self) -> Option<(&Written, f64)> {
        self.written.as_ref().map(|(_, w, s)| (w, *s))
    }

    /// Writes every file into directory `dir` (created if missing, removed
    /// again if it was created and a write fails), all renamed into place
    /// together; see the [module docs](super) for the files.
    ///
    /// # Errors
    ///
    /// The directory cannot be made; an encoding or write error (nothing
    /// is left half-written); [`crate::Error::Cancelled`].
    pub fn write(&self, dir: impl AsRef<Path>) -> Result<Written> {
        write::write(
            dir.as_ref(),
            &self.bake,
            &self.options,
            &self.preset,
            &self.provenance,
            &self.save,
        )
    }

    /// The same files as [`Baked::write`] would write into a directory
    /// named `name`, made in memory (nothing on disk is read or written):
    /// each by its name, `specular.ktx2` and so on. `name` only names files
    /// that carry it (Filament's `<name>_ibl.ktx`, as cmgen names them).
    ///
    /// # Errors
    ///
    /// An encoding error; [`crate::Error::Cancelled`].
    pub fn files(&self, name: impl AsRef<Path>) -> Result<BakeFiles> {
        write::in_memory(
            name.as_ref(),
            &self.bake,
            &self.options,
            &self.preset,
            &self.provenance,
        )
    }

    /// The chain's and the irradiance map's texels in the preset's texel
    /// format, per level and face, ready for an engine's upload (the cube
    /// in the preset's axes); no file is made.
    ///
    /// # Errors
    ///
    /// Levels that do not make a texture (a chain that does not halve).
    pub fn textures(&self) -> Result<EngineTextures> {
        write::engine_textures(&self.bake, &self.preset)
    }
}
