//! The normal pass: wrap-around central differences of the heights into an rgba16float map.

use super::Textures;
use crate::params::TerrainParams;

/// Mirrors `NormalUniforms` in `wgsl/normals.wgsl` field by field.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct NormalUniforms {
    /// Texture side in texels.
    pub size: u32,
    /// 0: central differences, 1: analytic gradient.
    pub method: u32,
    /// World height of normalised height 1.
    pub height_scale: f32,
    /// World distance between neighbouring texels.
    pub texel_world: f32,
    /// Lattice cells across the tile at octave 0.
    pub frequency: u32,
    /// Octave count.
    pub octaves: u32,
    /// Hash seed.
    pub seed: u32,
    /// Amplitude ratio between octaves.
    pub gain: f32,
    /// Scroll offset in tiles, reduced to [0, 1).
    pub offset: [f32; 2],
    /// Padding to the WGSL struct's size.
    pub _pad: [u32; 2],
}

impl NormalUniforms {
    /// The uniforms for a validated parameter set.
    pub fn new(p: &TerrainParams) -> Self {
        let off = p.reduced_offset();
        Self {
            size: p.size,
            method: match p.normals {
                crate::params::NormalMethod::Differences => 0,
                crate::params::NormalMethod::Analytic => 1,
            },
            height_scale: p.height_scale,
            texel_world: (crate::WORLD_SIZE / f64::from(p.size)) as f32,
            frequency: p.frequency,
            octaves: p.octaves,
            seed: p.seed,
            gain: p.gain,
            offset: [off[0] as f32, off[1] as f32],
            _pad: [0; 2],
        }
    }
}

pub(crate) struct NormalPass {
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
    uniforms: wgpu::Buffer,
    bind_group: Option<wgpu::BindGroup>,
}

impl NormalPass {
    pub fn new(device: &wgpu::Device) -> Self {
        let module = super::shader::module(
            device,
            "relief:normals:shader",
            &super::shader::source("normals"),
        );
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("relief:normals:bind-group-layout"),
            entries: &[
                super::uniform_entry::<NormalUniforms>(0, wgpu::ShaderStages::COMPUTE),
                super::texture_entry(1, wgpu::ShaderStages::COMPUTE, false),
                wgpu::BindGroupLayoutEntry {
                    binding: 2,
                    visibility: wgpu::ShaderStages::COMPUTE,
                    ty: wgpu::BindingType::StorageTexture {
                        access: wgpu::StorageTextureAccess::WriteOnly,
                        format: Textures::NORMAL_FORMAT,
                        view_dimension: wgpu::TextureViewDimension::D2,
                    },
                    count: None,
                },
            ],
        });
        let pipeline =
            super::compute_pipeline(device, "relief:normals", &layout, &module, "normals_main");
        let uniforms = super::uniform_buffer::<NormalUniforms>(device, "relief:normals:uniforms");
        Self {
            pipeline,
            layout,
            uniforms,
            bind_group: None,
        }
    }

    pub fn bind(&mut self, device: &wgpu::Device, textures: &Textures) {
        self.bind_group = Some(device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("relief:normals:bind-group"),
            layout: &self.layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: self.uniforms.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::TextureView(&textures.terrain_view),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: wgpu::BindingResource::TextureView(&textures.normal_view),
                },
            ],
        }));
    }

    pub fn write(&self, queue: &wgpu::Queue, params: &TerrainParams) {
        queue.write_buffer(
            &self.uniforms,
            0,
            bytemuck::bytes_of(&NormalUniforms::new(params)),
        );
    }

    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        size: u32,
        timestamps: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) {
        super::dispatch_square(
            encoder,
            "relief:normals:pass",
            &self.pipeline,
            self.bind_group.as_ref(),
            size,
            timestamps,
        );
    }
}
