//! The engines' presets as values: what a bake makes for Bevy, glTF viewers
//! and Filament (sizes, roughness rule, texel format, container, axes, file
//! names), and the container choice itself.

use envmap_core::glam::{Mat3, Vec3};
use envmap_core::Frame;

use crate::error::{Error, Result};
use crate::filter::bake::BakeOptions;
use crate::filter::dfg::DfgGrid;
use crate::filter::sh::ShWindow;
use crate::filter::specular::RoughnessRule;
use crate::image::convention::FileAxes;
use crate::image::layout::Layout;
use crate::image::texture::TextureOptions;
use crate::image::{FileFormat, TexelFormat};

/// An engine a bake is made for (`envmap bake --target`); see
/// `docs/engines.md` for what each loads and how it was checked.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Target {
    /// Bevy's `EnvironmentMapLight`: E5B9G9R9 + zstd KTX2 cubes, 512²
    /// specular (roughness = mip / (mips − 1)), 32² diffuse.
    Bevy,
    /// glTF-IBL-Sampler's outputs: RGBA16F KTX2 cubes and the BRDF LUT.
    Gltf,
    /// Filament's `cmgen --deploy`: KTX 1, R11F_G11F_B10F, the `sh` key,
    /// mirrored unless asked otherwise.
    Filament,
    /// Babylon.js's `.env`: one file holding an RGBD cube chain (PNG) down
    /// to 1×1 at Babylon.js's roughness rule, and the irradiance
    /// polynomial; 256², in Babylon.js's left-handed y-up world.
    Babylon,
    /// glTF's `EXT_lights_image_based`, as Babylon.js's glTF loader reads
    /// it: one `.gltf` holding the light (RGBD PNG levels down to 1×1 at
    /// lod = log2(size·α), the irradiance SH), 256², in Babylon.js's world.
    GltfIbl,
}

impl Target {
    /// Every target.
    pub const ALL: [Target; 5] = [
        Target::Bevy,
        Target::Gltf,
        Target::Filament,
        Target::Babylon,
        Target::GltfIbl,
    ];

    /// The name `--target` takes and the manifest records.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Target::Bevy => "bevy",
            Target::Gltf => "gltf",
            Target::Filament => "filament",
            Target::Babylon => "babylon",
            Target::GltfIbl => "gltf-ibl",
        }
    }
}

impl std::str::FromStr for Target {
    type Err = String;

    fn from_str(s: &str) -> std::result::Result<Self, String> {
        match s.to_ascii_lowercase().as_str() {
            "bevy" => Ok(Target::Bevy),
            "gltf" | "gltf-ibl-sampler" | "khronos" => Ok(Target::Gltf),
            "filament" | "cmgen" => Ok(Target::Filament),
            "babylon" | "babylonjs" | "babylon.js" => Ok(Target::Babylon),
            "gltf-ibl" | "ext_lights_image_based" => Ok(Target::GltfIbl),
            _ => Err(format!(
                "{s}: expected bevy, gltf, filament, babylon or gltf-ibl"
            )),
        }
    }
}

/// The zstd level of the presets that supercompress: zstd's own default
/// (higher levels give smaller files far more slowly;
/// `docs/performance.md`).
pub const DEFAULT_ZSTD: i32 = 3;

/// What a bake makes and how its files are written: a [`Target`]'s
/// choices ([`Preset::for_target`]) or envmap's own default
/// ([`Preset::default`]), any field of which a caller may change.
/// [`Preset::bake_options`] turns it into the bake's options;
/// [`crate::bake::Baker::with_preset`] bakes with it, and the result writes
/// the files it names.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct Preset {
    /// The engine, if any (recorded in the manifest).
    pub target: Option<Target>,
    /// Face size of the specular chain's level 0.
    pub size: u32,
    /// The mip ↔ roughness rule.
    pub rule: RoughnessRule,
    /// Face size of the smallest level (`None`: the rule's default).
    pub min_size: Option<u32>,
    /// Face size of the irradiance cube (0: none).
    pub irradiance_size: u32,
    /// Deringing of the SH9 (and of the irradiance map made from it).
    pub sh_window: Option<ShWindow>,
    /// Size of the DFG table (0: none).
    pub dfg_size: u32,
    /// Where the DFG table's texels sit (texel centres unless asked).
    pub dfg_grid: DfgGrid,
    /// Container of the maps: [`FileFormat::Exr`] (one file, or six, per
    /// level), or one texture file per map, every level inside:
    /// [`FileFormat::Ktx2`], [`FileFormat::Dds`] or [`FileFormat::Ktx`]
    /// (KTX 1, Filament's).
    pub container: FileFormat,
    /// Texel format and supercompression of texture containers.
    pub texture: TextureOptions,
    /// Layout of the chain's OpenEXR files ([`FileFormat::Exr`]).
    pub layout: Layout,
    /// The cube files' axes.
    pub axes: FileAxes,
    /// The cube mirrored as cmgen's default (x negated; Filament's shaders
    /// undo it).
    pub mirrored: bool,
    /// The specular chain's file stem (`specular`; Filament's `ibl`).
    pub specular: &'static str,
    /// The irradiance map's file stem (`irradiance`; Bevy's and glTF's
    /// `diffuse`).
    pub irradiance: &'static str,
}

impl Default for Preset {
    /// envmap's own: a 512² chain by the linear rule down to 2², one
    /// OpenEXR cross per level, a 32² irradiance cube, the 128² DFG table,
    /// GL axes.
    fn default() -> Self {
        Self {
            target: None,
            size: 512,
            rule: RoughnessRule::Linear,
            min_size: None,
            irradiance_size: crate::filter::sh::DEFAULT_IRRADIANCE_SIZE,
            sh_window: None,
            dfg_size: crate::filter::dfg::DEFAULT_SIZE,
            dfg_grid: DfgGrid::TexelCentres,
            container: FileFormat::Exr,
            texture: TextureOptions::default(),
            layout: Layout::Cross,
            axes: FileAxes::default(),
            mirrored: false,
            specular: "specular",
            irradiance: "irradiance",
        }
    }
}

/// `axes` with z negated: the y-up left-handed world of a y-up one (and
/// back), any other frame times diag(1, 1, −1).
#[must_use]
pub(crate) fn z_negated(axes: FileAxes) -> FileAxes {
    use crate::image::convention::World;
    match axes {
        FileAxes::Convention(c, World::YUp) => FileAxes::Convention(c, World::YUpLh),
        FileAxes::Convention(c, World::YUpLh) => FileAxes::Convention(c, World::YUp),
        other => {
            let f = other.frame(envmap_core::AnyMapping::Cube);
            let m = f.matrix() * Mat3::from_diagonal(Vec3::new(1.0, 1.0, -1.0));
            FileAxes::Frame(Frame::from_mat3(m).unwrap_or(f))
        }
    }
}

/// The GL world with x negated: the axes of cmgen's default (mirrored)
/// cube files (`CubemapUtils::mirrorCubemap` samples the source at
/// (−x, y, z)).
fn mirrored_gl() -> FileAxes {
    let m = Frame::Y_UP_RH.matrix() * Mat3::from_diagonal(Vec3::new(-1.0, 1.0, 1.0));
    FileAxes::Frame(Frame::from_mat3(m).unwrap_or(Frame::Y_UP_RH))
}

impl Preset {
    /// The choices of `target`, with the cube files in `axes` (envmap's
    /// default: GL's). Filament's preset mirrors the cube as cmgen does by
    /// default, in GL's axes whatever `axes` says (Filament's world);
    /// `Preset::unmirrored` is `cmgen --no-mirror`.
    #[must_use]
    pub fn for_target(target: Target, axes: FileAxes) -> Self {
        let base = Self {
            target: Some(target),
            axes,
            ..Self::default()
        };
        match target {
            // Bevy's shipped maps (pisa_*_rgb9e5_zstd.ktx2) and its runtime
            // generator: 512² specular with roughness = mip / (mips − 1),
            // 32² diffuse, one level; E5B9G9R9 + zstd. Bevy reads a cube at
            // (x, y, −z) of its world direction (`skybox.wgsl`,
            // `environment_map.wgsl`: "cube maps are left-handed"), so the
            // cube is written in its world with z negated: Bevy then shows
            // the environment as envmap renders it (checked on lavapipe by
            // integrations/bevy/tests/headless.rs; the cube in the world's
            // own axes shows it mirrored).
            Target::Bevy => Self {
                axes: z_negated(axes),
                dfg_size: 0,
                container: FileFormat::Ktx2,
                texture: TextureOptions {
                    format: TexelFormat::E5b9g9r9,
                    zstd: Some(DEFAULT_ZSTD),
                    ..TextureOptions::default()
                },
                irradiance: "diffuse",
                ..base
            },
            // glTF-IBL-Sampler (lib/source/lib.cpp): RGBA16F through libktx,
            // ⌊log2 size⌋ levels (down to 2×2) at roughness i/(n − 1), the
            // Lambertian map, the GGX BRDF LUT.
            Target::Gltf => Self {
                min_size: Some(2),
                container: FileFormat::Ktx2,
                irradiance: "diffuse",
                ..base
            },
            // cmgen --deploy (tools/cmgen): 256², levels down to 16² at
            // lod = (n − 1)·r·(2 − r), R11F_G11F_B10F KTX 1, the SH in the
            // `sh` key (auto-windowed), mirrored unless --no-mirror.
            Target::Filament => Self {
                size: 256,
                rule: RoughnessRule::Filament,
                min_size: Some(16),
                irradiance_size: 0,
                sh_window: Some(ShWindow::Cmgen),
                dfg_size: 0,
                container: FileFormat::Ktx,
                texture: TextureOptions {
                    format: TexelFormat::B10g11r11,
                    zstd: None,
                    ..TextureOptions::default()
                },
                axes: mirrored_gl(),
                mirrored: true,
                specular: "ibl",
                ..base
            },
            // Babylon.js (Misc/environmentTextureTools.ts, HDRFiltering):
            // a .env of RGBD PNGs, every level down to 1×1 at α =
            // 2^(lod/0.8)/size (level 0 unfiltered), the irradiance as its
            // SphericalPolynomial; no irradiance map or DFG table (Babylon.js
            // ships its own BRDF table). Its world is left-handed y-up and it
            // reads a cube at its world direction, so the cube is written in
            // the world with z negated, as for Bevy.
            Target::Babylon => Self {
                size: 256,
                rule: RoughnessRule::Babylon,
                min_size: Some(1),
                irradiance_size: 0,
                dfg_size: 0,
                container: FileFormat::Env,
                texture: TextureOptions {
                    format: TexelFormat::Rgbd8,
                    zstd: None,
                    ..TextureOptions::default()
                },
                axes: z_negated(axes),
                specular: "environment",
                ..base
            },
            // EXT_lights_image_based as Babylon.js's glTF loader reads it
            // (loaders/glTF/2.0/Extensions/EXT_lights_image_based.ts):
            // lodGenerationScale = (levels − 1)/log2(size), 1 for a chain
            // down to 1×1; the same RGBD faces as a .env, in the same world.
            Target::GltfIbl => Self {
                target: Some(target),
                rule: RoughnessRule::Log2,
                container: FileFormat::Gltf,
                ..Self::for_target(Target::Babylon, axes)
            },
        }
    }

    /// `self` without cmgen's mirroring (`cmgen --no-mirror`): the cube in
    /// the axes it was made for.
    #[cfg_attr(not(feature = "instruments"), allow(dead_code))]
    #[cfg_attr(feature = "instruments", visibility::make(pub))]
    #[must_use]
    pub(crate) fn unmirrored(self, axes: FileAxes) -> Self {
        Self {
            axes,
            mirrored: false,
            ..self
        }
    }

    /// The bake's options for this preset (size, levels, rule, irradiance,
    /// SH window, DFG table and its grid, axes); every other field is
    /// `base`'s.
    #[must_use]
    pub fn bake_options<'a>(&self, base: BakeOptions<'a>) -> BakeOptions<'a> {
        BakeOptions {
            size: self.size,
            min_size: self.min_size,
            rule: self.rule.clone(),
            irradiance_size: self.irradiance_size,
            sh_window: self.sh_window,
            dfg_size: self.dfg_size,
            dfg_grid: self.dfg_grid,
            axes: self.axes,
            ..base
        }
    }

    /// Checks the choices against each other.
    ///
    /// # Errors
    ///
    /// A container that holds no bake, supercompression outside KTX2, a
    /// layout that is not a cube's.
    #[cfg_attr(feature = "instruments", visibility::make(pub))]
    pub(crate) fn check(&self) -> Result<()> {
        if !(self.container == FileFormat::Exr || self.container.is_texture()) {
            return Err(Error::options(format!(
                "{}: a bake is written as exr, ktx2, dds, ktx, env or gltf",
                self.container.name()
            )));
        }
        if self.container != FileFormat::Ktx2 && self.texture.zstd.is_some() {
            return Err(Error::options(format!(
                "zstd: only KTX2 has supercompression (the container is {})",
                self.container.extension()
            )));
        }
        if matches!(self.container, FileFormat::Env | FileFormat::Gltf) && self.irradiance_size > 0
        {
            return Err(Error::options(format!(
                "{}: holds the specular chain and the irradiance as SH, no irradiance map (irradiance size 0)",
                self.container.name()
            )));
        }
        if !Layout::for_mapping(envmap_core::AnyMapping::Cube).contains(&self.layout) {
            return Err(Error::options(format!(
                "layout {}: not a cube layout (cross, vcross, strip, vstrip, faces)",
                self.layout
            )));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::convention::{Convention, World};
    use envmap_core::AnyMapping;

    /// A bake is written only in a container that holds one; another
    /// format is refused by name.
    #[test]
    fn only_exr_and_texture_containers_hold_a_bake() {
        for &f in FileFormat::ALL {
            let p = Preset {
                container: f,
                ..Preset::default()
            };
            let ok = p.check();
            assert_eq!(
                ok.is_ok(),
                matches!(
                    f,
                    FileFormat::Exr | FileFormat::Ktx2 | FileFormat::Dds | FileFormat::Ktx
                ),
                "{}",
                f.name()
            );
            if let Err(e) = ok {
                assert!(e.to_string().contains(f.name()), "{e}");
            }
        }
    }

    /// Bevy's axes are the world's with z negated, however they are named.
    #[test]
    fn bevys_axes_negate_z() {
        let gl = FileAxes::Convention(Convention::Envmap, World::YUp);
        let bevy = Preset::for_target(Target::Bevy, gl).axes;
        assert_eq!(bevy, FileAxes::Convention(Convention::Envmap, World::YUpLh));
        let want =
            gl.frame(AnyMapping::Cube).matrix() * Mat3::from_diagonal(Vec3::new(1.0, 1.0, -1.0));
        let got = bevy.frame(AnyMapping::Cube).matrix();
        assert!(got.abs_diff_eq(want, 1e-6), "{got:?} against {want:?}");
        let z = FileAxes::Convention(Convention::Envmap, World::ZUp);
        let zb = z_negated(z).frame(AnyMapping::Cube).matrix();
        let zw =
            z.frame(AnyMapping::Cube).matrix() * Mat3::from_diagonal(Vec3::new(1.0, 1.0, -1.0));
        assert!(zb.abs_diff_eq(zw, 1e-6));
        assert_eq!(z_negated(z_negated(gl)), gl);
    }
}
