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
}

impl Slot {
    /// All slots, in order.
    pub const ALL: [Slot; 3] = [Slot::Bake, Slot::Normals, Slot::Render];

    /// The slot's name as printed.
    pub fn name(self) -> &'static str {
        match self {
            Slot::Bake => "bake",
            Slot::Normals => "normals",
            Slot::Render => "render",
        }
    }
}

/// Durations in milliseconds per [`Slot`]; `None` where the pass did not run.
pub type Timings = [Option<f64>; 3];

/// Begin/end timestamp pairs for each [`Slot`], resolved into a buffer and read back.
pub struct GpuTimer {
    queries: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    readback: wgpu::Buffer,
    period_ns: f64,
    written: Cell<u32>,
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

    /// Resolves the timestamps written since the last [`GpuTimer::read`] into the readback
    /// buffer; record after the timed passes, in the same or a later encoder.
    pub fn resolve(&self, encoder: &mut wgpu::CommandEncoder) {
        for slot in Slot::ALL {
            if self.written.get() & (1 << slot as u32) != 0 {
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
    }

    /// Waits for the resolved timestamps and returns each written slot's duration.
    #[cfg(not(target_arch = "wasm32"))]
    pub fn read(&self, device: &wgpu::Device) -> Result<Timings> {
        let bytes = super::headless::map_read(device, &self.readback)?;
        let ticks: &[u64] = bytemuck::cast_slice(&bytes);
        let mut out = [None; 3];
        for slot in Slot::ALL {
            if self.written.get() & (1 << slot as u32) != 0 {
                let i = (BLOCK / 8) as usize * slot as usize;
                let dt = ticks[i + 1].wrapping_sub(ticks[i]);
                if ticks[i + 1] < ticks[i] {
                    return Err(Error::Readback(format!(
                        "{} timestamps out of order",
                        slot.name()
                    )));
                }
                out[slot as usize] = Some(dt as f64 * self.period_ns * 1e-6);
            }
        }
        self.written.set(0);
        Ok(out)
    }
}
