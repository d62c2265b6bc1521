//! Tier 1 of the shader tests, the lighting lookups (`lighting.wgsl`) on a
//! Vulkan device (Mesa's lavapipe in CI) through wgpu, against envmap-render
//! on the CPU, outputs pre-filled with NaN:
//!
//! * SH9: `envmap_sh9_irradiance`, `_over_pi`, `envmap_sh9_eval` and
//!   Filament's pre-scaled form against `Sh9::irradiance_at` (E and E/π)
//!   over 10⁴ directions for the built-in sky's coefficients and 20 random
//!   sets: within 10⁻⁶ relative ([`SH_BOUND`]);
//! * roughness → level for the linear, Filament and Unity rules against the
//!   formulas in f64 and against `RoughnessRule::roughness` at every level;
//! * the split sum of a pixel: a cube mip chain baked by `LitEnvironment::bake_with`
//!   from the built-in sky (and the same levels converted to latlong,
//!   octahedral and equal-area octahedral chains), its irradiance cube and
//!   DFG table read by the shipped WGSL (`envmap_*_chain`,
//!   `envmap_cube_chain` for the irradiance, `envmap_dfg_load`,
//!   `envmap_split_sum`) for six materials, with and without multiscatter
//!   and the dominant direction, against `LitSampler::shade`: within 10⁻⁴
//!   relative per channel ([`PIXEL_BOUND`]).
//!
//! `cargo test --release -p envmap-tests --test shader_lighting_gpu --
//! --nocapture` prints the worst cases and where they occur.

mod gpu;

use envmap_core::atlas::Atlas;
use envmap_core::shaders::ALL_WGSL;
use envmap_core::{AnyMapping, Frame};
use envmap_render::filter::bake::BakeOptions;
use envmap_render::filter::sh::{IrradianceScale, Sh9, ShKind};
use envmap_render::filter::specular::RoughnessRule;
use envmap_render::image::FileAxes;
use envmap_render::scene::Builtin;
use envmap_render::scene::Material;
use envmap_render::scene::{LevelBlend, LitEnvironment};
use envmap_render::{
    filter::{convert, ConvertOptions},
    image::{EnvImage, Representation},
};
use envmap_tests::{uniform_direction, SplitMix64};
use glam::Vec3;
use gpu::{bytes_f32, f32s, gpu, Binding, Gpu, Level, INDEX_WGSL};

/// SH9 irradiance within this of the CPU, relative.
const SH_BOUND: f64 = 1e-6;
/// A lit pixel within this of `LitSampler::shade`, relative, per channel.
const PIXEL_BOUND: f64 = 1e-4;

fn fibonacci(n: usize) -> Vec<Vec3> {
    let golden = (1.0 + 5f64.sqrt()) / 2.0;
    (0..n)
        .map(|k| {
            uniform_direction((k as f64 + 0.5) / n as f64, (k as f64 / golden).fract()).as_vec3()
        })
        .collect()
}

fn sky_cube(face: u32) -> EnvImage {
    let repr = Representation::for_file(AnyMapping::Cube, FileAxes::default());
    Builtin::Sky
        .image(repr, 4 * face, 3 * face)
        .expect("the built-in sky")
}

/// `sh` with every coefficient rounded to f32 (what the device is given).
fn rounded(sh: &Sh9) -> Sh9 {
    Sh9 {
        coeffs: sh.coeffs.map(|c| c.map(|v| f64::from(v as f32))),
        kind: sh.kind,
    }
}

/// The relative error of `got`; infinite when it is NaN or infinite (a
/// write the device dropped leaves the NaN the output started as).
fn rel(got: f32, want: f64) -> f64 {
    if !got.is_finite() {
        return f64::INFINITY;
    }
    (f64::from(got) - want).abs() / want.abs().max(1e-30)
}

#[test]
fn sh9_irradiance_on_the_gpu() {
    let g = gpu("shader SH9");
    let mut sets = vec![(
        "the built-in sky".to_string(),
        rounded(&Sh9::project(&sky_cube(64))),
    )];
    let mut rng = SplitMix64::new(9);
    for k in 0..20 {
        let l00 = 1.0 + rng.next_f64();
        let mut c = [[0.0f64; 3]; 9];
        for (i, ci) in c.iter_mut().enumerate() {
            for v in ci.iter_mut() {
                *v = if i == 0 {
                    l00
                } else {
                    (rng.next_f64() - 0.5) * 0.2 * l00
                };
            }
        }
        sets.push((
            format!("random set {k}"),
            rounded(&Sh9 {
                coeffs: c,
                kind: ShKind::Radiance,
            }),
        ));
    }
    let mut dirs = fibonacci(10_000);
    dirs.extend([
        Vec3::X,
        Vec3::NEG_X,
        Vec3::Y,
        Vec3::NEG_Y,
        Vec3::Z,
        Vec3::NEG_Z,
        Vec3::new(3.0, -4.0, 12.0),
    ]);
    let src = format!(
        "{ALL_WGSL}\n{INDEX_WGSL}
@group(0) @binding(0) var<storage, read> dirs: array<vec4<f32>>;
@group(0) @binding(1) var<uniform> sh: array<vec4<f32>, 27>;
@group(0) @binding(2) var<storage, read_write> out: array<vec4<f32>>;

fn coeffs(base: u32) -> array<vec3<f32>, 9> {{
    var c: array<vec3<f32>, 9>;
    for (var i = 0u; i < 9u; i++) {{
        c[i] = sh[base + i].xyz;
    }}
    return c;
}}

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {{
    let i = test_index(gid);
    if i >= arrayLength(&dirs) {{
        return;
    }}
    let n = dirs[i].xyz;
    out[4u * i] = vec4<f32>(envmap_sh9_irradiance(coeffs(0u), n), 0.0);
    out[4u * i + 1u] = vec4<f32>(envmap_sh9_irradiance_over_pi(coeffs(0u), n), 0.0);
    out[4u * i + 2u] = vec4<f32>(envmap_sh9_eval(coeffs(9u), n), 0.0);
    // Filament's form is in GL axes: n there is (x, z, -y) of the canonical n.
    out[4u * i + 3u] = vec4<f32>(envmap_sh9_filament(coeffs(18u), vec3<f32>(n.x, n.z, -n.y)), 0.0);
}}
"
    );
    let dir_bytes = bytes_f32(
        &dirs
            .iter()
            .flat_map(|d| [d.x, d.y, d.z, 0.0])
            .collect::<Vec<_>>(),
    );
    let names = [
        "E (envmap_sh9_irradiance)",
        "E/π (…_over_pi)",
        "E (envmap_sh9_eval of E_lm)",
        "E/π (envmap_sh9_filament)",
    ];
    let mut worst: [(f64, String); 4] = Default::default();
    for (name, sh) in &sets {
        let irr = sh.irradiance();
        let fil = sh.filament_shader_form();
        let mut uni = Vec::new();
        for c in sh.coeffs.iter().chain(&irr.coeffs) {
            uni.extend([c[0] as f32, c[1] as f32, c[2] as f32, 0.0]);
        }
        for c in &fil {
            uni.extend([c[0] as f32, c[1] as f32, c[2] as f32, 0.0]);
        }
        let out = g.run(
            &src,
            "main",
            &[
                Binding::Input(&dir_bytes),
                Binding::Uniform(&bytes_f32(&uni)),
                Binding::Output(64 * dirs.len() as u64),
            ],
            dirs.len() as u32,
        );
        let out = f32s(&out[0]);
        // The references: the CPU's functions of the same (f32) coefficients,
        // in f64; Filament's form from its f32 values, evaluated in f64.
        let fil32 = Sh9 {
            coeffs: fil.map(|c| c.map(|v| f64::from(v as f32))),
            kind: ShKind::Irradiance,
        };
        for (k, &n) in dirs.iter().enumerate() {
            let gl = Frame::Y_UP_RH.from_canonical(n);
            let (x, y, z) = (f64::from(gl.x), f64::from(gl.y), f64::from(gl.z));
            let l = (x * x + y * y + z * z).sqrt();
            let (x, y, z) = (x / l, y / l, z / l);
            let poly = [
                1.0,
                y,
                z,
                x,
                y * x,
                y * z,
                3.0 * z * z - 1.0,
                z * x,
                x * x - y * y,
            ];
            let filament: [f64; 3] =
                core::array::from_fn(|c| (0..9).map(|i| fil32.coeffs[i][c] * poly[i]).sum());
            let e = sh.irradiance().eval_f64(to64(n));
            let wants = [
                e,
                e.map(|v| v / std::f64::consts::PI),
                irr.eval_f64(to64(n)),
                filament,
            ];
            // E/π from the CPU's own function too: the filament form must
            // mean the same irradiance.
            let cpu_over_pi = sh.irradiance_at(n, IrradianceScale::EOverPi);
            for (j, want) in wants.iter().enumerate() {
                for c in 0..3 {
                    let got = out[16 * k + 4 * j + c];
                    let e = rel(got, want[c]);
                    if e > worst[j].0 {
                        worst[j] = (
                            e,
                            format!(
                                "{name}, n = {n}, channel {c}: CPU {:.9e}, device {got:.9e}",
                                want[c]
                            ),
                        );
                    }
                }
            }
            for c in 0..3 {
                let got = out[16 * k + 12 + c];
                assert!(
                    rel(got, f64::from(cpu_over_pi[c])) < 2e-6,
                    "{name}: Filament's form at {n}: {got} against irradiance_at's {}",
                    cpu_over_pi[c]
                );
            }
        }
    }
    for (name, (e, at)) in names.iter().zip(&worst) {
        println!("SH9 {name}: worst relative error {e:.3e} at {at}");
    }
    for (name, (e, at)) in names.iter().zip(&worst) {
        assert!(*e <= SH_BOUND, "SH9 {name}: {e:.3e} > {SH_BOUND:e} at {at}");
    }
}

fn to64(v: Vec3) -> [f64; 3] {
    [f64::from(v.x), f64::from(v.y), f64::from(v.z)]
}

#[test]
fn roughness_rules_on_the_gpu() {
    let g = gpu("shader roughness rules");
    let level_counts = [2u32, 5, 8, 10, 12];
    // (roughness, levels) pairs: a fine grid, and each rule's level roughness.
    let mut input: Vec<[f32; 2]> = Vec::new();
    for &n in &level_counts {
        for k in 0..=4096 {
            input.push([k as f32 / 4096.0, n as f32]);
        }
        for rule in [
            RoughnessRule::Linear,
            RoughnessRule::Filament,
            RoughnessRule::Unity,
        ] {
            for k in 0..n as usize {
                input.push([rule.roughness(k, n as usize), n as f32]);
            }
        }
    }
    let src = format!(
        "{ALL_WGSL}\n{INDEX_WGSL}
@group(0) @binding(0) var<storage, read> rn: array<vec2<f32>>;
@group(0) @binding(1) var<storage, read_write> out: array<vec4<f32>>;
@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {{
    let i = test_index(gid);
    if i >= arrayLength(&rn) {{
        return;
    }}
    let p = rn[i];
    out[i] = vec4<f32>(envmap_roughness_to_lod_linear(p.x, p.y), envmap_roughness_to_lod_filament(p.x, p.y), envmap_roughness_to_lod_unity(p.x, p.y), 0.0);
}}
"
    );
    let bytes = bytes_f32(&input.iter().flatten().copied().collect::<Vec<_>>());
    let out = g.run(
        &src,
        "main",
        &[
            Binding::Input(&bytes),
            Binding::Output(16 * input.len() as u64),
        ],
        input.len() as u32,
    );
    let out = f32s(&out[0]);
    let formulas: [fn(f64) -> f64; 3] = [|r| r, |r| r * (2.0 - r), |r| r * (1.7 - 0.7 * r)];
    let names = ["linear", "filament", "unity"];
    let mut worst: [(f64, String); 3] = Default::default();
    for (k, &[r, n]) in input.iter().enumerate() {
        for j in 0..3 {
            let want = formulas[j](f64::from(r)) * (f64::from(n) - 1.0);
            let got = f64::from(out[4 * k + j]);
            let e = if got.is_finite() {
                (got - want).abs()
            } else {
                f64::INFINITY
            };
            if e > worst[j].0 {
                worst[j] = (
                    e,
                    format!("r = {r}, {n} levels: {want:.9} against {got:.9}"),
                );
            }
        }
    }
    for (name, (e, at)) in names.iter().zip(&worst) {
        println!("roughness → level, {name}: worst |Δlevel| {e:.3e} at {at}");
        assert!(*e < 4e-6, "{name}: {e} at {at}");
    }
    // Each rule's own levels come back as whole levels.
    let mut at_levels = 0.0f64;
    for (k, &[r, n]) in input.iter().enumerate() {
        for (j, rule) in [
            RoughnessRule::Linear,
            RoughnessRule::Filament,
            RoughnessRule::Unity,
        ]
        .iter()
        .enumerate()
        {
            for level in 0..n as usize {
                if rule.roughness(level, n as usize) == r {
                    let got = f64::from(out[4 * k + j]);
                    let e = (got - level as f64).abs();
                    at_levels = if e.is_nan() {
                        f64::INFINITY
                    } else {
                        at_levels.max(e)
                    };
                }
            }
        }
    }
    println!(
        "roughness → level at each rule's own level roughness: within {at_levels:.3e} of the level"
    );
    assert!(at_levels < 1e-5, "{at_levels}");
    // What the engines' formulas differ from LitSampler's levels_of between
    // levels (linear in roughness between the levels' roughness), on the CPU.
    for (j, rule) in [RoughnessRule::Filament, RoughnessRule::Unity]
        .iter()
        .enumerate()
    {
        let mut most = 0.0f64;
        for &n in &level_counts {
            let rs: Vec<f64> = (0..n as usize)
                .map(|k| f64::from(rule.roughness(k, n as usize)))
                .collect();
            for s in 0..=10_000 {
                let r = f64::from(s) / 10_000.0;
                let k = rs
                    .partition_point(|&x| x <= r)
                    .saturating_sub(1)
                    .min(rs.len() - 2);
                let t = ((r - rs[k]) / (rs[k + 1] - rs[k])).clamp(0.0, 1.0);
                let piecewise = k as f64 + t;
                most = most.max((piecewise - formulas[j + 1](r) * (f64::from(n) - 1.0)).abs());
            }
        }
        println!("{}: the formula against LitSampler's piecewise-linear levels_of: at most {most:.3} levels apart between levels (2-12 levels)", names[j + 1]);
    }
}

// ---------------------------------------------------------------------------
// The split sum of a pixel

/// The texels of chart `chart` of `img` (row 0 first) as RGBA.
fn chart_texels(img: &EnvImage, chart: u32) -> (u32, u32, Vec<[f32; 4]>) {
    let (w, h) = img.cell_size();
    let mut t = Vec::with_capacity((w * h) as usize);
    for j in 0..h {
        for i in 0..w {
            let [r, g, b] = img.chart_texel(chart, i, j).expect("a texel of the chart");
            t.push([r, g, b, 1.0]);
        }
    }
    (w, h, t)
}

/// The chain's levels (or one map) as a texture: a 2D array of six layers
/// for a cube, a 2D texture otherwise.
fn upload(g: &Gpu, levels: &[EnvImage]) -> wgpu::TextureView {
    let cube = levels[0].mapping() == AnyMapping::Cube;
    let layers = if cube { 6 } else { 1 };
    let ls: Vec<Level> = levels
        .iter()
        .map(|img| {
            let mut texels = Vec::new();
            let mut size = (0, 0);
            for chart in 0..layers {
                let (w, h, t) = chart_texels(img, chart);
                size = (w, h);
                texels.extend(t);
            }
            Level {
                width: size.0,
                height: size.1,
                texels,
            }
        })
        .collect();
    g.texture(&ls, layers, cube)
}

/// `levels` converted to `mapping` (a square of twice the face size for
/// the octahedral maps, 4:2 for the latlong), in the same axes.
fn converted(levels: &[EnvImage], mapping: AnyMapping) -> Vec<EnvImage> {
    levels
        .iter()
        .map(|l| {
            let s = l.cell_size().0;
            let (atlas, w, h) = match mapping {
                AnyMapping::LatLong => (Atlas::LATLONG, 4 * s, 2 * s),
                _ => (Atlas::SINGLE_SQUARE, 2 * s, 2 * s),
            };
            let repr = Representation::new(mapping, atlas, l.representation().frame)
                .expect("a representation");
            convert(l, repr, w, h, &ConvertOptions::default(), None).expect("a conversion")
        })
        .collect()
}

#[test]
fn split_sum_of_a_pixel_against_lit_sampler() {
    let g = gpu("shader split sum");
    let t0 = std::time::Instant::now();
    // A mip chain as `envmap bake` makes for engines (the linear rule,
    // the DFG table at texel centres), read blended linearly in roughness
    // as a GPU's trilinear filter reads it.
    let mut opts = BakeOptions::default();
    (opts.size, opts.irradiance_size, opts.dfg_size) = (32, 32, 64);
    let baked = LitEnvironment::bake_with(&sky_cube(64), &opts).expect("a bake");
    println!(
        "baked a {}-level chain from 32² in {:.2} s",
        baked.levels().len(),
        t0.elapsed().as_secs_f64()
    );
    let dfg = baked.dfg();
    let n = dfg.size();
    let dfg_texels: Vec<[f32; 4]> = dfg
        .single_scatter_texels()
        .iter()
        .map(|&[a, b]| [a, b, 0.0, 0.0])
        .collect();
    let dfg_view = g.texture(
        &[Level {
            width: n,
            height: n,
            texels: dfg_texels,
        }],
        1,
        false,
    );
    let irr_view = upload(&g, std::slice::from_ref(baked.irradiance()));
    // Pixels: normals over the sphere, view vectors in their hemisphere
    // (some grazing, some head-on).
    let mut rng = SplitMix64::new(77);
    let mut pixels: Vec<(Vec3, Vec3)> = Vec::new();
    for k in 0..4096 {
        let nrm = rng.direction();
        let v = match k % 8 {
            0 => nrm,
            1 => {
                let t = nrm.cross(rng.direction()).normalize();
                (t + nrm * 1e-3).normalize()
            }
            _ => {
                let d = rng.direction();
                if d.dot(nrm) > 0.0 {
                    d
                } else {
                    -d
                }
            }
        };
        if v.dot(nrm) > 0.0 {
            pixels.push((nrm, v));
        }
    }
    let px_bytes = bytes_f32(
        &pixels
            .iter()
            .flat_map(|(nn, v)| [nn.x, nn.y, nn.z, 0.0, v.x, v.y, v.z, 0.0])
            .collect::<Vec<_>>(),
    );
    let materials: Vec<(&str, Material)> =
        ["mirror", "chrome", "gold", "plastic", "rubber", "diffuse"]
            .iter()
            .map(|&m| (m, Material::preset(m).expect("a preset")))
            .collect();
    let chains = [
        (
            "cube",
            AnyMapping::Cube,
            "envmap_cube_chain",
            "texture_2d_array<f32>",
        ),
        (
            "latlong",
            AnyMapping::LatLong,
            "envmap_latlong_chain",
            "texture_2d<f32>",
        ),
        (
            "octahedral",
            AnyMapping::Octahedral,
            "envmap_octahedral_chain",
            "texture_2d<f32>",
        ),
        (
            "octahedral-equal-area",
            AnyMapping::EqualAreaOctahedral,
            "envmap_equal_area_octahedral_chain",
            "texture_2d<f32>",
        ),
    ];
    let mut overall = (0.0f64, String::new());
    for (name, mapping, chain_fn, chain_ty) in chains {
        let levels = if mapping == AnyMapping::Cube {
            baked.levels().to_vec()
        } else {
            converted(baked.levels(), mapping)
        };
        let env = LitEnvironment::new(
            levels.clone(),
            baked.roughness().to_vec(),
            baked.irradiance().clone(),
            baked.irradiance_scale(),
            dfg.clone(),
        )
        .expect("a lit environment")
        .with_blend(LevelBlend::Roughness);
        assert_eq!(env.irradiance_scale(), IrradianceScale::EOverPi);
        let sampler = env.sampler();
        let chain_view = upload(&g, &levels);
        let to_map = levels[0].representation().frame.matrix().transpose();
        let src = format!(
            "{ALL_WGSL}\n{INDEX_WGSL}
struct Params {{
    to_map: array<vec4<f32>, 3>,
    base: vec4<f32>,
    misc: vec4<f32>,
}}
@group(0) @binding(0) var<storage, read> px: array<vec4<f32>>;
@group(0) @binding(1) var<uniform> params: Params;
@group(0) @binding(2) var chain: {chain_ty};
@group(0) @binding(3) var irradiance: texture_2d_array<f32>;
@group(0) @binding(4) var dfg: texture_2d<f32>;
@group(0) @binding(5) var<storage, read_write> out: array<vec4<f32>>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {{
    let i = test_index(gid);
    if i >= arrayLength(&px) / 2u {{
        return;
    }}
    let n = px[2u * i].xyz;
    let v = px[2u * i + 1u].xyz;
    let to_map = mat3x3<f32>(params.to_map[0].xyz, params.to_map[1].xyz, params.to_map[2].xyz);
    let roughness = clamp(params.misc.x, 0.0, 1.0);
    let levels = i32(params.misc.z);
    let flags = u32(params.misc.w);
    let multiscatter = (flags & 1u) != 0u;
    let dominant = (flags & 2u) != 0u;
    let dir = envmap_specular_direction(n, v, roughness, dominant);
    let lod = envmap_roughness_to_lod_linear(roughness, f32(levels));
    let ld = {chain_fn}(chain, levels, to_map * dir, lod);
    let e = envmap_cube_chain(irradiance, 1, to_map * n, 0.0);
    let ab = envmap_dfg_load(dfg, dot(n, v), roughness);
    let f0 = envmap_f0_color(params.base.xyz, params.base.w, params.misc.y);
    let diffuse = envmap_diffuse_color(params.base.xyz, params.base.w);
    out[i] = vec4<f32>(envmap_split_sum(diffuse, f0, e, ld, ab, multiscatter), 0.0);
}}
"
        );
        let mut worst = (0.0f64, String::new());
        for (mname, m) in &materials {
            for (multiscatter, dominant) in [(false, true), (true, true), (false, false)] {
                let flags = u32::from(multiscatter) | (u32::from(dominant) << 1);
                let c = to_map.to_cols_array_2d();
                let uni: Vec<f32> = vec![
                    c[0][0],
                    c[0][1],
                    c[0][2],
                    0.0,
                    c[1][0],
                    c[1][1],
                    c[1][2],
                    0.0,
                    c[2][0],
                    c[2][1],
                    c[2][2],
                    0.0,
                    m.base_color[0],
                    m.base_color[1],
                    m.base_color[2],
                    m.metallic,
                    m.roughness,
                    m.dielectric_f0,
                    levels.len() as f32,
                    flags as f32,
                ];
                let out = g.run(
                    &src,
                    "main",
                    &[
                        Binding::Input(&px_bytes),
                        Binding::Uniform(&bytes_f32(&uni)),
                        Binding::Texture(&chain_view),
                        Binding::Texture(&irr_view),
                        Binding::Texture(&dfg_view),
                        Binding::Output(16 * pixels.len() as u64),
                    ],
                    pixels.len() as u32,
                );
                let out = f32s(&out[0]);
                for (k, &(nrm, v)) in pixels.iter().enumerate() {
                    let want = sampler.shade(m, nrm, v, multiscatter, dominant);
                    for ch in 0..3 {
                        let got = out[4 * k + ch];
                        let e = rel(got, f64::from(want[ch]));
                        if e > worst.0 {
                            worst = (
                                e,
                                format!(
                                    "{mname} (multiscatter {multiscatter}, dominant {dominant}), n = {nrm}, v = {v}, channel {ch}: shade {:.7e}, device {got:.7e}",
                                    want[ch]
                                ),
                            );
                        }
                    }
                }
            }
        }
        println!("split sum, {name} chain ({} levels, {} pixels × 6 materials × 3 settings): worst relative error {:.3e} at {}", levels.len(), pixels.len(), worst.0, worst.1);
        if worst.0 > overall.0 {
            overall = (worst.0, format!("{name} chain: {}", worst.1));
        }
    }
    assert!(
        overall.0 <= PIXEL_BOUND,
        "a lit pixel {:.3e} from LitSampler::shade: {}",
        overall.0,
        overall.1
    );
}
