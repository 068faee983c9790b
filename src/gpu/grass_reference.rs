//! The grass of the reference (`--method reference` with grass on): the blades the frame's
//! scatter makes (the same cells, the same hash), every one of them to [`REACH`] times the draw
//! distance at its full height in all four segments (no level of detail, no thinning, no
//! widening), rooted on the continuous surface the reference's rays meet and lit by that
//! surface's horizon and valley (`wgsl/grass_reference.wgsl`), and with props by the props too
//! (cut inside them, their shadow and occlusion: `props_grass_reference` in
//! `wgsl/props_march.wgsl`); drawn as a layer over the cast at
//! its samples, depth-tested against the surface it found ([`super::ray_layers`]), by the
//! rasteriser's draw of the frame's blades (`wgsl/grass_draw.wgsl`). The ground under them is
//! bare earth to that distance (`grass_ground` in `wgsl/shade.wgsl`).
//!
//! The cast with grass takes [`JITTERS`] x [`JITTERS`] sub-pixel offsets of the reference's
//! 3x3 samples, averaged in linear light: 9x9 samples a pixel for the terrain and the blades
//! alike (`headless::render_world_rays`).

use super::grass::{GrassUniforms, BLADE_BYTES};
use super::layer::{Layer, LayerFrame};
use super::render::RenderUniforms;
use super::world_rays::WorldRayUniforms;
use super::Targets;
use crate::error::{Error, Result};

/// How far the reference draws blades, as a multiple of the grass's draw distance.
pub const REACH: f32 = 2.0;

/// Sub-pixel offsets each way of the cast with grass (of the reference's 3x3 rays a pixel).
pub const JITTERS: u32 = 3;

/// Mirrors `ReferenceFrame` in `wgsl/grass_reference.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
struct ReferenceFrame {
    g: GrassUniforms,
    eye_in_cell: [f32; 2],
    distance: f32,
    side: u32,
    capacity: u32,
    _pad: [u32; 3],
    wind: [f32; 4],
    gust_phase: [f32; 4],
}

/// The reference's blades for one view, scattered when made, drawn as a layer of the cast.
pub(crate) struct GrassReference {
    blades: wgpu::Buffer,
    count: u32,
    /// The counts as the props' pass over the blades reads them (the fourth: `count`).
    counts: wgpu::Buffer,
    layout: wgpu::BindGroupLayout,
    module: wgpu::ShaderModule,
    pipelines: Vec<(Targets, wgpu::RenderPipeline)>,
    groups: Vec<(wgpu::Buffer, wgpu::BindGroup)>,
}

impl GrassReference {
    /// Scatters the blades of `params`' grass seen through `view`, with the cast's `ray`
    /// uniforms and the layers' `render` uniforms (whose matrix culls them): once to count
    /// them, once to keep them in a buffer of that size (blocking). Refuses a view that keeps
    /// more blades than the device's largest storage buffer holds, in words.
    pub fn new(
        gpu: &super::headless::Gpu,
        params: &crate::world::WorldParams,
        view: &crate::WorldView,
        (ray, render): (&WorldRayUniforms, &RenderUniforms),
    ) -> Result<Self> {
        use wgpu::util::DeviceExt as _;
        let device = &gpu.device;
        let grass = params.grass;
        let eye = view.eye;
        let s = grass.cell();
        let eye_cell = grass.cell_at(eye.x, eye.z);
        let distance = REACH * grass.distance;
        let side = 2 * (f64::from(distance) / s).ceil() as u32 + 3;
        let (wind, gust_phase) =
            super::grass::wind_uniforms(params.wind.velocity(), (params.clock, params.clock), eye);
        let frame = |capacity| ReferenceFrame {
            g: GrassUniforms::new(&grass, params.land.seed, eye_cell),
            eye_in_cell: [
                (eye.x - eye_cell[0] as f64 * s) as f32,
                (eye.z - eye_cell[1] as f64 * s) as f32,
            ],
            distance,
            side,
            capacity,
            _pad: [0; 3],
            wind,
            gust_phase,
        };
        let init = |label: &str, contents: &[u8], usage| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage,
            })
        };
        let uniform = wgpu::BufferUsages::UNIFORM;
        let render_buffer = init(
            "relief:grass-reference:render",
            bytemuck::bytes_of(render),
            uniform,
        );
        let ray_buffer = init(
            "relief:grass-reference:ray",
            bytemuck::bytes_of(ray),
            uniform,
        );
        let module = super::shader::module(
            device,
            "relief:grass-reference:scatter",
            &super::shader::source("grass_reference"),
        );
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("relief:grass-reference:scatter"),
            layout: None,
            module: &module,
            entry_point: Some("scatter_reference"),
            compilation_options: Default::default(),
            cache: None,
        });
        let group = |index: u32, buffers: &[&wgpu::Buffer]| {
            let entries: Vec<_> = buffers
                .iter()
                .enumerate()
                .map(|(i, b)| wgpu::BindGroupEntry {
                    binding: i as u32,
                    resource: b.as_entire_binding(),
                })
                .collect();
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("relief:grass-reference:scatter"),
                layout: &pipeline.get_bind_group_layout(index),
                entries: &entries,
            })
        };
        let uniforms = group(0, &[&render_buffer, &ray_buffer]);
        let storage = wgpu::BufferUsages::STORAGE;
        let counts = init(
            "relief:grass-reference:counts",
            &[0; 16],
            storage | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
        );
        // Once to count (nothing stored), once to store exactly that many.
        let run = |capacity: u32| -> Result<(wgpu::Buffer, u32)> {
            let blades = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("relief:grass-reference:blades"),
                size: (u64::from(capacity) * BLADE_BYTES).max(BLADE_BYTES),
                usage: storage,
                mapped_at_creation: false,
            });
            let frame_buffer = init(
                "relief:grass-reference:frame",
                bytemuck::bytes_of(&frame(capacity)),
                uniform,
            );
            let io = group(1, &[&frame_buffer, &blades, &counts]);
            let staging = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("relief:grass-reference:staging"),
                size: 16,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            super::scoped(device, || {
                let mut encoder = device.create_command_encoder(&Default::default());
                encoder.clear_buffer(&counts, 0, None);
                {
                    let mut pass = encoder.begin_compute_pass(&Default::default());
                    pass.set_pipeline(&pipeline);
                    pass.set_bind_group(0, &uniforms, &[]);
                    pass.set_bind_group(1, &io, &[]);
                    let groups = side.div_ceil(super::WORKGROUP);
                    pass.dispatch_workgroups(groups, groups, 1);
                }
                encoder.copy_buffer_to_buffer(&counts, 0, &staging, 0, 16);
                gpu.queue.submit([encoder.finish()]);
            })?;
            let bytes = super::map_read(device, &staging)?;
            Ok((blades, bytemuck::pod_read_unaligned::<u32>(&bytes[..4])))
        };
        let (_, count) = run(0)?;
        let limits = device.limits();
        let most = limits
            .max_storage_buffer_binding_size
            .min(limits.max_buffer_size)
            / BLADE_BYTES;
        if u64::from(count) > most {
            return Err(Error::invalid(
                "grass_distance",
                grass.distance,
                format!(
                    "a reference of at most {most} blades on this device (this view keeps \
                     {count} within {distance} m): a shorter distance or a lower density"
                ),
            ));
        }
        let (blades, stored) = run(count)?;
        let count = stored.min(count);
        let counts = init(
            "relief:grass-reference:props-counts",
            bytemuck::cast_slice(&[0, 0, 0, count, 0, 0, 0, 0u32]),
            storage,
        );
        Ok(Self {
            blades,
            count,
            counts,
            layout: super::grass::draw_layout(device),
            module: super::grass::draw_module(device),
            pipelines: Vec::new(),
            groups: Vec::new(),
        })
    }

    /// The blades it draws.
    pub fn count(&self) -> u32 {
        self.count
    }

    /// Its blades and their counts, for the props' pass over them
    /// ([`crate::World::encode_reference_grass`]).
    pub fn blades(&self) -> (&wgpu::Buffer, &wgpu::Buffer) {
        (&self.blades, &self.counts)
    }
}

impl Layer for GrassReference {
    fn name(&self) -> &str {
        "grass reference"
    }

    fn prepare(&mut self, frame: &LayerFrame<'_>, _: &mut wgpu::CommandEncoder) {
        let device = frame.device;
        if !self.pipelines.iter().any(|(t, _)| t == frame.targets) {
            let pipeline =
                super::grass::draw_pipeline(device, (&self.layout, &self.module), frame.targets);
            self.pipelines.push((*frame.targets, pipeline));
        }
        let uniforms = frame.render_uniforms;
        if !self.groups.iter().any(|(b, _)| b == uniforms) {
            let group = super::grass::draw_group(device, &self.layout, uniforms, &self.blades);
            // One cast's buffer at a time: each cast makes its own.
            self.groups.clear();
            self.groups.push((uniforms.clone(), group));
        }
    }

    fn render(&self, pass: &mut wgpu::RenderPass<'_>) {
        let (Some((_, pipeline)), Some((_, group))) = (self.pipelines.first(), self.groups.first())
        else {
            return;
        };
        if self.count == 0 {
            return;
        }
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, group, &[]);
        pass.draw(0..9, 0..self.count);
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn the_frame_matches_the_wgsl() {
        let source = super::super::shader::source("grass_reference");
        let module = naga::front::wgsl::parse_str(&source).expect("grass_reference.wgsl parses");
        let (_, ty) = module
            .types
            .iter()
            .find(|(_, t)| t.name.as_deref() == Some("ReferenceFrame"))
            .expect("ReferenceFrame");
        let naga::TypeInner::Struct { span, .. } = ty.inner else {
            panic!("a struct");
        };
        assert_eq!(span as usize, std::mem::size_of::<super::ReferenceFrame>());
    }
}
