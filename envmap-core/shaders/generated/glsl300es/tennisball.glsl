// envmap shaders, GLSL ES 3.00: tennisball (from common.wgsl, frame.wgsl, tennisball.wgsl).
// Written by naga 29.0.4 from the WGSL in envmap-core/shaders/ (the source, with every
// formula, source and comment): do not edit; after changing the WGSL run
// ENVMAP_BLESS_SHADERS=1 cargo test --release -p envmap-tests --test shader_sources
// A library: no #version line and no entry point (docs/shaders.md).
precision highp float;
precision highp int;

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
    uint b_1 = floatBitsToUint(x_2);
    if (!((b_1 <= 1065353216u))) {
        local = (b_1 == 2147483648u);
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
    vec3 a_2 = abs(d_1);
    float m = max(max(a_2.x, a_2.y), a_2.z);
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
    vec3 a_3 = abs(d_2);
    float m_1 = max(max(a_3.x, a_3.y), a_3.z);
    if ((m_1 == 0.0)) {
        return d_2;
    }
    return (frame * (d_2 / vec3(m_1)));
}

EnvmapDirection envmap_frame_from_canonical(mat3x3 frame_1, EnvmapDirection d_3) {
    return EnvmapDirection((transpose(frame_1) * d_3.dir), d_3.valid);
}

bool envmap_tennisball_selects_first_chart(float a_1, float b, float c) {
    bool local_2 = false;
    bool local_3 = false;
    bool local_4 = false;
    if ((c >= 0.0)) {
        local_2 = (abs(b) <= ENVMAP_SQRT_HALF);
    } else {
        local_2 = false;
    }
    bool _e11 = local_2;
    if (!(_e11)) {
        if ((c <= 0.0)) {
            local_4 = (abs(a_1) >= ENVMAP_SQRT_HALF);
        } else {
            local_4 = false;
        }
        bool _e23 = local_4;
        local_3 = _e23;
    } else {
        local_3 = true;
    }
    bool _e25 = local_3;
    return _e25;
}

EnvmapChartUv envmap_tennisball_forward(vec3 dir) {
    uint chart = 0u;
    float theta = 0.0;
    float phi = 0.0;
    EnvmapDirection _e1 = envmap_normalize_direction(dir);
    if (!(_e1.valid)) {
        EnvmapChartUv _e4 = envmap_invalid_chart_uv();
        return _e4;
    }
    float a_4 = _e1.dir.x;
    float b_2 = _e1.dir.y;
    float c_2 = _e1.dir.z;
    bool _e14 = envmap_tennisball_selects_first_chart(a_4, b_2, c_2);
    if (_e14) {
        chart = 0u;
        float _e20 = envmap_atan2f(b_2, sqrt(((a_4 * a_4) + (c_2 * c_2))));
        theta = _e20;
        float _e21 = envmap_atan2f(a_4, c_2);
        phi = _e21;
    } else {
        chart = 1u;
        float _e27 = envmap_atan2f(a_4, sqrt(((b_2 * b_2) + (c_2 * c_2))));
        theta = _e27;
        float _e29 = envmap_atan2f(b_2, -(c_2));
        phi = _e29;
    }
    float _e32 = theta;
    theta = clamp(_e32, -0.7853982, ENVMAP_QUARTER_PI);
    float _e36 = phi;
    phi = clamp(_e36, -(2.3561945), 2.3561945);
    float _e39 = phi;
    float _e43 = envmap_clamp_unit(((_e39 / 4.712389) + 0.5));
    float _e44 = theta;
    float _e49 = envmap_clamp_unit((0.5 - (_e44 / ENVMAP_HALF_PI)));
    uint _e50 = chart;
    return EnvmapChartUv(_e50, vec2(_e43, _e49));
}

EnvmapDirection envmap_tennisball_inverse(EnvmapChartUv c_1) {
    bool local_5 = false;
    if (!((c_1.chart > 1u))) {
        bool _e8 = envmap_in_unit_square(c_1.uv);
        local_5 = !(_e8);
    } else {
        local_5 = true;
    }
    bool _e11 = local_5;
    if (_e11) {
        EnvmapDirection _e12 = envmap_invalid_direction();
        return _e12;
    }
    float phi_1 = ((c_1.uv.x - 0.5) * 4.712389);
    float theta_1 = ((0.5 - c_1.uv.y) * ENVMAP_HALF_PI);
    float sp = sin(phi_1);
    float cp = cos(phi_1);
    float st = sin(theta_1);
    float ct = cos(theta_1);
    if ((c_1.chart == 0u)) {
        return EnvmapDirection(vec3((ct * sp), st, (ct * cp)), true);
    }
    return EnvmapDirection(vec3(st, (ct * sp), (-(ct) * cp)), true);
}
