// envmap shaders: the octahedral maps, plain (Engelhardt & Dachsbacher 2008)
// and equal-area (Clarberg 2008, as pbrt-v4). The WGSL of
// envmap-core/src/octahedral.rs, branch for branch. Needs common.wgsl.
//
// Both unfold the sphere onto [-1, 1]^2 (u' = 2u - 1, v' = 2v - 1): the upper
// hemisphere (z >= 0) is the diamond |u'| + |v'| <= 1 around +z at the
// centre, the lower one the four corner triangles, -z the corners.
//
// Octahedral (Engelhardt & Dachsbacher, "Octahedron Environment Maps", VMV 2008):
//   p = R / (|rx| + |ry| + |rz|)
//   (u', v') = (px, py)                                      if rz >= 0
//   (u', v') = ((1 - |py|) sgn px, (1 - |px|) sgn py)        if rz < 0 (the fold)
//   inverse: z = 1 - |u'| - |v'|; (x, y) = (u', v') if z >= 0,
//            else ((1 - |v'|) sgn u', (1 - |u'|) sgn v'); R = normalize(x, y, z)
// sgn is the sign bit (copysign), so signed zeros count: on the lower
// hemisphere's folds x = +-0 and y = +-0 go to the two images of the same
// direction on the square's edge. (Engines' encoders disagree here: Bevy's
// WGSL sends 0 to -1 where its Rust sends it to +1.) The sign bits are read
// from the direction as given, which has the signs of p.
//
// Equal-area (Clarberg, "Fast Equal-Area Mapping of the (Hemi)Sphere using
// SIMD", JGT 2008; pbrt-v4 EqualAreaSphereToSquare):
//   r = sqrt(1 - |rz|), as sqrt((rx^2 + ry^2) / (1 + |rz|))
//   phi = (2/pi) atan(min(|rx|, |ry|) / max(|rx|, |ry|)), then 1 - phi if |rx| < |ry|
//   v' = phi r, u' = r - v';  if rz < 0: (u', v') = (1 - v', 1 - u')
//   u' = copysign(u', rx), v' = copysign(v', ry)
//   inverse: d = 1 - |u'| - |v'|, r = 1 - |d|, phi = ((|v'| - |u'|) / r + 1) pi/4,
//            z = copysign(1 - r^2, d), (x, y) = (copysign(cos phi, u'), copysign(sin phi, v')) r sqrt(2 - r^2)
//
// Seams: the square's outer edges ((u', +-1) and (-u', +-1) are one
// direction, as are (+-1, v') and (+-1, -v')); the corners are all -z.

/// The chart point of (u', v') in [-1, 1]^2.
fn envmap_octahedral_to_uv(x: f32, y: f32) -> EnvmapChartUv {
    return EnvmapChartUv(0u, vec2<f32>(envmap_clamp_unit(0.5 * x + 0.5), envmap_clamp_unit(0.5 * y + 0.5)));
}

/// Octahedral::forward.
fn envmap_octahedral_forward(dir: vec3<f32>) -> EnvmapChartUv {
    let n = envmap_normalize_direction(dir);
    if !n.valid {
        return envmap_invalid_chart_uv();
    }
    let d = n.dir;
    let p = d / (abs(d.x) + abs(d.y) + abs(d.z));
    if p.z < 0.0 {
        return envmap_octahedral_to_uv(
            envmap_copysign(1.0 - abs(p.y), dir.x),
            envmap_copysign(1.0 - abs(p.x), dir.y),
        );
    }
    return envmap_octahedral_to_uv(p.x, p.y);
}

/// Octahedral::inverse; invalid outside [0, 1]^2, for NaN or a chart other than 0.
fn envmap_octahedral_inverse(c: EnvmapChartUv) -> EnvmapDirection {
    if c.chart != 0u || !envmap_in_unit_square(c.uv) {
        return envmap_invalid_direction();
    }
    let x = 2.0 * c.uv.x - 1.0;
    let y = 2.0 * c.uv.y - 1.0;
    let z = 1.0 - abs(x) - abs(y);
    var d = vec3<f32>(x, y, z);
    if z < 0.0 {
        d = vec3<f32>(envmap_copysign(1.0 - abs(y), x), envmap_copysign(1.0 - abs(x), y), z);
    }
    return EnvmapDirection(d / sqrt(dot(d, d)), true);
}

/// EqualAreaOctahedral::forward.
fn envmap_equal_area_octahedral_forward(dir: vec3<f32>) -> EnvmapChartUv {
    let n = envmap_normalize_direction(dir);
    if !n.valid {
        return envmap_invalid_chart_uv();
    }
    let d = n.dir;
    let ax = abs(d.x);
    let ay = abs(d.y);
    let az = abs(d.z);
    let r = sqrt((ax * ax + ay * ay) / (1.0 + az));
    let hi = max(ax, ay);
    let lo = min(ax, ay);
    var phi = 0.0;
    if hi != 0.0 {
        phi = envmap_atan_unit(lo / hi) * ENVMAP_TWO_OVER_PI;
    }
    if ax < ay {
        phi = 1.0 - phi;
    }
    var v = phi * r;
    var u = r - v;
    if d.z < 0.0 {
        let u0 = u;
        u = 1.0 - v;
        v = 1.0 - u0;
    }
    return envmap_octahedral_to_uv(envmap_copysign(u, dir.x), envmap_copysign(v, dir.y));
}

/// EqualAreaOctahedral::inverse; invalid outside [0, 1]^2, for NaN or a chart other than 0.
fn envmap_equal_area_octahedral_inverse(c: EnvmapChartUv) -> EnvmapDirection {
    if c.chart != 0u || !envmap_in_unit_square(c.uv) {
        return envmap_invalid_direction();
    }
    let u = 2.0 * c.uv.x - 1.0;
    let v = 2.0 * c.uv.y - 1.0;
    let au = abs(u);
    let av = abs(v);
    let sum = au + av;
    let signed_distance = 1.0 - sum;
    // r = 1 - |1 - sum|, written to keep full precision next to both poles.
    var r = sum;
    if signed_distance < 0.0 {
        r = 2.0 - sum;
    }
    var phi = ENVMAP_QUARTER_PI;
    if r != 0.0 {
        phi = ((av - au) / r + 1.0) * ENVMAP_QUARTER_PI;
    }
    let z = envmap_copysign(1.0 - r * r, signed_distance);
    let k = r * sqrt(max(2.0 - r * r, 0.0));
    let d = vec3<f32>(envmap_copysign(cos(phi), u) * k, envmap_copysign(sin(phi), v) * k, z);
    return EnvmapDirection(d / sqrt(dot(d, d)), true);
}
