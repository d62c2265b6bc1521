//! GGX-prefiltered specular levels: the split sum's first factor, exact or
//! importance-sampled, with the brightest texels (a sun) summed by a tree over their parts (`crate::filter::bright_tree`).
//!
//! # The integral
//!
//! For each output direction R, with N = V = R as the split sum takes them
//! (Karis 2013, "Real Shading in Unreal Engine 4", §image-based lighting;
//! Filament's `CubemapIBL::roughnessFilter`):
//!
//! ```text
//! LD(R) = ∫ L(l) D(h) (n·l)⁺ dl / ∫ D(h) (n·l)⁺ dl,   h = normalize(l + R)
//! D(h) = α² / (π ((n·h)²(α² − 1) + 1)²)               (GGX, Walter et al. 2007), α = roughness²
//! ```
//!
//! With N = V the weight depends on c = R·l alone: (n·h)² = (1 + c)/2 and
//! (n·l) = c, so w(c) = D((1 + c)/2)·c for c > 0 and 0 behind.
//!
//! # Exact
//!
//! [`Method::Exact`] sums the integral by brute force over every texel of a
//! pyramid level, each texel l_j with its exact solid angle Ω_j
//! (`TexelWeights`): LD(R) = Σ w(R·l_j) Ω_j L_j / Σ w(R·l_j) Ω_j. The level
//! is the coarsest whose texels are at most an eighth of the lobe's width
//! (`lobe_width`), or the base.
//!
//! # Importance-sampled
//!
//! [`Method::Sampled`] draws N half vectors from the GGX distribution of
//! n·h (Hammersley points, Karis's cos²θh = (1 − ξ)/(1 + (α² − 1)ξ)),
//! turned about R by an angle hashed from the output texel, so neighbouring
//! texels use different samples (the same at any thread count), and takes
//! LD = Σ (n·l) L(l) / Σ (n·l) over the samples with n·l > 0. Each sample
//! reads the pyramid at the level its density asks for (filtered importance
//! sampling, Křivánek & Colbert 2008, as Filament's cmgen does):
//! lod = ½·log2(Ωs/Ωp) + bias, with Ωs = 4 / (N·D) the solid angle one
//! sample stands for (pdf = D/4 when N = V) and Ωp = 4π / (6·s²) a base
//! texel's for a cube of face s.
//!
//! # The brightest texels
//!
//! A sun or a lamp a thousand times brighter than the sky turns importance
//! samples into noise and bias. `split_bright` takes out of the base every
//! texel brighter than a threshold (see there), and each level adds their
//! contribution exactly: Σ_b w(R·l_b) Ω_b L_b / Z, where Z = ∫ D(h)(n·l)⁺ dl
//! (`lobe_normalizer`, by quadrature in f64) for a sampled level, and
//! the exact sum's own Σ w Ω for an exact one. The rest is filtered as
//! above. The integral is linear in L, so nothing is lost: only the
//! sampled part has the sampling's error.

use std::sync::atomic::AtomicBool;

use crate::par::*;
use envmap_core::glam::Vec3;
use envmap_core::texel::texel_center;
use envmap_core::{AnyMapping, ChartUv, Mapping};
use envmap_simd::{Dir8, Fine, Mapping8, Uv8, LANES};
use wide::{f32x4, f32x8, u32x8};

use crate::cancel;
// GGX D stays reachable here, where the instruments and tests read it.
use crate::error::{Error, Result};
#[cfg(feature = "instruments")]
pub use crate::filter::brdf::ggx_d;
#[cfg(not(feature = "instruments"))]
pub(crate) use crate::filter::brdf::ggx_d;
use crate::filter::brdf::lobe_width;
use crate::filter::bright_tree::BrightTree;
use crate::filter::pyramid::{Pyramid, Trilinear};
use crate::filter::quadrature::Gauss;
use crate::filter::weights::TexelWeights;
use crate::image::{EnvImage, Representation, RgbImage};

mod bright;
pub use bright::*;

/// How roughness follows mip level in an engine's shader.
#[derive(Clone, Debug, PartialEq)]
pub enum RoughnessRule {
    /// roughness = k/(n − 1): glTF-IBL-Sampler, Bevy (`radiance_level =
    /// perceptual_roughness · (mip_count − 1)`). The default.
    Linear,
    /// lod = r(2 − r)·(n − 1): Filament (`perceptualRoughnessToLod`), with
    /// cmgen's 16² smallest level.
    Filament,
    /// lod = r(1.7 − 0.7r)·(n − 1): Unity (`ImageBasedLighting.hlsl`).
    Unity,
    /// Babylon.js (`HDRFiltering`, and its PBR shader's
    /// `getLodFromAlphaG`): lod = 0.8·log2(size·α) on a chain down to 1×1,
    /// so level k ≥ 1 holds α = 2^(k/0.8)/size and level 0 is unfiltered
    /// (α = 0). The levels past α = 1 (Babylon.js's filter goes on to α
    /// of 2 and more there) are made at roughness 1.
    Babylon,
    /// lod = log2(size·α) on a chain down to 1×1: level k ≥ 1 holds α =
    /// 2^k/size (the 1×1 level α = 1), level 0 unfiltered. How Babylon.js's
    /// glTF loader reads an `EXT_lights_image_based` light of a full chain
    /// (lodGenerationScale = (levels − 1)/log2 size = 1).
    Log2,
    /// One perceptual roughness per level, level 0 first.
    Custom(Vec<f32>),
}

impl RoughnessRule {
    /// The name on the command line.
    #[must_use]
    pub fn name(&self) -> &'static str {
        match self {
            RoughnessRule::Linear => "linear",
            RoughnessRule::Filament => "filament",
            RoughnessRule::Unity => "unity",
            RoughnessRule::Babylon => "babylon",
            RoughnessRule::Log2 => "log2",
            RoughnessRule::Custom(_) => "custom",
        }
    }

    /// The rule's formula, for manifests.
    #[must_use]
    pub fn formula(&self) -> &'static str {
        match self {
            RoughnessRule::Linear => "roughness = level / (levels - 1)",
            RoughnessRule::Filament => {
                "lod = r(2 - r)(levels - 1), r = 1 - sqrt(1 - level/(levels - 1))"
            }
            RoughnessRule::Unity => "lod = r(1.7 - 0.7r)(levels - 1)",
            RoughnessRule::Babylon => {
                "alpha = r^2 = 2^(level/0.8)/size (at most 1), level 0 unfiltered: lod = 0.8 log2(size alpha)"
            }
            RoughnessRule::Log2 => {
                "alpha = r^2 = 2^level/size, level 0 unfiltered: lod = log2(size alpha)"
            }
            RoughnessRule::Custom(_) => "roughness per level as given",
        }
    }

    /// The smallest level's chart size the rule expects by default: 16 for
    /// Filament (cmgen's `--ibl-min-lod-size`), 8 for Unity (its 6 LOD
    /// steps at 512), 1 for Babylon.js (its `.env` files hold every level),
    /// 2 otherwise (glTF-IBL-Sampler's ⌊log2 size⌋ levels).
    #[must_use]
    pub(crate) fn default_min_size(&self) -> u32 {
        match self {
            RoughnessRule::Filament => 16,
            RoughnessRule::Unity => 8,
            RoughnessRule::Babylon | RoughnessRule::Log2 => 1,
            _ => 2,
        }
    }

    /// The perceptual roughness of `level` of `levels`.
    #[must_use]
    pub fn roughness(&self, level: usize, levels: usize) -> f32 {
        if levels <= 1 {
            return 0.0;
        }
        let t = (level as f64 / (levels - 1) as f64).clamp(0.0, 1.0);
        if let RoughnessRule::Babylon | RoughnessRule::Log2 = self {
            // size = 2^(levels − 1): the chain goes down to 1×1.
            if level == 0 {
                return 0.0;
            }
            let scale = if *self == RoughnessRule::Babylon {
                0.8
            } else {
                1.0
            };
            let alpha = (level as f64 / scale - (levels - 1) as f64).exp2();
            return alpha.min(1.0).sqrt() as f32;
        }
        let r = match self {
            RoughnessRule::Linear => t,
            RoughnessRule::Filament => 1.0 - (1.0 - t).sqrt(),
            RoughnessRule::Unity => (1.7 - (2.89 - 2.8 * t).max(0.0).sqrt()) / 1.4,
            RoughnessRule::Babylon | RoughnessRule::Log2 => 0.0,
            RoughnessRule::Custom(v) => {
                return v.get(level).copied().unwrap_or(1.0).clamp(0.0, 1.0);
            }
        };
        r as f32
    }
}

impl std::str::FromStr for RoughnessRule {
    type Err = Error;

    /// `linear`, `filament`, `unity`, `babylon`, `log2`, or comma-separated roughness values
    /// (`0,0.2,0.5,1`).
    fn from_str(s: &str) -> Result<Self> {
        match s.to_ascii_lowercase().as_str() {
            "linear" | "gltf" | "bevy" => return Ok(RoughnessRule::Linear),
            "filament" | "cmgen" => return Ok(RoughnessRule::Filament),
            "unity" => return Ok(RoughnessRule::Unity),
            "babylon" => return Ok(RoughnessRule::Babylon),
            "log2" | "gltf-ibl" => return Ok(RoughnessRule::Log2),
            _ => {}
        }
        let v: std::result::Result<Vec<f32>, _> =
            s.split(',').map(|t| t.trim().parse::<f32>()).collect();
        match v {
            Ok(v) if !v.is_empty() && v.iter().all(|r| (0.0..=1.0).contains(r)) => {
                Ok(RoughnessRule::Custom(v))
            }
            _ => Err(Error::UnknownName {
                what: "roughness rule",
                name: s.to_owned(),
                expected:
                    "linear, filament, unity, babylon, log2, or roughness values in [0, 1] such as 0,0.25,0.5,1"
                        .to_owned(),
            }),
        }
    }
}

/// Z(α) = ∫ D(h)(n·l)⁺ dl with N = V: the integral over half vectors
/// θh ∈ [0, π/4] (where n·l = cos 2θh > 0) of D(θh)·cos 2θh·4 cos θh ·
/// 2π sin θh dθh (dl = 4 (v·h) dh), by 8-point Gauss–Legendre (`Gauss`) on 64 panels
/// graded towards the peak, in f64 (within 1e-7 relative of a million-step
/// midpoint sum from α = 0.01 to 1).
#[cfg_attr(feature = "instruments", visibility::make(pub))]
#[must_use]
pub(crate) fn lobe_normalizer(alpha: f64) -> f64 {
    let rule = Gauss::new(8);
    // In t = cos θh ∈ [1/√2, 1]: dω_h = 2π dt, the integrand D(t²)(2t² − 1)4t.
    // Panels crowd towards t = 1, where a narrow lobe lives: t = 1 − s² over
    // s, with panel edges at s_max·(p/P)².
    let s_max = (1.0 - std::f64::consts::FRAC_1_SQRT_2).sqrt();
    let panels = 64;
    let edge = |p: i32| s_max * (f64::from(p) / f64::from(panels)).powi(2);
    let mut z = 0.0;
    for p in 0..panels {
        let (a, b) = (edge(p), edge(p + 1));
        for (x, w) in rule.iter() {
            let s = a + (b - a) * x;
            let t = 1.0 - s * s;
            let f =
                ggx_d(t * t, alpha) * (2.0 * t * t - 1.0) * 4.0 * t * 2.0 * std::f64::consts::PI;
            z += w * (b - a) * f * 2.0 * s; // dt = 2s ds
        }
    }
    z
}

/// The GGX weight w(c) = D((1 + c)/2)·c of a source direction l for eight
/// output directions R (lanes), c = R·l (0 where c ≤ 0). D's denominator
/// (n·h)²(α² − 1) + 1 is computed as |R − l|²/4 + (n·h)²α², two positive
/// terms (|R − l|² = 2(1 − c) for unit vectors), so a narrow lobe keeps its
/// f32 precision where 1 − (n·h)² would cancel.
#[inline(always)]
pub(crate) fn weight8(r: &Dir8, l: Vec3, a2: f32) -> f32x8 {
    let (dx, dy, dz) = (
        r.x - f32x8::splat(l.x),
        r.y - f32x8::splat(l.y),
        r.z - f32x8::splat(l.z),
    );
    let dist2 = dx * dx + dy * dy + dz * dz;
    let c = f32x8::ONE - dist2 * f32x8::splat(0.5);
    let front = c.simd_gt(f32x8::ZERO);
    let noh2 = (f32x8::ONE + c) * f32x8::splat(0.5);
    let d = dist2 * f32x8::splat(0.25) + noh2 * f32x8::splat(a2);
    let w = c * f32x8::splat(a2 / std::f32::consts::PI) / (d * d);
    front.select(w, f32x8::ZERO)
}

/// How a level is filtered.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// The exact sum over every texel of pyramid level `level`.
    Exact {
        /// The pyramid level summed over.
        level: usize,
    },
    /// Importance-sampled with this many samples per texel.
    Sampled {
        /// Samples per output texel.
        samples: u32,
    },
}

/// The angle a texel of `img` spans across at its chart's centre
/// (radians): a cube or EAC face's π/2 over its width, else the full turn
/// over the atlas's width (a latlong's row).
#[must_use]
pub(crate) fn texel_pitch(img: &EnvImage) -> f64 {
    let (cw, _) = img.cell_size();
    match img.mapping() {
        AnyMapping::Cube | AnyMapping::Eac => std::f64::consts::FRAC_PI_2 / f64::from(cw.max(1)),
        _ => std::f64::consts::TAU / f64::from((cw * img.atlas().cols).max(1)),
    }
}

/// The pyramid level an exact sum at roughness `r` uses: the coarsest whose
/// texels are at most an eighth of `lobe_width` across (a cube face of s
/// texels: π/2 / s), or level 0.
#[cfg_attr(feature = "instruments", visibility::make(pub))]
#[must_use]
pub(crate) fn exact_level(p: &Pyramid, roughness: f32) -> usize {
    let alpha = f64::from(roughness) * f64::from(roughness);
    let want = lobe_width(alpha) / 8.0;
    let mut best = 0;
    for (k, l) in p.levels().iter().enumerate() {
        if texel_pitch(l) <= want {
            best = k;
        }
    }
    best
}

/// Per-sample values shared by every output texel of a sampled level.
#[derive(Clone, Copy, Debug)]
struct Sample {
    cos_h: f32,
    sin_h: f32,
    cos_phi: f32,
    sin_phi: f32,
    /// n·l = 2 cos²θh − 1 > 0.
    nol: f32,
    lod: f32,
}

/// Van der Corput's radical inverse of `i` in base 2.
fn radical_inverse(i: u32) -> f64 {
    f64::from(i.reverse_bits()) / 4_294_967_296.0
}

/// The samples of a level: Hammersley points through GGX, those with
/// n·l > 0, with their FIS levels.
fn samples_plan(alpha: f32, n: u32, omega_p: f64, lod_bias: f32) -> Vec<Sample> {
    let a2 = f64::from(alpha) * f64::from(alpha);
    (0..n)
        .filter_map(|k| {
            let xi = (f64::from(k) + 0.5) / f64::from(n);
            let phi = std::f64::consts::TAU * radical_inverse(k);
            let cos2 = (1.0 - xi) / (1.0 + (a2 - 1.0) * xi);
            let nol = 2.0 * cos2 - 1.0;
            if nol <= 0.0 {
                return None;
            }
            let d = ggx_d(cos2, f64::from(alpha));
            let omega_s = 4.0 / (f64::from(n) * d);
            let lod = 0.5 * (omega_s / omega_p).log2() + f64::from(lod_bias);
            Some(Sample {
                cos_h: cos2.sqrt() as f32,
                sin_h: (1.0 - cos2).max(0.0).sqrt() as f32,
                cos_phi: phi.cos() as f32,
                sin_phi: phi.sin() as f32,
                nol: nol as f32,
                lod: lod.max(0.0) as f32,
            })
        })
        .collect()
}

/// The mean solid angle of a texel of `img`: 4π over its texels (Ωp of
/// the FIS level).
fn mean_texel_solid_angle(img: &EnvImage) -> f64 {
    let (w, h) = img.cell_size();
    4.0 * std::f64::consts::PI
        / f64::from(img.mapping().chart_count())
        / f64::from(w)
        / f64::from(h)
}

/// The finest pyramid level a sampled level at `roughness` with `samples`
/// samples reads (the FIS level of its densest sample, rounded down): the
/// levels finer than that need no preparing ([`Trilinear::starting_at`]).
#[must_use]
pub(crate) fn finest_sampled_level(
    rest: &Pyramid,
    roughness: f32,
    samples: u32,
    lod_bias: f32,
) -> usize {
    let alpha = roughness * roughness;
    let omega_p = mean_texel_solid_angle(rest.level(0));
    samples_plan(alpha, samples.max(1), omega_p, lod_bias)
        .iter()
        .map(|s| s.lod)
        .fold(f32::INFINITY, f32::min)
        .max(0.0)
        .min(rest.len().saturating_sub(1) as f32) as usize
}

/// A 32-bit hash of a texel's place (chart, column, row, level), for its
/// sample rotation: the same at any thread count.
#[inline]
fn texel_hash(chart: u32, i: u32, j: u32, level: u32) -> u32 {
    let mut h = chart.wrapping_mul(0x9e37_79b1)
        ^ i.wrapping_mul(0x85eb_ca77)
        ^ j.wrapping_mul(0xc2b2_ae3d)
        ^ level.wrapping_mul(0x27d4_eb2f);
    h ^= h >> 15;
    h = h.wrapping_mul(0x2c1b_3c6d);
    h ^= h >> 12;
    h = h.wrapping_mul(0x297a_2d39);
    h ^ (h >> 15)
}

/// A source level's texels as arrays for the exact sum: directions (the
/// map's axes), Ω and Ω·L.
struct Texels {
    x: Vec<f32>,
    y: Vec<f32>,
    z: Vec<f32>,
    omega: Vec<f32>,
    ol: [Vec<f32>; 3],
}

fn texels_of(img: &EnvImage) -> Texels {
    let mapping = img.mapping();
    let (cw, ch) = img.cell_size();
    let weights = TexelWeights::new(mapping, cw, ch);
    let mut t = Texels {
        x: Vec::new(),
        y: Vec::new(),
        z: Vec::new(),
        omega: Vec::new(),
        ol: [Vec::new(), Vec::new(), Vec::new()],
    };
    for chart in 0..mapping.chart_count() {
        let Some(face) = img.chart_image(chart) else {
            continue;
        };
        for j in 0..ch {
            for i in 0..cw {
                let o = weights.get(chart, i, j);
                let c = ChartUv::new(chart, texel_center(i, cw), texel_center(j, ch));
                let Some(d) = mapping.inverse(c).filter(|_| o > 0.0) else {
                    continue;
                };
                let p = face.pixels[(j * cw + i) as usize];
                t.x.push(d.x);
                t.y.push(d.y);
                t.z.push(d.z);
                t.omega.push(o as f32);
                for (ol, v) in t.ol.iter_mut().zip(p) {
                    ol.push((o * f64::from(v)) as f32);
                }
            }
        }
    }
    t
}

/// Σ w Ω L and Σ w Ω over `t` for eight directions R (lanes), accumulated
/// in f32 per block of 256 texels and in f64 across blocks.
fn exact_sums(t: &Texels, r: &Dir8, a2: f32) -> ([[f64; 3]; 8], [f64; 8]) {
    let mut acc = [[0.0f64; 3]; 8];
    let mut wsum = [0.0f64; 8];
    for start in (0..t.x.len()).step_by(256) {
        let end = (start + 256).min(t.x.len());
        let (mut sw, mut s0, mut s1, mut s2) = (f32x8::ZERO, f32x8::ZERO, f32x8::ZERO, f32x8::ZERO);
        for k in start..end {
            let w = weight8(r, Vec3::new(t.x[k], t.y[k], t.z[k]), a2);
            sw += w * f32x8::splat(t.omega[k]);
            s0 += w * f32x8::splat(t.ol[0][k]);
            s1 += w * f32x8::splat(t.ol[1][k]);
            s2 += w * f32x8::splat(t.ol[2][k]);
        }
        let (sw, s0, s1, s2) = (sw.to_array(), s0.to_array(), s1.to_array(), s2.to_array());
        for l in 0..8 {
            wsum[l] += f64::from(sw[l]);
            acc[l][0] += f64::from(s0[l]);
            acc[l][1] += f64::from(s1[l]);
            acc[l][2] += f64::from(s2[l]);
        }
    }
    (acc, wsum)
}

/// What a level needs besides its output: the filtered part's pyramid
/// (and its trilinear sampler), the bright texels, the roughness, the
/// method.
#[cfg_attr(feature = "instruments", visibility::make(pub))]
#[derive(Clone, Copy, Debug)]
pub(crate) struct LevelJob<'a> {
    /// The source without its bright texels, and its levels.
    pub rest: &'a Pyramid,
    /// Trilinear sampling of `rest` ([`Trilinear::new`]), made once for
    /// every level.
    pub sampler: &'a Trilinear<'a>,
    /// The bright texels, in the source's axes.
    pub bright: &'a Bright,
    /// Perceptual roughness (α = roughness²).
    pub roughness: f32,
    /// Exact or sampled.
    pub method: Method,
    /// Added to each sample's FIS level (see the [module docs](self)).
    pub lod_bias: f32,
    /// The level's index, for the sample rotation hash.
    pub level: u32,
    /// Stops the level once set ([`Error::Cancelled`]).
    pub cancel: Option<&'a AtomicBool>,
}

/// One prefiltered level in representation `repr` at `w × h` (whose frame
/// places it in the world; the source's frame places the source).
///
/// # Errors
///
/// The size does not fit `repr`; [`Error::Cancelled`].
#[cfg_attr(feature = "instruments", visibility::make(pub))]
pub(crate) fn prefilter_level(
    job: &LevelJob<'_>,
    repr: Representation,
    w: u32,
    h: u32,
) -> Result<EnvImage> {
    let mut out = EnvImage::new(w, h, repr)?;
    let src = job.rest.level(0);
    // Output axes → world → source axes.
    let m = src.representation().frame.matrix().transpose() * repr.frame.matrix();
    let alpha = job.roughness * job.roughness;
    let a2 = alpha * alpha;
    let z = lobe_normalizer(f64::from(alpha));
    let (cw, ch) = out.cell_size();
    let mapping = repr.mapping;
    let bright = BrightTree::new(job.bright);
    let width = lobe_width(f64::from(alpha)) as f32;
    let exact_texels = match job.method {
        Method::Exact { level } => Some(texels_of(job.rest.level(level))),
        Method::Sampled { .. } => None,
    };
    let omega_p = mean_texel_solid_angle(src);
    let plan = match job.method {
        Method::Sampled { samples: n } => samples_plan(alpha, n.max(1), omega_p, job.lod_bias),
        Method::Exact { .. } => Vec::new(),
    };
    let nol_sum: f32 = plan.iter().map(|s| s.nol).sum();
    let tri = job.sampler;
    let src_mapping = src.mapping();
    for chart in 0..mapping.chart_count() {
        cancel::check(job.cancel)?;
        let rows: Vec<Vec<[f32; 3]>> = (0..ch)
            .into_par_iter()
            .map(|j| {
                if cancel::is_set(job.cancel) {
                    return Vec::new();
                }
                let v = texel_center(j, ch);
                let mut row = vec![[0.0f32; 3]; cw as usize];
                for i0 in (0..cw).step_by(LANES) {
                    let us: [f32; LANES] =
                        core::array::from_fn(|k| texel_center((i0 + k as u32).min(cw - 1), cw));
                    let q = Uv8::new(u32x8::splat(chart), f32x8::new(us), f32x8::splat(v));
                    let d = mapping.inverse8::<Fine>(q);
                    let (c0, c1, c2) = (m.x_axis, m.y_axis, m.z_axis);
                    let s = |k: f32| f32x8::splat(k);
                    let r = Dir8::new(
                        s(c0.x) * d.x + s(c1.x) * d.y + s(c2.x) * d.z,
                        s(c0.y) * d.x + s(c1.y) * d.y + s(c2.y) * d.z,
                        s(c0.z) * d.x + s(c1.z) * d.y + s(c2.z) * d.z,
                    );
                    let bright = bright.sums(&r, a2, width);
                    let vals: [[f32; 3]; 8] = match &exact_texels {
                        Some(t) => {
                            let (acc, wsum) = exact_sums(t, &r, a2);
                            core::array::from_fn(|l| {
                                if wsum[l] > 0.0 {
                                    core::array::from_fn(|c| {
                                        ((acc[l][c] + bright[l][c]) / wsum[l]) as f32
                                    })
                                } else {
                                    [0.0; 3]
                                }
                            })
                        }
                        None => {
                            let rest =
                                sampled(tri, src_mapping, &plan, &r, chart, i0, j, job.level);
                            core::array::from_fn(|l| {
                                core::array::from_fn(|c| {
                                    rest[l][c] / nol_sum + (bright[l][c] / z) as f32
                                })
                            })
                        }
                    };
                    for (k, v) in vals.iter().enumerate() {
                        if let Some(o) = row.get_mut(i0 as usize + k) {
                            *o = *v;
                        }
                    }
                }
                row
            })
            .collect();
        cancel::check(job.cancel)?;
        let face = RgbImage {
            width: cw,
            height: ch,
            pixels: rows.into_iter().flatten().collect(),
        };
        out.set_chart_image(chart, &face)?;
    }
    Ok(out)
}

/// Σ n·l·L over the samples for eight directions R (lanes), the samples
/// turned about each R by its texel's hashed angle.
#[allow(clippy::too_many_arguments)]
fn sampled(
    tri: &Trilinear<'_>,
    src: AnyMapping,
    plan: &[Sample],
    r: &Dir8,
    chart: u32,
    i0: u32,
    j: u32,
    level: u32,
) -> [[f32; 3]; 8] {
    // Each lane's rotation about R, and its tangent frame (Duff et al.
    // 2017, "Building an Orthonormal Basis, Revisited").
    let rot: [f32; 8] = core::array::from_fn(|k| {
        texel_hash(chart, i0 + k as u32, j, level) as f32
            * (std::f32::consts::TAU / 4_294_967_296.0)
    });
    let (sr, cr) = (f32x8::new(rot.map(f32::sin)), f32x8::new(rot.map(f32::cos)));
    let sign = f32x8::ONE.copysign(r.z);
    let a = -f32x8::ONE / (sign + r.z);
    let b = r.x * r.y * a;
    let t = (f32x8::ONE + sign * r.x * r.x * a, sign * b, -sign * r.x);
    let bt = (b, sign + r.y * r.y * a, -r.y);
    let mut acc = [f32x4::ZERO; 8];
    for s in plan {
        // cos(φ + ρ), sin(φ + ρ) per lane.
        let (cp, sp) = (f32x8::splat(s.cos_phi), f32x8::splat(s.sin_phi));
        let c = cp * cr - sp * sr;
        let sn = sp * cr + cp * sr;
        let sh = f32x8::splat(s.sin_h);
        let chh = f32x8::splat(s.cos_h);
        let hx = sh * (c * t.0 + sn * bt.0) + chh * r.x;
        let hy = sh * (c * t.1 + sn * bt.1) + chh * r.y;
        let hz = sh * (c * t.2 + sn * bt.2) + chh * r.z;
        let two_c = chh + chh;
        let l = Dir8::new(two_c * hx - r.x, two_c * hy - r.y, two_c * hz - r.z);
        let q = src.forward8_ray::<Fine>(l);
        let v = tri.sample8_at(&q, s.lod);
        let nol = f32x4::splat(s.nol);
        for k in 0..8 {
            acc[k] = v[k].mul_add(nol, acc[k]);
        }
    }
    acc.map(|a| {
        let [r, g, b, _] = a.to_array();
        [r, g, b]
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rules_give_their_roughness() {
        let n = 5;
        let lin: Vec<f32> = (0..n)
            .map(|k| RoughnessRule::Linear.roughness(k, n))
            .collect();
        assert_eq!(lin, [0.0, 0.25, 0.5, 0.75, 1.0]);
        // Filament at 5 levels: r = 0, 0.134, 0.293, 0.5, 1 (lod = r(2 − r)·4 inverted).
        let f: Vec<f32> = (0..n)
            .map(|k| RoughnessRule::Filament.roughness(k, n))
            .collect();
        for (a, b) in f.iter().zip([0.0, 0.134, 0.293, 0.5, 1.0]) {
            assert!((a - b).abs() < 1e-3, "{f:?}");
        }
        // Unity: lod/max = r(1.7 − 0.7r); r = 0.5 gives 0.675.
        let r = RoughnessRule::Unity.roughness(27, 41); // t = 0.675
        assert!((r - 0.5).abs() < 1e-6, "{r}");
        assert_eq!(RoughnessRule::Unity.roughness(4, 5), 1.0);
        let c: RoughnessRule = "0, 0.3,1".parse().unwrap();
        assert_eq!(c.roughness(1, 3), 0.3);
        assert!("steep".parse::<RoughnessRule>().is_err());
    }

    #[test]
    fn the_lobe_normalizer_matches_a_brute_force_sum() {
        // Z(α) against a plain midpoint sum over θh in f64 with a million steps.
        for alpha in [0.01, 0.1, 0.5, 1.0] {
            let n = 1_000_000;
            let th_max = std::f64::consts::FRAC_PI_4;
            let mut z = 0.0;
            for k in 0..n {
                let th = (f64::from(k) + 0.5) / f64::from(n) * th_max;
                let (s, c) = th.sin_cos();
                z +=
                    ggx_d(c * c, alpha) * (2.0 * c * c - 1.0) * 4.0 * c * std::f64::consts::TAU * s;
            }
            z *= th_max / f64::from(n);
            let got = lobe_normalizer(alpha);
            assert!((got - z).abs() < 1e-7 * z, "{alpha}: {got} vs {z}");
        }
    }
}
