// Pyramid: the one holder of a map's levels, each kept as an image, as a
// copy ready for bilinear reads (with its one-texel border), or both.

use std::borrow::Cow;

use super::bordered::Bordered;
use super::halving::{downsample, downsample_to, next_chart_size, present};
use super::trilinear::Level;
use crate::error::Result;
use crate::filter::sample::Sampler;
use crate::filter::weights::TexelWeights;
use crate::image::layout::check_compatible;
use crate::image::{EnvImage, Representation};
use envmap_core::atlas::Atlas;
use envmap_core::Mapping;

/// An environment map and its mip levels; see the [module docs](super).
///
/// Each level is kept as an image, and, once made ready for sampling, as
/// a copy of its charts with a one-texel border that holds the edge rule
/// (every level but a disk map's, which is read in place). The samplers
/// ([`Trilinear`](super::Trilinear), the lit renderer's) read a level's
/// ready copy where it has one.
#[derive(Clone, Debug, PartialEq)]
pub struct Pyramid {
    /// The levels' images, largest first; empty for levels made straight
    /// into their ready copies (`Pyramid::below`, for the renderer).
    pub(super) levels: Vec<EnvImage>,
    /// Each level's ready copy, where one has been made.
    pub(super) ready: Vec<Option<Bordered>>,
}

impl Pyramid {
    /// `base` and its levels down to charts of height 1, or down to the
    /// last level whose charts are at least `min_height` texels high
    /// (`min_height` 1 for the whole chain).
    ///
    /// # Errors
    ///
    /// Only if a level cannot be made (see `downsample`).
    pub fn new(base: EnvImage, min_height: u32) -> Result<Self> {
        let mut levels = vec![base];
        loop {
            let last = &levels[levels.len() - 1];
            let (cw, ch) = last.cell_size();
            let a = last.atlas();
            let (_, h2) = next_chart_size(cw, ch, a.cell_aspect_w, a.cell_aspect_h);
            if ch <= 1 || h2 < min_height.max(1) {
                break;
            }
            let weights = TexelWeights::new(last.mapping(), cw, ch);
            let next = downsample(last, &weights)?;
            levels.push(next);
        }
        Ok(Self::of_levels(levels))
    }

    /// Levels given as they are (a prefiltered chain, largest first, or a
    /// single map), none of them ready yet.
    pub(crate) fn of_levels(levels: Vec<EnvImage>) -> Self {
        let ready = vec![None; levels.len()];
        Self { levels, ready }
    }

    /// The levels below `map`, from half its size down to charts of height
    /// 1, as `Pyramid::new(downsample_to(map, weights, atlas)?, 1)?` made
    /// ready ([`Pyramid::ready_from`] 0) holds them, bit for bit, with less
    /// work: a level of an even size is halved straight into its ready copy
    /// from the one above (no level image made, none copied), and no image
    /// is kept. A disk map's levels are made as images (they are read in
    /// place). `weights` are `map`'s texel solid angles; `atlas`, one of
    /// its mapping's, is how an odd level in between is laid out.
    ///
    /// # Errors
    ///
    /// If `atlas` is not an atlas of `map`'s mapping, or a level cannot be
    /// made (see `downsample`).
    pub(crate) fn below(map: &EnvImage, weights: &TexelWeights, atlas: Atlas) -> Result<Self> {
        let mapping = map.mapping();
        if mapping.has_disk_charts() {
            return Self::new(downsample_to(map, weights, atlas)?, 1);
        }
        check_compatible(mapping, &atlas)?;
        let repr = Representation {
            atlas,
            ..*map.representation()
        };
        let mut ready: Vec<Option<Bordered>> = Vec::new();
        let (mut cw, mut ch) = map.cell_size();
        loop {
            let next = next_chart_size(cw, ch, atlas.cell_aspect_w, atlas.cell_aspect_h);
            let even = (cw, ch) == (2 * next.0, 2 * next.1);
            let level = match ready.last().and_then(Option::as_ref) {
                None if even => Bordered::halved(map, weights, mapping, next),
                None => Bordered::new(&downsample_to(map, weights, atlas)?),
                Some(above) => {
                    let weights = TexelWeights::new(mapping, cw, ch);
                    if even {
                        Bordered::halved(above, &weights, mapping, next)
                    } else {
                        Bordered::new(&downsample(&above.to_image(repr)?, &weights)?)
                    }
                }
            };
            ready.push(Some(level));
            (cw, ch) = next;
            if ch <= 1 {
                break;
            }
        }
        Ok(Self {
            levels: Vec::new(),
            ready,
        })
    }

    /// Makes the ready copy of every level from `first` down that lacks one
    /// (none for a disk map: its levels are read in place).
    pub(crate) fn ready_from(&mut self, first: usize) {
        for (image, ready) in self.levels.iter().zip(&mut self.ready).skip(first) {
            if ready.is_none() && !image.mapping().has_disk_charts() {
                *ready = Some(Bordered::new(image));
            }
        }
    }

    /// Level `k` as a sampler reads it: its ready copy where it has one,
    /// else its image in place (`Owned` copy: made now, for a level that
    /// lacks one, where `copy` asks for it).
    pub(crate) fn reader(&self, k: usize, copy: bool) -> Level<'_> {
        if let Some(b) = &self.ready[k] {
            return Level::Bordered(Cow::Borrowed(b));
        }
        let image = &self.levels[k];
        if copy && !image.mapping().has_disk_charts() {
            Level::Bordered(Cow::Owned(Bordered::new(image)))
        } else {
            Level::Plain(Sampler::new(image))
        }
    }

    /// The chart size of every level, largest first.
    #[must_use]
    pub(crate) fn chart_sizes(&self) -> Vec<(u32, u32)> {
        match self.levels.is_empty() {
            true => self.ready.iter().flatten().map(|l| (l.w, l.h)).collect(),
            false => self.levels.iter().map(EnvImage::cell_size).collect(),
        }
    }

    /// The levels below `map` made again in place, into the memory they
    /// hold, where they are [`Pyramid::below`] of a map of `map`'s mapping
    /// and chart size and every level halves evenly (no level allocated,
    /// none zeroed: for a map that changes between renders); bit for bit
    /// what `below` makes of `map`. `weights` are `map`'s texel solid
    /// angles and `above[k]` those of level `k + 1` (the level that level
    /// `k + 2` is made from). Returns false, changing nothing, where they
    /// cannot be made in place (sizes that turn odd, a disk map, a map that
    /// lacks a chart, weights of other sizes).
    pub(crate) fn remake_below(
        &mut self,
        map: &EnvImage,
        weights: &TexelWeights,
        above: &[TexelWeights],
    ) -> bool {
        if !self.levels.is_empty() || self.ready.iter().any(Option::is_none) {
            return false;
        }
        let levels: Vec<&mut Bordered> = self.ready.iter_mut().flatten().collect();
        let mapping = map.mapping();
        let charts = mapping.chart_count();
        if charts >= 32 || present(map, mapping) != (1 << charts) - 1 {
            return false;
        }
        if above.len() + 1 != levels.len() || weights.size() != map.cell_size() {
            return false;
        }
        let mut size = map.cell_size();
        for (k, l) in levels.iter().enumerate() {
            let w = if k == 0 { weights } else { &above[k - 1] };
            if size != (2 * l.w, 2 * l.h) || w.size() != size || l.charts != charts {
                return false;
            }
            size = (l.w, l.h);
        }
        let mut levels = levels;
        for k in 0..levels.len() {
            let (made, rest) = levels.split_at_mut(k);
            match made.last() {
                None => rest[0].halve_from(map, weights, mapping),
                Some(src) => rest[0].halve_from(&**src, &above[k - 1], mapping),
            }
        }
        true
    }

    /// The levels' images, largest first.
    #[must_use]
    pub fn levels(&self) -> &[EnvImage] {
        &self.levels
    }

    /// The levels' images, largest first, given up (no copy): for a caller
    /// that writes them out.
    #[must_use]
    pub fn into_levels(self) -> Vec<EnvImage> {
        self.levels
    }

    /// Level `k` (clamped to the last).
    #[must_use]
    pub fn level(&self, k: usize) -> &EnvImage {
        &self.levels[k.min(self.levels.len() - 1)]
    }

    /// The number of levels.
    #[must_use]
    pub fn len(&self) -> usize {
        self.ready.len()
    }

    /// Always false: a pyramid has its base at least.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.ready.is_empty()
    }
}
