// envmap shaders, HLSL (shader model 5.0): angular (from common.wgsl, frame.wgsl, angular.wgsl).
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
    float3 s_2 = (d_1 / (m).xxx);
    const EnvmapDirection envmapdirection_3 = ConstructEnvmapDirection((s_2 / (sqrt(dot(s_2, s_2))).xxx), true);
    return envmapdirection_3;
}

float envmap_atan_unit(float z)
{
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

EnvmapChartUv envmap_angular_forward(float3 dir)
{
    float px = 1.0;
    float py = 0.0;

    const EnvmapDirection _e1 = envmap_normalize_direction(dir);
    if (!(_e1.valid)) {
        const EnvmapChartUv _e4 = envmap_invalid_chart_uv();
        const EnvmapChartUv envmapchartuv_1 = _e4;
        return envmapchartuv_1;
    }
    float3 r = _e1.dir;
    float a_3 = max(abs(dir.x), abs(dir.y));
    if ((a_3 != 0.0)) {
        px = (dir.x / a_3);
        py = (dir.y / a_3);
    }
    float _e21 = px;
    float _e22 = px;
    float _e24 = py;
    float _e25 = py;
    float len = sqrt(((_e21 * _e22) + (_e24 * _e25)));
    float sin_theta = (max(abs(r.x), abs(r.y)) * len);
    const float _e36 = envmap_atan2f(sin_theta, r.z);
    float rho = min((_e36 / ENVMAP_PI), 1.0);
    float k_1 = (rho / len);
    float _e42 = px;
    const float _e48 = envmap_clamp_unit(((0.5 * (k_1 * _e42)) + 0.5));
    float _e49 = py;
    const float _e55 = envmap_clamp_unit(((0.5 * (k_1 * _e49)) + 0.5));
    const EnvmapChartUv envmapchartuv_2 = ConstructEnvmapChartUv(0u, float2(_e48, _e55));
    return envmapchartuv_2;
}

EnvmapDirection envmap_angular_inverse(EnvmapChartUv c)
{
    bool local_2 = (bool)0;
    float s_1 = (float)0;
    float co = (float)0;
    float k = ENVMAP_PI;

    if (!((c.chart != 0u))) {
        const bool _e8 = envmap_in_unit_disk(c.uv);
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
    float x_5 = ((2.0 * c.uv.x) - 1.0);
    float y_1 = ((2.0 * c.uv.y) - 1.0);
    float rho_1 = min(sqrt(((x_5 * x_5) + (y_1 * y_1))), 1.0);
    if ((rho_1 <= 0.5)) {
        s_1 = sin((ENVMAP_PI * rho_1));
        co = cos((ENVMAP_PI * rho_1));
    } else {
        float t = (ENVMAP_PI * (1.0 - rho_1));
        s_1 = sin(t);
        co = -(cos(t));
    }
    if ((rho_1 > 0.0)) {
        float _e52 = s_1;
        k = (_e52 / rho_1);
    }
    float _e54 = k;
    float _e56 = k;
    float _e58 = co;
    float3 d_4 = float3((_e54 * x_5), (_e56 * y_1), _e58);
    const EnvmapDirection envmapdirection_6 = ConstructEnvmapDirection((d_4 / (sqrt(dot(d_4, d_4))).xxx), true);
    return envmapdirection_6;
}
