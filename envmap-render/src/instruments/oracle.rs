// The oracle: the bake's integrals (LD, E, SH9) computed from the input
// itself by adaptive quadrature over its texels (see the module docs).

use crate::par::*;
use envmap_core::texel::texel_center;
use envmap_core::{ChartUv, Mapping};
use glam::{DMat3, DVec3, Vec3};

use crate::filter::brdf::lobe_width;
use crate::filter::sample::{Filter, Sampler};
use crate::filter::sh::{basis, Sh9, ShKind};
use crate::filter::weights::TexelWeights;
use crate::image::EnvImage;

/// The largest side of a leaf, in texels.
const LEAF: u32 = 8;
/// The most parts a subdivided texel is cut into per side.
const MAX_SPLIT: u32 = 64;
/// A texel brighter than this many times the map's mean (largest absolute
/// channel, solid-angle weighted) is held to a quarter of the tolerance.
const BRIGHT_FACTOR: f64 = 64.0;

/// Sums over a node's texels (f64).
#[derive(Clone, Copy, Debug, Default)]
struct Sums {
    /// Σ Ω.
    w0: f64,
    /// Σ Ω·d.
    w1: DVec3,
    /// Σ Ω·L per channel.
    s0: [f64; 3],
    /// Σ Ω·L·d per channel.
    s1: [DVec3; 3],
}

impl Sums {
    fn add(&mut self, o: &Sums) {
        self.w0 += o.w0;
        self.w1 += o.w1;
        for c in 0..3 {
            self.s0[c] += o.s0[c];
            self.s1[c] += o.s1[c];
        }
    }

    fn texel(&mut self, d: DVec3, omega: f64, l: [f64; 3]) {
        self.w0 += omega;
        self.w1 += omega * d;
        for c in 0..3 {
            self.s0[c] += omega * l[c];
            self.s1[c] += (omega * l[c]) * d;
        }
    }
}

/// A rectangle of one chart's texels.
#[derive(Clone, Copy, Debug)]
struct Rect {
    chart: u32,
    i0: u32,
    i1: u32,
    j0: u32,
    j1: u32,
}

#[derive(Debug)]
struct Node {
    rect: Rect,
    sums: Sums,
    centre: DVec3,
    /// Angular radius of a cap about `centre` holding every texel.
    radius: f64,
    bright: bool,
    children: Option<Box<(Node, Node)>>,
    /// A leaf's texels, row by row: centre direction and cap radius (NaN
    /// for a texel that holds no direction).
    caps: Vec<[f32; 4]>,
}

/// The weight a lobe gives a direction at c = R·l (0 behind), its
/// derivative in c, and the angular scale on which it changes.
trait Kernel: Sync {
    fn w(&self, c: f64) -> f64;
    fn dw(&self, c: f64) -> f64;
    fn scale(&self, theta: f64) -> f64;
    /// w′ at the horizon over w at the peak: how much a texel that
    /// straddles the horizon matters.
    fn kink(&self) -> f64;
}

/// GGX with N = V: w(c) = D((1 + c)/2)·c.
struct Ggx {
    a2: f64,
    width: f64,
}

impl Ggx {
    fn new(roughness: f64) -> Self {
        let alpha = roughness * roughness;
        Self {
            a2: alpha * alpha,
            width: lobe_width(alpha).max(1e-9),
        }
    }

    /// D's denominator g = sin²θh + α² cos²θh, with sin²θh = (1 − c)/2 and
    /// cos²θh = (1 + c)/2 (two positive terms: no cancellation).
    #[inline]
    fn g(&self, c: f64) -> f64 {
        0.5 * (1.0 - c) + self.a2 * 0.5 * (1.0 + c)
    }
}

impl Kernel for Ggx {
    #[inline]
    fn w(&self, c: f64) -> f64 {
        if c <= 0.0 {
            return 0.0;
        }
        let g = self.g(c);
        self.a2 / (core::f64::consts::PI * g * g) * c
    }

    #[inline]
    fn dw(&self, c: f64) -> f64 {
        if c <= 0.0 {
            return 0.0;
        }
        let g = self.g(c);
        let d = self.a2 / (core::f64::consts::PI * g * g);
        // dD/dc = −2D/g · dg/dc, dg/dc = (α² − 1)/2.
        d + c * d * (1.0 - self.a2) / g
    }

    #[inline]
    fn scale(&self, theta: f64) -> f64 {
        theta.max(self.width)
    }

    fn kink(&self) -> f64 {
        self.dw(1e-12) / self.w(1.0)
    }
}

/// The cosine: w(c) = max(c, 0).
struct Cosine;

impl Kernel for Cosine {
    #[inline]
    fn w(&self, c: f64) -> f64 {
        c.max(0.0)
    }
    #[inline]
    fn dw(&self, c: f64) -> f64 {
        if c > 0.0 {
            1.0
        } else {
            0.0
        }
    }
    #[inline]
    fn scale(&self, _theta: f64) -> f64 {
        1.0
    }

    fn kink(&self) -> f64 {
        1.0
    }
}

/// Numerator (per channel) and denominator of a weighted integral.
#[derive(Clone, Copy, Debug, Default)]
struct Acc {
    num: [f64; 3],
    den: f64,
    /// Texels subdivided and parts evaluated, for reports.
    parts: u64,
}

/// How the oracle reads the input between its texel centres (see the
/// [module docs](crate::instruments#between-texel-centres-reconstruction)).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Reconstruction {
    /// Constant over each texel: the input's texels as given.
    #[default]
    Constant,
    /// The bilinear interpolation of the nearest texel centres, as
    /// renderers sample maps ([`Filter::Bilinear`]).
    Bilinear,
}

/// The input's integrals, exactly enough to measure the bake against; see
/// the [module docs](crate::instruments).
pub struct Oracle<'a> {
    src: &'a EnvImage,
    /// With [`Reconstruction::Bilinear`]: the sampler, and each texel's
    /// mean of the bilinear function over its area (chart, row, column).
    bilinear: Option<(Sampler<'a>, Vec<[f64; 3]>)>,
    weights: TexelWeights,
    /// World (canonical) axes → the input's axes.
    to_src: DMat3,
    /// The input's axes → world.
    to_world: DMat3,
    roots: Vec<Node>,
    bright_level: f64,
    tolerance: f64,
}

impl std::fmt::Debug for Oracle<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Oracle")
            .field("tolerance", &self.tolerance)
            .field("bright_level", &self.bright_level)
            .finish_non_exhaustive()
    }
}

fn dvec(v: Vec3) -> DVec3 {
    DVec3::new(f64::from(v.x), f64::from(v.y), f64::from(v.z))
}

fn angle(a: DVec3, b: DVec3) -> f64 {
    // atan2(|a × b|, a·b): accurate at small and large angles.
    a.cross(b).length().atan2(a.dot(b))
}

impl<'a> Oracle<'a> {
    /// The oracle of `src` (texels as given: negative values count, NaN and
    /// infinite ones are taken as 0), constant over each texel, at the
    /// default tolerance 1/16.
    #[must_use]
    pub fn new(src: &'a EnvImage) -> Self {
        Self::with_reconstruction(src, Reconstruction::Constant)
    }

    /// The oracle of `src` read bilinearly between its texel centres
    /// ([`Reconstruction::Bilinear`]): the function renderers sample, the
    /// one the exact split sum integrates at every roughness down to 0.
    #[must_use]
    pub fn bilinear(src: &'a EnvImage) -> Self {
        Self::with_reconstruction(src, Reconstruction::Bilinear)
    }

    /// The oracle of `src` read between texel centres as `recon` says.
    #[must_use]
    pub(crate) fn with_reconstruction(src: &'a EnvImage, recon: Reconstruction) -> Self {
        let mapping = src.mapping();
        let (cw, ch) = src.cell_size();
        let weights = TexelWeights::new(mapping, cw, ch);
        let m = src.representation().frame.matrix();
        let to_world = DMat3::from_cols(dvec(m.x_axis), dvec(m.y_axis), dvec(m.z_axis));
        let bilinear = (recon == Reconstruction::Bilinear).then(|| {
            let sampler = Sampler::new(src);
            let means = texel_means(src, &sampler);
            (sampler, means)
        });
        let mut o = Oracle {
            src,
            bilinear,
            weights,
            to_src: to_world.transpose(),
            to_world,
            roots: Vec::new(),
            bright_level: f64::INFINITY,
            tolerance: 1.0 / 16.0,
        };
        // The mean of the largest absolute channel, for the bright rule.
        let (mut sum, mut sphere) = (0.0f64, 0.0f64);
        for chart in 0..mapping.chart_count() {
            for j in 0..ch {
                for i in 0..cw {
                    let w = o.weights.get(chart, i, j);
                    if w > 0.0 {
                        sum += w * o
                            .texel_value(chart, i, j)
                            .map(f64::abs)
                            .iter()
                            .fold(0.0f64, |a, &b| a.max(b));
                        sphere += w;
                    }
                }
            }
        }
        if sphere > 0.0 && sum > 0.0 {
            o.bright_level = BRIGHT_FACTOR * sum / sphere;
        }
        let roots: Vec<Node> = (0..mapping.chart_count())
            .into_par_iter()
            .map(|chart| {
                o.build(Rect {
                    chart,
                    i0: 0,
                    i1: cw,
                    j0: 0,
                    j1: ch,
                })
            })
            .collect();
        o.roots = roots;
        o
    }

    /// The same oracle at tolerance `tau` (smaller is finer and slower;
    /// see the [module docs](crate::instruments)).
    #[must_use]
    pub fn with_tolerance(mut self, tau: f64) -> Self {
        self.tolerance = tau.clamp(1e-4, 1.0);
        self
    }

    /// The tolerance τ.
    #[must_use]
    pub fn tolerance(&self) -> f64 {
        self.tolerance
    }

    /// The input.
    #[must_use]
    pub fn source(&self) -> &EnvImage {
        self.src
    }

    /// How the input is read between texel centres.
    #[must_use]
    pub fn reconstruction(&self) -> Reconstruction {
        if self.bilinear.is_some() {
            Reconstruction::Bilinear
        } else {
            Reconstruction::Constant
        }
    }

    /// What texel (i, j) stands for in the sums: its value, or with the
    /// bilinear reading the function's mean over its area.
    fn texel_value(&self, chart: u32, i: u32, j: u32) -> [f64; 3] {
        if let Some((_, means)) = &self.bilinear {
            let (cw, ch) = self.src.cell_size();
            return means[((chart * ch + j) * cw + i) as usize];
        }
        finite_texel(self.src, chart, i, j)
    }

    /// The value of a part of texel (i, j) centred at chart point (u, v):
    /// the texel's own value, or the bilinear function's there.
    fn part_value(&self, chart: u32, uv: (f64, f64), texel: [f64; 3]) -> [f64; 3] {
        match &self.bilinear {
            Some((s, _)) => bilinear_at(s, chart, uv.0, uv.1),
            None => texel,
        }
    }

    fn is_bright(&self, l: [f64; 3]) -> bool {
        l.iter().fold(0.0f64, |a, b| a.max(b.abs())) > self.bright_level
    }

    /// The direction at chart point (u, v), f64.
    fn dir(&self, chart: u32, u: f64, v: f64) -> Option<DVec3> {
        let m = self.src.mapping();
        m.inverse(ChartUv::new(chart, u as f32, v as f32))
            .map(|d| dvec(d).normalize())
    }

    /// Texel (i, j)'s centre direction and the angular radius of a cap
    /// about it holding the texel (its corners; a disk's rim texels get
    /// one texel's width more).
    fn texel_cap(&self, chart: u32, i: u32, j: u32) -> Option<(DVec3, f64)> {
        let (cw, ch) = self.src.cell_size();
        let d = self.dir(
            chart,
            f64::from(texel_center(i, cw)),
            f64::from(texel_center(j, ch)),
        )?;
        let mut r = 0.0f64;
        let mut missing = false;
        for (a, b) in [(i, j), (i + 1, j), (i, j + 1), (i + 1, j + 1)] {
            match self.dir(
                chart,
                f64::from(a) / f64::from(cw),
                f64::from(b) / f64::from(ch),
            ) {
                Some(c) => r = r.max(angle(d, c)),
                None => missing = true,
            }
        }
        if missing {
            r = 2.0 * r.max(self.weights.get(chart, i, j).sqrt());
        }
        Some((d, r))
    }

    fn build(&self, rect: Rect) -> Node {
        let (w, h) = (rect.i1 - rect.i0, rect.j1 - rect.j0);
        if w <= LEAF && h <= LEAF {
            let mut sums = Sums::default();
            let mut bright = false;
            let mut caps = Vec::with_capacity((w * h) as usize);
            for j in rect.j0..rect.j1 {
                for i in rect.i0..rect.i1 {
                    let omega = self.weights.get(rect.chart, i, j);
                    let cap = self.texel_cap(rect.chart, i, j).filter(|_| omega > 0.0);
                    let Some((d, r)) = cap else {
                        caps.push([f32::NAN; 4]);
                        continue;
                    };
                    let l = self.texel_value(rect.chart, i, j);
                    bright |= self.is_bright(l);
                    sums.texel(d, omega, l);
                    caps.push([d.x as f32, d.y as f32, d.z as f32, r as f32]);
                }
            }
            let cap_dir =
                |c: &[f32; 4]| DVec3::new(f64::from(c[0]), f64::from(c[1]), f64::from(c[2]));
            let centre = if sums.w1.length() > 1e-300 {
                sums.w1.normalize()
            } else {
                caps.iter()
                    .find(|c| !c[3].is_nan())
                    .map_or(DVec3::Z, cap_dir)
            };
            let radius = caps
                .iter()
                .filter(|c| !c[3].is_nan())
                .map(|c| angle(centre, cap_dir(c)) + f64::from(c[3]) * (1.0 + 1e-6))
                .fold(0.0, f64::max)
                .min(core::f64::consts::PI);
            return Node {
                rect,
                sums,
                centre,
                radius,
                bright,
                children: None,
                caps,
            };
        }
        let (a, b) = if w >= h {
            let m = rect.i0 + w / 2;
            (Rect { i1: m, ..rect }, Rect { i0: m, ..rect })
        } else {
            let m = rect.j0 + h / 2;
            (Rect { j1: m, ..rect }, Rect { j0: m, ..rect })
        };
        let (na, nb) = if w * h > 4096 {
            crate::par::join(|| self.build(a), || self.build(b))
        } else {
            (self.build(a), self.build(b))
        };
        let mut sums = na.sums;
        sums.add(&nb.sums);
        let centre = if sums.w1.length() > 1e-300 {
            sums.w1.normalize()
        } else {
            na.centre
        };
        let radius = [&na, &nb]
            .iter()
            .map(|n| angle(centre, n.centre) + n.radius)
            .fold(0.0, f64::max)
            .min(core::f64::consts::PI);
        Node {
            rect,
            sums,
            centre,
            radius,
            bright: na.bright || nb.bright,
            children: Some(Box::new((na, nb))),
            caps: Vec::new(),
        }
    }

    /// The test a cap passes to be taken whole: `Some(true)` take it,
    /// `Some(false)` open it, `None` skip it (wholly behind).
    ///
    /// A single texel that straddles the horizon passes when its radius
    /// does (the caller subdivides it where the weight's kink there
    /// matters: the cosine, rough GGX lobes); a node of many texels there
    /// is opened.
    #[inline]
    #[allow(clippy::too_many_arguments)]
    fn test(
        &self,
        k: &dyn Kernel,
        r: DVec3,
        centre: DVec3,
        radius: f64,
        bright: bool,
        texel: bool,
    ) -> Option<bool> {
        let theta = angle(r, centre);
        let lo = (theta - radius).max(0.0);
        let hi = theta + radius;
        let half = core::f64::consts::FRAC_PI_2;
        if lo >= half {
            return None;
        }
        let tau = if bright {
            0.25 * self.tolerance
        } else {
            self.tolerance
        };
        Some((texel || hi < half) && radius <= tau * k.scale(lo))
    }

    fn visit(&self, n: &Node, k: &dyn Kernel, r: DVec3, acc: &mut Acc) {
        match self.test(k, r, n.centre, n.radius, n.bright, false) {
            None => {}
            Some(true) => {
                let c = r.dot(n.centre).clamp(-1.0, 1.0);
                let (w, dw) = (k.w(c), k.dw(c));
                let s = &n.sums;
                for ch in 0..3 {
                    acc.num[ch] += w * s.s0[ch] + dw * (r.dot(s.s1[ch]) - c * s.s0[ch]);
                }
                acc.den += w * s.w0 + dw * (r.dot(s.w1) - c * s.w0);
            }
            Some(false) => match &n.children {
                Some(ch) => {
                    self.visit(&ch.0, k, r, acc);
                    self.visit(&ch.1, k, r, acc);
                }
                None => self.visit_leaf(n, k, r, acc),
            },
        }
    }

    fn visit_leaf(&self, n: &Node, k: &dyn Kernel, r: DVec3, acc: &mut Acc) {
        let rect = n.rect;
        let (cw, ch) = self.src.cell_size();
        let mapping = self.src.mapping();
        let mut caps = n.caps.iter();
        for j in rect.j0..rect.j1 {
            for i in rect.i0..rect.i1 {
                let Some(cap) = caps.next().filter(|c| !c[3].is_nan()) else {
                    continue;
                };
                let omega = self.weights.get(rect.chart, i, j);
                let d =
                    DVec3::new(f64::from(cap[0]), f64::from(cap[1]), f64::from(cap[2])).normalize();
                let radius = f64::from(cap[3]) * (1.0 + 1e-6);
                let l = self.texel_value(rect.chart, i, j);
                let bright = self.is_bright(l);
                let theta = angle(r, d);
                let straddles = (theta - radius) < core::f64::consts::FRAC_PI_2
                    && theta + radius > core::f64::consts::FRAC_PI_2;
                let kinked = straddles && k.kink() > 1e-3;
                match self.test(k, r, d, radius, bright, true) {
                    None => {}
                    Some(true) if !kinked => {
                        let w = k.w(r.dot(d).clamp(-1.0, 1.0));
                        for c in 0..3 {
                            acc.num[c] += w * omega * l[c];
                        }
                        acc.den += w * omega;
                    }
                    Some(_) => {
                        // Subdivide: parts whose radius is about radius/m
                        // (across the horizon, where the weight has a kink,
                        // at most a quarter of the tolerance in radians).
                        let lo = (theta - radius).max(0.0);
                        let tau = if bright || kinked {
                            0.25 * self.tolerance
                        } else {
                            self.tolerance
                        };
                        let want = (tau * k.scale(lo)).max(1e-12);
                        let m = ((radius / want).ceil() as u32).clamp(2, MAX_SPLIT);
                        let (u0, v0) = (f64::from(i) / f64::from(cw), f64::from(j) / f64::from(ch));
                        let (du, dv) = (1.0 / f64::from(cw * m), 1.0 / f64::from(ch * m));
                        for b in 0..m {
                            for a in 0..m {
                                let (ua, va) = (u0 + f64::from(a) * du, v0 + f64::from(b) * dv);
                                let o = mapping.solid_angle(rect.chart, ua, ua + du, va, va + dv);
                                if o <= 0.0 {
                                    continue;
                                }
                                let Some(p) = self.dir(rect.chart, ua + 0.5 * du, va + 0.5 * dv)
                                else {
                                    continue;
                                };
                                let w = k.w(r.dot(p).clamp(-1.0, 1.0));
                                let l =
                                    self.part_value(rect.chart, (ua + 0.5 * du, va + 0.5 * dv), l);
                                for c in 0..3 {
                                    acc.num[c] += w * o * l[c];
                                }
                                acc.den += w * o;
                            }
                        }
                        acc.parts += u64::from(m * m);
                    }
                }
            }
        }
    }

    fn integrate(&self, k: &dyn Kernel, r_world: Vec3) -> Acc {
        let r = (self.to_src * dvec(r_world)).normalize();
        let mut acc = Acc::default();
        if !r.is_finite() {
            return acc;
        }
        for n in &self.roots {
            self.visit(n, k, r, &mut acc);
        }
        acc
    }

    /// LD at each of `dirs` (world axes) for perceptual `roughness` (in
    /// [0, 1]; α = roughness²): the GGX-weighted mean of the input, f64.
    /// Zero where the lobe sees no texel. Constant over texels, roughness
    /// is taken as at least 10⁻³ (a lobe far narrower than any texel); read
    /// bilinearly, roughness 0 is the bilinear value at each direction.
    #[must_use]
    pub fn prefiltered(&self, roughness: f32, dirs: &[Vec3]) -> Vec<[f64; 3]> {
        if let (Some((s, _)), true) = (&self.bilinear, roughness <= 0.0) {
            let mapping = self.src.mapping();
            return dirs
                .par_iter()
                .map(|&d| {
                    let r = (self.to_src * dvec(d)).normalize();
                    let v = Vec3::new(r.x as f32, r.y as f32, r.z as f32);
                    match mapping.forward(v) {
                        Some(c) if r.is_finite() => finite(s.sample(c, Filter::Bilinear)),
                        _ => [0.0; 3],
                    }
                })
                .collect();
        }
        let k = Ggx::new(f64::from(roughness).max(1e-3));
        dirs.par_iter()
            .map(|&d| {
                let a = self.integrate(&k, d);
                if a.den > 0.0 {
                    a.num.map(|v| v / a.den)
                } else {
                    [0.0; 3]
                }
            })
            .collect()
    }

    /// E(n) = ∫ L max(n·l, 0) dl at each of `normals` (world axes), f64
    /// (divide by π for what an E/π map stores).
    #[must_use]
    pub fn irradiance(&self, normals: &[Vec3]) -> Vec<[f64; 3]> {
        normals
            .par_iter()
            .map(|&d| self.integrate(&Cosine, d).num)
            .collect()
    }

    #[cfg(test)]
    /// ∫ max(n·l, 0) dl over the input's texels at `n` (π for a map that
    /// covers the sphere): the quadrature's own check.
    #[must_use]
    pub(crate) fn cosine_total(&self, n: Vec3) -> f64 {
        self.integrate(&Cosine, n).den
    }

    /// The radiance SH9 coefficients (canonical axes) with every texel
    /// split into `m × m` parts (`m` ≥ 1), each with its exact solid angle.
    #[must_use]
    pub fn sh9(&self, m: u32) -> Sh9 {
        let m = m.max(1);
        let mapping = self.src.mapping();
        let (cw, ch) = self.src.cell_size();
        let rows: Vec<(u32, u32)> = (0..mapping.chart_count())
            .flat_map(|c| (0..ch).map(move |j| (c, j)))
            .collect();
        let parts: Vec<[[f64; 3]; 9]> = rows
            .par_iter()
            .map(|&(chart, j)| {
                let mut s = [[0.0f64; 3]; 9];
                for i in 0..cw {
                    if self.weights.get(chart, i, j) <= 0.0 {
                        continue;
                    }
                    let l = self.texel_value(chart, i, j);
                    let (u0, v0) = (f64::from(i) / f64::from(cw), f64::from(j) / f64::from(ch));
                    let (du, dv) = (1.0 / f64::from(cw * m), 1.0 / f64::from(ch * m));
                    for b in 0..m {
                        for a in 0..m {
                            let (ua, va) = (u0 + f64::from(a) * du, v0 + f64::from(b) * dv);
                            let o = mapping.solid_angle(chart, ua, ua + du, va, va + dv);
                            let Some(p) = self.dir(chart, ua + 0.5 * du, va + 0.5 * dv) else {
                                continue;
                            };
                            if o <= 0.0 {
                                continue;
                            }
                            let y = basis((self.to_world * p).to_array());
                            for (k, yk) in y.iter().enumerate() {
                                for c in 0..3 {
                                    s[k][c] += o * l[c] * yk;
                                }
                            }
                        }
                    }
                }
                s
            })
            .collect();
        let mut coeffs = [[0.0f64; 3]; 9];
        for p in &parts {
            for k in 0..9 {
                for c in 0..3 {
                    coeffs[k][c] += p[k][c];
                }
            }
        }
        Sh9 {
            coeffs,
            kind: ShKind::Radiance,
        }
    }

    /// The input's energy per channel, Σ Ω·L over its texels (exact solid
    /// angles), and of its negative values alone, Σ Ω·min(L, 0).
    #[must_use]
    pub fn energy(&self) -> ([f64; 3], [f64; 3]) {
        let mut e = [0.0; 3];
        let mut neg = [0.0; 3];
        for n in &self.roots {
            for c in 0..3 {
                e[c] += n.sums.s0[c];
            }
        }
        let mapping = self.src.mapping();
        let (cw, ch) = self.src.cell_size();
        for chart in 0..mapping.chart_count() {
            for j in 0..ch {
                for i in 0..cw {
                    let o = self.weights.get(chart, i, j);
                    for (c, v) in self.texel_value(chart, i, j).iter().enumerate() {
                        if *v < 0.0 {
                            neg[c] += o * v;
                        }
                    }
                }
            }
        }
        (e, neg)
    }
}

/// Texel (i, j) of `chart` as f64, non-finite values as 0.
fn finite_texel(src: &EnvImage, chart: u32, i: u32, j: u32) -> [f64; 3] {
    finite(src.chart_texel(chart, i, j).unwrap_or_default())
}

/// The bilinear function at chart point (u, v), f64, non-finite as 0.
fn bilinear_at(s: &Sampler<'_>, chart: u32, u: f64, v: f64) -> [f64; 3] {
    finite(s.sample(ChartUv::new(chart, u as f32, v as f32), Filter::Bilinear))
}

/// A value as f64, non-finite channels as 0.
fn finite(x: [f32; 3]) -> [f64; 3] {
    x.map(|x| if x.is_finite() { f64::from(x) } else { 0.0 })
}

/// Each texel's mean of the bilinear function over its area (chart, row,
/// column): its four quarters' centres weighted by their exact solid
/// angles; the texel's own value where it holds no solid angle.
fn texel_means(src: &EnvImage, s: &Sampler<'_>) -> Vec<[f64; 3]> {
    let mapping = src.mapping();
    let (cw, ch) = src.cell_size();
    let rows: Vec<(u32, u32)> = (0..mapping.chart_count())
        .flat_map(|c| (0..ch).map(move |j| (c, j)))
        .collect();
    rows.par_iter()
        .flat_map_iter(|&(chart, j)| {
            let (du, dv) = (0.5 / f64::from(cw), 0.5 / f64::from(ch));
            (0..cw).map(move |i| {
                let (u0, v0) = (f64::from(i) / f64::from(cw), f64::from(j) / f64::from(ch));
                let (mut sum, mut total) = ([0.0f64; 3], 0.0f64);
                for (a, b) in [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)] {
                    let (ua, va) = (u0 + a * du, v0 + b * dv);
                    let o = mapping.solid_angle(chart, ua, ua + du, va, va + dv);
                    if o <= 0.0 {
                        continue;
                    }
                    let l = bilinear_at(s, chart, ua + 0.5 * du, va + 0.5 * dv);
                    for c in 0..3 {
                        sum[c] += o * l[c];
                    }
                    total += o;
                }
                if total > 0.0 {
                    sum.map(|x| x / total)
                } else {
                    finite_texel(src, chart, i, j)
                }
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::filter::specular::{ggx_d, lobe_normalizer};
    use crate::image::Representation;
    use crate::scene::procedural::fill;
    use envmap_core::AnyMapping;

    fn latlong(w: u32, h: u32, f: impl Fn(Vec3) -> [f32; 3] + Sync) -> EnvImage {
        fill(Representation::default_for(AnyMapping::LatLong), w, h, f).unwrap()
    }

    fn dirs() -> Vec<Vec3> {
        // A small Fibonacci sphere plus the axes.
        let n = 24;
        let mut v: Vec<Vec3> = (0..n)
            .map(|k| {
                let z = 1.0 - 2.0 * (k as f32 + 0.5) / n as f32;
                let phi = k as f32 * 2.399_963;
                let r = (1.0 - z * z).sqrt();
                Vec3::new(r * phi.cos(), r * phi.sin(), z)
            })
            .collect();
        v.extend([Vec3::X, Vec3::Y, Vec3::Z, -Vec3::Z]);
        v
    }

    #[test]
    fn a_constant_map_gives_its_constant_and_pi() {
        let img = latlong(256, 128, |_| [2.0, 3.0, 5.0]);
        let o = Oracle::new(&img);
        for r in [0.1f32, 0.5, 1.0] {
            for v in o.prefiltered(r, &dirs()) {
                for (c, want) in [2.0, 3.0, 5.0].iter().enumerate() {
                    assert!((v[c] - want).abs() < 1e-9 * want, "{r}: {v:?}");
                }
            }
        }
        for (n, e) in dirs().iter().zip(o.irradiance(&dirs())) {
            // E = πL, within the midpoint rule's error over texels δ =
            // 1.4° wide (each texel's cosine read at its centre: δ²/8 =
            // 7.5·10⁻⁵ relative).
            let pi = core::f64::consts::PI;
            assert!((e[0] / 2.0 - pi).abs() < 1e-4 * pi, "{n}: {e:?}");
            assert!((o.cosine_total(*n) - pi).abs() < 1e-4 * pi);
        }
        let sh = o.sh9(2);
        let want = 2.0 * 4.0 * core::f64::consts::PI * crate::filter::sh::Y00;
        assert!((sh.coeffs[0][0] - want).abs() < 1e-9 * want, "{sh:?}");
        // The other coefficients vanish, to the midpoint rule's error over
        // texels split 2 × 2.
        assert!(
            sh.coeffs[1..].iter().all(|c| c[0].abs() < 5e-5 * want),
            "{sh:?}"
        );
        let (e, neg) = o.energy();
        assert!((e[0] - 8.0 * core::f64::consts::PI).abs() < 1e-9);
        assert_eq!(neg, [0.0; 3]);
    }

    #[test]
    fn a_hemisphere_step_gives_its_closed_forms() {
        // L = 1 above the horizon (z > 0), 0 below: a latlong whose rows
        // split exactly at the equator.
        let img = latlong(256, 128, |d| if d.z > 0.0 { [1.0; 3] } else { [0.0; 3] });
        let o = Oracle::new(&img);
        let e = o.irradiance(&[Vec3::Z, -Vec3::Z, Vec3::X]);
        // E(+z) = π, E(−z) = 0, E(horizontal) = π/2 (the half of the lit
        // hemisphere's cosine lobe above the horizon: ∫ = π/2 by symmetry).
        // Within the midpoint rule's δ²/8 (texels δ = 1.4° wide).
        assert!(
            (e[0][0] - core::f64::consts::PI).abs() < 1e-4 * core::f64::consts::PI,
            "{e:?}"
        );
        assert!(e[1][0].abs() < 1e-12, "{e:?}");
        assert!(
            (e[2][0] - core::f64::consts::FRAC_PI_2).abs() < 1e-5,
            "{e:?}"
        );
        for r in [0.2f32, 0.6, 1.0] {
            let ld = o.prefiltered(r, &[Vec3::Z, Vec3::X, -Vec3::Z]);
            assert!((ld[0][0] - 1.0).abs() < 1e-9, "{r} {ld:?}");
            // Horizontal R: the lobe is symmetric about the horizon.
            assert!((ld[1][0] - 0.5).abs() < 2e-4, "{r} {ld:?}");
            assert!(ld[2][0].abs() < 1e-12, "{r} {ld:?}");
        }
    }

    #[test]
    fn one_bright_texel_gives_the_ggx_lobe() {
        // One latlong texel of value V, black elsewhere: LD(R)·Z = V·∫ w over
        // the texel, which for a texel small against its distance to R is
        // V·Ω·w(R·d)/… with Z = lobe_normalizer(α) the lobe's integral.
        let (w, h) = (512u32, 256u32);
        let (ti, tj) = (300u32, 90u32);
        let mut img = latlong(w, h, |_| [0.0; 3]);
        assert!(img.set_chart_texel(0, ti, tj, [1000.0; 3]));
        let o = Oracle::new(&img);
        let d = AnyMapping::LatLong
            .inverse(ChartUv::new(0, texel_center(ti, w), texel_center(tj, h)))
            .unwrap();
        let omega = AnyMapping::LatLong.texel_solid_angle(0, ti, tj, w, h);
        let r = 0.5f32;
        let alpha = f64::from(r * r);
        let z = lobe_normalizer(alpha);
        // Directions 5° to 60° from the texel, in the plane of d and z.
        let axis = d.cross(Vec3::Z).normalize();
        for deg in [5.0f32, 15.0, 30.0, 60.0] {
            let q = envmap_core::glam::Quat::from_axis_angle(axis, deg.to_radians());
            let rdir = q * d;
            let got = o.prefiltered(r, &[rdir])[0][0];
            let c = f64::from(rdir.dot(d));
            let want = 1000.0 * omega * ggx_d(0.5 * (1.0 + c), alpha) * c / z;
            assert!(
                (got - want).abs() < 2e-3 * want,
                "{deg}°: {got} against {want}"
            );
        }
        // Through the texel itself (the lobe 60× narrower than the texel is
        // wide is integrated over its area, not read at its centre): LD·Z
        // is V times the part of the lobe the texel covers, at most V.
        let got = o.prefiltered(0.02, &[d])[0][0];
        assert!(got > 0.9 * 1000.0 && got <= 1000.0 * (1.0 + 1e-9), "{got}");
    }

    /// A checkerboard and a hot spot of `peak` where d·`hot` > `cos`.
    fn sharp(d: Vec3, hot: Vec3, cos: f32, peak: f32) -> [f32; 3] {
        let v = if ((d.x * 6.0).floor() + (d.y * 6.0).floor()) as i32 % 2 == 0 {
            1.0
        } else {
            0.2
        };
        if d.normalize().dot(hot) > cos {
            [peak; 3]
        } else {
            [v; 3]
        }
    }

    /// The largest relative difference of the first channel.
    fn max_rel(a: &[[f64; 3]], b: &[[f64; 3]]) -> f64 {
        a.iter()
            .zip(b)
            .map(|(p, q)| (p[0] - q[0]).abs() / p[0].abs())
            .fold(0.0, f64::max)
    }

    #[test]
    fn the_bilinear_reading_is_the_samplers_and_agrees_for_wide_lobes() {
        // A sharp map: a checkerboard and a small hot spot.
        let hot = Vec3::new(0.3, 0.2, 0.9).normalize();
        let img = latlong(256, 128, |d| sharp(d, hot, 0.999, 300.0));
        let (c, b) = (Oracle::new(&img), Oracle::bilinear(&img));
        assert_eq!(b.reconstruction(), Reconstruction::Bilinear);
        assert_eq!(c.reconstruction(), Reconstruction::Constant);
        // Roughness 0: the bilinear value itself.
        let s = Sampler::new(&img);
        let mut ds = dirs();
        ds.push(hot);
        for (d, v) in ds.iter().zip(b.prefiltered(0.0, &ds)) {
            let q = AnyMapping::LatLong.forward(*d).unwrap();
            let want = s.sample(q, Filter::Bilinear);
            assert_eq!(v[0], f64::from(want[0]), "{d}");
        }
        // A lobe far narrower than a texel: the bilinear value at R within
        // 1 % (the lobe's tail reaches the neighbours), where the constant
        // reading gives the texel's own value.
        let v = b.prefiltered(0.005, &ds);
        for (d, v) in ds.iter().zip(&v) {
            let want =
                f64::from(s.sample(AnyMapping::LatLong.forward(*d).unwrap(), Filter::Bilinear)[0]);
            assert!(
                (v[0] - want).abs() <= 0.01 * want.abs().max(1.0),
                "{d}: {v:?} {want}"
            );
        }
        // Wide lobes: the two readings differ by less the finer the map,
        // faster than the texel's size (second order where the map is
        // smooth, less where its edges and hot spot are).
        let coarse = max_rel(&c.prefiltered(0.3, &ds), &b.prefiltered(0.3, &ds));
        let fine_img = latlong(512, 256, |d| sharp(d, hot, 0.999, 300.0));
        let fine = max_rel(
            &Oracle::new(&fine_img).prefiltered(0.3, &ds),
            &Oracle::bilinear(&fine_img).prefiltered(0.3, &ds),
        );
        println!("constant against bilinear at roughness 0.3: {coarse:.2e} at 256 × 128, {fine:.2e} at 512 × 256");
        assert!(coarse < 1e-2 && fine < coarse / 2.0, "{coarse} {fine}");
        // Energy: the bilinear function's integral is the texels' within
        // the variation of the solid angle over a texel.
        let (ec, eb) = (c.energy().0[0], b.energy().0[0]);
        assert!((ec - eb).abs() < 1e-3 * ec, "{ec} {eb}");
    }

    #[test]
    fn halving_the_tolerance_changes_little() {
        // A sharp map (a checkerboard with a small hot spot): the oracle at
        // τ and τ/2 agree within a tenth of the bake's 1 % bound.
        let hot = Vec3::new(0.3, 0.2, 0.9).normalize();
        let img = latlong(512, 256, |d| sharp(d, hot, 0.9995, 500.0));
        let a = Oracle::new(&img);
        let b = Oracle::new(&img).with_tolerance(a.tolerance() / 2.0);
        for r in [0.1f32, 0.3, 0.7] {
            let (x, y) = (a.prefiltered(r, &dirs()), b.prefiltered(r, &dirs()));
            for (p, q) in x.iter().zip(&y) {
                let rel = (p[0] - q[0]).abs() / q[0];
                assert!(rel < 1e-3, "{r}: {p:?} {q:?} ({rel})");
            }
        }
    }
}
