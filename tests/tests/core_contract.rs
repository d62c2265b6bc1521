//! The mapping contract (`docs/conventions.md`, "The mapping contract"),
//! proven by property tests over every mapping of [`AnyMapping::ALL`].
//!
//! One proptest per property; each case checks every mapping. The default
//! run is quick; raise `PROPTEST_CASES` for a long sweep, and add
//! `-- --nocapture` to see the worst case each test measured:
//!
//! ```text
//! PROPTEST_CASES=200000 cargo test -p envmap-tests --release --test core_contract -- --nocapture
//! ```
//!
//! All reference values (angles, distances, stretch factors) are computed in
//! f64 from the exact `f32` inputs and outputs.

use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI};

use envmap_core::tennisball;
use envmap_core::texel::texel_index;
use envmap_core::{AnyMapping, ChartUv, Frame, Framed, Mapping};
use envmap_tests::{
    angle, awkward_component, cube_area_element, integrate_2d, nonzero, rotate_away, ulps_outside,
    uniform_direction, unit_f64, uv_distance, with_ties, wrapped_distance, Worst,
};
use glam::{DVec3, Quat, Vec3};
use proptest::prelude::*;

// ---------------------------------------------------------------------------------------------
// Strategies
// ---------------------------------------------------------------------------------------------

/// Uniformly distributed unit directions (rounded to f32, so only nearly unit).
fn unit_direction() -> impl Strategy<Value = Vec3> {
    (0.0f64..=1.0, 0.0f64..1.0).prop_map(|(s, t)| uniform_direction(s, t).as_vec3())
}

/// One awkward component: see [`awkward_component`].
fn awkward() -> impl Strategy<Value = f32> {
    (0u8..8, any::<u32>(), any::<bool>()).prop_map(|(k, b, n)| awkward_component(k, b, n))
}

/// Finite non-zero directions of any length: components from denormals to
/// `f32::MAX`, signed zeros, mixed magnitudes, and exact ties between
/// component magnitudes.
fn awkward_direction() -> impl Strategy<Value = Vec3> {
    (awkward(), awkward(), awkward(), 0u8..8)
        .prop_map(|(x, y, z, tie)| nonzero(with_ties(Vec3::new(x, y, z), tie)))
}

/// The 26 directions where something happens: the axes (poles, cube face
/// centres, sphere-map singular directions, tennisball chart centres), the
/// cube edge midpoints (also tennisball selection boundaries) and the cube
/// corners.
fn special_directions() -> Vec<DVec3> {
    let mut v = Vec::new();
    for x in [-1.0, 0.0, 1.0] {
        for y in [-1.0, 0.0, 1.0] {
            for z in [-1.0, 0.0, 1.0] {
                if (x, y, z) != (0.0, 0.0, 0.0) {
                    let d = DVec3::new(x, y, z);
                    v.push(d / d.length());
                }
            }
        }
    }
    v
}

/// Directions at a distance of 0 or 10^-1 … 10^-12 rad from one of
/// [`special_directions`].
fn near_special_direction() -> impl Strategy<Value = Vec3> {
    (
        0usize..26,
        0.0f64..std::f64::consts::TAU,
        0u32..13,
        0.0f64..1.0,
    )
        .prop_map(|(i, psi, e, frac)| {
            let base = special_directions()[i];
            let alpha = if e == 0 {
                0.0
            } else {
                10f64.powf(-(f64::from(e) + frac))
            };
            rotate_away(base, psi, alpha).as_vec3()
        })
}

/// Every kind of direction above.
fn any_direction() -> impl Strategy<Value = Vec3> {
    prop_oneof![
        4 => unit_direction(),
        3 => awkward_direction(),
        3 => near_special_direction(),
    ]
}

/// A chart coordinate in [0, 1]: uniform, exact edges and values a power of
/// two away from them.
fn coordinate() -> impl Strategy<Value = f32> {
    prop_oneof![
        8 => 0.0f32..=1.0,
        1 => Just(0.0f32),
        1 => Just(1.0f32),
        1 => Just(0.5f32),
        2 => (1i32..25).prop_map(|k| 2f32.powi(-k)),
        2 => (1i32..25).prop_map(|k| 1.0 - 2f32.powi(-k)),
    ]
}

// ---------------------------------------------------------------------------------------------
// Per-mapping facts the properties are stated with
// ---------------------------------------------------------------------------------------------

/// The singular direction of a disk map whose whole rim inverts to one
/// direction: the sphere maps' −V, the angular map's −z.
fn singular_direction(m: AnyMapping) -> Option<DVec3> {
    match m {
        AnyMapping::SphereMap => Some(DVec3::Z),
        AnyMapping::SphereMapGl | AnyMapping::Angular => Some(DVec3::NEG_Z),
        _ => None,
    }
}

/// Whether `m` sees the unit direction `d` (in `m`'s own axes): `Some(true)` for every
/// mapping but a fisheye that does not cover the sphere; for that one, whether `d` is within
/// its field of view, or `None` within 1e-6 rad of the rim, where rounding decides.
fn sees(m: AnyMapping, d: DVec3) -> Option<bool> {
    match envmap_tests::past_rim(m, d.as_vec3()) {
        None => Some(true),
        Some(p) if p.abs() < 1e-6 => None,
        Some(p) => Some(p < 0.0),
    }
}

/// `c`, the forward image of a direction whose unit vector in `m`'s axes is `d`, checked
/// against what `m` sees: a point exactly where the direction is seen, none where it is not.
fn check_seen(
    m: AnyMapping,
    c: Option<ChartUv>,
    d: DVec3,
) -> Result<Option<ChartUv>, TestCaseError> {
    match sees(m, d) {
        Some(true) => prop_assert!(c.is_some(), "{m}: forward({d}) is None"),
        Some(false) => prop_assert!(c.is_none(), "{m}: {d} is not seen, but forward gave {c:?}"),
        None => {}
    }
    Ok(c)
}

/// β: the angle (rad) from the unit direction `d` to `m`'s singular direction
/// (π for mappings without one).
fn beta(m: AnyMapping, d: DVec3) -> f64 {
    singular_direction(m).map_or(PI, |s| angle(d, s))
}

// Bounds on the angle (rad) between normalize(d) and inverse(forward(d)),
// measured in f64, for any finite non-zero f32 direction d. Each is 1.5–2×
// the worst error of a long run (PROPTEST_CASES=200000; the worst errors are
// in docs/accuracy.md, "Round trips"), so that a rarer input stays inside.

/// Latlong. The worst inputs have u and v near 1 (one f32 step is 6e-8,
/// i.e. 3.8e-7 rad of longitude), and 2πu and πv are rounded again before
/// sin/cos.
const LATLONG_RT: f64 = 1.5e-6;
/// Cube.
const CUBE_RT: f64 = 2e-7;
/// Equi-angular cube: atan and tan each rounded once more than the cube.
const EAC_RT: f64 = 4e-7;
/// Sphere maps, the constant part of `a + b/β`. Far from the singular
/// direction the errors stay below b/β.
const SPHERE_RT_A: f64 = 1e-7;
/// Sphere maps, the 1/β part: err·β stays about the same size for every β,
/// from next to the singular direction to far from it.
const SPHERE_RT_B: f64 = 1.8e-6;
/// Dual paraboloid; the worst inputs are at the rim.
const PARABOLOID_RT: f64 = 5e-7;
/// Tennisball.
const TENNISBALL_RT: f64 = 9e-7;
/// Octahedral.
const OCTAHEDRAL_RT: f64 = 7e-7;
/// Equal-area octahedral; the worst inputs are on the equator.
const EQUAL_AREA_OCTAHEDRAL_RT: f64 = 1e-6;
/// Angular map: no 1/β growth at its singular direction (an angle β from
/// −z sits β/π inside the rim, so one f32 step of (u, v) costs the same
/// angle there as elsewhere in the outer half). As for the latlong, the
/// worst inputs have u and v f32 above ½ (one step is 6e-8, i.e. 1.9e-7
/// rad along the radius, which is π rad per unit of u' = 2u − 1), and θ,
/// θ/π and the inverse's ρ and πρ are rounded on the way.
const ANGULAR_RT: f64 = 1.5e-6;
/// Fisheyes (the defaults of `AnyMapping::ALL`: equidistant, 180°): θ and θ/k rounded, then
/// the inverse's kρ and its sine and cosine.
const FISHEYE_RT: f64 = 1.5e-6;

/// The bound on the direction round-trip error of `m` at the unit direction
/// `d` (see the constants above). For the sphere maps it grows like 1/β near
/// the singular direction (β → 0), where an angular distance β sits only
/// β²/8 inside the rim, so that one f32 step of (u, v) is ~8/β·1e-7 rad
/// (the angular map's β/π does not: its bound is constant).
fn direction_round_trip_bound(m: AnyMapping, d: DVec3) -> f64 {
    match m {
        AnyMapping::LatLong => LATLONG_RT,
        AnyMapping::Cube => CUBE_RT,
        AnyMapping::SphereMap | AnyMapping::SphereMapGl => SPHERE_RT_A + SPHERE_RT_B / beta(m, d),
        AnyMapping::DualParaboloid => PARABOLOID_RT,
        AnyMapping::Tennisball => TENNISBALL_RT,
        AnyMapping::Octahedral => OCTAHEDRAL_RT,
        AnyMapping::EqualAreaOctahedral => EQUAL_AREA_OCTAHEDRAL_RT,
        AnyMapping::Angular => ANGULAR_RT,
        AnyMapping::Eac => EAC_RT,
        AnyMapping::Fisheye(_) => FISHEYE_RT,
    }
}

/// The largest stretch |Δ(u, v)| / Δangle of `m`'s forward map at the unit
/// direction `d` (the largest singular value of its Jacobian from the unit
/// sphere to (u, v)), derived from each formula:
///
/// * latlong: v = θ/π, u = φ/2π with arc length sin θ dφ, so
///   max(1/π, 1/(2π sin θ)), unbounded at the poles;
/// * cube: the gnomonic projection stretches radially by 1 + ρ² (ρ² ≤ 2 at a
///   face corner) and (u, v) are half the face coordinates: 3/2;
/// * sphere maps: r = sin(γ/2) with γ the angle from the viewer (β = π − γ):
///   radially cos(γ/2)/2, along the circle 1/(2 cos(γ/2)); in (u, v) half:
///   max(1/4, 1/(4 sin(β/2))), unbounded at the singular direction;
/// * paraboloid: stereographic, conformal, sec²(γ/2)/2 ≤ 1 at the rim: 1/2;
/// * tennisball: v = ½ − θ/(π/2), u = ½ + φ/(3π/2) with cos θ ≥ √2/2: 2/π;
/// * octahedral: largest at the octahedron's vertices on the equator, where
///   the Jacobian in (u', v') is [[−1, −1], [1, 0]] (singular value the
///   golden ratio): (1 + √5)/4;
/// * equal-area octahedral: largest on the equator next to the ±x and ±y
///   axes, where the Jacobian in (u', v') is [[−2/π, −1/2], [2/π, 0]]
///   (singular value 0.9771): 0.4886. (Both octahedral values were also
///   confirmed by a finite-difference search over 2·10⁶ directions.)
/// * angular: ρ = θ/π with θ the angle from +z, so radially 1/π and along
///   the circle ρ/sin θ = θ/(π sin θ) ≥ 1/π; in (u, v) half:
///   θ/(2π sin θ) = (π − β)/(2π sin β), unbounded at the singular direction.
/// * EAC: the cube's plane coordinate c grows by 1 + ρ² per radian radially,
///   and u = ½ + (2/π) atan c by (2/π)/(1 + c²) per unit of c; largest at a
///   face corner (c = 1 on both axes, ρ² = 2), along the diagonal:
///   3 · (1/π) · √2/√2 = 3/π (also found by a finite-difference search over
///   2·10⁵ directions: 0.9544).
/// * fisheye of half field of view k, θ from the nearer lens's axis: equidistant, r = θ/k,
///   radially 1/k and along the circle θ/(k sin θ); equisolid, r = sin(θ/2)/sin(k/2),
///   radially cos(θ/2)/(2 sin(k/2)) and along the circle 1/(2 sin(k/2) cos(θ/2)); in (u, v)
///   half of the larger.
fn stretch(m: AnyMapping, d: DVec3) -> f64 {
    match m {
        AnyMapping::LatLong => {
            let sin_theta = d.x.hypot(d.y);
            (1.0 / PI).max(1.0 / (2.0 * PI * sin_theta))
        }
        AnyMapping::Cube => 1.5,
        AnyMapping::SphereMap | AnyMapping::SphereMapGl => {
            0.25f64.max(1.0 / (4.0 * (0.5 * beta(m, d)).sin()))
        }
        AnyMapping::DualParaboloid => 0.5,
        AnyMapping::Tennisball => 2.0 / PI,
        AnyMapping::Octahedral => (1.0 + 5f64.sqrt()) / 4.0,
        AnyMapping::EqualAreaOctahedral => 0.4886,
        AnyMapping::Angular => angular_stretch(beta(m, d)),
        AnyMapping::Eac => 3.0 / PI,
        AnyMapping::Fisheye(f) => {
            let axial = if f.is_dual() { d.z.abs() } else { d.z };
            let theta = d.x.hypot(d.y).atan2(axial);
            let k = f.fov_degrees().to_radians() / 2.0;
            let s = if theta > 0.0 {
                theta / theta.sin()
            } else {
                1.0
            };
            match f.lens() {
                envmap_core::Lens::Equidistant => s / (2.0 * k),
                envmap_core::Lens::Equisolid => {
                    let h = (k / 2.0).sin();
                    ((theta / 2.0).cos() / (4.0 * h)).max(1.0 / (4.0 * h * (theta / 2.0).cos()))
                }
            }
        }
    }
}

/// The angular map's stretch at the angle β from −z (see [`stretch`]).
fn angular_stretch(beta: f64) -> f64 {
    if beta >= PI {
        1.0 / (2.0 * PI)
    } else {
        ((PI - beta) / (2.0 * PI * beta.sin())).max(1.0 / (2.0 * PI))
    }
}

fn describe(d: Vec3) -> String {
    format!("d = Vec3::new({:e}, {:e}, {:e})", d.x, d.y, d.z)
}

fn describe_c(c: ChartUv) -> String {
    format!("ChartUv::new({}, {:e}, {:e})", c.chart, c.u, c.v)
}

// ---------------------------------------------------------------------------------------------
// 1. Forward output is in range
// ---------------------------------------------------------------------------------------------

/// Property 1: for any finite non-zero direction (that a fisheye sees), `forward` gives a chart
/// below `chart_count` and (u, v) in [0, 1] for which `in_chart` holds (the
/// disk for the disk maps), at any length, without overflow.
#[test]
fn forward_output_is_in_range() {
    proptest!(|(d in prop_oneof![awkward_direction(), any_direction()])| {
        for m in AnyMapping::ALL {
            let Some(c) = check_seen(m, m.forward(d), unit_f64(d))? else {
                continue;
            };
            prop_assert!(c.chart < m.chart_count(), "{m}: {} -> {c:?}", describe(d));
            prop_assert!((0.0..=1.0).contains(&c.u), "{m}: {} -> {c:?}", describe(d));
            prop_assert!((0.0..=1.0).contains(&c.v), "{m}: {} -> {c:?}", describe(d));
            prop_assert!(
                m.in_chart(c.chart, c.u, c.v),
                "{m}: {} -> {c:?} not in chart", describe(d)
            );
        }
    });
}

// ---------------------------------------------------------------------------------------------
// 2. direction -> coordinates -> direction
// ---------------------------------------------------------------------------------------------

/// Property 2: `inverse(forward(d))` is `normalize(d)` within the stated
/// bound ([`direction_round_trip_bound`]), the angle measured in f64.
#[test]
fn direction_round_trip() {
    let worst = Worst::per_mapping();
    let ratio = Worst::per_mapping();
    let sphere_beta = Worst::new(&[
        "sphere err·β (β < 0.5)",
        "sphere-gl err·β (β < 0.5)",
        "sphere err (β ≥ 0.5)",
        "sphere-gl err (β ≥ 0.5)",
        "sphere err (β ≥ 2)",
        "sphere-gl err (β ≥ 2)",
    ]);
    proptest!(|(d in any_direction())| {
        let unit = unit_f64(d);
        for (k, m) in AnyMapping::ALL.into_iter().enumerate() {
            let Some(c) = check_seen(m, m.forward(d), unit)? else {
                continue;
            };
            let back = m.inverse(c);
            prop_assert!(back.is_some(), "{m}: inverse({c:?}) of {} is None", describe(d));
            let err = angle(unit, back.unwrap().as_dvec3());
            let bound = direction_round_trip_bound(m, unit);
            worst.record(k, err, || format!("{} -> {c:?}", describe(d)));
            ratio.record(k, err / bound, || format!("{} (err {err:.3e})", describe(d)));
            if matches!(m, AnyMapping::SphereMap | AnyMapping::SphereMapGl) {
                let b = beta(m, unit);
                let s = usize::from(m == AnyMapping::SphereMapGl);
                if b < 0.5 {
                    sphere_beta.record(s, err * b, || format!("{} β = {b:.3e}", describe(d)));
                } else {
                    sphere_beta.record(s + 2, err, || format!("{} β = {b:.3e}", describe(d)));
                }
                if b >= 2.0 {
                    sphere_beta.record(s + 4, err, || format!("{} β = {b:.3e}", describe(d)));
                }
            }
            prop_assert!(
                err <= bound,
                "{m}: {} -> {c:?} -> {:?}: {err:e} rad > {bound:e}", describe(d), back.unwrap()
            );
        }
    });
    worst.report("direction round trip: worst error (rad)");
    ratio.report("direction round trip: worst error / bound");
    sphere_beta.report("sphere maps near the singular direction");
}

/// Property 2, at scale: a unit direction multiplied by 1e-30, 1e30 and
/// `f32::MAX`/2 gives the same coordinates as the unit direction, within
/// 1e-6 plus the mapping's stretch times the angle by which rounding the
/// product to f32 turned the direction.
#[test]
fn forward_is_scale_invariant() {
    let worst = Worst::per_mapping();
    proptest!(|(d in prop_oneof![unit_direction(), near_special_direction()])| {
        let unit = unit_f64(d);
        for (k, m) in AnyMapping::ALL.into_iter().enumerate() {
            let Some(c) = check_seen(m, m.forward(d), unit)? else {
                continue;
            };
            for scale in [1e-30f32, 1e30, f32::MAX / 2.0] {
                let ds = d * scale;
                let turned = angle(unit, ds.as_dvec3());
                let Some(cs) = m.forward(ds) else {
                    // Only at a fisheye's rim, where rounding decides.
                    prop_assert!(sees(m, unit).is_none(), "{m}: {} × {scale:e} unseen", describe(d));
                    continue;
                };
                if cs.chart != c.chart {
                    // A chart boundary (cube edge, tennisball selection
                    // boundary, paraboloid equator): both must be the same
                    // direction.
                    let (a, b) = (m.inverse(c), m.inverse(cs));
                    prop_assert!(
                        a.is_some() && b.is_some(),
                        "{m}: {c:?} or {cs:?} does not invert"
                    );
                    let (a, b) = (a.unwrap().as_dvec3(), b.unwrap().as_dvec3());
                    let bound = 2.0 * direction_round_trip_bound(m, unit) + turned;
                    prop_assert!(
                        angle(a, b) <= bound,
                        "{m}: {} × {scale:e}: {c:?} vs {cs:?}", describe(d)
                    );
                    continue;
                }
                let dist = if m == AnyMapping::LatLong {
                    wrapped_distance(c.u, cs.u).hypot(f64::from(c.v) - f64::from(cs.v))
                } else {
                    uv_distance(c, cs)
                };
                let bound = 1e-6 + if turned > 0.0 { stretch(m, unit) * turned } else { 0.0 };
                worst.record(k, dist, || format!("{} × {scale:e}", describe(d)));
                prop_assert!(dist <= bound, "{m}: {} × {scale:e}: {c:?} vs {cs:?}", describe(d));
            }
        }
    });
    worst.report("scale invariance: worst |Δ(u, v)|");
}

// ---------------------------------------------------------------------------------------------
// 3. coordinates -> direction -> coordinates
// ---------------------------------------------------------------------------------------------

// Bounds on |forward(inverse(c)) − c| in (u, v) where the chart owns
// inverse(c) (latlong: max(|Δv|, |Δu|·sin πv)), about 2× the worst of a
// long run (PROPTEST_CASES=200000), a few f32 steps of (u, v).

/// Latlong.
const LATLONG_CRT: f64 = 2.4e-7;
/// Cube.
const CUBE_CRT: f64 = 1.6e-7;
/// Equi-angular cube.
const EAC_CRT: f64 = 3e-7;
/// Sphere maps.
const SPHERE_CRT: f64 = 1.6e-7;
/// Dual paraboloid.
const PARABOLOID_CRT: f64 = 2.4e-7;
/// Tennisball.
const TENNISBALL_CRT: f64 = 2.4e-7;
/// Octahedral.
const OCTAHEDRAL_CRT: f64 = 1.4e-7;
/// Equal-area octahedral.
const EQUAL_AREA_OCTAHEDRAL_CRT: f64 = 2.8e-7;
/// Angular map.
const ANGULAR_CRT: f64 = 2.4e-7;
/// Fisheyes.
const FISHEYE_CRT: f64 = 2.4e-7;

/// Sphere-map points this close to the rim (in r = |(u', v')|) are left out
/// of the coordinate round trip: the whole rim is one direction, and within
/// ~1e-7 of it r² rounds to 1 (the point inverts to the singular direction,
/// which forward sends to (1, ½)). Between 1 − 1e-3 and 1 − 1e-6 the round
/// trip holds with the same bound as inside.
const SPHERE_RIM: f64 = 1e-6;

/// Angular-map points this close to the rim (in r = |(u', v')|) are left
/// out of the coordinate round trip: the whole rim is −z, and where r
/// rounds to 1 in f32 (from r ≥ 1 − 3e-8) the point inverts to −z, which
/// forward sends to (1, ½). Everywhere further in, however close to the
/// rim, the round trip holds with the same bound as inside: the inverse
/// keeps the azimuth (sin θ from the exact 1 − ρ) and forward reads it back
/// from x and y as they are.
const ANGULAR_RIM: f64 = 1e-7;

/// How far (in the f64 quantities below) a tennisball point must be from its
/// chart's ownership boundary for the ownership check to apply.
const TENNISBALL_OWNERSHIP_MARGIN: f64 = 1e-6;

/// The tennisball chart's (θ, φ) at (u, v), as the chart's inverse computes them.
fn tennisball_angles(u: f32, v: f32) -> (f32, f32) {
    let phi = (u - 0.5) * (1.5 * std::f32::consts::PI);
    let theta = (0.5 - v) * std::f32::consts::FRAC_PI_2;
    (theta, phi)
}

/// Whether (θ, φ) is within [`TENNISBALL_OWNERSHIP_MARGIN`] of the boundary
/// of the region its chart owns: |φ| = π/2, cos θ |sin φ| = √2/2, or |θ| = π/4
/// (where chart 1 meets chart 0's selection rule |a| ≥ √2/2).
fn near_tennisball_ownership_boundary(theta: f32, phi: f32) -> bool {
    let (t, p) = (f64::from(theta), f64::from(phi));
    let m = TENNISBALL_OWNERSHIP_MARGIN;
    (p.abs() - FRAC_PI_2).abs() < m
        || (t.cos() * p.sin().abs() - 0.5f64.sqrt()).abs() < m
        || (t.abs() - FRAC_PI_4).abs() < m
}

/// Property 3: `forward(inverse(c))` is `c` wherever the chart owns
/// `inverse(c)`, within a stated bound.
///
/// Seams, and how each is handled rather than skipped where possible:
///
/// * latlong: the wrap u = 0 ≡ 1 is handled by measuring Δu modulo 1, and
///   the poles (v = 0, 1, where u is undefined) by weighting Δu with
///   sin(πv), i.e. measuring it as arc length along the parallel; nothing is
///   left out.
/// * cube: a point whose s or t is within 1e-6 of 0 or 1 is on a face edge
///   (a tie that the z-over-y-over-x rule may give to the neighbouring face):
///   there a change of face is allowed, and nowhere else.
/// * sphere maps: points with r > 1 − [`SPHERE_RIM`] are left out (the rim
///   is the singular direction), and angular-map points with
///   r > 1 − [`ANGULAR_RIM`] (its rim is −z); the paraboloid is tested up
///   to its rim (z = ±0 keeps the chart).
/// * tennisball: `forward` must answer in the same chart exactly when
///   `tennisball::owns` says the chart owns the point (away from the
///   ownership boundary); owned points must round-trip. The owned fraction
///   is checked in [`tennisball_owned_fraction_is_large`].
/// * octahedral maps: tested on the whole square including its outer edges
///   and corners (signed zeros keep the side of the fold).
#[test]
fn coordinate_round_trip() {
    let worst = Worst::per_mapping();
    proptest!(|(chart in 0u32..6, u in coordinate(), v in coordinate())| {
        for (k, m) in AnyMapping::ALL.into_iter().enumerate() {
            let c = ChartUv::new(chart % m.chart_count(), u, v);
            if !m.in_chart(c.chart, u, v) {
                prop_assert!(m.inverse(c).is_none(), "{m}: {c:?} outside its chart inverts");
                continue;
            }
            let d = m.inverse(c);
            prop_assert!(d.is_some(), "{m}: inverse({c:?}) is None");
            let d = d.unwrap();
            let c2 = m.forward(d);
            prop_assert!(c2.is_some(), "{m}: {} -> {d} is not seen", describe_c(c));
            let c2 = c2.unwrap();
            let (u64_, v64) = (f64::from(u), f64::from(v));
            let err = match m {
                AnyMapping::LatLong => {
                    let du = wrapped_distance(u, c2.u) * (PI * v64).sin();
                    du.max((v64 - f64::from(c2.v)).abs())
                }
                AnyMapping::Cube | AnyMapping::Eac => {
                    if c2.chart != c.chart {
                        let near_edge = [u64_, v64].iter().any(|&x| x.min(1.0 - x) <= 1e-6);
                        prop_assert!(near_edge, "{m}: {c:?} -> {d} -> {c2:?} changed face");
                        continue;
                    }
                    uv_distance(c, c2)
                }
                AnyMapping::SphereMap | AnyMapping::SphereMapGl => {
                    let r = (2.0 * u64_ - 1.0).hypot(2.0 * v64 - 1.0);
                    if r > 1.0 - SPHERE_RIM {
                        continue;
                    }
                    uv_distance(c, c2)
                }
                AnyMapping::Angular => {
                    let r = (2.0 * u64_ - 1.0).hypot(2.0 * v64 - 1.0);
                    if r > 1.0 - ANGULAR_RIM {
                        continue;
                    }
                    uv_distance(c, c2)
                }
                AnyMapping::Fisheye(f) => {
                    if c2.chart != c.chart {
                        // Two lenses: the other one owns the directions past the equator,
                        // at radius ρ₀ = (π/2)/k (equidistant) or sin(π/4)/sin(k/2)
                        // (equisolid), 1 for 180°.
                        let r = (2.0 * u64_ - 1.0).hypot(2.0 * v64 - 1.0);
                        let k = f.fov_degrees().to_radians() / 2.0;
                        let rho0 = match f.lens() {
                            envmap_core::Lens::Equidistant => FRAC_PI_2 / k,
                            envmap_core::Lens::Equisolid => FRAC_PI_4.sin() / (k / 2.0).sin(),
                        };
                        prop_assert!(
                            f.is_dual() && r >= rho0 - 1e-6,
                            "{m}: {} -> {d} -> {c2:?} changed lens", describe_c(c)
                        );
                        continue;
                    }
                    uv_distance(c, c2)
                }
                AnyMapping::Tennisball => {
                    let (theta, phi) = tennisball_angles(u, v);
                    let owned = c2.chart == c.chart;
                    if !near_tennisball_ownership_boundary(theta, phi) {
                        prop_assert_eq!(
                            owned, tennisball::owns(theta, phi),
                            "tennisball: {} -> {} -> {:?}", describe_c(c), d, c2
                        );
                    }
                    if !owned {
                        continue;
                    }
                    uv_distance(c, c2)
                }
                _ => {
                    prop_assert_eq!(c2.chart, c.chart);
                    uv_distance(c, c2)
                }
            };
            worst.record(k, err, || format!("{} -> {c2:?}", describe_c(c)));
            let bound = match m {
                AnyMapping::LatLong => LATLONG_CRT,
                AnyMapping::Cube => CUBE_CRT,
                AnyMapping::SphereMap | AnyMapping::SphereMapGl => SPHERE_CRT,
                AnyMapping::DualParaboloid => PARABOLOID_CRT,
                AnyMapping::Tennisball => TENNISBALL_CRT,
                AnyMapping::Octahedral => OCTAHEDRAL_CRT,
                AnyMapping::EqualAreaOctahedral => EQUAL_AREA_OCTAHEDRAL_CRT,
                AnyMapping::Angular => ANGULAR_CRT,
                AnyMapping::Eac => EAC_CRT,
                AnyMapping::Fisheye(_) => FISHEYE_CRT,
            };
            prop_assert!(
                err <= bound,
                "{m}: {} -> {d} -> {c2:?}: {err:e} > {bound:e}", describe_c(c)
            );
        }
    });
    worst.report("coordinate round trip: worst |Δ(u, v)|");
}

/// The tennisball part of property 3 cannot pass vacuously: on a fine grid
/// over both strips most points are owned, and ownership is exactly what
/// `tennisball::owns` says (away from its boundary).
#[test]
fn tennisball_owned_fraction_is_large() {
    let m = AnyMapping::Tennisball;
    let n = 600;
    let (mut owned, mut total, mut disagree) = (0u32, 0u32, 0u32);
    for chart in 0..2 {
        for j in 0..=n / 3 {
            for i in 0..=n {
                let (u, v) = (i as f32 / n as f32, j as f32 / (n / 3) as f32);
                let c = ChartUv::new(chart, u, v);
                let c2 = m.forward(m.inverse(c).unwrap()).unwrap();
                let (theta, phi) = tennisball_angles(u, v);
                total += 1;
                if c2.chart == chart {
                    owned += 1;
                    assert!(uv_distance(c, c2) <= TENNISBALL_CRT, "{c:?} -> {c2:?}");
                }
                if !near_tennisball_ownership_boundary(theta, phi)
                    && (c2.chart == chart) != tennisball::owns(theta, phi)
                {
                    disagree += 1;
                }
            }
        }
    }
    let fraction = f64::from(owned) / f64::from(total);
    println!(
        "tennisball: {owned} of {total} grid points owned ({:.1} %)",
        100.0 * fraction
    );
    assert_eq!(disagree, 0);
    // The owned part of a strip is 2π of its 3π/√2 sr; in (u, v) it is the
    // middle two thirds plus two lenses: 93.0 % of the grid.
    assert!(fraction > 0.9, "{fraction}");
}

// ---------------------------------------------------------------------------------------------
// 4. Continuity
// ---------------------------------------------------------------------------------------------

/// The rounding noise allowed on top of the stretch bound: each forward call
/// rounds (u, v) by a few f32 ulps of 1, and the perturbed direction is
/// itself rounded to f32. About 1.5× the worst excess |Δ(u, v)| − K·α of a
/// long run (PROPTEST_CASES=200000).
const CONTINUITY_NOISE: f64 = 3e-7;

/// Property 4: a change of direction by an angle α ≤ 1e-4 rad moves (u, v)
/// by at most K·α (K = [`stretch`], taken at the end of the step nearer the
/// singularity, less α) plus rounding noise, when both directions land in
/// the same chart and the step does not cross a documented seam:
///
/// * latlong: Δu is measured modulo 1 (u = 0 ≡ 1 is continuous), and steps
///   with an end within 2α of a pole are left out (K grows like 1/sin θ and
///   is taken at sin θ − α);
/// * sphere maps and the angular map: steps with an end within 2α of the
///   singular direction are left out (K grows like 1/β and is taken at
///   β − α);
/// * octahedral maps: steps with an end within 2Kα + 1e-6 of the square's
///   outer edge (the fold seams) are left out;
/// * cube, paraboloid, tennisball: the seams are the chart boundaries, so
///   "same chart" is the whole condition.
#[test]
fn forward_is_continuous() {
    let excess = Worst::per_mapping();
    let ratio = Worst::per_mapping();
    let start = prop_oneof![unit_direction(), near_special_direction()];
    proptest!(|(
        a in start,
        psi in 0.0f64..std::f64::consts::TAU,
        e in 4.0f64..9.0,
    )| {
        let alpha_target = 10f64.powf(-e);
        let b = rotate_away(unit_f64(a), psi, alpha_target).as_vec3();
        let (ua, ub) = (unit_f64(a), unit_f64(b));
        let alpha = angle(ua, ub);
        for (k, m) in AnyMapping::ALL.into_iter().enumerate() {
            let ca = check_seen(m, m.forward(a), ua)?;
            let cb = check_seen(m, m.forward(b), ub)?;
            let (Some(ca), Some(cb)) = (ca, cb) else {
                continue;
            };
            if ca.chart != cb.chart {
                continue;
            }
            let singular_distance = |d: DVec3| match m {
                AnyMapping::LatLong => d.x.hypot(d.y),
                AnyMapping::SphereMap | AnyMapping::SphereMapGl | AnyMapping::Angular => {
                    beta(m, d)
                }
                _ => PI,
            };
            let nearest = singular_distance(ua).min(singular_distance(ub)) - alpha;
            if nearest <= alpha {
                continue;
            }
            let near = if nearest == singular_distance(ua) - alpha { ua } else { ub };
            // K at the point of the step nearest the singularity.
            let kk = match m {
                AnyMapping::LatLong => (1.0 / PI).max(1.0 / (2.0 * PI * nearest)),
                AnyMapping::SphereMap | AnyMapping::SphereMapGl => {
                    0.25f64.max(1.0 / (4.0 * (0.5 * nearest).sin()))
                }
                AnyMapping::Angular => angular_stretch(nearest),
                _ => stretch(m, near),
            };
            if matches!(m, AnyMapping::Octahedral | AnyMapping::EqualAreaOctahedral) {
                let margin = 2.0 * kk * alpha + 1e-6;
                let near_edge = |c: ChartUv| {
                    [c.u, c.v].iter().any(|&x| f64::from(x).min(1.0 - f64::from(x)) < margin)
                };
                if near_edge(ca) || near_edge(cb) {
                    continue;
                }
            }
            let dist = if m == AnyMapping::LatLong {
                wrapped_distance(ca.u, cb.u).hypot(f64::from(ca.v) - f64::from(cb.v))
            } else {
                uv_distance(ca, cb)
            };
            excess.record(k, dist - kk * alpha, || format!("{} α = {alpha:.2e}", describe(a)));
            if alpha > 1e-6 {
                let what = || format!("{} α = {alpha:.2e}", describe(a));
                ratio.record(k, dist / (kk * alpha), what);
            }
            prop_assert!(
                dist <= kk * alpha + CONTINUITY_NOISE,
                "{m}: {} and {} ({alpha:e} rad apart): {ca:?} vs {cb:?}, \
                 |Δ| = {dist:e} > K·α = {:e}",
                describe(a), describe(b), kk * alpha
            );
        }
    });
    excess.report("continuity: worst |Δ(u, v)| − K·α");
    ratio.report("continuity: worst |Δ(u, v)| / (K·α) for α > 1e-6");
}

// ---------------------------------------------------------------------------------------------
// 5. Tennisball coverage
// ---------------------------------------------------------------------------------------------

/// Slack (in f32 ulps) allowed at the ends of the tennisball's ranges:
/// asin and atan2 round, and the f32 constants π/4 and 3π/4 are themselves
/// rounded, so a boundary direction can land an ulp or two outside.
const TENNISBALL_RANGE_ULPS: u64 = 2;

/// Checks the corrected tennisball at `d`: the chart is the one the
/// selection rule picks for normalize(d), and the unclamped angles are in
/// the printed ranges (up to [`TENNISBALL_RANGE_ULPS`]).
fn check_tennisball(d: Vec3) -> Result<(), TestCaseError> {
    let n = envmap_core::normalize_direction(d).unwrap();
    let (chart, theta, phi) = tennisball::raw_angles(d).unwrap();
    let expected = if tennisball::selects_chart_0(n.x, n.y, n.z) {
        0
    } else {
        1
    };
    prop_assert_eq!(chart, expected, "{}", describe(d));
    prop_assert_eq!(envmap_core::Tennisball::forward(d).unwrap().chart, expected);
    let (q, h) = (
        std::f32::consts::FRAC_PI_4,
        3.0 * std::f32::consts::FRAC_PI_4,
    );
    let slack_theta = ulps_outside(theta, -q, q);
    let slack_phi = ulps_outside(phi, -h, h);
    prop_assert!(
        slack_theta <= TENNISBALL_RANGE_ULPS && slack_phi <= TENNISBALL_RANGE_ULPS,
        "{}: chart {chart}, θ = {theta:e} ({slack_theta} ulps out), \
         φ = {phi:e} ({slack_phi} ulps out)",
        describe(d)
    );
    Ok(())
}

/// Directions on the selection rule's boundaries (up to the rounding of
/// their construction): |b| = √2/2 with c ≥ 0, |a| = √2/2 with c ≤ 0, and
/// c = ±0, from a parameter t and signs.
fn tennisball_boundary_direction() -> impl Strategy<Value = Vec3> {
    (
        0u8..3,
        0.0f64..std::f64::consts::TAU,
        any::<bool>(),
        any::<bool>(),
    )
        .prop_map(|(kind, t, sa, sb)| {
            let s = 0.5f64.sqrt();
            let sign = |neg: bool| if neg { -1.0 } else { 1.0 };
            let d = match kind {
                // |b| = √2/2, c ≥ 0: (a, c) on a circle of radius √2/2.
                0 => DVec3::new(s * t.cos(), sign(sb) * s, s * t.sin().abs()),
                // |a| = √2/2, c ≤ 0.
                1 => DVec3::new(sign(sa) * s, s * t.cos(), -s * t.sin().abs()),
                // c = ±0: the equator.
                _ => DVec3::new(t.cos(), t.sin(), 0.0),
            };
            let v = d.as_vec3();
            if kind == 2 && sa {
                Vec3::new(v.x, v.y, -0.0)
            } else {
                v
            }
        })
}

/// Property 5: every direction lands in the chart the seed's selection rule
/// picks, with the corrected angles inside the printed ranges: random
/// directions, awkward ones, the axes and the selection boundaries.
#[test]
fn tennisball_covers_the_sphere() {
    for d in special_directions() {
        check_tennisball(d.as_vec3()).unwrap();
    }
    for d in [
        Vec3::X,
        Vec3::NEG_X,
        Vec3::Y,
        Vec3::NEG_Y,
        Vec3::Z,
        Vec3::NEG_Z,
    ] {
        check_tennisball(d).unwrap();
        check_tennisball(d * 1e-30).unwrap();
    }
    proptest!(|(d in prop_oneof![any_direction(), tennisball_boundary_direction()])| {
        check_tennisball(d)?;
    });
}

// ---------------------------------------------------------------------------------------------
// 6. Solid angles
// ---------------------------------------------------------------------------------------------

/// Property 6: over each mapping's atlas, the texel solid angles add up to
/// 4π, or to what a fisheye sees (relative 1e-4 is the contract; the error is printed), and none is
/// negative. Cell widths 1, 3, 16 and 64 (where the layout allows them; the
/// tennisball's 3:1 cells need widths divisible by 3: 3, 48, 192).
#[test]
fn texel_solid_angles_add_up_to_4pi() {
    let mut worst = 0.0f64;
    for m in AnyMapping::ALL {
        let atlas = m.atlas();
        let widths: &[u32] = if m == AnyMapping::Tennisball {
            &[3, 48, 192]
        } else {
            &[1, 2, 3, 16, 64]
        };
        let mut tested = 0;
        for &cw in widths {
            let Some((w, h)) = atlas.image_size_for_cell_width(cw) else {
                continue;
            };
            let mut sum = envmap_tests::Sum::default();
            let mut texels = 0u32;
            for y in 0..h {
                for x in 0..w {
                    let Some(t) = atlas.texel_to_chart(x, y, w, h) else {
                        continue;
                    };
                    let sa = m.texel_solid_angle(t.chart, t.i, t.j, t.w, t.h);
                    assert!(sa >= 0.0, "{m}: texel ({x}, {y}) of {w}×{h}: {sa}");
                    sum.add(sa);
                    texels += 1;
                }
            }
            let total = covered_solid_angle(m);
            let rel = (sum.value() - total).abs() / total;
            println!(
                "{m:>22} {w:>4}×{h:<4} ({texels:>6} texels): Σ = {:.17} rel err {rel:.2e}",
                sum.value()
            );
            worst = worst.max(rel);
            assert!(
                rel <= 1e-4,
                "{m} {w}×{h}: Σ = {} (rel err {rel:e})",
                sum.value()
            );
            tested += 1;
        }
        assert!(tested >= 3, "{m}: only {tested} sizes fit the layout");
    }
    println!("worst relative error of Σ texel solid angles: {worst:.2e}");
}

/// The solid angle `m` sees: 4π, or a fisheye's caps 2π(1 − cos k), computed here from the
/// field of view (the library's `seen_solid_angle` is checked against it).
fn covered_solid_angle(m: AnyMapping) -> f64 {
    let total = match m {
        AnyMapping::Fisheye(f) if !f.covers_sphere() => {
            let k = f.fov_degrees().to_radians() / 2.0;
            f64::from(f.chart_count()) * 2.0 * PI * (1.0 - k.cos())
        }
        _ => envmap_tests::FOUR_PI,
    };
    assert!((m.seen_solid_angle() - total).abs() <= 1e-14 * total, "{m}");
    total
}

/// Property 6, cube: a texel's solid angle equals the gnomonic area element
/// 4 du dv / (1 + sc² + tc²)^{3/2} integrated numerically (Gauss–Legendre),
/// for random texels of random grid sizes on every face.
#[test]
fn cube_texel_solid_angle_matches_integration() {
    let worst = std::cell::Cell::new(0.0f64);
    proptest!(|(face in 0u32..6, n in 1u32..300, fi in 0.0f64..1.0, fj in 0.0f64..1.0)| {
        let index = |f: f64| ((f * f64::from(n)) as u32).min(n - 1);
        let (i, j) = (index(fi), index(fj));
        let sa = AnyMapping::Cube.texel_solid_angle(face, i, j, n, n);
        let (u0, u1) = envmap_core::texel::texel_bounds(i, n);
        let (v0, v1) = envmap_core::texel::texel_bounds(j, n);
        let panels = 2 + 16 / n;
        let reference = integrate_2d(cube_area_element, u0, u1, v0, v1, panels);
        let rel = (sa - reference).abs() / reference;
        worst.set(worst.get().max(rel));
        prop_assert!(rel <= 1e-12, "face {face} texel ({i}, {j}) of {n}²: {sa} vs {reference}");
    });
    println!(
        "cube texel solid angle vs integration: worst rel diff {:.2e}",
        worst.get()
    );
}

// ---------------------------------------------------------------------------------------------
// 7. Bad input
// ---------------------------------------------------------------------------------------------

/// Property 7, forward: a NaN or ±Inf in any component, or the zero vector
/// with any signs, gives `None` (also through a [`Framed`]).
#[test]
fn forward_rejects_bad_directions() {
    for sx in [0.0f32, -0.0] {
        for sy in [0.0f32, -0.0] {
            for sz in [0.0f32, -0.0] {
                for m in AnyMapping::ALL {
                    assert_eq!(m.forward(Vec3::new(sx, sy, sz)), None, "{m}");
                    let f = Framed::new(m, Frame::Y_UP_RH);
                    assert_eq!(f.forward(Vec3::new(sx, sy, sz)), None, "{m}");
                }
            }
        }
    }
    let bad = prop_oneof![
        Just(f32::NAN),
        Just(-f32::NAN),
        Just(f32::INFINITY),
        Just(f32::NEG_INFINITY)
    ];
    proptest!(|(d in any_direction(), which in 0usize..3, b in bad, all in any::<bool>())| {
        let mut a = d.to_array();
        a[which] = b;
        if all {
            a = [b; 3];
        }
        let d = Vec3::from_array(a);
        for m in AnyMapping::ALL {
            prop_assert_eq!(m.forward(d), None, "{}: {:?}", m, d);
            prop_assert_eq!(Framed::new(m, Frame::Y_UP_LH).forward(d), None, "{}: {:?}", m, d);
        }
    });
}

/// Property 7, inverse: `None` for a chart out of range, NaN u or v, u or v
/// outside [0, 1], and points of a disk chart outside the disk.
#[test]
fn inverse_rejects_bad_points() {
    let outside = prop_oneof![
        Just(f32::NAN),
        Just(f32::INFINITY),
        Just(f32::NEG_INFINITY),
        Just((-0.0f32).next_down()),
        Just(1.0f32.next_up()),
        -1e30f32..-1e-30,
        1.0000001f32..1e30,
    ];
    proptest!(|(
        u in 0.0f32..=1.0,
        v in 0.0f32..=1.0,
        bad in outside,
        chart in 0u32..6,
        extra in 0u32..100,
    )| {
        for m in AnyMapping::ALL {
            let n = m.chart_count();
            let c = chart % n;
            for cc in [n, n + extra, u32::MAX] {
                prop_assert_eq!(m.inverse(ChartUv::new(cc, u, v)), None, "{}", m);
            }
            prop_assert_eq!(m.inverse(ChartUv::new(c, bad, v)), None, "{}: u = {}", m, bad);
            prop_assert_eq!(m.inverse(ChartUv::new(c, u, bad)), None, "{}: v = {}", m, bad);
            prop_assert_eq!(m.inverse(ChartUv::new(c, bad, bad)), None, "{}", m);
            // The contract: inverse is defined exactly on in_chart.
            prop_assert_eq!(
                m.inverse(ChartUv::new(c, u, v)).is_some(),
                m.in_chart(c, u, v),
                "{}: ({}, {})", m, u, v
            );
        }
        // The disks: in_chart is the closed disk r ≤ 1.
        for m in AnyMapping::ALL.into_iter().filter(|m| m.has_disk_charts()) {
            let c = chart % m.chart_count();
            let r = (2.0 * f64::from(u) - 1.0).hypot(2.0 * f64::from(v) - 1.0);
            if r > 1.0 + 1e-6 {
                prop_assert!(!m.in_chart(c, u, v), "{}: ({}, {}) r = {}", m, u, v, r);
            } else if r < 1.0 - 1e-6 {
                prop_assert!(m.in_chart(c, u, v), "{}: ({}, {}) r = {}", m, u, v, r);
            }
        }
    });
}

/// Property 7, texel indices: `texel_index(1.0, n)` is `n − 1`, and any `u`
/// (NaN, negative, huge, ±Inf) gives an index below `n`; inside [0, 1] the
/// index is floor(u·n) up to the rounding of the f32 product.
#[test]
fn texel_index_stays_in_range() {
    for n in [1u32, 2, 3, 7, 1000, 4096, 16_777_216, 16_777_217, u32::MAX] {
        assert_eq!(texel_index(1.0, n), n - 1, "n = {n}");
        assert_eq!(texel_index(0.0, n), 0);
        assert_eq!(texel_index(-0.0, n), 0);
    }
    let u_any = prop_oneof![
        4 => 0.0f32..=1.0,
        1 => Just(f32::NAN),
        1 => Just(f32::INFINITY),
        1 => Just(f32::NEG_INFINITY),
        1 => any::<f32>(),
        1 => (0u32..64).prop_map(|k| 1.0f32 - k as f32 * f32::EPSILON / 2.0),
    ];
    proptest!(|(u in u_any, n in prop_oneof![1u32..5000, any::<u32>().prop_map(|n| n.max(1))])| {
        let i = texel_index(u, n);
        prop_assert!(i < n, "texel_index({}, {}) = {}", u, n, i);
        // For n ≤ 2^24, n is exact in f32 and the product's rounding moves
        // it by at most one texel.
        if (0.0..=1.0).contains(&u) && n <= 1 << 24 {
            let exact = (f64::from(u) * f64::from(n)).floor().min(f64::from(n - 1));
            prop_assert!(
                (f64::from(i) - exact).abs() <= 1.0,
                "texel_index({}, {}) = {} vs {}", u, n, i, exact
            );
        }
    });
}

// ---------------------------------------------------------------------------------------------
// 8. Frames
// ---------------------------------------------------------------------------------------------

/// Extra round-trip error allowed through a [`Frame`]: the rotation is
/// applied in f32 both ways, and a matrix from a quaternion is orthogonal
/// only to ~1e-7. About 2× the worst excess over the bare bound in a long
/// run (PROPTEST_CASES=200000).
const FRAME_EXTRA: f64 = 8e-7;

/// Property 8: through every preset and random rotations, `Framed` round
/// trips direction → coordinates → direction within the bare mapping's
/// bound (at the canonical direction) plus [`FRAME_EXTRA`].
#[test]
fn framed_round_trip() {
    assert_eq!(Frame::Y_UP_RH.to_canonical(Vec3::Y), Vec3::Z);
    let worst = Worst::per_mapping();
    let excess = Worst::per_mapping();
    let quat = (-1.0f32..1.0, -1.0f32..1.0, -1.0f32..1.0, -1.0f32..1.0)
        .prop_filter_map("zero quaternion", |(x, y, z, w)| {
            Frame::from_quat(Quat::from_xyzw(x, y, z, w))
        });
    let frame = prop_oneof![
        1 => Just(Frame::IDENTITY),
        1 => Just(Frame::Z_UP_RH),
        1 => Just(Frame::Y_UP_RH),
        1 => Just(Frame::Y_UP_LH),
        4 => quat,
    ];
    proptest!(|(d in any_direction(), frame in frame)| {
        let unit = unit_f64(d);
        let canonical = frame.matrix().as_dmat3() * unit;
        for (k, m) in AnyMapping::ALL.into_iter().enumerate() {
            let f = Framed::new(m, frame);
            let Some(c) = check_seen(m, f.forward(d), canonical / canonical.length())? else {
                continue;
            };
            prop_assert!(
                f.in_chart(c.chart, c.u, c.v),
                "{m}: {} through {frame:?} -> {c:?}", describe(d)
            );
            let back = f.inverse(c).unwrap();
            let err = angle(unit, back.as_dvec3());
            let bound =
                direction_round_trip_bound(m, canonical / canonical.length()) + FRAME_EXTRA;
            worst.record(k, err, || format!("{} through {:?}", describe(d), frame.matrix()));
            let what = || format!("{} through {:?}", describe(d), frame.matrix());
            excess.record(k, err - (bound - FRAME_EXTRA), what);
            prop_assert!(
                err <= bound,
                "{m}: {} through {frame:?}: {err:e} > {bound:e}", describe(d)
            );
        }
    });
    worst.report("framed round trip: worst error (rad)");
    excess.report("framed round trip: worst error − bare bound (rad)");
}

// ---------------------------------------------------------------------------------------------
// 9. AnyMapping names
// ---------------------------------------------------------------------------------------------

/// Property 9: every name of `AnyMapping::NAMES` parses to the variant at
/// the same position of `ALL`, in any letter case, and `Display` gives the
/// name back.
#[test]
fn any_mapping_names_round_trip() {
    for (m, name) in AnyMapping::ALL.into_iter().zip(AnyMapping::NAMES) {
        assert_eq!(name.parse::<AnyMapping>(), Ok(m));
        assert_eq!(name.to_uppercase().parse::<AnyMapping>(), Ok(m));
        assert_eq!(m.to_string(), name);
        assert_eq!(m.to_string().parse::<AnyMapping>(), Ok(m));
        assert_eq!(m.name(), name);
    }
    assert!("no-such-mapping".parse::<AnyMapping>().is_err());
    assert!("".parse::<AnyMapping>().is_err());
}
