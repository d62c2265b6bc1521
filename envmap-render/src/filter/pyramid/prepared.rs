// PreparedLevels: a pyramid's levels made ready for trilinear sampling once,
// built below a map and made again in place.

use super::bordered::Bordered;
use super::halving::{downsample, downsample_to, next_chart_size, present, Pyramid};
use crate::error::Result;
use crate::filter::weights::TexelWeights;
use crate::image::layout::check_compatible;
use crate::image::{EnvImage, Representation};
use envmap_core::atlas::Atlas;
use envmap_core::Mapping;

/// A pyramid's levels made ready for [`Trilinear`](super::Trilinear) once,
/// for samplers that borrow them (`Trilinear::over_prepared`): each level
/// copied with its one-texel border, the pyramid itself then let go; a
/// disk map's levels are kept as they are (its plain sampler reads them in
/// place).
#[derive(Clone, Debug, PartialEq)]
pub struct PreparedLevels {
    pub(super) kind: Prepared,
}

#[derive(Clone, Debug, PartialEq)]
pub(super) enum Prepared {
    Bordered(Vec<Bordered>),
    Plain(Pyramid),
}

impl PreparedLevels {
    /// `p`'s levels made ready.
    #[must_use]
    pub fn new(p: Pyramid) -> Self {
        let kind = if p.levels[0].mapping().has_disk_charts() {
            Prepared::Plain(p)
        } else {
            Prepared::Bordered(p.levels.iter().map(Bordered::new).collect())
        };
        Self { kind }
    }

    /// The levels below `map`, from half its size down to charts of height
    /// 1, as [`PreparedLevels::new`] of `Pyramid::new(downsample_to(map,
    /// weights, atlas)?, 1)?` makes them, bit for bit, with less work: a
    /// level of an even size is halved straight into its bordered copy
    /// from the one above (no level image made, none copied). `weights` are
    /// `map`'s texel solid angles; `atlas`, one of its mapping's, is how
    /// an odd level in between is laid out.
    ///
    /// # Errors
    ///
    /// If `atlas` is not an atlas of `map`'s mapping, or a level cannot be
    /// made (see `downsample`).
    pub(crate) fn below(map: &EnvImage, weights: &TexelWeights, atlas: Atlas) -> Result<Self> {
        let mapping = map.mapping();
        if mapping.has_disk_charts() {
            return Ok(Self::new(Pyramid::new(
                downsample_to(map, weights, atlas)?,
                1,
            )?));
        }
        check_compatible(mapping, &atlas)?;
        let repr = Representation {
            atlas,
            ..*map.representation()
        };
        let mut levels: Vec<Bordered> = Vec::new();
        let (mut cw, mut ch) = map.cell_size();
        loop {
            let next = next_chart_size(cw, ch, atlas.cell_aspect_w, atlas.cell_aspect_h);
            let even = (cw, ch) == (2 * next.0, 2 * next.1);
            let level = match levels.last() {
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
            levels.push(level);
            (cw, ch) = next;
            if ch <= 1 {
                break;
            }
        }
        Ok(Self {
            kind: Prepared::Bordered(levels),
        })
    }

    /// The number of levels.
    #[must_use]
    pub fn len(&self) -> usize {
        match &self.kind {
            Prepared::Bordered(b) => b.len(),
            Prepared::Plain(p) => p.len(),
        }
    }

    /// The chart size of every level, largest first.
    #[must_use]
    pub(crate) fn chart_sizes(&self) -> Vec<(u32, u32)> {
        match &self.kind {
            Prepared::Bordered(b) => b.iter().map(|l| (l.w, l.h)).collect(),
            Prepared::Plain(p) => p.levels.iter().map(EnvImage::cell_size).collect(),
        }
    }

    /// The levels below `map` made again in place, into the memory they
    /// hold, where they are [`PreparedLevels::below`] of a map of `map`'s
    /// mapping and chart size and every level halves evenly (no level
    /// allocated, none zeroed: for a map that changes between renders);
    /// bit for bit what `below` makes of `map`. `weights` are `map`'s
    /// texel solid angles and `above[k]` those of level `k + 1` (the level
    /// that level `k + 2` is made from). Returns false, changing nothing,
    /// where they cannot be made in place (sizes that turn odd, a disk
    /// map, a map that lacks a chart, weights of other sizes).
    pub(crate) fn remake_below(
        &mut self,
        map: &EnvImage,
        weights: &TexelWeights,
        above: &[TexelWeights],
    ) -> bool {
        let Prepared::Bordered(levels) = &mut self.kind else {
            return false;
        };
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
        for k in 0..levels.len() {
            let (made, rest) = levels.split_at_mut(k);
            match made.last() {
                None => rest[0].halve_from(map, weights, mapping),
                Some(src) => rest[0].halve_from(src, &above[k - 1], mapping),
            }
        }
        true
    }

    /// Always false: a pyramid has its base at least.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}
