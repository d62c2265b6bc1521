// envmap shaders: the image-based-lighting lookups an engine needs with
// envmap's bake (envmap bake, envmap_render::filter::bake). Needs
// common.wgsl, frame.wgsl, latlong.wgsl, cube.wgsl and octahedral.wgsl.
//
// The WGSL of envmap-render's scene/lit.rs (LitSampler::shade: the split sum),
// filter/sh.rs (the SH9 basis and irradiance), filter/specular.rs
// (RoughnessRule), filter/dfg.rs (the DFG table) and filter/sample.rs (each
// map's edge rule), with the same formulas:
//
//   diffuse  = c_diff E(N)/pi                                  (c_diff = base (1 - metallic))
//   specular = LD(R, r) (F0 A + B) [ (1 + F0 (1/(A + B) - 1)) ]  (Karis 2013; [Filament's multiscatter])
//   F0 = 0.04 (1 - metallic) + base metallic,  R = 2(N.V)N - V or the dominant direction mix(R, N, r^2)
//   E(n) = sum over l, m of A_l L_lm Y_lm(n), A = (pi, 2pi/3, pi/4)   (Ramamoorthi & Hanrahan 2001)
//   level for roughness r of n levels: linear r (n - 1); Filament r (2 - r)(n - 1); Unity r (1.7 - 0.7 r)(n - 1)
//   DFG table: column i at N.V = (i + 0.5)/size, row j at r = (j + 0.5)/size, row 0 the top
//
// Texture reads, two kinds:
//   * envmap_*_bilinear and envmap_*_chain read texels with textureLoad and
//     filter them as envmap's CPU sampler does, with each map's edge rule:
//     latlong wraps in u and continues half a turn round across a pole;
//     octahedral maps fold across the square's edges (row -1 at column i is
//     row 0 at column w - 1 - i); a cube (a 2D array view of six layers, GL
//     face order) steps onto the neighbouring face and averages the three
//     texels that meet at a corner. Exact to the CPU, at four loads per level.
//   * envmap_*_sample_level sample with the hardware's filter at a level the
//     caller chooses, and envmap_*_lod choose it from the direction's own
//     footprint (an angle, from envmap_direction_footprint of the direction's
//     derivatives) instead of from the screen-space derivatives of (u, v),
//     which jump at a latlong's seam (u 1 -> 0: the one-pixel line from pole
//     to pole at the coarsest level) and at an octahedral map's folds, and
//     shrink towards a latlong's poles (the wedges). Border rule with a
//     hardware sampler: latlong u repeat, v clamp to edge; octahedral clamp
//     to edge (docs/shaders.md says what that costs at the poles and folds).

// ---------------------------------------------------------------------------
// SH9 irradiance (envmap-render/src/filter/sh.rs)

/// Y00 = 1 / (2 sqrt(pi)), rounded to f32.
const ENVMAP_SH_Y00_CONSTANT: f32 = 0.2820948064327239990234375;
/// The band-1 constant sqrt(3 / 4pi): Y1-1 = Y1 y, Y10 = Y1 z, Y11 = Y1 x.
const ENVMAP_SH_Y1_CONSTANT: f32 = 0.48860251903533935546875;
/// The band-2 constant sqrt(15 / 4pi) of xy, yz and xz.
const ENVMAP_SH_Y2_CONSTANT: f32 = 1.09254848957061767578125;
/// Y20 = ENVMAP_SH_Y20_CONSTANT (3z^2 - 1): sqrt(5 / 16pi).
const ENVMAP_SH_Y20_CONSTANT: f32 = 0.3153915703296661376953125;
/// Y22 = ENVMAP_SH_Y22_CONSTANT (x^2 - y^2): sqrt(15 / 16pi).
const ENVMAP_SH_Y22_CONSTANT: f32 = 0.546274244785308837890625;
/// A1 = 2pi/3, the clamped cosine's band-1 factor (A0 = pi, A2 = pi/4).
const ENVMAP_SH_A1_FACTOR: f32 = 2.094395160675048828125;
/// 1 / pi, rounded to f32.
const ENVMAP_INV_PI: f32 = 0.3183098733425140380859375;

/// The nine basis polynomials times their constants at direction n (any
/// length; normalised first), in the coefficient order L00, L1-1, L10,
/// L11, L2-2, L2-1, L20, L21, L22; all zero for a NaN, infinite or zero n.
fn envmap_sh9_basis(n: vec3<f32>) -> array<f32, 9> {
    let u = envmap_normalize_direction(n);
    if !u.valid {
        return array<f32, 9>(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    }
    let x = u.dir.x;
    let y = u.dir.y;
    let z = u.dir.z;
    return array<f32, 9>(
        ENVMAP_SH_Y00_CONSTANT,
        ENVMAP_SH_Y1_CONSTANT * y,
        ENVMAP_SH_Y1_CONSTANT * z,
        ENVMAP_SH_Y1_CONSTANT * x,
        ENVMAP_SH_Y2_CONSTANT * (x * y),
        ENVMAP_SH_Y2_CONSTANT * (y * z),
        ENVMAP_SH_Y20_CONSTANT * (3.0 * z * z - 1.0),
        ENVMAP_SH_Y2_CONSTANT * (x * z),
        ENVMAP_SH_Y22_CONSTANT * (x * x - y * y),
    );
}

/// Sh9::eval: the function nine RGB coefficients stand for at n (radiance
/// for radiance coefficients, E for irradiance ones), in the coefficients'
/// axes (sh.json's "radiance" and "irradiance" are in the cube files' axes,
/// its "canonical_radiance" in envmap's z-up ones); zero for a bad n.
fn envmap_sh9_eval(c: array<vec3<f32>, 9>, n: vec3<f32>) -> vec3<f32> {
    let b = envmap_sh9_basis(n);
    var e = vec3<f32>(0.0);
    for (var i = 0u; i < 9u; i++) {
        e += c[i] * b[i];
    }
    return e;
}

/// The irradiance E(n) = sum A_l L_lm Y_lm(n) from radiance coefficients
/// (sh.json's "radiance"): Sh9::irradiance_at(n, IrradianceScale::E).
fn envmap_sh9_irradiance(radiance: array<vec3<f32>, 9>, n: vec3<f32>) -> vec3<f32> {
    let b = envmap_sh9_basis(n);
    let band0 = radiance[0] * b[0];
    let band1 = radiance[1] * b[1] + radiance[2] * b[2] + radiance[3] * b[3];
    var band2 = vec3<f32>(0.0);
    for (var i = 4u; i < 9u; i++) {
        band2 += radiance[i] * b[i];
    }
    return ENVMAP_PI * band0 + ENVMAP_SH_A1_FACTOR * band1 + ENVMAP_QUARTER_PI * band2;
}

/// E(n)/pi from radiance coefficients: Sh9::irradiance_at(n,
/// IrradianceScale::EOverPi), what a diffuse map of envmap's bake holds.
fn envmap_sh9_irradiance_over_pi(radiance: array<vec3<f32>, 9>, n: vec3<f32>) -> vec3<f32> {
    return envmap_sh9_irradiance(radiance, n) * ENVMAP_INV_PI;
}

/// Filament's pre-scaled form (sh.json's "filament", cmgen's sh.txt and
/// KTX "sh" key), E/pi for a unit GL-world direction n (normalised first):
/// sh0 + sh1 y + sh2 z + sh3 x + sh4 yx + sh5 yz + sh6 (3z^2 - 1) + sh7 zx + sh8 (x^2 - y^2).
fn envmap_sh9_filament(sh: array<vec3<f32>, 9>, n: vec3<f32>) -> vec3<f32> {
    let u = envmap_normalize_direction(n);
    if !u.valid {
        return vec3<f32>(0.0);
    }
    let x = u.dir.x;
    let y = u.dir.y;
    let z = u.dir.z;
    return sh[0] + sh[1] * y + sh[2] * z + sh[3] * x + sh[4] * (y * x) + sh[5] * (y * z)
        + sh[6] * (3.0 * z * z - 1.0) + sh[7] * (z * x) + sh[8] * (x * x - y * y);
}

// ---------------------------------------------------------------------------
// Roughness -> mip level (envmap-render/src/filter/specular.rs, RoughnessRule)

/// RoughnessRule::Linear (glTF-IBL-Sampler, Bevy): level = r (levels - 1),
/// r the perceptual roughness clamped to [0, 1].
fn envmap_roughness_to_lod_linear(roughness: f32, levels: f32) -> f32 {
    let r = clamp(roughness, 0.0, 1.0);
    return r * (levels - 1.0);
}

/// RoughnessRule::Filament (perceptualRoughnessToLod): level = r (2 - r) (levels - 1).
fn envmap_roughness_to_lod_filament(roughness: f32, levels: f32) -> f32 {
    let r = clamp(roughness, 0.0, 1.0);
    return r * (2.0 - r) * (levels - 1.0);
}

/// RoughnessRule::Unity (ImageBasedLighting.hlsl): level = r (1.7 - 0.7 r) (levels - 1).
fn envmap_roughness_to_lod_unity(roughness: f32, levels: f32) -> f32 {
    let r = clamp(roughness, 0.0, 1.0);
    return r * (1.7 - 0.7 * r) * (levels - 1.0);
}

// ---------------------------------------------------------------------------
// Directions and the split sum (envmap-render/src/scene/lit.rs)

/// reflect_view: R = 2(N.V)N - V, V from the surface towards the viewer.
fn envmap_reflect_view(n: vec3<f32>, v: vec3<f32>) -> vec3<f32> {
    return 2.0 * dot(n, v) * n - v;
}

/// reflect_incident (GLSL's reflect(I, N)): R = I - 2(N.I)N, I from the eye towards the surface.
fn envmap_reflect_incident(i: vec3<f32>, n: vec3<f32>) -> vec3<f32> {
    return i - 2.0 * dot(n, i) * n;
}

/// The GGX lobe's dominant direction, normalize(mix(R, N, r^2)) (Lagarde &
/// de Rousiers, "Moving Frostbite to PBR", 2014, section 4.9.3; Filament's
/// getSpecularDominantDirection); R itself when that has no length.
fn envmap_specular_dominant_direction(n: vec3<f32>, r: vec3<f32>, roughness: f32) -> vec3<f32> {
    let a = roughness * roughness;
    let d = r * (1.0 - a) + n * a;
    let l2 = dot(d, d);
    if l2 > 0.0 && envmap_all_finite(d) {
        return d * (1.0 / sqrt(l2));
    }
    return r;
}

/// Where LitSampler::shade reads the chain: R, or with `dominant` the
/// dominant direction, for unit n and v at perceptual roughness r (clamped).
fn envmap_specular_direction(n: vec3<f32>, v: vec3<f32>, roughness: f32, dominant: bool) -> vec3<f32> {
    let r = envmap_reflect_view(n, v);
    if dominant {
        return envmap_specular_dominant_direction(n, r, clamp(roughness, 0.0, 1.0));
    }
    return r;
}

/// Material::f0: the reflectance at normal incidence, dielectric_f0 (1 - m) + base m
/// (glTF 2.0: dielectric_f0 = 0.04), metallic m and base clamped to [0, 1].
fn envmap_f0_color(base_color: vec3<f32>, metallic: f32, dielectric_f0: f32) -> vec3<f32> {
    let m = clamp(metallic, 0.0, 1.0);
    return dielectric_f0 * (1.0 - m) + clamp(base_color, vec3<f32>(0.0), vec3<f32>(1.0)) * m;
}

/// Material::diffuse_color: the Lambertian albedo base (1 - metallic).
fn envmap_diffuse_color(base_color: vec3<f32>, metallic: f32) -> vec3<f32> {
    let m = clamp(metallic, 0.0, 1.0);
    return clamp(base_color, vec3<f32>(0.0), vec3<f32>(1.0)) * (1.0 - m);
}

/// The split sum's specular factor from the single-scatter DFG pair
/// dfg = (scale A, bias B) and F0: F0 A + B (Karis 2013), times Filament's
/// energy compensation 1 + F0 (1/(A + B) - 1) when `multiscatter` (and A + B > 0).
fn envmap_split_sum_factor(f0: vec3<f32>, dfg: vec2<f32>, multiscatter: bool) -> vec3<f32> {
    var s = f0 * dfg.x + dfg.y;
    let albedo = dfg.x + dfg.y;
    if multiscatter && albedo > 0.0 {
        s *= 1.0 + f0 * (1.0 / albedo - 1.0);
    }
    return s;
}

/// The same from Filament's multiscatter table dfg = (B, A + B) (what
/// envmap writes as the multiscatter DFG and Filament ships): mix(B, A + B,
/// F0), times 1 + F0 (1/(A + B) - 1) when `multiscatter`.
fn envmap_split_sum_factor_filament(f0: vec3<f32>, dfg: vec2<f32>, multiscatter: bool) -> vec3<f32> {
    var s = mix(vec3<f32>(dfg.x), vec3<f32>(dfg.y), f0);
    if multiscatter && dfg.y > 0.0 {
        s *= 1.0 + f0 * (1.0 / dfg.y - 1.0);
    }
    return s;
}

/// LitSampler's sum for one surface point: c_diff E/pi + LD (F0 A + B) [...]:
/// `diffuse` the Lambertian albedo, `e_over_pi` the irradiance map's value
/// (E/pi), `ld` the chain's value, `dfg` the single-scatter (A, B) at (N.V, r).
fn envmap_split_sum(diffuse: vec3<f32>, f0: vec3<f32>, e_over_pi: vec3<f32>, ld: vec3<f32>, dfg: vec2<f32>, multiscatter: bool) -> vec3<f32> {
    return diffuse * e_over_pi + ld * envmap_split_sum_factor(f0, dfg, multiscatter);
}

/// Where the DFG table is read for N.V and roughness: (u, v) =
/// (clamp(N.V, 1e-4, 1), clamp(r, 0, 1)), the texel centres being at
/// (i + 0.5)/size; a hardware sampler with linear filtering and clamp to
/// edge reads DfgTable::sample_single_scatter's value there.
fn envmap_dfg_uv(n_dot_v: f32, roughness: f32) -> vec2<f32> {
    return vec2<f32>(clamp(n_dot_v, 0.0000999999974737875163555145263671875, 1.0), clamp(roughness, 0.0, 1.0));
}

/// The DFG table's (R, G) at N.V and roughness, bilinear between texel
/// centres and clamped to the outermost ones, from textureLoad: as
/// DfgTable::sample_single_scatter (and sample_multiscatter) on the CPU.
fn envmap_dfg_load(t: texture_2d<f32>, n_dot_v: f32, roughness: f32) -> vec2<f32> {
    let uv = envmap_dfg_uv(n_dot_v, roughness);
    let size = vec2<f32>(textureDimensions(t, 0));
    let x = clamp(uv * size - 0.5, vec2<f32>(0.0), size - 1.0);
    let i0 = vec2<i32>(floor(x));
    let i1 = min(i0 + 1, vec2<i32>(size) - 1);
    let f = x - floor(x);
    let a = textureLoad(t, vec2<i32>(i0.x, i0.y), 0).xy;
    let b = textureLoad(t, vec2<i32>(i1.x, i0.y), 0).xy;
    let c = textureLoad(t, vec2<i32>(i0.x, i1.y), 0).xy;
    let d = textureLoad(t, vec2<i32>(i1.x, i1.y), 0).xy;
    let top = a + f.x * (b - a);
    let bottom = c + f.x * (d - c);
    return top + f.y * (bottom - top);
}

// ---------------------------------------------------------------------------
// Texel reads with each map's edge rule (envmap-render/src/filter/sample.rs)

/// The bilinear footprint of coordinate u in a row of n texels
/// (texel.rs bilinear_footprint): x = u n - 1/2 clamped to [-1/2, n - 1/2];
/// the first texel floor(x) (possibly -1), the second one more (possibly
/// n), and f, the weight of the second.
struct EnvmapFootprint {
    first: i32,
    second: i32,
    f: f32,
}

/// texel.rs bilinear_footprint (for finite u).
fn envmap_bilinear_footprint(u: f32, n: i32) -> EnvmapFootprint {
    let x = clamp(u * f32(n) - 0.5, -0.5, f32(n) - 0.5);
    let t = floor(x);
    return EnvmapFootprint(i32(t), i32(t) + 1, x - t);
}

/// The bilinear blend of four taps as the CPU's sampler makes it: the two
/// columns down first, then across.
fn envmap_blend(a: vec3<f32>, b: vec3<f32>, c: vec3<f32>, d: vec3<f32>, fx: f32, fy: f32) -> vec3<f32> {
    let left = (c - a) * fy + a;
    let right = (d - b) * fy + b;
    return (right - left) * fx + left;
}

/// Texel (i, j) of a latlong level, i and j up to one texel outside: wraps
/// in u, and beyond the top or bottom row continues half a turn round (row
/// -1 is row 0 shifted by w/2).
fn envmap_latlong_texel(t: texture_2d<f32>, i: i32, j: i32, level: i32) -> vec3<f32> {
    let size = vec2<i32>(textureDimensions(t, level));
    var ii = i;
    var jj = j;
    if jj < 0 || jj >= size.y {
        jj = select(2 * size.y - 1 - jj, -1 - jj, jj < 0);
        ii += size.x / 2;
    }
    // ii lies in [-1, 3w/2): one wrap (no %, which GLSL leaves undefined
    // for negative operands).
    if ii < 0 {
        ii += size.x;
    }
    if ii >= size.x {
        ii -= size.x;
    }
    jj = clamp(jj, 0, size.y - 1);
    return textureLoad(t, vec2<i32>(ii, jj), level).xyz;
}

/// A latlong level read bilinearly at (u, v) with the latlong's edge rule,
/// as envmap's CPU sampler reads it.
fn envmap_latlong_bilinear(t: texture_2d<f32>, uv: vec2<f32>, level: i32) -> vec3<f32> {
    let size = vec2<i32>(textureDimensions(t, level));
    let fu = envmap_bilinear_footprint(uv.x, size.x);
    let fv = envmap_bilinear_footprint(uv.y, size.y);
    return envmap_blend(
        envmap_latlong_texel(t, fu.first, fv.first, level),
        envmap_latlong_texel(t, fu.second, fv.first, level),
        envmap_latlong_texel(t, fu.first, fv.second, level),
        envmap_latlong_texel(t, fu.second, fv.second, level),
        fu.f,
        fv.f,
    );
}

/// Texel (i, j) of an octahedral level (either octahedral map), up to one
/// texel outside: folds across the square's edges, where the unfolded
/// octahedron continues (row -1 at column i is row 0 at column w - 1 - i,
/// and the same for columns).
fn envmap_octahedral_texel(t: texture_2d<f32>, i: i32, j: i32, level: i32) -> vec3<f32> {
    let size = vec2<i32>(textureDimensions(t, level));
    var ii = i;
    var jj = j;
    if jj < 0 || jj >= size.y {
        jj = select(2 * size.y - 1 - jj, -1 - jj, jj < 0);
        ii = size.x - 1 - ii;
    }
    if ii < 0 || ii >= size.x {
        ii = select(2 * size.x - 1 - ii, -1 - ii, ii < 0);
        jj = size.y - 1 - jj;
    }
    return textureLoad(t, vec2<i32>(clamp(ii, 0, size.x - 1), clamp(jj, 0, size.y - 1)), level).xyz;
}

/// An octahedral level (either octahedral map) read bilinearly at (u, v)
/// with the fold rule, as envmap's CPU sampler reads it.
fn envmap_octahedral_bilinear(t: texture_2d<f32>, uv: vec2<f32>, level: i32) -> vec3<f32> {
    let size = vec2<i32>(textureDimensions(t, level));
    let fu = envmap_bilinear_footprint(uv.x, size.x);
    let fv = envmap_bilinear_footprint(uv.y, size.y);
    return envmap_blend(
        envmap_octahedral_texel(t, fu.first, fv.first, level),
        envmap_octahedral_texel(t, fu.second, fv.first, level),
        envmap_octahedral_texel(t, fu.first, fv.second, level),
        envmap_octahedral_texel(t, fu.second, fv.second, level),
        fu.f,
        fv.f,
    );
}

/// texel.rs texel_index: the texel holding coordinate u (>= 0) in a row of
/// n, u = 1 included (the last texel).
fn envmap_texel_index(u: f32, n: i32) -> i32 {
    return min(i32(u * f32(n)), n - 1);
}

/// The texel of `face` (a layer of a 2D array view of a cube, GL face
/// order) at (i, j), where exactly one of i, j lies one texel outside the
/// face: the texel of the neighbouring face whose centre the face's plane,
/// extended, points at.
fn envmap_cube_texel_across(t: texture_2d_array<f32>, face: u32, i: i32, j: i32, level: i32) -> vec3<f32> {
    let size = vec2<i32>(textureDimensions(t, level));
    let sc = 2.0 * ((f32(i) + 0.5) / f32(size.x)) - 1.0;
    let tc = 2.0 * ((f32(j) + 0.5) / f32(size.y)) - 1.0;
    let p = envmap_cube_forward(envmap_cube_face_direction(face, sc, tc));
    let k = vec2<i32>(envmap_texel_index(p.uv.x, size.x), envmap_texel_index(p.uv.y, size.y));
    return textureLoad(t, k, i32(p.chart), level).xyz;
}

/// Texel (i, j) of a cube face, i and j up to one texel outside: inside
/// the face its own; across an edge the neighbouring face's, as GL's
/// seamless cube maps do; beyond a corner the average of the three texels
/// that meet there.
fn envmap_cube_texel(t: texture_2d_array<f32>, face: u32, i: i32, j: i32, level: i32) -> vec3<f32> {
    let size = vec2<i32>(textureDimensions(t, level));
    let iout = i < 0 || i >= size.x;
    let jout = j < 0 || j >= size.y;
    let ic = clamp(i, 0, size.x - 1);
    let jc = clamp(j, 0, size.y - 1);
    if iout && jout {
        let a = envmap_cube_texel_across(t, face, i, jc, level);
        let b = envmap_cube_texel_across(t, face, ic, j, level);
        let c = textureLoad(t, vec2<i32>(ic, jc), i32(face), level).xyz;
        return (a + b + c) / 3.0;
    }
    if iout || jout {
        return envmap_cube_texel_across(t, face, i, j, level);
    }
    return textureLoad(t, vec2<i32>(i, j), i32(face), level).xyz;
}

/// A cube level read bilinearly at a chart point (face, s, t), stepping
/// onto the neighbouring faces at the edges as envmap's CPU sampler does.
fn envmap_cube_bilinear(t: texture_2d_array<f32>, c: EnvmapChartUv, level: i32) -> vec3<f32> {
    let size = vec2<i32>(textureDimensions(t, level));
    let fu = envmap_bilinear_footprint(c.uv.x, size.x);
    let fv = envmap_bilinear_footprint(c.uv.y, size.y);
    return envmap_blend(
        envmap_cube_texel(t, c.chart, fu.first, fv.first, level),
        envmap_cube_texel(t, c.chart, fu.second, fv.first, level),
        envmap_cube_texel(t, c.chart, fu.first, fv.second, level),
        envmap_cube_texel(t, c.chart, fu.second, fv.second, level),
        fu.f,
        fv.f,
    );
}

/// The level below a fractional lod and the blend towards the next one
/// (LitSampler's levels_of for levels spaced evenly in lod): (k, t) with k
/// = floor(lod) clamped into [0, levels - 1], t in [0, 1), 0 at the last level.
struct EnvmapLevels {
    level: i32,
    blend: f32,
}

/// The two levels a lod reads (see EnvmapLevels).
fn envmap_levels(lod: f32, levels: i32) -> EnvmapLevels {
    let l = clamp(lod, 0.0, f32(levels - 1));
    let k = min(i32(floor(l)), levels - 1);
    if k + 1 >= levels {
        return EnvmapLevels(k, 0.0);
    }
    return EnvmapLevels(k, l - f32(k));
}

/// A latlong chain (the `levels` mips of one texture; passed in, as
/// GLSL ES 3.00 cannot ask a texture) read at direction `dir` (the
/// latlong's canonical axes: apply a frame first) and fractional level `lod`
/// (envmap_roughness_to_lod_*): bilinear in each of the two levels around
/// lod, linear between them, as LitSampler::specular reads it. Black for an
/// invalid direction.
fn envmap_latlong_chain(t: texture_2d<f32>, levels: i32, dir: vec3<f32>, lod: f32) -> vec3<f32> {
    let c = envmap_latlong_forward(dir);
    if c.chart == ENVMAP_INVALID_CHART {
        return vec3<f32>(0.0);
    }
    let l = envmap_levels(lod, levels);
    let a = envmap_latlong_bilinear(t, c.uv, l.level);
    if l.blend > 0.0 {
        return a + (envmap_latlong_bilinear(t, c.uv, l.level + 1) - a) * l.blend;
    }
    return a;
}

/// envmap_latlong_chain for an octahedral chain.
fn envmap_octahedral_chain(t: texture_2d<f32>, levels: i32, dir: vec3<f32>, lod: f32) -> vec3<f32> {
    let c = envmap_octahedral_forward(dir);
    if c.chart == ENVMAP_INVALID_CHART {
        return vec3<f32>(0.0);
    }
    let l = envmap_levels(lod, levels);
    let a = envmap_octahedral_bilinear(t, c.uv, l.level);
    if l.blend > 0.0 {
        return a + (envmap_octahedral_bilinear(t, c.uv, l.level + 1) - a) * l.blend;
    }
    return a;
}

/// envmap_latlong_chain for an equal-area octahedral chain.
fn envmap_equal_area_octahedral_chain(t: texture_2d<f32>, levels: i32, dir: vec3<f32>, lod: f32) -> vec3<f32> {
    let c = envmap_equal_area_octahedral_forward(dir);
    if c.chart == ENVMAP_INVALID_CHART {
        return vec3<f32>(0.0);
    }
    let l = envmap_levels(lod, levels);
    let a = envmap_octahedral_bilinear(t, c.uv, l.level);
    if l.blend > 0.0 {
        return a + (envmap_octahedral_bilinear(t, c.uv, l.level + 1) - a) * l.blend;
    }
    return a;
}

/// envmap_latlong_chain for a cube chain (a 2D array view of its six
/// layers; the direction as the cube's table takes it, e.g. GL's own).
fn envmap_cube_chain(t: texture_2d_array<f32>, levels: i32, dir: vec3<f32>, lod: f32) -> vec3<f32> {
    let c = envmap_cube_forward(dir);
    if c.chart == ENVMAP_INVALID_CHART {
        return vec3<f32>(0.0);
    }
    let l = envmap_levels(lod, levels);
    let a = envmap_cube_bilinear(t, c, l.level);
    if l.blend > 0.0 {
        return a + (envmap_cube_bilinear(t, c, l.level + 1) - a) * l.blend;
    }
    return a;
}

// ---------------------------------------------------------------------------
// Hardware sampling at a level from the direction's footprint

/// The angle (radians) one pixel's lookup direction spans, from the
/// derivatives of the (unnormalised) direction d across the pixel (in a
/// fragment shader: dpdx(d), dpdy(d); a ray cone's spread elsewhere):
/// |d x dd| / |d|^2 for each, the larger. Continuous wherever d is, so
/// across every seam and fold of every map.
fn envmap_direction_footprint(d: vec3<f32>, ddx: vec3<f32>, ddy: vec3<f32>) -> f32 {
    let l2 = dot(d, d);
    return max(length(cross(d, ddx)), length(cross(d, ddy))) / l2;
}

/// The mip level of a latlong whose level 0 has `height` rows at which a
/// footprint of `angle` radians covers one texel: log2(angle height / pi),
/// at least 0. A row is pi/height tall everywhere; a column's width
/// shrinks as sin(theta) towards the poles, where its texels oversample
/// the sphere, so the rows' size is the one to match.
fn envmap_latlong_lod(angle: f32, height: f32) -> f32 {
    return max(log2(angle * height / ENVMAP_PI), 0.0);
}

/// The mip level of an octahedral map of `size`^2 texels at level 0 for a
/// footprint of `angle` radians at direction dir: a texel there spans
/// about 2 / (size |p|^(3/2)) radians, p = dir / (|x| + |y| + |z|) (the
/// area element du' dv' / |p|^3), from 2/size on the axes to 4.56/size at
/// the octants' centres.
fn envmap_octahedral_lod(dir: vec3<f32>, angle: f32, size: f32) -> f32 {
    let a = abs(dir);
    let p = length(dir) / (a.x + a.y + a.z);
    let texel = 2.0 / (size * p * sqrt(p));
    return max(log2(angle / texel), 0.0);
}

/// The mip level of an equal-area octahedral map of `size`^2 texels: every
/// texel spans 4 pi / size^2 steradians, about sqrt(4 pi)/size radians.
fn envmap_equal_area_octahedral_lod(angle: f32, size: f32) -> f32 {
    return max(log2(angle * size / 3.5449077018110318), 0.0);
}

/// A latlong sampled by the hardware at direction dir (canonical axes) and
/// mip level lod (envmap_latlong_lod): textureSampleLevel, no derivatives
/// of (u, v), so no seam line. The sampler: linear filtering, u repeat
/// (the seam is continuous), v clamp to edge.
fn envmap_latlong_sample_level(t: texture_2d<f32>, s: sampler, dir: vec3<f32>, lod: f32) -> vec4<f32> {
    return textureSampleLevel(t, s, envmap_latlong_forward(dir).uv, lod);
}

/// An octahedral map sampled by the hardware at dir and lod
/// (envmap_octahedral_lod); the sampler clamps to the edge.
fn envmap_octahedral_sample_level(t: texture_2d<f32>, s: sampler, dir: vec3<f32>, lod: f32) -> vec4<f32> {
    return textureSampleLevel(t, s, envmap_octahedral_forward(dir).uv, lod);
}

/// An equal-area octahedral map sampled by the hardware at dir and lod
/// (envmap_equal_area_octahedral_lod); the sampler clamps to the edge.
fn envmap_equal_area_octahedral_sample_level(t: texture_2d<f32>, s: sampler, dir: vec3<f32>, lod: f32) -> vec4<f32> {
    return textureSampleLevel(t, s, envmap_equal_area_octahedral_forward(dir).uv, lod);
}
