//! Blocking conveniences on top of the core (native only): a device without a window, an
//! offscreen target drawn through the same [`Terrain`] calls as the window, and readback.

use super::blog::Blog;
use super::raymarch::{RayMarcher, RayScene};
use super::timing::{GpuTimer, Slot, Timings};
use super::world::{World, WorldView};
use super::{Targets, Terrain};
use crate::camera::View;
use crate::choice::{draw_ms, Candidate, Choice};
use crate::error::{Error, Result};

/// An adapter, device and queue made without any window.
pub struct Gpu {
    /// The adapter chosen.
    pub adapter: wgpu::Adapter,
    /// The device (with `TIMESTAMP_QUERY` when the adapter has it).
    pub device: wgpu::Device,
    /// Its queue.
    pub queue: wgpu::Queue,
}

impl Gpu {
    /// Picks the high-performance adapter (backends from `WGPU_BACKEND` if set) and creates a
    /// device with the adapter's own limits. Fails with [`Error::NoAdapter`] if there is none.
    pub fn new() -> Result<Self> {
        Self::with_features(wgpu::Features::TIMESTAMP_QUERY | super::raster::ID_FEATURES)
    }

    /// As [`Gpu::new`], asking for only those of `wanted` the adapter has (the tests draw
    /// without the compute raster's 64-bit atomics this way).
    pub fn with_features(wanted: wgpu::Features) -> Result<Self> {
        let instance =
            wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
        let adapter =
            pollster::block_on(
                instance.request_adapter(&wgpu::RequestAdapterOptions {
                    power_preference: wgpu::PowerPreference::from_env()
                        .unwrap_or(wgpu::PowerPreference::HighPerformance),
                    force_fallback_adapter: false,
                    compatible_surface: None,
                    apply_limit_buckets: false,
                }),
            )
            .map_err(|e| Error::NoAdapter(e.to_string()))?;
        let (device, queue) = pollster::block_on(super::request_device_with(&adapter, wanted))?;
        Ok(Self {
            adapter,
            device,
            queue,
        })
    }

    /// "name (backend)" of the adapter, for logs and reports.
    pub fn describe(&self) -> String {
        super::describe_adapter(&self.adapter.get_info())
    }
}

pub use super::map_read;

/// Records a copy of a whole 2-D texture into a new `MAP_READ` buffer; returns the buffer and
/// its padded row pitch in bytes. The texture must fit one buffer (see [`read_texture_bands`]
/// for any size).
pub fn encode_texture_copy(
    device: &wgpu::Device,
    encoder: &mut wgpu::CommandEncoder,
    texture: &wgpu::Texture,
) -> (wgpu::Buffer, u32) {
    encode_rows_copy(
        device,
        encoder,
        texture,
        wgpu::TextureAspect::All,
        0,
        0..texture.height(),
    )
}

fn row_pitch(texture: &wgpu::Texture, aspect: wgpu::TextureAspect) -> u32 {
    let bpp = texture
        .format()
        .block_copy_size(Some(aspect))
        .expect("copyable formats have a block size");
    (texture.width() * bpp).next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT)
}

/// Records a copy of rows `rows` of one aspect of one layer of a 2-D texture (array) into a
/// new `MAP_READ` buffer.
fn encode_rows_copy(
    device: &wgpu::Device,
    encoder: &mut wgpu::CommandEncoder,
    texture: &wgpu::Texture,
    aspect: wgpu::TextureAspect,
    layer: u32,
    rows: std::ops::Range<u32>,
) -> (wgpu::Buffer, u32) {
    let pitch = row_pitch(texture, aspect);
    let n = rows.end - rows.start;
    let buffer = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("relief:readback"),
        size: u64::from(pitch) * u64::from(n),
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    encoder.copy_texture_to_buffer(
        wgpu::TexelCopyTextureInfo {
            aspect,
            origin: wgpu::Origin3d {
                x: 0,
                y: rows.start,
                z: layer,
            },
            ..texture.as_image_copy()
        },
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(pitch),
                rows_per_image: Some(n),
            },
        },
        wgpu::Extent3d {
            width: texture.width(),
            height: n,
            depth_or_array_layers: 1,
        },
    );
    (buffer, pitch)
}

/// Largest readback buffer relief asks for: well under every device's `max_buffer_size`, and
/// small enough that reading a 16384² texture never holds more than this twice.
pub const MAX_READBACK_BYTES: u64 = 64 << 20;

/// Reads a 2-D texture back in bands of whole rows, each band at most `band_bytes` (and the
/// device's buffer limit), calling `sink(first_row, rows)` with the rows tightly packed.
/// Textures of any size the device can hold are read this way without one huge buffer. The
/// layers of an array texture follow each other (layer `k`'s row `y` is row `k * height + y`).
pub fn read_texture_bands(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    texture: &wgpu::Texture,
    band_bytes: u64,
    mut sink: impl FnMut(u32, &[u8]),
) -> Result<()> {
    let aspect = if texture.format().is_depth_stencil_format() {
        wgpu::TextureAspect::DepthOnly
    } else {
        wgpu::TextureAspect::All
    };
    let pitch = u64::from(row_pitch(texture, aspect));
    let limit = band_bytes.min(device.limits().max_buffer_size).max(pitch);
    let band = u32::try_from(limit / pitch).unwrap_or(u32::MAX).max(1);
    let row =
        (texture.width() * texture.format().block_copy_size(Some(aspect)).unwrap_or(4)) as usize;
    for layer in 0..texture.depth_or_array_layers() {
        let mut y = 0;
        while y < texture.height() {
            let rows = y..(y + band).min(texture.height());
            let (buffer, pitch) = super::scoped(device, || {
                let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                    label: Some("relief:readback"),
                });
                let copy =
                    encode_rows_copy(device, &mut encoder, texture, aspect, layer, rows.clone());
                queue.submit([encoder.finish()]);
                copy
            })?;
            let bytes = map_read(device, &buffer)?;
            let packed: Vec<u8> = bytes
                .chunks(pitch as usize)
                .take((rows.end - rows.start) as usize)
                .flat_map(|r| &r[..row])
                .copied()
                .collect();
            sink(layer * texture.height() + rows.start, &packed);
            y = rows.end;
        }
    }
    Ok(())
}

/// Reads a whole 2-D texture back, rows tightly packed (in bands; see [`read_texture_bands`]).
pub fn read_texture(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    texture: &wgpu::Texture,
) -> Result<Vec<u8>> {
    let mut out = Vec::new();
    read_texture_bands(device, queue, texture, MAX_READBACK_BYTES, |_, rows| {
        out.extend_from_slice(rows)
    })?;
    Ok(out)
}

fn unpad(bytes: &[u8], pitch: u32, texture: &wgpu::Texture) -> Vec<u8> {
    let row = (texture.width() * texture.format().block_copy_size(None).unwrap_or(4)) as usize;
    bytes
        .chunks(pitch as usize)
        .take(texture.height() as usize)
        .flat_map(|r| &r[..row])
        .copied()
        .collect()
}

/// The baked channels read back: heights and colour values, row-major, `size * size` each.
pub struct BakedTerrain {
    /// Texture side.
    pub size: u32,
    /// Normalised heights in [0, 1].
    pub heights: Vec<f32>,
    /// Colour channel in [0, 1].
    pub colors: Vec<f32>,
    /// Unit normals (x, y, z), y up.
    pub normals: Vec<[f32; 3]>,
}

/// Reads back everything [`Terrain`] baked (submit its bake first).
pub fn read_baked(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    terrain: &Terrain,
) -> Result<BakedTerrain> {
    let t = terrain.textures();
    // Copied into typed vectors: a Vec<u8> promises no alignment for casting in place.
    let rg: Vec<[f32; 2]> = bytemuck::pod_collect_to_vec(&read_texture(device, queue, &t.terrain)?);
    let halves: Vec<[u16; 4]> =
        bytemuck::pod_collect_to_vec(&read_texture(device, queue, &t.normals)?);
    Ok(BakedTerrain {
        size: terrain.params().size,
        heights: rg.iter().map(|v| v[0]).collect(),
        colors: rg.iter().map(|v| v[1]).collect(),
        normals: halves
            .iter()
            .map(|n| [0, 1, 2].map(|i| half::f16::from_bits(n[i]).to_f32()))
            .collect(),
    })
}

/// Bakes whatever is pending and waits for it.
pub fn bake_blocking(
    gpu: &Gpu,
    terrain: &mut Terrain,
    timer: Option<&GpuTimer>,
) -> Result<Option<Timings>> {
    super::scoped(&gpu.device, || {
        let mut encoder = gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("relief:headless:bake"),
            });
        terrain.encode_textures(&mut encoder, timer);
        if let Some(t) = timer {
            t.resolve(&mut encoder);
        }
        gpu.queue.submit([encoder.finish()]);
    })?;
    read_or_wait(gpu, timer)
}

/// Reads `timer`'s timings of the work submitted, or (without a timer) waits for that work.
fn read_or_wait(gpu: &Gpu, timer: Option<&GpuTimer>) -> Result<Option<Timings>> {
    match timer {
        Some(t) => t.read(&gpu.device).map(Some),
        None => {
            gpu.device
                .poll(wgpu::PollType::wait_indefinitely())
                .map_err(|e| Error::Readback(e.to_string()))?;
            Ok(None)
        }
    }
}

/// Times `run` (work it submits and waits for, timed by the timer it is given, if any) as a
/// benchmark, not one cold dispatch: an idle GPU lowers its clocks (a lone bake after a
/// read-back timed at up to twice its warm time on an H100), so `run` goes untimed for
/// [`BAKE_WARM_UP`] first, then [`BAKE_RUNS`] times timed. Returns each slot's median.
pub fn warm_median(
    timer: &GpuTimer,
    mut run: impl FnMut(Option<&GpuTimer>) -> Result<Option<Timings>>,
) -> Result<Timings> {
    let start = std::time::Instant::now();
    while start.elapsed() < BAKE_WARM_UP {
        run(None)?;
    }
    let mut runs = Vec::with_capacity(BAKE_RUNS);
    for _ in 0..BAKE_RUNS {
        runs.extend(run(Some(timer))?);
    }
    Ok(std::array::from_fn(|slot| {
        let mut ms: Vec<f64> = runs.iter().filter_map(|t| t[slot]).collect();
        ms.sort_by(f64::total_cmp);
        ms.get(ms.len() / 2).copied()
    }))
}

/// Runs `frame` (which records one frame into the encoder, timed by the timer it is given,
/// if any) back to back for the warm-up (at least `warmup.0` frames and `warmup.1`
/// milliseconds: an idle GPU lowers its clocks), then `frames` timed frames, each submitted
/// and waited for. Returns the GPU timings and the wall time of each timed frame.
pub fn measure_frames(
    gpu: &Gpu,
    (warmup, warmup_ms): (u32, f64),
    frames: u32,
    timer: Option<&GpuTimer>,
    mut frame: impl FnMut(&mut wgpu::CommandEncoder, Option<&GpuTimer>),
) -> Result<(Vec<Timings>, Vec<f64>)> {
    let wait = || {
        gpu.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map(|_| ())
            .map_err(|e| Error::Readback(e.to_string()))
    };
    let start = std::time::Instant::now();
    let mut n = 0;
    while n < warmup || start.elapsed().as_secs_f64() * 1e3 < warmup_ms {
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        frame(&mut encoder, None);
        gpu.queue.submit([encoder.finish()]);
        n += 1;
        if n % 16 == 0 {
            // Keep a bounded amount of work in flight.
            wait()?;
        }
    }
    wait()?;
    let (mut times, mut wall) = (Vec::new(), Vec::new());
    for _ in 0..frames {
        let start = std::time::Instant::now();
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        frame(&mut encoder, timer);
        if let Some(t) = timer {
            t.resolve(&mut encoder);
        }
        gpu.queue.submit([encoder.finish()]);
        wait()?;
        wall.push(start.elapsed().as_secs_f64() * 1e3);
        if let Some(t) = timer {
            times.push(t.read(&gpu.device)?);
        }
    }
    Ok((times, wall))
}

/// What [`choose_method`] draws: the tile (seen through a view) or the endless world (seen
/// through its view, whose size the frames are drawn at).
pub enum TrialScene<'a> {
    /// The tile, and the image size.
    Tile(&'a mut Terrain, &'a View, (u32, u32)),
    /// The endless world.
    Endless(&'a mut World, &'a WorldView),
}

impl TrialScene<'_> {
    /// Sets it to draw `c` as `relief render` does: into a target of [`render_samples`] (the
    /// host's 4x MSAA for the mesh, none for the methods that anti-alias on their own), at
    /// `c`'s samples a pixel.
    pub fn set(&mut self, device: &wgpu::Device, c: Candidate) -> Result<()> {
        let targets = Offscreen::targets(render_samples(c.method));
        match self {
            TrialScene::Tile(terrain, ..) => {
                terrain.set_targets(device, targets)?;
                terrain.set_method(device, c.config())
            }
            TrialScene::Endless(world, _) => {
                world.set_targets(device, targets)?;
                world.set_method(device, c.config())
            }
        }
    }
}

/// Untimed frames of each candidate before [`choose_method`] times it: at least this many
/// milliseconds (an H100 left idle while the next candidate is set up drops its clocks) ...
pub const TRIAL_WARM_UP_MS: f64 = 300.0;
/// ... and at least this many frames.
pub const TRIAL_WARM_UP: u32 = 2;
/// The trial measures no further candidate once this long has passed (the first is always
/// measured): on a software device a candidate can take tens of seconds.
pub const TRIAL_LIMIT: std::time::Duration = std::time::Duration::from_secs(10);

/// Timed frames of each candidate; their median decides.
pub const TRIAL_FRAMES: u32 = 5;

/// Chooses the method of the default ([`crate::choice`]) and leaves `scene` set to draw it
/// ([`TrialScene::set`]): draws [`TRIAL_FRAMES`] timed frames of each of the world's
/// [`Candidate`]s into an offscreen target of its own sample count, after a warm-up, and keeps
/// the fastest median draw. The trial bakes once for every candidate; then everything is
/// marked owed again, the viewport or target size put back, so the caller's next frame bakes
/// and draws as the chosen method pinned would (its timings and stats included). A size over
/// [`TILE`] a side is measured scaled down to fit it (a larger image is drawn in tiles of that
/// size). The mesh, said so, where the device has no timestamp queries. On an error the scene
/// is left set to one of the candidates.
pub fn choose_method(gpu: &Gpu, mut scene: TrialScene<'_>) -> Result<Choice> {
    let Some(timer) = GpuTimer::new(&gpu.device, &gpu.queue) else {
        let choice = Choice::unmeasured();
        scene.set(&gpu.device, choice.candidate)?;
        return Ok(choice);
    };
    let full = match &scene {
        TrialScene::Tile(.., size) => *size,
        TrialScene::Endless(_, view) => view.size,
    };
    let scale = (f64::from(TILE) / f64::from(full.0.max(full.1))).min(1.0);
    let size = (
        ((f64::from(full.0) * scale).round() as u32).max(1),
        ((f64::from(full.1) * scale).round() as u32).max(1),
    );
    let world = match scene {
        TrialScene::Tile(..) => crate::WorldKind::Tile,
        TrialScene::Endless(..) => crate::WorldKind::Endless,
    };
    let warm = (TRIAL_WARM_UP, TRIAL_WARM_UP_MS);
    let kept = match &scene {
        TrialScene::Tile(terrain, ..) => (Some(terrain.viewport()), None),
        TrialScene::Endless(world, _) => (None, world.target_size()),
    };
    let mut ms = Vec::new();
    let started = std::time::Instant::now();
    for &c in Candidate::all(world) {
        if started.elapsed() > TRIAL_LIMIT && !ms.is_empty() {
            // A slow device (a software one) would spend minutes on the rest: they stay
            // unmeasured, and the choice is among those measured.
            ms.push((c, f64::NAN));
            continue;
        }
        scene.set(&gpu.device, c)?;
        let samples = render_samples(c.method);
        let target = Offscreen::new(&gpu.device, size.0, size.1, samples)?;
        let mut failed = None;
        let (times, _) = match &mut scene {
            TrialScene::Tile(terrain, view, _) => {
                terrain.set_viewport(size);
                bake_whole(gpu, terrain, view, None)?;
                let sky = terrain.shading().sky_color;
                let clear = super::clear_color(sky, Offscreen::COLOR_FORMAT);
                measure_frames(gpu, warm, TRIAL_FRAMES, Some(&timer), |encoder, timer| {
                    let recorded =
                        terrain.prepare_timed(&gpu.device, &gpu.queue, encoder, view, timer);
                    if let Err(e) = recorded {
                        failed.get_or_insert(e);
                    }
                    target.draw(encoder, &**terrain, clear, timer);
                })?
            }
            TrialScene::Endless(world, view) => {
                let view = WorldView {
                    size,
                    crop: glam::Mat4::IDENTITY,
                    ..**view
                };
                world.set_target_size(None);
                let budgets = (world.bake_budget(), world.light_budget());
                let restore = |world: &mut World| {
                    world.set_bake_budget(budgets.0);
                    world.set_light_budget(budgets.1);
                };
                world.set_bake_budget(u64::MAX);
                world.set_light_budget(u64::MAX);
                let baked = bake_in_passes(gpu, None, |encoder, timer| {
                    world.encode_bake_timed(&gpu.device, &gpu.queue, encoder, &view, timer)?;
                    Ok(world.pending_texels())
                });
                if let Err(e) = baked {
                    restore(world);
                    return Err(e);
                }
                let sky = world.shading().sky_color;
                let clear = super::clear_color(sky, Offscreen::COLOR_FORMAT);
                let measured =
                    measure_frames(gpu, warm, TRIAL_FRAMES, Some(&timer), |encoder, timer| {
                        let recorded =
                            world.prepare_timed(&gpu.device, &gpu.queue, encoder, &view, timer);
                        if let Err(e) = recorded {
                            failed.get_or_insert(e);
                        }
                        target.draw(encoder, &**world, clear, timer);
                    });
                restore(world);
                measured?
            }
        };
        if let Some(e) = failed {
            return Err(e);
        }
        let mut draws: Vec<f64> = times.iter().filter_map(draw_ms).collect();
        draws.sort_by(f64::total_cmp);
        ms.push((c, draws.get(draws.len() / 2).copied().unwrap_or(f64::NAN)));
    }
    let choice = Choice::decide(ms, TRIAL_FRAMES as usize, size);
    scene.set(&gpu.device, choice.candidate)?;
    match scene {
        TrialScene::Tile(terrain, ..) => {
            terrain.set_viewport(kept.0.unwrap_or(size));
            terrain.invalidate();
        }
        TrialScene::Endless(world, _) => {
            world.set_target_size(kept.1);
            world.invalidate(&gpu.device)?;
        }
    }
    Ok(choice)
}

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
fn bake_in_passes(
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

pub use super::{render_samples, RENDER_SAMPLES};

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
    let samples = world.targets().sample_count;
    tiled(gpu, size, tile, samples, |target, crop| {
        let tile_view = WorldView {
            crop: crop * view.crop,
            ..*view
        };
        target.render_world(gpu, world, &tile_view, timer)
    })
}

/// Draws a `width` x `height` image in tiles of at most `tile` pixels a side: `draw(target,
/// crop)` draws the tile whose clip-space crop is `crop` into `target`.
fn tiled(
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
                    for s in [Slot::Render, Slot::Present, Slot::Raster, Slot::Shade] {
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
pub fn crop_matrix(full: (u32, u32), origin: (u32, u32), size: (u32, u32)) -> glam::Mat4 {
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
        super::scoped(device, || {
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
        let clear = super::clear_color(terrain.shading().sky_color, Self::COLOR_FORMAT);
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

    fn world_frame(
        &self,
        gpu: &Gpu,
        world: &mut World,
        view: &WorldView,
        timer: Option<&GpuTimer>,
        whole: bool,
    ) -> Result<(Vec<u8>, Option<Timings>)> {
        self.check_targets(world.targets())?;
        let clear = super::clear_color(world.shading().sky_color, Self::COLOR_FORMAT);
        // A tile of a larger image is drawn through the view's crop into this target.
        world.set_target_size(Some((self.width, self.height)));
        if whole {
            // A still frame is drawn whole: everything the view uncovered is baked and lit
            // first.
            let budgets = (world.bake_budget(), world.light_budget());
            world.set_bake_budget(u64::MAX);
            world.set_light_budget(u64::MAX);
            let baked = bake_in_passes(gpu, timer, |encoder, timer| {
                world.encode_bake_timed(&gpu.device, &gpu.queue, encoder, view, timer)?;
                Ok(world.pending_texels())
            });
            world.set_bake_budget(budgets.0);
            world.set_light_budget(budgets.1);
            baked?;
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
        let buffer_pitch = super::scoped(device, || -> Result<_> {
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
        let clear = super::clear_color(shading.sky_color, Self::COLOR_FORMAT);
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
    Exact { grid: u32, supersample: u32 },
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

pub use super::downsample_srgb;

/// How long [`warm_median`] runs the work untimed before it times it.
pub const BAKE_WARM_UP: std::time::Duration = std::time::Duration::from_millis(300);
/// How many timed runs [`warm_median`] takes the median of.
pub const BAKE_RUNS: usize = 9;

/// Bakes `size` x `size` samples of `land`, spaced `2^level_log2` metres, from world sample
/// `origin` (in that spacing) on, in bands of rows; `sink(first_row, texels)` receives each
/// band's (height, dh/dx, dh/dz, colour) texels, rows tightly packed. The grid keeps the octaves
/// whose cells span at least two samples (as a clipmap level does). Returns the GPU time of the
/// bake passes summed, when `timer` is given (each band's [`warm_median`]).
pub fn bake_region(
    gpu: &Gpu,
    land: &crate::landscape::Landscape,
    origin: [i32; 2],
    size: u32,
    level_log2: i32,
    timer: Option<&GpuTimer>,
    mut sink: impl FnMut(u32, &[[f32; 4]]),
) -> Result<Option<f64>> {
    use super::landscape::{LandscapeBake, Rect};
    let max = gpu.device.limits().max_texture_dimension_2d;
    if !(1..=max).contains(&size) {
        return Err(Error::invalid(
            "size",
            size,
            format!("1..={max} on this device"),
        ));
    }
    let row_bytes = u64::from(size) * 16;
    let band = (MAX_READBACK_BYTES / row_bytes).clamp(1, u64::from(size)) as u32;
    let pass = LandscapeBake::new(&gpu.device);
    let texture = super::scoped(&gpu.device, || {
        gpu.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("relief:bake-region:band"),
            size: wgpu::Extent3d {
                width: size,
                height: band,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: LandscapeBake::FORMAT,
            usage: wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        })
    })?;
    let view = texture.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        ..Default::default()
    });
    let target = pass.bind(&gpu.device, &view, size.max(band));
    let mut total: Option<f64> = None;
    let mut row = 0;
    while row < size {
        let rows = band.min(size - row);
        let rect = Rect {
            layer: 0,
            level_log2,
            origin: [origin[0], origin[1] + row as i32],
            extent: [size, rows],
        };
        let bake = |timer: Option<&GpuTimer>| {
            super::scoped(&gpu.device, || {
                let mut encoder = gpu.device.create_command_encoder(&Default::default());
                pass.encode_at_origin(
                    &gpu.queue,
                    &mut encoder,
                    &target,
                    land,
                    &rect,
                    timer.map(|t| t.compute_writes(Slot::Bake)),
                );
                if let Some(t) = timer {
                    t.resolve(&mut encoder);
                }
                gpu.queue.submit([encoder.finish()]);
            })
        };
        match timer {
            Some(t) => {
                let ms = warm_median(t, |timer| {
                    bake(timer)?;
                    read_or_wait(gpu, timer)
                })?[Slot::Bake as usize];
                if let Some(ms) = ms {
                    total = Some(total.unwrap_or(0.0) + ms);
                }
            }
            None => bake(None)?,
        }
        let bytes = read_texture(&gpu.device, &gpu.queue, &texture)?;
        let texels: Vec<[f32; 4]> = bytemuck::pod_collect_to_vec(&bytes);
        sink(row, &texels[..(rows * size) as usize]);
        row += rows;
    }
    Ok(total)
}

/// The screen-space geometric error of a drawn frame of the endless world, measured against the
/// continuous surface: each pixel's depth is turned back into the point drawn there, and its
/// vertical distance δ from the surface (the twin's `height_at`) at distance d counts as
/// `K·δ/d` pixels, the quantity [`crate::clipmap`]'s bound bounds.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ScreenError {
    /// Largest over the pixels measured, in pixels.
    pub max: f64,
    /// 99th percentile, pixels.
    pub p99: f64,
    /// Pixels measured (terrain pixels on the sampling grid).
    pub pixels: usize,
}

/// Draws `world` through `view` single-sampled (the world must target
/// `Offscreen::targets(1)`) and measures [`ScreenError`] at every `stride`-th pixel each way.
pub fn world_screen_error(
    gpu: &Gpu,
    world: &mut World,
    view: &WorldView,
    stride: u32,
) -> Result<ScreenError> {
    Ok(world_depth_metrics(gpu, world, view, stride)?.0)
}

/// [`world_screen_error`], and the distance from the eye of what every pixel shows (-1 for
/// sky): what the coverage against a ray cast compares.
pub fn world_depth_metrics(
    gpu: &Gpu,
    world: &mut World,
    view: &WorldView,
    stride: u32,
) -> Result<(ScreenError, Vec<f32>)> {
    let (w, h) = view.size;
    let target = Offscreen::new(&gpu.device, w, h, 1)?.keeping_depth();
    target.render_world(gpu, world, view, None)?;
    let depth = target.read_depth(gpu)?;
    let inverse = world.relative_matrix().inverse().as_dmat4();
    let k = view.pixels_per_radian();
    let mut errors = Vec::new();
    let stride = stride.max(1) as usize;
    let mut distance = vec![-1f32; depth.len()];
    for py in 0..h as usize {
        for px in 0..w as usize {
            let d = depth[py * w as usize + px];
            if d >= 1.0 {
                continue; // sky
            }
            let ndc = glam::DVec4::new(
                (px as f64 + 0.5) / f64::from(w) * 2.0 - 1.0,
                1.0 - (py as f64 + 0.5) / f64::from(h) * 2.0,
                f64::from(d),
                1.0,
            );
            let p = inverse * ndc;
            let rel = p.truncate() / p.w;
            distance[py * w as usize + px] = rel.length() as f32;
            if py % stride != 0 || px % stride != 0 {
                continue;
            }
            let at = view.eye + rel;
            let delta = (at.y - world.height_at(at.x, at.z)).abs();
            errors.push(k * delta / rel.length().max(1e-9));
        }
    }
    errors.sort_by(f64::total_cmp);
    let pick = |q: f64| {
        errors
            .get(((errors.len() as f64 * q) as usize).min(errors.len().saturating_sub(1)))
            .copied()
            .unwrap_or(0.0)
    };
    let error = ScreenError {
        max: errors.last().copied().unwrap_or(0.0),
        p99: pick(0.99),
        pixels: errors.len(),
    };
    Ok((error, distance))
}

/// What a ray-cast method drew: the image, and per pixel the distance of the pixel-centre ray.
#[derive(Clone, Debug, PartialEq)]
pub struct RayImage {
    /// sRGB RGBA8, supersampled where the method asks for it.
    pub rgba: Vec<u8>,
    /// Distance along the pixel-centre ray to the surface; -1 for sky, -2 where the ray ran
    /// out of steps (never counted as sky).
    pub distance: Vec<f32>,
    /// Rays (of every subsample) that ran out of steps.
    pub unresolved: usize,
    /// The cast's GPU time, when a timer was given.
    pub timings: Option<Timings>,
}

/// Draws one image with a ray-cast `method` (see [`crate::Method`]): its own colour and
/// distance targets, supersampled where the method asks for it (and the device allows),
/// averaged in linear light. Returns sRGB RGBA8, with the cast's GPU time when `timer` is given.
pub fn render_rays(
    gpu: &Gpu,
    params: &crate::TerrainParams,
    shading: &crate::Shading,
    view: &View,
    size: (u32, u32),
    method: crate::Method,
    timer: Option<&GpuTimer>,
) -> Result<(Vec<u8>, Option<Timings>)> {
    let Some(rays) = method.ray_method(params.octaves) else {
        return Err(Error::invalid("method", method, "a ray-cast method"));
    };
    let how = (method, method.supersample());
    let image = cast(gpu, size, how, RayScene::Tile, timer, |caster, _| {
        caster.prepare(&gpu.queue, params, shading, view, rays);
        Ok(())
    })?;
    Ok((image.rgba, image.timings))
}

/// [`render_rays`] for the endless world, bounded by the region the mesh draws at
/// `params.pixel_error` ([`super::world_rays::drawn_region`]).
pub fn render_world_rays(
    gpu: &Gpu,
    params: &crate::world::WorldParams,
    shading: &crate::Shading,
    view: &WorldView,
    method: crate::Method,
    timer: Option<&GpuTimer>,
) -> Result<RayImage> {
    let ss = method.supersample();
    render_world_rays_at(gpu, params, shading, view, method, ss, timer)
}

/// [`render_world_rays`] with `supersample` rays per pixel each way (what checks that the
/// reference's 3x3 has converged).
pub fn render_world_rays_at(
    gpu: &Gpu,
    params: &crate::world::WorldParams,
    shading: &crate::Shading,
    view: &WorldView,
    method: crate::Method,
    supersample: u32,
    timer: Option<&GpuTimer>,
) -> Result<RayImage> {
    let Some(rays) = method.ray_method(params.land.octaves) else {
        return Err(Error::invalid("method", method, "a ray-cast method"));
    };
    let region = super::world_rays::drawn_region(params, view);
    cast(
        gpu,
        view.size,
        (method, supersample),
        RayScene::World,
        timer,
        |caster, size| {
            let ray = super::world_rays::WorldRayUniforms::new(params, view, rays, size, region)?;
            let render = super::world::render_uniforms(
                params,
                shading,
                (crate::gpu::world_rays::ray_matrix(view), region, view.eye),
                true,
            );
            caster.prepare_world(&gpu.queue, &render, &ray)
        },
    )
}

/// The terrain's horizon towards the sun (radians above the horizontal) at each point `(x, z)`
/// (world metres) of the endless world's continuous surface, as `method`'s rays shade it
/// (`wgsl/horizon_probe.wgsl`): the reference's conservative march, or the seed's shadow march
/// with `method`'s ray settings. The sun is `params.sky`'s; `view` places the casters' reference
/// sample and bounds the march by the region the mesh draws.
pub fn world_horizons(
    gpu: &Gpu,
    params: &crate::world::WorldParams,
    view: &WorldView,
    method: super::raymarch::RayMethod,
    points: &[[f64; 2]],
) -> Result<Vec<f32>> {
    use wgpu::util::DeviceExt as _;
    if points.is_empty() {
        return Ok(Vec::new());
    }
    let region = super::world_rays::drawn_region(params, view);
    let ray = super::world_rays::WorldRayUniforms::new(params, view, method, view.size, region)?;
    let render = super::world::render_uniforms(
        params,
        &crate::Shading::default(),
        (super::world_rays::ray_matrix(view), region, view.eye),
        true,
    );
    // Positions relative to the reference sample, as the casters' are.
    let s = 2f64.powi(ray.base_log2);
    let origin = [
        f64::from(ray.reference[0]) * s,
        f64::from(ray.reference[1]) * s,
    ];
    let relative: Vec<[f32; 2]> = points
        .iter()
        .map(|p| [(p[0] - origin[0]) as f32, (p[1] - origin[1]) as f32])
        .collect();
    let device = &gpu.device;
    let source = super::shader::source("horizon_probe");
    let init = |label: &str, contents: &[u8], usage| {
        device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents,
            usage,
        })
    };
    let render_buffer = init(
        "relief:horizon-probe:render",
        bytemuck::bytes_of(&render),
        wgpu::BufferUsages::UNIFORM,
    );
    let ray_buffer = init(
        "relief:horizon-probe:ray",
        bytemuck::bytes_of(&ray),
        wgpu::BufferUsages::UNIFORM,
    );
    let point_buffer = init(
        "relief:horizon-probe:points",
        bytemuck::cast_slice(&relative),
        wgpu::BufferUsages::STORAGE,
    );
    let bytes = (points.len() * 4) as u64;
    let out = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("relief:horizon-probe:horizons"),
        size: bytes,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let staging = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("relief:horizon-probe:staging"),
        size: bytes,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    super::scoped(device, || {
        let module = super::shader::module(device, "relief:horizon-probe", &source);
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("relief:horizon-probe"),
            layout: None,
            module: &module,
            entry_point: Some("horizon_cs"),
            compilation_options: Default::default(),
            cache: None,
        });
        let group = |index: u32, buffers: [&wgpu::Buffer; 2]| {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("relief:horizon-probe"),
                layout: &pipeline.get_bind_group_layout(index),
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: buffers[0].as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: buffers[1].as_entire_binding(),
                    },
                ],
            })
        };
        let uniforms = group(0, [&render_buffer, &ray_buffer]);
        let io = group(1, [&point_buffer, &out]);
        let mut encoder = device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_compute_pass(&Default::default());
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, &uniforms, &[]);
            pass.set_bind_group(1, &io, &[]);
            pass.dispatch_workgroups((points.len() as u32).div_ceil(64), 1, 1);
        }
        encoder.copy_buffer_to_buffer(&out, 0, &staging, 0, bytes);
        gpu.queue.submit([encoder.finish()]);
    })?;
    Ok(bytemuck::pod_collect_to_vec(&super::map_read(
        device, &staging,
    )?))
}

/// The light bake's horizon towards the sun (radians) at every `stride`-th texel each way of
/// each of `world`'s levels `levels`, as the mesh shades them: per level, (world x, z,
/// horizon), unpacked from the light texture's two 16-bit floats.
pub fn world_light_horizons(
    gpu: &Gpu,
    world: &super::world::World,
    levels: &[usize],
    stride: usize,
) -> Result<Vec<Vec<(f64, f64, f32)>>> {
    let packed: Vec<u32> = bytemuck::pod_collect_to_vec(&read_texture(
        &gpu.device,
        &gpu.queue,
        world.light_texture(),
    )?);
    let map = world.clipmap();
    let side = map.side() as i64;
    let cells = map.cells() as i64;
    let mut out = Vec::with_capacity(levels.len());
    for &l in levels {
        let Some(level) = map.levels.get(l) else {
            return Err(Error::invalid(
                "level",
                l,
                format!("0..{} (the clipmap's levels)", map.levels.len()),
            ));
        };
        let s = level.spacing();
        let mut texels = Vec::new();
        for j in (0..=cells).step_by(stride.max(1)) {
            for i in (0..=cells).step_by(stride.max(1)) {
                let (si, sj) = (
                    i64::from(level.origin[0]) + i,
                    i64::from(level.origin[1]) + j,
                );
                let t = (i64::from(level.layer) * side + sj.rem_euclid(side)) * side
                    + si.rem_euclid(side);
                let horizon = half::f16::from_bits(packed[t as usize] as u16).to_f32();
                texels.push((si as f64 * s, sj as f64 * s, horizon));
            }
        }
        out.push(texels);
    }
    Ok(out)
}

/// Casts `method`'s rays at `scene` into a `width` x `height` image, `ss` rays per pixel each
/// way where the device allows; `prepare(caster, cast size)` writes the uniforms.
fn cast(
    gpu: &Gpu,
    (width, height): (u32, u32),
    (method, ss): (crate::Method, u32),
    scene: RayScene,
    timer: Option<&GpuTimer>,
    prepare: impl FnOnce(&RayMarcher, (u32, u32)) -> Result<()>,
) -> Result<RayImage> {
    let Some(path) = method.ray_path() else {
        return Err(Error::invalid("method", method, "a ray-cast method"));
    };
    let max = gpu.device.limits().max_texture_dimension_2d;
    let ss = ss.max(1);
    let ss = if width * ss <= max && height * ss <= max {
        ss
    } else {
        1
    };
    let size = (width * ss, height * ss);
    let caster = RayMarcher::for_scene(&gpu.device, size.0, size.1, scene)?;
    prepare(&caster, size)?;
    super::scoped(&gpu.device, || {
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        caster.encode(&mut encoder, path, timer);
        if let Some(t) = timer {
            t.resolve(&mut encoder);
        }
        gpu.queue.submit([encoder.finish()]);
    })?;
    let timings = timer.map(|t| t.read(&gpu.device)).transpose()?;
    let image = read_texture(&gpu.device, &gpu.queue, &caster.color)?;
    let all: Vec<f32> =
        bytemuck::pod_collect_to_vec(&read_texture(&gpu.device, &gpu.queue, &caster.distance)?);
    let unresolved = all.iter().filter(|&&d| d == -2.0).count();
    // The subsample nearest each pixel's centre (its centre where ss is odd).
    let distance = (0..height as usize)
        .flat_map(|y| {
            let row = (y * ss as usize + ss as usize / 2) * size.0 as usize;
            let all = &all;
            (0..width as usize).map(move |x| all[row + x * ss as usize + ss as usize / 2])
        })
        .collect();
    let rgba = if ss > 1 {
        downsample_srgb(&image, size.0, size.1, ss)
    } else {
        image
    };
    Ok(RayImage {
        rgba,
        distance,
        unresolved,
        timings,
    })
}
