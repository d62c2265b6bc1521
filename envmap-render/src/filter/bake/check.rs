// What `--check` measures: a level or an irradiance map against the oracle
// (the exact integral of the input), at hashed texels, and the sampling's
// estimated error.

use std::time::Instant;

use envmap_core::texel::texel_center;
use envmap_core::{AnyMapping, ChartUv, Mapping};

use crate::error::{Error, Result};
use crate::filter::sh::IrradianceScale;
use crate::image::EnvImage;
use crate::instruments::Oracle;

/// A level's error against the exact integral on a subset of its texels
/// (`measure_level`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LevelError {
    /// Texels measured.
    pub texels: u32,
    /// Relative RMS error √(Σ(a − b)²/Σb²) over the texels and channels.
    pub relative_rms: f64,
    /// Bias: Σ(a − b)/Σb.
    pub bias: f64,
    /// Seconds the exact sums took.
    pub seconds: f64,
}

/// Measures `level` (a cube, in its own axes) made at `roughness` against
/// the oracle of the input (`Oracle::prefiltered`: the input as given,
/// piecewise constant over its own texels, independent of the base cube and
/// the pyramid the bake made) at `texels` of its texels picked by a fixed
/// hash (`seed` varies the pick). The oracle's values are clamped at zero as
/// the outputs are.
///
/// # Errors
///
/// `level` is not a cube.
#[cfg_attr(feature = "instruments", visibility::make(pub))]
pub(crate) fn measure_level(
    oracle: &Oracle,
    roughness: f32,
    level: &EnvImage,
    texels: u32,
    seed: u32,
) -> Result<LevelError> {
    if level.mapping() != AnyMapping::Cube {
        return Err(Error::usage("measure_level: a cube level expected"));
    }
    let t = Instant::now();
    let s = level.cell_size().0;
    let coords = hashed_texels(6, s, s, texels, seed);
    let frame = level.representation().frame;
    let (dirs, coords): (Vec<_>, Vec<_>) = coords
        .iter()
        .filter_map(|&(c, i, j)| {
            AnyMapping::Cube
                .inverse(ChartUv::new(c, texel_center(i, s), texel_center(j, s)))
                .map(|d| (frame.to_canonical(d), (c, i, j)))
        })
        .unzip();
    let exact = if roughness > 0.0 {
        oracle.prefiltered(roughness, &dirs)
    } else {
        // Roughness 0: the input itself at each direction is not an
        // integral; the level is a resampling, measured by conversion tests.
        return Err(Error::usage(
            "measure_level: roughness 0 is a resampling, not an integral",
        ));
    };
    let pairs = coords.iter().zip(&exact).map(|(&(c, i, j), e)| {
        (
            level
                .chart_texel(c, i, j)
                .unwrap_or_default()
                .map(f64::from),
            e.map(|v| v.max(0.0)),
        )
    });
    let mut m = compare(pairs);
    m.seconds = t.elapsed().as_secs_f64();
    Ok(m)
}

/// `count` texels of a `charts × w × h` grid picked by a fixed xorshift
/// hash of `seed` (repeats possible), as (chart, i, j).
pub(super) fn hashed_texels(
    charts: u32,
    w: u32,
    h: u32,
    count: u32,
    seed: u32,
) -> Vec<(u32, u32, u32)> {
    let n = charts * w * h;
    let mut h32 = 0x9e37_79b9u32 ^ seed.wrapping_mul(0x85eb_ca77);
    (0..count.min(n))
        .map(|_| {
            h32 ^= h32 << 13;
            h32 ^= h32 >> 17;
            h32 ^= h32 << 5;
            let k = h32 % n;
            (k / (w * h), k % w, (k / w) % h)
        })
        .collect()
}

/// Relative RMS √(Σ(a − b)²/Σb²) and bias Σ(a − b)/Σb of (measured,
/// exact) pairs over every channel.
pub(super) fn compare(pairs: impl Iterator<Item = ([f64; 3], [f64; 3])>) -> LevelError {
    let (mut se, mut ss, mut sd, mut sm, mut n) = (0.0f64, 0.0f64, 0.0f64, 0.0f64, 0u32);
    for (a, e) in pairs {
        for (x, y) in a.iter().zip(&e) {
            let d = x - y;
            se += d * d;
            ss += y * y;
            sd += d;
            sm += y;
        }
        n += 1;
    }
    let ratio = |a: f64, b: f64| if b > 0.0 { a / b } else { 0.0 };
    LevelError {
        texels: n,
        relative_rms: ratio(se, ss).sqrt(),
        bias: ratio(sd, sm),
        seconds: 0.0,
    }
}

/// Measures an irradiance map (any representation, in its own axes; E or
/// E/π as `scale` says) against the oracle's E (`Oracle::irradiance`),
/// clamped at zero as the map is, at `texels` texels picked as in
/// [`measure_level`].
#[cfg_attr(feature = "instruments", visibility::make(pub))]
#[must_use]
pub(crate) fn measure_irradiance(
    oracle: &Oracle,
    map: &EnvImage,
    scale: IrradianceScale,
    texels: u32,
    seed: u32,
) -> LevelError {
    let t = Instant::now();
    let mapping = map.mapping();
    let (w, h) = map.cell_size();
    let frame = map.representation().frame;
    let (dirs, coords): (Vec<_>, Vec<_>) = hashed_texels(mapping.chart_count(), w, h, texels, seed)
        .into_iter()
        .filter_map(|(c, i, j)| {
            mapping
                .inverse(ChartUv::new(c, texel_center(i, w), texel_center(j, h)))
                .map(|d| (frame.to_canonical(d), (c, i, j)))
        })
        .unzip();
    let exact = oracle.irradiance(&dirs);
    let f = scale.factor();
    let mut m = compare(coords.iter().zip(&exact).map(|(&(c, i, j), e)| {
        (
            map.chart_texel(c, i, j).unwrap_or_default().map(f64::from),
            e.map(|v| (v * f).max(0.0)),
        )
    }));
    m.seconds = t.elapsed().as_secs_f64();
    m
}

/// The relative RMS error a sampled level is expected to have against the
/// exact integral on a smooth environment: the errors at 64 samples per
/// texel from a sweep of sample counts (`examples/bake_accuracy.rs` with
/// `SAMPLES=64,256`, 300 texels per level, a 512² chain from a smooth
/// 4096 × 2048 HDR), interpolated in roughness and scaled by √(64/N) for
/// N samples, which overestimates the error at 256. Sharp environments
/// (edges, small lights) have larger errors: `envmap bake --check`
/// measures them on the input itself.
#[cfg_attr(feature = "instruments", visibility::make(pub))]
#[must_use]
pub(crate) fn estimated_error(roughness: f32, samples: u32) -> f64 {
    const AT_64: [(f64, f64); 9] = [
        (0.0, 0.0),
        (0.125, 0.0030),
        (0.25, 0.0053),
        (0.375, 0.0057),
        (0.5, 0.0059),
        (0.625, 0.0074),
        (0.75, 0.0102),
        (0.875, 0.0119),
        (1.0, 0.0204),
    ];
    let r = f64::from(roughness).clamp(0.0, 1.0);
    let e = AT_64
        .windows(2)
        .find(|w| r <= w[1].0)
        .map_or(AT_64[8].1, |w| {
            let t = (r - w[0].0) / (w[1].0 - w[0].0);
            w[0].1 + t * (w[1].1 - w[0].1)
        });
    e * (64.0 / f64::from(samples.max(1))).sqrt()
}
