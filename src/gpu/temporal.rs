//! The temporal service on the GPU: two history images (premultiplied linear colour and
//! coverage; each pixel's clip w and frame count) written in turn, and the resolve pass
//! (`wgsl/temporal.wgsl`) that blends a frame into them as [`crate::temporal`] plans. The
//! methods shaded in compute run it after their shading; what they show is its output.

use super::timing::{GpuTimer, Slot};
use crate::temporal::Step;

/// The history's colour: what the shaded image holds, in full precision (a 256-frame mean
/// adds 1/256 of a difference a frame, below half precision's step).
const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
/// The nearest and farthest clip w of each pixel's 3x3 neighbourhood, and the frames its mean
/// holds.
const INFO_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;

/// How far (a fraction of the point's clip w) the history's depth may differ from where the
/// point was and still count as the same surface: a pixel of ground seen at a grazing angle
/// spans several percent of its distance.
pub const DEPTH_TOLERANCE: f32 = 0.05;

/// Mirrors `TemporalUniforms` in `wgsl/temporal.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct TemporalUniforms {
    reproject: [[f32; 4]; 4],
    last: [[f32; 4]; 4],
    depth: [f32; 4],
    size: [u32; 2],
    cap: u32,
    mode: u32,
}

impl TemporalUniforms {
    /// The resolve of `step` for an image of `size` whose depth turns into clip w as
    /// `depth` says (`VisUniforms::depth`), its means holding up to `cap` frames; `moved`: the
    /// frame wrote its points' own motion (the blades' in the wind) into the motion image.
    pub fn new(step: &Step, depth: [f32; 2], size: (u32, u32), (cap, moved): (u32, bool)) -> Self {
        Self {
            reproject: step.reproject.as_mat4().to_cols_array_2d(),
            last: step.last.as_mat4().to_cols_array_2d(),
            depth: [
                depth[0],
                depth[1],
                DEPTH_TOLERANCE,
                f32::from(u8::from(moved)),
            ],
            size: [size.0, size.1],
            cap: cap.max(1),
            mode: step.mode as u32,
        }
    }
}

#[cfg(test)]
#[test]
fn the_histories_take_what_the_memory_count_says() {
    let per_pixel = 2 * (super::texel_bytes(COLOR_FORMAT) + super::texel_bytes(INFO_FORMAT));
    assert_eq!(crate::temporal::history_bytes((3, 2)), 6 * per_pixel);
}

/// Where a frame's points did not move since the last but with the eye: a texel of
/// [`crate::gpu::raster::MOTION_FORMAT`], never written.
const STILL_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// The two histories of one image size.
struct Histories {
    size: (u32, u32),
    color: [wgpu::TextureView; 2],
    info: [wgpu::TextureView; 2],
    /// Bind groups writing history `i` from the other.
    groups: [wgpu::BindGroup; 2],
}

/// The resolve pass and its histories.
pub(crate) struct Resolve {
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
    uniforms: wgpu::Buffer,
    /// The motion image bound where a frame brings none (its uniforms say to read none).
    still: wgpu::TextureView,
    histories: Option<Histories>,
    /// The history the last resolve wrote.
    written: usize,
}

impl Resolve {
    pub fn new(device: &wgpu::Device) -> Self {
        let c = wgpu::ShaderStages::COMPUTE;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("relief:temporal:layout"),
            entries: &[
                super::uniform_entry::<TemporalUniforms>(0, c),
                super::texture_entry(1, c, false),
                super::texture_entry(2, c, false),
                super::texture_entry(3, c, false),
                super::texture_entry(4, c, false),
                super::storage_entry(5, COLOR_FORMAT),
                super::storage_entry(6, INFO_FORMAT),
                super::texture_entry(7, c, false),
            ],
        });
        let module = super::shader::module(
            device,
            "relief:temporal:shader",
            &super::shader::source("temporal"),
        );
        let pipeline = super::compute_pipeline(
            device,
            "relief:temporal:resolve",
            &layout,
            &module,
            "resolve",
        );
        Self {
            pipeline,
            layout,
            uniforms: super::uniform_buffer::<TemporalUniforms>(device, "relief:temporal:uniforms"),
            still: super::texture_2d(
                device,
                "relief:temporal:still",
                (1, 1),
                STILL_FORMAT,
                wgpu::TextureUsages::TEXTURE_BINDING,
            )
            .create_view(&Default::default()),
            histories: None,
            written: 0,
        }
    }

    /// GPU memory of the histories at `size`, bytes ([`crate::temporal::history_bytes`]: the
    /// formats' 16 bytes a pixel each, checked by a test).
    pub fn bytes(size: (u32, u32)) -> u64 {
        crate::temporal::history_bytes(size)
    }

    /// Makes the histories for frames of `size` read from `current` (colour),
    /// `current_depth` and, where the frame writes its points' own motion,
    /// `current_motion` ([`crate::gpu::raster::MOTION_FORMAT`]): the histories of `size` are
    /// kept where they exist, and their bind groups made again (the frame's images are new).
    pub fn bind(
        &mut self,
        device: &wgpu::Device,
        size: (u32, u32),
        (current, current_depth, current_motion): (
            &wgpu::TextureView,
            &wgpu::TextureView,
            Option<&wgpu::TextureView>,
        ),
    ) {
        let usage = wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::TEXTURE_BINDING;
        let make = |label, format| {
            [0, 1].map(|_| {
                super::texture_2d(device, label, size, format, usage)
                    .create_view(&Default::default())
            })
        };
        let (color, info) = match self.histories.take() {
            Some(h) if h.size == size => (h.color, h.info),
            _ => (
                make("relief:temporal:history", COLOR_FORMAT),
                make("relief:temporal:history-info", INFO_FORMAT),
            ),
        };
        use wgpu::BindingResource::TextureView;
        let entry = |binding, resource| wgpu::BindGroupEntry { binding, resource };
        let groups = [0, 1].map(|i| {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("relief:temporal:group"),
                layout: &self.layout,
                entries: &[
                    entry(0, self.uniforms.as_entire_binding()),
                    entry(1, TextureView(current)),
                    entry(2, TextureView(current_depth)),
                    entry(3, TextureView(&color[1 - i])),
                    entry(4, TextureView(&info[1 - i])),
                    entry(5, TextureView(&color[i])),
                    entry(6, TextureView(&info[i])),
                    entry(7, TextureView(current_motion.unwrap_or(&self.still))),
                ],
            })
        });
        self.histories = Some(Histories {
            size,
            color,
            info,
            groups,
        });
    }

    /// Records the resolve of a frame into the history the last one did not write (timed as
    /// [`Slot::Resolve`]). A fresh step reads no history, so new images need no clearing.
    pub fn encode(
        &mut self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        uniforms: &TemporalUniforms,
        timer: Option<&GpuTimer>,
    ) {
        let Some(h) = &self.histories else {
            return;
        };
        queue.write_buffer(&self.uniforms, 0, bytemuck::bytes_of(uniforms));
        let write = 1 - self.written;
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("relief:temporal:resolve-pass"),
            timestamp_writes: timer.map(|t| t.compute_writes(Slot::Resolve)),
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &h.groups[write], &[]);
        pass.dispatch_workgroups(
            h.size.0.div_ceil(super::WORKGROUP),
            h.size.1.div_ceil(super::WORKGROUP),
            1,
        );
        self.written = write;
    }

    /// The histories' colour images (what the frame shows is [`Resolve::written`]'s).
    pub fn colors(&self) -> Option<&[wgpu::TextureView; 2]> {
        self.histories.as_ref().map(|h| &h.color)
    }

    /// The history the last resolve wrote.
    pub fn written(&self) -> usize {
        self.written
    }
}
