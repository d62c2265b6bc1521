// The DFG integral at one (N·V, roughness): Gauss–Legendre quadrature on
// panels in τ = ln tan θ and φ, four nodes at a time, in f64.

use crate::par::*;
use wide::f64x4;

use super::{DfgGrid, MIN_ARGUMENT};
use crate::filter::quadrature::Gauss;

/// The rule's parameters: points per panel, panel widths, thresholds.
#[derive(Clone, Copy, Debug)]
pub(super) struct Params {
    /// Gauss points in ξ on the full region's lower part.
    full_xi: usize,
    /// Gauss points per τ panel of the full region.
    full_tau: usize,
    /// Width of the full region's τ panels.
    full_width: f64,
    /// Midpoint-rule points in φ on [0, π] in the full region (a multiple
    /// of 4).
    full_phi: usize,
    /// Gauss points per τ panel of the partial region.
    partial_tau: usize,
    /// Widest τ panel of the partial region.
    partial_width: f64,
    /// Gauss points per φ panel of the partial region (a multiple of 4).
    partial_phi: usize,
    /// Ratio of successive φ panels graded towards φₘ.
    grading: f64,
    /// One φ panel when the near singularity is at least this fraction of
    /// φₘ away.
    single_panel: f64,
    /// τ panels whose contribution is bounded below this are skipped.
    skip: f64,
    /// The φ grading stops at a layer whose contribution is bounded below
    /// this.
    layer: f64,
}

impl Params {
    /// What tables and [`dfg_integral`] use.
    pub(super) const STANDARD: Params = Params {
        full_xi: 8,
        full_tau: 8,
        full_width: 2.0,
        full_phi: 8,
        partial_tau: 8,
        partial_width: 2.0,
        partial_phi: 4,
        grading: 6.0,
        single_panel: 0.5,
        skip: 1e-10,
        layer: 1e-10,
    };

    /// The same panels with four times the points on each, and the
    /// skipping and grading thresholds at 10⁻¹⁴: the finer run the rule is
    /// checked against.
    #[cfg(test)]
    const FINE: Params = Params {
        full_xi: 32,
        full_tau: 32,
        full_phi: 32,
        partial_tau: 32,
        partial_phi: 16,
        skip: 1e-14,
        layer: 1e-14,
        ..Params::STANDARD
    };
}

/// cos φ for φ in [0, π], four at a time: sin(π/2 − φ) by its Taylor series
/// to x¹⁷ (truncation error below 5·10⁻¹⁴ on [−π/2, π/2]), the polynomial
/// in x² by Estrin's scheme.
#[inline(always)]
fn cos_0_pi(phi: f64x4) -> f64x4 {
    let splat = f64x4::splat;
    let x = splat(std::f64::consts::FRAC_PI_2) - phi;
    let y = x * x;
    // sin x = x − x³·p(x²), p(y) = Σ (−y)^k / (2k + 3)!, k = 0..=7.
    let q0 = splat(1.0 / 6.0) - splat(1.0 / 120.0) * y;
    let q1 = splat(1.0 / 5_040.0) - splat(1.0 / 362_880.0) * y;
    let q2 = splat(1.0 / 39_916_800.0) - splat(1.0 / 6_227_020_800.0) * y;
    let q3 = splat(1.0 / 1_307_674_368_000.0) - splat(1.0 / 355_687_428_096_000.0) * y;
    let y2 = y * y;
    let r0 = q0 + q1 * y2;
    let r1 = q2 + q3 * y2;
    let p = r0 + r1 * (y2 * y2);
    x - x * y * p
}

/// The constants of the integrand at one (μ, α).
#[derive(Clone, Copy, Debug)]
struct Point {
    mu: f64,
    /// √(1 − μ²).
    sv: f64,
    /// α².
    a2: f64,
    /// 1 − α².
    one_minus_a2: f64,
    /// √(μ²(1 − α²) + α²).
    av: f64,
}

impl Point {
    /// `((1 − Fc)·V', Fc·V')` at four half vectors with cos θ = `c`,
    /// sin θ = `s` and azimuth cosines `cos_phi`; 0 below the horizon.
    #[inline(always)]
    fn sample4(&self, c: f64x4, s: f64x4, cos_phi: f64x4) -> (f64x4, f64x4) {
        let splat = f64x4::splat;
        let mu = splat(self.mu);
        let voh = splat(self.sv) * s * cos_phi + mu * c;
        let nol = (splat(2.0) * c * voh - mu).max(f64x4::ZERO);
        // V' = 4·V_HC·NoL·VoH/NoH with V_HC = 0.5/den, and den ≥ μα > 0.
        let den = nol * splat(self.av)
            + mu * (nol * nol * splat(self.one_minus_a2) + splat(self.a2)).sqrt();
        let v = splat(2.0) * nol * voh / (c * den);
        let f = f64x4::ONE - voh;
        let f2 = f * f;
        let fc = f2 * f2 * f;
        (v - fc * v, fc * v)
    }
}

/// cos θ and sin θ from t = tan θ ≥ 0.
#[inline(always)]
fn cos_sin(t: f64) -> (f64, f64) {
    let c = 1.0 / (1.0 + t * t).sqrt();
    (c, t * c)
}

/// Four nodes, ready to evaluate: cos θ, sin θ, φ (its cosine in the full
/// region), and the weight (of θ and φ together, 1/π included).
#[derive(Clone, Copy, Debug)]
struct Lanes {
    c: f64x4,
    s: f64x4,
    x: f64x4,
    w: f64x4,
}

/// The nodes of one (μ, r), kept between calls to save allocations.
#[derive(Clone, Debug, Default)]
pub(super) struct Scratch {
    full: Vec<Lanes>,
    partial: Vec<Lanes>,
}

/// A τ node of the partial region, with what depends on μ only.
#[derive(Clone, Copy, Debug)]
struct TauNode {
    /// t = tan θ = e^τ.
    t: f64,
    /// cos θ.
    c: f64,
    /// sin θ.
    s: f64,
    /// √(cosh τ / √(1 − μ²)).
    sqrt_ch_sv: f64,
    /// φₘ.
    pm: f64,
    /// sin φₘ.
    sin_pm: f64,
    /// The node's quadrature weight in τ.
    w: f64,
}

/// A τ panel [lo, hi] of the partial region and its nodes.
#[derive(Clone, Debug)]
struct TauPanel {
    lo: f64,
    hi: f64,
    /// e^lo, e^hi.
    exp_lo: f64,
    exp_hi: f64,
    nodes: Vec<TauNode>,
}

/// What depends on μ only: τ₁ and the partial region's τ panels.
#[derive(Clone, Debug)]
pub(super) struct Column {
    mu: f64,
    /// √(1 − μ²).
    sv: f64,
    /// τ₁ = −asinh k.
    t1: f64,
    partial: Vec<TauPanel>,
}

/// A quadrature rule: its parameters and tables. On each region of the
/// module docs' τ axis:
///
/// * **Full region.** 8 Gauss points in ξ below min(τ₁, ln α) (the
///   φ-average is smooth in ξ there), then τ panels of width at most 2; the
///   one next to τ₁ has its nodes gathered towards it (τ = τ₁ − h·u²)
///   because the pole and branch points of V_HC come within about α/μ of
///   the real τ axis there. In φ, the midpoint rule over the whole period,
///   which converges geometrically for a periodic integrand analytic in
///   cos φ.
/// * **Partial region.** At least two τ panels of width at most 2; φₘ has a
///   square-root singularity at τ₁ and τ₂, which τ = τ₁ + h·u²
///   (τ = τ₂ − h·u²) on the end panels removes. In φ, Gauss panels graded
///   geometrically towards φₘ, because the same singularities lie just
///   beyond it.
/// * **Skipping.** A τ panel, or a φ layer, is skipped when a bound on its
///   contribution is below 10⁻¹⁰: the largest density on it times
///   V' ≤ 2√(1 + t²)/√(μ²(1 − α²) + α²) times its width.
///
/// A texel's nodes are gathered first and evaluated four at a time
/// (`wide::f64x4`), what depends on μ only once per column, and rows run in
/// parallel.
#[derive(Clone, Debug)]
pub(super) struct Rule {
    p: Params,
    full_xi: Gauss,
    full_tau: Gauss,
    partial_tau: Gauss,
    /// The φ panels' Gauss rule, four nodes (and weights) at a time.
    partial_phi: Vec<(f64x4, f64x4)>,
    /// cos φ at the midpoint nodes (k + ½)π/n, four at a time.
    full_cos: Vec<f64x4>,
}

impl Rule {
    pub(super) fn new(p: Params) -> Rule {
        let n = p.full_phi.div_ceil(4).max(1) * 4;
        let cosines: Vec<f64> = (0..n)
            .map(|k| ((k as f64 + 0.5) * std::f64::consts::PI / n as f64).cos())
            .collect();
        let phi = Gauss::new(p.partial_phi.div_ceil(4).max(1) * 4);
        let four = |v: &[f64]| f64x4::new([v[0], v[1], v[2], v[3]]);
        Rule {
            full_xi: Gauss::new(p.full_xi),
            full_tau: Gauss::new(p.full_tau),
            partial_tau: Gauss::new(p.partial_tau),
            partial_phi: phi
                .nodes
                .chunks_exact(4)
                .zip(phi.weights.chunks_exact(4))
                .map(|(x, w)| (four(x), four(w)))
                .collect(),
            full_cos: cosines.chunks_exact(4).map(four).collect(),
            p,
        }
    }

    /// μ's column (μ in [MIN_ARGUMENT, 1]).
    fn column(&self, mu: f64) -> Column {
        let sv = ((1.0 - mu) * (1.0 + mu)).sqrt();
        let k = sv / mu;
        let t1 = -k.asinh();
        let t2 = k.asinh();
        let panel = |lo: f64, hi: f64, nodes: Vec<TauNode>| TauPanel {
            lo,
            hi,
            exp_lo: lo.exp(),
            exp_hi: hi.exp(),
            nodes,
        };
        // Partial region: at least two panels.
        let mut partial = Vec::new();
        if t2 > t1 {
            let len = t2 - t1;
            let m = (len / self.p.partial_width).ceil().max(2.0) as usize;
            let h = len / m as f64;
            for j in 0..m {
                let lo = t1 + j as f64 * h;
                let hi = if j + 1 == m { t2 } else { lo + h };
                let nodes = self
                    .partial_tau
                    .iter()
                    .map(|(x, g)| {
                        // φₘ's square-root end points: τ = τ₁ + h·u²,
                        // τ = τ₂ − h·u².
                        let (tau, w) = if j == 0 {
                            (lo + h * x * x, g * 2.0 * h * x)
                        } else if j + 1 == m {
                            (hi - h * x * x, g * 2.0 * h * x)
                        } else {
                            (lo + h * x, g * h)
                        };
                        let t = tau.exp();
                        let (c, s) = cos_sin(t);
                        let ch = 0.5 * (t + 1.0 / t);
                        let sh = 0.5 * (t - 1.0 / t);
                        let bm = (sh / k).clamp(-1.0, 1.0);
                        TauNode {
                            t,
                            c,
                            s,
                            sqrt_ch_sv: (ch / sv).sqrt(),
                            pm: bm.acos(),
                            sin_pm: ((1.0 - bm) * (1.0 + bm)).sqrt(),
                            w,
                        }
                    })
                    .collect();
                partial.push(panel(lo, hi, nodes));
            }
        }
        Column {
            mu,
            sv,
            t1,
            partial,
        }
    }

    /// The φ nodes of the full region's integral (1/π)∫₀^π (the midpoint
    /// rule) at a θ whose own weight is `wt`, pushed onto `out` with their
    /// cosines in place of φ.
    #[inline]
    fn full_nodes(&self, c: f64, s: f64, wt: f64, out: &mut Vec<Lanes>) {
        let w = f64x4::splat(wt / (4 * self.full_cos.len()).max(1) as f64);
        let (c, s) = (f64x4::splat(c), f64x4::splat(s));
        for &x in &self.full_cos {
            out.push(Lanes { c, s, x, w });
        }
    }

    /// The φ nodes of the partial region's integral over [0, φₘ] at a τ
    /// node whose own weight is `wt`, pushed onto `out` (the weights
    /// include `wt` and 1/π); `sqrt_delta` is √min(μ, α/√(1 − α²)).
    #[inline]
    fn partial_nodes(
        &self,
        node: &TauNode,
        wt: f64,
        sqrt_delta: f64,
        d_min: f64,
        out: &mut Vec<Lanes>,
    ) {
        let pm = node.pm;
        if pm.is_nan() || pm <= 0.0 {
            return;
        }
        // About the distance from φₘ to where NoL = delta, which is about
        // how far the nearest singularity of V_HC is (exact to a factor √2);
        // no closer than `d_min`, a layer too thin to matter.
        let sqrt_dc = sqrt_delta * node.sqrt_ch_sv;
        let dc = sqrt_dc * sqrt_dc;
        let mut d = (dc / (node.sin_pm + sqrt_dc)).max(d_min).min(pm);
        let (c, s) = (f64x4::splat(node.c), f64x4::splat(node.s));
        let scale = wt / std::f64::consts::PI;
        let mut panel = |lo: f64, hi: f64| {
            let h = f64x4::splat(hi - lo);
            let w = f64x4::splat((hi - lo) * scale);
            let lo = f64x4::splat(lo);
            for &(x, g) in &self.partial_phi {
                out.push(Lanes {
                    c,
                    s,
                    x: lo + h * x,
                    w: w * g,
                });
            }
        };
        if d.is_nan() || d >= self.p.single_panel * pm {
            panel(0.0, pm);
        } else {
            let mut hi = pm;
            loop {
                let lo = pm - d;
                if lo.is_nan() || lo <= 0.0 {
                    panel(0.0, hi);
                    break;
                }
                panel(lo, hi);
                hi = lo;
                d *= self.p.grading;
            }
        }
    }

    /// (scale, bias) at μ and r, clamped into [MIN_ARGUMENT, 1]; NaN gives
    /// NaN.
    fn integrate(&self, mu: f64, r: f64) -> (f64, f64) {
        if mu.is_nan() || r.is_nan() {
            return (f64::NAN, f64::NAN);
        }
        let col = self.column(mu.clamp(MIN_ARGUMENT, 1.0));
        self.integrate_in(&col, r, &mut Scratch::default())
    }

    /// (scale, bias) in μ's column at r (not NaN); `scratch` holds the
    /// nodes.
    pub(super) fn integrate_in(&self, col: &Column, r: f64, scratch: &mut Scratch) -> (f64, f64) {
        let mu = col.mu;
        let r = r.clamp(MIN_ARGUMENT, 1.0);
        let alpha = r * r;
        let a2 = alpha * alpha;
        let pt = Point {
            mu,
            sv: col.sv,
            a2,
            one_minus_a2: 1.0 - a2,
            av: (mu * mu * (1.0 - a2) + a2).sqrt(),
        };
        let ln_a = alpha.ln();
        // The density of τ, dξ/dτ = 2t²α²/(α² + t²)².
        let density = |t: f64| {
            let q = a2 + t * t;
            2.0 * t * t * a2 / (q * q)
        };
        // A bound on a τ panel's contribution: the largest density on it
        // (at t = α if inside), times V' ≤ 2√(1 + t²)/av ≤ 2√2·max(1, t)/av
        // at its top, times its width; from e^lo and e^hi.
        let bound_exp = |exp_lo: f64, exp_hi: f64, width: f64| {
            density(alpha.clamp(exp_lo, exp_hi))
                * (2.0 * std::f64::consts::SQRT_2 / pt.av)
                * exp_hi.max(1.0)
                * width
        };
        let bound = |lo: f64, hi: f64| bound_exp(lo.exp(), hi.exp(), hi - lo);
        scratch.full.clear();
        scratch.partial.clear();

        // Full region, lower part: ξ ∈ [0, ξa], up to τa = min(τ₁, ln α).
        let t1 = col.t1;
        let ta = t1.min(ln_a);
        let ea = ta.exp();
        let xa = ea * ea / (a2 + ea * ea);
        for (x, w) in self.full_xi.iter() {
            let xi = xa * x;
            let (c, s) = cos_sin(alpha * (xi / (1.0 - xi)).sqrt());
            self.full_nodes(c, s, w * xa, &mut scratch.full);
        }

        // Full region, upper part: τ ∈ [τa, τ₁]. On the panel next to τ₁ the
        // nodes gather towards it (τ = τ₁ − h·u²), because V_HC's
        // singularities come within about α/μ of the real line there.
        if t1 > ta {
            let len = t1 - ta;
            let m = (len / self.p.full_width).ceil().max(1.0) as usize;
            let h = len / m as f64;
            for j in 0..m {
                let lo = ta + j as f64 * h;
                let hi = if j + 1 == m { t1 } else { lo + h };
                if bound(lo, hi) < self.p.skip {
                    continue;
                }
                for (x, w) in self.full_tau.iter() {
                    let (tau, w) = if j + 1 == m {
                        (hi - h * x * x, w * 2.0 * h * x)
                    } else {
                        (lo + h * x, w * h)
                    };
                    let t = tau.exp();
                    let (c, s) = cos_sin(t);
                    self.full_nodes(c, s, w * density(t), &mut scratch.full);
                }
            }
        }

        // Partial region: τ ∈ [τ₁, τ₂].
        // NoL at V_HC's branch points is α/√(1 − α²) (none at α = 1).
        let delta = if a2 < 1.0 {
            mu.min(alpha / (1.0 - a2).sqrt())
        } else {
            mu
        };
        let sqrt_delta = delta.sqrt();
        for panel in &col.partial {
            if bound_exp(panel.exp_lo, panel.exp_hi, panel.hi - panel.lo) < self.p.skip {
                continue;
            }
            for node in &panel.nodes {
                let wt = node.w * density(node.t);
                // A φ layer of width d contributes at most wt·V'max·d/π,
                // with V'max = 2√(1 + t²)/av = 2/(c·av).
                let d_min = self.p.layer * std::f64::consts::FRAC_PI_2 * node.c * pt.av / wt;
                self.partial_nodes(node, wt, sqrt_delta, d_min, &mut scratch.partial);
            }
        }

        // Every node, in two loops, four at a time.
        let (mut a, mut b) = (f64x4::ZERO, f64x4::ZERO);
        for l in &scratch.full {
            let (u, v) = pt.sample4(l.c, l.s, l.x);
            a += l.w * u;
            b += l.w * v;
        }
        for l in &scratch.partial {
            let (u, v) = pt.sample4(l.c, l.s, cos_0_pi(l.x));
            a += l.w * u;
            b += l.w * v;
        }
        (a.reduce_add(), b.reduce_add())
    }
}

/// The split-sum `(scale, bias)` at μ = N·V and perceptual roughness `r`,
/// in f64: `scale = E[(1 − Fc)·V']`, `bias = E[Fc·V']` with the
/// height-correlated Smith visibility. The [module docs](super) give the
/// integral, the quadrature and its accuracy.
///
/// μ and `r` are clamped into [[`MIN_ARGUMENT`], 1]. A NaN argument gives
/// `(NaN, NaN)`. The multiscatter pair is `(bias, scale + bias)`.
///
/// ```
/// use envmap_render::filter::dfg::dfg_integral;
/// // At α = 1 the height-correlated albedo is 1 − μ·ln(1 + 1/μ).
/// let (scale, bias) = dfg_integral(0.5, 1.0);
/// assert!((scale + bias - (1.0 - 0.5 * 3.0f64.ln())).abs() < 1e-6);
/// ```
#[cfg_attr(feature = "instruments", visibility::make(pub))]
#[must_use]
pub(crate) fn dfg_integral(mu: f64, r: f64) -> (f64, f64) {
    Rule::new(Params::STANDARD).integrate(mu, r)
}

/// Every column of a table of `size` on `grid`.
pub(super) fn columns(rule: &Rule, size: u32, grid: DfgGrid) -> Vec<Column> {
    (0..size)
        .into_par_iter()
        .map(|i| rule.column(grid.point(i, size).max(MIN_ARGUMENT)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::super::check_size;
    use super::*;
    use crate::error::Result;

    /// Every texel's (scale, bias) in f64, row-major, with the rule `p`.
    fn table_f64(size: u32, p: Params) -> Result<Vec<(f64, f64)>> {
        check_size(size)?;
        let rule = Rule::new(p);
        let columns = columns(&rule, size, DfgGrid::TexelCentres);
        Ok((0..size)
            .into_par_iter()
            .flat_map_iter(|j| {
                let r = texel_point(j, size);
                let mut scratch = Scratch::default();
                columns
                    .iter()
                    .map(|c| rule.integrate_in(c, r, &mut scratch))
                    .collect::<Vec<_>>()
            })
            .collect())
    }

    /// (index + 0.5)/size, in f64.
    #[inline]
    fn texel_point(index: u32, size: u32) -> f64 {
        (f64::from(index) + 0.5) / f64::from(size)
    }

    /// Adaptive quadrature (QUADPACK, scipy's `dblquad` at 10⁻¹⁰) of the
    /// same expectation written over the hemisphere of L,
    /// `∫ (1 − Fc | Fc)·D(h)·V_HC·NoL dω_L`: an independent formulation.
    /// Each line: μ, r, scale, bias.
    const HEMISPHERE_OF_L: [(f64, f64, f64, f64); 16] = [
        // The points of the 4-decimal reference table (`PRINTED`).
        (0.1, 0.25, 5.051472815538e-01, 3.916223537554e-01),
        (0.1, 0.5, 7.519299007931e-01, 1.396924510164e-01),
        (0.1, 1.0, 7.363435779070e-01, 2.386689481313e-02),
        (0.5, 0.25, 9.556866708417e-01, 3.263732939510e-02),
        (0.5, 0.5, 8.349161392934e-01, 2.234729628821e-02),
        (0.5, 0.75, 6.546928351455e-01, 8.483010131869e-03),
        (0.5, 1.0, 4.477051204110e-01, 2.988735254971e-03),
        (0.9, 0.5, 9.070363400458e-01, 3.467505870395e-04),
        (1.0, 0.25, 9.956851106765e-01, 2.950018170732e-06),
        (1.0, 0.5, 9.157850593233e-01, 2.737092642561e-05),
        (1.0, 1.0, 3.068192051453e-01, 3.361429472552e-05),
        // Texel centres of the 128² table: its corners and edges.
        (1.0 / 256.0, 255.0 / 256.0, 0.932827340213, 0.045650531883),
        (255.0 / 256.0, 255.0 / 256.0, 0.311494815294, 0.000037369525),
        (1.0 / 256.0, 0.5, 0.801648642201, 0.190352239753),
        (0.5, 255.0 / 256.0, 0.450880229847, 0.003036733687),
        (255.0 / 256.0, 0.5, 0.915479656269, 0.000032257673),
    ];

    /// The same by adaptive quadrature over the hemisphere of H, in τ and φ
    /// with the exact φ limits (QUADPACK's `quad`, nested, at 10⁻¹²), where
    /// the GGX lobe is too narrow for the hemisphere of L. It agrees with
    /// [`HEMISPHERE_OF_L`] to 2·10⁻¹⁴ wherever both were run.
    const HEMISPHERE_OF_H: [(f64, f64, f64, f64); 3] = [
        (1.0 / 256.0, 1.0 / 256.0, 0.019381469357, 0.980610858560),
        (255.0 / 256.0, 1.0 / 256.0, 0.999999999765, 0.000000000001),
        (0.5, 1.0 / 256.0, 0.968749998114, 0.031250001304),
    ];

    /// A commonly quoted table of Filament's height-correlated DFG, made
    /// with Filament's estimator at 2¹⁶ Hammersley samples: μ, r, scale,
    /// bias, printed to 4 decimals.
    const PRINTED: [(f64, f64, f64, f64); 11] = [
        (0.1, 0.25, 0.5056, 0.3916),
        (0.1, 0.5, 0.7520, 0.1397),
        (0.1, 1.0, 0.7363, 0.0239),
        (0.5, 0.25, 0.9556, 0.0326),
        (0.5, 0.5, 0.8349, 0.0223),
        (0.5, 0.75, 0.6547, 0.0085),
        (0.5, 1.0, 0.4477, 0.0030),
        (0.9, 0.5, 0.9070, 0.0003),
        (1.0, 0.25, 0.9957, 0.0000),
        (1.0, 0.5, 0.9158, 0.0000),
        (1.0, 1.0, 0.3068, 0.0000),
    ];

    /// Filament's `DFV` estimator in f64: `n` Hammersley points, H from
    /// the GGX CDF, `4/n · Σ (1 − Fc | Fc)·V_HC·NoL·VoH/NoH` over NoL > 0.
    fn hammersley(mu: f64, r: f64, n: u32) -> (f64, f64) {
        let a = r * r;
        let v = [(1.0 - mu * mu).sqrt(), 0.0, mu];
        let (mut s, mut b) = (0.0, 0.0);
        for i in 0..n {
            let u1 = f64::from(i) / f64::from(n);
            let u2 = f64::from(i.reverse_bits()) / 4_294_967_296.0;
            let phi = 2.0 * std::f64::consts::PI * u1;
            let ct = ((1.0 - u2) / (1.0 + (a * a - 1.0) * u2)).sqrt();
            let st = (1.0 - ct * ct).sqrt();
            let h = [st * phi.cos(), st * phi.sin(), ct];
            let voh = v[0] * h[0] + v[2] * h[2];
            let nol = 2.0 * voh * h[2] - v[2];
            if nol > 0.0 {
                let vis = 0.5
                    / (nol * (mu * mu * (1.0 - a * a) + a * a).sqrt()
                        + mu * (nol * nol * (1.0 - a * a) + a * a).sqrt());
                let g = vis * nol * voh / h[2];
                let fc = (1.0 - voh).powi(5);
                s += g * (1.0 - fc);
                b += g * fc;
            }
        }
        (4.0 * s / f64::from(n), 4.0 * b / f64::from(n))
    }

    /// The worst of |scale − scale'| and |bias − bias'| over two tables, and
    /// the texel (column, row) where it is.
    fn worst(a: &[(f64, f64)], b: &[(f64, f64)], size: u32) -> (f64, u32, u32) {
        let mut w = (0.0, 0, 0);
        for (k, (x, y)) in (0u32..).zip(a.iter().zip(b)) {
            let e = (x.0 - y.0).abs().max((x.1 - y.1).abs());
            if e > w.0 {
                w = (e, k % size, k / size);
            }
        }
        w
    }

    #[test]
    fn cosine_series_matches_the_library() {
        let mut worst = 0.0f64;
        for k in 0..=10_000 {
            let phi = std::f64::consts::PI * f64::from(k) / 10_000.0;
            let c = cos_0_pi(f64x4::splat(phi)).to_array()[0];
            worst = worst.max((c - phi.cos()).abs());
        }
        assert!(worst < 1e-13, "{worst}");
    }

    /// α = 1 (r = 1): the height-correlated albedo has the closed form
    /// scale + bias = 1 − μ·ln(1 + 1/μ). Asserted to the stated accuracy
    /// (10⁻⁵) at every texel centre of a 128² and of a 1024² table's row.
    #[test]
    fn rough_limit_is_the_closed_form() {
        for size in [128u32, 1024] {
            for i in 0..size {
                let mu = texel_point(i, size);
                let (s, b) = dfg_integral(mu, 1.0);
                let exact = 1.0 - mu * (1.0 + 1.0 / mu).ln();
                assert!((s + b - exact).abs() < 1e-5, "μ {mu}: {} vs {exact}", s + b);
            }
        }
        // As printed: 0.30685 at μ = 1, 0.4507 at 0.5, 0.7602 at 0.1.
        for (mu, printed, half_unit) in [
            (1.0, 0.30685, 5e-6),
            (0.5, 0.4507, 5e-5),
            (0.1, 0.7602, 5e-5),
        ] {
            let (s, b) = dfg_integral(mu, 1.0);
            assert!((s + b - printed).abs() < half_unit, "μ {mu}: {}", s + b);
        }
    }

    /// α → 0: scale + bias → 1 and bias → (1 − μ)⁵. At r = 2⁻¹⁴ (α = 2⁻²⁸)
    /// both hold to 10⁻⁸ at every texel centre of the 128² table's row. The
    /// table's own top row (r = 1/256, α = 1.5·10⁻⁵) is within 2·10⁻⁵ of the
    /// limit: the integral itself is that far from it there, not the rule.
    #[test]
    fn smooth_limit_is_the_closed_form() {
        for i in 0..128 {
            let mu = texel_point(i, 128);
            let (s, b) = dfg_integral(mu, MIN_ARGUMENT);
            let fresnel = (1.0 - mu).powi(5);
            assert!((s + b - 1.0).abs() < 1e-8, "μ {mu}: sum {}", s + b);
            assert!((b - fresnel).abs() < 1e-8, "μ {mu}: bias {b} vs {fresnel}");
            let (s, b) = dfg_integral(mu, 1.0 / 256.0);
            assert!((s + b - 1.0).abs() < 2e-5, "μ {mu}: sum {}", s + b);
            assert!((b - fresnel).abs() < 2e-5, "μ {mu}: bias {b} vs {fresnel}");
        }
    }

    /// The rule against adaptive quadrature of the exact integral, at the
    /// reference table's points and at the 128² table's corners and edges,
    /// to the stated accuracy (10⁻⁵).
    #[test]
    fn matches_adaptive_quadrature() {
        for &(mu, r, rs, rb) in HEMISPHERE_OF_L.iter().chain(&HEMISPHERE_OF_H) {
            let (s, b) = dfg_integral(mu, r);
            let e = (s - rs).abs().max((b - rb).abs());
            assert!(e < 1e-5, "({mu}, {r}): ({s}, {b}) vs ({rs}, {rb})");
        }
    }

    /// The 4-decimal reference table ([`PRINTED`]). Filament's estimator
    /// with 2¹⁶ Hammersley points, which is how it was made, reproduces all
    /// 22 printed numbers. The integral matches 19 of them to the printed
    /// digits (within half a unit of the 4th decimal). The other three are
    /// the estimator's own error: at (0.1, 0.25) the printed scale 0.5056 is
    /// 4.5·10⁻⁴ above the integral (0.50515, by two independent adaptive
    /// quadratures), at (0.1, 0.5) it is 0.7520 against 0.75193, and at
    /// (0.5, 0.25) it is 0.9556 against 0.95569.
    #[test]
    fn matches_the_printed_table() {
        let off = [(0.1, 0.25), (0.1, 0.5), (0.5, 0.25)];
        for &(mu, r, ps, pb) in &PRINTED {
            let (hs, hb) = hammersley(mu, r, 1 << 16);
            assert!(
                (hs - ps).abs() <= 5e-5,
                "({mu}, {r}) sampled scale {hs} vs {ps}"
            );
            assert!(
                (hb - pb).abs() <= 5e-5,
                "({mu}, {r}) sampled bias {hb} vs {pb}"
            );
            let (s, b) = dfg_integral(mu, r);
            assert!((b - pb).abs() <= 5e-5, "({mu}, {r}) bias {b} vs {pb}");
            if off.contains(&(mu, r)) {
                assert!((s - ps).abs() > 5e-5, "({mu}, {r}) scale {s} vs {ps}");
                assert!((s - ps).abs() < 5e-4, "({mu}, {r}) scale {s} vs {ps}");
            } else {
                assert!((s - ps).abs() <= 5e-5, "({mu}, {r}) scale {s} vs {ps}");
            }
        }
    }

    /// The convergence check: the 128² table against the same rule with
    /// four times the points on every panel (and the skipping and grading
    /// thresholds at 10⁻¹⁴): below 10⁻⁴ at every texel (a debug build checks
    /// every 8th row and column and the last ones, the release build all of
    /// them).
    #[test]
    fn finer_run_agrees_within_1e_4() {
        let size = 128;
        let coarse = table_f64(size, Params::STANDARD).unwrap();
        let (w, i, j) = if cfg!(debug_assertions) {
            let rule = Rule::new(Params::FINE);
            let picks: Vec<u32> = (0..size).step_by(8).chain([size - 1]).collect();
            let mut w = (0.0, 0, 0);
            for &j in &picks {
                for &i in &picks {
                    let (s, b) = rule.integrate(texel_point(i, size), texel_point(j, size));
                    let (cs, cb) = coarse[(j * size + i) as usize];
                    let e = (s - cs).abs().max((b - cb).abs());
                    if e > w.0 {
                        w = (e, i, j);
                    }
                }
            }
            w
        } else {
            let fine = table_f64(size, Params::FINE).unwrap();
            worst(&coarse, &fine, size)
        };
        assert!(w < 1e-4, "worst {w:e} at texel ({i}, {j})");
    }

    /// Corners beyond the 128² table, down to [`MIN_ARGUMENT`] (the
    /// centres of a 4096² table are at 2⁻¹³ and above), to the same 10⁻⁴.
    #[test]
    fn small_arguments_converge() {
        let coarse = Rule::new(Params::STANDARD);
        let fine = Rule::new(Params::FINE);
        let m = MIN_ARGUMENT;
        let e13 = 2.0 * MIN_ARGUMENT;
        for (mu, r) in [
            (m, m),
            (m, 0.5),
            (m, 1.0),
            (0.5, m),
            (1.0, m),
            (e13, e13),
            (e13, 0.3),
            (0.3, e13),
            (e13, 1.0),
        ] {
            let (s, b) = coarse.integrate(mu, r);
            let (fs, fb) = fine.integrate(mu, r);
            let e = (s - fs).abs().max((b - fb).abs());
            assert!(e < 1e-4, "({mu}, {r}): {e:e}");
        }
    }

    #[test]
    fn arguments_are_clamped_and_nan_gives_nan() {
        assert_eq!(dfg_integral(0.0, 0.5), dfg_integral(MIN_ARGUMENT, 0.5));
        assert_eq!(dfg_integral(-3.0, 0.5), dfg_integral(MIN_ARGUMENT, 0.5));
        assert_eq!(dfg_integral(2.0, 0.5), dfg_integral(1.0, 0.5));
        assert_eq!(dfg_integral(0.5, 0.0), dfg_integral(0.5, MIN_ARGUMENT));
        assert_eq!(dfg_integral(0.5, f64::INFINITY), dfg_integral(0.5, 1.0));
        assert_eq!(
            dfg_integral(f64::NEG_INFINITY, 0.5),
            dfg_integral(MIN_ARGUMENT, 0.5)
        );
        let (s, b) = dfg_integral(f64::NAN, 0.5);
        assert!(s.is_nan() && b.is_nan());
        let (s, b) = dfg_integral(0.5, f64::NAN);
        assert!(s.is_nan() && b.is_nan());
    }
}
