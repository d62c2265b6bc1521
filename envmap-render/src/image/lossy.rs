//! What a lossy texel format (BC6H, RGBD) lost: each level's decoded
//! texels measured against the texels they were encoded from.

use crate::image::envimage::RgbImage;
use crate::image::texture::Texture;

/// How far one level's decoded texels are from the texels they were
/// encoded from ([`measure_level`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct LevelError {
    /// Relative RMS: √(Σ (d − r)²) / √(Σ r²) over every component.
    pub(crate) rel_rms: f64,
    /// Log-space RMSE: √(mean of (ln(1 + d) − ln(1 + r))²) over every
    /// component (the measure of GPURealTimeBC6H's tables).
    pub(crate) log_rmse: f64,
    /// The worst texel's relative error: its largest channel difference
    /// |d − r| over its largest reference channel (at least 2⁻¹⁴, the
    /// smallest normal binary16).
    pub(crate) worst: f64,
    /// Where the worst texel is: face (0 for a 2D texture), column, row.
    pub(crate) worst_at: (usize, u32, u32),
    /// The worst texel's reference value.
    pub(crate) worst_value: [f32; 3],
}

impl LevelError {
    /// One line: `rel. RMS 1.23 %, log RMSE 0.0042, worst 8.1 % at face 2
    /// (31, 7) of (0.52, 0.61, 0.70)`.
    #[cfg_attr(not(feature = "ktx2"), allow(dead_code))]
    pub(crate) fn describe(&self) -> String {
        let [r, g, b] = self.worst_value;
        let (f, x, y) = self.worst_at;
        format!(
            "rel. RMS {:.3} %, log RMSE {:.5}, worst {:.2} % at face {f} ({x}, {y}) of ({r}, {g}, {b})",
            100.0 * self.rel_rms,
            self.log_rmse,
            100.0 * self.worst
        )
    }
}

/// The error of one level's `decoded` faces against its `reference` faces
/// (the reference clamped to [0, `max`] first, the most the file holds, as
/// its packing clamps; NaN as 0), texel by texel.
#[must_use]
pub(crate) fn measure_level(decoded: &[RgbImage], reference: &[RgbImage], max: f32) -> LevelError {
    let (mut num, mut den, mut log, mut n) = (0.0f64, 0.0f64, 0.0f64, 0usize);
    let mut e = LevelError::default();
    let floor = f64::from(2f32.powi(-14));
    for (face, (dimg, rimg)) in decoded.iter().zip(reference).enumerate() {
        let w = rimg.width.max(1) as usize;
        for (at, (d, r)) in dimg.pixels.iter().zip(&rimg.pixels).enumerate() {
            let (mut diff, mut top) = (0.0f64, 0.0f64);
            let rc = r.map(|v| if v.is_nan() { 0.0 } else { v.clamp(0.0, max) });
            for k in 0..3 {
                let (d, r) = (f64::from(d[k]), f64::from(rc[k]));
                num += (d - r) * (d - r);
                den += r * r;
                log += ((1.0 + d).ln() - (1.0 + r).ln()).powi(2);
                n += 1;
                diff = diff.max((d - r).abs());
                top = top.max(r);
            }
            let rel = diff / top.max(floor);
            if rel > e.worst {
                e.worst = rel;
                e.worst_at = (face, (at % w) as u32, (at / w) as u32);
                e.worst_value = rc;
            }
        }
    }
    e.rel_rms = if den > 0.0 {
        (num / den).sqrt()
    } else {
        num.sqrt()
    };
    e.log_rmse = if n > 0 { (log / n as f64).sqrt() } else { 0.0 };
    e
}

/// Every level's error: `decoded` (a texture read back from the bytes
/// written) against `reference` (the texture they were written from, by a
/// format holding up to `max`).
#[must_use]
pub(crate) fn measure(decoded: &Texture, reference: &Texture, max: f32) -> Vec<LevelError> {
    decoded
        .levels()
        .iter()
        .zip(reference.levels())
        .map(|(d, r)| measure_level(d, r, max))
        .collect()
}
