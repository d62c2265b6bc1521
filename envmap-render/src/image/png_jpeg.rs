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

use crate::error::{Error, Result};
use crate::image::atomic::TempWriter;
use crate::image::envimage::RgbImage;
use crate::image::format::{Codec, Contents, FileFormat, Source};
use crate::image::io::{
    decode_with_image, encode_error, expand, image_dimensions, SaveOptions, SourceFormat, View,
};
use crate::image::metadata;
use crate::image::srgb::{linear_to_srgb8, srgb16_lut, srgb8_lut};

/// The PNG or JPEG codec (one value per format).
pub(crate) struct PngJpeg(FileFormat);

/// PNG's codec.
pub(crate) const PNG: PngJpeg = PngJpeg(FileFormat::Png);
/// JPEG's codec.
pub(crate) const JPEG: PngJpeg = PngJpeg(FileFormat::Jpeg);

impl Codec for PngJpeg {
    fn read(&self, path: &Path, src: Source<'_>, max_texels: u64) -> Result<Contents> {
        read(path, src, self.0, max_texels).map(|(rgb, source)| Contents::Image(rgb, source))
    }

    fn dimensions(&self, path: &Path, src: Source<'_>) -> Result<(u32, u32)> {
        image_dimensions(path, src, self.0)
    }

    fn write_image(
        &self,
        path: &Path,
        view: View<'_>,
        opts: &SaveOptions,
        out: &mut TempWriter<'_>,
    ) -> Result<()> {
        encode(path, self.0, view, opts.exposure, out)
    }
}

/// Reads a PNG or JPEG file as linear RGB; refuses images above
/// `max_texels` before allocating their pixels.
fn read(
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
            tags: if format == FileFormat::Png {
                png_tags(path)
            } else {
                Vec::new()
            },
        },
    ))
}

/// Writes `view` as 8-bit sRGB PNG or JPEG after scaling by 2^`exposure`.
/// A PNG also gets its tags, description and envmap's name as `tEXt`
/// chunks (`Description`, `Software`), written with the `png` crate at the
/// compression and filter the `image` crate's encoder uses by default.
fn encode<W: Write>(
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
    if format == FileFormat::Jpeg {
        let color = ::image::ExtendedColorType::Rgb8;
        return ::image::codecs::jpeg::JpegEncoder::new_with_quality(out, 95)
            .write_image(&bytes, view.width, view.height, color)
            .map_err(|e| encode_error(path, format, e));
    }
    let png_err = |e: png::EncodingError| match e {
        png::EncodingError::IoError(io) => Error::write(path, io),
        other => Error::Encode {
            path: path.to_path_buf(),
            format: format.name(),
            message: other.to_string(),
        },
    };
    let mut enc = png::Encoder::new(out, view.width, view.height);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    enc.set_compression(png::Compression::Balanced);
    enc.set_filter(png::Filter::Adaptive);
    let mut text = vec![("Software".to_owned(), metadata::software())];
    if !view.description.is_empty() {
        text.push(("Description".to_owned(), view.description.to_owned()));
    }
    text.extend(view.tags.iter().cloned());
    for (k, v) in text {
        enc.add_text_chunk(k, metadata::ascii(&v))
            .map_err(png_err)?;
    }
    let mut writer = enc.write_header().map_err(png_err)?;
    writer.write_image_data(&bytes).map_err(png_err)?;
    writer.finish().map_err(png_err)
}

/// The `envmap.*` text chunks before a PNG's image data (empty for any
/// file that cannot be read as PNG: the decoder proper reports that).
pub(super) fn png_tags(path: &Path) -> Vec<(String, String)> {
    let Ok(file) = std::fs::File::open(path) else {
        return Vec::new();
    };
    let mut decoder = png::Decoder::new(std::io::BufReader::new(file));
    decoder.set_ignore_text_chunk(false);
    let Ok(reader) = decoder.read_info() else {
        return Vec::new();
    };
    let info = reader.info();
    let mut t: Vec<(String, String)> = info
        .uncompressed_latin1_text
        .iter()
        .map(|c| (c.keyword.clone(), c.text.clone()))
        .chain(
            info.utf8_text
                .iter()
                .filter_map(|c| Some((c.keyword.clone(), c.get_text().ok()?))),
        )
        .filter(|(k, _)| k.starts_with("envmap."))
        .collect();
    t.sort();
    t
}
