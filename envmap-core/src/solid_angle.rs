//! Exact solid angles of rectangles of chart coordinates, for every mapping.
//!
//! Each function takes a rectangle `[u0, u1] × [v0, v1]` in one chart's own texture coordinates
//! (u to the right, v downwards, both in [0, 1]) and returns, in steradians, the solid angle of
//! the set of directions that this chart *owns* inside the rectangle. This is what texel
//! weighting needs: the solid angle of texel `(i, j)` of a `w × h` chart is
//! `f(i / w, (i + 1) / w, j / h, (j + 1) / h)`, and summed over all texels these values add up
//! to the chart's total: 4π for the latitude–longitude map, the sphere map, the angular map and
//! both octahedral maps, 4π/6 for one cube face, 2π for one disk of the dual paraboloid and 2π
//! for one tennisball chart.
//!
//! # Rectangles: orientation, clipping, degenerate input
//!
//! Every function returns the *oriented* integral
//! `∫_{u0}^{u1} ∫_{v0}^{v1} ω(u, v) dv du` of the chart's solid-angle density `ω`, which is zero
//! outside [0, 1]² and where the chart owns no direction. Hence:
//!
//! - a rectangle partly outside [0, 1]² is clipped to it (infinite bounds are allowed);
//! - reversing one axis negates the value, reversing both keeps it, so
//!   `f(a, b, ..) + f(b, c, ..) == f(a, c, ..)` (up to rounding) for any `a`, `b`, `c`;
//! - a degenerate rectangle (`u0 == u1` or `v0 == v1`) and one that lies outside [0, 1]²
//!   give `0.0`;
//! - a NaN bound gives NaN.
//!
//! # Accuracy
//!
//! The formulas are arranged so that no step subtracts nearly equal quantities: differences of
//! sines and cosines are written as products of sines, `t − sin t` is summed as a series for
//! small `t`, differences of arctangents are taken with a single `atan2`, and widths come from
//! `u1 − u0` and `v1 − v0` directly. So the error is relative to the rectangle's *own* solid
//! angle, not to the sphere's: a texel of a 4096-wide map is as accurate as a whole chart.
//!
//! - texels that no boundary crosses (every texel of the latlong, a cube face and both
//!   octahedral maps) are within a few units in the last place, relative;
//! - texels crossed by a disk rim or by the tennisball's ownership boundary are less accurate
//!   in proportion to the resolution: the crossing points are located to about 1e-16 in angle,
//!   which is relative to the texel's width;
//! - when the owned part of a texel is only a thin sliver, the same absolute error is large
//!   relative to the sliver, and small relative to an average texel's solid angle;
//! - the angular map's density vanishes on the rim, so next to it the rounding of the
//!   quadrature nodes, relative to their distance from the rim, dominates.
//!
//! The angular map's errors against 30-digit references are in `docs/accuracy.md` (round
//! trips).
//!
//! Where no convenient closed form exists (the dual paraboloid, the tennisball's wings) the
//! solid angle is reduced to 1-D integrals (for the angular map, which has no antiderivative
//! in either variable, to 1-D integrals of 1-D integrals), split at every kink of the integrand and
//! integrated with 16-point Gauss–Legendre quadrature on panels at most 0.5 long, in a variable
//! chosen so that the integrand is analytic in a strip of half-width at least 0.88 around the
//! real axis (the substitution x = sin t removes the square-root singularity of a disk rim).
//! For such integrands the quadrature error is below 1e-20 relative, far under rounding. The
//! angular map's integrands are entire, and on short intervals take a single panel of 4 or 8
//! points instead, with the same margin (`gauss_legendre_entire` says why).

use core::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI, SQRT_2, TAU};

use glam::DVec3;
use libm::{acos, asin, atan, atan2, ceil, cos, fabs, sin, sqrt, tan};

/// Solid angle of `[u0, u1] × [v0, v1]` in a latitude–longitude chart.
///
/// Parameterization: azimuth φ = 2πu, polar angle θ = πv measured from +z (v = 0 is the
/// north pole +z, v = 1 the south pole). Area element: dΩ = sin θ dθ dφ = 2π² sin(πv) du dv.
///
/// Method: the closed form Ω = 2π (u1 − u0)(cos πv0 − cos πv1), evaluated as
/// 4π (u1 − u0) sin(π(v0 + v1)/2) sin(π(v1 − v0)/2) so that a thin row keeps its full relative
/// precision. The whole chart is 4π. Orientation, clipping and NaN as in the
/// [module documentation](self).
#[must_use]
#[inline]
pub fn latlong(u0: f64, u1: f64, v0: f64, v1: f64) -> f64 {
    oriented(u0, u1, v0, v1, |u0, u1, v0, v1| {
        // sin(π s / 2) is symmetric about s = 1: near the south pole use 2 − s, which is
        // computed exactly, instead of an argument close to π.
        let s = v0 + v1;
        let s = if s > 1.0 { (1.0 - v0) + (1.0 - v1) } else { s };
        2.0 * TAU * (u1 - u0) * sin(FRAC_PI_2 * s) * sin(FRAC_PI_2 * (v1 - v0))
    })
}

/// Solid angle of `[u0, u1] × [v0, v1]` in one cube face.
///
/// Parameterization: face coordinates sc = 2u − 1, tc = 2v − 1 ∈ [−1, 1]; the direction is
/// (sc, tc, 1) in the face's own frame (gnomonic projection onto the plane at distance 1).
/// Area element: dΩ = dsc dtc / (1 + sc² + tc²)^{3/2}.
///
/// Method: the standard closed form obtained by integrating that area element,
/// Ω = A(x1, y1) − A(x0, y1) − A(x1, y0) + A(x0, y0) with A(x, y) = atan2(x y, √(1 + x² + y²)),
/// is the solid angle of the spherical quadrilateral whose corners are the rectangle's corners
/// (straight lines of the face are great-circle arcs). It is evaluated as that quadrilateral,
/// split into two spherical triangles measured with the Van Oosterom–Strackee formula, which
/// gives the same value without the cancellation of the four-term sum for small texels. The
/// two halves, tan(Ωᵢ/2) = nᵢ/dᵢ, are added as one angle, Ω = 2·atan2(n₁d₂ + n₂d₁,
/// d₁d₂ − n₁n₂) (the tangent of a sum; both terms of the first argument are non-negative and
/// Ω/2 ≤ π/3 on a face, so nothing cancels), one arctangent and the four corners' lengths
/// per rectangle. Each face totals 4π/6. Orientation, clipping and NaN as in the
/// [module documentation](self).
#[must_use]
#[inline]
pub fn cube_face(u0: f64, u1: f64, v0: f64, v1: f64) -> f64 {
    oriented(u0, u1, v0, v1, |u0, u1, v0, v1| {
        face_rectangle(
            2.0 * u0 - 1.0,
            2.0 * v0 - 1.0,
            2.0 * (u1 - u0),
            2.0 * (v1 - v0),
        )
    })
}

/// Solid angle of `[u0, u1] × [v0, v1]` on one face of the equi-angular cube map
/// ([`crate::eac`]).
///
/// Each axis is an angle: the face coordinate is `x = tan(α)` with `α = π/4 · (2u − 1)`, so a
/// rectangle of `(u, v)` is a rectangle of the cube face's plane and the cube's formula
/// applies to it. Its width `tan α1 − tan α0` is taken as `sin(α1 − α0) / (cos α0 cos α1)`,
/// with `α1 − α0 = π/2 · (u1 − u0)`, so that a texel keeps its relative precision. Each face
/// totals 4π/6. Orientation, clipping and NaN as in the [module documentation](self).
#[must_use]
#[inline]
pub fn eac_face(u0: f64, u1: f64, v0: f64, v1: f64) -> f64 {
    oriented(u0, u1, v0, v1, |u0, u1, v0, v1| {
        let angle = |u: f64| FRAC_PI_4 * (2.0 * u - 1.0);
        let (a0, b0) = (angle(u0), angle(v0));
        let width = |a0: f64, d: f64| sin(FRAC_PI_2 * d) / (cos(a0) * cos(a0 + FRAC_PI_2 * d));
        face_rectangle(tan(a0), tan(b0), width(a0, u1 - u0), width(b0, v1 - v0))
    })
}

/// Solid angle of `[u0, u1] × [v0, v1]` in a perspective view whose half-width and
/// half-height on the plane z = 1 are `tx` = tan(H/2) and `ty` = tan(V/2)
/// ([`crate::perspective`]).
///
/// A rectangle of (u, v) is the rectangle `[tx(2u0 − 1), tx(2u1 − 1)] × [ty(2v0 − 1),
/// ty(2v1 − 1)]` of the plane (its mirror image in y, of the same solid angle), measured as the
/// cube face's. Orientation, clipping and NaN as in the [module documentation](self).
#[must_use]
#[inline]
pub fn perspective(tx: f64, ty: f64, u0: f64, u1: f64, v0: f64, v1: f64) -> f64 {
    oriented(u0, u1, v0, v1, |u0, u1, v0, v1| {
        face_rectangle(
            tx * (2.0 * u0 - 1.0),
            ty * (2.0 * v0 - 1.0),
            2.0 * tx * (u1 - u0),
            2.0 * ty * (v1 - v0),
        )
    })
}

/// Solid angle of the rectangle `[x, x + dx] × [y, y + dy]` of the plane z = 1 (a cube
/// face's, coordinates in [−1, 1]), as two triangles.
#[inline]
fn face_rectangle(x: f64, y: f64, dx: f64, dy: f64) -> f64 {
    let a = DVec3::new(x, y, 1.0);
    let ex = DVec3::new(dx, 0.0, 0.0);
    let ey = DVec3::new(0.0, dy, 0.0);
    let diagonal = DVec3::new(dx, dy, 0.0);
    // Triangles (a, a + ex, a + diagonal) and (a, a + diagonal,
    // a + ey), their four corners measured once.
    let (la, lb, lc, ld) = (
        a.length(),
        (a + ex).length(),
        (a + diagonal).length(),
        (a + ey).length(),
    );
    let (n1, d1) = triangle_tangent(a, ex, diagonal, (la, lb, lc));
    let (n2, d2) = triangle_tangent(a, diagonal, ey, (la, lc, ld));
    2.0 * atan2(n1 * d2 + n2 * d1, d1 * d2 - n1 * n2)
}

/// Solid angle of `[u0, u1] × [v0, v1]` in a sphere map.
///
/// Parameterization: u' = 2u − 1, v' = 2v − 1; the chart is the closed unit disk
/// u'² + v'² ≤ 1, which the sphere map covers equal-area: dΩ = 4 du' dv' = 16 du dv inside the
/// disk and 0 outside (the whole disk, area π, is the whole sphere, 4π).
///
/// Method: exact, Ω = 4 × area(rectangle ∩ unit disk) in (u', v'), with the rectangle–disk
/// intersection area in closed form: in x = u' = sin t the column height is piecewise one of
/// y1 − y0, cos t − y0, y1 + cos t, 2 cos t, split at the rectangle's edges and where the rim
/// crosses the lines v' = y0, y1 (t = ±acos|y|); each piece is integrated in closed form
/// (∫cos² t dt = (t + sin t cos t)/2, written without cancellation). Orientation, clipping and
/// NaN as in the [module documentation](self).
#[must_use]
#[inline]
pub fn sphere_map(u0: f64, u1: f64, v0: f64, v1: f64) -> f64 {
    oriented(u0, u1, v0, v1, |u0, u1, v0, v1| {
        4.0 * disk_area(DiskRect::new(u0, u1, v0, v1))
    })
}

/// Solid angle of `[u0, u1] × [v0, v1]` in one disk of the dual paraboloid map.
///
/// Parameterization: u' = 2u − 1, v' = 2v − 1; the chart is the unit disk u'² + v'² ≤ 1, which
/// covers one hemisphere by the stereographic projection (a paraboloid's reflection map), so
/// dΩ = 4 du' dv' / (1 + u'² + v'²)² inside the disk and 0 outside. Each disk totals 2π.
///
/// Method: the inner integral over v' is in closed form,
/// ∫ dy / (c² + y²)² = y / (2c²(c² + y²)) + atan(y / c) / (2c³) with c² = 1 + u'², and its
/// difference between the column's ends is rewritten as a sum of two non-negative terms
/// (no cancellation). The outer integral is done numerically: split at the rectangle's edges
/// and where the rim crosses the lines v' = y0, y1, each piece is integrated with 16-point
/// Gauss–Legendre panels, in u' itself where the column does not touch the rim and in
/// t = asin u' where it does (which removes the rim's square-root singularity). Orientation,
/// clipping and NaN as in the [module documentation](self).
#[must_use]
#[inline]
pub fn paraboloid(u0: f64, u1: f64, v0: f64, v1: f64) -> f64 {
    oriented(u0, u1, v0, v1, |u0, u1, v0, v1| {
        4.0 * stereographic_disk(DiskRect::new(u0, u1, v0, v1))
    })
}

/// Solid angle of `[u0, u1] × [v0, v1]` in an angular map (Debevec's light probe).
///
/// Parameterization: u' = 2u − 1, v' = 2v − 1; the chart is the unit disk
/// ρ = √(u'² + v'²) ≤ 1, whose point (u', v') is the direction at θ = πρ from +z at the azimuth
/// of (u', v') (the azimuthal equidistant projection), so dΩ = sin θ dθ dφ =
/// π sin(πρ)/ρ du' dv' = 4π sin(πρ)/ρ du dv inside the disk and 0 outside. The whole disk is
/// 2π² ∫₀¹ sin(πρ) dρ = 4π.
///
/// Method: no elementary antiderivative exists even in one variable, so both integrals are
/// numerical, with the paraboloid's machinery: split at the rectangle's edges and where the rim
/// crosses the lines v' = y0, y1, each piece is integrated with 16-point Gauss–Legendre panels,
/// in u' itself where the column does not touch the rim and in t = asin u' where it does (which
/// removes the rim's square-root singularity); the inner integral over each column is done by
/// the same panels. The density π sin(πρ)/ρ is an entire function of ρ² = u'² + v'²
/// (π² Σ (−π²ρ²)^k/(2k + 1)!), so every integrand is analytic. It vanishes on the rim, so a
/// column that ends on the rim is integrated in the distance z from that end, in which
/// 1 − ρ² = z(2 cos t − z) keeps its relative precision, and the density there is evaluated as
/// π sin(π(1 − ρ))/ρ with 1 − ρ = (1 − ρ²)/(1 + ρ): no cancellation next to the rim.
///
/// Accuracy: see the [module documentation](self) and `docs/accuracy.md`.
/// Orientation, clipping and NaN as in the [module documentation](self).
#[must_use]
#[inline]
pub fn angular(u0: f64, u1: f64, v0: f64, v1: f64) -> f64 {
    oriented(u0, u1, v0, v1, |u0, u1, v0, v1| {
        PI * equidistant_disk(DiskRect::new(u0, u1, v0, v1), PI)
    })
}

/// Solid angle of `[u0, u1] × [v0, v1]` in one lens of a fisheye of half field of view `k`
/// (radians, in (0, π]; [`crate::fisheye`]).
///
/// Parameterization: u' = 2u − 1, v' = 2v − 1, ρ = √(u'² + v'²) ≤ 1 the image circle. The
/// equidistant lens puts θ = kρ from its axis, so dΩ = k sin(kρ)/ρ du' dv', integrated as the
/// angular map's (which is k = π) is; the equisolid lens is equal-area,
/// dΩ = 4 sin²(k/2) du' dv', so the solid angle is that times the area of the rectangle's part
/// inside the circle, in closed form as the sphere map's. Orientation, clipping and NaN as in
/// the [module documentation](self).
#[must_use]
#[inline]
pub fn fisheye(lens: crate::fisheye::Lens, k: f64, u0: f64, u1: f64, v0: f64, v1: f64) -> f64 {
    oriented(u0, u1, v0, v1, |u0, u1, v0, v1| {
        let r = DiskRect::new(u0, u1, v0, v1);
        match lens {
            crate::fisheye::Lens::Equidistant => k * equidistant_disk(r, k),
            crate::fisheye::Lens::Equisolid => {
                let s = sin(0.5 * k);
                4.0 * s * s * disk_area(r)
            }
        }
    })
}

/// Solid angle of `[u0, u1] × [v0, v1]` in one chart of the tennisball map (both charts own
/// the same shape in their own coordinates).
///
/// Parameterization: longitude φ = (u − 1/2)·3π/2 ∈ [−3π/4, 3π/4] and latitude
/// θ = (1/2 − v)·π/2 ∈ [−π/4, π/4] (v = 0 is θ = +π/4). Area element: dΩ = cos θ dθ dφ.
/// Ownership: the chart owns the points with |φ| ≤ π/2 (its central band, u ∈ [1/6, 5/6]),
/// and in the wings |φ| > π/2 those with cos θ·|sin φ| ≥ √2/2, a lens that narrows to a point
/// at φ = ±3π/4. The full chart rectangle covers 3π/√2 ≈ 6.664 sr; the owned part is exactly
/// 2π, so the two charts together cover 4π.
///
/// Method: the central band is the closed form (φ1 − φ0)(sin θ1 − sin θ0). In a wing, with
/// ψ = |φ| − π/2 ∈ [0, π/4], a point is owned when |sin θ| ≤ √(1 − tan²ψ)/√2; the
/// substitution tan ψ = sin s (s ∈ [0, π/2]) turns the owned half-width into cos s/√2 and
/// removes the square-root singularity at the wing's tip. The latitude range is folded onto
/// θ ≥ 0 by symmetry; per band [τ0, τ1], the column is full (closed form) for s below the
/// kink where cos s/√2 = sin τ1, is (cos s − cos κ0)/√2 up to the kink κ0 where
/// cos s/√2 = sin τ0, and empty after it. The middle piece,
/// ∫ (cos s − cos κ0)/√2 · cos s/(1 + sin² s) ds, is integrated with 16-point Gauss–Legendre
/// panels on the cancellation-free integrand √2 sin((κ0 + s)/2) sin((κ0 − s)/2) cos s/(1 + sin² s).
/// (Its antiderivative √2 atan(√2 tan s) − s − cos κ0 · atan(sin s), over √2, exists but loses
/// digits along the ownership boundary; the tests use it as a reference.) Orientation,
/// clipping and NaN as in the [module documentation](self).
#[must_use]
#[inline]
pub fn tennisball(u0: f64, u1: f64, v0: f64, v1: f64) -> f64 {
    oriented(u0, u1, v0, v1, tennisball_owned)
}

/// Solid angle of `[u0, u1] × [v0, v1]` in an octahedral map (Engelhardt & Dachsbacher 2008).
///
/// Parameterization: u' = 2u − 1, v' = 2v − 1 ∈ [−1, 1]²; the point before normalisation is
/// p = (u', v', 1 − |u'| − |v'|) inside the diamond |u'| + |v'| ≤ 1 and
/// p = (sgn(u')(1 − |v'|), sgn(v')(1 − |u'|), 1 − |u'| − |v'|) outside it. The map is affine on
/// each of 8 triangles (the four quadrants, each split by the diamond) onto the faces of the
/// octahedron |x| + |y| + |z| = 1, so dΩ = du' dv' / |p|³ (a face's area element √3 du' dv'
/// times its distance from the origin, 1/√3, over |p|³).
///
/// Method: exact geometry. A straight segment inside one triangle maps to a straight segment
/// of one octahedron face, which projects onto a great-circle arc; so the rectangle is clipped
/// to each triangle (Sutherland–Hodgman against its three half-planes, in fixed-size arrays),
/// the clipped polygon's vertices are mapped through p, and the spherical polygon's solid angle
/// is the sum over a fan of spherical triangles, each measured with the Van Oosterom–Strackee
/// formula tan(Ω/2) = |a·(b × c)| / (|a||b||c| + (a·b)|c| + (a·c)|b| + (b·c)|a|). The whole
/// square is 4π. Orientation, clipping and NaN as in the [module documentation](self).
#[must_use]
#[inline]
pub fn octahedral(u0: f64, u1: f64, v0: f64, v1: f64) -> f64 {
    oriented(u0, u1, v0, v1, |u0, u1, v0, v1| {
        let x0 = 2.0 * u0 - 1.0;
        let x1 = 2.0 * u1 - 1.0;
        let y0 = 2.0 * v0 - 1.0;
        let y1 = 2.0 * v1 - 1.0;
        // Vertices are kept as offsets from the corner (x0, y0), so the rectangle's own width
        // and height, 2(u1 − u0) and 2(v1 − v0), are exact.
        let rectangle = Polygon::rectangle(x0, y0, 2.0 * (u1 - u0), 2.0 * (v1 - v0));
        let mut total = 0.0;
        for sx in [-1.0, 1.0] {
            if (sx > 0.0 && x1 <= 0.0) || (sx < 0.0 && x0 >= 0.0) {
                continue;
            }
            for sy in [-1.0, 1.0] {
                if (sy > 0.0 && y1 <= 0.0) || (sy < 0.0 && y0 >= 0.0) {
                    continue;
                }
                let quadrant = rectangle.clip(sx, 0.0, 0.0).clip(0.0, sy, 0.0);
                // Inside the diamond: sx x + sy y ≤ 1; outside: sx x + sy y ≥ 1.
                let inner = quadrant.clip(-sx, -sy, 1.0);
                let outer = quadrant.clip(sx, sy, -1.0);
                total += inner.octahedral_solid_angle(sx, sy, false);
                total += outer.octahedral_solid_angle(sx, sy, true);
            }
        }
        total
    })
}

/// Solid angle of `[u0, u1] × [v0, v1]` in Clarberg's equal-area octahedral map (2008; the
/// `EqualAreaSquareToSphere` of pbrt-v4).
///
/// Parameterization: the unit square maps onto the sphere with constant Jacobian, so
/// dΩ = 4π du dv. Method: the closed form Ω = 4π (u1 − u0)(v1 − v0). Orientation, clipping and
/// NaN as in the [module documentation](self).
#[must_use]
#[inline]
pub fn equal_area_octahedral(u0: f64, u1: f64, v0: f64, v1: f64) -> f64 {
    oriented(u0, u1, v0, v1, |u0, u1, v0, v1| {
        2.0 * TAU * (u1 - u0) * (v1 - v0)
    })
}

// ---------------------------------------------------------------------------------------------
// Rectangle handling
// ---------------------------------------------------------------------------------------------

/// Applies the module's rectangle rules, then calls `f` on a proper rectangle inside [0, 1]²:
/// NaN in, NaN out; each axis is sorted, remembering its orientation; the rectangle is
/// clipped to [0, 1]²; an empty result gives 0; otherwise `f(u0, u1, v0, v1)` with
/// `0 ≤ u0 < u1 ≤ 1`, `0 ≤ v0 < v1 ≤ 1`, times the product of the two orientations.
#[inline]
fn oriented(u0: f64, u1: f64, v0: f64, v1: f64, f: impl FnOnce(f64, f64, f64, f64) -> f64) -> f64 {
    if u0.is_nan() || u1.is_nan() || v0.is_nan() || v1.is_nan() {
        return f64::NAN;
    }
    let (ua, ub, su) = if u0 <= u1 {
        (u0, u1, 1.0)
    } else {
        (u1, u0, -1.0)
    };
    let (va, vb, sv) = if v0 <= v1 {
        (v0, v1, 1.0)
    } else {
        (v1, v0, -1.0)
    };
    let (ua, ub) = (ua.max(0.0), ub.min(1.0));
    let (va, vb) = (va.max(0.0), vb.min(1.0));
    if ua >= ub || va >= vb {
        return 0.0;
    }
    su * sv * f(ua, ub, va, vb)
}

// ---------------------------------------------------------------------------------------------
// Elementary pieces, written without cancellation
// ---------------------------------------------------------------------------------------------

/// `x − sin x` for `x ≥ 0`, accurate for small `x` (series below 1, where the direct
/// difference would cancel).
#[inline]
fn x_minus_sin(x: f64) -> f64 {
    if x >= 1.0 {
        return x - sin(x);
    }
    // x³/3! − x⁵/5! + x⁷/7! − …; each term is at most 1/20 of the previous one.
    let x2 = x * x;
    let mut term = x * x2 / 6.0;
    let mut sum = term;
    let mut k = 4.0;
    while fabs(term) > 1e-18 * fabs(sum) {
        term *= -x2 / (k * (k + 1.0));
        sum += term;
        k += 2.0;
    }
    sum
}

/// `cos x − cos α = 2 sin((α + x)/2) sin((α − x)/2)`, which stays accurate when `x` is near
/// `±α`.
#[inline]
fn cos_minus_cos(x: f64, alpha: f64) -> f64 {
    2.0 * sin(0.5 * (alpha + x)) * sin(0.5 * (alpha - x))
}

/// `∫_a^b cos² t dt` for `−π/2 ≤ a ≤ b ≤ π/2`, as
/// `((b − a) − sin(b − a))/2 + sin(b − a) cos²((a + b)/2)`: two non-negative terms.
#[inline]
fn integral_cos_sq(a: f64, b: f64) -> f64 {
    let d = b - a;
    let c = cos(0.5 * (a + b));
    0.5 * x_minus_sin(d) + sin(d) * c * c
}

/// `∫_a^b (cos t − cos α) cos t dt` for `−α ≤ a ≤ b ≤ α ≤ π/2`: the area of a strip of a
/// circular segment (the part of the unit disk above the chord y = cos α) between x = sin a and
/// x = sin b. Written as `(d − sin d)/2 + 2 sin(d/2) cos(σ/2) (cos(d/2) cos(σ/2) − cos α)` with
/// `d = b − a`, `σ = a + b`, and the last factor as `((cos a − cos α) + (cos b − cos α))/2`:
/// all terms are non-negative.
#[inline]
fn integral_segment(a: f64, b: f64, alpha: f64) -> f64 {
    let d = b - a;
    let rise = 0.5 * (cos_minus_cos(a, alpha) + cos_minus_cos(b, alpha));
    0.5 * x_minus_sin(d) + 2.0 * sin(0.5 * d) * cos(0.5 * (a + b)) * rise
}

/// Half the 16 Gauss–Legendre nodes on [−1, 1] (the positive ones; the rule is symmetric).
const GL_NODES: [f64; 8] = [
    0.09501250983763744,
    0.2816035507792589,
    0.45801677765722737,
    0.6178762444026438,
    0.755404408355003,
    0.8656312023878318,
    0.9445750230732326,
    0.9894009349916499,
];

/// The Gauss–Legendre weights of [`GL_NODES`].
const GL_WEIGHTS: [f64; 8] = [
    0.1894506104550685,
    0.18260341504492358,
    0.16915651939500254,
    0.14959598881657674,
    0.12462897125553388,
    0.09515851168249279,
    0.062253523938647894,
    0.027152459411754096,
];

/// Longest panel of [`gauss_legendre`]. With the integrands of this module analytic in a strip
/// of half-width ≥ 0.88, a 0.5-long panel has a Bernstein ellipse parameter ρ > 5, so the
/// 16-point rule's error is of order ρ^−32 < 1e-20 relative.
const MAX_PANEL: f64 = 0.5;

/// `∫_a^{a + length} f`, with 16-point Gauss–Legendre on `⌈length / 0.5⌉` equal panels; 0 when
/// `length ≤ 0`. The length is passed on its own so that an accurately known width is not
/// recomputed as a difference of rounded ends.
#[inline]
fn gauss_legendre(a: f64, length: f64, f: impl Fn(f64) -> f64) -> f64 {
    if length.is_nan() || length <= 0.0 {
        return 0.0;
    }
    let panels = ceil(length / MAX_PANEL).max(1.0);
    let count = panels as usize;
    let step = length / panels;
    let half = 0.5 * step;
    let mut total = 0.0;
    for k in 0..count {
        let mid = a + (k as f64 + 0.5) * step;
        let mut sum = 0.0;
        for (node, weight) in GL_NODES.iter().zip(GL_WEIGHTS.iter()) {
            let dx = half * node;
            sum += weight * (f(mid - dx) + f(mid + dx));
        }
        total += half * sum;
    }
    total
}

/// The positive nodes of the 4-point Gauss–Legendre rule on [−1, 1].
const GL4_NODES: [f64; 2] = [0.33998104358485626, 0.8611363115940526];

/// The weights of [`GL4_NODES`].
const GL4_WEIGHTS: [f64; 2] = [0.6521451548625461, 0.34785484513745385];

/// The positive nodes of the 8-point Gauss–Legendre rule on [−1, 1].
const GL8_NODES: [f64; 4] = [
    0.1834346424956498,
    0.525532409916329,
    0.7966664774136267,
    0.9602898564975363,
];

/// The weights of [`GL8_NODES`].
const GL8_WEIGHTS: [f64; 4] = [
    0.362683783378362,
    0.31370664587788727,
    0.22238103445337448,
    0.10122853629037626,
];

/// [`gauss_legendre`] for an entire integrand of the angular map's kind, with fewer nodes on
/// short intervals: one panel of 4 points up to length 1/128, of 8 points up to 1/8, and
/// `gauss_legendre`'s 16-point panels beyond.
///
/// The n-point rule's error on a panel of length L is L^(2n+1) (n!)⁴ / ((2n + 1) ((2n)!)³)
/// times the 2n-th derivative somewhere inside, and by Cauchy's estimate on circles of radius
/// 1 that derivative is at most (2n)! M with M the integrand's largest modulus within distance
/// 1 of the panel. The angular map's integrands are built from sin(π√s)/√s, whose modulus is at
/// most sinh(π√|s|)/√|s| ≤ 250 for |s| ≤ 5, and from sin and cos, at most cosh 1 = 1.54 there,
/// so M ≤ 1000; relative to L times the largest density π the error is then at most
/// 2.3e-5·(1/128)⁸·1000/π ≤ 1e-19 for 4 points and 3.6e-10·(1/8)¹⁶·1000/π ≤ 5e-22 for 8,
/// far under rounding (texels of a chart 64 or more wide take the 8-point rule, 256 or more
/// the 4-point one: 16 or 64 evaluations instead of 256 per 2-D piece).
#[inline]
fn gauss_legendre_entire(a: f64, length: f64, f: impl Fn(f64) -> f64) -> f64 {
    if length.is_nan() || length <= 0.0 {
        return 0.0;
    }
    let (nodes, weights): (&[f64], &[f64]) = if length <= 1.0 / 128.0 {
        (&GL4_NODES, &GL4_WEIGHTS)
    } else if length <= 0.125 {
        (&GL8_NODES, &GL8_WEIGHTS)
    } else {
        return gauss_legendre(a, length, f);
    };
    let half = 0.5 * length;
    let mid = a + half;
    let mut sum = 0.0;
    for (node, weight) in nodes.iter().zip(weights) {
        let dx = half * node;
        sum += weight * (f(mid - dx) + f(mid + dx));
    }
    half * sum
}

/// Solid angle of the spherical triangle with vertices `a`, `a + e1`, `a + e2` (any lengths,
/// not through the origin), 2·atan2 of [`triangle_tangent`].
#[inline]
fn spherical_triangle(a: DVec3, e1: DVec3, e2: DVec3) -> f64 {
    let lengths = (a.length(), (a + e1).length(), (a + e2).length());
    let (numerator, denominator) = triangle_tangent(a, e1, e2, lengths);
    2.0 * atan2(numerator, denominator)
}

/// tan(Ω/2) of the spherical triangle with vertices `a`, `b = a + e1`, `c = a + e2`, as a
/// numerator and denominator, by Van Oosterom & Strackee (1983):
/// tan(Ω/2) = |a·(b × c)| / (|a||b||c| + (a·b)|c| + (a·c)|b| + (b·c)|a|), given the three
/// lengths (corners shared by two triangles are measured once). The triple product is taken as
/// `a·(e1 × e2)` from the edge vectors, so a small triangle keeps its relative precision.
#[inline]
fn triangle_tangent(a: DVec3, e1: DVec3, e2: DVec3, (la, lb, lc): (f64, f64, f64)) -> (f64, f64) {
    let (b, c) = (a + e1, a + e2);
    let numerator = fabs(a.dot(e1.cross(e2)));
    let denominator = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
    (numerator, denominator)
}

// ---------------------------------------------------------------------------------------------
// Disks: rectangle ∩ unit disk, cut into pieces
// ---------------------------------------------------------------------------------------------

/// A piece of the set rectangle ∩ unit disk between consecutive kinks, over which the column
/// `{y : (x, y) in the set}` has a fixed kind of lower and upper end. Points are x = sin t.
#[derive(Clone, Copy)]
struct DiskPiece {
    /// Start angle, `x = sin a`.
    a: f64,
    /// End angle, `x = sin b`, `b > a`.
    b: f64,
    /// `sin a`, exact when `a` is the rectangle's own edge.
    xa: f64,
    /// `sin b − sin a`, exact when both ends are the rectangle's own edges.
    dx: f64,
    /// The column's top is the rim `y = cos t` (else the line `y = y1`).
    upper_rim: bool,
    /// The column's bottom is the rim `y = −cos t` (else the line `y = y0`).
    lower_rim: bool,
}

/// A rectangle `[x0, x1] × [y0, y1]` in the disk coordinates u' = 2u − 1, v' = 2v − 1, with
/// its width and height taken from u and v directly (2(u1 − u0) is exact where x1 − x0,
/// computed from rounded ends, is not).
#[derive(Clone, Copy)]
struct DiskRect {
    /// Left edge, 2u0 − 1.
    x0: f64,
    /// Right edge, 2u1 − 1.
    x1: f64,
    /// Bottom edge (in y), 2v0 − 1.
    y0: f64,
    /// Top edge (in y), 2v1 − 1.
    y1: f64,
    /// `x1 − x0`, accurately.
    width: f64,
    /// `y1 − y0`, accurately.
    height: f64,
}

impl DiskRect {
    /// The disk-coordinate rectangle of `[u0, u1] × [v0, v1]`.
    #[inline]
    fn new(u0: f64, u1: f64, v0: f64, v1: f64) -> Self {
        Self {
            x0: 2.0 * u0 - 1.0,
            x1: 2.0 * u1 - 1.0,
            y0: 2.0 * v0 - 1.0,
            y1: 2.0 * v1 - 1.0,
            width: 2.0 * (u1 - u0),
            height: 2.0 * (v1 - v0),
        }
    }
}

/// Calls `f` on each piece of `r ∩ unit disk` and returns the sum. The pieces are the parts of
/// `[asin x0, asin x1]` between the rim's crossings with the lines y = y0 and y = y1
/// (t = ±acos|y|); pieces where the column is empty are skipped.
#[inline]
fn disk_pieces(r: DiskRect, mut f: impl FnMut(DiskPiece) -> f64) -> f64 {
    let DiskRect { x0, x1, y0, y1, .. } = r;
    let ta = asin(x0);
    let tb = asin(x1);
    // (t, sin t): the two edges and up to four rim crossings.
    let mut cuts = [(0.0, 0.0); 6];
    cuts[0] = (ta, x0);
    cuts[1] = (tb, x1);
    let mut count = 2;
    for y in [y0, y1] {
        let ay = fabs(y);
        if ay < 1.0 {
            let t = acos(ay);
            let x = sqrt((1.0 - ay) * (1.0 + ay));
            for (tc, xc) in [(-t, -x), (t, x)] {
                if tc > ta && tc < tb {
                    cuts[count] = (tc, xc);
                    count += 1;
                }
            }
        }
    }
    let cuts = &mut cuts[..count];
    cuts.sort_unstable_by(|p, q| p.0.total_cmp(&q.0));
    let mut total = 0.0;
    for pair in cuts.windows(2) {
        let ((a, xa), (b, xb)) = (pair[0], pair[1]);
        if b <= a {
            continue;
        }
        let h = cos(0.5 * (a + b));
        if y1.min(h) <= y0.max(-h) {
            continue;
        }
        let upper_rim = h <= y1;
        let lower_rim = -h >= y0;
        // With no crossing inside, the only piece spans the whole rectangle.
        let dx = if count == 2 { r.width } else { xb - xa };
        total += f(DiskPiece {
            a,
            b,
            xa,
            dx,
            upper_rim,
            lower_rim,
        });
    }
    total
}

/// Area of `r ∩ unit disk`, in closed form piece by piece.
fn disk_area(r: DiskRect) -> f64 {
    let DiskRect { y0, y1, .. } = r;
    let alpha0 = acos(fabs(y0));
    let alpha1 = acos(fabs(y1));
    disk_pieces(r, |p| match (p.upper_rim, p.lower_rim) {
        (false, false) => r.height * p.dx,
        (true, true) => 2.0 * integral_cos_sq(p.a, p.b),
        // Column [y0, cos t].
        (true, false) if y0 <= 0.0 => integral_cos_sq(p.a, p.b) - y0 * p.dx,
        (true, false) => integral_segment(p.a, p.b, alpha0),
        // Column [−cos t, y1].
        (false, true) if y1 >= 0.0 => integral_cos_sq(p.a, p.b) + y1 * p.dx,
        (false, true) => integral_segment(p.a, p.b, alpha1),
    })
}

/// `∫_lo^hi dy / (c² + y²)²` with `len = hi − lo ≥ 0` given separately (accurately), from
/// `J(y) = y / (2c²(c² + y²)) + atan(y / c) / (2c³)`:
/// `J(hi) − J(lo) = len (c² − hi·lo) / (2c² (c² + hi²)(c² + lo²)) + atan2(len·c, c² + hi·lo) / (2c³)`,
/// two non-negative terms inside the unit disk (where `hi·lo ≤ 1 ≤ c²`).
#[inline]
fn stereographic_column(c2: f64, hi: f64, lo: f64, len: f64) -> f64 {
    if len.is_nan() || len <= 0.0 {
        return 0.0;
    }
    let c = sqrt(c2);
    let d_hi = c2 + hi * hi;
    let d_lo = c2 + lo * lo;
    len * (c2 - hi * lo) / (2.0 * c2 * d_hi * d_lo) + atan2(len * c, c2 + hi * lo) / (2.0 * c2 * c)
}

/// `∫∫ dx dy / (1 + x² + y²)²` over `r ∩ unit disk`.
fn stereographic_disk(r: DiskRect) -> f64 {
    let DiskRect { y0, y1, height, .. } = r;
    let alpha0 = acos(fabs(y0));
    let alpha1 = acos(fabs(y1));
    disk_pieces(r, |p| {
        if !p.upper_rim && !p.lower_rim {
            // The column is [y0, y1] throughout: smooth in x, integrate in x.
            return gauss_legendre(p.xa, p.dx, |x| {
                stereographic_column(1.0 + x * x, y1, y0, height)
            });
        }
        gauss_legendre(p.a, p.b - p.a, |t| {
            let x = sin(t);
            let h = cos(t);
            let (hi, lo, len) = match (p.upper_rim, p.lower_rim) {
                (true, true) => (h, -h, 2.0 * h),
                (true, _) if y0 <= 0.0 => (h, y0, h - y0),
                (true, _) => (h, y0, cos_minus_cos(t, alpha0)),
                (_, _) if y1 >= 0.0 => (y1, -h, y1 + h),
                (_, _) => (y1, -h, cos_minus_cos(t, alpha1)),
            };
            h * stereographic_column(1.0 + x * x, hi, lo, len)
        })
    })
}

/// `sin(πρ)/ρ` at `ρ² = s`, given `rest = 1 − s` as accurately as the caller knows it: directly
/// in the inner half of the disk (by its series where `s` is tiny or has underflowed), and as
/// `sin(π(1 − ρ))/ρ` with `1 − ρ = rest/(1 + ρ)` in the outer half, where `sin(πρ)` would
/// lose the relative precision of its small value.
///
/// For another lens scale `k` (an equidistant fisheye of field of view 2k < 2π), `sin(kρ)/ρ`:
/// its value on the rim, sin k, is not small, so it is computed directly.
#[inline]
fn equidistant_density(k: f64, s: f64, rest: f64) -> f64 {
    if k != PI {
        if s < 1e-16 {
            return k * (1.0 - k * k * s / 6.0);
        }
        let rho = sqrt(s);
        return sin(k * rho) / rho;
    }
    if s < 1e-16 {
        // π(1 − π²s/6 + …): the next term, π⁵s²/120, is below 1e-32.
        return PI * (1.0 - PI * PI * s / 6.0);
    }
    let rho = sqrt(s);
    if s < 0.25 {
        sin(PI * rho) / rho
    } else {
        sin(PI * (rest.max(0.0) / (1.0 + rho))) / rho
    }
}

/// `∫ sin(πρ)/ρ dy` over a column that ends on the rim, at x = sin t with h = cos t (the rim
/// end at y = ±h), of length `len`, in the distance z from the rim end:
/// ρ² = x² + (h − z)² and 1 − ρ² = z(2h − z) exactly (given x² + h² = 1), so the density
/// next to the rim is computed without cancellation.
#[inline]
fn equidistant_rim_column(k: f64, x: f64, h: f64, len: f64) -> f64 {
    gauss_legendre_entire(0.0, len, |z| {
        let y = h - z;
        equidistant_density(k, x * x + y * y, z * (2.0 * h - z))
    })
}

/// `∫∫ sin(kρ)/ρ dx dy` over `r ∩ unit disk` (ρ² = x² + y²; k = π for the angular map).
fn equidistant_disk(r: DiskRect, k: f64) -> f64 {
    let DiskRect { y0, y1, height, .. } = r;
    let alpha0 = acos(fabs(y0));
    let alpha1 = acos(fabs(y1));
    disk_pieces(r, |p| {
        if !p.upper_rim && !p.lower_rim {
            // The column is [y0, y1] throughout, inside the disk.
            return gauss_legendre_entire(p.xa, p.dx, |x| {
                gauss_legendre_entire(y0, height, |y| {
                    let s = x * x + y * y;
                    equidistant_density(k, s, 1.0 - s)
                })
            });
        }
        gauss_legendre_entire(p.a, p.b - p.a, |t| {
            let x = sin(t);
            let h = cos(t);
            let column = match (p.upper_rim, p.lower_rim) {
                // [−h, h], symmetric: twice [0, h], measured from the top.
                (true, true) => 2.0 * equidistant_rim_column(k, x, h, h),
                // [y0, h], from the top.
                (true, _) if y0 <= 0.0 => equidistant_rim_column(k, x, h, h - y0),
                (true, _) => equidistant_rim_column(k, x, h, cos_minus_cos(t, alpha0)),
                // [−h, y1], from the bottom (the density is even in y).
                (_, _) if y1 >= 0.0 => equidistant_rim_column(k, x, h, y1 + h),
                (_, _) => equidistant_rim_column(k, x, h, cos_minus_cos(t, alpha1)),
            };
            h * column
        })
    })
}

// ---------------------------------------------------------------------------------------------
// Tennisball
// ---------------------------------------------------------------------------------------------

/// dφ/du of the tennisball chart: φ = (u − 1/2)·3π/2.
const TENNIS_PHI_SCALE: f64 = 1.5 * PI;

/// u where the central band of a tennisball chart starts (φ = −π/2).
const TENNIS_U_LEFT: f64 = 1.0 / 6.0;

/// u where the central band of a tennisball chart ends (φ = +π/2).
const TENNIS_U_RIGHT: f64 = 5.0 / 6.0;

/// A latitude band `[τ0, τ1] ⊂ [0, π/4]` of the folded tennisball chart.
#[derive(Clone, Copy)]
struct Band {
    /// Lower latitude τ0 ≥ 0.
    tau0: f64,
    /// Upper latitude τ1 ≤ π/4.
    tau1: f64,
    /// `sin τ1 − sin τ0`, computed accurately.
    height: f64,
}

/// A ψ-interval `[ψa, ψb] ⊂ [0, π/4]` of one tennisball wing (ψ = |φ| − π/2), with the
/// complements `π/4 − ψ` computed from u without cancellation.
#[derive(Clone, Copy)]
struct WingSpan {
    /// ψ at the start.
    psi_a: f64,
    /// `π/4 − ψa`.
    rest_a: f64,
    /// ψ at the end.
    psi_b: f64,
    /// `π/4 − ψb`.
    rest_b: f64,
    /// `ψb − ψa`.
    width: f64,
}

/// The tennisball solid angle of a proper rectangle inside [0, 1]².
fn tennisball_owned(u0: f64, u1: f64, v0: f64, v1: f64) -> f64 {
    // θ = (1/2 − v)·π/2: v0 is the upper latitude.
    let theta_hi = (0.5 - v0) * FRAC_PI_2;
    let theta_lo = (0.5 - v1) * FRAC_PI_2;
    // sin θhi − sin θlo = 2 cos(mid) sin(half-width), both straight from v.
    let full_height = 2.0 * cos((1.0 - v0 - v1) * FRAC_PI_4) * sin((v1 - v0) * FRAC_PI_4);

    let mut total = 0.0;
    let (ca, cb) = (u0.max(TENNIS_U_LEFT), u1.min(TENNIS_U_RIGHT));
    if cb > ca {
        total += (cb - ca) * TENNIS_PHI_SCALE * full_height;
    }
    if u1 <= TENNIS_U_RIGHT && u0 >= TENNIS_U_LEFT {
        return total;
    }

    // Fold the latitude range onto θ ≥ 0 (ownership is symmetric in θ).
    let mut bands = [Band {
        tau0: 0.0,
        tau1: 0.0,
        height: 0.0,
    }; 2];
    let mut count = 0;
    if theta_lo >= 0.0 || theta_hi <= 0.0 {
        let (tau0, tau1) = if theta_lo >= 0.0 {
            (theta_lo, theta_hi)
        } else {
            (-theta_hi, -theta_lo)
        };
        bands[0] = Band {
            tau0,
            tau1,
            height: full_height,
        };
        count = 1;
    } else {
        for tau1 in [theta_hi, -theta_lo] {
            bands[count] = Band {
                tau0: 0.0,
                tau1,
                height: sin(tau1),
            };
            count += 1;
        }
    }
    let bands = &bands[..count];

    if u1 > TENNIS_U_RIGHT {
        let ua = u0.max(TENNIS_U_RIGHT);
        let span = WingSpan {
            psi_a: (ua - TENNIS_U_RIGHT) * TENNIS_PHI_SCALE,
            rest_a: (1.0 - ua) * TENNIS_PHI_SCALE,
            psi_b: (u1 - TENNIS_U_RIGHT) * TENNIS_PHI_SCALE,
            rest_b: (1.0 - u1) * TENNIS_PHI_SCALE,
            width: (u1 - ua) * TENNIS_PHI_SCALE,
        };
        total += tennisball_wing(span, bands);
    }
    if u0 < TENNIS_U_LEFT {
        // The left wing, mirrored: ψ = −π/2 − φ = (1/6 − u)·3π/2.
        let ub = u1.min(TENNIS_U_LEFT);
        let span = WingSpan {
            psi_a: (TENNIS_U_LEFT - ub) * TENNIS_PHI_SCALE,
            rest_a: ub * TENNIS_PHI_SCALE,
            psi_b: (TENNIS_U_LEFT - u0) * TENNIS_PHI_SCALE,
            rest_b: u0 * TENNIS_PHI_SCALE,
            width: (ub - u0) * TENNIS_PHI_SCALE,
        };
        total += tennisball_wing(span, bands);
    }
    total
}

/// `s ∈ [0, π/2]` with `sin s = tan ψ`, from ψ and `π/4 − ψ`:
/// `tan s = sin ψ / √(cos 2ψ)` and `cos 2ψ = sin(2(π/4 − ψ))`.
#[inline]
fn wing_s(psi: f64, rest: f64) -> f64 {
    atan2(sin(psi), sqrt(sin(2.0 * rest).max(0.0)))
}

/// Where the wing's ownership boundary `|sin θ| = cos s/√2` crosses the latitude τ ∈ [0, π/4]:
/// returns `(s, ψ)` with `cos s = √2 sin τ`, `sin s = tan ψ = √(cos 2τ)`.
#[inline]
fn wing_kink(tau: f64) -> (f64, f64) {
    let root = sqrt(sin(2.0 * (FRAC_PI_4 - tau)).max(0.0));
    (atan2(root, SQRT_2 * sin(tau)), atan(root))
}

/// Owned solid angle of one wing over `span` and the folded latitude `bands`.
fn tennisball_wing(span: WingSpan, bands: &[Band]) -> f64 {
    let sa = wing_s(span.psi_a, span.rest_a);
    let sb = wing_s(span.psi_b, span.rest_b);
    let mut total = 0.0;
    for band in bands {
        let (kappa1, psi_kappa1) = wing_kink(band.tau1);
        let (kappa0, _) = wing_kink(band.tau0);
        // Full columns: ψ below the kink of τ1.
        if span.psi_b <= psi_kappa1 {
            total += band.height * span.width;
        } else if psi_kappa1 > span.psi_a {
            total += band.height * (psi_kappa1 - span.psi_a);
        }
        // Partial columns, between the kinks of τ1 and τ0: owned sin θ ∈ [sin τ0, cos s/√2].
        let a = sa.max(kappa1);
        let b = sb.min(kappa0);
        total += gauss_legendre(a, b - a, |s| {
            let sin_s = sin(s);
            SQRT_2 * sin(0.5 * (kappa0 + s)) * sin(0.5 * (kappa0 - s)) * cos(s)
                / (1.0 + sin_s * sin_s)
        });
    }
    total
}

// ---------------------------------------------------------------------------------------------
// Octahedral map: convex polygons in (u', v')
// ---------------------------------------------------------------------------------------------

/// A convex polygon in (u', v') with at most 8 vertices (a rectangle clipped by three
/// half-planes has at most 7).
#[derive(Clone, Copy)]
struct Polygon {
    /// Origin of the vertex coordinates: vertex `k` is the point `origin + vertices[k]`.
    origin: [f64; 2],
    /// Vertices, as offsets from `origin`, in order around the polygon; only the first `len`
    /// are used.
    vertices: [[f64; 2]; 8],
    /// Number of vertices.
    len: usize,
}

impl Polygon {
    /// The rectangle `[x0, x0 + width] × [y0, y0 + height]`, with origin `(x0, y0)`.
    #[inline]
    fn rectangle(x0: f64, y0: f64, width: f64, height: f64) -> Self {
        let mut vertices = [[0.0; 2]; 8];
        vertices[..4].copy_from_slice(&[[0.0, 0.0], [width, 0.0], [width, height], [0.0, height]]);
        Self {
            origin: [x0, y0],
            vertices,
            len: 4,
        }
    }

    /// Sutherland–Hodgman: the part of the polygon where `nx·x + ny·y + c ≥ 0`.
    #[inline]
    fn clip(&self, nx: f64, ny: f64, c: f64) -> Self {
        let mut out = Self {
            origin: self.origin,
            vertices: [[0.0; 2]; 8],
            len: 0,
        };
        // The half-plane in offset coordinates.
        let c = nx * self.origin[0] + ny * self.origin[1] + c;
        let side = |p: [f64; 2]| nx * p[0] + ny * p[1] + c;
        for i in 0..self.len {
            let p = self.vertices[i];
            let q = self.vertices[(i + 1) % self.len];
            let (dp, dq) = (side(p), side(q));
            if dp >= 0.0 {
                out.push(p);
            }
            if (dp > 0.0 && dq < 0.0) || (dp < 0.0 && dq > 0.0) {
                let t = dp / (dp - dq);
                out.push([p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])]);
            }
        }
        out
    }

    /// Appends a vertex (silently dropped if full, which a convex input cannot cause).
    #[inline]
    fn push(&mut self, p: [f64; 2]) {
        if self.len < self.vertices.len() {
            self.vertices[self.len] = p;
            self.len += 1;
        }
    }

    /// Solid angle of this polygon, which lies in the octahedral-map triangle of quadrant
    /// `(sx, sy)`, inside (`outer == false`) or outside the diamond: its vertices are mapped
    /// affinely onto the octahedron and the spherical polygon is summed as a fan.
    fn octahedral_solid_angle(&self, sx: f64, sy: f64, outer: bool) -> f64 {
        if self.len < 3 {
            return 0.0;
        }
        // The affine map p(x, y) of this triangle and its linear part.
        let point = |v: [f64; 2]| {
            let z = 1.0 - sx * v[0] - sy * v[1];
            if outer {
                DVec3::new(sx * (1.0 - sy * v[1]), sy * (1.0 - sx * v[0]), z)
            } else {
                DVec3::new(v[0], v[1], z)
            }
        };
        let linear = |dx: f64, dy: f64| {
            let dz = -sx * dx - sy * dy;
            if outer {
                DVec3::new(-sx * sy * dy, -sx * sy * dx, dz)
            } else {
                DVec3::new(dx, dy, dz)
            }
        };
        let first = self.vertices[0];
        let apex = point([self.origin[0] + first[0], self.origin[1] + first[1]]);
        let edge = |v: [f64; 2]| linear(v[0] - first[0], v[1] - first[1]);
        let mut total = 0.0;
        for i in 1..self.len - 1 {
            total += spherical_triangle(apex, edge(self.vertices[i]), edge(self.vertices[i + 1]));
        }
        total
    }
}

#[cfg(test)]
mod tests {
    extern crate std;

    use super::*;
    use std::vec::Vec;

    const FOUR_PI: f64 = 2.0 * TAU;

    /// Compensated (Neumaier) sum, so the grid sums measure the function, not the summation.
    fn neumaier(values: impl Iterator<Item = f64>) -> f64 {
        let (mut sum, mut comp) = (0.0f64, 0.0f64);
        for v in values {
            let t = sum + v;
            if fabs(sum) >= fabs(v) {
                comp += (sum - t) + v;
            } else {
                comp += (v - t) + sum;
            }
            sum = t;
        }
        sum + comp
    }

    type Chart = fn(f64, f64, f64, f64) -> f64;

    /// The texel `(i, j)` of a `w × h` grid.
    fn texel(f: Chart, w: usize, h: usize, i: usize, j: usize) -> f64 {
        let (w, h) = (w as f64, h as f64);
        f(
            i as f64 / w,
            (i + 1) as f64 / w,
            j as f64 / h,
            (j + 1) as f64 / h,
        )
    }

    fn grid_sum(f: Chart, w: usize, h: usize) -> f64 {
        neumaier((0..h).flat_map(|j| (0..w).map(move |i| texel(f, w, h, i, j))))
    }

    fn rel(a: f64, b: f64) -> f64 {
        if a == b {
            0.0
        } else {
            fabs(a - b) / fabs(b)
        }
    }

    const SIZES: [(usize, usize); 9] = [
        (1, 1),
        (3, 3),
        (7, 7),
        (64, 64),
        (255, 255),
        (7, 3),
        (3, 7),
        (255, 64),
        (1, 255),
    ];

    fn check_sums(name: &str, f: Chart, total: f64, sizes: &[(usize, usize)]) {
        let mut worst = 0.0f64;
        for &(w, h) in sizes {
            let sum = grid_sum(f, w, h);
            let err = rel(sum, total);
            std::println!("{name:>22} {w:>4} x {h:<4} sum rel err {err:.2e}");
            assert!(err <= 1e-10, "{name} {w}x{h}: {sum} vs {total} ({err:e})");
            worst = worst.max(err);
        }
        std::println!("{name:>22} worst sum rel err {worst:.2e}");
    }

    #[test]
    fn sums_latlong() {
        check_sums("latlong", latlong, FOUR_PI, &SIZES);
    }

    #[test]
    fn sums_cube_face() {
        check_sums("cube_face", cube_face, FOUR_PI / 6.0, &SIZES);
    }

    #[test]
    fn sums_sphere_map() {
        check_sums("sphere_map", sphere_map, FOUR_PI, &SIZES);
    }

    #[test]
    fn sums_paraboloid() {
        check_sums("paraboloid", paraboloid, TAU, &SIZES);
    }

    #[test]
    fn sums_angular() {
        let mut sizes = SIZES.to_vec();
        sizes.extend([(2, 2), (4, 4), (512, 512)]);
        check_sums("angular", angular, FOUR_PI, &sizes);
    }

    #[test]
    fn sums_tennisball() {
        let mut sizes = SIZES.to_vec();
        sizes.extend([(3, 1), (21, 7), (765, 255), (192, 64), (256, 64)]);
        check_sums("tennisball", tennisball, TAU, &sizes);
    }

    #[test]
    fn sums_octahedral() {
        check_sums("octahedral", octahedral, FOUR_PI, &SIZES);
    }

    #[test]
    fn sums_equal_area_octahedral() {
        check_sums(
            "equal_area_octahedral",
            equal_area_octahedral,
            FOUR_PI,
            &SIZES,
        );
    }

    #[test]
    fn whole_charts() {
        assert!(rel(latlong(0.0, 1.0, 0.0, 1.0), FOUR_PI) < 1e-15);
        assert!(rel(cube_face(0.0, 1.0, 0.0, 1.0), FOUR_PI / 6.0) < 1e-15);
        assert!(rel(sphere_map(0.0, 1.0, 0.0, 1.0), FOUR_PI) < 1e-15);
        assert!(rel(paraboloid(0.0, 1.0, 0.0, 1.0), TAU) < 1e-15);
        assert!(rel(tennisball(0.0, 1.0, 0.0, 1.0), TAU) < 1e-15);
        assert!(rel(octahedral(0.0, 1.0, 0.0, 1.0), FOUR_PI) < 1e-15);
        assert!(rel(equal_area_octahedral(0.0, 1.0, 0.0, 1.0), FOUR_PI) < 1e-15);
        assert!(rel(angular(0.0, 1.0, 0.0, 1.0), FOUR_PI) < 1e-15);
        // Pieces with known closed forms.
        let wing = TAU - PI * SQRT_2;
        assert!(rel(tennisball(0.0, 1.0 / 6.0, 0.0, 1.0), 0.5 * wing) < 1e-14);
        assert!(rel(tennisball(1.0 / 6.0, 5.0 / 6.0, 0.0, 1.0), PI * SQRT_2) < 1e-15);
        assert!(rel(sphere_map(0.5, 1.0, 0.5, 1.0), PI) < 1e-15);
        assert!(rel(paraboloid(0.5, 1.0, 0.0, 1.0), PI) < 1e-15);
        assert!(rel(octahedral(0.5, 1.0, 0.5, 1.0), PI) < 1e-15);
        // Angular map: a quadrant and a half of the disk, by symmetry.
        assert!(rel(angular(0.5, 1.0, 0.5, 1.0), PI) < 1e-15);
        assert!(rel(angular(0.0, 1.0, 0.0, 0.5), TAU) < 1e-15);
        // Northern hemisphere of the latlong map, a hemisphere's worth of octahedral triangles.
        assert!(rel(latlong(0.0, 1.0, 0.0, 0.5), TAU) < 1e-15);
    }

    const ALL: [(&str, Chart); 8] = [
        ("latlong", latlong),
        ("cube_face", cube_face),
        ("sphere_map", sphere_map),
        ("paraboloid", paraboloid),
        ("tennisball", tennisball),
        ("octahedral", octahedral),
        ("equal_area_octahedral", equal_area_octahedral),
        ("angular", angular),
    ];

    #[test]
    fn orientation_clipping_degenerate() {
        for (name, f) in ALL {
            let (a, b, c, d) = (0.1, 0.93, 0.02, 0.71);
            let x = f(a, b, c, d);
            assert!(x > 0.0, "{name}");
            assert_eq!(f(b, a, c, d), -x, "{name}");
            assert_eq!(f(a, b, d, c), -x, "{name}");
            assert_eq!(f(b, a, d, c), x, "{name}");
            assert_eq!(f(a, a, c, d), 0.0, "{name}");
            assert_eq!(f(a, b, c, c), 0.0, "{name}");
            assert_eq!(f(1.5, 2.0, c, d), 0.0, "{name}");
            assert_eq!(f(a, b, -3.0, -1.0), 0.0, "{name}");
            assert!(f(f64::NAN, b, c, d).is_nan(), "{name}");
            assert!(f(a, b, c, f64::NAN).is_nan(), "{name}");
            // Clipping.
            assert_eq!(f(-0.5, 1.5, -2.0, 7.0), f(0.0, 1.0, 0.0, 1.0), "{name}");
            assert_eq!(
                f(f64::NEG_INFINITY, f64::INFINITY, 0.0, 1.0),
                f(0.0, 1.0, 0.0, 1.0)
            );
            assert_eq!(f(-0.25, b, c, 1.25), f(0.0, b, c, 1.0), "{name}");
            // Additivity across arbitrary (also reversed) splits.
            for (m, n) in [(0.37, 0.5), (0.5, 0.83), (0.97, 0.05), (0.25, 0.75)] {
                let split = f(a, m, c, n) + f(m, b, c, n) + f(a, m, n, d) + f(m, b, n, d);
                assert!(
                    fabs(split - x) <= 1e-14 * fabs(x),
                    "{name} {m} {n}: {split} {x}"
                );
            }
        }
    }

    /// Checks that texel (i, j) and its images under the chart's symmetries agree.
    fn check_symmetry(name: &str, f: Chart, w: usize, h: usize, transpose: bool) {
        let mut worst = 0.0f64;
        for j in 0..h {
            for i in 0..w {
                let x = texel(f, w, h, i, j);
                let mut images = std::vec![
                    texel(f, w, h, w - 1 - i, j),
                    texel(f, w, h, i, h - 1 - j),
                    texel(f, w, h, w - 1 - i, h - 1 - j),
                ];
                if transpose {
                    images.push(texel(f, h, w, j, i));
                }
                for y in images {
                    let d = fabs(x - y) / fabs(x).max(1e-300);
                    worst = worst.max(if x == y { 0.0 } else { d });
                }
            }
        }
        std::println!("{name:>22} {w}x{h} worst mirror-texel rel diff {worst:.2e}");
        assert!(worst <= 1e-12, "{name}: {worst}");
    }

    #[test]
    fn symmetries() {
        for (w, h) in [(7, 7), (64, 64), (63, 63)] {
            check_symmetry("latlong", latlong, w, h, false);
            check_symmetry("cube_face", cube_face, w, h, true);
            check_symmetry("sphere_map", sphere_map, w, h, true);
            check_symmetry("paraboloid", paraboloid, w, h, true);
            check_symmetry("octahedral", octahedral, w, h, true);
            check_symmetry("angular", angular, w, h, true);
        }
        for (w, h) in [(21, 7), (192, 64), (189, 63)] {
            check_symmetry("tennisball", tennisball, w, h, false);
        }
        // Latlong: every texel of a row is the same.
        let row: Vec<f64> = (0..9).map(|i| texel(latlong, 9, 5, i, 1)).collect();
        assert!(row.iter().all(|&x| rel(x, row[0]) < 1e-15));
    }

    // -----------------------------------------------------------------------------------------
    // Independent references
    // -----------------------------------------------------------------------------------------

    /// Solid-angle densities in (u, v), with the ownership / disk indicator.
    fn density_latlong(_u: f64, v: f64) -> f64 {
        2.0 * PI * PI * sin(PI * v)
    }
    fn density_cube(u: f64, v: f64) -> f64 {
        let (x, y) = (2.0 * u - 1.0, 2.0 * v - 1.0);
        4.0 / libm::pow(1.0 + x * x + y * y, 1.5)
    }
    fn density_sphere(u: f64, v: f64) -> f64 {
        let (x, y) = (2.0 * u - 1.0, 2.0 * v - 1.0);
        if x * x + y * y <= 1.0 {
            16.0
        } else {
            0.0
        }
    }
    fn density_paraboloid(u: f64, v: f64) -> f64 {
        let (x, y) = (2.0 * u - 1.0, 2.0 * v - 1.0);
        let r2 = x * x + y * y;
        if r2 <= 1.0 {
            16.0 / ((1.0 + r2) * (1.0 + r2))
        } else {
            0.0
        }
    }
    fn density_angular(u: f64, v: f64) -> f64 {
        let (x, y) = (2.0 * u - 1.0, 2.0 * v - 1.0);
        let r = x.hypot(y);
        if r > 1.0 {
            0.0
        } else if r == 0.0 {
            4.0 * PI * PI
        } else {
            4.0 * PI * sin(PI * r) / r
        }
    }
    fn tennis_owned(phi: f64, theta: f64) -> bool {
        fabs(phi) <= FRAC_PI_2 || cos(theta) * fabs(sin(phi)) >= 0.5 * SQRT_2
    }
    fn density_tennisball(u: f64, v: f64) -> f64 {
        let phi = (u - 0.5) * 1.5 * PI;
        let theta = (0.5 - v) * FRAC_PI_2;
        if tennis_owned(phi, theta) {
            1.5 * PI * FRAC_PI_2 * cos(theta)
        } else {
            0.0
        }
    }
    fn density_octahedral(u: f64, v: f64) -> f64 {
        let (x, y) = (2.0 * u - 1.0, 2.0 * v - 1.0);
        let z = 1.0 - fabs(x) - fabs(y);
        let p = if z >= 0.0 {
            DVec3::new(x, y, z)
        } else {
            DVec3::new((1.0 - fabs(y)).copysign(x), (1.0 - fabs(x)).copysign(y), z)
        };
        4.0 / (p.length() * p.dot(p))
    }

    /// Midpoint rule with `n × n` samples over the rectangle. Also returns a bound on the
    /// error the ownership indicator's jump can cause: the mass (cell area × largest density
    /// at its corners and midpoint) of the cells whose corners are not all owned or all not.
    fn midpoint(density: fn(f64, f64) -> f64, r: [f64; 4], n: usize) -> (f64, f64) {
        let du = (r[1] - r[0]) / n as f64;
        let dv = (r[3] - r[2]) / n as f64;
        let corner = |i: usize, j: usize| density(r[0] + i as f64 * du, r[2] + j as f64 * dv);
        let mut below: Vec<f64> = (0..=n).map(|i| corner(i, 0)).collect();
        let (mut sum, mut jump) = (Vec::with_capacity(n * n), 0.0);
        for j in 0..n {
            let above: Vec<f64> = (0..=n).map(|i| corner(i, j + 1)).collect();
            for i in 0..n {
                let mid = density(r[0] + (i as f64 + 0.5) * du, r[2] + (j as f64 + 0.5) * dv);
                sum.push(mid);
                let c = [below[i], below[i + 1], above[i], above[i + 1], mid];
                if c.contains(&0.0) && c.iter().any(|&x| x != 0.0) {
                    jump += c.iter().fold(0.0f64, |m, &x| m.max(x));
                }
            }
            below = above;
        }
        (neumaier(sum.into_iter()) * du * dv, jump * du * dv)
    }

    /// Adaptive Simpson (std recursion), to an absolute tolerance (or rounding level).
    fn simpson(f: &dyn Fn(f64) -> f64, a: f64, b: f64, tol: f64) -> f64 {
        /// An interval with its end and mid values and its Simpson estimate.
        struct Seg {
            a: f64,
            b: f64,
            fa: f64,
            fm: f64,
            fb: f64,
            whole: f64,
        }
        fn step(f: &dyn Fn(f64) -> f64, seg: Seg, tol: f64, depth: u32) -> f64 {
            let Seg {
                a,
                b,
                fa,
                fm,
                fb,
                whole,
            } = seg;
            let m = 0.5 * (a + b);
            let (lm, rm) = (0.5 * (a + m), 0.5 * (m + b));
            let (flm, frm) = (f(lm), f(rm));
            let left = (m - a) / 6.0 * (fa + 4.0 * flm + fm);
            let right = (b - m) / 6.0 * (fm + 4.0 * frm + fb);
            let delta = left + right - whole;
            // Stop at the tolerance, or where the estimate has reached rounding level.
            if depth == 0 || fabs(delta) <= 15.0 * tol || fabs(delta) <= 1e-12 * fabs(whole) {
                left + right + delta / 15.0
            } else {
                let l = Seg {
                    a,
                    b: m,
                    fa,
                    fm: flm,
                    fb: fm,
                    whole: left,
                };
                let r = Seg {
                    a: m,
                    b,
                    fa: fm,
                    fm: frm,
                    fb,
                    whole: right,
                };
                step(f, l, 0.5 * tol, depth - 1) + step(f, r, 0.5 * tol, depth - 1)
            }
        }
        let (fa, fm, fb) = (f(a), f(0.5 * (a + b)), f(b));
        let whole = (b - a) / 6.0 * (fa + 4.0 * fm + fb);
        step(
            f,
            Seg {
                a,
                b,
                fa,
                fm,
                fb,
                whole,
            },
            tol,
            30,
        )
    }

    /// Sharp 1-D reference for the sphere map: ∫ dx of the naive column height, in x.
    fn reference_sphere(r: [f64; 4]) -> f64 {
        let (x0, x1, y0, y1) = (
            2.0 * r[0] - 1.0,
            2.0 * r[1] - 1.0,
            2.0 * r[2] - 1.0,
            2.0 * r[3] - 1.0,
        );
        let column = |x: f64| {
            let h = sqrt((1.0 - x * x).max(0.0));
            (y1.min(h) - y0.max(-h)).max(0.0)
        };
        4.0 * simpson(&column, x0, x1, 1e-16)
    }

    /// Sharp 1-D reference for the paraboloid: naive J(hi) − J(lo) in x.
    fn reference_paraboloid(r: [f64; 4]) -> f64 {
        let (x0, x1, y0, y1) = (
            2.0 * r[0] - 1.0,
            2.0 * r[1] - 1.0,
            2.0 * r[2] - 1.0,
            2.0 * r[3] - 1.0,
        );
        let column = |x: f64| {
            let h = sqrt((1.0 - x * x).max(0.0));
            let (lo, hi) = (y0.max(-h), y1.min(h));
            if hi <= lo {
                return 0.0;
            }
            let c2 = 1.0 + x * x;
            let c = sqrt(c2);
            let j = |y: f64| y / (2.0 * c2 * (c2 + y * y)) + atan(y / c) / (2.0 * c2 * c);
            j(hi) - j(lo)
        };
        4.0 * simpson(&column, x0, x1, 1e-16)
    }

    /// Sharp 1-D reference for the angular map, in polar coordinates (an independent
    /// formulation): dΩ = π sin(πρ) dρ dφ, so along each ray φ the owned part [ρin, ρout] of
    /// the rectangle (clipped to the disk) contributes cos(πρin) − cos(πρout), written as
    /// 2 sin(π(ρin + ρout)/2) sin(π(ρout − ρin)/2); adaptive Simpson in φ, split at the
    /// corners' angles and where the rim crosses the edges (the kinks of ρin and ρout).
    fn reference_angular(r: [f64; 4]) -> f64 {
        let (x0, x1, y0, y1) = (
            2.0 * r[0] - 1.0,
            2.0 * r[1] - 1.0,
            2.0 * r[2] - 1.0,
            2.0 * r[3] - 1.0,
        );
        // The ρ-interval of the ray at angle φ inside the slab [a, b] of one coordinate.
        let slab = |c: f64, a: f64, b: f64| -> (f64, f64) {
            if c == 0.0 {
                if a <= 0.0 && 0.0 <= b {
                    (0.0, f64::INFINITY)
                } else {
                    (1.0, 0.0)
                }
            } else {
                let (p, q) = (a / c, b / c);
                (p.min(q), p.max(q))
            }
        };
        let column = |phi: f64| {
            let (sp, cp) = libm::sincos(phi);
            let (ax, bx) = slab(cp, x0, x1);
            let (ay, by) = slab(sp, y0, y1);
            let lo = ax.max(ay).max(0.0);
            let hi = bx.min(by).min(1.0);
            if hi <= lo {
                return 0.0;
            }
            2.0 * sin(0.5 * PI * (lo + hi)) * sin(0.5 * PI * (hi - lo))
        };
        let mut cuts = std::vec![-PI, PI];
        for (x, y) in [(x0, y0), (x0, y1), (x1, y0), (x1, y1)] {
            cuts.push(atan2(y, x));
        }
        for (c, lo, hi, vertical) in [
            (x0, y0, y1, true),
            (x1, y0, y1, true),
            (y0, x0, x1, false),
            (y1, x0, x1, false),
        ] {
            if fabs(c) < 1.0 {
                let h = sqrt(1.0 - c * c);
                for w in [-h, h] {
                    if w >= lo && w <= hi {
                        cuts.push(if vertical { atan2(w, c) } else { atan2(c, w) });
                    }
                }
            }
        }
        cuts.sort_by(f64::total_cmp);
        // The integrand jumps at some cuts (a ray through a corner), whose angles are rounded:
        // each piece is evaluated a few ulps inside its ends, at its own one-sided values.
        let eta = 2e-15;
        cuts.windows(2)
            .filter(|p| p[1] - p[0] > 2.0 * eta)
            .map(|p| {
                let inside = |phi: f64| column(phi.clamp(p[0] + eta, p[1] - eta));
                simpson(&inside, p[0], p[1], 1e-17)
            })
            .sum()
    }

    /// Sharp 1-D reference for the tennisball: in φ, with β(φ) = acos(√2 / (2|sin φ|)).
    fn reference_tennisball(r: [f64; 4]) -> f64 {
        let phi0 = (r[0] - 0.5) * 1.5 * PI;
        let phi1 = (r[1] - 0.5) * 1.5 * PI;
        let theta1 = (0.5 - r[2]) * FRAC_PI_2;
        let theta0 = (0.5 - r[3]) * FRAC_PI_2;
        let column = |phi: f64| {
            let beta = if fabs(phi) <= FRAC_PI_2 {
                FRAC_PI_4
            } else {
                acos((0.5 * SQRT_2 / fabs(sin(phi))).min(1.0))
            };
            (sin(theta1.min(beta)) - sin(theta0.max(-beta))).max(0.0)
        };
        // Split at ±π/2, where β has a kink.
        let mut cuts = std::vec![phi0, phi1];
        for c in [-FRAC_PI_2, FRAC_PI_2] {
            if c > phi0 && c < phi1 {
                cuts.push(c);
            }
        }
        cuts.sort_by(f64::total_cmp);
        cuts.windows(2)
            .map(|p| simpson(&column, p[0], p[1], 1e-16))
            .sum()
    }

    /// Sharp 1-D reference for the octahedral map: adaptive Simpson in x of the inner integral
    /// in y, which is in closed form on each triangle: there |p|² = Q(y) = A y² + B y + C and
    /// ∫ Q^(−3/2) dy = 2(2Ay + B) / ((4AC − B²) √Q).
    fn reference_octahedral(r: [f64; 4]) -> f64 {
        let (x0, x1, y0, y1) = (
            2.0 * r[0] - 1.0,
            2.0 * r[1] - 1.0,
            2.0 * r[2] - 1.0,
            2.0 * r[3] - 1.0,
        );
        let column = |x: f64| {
            let mut cuts = std::vec![y0, y1];
            for c in [0.0, 1.0 - fabs(x), fabs(x) - 1.0] {
                if c > y0 && c < y1 {
                    cuts.push(c);
                }
            }
            cuts.sort_by(f64::total_cmp);
            let sx = if x < 0.0 { -1.0 } else { 1.0 };
            let m = 1.0 - sx * x;
            cuts.windows(2)
                .map(|p| {
                    let mid = 0.5 * (p[0] + p[1]);
                    let sy = if mid < 0.0 { -1.0 } else { 1.0 };
                    let (a, b, c) = if fabs(x) + fabs(mid) <= 1.0 {
                        (2.0, -2.0 * m * sy, x * x + m * m)
                    } else {
                        (2.0, -2.0 * sy * (1.0 + m), 1.0 + 2.0 * m * m)
                    };
                    let prim = |y: f64| {
                        2.0 * (2.0 * a * y + b)
                            / ((4.0 * a * c - b * b) * sqrt(a * y * y + b * y + c))
                    };
                    prim(p[1]) - prim(p[0])
                })
                .sum::<f64>()
        };
        // dΩ = dx dy / |p|³ in x = u', y = v'.
        simpson(&column, x0, x1, 1e-16)
    }

    /// The wing of the tennisball from its closed-form antiderivative (a cancellation-prone
    /// but independent formula): owned solid angle of a full-height wing column ψ ∈ [ψa, ψb].
    fn wing_column_closed_form(psi_a: f64, psi_b: f64) -> f64 {
        let w = |psi: f64| {
            let s = asin(libm::tan(psi).min(1.0));
            SQRT_2 * atan(SQRT_2 * libm::tan(s)) - s
        };
        let w_end = |psi: f64| {
            if psi >= FRAC_PI_4 {
                SQRT_2 * FRAC_PI_2 - FRAC_PI_2
            } else {
                w(psi)
            }
        };
        SQRT_2 * (w_end(psi_b) - w_end(psi_a))
    }

    fn four_corner_cube(r: [f64; 4]) -> f64 {
        let a = |u: f64, v: f64| {
            let (x, y) = (2.0 * u - 1.0, 2.0 * v - 1.0);
            atan2(x * y, sqrt(1.0 + x * x + y * y))
        };
        a(r[1], r[3]) - a(r[0], r[3]) - a(r[1], r[2]) + a(r[0], r[2])
    }

    /// A sharp reference value of a rectangle `[u0, u1, v0, v1]`.
    type Reference = fn([f64; 4]) -> f64;

    fn grid_rect(w: usize, h: usize, i: usize, j: usize) -> [f64; 4] {
        let (wf, hf) = (w as f64, h as f64);
        [
            i as f64 / wf,
            (i + 1) as f64 / wf,
            j as f64 / hf,
            (j + 1) as f64 / hf,
        ]
    }

    fn call(f: Chart, r: [f64; 4]) -> f64 {
        f(r[0], r[1], r[2], r[3])
    }

    /// Spot check against the brute-force midpoint rule (tolerance: that rule's own error,
    /// bounded by comparing n and 2n samples, plus a floor) and, where given, a sharp reference.
    fn spot(
        name: &str,
        f: Chart,
        density: fn(f64, f64) -> f64,
        sharp: Option<(Reference, f64)>,
        r: [f64; 4],
        n: usize,
        worst: &mut [f64; 2],
    ) {
        let x = call(f, r);
        let (coarse, _) = midpoint(density, r, n / 2);
        let (fine, jump) = midpoint(density, r, n);
        // The midpoint rule's error: O(h²) where the density is smooth, which |fine − coarse|
        // bounds (it is 3 times the fine rule's error there), plus at most `jump` from the
        // cells an ownership boundary crosses.
        let tol = fabs(fine - coarse) + jump + 1e-12 * fabs(fine);
        let err = fabs(x - fine);
        let scale = fabs(x).max(f64::MIN_POSITIVE);
        std::println!(
            "{name:>22} {:?}: {x:.16e}  brute {fine:.16e}  diff {:.1e} (tol {:.1e})",
            r,
            err / scale,
            tol / scale
        );
        assert!(
            err <= tol,
            "{name} {r:?}: {x} vs brute force {fine} (tol {tol:e})"
        );
        worst[0] = worst[0].max(err / scale);
        if let Some((reference, rtol)) = sharp {
            let y = reference(r);
            let e = rel(x, y);
            std::println!("{name:>22}   sharp reference {y:.16e}  rel diff {e:.1e}");
            assert!(e <= rtol, "{name} {r:?}: {x} vs reference {y} ({e:e})");
            worst[1] = worst[1].max(e);
        }
    }

    #[test]
    fn spot_checks() {
        let mut worst = [0.0f64; 2];
        let n = 1024;
        // Latlong: pole row, equator row, generic texel.
        for r in [
            grid_rect(64, 32, 5, 0),
            grid_rect(64, 32, 63, 16),
            grid_rect(7, 3, 2, 2),
        ] {
            let naive = |r: [f64; 4]| TAU * (r[1] - r[0]) * (cos(PI * r[2]) - cos(PI * r[3]));
            spot("latlong", latlong, density_latlong, None, r, n, &mut worst);
            assert!(rel(call(latlong, r), naive(r)) < 1e-12);
        }
        // Cube: corner, edge and centre texels, and an odd rectangle.
        let cube_ref: Reference = four_corner_cube;
        for r in [
            grid_rect(64, 64, 0, 0),
            grid_rect(64, 64, 31, 0),
            grid_rect(63, 63, 31, 31),
            grid_rect(7, 7, 5, 2),
            [0.1, 0.73, 0.22, 0.9],
        ] {
            spot(
                "cube_face",
                cube_face,
                density_cube,
                Some((cube_ref, 1e-12)),
                r,
                n,
                &mut worst,
            );
        }
        // Sphere map: interior, rim texels, a texel the rim barely crosses, a big rectangle.
        for r in [
            grid_rect(64, 64, 40, 30),
            grid_rect(64, 64, 0, 31),
            grid_rect(64, 64, 9, 9),
            grid_rect(64, 64, 10, 5),
            grid_rect(7, 7, 6, 2),
            [0.05, 0.7, 0.4, 0.97],
        ] {
            spot(
                "sphere_map",
                sphere_map,
                density_sphere,
                Some((reference_sphere, 1e-11)),
                r,
                n,
                &mut worst,
            );
        }
        // Paraboloid: the same kinds of texels.
        for r in [
            grid_rect(64, 64, 40, 30),
            grid_rect(64, 64, 0, 31),
            grid_rect(64, 64, 9, 9),
            grid_rect(64, 64, 10, 5),
            grid_rect(7, 7, 6, 2),
            [0.05, 0.7, 0.4, 0.97],
            [0.0, 1.0, 0.0, 0.003],
        ] {
            spot(
                "paraboloid",
                paraboloid,
                density_paraboloid,
                Some((reference_paraboloid, 1e-11)),
                r,
                n,
                &mut worst,
            );
        }
        // Tennisball: centre, a wing texel inside, boundary texels, the tip, a big rectangle.
        for r in [
            grid_rect(192, 64, 96, 10),
            grid_rect(192, 64, 170, 31),
            grid_rect(192, 64, 175, 10),
            grid_rect(192, 64, 20, 50),
            grid_rect(192, 64, 191, 31),
            grid_rect(192, 64, 160, 0),
            grid_rect(21, 7, 19, 4),
            [0.02, 0.9, 0.1, 0.45],
        ] {
            spot(
                "tennisball",
                tennisball,
                density_tennisball,
                Some((reference_tennisball, 1e-11)),
                r,
                n,
                &mut worst,
            );
        }
        // Angular map: the centre, interior, rim texels, a texel the rim barely crosses, a
        // big rectangle, a thin strip along the rim and texels of a 4096-wide map.
        for r in [
            grid_rect(64, 64, 31, 31),
            grid_rect(64, 64, 40, 30),
            grid_rect(64, 64, 0, 31),
            grid_rect(64, 64, 9, 9),
            grid_rect(64, 64, 10, 5),
            grid_rect(7, 7, 6, 2),
            [0.05, 0.7, 0.4, 0.97],
            [0.0, 1.0, 0.0, 0.003],
            grid_rect(4096, 4096, 2048, 4095),
            grid_rect(4096, 4096, 3000, 500),
        ] {
            spot(
                "angular",
                angular,
                density_angular,
                Some((reference_angular, 1e-11)),
                r,
                n,
                &mut worst,
            );
        }
        // Octahedral: texels on the diamond, on an axis, at the centre and a corner, generic.
        for r in [
            grid_rect(64, 64, 48, 16),
            grid_rect(63, 63, 31, 10),
            grid_rect(63, 63, 31, 31),
            grid_rect(64, 64, 0, 63),
            grid_rect(7, 7, 1, 2),
            [0.1, 0.8, 0.3, 0.95],
        ] {
            spot(
                "octahedral",
                octahedral,
                density_octahedral,
                Some((reference_octahedral, 1e-11)),
                r,
                n,
                &mut worst,
            );
        }
        std::println!(
            "worst spot-check difference: {:.1e} vs brute force, {:.1e} vs sharp references",
            worst[0],
            worst[1]
        );
    }

    /// Every texel of odd and even grids against the polar reference: relative to the texel's
    /// own solid angle, and for the slivers the rim cuts off, relative to an average texel's.
    /// The difference is mostly the reference's own error (its Simpson rule stops at steps of
    /// 1e-12 relative), which the bounds leave room for.
    #[test]
    fn angular_texels_match_polar_reference() {
        for n in [16usize, 33] {
            let average = FOUR_PI / (PI * 0.25 * (n * n) as f64);
            let (mut worst_rel, mut worst_abs) = (0.0f64, 0.0f64);
            for j in 0..n {
                for i in 0..n {
                    let r = grid_rect(n, n, i, j);
                    let (x, y) = (call(angular, r), reference_angular(r));
                    let e = fabs(x - y);
                    if y > 1e-3 * average {
                        worst_rel = worst_rel.max(e / y);
                    }
                    worst_abs = worst_abs.max(e / average);
                }
            }
            std::println!(
                "angular {n}x{n} vs polar reference: worst rel {worst_rel:.1e}, \
                 worst abs / average texel {worst_abs:.1e}"
            );
            assert!(worst_rel <= 1e-13, "{n}: {worst_rel:e}");
            assert!(worst_abs <= 5e-14, "{n}: {worst_abs:e}");
        }
    }

    /// The short rules of `gauss_legendre_entire` against the 16-point panels, on columns of
    /// the angular map's density at its largest lengths (1/128 and 1/8) and shorter ones, kept
    /// 0.05 from the rim (where the density's own rounding, relative to its small value, differs
    /// from node to node and would hide a truncation error).
    #[test]
    fn short_gauss_legendre_rules_match_the_panels() {
        let mut worst = 0.0f64;
        for c in [0.0, 0.3, 0.7, 0.95] {
            let f = |x: f64| {
                let s = x * x + c * c;
                equidistant_density(PI, s, 1.0 - s)
            };
            for length in [1.0 / 128.0, 1e-3, 0.125, 0.05] {
                for k in 0..16 {
                    let a = -0.99 + f64::from(k) * 0.12;
                    let edge = sqrt(1.0 - c * c) - 0.05;
                    let a = a.min(edge - length).max(-edge);
                    let x = gauss_legendre_entire(a, length, f);
                    let y = gauss_legendre(a, length, f);
                    worst = worst.max(rel(x, y));
                }
            }
        }
        // What remains is the density's own rounding near the rim.
        std::println!("short Gauss–Legendre rules vs 16-point panels: {worst:.1e}");
        assert!(worst <= 4e-15, "{worst:e}");
    }

    #[test]
    fn tennisball_wing_columns_match_closed_form() {
        // Full-height wing columns of a 192-wide chart (32 columns per wing).
        let mut worst = 0.0f64;
        for i in 160..192 {
            let r = grid_rect(192, 1, i, 0);
            let psi_a = (r[0] - 5.0 / 6.0) * 1.5 * PI;
            let psi_b = (r[1] - 5.0 / 6.0) * 1.5 * PI;
            let x = call(tennisball, r);
            let y = wing_column_closed_form(psi_a, psi_b);
            worst = worst.max(rel(x, y));
            // The mirrored column of the left wing.
            assert!(rel(texel(tennisball, 192, 1, 191 - i, 0), x) < 1e-13);
        }
        std::println!("tennisball wing columns vs closed form: {worst:.1e}");
        assert!(worst < 1e-11);
    }

    #[test]
    fn equal_area_octahedral_has_constant_jacobian() {
        // Clarberg's map as in pbrt-v4's EqualAreaSquareToSphere; its Jacobian is 4π everywhere.
        fn map(u: f64, v: f64) -> DVec3 {
            let (x, y) = (2.0 * u - 1.0, 2.0 * v - 1.0);
            let (ax, ay) = (fabs(x), fabs(y));
            let signed_distance = 1.0 - (ax + ay);
            let r = 1.0 - fabs(signed_distance);
            let phi = if r == 0.0 { 1.0 } else { (ay - ax) / r + 1.0 } * FRAC_PI_4;
            let z = (1.0 - r * r).copysign(signed_distance);
            let k = r * sqrt((2.0 - r * r).max(0.0));
            DVec3::new(cos(phi).copysign(x) * k, sin(phi).copysign(y) * k, z)
        }
        let h = 1e-6;
        for (u, v) in [
            (0.1, 0.2),
            (0.3, 0.7),
            (0.6, 0.45),
            (0.9, 0.95),
            (0.52, 0.13),
            (0.83, 0.31),
        ] {
            let diff = |a: DVec3, b: DVec3| (a - b) / (2.0 * h);
            let du = diff(map(u + h, v), map(u - h, v));
            let dv = diff(map(u, v + h), map(u, v - h));
            let jacobian = du.cross(dv).length();
            assert!(rel(jacobian, FOUR_PI) < 1e-7, "{u} {v}: {jacobian}");
        }
    }
}
