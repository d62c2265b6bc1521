// Files whose layout is more than an atlas: ffmpeg `v360`'s `eac` files turn
// the faces of their bottom row and pad every row. The image is held in
// memory in the layout's atlas (faces in GL's orientation, no padding);
// the turns and the padding are applied on writing and undone on reading.

use envmap_core::{Atlas, CubeFace};

use crate::error::{Error, Result};
use crate::image::envimage::{EnvImage, RgbImage};
use crate::image::face_ops::{FaceTransforms, FaceTurn};
use crate::image::layout::Representation;

/// How a file lays out an atlas beyond its cells: each face turned, and a
/// padding of `pad` pixels around the image's left and right sides and
/// above and below every row of cells (ffmpeg `v360`'s `eac`: 2 pixels, so
/// that the two rows are 4 pixels apart and the faces of a row touch).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Framing {
    /// The file's faces against GL's orientation.
    turns: FaceTransforms,
    /// Pixels of padding.
    pad: u32,
}

impl Framing {
    /// The framing of `atlas`'s files, if it has one ([`Atlas::EAC_V360`]).
    ///
    /// v360's `eac` turns −y and +y by `ROT_270` and −z by `ROT_90`
    /// (`prepare_eac_out` in `libavfilter/vf_v360.c`); its `xyz_to_eac`
    /// pads by `pixel_pad = 2` pixels.
    #[must_use]
    pub(crate) fn of(atlas: &Atlas) -> Option<Framing> {
        if *atlas != Atlas::EAC_V360 {
            return None;
        }
        let turns = FaceTransforms::default()
            .with(CubeFace::NegY, FaceTurn::ROT270)
            .with(CubeFace::NegZ, FaceTurn::ROT90)
            .with(CubeFace::PosY, FaceTurn::ROT270);
        Some(Framing { turns, pad: 2 })
    }

    /// The file's size for an image of `width × height` in `atlas`.
    #[must_use]
    pub(crate) fn file_size(&self, atlas: &Atlas, width: u32, height: u32) -> (u32, u32) {
        (width + 2 * self.pad, height + 2 * self.pad * atlas.rows)
    }

    /// The image's size inside a `width × height` file in `atlas`; an error
    /// naming the sizes that fit when the cells would not be whole squares
    /// of the atlas's shape.
    pub(crate) fn inner_size(&self, atlas: &Atlas, width: u32, height: u32) -> Result<(u32, u32)> {
        let inner = width
            .checked_sub(2 * self.pad)
            .zip(height.checked_sub(2 * self.pad * atlas.rows))
            .filter(|&(w, h)| atlas.cell_size(w, h).is_some());
        inner.ok_or_else(|| {
            let (cols, rows) = (atlas.cols, atlas.rows);
            let (px, py) = (2 * self.pad, 2 * self.pad * rows);
            Error::layout(format!(
                "the {} layout is ({cols}n + {px}) × ({rows}n + {py}) pixels for faces of n × n \
                 ({} pixels of padding around each row); this image is {width}×{height} \
                 (ffmpeg's v360 writes such a file with w={cols}n+{px}:h={rows}n+{py})",
                atlas.name, self.pad
            ))
        })
    }

    /// `image` as the file stores it: its faces turned, then padded by
    /// repeating each row's edge texels outwards.
    pub(crate) fn framed(&self, image: &EnvImage) -> Result<RgbImage> {
        let turned = self.turns.apply(image.clone(), true)?;
        let atlas = image.representation().atlas;
        let (w, h) = (turned.width(), turned.height());
        let ch = h / atlas.rows;
        let (fw, fh) = self.file_size(&atlas, w, h);
        let band = ch + 2 * self.pad;
        let mut pixels = Vec::with_capacity(fw as usize * fh as usize);
        for y in 0..fh {
            let (row, in_band) = (y / band, y % band);
            let sy = row * ch + in_band.saturating_sub(self.pad).min(ch - 1);
            let src = &turned.pixels()[(sy * w) as usize..((sy + 1) * w) as usize];
            pixels.extend((0..fw).map(|x| src[x.saturating_sub(self.pad).min(w - 1) as usize]));
        }
        Ok(RgbImage {
            width: fw,
            height: fh,
            pixels,
        })
    }

    /// The image a file of this framing holds: the padding cut away, the
    /// faces turned back to GL's orientation.
    pub(crate) fn unframed(&self, rgb: &RgbImage, repr: Representation) -> Result<EnvImage> {
        let atlas = repr.atlas;
        let (w, h) = self.inner_size(&atlas, rgb.width, rgb.height)?;
        let ch = h / atlas.rows;
        let band = ch + 2 * self.pad;
        let mut pixels = Vec::with_capacity(w as usize * h as usize);
        for y in 0..h {
            let fy = (y / ch) * band + self.pad + y % ch;
            let start = (fy * rgb.width + self.pad) as usize;
            pixels.extend_from_slice(&rgb.pixels[start..start + w as usize]);
        }
        let image = EnvImage::from_rgb(
            RgbImage {
                width: w,
                height: h,
                pixels,
            },
            repr,
        )?;
        self.turns.apply(image, false)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use envmap_core::{AnyMapping, Frame};

    fn numbered(n: u32) -> EnvImage {
        let repr = Representation::new(AnyMapping::Eac, Atlas::EAC_V360, Frame::IDENTITY).unwrap();
        let mut img = EnvImage::new(3 * n, 2 * n, repr).unwrap();
        for y in 0..2 * n {
            for x in 0..3 * n {
                img.set(x, y, [x as f32, y as f32, 1.0]);
            }
        }
        img
    }

    #[test]
    fn file_round_trips_and_pads_with_edges() {
        let img = numbered(5);
        let f = Framing::of(&img.representation().atlas).unwrap();
        let file = f.framed(&img).unwrap();
        assert_eq!((file.width, file.height), (19, 18));
        let back = f.unframed(&file, *img.representation()).unwrap();
        assert_eq!(back, img);
        // The top-left corner of the file repeats the −x face's texel (0, 0),
        // as stored (that face is not turned).
        assert_eq!(file.pixels[0], img.get(0, 0));
        // Row 2 of the file is the first row of faces; row 7 the last.
        assert_eq!(file.pixels[(2 * 19 + 2) as usize], img.get(0, 0));
        assert_eq!(file.pixels[(8 * 19 + 2) as usize], img.get(0, 4));
    }

    #[test]
    fn sizes_that_do_not_fit_are_named() {
        let f = Framing::of(&Atlas::EAC_V360).unwrap();
        assert_eq!(
            f.inner_size(&Atlas::EAC_V360, 3076, 2056).unwrap(),
            (3072, 2048)
        );
        let e = f
            .inner_size(&Atlas::EAC_V360, 4096, 2304)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("(3n + 4) × (2n + 8)") && e.contains("4096×2304"),
            "{e}"
        );
        assert!(f.inner_size(&Atlas::EAC_V360, 3, 7).is_err());
        assert_eq!(Framing::of(&Atlas::CUBE_3X2), None);
    }
}
