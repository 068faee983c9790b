//! Blocking conveniences on top of the core (native only): a device without a window, an
//! offscreen target drawn through the same [`Terrain`] calls as the window, and readback.

mod grass_probe;
mod measure;
mod offscreen;
mod trial;

pub use self::grass_probe::grass_probe;
pub use self::measure::*;
pub use self::offscreen::*;
pub use self::trial::*;
use super::blog::Blog;
pub use super::downsample_srgb;
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
            block_on(
                instance.request_adapter(&wgpu::RequestAdapterOptions {
                    power_preference: wgpu::PowerPreference::from_env()
                        .unwrap_or(wgpu::PowerPreference::HighPerformance),
                    force_fallback_adapter: false,
                    compatible_surface: None,
                    apply_limit_buckets: false,
                }),
            )
            .map_err(|e| Error::NoAdapter(e.to_string()))?;
        let (device, queue) = block_on(super::request_device_with(&adapter, wanted))?;
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

pub(crate) use super::map_read;

/// Records a copy of a whole 2-D texture into a new `MAP_READ` buffer; returns the buffer and
/// its padded row pitch in bytes. The texture must fit one buffer (see [`read_texture_bands`]
/// for any size).
pub(crate) fn encode_texture_copy(
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

/// Runs `future` to completion on this thread, parking between polls (wgpu's native futures
/// are ready at once or woken from the driver's thread). relief's own few lines instead of an
/// executor crate, so that the core depends on no front end's runtime.
pub fn block_on<F: std::future::Future>(future: F) -> F::Output {
    use std::sync::Arc;
    use std::task::{Context, Poll, Wake, Waker};
    struct Unpark(std::thread::Thread);
    impl Wake for Unpark {
        fn wake(self: Arc<Self>) {
            self.0.unpark();
        }
        fn wake_by_ref(self: &Arc<Self>) {
            self.0.unpark();
        }
    }
    let waker = Waker::from(Arc::new(Unpark(std::thread::current())));
    let mut context = Context::from_waker(&waker);
    let mut future = std::pin::pin!(future);
    loop {
        match future.as_mut().poll(&mut context) {
            Poll::Ready(output) => return output,
            Poll::Pending => std::thread::park(),
        }
    }
}
