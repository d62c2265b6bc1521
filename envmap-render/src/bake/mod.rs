//! The bake directory: the files `envmap bake` writes and `envmap render
//! --env DIR` reads, owned here, writer and reader side by side, so that a
//! library gets the same files (or their bytes) without the command line.
//!
//! # The files
//!
//! | file | what | when |
//! | --- | --- | --- |
//! | `manifest.json` | the input, the axes (`frame_to_canonical`), the container, texel format and target, every level's file, size, perceptual roughness, method and samples, the energy bookkeeping, the irradiance map's file and scale (E or E/π), the DFG table's axes, timings | always |
//! | `sh.json` | the SH9 of the input: radiance and irradiance coefficients in the files' axes and in envmap's, Filament's pre-scaled form, the basis and window | always |
//! | `specular_k.exr` (or `specular_k_{face}.exr`) | level k of the GGX chain, a cube in [`Preset::layout`] | [`FileFormat::Exr`](crate::image::FileFormat::Exr) |
//! | `specular.ktx2` / `.dds` | the whole chain in one cube texture, level k = mip k | [`FileFormat::Ktx2`](crate::image::FileFormat::Ktx2), [`FileFormat::Dds`](crate::image::FileFormat::Dds) |
//! | `irradiance.exr`, or `irradiance.ktx2` / `diffuse.ktx2` / `.dds` | the irradiance cube (E/π by default) | an irradiance size above 0 |
//! | `dfg.exr`, `dfg_multiscatter.exr` | the DFG table (scale, bias; Filament's multiscatter form), f32 | a DFG size above 0 |
//! | `lut_ggx.ktx2` | glTF-IBL-Sampler's BRDF LUT | [`Target::Gltf`] |
//! | `<dir>_ibl.ktx`, `<dir>_skybox.ktx`, `sh.txt` | cmgen's files: the chain with the SH in its `sh` key, level 0, the SH as text | [`FileFormat::Ktx`](crate::image::FileFormat::Ktx) ([`Target::Filament`]) |
//!
//! A manifest names a level inside a texture as `"specular.ktx2 (level 3)"`
//! (`specular.ktx2 (level k)`). Every value's convention (axes, E or E/π, which
//! mip is which roughness) is written beside it in the manifest.
//!
//! # Baking, writing and reading
//!
//! * [`Baker`]: the one way to bake. A [`Target`]'s choices
//!   ([`Baker::for_target`]) or envmap's own ([`Baker::new`]), any
//!   override, then [`Baker::bake`] (the input by value or by reference)
//!   or [`Baker::bake_into`] (each level of an OpenEXR chain written while
//!   the next is made: what `envmap bake` runs).
//! * [`Baked`]: the result, holding the choices it was made with:
//!   [`Baked::write`] (every file into a directory, renamed into place
//!   together), [`Baked::files`] (the same files' bytes, nothing on disk
//!   touched), [`Baked::textures`] (the maps' texels per level and face in
//!   the preset's texel format, for an engine's own upload).
//! * [`open`]: the maps back as a [`crate::scene::lit::LitEnvironment`].
//!
//! ```
//! use envmap_render::bake::{Baker, Target};
//! use envmap_render::scene::{fill, smooth};
//! use envmap_render::image::Representation;
//! use envmap_core::AnyMapping;
//!
//! let src = fill(Representation::default_for(AnyMapping::LatLong), 128, 64, smooth)?;
//! let baked = Baker::for_target(Target::Bevy).size(16).input_name("smooth").bake(&src)?;
//! let files = baked.files("ibl")?;
//! let ktx2 = files.get("specular.ktx2").expect("the chain");
//! assert_eq!(&ktx2[..12], b"\xABKTX 20\xBB\r\n\x1A\n");
//! # Ok::<(), envmap_render::Error>(())
//! ```

mod builder;
mod manifest;
mod preset;
mod read;
mod write;

pub use builder::*;
pub use preset::*;
pub use read::*;
pub use write::*;
