// envmap shaders: what every other file needs. Prepend it (WGSL has no includes).
//
// The WGSL of envmap-core/src/direction.rs (overflow-free normalisation),
// mapping.rs (the unit square and disk tests) and math.rs (copysign,
// clamping), and an atan2 of its own. The WGSL files are the source; the
// GLSL and HLSL in generated/ are written from them by naga
// (docs/shaders.md says how to include either in an engine).
//
// Conventions, as in envmap-core (docs/conventions.md):
//   * a direction need not be unit length; components may be anywhere from
//     tiny to 3.4e38. NaN or infinite components and the zero vector are
//     invalid: forward gives chart ENVMAP_INVALID_CHART and uv (0, 0);
//   * (chart, u, v): u grows to the right, v downwards, both in [0, 1];
//     inverse gives a direction and valid = true, or valid = false and
//     (0, 0, 0) for a chart out of range, coordinates outside [0, 1]
//     (NaN included; -0 counts as 0) or outside a disk chart.
//
// Tests on bits, not on floats: NaN, infinities and sign bits are read
// from the bit patterns (bitcast), because WGSL lets an implementation
// assume that no NaN or infinity occurs and ignore the sign of zero in
// arithmetic; integer operations are exact everywhere.
//
// atan2: WGSL's own is only held to 4096 ULP (Mesa's lavapipe measured
// 3.3e-6 rad) and its asin and acos to the same forms (lavapipe: 3.9e-4
// rad). envmap_atan2f reduces to atan(z), z = min/max in [0, 1], and
// evaluates envmap-simd's exact-tier minimax polynomial z + z^3 P(z^2)
// (envmap-simd/src/approx/coeffs.rs, ATAN_EXACT) with plain additions and
// multiplications, whose accuracy WGSL fixes; its bound is in
// docs/shaders.md. sin, cos and sqrt are the built-ins (each call's
// argument lies in [-pi, pi], where WGSL bounds sin and cos).

/// The chart of an invalid forward result (NaN, infinite or zero direction).
const ENVMAP_INVALID_CHART: u32 = 0xffffffffu;
/// pi, rounded to f32 (0x40490fdb).
const ENVMAP_PI: f32 = 3.1415927410125732421875;
/// 2 pi, rounded to f32 (0x40c90fdb).
const ENVMAP_TAU: f32 = 6.283185482025146484375;
/// pi / 2, rounded to f32 (0x3fc90fdb).
const ENVMAP_HALF_PI: f32 = 1.57079637050628662109375;
/// pi / 4, rounded to f32 (0x3f490fdb).
const ENVMAP_QUARTER_PI: f32 = 0.785398185253143310546875;
/// sqrt(2) / 2, rounded to f32 (0x3f3504f3).
const ENVMAP_SQRT_HALF: f32 = 0.707106769084930419921875;
/// 2 / pi, rounded to f32 (0x3f22f983).
const ENVMAP_TWO_OVER_PI: f32 = 0.636619746685028076171875;
/// The largest u'^2 + v'^2 inside a disk chart, 1 + 4 * 2^-23: the rim's
/// own coordinates may round to just outside the unit circle.
const ENVMAP_DISK_LIMIT: f32 = 1.000000476837158203125;

/// A point of a chart: which chart (cube face, paraboloid disk, tennisball
/// strip; 0 for single-chart maps), and (u, v) in it.
struct EnvmapChartUv {
    chart: u32,
    uv: vec2<f32>,
}

/// A direction from an inverse mapping: unit length (within the rounding
/// of the math) when valid; (0, 0, 0) and valid = false otherwise.
struct EnvmapDirection {
    dir: vec3<f32>,
    valid: bool,
}

/// The forward result for an invalid direction.
fn envmap_invalid_chart_uv() -> EnvmapChartUv {
    return EnvmapChartUv(ENVMAP_INVALID_CHART, vec2<f32>(0.0, 0.0));
}

/// The inverse result for an invalid chart point.
fn envmap_invalid_direction() -> EnvmapDirection {
    return EnvmapDirection(vec3<f32>(0.0, 0.0, 0.0), false);
}

/// Whether the sign bit of x is set (-0 included).
fn envmap_sign_bit(x: f32) -> bool {
    return (bitcast<u32>(x) & 0x80000000u) != 0u;
}

/// |x| with the sign bit of s (math.rs copysign; signed zeros respected).
fn envmap_copysign(x: f32, s: f32) -> f32 {
    return bitcast<f32>((bitcast<u32>(x) & 0x7fffffffu) | (bitcast<u32>(s) & 0x80000000u));
}

/// Whether no component of d is NaN or infinite (read from the exponent bits).
fn envmap_all_finite(d: vec3<f32>) -> bool {
    let e = bitcast<vec3<u32>>(d) & vec3<u32>(0x7f800000u);
    return all(e != vec3<u32>(0x7f800000u));
}

/// Whether x lies in [0, 1] (-0 counts as 0; false for NaN): the bit
/// pattern of a float in [+0, 1] is at most that of 1.0.
fn envmap_in_unit_interval(x: f32) -> bool {
    let b = bitcast<u32>(x);
    return b <= 0x3f800000u || b == 0x80000000u;
}

/// mapping.rs in_unit_square: (u, v) in the closed unit square.
fn envmap_in_unit_square(uv: vec2<f32>) -> bool {
    return envmap_in_unit_interval(uv.x) && envmap_in_unit_interval(uv.y);
}

/// mapping.rs in_unit_disk: (u, v) in the square and u'^2 + v'^2 <= 1 + 4 * 2^-23
/// with (u', v') = (2u - 1, 2v - 1).
fn envmap_in_unit_disk(uv: vec2<f32>) -> bool {
    if !envmap_in_unit_square(uv) {
        return false;
    }
    let p = 2.0 * uv - 1.0;
    return p.x * p.x + p.y * p.y <= ENVMAP_DISK_LIMIT;
}

/// x clamped into [0, 1].
fn envmap_clamp_unit(x: f32) -> f32 {
    return clamp(x, 0.0, 1.0);
}

/// direction.rs normalize_direction: d divided by its largest magnitude
/// (so nothing is squared at its own scale, whatever the magnitude), then
/// normalised; invalid for NaN or infinite components and the zero vector.
fn envmap_normalize_direction(d: vec3<f32>) -> EnvmapDirection {
    if !envmap_all_finite(d) {
        return envmap_invalid_direction();
    }
    let a = abs(d);
    let m = max(max(a.x, a.y), a.z);
    if m == 0.0 {
        return envmap_invalid_direction();
    }
    let s = d / m;
    return EnvmapDirection(s / sqrt(dot(s, s)), true);
}

/// atan(z) for z in [0, 1]: z + z^3 P(z^2), P the minimax fit of
/// envmap-simd's exact tier (ATAN_EXACT, relative error), by Horner's scheme.
fn envmap_atan_unit(z: f32) -> f32 {
    let u = z * z;
    var p = 0.00291936122812330722808837890625;
    p = p * u - 0.01636301167309284210205078125;
    p = p * u + 0.043204538524150848388671875;
    p = p * u - 0.075516514480113983154296875;
    p = p * u + 0.106657676398754119873046875;
    p = p * u - 0.1421100199222564697265625;
    p = p * u + 0.1999376714229583740234375;
    p = p * u - 0.333331525325775146484375;
    return z + z * (u * p);
}

/// The four-quadrant arctangent of y / x in [-pi, pi], as libm's atan2f
/// for finite arguments: z = min(|x|, |y|) / max(|x|, |y|), atan(z) rebuilt
/// as p, pi/2 - p, pi/2 + p or pi - p by the octant, then the sign of y
/// (its sign bit, so atan2(+-0, -1) = +-pi and atan2(+-0, -0) = +-pi).
/// Scale-invariant: any finite pair, however large or small (but see
/// docs/shaders.md on subnormals, which a GPU may flush to zero).
fn envmap_atan2f(y: f32, x: f32) -> f32 {
    let ax = abs(x);
    let ay = abs(y);
    let swap = ay > ax;
    let num = select(ay, ax, swap);
    let den = select(ax, ay, swap);
    // Both zero: the angle is 0 or pi, from the signs alone.
    var z = 0.0;
    if den > 0.0 {
        z = num / den;
    }
    let p = envmap_atan_unit(z);
    let x_negative = envmap_sign_bit(x);
    var a: f32;
    if swap {
        a = select(ENVMAP_HALF_PI - p, ENVMAP_HALF_PI + p, x_negative);
    } else {
        a = select(p, ENVMAP_PI - p, x_negative);
    }
    return envmap_copysign(a, y);
}
