//! The exact solid angle of every texel of a representation's charts, as
//! weights for averaging (mip pyramids), projecting (SH9) and integrating
//! (irradiance, prefiltering) over the sphere.
//!
//! Each value is [`Mapping::texel_solid_angle`] from `envmap-core`, computed
//! once per grid: a latlong's texels differ only by row and a cube's six
//! faces share one table, so those are stored once; every other mapping
//! keeps a table per chart. The texels of all charts add up to 4π (to f64
//! rounding: the core's accuracy is stated in `envmap_core::solid_angle`),
//! except on a disk chart (sphere maps, paraboloid, angular), where a texel
//! whose centre lies outside the disk holds no direction and has weight 0:
//! there the sum falls short of 4π by the slivers of disk those rim texels
//! cover.

use crate::par::*;
use envmap_core::texel::{texel_bounds, texel_center};
use envmap_core::{AnyMapping, Mapping};
use envmap_simd::solid_angle::cube_face4;
use envmap_simd::Uv8;
use wide::{f32x8, f64x4, i32x8};

/// Texel solid angles of a representation's charts, `w × h` texels each;
/// see the [module docs](self).
#[derive(Clone, Debug, PartialEq)]
pub struct TexelWeights {
    w: u32,
    h: u32,
    charts: u32,
    kind: Kind,
    /// A square cube face's quadrant folded across its diagonal too and
    /// rounded to f32, for [`TexelWeights::get_f32`], made by
    /// [`TexelWeights::for_lookups`]; empty otherwise.
    folded: Vec<f32>,
}

#[derive(Clone, Debug, PartialEq)]
enum Kind {
    /// One value per row (latlong).
    Rows(Vec<f64>),
    /// One quadrant of a table shared by every chart (the cube's faces,
    /// each symmetric about its centre lines: [`cube_quadrant`]).
    Quadrant(Vec<f64>),
    /// A table per chart.
    PerChart(Vec<Vec<f64>>),
}

/// Solid angles of one chart's texels, row by row; 0 for a texel whose
/// centre lies outside the chart's domain (a disk's corners: it holds no
/// direction, and no value).
fn table(mapping: AnyMapping, chart: u32, w: u32, h: u32) -> Vec<f64> {
    (0..h)
        .into_par_iter()
        .flat_map_iter(|j| (0..w).map(move |i| weight(mapping, chart, i, j, w, h)))
        .collect()
}

/// A cube face's quadrant: a face is symmetric under u → 1 − u and
/// v → 1 − v, so texel (i, j) has the solid angle of (w − 1 − i, j) and of
/// (i, h − 1 − j); only ⌈w/2⌉ × ⌈h/2⌉ texels are stored. A square face is
/// also symmetric under u ↔ v: there (i, j) below the diagonal takes the
/// solid angle measured at (j, i), and only half the quadrant is measured.
/// Measured four texels at a time ([`cube_face4`]: the core's formula,
/// within 10⁻¹⁵ relative of it).
fn cube_quadrant(w: u32, h: u32) -> Vec<f64> {
    let (qw, qh) = (w.div_ceil(2), h.div_ceil(2));
    let square = w == h;
    // Row j of the quadrant from texel `from` on (the rest 0).
    let row = move |j: u32, from: u32| {
        let mut out = vec![0.0; qw as usize];
        let (v0, v1) = texel_bounds(j, h);
        for i0 in (from..qw).step_by(4) {
            // Lanes past the quadrant's edge repeat its last texel, unused.
            let u: [(f64, f64); 4] =
                core::array::from_fn(|k| texel_bounds((i0 + k as u32).min(qw - 1), w));
            let omega = cube_face4(
                f64x4::new(u.map(|b| b.0)),
                f64x4::new(u.map(|b| b.1)),
                f64x4::splat(v0),
                f64x4::splat(v1),
            );
            for (o, x) in out[i0 as usize..].iter_mut().zip(omega.to_array()) {
                *o = x;
            }
        }
        out
    };
    // Below the diagonal of a square face: the mirror images of (j, i),
    // filled in afterwards.
    let mut t: Vec<f64> = (0..qh)
        .into_par_iter()
        .flat_map_iter(|j| row(j, if square { j.min(qw) } else { 0 }))
        .collect();
    if square {
        let q = qw as usize;
        for j in 0..q {
            for i in 0..j {
                t[j * q + i] = t[i * q + j];
            }
        }
    }
    t
}

/// The lower triangle of a square quadrant `q` texels wide (row `a`
/// holds columns `0..=a`), rounded to f32: by the face's symmetry across
/// its diagonal, every texel of the quadrant.
fn fold_diagonal(t: &[f64], q: u32) -> Vec<f32> {
    let q = q as usize;
    (0..q)
        .flat_map(|a| t[a * q..a * q + a + 1].iter().map(|&x| x as f32))
        .collect()
}

/// Four texels' solid angles, two from each of two rows, as the weights
/// of their mean ([`TexelWeights::halving_taps`]): each over the sum
/// (a₀ + a₁) + (b₀ + b₁), rounded to f32; all 0 where the sum is 0.
#[inline]
fn halving_tap(a: [f64; 2], b: [f64; 2]) -> [f32; 4] {
    let sum = (a[0] + a[1]) + (b[0] + b[1]);
    if sum > 0.0 {
        let inv = 1.0 / sum;
        [a[0], a[1], b[0], b[1]].map(|w| (w * inv) as f32)
    } else {
        [0.0; 4]
    }
}

/// The weight of one texel: its solid angle, or 0 where its centre is
/// outside the chart.
#[inline]
pub(crate) fn weight(mapping: AnyMapping, chart: u32, i: u32, j: u32, w: u32, h: u32) -> f64 {
    let (u, v) = (texel_center(i, w), texel_center(j, h));
    if mapping.has_disk_charts() && !mapping.in_chart(chart, u, v) {
        return 0.0;
    }
    mapping.texel_solid_angle(chart, i, j, w, h)
}

impl TexelWeights {
    /// The weights of `mapping`'s charts at `w × h` texels each.
    #[must_use]
    pub fn new(mapping: AnyMapping, w: u32, h: u32) -> Self {
        let charts = mapping.chart_count();
        let kind = match mapping {
            AnyMapping::LatLong => Kind::Rows(
                (0..h)
                    .map(|j| mapping.texel_solid_angle(0, 0, j, w, h))
                    .collect(),
            ),
            AnyMapping::Cube => Kind::Quadrant(cube_quadrant(w, h)),
            _ => Kind::PerChart((0..charts).map(|c| table(mapping, c, w, h)).collect()),
        };
        Self {
            w,
            h,
            charts,
            kind,
            folded: Vec::new(),
        }
    }

    /// The same weights, made ready for [`TexelWeights::get_f32`] one texel
    /// at a time in no order: a square cube face's quadrant also folded
    /// across its diagonal in f32 (its eighth: 512 KiB for 1024² faces,
    /// against the f64 quadrant's 2 MiB), which stays in the cache. Other
    /// tables are read as they are.
    #[must_use]
    pub fn for_lookups(mut self) -> Self {
        if let Kind::Quadrant(t) = &self.kind {
            if self.w == self.h {
                self.folded = fold_diagonal(t, self.w.div_ceil(2));
            }
        }
        self
    }

    /// Chart size in texels.
    #[must_use]
    pub fn size(&self) -> (u32, u32) {
        (self.w, self.h)
    }

    /// Whether every chart has the same weights (a latlong's one chart, a
    /// cube's six faces), so that what is made from one chart's row serves
    /// every chart's.
    #[must_use]
    pub fn shared(&self) -> bool {
        matches!(self.kind, Kind::Rows(_) | Kind::Quadrant(_))
    }

    /// The solid angle of texel `(i, j)` of `chart` (0 out of range).
    #[inline]
    #[must_use]
    pub fn get(&self, chart: u32, i: u32, j: u32) -> f64 {
        if chart >= self.charts || i >= self.w || j >= self.h {
            return 0.0;
        }
        let k = (j * self.w + i) as usize;
        match &self.kind {
            Kind::Rows(r) => r[j as usize],
            Kind::Quadrant(t) => {
                let (i, j) = (i.min(self.w - 1 - i), j.min(self.h - 1 - j));
                t[(j * self.w.div_ceil(2) + i) as usize]
            }
            Kind::PerChart(t) => t[chart as usize][k],
        }
    }

    /// [`TexelWeights::get`] rounded to f32, bit for bit; from the folded
    /// table where [`TexelWeights::for_lookups`] made one (a mip-aware
    /// render's levels, a lookup per pixel).
    #[inline]
    #[must_use]
    pub fn get_f32(&self, chart: u32, i: u32, j: u32) -> f32 {
        if self.folded.is_empty() {
            return self.get(chart, i, j) as f32;
        }
        if chart >= self.charts || i >= self.w || j >= self.h {
            return 0.0;
        }
        let (i, j) = (i.min(self.w - 1 - i), j.min(self.h - 1 - j));
        let (a, b) = (i.max(j) as usize, i.min(j) as usize);
        self.folded.get(a * (a + 1) / 2 + b).copied().unwrap_or(0.0)
    }

    /// The f32 solid angles of the texels eight chart points land in:
    /// lane `k` is [`TexelWeights::get_f32`] of texel
    /// (`texel_index(u, w)`, `texel_index(v, h)`: the core's
    /// [`texel_index`](envmap_core::texel::texel_index)) of its chart, bit
    /// for bit (the same rule in eight lanes: clamped to [0, 1], a NaN
    /// coordinate counting as 0). With the folded table (a
    /// square cube face's, [`TexelWeights::for_lookups`]) the texels are
    /// found and folded eight at a time, leaving only the eight loads.
    #[inline]
    #[must_use]
    pub fn get8_f32(&self, q: &Uv8) -> f32x8 {
        let (w, h) = (self.w, self.h);
        // clamp(u, 0, 1), NaN to 0 (`max` takes the other lane where one is
        // NaN), times the size; ≥ 0, so truncation is the floor.
        let texel = |u: f32x8, n: u32| {
            let x = u.max(f32x8::ZERO).min(f32x8::ONE) * f32x8::splat(n as f32);
            x.fast_trunc_int().min(i32x8::splat(n as i32 - 1))
        };
        let (i, j) = (texel(q.u, w), texel(q.v, h));
        let chart = q.chart.to_array();
        if self.folded.is_empty() || w != h {
            let (i, j) = (i.to_array(), j.to_array());
            return f32x8::new(core::array::from_fn(|k| {
                self.get_f32(chart[k], i[k] as u32, j[k] as u32)
            }));
        }
        // Folded into the quadrant, then below its diagonal: row a ≥ b.
        let last = i32x8::splat(w as i32 - 1);
        let (i, j) = (i.min(last - i), j.min(last - j));
        let (a, b) = (i.max(j).to_array(), i.min(j).to_array());
        f32x8::new(core::array::from_fn(|k| {
            let (a, b) = (a[k] as usize, b[k] as usize);
            if chart[k] >= self.charts {
                return 0.0;
            }
            self.folded.get(a * (a + 1) / 2 + b).copied().unwrap_or(0.0)
        }))
    }

    /// Row `j` of `chart`, `w` values.
    #[must_use]
    pub fn row(&self, chart: u32, j: u32) -> Vec<f64> {
        let mut out = Vec::new();
        self.row_into(chart, j, &mut out);
        out
    }

    /// Row `j` of `chart` into `out` (resized to `w` values), each
    /// [`TexelWeights::get`]'s, without a lookup per texel.
    pub(crate) fn row_into(&self, chart: u32, j: u32, out: &mut Vec<f64>) {
        let w = self.w as usize;
        out.clear();
        if chart >= self.charts || j >= self.h {
            out.resize(w, 0.0);
            return;
        }
        match (&self.kind, self.quadrant_row(j)) {
            (Kind::Rows(r), _) => out.resize(w, r[j as usize]),
            (Kind::Quadrant(_), Some(half)) => {
                // The left half as stored, the right half its mirror
                // image (the middle texel of an odd row once).
                out.extend_from_slice(half);
                out.extend(half[..w - half.len()].iter().rev());
            }
            (Kind::Quadrant(_), None) => out.resize(w, 0.0),
            (Kind::PerChart(t), _) => {
                out.extend_from_slice(&t[chart as usize][j as usize * w..][..w]);
            }
        }
    }

    /// The weights halving makes texel `k` of row `cj` one level down
    /// with (an even size, `w / 2` texels): texels `2k` and `2k + 1` of rows
    /// `2cj` (a) and `2cj + 1` (b) of `chart`, each solid angle over their
    /// sum (a₀ + a₁) + (b₀ + b₁) in f64, rounded to f32; all 0 where the sum
    /// is 0; into `out`. The sum reads the same in any mirror image of the
    /// four, so a cube face, whose weights mirror left to right, has the
    /// right half of every row's weights made as the left half's mirror
    /// image, read from its quadrant in place; other tables' rows are
    /// copied into `rows` first.
    pub(crate) fn halving_taps(
        &self,
        chart: u32,
        cj: u32,
        rows: &mut [Vec<f64>; 2],
        out: &mut Vec<[f32; 4]>,
    ) {
        let n = (self.w / 2) as usize;
        let (j0, j1) = (2 * cj, 2 * cj + 1);
        out.clear();
        match self.quadrant_rows(chart, cj) {
            Some((a, b)) => {
                let w = self.w as usize;
                // The pairs in the left half as stored; the middle pair of
                // an odd count straddles the middle (texel i of a row is
                // its quadrant's min(i, w − 1 − i)); the rest mirrored.
                let left = n / 2;
                let (a2, b2) = (&a[..2 * left], &b[..2 * left]);
                let pairs = a2.chunks_exact(2).zip(b2.chunks_exact(2));
                out.extend(pairs.map(|(a, b)| halving_tap([a[0], a[1]], [b[0], b[1]])));
                if n % 2 == 1 {
                    let (i0, i1) = (2 * left, (2 * left + 1).min(w - 2 * left - 2));
                    out.push(halving_tap([a[i0], a[i1]], [b[i0], b[i1]]));
                }
                for k in n - left..n {
                    let [a0, a1, b0, b1] = out[n - 1 - k];
                    out.push([a1, a0, b1, b0]);
                }
            }
            None => {
                let [r0, r1] = rows;
                self.row_into(chart, j0, r0);
                self.row_into(chart, j1, r1);
                let pairs = r0.chunks_exact(2).zip(r1.chunks_exact(2)).take(n);
                out.extend(pairs.map(|(a, b)| halving_tap([a[0], a[1]], [b[0], b[1]])));
            }
        }
    }

    /// Asks the processor to start loading what
    /// [`TexelWeights::halving_taps`] reads for row `cj` of `chart` from a
    /// cube face's quadrant, without waiting: a hint only (nothing for
    /// other tables, or off x86-64).
    pub(crate) fn ask_for_halving(&self, chart: u32, cj: u32) {
        #[cfg(all(target_arch = "x86_64", target_feature = "sse"))]
        if let Some((a, b)) = self.quadrant_rows(chart, cj) {
            for row in [a, b] {
                // Every 64-byte line of the row (eight weights).
                for x in row.iter().step_by(8) {
                    safe_arch::prefetch_t0(x);
                }
            }
        }
        #[cfg(not(all(target_arch = "x86_64", target_feature = "sse")))]
        let _ = (chart, cj);
    }

    /// The left half of row `j` of a cube face as its quadrant table
    /// stores it (row `j` is the quadrant's row min(j, h − 1 − j), and
    /// texel `i` of a row its half's min(i, w − 1 − i)); `None` for other
    /// tables or a row past the last.
    fn quadrant_row(&self, j: u32) -> Option<&[f64]> {
        let Kind::Quadrant(t) = &self.kind else {
            return None;
        };
        if j >= self.h {
            return None;
        }
        let qw = self.w.div_ceil(2) as usize;
        t.get(j.min(self.h - 1 - j) as usize * qw..)?.get(..qw)
    }

    /// The quadrant rows ([`TexelWeights::quadrant_row`]) of rows `2·cj`
    /// and `2·cj + 1` of `chart`: what [`TexelWeights::halving_taps`]
    /// makes a row of weights from. `None` for other tables, a chart out
    /// of range or rows past the last.
    fn quadrant_rows(&self, chart: u32, cj: u32) -> Option<(&[f64], &[f64])> {
        if chart >= self.charts {
            return None;
        }
        Some((self.quadrant_row(2 * cj)?, self.quadrant_row(2 * cj + 1)?))
    }

    /// The smallest solid angle of a texel that holds a direction (the
    /// smallest non-zero weight; 0 if there is none).
    #[must_use]
    pub fn smallest(&self) -> f64 {
        let tables: &[Vec<f64>] = match &self.kind {
            Kind::Rows(r) | Kind::Quadrant(r) => core::slice::from_ref(r),
            Kind::PerChart(t) => t,
        };
        // In parallel, each run with a comparison the compiler can make
        // vector-wide (the weights are finite and not NaN).
        let least = tables
            .par_iter()
            .flat_map(|t| t.par_chunks(4096))
            .map(|run| {
                run.iter().fold(f64::INFINITY, |m, &x| {
                    let x = if x > 0.0 { x } else { f64::INFINITY };
                    if x < m {
                        x
                    } else {
                        m
                    }
                })
            })
            .collect::<Vec<f64>>()
            .into_iter()
            .fold(f64::INFINITY, f64::min);
        if least.is_finite() {
            least
        } else {
            0.0
        }
    }

    /// The sum over every texel of every chart (4π for a whole sphere).
    #[must_use]
    pub fn total(&self) -> f64 {
        match &self.kind {
            Kind::Rows(r) => r.iter().sum::<f64>() * f64::from(self.w),
            Kind::Quadrant(_) => {
                let per_face: f64 = (0..self.h)
                    .flat_map(|j| (0..self.w).map(move |i| (i, j)))
                    .map(|(i, j)| self.get(0, i, j))
                    .sum();
                per_face * f64::from(self.charts)
            }
            Kind::PerChart(t) => t.iter().flatten().sum(),
        }
    }
}

/// A map's energy per channel (Σ Ω·L over its texels, exact solid
/// angles; NaN and infinite values count as 0), and that of its negative
/// values alone.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ChannelEnergy {
    /// Σ Ω·L per channel, negative texels included.
    pub total: [f64; 3],
    /// Σ Ω·min(L, 0) per channel (≤ 0).
    pub negative: [f64; 3],
}

/// [`ChannelEnergy`] of `img`, summed in f64 per row and added in a fixed
/// order (the same at any thread count).
#[must_use]
#[allow(clippy::needless_range_loop)]
pub fn channel_energy(img: &crate::image::EnvImage) -> ChannelEnergy {
    let mapping = img.mapping();
    let (cw, ch) = img.cell_size();
    let weights = TexelWeights::new(mapping, cw, ch);
    let rows: Vec<(u32, u32)> = (0..mapping.chart_count())
        .flat_map(|c| (0..ch).map(move |j| (c, j)))
        .collect();
    let parts: Vec<ChannelEnergy> = rows
        .par_iter()
        .map(|&(chart, j)| {
            let mut e = ChannelEnergy::default();
            let Some((row, reversed)) = img.chart_row(chart, j) else {
                return e;
            };
            for (k, p) in row.iter().enumerate() {
                let i = if reversed {
                    cw - 1 - k as u32
                } else {
                    k as u32
                };
                let o = weights.get(chart, i, j);
                for c in 0..3 {
                    let v = if p[c].is_finite() {
                        f64::from(p[c])
                    } else {
                        0.0
                    };
                    e.total[c] += o * v;
                    if v < 0.0 {
                        e.negative[c] += o * v;
                    }
                }
            }
            e
        })
        .collect();
    let mut e = ChannelEnergy::default();
    for p in &parts {
        for c in 0..3 {
            e.total[c] += p.total[c];
            e.negative[c] += p.negative[c];
        }
    }
    e
}

#[cfg(test)]
mod tests {
    use super::*;
    use envmap_core::texel::texel_index;
    use envmap_core::ChartUv;

    /// A row at once is each texel's weight: every kind of table, odd and
    /// even sizes, rows out of range.
    #[test]
    fn the_smallest_weight_is_the_smallest_texel_that_holds_a_direction() {
        for m in AnyMapping::ALL {
            let (w, h) = (12 * m.atlas().cell_aspect_w, 12 * m.atlas().cell_aspect_h);
            let t = TexelWeights::new(m, w, h);
            let least = (0..m.chart_count())
                .flat_map(|c| (0..h).flat_map(move |j| (0..w).map(move |i| (c, i, j))))
                .map(|(c, i, j)| t.get(c, i, j))
                .filter(|&x| x > 0.0)
                .fold(f64::INFINITY, f64::min);
            assert_eq!(t.smallest(), least, "{m}");
        }
    }

    #[test]
    fn a_row_is_its_texels_weights() {
        for m in [AnyMapping::Cube, AnyMapping::LatLong, AnyMapping::SphereMap] {
            for (w, h) in [(1, 1), (4, 4), (7, 7), (9, 5)] {
                let (w, h) = if m == AnyMapping::Cube {
                    (w, w)
                } else {
                    (w, h)
                };
                let t = TexelWeights::new(m, w, h);
                let mut row = Vec::new();
                for chart in 0..=m.chart_count() {
                    for j in 0..=h {
                        t.row_into(chart, j, &mut row);
                        let want: Vec<f64> = (0..w).map(|i| t.get(chart, i, j)).collect();
                        assert_eq!(row, want, "{m} {w}×{h} chart {chart} row {j}");
                    }
                }
            }
        }
    }

    #[test]
    fn the_cube_quadrant_mirrors_the_whole_face() {
        for (w, h) in [(1, 1), (2, 2), (5, 5), (8, 8), (17, 17)] {
            let t = TexelWeights::new(AnyMapping::Cube, w, h);
            for j in 0..h {
                for i in 0..w {
                    let direct = weight(AnyMapping::Cube, 0, i, j, w, h);
                    let got = t.get(3, i, j);
                    // The same solid angle by the formula at the mirrored
                    // texel, whose f64 rounding differs by a few units in
                    // the last place, far below f32's.
                    assert!(
                        (got - direct).abs() <= 1e-13 * direct,
                        "{w}×{h} ({i}, {j}): {got} {direct}"
                    );
                }
            }
        }
    }

    /// Tables read by lookups: square cube faces folded (odd and even
    /// sizes), a cube's oblong faces, a latlong's rows, a table per chart.
    const LOOKUP_CASES: [(AnyMapping, u32, u32); 7] = [
        (AnyMapping::Cube, 1, 1),
        (AnyMapping::Cube, 2, 2),
        (AnyMapping::Cube, 7, 7),
        (AnyMapping::Cube, 16, 16),
        (AnyMapping::Cube, 6, 4),
        (AnyMapping::LatLong, 12, 6),
        (AnyMapping::Octahedral, 9, 9),
    ];

    /// The f32 lookup is the f64 one rounded, bit for bit, through the
    /// folded table of a square cube face (odd and even sizes, every face,
    /// texels out of range) and the plain rounding elsewhere.
    #[test]
    fn an_f32_lookup_is_the_f64_weight_rounded() {
        for (m, w, h) in LOOKUP_CASES {
            let t = TexelWeights::new(m, w, h).for_lookups();
            if m == AnyMapping::Cube && w == h {
                assert_eq!(
                    t.folded.len() as u32,
                    w.div_ceil(2) * (w.div_ceil(2) + 1) / 2
                );
            }
            for chart in 0..=m.chart_count() {
                for j in 0..=h {
                    for i in 0..=w {
                        let (want, got) = (t.get(chart, i, j) as f32, t.get_f32(chart, i, j));
                        assert_eq!(
                            got.to_bits(),
                            want.to_bits(),
                            "{m} {w}×{h} {chart} ({i}, {j})"
                        );
                    }
                }
            }
        }
    }

    /// Eight chart points at a time, folded or not, are the texels the
    /// core's scalar rule ([`texel_index`]) finds, looked up one at a
    /// time: over each mapping's texel edges and centres, past both ends,
    /// NaN and charts out of range.
    #[test]
    fn eight_lookups_are_eight_single_ones() {
        for (m, w, h) in LOOKUP_CASES {
            let t = TexelWeights::new(m, w, h).for_lookups();
            // Texel edges and centres, and beyond: −0.5 … 1.5 in eighths
            // of a texel, then the odd ones.
            let mut coords: Vec<f32> = (-4 * w as i32..=12 * w as i32)
                .map(|k| k as f32 / (8 * w) as f32)
                .collect();
            coords.extend([f32::NAN, -0.0, 1.0, f32::INFINITY, f32::NEG_INFINITY]);
            coords.extend([1.0 - f32::EPSILON / 2.0, f32::MIN_POSITIVE]);
            let points: Vec<ChartUv> = (0..=m.chart_count())
                .flat_map(|c| {
                    let coords = &coords;
                    coords.iter().enumerate().map(move |(k, &u)| {
                        // v runs through the same values in another order.
                        let v = coords[(k * 7 + 3) % coords.len()];
                        ChartUv::new(c, u, v)
                    })
                })
                .collect();
            for p in points.chunks(8) {
                let mut lanes = [ChartUv::default(); 8];
                lanes[..p.len()].copy_from_slice(p);
                let got = t.get8_f32(&Uv8::from_chart_uvs(&lanes)).to_array();
                for (c, g) in lanes.iter().zip(got) {
                    let want = t.get_f32(c.chart, texel_index(c.u, w), texel_index(c.v, h));
                    assert_eq!(g.to_bits(), want.to_bits(), "{m} {w}×{h} {c:?}");
                }
            }
        }
    }

    /// Halving's weights, read from a cube face's quadrant with the right
    /// half mirrored, are those made from each row's weights in full, bit
    /// for bit; every table kind's sum to 1 (to f32 rounding).
    #[test]
    fn halving_weights_are_those_of_the_full_rows() {
        let cases = [
            (AnyMapping::Cube, 2, 2),
            (AnyMapping::Cube, 6, 6),
            (AnyMapping::Cube, 16, 16),
            (AnyMapping::Cube, 10, 6),
            (AnyMapping::LatLong, 12, 6),
            (AnyMapping::Octahedral, 8, 8),
            (AnyMapping::SphereMap, 8, 8),
        ];
        let (mut rows, mut got) = (Default::default(), Vec::new());
        for (m, w, h) in cases {
            let t = TexelWeights::new(m, w, h);
            for chart in 0..=m.chart_count() {
                for cj in 0..h / 2 {
                    t.halving_taps(chart, cj, &mut rows, &mut got);
                    let (r0, r1) = (t.row(chart, 2 * cj), t.row(chart, 2 * cj + 1));
                    let want: Vec<[f32; 4]> = (0..w as usize / 2)
                        .map(|k| {
                            halving_tap([r0[2 * k], r0[2 * k + 1]], [r1[2 * k], r1[2 * k + 1]])
                        })
                        .collect();
                    assert_eq!(got, want, "{m} {w}×{h} chart {chart} row {cj}");
                    for tap in &got {
                        let sum: f32 = tap.iter().sum();
                        assert!(sum == 0.0 || (sum - 1.0).abs() < 4e-7, "{m} {tap:?}");
                    }
                }
            }
        }
    }

    #[test]
    fn every_representation_adds_up_to_the_sphere() {
        for m in AnyMapping::ALL {
            let a = m.atlas();
            let (w, h) = (8 * a.cell_aspect_w, 8 * a.cell_aspect_h);
            let t = TexelWeights::new(m, w, h);
            let total = t.total();
            // The sphere, or what a fisheye sees.
            let sphere = m.seen_solid_angle();
            if m.has_disk_charts() {
                // The slivers of the rim texels whose centres are outside.
                assert!(total < sphere && total > 0.95 * sphere, "{m}: {total}");
            } else {
                assert!((total - sphere).abs() < 1e-12, "{m}: {total}");
            }
            assert_eq!(t.get(m.chart_count(), 0, 0), 0.0);
            assert_eq!(t.get(0, w, 0), 0.0);
        }
    }
}
