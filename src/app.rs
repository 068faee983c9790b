//! The interactive window: a winit app that hosts [`Terrain`] exactly as any embedding app
//! would (surface texture as the target). Drag to orbit, wheel to zoom, Space pauses the
//! scroll, R re-seeds, Escape quits.

#![cfg(not(target_arch = "wasm32"))]

use crate::error::{Error, Result};
use crate::gpu::timing::{GpuTimer, Slot};
use crate::gpu::Targets;
use crate::params::TerrainParams;
use crate::{OrbitCamera, Terrain};
use std::sync::Arc;
use std::time::Instant;
use winit::application::ApplicationHandler;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, EventLoop};
use winit::keyboard::{Key, NamedKey};
use winit::window::{Window, WindowId};

/// Scroll speed of the animated offset, in tiles per second.
pub const SCROLL_SPEED: [f64; 2] = [0.01, 0.004];
/// Depth format of the window's depth buffer.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// Opens the window and runs until it is closed.
pub fn run_native(params: TerrainParams, timings: bool) -> Result<()> {
    let event_loop =
        EventLoop::new().map_err(|e| Error::Device(format!("cannot open a window: {e}")))?;
    let mut app = App::new(params, timings);
    event_loop
        .run_app(&mut app)
        .map_err(|e| Error::Device(format!("window event loop failed: {e}")))?;
    match app.error.take() {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

struct App {
    params: TerrainParams,
    camera: OrbitCamera,
    paused: bool,
    timings: bool,
    drag: Option<(f64, f64)>,
    cursor: (f64, f64),
    last: Instant,
    frames: u64,
    state: Option<State>,
    error: Option<Error>,
}

struct State {
    window: Arc<Window>,
    surface: wgpu::Surface<'static>,
    device: wgpu::Device,
    queue: wgpu::Queue,
    config: wgpu::SurfaceConfiguration,
    depth: Option<wgpu::TextureView>,
    terrain: Terrain,
    timer: Option<GpuTimer>,
    describe: String,
}

impl App {
    fn new(params: TerrainParams, timings: bool) -> Self {
        Self {
            params,
            camera: OrbitCamera::default(),
            paused: false,
            timings,
            drag: None,
            cursor: (0.0, 0.0),
            last: Instant::now(),
            frames: 0,
            state: None,
            error: None,
        }
    }

    fn fail(&mut self, event_loop: &ActiveEventLoop, e: Error) {
        self.error = Some(e);
        event_loop.exit();
    }

    fn init(&self, event_loop: &ActiveEventLoop) -> Result<State> {
        let window = Arc::new(
            event_loop
                .create_window(
                    Window::default_attributes()
                        .with_title("relief")
                        .with_inner_size(winit::dpi::LogicalSize::new(1280, 720)),
                )
                .map_err(|e| Error::Device(format!("cannot create a window: {e}")))?,
        );
        let instance =
            wgpu::Instance::new(wgpu::InstanceDescriptor::new_with_display_handle_from_env(
                Box::new(event_loop.owned_display_handle()),
            ));
        let surface = instance
            .create_surface(window.clone())
            .map_err(|e| Error::Device(format!("cannot create a surface: {e}")))?;
        let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            force_fallback_adapter: false,
            compatible_surface: Some(&surface),
            apply_limit_buckets: false,
        }))
        .map_err(|e| Error::NoAdapter(e.to_string()))?;
        let info = adapter.get_info();
        let describe = format!("{} ({:?})", info.name, info.backend);
        log::info!("window on {describe}");
        let (device, queue) = pollster::block_on(crate::gpu::headless::request_device(&adapter))?;
        let caps = surface.get_capabilities(&adapter);
        let format = caps
            .formats
            .iter()
            .copied()
            .find(|f| f.is_srgb())
            .or_else(|| caps.formats.first().copied())
            .ok_or_else(|| Error::Device("the surface supports no format".into()))?;
        let size = window.inner_size();
        let config = wgpu::SurfaceConfiguration {
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
            format,
            width: size.width.max(1),
            height: size.height.max(1),
            present_mode: wgpu::PresentMode::AutoVsync,
            desired_maximum_frame_latency: 2,
            alpha_mode: caps
                .alpha_modes
                .first()
                .copied()
                .unwrap_or(wgpu::CompositeAlphaMode::Auto),
            view_formats: vec![],
            color_space: wgpu::SurfaceColorSpace::Auto,
        };
        let targets = Targets {
            color_format: format,
            depth_format: Some(DEPTH_FORMAT),
            sample_count: 1,
        };
        let terrain = Terrain::new(&device, &queue, targets, self.params)?;
        let timer = if self.timings {
            let t = GpuTimer::new(&device, &queue);
            if t.is_none() {
                println!("timings: {describe} has no timestamp queries");
            }
            t
        } else {
            None
        };
        let mut state = State {
            window,
            surface,
            device,
            queue,
            config,
            depth: None,
            terrain,
            timer,
            describe,
        };
        state.resize(size.width, size.height);
        Ok(state)
    }

    fn set_params(&mut self, params: TerrainParams) {
        if let Some(s) = &mut self.state {
            match s.terrain.set_params(&s.device, &s.queue, params) {
                Ok(_) => self.params = params,
                Err(e) => log::warn!("parameters refused: {e}"),
            }
        }
    }
}

impl State {
    /// Reconfigures for a new window size; a 0 x 0 (minimised) window is left unconfigured.
    fn resize(&mut self, width: u32, height: u32) {
        if width == 0 || height == 0 {
            self.depth = None;
            return;
        }
        let max = self.device.limits().max_texture_dimension_2d;
        self.config.width = width.min(max);
        self.config.height = height.min(max);
        self.surface.configure(&self.device, &self.config);
        let depth = self.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("relief:window:depth"),
            size: wgpu::Extent3d {
                width: self.config.width,
                height: self.config.height,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: DEPTH_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
            view_formats: &[],
        });
        self.depth = Some(depth.create_view(&Default::default()));
    }

    fn draw(&mut self, camera: &OrbitCamera, timed: bool) {
        let Some(depth) = &self.depth else {
            return; // minimised
        };
        let frame = match self.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(t)
            | wgpu::CurrentSurfaceTexture::Suboptimal(t) => t,
            wgpu::CurrentSurfaceTexture::Outdated | wgpu::CurrentSurfaceTexture::Lost => {
                self.surface.configure(&self.device, &self.config);
                return;
            }
            _ => return,
        };
        let view = frame.texture.create_view(&Default::default());
        let timer = self.timer.as_ref().filter(|_| timed);
        let mut encoder = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("relief:window:frame"),
            });
        self.terrain.encode_bake_timed(&mut encoder, timer);
        let aspect = self.config.width as f32 / self.config.height as f32;
        self.terrain.prepare(&self.queue, &camera.view(aspect));
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("relief:window:pass"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(crate::gpu::clear_color(
                            self.terrain.shading().sky_color,
                        )),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: depth,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Discard,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: timer.map(|t| t.render_writes(Slot::Render)),
                occlusion_query_set: None,
                multiview_mask: None,
            });
            self.terrain.render(&mut pass);
        }
        if let Some(t) = timer {
            t.resolve(&mut encoder);
        }
        self.queue.submit([encoder.finish()]);
        self.window.pre_present_notify();
        self.queue.present(frame);
        if let Some(t) = timer {
            match t.read(&self.device) {
                Ok(ms) => {
                    let parts: Vec<String> = Slot::ALL
                        .iter()
                        .filter_map(|&s| ms[s as usize].map(|v| format!("{} {v:.3} ms", s.name())))
                        .collect();
                    println!("timings on {}: {}", self.describe, parts.join(", "));
                }
                Err(e) => log::warn!("timings: {e}"),
            }
        }
    }
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.state.is_some() {
            return;
        }
        match self.init(event_loop) {
            Ok(state) => {
                state.window.request_redraw();
                self.state = Some(state);
                self.last = Instant::now();
            }
            Err(e) => self.fail(event_loop, e),
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::Resized(size) => {
                if let Some(s) = &mut self.state {
                    s.resize(size.width, size.height);
                    s.window.request_redraw();
                }
            }
            WindowEvent::KeyboardInput { event, .. } if event.state == ElementState::Pressed => {
                match event.logical_key {
                    Key::Named(NamedKey::Escape) => event_loop.exit(),
                    Key::Named(NamedKey::Space) => self.paused = !self.paused,
                    Key::Character(c) if c.eq_ignore_ascii_case("r") => {
                        let p = TerrainParams {
                            seed: self.params.seed.wrapping_add(1),
                            ..self.params
                        };
                        log::info!("seed {}", p.seed);
                        self.set_params(p);
                    }
                    _ => {}
                }
            }
            WindowEvent::MouseInput {
                state,
                button: MouseButton::Left,
                ..
            } => {
                self.drag = (state == ElementState::Pressed).then_some(self.cursor);
            }
            WindowEvent::CursorMoved { position, .. } => {
                self.cursor = (position.x, position.y);
                if let (Some((x0, y0)), Some(s)) = (self.drag, &self.state) {
                    let h = f64::from(s.config.height.max(1));
                    let k = std::f64::consts::PI / h;
                    self.camera.rotate(
                        ((position.x - x0) * k) as f32,
                        ((position.y - y0) * k) as f32,
                    );
                    self.drag = Some(self.cursor);
                }
            }
            WindowEvent::MouseWheel { delta, .. } => {
                let steps = match delta {
                    MouseScrollDelta::LineDelta(_, y) => y,
                    MouseScrollDelta::PixelDelta(p) => (p.y / 40.0) as f32,
                };
                self.camera.zoom(steps);
            }
            WindowEvent::RedrawRequested => {
                let now = Instant::now();
                let dt = now.duration_since(self.last).as_secs_f64().min(0.25);
                self.last = now;
                if !self.paused {
                    let mut p = self.params;
                    p.offset = [
                        (p.offset[0] + SCROLL_SPEED[0] * dt).rem_euclid(1.0),
                        (p.offset[1] + SCROLL_SPEED[1] * dt).rem_euclid(1.0),
                    ];
                    self.set_params(p);
                }
                self.frames += 1;
                let timed = self.timings && self.frames % 120 == 1;
                if let Some(s) = &mut self.state {
                    s.draw(&self.camera, timed);
                    s.window.request_redraw();
                }
            }
            _ => {}
        }
    }
}
