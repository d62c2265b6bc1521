//! envmap's image-based lighting in Bevy: the `Image`s of an
//! [`EnvironmentMapLight`] and a [`Skybox`] made from an in-memory bake,
//! exactly as Bevy's own KTX2 loader makes them from the files `envmap bake
//! --target bevy` writes, and a plugin that bakes an HDRI off the main thread.
//!
//! * [`bake_hdri`]: an HDRI file's bytes (`.hdr`, `.exr`, `.png`, …) to a
//!   [`Bake`] with Bevy's preset (512² specular chain by roughness =
//!   mip / (mips − 1), 32² diffuse holding E/π).
//! * [`EnvironmentImages::from_bake`]: the bake as two Bevy cube `Image`s
//!   (mip-major data, a cube view, every level), in RGB9E5 (the default, as
//!   Bevy's shipped maps) or RGBA16F.
//! * [`EnvironmentImages::into_components`]: the images added to
//!   `Assets<Image>`, as an [`EnvironmentMapLight`] and a [`Skybox`] for a
//!   camera.
//! * [`EnvmapPlugin`] with the [`BakeEnvironment`] component: put it on a
//!   camera and the bake runs on Bevy's `AsyncComputeTaskPool`; when it is
//!   done the camera gets its `EnvironmentMapLight` and `Skybox`.
//!
//! # Features
//!
//! `window` (default): Bevy's winit on X11 with mouse and keyboard, for the
//! `viewer` example's window. Without it (`default-features = false`) the
//! crate is the library and the [`headless`] harness, and Bevy is built
//! without a windowing backend.
//!
//! # Conventions
//!
//! Bevy's world is y up, right-handed (GL's), and Bevy reads a cube at
//! (x, y, −z) of the world direction ("cube maps are left-handed",
//! `skybox.wgsl` and `environment_map.wgsl`). The images here are the cube
//! files of Bevy's preset ([`Preset::for_target`]`(Target::Bevy, …)`),
//! whose axes are chosen for that lookup; `tests/headless.rs` renders the
//! skybox on a software GPU and holds it to envmap's own render of the same
//! background. The diffuse map holds E/π (the radiance a white Lambertian
//! surface reflects), which is what Bevy multiplies by the albedo.
//! Intensities are Bevy's: a map value times `intensity` times the camera's
//! exposure (`Exposure::exposure()`, 1/(1.2 · 2^ev100)) is what lands in the
//! render target; with ev100 = −log₂ 1.2 ([`UNIT_EXPOSURE_EV100`]) and
//! intensity 1 the map's own values do.
#![forbid(unsafe_code)]

use std::sync::Arc;

use bevy::asset::RenderAssetUsages;
use bevy::camera::Exposure;
use bevy::image::Image;
use bevy::light::{EnvironmentMapLight, Skybox};
use bevy::prelude::*;
use bevy::render::render_resource::{
    Extent3d, TextureDataOrder, TextureDimension, TextureFormat, TextureViewDescriptor,
    TextureViewDimension,
};
use bevy::tasks::{block_on, poll_once, AsyncComputeTaskPool, Task};

pub mod headless;

pub use envmap_render;
use envmap_render::bake::{Baker, Preset, Target};
use envmap_render::filter::bake::Bake;
use envmap_render::image::EnvImage;
use envmap_render::image::{load_from_memory, LoadOptions};
use envmap_render::image::{texture::Texture, FileAxes, TexelFormat};

/// The camera exposure (EV100) under which Bevy writes a map's values
/// unscaled: Bevy's exposure is 2^−ev100 / 1.2, so ev100 = −log₂ 1.2.
pub const UNIT_EXPOSURE_EV100: f32 = -0.263_034_4;

/// An [`Exposure`] of 1: the render target holds radiance as the maps do.
#[must_use]
pub fn unit_exposure() -> Exposure {
    Exposure {
        ev100: UNIT_EXPOSURE_EV100,
    }
}

/// Bevy's preset ([`Target::Bevy`]) at a chain of `size`² (its default
/// 512): the options [`bake_hdri`] uses.
#[must_use]
pub fn bevy_preset(size: u32) -> Preset {
    let mut p = Preset::for_target(Target::Bevy, FileAxes::default());
    p.size = size;
    p
}

/// Bakes an HDRI from its file's bytes (the format from `name`'s
/// extension, as [`load_from_memory`] reads it) with Bevy's preset at a
/// `size`² chain; no file is read or written.
///
/// # Errors
///
/// The file does not decode, or the bake fails (see
/// [`envmap_render::Error`]).
pub fn bake_hdri(bytes: &[u8], name: &str, size: u32) -> envmap_render::Result<Bake> {
    let src = load_from_memory(bytes, name, &LoadOptions::default())?.image;
    bake_image(&src, size)
}

/// Bakes an environment already in memory with Bevy's preset at a `size`²
/// chain.
///
/// # Errors
///
/// As [`Baker::bake`].
pub fn bake_image(src: &EnvImage, size: u32) -> envmap_render::Result<Bake> {
    Ok(Baker::with_preset(bevy_preset(size)).bake(src)?.into_bake())
}

/// The wgpu format of a texel format envmap writes (BC6H needs a device
/// with `TEXTURE_COMPRESSION_BC`).
#[must_use]
pub fn texture_format(format: TexelFormat) -> Option<TextureFormat> {
    Some(match format {
        TexelFormat::Rgba16f => TextureFormat::Rgba16Float,
        TexelFormat::Rgba32f => TextureFormat::Rgba32Float,
        TexelFormat::B10g11r11 => TextureFormat::Rg11b10Ufloat,
        TexelFormat::E5b9g9r9 => TextureFormat::Rgb9e5Ufloat,
        TexelFormat::Bc6h => TextureFormat::Bc6hRgbUfloat,
        // RGBD is 8-bit RGBA that only a decoding shader reads as HDR.
        TexelFormat::Rgb16f | TexelFormat::Rgb32f | TexelFormat::Rgbd8 => return None,
    })
}

/// A cube `Image` of `levels` (largest first, each a cube of half the size
/// of the one before) in `format`, laid out as Bevy's KTX2 loader lays out
/// a KTX2 cube: the levels' faces (+X, −X, +Y, −Y, +Z, −Z) mip-major, a
/// `Cube` view, `mip_level_count` the number of levels.
///
/// # Errors
///
/// Levels that are not a cube chain; a format wgpu does not have.
pub fn cube_image(levels: &[EnvImage], format: TexelFormat) -> envmap_render::Result<Image> {
    let tex = Texture::from_env(levels)?;
    let wgpu_format = texture_format(format)
        .ok_or_else(|| envmap_render::Error::Input(format!("{}: no wgpu format", format.name())))?;
    let (packed, _clamped) = tex.pack(format);
    let (w, h) = tex.size();
    let mut image = Image::default();
    image.texture_descriptor.format = wgpu_format;
    image.data = Some(packed.concat());
    image.data_order = TextureDataOrder::MipMajor;
    image.texture_descriptor.size = Extent3d {
        width: w,
        height: h,
        depth_or_array_layers: 6,
    };
    image.texture_descriptor.mip_level_count = tex.level_count() as u32;
    image.texture_descriptor.dimension = TextureDimension::D2;
    image.texture_view_descriptor = Some(TextureViewDescriptor {
        dimension: Some(TextureViewDimension::Cube),
        ..default()
    });
    image.asset_usage = RenderAssetUsages::default();
    Ok(image)
}

/// The two cube maps of an [`EnvironmentMapLight`] and a skybox.
#[derive(Clone, Debug)]
pub struct EnvironmentImages {
    /// The GGX-prefiltered chain: level k at perceptual roughness
    /// k / (levels − 1), Bevy's rule.
    pub specular: Image,
    /// The irradiance cube, E/π.
    pub diffuse: Image,
    /// The environment itself (the chain's level 0) with no other level:
    /// Bevy's skybox picks its mip level from screen-space derivatives, and
    /// the chain's other levels are blurred by the GGX lobe, not downsampled.
    pub skybox: Image,
}

impl EnvironmentImages {
    /// The images of `bake` (which must hold a chain and an irradiance map:
    /// Bevy's preset makes both) in `format` (RGB9E5, as Bevy's own maps,
    /// or RGBA16F).
    ///
    /// # Errors
    ///
    /// A bake without its chain or irradiance map; a format wgpu lacks.
    pub fn from_bake(bake: &Bake, format: TexelFormat) -> envmap_render::Result<Self> {
        let chain = bake
            .chain
            .as_ref()
            .ok_or_else(|| envmap_render::Error::Input("the bake has no specular chain".into()))?;
        let irr = bake
            .irradiance
            .as_ref()
            .ok_or_else(|| envmap_render::Error::Input("the bake has no irradiance map".into()))?;
        Ok(Self {
            specular: cube_image(&chain.levels, format)?,
            diffuse: cube_image(std::slice::from_ref(&irr.image), format)?,
            skybox: cube_image(&chain.levels[..1], format)?,
        })
    }

    /// Adds the images to `images`; returns the light (diffuse + specular at
    /// `intensity`) and the skybox at the same brightness.
    pub fn into_components(
        self,
        images: &mut Assets<Image>,
        intensity: f32,
    ) -> (EnvironmentMapLight, Skybox) {
        let specular = images.add(self.specular);
        let diffuse = images.add(self.diffuse);
        let skybox = images.add(self.skybox);
        (
            EnvironmentMapLight {
                diffuse_map: diffuse,
                specular_map: specular,
                intensity,
                ..default()
            },
            Skybox {
                image: Some(skybox),
                brightness: intensity,
                ..default()
            },
        )
    }
}

/// Put on a camera: its environment, baked by [`EnvmapPlugin`] off the
/// main thread from an HDRI file's bytes; when the bake is done the camera
/// gets an [`EnvironmentMapLight`] and a [`Skybox`] and this component is
/// replaced by [`BakedEnvironment`].
#[derive(Component, Clone, Debug)]
pub struct BakeEnvironment {
    /// The HDRI file's bytes.
    pub bytes: Arc<[u8]>,
    /// Its name (the extension says the format).
    pub name: String,
    /// The chain's face size (Bevy's default 512).
    pub size: u32,
    /// The texel format of the maps.
    pub format: TexelFormat,
    /// The light's intensity and the skybox's brightness.
    pub intensity: f32,
}

impl BakeEnvironment {
    /// `bytes` of the file `name`, a 512² chain in RGB9E5, intensity 1.
    pub fn new(bytes: impl Into<Arc<[u8]>>, name: impl Into<String>) -> Self {
        Self {
            bytes: bytes.into(),
            name: name.into(),
            size: 512,
            format: TexelFormat::E5b9g9r9,
            intensity: 1.0,
        }
    }
}

/// What a finished [`BakeEnvironment`] left on its camera.
#[derive(Component, Clone, Debug)]
pub struct BakedEnvironment {
    /// Seconds the bake took (on the task pool's thread).
    pub seconds: f64,
    /// The error, if it failed (the camera then has no light from it).
    pub error: Option<String>,
}

/// A bake running on the task pool.
#[derive(Component)]
struct BakeTask(Task<(envmap_render::Result<EnvironmentImages>, f64)>, f32);

/// Runs [`BakeEnvironment`]s on the `AsyncComputeTaskPool` and gives their
/// cameras the result.
pub struct EnvmapPlugin;

impl Plugin for EnvmapPlugin {
    fn build(&self, app: &mut App) {
        app.add_systems(Update, (start_bakes, finish_bakes).chain());
    }
}

fn start_bakes(mut commands: Commands, requests: Query<(Entity, &BakeEnvironment)>) {
    let pool = AsyncComputeTaskPool::get();
    for (entity, req) in &requests {
        let req = req.clone();
        let task = pool.spawn(async move {
            let t = std::time::Instant::now();
            let images = bake_hdri(&req.bytes, &req.name, req.size)
                .and_then(|b| EnvironmentImages::from_bake(&b, req.format));
            (images, t.elapsed().as_secs_f64())
        });
        commands
            .entity(entity)
            .remove::<BakeEnvironment>()
            .insert(BakeTask(task, req.intensity));
    }
}

fn finish_bakes(
    mut commands: Commands,
    mut tasks: Query<(Entity, &mut BakeTask)>,
    mut images: ResMut<Assets<Image>>,
) {
    for (entity, mut task) in &mut tasks {
        let intensity = task.1;
        let Some((result, seconds)) = block_on(poll_once(&mut task.0)) else {
            continue;
        };
        let mut e = commands.entity(entity);
        e.remove::<BakeTask>();
        match result {
            Ok(env) => {
                let (light, sky) = env.into_components(&mut images, intensity);
                e.insert((
                    light,
                    sky,
                    BakedEnvironment {
                        seconds,
                        error: None,
                    },
                ));
            }
            Err(err) => {
                e.insert(BakedEnvironment {
                    seconds,
                    error: Some(err.to_string()),
                });
            }
        }
    }
}
