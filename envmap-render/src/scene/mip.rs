// Mip-aware lookups: the map's levels below it, and the footprint and
// level of each lookup (see the folder's section "Mip-aware lookups").
use envmap_core::glam::Vec3;
use envmap_core::reflect_view;
use envmap_core::AnyMapping;
use envmap_simd::{Uv8, LANES};
use wide::f32x8;

use super::raster::*;
use crate::error::Result;
use crate::filter::pyramid::Pyramid;
use crate::filter::weights::TexelWeights;
use crate::image::EnvImage;
use crate::scene::mesh::Mesh;

/// What a mip-aware render reads below an environment map (the map itself
/// is level 0, read in place): its solid-angle-weighted pyramid from half
/// its size down to 1², each level ready for sampling (made with its
/// border, once, here), and its texels' solid angles; see
/// [Mip-aware lookups](super#mip-aware-lookups). Make it once to render a
/// map many times: a render from it copies nothing.
#[derive(Clone, Debug)]
pub struct MipLevels {
    pub(super) below: Pyramid,
    pub(super) texels: TexelWeights,
    /// The smallest texel solid angle ([`TexelWeights::smallest`]).
    pub(super) least: f64,
    pub(super) mapping: AnyMapping,
    pub(super) cell: (u32, u32),
    /// Where the levels' charts are laid out.
    pub(super) atlas: envmap_core::atlas::Atlas,
    /// The texel solid angles of each level from the first down that the
    /// next is made from, for [`MipLevels::rebuild`] (made by its first
    /// call).
    pub(super) above: Vec<TexelWeights>,
}

impl MipLevels {
    /// The levels below `map`.
    ///
    /// # Errors
    ///
    /// Only if a level cannot be made (see `Pyramid::below`).
    pub fn new(map: &EnvImage) -> Result<Self> {
        let (cw, ch) = map.cell_size();
        let mapping = map.mapping();
        let texels = TexelWeights::new(mapping, cw, ch).for_lookups();
        let atlas = Self::atlas_for(map);
        let below = Pyramid::below(map, &texels, atlas)?;
        Ok(Self {
            below,
            least: texels.smallest(),
            texels,
            mapping,
            cell: (cw, ch),
            atlas,
            above: Vec::new(),
        })
    }

    /// Where the levels of `map` are laid out: a cube's as a strip,
    /// whatever its layout (a cross's empty cells would be half of every
    /// level's memory, its pages touched in every render that builds
    /// them), any other map's as the map is.
    pub(super) fn atlas_for(map: &EnvImage) -> envmap_core::atlas::Atlas {
        match map.mapping() {
            AnyMapping::Cube => envmap_core::atlas::Atlas::CUBE_HORIZONTAL_STRIP,
            _ => map.representation().atlas,
        }
    }

    /// These levels made again for `map`, a map that changes between
    /// renders (an environment captured anew for each frame): where `map`
    /// has the mapping, chart size and layout of the map they were made
    /// for, and its levels halve evenly, each level is halved again into
    /// the memory it holds, and the texel solid angles are kept (they
    /// depend on the geometry only): no level allocated, no page of memory
    /// new to the process (the first call makes the solid angles of the
    /// levels that the next are made from, and keeps them). Otherwise as [`MipLevels::new`]. Either way, bit for
    /// bit the levels `MipLevels::new(map)` makes.
    ///
    /// # Errors
    ///
    /// As [`MipLevels::new`].
    pub fn rebuild(&mut self, map: &EnvImage) -> Result<()> {
        let sizes = self.below.chart_sizes();
        // Every level half the one above it (else the levels are made anew,
        // and the solid angles below are not worth making).
        let even = sizes
            .iter()
            .scan(self.cell, |above, &(w, h)| {
                let halves = *above == (2 * w, 2 * h);
                *above = (w, h);
                Some(halves)
            })
            .all(|h| h);
        if even && self.fits(map) && Self::atlas_for(map) == self.atlas {
            let chain = sizes.len().saturating_sub(1);
            if self.above.len() != chain {
                self.above = sizes[..chain]
                    .iter()
                    .map(|&(w, h)| TexelWeights::new(self.mapping, w, h))
                    .collect();
            }
            if self.below.remake_below(map, &self.texels, &self.above) {
                return Ok(());
            }
        }
        *self = Self::new(map)?;
        Ok(())
    }

    /// Whether these are levels of a map of `map`'s mapping and size.
    #[cfg_attr(feature = "instruments", visibility::make(pub))]
    #[must_use]
    pub(crate) fn fits(&self, map: &EnvImage) -> bool {
        map.mapping() == self.mapping && map.cell_size() == self.cell
    }
}

/// The footprint of the direction `d` looked up at pixel position `(x, y)`:
/// the larger of the angles (as chords of the unit sphere) between `d` and
/// the directions one pixel to the right and one pixel down. For a hit,
/// those are the reflections at the screen points on the same triangle's
/// plane, its weights extrapolated (Igehy's ray differentials, by finite
/// differences of the interpolated surface); for the background, the view
/// rays there. `known` holds the turns towards those pixels (their
/// direction minus `d`) where the caller has them; only the others are
/// made here.
#[allow(clippy::too_many_arguments)]
pub(super) fn footprint(
    mesh: &Mesh,
    projected: &[(f32, f32, f32)],
    hit: Option<&Hit>,
    view: &View,
    x: f32,
    y: f32,
    d: Vec3,
    known: (Option<Vec3>, Option<Vec3>),
) -> f32 {
    let at = |px: f32, py: f32| -> Vec3 {
        let Some(hit) = hit else {
            return view.ray(px, py);
        };
        let v = mesh.triangles[hit.tri as usize].map(|i| projected[i as usize]);
        match weights_at(&v, px, py) {
            Some(w) => {
                let (n, vv) = surface(mesh, &Hit { w, ..*hit }, view);
                reflect_view(n, vv)
            }
            None => d,
        }
    };
    let dx = known.0.unwrap_or_else(|| at(x + 1.0, y) - d);
    let dy = known.1.unwrap_or_else(|| at(x, y + 1.0) - d);
    dx.length_squared().max(dy.length_squared()).sqrt()
}

/// The footprints of the lookups `dirs` of the pixels `need` in a band
/// of rows from `y0`, `w` wide (see [`footprint`]). On each axis where a
/// pixel on the object has a neighbour in the band (left or right, up or
/// down) on the same triangle, it takes the difference from that
/// neighbour's direction, already made (the forward difference where there
/// is one, else the backward): the same ray differential as extrapolating
/// on the triangle's plane, without making that direction again; the
/// background likewise from background neighbours' view rays. An axis
/// without such a neighbour is extrapolated ([`footprint`]), the other
/// axis kept.
/// With `background_at_base` ([`background_stays_at_base`]) a background
/// pixel's footprint is not measured but given as 0 (its level is 0
/// either way), and only the lookups `on_object` (those of pixels hit,
/// ascending) are visited. Into `out.0` (what it held is dropped); `out.1`
/// is room for a table from pixels to lookups.
#[allow(clippy::too_many_arguments)]
pub(super) fn footprints(
    mesh: &Mesh,
    projected: &[(f32, f32, f32)],
    view: &View,
    hits: &[Option<Hit>],
    need: &[usize],
    dirs: &[Vec3],
    w: u32,
    y0: u32,
    background_at_base: bool,
    on_object: &[usize],
    (out, slot): (&mut Vec<f32>, &mut Vec<u32>),
) {
    let (w32, w) = (w, w as usize);
    // Pixel → its lookup, where it has one.
    let every = need.len() == hits.len();
    slot.clear();
    if !every {
        slot.resize(hits.len(), u32::MAX);
        for (j, &k) in need.iter().enumerate() {
            slot[k] = j as u32;
        }
    }
    let lookup = |k: usize| -> Option<usize> {
        if every {
            Some(k)
        } else {
            slot.get(k)
                .copied()
                .filter(|&j| j != u32::MAX)
                .map(|j| j as usize)
        }
    };
    let measure = |k: usize, d: Vec3| -> f32 {
        let hit = hits[k].as_ref();
        // A band has fewer than 2³² pixels: a 32-bit division.
        let (x, y) = ((k as u32 % w32) as usize, (k as u32 / w32) as usize);
        // The direction at neighbour `n` if it is on `hit`'s triangle, or
        // background beside background.
        let same = |n: usize| match (hit, hits.get(n)?) {
            (Some(h), Some(o)) if o.tri == h.tri => lookup(n).map(|j| dirs[j]),
            (None, None) => lookup(n).map(|j| dirs[j]),
            _ => None,
        };
        let dx = (x + 1 < w)
            .then(|| same(k + 1))
            .flatten()
            .map(|r| r - d)
            .or_else(|| (x > 0).then(|| same(k - 1)).flatten().map(|l| d - l));
        let dy = same(k + w)
            .map(|r| r - d)
            .or_else(|| (k >= w).then(|| same(k - w)).flatten().map(|l| d - l));
        match (dx, dy) {
            (Some(dx), Some(dy)) => dx.length_squared().max(dy.length_squared()).sqrt(),
            // An axis without such a neighbour extrapolates.
            known => {
                let (px, py) = (x as f32 + 0.5, (y0 as usize + y) as f32 + 0.5);
                footprint(mesh, projected, hit, view, px, py, d, known)
            }
        }
    };
    out.clear();
    if background_at_base {
        // Only the object's lookups are measured; the rest stay 0.
        out.resize(need.len(), 0.0);
        for &j in on_object {
            out[j] = measure(need[j], dirs[j]);
        }
    } else {
        out.extend(need.iter().zip(dirs).map(|(&k, &d)| measure(k, d)));
    }
}

/// Whether no background lookup of `view` can read above level 0 in a map
/// whose smallest texel solid angle is `least`. Two neighbouring pixels'
/// view rays pass through points Δ = 2·tan(half the field of view) / pixels
/// apart on the image plane at distance 1; the eye is at least 1 from the
/// line through them, so the angle between the rays is at most
/// 2·atan(Δ/2) ≤ Δ, and their chord (the footprint) less. [`lod8`]'s
/// level is above 0 only where footprint² / Ω > 4, so where Δ² ≤ 4·least
/// (with room for f32 rounding) every background lookup reads level 0,
/// and its footprint need not be measured: the background of a 1920 × 1080
/// view at the default 35° in a 6 × 1024² cube, say (Δ = 5.8·10⁻⁴ against
/// 2·√least = 1.7·10⁻³).
pub(super) fn background_stays_at_base(view: &View, least: f64) -> bool {
    let dx = 2.0 * f64::from(view.tan_x) / f64::from(view.width);
    let dy = 2.0 * f64::from(view.tan_y) / f64::from(view.height);
    let s = dx.max(dy) * 1.001 + 1e-6;
    s * s <= 3.99 * least
}

/// Added to every mip-aware lookup's level: one level finer than the
/// footprint's own (see [Mip-aware lookups](super#mip-aware-lookups)).
pub(super) const LOD_BIAS: f32 = -1.0;

/// Perspective-correct weights of screen point `(px, py)` on the plane of a
/// projected triangle, inside it or not (`None` if degenerate).
pub(super) fn weights_at(v: &[(f32, f32, f32); 3], px: f32, py: f32) -> Option<[f32; 3]> {
    let area = (v[1].0 - v[0].0) * (v[2].1 - v[0].1) - (v[2].0 - v[0].0) * (v[1].1 - v[0].1);
    if area.abs() < 1e-12 || !area.is_finite() {
        return None;
    }
    let inv_area = 1.0 / area;
    let b0 = ((v[1].0 - px) * (v[2].1 - py) - (v[2].0 - px) * (v[1].1 - py)) * inv_area;
    let b1 = ((v[2].0 - px) * (v[0].1 - py) - (v[0].0 - px) * (v[2].1 - py)) * inv_area;
    let b2 = 1.0 - b0 - b1;
    let inv_z = [1.0 / v[0].2, 1.0 / v[1].2, 1.0 / v[2].2];
    let iz = b0 * inv_z[0] + b1 * inv_z[1] + b2 * inv_z[2];
    if !(iz > 0.0 && iz.is_finite()) {
        return None;
    }
    Some([b0 * inv_z[0] / iz, b1 * inv_z[1] / iz, b2 * inv_z[2] / iz])
}

/// The mip level of eight lookups: log2 of each footprint (radians) over
/// the angular size of the base texel it lands in (the square root of
/// that texel's solid angle), plus [`LOD_BIAS`], at least 0; 0 where the
/// texel holds no direction (a disk's corners). The texels are found
/// eight at a time ([`TexelWeights::get8_f32`]); lanes past `spread`'s
/// length have footprint 0, level 0.
pub(super) fn lod8(texels: &TexelWeights, q: &Uv8, spread: &[f32]) -> f32x8 {
    let omega = texels.get8_f32(q);
    let mut s = [0.0f32; LANES];
    for (s, sp) in s.iter_mut().zip(spread) {
        *s = *sp;
    }
    let s = f32x8::new(s);
    // log2(s / √Ω) = ½ log2(s² / Ω), eight at a time. Where s² / Ω ≤ 4
    // the level is at most 0 (the bias is −1), and it is 0 where Ω is 0
    // or the ratio is not finite.
    let ratio = s * s / omega;
    let lod = ratio.ln() * f32x8::splat(0.5 * core::f32::consts::LOG2_E) + f32x8::splat(LOD_BIAS);
    let above = ratio.simd_gt(f32x8::splat(4.0)) & ratio.simd_lt(f32x8::splat(f32::INFINITY));
    above.select(lod.max(f32x8::ZERO), f32x8::ZERO)
}
