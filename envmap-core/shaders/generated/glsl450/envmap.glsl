// envmap shaders, GLSL 4.50: envmap (from common.wgsl, frame.wgsl, latlong.wgsl, cube.wgsl, eac.wgsl, sphere_map.wgsl, dual_paraboloid.wgsl, angular.wgsl, tennisball.wgsl, octahedral.wgsl, fisheye.wgsl, lighting.wgsl).
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
struct EnvmapCubeFace {
    uint face;
    float sc;
    float tc;
    float ma;
};
struct EnvmapFootprint {
    int first;
    int second;
    float f;
};
struct EnvmapLevels {
    int level;
    float blend;
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
const float ENVMAP_SH_Y00_CONSTANT = 0.2820948;
const float ENVMAP_SH_Y1_CONSTANT = 0.48860252;
const float ENVMAP_SH_Y2_CONSTANT = 1.0925485;
const float ENVMAP_SH_Y20_CONSTANT = 0.31539157;
const float ENVMAP_SH_Y22_CONSTANT = 0.54627424;
const float ENVMAP_SH_A1_FACTOR = 2.0943952;
const float ENVMAP_INV_PI = 0.31830987;


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
    uvec3 e_1 = (floatBitsToUint(d) & uvec3(2139095040u));
    return all(notEqual(e_1, uvec3(2139095040u)));
}

bool envmap_in_unit_interval(float x_2) {
    bool local = false;
    uint b_2 = floatBitsToUint(x_2);
    if (!((b_2 <= 1065353216u))) {
        local = (b_2 == 2147483648u);
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
    vec3 a_3 = abs(d_1);
    float m = max(max(a_3.x, a_3.y), a_3.z);
    if ((m == 0.0)) {
        EnvmapDirection _e12 = envmap_invalid_direction();
        return _e12;
    }
    vec3 s_7 = (d_1 / vec3(m));
    return EnvmapDirection((s_7 / vec3(sqrt(dot(s_7, s_7)))), true);
}

float envmap_atan_unit(float z) {
    float p = 0.0029193612;
    float u_5 = (z * z);
    float _e4 = p;
    p = ((_e4 * u_5) - 0.016363012);
    float _e8 = p;
    p = ((_e8 * u_5) + 0.04320454);
    float _e12 = p;
    p = ((_e12 * u_5) - 0.075516514);
    float _e16 = p;
    p = ((_e16 * u_5) + 0.10665768);
    float _e20 = p;
    p = ((_e20 * u_5) - 0.14211002);
    float _e24 = p;
    p = ((_e24 * u_5) + 0.19993767);
    float _e28 = p;
    p = ((_e28 * u_5) - 0.33333153);
    float _e32 = p;
    return (z + (z * (u_5 * _e32)));
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
    vec3 a_4 = abs(d_2);
    float m_1 = max(max(a_4.x, a_4.y), a_4.z);
    if ((m_1 == 0.0)) {
        return d_2;
    }
    return (frame * (d_2 / vec3(m_1)));
}

EnvmapDirection envmap_frame_from_canonical(mat3x3 frame_1, EnvmapDirection d_3) {
    return EnvmapDirection((transpose(frame_1) * d_3.dir), d_3.valid);
}

EnvmapChartUv envmap_latlong_forward(vec3 dir) {
    float u = 0.0;
    EnvmapDirection _e1 = envmap_normalize_direction(dir);
    if (!(_e1.valid)) {
        EnvmapChartUv _e4 = envmap_invalid_chart_uv();
        return _e4;
    }
    vec3 d_8 = _e1.dir;
    float _e8 = envmap_atan2f(dir.y, dir.x);
    u = (_e8 / ENVMAP_TAU);
    float _e12 = u;
    if ((_e12 < 0.0)) {
        float _e15 = u;
        u = (_e15 + 1.0);
        float _e18 = u;
        if ((_e18 >= 1.0)) {
            u = 0.0;
        }
    }
    float _e22 = u;
    u = abs(_e22);
    float rho = sqrt(((d_8.x * d_8.x) + (d_8.y * d_8.y)));
    float _e33 = envmap_atan2f(rho, d_8.z);
    float _e36 = envmap_clamp_unit((_e33 / ENVMAP_PI));
    float _e38 = u;
    return EnvmapChartUv(0u, vec2(_e38, _e36));
}

EnvmapDirection envmap_latlong_inverse(EnvmapChartUv c) {
    bool local_2 = false;
    float phi = 0.0;
    if (!((c.chart != 0u))) {
        bool _e8 = envmap_in_unit_square(c.uv);
        local_2 = !(_e8);
    } else {
        local_2 = true;
    }
    bool _e11 = local_2;
    if (_e11) {
        EnvmapDirection _e12 = envmap_invalid_direction();
        return _e12;
    }
    phi = (ENVMAP_TAU * c.uv.x);
    if ((c.uv.x > 0.5)) {
        phi = (ENVMAP_TAU * (c.uv.x - 1.0));
    }
    float theta_2 = (ENVMAP_PI * c.uv.y);
    float st = sin(theta_2);
    float _e33 = phi;
    float _e36 = phi;
    return EnvmapDirection(vec3((st * cos(_e33)), (st * sin(_e36)), cos(theta_2)), true);
}

EnvmapCubeFace envmap_cube_select_face(vec3 d_4) {
    EnvmapCubeFace r = EnvmapCubeFace(0u, 0.0, 0.0, 0.0);
    bool local_3 = false;
    bool _e1 = envmap_all_finite(d_4);
    if (!(_e1)) {
        return EnvmapCubeFace(4294967295u, 0.0, 0.0, 0.0);
    }
    float ax_1 = abs(d_4.x);
    float ay_1 = abs(d_4.y);
    float az = abs(d_4.z);
    if ((az >= ax_1)) {
        local_3 = (az >= ay_1);
    } else {
        local_3 = false;
    }
    bool _e20 = local_3;
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

EnvmapChartUv envmap_cube_forward(vec3 dir_1) {
    EnvmapCubeFace _e1 = envmap_cube_select_face(dir_1);
    if ((_e1.face == ENVMAP_INVALID_CHART)) {
        EnvmapChartUv _e5 = envmap_invalid_chart_uv();
        return _e5;
    }
    float s_8 = (0.5 * ((_e1.sc / _e1.ma) + 1.0));
    float t_15 = (0.5 * ((_e1.tc / _e1.ma) + 1.0));
    return EnvmapChartUv(_e1.face, vec2(s_8, t_15));
}

EnvmapDirection envmap_cube_inverse(EnvmapChartUv c_1) {
    bool local_4 = false;
    if (!((c_1.chart > 5u))) {
        bool _e8 = envmap_in_unit_square(c_1.uv);
        local_4 = !(_e8);
    } else {
        local_4 = true;
    }
    bool _e11 = local_4;
    if (_e11) {
        EnvmapDirection _e12 = envmap_invalid_direction();
        return _e12;
    }
    vec3 _e26 = envmap_cube_face_direction(c_1.chart, ((2.0 * c_1.uv.x) - 1.0), ((2.0 * c_1.uv.y) - 1.0));
    return EnvmapDirection((_e26 / vec3(sqrt(dot(_e26, _e26)))), true);
}

float envmap_eac_atan(float c_2) {
    float _e2 = envmap_atan_unit(abs(c_2));
    float _e3 = envmap_copysign(_e2, c_2);
    return _e3;
}

float envmap_eac_angle(float u_1) {
    return (ENVMAP_QUARTER_PI * ((2.0 * u_1) - 1.0));
}

EnvmapChartUv envmap_eac_forward(vec3 dir_2) {
    EnvmapCubeFace _e1 = envmap_cube_select_face(dir_2);
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

EnvmapDirection envmap_eac_inverse(EnvmapChartUv c_3) {
    bool local_5 = false;
    if (!((c_3.chart > 5u))) {
        bool _e8 = envmap_in_unit_square(c_3.uv);
        local_5 = !(_e8);
    } else {
        local_5 = true;
    }
    bool _e11 = local_5;
    if (_e11) {
        EnvmapDirection _e12 = envmap_invalid_direction();
        return _e12;
    }
    float _e16 = envmap_eac_angle(c_3.uv.x);
    float _e20 = envmap_eac_angle(c_3.uv.y);
    vec3 _e22 = envmap_cube_face_direction(c_3.chart, tan(_e16), tan(_e20));
    return EnvmapDirection((_e22 / vec3(sqrt(dot(_e22, _e22)))), true);
}

EnvmapChartUv envmap_sphere_map_forward_sigma(vec3 dir_3, float sigma) {
    float one_plus_w = 0.0;
    EnvmapDirection _e2 = envmap_normalize_direction(dir_3);
    if (!(_e2.valid)) {
        EnvmapChartUv _e5 = envmap_invalid_chart_uv();
        return _e5;
    }
    vec3 r_4 = _e2.dir;
    float w = (sigma * r_4.z);
    if ((w < 0.0)) {
        one_plus_w = (((r_4.x * r_4.x) + (r_4.y * r_4.y)) / (1.0 - w));
    } else {
        one_plus_w = (1.0 + w);
    }
    float _e29 = one_plus_w;
    float s_9 = max(max(abs(r_4.x), abs(r_4.y)), _e29);
    if ((s_9 == 0.0)) {
        return EnvmapChartUv(0u, vec2(1.0, 0.5));
    }
    float x_8 = (r_4.x / s_9);
    float y_3 = (r_4.y / s_9);
    float _e42 = one_plus_w;
    float h = (_e42 / s_9);
    float m_2 = sqrt((((x_8 * x_8) + (y_3 * y_3)) + (h * h)));
    float _e55 = envmap_clamp_unit(((0.5 * (x_8 / m_2)) + 0.5));
    float _e61 = envmap_clamp_unit(((0.5 * (y_3 / m_2)) + 0.5));
    return EnvmapChartUv(0u, vec2(_e55, _e61));
}

EnvmapDirection envmap_sphere_map_inverse_sigma(EnvmapChartUv c_4, float sigma_1) {
    bool local_6 = false;
    if (!((c_4.chart != 0u))) {
        bool _e9 = envmap_in_unit_disk(c_4.uv);
        local_6 = !(_e9);
    } else {
        local_6 = true;
    }
    bool _e12 = local_6;
    if (_e12) {
        EnvmapDirection _e13 = envmap_invalid_direction();
        return _e13;
    }
    float x_9 = ((2.0 * c_4.uv.x) - 1.0);
    float y_4 = ((2.0 * c_4.uv.y) - 1.0);
    float r2_ = ((x_9 * x_9) + (y_4 * y_4));
    float nz = sqrt(max((1.0 - r2_), 0.0));
    vec3 d_9 = vec3(((2.0 * x_9) * nz), ((2.0 * y_4) * nz), (sigma_1 * (1.0 - (2.0 * r2_))));
    return EnvmapDirection((d_9 / vec3(sqrt(dot(d_9, d_9)))), true);
}

EnvmapChartUv envmap_sphere_map_forward(vec3 dir_4) {
    EnvmapChartUv _e2 = envmap_sphere_map_forward_sigma(dir_4, -1.0);
    return _e2;
}

EnvmapDirection envmap_sphere_map_inverse(EnvmapChartUv c_5) {
    EnvmapDirection _e2 = envmap_sphere_map_inverse_sigma(c_5, -1.0);
    return _e2;
}

EnvmapChartUv envmap_sphere_map_gl_forward(vec3 dir_5) {
    EnvmapChartUv _e2 = envmap_sphere_map_forward_sigma(dir_5, 1.0);
    return _e2;
}

EnvmapDirection envmap_sphere_map_gl_inverse(EnvmapChartUv c_6) {
    EnvmapDirection _e2 = envmap_sphere_map_inverse_sigma(c_6, 1.0);
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

EnvmapChartUv envmap_dual_paraboloid_forward(vec3 dir_6) {
    EnvmapDirection _e1 = envmap_normalize_direction(dir_6);
    if (!(_e1.valid)) {
        EnvmapChartUv _e4 = envmap_invalid_chart_uv();
        return _e4;
    }
    vec3 r_5 = _e1.dir;
    bool _e7 = envmap_sign_bit(dir_6.z);
    float den_1 = (1.0 + abs(r_5.z));
    float _e18 = envmap_clamp_unit(((0.5 * (r_5.x / den_1)) + 0.5));
    float _e25 = envmap_clamp_unit(((0.5 * (r_5.y / den_1)) + 0.5));
    return EnvmapChartUv((_e7 ? 1u : 0u), vec2(_e18, _e25));
}

EnvmapDirection envmap_dual_paraboloid_inverse(EnvmapChartUv c_7) {
    bool local_7 = false;
    float z_2 = 0.0;
    if (!((c_7.chart > 1u))) {
        bool _e8 = envmap_in_unit_disk(c_7.uv);
        local_7 = !(_e8);
    } else {
        local_7 = true;
    }
    bool _e11 = local_7;
    if (_e11) {
        EnvmapDirection _e12 = envmap_invalid_direction();
        return _e12;
    }
    float x_10 = ((2.0 * c_7.uv.x) - 1.0);
    float y_5 = ((2.0 * c_7.uv.y) - 1.0);
    float r2_1 = ((x_10 * x_10) + (y_5 * y_5));
    z_2 = max((1.0 - r2_1), 0.0);
    if ((c_7.chart == 1u)) {
        float _e36 = z_2;
        z_2 = -(_e36);
    }
    float _e42 = z_2;
    vec3 d_10 = (vec3((2.0 * x_10), (2.0 * y_5), _e42) / vec3((1.0 + r2_1)));
    return EnvmapDirection((d_10 / vec3(sqrt(dot(d_10, d_10)))), true);
}

EnvmapChartUv envmap_angular_forward(vec3 dir_7) {
    float px = 1.0;
    float py = 0.0;
    EnvmapDirection _e1 = envmap_normalize_direction(dir_7);
    if (!(_e1.valid)) {
        EnvmapChartUv _e4 = envmap_invalid_chart_uv();
        return _e4;
    }
    vec3 r_6 = _e1.dir;
    float a_5 = max(abs(dir_7.x), abs(dir_7.y));
    if ((a_5 != 0.0)) {
        px = (dir_7.x / a_5);
        py = (dir_7.y / a_5);
    }
    float _e21 = px;
    float _e22 = px;
    float _e24 = py;
    float _e25 = py;
    float len = sqrt(((_e21 * _e22) + (_e24 * _e25)));
    float sin_theta = (max(abs(r_6.x), abs(r_6.y)) * len);
    float _e36 = envmap_atan2f(sin_theta, r_6.z);
    float rho_1 = min((_e36 / ENVMAP_PI), 1.0);
    float k_1 = (rho_1 / len);
    float _e42 = px;
    float _e48 = envmap_clamp_unit(((0.5 * (k_1 * _e42)) + 0.5));
    float _e49 = py;
    float _e55 = envmap_clamp_unit(((0.5 * (k_1 * _e49)) + 0.5));
    return EnvmapChartUv(0u, vec2(_e48, _e55));
}

EnvmapDirection envmap_angular_inverse(EnvmapChartUv c_8) {
    bool local_8 = false;
    float s_1 = 0.0;
    float co = 0.0;
    float k = ENVMAP_PI;
    if (!((c_8.chart != 0u))) {
        bool _e8 = envmap_in_unit_disk(c_8.uv);
        local_8 = !(_e8);
    } else {
        local_8 = true;
    }
    bool _e11 = local_8;
    if (_e11) {
        EnvmapDirection _e12 = envmap_invalid_direction();
        return _e12;
    }
    float x_11 = ((2.0 * c_8.uv.x) - 1.0);
    float y_6 = ((2.0 * c_8.uv.y) - 1.0);
    float rho_2 = min(sqrt(((x_11 * x_11) + (y_6 * y_6))), 1.0);
    if ((rho_2 <= 0.5)) {
        s_1 = sin((ENVMAP_PI * rho_2));
        co = cos((ENVMAP_PI * rho_2));
    } else {
        float t_16 = (ENVMAP_PI * (1.0 - rho_2));
        s_1 = sin(t_16);
        co = -(cos(t_16));
    }
    if ((rho_2 > 0.0)) {
        float _e52 = s_1;
        k = (_e52 / rho_2);
    }
    float _e54 = k;
    float _e56 = k;
    float _e58 = co;
    vec3 d_11 = vec3((_e54 * x_11), (_e56 * y_6), _e58);
    return EnvmapDirection((d_11 / vec3(sqrt(dot(d_11, d_11)))), true);
}

bool envmap_tennisball_selects_first_chart(float a_1, float b, float c_9) {
    bool local_9 = false;
    bool local_10 = false;
    bool local_11 = false;
    if ((c_9 >= 0.0)) {
        local_9 = (abs(b) <= ENVMAP_SQRT_HALF);
    } else {
        local_9 = false;
    }
    bool _e11 = local_9;
    if (!(_e11)) {
        if ((c_9 <= 0.0)) {
            local_11 = (abs(a_1) >= ENVMAP_SQRT_HALF);
        } else {
            local_11 = false;
        }
        bool _e23 = local_11;
        local_10 = _e23;
    } else {
        local_10 = true;
    }
    bool _e25 = local_10;
    return _e25;
}

EnvmapChartUv envmap_tennisball_forward(vec3 dir_8) {
    uint chart = 0u;
    float theta = 0.0;
    float phi_1 = 0.0;
    EnvmapDirection _e1 = envmap_normalize_direction(dir_8);
    if (!(_e1.valid)) {
        EnvmapChartUv _e4 = envmap_invalid_chart_uv();
        return _e4;
    }
    float a_6 = _e1.dir.x;
    float b_3 = _e1.dir.y;
    float c_17 = _e1.dir.z;
    bool _e14 = envmap_tennisball_selects_first_chart(a_6, b_3, c_17);
    if (_e14) {
        chart = 0u;
        float _e20 = envmap_atan2f(b_3, sqrt(((a_6 * a_6) + (c_17 * c_17))));
        theta = _e20;
        float _e21 = envmap_atan2f(a_6, c_17);
        phi_1 = _e21;
    } else {
        chart = 1u;
        float _e27 = envmap_atan2f(a_6, sqrt(((b_3 * b_3) + (c_17 * c_17))));
        theta = _e27;
        float _e29 = envmap_atan2f(b_3, -(c_17));
        phi_1 = _e29;
    }
    float _e32 = theta;
    theta = clamp(_e32, -0.7853982, ENVMAP_QUARTER_PI);
    float _e36 = phi_1;
    phi_1 = clamp(_e36, -(2.3561945), 2.3561945);
    float _e39 = phi_1;
    float _e43 = envmap_clamp_unit(((_e39 / 4.712389) + 0.5));
    float _e44 = theta;
    float _e49 = envmap_clamp_unit((0.5 - (_e44 / ENVMAP_HALF_PI)));
    uint _e50 = chart;
    return EnvmapChartUv(_e50, vec2(_e43, _e49));
}

EnvmapDirection envmap_tennisball_inverse(EnvmapChartUv c_10) {
    bool local_12 = false;
    if (!((c_10.chart > 1u))) {
        bool _e8 = envmap_in_unit_square(c_10.uv);
        local_12 = !(_e8);
    } else {
        local_12 = true;
    }
    bool _e11 = local_12;
    if (_e11) {
        EnvmapDirection _e12 = envmap_invalid_direction();
        return _e12;
    }
    float phi_4 = ((c_10.uv.x - 0.5) * 4.712389);
    float theta_3 = ((0.5 - c_10.uv.y) * ENVMAP_HALF_PI);
    float sp = sin(phi_4);
    float cp = cos(phi_4);
    float st_1 = sin(theta_3);
    float ct = cos(theta_3);
    if ((c_10.chart == 0u)) {
        return EnvmapDirection(vec3((ct * sp), st_1, (ct * cp)), true);
    }
    return EnvmapDirection(vec3(st_1, (ct * sp), (-(ct) * cp)), true);
}

EnvmapChartUv envmap_octahedral_to_uv(float x_5, float y_1) {
    float _e7 = envmap_clamp_unit(((0.5 * x_5) + 0.5));
    float _e12 = envmap_clamp_unit(((0.5 * y_1) + 0.5));
    return EnvmapChartUv(0u, vec2(_e7, _e12));
}

EnvmapChartUv envmap_octahedral_forward(vec3 dir_9) {
    EnvmapDirection _e1 = envmap_normalize_direction(dir_9);
    if (!(_e1.valid)) {
        EnvmapChartUv _e4 = envmap_invalid_chart_uv();
        return _e4;
    }
    vec3 d_12 = _e1.dir;
    vec3 p_3 = (d_12 / vec3(((abs(d_12.x) + abs(d_12.y)) + abs(d_12.z))));
    if ((p_3.z < 0.0)) {
        float _e24 = envmap_copysign((1.0 - abs(p_3.y)), dir_9.x);
        float _e30 = envmap_copysign((1.0 - abs(p_3.x)), dir_9.y);
        EnvmapChartUv _e31 = envmap_octahedral_to_uv(_e24, _e30);
        return _e31;
    }
    EnvmapChartUv _e34 = envmap_octahedral_to_uv(p_3.x, p_3.y);
    return _e34;
}

EnvmapDirection envmap_octahedral_inverse(EnvmapChartUv c_11) {
    bool local_13 = false;
    vec3 d_5 = vec3(0.0);
    if (!((c_11.chart != 0u))) {
        bool _e8 = envmap_in_unit_square(c_11.uv);
        local_13 = !(_e8);
    } else {
        local_13 = true;
    }
    bool _e11 = local_13;
    if (_e11) {
        EnvmapDirection _e12 = envmap_invalid_direction();
        return _e12;
    }
    float x_12 = ((2.0 * c_11.uv.x) - 1.0);
    float y_7 = ((2.0 * c_11.uv.y) - 1.0);
    float z_3 = ((1.0 - abs(x_12)) - abs(y_7));
    d_5 = vec3(x_12, y_7, z_3);
    if ((z_3 < 0.0)) {
        float _e37 = envmap_copysign((1.0 - abs(y_7)), x_12);
        float _e41 = envmap_copysign((1.0 - abs(x_12)), y_7);
        d_5 = vec3(_e37, _e41, z_3);
    }
    vec3 _e43 = d_5;
    vec3 _e44 = d_5;
    vec3 _e45 = d_5;
    return EnvmapDirection((_e43 / vec3(sqrt(dot(_e44, _e45)))), true);
}

EnvmapChartUv envmap_equal_area_octahedral_forward(vec3 dir_10) {
    float phi_2 = 0.0;
    float v = 0.0;
    float u_2 = 0.0;
    EnvmapDirection _e1 = envmap_normalize_direction(dir_10);
    if (!(_e1.valid)) {
        EnvmapChartUv _e4 = envmap_invalid_chart_uv();
        return _e4;
    }
    vec3 d_13 = _e1.dir;
    float ax_2 = abs(d_13.x);
    float ay_2 = abs(d_13.y);
    float az_1 = abs(d_13.z);
    float r_7 = sqrt((((ax_2 * ax_2) + (ay_2 * ay_2)) / (1.0 + az_1)));
    float hi = max(ax_2, ay_2);
    float lo = min(ax_2, ay_2);
    if ((hi != 0.0)) {
        float _e26 = envmap_atan_unit((lo / hi));
        phi_2 = (_e26 * ENVMAP_TWO_OVER_PI);
    }
    if ((ax_2 < ay_2)) {
        float _e30 = phi_2;
        phi_2 = (1.0 - _e30);
    }
    float _e33 = phi_2;
    v = (_e33 * r_7);
    float _e36 = v;
    u_2 = (r_7 - _e36);
    if ((d_13.z < 0.0)) {
        float u0_ = u_2;
        float _e43 = v;
        u_2 = (1.0 - _e43);
        v = (1.0 - u0_);
    }
    float _e48 = u_2;
    float _e50 = envmap_copysign(_e48, dir_10.x);
    float _e51 = v;
    float _e53 = envmap_copysign(_e51, dir_10.y);
    EnvmapChartUv _e54 = envmap_octahedral_to_uv(_e50, _e53);
    return _e54;
}

EnvmapDirection envmap_equal_area_octahedral_inverse(EnvmapChartUv c_12) {
    bool local_14 = false;
    float r_1 = 0.0;
    float phi_3 = ENVMAP_QUARTER_PI;
    if (!((c_12.chart != 0u))) {
        bool _e8 = envmap_in_unit_square(c_12.uv);
        local_14 = !(_e8);
    } else {
        local_14 = true;
    }
    bool _e11 = local_14;
    if (_e11) {
        EnvmapDirection _e12 = envmap_invalid_direction();
        return _e12;
    }
    float u_6 = ((2.0 * c_12.uv.x) - 1.0);
    float v_3 = ((2.0 * c_12.uv.y) - 1.0);
    float au = abs(u_6);
    float av = abs(v_3);
    float sum = (au + av);
    float signed_distance = (1.0 - sum);
    r_1 = sum;
    if ((signed_distance < 0.0)) {
        r_1 = (2.0 - sum);
    }
    float _e37 = r_1;
    if ((_e37 != 0.0)) {
        float _e41 = r_1;
        phi_3 = ((((av - au) / _e41) + 1.0) * ENVMAP_QUARTER_PI);
    }
    float _e47 = r_1;
    float _e48 = r_1;
    float _e52 = envmap_copysign((1.0 - (_e47 * _e48)), signed_distance);
    float _e53 = r_1;
    float _e54 = r_1;
    float _e55 = r_1;
    float k_2 = (_e53 * sqrt(max((2.0 - (_e54 * _e55)), 0.0)));
    float _e63 = phi_3;
    float _e65 = envmap_copysign(cos(_e63), u_6);
    float _e67 = phi_3;
    float _e69 = envmap_copysign(sin(_e67), v_3);
    vec3 d_14 = vec3((_e65 * k_2), (_e69 * k_2), _e52);
    return EnvmapDirection((d_14 / vec3(sqrt(dot(d_14, d_14)))), true);
}

float envmap_fisheye_sin(float x_6) {
    float p_1 = -0.0001951829;
    float q = 2.4432327e-5;
    if ((x_6 <= ENVMAP_QUARTER_PI)) {
        float u_7 = (x_6 * x_6);
        float _e6 = p_1;
        p_1 = ((_e6 * u_7) + 0.008332189);
        float _e10 = p_1;
        p_1 = ((_e10 * u_7) - 0.16666655);
        float _e14 = p_1;
        return (x_6 + (x_6 * (u_7 * _e14)));
    }
    float y_8 = ((ENVMAP_HALF_PI - x_6) + ENVMAP_FISHEYE_HALF_PI_LO);
    float u_8 = (y_8 * y_8);
    float _e25 = q;
    q = ((_e25 * u_8) - 0.001388731);
    float _e29 = q;
    q = ((_e29 * u_8) + 0.041666646);
    float half_u = (0.5 * u_8);
    float w_1 = (1.0 - half_u);
    float rest = ((1.0 - w_1) - half_u);
    float _e41 = q;
    return (w_1 + (((u_8 * u_8) * _e41) + rest));
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

EnvmapChartUv envmap_fisheye_forward(vec3 dir_11, float half_fov_1, bool equisolid, bool dual_1) {
    bool local_15 = false;
    float axial = 0.0;
    float side = 1.0;
    bool local_16 = false;
    float r_2 = 0.0;
    float x_7 = 1.0;
    float y_2 = 0.0;
    EnvmapDirection _e4 = envmap_normalize_direction(dir_11);
    if (!(_e4.valid)) {
        EnvmapChartUv _e7 = envmap_invalid_chart_uv();
        return _e7;
    }
    vec3 d_15 = _e4.dir;
    if (dual_1) {
        local_15 = (dir_11.z < 0.0);
    } else {
        local_15 = false;
    }
    bool back = local_15;
    axial = d_15.z;
    if (back) {
        axial = -(d_15.z);
        side = -1.0;
    }
    float rho_3 = sqrt(((d_15.x * d_15.x) + (d_15.y * d_15.y)));
    float _e31 = axial;
    float _e32 = envmap_atan2f(rho_3, _e31);
    bool _e33 = envmap_fisheye_covers_sphere(half_fov_1, dual_1);
    if (!(_e33)) {
        local_16 = (_e32 > (half_fov_1 * ENVMAP_FISHEYE_SEEN_SCALE));
    } else {
        local_16 = false;
    }
    bool _e41 = local_16;
    if (_e41) {
        EnvmapChartUv _e42 = envmap_invalid_chart_uv();
        return _e42;
    }
    if (equisolid) {
        float _e46 = envmap_fisheye_sin((0.5 * _e32));
        float _e49 = envmap_fisheye_sin((0.5 * half_fov_1));
        r_2 = (_e46 / _e49);
    } else {
        r_2 = (_e32 / half_fov_1);
    }
    float _e52 = r_2;
    r_2 = min(_e52, 1.0);
    float a_7 = max(abs(dir_11.x), abs(dir_11.y));
    if ((a_7 != 0.0)) {
        x_7 = (dir_11.x / a_7);
        y_2 = (dir_11.y / a_7);
    }
    float _e70 = r_2;
    float _e73 = x_7;
    float _e74 = x_7;
    float _e76 = y_2;
    float _e77 = y_2;
    float s_10 = ((0.5 * _e70) / sqrt(((_e73 * _e74) + (_e76 * _e77))));
    float _e82 = side;
    float _e84 = x_7;
    float _e88 = envmap_clamp_unit((0.5 + ((_e82 * s_10) * _e84)));
    float _e89 = y_2;
    float _e93 = envmap_clamp_unit((0.5 - (s_10 * _e89)));
    return EnvmapChartUv((back ? 1u : 0u), vec2(_e88, _e93));
}

EnvmapDirection envmap_fisheye_inverse(EnvmapChartUv c_13, float half_fov_2, bool equisolid_1, bool dual_2) {
    bool local_17 = false;
    float side_1 = 1.0;
    float theta_1 = 0.0;
    uint charts = (dual_2 ? 2u : 1u);
    if (!((c_13.chart >= charts))) {
        bool _e13 = envmap_in_unit_disk(c_13.uv);
        local_17 = !(_e13);
    } else {
        local_17 = true;
    }
    bool _e16 = local_17;
    if (_e16) {
        EnvmapDirection _e17 = envmap_invalid_direction();
        return _e17;
    }
    if ((c_13.chart == 1u)) {
        side_1 = -1.0;
    }
    float a_8 = ((2.0 * c_13.uv.x) - 1.0);
    float b_4 = (1.0 - (2.0 * c_13.uv.y));
    float r_8 = min(sqrt(((a_8 * a_8) + (b_4 * b_4))), 1.0);
    if (equisolid_1) {
        float _e45 = envmap_fisheye_sin((0.5 * half_fov_2));
        float _e49 = envmap_fisheye_asin(min((r_8 * _e45), 1.0));
        theta_1 = (2.0 * _e49);
    } else {
        theta_1 = (r_8 * half_fov_2);
    }
    float _e53 = theta_1;
    float t_17 = min(_e53, ENVMAP_PI);
    float sin_t = sin(t_17);
    float cos_t = cos(t_17);
    if ((r_8 == 0.0)) {
        float _e60 = side_1;
        return EnvmapDirection(vec3(0.0, 0.0, _e60), true);
    }
    float s_11 = (sin_t / r_8);
    float _e67 = side_1;
    float _e71 = side_1;
    vec3 d_16 = vec3(((_e67 * s_11) * a_8), (s_11 * b_4), (_e71 * cos_t));
    return EnvmapDirection((d_16 / vec3(sqrt(dot(d_16, d_16)))), true);
}

float[9] envmap_sh9_basis(vec3 n_1) {
    EnvmapDirection _e1 = envmap_normalize_direction(n_1);
    if (!(_e1.valid)) {
        return float[9](0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    }
    float x_13 = _e1.dir.x;
    float y_9 = _e1.dir.y;
    float z_4 = _e1.dir.z;
    return float[9](ENVMAP_SH_Y00_CONSTANT, (ENVMAP_SH_Y1_CONSTANT * y_9), (ENVMAP_SH_Y1_CONSTANT * z_4), (ENVMAP_SH_Y1_CONSTANT * x_13), (ENVMAP_SH_Y2_CONSTANT * (x_13 * y_9)), (ENVMAP_SH_Y2_CONSTANT * (y_9 * z_4)), (ENVMAP_SH_Y20_CONSTANT * (((3.0 * z_4) * z_4) - 1.0)), (ENVMAP_SH_Y2_CONSTANT * (x_13 * z_4)), (ENVMAP_SH_Y22_CONSTANT * ((x_13 * x_13) - (y_9 * y_9))));
}

vec3 envmap_sh9_eval(vec3 c_14[9], vec3 n_2) {
    vec3 e = vec3(0.0);
    uint i = 0u;
    float _e2[9] = envmap_sh9_basis(n_2);
    bool loop_init = true;
    while(true) {
        if (!loop_init) {
            uint _e19 = i;
            i = (_e19 + 1u);
        }
        loop_init = false;
        uint _e8 = i;
        if ((_e8 < 9u)) {
        } else {
            break;
        }
        {
            vec3 _e11 = e;
            uint _e12 = i;
            uint _e14 = i;
            e = (_e11 + (c_14[_e12] * _e2[_e14]));
        }
    }
    vec3 _e21 = e;
    return _e21;
}

vec3 envmap_sh9_irradiance(vec3 radiance[9], vec3 n_3) {
    vec3 band2_ = vec3(0.0);
    uint i_1 = 4u;
    float _e2[9] = envmap_sh9_basis(n_3);
    vec3 band0_ = (radiance[0] * _e2[0]);
    vec3 band1_ = (((radiance[1] * _e2[1]) + (radiance[2] * _e2[2])) + (radiance[3] * _e2[3]));
    bool loop_init_1 = true;
    while(true) {
        if (!loop_init_1) {
            uint _e33 = i_1;
            i_1 = (_e33 + 1u);
        }
        loop_init_1 = false;
        uint _e22 = i_1;
        if ((_e22 < 9u)) {
        } else {
            break;
        }
        {
            vec3 _e25 = band2_;
            uint _e26 = i_1;
            uint _e28 = i_1;
            band2_ = (_e25 + (radiance[_e26] * _e2[_e28]));
        }
    }
    vec3 _e41 = band2_;
    return (((ENVMAP_PI * band0_) + (ENVMAP_SH_A1_FACTOR * band1_)) + (ENVMAP_QUARTER_PI * _e41));
}

vec3 envmap_sh9_irradiance_over_pi(vec3 radiance_1[9], vec3 n_4) {
    vec3 _e2 = envmap_sh9_irradiance(radiance_1, n_4);
    return (_e2 * ENVMAP_INV_PI);
}

vec3 envmap_sh9_filament(vec3 sh[9], vec3 n_5) {
    EnvmapDirection _e2 = envmap_normalize_direction(n_5);
    if (!(_e2.valid)) {
        return vec3(0.0);
    }
    float x_14 = _e2.dir.x;
    float y_10 = _e2.dir.y;
    float z_5 = _e2.dir.z;
    return ((((((((sh[0] + (sh[1] * y_10)) + (sh[2] * z_5)) + (sh[3] * x_14)) + (sh[4] * (y_10 * x_14))) + (sh[5] * (y_10 * z_5))) + (sh[6] * (((3.0 * z_5) * z_5) - 1.0))) + (sh[7] * (z_5 * x_14))) + (sh[8] * ((x_14 * x_14) - (y_10 * y_10))));
}

float envmap_roughness_to_lod_linear(float roughness, float levels) {
    float r_9 = clamp(roughness, 0.0, 1.0);
    return (r_9 * (levels - 1.0));
}

float envmap_roughness_to_lod_filament(float roughness_1, float levels_1) {
    float r_10 = clamp(roughness_1, 0.0, 1.0);
    return ((r_10 * (2.0 - r_10)) * (levels_1 - 1.0));
}

float envmap_roughness_to_lod_unity(float roughness_2, float levels_2) {
    float r_11 = clamp(roughness_2, 0.0, 1.0);
    return ((r_11 * (1.7 - (0.7 * r_11))) * (levels_2 - 1.0));
}

vec3 envmap_reflect_view(vec3 n_6, vec3 v_1) {
    return (((2.0 * dot(n_6, v_1)) * n_6) - v_1);
}

vec3 envmap_reflect_incident(vec3 i_2, vec3 n_7) {
    return (i_2 - ((2.0 * dot(n_7, i_2)) * n_7));
}

vec3 envmap_specular_dominant_direction(vec3 n_8, vec3 r_3, float roughness_3) {
    bool local_18 = false;
    float a_9 = (roughness_3 * roughness_3);
    vec3 d_17 = ((r_3 * (1.0 - a_9)) + (n_8 * a_9));
    float l2_ = dot(d_17, d_17);
    if ((l2_ > 0.0)) {
        bool _e14 = envmap_all_finite(d_17);
        local_18 = _e14;
    } else {
        local_18 = false;
    }
    bool _e16 = local_18;
    if (_e16) {
        return (d_17 * (1.0 / sqrt(l2_)));
    }
    return r_3;
}

vec3 envmap_specular_direction(vec3 n_9, vec3 v_2, float roughness_4, bool dominant) {
    vec3 _e4 = envmap_reflect_view(n_9, v_2);
    if (dominant) {
        vec3 _e8 = envmap_specular_dominant_direction(n_9, _e4, clamp(roughness_4, 0.0, 1.0));
        return _e8;
    }
    return _e4;
}

vec3 envmap_f0_color(vec3 base_color, float metallic, float dielectric_f0_) {
    float m_3 = clamp(metallic, 0.0, 1.0);
    return (vec3((dielectric_f0_ * (1.0 - m_3))) + (clamp(base_color, vec3(0.0), vec3(1.0)) * m_3));
}

vec3 envmap_diffuse_color(vec3 base_color_1, float metallic_1) {
    float m_4 = clamp(metallic_1, 0.0, 1.0);
    return (clamp(base_color_1, vec3(0.0), vec3(1.0)) * (1.0 - m_4));
}

vec3 envmap_split_sum_factor(vec3 f0_, vec2 dfg, bool multiscatter) {
    vec3 s_2 = vec3(0.0);
    bool local_19 = false;
    s_2 = ((f0_ * dfg.x) + vec3(dfg.y));
    float albedo = (dfg.x + dfg.y);
    if (multiscatter) {
        local_19 = (albedo > 0.0);
    } else {
        local_19 = false;
    }
    bool _e17 = local_19;
    if (_e17) {
        vec3 _e18 = s_2;
        s_2 = (_e18 * (vec3(1.0) + (f0_ * ((1.0 / albedo) - 1.0))));
    }
    vec3 _e28 = s_2;
    return _e28;
}

vec3 envmap_split_sum_factor_filament(vec3 f0_1, vec2 dfg_1, bool multiscatter_1) {
    vec3 s_3 = vec3(0.0);
    bool local_20 = false;
    s_3 = mix(vec3(dfg_1.x), vec3(dfg_1.y), f0_1);
    if (multiscatter_1) {
        local_20 = (dfg_1.y > 0.0);
    } else {
        local_20 = false;
    }
    bool _e15 = local_20;
    if (_e15) {
        vec3 _e16 = s_3;
        s_3 = (_e16 * (vec3(1.0) + (f0_1 * ((1.0 / dfg_1.y) - 1.0))));
    }
    vec3 _e27 = s_3;
    return _e27;
}

vec3 envmap_split_sum(vec3 diffuse, vec3 f0_2, vec3 e_over_pi, vec3 ld, vec2 dfg_2, bool multiscatter_2) {
    vec3 _e7 = envmap_split_sum_factor(f0_2, dfg_2, multiscatter_2);
    return ((diffuse * e_over_pi) + (ld * _e7));
}

vec2 envmap_dfg_uv(float n_dot_v, float roughness_5) {
    return vec2(clamp(n_dot_v, 0.0001, 1.0), clamp(roughness_5, 0.0, 1.0));
}

vec2 envmap_dfg_load(sampler2D t, float n_dot_v_1, float roughness_6) {
    vec2 _e3 = envmap_dfg_uv(n_dot_v_1, roughness_6);
    vec2 size_2 = vec2(uvec2(textureSize(t, 0).xy));
    vec2 x_15 = clamp(((_e3 * size_2) - vec2(0.5)), vec2(0.0), (size_2 - vec2(1.0)));
    ivec2 i0_ = ivec2(floor(x_15));
    ivec2 i1_ = min((i0_ + ivec2(1)), (ivec2(size_2) - ivec2(1)));
    vec2 f = (x_15 - floor(x_15));
    vec4 _e33 = texelFetch(t, ivec2(i0_.x, i0_.y), 0);
    vec2 a_10 = _e33.xy;
    vec4 _e39 = texelFetch(t, ivec2(i1_.x, i0_.y), 0);
    vec2 b_5 = _e39.xy;
    vec4 _e45 = texelFetch(t, ivec2(i0_.x, i1_.y), 0);
    vec2 c_18 = _e45.xy;
    vec4 _e51 = texelFetch(t, ivec2(i1_.x, i1_.y), 0);
    vec2 d_18 = _e51.xy;
    vec2 top = (a_10 + (f.x * (b_5 - a_10)));
    vec2 bottom = (c_18 + (f.x * (d_18 - c_18)));
    return (top + (f.y * (bottom - top)));
}

EnvmapFootprint envmap_bilinear_footprint(float u_3, int n_10) {
    float x_16 = clamp(((u_3 * float(n_10)) - 0.5), -0.5, (float(n_10) - 0.5));
    float t_18 = floor(x_16);
    return EnvmapFootprint(int(t_18), (int(t_18) + 1), (x_16 - t_18));
}

vec3 envmap_blend(vec3 a_2, vec3 b_1, vec3 c_15, vec3 d_6, float fx, float fy) {
    vec3 left = (((c_15 - a_2) * fy) + a_2);
    vec3 right = (((d_6 - b_1) * fy) + b_1);
    return (((right - left) * fx) + left);
}

vec3 envmap_latlong_texel(sampler2D t_1, int i_3, int j, int level) {
    int ii = 0;
    int jj = 0;
    bool local_21 = false;
    ivec2 size_3 = ivec2(uvec2(textureSize(t_1, level).xy));
    ii = i_3;
    jj = j;
    int _e8 = jj;
    if (!((_e8 < 0))) {
        int _e14 = jj;
        local_21 = (_e14 >= size_3.y);
    } else {
        local_21 = true;
    }
    bool _e18 = local_21;
    if (_e18) {
        int _e24 = jj;
        int _e26 = jj;
        int _e29 = jj;
        jj = ((_e29 < 0) ? (-1 - _e26) : (((2 * size_3.y) - 1) - _e24));
        int _e33 = ii;
        ii = (_e33 + (size_3.x / 2));
    }
    int _e38 = ii;
    if ((_e38 < 0)) {
        int _e41 = ii;
        ii = (_e41 + size_3.x);
    }
    int _e44 = ii;
    if ((_e44 >= size_3.x)) {
        int _e47 = ii;
        ii = (_e47 - size_3.x);
    }
    int _e50 = jj;
    jj = min(max(_e50, 0), (size_3.y - 1));
    int _e56 = ii;
    int _e57 = jj;
    vec4 _e59 = texelFetch(t_1, ivec2(_e56, _e57), level);
    return _e59.xyz;
}

vec3 envmap_latlong_bilinear(sampler2D t_2, vec2 uv_2, int level_1) {
    ivec2 size_4 = ivec2(uvec2(textureSize(t_2, level_1).xy));
    EnvmapFootprint _e7 = envmap_bilinear_footprint(uv_2.x, size_4.x);
    EnvmapFootprint _e10 = envmap_bilinear_footprint(uv_2.y, size_4.y);
    vec3 _e13 = envmap_latlong_texel(t_2, _e7.first, _e10.first, level_1);
    vec3 _e16 = envmap_latlong_texel(t_2, _e7.second, _e10.first, level_1);
    vec3 _e19 = envmap_latlong_texel(t_2, _e7.first, _e10.second, level_1);
    vec3 _e22 = envmap_latlong_texel(t_2, _e7.second, _e10.second, level_1);
    vec3 _e25 = envmap_blend(_e13, _e16, _e19, _e22, _e7.f, _e10.f);
    return _e25;
}

vec3 envmap_octahedral_texel(sampler2D t_3, int i_4, int j_1, int level_2) {
    int ii_1 = 0;
    int jj_1 = 0;
    bool local_22 = false;
    bool local_23 = false;
    ivec2 size_5 = ivec2(uvec2(textureSize(t_3, level_2).xy));
    ii_1 = i_4;
    jj_1 = j_1;
    int _e8 = jj_1;
    if (!((_e8 < 0))) {
        int _e14 = jj_1;
        local_22 = (_e14 >= size_5.y);
    } else {
        local_22 = true;
    }
    bool _e18 = local_22;
    if (_e18) {
        int _e24 = jj_1;
        int _e26 = jj_1;
        int _e29 = jj_1;
        jj_1 = ((_e29 < 0) ? (-1 - _e26) : (((2 * size_5.y) - 1) - _e24));
        int _e36 = ii_1;
        ii_1 = ((size_5.x - 1) - _e36);
    }
    int _e38 = ii_1;
    if (!((_e38 < 0))) {
        int _e44 = ii_1;
        local_23 = (_e44 >= size_5.x);
    } else {
        local_23 = true;
    }
    bool _e48 = local_23;
    if (_e48) {
        int _e54 = ii_1;
        int _e56 = ii_1;
        int _e59 = ii_1;
        ii_1 = ((_e59 < 0) ? (-1 - _e56) : (((2 * size_5.x) - 1) - _e54));
        int _e66 = jj_1;
        jj_1 = ((size_5.y - 1) - _e66);
    }
    int _e68 = ii_1;
    int _e74 = jj_1;
    vec4 _e81 = texelFetch(t_3, ivec2(min(max(_e68, 0), (size_5.x - 1)), min(max(_e74, 0), (size_5.y - 1))), level_2);
    return _e81.xyz;
}

vec3 envmap_octahedral_bilinear(sampler2D t_4, vec2 uv_3, int level_3) {
    ivec2 size_6 = ivec2(uvec2(textureSize(t_4, level_3).xy));
    EnvmapFootprint _e7 = envmap_bilinear_footprint(uv_3.x, size_6.x);
    EnvmapFootprint _e10 = envmap_bilinear_footprint(uv_3.y, size_6.y);
    vec3 _e13 = envmap_octahedral_texel(t_4, _e7.first, _e10.first, level_3);
    vec3 _e16 = envmap_octahedral_texel(t_4, _e7.second, _e10.first, level_3);
    vec3 _e19 = envmap_octahedral_texel(t_4, _e7.first, _e10.second, level_3);
    vec3 _e22 = envmap_octahedral_texel(t_4, _e7.second, _e10.second, level_3);
    vec3 _e25 = envmap_blend(_e13, _e16, _e19, _e22, _e7.f, _e10.f);
    return _e25;
}

int envmap_texel_index(float u_4, int n_11) {
    return min(int((u_4 * float(n_11))), (n_11 - 1));
}

vec3 envmap_cube_texel_across(sampler2DArray t_5, uint face_1, int i_5, int j_2, int level_4) {
    ivec2 size_7 = ivec2(uvec2(textureSize(t_5, level_4).xy));
    float sc_1 = ((2.0 * ((float(i_5) + 0.5) / float(size_7.x))) - 1.0);
    float tc_1 = ((2.0 * ((float(j_2) + 0.5) / float(size_7.y))) - 1.0);
    vec3 _e27 = envmap_cube_face_direction(face_1, sc_1, tc_1);
    EnvmapChartUv _e28 = envmap_cube_forward(_e27);
    int _e32 = envmap_texel_index(_e28.uv.x, size_7.x);
    int _e36 = envmap_texel_index(_e28.uv.y, size_7.y);
    ivec2 k_3 = ivec2(_e32, _e36);
    vec4 _e40 = texelFetch(t_5, ivec3(k_3, int(_e28.chart)), level_4);
    return _e40.xyz;
}

vec3 envmap_cube_texel(sampler2DArray t_6, uint face_2, int i_6, int j_3, int level_5) {
    bool local_24 = false;
    bool local_25 = false;
    bool local_26 = false;
    bool local_27 = false;
    ivec2 size_8 = ivec2(uvec2(textureSize(t_6, level_5).xy));
    if (!((i_6 < 0))) {
        local_24 = (i_6 >= size_8.x);
    } else {
        local_24 = true;
    }
    bool iout = local_24;
    if (!((j_3 < 0))) {
        local_25 = (j_3 >= size_8.y);
    } else {
        local_25 = true;
    }
    bool jout = local_25;
    int ic = min(max(i_6, 0), (size_8.x - 1));
    int jc = min(max(j_3, 0), (size_8.y - 1));
    if (iout) {
        local_26 = jout;
    } else {
        local_26 = false;
    }
    bool _e38 = local_26;
    if (_e38) {
        vec3 _e39 = envmap_cube_texel_across(t_6, face_2, i_6, jc, level_5);
        vec3 _e40 = envmap_cube_texel_across(t_6, face_2, ic, j_3, level_5);
        vec4 _e43 = texelFetch(t_6, ivec3(ivec2(ic, jc), int(face_2)), level_5);
        vec3 c_19 = _e43.xyz;
        return (((_e39 + _e40) + c_19) / vec3(3.0));
    }
    if (!(iout)) {
        local_27 = jout;
    } else {
        local_27 = true;
    }
    bool _e54 = local_27;
    if (_e54) {
        vec3 _e55 = envmap_cube_texel_across(t_6, face_2, i_6, j_3, level_5);
        return _e55;
    }
    vec4 _e58 = texelFetch(t_6, ivec3(ivec2(i_6, j_3), int(face_2)), level_5);
    return _e58.xyz;
}

vec3 envmap_cube_bilinear(sampler2DArray t_7, EnvmapChartUv c_16, int level_6) {
    ivec2 size_9 = ivec2(uvec2(textureSize(t_7, level_6).xy));
    EnvmapFootprint _e8 = envmap_bilinear_footprint(c_16.uv.x, size_9.x);
    EnvmapFootprint _e12 = envmap_bilinear_footprint(c_16.uv.y, size_9.y);
    vec3 _e16 = envmap_cube_texel(t_7, c_16.chart, _e8.first, _e12.first, level_6);
    vec3 _e20 = envmap_cube_texel(t_7, c_16.chart, _e8.second, _e12.first, level_6);
    vec3 _e24 = envmap_cube_texel(t_7, c_16.chart, _e8.first, _e12.second, level_6);
    vec3 _e28 = envmap_cube_texel(t_7, c_16.chart, _e8.second, _e12.second, level_6);
    vec3 _e31 = envmap_blend(_e16, _e20, _e24, _e28, _e8.f, _e12.f);
    return _e31;
}

EnvmapLevels envmap_levels(float lod, int levels_3) {
    float l = clamp(lod, 0.0, float((levels_3 - 1)));
    int k_4 = min(int(floor(l)), (levels_3 - 1));
    if (((k_4 + 1) >= levels_3)) {
        return EnvmapLevels(k_4, 0.0);
    }
    return EnvmapLevels(k_4, (l - float(k_4)));
}

vec3 envmap_latlong_chain(sampler2D t_8, int levels_4, vec3 dir_12, float lod_1) {
    EnvmapChartUv _e4 = envmap_latlong_forward(dir_12);
    if ((_e4.chart == ENVMAP_INVALID_CHART)) {
        return vec3(0.0);
    }
    EnvmapLevels _e10 = envmap_levels(lod_1, levels_4);
    vec3 _e13 = envmap_latlong_bilinear(t_8, _e4.uv, _e10.level);
    if ((_e10.blend > 0.0)) {
        vec3 _e21 = envmap_latlong_bilinear(t_8, _e4.uv, (_e10.level + 1));
        return (_e13 + ((_e21 - _e13) * _e10.blend));
    }
    return _e13;
}

vec3 envmap_octahedral_chain(sampler2D t_9, int levels_5, vec3 dir_13, float lod_2) {
    EnvmapChartUv _e4 = envmap_octahedral_forward(dir_13);
    if ((_e4.chart == ENVMAP_INVALID_CHART)) {
        return vec3(0.0);
    }
    EnvmapLevels _e10 = envmap_levels(lod_2, levels_5);
    vec3 _e13 = envmap_octahedral_bilinear(t_9, _e4.uv, _e10.level);
    if ((_e10.blend > 0.0)) {
        vec3 _e21 = envmap_octahedral_bilinear(t_9, _e4.uv, (_e10.level + 1));
        return (_e13 + ((_e21 - _e13) * _e10.blend));
    }
    return _e13;
}

vec3 envmap_equal_area_octahedral_chain(sampler2D t_10, int levels_6, vec3 dir_14, float lod_3) {
    EnvmapChartUv _e4 = envmap_equal_area_octahedral_forward(dir_14);
    if ((_e4.chart == ENVMAP_INVALID_CHART)) {
        return vec3(0.0);
    }
    EnvmapLevels _e10 = envmap_levels(lod_3, levels_6);
    vec3 _e13 = envmap_octahedral_bilinear(t_10, _e4.uv, _e10.level);
    if ((_e10.blend > 0.0)) {
        vec3 _e21 = envmap_octahedral_bilinear(t_10, _e4.uv, (_e10.level + 1));
        return (_e13 + ((_e21 - _e13) * _e10.blend));
    }
    return _e13;
}

vec3 envmap_cube_chain(sampler2DArray t_11, int levels_7, vec3 dir_15, float lod_4) {
    EnvmapChartUv _e4 = envmap_cube_forward(dir_15);
    if ((_e4.chart == ENVMAP_INVALID_CHART)) {
        return vec3(0.0);
    }
    EnvmapLevels _e10 = envmap_levels(lod_4, levels_7);
    vec3 _e12 = envmap_cube_bilinear(t_11, _e4, _e10.level);
    if ((_e10.blend > 0.0)) {
        vec3 _e19 = envmap_cube_bilinear(t_11, _e4, (_e10.level + 1));
        return (_e12 + ((_e19 - _e12) * _e10.blend));
    }
    return _e12;
}

float envmap_direction_footprint(vec3 d_7, vec3 ddx, vec3 ddy) {
    float l2_1 = dot(d_7, d_7);
    return (max(length(cross(d_7, ddx)), length(cross(d_7, ddy))) / l2_1);
}

float envmap_latlong_lod(float angle, float height) {
    return max(log2(((angle * height) / ENVMAP_PI)), 0.0);
}

float envmap_octahedral_lod(vec3 dir_16, float angle_1, float size) {
    vec3 a_11 = abs(dir_16);
    float p_4 = (length(dir_16) / ((a_11.x + a_11.y) + a_11.z));
    float texel = (2.0 / ((size * p_4) * sqrt(p_4)));
    return max(log2((angle_1 / texel)), 0.0);
}

float envmap_equal_area_octahedral_lod(float angle_2, float size_1) {
    return max(log2(((angle_2 * size_1) / 3.5449078)), 0.0);
}

vec4 envmap_latlong_sample_level(sampler2D t_12, vec3 dir_17, float lod_5) {
    EnvmapChartUv _e4 = envmap_latlong_forward(dir_17);
    vec4 _e6 = textureLod(t_12, vec2(_e4.uv), lod_5);
    return _e6;
}

vec4 envmap_octahedral_sample_level(sampler2D t_13, vec3 dir_18, float lod_6) {
    EnvmapChartUv _e4 = envmap_octahedral_forward(dir_18);
    vec4 _e6 = textureLod(t_13, vec2(_e4.uv), lod_6);
    return _e6;
}

vec4 envmap_equal_area_octahedral_sample_level(sampler2D t_14, vec3 dir_19, float lod_7) {
    EnvmapChartUv _e4 = envmap_equal_area_octahedral_forward(dir_19);
    vec4 _e6 = textureLod(t_14, vec2(_e4.uv), lod_7);
    return _e6;
}
