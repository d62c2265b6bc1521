//! Every SIMD kernel against the scalar core, lane by lane, at every tier.
//!
//! Bounds (in u, v and in radians for directions) follow from each tier's
//! documented function error (see `envmap_tests::simd_uv_bound` and
//! `envmap_tests::simd_angle_bound`). Mappings without
//! trigonometry (cube, sphere maps, paraboloid, octahedral) evaluate the same
//! operations in the same order as the core and must agree bit for bit.
//!
//! `ENVMAP_EXTENSIVE=1` runs 16× more random directions.

use envmap_core::glam::Vec3;
use envmap_core::{AnyMapping, ChartUv, Mapping};
use envmap_simd::{forward_slice, inverse_slice, Exact, Fast, Fine, Mapping8, Tier, INVALID_CHART};
use envmap_tests::{simd_angle_bound, simd_matches_bitwise, simd_uv_bound, SplitMix64};

/// A uniform `f32` in `[0, 1)`.
fn unit(rng: &mut SplitMix64) -> f32 {
    (rng.next_u64() >> 40) as f32 / (1u64 << 24) as f32
}

/// A random direction with a random length over many decades.
fn dir(rng: &mut SplitMix64) -> Vec3 {
    loop {
        let v = Vec3::new(
            2.0 * unit(rng) - 1.0,
            2.0 * unit(rng) - 1.0,
            2.0 * unit(rng) - 1.0,
        );
        let l = v.length();
        if l > 1e-3 && l <= 1.0 {
            let scale = 10f32.powi((rng.next_u64() % 41) as i32 - 20);
            return v / l * scale;
        }
    }
}

fn count() -> usize {
    if std::env::var("ENVMAP_EXTENSIVE").is_ok_and(|v| v == "1") {
        1 << 20
    } else {
        1 << 16
    }
}

/// Named hard cases: axes, cube edges and corners (exact ties), signed zeros,
/// poles, the sphere maps' and the angular map's singular directions and
/// their neighbourhoods, tennisball boundaries, tiny, huge and denormal
/// components, and bad input.
fn hard_cases() -> Vec<Vec3> {
    let s = std::f32::consts::FRAC_1_SQRT_2;
    let mut v = vec![
        Vec3::X,
        Vec3::NEG_X,
        Vec3::Y,
        Vec3::NEG_Y,
        Vec3::Z,
        Vec3::NEG_Z,
        Vec3::new(-0.0, 0.0, 1.0),
        Vec3::new(0.0, -0.0, -1.0),
        Vec3::new(1.0, -0.0, -0.0),
        Vec3::new(-0.0, -1.0, 0.0),
        Vec3::new(1e-30, 0.0, 1.0),
        Vec3::new(0.0, -1e-38, -1.0),
        Vec3::new(1e30, 1e-30, -0.0),
        Vec3::new(f32::MAX, f32::MAX, f32::MAX),
        Vec3::new(-f32::MAX, f32::MAX / 2.0, 1.0),
        Vec3::new(1e-45, 1e-45, 1e-45),
        Vec3::new(1e-45, -1e-45, 0.0),
        Vec3::new(3e-39, 1.0e-39, -2e-39),
        Vec3::new(-1e-45, 0.0, -1.0),
        Vec3::new(1e-20, -3e-20, -1.0),
        Vec3::new(-2e-4, 1e-4, -1.0),
        Vec3::new(1.0, -1.0, -1e7),
        Vec3::new(-3e-39, 1e-39, -1e30),
        Vec3::new(s, s, 0.0),
        Vec3::new(s, 0.0, -s),
        Vec3::new(0.0, s, s),
        Vec3::new(s, 0.5, -0.5),
        Vec3::new(0.5, s, 0.5),
        Vec3::ZERO,
        Vec3::new(-0.0, -0.0, -0.0),
        Vec3::new(f32::NAN, 0.0, 1.0),
        Vec3::new(0.0, f32::INFINITY, 1.0),
        Vec3::new(0.0, 1.0, f32::NEG_INFINITY),
        Vec3::NAN,
    ];
    // Every cube edge and corner, with exact ties, in both signs.
    for x in [-1.0f32, -0.0, 0.0, 1.0] {
        for y in [-1.0f32, -0.0, 0.0, 1.0] {
            for z in [-1.0f32, -0.0, 0.0, 1.0] {
                v.push(Vec3::new(x, y, z));
                v.push(Vec3::new(x * 3.0, y * 3.0, z * 0.5));
                v.push(Vec3::new(x * 0.5, y * 3.0, z * 3.0));
            }
        }
    }
    v
}

/// Angle between two directions in f64, as atan2(|a × b|, a · b).
fn angle(a: Vec3, b: Vec3) -> f64 {
    let a = [f64::from(a.x), f64::from(a.y), f64::from(a.z)];
    let b = [f64::from(b.x), f64::from(b.y), f64::from(b.z)];
    let c = [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ];
    let cl = (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt();
    cl.atan2(a[0] * b[0] + a[1] * b[1] + a[2] * b[2])
}

fn check_forward<T: Tier>(m: AnyMapping, dirs: &[Vec3]) {
    let tn = T::NAME;
    let mut out = vec![ChartUv::default(); dirs.len()];
    assert_eq!(forward_slice::<_, T>(&m, dirs, &mut out), dirs.len());
    let bound = simd_uv_bound(T::NAME);
    let mut worst = (0.0f32, Vec3::ZERO);
    for (d, got) in dirs.iter().zip(&out) {
        let want = m.forward(*d);
        // At a partial fisheye's rim the tier's angle may fall on either side.
        if (want.is_none() != (got.chart == INVALID_CHART))
            && envmap_tests::past_rim(m, *d).is_some_and(|p| p.abs() < 1e-3)
        {
            continue;
        }
        match want {
            None => {
                assert_eq!(
                    got.chart, INVALID_CHART,
                    "{m} {tn} {d}: expected invalid lane"
                );
                assert!(got.u.is_nan() && got.v.is_nan());
            }
            Some(want) => {
                assert_eq!(got.chart, want.chart, "{m} {tn} {d}: chart");
                if simd_matches_bitwise(m) {
                    assert_eq!(
                        (got.u.to_bits(), got.v.to_bits()),
                        (want.u.to_bits(), want.v.to_bits()),
                        "{m} {tn} {d}: {got:?} vs {want:?}"
                    );
                    continue;
                }
                let mut du = (got.u - want.u).abs();
                if m == AnyMapping::LatLong {
                    du = du.min(1.0 - du); // u wraps
                }
                let e = du.max((got.v - want.v).abs());
                assert!(
                    (0.0..=1.0).contains(&got.u) && (0.0..=1.0).contains(&got.v),
                    "{m} {tn} {d}: {got:?} out of range"
                );
                if e > worst.0 {
                    worst = (e, *d);
                }
            }
        }
    }
    assert!(
        worst.0 <= bound,
        "{m} {tn} forward: max |Δuv| {:e} at {} exceeds {bound:e}",
        worst.0,
        worst.1
    );
    println!(
        "{m:>22} {:>5} forward: max |Δuv| = {:.2e} at {}",
        T::NAME,
        worst.0,
        worst.1
    );
}

fn check_inverse<T: Tier>(m: AnyMapping, rng: &mut SplitMix64, n: usize) {
    let tn = T::NAME;
    let mut coords: Vec<ChartUv> = (0..n)
        .map(|_| {
            ChartUv::new(
                (rng.next_u64() % u64::from(m.chart_count())) as u32,
                unit(rng),
                unit(rng),
            )
        })
        .collect();
    // Edges, corners and bad points.
    for c in 0..m.chart_count() + 1 {
        for (u, v) in [
            (0.0, 0.0),
            (1.0, 1.0),
            (0.5, 0.5),
            (0.0, 0.5),
            (1.0, 0.25),
            (1.5, 0.5),
            (f32::NAN, 0.5),
            (0.5, -0.0),
            (-1e-9, 0.5),
        ] {
            coords.push(ChartUv::new(c, u, v));
        }
    }
    let mut out = vec![Vec3::ZERO; coords.len()];
    assert_eq!(inverse_slice::<_, T>(&m, &coords, &mut out), coords.len());
    let bound = simd_angle_bound(T::NAME);
    let mut worst = (0.0f64, ChartUv::default());
    for (c, got) in coords.iter().zip(&out) {
        match m.inverse(*c) {
            None => assert!(got.is_nan(), "{m} {tn} {c:?}: expected NaN, got {got}"),
            Some(want) => {
                assert!(got.is_finite(), "{m} {tn} {c:?}: got {got}");
                let e = angle(*got, want);
                if e > worst.0 {
                    worst = (e, *c);
                }
            }
        }
    }
    assert!(
        worst.0 <= bound,
        "{m} {tn} inverse: max angle {:e} at {:?} exceeds {bound:e}",
        worst.0,
        worst.1
    );
    println!(
        "{m:>22} {:>5} inverse: max angle = {:.2e} rad at {:?}",
        T::NAME,
        worst.0,
        worst.1
    );
}

fn all_tiers(m: AnyMapping) {
    // Seeded by the mapping's place in `ALL` (a fisheye of other parameters by its field of
    // view).
    let seed = match AnyMapping::ALL.iter().position(|a| *a == m) {
        Some(i) => i as u64,
        None => match m {
            AnyMapping::Fisheye(f) => (f.fov_degrees() * 1000.0) as u64,
            _ => 0,
        },
    };
    let mut rng = SplitMix64::new(0x9E37_79B9_7F4A_7C15 ^ seed);
    let mut dirs: Vec<Vec3> = (0..count()).map(|_| dir(&mut rng)).collect();
    dirs.extend(hard_cases());
    check_forward::<Exact>(m, &dirs);
    check_forward::<Fine>(m, &dirs);
    check_forward::<Fast>(m, &dirs);
    let n = count() / 4;
    check_inverse::<Exact>(m, &mut rng, n);
    check_inverse::<Fine>(m, &mut rng, n);
    check_inverse::<Fast>(m, &mut rng, n);
}

#[test]
fn latlong() {
    all_tiers(AnyMapping::LatLong);
}
#[test]
fn cube() {
    all_tiers(AnyMapping::Cube);
}
#[test]
fn sphere_map_class() {
    all_tiers(AnyMapping::SphereMap);
}
#[test]
fn sphere_map_gl() {
    all_tiers(AnyMapping::SphereMapGl);
}
#[test]
fn dual_paraboloid() {
    all_tiers(AnyMapping::DualParaboloid);
}
#[test]
fn tennisball() {
    all_tiers(AnyMapping::Tennisball);
}
#[test]
fn octahedral() {
    all_tiers(AnyMapping::Octahedral);
}
#[test]
fn equal_area_octahedral() {
    all_tiers(AnyMapping::EqualAreaOctahedral);
}
#[test]
fn angular() {
    all_tiers(AnyMapping::Angular);
}
#[test]
fn eac() {
    all_tiers(AnyMapping::Eac);
}
#[test]
fn fisheye() {
    use envmap_core::{Fisheye, Lens};
    all_tiers(AnyMapping::Fisheye(Fisheye::SINGLE));
    all_tiers(AnyMapping::Fisheye(Fisheye::DUAL));
    for (lens, fov, dual) in [
        (Lens::Equidistant, 190.0, true),
        (Lens::Equisolid, 190.0, true),
        (Lens::Equisolid, 250.0, false),
        (Lens::Equidistant, 360.0, false),
        (Lens::Equidistant, 90.0, false),
    ] {
        all_tiers(AnyMapping::Fisheye(Fisheye::new(lens, fov, dual).unwrap()));
    }
}

/// Slices of awkward lengths give the same result as the scalar core in each
/// position (the tail goes through the padded kernel).
#[test]
fn slice_lengths() {
    let mut rng = SplitMix64::new(7);
    for n in [0usize, 1, 7, 8, 9, 17, 8 * 37 + 1] {
        let dirs: Vec<Vec3> = (0..n).map(|_| dir(&mut rng)).collect();
        for m in AnyMapping::ALL {
            let mut out = vec![ChartUv::new(99, -1.0, -1.0); n + 3];
            assert_eq!(forward_slice::<_, Exact>(&m, &dirs, &mut out), n);
            for (k, d) in dirs.iter().enumerate() {
                let want = m.forward(*d).map_or(INVALID_CHART, |c| c.chart);
                assert_eq!(out[k].chart, want, "{m} n={n} k={k}");
            }
            // Elements past the input are untouched.
            assert!(out[n..].iter().all(|c| c.chart == 99));
            let mut back = vec![Vec3::ZERO; n];
            assert_eq!(inverse_slice::<_, Exact>(&m, &out[..n], &mut back), n);
            for (k, d) in dirs.iter().enumerate() {
                if out[k].chart == INVALID_CHART {
                    // A direction the fisheye does not see: no point, no direction.
                    assert!(!m.covers_sphere() && back[k].is_nan(), "{m} n={n} k={k}");
                    continue;
                }
                assert!(angle(back[k], *d) < 1e-5, "{m} n={n} k={k}");
            }
        }
    }
}

/// A bad lane leaves the other seven lanes bit-identical.
#[test]
fn bad_lanes_do_not_disturb_good_ones() {
    let mut rng = SplitMix64::new(11);
    let good: Vec<Vec3> = (0..8).map(|_| dir(&mut rng)).collect();
    for m in AnyMapping::ALL {
        let mut clean = vec![ChartUv::default(); 8];
        forward_slice::<_, Fast>(&m, &good, &mut clean);
        for bad in [Vec3::NAN, Vec3::ZERO, Vec3::new(f32::INFINITY, 0.0, 0.0)] {
            for lane in 0..8 {
                let mut dirs = good.clone();
                dirs[lane] = bad;
                let mut out = vec![ChartUv::default(); 8];
                forward_slice::<_, Fast>(&m, &dirs, &mut out);
                for k in 0..8 {
                    if k == lane {
                        assert_eq!(out[k].chart, INVALID_CHART);
                    } else {
                        assert_eq!(out[k].chart, clean[k].chart);
                        assert_eq!(out[k].u.to_bits(), clean[k].u.to_bits(), "{m}");
                        assert_eq!(out[k].v.to_bits(), clean[k].v.to_bits(), "{m}");
                    }
                }
            }
        }
    }
}

/// The batch loads agree with each other.
#[test]
fn batch_loads() {
    use envmap_simd::Dir8;
    let v: [Vec3; 8] = core::array::from_fn(|k| Vec3::new(k as f32, -(k as f32), 0.5 * k as f32));
    let a: [[f32; 3]; 8] = core::array::from_fn(|k| v[k].to_array());
    let x: [f32; 8] = core::array::from_fn(|k| v[k].x);
    let y: [f32; 8] = core::array::from_fn(|k| v[k].y);
    let z: [f32; 8] = core::array::from_fn(|k| v[k].z);
    let b = Dir8::from_vec3s(&v);
    assert_eq!(b, Dir8::from_arrays(&a));
    assert_eq!(b, Dir8::from_xyz(&x, &y, &z));
    assert_eq!(b.to_arrays(), a);
    let c = AnyMapping::Cube.forward8::<Exact>(b);
    assert_eq!(c.lane(0), None); // the zero vector
    assert_eq!(c.lane(1), AnyMapping::Cube.forward(v[1]));
}

/// A chart point's inverse does not depend on its batch: batches whose eight
/// lanes share one chart (as a conversion's rows do, which the cube maps
/// with a shortcut) give each lane bit for bit what the same point gives in
/// a batch of mixed charts.
#[test]
fn inverse_lanes_do_not_depend_on_their_batch() {
    fn check<T: Tier>(m: AnyMapping, rng: &mut SplitMix64) {
        // Groups of eight points on one chart each: random points, then the
        // edges, corners and bad points of every chart (and one chart past
        // the last), charts taken in turn.
        let charts = m.chart_count() + 1;
        let mut points = Vec::new();
        for g in 0..64 * charts {
            let c = g % charts;
            for k in 0..8 {
                let (u, v) = if g < 60 * charts {
                    (unit(rng), unit(rng))
                } else {
                    [(0.0, 0.0), (1.0, 1.0), (0.5, -0.0), (1.0, 0.25)][k % 4]
                };
                let u = if k == 7 && g % 3 == 0 { f32::NAN } else { u };
                points.push(ChartUv::new(c, u, v));
            }
        }
        let groups = points.len() / 8;
        // The same points with consecutive entries from different groups.
        let mixed: Vec<ChartUv> = (0..points.len())
            .map(|i| points[(i % groups) * 8 + i / groups])
            .collect();
        assert!(mixed[..8].iter().any(|p| p.chart != mixed[0].chart));
        let mut one = vec![Vec3::ZERO; points.len()];
        let mut many = vec![Vec3::ZERO; points.len()];
        inverse_slice::<_, T>(&m, &points, &mut one);
        inverse_slice::<_, T>(&m, &mixed, &mut many);
        for (i, got) in many.iter().enumerate() {
            let j = (i % groups) * 8 + i / groups;
            let want = one[j];
            assert_eq!(
                got.to_array().map(f32::to_bits),
                want.to_array().map(f32::to_bits),
                "{m} {} {:?}: {got} in a mixed batch, {want} in a one-chart batch",
                T::NAME,
                points[j]
            );
        }
    }
    let mut rng = SplitMix64::new(23);
    for m in AnyMapping::ALL {
        check::<Exact>(m, &mut rng);
        check::<Fine>(m, &mut rng);
        check::<Fast>(m, &mut rng);
    }
}

/// Random chart points of every chart of `m`, eight at a time: what
/// `inverse8` and `inverse8_ray` give for them.
fn inverses(m: AnyMapping, rng: &mut SplitMix64) -> Vec<(Vec3, Vec3)> {
    use envmap_simd::Uv8;
    let mut out = Vec::new();
    for _ in 0..512 {
        let c: [ChartUv; 8] = core::array::from_fn(|_| {
            let c = (rng.next_u64() % u64::from(m.chart_count())) as u32;
            ChartUv::new(c, unit(rng), unit(rng))
        });
        let q = Uv8::from_chart_uvs(&c);
        let (unit, ray) = (m.inverse8::<Fine>(q), m.inverse8_ray::<Fine>(q));
        out.extend((0..8).map(|k| (unit.lane(k), ray.lane(k))));
    }
    out
}

/// `inverse8_ray`: NaN exactly where `inverse8` is, and otherwise the same
/// ray (within 2e-7 rad) with its largest component between 1/2 and 2; for
/// the cube, `inverse8` is the ray divided by its length bit for bit.
#[test]
fn inverse8_ray_is_inverse8_up_to_scale() {
    let mut rng = SplitMix64::new(37);
    for m in AnyMapping::ALL {
        for (unit, ray) in inverses(m, &mut rng) {
            assert_eq!(unit.is_nan(), ray.is_nan(), "{m}: {unit} against {ray}");
            if unit.is_nan() {
                continue;
            }
            let big = ray.abs().max_element();
            assert!((0.5..=2.0).contains(&big), "{m}: ray {ray}");
            assert!(angle(unit, ray) <= 2e-7, "{m}: {unit} against {ray}");
            if m == AnyMapping::Cube {
                let len = (ray.x * ray.x + ray.y * ray.y + ray.z * ray.z).sqrt();
                assert_eq!((ray / len).to_array(), unit.to_array(), "{m}");
            }
        }
    }
}

/// `forward8_ray` on rays of moderate length (what every mapping's
/// `inverse8` and `inverse8_ray` return, normalised random directions and
/// the same scaled by 1/2 to 2, axes, seams and directions a hair from the
/// poles) and on NaN lanes: the same chart as `forward8`, and the same u
/// and v bit for bit, except within 10⁻¹⁸ rad of the z axis, where they
/// stay within the tier's bound.
#[test]
fn forward8_ray_agrees_with_forward8_on_rays() {
    use envmap_simd::Dir8;
    let mut rng = SplitMix64::new(31);
    let mut dirs: Vec<Vec3> = Vec::new();
    for m in AnyMapping::ALL {
        for (unit, ray) in inverses(m, &mut rng) {
            if !unit.is_nan() {
                dirs.extend([unit, ray]);
            }
        }
    }
    for _ in 0..4096 {
        // Normalised in f64: any length normalises without overflow.
        let d = dir(&mut rng).to_array().map(f64::from);
        let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        let u = Vec3::from_array(d.map(|c| (c / l) as f32));
        dirs.extend([u, u * (0.5 + 1.5 * unit(&mut rng))]);
    }
    for (x, y) in [
        (1e-20f32, 1e-20f32),
        (-1e-30, 0.0),
        (0.0, -0.0),
        (3e-19, -2e-19),
    ] {
        for z in [
            1.0f32,
            -1.0,
            1.0 - f32::EPSILON / 2.0,
            f32::EPSILON / 2.0 - 1.0,
        ] {
            dirs.push(Vec3::new(x, y, z));
        }
    }
    // The named hard cases of unit length: axes, signed zeros, edges.
    dirs.extend(
        hard_cases()
            .into_iter()
            .filter(|d| (d.length() - 1.0).abs() < 1e-6),
    );
    dirs.push(Vec3::new(-1.0, -0.0, 0.0));
    dirs.push(Vec3::new(-1.0, 0.0, -0.0));
    dirs.push(Vec3::NAN);
    while !dirs.len().is_multiple_of(8) {
        dirs.push(Vec3::NAN);
    }
    fn check<T: Tier>(m: AnyMapping, dirs: &[Vec3]) {
        let bound = simd_uv_bound(T::NAME);
        let mut differing = 0;
        for block in dirs.chunks_exact(8) {
            let b: &[Vec3; 8] = block.try_into().unwrap();
            let d = Dir8::from_vec3s(b);
            let (full, unit) = (m.forward8::<T>(d), m.forward8_ray::<T>(d));
            for (k, v) in b.iter().enumerate() {
                let (f, u) = (full.lane_raw(k), unit.lane_raw(k));
                assert_eq!(f.chart, u.chart, "{m} {} {v}", T::NAME);
                if v.is_nan() {
                    assert_eq!(u.chart, INVALID_CHART);
                    assert!(u.u.is_nan() && u.v.is_nan());
                    continue;
                }
                if (f.u.to_bits(), f.v.to_bits()) == (u.u.to_bits(), u.v.to_bits()) {
                    continue;
                }
                differing += 1;
                let near_pole = v.x.abs() < 1e-18 && v.y.abs() < 1e-18;
                let e = (f.u - u.u).abs().max((f.v - u.v).abs());
                assert!(
                    near_pole && e <= bound,
                    "{m} {} {v}: forward8 {f:?}, forward8_ray {u:?}",
                    T::NAME
                );
            }
        }
        println!(
            "{m:>22} {:>5}: {differing} lanes differ (near a pole)",
            T::NAME
        );
    }
    for m in AnyMapping::ALL {
        check::<Exact>(m, &dirs);
        check::<Fine>(m, &dirs);
        check::<Fast>(m, &dirs);
    }
}
