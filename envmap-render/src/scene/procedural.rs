// Environments defined by a function of direction, evaluated into any
// representation.

use crate::par::*;
use envmap_core::glam::Vec3;
use envmap_core::texel::texel_center;
use envmap_core::ChartUv;

use crate::error::Result;
use crate::image::{EnvImage, Representation};

/// Evaluates `f` at every texel centre of a `width × height` image in `repr`
/// (the direction given to `f` is in world axes, z up: the representation's
/// frame is applied). Texels outside every chart are black.
pub fn fill(
    repr: Representation,
    width: u32,
    height: u32,
    f: impl Fn(Vec3) -> [f32; 3] + Sync,
) -> Result<EnvImage> {
    let mut img = EnvImage::new(width, height, repr)?;
    let atlas = repr.atlas;
    let mapping = repr.mapping;
    let frame = repr.frame;
    img.pixels_mut()
        .par_chunks_mut(width as usize)
        .enumerate()
        .for_each(|(y, row)| {
            for (x, px) in row.iter_mut().enumerate() {
                let Some(t) = atlas.texel_to_chart(x as u32, y as u32, width, height) else {
                    continue;
                };
                let c = ChartUv::new(t.chart, texel_center(t.i, t.w), texel_center(t.j, t.h));
                if let Some(d) = mapping.inverse(c) {
                    *px = f(frame.to_canonical(d));
                }
            }
        });
    Ok(img)
}

/// A smooth test environment: colour varies with direction at a few
/// frequencies, positive everywhere, no discontinuity. Useful for measuring
/// conversion error (its exact value is known everywhere).
#[cfg_attr(not(feature = "instruments"), allow(dead_code))]
#[cfg_attr(feature = "instruments", visibility::make(pub))]
#[must_use]
pub(crate) fn smooth(d: Vec3) -> [f32; 3] {
    let d = d.normalize_or_zero();
    [
        0.6 + 0.4 * d.x + 0.2 * (3.0 * d.y).sin() * d.z,
        0.6 + 0.4 * d.y + 0.2 * (2.0 * d.z + d.x).cos(),
        0.6 + 0.4 * d.z + 0.1 * (4.0 * d.x * d.y).sin(),
    ]
}

/// [`smooth`] plus a sun 50 000 times as bright and 3° across, towards
/// (0.3, −0.5, 0.8): the test environment of a real HDRI's worst feature.
#[cfg_attr(not(feature = "instruments"), allow(dead_code))]
#[cfg_attr(feature = "instruments", visibility::make(pub))]
#[must_use]
pub(crate) fn sunny(d: Vec3) -> [f32; 3] {
    smooth_with_sun(d, 1.5, 50_000.0)
}

/// [`smooth`] plus a disc of `radius` degrees about (0.3, −0.5, 0.8) raised
/// by `value`.
#[cfg_attr(not(feature = "instruments"), allow(dead_code))]
fn smooth_with_sun(d: Vec3, radius: f32, value: f32) -> [f32; 3] {
    let s = Vec3::new(0.3, -0.5, 0.8).normalize();
    let base = smooth(d);
    if d.normalize().dot(s) > radius.to_radians().cos() {
        base.map(|v| v + value)
    } else {
        base
    }
}

/// [`smooth`] plus a sun 100 000 times as bright and 0.5° across (the
/// real sun's size), towards (0.3, −0.5, 0.8): a 4096 × 2048 latlong of it
/// has about 25 sun texels, the bake's benchmark of a map with a sun.
#[cfg_attr(not(feature = "instruments"), allow(dead_code))]
#[cfg_attr(feature = "instruments", visibility::make(pub))]
#[must_use]
pub(crate) fn small_sun(d: Vec3) -> [f32; 3] {
    smooth_with_sun(d, 0.25, 100_000.0)
}

/// Peak signal-to-noise ratio in dB of `a` against the reference `b` over
/// the texels where `mask` is true, with peak `peak`.
#[cfg_attr(not(feature = "instruments"), allow(dead_code))]
#[cfg_attr(feature = "instruments", visibility::make(pub))]
#[must_use]
pub(crate) fn psnr(a: &[[f32; 3]], b: &[[f32; 3]], mask: impl Fn(usize) -> bool, peak: f64) -> f64 {
    let mut se = 0.0f64;
    let mut n = 0u64;
    for (k, (p, q)) in a.iter().zip(b).enumerate() {
        if !mask(k) {
            continue;
        }
        for c in 0..3 {
            let e = f64::from(p[c]) - f64::from(q[c]);
            se += e * e;
        }
        n += 3;
    }
    if n == 0 || se == 0.0 {
        return f64::INFINITY;
    }
    10.0 * (peak * peak / (se / n as f64)).log10()
}

#[cfg(test)]
mod tests {
    use super::*;
    use envmap_core::AnyMapping;

    #[test]
    fn sphere_means_agree_across_representations() {
        // One environment in every representation: the solid-angle weighted
        // means agree; the per-texel means do not (a latlong over-counts its
        // poles): the former within 10⁻³ of each other, the latter spread
        // by more than 1 %.
        let mut means = Vec::new();
        // A fisheye under 360° holds part of the sphere, whose mean is its own.
        for m in AnyMapping::ALL.into_iter().filter(|m| m.covers_sphere()) {
            let repr = Representation::default_for(m);
            let (w, h) = repr.atlas.image_size_for_cell_width(192).unwrap();
            let s = fill(repr, w, h, smooth).unwrap().stats();
            means.push((m, s.sphere_mean_luminance, s.mean_luminance));
        }
        let reference = means[0].1;
        for &(m, sphere, _) in &means {
            assert!(
                (sphere - reference).abs() < 1e-3 * reference,
                "{m}: {sphere} vs {reference}"
            );
        }
        let per_texel: Vec<f64> = means.iter().map(|m| m.2).collect();
        let spread = per_texel.iter().copied().fold(0.0, f64::max)
            - per_texel.iter().copied().fold(f64::INFINITY, f64::min);
        assert!(
            spread > 1e-2 * reference,
            "per-texel means spread only {spread}"
        );
    }
}
