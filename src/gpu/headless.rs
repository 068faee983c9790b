//! Blocking conveniences on top of the core (native only): a device without a window, an
//! offscreen target drawn through the same [`Terrain`] calls as the window, and readback.

use super::timing::{GpuTimer, Slot, Timings};
use super::{Targets, Terrain};
use crate::camera::View;
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
        let (device, queue) = pollster::block_on(super::request_device(&adapter))?;
        Ok(Self {
            adapter,
            device,
            queue,
        })
    }

    /// "name (backend)" of the adapter, for logs and reports.
    pub fn describe(&self) -> String {
        let info = self.adapter.get_info();
        format!("{} ({:?})", info.name, info.backend)
    }
}

/// Maps a `MAP_READ` buffer, waits, and copies its contents out.
pub fn map_read(device: &wgpu::Device, buffer: &wgpu::Buffer) -> Result<Vec<u8>> {
    let slice = buffer.slice(..);
    let (tx, rx) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |r| {
        let _ = tx.send(r);
    });
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| Error::Readback(e.to_string()))?;
    rx.recv()
        .map_err(|e| Error::Readback(e.to_string()))?
        .map_err(|e| Error::Readback(e.to_string()))?;
    let bytes = slice
        .get_mapped_range()
        .map_err(|e| Error::Readback(e.to_string()))?
        .to_vec();
    buffer.unmap();
    Ok(bytes)
}

/// Records a copy of a whole 2-D texture into a new `MAP_READ` buffer; returns the buffer and
/// its padded row pitch in bytes.
pub fn encode_texture_copy(
    device: &wgpu::Device,
    encoder: &mut wgpu::CommandEncoder,
    texture: &wgpu::Texture,
) -> (wgpu::Buffer, u32) {
    encode_aspect_copy(device, encoder, texture, wgpu::TextureAspect::All)
}

/// [`encode_texture_copy`] of one aspect (`DepthOnly` for a depth buffer).
fn encode_aspect_copy(
    device: &wgpu::Device,
    encoder: &mut wgpu::CommandEncoder,
    texture: &wgpu::Texture,
    aspect: wgpu::TextureAspect,
) -> (wgpu::Buffer, u32) {
    let (w, h) = (texture.width(), texture.height());
    let bpp = texture
        .format()
        .block_copy_size(Some(aspect))
        .expect("copyable formats have a block size");
    let pitch = (w * bpp).next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
    let buffer = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("relief:readback"),
        size: u64::from(pitch) * u64::from(h),
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    encoder.copy_texture_to_buffer(
        wgpu::TexelCopyTextureInfo {
            aspect,
            ..texture.as_image_copy()
        },
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(pitch),
                rows_per_image: Some(h),
            },
        },
        texture.size(),
    );
    (buffer, pitch)
}

/// Reads a whole 2-D texture back, rows tightly packed.
pub fn read_texture(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    texture: &wgpu::Texture,
) -> Result<Vec<u8>> {
    let mut encoder = device.create_command_encoder(&Default::default());
    let (buffer, pitch) = encode_texture_copy(device, &mut encoder, texture);
    queue.submit([encoder.finish()]);
    let bytes = map_read(device, &buffer)?;
    Ok(unpad(&bytes, pitch, texture))
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
    let raw = read_texture(device, queue, &t.terrain)?;
    let rg: &[[f32; 2]] = bytemuck::cast_slice(&raw);
    let raw_n = read_texture(device, queue, &t.normals)?;
    let halves: &[[u16; 4]] = bytemuck::cast_slice(&raw_n);
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
        terrain.encode_bake_timed(&mut encoder, timer);
        if let Some(t) = timer {
            t.resolve(&mut encoder);
        }
        gpu.queue.submit([encoder.finish()]);
    })?;
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

/// An offscreen colour (+ depth, + MSAA) target that [`Terrain`] draws into exactly as it
/// draws into a window's surface.
pub struct Offscreen {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// The resolved colour texture (`Rgba8UnormSrgb`).
    pub color: wgpu::Texture,
    msaa: Option<wgpu::TextureView>,
    depth: wgpu::TextureView,
    depth_texture: wgpu::Texture,
    targets: Targets,
}

impl Offscreen {
    /// Colour format of offscreen images.
    pub const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
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
        let make = |label, format, samples, usage| {
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size,
                mip_level_count: 1,
                sample_count: samples,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage,
                view_formats: &[],
            })
        };
        super::scoped(device, || {
            let attach = wgpu::TextureUsages::RENDER_ATTACHMENT;
            let color = make(
                "relief:offscreen:color",
                Self::COLOR_FORMAT,
                1,
                attach | wgpu::TextureUsages::COPY_SRC,
            );
            let msaa = (sample_count > 1).then(|| {
                make(
                    "relief:offscreen:msaa",
                    Self::COLOR_FORMAT,
                    sample_count,
                    attach,
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
            );
            Self {
                width,
                height,
                color,
                msaa,
                depth: depth_texture.create_view(&Default::default()),
                depth_texture,
                targets,
            }
        })
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
        if terrain.targets() != &self.targets {
            return Err(Error::invalid(
                "targets",
                format!("{:?}", terrain.targets()),
                format!("{:?} (the offscreen target's)", self.targets),
            ));
        }
        let device = &gpu.device;
        let buffer_pitch = super::scoped(device, || {
            let color_view = self.color.create_view(&Default::default());
            let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("relief:offscreen:frame"),
            });
            terrain.encode_bake_timed(&mut encoder, timer);
            terrain.prepare(&gpu.queue, view);
            {
                let clear = super::clear_color(terrain.shading().sky_color, Self::COLOR_FORMAT);
                let mut pass = self.begin_pass(
                    &mut encoder,
                    &color_view,
                    clear,
                    timer.map(|t| t.render_writes(Slot::Render)),
                );
                terrain.render(&mut pass);
            }
            let copy = encode_texture_copy(device, &mut encoder, &self.color);
            if let Some(t) = timer {
                t.resolve(&mut encoder);
            }
            gpu.queue.submit([encoder.finish()]);
            copy
        })?;
        let (buffer, pitch) = buffer_pitch;
        let bytes = map_read(device, &buffer)?;
        let timings = timer.map(|t| t.read(device)).transpose()?;
        Ok((unpad(&bytes, pitch, &self.color), timings))
    }
}

impl Offscreen {
    /// The depth buffer of the last frame (single-sampled targets only), row-major.
    pub fn read_depth(&self, gpu: &Gpu) -> Result<Vec<f32>> {
        if self.msaa.is_some() {
            return Err(Error::invalid(
                "sample_count",
                self.targets.sample_count,
                "1 to read depth back",
            ));
        }
        let (w, h) = (self.width, self.height);
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        let (buffer, pitch) = encode_aspect_copy(
            &gpu.device,
            &mut encoder,
            &self.depth_texture,
            wgpu::TextureAspect::DepthOnly,
        );
        gpu.queue.submit([encoder.finish()]);
        let bytes = map_read(&gpu.device, &buffer)?;
        Ok(bytes
            .chunks(pitch as usize)
            .take(h as usize)
            .flat_map(|row| bytemuck::cast_slice::<u8, f32>(&row[..(w * 4) as usize]).to_vec())
            .collect())
    }
}
