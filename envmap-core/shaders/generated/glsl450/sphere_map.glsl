// envmap shaders, GLSL 4.50: sphere_map (from common.wgsl, frame.wgsl, sphere_map.wgsl).
// Written by naga 29.0.4 from the WGSL in envmap-core/shaders/ (the source, with every
// formula, source and comment): do not edit; after changing the WGSL run
// ENVMAP_BLESS_SHADERS=1 cargo test --release -p envmap-tests --test shader_sources
// A library: no #version line and no entry point (docs/shaders.md).
struct EnvmapChartUv {
    uint chart;
    vec2 uv;
};
struct EnvmapDirection {
    vec3 dir;
    bool valid;
};
const uint ENVMAP_INVALID_CHART = 4294967295u;
const float ENVMAP_PI = 3.1415927;
const float ENVMAP_TAU = 6.2831855;
const float ENVMAP_HALF_PI = 1.5707964;
const float ENVMAP_QUARTER_PI = 0.7853982;
const float ENVMAP_SQRT_HALF = 0.70710677;
const float ENVMAP_TWO_OVER_PI = 0.63661975;
const float ENVMAP_DISK_LIMIT = 1.0000005;
const mat3x3 ENVMAP_FRAME_Z_UP_RH = mat3x3(vec3(1.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0), vec3(0.0, 0.0, 1.0));
const mat3x3 ENVMAP_FRAME_Y_UP_RH = mat3x3(vec3(1.0, 0.0, 0.0), vec3(0.0, 0.0, 1.0), vec3(0.0, -1.0, 0.0));
const mat3x3 ENVMAP_FRAME_Y_UP_LH = mat3x3(vec3(1.0, 0.0, 0.0), vec3(0.0, 0.0, 1.0), vec3(0.0, 1.0, 0.0));


EnvmapChartUv envmap_invalid_chart_uv() {
    return EnvmapChartUv(4294967295u, vec2(0.0, 0.0));
}

EnvmapDirection envmap_invalid_direction() {
    return EnvmapDirection(vec3(0.0, 0.0, 0.0), false);
}

bool envmap_sign_bit(float x) {
    return ((floatBitsToUint(x) & 2147483648u) != 0u);
}

float envmap_copysign(float x_1, float s) {
    return uintBitsToFloat(((floatBitsToUint(x_1) & 2147483647u) | (floatBitsToUint(s) & 2147483648u)));
}

bool envmap_all_finite(vec3 d) {
    uvec3 e = (floatBitsToUint(d) & uvec3(2139095040u));
    return all(notEqual(e, uvec3(2139095040u)));
}

bool envmap_in_unit_interval(float x_2) {
    bool local = false;
    uint b = floatBitsToUint(x_2);
    if (!((b <= 1065353216u))) {
        local = (b == 2147483648u);
    } else {
        local = true;
    }
    bool _e10 = local;
    return _e10;
}

bool envmap_in_unit_square(vec2 uv) {
    bool local_1 = false;
    bool _e2 = envmap_in_unit_interval(uv.x);
    if (_e2) {
        bool _e6 = envmap_in_unit_interval(uv.y);
        local_1 = _e6;
    } else {
        local_1 = false;
    }
    bool _e8 = local_1;
    return _e8;
}

bool envmap_in_unit_disk(vec2 uv_1) {
    bool _e1 = envmap_in_unit_square(uv_1);
    if (!(_e1)) {
        return false;
    }
    vec2 p_1 = ((2.0 * uv_1) - vec2(1.0));
    return (((p_1.x * p_1.x) + (p_1.y * p_1.y)) <= ENVMAP_DISK_LIMIT);
}

float envmap_clamp_unit(float x_3) {
    return clamp(x_3, 0.0, 1.0);
}

EnvmapDirection envmap_normalize_direction(vec3 d_1) {
    bool _e1 = envmap_all_finite(d_1);
    if (!(_e1)) {
        EnvmapDirection _e3 = envmap_invalid_direction();
        return _e3;
    }
    vec3 a_1 = abs(d_1);
    float m = max(max(a_1.x, a_1.y), a_1.z);
    if ((m == 0.0)) {
        EnvmapDirection _e12 = envmap_invalid_direction();
        return _e12;
    }
    vec3 s_1 = (d_1 / vec3(m));
    return EnvmapDirection((s_1 / vec3(sqrt(dot(s_1, s_1)))), true);
}

float envmap_atan_unit(float z) {
    float p = 0.0029193612;
    float u = (z * z);
    float _e4 = p;
    p = ((_e4 * u) - 0.016363012);
    float _e8 = p;
    p = ((_e8 * u) + 0.04320454);
    float _e12 = p;
    p = ((_e12 * u) - 0.075516514);
    float _e16 = p;
    p = ((_e16 * u) + 0.10665768);
    float _e20 = p;
    p = ((_e20 * u) - 0.14211002);
    float _e24 = p;
    p = ((_e24 * u) + 0.19993767);
    float _e28 = p;
    p = ((_e28 * u) - 0.33333153);
    float _e32 = p;
    return (z + (z * (u * _e32)));
}

float envmap_atan2f(float y, float x_4) {
    float z_1 = 0.0;
    float a = 0.0;
    float ax = abs(x_4);
    float ay = abs(y);
    bool swap = (ay > ax);
    float num = (swap ? ax : ay);
    float den = (swap ? ay : ax);
    if ((den > 0.0)) {
        z_1 = (num / den);
    }
    float _e12 = z_1;
    float _e13 = envmap_atan_unit(_e12);
    bool _e14 = envmap_sign_bit(x_4);
    if (swap) {
        a = (_e14 ? (ENVMAP_HALF_PI + _e13) : (ENVMAP_HALF_PI - _e13));
    } else {
        a = (_e14 ? (ENVMAP_PI - _e13) : _e13);
    }
    float _e24 = a;
    float _e25 = envmap_copysign(_e24, y);
    return _e25;
}

vec3 envmap_frame_to_canonical(mat3x3 frame, vec3 d_2) {
    bool _e2 = envmap_all_finite(d_2);
    if (!(_e2)) {
        return d_2;
    }
    vec3 a_2 = abs(d_2);
    float m_1 = max(max(a_2.x, a_2.y), a_2.z);
    if ((m_1 == 0.0)) {
        return d_2;
    }
    return (frame * (d_2 / vec3(m_1)));
}

EnvmapDirection envmap_frame_from_canonical(mat3x3 frame_1, EnvmapDirection d_3) {
    return EnvmapDirection((transpose(frame_1) * d_3.dir), d_3.valid);
}

EnvmapChartUv envmap_sphere_map_forward_sigma(vec3 dir, float sigma) {
    float one_plus_w = 0.0;
    EnvmapDirection _e2 = envmap_normalize_direction(dir);
    if (!(_e2.valid)) {
        EnvmapChartUv _e5 = envmap_invalid_chart_uv();
        return _e5;
    }
    vec3 r = _e2.dir;
    float w = (sigma * r.z);
    if ((w < 0.0)) {
        one_plus_w = (((r.x * r.x) + (r.y * r.y)) / (1.0 - w));
    } else {
        one_plus_w = (1.0 + w);
    }
    float _e29 = one_plus_w;
    float s_2 = max(max(abs(r.x), abs(r.y)), _e29);
    if ((s_2 == 0.0)) {
        return EnvmapChartUv(0u, vec2(1.0, 0.5));
    }
    float x_5 = (r.x / s_2);
    float y_1 = (r.y / s_2);
    float _e42 = one_plus_w;
    float h = (_e42 / s_2);
    float m_2 = sqrt((((x_5 * x_5) + (y_1 * y_1)) + (h * h)));
    float _e55 = envmap_clamp_unit(((0.5 * (x_5 / m_2)) + 0.5));
    float _e61 = envmap_clamp_unit(((0.5 * (y_1 / m_2)) + 0.5));
    return EnvmapChartUv(0u, vec2(_e55, _e61));
}

EnvmapDirection envmap_sphere_map_inverse_sigma(EnvmapChartUv c, float sigma_1) {
    bool local_2 = false;
    if (!((c.chart != 0u))) {
        bool _e9 = envmap_in_unit_disk(c.uv);
        local_2 = !(_e9);
    } else {
        local_2 = true;
    }
    bool _e12 = local_2;
    if (_e12) {
        EnvmapDirection _e13 = envmap_invalid_direction();
        return _e13;
    }
    float x_6 = ((2.0 * c.uv.x) - 1.0);
    float y_2 = ((2.0 * c.uv.y) - 1.0);
    float r2_ = ((x_6 * x_6) + (y_2 * y_2));
    float nz = sqrt(max((1.0 - r2_), 0.0));
    vec3 d_4 = vec3(((2.0 * x_6) * nz), ((2.0 * y_2) * nz), (sigma_1 * (1.0 - (2.0 * r2_))));
    return EnvmapDirection((d_4 / vec3(sqrt(dot(d_4, d_4)))), true);
}

EnvmapChartUv envmap_sphere_map_forward(vec3 dir_1) {
    EnvmapChartUv _e2 = envmap_sphere_map_forward_sigma(dir_1, -1.0);
    return _e2;
}

EnvmapDirection envmap_sphere_map_inverse(EnvmapChartUv c_1) {
    EnvmapDirection _e2 = envmap_sphere_map_inverse_sigma(c_1, -1.0);
    return _e2;
}

EnvmapChartUv envmap_sphere_map_gl_forward(vec3 dir_2) {
    EnvmapChartUv _e2 = envmap_sphere_map_forward_sigma(dir_2, 1.0);
    return _e2;
}

EnvmapDirection envmap_sphere_map_gl_inverse(EnvmapChartUv c_2) {
    EnvmapDirection _e2 = envmap_sphere_map_inverse_sigma(c_2, 1.0);
    return _e2;
}

EnvmapChartUv envmap_sphere_map_uv_from_normal(vec3 n) {
    EnvmapDirection _e1 = envmap_normalize_direction(n);
    if (!(_e1.valid)) {
        EnvmapChartUv _e4 = envmap_invalid_chart_uv();
        return _e4;
    }
    float _e12 = envmap_clamp_unit(((0.5 * _e1.dir.x) + 0.5));
    float _e19 = envmap_clamp_unit(((0.5 * _e1.dir.y) + 0.5));
    return EnvmapChartUv(0u, vec2(_e12, _e19));
}
