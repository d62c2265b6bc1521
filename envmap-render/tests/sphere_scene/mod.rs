//! The scene and the measure the split-sum render is held to the exact
//! split sum with, shared by `tests/split_sum.rs` and
//! `examples/split_sum.rs`: a white metal sphere (F0 = 1) of radius 1.5 at
//! (0, 1.4, 0) in the GL world, seen from (0, 1.4, 6) with a 35° field of
//! view (`envmap render --object sphere --eye 0,1.4,6 --target 0,1.4,0`),
//! read along the lobe's dominant direction, no background; relative RMS
//! √(Σ(a − b)²/Σb²) and bias Σ(a − b)/Σb over the sphere's pixels and
//! channels.
#![allow(dead_code)]

use std::path::Path;

use envmap_core::glam::Vec3;
use envmap_core::AnyMapping;
use envmap_render::image::RgbImage;
use envmap_render::image::{load, LoadOptions, NonFinite};
use envmap_render::image::{EnvImage, FileAxes, Representation};
use envmap_render::instruments::Oracle;
use envmap_render::scene::Builtin;
use envmap_render::scene::LitEnvironment;
use envmap_render::scene::Material;
use envmap_render::scene::Mesh;
use envmap_render::scene::{Camera, EnvSource, RenderOptions, Renderer, Shading};

/// The sphere and the camera, in envmap's z-up axes.
pub(crate) fn scene() -> (Mesh, Camera) {
    let mut m = Mesh::sphere(1.5, 128, 64);
    for p in &mut m.positions {
        *p += Vec3::new(0.0, 0.0, 1.4);
    }
    let cam = Camera {
        eye: Vec3::new(0.0, -6.0, 1.4),
        target: Vec3::new(0.0, 0.0, 1.4),
        up: Vec3::Z,
        fov_y_deg: 35.0,
    };
    (m, cam)
}

/// A white metal (F0 = 1, no diffuse part) at roughness `r`.
pub(crate) fn metal(r: f32) -> Material {
    Material::new([1.0; 3], 1.0, r)
}

/// `shading` of the sphere in `env`, `px`² pixels, no background.
pub(crate) fn draw(env: &EnvImage, shading: Shading<'_>, px: u32) -> RgbImage {
    let (mesh, cam) = scene();
    let opts = {
        let mut o = RenderOptions::default();
        o.width = px;
        o.height = px;
        o.samples = 1;
        o.background = false;
        o.shading = shading;
        o
    };
    Renderer::new()
        .render(&mesh, EnvSource::Map(env), &cam, &opts)
        .expect("render")
}

/// The sphere's pixels.
pub(crate) fn mask(px: u32) -> Vec<bool> {
    let (mesh, cam) = scene();
    let white = |_: Vec3| [1.0f32; 3];
    let opts = {
        let mut o = RenderOptions::default();
        o.width = px;
        o.height = px;
        o.samples = 1;
        o.background = false;
        o
    };
    Renderer::new()
        .render(&mesh, EnvSource::Analytic(&white), &cam, &opts)
        .expect("render")
        .pixels
        .iter()
        .map(|p| p[0] > 0.5)
        .collect()
}

/// The exact split sum of the white metal at `r`.
pub(crate) fn exact(env: &EnvImage, oracle: &Oracle, r: f32, px: u32) -> RgbImage {
    draw(
        env,
        Shading::ExactSplitSum {
            oracle,
            material: metal(r),
            multiscatter: false,
            dominant: true,
        },
        px,
    )
}

/// The split sum of the white metal at `r` from `lit`.
pub(crate) fn split(env: &EnvImage, lit: &LitEnvironment, r: f32, px: u32) -> RgbImage {
    draw(
        env,
        Shading::SplitSum {
            env: lit,
            material: metal(r),
            multiscatter: false,
            dominant: true,
        },
        px,
    )
}

/// Relative RMS and bias of `a` against `e` over the `mask`ed pixels.
pub(crate) fn measure(a: &RgbImage, e: &RgbImage, mask: &[bool]) -> (f64, f64) {
    let (mut se, mut ss, mut sd, mut sm) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for (k, _) in mask.iter().enumerate().filter(|(_, &m)| m) {
        for c in 0..3 {
            let (x, y) = (f64::from(a.pixels[k][c]), f64::from(e.pixels[k][c]));
            se += (x - y) * (x - y);
            ss += y * y;
            sd += x - y;
            sm += y;
        }
    }
    assert!(ss > 0.0 && sm > 0.0, "an empty or black sphere");
    ((se / ss).sqrt(), sd / sm)
}

/// A committed HDRI (`test-data/hdri/NAME.exr`), loaded as `envmap
/// render` loads it.
pub(crate) fn committed(name: &str) -> EnvImage {
    let path = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../test-data/hdri"))
        .join(format!("{name}.exr"));
    load(&path, &{
        let mut o = LoadOptions::default();
        o.non_finite = NonFinite::Zero;
        o
    })
    .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The built-in sky as `envmap render` stores it: a cube of `face`² in the
/// GL world.
pub(crate) fn builtin_sky(face: u32) -> EnvImage {
    let repr = Representation::for_file(AnyMapping::Cube, FileAxes::default());
    let (w, h) = repr
        .atlas
        .image_size_for_cell_width(face)
        .expect("cube size");
    Builtin::Sky.image(repr, w, h).expect("sky")
}
