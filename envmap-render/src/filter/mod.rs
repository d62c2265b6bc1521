//! Filtering: sampling an environment map with each representation's edge
//! rule, and the one conversion loop between any two representations.
//!
//! * `sample`: nearest and bilinear sampling at chart points, one at a time
//!   or eight at a time (`sample::Sampler`).
//! * [`convert`]: any representation to any other, one generic loop
//!   ([`convert::convert`]).
//!
//! * `weights`: the exact solid angle of every texel (`weights::TexelWeights`).
//! * [`pyramid`]: mip pyramids weighted by solid angle, and trilinear
//!   sampling at a fractional level ([`pyramid::Pyramid`],
//!   [`pyramid::Trilinear`]).
//! * [`dfg`]: the split-sum DFG table, single and multiscatter
//!   ([`dfg::DfgTable`], [`dfg::dfg_integral`]).
//! * `oracle`: the bake's integrals from the input itself, piecewise
//!   constant over its own texels, by adaptive quadrature (`oracle::Oracle`).
//! * [`bake`]: the lighting bake's pipeline (chain, levels, reports).
//! * `bright_tree`: the split texels summed hierarchically per eight
//!   directions (Barnes–Hut), near the lobe point by point.
//! * [`specular`]: GGX-prefiltered levels, exact or importance-sampled, the
//!   brightest texels added by a tree, and the mip↔roughness rules.
//! * [`sh`]: irradiance: SH9 projection, irradiance coefficients (E, or E/π
//!   in Filament's shader form), deringing, irradiance maps from the SH or
//!   by exact cosine convolution.
//!
//! This folder uses `envmap-core`, `envmap-simd` and [`crate::image`];
//! nothing from `scene` or `cli`.

pub mod bake;
pub(crate) mod bright_tree;
pub mod convert;
pub mod dfg;
// Its channel loops index several per-channel arrays in step.
#[allow(clippy::needless_range_loop)]
#[cfg(feature = "instruments")]
pub mod oracle;
#[allow(clippy::needless_range_loop)]
#[cfg(not(feature = "instruments"))]
#[allow(unreachable_pub, dead_code)]
pub(crate) mod oracle;
pub mod pyramid;
#[cfg(feature = "instruments")]
pub mod sample;
#[cfg(not(feature = "instruments"))]
#[allow(unreachable_pub, dead_code)]
pub(crate) mod sample;
pub mod sh;
pub mod specular;
#[cfg(feature = "instruments")]
pub mod weights;
#[cfg(not(feature = "instruments"))]
#[allow(unreachable_pub, dead_code)]
pub(crate) mod weights;

pub use sample::Filter;
