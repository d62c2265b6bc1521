//! OpenEXR (`.exr`): read the R, G, B channels (any of f16, f32, u32) of the
//! first layer that has them, alpha and other channels ignored; write f32 RGB
//! (bit for bit) or f16, with the `exr` crate.

use std::io::{BufReader, Seek, SeekFrom, Write};
use std::path::Path;

use crate::error::{Error, Result};
use crate::image::atomic::TempWriter;
use crate::image::envimage::{check_size, RgbImage};
use crate::image::format::{decode_error, Codec, Contents, FileFormat, Source};
use crate::image::io::{ExrCompression, ExrPrecision, SaveOptions, SourceFormat, View};

/// OpenEXR's codec.
pub(crate) struct Exr;

impl Codec for Exr {
    fn read(&self, path: &Path, src: Source<'_>, max_texels: u64) -> Result<Contents> {
        read(path, src, max_texels).map(|(rgb, source)| Contents::Image(rgb, source))
    }

    fn dimensions(&self, path: &Path, src: Source<'_>) -> Result<(u32, u32)> {
        let meta = ::exr::meta::MetaData::read_from_buffered(BufReader::new(src), false)
            .map_err(|e| decode_error(path, FileFormat::Exr, e))?;
        exr_size(path, rgb_header(path, &meta)?)
    }

    fn write_image(
        &self,
        path: &Path,
        view: View<'_>,
        opts: &SaveOptions,
        out: &mut TempWriter<'_>,
    ) -> Result<()> {
        encode(path, view, opts.exr_precision, opts.exr_compression, out)
    }
}
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

    // The pixels, block by block: chunks are read from the file in order,
    // a batch at a time, then decompressed and turned into RGB rows in
    // parallel (each block into rows of its own), and copied into place.
    let layer = meta
        .headers
        .iter()
        .position(|h| std::ptr::eq(h, header))
        .unwrap_or(0);
    let rgb = rgb_channels(path, header)?;
    let bytes_per_pixel = header.channels.bytes_per_pixel;
    let mut pixels = vec![[0.0f32; 3]; n];
    reader
        .seek(SeekFrom::Start(0))
        .map_err(|e| Error::read(path, e))?;
    use ::exr::block::reader::ChunksReader;
    let mut chunks = ::exr::block::read(reader, false)
        .map_err(err)?
        .filter_chunks(false, move |_, tile, block| {
            block.layer == layer && tile.is_largest_resolution_level()
        })
        .map_err(err)?;
    let meta = chunks.meta_data().clone();
    let header = &meta.headers[layer];
    let (w, h) = (width as usize, height as usize);
    // Reading the next batch from the file overlaps decoding this one.
    let mut read_batch = || -> Result<Vec<Placed>> {
        let mut placed = Vec::new();
        let mut bytes = 0usize;
        while bytes < BATCH_BYTES {
            let Some(chunk) = chunks.next() else { break };
            let chunk = chunk.map_err(err)?;
            bytes += chunk_bytes(&chunk).max(1);
            placed.push(place(path, header, chunk, (w, h))?);
        }
        Ok(placed)
    };
    let mut next = read_batch()?;
    while !next.is_empty() {
        let batch = std::mem::take(&mut next);
        let (decoded, read) = crate::par::join(
            || {
                decode_batch(
                    path,
                    &meta,
                    layer,
                    &rgb,
                    bytes_per_pixel,
                    batch,
                    &mut pixels,
                    w,
                )
            },
            &mut read_batch,
        );
        decoded?;
        next = read?;
    }
    Ok((
        RgbImage {
            width,
            height,
            pixels,
        },
        SourceFormat {
            format,
            pixel_format,
            tags,
        },
    ))
}

/// Where a block goes in its layer: (x, y, width, height).
type Rect = (usize, usize, usize, usize);

/// A chunk and where its block goes.
type Placed = (Rect, ::exr::block::chunk::Chunk);

/// Where `chunk`'s block goes in the `w` × `h` layer, from the chunk alone
/// (before decompressing it); an error if outside.
fn place(
    path: &Path,
    header: &::exr::meta::header::Header,
    chunk: ::exr::block::chunk::Chunk,
    (w, h): (usize, usize),
) -> Result<Placed> {
    let err = |e: ::exr::error::Error| decode_error(path, FileFormat::Exr, e);
    let tile = header
        .get_block_data_indices(&chunk.compressed_block)
        .map_err(err)?;
    let b = header
        .get_absolute_block_pixel_coordinates(tile)
        .map_err(err)?;
    let (x0, y0) = (
        usize::try_from(b.position.x()).unwrap_or(usize::MAX),
        usize::try_from(b.position.y()).unwrap_or(usize::MAX),
    );
    let (bw, bh) = (b.size.width(), b.size.height());
    if x0.checked_add(bw).is_none_or(|r| r > w) || y0.checked_add(bh).is_none_or(|b| b > h) {
        return Err(decode_error(
            path,
            FileFormat::Exr,
            format!("a block at ({x0}, {y0}) of {bw}×{bh} lies outside the {w}×{h} layer"),
        ));
    }
    Ok(((x0, y0, bw, bh), chunk))
}

/// Decompresses a batch of blocks and puts their pixels into `pixels` (rows
/// of `w`), in parallel: scan-line blocks (whole rows) straight into their
/// own rows, tiles each into rows of its own and then copied.
#[allow(clippy::too_many_arguments)]
fn decode_batch(
    path: &Path,
    meta: &::exr::meta::MetaData,
    layer: usize,
    rgb: &[(usize, ::exr::meta::attribute::SampleType); 3],
    bytes_per_pixel: usize,
    mut placed: Vec<Placed>,
    pixels: &mut [[f32; 3]],
    w: usize,
) -> Result<()> {
    use crate::par::*;
    let header = &meta.headers[layer];
    let decode = |chunk, out: &mut [[f32; 3]]| -> Result<()> {
        let block = ::exr::block::UncompressedBlock::decompress_chunk(chunk, meta, false)
            .map_err(|e| decode_error(path, FileFormat::Exr, e))?;
        block_rgb(path, header, &block, rgb, bytes_per_pixel, out)
    };
    placed.sort_by_key(|((x0, y0, ..), _)| (*y0, *x0));
    if placed
        .iter()
        .all(|((x0, _, bw, _), _)| *x0 == 0 && *bw == w)
    {
        let mut jobs = Vec::with_capacity(placed.len());
        let mut rest: &mut [[f32; 3]] = pixels;
        let mut at = 0usize;
        for ((_, y0, _, bh), chunk) in placed {
            if y0 < at {
                return Err(decode_error(
                    path,
                    FileFormat::Exr,
                    format!("two blocks hold row {y0}"),
                ));
            }
            let (_, tail) = std::mem::take(&mut rest).split_at_mut((y0 - at) * w);
            let (rows, tail) = tail.split_at_mut(bh * w);
            rest = tail;
            at = y0 + bh;
            jobs.push((chunk, rows));
        }
        return jobs
            .into_par_iter()
            .map(|(chunk, rows)| decode(chunk, rows))
            .collect::<Result<Vec<()>>>()
            .map(drop);
    }
    let blocks: Vec<Result<(Rect, Vec<[f32; 3]>)>> = placed
        .into_par_iter()
        .map(|(at, chunk)| {
            let mut px = vec![[0.0f32; 3]; at.2 * at.3];
            decode(chunk, &mut px).map(|()| (at, px))
        })
        .collect();
    for block in blocks {
        let ((x0, y0, bw, _), px) = block?;
        for (row, src) in px.chunks_exact(bw.max(1)).enumerate() {
            let start = (y0 + row) * w + x0;
            if let Some(dst) = pixels.get_mut(start..start + bw) {
                dst.copy_from_slice(src);
            }
        }
    }
    Ok(())
}

/// Compressed chunks read before a batch is decompressed (by their
/// decompressed size): enough to keep every thread busy, little enough
/// not to hold much of the file twice.
const BATCH_BYTES: usize = 4 << 20;

/// A chunk's size once decompressed, roughly (its pixel count is not in
/// the chunk; its compressed size bounds the work well enough).
fn chunk_bytes(chunk: &::exr::block::chunk::Chunk) -> usize {
    use ::exr::block::chunk::CompressedBlock as B;
    match &chunk.compressed_block {
        B::ScanLine(b) => b.compressed_pixels_le.len(),
        B::Tile(b) => b.compressed_pixels_le.len(),
        // Deep layers are refused before their chunks are read.
        B::DeepScanLine(_) | B::DeepTile(_) => 0,
    }
}

/// Where R, G and B are in a layer's (sorted) channel list, with their
/// sample types.
fn rgb_channels(
    path: &Path,
    header: &::exr::meta::header::Header,
) -> Result<[(usize, ::exr::meta::attribute::SampleType); 3]> {
    let mut out = [(0, ::exr::meta::attribute::SampleType::F32); 3];
    for (k, name) in ["R", "G", "B"].into_iter().enumerate() {
        let (i, c) = header
            .channels
            .list
            .iter()
            .enumerate()
            .find(|(_, c)| c.name.eq(name))
            .ok_or_else(|| decode_error(path, FileFormat::Exr, format!("no {name} channel")))?;
        if c.sampling.x() != 1 || c.sampling.y() != 1 {
            return Err(decode_error(
                path,
                FileFormat::Exr,
                format!("channel {name} is subsampled; only full-resolution channels are read"),
            ));
        }
        out[k] = (i, c.sample_type);
    }
    Ok(out)
}

/// One decompressed block's pixels into `px`, its RGB rows (the block's
/// width × its height), checked against its data's size.
fn block_rgb(
    path: &Path,
    header: &::exr::meta::header::Header,
    block: &::exr::block::UncompressedBlock,
    rgb: &[(usize, ::exr::meta::attribute::SampleType); 3],
    bytes_per_pixel: usize,
    px: &mut [[f32; 3]],
) -> Result<()> {
    use ::exr::meta::attribute::SampleType;
    let index = block.index;
    let (x0, y0) = (index.pixel_position.x(), index.pixel_position.y());
    let (bw, bh) = (index.pixel_size.width(), index.pixel_size.height());
    if px.len() != bw * bh || block.data.len() != bw * bh * bytes_per_pixel {
        return Err(decode_error(
            path,
            FileFormat::Exr,
            format!("the block at ({x0}, {y0}) of {bw}×{bh} does not hold its data"),
        ));
    }
    for (range, line) in ::exr::block::lines::LineIndex::lines_in_block(index, &header.channels) {
        let Some(k) = rgb.iter().position(|(c, _)| *c == line.channel) else {
            continue;
        };
        let sample = rgb[k].1;
        let (Some(bytes), Some(row)) = (
            block.data.get(range),
            px.get_mut((line.position.y() - y0) * bw..(line.position.y() - y0 + 1) * bw),
        ) else {
            continue;
        };
        match sample {
            SampleType::F32 => {
                for (p, b) in row.iter_mut().zip(bytes.chunks_exact(4)) {
                    p[k] = f32::from_ne_bytes([b[0], b[1], b[2], b[3]]);
                }
            }
            SampleType::F16 => {
                for (p, b) in row.iter_mut().zip(bytes.chunks_exact(2)) {
                    p[k] = ::exr::prelude::f16::from_ne_bytes([b[0], b[1]]).to_f32();
                }
            }
            SampleType::U32 => {
                for (p, b) in row.iter_mut().zip(bytes.chunks_exact(4)) {
                    p[k] = u32::from_ne_bytes([b[0], b[1], b[2], b[3]]) as f32;
                }
            }
        }
    }
    Ok(())
}

/// The codec of `compression` at `precision`. envmap writes scan lines in
/// increasing order: tiled files with chunks in any order (the `exr`
/// crate's `FAST_LOSSLESS`) are read wrongly by some readers (Filament's
/// cmgen shifts their rows); scan lines in order are what every reader
/// handles.
fn codec(compression: ExrCompression, precision: ExrPrecision) -> ::exr::prelude::Compression {
    use ::exr::prelude::Compression as C;
    match compression.resolve(precision) {
        ExrCompression::Auto | ExrCompression::None => C::Uncompressed,
        ExrCompression::Rle => C::RLE,
        ExrCompression::Zips => C::ZIP1,
        ExrCompression::Zip => C::ZIP16,
        ExrCompression::Piz => C::PIZ,
        ExrCompression::Pxr24 => C::PXR24,
        ExrCompression::B44 => C::B44,
        ExrCompression::B44a => C::B44A,
    }
}

/// Writes `view` as an OpenEXR file of RGB channels in `precision`,
/// compressed by `compression`, with its tags as text attributes of the
/// layer, its description as the `comments` attribute and envmap as the
/// `software` attribute (text made ASCII, as EXR text attributes hold
/// Latin-1).
///
/// The scan-line blocks are made from the pixels and compressed in
/// parallel, a batch at a time, and written in order as each batch is
/// done: what is held besides the image is one batch.
pub(super) fn encode<W: Write + Seek>(
    path: &Path,
    view: View<'_>,
    precision: ExrPrecision,
    compression: ExrCompression,
    out: &mut W,
) -> Result<()> {
    use ::exr::meta::attribute::SampleType;
    use ::exr::prelude::SmallVec;
    let (attributes, tags) = layer_attributes(view);
    let sample = match precision {
        ExrPrecision::F32 => SampleType::F32,
        ExrPrecision::F16 => SampleType::F16,
    };
    // `auto` in f32 with empty cells (a cube cross's corners): the file is
    // RLE, but only the blocks that cross an empty cell are compressed (to
    // a few bytes for the empty part); the rest are stored raw, as an RLE
    // file stores any block compression does not shrink (the OpenEXR
    // file layout: a chunk whose size is its pixels' is not compressed).
    let sparse = view
        .atlas
        .filter(|_| {
            compression == ExrCompression::Auto && precision == ExrPrecision::F32 && view.height > 0
        })
        .and_then(|a| EmptyCells::of(&a, view.height));
    let file_codec = if sparse.is_some() {
        ::exr::prelude::Compression::RLE
    } else {
        codec(compression, precision)
    };
    let header = layer_header(view, sample, file_codec, attributes);
    let reorder = TagOrder::of(&header, &tags);
    let start = out.stream_position().map_err(|e| Error::write(path, e))?;
    let mut headers = SmallVec::new();
    headers.push(header);
    let result = ::exr::block::write(&mut *out, headers, true, |meta, writer| {
        write_blocks(&meta, writer, view, sample, sparse)
    });
    result.map_err(|e| match e {
        ::exr::error::Error::Io(io) => Error::write(path, io),
        other => Error::Encode {
            path: path.to_path_buf(),
            format: FileFormat::Exr.name(),
            message: other.to_string(),
        },
    })?;
    if let Some(order) = reorder {
        order.write(start, out).map_err(|e| Error::write(path, e))?;
    }
    Ok(())
}

/// The layer's attributes (software, comments, the tags as text) and the
/// tags as written, in their order: a later tag of a name replaces an
/// earlier one's value, as the header's map does.
fn layer_attributes(
    view: View<'_>,
) -> (
    ::exr::meta::header::LayerAttributes,
    Vec<(::exr::meta::attribute::Text, ::exr::meta::attribute::Text)>,
) {
    use ::exr::meta::attribute::{AttributeValue, Text};
    use ::exr::meta::header::LayerAttributes;
    let text = |s: &str| Text::new_or_none(metadata::ascii(s));
    let mut attributes = LayerAttributes {
        software_name: text(&metadata::software()),
        ..LayerAttributes::default()
    };
    if !view.description.is_empty() {
        attributes.comments = text(view.description);
    }
    let mut tags: Vec<(Text, Text)> = Vec::new();
    for (k, v) in view.tags {
        if let (Some(k), Some(v)) = (text(k), text(v)) {
            match tags.iter_mut().find(|(name, _)| *name == k) {
                Some(tag) => tag.1 = v,
                None => tags.push((k, v)),
            }
        }
    }
    for (k, v) in &tags {
        attributes
            .other
            .insert(k.clone(), AttributeValue::Text(v.clone()));
    }
    (attributes, tags)
}

/// The header of `view`'s one layer: B, G and R channels of `sample`,
/// scan lines in increasing order, compressed by `compression`.
fn layer_header(
    view: View<'_>,
    sample: ::exr::meta::attribute::SampleType,
    compression: ::exr::prelude::Compression,
    attributes: ::exr::meta::header::LayerAttributes,
) -> ::exr::meta::header::Header {
    use ::exr::meta::attribute::{ChannelDescription, Text};
    use ::exr::meta::header::Header;
    use ::exr::prelude::SmallVec;
    let (w, h) = (view.width as usize, view.height as usize);
    let channels: SmallVec<[ChannelDescription; 5]> = ["B", "G", "R"]
        .into_iter()
        .map(|c| ChannelDescription::named(c, sample))
        .collect();
    Header::new(Text::from(""), (w, h), channels)
        .with_encoding(
            compression,
            ::exr::meta::BlockDescription::ScanLines,
            ::exr::meta::attribute::LineOrder::Increasing,
        )
        .with_attributes(attributes)
}

/// Writes every scan-line block of `view` in order, a batch of blocks at
/// a time, the blocks of a batch made and compressed in parallel.
fn write_blocks(
    meta: &::exr::meta::MetaData,
    writer: &mut impl ::exr::block::writer::ChunksWriter,
    view: View<'_>,
    sample: ::exr::meta::attribute::SampleType,
    sparse: Option<EmptyCells>,
) -> ::exr::error::UnitResult {
    let w = view.width as usize;
    let header = &meta.headers[0];
    // Each channel of the (sorted) list: which of R, G, B it is.
    let order: Vec<usize> = header
        .channels
        .list
        .iter()
        .map(|c| usize::from(c.name.eq("G")) + 2 * usize::from(c.name.eq("B")))
        .collect();
    let blocks: Vec<(usize, ::exr::block::BlockIndex)> =
        ::exr::block::enumerate_ordered_header_block_indices(&meta.headers).collect();
    let lines = blocks
        .first()
        .map_or(1, |(_, b)| b.pixel_size.height().max(1));
    let per_batch = (BATCH_BYTES / (lines * w * header.channels.bytes_per_pixel).max(1)).max(1);
    for batch in blocks.chunks(per_batch) {
        use crate::par::*;
        let chunks: Vec<::exr::error::Result<(usize, ::exr::block::chunk::Chunk)>> = batch
            .par_iter()
            .map(|&(i, index)| {
                block_chunk(&meta.headers, view, index, &order, sample, sparse).map(|c| (i, c))
            })
            .collect();
        for chunk in chunks {
            let (i, chunk) = chunk?;
            writer.write_chunk(i, chunk)?;
        }
    }
    Ok(())
}

/// The chunk of the block at `index`: its rows (from the pixels, or made
/// now by the view's stream) compressed, or stored raw when `sparse` says
/// the block crosses no empty cell.
fn block_chunk(
    headers: &[::exr::meta::header::Header],
    view: View<'_>,
    index: ::exr::block::BlockIndex,
    order: &[usize],
    sample: ::exr::meta::attribute::SampleType,
    sparse: Option<EmptyCells>,
) -> ::exr::error::Result<::exr::block::chunk::Chunk> {
    let w = view.width as usize;
    let (y0, bh) = (index.pixel_position.y(), index.pixel_size.height());
    let data = match view.stream {
        None => block_bytes(view.pixels, w, index, order, sample),
        Some(stream) => {
            // The block's rows made now, and encoded.
            let mut rows = vec![[0.0f32; 3]; bh * w];
            stream.rows(y0 as u32, &mut rows);
            let at = ::exr::block::BlockIndex {
                pixel_position: ::exr::math::Vec2(0, 0),
                ..index
            };
            block_bytes(&rows, w, at, order, sample)
        }
    };
    if sparse.is_some_and(|e| !e.crossed(y0, bh)) {
        return Ok(raw_chunk(y0, data));
    }
    ::exr::block::UncompressedBlock { index, data }.compress_to_chunk(headers)
}

/// The place of the tags' attributes in an OpenEXR header, to write them
/// in the tags' order.
///
/// The `exr` crate holds a header's other attributes in a `HashMap` and
/// writes them last, in the map's order, which changes from one map to
/// the next: the same image would give different bytes on each run. The
/// attributes take the same bytes in any order, so the run of them in the
/// written header is overwritten with the same attributes in order.
struct TagOrder {
    /// Where the run of attributes starts, from the start of the header.
    at: u64,
    /// The attributes in the tags' order.
    bytes: Vec<u8>,
}

impl TagOrder {
    /// The attributes of `tags` in order and where `header` writes them;
    /// `None` when there is nothing to reorder, or when the header's bytes
    /// do not end with exactly these attributes (then the file is written
    /// as the `exr` crate orders it).
    fn of(
        header: &::exr::meta::header::Header,
        tags: &[(::exr::meta::attribute::Text, ::exr::meta::attribute::Text)],
    ) -> Option<Self> {
        use ::exr::meta::attribute::{write, AttributeValue};
        if tags.len() < 2 {
            return None;
        }
        let encoded: Vec<Vec<u8>> = tags
            .iter()
            .map(|(k, v)| {
                let mut b = Vec::new();
                write(k.as_slice(), &AttributeValue::Text(v.clone()), &mut b).ok()?;
                Some(b)
            })
            .collect::<Option<_>>()?;
        let mut written = Vec::new();
        header.write(&mut written).ok()?;
        let len: usize = encoded.iter().map(Vec::len).sum();
        // The header's attributes end with one zero byte.
        let end = written.len().checked_sub(1)?;
        let run = &written[end.checked_sub(len)?..end];
        // The run must be these attributes, each once, in some order.
        let mut used = vec![false; encoded.len()];
        let mut at = 0;
        while at < run.len() {
            let i = (0..encoded.len()).find(|&i| !used[i] && run[at..].starts_with(&encoded[i]))?;
            used[i] = true;
            at += encoded[i].len();
        }
        Some(Self {
            // The magic number and the version field come before the header.
            at: 8 + (end - len) as u64,
            bytes: encoded.concat(),
        })
    }

    /// Overwrites the run of attributes of the file that starts at `start`
    /// of `out`, and leaves `out` at its end.
    fn write<W: Write + Seek>(&self, start: u64, out: &mut W) -> std::io::Result<()> {
        out.seek(SeekFrom::Start(start + self.at))?;
        out.write_all(&self.bytes)?;
        out.seek(SeekFrom::End(0))?;
        Ok(())
    }
}

/// Which rows of an atlas image cross a cell without a chart.
#[derive(Clone, Copy, Debug)]
struct EmptyCells {
    /// Rows per cell.
    cell_height: usize,
    /// Bit r: cell row r has an empty cell (atlases have at most a few rows).
    rows: u64,
}

impl EmptyCells {
    /// `None` for an atlas every cell of which holds a chart (or one whose
    /// rows the height does not divide evenly).
    fn of(atlas: &envmap_core::Atlas, height: u32) -> Option<Self> {
        let cell_height = (height / atlas.rows.max(1)) as usize;
        if cell_height == 0 || atlas.rows > 64 || !height.is_multiple_of(atlas.rows) {
            return None;
        }
        let rows = (0..atlas.rows)
            .filter(|&r| (0..atlas.cols).any(|c| atlas.cell_at(c, r).is_none()))
            .fold(0u64, |m, r| m | 1 << r);
        (rows != 0).then_some(Self { cell_height, rows })
    }

    /// Whether rows `y0..y0 + n` cross an empty cell.
    fn crossed(self, y0: usize, n: usize) -> bool {
        let (first, last) = (
            y0 / self.cell_height,
            (y0 + n.max(1) - 1) / self.cell_height,
        );
        (first..=last).any(|r| r < 64 && self.rows & (1 << r) != 0)
    }
}

/// A scan-line block stored as it is: its bytes (native endian, f32 or
/// f16 samples) made little endian.
fn raw_chunk(y0: usize, mut data: Vec<u8>) -> ::exr::block::chunk::Chunk {
    use ::exr::block::chunk::{Chunk, CompressedBlock, CompressedScanLineBlock};
    if cfg!(target_endian = "big") {
        // Every channel has the same sample type: f32 here (the `auto`
        // case that stores blocks raw is f32 only).
        data.chunks_exact_mut(4).for_each(<[u8]>::reverse);
    }
    Chunk {
        layer_index: 0,
        compressed_block: CompressedBlock::ScanLine(CompressedScanLineBlock {
            y_coordinate: i32::try_from(y0).unwrap_or(i32::MAX),
            compressed_pixels_le: data,
        }),
    }
}

/// A scan-line block's bytes (native endian, as the `exr` crate's blocks
/// are before compression): for each line, each channel's samples in the
/// list's order (`order[c]` is which of R, G, B channel c is).
fn block_bytes(
    pixels: &[[f32; 3]],
    w: usize,
    index: ::exr::block::BlockIndex,
    order: &[usize],
    sample: ::exr::meta::attribute::SampleType,
) -> Vec<u8> {
    use ::exr::meta::attribute::SampleType;
    let (y0, bh) = (index.pixel_position.y(), index.pixel_size.height());
    let size = sample.bytes_per_sample();
    let mut data = vec![0u8; bh * w * order.len() * size];
    let line_bytes = w * size;
    for (j, out) in data.chunks_exact_mut(line_bytes * order.len()).enumerate() {
        let row = &pixels[(y0 + j) * w..(y0 + j + 1) * w];
        for (&k, line) in order.iter().zip(out.chunks_exact_mut(line_bytes)) {
            match sample {
                SampleType::F16 => {
                    for (b, p) in line.chunks_exact_mut(2).zip(row) {
                        b.copy_from_slice(&::exr::prelude::f16::from_f32(p[k]).to_ne_bytes());
                    }
                }
                SampleType::F32 | SampleType::U32 => {
                    for (b, p) in line.chunks_exact_mut(4).zip(row) {
                        b.copy_from_slice(&p[k].to_ne_bytes());
                    }
                }
            }
        }
    }
    data
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::io::{read_rgb, write_rgb, SaveOptions};
    use ::exr::prelude::*;

    /// A value per pixel and channel with every bit pattern kind in play
    /// (negative, tiny, huge, fractional), exact in f16 where asked.
    fn value(x: usize, y: usize, c: usize, half: bool) -> f32 {
        let v = ((x * 7 + y * 13 + c * 5) % 97) as f32 * 0.37 - 11.0
            + if (x + y).is_multiple_of(11) {
                3.0e4
            } else {
                0.0
            };
        if half {
            f16::from_f32(v).to_f32()
        } else {
            v * 1.000_001
        }
    }

    /// A file's RGB texels as the `exr` crate's own reader reads them.
    fn read_by_the_exr_crate(path: &std::path::Path) -> Vec<[f32; 3]> {
        let back = read_first_rgba_layer_from_file(
            path,
            |res, _| (res.width(), vec![[0f32; 3]; res.area()]),
            |s: &mut (usize, Vec<[f32; 3]>), p, (r, g, b, _): (f32, f32, f32, f32)| {
                s.1[p.y() * s.0 + p.x()] = [r, g, b];
            },
        )
        .expect("the exr crate reads it");
        back.layer_data.channel_data.pixels.1
    }

    fn temp(name: &str) -> std::path::PathBuf {
        std::env::temp_dir().join(format!("envmap-exr-{}-{name}", std::process::id()))
    }

    /// Files the `exr` crate writes in forms envmap does not (tiles, mip
    /// levels, every codec, f16/f32/u32 channels, an alpha channel, odd
    /// sizes) are read by envmap's block reader to the bit.
    #[test]
    fn the_block_reader_reads_what_the_exr_crate_writes() {
        let (w, h) = (67usize, 41usize);
        let codecs = [
            Compression::Uncompressed,
            Compression::RLE,
            Compression::ZIP1,
            Compression::ZIP16,
            Compression::PIZ,
        ];
        let blocks = [Blocks::ScanLines, Blocks::Tiles(Vec2(16, 8))];
        let mut n = 0;
        for (k, &compression) in codecs.iter().enumerate() {
            for &block in &blocks {
                for half in [false, true] {
                    let path = temp(&format!("{k}-{n}.exr"));
                    n += 1;
                    let enc = Encoding {
                        compression,
                        blocks: block,
                        line_order: LineOrder::Increasing,
                    };
                    let px = |Vec2(x, y): Vec2<usize>| {
                        (
                            f16::from_f32(value(x, y, 0, true)),
                            value(x, y, 1, half),
                            value(x, y, 2, half),
                            0.5f32,
                        )
                    };
                    let image =
                        Image::from_encoded_channels((w, h), enc, SpecificChannels::rgba(px));
                    image.write().to_file(&path).expect("write");
                    let (got, _) = read_rgb(&path, 1 << 30, None).expect("read");
                    let _ = std::fs::remove_file(&path);
                    assert_eq!((got.width, got.height), (w as u32, h as u32));
                    for y in 0..h {
                        for x in 0..w {
                            let want = [
                                value(x, y, 0, true),
                                value(x, y, 1, half),
                                value(x, y, 2, half),
                            ];
                            assert_eq!(
                                got.pixels[y * w + x].map(f32::to_bits),
                                want.map(f32::to_bits),
                                "{compression:?} {block:?} half {half}: pixel ({x}, {y})"
                            );
                        }
                    }
                }
            }
        }
    }

    /// envmap's block writer, every codec and both precisions, read back by
    /// the `exr` crate's own reader: lossless codecs give the pixels to the
    /// bit, and the attributes are there.
    #[test]
    fn the_block_writer_is_read_by_the_exr_crate() {
        let (w, h) = (53u32, 37u32);
        let pixels: Vec<[f32; 3]> = (0..h as usize)
            .flat_map(|y| (0..w as usize).map(move |x| [0, 1, 2].map(|c| value(x, y, c, false))))
            .collect();
        let img = RgbImage {
            width: w,
            height: h,
            pixels: pixels.clone(),
        };
        // The lossless ones.
        for compression in &ExrCompression::ALL[..6] {
            let compression = *compression;
            for precision in [ExrPrecision::F32, ExrPrecision::F16] {
                let path = temp(&format!("w-{}-{precision:?}.exr", compression.name()));
                let opts = SaveOptions {
                    exr_compression: compression,
                    exr_precision: precision,
                    content: Some("test content".into()),
                    ..SaveOptions::default()
                };
                write_rgb(&img, &path, &opts).expect("write");
                let got = read_by_the_exr_crate(&path);
                let meta = ::exr::meta::MetaData::read_from_file(&path, false).expect("meta");
                let _ = std::fs::remove_file(&path);
                let header = &meta.headers[0];
                let codec = match compression.resolve(precision) {
                    ExrCompression::None => Compression::Uncompressed,
                    ExrCompression::Rle => Compression::RLE,
                    ExrCompression::Zips => Compression::ZIP1,
                    ExrCompression::Zip => Compression::ZIP16,
                    ExrCompression::Piz => Compression::PIZ,
                    other => panic!("{other:?}"),
                };
                assert_eq!(header.compression, codec, "{compression:?}");
                assert!(header
                    .own_attributes
                    .comments
                    .as_ref()
                    .is_some_and(|c| c.to_string().contains("test content")));
                for (k, (g, p)) in got.iter().zip(&pixels).enumerate() {
                    let want = match precision {
                        ExrPrecision::F32 => *p,
                        ExrPrecision::F16 => p.map(|v| f16::from_f32(v).to_f32()),
                    };
                    assert_eq!(
                        g.map(f32::to_bits),
                        want.map(f32::to_bits),
                        "{compression:?} {precision:?}: pixel {k}"
                    );
                }
            }
        }
    }

    /// The tags are text attributes in their order, whatever order the
    /// `exr` crate's map would give them: the same image is the same bytes
    /// each time it is written, and each tag reads back.
    #[test]
    fn tags_are_written_in_their_order_every_time() {
        use crate::image::io::View;
        let pixels = vec![[0.25f32, 0.5, 1.0]; 8 * 4];
        let tags: Vec<(String, String)> = (0..7)
            .map(|i| (format!("envmap.t{}", (i * 5) % 7), format!("value {i}")))
            .chain([("envmap.t3".to_string(), "last".to_string())])
            .collect();
        let view = View {
            width: 8,
            height: 4,
            pixels: &pixels,
            stream: None,
            atlas: None,
            tags: &tags,
            description: "",
        };
        let write = || {
            let mut out = std::io::Cursor::new(Vec::new());
            encode(
                Path::new("t.exr"),
                view,
                ExrPrecision::F32,
                ExrCompression::None,
                &mut out,
            )
            .expect("encode");
            out.into_inner()
        };
        let first = write();
        // Eight maps of seven names: each order 1 in 5 040.
        for _ in 0..8 {
            assert!(
                write() == first,
                "the bytes differ from one write to the next"
            );
        }
        // In order: t0, t5, t3 (its later value), t1, t6, t4, t2.
        let text = String::from_utf8_lossy(&first);
        let at = |s: &str| text.find(s).unwrap_or_else(|| panic!("{s} missing"));
        let names =
            ["t0", "t5", "t3", "t1", "t6", "t4", "t2"].map(|n| at(&format!("envmap.{n}\0")));
        assert!(names.windows(2).all(|w| w[0] < w[1]), "{names:?}");
        assert!(!text.contains("value 2") && text.contains("last"));
        let meta = ::exr::meta::MetaData::read_from_buffered(std::io::Cursor::new(&first), true)
            .expect("the exr crate reads it");
        assert_eq!(meta.headers[0].own_attributes.other.len(), 7);
        let source = crate::image::format::memory(&first, None);
        let back = super::read(Path::new("t.exr"), source, u64::MAX).expect("read");
        assert_eq!(back.0.pixels, pixels);
    }

    /// `auto` in f32: an atlas with empty cells (the crosses) is an RLE file
    /// whose blocks are compressed only where they cross an empty cell, and
    /// stored raw elsewhere; an atlas without one (a strip, a latlong) is
    /// uncompressed. Either reads back to the bit through the `exr`
    /// crate's own reader, and the cross takes little more than its faces.
    #[test]
    fn auto_compresses_only_the_rows_through_empty_cells() {
        use crate::image::io::save;
        use crate::image::{EnvImage, Representation};
        use envmap_core::{AnyMapping, Atlas, Frame, Mapping};
        let face = 24u32;
        for (mapping, atlas, compressed) in [
            (AnyMapping::Cube, Atlas::CUBE_HORIZONTAL_CROSS, true),
            (AnyMapping::Cube, Atlas::CUBE_VERTICAL_CROSS, true),
            (AnyMapping::Cube, Atlas::CUBE_HORIZONTAL_STRIP, false),
            (AnyMapping::LatLong, Atlas::LATLONG, false),
        ] {
            let repr = Representation::new(mapping, atlas, Frame::IDENTITY).unwrap();
            let (w, h) = atlas.image_size_for_cell_width(face).unwrap();
            let mut img = EnvImage::new(w, h, repr).unwrap();
            for chart in 0..mapping.chart_count() {
                let (cw, ch) = img.cell_size();
                for j in 0..ch {
                    for i in 0..cw {
                        let v = [0, 1, 2]
                            .map(|c| value(i as usize, j as usize, c + chart as usize, false));
                        assert!(img.set_chart_texel(chart, i, j, v));
                    }
                }
            }
            let path = temp(&format!("auto-{}.exr", atlas.name));
            save(&img, &path, &SaveOptions::default()).expect("save");
            let meta = ::exr::meta::MetaData::read_from_file(&path, false).expect("meta");
            let header = &meta.headers[0];
            let want = if compressed {
                Compression::RLE
            } else {
                Compression::Uncompressed
            };
            assert_eq!(header.compression, want, "{}", atlas.name);
            // Each block: raw exactly where its row crosses no empty cell.
            let file = std::fs::File::open(&path).expect("open");
            let reader = ::exr::block::read(std::io::BufReader::new(file), false).expect("read");
            let line_bytes = w as usize * 12;
            let cell_h = (h / atlas.rows) as usize;
            let mut stored = 0usize;
            for chunk in reader.all_chunks(false).expect("chunks") {
                let chunk = chunk.expect("chunk");
                let ::exr::block::chunk::CompressedBlock::ScanLine(b) = chunk.compressed_block
                else {
                    panic!("scan lines")
                };
                let y = b.y_coordinate as usize;
                let r = (y / cell_h) as u32;
                let full = (0..atlas.cols).all(|c| atlas.cell_at(c, r).is_some());
                let n = b.compressed_pixels_le.len();
                stored += n;
                if full || !compressed {
                    assert_eq!(n, line_bytes, "{} row {y}: stored raw", atlas.name);
                } else {
                    assert!(n < line_bytes, "{} row {y}: compressed", atlas.name);
                }
            }
            let faces = (mapping.chart_count() * face * face) as usize * 12;
            if compressed {
                assert!(
                    stored < faces + faces / 20,
                    "{}: {stored} bytes for {faces}",
                    atlas.name
                );
            }
            let got = read_by_the_exr_crate(&path);
            let _ = std::fs::remove_file(&path);
            assert!(
                got.iter()
                    .zip(img.pixels())
                    .all(|(g, p)| g.map(f32::to_bits) == p.map(f32::to_bits)),
                "{}: read back",
                atlas.name
            );
        }
    }
}
