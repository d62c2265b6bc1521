// envmap shaders: the cube map with the OpenGL / Vulkan face table.
// The WGSL of envmap-core/src/cube.rs, branch for branch. Needs common.wgsl.
//
// Seed 000 ("Cubic texture environment map"): the largest |component| picks
// the face, and R is scaled by 1 / max(|rx|, |ry|, |rz|) onto the cube. The
// faces are OpenGL 4.6's (section 8.13 "Cube Map Texture Selection", table
// 8.19), so the maps load into GL, Vulkan, Direct3D and wgpu unchanged:
//
//   | major axis | face | sc | tc | ma |
//   | +x         | 0    | -z | -y | x  |
//   | -x         | 1    | +z | -y | x  |
//   | +y         | 2    | +x | +z | y  |
//   | -y         | 3    | +x | -z | y  |
//   | +z         | 4    | +x | -y | z  |
//   | -z         | 5    | -x | -y | z  |
//
//   s = (sc / |ma| + 1) / 2,   t = (tc / |ma| + 1) / 2      (u = s, v = t)
//   inverse: (sc, tc) = (2s - 1, 2t - 1), R = normalize(the table solved with |ma| = 1)
//
// Ties (cube edges and corners): z over y over x, as the Vulkan
// specification recommends (section 16.5.4) and GL implementations do:
//   if |z| >= |x| and |z| >= |y|: z major; else if |y| >= |x|: y major; else x major
// The major component's sign bit picks the face, so signed zeros count.
// (Engines' own shaders differ here: Bevy's filter breaks ties X >= Y >= Z.)
// s and t are computed exactly as written, without normalising R.
// Area element: d omega = dsc dtc / (1 + sc^2 + tc^2)^(3/2).

/// select_face's result: the face (ENVMAP_INVALID_CHART for a NaN,
/// infinite or zero direction), sc, tc and |ma| by the table.
struct EnvmapCubeFace {
    face: u32,
    sc: f32,
    tc: f32,
    ma: f32,
}

/// cube.rs select_face: the face by the GL table and the z-over-y-over-x
/// tie rule, with (sc, tc, |ma|).
fn envmap_cube_select_face(d: vec3<f32>) -> EnvmapCubeFace {
    if !envmap_all_finite(d) {
        return EnvmapCubeFace(ENVMAP_INVALID_CHART, 0.0, 0.0, 0.0);
    }
    let ax = abs(d.x);
    let ay = abs(d.y);
    let az = abs(d.z);
    var r: EnvmapCubeFace;
    if az >= ax && az >= ay {
        if envmap_sign_bit(d.z) {
            r = EnvmapCubeFace(5u, -d.x, -d.y, az);
        } else {
            r = EnvmapCubeFace(4u, d.x, -d.y, az);
        }
    } else if ay >= ax {
        if envmap_sign_bit(d.y) {
            r = EnvmapCubeFace(3u, d.x, -d.z, ay);
        } else {
            r = EnvmapCubeFace(2u, d.x, d.z, ay);
        }
    } else if envmap_sign_bit(d.x) {
        r = EnvmapCubeFace(1u, d.z, -d.y, ax);
    } else {
        r = EnvmapCubeFace(0u, -d.z, -d.y, ax);
    }
    if r.ma == 0.0 {
        return EnvmapCubeFace(ENVMAP_INVALID_CHART, 0.0, 0.0, 0.0);
    }
    return r;
}

/// cube.rs face_direction: the (unnormalised) direction through face
/// coordinates (sc, tc) of `face` with |ma| = 1; coordinates outside
/// [-1, 1] give points beyond the face's edges on its plane. A face above
/// 5 gives (0, 0, 0).
fn envmap_cube_face_direction(face: u32, sc: f32, tc: f32) -> vec3<f32> {
    switch face {
        case 0u: { return vec3<f32>(1.0, -tc, -sc); }
        case 1u: { return vec3<f32>(-1.0, -tc, sc); }
        case 2u: { return vec3<f32>(sc, 1.0, tc); }
        case 3u: { return vec3<f32>(sc, -1.0, -tc); }
        case 4u: { return vec3<f32>(sc, -tc, 1.0); }
        case 5u: { return vec3<f32>(-sc, -tc, -1.0); }
        default: { return vec3<f32>(0.0, 0.0, 0.0); }
    }
}

/// Cube::forward: the face as the chart and (s, t) as (u, v).
fn envmap_cube_forward(dir: vec3<f32>) -> EnvmapChartUv {
    let f = envmap_cube_select_face(dir);
    if f.face == ENVMAP_INVALID_CHART {
        return envmap_invalid_chart_uv();
    }
    let s = 0.5 * (f.sc / f.ma + 1.0);
    let t = 0.5 * (f.tc / f.ma + 1.0);
    return EnvmapChartUv(f.face, vec2<f32>(s, t));
}

/// Cube::inverse: invalid for a face above 5, NaN or (s, t) outside [0, 1]^2.
fn envmap_cube_inverse(c: EnvmapChartUv) -> EnvmapDirection {
    if c.chart > 5u || !envmap_in_unit_square(c.uv) {
        return envmap_invalid_direction();
    }
    let d = envmap_cube_face_direction(c.chart, 2.0 * c.uv.x - 1.0, 2.0 * c.uv.y - 1.0);
    return EnvmapDirection(d / sqrt(dot(d, d)), true);
}
