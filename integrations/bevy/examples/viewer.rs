//! Spheres of roughness 0 to 1, metal above and plastic below, under an
//! HDRI's light and skybox, baked by envmap in the app.
//!
//! ```text
//! cargo run --release --example viewer -- [FILE.hdr|.exr] [--size N] [--screenshot OUT.png]
//! ```
//!
//! Without a file, envmap's built-in sky. `--screenshot` renders one frame
//! headless (no window; a Vulkan device, lavapipe will do), writes it as a
//! PNG (linear radiance, sRGB-encoded, no tonemapping) and exits. A
//! windowed mode is not built yet (the crate leaves out Bevy's window
//! features to keep its build small): `--screenshot` is required.

use std::path::PathBuf;

use bevy::light::GlobalAmbientLight;
use bevy::prelude::*;
use envmap_bevy::headless::{self, View};
use envmap_bevy::{bake_hdri, bake_image, EnvironmentImages};
use envmap_render::image::{Representation, TexelFormat};

/// The scene: 2 rows of 6 spheres.
fn spheres(world: &mut World) {
    let mesh = world
        .resource_mut::<Assets<Mesh>>()
        .add(Sphere::new(0.42).mesh().uv(96, 48));
    for (row, metallic) in [(0, 1.0f32), (1, 0.0)] {
        for k in 0..6 {
            let roughness = k as f32 / 5.0;
            let material = world
                .resource_mut::<Assets<StandardMaterial>>()
                .add(StandardMaterial {
                    base_color: if metallic > 0.0 {
                        Color::linear_rgb(0.95, 0.93, 0.88)
                    } else {
                        Color::linear_rgb(0.8, 0.1, 0.1)
                    },
                    metallic,
                    perceptual_roughness: roughness,
                    ..default()
                });
            world.spawn((
                Mesh3d(mesh.clone()),
                MeshMaterial3d(material),
                Transform::from_xyz(k as f32 - 2.5, 0.5 - row as f32, 0.0),
            ));
        }
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let (mut file, mut size, mut shot) = (None::<PathBuf>, 256u32, None::<PathBuf>);
    while let Some(a) = args.next() {
        match a.as_str() {
            "--size" => size = args.next().ok_or("--size N")?.parse()?,
            "--screenshot" => shot = Some(args.next().ok_or("--screenshot OUT.png")?.into()),
            _ => file = Some(a.into()),
        }
    }
    let t = std::time::Instant::now();
    let baked = match &file {
        Some(f) => bake_hdri(&std::fs::read(f)?, &f.to_string_lossy(), size)?,
        None => {
            let repr = Representation::default_for(envmap_core::AnyMapping::LatLong);
            let sky = envmap_render::environments::Builtin::Sky.image(repr, 1024, 512)?;
            bake_image(&sky, size)?
        }
    };
    eprintln!(
        "baked a {size}² chain in {:.0} ms",
        t.elapsed().as_secs_f64() * 1e3
    );
    let images = EnvironmentImages::from_bake(&baked, TexelFormat::E5b9g9r9)?;
    let view = View {
        eye: Vec3::new(0.0, 0.2, 7.5),
        target: Vec3::ZERO,
        fov_y_deg: 40.0,
    };
    let Some(out) = shot else {
        return Err(
            "a window needs the `window` feature; use --screenshot OUT.png headless".into(),
        );
    };
    let (w, h) = (960, 400);
    let mut app = headless::app();
    let world = app.world_mut();
    world.insert_resource(GlobalAmbientLight::NONE);
    let (camera, target) = headless::spawn_camera(world, view, w, h);
    let (light, sky) = images.into_components(&mut world.resource_mut::<Assets<Image>>(), 1.0);
    world.entity_mut(camera).insert((light, sky));
    spheres(world);
    let frame = headless::capture(&mut app, &target, 3).ok_or("no frame from Bevy")?;
    let img = envmap_render::RgbImage {
        width: frame.width,
        height: frame.height,
        pixels: frame.rgb(),
    };
    envmap_render::io::write_rgb(&img, &out, &envmap_render::io::SaveOptions::default())?;
    eprintln!("{} ({}×{})", out.display(), frame.width, frame.height);
    Ok(())
}
