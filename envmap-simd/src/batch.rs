//! Struct-of-arrays batches of eight directions or chart points, and their
//! loads and stores.
//!
//! Loads from array-of-structs memory (`[Vec3; 8]`, `[[f32; 3]; 8]`) read the
//! 24 floats as three `f32x8` registers and transpose them with three
//! single-register permutes and two blends per output register, not lane by lane.

use envmap_core::glam::Vec3;
use envmap_core::ChartUv;
use wide::{f32x8, u32x8};

/// Lanes per batch.
pub const LANES: usize = 8;

/// The chart number of an invalid lane (NaN, ±Inf or zero input; or an inverse
/// of a point outside every chart).
pub const INVALID_CHART: u32 = u32::MAX;

/// Eight directions, one per lane.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Dir8 {
    /// x components.
    pub x: f32x8,
    /// y components.
    pub y: f32x8,
    /// z components.
    pub z: f32x8,
}

/// Eight chart points, one per lane. Invalid lanes have chart
/// [`INVALID_CHART`] and NaN coordinates.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Uv8 {
    /// Chart per lane.
    pub chart: u32x8,
    /// u per lane.
    pub u: f32x8,
    /// v per lane.
    pub v: f32x8,
}

/// Where output lane `k` of a 3-register gather comes from: which register
/// (as three lane masks) and which lane of it.
struct Gather {
    lane: u32x8,
    from0: f32x8,
    from1: f32x8,
}

/// The gather that picks component `c` of eight interleaved x, y, z triples
/// held in three registers (float `3n + c` is register `(3n + c) / 8`, lane
/// `(3n + c) % 8`).
const fn deinterleave(c: usize) -> Gather {
    let mut lane = [0u32; 8];
    let mut r0 = [0u32; 8];
    let mut r1 = [0u32; 8];
    let mut n = 0;
    while n < 8 {
        let f = 3 * n + c;
        lane[n] = (f % 8) as u32;
        r0[n] = if f / 8 == 0 { u32::MAX } else { 0 };
        r1[n] = if f / 8 == 1 { u32::MAX } else { 0 };
        n += 1;
    }
    Gather {
        lane: u32x8::new(lane),
        from0: f32x8::from_bits(u32x8::new(r0)),
        from1: f32x8::from_bits(u32x8::new(r1)),
    }
}

/// The gather that builds register `r` of the interleaved output from the
/// x, y, z registers (float `8r + k` is component `(8r + k) % 3` of
/// direction `(8r + k) / 3`).
const fn interleave(r: usize) -> Gather {
    let mut lane = [0u32; 8];
    let mut r0 = [0u32; 8];
    let mut r1 = [0u32; 8];
    let mut k = 0;
    while k < 8 {
        let f = 8 * r + k;
        lane[k] = (f / 3) as u32;
        r0[k] = if f.is_multiple_of(3) { u32::MAX } else { 0 };
        r1[k] = if f % 3 == 1 { u32::MAX } else { 0 };
        k += 1;
    }
    Gather {
        lane: u32x8::new(lane),
        from0: f32x8::from_bits(u32x8::new(r0)),
        from1: f32x8::from_bits(u32x8::new(r1)),
    }
}

const LOAD: [Gather; 3] = [deinterleave(0), deinterleave(1), deinterleave(2)];
const STORE: [Gather; 3] = [interleave(0), interleave(1), interleave(2)];

/// Three single-register permutes (one `vpermps` each with AVX2) and two
/// blends.
#[inline]
fn gather(g: &Gather, a: f32x8, b: f32x8, c: f32x8) -> f32x8 {
    g.from0.select(
        a.shuffle(g.lane),
        g.from1.select(b.shuffle(g.lane), c.shuffle(g.lane)),
    )
}

#[inline]
fn load8(s: &[f32]) -> f32x8 {
    let mut a = [0.0f32; 8];
    a.copy_from_slice(&s[..8]);
    f32x8::new(a)
}

impl Dir8 {
    /// A batch from its three component registers.
    #[inline]
    #[must_use]
    pub const fn new(x: f32x8, y: f32x8, z: f32x8) -> Self {
        Self { x, y, z }
    }

    /// The same direction in every lane.
    #[inline]
    #[must_use]
    pub fn splat(d: Vec3) -> Self {
        Self::new(f32x8::splat(d.x), f32x8::splat(d.y), f32x8::splat(d.z))
    }

    /// Transposes 24 floats in x, y, z order (eight directions) into a batch.
    #[inline]
    #[must_use]
    pub fn from_interleaved(f: &[f32; 24]) -> Self {
        let (a, b, c) = (load8(&f[0..8]), load8(&f[8..16]), load8(&f[16..24]));
        Self::new(
            gather(&LOAD[0], a, b, c),
            gather(&LOAD[1], a, b, c),
            gather(&LOAD[2], a, b, c),
        )
    }

    /// Loads eight `Vec3`s.
    #[inline]
    #[must_use]
    pub fn from_vec3s(v: &[Vec3; 8]) -> Self {
        Self::from_interleaved(bytemuck::cast_ref(v))
    }

    /// Loads eight `[x, y, z]` arrays.
    #[inline]
    #[must_use]
    pub fn from_arrays(v: &[[f32; 3]; 8]) -> Self {
        Self::from_interleaved(bytemuck::cast_ref(v))
    }

    /// Loads from separate x, y and z slices of eight.
    #[inline]
    #[must_use]
    pub fn from_xyz(x: &[f32; 8], y: &[f32; 8], z: &[f32; 8]) -> Self {
        Self::new(f32x8::new(*x), f32x8::new(*y), f32x8::new(*z))
    }

    /// Loads up to eight `Vec3`s, filling missing lanes with +z (a valid
    /// direction, so padding never produces NaN work).
    #[inline(always)]
    #[must_use]
    pub fn from_partial(v: &[Vec3]) -> Self {
        // A full batch loads in place; a short one is copied lane by lane
        // (a copy of a length known only at run time is a call whose wide
        // stores the loads after it cannot be forwarded from).
        if let Some(full) = v.first_chunk::<8>() {
            return Self::from_vec3s(full);
        }
        let mut a = [Vec3::Z; 8];
        for (a, v) in a.iter_mut().zip(v) {
            *a = *v;
        }
        Self::from_vec3s(&a)
    }

    /// Interleaves the batch back into 24 floats in x, y, z order.
    #[inline]
    #[must_use]
    pub fn to_interleaved(self) -> [f32; 24] {
        let (x, y, z) = (self.x, self.y, self.z);
        let mut out = [0.0f32; 24];
        out[0..8].copy_from_slice(&gather(&STORE[0], x, y, z).to_array());
        out[8..16].copy_from_slice(&gather(&STORE[1], x, y, z).to_array());
        out[16..24].copy_from_slice(&gather(&STORE[2], x, y, z).to_array());
        out
    }

    /// Stores as eight `Vec3`s.
    #[inline]
    #[must_use]
    pub fn to_vec3s(self) -> [Vec3; 8] {
        bytemuck::cast(self.to_interleaved())
    }

    /// Stores as eight `[x, y, z]` arrays.
    #[inline]
    #[must_use]
    pub fn to_arrays(self) -> [[f32; 3]; 8] {
        bytemuck::cast(self.to_interleaved())
    }

    /// Lane `i` (0..8) as a `Vec3`.
    #[inline]
    #[must_use]
    pub fn lane(&self, i: usize) -> Vec3 {
        Vec3::new(
            self.x.as_array()[i],
            self.y.as_array()[i],
            self.z.as_array()[i],
        )
    }
}

impl Uv8 {
    /// A batch from its registers.
    #[inline]
    #[must_use]
    pub const fn new(chart: u32x8, u: f32x8, v: f32x8) -> Self {
        Self { chart, u, v }
    }

    /// Loads eight chart points.
    #[inline]
    #[must_use]
    pub fn from_chart_uvs(c: &[ChartUv; 8]) -> Self {
        let mut ch = [0u32; 8];
        let mut u = [0.0f32; 8];
        let mut v = [0.0f32; 8];
        for k in 0..8 {
            ch[k] = c[k].chart;
            u[k] = c[k].u;
            v[k] = c[k].v;
        }
        Self::new(u32x8::new(ch), f32x8::new(u), f32x8::new(v))
    }

    /// Loads up to eight chart points; missing lanes get chart 0 at (½, ½).
    #[inline]
    #[must_use]
    pub fn from_partial(c: &[ChartUv]) -> Self {
        // As `Dir8::from_partial`: a full batch in place, a short one lane
        // by lane.
        if let Some(full) = c.first_chunk::<8>() {
            return Self::from_chart_uvs(full);
        }
        let mut a = [ChartUv::new(0, 0.5, 0.5); 8];
        for (a, c) in a.iter_mut().zip(c) {
            *a = *c;
        }
        Self::from_chart_uvs(&a)
    }

    /// Lane `i` (0..8); `None` for an invalid lane.
    #[inline]
    #[must_use]
    pub fn lane(&self, i: usize) -> Option<ChartUv> {
        let c = self.chart.as_array()[i];
        (c != INVALID_CHART).then(|| ChartUv::new(c, self.u.as_array()[i], self.v.as_array()[i]))
    }

    /// Lane `i` (0..8) as stored, invalid lanes included.
    #[inline]
    #[must_use]
    pub fn lane_raw(&self, i: usize) -> ChartUv {
        ChartUv::new(
            self.chart.as_array()[i],
            self.u.as_array()[i],
            self.v.as_array()[i],
        )
    }
}

/// Whether each lane is a valid direction: all components finite and not all
/// zero. All-ones lanes for valid, as an `f32x8` mask.
#[inline]
#[must_use]
pub(crate) fn valid_direction(d: &Dir8) -> f32x8 {
    // 0·x is ±0 for a finite x and NaN for ±Inf or NaN, so the sum is zero
    // exactly when all three components are finite.
    let zero = f32x8::ZERO;
    let finite = (zero * d.x + zero * d.y + zero * d.z).simd_eq(zero);
    finite & max_abs(d).simd_gt(f32x8::ZERO)
}

/// The largest component magnitude of each lane, `max(|x|, |y|, |z|)`, with
/// the plain (not NaN-aware) maximum: unspecified for a lane with a NaN
/// component, which [`valid_direction`] marks invalid anyway.
#[inline(always)]
#[must_use]
pub(crate) fn max_abs(d: &Dir8) -> f32x8 {
    d.x.abs().fast_max(d.y.abs()).fast_max(d.z.abs())
}

/// Normalises each lane as `envmap_core::normalize_direction` does: divide by
/// the largest magnitude, then by the length. Invalid lanes become NaN.
#[inline]
#[must_use]
pub(crate) fn normalize(d: &Dir8) -> Dir8 {
    let m = max_abs(d);
    let (x, y, z) = (d.x / m, d.y / m, d.z / m);
    let len = (x * x + y * y + z * z).sqrt();
    Dir8::new(x / len, y / len, z / len)
}

/// Scales each lane by a power of two (exactly, no rounding) so that its
/// largest component has magnitude in `[1, 2)`: squares can then neither
/// overflow nor underflow. Lanes with a zero, infinite or NaN largest
/// component are scaled by an arbitrary power of two (they are masked later).
#[inline]
#[must_use]
pub(crate) fn scale_pow2(d: &Dir8) -> Dir8 {
    let m = max_abs(d);
    // Denormal or tiny lanes: first lift them by 2^64 so the exponent is normal.
    let tiny = m.simd_lt(f32x8::splat(1e-18));
    let lift = tiny.select(f32x8::splat(18_446_744_073_709_551_616.0), f32x8::ONE);
    let m = m * lift;
    // 2^-e for m = 1.x · 2^e: exponent field 254 − biased(e), clamped to a
    // valid normal exponent (m is not negative, so its bits above the
    // exponent field are zero).
    let bits: u32x8 = m.to_bits();
    let e: u32x8 = bits >> 23;
    let e = e.min(u32x8::splat(254));
    let inv_e = (u32x8::splat(254) - e).max(u32x8::ONE);
    let k = f32x8::from_bits(inv_e << 23);
    Dir8::new(d.x * lift * k, d.y * lift * k, d.z * lift * k)
}

/// Sets invalid lanes (mask false) to [`INVALID_CHART`] and NaN.
#[inline]
#[must_use]
pub(crate) fn finish(valid: f32x8, chart: u32x8, u: f32x8, v: f32x8) -> Uv8 {
    let nan = f32x8::splat(f32::NAN);
    Uv8::new(
        valid.to_bits().select(chart, u32x8::splat(INVALID_CHART)),
        valid.select(u, nan),
        valid.select(v, nan),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A batch from a slice of any length: its first eight lanes, the
    /// rest the documented padding.
    #[test]
    fn partial_batches_pad_their_missing_lanes() {
        let v: [Vec3; 10] =
            core::array::from_fn(|k| Vec3::new(k as f32, 10.0 + k as f32, -(k as f32)));
        let c: [ChartUv; 10] = core::array::from_fn(|k| {
            ChartUv::new(k as u32 % 6, k as f32 / 10.0, 1.0 - k as f32 / 10.0)
        });
        for n in 0..=10 {
            let (d, q) = (Dir8::from_partial(&v[..n]), Uv8::from_partial(&c[..n]));
            for k in 0..8 {
                let (want_d, want_q) = if k < n {
                    (v[k], c[k])
                } else {
                    (Vec3::Z, ChartUv::new(0, 0.5, 0.5))
                };
                assert_eq!(d.lane(k), want_d, "{n} lanes, lane {k}");
                assert_eq!(q.lane_raw(k), want_q, "{n} lanes, lane {k}");
            }
        }
    }

    #[test]
    fn transpose_round_trip() {
        let mut v = [Vec3::ZERO; 8];
        for (k, e) in v.iter_mut().enumerate() {
            let k = k as f32;
            *e = Vec3::new(k, 10.0 + k, 20.0 + k);
        }
        let b = Dir8::from_vec3s(&v);
        assert_eq!(b.x.to_array(), [0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0]);
        assert_eq!(b.y.to_array()[3], 13.0);
        assert_eq!(b.z.to_array()[7], 27.0);
        assert_eq!(b.to_vec3s(), v);
        assert_eq!(b.lane(5), v[5]);
    }
}
