//! Rendering a Bevy scene headless into a float image and reading it back:
//! the harness of the render tests and of the viewer's `--screenshot`.
//!
//! The camera renders into an `Rgba32Float` image (through Bevy's HDR main
//! pass, `Rgba16Float`), with tonemapping, deband dithering and MSAA off
//! and an exposure of 1 ([`crate::unit_exposure`]), so the pixels are the
//! scene's linear radiance; a [`Screenshot`] of that image is read back.
//! Pipelines compile synchronously, so the frames rendered are complete.

use std::sync::{Arc, Mutex};

use bevy::app::PluginsState;
use bevy::camera::{Hdr, RenderTarget};
use bevy::core_pipeline::tonemapping::{DebandDither, Tonemapping};
use bevy::prelude::*;
use bevy::render::render_resource::{TextureFormat, TextureUsages};
use bevy::render::settings::{Backends, RenderCreation, WgpuSettings};
use bevy::render::view::screenshot::{Screenshot, ScreenshotCaptured};
use bevy::render::view::Msaa;
use bevy::render::RenderPlugin;
use bevy::window::ExitCondition;

/// A rendered frame: linear RGBA, rows top-down.
#[derive(Clone, Debug)]
pub struct Frame {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// The pixels, row by row from the top.
    pub pixels: Vec<[f32; 4]>,
}

impl Frame {
    /// The RGB of every pixel.
    #[must_use]
    pub fn rgb(&self) -> Vec<[f32; 3]> {
        self.pixels.iter().map(|p| [p[0], p[1], p[2]]).collect()
    }
}

/// A perspective camera: where it is, what it looks at, its vertical
/// field of view (degrees), in Bevy's world (y up, right-handed).
#[derive(Clone, Copy, Debug)]
pub struct View {
    /// The camera's position.
    pub eye: Vec3,
    /// The point it looks at.
    pub target: Vec3,
    /// Vertical field of view, degrees.
    pub fov_y_deg: f32,
}

/// A Bevy app with the plugins a headless render needs (no window, Vulkan
/// only: lavapipe where it is the only adapter), its renderer ready.
pub fn app() -> App {
    app_with(|_| {})
}

/// [`app`] with more plugins, added by `more` before the app is finished.
pub fn app_with(more: impl FnOnce(&mut App)) -> App {
    build(None, more)
}

/// [`app`] whose `AssetServer` reads files under `root`.
pub fn app_with_assets(root: impl Into<String>) -> App {
    build(Some(root.into()), |_| {})
}

fn build(asset_root: Option<String>, more: impl FnOnce(&mut App)) -> App {
    let mut app = App::new();
    let plugins = DefaultPlugins
        .set(AssetPlugin {
            file_path: asset_root.unwrap_or_else(|| AssetPlugin::default().file_path),
            ..default()
        })
        .set(WindowPlugin {
            primary_window: None,
            exit_condition: ExitCondition::DontExit,
            ..default()
        })
        .set(RenderPlugin {
            render_creation: RenderCreation::Automatic(Box::new(WgpuSettings {
                backends: Some(Backends::VULKAN),
                ..default()
            })),
            synchronous_pipeline_compilation: true,
            ..default()
        });
    // With the `window` feature, winit would open a display and run its
    // own loop: a headless app leaves it out.
    #[cfg(feature = "window")]
    let plugins = plugins.disable::<bevy::winit::WinitPlugin>();
    app.add_plugins(plugins);
    more(&mut app);
    while app.plugins_state() == PluginsState::Adding {
        bevy::tasks::tick_global_task_pools_on_main_thread();
    }
    app.finish();
    app.cleanup();
    app
}

/// Spawns a camera for `view` rendering into a new `width`×`height`
/// `Rgba32Float` image, with the settings of the [module docs](self);
/// returns the camera and the image.
pub fn spawn_camera(
    world: &mut World,
    view: View,
    width: u32,
    height: u32,
) -> (Entity, Handle<Image>) {
    let mut target = Image::new_target_texture(width, height, TextureFormat::Rgba32Float, None);
    target.texture_descriptor.usage |= TextureUsages::COPY_SRC;
    let handle = world.resource_mut::<Assets<Image>>().add(target);
    let camera = world
        .spawn((
            Camera3d::default(),
            RenderTarget::Image(handle.clone().into()),
            Hdr,
            Tonemapping::None,
            DebandDither::Disabled,
            Msaa::Off,
            crate::unit_exposure(),
            Projection::Perspective(PerspectiveProjection {
                fov: view.fov_y_deg.to_radians(),
                aspect_ratio: width as f32 / height as f32,
                ..default()
            }),
            Transform::from_translation(view.eye).looking_at(view.target, Vec3::Y),
        ))
        .id();
    (camera, handle)
}

/// Renders `frames` frames of `app`, then reads back `target`; `None` if no
/// screenshot arrives within 50 more frames.
pub fn capture(app: &mut App, target: &Handle<Image>, frames: u32) -> Option<Frame> {
    for _ in 0..frames {
        app.update();
    }
    let got: Arc<Mutex<Option<Frame>>> = Arc::default();
    let sink = got.clone();
    app.world_mut()
        .spawn(Screenshot::image(target.clone()))
        .observe(move |shot: On<ScreenshotCaptured>| {
            let img: &Image = &shot;
            let (w, h) = (img.width(), img.height());
            let Some(data) = img.data.as_ref() else {
                return;
            };
            let px: Vec<[f32; 4]> = data
                .chunks_exact(16)
                .map(|c| {
                    core::array::from_fn(|k| {
                        f32::from_le_bytes([c[4 * k], c[4 * k + 1], c[4 * k + 2], c[4 * k + 3]])
                    })
                })
                .collect();
            if px.len() == (w * h) as usize {
                if let Ok(mut g) = sink.lock() {
                    *g = Some(Frame {
                        width: w,
                        height: h,
                        pixels: px,
                    });
                }
            }
        });
    for _ in 0..50 {
        app.update();
        if let Some(f) = got.lock().ok().and_then(|g| g.clone()) {
            return Some(f);
        }
    }
    None
}
