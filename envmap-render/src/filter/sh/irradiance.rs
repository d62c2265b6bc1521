// Irradiance maps: from SH9, and by the exact cosine convolution of a
// level of the map's pyramid.

use std::f64::consts::PI;

use envmap_core::texel::texel_center;
use envmap_core::{AnyMapping, ChartUv, Frame, Mapping};
use envmap_simd::{Dir8, Exact, Mapping8, Uv8, LANES};
use wide::{f32x8, u32x8};

use super::*;
use crate::error::Result;
use crate::filter::pyramid::Pyramid;
use crate::filter::weights::TexelWeights;
use crate::image::{EnvImage, FileAxes, Representation, RgbImage};

/// What an irradiance map stores.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum IrradianceScale {
    /// The irradiance E(n) = ∫ L(ω) max(n·ω, 0) dω itself.
    E,
    /// E/π, the default: the outgoing radiance of a white Lambertian surface
    /// (albedo 1), what engines sample their diffuse maps for (Filament,
    /// Bevy, glTF-IBL-Sampler, cmft all store it).
    #[default]
    EOverPi,
}

impl IrradianceScale {
    /// The factor applied to E: 1 or 1/π.
    #[cfg_attr(feature = "instruments", visibility::make(pub))]
    #[must_use]
    pub(crate) fn factor(self) -> f64 {
        match self {
            IrradianceScale::E => 1.0,
            IrradianceScale::EOverPi => 1.0 / PI,
        }
    }

    /// `"E"` or `"E/pi"`, for manifests and metadata.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            IrradianceScale::E => "E",
            IrradianceScale::EOverPi => "E/pi",
        }
    }
}

/// The face size of `irradiance_cube`: 32 (Bevy's and glTF-IBL-Sampler's
/// diffuse cube size).
pub const DEFAULT_IRRADIANCE_SIZE: u32 = 32;

/// The default irradiance map's representation: a cube in envmap's file
/// conventions (the GL world, y up; horizontal cross), as
/// `Representation::for_file(AnyMapping::Cube, FileAxes::default())`.
#[cfg_attr(not(feature = "instruments"), allow(dead_code))]
#[cfg_attr(feature = "instruments", visibility::make(pub))]
#[must_use]
pub(crate) fn default_irradiance_representation() -> Representation {
    Representation::for_file(AnyMapping::Cube, FileAxes::default())
}

/// Evaluates `row_fn` on every chart row of a new `width × height` image in
/// `repr`: it gets the row's unit directions (in `repr`'s own axes, eight
/// per batch, the last batch padded) and fills the row; texels with no
/// direction (outside a disk) are then set black, and so are texels
/// outside every chart.
pub(super) fn fill_map(
    repr: Representation,
    width: u32,
    height: u32,
    row_fn: impl Fn(&[Dir8], &mut [[f32; 3]]) + Sync,
) -> Result<EnvImage> {
    let mut out = EnvImage::new(width, height, repr)?;
    let (cw, ch) = out.cell_size();
    let us = padded_centres(cw, false);
    let mapping = repr.mapping;
    for chart in 0..mapping.chart_count() {
        if repr.atlas.cell_of(chart).is_none() {
            continue;
        }
        let mut px = vec![[0.0f32; 3]; cw as usize * ch as usize];
        px.par_chunks_mut(cw as usize)
            .enumerate()
            .for_each(|(j, row)| {
                let j = j as u32;
                let v = f32x8::splat(texel_center(j, ch));
                let c8 = u32x8::splat(chart);
                let dirs: Vec<Dir8> = us
                    .as_chunks::<LANES>()
                    .0
                    .iter()
                    .map(|u| mapping.inverse8::<Exact>(Uv8::new(c8, f32x8::new(*u), v)))
                    .collect();
                row_fn(&dirs, row);
                for (k, p) in row.iter_mut().enumerate() {
                    let none = dirs
                        .get(k / LANES)
                        .is_none_or(|d| d.x.as_array()[k % LANES].is_nan());
                    if none {
                        *p = [0.0; 3];
                    }
                }
            });
        let face = RgbImage {
            width: cw,
            height: ch,
            pixels: px,
        };
        out.set_chart_image(chart, &face)?;
    }
    Ok(out)
}

/// Writes lane `k` of `vals` (R, G, B registers) of batch `b` into `row`.
#[inline]
pub(super) fn store(row: &mut [[f32; 3]], b: usize, vals: [[f32; LANES]; 3]) {
    let [r, g, bl] = vals;
    for (k, p) in row.iter_mut().skip(b * LANES).take(LANES).enumerate() {
        *p = [r[k], g[k], bl[k]];
    }
}

/// An irradiance map of `width × height` texels in `repr`, from the SH
/// (convolved first if they are radiance): each texel holds E or E/π at its
/// centre's direction, as `scale` says (E/π by default: see
/// [`IrradianceScale`]). Texels outside every chart are black.
///
/// # Errors
///
/// The size does not fit `repr` or exceeds the default size limit.
pub fn irradiance_map(
    sh: &Sh9,
    repr: Representation,
    width: u32,
    height: u32,
    scale: IrradianceScale,
) -> Result<EnvImage> {
    // The SH in the map's own axes, each coefficient times its basis
    // constant and the scale: the map evaluates polynomials only.
    let e = sh.irradiance().in_frame(repr.frame);
    let f: [[f32x8; 3]; 9] = core::array::from_fn(|i| {
        e.coeffs[i].map(|v| f32x8::splat((v * BASIS_CONSTANTS[i] * scale.factor()) as f32))
    });
    fill_map(repr, width, height, |dirs, row| {
        for (b, d) in dirs.iter().enumerate() {
            let (x, y, z) = (d.x, d.y, d.z);
            let p = [
                y,
                z,
                x,
                x * y,
                y * z,
                (z * f32x8::splat(3.0)).mul_sub(z, f32x8::ONE),
                x * z,
                x.mul_sub(x, y * y),
            ];
            let vals = [0, 1, 2].map(|c| {
                let mut e = f[0][c];
                for (pi, fi) in p.iter().zip(&f[1..]) {
                    e = pi.mul_add(fi[c], e);
                }
                e.to_array()
            });
            store(row, b, vals);
        }
    })
}

/// [`irradiance_map`] as a [`DEFAULT_IRRADIANCE_SIZE`]² cube in
/// [`default_irradiance_representation`].
///
/// # Errors
///
/// None in practice (the size is fixed and small).
#[cfg_attr(not(feature = "instruments"), allow(dead_code))]
#[cfg_attr(feature = "instruments", visibility::make(pub))]
pub(crate) fn irradiance_cube(sh: &Sh9, scale: IrradianceScale) -> Result<EnvImage> {
    let repr = default_irradiance_representation();
    let (w, h) = repr
        .size_for_cell_width(DEFAULT_IRRADIANCE_SIZE)
        .unwrap_or((4 * DEFAULT_IRRADIANCE_SIZE, 3 * DEFAULT_IRRADIANCE_SIZE));
    irradiance_map(sh, repr, w, h, scale)
}

/// Which pyramid level `irradiance_map_exact` convolves.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ExactLevel {
    /// The level the [module docs](super)' rule picks: finer levels until
    /// two successive ones differ by at most `tolerance` (relative RMS).
    Auto {
        /// The largest relative RMS difference accepted.
        tolerance: f64,
    },
    /// This level (clamped to the pyramid); 0 is the full resolution, the
    /// definition itself.
    Level(usize),
}

/// [`ExactLevel::Auto`]'s default tolerance.
pub const DEFAULT_EXACT_TOLERANCE: f64 = 1e-3;

/// Where [`ExactLevel::Auto`] starts: the coarsest level with at least
/// this many texels.
pub const AUTO_START_TEXELS: u64 = 1024;

impl Default for ExactLevel {
    /// `Auto` with [`DEFAULT_EXACT_TOLERANCE`].
    fn default() -> Self {
        ExactLevel::Auto {
            tolerance: DEFAULT_EXACT_TOLERANCE,
        }
    }
}

/// An exact irradiance map and how it was made.
#[derive(Clone, Debug, PartialEq)]
pub struct ExactIrradiance {
    /// The map.
    pub image: EnvImage,
    /// The pyramid level convolved.
    pub level: usize,
    /// The relative RMS difference from the map made from the next coarser
    /// level ([`ExactLevel::Auto`]; `None` when only one level was
    /// convolved).
    pub difference: Option<f64>,
    /// Source texels skipped because a channel was NaN or ±Inf.
    pub skipped: u64,
}

/// Source texels for the convolution: direction (x, y, z, in the output's
/// axes), then radiance × solid angle (R, G, B), then padding.
pub(super) type Source = [f32; 8];

/// Texels of a level with nonzero weight and radiance, as [`Source`]s in
/// the axes of `out_frame`, and the count of non-finite ones.
pub(super) fn sources(level: &EnvImage, out_frame: Frame) -> (Vec<Source>, u64) {
    let to_out = out_frame.matrix().as_dmat3().transpose()
        * level.representation().frame.matrix().as_dmat3();
    let mapping = level.mapping();
    let (cw, ch) = level.cell_size();
    let weights = TexelWeights::new(mapping, cw, ch);
    let rows: Vec<(u32, u32)> = (0..mapping.chart_count())
        .flat_map(|c| (0..ch).map(move |j| (c, j)))
        .collect();
    let parts: Vec<(Vec<Source>, u64)> = rows
        .par_iter()
        .map(|&(chart, j)| {
            let mut out = Vec::new();
            let mut skipped = 0;
            for i in 0..cw {
                let wt = weights.get(chart, i, j);
                let Some(l) = level.chart_texel(chart, i, j) else {
                    continue;
                };
                if wt == 0.0 {
                    continue;
                }
                if !l.iter().all(|c| c.is_finite()) {
                    skipped += 1;
                    continue;
                }
                if l == [0.0; 3] {
                    continue;
                }
                let c = ChartUv::new(chart, texel_center(i, cw), texel_center(j, ch));
                let Some(d) = mapping.inverse(c).and_then(|d| unit(to_out * d.as_dvec3())) else {
                    continue;
                };
                let lw = l.map(|v| (f64::from(v) * wt) as f32);
                out.push([
                    d.x as f32, d.y as f32, d.z as f32, lw[0], lw[1], lw[2], 0.0, 0.0,
                ]);
            }
            (out, skipped)
        })
        .collect();
    let skipped = parts.iter().map(|p| p.1).sum();
    (parts.into_iter().flat_map(|p| p.0).collect(), skipped)
}

/// Sources summed in f32 before being added in f64.
pub(super) const BLOCK: usize = 256;

/// One row of the exact convolution: for each output direction n,
/// Σ max(n·l, 0)·L·Ω over `src`, times `factor`; two batches (16 texels)
/// at a time.
pub(super) fn convolve_row(dirs: &[Dir8], src: &[Source], factor: f64, row: &mut [[f32; 3]]) {
    for (pair_index, pair) in dirs.chunks(2).enumerate() {
        let (a, b) = match pair {
            [a, b] => (*a, *b),
            [a] => (*a, *a),
            _ => continue,
        };
        let mut sum = [[0.0f64; 3]; 2 * LANES];
        for block in src.chunks(BLOCK) {
            let mut acc = [f32x8::ZERO; 6];
            for s in block {
                let (lx, ly, lz) = (f32x8::splat(s[0]), f32x8::splat(s[1]), f32x8::splat(s[2]));
                let ca =
                    a.x.mul_add(lx, a.y.mul_add(ly, a.z * lz))
                        .fast_max(f32x8::ZERO);
                let cb =
                    b.x.mul_add(lx, b.y.mul_add(ly, b.z * lz))
                        .fast_max(f32x8::ZERO);
                let (r, g, bl) = (f32x8::splat(s[3]), f32x8::splat(s[4]), f32x8::splat(s[5]));
                acc[0] = ca.mul_add(r, acc[0]);
                acc[1] = ca.mul_add(g, acc[1]);
                acc[2] = ca.mul_add(bl, acc[2]);
                acc[3] = cb.mul_add(r, acc[3]);
                acc[4] = cb.mul_add(g, acc[4]);
                acc[5] = cb.mul_add(bl, acc[5]);
            }
            for (h, half) in [&acc[0..3], &acc[3..6]].into_iter().enumerate() {
                for (c, v) in half.iter().enumerate() {
                    for (k, x) in v.to_array().into_iter().enumerate() {
                        sum[h * LANES + k][c] += f64::from(x);
                    }
                }
            }
        }
        for (k, s) in sum.iter().enumerate() {
            if let Some(p) = row.get_mut(pair_index * 2 * LANES + k) {
                *p = s.map(|v| (v * factor) as f32);
            }
        }
    }
}

/// The map convolved exactly from one level.
pub(super) fn exact_from_level(
    level: &EnvImage,
    repr: Representation,
    width: u32,
    height: u32,
    scale: IrradianceScale,
) -> Result<(EnvImage, u64)> {
    let (src, skipped) = sources(level, repr.frame);
    let factor = scale.factor();
    let img = fill_map(repr, width, height, |dirs, row| {
        convolve_row(dirs, &src, factor, row);
    })?;
    Ok((img, skipped))
}

/// The relative RMS difference of `a` from `b`: √(Σ(a − b)² / Σb²) over
/// every texel and channel (0 when both are black).
#[cfg_attr(feature = "instruments", visibility::make(pub))]
#[must_use]
pub(crate) fn relative_rms(a: &EnvImage, b: &EnvImage) -> f64 {
    let (mut se, mut ss) = (0.0f64, 0.0f64);
    for (p, q) in a.pixels().iter().zip(b.pixels()) {
        for c in 0..3 {
            let d = f64::from(p[c]) - f64::from(q[c]);
            se += d * d;
            ss += f64::from(q[c]) * f64::from(q[c]);
        }
    }
    if ss == 0.0 {
        if se == 0.0 {
            0.0
        } else {
            f64::INFINITY
        }
    } else {
        (se / ss).sqrt()
    }
}

/// Texels in all charts of a level.
pub(super) fn texels(level: &EnvImage) -> u64 {
    let (cw, ch) = level.cell_size();
    u64::from(cw) * u64::from(ch) * u64::from(level.mapping().chart_count())
}

/// An irradiance map by direct cosine convolution over a level of `src`:
/// E(n) = Σ_j L_j·max(n·l_j, 0)·Ω_j over the level's texels (direction
/// l_j at the texel centre, Ω_j its exact solid angle), stored as E or E/π
/// as `scale` says; eight output texels at a time, rows in parallel. The
/// level is chosen as `level` says (see the [module docs](super)).
///
/// # Errors
///
/// The size does not fit `repr` or exceeds the default size limit.
#[cfg_attr(feature = "instruments", visibility::make(pub))]
pub(crate) fn irradiance_map_exact(
    src: &Pyramid,
    repr: Representation,
    width: u32,
    height: u32,
    scale: IrradianceScale,
    level: ExactLevel,
) -> Result<ExactIrradiance> {
    let last = src.len().saturating_sub(1);
    let tolerance = match level {
        ExactLevel::Level(k) => {
            let k = k.min(last);
            let (image, skipped) = exact_from_level(src.level(k), repr, width, height, scale)?;
            return Ok(ExactIrradiance {
                image,
                level: k,
                difference: None,
                skipped,
            });
        }
        ExactLevel::Auto { tolerance } => tolerance,
    };
    let start = (0..src.len())
        .rev()
        .find(|&k| texels(src.level(k)) >= AUTO_START_TEXELS)
        .unwrap_or(0);
    let (mut prev, mut skipped) = exact_from_level(src.level(start), repr, width, height, scale)?;
    let mut k = start;
    let mut difference = None;
    while k > 0 {
        let (cur, s) = exact_from_level(src.level(k - 1), repr, width, height, scale)?;
        let d = relative_rms(&cur, &prev);
        (prev, skipped, k, difference) = (cur, s, k - 1, Some(d));
        if d <= tolerance {
            break;
        }
    }
    Ok(ExactIrradiance {
        image: prev,
        level: k,
        difference,
        skipped,
    })
}
