// envmap shaders, GLSL ES 3.00: eac (from common.wgsl, frame.wgsl, cube.wgsl, eac.wgsl).
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
struct EnvmapCubeFace {
    uint face;
    float sc;
    float tc;
    float ma;
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
    float u_1 = (z * z);
    float _e4 = p;
    p = ((_e4 * u_1) - 0.016363012);
    float _e8 = p;
    p = ((_e8 * u_1) + 0.04320454);
    float _e12 = p;
    p = ((_e12 * u_1) - 0.075516514);
    float _e16 = p;
    p = ((_e16 * u_1) + 0.10665768);
    float _e20 = p;
    p = ((_e20 * u_1) - 0.14211002);
    float _e24 = p;
    p = ((_e24 * u_1) + 0.19993767);
    float _e28 = p;
    p = ((_e28 * u_1) - 0.33333153);
    float _e32 = p;
    return (z + (z * (u_1 * _e32)));
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

EnvmapCubeFace envmap_cube_select_face(vec3 d_4) {
    EnvmapCubeFace r = EnvmapCubeFace(0u, 0.0, 0.0, 0.0);
    bool local_2 = false;
    bool _e1 = envmap_all_finite(d_4);
    if (!(_e1)) {
        return EnvmapCubeFace(4294967295u, 0.0, 0.0, 0.0);
    }
    float ax_1 = abs(d_4.x);
    float ay_1 = abs(d_4.y);
    float az = abs(d_4.z);
    if ((az >= ax_1)) {
        local_2 = (az >= ay_1);
    } else {
        local_2 = false;
    }
    bool _e20 = local_2;
    if (_e20) {
        bool _e22 = envmap_sign_bit(d_4.z);
        if (_e22) {
            r = EnvmapCubeFace(5u, -(d_4.x), -(d_4.y), az);
        } else {
            r = EnvmapCubeFace(4u, d_4.x, -(d_4.y), az);
        }
    } else {
        if ((ay_1 >= ax_1)) {
            bool _e36 = envmap_sign_bit(d_4.y);
            if (_e36) {
                r = EnvmapCubeFace(3u, d_4.x, -(d_4.z), ay_1);
            } else {
                r = EnvmapCubeFace(2u, d_4.x, d_4.z, ay_1);
            }
        } else {
            bool _e47 = envmap_sign_bit(d_4.x);
            if (_e47) {
                r = EnvmapCubeFace(1u, d_4.z, -(d_4.y), ax_1);
            } else {
                r = EnvmapCubeFace(0u, -(d_4.z), -(d_4.y), ax_1);
            }
        }
    }
    float _e60 = r.ma;
    if ((_e60 == 0.0)) {
        return EnvmapCubeFace(4294967295u, 0.0, 0.0, 0.0);
    }
    EnvmapCubeFace _e68 = r;
    return _e68;
}

vec3 envmap_cube_face_direction(uint face, float sc, float tc) {
    switch(face) {
        case 0u: {
            return vec3(1.0, -(tc), -(sc));
        }
        case 1u: {
            return vec3(-1.0, -(tc), sc);
        }
        case 2u: {
            return vec3(sc, 1.0, tc);
        }
        case 3u: {
            return vec3(sc, -1.0, -(tc));
        }
        case 4u: {
            return vec3(sc, -(tc), 1.0);
        }
        case 5u: {
            return vec3(-(sc), -(tc), -1.0);
        }
        default: {
            return vec3(0.0, 0.0, 0.0);
        }
    }
}

EnvmapChartUv envmap_cube_forward(vec3 dir) {
    EnvmapCubeFace _e1 = envmap_cube_select_face(dir);
    if ((_e1.face == ENVMAP_INVALID_CHART)) {
        EnvmapChartUv _e5 = envmap_invalid_chart_uv();
        return _e5;
    }
    float s_2 = (0.5 * ((_e1.sc / _e1.ma) + 1.0));
    float t = (0.5 * ((_e1.tc / _e1.ma) + 1.0));
    return EnvmapChartUv(_e1.face, vec2(s_2, t));
}

EnvmapDirection envmap_cube_inverse(EnvmapChartUv c) {
    bool local_3 = false;
    if (!((c.chart > 5u))) {
        bool _e8 = envmap_in_unit_square(c.uv);
        local_3 = !(_e8);
    } else {
        local_3 = true;
    }
    bool _e11 = local_3;
    if (_e11) {
        EnvmapDirection _e12 = envmap_invalid_direction();
        return _e12;
    }
    vec3 _e26 = envmap_cube_face_direction(c.chart, ((2.0 * c.uv.x) - 1.0), ((2.0 * c.uv.y) - 1.0));
    return EnvmapDirection((_e26 / vec3(sqrt(dot(_e26, _e26)))), true);
}

float envmap_eac_atan(float c_1) {
    float _e2 = envmap_atan_unit(abs(c_1));
    float _e3 = envmap_copysign(_e2, c_1);
    return _e3;
}

float envmap_eac_angle(float u) {
    return (ENVMAP_QUARTER_PI * ((2.0 * u) - 1.0));
}

EnvmapChartUv envmap_eac_forward(vec3 dir_1) {
    EnvmapCubeFace _e1 = envmap_cube_select_face(dir_1);
    if ((_e1.face == ENVMAP_INVALID_CHART)) {
        EnvmapChartUv _e5 = envmap_invalid_chart_uv();
        return _e5;
    }
    float _e10 = envmap_eac_atan((_e1.sc / _e1.ma));
    float _e14 = envmap_clamp_unit((0.5 + (ENVMAP_TWO_OVER_PI * _e10)));
    float _e19 = envmap_eac_atan((_e1.tc / _e1.ma));
    float _e23 = envmap_clamp_unit((0.5 + (ENVMAP_TWO_OVER_PI * _e19)));
    return EnvmapChartUv(_e1.face, vec2(_e14, _e23));
}

EnvmapDirection envmap_eac_inverse(EnvmapChartUv c_2) {
    bool local_4 = false;
    if (!((c_2.chart > 5u))) {
        bool _e8 = envmap_in_unit_square(c_2.uv);
        local_4 = !(_e8);
    } else {
        local_4 = true;
    }
    bool _e11 = local_4;
    if (_e11) {
        EnvmapDirection _e12 = envmap_invalid_direction();
        return _e12;
    }
    float _e16 = envmap_eac_angle(c_2.uv.x);
    float _e20 = envmap_eac_angle(c_2.uv.y);
    vec3 _e22 = envmap_cube_face_direction(c_2.chart, tan(_e16), tan(_e20));
    return EnvmapDirection((_e22 / vec3(sqrt(dot(_e22, _e22)))), true);
}
