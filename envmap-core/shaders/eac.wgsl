// envmap shaders: the equi-angular cube map (EAC), the cube's six faces,
// each storing angle instead of tangent. The WGSL of envmap-core/src/eac.rs,
// branch for branch. Needs common.wgsl and cube.wgsl.
//
// C. Brown, "Bringing pixels front and center in VR video" (Google, 2017),
// as ffmpeg's v360 filter computes it (xyz_to_eac / eac_to_xyz in
// libavfilter/vf_v360.c). The face is picked and its coordinates (sc, tc)
// are taken exactly as for the cube (envmap_cube_select_face: the GL /
// Vulkan face table and its z-over-y-over-x tie rule); then each axis
// stores the angle from the face's centre, atan(c) in [-pi/4, pi/4],
// scaled to [0, 1]:
//
//   u = 1/2 + (2/pi) atan(sc / |ma|),   v = 1/2 + (2/pi) atan(tc / |ma|)
//   inverse: (sc, tc) = (tan(pi/4 (2u - 1)), tan(pi/4 (2v - 1))), R = normalize(face table)
//
// u and v are clamped to [0, 1] (f32's atan(1) times 2/pi can round past
// 1/4). The charts are the cube's faces in GL order with the cube's
// orientation, so every cube layout holds an EAC map the same way.
// Area element: d omega = (pi/2)^2 (1 + sc^2)(1 + tc^2) / (1 + sc^2 + tc^2)^(3/2) du dv.
//
// atan: |sc / |ma|| <= 1, so the forward is common.wgsl's envmap_atan_unit
// (not WGSL's atan, held only to 4096 ULP) with the argument's sign. tan:
// WGSL's, whose accuracy is inherited from sin(x) / cos(x), with x in
// [-pi/4, pi/4] where sin and cos are bounded (docs/shaders.md).

/// eac.rs's atan of c = sc / |ma| in [-1, 1] (a division may round just
/// past 1, still within envmap_atan_unit's reach): atan(|c|) with c's sign.
fn envmap_eac_atan(c: f32) -> f32 {
    return envmap_copysign(envmap_atan_unit(abs(c)), c);
}

/// eac.rs's angle: pi/4 (2u - 1), the angle from the face's centre.
fn envmap_eac_angle(u: f32) -> f32 {
    return ENVMAP_QUARTER_PI * (2.0 * u - 1.0);
}

/// Eac::forward: the face as the chart and the angles along its axes as (u, v).
fn envmap_eac_forward(dir: vec3<f32>) -> EnvmapChartUv {
    let f = envmap_cube_select_face(dir);
    if f.face == ENVMAP_INVALID_CHART {
        return envmap_invalid_chart_uv();
    }
    let u = envmap_clamp_unit(0.5 + ENVMAP_TWO_OVER_PI * envmap_eac_atan(f.sc / f.ma));
    let v = envmap_clamp_unit(0.5 + ENVMAP_TWO_OVER_PI * envmap_eac_atan(f.tc / f.ma));
    return EnvmapChartUv(f.face, vec2<f32>(u, v));
}

/// Eac::inverse: invalid for a face above 5, NaN or (u, v) outside [0, 1]^2.
fn envmap_eac_inverse(c: EnvmapChartUv) -> EnvmapDirection {
    if c.chart > 5u || !envmap_in_unit_square(c.uv) {
        return envmap_invalid_direction();
    }
    let d = envmap_cube_face_direction(
        c.chart,
        tan(envmap_eac_angle(c.uv.x)),
        tan(envmap_eac_angle(c.uv.y)),
    );
    return EnvmapDirection(d / sqrt(dot(d, d)), true);
}
