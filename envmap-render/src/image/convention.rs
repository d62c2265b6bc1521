// File conventions: what the directions of a file mean.

use std::fmt;
use std::str::FromStr;

use envmap_core::glam::{Mat3, Vec3};
use envmap_core::{AnyMapping, Frame};

use crate::error::{Error, Result};

/// The axes the command's directions, and the conventions of its files, are
/// expressed in; see the [module docs](super).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum World {
    /// The GL world: y up, right-handed (OpenGL, Vulkan, glTF, WebGPU,
    /// three.js, Bevy, Filament). The default.
    #[default]
    YUp,
    /// Y up, left-handed (Direct3D, Unity): the GL world with z negated.
    YUpLh,
    /// envmap's canonical frame (z up, right-handed; seed `000`): every
    /// mapping's formula is applied to the directions as given, whatever the
    /// convention.
    ZUp,
}

impl World {
    /// Every world, as [`World::NAMES`] lists them.
    pub const ALL: [World; 3] = [World::YUp, World::YUpLh, World::ZUp];

    /// The names on the command line (`--frame`, `--from-frame`, `--to-frame`).
    pub const NAMES: [&'static str; 3] = ["y-up", "y-up-lh", "z-up"];

    /// The name on the command line.
    #[must_use]
    pub const fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }

    /// World axes → envmap's canonical axes ([`Frame::Y_UP_RH`],
    /// [`Frame::Y_UP_LH`] or the identity).
    #[must_use]
    pub const fn frame(self) -> Frame {
        match self {
            World::YUp => Frame::Y_UP_RH,
            World::YUpLh => Frame::Y_UP_LH,
            World::ZUp => Frame::Z_UP_RH,
        }
    }

    /// What the world is, in a few words.
    #[must_use]
    pub const fn describe(self) -> &'static str {
        match self {
            World::YUp => "the GL world (y up, right-handed)",
            World::YUpLh => "y up, left-handed (Direct3D, Unity: the GL world with z negated)",
            World::ZUp => "envmap's canonical z-up frame (seed 000): each mapping's formula on the directions as given",
        }
    }
}

impl fmt::Display for World {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for World {
    type Err = Error;

    /// The names in [`World::NAMES`] (case-insensitive) and the aliases
    /// `yup`, `y-up-rh`, `gl`, `gltf` (y-up); `d3d`, `unity` (y-up-lh); `zup`,
    /// `z-up-rh`, `seed` (z-up).
    fn from_str(s: &str) -> Result<Self> {
        match s.to_ascii_lowercase().as_str() {
            "y-up" | "yup" | "y-up-rh" | "gl" | "gltf" => Ok(World::YUp),
            "y-up-lh" | "d3d" | "unity" => Ok(World::YUpLh),
            "z-up" | "zup" | "z-up-rh" | "seed" => Ok(World::ZUp),
            _ => Err(Error::UnknownName {
                what: "frame",
                name: s.to_owned(),
                expected: "y-up (the GL world, the default), y-up-lh (Direct3D, Unity), \
                           z-up (envmap's canonical frame, the seed's)"
                    .to_owned(),
            }),
        }
    }
}

/// A named set of file conventions; see the [module docs](super).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Convention {
    /// envmap's own (the default): a latlong as `cmgen --no-mirror` and
    /// `py360convert.e2c` read it (image centre +z, +x at u = 0.75); every
    /// other mapping as `Convention::frame_in_world` states.
    #[default]
    Envmap,
    /// Filament's `cmgen` with its default mirroring (also OpenEXR's
    /// `exrenvmap` and Mitsuba 3): image centre +z, −x at u = 0.75.
    Cmgen,
    /// `py360convert` (its `e2c` faces F, R, B, L, U, D are +z, +x, −z, −x,
    /// +y, −y): the same latlong as [`Convention::Envmap`].
    Py360convert,
    /// Blender (Cycles' and EEVEE's equirectangular environment texture),
    /// in glTF's axes (x, z, −y): image centre +x, +z at u = 0.75.
    Blender,
    /// three.js (`equirectUv`, `fromEquirectangularTexture`): as Blender.
    Three,
    /// glTF-IBL-Sampler (`panoramaToCubeMap`): as Blender.
    GltfIblSampler,
    /// Bevy (`Image::equirectangular_to_cubemap`): as Blender.
    Bevy,
    /// Unity (`Skybox/Panoramic`), with Unity's left-handed world taken to
    /// the GL world by negating z: as Blender.
    Unity,
    /// pbrt-v3 and pbrt-v4 (`InfiniteAreaLight`, `imgtool makeequiarea`),
    /// pbrt's left-handed z-up world taken to the GL world as (x, z, y):
    /// image centre −x, −z at u = 0.75.
    Pbrt,
}

/// The six latlong layouts of the presets: the linear map from the core's
/// latlong axes f (u = atan2(f.y, f.x)/2π, v = acos(f.z)/π) to y-up world
/// axes g, as `[g.x, g.y, g.z]` in terms of f, each a signed axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum LatLongLayout {
    /// Image centre +z, u → +x: `cmgen --no-mirror`, py360convert.
    CentreZMirrored,
    /// Image centre +z, u → −x: cmgen (mirrored), OpenEXR, Mitsuba.
    CentreZ,
    /// Image centre +x, u → +z: Blender, three.js, glTF-IBL-Sampler.
    CentreX,
    /// Image centre −x, u → −z: pbrt.
    CentreMinusX,
}

impl LatLongLayout {
    /// f → g.
    fn matrix(self) -> Mat3 {
        // With φ = 2π(u − ½): the core's f = (−sin θ cos φ, −sin θ sin φ, cos θ).
        let cols = |gx: Vec3, gy: Vec3, gz: Vec3| Mat3::from_cols(gx, gy, gz).transpose();
        match self {
            // g = (sin θ sin φ, cos θ, sin θ cos φ) = (−f.y, f.z, −f.x)
            LatLongLayout::CentreZMirrored => cols(-Vec3::Y, Vec3::Z, -Vec3::X),
            // g = (−sin θ sin φ, cos θ, sin θ cos φ) = (f.y, f.z, −f.x)
            LatLongLayout::CentreZ => cols(Vec3::Y, Vec3::Z, -Vec3::X),
            // g = (sin θ cos φ, cos θ, sin θ sin φ) = (−f.x, f.z, −f.y)
            LatLongLayout::CentreX => cols(-Vec3::X, Vec3::Z, -Vec3::Y),
            // g = (−sin θ cos φ, cos θ, −sin θ sin φ) = (f.x, f.z, f.y)
            LatLongLayout::CentreMinusX => cols(Vec3::X, Vec3::Z, Vec3::Y),
        }
    }
}

impl Convention {
    /// Every convention, as [`Convention::NAMES`] lists them.
    pub const ALL: [Convention; 9] = [
        Convention::Envmap,
        Convention::Cmgen,
        Convention::Py360convert,
        Convention::Blender,
        Convention::Three,
        Convention::GltfIblSampler,
        Convention::Bevy,
        Convention::Unity,
        Convention::Pbrt,
    ];

    /// The names on the command line (`--convention`), in the order of
    /// [`Convention::ALL`].
    pub const NAMES: [&'static str; 9] = [
        "envmap",
        "cmgen",
        "py360convert",
        "blender",
        "three",
        "gltf-ibl-sampler",
        "bevy",
        "unity",
        "pbrt",
    ];

    /// The name on the command line.
    #[must_use]
    pub const fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }

    fn latlong(self) -> LatLongLayout {
        match self {
            Convention::Envmap | Convention::Py360convert => LatLongLayout::CentreZMirrored,
            Convention::Cmgen => LatLongLayout::CentreZ,
            Convention::Blender
            | Convention::Three
            | Convention::GltfIblSampler
            | Convention::Bevy
            | Convention::Unity => LatLongLayout::CentreX,
            Convention::Pbrt => LatLongLayout::CentreMinusX,
        }
    }

    /// Where each preset comes from: the tool's own code, as read, and what
    /// was measured against the tool itself.
    #[must_use]
    pub const fn source(self) -> &'static str {
        match self {
            Convention::Envmap => {
                "envmap's default; equal, face for face, to `cmgen --no-mirror` (Filament 1.9.25) \
                 and `py360convert.e2c` (1.0.4), measured"
            }
            Convention::Cmgen => {
                "google/filament libs/ibl/src/CubemapUtils.cpp (equirectangularToCubemap: \
                 u = 1/2 + atan2(x, z)/2π, v = acos(y)/π; mirrorCubemap samples (−x, y, z)) and \
                 tools/cmgen/src/cmgen.cpp (\"we mirror by default\"); measured against cmgen 1.9.25; \
                 also OpenEXR ImfEnvmap.cpp LatLongMap::direction and Mitsuba 3 envmap.cpp uv_to_direction"
            }
            Convention::Py360convert => {
                "sunset1995/py360convert utils.py (xyz2uv: u = atan2(x, z), uv2coor; xyzcube: \
                 faces F R B L U D); measured against py360convert 1.0.4"
            }
            Convention::Blender => {
                "blender intern/cycles/kernel/camera/projection.h (direction_to_equirectangular, \
                 range (−2π, π, −π, π)) and EEVEE's node_tex_environment_equirectangular; Blender's \
                 z-up world taken to the GL world as glTF does (x, z, −y)"
            }
            Convention::Three => {
                "mrdoob/three.js src/renderers/shaders/ShaderChunk/common.glsl.js (equirectUv: \
                 u = atan(z, x)/2π + 1/2) and WebGLCubeRenderTarget.fromEquirectangularTexture"
            }
            Convention::GltfIblSampler => {
                "KhronosGroup/glTF-IBL-Sampler lib/source/shaders/filter.frag (panoramaToCubeMap, \
                 uvToXYZ, dirToUV: u = 1/2 + atan(z, x)/2π)"
            }
            Convention::Bevy => {
                "bevyengine/bevy crates/bevy_image/src/equirectangular.rs \
                 (equirectangular_to_cubemap: u = 1/2 + atan2(z, x)/2π, v = acos(y)/π); Bevy samples \
                 cube maps at (x, y, −z) (skybox.wgsl, environment_map.wgsl)"
            }
            Convention::Unity => {
                "Unity built-in shaders DefaultResourcesExtra/Skybox-Panoramic.shader \
                 (ToRadialCoords: longitude atan2(z, x), latitude acos(y)); Unity's left-handed \
                 world taken to the GL world by negating z"
            }
            Convention::Pbrt => {
                "mmp/pbrt-v3 src/lights/infinite.cpp (InfiniteAreaLight::Le: SphericalPhi = \
                 atan2(y, x), SphericalTheta = acos(z)) and mmp/pbrt-v4 src/pbrt/cmd/imgtool.cpp \
                 (makeequiarea); pbrt's left-handed z-up world taken to the GL world as (x, z, y)"
            }
        }
    }

    /// For `mapping`, the linear map from the axes its core formula is
    /// applied in to the y-up world's axes (`world` the world the convention
    /// is expressed in, for [`World::YUp`] and [`World::YUpLh`] alike):
    ///
    /// | mapping | the file, in the y-up world |
    /// | --- | --- |
    /// | cube and EAC (every convention) | the GL face table applied to (x, y, z) as given: +y face up |
    /// | fisheye, dual fisheye (every convention) | the (front) lens looks along +z, the latlong's centre, with +x to the right of its image and +y up; the back lens looks along −z with −x to its right |
    /// | latlong | the preset's row of the [module docs](super) table |
    /// | tennisball | the latlong's axes |
    /// | octahedral, equal-area octahedral | centre +y (up), +x at the right edge's middle, +z at the bottom edge's middle |
    /// | sphere map (class and GL), angular, dual paraboloid | a mirror ball photographed from +z looking along −z, +y up: centre +z, +x to the right, +y to the top (the paraboloid's front disk, on the left, is +z; its back disk −z, joining it at the rim) |
    #[must_use]
    pub(crate) fn frame_in_world(self, mapping: AnyMapping) -> Mat3 {
        let diag = |x: f32, y: f32, z: f32| Mat3::from_diagonal(Vec3::new(x, y, z));
        match mapping {
            // The fisheye's formula axes are the camera's: x right, y up, the lens along z.
            AnyMapping::Cube | AnyMapping::Eac | AnyMapping::Fisheye(_) => Mat3::IDENTITY,
            AnyMapping::LatLong | AnyMapping::Tennisball => self.latlong().matrix(),
            // g = (f.x, f.z, f.y)
            AnyMapping::Octahedral | AnyMapping::EqualAreaOctahedral => {
                Mat3::from_cols(Vec3::X, Vec3::Z, Vec3::Y)
            }
            // The class formula's own axes are a camera's (x right, y down,
            // z forward): a camera at +z looking along −z has them as
            // (x, −y, −z).
            AnyMapping::SphereMap => diag(1.0, -1.0, -1.0),
            AnyMapping::SphereMapGl | AnyMapping::DualParaboloid | AnyMapping::Angular => {
                diag(1.0, -1.0, 1.0)
            }
        }
    }

    /// The frame (file axes → envmap's canonical axes) of a `mapping` file
    /// in this convention and `world`: the world's frame after
    /// `Convention::frame_in_world`, or the identity in [`World::ZUp`].
    #[must_use]
    pub fn frame(self, mapping: AnyMapping, world: World) -> Frame {
        if world == World::ZUp {
            return Frame::IDENTITY;
        }
        let m = world.frame().matrix() * self.frame_in_world(mapping);
        // A signed permutation of the axes: always orthogonal.
        Frame::from_mat3(m).unwrap_or(Frame::IDENTITY)
    }
}

impl fmt::Display for Convention {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Convention {
    type Err = Error;

    /// The names in [`Convention::NAMES`] (case-insensitive) and the aliases
    /// `filament` (cmgen), `cmgen-no-mirror` (envmap), `py360` (py360convert),
    /// `threejs`, `three.js` (three), `gltf`, `gltf-ibl`, `ibl-sampler`
    /// (gltf-ibl-sampler), `pbrt-v3`, `pbrt-v4` (pbrt), `openexr`,
    /// `exrenvmap`, `mitsuba` (cmgen: the same latlong).
    fn from_str(s: &str) -> Result<Self> {
        let l = s.to_ascii_lowercase();
        if let Some(c) = Convention::ALL.into_iter().find(|c| c.name() == l) {
            return Ok(c);
        }
        Ok(match l.as_str() {
            "cmgen-no-mirror" => Convention::Envmap,
            "filament" | "openexr" | "exrenvmap" | "mitsuba" | "mitsuba3" => Convention::Cmgen,
            "py360" => Convention::Py360convert,
            "threejs" | "three.js" => Convention::Three,
            "gltf" | "gltf-ibl" | "ibl-sampler" => Convention::GltfIblSampler,
            "pbrt-v3" | "pbrt-v4" => Convention::Pbrt,
            _ => {
                return Err(Error::UnknownName {
                    what: "convention",
                    name: s.to_owned(),
                    expected: Convention::NAMES.join(", "),
                })
            }
        })
    }
}

/// How a file's directions relate to envmap's canonical frame: a
/// convention in a world, or an explicit frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FileAxes {
    /// The convention's axes for the file's mapping, in the world.
    Convention(Convention, World),
    /// This frame, whatever the mapping.
    Frame(Frame),
}

impl Default for FileAxes {
    /// [`Convention::Envmap`] in [`World::YUp`].
    fn default() -> Self {
        FileAxes::Convention(Convention::Envmap, World::YUp)
    }
}

impl FileAxes {
    /// The seed's axes: every formula on the directions as given
    /// ([`World::ZUp`]).
    pub const Z_UP: FileAxes = FileAxes::Convention(Convention::Envmap, World::ZUp);

    /// The frame of a `mapping` file.
    #[must_use]
    pub fn frame(self, mapping: AnyMapping) -> Frame {
        match self {
            FileAxes::Convention(c, w) => c.frame(mapping, w),
            FileAxes::Frame(f) => f,
        }
    }

    /// A `mapping` file's axes in a sentence, for `envmap info` and a
    /// file's metadata: the world, the convention, and where the image's
    /// centre and edges look.
    #[must_use]
    pub fn describe(self, mapping: AnyMapping) -> String {
        match self {
            FileAxes::Convention(_, World::ZUp) => format!(
                "{}; {}",
                World::ZUp.describe(),
                landmarks(mapping, Frame::IDENTITY, World::ZUp)
            ),
            FileAxes::Convention(c, w) => format!(
                "convention {c} in {}; {}",
                w.describe(),
                landmarks(mapping, c.frame(mapping, w), w)
            ),
            FileAxes::Frame(f) => {
                let m = f.matrix();
                format!(
                    "a frame given explicitly (file axes → envmap's z-up axes: x → {}, y → {}, z → {})",
                    axis_name(m.x_axis),
                    axis_name(m.y_axis),
                    axis_name(m.z_axis)
                )
            }
        }
    }
}

/// `v` as `+x` ... `−z` when it is an axis (within rounding), else its
/// components.
fn axis_name(v: Vec3) -> String {
    for (a, n) in [(Vec3::X, "x"), (Vec3::Y, "y"), (Vec3::Z, "z")] {
        if (v - a).length() < 1e-5 {
            return format!("+{n}");
        }
        if (v + a).length() < 1e-5 {
            return format!("−{n}");
        }
    }
    format!("({:.3}, {:.3}, {:.3})", v.x, v.y, v.z)
}

/// Where the charts' centres look, and where the world's +x and +y land,
/// for a `mapping` file with `frame` in `world`.
fn landmarks(mapping: AnyMapping, frame: Frame, world: World) -> String {
    use envmap_core::{ChartUv, Mapping};
    if mapping.has_cube_faces() {
        return "the GL face table on (x, y, z) as given, row 0 of each face at the top".to_owned();
    }
    let to_file = |w: Vec3| frame.from_canonical(world.frame().to_canonical(w));
    let centres: Vec<String> = (0..mapping.chart_count())
        .map(|c| {
            mapping
                .inverse(ChartUv::new(c, 0.5, 0.5))
                .map(|d| axis_name(world.frame().from_canonical(frame.to_canonical(d))))
                .unwrap_or_else(|| "—".to_owned())
        })
        .collect();
    let at = |w: Vec3| match mapping.forward(to_file(w)) {
        Some(p) if mapping.chart_count() > 1 => {
            format!("chart {} ({:.3}, {:.3})", p.chart, p.u, p.v)
        }
        Some(p) => format!("({:.3}, {:.3})", p.u, p.v),
        None => "—".to_owned(),
    };
    let centre = if centres.len() == 1 {
        format!("image centre {}", centres[0])
    } else {
        format!("chart centres {}", centres.join(", "))
    };
    format!(
        "{centre}; +x at (u, v) = {}, +y at {}",
        at(Vec3::X),
        at(Vec3::Y)
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use envmap_core::ChartUv;

    /// Where chart point (u, v) of a latlong looks in the GL world under `c`.
    fn latlong_dir(c: Convention, u: f32, v: f32) -> Vec3 {
        let f = AnyMapping::LatLong.inverse(ChartUv::new(0, u, v)).unwrap();
        World::YUp
            .frame()
            .from_canonical(c.frame(AnyMapping::LatLong, World::YUp).to_canonical(f))
    }

    /// Each preset against the formula written from its source, at points
    /// all over the image (not only at the axes).
    #[test]
    fn every_preset_matches_its_formula() {
        use std::f32::consts::PI;
        type Formula = fn(f32, f32) -> Vec3;
        let a: Formula = |t, p| Vec3::new(t.sin() * p.cos(), t.cos(), t.sin() * p.sin());
        let b: Formula = |t, p| Vec3::new(-t.sin() * p.sin(), t.cos(), t.sin() * p.cos());
        let d: Formula = |t, p| Vec3::new(-t.sin() * p.cos(), t.cos(), -t.sin() * p.sin());
        let f: Formula = |t, p| Vec3::new(t.sin() * p.sin(), t.cos(), t.sin() * p.cos());
        for c in Convention::ALL {
            let want = match c {
                Convention::Envmap | Convention::Py360convert => f,
                Convention::Cmgen => b,
                Convention::Pbrt => d,
                _ => a,
            };
            for i in 0..37 {
                for j in 1..18 {
                    let (u, v) = (i as f32 / 37.0 + 0.01, j as f32 / 18.0);
                    let got = latlong_dir(c, u, v);
                    let w = want(PI * v, 2.0 * PI * (u - 0.5));
                    assert!((got - w).length() < 2e-6, "{c} at ({u}, {v}): {got} vs {w}");
                }
            }
        }
        // The source formulas themselves, as the tools write them, at one
        // point: cmgen --no-mirror and py360convert read u = ½ + atan2(x, z)/2π.
        let g = latlong_dir(Convention::Envmap, 0.6, 0.3);
        let u = 0.5 + g.x.atan2(g.z) / (2.0 * PI);
        assert!((u - 0.6).abs() < 1e-6 && (g.y.acos() / PI - 0.3).abs() < 1e-6);
        // three.js: u = atan(z, x)/2π + ½.
        let g = latlong_dir(Convention::Three, 0.6, 0.3);
        assert!((g.z.atan2(g.x) / (2.0 * PI) + 0.5 - 0.6).abs() < 1e-6);
        // pbrt, in its own axes p = (g.x, g.z, g.y): u = atan2(p.y, p.x)/2π
        // (wrapped), v = acos(p.z)/π.
        let g = latlong_dir(Convention::Pbrt, 0.6, 0.3);
        let u = g.z.atan2(g.x).rem_euclid(2.0 * PI) / (2.0 * PI);
        assert!((u - 0.6).abs() < 1e-6, "{u}");
    }

    #[test]
    fn cube_files_are_in_the_gl_world_whatever_the_convention() {
        for c in Convention::ALL {
            let f = c.frame(AnyMapping::Cube, World::YUp);
            assert_eq!(f, Frame::Y_UP_RH);
            // +y of the file is the world's up (canonical +z).
            assert_eq!(f.to_canonical(Vec3::Y), Vec3::Z);
        }
        assert_eq!(
            Convention::Envmap.frame(AnyMapping::Cube, World::ZUp),
            Frame::IDENTITY
        );
    }

    #[test]
    fn names_round_trip_and_errors_list_them() {
        for c in Convention::ALL {
            assert_eq!(c.name().parse::<Convention>().unwrap(), c);
        }
        for w in World::ALL {
            assert_eq!(w.name().parse::<World>().unwrap(), w);
        }
        assert_eq!("Filament".parse::<Convention>().unwrap(), Convention::Cmgen);
        let e = "maya".parse::<Convention>().unwrap_err().to_string();
        assert!(e.contains("blender") && e.contains("maya"), "{e}");
    }

    #[test]
    fn descriptions_name_the_landmarks() {
        let d = FileAxes::default().describe(AnyMapping::LatLong);
        assert!(
            d.contains("image centre +z") && d.contains("+x at (u, v) = (0.750, 0.500)"),
            "{d}"
        );
        assert!(d.contains("+y at (0.") && d.contains(", 0.000)"), "{d}");
        let d = FileAxes::default().describe(AnyMapping::Octahedral);
        assert!(
            d.contains("centre +y") && d.contains("+x at (u, v) = (1.000, 0.500)"),
            "{d}"
        );
        let d = FileAxes::default().describe(AnyMapping::SphereMapGl);
        assert!(
            d.contains("centre +z") && d.contains("+y at (0.500, 0.146)"),
            "{d}"
        );
        let d = FileAxes::Z_UP.describe(AnyMapping::Cube);
        assert!(d.contains("canonical z-up"), "{d}");
        let d = FileAxes::Frame(Frame::Y_UP_RH).describe(AnyMapping::Cube);
        assert!(d.contains("explicitly") && d.contains("y → +z"), "{d}");
    }
}
