//! The window's GPU state: surface, device, depth and MSAA targets, and the terrain, hosted
//! exactly as any embedding app would host relief (the surface texture is the target).

use super::{UserEvent, DEPTH_FORMAT, SAMPLES};
use relief::camera::View;
use relief::error::{Error, Result};
use relief::gpu::raymarch::{RayMarcher, RayScene};
use relief::gpu::timing::{GpuTimer, Slot};
use relief::gpu::Targets;
use relief::params::TerrainParams;
use relief::{FlyCamera, Method, Terrain, World, WorldParams};
use std::sync::Arc;
use winit::event_loop::EventLoopProxy;
use winit::window::Window;

/// Posts events to the app from wgpu's callbacks, which must be `Send`. Natively that is the
/// event loop's proxy; on the web the app's events are not `Send`, so they go through the
/// page's own proxy (`web::send`).
#[derive(Clone)]
struct Poster {
    #[cfg(not(target_arch = "wasm32"))]
    proxy: EventLoopProxy<UserEvent>,
}

impl Poster {
    #[cfg_attr(
        target_arch = "wasm32",
        expect(unused_variables, reason = "the web uses its own proxy")
    )]
    fn new(proxy: &EventLoopProxy<UserEvent>) -> Self {
        Self {
            #[cfg(not(target_arch = "wasm32"))]
            proxy: proxy.clone(),
        }
    }

    fn send(&self, event: UserEvent) {
        #[cfg(not(target_arch = "wasm32"))]
        let _ = self.proxy.send_event(event);
        #[cfg(target_arch = "wasm32")]
        super::web::send(event);
    }
}

/// What one call of [`State::draw`] did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Drawn {
    /// A frame was presented.
    Frame,
    /// Nothing to draw into (minimised, or the surface was busy or reconfigured).
    Skipped,
    /// The window's surface is lost: it must be created again ([`State::recreate_surface`]).
    SurfaceLost,
}

/// The window's GPU state.
pub struct State {
    pub(crate) window: Arc<Window>,
    surface: wgpu::Surface<'static>,
    pub(crate) device: wgpu::Device,
    pub(crate) queue: wgpu::Queue,
    pub(crate) config: wgpu::SurfaceConfiguration,
    depth: Option<wgpu::TextureView>,
    msaa: Option<wgpu::TextureView>,
    /// Samples of the window's depth and colour targets: [`relief::gpu::render_samples`] of the
    /// method last drawn with the mesh.
    samples: u32,
    /// Setting the terrain's or the world's targets to [`State::samples`] failed.
    targets_failed: bool,
    /// The samples a pixel and the raster that `visibility` and `hybrid` draw with (from the
    /// chosen candidate); the method is the app's, given to each [`State::draw`].
    method_knobs: (u32, relief::Raster),
    /// Whether the endless world accumulates frames ([`relief::World::set_temporal`]); the
    /// app's, set before each [`State::draw`].
    pub(crate) temporal: bool,
    pub(crate) terrain: Terrain,
    /// The endless world, when the window shows it instead of the tile.
    pub(crate) world: Option<World>,
    pub(crate) timer: Option<GpuTimer>,
    /// Time the last [`State::draw`] spent waiting on the surface (acquiring its texture and
    /// presenting), which is the GPU's pace, not CPU work.
    pub(crate) waited: web_time::Duration,
    // The instance and adapter the surface and device came from, kept for the window's life.
    _instance: wgpu::Instance,
    #[cfg_attr(
        target_arch = "wasm32",
        expect(
            dead_code,
            reason = "the page does not choose its method by measurement"
        )
    )]
    pub(crate) adapter: wgpu::Adapter,
    /// "name (backend)" of the adapter.
    pub describe: String,
    /// The ray caster's targets when the method is a ray caster (rebuilt for a new size or
    /// world), and the pass that shows its image.
    rays: Option<RayCast>,
    blit: Option<relief::gpu::blit::Blit>,
    /// The blog's pipeline, once the method `blog` has been drawn.
    blog: Option<relief::gpu::blog::Blog>,
    /// Building it failed (said once; the mesh is drawn instead).
    blog_failed: bool,
}

/// A ray caster sized for the window: its scene, its cast size, rays per pixel each way.
struct RayCast {
    caster: RayMarcher,
    /// The blit's bind group for the caster's image.
    shown: wgpu::BindGroup,
    scene: RayScene,
    size: (u32, u32),
    ss: u32,
}

impl State {
    /// Whether levels wait on a bake (over the per-frame budget): frames must keep coming.
    pub(crate) fn baking(&self) -> bool {
        match &self.world {
            Some(w) => w.pending_texels() > 0,
            None => self.terrain.pending_texels() > 0,
        }
    }

    /// Creates the surface, device and terrain for `window`. wgpu errors nobody captures and
    /// the loss of the device reach the app through `proxy` as events.
    pub async fn new(
        window: Arc<Window>,
        instance: wgpu::Instance,
        params: TerrainParams,
        world: Option<WorldParams>,
        timings: bool,
        proxy: EventLoopProxy<UserEvent>,
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
        let describe = relief::gpu::describe_adapter(&info);
        log::info!("window on {describe}");
        let (device, queue) = relief::gpu::request_device(&adapter).await?;
        // A window has no Result to return per frame: wgpu's errors are logged instead of the
        // default handler's panic, and a lost device is reported to the app to recover from.
        let errors = Poster::new(&proxy);
        device.on_uncaptured_error(Arc::new(move |e| {
            errors.send(UserEvent::GpuError(e.to_string()));
        }));
        let lost = Poster::new(&proxy);
        device.set_device_lost_callback(move |reason, message| {
            let why = match reason {
                wgpu::DeviceLostReason::Destroyed => "destroyed".to_owned(),
                _ => format!("{reason:?}"),
            };
            let message = message.split_whitespace().collect::<Vec<_>>().join(" ");
            let message = message.trim_end_matches('.');
            let text = if message.is_empty() {
                why
            } else {
                format!("{why}: {message}")
            };
            lost.send(UserEvent::DeviceLost(text));
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
        // A copy into the surface lets the visibility method write its frame without a render
        // pass (`World::present`), where the surface allows one.
        let copy = caps.usages & wgpu::TextureUsages::COPY_DST;
        let config = wgpu::SurfaceConfiguration {
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | copy,
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
        // A size over this device's limit is clamped here and refused (with its reason) by
        // the app's first `set_params`, so one bad value does not stop the window.
        let limit = device.limits().max_texture_dimension_2d;
        let start = TerrainParams {
            size: params.size.min(limit),
            ..params
        };
        let terrain = Terrain::new(&device, &queue, targets, start)?;
        let world = world
            .map(|p| World::new(&device, &queue, targets, p))
            .transpose()?;
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
            samples: SAMPLES,
            targets_failed: false,
            method_knobs: (4, relief::Raster::Hardware),
            temporal: true,
            terrain,
            world,
            timer,
            _instance: instance,
            adapter,
            describe,
            rays: None,
            blit: None,
            blog: None,
            blog_failed: false,
            waited: web_time::Duration::ZERO,
        };
        state.resize(size.width, size.height);
        Ok(state)
    }

    /// Reconfigures for a new window size; a 0 x 0 (minimised) window is left unconfigured.
    pub fn resize(&mut self, width: u32, height: u32) {
        if width == 0 || height == 0 {
            self.depth = None;
            self.msaa = None;
            return;
        }
        let max = self.device.limits().max_texture_dimension_2d;
        self.config.width = width.min(max);
        self.config.height = height.min(max);
        self.surface.configure(&self.device, &self.config);
        self.make_textures();
    }

    /// The depth and (for MSAA) colour textures at the surface's size and [`State::samples`].
    fn make_textures(&mut self) {
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
                    sample_count: self.samples,
                    dimension: wgpu::TextureDimension::D2,
                    format,
                    usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
                    view_formats: &[],
                })
                .create_view(&Default::default())
        };
        self.depth = Some(make("relief:window:depth", DEPTH_FORMAT));
        self.msaa = (self.samples > 1).then(|| make("relief:window:msaa", self.config.format));
    }

    /// The window's targets at `samples` a pixel, as the terrain and the world draw into them.
    fn targets(&self, samples: u32) -> Targets {
        Targets {
            color_format: self.config.format,
            depth_format: Some(DEPTH_FORMAT),
            sample_count: samples,
        }
    }

    /// Sets the window's targets to `samples` a pixel (a mesh-based method's
    /// [`relief::gpu::render_samples`]): the terrain's and the world's pipelines, and the depth
    /// and colour textures. The blog's pipeline is built again when next drawn.
    /// Every step is tried and the textures rebuilt whatever fails (so the pipelines and the
    /// textures never differ in samples); the first error is returned, and the next frame of a
    /// method of these samples tries again.
    fn set_samples(&mut self, samples: u32) -> Result<()> {
        let targets = self.targets(samples);
        self.blog = None;
        self.blog_failed = false;
        let terrain = self.terrain.set_targets(&self.device, targets);
        let world = match &mut self.world {
            Some(world) => world.set_targets(&self.device, targets),
            None => Ok(()),
        };
        self.samples = samples;
        if self.depth.is_some() {
            self.make_textures();
        }
        let failed = terrain.and(world);
        // Not set after all: the next frame tries again.
        self.targets_failed = failed.is_err();
        failed
    }

    /// Draws with `c` from the next frame on: its method's samples a pixel and raster in the
    /// terrain and the world, and the window's targets for its method (the method itself is the
    /// app's, given to each [`State::draw`]).
    pub fn use_candidate(&mut self, c: relief::choice::Candidate) -> Result<()> {
        c.config().validate()?;
        self.method_knobs = (c.samples, c.raster);
        self.set_samples(relief::gpu::render_samples(c.method))
    }

    /// Creates the window's surface again (after [`Drawn::SurfaceLost`]) on the same device.
    pub fn recreate_surface(&mut self) -> Result<()> {
        self.surface = self
            ._instance
            .create_surface(self.window.clone())
            .map_err(|e| Error::Device(format!("cannot create a surface again: {e}")))?;
        let (w, h) = (self.config.width, self.config.height);
        self.resize(w, h);
        self.window.request_redraw();
        Ok(())
    }

    /// Whether the window is minimised (nothing to draw into).
    pub fn minimised(&self) -> bool {
        self.depth.is_none()
    }

    /// Width over height of the surface.
    pub fn aspect(&self) -> f32 {
        self.config.width as f32 / self.config.height.max(1) as f32
    }

    /// Makes ready what a frame of `method` draws with (its targets, its pipelines, the
    /// temporal service), `flying` through the endless world or not: what [`State::draw`] does
    /// first, and the page before its first frame (whose GPU builds the pipelines after the
    /// calls return).
    pub fn configure(&mut self, method: Method, flying: bool) {
        // The mesh-based methods draw into targets of their own samples a pixel (ray casters
        // show their image without them). The endless world's forward mesh accumulating
        // jittered frames anti-aliases through its history, as the visibility method at one
        // sample does: a 4x target would only make its composite cost more (on an H100 at
        // 1080p the mesh took 14.3 ms a frame with the history into 4x targets, 10.9 ms
        // without).
        if method.ray_path().is_none() {
            let mesh = Self::mesh_method(method);
            let samples = if flying && self.temporal && mesh == Method::Mesh {
                1
            } else {
                relief::gpu::render_samples(mesh)
            };
            if samples != self.samples || self.targets_failed {
                if let Err(e) = self.set_samples(samples) {
                    log::warn!("{e}");
                }
            }
        }
        if method == Method::Blog && !flying && self.blog.is_none() && !self.blog_failed {
            // Built on first use, for the window's targets; tried once.
            match relief::gpu::blog::Blog::new(&self.device, *self.terrain.targets()) {
                Ok(blog) => self.blog = Some(blog),
                Err(e) => {
                    self.blog_failed = true;
                    log::warn!("the blog's pipeline could not be built ({e}): drawing the mesh");
                }
            }
        }
        if method.ray_path().is_some() {
            return;
        }
        let config = self.method_config(method);
        match (&mut self.world, flying) {
            (Some(world), true) => {
                if let Err(e) = world.set_method(&self.device, config) {
                    log::warn!("{e}");
                }
                let temporal = if self.temporal {
                    relief::Temporal::INTERACTIVE
                } else {
                    relief::Temporal::OFF
                };
                if let Err(e) = world.set_temporal(&self.device, temporal) {
                    log::warn!("{e}");
                }
            }
            _ if method == Method::Blog => {}
            _ => {
                if let Err(e) = self.terrain.set_method(&self.device, config) {
                    log::warn!("{e}");
                }
            }
        }
    }

    /// Draws one frame seen through `view` (or, showing the endless world, through `fly`) with
    /// `method`; with `timed`, writes GPU timestamps and resolves them for
    /// [`GpuTimer::read_async`].
    pub fn draw(
        &mut self,
        view: &View,
        fly: Option<&FlyCamera>,
        timed: bool,
        method: Method,
    ) -> Drawn {
        self.configure(method, fly.is_some());
        let Some(depth) = &self.depth else {
            return Drawn::Skipped; // minimised
        };
        let acquire = web_time::Instant::now();
        let acquired = self.surface.get_current_texture();
        self.waited = acquire.elapsed();
        let frame = match acquired {
            wgpu::CurrentSurfaceTexture::Success(t)
            | wgpu::CurrentSurfaceTexture::Suboptimal(t) => t,
            wgpu::CurrentSurfaceTexture::Outdated => {
                // The surface changed under us (resize, display change): configure it again
                // and draw the next frame.
                self.surface.configure(&self.device, &self.config);
                self.window.request_redraw();
                return Drawn::Skipped;
            }
            wgpu::CurrentSurfaceTexture::Lost => return Drawn::SurfaceLost,
            wgpu::CurrentSurfaceTexture::Timeout => {
                self.window.request_redraw();
                return Drawn::Skipped;
            }
            wgpu::CurrentSurfaceTexture::Occluded => return Drawn::Skipped,
            _ => {
                // A validation error (reported through the error handler) or a lost device:
                // poll so that a loss reaches the app and it can recover.
                #[cfg(not(target_arch = "wasm32"))]
                let _ = self.device.poll(wgpu::PollType::Poll);
                return Drawn::Skipped;
            }
        };
        let target_view = frame.texture.create_view(&Default::default());
        let timer = self.timer.as_ref().filter(|_| timed);
        let mut encoder = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("relief:window:frame"),
            });
        let size = (self.config.width, self.config.height);
        if method.ray_path().is_some() {
            if let Err(e) = self.cast(&mut encoder, view, fly, timed, method, &target_view) {
                log::warn!("{e}");
                // Nothing was cast: show the sky, not whatever the surface texture held.
                let sky =
                    relief::gpu::clear_color(self.terrain.shading().sky_color, self.config.format);
                encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("relief:window:clear"),
                    color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                        view: &target_view,
                        depth_slice: None,
                        resolve_target: None,
                        ops: wgpu::Operations {
                            load: wgpu::LoadOp::Clear(sky),
                            store: wgpu::StoreOp::Store,
                        },
                    })],
                    depth_stencil_attachment: None,
                    timestamp_writes: None,
                    occlusion_query_set: None,
                    multiview_mask: None,
                });
            }
            return self.finish(encoder, frame, timed);
        }
        let world = match (&mut self.world, fly) {
            (Some(world), Some(fly)) => {
                let view = fly.view(size);
                if let Err(e) =
                    world.prepare_timed(&self.device, &self.queue, &mut encoder, &view, timer)
                {
                    log::warn!("{e}");
                }
                Some(&*world)
            }
            _ if method == Method::Blog => {
                self.blog_frame(&mut encoder, view, timer);
                None
            }
            _ => {
                self.terrain.set_viewport(size);
                if let Err(e) =
                    self.terrain
                        .prepare_timed(&self.device, &self.queue, &mut encoder, view, timer)
                {
                    log::warn!("{e}");
                }
                None
            }
        };
        // The visibility method and the hybrid write their frame straight into the surface
        // where they can: no render pass (on a compute chip a full-screen draw costs more than
        // their shading).
        let presented = self.msaa.is_none()
            && match (world, &self.blog) {
                (Some(world), _) => world.present(&mut encoder, &frame.texture, timer),
                (None, Some(_)) if method == Method::Blog => false,
                _ => self.terrain.present(&mut encoder, &frame.texture, timer),
            };
        if !presented {
            let (target, resolve_target) = match &self.msaa {
                Some(msaa) => (msaa, Some(&target_view)),
                None => (&target_view, None),
            };
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("relief:window:pass"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: target,
                    depth_slice: None,
                    resolve_target,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(relief::gpu::clear_color(
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
            match (world, &self.blog) {
                (Some(world), _) => world.render(&mut pass),
                (None, Some(blog)) if method == Method::Blog => blog.render(&mut pass),
                _ => self.terrain.render(&mut pass),
            }
        }
        self.finish(encoder, frame, timed)
    }

    /// How the mesh draws a frame of `method`: itself where it is one of the mesh's methods,
    /// else the forward mesh.
    fn mesh_method(method: Method) -> Method {
        if method.is_mesh() {
            method
        } else {
            Method::Mesh
        }
    }

    /// How the terrain and the world draw a frame of `method`: the mesh-based method with the
    /// chosen samples and raster.
    fn method_config(&self, method: Method) -> relief::MethodConfig {
        relief::MethodConfig {
            method: Self::mesh_method(method),
            samples: self.method_knobs.0,
            raster: self.method_knobs.1,
        }
    }

    /// Submits the frame's work and presents it.
    fn finish(
        &mut self,
        mut encoder: wgpu::CommandEncoder,
        frame: wgpu::SurfaceTexture,
        timed: bool,
    ) -> Drawn {
        if let Some(t) = self.timer.as_ref().filter(|_| timed) {
            t.resolve(&mut encoder);
        }
        self.queue.submit([encoder.finish()]);
        self.window.pre_present_notify();
        let present = web_time::Instant::now();
        self.queue.present(frame);
        self.waited += present.elapsed();
        // Natively, callbacks (timestamp reads, device loss) run inside poll.
        #[cfg(not(target_arch = "wasm32"))]
        let _ = self.device.poll(wgpu::PollType::Poll);
        Drawn::Frame
    }

    /// Records the blog's bake and normal passes for a frame of the method `blog`, scrolled
    /// along x as the tile is (nothing if the blog's pipeline could not be built).
    fn blog_frame(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        view: &View,
        timer: Option<&GpuTimer>,
    ) {
        let Some(blog) = &self.blog else {
            return;
        };
        let params = self.terrain.shown_params();
        let progress = self.terrain.shown_offset()[0] as f32;
        blog.prepare(&self.queue, &params, self.terrain.shading(), view, progress);
        blog.encode_bake(encoder, timer);
    }

    /// Records a ray-cast frame with `method` (timed as the render pass) and shows it in
    /// `target`.
    fn cast(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        view: &View,
        fly: Option<&FlyCamera>,
        timed: bool,
        method: Method,
        target: &wgpu::TextureView,
    ) -> Result<()> {
        let (Some(path), Some(_)) = (method.ray_path(), method.ray_method(1)) else {
            return Ok(());
        };
        let size = (self.config.width, self.config.height);
        let world = match (&self.world, fly) {
            (Some(world), Some(fly)) => Some((world, fly.view(size))),
            _ => None,
        };
        let scene = match &world {
            Some((w, _)) => RayScene::for_world(w.params()),
            None => RayScene::Tile,
        };
        let max = self.device.limits().max_texture_dimension_2d;
        let ss = method.supersample();
        let ss = if size.0 * ss <= max && size.1 * ss <= max {
            ss
        } else {
            1
        };
        let cast = (size.0 * ss, size.1 * ss);
        if self
            .blit
            .as_ref()
            .is_none_or(|b| b.format() != self.config.format)
        {
            self.blit = Some(relief::gpu::blit::Blit::new(
                &self.device,
                self.config.format,
            ));
            self.rays = None; // bound to the old blit
        }
        let blit = self.blit.as_ref().expect("made above");
        if !self
            .rays
            .as_ref()
            .is_some_and(|r| r.scene == scene && r.size == cast && r.ss == ss)
        {
            self.rays = None;
            let caster = RayMarcher::for_scene(&self.device, cast.0, cast.1, scene)?;
            let shown = blit.bind(&self.device, &caster.color);
            self.rays = Some(RayCast {
                caster,
                shown,
                scene,
                size: cast,
                ss,
            });
        }
        let rays = self.rays.as_ref().expect("made above");
        match world {
            Some((world, view)) => {
                let params = world.params();
                let Some(how) = method.ray_method(params.land.octaves) else {
                    return Ok(());
                };
                // The world's own layout and slope bounds: nothing measured again per frame.
                let region = world.clipmap().drawn_region(view.eye.x, view.eye.z);
                let ray = relief::gpu::world_rays::WorldRayUniforms::with_slopes(
                    params,
                    &view,
                    (how, cast, region),
                    world.slope_bounds(),
                )?;
                // The world's clock, as the mesh-based methods draw it.
                let now = relief::world::WorldParams {
                    clock: world.clock(),
                    ..*params
                };
                let render = relief::gpu::world::render_uniforms(
                    &now,
                    world.shading(),
                    (relief::gpu::world_rays::ray_matrix(&view), region, view.eye),
                    true,
                );
                rays.caster.prepare_world(&self.queue, &render, &ray)?;
            }
            None => {
                // The offset shown, scrolled or baked.
                let params = self.terrain.shown_params();
                let Some(how) = method.ray_method(params.octaves) else {
                    return Ok(());
                };
                let shading = *self.terrain.shading();
                rays.caster
                    .prepare(&self.queue, &params, &shading, view, how);
            }
        }
        rays.caster
            .encode(encoder, path, self.timer.as_ref().filter(|_| timed));
        let timer = self.timer.as_ref().filter(|_| timed);
        blit.encode(&self.queue, encoder, (&rays.shown, ss), target, timer);
        Ok(())
    }
}
