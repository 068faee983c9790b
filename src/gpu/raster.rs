//! Where the visibility method's raster pass runs: the GPU's rasteriser (a render pass writing
//! depth, the default) or a compute pass of its own (`wgsl/raster.wgsl`: a thread a cell of
//! the mesh, its two triangles clipped to the near plane and rasterised at pixel centres, the
//! nearest depth kept by an atomic).
//!
//! Why both: an H100 has a few raster units beside a great deal of compute, and its
//! depth-only raster of the default tile (131k triangles, 1920x1080) took 0.50 ms, about half
//! the frame; a desktop GPU rasterises the same in a fraction of that. The choice of the
//! default ([`crate::choice`]) measures both where both can draw.
//!
//! So far the compute raster draws the tile at one sample a pixel: the tile's shading reads
//! its textures at the depth's point, so depth is all the raster must leave. The endless world's
//! raster also leaves each sample's attributes (slope, colour, the light bake's horizon and
//! valley), which an atomic on depth alone cannot carry.

use crate::error::{Error, Result};

/// Where the visibility method rasterises its mesh.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Raster {
    /// The GPU's rasteriser: a render pass writing depth (and the world's attributes).
    #[default]
    Hardware,
    /// A compute pass: the tile at one sample a pixel only.
    Compute,
}

impl Raster {
    /// Every raster, in the order of docs and tables.
    pub const ALL: [Raster; 2] = [Raster::Hardware, Raster::Compute];

    /// Its name on the command line and in the benchmark's CSV.
    pub fn name(self) -> &'static str {
        match self {
            Raster::Hardware => "hardware",
            Raster::Compute => "compute",
        }
    }

    /// The raster called `name`.
    pub fn from_name(name: &str) -> Result<Self> {
        Self::ALL
            .into_iter()
            .find(|r| r.name() == name.trim())
            .ok_or_else(|| Error::invalid("raster", name, "hardware or compute"))
    }

    /// Why the compute raster cannot draw a world (`tile`: the tile or the endless world) at
    /// `samples` a pixel, or `None` where it can.
    pub fn refusal(self, tile: bool, samples: u32) -> Option<&'static str> {
        match self {
            Raster::Hardware => None,
            Raster::Compute if !tile => Some(
                "hardware in the endless world; the compute raster leaves depth alone, and the \
                 world's raster also leaves each sample's attributes",
            ),
            Raster::Compute if samples != 1 => Some(
                "hardware at 4 samples a pixel; the compute raster draws the tile at one sample \
                 a pixel (--samples 1)",
            ),
            Raster::Compute => None,
        }
    }
}

impl std::fmt::Display for Raster {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// Mirrors `RasterUniforms` in `wgsl/raster.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
struct RasterUniforms {
    size: [u32; 2],
    whole: u32,
    subs: u32,
    patch_cells: u32,
    sub_cells: u32,
    row_threads: u32,
    _pad: u32,
}

/// Threads in a workgroup of `raster_cells`.
const GROUP: u32 = 64;
/// Most workgroups in one dimension of a dispatch (WebGPU's default limit).
const MAX_GROUPS: u32 = 65_535;

/// The mesh the raster draws: the world's bind group (its uniforms and level textures, group
/// 0), its patch instances (whole patches first), how many of each, and the cells per side of
/// a whole patch and of a sub-patch.
pub(crate) struct Patches<'a> {
    pub group: &'a wgpu::BindGroup,
    pub instances: &'a wgpu::Buffer,
    pub counts: [u32; 2],
    pub cells: [u32; 2],
}

/// The compute raster's pipeline, uniforms and depth buffer (see the module docs).
pub(crate) struct ComputeRaster {
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
    uniforms: wgpu::Buffer,
    /// Per pixel, row by row: the nearest depth's complemented bits, 0 where nothing is drawn.
    depth: Option<(u32, u32, wgpu::Buffer)>,
    /// Binds the uniforms, the world's instances and the depth buffer (made again with the
    /// depth buffer; the world's instance buffer lives as long as the world).
    group: Option<wgpu::BindGroup>,
}

impl ComputeRaster {
    /// The pipeline for a world whose bind group 0 has `world_layout` (visible to compute).
    pub(crate) fn new(device: &wgpu::Device, world_layout: &wgpu::BindGroupLayout) -> Self {
        use super::shader as s;
        let module = s::module(
            device,
            "relief:raster:shader",
            &s::compose(&[s::SHADE, s::LEVEL_TEXEL, s::WORLD, s::RASTER]),
        );
        let c = wgpu::ShaderStages::COMPUTE;
        let storage = |binding, read_only| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: c,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Storage { read_only },
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        };
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("relief:raster:layout"),
            entries: &[
                super::uniform_entry::<RasterUniforms>(0, c),
                storage(1, true),
                storage(2, false),
            ],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("relief:raster:pipeline-layout"),
            bind_group_layouts: &[Some(world_layout), Some(&layout)],
            immediate_size: 0,
        });
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("relief:raster:cells"),
            layout: Some(&pipeline_layout),
            module: &module,
            entry_point: Some("raster_cells"),
            compilation_options: Default::default(),
            cache: None,
        });
        Self {
            pipeline,
            layout,
            uniforms: super::uniform_buffer::<RasterUniforms>(device, "relief:raster:uniforms"),
            depth: None,
            group: None,
        }
    }

    /// The depth buffer for an image of `size`, made again when the size changes.
    pub(crate) fn depth(&mut self, device: &wgpu::Device, size: (u32, u32)) -> &wgpu::Buffer {
        if !matches!(&self.depth, Some((w, h, _)) if (*w, *h) == size) {
            let buffer = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("relief:raster:depth"),
                size: u64::from(size.0) * u64::from(size.1) * 4,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            self.depth = Some((size.0, size.1, buffer));
            self.group = None;
        }
        &self.depth.as_ref().expect("made above").2
    }

    /// Records the raster of `patches` into an image of `size`: clears the depth buffer, then
    /// one compute pass (timed as `timestamps`).
    pub(crate) fn encode(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        (size, patches): ((u32, u32), &Patches<'_>),
        timestamps: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) {
        self.depth(device, size);
        let Some((_, _, depth)) = &self.depth else {
            return;
        };
        if self.group.is_none() {
            self.group = Some(device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("relief:raster:group"),
                layout: &self.layout,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: self.uniforms.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: patches.instances.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 2,
                        resource: depth.as_entire_binding(),
                    },
                ],
            }));
        }
        let [whole, subs] = patches.counts;
        let [patch_cells, sub_cells] = patches.cells;
        let cells = u64::from(whole) * u64::from(patch_cells).pow(2)
            + u64::from(subs) * u64::from(sub_cells).pow(2);
        let groups = cells.div_ceil(u64::from(GROUP));
        let x = groups.min(u64::from(MAX_GROUPS)) as u32;
        let y = groups.div_ceil(u64::from(x.max(1))) as u32;
        let u = RasterUniforms {
            size: [size.0, size.1],
            whole,
            subs,
            patch_cells,
            sub_cells,
            row_threads: x * GROUP,
            _pad: 0,
        };
        queue.write_buffer(&self.uniforms, 0, bytemuck::bytes_of(&u));
        encoder.clear_buffer(depth, 0, None);
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("relief:raster:pass"),
            timestamp_writes: timestamps,
        });
        if cells == 0 {
            return;
        }
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, patches.group, &[]);
        pass.set_bind_group(1, self.group.as_ref(), &[]);
        pass.dispatch_workgroups(x, y, 1);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_uniforms_have_the_wgsl_layout() {
        // wgsl/raster.wgsl's RasterUniforms: a vec2<u32> and six u32, 32 bytes.
        assert_eq!(std::mem::size_of::<RasterUniforms>(), 32);
        assert_eq!(std::mem::offset_of!(RasterUniforms, whole), 8);
        assert_eq!(std::mem::offset_of!(RasterUniforms, row_threads), 24);
    }

    #[test]
    fn names_round_trip_and_a_bad_one_says_what_is_accepted() {
        for r in Raster::ALL {
            assert_eq!(Raster::from_name(r.name()).unwrap(), r);
        }
        let e = Raster::from_name("software").unwrap_err().to_string();
        assert!(e.contains("hardware or compute"), "{e}");
    }

    #[test]
    fn the_compute_raster_draws_the_tile_at_one_sample_only() {
        assert_eq!(Raster::Compute.refusal(true, 1), None);
        assert!(Raster::Compute.refusal(true, 4).is_some());
        assert!(Raster::Compute.refusal(false, 1).is_some());
        for tile in [false, true] {
            for samples in [1, 4] {
                assert_eq!(Raster::Hardware.refusal(tile, samples), None);
            }
        }
    }
}
