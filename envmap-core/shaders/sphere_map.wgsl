// envmap shaders: the sphere map (a mirror ball's image), in the class and
// OpenGL conventions. The WGSL of envmap-core/src/sphere_map.rs, branch for
// branch. Needs common.wgsl.
//
// Seed 000 ("Spherical texture environment map"): the ball normal that
// reflects the view into R is half-way between R and the vector V towards
// the viewer; the map is its projection along the view axis:
//
//   class (eye along +z, V = (0, 0, -1), sigma = -1):  (u', v') = (rx, ry) / sqrt(rx^2 + ry^2 + (rz - 1)^2)
//   OpenGL GL_SPHERE_MAP (eye along -z, V = (0, 0, +1), sigma = +1): (rz + 1) instead
//   both: (u, v) = (u'/2 + 1/2, v'/2 + 1/2)
//   inverse, r^2 = u'^2 + v'^2 <= 1: R = (2u' sqrt(1 - r^2), 2v' sqrt(1 - r^2), sigma (1 - 2r^2))
//   short cut from the ball's normal: (u', v') = (nx, ny)
//
// The singular direction -V (class: +z; OpenGL: -z) maps to the rim point
// (1, 1/2); every rim point inverts to it; the centre is V. rz + sigma is
// computed as sigma (1 + w), w = sigma rz, and 1 + w = (rx^2 + ry^2) / (1 - w)
// when w < 0, so nothing cancels next to the singular direction. The
// corners outside the disk hold no direction. Area: d omega = 4 du' dv'.

/// SphereMap::forward with sigma = -1 (the class convention) or +1
/// (OpenGL's): see the file's header.
fn envmap_sphere_map_forward_sigma(dir: vec3<f32>, sigma: f32) -> EnvmapChartUv {
    let n = envmap_normalize_direction(dir);
    if !n.valid {
        return envmap_invalid_chart_uv();
    }
    let r = n.dir;
    let w = sigma * r.z;
    var one_plus_w: f32;
    if w < 0.0 {
        one_plus_w = (r.x * r.x + r.y * r.y) / (1.0 - w);
    } else {
        one_plus_w = 1.0 + w;
    }
    // Scale before squaring: rx, ry may be tiny.
    let s = max(max(abs(r.x), abs(r.y)), one_plus_w);
    if s == 0.0 {
        return EnvmapChartUv(0u, vec2<f32>(1.0, 0.5));
    }
    let x = r.x / s;
    let y = r.y / s;
    let h = one_plus_w / s;
    let m = sqrt(x * x + y * y + h * h);
    let u = envmap_clamp_unit(0.5 * (x / m) + 0.5);
    let v = envmap_clamp_unit(0.5 * (y / m) + 0.5);
    return EnvmapChartUv(0u, vec2<f32>(u, v));
}

/// SphereMap::inverse with sigma = -1 (class) or +1 (OpenGL); invalid
/// outside the disk, for NaN or a chart other than 0.
fn envmap_sphere_map_inverse_sigma(c: EnvmapChartUv, sigma: f32) -> EnvmapDirection {
    if c.chart != 0u || !envmap_in_unit_disk(c.uv) {
        return envmap_invalid_direction();
    }
    let x = 2.0 * c.uv.x - 1.0;
    let y = 2.0 * c.uv.y - 1.0;
    let r2 = x * x + y * y;
    let nz = sqrt(max(1.0 - r2, 0.0));
    let d = vec3<f32>(2.0 * x * nz, 2.0 * y * nz, sigma * (1.0 - 2.0 * r2));
    return EnvmapDirection(d / sqrt(dot(d, d)), true);
}

/// SphereMap::CLASS.forward: the eye looks along +z; +z is singular.
fn envmap_sphere_map_forward(dir: vec3<f32>) -> EnvmapChartUv {
    return envmap_sphere_map_forward_sigma(dir, -1.0);
}

/// SphereMap::CLASS.inverse.
fn envmap_sphere_map_inverse(c: EnvmapChartUv) -> EnvmapDirection {
    return envmap_sphere_map_inverse_sigma(c, -1.0);
}

/// SphereMap::OPENGL.forward (GL_SPHERE_MAP): the eye looks along -z; -z is singular.
fn envmap_sphere_map_gl_forward(dir: vec3<f32>) -> EnvmapChartUv {
    return envmap_sphere_map_forward_sigma(dir, 1.0);
}

/// SphereMap::OPENGL.inverse.
fn envmap_sphere_map_gl_inverse(c: EnvmapChartUv) -> EnvmapDirection {
    return envmap_sphere_map_inverse_sigma(c, 1.0);
}

/// sphere_map.rs uv_from_normal, the seed's short cut: (u, v) = (nx, ny)/2 + 1/2
/// from the mirror ball's normal n (any length); invalid for NaN, infinite or zero n.
fn envmap_sphere_map_uv_from_normal(n: vec3<f32>) -> EnvmapChartUv {
    let u = envmap_normalize_direction(n);
    if !u.valid {
        return envmap_invalid_chart_uv();
    }
    return EnvmapChartUv(0u, vec2<f32>(envmap_clamp_unit(0.5 * u.dir.x + 0.5), envmap_clamp_unit(0.5 * u.dir.y + 0.5)));
}
