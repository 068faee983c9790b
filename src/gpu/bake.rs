//! The bake pass: fBm height and colour channels into one rg32float texture, a texel an
//! invocation, or a 2x2 quad of texels an invocation where the quad's texels share every
//! octave's lattice cell ([`quads_share_cells`]): they then share its hashed corners.

use super::{shader, Textures};
use crate::params::TerrainParams;

/// Mirrors `BakeUniforms` in `wgsl/bake.wgsl` field by field.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct BakeUniforms {
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

/// Whether every 2x2 quad of texels from an even texel lies in one lattice cell of every octave
/// of `p`: with no scroll offset, when each octave's cells span an even number of texels (the
/// tile's side a multiple of twice the finest octave's cells across it).
pub(crate) fn quads_share_cells(p: &TerrainParams) -> bool {
    let finest = u64::from(p.frequency) << p.octaves.saturating_sub(1).min(32);
    p.reduced_offset() == [0.0, 0.0] && finest > 0 && u64::from(p.size) % (2 * finest) == 0
}

pub(crate) struct BakePass {
    pipeline: wgpu::ComputePipeline,
    /// `bake_quads`: a 2x2 quad of texels an invocation.
    quads_pipeline: wgpu::ComputePipeline,
    /// Whether the last written parameters bake by quads ([`quads_share_cells`]).
    quads: bool,
    layout: wgpu::BindGroupLayout,
    uniforms: wgpu::Buffer,
    bind_group: Option<wgpu::BindGroup>,
}

impl BakePass {
    pub fn new(device: &wgpu::Device) -> Self {
        let module = shader::module(device, "relief:bake:shader", &shader::source("bake"));
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
        let quads_pipeline =
            super::compute_pipeline(device, "relief:bake:quads", &layout, &module, "bake_quads");
        let uniforms = super::uniform_buffer::<BakeUniforms>(device, "relief:bake:uniforms");
        Self {
            pipeline,
            quads_pipeline,
            quads: false,
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

    pub fn write(&mut self, queue: &wgpu::Queue, params: &TerrainParams) {
        self.quads = quads_share_cells(params);
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
        let (pipeline, invocations) = if self.quads {
            (&self.quads_pipeline, size.div_ceil(2))
        } else {
            (&self.pipeline, size)
        };
        super::dispatch_square(
            encoder,
            "relief:bake:pass",
            pipeline,
            self.bind_group.as_ref(),
            invocations,
            timestamps,
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quads_only_where_they_share_every_octaves_cell() {
        let p = |size, frequency, octaves, offset| TerrainParams {
            size,
            frequency,
            octaves,
            offset,
            ..Default::default()
        };
        // The default: 1024 texels, 4 cells at octave 0, 8 octaves: 2 texels to the finest cell.
        assert!(quads_share_cells(&p(1024, 4, 8, [0.0, 0.0])));
        assert!(quads_share_cells(&p(4096, 4, 8, [1.0, -2.0])));
        // 50 texels to the finest cell (5 x 4 cells across 1000).
        assert!(quads_share_cells(&p(1000, 5, 3, [0.0, 0.0])));
        // One texel to the finest cell; 83.3 (cell boundaries inside quads); a scroll.
        assert!(!quads_share_cells(&p(512, 4, 8, [0.0, 0.0])));
        assert!(!quads_share_cells(&p(1000, 3, 3, [0.0, 0.0])));
        assert!(!quads_share_cells(&p(1024, 4, 8, [0.25, 0.0])));
    }
}
