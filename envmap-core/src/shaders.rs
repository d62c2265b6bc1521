//! The mappings and the image-based-lighting lookups as shader code, held to
//! this crate's results on a GPU.
//!
//! **WGSL is the source** (`envmap-core/shaders/*.wgsl`, one file per
//! mapping with the name of its Rust module, each beginning with its formula
//! and source as the Rust file does). GLSL 4.50, GLSL ES 3.00 and HLSL
//! (shader model 5.0) are written from it by naga and committed under
//! `envmap-core/shaders/generated/`; a test of `envmap-tests` fails when
//! they are stale. Each function mirrors the Rust one branch for branch:
//! the same tie rules (the cube's z over y over x), seams, fold signs,
//! clamps and invalid results. Where a GPU may legitimately disagree (it may
//! flush subnormals to zero, ignore the sign of zero in arithmetic, and its
//! `sin`, `cos` and `sqrt` round differently), `docs/shaders.md` says so and
//! gives each function's bound, portable and as measured on Mesa's
//! lavapipe.
//!
//! WGSL has no includes: every file after [`COMMON_WGSL`] needs it (and
//! [`EAC_WGSL`] needs [`CUBE_WGSL`] too, [`LIGHTING_WGSL`] [`FRAME_WGSL`],
//! [`LATLONG_WGSL`], [`CUBE_WGSL`] and [`OCTAHEDRAL_WGSL`]), in the order of
//! [`WGSL_FILES`]. [`ALL_WGSL`] is every file in that order, one
//! self-contained module. Every name is prefixed `envmap_` (functions),
//! `Envmap` (structs) or `ENVMAP_` (constants), and none ends in a digit, so
//! naga writes every one of them unchanged into the GLSL and HLSL (a test
//! checks it).
//!
//! The generated files are self-contained too, one per mapping (`common`,
//! `frame` and the mapping; the EAC's holds the cube too), one for the
//! lighting lookups and one with everything ([`ALL_GLSL`],
//! [`ALL_GLSL_ES`], [`ALL_HLSL`]): include one of
//! them in a shader (each carries the shared functions, so two of them
//! together define those twice). They hold no `#version` line and no entry
//! point: they are libraries to paste or include after the shader's own
//! header.
//!
//! ```
//! use envmap_core::shaders;
//! // A wgpu or Bevy shader: the library, then the shader's own code.
//! let source = format!("{}\n{}", shaders::ALL_WGSL, "/* your entry points */");
//! assert!(source.contains("fn envmap_latlong_forward("));
//! assert!(shaders::LATLONG_GLSL.contains("EnvmapChartUv envmap_latlong_forward("));
//! ```
//!
//! How to include them in wgpu, Bevy, three.js, Unity and Unreal, and the
//! conventions that differ per engine: `docs/shaders.md`.

macro_rules! wgsl_files {
    ($(($name:ident, $file:literal, $doc:literal)),* $(,)?) => {
        $(
            #[doc = $doc]
            #[doc = ""]
            #[doc = concat!("The text of `envmap-core/shaders/", $file, "`.")]
            pub const $name: &str = include_str!(concat!("../shaders/", $file));
        )*
        /// Every WGSL file as `(file name, text)`, in the order in which they
        /// can be concatenated (each needs only the ones before it).
        pub const WGSL_FILES: [(&str, &str); 12] = [$(($file, $name)),*];
        /// Every WGSL file concatenated in the order of [`WGSL_FILES`]: one
        /// self-contained module with every mapping and the lighting lookups.
        pub const ALL_WGSL: &str = concat!($(include_str!(concat!("../shaders/", $file))),*);
    };
}

wgsl_files!(
    (
        COMMON_WGSL,
        "common.wgsl",
        "What every other file needs: `EnvmapChartUv`, `EnvmapDirection`, `ENVMAP_INVALID_CHART`, the direction's normalisation, the unit square and disk tests, `envmap_atan2f`."
    ),
    (
        FRAME_WGSL,
        "frame.wgsl",
        "The frames as constants (`ENVMAP_FRAME_Y_UP_RH`, …) and their application (`envmap_frame_to_canonical`, `envmap_frame_from_canonical`), as [`crate::frame`]."
    ),
    (
        LATLONG_WGSL,
        "latlong.wgsl",
        "`envmap_latlong_forward` and `envmap_latlong_inverse`, as [`crate::LatLong`]."
    ),
    (
        CUBE_WGSL,
        "cube.wgsl",
        "`envmap_cube_forward`, `envmap_cube_inverse`, `envmap_cube_select_face` and `envmap_cube_face_direction`, as [`crate::cube`]."
    ),
    (
        EAC_WGSL,
        "eac.wgsl",
        "`envmap_eac_forward` and `envmap_eac_inverse`, as [`crate::Eac`] (through `envmap_cube_select_face` and `envmap_cube_face_direction`: it needs [`CUBE_WGSL`])."
    ),
    (
        SPHERE_MAP_WGSL,
        "sphere_map.wgsl",
        "`envmap_sphere_map_forward`/`_inverse` (the class convention), `envmap_sphere_map_gl_forward`/`_inverse` (`GL_SPHERE_MAP`) and `envmap_sphere_map_uv_from_normal`, as [`crate::sphere_map`]."
    ),
    (
        DUAL_PARABOLOID_WGSL,
        "dual_paraboloid.wgsl",
        "`envmap_dual_paraboloid_forward` and `_inverse`, as [`crate::DualParaboloid`]."
    ),
    (
        ANGULAR_WGSL,
        "angular.wgsl",
        "`envmap_angular_forward` and `_inverse`, as [`crate::Angular`]."
    ),
    (
        TENNISBALL_WGSL,
        "tennisball.wgsl",
        "`envmap_tennisball_forward` and `_inverse`, as [`crate::Tennisball`]."
    ),
    (
        OCTAHEDRAL_WGSL,
        "octahedral.wgsl",
        "`envmap_octahedral_forward`/`_inverse` and `envmap_equal_area_octahedral_forward`/`_inverse`, as [`crate::Octahedral`] and [`crate::EqualAreaOctahedral`]."
    ),
    (
        FISHEYE_WGSL,
        "fisheye.wgsl",
        "`envmap_fisheye_forward` and `envmap_fisheye_inverse`, as [`crate::Fisheye`], the lens given by the arguments (half the field of view in radians, [`Fisheye::half_fov`](crate::Fisheye::half_fov); equisolid or equidistant; one lens or two), `envmap_fisheye_covers_sphere` and `envmap_fisheye_sin`."
    ),
    (
        LIGHTING_WGSL,
        "lighting.wgsl",
        "The image-based-lighting lookups for envmap's bake: SH9 irradiance, roughness to mip level per rule, the split sum with the DFG table, the dominant direction, and texture reads of latlong, octahedral and cube maps with each map's edge rule and a mip level from the direction's footprint."
    ),
);

/// The WGSL files each generated module is written from, in order: its
/// name (the generated files' stem) and the files concatenated.
pub const MODULES: [(&str, &[&str]); 12] = [
    ("latlong", &["common.wgsl", "frame.wgsl", "latlong.wgsl"]),
    ("cube", &["common.wgsl", "frame.wgsl", "cube.wgsl"]),
    (
        "eac",
        &["common.wgsl", "frame.wgsl", "cube.wgsl", "eac.wgsl"],
    ),
    (
        "sphere_map",
        &["common.wgsl", "frame.wgsl", "sphere_map.wgsl"],
    ),
    (
        "dual_paraboloid",
        &["common.wgsl", "frame.wgsl", "dual_paraboloid.wgsl"],
    ),
    ("angular", &["common.wgsl", "frame.wgsl", "angular.wgsl"]),
    (
        "tennisball",
        &["common.wgsl", "frame.wgsl", "tennisball.wgsl"],
    ),
    (
        "octahedral",
        &["common.wgsl", "frame.wgsl", "octahedral.wgsl"],
    ),
    ("fisheye", &["common.wgsl", "frame.wgsl", "fisheye.wgsl"]),
    (
        "lighting",
        &[
            "common.wgsl",
            "frame.wgsl",
            "latlong.wgsl",
            "cube.wgsl",
            "octahedral.wgsl",
            "lighting.wgsl",
        ],
    ),
    (
        "envmap",
        &[
            "common.wgsl",
            "frame.wgsl",
            "latlong.wgsl",
            "cube.wgsl",
            "eac.wgsl",
            "sphere_map.wgsl",
            "dual_paraboloid.wgsl",
            "angular.wgsl",
            "tennisball.wgsl",
            "octahedral.wgsl",
            "fisheye.wgsl",
            "lighting.wgsl",
        ],
    ),
    ("common", &["common.wgsl", "frame.wgsl"]),
];

macro_rules! generated {
    ($(($glsl:ident, $es:ident, $hlsl:ident, $file:literal, $what:literal)),* $(,)?) => {
        $(
            #[doc = concat!("GLSL 4.50 of ", $what, ", written by naga from the WGSL (`envmap-core/shaders/generated/glsl450/", $file, ".glsl`).")]
            pub const $glsl: &str = include_str!(concat!("../shaders/generated/glsl450/", $file, ".glsl"));
            #[doc = concat!("GLSL ES 3.00 of ", $what, ", written by naga from the WGSL (`envmap-core/shaders/generated/glsl300es/", $file, ".glsl`).")]
            pub const $es: &str = include_str!(concat!("../shaders/generated/glsl300es/", $file, ".glsl"));
            #[doc = concat!("HLSL (shader model 5.0) of ", $what, ", written by naga from the WGSL (`envmap-core/shaders/generated/hlsl/", $file, ".hlsl`).")]
            pub const $hlsl: &str = include_str!(concat!("../shaders/generated/hlsl/", $file, ".hlsl"));
        )*
        /// Every generated module as `(name, GLSL 4.50, GLSL ES 3.00, HLSL)`.
        pub const GENERATED: [(&str, &str, &str, &str); 12] = [$(($file, $glsl, $es, $hlsl)),*];
    };
}

generated!(
    (
        LATLONG_GLSL,
        LATLONG_GLSL_ES,
        LATLONG_HLSL,
        "latlong",
        "the latlong mapping (with the common functions and the frames)"
    ),
    (
        CUBE_GLSL,
        CUBE_GLSL_ES,
        CUBE_HLSL,
        "cube",
        "the cube mapping (with the common functions and the frames)"
    ),
    (
        EAC_GLSL,
        EAC_GLSL_ES,
        EAC_HLSL,
        "eac",
        "the equi-angular cube map (with the common functions, the frames and the cube it builds on)"
    ),
    (
        SPHERE_MAP_GLSL,
        SPHERE_MAP_GLSL_ES,
        SPHERE_MAP_HLSL,
        "sphere_map",
        "the sphere maps (with the common functions and the frames)"
    ),
    (
        DUAL_PARABOLOID_GLSL,
        DUAL_PARABOLOID_GLSL_ES,
        DUAL_PARABOLOID_HLSL,
        "dual_paraboloid",
        "the dual paraboloid (with the common functions and the frames)"
    ),
    (
        ANGULAR_GLSL,
        ANGULAR_GLSL_ES,
        ANGULAR_HLSL,
        "angular",
        "the angular map (with the common functions and the frames)"
    ),
    (
        TENNISBALL_GLSL,
        TENNISBALL_GLSL_ES,
        TENNISBALL_HLSL,
        "tennisball",
        "the tennisball map (with the common functions and the frames)"
    ),
    (
        OCTAHEDRAL_GLSL,
        OCTAHEDRAL_GLSL_ES,
        OCTAHEDRAL_HLSL,
        "octahedral",
        "both octahedral maps (with the common functions and the frames)"
    ),
    (
        FISHEYE_GLSL,
        FISHEYE_GLSL_ES,
        FISHEYE_HLSL,
        "fisheye",
        "the fisheye lenses (with the common functions and the frames)"
    ),
    (
        LIGHTING_GLSL,
        LIGHTING_GLSL_ES,
        LIGHTING_HLSL,
        "lighting",
        "the lighting lookups (with the common functions, the frames, and the latlong, cube and octahedral maps they read)"
    ),
    (
        ALL_GLSL,
        ALL_GLSL_ES,
        ALL_HLSL,
        "envmap",
        "every file: all mappings and the lighting lookups"
    ),
    (
        COMMON_GLSL,
        COMMON_GLSL_ES,
        COMMON_HLSL,
        "common",
        "the common functions and the frames alone"
    ),
);
