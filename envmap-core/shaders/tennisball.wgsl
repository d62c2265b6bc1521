// envmap shaders: the tennisball map, two latitude-longitude strips that
// cover each other's poles and seams. The WGSL of
// envmap-core/src/tennisball.rs, branch for branch. Needs common.wgsl.
//
// Seed 000 ("Tennisball map") prints, for R = (a, b, c):
//   C1: (theta, phi) = (asin b, atan2(a, -c));  C2: (theta, phi) = (asin a, atan2(b, -c))
//   C1 when (c >= 0 and |b| <= sqrt(2)/2) or (c <= 0 and |a| >= sqrt(2)/2), else C2
//   ranges: -pi/4 <= theta <= pi/4, -3pi/4 <= phi <= 3pi/4
// Erratum: as printed both charts leave out the same wedge around +z. envmap
// measures C1's longitude from +z, atan2(a, c); chart 2 and the selection
// are as printed, and every direction then lands inside the ranges:
//
//   chart 0: (theta, phi) = (asin b, atan2(a, c));  chart 1: (asin a, atan2(b, -c))
//   u = (phi + 3pi/4) / (3pi/2),  v = (pi/4 - theta) / (pi/2)
//   inverse chart 0: (a, b, c) = (cos theta sin phi, sin theta, cos theta cos phi)
//   inverse chart 1: (a, b, c) = (sin theta, cos theta sin phi, -cos theta cos phi)
//
// theta = asin b is computed as atan2(b, sqrt(a^2 + c^2)), the same angle
// for a unit vector: WGSL bounds its asin only through the atan2 form
// (Mesa's lavapipe measured 3.9e-4 rad). theta and phi are clamped to the
// ranges (they leave them by a rounding at most). Each chart is a 3:1 strip,
// phi across and theta down; stacked, chart 0 on top. Area: cos theta d theta d phi.

/// tennisball.rs selects_chart_0: the seed's selection rule for the unit vector (a, b, c).
fn envmap_tennisball_selects_first_chart(a: f32, b: f32, c: f32) -> bool {
    return (c >= 0.0 && abs(b) <= ENVMAP_SQRT_HALF) || (c <= 0.0 && abs(a) >= ENVMAP_SQRT_HALF);
}

/// Tennisball::forward.
fn envmap_tennisball_forward(dir: vec3<f32>) -> EnvmapChartUv {
    let n = envmap_normalize_direction(dir);
    if !n.valid {
        return envmap_invalid_chart_uv();
    }
    let a = n.dir.x;
    let b = n.dir.y;
    let c = n.dir.z;
    var chart: u32;
    var theta: f32;
    var phi: f32;
    if envmap_tennisball_selects_first_chart(a, b, c) {
        chart = 0u;
        theta = envmap_atan2f(b, sqrt(a * a + c * c));
        phi = envmap_atan2f(a, c);
    } else {
        chart = 1u;
        theta = envmap_atan2f(a, sqrt(b * b + c * c));
        phi = envmap_atan2f(b, -c);
    }
    // 3 pi/4 and 3 pi/2 as the CPU rounds them to f32.
    let phi_max = 2.35619449615478515625;
    let phi_span = 4.7123889923095703125;
    theta = clamp(theta, -ENVMAP_QUARTER_PI, ENVMAP_QUARTER_PI);
    phi = clamp(phi, -phi_max, phi_max);
    let u = envmap_clamp_unit(phi / phi_span + 0.5);
    let v = envmap_clamp_unit(0.5 - theta / ENVMAP_HALF_PI);
    return EnvmapChartUv(chart, vec2<f32>(u, v));
}

/// Tennisball::inverse; invalid outside [0, 1]^2, for NaN or a chart above 1.
fn envmap_tennisball_inverse(c: EnvmapChartUv) -> EnvmapDirection {
    if c.chart > 1u || !envmap_in_unit_square(c.uv) {
        return envmap_invalid_direction();
    }
    let phi = (c.uv.x - 0.5) * 4.7123889923095703125;
    let theta = (0.5 - c.uv.y) * ENVMAP_HALF_PI;
    let sp = sin(phi);
    let cp = cos(phi);
    let st = sin(theta);
    let ct = cos(theta);
    if c.chart == 0u {
        return EnvmapDirection(vec3<f32>(ct * sp, st, ct * cp), true);
    }
    return EnvmapDirection(vec3<f32>(st, ct * sp, -ct * cp), true);
}
