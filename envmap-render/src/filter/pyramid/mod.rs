//! Mip pyramids of an environment map in any representation, and sampling
//! them at a fractional level.
//!
//! # Levels
//!
//! Level 0 is the image. Each next level halves every chart: its height
//! becomes ⌊h/2⌋ (at least 1), as GL's rule for odd sizes has it, and its
//! width follows the chart's shape (a cube face stays square, a latlong
//! 2:1). Each texel of a level is the average of the texels of the level
//! above that it covers, weighted by their exact solid angles
//! (`TexelWeights`): a cube face's 2 × 2 texels by their own solid angles, a
//! latlong's by their rows'. Where a size is odd, a texel covers parts of
//! texels; each part is weighted by the exact solid angle of the part
//! ([`Mapping::solid_angle`] of the overlap). So every level keeps the
//! solid-angle-weighted mean of the image, to f32 rounding, and a texel
//! outside every chart (a cross's corners, a disk's) stays black. On a disk
//! chart a texel whose centre is outside the disk holds no value and
//! weighs nothing, so there the mean is kept up to the rim's slivers.
//!
//! # Trilinear sampling
//!
//! [`Trilinear`] samples at a chart point and a fractional level `lod`:
//! bilinear at levels ⌊lod⌋ and ⌊lod⌋ + 1, each with its representation's
//! edge rule (`Sampler`: the cube seamless across faces and corners, the
//! latlong wrapping and crossing its poles, read from a copy of each chart
//! with a one-texel border that holds them), blended as
//! `a + f·(b − a)`, f = lod − ⌊lod⌋. `lod` is clamped to the levels (NaN is
//! level 0). Eight points at a time ([`Trilinear::sample8`]) gives each lane
//! exactly what [`Trilinear::sample`] gives it, bit for bit.

use std::borrow::Cow;

use crate::par::*;
use envmap_core::atlas::{Atlas, Turn};
use envmap_core::texel::texel_center;
use envmap_core::{AnyMapping, ChartUv, Mapping};
use envmap_simd::Uv8;
use wide::{f32x4, f32x8, i32x8, u32x8};

use crate::error::Result;
use crate::filter::sample::{Filter, Sampler, Source};
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

/// One level down from `img` (see the [module docs](self)); `weights` are
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
fn halve_chart_row(
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
struct RowTaps {
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
trait ChartRows: Sync {
    /// Row `j` of `chart` as stored, and whether it is stored turned (its
    /// texels in reverse order); `None` for a chart or row not stored.
    fn chart_row(&self, chart: u32, j: u32) -> Option<(&[[f32; 3]], bool)>;
}

impl ChartRows for EnvImage {
    fn chart_row(&self, chart: u32, j: u32) -> Option<(&[[f32; 3]], bool)> {
        EnvImage::chart_row(self, chart, j)
    }
}

impl ChartRows for Bordered {
    fn chart_row(&self, chart: u32, j: u32) -> Option<(&[[f32; 3]], bool)> {
        if chart >= self.charts || j >= self.h {
            return None;
        }
        let (bw, bh) = (self.w as usize + 2, self.h as usize + 2);
        let at = ((chart as usize * bh + j as usize + 1) * bw + 1) * 3;
        let row = self.floats.get(at..at + 3 * self.w as usize)?;
        Some((row.as_chunks::<3>().0, false))
    }
}

/// The charts of `mapping` that `src` stores, a bit per chart.
fn present(src: &impl ChartRows, mapping: AnyMapping) -> u32 {
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
const HALVING_RUN: usize = 32;

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

/// An environment map and its mip levels; see the [module docs](self).
#[derive(Clone, Debug, PartialEq)]
pub struct Pyramid {
    levels: Vec<EnvImage>,
}

impl Pyramid {
    /// `base` and its levels down to charts of height 1, or down to the
    /// last level whose charts are at least `min_height` texels high
    /// (`min_height` 1 for the whole chain).
    ///
    /// # Errors
    ///
    /// Only if a level cannot be made (see `downsample`).
    pub fn new(base: EnvImage, min_height: u32) -> Result<Self> {
        let mut levels = vec![base];
        loop {
            let last = &levels[levels.len() - 1];
            let (cw, ch) = last.cell_size();
            let a = last.atlas();
            let (_, h2) = next_chart_size(cw, ch, a.cell_aspect_w, a.cell_aspect_h);
            if ch <= 1 || h2 < min_height.max(1) {
                break;
            }
            let weights = TexelWeights::new(last.mapping(), cw, ch);
            let next = downsample(last, &weights)?;
            levels.push(next);
        }
        Ok(Self { levels })
    }

    /// The levels, largest first.
    #[must_use]
    pub fn levels(&self) -> &[EnvImage] {
        &self.levels
    }

    /// Level `k` (clamped to the last).
    #[must_use]
    pub fn level(&self, k: usize) -> &EnvImage {
        &self.levels[k.min(self.levels.len() - 1)]
    }

    /// The number of levels.
    #[must_use]
    pub fn len(&self) -> usize {
        self.levels.len()
    }

    /// Always false: a pyramid has its base at least.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.levels.is_empty()
    }
}

/// One level's charts, each stored with a border of one texel on every
/// side that holds what the representation's edge rule reads there (the
/// neighbouring face's texel across a cube edge, the average of three at a
/// corner, the wrapped column of a latlong, ...; [`Sampler`]), so that a
/// bilinear footprint never leaves its chart's block. Disk charts keep the
/// plain sampler: their rule renormalises over the taps inside the disk.
#[derive(Clone, Debug)]
pub(crate) struct Bordered {
    /// RGB floats, chart after chart, each `(w + 2) × (h + 2)` texels row
    /// by row, then eight spare floats.
    floats: Vec<f32>,
    w: u32,
    h: u32,
    charts: u32,
    /// Where the frames were last filled from, kept for filling them
    /// again ([`Bordered::frame`]).
    plan: Option<FramePlan>,
}

/// Two levels are equal where their texels are: the frame plan is only
/// a record of where the frames came from.
impl PartialEq for Bordered {
    fn eq(&self, other: &Self) -> bool {
        (&self.floats, self.w, self.h, self.charts)
            == (&other.floats, other.w, other.h, other.charts)
    }
}

/// Where each texel of a bordered level's frames is read from
/// ([`Sampler::edge_source`]), for the mapping and the charts present it
/// was found for: the same for every level of that size, so filling the
/// frames of a level made again is a copy per texel.
#[derive(Clone, Debug)]
struct FramePlan {
    mapping: AnyMapping,
    present: u32,
    /// A frame texel (its index in the texels) and where it comes from.
    texels: Vec<(usize, Option<Source>)>,
}

/// Levels with fewer texels than this are made on one thread: below it,
/// handing the rows to the other threads costs more than making them.
const SMALL_LEVEL: usize = 1 << 15;

impl Bordered {
    /// `img`'s charts with their borders: each stored row of a chart
    /// copied in one piece (reversed where the atlas stores it turned), all
    /// rows of all charts in parallel, then the frames ([`Bordered::frame`]).
    fn new(img: &EnvImage) -> Self {
        let (w, h) = img.cell_size();
        let mapping = img.mapping();
        let mut b = Self::blank(w, h, mapping.chart_count());
        b.rows().into_par_iter().for_each(|(chart, j, dst)| {
            if let Some((src, turned)) = img.chart_row(chart, j) {
                dst.copy_from_slice(src);
                if turned {
                    dst.reverse();
                }
            }
        });
        b.frame(mapping, present(img, mapping));
        b
    }

    /// One level down from `src` in the even case (its charts `2w × 2h`,
    /// `weights` their texel solid angles), made straight into the
    /// bordered layout: each chart row halved into its place, upright,
    /// then the frames. Bit for bit [`Bordered::new`] of the level
    /// [`downsample`] makes, without that level or a copy of it.
    fn halved(
        src: &impl ChartRows,
        weights: &TexelWeights,
        mapping: AnyMapping,
        (w, h): (u32, u32),
    ) -> Self {
        let mut b = Self::blank(w, h, mapping.chart_count());
        b.halve_from(src, weights, mapping);
        b
    }

    /// Every chart row made again, in place, one level down from `src`
    /// (its charts twice this level's size), then the frames: what
    /// [`Bordered::halved`] makes, where `src` has every chart (a chart it
    /// lacks keeps what this level held).
    fn halve_from(&mut self, src: &impl ChartRows, weights: &TexelWeights, mapping: AnyMapping) {
        let small = self.texels() < SMALL_LEVEL;
        let mut rows = self.rows();
        let halve = |taps: &mut RowTaps, run: &mut [(u32, u32, &mut [[f32; 3]])]| {
            for k in 0..run.len() {
                let next = run.get(k + 1).map(|r| (r.0, r.1));
                let (chart, j, dst) = &mut run[k];
                halve_chart_row(src, weights, (*chart, *j), next, false, dst, taps);
            }
        };
        if small {
            halve(&mut RowTaps::default(), &mut rows);
        } else {
            rows.par_chunks_mut(HALVING_RUN)
                .for_each_init(RowTaps::default, halve);
        }
        self.frame(mapping, present(src, mapping));
    }

    /// The number of texels inside the frames.
    fn texels(&self) -> usize {
        self.charts as usize * self.w as usize * self.h as usize
    }

    /// `img`'s bordered copy for reading many times ([`Level::of`]), or
    /// `None` for a map with disk charts (read in place: its plain
    /// sampler renormalises over the taps inside the disk).
    pub(crate) fn for_reading(img: &EnvImage) -> Option<Self> {
        (!img.mapping().has_disk_charts()).then(|| Self::new(img))
    }

    /// Black charts of `w × h`, frames and all.
    fn blank(w: u32, h: u32, charts: u32) -> Self {
        let floats = vec![0.0f32; charts as usize * (w as usize + 2) * (h as usize + 2) * 3 + 8];
        Self {
            floats,
            w,
            h,
            charts,
            plan: None,
        }
    }

    /// Every chart row inside the frames: (chart, row, its texels), row by
    /// row across the charts (a worker given a run of them makes the same
    /// row of every chart, with the same weights where the charts share
    /// them, [`RowTaps`]).
    fn rows(&mut self) -> Vec<(u32, u32, &mut [[f32; 3]])> {
        let (w, bh) = (self.w as usize, self.h as usize + 2);
        let row = (w + 2) * 3;
        let blocks = self.charts as usize * bh * row;
        let mut rows: Vec<(u32, u32, &mut [[f32; 3]])> = self.floats[..blocks]
            .chunks_mut(row)
            .enumerate()
            .filter_map(|(r, line)| {
                let (chart, jb) = (r / bh, r % bh);
                (jb != 0 && jb != bh - 1).then(|| {
                    let texels = line[3..3 + 3 * w].as_chunks_mut::<3>().0;
                    (chart as u32, jb as u32 - 1, texels)
                })
            })
            .collect();
        rows.sort_by_key(|&(chart, j, _)| (j, chart));
        rows
    }

    /// Fills the one-texel frame around each chart in `present` (a bit per
    /// chart) with what the edge rule reads there ([`Sampler::edge_source`],
    /// from the charts themselves). Where each frame texel is read from is
    /// found once and kept ([`FramePlan`]); a level made again in place
    /// fills its frames by copying from there.
    fn frame(&mut self, mapping: AnyMapping, present: u32) {
        let (w, h) = (self.w, self.h);
        let (bw, bh) = (w as usize + 2, h as usize + 2);
        let blocks = self.charts as usize * bw * bh * 3;
        let plan = match self.plan.take() {
            Some(p) if (p.mapping, p.present) == (mapping, present) => p,
            _ => {
                let texels = self.floats[..blocks].as_chunks::<3>().0;
                let sampler = Sampler::over_blocks(texels, w, h, mapping);
                let ring = (0..self.charts)
                    .filter(|c| present >> c & 1 != 0)
                    .flat_map(|c| {
                        let rows = [0, bh - 1]
                            .into_iter()
                            .flat_map(move |y| (0..bw).map(move |x| (x, y)));
                        let sides = (1..bh - 1).flat_map(move |y| [(0, y), (bw - 1, y)]);
                        rows.chain(sides).map(move |(x, y)| (c, x, y))
                    });
                let texels = ring
                    .map(|(c, x, y)| {
                        let at = (c as usize * bh + y) * bw + x;
                        (at, sampler.edge_source(c, x as i64 - 1, y as i64 - 1))
                    })
                    .collect();
                FramePlan {
                    mapping,
                    present,
                    texels,
                }
            }
        };
        // Every source is inside a chart, never in a frame: the frames can
        // be written while the charts are read.
        let texels = self.floats[..blocks].as_chunks_mut::<3>().0;
        for &(at, src) in &plan.texels {
            texels[at] = src.map_or([0.0; 3], |s| s.value(texels));
        }
        self.plan = Some(plan);
    }

    /// The charts without their frames, as an image in `repr`.
    fn to_image(&self, repr: Representation) -> Result<EnvImage> {
        let (w, h) = (self.w, self.h);
        let a = repr.atlas;
        let mut img = EnvImage::new(a.cols * w, a.rows * h, repr)?;
        for chart in 0..self.charts {
            let pixels = (0..h)
                .flat_map(|j| self.chart_row(chart, j).map_or(&[][..], |r| r.0))
                .copied()
                .collect();
            let chart_image = RgbImage {
                width: w,
                height: h,
                pixels,
            };
            img.set_chart_image(chart, &chart_image)?;
        }
        Ok(img)
    }

    /// Where chart point (u, v)'s footprint starts (in floats) and its
    /// fractions, from the bordered coordinates x = clamp(u)·w + ½.
    #[inline(always)]
    fn footprint(&self, chart: u32, x: f32, y: f32) -> (usize, f32, f32) {
        // x, y ≥ ½: truncation is floor.
        let (i, j) = (x as u32, y as u32);
        let (bw, bh) = (self.w as usize + 2, self.h as usize + 2);
        let at = (chart as usize * bw * bh + j as usize * bw + i as usize) * 3;
        (at, x - i as f32, y - j as f32)
    }

    /// The bilinear blend of the footprint at `at` (red, green, blue and a
    /// spare float): two vertical interpolations and a horizontal one, as
    /// `p + f·(q − p)` with multiply-adds (fused where the target has FMA),
    /// in four-wide registers; the scalar and eight-lane paths both call it.
    #[inline(always)]
    fn blend(&self, at: usize, fx: f32, fy: f32) -> f32x4 {
        let row = (self.w as usize + 2) * 3;
        // Both rows of the footprint: texels (i, j), (i + 1, j) and the
        // same below, each row with a float to spare (the buffer ends with
        // eight spare floats).
        let rows = self
            .floats
            .get(at..)
            .and_then(|t| Some((t.first_chunk::<7>()?, t.get(row..)?.first_chunk::<7>()?)));
        let Some((top, bot)) = rows else {
            return f32x4::ZERO;
        };
        let four = |t: &[f32; 7], k: usize| f32x4::new([t[k], t[k + 1], t[k + 2], t[k + 3]]);
        let (a, b, c, d) = (four(top, 0), four(top, 3), four(bot, 0), four(bot, 3));
        let (fx, fy) = (f32x4::splat(fx), f32x4::splat(fy));
        let left = (c - a).mul_add(fy, a);
        let right = (d - b).mul_add(fy, b);
        (right - left).mul_add(fx, left)
    }

    /// Bilinear at a chart point: black for a chart out of range or NaN.
    #[inline]
    fn sample(&self, c: ChartUv) -> f32x4 {
        if c.chart >= self.charts || c.u.is_nan() || c.v.is_nan() {
            return f32x4::ZERO;
        }
        let x = c.u.clamp(0.0, 1.0) * self.w as f32 + 0.5;
        let y = c.v.clamp(0.0, 1.0) * self.h as f32 + 0.5;
        let (at, fx, fy) = self.footprint(c.chart, x, y);
        self.blend(at, fx, fy)
    }

    /// Where the footprints of eight chart points start (in floats) and
    /// their fractions, addressed eight at a time as [`Bordered::sample`]
    /// addresses one (a chart out of range clamped to the last: such lanes
    /// and NaN ones are for the caller to leave out).
    #[inline(always)]
    fn footprints8(&self, q: &Uv8) -> ([i32; 8], [f32; 8], [f32; 8]) {
        let (w, h) = (f32x8::splat(self.w as f32), f32x8::splat(self.h as f32));
        let half = f32x8::splat(0.5);
        let x = q.u.max(f32x8::ZERO).min(f32x8::ONE) * w + half;
        let y = q.v.max(f32x8::ZERO).min(f32x8::ONE) * h + half;
        // x, y ≥ ½ (or NaN, on lanes the caller leaves out): truncation is floor.
        let (i, j) = (x.fast_trunc_int(), y.fast_trunc_int());
        let (fx, fy) = (
            (x - i.round_float()).to_array(),
            (y - j.round_float()).to_array(),
        );
        let (bw, bh) = (self.w as i32 + 2, self.h as i32 + 2);
        let chart = bytemuck::cast::<u32x8, i32x8>(q.chart.min(u32x8::splat(self.charts - 1)));
        let at = ((chart * i32x8::splat(bw * bh) + j * i32x8::splat(bw) + i) * i32x8::splat(3))
            .to_array();
        (at, fx, fy)
    }

    /// Eight chart points, on the lanes set in `lanes` only (the others are
    /// zero: the lanes of a batch that read this level); lane `k` is
    /// `sample(q.lane_raw(k))` bit for bit. The footprints are addressed
    /// eight at a time.
    #[inline]
    fn sample8_lanes(&self, q: &Uv8, lanes: u32) -> [f32x4; 8] {
        let (at, fx, fy) = self.footprints8(q);
        let bad = q.chart.simd_ge(u32x8::splat(self.charts)).to_bitmask()
            | q.u.simd_ne(q.u).to_bitmask()
            | q.v.simd_ne(q.v).to_bitmask()
            | !lanes;
        // A plain loop, not `array::from_fn`: the compiler may leave
        // from_fn's per-lane closure out of line here (a call per lane, the
        // sampled levels much slower) when the code around the caller
        // changes.
        let mut out = [f32x4::ZERO; 8];
        for (k, o) in out.iter_mut().enumerate() {
            if bad >> k & 1 == 0 {
                *o = self.blend(at[k] as usize, fx[k], fy[k]);
            }
        }
        out
    }

    /// Asks the processor to start loading both rows of the footprints of
    /// the lanes of `q` set in `lanes`, as [`Bordered::sample8_lanes`]
    /// addresses them, without waiting for them. Only a hint: results never
    /// depend on it. Does nothing off x86-64.
    #[inline(always)]
    fn prefetch8(&self, q: &Uv8, lanes: u32) {
        #[cfg(all(target_arch = "x86_64", target_feature = "sse"))]
        {
            let (at, _, _) = self.footprints8(q);
            let row = (self.w as usize + 2) * 3;
            for (k, &a) in at.iter().enumerate() {
                if lanes >> k & 1 == 0 {
                    continue;
                }
                // A NaN lane's address is garbage: `get` keeps it in range.
                let a = a as usize;
                if let (Some(t), Some(b)) = (self.floats.get(a), self.floats.get(a + row)) {
                    safe_arch::prefetch_t0(t);
                    safe_arch::prefetch_t0(b);
                }
            }
        }
        #[cfg(not(all(target_arch = "x86_64", target_feature = "sse")))]
        let _ = (q, lanes);
    }
}

/// A level as [`Trilinear`] reads it (and the split sum's chain,
/// `LitSampler`): bilinear with its representation's edge rule.
#[derive(Debug)]
pub(crate) enum Level<'a> {
    /// Made for the sampler, or borrowed from [`PreparedLevels`].
    Bordered(Cow<'a, Bordered>),
    Plain(Sampler<'a>),
    /// Not prepared ([`Trilinear::starting_at`]): never read.
    Absent,
}

impl<'a> Level<'a> {
    /// `img` read through `copy`, its bordered copy
    /// ([`Bordered::for_reading`]), where there is one, else in place.
    pub(crate) fn of(img: &'a EnvImage, copy: Option<&'a Bordered>) -> Self {
        match copy {
            Some(b) => Level::Bordered(Cow::Borrowed(b)),
            None => Level::Plain(Sampler::new(img)),
        }
    }

    /// Bilinear at a chart point (red, green, blue and a zero); black for
    /// a chart out of range or NaN.
    #[inline]
    pub(crate) fn sample(&self, c: ChartUv) -> f32x4 {
        match self {
            Level::Bordered(b) => b.sample(c),
            Level::Plain(s) => {
                let [r, g, b] = s.sample(c, Filter::Bilinear);
                f32x4::new([r, g, b, 0.0])
            }
            Level::Absent => f32x4::ZERO,
        }
    }

    /// Starts loading what [`Level::sample8`] reads for the lanes set in
    /// `lanes` (a hint only; a level read in place is asked for on every
    /// lane).
    #[inline(always)]
    pub(crate) fn prefetch8(&self, q: &Uv8, lanes: u32) {
        match self {
            Level::Bordered(b) => b.prefetch8(q, lanes),
            Level::Plain(s) => s.prefetch8(&s.footprint8(q, Filter::Bilinear)),
            Level::Absent => {}
        }
    }

    /// Lane `k` of `q` where bit `k` of `lanes` is set; the others are
    /// zero, or read anyway where that costs nothing more.
    #[inline]
    pub(crate) fn sample8(&self, q: &Uv8, lanes: u32) -> [f32x4; 8] {
        match self {
            Level::Bordered(b) => b.sample8_lanes(q, lanes),
            Level::Plain(s) => s
                .sample8(q, Filter::Bilinear)
                .map(|[r, g, b]| f32x4::new([r, g, b, 0.0])),
            Level::Absent => [f32x4::ZERO; 8],
        }
    }
}

/// A pyramid's levels made ready for [`Trilinear`] once, for samplers that
/// borrow them (`Trilinear::over_prepared`): each level copied with its
/// one-texel border, the pyramid itself then let go; a disk map's levels
/// are kept as they are (its plain sampler reads them in place).
#[derive(Clone, Debug, PartialEq)]
pub struct PreparedLevels {
    kind: Prepared,
}

#[derive(Clone, Debug, PartialEq)]
enum Prepared {
    Bordered(Vec<Bordered>),
    Plain(Pyramid),
}

impl PreparedLevels {
    /// `p`'s levels made ready.
    #[must_use]
    pub fn new(p: Pyramid) -> Self {
        let kind = if p.levels[0].mapping().has_disk_charts() {
            Prepared::Plain(p)
        } else {
            Prepared::Bordered(p.levels.iter().map(Bordered::new).collect())
        };
        Self { kind }
    }

    /// The levels below `map`, from half its size down to charts of height
    /// 1, as [`PreparedLevels::new`] of `Pyramid::new(downsample_to(map,
    /// weights, atlas)?, 1)?` makes them, bit for bit, with less work: a
    /// level of an even size is halved straight into its bordered copy
    /// from the one above (no level image made, none copied). `weights` are
    /// `map`'s texel solid angles; `atlas`, one of its mapping's, is how
    /// an odd level in between is laid out.
    ///
    /// # Errors
    ///
    /// If `atlas` is not an atlas of `map`'s mapping, or a level cannot be
    /// made (see `downsample`).
    pub(crate) fn below(map: &EnvImage, weights: &TexelWeights, atlas: Atlas) -> Result<Self> {
        let mapping = map.mapping();
        if mapping.has_disk_charts() {
            return Ok(Self::new(Pyramid::new(
                downsample_to(map, weights, atlas)?,
                1,
            )?));
        }
        check_compatible(mapping, &atlas)?;
        let repr = Representation {
            atlas,
            ..*map.representation()
        };
        let mut levels: Vec<Bordered> = Vec::new();
        let (mut cw, mut ch) = map.cell_size();
        loop {
            let next = next_chart_size(cw, ch, atlas.cell_aspect_w, atlas.cell_aspect_h);
            let even = (cw, ch) == (2 * next.0, 2 * next.1);
            let level = match levels.last() {
                None if even => Bordered::halved(map, weights, mapping, next),
                None => Bordered::new(&downsample_to(map, weights, atlas)?),
                Some(above) => {
                    let weights = TexelWeights::new(mapping, cw, ch);
                    if even {
                        Bordered::halved(above, &weights, mapping, next)
                    } else {
                        Bordered::new(&downsample(&above.to_image(repr)?, &weights)?)
                    }
                }
            };
            levels.push(level);
            (cw, ch) = next;
            if ch <= 1 {
                break;
            }
        }
        Ok(Self {
            kind: Prepared::Bordered(levels),
        })
    }

    /// The number of levels.
    #[must_use]
    pub fn len(&self) -> usize {
        match &self.kind {
            Prepared::Bordered(b) => b.len(),
            Prepared::Plain(p) => p.len(),
        }
    }

    /// The chart size of every level, largest first.
    #[must_use]
    pub(crate) fn chart_sizes(&self) -> Vec<(u32, u32)> {
        match &self.kind {
            Prepared::Bordered(b) => b.iter().map(|l| (l.w, l.h)).collect(),
            Prepared::Plain(p) => p.levels.iter().map(EnvImage::cell_size).collect(),
        }
    }

    /// The levels below `map` made again in place, into the memory they
    /// hold, where they are [`PreparedLevels::below`] of a map of `map`'s
    /// mapping and chart size and every level halves evenly (no level
    /// allocated, none zeroed: for a map that changes between renders);
    /// bit for bit what `below` makes of `map`. `weights` are `map`'s
    /// texel solid angles and `above[k]` those of level `k + 1` (the level
    /// that level `k + 2` is made from). Returns false, changing nothing,
    /// where they cannot be made in place (sizes that turn odd, a disk
    /// map, a map that lacks a chart, weights of other sizes).
    pub(crate) fn remake_below(
        &mut self,
        map: &EnvImage,
        weights: &TexelWeights,
        above: &[TexelWeights],
    ) -> bool {
        let Prepared::Bordered(levels) = &mut self.kind else {
            return false;
        };
        let mapping = map.mapping();
        let charts = mapping.chart_count();
        if charts >= 32 || present(map, mapping) != (1 << charts) - 1 {
            return false;
        }
        if above.len() + 1 != levels.len() || weights.size() != map.cell_size() {
            return false;
        }
        let mut size = map.cell_size();
        for (k, l) in levels.iter().enumerate() {
            let w = if k == 0 { weights } else { &above[k - 1] };
            if size != (2 * l.w, 2 * l.h) || w.size() != size || l.charts != charts {
                return false;
            }
            size = (l.w, l.h);
        }
        for k in 0..levels.len() {
            let (made, rest) = levels.split_at_mut(k);
            match made.last() {
                None => rest[0].halve_from(map, weights, mapping),
                Some(src) => rest[0].halve_from(src, &above[k - 1], mapping),
            }
        }
        true
    }

    /// Always false: a pyramid has its base at least.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// Trilinear sampling of a [`Pyramid`]; see the [module docs](self).
///
/// Each level but a disk map's is copied once with a one-texel border that
/// holds what the edge rule reads beyond the chart, so every footprint is
/// read with four loads and no edge case.
#[derive(Debug)]
pub struct Trilinear<'a> {
    levels: Vec<Level<'a>>,
    /// The finest level prepared.
    first: usize,
}

impl<'a> Trilinear<'a> {
    /// A sampler over every level of `p`.
    #[must_use]
    pub fn new(p: &'a Pyramid) -> Self {
        Self::starting_at(p, 0)
    }

    /// A sampler over the levels of `p` from `first` down (clamped to the
    /// last): the finer ones are not prepared, and a `lod` below `first`
    /// reads as `first`. At every `lod ≥ first` the result is
    /// [`Trilinear::new`]'s, bit for bit; for importance sampling whose
    /// samples never ask for the finest levels, it saves their copies.
    #[must_use]
    pub(crate) fn starting_at(p: &'a Pyramid, first: usize) -> Self {
        let first = first.min(p.levels.len() - 1);
        Self {
            levels: p
                .levels
                .iter()
                .enumerate()
                .map(|(k, l)| {
                    if k < first {
                        return Level::Absent;
                    }
                    match Bordered::for_reading(l) {
                        Some(b) => Level::Bordered(Cow::Owned(b)),
                        None => Level::Plain(Sampler::new(l)),
                    }
                })
                .collect(),
            first,
        }
    }

    /// A sampler whose level 0 is `base`, read in place through its plain
    /// bilinear `Sampler` (no copy), and whose levels 1, 2, … are `below`'s
    /// levels, `below` being the pyramid of `base` one level down
    /// (`Pyramid::new(downsample(base, …)?, …)`). It saves the renderer a
    /// copy of the full-size map per render: the base, three quarters of a
    /// pyramid's texels, is neither cloned into a [`Pyramid`] nor copied with
    /// a border. The plain sampler keeps the same edge rule, so it reads
    /// what [`Trilinear::new`] reads there to f32 rounding (not bit for
    /// bit: the blends are not grouped alike).
    #[must_use]
    pub fn over(base: &'a EnvImage, below: &'a Pyramid) -> Self {
        let full = Self::new(below);
        let mut levels = Vec::with_capacity(full.levels.len() + 1);
        levels.push(Level::Plain(Sampler::new(base)));
        levels.extend(full.levels);
        Self { levels, first: 0 }
    }

    /// [`Trilinear::over`] with the levels below `base` made ready
    /// beforehand ([`PreparedLevels::new`] of `below`): reads what `over`
    /// reads, bit for bit, without copying a level. For many samplers of
    /// one map (a renderer drawing several images of it).
    #[must_use]
    pub(crate) fn over_prepared(base: &'a EnvImage, below: &'a PreparedLevels) -> Self {
        let mut levels = Vec::with_capacity(below.len() + 1);
        levels.push(Level::Plain(Sampler::new(base)));
        match &below.kind {
            Prepared::Bordered(b) => {
                levels.extend(b.iter().map(|b| Level::Bordered(Cow::Borrowed(b))));
            }
            Prepared::Plain(p) => {
                levels.extend(p.levels.iter().map(|l| Level::Plain(Sampler::new(l))))
            }
        }
        Self { levels, first: 0 }
    }

    /// The number of levels.
    #[must_use]
    pub fn levels(&self) -> usize {
        self.levels.len()
    }

    /// The level below `lod` and the blend towards the next, `lod` clamped
    /// to `[first, levels − 1]` (NaN is `first`).
    #[inline]
    fn split(&self, lod: f32) -> (usize, f32) {
        let top = (self.levels.len() - 1) as f32;
        let bottom = self.first as f32;
        let lod = if lod.is_nan() {
            bottom
        } else {
            lod.clamp(bottom, top)
        };
        // lod ≥ 0: truncation is floor.
        let i = lod as u32 as f32;
        (i as usize, lod - i)
    }

    /// Samples chart point `c` at level `lod`; a chart out of range or NaN
    /// coordinates give black.
    #[must_use]
    pub fn sample(&self, c: ChartUv, lod: f32) -> [f32; 3] {
        let (i, f) = self.split(lod);
        let a = self.levels[i].sample(c);
        let v = if f == 0.0 {
            a
        } else {
            blend(a, self.levels[i + 1].sample(c), f)
        };
        let [r, g, b, _] = v.to_array();
        [r, g, b]
    }

    /// Eight chart points at eight levels; lane `k` equals
    /// `sample(q.lane_raw(k), lod[k])` bit for bit. The lanes that share a
    /// level are read together.
    #[must_use]
    pub fn sample8(&self, q: &Uv8, lod: f32x8) -> [[f32; 3]; 8] {
        let lods = lod.to_array();
        let split: [(usize, f32); 8] = core::array::from_fn(|k| self.split(lods[k]));
        let mut out = [f32x4::ZERO; 8];
        let mut todo = 0xffu32;
        while todo != 0 {
            let first = todo.trailing_zeros() as usize;
            let level = split[first].0;
            // The lanes at this level, and those of them blended with the next.
            let (mut here, mut blended) = (0u32, 0u32);
            for (k, &(l, f)) in split.iter().enumerate() {
                if todo >> k & 1 != 0 && l == level {
                    here |= 1 << k;
                    if f != 0.0 {
                        blended |= 1 << k;
                    }
                }
            }
            let a = self.levels[level].sample8(q, here);
            let b = if blended != 0 {
                Some(self.levels[level + 1].sample8(q, blended))
            } else {
                None
            };
            for k in 0..8 {
                if todo >> k & 1 == 0 || split[k].0 != level {
                    continue;
                }
                let f = split[k].1;
                out[k] = match (&b, f == 0.0) {
                    (Some(b), false) => blend(a[k], b[k], f),
                    _ => a[k],
                };
                todo &= !(1 << k);
            }
        }
        out.map(|v| {
            let [r, g, b, _] = v.to_array();
            [r, g, b]
        })
    }

    /// Starts loading what [`Trilinear::sample8`] reads at `q` and `lod`
    /// (a hint only: results never depend on it), so that a batch asked
    /// for some batches ahead of its sampling rarely waits for memory.
    #[inline]
    pub(crate) fn prefetch8(&self, q: &Uv8, lod: f32x8) {
        let lods = lod.to_array();
        // A bit per lane for each level read.
        let mut read = [0u32; 32];
        for (k, &l) in lods.iter().enumerate() {
            let (i, f) = self.split(l);
            if let Some(m) = read.get_mut(i) {
                *m |= 1 << k;
            }
            if f != 0.0 {
                if let Some(m) = read.get_mut(i + 1) {
                    *m |= 1 << k;
                }
            }
        }
        for (level, &lanes) in self.levels.iter().zip(&read) {
            if lanes != 0 {
                level.prefetch8(q, lanes);
            }
        }
    }

    /// Eight chart points at one level `lod`, as red, green, blue and a
    /// spare float per lane: lane `k` equals `sample(q.lane_raw(k), lod)`
    /// bit for bit (the fast path of importance sampling, whose lanes share
    /// a level).
    #[inline]
    #[must_use]
    pub fn sample8_at(&self, q: &Uv8, lod: f32) -> [f32x4; 8] {
        let (i, f) = self.split(lod);
        let a = self.levels[i].sample8(q, 0xff);
        if f == 0.0 {
            return a;
        }
        let b = self.levels[i + 1].sample8(q, 0xff);
        core::array::from_fn(|k| blend(a[k], b[k], f))
    }
}

/// How many batches [`TrilinearAhead`] asks for before sampling the first.
const TRILINEAR_AHEAD: usize = 32;

/// Batches of trilinear lookups whose texels are loading
/// ([`Trilinear::prefetch8`]), sampled `TRILINEAR_AHEAD` batches later so
/// that the sampling rarely waits for memory: the mip-aware render's
/// counterpart of the plain lookups' queue (`Ahead`). Each batch is
/// sampled by [`Trilinear::sample8`] into its own place, so only the time
/// of its sampling changes, never a value.
#[derive(Default)]
pub(crate) struct TrilinearAhead {
    /// Chart points, levels, and where the lanes go (start, count).
    queue: [(Uv8, f32x8, usize, usize); TRILINEAR_AHEAD],
    /// The slot the next batch goes into: when the queue is full, the
    /// oldest batch's.
    next: usize,
    len: usize,
}

impl TrilinearAhead {
    /// Queues the batch `q` at levels `lod` for `out[at..at + len]` (at
    /// most eight values): starts loading its texels, after sampling the
    /// oldest batch when the queue is full.
    #[inline]
    pub(crate) fn push(
        &mut self,
        tri: &Trilinear<'_>,
        q: Uv8,
        lod: f32x8,
        (at, len): (usize, usize),
        out: &mut [[f32; 3]],
    ) {
        tri.prefetch8(&q, lod);
        let k = self.next;
        self.next = (k + 1) % TRILINEAR_AHEAD;
        if self.len == TRILINEAR_AHEAD {
            let (q, lod, at, len) = self.queue[k];
            Self::sample_into(tri, &q, lod, at..at + len, out);
        } else {
            self.len += 1;
        }
        self.queue[k] = (q, lod, at, len);
    }

    /// Samples every queued batch, oldest first.
    pub(crate) fn drain(&mut self, tri: &Trilinear<'_>, out: &mut [[f32; 3]]) {
        let oldest = self.next + TRILINEAR_AHEAD - self.len;
        for k in oldest..oldest + self.len {
            let (q, lod, at, len) = self.queue[k % TRILINEAR_AHEAD];
            Self::sample_into(tri, &q, lod, at..at + len, out);
        }
        self.len = 0;
    }

    /// `tri.sample8` of the batch into `out[at]`.
    #[inline]
    fn sample_into(
        tri: &Trilinear<'_>,
        q: &Uv8,
        lod: f32x8,
        at: core::ops::Range<usize>,
        out: &mut [[f32; 3]],
    ) {
        let rgb = tri.sample8(q, lod);
        if let Some(dst) = out.get_mut(at) {
            let n = dst.len().min(8);
            dst[..n].copy_from_slice(&rgb[..n]);
        }
    }
}

/// `a + f·(b − a)` per channel, in plain f32 operations (no fused
/// multiply-add), as every path computes it.
#[inline(always)]
fn blend(a: f32x4, b: f32x4, f: f32) -> f32x4 {
    a + f32x4::splat(f) * (b - a)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::Representation;
    use crate::scene::procedural::{fill, smooth};

    #[test]
    fn chart_sizes_halve_by_the_gl_rule_keeping_their_shape() {
        assert_eq!(next_chart_size(512, 512, 1, 1), (256, 256));
        assert_eq!(next_chart_size(5, 5, 1, 1), (2, 2));
        assert_eq!(next_chart_size(1, 1, 1, 1), (1, 1));
        assert_eq!(next_chart_size(14, 7, 2, 1), (6, 3));
        assert_eq!(next_chart_size(6, 2, 3, 1), (3, 1));
    }

    #[test]
    fn a_constant_stays_constant_at_every_level_of_every_mapping() {
        for m in AnyMapping::ALL {
            let repr = Representation::default_for(m);
            let (w, h) = repr
                .atlas
                .image_size_for_cell_width(16 * repr.atlas.cell_aspect_w)
                .unwrap();
            let img = fill(repr, w, h, |_| [2.0, 3.0, 4.0]).unwrap();
            let p = Pyramid::new(img, 1).unwrap();
            assert_eq!(p.levels().last().unwrap().cell_size().1, 1, "{m}");
            for (k, l) in p.levels().iter().enumerate() {
                let s = l.stats();
                for c in 0..3 {
                    let want = [2.0, 3.0, 4.0][c];
                    assert!(
                        (s.sphere_mean[c] - want).abs() < 1e-5 * want,
                        "{m} level {k}: {:?}",
                        s.sphere_mean
                    );
                }
            }
        }
    }

    #[test]
    fn a_sampler_starting_at_a_level_reads_as_the_full_one_from_there() {
        let repr = Representation::default_for(AnyMapping::Cube);
        let (w, h) = repr.atlas.image_size_for_cell_width(32).unwrap();
        let p = Pyramid::new(fill(repr, w, h, smooth).unwrap(), 1).unwrap();
        let (full, from2) = (Trilinear::new(&p), Trilinear::starting_at(&p, 2));
        for chart in 0..6 {
            for k in 0..7 {
                let c = ChartUv::new(chart, (k as f32 + 0.3) / 7.0, (k as f32 * 0.61) % 1.0);
                for lod in [2.0, 2.3, 3.7, 5.0, 10.0] {
                    let (a, b) = (full.sample(c, lod), from2.sample(c, lod));
                    assert_eq!(a.map(f32::to_bits), b.map(f32::to_bits), "{c:?} {lod}");
                }
                // Finer than its first level: read at the first.
                let (a, b) = (full.sample(c, 2.0), from2.sample(c, 0.5));
                assert_eq!(a.map(f32::to_bits), b.map(f32::to_bits), "{c:?}");
            }
        }
    }

    /// Each texel of a level against the solid-angle-weighted mean of the
    /// four texels above it, summed in f64 from the map and its weights:
    /// the f32 sums with weights rounded to f32 stay within 4 f32 roundings
    /// of it (measured worst: printed), on every mapping whose size halves
    /// evenly, with positive and negative values, charts stored turned.
    #[test]
    fn a_level_is_the_f64_weighted_mean_to_a_few_f32_roundings() {
        use envmap_core::atlas::Atlas;
        let mut reprs: Vec<Representation> =
            AnyMapping::ALL.map(Representation::default_for).to_vec();
        reprs.push(Representation {
            atlas: Atlas::CUBE_VERTICAL_CROSS,
            ..Representation::default_for(AnyMapping::Cube)
        });
        let mut worst = (0.0f64, String::new());
        for repr in reprs {
            let m = repr.mapping;
            let (w, h) = repr
                .atlas
                .image_size_for_cell_width(16 * repr.atlas.cell_aspect_w)
                .unwrap();
            let img = fill(repr, w, h, |d| {
                [d.x * 3.0 + d.y, 0.25 + d.z * d.z, 1e3 * (1.5 + d.x * d.y)]
            })
            .unwrap();
            let (cw, ch) = img.cell_size();
            let weights = TexelWeights::new(m, cw, ch);
            let level = downsample(&img, &weights).unwrap();
            assert_eq!(level.cell_size(), (cw / 2, ch / 2), "{m}");
            for chart in 0..m.chart_count() {
                let (Some(above), Some(got)) = (img.chart_image(chart), level.chart_image(chart))
                else {
                    continue;
                };
                for j in 0..ch / 2 {
                    for i in 0..cw / 2 {
                        let taps = [(0, 0), (1, 0), (0, 1), (1, 1)]
                            .map(|(di, dj)| (2 * i + di, 2 * j + dj))
                            .map(|(x, y)| {
                                (
                                    weights.get(chart, x, y),
                                    above.pixels[(y * cw + x) as usize],
                                )
                            });
                        let sum: f64 = taps.iter().map(|t| t.0).sum();
                        if sum == 0.0 {
                            continue;
                        }
                        let g = got.pixels[(j * (cw / 2) + i) as usize];
                        for (c, &g) in g.iter().enumerate() {
                            let want: f64 =
                                taps.iter().map(|t| t.0 * f64::from(t.1[c])).sum::<f64>() / sum;
                            let size: f64 = taps
                                .iter()
                                .map(|t| t.0 * f64::from(t.1[c]).abs())
                                .sum::<f64>()
                                / sum;
                            let err = (f64::from(g) - want).abs() / size;
                            if err > worst.0 {
                                worst = (err, format!("{m} chart {chart} ({i}, {j}) channel {c}"));
                            }
                        }
                    }
                }
            }
        }
        println!("worst {:.2e} of the taps' size at {}", worst.0, worst.1);
        assert!(worst.0 <= 4.0 * f64::from(f32::EPSILON), "{worst:?}");
    }

    #[test]
    fn a_chart_stored_turned_halves_as_the_same_chart_stored_upright() {
        // The vertical cross stores −z turned by half a turn; the strip
        // stores every face upright. A level of one is the other's,
        // chart for chart, texel for texel.
        use envmap_core::atlas::Atlas;
        let cross = Representation {
            atlas: Atlas::CUBE_VERTICAL_CROSS,
            ..Representation::default_for(AnyMapping::Cube)
        };
        let (w, h) = cross.atlas.image_size_for_cell_width(48).unwrap();
        let a = fill(cross, w, h, |d| {
            [d.x.max(0.0) * 3.0 + d.y, d.z * d.z, 1.0 + d.x * d.y]
        })
        .unwrap();
        let b = a.relayout(Atlas::CUBE_HORIZONTAL_STRIP).unwrap();
        assert!((0..6).any(|c| cross.atlas.cell_of(c).unwrap().turn == Turn::Half));
        let weights = TexelWeights::new(AnyMapping::Cube, 48, 48);
        let (la, lb) = (
            downsample(&a, &weights).unwrap(),
            downsample(&b, &weights).unwrap(),
        );
        for chart in 0..6 {
            assert_eq!(
                la.chart_image(chart),
                lb.chart_image(chart),
                "chart {chart}"
            );
        }
    }

    #[test]
    fn a_level_made_into_another_atlas_holds_the_same_charts() {
        // The vertical cross's −z is stored turned, the strip's upright:
        // its level made into the strip is the level made in the cross.
        use envmap_core::atlas::Atlas;
        let cross = Representation {
            atlas: Atlas::CUBE_VERTICAL_CROSS,
            ..Representation::default_for(AnyMapping::Cube)
        };
        let (w, h) = cross.atlas.image_size_for_cell_width(16).unwrap();
        let a = fill(cross, w, h, smooth).unwrap();
        let weights = TexelWeights::new(AnyMapping::Cube, 16, 16);
        let own = downsample(&a, &weights).unwrap();
        let strip = downsample_to(&a, &weights, Atlas::CUBE_HORIZONTAL_STRIP).unwrap();
        for chart in 0..6 {
            assert_eq!(
                own.chart_image(chart),
                strip.chart_image(chart),
                "chart {chart}"
            );
        }
    }

    /// Maps whose levels the bordered tests make: (representation, chart
    /// width, the levels' atlas if not the map's, whether every level
    /// halves evenly): turned charts, a change of atlas, sizes that turn
    /// odd on the way down (40: 20, 10, 5, 2, 1; 24: 12, 6, 3, 1; 36: 18,
    /// 9, ...), the non-cube edge rules and a disk map; and a cube whose
    /// first level is made by every thread (more than `SMALL_LEVEL` texels)
    /// and the rest on one.
    fn level_cases() -> [(Representation, u32, Option<Atlas>, bool); 9] {
        let strip = Atlas::CUBE_HORIZONTAL_STRIP;
        let cube = |atlas| Representation {
            atlas,
            ..Representation::default_for(AnyMapping::Cube)
        };
        let other = Representation::default_for;
        [
            (cube(Atlas::CUBE_VERTICAL_CROSS), 32, Some(strip), true),
            (cube(Atlas::CUBE_HORIZONTAL_CROSS), 40, Some(strip), false),
            (cube(Atlas::CUBE_VERTICAL_CROSS), 24, None, false),
            (cube(Atlas::CUBE_HORIZONTAL_CROSS), 256, None, true),
            (other(AnyMapping::LatLong), 64, None, true),
            (other(AnyMapping::Octahedral), 24, None, false),
            (other(AnyMapping::Octahedral), 16, None, true),
            (other(AnyMapping::Tennisball), 36, None, false),
            (other(AnyMapping::SphereMap), 32, None, false),
        ]
    }

    #[test]
    fn levels_halved_into_their_borders_are_the_levels_bordered_afterwards() {
        for (repr, cell, atlas, _) in level_cases() {
            let m = repr.mapping;
            let atlas = atlas.unwrap_or(repr.atlas);
            let (w, h) = repr.atlas.image_size_for_cell_width(cell).unwrap();
            let map = fill(repr, w, h, |d| {
                [d.x.max(0.0) * 3.0 + d.y, d.z * d.z, 1.0 + d.x * d.y]
            })
            .unwrap();
            let (cw, ch) = map.cell_size();
            let weights = TexelWeights::new(m, cw, ch);
            let made = PreparedLevels::below(&map, &weights, atlas).unwrap();
            let want = PreparedLevels::new(
                Pyramid::new(downsample_to(&map, &weights, atlas).unwrap(), 1).unwrap(),
            );
            assert_eq!(made.len(), want.len(), "{m} {cell}");
            assert!(made == want, "{m} {cell}");
        }
    }

    /// Levels made again in place for a second map of the same geometry
    /// are, bit for bit, the levels `below` makes of it, turned charts and
    /// a change of atlas included; where sizes turn odd or the map is a
    /// disk, nothing is made in place and the levels are left as they were.
    #[test]
    fn levels_remade_in_place_are_the_levels_made_anew() {
        const { assert!(6 * 128 * 128 > SMALL_LEVEL && 6 * 64 * 64 < SMALL_LEVEL) };
        for (repr, cell, atlas, even) in level_cases() {
            let m = repr.mapping;
            let atlas = atlas.unwrap_or(repr.atlas);
            let (w, h) = repr.atlas.image_size_for_cell_width(cell).unwrap();
            let first = fill(repr, w, h, |d| [d.x.max(0.0) * 3.0 + d.y, d.z * d.z, 1.0]).unwrap();
            let second = fill(repr, w, h, |d| [d.y * d.y, 2.0 - d.x, d.z.min(0.0)]).unwrap();
            let (cw, ch) = first.cell_size();
            let weights = TexelWeights::new(m, cw, ch);
            let mut levels = PreparedLevels::below(&first, &weights, atlas).unwrap();
            let sizes = levels.chart_sizes();
            let above: Vec<TexelWeights> = sizes[..sizes.len() - 1]
                .iter()
                .map(|&(w, h)| TexelWeights::new(m, w, h))
                .collect();
            let made = levels.remake_below(&second, &weights, &above);
            assert_eq!(made, even, "{m} {cell}");
            let want = if even { &second } else { &first };
            assert!(
                levels == PreparedLevels::below(want, &weights, atlas).unwrap(),
                "{m} {cell}"
            );
            // Weights of another size: nothing made.
            let wrong = TexelWeights::new(m, cw / 2, ch / 2);
            assert!(!levels.remake_below(&first, &wrong, &above), "{m} {cell}");
        }
    }

    /// A smooth map of `m`, charts 32 texels wide, and its pyramid from one
    /// level down.
    fn smooth_and_below(m: AnyMapping) -> (EnvImage, Pyramid) {
        let repr = Representation::default_for(m);
        let (w, h) = repr
            .atlas
            .image_size_for_cell_width(32 * repr.atlas.cell_aspect_w)
            .unwrap();
        let base = fill(repr, w, h, smooth).unwrap();
        let (cw, ch) = base.cell_size();
        let below = downsample(&base, &TexelWeights::new(m, cw, ch)).unwrap();
        (base, Pyramid::new(below, 1).unwrap())
    }

    #[test]
    fn prepared_levels_read_as_the_sampler_that_makes_its_own() {
        for m in [AnyMapping::Cube, AnyMapping::LatLong, AnyMapping::SphereMap] {
            let (base, below) = smooth_and_below(m);
            let prepared = PreparedLevels::new(below.clone());
            let (own, borrowed) = (
                Trilinear::over(&base, &below),
                Trilinear::over_prepared(&base, &prepared),
            );
            assert_eq!(prepared.len() + 1, own.levels(), "{m}");
            for chart in 0..m.chart_count() {
                for k in 0..9 {
                    let c = ChartUv::new(chart, (k as f32 + 0.3) / 9.0, (k as f32 * 0.61) % 1.0);
                    for lod in [0.0, 0.4, 1.0, 2.5, 9.0] {
                        assert_eq!(own.sample(c, lod), borrowed.sample(c, lod), "{m} {c:?}");
                    }
                }
            }
        }
    }

    /// The queue that samples batches some batches after asking for their
    /// texels puts every batch where it belongs, bit for bit what sampling
    /// each batch at once gives: more batches than the queue holds, short
    /// batches, lanes at different levels, a drain with a part-full queue.
    #[test]
    fn queued_batches_read_as_batches_read_at_once() {
        let (base, below) = smooth_and_below(AnyMapping::Cube);
        let prepared = PreparedLevels::new(below);
        let tri = Trilinear::over_prepared(&base, &prepared);
        let batches = 2 * TRILINEAR_AHEAD + 5;
        let mut want = vec![[0.0f32; 3]; 8 * batches];
        let mut got = vec![[f32::NAN; 3]; 8 * batches];
        let mut queue = TrilinearAhead::default();
        for b in 0..batches {
            let chart = u32x8::new(core::array::from_fn(|k| ((b + k) % 6) as u32));
            let u = f32x8::new(core::array::from_fn(|k| ((b * 8 + k) as f32 * 0.137) % 1.0));
            let v = f32x8::new(core::array::from_fn(|k| ((b * 5 + k) as f32 * 0.291) % 1.0));
            let lod = f32x8::new(core::array::from_fn(|k| ((b + 3 * k) % 11) as f32 * 0.45));
            let q = Uv8 { chart, u, v };
            // Every seventh batch is short.
            let n = if b % 7 == 3 { 5 } else { 8 };
            want[8 * b..8 * b + n].copy_from_slice(&tri.sample8(&q, lod)[..n]);
            queue.push(&tri, q, lod, (8 * b, n), &mut got);
        }
        queue.drain(&tri, &mut got);
        for (k, (g, w)) in got.iter().zip(&want).enumerate() {
            if k % 8 >= 5 && (k / 8) % 7 == 3 {
                assert!(g[0].is_nan(), "lane {k} beyond its batch was written");
                continue;
            }
            assert_eq!(g.map(f32::to_bits), w.map(f32::to_bits), "lane {k}");
        }
    }

    #[test]
    fn a_sampler_over_a_base_and_the_pyramid_below_reads_as_the_full_one() {
        for m in [AnyMapping::Cube, AnyMapping::LatLong, AnyMapping::SphereMap] {
            let (base, below) = smooth_and_below(m);
            let p = Pyramid::new(base.clone(), 1).unwrap();
            let (full, over) = (Trilinear::new(&p), Trilinear::over(&base, &below));
            assert_eq!(full.levels(), over.levels(), "{m}");
            for chart in 0..m.chart_count() {
                for k in 0..9 {
                    let c = ChartUv::new(chart, (k as f32 + 0.3) / 9.0, (k as f32 * 0.61) % 1.0);
                    for lod in [0.0, 0.4, 1.0, 2.5, 9.0] {
                        let (a, b) = (full.sample(c, lod), over.sample(c, lod));
                        for i in 0..3 {
                            assert!((a[i] - b[i]).abs() < 1e-5, "{m} {c:?} {lod}: {a:?} {b:?}");
                        }
                    }
                }
            }
        }
    }
}
