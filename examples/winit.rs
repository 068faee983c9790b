//! relief in a host app with a window: the host owns the window, the surface, the device and
//! the depth buffer; relief draws the endless world into the host's render pass, and the
//! host's own object (a red pillar standing on the ground) shares the depth buffer with it.
//!
//! `cargo run --release --example winit` (Esc quits; `--exit-after SECONDS` closes it).

use std::sync::Arc;
use std::time::Instant;

use glam::DVec3;
use relief::{wgpu, MethodConfig, Targets, World, WorldParams, WorldView};
use winit::application::ApplicationHandler;
use winit::event::{ElementState, KeyEvent, WindowEvent};
use winit::event_loop::{ActiveEventLoop, EventLoop};
use winit::keyboard::{Key, NamedKey};
use winit::window::{Window, WindowId};

const DEPTH: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// The host's pillar: a box from 40 m below the ground to 200 m above it, 30 m wide, in
/// positions relative to the eye (relief draws camera-relative too).
const PILLAR: &str = r#"
struct U { view_proj: mat4x4<f32>, foot: vec4<f32> }
@group(0) @binding(0) var<uniform> u: U;
@vertex fn vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let c = array<vec3<f32>, 8>(vec3(-1., 0., -1.), vec3(1., 0., -1.), vec3(1., 0., 1.),
        vec3(-1., 0., 1.), vec3(-1., 1., -1.), vec3(1., 1., -1.), vec3(1., 1., 1.), vec3(-1., 1., 1.));
    let k = array<u32, 36>(0u,1u,2u, 0u,2u,3u, 4u,6u,5u, 4u,7u,6u, 0u,4u,5u, 0u,5u,1u,
        1u,5u,6u, 1u,6u,2u, 2u,6u,7u, 2u,7u,3u, 3u,7u,4u, 3u,4u,0u);
    let p = c[k[i]];
    let local = vec3(p.x * 15.0, mix(-40.0, 200.0, p.y), p.z * 15.0);
    return u.view_proj * vec4(u.foot.xyz + local, 1.0);
}
@fragment fn fs() -> @location(0) vec4<f32> { return vec4(0.8, 0.1, 0.1, 1.0); }
"#;

/// Everything the host made once it had a window.
struct Gpu {
    window: Arc<Window>,
    surface: wgpu::Surface<'static>,
    device: wgpu::Device,
    queue: wgpu::Queue,
    config: wgpu::SurfaceConfiguration,
    depth: wgpu::TextureView,
    world: World,
    pillar: (wgpu::RenderPipeline, wgpu::Buffer, wgpu::BindGroup),
}

#[derive(Default)]
struct Host {
    gpu: Option<Gpu>,
    started: Option<Instant>,
    exit_after: Option<f64>,
}

fn depth_view(device: &wgpu::Device, config: &wgpu::SurfaceConfiguration) -> wgpu::TextureView {
    device
        .create_texture(&wgpu::TextureDescriptor {
            label: Some("host:depth"),
            size: wgpu::Extent3d {
                width: config.width,
                height: config.height,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: DEPTH,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
            view_formats: &[],
        })
        .create_view(&Default::default())
}

fn pillar(
    device: &wgpu::Device,
    format: wgpu::TextureFormat,
) -> (wgpu::RenderPipeline, wgpu::Buffer, wgpu::BindGroup) {
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("host:pillar"),
        source: wgpu::ShaderSource::Wgsl(PILLAR.into()),
    });
    let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("host:pillar"),
        layout: None,
        vertex: wgpu::VertexState {
            module: &module,
            entry_point: Some("vs"),
            compilation_options: Default::default(),
            buffers: &[],
        },
        fragment: Some(wgpu::FragmentState {
            module: &module,
            entry_point: Some("fs"),
            compilation_options: Default::default(),
            targets: &[Some(format.into())],
        }),
        primitive: Default::default(),
        depth_stencil: Some(wgpu::DepthStencilState {
            format: DEPTH,
            depth_write_enabled: Some(true),
            depth_compare: Some(wgpu::CompareFunction::Less),
            stencil: Default::default(),
            bias: Default::default(),
        }),
        multisample: Default::default(),
        multiview_mask: None,
        cache: None,
    });
    let uniforms = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("host:pillar"),
        size: 80,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("host:pillar"),
        layout: &pipeline.get_bind_group_layout(0),
        entries: &[wgpu::BindGroupEntry {
            binding: 0,
            resource: uniforms.as_entire_binding(),
        }],
    });
    (pipeline, uniforms, bind_group)
}

impl Gpu {
    fn new(window: Arc<Window>) -> Result<Self, Box<dyn std::error::Error>> {
        let instance = wgpu::Instance::default();
        let surface = instance.create_surface(window.clone())?;
        let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
            compatible_surface: Some(&surface),
            ..Default::default()
        }))?;
        let (device, queue) = pollster::block_on(relief::gpu::request_device(&adapter))?;
        let size = window.inner_size();
        let config = surface
            .get_default_config(&adapter, size.width.max(1), size.height.max(1))
            .ok_or("the surface does not fit this adapter")?;
        surface.configure(&device, &config);
        let targets = Targets {
            color_format: config.format,
            depth_format: Some(DEPTH),
            sample_count: 1,
        };
        let mut world = World::new(&device, &queue, targets, WorldParams::default())?;
        world.set_method(&device, MethodConfig::MESH)?;
        Ok(Self {
            depth: depth_view(&device, &config),
            pillar: pillar(&device, config.format),
            window,
            surface,
            device,
            queue,
            config,
            world,
        })
    }

    fn draw(&mut self, seconds: f64) -> Result<(), Box<dyn std::error::Error>> {
        let wgpu::CurrentSurfaceTexture::Success(frame) = self.surface.get_current_texture() else {
            self.surface.configure(&self.device, &self.config);
            return Ok(());
        };
        // A slow flight east, 150 m above the ground; the pillar 900 m ahead of the start.
        let (x, z) = (2000.0 + 15.0 * seconds, -3000.0);
        let eye = DVec3::new(x, self.world.height_at(x, z) + 150.0, z);
        let foot = DVec3::new(2900.0, self.world.height_at(2900.0, z), z);
        let size = (self.config.width, self.config.height);
        let view = WorldView::look_at(eye, foot + DVec3::Y * 60.0, 0.9, size);
        self.world.set_time(seconds);
        let mut encoder = self.device.create_command_encoder(&Default::default());
        self.world
            .prepare(&self.device, &self.queue, &mut encoder, &view)?;
        // relief's camera-relative matrix, so the pillar and the terrain share one depth. With
        // the temporal service on (`World::set_temporal`, the visibility method or the hybrid)
        // the matrix carries this frame's sub-pixel jitter, and relief has already resolved its
        // history in `prepare`, before this pass: the pillar is drawn without the jitter, so it
        // holds still (its edge against the terrain's depth moves by at most the jitter).
        let rel = (foot - eye).as_vec3();
        let unjittered = relief::temporal::jitter_matrix(self.world.jitter(), size).inverse()
            * self.world.relative_matrix();
        let mut uniforms = unjittered.to_cols_array().to_vec();
        uniforms.extend([rel.x, rel.y, rel.z, 0.0]);
        self.queue
            .write_buffer(&self.pillar.1, 0, bytemuck::cast_slice(&uniforms));
        let color = frame.texture.create_view(&Default::default());
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("host:pass"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &color,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations::default(),
                })],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &self.depth,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Discard,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(&self.pillar.0);
            pass.set_bind_group(0, &self.pillar.2, &[]);
            pass.draw(0..36, 0..1);
            self.world.render(&mut pass); // the terrain and the sky behind it
        }
        self.queue.submit([encoder.finish()]);
        self.queue.present(frame);
        Ok(())
    }
}

impl ApplicationHandler for Host {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.gpu.is_some() {
            return;
        }
        let made = event_loop
            .create_window(Window::default_attributes().with_title("relief in a host"))
            .map_err(Into::into)
            .and_then(|w| Gpu::new(Arc::new(w)));
        match made {
            Ok(gpu) => self.gpu = Some(gpu),
            Err(e) => {
                eprintln!("{e}");
                event_loop.exit();
            }
        }
        self.started = Some(Instant::now());
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _: WindowId, event: WindowEvent) {
        let Some(gpu) = &mut self.gpu else { return };
        let seconds = self.started.map_or(0.0, |t| t.elapsed().as_secs_f64());
        match event {
            WindowEvent::CloseRequested
            | WindowEvent::KeyboardInput {
                event:
                    KeyEvent {
                        logical_key: Key::Named(NamedKey::Escape),
                        state: ElementState::Pressed,
                        ..
                    },
                ..
            } => event_loop.exit(),
            WindowEvent::Resized(size) if size.width > 0 && size.height > 0 => {
                gpu.config.width = size.width;
                gpu.config.height = size.height;
                gpu.surface.configure(&gpu.device, &gpu.config);
                gpu.depth = depth_view(&gpu.device, &gpu.config);
            }
            WindowEvent::RedrawRequested => {
                if self.exit_after.is_some_and(|s| seconds > s) {
                    return event_loop.exit();
                }
                if let Err(e) = gpu.draw(seconds) {
                    eprintln!("{e}");
                    event_loop.exit();
                }
                gpu.window.request_redraw();
            }
            _ => {}
        }
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let exit_after = match args.iter().position(|a| a == "--exit-after") {
        Some(i) => Some(
            args.get(i + 1)
                .ok_or("--exit-after SECONDS")?
                .parse::<f64>()?,
        ),
        None => None,
    };
    let mut host = Host {
        exit_after,
        ..Default::default()
    };
    EventLoop::new()?.run_app(&mut host)?;
    Ok(())
}
