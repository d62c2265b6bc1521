//! The measuring instruments: what envmap's outputs are held to, computed
//! from the input itself by other means than the product's own, and slow
//! where exactness needs it.
//!
//! * `Oracle`: the prefiltered integral LD, the irradiance E and the SH9
//!   coefficients of a map, by adaptive quadrature over its own texels (the
//!   bake's `--check`, the exact split sum, the tests).
//! * The exact split sum (`exact_split_sum`): what the split-sum render
//!   approximates, from the input through the oracle and the exact DFG
//!   integral (`envmap render --exact-split-sum`).
//! * The Monte Carlo reference of the full rendering integral
//!   (`reference`, `envmap render --reference`), with its random
//!   sequence (`Pcg32`, the generator the library's sequences and its
//!   tests draw from) and light sampling by the environment's luminance
//!   ([`EnvSampling`]).
//!
//! Everything here but [`EnvSampling`] (which a reference render is given)
//! is public with the `instruments` feature only.
//!
//! # The oracle
//!
//! `Oracle`: the bake's integrals computed from the input itself, read as
//! piecewise constant over its own texels, independent of the bake's own
//! stages (no base cube, no pyramid, no sampling).
//!
//! ## What it computes
//!
//! The input is a function L on the sphere that is constant over each of its
//! own texels (each texel's value over its exact solid angle, in its own
//! mapping: latlong rows, cube faces, any representation envmap reads). For
//! a direction R the oracle gives, with N = V = R as the split sum takes them
//! (Karis 2013; the formula of [`crate::filter::specular`]):
//!
//! ```text
//! LD(R) = ∫ L(l) w(R·l) dl / ∫ w(R·l) dl,   w(c) = D((1 + c)/2)·c for c > 0, 0 behind
//! E(n)  = ∫ L(l) max(n·l, 0) dl                         (irradiance; E/π is what maps store)
//! L_lm  = ∫ L(l) Y_lm(l) dl                             (SH9, the basis of [`crate::filter::sh`])
//! ```
//!
//! with D the GGX distribution (Walter et al. 2007) at α = roughness².
//!
//! ## How (adaptive quadrature over the input's texels)
//!
//! The texels of each chart are grouped into a tree of rectangles (a leaf
//! holds at most 8 × 8 texels); each node keeps, in f64, its solid angle
//! Σ Ω, its first moment Σ Ω·d, and per channel Σ Ω·L and Σ Ω·L·d, with d a
//! texel's centre direction, plus a cap (centre, angular radius ρ) that
//! holds every one of its texels. For each R the tree is walked from the
//! roots:
//!
//! * a node wholly behind R (the weight is 0 there) is skipped;
//! * a node whose radius is small against the scale on which the weight
//!   changes there, ρ ≤ τ·s(θ) (θ the nearest angle from R to the cap), and
//!   that does not straddle the horizon R·l = 0 (where the weight has a
//!   kink), is taken whole, to first order in the weight:
//!   Σ Ω L w(c_j) ≈ w(c̄)·Σ Ω L + w′(c̄)·(R·Σ Ω L d − c̄·Σ Ω L), c̄ = R·centre, so
//!   its error is second order in ρ/s;
//! * otherwise its children are walked; a leaf's texels are tested one by
//!   one in the same way (each with its own cap), a texel that passes taken
//!   at its centre, one that does not **subdivided** into m × m
//!   sub-rectangles of its chart coordinates, each with its exact solid
//!   angle ([`Mapping::solid_angle`](envmap_core::Mapping::solid_angle)) and its centre's direction, m chosen so
//!   that each part passes the same test (at most 64).
//!
//! s(θ) is max(θ, W) for GGX, W = the GGX lobe's width (`crate::filter::brdf::lobe_width`)
//! (near the peak the lobe changes over its own width, in the tail w falls
//! as θ⁻⁴, changing by a fixed fraction over a fixed fraction of θ), and 1 rad
//! for the cosine. Texels brighter than 64 × the map's mean (by the largest
//! absolute channel: a sun and what rings around it) and the nodes holding
//! them are held to τ/4. The denominator is the same sum with L = 1, so a
//! constant map gives its constant to rounding. τ (`Oracle::tolerance`,
//! default 1/16) sets the accuracy; halving it shows the convergence (the
//! tests and `examples/bake_accuracy.rs` do).
//!
//! SH9 is a sum over every texel split into m × m parts (`sh9(m)`): the
//! basis is a quadratic polynomial, smooth everywhere.
//!
//! ## Between texel centres (`Reconstruction`)
//!
//! `Oracle::new` reads the input as constant over each texel. Where a lobe
//! is wider than a few texels that and any other reading of the texels
//! give the same integrals to second order; where it is narrower (GGX below
//! roughness ≈ 0.1 on a 512-wide map, and the mirror at 0) the integral is
//! the input's value between texel centres, which the texels alone do not
//! define. `Oracle::bilinear` takes it as every renderer and GPU sampler
//! reads it: the bilinear interpolation of the four nearest texel centres
//! with the representation's edge rules ([`Filter::Bilinear`](crate::filter::Filter::Bilinear)). Each texel
//! then stands in the sums for the mean of that function over its own area
//! (its four quarters' centres, each with its exact solid angle: the
//! midpoint rule, exact for a bilinear function up to the variation of the
//! solid angle across a quarter), and a subdivided texel's parts read the
//! function at their centres, so every part of the sphere is read the same
//! way; at roughness 0 the lobe is a delta and LD is the bilinear value at R.

#[cfg_attr(not(feature = "instruments"), allow(dead_code))]
mod monte_carlo;
#[allow(clippy::needless_range_loop)] // per-channel arrays indexed in step
#[cfg_attr(not(feature = "instruments"), allow(unreachable_pub, dead_code))]
mod oracle;

pub use monte_carlo::*;
#[cfg(feature = "instruments")]
pub use oracle::*;
#[cfg(not(feature = "instruments"))]
pub(crate) use oracle::*;

/// How far one level's `decoded` faces are from the `reference` faces they
/// were encoded from, as a bake's manifest records it for BC6H and RGBD:
/// (relative RMS √(Σ (d − r)²) / √(Σ r²), log-space RMSE √(mean (ln(1 + d) −
/// ln(1 + r))²), the worst texel's largest channel difference over its
/// largest reference channel, at least 2⁻¹⁴), every component counted, the
/// reference clamped to `[0, max]` first as the format's packing clamps it.
#[cfg(all(feature = "instruments", any(feature = "bc6h", feature = "babylon")))]
#[must_use]
pub fn lossy_level_error(
    decoded: &[crate::image::RgbImage],
    reference: &[crate::image::RgbImage],
    max: f32,
) -> (f64, f64, f64) {
    let e = crate::image::lossy::measure_level(decoded, reference, max);
    (e.rel_rms, e.log_rmse, e.worst)
}
