// The specular chain: its sizes and roughnesses, the input's clamps, the
// base cube and its pyramid, and the levels made from them, each handed out
// as the next is made.

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use envmap_core::glam::Mat3;
use envmap_core::{AnyMapping, Atlas, Mapping};

use std::borrow::Cow;

use super::*;
use crate::cancel;
use crate::error::{Error, Result};
use crate::filter::brdf::{alpha_of_lobe_width, lobe_width};
use crate::filter::pyramid::{Pyramid, Trilinear};
use crate::filter::sample::Filter;
use crate::filter::specular::{
    exact_level, finest_sampled_level, prefilter_level, split_bright, texel_pitch, Bright,
    BrightReport, LevelJob, Method, RoughnessRule, PART,
};
use crate::filter::weights::channel_energy;
use crate::filter::{convert, ConvertOptions};
use crate::image::{luminance, EnvImage, Representation};
use crate::instruments::Oracle;

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
pub(super) fn widen_polar_rows(img: &mut EnvImage, width: f64) {
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
pub(super) fn clamp_negative(img: &mut EnvImage) -> u64 {
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
/// `step` in the logarithm of the lobe's width (`brdf::lobe_width`), each at
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
    let width = |r: f64| lobe_width(r * r);
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
            alpha_of_lobe_width(w).sqrt().min(1.0)
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
pub(super) fn refuse_non_finite(src: &EnvImage) -> Result<()> {
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
pub(super) fn chain_checked(
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
pub(super) fn base_size(src_texels: u64, sizes: &[u32]) -> u32 {
    let per_face = ((src_texels as f64 / 6.0).sqrt() * 1.05).max(1.0) as u32;
    let floor_pow2 = 1u32 << (31 - per_face.leading_zeros());
    let top = sizes.iter().copied().max().unwrap_or(1);
    floor_pow2.clamp((2 * top).min(2048), 2048)
}

/// Where a bake's time goes, stage by stage: each stage's name and the
/// seconds since the one before.
pub(super) struct Stages {
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
pub(super) struct Hand<'h> {
    hand: &'h (dyn Fn(usize, &EnvImage, &LevelReport) -> Result<()> + Sync),
    failed: &'h AtomicBool,
}

/// A level's report.
pub(super) fn level_report(
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
pub(super) struct Below<'a> {
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
pub(super) type LevelsBelow = (Vec<EnvImage>, Vec<LevelReport>, BrightReport, EnergyReport);

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
