//! Scenes: what is rendered and how.
//!
//! * [`environments`]: the built-in sky and room (`--env sky`, `--env room`).
//! * [`procedural`]: environments given as a function of direction, filled
//!   into any representation; the smooth test environment; PSNR.
//! * [`mesh`]: the sphere, torus and Utah teapot meshes.
//! * [`material`]: the glTF metallic-roughness model and its presets.
//! * [`lit`]: shading with baked maps (the split sum) and the Monte Carlo
//!   reference it approximates.
//! * [`render`]: the rasterizer, per pixel (seed `000`) and per vertex
//!   (seed `002`).
//!
//! This folder uses [`crate::image`] and [`crate::filter`].

pub mod environments;
pub mod lit;
pub mod material;
pub mod mesh;
pub mod procedural;
pub mod render;
