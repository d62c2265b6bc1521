// envmap shaders, HLSL (shader model 5.0): octahedral (from common.wgsl, frame.wgsl, octahedral.wgsl).
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

EnvmapChartUv envmap_octahedral_to_uv(float x_5, float y_1)
{
    const float _e7 = envmap_clamp_unit(((0.5 * x_5) + 0.5));
    const float _e12 = envmap_clamp_unit(((0.5 * y_1) + 0.5));
    const EnvmapChartUv envmapchartuv_1 = ConstructEnvmapChartUv(0u, float2(_e7, _e12));
    return envmapchartuv_1;
}

EnvmapChartUv envmap_octahedral_forward(float3 dir)
{
    const EnvmapDirection _e1 = envmap_normalize_direction(dir);
    if (!(_e1.valid)) {
        const EnvmapChartUv _e4 = envmap_invalid_chart_uv();
        const EnvmapChartUv envmapchartuv_2 = _e4;
        return envmapchartuv_2;
    }
    float3 d_5 = _e1.dir;
    float3 p_2 = (d_5 / (((abs(d_5.x) + abs(d_5.y)) + abs(d_5.z))).xxx);
    if ((p_2.z < 0.0)) {
        const float _e24 = envmap_copysign((1.0 - abs(p_2.y)), dir.x);
        const float _e30 = envmap_copysign((1.0 - abs(p_2.x)), dir.y);
        const EnvmapChartUv _e31 = envmap_octahedral_to_uv(_e24, _e30);
        const EnvmapChartUv envmapchartuv_3 = _e31;
        return envmapchartuv_3;
    }
    const EnvmapChartUv _e34 = envmap_octahedral_to_uv(p_2.x, p_2.y);
    const EnvmapChartUv envmapchartuv_4 = _e34;
    return envmapchartuv_4;
}

EnvmapDirection envmap_octahedral_inverse(EnvmapChartUv c)
{
    bool local_2 = (bool)0;
    float3 d_4 = (float3)0;

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
    float x_6 = ((2.0 * c.uv.x) - 1.0);
    float y_2 = ((2.0 * c.uv.y) - 1.0);
    float z_2 = ((1.0 - abs(x_6)) - abs(y_2));
    d_4 = float3(x_6, y_2, z_2);
    if ((z_2 < 0.0)) {
        const float _e37 = envmap_copysign((1.0 - abs(y_2)), x_6);
        const float _e41 = envmap_copysign((1.0 - abs(x_6)), y_2);
        d_4 = float3(_e37, _e41, z_2);
    }
    float3 _e43 = d_4;
    float3 _e44 = d_4;
    float3 _e45 = d_4;
    const EnvmapDirection envmapdirection_6 = ConstructEnvmapDirection((_e43 / (sqrt(dot(_e44, _e45))).xxx), true);
    return envmapdirection_6;
}

EnvmapChartUv envmap_equal_area_octahedral_forward(float3 dir_1)
{
    float phi = 0.0;
    float v = (float)0;
    float u = (float)0;

    const EnvmapDirection _e1 = envmap_normalize_direction(dir_1);
    if (!(_e1.valid)) {
        const EnvmapChartUv _e4 = envmap_invalid_chart_uv();
        const EnvmapChartUv envmapchartuv_5 = _e4;
        return envmapchartuv_5;
    }
    float3 d_6 = _e1.dir;
    float ax_1 = abs(d_6.x);
    float ay_1 = abs(d_6.y);
    float az = abs(d_6.z);
    float r_1 = sqrt((((ax_1 * ax_1) + (ay_1 * ay_1)) / (1.0 + az)));
    float hi = max(ax_1, ay_1);
    float lo = min(ax_1, ay_1);
    if ((hi != 0.0)) {
        const float _e26 = envmap_atan_unit((lo / hi));
        phi = (_e26 * ENVMAP_TWO_OVER_PI);
    }
    if ((ax_1 < ay_1)) {
        float _e30 = phi;
        phi = (1.0 - _e30);
    }
    float _e33 = phi;
    v = (_e33 * r_1);
    float _e36 = v;
    u = (r_1 - _e36);
    if ((d_6.z < 0.0)) {
        float u0_ = u;
        float _e43 = v;
        u = (1.0 - _e43);
        v = (1.0 - u0_);
    }
    float _e48 = u;
    const float _e50 = envmap_copysign(_e48, dir_1.x);
    float _e51 = v;
    const float _e53 = envmap_copysign(_e51, dir_1.y);
    const EnvmapChartUv _e54 = envmap_octahedral_to_uv(_e50, _e53);
    const EnvmapChartUv envmapchartuv_6 = _e54;
    return envmapchartuv_6;
}

EnvmapDirection envmap_equal_area_octahedral_inverse(EnvmapChartUv c_1)
{
    bool local_3 = (bool)0;
    float r = (float)0;
    float phi_1 = ENVMAP_QUARTER_PI;

    if (!((c_1.chart != 0u))) {
        const bool _e8 = envmap_in_unit_square(c_1.uv);
        local_3 = !(_e8);
    } else {
        local_3 = true;
    }
    bool _e11 = local_3;
    if (_e11) {
        const EnvmapDirection _e12 = envmap_invalid_direction();
        const EnvmapDirection envmapdirection_7 = _e12;
        return envmapdirection_7;
    }
    float u_2 = ((2.0 * c_1.uv.x) - 1.0);
    float v_1 = ((2.0 * c_1.uv.y) - 1.0);
    float au = abs(u_2);
    float av = abs(v_1);
    float sum = (au + av);
    float signed_distance = (1.0 - sum);
    r = sum;
    if ((signed_distance < 0.0)) {
        r = (2.0 - sum);
    }
    float _e37 = r;
    if ((_e37 != 0.0)) {
        float _e41 = r;
        phi_1 = ((((av - au) / _e41) + 1.0) * ENVMAP_QUARTER_PI);
    }
    float _e47 = r;
    float _e48 = r;
    const float _e52 = envmap_copysign((1.0 - (_e47 * _e48)), signed_distance);
    float _e53 = r;
    float _e54 = r;
    float _e55 = r;
    float k = (_e53 * sqrt(max((2.0 - (_e54 * _e55)), 0.0)));
    float _e63 = phi_1;
    const float _e65 = envmap_copysign(cos(_e63), u_2);
    float _e67 = phi_1;
    const float _e69 = envmap_copysign(sin(_e67), v_1);
    float3 d_7 = float3((_e65 * k), (_e69 * k), _e52);
    const EnvmapDirection envmapdirection_8 = ConstructEnvmapDirection((d_7 / (sqrt(dot(d_7, d_7))).xxx), true);
    return envmapdirection_8;
}
