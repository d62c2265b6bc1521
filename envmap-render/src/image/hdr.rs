//! Radiance RGBE (`.hdr`): linear floating point with a shared 8-bit
//! exponent, read and written with the `image` crate (within RGBE
//! precision, about 1 %).

use std::io::Write;
use std::path::Path;

use ::image::DynamicImage;

use crate::error::Result;
use crate::image::atomic::TempWriter;
use crate::image::envimage::RgbImage;
use crate::image::format::{Codec, Contents, FileFormat, Source};
use crate::image::io::{
    decode_with_image, encode_error, expand, image_dimensions, SaveOptions, SourceFormat, View,
};

/// Radiance's codec.
pub(crate) struct Hdr;

impl Codec for Hdr {
    fn read(&self, path: &Path, src: Source<'_>, max_texels: u64) -> Result<Contents> {
        read(path, src, max_texels).map(|(rgb, source)| Contents::Image(rgb, source))
    }

    fn dimensions(&self, path: &Path, src: Source<'_>) -> Result<(u32, u32)> {
        image_dimensions(path, src, FileFormat::Hdr)
    }

    fn write_image(
        &self,
        path: &Path,
        view: View<'_>,
        _opts: &SaveOptions,
        out: &mut TempWriter<'_>,
    ) -> Result<()> {
        encode(path, view, out)
    }
}

/// Reads a Radiance file as linear RGB; refuses images above `max_texels`
/// before allocating their pixels.
fn read(path: &Path, file: Source<'_>, max_texels: u64) -> Result<(RgbImage, SourceFormat)> {
    let format = FileFormat::Hdr;
    let decoded = decode_with_image(path, file, format, max_texels)?;
    let (width, height) = (decoded.width(), decoded.height());
    let lin = |v: f32| v;
    let pixels = match decoded {
        // Float RGB (what the HDR decoder gives): the decoder's buffer
        // becomes the texels as it is, so loading needs no second copy of
        // the image.
        DynamicImage::ImageRgb32F(b) => {
            let raw = b.into_raw();
            bytemuck::allocation::try_cast_vec::<f32, [f32; 3]>(raw)
                .unwrap_or_else(|(_, raw)| expand(&raw, 3, lin))
        }
        DynamicImage::ImageRgba32F(b) => expand(b.as_raw(), 4, lin),
        other => expand(other.to_rgb32f().as_raw(), 3, lin),
    };
    let rgb = RgbImage {
        width,
        height,
        pixels,
    };
    let source = SourceFormat {
        format,
        pixel_format: "RGBE (shared 8-bit exponent), linear".to_owned(),
        tags: Vec::new(),
    };
    Ok((rgb, source))
}

/// Writes `view` as a Radiance file; NaN and negative values become 0 (RGBE
/// holds non-negative finite values only).
fn encode<W: Write>(path: &Path, view: View<'_>, out: &mut W) -> Result<()> {
    let px: Vec<::image::Rgb<f32>> = view
        .pixels
        .iter()
        .map(|p| {
            ::image::Rgb(p.map(|c| {
                if c.is_nan() {
                    0.0
                } else {
                    c.clamp(0.0, f32::MAX)
                }
            }))
        })
        .collect();
    ::image::codecs::hdr::HdrEncoder::new(out)
        .encode(&px, view.width as usize, view.height as usize)
        .map_err(|e| encode_error(path, FileFormat::Hdr, e))
}
