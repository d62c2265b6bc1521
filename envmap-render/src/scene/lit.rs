// The split sum engines shade with: the baked maps a render reads
// (`LitEnvironment`), how the chain is blended between its levels, and the
// sampler that combines them per pixel (`LitSampler`).

use envmap_core::glam::{Mat3, Vec3};
use envmap_core::{reflect_view, AnyMapping, ChartUv};

use crate::error::{Error, Result};
use crate::filter::bake::{lobe_chain, ChainShape};
use crate::filter::brdf::alpha_of_lobe_width;
use crate::filter::dfg::{DfgGrid, DfgTable};
use crate::filter::pyramid::{Level, Pyramid};
use crate::filter::sample::{Filter, Sampler};
use crate::filter::sh::IrradianceScale;
use crate::filter::specular::RoughnessRule;
use crate::image::EnvImage;
use crate::scene::material::Material;
use crate::scene::near_field::NearField;

/// How the chain is read between two levels: the weight t of the rougher
/// one, from the two levels' roughness r₀ < r₁ and the pixel's r. Every
/// variant is linear in some function g of the roughness,
/// t = (g(r) − g(r₀))/(g(r₁) − g(r₀)); they differ in g.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LevelBlend {
    /// g(r) = −1/α_e with α_e = √(α² + floor²), α = r²: linear in the
    /// inverse of the lobe's width, the variable in which a level's value
    /// changes evenly. A sun (any light narrower than the lobe) reflects as
    /// the lobe's own shape, whose peak grows as 1/α² and whose width
    /// shrinks as α; blended linearly in r, two levels of very different
    /// width give a shape neither has, and the weight that comes closest to
    /// the lobe in between is linear in 1/α (least squares over the
    /// sphere, measured for GGX with N = V = R: `docs/design/lighting-method.md`).
    /// `floor` is the width of what a level at roughness 0 holds (its
    /// texels, in α units), so that level 0 blends as a lobe too. envmap's
    /// own.
    InverseWidth {
        /// The narrowest width, in α units; 0 reads a level at roughness
        /// 0 as a delta.
        floor: f32,
    },
    /// g(r) = r: linear in the roughness, as an engine's trilinear filter
    /// does with the linear rule (Bevy, glTF viewers: lod = r·(n − 1)).
    Roughness,
    /// g(r) = r(2 − r): Filament's lod (`perceptualRoughnessToLod`), as its
    /// trilinear filter blends a chain by the filament rule.
    FilamentLod,
    /// g(r) = r(1.7 − 0.7r): Unity's lod (`ImageBasedLighting.hlsl`).
    UnityLod,
    /// g(r) = log₂ r²: Babylon.js's lod, scale·log₂(size·α) (its PBR
    /// shader's `getLodFromAlphaG`), up to a constant; a level at
    /// roughness 0 is lod 0, `step` (1/scale) below the next level's g.
    BabylonLod {
        /// 1/lodGenerationScale: 1.25 for a `.env`, 1 for a glTF light
        /// of a full chain.
        step: f32,
    },
}

impl LevelBlend {
    /// How an engine that reads a chain made by `rule` blends it: linear in
    /// its lod (for a list of roughness values, linear in r).
    #[cfg_attr(not(feature = "instruments"), allow(dead_code))]
    #[cfg_attr(feature = "instruments", visibility::make(pub))]
    #[must_use]
    pub(crate) fn engine(rule: &RoughnessRule) -> Self {
        match rule {
            RoughnessRule::Filament => LevelBlend::FilamentLod,
            RoughnessRule::Unity => LevelBlend::UnityLod,
            RoughnessRule::Babylon => LevelBlend::BabylonLod { step: 1.25 },
            RoughnessRule::Log2 => LevelBlend::BabylonLod { step: 1.0 },
            _ => LevelBlend::Roughness,
        }
    }

    /// g(r) (see the type's docs).
    #[inline]
    fn key(self, r: f32) -> f32 {
        match self {
            LevelBlend::InverseWidth { floor } => {
                let a = r * r;
                -1.0 / (a * a + floor * floor).sqrt()
            }
            LevelBlend::Roughness => r,
            LevelBlend::FilamentLod => r * (2.0 - r),
            LevelBlend::UnityLod => r * (1.7 - 0.7 * r),
            LevelBlend::BabylonLod { .. } => (r * r).log2(),
        }
    }

    /// The weight of the rougher level (roughness `hi`) against the
    /// smoother (`lo`) at roughness `r` between them, in [0, 1].
    #[inline]
    #[must_use]
    pub(crate) fn weight(self, lo: f32, hi: f32, r: f32) -> f32 {
        let (mut a, b, mut x) = (self.key(lo), self.key(hi), self.key(r));
        if let (LevelBlend::BabylonLod { step }, 0.0) = (self, lo) {
            // Level 0 is lod 0, one level step (1/scale in log₂ α) below
            // level 1; Babylon.js clamps a smaller lod to it.
            a = b - step;
            x = x.max(a);
        }
        let t = if a.is_finite() {
            (x - a) / (b - a)
        } else {
            // A delta (floor 0 at roughness 0): anything wider is the lobe.
            1.0
        };
        if t.is_nan() {
            0.0
        } else {
            t.clamp(0.0, 1.0)
        }
    }
}

/// The DFG table's size in the maps `LitEnvironment::bake` makes (on the
/// edges grid), the size of the tables engines ship: on the edges grid the
/// split sum of a constant sky at roughness 1 then follows its closed form
/// over a sphere (`tests/split_sum.rs`).
pub const RENDER_DFG_SIZE: u32 = 128;

/// The maps a split-sum render reads; see the [module docs](super).
///
/// Besides the maps it keeps a bordered copy of every level but the first
/// and of the irradiance map (one texel more on each side of each chart),
/// made once here so that renders read them without an edge case: about
/// the memory of the chain below its first level and the irradiance map
/// once more (a third of the first level's, for a chain that halves).
#[derive(Clone, Debug)]
pub struct LitEnvironment {
    /// The chain. Every level but the first is made ready (copied with a
    /// one-texel border that holds its edge rule, so that every bilinear
    /// read is four loads with no edge case: a small level's edges are
    /// read often, a 16² face's by one lookup in eight); the first, the
    /// largest, is read in place (its edges seldom). No copies where the
    /// mapping has disk charts.
    levels: Pyramid,
    /// The irradiance map, as a level of its own, made ready.
    irradiance: Pyramid,
    /// The input itself, read in place of level 0 (roughness 0) when given.
    source: Option<EnvImage>,
    roughness: Vec<f32>,
    scale: IrradianceScale,
    dfg: DfgTable,
    blend: LevelBlend,
}

impl LitEnvironment {
    /// The chain `levels` (largest first, each a map in the same axes) with
    /// their perceptual roughness (non-decreasing), the irradiance map
    /// (`scale` says whether it holds E or E/π) and the DFG table.
    ///
    /// # Errors
    ///
    /// No levels, a roughness list of another length or not non-decreasing,
    /// or maps in different axes.
    pub fn new(
        levels: Vec<EnvImage>,
        roughness: Vec<f32>,
        irradiance: EnvImage,
        scale: IrradianceScale,
        dfg: DfgTable,
    ) -> Result<Self> {
        if levels.is_empty() || levels.len() != roughness.len() {
            return Err(Error::dimensions(format!(
                "a lit environment needs one roughness per level: {} levels, {} values",
                levels.len(),
                roughness.len()
            )));
        }
        if roughness
            .windows(2)
            .any(|w| w[0].partial_cmp(&w[1]).is_none_or(|o| o.is_gt()))
        {
            return Err(Error::dimensions(format!(
                "the levels' roughness must not decrease: {roughness:?}"
            )));
        }
        let frame = levels[0].representation().frame;
        if levels
            .iter()
            .chain(std::iter::once(&irradiance))
            .any(|l| l.representation().frame != frame)
        {
            return Err(Error::options(
                "the chain and the irradiance map are in different axes",
            ));
        }
        let blend = LevelBlend::InverseWidth {
            floor: texel_alpha(&levels[0]),
        };
        // The first level is read in place.
        let mut levels = Pyramid::of_levels(levels);
        levels.ready_from(1);
        let mut irradiance = Pyramid::of_levels(vec![irradiance]);
        irradiance.ready_from(0);
        Ok(Self {
            levels,
            source: None,
            roughness,
            irradiance,
            scale,
            dfg,
            blend,
        })
    }

    /// The same maps with `src`, the map the chain was baked from, read at
    /// roughness 0 in place of level 0 (in its own mapping and resolution,
    /// bilinearly, as the mirror render reads it) and, between roughness 0
    /// and level 1, through the near field (`NearField`: the cap around
    /// R integrated over `src`, the rest of the lobe from level 1). There
    /// the lobe is narrower than level 0's texels and most of its weight
    /// lies in its tail: neither a resampled level 0 (a footprint average)
    /// nor any blend of two levels holds it near a sun. The blend between
    /// the other levels is unchanged.
    ///
    /// # Errors
    ///
    /// The chain's level 0 is not at roughness 0, or `src` is in other axes.
    pub fn with_source(self, src: EnvImage) -> Result<Self> {
        if self.roughness[0] != 0.0 {
            return Err(Error::dimensions(format!(
                "the source map stands for roughness 0, the chain's level 0 is at {}",
                self.roughness[0]
            )));
        }
        if src.representation().frame != self.levels.levels()[0].representation().frame {
            return Err(Error::options(
                "the source map and the chain are in different axes",
            ));
        }
        Ok(Self {
            source: Some(src),
            ..self
        })
    }

    /// The map read at roughness 0 in place of level 0, if any
    /// ([`LitEnvironment::with_source`]).
    #[must_use]
    pub fn source(&self) -> Option<&EnvImage> {
        self.source.as_ref()
    }

    /// The same maps read with `blend` between levels (the default is
    /// [`LevelBlend::InverseWidth`] with the floor of level 0's texels).
    #[must_use]
    pub fn with_blend(self, blend: LevelBlend) -> Self {
        Self { blend, ..self }
    }

    /// How the chain is read between levels.
    #[must_use]
    pub fn blend(&self) -> LevelBlend {
        self.blend
    }

    /// What envmap's split-sum render reads, baked from `src` in its own
    /// axes: the renderer's chain (`render_chain`: level 0 at `size`²,
    /// then levels from roughness 0.13 to 1 spaced evenly in the logarithm
    /// of the lobe's width, each as large as its lobe needs, the smallest
    /// 16²), a 32² irradiance cube of E/π from the SH9, and a 128² DFG
    /// table on the edges grid ([`DfgGrid::Edges`]); read with
    /// [`LevelBlend::InverseWidth`], with `src` itself (a copy) read at
    /// roughness 0 and through the near field below the first level
    /// ([`LitEnvironment::with_source`]).
    /// Not a mip chain: an engine's files come from `envmap bake`
    /// (`LitEnvironment::bake_with` bakes those).
    ///
    /// # Errors
    ///
    /// As [`crate::bake::Baker::bake`]; [`Error::Cancelled`].
    pub fn bake(
        src: &EnvImage,
        size: u32,
        cancel: Option<&std::sync::atomic::AtomicBool>,
    ) -> Result<Self> {
        use crate::filter::bake::BakeOptions;
        let opts = BakeOptions {
            irradiance_size: 32,
            dfg_size: RENDER_DFG_SIZE,
            dfg_grid: DfgGrid::Edges,
            cancel,
            ..render_chain(size).apply(BakeOptions::default())
        };
        Self::bake_with(src, &opts)?.with_source(src.clone())
    }

    /// What a split-sum render reads, baked from `src` with `opts` (their
    /// axes replaced by `src`'s own, the irradiance map E/π): any chain
    /// `envmap bake` makes, such as an engine's ([`LitEnvironment::bake`]
    /// is envmap's own). The table is on `opts`' grid; a DFG size of 0
    /// takes 128² on the edges grid.
    ///
    /// # Errors
    ///
    /// As [`crate::filter::bake::bake`]; [`Error::Cancelled`].
    #[cfg_attr(not(feature = "instruments"), allow(dead_code))]
    #[cfg_attr(feature = "instruments", visibility::make(pub))]
    pub(crate) fn bake_with(
        src: &EnvImage,
        opts: &crate::filter::bake::BakeOptions,
    ) -> Result<Self> {
        use crate::filter::bake::{bake, BakeOptions};
        let mut opts = BakeOptions {
            axes: crate::image::FileAxes::Frame(src.representation().frame),
            irradiance_scale: IrradianceScale::EOverPi,
            ..opts.clone()
        };
        if opts.irradiance_size == 0 {
            opts.irradiance_size = 32;
        }
        if opts.dfg_size == 0 {
            opts.dfg_size = RENDER_DFG_SIZE;
            opts.dfg_grid = DfgGrid::Edges;
        }
        let b = bake(src, &opts, &|_, _| {})?;
        let (Some(chain), Some(irr), Some(dfg)) = (b.chain, b.irradiance, b.dfg) else {
            return Err(Error::options(
                "the bake made no chain, irradiance map or DFG table",
            ));
        };
        let roughness = chain.reports.iter().map(|r| r.roughness).collect();
        Self::new(
            chain.levels,
            roughness,
            irr.image,
            IrradianceScale::EOverPi,
            dfg,
        )
    }

    /// The levels, largest first.
    #[must_use]
    pub fn levels(&self) -> &[EnvImage] {
        self.levels.levels()
    }

    /// The irradiance map.
    #[must_use]
    pub fn irradiance(&self) -> &EnvImage {
        &self.irradiance.levels()[0]
    }

    /// Whether the irradiance map holds E or E/π.
    #[must_use]
    pub fn irradiance_scale(&self) -> IrradianceScale {
        self.scale
    }

    /// The DFG table.
    #[must_use]
    pub fn dfg(&self) -> &DfgTable {
        &self.dfg
    }

    /// Each level's perceptual roughness.
    #[must_use]
    pub fn roughness(&self) -> &[f32] {
        &self.roughness
    }

    /// Samplers over the maps, for shading many pixels.
    #[cfg_attr(feature = "instruments", visibility::make(pub))]
    #[must_use]
    pub(crate) fn sampler(&self) -> LitSampler<'_> {
        LitSampler {
            env: self,
            levels: (0..self.levels.len())
                .map(|k| self.levels.reader(k, false))
                .collect(),
            source: self.source.as_ref().map(|s| (Sampler::new(s), s.mapping())),
            near: std::sync::Mutex::new(Vec::new()),
            irradiance: self.irradiance.reader(0, false),
            to_map: self.levels()[0].representation().frame.matrix().transpose(),
            mapping: self.levels()[0].mapping(),
            irr_mapping: self.irradiance().mapping(),
        }
    }
}

/// [`LitEnvironment`]'s maps ready to be read.
#[cfg_attr(feature = "instruments", visibility::make(pub))]
pub(crate) struct LitSampler<'a> {
    env: &'a LitEnvironment,
    levels: Vec<Level<'a>>,
    /// The source read in place of level 0, and its mapping.
    source: Option<(Sampler<'a>, AnyMapping)>,
    /// The near-field quadratures made so far, by roughness (bits).
    near: std::sync::Mutex<Vec<(u32, std::sync::Arc<NearField>)>>,
    irradiance: Level<'a>,
    to_map: Mat3,
    mapping: AnyMapping,
    irr_mapping: AnyMapping,
}

/// Where the chain is read for unit normal `n` seen along unit `v` at
/// perceptual roughness `r`: R = 2(N·V)N − V, or with `dominant` the lobe's
/// dominant direction mix(R, N, r²) (Lagarde & de Rousiers 2014, §4.9.3).
pub(crate) fn specular_direction(n: Vec3, v: Vec3, r: f32, dominant: bool) -> Vec3 {
    let refl = reflect_view(n, v);
    if dominant {
        refl.lerp(n, r * r).normalize_or(refl)
    } else {
        refl
    }
}

/// The angle a texel of `level` spans at its chart's centre (for a cube
/// face of s², 2·atan(1/s); an EAC face's, (π/2)/s; a latitude-longitude
/// map's at the equator).
fn texel_angle(level: &EnvImage) -> f64 {
    let (w, h) = level.cell_size();
    let s = f64::from(w.max(h).max(1));
    match level.mapping() {
        AnyMapping::Cube => 2.0 * (1.0 / s).atan(),
        AnyMapping::Eac => core::f64::consts::FRAC_PI_2 / s,
        AnyMapping::LatLong => 2.0 * core::f64::consts::PI / f64::from(w.max(1)),
        _ => core::f64::consts::PI / s,
    }
}

/// The width of a map's texels in α units: the α whose GGX lobe is as
/// wide as a texel of `level` at its chart's centre.
fn texel_alpha(level: &EnvImage) -> f32 {
    alpha_of_lobe_width(texel_angle(level)) as f32
}

/// N·V as the split sum reads the DFG at it: clamped to [10⁻⁴, 1].
#[inline]
pub(crate) fn clamp_nv(nv: f32) -> f32 {
    nv.clamp(1e-4, 1.0)
}

/// The split sum's last step, shared by [`LitSampler`] and
/// [`exact_split_sum`](super::exact_split_sum): c_diff·E/π +
/// LD·(F0·A + B), times Filament's multiscatter factor
/// 1 + F0·(1/(A + B) − 1) when asked for (see the [module docs](super)),
/// from the DFG's `[A, B]`, the prefiltered
/// radiance `ld` and E/π `e`.
#[inline]
pub(crate) fn split_sum(
    m: &Material,
    [a, b]: [f32; 2],
    ld: [f32; 3],
    e: [f32; 3],
    multiscatter: bool,
) -> [f32; 3] {
    let (f0, diff) = (m.f0(), m.diffuse_color());
    [0, 1, 2].map(|i| {
        let mut s = f0[i] * a + b;
        if multiscatter && a + b > 0.0 {
            s *= 1.0 + f0[i] * (1.0 / (a + b) - 1.0);
        }
        diff[i] * e[i] + ld[i] * s
    })
}

/// Negative values (a lossy file's ringing) as 0, as the chain's levels
/// and the exact split sum clamp them.
fn non_negative(x: [f32; 3]) -> [f32; 3] {
    x.map(|v| v.max(0.0))
}

/// A sampled level's red, green and blue.
#[inline(always)]
fn rgb(v: wide::f32x4) -> [f32; 3] {
    let [r, g, b, _] = v.to_array();
    [r, g, b]
}

/// `a + (b − a)·t` per channel.
fn lerp3(a: [f32; 3], b: [f32; 3], t: f32) -> [f32; 3] {
    [0, 1, 2].map(|i| a[i] + (b[i] - a[i]) * t)
}

#[cfg_attr(not(feature = "instruments"), allow(unreachable_pub, dead_code))]
impl LitSampler<'_> {
    /// The prefiltered radiance towards world direction `r` at perceptual
    /// roughness `roughness` (see the [module docs](super)).
    #[must_use]
    pub fn specular(&self, r: Vec3, roughness: f32) -> [f32; 3] {
        match self.mapping.forward(self.to_map * r) {
            Some(c) => self.specular_at(c, roughness),
            None => [0.0; 3],
        }
    }

    /// The prefiltered radiance at chart point `c` of the chain.
    #[must_use]
    pub(crate) fn specular_at(&self, c: ChartUv, roughness: f32) -> [f32; 3] {
        let (k, blend) = self.levels_of(roughness);
        if let (Some(nf), Some(d)) = (
            self.near_field(k, blend, roughness),
            self.mapping.inverse(c),
        ) {
            let l1 = rgb(self.levels[1].sample(c));
            return self.near_value(&nf, d, l1);
        }
        let a = match (&self.source, k) {
            (Some((s, m)), 0) => self
                .mapping
                .inverse(c)
                .and_then(|d| m.forward(d))
                .map_or([0.0; 3], |q| non_negative(s.sample(q, Filter::Bilinear))),
            _ => rgb(self.levels[k].sample(c)),
        };
        match blend {
            None => a,
            Some(t) => lerp3(a, rgb(self.levels[k + 1].sample(c)), t),
        }
    }

    /// The near-field quadrature at `roughness` when the chain is read
    /// between the source (level 0) and level 1 there.
    fn near_field(
        &self,
        k: usize,
        blend: Option<f32>,
        roughness: f32,
    ) -> Option<std::sync::Arc<NearField>> {
        if self.source.is_none() || k != 0 || blend.is_none() || roughness <= 0.0 {
            return None;
        }
        let key = roughness.to_bits();
        let mut cache = self
            .near
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        if let Some((_, nf)) = cache.iter().find(|(b, _)| *b == key) {
            return Some(nf.clone());
        }
        let texel = self.env.source.as_ref().map_or(0.0, texel_angle);
        let nf = std::sync::Arc::new(NearField::new(roughness, self.env.roughness[1], texel));
        cache.push((key, nf.clone()));
        Some(nf)
    }

    /// LD at map-axes direction `d` from the near field `nf` over the
    /// source and level 1's value `l1` there (see [`NearField`]).
    fn near_value(&self, nf: &NearField, d: Vec3, l1: [f32; 3]) -> [f32; 3] {
        use envmap_simd::{Dir8, Fine, Mapping8};
        let Some((src, m)) = &self.source else {
            return l1;
        };
        let (t, b) = basis(d);
        let mut sum = [0.0f64; 3];
        let mut dirs = [Vec3::Z; 8];
        for (nodes, weights) in nf.nodes.chunks(8).zip(nf.weights.chunks(8)) {
            for (o, n) in dirs.iter_mut().zip(nodes) {
                *o = d * n[0] + t * n[1] + b * n[2];
            }
            let q = m.forward8::<Fine>(Dir8::from_partial(&dirs[..nodes.len()]));
            let v = src.sample8(&q, Filter::Bilinear);
            for (v, &w) in v.iter().zip(weights) {
                for c in 0..3 {
                    sum[c] += f64::from(w) * f64::from(v[c]);
                }
            }
        }
        [0, 1, 2].map(|c| ((nf.far * f64::from(l1[c]) + sum[c]) / nf.total).max(0.0) as f32)
    }

    /// The level whose roughness is the largest at most `roughness`, and
    /// the weight of the next one ([`LevelBlend`]) when `roughness` lies
    /// between them.
    fn levels_of(&self, roughness: f32) -> (usize, Option<f32>) {
        let rs = &self.env.roughness;
        let k = rs.partition_point(|&x| x <= roughness).saturating_sub(1);
        if k + 1 >= rs.len() || roughness <= rs[k] {
            return (k, None);
        }
        let t = self.env.blend.weight(rs[k], rs[k + 1], roughness);
        (k, Some(t))
    }

    /// The irradiance map's value `e` as E/π.
    fn as_e_over_pi(&self, e: [f32; 3]) -> [f32; 3] {
        match self.env.scale {
            IrradianceScale::EOverPi => e,
            IrradianceScale::E => e.map(|v| v / core::f32::consts::PI),
        }
    }

    /// The split sum's sum (see the [module docs](super)) from the chain's
    /// value `ld`, E/π `e`, and N·V.
    fn combine(
        &self,
        m: &Material,
        nv: f32,
        ld: [f32; 3],
        e: [f32; 3],
        multiscatter: bool,
    ) -> [f32; 3] {
        let r = m.clamped_roughness();
        let dfg = self.env.dfg.sample_single_scatter(clamp_nv(nv), r);
        split_sum(m, dfg, ld, e, multiscatter)
    }

    /// E(n)/π towards world normal `n`.
    #[must_use]
    pub fn irradiance_over_pi(&self, n: Vec3) -> [f32; 3] {
        match self.irr_mapping.forward(self.to_map * n) {
            Some(c) => self.irradiance_at(c),
            None => [0.0; 3],
        }
    }

    /// E/π at chart point `c` of the irradiance map.
    #[must_use]
    pub fn irradiance_at(&self, c: ChartUv) -> [f32; 3] {
        self.as_e_over_pi(rgb(self.irradiance.sample(c)))
    }

    /// Where [`LitSampler::shade`] looks: the chart points of the specular
    /// direction (R, or the dominant direction mix(R, N, α)) in the chain
    /// and of `n` in the irradiance map. Per-vertex shading computes these
    /// at the vertices and interpolates them (seed `002`).
    #[must_use]
    pub(crate) fn lookup_points(
        &self,
        m: &Material,
        n: Vec3,
        v: Vec3,
        dominant: bool,
    ) -> (ChartUv, ChartUv) {
        let dir = specular_direction(n, v, m.clamped_roughness(), dominant);
        let bad = ChartUv::new(u32::MAX, f32::NAN, f32::NAN);
        (
            self.mapping.forward(self.to_map * dir).unwrap_or(bad),
            self.irr_mapping.forward(self.to_map * n).unwrap_or(bad),
        )
    }

    /// The split-sum radiance leaving a surface of material `m` at unit
    /// normal `n` towards unit `v`; `multiscatter` adds Filament's energy
    /// compensation; `dominant` reads the chain along the lobe's dominant
    /// direction mix(R, N, α) instead of R (Lagarde & de Rousiers, "Moving
    /// Frostbite to PBR", 2014, §4.9.3; Filament's
    /// `getSpecularDominantDirection`).
    #[must_use]
    pub fn shade(
        &self,
        m: &Material,
        n: Vec3,
        v: Vec3,
        multiscatter: bool,
        dominant: bool,
    ) -> [f32; 3] {
        let (s, e) = self.lookup_points(m, n, v, dominant);
        self.shade_at(m, n.dot(v), s, e, multiscatter)
    }

    /// [`LitSampler::shade`] for up to eight surface points at once (unit
    /// normals `n`, unit view vectors `v`, as many of each), into the first
    /// `n.len()` entries of `out`: the lookup points mapped eight at a
    /// time, the chain's two levels and the irradiance map read eight at a
    /// time; lane `k` equals `shade(m, n[k], v[k], …)` (bit for bit on the
    /// tests' random inputs; within 10⁻⁵ relative is what they require).
    pub fn shade8(
        &self,
        m: &Material,
        n: &[Vec3],
        v: &[Vec3],
        multiscatter: bool,
        dominant: bool,
        out: &mut [[f32; 3]],
    ) {
        use envmap_simd::{Dir8, Fine, Mapping8, LANES};
        let lanes = n.len().min(v.len()).min(out.len()).min(LANES);
        let mask = (1u32 << lanes) - 1;
        let r = m.clamped_roughness();
        let mut spec = [Vec3::Z; LANES];
        let mut irr = [Vec3::Z; LANES];
        let mut nv = [1.0f32; LANES];
        for k in 0..lanes {
            spec[k] = self.to_map * specular_direction(n[k], v[k], r, dominant);
            irr[k] = self.to_map * n[k];
            nv[k] = n[k].dot(v[k]);
        }
        let qs = self.mapping.forward8::<Fine>(Dir8::from_partial(&spec));
        let qi = self.irr_mapping.forward8::<Fine>(Dir8::from_partial(&irr));
        // One roughness for all lanes: the same two levels and blend.
        let (level, blend) = self.levels_of(r);
        if let Some(nf) = self.near_field(level, blend, r) {
            let l1 = self.levels[1].sample8(&qs, mask).map(rgb);
            let e = self.irradiance.sample8(&qi, mask).map(rgb);
            for k in 0..lanes {
                let ld = self.near_value(&nf, spec[k], l1[k]);
                out[k] = self.combine(m, nv[k], ld, self.as_e_over_pi(e[k]), multiscatter);
            }
            return;
        }
        let mut ld = match (&self.source, level) {
            (Some((s, m)), 0) => s
                .sample8(
                    &m.forward8::<Fine>(Dir8::from_partial(&spec)),
                    Filter::Bilinear,
                )
                .map(non_negative),
            _ => self.levels[level].sample8(&qs, mask).map(rgb),
        };
        if let Some(t) = blend {
            let b = self.levels[level + 1].sample8(&qs, mask).map(rgb);
            for (a, b) in ld.iter_mut().zip(&b) {
                *a = lerp3(*a, *b, t);
            }
        }
        let e = self.irradiance.sample8(&qi, mask).map(rgb);
        let mut dfg = [[0.0f32; 2]; LANES];
        self.env
            .dfg
            .sample_single_scatter_at(&nv.map(clamp_nv), r, &mut dfg);
        for k in 0..lanes {
            let e = self.as_e_over_pi(e[k]);
            out[k] = split_sum(m, dfg[k], ld[k], e, multiscatter);
        }
    }

    /// [`LitSampler::shade`] from given lookup points ([`LitSampler::lookup_points`]):
    /// `nv` is N·V, `spec` the chain's point, `irr` the irradiance map's.
    #[must_use]
    pub(crate) fn shade_at(
        &self,
        m: &Material,
        nv: f32,
        spec: ChartUv,
        irr: ChartUv,
        multiscatter: bool,
    ) -> [f32; 3] {
        let ld = self.specular_at(spec, m.clamped_roughness());
        self.combine(m, nv, ld, self.irradiance_at(irr), multiscatter)
    }
}

/// An orthonormal basis around unit `n` (Duff et al. 2017).
pub(crate) fn basis(n: Vec3) -> (Vec3, Vec3) {
    let s = 1f32.copysign(n.z);
    let a = -1.0 / (s + n.z);
    let b = n.x * n.y * a;
    (
        Vec3::new(1.0 + s * n.x * n.x * a, s * b, -s * n.x),
        Vec3::new(b, s + n.y * n.y * a, -n.y),
    )
}

/// The chain envmap's own renderer bakes ([`crate::scene::lit::LitEnvironment::bake`]):
/// `lobe_chain` from roughness [`RENDER_FIRST_ROUGHNESS`] in steps of
/// [`RENDER_WIDTH_STEP`], [`RENDER_TEXELS_PER_LOBE`] texels per lobe width,
/// level 0 at `size`², the others from [`RENDER_MIN_SIZE`]² up to 1.5 ×
/// `size` (the first few, whose lobes are narrower than 4 of level 0's
/// texels). Below the first level the renderer reads the input itself
/// ([`crate::scene::lit::LitEnvironment::with_source`]). Its target against
/// the exact split sum is 2 % RMS and 0.5 % bias at every roughness from 0
/// to 1 (`docs/design/lighting-method.md`, "How exact the lit renders are", has the
/// measurements).
#[cfg_attr(not(feature = "instruments"), allow(dead_code))]
#[must_use]
pub(crate) fn render_chain(size: u32) -> ChainShape {
    let first = RENDER_FIRST_ROUGHNESS * (256.0 / size.max(1) as f32).sqrt();
    lobe_chain(
        size,
        size.saturating_add(size / 2),
        first.min(0.5),
        RENDER_WIDTH_STEP,
        RENDER_TEXELS_PER_LOBE,
        RENDER_MIN_SIZE,
    )
}

/// The roughness of [`render_chain`]'s first level above 0 at a level 0
/// of 256² (scaled by √(256/size) for others: 0.065 at 1024², 0.18 at
/// 128²). Below it the renderer reads the input itself through the near
/// field (`scene::near_field`'s `NearField`), which follows the input read
/// bilinearly; a level lower than this, baked from the input's texels,
/// differs from that reading near a one-texel sun.
#[cfg_attr(not(feature = "instruments"), allow(dead_code))]
pub(crate) const RENDER_FIRST_ROUGHNESS: f32 = 0.13;

/// [`render_chain`]'s largest step in ln(lobe width) from one level to the
/// next (the width grows by at most e^0.25 = 1.28 per level). Blended
/// linearly in 1/α, two lobes this far apart stand for the lobe between
/// them within about 1 % (L² over the sphere, a point light).
#[cfg_attr(not(feature = "instruments"), allow(dead_code))]
pub(crate) const RENDER_WIDTH_STEP: f64 = 0.25;

/// Texels of [`render_chain`]'s levels per lobe width (at a face's
/// centre), up to 1.5 × level 0's size: a level read at its own roughness
/// is then within 0.4 % of the exact split sum, and more or fewer texels
/// per lobe hardly change the worst error between levels.
#[cfg_attr(not(feature = "instruments"), allow(dead_code))]
pub(crate) const RENDER_TEXELS_PER_LOBE: f64 = 4.0;

/// [`render_chain`]'s smallest face: roughness 1's level holds its lobe
/// (a 2² level reads it several per cent too dark or bright).
#[cfg_attr(not(feature = "instruments"), allow(dead_code))]
pub(crate) const RENDER_MIN_SIZE: u32 = 16;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::instruments::Oracle;

    /// Below the first level the render reads the source through the near
    /// field: a constant map gives its constant, roughness 0 the source's
    /// bilinear value, and just below the first level the level itself;
    /// on a map with a one-texel sun it follows the exact integral of the
    /// bilinear source ([`Oracle::bilinear`]) where level 0 and the first
    /// level are far from it.
    #[test]
    fn the_near_field_reads_the_source_below_the_first_level() {
        use crate::image::Representation;
        use crate::scene::procedural::fill;
        let repr = Representation::default_for(AnyMapping::LatLong);
        let constant = fill(repr, 128, 64, |_| [0.7; 3]).unwrap();
        let lit = LitEnvironment::bake(&constant, 32, None).unwrap();
        let r1 = lit.roughness()[1];
        let s = lit.sampler();
        let dirs = [Vec3::X, Vec3::new(0.3, -0.5, 0.8).normalize(), -Vec3::Z];
        for r in [0.01f32, 0.1 * r1, 0.5 * r1, 0.99 * r1] {
            for d in dirs {
                let v = s.specular(d, r)[0];
                assert!((v - 0.7).abs() < 1e-5, "{r} {d}: {v}");
            }
        }
        // A one-texel sun in a smooth sky.
        let sun = Vec3::new(0.4, 0.3, 0.6).normalize();
        let mut img = fill(repr, 256, 128, |d| [1.0 + 0.5 * d.z; 3]).unwrap();
        let q = AnyMapping::LatLong.forward(sun).unwrap();
        let (i, j) = ((q.u * 256.0) as u32, (q.v * 128.0) as u32);
        assert!(img.set_chart_texel(0, i, j, [5000.0; 3]));
        let lit = LitEnvironment::bake(&img, 64, None).unwrap();
        let r1 = lit.roughness()[1];
        let s = lit.sampler();
        let oracle = Oracle::bilinear(&img);
        let src = Sampler::new(&img);
        let centre = AnyMapping::LatLong
            .inverse(ChartUv::new(
                0,
                (i as f32 + 0.5) / 256.0,
                (j as f32 + 0.5) / 128.0,
            ))
            .unwrap();
        let off = AnyMapping::LatLong
            .inverse(ChartUv::new(
                0,
                (i as f32 + 2.0) / 256.0,
                (j as f32 + 0.9) / 128.0,
            ))
            .unwrap();
        let to_world = img.representation().frame.matrix();
        for local in [centre, off] {
            let c = AnyMapping::LatLong.forward(local).unwrap();
            let d = to_world * local;
            // Through the chain's chart point and back: to rounding.
            let (got, want) = (s.specular(d, 0.0)[0], src.sample(c, Filter::Bilinear)[0]);
            assert!((got - want).abs() < 1e-5 * want, "{d}: {got} {want}");
            let at_r1 = s.specular(d, r1)[0];
            let below = s.specular(d, r1 * (1.0 - 1e-4))[0];
            assert!((below - at_r1).abs() < 2e-3 * at_r1, "{d}: {below} {at_r1}");
            for r in [0.3 * r1, 0.6 * r1] {
                let got = f64::from(s.specular(d, r)[0]);
                let want = oracle.prefiltered(r, &[d])[0][0];
                // Without the near field: the blend of level 0 and level 1.
                let level0 = f64::from(
                    Sampler::new(&lit.levels()[0])
                        .sample(AnyMapping::Cube.forward(local).unwrap(), Filter::Bilinear)[0],
                );
                println!("{d} r {r}: near field {got:.2}, exact {want:.2}, level 0 {level0:.2}, level 1 {at_r1:.2}");
                assert!(
                    (got - want).abs() < 0.01 * want,
                    "{d} r {r}: {got} vs {want}"
                );
            }
        }
    }

    /// The chain's levels and the irradiance map read through their
    /// bordered copies as their own bilinear sampler reads them (to f32
    /// rounding: the two group the blend differently), at points all over
    /// each chart, its edges and corners included, one at a time and eight
    /// at a time; a sphere map's, which has no copies, bit for bit.
    #[test]
    fn the_chain_reads_through_its_copies_as_in_place() {
        use crate::image::Representation;
        use crate::scene::procedural::{fill, smooth};
        use envmap_core::Mapping;
        use envmap_simd::Uv8;
        for m in [AnyMapping::Cube, AnyMapping::LatLong, AnyMapping::SphereMap] {
            let repr = Representation::default_for(m);
            let map = |cell: u32| {
                let a = repr.atlas;
                let (w, h) = a.image_size_for_cell_width(cell * a.cell_aspect_w).unwrap();
                fill(repr, w, h, smooth).unwrap()
            };
            let levels = vec![map(16), map(8), map(4)];
            let env = LitEnvironment::new(
                levels,
                vec![0.0, 0.5, 1.0],
                map(2),
                IrradianceScale::EOverPi,
                DfgTable::new(8).unwrap(),
            )
            .unwrap();
            let s = env.sampler();
            let copied = !m.has_disk_charts();
            assert!(
                matches!(s.levels[0], Level::Plain(_)),
                "{m}: level 0 is read in place"
            );
            assert_eq!(matches!(s.levels[1], Level::Bordered(_)), copied, "{m}");
            assert_eq!(matches!(s.irradiance, Level::Bordered(_)), copied, "{m}");
            let maps = env.levels().iter().zip(&s.levels);
            let all = maps.chain([(env.irradiance(), &s.irradiance)]);
            let ts = [0.0, 0.01, 0.2, 0.5, 0.77, 0.99, 1.0];
            for (img, level) in all {
                let own = Sampler::new(img);
                for chart in 0..m.chart_count() {
                    let points: Vec<ChartUv> = ts
                        .iter()
                        .flat_map(|&u| ts.iter().map(move |&v| ChartUv::new(chart, u, v)))
                        .collect();
                    for batch in points.chunks(8) {
                        let got8 = level.sample8(&Uv8::from_partial(batch), 0xff);
                        for (k, &c) in batch.iter().enumerate() {
                            let want = own.sample(c, Filter::Bilinear);
                            let got = rgb(level.sample(c));
                            assert_eq!(rgb(got8[k]), got, "{m} {c:?}");
                            for i in 0..3 {
                                let tol = if copied { 1e-6 * want[i].abs() } else { 0.0 };
                                assert!(
                                    (got[i] - want[i]).abs() <= tol,
                                    "{m} {c:?}: {got:?} {want:?}"
                                );
                            }
                        }
                    }
                }
            }
        }
    }

    /// An engine's blend is its trilinear filter's: the weight of the next
    /// level is the fractional part of lod = f(r)·(n − 1) at levels made by
    /// the same rule; envmap's puts the middle in 1/α at one half, and
    /// treats a level at roughness 0 as a lobe as wide as `floor`.
    #[test]
    fn level_blends() {
        let n = 6;
        for rule in [
            RoughnessRule::Linear,
            RoughnessRule::Filament,
            RoughnessRule::Unity,
        ] {
            let rs: Vec<f32> = (0..n).map(|k| rule.roughness(k, n)).collect();
            let blend = LevelBlend::engine(&rule);
            let lod = |r: f32| match rule {
                RoughnessRule::Filament => r * (2.0 - r),
                RoughnessRule::Unity => r * (1.7 - 0.7 * r),
                _ => r,
            } * (n - 1) as f32;
            for r in [0.03f32, 0.21, 0.5, 0.77, 0.99] {
                let k = rs.partition_point(|&x| x <= r) - 1;
                let t = blend.weight(rs[k], rs[k + 1], r);
                let want = lod(r) - k as f32;
                assert!((t - want).abs() < 1e-4, "{rule:?} {r}: {t} vs {want}");
            }
        }
        // Babylon.js: lod = scale·log2(size·α) at levels made by its rule,
        // clamped to level 0 below.
        for (rule, scale) in [(RoughnessRule::Babylon, 0.8), (RoughnessRule::Log2, 1.0)] {
            let n = 9;
            let rs: Vec<f32> = (0..n).map(|k| rule.roughness(k, n)).collect();
            let blend = LevelBlend::engine(&rule);
            for r in [0.01f32, 0.05, 0.1, 0.3, 0.5, 0.8] {
                let lod = (scale * (256.0 * r * r).log2()).max(0.0);
                let k = rs.partition_point(|&x| x <= r) - 1;
                let t = blend.weight(rs[k], rs[k + 1], r);
                let want = lod - k as f32;
                assert!((t - want).abs() < 1e-4, "{rule:?} {r}: {t} vs {want}");
            }
        }
        let iw = LevelBlend::InverseWidth { floor: 0.0 };
        let (lo, hi) = (0.2f32, 0.3f32);
        let mid = (2.0 / (1.0 / (lo * lo) + 1.0 / (hi * hi))).sqrt();
        assert!((iw.weight(lo, hi, mid) - 0.5).abs() < 1e-5);
        assert_eq!(iw.weight(lo, hi, lo), 0.0);
        assert_eq!(iw.weight(lo, hi, hi), 1.0);
        // Linear in r would give the rougher level less weight at the middle.
        assert!(LevelBlend::Roughness.weight(lo, hi, mid) < 0.45);
        // A delta at roughness 0: anything rougher reads the first lobe.
        assert_eq!(iw.weight(0.0, 0.1, 0.01), 1.0);
        let floored = LevelBlend::InverseWidth { floor: 0.006 };
        assert!(floored.weight(0.0, 0.1, 0.01) < 0.05);
        assert!(floored.weight(0.0, 0.1, 0.09) > 0.8);
    }
}
