// The solid-angle-weighted halving that makes each level from the one
// above: the even fast path and the odd fallback.

use crate::par::*;
use envmap_core::atlas::{Atlas, Turn};
use envmap_core::texel::texel_center;
use envmap_core::{AnyMapping, Mapping};
use wide::f32x4;

use crate::error::Result;
use crate::filter::weights::TexelWeights;
use crate::image::layout::check_compatible;
use crate::image::{EnvImage, Representation, RgbImage};

/// The chart size one level down: height ⌊h/2⌋ (at least 1), width by the
/// chart's aspect `aw : ah`.
#[must_use]
pub(crate) fn next_chart_size(w: u32, h: u32, aw: u32, ah: u32) -> (u32, u32) {
    let _ = w;
    let h2 = (h / 2).max(1);
    let w2 = (h2 * aw / ah.max(1)).max(1);
    (w2, h2)
}

/// One level down from `img` (see the [module docs](super)); `weights` are
/// `img`'s texel solid angles ([`TexelWeights::new`] of its chart size).
///
/// # Errors
///
/// Only if the smaller image cannot be made (it never exceeds the
/// original's size, so in practice never).
pub(crate) fn downsample(img: &EnvImage, weights: &TexelWeights) -> Result<EnvImage> {
    downsample_to(img, weights, img.representation().atlas)
}

/// [`downsample`] into another atlas of the same mapping (its charts are
/// the same texel for texel; only where they are stored differs): a cube
/// cross's levels as a strip, say, without the cross's empty cells.
///
/// # Errors
///
/// If `atlas` is not an atlas of `img`'s mapping.
pub(crate) fn downsample_to(
    img: &EnvImage,
    weights: &TexelWeights,
    atlas: Atlas,
) -> Result<EnvImage> {
    let repr = Representation {
        atlas,
        ..*img.representation()
    };
    check_compatible(repr.mapping, &atlas)?;
    let (cw, ch) = img.cell_size();
    let (w2, h2) = next_chart_size(cw, ch, atlas.cell_aspect_w, atlas.cell_aspect_h);
    let (iw, ih) = (atlas.cols * w2, atlas.rows * h2);
    let mut out = EnvImage::new(iw, ih, repr)?;
    if cw == 2 * w2 && ch == 2 * h2 {
        halve(img, weights, &mut out);
        return Ok(out);
    }
    let mapping = repr.mapping;
    for chart in 0..mapping.chart_count() {
        let Some(src) = img.chart_image(chart) else {
            continue;
        };
        let dst = resample(&src, mapping, chart, w2, h2);
        out.set_chart_image(chart, &dst)?;
    }
    Ok(out)
}

/// The even case: each texel of `out` the solid-angle-weighted mean of the
/// 2 × 2 texels of `img` it covers, every chart at once, written in place
/// row by row of the stored image (one pass over each, no copies). A row
/// stored turned by half a turn is read in chart order from its end; the
/// row made is turned over where `out` stores the chart the other way round
/// (`out` in another atlas: a cross's levels as a strip).
fn halve(img: &EnvImage, weights: &TexelWeights, out: &mut EnvImage) {
    let (w2, h2) = out.cell_size();
    let atlas = *out.atlas();
    let stride = out.width() as usize;
    out.pixels_mut()
        .par_chunks_mut(stride)
        .enumerate()
        .for_each(|(y, line)| {
            let (cell_row, ly) = (y as u32 / h2, y as u32 % h2);
            let mut taps = RowTaps::default();
            for col in 0..atlas.cols {
                let Some(cell) = atlas.cell_at(col, cell_row) else {
                    continue;
                };
                let turned = cell.turn == Turn::Half;
                // The chart row this stored row holds, and the two above it.
                let cj = if turned { h2 - 1 - ly } else { ly };
                let dst = &mut line[(col * w2) as usize..][..w2 as usize];
                halve_chart_row(img, weights, (cell.chart, cj), None, turned, dst, &mut taps);
            }
        });
}

/// Row `cj` of `chart` one level down from `src` into `dst`, turned (its
/// texels in reverse) where `turned`; `taps` holds the weights of the row
/// last made, reused where this row's are the same. Left as it is where
/// `src` lacks the chart. `next` is the row (chart, row) to be made after
/// this one, whose texels this one asks for as it ends ([`halve_row`]).
pub(super) fn halve_chart_row(
    src: &impl ChartRows,
    weights: &TexelWeights,
    (chart, cj): (u32, u32),
    next: Option<(u32, u32)>,
    turned: bool,
    dst: &mut [[f32; 3]],
    taps: &mut RowTaps,
) {
    let rows = |(chart, cj): (u32, u32)| {
        Some((
            src.chart_row(chart, 2 * cj)?,
            src.chart_row(chart, 2 * cj + 1)?.0,
        ))
    };
    let Some(((r0, stored_turned), r1)) = rows((chart, cj)) else {
        return;
    };
    let ahead = next.and_then(rows).map_or([&[][..]; 2], |((n0, _), n1)| {
        [n0.as_flattened(), n1.as_flattened()]
    });
    let t = taps.of(weights, chart, cj);
    if stored_turned {
        halve_row::<true>(r0, r1, t, ahead, dst);
    } else {
        halve_row::<false>(r0, r1, t, ahead, dst);
    }
    if stored_turned != turned {
        dst.reverse();
    }
}

/// The weights of the four texels each texel of one halved row is made
/// from ([`TexelWeights::halving_taps`]), kept for the next row made: the
/// six faces of a cube (a latlong's rows) share their weights, so a row of
/// every face is made with the weights found once.
#[derive(Default)]
pub(super) struct RowTaps {
    /// The chart (0 where [`TexelWeights::shared`]) and row made last.
    made: Option<(u32, u32)>,
    taps: Vec<[f32; 4]>,
    rows: [Vec<f64>; 2],
}

impl RowTaps {
    /// The weights of row `cj` of `chart` one level down.
    fn of(&mut self, weights: &TexelWeights, chart: u32, cj: u32) -> &[[f32; 4]] {
        let key = (if weights.shared() { 0 } else { chart }, cj);
        if self.made != Some(key) {
            weights.halving_taps(chart, cj, &mut self.rows, &mut self.taps);
            // The rows come in row order across the charts: the weights of
            // the next row are the next made.
            weights.ask_for_halving(chart, cj + 1);
            self.made = Some(key);
        }
        &self.taps
    }
}

/// The rows of a level's charts, as halving reads them.
pub(super) trait ChartRows: Sync {
    /// Row `j` of `chart` as stored, and whether it is stored turned (its
    /// texels in reverse order); `None` for a chart or row not stored.
    fn chart_row(&self, chart: u32, j: u32) -> Option<(&[[f32; 3]], bool)>;
}

impl ChartRows for EnvImage {
    fn chart_row(&self, chart: u32, j: u32) -> Option<(&[[f32; 3]], bool)> {
        EnvImage::chart_row(self, chart, j)
    }
}

/// The charts of `mapping` that `src` stores, a bit per chart.
pub(super) fn present(src: &impl ChartRows, mapping: AnyMapping) -> u32 {
    (0..mapping.chart_count().min(32))
        .filter(|&c| src.chart_row(c, 0).is_some())
        .fold(0, |m, c| m | 1 << c)
}

/// How far ahead (in floats: 96 texels, 1 152 bytes) [`halve_row`] asks
/// for the rows it reads.
const HALVING_AHEAD: usize = 6 * 96;

/// How many rows of a level a worker makes in one run, each asking for the
/// next one's texels as it ends ([`halve_row`]); the runs are shared out
/// among the threads.
pub(super) const HALVING_RUN: usize = 32;

/// Asks the processor to start loading float `at` of both rows (where
/// they have it), without waiting: a hint only. Does nothing off x86-64.
#[inline(always)]
fn ask_for_both(r0: &[f32], r1: &[f32], at: usize) {
    #[cfg(all(target_arch = "x86_64", target_feature = "sse"))]
    if let (Some(p), Some(q)) = (r0.get(at), r1.get(at)) {
        safe_arch::prefetch_t0(p);
        safe_arch::prefetch_t0(q);
    }
    #[cfg(not(all(target_arch = "x86_64", target_feature = "sse")))]
    let _ = (r0, r1, at);
}

/// One row of the even case: `dst[k]` the weighted sum
/// ((a₀·t₀ + a₁·t₁) + b₀·t₂) + b₁·t₃ of texels a = `2k`, `2k + 1` of row
/// `r0` and b of `r1` (chart order) with `taps[k]`, in f32, four floats at
/// a time (each texel's three channels and one to spare); a texel whose
/// weights are all 0 is black. `TURNED`: the rows are stored in
/// reverse, so chart texel `2k` is stored at `2n − 1 − 2k` (`n` texels
/// made), and `dst` is written in the rows' stored order. The weights sum
/// to 1 to f32 rounding, so the sum is within a few f32 roundings of the
/// f64 mean of the four texels.
///
/// Both rows are asked for [`HALVING_AHEAD`] floats ahead of the texels
/// being made (the first that far at once): rows of a cube face are short
/// streams (12 KiB for 1024 texels) that the processor's own prefetching
/// is slow to pick up, and without this, halving a cube waits on memory
/// for most of its time.
/// Near the end of the rows, the asking goes on into `next`, the two rows
/// (flattened) that the row made after this one reads, so that its start
/// does not wait either (empty where there is none).
fn halve_row<const TURNED: bool>(
    r0: &[[f32; 3]],
    r1: &[[f32; 3]],
    taps: &[[f32; 4]],
    [n0, n1]: [&[f32]; 2],
    dst: &mut [[f32; 3]],
) {
    let n = dst
        .len()
        .min(taps.len())
        .min(r0.len() / 2)
        .min(r1.len() / 2);
    if n == 0 {
        return;
    }
    // Stored texels 2k and 2k + 1 are chart texels (first, second) of the
    // pair; a turned row's pairs come in reverse chart order.
    let (first, second) = if TURNED { (3, 0) } else { (0, 3) };
    let tap = |k: usize| if TURNED { taps[n - 1 - k] } else { taps[k] };
    // Both pairs with a float to spare after them (seven floats from 6k);
    // the last pair of a row has none, and is made one channel at a time
    // (the same sums in the same order).
    let (f0, f1) = (r0.as_flattened(), r1.as_flattened());
    let pairs = f0.windows(7).step_by(6).zip(f1.windows(7).step_by(6));
    for at in (0..HALVING_AHEAD).step_by(16) {
        ask_for_both(f0, f1, at);
    }
    for (k, (out, (a, b))) in dst[..n - 1].iter_mut().zip(pairs).enumerate() {
        let ahead = 6 * k + HALVING_AHEAD;
        if ahead < f0.len() {
            ask_for_both(f0, f1, ahead);
        } else {
            ask_for_both(n0, n1, ahead - f0.len());
        }
        let t = tap(k);
        if t == [0.0; 4] {
            *out = [0.0; 3];
            continue;
        }
        let four = |p: &[f32], at: usize| {
            p.get(at..at + 4)
                .and_then(|q| q.first_chunk::<4>())
                .map_or(f32x4::ZERO, |q| f32x4::new(*q))
        };
        let w = |i: usize| f32x4::splat(t[i]);
        let v = four(a, first) * w(0)
            + four(a, second) * w(1)
            + four(b, first) * w(2)
            + four(b, second) * w(3);
        let v = v.to_array();
        *out = [v[0], v[1], v[2]];
    }
    let k = n - 1;
    let t = tap(k);
    dst[k] = if t == [0.0; 4] {
        [0.0; 3]
    } else {
        let (i0, i1) = if TURNED { (1, 0) } else { (0, 1) };
        let (a, b) = (&r0[2 * k..2 * k + 2], &r1[2 * k..2 * k + 2]);
        core::array::from_fn(|c| {
            a[i0][c] * t[0] + a[i1][c] * t[1] + b[i0][c] * t[2] + b[i1][c] * t[3]
        })
    };
}

/// The general case (an odd size): each texel the mean of the parts of the
/// texels it covers, each part weighted by its exact solid angle.
fn resample(src: &RgbImage, mapping: AnyMapping, chart: u32, w2: u32, h2: u32) -> RgbImage {
    let (w, h) = (src.width, src.height);
    // The fine texels texel `c` of `n2` covers, with the overlap in fine
    // coordinates, along one axis of `n` texels.
    let spans = |n: u32, n2: u32| -> Vec<Vec<(u32, f64, f64)>> {
        (0..n2)
            .map(|c| {
                let (a, b) = (
                    f64::from(c) * f64::from(n) / f64::from(n2),
                    f64::from(c + 1) * f64::from(n) / f64::from(n2),
                );
                let (k0, k1) = (a.floor() as u32, (b.ceil() as u32).min(n));
                (k0..k1)
                    .map(|k| (k, a.max(f64::from(k)), b.min(f64::from(k + 1))))
                    .filter(|(_, lo, hi)| hi > lo)
                    .collect()
            })
            .collect()
    };
    let (sx, sy) = (spans(w, w2), spans(h, h2));
    let mut pixels = vec![[0.0f32; 3]; (w2 * h2) as usize];
    pixels
        .par_chunks_mut(w2 as usize)
        .enumerate()
        .for_each(|(cj, row)| {
            for (ci, out) in row.iter_mut().enumerate() {
                let mut acc = [0.0f64; 3];
                let mut wsum = 0.0f64;
                for &(j, v0, v1) in &sy[cj] {
                    for &(i, u0, u1) in &sx[ci] {
                        let inside =
                            mapping.in_chart(chart, texel_center(i, w), texel_center(j, h));
                        if mapping.has_disk_charts() && !inside {
                            continue;
                        }
                        let wt = mapping.solid_angle(
                            chart,
                            u0 / f64::from(w),
                            u1 / f64::from(w),
                            v0 / f64::from(h),
                            v1 / f64::from(h),
                        );
                        let p = src.pixels[(j * w + i) as usize];
                        for c in 0..3 {
                            acc[c] += wt * f64::from(p[c]);
                        }
                        wsum += wt;
                    }
                }
                if wsum > 0.0 {
                    *out = acc.map(|a| (a / wsum) as f32);
                }
            }
        });
    RgbImage {
        width: w2,
        height: h2,
        pixels,
    }
}
