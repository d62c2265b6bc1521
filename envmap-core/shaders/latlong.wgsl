// envmap shaders: latitude-longitude (polar spherical, Blinn & Newell 1976).
// The WGSL of envmap-core/src/latlong.rs, branch for branch. Needs common.wgsl.
//
// Seed 000 ("Polar spherical texture environment map") prints
//   (u, v) = (atan(y / x) / 2 pi, acos(z) / pi)
// Erratum: atan(y / x) loses the quadrant; envmap uses atan2(y, x) wrapped
// into [0, 1), and the polar angle atan2(sqrt(x^2 + y^2), z), which keeps
// its accuracy next to the poles where acos(z) does not:
//
//   phi = atan2(y, x) in (-pi, pi],   u = phi / 2 pi, plus 1 if negative   in [0, 1)
//   theta = atan2(sqrt(x^2 + y^2), z) in [0, pi],   v = theta / pi        in [0, 1]
//   inverse: (x, y, z) = (sin theta cos phi, sin theta sin phi, cos theta), phi = 2 pi u, theta = pi v
//
// Axes: z is the pole (v = 0, the top row, is +z; v = 1 is -z); u = 0 is
// +x and u grows towards +y (u = 1/4 is +y). Y-up data: a frame (frame.wgsl).
// Seam: the half plane y = 0, x > 0 (u = 0 and 1); y = -0 is on the u = 0
// side, a tiny negative phi that rounds to u = 1 wraps to 0, so u < 1
// always. Poles (x = y = 0): u = 0 (u = 1/2 for x = -0), v = 0 or 1; any
// u on the top or bottom row inverts to the pole. phi is computed from x
// and y as given, so u keeps its accuracy next to a pole.
// Area element: d omega = 2 pi^2 sin(pi v) du dv.

/// LatLong::forward: the chart point of a direction of any length.
fn envmap_latlong_forward(dir: vec3<f32>) -> EnvmapChartUv {
    let n = envmap_normalize_direction(dir);
    if !n.valid {
        return envmap_invalid_chart_uv();
    }
    let d = n.dir;
    // phi from the components as given (atan2 is scale-invariant).
    let phi = envmap_atan2f(dir.y, dir.x);
    var u = phi / ENVMAP_TAU;
    if u < 0.0 {
        u += 1.0;
        // A tiny negative phi rounds up to exactly 1: wrap it to the seam.
        if u >= 1.0 {
            u = 0.0;
        }
    }
    // u is in [0, 1): abs turns a -0 (from y = -0) into +0, as the CPU's
    // `+ 0.0` does, whatever the compiler does with signed zeros.
    u = abs(u);
    let rho = sqrt(d.x * d.x + d.y * d.y);
    let theta = envmap_atan2f(rho, d.z);
    let v = envmap_clamp_unit(theta / ENVMAP_PI);
    return EnvmapChartUv(0u, vec2<f32>(u, v));
}

/// LatLong::inverse: the unit direction of (chart 0, u, v); invalid outside
/// [0, 1]^2, for NaN or another chart.
fn envmap_latlong_inverse(c: EnvmapChartUv) -> EnvmapDirection {
    if c.chart != 0u || !envmap_in_unit_square(c.uv) {
        return envmap_invalid_direction();
    }
    // phi = 2 pi u, taken into [-pi, pi] (where WGSL bounds sin and cos) as
    // 2 pi (u - 1) for u > 1/2 (u - 1 is exact there).
    var phi = ENVMAP_TAU * c.uv.x;
    if c.uv.x > 0.5 {
        phi = ENVMAP_TAU * (c.uv.x - 1.0);
    }
    let theta = ENVMAP_PI * c.uv.y;
    let st = sin(theta);
    return EnvmapDirection(vec3<f32>(st * cos(phi), st * sin(phi), cos(theta)), true);
}
