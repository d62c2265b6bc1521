// The bright split: the brightest texels of a map taken out to be summed
// exactly to every level, each cut into parts no wider than a lobe's cell.

use envmap_core::glam::Vec3;
use envmap_core::texel::texel_bounds;
use envmap_core::{AnyMapping, ChartUv, Mapping};

use super::*;
use crate::error::Result;
use crate::filter::weights::TexelWeights;
use crate::image::{luminance, EnvImage};

/// Texels taken out of a map, to be summed to every level: points (a texel's
/// centre, or the centres of the parts a texel was cut into) with their
/// directions (in the map's own axes) and Ω·L.
#[cfg_attr(feature = "instruments", visibility::make(pub))]
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct Bright {
    /// Direction of each point (unit, the map's axes).
    pub dirs: Vec<Vec3>,
    /// Ω·L per point (solid angle times radiance; negative values kept).
    pub omega_l: Vec<[f32; 3]>,
    /// What was taken, for reports.
    pub report: BrightReport,
}

/// How many texels `split_bright` took and what they carry.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BrightReport {
    /// The threshold on the largest absolute channel.
    pub threshold: f32,
    /// Texels taken out.
    pub texels: u64,
    /// Points they were cut into (each texel into m × m parts where the
    /// narrowest lobe asks for it).
    pub points: u64,
    /// Their share of the map's energy by luminance (Σ Ω·Y of the texels
    /// over Σ Ω·max(Y, 0) of the map).
    pub energy_share: f64,
    /// Σ Ω·L per channel of the texels taken (negative values count).
    pub energy: [f64; 3],
}

/// The largest absolute channel of a texel: the split's measure, so that a
/// negative lobe ringing around a sun counts as much as its overshoot.
#[inline]
#[must_use]
pub(crate) fn peak_magnitude(p: [f32; 3]) -> f32 {
    p[0].abs().max(p[1].abs()).max(p[2].abs())
}

/// Takes out of `img` (in place, setting them to black) the texels whose
/// largest absolute channel (`peak_magnitude`) exceeds both P and
/// [`SPLIT_MEAN`] × its solid-angle mean, with P the solid-angle-weighted
/// 99th percentile of that measure (the value that 1 % of the sphere
/// exceeds, read from a histogram of 64 bins per octave: a value's bin is
/// its f32 exponent and top six mantissa bits, P the lower edge of its
/// bin), at most `max_texels` of them (the largest); returns them with
/// their energy. The brightest 1 % of the sphere, where it stands out of
/// the map's mean: a sun, the lamps and windows of an interior, not the
/// bright half of a smooth sky. Measured by the largest absolute channel, the
/// rule takes a sun and the ringing around it that lossy compression leaves
/// (negative texels of a large magnitude), so the two are summed exactly
/// together and cancel as they do in the data.
///
/// Each texel taken is cut into m × m parts of its chart coordinates, each
/// with its exact solid angle and its centre's direction, m the smallest
/// that makes a part at most `pitch` radians across (at most 16; `pitch`
/// infinite for one point per texel). The rule is stated in the bake's
/// manifest and `docs/lighting.md`.
#[cfg_attr(feature = "instruments", visibility::make(pub))]
pub(crate) fn split_bright(img: &mut EnvImage, max_texels: usize, pitch: f64) -> Result<Bright> {
    let mapping = img.mapping();
    let (cw, ch) = img.cell_size();
    let weights = TexelWeights::new(mapping, cw, ch);
    let rows: Vec<(u32, u32)> = (0..mapping.chart_count())
        .flat_map(|c| (0..ch).map(move |j| (c, j)))
        .filter(|&(c, j)| img.chart_row(c, j).is_some())
        .collect();
    let census = Census::of(img, &weights, &rows);
    let threshold = census.threshold();
    let cand = candidates(img, &weights, &rows, &census.maxima, threshold, max_texels);
    let mut out = Bright {
        report: BrightReport {
            threshold,
            ..BrightReport::default()
        },
        ..Bright::default()
    };
    let mut carried = 0.0f64;
    for &(_, chart, i, j) in &cand {
        let (u0, u1) = texel_bounds(i, cw);
        let (v0, v1) = texel_bounds(j, ch);
        let (Some(d), Some(p)) = (
            texel_dir(mapping, chart, 0.5 * (u0 + u1), 0.5 * (v0 + v1)),
            img.chart_texel(chart, i, j),
        ) else {
            continue;
        };
        let o = weights.get(chart, i, j);
        cut_texel(
            mapping,
            chart,
            ((u0, u1), (v0, v1)),
            (d, o, p),
            pitch,
            &mut out,
        );
        for (e, v) in out.report.energy.iter_mut().zip(p) {
            *e += o * f64::from(v);
        }
        carried += o * f64::from(luminance(p));
        out.report.texels += 1;
        img.set_chart_texel(chart, i, j, [0.0; 3]);
    }
    out.report.points = out.dirs.len() as u64;
    out.report.energy_share = if census.total > 0.0 {
        carried / census.total
    } else {
        0.0
    };
    Ok(out)
}

/// Bits below the top six of the mantissa: a histogram bin of the split's
/// measure is its f32 exponent and top six mantissa bits.
pub(super) const BIN_SHIFT: u32 = 17;

/// The histogram's bins.
pub(super) const BINS: usize = (0x7f80_0000u32 >> BIN_SHIFT) as usize;

/// The direction at chart point `(u, v)`.
pub(super) fn texel_dir(mapping: AnyMapping, chart: u32, u: f64, v: f64) -> Option<Vec3> {
    mapping.inverse(ChartUv::new(chart, u as f32, v as f32))
}

/// Row `j` of `chart` as (i, texel) pairs, read in place.
pub(super) fn row_texels(
    img: &EnvImage,
    chart: u32,
    j: u32,
) -> impl Iterator<Item = (u32, [f32; 3])> + '_ {
    let cw = img.cell_size().0;
    let (row, reversed) = img.chart_row(chart, j).unwrap_or((&[], false));
    row.iter().enumerate().map(move |(k, p)| {
        let i = if reversed {
            cw - 1 - k as u32
        } else {
            k as u32
        };
        (i, *p)
    })
}

/// What [`split_bright`]'s threshold is read from: the solid-angle-weighted
/// histogram of the split's measure, Σ Ω·Y⁺, Σ Ω, Σ Ω·peak, and each row's
/// largest value (so that the search for the texels above the threshold
/// reads only the rows that hold some).
pub(super) struct Census {
    hist: Vec<f64>,
    total: f64,
    sphere: f64,
    peak: f64,
    maxima: Vec<f32>,
}

impl Census {
    /// The census of `rows` of `img`, in fixed blocks of rows added in
    /// order: the same sums at any thread count.
    fn of(img: &EnvImage, weights: &TexelWeights, rows: &[(u32, u32)]) -> Self {
        // Positive finite values by their bits (monotone in the value);
        // zero and non-finite ones in bin 0.
        let bin = |y: f32| -> usize {
            if y > 0.0 && y.is_finite() {
                (y.to_bits() >> BIN_SHIFT) as usize
            } else {
                0
            }
        };
        let parts: Vec<Self> = rows
            .par_chunks(256)
            .map(|block| {
                let (mut hist, mut total, mut sphere, mut peak) =
                    (vec![0.0f64; BINS], 0.0f64, 0.0f64, 0.0f64);
                let mut maxima = Vec::with_capacity(block.len());
                for &(chart, j) in block {
                    let mut top = f32::NEG_INFINITY;
                    for (i, p) in row_texels(img, chart, j) {
                        let o = weights.get(chart, i, j);
                        if o > 0.0 {
                            let m = peak_magnitude(p);
                            hist[bin(m)] += o;
                            total += o * f64::from(luminance(p).max(0.0));
                            sphere += o;
                            peak += o * f64::from(m);
                            top = top.max(m);
                        }
                    }
                    maxima.push(top);
                }
                Self {
                    hist,
                    total,
                    sphere,
                    peak,
                    maxima,
                }
            })
            .collect();
        let mut all = Self {
            hist: vec![0.0f64; BINS],
            total: 0.0,
            sphere: 0.0,
            peak: 0.0,
            maxima: Vec::with_capacity(rows.len()),
        };
        for part in &parts {
            all.peak += part.peak;
            for (a, b) in all.hist.iter_mut().zip(&part.hist) {
                *a += b;
            }
            all.total += part.total;
            all.sphere += part.sphere;
            all.maxima.extend_from_slice(&part.maxima);
        }
        all
    }

    /// The larger of P, the lower edge of the bin where the largest 1 % of
    /// the sphere begins, and [`SPLIT_MEAN`] × the solid-angle mean.
    fn threshold(&self) -> f32 {
        let mut acc = 0.0;
        let mut p99 = 0.0f32;
        for (k, h) in self.hist.iter().enumerate().rev() {
            acc += h;
            if acc >= 0.01 * self.sphere {
                p99 = f32::from_bits((k as u32) << BIN_SHIFT);
                break;
            }
        }
        let mean = if self.sphere > 0.0 {
            self.peak / self.sphere
        } else {
            0.0
        };
        p99.max((SPLIT_MEAN * mean) as f32).max(f32::MIN_POSITIVE)
    }
}

/// The texels of `rows` above `threshold` (the rows whose largest value
/// `maxima` is above it), the largest `max_texels` of them, as (measure,
/// chart, i, j) in chart, row, column order.
pub(super) fn candidates(
    img: &EnvImage,
    weights: &TexelWeights,
    rows: &[(u32, u32)],
    maxima: &[f32],
    threshold: f32,
    max_texels: usize,
) -> Vec<(f32, u32, u32, u32)> {
    let mut cand: Vec<(f32, u32, u32, u32)> = Vec::new();
    for (&(chart, j), _) in rows.iter().zip(maxima).filter(|(_, &m)| m > threshold) {
        for (i, p) in row_texels(img, chart, j) {
            let m = peak_magnitude(p);
            if m > threshold && weights.get(chart, i, j) > 0.0 {
                cand.push((m, chart, i, j));
            }
        }
    }
    if cand.len() > max_texels {
        cand.select_nth_unstable_by(max_texels, |a, b| b.0.total_cmp(&a.0));
        cand.truncate(max_texels);
    }
    cand.sort_unstable_by_key(|&(_, c, i, j)| (c, j, i));
    cand
}

/// Adds to `out` the points of one texel taken, its chart bounds `(u, v)`,
/// its centre's direction `d`, solid angle `o` and value `p`: the texel
/// whole, or cut into m × m parts, each with its exact solid angle and its
/// centre's direction, m the smallest that makes a part at most `pitch`
/// radians across (at most 16).
pub(super) fn cut_texel(
    mapping: AnyMapping,
    chart: u32,
    ((u0, u1), (v0, v1)): ((f64, f64), (f64, f64)),
    (d, o, p): (Vec3, f64, [f32; 3]),
    pitch: f64,
    out: &mut Bright,
) {
    // The texel's width: the largest angle between its corners and its
    // centre, twice.
    let width = [(u0, v0), (u1, v0), (u0, v1), (u1, v1)]
        .iter()
        .filter_map(|&(u, v)| texel_dir(mapping, chart, u, v))
        .map(|c| 2.0 * f64::from(c.angle_between(d)))
        .fold(0.0f64, f64::max);
    let m = if pitch.is_finite() && pitch > 0.0 {
        ((width / pitch).ceil() as u32).clamp(1, 16)
    } else {
        1
    };
    if m == 1 {
        out.dirs.push(d);
        out.omega_l.push(p.map(|v| (o * f64::from(v)) as f32));
        return;
    }
    let (du, dv) = ((u1 - u0) / f64::from(m), (v1 - v0) / f64::from(m));
    for b in 0..m {
        for a in 0..m {
            let (ua, va) = (u0 + f64::from(a) * du, v0 + f64::from(b) * dv);
            let os = mapping.solid_angle(chart, ua, ua + du, va, va + dv);
            let Some(ds) =
                texel_dir(mapping, chart, ua + 0.5 * du, va + 0.5 * dv).filter(|_| os > 0.0)
            else {
                continue;
            };
            out.dirs.push(ds);
            out.omega_l.push(p.map(|v| (os * f64::from(v)) as f32));
        }
    }
}

/// `split_bright` takes texels above this many times the map's mean (by
/// the largest absolute channel, solid-angle weighted) as well as above its
/// 99th percentile. On real HDRIs baked at a chain denser than their
/// texels (where the sampled levels meet lamps and windows texel by
/// texel), a threshold on the percentile alone (16 × P99) left lamps to
/// the sampling and many maps outside the 1 % bound; the percentile and 4 ×
/// the mean bring them within it, and the mean keeps a smooth sky, whose
/// 99th percentile is no outlier, from being split for nothing.
pub const SPLIT_MEAN: f64 = 4.0;

/// The split texels are cut into parts at most 1/`PART` of the narrowest
/// level's lobe across (`split_bright`'s `pitch`): finer parts (1/8,
/// 1/16) gain nothing on real HDRIs (a Barnes–Hut tree sums them, near
/// each lobe part by part).
pub const PART: f64 = 4.0;
