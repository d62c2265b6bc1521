// The projection: SH9 sums over any map's texels, eight at a time, in
// fixed blocks (the same sums at any thread count).

use std::f64::consts::PI;

use envmap_core::atlas::{Cell, Turn};
use envmap_core::texel::texel_center;
use envmap_core::{AnyMapping, ChartUv, Mapping};
use envmap_simd::{Dir8, Exact, Mapping8, Uv8, LANES};
use wide::{f32x8, u32x8};

use super::*;
use crate::filter::weights::TexelWeights;
use crate::image::EnvImage;

/// Σ L·Ω·poly per coefficient and channel.
pub(super) type Raw = [[f64; 3]; 9];

/// Rows per parallel task: fixed, so the sum's order (and every bit of it)
/// does not depend on the number of threads.
pub(super) const ROWS_PER_TASK: u32 = 8;
/// Batches of eight texels summed in f32 before being added in f64.
pub(super) const FLUSH: usize = 64;

/// Which loop projects a latlong.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Path {
    /// The latlong's separable sums where it applies, the generic loop
    /// elsewhere.
    Fast,
    /// The generic loop for every mapping (tests compare the two).
    #[cfg_attr(not(test), allow(dead_code))]
    Generic,
}

#[inline]
pub(super) fn add_raw(a: &mut Raw, b: &Raw) {
    for (x, y) in a.iter_mut().zip(b) {
        for c in 0..3 {
            x[c] += y[c];
        }
    }
}

pub(super) fn finite(r: &[[f64; 3]]) -> bool {
    r.iter().flatten().all(|v| v.is_finite())
}

/// Adds each f32 accumulator's lanes into `out` in f64 (in lane order) and
/// clears it.
#[inline]
pub(super) fn flush<const N: usize>(acc: &mut [[f32x8; 3]; N], out: &mut [[f64; 3]; N]) {
    for (a, o) in acc.iter_mut().zip(out.iter_mut()) {
        for c in 0..3 {
            o[c] += a[c].to_array().iter().map(|&v| f64::from(v)).sum::<f64>();
            a[c] = f32x8::ZERO;
        }
    }
}

/// What the projection of one map shares between its tasks.
pub(super) struct ProjectJob<'a> {
    pub(super) img: &'a EnvImage,
    pub(super) mapping: AnyMapping,
    pub(super) cw: u32,
    pub(super) ch: u32,
    pub(super) weights: TexelWeights,
    /// The charts with a cell, with their cell.
    pub(super) charts: Vec<(u32, Cell)>,
    /// Per entry of `charts`: index into `tables` (generic loop).
    pub(super) table_of: Vec<usize>,
    /// Texel weights in stored order, f32 (generic loop).
    pub(super) tables: Vec<Vec<f32>>,
    /// The latlong's column tables, when its separable sums are used.
    pub(super) columns: Option<Columns>,
    /// Texel centres along u, left to right and reversed, padded to whole
    /// batches.
    pub(super) us: Vec<f32>,
    pub(super) us_turned: Vec<f32>,
}

/// cos φ, sin φ, cos 2φ and sin 2φ at each latlong column's centre
/// (φ = 2πu, computed in f64), each value three times over (once per
/// channel, as the texels' floats lie: R G B R G B ...), padded with zeros
/// to whole batches of eight texels.
pub(super) struct Columns {
    pub(super) tabs: [Vec<f32>; 4],
}

impl Columns {
    pub(super) fn new(w: u32) -> Self {
        let n = 3 * (w as usize).div_ceil(LANES) * LANES;
        let mut tabs = [vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]];
        for i in 0..w as usize {
            let phi = 2.0 * PI * (i as f64 + 0.5) / f64::from(w);
            let (s, c) = phi.sin_cos();
            let (s2, c2) = (2.0 * phi).sin_cos();
            for (t, v) in tabs.iter_mut().zip([c, s, c2, s2]) {
                t[3 * i..3 * i + 3].fill(v as f32);
            }
        }
        Self { tabs }
    }
}

/// The texel weights of one chart in stored order (rows of the cell top to
/// bottom, left to right), f32.
pub(super) fn stored_weights(
    weights: &TexelWeights,
    chart: u32,
    cw: u32,
    ch: u32,
    half: bool,
) -> Vec<f32> {
    (0..ch)
        .into_par_iter()
        .flat_map_iter(|r| {
            (0..cw).map(move |k| {
                let (i, j) = if half {
                    (cw - 1 - k, ch - 1 - r)
                } else {
                    (k, r)
                };
                weights.get(chart, i, j) as f32
            })
        })
        .collect()
}

pub(super) fn padded_centres(cw: u32, reversed: bool) -> Vec<f32> {
    let n = (cw as usize).div_ceil(LANES) * LANES;
    let mut us: Vec<f32> = (0..cw)
        .map(|k| texel_center(if reversed { cw - 1 - k } else { k }, cw))
        .collect();
    us.resize(n, 0.5);
    us
}

/// Σ L·Ω·poly over every texel of `img`, in its own axes, and the number of
/// texels skipped.
pub(super) fn native_sums(img: &EnvImage, path: Path) -> (Raw, u64) {
    let mapping = img.mapping();
    let (cw, ch) = img.cell_size();
    let atlas = *img.atlas();
    let charts: Vec<(u32, Cell)> = (0..mapping.chart_count())
        .filter_map(|c| atlas.cell_of(c).map(|cell| (c, cell)))
        .collect();
    let weights = TexelWeights::new(mapping, cw, ch);
    let separable = path == Path::Fast
        && mapping == AnyMapping::LatLong
        && charts.iter().all(|(_, c)| c.turn == Turn::None);
    let (mut tables, mut table_of) = (Vec::new(), Vec::new());
    if !separable {
        for (k, &(chart, cell)) in charts.iter().enumerate() {
            let half = cell.turn == Turn::Half;
            // The cube's faces share one table of weights.
            let shared = (mapping == AnyMapping::Cube)
                .then(|| charts[..k].iter().position(|(_, c)| c.turn == cell.turn))
                .flatten();
            match shared {
                Some(p) => table_of.push(table_of[p]),
                None => {
                    table_of.push(tables.len());
                    tables.push(stored_weights(&weights, chart, cw, ch, half));
                }
            }
        }
    }
    let job = ProjectJob {
        img,
        mapping,
        cw,
        ch,
        weights,
        columns: separable.then(|| Columns::new(cw)),
        charts,
        table_of,
        tables,
        us: padded_centres(cw, false),
        us_turned: padded_centres(cw, true),
    };
    let tasks: Vec<(usize, u32)> = (0..job.charts.len())
        .flat_map(|k| (0..ch.div_ceil(ROWS_PER_TASK)).map(move |t| (k, t * ROWS_PER_TASK)))
        .collect();
    let parts: Vec<(Raw, u64)> = tasks
        .par_iter()
        .map(|&(k, r0)| {
            let mut raw = [[0.0; 3]; 9];
            let mut skipped = 0;
            for r in r0..(r0 + ROWS_PER_TASK).min(ch) {
                let (row, s) = job.row(k, r);
                add_raw(&mut raw, &row);
                skipped += s;
            }
            (raw, skipped)
        })
        .collect();
    let mut raw = [[0.0; 3]; 9];
    let mut skipped = 0;
    for (p, s) in &parts {
        add_raw(&mut raw, p);
        skipped += s;
    }
    (raw, skipped)
}

impl ProjectJob<'_> {
    /// Stored row `r` of chart entry `k`: its sums and skipped texels.
    pub(super) fn row(&self, k: usize, r: u32) -> (Raw, u64) {
        let (chart, cell) = self.charts[k];
        let half = cell.turn == Turn::Half;
        let j = if half { self.ch - 1 - r } else { r };
        let (cw, ch) = (self.cw as usize, self.ch as usize);
        let y = cell.row as usize * ch + r as usize;
        let x0 = cell.col as usize * cw;
        let start = y * self.img.width() as usize + x0;
        let Some(px) = self.img.pixels().get(start..start + cw) else {
            return ([[0.0; 3]; 9], 0);
        };
        let fast = match &self.columns {
            Some(cols) => latlong_row(px, cols, j, self.ch, self.weights.get(chart, 0, j)),
            None => {
                let t = &self.tables[self.table_of[k]];
                let wts = &t[r as usize * cw..(r as usize + 1) * cw];
                let us = if half { &self.us_turned } else { &self.us };
                let v = texel_center(j, self.ch);
                generic_row(self.mapping, chart, us, v, px, wts)
            }
        };
        if finite(&fast) {
            return (fast, 0);
        }
        careful_row(
            self.mapping,
            chart,
            (self.cw, self.ch),
            j,
            half,
            px,
            &self.weights,
        )
    }
}

/// One latlong row by its separable sums: with x = sin θ cos φ,
/// y = sin θ sin φ, z = cos θ, every basis polynomial is a function of θ
/// times one of 1, cos φ, sin φ, cos 2φ, sin 2φ, so the row needs only
/// S_k = Σ L·t_k(φ), combined with θ's factors and the row's solid angle
/// `omega` in f64.
///
/// The sums run over the row's floats as they lie (R G B R G B ...), eight
/// at a time against [`Columns`]' tables laid out the same way: 24 floats
/// (eight texels) are three registers whose lanes hold known channels
/// (float 8p + l is channel (8p + l) mod 3), so the five sums need 15
/// accumulators and no shuffling, and everything stays in registers. f32
/// within [`FLUSH`] batches of eight texels, f64 beyond.
pub(super) fn latlong_row(px: &[[f32; 3]], cols: &Columns, j: u32, h: u32, omega: f64) -> Raw {
    /// Adds the accumulators into `s` (per channel) and clears them.
    fn drain(acc: &mut [[f32x8; 3]; 5], s: &mut [[f64; 3]; 5]) {
        for (a, sk) in acc.iter_mut().zip(s.iter_mut()) {
            for (p, ap) in a.iter_mut().enumerate() {
                for (l, v) in ap.to_array().into_iter().enumerate() {
                    sk[(LANES * p + l) % 3] += f64::from(v);
                }
                *ap = f32x8::ZERO;
            }
        }
    }
    let flat = px.as_flattened();
    let (data, tail) = flat.as_chunks::<LANES>();
    let [t0, t1, t2, t3] = [0, 1, 2, 3].map(|k| cols.tabs[k].as_chunks::<LANES>().0);
    let mut s = [[0.0f64; 3]; 5];
    let mut acc = [[f32x8::ZERO; 3]; 5];
    // One register of floats against the four tables' registers, phase p
    // (its position among the three registers of eight texels).
    #[inline(always)]
    fn add(acc: &mut [[f32x8; 3]; 5], p: usize, d: &[f32; LANES], t: [&[f32; LANES]; 4]) {
        let x = f32x8::new(*d);
        acc[0][p] += x;
        acc[1][p] = x.mul_add(f32x8::new(*t[0]), acc[1][p]);
        acc[2][p] = x.mul_add(f32x8::new(*t[1]), acc[2][p]);
        acc[3][p] = x.mul_add(f32x8::new(*t[2]), acc[3][p]);
        acc[4][p] = x.mul_add(f32x8::new(*t[3]), acc[4][p]);
    }
    let groups = data.chunks_exact(3);
    let (full, rest) = (groups.len(), groups.remainder());
    let table_groups = t0
        .chunks_exact(3)
        .zip(t1.chunks_exact(3))
        .zip(t2.chunks_exact(3))
        .zip(t3.chunks_exact(3));
    let mut n = 0;
    for (d, (((a, b), c), e)) in groups.zip(table_groups.clone()) {
        for p in 0..3 {
            add(&mut acc, p, &d[p], [&a[p], &b[p], &c[p], &e[p]]);
        }
        n += 1;
        if n == FLUSH {
            drain(&mut acc, &mut s);
            n = 0;
        }
    }
    if !rest.is_empty() || !tail.is_empty() {
        // The last texels (fewer than eight), zero-padded; the tables are
        // padded already.
        let mut d = [[0.0f32; LANES]; 3];
        let flat_rest = rest.as_flattened();
        for (k, v) in flat_rest.iter().chain(tail).enumerate() {
            d[k / LANES][k % LANES] = *v;
        }
        if let Some((((a, b), c), e)) = table_groups.clone().nth(full) {
            for p in 0..3 {
                add(&mut acc, p, &d[p], [&a[p], &b[p], &c[p], &e[p]]);
            }
        }
    }
    drain(&mut acc, &mut s);
    let theta = PI * (f64::from(j) + 0.5) / f64::from(h);
    let (st, ct) = theta.sin_cos();
    let [s0, sc, ss, sc2, ss2] = s;
    let mut raw = [[0.0; 3]; 9];
    for c in 0..3 {
        raw[0][c] = omega * s0[c];
        raw[1][c] = omega * st * ss[c];
        raw[2][c] = omega * ct * s0[c];
        raw[3][c] = omega * st * sc[c];
        raw[4][c] = omega * 0.5 * st * st * ss2[c];
        raw[5][c] = omega * st * ct * ss[c];
        raw[6][c] = omega * (3.0 * ct * ct - 1.0) * s0[c];
        raw[7][c] = omega * st * ct * sc[c];
        raw[8][c] = omega * st * st * sc2[c];
    }
    raw
}

/// Adds eight texels (radiance `l` as x, y, z = R, G, B; solid angles `w`;
/// unit directions `d`, NaN where a texel holds none) into `acc`.
#[inline(always)]
pub(super) fn accumulate(acc: &mut [[f32x8; 3]; 9], d: Dir8, l: Dir8, w: f32x8) {
    let bad = d.x.is_nan();
    let zero = f32x8::ZERO;
    let (x, y, z) = (
        bad.select(zero, d.x),
        bad.select(zero, d.y),
        bad.select(zero, d.z),
    );
    let p = [
        y,
        z,
        x,
        x * y,
        y * z,
        (z * f32x8::splat(3.0)).mul_sub(z, f32x8::ONE),
        x * z,
        x.mul_sub(x, y * y),
    ];
    for (c, lc) in [l.x * w, l.y * w, l.z * w].into_iter().enumerate() {
        acc[0][c] += lc;
        for (a, pi) in acc[1..].iter_mut().zip(&p) {
            a[c] = lc.mul_add(*pi, a[c]);
        }
    }
}

/// One stored row of any chart: directions from the mapping's 8-wide
/// inverse ([`Exact`] tier) at the texel centres `us` (stored order, padded
/// to whole batches) and `v`, weights `wts` (stored order).
pub(super) fn generic_row(
    mapping: AnyMapping,
    chart: u32,
    us: &[f32],
    v: f32,
    px: &[[f32; 3]],
    wts: &[f32],
) -> Raw {
    let mut out = [[0.0f64; 3]; 9];
    let mut acc = [[f32x8::ZERO; 3]; 9];
    let (px8, ptail) = px.as_chunks::<LANES>();
    let (w8, wtail) = wts.as_chunks::<LANES>();
    let (u8s, _) = us.as_chunks::<LANES>();
    let (chart8, v8) = (u32x8::splat(chart), f32x8::splat(v));
    let dirs = |u: &[f32; LANES]| mapping.inverse8::<Exact>(Uv8::new(chart8, f32x8::new(*u), v8));
    let mut n = 0;
    for ((p, w), u) in px8.iter().zip(w8).zip(u8s) {
        accumulate(&mut acc, dirs(u), Dir8::from_arrays(p), f32x8::new(*w));
        n += 1;
        if n == FLUSH {
            flush(&mut acc, &mut out);
            n = 0;
        }
    }
    if let Some(u) = u8s.get(px8.len()).filter(|_| !ptail.is_empty()) {
        let mut p = [[0.0f32; 3]; LANES];
        let mut w = [0.0f32; LANES];
        p[..ptail.len()].copy_from_slice(ptail);
        w[..wtail.len()].copy_from_slice(wtail);
        accumulate(&mut acc, dirs(u), Dir8::from_arrays(&p), f32x8::new(w));
    }
    flush(&mut acc, &mut out);
    out
}

/// One stored row texel by texel in f64, skipping (and counting) texels
/// with a NaN or infinite channel: what a row whose fast sums are not
/// finite is summed with.
pub(super) fn careful_row(
    mapping: AnyMapping,
    chart: u32,
    (cw, ch): (u32, u32),
    j: u32,
    half: bool,
    px: &[[f32; 3]],
    weights: &TexelWeights,
) -> (Raw, u64) {
    let mut raw = [[0.0; 3]; 9];
    let mut skipped = 0;
    for (k, l) in (0u32..).zip(px) {
        let i = if half { cw - 1 - k } else { k };
        let wt = weights.get(chart, i, j);
        if wt == 0.0 {
            continue;
        }
        if !l.iter().all(|c| c.is_finite()) {
            skipped += 1;
            continue;
        }
        let c = ChartUv::new(chart, texel_center(i, cw), texel_center(j, ch));
        let Some(d) = mapping.inverse(c).and_then(|d| unit(d.as_dvec3())) else {
            continue;
        };
        let p = poly(d);
        for (r, pi) in raw.iter_mut().zip(p) {
            for c in 0..3 {
                r[c] += f64::from(l[c]) * wt * pi;
            }
        }
    }
    (raw, skipped)
}
