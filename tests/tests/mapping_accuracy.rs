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

use envmap_bench::mapping_accuracy::{
    chart_points, directions, forward_f64, inverse_f64, measure_forward, measure_inverse,
    ForwardErrors, InverseErrors,
};
use envmap_core::glam::Vec3;
use envmap_core::{AnyMapping, ChartUv};
use envmap_simd::{forward_slice, inverse_slice, Exact, Fast, Fine, Tier};
use envmap_tests::SplitMix64;

fn count() -> usize {
    if std::env::var("ENVMAP_EXTENSIVE").is_ok_and(|v| v == "1") {
        1 << 21
    } else {
        1 << 17
    }
}

fn simd_forward<T: Tier>(m: AnyMapping, dirs: &[Vec3]) -> ForwardErrors {
    let mut out = vec![ChartUv::default(); dirs.len()];
    forward_slice::<_, T>(&m, dirs, &mut out);
    measure_forward(m, dirs, &out)
}

fn simd_inverse<T: Tier>(m: AnyMapping, cs: &[ChartUv]) -> InverseErrors {
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
        let cs = chart_points(m, n / 2);
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
        for (name, fwd, inv) in rows {
            assert!(fwd.bad_chart.is_none(), "{m} {name}: {:?}", fwd.bad_chart);
            let (f, inner, all) = (&fwd.uv, &inv.inner, &inv.all);
            println!(
                "| {m} | {name} | {:.2e} | {:.4} | {} | {:.2e} | {} | {:.2e} |",
                f.err, fwd.texels_4096, f.at, inner.err, inner.at, all.err
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
            // A fisheye under 360° sees only part of the sphere.
            let Some(c) = m.forward(d) else {
                assert!(!m.covers_sphere(), "{m} {d}");
                continue;
            };
            let dd = d.as_dvec3();
            let dd = dd / dd.length();
            let (u, v) = forward_f64(m, c.chart, dd);
            let back = inverse_f64(m, ChartUv::new(c.chart, u as f32, v as f32));
            assert!(envmap_tests::angle(back, dd) < 2e-5, "{m} {d}");
        }
    }
}
