//! The batch mapping contract and the slice functions over it.

use envmap_core::glam::Vec3;
use envmap_core::{AnyMapping, ChartUv};
use wide::f32x8;

use crate::approx::Tier;
#[allow(unused_imports)]
use crate::batch::INVALID_CHART;
use crate::batch::{Dir8, Uv8, LANES};

/// A mapping evaluated eight directions at a time at accuracy tier `T`.
///
/// Implemented for every mapping type of `envmap-core` (and for
/// [`AnyMapping`]). Lanes agree with the scalar core within the tier's bound
/// (the cube, sphere maps, paraboloid and plain octahedral map need no
/// trigonometry and agree to an ulp or two at every tier; the cube's face is
/// always identical). Bad lanes — NaN, ±Inf or zero directions; chart points
/// outside their chart — give [`INVALID_CHART`] and NaN coordinates, or NaN
/// directions, without disturbing the other lanes.
pub trait Mapping8 {
    /// Forward mapping of eight directions (any length, as in the core).
    fn forward8<T: Tier>(&self, d: Dir8) -> Uv8;
    /// Inverse mapping of eight chart points to unit directions.
    fn inverse8<T: Tier>(&self, c: Uv8) -> Dir8;

    /// [`Mapping8::inverse8`] up to a positive scale: each lane's direction
    /// on the ray through `inverse8`'s unit direction, with its largest
    /// component between 1/2 and 2 (NaN where `inverse8` gives NaN), for
    /// callers that need only the ray, such as
    /// [`Mapping8::forward8_ray`]. Conversions map their output texels with
    /// it.
    ///
    /// The default is `inverse8` itself. The cube overrides it with the
    /// face table's row `(±1, ±s, ±t)`, skipping the normalisation (a
    /// square root and three divisions); `inverse8` is that row divided by
    /// its length, bit for bit.
    #[inline]
    fn inverse8_ray<T: Tier>(&self, c: Uv8) -> Dir8 {
        self.inverse8::<T>(c)
    }

    /// [`Mapping8::forward8`] for directions of moderate length: each
    /// lane's largest component between 1/2 and 2 (unit directions as
    /// [`Mapping8::inverse8`] returns them, rays as
    /// [`Mapping8::inverse8_ray`] returns them, either of them rotated), or
    /// NaN in every component (those methods' invalid lanes), so that a
    /// mapping can skip the rescaling and validation that arbitrary input
    /// needs. On such lanes it agrees with `forward8` within the tier's
    /// bound (same chart; a NaN lane gives [`INVALID_CHART`] and NaN
    /// coordinates); other lanes give unspecified values, never a panic.
    ///
    /// The default is `forward8` itself. The latlong overrides it: on such
    /// a direction it is bit for bit `forward8` except within about
    /// 10⁻¹⁹ rad of a pole (where `x² + y²` underflows; the angle is still
    /// within the bound).
    #[inline]
    fn forward8_ray<T: Tier>(&self, d: Dir8) -> Uv8 {
        self.forward8::<T>(d)
    }

    /// [`forward_slice`] for this mapping (override to dispatch once per slice).
    #[inline]
    fn forward_slice<T: Tier>(&self, dirs: &[Vec3], out: &mut [ChartUv]) -> usize {
        forward_slice_with(|d| self.forward8::<T>(d), dirs, out)
    }

    /// [`inverse_slice`] for this mapping (override to dispatch once per slice).
    #[inline]
    fn inverse_slice<T: Tier>(&self, coords: &[ChartUv], out: &mut [Vec3]) -> usize {
        inverse_slice_with(|c| self.inverse8::<T>(c), coords, out)
    }
}

/// Maps `dirs` into `out` (as many as the shorter of the two holds; returns
/// that count). Invalid directions give `ChartUv { chart: INVALID_CHART, u:
/// NaN, v: NaN }`. The tail of fewer than eight goes through the same kernel,
/// padded, so every element gets the same result it would get in a full batch.
///
/// ```
/// use envmap_core::{glam::Vec3, LatLong};
/// use envmap_simd::{forward_slice, Fast};
/// let dirs = [Vec3::X, Vec3::Y, Vec3::NEG_Z];
/// let mut out = [Default::default(); 3];
/// assert_eq!(forward_slice::<_, Fast>(&LatLong, &dirs, &mut out), 3);
/// assert!((out[1].u - 0.25).abs() < 1e-4);
/// ```
pub fn forward_slice<M: Mapping8 + ?Sized, T: Tier>(
    m: &M,
    dirs: &[Vec3],
    out: &mut [ChartUv],
) -> usize {
    m.forward_slice::<T>(dirs, out)
}

#[inline(always)]
fn forward_slice_with(kernel: impl Fn(Dir8) -> Uv8, dirs: &[Vec3], out: &mut [ChartUv]) -> usize {
    let n = dirs.len().min(out.len());
    let (dirs, out) = (&dirs[..n], &mut out[..n]);
    let mut din = dirs.chunks_exact(LANES);
    let mut dout = out.chunks_exact_mut(LANES);
    for (i, o) in (&mut din).zip(&mut dout) {
        let Ok(block) = <&[Vec3; LANES]>::try_from(i) else {
            continue;
        };
        store_uv(kernel(Dir8::from_vec3s(block)), o);
    }
    let (i, o) = (din.remainder(), dout.into_remainder());
    if !i.is_empty() {
        store_uv(kernel(Dir8::from_partial(i)), o);
    }
    n
}

/// Inverse-maps `coords` into `out` (as many as the shorter holds; returns
/// that count). Points outside their chart give `Vec3::NAN`.
pub fn inverse_slice<M: Mapping8 + ?Sized, T: Tier>(
    m: &M,
    coords: &[ChartUv],
    out: &mut [Vec3],
) -> usize {
    m.inverse_slice::<T>(coords, out)
}

#[inline(always)]
fn inverse_slice_with(kernel: impl Fn(Uv8) -> Dir8, coords: &[ChartUv], out: &mut [Vec3]) -> usize {
    let n = coords.len().min(out.len());
    let (coords, out) = (&coords[..n], &mut out[..n]);
    let mut cin = coords.chunks_exact(LANES);
    let mut cout = out.chunks_exact_mut(LANES);
    for (i, o) in (&mut cin).zip(&mut cout) {
        let Ok(block) = <&[ChartUv; LANES]>::try_from(i) else {
            continue;
        };
        let d = kernel(load_uv(block));
        o.copy_from_slice(&d.to_vec3s());
    }
    let (i, o) = (cin.remainder(), cout.into_remainder());
    if !i.is_empty() {
        let d = kernel(Uv8::from_partial(i)).to_vec3s();
        o.copy_from_slice(&d[..o.len()]);
    }
    n
}

/// Loads eight `ChartUv`s as three interleaved registers and transposes them
/// with the same permutes as `Dir8` loads.
#[inline]
fn load_uv(c: &[ChartUv; LANES]) -> Uv8 {
    let mut f = [0.0f32; 3 * LANES];
    for (k, p) in c.iter().enumerate() {
        f[3 * k] = f32::from_bits(p.chart);
        f[3 * k + 1] = p.u;
        f[3 * k + 2] = p.v;
    }
    let d = Dir8::from_interleaved(&f);
    Uv8::new(d.x.to_bits(), d.y, d.z)
}

/// Stores a batch as `ChartUv`s: interleaved with the same permutes as
/// `Dir8` stores, then written field by field (which the compiler merges into
/// whole-register stores, `ChartUv` being `repr(C)`).
#[inline]
fn store_uv(b: Uv8, out: &mut [ChartUv]) {
    let a = Dir8::new(f32x8::from_bits(b.chart), b.u, b.v).to_interleaved();
    for (k, o) in out.iter_mut().enumerate() {
        *o = ChartUv::new(a[3 * k].to_bits(), a[3 * k + 1], a[3 * k + 2]);
    }
}

/// Mask of lanes with u and v in `[0, 1]` (false for NaN).
#[inline]
#[must_use]
pub(crate) fn in_unit_square(u: f32x8, v: f32x8) -> f32x8 {
    let (zero, one) = (f32x8::ZERO, f32x8::ONE);
    u.simd_ge(zero) & u.simd_le(one) & v.simd_ge(zero) & v.simd_le(one)
}

/// Mask of lanes inside the disk inscribed in `[0, 1]²`, tested exactly as the
/// core does: u'² + v'² ≤ 1 + 4ε with u' = 2u − 1, v' = 2v − 1.
#[inline]
#[must_use]
pub(crate) fn in_unit_disk(u: f32x8, v: f32x8) -> f32x8 {
    let two = f32x8::splat(2.0);
    let (x, y) = (two * u - f32x8::ONE, two * v - f32x8::ONE);
    in_unit_square(u, v) & (x * x + y * y).simd_le(f32x8::splat(1.0 + 4.0 * f32::EPSILON))
}

/// Mask of lanes whose chart is below `n`.
#[inline]
#[must_use]
pub(crate) fn chart_below(c: &Uv8, n: u32) -> f32x8 {
    f32x8::from_bits(c.chart.simd_lt(wide::u32x8::splat(n)))
}

/// NaN in the lanes where `valid` is false.
#[inline]
#[must_use]
pub(crate) fn mask_dir(valid: f32x8, d: Dir8) -> Dir8 {
    let nan = f32x8::splat(f32::NAN);
    Dir8::new(
        valid.select(d.x, nan),
        valid.select(d.y, nan),
        valid.select(d.z, nan),
    )
}

/// The azimuth about z of each lane, from x and y as given divided by the larger of |x|, |y|
/// (so that neither underflows next to ±z): `(px, py, √(px² + py²))`; on the z axis the
/// azimuth of +x, `(1, 0, 1)`.
#[inline]
#[must_use]
pub(crate) fn azimuth(d: &Dir8) -> (f32x8, f32x8, f32x8) {
    let a = d.x.abs().fast_max(d.y.abs());
    let pole = a.simd_eq(f32x8::ZERO);
    let px = pole.select(f32x8::ONE, d.x / a);
    let py = pole.select(f32x8::ZERO, d.y / a);
    (px, py, (px * px + py * py).sqrt())
}

/// Divides each lane by its length.
#[inline]
#[must_use]
pub(crate) fn unit(x: f32x8, y: f32x8, z: f32x8) -> Dir8 {
    let len = (x * x + y * y + z * z).sqrt();
    Dir8::new(x / len, y / len, z / len)
}

/// `x` clamped into `[0, 1]`, NaN kept (as `f32::clamp`).
#[inline]
#[must_use]
pub(crate) fn clamp01(x: f32x8) -> f32x8 {
    let lo = x.simd_lt(f32x8::ZERO);
    let hi = x.simd_gt(f32x8::ONE);
    lo.select(f32x8::ZERO, hi.select(f32x8::ONE, x))
}

/// Dispatches once per call: per batch for `forward8`/`inverse8`, per slice
/// for the slice functions (so the concrete kernel inlines into the loop).
impl Mapping8 for AnyMapping {
    fn forward_slice<T: Tier>(&self, dirs: &[Vec3], out: &mut [ChartUv]) -> usize {
        use envmap_core::*;
        match self {
            AnyMapping::LatLong => LatLong.forward_slice::<T>(dirs, out),
            AnyMapping::Cube => Cube.forward_slice::<T>(dirs, out),
            AnyMapping::SphereMap => SphereMap::CLASS.forward_slice::<T>(dirs, out),
            AnyMapping::SphereMapGl => SphereMap::OPENGL.forward_slice::<T>(dirs, out),
            AnyMapping::DualParaboloid => DualParaboloid.forward_slice::<T>(dirs, out),
            AnyMapping::Tennisball => Tennisball.forward_slice::<T>(dirs, out),
            AnyMapping::Octahedral => Octahedral.forward_slice::<T>(dirs, out),
            AnyMapping::EqualAreaOctahedral => EqualAreaOctahedral.forward_slice::<T>(dirs, out),
            AnyMapping::Angular => Angular.forward_slice::<T>(dirs, out),
            AnyMapping::Eac => Eac.forward_slice::<T>(dirs, out),
            AnyMapping::Fisheye(f) => f.forward_slice::<T>(dirs, out),
        }
    }
    fn inverse_slice<T: Tier>(&self, coords: &[ChartUv], out: &mut [Vec3]) -> usize {
        use envmap_core::*;
        match self {
            AnyMapping::LatLong => LatLong.inverse_slice::<T>(coords, out),
            AnyMapping::Cube => Cube.inverse_slice::<T>(coords, out),
            AnyMapping::SphereMap => SphereMap::CLASS.inverse_slice::<T>(coords, out),
            AnyMapping::SphereMapGl => SphereMap::OPENGL.inverse_slice::<T>(coords, out),
            AnyMapping::DualParaboloid => DualParaboloid.inverse_slice::<T>(coords, out),
            AnyMapping::Tennisball => Tennisball.inverse_slice::<T>(coords, out),
            AnyMapping::Octahedral => Octahedral.inverse_slice::<T>(coords, out),
            AnyMapping::EqualAreaOctahedral => EqualAreaOctahedral.inverse_slice::<T>(coords, out),
            AnyMapping::Angular => Angular.inverse_slice::<T>(coords, out),
            AnyMapping::Eac => Eac.inverse_slice::<T>(coords, out),
            AnyMapping::Fisheye(f) => f.inverse_slice::<T>(coords, out),
        }
    }

    fn forward8<T: Tier>(&self, d: Dir8) -> Uv8 {
        use envmap_core::*;
        match self {
            AnyMapping::LatLong => LatLong.forward8::<T>(d),
            AnyMapping::Cube => Cube.forward8::<T>(d),
            AnyMapping::SphereMap => SphereMap::CLASS.forward8::<T>(d),
            AnyMapping::SphereMapGl => SphereMap::OPENGL.forward8::<T>(d),
            AnyMapping::DualParaboloid => DualParaboloid.forward8::<T>(d),
            AnyMapping::Tennisball => Tennisball.forward8::<T>(d),
            AnyMapping::Octahedral => Octahedral.forward8::<T>(d),
            AnyMapping::EqualAreaOctahedral => EqualAreaOctahedral.forward8::<T>(d),
            AnyMapping::Angular => Angular.forward8::<T>(d),
            AnyMapping::Eac => Eac.forward8::<T>(d),
            AnyMapping::Fisheye(f) => f.forward8::<T>(d),
        }
    }
    fn forward8_ray<T: Tier>(&self, d: Dir8) -> Uv8 {
        use envmap_core::*;
        match self {
            AnyMapping::LatLong => LatLong.forward8_ray::<T>(d),
            AnyMapping::Cube => Cube.forward8_ray::<T>(d),
            AnyMapping::SphereMap => SphereMap::CLASS.forward8_ray::<T>(d),
            AnyMapping::SphereMapGl => SphereMap::OPENGL.forward8_ray::<T>(d),
            AnyMapping::DualParaboloid => DualParaboloid.forward8_ray::<T>(d),
            AnyMapping::Tennisball => Tennisball.forward8_ray::<T>(d),
            AnyMapping::Octahedral => Octahedral.forward8_ray::<T>(d),
            AnyMapping::EqualAreaOctahedral => EqualAreaOctahedral.forward8_ray::<T>(d),
            AnyMapping::Angular => Angular.forward8_ray::<T>(d),
            AnyMapping::Eac => Eac.forward8_ray::<T>(d),
            AnyMapping::Fisheye(f) => f.forward8_ray::<T>(d),
        }
    }
    fn inverse8_ray<T: Tier>(&self, c: Uv8) -> Dir8 {
        use envmap_core::*;
        match self {
            AnyMapping::LatLong => LatLong.inverse8_ray::<T>(c),
            AnyMapping::Cube => Cube.inverse8_ray::<T>(c),
            AnyMapping::SphereMap => SphereMap::CLASS.inverse8_ray::<T>(c),
            AnyMapping::SphereMapGl => SphereMap::OPENGL.inverse8_ray::<T>(c),
            AnyMapping::DualParaboloid => DualParaboloid.inverse8_ray::<T>(c),
            AnyMapping::Tennisball => Tennisball.inverse8_ray::<T>(c),
            AnyMapping::Octahedral => Octahedral.inverse8_ray::<T>(c),
            AnyMapping::EqualAreaOctahedral => EqualAreaOctahedral.inverse8_ray::<T>(c),
            AnyMapping::Angular => Angular.inverse8_ray::<T>(c),
            AnyMapping::Eac => Eac.inverse8_ray::<T>(c),
            AnyMapping::Fisheye(f) => f.inverse8_ray::<T>(c),
        }
    }
    fn inverse8<T: Tier>(&self, c: Uv8) -> Dir8 {
        use envmap_core::*;
        match self {
            AnyMapping::LatLong => LatLong.inverse8::<T>(c),
            AnyMapping::Cube => Cube.inverse8::<T>(c),
            AnyMapping::SphereMap => SphereMap::CLASS.inverse8::<T>(c),
            AnyMapping::SphereMapGl => SphereMap::OPENGL.inverse8::<T>(c),
            AnyMapping::DualParaboloid => DualParaboloid.inverse8::<T>(c),
            AnyMapping::Tennisball => Tennisball.inverse8::<T>(c),
            AnyMapping::Octahedral => Octahedral.inverse8::<T>(c),
            AnyMapping::EqualAreaOctahedral => EqualAreaOctahedral.inverse8::<T>(c),
            AnyMapping::Angular => Angular.inverse8::<T>(c),
            AnyMapping::Eac => Eac.inverse8::<T>(c),
            AnyMapping::Fisheye(f) => f.inverse8::<T>(c),
        }
    }
}
