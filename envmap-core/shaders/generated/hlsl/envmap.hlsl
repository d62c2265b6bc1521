// envmap shaders, HLSL (shader model 5.0): envmap (from common.wgsl, frame.wgsl, latlong.wgsl, cube.wgsl, eac.wgsl, sphere_map.wgsl, dual_paraboloid.wgsl, angular.wgsl, tennisball.wgsl, octahedral.wgsl, fisheye.wgsl, lighting.wgsl).
// Written by naga 29.0.4 from the WGSL in envmap-core/shaders/ (the source, with every
// formula, source and comment): do not edit; after changing the WGSL run
// ENVMAP_BLESS_SHADERS=1 cargo test --release -p envmap-tests --test shader_sources
// A library: no #version line and no entry point (docs/shaders.md).
struct EnvmapChartUv {
    uint chart;
    int _pad1_0;
    float2 uv;
};

struct EnvmapDirection {
    float3 dir;
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

static const uint ENVMAP_INVALID_CHART = 4294967295u;
static const float ENVMAP_PI = 3.1415927;
static const float ENVMAP_TAU = 6.2831855;
static const float ENVMAP_HALF_PI = 1.5707964;
static const float ENVMAP_QUARTER_PI = 0.7853982;
static const float ENVMAP_SQRT_HALF = 0.70710677;
static const float ENVMAP_TWO_OVER_PI = 0.63661975;
static const float ENVMAP_DISK_LIMIT = 1.0000005;
static const float3x3 ENVMAP_FRAME_Z_UP_RH = float3x3(float3(1.0, 0.0, 0.0), float3(0.0, 1.0, 0.0), float3(0.0, 0.0, 1.0));
static const float3x3 ENVMAP_FRAME_Y_UP_RH = float3x3(float3(1.0, 0.0, 0.0), float3(0.0, 0.0, 1.0), float3(0.0, -1.0, 0.0));
static const float3x3 ENVMAP_FRAME_Y_UP_LH = float3x3(float3(1.0, 0.0, 0.0), float3(0.0, 0.0, 1.0), float3(0.0, 1.0, 0.0));
static const float ENVMAP_FISHEYE_SEEN_SCALE = 1.0000005;
static const float ENVMAP_FISHEYE_HALF_PI_LO = -4.371139e-8;
static const float ENVMAP_SH_Y00_CONSTANT = 0.2820948;
static const float ENVMAP_SH_Y1_CONSTANT = 0.48860252;
static const float ENVMAP_SH_Y2_CONSTANT = 1.0925485;
static const float ENVMAP_SH_Y20_CONSTANT = 0.31539157;
static const float ENVMAP_SH_Y22_CONSTANT = 0.54627424;
static const float ENVMAP_SH_A1_FACTOR = 2.0943952;
static const float ENVMAP_INV_PI = 0.31830987;

EnvmapChartUv ConstructEnvmapChartUv(uint arg0, float2 arg1) {
    EnvmapChartUv ret = (EnvmapChartUv)0;
    ret.chart = arg0;
    ret.uv = arg1;
    return ret;
}

EnvmapChartUv envmap_invalid_chart_uv()
{
    const EnvmapChartUv envmapchartuv = ConstructEnvmapChartUv(4294967295u, float2(0.0, 0.0));
    return envmapchartuv;
}

EnvmapDirection ConstructEnvmapDirection(float3 arg0, bool arg1) {
    EnvmapDirection ret = (EnvmapDirection)0;
    ret.dir = arg0;
    ret.valid = arg1;
    return ret;
}

EnvmapDirection envmap_invalid_direction()
{
    const EnvmapDirection envmapdirection = ConstructEnvmapDirection(float3(0.0, 0.0, 0.0), false);
    return envmapdirection;
}

bool envmap_sign_bit(float x)
{
    return ((asuint(x) & 2147483648u) != 0u);
}

float envmap_copysign(float x_1, float s)
{
    return asfloat(((asuint(x_1) & 2147483647u) | (asuint(s) & 2147483648u)));
}

bool envmap_all_finite(float3 d)
{
    uint3 e_1 = (asuint(d) & (2139095040u).xxx);
    return all((e_1 != (2139095040u).xxx));
}

bool envmap_in_unit_interval(float x_2)
{
    bool local = (bool)0;

    uint b_2 = asuint(x_2);
    if (!((b_2 <= 1065353216u))) {
        local = (b_2 == 2147483648u);
    } else {
        local = true;
    }
    bool _e10 = local;
    return _e10;
}

bool envmap_in_unit_square(float2 uv)
{
    bool local_1 = (bool)0;

    const bool _e2 = envmap_in_unit_interval(uv.x);
    if (_e2) {
        const bool _e6 = envmap_in_unit_interval(uv.y);
        local_1 = _e6;
    } else {
        local_1 = false;
    }
    bool _e8 = local_1;
    return _e8;
}

bool envmap_in_unit_disk(float2 uv_1)
{
    const bool _e1 = envmap_in_unit_square(uv_1);
    if (!(_e1)) {
        return false;
    }
    float2 p_2 = ((2.0 * uv_1) - (1.0).xx);
    return (((p_2.x * p_2.x) + (p_2.y * p_2.y)) <= ENVMAP_DISK_LIMIT);
}

float envmap_clamp_unit(float x_3)
{
    return clamp(x_3, 0.0, 1.0);
}

EnvmapDirection envmap_normalize_direction(float3 d_1)
{
    const bool _e1 = envmap_all_finite(d_1);
    if (!(_e1)) {
        const EnvmapDirection _e3 = envmap_invalid_direction();
        const EnvmapDirection envmapdirection_1 = _e3;
        return envmapdirection_1;
    }
    float3 a_3 = abs(d_1);
    float m = max(max(a_3.x, a_3.y), a_3.z);
    if ((m == 0.0)) {
        const EnvmapDirection _e12 = envmap_invalid_direction();
        const EnvmapDirection envmapdirection_2 = _e12;
        return envmapdirection_2;
    }
    float3 s_7 = (d_1 / (m).xxx);
    const EnvmapDirection envmapdirection_3 = ConstructEnvmapDirection((s_7 / (sqrt(dot(s_7, s_7))).xxx), true);
    return envmapdirection_3;
}

float envmap_atan_unit(float z)
{
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

float envmap_atan2f(float y, float x_4)
{
    float z_1 = 0.0;
    float a = (float)0;

    float ax = abs(x_4);
    float ay = abs(y);
    bool swap = (ay > ax);
    float num = (swap ? ax : ay);
    float den = (swap ? ay : ax);
    if ((den > 0.0)) {
        z_1 = (num / den);
    }
    float _e12 = z_1;
    const float _e13 = envmap_atan_unit(_e12);
    const bool _e14 = envmap_sign_bit(x_4);
    if (swap) {
        a = (_e14 ? (ENVMAP_HALF_PI + _e13) : (ENVMAP_HALF_PI - _e13));
    } else {
        a = (_e14 ? (ENVMAP_PI - _e13) : _e13);
    }
    float _e24 = a;
    const float _e25 = envmap_copysign(_e24, y);
    return _e25;
}

float3 envmap_frame_to_canonical(float3x3 frame, float3 d_2)
{
    const bool _e2 = envmap_all_finite(d_2);
    if (!(_e2)) {
        return d_2;
    }
    float3 a_4 = abs(d_2);
    float m_1 = max(max(a_4.x, a_4.y), a_4.z);
    if ((m_1 == 0.0)) {
        return d_2;
    }
    return mul((d_2 / (m_1).xxx), frame);
}

EnvmapDirection envmap_frame_from_canonical(float3x3 frame_1, EnvmapDirection d_3)
{
    const EnvmapDirection envmapdirection_4 = ConstructEnvmapDirection(mul(d_3.dir, transpose(frame_1)), d_3.valid);
    return envmapdirection_4;
}

EnvmapChartUv envmap_latlong_forward(float3 dir)
{
    float u = (float)0;

    const EnvmapDirection _e1 = envmap_normalize_direction(dir);
    if (!(_e1.valid)) {
        const EnvmapChartUv _e4 = envmap_invalid_chart_uv();
        const EnvmapChartUv envmapchartuv_1 = _e4;
        return envmapchartuv_1;
    }
    float3 d_8 = _e1.dir;
    const float _e8 = envmap_atan2f(dir.y, dir.x);
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
    const float _e33 = envmap_atan2f(rho, d_8.z);
    const float _e36 = envmap_clamp_unit((_e33 / ENVMAP_PI));
    float _e38 = u;
    const EnvmapChartUv envmapchartuv_2 = ConstructEnvmapChartUv(0u, float2(_e38, _e36));
    return envmapchartuv_2;
}

EnvmapDirection envmap_latlong_inverse(EnvmapChartUv c)
{
    bool local_2 = (bool)0;
    float phi = (float)0;

    if (!((c.chart != 0u))) {
        const bool _e8 = envmap_in_unit_square(c.uv);
        local_2 = !(_e8);
    } else {
        local_2 = true;
    }
    bool _e11 = local_2;
    if (_e11) {
        const EnvmapDirection _e12 = envmap_invalid_direction();
        const EnvmapDirection envmapdirection_5 = _e12;
        return envmapdirection_5;
    }
    phi = (ENVMAP_TAU * c.uv.x);
    if ((c.uv.x > 0.5)) {
        phi = (ENVMAP_TAU * (c.uv.x - 1.0));
    }
    float theta_2 = (ENVMAP_PI * c.uv.y);
    float st = sin(theta_2);
    float _e33 = phi;
    float _e36 = phi;
    const EnvmapDirection envmapdirection_6 = ConstructEnvmapDirection(float3((st * cos(_e33)), (st * sin(_e36)), cos(theta_2)), true);
    return envmapdirection_6;
}

EnvmapCubeFace ConstructEnvmapCubeFace(uint arg0, float arg1, float arg2, float arg3) {
    EnvmapCubeFace ret = (EnvmapCubeFace)0;
    ret.face = arg0;
    ret.sc = arg1;
    ret.tc = arg2;
    ret.ma = arg3;
    return ret;
}

EnvmapCubeFace envmap_cube_select_face(float3 d_4)
{
    EnvmapCubeFace r = (EnvmapCubeFace)0;
    bool local_3 = (bool)0;

    const bool _e1 = envmap_all_finite(d_4);
    if (!(_e1)) {
        const EnvmapCubeFace envmapcubeface = ConstructEnvmapCubeFace(4294967295u, 0.0, 0.0, 0.0);
        return envmapcubeface;
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
        const bool _e22 = envmap_sign_bit(d_4.z);
        if (_e22) {
            r = ConstructEnvmapCubeFace(5u, -(d_4.x), -(d_4.y), az);
        } else {
            r = ConstructEnvmapCubeFace(4u, d_4.x, -(d_4.y), az);
        }
    } else {
        if ((ay_1 >= ax_1)) {
            const bool _e36 = envmap_sign_bit(d_4.y);
            if (_e36) {
                r = ConstructEnvmapCubeFace(3u, d_4.x, -(d_4.z), ay_1);
            } else {
                r = ConstructEnvmapCubeFace(2u, d_4.x, d_4.z, ay_1);
            }
        } else {
            const bool _e47 = envmap_sign_bit(d_4.x);
            if (_e47) {
                r = ConstructEnvmapCubeFace(1u, d_4.z, -(d_4.y), ax_1);
            } else {
                r = ConstructEnvmapCubeFace(0u, -(d_4.z), -(d_4.y), ax_1);
            }
        }
    }
    float _e60 = r.ma;
    if ((_e60 == 0.0)) {
        const EnvmapCubeFace envmapcubeface_1 = ConstructEnvmapCubeFace(4294967295u, 0.0, 0.0, 0.0);
        return envmapcubeface_1;
    }
    EnvmapCubeFace _e68 = r;
    const EnvmapCubeFace envmapcubeface_2 = _e68;
    return envmapcubeface_2;
}

float3 envmap_cube_face_direction(uint face, float sc, float tc)
{
    switch(face) {
        case 0u: {
            return float3(1.0, -(tc), -(sc));
        }
        case 1u: {
            return float3(-1.0, -(tc), sc);
        }
        case 2u: {
            return float3(sc, 1.0, tc);
        }
        case 3u: {
            return float3(sc, -1.0, -(tc));
        }
        case 4u: {
            return float3(sc, -(tc), 1.0);
        }
        case 5u: {
            return float3(-(sc), -(tc), -1.0);
        }
        default: {
            return float3(0.0, 0.0, 0.0);
        }
    }
}

EnvmapChartUv envmap_cube_forward(float3 dir_1)
{
    const EnvmapCubeFace _e1 = envmap_cube_select_face(dir_1);
    if ((_e1.face == ENVMAP_INVALID_CHART)) {
        const EnvmapChartUv _e5 = envmap_invalid_chart_uv();
        const EnvmapChartUv envmapchartuv_3 = _e5;
        return envmapchartuv_3;
    }
    float s_8 = (0.5 * ((_e1.sc / _e1.ma) + 1.0));
    float t_15 = (0.5 * ((_e1.tc / _e1.ma) + 1.0));
    const EnvmapChartUv envmapchartuv_4 = ConstructEnvmapChartUv(_e1.face, float2(s_8, t_15));
    return envmapchartuv_4;
}

EnvmapDirection envmap_cube_inverse(EnvmapChartUv c_1)
{
    bool local_4 = (bool)0;

    if (!((c_1.chart > 5u))) {
        const bool _e8 = envmap_in_unit_square(c_1.uv);
        local_4 = !(_e8);
    } else {
        local_4 = true;
    }
    bool _e11 = local_4;
    if (_e11) {
        const EnvmapDirection _e12 = envmap_invalid_direction();
        const EnvmapDirection envmapdirection_7 = _e12;
        return envmapdirection_7;
    }
    const float3 _e26 = envmap_cube_face_direction(c_1.chart, ((2.0 * c_1.uv.x) - 1.0), ((2.0 * c_1.uv.y) - 1.0));
    const EnvmapDirection envmapdirection_8 = ConstructEnvmapDirection((_e26 / (sqrt(dot(_e26, _e26))).xxx), true);
    return envmapdirection_8;
}

float envmap_eac_atan(float c_2)
{
    const float _e2 = envmap_atan_unit(abs(c_2));
    const float _e3 = envmap_copysign(_e2, c_2);
    return _e3;
}

float envmap_eac_angle(float u_1)
{
    return (ENVMAP_QUARTER_PI * ((2.0 * u_1) - 1.0));
}

EnvmapChartUv envmap_eac_forward(float3 dir_2)
{
    const EnvmapCubeFace _e1 = envmap_cube_select_face(dir_2);
    if ((_e1.face == ENVMAP_INVALID_CHART)) {
        const EnvmapChartUv _e5 = envmap_invalid_chart_uv();
        const EnvmapChartUv envmapchartuv_5 = _e5;
        return envmapchartuv_5;
    }
    const float _e10 = envmap_eac_atan((_e1.sc / _e1.ma));
    const float _e14 = envmap_clamp_unit((0.5 + (ENVMAP_TWO_OVER_PI * _e10)));
    const float _e19 = envmap_eac_atan((_e1.tc / _e1.ma));
    const float _e23 = envmap_clamp_unit((0.5 + (ENVMAP_TWO_OVER_PI * _e19)));
    const EnvmapChartUv envmapchartuv_6 = ConstructEnvmapChartUv(_e1.face, float2(_e14, _e23));
    return envmapchartuv_6;
}

EnvmapDirection envmap_eac_inverse(EnvmapChartUv c_3)
{
    bool local_5 = (bool)0;

    if (!((c_3.chart > 5u))) {
        const bool _e8 = envmap_in_unit_square(c_3.uv);
        local_5 = !(_e8);
    } else {
        local_5 = true;
    }
    bool _e11 = local_5;
    if (_e11) {
        const EnvmapDirection _e12 = envmap_invalid_direction();
        const EnvmapDirection envmapdirection_9 = _e12;
        return envmapdirection_9;
    }
    const float _e16 = envmap_eac_angle(c_3.uv.x);
    const float _e20 = envmap_eac_angle(c_3.uv.y);
    const float3 _e22 = envmap_cube_face_direction(c_3.chart, tan(_e16), tan(_e20));
    const EnvmapDirection envmapdirection_10 = ConstructEnvmapDirection((_e22 / (sqrt(dot(_e22, _e22))).xxx), true);
    return envmapdirection_10;
}

EnvmapChartUv envmap_sphere_map_forward_sigma(float3 dir_3, float sigma)
{
    float one_plus_w = (float)0;

    const EnvmapDirection _e2 = envmap_normalize_direction(dir_3);
    if (!(_e2.valid)) {
        const EnvmapChartUv _e5 = envmap_invalid_chart_uv();
        const EnvmapChartUv envmapchartuv_7 = _e5;
        return envmapchartuv_7;
    }
    float3 r_4 = _e2.dir;
    float w = (sigma * r_4.z);
    if ((w < 0.0)) {
        one_plus_w = (((r_4.x * r_4.x) + (r_4.y * r_4.y)) / (1.0 - w));
    } else {
        one_plus_w = (1.0 + w);
    }
    float _e29 = one_plus_w;
    float s_9 = max(max(abs(r_4.x), abs(r_4.y)), _e29);
    if ((s_9 == 0.0)) {
        const EnvmapChartUv envmapchartuv_8 = ConstructEnvmapChartUv(0u, float2(1.0, 0.5));
        return envmapchartuv_8;
    }
    float x_8 = (r_4.x / s_9);
    float y_3 = (r_4.y / s_9);
    float _e42 = one_plus_w;
    float h = (_e42 / s_9);
    float m_2 = sqrt((((x_8 * x_8) + (y_3 * y_3)) + (h * h)));
    const float _e55 = envmap_clamp_unit(((0.5 * (x_8 / m_2)) + 0.5));
    const float _e61 = envmap_clamp_unit(((0.5 * (y_3 / m_2)) + 0.5));
    const EnvmapChartUv envmapchartuv_9 = ConstructEnvmapChartUv(0u, float2(_e55, _e61));
    return envmapchartuv_9;
}

EnvmapDirection envmap_sphere_map_inverse_sigma(EnvmapChartUv c_4, float sigma_1)
{
    bool local_6 = (bool)0;

    if (!((c_4.chart != 0u))) {
        const bool _e9 = envmap_in_unit_disk(c_4.uv);
        local_6 = !(_e9);
    } else {
        local_6 = true;
    }
    bool _e12 = local_6;
    if (_e12) {
        const EnvmapDirection _e13 = envmap_invalid_direction();
        const EnvmapDirection envmapdirection_11 = _e13;
        return envmapdirection_11;
    }
    float x_9 = ((2.0 * c_4.uv.x) - 1.0);
    float y_4 = ((2.0 * c_4.uv.y) - 1.0);
    float r2_ = ((x_9 * x_9) + (y_4 * y_4));
    float nz = sqrt(max((1.0 - r2_), 0.0));
    float3 d_9 = float3(((2.0 * x_9) * nz), ((2.0 * y_4) * nz), (sigma_1 * (1.0 - (2.0 * r2_))));
    const EnvmapDirection envmapdirection_12 = ConstructEnvmapDirection((d_9 / (sqrt(dot(d_9, d_9))).xxx), true);
    return envmapdirection_12;
}

EnvmapChartUv envmap_sphere_map_forward(float3 dir_4)
{
    const EnvmapChartUv _e2 = envmap_sphere_map_forward_sigma(dir_4, -1.0);
    const EnvmapChartUv envmapchartuv_10 = _e2;
    return envmapchartuv_10;
}

EnvmapDirection envmap_sphere_map_inverse(EnvmapChartUv c_5)
{
    const EnvmapDirection _e2 = envmap_sphere_map_inverse_sigma(c_5, -1.0);
    const EnvmapDirection envmapdirection_13 = _e2;
    return envmapdirection_13;
}

EnvmapChartUv envmap_sphere_map_gl_forward(float3 dir_5)
{
    const EnvmapChartUv _e2 = envmap_sphere_map_forward_sigma(dir_5, 1.0);
    const EnvmapChartUv envmapchartuv_11 = _e2;
    return envmapchartuv_11;
}

EnvmapDirection envmap_sphere_map_gl_inverse(EnvmapChartUv c_6)
{
    const EnvmapDirection _e2 = envmap_sphere_map_inverse_sigma(c_6, 1.0);
    const EnvmapDirection envmapdirection_14 = _e2;
    return envmapdirection_14;
}

EnvmapChartUv envmap_sphere_map_uv_from_normal(float3 n)
{
    const EnvmapDirection _e1 = envmap_normalize_direction(n);
    if (!(_e1.valid)) {
        const EnvmapChartUv _e4 = envmap_invalid_chart_uv();
        const EnvmapChartUv envmapchartuv_12 = _e4;
        return envmapchartuv_12;
    }
    const float _e12 = envmap_clamp_unit(((0.5 * _e1.dir.x) + 0.5));
    const float _e19 = envmap_clamp_unit(((0.5 * _e1.dir.y) + 0.5));
    const EnvmapChartUv envmapchartuv_13 = ConstructEnvmapChartUv(0u, float2(_e12, _e19));
    return envmapchartuv_13;
}

EnvmapChartUv envmap_dual_paraboloid_forward(float3 dir_6)
{
    const EnvmapDirection _e1 = envmap_normalize_direction(dir_6);
    if (!(_e1.valid)) {
        const EnvmapChartUv _e4 = envmap_invalid_chart_uv();
        const EnvmapChartUv envmapchartuv_14 = _e4;
        return envmapchartuv_14;
    }
    float3 r_5 = _e1.dir;
    const bool _e7 = envmap_sign_bit(dir_6.z);
    float den_1 = (1.0 + abs(r_5.z));
    const float _e18 = envmap_clamp_unit(((0.5 * (r_5.x / den_1)) + 0.5));
    const float _e25 = envmap_clamp_unit(((0.5 * (r_5.y / den_1)) + 0.5));
    const EnvmapChartUv envmapchartuv_15 = ConstructEnvmapChartUv((_e7 ? 1u : 0u), float2(_e18, _e25));
    return envmapchartuv_15;
}

EnvmapDirection envmap_dual_paraboloid_inverse(EnvmapChartUv c_7)
{
    bool local_7 = (bool)0;
    float z_2 = (float)0;

    if (!((c_7.chart > 1u))) {
        const bool _e8 = envmap_in_unit_disk(c_7.uv);
        local_7 = !(_e8);
    } else {
        local_7 = true;
    }
    bool _e11 = local_7;
    if (_e11) {
        const EnvmapDirection _e12 = envmap_invalid_direction();
        const EnvmapDirection envmapdirection_15 = _e12;
        return envmapdirection_15;
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
    float3 d_10 = (float3((2.0 * x_10), (2.0 * y_5), _e42) / ((1.0 + r2_1)).xxx);
    const EnvmapDirection envmapdirection_16 = ConstructEnvmapDirection((d_10 / (sqrt(dot(d_10, d_10))).xxx), true);
    return envmapdirection_16;
}

EnvmapChartUv envmap_angular_forward(float3 dir_7)
{
    float px = 1.0;
    float py = 0.0;

    const EnvmapDirection _e1 = envmap_normalize_direction(dir_7);
    if (!(_e1.valid)) {
        const EnvmapChartUv _e4 = envmap_invalid_chart_uv();
        const EnvmapChartUv envmapchartuv_16 = _e4;
        return envmapchartuv_16;
    }
    float3 r_6 = _e1.dir;
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
    const float _e36 = envmap_atan2f(sin_theta, r_6.z);
    float rho_1 = min((_e36 / ENVMAP_PI), 1.0);
    float k_1 = (rho_1 / len);
    float _e42 = px;
    const float _e48 = envmap_clamp_unit(((0.5 * (k_1 * _e42)) + 0.5));
    float _e49 = py;
    const float _e55 = envmap_clamp_unit(((0.5 * (k_1 * _e49)) + 0.5));
    const EnvmapChartUv envmapchartuv_17 = ConstructEnvmapChartUv(0u, float2(_e48, _e55));
    return envmapchartuv_17;
}

EnvmapDirection envmap_angular_inverse(EnvmapChartUv c_8)
{
    bool local_8 = (bool)0;
    float s_1 = (float)0;
    float co = (float)0;
    float k = ENVMAP_PI;

    if (!((c_8.chart != 0u))) {
        const bool _e8 = envmap_in_unit_disk(c_8.uv);
        local_8 = !(_e8);
    } else {
        local_8 = true;
    }
    bool _e11 = local_8;
    if (_e11) {
        const EnvmapDirection _e12 = envmap_invalid_direction();
        const EnvmapDirection envmapdirection_17 = _e12;
        return envmapdirection_17;
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
    float3 d_11 = float3((_e54 * x_11), (_e56 * y_6), _e58);
    const EnvmapDirection envmapdirection_18 = ConstructEnvmapDirection((d_11 / (sqrt(dot(d_11, d_11))).xxx), true);
    return envmapdirection_18;
}

bool envmap_tennisball_selects_first_chart(float a_1, float b, float c_9)
{
    bool local_9 = (bool)0;
    bool local_10 = (bool)0;
    bool local_11 = (bool)0;

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

EnvmapChartUv envmap_tennisball_forward(float3 dir_8)
{
    uint chart = (uint)0;
    float theta = (float)0;
    float phi_1 = (float)0;

    const EnvmapDirection _e1 = envmap_normalize_direction(dir_8);
    if (!(_e1.valid)) {
        const EnvmapChartUv _e4 = envmap_invalid_chart_uv();
        const EnvmapChartUv envmapchartuv_18 = _e4;
        return envmapchartuv_18;
    }
    float a_6 = _e1.dir.x;
    float b_3 = _e1.dir.y;
    float c_17 = _e1.dir.z;
    const bool _e14 = envmap_tennisball_selects_first_chart(a_6, b_3, c_17);
    if (_e14) {
        chart = 0u;
        const float _e20 = envmap_atan2f(b_3, sqrt(((a_6 * a_6) + (c_17 * c_17))));
        theta = _e20;
        const float _e21 = envmap_atan2f(a_6, c_17);
        phi_1 = _e21;
    } else {
        chart = 1u;
        const float _e27 = envmap_atan2f(a_6, sqrt(((b_3 * b_3) + (c_17 * c_17))));
        theta = _e27;
        const float _e29 = envmap_atan2f(b_3, -(c_17));
        phi_1 = _e29;
    }
    float _e32 = theta;
    theta = clamp(_e32, -0.7853982, ENVMAP_QUARTER_PI);
    float _e36 = phi_1;
    phi_1 = clamp(_e36, -(2.3561945), 2.3561945);
    float _e39 = phi_1;
    const float _e43 = envmap_clamp_unit(((_e39 / 4.712389) + 0.5));
    float _e44 = theta;
    const float _e49 = envmap_clamp_unit((0.5 - (_e44 / ENVMAP_HALF_PI)));
    uint _e50 = chart;
    const EnvmapChartUv envmapchartuv_19 = ConstructEnvmapChartUv(_e50, float2(_e43, _e49));
    return envmapchartuv_19;
}

EnvmapDirection envmap_tennisball_inverse(EnvmapChartUv c_10)
{
    bool local_12 = (bool)0;

    if (!((c_10.chart > 1u))) {
        const bool _e8 = envmap_in_unit_square(c_10.uv);
        local_12 = !(_e8);
    } else {
        local_12 = true;
    }
    bool _e11 = local_12;
    if (_e11) {
        const EnvmapDirection _e12 = envmap_invalid_direction();
        const EnvmapDirection envmapdirection_19 = _e12;
        return envmapdirection_19;
    }
    float phi_4 = ((c_10.uv.x - 0.5) * 4.712389);
    float theta_3 = ((0.5 - c_10.uv.y) * ENVMAP_HALF_PI);
    float sp = sin(phi_4);
    float cp = cos(phi_4);
    float st_1 = sin(theta_3);
    float ct = cos(theta_3);
    if ((c_10.chart == 0u)) {
        const EnvmapDirection envmapdirection_20 = ConstructEnvmapDirection(float3((ct * sp), st_1, (ct * cp)), true);
        return envmapdirection_20;
    }
    const EnvmapDirection envmapdirection_21 = ConstructEnvmapDirection(float3(st_1, (ct * sp), (-(ct) * cp)), true);
    return envmapdirection_21;
}

EnvmapChartUv envmap_octahedral_to_uv(float x_5, float y_1)
{
    const float _e7 = envmap_clamp_unit(((0.5 * x_5) + 0.5));
    const float _e12 = envmap_clamp_unit(((0.5 * y_1) + 0.5));
    const EnvmapChartUv envmapchartuv_20 = ConstructEnvmapChartUv(0u, float2(_e7, _e12));
    return envmapchartuv_20;
}

EnvmapChartUv envmap_octahedral_forward(float3 dir_9)
{
    const EnvmapDirection _e1 = envmap_normalize_direction(dir_9);
    if (!(_e1.valid)) {
        const EnvmapChartUv _e4 = envmap_invalid_chart_uv();
        const EnvmapChartUv envmapchartuv_21 = _e4;
        return envmapchartuv_21;
    }
    float3 d_12 = _e1.dir;
    float3 p_3 = (d_12 / (((abs(d_12.x) + abs(d_12.y)) + abs(d_12.z))).xxx);
    if ((p_3.z < 0.0)) {
        const float _e24 = envmap_copysign((1.0 - abs(p_3.y)), dir_9.x);
        const float _e30 = envmap_copysign((1.0 - abs(p_3.x)), dir_9.y);
        const EnvmapChartUv _e31 = envmap_octahedral_to_uv(_e24, _e30);
        const EnvmapChartUv envmapchartuv_22 = _e31;
        return envmapchartuv_22;
    }
    const EnvmapChartUv _e34 = envmap_octahedral_to_uv(p_3.x, p_3.y);
    const EnvmapChartUv envmapchartuv_23 = _e34;
    return envmapchartuv_23;
}

EnvmapDirection envmap_octahedral_inverse(EnvmapChartUv c_11)
{
    bool local_13 = (bool)0;
    float3 d_5 = (float3)0;

    if (!((c_11.chart != 0u))) {
        const bool _e8 = envmap_in_unit_square(c_11.uv);
        local_13 = !(_e8);
    } else {
        local_13 = true;
    }
    bool _e11 = local_13;
    if (_e11) {
        const EnvmapDirection _e12 = envmap_invalid_direction();
        const EnvmapDirection envmapdirection_22 = _e12;
        return envmapdirection_22;
    }
    float x_12 = ((2.0 * c_11.uv.x) - 1.0);
    float y_7 = ((2.0 * c_11.uv.y) - 1.0);
    float z_3 = ((1.0 - abs(x_12)) - abs(y_7));
    d_5 = float3(x_12, y_7, z_3);
    if ((z_3 < 0.0)) {
        const float _e37 = envmap_copysign((1.0 - abs(y_7)), x_12);
        const float _e41 = envmap_copysign((1.0 - abs(x_12)), y_7);
        d_5 = float3(_e37, _e41, z_3);
    }
    float3 _e43 = d_5;
    float3 _e44 = d_5;
    float3 _e45 = d_5;
    const EnvmapDirection envmapdirection_23 = ConstructEnvmapDirection((_e43 / (sqrt(dot(_e44, _e45))).xxx), true);
    return envmapdirection_23;
}

EnvmapChartUv envmap_equal_area_octahedral_forward(float3 dir_10)
{
    float phi_2 = 0.0;
    float v = (float)0;
    float u_2 = (float)0;

    const EnvmapDirection _e1 = envmap_normalize_direction(dir_10);
    if (!(_e1.valid)) {
        const EnvmapChartUv _e4 = envmap_invalid_chart_uv();
        const EnvmapChartUv envmapchartuv_24 = _e4;
        return envmapchartuv_24;
    }
    float3 d_13 = _e1.dir;
    float ax_2 = abs(d_13.x);
    float ay_2 = abs(d_13.y);
    float az_1 = abs(d_13.z);
    float r_7 = sqrt((((ax_2 * ax_2) + (ay_2 * ay_2)) / (1.0 + az_1)));
    float hi = max(ax_2, ay_2);
    float lo = min(ax_2, ay_2);
    if ((hi != 0.0)) {
        const float _e26 = envmap_atan_unit((lo / hi));
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
    const float _e50 = envmap_copysign(_e48, dir_10.x);
    float _e51 = v;
    const float _e53 = envmap_copysign(_e51, dir_10.y);
    const EnvmapChartUv _e54 = envmap_octahedral_to_uv(_e50, _e53);
    const EnvmapChartUv envmapchartuv_25 = _e54;
    return envmapchartuv_25;
}

EnvmapDirection envmap_equal_area_octahedral_inverse(EnvmapChartUv c_12)
{
    bool local_14 = (bool)0;
    float r_1 = (float)0;
    float phi_3 = ENVMAP_QUARTER_PI;

    if (!((c_12.chart != 0u))) {
        const bool _e8 = envmap_in_unit_square(c_12.uv);
        local_14 = !(_e8);
    } else {
        local_14 = true;
    }
    bool _e11 = local_14;
    if (_e11) {
        const EnvmapDirection _e12 = envmap_invalid_direction();
        const EnvmapDirection envmapdirection_24 = _e12;
        return envmapdirection_24;
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
    const float _e52 = envmap_copysign((1.0 - (_e47 * _e48)), signed_distance);
    float _e53 = r_1;
    float _e54 = r_1;
    float _e55 = r_1;
    float k_2 = (_e53 * sqrt(max((2.0 - (_e54 * _e55)), 0.0)));
    float _e63 = phi_3;
    const float _e65 = envmap_copysign(cos(_e63), u_6);
    float _e67 = phi_3;
    const float _e69 = envmap_copysign(sin(_e67), v_3);
    float3 d_14 = float3((_e65 * k_2), (_e69 * k_2), _e52);
    const EnvmapDirection envmapdirection_25 = ConstructEnvmapDirection((d_14 / (sqrt(dot(d_14, d_14))).xxx), true);
    return envmapdirection_25;
}

float envmap_fisheye_sin(float x_6)
{
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

float envmap_fisheye_asin(float q_1)
{
    const float _e7 = envmap_atan2f(q_1, sqrt(((1.0 - q_1) * (1.0 + q_1))));
    return _e7;
}

bool envmap_fisheye_covers_sphere(float half_fov, bool dual)
{
    if (dual) {
        return (half_fov >= ENVMAP_HALF_PI);
    }
    return (half_fov >= ENVMAP_PI);
}

EnvmapChartUv envmap_fisheye_forward(float3 dir_11, float half_fov_1, bool equisolid, bool dual_1)
{
    bool local_15 = (bool)0;
    float axial = (float)0;
    float side = 1.0;
    bool local_16 = (bool)0;
    float r_2 = (float)0;
    float x_7 = 1.0;
    float y_2 = 0.0;

    const EnvmapDirection _e4 = envmap_normalize_direction(dir_11);
    if (!(_e4.valid)) {
        const EnvmapChartUv _e7 = envmap_invalid_chart_uv();
        const EnvmapChartUv envmapchartuv_26 = _e7;
        return envmapchartuv_26;
    }
    float3 d_15 = _e4.dir;
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
    const float _e32 = envmap_atan2f(rho_3, _e31);
    const bool _e33 = envmap_fisheye_covers_sphere(half_fov_1, dual_1);
    if (!(_e33)) {
        local_16 = (_e32 > (half_fov_1 * ENVMAP_FISHEYE_SEEN_SCALE));
    } else {
        local_16 = false;
    }
    bool _e41 = local_16;
    if (_e41) {
        const EnvmapChartUv _e42 = envmap_invalid_chart_uv();
        const EnvmapChartUv envmapchartuv_27 = _e42;
        return envmapchartuv_27;
    }
    if (equisolid) {
        const float _e46 = envmap_fisheye_sin((0.5 * _e32));
        const float _e49 = envmap_fisheye_sin((0.5 * half_fov_1));
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
    const float _e88 = envmap_clamp_unit((0.5 + ((_e82 * s_10) * _e84)));
    float _e89 = y_2;
    const float _e93 = envmap_clamp_unit((0.5 - (s_10 * _e89)));
    const EnvmapChartUv envmapchartuv_28 = ConstructEnvmapChartUv((back ? 1u : 0u), float2(_e88, _e93));
    return envmapchartuv_28;
}

EnvmapDirection envmap_fisheye_inverse(EnvmapChartUv c_13, float half_fov_2, bool equisolid_1, bool dual_2)
{
    bool local_17 = (bool)0;
    float side_1 = 1.0;
    float theta_1 = (float)0;

    uint charts = (dual_2 ? 2u : 1u);
    if (!((c_13.chart >= charts))) {
        const bool _e13 = envmap_in_unit_disk(c_13.uv);
        local_17 = !(_e13);
    } else {
        local_17 = true;
    }
    bool _e16 = local_17;
    if (_e16) {
        const EnvmapDirection _e17 = envmap_invalid_direction();
        const EnvmapDirection envmapdirection_26 = _e17;
        return envmapdirection_26;
    }
    if ((c_13.chart == 1u)) {
        side_1 = -1.0;
    }
    float a_8 = ((2.0 * c_13.uv.x) - 1.0);
    float b_4 = (1.0 - (2.0 * c_13.uv.y));
    float r_8 = min(sqrt(((a_8 * a_8) + (b_4 * b_4))), 1.0);
    if (equisolid_1) {
        const float _e45 = envmap_fisheye_sin((0.5 * half_fov_2));
        const float _e49 = envmap_fisheye_asin(min((r_8 * _e45), 1.0));
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
        const EnvmapDirection envmapdirection_27 = ConstructEnvmapDirection(float3(0.0, 0.0, _e60), true);
        return envmapdirection_27;
    }
    float s_11 = (sin_t / r_8);
    float _e67 = side_1;
    float _e71 = side_1;
    float3 d_16 = float3(((_e67 * s_11) * a_8), (s_11 * b_4), (_e71 * cos_t));
    const EnvmapDirection envmapdirection_28 = ConstructEnvmapDirection((d_16 / (sqrt(dot(d_16, d_16))).xxx), true);
    return envmapdirection_28;
}

typedef float ret_Constructarray9_float_[9];
ret_Constructarray9_float_ Constructarray9_float_(float arg0, float arg1, float arg2, float arg3, float arg4, float arg5, float arg6, float arg7, float arg8) {
    float ret[9] = { arg0, arg1, arg2, arg3, arg4, arg5, arg6, arg7, arg8 };
    return ret;
}

typedef float ret_envmap_sh9_basis[9];
ret_envmap_sh9_basis envmap_sh9_basis(float3 n_1)
{
    const EnvmapDirection _e1 = envmap_normalize_direction(n_1);
    if (!(_e1.valid)) {
        return Constructarray9_float_(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    }
    float x_13 = _e1.dir.x;
    float y_9 = _e1.dir.y;
    float z_4 = _e1.dir.z;
    return Constructarray9_float_(ENVMAP_SH_Y00_CONSTANT, (ENVMAP_SH_Y1_CONSTANT * y_9), (ENVMAP_SH_Y1_CONSTANT * z_4), (ENVMAP_SH_Y1_CONSTANT * x_13), (ENVMAP_SH_Y2_CONSTANT * (x_13 * y_9)), (ENVMAP_SH_Y2_CONSTANT * (y_9 * z_4)), (ENVMAP_SH_Y20_CONSTANT * (((3.0 * z_4) * z_4) - 1.0)), (ENVMAP_SH_Y2_CONSTANT * (x_13 * z_4)), (ENVMAP_SH_Y22_CONSTANT * ((x_13 * x_13) - (y_9 * y_9))));
}

float3 envmap_sh9_eval(float3 c_14[9], float3 n_2)
{
    float3 e = (0.0).xxx;
    uint i = 0u;

    const float _e2[9] = envmap_sh9_basis(n_2);
    uint2 loop_bound = uint2(4294967295u, 4294967295u);
    bool loop_init = true;
    while(true) {
        if (all(loop_bound == uint2(0u, 0u))) { break; }
        loop_bound -= uint2(loop_bound.y == 0u, 1u);
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
            float3 _e11 = e;
            uint _e12 = i;
            uint _e14 = i;
            e = (_e11 + (c_14[min(uint(_e12), 8u)] * _e2[min(uint(_e14), 8u)]));
        }
    }
    float3 _e21 = e;
    return _e21;
}

float3 envmap_sh9_irradiance(float3 radiance[9], float3 n_3)
{
    float3 band2_ = (0.0).xxx;
    uint i_1 = 4u;

    const float _e2[9] = envmap_sh9_basis(n_3);
    float3 band0_ = (radiance[0] * _e2[0]);
    float3 band1_ = (((radiance[1] * _e2[1]) + (radiance[2] * _e2[2])) + (radiance[3] * _e2[3]));
    uint2 loop_bound_1 = uint2(4294967295u, 4294967295u);
    bool loop_init_1 = true;
    while(true) {
        if (all(loop_bound_1 == uint2(0u, 0u))) { break; }
        loop_bound_1 -= uint2(loop_bound_1.y == 0u, 1u);
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
            float3 _e25 = band2_;
            uint _e26 = i_1;
            uint _e28 = i_1;
            band2_ = (_e25 + (radiance[min(uint(_e26), 8u)] * _e2[min(uint(_e28), 8u)]));
        }
    }
    float3 _e41 = band2_;
    return (((ENVMAP_PI * band0_) + (ENVMAP_SH_A1_FACTOR * band1_)) + (ENVMAP_QUARTER_PI * _e41));
}

float3 envmap_sh9_irradiance_over_pi(float3 radiance_1[9], float3 n_4)
{
    const float3 _e2 = envmap_sh9_irradiance(radiance_1, n_4);
    return (_e2 * ENVMAP_INV_PI);
}

float3 envmap_sh9_filament(float3 sh[9], float3 n_5)
{
    const EnvmapDirection _e2 = envmap_normalize_direction(n_5);
    if (!(_e2.valid)) {
        return (0.0).xxx;
    }
    float x_14 = _e2.dir.x;
    float y_10 = _e2.dir.y;
    float z_5 = _e2.dir.z;
    return ((((((((sh[0] + (sh[1] * y_10)) + (sh[2] * z_5)) + (sh[3] * x_14)) + (sh[4] * (y_10 * x_14))) + (sh[5] * (y_10 * z_5))) + (sh[6] * (((3.0 * z_5) * z_5) - 1.0))) + (sh[7] * (z_5 * x_14))) + (sh[8] * ((x_14 * x_14) - (y_10 * y_10))));
}

float envmap_roughness_to_lod_linear(float roughness, float levels)
{
    float r_9 = clamp(roughness, 0.0, 1.0);
    return (r_9 * (levels - 1.0));
}

float envmap_roughness_to_lod_filament(float roughness_1, float levels_1)
{
    float r_10 = clamp(roughness_1, 0.0, 1.0);
    return ((r_10 * (2.0 - r_10)) * (levels_1 - 1.0));
}

float envmap_roughness_to_lod_unity(float roughness_2, float levels_2)
{
    float r_11 = clamp(roughness_2, 0.0, 1.0);
    return ((r_11 * (1.7 - (0.7 * r_11))) * (levels_2 - 1.0));
}

float3 envmap_reflect_view(float3 n_6, float3 v_1)
{
    return (((2.0 * dot(n_6, v_1)) * n_6) - v_1);
}

float3 envmap_reflect_incident(float3 i_2, float3 n_7)
{
    return (i_2 - ((2.0 * dot(n_7, i_2)) * n_7));
}

float3 envmap_specular_dominant_direction(float3 n_8, float3 r_3, float roughness_3)
{
    bool local_18 = (bool)0;

    float a_9 = (roughness_3 * roughness_3);
    float3 d_17 = ((r_3 * (1.0 - a_9)) + (n_8 * a_9));
    float l2_ = dot(d_17, d_17);
    if ((l2_ > 0.0)) {
        const bool _e14 = envmap_all_finite(d_17);
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

float3 envmap_specular_direction(float3 n_9, float3 v_2, float roughness_4, bool dominant)
{
    const float3 _e4 = envmap_reflect_view(n_9, v_2);
    if (dominant) {
        const float3 _e8 = envmap_specular_dominant_direction(n_9, _e4, clamp(roughness_4, 0.0, 1.0));
        return _e8;
    }
    return _e4;
}

float3 envmap_f0_color(float3 base_color, float metallic, float dielectric_f0_)
{
    float m_3 = clamp(metallic, 0.0, 1.0);
    return (((dielectric_f0_ * (1.0 - m_3))).xxx + (clamp(base_color, (0.0).xxx, (1.0).xxx) * m_3));
}

float3 envmap_diffuse_color(float3 base_color_1, float metallic_1)
{
    float m_4 = clamp(metallic_1, 0.0, 1.0);
    return (clamp(base_color_1, (0.0).xxx, (1.0).xxx) * (1.0 - m_4));
}

float3 envmap_split_sum_factor(float3 f0_, float2 dfg, bool multiscatter)
{
    float3 s_2 = (float3)0;
    bool local_19 = (bool)0;

    s_2 = ((f0_ * dfg.x) + (dfg.y).xxx);
    float albedo = (dfg.x + dfg.y);
    if (multiscatter) {
        local_19 = (albedo > 0.0);
    } else {
        local_19 = false;
    }
    bool _e17 = local_19;
    if (_e17) {
        float3 _e18 = s_2;
        s_2 = (_e18 * ((1.0).xxx + (f0_ * ((1.0 / albedo) - 1.0))));
    }
    float3 _e28 = s_2;
    return _e28;
}

float3 envmap_split_sum_factor_filament(float3 f0_1, float2 dfg_1, bool multiscatter_1)
{
    float3 s_3 = (float3)0;
    bool local_20 = (bool)0;

    s_3 = lerp((dfg_1.x).xxx, (dfg_1.y).xxx, f0_1);
    if (multiscatter_1) {
        local_20 = (dfg_1.y > 0.0);
    } else {
        local_20 = false;
    }
    bool _e15 = local_20;
    if (_e15) {
        float3 _e16 = s_3;
        s_3 = (_e16 * ((1.0).xxx + (f0_1 * ((1.0 / dfg_1.y) - 1.0))));
    }
    float3 _e27 = s_3;
    return _e27;
}

float3 envmap_split_sum(float3 diffuse, float3 f0_2, float3 e_over_pi, float3 ld, float2 dfg_2, bool multiscatter_2)
{
    const float3 _e7 = envmap_split_sum_factor(f0_2, dfg_2, multiscatter_2);
    return ((diffuse * e_over_pi) + (ld * _e7));
}

float2 envmap_dfg_uv(float n_dot_v, float roughness_5)
{
    return float2(clamp(n_dot_v, 0.0001, 1.0), clamp(roughness_5, 0.0, 1.0));
}

int2 naga_f2i32(float2 value) {
    return int2(clamp(value, -2147483600.0, 2147483500.0));
}

uint2 NagaMipDimensions2D(Texture2D<float4> tex, uint mip_level)
{
    uint4 ret;
    tex.GetDimensions(mip_level, ret.x, ret.y, ret.z);
    return ret.xy;
}

float2 envmap_dfg_load(Texture2D<float4> t, float n_dot_v_1, float roughness_6)
{
    const float2 _e3 = envmap_dfg_uv(n_dot_v_1, roughness_6);
    float2 size_2 = float2(NagaMipDimensions2D(t, int(0)));
    float2 x_15 = clamp(((_e3 * size_2) - (0.5).xx), (0.0).xx, (size_2 - (1.0).xx));
    int2 i0_ = naga_f2i32(floor(x_15));
    int2 i1_ = min(asint(asuint(i0_) + asuint((int(1)).xx)), asint(asuint(naga_f2i32(size_2)) - asuint((int(1)).xx)));
    float2 f = (x_15 - floor(x_15));
    float4 _e33 = t.Load(int3(int2(i0_.x, i0_.y), int(0)));
    float2 a_10 = _e33.xy;
    float4 _e39 = t.Load(int3(int2(i1_.x, i0_.y), int(0)));
    float2 b_5 = _e39.xy;
    float4 _e45 = t.Load(int3(int2(i0_.x, i1_.y), int(0)));
    float2 c_18 = _e45.xy;
    float4 _e51 = t.Load(int3(int2(i1_.x, i1_.y), int(0)));
    float2 d_18 = _e51.xy;
    float2 top = (a_10 + (f.x * (b_5 - a_10)));
    float2 bottom = (c_18 + (f.x * (d_18 - c_18)));
    return (top + (f.y * (bottom - top)));
}

EnvmapFootprint ConstructEnvmapFootprint(int arg0, int arg1, float arg2) {
    EnvmapFootprint ret = (EnvmapFootprint)0;
    ret.first = arg0;
    ret.second = arg1;
    ret.f = arg2;
    return ret;
}

int naga_f2i32(float value) {
    return int(clamp(value, -2147483600.0, 2147483500.0));
}

EnvmapFootprint envmap_bilinear_footprint(float u_3, int n_10)
{
    float x_16 = clamp(((u_3 * float(n_10)) - 0.5), -0.5, (float(n_10) - 0.5));
    float t_18 = floor(x_16);
    const EnvmapFootprint envmapfootprint = ConstructEnvmapFootprint(naga_f2i32(t_18), asint(asuint(naga_f2i32(t_18)) + asuint(int(1))), (x_16 - t_18));
    return envmapfootprint;
}

float3 envmap_blend(float3 a_2, float3 b_1, float3 c_15, float3 d_6, float fx, float fy)
{
    float3 left = (((c_15 - a_2) * fy) + a_2);
    float3 right = (((d_6 - b_1) * fy) + b_1);
    return (((right - left) * fx) + left);
}

int naga_div(int lhs, int rhs) {
    return lhs / (((lhs == int(-2147483647 - 1) & rhs == -1) | (rhs == 0)) ? 1 : rhs);
}

float3 envmap_latlong_texel(Texture2D<float4> t_1, int i_3, int j, int level)
{
    int ii = (int)0;
    int jj = (int)0;
    bool local_21 = (bool)0;

    int2 size_3 = int2(NagaMipDimensions2D(t_1, level));
    ii = i_3;
    jj = j;
    int _e8 = jj;
    if (!((_e8 < int(0)))) {
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
        jj = ((_e29 < int(0)) ? asint(asuint(int(-1)) - asuint(_e26)) : asint(asuint(asint(asuint(asint(asuint(int(2)) * asuint(size_3.y))) - asuint(int(1)))) - asuint(_e24)));
        int _e33 = ii;
        ii = asint(asuint(_e33) + asuint(naga_div(size_3.x, int(2))));
    }
    int _e38 = ii;
    if ((_e38 < int(0))) {
        int _e41 = ii;
        ii = asint(asuint(_e41) + asuint(size_3.x));
    }
    int _e44 = ii;
    if ((_e44 >= size_3.x)) {
        int _e47 = ii;
        ii = asint(asuint(_e47) - asuint(size_3.x));
    }
    int _e50 = jj;
    jj = clamp(_e50, int(0), asint(asuint(size_3.y) - asuint(int(1))));
    int _e56 = ii;
    int _e57 = jj;
    float4 _e59 = t_1.Load(int3(int2(_e56, _e57), level));
    return _e59.xyz;
}

float3 envmap_latlong_bilinear(Texture2D<float4> t_2, float2 uv_2, int level_1)
{
    int2 size_4 = int2(NagaMipDimensions2D(t_2, level_1));
    const EnvmapFootprint _e7 = envmap_bilinear_footprint(uv_2.x, size_4.x);
    const EnvmapFootprint _e10 = envmap_bilinear_footprint(uv_2.y, size_4.y);
    const float3 _e13 = envmap_latlong_texel(t_2, _e7.first, _e10.first, level_1);
    const float3 _e16 = envmap_latlong_texel(t_2, _e7.second, _e10.first, level_1);
    const float3 _e19 = envmap_latlong_texel(t_2, _e7.first, _e10.second, level_1);
    const float3 _e22 = envmap_latlong_texel(t_2, _e7.second, _e10.second, level_1);
    const float3 _e25 = envmap_blend(_e13, _e16, _e19, _e22, _e7.f, _e10.f);
    return _e25;
}

float3 envmap_octahedral_texel(Texture2D<float4> t_3, int i_4, int j_1, int level_2)
{
    int ii_1 = (int)0;
    int jj_1 = (int)0;
    bool local_22 = (bool)0;
    bool local_23 = (bool)0;

    int2 size_5 = int2(NagaMipDimensions2D(t_3, level_2));
    ii_1 = i_4;
    jj_1 = j_1;
    int _e8 = jj_1;
    if (!((_e8 < int(0)))) {
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
        jj_1 = ((_e29 < int(0)) ? asint(asuint(int(-1)) - asuint(_e26)) : asint(asuint(asint(asuint(asint(asuint(int(2)) * asuint(size_5.y))) - asuint(int(1)))) - asuint(_e24)));
        int _e36 = ii_1;
        ii_1 = asint(asuint(asint(asuint(size_5.x) - asuint(int(1)))) - asuint(_e36));
    }
    int _e38 = ii_1;
    if (!((_e38 < int(0)))) {
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
        ii_1 = ((_e59 < int(0)) ? asint(asuint(int(-1)) - asuint(_e56)) : asint(asuint(asint(asuint(asint(asuint(int(2)) * asuint(size_5.x))) - asuint(int(1)))) - asuint(_e54)));
        int _e66 = jj_1;
        jj_1 = asint(asuint(asint(asuint(size_5.y) - asuint(int(1)))) - asuint(_e66));
    }
    int _e68 = ii_1;
    int _e74 = jj_1;
    float4 _e81 = t_3.Load(int3(int2(clamp(_e68, int(0), asint(asuint(size_5.x) - asuint(int(1)))), clamp(_e74, int(0), asint(asuint(size_5.y) - asuint(int(1))))), level_2));
    return _e81.xyz;
}

float3 envmap_octahedral_bilinear(Texture2D<float4> t_4, float2 uv_3, int level_3)
{
    int2 size_6 = int2(NagaMipDimensions2D(t_4, level_3));
    const EnvmapFootprint _e7 = envmap_bilinear_footprint(uv_3.x, size_6.x);
    const EnvmapFootprint _e10 = envmap_bilinear_footprint(uv_3.y, size_6.y);
    const float3 _e13 = envmap_octahedral_texel(t_4, _e7.first, _e10.first, level_3);
    const float3 _e16 = envmap_octahedral_texel(t_4, _e7.second, _e10.first, level_3);
    const float3 _e19 = envmap_octahedral_texel(t_4, _e7.first, _e10.second, level_3);
    const float3 _e22 = envmap_octahedral_texel(t_4, _e7.second, _e10.second, level_3);
    const float3 _e25 = envmap_blend(_e13, _e16, _e19, _e22, _e7.f, _e10.f);
    return _e25;
}

int envmap_texel_index(float u_4, int n_11)
{
    return min(naga_f2i32((u_4 * float(n_11))), asint(asuint(n_11) - asuint(int(1))));
}

uint2 NagaMipDimensions2DArray(Texture2DArray<float4> tex, uint mip_level)
{
    uint4 ret;
    tex.GetDimensions(mip_level, ret.x, ret.y, ret.z, ret.w);
    return ret.xy;
}

float3 envmap_cube_texel_across(Texture2DArray<float4> t_5, uint face_1, int i_5, int j_2, int level_4)
{
    int2 size_7 = int2(NagaMipDimensions2DArray(t_5, level_4));
    float sc_1 = ((2.0 * ((float(i_5) + 0.5) / float(size_7.x))) - 1.0);
    float tc_1 = ((2.0 * ((float(j_2) + 0.5) / float(size_7.y))) - 1.0);
    const float3 _e27 = envmap_cube_face_direction(face_1, sc_1, tc_1);
    const EnvmapChartUv _e28 = envmap_cube_forward(_e27);
    const int _e32 = envmap_texel_index(_e28.uv.x, size_7.x);
    const int _e36 = envmap_texel_index(_e28.uv.y, size_7.y);
    int2 k_3 = int2(_e32, _e36);
    float4 _e40 = t_5.Load(int4(k_3, int(_e28.chart), level_4));
    return _e40.xyz;
}

float3 envmap_cube_texel(Texture2DArray<float4> t_6, uint face_2, int i_6, int j_3, int level_5)
{
    bool local_24 = (bool)0;
    bool local_25 = (bool)0;
    bool local_26 = (bool)0;
    bool local_27 = (bool)0;

    int2 size_8 = int2(NagaMipDimensions2DArray(t_6, level_5));
    if (!((i_6 < int(0)))) {
        local_24 = (i_6 >= size_8.x);
    } else {
        local_24 = true;
    }
    bool iout = local_24;
    if (!((j_3 < int(0)))) {
        local_25 = (j_3 >= size_8.y);
    } else {
        local_25 = true;
    }
    bool jout = local_25;
    int ic = clamp(i_6, int(0), asint(asuint(size_8.x) - asuint(int(1))));
    int jc = clamp(j_3, int(0), asint(asuint(size_8.y) - asuint(int(1))));
    if (iout) {
        local_26 = jout;
    } else {
        local_26 = false;
    }
    bool _e38 = local_26;
    if (_e38) {
        const float3 _e39 = envmap_cube_texel_across(t_6, face_2, i_6, jc, level_5);
        const float3 _e40 = envmap_cube_texel_across(t_6, face_2, ic, j_3, level_5);
        float4 _e43 = t_6.Load(int4(int2(ic, jc), int(face_2), level_5));
        float3 c_19 = _e43.xyz;
        return (((_e39 + _e40) + c_19) / (3.0).xxx);
    }
    if (!(iout)) {
        local_27 = jout;
    } else {
        local_27 = true;
    }
    bool _e54 = local_27;
    if (_e54) {
        const float3 _e55 = envmap_cube_texel_across(t_6, face_2, i_6, j_3, level_5);
        return _e55;
    }
    float4 _e58 = t_6.Load(int4(int2(i_6, j_3), int(face_2), level_5));
    return _e58.xyz;
}

float3 envmap_cube_bilinear(Texture2DArray<float4> t_7, EnvmapChartUv c_16, int level_6)
{
    int2 size_9 = int2(NagaMipDimensions2DArray(t_7, level_6));
    const EnvmapFootprint _e8 = envmap_bilinear_footprint(c_16.uv.x, size_9.x);
    const EnvmapFootprint _e12 = envmap_bilinear_footprint(c_16.uv.y, size_9.y);
    const float3 _e16 = envmap_cube_texel(t_7, c_16.chart, _e8.first, _e12.first, level_6);
    const float3 _e20 = envmap_cube_texel(t_7, c_16.chart, _e8.second, _e12.first, level_6);
    const float3 _e24 = envmap_cube_texel(t_7, c_16.chart, _e8.first, _e12.second, level_6);
    const float3 _e28 = envmap_cube_texel(t_7, c_16.chart, _e8.second, _e12.second, level_6);
    const float3 _e31 = envmap_blend(_e16, _e20, _e24, _e28, _e8.f, _e12.f);
    return _e31;
}

EnvmapLevels ConstructEnvmapLevels(int arg0, float arg1) {
    EnvmapLevels ret = (EnvmapLevels)0;
    ret.level = arg0;
    ret.blend = arg1;
    return ret;
}

EnvmapLevels envmap_levels(float lod, int levels_3)
{
    float l = clamp(lod, 0.0, float(asint(asuint(levels_3) - asuint(int(1)))));
    int k_4 = min(naga_f2i32(floor(l)), asint(asuint(levels_3) - asuint(int(1))));
    if ((asint(asuint(k_4) + asuint(int(1))) >= levels_3)) {
        const EnvmapLevels envmaplevels = ConstructEnvmapLevels(k_4, 0.0);
        return envmaplevels;
    }
    const EnvmapLevels envmaplevels_1 = ConstructEnvmapLevels(k_4, (l - float(k_4)));
    return envmaplevels_1;
}

float3 envmap_latlong_chain(Texture2D<float4> t_8, int levels_4, float3 dir_12, float lod_1)
{
    const EnvmapChartUv _e4 = envmap_latlong_forward(dir_12);
    if ((_e4.chart == ENVMAP_INVALID_CHART)) {
        return (0.0).xxx;
    }
    const EnvmapLevels _e10 = envmap_levels(lod_1, levels_4);
    const float3 _e13 = envmap_latlong_bilinear(t_8, _e4.uv, _e10.level);
    if ((_e10.blend > 0.0)) {
        const float3 _e21 = envmap_latlong_bilinear(t_8, _e4.uv, asint(asuint(_e10.level) + asuint(int(1))));
        return (_e13 + ((_e21 - _e13) * _e10.blend));
    }
    return _e13;
}

float3 envmap_octahedral_chain(Texture2D<float4> t_9, int levels_5, float3 dir_13, float lod_2)
{
    const EnvmapChartUv _e4 = envmap_octahedral_forward(dir_13);
    if ((_e4.chart == ENVMAP_INVALID_CHART)) {
        return (0.0).xxx;
    }
    const EnvmapLevels _e10 = envmap_levels(lod_2, levels_5);
    const float3 _e13 = envmap_octahedral_bilinear(t_9, _e4.uv, _e10.level);
    if ((_e10.blend > 0.0)) {
        const float3 _e21 = envmap_octahedral_bilinear(t_9, _e4.uv, asint(asuint(_e10.level) + asuint(int(1))));
        return (_e13 + ((_e21 - _e13) * _e10.blend));
    }
    return _e13;
}

float3 envmap_equal_area_octahedral_chain(Texture2D<float4> t_10, int levels_6, float3 dir_14, float lod_3)
{
    const EnvmapChartUv _e4 = envmap_equal_area_octahedral_forward(dir_14);
    if ((_e4.chart == ENVMAP_INVALID_CHART)) {
        return (0.0).xxx;
    }
    const EnvmapLevels _e10 = envmap_levels(lod_3, levels_6);
    const float3 _e13 = envmap_octahedral_bilinear(t_10, _e4.uv, _e10.level);
    if ((_e10.blend > 0.0)) {
        const float3 _e21 = envmap_octahedral_bilinear(t_10, _e4.uv, asint(asuint(_e10.level) + asuint(int(1))));
        return (_e13 + ((_e21 - _e13) * _e10.blend));
    }
    return _e13;
}

float3 envmap_cube_chain(Texture2DArray<float4> t_11, int levels_7, float3 dir_15, float lod_4)
{
    const EnvmapChartUv _e4 = envmap_cube_forward(dir_15);
    if ((_e4.chart == ENVMAP_INVALID_CHART)) {
        return (0.0).xxx;
    }
    const EnvmapLevels _e10 = envmap_levels(lod_4, levels_7);
    const float3 _e12 = envmap_cube_bilinear(t_11, _e4, _e10.level);
    if ((_e10.blend > 0.0)) {
        const float3 _e19 = envmap_cube_bilinear(t_11, _e4, asint(asuint(_e10.level) + asuint(int(1))));
        return (_e12 + ((_e19 - _e12) * _e10.blend));
    }
    return _e12;
}

float envmap_direction_footprint(float3 d_7, float3 ddx_, float3 ddy_)
{
    float l2_1 = dot(d_7, d_7);
    return (max(length(cross(d_7, ddx_)), length(cross(d_7, ddy_))) / l2_1);
}

float envmap_latlong_lod(float angle, float height)
{
    return max(log2(((angle * height) / ENVMAP_PI)), 0.0);
}

float envmap_octahedral_lod(float3 dir_16, float angle_1, float size)
{
    float3 a_11 = abs(dir_16);
    float p_4 = (length(dir_16) / ((a_11.x + a_11.y) + a_11.z));
    float texel = (2.0 / ((size * p_4) * sqrt(p_4)));
    return max(log2((angle_1 / texel)), 0.0);
}

float envmap_equal_area_octahedral_lod(float angle_2, float size_1)
{
    return max(log2(((angle_2 * size_1) / 3.5449078)), 0.0);
}

float4 envmap_latlong_sample_level(Texture2D<float4> t_12, SamplerState s_4, float3 dir_17, float lod_5)
{
    const EnvmapChartUv _e4 = envmap_latlong_forward(dir_17);
    float4 _e6 = t_12.SampleLevel(s_4, _e4.uv, lod_5);
    return _e6;
}

float4 envmap_octahedral_sample_level(Texture2D<float4> t_13, SamplerState s_5, float3 dir_18, float lod_6)
{
    const EnvmapChartUv _e4 = envmap_octahedral_forward(dir_18);
    float4 _e6 = t_13.SampleLevel(s_5, _e4.uv, lod_6);
    return _e6;
}

float4 envmap_equal_area_octahedral_sample_level(Texture2D<float4> t_14, SamplerState s_6, float3 dir_19, float lod_7)
{
    const EnvmapChartUv _e4 = envmap_equal_area_octahedral_forward(dir_19);
    float4 _e6 = t_14.SampleLevel(s_6, _e4.uv, lod_7);
    return _e6;
}
