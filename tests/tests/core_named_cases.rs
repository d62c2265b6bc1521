//! Named cases of envmap-core: the cube's face table row by row, its edges,
//! corners, exact ties and signed zeros; the latlong poles; the sphere map's
//! singular direction; the angular map's centre, 90° ring and singular
//! direction (with the SIMD tiers beside the core); the tennisball seed
//! erratum; the frame presets; the equi-angular cube map against the cube.
//!
//! The generic properties are in `core_contract.rs`; these are the inputs
//! the design calls out by name, with their exact expected outputs where the
//! arithmetic is exact (dyadic inputs).

use envmap_core::cube::select_face;
use envmap_core::sphere_map::uv_from_normal;
use envmap_core::tennisball;
use envmap_core::{
    Angular, AnyMapping, Atlas, ChartUv, Cube, CubeFace, DualParaboloid, Eac, EqualAreaOctahedral,
    Frame, Framed, LatLong, Mapping, Octahedral, SphereMap, Tennisball,
};
use envmap_simd::{forward_slice, inverse_slice, Exact, Fast, Fine, Tier};
use envmap_tests::{angle_f32, check_simd_forward, check_simd_inverse, SplitMix64};
use glam::Vec3;

fn v(x: f32, y: f32, z: f32) -> Vec3 {
    Vec3::new(x, y, z)
}

// ---------------------------------------------------------------------------------------------
// Cube
// ---------------------------------------------------------------------------------------------

/// The cube face table (`docs/conventions.md`), written out independently of envmap-core:
/// (face, sc, tc, |ma|) for a direction, with the z-over-y-over-x tie rule
/// and the major component's sign bit picking the face.
fn table_face(d: Vec3) -> (u32, f32, f32, f32) {
    let (x, y, z) = (d.x, d.y, d.z);
    let (ax, ay, az) = (x.abs(), y.abs(), z.abs());
    if az >= ax && az >= ay {
        if z.is_sign_negative() {
            (5, -x, -y, az)
        } else {
            (4, x, -y, az)
        }
    } else if ay >= ax {
        if y.is_sign_negative() {
            (3, x, -z, ay)
        } else {
            (2, x, z, ay)
        }
    } else if x.is_sign_negative() {
        (1, z, -y, ax)
    } else {
        (0, -z, -y, ax)
    }
}

/// The expected chart point of `d` from [`table_face`]: s = (sc/|ma| + 1)/2,
/// t = (tc/|ma| + 1)/2 (exact for the dyadic inputs used here).
fn table_point(d: Vec3) -> ChartUv {
    let (face, sc, tc, ma) = table_face(d);
    ChartUv::new(face, 0.5 * (sc / ma + 1.0), 0.5 * (tc / ma + 1.0))
}

#[test]
fn cube_table_rows() {
    // One direction per row, distinct magnitudes 4 > 2 > 1, checked against
    // the row by hand: (direction, face, s, t).
    let rows = [
        (v(4.0, 1.0, 2.0), 0, 0.25, 0.375),  // +x: sc = −z, tc = −y
        (v(-4.0, 1.0, 2.0), 1, 0.75, 0.375), // −x: sc = +z, tc = −y
        (v(1.0, 4.0, 2.0), 2, 0.625, 0.75),  // +y: sc = +x, tc = +z
        (v(1.0, -4.0, 2.0), 3, 0.625, 0.25), // −y: sc = +x, tc = −z
        (v(1.0, 2.0, 4.0), 4, 0.625, 0.25),  // +z: sc = +x, tc = −y
        (v(1.0, 2.0, -4.0), 5, 0.375, 0.25), // −z: sc = −x, tc = −y
    ];
    for (d, face, s, t) in rows {
        assert_eq!(Cube::forward(d), Some(ChartUv::new(face, s, t)), "{d}");
        assert_eq!(table_point(d), ChartUv::new(face, s, t), "{d}");
        let back = Cube::inverse(ChartUv::new(face, s, t)).unwrap();
        assert!(angle_f32(back, d) < 1e-7, "{d}: {back}");
    }
    // Every row with every sign of the two minor components, and minor
    // components in either order.
    for major in 0..3 {
        for sign in [1.0f32, -1.0] {
            for (a, b) in [(1.0f32, 2.0f32), (2.0, 1.0), (3.0, 0.5)] {
                for (sa, sb) in [(1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)] {
                    let mut c = [0.0f32; 3];
                    c[major] = sign * 4.0;
                    c[(major + 1) % 3] = sa * a;
                    c[(major + 2) % 3] = sb * b;
                    let d = Vec3::from_array(c);
                    assert_eq!(Cube::forward(d), Some(table_point(d)), "{d}");
                    let face = CubeFace::from_index(table_point(d).chart).unwrap();
                    assert_eq!(face.axis()[major], sign, "{d}");
                    assert_eq!(select_face(d).map(|f| f.0), Some(face));
                }
            }
        }
    }
}

#[test]
fn cube_face_centres_and_corners_of_faces() {
    for face in CubeFace::ALL {
        let c = Cube::forward(face.axis()).unwrap();
        assert_eq!(c, ChartUv::new(face as u32, 0.5, 0.5), "{}", face.name());
        assert_eq!(Cube::inverse(c), Some(face.axis()));
        // The four corners of each face invert to cube corners (±1, ±1, ±1)/√3.
        for (s, t) in [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)] {
            let d = Cube::inverse(ChartUv::new(face as u32, s, t)).unwrap();
            for k in 0..3 {
                assert!(
                    (d[k].abs() - 1.0 / 3f32.sqrt()).abs() < 1e-7,
                    "{}: {d}",
                    face.name()
                );
            }
            assert!(face.axis().dot(d) > 0.5);
        }
    }
}

/// Exact ties between two components (the cube's edges): the z-over-y-over-x
/// rule decides, for every sign combination, with the third component
/// smaller, zero or negative zero; (s, t) lands exactly on the face's edge.
#[test]
fn cube_edges_exact_ties() {
    let smalls = [0.5f32, -0.5, 0.0, -0.0, 1e-30, -1e-45];
    for (i, j) in [(0usize, 1usize), (0, 2), (1, 2)] {
        let k = 3 - i - j;
        for si in [1.0f32, -1.0] {
            for sj in [1.0f32, -1.0] {
                for small in smalls {
                    for scale in [1.0f32, 1e-30, 3e38] {
                        let mut c = [0.0f32; 3];
                        c[i] = si * scale;
                        c[j] = sj * scale;
                        c[k] = small * scale.min(1.0);
                        let d = Vec3::from_array(c);
                        let got = Cube::forward(d).unwrap();
                        assert_eq!(got, table_point(d), "{d:?}");
                        // The later axis of the pair (z over y over x) wins.
                        let face = CubeFace::from_index(got.chart).unwrap();
                        assert_eq!(face.axis()[j], sj, "{d:?} -> {}", face.name());
                        // On the edge: s or t is exactly 0 or 1.
                        assert!(
                            [got.u, got.v].iter().any(|&x| x == 0.0 || x == 1.0),
                            "{d:?} -> {got:?}"
                        );
                    }
                }
            }
        }
    }
    // The examples of the tie rule, by hand.
    let face = |x, y, z| Cube::forward(v(x, y, z)).unwrap().chart;
    assert_eq!(face(1.0, 1.0, 0.5), 2); // y over x
    assert_eq!(face(-1.0, -1.0, 0.5), 3);
    assert_eq!(face(1.0, 0.5, 1.0), 4); // z over x
    assert_eq!(face(-1.0, 0.5, -1.0), 5);
    assert_eq!(face(0.5, 1.0, 1.0), 4); // z over y
    assert_eq!(face(0.5, -1.0, -1.0), 5);
}

/// The corners (three-way ties) all go to a z face, at a corner of it.
#[test]
fn cube_corners() {
    for sx in [1.0f32, -1.0] {
        for sy in [1.0f32, -1.0] {
            for sz in [1.0f32, -1.0] {
                for scale in [1.0f32, 1e-40, f32::MAX] {
                    let d = v(sx, sy, sz) * scale;
                    let c = Cube::forward(d).unwrap();
                    assert_eq!(c.chart, if sz > 0.0 { 4 } else { 5 }, "{d}");
                    assert_eq!(c, table_point(d));
                    assert!(c.u == 0.0 || c.u == 1.0, "{d} -> {c:?}");
                    assert!(c.v == 0.0 || c.v == 1.0, "{d} -> {c:?}");
                    let back = Cube::inverse(c).unwrap();
                    assert!(angle_f32(back, d) < 1e-7, "{d}");
                }
            }
        }
    }
    // +z face corner (s, t) = (0, 0) is (−1, +1, +1)/√3.
    let d = Cube::inverse(ChartUv::new(4, 0.0, 0.0)).unwrap();
    assert!(angle_f32(d, v(-1.0, 1.0, 1.0)) < 1e-7);
}

/// Signed zeros: the face is picked by the major component's sign bit, and
/// zeros in the minor components give the face centre line exactly.
#[test]
fn cube_signed_zeros() {
    for (d, face) in [
        (v(1.0, 0.0, -0.0), 0),
        (v(-1.0, -0.0, 0.0), 1),
        (v(-0.0, 1.0, -0.0), 2),
        (v(0.0, -1.0, 0.0), 3),
        (v(-0.0, -0.0, 1.0), 4),
        (v(0.0, 0.0, -1.0), 5),
        (v(-0.0, 0.0, -1e-45), 5),
        (v(0.0, -0.0, 1e-45), 4),
    ] {
        assert_eq!(
            Cube::forward(d),
            Some(ChartUv::new(face, 0.5, 0.5)),
            "{d:?}"
        );
    }
    for sx in [0.0f32, -0.0] {
        for sy in [0.0f32, -0.0] {
            for sz in [0.0f32, -0.0] {
                assert_eq!(Cube::forward(v(sx, sy, sz)), None);
                assert_eq!(select_face(v(sx, sy, sz)), None);
            }
        }
    }
}

/// Across a face edge the two faces agree, as in GL's seamless cube maps:
/// the named edges of the horizontal cross (−x +z +x −z across, +y above and
/// −y below +z), then every edge of every face.
#[test]
fn cube_edges_are_seamless() {
    // (face A, its edge point (s, t) as a function of p, face B, B's point).
    type Edge = (u32, fn(f32) -> (f32, f32), u32, fn(f32) -> (f32, f32));
    let named: [Edge; 6] = [
        (4, |p| (1.0, p), 0, |p| (0.0, p)), // +z right = +x left
        (0, |p| (1.0, p), 5, |p| (0.0, p)), // +x right = −z left
        (5, |p| (1.0, p), 1, |p| (0.0, p)), // −z right = −x left
        (1, |p| (1.0, p), 4, |p| (0.0, p)), // −x right = +z left
        (2, |p| (p, 1.0), 4, |p| (p, 0.0)), // +y bottom = +z top
        (3, |p| (p, 0.0), 4, |p| (p, 1.0)), // −y top = +z bottom
    ];
    for (fa, pa, fb, pb) in named {
        for p in [0.0f32, 0.125, 0.3, 0.5, 0.77, 1.0] {
            let (sa, ta) = pa(p);
            let (sb, tb) = pb(p);
            let da = Cube::inverse(ChartUv::new(fa, sa, ta)).unwrap();
            let db = Cube::inverse(ChartUv::new(fb, sb, tb)).unwrap();
            assert!(
                angle_f32(da, db) < 1e-7,
                "face {fa} ({sa}, {ta}) vs face {fb} ({sb}, {tb})"
            );
            // Stepping off the edge into either face gives that face's
            // coordinates of the same edge point.
            for (face, s, t) in [(fa, sa, ta), (fb, sb, tb)] {
                let axis = CubeFace::from_index(face).unwrap().axis();
                let inside = da + axis * 1e-5;
                let c = Cube::forward(inside).unwrap();
                assert_eq!(c.chart, face, "{inside}");
                assert!(
                    (c.u - s).abs() < 2e-5 && (c.v - t).abs() < 2e-5,
                    "{c:?} vs ({s}, {t})"
                );
            }
        }
    }
    // Every edge of every face has exactly one partner edge on another face
    // with the same directions (possibly running the other way).
    let edge_point = |e: u32, p: f32| match e {
        0 => (p, 0.0),
        1 => (1.0, p),
        2 => (p, 1.0),
        _ => (0.0, p),
    };
    for fa in 0..6 {
        for ea in 0..4 {
            let mut partners = 0;
            for fb in (0..6).filter(|&f| f != fa) {
                for eb in 0..4 {
                    for reversed in [false, true] {
                        let matches = [0.1f32, 0.4, 0.9].iter().all(|&p| {
                            let (sa, ta) = edge_point(ea, p);
                            let (sb, tb) = edge_point(eb, if reversed { 1.0 - p } else { p });
                            let da = Cube::inverse(ChartUv::new(fa, sa, ta)).unwrap();
                            let db = Cube::inverse(ChartUv::new(fb, sb, tb)).unwrap();
                            angle_f32(da, db) < 1e-6
                        });
                        partners += u32::from(matches);
                    }
                }
            }
            assert_eq!(partners, 1, "face {fa} edge {ea}");
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Latlong poles and seam
// ---------------------------------------------------------------------------------------------

#[test]
fn latlong_axes_poles_and_seam() {
    let cases = [
        (v(1.0, 0.0, 0.0), 0.0, 0.5),
        (v(0.0, 1.0, 0.0), 0.25, 0.5),
        (v(-1.0, 0.0, 0.0), 0.5, 0.5),
        (v(0.0, -1.0, 0.0), 0.75, 0.5),
        (v(0.0, 0.0, 1.0), 0.0, 0.0),
        (v(0.0, 0.0, -1.0), 0.0, 1.0),
        // The documented pole rule: atan2(0, −0) = π gives u = 1/2.
        (v(-0.0, 0.0, 1.0), 0.5, 0.0),
        (v(-0.0, 0.0, -1.0), 0.5, 1.0),
        // Poles at any scale.
        (v(0.0, 0.0, 1e-45), 0.0, 0.0),
        (v(0.0, 0.0, -f32::MAX), 0.0, 1.0),
    ];
    for (d, u, vv) in cases {
        let c = LatLong::forward(d).unwrap();
        assert_eq!((c.chart, c.u, c.v), (0, u, vv), "{d:?}");
    }
    // Every u on the top and bottom rows is the pole.
    for i in 0..=64 {
        let u = i as f32 / 64.0;
        let top = LatLong::inverse(ChartUv::new(0, u, 0.0)).unwrap();
        let bottom = LatLong::inverse(ChartUv::new(0, u, 1.0)).unwrap();
        assert!(angle_f32(top, Vec3::Z) < 1e-7, "u = {u}: {top}");
        assert!(angle_f32(bottom, Vec3::NEG_Z) < 2e-7, "u = {u}: {bottom}");
    }
    // Just off the poles, v is the polar angle / π at full relative accuracy
    // (down to angles whose square is still a normal f32), and within the
    // round-trip accuracy below that.
    for theta in [1e-3f64, 1e-10, 1e-15, 1e-30] {
        let d = v(theta as f32, 0.0, 1.0);
        let c = LatLong::forward(d).unwrap();
        let v_theta = f64::from(c.v) * std::f64::consts::PI;
        if theta >= 1e-15 {
            assert!((v_theta / theta - 1.0).abs() < 1e-6, "{theta:e}: {c:?}");
        } else {
            assert!((v_theta - theta).abs() < 1e-7, "{theta:e}: {c:?}");
        }
        let c = LatLong::forward(v(0.0, theta as f32, -1.0)).unwrap();
        assert_eq!(c.u, 0.25);
        // v is near 1 here, where one f32 step is 6e-8 (π × that in angle).
        assert!(((1.0 - f64::from(c.v)) * std::f64::consts::PI - theta).abs() < 4e-7);
    }
    // The seam: just above it u is near 0, just below near 1, never 1 itself.
    for y in [1e-3f32, 1e-20, 1e-45] {
        assert!(LatLong::forward(v(1.0, y, 0.3)).unwrap().u < 1e-3);
        let below = LatLong::forward(v(1.0, -y, 0.3)).unwrap().u;
        assert!(below > 0.999 || below == 0.0, "{y}: {below}");
        assert!(below < 1.0);
    }
    // The seed's quadrant erratum: opposite directions get different u.
    let a = LatLong::forward(v(1.0, 1.0, 0.0)).unwrap();
    let b = LatLong::forward(v(-1.0, -1.0, 0.0)).unwrap();
    assert_eq!((a.u, b.u), (0.125, 0.625));
}

// ---------------------------------------------------------------------------------------------
// Sphere map: centre, rim and the singular direction
// ---------------------------------------------------------------------------------------------

#[test]
fn sphere_map_singular_direction() {
    // Points forward puts outside the disk, reported after the other checks.
    let mut outside = Vec::new();
    for (m, toward, away) in [
        (SphereMap::CLASS, Vec3::NEG_Z, Vec3::Z),
        (SphereMap::OPENGL, Vec3::Z, Vec3::NEG_Z),
    ] {
        // The viewer's direction is the centre, both ways, at any scale.
        for s in [1.0f32, 1e-45, f32::MAX] {
            assert_eq!(m.forward(toward * s), Some(ChartUv::new(0, 0.5, 0.5)));
            // The singular direction itself: the documented rim point.
            assert_eq!(m.forward(away * s), Some(ChartUv::new(0, 1.0, 0.5)));
        }
        assert_eq!(m.inverse(ChartUv::new(0, 0.5, 0.5)), Some(toward));
        // The rim points that are exact in binary invert to the singular
        // direction exactly; other rim points, rounded to f32, lie up to an
        // ulp inside the rim, i.e. within √(8·1.2e-7) ≈ 1e-3 rad of it.
        for (u, vv) in [(1.0, 0.5), (0.0, 0.5), (0.5, 0.0), (0.5, 1.0)] {
            assert!(m.in_chart(0, u, vv), "({u}, {vv})");
            let d = m.inverse(ChartUv::new(0, u, vv)).unwrap();
            assert!(angle_f32(d, away) == 0.0, "({u}, {vv}): {d}");
        }
        for j in 0..64 {
            let t = f64::from(j) * std::f64::consts::TAU / 64.0;
            let (u, vv) = ((0.5 + 0.5 * t.cos()) as f32, (0.5 + 0.5 * t.sin()) as f32);
            if let Some(d) = m.inverse(ChartUv::new(0, u, vv)) {
                assert!(angle_f32(d, away) < 1.2e-3, "({u}, {vv}): {d}");
            }
        }
        // Near the singular direction: at angle β the point is at r = cos(β/2)
        // (1 − r ≈ β²/8), at the direction's own azimuth, and inside the disk.
        for k in 1..=12 {
            let beta = 10f64.powi(-k);
            for j in 0..8 {
                let az = f64::from(j) * std::f64::consts::FRAC_PI_4 + 0.1;
                let d = v(
                    (beta.sin() * az.cos()) as f32,
                    (beta.sin() * az.sin()) as f32,
                    away.z * beta.cos() as f32,
                );
                let c = m.forward(d).unwrap();
                let (x, y) = (2.0 * f64::from(c.u) - 1.0, 2.0 * f64::from(c.v) - 1.0);
                let r = x.hypot(y);
                assert!(
                    (r - (0.5 * beta).cos()).abs() < 3e-7,
                    "β = {beta:e}: r = {r}"
                );
                let az_err = (y.atan2(x) - az + std::f64::consts::PI)
                    .rem_euclid(std::f64::consts::TAU)
                    - std::f64::consts::PI;
                let az_err = az_err.abs();
                assert!(az_err < 1e-6, "β = {beta:e}, azimuth {az}: {c:?}");
                if !m.in_chart(0, c.u, c.v) {
                    outside.push(format!(
                        "{}: {d:?} (β = {beta:e}) -> {c:?}",
                        Mapping::name(&m)
                    ));
                }
            }
        }
        // Perpendicular directions sit at r = √2/2.
        let c = m.forward(Vec3::X).unwrap();
        assert!((f64::from(2.0 * c.u - 1.0) - 0.5f64.sqrt()).abs() < 1e-7);
        assert_eq!(c.v, 0.5);
        // Corners hold no direction.
        for (u, vv) in [(0.0, 0.0), (1.0, 1.0), (0.1, 0.1)] {
            assert!(!m.in_chart(0, u, vv));
            assert_eq!(m.inverse(ChartUv::new(0, u, vv)), None);
        }
    }
    // The seed's short cut from the normal agrees with reflecting the viewer.
    for n in [v(0.3, -0.4, 0.5), v(-0.7, 0.1, 0.2), v(0.0, 0.0, 1.0)] {
        let n = n.normalize();
        let a = uv_from_normal(n).unwrap();
        let b = SphereMap::OPENGL
            .forward(envmap_core::reflect_view(n, Vec3::Z))
            .unwrap();
        assert!(
            (a.u - b.u).abs() < 1e-6 && (a.v - b.v).abs() < 1e-6,
            "{n}: {a:?} vs {b:?}"
        );
    }
    assert!(
        outside.is_empty(),
        "forward left the disk:\n{}",
        outside.join("\n")
    );
}

/// Forward's output must be inside the disk (`in_chart`, so that `inverse`
/// takes it back), also at the disks' rims: named inputs that land on the
/// rim up to rounding (the paraboloid's equator, the directions next to the
/// sphere maps' singular direction). All failures are listed at once.
#[test]
fn disk_maps_stay_inside_the_disk_at_the_rim() {
    let mut outside = Vec::new();
    let paraboloid = [
        (AnyMapping::DualParaboloid, v(1.0, 1.0, 0.0)),
        (AnyMapping::DualParaboloid, v(0.6, 0.8, 0.0)),
        (AnyMapping::DualParaboloid, v(1.0, 2.0, -0.0)),
        (AnyMapping::DualParaboloid, v(-3.0, 1.0, 1e-30)),
    ];
    let sphere = [AnyMapping::SphereMap, AnyMapping::SphereMapGl]
        .into_iter()
        .flat_map(|m| {
            let z = if m == AnyMapping::SphereMap {
                1.0f32
            } else {
                -1.0
            };
            [v(1e-20, 1e-20, z), v(1e-4, 1e-4, z), v(1.0, 1.0, 1e6 * z)].map(|d| (m, d))
        });
    let angular = [
        v(1e-20, 1e-20, -1.0),
        v(1e-4, 1e-4, -1.0),
        v(1.0, 1.0, -1e6),
        v(-3.0, 1e-30, -1e30),
        v(0.6, -0.8, -1e7),
    ]
    .map(|d| (AnyMapping::Angular, d));
    for (m, d) in paraboloid.into_iter().chain(sphere).chain(angular) {
        let c = m.forward(d).unwrap();
        if !m.in_chart(c.chart, c.u, c.v) || m.inverse(c).is_none() {
            outside.push(format!("{m}: forward({d:?}) = {c:?}"));
        }
    }
    assert!(
        outside.is_empty(),
        "outside the disk:\n{}",
        outside.join("\n")
    );
}

// ---------------------------------------------------------------------------------------------
// Angular map: centre, the 90° ring and the singular direction
// ---------------------------------------------------------------------------------------------

/// The angular map's closed form in f64, (u, v) for a direction d:
/// ρ = angle(d, +z)/π along the azimuth of (x, y), (u, v) = ((ρ cos φ + 1)/2, (ρ sin φ + 1)/2).
fn angular_closed_form(d: Vec3) -> (f64, f64) {
    let (x, y, z) = (f64::from(d.x), f64::from(d.y), f64::from(d.z));
    let s = x.hypot(y);
    let rho = s.atan2(z) / std::f64::consts::PI;
    let (c, sn) = if s == 0.0 { (1.0, 0.0) } else { (x / s, y / s) };
    (0.5 * (rho * c) + 0.5, 0.5 * (rho * sn) + 0.5)
}

#[test]
fn angular_centre_ring_and_singular_direction() {
    let m = Angular;
    // The view axis is the centre, and −z (with any signs of zero in x and
    // y) the documented rim point (1, ½), at any scale.
    for s in [1.0f32, 1e-45, 1e-30, 3e38] {
        assert_eq!(
            Angular::forward(Vec3::Z * s),
            Some(ChartUv::new(0, 0.5, 0.5))
        );
        for (x, y) in [(0.0f32, 0.0f32), (-0.0, 0.0), (0.0, -0.0), (-0.0, -0.0)] {
            assert_eq!(
                Angular::forward(v(x, y, -s)),
                Some(ChartUv::new(0, 1.0, 0.5)),
                "({x}, {y}, -{s})"
            );
            assert_eq!(
                Angular::forward(v(x, y, s)),
                Some(ChartUv::new(0, 0.5, 0.5))
            );
        }
    }
    assert_eq!(Angular::inverse(ChartUv::new(0, 0.5, 0.5)), Some(Vec3::Z));
    // The 90° ring (z = 0) is the circle of radius ½, exactly on the axes.
    for (d, u, vv) in [
        (Vec3::X, 0.75, 0.5),
        (Vec3::NEG_X, 0.25, 0.5),
        (Vec3::Y, 0.5, 0.75),
        (Vec3::NEG_Y, 0.5, 0.25),
    ] {
        for s in [1.0f32, 1e-40, 2e38] {
            assert_eq!(Angular::forward(d * s), Some(ChartUv::new(0, u, vv)), "{d}");
        }
        let back = Angular::inverse(ChartUv::new(0, u, vv)).unwrap();
        assert!(angle_f32(back, d) < 1e-7, "({u}, {vv}) -> {back}");
    }
    for j in 0..16 {
        let az = f64::from(j) * std::f64::consts::TAU / 16.0 + 0.01;
        let d = v(az.cos() as f32, az.sin() as f32, 0.0);
        let c = Angular::forward(d).unwrap();
        let r = (2.0 * f64::from(c.u) - 1.0).hypot(2.0 * f64::from(c.v) - 1.0);
        // Two f32 steps of u and v, which are 6e-8 above ½.
        assert!((r - 0.5).abs() < 1.2e-7, "{d}: r = {r}");
    }
    // Every rim point inverts to −z: exactly where the point is exact in
    // binary, within π times its f32 distance from the rim elsewhere.
    for (u, vv) in [(1.0, 0.5), (0.0, 0.5), (0.5, 0.0), (0.5, 1.0)] {
        assert!(m.in_chart(0, u, vv));
        assert_eq!(Angular::inverse(ChartUv::new(0, u, vv)), Some(Vec3::NEG_Z));
    }
    for j in 0..64 {
        let t = f64::from(j) * std::f64::consts::TAU / 64.0;
        let (u, vv) = ((0.5 + 0.5 * t.cos()) as f32, (0.5 + 0.5 * t.sin()) as f32);
        if let Some(d) = Angular::inverse(ChartUv::new(0, u, vv)) {
            assert!(angle_f32(d, Vec3::NEG_Z) < 4e-7, "({u}, {vv}): {d}");
        }
    }
    // Next to the singular direction: at angle β the point is at
    // ρ = 1 − β/π, at the direction's own azimuth, inside the disk (an
    // equidistant map does not squeeze the rim as a sphere map does).
    for k in 1..=12 {
        let beta = 10f64.powi(-k);
        for j in 0..8 {
            let az = f64::from(j) * std::f64::consts::FRAC_PI_4 + 0.1;
            let d = v(
                (beta.sin() * az.cos()) as f32,
                (beta.sin() * az.sin()) as f32,
                -beta.cos() as f32,
            );
            let c = Angular::forward(d).unwrap();
            assert!(m.in_chart(0, c.u, c.v), "β = {beta:e}: {c:?}");
            let (x, y) = (2.0 * f64::from(c.u) - 1.0, 2.0 * f64::from(c.v) - 1.0);
            let r = x.hypot(y);
            // A few f32 steps of u and v in the radius, the azimuth and the
            // round trip.
            let want = 1.0 - beta / std::f64::consts::PI;
            assert!(
                (r - want).abs() < 2.5e-7,
                "β = {beta:e}: r = {r}, want {want}"
            );
            let az_err = ((y.atan2(x) - az + std::f64::consts::PI)
                .rem_euclid(std::f64::consts::TAU)
                - std::f64::consts::PI)
                .abs();
            assert!(az_err < 1e-6, "β = {beta:e}, azimuth {az}: {c:?}");
            let back = Angular::inverse(c).unwrap();
            assert!(angle_f32(back, d) < 1e-6, "β = {beta:e}: {d} -> {back}");
        }
    }
    // Against the closed form at named directions (exact: the axes, the
    // ring, 60° and 120° from +z, the diagonals).
    let h = 0.5f32;
    let r3 = 0.75f32.sqrt();
    let named = [
        v(r3, 0.0, h),
        v(0.0, -r3, -h),
        v(1.0, 1.0, 0.0),
        v(-1.0, 1.0, 1.0),
        v(1.0, -1.0, -1.0),
        v(1e-30, 0.0, -1.0),
        v(0.0, -1e-38, -1.0),
        v(-1e-45, 1e-45, -1.0),
        v(3e-39, 1e-39, 1.0),
    ];
    for d in named {
        let c = Angular::forward(d).unwrap();
        let (u, vv) = angular_closed_form(d);
        let e = (f64::from(c.u) - u).abs().max((f64::from(c.v) - vv).abs());
        // The bound is two f32 steps.
        assert!(e < 1.2e-7, "{d}: {c:?} vs ({u}, {vv})");
    }
    // The SIMD tiers agree with the core on every named input, forward and
    // inverse (the tier's bound, and the documented points exactly).
    let mut dirs = vec![
        Vec3::Z,
        Vec3::NEG_Z,
        v(-0.0, -0.0, -1.0),
        v(0.0, -0.0, 1e-30),
        Vec3::X,
        Vec3::NEG_X,
        Vec3::Y,
        Vec3::NEG_Y,
    ];
    dirs.extend(named);
    let points = [
        ChartUv::new(0, 0.5, 0.5),
        ChartUv::new(0, 0.75, 0.5),
        ChartUv::new(0, 0.5, 0.75),
        ChartUv::new(0, 1.0, 0.5),
        ChartUv::new(0, 0.0, 0.5),
        ChartUv::new(0, 0.5, 0.0),
        ChartUv::new(0, 0.5, 1.0),
        ChartUv::new(0, 0.0, 0.0),
        ChartUv::new(1, 0.5, 0.5),
    ];
    fn tier<T: Tier>(dirs: &[Vec3], points: &[ChartUv]) {
        let m = AnyMapping::Angular;
        let mut out = vec![ChartUv::default(); dirs.len()];
        forward_slice::<_, T>(&m, dirs, &mut out);
        for (d, got) in dirs.iter().zip(&out) {
            check_simd_forward(m, T::NAME, *d, *got).unwrap();
        }
        // The documented points themselves, bit for bit at every tier.
        for k in 0..4 {
            assert_eq!(Some(out[k]), m.forward(dirs[k]), "{} {}", T::NAME, dirs[k]);
        }
        let mut back = vec![Vec3::ZERO; points.len()];
        inverse_slice::<_, T>(&m, points, &mut back);
        for (c, got) in points.iter().zip(&back) {
            check_simd_inverse(m, T::NAME, *c, *got).unwrap();
        }
        assert_eq!(back[0], Vec3::Z, "{}", T::NAME);
        for d in &back[3..7] {
            assert_eq!(*d, Vec3::NEG_Z, "{}", T::NAME);
        }
    }
    tier::<Exact>(&dirs, &points);
    tier::<Fine>(&dirs, &points);
    tier::<Fast>(&dirs, &points);
}

/// Names the command line accepts for the angular map and the mirror ball.
#[test]
fn angular_and_mirror_ball_names() {
    for name in [
        "angular",
        "light-probe",
        "lightprobe",
        "Light-Probe",
        "ANGULAR",
    ] {
        assert_eq!(
            name.parse::<AnyMapping>(),
            Ok(AnyMapping::Angular),
            "{name}"
        );
    }
    for name in ["mirror-ball", "mirrorball", "Mirror-Ball"] {
        assert_eq!(
            name.parse::<AnyMapping>(),
            Ok(AnyMapping::SphereMapGl),
            "{name}"
        );
    }
    assert_eq!(AnyMapping::Angular.to_string(), "angular");
    assert!(AnyMapping::Angular.has_disk_charts());
    assert_eq!(
        AnyMapping::Angular.atlas(),
        envmap_core::Atlas::SINGLE_SQUARE
    );
}

// ---------------------------------------------------------------------------------------------
// Dual paraboloid and octahedral: seams with signed zeros
// ---------------------------------------------------------------------------------------------

#[test]
fn paraboloid_poles_and_equator() {
    assert_eq!(
        DualParaboloid::forward(Vec3::Z),
        Some(ChartUv::new(0, 0.5, 0.5))
    );
    assert_eq!(
        DualParaboloid::forward(Vec3::NEG_Z),
        Some(ChartUv::new(1, 0.5, 0.5))
    );
    // z = ±0 picks the chart; the (u, v) agree.
    let a = DualParaboloid::forward(v(0.6, 0.8, 0.0)).unwrap();
    let b = DualParaboloid::forward(v(0.6, 0.8, -0.0)).unwrap();
    assert_eq!((a.chart, b.chart), (0, 1));
    assert_eq!((a.u, a.v), (b.u, b.v));
    let (da, db) = (
        DualParaboloid::inverse(a).unwrap(),
        DualParaboloid::inverse(b).unwrap(),
    );
    assert!(da.z >= 0.0 && db.z <= 0.0 && angle_f32(da, db) < 1e-7);
}

#[test]
fn octahedral_poles_folds_and_corners() {
    for m in [AnyMapping::Octahedral, AnyMapping::EqualAreaOctahedral] {
        assert_eq!(m.forward(Vec3::Z), Some(ChartUv::new(0, 0.5, 0.5)), "{m}");
        // −z is a corner, and all four corners are −z.
        let c = m.forward(Vec3::NEG_Z).unwrap();
        assert!(
            (c.u == 0.0 || c.u == 1.0) && (c.v == 0.0 || c.v == 1.0),
            "{m}: {c:?}"
        );
        for (u, vv) in [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)] {
            let d = m.inverse(ChartUv::new(0, u, vv)).unwrap();
            assert!(angle_f32(d, Vec3::NEG_Z) < 1e-7, "{m}: ({u}, {vv}) -> {d}");
            // And forward keeps the corner it came from (signed zeros).
            assert_eq!(m.forward(d), Some(ChartUv::new(0, u, vv)), "{m}: {d:?}");
        }
        // On the lower hemisphere's folds, the sign of a zero component
        // picks one of the two images on the square's edge.
        for (p, q) in [
            (v(0.0, 0.6, -0.8), v(-0.0, 0.6, -0.8)),
            (v(0.6, 0.0, -0.8), v(0.6, -0.0, -0.8)),
        ] {
            let (a, b) = (m.forward(p).unwrap(), m.forward(q).unwrap());
            assert_ne!(a, b, "{m}: {p:?} and {q:?}");
            let on_edge = |c: ChartUv| [c.u, c.v].iter().any(|&x| x == 0.0 || x == 1.0);
            assert!(on_edge(a) && on_edge(b), "{m}: {a:?} {b:?}");
            assert!(
                angle_f32(m.inverse(a).unwrap(), m.inverse(b).unwrap()) < 2e-7,
                "{m}"
            );
            // Mirror images across the square's centre line.
            assert!((a.u - (1.0 - b.u)).abs() < 1e-7 || (a.v - (1.0 - b.v)).abs() < 1e-7);
        }
        // The axes on the equator.
        for (d, u, vv) in [
            (Vec3::X, 1.0, 0.5),
            (Vec3::NEG_X, 0.0, 0.5),
            (Vec3::Y, 0.5, 1.0),
            (Vec3::NEG_Y, 0.5, 0.0),
        ] {
            let c = m.forward(d).unwrap();
            assert!(
                (c.u - u).abs() < 1e-7 && (c.v - vv).abs() < 1e-7,
                "{m}: {d} -> {c:?}"
            );
        }
    }
    let c = Octahedral::forward(v(1.0, 1.0, 0.0)).unwrap();
    assert_eq!((c.u, c.v), (0.75, 0.75));
    let c = EqualAreaOctahedral::forward(v(1.0, 1.0, 0.0)).unwrap();
    assert!((c.u - 0.75).abs() < 1e-7 && (c.v - 0.75).abs() < 1e-7);
}

// ---------------------------------------------------------------------------------------------
// Tennisball: the seed erratum
// ---------------------------------------------------------------------------------------------

/// Whether (θ, φ) is inside the printed ranges −π/4 ≤ θ ≤ π/4,
/// −3π/4 ≤ φ ≤ 3π/4, allowing 2 f32 ulps at the ends (rounding of asin,
/// atan2 and of the constants).
fn in_printed_ranges(theta: f32, phi: f32) -> bool {
    let q = std::f32::consts::FRAC_PI_4;
    envmap_tests::ulps_outside(theta, -q, q) <= 2
        && envmap_tests::ulps_outside(phi, -3.0 * q, 3.0 * q) <= 2
}

#[test]
fn tennisball_seed_erratum() {
    // +z: the printed formula puts it at φ = π in chart 0, outside the range.
    let (chart, _, phi) = tennisball::seed_printed_angles(Vec3::Z).unwrap();
    assert_eq!(chart, 0);
    assert!((phi - std::f32::consts::PI).abs() < 1e-6);
    assert_eq!(tennisball::raw_angles(Vec3::Z), Some((0, 0.0, 0.0)));
    assert_eq!(
        Tennisball::forward(Vec3::Z),
        Some(ChartUv::new(0, 0.5, 0.5))
    );

    // Over 20000 deterministic pseudo-random directions, the printed
    // formulas leave a sizeable fraction outside the printed ranges; the
    // corrected ones leave none.
    let mut rng = SplitMix64::new(0x7e55_15ba);
    let n = 20_000;
    let (mut seed_out, mut fixed_out) = (0u32, 0u32);
    for _ in 0..n {
        let d = rng.direction();
        let (_, theta, phi) = tennisball::seed_printed_angles(d).unwrap();
        seed_out += u32::from(!in_printed_ranges(theta, phi));
        let (_, theta, phi) = tennisball::raw_angles(d).unwrap();
        fixed_out += u32::from(!in_printed_ranges(theta, phi));
    }
    let fraction = f64::from(seed_out) / f64::from(n);
    println!(
        "tennisball: the printed formulas leave {:.2} % of {n} directions outside the ranges, \
         the corrected ones {fixed_out}",
        100.0 * fraction
    );
    assert!((0.10..=0.30).contains(&fraction), "{fraction}");
    assert_eq!(fixed_out, 0);
}

#[test]
fn tennisball_axes_and_selection_boundaries() {
    // (direction, chart, u, v)
    let cases = [
        (Vec3::Z, 0, 0.5, 0.5),
        (Vec3::X, 0, 5.0 / 6.0, 0.5),
        (Vec3::NEG_X, 0, 1.0 / 6.0, 0.5),
        (Vec3::Y, 1, 5.0 / 6.0, 0.5),
        (Vec3::NEG_Y, 1, 1.0 / 6.0, 0.5),
        (Vec3::NEG_Z, 1, 0.5, 0.5),
    ];
    for (d, chart, u, vv) in cases {
        let c = Tennisball::forward(d).unwrap();
        assert_eq!(c.chart, chart, "{d}");
        assert!(
            (c.u - u).abs() < 2e-7 && (c.v - vv).abs() < 2e-7,
            "{d}: {c:?} vs ({u}, {vv})"
        );
        assert!(angle_f32(Tennisball::inverse(c).unwrap(), d) < 2e-7, "{d}");
    }
    let s = std::f32::consts::FRAC_1_SQRT_2;
    // On the selection boundaries: the printed rule decides, and the angles
    // stay in range. (direction, expected chart)
    let boundary = [
        (v(s, s, 0.0), 0),     // c = 0, |b| = √2/2: first clause
        (v(s, -s, 0.0), 0),    // also |a| = √2/2 with c = 0: second clause
        (v(s, s, -0.0), 0),    // c = −0 ≤ 0 and |a| = √2/2
        (v(0.5, s, 0.5), 0),   // c > 0, |b| = √2/2
        (v(-s, 0.5, -0.5), 0), // c < 0, |a| = √2/2
        (v(0.5, 0.5, -s), 1),  // c < 0, |a| < √2/2
        (v(0.0, 1.0, 0.0), 1),
        (v(0.0, s, s), 0),
        (v(0.0, s, -s), 1),
    ];
    for (d, chart) in boundary {
        let n = envmap_core::normalize_direction(d).unwrap();
        assert_eq!(
            tennisball::selects_chart_0(n.x, n.y, n.z),
            chart == 0,
            "{d}"
        );
        let (got, theta, phi) = tennisball::raw_angles(d).unwrap();
        assert_eq!(got, chart, "{d}");
        assert!(in_printed_ranges(theta, phi), "{d}: θ = {theta}, φ = {phi}");
        let c = Tennisball::forward(d).unwrap();
        assert_eq!(c.chart, chart);
        assert!(angle_f32(Tennisball::inverse(c).unwrap(), d) < 2e-7, "{d}");
    }
}

// ---------------------------------------------------------------------------------------------
// Frames
// ---------------------------------------------------------------------------------------------

#[test]
fn frame_presets() {
    assert_eq!(Frame::Y_UP_RH.to_canonical(Vec3::Y), Vec3::Z);
    assert_eq!(Frame::Y_UP_LH.to_canonical(Vec3::Y), Vec3::Z);
    assert_eq!(Frame::Y_UP_RH.to_canonical(Vec3::Z), Vec3::NEG_Y);
    assert_eq!(Frame::Y_UP_LH.to_canonical(Vec3::Z), Vec3::Y);
    assert_eq!(Frame::Y_UP_RH.to_canonical(Vec3::X), Vec3::X);
    assert_eq!(Frame::Z_UP_RH, Frame::IDENTITY);
    assert!(!Frame::Y_UP_RH.is_reflection());
    assert!(Frame::Y_UP_LH.is_reflection());
    for f in [Frame::IDENTITY, Frame::Y_UP_RH, Frame::Y_UP_LH] {
        for d in [Vec3::X, Vec3::Y, Vec3::Z, v(0.25, -0.5, 2.0)] {
            assert_eq!(f.from_canonical(f.to_canonical(d)), d);
            assert_eq!(f.inverse().to_canonical(f.to_canonical(d)), d);
        }
    }
    // Y-up latlong: the caller's up is the top row, down the bottom row.
    let ll = Framed::new(LatLong, Frame::Y_UP_RH);
    assert_eq!(ll.forward(Vec3::Y).map(|c| c.v), Some(0.0));
    assert_eq!(ll.forward(Vec3::NEG_Y).map(|c| c.v), Some(1.0));
    // glTF's +z (towards the viewer) is canonical −y: u = 3/4 on the horizon.
    assert_eq!(ll.forward(Vec3::Z), Some(ChartUv::new(0, 0.75, 0.5)));
    // A preset only permutes and negates components: Framed gives exactly
    // the bare mapping of the permuted direction.
    for m in AnyMapping::ALL {
        for f in [Frame::IDENTITY, Frame::Y_UP_RH, Frame::Y_UP_LH] {
            for d in [
                v(0.25, -0.5, 2.0),
                v(-3.0, 1.5, -0.125),
                v(1e-30, 2e30, -7.0),
            ] {
                let framed = Framed::new(m, f).forward(d);
                assert_eq!(framed, m.forward(f.to_canonical(d)), "{m} {f:?} {d}");
                // A direction a fisheye does not see has no point, framed or not.
                let Some(c) = framed else {
                    assert!(!m.covers_sphere(), "{m} {f:?} {d}");
                    continue;
                };
                let back = Framed::new(m, f).inverse(c).unwrap();
                assert_eq!(back, f.from_canonical(m.inverse(c).unwrap()));
            }
        }
    }
    // Cube maps for GL, Vulkan, D3D and wgpu take the API's vector as is.
    let cube = Framed::new(Cube, Frame::IDENTITY);
    assert_eq!(
        cube.forward(v(4.0, 1.0, 2.0)),
        Cube::forward(v(4.0, 1.0, 2.0))
    );
}

// ---------------------------------------------------------------------------------------------
// The equi-angular cube map
// ---------------------------------------------------------------------------------------------

/// EAC is the cube with each face coordinate warped by angle: the same face
/// and the same direction as the cube at s = ½ + ½ tan(π/4 (2u − 1)), so
/// that face centres, edge midpoints and corners coincide with the cube's,
/// its edges are seamless where the cube's are, and the 22.5° point of an
/// axis is at u = ¾ (the cube's ½ + ½ tan(π/8) = 0.7071).
#[test]
fn eac_is_the_cube_warped_by_angle() {
    let warp = |u: f32| 0.5 + 0.5 * (std::f32::consts::FRAC_PI_4 * (2.0 * u - 1.0)).tan();
    for face in 0..6 {
        for (u, v) in [
            (0.5, 0.5),
            (0.0, 0.5),
            (1.0, 0.5),
            (0.5, 0.0),
            (0.0, 1.0),
            (1.0, 1.0),
        ] {
            let e = Eac::inverse(ChartUv::new(face, u, v)).unwrap();
            let c = Cube::inverse(ChartUv::new(face, u, v)).unwrap();
            assert!(angle_f32(e, c) < 2e-7, "face {face} ({u}, {v})");
        }
        for (u, v) in [(0.75, 0.5), (0.1, 0.9), (0.3, 0.62)] {
            let e = Eac::inverse(ChartUv::new(face, u, v)).unwrap();
            let c = Cube::inverse(ChartUv::new(face, warp(u), warp(v))).unwrap();
            assert!(angle_f32(e, c) < 3e-7, "face {face} ({u}, {v})");
            assert_eq!(Eac::forward(e).unwrap().chart, face);
        }
    }
    let d = Vec3::new((std::f32::consts::PI / 8.0).tan(), 0.0, 1.0);
    let c = Eac::forward(d).unwrap();
    assert_eq!(c.chart, 4);
    assert!(
        (c.u - 0.75).abs() < 1e-7 && (c.v - 0.5).abs() < 1e-7,
        "{c:?}"
    );
    assert_eq!("eac".parse::<AnyMapping>(), Ok(AnyMapping::Eac));
    assert_eq!(AnyMapping::Eac.to_string(), "eac");
    assert!(AnyMapping::Eac.has_cube_faces() && !AnyMapping::Eac.has_disk_charts());
}

/// The cells of EAC's default atlas, v360's `eac` layout as held in memory,
/// look at −x, +z, +x on top and −y, −z, +y below; the cube's 3×2 at +x,
/// −x, +y and −y, +z, −z.
#[test]
fn eac_and_cube_three_by_two_cells() {
    let centre = |m: AnyMapping, atlas: Atlas, col: u32, row: u32| {
        let p = atlas
            .image_to_chart((col as f32 + 0.5) / 3.0, (row as f32 + 0.5) / 2.0)
            .unwrap();
        m.inverse(p).unwrap()
    };
    assert_eq!(AnyMapping::Eac.atlas(), Atlas::EAC_V360);
    let eac = [
        [Vec3::NEG_X, Vec3::Z, Vec3::X],
        [Vec3::NEG_Y, Vec3::NEG_Z, Vec3::Y],
    ];
    let cube = [
        [Vec3::X, Vec3::NEG_X, Vec3::Y],
        [Vec3::NEG_Y, Vec3::Z, Vec3::NEG_Z],
    ];
    for row in 0..2 {
        for col in 0..3 {
            let got = centre(AnyMapping::Eac, Atlas::EAC_V360, col, row);
            assert!(
                angle_f32(got, eac[row as usize][col as usize]) < 1e-6,
                "{col},{row}"
            );
            let got = centre(AnyMapping::Cube, Atlas::CUBE_3X2, col, row);
            assert!(
                angle_f32(got, cube[row as usize][col as usize]) < 1e-6,
                "{col},{row}"
            );
        }
    }
}
