//! Tier 1 of the shader tests, the hardware-sampling helpers of
//! `lighting.wgsl` in a real fragment shader (a render pass on lavapipe in
//! CI): a mip level chosen from the lookup direction's own footprint
//! (`envmap_direction_footprint` of `dpdx(d)`, `dpdy(d)`, then
//! `envmap_latlong_lod` / `envmap_octahedral_lod` /
//! `envmap_equal_area_octahedral_lod`, read by `envmap_*_sample_level`)
//! against the level the pixel's footprint asks for, computed on the CPU
//! from the same directions.
//!
//! Each mip level k of the test maps holds the value k, so a trilinear
//! read returns the level the hardware used. Views look across a latlong's
//! seam (+x) and into its pole (+z), and into an octahedral map's lower
//! pole (−z), where its four folds meet. The helpers must follow the
//! expected level within 0.05 everywhere and change by at most 0.05
//! between neighbouring pixels (no line, no wedge). The same pixels read
//! with `textureSample` (the level from the screen-space derivatives of
//! (u, v)) are printed beside them: the seam's one-pixel line at a far
//! coarser level and the pole's wedges, the artifacts the helpers remove.

mod gpu;

use envmap_core::shaders::ALL_WGSL;
use glam::DVec3;
use gpu::{gpu, Binding, Gpu, Level};

const SIZE: u32 = 64;
const FOV_DEG: f64 = 60.0;

/// A texture whose level k (of `levels`, level 0 `w × h`) holds k everywhere.
fn level_probe(g: &Gpu, w: u32, h: u32, levels: u32) -> wgpu::TextureView {
    let ls: Vec<Level> = (0..levels)
        .map(|k| {
            let (lw, lh) = ((w >> k).max(1), (h >> k).max(1));
            Level {
                width: lw,
                height: lh,
                texels: vec![[k as f32, 0.0, 0.0, 1.0]; (lw * lh) as usize],
            }
        })
        .collect();
    g.texture(&ls, 1, false)
}

/// The camera: pixel (x, y)'s direction, unnormalised, in f64.
fn pixel_dir(forward: DVec3, right: DVec3, up: DVec3, x: f64, y: f64) -> DVec3 {
    let t = (FOV_DEG.to_radians() / 2.0).tan();
    let h = f64::from(SIZE) / 2.0;
    let sx = (x + 0.5 - h) / h * t;
    let sy = -(y + 0.5 - h) / h * t;
    forward + right * sx + up * sy
}

/// The angular footprint of pixel (x, y) as the helper computes it from
/// the derivatives (one-pixel differences of the direction), in f64.
fn footprint(cam: (DVec3, DVec3, DVec3), x: u32, y: u32) -> f64 {
    let (f, r, u) = cam;
    let d = pixel_dir(f, r, u, f64::from(x), f64::from(y));
    let dx = pixel_dir(f, r, u, f64::from(x) + 1.0, f64::from(y));
    let dy = pixel_dir(f, r, u, f64::from(x), f64::from(y) + 1.0);
    let (ddx, ddy) = (dx - d, dy - d);
    d.cross(ddx).length().max(d.cross(ddy).length()) / d.length_squared()
}

struct View {
    name: &'static str,
    cam: (DVec3, DVec3, DVec3),
}

/// A map under test: its level probe, sampler, helpers and expectation.
struct Map<'a> {
    /// "latlong", "octahedral" or "equal-area octahedral".
    name: &'a str,
    texture: &'a wgpu::TextureView,
    sampler: &'a wgpu::Sampler,
    /// The level, a WGSL expression of `fp` (the footprint) and `d`.
    lod_expr: &'a str,
    /// The WGSL sampling helper.
    sample_fn: &'a str,
    /// The level a pixel of direction `d` and footprint `fp` asks for.
    expected: &'a dyn Fn(DVec3, f64) -> f64,
    /// The last level.
    max_level: f64,
}

/// Renders `views` of `m` and checks its helpers against `m.expected`.
fn check_map(g: &Gpu, m: &Map<'_>, views: &[View]) {
    let Map {
        name: map,
        texture,
        sampler,
        lod_expr,
        sample_fn,
        expected,
        max_level,
    } = *m;
    for v in views {
        let (f, r, u) = v.cam;
        let vec = |a: DVec3| format!("vec3<f32>({:.9}, {:.9}, {:.9})", a.x, a.y, a.z);
        let src = format!(
            "{ALL_WGSL}
@group(0) @binding(0) var t: texture_2d<f32>;
@group(0) @binding(1) var s: sampler;

@vertex
fn vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {{
    let p = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    return vec4<f32>(p * 2.0 - 1.0, 0.0, 1.0);
}}

@fragment
fn fs(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {{
    let tan_half = {tan:.9};
    let h = {half:.1};
    let sx = (pos.x - h) / h * tan_half;
    let sy = -(pos.y - h) / h * tan_half;
    let d = {f} + {r} * sx + {u} * sy;
    let fp = envmap_direction_footprint(d, dpdx(d), dpdy(d));
    let lod = {lod_expr};
    let ours = {sample_fn}(t, s, d, lod).x;
    // The naive read: the level from the screen-space derivatives of (u, v).
    let naive = textureSample(t, s, {forward}(d).uv).x;
    return vec4<f32>(ours, lod, naive, fp);
}}
",
            tan = (FOV_DEG.to_radians() / 2.0).tan(),
            half = f64::from(SIZE) / 2.0,
            f = vec(f),
            r = vec(r),
            u = vec(u),
            forward = if map == "latlong" {
                "envmap_latlong_forward"
            } else if map == "octahedral" {
                "envmap_octahedral_forward"
            } else {
                "envmap_equal_area_octahedral_forward"
            },
        );
        let px = g.render(
            &src,
            &[Binding::Texture(texture), Binding::Sampler(sampler)],
            SIZE,
            SIZE,
        );
        let at = |x: u32, y: u32| px[(y * SIZE + x) as usize];
        let (mut worst_lod, mut worst_read, mut jump, mut naive_jump) = (
            (0.0f64, (0, 0)),
            (0.0f64, (0, 0)),
            (0.0f64, (0, 0)),
            (0.0f64, (0, 0)),
        );
        let (mut naive_lo, mut naive_hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for y in 0..SIZE {
            for x in 0..SIZE {
                let [ours, lod, naive, _] = at(x, y);
                let d = pixel_dir(f, r, u, f64::from(x), f64::from(y));
                let want = expected(d, footprint(v.cam, x, y)).clamp(0.0, max_level);
                let e_lod = (f64::from(lod).clamp(0.0, max_level) - want).abs();
                let e_read = (f64::from(ours) - want).abs();
                let e_lod = if e_lod.is_nan() { f64::INFINITY } else { e_lod };
                let e_read = if e_read.is_nan() {
                    f64::INFINITY
                } else {
                    e_read
                };
                if e_lod > worst_lod.0 {
                    worst_lod = (e_lod, (x, y));
                }
                if e_read > worst_read.0 {
                    worst_read = (e_read, (x, y));
                }
                naive_lo = naive_lo.min(f64::from(naive));
                naive_hi = naive_hi.max(f64::from(naive));
                for (nx, ny) in [(x + 1, y), (x, y + 1)] {
                    if nx < SIZE && ny < SIZE {
                        let j = (f64::from(at(nx, ny)[0]) - f64::from(ours)).abs();
                        let j = if j.is_nan() { f64::INFINITY } else { j };
                        if j > jump.0 {
                            jump = (j, (x, y));
                        }
                        let nj = (f64::from(at(nx, ny)[2]) - f64::from(naive)).abs();
                        if nj > naive_jump.0 {
                            naive_jump = (nj, (x, y));
                        }
                    }
                }
            }
        }
        println!(
            "{map}, {}: footprint level within {:.2e} of the expected (at pixel {:?}), the read {:.2e} (at {:?}); largest step between neighbours {:.4} (at {:?})",
            v.name, worst_lod.0, worst_lod.1, worst_read.0, worst_read.1, jump.0, jump.1
        );
        println!(
            "    naive textureSample: levels {naive_lo:.2} to {naive_hi:.2}, largest step between neighbours {:.2} (at {:?})",
            naive_jump.0, naive_jump.1
        );
        assert!(
            worst_lod.0 <= 0.05,
            "{map}, {}: level {} off at {:?}",
            v.name,
            worst_lod.0,
            worst_lod.1
        );
        assert!(
            worst_read.0 <= 0.05,
            "{map}, {}: read {} off at {:?}",
            v.name,
            worst_read.0,
            worst_read.1
        );
        assert!(
            jump.0 <= 0.05,
            "{map}, {}: a step of {} levels at {:?}",
            v.name,
            jump.0,
            jump.1
        );
    }
}

#[test]
fn footprint_levels_have_no_seam_line_and_no_pole_wedges() {
    let g = gpu("shader sampling");
    let linear = wgpu::FilterMode::Linear;
    let sampler = |u: wgpu::AddressMode, v: wgpu::AddressMode| {
        g.device.create_sampler(&wgpu::SamplerDescriptor {
            address_mode_u: u,
            address_mode_v: v,
            mag_filter: linear,
            min_filter: linear,
            mipmap_filter: wgpu::MipmapFilterMode::Linear,
            ..wgpu::SamplerDescriptor::default()
        })
    };
    // A 1024 × 512 latlong (11 levels); u repeats, v clamps.
    let latlong = level_probe(&g, 1024, 512, 11);
    let ll_sampler = sampler(wgpu::AddressMode::Repeat, wgpu::AddressMode::ClampToEdge);
    let seam = View {
        name: "looking across the seam (+x)",
        // Turned a little, so that the seam (y = 0) runs inside a 2 × 2
        // quad of pixels, where the derivatives see it, as it does in
        // general.
        cam: (
            DVec3::new(1.0, -0.01, 0.1),
            DVec3::new(0.0, -1.0, 0.0),
            DVec3::new(0.0, 0.0, 1.0),
        ),
    };
    let pole = View {
        name: "looking into the pole (+z)",
        cam: (
            DVec3::new(0.013, 0.021, 1.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
        ),
    };
    let latlong_expected = |_d: DVec3, fp: f64| (fp * 512.0 / std::f64::consts::PI).log2();
    let m = Map {
        name: "latlong",
        texture: &latlong,
        sampler: &ll_sampler,
        lod_expr: "envmap_latlong_lod(fp, 512.0)",
        sample_fn: "envmap_latlong_sample_level",
        expected: &latlong_expected,
        max_level: 10.0,
    };
    check_map(&g, &m, &[seam, pole]);
    // A 1024² octahedral map (11 levels), clamped.
    let oct = level_probe(&g, 1024, 1024, 11);
    let oct_sampler = sampler(
        wgpu::AddressMode::ClampToEdge,
        wgpu::AddressMode::ClampToEdge,
    );
    let views = || {
        [
            View {
                name: "looking into the lower pole (-z), where the folds meet",
                cam: (
                    DVec3::new(0.013, 0.021, -1.0),
                    DVec3::new(1.0, 0.0, 0.0),
                    DVec3::new(0.0, 1.0, 0.0),
                ),
            },
            View {
                name: "looking along a fold (x = 0, z < 0)",
                cam: (
                    DVec3::new(0.011, 0.6, -0.8),
                    DVec3::new(1.0, 0.0, 0.0),
                    DVec3::new(0.0, 0.8, 0.6),
                ),
            },
        ]
    };
    let oct_expected = |d: DVec3, fp: f64| {
        let l = d.length();
        let p = l / (d.x.abs() + d.y.abs() + d.z.abs());
        let texel = 2.0 / (1024.0 * p.powf(1.5));
        (fp / texel).log2()
    };
    let m = Map {
        name: "octahedral",
        texture: &oct,
        sampler: &oct_sampler,
        lod_expr: "envmap_octahedral_lod(d, fp, 1024.0)",
        sample_fn: "envmap_octahedral_sample_level",
        expected: &oct_expected,
        max_level: 10.0,
    };
    check_map(&g, &m, &views());
    let ea_expected =
        |_d: DVec3, fp: f64| (fp * 1024.0 / (4.0 * std::f64::consts::PI).sqrt()).log2();
    let m = Map {
        name: "equal-area octahedral",
        texture: &oct,
        sampler: &oct_sampler,
        lod_expr: "envmap_equal_area_octahedral_lod(fp, 1024.0)",
        sample_fn: "envmap_equal_area_octahedral_sample_level",
        expected: &ea_expected,
        max_level: 10.0,
    };
    check_map(&g, &m, &views());
}
