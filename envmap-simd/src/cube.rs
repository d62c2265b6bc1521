//! Cube mapping, eight directions at a time, bit-identical to
//! [`envmap_core::Cube`].
//!
//! Same formula and tie rule as the scalar core (see [`envmap_core::cube`]):
//! z major if |z| ≥ |x| and |z| ≥ |y|, else y major if |y| ≥ |x|, else x
//! major; the face sign from the major component's sign bit;
//! s = ½(sc/|ma| + 1), t = ½(tc/|ma| + 1) with the same operations in the same
//! order. Selection is branch-free (masks and blends); sc and tc are the input
//! components with their sign bits flipped by mask, which is exact, so every
//! lane equals the scalar result bit for bit. No trigonometry, so every
//! accuracy tier runs the same code.

use envmap_core::Cube;
use wide::{f32x8, u32x8};

use crate::approx::Tier;
use crate::batch::{finish, Dir8, Uv8};
use crate::kernel::Mapping8;

const SIGN: u32 = 0x8000_0000;

#[inline]
fn sign_bits(x: f32x8) -> u32x8 {
    x.to_bits() & u32x8::splat(SIGN)
}

#[inline]
fn xor_sign(x: f32x8, s: u32x8) -> f32x8 {
    f32x8::from_bits(x.to_bits() ^ s)
}

/// The face each lane's direction selects and its coordinates on it, by the
/// core's table and tie rule ([`envmap_core::cube::select_face`]), bit for
/// bit: `(face, sc, tc, |ma|, valid)`, `valid` the lanes with a finite,
/// non-zero direction (all bits set) and the other lanes unspecified.
#[inline]
#[must_use]
pub(crate) fn select8(d: Dir8) -> (u32x8, f32x8, f32x8, f32x8, f32x8) {
    let (ax, ay, az) = (d.x.abs(), d.y.abs(), d.z.abs());
    let zmaj = az.simd_ge(ax) & az.simd_ge(ay);
    let ymaj = !zmaj & ay.simd_ge(ax);
    let (zm, ym) = (zmaj.to_bits(), ymaj.to_bits());

    let (sx, sy, sz) = (sign_bits(d.x), sign_bits(d.y), sign_bits(d.z));
    let all = u32x8::splat(SIGN);
    // x major: +x (sc, tc) = (−z, −y), −x: (+z, −y)
    // y major: +y (sc, tc) = (+x, +z), −y: (+x, −z)
    // z major: +z (sc, tc) = (+x, −y), −z: (−x, −y)
    let sc_x = xor_sign(d.z, sx ^ all);
    let sc_y = d.x;
    let sc_z = xor_sign(d.x, sz);
    let tc_x = xor_sign(d.y, all);
    let tc_y = xor_sign(d.z, sy);
    let tc_z = tc_x;
    let sc = zmaj.select(sc_z, ymaj.select(sc_y, sc_x));
    let tc = zmaj.select(tc_z, ymaj.select(tc_y, tc_x));
    let ma = zmaj.select(az, ymaj.select(ay, ax));

    // face = 2·axis + sign bit, axis 0/1/2 for x/y/z.
    let sign = zm.select(sz, ym.select(sy, sx)) >> 31;
    let axis = zm.select(u32x8::splat(2), ym.select(u32x8::splat(1), u32x8::ZERO));
    let face = axis + axis + sign;

    let finite = d.x.is_finite() & d.y.is_finite() & d.z.is_finite();
    let valid = finite & ma.simd_gt(f32x8::ZERO);
    (face, sc, tc, ma, valid)
}

/// Branch-free cube forward mapping (any tier).
#[inline]
#[must_use]
pub fn forward8(d: Dir8) -> Uv8 {
    let (face, sc, tc, ma, valid) = select8(d);
    let half = f32x8::splat(0.5);
    let one = f32x8::ONE;
    let s = half * (sc / ma + one);
    let t = half * (tc / ma + one);
    finish(valid, face, s, t)
}

/// The cube inverse mapping's ray (any tier): the face table's row
/// `(±1, ±s, ±t)` in some order, with `s`, `t` in `[−1, 1]`, unnormalised
/// (its largest component is ±1); invalid lanes (face > 5, NaN, outside
/// `[0, 1]²`) give NaN. [`inverse8`] is this divided by its length.
#[inline]
#[must_use]
pub fn ray8(c: Uv8) -> Dir8 {
    let two = f32x8::splat(2.0);
    let one = f32x8::ONE;
    let sc = two * c.u - one;
    let tc = two * c.v - one;
    rows8(c, one, sc, tc)
}

/// The face table's rows `(±m, ±sc, ±tc)` in each lane's order (its chart's
/// face), NaN on lanes whose chart is above 5 or whose `(u, v)` is NaN or
/// outside `[0, 1]²`: the cube's ray with `m = 1`, and the equi-angular
/// cube's with each axis's cosines folded in.
#[inline]
#[must_use]
pub(crate) fn rows8(c: Uv8, m: f32x8, sc: f32x8, tc: f32x8) -> Dir8 {
    let f = c.chart;
    let neg = |x: f32x8| -x;
    // Rows of the face table solved for (x, y, z) with |ma| = m; charts
    // above 5 take the −z row (they come out NaN below).
    let row = |face: u32| match face {
        0 => (m, neg(tc), neg(sc)),
        1 => (-m, neg(tc), sc),
        2 => (sc, m, tc),
        3 => (sc, -m, neg(tc)),
        4 => (sc, neg(tc), m),
        _ => (neg(sc), neg(tc), -m),
    };
    let first = f.as_array()[0];
    let (x, y, z) = if f.simd_eq(u32x8::splat(first)).all() {
        // One face for the whole batch (a row of a face, as conversions
        // map): its row directly.
        row(first)
    } else {
        // Each lane's row, blended from the six (the −z row by default).
        let (mut x, mut y, mut z) = row(5);
        for k in (0..5).rev() {
            let here = f32x8::from_bits(f.simd_eq(u32x8::splat(k)));
            let (rx, ry, rz) = row(k);
            (x, y, z) = (here.select(rx, x), here.select(ry, y), here.select(rz, z));
        }
        (x, y, z)
    };
    let valid =
        crate::kernel::in_unit_square(c.u, c.v) & f32x8::from_bits(f.simd_lt(u32x8::splat(6)));
    let nan = f32x8::splat(f32::NAN);
    Dir8::new(
        valid.select(x, nan),
        valid.select(y, nan),
        valid.select(z, nan),
    )
}

/// Cube inverse mapping (any tier): invalid lanes (face > 5, NaN, outside
/// `[0, 1]²`) give NaN.
#[inline]
#[must_use]
pub fn inverse8(c: Uv8) -> Dir8 {
    let r = ray8(c);
    let len = (r.x * r.x + r.y * r.y + r.z * r.z).sqrt();
    Dir8::new(r.x / len, r.y / len, r.z / len)
}

impl Mapping8 for Cube {
    #[inline]
    fn forward8<T: Tier>(&self, d: Dir8) -> Uv8 {
        forward8(d)
    }
    #[inline]
    fn inverse8<T: Tier>(&self, c: Uv8) -> Dir8 {
        inverse8(c)
    }
    /// The face table's row, unnormalised: see [`ray8`].
    #[inline]
    fn inverse8_ray<T: Tier>(&self, c: Uv8) -> Dir8 {
        ray8(c)
    }
}
