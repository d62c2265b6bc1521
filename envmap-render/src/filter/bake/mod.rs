//! The lighting bake: from one environment map, the GGX-prefiltered
//! specular chain, the irradiance (SH9 and a map) and the DFG table, with
//! every convention and every approximation reported.
//!
//! ```text
//! source → cube base (face s₀ ≥ the source's resolution) → the brightest texels split out
//!        → mip pyramid of the rest (solid-angle box filter)
//!        → level 0: the source resampled (roughness 0)
//!        → level k: GGX at the rule's roughness, exact or importance-sampled, + the split texels exactly
//! source → SH9 (exact texel solid angles) → irradiance map (E/π by default)
//! DFG table (scale, bias; single and multiscatter)
//! ```
//!
//! Outputs are clamped at zero (a lossy EXR's ringing around a sun gives
//! negative texels: the bake integrates the data as given and counts what
//! it clamps). NaN and infinite texels are refused (the command replaces
//! them by black when it loads a file, as `convert` does).

use std::sync::atomic::AtomicBool;
use std::time::Instant;

use envmap_core::{AnyMapping, Atlas};

use crate::par::*;
use std::borrow::Cow;

use crate::cancel;
use crate::error::{Error, Result};
use crate::filter::dfg::{self, DfgGrid, DfgTable};
use crate::filter::pyramid::Pyramid;
use crate::filter::sh::{
    irradiance_map, irradiance_map_exact, ExactLevel, IrradianceScale, Sh9, ShWindow,
    DEFAULT_IRRADIANCE_SIZE,
};
use crate::filter::specular::RoughnessRule;
use crate::image::{EnvImage, FileAxes, Representation};
use crate::instruments::Oracle;

mod chain;
mod check;
pub use chain::*;
pub use check::*;

/// How many samples the importance-sampled levels take.
///
/// The default's counts grow with roughness, as the sampling's error does
/// at a fixed count (against the exact integral; sharp edges need more than
/// smooth maps, `estimated_error` and `docs/lighting.md`): 64 up to
/// roughness 0.15, 128 up to 0.3, 256 up to 0.5, 1024 above. Draft takes a quarter of
/// those, high four times as many. The bake doubles a level's count where
/// its lobe is under [`SHARP_TEXELS`] of the input's texels across.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Quality {
    /// A quarter of the default's samples (at least 16).
    Draft,
    /// 64, 128, 256 or 1024 samples by roughness.
    #[default]
    Default,
    /// Four times the default's samples.
    High,
}

impl Quality {
    /// Samples per texel at `roughness`.
    #[cfg_attr(feature = "instruments", visibility::make(pub))]
    #[must_use]
    pub(crate) fn samples(self, roughness: f32) -> u32 {
        let base = match roughness {
            r if r <= 0.15 => 64,
            r if r <= 0.3 => 128,
            r if r <= 0.5 => 256,
            _ => 1024,
        };
        match self {
            Quality::Draft => (base / 4).max(16),
            Quality::Default => base,
            Quality::High => 4 * base,
        }
    }

    /// Samples per texel at `roughness` for a level of `texels` texels:
    /// [`Quality::samples`], raised so that the level takes at least
    /// [`SAMPLE_BUDGET`] samples in all (scaled as the quality scales its
    /// counts), at most 4096 per texel.
    #[must_use]
    pub(crate) fn samples_for(self, roughness: f32, texels: u64) -> u32 {
        let budget = match self {
            Quality::Draft => SAMPLE_BUDGET / 4,
            Quality::Default => SAMPLE_BUDGET,
            Quality::High => 4 * SAMPLE_BUDGET,
        };
        let floor = (budget / texels.max(1)).min(4096) as u32;
        self.samples(roughness).max(floor)
    }

    /// The name on the command line.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Quality::Draft => "draft",
            Quality::Default => "default",
            Quality::High => "high",
        }
    }
}

impl std::str::FromStr for Quality {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        match s.to_ascii_lowercase().as_str() {
            "draft" => Ok(Quality::Draft),
            "default" => Ok(Quality::Default),
            "high" => Ok(Quality::High),
            _ => Err(Error::UnknownName {
                what: "quality",
                name: s.to_owned(),
                expected: "draft, default, high".to_owned(),
            }),
        }
    }
}

/// A sampled level whose lobe is narrower than this many of the input's
/// texels (`texel_pitch`) takes twice `Quality::samples_for`'s count.
pub const SHARP_TEXELS: f64 = 2.0;

/// A level is summed exactly when its source level has at most this many
/// texels per sample it would otherwise take: an exact sum over a source
/// texel, eight output texels at a time, costs about a sixteenth of a
/// sample's mapping and trilinear read.
pub const EXACT_PER_SAMPLE: u64 = 16;

/// A level is also summed exactly when the whole sum takes at most this
/// many (output texel, source texel) pairs (2²⁸), whatever its sample
/// count: the rough, small levels, whose exact sum is cheap.
pub const EXACT_BUDGET: u64 = 1 << 28;

/// Samples a sampled level takes at least in all, at the default quality
/// (2²³): a small level takes more per texel than the default counts, at
/// the cost of a large level's few samples per texel (a quarter for
/// draft, four times for high).
pub const SAMPLE_BUDGET: u64 = 1 << 23;

/// What to bake. `#[non_exhaustive]`, so that options can be added without
/// breaking callers: start from [`BakeOptions::default`] (or
/// [`crate::bake::Preset::bake_options`]) and set the fields wanted.
#[derive(Clone, Debug)]
#[non_exhaustive]
pub struct BakeOptions<'a> {
    /// The specular chain's level-0 face size. Default 512.
    pub size: u32,
    /// Number of levels; `None` down to `min_size`.
    pub levels: Option<usize>,
    /// The smallest level's face size when `levels` is `None`; `None` for
    /// the rule's own (`RoughnessRule::default_min_size`).
    pub min_size: Option<u32>,
    /// Each level's face size, level 0 first, instead of sizes halving from
    /// `size` (then `size`, `levels` and `min_size` are not read): a chain
    /// that is not a mip chain, such as the one envmap's renderer bakes
    /// (`render_chain`), whose levels follow their lobes. `None` (the
    /// default): a mip chain, what engines load.
    pub sizes: Option<Vec<u32>>,
    /// Which roughness each level has.
    pub rule: RoughnessRule,
    /// Sample counts of the sampled levels.
    pub quality: Quality,
    /// Samples per texel for every sampled level, overriding `quality`.
    pub samples: Option<u32>,
    /// Every level by the exact sum (slow at large sizes; the oracle), and
    /// the irradiance map by the exact cosine convolution.
    pub exact: bool,
    /// The irradiance map by the exact cosine convolution of the input
    /// (its pyramid at a level fine enough, `irradiance_map_exact`)
    /// instead of from the SH9, whatever `exact` says: SH9's band limit
    /// cannot hold a sun or a window. Default false.
    pub exact_irradiance: bool,
    /// Added to each sample's FIS level. Default 0 (measured best on smooth
    /// and sharp environments: `docs/lighting.md`).
    pub lod_bias: f32,
    /// At most this many brightest texels are split out and summed by a Barnes–Hut tree near each lobe.
    pub bright_max: usize,
    /// Firefly control: texels above this luminance are compressed
    /// (Y → T·(1 + ln(Y/T))) before the specular chain is filtered (the SH
    /// and the irradiance map integrate the data as given); `None` (the
    /// default) leaves them.
    pub clamp: Option<f32>,
    /// The outputs' axes (cube files in the GL world by default).
    pub axes: FileAxes,
    /// The irradiance map's face size (`bake`); 0 for none. Default 32.
    pub irradiance_size: u32,
    /// What the irradiance map stores: E/π (the default) or E.
    pub irradiance_scale: IrradianceScale,
    /// A deringing window for the SH (and the irradiance map made from
    /// it); `None` (the default) for none.
    pub sh_window: Option<ShWindow>,
    /// Only the SH (`bake` skips the chain, the map and the table).
    pub sh_only: bool,
    /// The DFG table's size (`bake`); 0 for none. Default 128.
    pub dfg_size: u32,
    /// Where the DFG table's texels sit: texel centres (the default, what
    /// engines sample at (N·V, roughness)) or the edges grid (N·V and
    /// roughness of 0 and 1 exact; [`DfgGrid`]).
    pub dfg_grid: DfgGrid,
    /// Texels per sampled level measured against the exact integral
    /// (`measure_level`); 0 (the default) for none.
    pub check: u32,
    /// Stops the bake once set ([`Error::Cancelled`]).
    pub cancel: Option<&'a AtomicBool>,
}

impl Default for BakeOptions<'_> {
    fn default() -> Self {
        Self {
            size: 512,
            levels: None,
            min_size: None,
            sizes: None,
            rule: RoughnessRule::Linear,
            quality: Quality::Default,
            samples: None,
            exact: false,
            exact_irradiance: false,
            lod_bias: 0.0,
            bright_max: 16384,
            clamp: None,
            axes: FileAxes::default(),
            irradiance_size: DEFAULT_IRRADIANCE_SIZE,
            irradiance_scale: IrradianceScale::EOverPi,
            sh_window: None,
            sh_only: false,
            dfg_size: dfg::DEFAULT_SIZE,
            dfg_grid: DfgGrid::TexelCentres,
            check: 0,
            cancel: None,
        }
    }
}

/// One level of the chain, for reports and manifests.
#[derive(Clone, Debug, PartialEq)]
pub struct LevelReport {
    /// Face size.
    pub size: u32,
    /// Perceptual roughness.
    pub roughness: f32,
    /// `"resampled"`, `"exact"` or `"sampled"`.
    pub method: &'static str,
    /// Samples per texel (sampled levels).
    pub samples: u32,
    /// The pyramid level summed over (exact levels).
    pub source_level: Option<usize>,
    /// Output texels clamped at zero (negative source data).
    pub clamped: u64,
    /// Seconds.
    pub seconds: f64,
    /// The error measured against the exact integral on
    /// [`BakeOptions::check`] texels (sampled levels, when asked).
    pub measured: Option<LevelError>,
}

impl LevelReport {
    /// The relative RMS error this level's method is measured to have on
    /// smooth light (`estimated_error`, `docs/lighting.md`); `None` for the
    /// resampled and exact levels, which have no sampling error.
    #[must_use]
    pub fn estimated_error(&self) -> Option<f64> {
        (self.method == "sampled").then(|| estimated_error(self.roughness, self.samples))
    }
}

/// The irradiance map and how it was made.
#[derive(Clone, Debug)]
pub struct Irradiance {
    /// The map: a cube (horizontal strip) in the output axes, E or E/π as
    /// [`BakeOptions::irradiance_scale`] says.
    pub image: EnvImage,
    /// `"sh9"` (from the SH, the default) or `"exact"` (direct cosine
    /// convolution over a level of the source's pyramid: `--exact`).
    pub method: &'static str,
    /// The pyramid level convolved (exact).
    pub source_level: Option<usize>,
    /// Texels clamped at zero (SH9 rings below zero around a sun; negative
    /// source data).
    pub clamped: u64,
}

/// Everything `bake` makes.
#[derive(Clone, Debug)]
pub struct Bake {
    /// The specular chain (`None` with [`BakeOptions::sh_only`]).
    pub chain: Option<SpecularChain>,
    /// The source's radiance coefficients, canonical axes, unwindowed.
    pub sh: Sh9,
    /// The deringing window's cutoff, if a window was applied.
    pub sh_cutoff: Option<f64>,
    /// The irradiance map (`None` for size 0 or [`BakeOptions::sh_only`]).
    pub irradiance: Option<Irradiance>,
    /// The DFG table (`None` for size 0 or [`BakeOptions::sh_only`]).
    pub dfg: Option<DfgTable>,
    /// Seconds per stage besides the chain's: `sh9`, `irradiance`, `dfg`.
    pub stages: Vec<(&'static str, f64)>,
    /// The irradiance map and the SH9 measured against the oracle of the
    /// input, when [`BakeOptions::check`] asks.
    pub checked: Option<BakeCheck>,
}

/// What [`BakeOptions::check`] measured besides the levels (theirs are in
/// each [`LevelReport::measured`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BakeCheck {
    /// The irradiance map against the oracle's E (or E/π), on `check`
    /// texels.
    pub irradiance: Option<LevelError>,
    /// The SH9's relative error against the oracle's projection (texels
    /// split 2 × 2): √(Σ(a − b)²/Σb²) over the 27 coefficients.
    pub sh9: f64,
}

/// The whole lighting bake of `src`: the specular chain
/// (`specular_chain`), the SH9 radiance coefficients ([`Sh9::project`]),
/// the irradiance map (from the SH, or exact with [`BakeOptions::exact`]),
/// and the DFG table. `progress(level, levels)` as for the chain.
///
/// # Errors
///
/// As `specular_chain`; a bad irradiance or DFG size.
#[cfg_attr(feature = "instruments", visibility::make(pub))]
pub(crate) fn bake(
    src: &EnvImage,
    opts: &BakeOptions,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<Bake> {
    bake_input(Cow::Borrowed(src), opts, progress, None)
}

/// [`bake`] of an input the caller gives away: the chain's working copy
/// of the input (its brightest texels split off, its polar rows widened)
/// is the input itself, so the bake never holds the input twice (peak
/// memory about one input less; `envmap bake` bakes so). The same result
/// as [`bake`], bit for bit. With [`BakeOptions::check`] or an exact
/// irradiance map, which read the input after the chain, the input is
/// copied as [`bake`] copies it.
///
/// # Errors
///
/// As [`bake`].
pub(crate) fn bake_owned(
    src: EnvImage,
    opts: &BakeOptions,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<Bake> {
    bake_input(Cow::Owned(src), opts, progress, None)
}

/// What `bake_owned_streaming` hands each level of the specular chain
/// to, as soon as the level is final: its index (0: the input resampled),
/// the level as [`SpecularChain::levels`] will hold it, and its report.
pub type LevelSink<'s> = dyn Fn(usize, &EnvImage, &LevelReport) -> Result<()> + Sync + 's;

/// [`bake_owned`], handing each level of the specular chain to `sink` as
/// soon as it is final, while the bake goes on: a caller writes (or
/// uploads) level k while level k + 1 is filtered
/// ([`crate::bake::Baker::bake_into`] writes a bake directory so).
///
/// The levels come in order, each once: level 0 before the base cube and
/// the pyramid are made, level k − 1 beside the making of level k
/// (`rayon::join`: the sink runs on the pool's threads, none of its own;
/// in order on the calling thread without the `parallel` feature), the
/// last after it. The result is [`bake_owned`]'s, bit for bit.
///
/// # Errors
///
/// As [`bake`]; an error `sink` returns stops the bake before its next
/// level and is the bake's error.
pub(crate) fn bake_owned_streaming(
    src: EnvImage,
    opts: &BakeOptions,
    progress: &(dyn Fn(usize, usize) + Sync),
    sink: &LevelSink<'_>,
) -> Result<Bake> {
    bake_input(Cow::Owned(src), opts, progress, Some(sink))
}

pub(crate) fn bake_input(
    input: Cow<'_, EnvImage>,
    opts: &BakeOptions,
    progress: &(dyn Fn(usize, usize) + Sync),
    sink: Option<&LevelSink<'_>>,
) -> Result<Bake> {
    let mut stages = Vec::new();
    // The SH9 first: the chain may consume the input.
    let t = Instant::now();
    let sh = Sh9::project(&input);
    stages.push(("sh9", t.elapsed().as_secs_f64()));
    // Whether the input is read after the chain.
    let later = opts.check > 0 || opts.exact || opts.exact_irradiance || opts.sh_only;
    if later {
        let src = &*input;
        let oracle = (opts.check > 0).then(|| Oracle::new(src));
        let chain = if opts.sh_only {
            refuse_non_finite(src)?;
            None
        } else {
            Some(chain_checked(
                Cow::Borrowed(src),
                opts,
                progress,
                oracle.as_ref(),
                sink,
            )?)
        };
        finish(Some(src), oracle, chain, sh, stages, opts)
    } else {
        let chain = chain_checked(input, opts, progress, None, sink)?;
        finish(None, None, Some(chain), sh, stages, opts)
    }
}

/// The rest of a bake once its chain is made: the irradiance map (exact
/// from `src`, the input, where asked: then it is given), the DFG table,
/// the checks against `oracle`.
fn finish(
    src: Option<&EnvImage>,
    oracle: Option<Oracle<'_>>,
    chain: Option<SpecularChain>,
    sh: Sh9,
    mut stages: Vec<(&'static str, f64)>,
    opts: &BakeOptions,
) -> Result<Bake> {
    cancel::check(opts.cancel)?;
    let cube = Representation::new(
        AnyMapping::Cube,
        Atlas::CUBE_HORIZONTAL_STRIP,
        opts.axes.frame(AnyMapping::Cube),
    )?;
    let (windowed, sh_cutoff) = match opts.sh_window {
        None => (sh, None),
        Some(w) => {
            let cutoff = w.cutoff(&sh);
            (sh.windowed(w), cutoff)
        }
    };
    let mut irradiance = None;
    if !opts.sh_only && opts.irradiance_size > 0 {
        let t = Instant::now();
        let (w, h) = (6 * opts.irradiance_size, opts.irradiance_size);
        let exact = if opts.exact || opts.exact_irradiance {
            src
        } else {
            None
        };
        let (mut image, method, source_level) = if let Some(src) = exact {
            let p = Pyramid::new(src.clone(), 1)?;
            let e =
                irradiance_map_exact(&p, cube, w, h, opts.irradiance_scale, ExactLevel::default())?;
            (e.image, "exact", Some(e.level))
        } else {
            (
                irradiance_map(&windowed, cube, w, h, opts.irradiance_scale)?,
                "sh9",
                None,
            )
        };
        let clamped = clamp_negative(&mut image);
        irradiance = Some(Irradiance {
            image,
            method,
            source_level,
            clamped,
        });
        stages.push(("irradiance", t.elapsed().as_secs_f64()));
    }
    cancel::check(opts.cancel)?;
    let mut table = None;
    if !opts.sh_only && opts.dfg_size > 0 {
        let t = Instant::now();
        table = Some(DfgTable::on_grid(
            opts.dfg_size,
            opts.dfg_grid,
            opts.cancel,
        )?);
        stages.push(("dfg", t.elapsed().as_secs_f64()));
    }
    let checked = oracle.map(|o| {
        let exact = o.sh9(2);
        let (mut se, mut ss) = (0.0f64, 0.0f64);
        for (a, e) in sh.coeffs.iter().zip(&exact.coeffs) {
            for (x, y) in a.iter().zip(e) {
                se += (x - y) * (x - y);
                ss += y * y;
            }
        }
        BakeCheck {
            irradiance: irradiance
                .as_ref()
                .map(|i| measure_irradiance(&o, &i.image, opts.irradiance_scale, opts.check, 7)),
            sh9: if ss > 0.0 { (se / ss).sqrt() } else { 0.0 },
        }
    });
    Ok(Bake {
        chain,
        sh,
        sh_cutoff,
        irradiance,
        dfg: table,
        stages,
        checked,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A small smooth latlong and a small bake of it.
    fn small() -> (EnvImage, BakeOptions<'static>) {
        use crate::scene::procedural::{fill, smooth};
        let src = fill(
            Representation::default_for(AnyMapping::LatLong),
            64,
            32,
            smooth,
        )
        .unwrap();
        let opts = BakeOptions {
            size: 16,
            irradiance_size: 8,
            dfg_size: 8,
            ..BakeOptions::default()
        };
        (src, opts)
    }

    /// The bake of an input given away is the bake of a borrowed one, bit
    /// for bit (its working copy is the input itself).
    #[test]
    fn an_owned_input_bakes_as_a_borrowed_one() {
        let (src, opts) = small();
        let a = bake(&src, &opts, &|_, _| {}).unwrap();
        let b = bake_owned(src, &opts, &|_, _| {}).unwrap();
        let (ca, cb) = (a.chain.unwrap(), b.chain.unwrap());
        assert_eq!(ca.levels.len(), cb.levels.len());
        for (x, y) in ca.levels.iter().zip(&cb.levels) {
            assert_eq!(x.pixels(), y.pixels());
        }
        assert_eq!(a.sh.coeffs, b.sh.coeffs);
        assert_eq!(
            a.irradiance.unwrap().image.pixels(),
            b.irradiance.unwrap().image.pixels()
        );
    }

    /// The streaming bake hands every level once, in order, as the chain
    /// holds it, and returns the plain bake; a sink's error stops it before
    /// the next level and is its error.
    #[test]
    fn levels_are_handed_out_in_order_and_a_sink_error_stops_the_bake() {
        use std::sync::Mutex;
        let (src, opts) = small();
        let plain = bake(&src, &opts, &|_, _| {}).unwrap();
        let handed = Mutex::new(Vec::new());
        let sink = |k: usize, img: &EnvImage, r: &LevelReport| -> Result<()> {
            handed.lock().unwrap().push((k, img.clone(), r.clone()));
            Ok(())
        };
        let streamed = bake_owned_streaming(src.clone(), &opts, &|_, _| {}, &sink).unwrap();
        let chain = streamed.chain.unwrap();
        let handed = handed.into_inner().unwrap();
        assert_eq!(handed.len(), chain.levels.len());
        for (i, (k, img, r)) in handed.iter().enumerate() {
            assert_eq!(*k, i);
            assert_eq!(img.pixels(), chain.levels[i].pixels());
            assert_eq!(r, &chain.reports[i]);
        }
        for (x, y) in chain.levels.iter().zip(&plain.chain.unwrap().levels) {
            assert_eq!(x.pixels(), y.pixels());
        }
        assert_eq!(streamed.sh.coeffs, plain.sh.coeffs);

        // Level 0's sink fails: no level past 1 is started, and the error
        // is the sink's.
        let started = Mutex::new(Vec::new());
        let failing = |k: usize, _: &EnvImage, _: &LevelReport| -> Result<()> {
            Err(Error::usage(format!("disk full at level {k}")))
        };
        let e = bake_owned_streaming(
            src,
            &opts,
            &|k, _| started.lock().unwrap().push(k),
            &failing,
        )
        .unwrap_err();
        assert!(e.to_string().contains("disk full at level 0"), "{e}");
        assert!(started.into_inner().unwrap().iter().all(|&k| k <= 1));
    }

    #[test]
    fn chain_sizes_follow_the_rule_and_refuse_too_many_levels() {
        let o = BakeOptions::default();
        assert_eq!(
            chain_sizes(&o).unwrap(),
            [512, 256, 128, 64, 32, 16, 8, 4, 2]
        );
        let f = BakeOptions {
            rule: RoughnessRule::Filament,
            ..BakeOptions::default()
        };
        assert_eq!(chain_sizes(&f).unwrap(), [512, 256, 128, 64, 32, 16]);
        let l = BakeOptions {
            levels: Some(10),
            ..BakeOptions::default()
        };
        assert_eq!(chain_sizes(&l).unwrap().last(), Some(&1));
        let e = chain_sizes(&BakeOptions {
            levels: Some(11),
            ..BakeOptions::default()
        })
        .unwrap_err()
        .to_string();
        assert!(e.contains("at most 10 levels"), "{e}");
    }
}
