// The DFG table: the integral at every texel of a grid, in the single
// and multiscatter forms, its images and its bilinear lookups.

use std::sync::atomic::AtomicBool;

use crate::cancel;
use crate::error::{Error, Result};
use crate::image::RgbImage;
use crate::par::*;

use super::integral::{columns, Params, Rule, Scratch};
use super::{check_size, DfgGrid};

/// A DFG table of `size × size` texels: the single-scatter
/// `(scale, bias)` and the multiscatter `(bias, scale + bias)`, each
/// computed in f64 and stored as f32. Column `i` is μ = (i + 0.5)/size and
/// row `j` is the perceptual roughness r = (j + 0.5)/size (on
/// [`DfgGrid::Edges`]: i/(size − 1), j/(size − 1)), row 0 first (the top
/// row of its images). See the [module docs](super).
#[derive(Clone, Debug, PartialEq)]
pub struct DfgTable {
    size: u32,
    grid: DfgGrid,
    single: Vec<[f32; 2]>,
    multi: Vec<[f32; 2]>,
}

impl DfgTable {
    /// The table of `size × size` texels
    /// ([`DEFAULT_SIZE`](super::DEFAULT_SIZE) is 128). Rows are computed in
    /// parallel.
    ///
    /// # Errors
    ///
    /// [`Error::Layout`] for size 0, and [`Error::TooLarge`] above
    /// [`MAX_SIZE`](super::MAX_SIZE).
    pub fn new(size: u32) -> Result<DfgTable> {
        DfgTable::new_cancellable(size, None)
    }

    /// As [`DfgTable::new`], checking `cancel` once per row (see
    /// [`crate::cancel`]).
    ///
    /// # Errors
    ///
    /// As [`DfgTable::new`], and [`Error::Cancelled`] once `cancel` is set.
    pub(crate) fn new_cancellable(size: u32, cancel: Option<&AtomicBool>) -> Result<DfgTable> {
        DfgTable::on_grid(size, DfgGrid::TexelCentres, cancel)
    }

    /// As `DfgTable::new_cancellable`, the texels on `grid` (see the
    /// [module docs](super#grids-texel-centres-or-edges)).
    ///
    /// # Errors
    ///
    /// As `DfgTable::new_cancellable`; [`Error::Layout`] for a
    /// [`DfgGrid::Edges`] table under 2 × 2.
    #[cfg_attr(feature = "instruments", visibility::make(pub))]
    pub(crate) fn on_grid(
        size: u32,
        grid: DfgGrid,
        cancel: Option<&AtomicBool>,
    ) -> Result<DfgTable> {
        check_size(size)?;
        if grid == DfgGrid::Edges && size < 2 {
            return Err(Error::layout(
                "DFG table on the edges grid: at least 2×2 texels (its first and last rows are 0 and 1)",
            ));
        }
        let n = size as usize;
        let mut single = vec![[0.0f32; 2]; n * n];
        let mut multi = vec![[0.0f32; 2]; n * n];
        let rule = Rule::new(Params::STANDARD);
        let columns = columns(&rule, size, grid);
        single
            .par_chunks_mut(n)
            .zip(multi.par_chunks_mut(n))
            .enumerate()
            .try_for_each(|(j, (single, multi))| {
                cancel::check(cancel)?;
                let r = grid.point(j as u32, size);
                let mut scratch = Scratch::default();
                for ((col, one), two) in columns.iter().zip(single).zip(multi) {
                    let (s, b) = rule.integrate_in(col, r, &mut scratch);
                    *one = [s as f32, b as f32];
                    *two = [b as f32, (s + b) as f32];
                }
                Ok(())
            })?;
        Ok(DfgTable {
            size,
            grid,
            single,
            multi,
        })
    }

    /// The width and height in texels.
    #[inline]
    #[must_use]
    pub fn size(&self) -> u32 {
        self.size
    }

    /// Where the texels sit ([`DfgGrid`]).
    #[cfg_attr(feature = "instruments", visibility::make(pub))]
    #[inline]
    #[must_use]
    pub(crate) fn grid(&self) -> DfgGrid {
        self.grid
    }

    #[cfg(test)]
    /// (μ, r) of texel (`i`, `j`): ((i + 0.5)/size, (j + 0.5)/size) at
    /// texel centres, (i/(size − 1), j/(size − 1)) on the edges grid.
    #[inline]
    #[must_use]
    pub(crate) fn texel_point(&self, i: u32, j: u32) -> (f64, f64) {
        (self.grid.point(i, self.size), self.grid.point(j, self.size))
    }

    #[cfg(test)]
    /// The single-scatter `[scale, bias]` at column `i` (μ) and row `j` (r);
    /// `None` outside the table.
    #[inline]
    #[must_use]
    pub(crate) fn single_scatter(&self, i: u32, j: u32) -> Option<[f32; 2]> {
        self.index(i, j).map(|k| self.single[k])
    }

    /// The multiscatter `[bias, scale + bias]` at column `i` (μ) and row `j`
    /// (r); `None` outside the table.
    #[inline]
    #[must_use]
    pub fn multiscatter(&self, i: u32, j: u32) -> Option<[f32; 2]> {
        self.index(i, j).map(|k| self.multi[k])
    }

    /// Every texel's single-scatter `[scale, bias]`, row-major, row 0 first.
    #[inline]
    #[must_use]
    pub fn single_scatter_texels(&self) -> &[[f32; 2]] {
        &self.single
    }

    #[cfg(test)]
    /// Every texel's multiscatter `[bias, scale + bias]`, row-major, row 0
    /// first.
    #[inline]
    #[must_use]
    pub(crate) fn multiscatter_texels(&self) -> &[[f32; 2]] {
        &self.multi
    }

    /// The single-scatter `[scale, bias]` at μ and r, bilinear between the
    /// texels' points (`DfgTable::texel_point`): at texel centres, as a
    /// GPU samples the table at (μ, r) with linear filtering and
    /// clamp-to-edge; on the edges grid, as it samples it at
    /// ((size − 1)·x + ½)/size. The arguments are clamped to the outermost
    /// texels; NaN is taken as 0.
    #[must_use]
    pub(crate) fn sample_single_scatter(&self, mu: f32, r: f32) -> [f32; 2] {
        bilinear(&self.single, self.size, self.grid, mu, r)
    }

    /// [`DfgTable::sample_single_scatter`] at each of `mu` and one `r`,
    /// into `out` (as many as both have): the r axis found once, each
    /// value the single lookup's bit for bit.
    pub(crate) fn sample_single_scatter_at(&self, mu: &[f32], r: f32, out: &mut [[f32; 2]]) {
        let (n, r_axis) = (self.size as usize, axis(self.grid, self.size, r));
        let empty = n == 0 || self.single.len() < n * n;
        for (o, &m) in out.iter_mut().zip(mu) {
            *o = if empty {
                [0.0; 2]
            } else {
                blend(&self.single, n, axis(self.grid, self.size, m), r_axis)
            };
        }
    }

    #[cfg(test)]
    /// The multiscatter `[bias, scale + bias]` at μ and r, bilinear as in
    /// [`DfgTable::sample_single_scatter`].
    #[must_use]
    pub(crate) fn sample_multiscatter(&self, mu: f32, r: f32) -> [f32; 2] {
        bilinear(&self.multi, self.size, self.grid, mu, r)
    }

    /// The single-scatter table as an image: R = scale, G = bias, B = 0.
    /// Column i is μ = (i + 0.5)/size; row j (top row first) is
    /// r = (j + 0.5)/size.
    #[cfg_attr(feature = "instruments", visibility::make(pub))]
    #[must_use]
    pub(crate) fn single_scatter_image(&self) -> RgbImage {
        self.image(&self.single)
    }

    /// The multiscatter table (Filament's) as an image: R = bias,
    /// G = scale + bias, B = 0. Column i is μ = (i + 0.5)/size; row j (top
    /// row first) is r = (j + 0.5)/size.
    #[cfg_attr(feature = "instruments", visibility::make(pub))]
    #[must_use]
    pub(crate) fn multiscatter_image(&self) -> RgbImage {
        self.image(&self.multi)
    }

    #[cfg(test)]
    /// The single-scatter texels as IEEE half floats (their bits), rounded
    /// to nearest from the stored f32, row-major, row 0 first: the texels of
    /// an RG16F texture.
    #[must_use]
    pub(crate) fn single_scatter_f16_bits(&self) -> Vec<[u16; 2]> {
        to_f16_bits(&self.single)
    }

    #[cfg(test)]
    /// The multiscatter texels as IEEE half floats (their bits), rounded to
    /// nearest from the stored f32, row-major, row 0 first: the texels of
    /// an RG16F texture.
    #[must_use]
    pub(crate) fn multiscatter_f16_bits(&self) -> Vec<[u16; 2]> {
        to_f16_bits(&self.multi)
    }

    fn index(&self, i: u32, j: u32) -> Option<usize> {
        (i < self.size && j < self.size).then(|| j as usize * self.size as usize + i as usize)
    }

    fn image(&self, texels: &[[f32; 2]]) -> RgbImage {
        RgbImage {
            width: self.size,
            height: self.size,
            pixels: texels.iter().map(|&[a, b]| [a, b, 0.0]).collect(),
        }
    }
}

/// Bilinear lookup between the texels' points on `grid`, clamped to the
/// outermost ones.
fn bilinear(texels: &[[f32; 2]], size: u32, grid: DfgGrid, mu: f32, r: f32) -> [f32; 2] {
    let (n, r_axis) = (size as usize, axis(grid, size, r));
    if n == 0 || texels.len() < n * n {
        return [0.0; 2];
    }
    blend(texels, n, axis(grid, size, mu), r_axis)
}

/// Where `v` falls on one axis of a table of `size` on `grid`: the texel
/// before it, the one after (the same at the last) and the fraction
/// between them; clamped to the outermost texels, NaN taken as 0.
#[inline]
fn axis(grid: DfgGrid, size: u32, v: f32) -> (usize, usize, f32) {
    let n = size.max(1) as usize;
    let v = if v.is_nan() { 0.0 } else { v };
    let x = grid.index_of(v, size).clamp(0.0, (n - 1) as f32);
    let i0 = (x as usize).min(n - 1);
    (i0, (i0 + 1).min(n - 1), x - i0 as f32)
}

/// The bilinear blend of a table of `n` × `n` texels (at least that many)
/// at the places [`axis`] found across (μ) and down (r): across first,
/// then down.
#[inline]
fn blend(
    texels: &[[f32; 2]],
    n: usize,
    (i0, i1, fx): (usize, usize, f32),
    (j0, j1, fy): (usize, usize, f32),
) -> [f32; 2] {
    let at = |i: usize, j: usize| texels[j * n + i];
    let lerp =
        |a: [f32; 2], b: [f32; 2], f: f32| [a[0] + f * (b[0] - a[0]), a[1] + f * (b[1] - a[1])];
    lerp(
        lerp(at(i0, j0), at(i1, j0), fx),
        lerp(at(i0, j1), at(i1, j1), fx),
        fy,
    )
}

/// Each texel's two values as f16 bits, as a half-float file stores them.
#[cfg(test)]
fn to_f16_bits(texels: &[[f32; 2]]) -> Vec<[u16; 2]> {
    use crate::image::texel::f16;
    texels
        .iter()
        .map(|&[a, b]| [f16::from_f32(a), f16::from_f32(b)])
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    use super::super::{dfg_integral, MAX_SIZE, MIN_ARGUMENT};

    /// On the edges grid the first and last rows and columns are at 0 and
    /// 1: roughness 1 and N·V = 1 read the integral there (α = 1:
    /// scale + bias = 1 − μ·ln(1 + 1/μ), 1 − ln 2 head-on), where the texel
    /// centres of the same size read it at 1 − ½/size, 2 to 4 % too high
    /// head-on for 64².
    #[test]
    fn the_edges_grid_reads_exactly_at_its_edges() {
        let edges = DfgTable::on_grid(64, DfgGrid::Edges, None).unwrap();
        let centres = DfgTable::new(64).unwrap();
        assert_eq!(edges.grid(), DfgGrid::Edges);
        assert_eq!(edges.texel_point(0, 63), (0.0, 1.0));
        assert_eq!(edges.texel_point(63, 0), (1.0, 0.0));
        assert_eq!(edges.texel_point(21, 42), (21.0 / 63.0, 42.0 / 63.0));
        let albedo = |t: &DfgTable, mu: f32| {
            let [a, b] = t.sample_single_scatter(mu, 1.0);
            f64::from(a + b)
        };
        let closed = |mu: f64| 1.0 - mu * (1.0 + 1.0 / mu).ln();
        // Head-on, and at a column of the grid (μ = 21/63).
        for mu in [1.0f64, 21.0 / 63.0] {
            let got = albedo(&edges, mu as f32);
            assert!((got / closed(mu) - 1.0).abs() < 2e-6, "{mu}: {got}");
        }
        let off = albedo(&centres, 1.0) / closed(1.0) - 1.0;
        let off128 = albedo(&DfgTable::new(128).unwrap(), 1.0) / closed(1.0) - 1.0;
        println!(
            "at texel centres, roughness 1, head-on: 64² {:+.3} %, 128² {:+.3} %",
            100.0 * off,
            100.0 * off128
        );
        assert!(off > 0.02 && off < 0.04, "{off}");
        // Smooth and grazing: the α → 0 limit at μ = 0 (all bias).
        let [s, b] = edges.sample_single_scatter(0.0, 0.0);
        let (ws, wb) = dfg_integral(MIN_ARGUMENT, MIN_ARGUMENT);
        assert_eq!([s, b], [ws as f32, wb as f32]);
        // Between the points the two grids agree with the integral alike.
        let (ws, wb) = dfg_integral(0.5, 0.5);
        for t in [&edges, &centres] {
            let [s, b] = t.sample_single_scatter(0.5, 0.5);
            assert!((f64::from(s) - ws).abs() < 2e-3 && (f64::from(b) - wb).abs() < 2e-3);
        }
        assert!(matches!(
            DfgTable::on_grid(1, DfgGrid::Edges, None),
            Err(Error::Layout(_))
        ));
        assert_eq!("edges".parse::<DfgGrid>().unwrap(), DfgGrid::Edges);
        assert_eq!(
            "texel-centres".parse::<DfgGrid>().unwrap(),
            DfgGrid::TexelCentres
        );
        assert!("corners".parse::<DfgGrid>().is_err());
    }

    #[test]
    fn sizes() {
        assert!(matches!(DfgTable::new(0), Err(Error::Layout(_))));
        assert!(matches!(
            DfgTable::new(MAX_SIZE + 1),
            Err(Error::TooLarge { limit, .. }) if limit == 4096 * 4096
        ));
        assert!(matches!(
            DfgTable::new(u32::MAX),
            Err(Error::TooLarge { .. })
        ));
        let one = DfgTable::new(1).unwrap();
        assert_eq!(one.size(), 1);
        assert_eq!(one.texel_point(0, 0), (0.5, 0.5));
        let (s, b) = dfg_integral(0.5, 0.5);
        assert_eq!(one.single_scatter(0, 0), Some([s as f32, b as f32]));
        assert_eq!(one.single_scatter(1, 0), None);
        assert_eq!(one.multiscatter(0, 1), None);
        assert_eq!(one.sample_single_scatter(0.9, 0.1), [s as f32, b as f32]);
    }

    /// Column i is μ = (i + 0.5)/n, row j is r = (j + 0.5)/n, row 0 (the
    /// top row of the images) smooth.
    #[test]
    fn orientation_and_forms() {
        let n = 16;
        let t = DfgTable::new(n).unwrap();
        let single = t.single_scatter_image();
        let multi = t.multiscatter_image();
        assert_eq!((single.width, single.height), (n, n));
        assert_eq!((multi.width, multi.height), (n, n));
        for j in 0..n {
            for i in 0..n {
                let (mu, r) = t.texel_point(i, j);
                assert_eq!(
                    (mu, r),
                    ((f64::from(i) + 0.5) / 16.0, (f64::from(j) + 0.5) / 16.0)
                );
                let (s, b) = dfg_integral(mu, r);
                let k = (j * n + i) as usize;
                assert_eq!(t.single_scatter(i, j), Some([s as f32, b as f32]));
                assert_eq!(t.multiscatter(i, j), Some([b as f32, (s + b) as f32]));
                assert_eq!(single.pixels[k], [s as f32, b as f32, 0.0]);
                assert_eq!(multi.pixels[k], [b as f32, (s + b) as f32, 0.0]);
                assert_eq!(t.single_scatter_texels()[k], [s as f32, b as f32]);
                assert_eq!(t.multiscatter_texels()[k], [b as f32, (s + b) as f32]);
            }
        }
        // Head-on (last column): the albedo falls from ~1 (smooth, top row)
        // to 1 − ln 2-ish (rough, bottom row).
        let top = t.multiscatter(n - 1, 0).unwrap()[1];
        let bottom = t.multiscatter(n - 1, n - 1).unwrap()[1];
        assert!(top > 0.999 && bottom < 0.35, "{top} {bottom}");
        // Grazing and smooth (first column, top row): mostly bias.
        let [s, b] = t.single_scatter(0, 0).unwrap();
        assert!(b > 0.8 && s < 0.2, "{s} {b}");
    }

    /// Every value of a 128² table is a fraction of the light: scale and
    /// bias are not negative and add up to at most 1.
    #[test]
    fn values_are_an_albedo() {
        let t = DfgTable::new(128).unwrap();
        for &[s, b] in t.single_scatter_texels() {
            assert!(s >= 0.0 && b >= 0.0 && s + b <= 1.0 + 1e-6, "{s} {b}");
        }
        for &[b, e] in t.multiscatter_texels() {
            assert!(b >= 0.0 && b <= e && e <= 1.0 + 1e-6, "{b} {e}");
        }
    }

    #[test]
    fn bilinear_lookup() {
        let n = 8;
        let t = DfgTable::new(n).unwrap();
        let c = |i: u32| (i as f32 + 0.5) / n as f32;
        // At texel centres: the texels.
        for (i, j) in [(0, 0), (3, 5), (7, 7), (7, 0)] {
            assert_eq!(
                t.sample_single_scatter(c(i), c(j)),
                t.single_scatter(i, j).unwrap()
            );
            assert_eq!(
                t.sample_multiscatter(c(i), c(j)),
                t.multiscatter(i, j).unwrap()
            );
        }
        // Half-way between four centres: their mean.
        let q = [(2, 3), (3, 3), (2, 4), (3, 4)].map(|(i, j)| t.single_scatter(i, j).unwrap());
        let got = t.sample_single_scatter(3.0 / n as f32, 4.0 / n as f32);
        for k in 0..2 {
            let mean = (q[0][k] + q[1][k] + q[2][k] + q[3][k]) / 4.0;
            assert!((got[k] - mean).abs() < 1e-6, "{got:?} {mean}");
        }
        // Clamped outside, NaN as 0.
        let corner = t.single_scatter(0, 0).unwrap();
        assert_eq!(t.sample_single_scatter(0.0, 0.0), corner);
        assert_eq!(t.sample_single_scatter(-5.0, f32::NEG_INFINITY), corner);
        assert_eq!(t.sample_single_scatter(f32::NAN, f32::NAN), corner);
        let far = t.multiscatter(n - 1, n - 1).unwrap();
        assert_eq!(t.sample_multiscatter(1.0, 1.0), far);
        assert_eq!(t.sample_multiscatter(7.0, f32::INFINITY), far);
        // Many μ at one r: each the single lookup, bit for bit.
        let mu = [0.0, 0.013, 0.3, 0.5, 0.77, 0.999, 1.0, -2.0, 3.0, f32::NAN];
        for r in [0.0, 0.07, 0.5, 0.93, 1.0, f32::NAN, 5.0] {
            let mut many = [[9.0f32; 2]; 10];
            t.sample_single_scatter_at(&mu, r, &mut many);
            for (m, got) in mu.iter().zip(many) {
                let one = t.sample_single_scatter(*m, r);
                assert_eq!(got.map(f32::to_bits), one.map(f32::to_bits), "{m} {r}");
            }
        }
    }

    #[test]
    fn half_floats() {
        use crate::image::texel::f16;
        let t = DfgTable::new(8).unwrap();
        for (h, v) in t
            .single_scatter_f16_bits()
            .iter()
            .zip(t.single_scatter_texels())
        {
            for k in 0..2 {
                let back = f16::own_to_f32(h[k]);
                assert_eq!(h[k], f16::from_f32(v[k]));
                assert!((back - v[k]).abs() <= v[k].abs() * 2f32.powi(-11) + 3e-8);
            }
        }
        let m = t.multiscatter_f16_bits();
        assert_eq!(m.len(), 64);
        // Head-on and smooth the albedo rounds to 1.0 (0x3C00) in f16.
        assert_eq!(m[7][1], 0x3C00);
    }

    /// Both images written as f16 EXR files read back as their f16 bits;
    /// as f32 files, as the stored values.
    #[test]
    #[cfg(feature = "exr")]
    fn images_round_trip_through_exr() {
        use crate::image::io::{read_rgb, write_rgb, ExrPrecision, SaveOptions};
        use ::exr::prelude::f16;
        let t = DfgTable::new(12).unwrap();
        let dir = tempfile::tempdir().unwrap();
        for (image, bits) in [
            (t.single_scatter_image(), t.single_scatter_f16_bits()),
            (t.multiscatter_image(), t.multiscatter_f16_bits()),
        ] {
            for precision in [ExrPrecision::F16, ExrPrecision::F32] {
                let path = dir.path().join("dfg.exr");
                let opts = SaveOptions {
                    exr_precision: precision,
                    ..SaveOptions::default()
                };
                write_rgb(&image, &path, &opts).unwrap();
                let (back, _) = read_rgb(&path, 1 << 20, None).unwrap();
                assert_eq!((back.width, back.height), (12, 12));
                for ((p, q), h) in back.pixels.iter().zip(&image.pixels).zip(&bits) {
                    let want = match precision {
                        ExrPrecision::F16 => [
                            f16::from_bits(h[0]).to_f32(),
                            f16::from_bits(h[1]).to_f32(),
                            0.0,
                        ],
                        ExrPrecision::F32 => *q,
                    };
                    assert_eq!(*p, want);
                }
            }
        }
    }

    #[test]
    #[cfg(feature = "parallel")]
    fn thread_count_does_not_change_the_values() {
        let one = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap()
            .install(|| DfgTable::new(24).unwrap());
        let three = rayon::ThreadPoolBuilder::new()
            .num_threads(3)
            .build()
            .unwrap()
            .install(|| DfgTable::new(24).unwrap());
        assert_eq!(one, three);
    }

    #[test]
    fn cancel_stops_the_table() {
        let stop = AtomicBool::new(true);
        assert!(matches!(
            DfgTable::new_cancellable(64, Some(&stop)),
            Err(Error::Cancelled)
        ));
        let go = AtomicBool::new(false);
        assert_eq!(
            DfgTable::new_cancellable(4, Some(&go)).unwrap(),
            DfgTable::new(4).unwrap()
        );
    }
}
