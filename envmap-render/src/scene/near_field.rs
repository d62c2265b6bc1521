// The near field: the lobe between roughness 0 and the chain's first level,
// integrated over the source map around R where no level holds it.

/// Radii of [`NearField`]'s quadrature (log-spaced, plus a central disk).
const NEAR_RADII: usize = 48;
/// The most angles of [`NearField`]'s quadrature on one ring; a ring has
/// one per half texel of the source along it, at least 8.
const NEAR_ANGLES: usize = 64;
/// [`NearField`]'s cap, in half-vector angle, as a multiple of level 1's
/// α: there the two lobes' tails agree in shape within 1.3 %.
const NEAR_CAP: f64 = 12.0;

/// The lobe at a roughness r between 0 and the chain's first level above
/// it (r₁), where no level holds it: a GGX lobe's weight lies far out in
/// its tail (the share beyond half-vector angle θh is α²/(α² + θh²): a
/// sun one texel wide holds little more than half of a lobe whose
/// half-maximum is half a texel), so neither the input (a delta) nor the
/// level at r₁ nor any blend of the two stands for it near a sun.
///
/// Far from R the two lobes have one shape: w_r ≈ s·w₁ with s = (α/α₁)²
/// for θh ≫ α₁ (GGX's tail is α²/(π θh⁴)). So, with w the split sum's
/// weight D((1 + c)/2)·c and Z₁ = ∫ w₁,
///
/// ```text
/// LD_r(R) = [ s·Z₁·LD₁(R) + ∫_cap L(l)·(w_r − s·w₁)(R·l) dl ] / [ s·Z₁ + ∫_cap (w_r − s·w₁) ]
/// ```
///
/// with LD₁ the chain's level at r₁ and the cap θh ≤ 12 α₁ around R
/// integrated over the input itself (read bilinearly, as at roughness 0)
/// by a midpoint rule on rings: [`NEAR_RADII`] radii spaced evenly in ln θ
/// from θ = α/8 (a central disk within it, one node at R) to the cap,
/// each ring with one node per half texel of the source along it (8 to
/// [`NEAR_ANGLES`]), offset by half a step from ring to ring (a
/// one-texel sun between two nodes of a ring is what a coarser ring
/// misses). The denominator is the same
/// sum for L = 1, so a constant map gives its constant; what is left out
/// is the two tails' difference beyond the cap (under 1.3 % of a tail that
/// holds (α/α₁)²·α₁²/(α₁² + (12α₁)²) < 0.7 % of the weight). At r → r₁,
/// s → 1 and the cap's kernel vanishes: LD₁; at r → 0 the input at R.
/// Costs up to NEAR_RADII × NEAR_ANGLES bilinear reads of the input per
/// lookup.
#[derive(Debug)]
pub(super) struct NearField {
    /// Per node: cos θ and sin θ·(cos φ, sin φ), in R's frame.
    pub(super) nodes: Vec<[f32; 3]>,
    /// Per node: (w_r − s·w₁)·sin θ·dθ·dφ.
    pub(super) weights: Vec<f32>,
    /// s·Z₁.
    pub(super) far: f64,
    /// s·Z₁ + the nodes' weights.
    pub(super) total: f64,
}

impl NearField {
    /// The quadrature at roughness `r` below the level at `r1`, over a
    /// source whose texels span `texel` radians.
    pub(super) fn new(r: f32, r1: f32, texel: f64) -> Self {
        use crate::filter::brdf::ggx_d;
        use crate::filter::specular::lobe_normalizer;
        let (a, a1) = (f64::from(r * r).max(1e-8), f64::from(r1 * r1));
        let s = (a / a1) * (a / a1);
        // w(θ) = D((1 + c)/2)·c, with (n·h)² = cos²(θ/2).
        let w = |alpha: f64, th: f64| {
            let h = (0.5 * th).cos();
            ggx_d(h * h, alpha) * th.cos()
        };
        let kernel = |th: f64| w(a, th) - s * w(a1, th);
        let cap = (2.0 * (NEAR_CAP * a1).atan()).min(core::f64::consts::FRAC_PI_2);
        let inner = (a / 8.0).min(cap / 2.0);
        let step = (cap / inner).ln() / NEAR_RADII as f64;
        // The central disk θ < inner as one node at R: the kernel at the
        // radius that halves the disk's area, times that area.
        let disk = core::f64::consts::TAU * (1.0 - inner.cos());
        // (θ, weight per node, nodes on the ring).
        let mut rings = vec![(
            0.0,
            kernel(inner * core::f64::consts::FRAC_1_SQRT_2) * disk,
            1,
        )];
        for k in 0..NEAR_RADII {
            let th = inner * (step * (k as f64 + 0.5)).exp();
            let along = (core::f64::consts::TAU * th.sin() / (0.5 * texel.max(1e-9))).ceil();
            let count = (along.min(NEAR_ANGLES as f64) as usize)
                .next_multiple_of(8)
                .max(8);
            let dphi = core::f64::consts::TAU / count as f64;
            rings.push((th, kernel(th) * th.sin() * th * step * dphi, count));
        }
        let (mut nodes, mut weights) = (Vec::new(), Vec::new());
        let mut sum = 0.0f64;
        for (j, &(th, wt, count)) in rings.iter().enumerate() {
            let dphi = core::f64::consts::TAU / count as f64;
            for i in 0..count {
                let phi = dphi * (i as f64 + 0.5 * (j % 2) as f64);
                let (sp, cp) = phi.sin_cos();
                let (st, ct) = th.sin_cos();
                nodes.push([ct as f32, (st * cp) as f32, (st * sp) as f32]);
                weights.push(wt as f32);
                sum += wt;
            }
        }
        let far = s * lobe_normalizer(a1);
        Self {
            nodes,
            weights,
            far,
            total: far + sum,
        }
    }
}
