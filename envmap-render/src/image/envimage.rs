//! The environment-map image: linear f32 RGB texels tagged with their
//! representation.
//!
//! An [`EnvImage`] is `width × height` texels, row-major, top row first, each
//! `[r, g, b]` in linear light (no transfer curve, no clamping: HDR values
//! survive every step). Its [`Representation`] says which mapping the charts
//! follow, how the charts lie in the image ([`Atlas`]), and the axis
//! convention ([`Frame`]). A cube is always one image in memory (cross,
//! vertical cross, strip or vertical strip); six files are only an on-disk
//! layout (see [`crate::image::io`]).
//!
//! Sizes are checked before any allocation against a limit on the number of
//! texels ([`DEFAULT_MAX_TEXELS`] unless given), so a corrupt header cannot
//! ask for terabytes.

use envmap_core::atlas::Turn;
use envmap_core::texel::texel_center;
use envmap_core::{AnyMapping, Atlas, Frame, Mapping};

use crate::error::{Error, Result};
use crate::image::layout::{check_compatible, Representation};

/// The default limit on texels per image: 2²⁸ (e.g. 16384 × 16384, or a
/// 23170 × 11585 latlong), 3 GiB of f32 RGB.
pub const DEFAULT_MAX_TEXELS: u64 = 1 << 28;

/// Bytes per texel of an [`EnvImage`] (three f32).
pub const BYTES_PER_TEXEL: usize = std::mem::size_of::<[f32; 3]>();

/// Checks `width × height × count` texels (`count` images of that size)
/// against `max_texels`; returns the texel count of one image as `usize`.
///
/// Call this before allocating: the error states the size and the limit.
pub(crate) fn check_size(width: u32, height: u32, count: u32, max_texels: u64) -> Result<usize> {
    let one = u64::from(width) * u64::from(height);
    let texels = one.saturating_mul(u64::from(count));
    if texels > max_texels {
        return Err(Error::TooLarge {
            width: u64::from(width),
            height: u64::from(height) * u64::from(count),
            texels,
            limit: max_texels,
        });
    }
    usize::try_from(one).map_err(|_| Error::TooLarge {
        width: u64::from(width),
        height: u64::from(height),
        texels,
        limit: usize::MAX as u64,
    })
}

/// A plain RGB image with no representation: what a file holds before its
/// layout is known, or one chart cut out of an [`EnvImage`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RgbImage {
    /// Width in texels.
    pub width: u32,
    /// Height in texels.
    pub height: u32,
    /// Linear RGB, row-major, top row first; `width × height` long.
    pub pixels: Vec<[f32; 3]>,
}

/// Summary statistics of an image's texels; see [`EnvImage::stats`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stats {
    /// Texels that hold a direction (inside a chart: not in a cross's empty
    /// cells, not in a disk's corners).
    pub texels: u64,
    /// Of those, texels whose three channels are finite.
    pub finite: u64,
    /// Texels with a NaN in any channel.
    pub nan: u64,
    /// Texels with an infinity in some channel and no NaN.
    pub inf: u64,
    /// Finite texels with a negative channel (lossy EXR compression rings
    /// around suns; no light is negative: `envmap bake` integrates them as
    /// given and clamps its outputs at zero, `convert` keeps them).
    pub negative: u64,
    /// Per-channel minimum over finite texels (0 if there are none).
    pub min: [f32; 3],
    /// Per-channel maximum over finite texels (0 if there are none).
    pub max: [f32; 3],
    /// Per-channel mean over finite texels (0 if there are none), unweighted
    /// by solid angle.
    pub mean: [f64; 3],
    /// Minimum luminance (Rec. 709: 0.2126 R + 0.7152 G + 0.0722 B).
    pub min_luminance: f32,
    /// Maximum luminance.
    pub max_luminance: f32,
    /// Mean luminance.
    pub mean_luminance: f64,
    /// Per-channel average over the sphere of directions: finite texels
    /// weighted by the solid angle they own, so maps of one environment in
    /// different representations agree (0 if there are no finite texels).
    /// Weights are exact per block of at most 256 × 256 blocks per chart and
    /// shared evenly by the block's texels.
    pub sphere_mean: [f64; 3],
    /// Luminance averaged over the sphere, weighted as [`Stats::sphere_mean`].
    pub sphere_mean_luminance: f64,
}

/// Rec. 709 / sRGB luminance of linear RGB.
#[inline]
#[must_use]
pub fn luminance(rgb: [f32; 3]) -> f32 {
    0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]
}

/// An environment map: linear f32 RGB texels and their [`Representation`].
///
/// The size always fits the atlas (checked by every constructor), so the
/// image is never empty and every chart has whole texels.
#[derive(Clone, Debug, PartialEq)]
pub struct EnvImage {
    width: u32,
    height: u32,
    pixels: Vec<[f32; 3]>,
    repr: Representation,
}

/// A chart's rectangle in the image: origin, size, turn.
#[derive(Clone, Copy)]
struct ChartRect {
    x0: u32,
    y0: u32,
    w: u32,
    h: u32,
    turn: Turn,
}

/// An image given away, for functions that take an image by value or by
/// reference ([`crate::bake::Baker::bake`]).
impl From<EnvImage> for std::borrow::Cow<'_, EnvImage> {
    fn from(image: EnvImage) -> Self {
        std::borrow::Cow::Owned(image)
    }
}

/// An image lent, for functions that take an image by value or by
/// reference ([`crate::bake::Baker::bake`]).
impl<'a> From<&'a EnvImage> for std::borrow::Cow<'a, EnvImage> {
    fn from(image: &'a EnvImage) -> Self {
        std::borrow::Cow::Borrowed(image)
    }
}

impl EnvImage {
    /// A black image, checked against [`DEFAULT_MAX_TEXELS`].
    pub fn new(width: u32, height: u32, repr: Representation) -> Result<Self> {
        Self::new_with_limit(width, height, repr, DEFAULT_MAX_TEXELS)
    }

    /// A black image, checked against `max_texels` before allocating.
    ///
    /// Errors if the representation is inconsistent, the size does not fit
    /// its atlas (`cross needs 4:3, this image is 2048×1024 (2:1)`), or the
    /// size exceeds the limit.
    pub(crate) fn new_with_limit(
        width: u32,
        height: u32,
        repr: Representation,
        max_texels: u64,
    ) -> Result<Self> {
        repr.check_size(width, height)?;
        let n = check_size(width, height, 1, max_texels)?;
        Ok(Self {
            width,
            height,
            pixels: vec![[0.0; 3]; n],
            repr,
        })
    }

    /// An image of the given texels (row-major, top row first).
    ///
    /// Errors if `pixels.len() != width × height` or the size does not fit
    /// the representation. No limit applies: the memory is already allocated.
    pub fn from_pixels(
        width: u32,
        height: u32,
        pixels: Vec<[f32; 3]>,
        repr: Representation,
    ) -> Result<Self> {
        repr.check_size(width, height)?;
        if u64::try_from(pixels.len()).ok() != Some(u64::from(width) * u64::from(height)) {
            return Err(Error::PixelCount {
                width,
                height,
                len: pixels.len(),
            });
        }
        Ok(Self {
            width,
            height,
            pixels,
            repr,
        })
    }

    /// An image of a plain RGB image's texels; see [`EnvImage::from_pixels`].
    pub fn from_rgb(rgb: RgbImage, repr: Representation) -> Result<Self> {
        Self::from_pixels(rgb.width, rgb.height, rgb.pixels, repr)
    }

    /// Width in texels.
    #[inline]
    #[must_use]
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in texels.
    #[inline]
    #[must_use]
    pub fn height(&self) -> u32 {
        self.height
    }

    /// The representation.
    #[inline]
    #[must_use]
    pub fn representation(&self) -> &Representation {
        &self.repr
    }

    /// The mapping (shorthand for `representation().mapping`).
    #[inline]
    #[must_use]
    pub fn mapping(&self) -> AnyMapping {
        self.repr.mapping
    }

    /// The atlas (shorthand for `representation().atlas`).
    #[inline]
    #[must_use]
    pub fn atlas(&self) -> &Atlas {
        &self.repr.atlas
    }

    /// Replaces the frame (the texels are unchanged: this only re-labels
    /// which axes they are seen in).
    pub(crate) fn set_frame(&mut self, frame: Frame) {
        self.repr.frame = frame;
    }

    /// Size of one atlas cell (a cube face, a paraboloid disk's square, a
    /// tennisball strip, or the whole image for single-chart layouts).
    #[must_use]
    pub fn cell_size(&self) -> (u32, u32) {
        // The constructors checked that the size fits the atlas.
        self.repr
            .atlas
            .cell_size(self.width, self.height)
            .unwrap_or((self.width, self.height))
    }

    /// All texels, row-major, top row first.
    #[inline]
    #[must_use]
    pub fn pixels(&self) -> &[[f32; 3]] {
        &self.pixels
    }

    /// All texels, mutable.
    #[inline]
    #[must_use]
    pub fn pixels_mut(&mut self) -> &mut [[f32; 3]] {
        &mut self.pixels
    }

    /// The texels, giving up the image.
    #[must_use]
    pub fn into_pixels(self) -> Vec<[f32; 3]> {
        self.pixels
    }

    /// The rows, top first, each `width` texels.
    pub fn rows(&self) -> std::slice::ChunksExact<'_, [f32; 3]> {
        self.pixels.chunks_exact(self.width as usize)
    }

    /// The rows, mutable (for filling rows in parallel).
    pub fn rows_mut(&mut self) -> std::slice::ChunksExactMut<'_, [f32; 3]> {
        self.pixels.chunks_exact_mut(self.width as usize)
    }

    /// Index into [`pixels`](EnvImage::pixels) of texel `(x, y)`, with `x`
    /// and `y` clamped into the image: always a valid index.
    #[inline]
    #[must_use]
    pub(crate) fn pixel_index(&self, x: u32, y: u32) -> usize {
        let x = x.min(self.width - 1) as usize;
        let y = y.min(self.height - 1) as usize;
        y * self.width as usize + x
    }

    /// Texel `(x, y)`, with coordinates clamped into the image.
    #[inline]
    #[must_use]
    pub fn get(&self, x: u32, y: u32) -> [f32; 3] {
        self.pixels[self.pixel_index(x, y)]
    }

    /// Sets texel `(x, y)`; returns `false` (and changes nothing) if it lies
    /// outside the image.
    #[inline]
    pub fn set(&mut self, x: u32, y: u32, rgb: [f32; 3]) -> bool {
        if x >= self.width || y >= self.height {
            return false;
        }
        let i = self.pixel_index(x, y);
        self.pixels[i] = rgb;
        true
    }

    /// Image texel of chart texel `(i, j)` (as the chart is oriented), or
    /// `None` for a chart or texel out of range.
    #[inline]
    #[must_use]
    pub(crate) fn chart_texel_position(&self, chart: u32, i: u32, j: u32) -> Option<(u32, u32)> {
        self.repr
            .atlas
            .chart_to_texel(chart, i, j, self.width, self.height)
    }

    /// Chart texel `(i, j)` of `chart`, read through
    /// [`Atlas::chart_to_texel`]; `None` out of range.
    #[inline]
    #[must_use]
    pub fn chart_texel(&self, chart: u32, i: u32, j: u32) -> Option<[f32; 3]> {
        let (x, y) = self.chart_texel_position(chart, i, j)?;
        Some(self.get(x, y))
    }

    /// Sets chart texel `(i, j)` of `chart`; `false` out of range.
    pub fn set_chart_texel(&mut self, chart: u32, i: u32, j: u32, rgb: [f32; 3]) -> bool {
        match self.chart_texel_position(chart, i, j) {
            Some((x, y)) => self.set(x, y, rgb),
            None => false,
        }
    }

    fn chart_rect(&self, chart: u32) -> Option<ChartRect> {
        let cell = self.repr.atlas.cell_of(chart)?;
        let (w, h) = self.cell_size();
        Some(ChartRect {
            x0: cell.col * w,
            y0: cell.row * h,
            w,
            h,
            turn: cell.turn,
        })
    }

    /// Row `j` of chart `chart` as stored in the image, and whether it is
    /// stored reversed (a chart turned by half a turn: texel `i` of the
    /// chart's row is then element `w − 1 − i`); `None` out of range. For
    /// reading charts without copying them ([`EnvImage::chart_image`]
    /// copies).
    #[must_use]
    pub(crate) fn chart_row(&self, chart: u32, j: u32) -> Option<(&[[f32; 3]], bool)> {
        let r = self.chart_rect(chart)?;
        (j < r.h).then(|| (self.stored_row(&r, j), r.turn == Turn::Half))
    }

    /// One chart cut out as a plain image, in the chart's own orientation (a
    /// cube face exactly as GL expects it); `None` for a chart out of range.
    #[must_use]
    pub fn chart_image(&self, chart: u32) -> Option<RgbImage> {
        let r = self.chart_rect(chart)?;
        let mut pixels = Vec::with_capacity(r.w as usize * r.h as usize);
        for j in 0..r.h {
            pixels.extend_from_slice(self.stored_row(&r, j));
            if r.turn == Turn::Half {
                let start = pixels.len() - r.w as usize;
                pixels[start..].reverse();
            }
        }
        Some(RgbImage {
            width: r.w,
            height: r.h,
            pixels,
        })
    }

    /// Replaces one chart's texels with `image` (in the chart's orientation).
    /// Errors if the chart does not exist or the sizes differ.
    pub fn set_chart_image(&mut self, chart: u32, image: &RgbImage) -> Result<()> {
        let r = self.chart_rect(chart).ok_or_else(|| {
            Error::layout(format!("{} has no chart {chart}", self.repr.atlas.name))
        })?;
        if (image.width, image.height) != (r.w, r.h)
            || image.pixels.len() != r.w as usize * r.h as usize
        {
            return Err(Error::layout(format!(
                "chart {chart} is {}×{}, the image given is {}×{}",
                r.w, r.h, image.width, image.height
            )));
        }
        for (j, src) in image.pixels.chunks_exact(r.w as usize).enumerate() {
            let dst = self.stored_row_mut(&r, j as u32);
            dst.copy_from_slice(src);
            if r.turn == Turn::Half {
                dst.reverse();
            }
        }
        Ok(())
    }

    /// The stored row that holds chart row `j` (in storage order: reversed
    /// for a half-turned chart).
    fn stored_row(&self, r: &ChartRect, j: u32) -> &[[f32; 3]] {
        let y = match r.turn {
            Turn::None => r.y0 + j,
            Turn::Half => r.y0 + r.h - 1 - j,
        };
        let start = y as usize * self.width as usize + r.x0 as usize;
        &self.pixels[start..start + r.w as usize]
    }

    fn stored_row_mut(&mut self, r: &ChartRect, j: u32) -> &mut [[f32; 3]] {
        let y = match r.turn {
            Turn::None => r.y0 + j,
            Turn::Half => r.y0 + r.h - 1 - j,
        };
        let start = y as usize * self.width as usize + r.x0 as usize;
        &mut self.pixels[start..start + r.w as usize]
    }

    /// The same charts, texel for texel, in another atlas of the same mapping
    /// (a cube cross as a strip, say); cells without a chart are black.
    /// Checked against [`DEFAULT_MAX_TEXELS`]. The rows are
    /// [`EnvImage::in_atlas`]'s: a writer that streams takes those instead
    /// of this copy.
    pub fn relayout(&self, atlas: Atlas) -> Result<EnvImage> {
        let view = self.in_atlas(atlas)?;
        let mut out = EnvImage::new(view.width, view.height, view.repr)?;
        view.rows(0, out.pixels_mut());
        Ok(out)
    }

    /// This image seen in another atlas of the same mapping, its rows made
    /// on demand ([`RowSource`]) from the charts where they are: what
    /// [`EnvImage::relayout`] would make, without the copy. Checked as
    /// [`EnvImage::relayout`] is.
    ///
    /// # Errors
    ///
    /// An atlas the mapping cannot be laid out in; a size past
    /// [`DEFAULT_MAX_TEXELS`].
    pub fn in_atlas(&self, atlas: Atlas) -> Result<InAtlas<'_>> {
        check_compatible(self.repr.mapping, &atlas)?;
        let (cw, ch) = self.cell_size();
        let too_big = || Error::TooLarge {
            width: u64::from(atlas.cols) * u64::from(cw),
            height: u64::from(atlas.rows) * u64::from(ch),
            texels: u64::from(atlas.cols) * u64::from(cw) * u64::from(atlas.rows) * u64::from(ch),
            limit: DEFAULT_MAX_TEXELS,
        };
        let width = atlas.cols.checked_mul(cw).ok_or_else(too_big)?;
        let height = atlas.rows.checked_mul(ch).ok_or_else(too_big)?;
        check_size(width, height, 1, DEFAULT_MAX_TEXELS)?;
        Ok(InAtlas {
            image: self,
            repr: Representation { atlas, ..self.repr },
            width,
            height,
            cell: (cw, ch),
        })
    }

    /// Texel statistics over the texels that hold a direction (see [`Stats`]).
    #[must_use]
    pub fn stats(&self) -> Stats {
        let mut s = Stats {
            texels: 0,
            finite: 0,
            nan: 0,
            inf: 0,
            negative: 0,
            min: [f32::INFINITY; 3],
            max: [f32::NEG_INFINITY; 3],
            mean: [0.0; 3],
            min_luminance: f32::INFINITY,
            max_luminance: f32::NEG_INFINITY,
            mean_luminance: 0.0,
            sphere_mean: [0.0; 3],
            sphere_mean_luminance: 0.0,
        };
        let mut sum_y = 0.0f64;
        // Solid-angle weighted sums, and the total weight of finite texels.
        let (mut sphere, mut sphere_y, mut weight) = ([0.0f64; 3], 0.0f64, 0.0f64);
        let mapping = self.repr.mapping;
        for chart in 0..mapping.chart_count() {
            let Some(r) = self.chart_rect(chart) else {
                continue;
            };
            // A domain that holds its corner texels holds them all (the
            // domains are convex): test each texel only for disks.
            let corners = [(0, 0), (r.w - 1, 0), (0, r.h - 1), (r.w - 1, r.h - 1)];
            let whole = corners
                .iter()
                .all(|&(i, j)| mapping.in_chart(chart, texel_center(i, r.w), texel_center(j, r.h)));
            // Texels per block side, and each block's solid angle per texel.
            let b = r.w.max(r.h).div_ceil(256).max(1);
            let (bw, bh) = (r.w.div_ceil(b), r.h.div_ceil(b));
            let block_weight: Vec<f64> = (0..bh)
                .flat_map(|bj| (0..bw).map(move |bi| (bi, bj)))
                .map(|(bi, bj)| {
                    let (i0, i1) = (bi * b, ((bi + 1) * b).min(r.w));
                    let (j0, j1) = (bj * b, ((bj + 1) * b).min(r.h));
                    let (w, h) = (f64::from(r.w), f64::from(r.h));
                    let omega = mapping.solid_angle(
                        chart,
                        f64::from(i0) / w,
                        f64::from(i1) / w,
                        f64::from(j0) / h,
                        f64::from(j1) / h,
                    );
                    omega / f64::from((i1 - i0) * (j1 - j0))
                })
                .collect();
            for j in 0..r.h {
                let row = self.stored_row(&r, j);
                let v = texel_center(j, r.h);
                for (k, px) in row.iter().enumerate() {
                    let i = match r.turn {
                        Turn::None => k as u32,
                        Turn::Half => r.w - 1 - k as u32,
                    };
                    if !whole && !mapping.in_chart(chart, texel_center(i, r.w), v) {
                        continue;
                    }
                    s.texels += 1;
                    if px.iter().any(|c| c.is_nan()) {
                        s.nan += 1;
                        continue;
                    }
                    if px.iter().any(|c| c.is_infinite()) {
                        s.inf += 1;
                        continue;
                    }
                    s.finite += 1;
                    if px.iter().any(|c| *c < 0.0) {
                        s.negative += 1;
                    }
                    let wt = block_weight[((j / b) * bw + i / b) as usize];
                    weight += wt;
                    for (c, &v) in px.iter().enumerate() {
                        s.min[c] = s.min[c].min(v);
                        s.max[c] = s.max[c].max(v);
                        s.mean[c] += f64::from(v);
                        sphere[c] += wt * f64::from(v);
                    }
                    let y = luminance(*px);
                    sphere_y += wt * f64::from(y);
                    s.min_luminance = s.min_luminance.min(y);
                    s.max_luminance = s.max_luminance.max(y);
                    sum_y += f64::from(y);
                }
            }
        }
        if s.finite == 0 {
            s.min = [0.0; 3];
            s.max = [0.0; 3];
            s.min_luminance = 0.0;
            s.max_luminance = 0.0;
        } else {
            let n = s.finite as f64;
            for m in &mut s.mean {
                *m /= n;
            }
            s.mean_luminance = sum_y / n;
            if weight > 0.0 {
                s.sphere_mean = sphere.map(|x| x / weight);
                s.sphere_mean_luminance = sphere_y / weight;
            }
        }
        s
    }

    /// Heap and inline memory this image uses, in bytes.
    #[must_use]
    pub fn memory_bytes(&self) -> usize {
        std::mem::size_of::<Self>() + self.pixels.capacity() * BYTES_PER_TEXEL
    }

    /// Memory an image of `width × height` texels would use, in bytes
    /// (for checking before allocating).
    #[must_use]
    pub fn memory_bytes_for(width: u32, height: u32) -> u64 {
        std::mem::size_of::<Self>() as u64
            + u64::from(width) * u64::from(height) * BYTES_PER_TEXEL as u64
    }
}

/// An image whose rows are made on demand, for a writer that streams its
/// output (OpenEXR's scan-line blocks, `crate::image::io::Outputs::stage_streamed`):
/// a conversion as it runs (`convert::Streamed`), an image in another atlas
/// ([`InAtlas`]). The image never needs to exist whole.
pub trait RowSource: Sync {
    /// The image's representation.
    fn representation(&self) -> &Representation;
    /// Its width in texels.
    fn width(&self) -> u32;
    /// Its height in texels.
    fn height(&self) -> u32;
    /// Rows `y0..` into `out`: as many whole rows as `out` holds (its length
    /// a multiple of the width), cut at the last row.
    fn rows(&self, y0: u32, out: &mut [[f32; 3]]);
}

/// An [`EnvImage`] seen in another atlas of its mapping
/// ([`EnvImage::in_atlas`]): each row copied from the charts' stored rows
/// as it is asked for, cells without a chart black.
///
/// ```
/// use envmap_core::{AnyMapping, Atlas};
/// use envmap_render::image::{EnvImage, Representation, RowSource};
/// let repr = Representation::default_for(AnyMapping::Cube); // a cross
/// let mut cross = EnvImage::new(32, 24, repr).unwrap();
/// cross.set_chart_texel(2, 0, 0, [1.0; 3]); // +y's first texel
/// let strip = cross.in_atlas(Atlas::CUBE_HORIZONTAL_STRIP).unwrap();
/// assert_eq!((strip.width(), strip.height()), (48, 8));
/// let mut row = vec![[0.0f32; 3]; 48];
/// strip.rows(0, &mut row);
/// assert_eq!(row[2 * 8], [1.0; 3]); // +y: the strip's third face
/// ```
#[derive(Clone, Copy, Debug)]
pub struct InAtlas<'a> {
    image: &'a EnvImage,
    repr: Representation,
    width: u32,
    height: u32,
    cell: (u32, u32),
}

impl RowSource for InAtlas<'_> {
    fn representation(&self) -> &Representation {
        &self.repr
    }

    fn width(&self) -> u32 {
        self.width
    }

    fn height(&self) -> u32 {
        self.height
    }

    fn rows(&self, y0: u32, out: &mut [[f32; 3]]) {
        let (cw, ch) = (self.cell.0 as usize, self.cell.1);
        let atlas = &self.repr.atlas;
        let w = self.width as usize;
        let n = (out.len() / w.max(1)).min(self.height.saturating_sub(y0) as usize);
        for (k, row) in out.chunks_exact_mut(w).take(n).enumerate() {
            let y = y0 + k as u32;
            let (r, jj) = (y / ch, y % ch);
            for (col, dst) in row.chunks_exact_mut(cw).enumerate() {
                let cell = atlas.cell_at(col as u32, r);
                // A cell turned half a turn stores chart row h − 1 − jj here,
                // reversed.
                let stored = cell.and_then(|c| {
                    let half = c.turn == Turn::Half;
                    let j = if half { ch - 1 - jj } else { jj };
                    self.image
                        .chart_row(c.chart, j)
                        .map(|(src, reversed)| (src, reversed != half))
                });
                match stored {
                    Some((src, reverse)) => {
                        dst.copy_from_slice(src);
                        if reverse {
                            dst.reverse();
                        }
                    }
                    None => dst.fill([0.0; 3]),
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cube(atlas: Atlas, face: u32) -> EnvImage {
        let repr = Representation::new(AnyMapping::Cube, atlas, Frame::IDENTITY).unwrap();
        let (w, h) = atlas.image_size_for_cell_width(face).unwrap();
        let mut img = EnvImage::new(w, h, repr).unwrap();
        for f in 0..6 {
            for j in 0..face {
                for i in 0..face {
                    let v = (f * 10_000 + j * 100 + i) as f32;
                    assert!(img.set_chart_texel(f, i, j, [v, f as f32, 1.0]));
                }
            }
        }
        img
    }

    #[test]
    fn sizes_are_validated() {
        let latlong = Representation::default_for(AnyMapping::LatLong);
        assert!(EnvImage::new(64, 32, latlong).is_ok());
        let e = EnvImage::new(64, 48, latlong).unwrap_err().to_string();
        assert_eq!(e, "latlong needs 2:1, this image is 64×48 (4:3)");
        assert!(EnvImage::new(0, 0, latlong).is_err());
        let e = EnvImage::new_with_limit(64, 32, latlong, 1000)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("64×32") && e.contains("2048 texels") && e.contains("1000"),
            "{e}"
        );
        // Far too large: refused before allocating.
        assert!(EnvImage::new(u32::MAX, u32::MAX / 2, latlong).is_err());
        let e = EnvImage::from_pixels(4, 2, vec![[0.0; 3]; 7], latlong).unwrap_err();
        assert!(matches!(e, Error::PixelCount { len: 7, .. }));
        let e = Representation::new(AnyMapping::SphereMap, Atlas::LATLONG, Frame::IDENTITY)
            .unwrap_err()
            .to_string();
        assert!(e.contains("sphere") && e.contains("square"), "{e}");
    }

    #[test]
    fn addressing_never_goes_out_of_range() {
        let mut img =
            EnvImage::new(8, 4, Representation::default_for(AnyMapping::LatLong)).unwrap();
        assert!(img.set(7, 3, [1.0, 2.0, 3.0]));
        assert!(!img.set(8, 0, [9.0; 3]));
        assert_eq!(img.pixel_index(100, 100), 31);
        assert_eq!(img.get(u32::MAX, u32::MAX), [1.0, 2.0, 3.0]);
        assert_eq!(img.chart_texel(0, 7, 3), Some([1.0, 2.0, 3.0]));
        assert_eq!(img.chart_texel(1, 0, 0), None);
        assert_eq!(img.chart_texel(0, 8, 0), None);
        assert_eq!(img.rows().count(), 4);
    }

    #[test]
    fn charts_survive_relayout_between_cube_atlases() {
        let cross = cube(Atlas::CUBE_HORIZONTAL_CROSS, 3);
        for atlas in [
            Atlas::CUBE_VERTICAL_CROSS,
            Atlas::CUBE_HORIZONTAL_STRIP,
            Atlas::CUBE_VERTICAL_STRIP,
        ] {
            let other = cross.relayout(atlas).unwrap();
            assert_eq!(other.atlas(), &atlas);
            for f in 0..6 {
                assert_eq!(other.chart_image(f), cross.chart_image(f));
                for j in 0..3 {
                    for i in 0..3 {
                        assert_eq!(other.chart_texel(f, i, j), cross.chart_texel(f, i, j));
                    }
                }
            }
            assert_eq!(other.relayout(Atlas::CUBE_HORIZONTAL_CROSS).unwrap(), cross);
        }
        // The vertical cross stores −z turned: its bottom-right texel is chart (0, 0).
        let v = cross.relayout(Atlas::CUBE_VERTICAL_CROSS).unwrap();
        assert_eq!(v.get(5, 11), cross.chart_texel(5, 0, 0).unwrap());
        assert!(cross.relayout(Atlas::LATLONG).is_err());
    }

    /// Rows asked for in any band (as a streaming writer asks) are the
    /// relaid image's rows, whatever `out` held; rows past the end are
    /// left alone; empty cells are black.
    #[test]
    fn rows_in_another_atlas_come_in_any_band() {
        let strip = cube(Atlas::CUBE_HORIZONTAL_STRIP, 5);
        for atlas in [
            Atlas::CUBE_HORIZONTAL_CROSS,
            Atlas::CUBE_VERTICAL_CROSS,
            Atlas::CUBE_HORIZONTAL_STRIP,
            Atlas::CUBE_VERTICAL_STRIP,
        ] {
            let whole = strip.relayout(atlas).unwrap();
            // Checked apart from the view: every chart texel where it belongs.
            for f in 0..6 {
                assert_eq!(whole.chart_image(f), strip.chart_image(f));
            }
            let view = strip.in_atlas(atlas).unwrap();
            assert_eq!(view.representation(), whole.representation());
            let (w, h) = (view.width() as usize, view.height());
            assert_eq!((w as u32, h), (whole.width(), whole.height()));
            for (y0, n) in [(0, 1), (3, 4), (4, 7), (h - 2, 5), (h - 1, 1), (h, 2)] {
                let mut out = vec![[7.0f32; 3]; n * w];
                view.rows(y0, &mut out);
                let made = (h - y0.min(h)) as usize;
                let made = made.min(n);
                let start = y0 as usize * w;
                assert_eq!(
                    &out[..made * w],
                    &whole.pixels()[start..start + made * w],
                    "{} rows {y0}+{n}",
                    atlas.name
                );
                assert!(out[made * w..].iter().all(|t| *t == [7.0; 3]));
            }
            // Every cell without a chart: black.
            let (cw, ch) = whole.cell_size();
            for r in 0..atlas.rows {
                for c in 0..atlas.cols {
                    if atlas.cell_at(c, r).is_some() {
                        continue;
                    }
                    for y in r * ch..(r + 1) * ch {
                        for x in c * cw..(c + 1) * cw {
                            assert_eq!(whole.get(x, y), [0.0; 3]);
                        }
                    }
                }
            }
        }
        let pb = EnvImage::new(
            16,
            8,
            Representation::default_for(AnyMapping::DualParaboloid),
        )
        .unwrap();
        assert_eq!(
            pb.relayout(Atlas::PARABOLOID_SIDE_BY_SIDE).unwrap(),
            pb,
            "the same atlas: the same image"
        );
        assert!(strip.in_atlas(Atlas::LATLONG).is_err());
    }

    #[test]
    fn stats_count_only_chart_texels() {
        let mut img = cube(Atlas::CUBE_HORIZONTAL_CROSS, 2);
        // An empty cell of the cross: ignored.
        img.set(0, 0, [f32::NAN; 3]);
        img.set_chart_texel(0, 0, 0, [f32::NAN, 0.0, 0.0]);
        img.set_chart_texel(0, 1, 0, [f32::INFINITY, 0.0, 0.0]);
        img.set_chart_texel(0, 0, 1, [-1.0, 0.0, 0.0]);
        let s = img.stats();
        assert_eq!((s.texels, s.nan, s.inf, s.finite), (24, 1, 1, 22));
        assert_eq!(s.min, [-1.0, 0.0, 0.0]);
        assert_eq!(s.max, [50_101.0, 5.0, 1.0]);
        // A sphere map's corners hold no direction.
        let sphere =
            EnvImage::new(16, 16, Representation::default_for(AnyMapping::SphereMap)).unwrap();
        let s = sphere.stats();
        assert!(s.texels < 256 && s.texels > 190, "{}", s.texels);
        assert_eq!(s.mean_luminance, 0.0);
        assert!(sphere.memory_bytes() >= 256 * 12);
        assert_eq!(
            EnvImage::memory_bytes_for(16, 16) as usize,
            sphere.memory_bytes()
        );
    }
}
