// envmap shaders, GLSL 4.50: fisheye (from common.wgsl, frame.wgsl, fisheye.wgsl).
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
const float ENVMAP_FISHEYE_SEEN_SCALE = 1.0000005;
const float ENVMAP_FISHEYE_HALF_PI_LO = -4.371139e-8;


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
    vec2 p_2 = ((2.0 * uv_1) - vec2(1.0));
    return (((p_2.x * p_2.x) + (p_2.y * p_2.y)) <= ENVMAP_DISK_LIMIT);
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

float envmap_fisheye_sin(float x_5) {
    float p_1 = -0.0001951829;
    float q = 2.4432327e-5;
    if ((x_5 <= ENVMAP_QUARTER_PI)) {
        float u_1 = (x_5 * x_5);
        float _e6 = p_1;
        p_1 = ((_e6 * u_1) + 0.008332189);
        float _e10 = p_1;
        p_1 = ((_e10 * u_1) - 0.16666655);
        float _e14 = p_1;
        return (x_5 + (x_5 * (u_1 * _e14)));
    }
    float y_2 = ((ENVMAP_HALF_PI - x_5) + ENVMAP_FISHEYE_HALF_PI_LO);
    float u_2 = (y_2 * y_2);
    float _e25 = q;
    q = ((_e25 * u_2) - 0.001388731);
    float _e29 = q;
    q = ((_e29 * u_2) + 0.041666646);
    float half_u = (0.5 * u_2);
    float w = (1.0 - half_u);
    float rest = ((1.0 - w) - half_u);
    float _e41 = q;
    return (w + (((u_2 * u_2) * _e41) + rest));
}

float envmap_fisheye_asin(float q_1) {
    float _e7 = envmap_atan2f(q_1, sqrt(((1.0 - q_1) * (1.0 + q_1))));
    return _e7;
}

bool envmap_fisheye_covers_sphere(float half_fov, bool dual) {
    if (dual) {
        return (half_fov >= ENVMAP_HALF_PI);
    }
    return (half_fov >= ENVMAP_PI);
}

EnvmapChartUv envmap_fisheye_forward(vec3 dir, float half_fov_1, bool equisolid, bool dual_1) {
    bool local_2 = false;
    float axial = 0.0;
    float side = 1.0;
    bool local_3 = false;
    float r = 0.0;
    float x_6 = 1.0;
    float y_1 = 0.0;
    EnvmapDirection _e4 = envmap_normalize_direction(dir);
    if (!(_e4.valid)) {
        EnvmapChartUv _e7 = envmap_invalid_chart_uv();
        return _e7;
    }
    vec3 d_4 = _e4.dir;
    if (dual_1) {
        local_2 = (dir.z < 0.0);
    } else {
        local_2 = false;
    }
    bool back = local_2;
    axial = d_4.z;
    if (back) {
        axial = -(d_4.z);
        side = -1.0;
    }
    float rho = sqrt(((d_4.x * d_4.x) + (d_4.y * d_4.y)));
    float _e31 = axial;
    float _e32 = envmap_atan2f(rho, _e31);
    bool _e33 = envmap_fisheye_covers_sphere(half_fov_1, dual_1);
    if (!(_e33)) {
        local_3 = (_e32 > (half_fov_1 * ENVMAP_FISHEYE_SEEN_SCALE));
    } else {
        local_3 = false;
    }
    bool _e41 = local_3;
    if (_e41) {
        EnvmapChartUv _e42 = envmap_invalid_chart_uv();
        return _e42;
    }
    if (equisolid) {
        float _e46 = envmap_fisheye_sin((0.5 * _e32));
        float _e49 = envmap_fisheye_sin((0.5 * half_fov_1));
        r = (_e46 / _e49);
    } else {
        r = (_e32 / half_fov_1);
    }
    float _e52 = r;
    r = min(_e52, 1.0);
    float a_3 = max(abs(dir.x), abs(dir.y));
    if ((a_3 != 0.0)) {
        x_6 = (dir.x / a_3);
        y_1 = (dir.y / a_3);
    }
    float _e70 = r;
    float _e73 = x_6;
    float _e74 = x_6;
    float _e76 = y_1;
    float _e77 = y_1;
    float s_2 = ((0.5 * _e70) / sqrt(((_e73 * _e74) + (_e76 * _e77))));
    float _e82 = side;
    float _e84 = x_6;
    float _e88 = envmap_clamp_unit((0.5 + ((_e82 * s_2) * _e84)));
    float _e89 = y_1;
    float _e93 = envmap_clamp_unit((0.5 - (s_2 * _e89)));
    return EnvmapChartUv((back ? 1u : 0u), vec2(_e88, _e93));
}

EnvmapDirection envmap_fisheye_inverse(EnvmapChartUv c, float half_fov_2, bool equisolid_1, bool dual_2) {
    bool local_4 = false;
    float side_1 = 1.0;
    float theta = 0.0;
    uint charts = (dual_2 ? 2u : 1u);
    if (!((c.chart >= charts))) {
        bool _e13 = envmap_in_unit_disk(c.uv);
        local_4 = !(_e13);
    } else {
        local_4 = true;
    }
    bool _e16 = local_4;
    if (_e16) {
        EnvmapDirection _e17 = envmap_invalid_direction();
        return _e17;
    }
    if ((c.chart == 1u)) {
        side_1 = -1.0;
    }
    float a_4 = ((2.0 * c.uv.x) - 1.0);
    float b_1 = (1.0 - (2.0 * c.uv.y));
    float r_1 = min(sqrt(((a_4 * a_4) + (b_1 * b_1))), 1.0);
    if (equisolid_1) {
        float _e45 = envmap_fisheye_sin((0.5 * half_fov_2));
        float _e49 = envmap_fisheye_asin(min((r_1 * _e45), 1.0));
        theta = (2.0 * _e49);
    } else {
        theta = (r_1 * half_fov_2);
    }
    float _e53 = theta;
    float t = min(_e53, ENVMAP_PI);
    float sin_t = sin(t);
    float cos_t = cos(t);
    if ((r_1 == 0.0)) {
        float _e60 = side_1;
        return EnvmapDirection(vec3(0.0, 0.0, _e60), true);
    }
    float s_3 = (sin_t / r_1);
    float _e67 = side_1;
    float _e71 = side_1;
    vec3 d_5 = vec3(((_e67 * s_3) * a_4), (s_3 * b_1), (_e71 * cos_t));
    return EnvmapDirection((d_5 / vec3(sqrt(dot(d_5, d_5)))), true);
}
