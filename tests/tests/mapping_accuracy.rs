//! Accuracy of every mapping — the scalar core and the SIMD kernels at each
//! tier — against an f64 reference of the same formula.
//!
//! Forward error is |Δ(u, v)| against the f64 forward map of the same (f32)
//! direction, also shown in texels of a 4096-wide chart; latlong's Δu is
//! measured on the sphere (weighted by sin θ, and across the wrap), since u
//! is undefined at the poles. Sphere maps skip directions within 1e-3 rad of
//! their singular direction, where the azimuth on the rim is ill-conditioned
//! (every direction there is within a few texels of the rim anyway). Inverse
//! error is the angle between the computed direction and the f64 inverse of
//! the same (f32) chart point; for the sphere maps it is reported separately
//! for r < 0.99 and on the whole disk, since the map is singular at its rim.
//!
//! `cargo test --release -p envmap-tests --test mapping_accuracy -- --nocapture`
//! prints the table; `ENVMAP_EXTENSIVE=1` runs 16× more points.

use std::f64::consts::{PI, TAU};

use envmap_core::glam::Vec3;
use envmap_core::{AnyMapping, ChartUv, Mapping};
use envmap_simd::{forward_slice, inverse_slice, Exact, Fast, Fine, Tier};
use envmap_tests::{to_f64, DVec3, SplitMix64};

fn count() -> usize {
    if std::env::var("ENVMAP_EXTENSIVE").is_ok_and(|v| v == "1") {
        1 << 21
    } else {
        1 << 17
    }
}

fn copysign(x: f64, s: f64) -> f64 {
    x.abs() * if s.is_sign_negative() { -1.0 } else { 1.0 }
}

/// The f64 forward map of a unit direction, in the chart the core chose
/// (charts are decided by exact comparisons, identical in f32 and f64 away
/// from ties; the core's choice is the one being measured).
fn forward_f64(m: AnyMapping, chart: u32, d: DVec3) -> (f64, f64) {
    let (x, y, z) = (d.x, d.y, d.z);
    match m {
        AnyMapping::LatLong => {
            let mut u = y.atan2(x) / TAU;
            if u < 0.0 {
                u += 1.0;
            }
            (u, x.hypot(y).atan2(z) / PI)
        }
        AnyMapping::Cube => {
            let (sc, tc, ma) = match chart {
                0 => (-z, -y, x),
                1 => (z, -y, x),
                2 => (x, z, y),
                3 => (x, -z, y),
                4 => (x, -y, z),
                _ => (-x, -y, z),
            };
            (0.5 * (sc / ma.abs() + 1.0), 0.5 * (tc / ma.abs() + 1.0))
        }
        AnyMapping::SphereMap | AnyMapping::SphereMapGl => {
            let sigma = if m == AnyMapping::SphereMap {
                -1.0
            } else {
                1.0
            };
            let mm = (x * x + y * y + (z + sigma) * (z + sigma)).sqrt();
            (0.5 * x / mm + 0.5, 0.5 * y / mm + 0.5)
        }
        AnyMapping::DualParaboloid => {
            let den = 1.0 + z.abs();
            (0.5 * x / den + 0.5, 0.5 * y / den + 0.5)
        }
        AnyMapping::Tennisball => {
            let (theta, phi) = if chart == 0 {
                (y.asin(), x.atan2(z))
            } else {
                (x.asin(), y.atan2(-z))
            };
            (phi / (1.5 * PI) + 0.5, 0.5 - theta / (0.5 * PI))
        }
        AnyMapping::Octahedral => {
            let l1 = x.abs() + y.abs() + z.abs();
            let (px, py, pz) = (x / l1, y / l1, z / l1);
            let (a, b) = if pz < 0.0 {
                (copysign(1.0 - py.abs(), px), copysign(1.0 - px.abs(), py))
            } else {
                (px, py)
            };
            (0.5 * a + 0.5, 0.5 * b + 0.5)
        }
        AnyMapping::EqualAreaOctahedral => {
            let (ax, ay, az) = (x.abs(), y.abs(), z.abs());
            let r = ((ax * ax + ay * ay) / (1.0 + az)).sqrt();
            let (hi, lo) = (ax.max(ay), ax.min(ay));
            let mut phi = if hi == 0.0 {
                0.0
            } else {
                (lo / hi).atan() * 2.0 / PI
            };
            if ax < ay {
                phi = 1.0 - phi;
            }
            let mut v = phi * r;
            let mut u = r - v;
            if z < 0.0 {
                (u, v) = (1.0 - v, 1.0 - u);
            }
            (0.5 * copysign(u, x) + 0.5, 0.5 * copysign(v, y) + 0.5)
        }
    }
}

/// The f64 inverse map of a chart point (assumed inside its chart).
fn inverse_f64(m: AnyMapping, c: ChartUv) -> DVec3 {
    let (u, v) = (f64::from(c.u), f64::from(c.v));
    let (a, b) = (2.0 * u - 1.0, 2.0 * v - 1.0);
    let d = match m {
        AnyMapping::LatLong => {
            let (phi, theta) = (TAU * u, PI * v);
            DVec3::new(
                theta.sin() * phi.cos(),
                theta.sin() * phi.sin(),
                theta.cos(),
            )
        }
        AnyMapping::Cube => match c.chart {
            0 => DVec3::new(1.0, -b, -a),
            1 => DVec3::new(-1.0, -b, a),
            2 => DVec3::new(a, 1.0, b),
            3 => DVec3::new(a, -1.0, -b),
            4 => DVec3::new(a, -b, 1.0),
            _ => DVec3::new(-a, -b, -1.0),
        },
        AnyMapping::SphereMap | AnyMapping::SphereMapGl => {
            let sigma = if m == AnyMapping::SphereMap {
                -1.0
            } else {
                1.0
            };
            let r2 = a * a + b * b;
            let nz = (1.0 - r2).max(0.0).sqrt();
            DVec3::new(2.0 * a * nz, 2.0 * b * nz, sigma * (1.0 - 2.0 * r2))
        }
        AnyMapping::DualParaboloid => {
            let r2 = a * a + b * b;
            let zz = (1.0 - r2).max(0.0);
            DVec3::new(2.0 * a, 2.0 * b, if c.chart == 1 { -zz } else { zz })
        }
        AnyMapping::Tennisball => {
            let phi = (u - 0.5) * 1.5 * PI;
            let theta = (0.5 - v) * 0.5 * PI;
            if c.chart == 0 {
                DVec3::new(
                    theta.cos() * phi.sin(),
                    theta.sin(),
                    theta.cos() * phi.cos(),
                )
            } else {
                DVec3::new(
                    theta.sin(),
                    theta.cos() * phi.sin(),
                    -theta.cos() * phi.cos(),
                )
            }
        }
        AnyMapping::Octahedral => {
            let zz = 1.0 - a.abs() - b.abs();
            if zz < 0.0 {
                DVec3::new(copysign(1.0 - b.abs(), a), copysign(1.0 - a.abs(), b), zz)
            } else {
                DVec3::new(a, b, zz)
            }
        }
        AnyMapping::EqualAreaOctahedral => {
            let (au, av) = (a.abs(), b.abs());
            let sd = 1.0 - (au + av);
            let r = 1.0 - sd.abs();
            let phi = if r == 0.0 { 1.0 } else { (av - au) / r + 1.0 } * PI / 4.0;
            let zz = copysign(1.0 - r * r, sd);
            let k = r * (2.0 - r * r).max(0.0).sqrt();
            DVec3::new(copysign(phi.cos(), a) * k, copysign(phi.sin(), b) * k, zz)
        }
    };
    d.normalize()
}

/// Worst value and where it occurred.
#[derive(Default)]
struct Worst {
    err: f64,
    at: String,
}
impl Worst {
    fn add(&mut self, e: f64, at: impl FnOnce() -> String) {
        if e > self.err {
            self.err = e;
            self.at = at();
        }
    }
}

/// Directions to measure for mapping `m` (uniform, plus a band near each
/// pole and equator where the formulas change branches).
fn directions(m: AnyMapping, n: usize) -> Vec<Vec3> {
    let mut rng = SplitMix64::new(0x5EED ^ m as u64);
    let mut v: Vec<Vec3> = (0..n).map(|_| rng.direction()).collect();
    for k in 0..n / 8 {
        let t = 1e-6 * (1.0 + k as f64);
        let phi = rng.next_f64() * TAU;
        let s = t.sin();
        for z in [t.cos(), -t.cos(), s] {
            let rho = (1.0 - z * z).sqrt();
            v.push(DVec3::new(rho * phi.cos(), rho * phi.sin(), z).as_vec3());
        }
    }
    v.retain(|d| {
        let singular = match m {
            AnyMapping::SphereMap => Some(Vec3::Z),
            AnyMapping::SphereMapGl => Some(Vec3::NEG_Z),
            _ => None,
        };
        singular.is_none_or(|s| envmap_tests::angle_f32(*d, s) >= 1e-3)
    });
    v
}

/// Chart size in texels when the whole atlas is 4096 texels wide (a cube
/// cross has 1024² faces, the paraboloid 2048² disks, the tennisball
/// 4096 × 1365 strips).
fn chart_texels_at_4096(m: AnyMapping) -> (f64, f64) {
    let a = m.atlas();
    let w = 4096.0 / f64::from(a.cols);
    (
        w,
        (w * f64::from(a.cell_aspect_h) / f64::from(a.cell_aspect_w)).floor(),
    )
}

/// (|Δu|, |Δv|) against the f64 forward map.
fn forward_error(m: AnyMapping, d: Vec3, c: ChartUv) -> (f64, f64) {
    let dd = to_f64(d).normalize();
    let (u, v) = forward_f64(m, c.chart, dd);
    let mut du = (f64::from(c.u) - u).abs();
    if m == AnyMapping::LatLong {
        du = du.min(1.0 - du) * (PI * v).sin();
    }
    (du, (f64::from(c.v) - v).abs())
}

/// Worst max(|Δu|, |Δv|), and worst error in texels at 4096 wide.
fn measure_forward(m: AnyMapping, dirs: &[Vec3], out: &[ChartUv]) -> (Worst, f64) {
    let (tw, th) = chart_texels_at_4096(m);
    let mut w = Worst::default();
    let mut texels = 0.0f64;
    for (d, c) in dirs.iter().zip(out) {
        assert!(c.chart < m.chart_count(), "{m}: {d} gave {c:?}");
        let (du, dv) = forward_error(m, *d, *c);
        w.add(du.max(dv), || format!("{d}"));
        texels = texels.max(du * tw).max(dv * th);
    }
    (w, texels)
}

fn simd_forward<T: Tier>(m: AnyMapping, dirs: &[Vec3]) -> (Worst, f64) {
    let mut out = vec![ChartUv::default(); dirs.len()];
    forward_slice::<_, T>(&m, dirs, &mut out);
    measure_forward(m, dirs, &out)
}

fn coords(m: AnyMapping, n: usize) -> Vec<ChartUv> {
    let mut rng = SplitMix64::new(0xC0DE ^ m as u64);
    let mut v = Vec::with_capacity(n);
    while v.len() < n {
        let c = ChartUv::new(
            (rng.next_u64() % u64::from(m.chart_count())) as u32,
            rng.next_f64() as f32,
            rng.next_f64() as f32,
        );
        if m.in_chart(c.chart, c.u, c.v) {
            v.push(c);
        }
    }
    v
}

fn measure_inverse(m: AnyMapping, cs: &[ChartUv], out: &[Vec3]) -> (Worst, Worst) {
    // (whole chart, away from a sphere map's rim r ≥ 0.99)
    let (mut all, mut inner) = (Worst::default(), Worst::default());
    for (c, d) in cs.iter().zip(out) {
        let e = envmap_tests::angle(to_f64(*d), inverse_f64(m, *c));
        all.add(e, || format!("{c:?}"));
        let (a, b) = (2.0 * f64::from(c.u) - 1.0, 2.0 * f64::from(c.v) - 1.0);
        if a * a + b * b < 0.99 * 0.99
            || !matches!(m, AnyMapping::SphereMap | AnyMapping::SphereMapGl)
        {
            inner.add(e, || format!("{c:?}"));
        }
    }
    (all, inner)
}

fn simd_inverse<T: Tier>(m: AnyMapping, cs: &[ChartUv]) -> (Worst, Worst) {
    let mut out = vec![Vec3::ZERO; cs.len()];
    inverse_slice::<_, T>(&m, cs, &mut out);
    measure_inverse(m, cs, &out)
}

/// Bounds, per implementation: (forward |Δuv|, inverse rad away from a
/// sphere map's rim). Set at about 1.5–2× the worst seen with
/// `ENVMAP_EXTENSIVE=1`; the tier's function bound explains each.
fn bounds(name: &str) -> (f64, f64) {
    match name {
        "scalar" | "exact" => (4e-7, 1.5e-6),
        "fine" => (1.5e-6, 4e-6),
        _ => (6e-5, 6e-5),
    }
}

#[test]
fn every_mapping_against_f64() {
    let n = count();
    println!("| mapping | impl | forward max |Δuv| | texels (atlas 4096 wide) | at | inverse max rad | at | inverse rad (whole disk) |");
    println!("| --- | --- | ---: | ---: | --- | ---: | --- | ---: |");
    let mut failures = Vec::new();
    for m in AnyMapping::ALL {
        let dirs = directions(m, n);
        let cs = coords(m, n / 2);
        let scalar_fwd: Vec<ChartUv> = dirs.iter().map(|d| m.forward(*d).unwrap()).collect();
        let scalar_inv: Vec<Vec3> = cs.iter().map(|c| m.inverse(*c).unwrap()).collect();
        let rows = [
            (
                "scalar",
                measure_forward(m, &dirs, &scalar_fwd),
                measure_inverse(m, &cs, &scalar_inv),
            ),
            (
                "exact",
                simd_forward::<Exact>(m, &dirs),
                simd_inverse::<Exact>(m, &cs),
            ),
            (
                "fine",
                simd_forward::<Fine>(m, &dirs),
                simd_inverse::<Fine>(m, &cs),
            ),
            (
                "fast",
                simd_forward::<Fast>(m, &dirs),
                simd_inverse::<Fast>(m, &cs),
            ),
        ];
        for (name, (f, texels), (all, inner)) in rows {
            println!(
                "| {m} | {name} | {:.2e} | {:.4} | {} | {:.2e} | {} | {:.2e} |",
                f.err, texels, f.at, inner.err, inner.at, all.err
            );
            let (bf, bi) = bounds(name);
            if f.err > bf || inner.err > bi {
                failures.push(format!(
                    "{m} {name}: forward {:e} (bound {bf:e}), inverse {:e} (bound {bi:e})",
                    f.err, inner.err
                ));
            }
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

#[test]
fn references_agree_with_each_other() {
    // The f64 references are inverses of each other (guards the test itself).
    let mut rng = SplitMix64::new(3);
    for m in AnyMapping::ALL {
        for _ in 0..2000 {
            let d = rng.direction();
            let c = m.forward(d).unwrap();
            let (u, v) = forward_f64(m, c.chart, to_f64(d).normalize());
            let back = inverse_f64(m, ChartUv::new(c.chart, u as f32, v as f32));
            assert!(
                envmap_tests::angle(back, to_f64(d).normalize()) < 2e-5,
                "{m} {d}"
            );
        }
    }
}
