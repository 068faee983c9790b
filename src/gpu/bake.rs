//! The bake pass: fBm height and colour channels into one rg32float texture.

use super::{shader, Textures};
use crate::params::TerrainParams;

/// Mirrors `BakeUniforms` in `wgsl/bake.wgsl` field by field.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct BakeUniforms {
    /// Texture side in texels.
    pub size: u32,
    /// Lattice cells across the tile at octave 0.
    pub frequency: u32,
    /// Octave count.
    pub octaves: u32,
    /// Hash seed.
    pub seed: u32,
    /// Amplitude ratio between octaves.
    pub gain: f32,
    /// Padding so `offset` sits at its WGSL alignment.
    pub _pad: u32,
    /// Scroll offset in tiles, reduced to [0, 1).
    pub offset: [f32; 2],
}

impl BakeUniforms {
    /// The uniforms for a validated parameter set.
    pub fn new(p: &TerrainParams) -> Self {
        let off = p.reduced_offset();
        Self {
            size: p.size,
            frequency: p.frequency,
            octaves: p.octaves,
            seed: p.seed,
            gain: p.gain,
            _pad: 0,
            offset: [off[0] as f32, off[1] as f32],
        }
    }
}

pub(crate) struct BakePass {
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
    uniforms: wgpu::Buffer,
    bind_group: Option<wgpu::BindGroup>,
}

impl BakePass {
    pub fn new(device: &wgpu::Device) -> Self {
        let module = shader::module(
            device,
            "relief:bake:shader",
            &shader::compose(&[shader::NOISE, shader::BAKE]),
        );
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("relief:bake:bind-group-layout"),
            entries: &[
                super::uniform_entry::<BakeUniforms>(0, wgpu::ShaderStages::COMPUTE),
                wgpu::BindGroupLayoutEntry {
                    binding: 1,
                    visibility: wgpu::ShaderStages::COMPUTE,
                    ty: wgpu::BindingType::StorageTexture {
                        access: wgpu::StorageTextureAccess::WriteOnly,
                        format: Textures::TERRAIN_FORMAT,
                        view_dimension: wgpu::TextureViewDimension::D2,
                    },
                    count: None,
                },
            ],
        });
        let pipeline =
            super::compute_pipeline(device, "relief:bake", &layout, &module, "bake_main");
        let uniforms = super::uniform_buffer::<BakeUniforms>(device, "relief:bake:uniforms");
        Self {
            pipeline,
            layout,
            uniforms,
            bind_group: None,
        }
    }

    pub fn bind(&mut self, device: &wgpu::Device, textures: &Textures) {
        self.bind_group = Some(device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("relief:bake:bind-group"),
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
            ],
        }));
    }

    pub fn write(&self, queue: &wgpu::Queue, params: &TerrainParams) {
        queue.write_buffer(
            &self.uniforms,
            0,
            bytemuck::bytes_of(&BakeUniforms::new(params)),
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
            "relief:bake:pass",
            &self.pipeline,
            self.bind_group.as_ref(),
            size,
            timestamps,
        );
    }
}
