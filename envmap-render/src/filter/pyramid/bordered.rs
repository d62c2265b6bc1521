// Bordered: a level's charts stored with a one-texel frame that holds
// what the edge rule reads beyond each chart, made, halved into and sampled.

use crate::par::*;
use envmap_core::{AnyMapping, ChartUv, Mapping};
use envmap_simd::Uv8;
use wide::{f32x4, f32x8, i32x8, u32x8};

use super::halving::{halve_chart_row, present, ChartRows, RowTaps, HALVING_RUN};
use crate::error::Result;
use crate::filter::sample::{Sampler, Source};
use crate::filter::weights::TexelWeights;
use crate::image::{EnvImage, Representation, RgbImage};

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
    pub(super) w: u32,
    pub(super) h: u32,
    pub(super) charts: u32,
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
pub(super) const SMALL_LEVEL: usize = 1 << 15;

impl Bordered {
    /// `img`'s charts with their borders: each stored row of a chart
    /// copied in one piece (reversed where the atlas stores it turned), all
    /// rows of all charts in parallel, then the frames ([`Bordered::frame`]).
    pub(super) fn new(img: &EnvImage) -> Self {
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
    /// [`downsample`](super::downsample) makes, without that level or a copy
    /// of it.
    pub(super) fn halved(
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
    pub(super) fn halve_from(
        &mut self,
        src: &impl ChartRows,
        weights: &TexelWeights,
        mapping: AnyMapping,
    ) {
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
    pub(super) fn to_image(&self, repr: Representation) -> Result<EnvImage> {
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
    pub(super) fn sample(&self, c: ChartUv) -> f32x4 {
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
    pub(super) fn sample8_lanes(&self, q: &Uv8, lanes: u32) -> [f32x4; 8] {
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
    pub(super) fn prefetch8(&self, q: &Uv8, lanes: u32) {
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
