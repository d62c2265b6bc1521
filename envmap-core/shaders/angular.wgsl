// envmap shaders: the angular map (Debevec's light probe), a disk whose radius
// is the angle from the view axis. The WGSL of envmap-core/src/angular.rs,
// branch for branch. Needs common.wgsl.
//
// P. Debevec, "Rendering Synthetic Objects into Real Scenes", SIGGRAPH 1998:
// (u', v') = (Dx r, Dy r), r = (1/pi) acos(Dz) / sqrt(Dx^2 + Dy^2), centre +z.
// envmap takes the angle as atan2(sqrt(x^2 + y^2), z), accurate next to +-z:
//
//   theta = atan2(sqrt(x^2 + y^2), z) in [0, pi],   rho = theta / pi in [0, 1]
//   (u', v') = rho (x, y) / sqrt(x^2 + y^2),   (u, v) = (u'/2 + 1/2, v'/2 + 1/2)
//   inverse: rho = sqrt(u'^2 + v'^2) <= 1, theta = pi rho,
//            R = (sin theta u'/rho, sin theta v'/rho, cos theta)   (sin theta / rho -> pi as rho -> 0)
//
// The centre is +z, u grows along +x, v along +y; z = 0 is the circle of
// radius 1/2. -z is singular: forward sends it (and any direction with
// x = y = +-0) to the azimuth of +x, the rim point (1, 1/2); every rim point
// inverts to -z. The azimuth is taken from x and y as given, divided by the
// larger of |x|, |y|. Next to the rim the inverse evaluates sin and cos at
// pi (1 - rho) (exact for rho >= 1/2). Area: d omega = 4 pi sin(pi rho)/rho du dv.

/// Angular::forward.
fn envmap_angular_forward(dir: vec3<f32>) -> EnvmapChartUv {
    let n = envmap_normalize_direction(dir);
    if !n.valid {
        return envmap_invalid_chart_uv();
    }
    let r = n.dir;
    // The azimuth from x and y as given, scaled by the larger magnitude;
    // x = y = +-0 takes the azimuth of +x.
    let a = max(abs(dir.x), abs(dir.y));
    var px = 1.0;
    var py = 0.0;
    if a != 0.0 {
        px = dir.x / a;
        py = dir.y / a;
    }
    // 1 <= len <= sqrt(2).
    let len = sqrt(px * px + py * py);
    let sin_theta = max(abs(r.x), abs(r.y)) * len;
    let theta = envmap_atan2f(sin_theta, r.z);
    let rho = min(theta / ENVMAP_PI, 1.0);
    let k = rho / len;
    let u = envmap_clamp_unit(0.5 * (k * px) + 0.5);
    let v = envmap_clamp_unit(0.5 * (k * py) + 0.5);
    return EnvmapChartUv(0u, vec2<f32>(u, v));
}

/// Angular::inverse; invalid outside the disk, for NaN or a chart other than 0.
fn envmap_angular_inverse(c: EnvmapChartUv) -> EnvmapDirection {
    if c.chart != 0u || !envmap_in_unit_disk(c.uv) {
        return envmap_invalid_direction();
    }
    let x = 2.0 * c.uv.x - 1.0;
    let y = 2.0 * c.uv.y - 1.0;
    let rho = min(sqrt(x * x + y * y), 1.0);
    var s: f32;
    var co: f32;
    if rho <= 0.5 {
        s = sin(ENVMAP_PI * rho);
        co = cos(ENVMAP_PI * rho);
    } else {
        let t = ENVMAP_PI * (1.0 - rho);
        s = sin(t);
        co = -cos(t);
    }
    var k = ENVMAP_PI;
    if rho > 0.0 {
        k = s / rho;
    }
    let d = vec3<f32>(k * x, k * y, co);
    return EnvmapDirection(d / sqrt(dot(d, d)), true);
}
