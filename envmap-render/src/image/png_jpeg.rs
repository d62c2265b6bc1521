//! PNG (`.png`) and JPEG (`.jpg`, `.jpeg`), through the `image` crate.
//!
//! Read: PNG 8- or 16-bit grey, grey+alpha, RGB, RGBA; JPEG 8-bit grey or
//! RGB (CMYK converted); taken as sRGB and decoded to linear with the exact
//! sRGB EOTF ([`srgb_to_linear`](crate::image::srgb::srgb_to_linear)), alpha
//! dropped. Colour profiles and PNG gamma chunks are ignored. Write: 8-bit
//! sRGB RGB after exposure, clamped (JPEG at quality 95).

use std::io::Write;
use std::path::Path;

use ::image::{DynamicImage, ImageEncoder};

use crate::error::Result;
use crate::image::envimage::RgbImage;
use crate::image::io::{
    decode_with_image, encode_error, expand, FileFormat, Source, SourceFormat, View,
};
use crate::image::srgb::{linear_to_srgb8, srgb16_lut, srgb8_lut};

/// Reads a PNG or JPEG file as linear RGB; refuses images above
/// `max_texels` before allocating their pixels.
pub(super) fn read(
    path: &Path,
    file: Source<'_>,
    format: FileFormat,
    max_texels: u64,
) -> Result<(RgbImage, SourceFormat)> {
    let decoded = decode_with_image(path, file, format, max_texels)?;
    let (width, height) = (decoded.width(), decoded.height());
    let l8 = |v: u8| srgb8_lut()[usize::from(v)];
    let l16 = |v: u16| srgb16_lut()[usize::from(v)];
    let (pixels, desc) = match &decoded {
        DynamicImage::ImageLuma8(b) => (expand(b.as_raw(), 1, l8), "8-bit sRGB grey"),
        DynamicImage::ImageLumaA8(b) => (
            expand(b.as_raw(), 2, l8),
            "8-bit sRGB grey+alpha (alpha dropped)",
        ),
        DynamicImage::ImageRgb8(b) => (expand(b.as_raw(), 3, l8), "8-bit sRGB RGB"),
        DynamicImage::ImageRgba8(b) => {
            (expand(b.as_raw(), 4, l8), "8-bit sRGB RGBA (alpha dropped)")
        }
        DynamicImage::ImageLuma16(b) => (expand(b.as_raw(), 1, l16), "16-bit sRGB grey"),
        DynamicImage::ImageLumaA16(b) => (
            expand(b.as_raw(), 2, l16),
            "16-bit sRGB grey+alpha (alpha dropped)",
        ),
        DynamicImage::ImageRgb16(b) => (expand(b.as_raw(), 3, l16), "16-bit sRGB RGB"),
        DynamicImage::ImageRgba16(b) => (
            expand(b.as_raw(), 4, l16),
            "16-bit sRGB RGBA (alpha dropped)",
        ),
        other => (expand(other.to_rgb16().as_raw(), 3, l16), "sRGB RGB"),
    };
    Ok((
        RgbImage {
            width,
            height,
            pixels,
        },
        SourceFormat {
            format,
            pixel_format: desc.to_owned(),
        },
    ))
}

/// Writes `view` as 8-bit sRGB PNG or JPEG after scaling by 2^`exposure`.
pub(super) fn encode<W: Write>(
    path: &Path,
    format: FileFormat,
    view: View<'_>,
    exposure: f32,
    out: &mut W,
) -> Result<()> {
    let scale = exposure.exp2();
    let bytes: Vec<u8> = view
        .pixels
        .iter()
        .flat_map(|p| p.map(|c| linear_to_srgb8(c * scale)))
        .collect();
    let color = ::image::ExtendedColorType::Rgb8;
    let result = if format == FileFormat::Png {
        ::image::codecs::png::PngEncoder::new(out).write_image(
            &bytes,
            view.width,
            view.height,
            color,
        )
    } else {
        ::image::codecs::jpeg::JpegEncoder::new_with_quality(out, 95).write_image(
            &bytes,
            view.width,
            view.height,
            color,
        )
    };
    result.map_err(|e| encode_error(path, format, e))
}
