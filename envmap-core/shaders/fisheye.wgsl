// envmap shaders: fisheye lenses, equidistant and equisolid, a field of view
// up to 360 degrees, one lens or two back to back (the raw frames of 360
// degree cameras). The WGSL of envmap-core/src/fisheye.rs, branch for
// branch. Needs common.wgsl.
//
// J. Kannala and S. Brandt, "A generic camera model and calibration method
// for conventional, wide-angle, and fish-eye lenses" (IEEE TPAMI 28(8),
// 2006), table 1, scaled so that the image circle is r = 1. theta is the
// angle of a direction from the lens's axis, k = F/2 half the full field of
// view F, r the distance of the image point from the circle's centre:
//
//   equidistant (f theta; ffmpeg v360's fisheye):  r = theta / k
//   equisolid (2f sin(theta/2); equal-area):       r = sin(theta / 2) / sin(k / 2)
//
//   theta = atan2(sqrt(x^2 + y^2), z) in [0, pi]
//   u = 1/2 + 1/2 r x / sqrt(x^2 + y^2),   v = 1/2 - 1/2 r y / sqrt(x^2 + y^2)
//   inverse: (a, b) = (2u - 1, 1 - 2v), r = sqrt(a^2 + b^2) <= 1,
//            theta = k r (equidistant) or 2 asin(r sin(k / 2)) (equisolid),
//            R = (sin theta a / r, sin theta b / r, cos theta)
//
// At F = 360 degrees the equidistant lens is the angular map's law and the
// equisolid lens the mirror ball's, about +z.
//
// Axes: +z is the lens's axis, +x to the right of its image, +y up; the
// image circle is the disk inscribed in the chart. Two lenses (dual) are
// chart 0, looking along +z as above, and chart 1, looking along -z with -x
// to the right of its image (seen from inside, as its camera sees):
// u = 1/2 - 1/2 r x / sqrt(x^2 + y^2). A direction goes to the lens of its
// hemisphere, read from z as given: z < 0 to chart 1, z >= 0 (-0 included)
// to chart 0. On the axis (x = y = +-0) the azimuth is that of +x, which
// matters only for a 360 degree lens looking away (r = 1: a rim point).
// Area element, (x', y') = (2u - 1, 2v - 1), rho' their radius:
// equidistant d omega = k sin(k rho') / rho' dx' dy', equisolid
// 4 sin^2(k/2) dx' dy'.
//
// The lens is given by the arguments: half_fov = k in (0, pi], radians, the
// f32 of Fisheye::half_fov(); equisolid (else equidistant); dual (two
// lenses). Forward of a direction further than k (1 + 4 * 2^-23) from its
// lens's axis (Fisheye::seen_limit) is invalid, as for a NaN or zero
// direction: chart ENVMAP_INVALID_CHART, uv (0, 0). Two lenses of 180
// degrees or more (k >= pi/2) and one of 360 (k = pi) see every direction.
// Inverse is invalid for a chart the fisheye lacks and outside the circle.
//
// Trigonometry: theta is envmap_atan2f's; sin(theta/2) and sin(k/2) are
// envmap_fisheye_sin, envmap-simd's exact-tier polynomials (not WGSL's sin,
// held only to 2^-11), so that a 360 degree equisolid lens's sin(k/2) is 1
// exactly, as on the CPU; asin(q) is atan2(q, sqrt((1 - q)(1 + q))); the
// inverse's sin and cos of theta are the built-ins, on [0, pi].

/// 1 + 4 * 2^-23: the factor of Fisheye::seen_limit, k (1 + 4 eps).
const ENVMAP_FISHEYE_SEEN_SCALE: f32 = 1.000000476837158203125;
/// pi/2 - ENVMAP_HALF_PI, rounded to f32 (0xb33bbd2e): the second part of pi/2.
const ENVMAP_FISHEYE_HALF_PI_LO: f32 = -0.00000004371138828673792886547744274139404296875;

/// sin(x) for x in [0, pi/2] (x a few ulps past pi/2 included): on
/// [0, pi/4] x + x^3 P(x^2), envmap-simd's exact-tier sine (SIN_EXACT), and
/// beyond it cos(pi/2 - x) by its exact-tier cosine 1 - y^2/2 + y^4 Q(y^2)
/// (COS_EXACT), pi/2 - x in two parts (the first difference is exact), and
/// 1 - y^2/2 kept with its rounding error.
fn envmap_fisheye_sin(x: f32) -> f32 {
    if x <= ENVMAP_QUARTER_PI {
        let u = x * x;
        var p = -0.000195182903553359210491180419921875;
        p = p * u + 0.0083321891725063323974609375;
        p = p * u - 0.16666655242443084716796875;
        return x + x * (u * p);
    }
    let y = (ENVMAP_HALF_PI - x) + ENVMAP_FISHEYE_HALF_PI_LO;
    let u = y * y;
    var q = 0.00002443232733639888465404510498046875;
    q = q * u - 0.0013887309469282627105712890625;
    q = q * u + 0.0416666455566883087158203125;
    let half_u = 0.5 * u;
    let w = 1.0 - half_u;
    let rest = (1.0 - w) - half_u;
    return w + ((u * u) * q + rest);
}

/// asin(q) for q in [0, 1], as the angle atan2(q, sqrt(1 - q^2)), with
/// 1 - q^2 as (1 - q)(1 + q) (exact next to 1, where asin is steep).
fn envmap_fisheye_asin(q: f32) -> f32 {
    return envmap_atan2f(q, sqrt((1.0 - q) * (1.0 + q)));
}

/// Fisheye::covers_sphere: two lenses of 180 degrees or more, or one of 360.
fn envmap_fisheye_covers_sphere(half_fov: f32, dual: bool) -> bool {
    if dual {
        return half_fov >= ENVMAP_HALF_PI;
    }
    return half_fov >= ENVMAP_PI;
}

/// Fisheye::forward: the lens (chart) and the image point; invalid for a
/// direction the lenses do not see, NaN, infinite or zero.
fn envmap_fisheye_forward(dir: vec3<f32>, half_fov: f32, equisolid: bool, dual: bool) -> EnvmapChartUv {
    let n = envmap_normalize_direction(dir);
    if !n.valid {
        return envmap_invalid_chart_uv();
    }
    let d = n.dir;
    // The hemisphere from z as given (normalising can flush a tiny z to -0).
    let back = dual && dir.z < 0.0;
    var axial = d.z;
    var side = 1.0;
    if back {
        axial = -d.z;
        side = -1.0;
    }
    let rho = sqrt(d.x * d.x + d.y * d.y);
    let theta = envmap_atan2f(rho, axial);
    if !envmap_fisheye_covers_sphere(half_fov, dual) && theta > half_fov * ENVMAP_FISHEYE_SEEN_SCALE {
        return envmap_invalid_chart_uv();
    }
    var r: f32;
    if equisolid {
        r = envmap_fisheye_sin(0.5 * theta) / envmap_fisheye_sin(0.5 * half_fov);
    } else {
        r = theta / half_fov;
    }
    r = min(r, 1.0);
    // The azimuth from the components as given, divided by the larger of
    // |x|, |y| (the normalised ones can underflow next to the axis); on the
    // axis the azimuth of +x.
    let a = max(abs(dir.x), abs(dir.y));
    var x = 1.0;
    var y = 0.0;
    if a != 0.0 {
        x = dir.x / a;
        y = dir.y / a;
    }
    let s = 0.5 * r / sqrt(x * x + y * y);
    let u = envmap_clamp_unit(0.5 + side * s * x);
    let v = envmap_clamp_unit(0.5 - s * y);
    return EnvmapChartUv(select(0u, 1u, back), vec2<f32>(u, v));
}

/// Fisheye::inverse: invalid for a chart the fisheye lacks (above 0, or
/// above 1 when dual), NaN, or a point outside the image circle.
fn envmap_fisheye_inverse(c: EnvmapChartUv, half_fov: f32, equisolid: bool, dual: bool) -> EnvmapDirection {
    let charts = select(1u, 2u, dual);
    if c.chart >= charts || !envmap_in_unit_disk(c.uv) {
        return envmap_invalid_direction();
    }
    // Chart 1 looks along -z with -x to the right.
    var side = 1.0;
    if c.chart == 1u {
        side = -1.0;
    }
    let a = 2.0 * c.uv.x - 1.0;
    let b = 1.0 - 2.0 * c.uv.y;
    let r = min(sqrt(a * a + b * b), 1.0);
    var theta: f32;
    if equisolid {
        theta = 2.0 * envmap_fisheye_asin(min(r * envmap_fisheye_sin(0.5 * half_fov), 1.0));
    } else {
        theta = r * half_fov;
    }
    let t = min(theta, ENVMAP_PI);
    let sin_t = sin(t);
    let cos_t = cos(t);
    if r == 0.0 {
        return EnvmapDirection(vec3<f32>(0.0, 0.0, side), true);
    }
    let s = sin_t / r;
    let d = vec3<f32>(side * s * a, s * b, side * cos_t);
    return EnvmapDirection(d / sqrt(dot(d, d)), true);
}
