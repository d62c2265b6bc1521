//! Shared helpers for envmap's cross-crate tests.
//!
//! Reference geometry in f64 (angles between directions, uniform directions,
//! small rotations), builders for awkward `f32` inputs (denormals, signed
//! zeros, huge and mixed magnitudes, exact ties), a deterministic
//! pseudo-random generator for tests that must not depend on proptest's
//! seed, ulp distances, numerical integration and a recorder of worst cases
//! that property tests print when run with `--nocapture`.
//!
//! Nothing here depends on proptest (a dev-dependency of this crate): the
//! test files build their strategies from raw integers and floats and call
//! the builders below.
//!
//! The tests themselves are in `tests/tests/`: `core_contract.rs` (the mapping
//! contract, by property tests over every mapping), `core_named_cases.rs` (the
//! cube's face table, ties, poles, the tennisball erratum, the frame presets),
//! `bad_input.rs` (the bad-input matrix of `docs/bad-input.md`),
//! `simd_vs_scalar.rs` (every SIMD kernel against the core, lane by lane),
//! `approx_accuracy.rs`, `approx_fit.rs` and `mapping_accuracy.rs` (the tier
//! bounds, the committed coefficients and the mapping errors of
//! `docs/accuracy.md`) and `fuzz_regressions.rs` (inputs the fuzz targets
//! found). The README's Rust examples also run here, as doctests.
#![forbid(unsafe_code)]

use envmap_core::{AnyMapping, ChartUv};
use glam::{DVec3, Vec3};
use std::cell::RefCell;
use std::f64::consts::{PI, TAU};

/// 4π, the solid angle of the whole sphere.
pub const FOUR_PI: f64 = 4.0 * PI;

/// `v` normalised in f64.
///
/// Every finite `f32` squared fits in f64 (`f32::MAX² ≈ 1.2e77`, the
/// smallest denormal squared ≈ 2e-90), so no scaling is needed. Returns the
/// zero vector for the zero vector.
#[must_use]
pub fn unit_f64(v: Vec3) -> DVec3 {
    let d = v.as_dvec3();
    let len = d.length();
    if len == 0.0 {
        DVec3::ZERO
    } else {
        d / len
    }
}

/// The angle in radians between two non-zero vectors (any lengths), computed
/// in f64 as `atan2(|a × b|, a · b)`, which is accurate for tiny and for
/// nearly opposite angles alike.
#[must_use]
pub fn angle(a: DVec3, b: DVec3) -> f64 {
    // Divided by the lengths (glam's `normalize` multiplies by the reciprocal).
    let (a, b) = (a / a.length(), b / b.length());
    a.cross(b).length().atan2(a.dot(b))
}

/// [`angle`] between two `f32` vectors, computed in f64.
#[must_use]
pub fn angle_f32(a: Vec3, b: Vec3) -> f64 {
    angle(a.as_dvec3(), b.as_dvec3())
}

/// A unit direction in f64 from two numbers in `[0, 1]`, uniformly
/// distributed on the sphere when `s` and `t` are uniform:
/// z = 1 − 2s, φ = 2πt.
#[must_use]
pub fn uniform_direction(s: f64, t: f64) -> DVec3 {
    let z = 1.0 - 2.0 * s;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let (sp, cp) = (TAU * t).sin_cos();
    DVec3::new(r * cp, r * sp, z)
}

/// Two unit vectors that complete the unit vector `d` to an orthonormal basis.
#[must_use]
pub fn perpendicular_basis(d: DVec3) -> (DVec3, DVec3) {
    let helper = if d.x.abs() < 0.6 { DVec3::X } else { DVec3::Y };
    let e1 = d.cross(helper);
    let e1 = e1 / e1.length();
    let e2 = d.cross(e1);
    (e1, e2)
}

/// The unit vector `d` turned by `alpha` radians towards the tangent
/// direction at angle `psi` in the plane perpendicular to `d`.
#[must_use]
pub fn rotate_away(d: DVec3, psi: f64, alpha: f64) -> DVec3 {
    let (e1, e2) = perpendicular_basis(d);
    let t = e1 * psi.cos() + e2 * psi.sin();
    d * alpha.cos() + t * alpha.sin()
}

/// An awkward `f32` component for direction inputs, from a `kind` (taken
/// modulo 8), 32 random bits and a sign.
///
/// | kind | value |
/// | --- | --- |
/// | 0, 7 | uniform in [−1, 1] |
/// | 1 | magnitude 10^e, e uniform in [−30, 30] |
/// | 2 | a denormal (from the smallest up to just below `f32::MIN_POSITIVE`) |
/// | 3 | a zero (the sign picks +0 or −0) |
/// | 4 | huge: in [`f32::MAX`/2, `f32::MAX`] |
/// | 5 | any finite non-NaN `f32` bit pattern (every exponent equally likely) |
/// | 6 | exactly ±1 (so that components tie) |
#[must_use]
pub fn awkward_component(kind: u8, bits: u32, negative: bool) -> f32 {
    let frac = f64::from(bits) / 4_294_967_296.0;
    let magnitude = match kind % 8 {
        1 => 10f64.powf(-30.0 + 60.0 * frac) as f32,
        2 => f32::from_bits(1 + bits % 0x007f_ffff),
        3 => 0.0,
        4 => (f64::from(f32::MAX) * (0.5 + 0.5 * frac)) as f32,
        5 => {
            // Exponent field at most 0xfe: finite.
            let b = bits & 0x7fff_ffff;
            let b = if b >> 23 == 0xff { b & 0x7f7f_ffff } else { b };
            f32::from_bits(b)
        }
        6 => 1.0,
        _ => frac as f32,
    };
    if negative {
        -magnitude
    } else {
        magnitude
    }
}

/// Makes the magnitudes of some components of `v` equal, keeping their signs,
/// so that the cube's tie rule and similar boundaries get exercised.
///
/// `tie % 8`: 0–2 leave `v` alone; 3: |y| = |x|; 4: |z| = |x|; 5: |z| = |y|;
/// 6: |y| = |z| = |x|; 7: |x| = |y| = |z| = the largest of the three.
#[must_use]
pub fn with_ties(v: Vec3, tie: u8) -> Vec3 {
    let (x, y, z) = (v.x, v.y, v.z);
    let m = x.abs().max(y.abs()).max(z.abs());
    match tie % 8 {
        3 => Vec3::new(x, x.abs().copysign(y), z),
        4 => Vec3::new(x, y, x.abs().copysign(z)),
        5 => Vec3::new(x, y, y.abs().copysign(z)),
        6 => Vec3::new(x, x.abs().copysign(y), x.abs().copysign(z)),
        7 => Vec3::new(m.copysign(x), m.copysign(y), m.copysign(z)),
        _ => v,
    }
}

/// `v`, or, if it is the zero vector, `v` with its z replaced by the smallest
/// denormal (keeping z's sign), so strategies need not reject.
#[must_use]
pub fn nonzero(v: Vec3) -> Vec3 {
    if v.x == 0.0 && v.y == 0.0 && v.z == 0.0 {
        Vec3::new(v.x, v.y, f32::from_bits(1).copysign(v.z))
    } else {
        v
    }
}

/// The position of `x` on the line of `f32` values, such that neighbouring
/// floats differ by 1 and both zeros are 0.
#[must_use]
pub fn ordinal(x: f32) -> i64 {
    let b = x.to_bits();
    let magnitude = i64::from(b & 0x7fff_ffff);
    if b >> 31 == 1 {
        -magnitude
    } else {
        magnitude
    }
}

/// How many `f32` steps (ulps) `x` lies outside `[lo, hi]`: 0 inside, and
/// `u64::MAX` for NaN.
#[must_use]
pub fn ulps_outside(x: f32, lo: f32, hi: f32) -> u64 {
    if x.is_nan() {
        return u64::MAX;
    }
    let (k, klo, khi) = (ordinal(x), ordinal(lo), ordinal(hi));
    if k < klo {
        (klo - k).unsigned_abs()
    } else if k > khi {
        (k - khi).unsigned_abs()
    } else {
        0
    }
}

/// The Euclidean distance between the `(u, v)` of two chart points, in f64
/// (the charts are not compared).
#[must_use]
pub fn uv_distance(a: ChartUv, b: ChartUv) -> f64 {
    let du = f64::from(a.u) - f64::from(b.u);
    let dv = f64::from(a.v) - f64::from(b.v);
    du.hypot(dv)
}

/// The distance between two values of a coordinate that wraps around
/// (0 ≡ 1): `min(|a − b|, 1 − |a − b|)`.
#[must_use]
pub fn wrapped_distance(a: f32, b: f32) -> f64 {
    let d = (f64::from(a) - f64::from(b)).abs();
    d.min(1.0 - d)
}

/// SplitMix64 (Steele, Lea & Flood 2014): a tiny deterministic generator for
/// tests whose inputs must not depend on proptest's seed.
#[derive(Clone, Debug)]
pub struct SplitMix64 {
    state: u64,
}

impl SplitMix64 {
    /// A generator started from `seed`.
    #[must_use]
    pub fn new(seed: u64) -> Self {
        Self { state: seed }
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// A uniform number in `[0, 1)` with 53 random bits.
    pub fn next_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// A uniformly distributed unit direction, rounded to `f32`.
    pub fn direction(&mut self) -> Vec3 {
        let (s, t) = (self.next_f64(), self.next_f64());
        uniform_direction(s, t).as_vec3()
    }
}

/// The positive nodes and weights of the 8-point Gauss–Legendre rule on [−1, 1].
const GAUSS_LEGENDRE_8: [(f64, f64); 4] = [
    (0.183_434_642_495_649_8, 0.362_683_783_378_362),
    (0.525_532_409_916_329, 0.313_706_645_877_887_3),
    (0.796_666_477_413_626_7, 0.222_381_034_453_374_5),
    (0.960_289_856_497_536_3, 0.101_228_536_290_376_3),
];

/// `∫∫ f(u, v) du dv` over `[u0, u1] × [v0, v1]` by the 8-point
/// Gauss–Legendre rule on a `panels × panels` grid of sub-rectangles.
///
/// For an analytic integrand (such as the cube's area element over a texel)
/// a few panels already give close to f64 precision.
#[must_use]
pub fn integrate_2d(
    f: impl Fn(f64, f64) -> f64,
    u0: f64,
    u1: f64,
    v0: f64,
    v1: f64,
    panels: u32,
) -> f64 {
    let nodes: Vec<(f64, f64)> = GAUSS_LEGENDRE_8
        .iter()
        .flat_map(|&(x, w)| [(-x, w), (x, w)])
        .collect();
    let n = f64::from(panels);
    let (hu, hv) = ((u1 - u0) / n, (v1 - v0) / n);
    let mut total = 0.0;
    for pi in 0..panels {
        for pj in 0..panels {
            let cu = u0 + (f64::from(pi) + 0.5) * hu;
            let cv = v0 + (f64::from(pj) + 0.5) * hv;
            let mut sum = 0.0;
            for &(xu, wu) in &nodes {
                for &(xv, wv) in &nodes {
                    sum += wu * wv * f(cu + 0.5 * hu * xu, cv + 0.5 * hv * xv);
                }
            }
            total += sum * 0.25 * hu * hv;
        }
    }
    total
}

/// The cube face's solid-angle density in its `(u, v)` coordinates: with
/// sc = 2u − 1 and tc = 2v − 1, dΩ = dsc dtc / (1 + sc² + tc²)^{3/2}
/// = 4 du dv / (1 + sc² + tc²)^{3/2} (the gnomonic area element).
#[must_use]
pub fn cube_area_element(u: f64, v: f64) -> f64 {
    let (sc, tc) = (2.0 * u - 1.0, 2.0 * v - 1.0);
    4.0 / (1.0 + sc * sc + tc * tc).powf(1.5)
}

/// A compensated (Neumaier) sum, so that adding up tens of thousands of
/// texel solid angles does not itself add rounding error worth measuring.
#[derive(Clone, Copy, Debug, Default)]
pub struct Sum {
    sum: f64,
    compensation: f64,
}

impl Sum {
    /// Adds `x`.
    pub fn add(&mut self, x: f64) {
        let t = self.sum + x;
        if self.sum.abs() >= x.abs() {
            self.compensation += (self.sum - t) + x;
        } else {
            self.compensation += (x - t) + self.sum;
        }
        self.sum = t;
    }

    /// The sum so far.
    #[must_use]
    pub fn value(&self) -> f64 {
        self.sum + self.compensation
    }
}

/// Records, per slot (usually per mapping), the largest value seen and a
/// description of the input that produced it; [`Worst::report`] prints the
/// table (visible with `cargo test -- --nocapture`).
///
/// Property tests record their measured errors here, so that the bounds they
/// state can be checked against what a long run (`PROPTEST_CASES=200000`)
/// actually reaches.
#[derive(Debug)]
pub struct Worst {
    slots: RefCell<Vec<(f64, String)>>,
    names: Vec<String>,
}

impl Worst {
    /// A recorder with one slot per name.
    #[must_use]
    pub fn new<S: ToString>(names: &[S]) -> Self {
        Self {
            slots: RefCell::new(vec![(f64::NEG_INFINITY, String::new()); names.len()]),
            names: names.iter().map(ToString::to_string).collect(),
        }
    }

    /// A recorder with one slot per mapping of [`AnyMapping::ALL`].
    #[must_use]
    pub fn per_mapping() -> Self {
        Self::new(&AnyMapping::NAMES)
    }

    /// Records `value` in `slot`; `what` describes the input and is only
    /// evaluated when `value` is a new worst.
    pub fn record(&self, slot: usize, value: f64, what: impl FnOnce() -> String) {
        let mut slots = self.slots.borrow_mut();
        if value > slots[slot].0 {
            slots[slot] = (value, what());
        }
    }

    /// Prints one line per slot with a recorded value.
    pub fn report(&self, title: &str) {
        println!("{title}");
        for (name, (value, what)) in self.names.iter().zip(self.slots.borrow().iter()) {
            if value.is_finite() {
                println!("  {name:>22}: {value:.3e}  at {what}");
            }
        }
    }
}

// ---------------------------------------------------------------------------
// SIMD against scalar: the agreement every lane must show

/// Whether `m`'s SIMD kernels use no trigonometry (cube, sphere maps,
/// paraboloid, plain octahedral): they evaluate the same operations in the
/// same order as the core and must agree with it bit for bit at every tier.
#[must_use]
pub fn simd_matches_bitwise(m: AnyMapping) -> bool {
    matches!(
        m,
        AnyMapping::Cube
            | AnyMapping::SphereMap
            | AnyMapping::SphereMapGl
            | AnyMapping::DualParaboloid
            | AnyMapping::Octahedral
    )
}

/// The documented worst error of a tier's functions, in radians, by
/// [`envmap_simd::Tier::NAME`]: exact 5e-7, fine 2e-6, fast 1e-4.
#[must_use]
pub fn tier_bound(tier: &str) -> f32 {
    match tier {
        "exact" => 5e-7,
        "fine" => 2e-6,
        _ => 1e-4,
    }
}

/// Bound on |Δu| and |Δv| between a SIMD forward lane at `tier` and the
/// scalar core: the mappings scale an angle error by at most 1/π (latlong v,
/// equal-area φ·2/π·½, angular θ/π·½) or 2/π (tennisball v) into (u, v), so
/// `tier + 1e-6` bounds every coordinate.
#[must_use]
pub fn simd_uv_bound(tier: &str) -> f32 {
    tier_bound(tier) + 1e-6
}

/// Bound on the angle in radians between a SIMD inverse lane at `tier` and
/// the scalar core: inverses combine two `sin_cos` results, so
/// `3·tier + 1e-6`.
#[must_use]
pub fn simd_angle_bound(tier: &str) -> f64 {
    f64::from(3.0 * tier_bound(tier) + 1e-6)
}

/// Checks one SIMD forward lane `got` (at tier `tier`) for direction `d`
/// against the scalar core: an invalid lane ([`envmap_simd::INVALID_CHART`],
/// NaN u and v) exactly where the core gives `None`; otherwise the same
/// chart, u and v inside `[0, 1]`, and u, v within [`simd_uv_bound`] (bit for
/// bit for the mappings of [`simd_matches_bitwise`]; latlong's u wraps).
///
/// # Errors
///
/// A message describing the disagreement.
pub fn check_simd_forward(m: AnyMapping, tier: &str, d: Vec3, got: ChartUv) -> Result<(), String> {
    let at = || format!("{m} {tier} forward {d:?}");
    let want = m.forward(d);
    // Within a tier's error of a fisheye's rim, the tier may decide either way.
    if want.is_none() != (got.chart == envmap_simd::INVALID_CHART)
        && past_rim(m, d).is_some_and(|p| p.abs() < 1e-3)
    {
        return Ok(());
    }
    let Some(want) = want else {
        if got.chart != envmap_simd::INVALID_CHART || !got.u.is_nan() || !got.v.is_nan() {
            return Err(format!("{}: expected an invalid lane, got {got:?}", at()));
        }
        return Ok(());
    };
    if got.chart != want.chart {
        return Err(format!("{}: chart {} vs scalar {want:?}", at(), got.chart));
    }
    if simd_matches_bitwise(m) {
        if (got.u.to_bits(), got.v.to_bits()) != (want.u.to_bits(), want.v.to_bits()) {
            return Err(format!("{}: {got:?} vs scalar {want:?} (bitwise)", at()));
        }
        return Ok(());
    }
    if !(0.0..=1.0).contains(&got.u) || !(0.0..=1.0).contains(&got.v) {
        return Err(format!("{}: {got:?} out of range", at()));
    }
    let du = if m == AnyMapping::LatLong {
        wrapped_distance(got.u, want.u)
    } else {
        (f64::from(got.u) - f64::from(want.u)).abs()
    };
    let e = du.max((f64::from(got.v) - f64::from(want.v)).abs());
    let bound = f64::from(simd_uv_bound(tier));
    if e > bound {
        return Err(format!(
            "{}: {got:?} vs scalar {want:?}: |Δuv| {e:e} > {bound:e}",
            at()
        ));
    }
    Ok(())
}

/// For a fisheye that does not cover the sphere, the angle (rad, in f64) by which the
/// direction `d` lies past the rim of what it sees (negative inside); `None` for every other
/// mapping and for a NaN, infinite or zero `d`.
#[must_use]
pub fn past_rim(m: AnyMapping, d: Vec3) -> Option<f64> {
    let AnyMapping::Fisheye(f) = m else {
        return None;
    };
    if f.covers_sphere() || !d.is_finite() || d == Vec3::ZERO {
        return None;
    }
    let scale = d.abs().max_element();
    let (x, y, z) = (
        f64::from(d.x / scale),
        f64::from(d.y / scale),
        f64::from(d.z / scale),
    );
    let axial = if f.is_dual() { z.abs() } else { z };
    Some(x.hypot(y).atan2(axial) - f.fov_degrees().to_radians() / 2.0)
}

/// Checks one SIMD inverse lane `got` (at tier `tier`) for chart point `c`
/// against the scalar core: all three components NaN exactly where the core
/// gives `None`; otherwise a finite direction within [`simd_angle_bound`]
/// of the core's.
///
/// # Errors
///
/// A message describing the disagreement.
pub fn check_simd_inverse(m: AnyMapping, tier: &str, c: ChartUv, got: Vec3) -> Result<(), String> {
    let at = || format!("{m} {tier} inverse {c:?}");
    let Some(want) = m.inverse(c) else {
        if !(got.x.is_nan() && got.y.is_nan() && got.z.is_nan()) {
            return Err(format!("{}: expected NaN, got {got}", at()));
        }
        return Ok(());
    };
    if !got.is_finite() {
        return Err(format!("{}: got {got}, scalar {want}", at()));
    }
    let e = angle_f32(got, want);
    let bound = simd_angle_bound(tier);
    if e > bound {
        return Err(format!(
            "{}: {got} vs scalar {want}: angle {e:e} > {bound:e}",
            at()
        ));
    }
    Ok(())
}

/// The README's examples, compiled and run as doctests.
#[cfg(doctest)]
#[doc = include_str!("../../README.md")]
struct ReadmeDoctests;

/// Bytes (a process's output) as text, for test messages.
#[must_use]
pub fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

/// The names in a directory, sorted (panics if it cannot be read: a test
/// helper).
#[must_use]
pub fn entries(dir: &std::path::Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .expect("read the directory")
        .map(|e| {
            e.expect("a directory entry")
                .file_name()
                .to_string_lossy()
                .into_owned()
        })
        .collect();
    v.sort();
    v
}
