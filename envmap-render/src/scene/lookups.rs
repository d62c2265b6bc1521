// A band's environment lookups: the directions to look up, and their
// values from the map (plain or mip-aware) or the analytic environment.
use envmap_core::glam::{Mat3, Vec3};
use envmap_core::AnyMapping;
use envmap_core::{reflect_view, ChartUv};
use envmap_simd::{forward_slice, Dir8, Fine, Mapping8, Uv8, LANES};
use wide::f32x8;

use super::mip::*;
use super::raster::*;
use super::renderer::*;
use crate::filter::brdf::schlick_f32;
use crate::filter::pyramid::{Trilinear, TrilinearAhead};
use crate::filter::sample::{Ahead, Filter, Sampler};
use crate::filter::weights::TexelWeights;
use crate::instruments::EnvSampling;
use crate::scene::mesh::Mesh;

/// The width of [`light_table`]'s grid.
#[cfg_attr(not(feature = "instruments"), allow(dead_code))]
pub(super) const LIGHT_TABLE_WIDTH: u32 = 1024;

/// The buffers a worker's bands are made in, kept from band to band and,
/// in the [`Renderer`], from frame to frame: allocating them for each band
/// (a megabyte and a half for a band of a 1080p frame) hands the system
/// pages to fault in and zero.
#[derive(Default)]
pub(super) struct BandScratch {
    /// What each pixel of the band sees.
    pub(super) hits: Vec<Option<Hit>>,
    /// The pixels hit, in order.
    pub(super) hit_at: Vec<usize>,
    /// The pixels looked up, in order.
    pub(super) need: Vec<usize>,
    pub(super) lookups: BandLookups,
    /// The lookups' footprints, and [`footprints`]' pixel-to-lookup table.
    pub(super) spread: Vec<f32>,
    pub(super) slot: Vec<u32>,
    /// The looked-up values where not every pixel is looked up.
    pub(super) buffer: Vec<[f32; 3]>,
}

/// What a band's lookups start from ([`band_lookups`]).
#[derive(Default)]
pub(super) struct BandLookups {
    /// Lookup `j`'s direction (world axes): the reflection at a pixel hit,
    /// else the view ray.
    pub(super) dirs: Vec<Vec3>,
    /// Lookup `j`'s Schlick factor (1 without `fresnel_f0`, and off the
    /// object).
    pub(super) fresnel: Vec<f32>,
    /// The lookups of pixels hit, ascending: the ones whose footprints
    /// [`footprints`] measures when the background stays at the base.
    pub(super) on_object: Vec<usize>,
}

/// The directions to look up for the pixels `need` of a band of rows from
/// `y0`, `w` wide: the reflection (per pixel) where the pixel is hit, the
/// view ray through its centre elsewhere; with each, Schlick's factor for
/// `fresnel_f0`, and which lookups are on the object; into `out` (what it
/// held is dropped).
#[allow(clippy::too_many_arguments)]
pub(super) fn band_lookups(
    mesh: &Mesh,
    view: &View,
    hits: &[Option<Hit>],
    need: &[usize],
    w: u32,
    y0: u32,
    fresnel_f0: Option<f32>,
    out: &mut BandLookups,
) {
    let BandLookups {
        dirs,
        fresnel,
        on_object,
    } = out;
    dirs.clear();
    fresnel.clear();
    fresnel.resize(need.len(), 1.0);
    on_object.clear();
    for (j, &k) in need.iter().enumerate() {
        let (x, y) = (
            (k as u32 % w) as f32 + 0.5,
            (y0 + k as u32 / w) as f32 + 0.5,
        );
        let d = match &hits[k] {
            None => view.ray(x, y),
            Some(hit) => {
                on_object.push(j);
                let (n, vv) = surface(mesh, hit, view);
                if let Some(f0) = fresnel_f0 {
                    fresnel[j] = schlick_f32(f0, n.dot(vv));
                }
                reflect_view(n, vv)
            }
        };
        dirs.push(d);
    }
}

/// The indices below `n` that are not in `at` (ascending), in order,
/// added to `out`: the background of a band from its pixels hit.
pub(super) fn missed(at: &[usize], n: usize, out: &mut Vec<usize>) {
    out.reserve(n.saturating_sub(at.len()));
    let mut next = 0;
    for &k in at.iter().chain(core::iter::once(&n)) {
        out.extend(next..k);
        next = k + 1;
    }
}

/// The map lookups of one band: directions `dirs` (world axes, turned into
/// the map's here) of the pixels `need`, into `vals`. Per pixel, straight
/// from directions to chart points to colours, eight at a time, queued so
/// that their texels load ahead of filtering (see `Ahead`), or mip-aware
/// (trilinear at each footprint's level, `spread`); per vertex, the pixels
/// hit take texture coordinates interpolated across the triangle.
#[allow(clippy::too_many_arguments)]
pub(super) fn lookups(
    sampler: &Sampler<'_>,
    mapping: &AnyMapping,
    per_vertex: bool,
    mip: Option<(&Trilinear<'_>, &TexelWeights)>,
    mesh: &Mesh,
    hits: &[Option<Hit>],
    need: &[usize],
    dirs: &mut [Vec3],
    spread: &[f32],
    vertex_uv: &[ChartUv],
    to_map: Mat3,
    filter: Filter,
    vals: &mut [[f32; 3]],
) {
    for d in dirs.iter_mut() {
        *d = to_map * *d;
    }
    let mut coords = Vec::new();
    if per_vertex {
        coords.resize(dirs.len(), ChartUv::default());
        forward_slice::<_, Fine>(mapping, dirs, &mut coords);
        for (c, &k) in coords.iter_mut().zip(need) {
            if let Some(hit) = &hits[k] {
                let [a, b, cc] = mesh.triangles[hit.tri as usize].map(|i| vertex_uv[i as usize]);
                *c = ChartUv::new(
                    a.chart,
                    a.u * hit.w[0] + b.u * hit.w[1] + cc.u * hit.w[2],
                    a.v * hit.w[0] + b.v * hit.w[1] + cc.v * hit.w[2],
                );
            }
        }
    }
    if let Some((tri, texels)) = mip {
        // Batches whose every lane reads the map itself (level 0: the
        // background, the flatter parts of an object) take the plain
        // path, their texels loaded ahead; the others read their levels.
        let mut ahead = Ahead::default();
        let mut levels = TrilinearAhead::default();
        for start in (0..vals.len()).step_by(LANES) {
            let at = start..(start + LANES).min(vals.len());
            let q = mapping.forward8::<Fine>(Dir8::from_partial(&dirs[at.clone()]));
            // A footprint of 0 (the background kept at the base) is level
            // 0 whatever its texel: no level to find.
            let spread = &spread[at.clone()];
            if spread.iter().all(|&s| s == 0.0) {
                ahead.push(sampler, &q, filter, at.start, at.len(), vals);
                continue;
            }
            let lod = lod8(texels, &q, spread);
            if lod.simd_eq(f32x8::ZERO).all() {
                ahead.push(sampler, &q, filter, at.start, at.len(), vals);
            } else {
                levels.push(tri, q, lod, (at.start, at.len()), vals);
            }
        }
        levels.drain(tri, vals);
        ahead.drain(sampler, vals);
    } else {
        let mut ahead = Ahead::default();
        for start in (0..vals.len()).step_by(LANES) {
            let at = start..(start + LANES).min(vals.len());
            let q = if per_vertex {
                Uv8::from_partial(&coords[at.clone()])
            } else {
                mapping.forward8::<Fine>(Dir8::from_partial(&dirs[at.clone()]))
            };
            ahead.push(sampler, &q, filter, at.start, at.len(), vals);
        }
        ahead.drain(sampler, vals);
    }
}

/// The radiance towards world direction `d`: the analytic environment
/// exactly, or the map through its mapping (in its axes) and `filter`.
pub(super) fn radiance(
    analytic: Option<&(dyn Fn(Vec3) -> [f32; 3] + Sync)>,
    sampler: Option<&Sampler<'_>>,
    mapping: AnyMapping,
    to_map: Mat3,
    filter: Filter,
    d: Vec3,
) -> [f32; 3] {
    match (analytic, sampler) {
        (Some(f), _) => f(d),
        (None, Some(s)) => mapping
            .forward(to_map * d)
            .map_or([0.0; 3], |c| s.sample(c, filter)),
        (None, None) => [0.0; 3],
    }
}

/// The light-sampling table of `env` for [`Shading::Reference`]: its
/// luminance, as the reference sees it (through `filter` for a map), on a
/// 1024 × 512 latitude-longitude grid ([`EnvSampling`]: cells of 0.35°, fine
/// enough for the built-in sky's 1.2° sun). It evaluates the environment
/// over the whole grid: make it once per environment.
#[cfg_attr(not(feature = "instruments"), allow(dead_code))]
#[cfg_attr(feature = "instruments", visibility::make(pub))]
#[must_use]
pub(crate) fn light_table(env: EnvSource<'_>, filter: Filter) -> EnvSampling {
    match env {
        EnvSource::Analytic(f) => EnvSampling::new(f, LIGHT_TABLE_WIDTH),
        EnvSource::Map(img) => {
            let s = Sampler::new(img);
            let to_map = img.representation().frame.matrix().transpose();
            let m = img.mapping();
            EnvSampling::new(
                &|d| radiance(None, Some(&s), m, to_map, filter, d),
                LIGHT_TABLE_WIDTH,
            )
        }
    }
}
