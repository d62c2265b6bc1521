//! A sphere shaded on a GPU by the shipped WGSL (`envmap_core::shaders`)
//! from a baked chain, beside `envmap render --material` of the same sphere.
//!
//! ```text
//! cargo run --release -p envmap-tests --example shader_lookup -- [BAKE_DIR [MATERIAL]]
//! ```
//!
//! `BAKE_DIR` is what `envmap bake` wrote (its manifest, specular chain,
//! irradiance cube and DFG table); without it the built-in sky is baked
//! first (a 128² chain, envmap's own preset: EXR crosses) into
//! `target/shader_lookup/bake`. MATERIAL is a preset (`gold` by default:
//! mirror, chrome, gold, plastic, rubber, diffuse).
//!
//! The GPU part is what an engine does with wgpu: the chain and the
//! irradiance cube as 2D-array textures of six layers (a cube texture's
//! faces), the DFG table as a 2D texture, `ALL_WGSL` prepended to its own
//! shaders; the sphere (`envmap render`'s: radius 1.5, 128 × 64 segments,
//! centred 1.4 above the origin) rasterized by the GPU with its vertex
//! normals, shaded per fragment by `envmap_specular_direction`,
//! `envmap_cube_chain` (the chain at the linear rule's level, and the
//! irradiance), `envmap_dfg_load` and `envmap_split_sum`; the background by
//! `envmap_cube_chain` at level 0 along each pixel's view ray.
//!
//! The CPU part is `envmap render`'s split sum as a library call, reading
//! the bake as an engine reads its files: as `envmap render
//! target/shader_lookup/cpu.png --env BAKE_DIR --object sphere --material
//! gold --engine gltf --samples 1 --no-mip --width 320 --height 240` does
//! (one sample per pixel, bilinear lookups in the chain's level 0, levels
//! blended linearly in the linear rule's level), but with the DFG table at
//! texel centres as `dfg.exr` holds it, where the command reads its own on
//! the edges grid.
//!
//! Writes `target/shader_lookup/gpu.png` and `cpu.png` (exposure 0, sRGB),
//! prints how far apart they are, and fails unless every pixel away from
//! the sphere's outline (whose coverage the two rasterizers decide each
//! their own way) is within [`TOLERANCE`] relative of the CPU's, linear,
//! and within one 8-bit level in the PNGs.

use std::path::{Path, PathBuf};

use envmap_core::shaders::ALL_WGSL;
use envmap_core::AnyMapping;
use envmap_render::bake::{open, Baker};
use envmap_render::filter::dfg::{DfgGrid, DfgTable};
use envmap_render::image::FileAxes;
use envmap_render::image::{write_rgb, SaveOptions};
use envmap_render::image::{EnvImage, Representation, RgbImage};
use envmap_render::scene::Builtin;
use envmap_render::scene::Material;
use envmap_render::scene::Mesh;
use envmap_render::scene::{Camera, EnvSource, RenderOptions, Renderer, Shading};
use envmap_render::scene::{LevelBlend, LitEnvironment};
use glam::Vec3;

const WIDTH: u32 = 320;
const HEIGHT: u32 = 240;
/// The largest relative difference (per channel, linear) allowed away
/// from the sphere's outline.
const TOLERANCE: f64 = 1e-3;

type Error = Box<dyn std::error::Error>;

fn main() -> Result<(), Error> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let out = Path::new(env!("CARGO_MANIFEST_DIR")).join("../target/shader_lookup");
    std::fs::create_dir_all(&out)?;
    let dir = match args.first() {
        Some(d) => PathBuf::from(d),
        None => bake_sky(&out.join("bake"))?,
    };
    let material_name = args.get(1).map_or("gold", String::as_str);
    let material = Material::preset(material_name)?;
    // The baked chain, read as `envmap render --env DIR` reads it.
    let lit = open(&dir, None, u64::MAX, None)?
        .ok_or_else(|| format!("{}: not a bake directory", dir.display()))?;
    println!("{}", lit.description);
    // Read as an engine reads the files, which is what the WGSL does: the
    // levels blended linearly in the linear rule's level (`--engine gltf`)
    // and the DFG table on the bake file's grid, at texel centres
    // (`envmap render` itself reads a table on the edges grid, exact at
    // N·V and roughness 0 and 1).
    let env = LitEnvironment::new(
        lit.env.levels().to_vec(),
        lit.env.roughness().to_vec(),
        lit.env.irradiance().clone(),
        lit.env.irradiance_scale(),
        DfgTable::on_grid(lit.env.dfg().size(), DfgGrid::TexelCentres, None)?,
    )?
    .with_blend(LevelBlend::Roughness);
    let levels = env.levels();
    if levels[0].mapping() != AnyMapping::Cube || env.irradiance().mapping() != AnyMapping::Cube {
        return Err("this example reads cube chains (envmap bake's default)".into());
    }
    // envmap render's sphere and camera.
    let mut mesh = Mesh::sphere(1.5, 128, 64);
    for p in &mut mesh.positions {
        *p += Vec3::new(0.0, 0.0, 1.4);
    }
    let cam = Camera::default();
    // The CPU: envmap render --material, one sample per pixel, no mip.
    let cpu = Renderer::new().render(&mesh, EnvSource::Map(&levels[0]), &cam, &{
        let mut o = RenderOptions::default();
        o.width = WIDTH;
        o.height = HEIGHT;
        o.samples = 1;
        o.mip = false;
        o.shading = Shading::SplitSum {
            env: &env,
            material,
            multiscatter: false,
            dominant: true,
        };
        o
    })?;
    // The GPU.
    let (gpu, info) = gpu_render(&env, &mesh, &cam, &material)?;
    println!("GPU: {info}");
    let save = SaveOptions::default();
    write_rgb(&cpu, out.join("cpu.png"), &save)?;
    let gpu_img = RgbImage {
        width: WIDTH,
        height: HEIGHT,
        pixels: gpu.iter().map(|p| [p[0], p[1], p[2]]).collect(),
    };
    write_rgb(&gpu_img, out.join("gpu.png"), &save)?;
    compare(&cpu, &gpu, &out, material_name)
}

/// The built-in sky baked as `envmap bake` would, at 128², into `dir`.
fn bake_sky(dir: &Path) -> Result<PathBuf, Error> {
    let src = Builtin::Sky.image(
        Representation::for_file(AnyMapping::Cube, FileAxes::default()),
        4 * 128,
        3 * 128,
    )?;
    Baker::new()
        .size(128)
        .input_name("sky")
        .bake(&src)?
        .write(dir)?;
    println!("baked the built-in sky into {}", dir.display());
    Ok(dir.to_path_buf())
}

/// The shader: the library, then the example's own entry points.
fn shader_source() -> String {
    format!(
        "{ALL_WGSL}
struct Params {{
    eye: vec4<f32>,
    forward: vec4<f32>,
    right: vec4<f32>,
    up: vec4<f32>,
    // tan_x, tan_y, width, height
    view: vec4<f32>,
    // the world (canonical, z up) to the maps' axes, by columns
    to_map: array<vec4<f32>, 3>,
    // base colour, metallic
    base: vec4<f32>,
    // roughness, dielectric F0, the chain's levels, flags (1 multiscatter, 2 dominant)
    misc: vec4<f32>,
}}

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var chain: texture_2d_array<f32>;
@group(0) @binding(2) var irradiance: texture_2d_array<f32>;
@group(0) @binding(3) var dfg: texture_2d<f32>;

fn to_map(d: vec3<f32>) -> vec3<f32> {{
    return mat3x3<f32>(params.to_map[0].xyz, params.to_map[1].xyz, params.to_map[2].xyz) * d;
}}

// The background: the view ray through the pixel, the chain's level 0.
@vertex
fn background_vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {{
    let p = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    return vec4<f32>(p * 2.0 - 1.0, 1.0, 1.0);
}}

@fragment
fn background_fs(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {{
    let sx = (2.0 * pos.x / params.view.z - 1.0) * params.view.x;
    let sy = (1.0 - 2.0 * pos.y / params.view.w) * params.view.y;
    let ray = normalize(params.forward.xyz + sx * params.right.xyz + sy * params.up.xyz);
    let levels = i32(params.misc.z);
    return vec4<f32>(envmap_cube_chain(chain, levels, to_map(ray), 0.0), 0.0);
}}

// The sphere: projected as envmap's renderer projects (view depth as w).
struct Vertex {{
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
}}

@vertex
fn sphere_vs(@location(0) p: vec3<f32>, @location(1) n: vec3<f32>) -> Vertex {{
    let d = p - params.eye.xyz;
    let z = dot(d, params.forward.xyz);
    let clip = vec4<f32>(dot(d, params.right.xyz) / params.view.x, dot(d, params.up.xyz) / params.view.y, z - 0.001, z);
    return Vertex(clip, p, n);
}}

@fragment
fn sphere_fs(in: Vertex) -> @location(0) vec4<f32> {{
    let n = normalize(in.normal);
    let v = normalize(params.eye.xyz - in.world);
    let roughness = clamp(params.misc.x, 0.0, 1.0);
    let levels = i32(params.misc.z);
    let flags = u32(params.misc.w);
    let dir = envmap_specular_direction(n, v, roughness, (flags & 2u) != 0u);
    let ld = envmap_cube_chain(chain, levels, to_map(dir), envmap_roughness_to_lod_linear(roughness, f32(levels)));
    let e = envmap_cube_chain(irradiance, 1, to_map(n), 0.0);
    let ab = envmap_dfg_load(dfg, dot(n, v), roughness);
    let f0 = envmap_f0_color(params.base.xyz, params.base.w, params.misc.y);
    let c = envmap_split_sum(envmap_diffuse_color(params.base.xyz, params.base.w), f0, e, ld, ab, (flags & 1u) != 0u);
    return vec4<f32>(c, 1.0);
}}
"
    )
}

/// Renders the sphere on the GPU: RGB and, in alpha, 1 where the sphere is.
fn gpu_render(
    env: &LitEnvironment,
    mesh: &Mesh,
    cam: &Camera,
    m: &Material,
) -> Result<(Vec<[f32; 4]>, String), Error> {
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor {
        flags: wgpu::InstanceFlags::ALLOW_UNDERLYING_NONCOMPLIANT_ADAPTER,
        ..wgpu::InstanceDescriptor::new_without_display_handle()
    });
    let adapter = block_on(instance.request_adapter(&wgpu::RequestAdapterOptions::default()))
        .map_err(|e| {
            format!("no GPU adapter ({e}); Mesa's lavapipe (Debian: mesa-vulkan-drivers) will do")
        })?;
    let info = adapter.get_info();
    let (device, queue) = block_on(adapter.request_device(&wgpu::DeviceDescriptor::default()))?;
    let info = format!(
        "{} ({:?}, {} {})",
        info.name, info.backend, info.driver, info.driver_info
    );

    // The textures: a cube chain as a 2D array of six layers per level.
    let levels = env.levels();
    let chain = cube_texture(&device, &queue, levels);
    let irradiance = cube_texture(&device, &queue, std::slice::from_ref(env.irradiance()));
    let table = env.dfg();
    let n = table.size();
    let dfg_texels: Vec<[f32; 4]> = table
        .single_scatter_texels()
        .iter()
        .map(|&[a, b]| [a, b, 0.0, 0.0])
        .collect();
    let dfg = texture(&device, &queue, &[(n, n, dfg_texels)], 1);

    // The uniforms: the camera as envmap's renderer sets it up.
    let forward = (cam.target - cam.eye).normalize();
    let right = forward.cross(cam.up).normalize();
    let up = right.cross(forward);
    let tan_y = (cam.fov_y_deg.to_radians() * 0.5).tan();
    let tan_x = tan_y * WIDTH as f32 / HEIGHT as f32;
    let to_map = levels[0]
        .representation()
        .frame
        .matrix()
        .transpose()
        .to_cols_array_2d();
    let flags = 2.0; // the dominant direction, no multiscatter: envmap render's default
    let v4 = |v: Vec3| [v.x, v.y, v.z, 0.0];
    let mut params: Vec<f32> = Vec::new();
    for p in [
        v4(cam.eye),
        v4(forward),
        v4(right),
        v4(up),
        [tan_x, tan_y, WIDTH as f32, HEIGHT as f32],
    ] {
        params.extend(p);
    }
    for c in to_map {
        params.extend([c[0], c[1], c[2], 0.0]);
    }
    params.extend([
        m.base_color[0],
        m.base_color[1],
        m.base_color[2],
        m.metallic,
    ]);
    params.extend([m.roughness, m.dielectric_f0, levels.len() as f32, flags]);
    use wgpu::util::DeviceExt;
    let uniform = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("params"),
        contents: &bytes(&params),
        usage: wgpu::BufferUsages::UNIFORM,
    });
    let vertices: Vec<f32> = mesh
        .positions
        .iter()
        .zip(&mesh.normals)
        .flat_map(|(p, n)| [p.x, p.y, p.z, n.x, n.y, n.z])
        .collect();
    let vertex_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("sphere"),
        contents: &bytes(&vertices),
        usage: wgpu::BufferUsages::VERTEX,
    });
    let indices: Vec<u32> = mesh.triangles.iter().flatten().copied().collect();
    let index_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("triangles"),
        contents: &indices
            .iter()
            .flat_map(|i| i.to_le_bytes())
            .collect::<Vec<u8>>(),
        usage: wgpu::BufferUsages::INDEX,
    });

    // The pipelines: one layout for both.
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("envmap shader lookup"),
        source: wgpu::ShaderSource::Wgsl(shader_source().into()),
    });
    let float = wgpu::TextureSampleType::Float { filterable: false };
    let tex = |binding, dim| wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::FRAGMENT,
        ty: wgpu::BindingType::Texture {
            sample_type: float,
            view_dimension: dim,
            multisampled: false,
        },
        count: None,
    };
    let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: None,
        entries: &[
            wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            },
            tex(1, wgpu::TextureViewDimension::D2Array),
            tex(2, wgpu::TextureViewDimension::D2Array),
            tex(3, wgpu::TextureViewDimension::D2),
        ],
    });
    let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &layout,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: uniform.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: wgpu::BindingResource::TextureView(&chain),
            },
            wgpu::BindGroupEntry {
                binding: 2,
                resource: wgpu::BindingResource::TextureView(&irradiance),
            },
            wgpu::BindGroupEntry {
                binding: 3,
                resource: wgpu::BindingResource::TextureView(&dfg),
            },
        ],
    });
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: None,
        bind_group_layouts: &[Some(&layout)],
        immediate_size: 0,
    });
    let format = wgpu::TextureFormat::Rgba32Float;
    let depth_format = wgpu::TextureFormat::Depth32Float;
    let pipeline = |vs: &str, fs: &str, buffers: &[wgpu::VertexBufferLayout<'_>], depth: bool| {
        device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(vs),
            layout: Some(&pipeline_layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some(vs),
                compilation_options: wgpu::PipelineCompilationOptions::default(),
                buffers,
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: Some(wgpu::DepthStencilState {
                format: depth_format,
                depth_write_enabled: Some(depth),
                depth_compare: Some(if depth {
                    wgpu::CompareFunction::Less
                } else {
                    wgpu::CompareFunction::Always
                }),
                stencil: wgpu::StencilState::default(),
                bias: wgpu::DepthBiasState::default(),
            }),
            multisample: wgpu::MultisampleState::default(),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some(fs),
                compilation_options: wgpu::PipelineCompilationOptions::default(),
                targets: &[Some(wgpu::ColorTargetState {
                    format,
                    blend: None,
                    write_mask: wgpu::ColorWrites::ALL,
                })],
            }),
            multiview_mask: None,
            cache: None,
        })
    };
    let background = pipeline("background_vs", "background_fs", &[], false);
    let sphere = pipeline(
        "sphere_vs",
        "sphere_fs",
        &[wgpu::VertexBufferLayout {
            array_stride: 24,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3],
        }],
        true,
    );
    let target = device.create_texture(&wgpu::TextureDescriptor {
        label: Some("image"),
        size: wgpu::Extent3d {
            width: WIDTH,
            height: HEIGHT,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    });
    let depth = device.create_texture(&wgpu::TextureDescriptor {
        label: Some("depth"),
        size: wgpu::Extent3d {
            width: WIDTH,
            height: HEIGHT,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: depth_format,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
        view_formats: &[],
    });
    let target_view = target.create_view(&wgpu::TextureViewDescriptor::default());
    let depth_view = depth.create_view(&wgpu::TextureViewDescriptor::default());
    let mut enc = device.create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
    {
        let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: None,
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &target_view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &depth_view,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            ..wgpu::RenderPassDescriptor::default()
        });
        pass.set_bind_group(0, &group, &[]);
        pass.set_pipeline(&background);
        pass.draw(0..3, 0..1);
        pass.set_pipeline(&sphere);
        pass.set_vertex_buffer(0, vertex_buffer.slice(..));
        pass.set_index_buffer(index_buffer.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..indices.len() as u32, 0, 0..1);
    }
    let size = u64::from(WIDTH * HEIGHT * 16);
    let readback = device.create_buffer(&wgpu::BufferDescriptor {
        label: None,
        size,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    enc.copy_texture_to_buffer(
        target.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &readback,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(16 * WIDTH),
                rows_per_image: Some(HEIGHT),
            },
        },
        wgpu::Extent3d {
            width: WIDTH,
            height: HEIGHT,
            depth_or_array_layers: 1,
        },
    );
    queue.submit([enc.finish()]);
    let slice = readback.slice(..);
    slice.map_async(wgpu::MapMode::Read, |r| r.expect("mapping the image"));
    device.poll(wgpu::PollType::wait_indefinitely())?;
    let data = slice.get_mapped_range();
    let px = data
        .chunks_exact(16)
        .map(|c| {
            core::array::from_fn(|i| {
                f32::from_le_bytes([c[4 * i], c[4 * i + 1], c[4 * i + 2], c[4 * i + 3]])
            })
        })
        .collect();
    Ok((px, info))
}

/// A cube chain (or one cube) as an `Rgba32Float` 2D array of six layers,
/// one mip per image, the layers in GL face order.
fn cube_texture(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    levels: &[EnvImage],
) -> wgpu::TextureView {
    let mips: Vec<(u32, u32, Vec<[f32; 4]>)> = levels
        .iter()
        .map(|img| {
            let (w, h) = img.cell_size();
            let mut t = Vec::new();
            for face in 0..6 {
                for j in 0..h {
                    for i in 0..w {
                        let [r, g, b] = img.chart_texel(face, i, j).unwrap_or([0.0; 3]);
                        t.push([r, g, b, 1.0]);
                    }
                }
            }
            (w, h, t)
        })
        .collect();
    texture(device, queue, &mips, 6)
}

/// An `Rgba32Float` texture from its mips (width, height, texels layer
/// after layer), viewed as a 2D array when it has more than one layer.
fn texture(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    mips: &[(u32, u32, Vec<[f32; 4]>)],
    layers: u32,
) -> wgpu::TextureView {
    let t = device.create_texture(&wgpu::TextureDescriptor {
        label: None,
        size: wgpu::Extent3d {
            width: mips[0].0,
            height: mips[0].1,
            depth_or_array_layers: layers,
        },
        mip_level_count: mips.len() as u32,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Rgba32Float,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    for (k, (w, h, texels)) in mips.iter().enumerate() {
        let data: Vec<f32> = texels.iter().flatten().copied().collect();
        queue.write_texture(
            wgpu::TexelCopyTextureInfo {
                texture: &t,
                mip_level: k as u32,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            &bytes(&data),
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(16 * w),
                rows_per_image: Some(*h),
            },
            wgpu::Extent3d {
                width: *w,
                height: *h,
                depth_or_array_layers: layers,
            },
        );
    }
    t.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(if layers > 1 {
            wgpu::TextureViewDimension::D2Array
        } else {
            wgpu::TextureViewDimension::D2
        }),
        ..wgpu::TextureViewDescriptor::default()
    })
}

fn bytes(v: &[f32]) -> Vec<u8> {
    v.iter().flat_map(|x| x.to_le_bytes()).collect()
}

/// sRGB encoding of a linear value, to 8 bits (as the PNGs hold it).
fn srgb8(x: f32) -> i32 {
    let x = x.clamp(0.0, 1.0);
    let s = if x <= 0.003_130_8 {
        12.92 * x
    } else {
        1.055 * x.powf(1.0 / 2.4) - 0.055
    };
    (s * 255.0).round() as i32
}

/// The two images against each other; an error beyond the tolerance.
fn compare(cpu: &RgbImage, gpu: &[[f32; 4]], out: &Path, material: &str) -> Result<(), Error> {
    let (w, h) = (WIDTH as i64, HEIGHT as i64);
    let on_sphere = |x: i64, y: i64| gpu[(y * w + x) as usize][3] > 0.5;
    let (mut worst, mut worst_at) = (0.0f64, (0, 0));
    let (mut png_worst, mut outline, mut outline_off) = (0i32, 0usize, 0usize);
    let (mut sphere_px, mut background_px) = (0usize, 0usize);
    for y in 0..h {
        for x in 0..w {
            let k = (y * w + x) as usize;
            let (c, g) = (cpu.pixels[k], gpu[k]);
            // Away from the outline: the 3 × 3 neighbourhood all sphere or all background.
            let here = on_sphere(x, y);
            let interior = (-1..=1).all(|dy| {
                (-1..=1).all(|dx| {
                    let (xx, yy) = ((x + dx).clamp(0, w - 1), (y + dy).clamp(0, h - 1));
                    on_sphere(xx, yy) == here
                })
            });
            let rel = (0..3)
                .map(|i| {
                    (f64::from(g[i]) - f64::from(c[i])).abs() / f64::from(c[i].abs()).max(1e-3)
                })
                .fold(0.0, f64::max);
            let png = (0..3)
                .map(|i| (srgb8(g[i]) - srgb8(c[i])).abs())
                .max()
                .unwrap_or(0);
            if !interior {
                outline += 1;
                outline_off += usize::from(png > 1);
                continue;
            }
            if here {
                sphere_px += 1;
            } else {
                background_px += 1;
            }
            if rel > worst || !rel.is_finite() {
                worst = if rel.is_finite() { rel } else { f64::INFINITY };
                worst_at = (x, y);
            }
            png_worst = png_worst.max(png);
        }
    }
    println!(
        "{material} sphere, {WIDTH}×{HEIGHT}: {sphere_px} sphere and {background_px} background pixels away from the outline: worst relative difference {worst:.3e} (pixel {worst_at:?}), at most {png_worst} of 255 in the PNGs"
    );
    println!("outline: {outline} pixels, {outline_off} more than one level apart in the PNGs (each rasterizer decides their coverage)");
    println!(
        "wrote {} and {}",
        out.join("gpu.png").display(),
        out.join("cpu.png").display()
    );
    if worst > TOLERANCE || png_worst > 1 {
        return Err(format!("the GPU's sphere is {worst:.3e} (or {png_worst} levels) from envmap render's, beyond {TOLERANCE:e}").into());
    }
    Ok(())
}

/// Runs a future that completes without outside events (wgpu's native
/// requests do) on this thread.
fn block_on<F: std::future::Future>(f: F) -> F::Output {
    use std::sync::Arc;
    use std::task::{Context, Poll, Wake, Waker};
    struct Unpark(std::thread::Thread);
    impl Wake for Unpark {
        fn wake(self: Arc<Self>) {
            self.0.unpark();
        }
    }
    let waker = Waker::from(Arc::new(Unpark(std::thread::current())));
    let mut cx = Context::from_waker(&waker);
    let mut f = std::pin::pin!(f);
    loop {
        match f.as_mut().poll(&mut cx) {
            Poll::Ready(v) => return v,
            Poll::Pending => std::thread::park(),
        }
    }
}
