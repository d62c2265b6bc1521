//! Tier 1 of the shader tests: every mapping's WGSL (`envmap-core/shaders/`)
//! run forward and inverse on a Vulkan device (Mesa's lavapipe in CI)
//! through wgpu, over more than 10⁵ directions — a Fibonacci sphere, the
//! same scaled to tiny and huge lengths, the axes with every sign of zero,
//! the cube's face edges and corners and near-ties, the latlong seam and
//! poles, the octahedral folds, the tennisball's chart boundaries,
//! subnormal and mixed magnitudes, NaN, infinities and zero vectors — and
//! over chart points (the round trip's, a grid over every chart with its
//! edges, and bad points), into outputs that start as NaN, held to the
//! scalar core:
//!
//! * forward: the same chart, u and v within 2·10⁻⁶ ([`UV_BOUND`]) of the
//!   core's, the invalid ones invalid; the only exceptions are the
//!   documented disagreements below, each counted, and each checked to
//!   name the same direction;
//! * inverse: the same validity, directions within 10⁻⁶ rad
//!   ([`ANGLE_BOUND`]) of the core's.
//!
//! Documented disagreements (`docs/shaders.md`): a device may flush
//! subnormals to zero (lavapipe does), so for a direction with a subnormal
//! component the device's answer may be the core's answer for the direction
//! with those components zeroed (and invalid if that is the zero vector);
//! the tennisball's chart choice compares normalised components with √2/2
//! and 0, so next to those boundaries (within 10⁻⁶) the device may pick the
//! other chart, which must then hold the same direction; and a frame's
//! matrix product may give a zero component either sign (the core's
//! `x·1 + y·0 + z·0` turns −0 into +0, a device may keep it), which moves a
//! pole's u or picks the other image of a fold: the same direction again;
//! and next to a fisheye lens's rim (within 10⁻⁴ rad, [`FISHEYE_RIM`]) the
//! device may see a direction the core does not, or the reverse (the two
//! angles round apart at the limit k·(1 + 4ε)); further from it the unseen
//! directions are invalid on both.
//!
//! The fisheye lenses (one equidistant lens of 180° and two, two equisolid
//! lenses of 190°, one equidistant lens of 250°, one equisolid lens of
//! 360°) take the lens as arguments, and each adds directions of its own
//! either side of its rims; their bounds are tighter than the shared ones
//! (twice the worst measured on lavapipe).
//!
//! The worst cases and where they occur are printed
//! (`cargo test --release -p envmap-tests --test shader_mappings_gpu --
//! --nocapture`); `docs/design/shaders.md` has them.

mod gpu;

use envmap_core::shaders::ALL_WGSL;
use envmap_core::{
    normalize_direction, AnyMapping, ChartUv, Fisheye, Frame, Framed, Lens, Mapping,
};
use envmap_tests::{angle_f32, uniform_direction, wrapped_distance, SplitMix64};
use glam::Vec3;
use gpu::{bytes_u32, f32s, gpu, u32s, Binding, INDEX_WGSL};

/// The targets: forward (u, v) within this of the core (0.008 texel on a
/// 4096 map).
const UV_BOUND: f64 = 2e-6;
/// Inverse directions within this many radians of the core's.
const ANGLE_BOUND: f64 = 1e-6;
/// How close to a tennisball selection boundary (in the normalised
/// components) a chart may differ.
const TENNISBALL_TIE: f64 = 1e-6;
/// How close to a fisheye lens's rim (radians from the circle θ = k) the
/// device may see a direction the core does not, or the reverse.
const FISHEYE_RIM: f64 = 1e-4;

/// One mapping as the test runs it: the core's, and the WGSL expressions of
/// its forward of `d` and inverse of `c`.
struct Case {
    name: String,
    mapping: Box<dyn Mapping>,
    any: Option<AnyMapping>,
    forward: String,
    inverse: String,
    /// u wraps (0 ≡ 1): the latlong.
    wraps: bool,
    /// The frame the WGSL applies by `envmap_frame_to_canonical`.
    frame: Option<Frame>,
    /// Forward (u, v) within this of the core's ([`UV_BOUND`] unless the
    /// case says otherwise).
    uv_bound: f64,
    /// Inverse directions within this many radians of the core's
    /// ([`ANGLE_BOUND`] unless the case says otherwise).
    angle_bound: f64,
    /// Directions of the case's own, after the shared ones (a fisheye's rims).
    extra: Vec<Vec3>,
}

fn cases() -> Vec<Case> {
    let plain = |m: AnyMapping, f: &str, i: &str| Case {
        name: m.name().to_string(),
        mapping: Box::new(m),
        any: Some(m),
        forward: f.to_string(),
        inverse: i.to_string(),
        wraps: m == AnyMapping::LatLong,
        frame: None,
        uv_bound: UV_BOUND,
        angle_bound: ANGLE_BOUND,
        extra: Vec::new(),
    };
    let mut v = vec![
        plain(
            AnyMapping::LatLong,
            "envmap_latlong_forward(d)",
            "envmap_latlong_inverse(c)",
        ),
        plain(
            AnyMapping::Cube,
            "envmap_cube_forward(d)",
            "envmap_cube_inverse(c)",
        ),
        // The EAC's forward goes through common.wgsl's atan polynomial (WGSL's
        // atan is held to 4096 ULP only), its inverse through WGSL's tan (as
        // sin/cos, on [-pi/4, pi/4]); both are well inside the shared bounds
        // (lavapipe: 1.2e-7 in u, v, one ulp; 1.3e-7 rad).
        plain(
            AnyMapping::Eac,
            "envmap_eac_forward(d)",
            "envmap_eac_inverse(c)",
        ),
        plain(
            AnyMapping::SphereMap,
            "envmap_sphere_map_forward(d)",
            "envmap_sphere_map_inverse(c)",
        ),
        plain(
            AnyMapping::SphereMapGl,
            "envmap_sphere_map_gl_forward(d)",
            "envmap_sphere_map_gl_inverse(c)",
        ),
        plain(
            AnyMapping::DualParaboloid,
            "envmap_dual_paraboloid_forward(d)",
            "envmap_dual_paraboloid_inverse(c)",
        ),
        plain(
            AnyMapping::Tennisball,
            "envmap_tennisball_forward(d)",
            "envmap_tennisball_inverse(c)",
        ),
        plain(
            AnyMapping::Octahedral,
            "envmap_octahedral_forward(d)",
            "envmap_octahedral_inverse(c)",
        ),
        plain(
            AnyMapping::EqualAreaOctahedral,
            "envmap_equal_area_octahedral_forward(d)",
            "envmap_equal_area_octahedral_inverse(c)",
        ),
        plain(
            AnyMapping::Angular,
            "envmap_angular_forward(d)",
            "envmap_angular_inverse(c)",
        ),
        Case {
            name: "latlong, Y_UP_RH".to_string(),
            mapping: Box::new(Framed::new(envmap_core::LatLong, Frame::Y_UP_RH)),
            any: None,
            forward: "envmap_latlong_forward(envmap_frame_to_canonical(ENVMAP_FRAME_Y_UP_RH, d))"
                .to_string(),
            inverse: "envmap_frame_from_canonical(ENVMAP_FRAME_Y_UP_RH, envmap_latlong_inverse(c))"
                .to_string(),
            wraps: true,
            frame: Some(Frame::Y_UP_RH),
            uv_bound: UV_BOUND,
            angle_bound: ANGLE_BOUND,
            extra: Vec::new(),
        },
        Case {
            name: "octahedral, Y_UP_LH".to_string(),
            mapping: Box::new(Framed::new(envmap_core::Octahedral, Frame::Y_UP_LH)),
            any: None,
            forward:
                "envmap_octahedral_forward(envmap_frame_to_canonical(ENVMAP_FRAME_Y_UP_LH, d))"
                    .to_string(),
            inverse:
                "envmap_frame_from_canonical(ENVMAP_FRAME_Y_UP_LH, envmap_octahedral_inverse(c))"
                    .to_string(),
            wraps: false,
            frame: Some(Frame::Y_UP_LH),
            uv_bound: UV_BOUND,
            angle_bound: ANGLE_BOUND,
            extra: Vec::new(),
        },
    ];
    // The fisheye lenses: the lens passed as arguments (half the field of
    // view as its f32 bits, exactly the core's), its rims swept. Bounds
    // about twice the worst measured on lavapipe: forward 1.2e-7 in u, v
    // (one ulp) for every lens; inverse 1.4e-7 rad (180°, one lens or two),
    // 2.9e-7 (equisolid 190°), 1.5e-7 (equidistant 250°), 5.0e-7 (equisolid
    // 360°).
    for (f, uv_bound, angle_bound) in [
        (Fisheye::SINGLE, 2.5e-7, 3e-7),
        (Fisheye::DUAL, 2.5e-7, 3e-7),
        (fisheye(Lens::Equisolid, 190.0, true), 2.5e-7, 6e-7),
        (fisheye(Lens::Equidistant, 250.0, false), 2.5e-7, 3e-7),
        (fisheye(Lens::Equisolid, 360.0, false), 2.5e-7, 1e-6),
    ] {
        v.push(fisheye_case(f, uv_bound, angle_bound));
    }
    v
}

fn fisheye(lens: Lens, fov: f64, dual: bool) -> Fisheye {
    Fisheye::new(lens, fov, dual).expect("a field of view in (0°, 360°]")
}

/// The case of one fisheye: `envmap_fisheye_forward(d, k, equisolid, dual)`
/// and its inverse.
fn fisheye_case(f: Fisheye, uv_bound: f64, angle_bound: f64) -> Case {
    let args = format!(
        "bitcast<f32>({:#010x}u), {}, {}",
        f.half_fov().to_bits(),
        f.lens() == Lens::Equisolid,
        f.is_dual()
    );
    Case {
        name: format!(
            "{} {} {}°",
            f.name(),
            match f.lens() {
                Lens::Equidistant => "equidistant",
                Lens::Equisolid => "equisolid",
            },
            f.fov_degrees()
        ),
        mapping: Box::new(f),
        any: Some(AnyMapping::Fisheye(f)),
        forward: format!("envmap_fisheye_forward(d, {args})"),
        inverse: format!("envmap_fisheye_inverse(c, {args})"),
        wraps: false,
        frame: None,
        uv_bound,
        angle_bound,
        extra: rim_directions(f),
    }
}

/// Directions at angles k + δ from each lens's axis (k half the field of
/// view; δ from −10⁻² to 10⁻² rad, 0 included), at 97 azimuths: either side
/// of where the core stops seeing.
fn rim_directions(f: Fisheye) -> Vec<Vec3> {
    let k = f64::from(f.half_fov());
    let mut v = Vec::new();
    let axes: &[f64] = if f.is_dual() { &[1.0, -1.0] } else { &[1.0] };
    for &axis in axes {
        let deltas = (-7..=-2).flat_map(|e| [-(10f64.powi(e)), 10f64.powi(e)]);
        for delta in deltas.chain([0.0]) {
            let theta = k + delta;
            if !(0.0..=std::f64::consts::PI).contains(&theta) {
                continue;
            }
            for j in 0..97 {
                let phi = std::f64::consts::TAU * (f64::from(j) + 0.25) / 97.0;
                let d = glam::DVec3::new(
                    theta.sin() * phi.cos(),
                    theta.sin() * phi.sin(),
                    axis * theta.cos(),
                );
                v.push(d.as_vec3());
            }
        }
    }
    v
}

/// How far `d` is from the rim of the lens that would see it (radians).
fn rim_distance(f: Fisheye, d: Vec3) -> f64 {
    let u = envmap_tests::unit_f64(d);
    let axial = if f.is_dual() && d.z < 0.0 { -u.z } else { u.z };
    let theta = u.x.hypot(u.y).atan2(axial);
    (theta - f64::from(f.half_fov())).abs()
}

/// The kernel of one case: forward of `dirs[i]`, inverse of `points[i]`,
/// every value passed as bits so that NaN payloads, subnormals and signed
/// zeros reach the functions as they are.
fn kernel(c: &Case) -> String {
    format!(
        "{ALL_WGSL}\n{INDEX_WGSL}
@group(0) @binding(0) var<storage, read> dirs: array<vec4<u32>>;
@group(0) @binding(1) var<storage, read> points: array<vec4<u32>>;
@group(0) @binding(2) var<storage, read_write> fwd_out: array<vec4<u32>>;
@group(0) @binding(3) var<storage, read_write> inv_out: array<vec4<f32>>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {{
    let i = test_index(gid);
    if i < arrayLength(&dirs) {{
        let d = bitcast<vec3<f32>>(dirs[i].xyz);
        let r = {fwd};
        fwd_out[i] = vec4<u32>(r.chart, bitcast<u32>(r.uv.x), bitcast<u32>(r.uv.y), 0u);
    }}
    if i < arrayLength(&points) {{
        let p = points[i];
        let c = EnvmapChartUv(p.x, bitcast<vec2<f32>>(p.yz));
        let r = {inv};
        inv_out[i] = vec4<f32>(r.dir, select(0.0, 1.0, r.valid));
    }}
}}
",
        fwd = c.forward,
        inv = c.inverse
    )
}

/// The directions: a Fibonacci sphere of 100 000 points, and the special
/// ones of the module docs.
fn directions() -> Vec<Vec3> {
    let n = 100_000;
    let golden = (1.0 + 5f64.sqrt()) / 2.0;
    let mut v: Vec<Vec3> = (0..n)
        .map(|k| {
            let s = (k as f64 + 0.5) / n as f64;
            let t = (k as f64 / golden).fract();
            uniform_direction(s, t).as_vec3()
        })
        .collect();
    let fib = v.clone();
    // Lengths from subnormal to huge, and mixed magnitudes.
    for (k, d) in fib.iter().enumerate().step_by(10) {
        let scale = [1e-30f32, 1e30, 1.7e38, 3e-39, 1e-44][k / 10 % 5];
        v.push(*d * scale);
        v.push(Vec3::new(d.x, d.y * 1e-30, d.z));
    }
    // The axes with every sign of zero, the zero vectors, and every vector
    // with components in {−1, −0, +0, 1}.
    let comps = [-1.0f32, -0.0, 0.0, 1.0];
    for x in comps {
        for y in comps {
            for z in comps {
                v.push(Vec3::new(x, y, z));
                v.push(Vec3::new(x * 3e38, y, z * 1e-38));
            }
        }
    }
    // Cube edges, corners and near-ties (one ulp either way), z over y over x.
    let up = |x: f32| f32::from_bits(x.to_bits() + 1);
    let down = |x: f32| f32::from_bits(x.to_bits() - 1);
    for a in [0.3f32, 0.7, 1.0] {
        for (p, q) in [(1.0, 1.0), (1.0, up(1.0)), (up(1.0), 1.0), (1.0, down(1.0))] {
            for s in [
                [1.0f32, 1.0, 1.0],
                [-1.0, 1.0, -1.0],
                [1.0, -1.0, 1.0],
                [-1.0, -1.0, -1.0],
            ] {
                v.push(Vec3::new(s[0] * p, s[1] * q, s[2] * a));
                v.push(Vec3::new(s[0] * p, s[1] * a, s[2] * q));
                v.push(Vec3::new(s[0] * a, s[1] * p, s[2] * q));
                v.push(Vec3::new(s[0] * p, s[1] * p, s[2] * q));
            }
        }
    }
    // The latlong seam (y = ±0 and ±tiny, x > 0) and next to the poles.
    for k in 0..200 {
        let z = -1.0 + 2.0 * (k as f32 + 0.5) / 200.0;
        let r = (1.0 - z * z).sqrt();
        for y in [0.0f32, -0.0, 1e-30, -1e-30, 1e-7, -1e-7, -1e-45] {
            v.push(Vec3::new(r, y, z));
            v.push(Vec3::new(-r, y, z));
        }
        let tiny = 10f32.powf(-(k as f32) * 0.19);
        v.push(Vec3::new(tiny, tiny * 0.3, 1.0));
        v.push(Vec3::new(-tiny, tiny, -1.0));
        v.push(Vec3::new(tiny * 0.7, -tiny, -1.0));
    }
    // Octahedral folds: x = ±0 or y = ±0 below the equator, and the equator z = ±0.
    for k in 0..400 {
        let t = (k as f32 + 0.5) / 400.0 * 2.0 - 1.0;
        let s = (1.0 - t * t).sqrt();
        for zero in [0.0f32, -0.0] {
            v.push(Vec3::new(zero, t, -s));
            v.push(Vec3::new(t, zero, -s));
            v.push(Vec3::new(t, s, zero));
            v.push(Vec3::new(s, t, zero));
        }
    }
    // The tennisball's boundaries: |b| or |a| at √2/2, c at 0.
    let h = std::f32::consts::FRAC_1_SQRT_2;
    for k in 0..400 {
        let phi = (k as f32 + 0.5) / 400.0 * std::f32::consts::TAU;
        for b in [h, up(h), down(h), -h] {
            let r = (1.0 - b * b).sqrt();
            v.push(Vec3::new(r * phi.cos(), b, r * phi.sin()));
            v.push(Vec3::new(b, r * phi.cos(), r * phi.sin()));
        }
    }
    // Random bit patterns (kept finite or not: the bad ones must be invalid).
    let mut rng = SplitMix64::new(0x5eed_5ade);
    for _ in 0..2000 {
        let b = rng.next_u64();
        v.push(Vec3::new(
            f32::from_bits(b as u32),
            f32::from_bits((b >> 32) as u32),
            f32::from_bits((b >> 16) as u32),
        ));
    }
    // NaN (both signs, payloads), infinities, beside finite components.
    for bad in [
        f32::NAN,
        -f32::NAN,
        f32::from_bits(0x7f80_0001),
        f32::INFINITY,
        f32::NEG_INFINITY,
    ] {
        v.push(Vec3::new(bad, 0.0, 1.0));
        v.push(Vec3::new(1.0, bad, 0.0));
        v.push(Vec3::new(0.0, 0.0, bad));
    }
    v
}

/// Chart points for the inverse: the core's forward of every direction, a
/// 129² grid over each chart with the edges exactly, and bad points.
fn points(m: &dyn Mapping, dirs: &[Vec3]) -> Vec<ChartUv> {
    let mut p: Vec<ChartUv> = dirs.iter().filter_map(|d| m.forward(*d)).collect();
    let n = 129;
    for chart in 0..m.chart_count() {
        for j in 0..n {
            for i in 0..n {
                p.push(ChartUv::new(
                    chart,
                    i as f32 / (n - 1) as f32,
                    j as f32 / (n - 1) as f32,
                ));
            }
        }
        for e in [-0.0f32, 1e-30, 0.5, 0.999_999_94] {
            for f in [0.0f32, 1.0, 0.25] {
                p.push(ChartUv::new(chart, e, f));
                p.push(ChartUv::new(chart, f, e));
            }
        }
    }
    let bad = [
        f32::NAN,
        -f32::NAN,
        f32::INFINITY,
        f32::NEG_INFINITY,
        -1e-30,
        f32::from_bits(1.0f32.to_bits() + 1),
        2.0,
    ];
    for b in bad {
        p.push(ChartUv::new(0, b, 0.5));
        p.push(ChartUv::new(0, 0.5, b));
    }
    for chart in [m.chart_count(), 6, 7, u32::MAX] {
        p.push(ChartUv::new(chart, 0.5, 0.5));
    }
    p
}

/// `d` with its subnormal components made zero (their signs kept), as a
/// device that flushes subnormals reads it.
fn flushed(d: Vec3) -> Vec3 {
    let f = |x: f32| {
        if x != 0.0 && x.abs() < f32::MIN_POSITIVE {
            0.0f32.copysign(x)
        } else {
            x
        }
    };
    Vec3::new(f(d.x), f(d.y), f(d.z))
}

fn has_subnormal(d: Vec3) -> bool {
    flushed(d) != d || [d.x, d.y, d.z].iter().any(|x| x.is_subnormal())
}

/// Whether `d` lies next to a tennisball selection boundary.
fn near_tennisball_boundary(d: Vec3) -> bool {
    let u = envmap_tests::unit_f64(d);
    let h = std::f64::consts::FRAC_1_SQRT_2;
    (u.y.abs() - h).abs() < TENNISBALL_TIE
        || (u.x.abs() - h).abs() < TENNISBALL_TIE
        || u.z.abs() < TENNISBALL_TIE
}

/// The (u, v) distance of two points of one chart, u wrapped if it wraps.
fn uv_error(a: ChartUv, b: ChartUv, wraps: bool) -> f64 {
    let du = if wraps {
        wrapped_distance(a.u, b.u)
    } else {
        (f64::from(a.u) - f64::from(b.u)).abs()
    };
    du.max((f64::from(a.v) - f64::from(b.v)).abs())
}

fn show(d: Vec3) -> String {
    format!("({:e}, {:e}, {:e})", d.x, d.y, d.z)
}

fn show_c(c: ChartUv) -> String {
    format!("({}, {:e}, {:e})", c.chart, c.u, c.v)
}

/// What one case measured.
#[derive(Default)]
struct Tally {
    forward_worst: (f64, String),
    forward_angle: (f64, String),
    inverse_worst: (f64, String),
    subnormal: usize,
    tennisball_ties: usize,
    frame_zeros: usize,
    /// Fisheye directions within [`FISHEYE_RIM`] of the rim that one side
    /// sees and the other does not.
    fisheye_rim: usize,
    /// The furthest of them from the rim (radians).
    fisheye_rim_worst: f64,
    /// Finite non-zero directions invalid on both (a fisheye's unseen ones).
    unseen: usize,
    failures: Vec<String>,
}

impl Tally {
    fn fail(&mut self, what: String) {
        if self.failures.len() < 12 {
            self.failures.push(what);
        }
    }
}

#[test]
fn every_mapping_on_the_gpu_against_the_core() {
    let g = gpu("shader mappings");
    let shared = directions();
    println!("{} directions", shared.len());
    assert!(shared.len() >= 100_000);
    let mut all_failures = Vec::new();
    let mut table = Vec::new();
    for case in cases() {
        let m = case.mapping.as_ref();
        let fisheye = match case.any {
            Some(AnyMapping::Fisheye(f)) => Some(f),
            _ => None,
        };
        let dirs: Vec<Vec3> = shared.iter().chain(&case.extra).copied().collect();
        let dir_bits: Vec<u32> = dirs
            .iter()
            .flat_map(|d| [d.x.to_bits(), d.y.to_bits(), d.z.to_bits(), 0])
            .collect();
        let pts = points(m, &dirs);
        let pt_bits: Vec<u32> = pts
            .iter()
            .flat_map(|c| [c.chart, c.u.to_bits(), c.v.to_bits(), 0])
            .collect();
        let t0 = std::time::Instant::now();
        let out = g.run(
            &kernel(&case),
            "main",
            &[
                Binding::Input(&bytes_u32(&dir_bits)),
                Binding::Input(&bytes_u32(&pt_bits)),
                Binding::Output(16 * dirs.len() as u64),
                Binding::Output(16 * pts.len() as u64),
            ],
            dirs.len().max(pts.len()) as u32,
        );
        let elapsed = t0.elapsed();
        let fwd = u32s(&out[0]);
        let inv = f32s(&out[1]);
        let mut t = Tally::default();
        // Forward.
        for (k, &d) in dirs.iter().enumerate() {
            let got = ChartUv::new(
                fwd[4 * k],
                f32::from_bits(fwd[4 * k + 1]),
                f32::from_bits(fwd[4 * k + 2]),
            );
            let want = m.forward(d);
            let sub = has_subnormal(d);
            let invalid = got.chart == u32::MAX && got.u == 0.0 && got.v == 0.0;
            let matches = |want: Option<ChartUv>| match want {
                None => invalid,
                Some(w) => w.chart == got.chart && uv_error(w, got, case.wraps) <= case.uv_bound,
            };
            if matches(want) {
                if want.is_none() && normalize_direction(d).is_some() {
                    t.unseen += 1;
                }
                if let Some(w) = want {
                    let e = uv_error(w, got, case.wraps);
                    if e > t.forward_worst.0 || t.forward_worst.1.is_empty() {
                        t.forward_worst = (
                            e,
                            format!(
                                "d = {} (core {}, device {})",
                                show(d),
                                show_c(w),
                                show_c(got)
                            ),
                        );
                    }
                    if let (Some(a), Some(b)) = (m.inverse(w), m.inverse(got)) {
                        let ang = angle_f32(a, b);
                        if ang > t.forward_angle.0 {
                            t.forward_angle = (ang, format!("d = {}", show(d)));
                        }
                    }
                }
                continue;
            }
            if sub && matches(m.forward(flushed(d))) {
                t.subnormal += 1;
                continue;
            }
            if case.any == Some(AnyMapping::Tennisball) && near_tennisball_boundary(d) {
                if let (Some(w), Some(back)) = (want, m.inverse(got)) {
                    let a = angle_f32(back, d);
                    if w.chart != got.chart && a < 1e-5 {
                        t.tennisball_ties += 1;
                        continue;
                    }
                }
            }
            if let Some(f) = fisheye {
                let rim = rim_distance(f, d);
                if want.is_none() != invalid && rim < FISHEYE_RIM {
                    t.fisheye_rim += 1;
                    t.fisheye_rim_worst = t.fisheye_rim_worst.max(rim);
                    continue;
                }
            }
            if let (Some(f), Some(w)) = (case.frame, want) {
                let m0 = d.abs().max_element();
                let canonical = f.to_canonical(d / m0);
                let zero = [canonical.x, canonical.y, canonical.z].contains(&0.0);
                if let (true, Some(a), Some(b)) = (zero, m.inverse(w), m.inverse(got)) {
                    if angle_f32(a, b) < ANGLE_BOUND {
                        t.frame_zeros += 1;
                        continue;
                    }
                }
            }
            t.fail(format!(
                "forward of {} (bits {:08x} {:08x} {:08x}): core {:?}, device {}",
                show(d),
                d.x.to_bits(),
                d.y.to_bits(),
                d.z.to_bits(),
                want.map(show_c),
                show_c(got)
            ));
        }
        // Inverse.
        for (k, &c) in pts.iter().enumerate() {
            let got = Vec3::new(inv[4 * k], inv[4 * k + 1], inv[4 * k + 2]);
            let valid = inv[4 * k + 3];
            let want = m.inverse(c);
            match (want, valid) {
                (None, 0.0) if got == Vec3::ZERO => {}
                (Some(w), 1.0) => {
                    let a = angle_f32(w, got);
                    let len = f64::from(got.length());
                    if a > t.inverse_worst.0 || t.inverse_worst.1.is_empty() {
                        t.inverse_worst = (
                            a,
                            format!("c = {} (core {}, device {})", show_c(c), show(w), show(got)),
                        );
                    }
                    if a > case.angle_bound || (len - 1.0).abs() > 1e-5 {
                        t.fail(format!(
                            "inverse of {}: core {}, device {} ({a:.3e} rad, length {len})",
                            show_c(c),
                            show(w),
                            show(got)
                        ));
                    }
                }
                _ => t.fail(format!(
                    "inverse of {} (bits {:08x} {:08x}): core {:?}, device {} valid {valid}",
                    show_c(c),
                    c.u.to_bits(),
                    c.v.to_bits(),
                    want.map(show),
                    show(got)
                )),
            }
        }
        println!(
            "{:>22}: {} directions, {} points, {:.2} s on the device and back",
            case.name,
            dirs.len(),
            pts.len(),
            elapsed.as_secs_f64()
        );
        let at = |(e, w): &(f64, String)| {
            if *e == 0.0 {
                "0 (equal everywhere)".to_string()
            } else {
                format!("{e:.3e} at {w}")
            }
        };
        println!("    forward worst |Δu|, |Δv|: {}", at(&t.forward_worst));
        println!(
            "    forward worst as an angle (rad): {}",
            at(&t.forward_angle)
        );
        println!("    inverse worst (rad): {}", at(&t.inverse_worst));
        println!(
            "    documented disagreements: {} subnormal, {} tennisball chart ties, {} signed zeros from a frame, {} seen on one side only within {FISHEYE_RIM:e} rad of a fisheye's rim",
            t.subnormal, t.tennisball_ties, t.frame_zeros, t.fisheye_rim
        );
        if let Some(f) = fisheye {
            println!(
                "    {} unseen directions invalid on both ({} of the case's own at its rims); \
                 seen on one side only at most {:.2e} rad from the rim",
                t.unseen,
                case.extra.len(),
                t.fisheye_rim_worst
            );
            if !f.covers_sphere() && t.unseen == 0 {
                t.fail("no unseen direction was tested".to_string());
            }
        }
        table.push(format!(
            "| {} | {:.2e} | {:.2e} | {:.2e} | {} | {} | {} | {} |",
            case.name,
            t.forward_worst.0,
            t.forward_angle.0,
            t.inverse_worst.0,
            t.subnormal,
            t.tennisball_ties,
            t.frame_zeros,
            t.fisheye_rim
        ));
        for f in &t.failures {
            all_failures.push(format!("{}: {f}", case.name));
        }
    }
    println!("| mapping | forward max |Δu|,|Δv| | forward as angle (rad) | inverse (rad) | subnormal | chart ties | frame zeros | fisheye rim |");
    for row in table {
        println!("{row}");
    }
    assert!(
        all_failures.is_empty(),
        "the device disagrees with the core:\n{}",
        all_failures.join("\n")
    );
}

/// `envmap_atan2f` on the device within the bound its emulation under
/// WGSL's rules gives (tier 0, `shader_sources.rs`), and the device's own
/// built-ins within what WGSL's accuracy rules allow them (so the portable
/// bounds of docs/shaders.md hold on it), each measured against f64 and
/// printed: atan2 (4096 ULP), sin and cos (2⁻¹¹ absolute on [−π, π]),
/// sqrt and inverseSqrt (inverseSqrt 2 ULP, sqrt inherited from
/// 1/inverseSqrt: 4.5 ULP); asin and acos are printed only (WGSL inherits
/// their bound from atan2(x, sqrt(1 − x²)), unbounded in absolute terms at
/// ±1), to say why the shaders do not call them.
#[test]
fn atan2f_and_the_device_builtins() {
    let g = gpu("shader built-ins");
    let n = 200_000usize;
    let mut input = Vec::with_capacity(2 * n);
    for k in 0..n {
        let t = (k as f64 + 0.5) / n as f64;
        // (y, x) round the circle at radius 10^(−3…3), and a sin/cos
        // argument in [−π, π] and an asin argument in [−1, 1] from the same t.
        let a = -std::f64::consts::PI + std::f64::consts::TAU * t;
        let r = 10f64.powf(-3.0 + 6.0 * ((k * 7919) % n) as f64 / n as f64);
        input.extend([
            (r * a.sin()) as f32,
            (r * a.cos()) as f32,
            a as f32,
            (-1.0 + 2.0 * t) as f32,
        ]);
    }
    let src = format!(
        "{ALL_WGSL}\n{INDEX_WGSL}
@group(0) @binding(0) var<storage, read> xs: array<vec4<f32>>;
@group(0) @binding(1) var<storage, read_write> out: array<vec4<f32>>;
@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {{
    let i = test_index(gid);
    if i >= arrayLength(&xs) {{
        return;
    }}
    let p = xs[i];
    out[2u * i] = vec4<f32>(envmap_atan2f(p.x, p.y), atan2(p.x, p.y), sin(p.z), cos(p.z));
    out[2u * i + 1u] = vec4<f32>(asin(p.w), acos(p.w), sqrt(abs(p.z)), inverseSqrt(abs(p.z)));
}}
"
    );
    let out = g.run(
        &src,
        "main",
        &[
            Binding::Input(&gpu::bytes_f32(&input)),
            Binding::Output(32 * n as u64),
        ],
        n as u32,
    );
    let o = f32s(&out[0]);
    let ulp = |x: f64| {
        f64::from(f32::EPSILON)
            * 2f64.powi(x.abs().max(f64::from(f32::MIN_POSITIVE)).log2().floor() as i32)
    };
    let names = [
        "envmap_atan2f (rad)",
        "atan2 (ULP)",
        "sin (abs)",
        "cos (abs)",
        "asin (rad)",
        "acos (rad)",
        "sqrt (ULP)",
        "inverseSqrt (ULP)",
    ];
    let mut worst = [(0.0f64, 0usize); 8];
    for k in 0..n {
        let [y, x, a, s] = [
            input[4 * k],
            input[4 * k + 1],
            input[4 * k + 2],
            input[4 * k + 3],
        ]
        .map(f64::from);
        let want = [
            y.atan2(x),
            y.atan2(x),
            a.sin(),
            a.cos(),
            s.asin(),
            s.acos(),
            a.abs().sqrt(),
            1.0 / a.abs().sqrt(),
        ];
        for j in 0..8 {
            let got = f64::from(o[8 * k + j]);
            let err = (got - want[j]).abs();
            let e = match j {
                1 | 6 | 7 => err / ulp(want[j]),
                _ => err,
            };
            let e = if e.is_nan() && want[j].is_finite() {
                f64::INFINITY
            } else {
                e
            };
            if e > worst[j].0 {
                worst[j] = (e, k);
            }
        }
    }
    for (name, (e, k)) in names.iter().zip(&worst) {
        println!(
            "device {name}: worst {e:.3e} at input {:?}",
            &input[4 * k..4 * k + 4]
        );
    }
    assert!(worst[0].0 <= 3.5e-7, "envmap_atan2f: {:?}", worst[0]);
    assert!(
        worst[1].0 <= 4096.0,
        "the device's atan2 breaks WGSL's 4096 ULP: {:?}",
        worst[1]
    );
    assert!(
        worst[2].0 <= 2f64.powi(-11) && worst[3].0 <= 2f64.powi(-11),
        "sin/cos beyond 2^-11"
    );
    assert!(
        worst[6].0 <= 4.5 && worst[7].0 <= 2.0,
        "sqrt/inverseSqrt beyond WGSL's bounds"
    );
}
