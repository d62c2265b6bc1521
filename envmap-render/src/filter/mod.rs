//! Filtering: sampling an environment map with each representation's edge
//! rule, and the one conversion loop between any two representations.
//!
//! * `sample`: nearest and bilinear sampling at chart points, one at a time
//!   or eight at a time (`sample::Sampler`).
//! * [`convert()`]: any representation to any other, one generic loop
//!   ([Conversion](#conversion)).
//!
//! * `weights`: the exact solid angle of every texel (`weights::TexelWeights`).
//! * `pyramid`: mip pyramids weighted by solid angle, and trilinear
//!   sampling at a fractional level (`pyramid::Pyramid`,
//!   `pyramid::Trilinear`).
//! * `brdf`: the microfacet BRDF's formulas (GGX D, Smith visibility,
//!   Schlick's Fresnel, the lobe's width), each defined once.
//! * [`dfg`]: the split-sum DFG table, single and multiscatter
//!   ([`dfg::DfgTable`], `dfg::dfg_integral`).
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
//!
//! # Conversion
//!
//! Conversion between any two representations: one generic loop.
//!
//! For each output texel inside a chart: its centre, or N×N stratified
//! sub-sample points, are inverse-mapped to directions (envmap-simd, eight at
//! a time), carried from the output's axes through the world (z up) into the
//! input's axes (with an optional rotation on the way; see
//! [`Representation::frame`](crate::image::Representation::frame)), forward-mapped into the input's charts and
//! filtered there (`Sampler`); only the ray matters, so the output's
//! [`Mapping8::inverse8_ray`](envmap_simd::Mapping8::inverse8_ray) feeds the input's [`Mapping8::forward8_ray`](envmap_simd::Mapping8::forward8_ray).
//! Texels outside every chart (cross corners, the corners around a disk) are
//! black. Bands of up to 128 rows run in parallel (rayon), each walked in
//! tiles of 32 columns; within a band, batches are mapped two at a time and
//! addressed 32 ahead of filtering while their texels load (see the
//! `crate::filter::sample` module). With one sample per
//! texel, samples go straight into the output; N×N sub-samples, and every
//! sample on a disk chart, go into a scratch tile and are averaged (on a disk,
//! over the sub-samples inside it).

pub mod bake;
pub(crate) mod brdf;
pub(crate) mod bright_tree;
pub(crate) mod conversion;
pub mod dfg;
#[cfg(feature = "instruments")]
pub mod pyramid;
#[cfg(not(feature = "instruments"))]
#[allow(unreachable_pub, dead_code)]
pub(crate) mod pyramid;
pub(crate) mod quadrature;
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

pub use conversion::*;
pub use sample::Filter;
