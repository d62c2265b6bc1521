//! Spheres of roughness 0 to 1, metal above and plastic below, under an
//! HDRI's light and skybox, baked by envmap in the app.
//!
//! ```text
//! cargo run --release --example viewer -- [FILE.hdr|.exr] [--size N]
//!     [--screenshot OUT.png] [--frames N] [--save OUT.png]
//! ```
//!
//! Without a file, envmap's built-in sky (a 2048 × 1024 map with a sun).
//!
//! * In a window (the default, the crate's `window` feature): the window
//!   opens at once and the bake runs off the main thread
//!   ([`envmap_bevy::EnvmapPlugin`]); the spheres are lit when it is done
//!   and the title says how long it took. Drag with the left mouse button
//!   or use the arrow keys to orbit, the wheel or `+`/`-` to zoom, `E`/`Q`
//!   for one stop more or less exposure, `S` to save the window as
//!   `envmap-viewer-K.png`. The window shows ACES-fitted tonemapped colour.
//!   `--frames N` quits N frames after the environment arrives (writing the
//!   window to `--save OUT.png` first, if given): a smoke test, e.g. under
//!   `xvfb-run` on lavapipe.
//! * `--screenshot OUT.png`: renders one frame headless (no window, no
//!   display; a Vulkan device, lavapipe will do), writes it as a PNG
//!   (linear radiance, sRGB-encoded, no tonemapping) and exits.

use std::path::{Path, PathBuf};

use bevy::ecs::system::RunSystemOnce;
use bevy::light::GlobalAmbientLight;
use bevy::prelude::*;
use envmap_bevy::headless::{self, View};
use envmap_bevy::{bake_hdri, EnvironmentImages};
use envmap_render::image::TexelFormat;

/// The command line.
struct Args {
    /// The HDRI, or `None` for the built-in sky.
    file: Option<PathBuf>,
    /// The chain's face size.
    size: u32,
    /// Headless: render one frame to this PNG and exit.
    screenshot: Option<PathBuf>,
    /// Windowed: quit this many frames after the environment arrives.
    frames: Option<u32>,
    /// Windowed with `--frames`: save the window here before quitting.
    save: Option<PathBuf>,
}

impl Args {
    fn parse() -> Result<Self, String> {
        let mut args = std::env::args().skip(1);
        let mut a = Self {
            file: None,
            size: 256,
            screenshot: None,
            frames: None,
            save: None,
        };
        let number = |v: Option<String>, flag: &str| -> Result<u32, String> {
            v.as_deref()
                .and_then(|s| s.parse().ok())
                .filter(|&n| n > 0)
                .ok_or_else(|| format!("{flag} takes a positive whole number"))
        };
        while let Some(arg) = args.next() {
            match arg.as_str() {
                "--size" => a.size = number(args.next(), "--size")?,
                "--frames" => a.frames = Some(number(args.next(), "--frames")?),
                "--screenshot" => {
                    a.screenshot = Some(args.next().ok_or("--screenshot OUT.png")?.into());
                }
                "--save" => a.save = Some(args.next().ok_or("--save OUT.png")?.into()),
                "-h" | "--help" => {
                    return Err(
                        "usage: viewer [FILE.hdr|.exr] [--size N] [--screenshot OUT.png] \
                                [--frames N] [--save OUT.png]"
                            .into(),
                    )
                }
                f if f.starts_with('-') => return Err(format!("unknown flag {f}")),
                f => a.file = Some(f.into()),
            }
        }
        if a.save.is_some() && a.frames.is_none() {
            return Err("--save needs --frames N (the frame to save)".into());
        }
        Ok(a)
    }

    /// The HDRI file's bytes and name; for the built-in sky, its Radiance
    /// file made in memory (so both take the same path through the bake).
    fn hdri(&self) -> Result<(Vec<u8>, String), String> {
        match &self.file {
            Some(f) => std::fs::read(f)
                .map(|b| (b, f.to_string_lossy().into_owned()))
                .map_err(|e| format!("{}: {e}", f.display())),
            None => {
                use envmap_render::image::Representation;
                use envmap_render::image::{Outputs, SaveOptions};
                let repr = Representation::default_for(envmap_core::AnyMapping::LatLong);
                let sky = envmap_render::scene::Builtin::Sky
                    .image(repr, 2048, 1024)
                    .map_err(|e| e.to_string())?;
                let mut run = Outputs::in_memory(None);
                run.stage_image(&sky, "sky.hdr", &SaveOptions::default())
                    .map_err(|e| e.to_string())?;
                let bytes = run
                    .into_memory()
                    .map_err(|e| e.to_string())?
                    .remove(0)
                    .bytes;
                Ok((bytes, "built-in sky.hdr".into()))
            }
        }
    }
}

/// The scene: 2 rows of 6 spheres.
fn spheres(
    commands: &mut Commands,
    meshes: &mut Assets<Mesh>,
    materials: &mut Assets<StandardMaterial>,
) {
    let mesh = meshes.add(Sphere::new(0.42).mesh().uv(96, 48));
    for (row, metallic) in [(0, 1.0f32), (1, 0.0)] {
        for k in 0..6 {
            let roughness = k as f32 / 5.0;
            let material = materials.add(StandardMaterial {
                base_color: if metallic > 0.0 {
                    Color::linear_rgb(0.95, 0.93, 0.88)
                } else {
                    Color::linear_rgb(0.8, 0.1, 0.1)
                },
                metallic,
                perceptual_roughness: roughness,
                ..default()
            });
            commands.spawn((
                Mesh3d(mesh.clone()),
                MeshMaterial3d(material),
                Transform::from_xyz(k as f32 - 2.5, 0.5 - row as f32, 0.0),
            ));
        }
    }
}

/// The camera of both modes.
const VIEW: View = View {
    eye: Vec3::new(0.0, 0.2, 7.5),
    target: Vec3::ZERO,
    fov_y_deg: 40.0,
};

fn main() -> std::process::ExitCode {
    let args = match Args::parse() {
        Ok(a) => a,
        Err(e) => {
            eprintln!("viewer: {e}");
            return std::process::ExitCode::from(2);
        }
    };
    let result = match &args.screenshot {
        Some(out) => screenshot(&args, out),
        None => window(args),
    };
    match result {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("viewer: {e}");
            std::process::ExitCode::FAILURE
        }
    }
}

/// `--screenshot`: bake, render one frame headless, write it, exit.
fn screenshot(args: &Args, out: &Path) -> Result<(), String> {
    let (bytes, name) = args.hdri()?;
    let t = std::time::Instant::now();
    let baked = bake_hdri(&bytes, &name, args.size).map_err(|e| format!("{name}: {e}"))?;
    eprintln!(
        "baked a {}² chain in {:.0} ms",
        args.size,
        t.elapsed().as_secs_f64() * 1e3
    );
    let images =
        EnvironmentImages::from_bake(&baked, TexelFormat::E5b9g9r9).map_err(|e| e.to_string())?;
    let (w, h) = (960, 400);
    let mut app = headless::app();
    let world = app.world_mut();
    world.insert_resource(GlobalAmbientLight::NONE);
    let (camera, target) = headless::spawn_camera(world, VIEW, w, h);
    let (light, sky) = images.into_components(&mut world.resource_mut::<Assets<Image>>(), 1.0);
    world.entity_mut(camera).insert((light, sky));
    world
        .run_system_once(
            |mut c: Commands,
             mut m: ResMut<Assets<Mesh>>,
             mut s: ResMut<Assets<StandardMaterial>>| spheres(&mut c, &mut m, &mut s),
        )
        .map_err(|e| e.to_string())?;
    let frame = headless::capture(&mut app, &target, 3)
        .ok_or("no frame from Bevy (is there a Vulkan device? lavapipe will do)")?;
    let img = envmap_render::image::RgbImage {
        width: frame.width,
        height: frame.height,
        pixels: frame.rgb(),
    };
    envmap_render::image::write_rgb(&img, out, &envmap_render::image::SaveOptions::default())
        .map_err(|e| e.to_string())?;
    eprintln!("{} ({}×{})", out.display(), frame.width, frame.height);
    Ok(())
}

#[cfg(not(feature = "window"))]
fn window(_: Args) -> Result<(), String> {
    Err("built without the `window` feature: use --screenshot OUT.png".into())
}

#[cfg(feature = "window")]
fn window(args: Args) -> Result<(), String> {
    windowed::run(args)
}

/// The windowed viewer.
#[cfg(feature = "window")]
mod windowed {
    use super::*;
    use bevy::camera::Exposure;
    use bevy::core_pipeline::tonemapping::Tonemapping;
    use bevy::input::mouse::{AccumulatedMouseScroll, MouseScrollUnit};
    use bevy::render::view::screenshot::{save_to_disk, Screenshot, ScreenshotCaptured};
    use bevy::window::PrimaryWindow;
    use envmap_bevy::{BakeEnvironment, BakedEnvironment, EnvmapPlugin, UNIT_EXPOSURE_EV100};

    /// The orbit camera's state and the run's settings.
    #[derive(Resource)]
    struct Viewer {
        yaw: f32,
        pitch: f32,
        distance: f32,
        name: String,
        size: u32,
        /// Frames left before quitting (`--frames`), counted once lit.
        frames_left: Option<u32>,
        save: Option<PathBuf>,
        shots: u32,
    }

    pub(super) fn run(args: Args) -> Result<(), String> {
        let (bytes, name) = args.hdri()?;
        let short = Path::new(&name)
            .file_name()
            .map_or(name.clone(), |f| f.to_string_lossy().into_owned());
        let offset = VIEW.eye - VIEW.target;
        let mut app = App::new();
        app.add_plugins(DefaultPlugins.set(WindowPlugin {
            primary_window: Some(Window {
                title: format!("envmap viewer: {short} (baking a {}² chain…)", args.size),
                resolution: (1280u32, 640u32).into(),
                ..default()
            }),
            ..default()
        }))
        .add_plugins(EnvmapPlugin)
        .insert_resource(GlobalAmbientLight::NONE)
        .insert_resource(Viewer {
            yaw: offset.x.atan2(offset.z),
            pitch: (offset.y / offset.length()).asin(),
            distance: offset.length(),
            name: short,
            size: args.size,
            frames_left: args.frames,
            save: args.save,
            shots: 0,
        })
        .add_systems(
            Startup,
            move |mut commands: Commands,
                  mut meshes: ResMut<Assets<Mesh>>,
                  mut materials: ResMut<Assets<StandardMaterial>>| {
                spheres(&mut commands, &mut meshes, &mut materials);
                let mut request = BakeEnvironment::new(bytes.clone(), name.clone());
                request.size = args.size;
                commands.spawn((
                    Camera3d::default(),
                    bevy::camera::Hdr,
                    Tonemapping::AcesFitted,
                    envmap_bevy::unit_exposure(),
                    Projection::Perspective(PerspectiveProjection {
                        fov: VIEW.fov_y_deg.to_radians(),
                        ..default()
                    }),
                    Transform::from_translation(VIEW.eye).looking_at(VIEW.target, Vec3::Y),
                    request,
                ));
            },
        )
        .add_systems(Update, (orbit, keys, baked, count_frames));
        // A failed bake under `--frames` exits with an error (`baked`).
        match app.run() {
            AppExit::Success => Ok(()),
            AppExit::Error(_) => Err("the environment was not baked".into()),
        }
    }

    /// Drag or arrow keys orbit; wheel or `+`/`-` zoom. A drag follows the
    /// cursor's position in the window (not raw device motion, which remote
    /// and virtual displays may not deliver).
    #[allow(clippy::too_many_arguments)]
    fn orbit(
        mut viewer: ResMut<Viewer>,
        mouse: Res<ButtonInput<MouseButton>>,
        scroll: Res<AccumulatedMouseScroll>,
        keys: Res<ButtonInput<KeyCode>>,
        time: Res<Time>,
        window: Query<&Window, With<PrimaryWindow>>,
        mut last_cursor: Local<Option<Vec2>>,
        mut camera: Query<&mut Transform, With<Camera3d>>,
    ) {
        let dt = time.delta_secs();
        let mut turn = Vec2::ZERO;
        let cursor = window.single().ok().and_then(Window::cursor_position);
        if mouse.pressed(MouseButton::Left) {
            if let (Some(now), Some(before)) = (cursor, *last_cursor) {
                turn += (now - before) * 0.005;
            }
        }
        *last_cursor = cursor;
        for (key, d) in [
            (KeyCode::ArrowLeft, Vec2::NEG_X),
            (KeyCode::ArrowRight, Vec2::X),
            (KeyCode::ArrowUp, Vec2::NEG_Y),
            (KeyCode::ArrowDown, Vec2::Y),
        ] {
            if keys.pressed(key) {
                turn += d * 1.5 * dt;
            }
        }
        let lines = match scroll.unit {
            MouseScrollUnit::Line => scroll.delta.y,
            MouseScrollUnit::Pixel => scroll.delta.y / 40.0,
        };
        let mut zoom = -lines * 0.1;
        if keys.pressed(KeyCode::Equal) || keys.pressed(KeyCode::NumpadAdd) {
            zoom -= dt;
        }
        if keys.pressed(KeyCode::Minus) || keys.pressed(KeyCode::NumpadSubtract) {
            zoom += dt;
        }
        viewer.yaw -= turn.x;
        viewer.pitch = (viewer.pitch + turn.y).clamp(-1.5, 1.5);
        viewer.distance = (viewer.distance * zoom.exp()).clamp(1.0, 50.0);
        let (sy, cy) = viewer.yaw.sin_cos();
        let (sp, cp) = viewer.pitch.sin_cos();
        let eye = VIEW.target + viewer.distance * Vec3::new(sy * cp, sp, cy * cp);
        for mut t in &mut camera {
            *t = Transform::from_translation(eye).looking_at(VIEW.target, Vec3::Y);
        }
    }

    /// `E`/`Q`: exposure up or down a stop; `S`: save the window.
    fn keys(
        mut commands: Commands,
        mut viewer: ResMut<Viewer>,
        keys: Res<ButtonInput<KeyCode>>,
        mut exposure: Query<&mut Exposure>,
    ) {
        for mut e in &mut exposure {
            if keys.just_pressed(KeyCode::KeyE) {
                e.ev100 -= 1.0;
            }
            if keys.just_pressed(KeyCode::KeyQ) {
                e.ev100 += 1.0;
            }
            if keys.just_pressed(KeyCode::Digit0) {
                e.ev100 = UNIT_EXPOSURE_EV100;
            }
        }
        if keys.just_pressed(KeyCode::KeyS) {
            viewer.shots += 1;
            let path = format!("envmap-viewer-{}.png", viewer.shots);
            eprintln!("saving {path}");
            commands
                .spawn(Screenshot::primary_window())
                .observe(save_to_disk(path));
        }
    }

    /// The bake's end: the title says how it went.
    fn baked(
        viewer: Res<Viewer>,
        done: Query<&BakedEnvironment, Added<BakedEnvironment>>,
        mut window: Query<&mut Window, With<PrimaryWindow>>,
        mut exit: MessageWriter<AppExit>,
    ) {
        for b in &done {
            let title = match &b.error {
                None => format!(
                    "envmap viewer: {} ({}² chain baked in {:.0} ms off the main thread)",
                    viewer.name,
                    viewer.size,
                    b.seconds * 1e3
                ),
                Some(e) => format!("envmap viewer: {}: {e}", viewer.name),
            };
            eprintln!("{title}");
            for mut w in &mut window {
                w.title.clone_from(&title);
            }
            if b.error.is_some() && viewer.frames_left.is_some() {
                exit.write(AppExit::error());
            }
        }
    }

    /// `--frames N`: quits N frames after the light arrives, saving the
    /// window first with `--save`.
    fn count_frames(
        mut commands: Commands,
        mut viewer: ResMut<Viewer>,
        lit: Query<(), With<bevy::light::EnvironmentMapLight>>,
        mut exit: MessageWriter<AppExit>,
    ) {
        if lit.is_empty() {
            return;
        }
        let Some(left) = viewer.frames_left else {
            return;
        };
        viewer.frames_left = Some(left.saturating_sub(1));
        if left != 1 {
            return;
        }
        match viewer.save.clone() {
            None => {
                exit.write(AppExit::Success);
            }
            Some(path) => {
                let mut save = save_to_disk(path.clone());
                commands.spawn(Screenshot::primary_window()).observe(
                    move |shot: On<ScreenshotCaptured>, mut exit: MessageWriter<AppExit>| {
                        save(shot);
                        eprintln!("{}", path.display());
                        exit.write(AppExit::Success);
                    },
                );
            }
        }
    }
}
