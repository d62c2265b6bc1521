// The renderer: a reflective object in an environment, seen through a
// pinhole camera.

use std::sync::atomic::AtomicBool;

use crate::par::*;
use envmap_core::glam::{Mat3, Vec3};
use envmap_core::AnyMapping;
use envmap_core::{reflect_view, ChartUv};
use envmap_simd::{forward_slice, Fine, LANES};

use super::lookups::*;
use super::mip::*;
use super::raster::*;
use crate::cancel;
#[cfg(doc)]
use crate::error::Error;
use crate::error::Result;
use crate::filter::pyramid::Trilinear;
use crate::filter::sample::{Filter, Sampler};
use crate::filter::weights::TexelWeights;
use crate::image::{EnvImage, RgbImage};
use crate::instruments::Oracle;
use crate::instruments::{exact_split_sum, reference, EnvSampling, Pcg32};
use crate::scene::lit::{LitEnvironment, LitSampler};
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
    /// (`crate::instruments::exact_split_sum`); no chain, table or
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
    /// The rendering integral of the environment given to [`Renderer::render`]
    /// against the material's full BRDF, by Monte Carlo per pixel (looked
    /// up exactly for an analytic environment, bilinear in the map
    /// otherwise): cosine, GGX and light sampling (by the environment's
    /// luminance) combined by the balance heuristic
    /// (`crate::instruments::reference`); deterministic, seeded by the pixel.
    Reference {
        /// The material.
        material: Material,
        /// Samples per pixel and per strategy (cosine, GGX, light).
        samples: u32,
        /// Light sampling by the environment's luminance: the table of the
        /// environment given to [`Renderer::render`] (`light_table`, made once and
        /// shared by every render in it); what finds a small bright sun. A
        /// smooth environment needs only the other two strategies (`None`).
        light: Option<&'a EnvSampling>,
        /// Mixed into every pixel's seed: renders with different seeds are
        /// independent estimates (their difference measures the noise).
        seed: u64,
    },
}

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
/// use envmap_core::AnyMapping;
/// use envmap_render::image::Representation;
/// use envmap_render::scene::{Builtin, Camera, EnvSource, Mesh, RenderOptions, Renderer};
/// let sky = Builtin::Sky.image(Representation::default_for(AnyMapping::LatLong), 64, 32)?;
/// let sphere = Mesh::sphere(1.0, 16, 8);
/// let mut renderer = Renderer::new();
/// let mut opts = RenderOptions::default();
/// (opts.width, opts.height, opts.mip) = (32, 24, true);
/// for _frame in 0..2 {
///     let img = renderer.render(&sphere, EnvSource::Map(&sky), &Camera::default(), &opts)?;
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
            trilinear: mip.map(|(base, l)| Trilinear::over(base, &l.below)),
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

#[cfg(test)]
mod tests {
    use super::*;
    use envmap_simd::{Dir8, Mapping8, Uv8};

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
