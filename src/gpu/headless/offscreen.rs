//! Offscreen frames: the target a frame is drawn into (any method, either world, tiled when it
//! is larger than the device allows), read back as sRGB bytes.

use super::*;

/// Bakes everything `terrain` owes for `view` and waits for nothing: its textures and every
/// level of its mesh the view needs, whatever the per-frame budget (a still frame is drawn
/// whole, as the endless world's are). `timer` times the first pass.
pub fn bake_whole(
    gpu: &Gpu,
    terrain: &mut Terrain,
    view: &View,
    timer: Option<&GpuTimer>,
) -> Result<()> {
    let budget = terrain.bake_budget();
    terrain.set_bake_budget(u64::MAX);
    let baked = bake_in_passes(gpu, timer, |encoder, timer| {
        terrain.encode_bake_timed(&gpu.device, &gpu.queue, encoder, view, timer)?;
        Ok(terrain.pending_texels())
    });
    terrain.set_bake_budget(budget);
    baked
}

/// Runs `step` (which records a bake and says how many texels still wait) in passes until
/// nothing waits: more than one pass only where more strips wait than one pass's uniform slots
/// hold; each is submitted on its own, as the passes share those slots. `timer` times the first.
pub(super) fn bake_in_passes(
    gpu: &Gpu,
    timer: Option<&GpuTimer>,
    mut step: impl FnMut(&mut wgpu::CommandEncoder, Option<&GpuTimer>) -> Result<u64>,
) -> Result<()> {
    // Each pass bakes at most as many rectangles as one pass's slots hold: a few passes for
    // the heights, then the light, level by level, coarsest first.
    for pass in 0..4 * crate::clipmap::MAX_LEVELS {
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        let waiting = step(&mut encoder, timer.filter(|_| pass == 0));
        gpu.queue.submit([encoder.finish()]);
        if waiting? == 0 {
            break;
        }
    }
    Ok(())
}

pub use crate::gpu::{render_samples, RENDER_SAMPLES};

/// Largest image side `relief render` accepts.
pub const MAX_IMAGE: u32 = 16384;
/// Largest tile [`render_image`] draws at once: bigger images are drawn in tiles, so their
/// size is bounded by host memory, not by the device's texture limit or GPU memory.
pub const TILE: u32 = 4096;

/// Draws `terrain` seen through `view` into a `width` x `height` sRGB RGBA8 image, through
/// the same [`Terrain`] calls as the window, in tiles of at most `tile` pixels per side (each
/// tile is the full view's frustum cropped to its pixels, so tiles join without a seam).
/// With `timer`, returns the bake's timings and the draw's passes summed over the tiles.
pub fn render_image(
    gpu: &Gpu,
    terrain: &mut Terrain,
    view: &View,
    size: (u32, u32),
    tile: u32,
    timer: Option<&GpuTimer>,
) -> Result<(Vec<u8>, Option<Timings>)> {
    let samples = terrain.targets().sample_count;
    tiled(gpu, size, tile, samples, |target, crop| {
        let tile_view = View {
            view_proj: crop * view.view_proj,
            ..*view
        };
        target.render(gpu, terrain, &tile_view, timer)
    })
}

/// [`render_image`] for the endless world (each tile culls its own patches).
pub fn render_world_image(
    gpu: &Gpu,
    world: &mut World,
    view: &WorldView,
    size: (u32, u32),
    tile: u32,
    timer: Option<&GpuTimer>,
) -> Result<(Vec<u8>, Option<Timings>)> {
    render_world_frames(gpu, world, view, (size, 1), tile, timer)
}

/// [`render_world_image`] after `frames` frames of the still `view` (each tile's, for an
/// image drawn in tiles), accumulated by the world's temporal service
/// ([`World::set_temporal`]; with it off the frames are alike and the last is the image).
/// A new history starts with the first of them; `timer` times the last.
pub fn render_world_frames(
    gpu: &Gpu,
    world: &mut World,
    view: &WorldView,
    (size, frames): ((u32, u32), u32),
    tile: u32,
    timer: Option<&GpuTimer>,
) -> Result<(Vec<u8>, Option<Timings>)> {
    let samples = world.targets().sample_count;
    tiled(gpu, size, tile, samples, |target, crop| {
        let tile_view = WorldView {
            crop: crop * view.crop,
            ..*view
        };
        if frames > 1 {
            target.accumulate_world(gpu, world, &tile_view, frames - 1)?;
        } else if world.temporal().on() {
            // One frame: the history's first.
            world.cut();
        }
        target.render_world(gpu, world, &tile_view, timer)
    })
}

/// Draws a `width` x `height` image in tiles of at most `tile` pixels a side: `draw(target,
/// crop)` draws the tile whose clip-space crop is `crop` into `target`.
pub(super) fn tiled(
    gpu: &Gpu,
    (width, height): (u32, u32),
    tile: u32,
    samples: u32,
    mut draw: impl FnMut(&Offscreen, glam::Mat4) -> Result<(Vec<u8>, Option<Timings>)>,
) -> Result<(Vec<u8>, Option<Timings>)> {
    for (name, v) in [("width", width), ("height", height)] {
        if !(1..=MAX_IMAGE).contains(&v) {
            return Err(Error::invalid(name, v, format!("1..={MAX_IMAGE}")));
        }
    }
    let tile = tile.clamp(1, gpu.device.limits().max_texture_dimension_2d);
    if width <= tile && height <= tile {
        let target = Offscreen::new(&gpu.device, width, height, samples)?;
        return draw(&target, glam::Mat4::IDENTITY);
    }
    let (tw, th) = (width.min(tile), height.min(tile));
    let target = Offscreen::new(&gpu.device, tw, th, samples)?;
    let mut image = vec![0u8; width as usize * height as usize * 4];
    let mut total: Option<Timings> = None;
    for y0 in (0..height).step_by(th as usize) {
        for x0 in (0..width).step_by(tw as usize) {
            let crop = crop_matrix((width, height), (x0, y0), (tw, th));
            let (pixels, t) = draw(&target, crop)?;
            match (&mut total, t) {
                (None, t) => total = t,
                (Some(sum), Some(t)) => {
                    // Each tile draws again: its draw's passes add up (the bake ran once).
                    for s in [
                        Slot::Render,
                        Slot::Present,
                        Slot::Raster,
                        Slot::Shade,
                        Slot::Resolve,
                    ] {
                        let i = s as usize;
                        if t[i].is_some() {
                            sum[i] = Some(sum[i].unwrap_or(0.0) + t[i].unwrap_or(0.0));
                        }
                    }
                }
                (Some(_), None) => {}
            }
            let (cw, ch) = (
                (width - x0).min(tw) as usize,
                (height - y0).min(th) as usize,
            );
            for row in 0..ch {
                let src = row * tw as usize * 4;
                let dst = ((y0 as usize + row) * width as usize + x0 as usize) * 4;
                image[dst..dst + cw * 4].copy_from_slice(&pixels[src..src + cw * 4]);
            }
        }
    }
    Ok((image, total))
}

/// The clip-space transform that makes the `size` pixels at `origin` of a `full` image fill the
/// viewport: drawing with `crop * view_proj` into a target of `size` draws exactly those pixels.
pub(crate) fn crop_matrix(full: (u32, u32), origin: (u32, u32), size: (u32, u32)) -> glam::Mat4 {
    let (w, h) = (f64::from(full.0), f64::from(full.1));
    let (x0, y0) = (f64::from(origin.0), f64::from(origin.1));
    let (tw, th) = (f64::from(size.0), f64::from(size.1));
    // NDC x of the tile's left and right edges, y of its top and bottom (y up in NDC).
    let (l, r) = (2.0 * x0 / w - 1.0, 2.0 * (x0 + tw) / w - 1.0);
    let (t, b) = (1.0 - 2.0 * y0 / h, 1.0 - 2.0 * (y0 + th) / h);
    let (sx, sy) = (2.0 / (r - l), 2.0 / (t - b));
    let (ox, oy) = (-(r + l) / (r - l), -(t + b) / (t - b));
    glam::DMat4::from_cols(
        glam::DVec4::new(sx, 0.0, 0.0, 0.0),
        glam::DVec4::new(0.0, sy, 0.0, 0.0),
        glam::DVec4::new(0.0, 0.0, 1.0, 0.0),
        glam::DVec4::new(ox, oy, 0.0, 1.0),
    )
    .as_mat4()
}

/// An offscreen colour (+ depth, + MSAA) target that [`Terrain`] draws into exactly as it
/// draws into a window's surface.
pub struct Offscreen {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// The resolved colour texture ([`Offscreen::IMAGE_FORMAT`], `Rgba8Unorm`: a frame shaded
    /// in compute is stored straight in; render passes draw through [`Offscreen::color_view`]).
    pub color: wgpu::Texture,
    msaa: Option<wgpu::TextureView>,
    depth: wgpu::TextureView,
    depth_texture: wgpu::Texture,
    targets: Targets,
    /// Whether a method may write its frame straight in ([`Offscreen::draw`]).
    present: bool,
    /// Whether the last frame was written straight in: its depth was not drawn.
    presented: std::cell::Cell<bool>,
}

/// What draws a frame into a target: in a render pass ([`Drawn::render`]), or where its method
/// allows without one ([`Drawn::present`]). The tile's [`Terrain`], the endless [`World`] and
/// the seed blog's pipeline.
pub trait Drawn {
    /// Writes the frame straight into `target`; false where it cannot ([`World::present`]),
    /// as by default: only a frame shaded in compute can be.
    fn present(
        &self,
        _encoder: &mut wgpu::CommandEncoder,
        _target: &wgpu::Texture,
        _timer: Option<&GpuTimer>,
    ) -> bool {
        false
    }
    /// Draws the frame into the host's render pass.
    fn render(&self, pass: &mut wgpu::RenderPass<'_>);
}

/// The tile's terrain and the endless world answer both calls themselves.
macro_rules! drawn_by_their_own_calls {
    ($($drawn:ty),*) => {$(
        impl Drawn for $drawn {
            fn present(
                &self,
                encoder: &mut wgpu::CommandEncoder,
                target: &wgpu::Texture,
                timer: Option<&GpuTimer>,
            ) -> bool {
                <$drawn>::present(self, encoder, target, timer)
            }
            fn render(&self, pass: &mut wgpu::RenderPass<'_>) {
                <$drawn>::render(self, pass);
            }
        }
    )*};
}

drawn_by_their_own_calls!(Terrain, World);

impl Drawn for Blog {
    fn render(&self, pass: &mut wgpu::RenderPass<'_>) {
        Blog::render(self, pass);
    }
}

impl Offscreen {
    /// Colour format of offscreen images as their render passes draw them (a view of the
    /// image, which is [`Offscreen::IMAGE_FORMAT`]).
    pub const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
    /// Format of the offscreen colour image itself: the same bytes as [`Offscreen::COLOR_FORMAT`]
    /// without the sRGB view, so that a frame shaded in compute can be stored straight in
    /// ([`World::present`]); render passes draw through an sRGB view of it.
    pub const IMAGE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;
    /// Depth format of offscreen images.
    pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

    /// The targets an offscreen image with `sample_count` samples needs.
    pub fn targets(sample_count: u32) -> Targets {
        Targets {
            color_format: Self::COLOR_FORMAT,
            depth_format: Some(Self::DEPTH_FORMAT),
            sample_count,
        }
    }

    /// Creates the textures; sizes are checked against the device's limits.
    pub fn new(device: &wgpu::Device, width: u32, height: u32, sample_count: u32) -> Result<Self> {
        let max = device.limits().max_texture_dimension_2d;
        for (name, v) in [("width", width), ("height", height)] {
            if v == 0 || v > max {
                return Err(Error::invalid(name, v, format!("1..={max} on this device")));
            }
        }
        let targets = Self::targets(sample_count);
        let size = wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        };
        let make = |label, format, samples, usage, view_formats: &[wgpu::TextureFormat]| {
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size,
                mip_level_count: 1,
                sample_count: samples,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage,
                view_formats,
            })
        };
        // Resolved colour, MSAA colour (when multisampled) and depth, 4 bytes a sample.
        let s = u64::from(sample_count);
        let bytes_per_pixel = 4 * (1 + if s > 1 { s } else { 0 } + s);
        let mib = (u64::from(width) * u64::from(height) * bytes_per_pixel) >> 20;
        let too_big = |e: Error| {
            match e {
            Error::Gpu { .. } => Error::invalid(
                "width x height",
                format!("{width}x{height}"),
                format!("a size whose {sample_count}-sample targets (~{mib} MiB) fit this device's memory: {e}"),
            ),
            other => other,
        }
        };
        crate::gpu::scoped(device, || {
            let attach = wgpu::TextureUsages::RENDER_ATTACHMENT;
            let color = make(
                "relief:offscreen:color",
                Self::IMAGE_FORMAT,
                1,
                attach
                    | wgpu::TextureUsages::COPY_SRC
                    | wgpu::TextureUsages::COPY_DST
                    | wgpu::TextureUsages::STORAGE_BINDING,
                &[Self::COLOR_FORMAT],
            );
            let msaa = (sample_count > 1).then(|| {
                make(
                    "relief:offscreen:msaa",
                    Self::COLOR_FORMAT,
                    sample_count,
                    attach,
                    &[],
                )
                .create_view(&Default::default())
            });
            // Single-sampled depth can be read back (see `Offscreen::read_depth`).
            let depth_usage = if sample_count == 1 {
                attach | wgpu::TextureUsages::COPY_SRC
            } else {
                attach
            };
            let depth_texture = make(
                "relief:offscreen:depth",
                Self::DEPTH_FORMAT,
                sample_count,
                depth_usage,
                &[],
            );
            Self {
                width,
                height,
                color,
                msaa,
                depth: depth_texture.create_view(&Default::default()),
                depth_texture,
                targets,
                present: true,
                presented: std::cell::Cell::new(false),
            }
        })
        .map_err(too_big)
    }

    /// Draws `drawn`'s frame into this target: written straight in, with no render pass, where
    /// its method can ([`World::present`]) and the target does not keep its depth
    /// ([`Offscreen::keeping_depth`]); otherwise in a render pass cleared to `clear`. Timed
    /// into `timer` as [`Slot::Present`] or [`Slot::Render`].
    pub fn draw(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        drawn: &impl Drawn,
        clear: wgpu::Color,
        timer: Option<&GpuTimer>,
    ) {
        let presented = self.present && drawn.present(encoder, &self.color, timer);
        self.presented.set(presented);
        if presented {
            return;
        }
        let color = self.color_view();
        let writes = timer.map(|t| t.render_writes(Slot::Render));
        let mut pass = self.begin_pass(encoder, &color, clear, writes);
        drawn.render(&mut pass);
    }

    /// The colour image as render passes draw into it ([`Offscreen::COLOR_FORMAT`]).
    pub fn color_view(&self) -> wgpu::TextureView {
        self.color.create_view(&wgpu::TextureViewDescriptor {
            format: Some(Self::COLOR_FORMAT),
            // An sRGB view cannot be bound for storage, as the image itself is.
            usage: Some(wgpu::TextureUsages::RENDER_ATTACHMENT),
            ..Default::default()
        })
    }

    /// This target with every frame drawn in a render pass, so that its depth holds what was
    /// drawn ([`Offscreen::read_depth`]): no method writes its frame straight in.
    pub fn keeping_depth(self) -> Self {
        Self {
            present: false,
            ..self
        }
    }

    /// Begins a render pass on this target, cleared to `clear` (linear RGB).
    pub fn begin_pass<'e>(
        &'e self,
        encoder: &'e mut wgpu::CommandEncoder,
        color_view: &'e wgpu::TextureView,
        clear: wgpu::Color,
        timestamps: Option<wgpu::RenderPassTimestampWrites<'e>>,
    ) -> wgpu::RenderPass<'e> {
        let (view, resolve_target) = match &self.msaa {
            Some(msaa) => (msaa, Some(color_view)),
            None => (color_view, None),
        };
        encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("relief:offscreen:pass"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view,
                depth_slice: None,
                resolve_target,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(clear),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &self.depth,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: if self.msaa.is_none() {
                        wgpu::StoreOp::Store
                    } else {
                        wgpu::StoreOp::Discard
                    },
                }),
                stencil_ops: None,
            }),
            timestamp_writes: timestamps,
            occlusion_query_set: None,
            multiview_mask: None,
        })
    }

    /// Bakes what is pending, draws one frame of `terrain` seen through `view`, and returns
    /// the image as tightly packed sRGB RGBA8, with GPU timings when `timer` is given.
    pub fn render(
        &self,
        gpu: &Gpu,
        terrain: &mut Terrain,
        view: &View,
        timer: Option<&GpuTimer>,
    ) -> Result<(Vec<u8>, Option<Timings>)> {
        self.check_targets(terrain.targets())?;
        let clear = crate::gpu::clear_color(terrain.shading().sky_color, Self::COLOR_FORMAT);
        terrain.set_viewport((self.width, self.height));
        bake_whole(gpu, terrain, view, timer)?;
        let terrain = std::cell::RefCell::new(terrain);
        self.frame(
            gpu,
            timer,
            |encoder| {
                let mut t = terrain.borrow_mut();
                t.prepare_timed(&gpu.device, &gpu.queue, encoder, view, timer)?;
                Ok(())
            },
            |encoder| self.draw(encoder, &**terrain.borrow(), clear, timer),
        )
    }

    /// [`Offscreen::render`] for the endless world: moves its levels to `view`, bakes all they
    /// uncovered (a still frame is drawn whole, whatever the bake budget), selects and draws
    /// the visible patches.
    pub fn render_world(
        &self,
        gpu: &Gpu,
        world: &mut World,
        view: &WorldView,
        timer: Option<&GpuTimer>,
    ) -> Result<(Vec<u8>, Option<Timings>)> {
        self.world_frame(gpu, world, view, timer, true)
    }

    /// One frame of the endless world as a window draws it: the bake within the world's
    /// per-frame budget ([`World::set_bake_budget`]), levels still waiting on it not drawn.
    pub fn render_world_budgeted(
        &self,
        gpu: &Gpu,
        world: &mut World,
        view: &WorldView,
    ) -> Result<(Vec<u8>, Option<Timings>)> {
        self.world_frame(gpu, world, view, None, false)
    }

    /// Bakes everything `view` needs, then starts a new history ([`World::cut`]) and
    /// draws `frames` frames of `view` into it, reading nothing back: what a still image
    /// accumulated over frames draws before its last.
    pub fn accumulate_world(
        &self,
        gpu: &Gpu,
        world: &mut World,
        view: &WorldView,
        frames: u32,
    ) -> Result<()> {
        self.bake_world_for(gpu, world, view)?;
        world.cut();
        self.advance_world(gpu, world, view, frames)
    }

    /// Checks `world` draws into this target's formats, sizes its images to this target, and
    /// bakes and lights everything `view` needs.
    fn bake_world_for(&self, gpu: &Gpu, world: &mut World, view: &WorldView) -> Result<()> {
        self.check_targets(world.targets())?;
        world.set_target_size(Some((self.width, self.height)));
        bake_world_whole(gpu, world, view, None)
    }

    /// One frame of `view` drawn whole (everything it uncovered baked and lit first) into the
    /// world's history after what it holds, read nothing back: a frame of a moving camera
    /// that is not looked at.
    pub fn accumulate_frame(&self, gpu: &Gpu, world: &mut World, view: &WorldView) -> Result<()> {
        self.bake_world_for(gpu, world, view)?;
        self.advance_world(gpu, world, view, 1)
    }

    /// Draws `frames` frames of `view` into the world's history (after what it holds), reading
    /// nothing back.
    pub fn advance_world(
        &self,
        gpu: &Gpu,
        world: &mut World,
        view: &WorldView,
        frames: u32,
    ) -> Result<()> {
        for _ in 0..frames {
            crate::gpu::scoped(&gpu.device, || -> Result<()> {
                let mut encoder =
                    gpu.device
                        .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                            label: Some("relief:offscreen:accumulate"),
                        });
                world.prepare(&gpu.device, &gpu.queue, &mut encoder, view)?;
                gpu.queue.submit([encoder.finish()]);
                Ok(())
            })??;
        }
        Ok(())
    }

    fn world_frame(
        &self,
        gpu: &Gpu,
        world: &mut World,
        view: &WorldView,
        timer: Option<&GpuTimer>,
        whole: bool,
    ) -> Result<(Vec<u8>, Option<Timings>)> {
        self.check_targets(world.targets())?;
        let clear = crate::gpu::clear_color(world.shading().sky_color, Self::COLOR_FORMAT);
        // A tile of a larger image is drawn through the view's crop into this target.
        world.set_target_size(Some((self.width, self.height)));
        if whole {
            bake_world_whole(gpu, world, view, timer)?;
        }
        let world = std::cell::RefCell::new(world);
        self.frame(
            gpu,
            timer,
            |encoder| {
                let mut w = world.borrow_mut();
                w.prepare_timed(&gpu.device, &gpu.queue, encoder, view, timer)?;
                Ok(())
            },
            |encoder| self.draw(encoder, &**world.borrow(), clear, timer),
        )
    }

    fn check_targets(&self, targets: &Targets) -> Result<()> {
        if targets != &self.targets {
            return Err(Error::invalid(
                "targets",
                format!("{targets:?}"),
                format!("{:?} (the offscreen target's)", self.targets),
            ));
        }
        Ok(())
    }

    /// One frame: `record` records the compute work and writes uniforms, `draw` draws the
    /// frame into this target ([`Offscreen::draw`]); the colour is read back as tightly packed
    /// RGBA8.
    fn frame(
        &self,
        gpu: &Gpu,
        timer: Option<&GpuTimer>,
        record: impl FnOnce(&mut wgpu::CommandEncoder) -> Result<()>,
        draw: impl FnOnce(&mut wgpu::CommandEncoder),
    ) -> Result<(Vec<u8>, Option<Timings>)> {
        let device = &gpu.device;
        let buffer_pitch = crate::gpu::scoped(device, || -> Result<_> {
            let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("relief:offscreen:frame"),
            });
            record(&mut encoder)?;
            draw(&mut encoder);
            let copy = encode_texture_copy(device, &mut encoder, &self.color);
            if let Some(t) = timer {
                t.resolve(&mut encoder);
            }
            gpu.queue.submit([encoder.finish()]);
            Ok(copy)
        })??;
        let (buffer, pitch) = buffer_pitch;
        let bytes = map_read(device, &buffer)?;
        let timings = timer.map(|t| t.read(device)).transpose()?;
        Ok((unpad(&bytes, pitch, &self.color), timings))
    }
}

impl Offscreen {
    /// One frame of `blog` seen through `view`: its bake and normal passes (as the blog runs
    /// them every frame) and its draw, with the light and sky of `shading`. Returns the image as
    /// [`Offscreen::render`] does.
    pub fn render_blog(
        &self,
        gpu: &Gpu,
        blog: &Blog,
        (params, shading): (&crate::TerrainParams, &crate::Shading),
        view: &View,
        timer: Option<&GpuTimer>,
    ) -> Result<(Vec<u8>, Option<Timings>)> {
        self.check_targets(blog.targets())?;
        let clear = crate::gpu::clear_color(shading.sky_color, Self::COLOR_FORMAT);
        self.frame(
            gpu,
            timer,
            |encoder| {
                blog.prepare(&gpu.queue, params, shading, view, 0.0);
                blog.encode_bake(encoder, timer);
                Ok(())
            },
            |encoder| self.draw(encoder, blog, clear, timer),
        )
    }
}

/// What [`render_blog`] draws.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BlogImage {
    /// The blog's pipeline, single-sampled as the blog draws.
    Pipeline,
    /// Its exact surface on a `grid`-vertex grid, `supersample` x `supersample` per pixel (where
    /// the device allows).
    Exact {
        /// Vertices along each side of the grid.
        grid: u32,
        /// Samples along each side of a pixel.
        supersample: u32,
    },
}

/// Draws the seed blog's terrain (the method `blog`, [`Blog`]) into a `size` image, sRGB RGBA8,
/// with the GPU time of its passes when `timer` is given.
pub fn render_blog(
    gpu: &Gpu,
    scene: (&crate::TerrainParams, &crate::Shading),
    view: &View,
    (width, height): (u32, u32),
    what: BlogImage,
    timer: Option<&GpuTimer>,
) -> Result<(Vec<u8>, Option<Timings>)> {
    let targets = Offscreen::targets(1);
    let (blog, ss) = match what {
        BlogImage::Pipeline => (Blog::new(&gpu.device, targets)?, 1),
        BlogImage::Exact { grid, supersample } => {
            let max = gpu.device.limits().max_texture_dimension_2d;
            let ss = supersample.max(1);
            let ss = if width * ss <= max && height * ss <= max {
                ss
            } else {
                1
            };
            (Blog::exact(&gpu.device, targets, grid)?, ss)
        }
    };
    let target = Offscreen::new(&gpu.device, width * ss, height * ss, 1)?;
    let (rgba, timings) = target.render_blog(gpu, &blog, scene, view, timer)?;
    let rgba = if ss > 1 {
        downsample_srgb(&rgba, width * ss, height * ss, ss)
    } else {
        rgba
    };
    Ok((rgba, timings))
}

impl Offscreen {
    /// The depth buffer of the last frame (single-sampled targets only), row-major: what it
    /// drew in a render pass (see [`Offscreen::keeping_depth`]).
    pub fn read_depth(&self, gpu: &Gpu) -> Result<Vec<f32>> {
        if self.msaa.is_some() {
            return Err(Error::invalid(
                "sample_count",
                self.targets.sample_count,
                "1 to read depth back",
            ));
        }
        if self.presented.get() {
            return Err(Error::Usage(
                "the last frame was written without a render pass and drew no depth: read depth from a target made with Offscreen::keeping_depth".into(),
            ));
        }
        let bytes = read_texture(&gpu.device, &gpu.queue, &self.depth_texture)?;
        Ok(bytemuck::pod_collect_to_vec(&bytes))
    }
}

/// A still frame is drawn whole: everything `view` uncovered is baked and lit first.
pub(super) fn bake_world_whole(
    gpu: &Gpu,
    world: &mut World,
    view: &WorldView,
    timer: Option<&GpuTimer>,
) -> Result<()> {
    let budgets = (world.bake_budget(), world.light_budget());
    world.set_bake_budget(u64::MAX);
    world.set_light_budget(u64::MAX);
    let baked = bake_in_passes(gpu, timer, |encoder, timer| {
        world.encode_bake_timed(&gpu.device, &gpu.queue, encoder, view, timer)?;
        Ok(world.pending_texels())
    });
    world.set_bake_budget(budgets.0);
    world.set_light_budget(budgets.1);
    baked
}
