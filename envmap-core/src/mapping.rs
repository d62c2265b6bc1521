//! The mapping contract: every representation is an atlas of charts.

use glam::Vec3;

use crate::atlas::Atlas;

/// A point of a chart: which chart, and where in it.
///
/// `u` grows to the right and `v` downwards, both in `[0, 1]`; `(0, 0)` is the
/// top-left corner of the chart's rectangle (see [`crate::texel`] for how that
/// becomes a texel). Single-chart mappings use chart 0; the cube has six
/// charts (its faces, in GL order), the dual paraboloid and the tennisball two.
///
/// `#[repr(C)]`: 12 bytes, `chart` then `u` then `v`, so arrays of it can be
/// uploaded to GPU buffers as is.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C)]
pub struct ChartUv {
    /// The chart (cube face, paraboloid disk, tennisball strip), from 0.
    pub chart: u32,
    /// Horizontal coordinate in `[0, 1]`, growing to the right.
    pub u: f32,
    /// Vertical coordinate in `[0, 1]`, growing downwards.
    pub v: f32,
}

impl ChartUv {
    /// A chart point.
    #[inline]
    #[must_use]
    pub const fn new(chart: u32, u: f32, v: f32) -> Self {
        Self { chart, u, v }
    }
}

/// The contract every environment-map parameterization keeps.
///
/// * [`forward`](Mapping::forward): any finite non-zero direction (not
///   necessarily unit; components from denormals to `f32::MAX`) gives a chart
///   below [`chart_count`](Mapping::chart_count) and `u`, `v` in `[0, 1]`
///   for which [`in_chart`](Mapping::in_chart) holds. NaN or infinite
///   components and the zero vector give `None`.
/// * [`inverse`](Mapping::inverse): a chart point inside its chart gives a unit
///   direction; a chart number out of range, NaN coordinates, coordinates
///   outside `[0, 1]` or outside the chart's domain (a disk's corners) give
///   `None`.
/// * `inverse(forward(d))` is `normalize(d)` within each mapping's stated
///   angular bound, and `forward(inverse(c))` is `c` wherever the chart owns
///   the direction `inverse(c)` (away from seams, see each mapping).
/// * [`solid_angle`](Mapping::solid_angle) integrates the directions a chart
///   owns over a rectangle of its coordinates, so that the texels of an atlas
///   add up to 4π.
pub trait Mapping {
    /// A short lowercase name (`"latlong"`, `"cube"`, ...), as the command line spells it.
    fn name(&self) -> &'static str;

    /// Number of charts.
    fn chart_count(&self) -> u32;

    /// Direction → chart point. `None` for NaN, ±Inf or zero input.
    fn forward(&self, dir: Vec3) -> Option<ChartUv>;

    /// Chart point → unit direction. `None` outside the chart.
    fn inverse(&self, c: ChartUv) -> Option<Vec3>;

    /// Whether `(u, v)` lies in the domain of `chart` (a rectangle's `[0, 1]²`,
    /// or a disk inscribed in it). Points outside every chart's domain, such as
    /// a sphere map's corners, hold no direction.
    #[must_use]
    fn in_chart(&self, chart: u32, u: f32, v: f32) -> bool {
        chart < self.chart_count() && (0.0..=1.0).contains(&u) && (0.0..=1.0).contains(&v)
    }

    /// Solid angle in steradians of the directions that `chart` owns (the ones
    /// [`forward`](Mapping::forward) sends to it) within the rectangle
    /// `[u0, u1] × [v0, v1]` of its coordinates. Computed in f64 from the
    /// mapping's exact area element; 0 for a chart out of range.
    #[must_use]
    fn solid_angle(&self, chart: u32, u0: f64, u1: f64, v0: f64, v1: f64) -> f64;

    /// Solid angle of texel `(i, j)` of a `w × h` grid laid over one chart.
    #[must_use]
    fn texel_solid_angle(&self, chart: u32, i: u32, j: u32, w: u32, h: u32) -> f64 {
        let (u0, u1) = crate::texel::texel_bounds(i, w);
        let (v0, v1) = crate::texel::texel_bounds(j, h);
        self.solid_angle(chart, u0, u1, v0, v1)
    }

    /// The default layout of the charts in one image.
    fn atlas(&self) -> Atlas;
}

/// Forwarding through references, so `&M` can be used where `M` is expected.
impl<M: Mapping + ?Sized> Mapping for &M {
    fn name(&self) -> &'static str {
        (**self).name()
    }
    fn chart_count(&self) -> u32 {
        (**self).chart_count()
    }
    fn forward(&self, dir: Vec3) -> Option<ChartUv> {
        (**self).forward(dir)
    }
    fn inverse(&self, c: ChartUv) -> Option<Vec3> {
        (**self).inverse(c)
    }
    fn in_chart(&self, chart: u32, u: f32, v: f32) -> bool {
        (**self).in_chart(chart, u, v)
    }
    fn solid_angle(&self, chart: u32, u0: f64, u1: f64, v0: f64, v1: f64) -> f64 {
        (**self).solid_angle(chart, u0, u1, v0, v1)
    }
    fn atlas(&self) -> Atlas {
        (**self).atlas()
    }
}

/// Whether `(u, v)` lies in the closed unit square `[0, 1]²` (false for NaN).
#[inline]
#[must_use]
pub(crate) fn in_unit_square(u: f32, v: f32) -> bool {
    (0.0..=1.0).contains(&u) && (0.0..=1.0).contains(&v)
}

/// Whether `(u, v)` lies in the disk inscribed in `[0, 1]²`, tested as
/// u'² + v'² ≤ 1 + 4ε with u' = 2u − 1, v' = 2v − 1 and ε = `f32::EPSILON`
/// (false for NaN).
///
/// The 4ε allows for the rounding of a rim point's coordinates: `forward` of
/// a direction on a disk's rim (the paraboloid's equator, the sphere map's
/// singular direction) can give u'² + v'² = 1 + ε in f32. Such points invert
/// to the rim direction (`inverse` clamps 1 − r² at 0).
#[inline]
#[must_use]
pub(crate) fn in_unit_disk(u: f32, v: f32) -> bool {
    if !in_unit_square(u, v) {
        return false;
    }
    let (x, y) = (2.0 * u - 1.0, 2.0 * v - 1.0);
    x * x + y * y <= DISK_LIMIT
}

/// The largest u'² + v'² inside a disk chart: 1 + 4ε.
pub(crate) const DISK_LIMIT: f32 = 1.0 + 4.0 * f32::EPSILON;
