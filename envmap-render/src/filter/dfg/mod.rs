//! The DFG table of split-sum image-based lighting: the scale and bias the
//! prefiltered radiance is multiplied by, per view angle and roughness, in
//! the single-scatter form and in Filament's multiscatter form.
//!
//! # What it holds
//!
//! The split sum (Karis 2013, "Real Shading in UE4", §Image-based lighting)
//! writes the specular part of image-based lighting as
//! `LD(R) · (F0 · scale + bias)`, where `LD` is the prefiltered radiance and
//! `scale`, `bias` depend only on μ = N·V and the perceptual roughness r.
//! With N = +z, V = (√(1 − μ²), 0, μ), α = r², the GGX distribution
//! D(h) = α² / (π ((n·h)²(α² − 1) + 1)²), the height-correlated Smith
//! visibility (Heitz 2014, "Understanding the Masking-Shadowing Function in
//! Microfacet-Based BRDFs"; Filament's `Visibility`)
//!
//! ```text
//! V_HC = 0.5 / (NoL·√(NoV²(1 − α²) + α²) + NoV·√(NoL²(1 − α²) + α²))
//! ```
//!
//! and Schlick's Fc = (1 − V·H)⁵, both numbers are expectations over half
//! vectors H drawn with density D(h)·(n·h), counting only the H whose
//! reflection L = 2(V·H)H − V is above the surface
//! (NoL = 2·VoH·NoH − NoV > 0):
//!
//! ```text
//! V'    = 4 · V_HC · NoL · VoH / NoH          (Filament's DFV integrand)
//! scale = E[(1 − Fc) · V'],   bias = E[Fc · V']
//! ```
//!
//! Two forms are kept, both from the one integral:
//!
//! * **single scatter** `(scale, bias)`: `specular = LD · (F0·scale + bias)`
//!   (Karis 2013);
//! * **multiscatter** `(bias, scale + bias)`, what Filament ships
//!   (`CubemapIBL::DFG` with `DFV_Multiscatter`; "Physically Based Rendering
//!   in Filament" §5.3.4 and §9.5): sampled as `dfg`, the specular is
//!   `LD · mix(dfg.x, dfg.y, F0)`, and the energy single scattering loses is
//!   put back by the factor `1 + F0 · (1/dfg.y − 1)`.
//!
//! # Orientation
//!
//! A table of `size × size` texels holds column `i` at μ = (i + 0.5)/size
//! and row `j` at r = (j + 0.5)/size, row 0 being the **top** row of its
//! images (smooth at the top, rough at the bottom). These are texel
//! centres, as everywhere in this crate, so an image's (u, v) are exactly
//! (μ, r). Uploaded top row first (EXR files are read that way, and GL,
//! Vulkan and D3D put a texture's first row at t = 0), the table is sampled
//! at `(NoV, perceptualRoughness)` directly, as Filament's shaders sample
//! theirs. Each value is the integral at its texel's centre, not at
//! `i / (size − 1)`.
//!
//! # Grids: texel centres or edges
//!
//! Texel centres ([`DfgGrid::TexelCentres`], the default and what every
//! file holds unless asked otherwise) are what an engine that samples the
//! table at `(NoV, perceptualRoughness)` with linear filtering and
//! clamp-to-edge expects. They leave the table's edges half a texel short:
//! roughness 1 reads the last row, whose centre is at 1 − ½/size, and
//! N·V = 1 the last column. Near roughness 1 the albedo still falls steeply
//! (head-on it reaches 1 − ln 2 at r = 1 for the height-correlated
//! visibility), so a small table reads the roughest materials too bright
//! (how much: `docs/lighting.md`, and `tests/split_sum.rs`).
//!
//! [`DfgGrid::Edges`] puts the first and last rows and columns at 0 and 1
//! exactly: column `i` at μ = i/(size − 1), row `j` at r = j/(size − 1)
//! (μ = 0 and r = 0 evaluated at [`MIN_ARGUMENT`]). Read at texel centres,
//! such a table is sampled at `((size − 1)·x + ½)/size` for x = N·V and
//! x = roughness: the one-line remapping a shader needs (Unreal's and
//! Bevy's lookups of their own tables do the same). envmap's renderer
//! ([`crate::scene`]) builds its table on this grid; `envmap bake
//! --dfg-grid edges` writes one, and the manifest says which grid a table
//! is on, so a file on the default grid still reads as engines expect.
//!
//! Written as a half-float EXR, as engines load it:
//!
//! ```no_run
//! use envmap_render::filter::dfg::{DfgTable, DEFAULT_SIZE};
//! use envmap_render::image::{write_rgb, ExrPrecision, SaveOptions};
//!
//! let table = DfgTable::new(DEFAULT_SIZE)?;
//! let mut half = SaveOptions::default();
//! half.exr_precision = ExrPrecision::F16;
//! // R = bias, G = scale + bias (Filament's); or single_scatter_image():
//! // R = scale, G = bias. Column i: μ = (i + 0.5)/128; row j (top first):
//! // r = (j + 0.5)/128.
//! write_rgb(&table.multiscatter_image(), "dfg.exr", &half)?;
//! # Ok::<(), envmap_render::Error>(())
//! ```
//!
//! # How it is computed
//!
//! The expectation is not sampled: it is written as an exact integral and
//! evaluated in f64 by Gauss–Legendre quadrature on panels where the
//! integrand is smooth, so it converges fast and without noise.
//!
//! Put h at polar angle θ and azimuth φ. Substituting the GGX CDF makes the
//! density uniform: with ξ = F(θ), tan²θ = α²ξ/(1 − ξ), and
//! `E[g] = ∫₀¹ dξ (1/π) ∫₀^π g dφ` (the integrand is even in φ because V
//! lies in the xz-plane). The outer variable is τ = ln tan θ, because in τ
//! `dξ = 2t²α²/(α² + t²)² dτ` (t = tan θ) is a logistic bump of width about
//! 1 centred at ln α: every feature of the integrand has a width of order
//! 1, whatever μ and α are. The horizon has a closed form in τ,
//! `NoL = √(1 − μ²)·(cos φ − sinh τ / k) / cosh τ` with k = √(1 − μ²)/μ,
//! which splits the τ axis at τ₁ = −asinh k and τ₂ = asinh k: below τ₁
//! every φ counts (the *full* region), between them φ runs over [0, φₘ]
//! with φₘ = acos(sinh τ / k) (the *partial* region), above τ₂ none does.
//!
//! The rule on each region (`dfg_integral` evaluates it at one point)
//! puts its panels where the integrand's singularities are; a texel's nodes
//! are evaluated four at a time, and the result does not depend on the
//! number of threads.
//!
//! # Accuracy
//!
//! Every texel of the 128² table is within 10⁻⁴ of the same rule run with
//! four times the points on every panel (a test holds it). Tests also check
//! the rule against the closed forms at α → 0 and α = 1, against adaptive
//! quadrature over the hemispheres of L and of H, and against a commonly
//! quoted 4-decimal table of Filament's DFG; where that table differs from
//! the integral in its 4th decimal, the difference is the sampling error
//! of the Hammersley estimator it was made with. Stored as f16
//! ([`ExrPrecision::F16`](crate::image::io::ExrPrecision::F16),
//! `DfgTable::multiscatter_f16_bits`) the values are rounded to a
//! relative 2⁻¹¹. The measured errors are in `docs/lighting.md`; the
//! criterion bench `dfg` in `envmap-bench` times the table.
//!
//! # Sizes and arguments
//!
//! Sizes 1 to [`MAX_SIZE`] (4096) are accepted. Size 0 and larger sizes are
//! errors. `dfg_integral` clamps μ and r into [[`MIN_ARGUMENT`], 1] (2⁻¹⁴,
//! below every texel centre of the largest table) and gives NaN for a NaN
//! argument. The bilinear lookups clamp to the table's outermost texels
//! (on [`DfgGrid::Edges`], 0 and 1). An edges table needs at least 2 × 2
//! texels.

use crate::error::{Error, Result};

// The quadrature of the integral at one point.
mod integral;
// The table of integrals and its lookups.
mod table;

// `dfg_integral` is public only with the `instruments` feature.
#[cfg(feature = "instruments")]
pub use integral::*;
#[cfg(not(feature = "instruments"))]
pub(crate) use integral::*;
pub use table::*;

/// The table size engines use by default (Filament's `cmgen` bakes 128²).
pub const DEFAULT_SIZE: u32 = 128;

/// The largest table size accepted (4096², 16.7 million texels).
pub const MAX_SIZE: u32 = 4096;

/// The smallest μ and r that `dfg_integral` evaluates at (2⁻¹⁴). Smaller
/// arguments are clamped to it. Every texel centre of a table up to
/// [`MAX_SIZE`] is above it.
pub const MIN_ARGUMENT: f64 = 1.0 / 16384.0;

/// Where a [`DfgTable`]'s texels sit in (N·V, roughness); see the
/// [module docs](self#grids-texel-centres-or-edges).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum DfgGrid {
    /// Texel `i` of `size` at (i + ½)/size: a texture sampled at (N·V,
    /// roughness) with linear filtering reads the integral at its texel
    /// centres (Filament's and glTF viewers' lookup). The default, and what
    /// files hold unless asked otherwise.
    #[default]
    TexelCentres,
    /// Texel `i` of `size` at i/(size − 1): the first and last rows and
    /// columns at 0 and 1, so N·V and roughness of 0 and 1 read exactly. A
    /// shader samples such a texture at ((size − 1)·x + ½)/size.
    Edges,
}

impl DfgGrid {
    /// The name `--dfg-grid` takes and the manifest records:
    /// `texel-centres` or `edges`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            DfgGrid::TexelCentres => "texel-centres",
            DfgGrid::Edges => "edges",
        }
    }

    /// Texel `index`'s argument in a table of `size`, f64.
    #[cfg_attr(feature = "instruments", visibility::make(pub))]
    #[inline]
    #[must_use]
    pub(crate) fn point(self, index: u32, size: u32) -> f64 {
        match self {
            DfgGrid::TexelCentres => (f64::from(index) + 0.5) / f64::from(size),
            DfgGrid::Edges => f64::from(index) / f64::from(size.max(2) - 1),
        }
    }

    /// What texel coordinate argument `x` (N·V or roughness) falls on in a
    /// table of `size`: the continuous index that [`DfgGrid::point`]
    /// inverts, before clamping.
    #[inline]
    fn index_of(self, x: f32, size: u32) -> f32 {
        match self {
            DfgGrid::TexelCentres => x * size as f32 - 0.5,
            DfgGrid::Edges => x * (size.max(2) - 1) as f32,
        }
    }
}

impl std::str::FromStr for DfgGrid {
    type Err = Error;

    fn from_str(s: &str) -> Result<Self> {
        match s.to_ascii_lowercase().as_str() {
            "texel-centres" | "texel-centers" | "centres" | "centers" => Ok(DfgGrid::TexelCentres),
            "edges" => Ok(DfgGrid::Edges),
            _ => Err(Error::UnknownName {
                what: "DFG grid",
                name: s.to_owned(),
                expected: "texel-centres, edges".to_owned(),
            }),
        }
    }
}

/// Size 0 and sizes above [`MAX_SIZE`] are errors.
fn check_size(size: u32) -> Result<()> {
    if size == 0 {
        return Err(Error::layout(
            "DFG table size 0: a table needs at least 1×1 texels",
        ));
    }
    if size > MAX_SIZE {
        let s = u64::from(size);
        return Err(Error::TooLarge {
            width: s,
            height: s,
            texels: s * s,
            limit: u64::from(MAX_SIZE) * u64::from(MAX_SIZE),
        });
    }
    Ok(())
}
