//! OpenEXR (`.exr`): read the R, G, B channels (any of f16, f32, u32) of the
//! first layer that has them, alpha and other channels ignored; write f32 RGB
//! (bit for bit) or f16, with the `exr` crate.

use std::io::{BufReader, Seek, SeekFrom, Write};
use std::path::Path;

use crate::error::{Error, Result};
use crate::image::envimage::{check_size, RgbImage};
use crate::image::io::{decode_error, ExrPrecision, FileFormat, Source, SourceFormat, View};
use crate::image::metadata;

fn exr_has(header: &::exr::meta::header::Header, name: &str) -> bool {
    header.channels.list.iter().any(|c| c.name.eq(name))
}

/// The first layer (header) with R, G and B channels.
pub(super) fn rgb_header<'m>(
    path: &Path,
    meta: &'m ::exr::meta::MetaData,
) -> Result<&'m ::exr::meta::header::Header> {
    meta.headers
        .iter()
        .find(|h| exr_has(h, "R") && exr_has(h, "G") && exr_has(h, "B"))
        .ok_or_else(|| {
            let mut found: Vec<String> = Vec::new();
            for h in &meta.headers {
                for c in &h.channels.list {
                    found.push(c.name.to_string());
                }
            }
            Error::MissingChannels {
                path: path.to_path_buf(),
                found: if found.is_empty() {
                    "none".to_owned()
                } else {
                    found.join(", ")
                },
            }
        })
}

pub(super) fn exr_size(path: &Path, header: &::exr::meta::header::Header) -> Result<(u32, u32)> {
    let size = header.layer_size;
    match (u32::try_from(size.width()), u32::try_from(size.height())) {
        (Ok(w), Ok(h)) if w > 0 && h > 0 => Ok((w, h)),
        _ => Err(decode_error(
            path,
            FileFormat::Exr,
            format!("the layer is {}×{}", size.width(), size.height()),
        )),
    }
}

fn sample_name(t: ::exr::meta::attribute::SampleType) -> &'static str {
    match t {
        ::exr::meta::attribute::SampleType::F16 => "f16",
        ::exr::meta::attribute::SampleType::F32 => "f32",
        ::exr::meta::attribute::SampleType::U32 => "u32",
    }
}

pub(super) fn read(
    path: &Path,
    file: Source<'_>,
    max_texels: u64,
) -> Result<(RgbImage, SourceFormat)> {
    use ::exr::prelude::{ReadChannels, ReadLayers, ReadSpecificChannel};

    let format = FileFormat::Exr;
    let err = |e: ::exr::error::Error| decode_error(path, format, e);
    let mut reader = BufReader::new(file);
    let meta = ::exr::meta::MetaData::read_from_buffered(&mut reader, false).map_err(err)?;
    let header = rgb_header(path, &meta)?;
    if header.deep {
        return Err(decode_error(path, format, "deep data is not supported"));
    }
    let (width, height) = exr_size(path, header)?;
    let tags = tags(header);
    let n = check_size(width, height, 1, max_texels).map_err(|e| e.in_file(path))?;

    let channels: Vec<String> = header
        .channels
        .list
        .iter()
        .map(|c| c.name.to_string())
        .collect();
    let types: Vec<&str> = ["R", "G", "B"]
        .iter()
        .filter_map(|n| header.channels.list.iter().find(|c| c.name.eq(n)))
        .map(|c| sample_name(c.sample_type))
        .collect();
    let sample = if types.iter().all(|t| *t == types[0]) {
        types[0].to_owned()
    } else {
        types.join("/")
    };
    let others: Vec<&str> = channels
        .iter()
        .map(String::as_str)
        .filter(|c| !matches!(*c, "R" | "G" | "B"))
        .collect();
    let pixel_format = if others.is_empty() {
        format!("{sample} RGB")
    } else if others == ["A"] {
        format!("{sample} RGBA (alpha dropped)")
    } else {
        format!(
            "{sample} RGB (other channels ignored: {})",
            others.join(", ")
        )
    };

    reader
        .seek(SeekFrom::Start(0))
        .map_err(|e| Error::read(path, e))?;
    let image = ::exr::prelude::read()
        .no_deep_data()
        .largest_resolution_level()
        .specific_channels()
        .required("R")
        .required("G")
        .required("B")
        .collect_pixels(
            move |size, _| (size.width(), vec![[0.0f32; 3]; n.min(size.area())]),
            |store: &mut (usize, Vec<[f32; 3]>), pos, (r, g, b): (f32, f32, f32)| {
                let i = pos.y() * store.0 + pos.x();
                if let Some(p) = store.1.get_mut(i) {
                    *p = [r, g, b];
                }
            },
        )
        .first_valid_layer()
        .all_attributes()
        .from_buffered(reader)
        .map_err(err)?;
    let layer = image.layer_data;
    let (w, h) = (layer.size.width(), layer.size.height());
    if (w, h) != (width as usize, height as usize) {
        return Err(decode_error(
            path,
            format,
            format!("the layer read is {w}×{h}, its header said {width}×{height}"),
        ));
    }
    Ok((
        RgbImage {
            width,
            height,
            pixels: layer.channel_data.pixels.1,
        },
        SourceFormat {
            format,
            pixel_format,
            tags,
        },
    ))
}

/// How envmap writes OpenEXR: run-length compressed scan lines in
/// increasing order. Tiled files with chunks in any order (the `exr`
/// crate's `FAST_LOSSLESS`) are read wrongly by some readers (Filament's
/// cmgen shifts their rows); scan lines in order are what every reader
/// handles, and RLE keeps the writing as fast.
const ENCODING: ::exr::prelude::Encoding = ::exr::prelude::Encoding {
    compression: ::exr::prelude::Compression::RLE,
    blocks: ::exr::prelude::Blocks::ScanLines,
    line_order: ::exr::prelude::LineOrder::Increasing,
};

/// Writes `view` as an OpenEXR file of RGB channels in `precision`, with
/// its tags as text attributes of the layer, its description as the
/// `comments` attribute and envmap as the `software` attribute (text made
/// ASCII, as EXR text attributes hold Latin-1).
pub(super) fn encode<W: Write + Seek>(
    path: &Path,
    view: View<'_>,
    precision: ExrPrecision,
    out: &mut W,
) -> Result<()> {
    use ::exr::meta::attribute::{AttributeValue, Text};
    use ::exr::prelude::{f16, Image, SpecificChannels, Vec2, WritableImage};
    let w = view.width as usize;
    let size = (w, view.height as usize);
    let px = view.pixels;
    let text = |s: &str| Text::new_or_none(metadata::ascii(s));
    let describe = |attributes: &mut ::exr::meta::header::LayerAttributes| {
        attributes.software_name = text(&metadata::software());
        if !view.description.is_empty() {
            attributes.comments = text(view.description);
        }
        for (k, v) in view.tags {
            if let (Some(k), Some(v)) = (text(k), text(v)) {
                attributes.other.insert(k, AttributeValue::Text(v));
            }
        }
    };
    let result = match precision {
        ExrPrecision::F32 => {
            let mut image = Image::from_encoded_channels(
                size,
                ENCODING,
                SpecificChannels::rgb(|Vec2(x, y): Vec2<usize>| {
                    let p = px[y * w + x];
                    (p[0], p[1], p[2])
                }),
            );
            describe(&mut image.layer_data.attributes);
            image.write().to_buffered(&mut *out)
        }
        ExrPrecision::F16 => {
            let mut image = Image::from_encoded_channels(
                size,
                ENCODING,
                SpecificChannels::rgb(|Vec2(x, y): Vec2<usize>| {
                    let p = px[y * w + x];
                    (
                        f16::from_f32(p[0]),
                        f16::from_f32(p[1]),
                        f16::from_f32(p[2]),
                    )
                }),
            );
            describe(&mut image.layer_data.attributes);
            image.write().to_buffered(&mut *out)
        }
    };
    result.map_err(|e| match e {
        ::exr::error::Error::Io(io) => Error::write(path, io),
        other => Error::Encode {
            path: path.to_path_buf(),
            format: FileFormat::Exr.name(),
            message: other.to_string(),
        },
    })
}

/// The `envmap.*` text attributes of a layer.
pub(super) fn tags(header: &::exr::meta::header::Header) -> Vec<(String, String)> {
    use ::exr::meta::attribute::AttributeValue;
    let mut t: Vec<(String, String)> = header
        .own_attributes
        .other
        .iter()
        .filter_map(|(k, v)| match v {
            AttributeValue::Text(v) if k.to_string().starts_with("envmap.") => {
                Some((k.to_string(), v.to_string()))
            }
            _ => None,
        })
        .collect();
    t.sort();
    t
}
