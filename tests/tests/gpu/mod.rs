//! The software-GPU harness of the shader tests: a wgpu device on Vulkan
//! (Mesa's lavapipe in CI) and compute dispatches over storage buffers,
//! whose outputs start as NaN so that a write the device drops cannot pass.
//!
//! Adapter policy: without a Vulkan adapter a test fails with the reason and
//! how to install lavapipe (`.ci/run` installs it).
#![allow(dead_code, unreachable_pub)]

use std::future::Future;
use std::pin::pin;
use std::sync::Arc;
use std::task::{Context, Poll, Wake, Waker};

/// The bit pattern every output word starts as: a quiet NaN (as u32 it is no
/// valid chart either).
pub const FILL: u32 = 0x7fc0_0000;

/// Workgroup size of the test kernels; [`Gpu::run`] dispatches
/// `ceil(n / 64)` groups over x and y, and a kernel finds its index with
/// [`INDEX_WGSL`].
pub const WORKGROUP: u32 = 64;

/// Groups per row of a dispatch (x); more rows go to y.
pub const GROUPS_X: u32 = 1024;

/// `fn index(gid) -> u32` for the kernels: the invocation's index in the
/// flattened dispatch.
pub const INDEX_WGSL: &str = "
fn test_index(gid: vec3<u32>) -> u32 { return gid.x + gid.y * (1024u * 64u); }
";

/// Runs a future that completes without outside events (wgpu's native
/// requests do) on this thread.
pub fn block_on<F: Future>(f: F) -> F::Output {
    struct Unpark(std::thread::Thread);
    impl Wake for Unpark {
        fn wake(self: Arc<Self>) {
            self.0.unpark();
        }
    }
    let waker = Waker::from(Arc::new(Unpark(std::thread::current())));
    let mut cx = Context::from_waker(&waker);
    let mut f = pin!(f);
    loop {
        match f.as_mut().poll(&mut cx) {
            Poll::Ready(v) => return v,
            Poll::Pending => std::thread::park(),
        }
    }
}

/// A device and its queue.
pub struct Gpu {
    /// The device.
    pub device: wgpu::Device,
    /// Its queue.
    pub queue: wgpu::Queue,
    /// What the adapter says it is.
    pub info: wgpu::AdapterInfo,
    /// Compute pipelines made so far, by source and entry point (lavapipe
    /// compiles each in a fraction of a second; tests run one many times).
    pipelines: std::cell::RefCell<Vec<(String, String, wgpu::ComputePipeline)>>,
}

/// The Vulkan device; without one the test fails with the reason.
pub fn gpu(test: &str) -> Gpu {
    match open() {
        Ok(g) => {
            eprintln!(
                "{test}: on {} ({:?}, driver {} {})",
                g.info.name, g.info.device_type, g.info.driver, g.info.driver_info
            );
            g
        }
        Err(why) => panic!(
            "{test}: no Vulkan device: {why}. Install Mesa's lavapipe (Debian: apt-get install \
             mesa-vulkan-drivers libvulkan1; it provides \
             /usr/share/vulkan/icd.d/lvp_icd.x86_64.json) or a Vulkan driver"
        ),
    }
}

fn open() -> Result<Gpu, String> {
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor {
        backends: wgpu::Backends::VULKAN,
        flags: wgpu::InstanceFlags::ALLOW_UNDERLYING_NONCOMPLIANT_ADAPTER,
        ..wgpu::InstanceDescriptor::new_without_display_handle()
    });
    let adapter = block_on(instance.request_adapter(&wgpu::RequestAdapterOptions::default()))
        .map_err(|e| format!("wgpu found no Vulkan adapter ({e})"))?;
    let info = adapter.get_info();
    let (device, queue) = block_on(adapter.request_device(&wgpu::DeviceDescriptor {
        label: Some("envmap shader tests"),
        required_features: adapter.features() & wgpu::Features::FLOAT32_FILTERABLE,
        required_limits: wgpu::Limits {
            max_storage_buffers_per_shader_stage: 8,
            max_storage_buffer_binding_size: 1 << 27,
            ..wgpu::Limits::default()
        },
        ..wgpu::DeviceDescriptor::default()
    }))
    .map_err(|e| format!("the adapter {} gave no device ({e})", info.name))?;
    Ok(Gpu {
        device,
        queue,
        info,
        pipelines: std::cell::RefCell::default(),
    })
}

/// A resource bound at the next binding of group 0, in order.
pub enum Binding<'a> {
    /// `var<storage, read>` holding these bytes.
    Input(&'a [u8]),
    /// `var<storage, read_write>` of this many bytes, filled with [`FILL`]
    /// before the dispatch and returned after it.
    Output(u64),
    /// `var<uniform>` holding these bytes.
    Uniform(&'a [u8]),
    /// A texture view.
    Texture(&'a wgpu::TextureView),
    /// A sampler.
    Sampler(&'a wgpu::Sampler),
}

impl Gpu {
    /// Compiles `wgsl`, runs its compute entry point `entry` over `n`
    /// invocations (see [`INDEX_WGSL`]) with `bindings` at bindings 0, 1, …
    /// of group 0, and returns the outputs' bytes in order.
    pub fn run(&self, wgsl: &str, entry: &str, bindings: &[Binding<'_>], n: u32) -> Vec<Vec<u8>> {
        use wgpu::util::DeviceExt;
        let d = &self.device;
        let pipeline = self.pipeline(wgsl, entry);
        let mut buffers = Vec::new();
        let mut outputs = Vec::new();
        for (i, b) in bindings.iter().enumerate() {
            match b {
                Binding::Input(bytes) | Binding::Uniform(bytes) => {
                    let usage = if matches!(b, Binding::Input(_)) {
                        wgpu::BufferUsages::STORAGE
                    } else {
                        wgpu::BufferUsages::UNIFORM
                    };
                    // A zero-sized binding is not allowed: pad empty inputs.
                    let padded;
                    let contents = if bytes.is_empty() {
                        padded = [0u8; 16];
                        &padded[..]
                    } else {
                        bytes
                    };
                    buffers.push(Some(d.create_buffer_init(
                        &wgpu::util::BufferInitDescriptor {
                            label: None,
                            contents,
                            usage,
                        },
                    )));
                }
                Binding::Output(size) => {
                    let buf = d.create_buffer(&wgpu::BufferDescriptor {
                        label: None,
                        size: *size,
                        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
                        mapped_at_creation: true,
                    });
                    {
                        let fill: Vec<u8> =
                            (0..*size / 4).flat_map(|_| FILL.to_le_bytes()).collect();
                        buf.slice(..).get_mapped_range_mut().copy_from_slice(&fill);
                    }
                    buf.unmap();
                    outputs.push((i, *size));
                    buffers.push(Some(buf));
                }
                Binding::Texture(_) | Binding::Sampler(_) => buffers.push(None),
            }
        }
        let entries: Vec<wgpu::BindGroupEntry<'_>> = bindings
            .iter()
            .enumerate()
            .map(|(i, b)| wgpu::BindGroupEntry {
                binding: i as u32,
                resource: match b {
                    Binding::Texture(v) => wgpu::BindingResource::TextureView(v),
                    Binding::Sampler(s) => wgpu::BindingResource::Sampler(s),
                    _ => buffers[i].as_ref().expect("a buffer").as_entire_binding(),
                },
            })
            .collect();
        let group = d.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &pipeline.get_bind_group_layout(0),
            entries: &entries,
        });
        let mut enc = d.create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
        {
            let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor::default());
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, &group, &[]);
            let groups = n.div_ceil(WORKGROUP).max(1);
            pass.dispatch_workgroups(groups.min(GROUPS_X), groups.div_ceil(GROUPS_X), 1);
        }
        let mut readbacks = Vec::new();
        for &(i, size) in &outputs {
            let rb = d.create_buffer(&wgpu::BufferDescriptor {
                label: None,
                size,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            enc.copy_buffer_to_buffer(buffers[i].as_ref().expect("an output"), 0, &rb, 0, size);
            readbacks.push(rb);
        }
        self.queue.submit([enc.finish()]);
        let mut out = Vec::new();
        for rb in readbacks {
            let slice = rb.slice(..);
            slice.map_async(wgpu::MapMode::Read, |r| {
                r.expect("mapping a readback buffer")
            });
            d.poll(wgpu::PollType::wait_indefinitely())
                .expect("waiting for the device");
            out.push(slice.get_mapped_range().to_vec());
        }
        out
    }
}

impl Gpu {
    /// The compute pipeline of `wgsl`'s entry point `entry`, made once.
    pub fn pipeline(&self, wgsl: &str, entry: &str) -> wgpu::ComputePipeline {
        let mut cache = self.pipelines.borrow_mut();
        if let Some((_, _, p)) = cache.iter().find(|(s, e, _)| s == wgsl && e == entry) {
            return p.clone();
        }
        let module = self
            .device
            .create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(entry),
                source: wgpu::ShaderSource::Wgsl(wgsl.into()),
            });
        let p = self
            .device
            .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(entry),
                layout: None,
                module: &module,
                entry_point: Some(entry),
                compilation_options: wgpu::PipelineCompilationOptions::default(),
                cache: None,
            });
        cache.push((wgsl.to_owned(), entry.to_owned(), p.clone()));
        p
    }
}

/// f32 values as bytes.
pub fn bytes_f32(v: &[f32]) -> Vec<u8> {
    v.iter().flat_map(|x| x.to_le_bytes()).collect()
}

/// u32 values as bytes.
pub fn bytes_u32(v: &[u32]) -> Vec<u8> {
    v.iter().flat_map(|x| x.to_le_bytes()).collect()
}

/// Bytes as f32 values.
pub fn f32s(b: &[u8]) -> Vec<f32> {
    b.chunks_exact(4)
        .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect()
}

/// Bytes as u32 values.
pub fn u32s(b: &[u8]) -> Vec<u32> {
    b.chunks_exact(4)
        .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect()
}

/// One level of a texture: width, height and RGBA texels (row 0 first),
/// layer after layer for an array.
pub struct Level {
    /// Width in texels.
    pub width: u32,
    /// Height in texels.
    pub height: u32,
    /// `width × height × layers` texels.
    pub texels: Vec<[f32; 4]>,
}

impl Gpu {
    /// An `Rgba32Float` texture with `levels` as its mips (each layer's
    /// texels one after the other), viewed as 2D (one layer) or as a 2D
    /// array (`array`).
    pub fn texture(&self, levels: &[Level], layers: u32, array: bool) -> wgpu::TextureView {
        let t = self.device.create_texture(&wgpu::TextureDescriptor {
            label: None,
            size: wgpu::Extent3d {
                width: levels[0].width,
                height: levels[0].height,
                depth_or_array_layers: layers,
            },
            mip_level_count: levels.len() as u32,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba32Float,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        });
        for (k, l) in levels.iter().enumerate() {
            assert_eq!(l.texels.len(), (l.width * l.height * layers) as usize);
            let bytes: Vec<u8> = l
                .texels
                .iter()
                .flat_map(|t| t.iter().flat_map(|x| x.to_le_bytes()))
                .collect();
            self.queue.write_texture(
                wgpu::TexelCopyTextureInfo {
                    texture: &t,
                    mip_level: k as u32,
                    origin: wgpu::Origin3d::ZERO,
                    aspect: wgpu::TextureAspect::All,
                },
                &bytes,
                wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(16 * l.width),
                    rows_per_image: Some(l.height),
                },
                wgpu::Extent3d {
                    width: l.width,
                    height: l.height,
                    depth_or_array_layers: layers,
                },
            );
        }
        t.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(if array {
                wgpu::TextureViewDimension::D2Array
            } else {
                wgpu::TextureViewDimension::D2
            }),
            ..wgpu::TextureViewDescriptor::default()
        })
    }
}

impl Gpu {
    /// Draws one triangle covering a `width × height` (a multiple of 16)
    /// `Rgba32Float` target with `wgsl`'s vertex entry point `vs` and
    /// fragment entry point `fs`, `bindings` at group 0, and returns its
    /// texels (row 0 first). The target starts as NaN.
    pub fn render(
        &self,
        wgsl: &str,
        bindings: &[Binding<'_>],
        width: u32,
        height: u32,
    ) -> Vec<[f32; 4]> {
        let d = &self.device;
        let module = d.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("render"),
            source: wgpu::ShaderSource::Wgsl(wgsl.into()),
        });
        let format = wgpu::TextureFormat::Rgba32Float;
        let pipeline = d.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("render"),
            layout: None,
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs"),
                compilation_options: wgpu::PipelineCompilationOptions::default(),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: None,
            multisample: wgpu::MultisampleState::default(),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs"),
                compilation_options: wgpu::PipelineCompilationOptions::default(),
                targets: &[Some(wgpu::ColorTargetState {
                    format,
                    blend: None,
                    write_mask: wgpu::ColorWrites::ALL,
                })],
            }),
            multiview_mask: None,
            cache: None,
        });
        let target = d.create_texture(&wgpu::TextureDescriptor {
            label: None,
            size: wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        let view = target.create_view(&wgpu::TextureViewDescriptor::default());
        let mut buffers = Vec::new();
        for b in bindings {
            buffers.push(match b {
                Binding::Uniform(bytes) | Binding::Input(bytes) => {
                    use wgpu::util::DeviceExt;
                    Some(d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                        label: None,
                        contents: bytes,
                        usage: if matches!(b, Binding::Uniform(_)) {
                            wgpu::BufferUsages::UNIFORM
                        } else {
                            wgpu::BufferUsages::STORAGE
                        },
                    }))
                }
                _ => None,
            });
        }
        let entries: Vec<wgpu::BindGroupEntry<'_>> = bindings
            .iter()
            .enumerate()
            .map(|(i, b)| wgpu::BindGroupEntry {
                binding: i as u32,
                resource: match b {
                    Binding::Texture(v) => wgpu::BindingResource::TextureView(v),
                    Binding::Sampler(s) => wgpu::BindingResource::Sampler(s),
                    Binding::Output(_) => panic!("a render has no storage outputs here"),
                    _ => buffers[i].as_ref().expect("a buffer").as_entire_binding(),
                },
            })
            .collect();
        let group = d.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &pipeline.get_bind_group_layout(0),
            entries: &entries,
        });
        let nan = f64::from(f32::from_bits(FILL));
        let mut enc = d.create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
        {
            let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: None,
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color {
                            r: nan,
                            g: nan,
                            b: nan,
                            a: nan,
                        }),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                ..wgpu::RenderPassDescriptor::default()
            });
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, &group, &[]);
            pass.draw(0..3, 0..1);
        }
        let size = u64::from(width) * u64::from(height) * 16;
        let rb = d.create_buffer(&wgpu::BufferDescriptor {
            label: None,
            size,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        enc.copy_texture_to_buffer(
            wgpu::TexelCopyTextureInfo {
                texture: &target,
                mip_level: 0,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            wgpu::TexelCopyBufferInfo {
                buffer: &rb,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(16 * width),
                    rows_per_image: Some(height),
                },
            },
            wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: 1,
            },
        );
        self.queue.submit([enc.finish()]);
        let slice = rb.slice(..);
        slice.map_async(wgpu::MapMode::Read, |r| {
            r.expect("mapping a readback buffer")
        });
        d.poll(wgpu::PollType::wait_indefinitely())
            .expect("waiting for the device");
        let v = f32s(&slice.get_mapped_range());
        v.chunks_exact(4)
            .map(|c| [c[0], c[1], c[2], c[3]])
            .collect()
    }
}
