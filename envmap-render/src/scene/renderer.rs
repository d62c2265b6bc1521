// The renderer: a reflective object in an environment, seen through a
// pinhole camera.

use std::sync::atomic::AtomicBool;

use crate::par::*;
use envmap_core::glam::{Mat3, Vec3};
use envmap_core::AnyMapping;
use envmap_core::{reflect_view, ChartUv};
use envmap_simd::{forward_slice, Dir8, Fine, Mapping8, Uv8, LANES};
use wide::f32x8;

use crate::cancel;
#[cfg(doc)]
use crate::error::Error;
use crate::error::Result;
use crate::filter::oracle::Oracle;
use crate::filter::pyramid::{PreparedLevels, Trilinear, TrilinearAhead};
use crate::filter::sample::{Ahead, Filter, Sampler};
use crate::filter::weights::TexelWeights;
use crate::image::{EnvImage, RgbImage};
use crate::scene::lit::{
    exact_split_sum, reference, EnvSampling, LitEnvironment, LitSampler, Pcg32,
};
use crate::scene::material::Material;
use crate::scene::mesh::Mesh;

/// A pinhole camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Position of the eye.
    pub eye: Vec3,
    /// The point looked at (the centre of the image).
    pub target: Vec3,
    /// The world's up direction (need not be perpendicular to the view).
    pub up: Vec3,
    /// Vertical field of view in degrees.
    pub fov_y_deg: f32,
}

impl Default for Camera {
    /// Looking at the teapot (which stands on z = 0, about 3 units tall) from
    /// the front and a little above.
    fn default() -> Self {
        Self {
            eye: Vec3::new(0.0, -9.5, 4.0),
            target: Vec3::new(0.0, 0.0, 1.4),
            up: Vec3::Z,
            fov_y_deg: 35.0,
        }
    }
}

/// How the environment is looked up on the object.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Mode {
    /// Reflection direction and lookup per pixel (seed `000`).
    #[default]
    PerPixel,
    /// Texture coordinates per vertex, interpolated across triangles (seed `002`).
    PerVertex,
}

/// Rendering options.
#[derive(Clone, Copy, Debug)]
#[non_exhaustive]
pub struct RenderOptions<'a> {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Per-pixel or per-vertex lookups.
    pub mode: Mode,
    /// Supersampling: `samples × samples` sub-pixels per pixel, box-filtered.
    pub samples: u32,
    /// Texture filter.
    pub filter: Filter,
    /// Schlick Fresnel with this reflectance at normal incidence (e.g. 0.04
    /// for glass, 0.9 for polished metal); `None` is a perfect mirror.
    pub fresnel_f0: Option<f32>,
    /// Colour the reflection is multiplied by.
    pub tint: [f32; 3],
    /// Show the environment behind the object (otherwise black).
    pub background: bool,
    /// How the object's surface is shaded: a mirror (the default; with
    /// [`RenderOptions::fresnel_f0`] and [`RenderOptions::tint`]), a
    /// material by the split sum, or its Monte Carlo reference.
    pub shading: Shading<'a>,
    /// Stops the render once set, at the next band of rows, with
    /// [`Error::Cancelled`]; see [`crate::cancel`].
    pub cancel: Option<&'a AtomicBool>,
    /// Mip-aware lookups: per pixel, every lookup in an environment map
    /// (the mirror's reflections and the background) reads a mip
    /// pyramid of the map trilinearly, at the level of the looked-up
    /// ray's footprint (see [Mip-aware lookups](super#mip-aware-lookups)),
    /// so that distant or strongly curved reflections stop aliasing. Off
    /// (the default here), every lookup reads the map itself with
    /// [`RenderOptions::filter`], as seed `000` does. Only with
    /// [`Filter::Bilinear`] in per-pixel mode and an [`EnvSource::Map`];
    /// per-vertex mode (seed `002`), [`Filter::Nearest`] and an analytic
    /// environment are unaffected. `envmap render` turns it on unless
    /// given `--no-mip`.
    pub mip: bool,
    /// For [`RenderOptions::mip`]: the map's levels made beforehand
    /// ([`MipLevels::new`]), so that many renders of one map build them
    /// once; ignored unless made from a map of the environment's mapping
    /// and size (then the [`Renderer`] builds them, as when `None`, into
    /// the memory of the levels it built last).
    pub mip_levels: Option<&'a MipLevels>,
    /// Called from the workers as bands of rows finish, with the bands done
    /// and their number (for a progress bar on long renders: the reference).
    pub progress: Option<Progress<'a>>,
}

/// What a mip-aware render reads below an environment map (the map itself
/// is level 0, read in place): its solid-angle-weighted pyramid from half
/// its size down to 1², each level ready for sampling (made with its
/// border, once, here), and its texels' solid angles; see
/// [Mip-aware lookups](super#mip-aware-lookups). Make it once to render a
/// map many times: a render from it copies nothing.
#[derive(Clone, Debug)]
pub struct MipLevels {
    below: PreparedLevels,
    texels: TexelWeights,
    /// The smallest texel solid angle ([`TexelWeights::smallest`]).
    least: f64,
    mapping: AnyMapping,
    cell: (u32, u32),
    /// Where the levels' charts are laid out.
    atlas: envmap_core::atlas::Atlas,
    /// The texel solid angles of each level from the first down that the
    /// next is made from, for [`MipLevels::rebuild`] (made by its first
    /// call).
    above: Vec<TexelWeights>,
}

impl MipLevels {
    /// The levels below `map`.
    ///
    /// # Errors
    ///
    /// Only if a level cannot be made (see `PreparedLevels::below`).
    pub fn new(map: &EnvImage) -> Result<Self> {
        let (cw, ch) = map.cell_size();
        let mapping = map.mapping();
        let texels = TexelWeights::new(mapping, cw, ch).for_lookups();
        let atlas = Self::atlas_for(map);
        let below = PreparedLevels::below(map, &texels, atlas)?;
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
    fn atlas_for(map: &EnvImage) -> envmap_core::atlas::Atlas {
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
    #[must_use]
    pub fn fits(&self, map: &EnvImage) -> bool {
        map.mapping() == self.mapping && map.cell_size() == self.cell
    }
}

/// A progress callback: `(done, total)`; see [`RenderOptions::progress`].
#[derive(Clone, Copy)]
pub struct Progress<'a>(pub &'a (dyn Fn(u32, u32) + Sync));

impl core::fmt::Debug for Progress<'_> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str("Progress")
    }
}

impl Default for RenderOptions<'_> {
    fn default() -> Self {
        Self {
            width: 640,
            height: 480,
            mode: Mode::PerPixel,
            samples: 1,
            filter: Filter::Bilinear,
            fresnel_f0: None,
            tint: [1.0; 3],
            background: true,
            shading: Shading::Mirror,
            cancel: None,
            mip: false,
            mip_levels: None,
            progress: None,
        }
    }
}

/// How the object is shaded; see [`crate::scene`].
#[derive(Clone, Copy, Debug, Default)]
pub enum Shading<'a> {
    /// A mirror: the environment looked up along R (seed `000`).
    #[default]
    Mirror,
    /// A material by the split sum from baked maps, per pixel, or in
    /// per-vertex mode from the maps' lookup points computed at the
    /// vertices and interpolated across each triangle (seed `002`).
    SplitSum {
        /// The baked maps.
        env: &'a LitEnvironment,
        /// The material.
        material: Material,
        /// Filament's multiscatter energy compensation.
        multiscatter: bool,
        /// Read the chain along the lobe's dominant direction, mix(R, N,
        /// α), as Filament and Frostbite do, instead of R.
        dominant: bool,
    },
    /// The split sum made exact, the measure [`Shading::SplitSum`] is held
    /// to: per pixel, the prefiltered integral of the oracle's input at the
    /// material's own roughness around the same lookup direction, the DFG
    /// integral at the pixel's own N·V and roughness, and the exact
    /// irradiance, combined as the split sum combines them
    /// (`crate::scene::lit::exact_split_sum`); no chain, table or
    /// irradiance map. Slow (an oracle integral per pixel); per-vertex mode
    /// shades per pixel.
    ExactSplitSum {
        /// The input's oracle: the map the split sum's maps are baked
        /// from, read as piecewise constant over its own texels.
        oracle: &'a Oracle<'a>,
        /// The material.
        material: Material,
        /// Filament's multiscatter energy compensation.
        multiscatter: bool,
        /// Around the lobe's dominant direction mix(R, N, α) instead of R,
        /// as [`Shading::SplitSum`]'s `dominant`.
        dominant: bool,
    },
    /// The rendering integral of the environment given to [`render`]
    /// against the material's full BRDF, by Monte Carlo per pixel (looked
    /// up exactly for an analytic environment, bilinear in the map
    /// otherwise): cosine, GGX and light sampling (by the environment's
    /// luminance) combined by the balance heuristic
    /// (`crate::scene::lit::reference`); deterministic, seeded by the pixel.
    Reference {
        /// The material.
        material: Material,
        /// Samples per pixel and per strategy (cosine, GGX, light).
        samples: u32,
        /// Light sampling by the environment's luminance: the table of the
        /// environment given to [`render`] (`light_table`, made once and
        /// shared by every render in it); what finds a small bright sun. A
        /// smooth environment needs only the other two strategies (`None`).
        light: Option<&'a EnvSampling>,
        /// Mixed into every pixel's seed: renders with different seeds are
        /// independent estimates (their difference measures the noise).
        seed: u64,
    },
}

/// The camera's orthonormal basis and projection scale.
#[derive(Clone, Copy, Debug)]
struct View {
    eye: Vec3,
    forward: Vec3,
    right: Vec3,
    up: Vec3,
    tan_y: f32,
    tan_x: f32,
    width: f32,
    height: f32,
}

impl View {
    fn new(cam: &Camera, width: u32, height: u32) -> Self {
        let forward = (cam.target - cam.eye).normalize_or(Vec3::Y);
        let right = forward.cross(cam.up).normalize_or(Vec3::X);
        let up = right.cross(forward);
        let tan_y = (cam.fov_y_deg.clamp(1.0, 170.0).to_radians() * 0.5).tan();
        Self {
            eye: cam.eye,
            forward,
            right,
            up,
            tan_y,
            tan_x: tan_y * width as f32 / height as f32,
            width: width as f32,
            height: height as f32,
        }
    }

    /// The view ray through pixel position `(x, y)` (pixel units, y down).
    fn ray(&self, x: f32, y: f32) -> Vec3 {
        let sx = (2.0 * x / self.width - 1.0) * self.tan_x;
        let sy = (1.0 - 2.0 * y / self.height) * self.tan_y;
        (self.forward + sx * self.right + sy * self.up).normalize()
    }

    /// Screen position (pixel units) and view depth of a world point.
    fn project(&self, p: Vec3) -> (f32, f32, f32) {
        let d = p - self.eye;
        let z = d.dot(self.forward);
        let x = d.dot(self.right) / (z * self.tan_x);
        let y = d.dot(self.up) / (z * self.tan_y);
        (
            (x + 1.0) * 0.5 * self.width,
            (1.0 - y) * 0.5 * self.height,
            z,
        )
    }
}

/// The nearest surface found at one pixel: triangle and perspective-correct
/// barycentric weights.
#[derive(Clone, Copy, Debug)]
struct Hit {
    tri: u32,
    w: [f32; 3],
    inv_z: f32,
}

const NEAR: f32 = 1e-3;
/// The width of [`light_table`]'s grid.
#[cfg_attr(not(feature = "instruments"), allow(dead_code))]
const LIGHT_TABLE_WIDTH: u32 = 1024;
const BAND: u32 = 16;

/// Where reflected directions get their radiance.
#[derive(Clone, Copy)]
pub enum EnvSource<'a> {
    /// An environment map, looked up through its mapping and filtered.
    Map(&'a EnvImage),
    /// An analytic environment evaluated at the exact direction (world axes,
    /// z up): the reference the maps are measured against. Per-vertex mode
    /// has no texture coordinates here and shades per pixel.
    Analytic(&'a (dyn Fn(Vec3) -> [f32; 3] + Sync)),
}

impl core::fmt::Debug for EnvSource<'_> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            EnvSource::Map(img) => {
                write!(f, "Map({} {}×{})", img.mapping(), img.width(), img.height())
            }
            EnvSource::Analytic(_) => f.write_str("Analytic"),
        }
    }
}

/// The renderer: draws meshes in environments frame after frame, and keeps
/// what a frame needs from one to the next, so that a render allocates
/// nothing it made before: the workers' band buffers and, for mip-aware
/// renders ([`RenderOptions::mip`]) without levels given, the levels of
/// the last map, which the next render of a map of the same mapping and
/// size builds into ([`MipLevels::rebuild`]: no level allocated, no page of
/// memory new to the process). Memory new to the process costs the system
/// more to hand out than the levels cost to build; a renderer reused from
/// frame to frame pays it once. Dropping the renderer frees it all.
///
/// ```
/// use envmap_render::scene::{environments, Camera, EnvSource, Mesh, RenderOptions, Renderer};
/// let sky = environments::sky(64, 32);
/// let mut renderer = Renderer::new();
/// let opts = RenderOptions { width: 32, height: 24, ..RenderOptions::default() };
/// for _frame in 0..2 {
///     let img = renderer.render(&Mesh::sphere(8), EnvSource::Map(&sky), &Camera::default(), &opts)?;
///     assert_eq!((img.width, img.height), (32, 24));
/// }
/// # Ok::<(), envmap_render::Error>(())
/// ```
#[derive(Default)]
pub struct Renderer {
    /// The levels the last mip-aware render without levels given made,
    /// for the next to build into.
    levels: Option<MipLevels>,
    /// Band buffers, lent to a worker for a frame and given back after.
    scratch: std::sync::Mutex<Vec<BandScratch>>,
}

impl core::fmt::Debug for Renderer {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Renderer")
            .field("levels", &self.levels.is_some())
            .finish_non_exhaustive()
    }
}

impl Renderer {
    /// A renderer holding no memory yet.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Renders `mesh` (in world coordinates) in `env`, shaded as
    /// `opts.shading` says (a mirror by default).
    ///
    /// # Errors
    ///
    /// A mesh that [`Mesh::validate`] refuses ([`Error::MeshIndex`] for a
    /// triangle past the last vertex, [`Error::MeshCounts`],
    /// [`Error::MeshPosition`], [`Error::MeshNormal`]), checked before
    /// anything is drawn; [`Error::Cancelled`], once `opts.cancel` is set
    /// (checked at every band of rows).
    pub fn render(
        &mut self,
        mesh: &Mesh,
        env: EnvSource<'_>,
        cam: &Camera,
        opts: &RenderOptions,
    ) -> Result<RgbImage> {
        // A triangle's index past the last vertex would be read below.
        mesh.validate()?;
        let (map, analytic) = match env {
            EnvSource::Map(img) => (Some(img), None),
            EnvSource::Analytic(f) => (None, Some(f)),
        };
        let per_vertex = opts.mode == Mode::PerVertex && analytic.is_none();
        // Mip-aware lookups: the map's levels below its own (the map is
        // read in place as level 0), given or built for this render, and
        // the base's texel solid angles (the texel's angular size where a
        // lookup lands).
        let mip = match map {
            Some(e) if opts.mip && opts.filter == Filter::Bilinear && !per_vertex => {
                match opts.mip_levels.filter(|l| l.fits(e)) {
                    Some(l) => Some((e, l)),
                    None => Some((e, levels_of(&mut self.levels, e)?)),
                }
            }
            _ => None,
        };
        let frame = Frame::new(mesh, map, analytic, mip, cam, opts);
        let bins = frame.bins();
        let mut hi = vec![[0.0f32; 3]; (frame.w * frame.h) as usize];
        let bands_done = std::sync::atomic::AtomicU32::new(0);
        let total_bands = bins.len() as u32;
        let pool = &self.scratch;
        hi.par_chunks_mut((frame.w * BAND) as usize)
            .zip(bins.par_iter())
            .enumerate()
            .for_each_init(
                || Lent::from(pool),
                |scratch, (band, (px, tris))| {
                    if cancel::is_set(opts.cancel) {
                        return;
                    }
                    frame.band(&mut scratch.buffers, band as u32 * BAND, px, tris);
                    if let Some(Progress(tick)) = opts.progress {
                        let done =
                            bands_done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
                        tick(done, total_bands);
                    }
                },
            );
        cancel::check(opts.cancel)?;
        Ok(downsample(hi, frame.w, frame.h, frame.s))
    }
}

/// The levels of `map`, built into the memory of the levels `held` where
/// they have its geometry, and held there for the next render.
fn levels_of<'h>(held: &'h mut Option<MipLevels>, map: &EnvImage) -> Result<&'h MipLevels> {
    let levels = match held.take() {
        Some(mut l) if l.fits(map) => {
            l.rebuild(map)?;
            l
        }
        other => {
            // Levels of another map go before these are made.
            drop(other);
            MipLevels::new(map)?
        }
    };
    Ok(held.insert(levels))
}

/// A worker's band buffers for one frame, taken from the renderer's and
/// given back to them when the worker is done.
struct Lent<'p> {
    buffers: BandScratch,
    pool: &'p std::sync::Mutex<Vec<BandScratch>>,
}

impl<'p> Lent<'p> {
    fn from(pool: &'p std::sync::Mutex<Vec<BandScratch>>) -> Self {
        let buffers = lock(pool).pop().unwrap_or_default();
        Self { buffers, pool }
    }
}

impl Drop for Lent<'_> {
    fn drop(&mut self) {
        lock(self.pool).push(core::mem::take(&mut self.buffers));
    }
}

/// The band buffers' pool; a worker that panicked while holding it left
/// only whole buffers in it.
fn lock(pool: &std::sync::Mutex<Vec<BandScratch>>) -> std::sync::MutexGuard<'_, Vec<BandScratch>> {
    pool.lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// What every band of one frame reads: the view, the environment and how
/// it is looked up, the mesh's vertices projected, and what per-vertex and
/// lit shading computed at the vertices.
struct Frame<'a> {
    mesh: &'a Mesh,
    opts: &'a RenderOptions<'a>,
    view: View,
    /// The supersampled image's size, and the supersampling.
    w: u32,
    h: u32,
    s: u32,
    sampler: Option<Sampler<'a>>,
    analytic: Option<&'a (dyn Fn(Vec3) -> [f32; 3] + Sync)>,
    /// World → the map's own axes (see `Representation::frame`).
    to_map: Mat3,
    mapping: AnyMapping,
    per_vertex: bool,
    trilinear: Option<Trilinear<'a>>,
    texels: Option<&'a TexelWeights>,
    background_at_base: bool,
    projected: Vec<(f32, f32, f32)>,
    /// Per-vertex mode: R's chart point at each vertex.
    vertex_uv: Vec<ChartUv>,
    lit_sampler: Option<LitSampler<'a>>,
    per_vertex_lit: bool,
    /// Lit per vertex: the lookup points at each vertex.
    vertex_lit: Vec<(ChartUv, ChartUv)>,
}

impl<'a> Frame<'a> {
    /// Everything computed once per frame: per vertex, the projection, and
    /// R's chart point (per-vertex mode) or the split sum's lookup points
    /// (lit per vertex: seed `002`, interpolated across each triangle in
    /// its first vertex's chart, seams and all).
    fn new(
        mesh: &'a Mesh,
        env: Option<&'a EnvImage>,
        analytic: Option<&'a (dyn Fn(Vec3) -> [f32; 3] + Sync)>,
        mip: Option<(&'a EnvImage, &'a MipLevels)>,
        cam: &Camera,
        opts: &'a RenderOptions<'a>,
    ) -> Self {
        let s = opts.samples.clamp(1, 8);
        let (w, h) = (opts.width.max(1) * s, opts.height.max(1) * s);
        let view = View::new(cam, w, h);
        let to_map = env.map_or(Mat3::IDENTITY, |e| {
            e.representation().frame.matrix().transpose()
        });
        let mapping = env.map_or(AnyMapping::LatLong, EnvImage::mapping);
        let per_vertex = opts.mode == Mode::PerVertex && analytic.is_none();
        let projected = mesh.positions.iter().map(|p| view.project(*p)).collect();
        let vertex_uv = if per_vertex {
            let dirs: Vec<Vec3> = mesh
                .positions
                .iter()
                .zip(&mesh.normals)
                .map(|(p, n)| to_map * reflect_view(*n, (view.eye - *p).normalize_or(Vec3::Z)))
                .collect();
            let mut uv = vec![ChartUv::default(); dirs.len()];
            forward_slice::<_, Fine>(&mapping, &dirs, &mut uv);
            uv
        } else {
            Vec::new()
        };
        let lit_sampler = match opts.shading {
            Shading::SplitSum { env, .. } => Some(env.sampler()),
            _ => None,
        };
        let per_vertex_lit = opts.mode == Mode::PerVertex && lit_sampler.is_some();
        let vertex_lit = match (&lit_sampler, opts.shading) {
            (
                Some(ls),
                Shading::SplitSum {
                    material, dominant, ..
                },
            ) if per_vertex_lit => mesh
                .positions
                .iter()
                .zip(&mesh.normals)
                .map(|(p, n)| {
                    let n = n.normalize_or(Vec3::Z);
                    ls.lookup_points(
                        &material,
                        n,
                        (view.eye - *p).normalize_or(Vec3::Z),
                        dominant,
                    )
                })
                .collect(),
            _ => Vec::new(),
        };
        Self {
            mesh,
            opts,
            w,
            h,
            s,
            sampler: env.map(Sampler::new),
            analytic,
            to_map,
            mapping,
            per_vertex,
            trilinear: mip.map(|(base, l)| Trilinear::over_prepared(base, &l.below)),
            texels: mip.map(|(_, l)| &l.texels),
            background_at_base: mip.is_some_and(|(_, l)| background_stays_at_base(&view, l.least)),
            view,
            projected,
            vertex_uv,
            lit_sampler,
            per_vertex_lit,
            vertex_lit,
        }
    }

    /// The triangles, binned by the bands of rows they touch.
    fn bins(&self) -> Vec<Vec<u32>> {
        let h = self.h;
        let mut bins: Vec<Vec<u32>> = vec![Vec::new(); h.div_ceil(BAND) as usize];
        for (t, tri) in self.mesh.triangles.iter().enumerate() {
            let v = tri.map(|i| self.projected[i as usize]);
            if v.iter()
                .any(|p| p.2 <= NEAR || !p.0.is_finite() || !p.1.is_finite())
            {
                continue;
            }
            let ymin = v.iter().map(|p| p.1).fold(f32::INFINITY, f32::min).max(0.0);
            let ymax = v
                .iter()
                .map(|p| p.1)
                .fold(f32::NEG_INFINITY, f32::max)
                .min(h as f32 - 1.0);
            if ymin > ymax {
                continue;
            }
            for b in (ymin as u32 / BAND)..=(ymax as u32 / BAND) {
                bins[b as usize].push(t as u32);
            }
        }
        bins
    }

    /// The radiance the reference sees towards world direction `d`: the
    /// environment exactly (analytic) or through the map.
    fn look(&self, d: Vec3) -> [f32; 3] {
        radiance(
            self.analytic,
            self.sampler.as_ref(),
            self.mapping,
            self.to_map,
            self.opts.filter,
            d,
        )
    }

    /// One band of rows from `y0`, its pixels `px` (black), the triangles
    /// `tris` touching it: raster, shading of lit materials, the lookups of
    /// the mirror and the background.
    fn band(&self, scratch: &mut BandScratch, y0: u32, px: &mut [[f32; 3]], tris: &[u32]) {
        let BandScratch { hits, hit_at, .. } = scratch;
        let rows = (px.len() / self.w as usize) as u32;
        hits.clear();
        hits.resize(px.len(), None);
        for &t in tris {
            let v = self.mesh.triangles[t as usize].map(|i| self.projected[i as usize]);
            raster(&v, t, y0, rows, self.w, hits);
        }
        // The pixels hit, in order, found in one pass over `hits` for the
        // shading and the lookups (a mirror with its background looks up
        // every pixel and needs no list).
        let mirror = matches!(self.opts.shading, Shading::Mirror);
        hit_at.clear();
        if !(mirror && self.opts.background) {
            hit_at.extend((0..px.len()).filter(|&k| hits[k].is_some()));
        }
        // Lit materials: shaded here, straight into the band (which starts
        // black); the lookups then fill only the background. A mirror has
        // no lit pixels.
        if !mirror {
            self.shade(hits, hit_at, y0, px);
        }
        self.look_up(scratch, y0, px);
    }

    /// Shades the pixels of a band hit (`hit_at`) with the lit material:
    /// the split sum eight at a time per pixel, the exact split sum for the
    /// band's hits at once (the oracle's integrals run in parallel over
    /// them), per vertex and the reference one at a time.
    fn shade(&self, hits: &[Option<Hit>], hit_at: &[usize], y0: u32, px: &mut [[f32; 3]]) {
        let (mesh, view) = (self.mesh, &self.view);
        match (&self.lit_sampler, self.opts.shading) {
            (
                Some(ls),
                Shading::SplitSum {
                    material,
                    multiscatter,
                    dominant,
                    ..
                },
            ) if !self.per_vertex_lit => {
                for chunk in hit_at.chunks(LANES) {
                    let (mut ns, mut vs) = ([Vec3::Z; LANES], [Vec3::Z; LANES]);
                    for (j, &k) in chunk.iter().enumerate() {
                        if let Some(hit) = &hits[k] {
                            (ns[j], vs[j]) = surface(mesh, hit, view);
                        }
                    }
                    let mut out = [[0.0f32; 3]; LANES];
                    let n = chunk.len();
                    ls.shade8(
                        &material,
                        &ns[..n],
                        &vs[..n],
                        multiscatter,
                        dominant,
                        &mut out,
                    );
                    for (j, &k) in chunk.iter().enumerate() {
                        px[k] = out[j];
                    }
                }
            }
            (
                _,
                Shading::ExactSplitSum {
                    oracle,
                    material,
                    multiscatter,
                    dominant,
                },
            ) => {
                let (ns, vs): (Vec<Vec3>, Vec<Vec3>) = hit_at
                    .iter()
                    .filter_map(|&k| hits[k].as_ref().map(|hit| surface(mesh, hit, view)))
                    .unzip();
                let out = exact_split_sum(oracle, &material, &ns, &vs, multiscatter, dominant);
                for (&k, o) in hit_at.iter().zip(out) {
                    px[k] = o;
                }
            }
            _ => {
                for (k, hit) in hits.iter().enumerate() {
                    if let Some(hit) = hit {
                        px[k] = self.shade_one(hit, y0 + k as u32 / self.w, k as u32 % self.w);
                    }
                }
            }
        }
    }

    /// One pixel `(x, y)` hit, lit per vertex (from the lookup points
    /// interpolated across the triangle) or by the reference.
    fn shade_one(&self, hit: &Hit, y: u32, x: u32) -> [f32; 3] {
        let (n, v) = surface(self.mesh, hit, &self.view);
        match (&self.lit_sampler, self.opts.shading) {
            (
                Some(ls),
                Shading::SplitSum {
                    material,
                    multiscatter,
                    ..
                },
            ) if self.per_vertex_lit => {
                let tri = self.mesh.triangles[hit.tri as usize];
                let lerp = |pick: fn(&(ChartUv, ChartUv)) -> ChartUv| {
                    let [p, q, r] = tri.map(|i| pick(&self.vertex_lit[i as usize]));
                    ChartUv::new(
                        p.chart,
                        p.u * hit.w[0] + q.u * hit.w[1] + r.u * hit.w[2],
                        p.v * hit.w[0] + q.v * hit.w[1] + r.v * hit.w[2],
                    )
                };
                let (sp, ir) = (lerp(|x| x.0), lerp(|x| x.1));
                ls.shade_at(&material, n.dot(v), sp, ir, multiscatter)
            }
            (
                _,
                Shading::Reference {
                    material,
                    samples,
                    light,
                    seed,
                },
            ) => {
                let pixel = u64::from(y) * u64::from(self.w) + u64::from(x);
                let mut rng = Pcg32::new(pixel ^ seed.rotate_left(40));
                let look = |d: Vec3| self.look(d);
                reference(&look, light, &material, n, v, samples, &mut rng)
            }
            _ => [0.0; 3],
        }
    }

    /// The environment lookups of a band: the reflection of a mirror's
    /// pixels, the view ray of the background's (when shown), each with
    /// its footprint when mip-aware, looked up and tinted into `px`.
    fn look_up(&self, scratch: &mut BandScratch, y0: u32, px: &mut [[f32; 3]]) {
        let BandScratch {
            hits,
            hit_at,
            need,
            lookups: band_dirs,
            spread,
            slot,
            buffer,
        } = scratch;
        let (opts, w) = (self.opts, self.w);
        let mirror = matches!(opts.shading, Shading::Mirror);
        // `need[j]` is the pixel of lookup `j`.
        need.clear();
        match (mirror, opts.background) {
            (true, true) => need.extend(0..px.len()),
            (true, false) => need.extend_from_slice(hit_at),
            (false, true) => missed(hit_at, px.len(), need),
            (false, false) => {}
        }
        let (hits, need): (&[Option<Hit>], &[usize]) = (hits, need);
        band_lookups(
            self.mesh,
            &self.view,
            hits,
            need,
            w,
            y0,
            opts.fresnel_f0,
            band_dirs,
        );
        let BandLookups {
            dirs,
            fresnel: fres,
            on_object,
        } = band_dirs;
        // With mip-aware lookups, each direction's footprint: the angle it
        // turns through from one pixel to the next.
        spread.clear();
        if self.trilinear.is_some() {
            let bg = self.background_at_base;
            let (on, out) = (&on_object[..], (&mut *spread, &mut *slot));
            let (mesh, projected, view) = (self.mesh, &self.projected, &self.view);
            footprints(mesh, projected, view, hits, need, dirs, w, y0, bg, on, out);
        }
        // The looked-up values, `vals[j]` for pixel `need[j]`: straight
        // into the band when every pixel is looked up (a mirror with its
        // background), else into a buffer scattered afterwards.
        let every = need.len() == px.len();
        buffer.clear();
        if !every {
            buffer.resize(need.len(), [0.0; 3]);
        }
        let vals: &mut [[f32; 3]] = if every { &mut *px } else { &mut *buffer };
        if let (Some(sampler), None) = (self.sampler.as_ref(), self.analytic) {
            lookups(
                sampler,
                &self.mapping,
                self.per_vertex,
                self.trilinear.as_ref().zip(self.texels),
                self.mesh,
                hits,
                need,
                dirs,
                spread,
                &self.vertex_uv,
                self.to_map,
                opts.filter,
                vals,
            );
        } else {
            let f = self.analytic.unwrap_or(&|_| [0.0; 3]);
            for (v, d) in vals.iter_mut().zip(dirs.iter()) {
                *v = f(*d);
            }
        }
        let tinted = |v: [f32; 3], f: f32| [0, 1, 2].map(|c| v[c] * f * opts.tint[c]);
        if every {
            for ((out, hit), f) in px.iter_mut().zip(hits).zip(fres.iter()) {
                if hit.is_some() {
                    *out = tinted(*out, *f);
                }
            }
        } else {
            // The lit pixels are in place; the rest black but these.
            for ((&k, v), f) in need.iter().zip(buffer.iter()).zip(fres.iter()) {
                px[k] = match hits[k] {
                    None => *v,
                    Some(_) => tinted(*v, *f),
                };
            }
        }
    }
}

/// The buffers a worker's bands are made in, kept from band to band and,
/// in the [`Renderer`], from frame to frame: allocating them for each band
/// (a megabyte and a half for a band of a 1080p frame) hands the system
/// pages to fault in and zero.
#[derive(Default)]
struct BandScratch {
    /// What each pixel of the band sees.
    hits: Vec<Option<Hit>>,
    /// The pixels hit, in order.
    hit_at: Vec<usize>,
    /// The pixels looked up, in order.
    need: Vec<usize>,
    lookups: BandLookups,
    /// The lookups' footprints, and [`footprints`]' pixel-to-lookup table.
    spread: Vec<f32>,
    slot: Vec<u32>,
    /// The looked-up values where not every pixel is looked up.
    buffer: Vec<[f32; 3]>,
}

/// What a band's lookups start from ([`band_lookups`]).
#[derive(Default)]
struct BandLookups {
    /// Lookup `j`'s direction (world axes): the reflection at a pixel hit,
    /// else the view ray.
    dirs: Vec<Vec3>,
    /// Lookup `j`'s Schlick factor (1 without `fresnel_f0`, and off the
    /// object).
    fresnel: Vec<f32>,
    /// The lookups of pixels hit, ascending: the ones whose footprints
    /// [`footprints`] measures when the background stays at the base.
    on_object: Vec<usize>,
}

/// The directions to look up for the pixels `need` of a band of rows from
/// `y0`, `w` wide: the reflection (per pixel) where the pixel is hit, the
/// view ray through its centre elsewhere; with each, Schlick's factor for
/// `fresnel_f0`, and which lookups are on the object; into `out` (what it
/// held is dropped).
#[allow(clippy::too_many_arguments)]
fn band_lookups(
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
                    let c = n.dot(vv).clamp(0.0, 1.0);
                    fresnel[j] = f0 + (1.0 - f0) * (1.0 - c).powi(5);
                }
                reflect_view(n, vv)
            }
        };
        dirs.push(d);
    }
}

/// The indices below `n` that are not in `at` (ascending), in order,
/// added to `out`: the background of a band from its pixels hit.
fn missed(at: &[usize], n: usize, out: &mut Vec<usize>) {
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
fn lookups(
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
fn radiance(
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
fn footprint(
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
fn footprints(
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
fn background_stays_at_base(view: &View, least: f64) -> bool {
    let dx = 2.0 * f64::from(view.tan_x) / f64::from(view.width);
    let dy = 2.0 * f64::from(view.tan_y) / f64::from(view.height);
    let s = dx.max(dy) * 1.001 + 1e-6;
    s * s <= 3.99 * least
}

/// Added to every mip-aware lookup's level: one level finer than the
/// footprint's own (see [Mip-aware lookups](super#mip-aware-lookups)).
const LOD_BIAS: f32 = -1.0;

/// Perspective-correct weights of screen point `(px, py)` on the plane of a
/// projected triangle, inside it or not (`None` if degenerate).
fn weights_at(v: &[(f32, f32, f32); 3], px: f32, py: f32) -> Option<[f32; 3]> {
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
fn lod8(texels: &TexelWeights, q: &Uv8, spread: &[f32]) -> f32x8 {
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

/// The interpolated unit normal at a hit and the unit vector from it to
/// the eye.
#[inline(always)]
fn surface(mesh: &Mesh, hit: &Hit, view: &View) -> (Vec3, Vec3) {
    let [a, b, c] = mesh.triangles[hit.tri as usize].map(|i| i as usize);
    let n = (mesh.normals[a] * hit.w[0] + mesh.normals[b] * hit.w[1] + mesh.normals[c] * hit.w[2])
        .normalize_or(Vec3::Z);
    let p =
        mesh.positions[a] * hit.w[0] + mesh.positions[b] * hit.w[1] + mesh.positions[c] * hit.w[2];
    (n, (view.eye - p).normalize_or(-view.forward))
}

/// Rasterizes one projected triangle into the band starting at row `y0`,
/// keeping the nearest hit per pixel (largest 1/z).
fn raster(v: &[(f32, f32, f32); 3], t: u32, y0: u32, rows: u32, w: u32, hits: &mut [Option<Hit>]) {
    let area = (v[1].0 - v[0].0) * (v[2].1 - v[0].1) - (v[2].0 - v[0].0) * (v[1].1 - v[0].1);
    if area.abs() < 1e-12 || !area.is_finite() {
        return;
    }
    let xmin = v
        .iter()
        .map(|p| p.0)
        .fold(f32::INFINITY, f32::min)
        .floor()
        .max(0.0) as u32;
    let xmax = v
        .iter()
        .map(|p| p.0)
        .fold(f32::NEG_INFINITY, f32::max)
        .ceil()
        .min(w as f32 - 1.0);
    if xmax < 0.0 {
        return;
    }
    let xmax = xmax as u32;
    let ymin = v
        .iter()
        .map(|p| p.1)
        .fold(f32::INFINITY, f32::min)
        .floor()
        .max(y0 as f32) as u32;
    let ymax = v
        .iter()
        .map(|p| p.1)
        .fold(f32::NEG_INFINITY, f32::max)
        .ceil()
        .min((y0 + rows) as f32 - 1.0);
    if ymax < y0 as f32 {
        return;
    }
    let ymax = ymax as u32;
    let inv_area = 1.0 / area;
    let inv_z = [1.0 / v[0].2, 1.0 / v[1].2, 1.0 / v[2].2];
    for y in ymin..=ymax {
        let py = y as f32 + 0.5;
        for x in xmin..=xmax {
            let px = x as f32 + 0.5;
            // Screen-space barycentrics from edge functions.
            let b0 = ((v[1].0 - px) * (v[2].1 - py) - (v[2].0 - px) * (v[1].1 - py)) * inv_area;
            let b1 = ((v[2].0 - px) * (v[0].1 - py) - (v[0].0 - px) * (v[2].1 - py)) * inv_area;
            let b2 = 1.0 - b0 - b1;
            if b0 < 0.0 || b1 < 0.0 || b2 < 0.0 {
                continue;
            }
            let iz = b0 * inv_z[0] + b1 * inv_z[1] + b2 * inv_z[2];
            let k = ((y - y0) * w + x) as usize;
            if hits[k].is_some_and(|h| h.inv_z >= iz) {
                continue;
            }
            // Perspective-correct weights.
            let wts = [b0 * inv_z[0] / iz, b1 * inv_z[1] / iz, b2 * inv_z[2] / iz];
            hits[k] = Some(Hit {
                tri: t,
                w: wts,
                inv_z: iz,
            });
        }
    }
}

/// Box-filters an image `s` times larger in each direction.
fn downsample(hi: Vec<[f32; 3]>, w: u32, h: u32, s: u32) -> RgbImage {
    if s == 1 {
        return RgbImage {
            width: w,
            height: h,
            pixels: hi,
        };
    }
    let (ow, oh) = (w / s, h / s);
    let mut pixels = vec![[0.0f32; 3]; (ow * oh) as usize];
    let inv = 1.0 / (s * s) as f32;
    for (k, out) in pixels.iter_mut().enumerate() {
        let (x, y) = (k as u32 % ow, k as u32 / ow);
        let mut acc = [0.0f32; 3];
        for dy in 0..s {
            for dx in 0..s {
                let p = hi[((y * s + dy) * w + x * s + dx) as usize];
                for c in 0..3 {
                    acc[c] += p[c];
                }
            }
        }
        *out = acc.map(|a| a * inv);
    }
    RgbImage {
        width: ow,
        height: oh,
        pixels,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A band's background from its pixels hit: every index not hit, in
    /// order, whether hits start, end or run together.
    #[test]
    fn the_background_is_every_pixel_not_hit() {
        let n = 12;
        for at in [
            vec![],
            vec![0],
            vec![11],
            vec![0, 1, 2],
            vec![3, 4, 9, 11],
            (0..12).collect(),
        ] {
            let want: Vec<usize> = (0..n).filter(|k| !at.contains(k)).collect();
            let mut got = Vec::new();
            missed(&at, n, &mut got);
            assert_eq!(got, want, "{at:?}");
        }
        let mut none = Vec::new();
        missed(&[], 0, &mut none);
        assert!(none.is_empty());
    }

    /// `lod8`'s level (log2 eight at a time through `wide`'s `ln`) against
    /// the same formula in f64 from the texel's exact solid angle, over
    /// footprints from 10⁻⁶ to 1 rad at texels across a cube face (centre
    /// to corner): within 10⁻⁵ of a level everywhere, and 0 where the f64
    /// level is at most 0.
    #[test]
    fn lod8_levels_are_the_f64_formula() {
        let n = 256;
        let texels = TexelWeights::new(AnyMapping::Cube, n, n);
        let mut worst = (0.0f64, 0.0f32, 0.0f32);
        for k in 0..200 {
            let s = 1e-6f32 * 10f32.powf(6.0 * k as f32 / 199.0);
            let uvs: [ChartUv; 8] = core::array::from_fn(|l| {
                let t = (l as f32 + 0.5) / 8.0 * 0.5;
                ChartUv::new(l as u32 % 6, t, t * 0.9)
            });
            let q = Uv8::from_chart_uvs(&uvs);
            let got = lod8(&texels, &q, &[s; 8]).to_array();
            for (c, g) in uvs.iter().zip(got) {
                let (i, j) = ((c.u * n as f32) as u32, (c.v * n as f32) as u32);
                let omega = texels.get(c.chart, i, j);
                let want = ((f64::from(s) / omega.sqrt()).log2() + f64::from(LOD_BIAS)).max(0.0);
                let e = (f64::from(g) - want).abs();
                if e > worst.0 {
                    worst = (e, s, c.u);
                }
            }
        }
        println!(
            "lod8 against f64: worst {:.2e} levels (footprint {:.2e} rad, u {})",
            worst.0, worst.1, worst.2
        );
        assert!(worst.0 < 1e-5, "{worst:?}");
    }

    /// Where [`background_stays_at_base`] holds, every background pixel's
    /// measured footprint gives level 0 (checked on a grid of pixels out
    /// to the image's corners, at several fields of view and map sizes);
    /// and it does hold for the render bench's view, and not for a coarse
    /// wide one.
    #[test]
    fn a_background_kept_at_the_base_would_read_the_base() {
        use envmap_core::Mapping as _;
        let mut held = Vec::new();
        for (m, n) in [
            (AnyMapping::Cube, 1024),
            (AnyMapping::Cube, 64),
            (AnyMapping::LatLong, 512),
        ] {
            let (cw, ch) = (n * m.atlas().cell_aspect_w, n * m.atlas().cell_aspect_h);
            let texels = TexelWeights::new(m, cw, ch);
            for fov in [10.0, 35.0, 90.0, 150.0] {
                for (w, h) in [(64, 48), (640, 480), (1920, 1080)] {
                    let cam = Camera {
                        fov_y_deg: fov,
                        ..Camera::default()
                    };
                    let view = View::new(&cam, w, h);
                    if !background_stays_at_base(&view, texels.smallest()) {
                        continue;
                    }
                    held.push((m, n, fov, w));
                    let mut spread = Vec::new();
                    let mut dirs = Vec::new();
                    for a in 0..=16 {
                        for b in 0..=16 {
                            let x = (w - 2) as f32 * a as f32 / 16.0 + 0.5;
                            let y = (h - 2) as f32 * b as f32 / 16.0 + 0.5;
                            let d = view.ray(x, y);
                            let (dx, dy) = (view.ray(x + 1.0, y) - d, view.ray(x, y + 1.0) - d);
                            spread.push(dx.length().max(dy.length()));
                            dirs.push(d);
                        }
                    }
                    for (d, s) in dirs.chunks(LANES).zip(spread.chunks(LANES)) {
                        let q = m.forward8::<Fine>(Dir8::from_partial(d));
                        let lod = lod8(&texels, &q, s).to_array();
                        assert!(
                            lod[..d.len()].iter().all(|&l| l == 0.0),
                            "{m} {n} fov {fov} {w}x{h}: {lod:?}"
                        );
                    }
                }
            }
        }
        assert!(
            held.contains(&(AnyMapping::Cube, 1024, 35.0, 1920)),
            "{held:?}"
        );
        assert!(
            !held.contains(&(AnyMapping::Cube, 1024, 90.0, 64)),
            "{held:?}"
        );
    }

    /// [`sphere_band`]'s mesh, view, projected vertices and hits.
    type SphereBand = (Mesh, View, Vec<(f32, f32, f32)>, Vec<Option<Hit>>);

    /// A sphere of radius `r` whose nearest point is `gap` in front of the
    /// eye (`detail` segments around), seen head-on in a 64 × 64 view of
    /// 30°: the mesh, the view, its projected vertices and the hits of the
    /// band of `rows` rows from `y0`.
    fn sphere_band(r: f32, gap: f32, detail: u32, y0: u32, rows: u32) -> SphereBand {
        let mut mesh = Mesh::sphere(r, detail, detail / 2);
        for p in &mut mesh.positions {
            *p += Vec3::new(0.0, r + gap, 0.0);
        }
        let cam = Camera {
            eye: Vec3::ZERO,
            target: Vec3::Y,
            up: Vec3::Z,
            fov_y_deg: 30.0,
        };
        let w = 64;
        let view = View::new(&cam, w, 64);
        let projected: Vec<_> = mesh.positions.iter().map(|p| view.project(*p)).collect();
        let mut hits = vec![None; (w * rows) as usize];
        for (t, tri) in mesh.triangles.iter().enumerate() {
            let v = tri.map(|i| projected[i as usize]);
            if v.iter().all(|p| p.2 > NEAR) {
                raster(&v, t as u32, y0, rows, w, &mut hits);
            }
        }
        (mesh, view, projected, hits)
    }

    /// A band's lookups on the object are listed, every one of them, for
    /// each way a band chooses its lookups (every pixel, the pixels hit,
    /// the background); measured from that list with the background kept
    /// at the base, their footprints are the ones measured pixel by pixel,
    /// bit for bit, and every other footprint is 0. The buffers are reused
    /// from one way to the next, as a worker reuses them from band to band.
    #[test]
    fn the_lookups_on_the_object_are_listed_and_measured() {
        let (w, y0) = (64, 24);
        let (mesh, view, projected, hits) = sphere_band(1.0, 7.0, 48, y0, 16);
        let hit_at: Vec<usize> = (0..hits.len()).filter(|&k| hits[k].is_some()).collect();
        assert!(hit_at.len() > 100 && hit_at.len() < hits.len() - 100);
        let mut background = Vec::new();
        missed(&hit_at, hits.len(), &mut background);
        let (mut band, mut all, mut kept, mut slot) = Default::default();
        for need in [
            (0..hits.len()).collect::<Vec<_>>(),
            hit_at.clone(),
            background,
        ] {
            band_lookups(&mesh, &view, &hits, &need, w, y0, None, &mut band);
            let want: Vec<usize> = (0..need.len())
                .filter(|&j| hits[need[j]].is_some())
                .collect();
            assert_eq!(band.on_object, want);
            assert_eq!(
                (band.dirs.len(), band.fresnel.len()),
                (need.len(), need.len())
            );
            let (dirs, on) = (&band.dirs, &band.on_object);
            let args = (
                &mesh,
                &projected[..],
                &view,
                &hits[..],
                &need[..],
                &dirs[..],
            );
            let measured = |kept_at_base: bool, out: &mut Vec<f32>, slot: &mut Vec<u32>| {
                let (m, p, v, h, n, d) = args;
                footprints(m, p, v, h, n, d, w, y0, kept_at_base, on, (out, slot));
            };
            measured(false, &mut all, &mut slot);
            measured(true, &mut kept, &mut slot);
            assert_eq!((all.len(), kept.len()), (need.len(), need.len()));
            for (j, (a, k)) in all.iter().zip(&kept).enumerate() {
                if on.contains(&j) {
                    assert!(*a > 0.0 && a.to_bits() == k.to_bits(), "{j}: {a} {k}");
                } else {
                    assert_eq!(*k, 0.0);
                }
            }
        }
    }

    /// Footprints taken from neighbours on the same triangle, on both axes
    /// or one, are those extrapolated on the triangle's plane at the
    /// pixel: a forward difference is the same difference made another way
    /// (to f32 rounding), a backward one differs by the surface's
    /// curvature across one pixel (a few per cent of the footprint here). Over a
    /// sphere's band, every pixel of each kind is checked, and each kind
    /// occurs.
    #[test]
    fn footprints_from_neighbours_are_the_extrapolated_ones() {
        let (w, y0) = (64, 24);
        let (mesh, view, projected, hits) = sphere_band(1.0, 7.0, 48, y0, 16);
        let need: Vec<usize> = (0..hits.len()).collect();
        let (mut band, mut out, mut slot) = Default::default();
        band_lookups(&mesh, &view, &hits, &need, w, y0, None, &mut band);
        let (dirs, on) = (&band.dirs, &band.on_object);
        footprints(
            &mesh,
            &projected,
            &view,
            &hits,
            &need,
            dirs,
            w,
            y0,
            true,
            on,
            (&mut out, &mut slot),
        );
        let tri = |k: usize| hits.get(k).copied().flatten().map(|h| h.tri);
        let mut worst = [0.0f32; 3];
        let mut seen = [0; 3];
        for &k in on.iter() {
            let (x, y) = (k as u32 % w, k as u32 / w);
            let t = tri(k);
            let right = x + 1 < w && tri(k + 1) == t;
            let left = x > 0 && tri(k - 1) == t;
            let down = tri(k + w as usize) == t;
            let up = k >= w as usize && tri(k - w as usize) == t;
            // 0: both axes extrapolated, 1: one from a neighbour, 2: both.
            let kind = usize::from(right || left) + usize::from(down || up);
            let at = (x as f32 + 0.5, (y0 + y) as f32 + 0.5);
            let want = footprint(
                &mesh,
                &projected,
                hits[k].as_ref(),
                &view,
                at.0,
                at.1,
                dirs[k],
                (None, None),
            );
            let e = (out[k] / want - 1.0).abs();
            worst[kind] = worst[kind].max(e);
            seen[kind] += 1;
        }
        println!("footprints against extrapolation: worst {worst:?} over {seen:?} pixels");
        assert!(seen.iter().all(|&n| n > 10), "{seen:?}");
        assert_eq!(worst[0], 0.0);
        assert!(worst[1] < 0.03 && worst[2] < 0.03, "{worst:?}");
    }

    /// The footprint and the mip level of the reflection at the centre pixel
    /// of a 64 × 64 view of a sphere of radius `r` whose nearest point is
    /// `gap` in front of the eye, in a cube map of 256² faces.
    fn centre(r: f32, gap: f32) -> (f32, f32) {
        let (mesh, view, projected, hits) = sphere_band(r, gap, 192, 32, 1);
        let hit = hits[32].expect("the centre pixel sees the sphere");
        let (n, vv) = surface(&mesh, &hit, &view);
        let d = reflect_view(n, vv);
        let s = footprint(
            &mesh,
            &projected,
            Some(&hit),
            &view,
            32.5,
            32.5,
            d,
            (None, None),
        );
        let texels = TexelWeights::new(AnyMapping::Cube, 256, 256);
        let q = AnyMapping::Cube.forward8::<Fine>(Dir8::from_partial(&[d]));
        (s, lod8(&texels, &q, &[s]).to_array()[0])
    }

    #[test]
    fn the_level_grows_with_distance_and_curvature() {
        let (near, far) = (centre(1.0, 3.0), centre(1.0, 12.0));
        let (flat, curved) = (centre(20.0, 3.0), centre(0.25, 3.0));
        // The chord per pixel at the centre of a sphere seen head-on is
        // about the pixel angle (the view ray's turn) plus twice the normal's
        // turn: with 30° over 64 pixels, 8.2e-3 + 2 × gap / r × 8.2e-3.
        let pixel = (15f32.to_radians().tan() * 2.0 / 64.0).atan();
        for ((s, _), gap_over_r) in [(near, 3.0), (far, 12.0), (flat, 0.15), (curved, 12.0)] {
            let want = pixel * (1.0 + 2.0 * gap_over_r);
            assert!((s / want - 1.0).abs() < 0.1, "{s} vs {want}");
        }
        assert!(near.1 < far.1, "{near:?} {far:?}");
        assert!(
            flat.1 < near.1 && near.1 < curved.1,
            "{flat:?} {near:?} {curved:?}"
        );
        // A flat mirror reflects the pixel's own footprint: about a texel of
        // a 256² face at its centre (π/2 over 256), so level 0.
        assert_eq!(flat.1, 0.0, "{flat:?}");
    }
}
