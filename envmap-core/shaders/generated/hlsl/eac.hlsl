// envmap shaders, HLSL (shader model 5.0): eac (from common.wgsl, frame.wgsl, cube.wgsl, eac.wgsl).
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
    uint3 e = (asuint(d) & (2139095040u).xxx);
    return all((e != (2139095040u).xxx));
}

bool envmap_in_unit_interval(float x_2)
{
    bool local = (bool)0;

    uint b = asuint(x_2);
    if (!((b <= 1065353216u))) {
        local = (b == 2147483648u);
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
    float2 p_1 = ((2.0 * uv_1) - (1.0).xx);
    return (((p_1.x * p_1.x) + (p_1.y * p_1.y)) <= ENVMAP_DISK_LIMIT);
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
    float3 a_1 = abs(d_1);
    float m = max(max(a_1.x, a_1.y), a_1.z);
    if ((m == 0.0)) {
        const EnvmapDirection _e12 = envmap_invalid_direction();
        const EnvmapDirection envmapdirection_2 = _e12;
        return envmapdirection_2;
    }
    float3 s_1 = (d_1 / (m).xxx);
    const EnvmapDirection envmapdirection_3 = ConstructEnvmapDirection((s_1 / (sqrt(dot(s_1, s_1))).xxx), true);
    return envmapdirection_3;
}

float envmap_atan_unit(float z)
{
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
    float3 a_2 = abs(d_2);
    float m_1 = max(max(a_2.x, a_2.y), a_2.z);
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
    bool local_2 = (bool)0;

    const bool _e1 = envmap_all_finite(d_4);
    if (!(_e1)) {
        const EnvmapCubeFace envmapcubeface = ConstructEnvmapCubeFace(4294967295u, 0.0, 0.0, 0.0);
        return envmapcubeface;
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

EnvmapChartUv envmap_cube_forward(float3 dir)
{
    const EnvmapCubeFace _e1 = envmap_cube_select_face(dir);
    if ((_e1.face == ENVMAP_INVALID_CHART)) {
        const EnvmapChartUv _e5 = envmap_invalid_chart_uv();
        const EnvmapChartUv envmapchartuv_1 = _e5;
        return envmapchartuv_1;
    }
    float s_2 = (0.5 * ((_e1.sc / _e1.ma) + 1.0));
    float t = (0.5 * ((_e1.tc / _e1.ma) + 1.0));
    const EnvmapChartUv envmapchartuv_2 = ConstructEnvmapChartUv(_e1.face, float2(s_2, t));
    return envmapchartuv_2;
}

EnvmapDirection envmap_cube_inverse(EnvmapChartUv c)
{
    bool local_3 = (bool)0;

    if (!((c.chart > 5u))) {
        const bool _e8 = envmap_in_unit_square(c.uv);
        local_3 = !(_e8);
    } else {
        local_3 = true;
    }
    bool _e11 = local_3;
    if (_e11) {
        const EnvmapDirection _e12 = envmap_invalid_direction();
        const EnvmapDirection envmapdirection_5 = _e12;
        return envmapdirection_5;
    }
    const float3 _e26 = envmap_cube_face_direction(c.chart, ((2.0 * c.uv.x) - 1.0), ((2.0 * c.uv.y) - 1.0));
    const EnvmapDirection envmapdirection_6 = ConstructEnvmapDirection((_e26 / (sqrt(dot(_e26, _e26))).xxx), true);
    return envmapdirection_6;
}

float envmap_eac_atan(float c_1)
{
    const float _e2 = envmap_atan_unit(abs(c_1));
    const float _e3 = envmap_copysign(_e2, c_1);
    return _e3;
}

float envmap_eac_angle(float u)
{
    return (ENVMAP_QUARTER_PI * ((2.0 * u) - 1.0));
}

EnvmapChartUv envmap_eac_forward(float3 dir_1)
{
    const EnvmapCubeFace _e1 = envmap_cube_select_face(dir_1);
    if ((_e1.face == ENVMAP_INVALID_CHART)) {
        const EnvmapChartUv _e5 = envmap_invalid_chart_uv();
        const EnvmapChartUv envmapchartuv_3 = _e5;
        return envmapchartuv_3;
    }
    const float _e10 = envmap_eac_atan((_e1.sc / _e1.ma));
    const float _e14 = envmap_clamp_unit((0.5 + (ENVMAP_TWO_OVER_PI * _e10)));
    const float _e19 = envmap_eac_atan((_e1.tc / _e1.ma));
    const float _e23 = envmap_clamp_unit((0.5 + (ENVMAP_TWO_OVER_PI * _e19)));
    const EnvmapChartUv envmapchartuv_4 = ConstructEnvmapChartUv(_e1.face, float2(_e14, _e23));
    return envmapchartuv_4;
}

EnvmapDirection envmap_eac_inverse(EnvmapChartUv c_2)
{
    bool local_4 = (bool)0;

    if (!((c_2.chart > 5u))) {
        const bool _e8 = envmap_in_unit_square(c_2.uv);
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
    const float _e16 = envmap_eac_angle(c_2.uv.x);
    const float _e20 = envmap_eac_angle(c_2.uv.y);
    const float3 _e22 = envmap_cube_face_direction(c_2.chart, tan(_e16), tan(_e20));
    const EnvmapDirection envmapdirection_8 = ConstructEnvmapDirection((_e22 / (sqrt(dot(_e22, _e22))).xxx), true);
    return envmapdirection_8;
}
