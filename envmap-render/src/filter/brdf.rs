// The microfacet BRDF's formulas (GGX's distribution, the height-correlated
// Smith visibility, Schlick's Fresnel, the GGX lobe's width), each written
// once so that everything evaluating them evaluates the same arithmetic.
// The f32 and f64 forms are separate functions: each caller's precision is
// part of its results.

/// GGX D (Walter et al. 2007, "Microfacet Models for Refraction through
/// Rough Surfaces", the GTR2 of Burley 2012) as a function of (n·h)², in
/// f64: α² / (π ((n·h)²(α² − 1) + 1)²).
#[cfg_attr(feature = "instruments", visibility::make(pub))]
#[inline]
#[must_use]
pub(crate) fn ggx_d(noh2: f64, alpha: f64) -> f64 {
    let a2 = alpha * alpha;
    let d = noh2 * (a2 - 1.0) + 1.0;
    a2 / (std::f64::consts::PI * d * d)
}

/// GGX D (Walter et al. 2007) as a function of (n·h)², in f32:
/// α² / (π ((n·h)²(α² − 1) + 1)²), its denominator kept from 0 so that a
/// mirror-like α gives a finite peak.
#[inline]
#[must_use]
pub(crate) fn ggx_d_f32(noh2: f32, alpha: f32) -> f32 {
    let a2 = alpha * alpha;
    let k = noh2 * (a2 - 1.0) + 1.0;
    a2 * core::f32::consts::FRAC_1_PI / (k * k).max(1e-30)
}

/// The height-correlated Smith visibility V = G₂ / (4 N·L N·V) for GGX
/// (Heitz 2014, "Understanding the Masking-Shadowing Function in
/// Microfacet-Based BRDFs"; glTF 2.0 Appendix B; Filament's `Visibility`),
/// in f32, from N·L, N·V and α²; 0 where both are 0.
#[inline]
#[must_use]
pub(crate) fn smith_visibility_f32(nl: f32, nv: f32, alpha2: f32) -> f32 {
    let gv = nl * (nv * nv * (1.0 - alpha2) + alpha2).sqrt();
    let gl = nv * (nl * nl * (1.0 - alpha2) + alpha2).sqrt();
    let d = gv + gl;
    if d > 0.0 {
        0.5 / d
    } else {
        0.0
    }
}

/// Schlick's Fresnel (Schlick 1994, "An Inexpensive BRDF Model for
/// Physically-based Rendering"; Karis 2013 and glTF 2.0 Appendix B use it)
/// in f32: F0 + (1 − F0)(1 − cos)⁵ with reflectance `f0` at normal
/// incidence, `cos` clamped into [0, 1].
#[inline]
#[must_use]
pub(crate) fn schlick_f32(f0: f32, cos: f32) -> f32 {
    let k = (1.0 - cos.clamp(0.0, 1.0)).powi(5);
    f0 + (1.0 - f0) * k
}

/// An angular width of the GGX lobe in l (radians): twice the half angle at
/// which D (Walter et al. 2007) falls to half its peak,
/// 2·atan(α·√(√2 − 1)), in f64.
#[must_use]
pub(crate) fn lobe_width(alpha: f64) -> f64 {
    2.0 * (alpha * (std::f64::consts::SQRT_2 - 1.0).sqrt()).atan()
}

/// The GGX α whose lobe is `width` radians wide: the inverse of the lobe
/// width 2·atan(α·√(√2 − 1)) (twice the half-vector angle at which D falls
/// to half its peak, from Walter et al. 2007's D), in f64.
#[inline]
#[must_use]
pub(crate) fn alpha_of_lobe_width(width: f64) -> f64 {
    (width / 2.0).tan() / (std::f64::consts::SQRT_2 - 1.0).sqrt()
}
