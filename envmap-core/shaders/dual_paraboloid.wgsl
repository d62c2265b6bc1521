// envmap shaders: the dual paraboloid map (Heidrich & Seidel 1998), two disks.
// The WGSL of envmap-core/src/dual_paraboloid.rs, branch for branch. Needs common.wgsl.
//
// Seed 000 ("Paraboloid Mapping") prints (u', v') = (rx, ry) / (rz +- 1).
// envmap's sign convention makes the two rims meet at the same (u, v)
// (the back disk is the front one's mirror image through z = 0; the seed's
// back disk as printed is a half turn of it):
//
//   chart 0 (front, rz >= 0, sign bit clear): (u', v') = (rx, ry) / (1 + rz)
//   chart 1 (back,  rz <= 0, sign bit set):   (u', v') = (rx, ry) / (1 - rz)
//   (u, v) = (u'/2 + 1/2, v'/2 + 1/2)
//   inverse, r^2 = u'^2 + v'^2 <= 1: R = (2u', 2v', +-(1 - r^2)) / (1 + r^2)
//
// The seam is the equator (the two rims): z = +0 goes to the front, z = -0
// to the back, with the same (u, v). The corners hold no direction.
// Area element: d omega = 4 du' dv' / (1 + r^2)^2.

/// DualParaboloid::forward; the chart is the sign bit of z.
fn envmap_dual_paraboloid_forward(dir: vec3<f32>) -> EnvmapChartUv {
    let n = envmap_normalize_direction(dir);
    if !n.valid {
        return envmap_invalid_chart_uv();
    }
    let r = n.dir;
    // The sign bit of the normalised z is that of the z given (a division
    // by a positive number); read from the input, it survives any
    // treatment of signed zeros in the arithmetic.
    let back = envmap_sign_bit(dir.z);
    let den = 1.0 + abs(r.z);
    let u = envmap_clamp_unit(0.5 * (r.x / den) + 0.5);
    let v = envmap_clamp_unit(0.5 * (r.y / den) + 0.5);
    return EnvmapChartUv(select(0u, 1u, back), vec2<f32>(u, v));
}

/// DualParaboloid::inverse; invalid outside the disk, for NaN or a chart above 1.
fn envmap_dual_paraboloid_inverse(c: EnvmapChartUv) -> EnvmapDirection {
    if c.chart > 1u || !envmap_in_unit_disk(c.uv) {
        return envmap_invalid_direction();
    }
    let x = 2.0 * c.uv.x - 1.0;
    let y = 2.0 * c.uv.y - 1.0;
    let r2 = x * x + y * y;
    var z = max(1.0 - r2, 0.0);
    if c.chart == 1u {
        z = -z;
    }
    let d = vec3<f32>(2.0 * x, 2.0 * y, z) / (1.0 + r2);
    return EnvmapDirection(d / sqrt(dot(d, d)), true);
}
