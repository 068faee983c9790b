//! GPU timestamps for relief's passes, where the adapter has `TIMESTAMP_QUERY`.

use crate::error::{Error, Result};
use std::cell::Cell;

/// A pass relief can time.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Slot {
    /// The fBm bake (height and colour).
    Bake = 0,
    /// The normal pass.
    Normals = 1,
    /// The host's render pass holding the terrain draw.
    Render = 2,
    /// The endless world's light bake (shadows and valley occlusion).
    Light = 3,
    /// The visibility method's raster pass (depth and surface attributes per sample).
    Raster = 4,
    /// The visibility method's compute shading of every sample, or the forward mesh's own
    /// image drawn for the temporal service.
    Shade = 5,
    /// A ray-cast image shown in the target (the window's, the benchmark's): a full-screen draw.
    Show = 6,
    /// The visibility method's image written into the target without a render pass: one
    /// compute pass storing it, or a compute pass packing it and a copy.
    Present = 7,
    /// The temporal service's resolve of the frame into its history.
    Resolve = 8,
    /// The grass's scatter of the frame's blades (their draw is in the pass that draws them).
    Grass = 9,
    /// The grass's blades in the visibility method's compute raster: their raster, big
    /// triangles and resolve, a compute pass after the terrain's raster.
    Blades = 10,
    /// The props' scatter: the grid of placed props around the eye and their heights.
    Props = 11,
    /// The props' march: each pixel's ray through the placed props, after the raster.
    March = 12,
    /// The props' shadow and occlusion on the raster's surface, a 2x2 block of pixels at a
    /// time, before the march.
    PropShadows = 13,
    /// The clouds' image (the visibility method's, where the temporal service runs): a
    /// fraction of its pixels marched, the others carried over from the last frame.
    Clouds = 14,
    /// The terrain's shadow-height map for the light shafts, baked whole on every frame that
    /// draws shafts.
    AirShadow = 15,
}

impl Slot {
    /// All slots, in order.
    pub const ALL: [Slot; 16] = [
        Slot::Bake,
        Slot::Normals,
        Slot::Render,
        Slot::Light,
        Slot::Raster,
        Slot::Shade,
        Slot::Show,
        Slot::Present,
        Slot::Resolve,
        Slot::Grass,
        Slot::Blades,
        Slot::Props,
        Slot::PropShadows,
        Slot::March,
        Slot::Clouds,
        Slot::AirShadow,
    ];

    /// The slot's name as printed.
    pub fn name(self) -> &'static str {
        match self {
            Slot::Bake => "bake",
            Slot::Normals => "normals",
            Slot::Render => "render",
            Slot::Light => "light",
            Slot::Raster => "raster",
            Slot::Shade => "shade",
            Slot::Show => "show",
            Slot::Present => "present",
            Slot::Resolve => "resolve",
            Slot::Grass => "grass",
            Slot::Blades => "blades",
            Slot::Props => "props",
            Slot::March => "march",
            Slot::PropShadows => "props-shadows",
            Slot::Clouds => "clouds",
            Slot::AirShadow => "air-shadow",
        }
    }
}

/// Durations in milliseconds per [`Slot`]; `None` where the pass did not run.
pub type Timings = [Option<f64>; Slot::ALL.len()];

/// Begin/end timestamp pairs for each [`Slot`], resolved into a buffer and read back.
pub struct GpuTimer {
    queries: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    readback: wgpu::Buffer,
    period_ns: f64,
    written: Cell<u32>,
    resolved: Cell<u32>,
}

const QUERIES: u32 = 2 * Slot::ALL.len() as u32;
/// Each slot's pair resolves to its own aligned block of the resolve buffer.
const BLOCK: u64 = wgpu::QUERY_RESOLVE_BUFFER_ALIGNMENT;
const BUFFER_SIZE: u64 = BLOCK * Slot::ALL.len() as u64;

impl GpuTimer {
    /// A timer, or `None` when the device lacks `TIMESTAMP_QUERY`.
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue) -> Option<Self> {
        if !device.features().contains(wgpu::Features::TIMESTAMP_QUERY) {
            return None;
        }
        Some(Self {
            queries: device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("relief:timing:queries"),
                ty: wgpu::QueryType::Timestamp,
                count: QUERIES,
            }),
            resolve: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("relief:timing:resolve"),
                size: BUFFER_SIZE,
                usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            }),
            readback: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("relief:timing:readback"),
                size: BUFFER_SIZE,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            period_ns: f64::from(queue.get_timestamp_period()),
            written: Cell::new(0),
            resolved: Cell::new(0),
        })
    }

    /// Timestamp writes for a compute pass timed as `slot`.
    pub fn compute_writes(&self, slot: Slot) -> wgpu::ComputePassTimestampWrites<'_> {
        self.mark(slot);
        wgpu::ComputePassTimestampWrites {
            query_set: &self.queries,
            beginning_of_pass_write_index: Some(2 * slot as u32),
            end_of_pass_write_index: Some(2 * slot as u32 + 1),
        }
    }

    /// Timestamp writes for a compute pass that begins `slot`: [`GpuTimer::end_after`] ends it
    /// after the commands recorded after the pass (a copy, which cannot be timed by itself).
    pub fn compute_begins(&self, slot: Slot) -> wgpu::ComputePassTimestampWrites<'_> {
        let mut writes = self.compute_writes(slot);
        writes.end_of_pass_write_index = None;
        writes
    }

    /// Ends `slot`, begun by [`GpuTimer::compute_begins`], after what `encoder` recorded so
    /// far: an empty compute pass that only writes the end timestamp (what every device with
    /// timestamps can do, where a timestamp between passes needs a feature of its own).
    pub fn end_after(&self, encoder: &mut wgpu::CommandEncoder, slot: Slot) {
        encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("relief:timing:end"),
            timestamp_writes: Some(wgpu::ComputePassTimestampWrites {
                query_set: &self.queries,
                beginning_of_pass_write_index: None,
                end_of_pass_write_index: Some(2 * slot as u32 + 1),
            }),
        });
    }

    /// Timestamp writes for a render pass timed as `slot`.
    pub fn render_writes(&self, slot: Slot) -> wgpu::RenderPassTimestampWrites<'_> {
        self.mark(slot);
        wgpu::RenderPassTimestampWrites {
            query_set: &self.queries,
            beginning_of_pass_write_index: Some(2 * slot as u32),
            end_of_pass_write_index: Some(2 * slot as u32 + 1),
        }
    }

    fn mark(&self, slot: Slot) {
        self.written.set(self.written.get() | 1 << slot as u32);
    }

    /// Resolves the timestamps written since the last resolve into the readback buffer;
    /// record after the timed passes, in the same or a later encoder. Do not resolve again
    /// until the read of this one has finished.
    pub fn resolve(&self, encoder: &mut wgpu::CommandEncoder) {
        let written = self.written.replace(0);
        for slot in Slot::ALL {
            if written & (1 << slot as u32) != 0 {
                let first = 2 * slot as u32;
                encoder.resolve_query_set(
                    &self.queries,
                    first..first + 2,
                    &self.resolve,
                    BLOCK * slot as u64,
                );
            }
        }
        encoder.copy_buffer_to_buffer(&self.resolve, 0, &self.readback, 0, BUFFER_SIZE);
        self.resolved.set(written);
    }

    /// Waits for the resolved timestamps and returns each resolved slot's duration.
    #[cfg(not(target_arch = "wasm32"))]
    pub fn read(&self, device: &wgpu::Device) -> Result<Timings> {
        let bytes = super::map_read(device, &self.readback)?;
        durations(&bytes, self.resolved.get(), self.period_ns)
    }

    /// Reads the resolved timestamps without blocking (submit the resolve first): `done` runs
    /// once the GPU has finished, from `Device::poll` natively or from the browser's event
    /// loop on the web.
    pub fn read_async(&self, done: impl FnOnce(Result<Timings>) + wgpu::WasmNotSend + 'static) {
        let buffer = self.readback.clone();
        let (mask, period) = (self.resolved.get(), self.period_ns);
        self.readback
            .slice(..)
            .map_async(wgpu::MapMode::Read, move |r| {
                let result = r
                    .map_err(|e| Error::Readback(e.to_string()))
                    .and_then(|()| {
                        let view = buffer
                            .slice(..)
                            .get_mapped_range()
                            .map_err(|e| Error::Readback(e.to_string()))?;
                        durations(&view, mask, period)
                    });
                buffer.unmap();
                done(result);
            });
    }
}

fn durations(bytes: &[u8], mask: u32, period_ns: f64) -> Result<Timings> {
    let ticks: Vec<u64> = bytes
        .chunks_exact(8)
        .map(|c| u64::from_le_bytes(c.try_into().expect("8-byte chunks")))
        .collect();
    let mut out = [None; Slot::ALL.len()];
    for slot in Slot::ALL {
        if mask & (1 << slot as u32) != 0 {
            let i = (BLOCK / 8) as usize * slot as usize;
            if ticks[i + 1] < ticks[i] {
                return Err(Error::Readback(format!(
                    "{} timestamps out of order",
                    slot.name()
                )));
            }
            out[slot as usize] = Some((ticks[i + 1] - ticks[i]) as f64 * period_ns * 1e-6);
        }
    }
    Ok(out)
}
