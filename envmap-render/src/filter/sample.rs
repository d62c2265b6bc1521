//! Sampling an environment map at a chart point, with each representation's
//! own edge rule.
//!
//! | representation | a bilinear footprint that leaves the chart ... |
//! | --- | --- |
//! | latlong | wraps in u; across a pole it continues half a turn round (row −1 is row 0 shifted by w/2) |
//! | cube | steps onto the neighbouring face (the texel whose centre the extended face plane points at), as GL's seamless cube maps do; at a corner the missing texel is the average of the three texels that meet there |
//! | sphere maps, paraboloid, angular map | stays inside the rim: texels whose centres lie outside the disk get no weight (the rest are renormalised), and points are pulled inside the last ring of texels |
//! | tennisball | is clamped to its own strip (the strips overlap, so the texels needed exist inside it) |
//! | octahedral maps | folds across the square's edges, which is where the unfolded octahedron continues: row −1 at column i is row 0 at column w − 1 − i |
//!
//! Nearest sampling picks the texel containing the point (clamped, never out
//! of range).
//!
//! Cubic sampling ([`Filter::Cubic`], for outputs finer than the input)
//! weights the 4×4 texels around the point by the Catmull-Rom spline
//! (Keys' cubic convolution with a = −½: R. Keys, "Cubic convolution
//! interpolation for digital image processing", IEEE Trans. ASSP 29(6),
//! 1981), each tap read through the same edge rules. The spline's negative
//! lobes ring around a sun (overshooting next to it, going below zero
//! beside it), and cutting them off (a clamp) adds energy: up to
//! (1 + 1/12)² − 1 ≈ 17 % of a lone bright texel's. So where the 4×4
//! texels are not smooth, the spread between their least and greatest
//! value exceeding their mean magnitude in any channel (around a sun, at a
//! sharp edge, next to a zero), the sample is bilinear instead, which
//! neither rings nor moves energy: a sun's texel is spread exactly as
//! bilinear spreads it. Where the spline is used, each channel is also
//! clamped to the range of the four texels a bilinear sample there reads,
//! so that no value leaves its neighbourhood's range. On smooth input the
//! spline's third-order accuracy is kept (bilinear's is second).
//!
//! Eight points at a time ([`Sampler::sample8_into`]) is two steps:
//! [`Sampler::footprint8`] addresses the texels and fractions, and
//! [`Sampler::gather8_into`] filters. Conversions and the renderer keep 32
//! batches between the two and ask the processor for their texels in the
//! meantime ([`Sampler::prefetch8`]), so that filtering rarely waits for
//! memory (`docs/design/kernels.md` has the measurements).

use envmap_core::cube::{face_direction, CubeFace};
use envmap_core::texel::{bilinear_footprint, texel_index};
use envmap_core::{AnyMapping, ChartUv, Cube, Mapping};
use envmap_simd::Uv8;
use wide::{f32x4, f32x8, i32x8, u32x8};

use crate::image::EnvImage;
use envmap_core::atlas::Turn;

/// Reconstruction filter.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Filter {
    /// The texel containing the point.
    Nearest,
    /// Bilinear interpolation of the four nearest texel centres, with the
    /// representation's edge rule.
    #[default]
    Bilinear,
    /// Catmull-Rom (Keys 1981, a = −½) over the 4×4 nearest texel centres
    /// where they are smooth, bilinear where they are not (their spread
    /// above their mean magnitude: a sun, an edge), so that nothing rings
    /// and a sun keeps its energy (a clamp alone would add up to 17 % of a
    /// lone bright texel's); the spline's value is also clamped to the
    /// range of the central 2×2. Slower than bilinear (16 taps, each
    /// through the edge rules): for upsampling.
    Cubic,
}

impl core::str::FromStr for Filter {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.to_ascii_lowercase().as_str() {
            "nearest" => Ok(Filter::Nearest),
            "bilinear" | "linear" => Ok(Filter::Bilinear),
            "cubic" | "bicubic" | "catmull-rom" => Ok(Filter::Cubic),
            _ => Err(format!(
                "unknown filter '{s}'; expected nearest, bilinear or cubic"
            )),
        }
    }
}

#[derive(Clone, Copy, Debug)]
struct Rect {
    x0: u32,
    y0: u32,
    turn: Turn,
}

/// The bilinear blend of four taps (red, green, blue and a spare float
/// each): `a`, `b` on the upper row, `c`, `d` below, at fractions `fx`
/// across and `fy` down, as two vertical and one horizontal
/// interpolation `p + f·(q − p)` with `wide`'s multiply-adds (fused where
/// the target has FMA). Exact at the texel centres (`f = 0`). The scalar
/// and the eight-lane samplers both call it, so they agree bit for bit on
/// every target.
#[inline(always)]
fn bilinear4(a: f32x4, b: f32x4, c: f32x4, d: f32x4, fx: f32x4, fy: f32x4) -> f32x4 {
    let left = (c - a).mul_add(fy, a);
    let right = (d - b).mul_add(fy, b);
    (right - left).mul_add(fx, left)
}

/// Eight chart points' texel addresses and bilinear fractions, from
/// [`Sampler::footprint8`], for [`Sampler::prefetch8`] and
/// [`Sampler::gather8_into`].
#[derive(Clone, Copy, Debug, Default)]
pub struct Footprint8 {
    q: Uv8,
    bilinear: bool,
    /// Cubic lanes all go through [`Sampler::sample`].
    cubic: bool,
    /// Where each lane's first tap starts, in floats.
    at: [i32; 8],
    /// Lanes that take the plain path (bit k for lane k); the others go
    /// through [`Sampler::sample`].
    fast: u32,
    /// Each lane's bilinear fractions across and down.
    frac: [[f32; 8]; 2],
}

impl Footprint8 {
    /// Lane `k`'s bilinear blend: `top` and `bottom` start at texel (i, j)
    /// and (i, j+1), each with the texel after it and two spare floats (red,
    /// green, blue, red, green, blue, spare, spare). Each float goes
    /// through the same operations as in `bilinear4`, which
    /// [`Sampler::bilinear_interior`] calls, so the two agree bit for bit.
    #[inline(always)]
    fn blend(&self, k: usize, top: &[f32], bottom: &[f32]) -> [f32; 4] {
        let eight = |t: &[f32]| {
            t.first_chunk::<8>()
                .map_or(f32x8::ZERO, |&t| f32x8::from(t))
        };
        let (t, b) = (eight(top), eight(bottom));
        // Both columns' vertical interpolation at once (floats 0..3 and
        // 3..6), then the horizontal one between them.
        let v = (b - t).mul_add(f32x8::splat(self.frac[1][k]), t);
        let shifted: u32x8 =
            bytemuck::cast::<f32x8, u32x8>(v).shuffle(u32x8::new([3, 4, 5, 6, 7, 7, 7, 7]));
        let low = |x: f32x8| bytemuck::cast::<f32x8, [f32x4; 2]>(x)[0];
        let (left, right) = (low(v), low(bytemuck::cast(shifted)));
        (right - left)
            .mul_add(f32x4::splat(self.frac[0][k]), left)
            .to_array()
    }
}

/// A read-only view of an [`EnvImage`] that samples chart points.
#[derive(Debug)]
pub struct Sampler<'a> {
    pixels: &'a [[f32; 3]],
    width: usize,
    mapping: AnyMapping,
    /// Chart size in texels (all charts of an atlas have one size).
    cw: u32,
    ch: u32,
    rects: [Rect; 6],
    /// Where texel (0, 0) of each chart stored unturned starts, in floats;
    /// `usize::MAX` for a turned or missing chart (which
    /// [`Sampler::sample8`] leaves to the scalar path).
    origin: [usize; 6],
    charts: u32,
    disk: bool,
    /// On disk charts: the largest squared radius (in the disk's own
    /// coordinates 2u − 1, 2v − 1) at which every texel centre of a bilinear
    /// footprint is surely inside the disk, `(1 − 2√2 / edge)²`; there the
    /// plain interior path applies.
    disk_inner: f32,
    /// The last float at which a plain lane can start, nearest and
    /// bilinear (four floats, or eight floats and the same a row below,
    /// must follow); −1 when there is none or the image is too large for
    /// `i32` offsets (then every lane takes the scalar path).
    last: [i32; 2],
}

impl<'a> Sampler<'a> {
    /// A sampler over `img`.
    #[must_use]
    pub fn new(img: &'a EnvImage) -> Self {
        let (cw, ch) = img.cell_size();
        let atlas = img.atlas();
        let mut rects = [Rect {
            x0: 0,
            y0: 0,
            turn: Turn::None,
        }; 6];
        let charts = img.mapping().chart_count().min(6);
        for c in 0..charts {
            if let Some(cell) = atlas.cell_of(c) {
                rects[c as usize] = Rect {
                    x0: cell.col * cw,
                    y0: cell.row * ch,
                    turn: cell.turn,
                };
            }
        }
        Self::from_parts(
            img.pixels(),
            img.width() as usize,
            img.mapping(),
            cw,
            ch,
            rects,
        )
    }

    /// A sampler over charts stored one below the other in blocks of
    /// `(w + 2) × (h + 2)` texels, each chart upright inside a one-texel
    /// frame (the layout of the pyramid's bordered levels), `pixels` the
    /// blocks row by row: for reading the charts' edge rule
    /// ([`Sampler::edge_source`]) before their frames are filled.
    pub(crate) fn over_blocks(pixels: &'a [[f32; 3]], w: u32, h: u32, mapping: AnyMapping) -> Self {
        let rects = core::array::from_fn(|c| Rect {
            x0: 1,
            y0: c as u32 * (h + 2) + 1,
            turn: Turn::None,
        });
        Self::from_parts(pixels, w as usize + 2, mapping, w, h, rects)
    }

    /// The sampler over `pixels`, `width` texels a row, whose charts of
    /// `cw × ch` texels start at `rects`.
    fn from_parts(
        pixels: &'a [[f32; 3]],
        width: usize,
        mapping: AnyMapping,
        cw: u32,
        ch: u32,
        rects: [Rect; 6],
    ) -> Self {
        let charts = mapping.chart_count().min(6);
        let mut origin = [usize::MAX; 6];
        for (c, (o, r)) in origin.iter_mut().zip(&rects).enumerate() {
            if (c as u32) < charts && r.turn == Turn::None {
                *o = 3 * (r.y0 as usize * width + r.x0 as usize);
            }
        }
        let floats = 3 * pixels.len();
        let last = |reach: usize| match floats.checked_sub(reach) {
            Some(l) if floats < i32::MAX as usize => l as i32,
            _ => -1,
        };
        Self {
            last: [last(4), last(3 * width + 8)],
            pixels,
            width,
            origin,
            mapping,
            cw,
            ch,
            rects,
            charts,
            disk: mapping.has_disk_charts(),
            disk_inner: {
                let margin = 1.0 - 2.0 * core::f32::consts::SQRT_2 / cw.min(ch).max(1) as f32;
                if margin > 0.0 {
                    margin * margin
                } else {
                    -1.0
                }
            },
        }
    }

    /// The texel `(i, j)` of `chart`, with `i < w`, `j < h`.
    #[inline]
    fn texel(&self, chart: u32, i: u32, j: u32) -> [f32; 3] {
        self.pixels[self.texel_at(chart, i, j)]
    }

    /// Where texel `(i, j)` of `chart` is stored: its index in the texels.
    #[inline]
    fn texel_at(&self, chart: u32, i: u32, j: u32) -> usize {
        let r = self.rects[chart.min(self.charts - 1) as usize];
        let (x, y) = match r.turn {
            Turn::None => (r.x0 + i, r.y0 + j),
            Turn::Half => (r.x0 + self.cw - 1 - i, r.y0 + self.ch - 1 - j),
        };
        y as usize * self.width + x as usize
    }

    /// Samples at a chart point; `None` charts or NaN give black.
    #[inline]
    #[must_use]
    pub fn sample(&self, c: ChartUv, filter: Filter) -> [f32; 3] {
        if c.chart >= self.charts || c.u.is_nan() || c.v.is_nan() {
            return [0.0; 3];
        }
        match filter {
            Filter::Nearest => self.texel(
                c.chart,
                texel_index(c.u, self.cw),
                texel_index(c.v, self.ch),
            ),
            Filter::Bilinear => self.bilinear(c),
            Filter::Cubic => self.cubic(c),
        }
    }

    /// [`Filter::Cubic`]: Catmull-Rom weights over the 4×4 texel centres
    /// around the point, read through the edge rules (texels a disk chart
    /// lacks get no weight, the rest renormalised); bilinear instead where
    /// those texels are not smooth (see the [module docs](self)); and each
    /// channel clamped to the range of the central 2×2.
    fn cubic(&self, c: ChartUv) -> [f32; 3] {
        let x = c.u * self.cw as f32 - 0.5;
        let y = c.v * self.ch as f32 - 0.5;
        let (i, j) = (x.floor(), y.floor());
        let (wx, wy) = (catmull_rom(x - i), catmull_rom(y - j));
        let (i, j) = (i as i64, j as i64);
        let mut acc = [0.0f32; 3];
        let mut wsum = 0.0f32;
        // The central 2×2's range, and the whole window's range and mean
        // magnitude, per channel.
        let mut lo = [f32::INFINITY; 3];
        let mut hi = [f32::NEG_INFINITY; 3];
        let mut wlo = [f32::INFINITY; 3];
        let mut whi = [f32::NEG_INFINITY; 3];
        let mut magnitude = [0.0f32; 3];
        let mut taps = 0.0f32;
        for (dj, wj) in (-1..=2).zip(wy) {
            for (di, wi) in (-1..=2).zip(wx) {
                let Some(t) = self.fetch(c.chart, i + di, j + dj, self.disk) else {
                    continue;
                };
                let w = wi * wj;
                let central = (0..=1).contains(&di) && (0..=1).contains(&dj);
                for k in 0..3 {
                    acc[k] += w * t[k];
                    wlo[k] = wlo[k].min(t[k]);
                    whi[k] = whi[k].max(t[k]);
                    magnitude[k] += t[k].abs();
                    if central {
                        lo[k] = lo[k].min(t[k]);
                        hi[k] = hi[k].max(t[k]);
                    }
                }
                wsum += w;
                taps += 1.0;
            }
        }
        // Not smooth: the window's spread exceeds its mean magnitude in
        // some channel (a sun, an edge, a texel of zero; NaN counts), or no
        // central texel (a disk's rim). Bilinear cannot ring, and keeps a
        // sun's energy where the spline with its lobes cut would add some.
        let rough = (0..3).any(|k| {
            let mean = magnitude[k] / taps.max(1.0);
            !matches!(
                (whi[k] - wlo[k]).partial_cmp(&mean),
                Some(core::cmp::Ordering::Less | core::cmp::Ordering::Equal)
            )
        });
        if rough || lo[0] > hi[0] || wsum <= 0.0 {
            return self.bilinear(c);
        }
        // max then min, not clamp: a channel whose central texels are all NaN
        // has lo > hi, where clamp would panic.
        core::array::from_fn(|k| (acc[k] / wsum).max(lo[k]).min(hi[k]))
    }

    /// Bilinear sample when the four taps lie inside one chart stored
    /// unturned and, on a disk chart, surely inside the disk (the common
    /// case); `None` otherwise, for [`Sampler::sample`] to handle with the
    /// edge rules. Small enough to inline into a conversion's inner loop.
    #[inline(always)]
    #[must_use]
    pub(crate) fn bilinear_interior(&self, chart: u32, u: f32, v: f32) -> Option<[f32; 3]> {
        if chart >= self.charts {
            return None;
        }
        if self.disk {
            let (p, q) = (2.0 * u - 1.0, 2.0 * v - 1.0);
            let surely_inside = p * p + q * q <= self.disk_inner; // false for NaN
            if !surely_inside {
                return None;
            }
        }
        let r = self.rects[chart as usize];
        if r.turn != Turn::None {
            return None;
        }
        let x = u * self.cw as f32 - 0.5;
        let y = v * self.ch as f32 - 0.5;
        // x ≥ 0 and x < w − 1 (false for NaN), so truncation is floor.
        if !(x >= 0.0 && y >= 0.0 && x < (self.cw - 1) as f32 && y < (self.ch - 1) as f32) {
            return None;
        }
        let (i, j) = (x as u32, y as u32);
        let (fx, fy) = (x - i as f32, y - j as f32);
        let base = (r.y0 + j) as usize * self.width + (r.x0 + i) as usize;
        let (a, b) = (self.pixels[base], self.pixels[base + 1]);
        let (c, d) = (
            self.pixels[base + self.width],
            self.pixels[base + self.width + 1],
        );
        let tap = |p: [f32; 3]| f32x4::new([p[0], p[1], p[2], 0.0]);
        let (fx, fy) = (f32x4::splat(fx), f32x4::splat(fy));
        let sum = bilinear4(tap(a), tap(b), tap(c), tap(d), fx, fy);
        let [r, g, b, _] = sum.to_array();
        Some([r, g, b])
    }

    /// Samples eight chart points at once; lane `k` of the result equals
    /// `sample(q.lane_raw(k), filter)` bit for bit. Lanes whose texels lie
    /// inside one unturned chart (for bilinear: all four taps, surely inside
    /// the disk on a disk chart) are addressed and weighted eight at a time and filtered with
    /// one four-wide operation per lane; the others (edges, seams, invalid
    /// lanes) go through [`Sampler::sample`].
    #[inline]
    #[must_use]
    pub fn sample8(&self, q: &Uv8, filter: Filter) -> [[f32; 3]; 8] {
        let mut out = [[0.0f32; 3]; 8];
        self.sample8_into(q, filter, &mut out);
        out
    }

    /// [`Sampler::sample8`] written straight into `dst`: lane `k` into
    /// `dst[k]`, for the first `min(8, dst.len())` lanes (the rest of `dst`
    /// is left alone).
    #[inline]
    pub fn sample8_into(&self, q: &Uv8, filter: Filter, dst: &mut [[f32; 3]]) {
        let f = self.footprint8(q, filter);
        self.gather8_into(&f, dst);
    }

    /// Where eight chart points read the input: the first half of
    /// [`Sampler::sample8_into`], which [`Sampler::gather8_into`] finishes.
    /// In between, [`Sampler::prefetch8`] can start loading the texels, so
    /// that a caller working a few batches ahead does not wait for memory.
    #[inline]
    #[must_use]
    pub fn footprint8(&self, q: &Uv8, filter: Filter) -> Footprint8 {
        let mut f = Footprint8::default();
        self.footprint8_into(q, filter, &mut f);
        f
    }

    /// [`Sampler::footprint8`] written into `f`, which a caller can keep in
    /// place (a queue slot) instead of moving.
    #[inline(always)]
    pub(crate) fn footprint8_into(&self, q: &Uv8, filter: Filter, f: &mut Footprint8) {
        let (cw, ch) = (self.cw as f32, self.ch as f32);
        let bilinear = filter == Filter::Bilinear;
        let (x, y, inside) = if bilinear {
            let x = q.u * f32x8::splat(cw) - f32x8::splat(0.5);
            let y = q.v * f32x8::splat(ch) - f32x8::splat(0.5);
            // x ≥ 0 and x < w − 1 (false for NaN): truncation is floor.
            let mut inside = x.simd_ge(f32x8::ZERO)
                & y.simd_ge(f32x8::ZERO)
                & x.simd_lt(f32x8::splat(cw - 1.0))
                & y.simd_lt(f32x8::splat(ch - 1.0));
            if self.disk {
                // As in `bilinear_interior`: footprints surely inside the disk.
                let two = f32x8::splat(2.0);
                let p = two * q.u - f32x8::ONE;
                let r = two * q.v - f32x8::ONE;
                inside &= (p * p + r * r).simd_le(f32x8::splat(self.disk_inner));
            }
            (x, y, inside)
        } else {
            // texel_index: u in [0, 1] (false for NaN), index clamped.
            let inside = q.u.simd_ge(f32x8::ZERO)
                & q.v.simd_ge(f32x8::ZERO)
                & q.u.simd_le(f32x8::ONE)
                & q.v.simd_le(f32x8::ONE);
            let x = (q.u * f32x8::splat(cw)).min(f32x8::splat(cw - 1.0));
            let y = (q.v * f32x8::splat(ch)).min(f32x8::splat(ch - 1.0));
            (x, y, inside)
        };
        let (i, j) = (x.fast_trunc_int(), y.fast_trunc_int());
        // Where each lane's first tap starts in `flat`, in i32 (images too
        // large for that, beyond the default size limit, take the scalar
        // path): the chart's origin (a select per chart) plus the texel's
        // offset in it.
        let fits = self.last[0] >= 0;
        let mut origin = i32x8::splat(-1);
        for (c, &o) in self.origin.iter().enumerate().take(self.charts as usize) {
            if o != usize::MAX && fits {
                let here = q.chart.simd_eq(u32x8::splat(c as u32));
                origin =
                    bytemuck::cast::<u32x8, i32x8>(here).select(i32x8::splat(o as i32), origin);
            }
        }
        let row = i32x8::splat(3 * self.width as i32);
        let at = origin + j * row + (i + i + i);
        // Plain lanes read whole rows of eight floats from `at` (and from
        // `at` plus a row, for bilinear), inside `flat`.
        let last = self.last[usize::from(bilinear)];
        let fast = if fits {
            (inside.to_bitmask()
                & !origin.simd_lt(i32x8::ZERO).to_bitmask()
                & !at.simd_gt(i32x8::splat(last)).to_bitmask())
                & 0xff
        } else {
            0
        };
        let (fx, fy) = (x - i.round_float(), y - j.round_float());
        f.q = *q;
        f.bilinear = bilinear;
        f.cubic = filter == Filter::Cubic;
        f.at = at.to_array();
        f.fast = if f.cubic { 0 } else { fast };
        f.frac = [fx.to_array(), fy.to_array()];
    }

    /// Asks the processor to start loading the texels that the lanes of
    /// `f` read (both rows of a bilinear footprint), without waiting for
    /// them. Only a hint: results never depend on it. Does nothing off
    /// x86-64.
    #[inline(always)]
    pub fn prefetch8(&self, f: &Footprint8) {
        #[cfg(all(target_arch = "x86_64", target_feature = "sse"))]
        {
            let flat = self.pixels.as_flattened();
            // Every lane's row, where its floats start, and for bilinear
            // the row below: one range check covers both, as `top` and
            // `bottom` have one length.
            let below = if f.bilinear { 3 * self.width } else { 0 };
            let bottom = flat.get(below..).unwrap_or_default();
            let top = flat.get(..bottom.len()).unwrap_or_default();
            for &at in &f.at {
                if let (Some(t), Some(b)) = (top.get(at as usize), bottom.get(at as usize)) {
                    safe_arch::prefetch_t0(t);
                    safe_arch::prefetch_t0(b);
                }
            }
        }
        #[cfg(not(all(target_arch = "x86_64", target_feature = "sse")))]
        let _ = f;
    }

    /// Filters the footprints `f` (from [`Sampler::footprint8`]) into
    /// `dst`: lane `k` into `dst[k]`, for the first `min(8, dst.len())`
    /// lanes, exactly as [`Sampler::sample8_into`] does.
    #[inline(always)]
    pub fn gather8_into(&self, f: &Footprint8, dst: &mut [[f32; 3]]) {
        if f.bilinear && f.fast == 0xff {
            if let Some(Ok(full)) = dst
                .get_mut(..8)
                .map(|d| <&mut [f32; 24]>::try_from(d.as_flattened_mut()))
            {
                if self.bilinear8_plain(f, full) {
                    return;
                }
            }
        }
        self.gather8_general(f, dst);
    }

    /// The common case, eight plain bilinear lanes, small enough to inline:
    /// lane k's two rows are eight floats at `at[k]` and a row below
    /// (`footprint8` checked that they fit; false, with `out` partly
    /// written, if one does not).
    #[inline(always)]
    fn bilinear8_plain(&self, f: &Footprint8, out: &mut [f32; 24]) -> bool {
        let flat = self.pixels.as_flattened();
        let below = flat.get(3 * self.width..).unwrap_or_default();
        for k in 0..8 {
            let at = f.at[k] as u32 as usize;
            let (Some(t), Some(b)) = (flat.get(at..at + 8), below.get(at..at + 8)) else {
                return false;
            };
            let v = f.blend(k, t, b);
            // Lane k's red, green and blue land at 3k..3k+3; a four-wide
            // store's fourth float goes into the next lane's red, which is
            // written after it (the last lane stores three floats).
            if k < 7 {
                out[3 * k..3 * k + 4].copy_from_slice(&v);
            } else {
                out[21..24].copy_from_slice(&v[..3]);
            }
        }
        true
    }

    /// Every other case of [`Sampler::gather8_into`]: plain lanes one by one
    /// with range checks, the others through [`Sampler::sample`].
    #[inline(never)]
    fn gather8_general(&self, f: &Footprint8, dst: &mut [[f32; 3]]) {
        let lanes = dst.len().min(8);
        let out = dst[..lanes].as_flattened_mut();
        let flat = self.pixels.as_flattened();
        let (at, mask) = (&f.at, f.fast);
        let row = 3 * self.width;
        let store = |out: &mut [f32], k: usize, v: [f32; 4]| match out.get_mut(3 * k..3 * k + 4) {
            Some(o) => o.copy_from_slice(&v),
            None => {
                if let Some(o) = out.get_mut(3 * k..3 * k + 3) {
                    o.copy_from_slice(&v[..3]);
                }
            }
        };
        let mut rest = 0u32;
        let filter = if f.cubic {
            rest = (1u32 << lanes) - 1;
            Filter::Cubic
        } else if f.bilinear {
            for (k, &at) in at.iter().enumerate().take(lanes) {
                // Both rows of the footprint: texels (i, j), (i+1, j) and
                // (i, j+1), (i+1, j+1), each row with two floats to spare.
                let taps = match flat.get(at as usize..(at as usize).wrapping_add(row + 8)) {
                    Some(t) if (mask >> k) & 1 != 0 => t,
                    _ => {
                        rest |= 1 << k;
                        continue;
                    }
                };
                store(out, k, f.blend(k, taps, &taps[row..]));
            }
            Filter::Bilinear
        } else {
            for (k, &at) in at.iter().enumerate().take(lanes) {
                match flat.get(at as usize..(at as usize).wrapping_add(4)) {
                    Some(t) if (mask >> k) & 1 != 0 => store(out, k, [t[0], t[1], t[2], t[3]]),
                    _ => rest |= 1 << k,
                }
            }
            Filter::Nearest
        };
        while rest != 0 {
            let k = rest.trailing_zeros() as usize;
            rest &= rest - 1;
            let s = self.sample(f.q.lane_raw(k), filter);
            if let Some(o) = out.get_mut(3 * k..3 * k + 3) {
                o.copy_from_slice(&s);
            }
        }
    }

    fn bilinear(&self, c: ChartUv) -> [f32; 3] {
        if let Some(rgb) = self.bilinear_interior(c.chart, c.u, c.v) {
            return rgb;
        }
        let (mut u, mut v) = (c.u, c.v);
        let disk = self.disk;
        if disk {
            // Pull the point inside the last ring of texel centres.
            let (x, y) = (2.0 * u - 1.0, 2.0 * v - 1.0);
            let r = (x * x + y * y).sqrt();
            let rmax = 1.0 - 1.0 / self.cw as f32;
            if r > rmax {
                let k = rmax / r;
                u = 0.5 * (x * k) + 0.5;
                v = 0.5 * (y * k) + 0.5;
            }
        }
        let (i0, i1, fx) = bilinear_footprint(u, self.cw);
        let (j0, j1, fy) = bilinear_footprint(v, self.ch);
        let taps = [
            (i0, j0, (1.0 - fx) * (1.0 - fy)),
            (i1, j0, fx * (1.0 - fy)),
            (i0, j1, (1.0 - fx) * fy),
            (i1, j1, fx * fy),
        ];
        let mut acc = [0.0f32; 3];
        let mut wsum = 0.0f32;
        for (i, j, w) in taps {
            if w == 0.0 {
                continue;
            }
            let Some(t) = self.fetch(c.chart, i, j, disk) else {
                continue;
            };
            for k in 0..3 {
                acc[k] += w * t[k];
            }
            wsum += w;
        }
        if wsum > 0.0 && wsum != 1.0 {
            for a in &mut acc {
                *a /= wsum;
            }
        }
        if wsum == 0.0 {
            // Only possible on a disk with no texel centre inside it nearby.
            return self.sample(c, Filter::Nearest);
        }
        acc
    }

    /// Where texel `(i, j)` of `chart` is read from, `i` and `j` up to one
    /// texel beyond the chart, with the representation's edge rule (what a
    /// bilinear tap there reads), as indices into the sampler's texels
    /// ([`Source::value`]): for filling the frames of bordered copies of a
    /// chart, the same for every image of this layout and size. `None`
    /// (black) on a disk chart's texels outside the disk.
    pub(crate) fn edge_source(&self, chart: u32, i: i64, j: i64) -> Option<Source> {
        self.source(chart, i, j, self.disk)
    }

    /// Texel `(i, j)` of `chart` with the edge rule applied to indices
    /// outside the chart; `None` for a disk texel whose centre is outside.
    fn fetch(&self, chart: u32, i: i64, j: i64, disk: bool) -> Option<[f32; 3]> {
        self.source(chart, i, j, disk).map(|s| s.value(self.pixels))
    }

    /// Where [`Sampler::fetch`] reads: the edge rule as texel indices.
    fn source(&self, chart: u32, i: i64, j: i64, disk: bool) -> Option<Source> {
        let (w, h) = (i64::from(self.cw), i64::from(self.ch));
        let inside = (0..w).contains(&i) && (0..h).contains(&j);
        if inside && !disk {
            return Some(Source::Texel(self.texel_at(chart, i as u32, j as u32)));
        }
        let texel =
            |c: u32, i: i64, j: i64| Some(Source::Texel(self.texel_at(c, i as u32, j as u32)));
        match self.mapping {
            AnyMapping::LatLong => {
                let (mut i, mut j) = (i, j);
                if j < 0 || j >= h {
                    j = if j < 0 { -1 - j } else { 2 * h - 1 - j };
                    i += w / 2;
                }
                texel(0, i.rem_euclid(w), j.clamp(0, h - 1))
            }
            AnyMapping::Cube | AnyMapping::Eac => self.cube_source(chart, i, j),
            AnyMapping::Tennisball => texel(chart, i.clamp(0, w - 1), j.clamp(0, h - 1)),
            AnyMapping::Octahedral | AnyMapping::EqualAreaOctahedral => {
                let (mut i, mut j) = (i, j);
                if j < 0 || j >= h {
                    j = if j < 0 { -1 - j } else { 2 * h - 1 - j };
                    i = w - 1 - i;
                }
                if i < 0 || i >= w {
                    i = if i < 0 { -1 - i } else { 2 * w - 1 - i };
                    j = h - 1 - j;
                }
                texel(0, i.clamp(0, w - 1), j.clamp(0, h - 1))
            }
            AnyMapping::SphereMap
            | AnyMapping::SphereMapGl
            | AnyMapping::DualParaboloid
            | AnyMapping::Angular
            | AnyMapping::Fisheye(_) => {
                // The disk charts (`has_disk_charts`).
                if !inside {
                    return None;
                }
                let u = (i as f32 + 0.5) / self.cw as f32;
                let v = (j as f32 + 0.5) / self.ch as f32;
                if self.mapping.in_chart(chart, u, v) {
                    texel(chart, i, j)
                } else {
                    None
                }
            }
        }
    }

    /// A cube texel index possibly beyond the face: follows the face plane
    /// onto the neighbouring face; at corners the three texels to average.
    /// `None` (black) only where the plane misses every face. The EAC map
    /// follows the same plane: its texel's angle past the edge,
    /// tan(π/4 · (2u − 1)), is the plane coordinate, and the texel it lands
    /// on is found with EAC's forward mapping.
    fn cube_source(&self, face: u32, i: i64, j: i64) -> Option<Source> {
        let (w, h) = (i64::from(self.cw), i64::from(self.ch));
        let iout = !(0..w).contains(&i);
        let jout = !(0..h).contains(&j);
        let one = |s: Option<Source>| match s {
            Some(Source::Texel(k)) => Some(k),
            _ => None,
        };
        if iout && jout {
            let ic = i.clamp(0, w - 1);
            let jc = j.clamp(0, h - 1);
            let a = one(self.cube_source(face, i, jc));
            let b = one(self.cube_source(face, ic, j));
            let c = self.texel_at(face, ic as u32, jc as u32);
            return Some(Source::Corner(a, b, c));
        }
        if !iout && !jout {
            return Some(Source::Texel(self.texel_at(face, i as u32, j as u32)));
        }
        let mut sc = 2.0 * ((i as f32 + 0.5) / self.cw as f32) - 1.0;
        let mut tc = 2.0 * ((j as f32 + 0.5) / self.ch as f32) - 1.0;
        let f = CubeFace::from_index(face).unwrap_or(CubeFace::PosX);
        let landed = if self.mapping == AnyMapping::Eac {
            let plane = |e: f32| (core::f32::consts::FRAC_PI_4 * e).tan();
            (sc, tc) = (plane(sc), plane(tc));
            envmap_core::Eac::forward(face_direction(f, sc, tc))
        } else {
            Cube::forward(face_direction(f, sc, tc))
        };
        landed.map(|p| {
            Source::Texel(self.texel_at(
                p.chart,
                texel_index(p.u, self.cw),
                texel_index(p.v, self.ch),
            ))
        })
    }
}

/// The Catmull-Rom weights of the texels at −1, 0, 1 and 2 for a point a
/// fraction `t` ∈ [0, 1) past texel 0 (Keys 1981, a = −½); they sum to 1.
fn catmull_rom(t: f32) -> [f32; 4] {
    let (t2, t3) = (t * t, t * t * t);
    [
        0.5 * (-t3 + 2.0 * t2 - t),
        0.5 * (3.0 * t3 - 5.0 * t2 + 2.0),
        0.5 * (-3.0 * t3 + 4.0 * t2 + t),
        0.5 * (t3 - t2),
    ]
}

/// Where an edge texel is read from ([`Sampler::edge_source`]): indices
/// into a sampler's texels.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Source {
    /// One texel.
    Texel(usize),
    /// A cube corner: the mean of the texels across both edges (black
    /// where the face plane misses, `None`) and the corner texel itself.
    Corner(Option<usize>, Option<usize>, usize),
}

impl Source {
    /// The value read from `texels`: one texel, or the mean of a cube
    /// corner's three, `(a + b + c) / 3` per channel.
    #[inline]
    pub(crate) fn value(self, texels: &[[f32; 3]]) -> [f32; 3] {
        let at = |k: Option<usize>| k.and_then(|k| texels.get(k)).copied().unwrap_or([0.0; 3]);
        match self {
            Source::Texel(k) => at(Some(k)),
            Source::Corner(a, b, c) => {
                let (a, b, c) = (at(a), at(b), at(Some(c)));
                [
                    (a[0] + b[0] + c[0]) / 3.0,
                    (a[1] + b[1] + c[1]) / 3.0,
                    (a[2] + b[2] + c[2]) / 3.0,
                ]
            }
        }
    }
}

/// How many batches are addressed before the first of them is filtered.
const AHEAD: usize = 32;

/// Batches whose footprints are known and whose texels are loading
/// ([`Sampler::prefetch8`]), filtered `AHEAD` batches later, so that the
/// filter rarely waits for memory.
#[derive(Default)]
pub(crate) struct Ahead {
    /// Footprint, and where its lanes go in the band (start, count).
    queue: [(Footprint8, usize, usize); AHEAD],
    /// The slot the next batch goes into: when the queue is full, the
    /// oldest batch's.
    next: usize,
    len: usize,
}

impl Ahead {
    /// Queues the batch of chart points `q` for `px[at..at + len]`:
    /// addresses it and starts loading its texels, after filtering the
    /// oldest batch when the queue is full. The footprint is written in
    /// place, into the slot it will be filtered from.
    #[inline(always)]
    pub(crate) fn push(
        &mut self,
        s: &Sampler<'_>,
        q: &Uv8,
        filter: Filter,
        at: usize,
        len: usize,
        px: &mut [[f32; 3]],
    ) {
        let k = self.next;
        self.next = (k + 1) % AHEAD;
        if self.len == AHEAD {
            let (f, a, n) = &self.queue[k];
            if let Some(o) = px.get_mut(*a..*a + *n) {
                s.gather8_into(f, o);
            }
        } else {
            self.len += 1;
        }
        let slot = &mut self.queue[k];
        s.footprint8_into(q, filter, &mut slot.0);
        (slot.1, slot.2) = (at, len);
        s.prefetch8(&slot.0);
        #[cfg(all(target_arch = "x86_64", target_feature = "sse"))]
        {
            // Where the batch's output will go, for writing: its first,
            // middle and last float, less than a cache line apart (8 texels
            // are 96 bytes), so every line the batch writes is asked for.
            let out = px.as_flattened();
            let (first, last) = (3 * at, 3 * (at + len));
            for f in [first, (first + last) / 2, last.wrapping_sub(1)] {
                if let Some(p) = out.get(f) {
                    safe_arch::prefetch_et0(p);
                }
            }
        }
    }

    /// Filters every queued batch.
    pub(crate) fn drain(&mut self, s: &Sampler<'_>, px: &mut [[f32; 3]]) {
        let oldest = self.next + AHEAD - self.len;
        for k in oldest..oldest + self.len {
            let (f, a, n) = &self.queue[k % AHEAD];
            if let Some(o) = px.get_mut(*a..*a + *n) {
                s.gather8_into(f, o);
            }
        }
        self.len = 0;
    }
}
