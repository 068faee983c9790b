//! Props on the GPU ([`crate::props`] is the scene and the f64 twin): the kinds' tapes, their
//! boxes and the materials in buffers (`wgsl/props.wgsl`); each frame's scatter of the props
//! around the eye into a grid, with the heights each dual cell and block of them spans
//! (`wgsl/props_scatter.wgsl`, reading the world's bind group for the drawn surface); and the
//! march of each pixel's ray through them (`wgsl/props_march.wgsl`), which the visibility
//! method records between its raster and its shading (`PropsPass::encode_march`).

use super::props_wgsl::gpu_tapes;
use crate::error::Result;
use crate::props::Props;
use crate::props::Scene;

/// Mirrors `PropsFrame` in `wgsl/props.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct PropsFrame {
    pub(crate) eye_cell: [u32; 4],
    pub(crate) eye_in_cell: [f32; 2],
    pub(crate) cell: f32,
    pub(crate) side: u32,
    pub(crate) density: f32,
    pub(crate) rock_density: f32,
    pub(crate) distance: f32,
    pub(crate) cutoff: f32,
    pub(crate) seed: u32,
    pub(crate) kinds: u32,
    pub(crate) placed: u32,
    pub(crate) water: f32,
    pub(crate) pixels: f32,
    pub(crate) band: f32,
    pub(crate) blocks: u32,
    pub(crate) steps: u32,
    pub(crate) flags: u32,
    pub(crate) peer_steps: u32,
    _pad: [u32; 2],
}

/// The most props put at given places a scene holds.
pub const MAX_EXPLICIT: usize = 64;
/// Bytes of a placed prop's record in the grid.
const RECORD_BYTES: u64 = 64;
/// Dual cells on a side of a block (`BLOCK` in `wgsl/props_grid.wgsl`).
const BLOCK: u32 = 8;
/// The most sphere-tracing steps a pixel's ray takes through the props.
pub const STEPS: u32 = 96;
/// `PropsFrame::flags`: march the seed's way (`seed_walk` in `wgsl/props_march.wgsl`).
const PEER_SEED: u32 = 16;
/// The steps of the seed's way where `RELIEF_PROPS_PEER=seed` asks for it.
pub const PEER_STEPS: u32 = 400;
/// Workgroups of 64 threads that stride over the grass's blades in its cut (`props_grass` in
/// `wgsl/props_march.wgsl`).
const GRASS_GROUPS: u32 = 512;
/// The props' shadow and occlusion on the raster's surface, a texel a 2x2 block of pixels: the
/// sun's share, the distance of the point it was marched from and the sky's share (`quad_in`
/// in `wgsl/props_march.wgsl`).
const QUAD_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;

/// The image of the props' shadow a 2x2 block of pixels for a frame's size, bound to be
/// written and to be read.
struct QuadImage {
    size: (u32, u32),
    bytes: u64,
    write: wgpu::BindGroup,
    read: wgpu::BindGroup,
}

/// `PropsFrame::flags`: march with no raster's depth (the overlay, [`super::props_overlay`]).
const UNBOUNDED: u32 = 32;
/// `PropsFrame::flags`: the reference's march ([`super::props_reference`]): every sample's own
/// shadow on the surface.
const REFERENCE: u32 = 64;
/// The most sphere-tracing steps the reference's rays take through the props.
pub const REFERENCE_STEPS: u32 = 1024;

/// What bounds a frame's march through the props, and how finely it is done.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum March {
    /// Up to the compute raster's depth, the props' shadow on its surface a 2x2 block of
    /// pixels at a time (the visibility method).
    Raster,
    /// To the draw distance, no raster's depth (the overlay).
    Unbounded,
    /// Up to the reference's cast's depth, every sample's own shadow, [`REFERENCE_STEPS`]
    /// steps and no screen-size cut-off: every prop to the draw distance whole.
    Reference,
}
/// Where the march leaves each pixel's prop (`wgsl/props_march.wgsl`).
pub(crate) const HIT_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Uint;

/// Cells on a side of the grid around the eye's cell that the draw distance reaches (even: the
/// eye's cell is number side / 2).
pub fn grid_side(p: &Props) -> u32 {
    2 * (f64::from(p.distance) / f64::from(p.cell)).ceil() as u32 + 4
}

/// The props of the endless world on the GPU (see the module docs).
pub(crate) struct PropsPass {
    scene: Scene,
    props: Props,
    /// The seed's way's steps, where the benchmark's peer marches them
    /// ([`crate::World::set_props_peer`]).
    peer: Option<u32>,
    frame: wgpu::Buffer,
    /// The kinds' instructions, the kinds, the materials; the grid's records, each cell's,
    /// dual cell's and block's heights; the props put at given places.
    buffers: [wgpu::Buffer; 8],
    side: u32,
    blocks: u32,
    scatter: [wgpu::ComputePipeline; 4],
    pub(super) scatter_group: wgpu::BindGroup,
    march: wgpu::ComputePipeline,
    march_layouts: [wgpu::BindGroupLayout; 2],
    /// The props' shadow on the raster's surface, a 2x2 block of pixels a thread, and the
    /// layouts of its image written and read.
    shadows: wgpu::ComputePipeline,
    quad_layouts: [wgpu::BindGroupLayout; 2],
    quads: std::sync::Mutex<Option<QuadImage>>,
    /// The cut of the grass inside the props, its layout of the grass's blades, and the empty
    /// group 0 it binds.
    grass: (
        wgpu::ComputePipeline,
        wgpu::BindGroupLayout,
        wgpu::BindGroup,
    ),
    /// The march's module and the scatter's layout, which the reference's treatment of its
    /// blades ([`PropsPass::encode_grass_reference`]) and the bake of the props' shade map
    /// ([`super::props_map`]) are made of when first asked, and they.
    pub(super) parts: (wgpu::ShaderModule, wgpu::BindGroupLayout),
    pub(super) map_bake: std::sync::OnceLock<wgpu::ComputePipeline>,
    #[cfg(not(target_arch = "wasm32"))]
    reference_grass: std::sync::OnceLock<(wgpu::ComputePipeline, wgpu::BindGroupLayout)>,
}

fn buffer_of(device: &wgpu::Device, label: &str, size: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: size.max(16),
        usage: wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_DST
            | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    })
}

impl PropsPass {
    /// The passes for `scene` (validated here: the error names the key), the scatter reading
    /// the world's bind group of `world_layout`.
    pub fn new(
        device: &wgpu::Device,
        world_layout: &wgpu::BindGroupLayout,
        (scene, props): (&Scene, Props),
    ) -> Result<Self> {
        let tapes = scene.compile(&props)?;
        if scene.placed.len() > MAX_EXPLICIT {
            return Err(crate::Error::invalid(
                "prop_place",
                format!("{} props", scene.placed.len()),
                format!("at most {MAX_EXPLICIT}"),
            ));
        }
        let (code, kinds) = gpu_tapes(scene, &tapes);
        let materials: Vec<[f32; 4]> = scene
            .materials
            .iter()
            .map(|m| [m.albedo[0], m.albedo[1], m.albedo[2], m.variation])
            .collect();
        let side = grid_side(&props);
        let dual = u64::from(side + 1);
        let blocks = (side + 1).div_ceil(BLOCK);
        let cells = u64::from(side) * u64::from(side) + MAX_EXPLICIT as u64;
        let sizes = [
            std::mem::size_of_val(code.as_slice()) as u64,
            std::mem::size_of_val(kinds.as_slice()) as u64,
            std::mem::size_of_val(materials.as_slice()) as u64,
            cells * RECORD_BYTES,
            cells * 8,
            dual * dual * 8,
            u64::from(blocks * blocks + 1) * 8,
            MAX_EXPLICIT as u64 * 32,
        ];
        let labels = [
            "relief:props:code",
            "relief:props:kinds",
            "relief:props:materials",
            "relief:props:grid",
            "relief:props:cell-range",
            "relief:props:dual-range",
            "relief:props:block-range",
            "relief:props:explicit",
        ];
        let contents: [&[u8]; 3] = [
            bytemuck::cast_slice(&code),
            bytemuck::cast_slice(&kinds),
            bytemuck::cast_slice(&materials),
        ];
        let buffers: [wgpu::Buffer; 8] = std::array::from_fn(|i| match contents.get(i) {
            Some(bytes) => {
                use wgpu::util::DeviceExt;
                device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some(labels[i]),
                    contents: bytes,
                    usage: wgpu::BufferUsages::STORAGE,
                })
            }
            None => buffer_of(device, labels[i], sizes[i]),
        });
        let c = wgpu::ShaderStages::COMPUTE;
        let mut entries = vec![
            super::uniform_entry::<PropsFrame>(0, c),
            super::storage_buffer_entry(1, true),
            super::storage_buffer_entry(2, true),
            super::storage_buffer_entry(3, true),
        ];
        entries.extend((4..8).map(|b| super::storage_buffer_entry(b, false)));
        let mut scatter_entries = entries.clone();
        scatter_entries.push(super::storage_buffer_entry(8, true));
        let scatter_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("relief:props:scatter-layout"),
            entries: &scatter_entries,
        });
        let mut march_entries = entries;
        march_entries.push(super::storage_entry(9, HIT_FORMAT));
        let march_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("relief:props:march-layout"),
            entries: &march_entries,
        });
        // The frame's render, world and visibility uniforms, the raster's depth.
        let uniform = |binding| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: c,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        };
        let view_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("relief:props:view-layout"),
            entries: &[
                uniform(0),
                uniform(1),
                uniform(12),
                super::storage_buffer_entry(19, true),
            ],
        });
        let frame = super::uniform_buffer::<PropsFrame>(device, "relief:props:frame");
        let scatter_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("relief:props:scatter-group"),
            layout: &scatter_layout,
            entries: &std::iter::once(frame.as_entire_binding())
                .chain(buffers.iter().map(|b| b.as_entire_binding()))
                .enumerate()
                .map(|(i, resource)| wgpu::BindGroupEntry {
                    binding: i as u32,
                    resource,
                })
                .collect::<Vec<_>>(),
        });
        let source = super::shader::source("props_scatter");
        let module = super::shader::module(device, "relief:props:scatter", &source);
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("relief:props:scatter-pipeline-layout"),
            bind_group_layouts: &[Some(world_layout), Some(&scatter_layout)],
            immediate_size: 0,
        });
        let pipeline = |module: &wgpu::ShaderModule, layout: &wgpu::PipelineLayout, entry: &str| {
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(&format!("relief:props:{entry}")),
                layout: Some(layout),
                module,
                entry_point: Some(entry),
                compilation_options: Default::default(),
                cache: None,
            })
        };
        let scatter = [
            "props_scatter",
            "props_ranges",
            "props_blocks",
            "props_span",
        ]
        .map(|entry| pipeline(&module, &layout, entry));
        // The tapes compiled into the march's WGSL, or read from their buffer where
        // RELIEF_PROPS_TAPES=buffer (the two are measured against each other: docs/props.md).
        let compiled = std::env::var("RELIEF_PROPS_TAPES").as_deref() != Ok("buffer");
        let march_module = super::shader::module(
            device,
            "relief:props:march",
            &super::props_wgsl::march_source(&tapes, compiled),
        );
        // The props' shadow on the raster's surface a 2x2 block at a time: written by
        // `props_shadows`, read by the march.
        let quad_layouts = [
            super::storage_entry(0, QUAD_FORMAT),
            super::texture_entry(1, c, false),
        ]
        .map(|entry| {
            device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("relief:props:quad-layout"),
                entries: &[entry],
            })
        });
        let [shadows, march] = [
            (&quad_layouts[0], "props_shadows"),
            (&quad_layouts[1], "props_march"),
        ]
        .map(|(quads, entry)| {
            let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("relief:props:march-pipeline-layout"),
                bind_group_layouts: &[Some(&view_layout), Some(&march_layout), Some(quads)],
                immediate_size: 0,
            });
            pipeline(&march_module, &layout, entry)
        });
        // The grass's cut: the props' records (the scatter's group) and the grass's blades.
        let empty = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("relief:props:empty-layout"),
            entries: &[],
        });
        let empty_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("relief:props:empty-group"),
            layout: &empty,
            entries: &[],
        });
        let grass_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("relief:props:grass-layout"),
            entries: &[
                super::storage_buffer_entry(0, false),
                super::storage_buffer_entry(1, true),
            ],
        });
        let grass_pipeline_layout =
            device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("relief:props:grass-pipeline-layout"),
                // An empty group 0 (the module's view uniforms, unused here): a gap in the
                // layouts is newer WebGPU than every browser has.
                bind_group_layouts: &[Some(&empty), Some(&scatter_layout), Some(&grass_layout)],
                immediate_size: 0,
            });
        let grass = pipeline(&march_module, &grass_pipeline_layout, "props_grass");
        let parts = (march_module.clone(), scatter_layout.clone());
        Ok(Self {
            scene: scene.clone(),
            props,
            peer: None,
            frame,
            buffers,
            side,
            blocks,
            scatter,
            scatter_group,
            march,
            shadows,
            march_layouts: [view_layout, march_layout],
            quad_layouts,
            quads: std::sync::Mutex::new(None),
            grass: (grass, grass_layout, empty_group),
            parts,
            map_bake: std::sync::OnceLock::new(),
            #[cfg(not(target_arch = "wasm32"))]
            reference_grass: std::sync::OnceLock::new(),
        })
    }

    /// Marches the view rays the seed's way with `steps` steps (the benchmark's peer), or
    /// relief's (`None`).
    pub fn set_peer(&mut self, steps: Option<u32>) {
        self.peer = steps;
    }

    /// The scene it draws and how it scatters it.
    pub fn drawn(&self) -> (&Scene, Props) {
        (&self.scene, self.props)
    }

    /// GPU memory of its buffers, bytes.
    pub fn bytes(&self) -> u64 {
        let quads = self
            .quads
            .lock()
            .map_or(0, |q| q.as_ref().map_or(0, |q| q.bytes));
        self.buffers.iter().map(wgpu::Buffer::size).sum::<u64>()
            + std::mem::size_of::<PropsFrame>() as u64
            + quads
    }

    /// Records the scatter of the props around `eye` (world metres) over the landscape of
    /// `seed`, with the world's bind group `world` at 0 (its uniforms already written), for an
    /// image whose height spans `pixels` pixels a unit of tan(angle), the water's normalised
    /// level `water` (`None`: none), and how the march runs (`march`); timed as
    /// [`super::timing::Slot::Props`].
    pub fn encode(
        &self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        (world, seed, eye): (&wgpu::BindGroup, u32, glam::DVec3),
        (pixels, water, march): (f32, Option<f32>, March),
        timer: Option<&super::timing::GpuTimer>,
    ) {
        let p = &self.props;
        let placed = &self.scene.placed;
        // The seed's way for the benchmark's peer (never the reference's): set, or
        // RELIEF_PROPS_PEER=seed (docs/props.md).
        let peer = match self.peer {
            Some(steps) => Some(steps),
            None if std::env::var("RELIEF_PROPS_PEER").as_deref() == Ok("seed") => Some(PEER_STEPS),
            None => None,
        }
        .filter(|_| march != March::Reference);
        let cell = f64::from(p.cell);
        let eye_cell = p.cell_at(eye.x, eye.z);
        let words = |v: i64| [v as u64 as u32, (v as u64 >> 32) as u32];
        let [x, z] = eye_cell.map(words);
        let frame = PropsFrame {
            eye_cell: [x[0], x[1], z[0], z[1]],
            eye_in_cell: [
                (eye.x - eye_cell[0] as f64 * cell) as f32,
                (eye.z - eye_cell[1] as f64 * cell) as f32,
            ],
            cell: p.cell,
            side: self.side,
            density: p.density,
            rock_density: p.rock_density,
            distance: p.distance,
            // The reference sinks none: a cut-off under any prop's size on screen.
            cutoff: if march == March::Reference {
                1e-6
            } else {
                p.cutoff
            },
            seed,
            kinds: self.scene.kinds.len() as u32,
            placed: placed.len() as u32,
            water: water.unwrap_or(-1e30),
            pixels,
            band: p.band,
            blocks: self.blocks,
            steps: if march == March::Reference {
                REFERENCE_STEPS
            } else {
                STEPS
            },
            flags: if peer.is_some() { PEER_SEED } else { 0 }
                | match march {
                    March::Raster => 0,
                    March::Unbounded => UNBOUNDED,
                    March::Reference => REFERENCE,
                },
            peer_steps: peer.unwrap_or(0),
            _pad: [0; 2],
        };
        queue.write_buffer(&self.frame, 0, bytemuck::bytes_of(&frame));
        if !placed.is_empty() {
            let records: Vec<[f32; 4]> = placed
                .iter()
                .enumerate()
                .flat_map(|(i, e)| {
                    let h = crate::noise::pcg(i as u32 ^ 0x7061_6365);
                    [
                        [
                            (e.at[0] - eye.x) as f32,
                            (e.at[1] - eye.z) as f32,
                            e.turn.to_radians(),
                            e.scale,
                        ],
                        [
                            e.kind as f32,
                            (h >> 8) as f32 / 16_777_216.0,
                            f32::from_bits(crate::noise::pcg(h)),
                            0.0,
                        ],
                    ]
                })
                .collect();
            queue.write_buffer(&self.buffers[7], 0, bytemuck::cast_slice(&records));
        }
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("relief:props:scatter-pass"),
            timestamp_writes: timer.map(|t| t.compute_writes(super::timing::Slot::Props)),
        });
        pass.set_bind_group(0, world, &[]);
        pass.set_bind_group(1, &self.scatter_group, &[]);
        let g = super::WORKGROUP;
        // The grid, and a row of threads past it for the props put at given places.
        let rows = self.side + (MAX_EXPLICIT as u32).div_ceil(self.side);
        let dispatches = [
            (self.side.div_ceil(g), rows.div_ceil(g)),
            ((self.side + 1).div_ceil(g), (self.side + 1).div_ceil(g)),
            (self.blocks.div_ceil(g), self.blocks.div_ceil(g)),
            (1, 1),
        ];
        for (pipeline, (x, y)) in self.scatter.iter().zip(dispatches) {
            pass.set_pipeline(pipeline);
            pass.dispatch_workgroups(x, y, 1);
        }
    }

    /// The image of the props' shadow on the raster's surface for a frame of `size` (a texel
    /// a 2x2 block of pixels): its bind groups to write and to read it.
    fn quad_image(&self, device: &wgpu::Device, size: (u32, u32)) -> QuadImage {
        let usage = wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::TEXTURE_BINDING;
        let texture = super::texture_2d(
            device,
            "relief:props:quads",
            (size.0.div_ceil(2).max(1), size.1.div_ceil(2).max(1)),
            QUAD_FORMAT,
            usage,
        );
        let view = texture.create_view(&Default::default());
        let [write, read] = [0, 1].map(|binding| {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("relief:props:quad-group"),
                layout: &self.quad_layouts[binding as usize],
                entries: &[wgpu::BindGroupEntry {
                    binding,
                    resource: wgpu::BindingResource::TextureView(&view),
                }],
            })
        });
        QuadImage {
            size,
            bytes: u64::from(texture.width())
                * u64::from(texture.height())
                * super::texel_bytes(QUAD_FORMAT),
            write,
            read,
        }
    }

    /// Records the march of each pixel of an image of `size` through the props into `hit`,
    /// reading the frame's render, world and visibility uniforms and the compute raster's
    /// depth, as `march` says ([`March::Raster`]: the props' shadow on the raster's surface
    /// first marched a 2x2 block of pixels at a time, timed as
    /// [`super::timing::Slot::PropShadows`]); timed as [`super::timing::Slot::March`].
    pub fn encode_march(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        (render, world, vis, depth): (&wgpu::Buffer, &wgpu::Buffer, &wgpu::Buffer, &wgpu::Buffer),
        (hit, size, march): (&wgpu::TextureView, (u32, u32), March),
        timer: Option<&super::timing::GpuTimer>,
    ) {
        // Only the raster's march reads the blocks' shadow: elsewhere a 1x1 image stands in.
        let bounded = march == March::Raster;
        let quad_size = if bounded { size } else { (1, 1) };
        let mut kept = self
            .quads
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        if kept.as_ref().is_none_or(|q| q.size != quad_size) {
            *kept = Some(self.quad_image(device, quad_size));
        }
        let quads = kept.as_ref().expect("made above");
        let entry = |binding: u32, resource| wgpu::BindGroupEntry { binding, resource };
        let view_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("relief:props:view-group"),
            layout: &self.march_layouts[0],
            entries: &[
                entry(0, render.as_entire_binding()),
                entry(1, world.as_entire_binding()),
                entry(12, vis.as_entire_binding()),
                entry(19, depth.as_entire_binding()),
            ],
        });
        let mut entries: Vec<wgpu::BindGroupEntry<'_>> =
            std::iter::once(self.frame.as_entire_binding())
                .chain(self.buffers[..7].iter().map(|b| b.as_entire_binding()))
                .enumerate()
                .map(|(i, resource)| entry(i as u32, resource))
                .collect();
        entries.push(entry(9, wgpu::BindingResource::TextureView(hit)));
        let march_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("relief:props:march-group"),
            layout: &self.march_layouts[1],
            entries: &entries,
        });
        let g = super::WORKGROUP;
        if bounded {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("relief:props:shadows-pass"),
                timestamp_writes: timer.map(|t| t.compute_writes(super::timing::Slot::PropShadows)),
            });
            pass.set_bind_group(0, &view_group, &[]);
            pass.set_bind_group(1, &march_group, &[]);
            pass.set_pipeline(&self.shadows);
            pass.set_bind_group(2, &quads.write, &[]);
            let blocks = (size.0.div_ceil(2), size.1.div_ceil(2));
            pass.dispatch_workgroups(blocks.0.div_ceil(g), blocks.1.div_ceil(g), 1);
        }
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("relief:props:march-pass"),
            timestamp_writes: timer.map(|t| t.compute_writes(super::timing::Slot::March)),
        });
        pass.set_bind_group(0, &view_group, &[]);
        pass.set_bind_group(1, &march_group, &[]);
        pass.set_pipeline(&self.march);
        pass.set_bind_group(2, &quads.read, &[]);
        pass.dispatch_workgroups(size.0.div_ceil(g), size.1.div_ceil(g), 1);
    }

    /// Records the props' part in the reference's blades (`wgsl/grass_reference.wgsl`, four
    /// vectors a blade, `counts`' fourth their number), after the props' scatter: a blade whose
    /// root is inside a prop is flattened, as [`PropsPass::encode_grass`] does; every other one
    /// takes the props' shadow at its middle into its sun's share and their occlusion at its
    /// root into its sky's, as the reference lights a blade whole. `render`: the cast's render
    /// uniforms (the sun).
    #[cfg(not(target_arch = "wasm32"))]
    pub(crate) fn encode_grass_reference(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        render: &wgpu::Buffer,
        (blades, counts): (&wgpu::Buffer, &wgpu::Buffer),
    ) {
        let (pipeline, sun_layout) = self.reference_grass.get_or_init(|| {
            let (module, scatter_layout) = &self.parts;
            let sun_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("relief:props:grass-reference-sun"),
                entries: &[wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: wgpu::ShaderStages::COMPUTE,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                    count: None,
                }],
            });
            let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("relief:props:grass-reference-layout"),
                bind_group_layouts: &[Some(&sun_layout), Some(scatter_layout), Some(&self.grass.1)],
                immediate_size: 0,
            });
            let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some("relief:props:props_grass_reference"),
                layout: Some(&layout),
                module,
                entry_point: Some("props_grass_reference"),
                compilation_options: Default::default(),
                cache: None,
            });
            (pipeline, sun_layout)
        });
        let sun = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("relief:props:grass-reference-sun"),
            layout: sun_layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: render.as_entire_binding(),
            }],
        });
        let group = self.grass_group(device, (blades, counts));
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("relief:props:grass-reference-pass"),
            timestamp_writes: None,
        });
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, &sun, &[]);
        pass.set_bind_group(1, &self.scatter_group, &[]);
        pass.set_bind_group(2, &group, &[]);
        pass.dispatch_workgroups(GRASS_GROUPS, 1, 1);
    }

    /// Records the cut of the grass inside the props: each of the grass's `blades` (its
    /// scatter already recorded, with its `counts`, and the props' scatter) whose root is
    /// inside a prop is flattened to nothing.
    pub(crate) fn encode_grass(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        (blades, counts): (&wgpu::Buffer, &wgpu::Buffer),
    ) {
        let (pipeline, _, empty) = &self.grass;
        let group = self.grass_group(device, (blades, counts));
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("relief:props:grass-pass"),
            timestamp_writes: None,
        });
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, empty, &[]);
        pass.set_bind_group(1, &self.scatter_group, &[]);
        pass.set_bind_group(2, &group, &[]);
        pass.dispatch_workgroups(GRASS_GROUPS, 1, 1);
    }

    /// The blades and their counts bound for the grass's cut.
    fn grass_group(
        &self,
        device: &wgpu::Device,
        (blades, counts): (&wgpu::Buffer, &wgpu::Buffer),
    ) -> wgpu::BindGroup {
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("relief:props:grass-group"),
            layout: &self.grass.1,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: blades.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: counts.as_entire_binding(),
                },
            ],
        })
    }

    /// Cells on a side of its grid around the eye's cell (the eye's is number side / 2).
    #[cfg(not(target_arch = "wasm32"))]
    pub fn side(&self) -> u32 {
        self.side
    }

    /// The last scatter's records, read back (blocking; native only): a cell's of the grid,
    /// row by row (z), then the props put at given places; each the prop's foot
    /// (camera-relative) and scale (0: none), the cosine and sine of its turn, its kind and its
    /// noise's seed (bits), its shade, the terrain's horizon and valley and the foot's
    /// normalised height; the centre (camera-relative) and radius of a sphere that holds it.
    #[cfg(not(target_arch = "wasm32"))]
    pub fn read_records(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<Vec<[f32; 16]>> {
        let n = u64::from(self.side) * u64::from(self.side) + self.scene.placed.len() as u64;
        let bytes = n * RECORD_BYTES;
        let staging = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("relief:props:grid-staging"),
            size: bytes,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut encoder = device.create_command_encoder(&Default::default());
        encoder.copy_buffer_to_buffer(&self.buffers[3], 0, &staging, 0, bytes);
        queue.submit([encoder.finish()]);
        let raw = super::map_read(device, &staging)?;
        let floats: &[f32] = bytemuck::cast_slice(&raw);
        Ok(floats
            .chunks_exact(16)
            .map(|c| std::array::from_fn(|i| c[i]))
            .collect())
    }
}
