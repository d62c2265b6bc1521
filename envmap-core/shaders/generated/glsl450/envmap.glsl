// envmap shaders, GLSL 4.50: envmap (from common.wgsl, frame.wgsl, latlong.wgsl, cube.wgsl, sphere_map.wgsl, dual_paraboloid.wgsl, angular.wgsl, tennisball.wgsl, octahedral.wgsl, lighting.wgsl).
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
    vec3 s_2 = (d_1 / vec3(m));
    return EnvmapDirection((s_2 / vec3(sqrt(dot(s_2, s_2)))), true);
}

float envmap_atan_unit(float z) {
    float p = 0.0029193612;
    float u_2 = (z * z);
    float _e4 = p;
    p = ((_e4 * u_2) - 0.016363012);
    float _e8 = p;
    p = ((_e8 * u_2) + 0.04320454);
    float _e12 = p;
    p = ((_e12 * u_2) - 0.075516514);
    float _e16 = p;
    p = ((_e16 * u_2) + 0.10665768);
    float _e20 = p;
    p = ((_e20 * u_2) - 0.14211002);
    float _e24 = p;
    p = ((_e24 * u_2) + 0.19993767);
    float _e28 = p;
    p = ((_e28 * u_2) - 0.33333153);
    float _e32 = p;
    return (z + (z * (u_2 * _e32)));
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

EnvmapChartUv envmap_latlong_forward(vec3 dir) {
    float u = 0.0;
    EnvmapDirection _e1 = envmap_normalize_direction(dir);
    if (!(_e1.valid)) {
        EnvmapChartUv _e4 = envmap_invalid_chart_uv();
        return _e4;
    }
    vec3 d_6 = _e1.dir;
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
    float rho = sqrt(((d_6.x * d_6.x) + (d_6.y * d_6.y)));
    float _e33 = envmap_atan2f(rho, d_6.z);
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
    float theta_1 = (ENVMAP_PI * c.uv.y);
    float st = sin(theta_1);
    float _e33 = phi;
    float _e36 = phi;
    return EnvmapDirection(vec3((st * cos(_e33)), (st * sin(_e36)), cos(theta_1)), true);
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
    float s_3 = (0.5 * ((_e1.sc / _e1.ma) + 1.0));
    float t = (0.5 * ((_e1.tc / _e1.ma) + 1.0));
    return EnvmapChartUv(_e1.face, vec2(s_3, t));
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

EnvmapChartUv envmap_sphere_map_forward_sigma(vec3 dir_2, float sigma) {
    float one_plus_w = 0.0;
    EnvmapDirection _e2 = envmap_normalize_direction(dir_2);
    if (!(_e2.valid)) {
        EnvmapChartUv _e5 = envmap_invalid_chart_uv();
        return _e5;
    }
    vec3 r_2 = _e2.dir;
    float w = (sigma * r_2.z);
    if ((w < 0.0)) {
        one_plus_w = (((r_2.x * r_2.x) + (r_2.y * r_2.y)) / (1.0 - w));
    } else {
        one_plus_w = (1.0 + w);
    }
    float _e29 = one_plus_w;
    float s_4 = max(max(abs(r_2.x), abs(r_2.y)), _e29);
    if ((s_4 == 0.0)) {
        return EnvmapChartUv(0u, vec2(1.0, 0.5));
    }
    float x_6 = (r_2.x / s_4);
    float y_2 = (r_2.y / s_4);
    float _e42 = one_plus_w;
    float h = (_e42 / s_4);
    float m_2 = sqrt((((x_6 * x_6) + (y_2 * y_2)) + (h * h)));
    float _e55 = envmap_clamp_unit(((0.5 * (x_6 / m_2)) + 0.5));
    float _e61 = envmap_clamp_unit(((0.5 * (y_2 / m_2)) + 0.5));
    return EnvmapChartUv(0u, vec2(_e55, _e61));
}

EnvmapDirection envmap_sphere_map_inverse_sigma(EnvmapChartUv c_2, float sigma_1) {
    bool local_5 = false;
    if (!((c_2.chart != 0u))) {
        bool _e9 = envmap_in_unit_disk(c_2.uv);
        local_5 = !(_e9);
    } else {
        local_5 = true;
    }
    bool _e12 = local_5;
    if (_e12) {
        EnvmapDirection _e13 = envmap_invalid_direction();
        return _e13;
    }
    float x_7 = ((2.0 * c_2.uv.x) - 1.0);
    float y_3 = ((2.0 * c_2.uv.y) - 1.0);
    float r2_ = ((x_7 * x_7) + (y_3 * y_3));
    float nz = sqrt(max((1.0 - r2_), 0.0));
    vec3 d_7 = vec3(((2.0 * x_7) * nz), ((2.0 * y_3) * nz), (sigma_1 * (1.0 - (2.0 * r2_))));
    return EnvmapDirection((d_7 / vec3(sqrt(dot(d_7, d_7)))), true);
}

EnvmapChartUv envmap_sphere_map_forward(vec3 dir_3) {
    EnvmapChartUv _e2 = envmap_sphere_map_forward_sigma(dir_3, -1.0);
    return _e2;
}

EnvmapDirection envmap_sphere_map_inverse(EnvmapChartUv c_3) {
    EnvmapDirection _e2 = envmap_sphere_map_inverse_sigma(c_3, -1.0);
    return _e2;
}

EnvmapChartUv envmap_sphere_map_gl_forward(vec3 dir_4) {
    EnvmapChartUv _e2 = envmap_sphere_map_forward_sigma(dir_4, 1.0);
    return _e2;
}

EnvmapDirection envmap_sphere_map_gl_inverse(EnvmapChartUv c_4) {
    EnvmapDirection _e2 = envmap_sphere_map_inverse_sigma(c_4, 1.0);
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

EnvmapChartUv envmap_dual_paraboloid_forward(vec3 dir_5) {
    EnvmapDirection _e1 = envmap_normalize_direction(dir_5);
    if (!(_e1.valid)) {
        EnvmapChartUv _e4 = envmap_invalid_chart_uv();
        return _e4;
    }
    vec3 r_3 = _e1.dir;
    bool _e7 = envmap_sign_bit(dir_5.z);
    float den_1 = (1.0 + abs(r_3.z));
    float _e18 = envmap_clamp_unit(((0.5 * (r_3.x / den_1)) + 0.5));
    float _e25 = envmap_clamp_unit(((0.5 * (r_3.y / den_1)) + 0.5));
    return EnvmapChartUv((_e7 ? 1u : 0u), vec2(_e18, _e25));
}

EnvmapDirection envmap_dual_paraboloid_inverse(EnvmapChartUv c_5) {
    bool local_6 = false;
    float z_2 = 0.0;
    if (!((c_5.chart > 1u))) {
        bool _e8 = envmap_in_unit_disk(c_5.uv);
        local_6 = !(_e8);
    } else {
        local_6 = true;
    }
    bool _e11 = local_6;
    if (_e11) {
        EnvmapDirection _e12 = envmap_invalid_direction();
        return _e12;
    }
    float x_8 = ((2.0 * c_5.uv.x) - 1.0);
    float y_4 = ((2.0 * c_5.uv.y) - 1.0);
    float r2_1 = ((x_8 * x_8) + (y_4 * y_4));
    z_2 = max((1.0 - r2_1), 0.0);
    if ((c_5.chart == 1u)) {
        float _e36 = z_2;
        z_2 = -(_e36);
    }
    float _e42 = z_2;
    vec3 d_8 = (vec3((2.0 * x_8), (2.0 * y_4), _e42) / vec3((1.0 + r2_1)));
    return EnvmapDirection((d_8 / vec3(sqrt(dot(d_8, d_8)))), true);
}

EnvmapChartUv envmap_angular_forward(vec3 dir_6) {
    float px = 1.0;
    float py = 0.0;
    EnvmapDirection _e1 = envmap_normalize_direction(dir_6);
    if (!(_e1.valid)) {
        EnvmapChartUv _e4 = envmap_invalid_chart_uv();
        return _e4;
    }
    vec3 r_4 = _e1.dir;
    float a_4 = max(abs(dir_6.x), abs(dir_6.y));
    if ((a_4 != 0.0)) {
        px = (dir_6.x / a_4);
        py = (dir_6.y / a_4);
    }
    float _e21 = px;
    float _e22 = px;
    float _e24 = py;
    float _e25 = py;
    float len = sqrt(((_e21 * _e22) + (_e24 * _e25)));
    float sin_theta = (max(abs(r_4.x), abs(r_4.y)) * len);
    float _e36 = envmap_atan2f(sin_theta, r_4.z);
    float rho_1 = min((_e36 / ENVMAP_PI), 1.0);
    float k_1 = (rho_1 / len);
    float _e42 = px;
    float _e48 = envmap_clamp_unit(((0.5 * (k_1 * _e42)) + 0.5));
    float _e49 = py;
    float _e55 = envmap_clamp_unit(((0.5 * (k_1 * _e49)) + 0.5));
    return EnvmapChartUv(0u, vec2(_e48, _e55));
}

EnvmapDirection envmap_angular_inverse(EnvmapChartUv c_6) {
    bool local_7 = false;
    float s_1 = 0.0;
    float co = 0.0;
    float k = ENVMAP_PI;
    if (!((c_6.chart != 0u))) {
        bool _e8 = envmap_in_unit_disk(c_6.uv);
        local_7 = !(_e8);
    } else {
        local_7 = true;
    }
    bool _e11 = local_7;
    if (_e11) {
        EnvmapDirection _e12 = envmap_invalid_direction();
        return _e12;
    }
    float x_9 = ((2.0 * c_6.uv.x) - 1.0);
    float y_5 = ((2.0 * c_6.uv.y) - 1.0);
    float rho_2 = min(sqrt(((x_9 * x_9) + (y_5 * y_5))), 1.0);
    if ((rho_2 <= 0.5)) {
        s_1 = sin((ENVMAP_PI * rho_2));
        co = cos((ENVMAP_PI * rho_2));
    } else {
        float t_1 = (ENVMAP_PI * (1.0 - rho_2));
        s_1 = sin(t_1);
        co = -(cos(t_1));
    }
    if ((rho_2 > 0.0)) {
        float _e52 = s_1;
        k = (_e52 / rho_2);
    }
    float _e54 = k;
    float _e56 = k;
    float _e58 = co;
    vec3 d_9 = vec3((_e54 * x_9), (_e56 * y_5), _e58);
    return EnvmapDirection((d_9 / vec3(sqrt(dot(d_9, d_9)))), true);
}

bool envmap_tennisball_selects_first_chart(float a_1, float b, float c_7) {
    bool local_8 = false;
    bool local_9 = false;
    bool local_10 = false;
    if ((c_7 >= 0.0)) {
        local_8 = (abs(b) <= ENVMAP_SQRT_HALF);
    } else {
        local_8 = false;
    }
    bool _e11 = local_8;
    if (!(_e11)) {
        if ((c_7 <= 0.0)) {
            local_10 = (abs(a_1) >= ENVMAP_SQRT_HALF);
        } else {
            local_10 = false;
        }
        bool _e23 = local_10;
        local_9 = _e23;
    } else {
        local_9 = true;
    }
    bool _e25 = local_9;
    return _e25;
}

EnvmapChartUv envmap_tennisball_forward(vec3 dir_7) {
    uint chart = 0u;
    float theta = 0.0;
    float phi_1 = 0.0;
    EnvmapDirection _e1 = envmap_normalize_direction(dir_7);
    if (!(_e1.valid)) {
        EnvmapChartUv _e4 = envmap_invalid_chart_uv();
        return _e4;
    }
    float a_5 = _e1.dir.x;
    float b_2 = _e1.dir.y;
    float c_11 = _e1.dir.z;
    bool _e14 = envmap_tennisball_selects_first_chart(a_5, b_2, c_11);
    if (_e14) {
        chart = 0u;
        float _e20 = envmap_atan2f(b_2, sqrt(((a_5 * a_5) + (c_11 * c_11))));
        theta = _e20;
        float _e21 = envmap_atan2f(a_5, c_11);
        phi_1 = _e21;
    } else {
        chart = 1u;
        float _e27 = envmap_atan2f(a_5, sqrt(((b_2 * b_2) + (c_11 * c_11))));
        theta = _e27;
        float _e29 = envmap_atan2f(b_2, -(c_11));
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

EnvmapDirection envmap_tennisball_inverse(EnvmapChartUv c_8) {
    bool local_11 = false;
    if (!((c_8.chart > 1u))) {
        bool _e8 = envmap_in_unit_square(c_8.uv);
        local_11 = !(_e8);
    } else {
        local_11 = true;
    }
    bool _e11 = local_11;
    if (_e11) {
        EnvmapDirection _e12 = envmap_invalid_direction();
        return _e12;
    }
    float phi_4 = ((c_8.uv.x - 0.5) * 4.712389);
    float theta_2 = ((0.5 - c_8.uv.y) * ENVMAP_HALF_PI);
    float sp = sin(phi_4);
    float cp = cos(phi_4);
    float st_1 = sin(theta_2);
    float ct = cos(theta_2);
    if ((c_8.chart == 0u)) {
        return EnvmapDirection(vec3((ct * sp), st_1, (ct * cp)), true);
    }
    return EnvmapDirection(vec3(st_1, (ct * sp), (-(ct) * cp)), true);
}

EnvmapChartUv envmap_octahedral_to_uv(float x_5, float y_1) {
    float _e7 = envmap_clamp_unit(((0.5 * x_5) + 0.5));
    float _e12 = envmap_clamp_unit(((0.5 * y_1) + 0.5));
    return EnvmapChartUv(0u, vec2(_e7, _e12));
}

EnvmapChartUv envmap_octahedral_forward(vec3 dir_8) {
    EnvmapDirection _e1 = envmap_normalize_direction(dir_8);
    if (!(_e1.valid)) {
        EnvmapChartUv _e4 = envmap_invalid_chart_uv();
        return _e4;
    }
    vec3 d_10 = _e1.dir;
    vec3 p_2 = (d_10 / vec3(((abs(d_10.x) + abs(d_10.y)) + abs(d_10.z))));
    if ((p_2.z < 0.0)) {
        float _e24 = envmap_copysign((1.0 - abs(p_2.y)), dir_8.x);
        float _e30 = envmap_copysign((1.0 - abs(p_2.x)), dir_8.y);
        EnvmapChartUv _e31 = envmap_octahedral_to_uv(_e24, _e30);
        return _e31;
    }
    EnvmapChartUv _e34 = envmap_octahedral_to_uv(p_2.x, p_2.y);
    return _e34;
}

EnvmapDirection envmap_octahedral_inverse(EnvmapChartUv c_9) {
    bool local_12 = false;
    vec3 d_5 = vec3(0.0);
    if (!((c_9.chart != 0u))) {
        bool _e8 = envmap_in_unit_square(c_9.uv);
        local_12 = !(_e8);
    } else {
        local_12 = true;
    }
    bool _e11 = local_12;
    if (_e11) {
        EnvmapDirection _e12 = envmap_invalid_direction();
        return _e12;
    }
    float x_10 = ((2.0 * c_9.uv.x) - 1.0);
    float y_6 = ((2.0 * c_9.uv.y) - 1.0);
    float z_3 = ((1.0 - abs(x_10)) - abs(y_6));
    d_5 = vec3(x_10, y_6, z_3);
    if ((z_3 < 0.0)) {
        float _e37 = envmap_copysign((1.0 - abs(y_6)), x_10);
        float _e41 = envmap_copysign((1.0 - abs(x_10)), y_6);
        d_5 = vec3(_e37, _e41, z_3);
    }
    vec3 _e43 = d_5;
    vec3 _e44 = d_5;
    vec3 _e45 = d_5;
    return EnvmapDirection((_e43 / vec3(sqrt(dot(_e44, _e45)))), true);
}

EnvmapChartUv envmap_equal_area_octahedral_forward(vec3 dir_9) {
    float phi_2 = 0.0;
    float v = 0.0;
    float u_1 = 0.0;
    EnvmapDirection _e1 = envmap_normalize_direction(dir_9);
    if (!(_e1.valid)) {
        EnvmapChartUv _e4 = envmap_invalid_chart_uv();
        return _e4;
    }
    vec3 d_11 = _e1.dir;
    float ax_2 = abs(d_11.x);
    float ay_2 = abs(d_11.y);
    float az_1 = abs(d_11.z);
    float r_5 = sqrt((((ax_2 * ax_2) + (ay_2 * ay_2)) / (1.0 + az_1)));
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
    v = (_e33 * r_5);
    float _e36 = v;
    u_1 = (r_5 - _e36);
    if ((d_11.z < 0.0)) {
        float u0_ = u_1;
        float _e43 = v;
        u_1 = (1.0 - _e43);
        v = (1.0 - u0_);
    }
    float _e48 = u_1;
    float _e50 = envmap_copysign(_e48, dir_9.x);
    float _e51 = v;
    float _e53 = envmap_copysign(_e51, dir_9.y);
    EnvmapChartUv _e54 = envmap_octahedral_to_uv(_e50, _e53);
    return _e54;
}

EnvmapDirection envmap_equal_area_octahedral_inverse(EnvmapChartUv c_10) {
    bool local_13 = false;
    float r_1 = 0.0;
    float phi_3 = ENVMAP_QUARTER_PI;
    if (!((c_10.chart != 0u))) {
        bool _e8 = envmap_in_unit_square(c_10.uv);
        local_13 = !(_e8);
    } else {
        local_13 = true;
    }
    bool _e11 = local_13;
    if (_e11) {
        EnvmapDirection _e12 = envmap_invalid_direction();
        return _e12;
    }
    float u_3 = ((2.0 * c_10.uv.x) - 1.0);
    float v_1 = ((2.0 * c_10.uv.y) - 1.0);
    float au = abs(u_3);
    float av = abs(v_1);
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
    float _e65 = envmap_copysign(cos(_e63), u_3);
    float _e67 = phi_3;
    float _e69 = envmap_copysign(sin(_e67), v_1);
    vec3 d_12 = vec3((_e65 * k_2), (_e69 * k_2), _e52);
    return EnvmapDirection((d_12 / vec3(sqrt(dot(d_12, d_12)))), true);
}
