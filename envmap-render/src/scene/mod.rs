//! Scenes: what is rendered and how.
//!
//! * `environments`: the built-in sky and room (`--env sky`, `--env room`).
//! * `procedural`: environments given as a function of direction, filled
//!   into any representation; the smooth test environment; PSNR.
//! * `mesh`: the sphere, torus and Utah teapot meshes.
//! * `material`: the glTF metallic-roughness model and its presets.
//! * `lit`: shading with baked maps (the split sum).
//! * `near_field`: the split sum's lobe below the chain's first level,
//!   from the source map itself.
//! * `reference`: what the split sum is measured against: the exact split
//!   sum and the Monte Carlo reference.
//! * `render`: the rasterizer, per pixel (seed `000`) and per vertex
//!   (seed `002`).
//!
//! This folder uses [`crate::image`] and [`crate::filter`].
//!
//! # Built-in environments
//!
//! The built-in environments, usable wherever an environment file is
//! (`--env sky`, `--env room`): no file needed.
//!
//! Directions are in world axes: z up, right-handed; azimuth is measured from
//! +x towards +y. Every function here normalises its direction, returns
//! black for a zero or non-finite one and a finite radiance otherwise.
//!
//! * [`sky`]: an analytic, HDR, linear-RGB sky. A gradient from a pale, bright
//!   horizon to a deeper blue zenith; a sun disk of angular radius
//!   [`SUN_RADIUS_DEG`] (0.6°) at elevation [`SUN_ELEVATION_DEG`] (35°) and
//!   azimuth [`SUN_AZIMUTH_DEG`] (40°) with radiance in the thousands
//!   ([`SUN_RADIANCE`]); a soft glow around it; below the horizon a
//!   checkered ground plane seen from [`SkyParams::eye_height`] (1 unit)
//!   above it, squares of [`SkyParams::checker_size`] (1 unit) in two greys,
//!   fading into the horizon's haze with distance. The only discontinuities
//!   are the sun's edge and the checker edges, both wanted: they show how each
//!   representation filters sharp detail.
//! * [`room`]: a box room seen from its centre, the scene that seed `002`
//!   captures as six views from one point. `room_cube` does exactly that:
//!   it renders the six GL faces from the eye, giving a cube map to use as
//!   the environment (the two-pass method).
//! * [`Builtin`]: the two by name, for the command line.
//!
//! # Procedural environments
//!
//! Environments defined by a function of direction, evaluated into any
//! representation.
//!
//! # Meshes
//!
//! Triangle meshes with smooth vertex normals: a sphere, a torus and the Utah
//! teapot.
//!
//! All meshes use world axes with z up. Triangles wind counter-clockwise seen
//! from outside, so `(b - a) × (c - a)` points the same way as the vertex
//! normals (outward).
//!
//! The teapot is Martin Newell's 1975 model (public domain): 32 bicubic
//! Bézier patches, including the bottom, embedded from `data/teapot.bpt`.
//! Each patch is evaluated on a regular parameter grid with the cubic
//! Bernstein basis
//!
//! ```text
//! S(u, v) = Σᵢ Σⱼ Bᵢ(u) Bⱼ(v) Pᵢⱼ,   B₀ = (1−t)³, B₁ = 3t(1−t)², B₂ = 3t²(1−t), B₃ = t³
//! ```
//!
//! and its normal is `∂S/∂u × ∂S/∂v`, evaluated a little inside the patch
//! where that product vanishes (the collapsed edges at the lid's knob and the
//! bottom's centre). Each patch is turned to face outward by casting rays
//! from it through the whole model and counting crossings (an even count
//! means the side it faces is outside). Vertices that patches share along
//! their seams are welded (positions quantised to [`WELD_TOLERANCE`]) and
//! their normals averaged, so shading is smooth across patch borders.
//!
//! # Materials
//!
//! Materials: the glTF 2.0 metallic-roughness model (glTF 2.0 spec,
//! Appendix B "BRDF Implementation"), and the named presets of the command
//! line.
//!
//! A material is a base colour (linear RGB), a metallic factor and a
//! perceptual roughness r (GGX α = r²). Its reflectance at normal incidence
//! is F0 = mix(0.04, base colour, metallic) (the dielectric F0 of 0.04
//! unless given), its diffuse colour base · (1 − metallic).
//!
//! # Shading with baked maps
//!
//! Lighting with environment maps: the split sum engines shade with, and
//! the Monte Carlo integral it approximates.
//!
//! [`LitEnvironment`] holds what `envmap bake` makes: the GGX-prefiltered
//! specular chain (with each level's perceptual roughness), the irradiance
//! cube and the DFG table. `LitSampler::shade` evaluates, for a
//! [`Material`] at normal N seen along V (both unit, world axes, V towards
//! the eye):
//!
//! ```text
//! diffuse  = c_diff · E(N)/π                       (c_diff = base · (1 − metallic))
//! specular = LD(R, r) · (F0 · A + B) [· (1 + F0 · (1/(A + B) − 1))]
//! ```
//!
//! with R = 2(N·V)N − V, LD the chain read at roughness r (between the two
//! levels whose roughness brackets r, weighted as [`LevelBlend`] says:
//! linear in 1/α by default, linear in the lod for an engine's chain;
//! bilinear in each), (A, B) the DFG table's single-scatter scale and bias
//! at (N·V, r), and the bracketed
//! factor Filament's multiscatter energy compensation (Filament's "Physically
//! Based Rendering in Filament", §4.7.2), when asked for. That is Karis'
//! split sum ("Real Shading in Unreal Engine 4", 2013): the prefiltered
//! radiance assumes N = V = R.
//!
//! `exact_split_sum` is the same sum with nothing baked: the prefiltered
//! integral of the input itself at r, the DFG integral at (N·V, r) and the
//! exact irradiance. The render's distance from it is what the chain and
//! the table cost (`tests/split_sum.rs`, `docs/design/lighting-method.md`).
//!
//! `reference()` is the integral the split sum stands for, per pixel:
//! L_o = ∫ L(l) (c_diff/π + D·Vis·F) (N·l)⁺ dl with GGX D, the
//! height-correlated Smith visibility and Schlick's Fresnel (glTF 2.0
//! Appendix B), estimated by importance sampling: cosine-weighted
//! directions, GGX half vectors (pdf D·(N·H)) and directions drawn by the
//! environment's luminance ([`EnvSampling`](crate::instruments::EnvSampling), which finds a small bright
//! sun the other two almost never hit), combined by the balance
//! heuristic, from a deterministic per-pixel sequence.
//!
//! # The renderer
//!
//! The renderer: a reflective object in an environment, seen through a
//! pinhole camera.
//!
//! One z-buffered rasterizer serves both of the seeds' methods:
//!
//! * [`Mode::PerPixel`] (seed `000`): for every pixel showing the object, the
//!   interpolated normal N, the view vector V, the reflection
//!   R = 2(N·V)N − V, its place in the environment map and the filtered texel.
//! * [`Mode::PerVertex`] (seed `002`): R and its texture coordinates are
//!   computed at the vertices only and the coordinates interpolated linearly
//!   (perspective-correct) across each triangle, in the chart of the
//!   triangle's first vertex — which reproduces the seams, poles and rim
//!   artifacts the seeds warn about.
//!
//! Where no object covers a pixel the environment itself is shown (the view
//! ray's direction looked up in the map). Bands of rows render in parallel.
//! World axes are envmap's canonical ones: z up, right-handed.
//!
//! ## Mip-aware lookups
//!
//! A mirror magnifies the environment where it curves: neighbouring pixels
//! of a distant or strongly curved part reflect directions far apart, and a
//! plain bilinear lookup per pixel then skips texels and aliases. With
//! [`RenderOptions::mip`], per-pixel lookups in a map read a mip pyramid
//! of it (`crate::filter::pyramid`: solid-angle-weighted box levels, the
//! representation's edge rule at each) through `Trilinear`,
//! at a level chosen per pixel from the footprint of the looked-up
//! direction:
//!
//! 1. **Footprint**, an angle in direction space (so no chart seam or pole
//!    of the map enters it): the larger of |R(x + 1, y) − R(x, y)| and
//!    |R(x, y + 1) − R(x, y)|, the chords from the pixel's direction to
//!    those one pixel right and one pixel down. For a pixel on the object
//!    these are ray differentials (Igehy 1999, "Tracing ray differentials",
//!    SIGGRAPH), taken by finite differences of the interpolated surface:
//!    the neighbours' screen points are put on the plane of the pixel's own
//!    triangle (its perspective-correct weights extrapolated), their normal
//!    and view vector interpolated there and reflected. So the footprint
//!    grows with the surface's curvature (the normal turns faster per
//!    pixel: R turns twice as fast) and with distance (a pixel covers more
//!    of the surface), which is the ray cone's spread, pixel angle plus
//!    twice the curvature term (Akenine-Möller et al. 2019, "Texture level
//!    of detail strategies for real-time ray tracing", Ray Tracing Gems
//!    ch. 20), measured rather than modelled, and never taken across a
//!    silhouette or from another part of the object. For a background pixel
//!    it is the view ray's own angular size.
//! 2. **Texel size** where the lookup lands: the square root of the base
//!    texel's exact solid angle (`TexelWeights`, one lookup per pixel), so
//!    a cube face's corners (texels 5.2 times smaller in solid angle than
//!    its centre) or a latlong's poles get their own scale.
//! 3. **Level** λ = log2(footprint / texel) − 1, at least 0 (the base),
//!    blended trilinearly between ⌊λ⌋ and ⌊λ⌋ + 1. The −1: GL's isotropic
//!    rule (λ = log2 of the larger footprint, no bias) over-blurs. Against a
//!    4 × 4-supersampled render of a mirror teapot, a bias of −1 scored best
//!    on every map tried, and the larger chord beat the geometric mean of
//!    the two (the footprint's area) at every bias: a level's bilinear tap
//!    already spreads over two of its texels, so the pixel's half-footprint
//!    is the size to match.
//!
//! `cargo test --release -p envmap-cli --test mip -- --nocapture` measures
//! the gain against that supersampled reference (`docs/cli.md` gives the
//! figures). What is left is mostly the silhouette's geometric aliasing,
//! which no texture filter touches.
//!
//! The pyramid is built for each render unless made beforehand
//! ([`MipLevels`], [`RenderOptions::mip_levels`]; made again in place for a
//! map that changes, [`MipLevels::rebuild`]); a [`Renderer`] building its
//! own builds them into the memory of the levels it built last. The map itself is read in place
//! as level 0 (`Trilinear::over`); the levels below it (every level down
//! to 1², about a third of the map's texels) are made from it, each in one
//! parallel pass over the level above, written straight into its copy with
//! a one-texel border (each but a disk map's; `Pyramid::below`: no
//! level image made, none copied), which [`MipLevels`] keeps: renders from
//! prebuilt levels copy nothing. Building them is the option's main cost, timed
//! beside the plain render in the render bench (`envmap-bench`,
//! `per-pixel-mip`, `per-pixel-mip-prebuilt`; `docs/performance.md`). The rest is
//! kept small: eight lookups whose levels are all 0 (the background, the
//! flatter parts) take the plain path, a level is read only on the lanes
//! that use it, a pixel's footprint comes from its neighbours'
//! directions on the same triangle where it has them, and the levels'
//! logarithms are taken eight at a time (within 10⁻⁵ of a level of the
//! f64 formula, `lod8_levels_are_the_f64_formula`).
//! Per-vertex mode keeps seed `002`'s lookups (their artifacts are its
//! point), [`Filter::Nearest`](crate::filter::Filter::Nearest) stays nearest, and an analytic environment
//! has no map to filter.

pub(crate) mod environments;
pub(crate) mod lit;
pub(crate) mod lookups;
pub(crate) mod material;
pub(crate) mod mesh;
pub(crate) mod mip;
pub(crate) mod near_field;
pub(crate) mod procedural;
pub(crate) mod raster;
pub(crate) mod renderer;

pub use environments::*;
pub use lit::*;
#[cfg(feature = "instruments")]
pub use lookups::*;
pub use material::*;
pub use mesh::*;
pub use mip::*;
pub use procedural::*;
pub use renderer::*;
