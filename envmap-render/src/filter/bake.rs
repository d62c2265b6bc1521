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

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use envmap_core::glam::Mat3;
use envmap_core::texel::texel_center;
use envmap_core::{AnyMapping, Atlas, ChartUv, Mapping};

use crate::par::*;
use std::borrow::Cow;

use crate::cancel;
use crate::error::{Error, Result};
use crate::filter::dfg::{self, DfgGrid, DfgTable};
use crate::filter::oracle::Oracle;
use crate::filter::pyramid::{Pyramid, Trilinear};
use crate::filter::sample::Filter;
use crate::filter::sh::{
    irradiance_map, irradiance_map_exact, ExactLevel, IrradianceScale, Sh9, ShWindow,
    DEFAULT_IRRADIANCE_SIZE,
};
use crate::filter::specular::{
    exact_level, finest_sampled_level, lobe_width, prefilter_level, split_bright, texel_pitch,
    Bright, BrightReport, LevelJob, Method, RoughnessRule, PART,
};
use crate::filter::weights::channel_energy;
use crate::filter::{convert, ConvertOptions};
use crate::image::{luminance, EnvImage, FileAxes, Representation};

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

/// A level's error against the exact integral on a subset of its texels
/// (`measure_level`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LevelError {
    /// Texels measured.
    pub texels: u32,
    /// Relative RMS error √(Σ(a − b)²/Σb²) over the texels and channels.
    pub relative_rms: f64,
    /// Bias: Σ(a − b)/Σb.
    pub bias: f64,
    /// Seconds the exact sums took.
    pub seconds: f64,
}

/// Measures `level` (a cube, in its own axes) made at `roughness` against
/// the oracle of the input (`Oracle::prefiltered`: the input as given,
/// piecewise constant over its own texels, independent of the base cube and
/// the pyramid the bake made) at `texels` of its texels picked by a fixed
/// hash (`seed` varies the pick). The oracle's values are clamped at zero as
/// the outputs are.
///
/// # Errors
///
/// `level` is not a cube.
#[cfg_attr(feature = "instruments", visibility::make(pub))]
pub(crate) fn measure_level(
    oracle: &Oracle,
    roughness: f32,
    level: &EnvImage,
    texels: u32,
    seed: u32,
) -> Result<LevelError> {
    if level.mapping() != AnyMapping::Cube {
        return Err(Error::usage("measure_level: a cube level expected"));
    }
    let t = Instant::now();
    let s = level.cell_size().0;
    let coords = hashed_texels(6, s, s, texels, seed);
    let frame = level.representation().frame;
    let (dirs, coords): (Vec<_>, Vec<_>) = coords
        .iter()
        .filter_map(|&(c, i, j)| {
            AnyMapping::Cube
                .inverse(ChartUv::new(c, texel_center(i, s), texel_center(j, s)))
                .map(|d| (frame.to_canonical(d), (c, i, j)))
        })
        .unzip();
    let exact = if roughness > 0.0 {
        oracle.prefiltered(roughness, &dirs)
    } else {
        // Roughness 0: the input itself at each direction is not an
        // integral; the level is a resampling, measured by conversion tests.
        return Err(Error::usage(
            "measure_level: roughness 0 is a resampling, not an integral",
        ));
    };
    let pairs = coords.iter().zip(&exact).map(|(&(c, i, j), e)| {
        (
            level
                .chart_texel(c, i, j)
                .unwrap_or_default()
                .map(f64::from),
            e.map(|v| v.max(0.0)),
        )
    });
    let mut m = compare(pairs);
    m.seconds = t.elapsed().as_secs_f64();
    Ok(m)
}

/// `count` texels of a `charts × w × h` grid picked by a fixed xorshift
/// hash of `seed` (repeats possible), as (chart, i, j).
fn hashed_texels(charts: u32, w: u32, h: u32, count: u32, seed: u32) -> Vec<(u32, u32, u32)> {
    let n = charts * w * h;
    let mut h32 = 0x9e37_79b9u32 ^ seed.wrapping_mul(0x85eb_ca77);
    (0..count.min(n))
        .map(|_| {
            h32 ^= h32 << 13;
            h32 ^= h32 >> 17;
            h32 ^= h32 << 5;
            let k = h32 % n;
            (k / (w * h), k % w, (k / w) % h)
        })
        .collect()
}

/// Relative RMS √(Σ(a − b)²/Σb²) and bias Σ(a − b)/Σb of (measured,
/// exact) pairs over every channel.
fn compare(pairs: impl Iterator<Item = ([f64; 3], [f64; 3])>) -> LevelError {
    let (mut se, mut ss, mut sd, mut sm, mut n) = (0.0f64, 0.0f64, 0.0f64, 0.0f64, 0u32);
    for (a, e) in pairs {
        for (x, y) in a.iter().zip(&e) {
            let d = x - y;
            se += d * d;
            ss += y * y;
            sd += d;
            sm += y;
        }
        n += 1;
    }
    let ratio = |a: f64, b: f64| if b > 0.0 { a / b } else { 0.0 };
    LevelError {
        texels: n,
        relative_rms: ratio(se, ss).sqrt(),
        bias: ratio(sd, sm),
        seconds: 0.0,
    }
}

/// Measures an irradiance map (any representation, in its own axes; E or
/// E/π as `scale` says) against the oracle's E (`Oracle::irradiance`),
/// clamped at zero as the map is, at `texels` texels picked as in
/// [`measure_level`].
#[cfg_attr(feature = "instruments", visibility::make(pub))]
#[must_use]
pub(crate) fn measure_irradiance(
    oracle: &Oracle,
    map: &EnvImage,
    scale: IrradianceScale,
    texels: u32,
    seed: u32,
) -> LevelError {
    let t = Instant::now();
    let mapping = map.mapping();
    let (w, h) = map.cell_size();
    let frame = map.representation().frame;
    let (dirs, coords): (Vec<_>, Vec<_>) = hashed_texels(mapping.chart_count(), w, h, texels, seed)
        .into_iter()
        .filter_map(|(c, i, j)| {
            mapping
                .inverse(ChartUv::new(c, texel_center(i, w), texel_center(j, h)))
                .map(|d| (frame.to_canonical(d), (c, i, j)))
        })
        .unzip();
    let exact = oracle.irradiance(&dirs);
    let f = scale.factor();
    let mut m = compare(coords.iter().zip(&exact).map(|(&(c, i, j), e)| {
        (
            map.chart_texel(c, i, j).unwrap_or_default().map(f64::from),
            e.map(|v| (v * f).max(0.0)),
        )
    }));
    m.seconds = t.elapsed().as_secs_f64();
    m
}

/// The relative RMS error a sampled level is expected to have against the
/// exact integral on a smooth environment: the errors at 64 samples per
/// texel from a sweep of sample counts (`examples/bake_accuracy.rs` with
/// `SAMPLES=64,256`, 300 texels per level, a 512² chain from a smooth
/// 4096 × 2048 HDR), interpolated in roughness and scaled by √(64/N) for
/// N samples, which overestimates the error at 256. Sharp environments
/// (edges, small lights) have larger errors: `envmap bake --check`
/// measures them on the input itself.
#[cfg_attr(feature = "instruments", visibility::make(pub))]
#[must_use]
pub(crate) fn estimated_error(roughness: f32, samples: u32) -> f64 {
    const AT_64: [(f64, f64); 9] = [
        (0.0, 0.0),
        (0.125, 0.0030),
        (0.25, 0.0053),
        (0.375, 0.0057),
        (0.5, 0.0059),
        (0.625, 0.0074),
        (0.75, 0.0102),
        (0.875, 0.0119),
        (1.0, 0.0204),
    ];
    let r = f64::from(roughness).clamp(0.0, 1.0);
    let e = AT_64
        .windows(2)
        .find(|w| r <= w[1].0)
        .map_or(AT_64[8].1, |w| {
            let t = (r - w[0].0) / (w[1].0 - w[0].0);
            w[0].1 + t * (w[1].1 - w[0].1)
        });
    e * (64.0 / f64::from(samples.max(1))).sqrt()
}

/// What `clamp_luminance` changed.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ClampReport {
    /// The luminance threshold.
    pub threshold: f32,
    /// Texels compressed.
    pub texels: u64,
    /// Fraction of the energy (Σ Ω·Y) taken away.
    pub energy_removed: f64,
}

/// Compresses every texel whose luminance Y exceeds `t` to the luminance
/// t·(1 + ln(Y/t)) (continuous, with slope 1 at t), keeping its colour.
pub(crate) fn clamp_luminance(img: &mut EnvImage, t: f32) -> Result<ClampReport> {
    let mapping = img.mapping();
    let (cw, ch) = img.cell_size();
    let weights = crate::filter::weights::TexelWeights::new(mapping, cw, ch);
    let mut rep = ClampReport {
        threshold: t,
        ..ClampReport::default()
    };
    let (mut total, mut removed) = (0.0f64, 0.0f64);
    for chart in 0..mapping.chart_count() {
        let Some(mut face) = img.chart_image(chart) else {
            continue;
        };
        for j in 0..ch {
            for i in 0..cw {
                let k = (j * cw + i) as usize;
                let o = weights.get(chart, i, j);
                let y = luminance(face.pixels[k]);
                total += o * f64::from(y.max(0.0));
                if y > t && t > 0.0 {
                    let y2 = t * (1.0 + (y / t).ln());
                    let s = y2 / y;
                    face.pixels[k] = face.pixels[k].map(|c| c * s);
                    removed += o * f64::from(y - y2);
                    rep.texels += 1;
                }
            }
        }
        img.set_chart_image(chart, &face)?;
    }
    rep.energy_removed = if total > 0.0 { removed / total } else { 0.0 };
    Ok(rep)
}

/// Replaces each texel of a latlong's row by the mean of the `k` texels
/// centred on it (circularly; k odd, the row's texels about `width`
/// radians across in all), for rows whose texels are narrower than
/// `width`; the rows nearer the equator are left as they are. A row's sum,
/// and so its energy, is kept (to f64 rounding).
fn widen_polar_rows(img: &mut EnvImage, width: f64) {
    let (w, h) = (img.width() as usize, img.height() as usize);
    img.rows_mut()
        .enumerate()
        .par_bridge()
        .for_each(|(j, row)| {
            let theta = std::f64::consts::PI * (j as f64 + 0.5) / h as f64;
            let texel = std::f64::consts::TAU / w as f64 * theta.sin();
            let k = (width / texel).round() as usize;
            if k < 2 || w < 3 {
                return;
            }
            let k = (k | 1).min(if w % 2 == 1 { w } else { w - 1 });
            let half = k / 2;
            let mut prefix = vec![[0.0f64; 3]; w + 1];
            for (i, p) in row.iter().enumerate() {
                for c in 0..3 {
                    prefix[i + 1][c] = prefix[i][c] + f64::from(p[c]);
                }
            }
            let total = prefix[w];
            // Σ over the circular window [i − half, i + half].
            let window = |i: usize| -> [f64; 3] {
                let lo = i as isize - half as isize;
                let hi = i + half + 1;
                core::array::from_fn(|c| {
                    let mut s = if hi <= w {
                        prefix[hi][c]
                    } else {
                        total[c] + prefix[hi - w][c]
                    };
                    s -= if lo >= 0 {
                        prefix[lo as usize][c]
                    } else {
                        prefix[(lo + w as isize) as usize][c] - total[c]
                    };
                    s
                })
            };
            for (i, p) in row.iter_mut().enumerate() {
                *p = window(i).map(|v| (v / k as f64) as f32);
            }
        });
}

/// Clamps negative components at zero; returns how many texels had one.
fn clamp_negative(img: &mut EnvImage) -> u64 {
    let mut n = 0;
    for p in img.pixels_mut() {
        if p.iter().any(|c| *c < 0.0) {
            n += 1;
            *p = p.map(|c| c.max(0.0));
        }
    }
    n
}

/// The chain's face sizes for `opts`.
///
/// # Errors
///
/// `levels` beyond the chain (more than ⌊log2 size⌋ + 1), or 0; a size of
/// 0.
#[cfg_attr(feature = "instruments", visibility::make(pub))]
pub(crate) fn chain_sizes(opts: &BakeOptions) -> Result<Vec<u32>> {
    if let Some(sizes) = &opts.sizes {
        if sizes.is_empty() || sizes.contains(&0) {
            return Err(Error::options(format!(
                "level sizes {sizes:?}: at least one level, each at least 1"
            )));
        }
        if let RoughnessRule::Custom(r) = &opts.rule {
            if r.len() != sizes.len() {
                return Err(Error::options(format!(
                    "{} level sizes for {} roughness values",
                    sizes.len(),
                    r.len()
                )));
            }
        }
        return Ok(sizes.clone());
    }
    if opts.size == 0 {
        return Err(Error::options("--size must be at least 1"));
    }
    let full: Vec<u32> =
        std::iter::successors(Some(opts.size), |&s| (s > 1).then_some(s / 2)).collect();
    match opts.levels {
        Some(0) => Err(Error::options("--levels must be at least 1")),
        Some(n) if n > full.len() => Err(Error::options(format!(
            "--levels {n}: a chain from {}² has at most {} levels (down to 1×1)",
            opts.size,
            full.len()
        ))),
        Some(n) => Ok(full[..n].to_vec()),
        None => {
            let min = opts
                .min_size
                .unwrap_or_else(|| opts.rule.default_min_size())
                .max(1);
            let v: Vec<u32> = full.iter().copied().take_while(|&s| s >= min).collect();
            Ok(if v.is_empty() { vec![opts.size] } else { v })
        }
    }
}

/// A chain's levels: each one's perceptual roughness and face size, level
/// 0 first (for [`BakeOptions::sizes`] and [`RoughnessRule::Custom`]).
#[cfg_attr(not(feature = "instruments"), allow(dead_code))]
#[cfg_attr(feature = "instruments", visibility::make(pub))]
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct ChainShape {
    /// Each level's perceptual roughness, non-decreasing, level 0 at 0.
    pub roughness: Vec<f32>,
    /// Each level's face size.
    pub sizes: Vec<u32>,
}

impl ChainShape {
    /// `opts` set to bake this chain (its roughness list and sizes).
    #[cfg_attr(not(feature = "instruments"), allow(dead_code))]
    #[cfg_attr(feature = "instruments", visibility::make(pub))]
    #[must_use]
    pub(crate) fn apply<'a>(&self, opts: BakeOptions<'a>) -> BakeOptions<'a> {
        BakeOptions {
            rule: RoughnessRule::Custom(self.roughness.clone()),
            sizes: Some(self.sizes.clone()),
            ..opts
        }
    }
}

/// A chain whose levels follow their lobes: level 0 the source at `size`,
/// then levels from roughness `first` to 1 at equal steps of at most
/// `step` in the logarithm of the lobe's width (`specular::lobe_width`), each at
/// the smallest face whose centre texel (2·atan(1/s) for s²) is at most
/// 1/`texels` of its lobe's width, within [`min_size`, `max_size`]. Sizes
/// need not be powers of two: this is not a mip chain.
#[cfg_attr(not(feature = "instruments"), allow(dead_code))]
#[cfg_attr(feature = "instruments", visibility::make(pub))]
#[must_use]
pub(crate) fn lobe_chain(
    size: u32,
    max_size: u32,
    first: f32,
    step: f64,
    texels: f64,
    min_size: u32,
) -> ChainShape {
    let c = (std::f64::consts::SQRT_2 - 1.0).sqrt();
    let width = |r: f64| lobe_width(r * r);
    let alpha_of = |w: f64| (w / 2.0).tan() / c;
    let (w0, w1) = (
        width(f64::from(first).clamp(1e-3, 1.0)).ln(),
        width(1.0).ln(),
    );
    let steps = ((w1 - w0) / step.max(1e-3)).ceil().max(1.0) as usize;
    let mut roughness = vec![0.0f32];
    let mut sizes = vec![size];
    for k in 0..=steps {
        let w = (w0 + (w1 - w0) * k as f64 / steps as f64).exp();
        let r = if k == steps {
            1.0
        } else {
            alpha_of(w).sqrt().min(1.0)
        };
        // A face of s² has a centre texel of 2·atan(1/s).
        let texel = w / texels.max(1.0);
        let s = (1.0 / (texel / 2.0).tan()).ceil().min(f64::from(u32::MAX)) as u32;
        let s = s.clamp(min_size.min(max_size).max(1), max_size.max(1));
        roughness.push(r as f32);
        sizes.push(s);
    }
    ChainShape { roughness, sizes }
}

/// The chain envmap's own renderer bakes ([`crate::scene::lit::LitEnvironment::bake`]):
/// [`lobe_chain`] from roughness [`RENDER_FIRST_ROUGHNESS`] in steps of
/// [`RENDER_WIDTH_STEP`], [`RENDER_TEXELS_PER_LOBE`] texels per lobe width,
/// level 0 at `size`², the others from [`RENDER_MIN_SIZE`]² up to 1.5 ×
/// `size` (the first few, whose lobes are narrower than 4 of level 0's
/// texels). Below the first level the renderer reads the input itself
/// ([`crate::scene::lit::LitEnvironment::with_source`]). Its target against
/// the exact split sum is 2 % RMS and 0.5 % bias at every roughness from 0
/// to 1 (`docs/design/lighting-method.md`, "How exact the lit renders are", has the
/// measurements).
#[cfg_attr(not(feature = "instruments"), allow(dead_code))]
#[must_use]
pub(crate) fn render_chain(size: u32) -> ChainShape {
    let first = RENDER_FIRST_ROUGHNESS * (256.0 / size.max(1) as f32).sqrt();
    lobe_chain(
        size,
        size.saturating_add(size / 2),
        first.min(0.5),
        RENDER_WIDTH_STEP,
        RENDER_TEXELS_PER_LOBE,
        RENDER_MIN_SIZE,
    )
}

/// The roughness of [`render_chain`]'s first level above 0 at a level 0
/// of 256² (scaled by √(256/size) for others: 0.065 at 1024², 0.18 at
/// 128²). Below it the renderer reads the input itself through the near
/// field (`scene::lit`'s `NearField`), which follows the input read
/// bilinearly; a level lower than this, baked from the input's texels,
/// differs from that reading near a one-texel sun.
#[cfg_attr(not(feature = "instruments"), allow(dead_code))]
pub(crate) const RENDER_FIRST_ROUGHNESS: f32 = 0.13;

/// [`render_chain`]'s largest step in ln(lobe width) from one level to the
/// next (the width grows by at most e^0.25 = 1.28 per level). Blended
/// linearly in 1/α, two lobes this far apart stand for the lobe between
/// them within about 1 % (L² over the sphere, a point light).
#[cfg_attr(not(feature = "instruments"), allow(dead_code))]
pub(crate) const RENDER_WIDTH_STEP: f64 = 0.25;

/// Texels of [`render_chain`]'s levels per lobe width (at a face's
/// centre), up to 1.5 × level 0's size: a level read at its own roughness
/// is then within 0.4 % of the exact split sum, and more or fewer texels
/// per lobe hardly change the worst error between levels.
#[cfg_attr(not(feature = "instruments"), allow(dead_code))]
pub(crate) const RENDER_TEXELS_PER_LOBE: f64 = 4.0;

/// [`render_chain`]'s smallest face: roughness 1's level holds its lobe
/// (a 2² level reads it several per cent too dark or bright).
#[cfg_attr(not(feature = "instruments"), allow(dead_code))]
pub(crate) const RENDER_MIN_SIZE: u32 = 16;

/// The specular chain and what was done to make it.
#[derive(Clone, Debug)]
pub struct SpecularChain {
    /// The levels, largest first, each a cube (horizontal strip) in the
    /// output axes.
    pub levels: Vec<EnvImage>,
    /// One report per level.
    pub reports: Vec<LevelReport>,
    /// The brightest texels split out (from the input's own texels).
    pub bright: BrightReport,
    /// Energy bookkeeping: the input's, the base cube's and the split's.
    pub energy: EnergyReport,
    /// What the firefly clamp changed, if it was asked for.
    pub clamp: Option<ClampReport>,
    /// The base cube's face size.
    pub base_size: u32,
    /// Seconds per preparation stage (the base cube, the split, the
    /// pyramid, ...), in order; each level's time is in its report.
    pub stages: Vec<(&'static str, f64)>,
}

/// Energy per channel, Σ Ω·L over a map's texels with their exact solid
/// angles, in steradian-radiance units: what the bake took in and where it
/// went. `input ≈ base + split`: the base cube is a footprint average that
/// keeps the integral, the split texels are summed exactly.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct EnergyReport {
    /// The input's (negative texels included, as given).
    pub input: [f64; 3],
    /// The input's negative texels alone (≤ 0).
    pub negative: [f64; 3],
    /// The base cube's (the input without the split texels, resampled).
    pub base: [f64; 3],
    /// The split texels'.
    pub split: [f64; 3],
    /// Points per side of each base texel's footprint average.
    pub footprint_samples: u32,
}

impl EnergyReport {
    /// The largest relative gap |input − base − split| / |input| over the
    /// channels (0 for a black input).
    #[must_use]
    pub fn gap(&self) -> f64 {
        (0..3)
            .map(|c| {
                let d = self.input[c] - self.base[c] - self.split[c];
                if self.input[c] != 0.0 {
                    (d / self.input[c]).abs()
                } else {
                    d.abs()
                }
            })
            .fold(0.0, f64::max)
    }

    /// Per channel, the share of negative energy: −negative / (input −
    /// negative), the negative texels' integral over the positive texels'.
    #[must_use]
    pub fn negative_share(&self) -> [f64; 3] {
        core::array::from_fn(|c| {
            let pos = self.input[c] - self.negative[c];
            if pos > 0.0 {
                -self.negative[c] / pos
            } else {
                0.0
            }
        })
    }
}

/// An error counting the NaN and infinite texels of `src`, if it has any.
fn refuse_non_finite(src: &EnvImage) -> Result<()> {
    let bad = src
        .pixels()
        .iter()
        .filter(|p| !p.iter().all(|c| c.is_finite()))
        .count();
    if bad == 0 {
        return Ok(());
    }
    Err(Error::NonFiniteTexels { texels: bad as u64 })
}

/// The specular chain of `src` (any representation, finite texels).
/// `progress(level, levels)` is called as each level starts.
///
/// # Errors
///
/// NaN or infinite texels in `src`; bad sizes or levels ([`chain_sizes`]);
/// [`Error::Cancelled`].
#[cfg_attr(not(feature = "instruments"), allow(dead_code))]
#[cfg_attr(feature = "instruments", visibility::make(pub))]
pub(crate) fn specular_chain(
    src: &EnvImage,
    opts: &BakeOptions,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<SpecularChain> {
    let oracle = (opts.check > 0).then(|| Oracle::new(src));
    chain_checked(Cow::Borrowed(src), opts, progress, oracle.as_ref(), None)
}

/// [`specular_chain`], measuring against `oracle` (of `src`) when
/// [`BakeOptions::check`] asks, handing each level to `sink` as soon as it
/// is final, beside the making of the next.
fn chain_checked(
    input: Cow<'_, EnvImage>,
    opts: &BakeOptions,
    progress: &(dyn Fn(usize, usize) + Sync),
    oracle: Option<&Oracle>,
    sink: Option<&LevelSink<'_>>,
) -> Result<SpecularChain> {
    let src = &*input;
    refuse_non_finite(src)?;
    let sizes = chain_sizes(opts)?;
    let cube = Representation::new(
        AnyMapping::Cube,
        Atlas::CUBE_HORIZONTAL_STRIP,
        opts.axes.frame(AnyMapping::Cube),
    )?;
    let src_texels = u64::from(src.width()) * u64::from(src.height());
    let base_size = base_size(src_texels, &sizes);
    let copts = ConvertOptions {
        cancel: opts.cancel,
        ..ConvertOptions::default()
    };
    progress(0, sizes.len());
    let t0 = Instant::now();
    let mut stages = Stages::new();
    let mut level0 = convert(src, cube, 6 * sizes[0], sizes[0], &copts, None)?;
    let level0_seconds = t0.elapsed().as_secs_f64();
    stages.mark("level 0 resampled");
    let input_energy = channel_energy(src);
    stages.mark("input energy");
    // What the rest needs of the input once it is the working copy below.
    let below = Below {
        opts,
        sizes: &sizes,
        cube,
        copts,
        base_size,
        src_texels,
        src_frame: src.representation().frame.matrix(),
        input_pitch: texel_pitch(src),
        input_energy: input_energy.total,
        input_negative: input_energy.negative,
        oracle,
        progress,
    };
    // The brightest texels, split from the input's own texels before any
    // resampling; each cut into parts no wider than the narrowest lobe's
    // cluster cell. An input the bake owns is worked on in place, else
    // copied.
    let mut rest_src = input.into_owned();
    let clamp = match opts.clamp {
        Some(t) => {
            clamp_luminance(&mut level0, t)?;
            Some(clamp_luminance(&mut rest_src, t)?)
        }
        None => None,
    };
    let n = sizes.len();
    // Level 0 is final here: it is handed out while the rest is made.
    let clamped0 = clamp_negative(&mut level0);
    let report0 = level_report(sizes[0], 0.0, None, clamped0, level0_seconds, None);
    // A level handed out whose sink fails stops the bake at the next
    // level (the sink's error is the one returned).
    let failed = AtomicBool::new(false);
    let hand = |k: usize, img: &EnvImage, report: &LevelReport| -> Result<()> {
        match sink {
            None => Ok(()),
            Some(f) => f(k, img, report).inspect_err(|_| failed.store(true, Ordering::Relaxed)),
        }
    };
    let hand_out = Hand {
        hand: &hand,
        failed: &failed,
    };
    // Everything after level 0, made while level 0 is handed out.
    let (handed0, rest) = join(
        || hand(0, &level0, &report0),
        || below.make(rest_src, &mut stages, &hand_out),
    );
    handed0?;
    let (more, more_reports, bright, energy) = rest?;
    let mut levels = Vec::with_capacity(n);
    levels.push(level0);
    levels.extend(more);
    let mut reports = Vec::with_capacity(n);
    reports.push(report0);
    reports.extend(more_reports);
    Ok(SpecularChain {
        levels,
        reports,
        bright,
        energy,
        clamp,
        base_size,
        stages: stages.done,
    })
}

/// The base cube's face size for an input of `src_texels` and a chain of
/// `sizes`: about as many texels as the source (a 4096 × 2048 latlong
/// gives 1024² faces), the power of two at or below, at least twice the
/// chain's level 0 (level 1's lobe then spans a dozen base texels or more:
/// at level 0's own size it spans about three, and the base's box filter
/// shows in level 1) and at most 2048.
fn base_size(src_texels: u64, sizes: &[u32]) -> u32 {
    let per_face = ((src_texels as f64 / 6.0).sqrt() * 1.05).max(1.0) as u32;
    let floor_pow2 = 1u32 << (31 - per_face.leading_zeros());
    let top = sizes.iter().copied().max().unwrap_or(1);
    floor_pow2.clamp((2 * top).min(2048), 2048)
}

/// Where a bake's time goes, stage by stage: each stage's name and the
/// seconds since the one before.
struct Stages {
    done: Vec<(&'static str, f64)>,
    last: Instant,
}

impl Stages {
    fn new() -> Self {
        Self {
            done: Vec::new(),
            last: Instant::now(),
        }
    }

    /// The stage `name` ends now.
    fn mark(&mut self, name: &'static str) {
        self.done.push((name, self.last.elapsed().as_secs_f64()));
        self.last = Instant::now();
    }
}

/// How levels are handed out: the sink's call, and the flag its failure
/// sets (which stops the levels still to make).
struct Hand<'h> {
    hand: &'h (dyn Fn(usize, &EnvImage, &LevelReport) -> Result<()> + Sync),
    failed: &'h AtomicBool,
}

/// A level's report.
fn level_report(
    size: u32,
    roughness: f32,
    method: Option<Method>,
    clamped: u64,
    seconds: f64,
    measured: Option<LevelError>,
) -> LevelReport {
    LevelReport {
        size,
        roughness,
        method: match method {
            None => "resampled",
            Some(Method::Exact { .. }) => "exact",
            Some(Method::Sampled { .. }) => "sampled",
        },
        samples: match method {
            Some(Method::Sampled { samples }) => samples,
            _ => 0,
        },
        source_level: match method {
            Some(Method::Exact { level }) => Some(level),
            _ => None,
        },
        clamped,
        seconds,
        measured,
    }
}

/// What the levels below level 0 are made from: the bake's options and
/// what it knows of its input.
struct Below<'a> {
    opts: &'a BakeOptions<'a>,
    sizes: &'a [u32],
    cube: Representation,
    copts: ConvertOptions<'a>,
    base_size: u32,
    src_texels: u64,
    /// The input's axes.
    src_frame: Mat3,
    /// The input's texel pitch (radians).
    input_pitch: f64,
    input_energy: [f64; 3],
    input_negative: [f64; 3],
    oracle: Option<&'a Oracle<'a>>,
    progress: &'a (dyn Fn(usize, usize) + Sync),
}

/// The levels below level 0, their reports, the bright split's report and
/// the energy accounting.
type LevelsBelow = (Vec<EnvImage>, Vec<LevelReport>, BrightReport, EnergyReport);

impl Below<'_> {
    /// Splits the bright texels from `rest_src` (the input, clamped), makes
    /// the base cube of the rest and its pyramid, and every level below
    /// level 0, handing each out as the next is made.
    fn make(
        &self,
        mut rest_src: EnvImage,
        stages: &mut Stages,
        hand: &Hand<'_>,
    ) -> Result<LevelsBelow> {
        let (opts, n) = (self.opts, self.sizes.len());
        let narrowest = (1..n)
            .map(|k| opts.rule.roughness(k, n))
            .filter(|&r| r > 0.0)
            .fold(1.0f32, f32::min);
        let alpha_min = f64::from(narrowest) * f64::from(narrowest);
        let mut bright =
            split_bright(&mut rest_src, opts.bright_max, lobe_width(alpha_min) / PART)?;
        stages.mark("bright texels split");
        let (base, n_foot) = self.base_cube(rest_src)?;
        stages.mark("base cube");
        let base_energy = channel_energy(&base);
        // The split points from the input's axes into the base's.
        let to_base = base.representation().frame.matrix().transpose() * self.src_frame;
        for d in &mut bright.dirs {
            *d = (to_base * *d).normalize();
        }
        let energy = EnergyReport {
            input: self.input_energy,
            negative: self.input_negative,
            base: base_energy.total,
            split: bright.report.energy,
            footprint_samples: n_foot,
        };
        let rest = Pyramid::new(base, 1)?;
        stages.mark("pyramid");
        cancel::check(opts.cancel)?;
        let plans = self.plans(&rest);
        // Only the levels the samples read are prepared for trilinear reads.
        let first = plans
            .iter()
            .filter_map(|&(r, m)| match m {
                Method::Sampled { samples } => {
                    Some(finest_sampled_level(&rest, r, samples, opts.lod_bias))
                }
                Method::Exact { .. } => None,
            })
            .min()
            .unwrap_or(rest.len() - 1);
        let sampler = Trilinear::starting_at(&rest, first);
        stages.mark("bordered levels");
        let (levels, reports) = self.levels(&rest, &sampler, &bright, &plans, hand)?;
        Ok((levels, reports, bright.report, energy))
    }

    /// The base cube: the footprint average of `rest_src`, each texel the
    /// mean over N × N points of its footprint of the input's bilinear
    /// reconstruction (which integrates to the input's own integral), N ≥ 2
    /// making the points at most 2/3 of an input texel apart, so that the
    /// base's energy plus the split's is the input's (a nearest-texel
    /// average would not be: its points divide the input's texels
    /// unevenly). With N.
    fn base_cube(&self, mut rest_src: EnvImage) -> Result<(EnvImage, u32)> {
        let input_texel = (4.0 * std::f64::consts::PI / self.src_texels.max(1) as f64).sqrt();
        let base_texel = std::f64::consts::FRAC_PI_2 / f64::from(self.base_size);
        // A base between one and two times as dense as the input takes at
        // least 3 × 3 points: 2 × 2 there fall unevenly on the input's
        // texels, and the base's energy drifts from the input's.
        let ratio = base_texel / input_texel;
        let least = if (0.5..1.0).contains(&ratio) { 3 } else { 2 };
        let n_foot = ((1.5 * ratio).ceil() as u32).clamp(least, 16);
        // A latlong's rows near the poles hold texels far narrower than a base
        // texel, which N × N points would alias (a few hot texels near a pole
        // read at half or twice their energy); a circular box along each such
        // row, as wide as a base texel, keeps the row's energy exactly (its
        // texels have equal solid angles) and leaves nothing narrow to alias.
        if rest_src.mapping() == AnyMapping::LatLong && rest_src.atlas().cols == 1 {
            widen_polar_rows(&mut rest_src, base_texel);
        }
        let base = convert(
            &rest_src,
            self.cube,
            6 * self.base_size,
            self.base_size,
            &ConvertOptions {
                filter: Filter::Bilinear,
                samples: Some(n_foot),
                ..self.copts
            },
            None,
        )?;
        Ok((base, n_foot))
    }

    /// Each level's roughness and method: exact where that costs no more
    /// than sampling (a source texel's weight, eight output texels at a
    /// time, costs about a sixteenth of a sample's trilinear read), or when
    /// asked.
    fn plans(&self, rest: &Pyramid) -> Vec<(f32, Method)> {
        let (opts, n) = (self.opts, self.sizes.len());
        self.sizes
            .iter()
            .enumerate()
            .skip(1)
            .map(|(k, &size)| {
                let roughness = opts.rule.roughness(k, n);
                let out_texels = 6 * u64::from(size) * u64::from(size);
                let samples = opts.samples.unwrap_or_else(|| {
                    let n = opts.quality.samples_for(roughness, out_texels);
                    // A lobe under two of the input's texels across meets their
                    // edges as the sharpest thing in the map: twice the samples
                    // (level 1 of a 512² chain from a 512 × 256 input, say).
                    let alpha = f64::from(roughness) * f64::from(roughness);
                    if lobe_width(alpha) < SHARP_TEXELS * self.input_pitch {
                        n.saturating_mul(2).min(4096)
                    } else {
                        n
                    }
                });
                let el = exact_level(rest, roughness);
                let src_texels = rest.level(el).pixels().len() as u64;
                let method = if opts.exact
                    || src_texels <= EXACT_PER_SAMPLE * u64::from(samples)
                    || out_texels.saturating_mul(src_texels) <= EXACT_BUDGET
                {
                    Method::Exact { level: el }
                } else {
                    Method::Sampled { samples }
                };
                (roughness, method)
            })
            .collect()
    }

    /// The levels below level 0 as `plans` say, each measured against the
    /// oracle when asked; level k is made while level k − 1 is handed out
    /// (level 0 already was).
    fn levels(
        &self,
        rest: &Pyramid,
        sampler: &Trilinear<'_>,
        bright: &Bright,
        plans: &[(f32, Method)],
        hand: &Hand<'_>,
    ) -> Result<(Vec<EnvImage>, Vec<LevelReport>)> {
        let (opts, n) = (self.opts, self.sizes.len());
        let mut levels: Vec<EnvImage> = Vec::with_capacity(n);
        let mut reports: Vec<LevelReport> = Vec::with_capacity(n);
        for (i, (&size, &(roughness, method))) in self.sizes[1..].iter().zip(plans).enumerate() {
            let k = i + 1;
            if hand.failed.load(Ordering::Relaxed) {
                return Err(Error::Cancelled);
            }
            (self.progress)(k, n);
            let make = || -> Result<_> {
                let t = Instant::now();
                let job = LevelJob {
                    rest,
                    sampler,
                    bright,
                    roughness,
                    method,
                    lod_bias: opts.lod_bias,
                    level: k as u32,
                    cancel: opts.cancel,
                };
                let mut img = prefilter_level(&job, self.cube, 6 * size, size)?;
                let clamped = clamp_negative(&mut img);
                let seconds = t.elapsed().as_secs_f64();
                // --check: every level, exact or sampled, against the oracle.
                let measured = match self.oracle {
                    Some(o) if opts.check > 0 => {
                        Some(measure_level(o, roughness, &img, opts.check, k as u32)?)
                    }
                    _ => None,
                };
                Ok((img, clamped, seconds, measured))
            };
            let previous = || match (levels.last(), reports.last()) {
                (Some(prev), Some(r)) => (hand.hand)(k - 1, prev, r),
                _ => Ok(()),
            };
            let (handed, made) = join(previous, make);
            handed?;
            let (img, clamped, seconds, measured) = made?;
            reports.push(level_report(
                size,
                roughness,
                Some(method),
                clamped,
                seconds,
                measured,
            ));
            levels.push(img);
        }
        if let (Some(last), Some(r)) = (levels.last(), reports.last()) {
            (hand.hand)(n - 1, last, r)?;
        }
        Ok((levels, reports))
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
