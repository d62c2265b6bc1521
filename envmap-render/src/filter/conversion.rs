// Conversion between any two representations: one generic loop.

use std::sync::atomic::AtomicBool;

use crate::par::*;
use envmap_core::atlas::Turn;
use envmap_core::glam::Mat3;
use envmap_core::AnyMapping;
use envmap_core::{Frame, Mapping};
use envmap_simd::{Dir8, Fine, Mapping8, Uv8, LANES};
use wide::{f32x8, u32x8};

use crate::cancel;
#[cfg(doc)]
use crate::error::Error;
use crate::error::Result;
use crate::filter::sample::{Ahead, Filter, Sampler};
use crate::image::{EnvImage, Representation, RowSource};

/// What every batch of a conversion shares.
struct RowContext<'a, D, S> {
    dst: D,
    src: S,
    /// Output axes → input axes, when not the identity.
    m: Option<Mat3>,
    sampler: Sampler<'a>,
    filter: Filter,
}

impl<D: Mapping8, S: Mapping8> RowContext<'_, D, S> {
    /// Maps eight output points: inverse in the output, forward in the
    /// input.
    #[inline(always)]
    fn map(&self, p: Uv8) -> Uv8 {
        // Rays (unit or not), as the forward mapping needs only the ray.
        let mut d = self.dst.inverse8_ray::<Fine>(p);
        if let Some(m) = self.m {
            let (c0, c1, c2) = (m.x_axis, m.y_axis, m.z_axis);
            let s = |k: f32| f32x8::splat(k);
            d = Dir8::new(
                s(c0.x) * d.x + s(c1.x) * d.y + s(c2.x) * d.z,
                s(c0.y) * d.x + s(c1.y) * d.y + s(c2.y) * d.z,
                s(c0.z) * d.x + s(c1.z) * d.y + s(c2.z) * d.z,
            );
        }
        // Rays of moderate length (or NaN lanes), as inverse8_ray gives
        // them and the rotation keeps them.
        self.src.forward8_ray::<Fine>(d)
    }

    /// One sample at each of the texel centres `us` (u per texel, all at
    /// `v`) of one row of `chart`, for `px[at..at + us.len()]`, eight texels
    /// at a time, through `ahead`.
    #[inline]
    fn run_row(
        &self,
        chart: u32,
        us: &[f32],
        v: f32,
        at: usize,
        ahead: &mut Ahead,
        px: &mut [[f32; 3]],
    ) {
        let (chart, v) = (u32x8::splat(chart), f32x8::splat(v));
        let batch = |u: &[f32]| {
            let u: [f32; LANES] = u.try_into().unwrap_or([0.5; LANES]);
            Uv8::new(chart, f32x8::new(u), v)
        };
        let mut at = at;
        // Two batches mapped before either is queued: the mapping is one
        // long chain of dependent operations per batch, and two independent
        // chains side by side keep the processor busy while each waits.
        let mut pairs = us.chunks_exact(2 * LANES);
        for u in &mut pairs {
            let (u0, u1) = u.split_at(LANES);
            let (q0, q1) = (self.map(batch(u0)), self.map(batch(u1)));
            ahead.push(&self.sampler, &q0, self.filter, at, LANES, px);
            ahead.push(&self.sampler, &q1, self.filter, at + LANES, LANES, px);
            at += 2 * LANES;
        }
        let mut lanes = pairs.remainder().chunks_exact(LANES);
        for u in &mut lanes {
            let q = self.map(batch(u));
            ahead.push(&self.sampler, &q, self.filter, at, LANES, px);
            at += LANES;
        }
        let u = lanes.remainder();
        if let Some(&last) = u.last() {
            // The tail: unused lanes repeat the last texel.
            let lanes = core::array::from_fn(|k| u.get(k).copied().unwrap_or(last));
            let q = self.map(Uv8::new(chart, f32x8::new(lanes), v));
            ahead.push(&self.sampler, &q, self.filter, at, u.len(), px);
        }
    }
}

/// How to convert.
#[derive(Clone, Copy, Debug, Default)]
#[non_exhaustive]
pub struct ConvertOptions<'a> {
    /// Reconstruction filter in the input.
    pub filter: Filter,
    /// Sub-samples per output texel side (N×N per texel); `None` chooses
    /// automatically from the ratio of texel counts (see [`auto_samples`]).
    pub samples: Option<u32>,
    /// A rotation of the world applied on the way: the output's direction
    /// `w` (in world axes, z up) reads the input at `rotation.to_canonical(w)`.
    pub rotation: Option<Frame>,
    /// Stops the conversion once set, at the next band of rows (at most 128
    /// rows per thread are finished after it), with [`Error::Cancelled`];
    /// see [`crate::cancel`].
    pub cancel: Option<&'a AtomicBool>,
}

/// Automatic supersampling: `round(√(input texels / output texels))`,
/// clamped to 1..=8, so that every input texel is visited about once when the
/// output is smaller than the input.
#[must_use]
pub fn auto_samples(input_texels: u64, output_texels: u64) -> u32 {
    if output_texels == 0 {
        return 1;
    }
    let r = (input_texels as f64 / output_texels as f64).sqrt().round();
    r.clamp(1.0, 8.0) as u32
}

/// Converts `src` into `repr` at `width × height` (which must fit the
/// representation's atlas). `progress` is called with the number of rows
/// finished, from worker threads.
///
/// # Errors
///
/// The size does not fit `repr` or is above the default size limit;
/// [`Error::Cancelled`] once `opts.cancel` is set.
pub fn convert(
    src: &EnvImage,
    repr: Representation,
    width: u32,
    height: u32,
    opts: &ConvertOptions,
    progress: Option<&(dyn Fn(u32) + Sync)>,
) -> Result<EnvImage> {
    let mut out = EnvImage::new(width, height, repr)?;
    convert_into(src, &mut out, opts, progress)?;
    Ok(out)
}

/// What the input of a conversion sees of its output: a fisheye under 360° leaves part of
/// the sphere unseen, and [`convert`] writes black there. See [`coverage`].
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct Coverage {
    /// The fraction of the output's solid angle that the input sees, in `[0, 1]`, each texel
    /// weighted by its exact solid angle.
    pub fraction: f64,
    /// Per output texel, row by row, the fraction of its 2 × 2 sub-samples inside its chart
    /// whose directions the input sees (0 outside every chart).
    pub texels: Vec<f32>,
}

/// Sub-samples per texel side of [`coverage`].
const COVERAGE_SAMPLES: u32 = 2;

/// What `src` (a representation) sees of a `width × height` output in `repr`, through the
/// rotation of `opts` as [`convert`] applies it: the fraction of the output's solid angle it
/// sees, and each texel's seen fraction (2 × 2 sub-samples per texel). Every mapping but a
/// fisheye under 360° sees everything (fraction 1).
///
/// # Errors
///
/// The size does not fit `repr`.
pub fn coverage(
    src: &Representation,
    repr: Representation,
    width: u32,
    height: u32,
    opts: &ConvertOptions,
) -> Result<Coverage> {
    repr.check_size(width, height)?;
    let rot = opts.rotation.map_or(Mat3::IDENTITY, Frame::matrix);
    let m = src.frame.matrix().transpose() * rot * repr.frame.matrix();
    let atlas = repr.atlas;
    let (cw, ch) = atlas.cell_size(width, height).unwrap_or((width, height));
    let weights = crate::filter::weights::TexelWeights::new(repr.mapping, cw, ch);
    let n = COVERAGE_SAMPLES;
    let w = width as usize;
    let mut texels = vec![0.0f32; w * height as usize];
    // Per row, then summed in row order: the same sums however many threads.
    let rows: Vec<(f64, f64)> = texels
        .par_chunks_mut(w.max(1))
        .enumerate()
        .map(|(y, row)| {
            let (mut seen, mut total) = (0.0f64, 0.0f64);
            for (x, t) in row.iter_mut().enumerate() {
                let Some(c) = atlas.texel_to_chart(x as u32, y as u32, width, height) else {
                    continue;
                };
                // Sub-samples inside the chart, and of those the ones seen.
                let (mut inside, mut k) = (0u32, 0u32);
                for b in 0..n {
                    for a in 0..n {
                        let u = ((f64::from(c.i) + (f64::from(a) + 0.5) / f64::from(n))
                            / f64::from(c.w)) as f32;
                        let v = ((f64::from(c.j) + (f64::from(b) + 0.5) / f64::from(n))
                            / f64::from(c.h)) as f32;
                        let Some(d) = repr
                            .mapping
                            .inverse(envmap_core::ChartUv::new(c.chart, u, v))
                        else {
                            continue;
                        };
                        inside += 1;
                        if src.mapping.forward(m * d).is_some() {
                            k += 1;
                        }
                    }
                }
                *t = if inside == 0 {
                    0.0
                } else {
                    k as f32 / inside as f32
                };
                let omega = weights.get(c.chart, c.i, c.j);
                seen += omega * f64::from(*t);
                total += omega;
            }
            (seen, total)
        })
        .collect();
    let (seen, total) = rows.iter().fold((0.0, 0.0), |a, b| (a.0 + b.0, a.1 + b.1));
    Ok(Coverage {
        fraction: if total > 0.0 { seen / total } else { 0.0 },
        texels,
    })
}

/// Runs `$body` with `$name` bound to the concrete mapping type of `$any`,
/// so that the loops built from it are monomorphic and the kernels inline.
macro_rules! concrete {
    ($any:expr, |$name:ident| $body:expr) => {
        match $any {
            AnyMapping::LatLong => {
                let $name = envmap_core::LatLong;
                $body
            }
            AnyMapping::Cube => {
                let $name = envmap_core::Cube;
                $body
            }
            AnyMapping::SphereMap => {
                let $name = envmap_core::SphereMap::CLASS;
                $body
            }
            AnyMapping::SphereMapGl => {
                let $name = envmap_core::SphereMap::OPENGL;
                $body
            }
            AnyMapping::DualParaboloid => {
                let $name = envmap_core::DualParaboloid;
                $body
            }
            AnyMapping::Tennisball => {
                let $name = envmap_core::Tennisball;
                $body
            }
            AnyMapping::Octahedral => {
                let $name = envmap_core::Octahedral;
                $body
            }
            AnyMapping::EqualAreaOctahedral => {
                let $name = envmap_core::EqualAreaOctahedral;
                $body
            }
            AnyMapping::Angular => {
                let $name = envmap_core::Angular;
                $body
            }
            AnyMapping::Eac => {
                let $name = envmap_core::Eac;
                $body
            }
            AnyMapping::Fisheye(f) => {
                let $name = f;
                $body
            }
        }
    };
}

/// Converts `src` into the existing image `out`, in `out`'s representation
/// and size, overwriting every texel (texels outside every chart become
/// black). Reusing `out` across calls saves allocating and first touching
/// its memory.
///
/// # Errors
///
/// [`Error::Cancelled`] once `opts.cancel` is set (checked at every band of
/// rows); `out` then holds the bands finished so far.
pub fn convert_into(
    src: &EnvImage,
    out: &mut EnvImage,
    opts: &ConvertOptions,
    progress: Option<&(dyn Fn(u32) + Sync)>,
) -> Result<()> {
    let job = Job::new(
        src,
        *out.representation(),
        out.width(),
        out.height(),
        opts,
        progress,
    );
    let geometry = Geometry::of(out);
    // One monomorphic loop per (output, input) pair, so both kernels inline.
    concrete!(job.dst_mapping, |d| concrete!(src.mapping(), |s| {
        Bands::new(&job, d, s, geometry).run(out)
    }));
    cancel::check(opts.cancel)
}

/// A conversion made on demand, rows at a time, instead of into a whole
/// image: what a writer that streams its output (OpenEXR's scan-line
/// blocks) asks for as it goes, so the converted image never exists whole
/// in memory. The rows are the very texels [`convert`] makes (the same
/// loop, band by band).
///
/// ```
/// use envmap_core::AnyMapping;
/// use envmap_render::filter::{convert, ConvertOptions, Streamed};
/// use envmap_render::image::{EnvImage, Representation};
/// let src = EnvImage::new(64, 32, Representation::default_for(AnyMapping::LatLong)).unwrap();
/// let cube = Representation::default_for(AnyMapping::Cube);
/// let opts = ConvertOptions::default();
/// let whole = convert(&src, cube, 64, 48, &opts, None).unwrap();
/// let stream = Streamed::new(&src, cube, 64, 48, &opts, None).unwrap();
/// let mut rows = vec![[0.0f32; 3]; 64 * 5];
/// stream.rows(10, &mut rows);
/// assert_eq!(&rows[..], &whole.pixels()[10 * 64..15 * 64]);
/// ```
pub struct Streamed<'a> {
    repr: Representation,
    width: u32,
    height: u32,
    band: Box<BandFn<'a>>,
}

/// One band of a [`Streamed`] conversion: rows from `y0` into whole rows,
/// through a scratch buffer.
type BandFn<'a> = dyn Fn(u32, &mut [[f32; 3]], &mut Vec<[f32; 3]>) + Sync + 'a;

impl<'a> Streamed<'a> {
    /// The conversion of `src` into a `width` × `height` image in `repr`, as
    /// [`convert`] would make it; `progress` is called with the number of
    /// rows made, as they are.
    ///
    /// # Errors
    ///
    /// A size that does not fit `repr` (as [`EnvImage::new`]).
    pub fn new(
        src: &'a EnvImage,
        repr: Representation,
        width: u32,
        height: u32,
        opts: &ConvertOptions<'a>,
        progress: Option<&'a (dyn Fn(u32) + Sync)>,
    ) -> Result<Self> {
        repr.check_size(width, height)?;
        let job = Job::new(src, repr, width, height, opts, progress);
        let atlas = repr.atlas;
        let geometry = Geometry {
            width,
            height,
            atlas,
            cell: atlas.cell_size(width, height).unwrap_or((width, height)),
            disk: repr.mapping.has_disk_charts(),
        };
        let band: Box<BandFn<'a>> = concrete!(job.dst_mapping, |d| concrete!(src.mapping(), |s| {
            let bands = Bands::new(&job, d, s, geometry);
            Box::new(move |y0, px, scratch| bands.band(y0, px, scratch))
        }));
        Ok(Self {
            repr,
            width,
            height,
            band,
        })
    }

    /// The output's representation.
    #[must_use]
    pub fn representation(&self) -> &Representation {
        &self.repr
    }

    /// The output's width in texels.
    #[must_use]
    pub fn width(&self) -> u32 {
        self.width
    }

    /// The output's height in texels.
    #[must_use]
    pub fn height(&self) -> u32 {
        self.height
    }

    /// Rows `y0..` of the output into `out`: as many whole rows as `out`
    /// holds (its length a multiple of the width), cut at the last row;
    /// the texels [`convert`] makes there. Nothing is written once the
    /// conversion's cancel flag is set.
    pub fn rows(&self, y0: u32, out: &mut [[f32; 3]]) {
        let w = self.width as usize;
        let rows = (out.len() / w.max(1)).min(self.height.saturating_sub(y0) as usize);
        if rows == 0 {
            return;
        }
        let mut scratch = Vec::new();
        (self.band)(y0, &mut out[..rows * w], &mut scratch);
    }
}

impl RowSource for Streamed<'_> {
    fn representation(&self) -> &Representation {
        Streamed::representation(self)
    }

    fn width(&self) -> u32 {
        Streamed::width(self)
    }

    fn height(&self) -> u32 {
        Streamed::height(self)
    }

    fn rows(&self, y0: u32, out: &mut [[f32; 3]]) {
        Streamed::rows(self, y0, out);
    }
}

impl core::fmt::Debug for Streamed<'_> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(
            f,
            "Streamed({} {}×{})",
            self.repr.mapping, self.width, self.height
        )
    }
}

/// The parts of a conversion that do not depend on the mapping types.
struct Job<'a> {
    n: u32,
    m: Option<Mat3>,
    src: &'a EnvImage,
    dst_mapping: AnyMapping,
    filter: Filter,
    progress: Option<&'a (dyn Fn(u32) + Sync)>,
    cancel: Option<&'a AtomicBool>,
}

impl<'a> Job<'a> {
    /// The conversion of `src` into a `width` × `height` image in `repr`.
    fn new(
        src: &'a EnvImage,
        repr: Representation,
        width: u32,
        height: u32,
        opts: &ConvertOptions<'a>,
        progress: Option<&'a (dyn Fn(u32) + Sync)>,
    ) -> Self {
        let n = opts.samples.unwrap_or_else(|| {
            auto_samples(
                u64::from(src.width()) * u64::from(src.height()),
                u64::from(width) * u64::from(height),
            )
        });
        let n = n.clamp(1, 16);
        // Output map's axes → world (z-up) → rotation → input map's axes.
        let rot = opts.rotation.map_or(Mat3::IDENTITY, Frame::matrix);
        let m = src.representation().frame.matrix().transpose() * rot * repr.frame.matrix();
        let transform = (m - Mat3::IDENTITY)
            .to_cols_array()
            .iter()
            .any(|e| e.abs() > 1e-7);
        Self {
            n,
            m: transform.then_some(m),
            src,
            dst_mapping: repr.mapping,
            filter: opts.filter,
            progress,
            cancel: opts.cancel,
        }
    }
}

/// The output's shape: its size, atlas and cells.
#[derive(Clone, Copy)]
struct Geometry {
    width: u32,
    height: u32,
    atlas: envmap_core::Atlas,
    cell: (u32, u32),
    /// Disk charts: texels are averaged over the sub-samples inside.
    disk: bool,
}

impl Geometry {
    fn of(img: &EnvImage) -> Self {
        Self {
            width: img.width(),
            height: img.height(),
            atlas: *img.atlas(),
            cell: img.cell_size(),
            disk: img.mapping().has_disk_charts(),
        }
    }
}

/// One conversion's bands of output rows, each made on its own (in
/// parallel by [`Bands::run`], or on demand by [`Streamed`]).
struct Bands<'a, D, S> {
    ctx: RowContext<'a, D, S>,
    n: u32,
    geometry: Geometry,
    /// Sub-sample coordinates along u and v of a cell.
    offsets_u: Vec<f32>,
    offsets_v: Vec<f32>,
    /// Texel centres of a half-turned cell's row, left to right.
    centres_turned: Vec<f32>,
    disk: bool,
    /// One sample per texel straight into the output.
    direct: bool,
    progress: Option<&'a (dyn Fn(u32) + Sync)>,
    cancel: Option<&'a AtomicBool>,
}

/// Columns of a tile: within a band, cells are walked in tiles of TILE
/// columns so that neighbouring output texels, which read neighbouring
/// input texels, are mapped one after another.
///
/// Tall bands of narrow tiles were the fastest of those tried (bands ×
/// tiles from 16 × 64 to 256 × 48, latlong to cube), with little between
/// 128 × 32, 128 × 40 and 256 × 32.
const TILE: u32 = 32;

impl<'a, D, S> Bands<'a, D, S>
where
    D: Mapping8 + Mapping + Copy + Sync,
    S: Mapping8 + Copy + Sync,
{
    fn new(job: &Job<'a>, dst: D, src: S, geometry: Geometry) -> Self {
        let n = job.n;
        let (cw, ch) = geometry.cell;
        // Sub-sample coordinates along u and v: texel i, sub-sample a at
        // (i + (a + ½)/n) / w, each rounded once from f64.
        let offsets = |len: u32| -> Vec<f32> {
            (0..len * n)
                .map(|k| {
                    let (i, a) = (k / n, k % n);
                    ((f64::from(i) + (f64::from(a) + 0.5) / f64::from(n)) / f64::from(len)) as f32
                })
                .collect()
        };
        let (offsets_u, offsets_v) = (offsets(cw), offsets(ch));
        let centres_turned: Vec<f32> = offsets_u.iter().rev().copied().collect();
        let disk = geometry.disk;
        Self {
            ctx: RowContext {
                dst,
                src,
                m: job.m,
                sampler: Sampler::new(job.src),
                filter: job.filter,
            },
            n,
            geometry,
            offsets_u,
            offsets_v,
            centres_turned,
            disk,
            // Rows of a cell are sampled eight points at a time through the
            // `Ahead` queue: one sample per texel straight into the output;
            // N×N sub-samples, or any sample of a disk chart, into a scratch
            // tile that is then averaged (on a disk, over the sub-samples
            // inside it).
            direct: n == 1 && !disk,
            progress: job.progress,
            cancel: job.cancel,
        }
    }

    /// Every band of `out`, in parallel. Bands shrink with N×N sub-samples
    /// (the scratch tile holds N² samples per texel) and for small outputs,
    /// so that every thread gets several bands.
    fn run(&self, out: &mut EnvImage) {
        let threads = crate::par::current_num_threads().max(1) as u32;
        let band = (self.geometry.height / (4 * threads)).clamp(8, 128 / self.n);
        let w = self.geometry.width as usize;
        out.pixels_mut()
            .par_chunks_mut(w * band as usize)
            .enumerate()
            .for_each_init(Vec::new, |scratch: &mut Vec<[f32; 3]>, (index, px)| {
                self.band(index as u32 * band, px, scratch);
            });
    }

    /// Rows `y0..` of the output into `px` (whole rows), through `scratch`;
    /// nothing once the conversion is cancelled.
    fn band(&self, y0: u32, px: &mut [[f32; 3]], scratch: &mut Vec<[f32; 3]>) {
        if cancel::is_set(self.cancel) {
            return;
        }
        let ctx = &self.ctx;
        let (n, disk, direct) = (self.n, self.disk, self.direct);
        let Geometry {
            width,
            atlas,
            cell: (cw, ch),
            ..
        } = self.geometry;
        let (offsets_u, offsets_v, centres_turned) =
            (&self.offsets_u, &self.offsets_v, &self.centres_turned);
        let dst = ctx.dst;
        let w = width as usize;
        let rows = (px.len() / w) as u32;
        // Every texel of a chart's cell is written once; only cells
        // outside every chart (a cross's corners) need clearing.
        for r in 0..rows {
            let gy = (y0 + r) / ch;
            for gx in (0..atlas.cols).filter(|&gx| atlas.cell_at(gx, gy).is_none()) {
                let at = (r * width + gx * cw) as usize;
                px[at..at + cw as usize].fill([0.0; 3]);
            }
        }
        // Row r of the band in cell column gx: its chart, the u of its
        // sub-samples left to right (reversed in a half-turned cell) and
        // its row index j in the chart; `None` outside every chart.
        let cell_row = |r: u32, gx: u32| {
            let y = y0 + r;
            let (gy, ly) = (y / ch, y % ch);
            let cell = atlas.cell_at(gx, gy)?;
            let half = cell.turn == Turn::Half;
            let j = if half { ch - 1 - ly } else { ly };
            let us: &[f32] = if half { centres_turned } else { offsets_u };
            Some((cell.chart, us, j))
        };
        let mut ahead = Ahead::default();
        for gx in 0..atlas.cols {
            // The rows of this cell column, looked up once for all its
            // tiles.
            let cells: Vec<_> = (0..rows).map(|r| cell_row(r, gx)).collect();
            for tx in (0..cw).step_by(TILE as usize) {
                let end = (tx + TILE).min(cw);
                let (cols, lo, hi) = ((end - tx) as usize, (tx * n) as usize, (end * n) as usize);
                // Scratch layout: row r, sub-row b, then the tile's
                // sub-samples left to right (`run` of them).
                let run = cols * n as usize;
                if !direct {
                    scratch.clear();
                    scratch.resize(rows as usize * n as usize * run, [0.0; 3]);
                }
                for (r, cell) in (0..rows).zip(&cells) {
                    let Some((chart, us, j)) = *cell else {
                        continue;
                    };
                    let at = (r * width + gx * cw + tx) as usize;
                    if direct {
                        let v = offsets_v[j as usize];
                        ctx.run_row(chart, &us[lo..hi], v, at, &mut ahead, px);
                        continue;
                    }
                    for b in 0..n {
                        let v = offsets_v[(j * n + b) as usize];
                        let at = (r * n + b) as usize * run;
                        ctx.run_row(chart, &us[lo..hi], v, at, &mut ahead, scratch);
                    }
                }
                if direct {
                    continue;
                }
                ahead.drain(&ctx.sampler, scratch);
                // Average each texel's sub-samples (in order: sub-row,
                // then left to right), on a disk only those inside it.
                let n = n as usize;
                // 1/k for the usual count, all N×N sub-samples, once.
                let all = (n * n) as u32;
                let r_all = 1.0 / all as f32;
                for (r, cell) in (0..rows).zip(&cells) {
                    let Some((chart, us, j)) = *cell else {
                        continue;
                    };
                    let at = r as usize * w + (gx * cw + tx) as usize;
                    for (lx, p) in px[at..at + cols].iter_mut().enumerate() {
                        let mut acc = [0.0f32; 3];
                        let mut k = 0u32;
                        for b in 0..n {
                            let v = offsets_v[j as usize * n + b];
                            let row = (r as usize * n + b) * run + lx * n;
                            for (a, s) in scratch[row..row + n].iter().enumerate() {
                                if disk && !dst.in_chart(chart, us[lo + lx * n + a], v) {
                                    continue;
                                }
                                acc[0] += s[0];
                                acc[1] += s[1];
                                acc[2] += s[2];
                                k += 1;
                            }
                        }
                        if k > 1 {
                            let rk = if k == all { r_all } else { 1.0 / k as f32 };
                            acc = acc.map(|c| c * rk);
                        }
                        *p = acc;
                    }
                }
            }
        }
        ahead.drain(&ctx.sampler, px);
        if let Some(p) = self.progress {
            p(rows);
        }
    }
}
