// Trilinear: sampling the levels at a fractional level (each level read as
// a `Level`), and `TrilinearAhead`, its queue of lookups whose texels load.

use std::borrow::Cow;

use envmap_core::ChartUv;
use envmap_simd::Uv8;
use wide::{f32x4, f32x8};

use super::bordered::Bordered;
use super::levels::Pyramid;
use crate::filter::sample::{Filter, Sampler};
use crate::image::EnvImage;

/// A level as [`Trilinear`] reads it (and the split sum's chain,
/// `LitSampler`): bilinear with its representation's edge rule.
#[derive(Debug)]
pub(crate) enum Level<'a> {
    /// A level's ready copy ([`Pyramid`]), or one made for the sampler.
    Bordered(Cow<'a, Bordered>),
    Plain(Sampler<'a>),
    /// Not prepared ([`Trilinear::starting_at`]): never read.
    Absent,
}

impl Level<'_> {
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

/// Trilinear sampling of a [`Pyramid`]; see the [module docs](super).
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
    /// last): the finer ones are not read, and a `lod` below `first`
    /// reads as `first`. At every `lod ≥ first` the result is
    /// [`Trilinear::new`]'s, bit for bit; for importance sampling whose
    /// samples never ask for the finest levels, it saves their copies.
    /// Each level is read through its ready copy, made here where `p`
    /// holds none (a disk map's levels are read in place).
    #[must_use]
    pub(crate) fn starting_at(p: &'a Pyramid, first: usize) -> Self {
        let first = first.min(p.len() - 1);
        Self {
            levels: (0..p.len())
                .map(|k| match k < first {
                    true => Level::Absent,
                    false => p.reader(k, true),
                })
                .collect(),
            first,
        }
    }

    /// A sampler whose level 0 is `base`, read in place through its plain
    /// bilinear `Sampler` (no copy), and whose levels 1, 2, … are `below`'s
    /// levels, `below` being the pyramid of `base` one level down
    /// (`Pyramid::new(downsample(base, …)?, …)`, or the renderer's
    /// `Pyramid::below`, whose levels are ready: none is copied then). It
    /// saves the renderer a copy of the full-size map per render: the base,
    /// three quarters of a pyramid's texels, is neither cloned into a
    /// [`Pyramid`] nor copied with a border. The plain sampler keeps the
    /// same edge rule, so it reads what [`Trilinear::new`] reads there to
    /// f32 rounding (not bit for bit: the blends are not grouped alike).
    #[must_use]
    pub fn over(base: &'a EnvImage, below: &'a Pyramid) -> Self {
        let mut levels = Vec::with_capacity(below.len() + 1);
        levels.push(Level::Plain(Sampler::new(base)));
        levels.extend((0..below.len()).map(|k| below.reader(k, true)));
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
pub(super) const TRILINEAR_AHEAD: usize = 32;

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
