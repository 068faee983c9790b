//! The interactive window, shared by the native program and the web page: a winit app that
//! hosts [`Terrain`] exactly as any embedding app would (the surface texture is the target).
//! Drag (or one finger) orbits, the wheel (or a pinch) zooms, Space pauses the scroll, R
//! re-seeds, Escape quits (native).
//!
//! Only the edges differ by platform: native creates the device by blocking, the web
//! asynchronously (`web.rs`), and the web reports frames and errors to the page.

#[cfg(target_arch = "wasm32")]
pub mod web;

use crate::error::{Error, Result};
use crate::gpu::timing::{GpuTimer, Slot, Timings};
use crate::gpu::Targets;
use crate::params::TerrainParams;
use crate::{OrbitCamera, Terrain};
use std::collections::HashMap;
use std::sync::{Arc, Mutex};
use web_time::Instant;
use winit::application::ApplicationHandler;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, TouchPhase, WindowEvent};
use winit::event_loop::ActiveEventLoop;
use winit::keyboard::{Key, NamedKey};
use winit::window::{Window, WindowId};

/// Default scroll speed of the animated offset, in tiles per second along x.
pub const SCROLL_SPEED: f64 = 0.01;
/// Depth format of the window's depth buffer.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// MSAA samples in the window, the same as `relief render`, so both show the same picture.
pub const SAMPLES: u32 = 4;

/// What the window starts with; the web page fills it from the URL.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AppOptions {
    /// The scene.
    pub params: TerrainParams,
    /// Scroll speed in tiles per second (along x; y moves at 0.4 of it).
    pub speed: f64,
    /// Whether the scroll starts paused.
    pub paused: bool,
    /// Whether to measure and report GPU pass times.
    pub timings: bool,
}

impl Default for AppOptions {
    fn default() -> Self {
        Self {
            params: TerrainParams::default(),
            speed: SCROLL_SPEED,
            paused: false,
            timings: false,
        }
    }
}

impl AppOptions {
    /// Sets a scene parameter or one of the app's own keys (`speed`, `paused`).
    pub fn set(&mut self, key: &str, value: &str) -> Result<()> {
        match key {
            "speed" => {
                let s: f64 = value
                    .trim()
                    .parse()
                    .ok()
                    .filter(|s: &f64| s.is_finite() && s.abs() <= 10.0)
                    .ok_or_else(|| Error::invalid("speed", value, "-10..=10 tiles per second"))?;
                self.speed = s;
            }
            "paused" => self.paused = matches!(value.trim(), "1" | "true" | "yes" | "on"),
            _ => {
                let mut p = self.params;
                p.set(key, value)?;
                p.validate()?;
                self.params = p;
            }
        }
        Ok(())
    }

    /// Applies a URL query string (`seed=3&octaves=6&paused=1`); the first bad entry is an
    /// error and nothing after it is applied.
    pub fn apply_query(&mut self, query: &str) -> Result<()> {
        for pair in query
            .trim_start_matches('?')
            .split('&')
            .filter(|p| !p.is_empty())
        {
            let (k, v) = pair.split_once('=').unwrap_or((pair, ""));
            self.set(&k.replace('-', "_"), &percent_decode(v))?;
        }
        Ok(())
    }

    /// The query string that reproduces these options.
    pub fn to_query(&self) -> String {
        let mut parts: Vec<String> = TerrainParams::KEYS
            .iter()
            .map(|k| format!("{k}={}", self.params.get(k).unwrap_or_default()))
            .collect();
        parts.push(format!("speed={}", self.speed));
        parts.push(format!("paused={}", u8::from(self.paused)));
        parts.join("&")
    }
}

fn percent_decode(s: &str) -> String {
    let bytes = s.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        match bytes[i] {
            b'%' if i + 2 < bytes.len() => {
                let hex = std::str::from_utf8(&bytes[i + 1..i + 3]).ok();
                match hex.and_then(|h| u8::from_str_radix(h, 16).ok()) {
                    Some(b) => {
                        out.push(b);
                        i += 3;
                        continue;
                    }
                    None => out.push(b'%'),
                }
            }
            b'+' => out.push(b' '),
            b => out.push(b),
        }
        i += 1;
    }
    String::from_utf8_lossy(&out).into_owned()
}

/// Events the app receives besides winit's.
pub enum UserEvent {
    /// The GPU state finished initialising (the web creates it asynchronously).
    Ready(Result<Box<State>>),
    /// The page changed a parameter.
    Set(String, String),
}

/// Frame statistics reported to the front end.
#[derive(Clone, Copy, Debug, Default)]
pub struct Stats {
    /// Frames drawn so far.
    pub frames: u64,
    /// Frames per second over the last half second.
    pub fps: f64,
    /// Latest GPU pass times, when the adapter has timestamps.
    pub gpu: Option<Timings>,
    /// Whether this adapter can time passes at all.
    pub timestamps: bool,
}

/// The window's GPU state: surface, device, depth and MSAA targets, and the terrain.
pub struct State {
    window: Arc<Window>,
    surface: wgpu::Surface<'static>,
    device: wgpu::Device,
    queue: wgpu::Queue,
    config: wgpu::SurfaceConfiguration,
    depth: Option<wgpu::TextureView>,
    msaa: Option<wgpu::TextureView>,
    terrain: Terrain,
    timer: Option<GpuTimer>,
    timing_pending: Arc<Mutex<Option<Result<Timings>>>>,
    timing_busy: bool,
    // The instance and adapter the surface and device came from, kept for the window's life.
    _instance: wgpu::Instance,
    _adapter: wgpu::Adapter,
    /// "name (backend)" of the adapter.
    pub describe: String,
}

impl State {
    /// Creates the surface, device and terrain for `window`.
    pub async fn new(
        window: Arc<Window>,
        instance: wgpu::Instance,
        params: TerrainParams,
        timings: bool,
    ) -> Result<Self> {
        let surface = instance
            .create_surface(window.clone())
            .map_err(|e| Error::Device(format!("cannot create a surface: {e}")))?;
        let adapter = instance
            .request_adapter(&wgpu::RequestAdapterOptions {
                power_preference: wgpu::PowerPreference::HighPerformance,
                force_fallback_adapter: false,
                compatible_surface: Some(&surface),
                apply_limit_buckets: false,
            })
            .await
            .map_err(|e| Error::NoAdapter(e.to_string()))?;
        let info = adapter.get_info();
        let describe = if info.name.is_empty() {
            format!("{:?}", info.backend)
        } else {
            format!("{} ({:?})", info.name, info.backend)
        };
        log::info!("window on {describe}");
        let (device, queue) = crate::gpu::request_device(&adapter).await?;
        // A window has no Result to return per frame: log what wgpu reports instead of the
        // default handler's panic.
        device.on_uncaptured_error(Arc::new(|e| log::error!("wgpu: {e}")));
        device.set_device_lost_callback(|reason, message| {
            log::error!("GPU device lost ({reason:?}): {message}")
        });
        let caps = surface.get_capabilities(&adapter);
        let format = caps
            .formats
            .iter()
            .copied()
            .find(|f| f.is_srgb())
            .or_else(|| caps.formats.first().copied())
            .ok_or_else(|| Error::Device("the surface supports no format".into()))?;
        // Browsers offer only non-sRGB canvas formats. sRGB views of them are allowed, but
        // headless Chromium (SwiftShader) wrote through such views without encoding; relief
        // encodes in its shader instead when the target is not sRGB, which works everywhere.
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
            sample_count: SAMPLES,
        };
        let terrain = Terrain::new(&device, &queue, targets, params)?;
        let timer = if timings {
            GpuTimer::new(&device, &queue)
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
            msaa: None,
            terrain,
            timer,
            timing_pending: Arc::new(Mutex::new(None)),
            timing_busy: false,
            _instance: instance,
            _adapter: adapter,
            describe,
        };
        state.resize(size.width, size.height);
        Ok(state)
    }

    /// Reconfigures for a new window size; a 0 x 0 (minimised) window is left unconfigured.
    fn resize(&mut self, width: u32, height: u32) {
        if width == 0 || height == 0 {
            self.depth = None;
            self.msaa = None;
            return;
        }
        let max = self.device.limits().max_texture_dimension_2d;
        self.config.width = width.min(max);
        self.config.height = height.min(max);
        self.surface.configure(&self.device, &self.config);
        let make = |label, format| {
            self.device
                .create_texture(&wgpu::TextureDescriptor {
                    label: Some(label),
                    size: wgpu::Extent3d {
                        width: self.config.width,
                        height: self.config.height,
                        depth_or_array_layers: 1,
                    },
                    mip_level_count: 1,
                    sample_count: SAMPLES,
                    dimension: wgpu::TextureDimension::D2,
                    format,
                    usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
                    view_formats: &[],
                })
                .create_view(&Default::default())
        };
        self.depth = Some(make("relief:window:depth", DEPTH_FORMAT));
        self.msaa = (SAMPLES > 1).then(|| make("relief:window:msaa", self.config.format));
    }

    /// Draws one frame; returns whether one was presented.
    fn draw(&mut self, camera: &OrbitCamera, stats: &mut Stats) -> bool {
        let Some(depth) = &self.depth else {
            return false; // minimised
        };
        let frame = match self.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(t)
            | wgpu::CurrentSurfaceTexture::Suboptimal(t) => t,
            wgpu::CurrentSurfaceTexture::Outdated | wgpu::CurrentSurfaceTexture::Lost => {
                self.surface.configure(&self.device, &self.config);
                return false;
            }
            _ => return false,
        };
        let view = frame.texture.create_view(&Default::default());
        let pending = self.timing_pending.lock().ok().and_then(|mut p| p.take());
        if let Some(result) = pending {
            self.timing_busy = false;
            match result {
                Ok(t) => stats.gpu = Some(t),
                Err(e) => log::warn!("timings: {e}"),
            }
        }
        // Time one frame in thirty, and only once the previous read has come back.
        let timer = self
            .timer
            .as_ref()
            .filter(|_| !self.timing_busy && stats.frames.is_multiple_of(30));
        let mut encoder = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("relief:window:frame"),
            });
        self.terrain.encode_bake_timed(&mut encoder, timer);
        let aspect = self.config.width as f32 / self.config.height as f32;
        self.terrain.prepare(&self.queue, &camera.view(aspect));
        {
            let (target, resolve_target) = match &self.msaa {
                Some(msaa) => (msaa, Some(&view)),
                None => (&view, None),
            };
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("relief:window:pass"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: target,
                    depth_slice: None,
                    resolve_target,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(crate::gpu::clear_color(
                            self.terrain.shading().sky_color,
                            self.config.format,
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
        if let Some(t) = timer {
            self.timing_busy = true;
            let slot = self.timing_pending.clone();
            t.read_async(move |r| {
                if let Ok(mut p) = slot.lock() {
                    *p = Some(r);
                }
            });
        }
        self.window.pre_present_notify();
        self.queue.present(frame);
        #[cfg(not(target_arch = "wasm32"))]
        let _ = self.device.poll(wgpu::PollType::Poll);
        true
    }
}

/// The winit application: input, animation, and the frame loop around [`State`].
pub struct App {
    options: AppOptions,
    camera: OrbitCamera,
    drag: Option<(f64, f64)>,
    cursor: (f64, f64),
    touches: HashMap<u64, (f64, f64)>,
    last: Instant,
    fps_window: (Instant, u64),
    stats: Stats,
    state: Option<State>,
    starting: bool,
    error: Option<Error>,
    #[cfg(target_arch = "wasm32")]
    proxy: winit::event_loop::EventLoopProxy<UserEvent>,
}

impl App {
    /// A new app; the window opens when the event loop resumes.
    pub fn new(
        options: AppOptions,
        #[cfg(target_arch = "wasm32")] proxy: winit::event_loop::EventLoopProxy<UserEvent>,
    ) -> Self {
        let now = Instant::now();
        Self {
            options,
            camera: OrbitCamera::default(),
            drag: None,
            cursor: (0.0, 0.0),
            touches: HashMap::new(),
            last: now,
            fps_window: (now, 0),
            stats: Stats::default(),
            state: None,
            starting: false,
            error: None,
            #[cfg(target_arch = "wasm32")]
            proxy,
        }
    }

    /// The error that ended the app, if any.
    pub fn take_error(&mut self) -> Option<Error> {
        self.error.take()
    }

    fn fail(&mut self, event_loop: &ActiveEventLoop, e: Error) {
        log::error!("{e}");
        #[cfg(target_arch = "wasm32")]
        web::show_error(&e.to_string());
        self.error = Some(e);
        event_loop.exit();
    }

    fn set_params(&mut self, params: TerrainParams) -> Result<()> {
        if let Some(s) = &mut self.state {
            s.terrain.set_params(&s.device, &s.queue, params)?;
        }
        self.options.params = params;
        Ok(())
    }

    fn set(&mut self, key: &str, value: &str) -> Result<()> {
        let mut options = self.options;
        options.set(key, value)?;
        self.set_params(options.params)?;
        self.options = options;
        #[cfg(target_arch = "wasm32")]
        web::options_changed(&self.options);
        Ok(())
    }

    fn ready(&mut self, state: State) {
        self.stats.timestamps = state.timer.is_some();
        if self.options.timings && state.timer.is_none() {
            println!("timings: {} has no timestamp queries", state.describe);
        }
        state.window.request_redraw();
        self.state = Some(state);
        self.last = Instant::now();
        #[cfg(target_arch = "wasm32")]
        web::options_changed(&self.options);
    }

    fn redraw(&mut self) {
        let now = Instant::now();
        let dt = now.duration_since(self.last).as_secs_f64().min(0.25);
        self.last = now;
        if !self.options.paused && self.options.speed != 0.0 {
            let mut p = self.options.params;
            let s = self.options.speed;
            p.offset = [
                (p.offset[0] + s * dt).rem_euclid(1.0),
                (p.offset[1] + 0.4 * s * dt).rem_euclid(1.0),
            ];
            if let Err(e) = self.set_params(p) {
                log::warn!("scroll refused: {e}");
            }
        }
        let Some(s) = &mut self.state else { return };
        if s.draw(&self.camera, &mut self.stats) {
            self.stats.frames += 1;
        }
        s.window.request_redraw();
        let (t0, f0) = self.fps_window;
        let span = now.duration_since(t0).as_secs_f64();
        if span >= 0.5 {
            self.stats.fps = (self.stats.frames - f0) as f64 / span;
            self.fps_window = (now, self.stats.frames);
            self.report();
        }
        #[cfg(target_arch = "wasm32")]
        web::frame_done(&self.stats);
    }

    fn report(&self) {
        #[cfg(target_arch = "wasm32")]
        web::show_stats(&self.stats);
        #[cfg(not(target_arch = "wasm32"))]
        if self.options.timings {
            if let (Some(t), Some(s)) = (self.stats.gpu, &self.state) {
                println!("timings on {}: {}", s.describe, format_timings(&t));
            }
        }
    }

    fn touch(&mut self, id: u64, phase: TouchPhase, x: f64, y: f64) {
        let before = self.touches.clone();
        match phase {
            TouchPhase::Started | TouchPhase::Moved => {
                self.touches.insert(id, (x, y));
            }
            TouchPhase::Ended | TouchPhase::Cancelled => {
                self.touches.remove(&id);
            }
        }
        let height = self
            .state
            .as_ref()
            .map_or(720.0, |s| f64::from(s.config.height.max(1)));
        match (before.len(), self.touches.len()) {
            (1, 1) if phase == TouchPhase::Moved => {
                if let Some(&(x0, y0)) = before.get(&id) {
                    let k = std::f64::consts::PI / height;
                    self.camera
                        .rotate(((x - x0) * k) as f32, ((y - y0) * k) as f32);
                }
            }
            (2, 2) => {
                let dist = |t: &HashMap<u64, (f64, f64)>| {
                    let v: Vec<_> = t.values().collect();
                    ((v[0].0 - v[1].0).powi(2) + (v[0].1 - v[1].1).powi(2)).sqrt()
                };
                let (d0, d1) = (dist(&before), dist(&self.touches));
                if d0 > 1.0 && d1 > 1.0 {
                    // Spreading two fingers by 10% zooms one notch.
                    self.camera.zoom(((d1 / d0).ln() / 1.1f64.ln()) as f32);
                }
            }
            _ => {}
        }
    }
}

/// "bake 0.186 ms, normals 0.016 ms, render 1.103 ms" for the passes that ran.
pub fn format_timings(t: &Timings) -> String {
    Slot::ALL
        .iter()
        .filter_map(|&s| t[s as usize].map(|ms| format!("{} {ms:.3} ms", s.name())))
        .collect::<Vec<_>>()
        .join(", ")
}

impl ApplicationHandler<UserEvent> for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.state.is_some() || self.starting {
            return;
        }
        self.starting = true;
        let attributes = Window::default_attributes().with_title("relief");
        #[cfg(not(target_arch = "wasm32"))]
        let attributes = attributes.with_inner_size(winit::dpi::LogicalSize::new(1280, 720));
        #[cfg(target_arch = "wasm32")]
        let attributes = web::window_attributes(attributes);
        let window = match event_loop.create_window(attributes) {
            Ok(w) => Arc::new(w),
            Err(e) => {
                return self.fail(
                    event_loop,
                    Error::Device(format!("cannot create a window: {e}")),
                )
            }
        };
        let instance =
            wgpu::Instance::new(wgpu::InstanceDescriptor::new_with_display_handle_from_env(
                Box::new(event_loop.owned_display_handle()),
            ));
        let future = State::new(window, instance, self.options.params, self.options.timings);
        #[cfg(not(target_arch = "wasm32"))]
        match pollster::block_on(future) {
            Ok(state) => self.ready(state),
            Err(e) => self.fail(event_loop, e),
        }
        #[cfg(target_arch = "wasm32")]
        {
            let proxy = self.proxy.clone();
            wasm_bindgen_futures::spawn_local(async move {
                let _ = proxy.send_event(UserEvent::Ready(future.await.map(Box::new)));
            });
        }
    }

    fn user_event(&mut self, event_loop: &ActiveEventLoop, event: UserEvent) {
        match event {
            UserEvent::Ready(Ok(state)) => self.ready(*state),
            UserEvent::Ready(Err(e)) => self.fail(event_loop, e),
            UserEvent::Set(k, v) => {
                if let Err(e) = self.set(&k, &v) {
                    log::warn!("{e}");
                    #[cfg(target_arch = "wasm32")]
                    web::show_error(&e.to_string());
                }
            }
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
                    #[cfg(not(target_arch = "wasm32"))]
                    Key::Named(NamedKey::Escape) => event_loop.exit(),
                    Key::Named(NamedKey::Space) => {
                        let paused = if self.options.paused { "0" } else { "1" };
                        let _ = self.set("paused", paused);
                    }
                    Key::Character(c) if c.eq_ignore_ascii_case("r") => {
                        let seed = self.options.params.seed.wrapping_add(1).to_string();
                        if let Err(e) = self.set("seed", &seed) {
                            log::warn!("{e}");
                        }
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
                    let k = std::f64::consts::PI / f64::from(s.config.height.max(1));
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
                    MouseScrollDelta::PixelDelta(p) => (p.y / 60.0) as f32,
                };
                self.camera.zoom(steps);
            }
            WindowEvent::Touch(t) => self.touch(t.id, t.phase, t.location.x, t.location.y),
            WindowEvent::RedrawRequested => self.redraw(),
            _ => {}
        }
    }
}

/// Opens the native window and runs until it is closed.
#[cfg(not(target_arch = "wasm32"))]
pub fn run_native(options: AppOptions) -> Result<()> {
    let event_loop = winit::event_loop::EventLoop::<UserEvent>::with_user_event()
        .build()
        .map_err(|e| Error::Device(format!("cannot open a window: {e}")))?;
    let mut app = App::new(options);
    event_loop
        .run_app(&mut app)
        .map_err(|e| Error::Device(format!("window event loop failed: {e}")))?;
    match app.take_error() {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn query_round_trip() {
        let mut o = AppOptions::default();
        o.apply_query("?seed=42&octaves=5&height-scale=0.8&offset=0.5%2C0.25&paused=1&speed=0.02")
            .unwrap();
        assert_eq!(o.params.seed, 42);
        assert_eq!(o.params.octaves, 5);
        assert_eq!(o.params.height_scale, 0.8);
        assert_eq!(o.params.offset, [0.5, 0.25]);
        assert!(o.paused);
        let mut p = AppOptions::default();
        p.apply_query(&o.to_query()).unwrap();
        assert_eq!(o, p);
        let e = p.apply_query("seed=3&grid=1").unwrap_err().to_string();
        assert!(e.contains("grid"), "{e}");
        assert_eq!(
            p.params.grid, o.params.grid,
            "a rejected value is not applied"
        );
    }
}
