//! Times the renderer: `cargo run --release -p envmap-render --example render_timing`
//! (`MIP=1`: mip-aware, `PREBUILT=1` with its levels made once and timed
//! apart, `LIT=1` glossy plastic at roughness 0.5 by the split sum from
//! the map's own bake, made once, `REBUILD=1` the levels made again in
//! every render into the last render's memory, `ITERS=n` renders,
//! `PROFILE=1` a black map). One renderer draws every frame.
use std::time::Instant;

use envmap_core::AnyMapping;
use envmap_render::image::Representation;
use envmap_render::scene::Builtin;
use envmap_render::scene::Mesh;
use envmap_render::scene::{Camera, EnvSource, RenderOptions, Renderer};

fn main() {
    let repr = Representation::default_for(AnyMapping::Cube);
    // PROFILE=1 skips drawing the sky (a black map), to profile the render alone.
    let env = if std::env::var("PROFILE").is_ok() {
        envmap_render::image::EnvImage::new(4096, 3072, repr).unwrap()
    } else {
        Builtin::Sky.image(repr, 4096, 3072).unwrap()
    };
    let mesh = Mesh::teapot(10);
    // PREBUILT=1: the mip levels made once, their time printed apart.
    let levels = std::env::var("PREBUILT").is_ok().then(|| {
        let t = Instant::now();
        let l = envmap_render::scene::MipLevels::new(&env).expect("levels");
        println!("levels made in {} ms", t.elapsed().as_secs_f64() * 1e3);
        l
    });
    // LIT=1: the split sum, as the `render` bench's envmap-chain case.
    let lit = std::env::var("LIT")
        .is_ok()
        .then(|| envmap_render::scene::LitEnvironment::bake(&env, 512, None).expect("bake"));
    let shading = match &lit {
        Some(env) => envmap_render::scene::Shading::SplitSum {
            env,
            material: envmap_render::scene::Material {
                roughness: 0.5,
                ..envmap_render::scene::Material::default()
            },
            multiscatter: false,
            dominant: true,
        },
        None => envmap_render::scene::Shading::Mirror,
    };
    let opts = {
        let mut o = RenderOptions::default();
        o.shading = shading;
        o.width = 1920;
        o.height = 1080;
        o.samples = 1;
        // MIP=1: the mip-aware lookups (`envmap render`'s default).
        o.mip = std::env::var("MIP").is_ok();
        o.mip_levels = levels.as_ref();
        o
    };
    // REBUILD=1 (with MIP=1): the levels made again in every render, into
    // the memory of the last (`MipLevels::rebuild`).
    let mut again = std::env::var("REBUILD")
        .is_ok()
        .then(|| envmap_render::scene::MipLevels::new(&env).expect("levels"));
    let mut renderer = Renderer::new();
    for _ in 0..std::env::var("ITERS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(5)
    {
        let t = Instant::now();
        if let Some(l) = again.as_mut() {
            l.rebuild(&env).expect("levels");
        }
        let opts = {
            let mut o = opts;
            o.mip_levels = again.as_ref().or(opts.mip_levels);
            o
        };
        let img = renderer
            .render(&mesh, EnvSource::Map(&env), &Camera::default(), &opts)
            .expect("render");
        println!(
            "{} ms ({} px)",
            t.elapsed().as_secs_f64() * 1e3,
            img.pixels.len()
        );
    }
}
