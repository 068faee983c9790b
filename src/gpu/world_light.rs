//! The endless world's light bake (`wgsl/world_light.wgsl`): per level texel, the terrain's
//! horizon towards the sun and the texel's valley depth ([`crate::light`]), into an
//! `r32uint` texture array (two 16-bit floats packed) beside the level heights, read from those heights. Several
//! rectangles per pass, each with its uniforms at a dynamic offset.

use super::shader;
use crate::clipmap::{Clipmap, MAX_LEVELS};
use crate::landscape::Landscape;
use crate::light::{STEPS_PER_DOUBLING, VALLEY_RADIUS};

/// Mirrors `LightLevel` in `wgsl/world_light.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct LightLevel {
    /// The level's first sample, in its samples.
    pub origin: [i32; 2],
    /// That sample's texel.
    pub origin_mod: [u32; 2],
    /// log2 of the spacing in metres.
    pub spacing_log2: i32,
    /// Texture-array layer.
    pub layer: u32,
    /// 1 when active and wholly baked.
    pub usable: u32,
    /// Padding.
    pub _pad: u32,
}

/// Mirrors `LightUniforms` in `wgsl/world_light.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct LightUniforms {
    /// Unit horizontal direction towards the sun (x, z).
    pub sun: [f32; 2],
    /// Cells per level side.
    pub cells: u32,
    /// Texture side.
    pub side: u32,
    /// Levels in the clipmap.
    pub levels: u32,
    /// World height of normalised height 1.
    pub peak: f32,
    /// `STEPS_PER_DOUBLING`.
    pub steps: f32,
    /// [`VALLEY_RADIUS`].
    pub valley_radius: f32,
    /// The terrain function: hash seed, octaves, [`crate::landscape::TerrainFn::code`], gain,
    /// log2 of octave 0's cell.
    pub seed: u32,
    /// All octaves.
    pub total_octaves: u32,
    /// The terrain function's code.
    pub terrain: u32,
    /// Amplitude ratio between octaves.
    pub gain: f32,
    /// log2 of octave 0's cell in metres.
    pub feature_log2: i32,
    /// 0: endless; else octave 0's lattice cells per period.
    pub period: u32,
    /// Padding.
    pub _pad: [u32; 2],
    /// The levels.
    pub entries: [LightLevel; MAX_LEVELS],
}

/// Mirrors `LightRect` in `wgsl/world_light.wgsl`: a rectangle of one level's samples.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct LightRect {
    /// First sample, in the level's samples.
    pub origin: [i32; 2],
    /// Size in samples.
    pub extent: [u32; 2],
    /// The level's index.
    pub level: u32,
    /// Padding.
    pub _pad: [u32; 3],
}

impl LightUniforms {
    /// The uniforms for `map` under a sun at `azimuth` degrees (clockwise from -z towards +x);
    /// `usable(l)` says whether level `l`'s texels may be read.
    pub fn new(
        map: &Clipmap,
        azimuth: f32,
        land: &Landscape,
        usable: impl Fn(usize) -> bool,
    ) -> Self {
        let side = map.side();
        let mut entries = [LightLevel::default(); MAX_LEVELS];
        for (l, level) in map.levels.iter().enumerate() {
            entries[l] = LightLevel {
                origin: level.origin,
                origin_mod: level.origin.map(|o| o.rem_euclid(side as i32) as u32),
                spacing_log2: level.spacing_log2,
                layer: level.layer,
                usable: u32::from(level.active && usable(l)),
                _pad: 0,
            };
        }
        let a = azimuth.to_radians();
        Self {
            sun: [a.sin(), -a.cos()],
            cells: map.cells(),
            side,
            levels: map.levels.len() as u32,
            peak: land.peak_height as f32,
            steps: STEPS_PER_DOUBLING,
            valley_radius: VALLEY_RADIUS,
            seed: land.seed,
            total_octaves: land.octaves,
            terrain: land.terrain.code(),
            gain: land.gain as f32,
            feature_log2: land.feature_log2,
            period: land.period,
            _pad: [0; 2],
            entries,
        }
    }
}

/// Most rectangles one [`LightBake::encode`] records.
pub(crate) const MAX_LIGHT_RECTS: usize = 96;

/// The pass: pipeline, layout, the level table and a buffer of rectangle slots.
pub(crate) struct LightBake {
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
    uniforms: wgpu::Buffer,
    rects: wgpu::Buffer,
    stride: u64,
}

impl LightBake {
    /// Format of the light textures: horizon elevation (radians) and valley depth (metres) as
    /// two 16-bit floats packed in 32 bits (`pack2x16float`; rg16float is not a storage format
    /// of core WebGPU). 16 bits keep either to about 1/2000 of its value, and a level texel
    /// takes 20 bytes with its heights instead of the 24 of rg32float.
    pub const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Uint;

    /// Builds the pipeline.
    pub fn new(device: &wgpu::Device) -> Self {
        let module = shader::module(
            device,
            "relief:world-light:shader",
            &shader::source("world_light"),
        );
        let c = wgpu::ShaderStages::COMPUTE;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("relief:world-light:bind-group-layout"),
            entries: &[
                super::uniform_entry::<LightUniforms>(0, c),
                wgpu::BindGroupLayoutEntry {
                    binding: 1,
                    visibility: c,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: true,
                        min_binding_size: wgpu::BufferSize::new(
                            std::mem::size_of::<LightRect>() as u64
                        ),
                    },
                    count: None,
                },
                super::array_texture_entry(2, c, wgpu::TextureSampleType::Uint),
                wgpu::BindGroupLayoutEntry {
                    binding: 3,
                    visibility: c,
                    ty: wgpu::BindingType::StorageTexture {
                        access: wgpu::StorageTextureAccess::WriteOnly,
                        format: Self::FORMAT,
                        view_dimension: wgpu::TextureViewDimension::D2Array,
                    },
                    count: None,
                },
            ],
        });
        let pipeline =
            super::compute_pipeline(device, "relief:world-light", &layout, &module, "light_main");
        let uniforms =
            super::uniform_buffer::<LightUniforms>(device, "relief:world-light:uniforms");
        let (rects, stride) =
            super::slot_buffer::<LightRect>(device, "relief:world-light:rects", MAX_LIGHT_RECTS);
        Self {
            pipeline,
            layout,
            uniforms,
            rects,
            stride,
        }
    }

    /// A bind group reading `heights` and writing `light` (2-D array views).
    pub fn bind(
        &self,
        device: &wgpu::Device,
        heights: &wgpu::TextureView,
        light: &wgpu::TextureView,
    ) -> wgpu::BindGroup {
        let entries = [
            wgpu::BindGroupEntry {
                binding: 0,
                resource: self.uniforms.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                    buffer: &self.rects,
                    offset: 0,
                    size: wgpu::BufferSize::new(std::mem::size_of::<LightRect>() as u64),
                }),
            },
            wgpu::BindGroupEntry {
                binding: 2,
                resource: wgpu::BindingResource::TextureView(heights),
            },
            wgpu::BindGroupEntry {
                binding: 3,
                resource: wgpu::BindingResource::TextureView(light),
            },
        ];
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("relief:world-light:bind-group"),
            layout: &self.layout,
            entries: &entries,
        })
    }

    /// Writes the level table and up to [`MAX_LIGHT_RECTS`] rectangles, and records one compute
    /// pass lighting them. Returns how many were recorded.
    pub fn encode(
        &self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        bind_group: &wgpu::BindGroup,
        uniforms: &LightUniforms,
        rects: &[LightRect],
        timestamps: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) -> usize {
        let rects = &rects[..rects.len().min(MAX_LIGHT_RECTS)];
        if rects.is_empty() {
            return 0;
        }
        queue.write_buffer(&self.uniforms, 0, bytemuck::bytes_of(uniforms));
        super::write_slots(queue, &self.rects, self.stride, rects.iter().copied());
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("relief:world-light:pass"),
            timestamp_writes: timestamps,
        });
        pass.set_pipeline(&self.pipeline);
        for (i, r) in rects.iter().enumerate() {
            pass.set_bind_group(0, bind_group, &[(i as u64 * self.stride) as u32]);
            pass.dispatch_workgroups(
                r.extent[0].div_ceil(super::WORKGROUP),
                r.extent[1].div_ceil(super::WORKGROUP),
                1,
            );
        }
        rects.len()
    }
}
