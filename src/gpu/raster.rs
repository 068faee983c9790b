//! Where the visibility method's and the hybrid's raster pass runs: the GPU's rasteriser (a
//! render pass writing depth and, for the endless world, attributes; the default) or a compute
//! pass of its own (`wgsl/raster.wgsl`: a thread a cell of the mesh, its two triangles clipped
//! to the near plane and rasterised at pixel centres, the nearest depth kept by an atomic).
//!
//! Why both: an H100 has a few raster units beside a great deal of compute, and its
//! depth-only raster of the default tile (131k triangles, 1920x1080) took 0.50 ms, about half
//! the frame; a desktop GPU rasterises the same in a fraction of that. The choice of the
//! default ([`crate::choice`]) measures both where both can draw.
//!
//! The compute raster draws one sample a pixel. The tile's shading reads its textures at the
//! depth's point, so depth is all its raster must leave. The endless world's shading also reads
//! each pixel's attributes (slope, colour channel, the light bake's horizon and valley), which
//! an atomic on depth cannot carry: a second dispatch of the same pipeline rasterises again and
//! stores them where a triangle's depth is the pixel's nearest, bit for bit. (The same
//! instructions compute it in both dispatches, so the comparison is exact.)

use crate::error::{Error, Result};

/// Where the visibility method rasterises its mesh.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Raster {
    /// The GPU's rasteriser: a render pass writing depth (and the world's attributes).
    #[default]
    Hardware,
    /// A compute pass: one sample a pixel only.
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

    /// Why this raster cannot draw at `samples` a pixel, or `None` where it can.
    pub fn refusal(self, samples: u32) -> Option<&'static str> {
        match self {
            Raster::Compute if samples != 1 => Some(
                "hardware at 4 samples a pixel; the compute raster draws one sample a pixel \
                 (--samples 1)",
            ),
            _ => None,
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
    mode: u32,
}

/// The attribute images the second dispatch writes (the endless world's): slope in x and z,
/// colour channel and horizon, as the hardware raster's surface target holds them ...
pub(crate) const SURFACE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// ... and the valley depth (32-bit: WebGPU's storage textures have no 16-bit red format).
pub(crate) const VALLEY_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;

/// Threads in a workgroup of `raster_cells`.
const GROUP: u32 = 64;
/// Most workgroups in one dimension of a dispatch (WebGPU's default limit).
const MAX_GROUPS: u32 = 65_535;

/// The mesh the raster draws: the world's bind group (its uniforms and level textures, group
/// 0), how many patch instances of each kind (whole patches first; the instances are bound by
/// [`ComputeRaster::bind`]), and the cells per side of a whole patch and of a sub-patch.
pub(crate) struct Patches<'a> {
    pub group: &'a wgpu::BindGroup,
    pub counts: [u32; 2],
    pub cells: [u32; 2],
}

/// The compute raster's pipeline, uniforms and depth buffer (see the module docs).
pub(crate) struct ComputeRaster {
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
    /// Whether a second dispatch writes each pixel's attributes (the endless world's).
    attributes: bool,
    /// The uniforms of the depth dispatch (`mode` 0) and of the attributes' (`mode` 1): one
    /// pipeline for both, so both compute a pixel's depth with the same instructions.
    uniforms: [wgpu::Buffer; 2],
    /// Per pixel, row by row: the nearest depth's complemented bits, 0 where nothing is drawn.
    depth: Option<(u32, u32, wgpu::Buffer)>,
    /// The two dispatches' bind groups ([`ComputeRaster::bind`]).
    groups: Option<[wgpu::BindGroup; 2]>,
}

impl ComputeRaster {
    /// The pipeline for a world whose bind group 0 has `world_layout` (visible to compute);
    /// `attributes`: the endless world's, written by a second dispatch.
    pub(crate) fn new(
        device: &wgpu::Device,
        world_layout: &wgpu::BindGroupLayout,
        attributes: bool,
    ) -> Self {
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
                super::storage_entry(3, SURFACE_FORMAT),
                super::storage_entry(4, VALLEY_FORMAT),
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
            attributes,
            uniforms: [
                "relief:raster:depth-uniforms",
                "relief:raster:attribute-uniforms",
            ]
            .map(|label| super::uniform_buffer::<RasterUniforms>(device, label)),
            depth: None,
            groups: None,
        }
    }

    /// The depth buffer for an image of `size`, made again when the size changes (the caller
    /// binds it again, [`ComputeRaster::bind`]).
    pub(crate) fn depth(&mut self, device: &wgpu::Device, size: (u32, u32)) -> &wgpu::Buffer {
        if !matches!(&self.depth, Some((w, h, _)) if (*w, *h) == size) {
            let buffer = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("relief:raster:depth"),
                size: u64::from(size.0) * u64::from(size.1) * 4,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            self.depth = Some((size.0, size.1, buffer));
            self.groups = None;
        }
        &self.depth.as_ref().expect("made above").2
    }

    /// Binds the world's patch `instances`, the depth buffer of `size` and the attribute
    /// images `surface` ([`SURFACE_FORMAT`]) and `valley` ([`VALLEY_FORMAT`]; 1x1 stand-ins
    /// where there are no attributes), each made with storage use.
    pub(crate) fn bind(
        &mut self,
        device: &wgpu::Device,
        (instances, size): (&wgpu::Buffer, (u32, u32)),
        (surface, valley): (&wgpu::TextureView, &wgpu::TextureView),
    ) {
        self.depth(device, size);
        let Some((_, _, depth)) = &self.depth else {
            return;
        };
        let layout = &self.layout;
        self.groups = Some([0, 1].map(|mode| {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("relief:raster:group"),
                layout,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: self.uniforms[mode].as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: instances.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 2,
                        resource: depth.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 3,
                        resource: wgpu::BindingResource::TextureView(surface),
                    },
                    wgpu::BindGroupEntry {
                        binding: 4,
                        resource: wgpu::BindingResource::TextureView(valley),
                    },
                ],
            })
        }));
    }

    /// Records the raster of `patches` into an image of `size` (bound by
    /// [`ComputeRaster::bind`] at that size): clears the depth buffer, then one compute pass
    /// (timed as `timestamps`) of one dispatch for the depth and, for the endless world, one
    /// for the attributes.
    pub(crate) fn encode(
        &self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        (size, patches): ((u32, u32), &Patches<'_>),
        timestamps: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) {
        let (Some((w, h, depth)), Some(groups)) = (&self.depth, &self.groups) else {
            return;
        };
        debug_assert_eq!((*w, *h), size, "bound at another size");
        let [whole, subs] = patches.counts;
        let [patch_cells, sub_cells] = patches.cells;
        let cells = u64::from(whole) * u64::from(patch_cells).pow(2)
            + u64::from(subs) * u64::from(sub_cells).pow(2);
        let groups_needed = cells.div_ceil(u64::from(GROUP));
        let x = groups_needed.min(u64::from(MAX_GROUPS)) as u32;
        let y = groups_needed.div_ceil(u64::from(x.max(1))) as u32;
        // The attributes' dispatch (and its uniforms) only where there are attributes.
        let dispatches = if self.attributes { 2 } else { 1 };
        for mode in 0..dispatches {
            let u = RasterUniforms {
                size: [size.0, size.1],
                whole,
                subs,
                patch_cells,
                sub_cells,
                row_threads: x * GROUP,
                mode: mode as u32,
            };
            queue.write_buffer(&self.uniforms[mode], 0, bytemuck::bytes_of(&u));
        }
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
        for group in &groups[..dispatches] {
            pass.set_bind_group(1, group, &[]);
            pass.dispatch_workgroups(x, y, 1);
        }
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
    fn the_compute_raster_draws_one_sample_a_pixel_only() {
        assert_eq!(Raster::Compute.refusal(1), None);
        assert!(Raster::Compute.refusal(4).is_some());
        for samples in [1, 4] {
            assert_eq!(Raster::Hardware.refusal(samples), None);
        }
    }
}
