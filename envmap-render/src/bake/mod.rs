//! The bake directory: the files `envmap bake` writes and `envmap render
//! --env DIR` reads, owned here, writer and reader side by side, so that a
//! library gets the same files (or their bytes) from a [`Bake`] without the
//! command line.
//!
//! # The files
//!
//! | file | what | when |
//! | --- | --- | --- |
//! | `manifest.json` | the input, the axes (`frame_to_canonical`), the container, texel format and target, every level's file, size, perceptual roughness, method and samples, the energy bookkeeping, the irradiance map's file and scale (E or E/π), the DFG table's axes, timings | always |
//! | `sh.json` | the SH9 of the input: radiance and irradiance coefficients in the files' axes and in envmap's, Filament's pre-scaled form, the basis and window | always |
//! | `specular_k.exr` (or `specular_k_{face}.exr`) | level k of the GGX chain, a cube in [`Preset::layout`] | [`Container::Exr`] |
//! | `specular.ktx2` / `.dds` | the whole chain in one cube texture, level k = mip k | [`Container::Ktx2`], [`Container::Dds`] |
//! | `irradiance.exr`, or `irradiance.ktx2` / `diffuse.ktx2` / `.dds` | the irradiance cube (E/π by default) | an irradiance size above 0 |
//! | `dfg.exr`, `dfg_multiscatter.exr` | the DFG table (scale, bias; Filament's multiscatter form), f32 | a DFG size above 0 |
//! | `lut_ggx.ktx2` | glTF-IBL-Sampler's BRDF LUT | [`Target::Gltf`] |
//! | `<dir>_ibl.ktx`, `<dir>_skybox.ktx`, `sh.txt` | cmgen's files: the chain with the SH in its `sh` key, level 0, the SH as text | [`Container::Ktx`] ([`Target::Filament`]) |
//!
//! A manifest names a level inside a texture as `"specular.ktx2 (level 3)"`
//! ([`read::level_entry`]). Every value's convention (axes, E or E/π, which
//! mip is which roughness) is written beside it in the manifest.
//!
//! # Writing and reading
//!
//! * [`Preset`]: a [`Target`]'s choices (or envmap's default), turned into
//!   [`crate::filter::bake::BakeOptions`] by [`Preset::bake_options`].
//! * [`write()`]: every file into a directory, renamed into place together;
//!   [`bake_into`]: the bake and its files at once, each level of an
//!   OpenEXR chain written while the next is made (what `envmap bake`
//!   runs); [`in_memory`]: the same files' bytes, with nothing on disk
//!   touched;
//!   [`engine_textures`]: the maps' texels per level and face in the
//!   preset's texel format, for an engine's own upload.
//! * [`read::open`]: the maps back as a [`crate::scene::lit::LitEnvironment`].
//!
//! ```
//! use envmap_render::bake::{self, Preset, Provenance, Target};
//! use envmap_render::filter::bake::{bake, BakeOptions};
//! use envmap_render::image::{FileAxes, Representation};
//! use envmap_render::scene::procedural::{fill, smooth};
//! use envmap_core::AnyMapping;
//!
//! let src = fill(Representation::default_for(AnyMapping::LatLong), 128, 64, smooth)?;
//! let mut preset = Preset::for_target(Target::Bevy, FileAxes::default());
//! preset.size = 16;
//! preset.irradiance_size = 8;
//! let opts = preset.bake_options(BakeOptions::default());
//! let baked = bake(&src, &opts, &|_, _| {})?;
//! let files = bake::in_memory("ibl".as_ref(), &baked, &opts, &preset, &Provenance::new("smooth"))?;
//! let ktx2 = files.get("specular.ktx2").expect("the chain");
//! assert_eq!(&ktx2[..12], b"\xABKTX 20\xBB\r\n\x1A\n");
//! # Ok::<(), envmap_render::Error>(())
//! ```
//!
//! [`Bake`]: crate::filter::bake::Bake

mod builder;
pub mod preset;
pub mod read;
pub mod write;

pub use builder::{Baked, Baker, Progress};
pub use preset::{Container, Preset, Target, DEFAULT_ZSTD};
pub use write::{BakeFiles, EngineTextures, Provenance, Written};
