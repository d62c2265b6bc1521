// BC6H (unsigned): HDR texels in 4×4 blocks of 16 bytes, one byte per
// texel. Encoded with the `block_compression` crate's CPU encoder (a Rust
// port of Intel's ISPC BC6H kernel), decoded with `bcdec_rs` (a Rust port
// of bcdec), an implementation independent of the encoder, so that the
// error a file reports is what a GPU's decoder gives back.

use half::f16;

use crate::image::texel::{clamp_counted, Bc6hQuality, Clamped, TexelFormat, F16_MAX};
use crate::par::*;

/// Bytes per 4×4 block.
const BLOCK_BYTES: usize = 16;

/// The `block_compression` settings of `quality`.
fn settings(quality: Bc6hQuality) -> block_compression::BC6HSettings {
    use block_compression::BC6HSettings as S;
    match quality {
        Bc6hQuality::VeryFast => S::very_fast(),
        Bc6hQuality::Fast => S::fast(),
        Bc6hQuality::Basic => S::basic(),
        Bc6hQuality::Slow => S::slow(),
        Bc6hQuality::VerySlow => S::very_slow(),
    }
}

/// Encodes the `w`×`h` texels `pixels` (rows top-down) as BC6H blocks
/// into `out` (exactly `TexelFormat::Bc6h.image_bytes(w, h)` long), rows of blocks in parallel.
/// Each component is first clamped to [0, 65504] (binary16's range; BC6H
/// UF16 holds no more), NaN written as 0, and counted. A partial block at
/// the right or bottom edge repeats the last column or row, which a reader
/// never samples.
///
/// # Panics
///
/// If `pixels` is not `w × h` long or `out` has another length.
pub(crate) fn encode(
    pixels: &[[f32; 3]],
    (w, h): (u32, u32),
    quality: Bc6hQuality,
    out: &mut [u8],
) -> Clamped {
    assert_eq!(pixels.len(), w as usize * h as usize, "texel count");
    assert_eq!(
        out.len(),
        TexelFormat::Bc6h.image_bytes(w, h),
        "BC6H length"
    );
    let (w, h) = (w as usize, h as usize);
    let row_bytes = w.div_ceil(4) * BLOCK_BYTES;
    if row_bytes == 0 {
        return Clamped::default();
    }
    let settings = block_compression::CompressionVariant::BC6H(settings(quality));
    out.par_chunks_mut(row_bytes)
        .enumerate()
        .map(|(by, dst)| {
            // One row of blocks: four texel rows, each padded to a whole
            // number of blocks, as binary16 RGBA.
            let w4 = w.div_ceil(4) * 4;
            let mut c = Clamped::default();
            let mut padding = Clamped::default();
            let mut strip = vec![f16::ZERO; w4 * 4 * 4];
            for y in 0..4 {
                let sy = (by * 4 + y).min(h - 1);
                let row = &pixels[sy * w..(sy + 1) * w];
                for x in 0..w4 {
                    let t = row[x.min(w - 1)];
                    let at = (y * w4 + x) * 4;
                    for k in 0..3 {
                        // The padding of a partial block repeats texels already
                        // counted: it is clamped alike, counted apart.
                        let counted = if x < w && by * 4 + y < h {
                            &mut c
                        } else {
                            &mut padding
                        };
                        let v = clamp_counted(t[k], 0.0, F16_MAX, counted);
                        strip[at + k] = f16::from_f32(v);
                    }
                    strip[at + 3] = f16::ONE;
                }
            }
            block_compression::encode::compress_rgba16(
                settings,
                &strip,
                dst,
                w4 as u32,
                4,
                (w4 * 4) as u32,
            );
            if quality != Bc6hQuality::VerySlow {
                refine(&strip, w4, dst);
            }
            c
        })
        .sum()
}

/// A block whose relative squared error Σ(d − r)² / Σr² is above this
/// (about 3 % relative RMS) is encoded again at [`Bc6hQuality::VerySlow`].
const REFINE_ABOVE: f64 = 1e-3;

/// Encodes again, at [`Bc6hQuality::VerySlow`], each block of the row
/// `dst` (from `strip`, four rows of `w4` binary16 RGBA texels) that
/// decodes with an error above [`REFINE_ABOVE`], keeping whichever of the
/// two decodes closer. The blocks that need it are few (a sun's, an
/// edge's), so every setting gets the slowest search where it matters at
/// little cost.
fn refine(strip: &[f16], w4: usize, dst: &mut [u8]) {
    let very_slow = block_compression::CompressionVariant::BC6H(settings(Bc6hQuality::VerySlow));
    for (bx, block) in dst.chunks_exact_mut(BLOCK_BYTES).enumerate() {
        let mut texels = [f16::ZERO; 64];
        for y in 0..4 {
            let at = (y * w4 + bx * 4) * 4;
            texels[16 * y..16 * y + 16].copy_from_slice(&strip[at..at + 16]);
        }
        let error = |b: &[u8]| {
            let mut px = [0.0f32; 48];
            bcdec_rs::bc6h_float(b, &mut px, 12, false);
            let (mut num, mut den) = (0.0f64, 0.0f64);
            for (i, d) in px.iter().enumerate() {
                let r = f64::from(texels[(i / 3) * 4 + i % 3].to_f32());
                num += (f64::from(*d) - r).powi(2);
                den += r * r;
            }
            num / den.max(f64::MIN_POSITIVE)
        };
        let before = error(block);
        if before <= REFINE_ABOVE {
            continue;
        }
        let mut again = [0u8; BLOCK_BYTES];
        block_compression::encode::compress_rgba16(very_slow, &texels, &mut again, 4, 4, 16);
        if error(&again) < before {
            block.copy_from_slice(&again);
        }
    }
}

/// Decodes the BC6H blocks `bytes` of a `w`×`h` image into its texels
/// (rows top-down; the padding of partial blocks dropped), with `bcdec_rs`.
/// Missing blocks decode as black.
#[must_use]
pub(crate) fn decode(bytes: &[u8], (w, h): (u32, u32)) -> Vec<[f32; 3]> {
    let (w, h) = (w as usize, h as usize);
    let mut out = vec![[0.0f32; 3]; w * h];
    let bw = w.div_ceil(4);
    if bw == 0 {
        return out;
    }
    out.par_chunks_mut(4 * w)
        .enumerate()
        .for_each(|(by, rows)| {
            let mut px = [0.0f32; 48];
            for bx in 0..bw {
                let at = (by * bw + bx) * BLOCK_BYTES;
                let Some(block) = bytes.get(at..at + BLOCK_BYTES) else {
                    continue;
                };
                bcdec_rs::bc6h_float(block, &mut px, 12, false);
                for (y, row) in rows.chunks_mut(w).enumerate() {
                    for x in 0..4 {
                        if let Some(t) = row.get_mut(bx * 4 + x) {
                            let k = y * 12 + x * 3;
                            *t = [px[k], px[k + 1], px[k + 2]];
                        }
                    }
                }
            }
        });
    out
}
