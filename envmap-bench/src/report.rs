//! What `envmap-report` measures: every approximation and every mapping at
//! every tier, timed in one process beside its baselines, with its worst
//! error against an `f64` reference; the conversion and the renderer timed
//! once each. Rows print as Markdown tables or as JSON lines, and
//! [`check_json_lines`] verifies that a JSON-lines report is complete.

use std::collections::BTreeSet;
use std::fmt::Write as _;
use std::hint::black_box;

use envmap_core::glam::Vec3;
use envmap_core::{AnyMapping, Atlas, ChartUv, Frame};
use envmap_simd::{approx, forward_slice, inverse_slice, Exact, Fast, Fine, Tier};
use serde_json::{json, Value};
use wide::f32x8;

use crate::accuracy::{
    function_stats, std_kernel, tier_kernel, wide_kernel, Density, Function, Kernel, Stats,
};
use crate::mapping_accuracy::{self as ma, ForwardErrors, InverseErrors};
use crate::timing::{self, ns_per_element};

/// The SIMD tiers, in order of accuracy.
pub const TIERS: [&str; 3] = ["exact", "fine", "fast"];

/// The functions a report times (`sin_cos` is one function; its error is
/// the larger of `sin`'s and `cos`'s).
pub const FUNCTIONS: [&str; 5] = ["atan", "atan2", "asin", "acos", "sin_cos"];

/// How much a report measures.
#[derive(Clone, Debug)]
pub struct Settings {
    /// Timed passes per measurement (the median is reported).
    pub passes: usize,
    /// Elements per timed pass for functions and mappings (fits in L1).
    pub n_small: usize,
    /// A second, out-of-cache size for latlong and cube, if any.
    pub n_large: Option<usize>,
    /// Function sweep density.
    pub density: Density,
    /// Directions (and half as many chart points) per mapping accuracy run.
    pub mapping_points: usize,
    /// Conversion: input latlong width (height is half), output cube face edge.
    pub convert_size: (u32, u32),
    /// Render: image width and height, cube face edge of the environment.
    pub render_size: (u32, u32, u32),
    /// Passes for the conversion and the render.
    pub big_passes: usize,
}

impl Settings {
    /// Seconds: few passes, sparse sweeps, small images.
    #[must_use]
    pub fn quick() -> Self {
        Settings {
            passes: 7,
            n_small: 4096,
            n_large: None,
            density: Density::Quick,
            mapping_points: 1 << 11,
            convert_size: (256, 64),
            render_size: (160, 90, 64),
            big_passes: 2,
        }
    }

    /// About a minute: dense sweeps, many passes, an out-of-cache size, and
    /// the conversion (latlong 4096×2048 → cube 6×1024²) and render (teapot
    /// 1920×1080 in a 6×1024² cube) at the sizes their targets are set for.
    #[must_use]
    pub fn full() -> Self {
        Settings {
            passes: 101,
            n_small: 4096,
            n_large: Some(1 << 22),
            density: Density::Dense,
            mapping_points: 1 << 17,
            convert_size: (4096, 1024),
            render_size: (1920, 1080, 1024),
            big_passes: 9,
        }
    }
}

/// One measurement: a function, mapping, conversion or render at one tier
/// (or a baseline: `scalar`, `std`, `wide`, `copy`).
#[derive(Clone, Debug, Default)]
pub struct Row {
    /// `function`, `mapping`, `convert` or `render`.
    pub kind: &'static str,
    /// Function or mapping name (`atan2`, `latlong`), or what was converted
    /// or rendered.
    pub name: String,
    /// `exact`, `fine`, `fast`, or a baseline: `scalar` (the core), `std`,
    /// `wide`, `copy`.
    pub tier: &'static str,
    /// `forward` or `inverse` for mappings.
    pub direction: Option<&'static str>,
    /// Elements per timed pass.
    pub n: usize,
    /// Median nanoseconds per element.
    pub ns: f64,
    /// Median milliseconds per pass (conversion and render).
    pub ms: Option<f64>,
    /// Worst absolute error in radians (forward mappings: the angle between
    /// the input and the `f64` inverse of the computed point).
    pub max_abs_err: Option<f64>,
    /// Worst distance in ULP (functions).
    pub max_ulp: Option<u64>,
    /// Worst forward error in texels of an atlas 4096 texels wide.
    pub texels_4096: Option<f64>,
    /// Worst forward `max(|Δu|, |Δv|)`.
    pub max_uv_err: Option<f64>,
    /// Where the worst absolute error occurs.
    pub err_at: Option<String>,
    /// `std`'s scalar functions in a plain loop, same run, ns per element.
    pub std_ns: Option<f64>,
    /// The scalar core in a loop, same run, ns per element.
    pub scalar_ns: Option<f64>,
    /// A plain copy of the same bytes, same run, ns per element.
    pub copy_ns: Option<f64>,
    /// `wide`'s own `f32x8` function, same run, ns per element.
    pub wide_ns: Option<f64>,
}

impl Row {
    /// The row as one JSON object.
    #[must_use]
    pub fn to_json(&self) -> Value {
        json!({
            "kind": self.kind,
            "name": self.name,
            "tier": self.tier,
            "direction": self.direction,
            "n": self.n,
            "ns": self.ns,
            "ms": self.ms,
            "max_abs_err": self.max_abs_err,
            "max_ulp": self.max_ulp,
            "texels_4096": self.texels_4096,
            "max_uv_err": self.max_uv_err,
            "err_at": self.err_at,
            "std_ns": self.std_ns,
            "scalar_ns": self.scalar_ns,
            "copy_ns": self.copy_ns,
            "wide_ns": self.wide_ns,
        })
    }
}

/// A function's input domain for timing.
fn timing_domain(name: &str) -> (f32, f32) {
    match name {
        "atan" => (-20.0, 20.0),
        "asin" | "acos" => (-1.0, 1.0),
        "sin_cos" => (-std::f32::consts::TAU, std::f32::consts::TAU),
        _ => (-10.0, 10.0),
    }
}

fn batches(v: &[f32]) -> Vec<f32x8> {
    v.chunks_exact(8)
        .map(|c| f32x8::new(c.try_into().unwrap_or([0.0; 8])))
        .collect()
}

/// Inputs of one timed function pass: two argument arrays, as `f32x8` and as `f32`.
struct FnInput {
    a8: Vec<f32x8>,
    b8: Vec<f32x8>,
    a: Vec<f32>,
    b: Vec<f32>,
}

fn fn_input(name: &str, n: usize, pass: usize) -> FnInput {
    let (lo, hi) = timing_domain(name);
    let seed = (pass as u64).wrapping_mul(0x1000_0001) ^ name.len() as u64;
    let a = timing::uniform(seed, n, lo, hi);
    let b = timing::uniform(seed ^ 0xABCD, n, lo, hi);
    FnInput {
        a8: batches(&a),
        b8: batches(&b),
        a,
        b,
    }
}

/// A timed `f32x8` implementation of one of [`FUNCTIONS`].
#[derive(Clone, Copy)]
enum Timed {
    Unary(fn(f32x8) -> f32x8),
    Binary(fn(f32x8, f32x8) -> f32x8),
    Pair(fn(f32x8) -> (f32x8, f32x8)),
}

fn time_simd(s: &Settings, name: &str, k: Timed) -> f64 {
    let n = s.n_small;
    let mut out = vec![f32x8::ZERO; n / 8];
    let mut out2 = vec![f32x8::ZERO; n / 8];
    ns_per_element(
        s.passes,
        n,
        |p| fn_input(name, n, p),
        |i| {
            match k {
                Timed::Unary(f) => {
                    for (o, &x) in out.iter_mut().zip(&i.a8) {
                        *o = f(x);
                    }
                }
                Timed::Binary(f) => {
                    for ((o, &y), &x) in out.iter_mut().zip(&i.a8).zip(&i.b8) {
                        *o = f(y, x);
                    }
                }
                Timed::Pair(f) => {
                    for ((o, o2), &x) in out.iter_mut().zip(out2.iter_mut()).zip(&i.a8) {
                        (*o, *o2) = f(x);
                    }
                }
            }
            black_box((&out, &out2));
        },
    )
}

fn time_std(s: &Settings, name: &str) -> f64 {
    let n = s.n_small;
    let mut out = vec![0.0_f32; n];
    let mut out2 = vec![0.0_f32; n];
    ns_per_element(
        s.passes,
        n,
        |p| fn_input(name, n, p),
        |i| {
            match name {
                "atan" => out.iter_mut().zip(&i.a).for_each(|(o, x)| *o = x.atan()),
                "asin" => out.iter_mut().zip(&i.a).for_each(|(o, x)| *o = x.asin()),
                "acos" => out.iter_mut().zip(&i.a).for_each(|(o, x)| *o = x.acos()),
                "sin_cos" => {
                    for ((o, o2), x) in out.iter_mut().zip(out2.iter_mut()).zip(&i.a) {
                        (*o, *o2) = x.sin_cos();
                    }
                }
                _ => {
                    for ((o, y), x) in out.iter_mut().zip(&i.a).zip(&i.b) {
                        *o = y.atan2(*x);
                    }
                }
            }
            black_box((&out, &out2));
        },
    )
}

fn time_copy(s: &Settings, name: &str) -> f64 {
    let n = s.n_small;
    let mut out = vec![f32x8::ZERO; n / 8];
    let mut out2 = vec![f32x8::ZERO; n / 8];
    let binary = name == "atan2";
    ns_per_element(
        s.passes,
        n,
        |p| fn_input(name, n, p),
        |i| {
            out.copy_from_slice(&i.a8);
            if binary {
                out2.copy_from_slice(&i.b8);
            }
            black_box((&out, &out2));
        },
    )
}

fn tier_timed<T: Tier>(name: &str) -> Timed {
    match name {
        "atan" => Timed::Unary(approx::atan::<T>),
        "asin" => Timed::Unary(approx::asin::<T>),
        "acos" => Timed::Unary(approx::acos::<T>),
        "sin_cos" => Timed::Pair(approx::sin_cos::<T>),
        _ => Timed::Binary(approx::atan2::<T>),
    }
}

fn wide_timed(name: &str) -> Timed {
    match name {
        "atan" => Timed::Unary(f32x8::atan),
        "asin" => Timed::Unary(f32x8::asin),
        "acos" => Timed::Unary(f32x8::acos),
        "sin_cos" => Timed::Pair(f32x8::sin_cos),
        _ => Timed::Binary(f32x8::atan2),
    }
}

/// The sweep stats of a timed function (`sin_cos`: the worse of `sin` and `cos`).
fn fn_stats(name: &str, kernel: impl Fn(Function) -> Kernel, density: Density) -> Stats {
    let functions: &[Function] = match name {
        "atan" => &[Function::Atan],
        "asin" => &[Function::Asin],
        "acos" => &[Function::Acos],
        "sin_cos" => &[Function::Sin, Function::Cos],
        _ => &[Function::Atan2],
    };
    let mut st = Stats::EMPTY;
    for &f in functions {
        st.merge(&function_stats(f, kernel(f), density));
    }
    st
}

fn at_text(name: &str, at: (f32, f32)) -> String {
    if name == "atan2" {
        format!("(y, x) = ({:e}, {:e})", at.0, at.1)
    } else {
        format!("x = {:e}", at.0)
    }
}

/// A function implementation: tier name, timed kernel, swept kernel.
type Impl = (&'static str, Timed, fn(Function) -> Kernel);

/// Times and sweeps every function at every tier, with `wide`, `std` and
/// copy baselines (also as rows of their own, tiers `wide` and `std`).
#[must_use]
pub fn functions(s: &Settings) -> Vec<Row> {
    let mut rows = Vec::new();
    for name in FUNCTIONS {
        let std_ns = time_std(s, name);
        let copy_ns = time_copy(s, name);
        let wide_ns = time_simd(s, name, wide_timed(name));
        let impls: [Impl; 5] = [
            ("exact", tier_timed::<Exact>(name), tier_kernel::<Exact>),
            ("fine", tier_timed::<Fine>(name), tier_kernel::<Fine>),
            ("fast", tier_timed::<Fast>(name), tier_kernel::<Fast>),
            ("wide", wide_timed(name), wide_kernel),
            ("std", Timed::Unary(|x| x), std_kernel),
        ];
        for (tier, timed, kernel) in impls {
            let ns = match tier {
                "wide" => wide_ns,
                "std" => std_ns,
                _ => time_simd(s, name, timed),
            };
            let st = fn_stats(name, kernel, s.density);
            rows.push(Row {
                kind: "function",
                name: name.to_string(),
                tier,
                n: s.n_small,
                ns,
                max_abs_err: Some(st.max_abs),
                // Near the zeros of sin and cos, ULP says nothing about an
                // absolute-error tier.
                max_ulp: (name != "sin_cos" || matches!(tier, "exact" | "std"))
                    .then_some(st.max_ulp),
                err_at: Some(at_text(name, st.abs_at)),
                std_ns: Some(std_ns),
                copy_ns: Some(copy_ns),
                wide_ns: Some(wide_ns),
                ..Row::default()
            });
        }
    }
    rows
}

/// The seed's latlong with `std`'s scalar functions, in a plain loop (the
/// `std` baseline of the mappings).
pub fn std_latlong_forward(dirs: &[Vec3], out: &mut [ChartUv]) {
    use std::f32::consts::{PI, TAU};
    for (d, o) in dirs.iter().zip(out.iter_mut()) {
        let n = d.normalize();
        let mut u = n.y.atan2(n.x) / TAU;
        if u < 0.0 {
            u += 1.0;
        }
        *o = ChartUv::new(0, u, n.z.clamp(-1.0, 1.0).acos() / PI);
    }
}

/// The latlong inverse with `std`'s scalar `sin_cos`, in a plain loop.
pub fn std_latlong_inverse(cs: &[ChartUv], out: &mut [Vec3]) {
    use std::f32::consts::{PI, TAU};
    for (c, o) in cs.iter().zip(out.iter_mut()) {
        let (sp, cp) = (TAU * c.u).sin_cos();
        let (st, ct) = (PI * c.v).sin_cos();
        *o = Vec3::new(st * cp, st * sp, ct);
    }
}

/// Input sets for one mapping size: fresh per pass below 2^16 elements,
/// else two pre-made sets used in turn (making 2^22 directions per pass
/// would take longer than the kernels).
struct Inputs<T> {
    sets: Vec<Vec<T>>,
    fresh: Option<Box<dyn Fn(usize) -> Vec<T>>>,
}

impl<T: Clone> Inputs<T> {
    fn new(n: usize, make: impl Fn(usize) -> Vec<T> + 'static) -> Self {
        if n < 1 << 16 {
            Inputs {
                sets: Vec::new(),
                fresh: Some(Box::new(make)),
            }
        } else {
            Inputs {
                sets: vec![make(1), make(2)],
                fresh: None,
            }
        }
    }

    fn get(&self, pass: usize) -> std::borrow::Cow<'_, [T]> {
        match &self.fresh {
            Some(f) => std::borrow::Cow::Owned(f(pass)),
            None => std::borrow::Cow::Borrowed(&self.sets[pass % self.sets.len()]),
        }
    }
}

/// A mapping implementation over slices.
type SliceFn<I, O> = fn(AnyMapping, &[I], &mut [O]);
type ForwardFn = SliceFn<Vec3, ChartUv>;
type InverseFn = SliceFn<ChartUv, Vec3>;

fn fwd_scalar(m: AnyMapping, d: &[Vec3], o: &mut [ChartUv]) {
    for (d, o) in d.iter().zip(o.iter_mut()) {
        *o = m.forward(*d).unwrap_or_default();
    }
}
fn fwd_tier<T: Tier>(m: AnyMapping, d: &[Vec3], o: &mut [ChartUv]) {
    forward_slice::<_, T>(&m, d, o);
}
fn fwd_std(_: AnyMapping, d: &[Vec3], o: &mut [ChartUv]) {
    std_latlong_forward(d, o);
}
fn inv_scalar(m: AnyMapping, c: &[ChartUv], o: &mut [Vec3]) {
    for (c, o) in c.iter().zip(o.iter_mut()) {
        *o = m.inverse(*c).unwrap_or(Vec3::NAN);
    }
}
fn inv_tier<T: Tier>(m: AnyMapping, c: &[ChartUv], o: &mut [Vec3]) {
    inverse_slice::<_, T>(&m, c, o);
}
fn inv_std(_: AnyMapping, c: &[ChartUv], o: &mut [Vec3]) {
    std_latlong_inverse(c, o);
}

/// The implementations of a mapping: (tier name, forward, inverse).
fn mapping_impls(m: AnyMapping) -> Vec<(&'static str, ForwardFn, InverseFn)> {
    let mut v: Vec<(&'static str, ForwardFn, InverseFn)> = vec![
        ("scalar", fwd_scalar, inv_scalar),
        ("exact", fwd_tier::<Exact>, inv_tier::<Exact>),
        ("fine", fwd_tier::<Fine>, inv_tier::<Fine>),
        ("fast", fwd_tier::<Fast>, inv_tier::<Fast>),
    ];
    if m == AnyMapping::LatLong {
        v.push(("std", fwd_std, inv_std));
    }
    v
}

/// Times `f` (from `I` to `O`; `None`: a copy of the input) at `n` elements.
fn time_map<I: Copy + Default, O: Copy + Default>(
    s: &Settings,
    m: AnyMapping,
    make: impl Fn(usize) -> Vec<I> + 'static,
    n: usize,
    f: Option<SliceFn<I, O>>,
) -> f64 {
    let inputs = Inputs::new(n, make);
    let mut out = vec![O::default(); n];
    let mut copy = vec![I::default(); n];
    let passes = if n >= 1 << 16 {
        s.passes.min(9)
    } else {
        s.passes
    };
    ns_per_element(
        passes,
        n,
        |p| inputs.get(p),
        |d| {
            match f {
                Some(f) => f(m, d, &mut out),
                None => copy.copy_from_slice(d),
            }
            black_box((&out, &copy));
        },
    )
}

fn time_forward(s: &Settings, m: AnyMapping, n: usize, f: Option<ForwardFn>) -> f64 {
    time_map(s, m, move |p| timing::directions(p as u64 ^ 0xD1, n), n, f)
}

fn time_inverse(s: &Settings, m: AnyMapping, n: usize, f: Option<InverseFn>) -> f64 {
    time_map(
        s,
        m,
        move |p| timing::chart_points(m, p as u64 ^ 0x1A, n),
        n,
        f,
    )
}

/// Times every mapping, forward and inverse, at every tier beside the scalar
/// core, `std` (latlong only) and a copy of the same bytes, at the small size
/// and (latlong and cube) the large size; and measures each
/// implementation's worst error.
#[must_use]
pub fn mappings(s: &Settings) -> Vec<Row> {
    let mut rows = Vec::new();
    for m in AnyMapping::ALL {
        let dirs = ma::directions(m, s.mapping_points);
        let cs = ma::chart_points(m, s.mapping_points / 2);
        let impls = mapping_impls(m);
        let errors: Vec<(ForwardErrors, InverseErrors)> = impls
            .iter()
            .map(|&(_, f, i)| {
                let mut out = vec![ChartUv::default(); dirs.len()];
                f(m, &dirs, &mut out);
                let mut back = vec![Vec3::ZERO; cs.len()];
                i(m, &cs, &mut back);
                (
                    ma::measure_forward(m, &dirs, &out),
                    ma::measure_inverse(m, &cs, &back),
                )
            })
            .collect();
        let mut sizes = vec![s.n_small];
        if matches!(m, AnyMapping::LatLong | AnyMapping::Cube) {
            sizes.extend(s.n_large);
        }
        for n in sizes {
            for direction in ["forward", "inverse"] {
                let fwd = direction == "forward";
                let time = |k: usize| {
                    let (_, f, i) = impls[k];
                    if fwd {
                        time_forward(s, m, n, Some(f))
                    } else {
                        time_inverse(s, m, n, Some(i))
                    }
                };
                let copy_ns = if fwd {
                    time_forward(s, m, n, None)
                } else {
                    time_inverse(s, m, n, None)
                };
                let times: Vec<f64> = (0..impls.len()).map(time).collect();
                let std_ns = impls.iter().position(|i| i.0 == "std").map(|k| times[k]);
                for (k, &(tier, _, _)) in impls.iter().enumerate() {
                    let (fe, ie) = &errors[k];
                    let mut row = Row {
                        kind: "mapping",
                        name: m.to_string(),
                        tier,
                        direction: Some(direction),
                        n,
                        ns: times[k],
                        std_ns,
                        scalar_ns: Some(times[0]),
                        copy_ns: Some(copy_ns),
                        ..Row::default()
                    };
                    if fwd {
                        let rad = if fe.bad_chart.is_some() {
                            f64::INFINITY
                        } else {
                            fe.rad.err
                        };
                        row.max_abs_err = Some(rad);
                        row.texels_4096 = Some(fe.texels_4096);
                        row.max_uv_err = Some(fe.uv.err);
                        row.err_at = Some(format!("direction {}", fe.rad.at));
                    } else {
                        row.max_abs_err = Some(ie.inner.err);
                        row.err_at = Some(ie.inner.at.clone());
                    }
                    rows.push(row);
                }
                rows.push(Row {
                    kind: "mapping",
                    name: m.to_string(),
                    tier: "copy",
                    direction: Some(direction),
                    n,
                    ns: copy_ns,
                    std_ns,
                    scalar_ns: Some(times[0]),
                    copy_ns: Some(copy_ns),
                    ..Row::default()
                });
            }
        }
    }
    rows
}

/// Times the conversion (latlong to a cube strip, bilinear, one sample per
/// texel, on the global rayon pool) and the renderer (a mirror teapot per
/// pixel in the built-in sky stored as a cube), both at the fine tier they
/// use, beside a copy of the conversion's input.
///
/// # Panics
///
/// If the images cannot be made (sizes are fixed and valid).
#[must_use]
pub fn convert_and_render(s: &Settings) -> Vec<Row> {
    use envmap_render::filter::Filter;
    use envmap_render::filter::{convert, convert_into, ConvertOptions};
    use envmap_render::image::Representation;
    use envmap_render::scene::Builtin;
    use envmap_render::scene::Mesh;
    use envmap_render::scene::{fill, smooth};
    use envmap_render::scene::{Camera, EnvSource, RenderOptions, Renderer};

    let (w, face) = s.convert_size;
    let src = fill(
        Representation::default_for(AnyMapping::LatLong),
        w,
        w / 2,
        smooth,
    )
    .expect("latlong image");
    let repr = Representation::new(
        AnyMapping::Cube,
        Atlas::CUBE_HORIZONTAL_STRIP,
        Frame::IDENTITY,
    )
    .expect("cube strip");
    let opts = {
        let mut o = ConvertOptions::default();
        o.filter = Filter::Bilinear;
        o.samples = Some(1);
        o.rotation = None;
        o.cancel = None;
        o
    };
    let mut out = convert(&src, repr, 6 * face, face, &opts, None).expect("cube image");
    let texels = 6 * (face as usize) * (face as usize);
    let timed = |f: &mut dyn FnMut()| ns_per_element(s.big_passes, 1, |_| (), |()| f()) * 1e-6;
    let mut copy = vec![[0.0f32; 3]; src.pixels().len()];
    let copy_ms = timed(&mut || {
        copy.copy_from_slice(black_box(src.pixels()));
        black_box(&copy);
    });
    let convert_ms = timed(&mut || {
        convert_into(black_box(&src), &mut out, &opts, None).expect("conversion");
    });
    let threads = rayon::current_num_threads();
    let mut rows = vec![Row {
        kind: "convert",
        name: format!(
            "latlong {w}x{} to cube 6x{face}^2, bilinear, {threads} threads",
            w / 2
        ),
        tier: "fine",
        n: texels,
        ns: convert_ms * 1e6 / texels as f64,
        ms: Some(convert_ms),
        copy_ns: Some(copy_ms * 1e6 / texels as f64),
        ..Row::default()
    }];
    let (rw, rh, env_face) = s.render_size;
    let env = Builtin::Sky
        .image(
            Representation::default_for(AnyMapping::Cube),
            4 * env_face,
            3 * env_face,
        )
        .expect("sky cube");
    let mesh = Mesh::teapot(10);
    let ropts = {
        let mut o = RenderOptions::default();
        o.width = rw;
        o.height = rh;
        o.samples = 1;
        o
    };
    let cam = Camera::default();
    let render_ms = timed(&mut || {
        black_box(
            Renderer::new()
                .render(&mesh, EnvSource::Map(&env), &cam, &ropts)
                .expect("render"),
        );
    });
    let pixels = (rw * rh) as usize;
    rows.push(Row {
        kind: "render",
        name: format!("teapot {rw}x{rh} per pixel, cube 6x{env_face}^2, {threads} threads"),
        tier: "fine",
        n: pixels,
        ns: render_ms * 1e6 / pixels as f64,
        ms: Some(render_ms),
        ..Row::default()
    });
    rows
}

fn sig(x: Option<f64>) -> String {
    match x {
        None => String::new(),
        Some(v) if !v.is_finite() => format!("{v}"),
        Some(0.0) => "0".into(),
        Some(v) if v >= 100.0 => format!("{v:.0}"),
        Some(v) if v >= 10.0 => format!("{v:.1}"),
        Some(v) => format!("{v:.2}"),
    }
}

fn sci(x: Option<f64>) -> String {
    match x {
        None => String::new(),
        Some(0.0) => "0".into(),
        Some(v) => format!("{v:.1e}"),
    }
}

fn find<'a>(
    rows: &'a [Row],
    kind: &str,
    name: &str,
    dir: Option<&str>,
    n: usize,
    tier: &str,
) -> Option<&'a Row> {
    rows.iter().find(|r| {
        r.kind == kind && r.name == name && r.direction == dir && r.n == n && r.tier == tier
    })
}

/// The rows as Markdown: a functions table, a mappings table per size and
/// direction (time, then error in radians and texels at 4096 wide), the
/// conversion and render timings, and where each worst case occurs.
#[must_use]
pub fn markdown(rows: &[Row]) -> String {
    let mut s = String::new();
    let fn_rows: Vec<&Row> = rows.iter().filter(|r| r.kind == "function").collect();
    if let Some(first) = fn_rows.first() {
        let _ = writeln!(
            s,
            "**Functions** ({} fresh random values per pass; ns per value; worst error over the \
             sweep, rad / ULP):\n",
            first.n
        );
        s.push_str("| function | exact | fine | fast | wide | std | copy | exact err | fine err | fast err | wide err | std err |\n");
        s.push_str("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n");
        for name in FUNCTIONS {
            let get = |t| find(rows, "function", name, None, first.n, t);
            let Some(base) = get("exact") else { continue };
            let mut line = format!("| {name} |");
            for t in ["exact", "fine", "fast", "wide", "std"] {
                let _ = write!(line, " {} |", sig(get(t).map(|r| r.ns)));
            }
            let _ = write!(line, " {} |", sig(base.copy_ns));
            for t in ["exact", "fine", "fast", "wide", "std"] {
                let e = get(t).map_or(String::new(), |r| match r.max_ulp {
                    Some(u) => format!("{} / {u}", sci(r.max_abs_err)),
                    None => sci(r.max_abs_err),
                });
                let _ = write!(line, " {e} |");
            }
            s.push_str(&line);
            s.push('\n');
        }
        s.push('\n');
    }
    let mut sizes: Vec<usize> = rows
        .iter()
        .filter(|r| r.kind == "mapping")
        .map(|r| r.n)
        .collect();
    sizes.sort_unstable();
    sizes.dedup();
    for n in sizes {
        for dir in ["forward", "inverse"] {
            let _ = writeln!(
                s,
                "**Mappings, {dir}, {n} {} per pass** (ns per element; worst error: {}):\n",
                if dir == "forward" {
                    "directions"
                } else {
                    "chart points"
                },
                if dir == "forward" {
                    "rad (texels at 4096 wide)"
                } else {
                    "rad"
                }
            );
            s.push_str("| mapping | copy | scalar | exact | fine | fast | std | scalar ÷ fast | scalar err | exact err | fine err | fast err |\n");
            s.push_str("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n");
            for m in AnyMapping::ALL {
                let name = m.to_string();
                let get = |t| find(rows, "mapping", &name, Some(dir), n, t);
                if get("scalar").is_none() {
                    continue;
                }
                let mut line = format!("| {name} |");
                for t in ["copy", "scalar", "exact", "fine", "fast", "std"] {
                    let _ = write!(line, " {} |", sig(get(t).map(|r| r.ns)));
                }
                let ratio = match (get("scalar"), get("fast")) {
                    (Some(a), Some(b)) => format!("{:.0}×", a.ns / b.ns),
                    _ => String::new(),
                };
                let _ = write!(line, " {ratio} |");
                for t in ["scalar", "exact", "fine", "fast"] {
                    let e = get(t).map_or(String::new(), |r| match r.texels_4096 {
                        Some(tx) => format!("{} ({tx:.4})", sci(r.max_abs_err)),
                        None => sci(r.max_abs_err),
                    });
                    let _ = write!(line, " {e} |");
                }
                s.push_str(&line);
                s.push('\n');
            }
            s.push('\n');
        }
    }
    let big: Vec<&Row> = rows
        .iter()
        .filter(|r| matches!(r.kind, "convert" | "render"))
        .collect();
    if !big.is_empty() {
        s.push_str("| what | ms | ns per output texel/pixel | copy of the input (ms) |\n| --- | ---: | ---: | ---: |\n");
        for r in big {
            let copy_ms = r.copy_ns.map(|c| c * r.n as f64 * 1e-6);
            let _ = writeln!(
                s,
                "| {} {} | {} | {} | {} |",
                r.kind,
                r.name,
                sig(r.ms),
                sig(Some(r.ns)),
                sig(copy_ms)
            );
        }
        s.push('\n');
    }
    s.push_str("Worst cases (functions):\n\n| function | tier | max abs err (rad) | at |\n| --- | --- | ---: | --- |\n");
    for r in fn_rows {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} |",
            r.name,
            r.tier,
            sci(r.max_abs_err),
            r.err_at.as_deref().unwrap_or("")
        );
    }
    s
}

/// The mappings a complete report covers, by name.
#[must_use]
pub fn mapping_names() -> Vec<String> {
    AnyMapping::ALL.iter().map(ToString::to_string).collect()
}

/// Checks a JSON-lines report: every line parses as an object with the
/// required fields of the right types, and every function × tier and every
/// mapping × direction × tier (and the scalar core and copy) is present, as
/// are a conversion and a render row. Timings are not judged.
///
/// # Errors
///
/// A description of the first problem found.
pub fn check_json_lines(text: &str) -> Result<usize, String> {
    let mut seen = BTreeSet::new();
    let mut count = 0;
    for (i, line) in text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty())
    {
        let v: Value = serde_json::from_str(line).map_err(|e| format!("line {}: {e}", i + 1))?;
        let o = v
            .as_object()
            .ok_or(format!("line {}: not an object", i + 1))?;
        let text = |k: &str| o.get(k).and_then(Value::as_str);
        let kind = text("kind").ok_or(format!("line {}: no kind", i + 1))?;
        let name = text("name").ok_or(format!("line {}: no name", i + 1))?;
        let tier = text("tier").ok_or(format!("line {}: no tier", i + 1))?;
        if !matches!(kind, "function" | "mapping" | "convert" | "render") {
            return Err(format!("line {}: kind {kind}", i + 1));
        }
        for k in ["n", "ns"] {
            o.get(k)
                .and_then(Value::as_f64)
                .ok_or(format!("line {}: {k} missing or not a number", i + 1))?;
        }
        for k in ["max_abs_err", "max_ulp", "std_ns", "scalar_ns", "copy_ns"] {
            if !o.contains_key(k) {
                return Err(format!("line {}: no {k}", i + 1));
            }
        }
        let direction = text("direction");
        match kind {
            "mapping" if !matches!(direction, Some("forward" | "inverse")) => {
                return Err(format!("line {}: mapping without a direction", i + 1));
            }
            "convert" | "render" => {
                o.get("ms")
                    .and_then(Value::as_f64)
                    .ok_or(format!("line {}: {kind} without ms", i + 1))?;
            }
            _ => {}
        }
        if matches!(tier, "exact" | "fine" | "fast") && kind != "convert" && kind != "render" {
            o.get("max_abs_err")
                .and_then(Value::as_f64)
                .ok_or(format!("line {}: {name} {tier} without an error", i + 1))?;
        }
        seen.insert(format!("{kind}/{name}/{}/{tier}", direction.unwrap_or("-")));
        if kind == "convert" || kind == "render" {
            seen.insert(kind.to_string());
        }
        count += 1;
    }
    let mut wanted = Vec::new();
    for f in FUNCTIONS {
        for t in TIERS.iter().chain(&["wide", "std"]) {
            wanted.push(format!("function/{f}/-/{t}"));
        }
    }
    for m in mapping_names() {
        for d in ["forward", "inverse"] {
            for t in TIERS.iter().chain(&["scalar", "copy"]) {
                wanted.push(format!("mapping/{m}/{d}/{t}"));
            }
        }
    }
    wanted.push("convert".into());
    wanted.push("render".into());
    match wanted.iter().find(|w| !seen.contains(*w)) {
        Some(w) => Err(format!("missing: {w}")),
        None => Ok(count),
    }
}
