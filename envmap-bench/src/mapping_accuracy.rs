//! Worst-case error of every mapping — the scalar core or the SIMD kernels at
//! any tier — against an `f64` evaluation of the same formula.
//!
//! Forward error is measured two ways: `|Δ(u, v)|` against the `f64` forward
//! map of the same (`f32`) direction, also in texels of an atlas 4096 texels
//! wide (latlong's `Δu` is measured on the sphere, weighted by `sin θ` and
//! across the wrap, since `u` is undefined at the poles), and as an angle:
//! the `f64` inverse of the computed chart point against the direction.
//! Sphere maps skip directions within `1e-3` rad of their singular direction,
//! where the azimuth on the rim is ill-conditioned, and their forward error
//! in radians counts only points inside `r < 0.99` (the inverse magnifies
//! any `Δ(u, v)` without bound towards the rim). Inverse error is the
//! angle between the computed direction and the `f64` inverse of the same
//! (`f32`) chart point, away from a sphere map's rim (`r < 0.99`, where
//! `1 − r²` cancels) and on the whole chart.

use std::f64::consts::{PI, TAU};

use envmap_core::glam::{DVec3, Vec3};
use envmap_core::{AnyMapping, ChartUv, Lens, Mapping};

use crate::accuracy::SplitMix64;

/// The angle in radians between two non-zero vectors, in `f64`, as
/// `atan2(|a × b|, a · b)` (accurate for tiny and nearly opposite angles).
#[must_use]
pub fn angle(a: DVec3, b: DVec3) -> f64 {
    // Divided by the lengths (glam's `normalize` multiplies by the reciprocal).
    let (a, b) = (a / a.length(), b / b.length());
    a.cross(b).length().atan2(a.dot(b))
}

fn copysign(x: f64, s: f64) -> f64 {
    x.abs() * if s.is_sign_negative() { -1.0 } else { 1.0 }
}

/// The `f64` forward map of a unit direction, in the chart `chart` (charts
/// are decided by exact comparisons, identical in `f32` and `f64` away from
/// ties; the implementation's choice is the one being measured).
#[must_use]
pub fn forward_f64(m: AnyMapping, chart: u32, d: DVec3) -> (f64, f64) {
    let DVec3 { x, y, z } = d;
    match m {
        AnyMapping::LatLong => {
            let mut u = y.atan2(x) / TAU;
            if u < 0.0 {
                u += 1.0;
            }
            (u, x.hypot(y).atan2(z) / PI)
        }
        AnyMapping::Cube | AnyMapping::Eac => {
            let (sc, tc, ma) = match chart {
                0 => (-z, -y, x),
                1 => (z, -y, x),
                2 => (x, z, y),
                3 => (x, -z, y),
                4 => (x, -y, z),
                _ => (-x, -y, z),
            };
            let (s, t) = (sc / ma.abs(), tc / ma.abs());
            if m == AnyMapping::Eac {
                // Brown 2017: u = ½ + (2/π) atan(s).
                (0.5 + s.atan() * 2.0 / PI, 0.5 + t.atan() * 2.0 / PI)
            } else {
                (0.5 * (s + 1.0), 0.5 * (t + 1.0))
            }
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
        AnyMapping::Fisheye(f) => {
            let (side, axial) = if chart == 1 { (-1.0, -z) } else { (1.0, z) };
            let s = x.hypot(y);
            let theta = s.atan2(axial);
            let k = f.fov_degrees().to_radians() / 2.0;
            let r = match f.lens() {
                Lens::Equidistant => theta / k,
                Lens::Equisolid => (theta / 2.0).sin() / (k / 2.0).sin(),
            };
            let (a, b) = if s == 0.0 {
                (0.0, 0.0)
            } else {
                (r * x / s, r * y / s)
            };
            (0.5 + 0.5 * side * a, 0.5 - 0.5 * b)
        }
        AnyMapping::Angular => {
            let s = x.hypot(y);
            let rho = s.atan2(z) / PI;
            // x = y = 0: the azimuth of +x, as the core's rule.
            let (a, b) = if s == 0.0 {
                (rho, 0.0)
            } else {
                (rho * x / s, rho * y / s)
            };
            (0.5 * a + 0.5, 0.5 * b + 0.5)
        }
    }
}

/// The `f64` inverse map of a chart point (assumed inside its chart), a unit
/// vector.
#[must_use]
pub fn inverse_f64(m: AnyMapping, c: ChartUv) -> DVec3 {
    inverse_f64_at(m, c.chart, f64::from(c.u), f64::from(c.v))
}

fn inverse_f64_at(m: AnyMapping, chart: u32, u: f64, v: f64) -> DVec3 {
    let (a, b) = (2.0 * u - 1.0, 2.0 * v - 1.0);
    let [x, y, z] = match m {
        AnyMapping::LatLong => {
            let (phi, theta) = (TAU * u, PI * v);
            [
                theta.sin() * phi.cos(),
                theta.sin() * phi.sin(),
                theta.cos(),
            ]
        }
        AnyMapping::Cube | AnyMapping::Eac => {
            let (a, b) = if m == AnyMapping::Eac {
                // The plane coordinates of angles π/4 · (2u − 1).
                ((PI / 4.0 * a).tan(), (PI / 4.0 * b).tan())
            } else {
                (a, b)
            };
            match chart {
                0 => [1.0, -b, -a],
                1 => [-1.0, -b, a],
                2 => [a, 1.0, b],
                3 => [a, -1.0, -b],
                4 => [a, -b, 1.0],
                _ => [-a, -b, -1.0],
            }
        }
        AnyMapping::SphereMap | AnyMapping::SphereMapGl => {
            let sigma = if m == AnyMapping::SphereMap {
                -1.0
            } else {
                1.0
            };
            let r2 = a * a + b * b;
            let nz = (1.0 - r2).max(0.0).sqrt();
            [2.0 * a * nz, 2.0 * b * nz, sigma * (1.0 - 2.0 * r2)]
        }
        AnyMapping::DualParaboloid => {
            let r2 = a * a + b * b;
            let zz = (1.0 - r2).max(0.0);
            [2.0 * a, 2.0 * b, if chart == 1 { -zz } else { zz }]
        }
        AnyMapping::Tennisball => {
            let phi = (u - 0.5) * 1.5 * PI;
            let theta = (0.5 - v) * 0.5 * PI;
            if chart == 0 {
                [
                    theta.cos() * phi.sin(),
                    theta.sin(),
                    theta.cos() * phi.cos(),
                ]
            } else {
                [
                    theta.sin(),
                    theta.cos() * phi.sin(),
                    -theta.cos() * phi.cos(),
                ]
            }
        }
        AnyMapping::Octahedral => {
            let zz = 1.0 - a.abs() - b.abs();
            if zz < 0.0 {
                [copysign(1.0 - b.abs(), a), copysign(1.0 - a.abs(), b), zz]
            } else {
                [a, b, zz]
            }
        }
        AnyMapping::EqualAreaOctahedral => {
            let (au, av) = (a.abs(), b.abs());
            let sd = 1.0 - (au + av);
            let r = 1.0 - sd.abs();
            let phi = if r == 0.0 { 1.0 } else { (av - au) / r + 1.0 } * PI / 4.0;
            let zz = copysign(1.0 - r * r, sd);
            let k = r * (2.0 - r * r).max(0.0).sqrt();
            [copysign(phi.cos(), a) * k, copysign(phi.sin(), b) * k, zz]
        }
        AnyMapping::Fisheye(f) => {
            let (side, axial) = if chart == 1 { (-1.0, -1.0) } else { (1.0, 1.0) };
            // The lens's image has +y up: b = 1 − 2v.
            let b = -b;
            let r = a.hypot(b).min(1.0);
            let k = f.fov_degrees().to_radians() / 2.0;
            let theta = match f.lens() {
                Lens::Equidistant => r * k,
                Lens::Equisolid => 2.0 * (r * (k / 2.0).sin()).min(1.0).asin(),
            };
            let q = if r > 0.0 { theta.sin() / r } else { 0.0 };
            [side * q * a, q * b, axial * theta.cos()]
        }
        AnyMapping::Angular => {
            let rho = a.hypot(b).min(1.0);
            let theta = PI * rho;
            let k = if rho > 0.0 { theta.sin() / rho } else { PI };
            [k * a, k * b, theta.cos()]
        }
    };
    // Divided by the length (glam's `normalize` multiplies by the reciprocal).
    let d = DVec3::new(x, y, z);
    d / d.length()
}

/// A uniformly distributed unit direction rounded to `f32`.
fn random_direction(rng: &mut SplitMix64) -> Vec3 {
    let z = 1.0 - 2.0 * rng.next_f64();
    let r = (1.0 - z * z).max(0.0).sqrt();
    let (sp, cp) = (TAU * rng.next_f64()).sin_cos();
    Vec3::new((r * cp) as f32, (r * sp) as f32, z as f32)
}

/// A number of `m` for seeding: its index in [`AnyMapping::ALL`] (a fisheye not there takes
/// that of its kind).
fn seed_of(m: AnyMapping) -> u64 {
    let kind = match m {
        AnyMapping::Fisheye(f) if f.is_dual() => AnyMapping::Fisheye(envmap_core::Fisheye::DUAL),
        AnyMapping::Fisheye(_) => AnyMapping::Fisheye(envmap_core::Fisheye::SINGLE),
        m => m,
    };
    AnyMapping::ALL.iter().position(|a| *a == kind).unwrap_or(0) as u64
}

/// `n` uniform directions plus `3n/8` in thin bands at the poles and the
/// equator (where the formulas change branches), deterministic for each
/// mapping; a sphere map's are kept `1e-3` rad from its singular direction, and a fisheye's
/// only those it sees, `1e-5` rad inside its field of view.
#[must_use]
pub fn directions(m: AnyMapping, n: usize) -> Vec<Vec3> {
    let mut rng = SplitMix64(0x5EED ^ seed_of(m));
    let mut v: Vec<Vec3> = (0..n).map(|_| random_direction(&mut rng)).collect();
    for k in 0..n / 8 {
        let t = 1e-6 * (1.0 + k as f64);
        let phi = rng.next_f64() * TAU;
        let s = t.sin();
        for z in [t.cos(), -t.cos(), s] {
            let rho = (1.0 - z * z).sqrt();
            v.push(Vec3::new(
                (rho * phi.cos()) as f32,
                (rho * phi.sin()) as f32,
                z as f32,
            ));
        }
    }
    let singular = match m {
        AnyMapping::SphereMap => Some(DVec3::Z),
        AnyMapping::SphereMapGl => Some(DVec3::NEG_Z),
        _ => None,
    };
    v.retain(|d| singular.is_none_or(|s| angle(d.as_dvec3(), s) >= 1e-3));
    if let AnyMapping::Fisheye(f) = m {
        let k = f.fov_degrees().to_radians() / 2.0;
        v.retain(|d| {
            let d = d.as_dvec3();
            let axial = if f.is_dual() { d.z.abs() } else { d.z };
            d.x.hypot(d.y).atan2(axial) <= k - 1e-5
        });
    }
    v
}

/// `n` random chart points uniformly inside `m`'s charts.
#[must_use]
pub fn chart_points(m: AnyMapping, n: usize) -> Vec<ChartUv> {
    let mut rng = SplitMix64(0xC0DE ^ seed_of(m));
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

/// Chart size in texels when the whole atlas is `width` texels wide (at 4096:
/// a cube cross has 1024² faces, the paraboloid 2048² disks, the tennisball
/// 4096 × 1365 strips).
#[must_use]
pub fn chart_texels(m: AnyMapping, width: f64) -> (f64, f64) {
    let a = m.atlas();
    let w = width / f64::from(a.cols);
    (
        w,
        (w * f64::from(a.cell_aspect_h) / f64::from(a.cell_aspect_w)).floor(),
    )
}

/// Worst value and where it occurred.
#[derive(Clone, Debug, Default)]
pub struct Worst {
    /// The worst value.
    pub err: f64,
    /// The input where it occurred.
    pub at: String,
}

impl Worst {
    /// Records `e`; `at` describes the input and is only called for a new worst.
    pub fn add(&mut self, e: f64, at: impl FnOnce() -> String) {
        if e > self.err {
            self.err = e;
            self.at = at();
        }
    }
}

/// Forward errors of one implementation.
#[derive(Clone, Debug, Default)]
pub struct ForwardErrors {
    /// Worst `max(|Δu|, |Δv|)` and the direction.
    pub uv: Worst,
    /// Worst error in texels of an atlas 4096 texels wide.
    pub texels_4096: f64,
    /// Worst angle between the `f64` inverse of the computed point and the
    /// direction, in radians, and the direction; for the sphere maps only
    /// where the computed point is inside `r < 0.99` (towards the rim the
    /// inverse magnifies any `Δ(u, v)` without bound).
    pub rad: Worst,
    /// A direction whose chart was out of range, if any.
    pub bad_chart: Option<String>,
}

/// Inverse errors of one implementation.
#[derive(Clone, Debug, Default)]
pub struct InverseErrors {
    /// Worst angle in radians on the whole chart, and the chart point.
    pub all: Worst,
    /// The same away from a sphere map's rim (`r < 0.99`); the same as
    /// [`InverseErrors::all`] for every other mapping.
    pub inner: Worst,
}

/// Whether `c` is a sphere map's point with `r ≥ 0.99`.
fn near_rim(m: AnyMapping, c: ChartUv) -> bool {
    let (a, b) = (2.0 * f64::from(c.u) - 1.0, 2.0 * f64::from(c.v) - 1.0);
    matches!(m, AnyMapping::SphereMap | AnyMapping::SphereMapGl) && a * a + b * b >= 0.99 * 0.99
}

/// The forward errors of `out`, the images of `dirs` under `m` by some
/// implementation.
#[must_use]
pub fn measure_forward(m: AnyMapping, dirs: &[Vec3], out: &[ChartUv]) -> ForwardErrors {
    let (tw, th) = chart_texels(m, 4096.0);
    let mut e = ForwardErrors::default();
    for (d, c) in dirs.iter().zip(out) {
        if c.chart >= m.chart_count() {
            e.bad_chart.get_or_insert_with(|| format!("{d} gave {c:?}"));
            continue;
        }
        let dd = d.as_dvec3();
        let dd = dd / dd.length();
        let (u, v) = forward_f64(m, c.chart, dd);
        let mut du = (f64::from(c.u) - u).abs();
        if m == AnyMapping::LatLong {
            du = du.min(1.0 - du) * (PI * v).sin();
        }
        let dv = (f64::from(c.v) - v).abs();
        e.uv.add(du.max(dv), || format!("{d}"));
        e.texels_4096 = e.texels_4096.max(du * tw).max(dv * th);
        if !near_rim(m, *c) {
            e.rad.add(angle(inverse_f64(m, *c), dd), || format!("{d}"));
        }
    }
    e
}

/// The inverse errors of `out`, the images of `cs` under `m`'s inverse by
/// some implementation.
#[must_use]
pub fn measure_inverse(m: AnyMapping, cs: &[ChartUv], out: &[Vec3]) -> InverseErrors {
    let mut e = InverseErrors::default();
    for (c, d) in cs.iter().zip(out) {
        let err = angle(d.as_dvec3(), inverse_f64(m, *c));
        let err = if err.is_nan() { f64::INFINITY } else { err };
        e.all.add(err, || format!("{c:?}"));
        if !near_rim(m, *c) {
            e.inner.add(err, || format!("{c:?}"));
        }
    }
    e
}
