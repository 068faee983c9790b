//! Grass on the GPU: the uniforms `wgsl/grass.wgsl` reads (the eye's cell and clump in 64
//! bits, the seed, the grass's parameters), the scatter pass that keeps each frame's blades
//! and their draw. (`headless::grass_probe` runs the blades and the cover at given cells and
//! surfaces, which the tests hold to the CPU twin, [`crate::grass`].)

use crate::grass::Grass;

/// Mirrors `GrassUniforms` in `wgsl/grass.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct GrassUniforms {
    pub(crate) eye_cell: [u32; 4],
    pub(crate) eye_clump: [u32; 4],
    pub(crate) eye_rem: [i32; 2],
    pub(crate) clump_cells: i32,
    pub(crate) seed: u32,
    pub(crate) height: f32,
    pub(crate) cell: f32,
    _pad: [f32; 2],
}

/// A 64-bit integer as its low and high words.
fn words(v: i64) -> [u32; 2] {
    [v as u64 as u32, (v as u64 >> 32) as u32]
}

impl GrassUniforms {
    /// The uniforms of `grass` over the landscape of `seed`, cells counted from `eye_cell`.
    pub fn new(grass: &Grass, seed: u32, eye_cell: [i64; 2]) -> Self {
        let k = i64::from(grass.clump_cells());
        let clump = eye_cell.map(|c| c.div_euclid(k));
        let [x, z] = eye_cell.map(words);
        let [cx, cz] = clump.map(words);
        Self {
            eye_cell: [x[0], x[1], z[0], z[1]],
            eye_clump: [cx[0], cx[1], cz[0], cz[1]],
            eye_rem: eye_cell.map(|c| c.rem_euclid(k) as i32),
            clump_cells: k as i32,
            seed,
            height: grass.height,
            cell: grass.cell() as f32,
            _pad: [0.0; 2],
        }
    }
}

/// Mirrors `GrassFrame` in `wgsl/grass_scatter.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
struct GrassFrame {
    g: GrassUniforms,
    eye_in_cell: [f32; 2],
    distance: f32,
    side: u32,
    capacity: u32,
    pixels_high: f32,
    peer: u32,
    _pad: u32,
    wind: [f32; 4],
    gust_phase: [f32; 4],
}

/// Threads of a workgroup of the cull (`@workgroup_size` of `cull` in the WGSL): a block each.
const CULL_GROUP: u32 = 64;

/// Blocks of 8 x 8 cells in the square of cells the scatter spans for `grass`.
fn block_count(grass: &Grass) -> u32 {
    grass.side().div_ceil(super::WORKGROUP).pow(2)
}

/// Bytes of the cull's list of blocks for `grass`: a word a block.
fn blocks_bytes(grass: &Grass) -> u64 {
    u64::from(block_count(grass)) * 4
}

/// Blades the draw holds at most a frame: 64 bytes each, 32 MiB.
pub const CAPACITY: u32 = 1 << 19;

/// Bytes a blade takes in the draw's buffer.
pub const BLADE_BYTES: u64 = 64;

/// Triangles the compute raster's list holds at most a frame (4 bytes each, 4 MiB): a blade's
/// number and its triangle's, so that a thread rasterises a triangle and none idles (the
/// meadow from 1.7 m draws 475k).
pub const TRIANGLE_CAPACITY: u32 = 1 << 20;

/// Bytes of the indirect arguments `finish` writes: the draw's (16), then the compute
/// raster's dispatch of a thread a triangle of its list (16, at [`DISPATCH_OFFSET`]).
const ARGS_BYTES: u64 = 32;
/// Bytes of the scatter's counts: blades considered, kept, appended, drawn, the triangles of
/// those kept, those in the compute raster's list, the blocks the cull listed, and 1 unused.
const COUNTS_BYTES: u64 = 32;
const DISPATCH_OFFSET: u64 = 16;
/// Bytes of the scatter's indirect dispatch, which the cull writes.
const SCATTER_ARGS_BYTES: u64 = 16;

/// The grass of the endless world on the GPU: the scatter pass that keeps each frame's blades
/// (`wgsl/grass_scatter.wgsl`, reading the world's bind group for the drawn surface), after a
/// cull that lists the blocks of cells it runs on, and their draw (`wgsl/grass_draw.wgsl`), one
/// indirect draw of a strip a blade.
pub(crate) struct GrassPass {
    grass: Grass,
    /// The benchmark's peer, where it is drawn in relief's place ([`crate::grass::Peer`]).
    peer: Option<crate::grass::Peer>,
    cull: wgpu::ComputePipeline,
    cull_finish: wgpu::ComputePipeline,
    scatter: wgpu::ComputePipeline,
    finish: wgpu::ComputePipeline,
    frame: wgpu::Buffer,
    blades: wgpu::Buffer,
    counts: wgpu::Buffer,
    args: wgpu::Buffer,
    /// The compute raster's list of the blades' triangles ([`TRIANGLE_CAPACITY`]).
    triangles: wgpu::Buffer,
    /// The scatter's indirect dispatch (a workgroup a listed block), which the cull writes: bound
    /// in a group of its own, used by the cull's pass alone, as the scatter's pass dispatches
    /// from it. (The list of blocks is bound in `scatter_group`.)
    scatter_args: wgpu::Buffer,
    scatter_group: wgpu::BindGroup,
    args_group: wgpu::BindGroup,
    draw_module: wgpu::ShaderModule,
    draw_layout: wgpu::BindGroupLayout,
    /// The draw's pipelines for the targets it drew into, and its bind groups for the
    /// render-uniform buffers it read (the host's pass's and the mesh history's own).
    pipelines: Vec<(super::Targets, wgpu::RenderPipeline)>,
    groups: Vec<(wgpu::Buffer, wgpu::BindGroup)>,
}

impl GrassPass {
    /// The passes for `grass`, the scatter reading the world's bind group of `world_layout`.
    pub fn new(device: &wgpu::Device, world_layout: &wgpu::BindGroupLayout, grass: Grass) -> Self {
        let c = wgpu::ShaderStages::COMPUTE;
        let frame_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("relief:grass:frame-layout"),
            entries: &[
                super::uniform_entry::<GrassFrame>(0, c),
                super::storage_buffer_entry(1, false),
                super::storage_buffer_entry(2, false),
                super::storage_buffer_entry(3, false),
                super::storage_buffer_entry(4, false),
                super::storage_buffer_entry(5, false),
            ],
        });
        let args_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("relief:grass:scatter-args-layout"),
            entries: &[super::storage_buffer_entry(0, false)],
        });
        let module = super::shader::module(
            device,
            "relief:grass:scatter",
            &super::shader::source("grass_scatter"),
        );
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("relief:grass:scatter-layout"),
            bind_group_layouts: &[Some(world_layout), Some(&frame_layout)],
            immediate_size: 0,
        });
        let cull_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("relief:grass:cull-layout"),
            bind_group_layouts: &[Some(world_layout), Some(&frame_layout), Some(&args_layout)],
            immediate_size: 0,
        });
        let pipeline = |entry: &str, layout: &wgpu::PipelineLayout| {
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some("relief:grass:scatter"),
                layout: Some(layout),
                module: &module,
                entry_point: Some(entry),
                compilation_options: Default::default(),
                cache: None,
            })
        };
        let buffer = |label: &str, size: u64, usage: wgpu::BufferUsages| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage,
                mapped_at_creation: false,
            })
        };
        let storage = wgpu::BufferUsages::STORAGE;
        let frame = super::uniform_buffer::<GrassFrame>(device, "relief:grass:frame");
        let blades = buffer(
            "relief:grass:blades",
            u64::from(CAPACITY) * BLADE_BYTES,
            storage | wgpu::BufferUsages::COPY_SRC,
        );
        let counts = buffer(
            "relief:grass:counts",
            COUNTS_BYTES,
            storage | wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
        );
        let args = buffer(
            "relief:grass:draw-args",
            ARGS_BYTES,
            storage | wgpu::BufferUsages::INDIRECT,
        );
        let triangles = buffer(
            "relief:grass:triangles",
            u64::from(TRIANGLE_CAPACITY) * 4,
            storage,
        );
        let blocks = buffer("relief:grass:blocks", blocks_bytes(&grass), storage);
        let scatter_args = buffer(
            "relief:grass:scatter-args",
            SCATTER_ARGS_BYTES,
            storage | wgpu::BufferUsages::INDIRECT,
        );
        let args_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("relief:grass:scatter-args-group"),
            layout: &args_layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: scatter_args.as_entire_binding(),
            }],
        });
        let scatter_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("relief:grass:frame-group"),
            layout: &frame_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: frame.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: blades.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: counts.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: args.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 4,
                    resource: triangles.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 5,
                    resource: blocks.as_entire_binding(),
                },
            ],
        });
        let draw_layout = draw_layout(device);
        Self {
            grass,
            peer: None,
            cull: pipeline("cull", &cull_layout),
            cull_finish: pipeline("cull_finish", &cull_layout),
            scatter: pipeline("scatter", &layout),
            finish: pipeline("finish", &layout),
            frame,
            blades,
            counts,
            args,
            triangles,
            scatter_args,
            scatter_group,
            args_group,
            draw_module: draw_module(device),
            draw_layout,
            pipelines: Vec::new(),
            groups: Vec::new(),
        }
    }

    /// The grass it draws.
    pub fn grass(&self) -> Grass {
        self.grass
    }

    /// The benchmark's peer it draws instead of relief's grass, if any.
    pub fn peer(&self) -> Option<crate::grass::Peer> {
        self.peer
    }

    /// Draws the benchmark's `peer` (its patch's distance already in [`GrassPass::grass`])
    /// instead of relief's grass, or relief's again.
    pub fn set_peer(&mut self, peer: Option<crate::grass::Peer>) {
        self.peer = peer;
    }

    /// GPU memory of its buffers, bytes.
    pub fn bytes(&self) -> u64 {
        u64::from(CAPACITY) * BLADE_BYTES
            + u64::from(TRIANGLE_CAPACITY) * 4
            + blocks_bytes(&self.grass)
            + SCATTER_ARGS_BYTES
            + COUNTS_BYTES
            + ARGS_BYTES
            + std::mem::size_of::<GrassFrame>() as u64
    }

    /// Records the scatter of the blades around `eye` (world metres) over the landscape of
    /// `seed` for an image `pixels_high` pixels high (each blade's level of detail follows its
    /// length on screen), with the world's bind group `world` at 0 (its uniforms already written), the
    /// tips blown by the air's `velocity` (m/s, x and z) at `clock` seconds (and how far they
    /// moved since the last frame's clock `before`, for the temporal service), timed as
    /// [`super::timing::Slot::Grass`].
    pub fn encode(
        &self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        (world, seed, eye, pixels_high): (&wgpu::BindGroup, u32, glam::DVec3, u32),
        (velocity, clock, before): (glam::DVec2, f64, f64),
        timer: Option<&super::timing::GpuTimer>,
    ) {
        let (wind, gust_phase) = wind_uniforms(velocity, (clock, before), eye);
        let s = self.grass.cell();
        let eye_cell = self.grass.cell_at(eye.x, eye.z);
        let frame = GrassFrame {
            g: GrassUniforms::new(&self.grass, seed, eye_cell),
            eye_in_cell: [
                (eye.x - eye_cell[0] as f64 * s) as f32,
                (eye.z - eye_cell[1] as f64 * s) as f32,
            ],
            distance: self.grass.distance,
            side: self.grass.side(),
            capacity: CAPACITY,
            pixels_high: pixels_high as f32,
            peer: u32::from(self.peer.is_some()),
            _pad: 0,
            wind,
            gust_phase,
        };
        queue.write_buffer(&self.frame, 0, bytemuck::bytes_of(&frame));
        encoder.clear_buffer(&self.counts, 0, None);
        // The cull, in a pass of its own: the scatter's pass reads its arguments as an indirect
        // dispatch, which a pass that binds them for writing cannot.
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("relief:grass:cull-pass"),
                timestamp_writes: timer.map(|t| t.compute_begins(super::timing::Slot::Grass)),
            });
            pass.set_pipeline(&self.cull);
            pass.set_bind_group(0, world, &[]);
            pass.set_bind_group(1, &self.scatter_group, &[]);
            pass.set_bind_group(2, &self.args_group, &[]);
            pass.dispatch_workgroups(block_count(&self.grass).div_ceil(CULL_GROUP), 1, 1);
            pass.set_pipeline(&self.cull_finish);
            pass.dispatch_workgroups(1, 1, 1);
        }
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("relief:grass:scatter-pass"),
            timestamp_writes: timer.map(|t| wgpu::ComputePassTimestampWrites {
                beginning_of_pass_write_index: None,
                ..t.compute_writes(super::timing::Slot::Grass)
            }),
        });
        pass.set_pipeline(&self.scatter);
        pass.set_bind_group(0, world, &[]);
        pass.set_bind_group(1, &self.scatter_group, &[]);
        pass.dispatch_workgroups_indirect(&self.scatter_args, 0);
        pass.set_pipeline(&self.finish);
        pass.dispatch_workgroups(1, 1, 1);
    }

    /// The blades for the compute raster with ids ([`super::raster::Blades`]).
    pub fn raster_blades(&self) -> super::raster::Blades<'_> {
        super::raster::Blades {
            blades: &self.blades,
            counts: &self.counts,
            triangles: &self.triangles,
            args: &self.args,
            args_offset: DISPATCH_OFFSET,
        }
    }

    /// The last scatter's counts, read back (blocking): blades considered (cells within the
    /// draw distance), kept (on grass, inside the view), drawn (kept, up to [`CAPACITY`]) and
    /// the kept blades' triangles (each of `s` segments has `2 s - 1`; the drawn blades' where
    /// none passed the capacity).
    #[cfg(not(target_arch = "wasm32"))]
    pub fn read_counts(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> crate::Result<[u32; 4]> {
        let staging = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("relief:grass:counts-staging"),
            size: COUNTS_BYTES,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut encoder = device.create_command_encoder(&Default::default());
        encoder.copy_buffer_to_buffer(&self.counts, 0, &staging, 0, COUNTS_BYTES);
        queue.submit([encoder.finish()]);
        let bytes = super::map_read(device, &staging)?;
        let c: &[u32] = bytemuck::cast_slice(&bytes);
        Ok([c[0], c[1], c[3], c[4]])
    }

    /// The first `n` blades the last scatter kept, read back (blocking): 16 numbers each, as
    /// `wgsl/grass_scatter.wgsl` writes them.
    #[cfg(not(target_arch = "wasm32"))]
    pub fn read_blades(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        n: u32,
    ) -> crate::Result<Vec<[f32; 16]>> {
        let drawn = self.read_counts(device, queue)?[2].min(n);
        let bytes = (u64::from(drawn) * BLADE_BYTES).max(BLADE_BYTES);
        let staging = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("relief:grass:blades-staging"),
            size: bytes,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut encoder = device.create_command_encoder(&Default::default());
        encoder.copy_buffer_to_buffer(&self.blades, 0, &staging, 0, bytes);
        queue.submit([encoder.finish()]);
        let raw = super::map_read(device, &staging)?;
        let floats: &[f32] = bytemuck::cast_slice(&raw);
        Ok(floats
            .chunks_exact(16)
            .take(drawn as usize)
            .map(|c| std::array::from_fn(|i| c[i]))
            .collect())
    }

    /// Makes the draw's pipeline for `targets` and its bind group for the render uniforms in
    /// `uniforms`, where it has none yet (a few of each are kept).
    pub fn prepare_draw(
        &mut self,
        device: &wgpu::Device,
        targets: &super::Targets,
        uniforms: &wgpu::Buffer,
    ) {
        if !self.pipelines.iter().any(|(t, _)| t == targets) {
            let pipeline = draw_pipeline(device, (&self.draw_layout, &self.draw_module), targets);
            self.pipelines.push((*targets, pipeline));
            if self.pipelines.len() > 4 {
                self.pipelines.remove(0);
            }
        }
        if !self.groups.iter().any(|(b, _)| b == uniforms) {
            let group = draw_group(device, &self.draw_layout, uniforms, &self.blades);
            self.groups.push((uniforms.clone(), group));
            if self.groups.len() > 4 {
                self.groups.remove(0);
            }
        }
    }

    /// Draws the blades the last scatter kept into `pass`, of `targets`, shaded with the
    /// render uniforms in `uniforms` (both made ready by [`GrassPass::prepare_draw`]; nothing
    /// is drawn otherwise).
    pub fn draw(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        targets: &super::Targets,
        uniforms: &wgpu::Buffer,
    ) {
        let pipeline = self.pipelines.iter().find(|(t, _)| t == targets);
        let group = self.groups.iter().find(|(b, _)| b == uniforms);
        let (Some((_, pipeline)), Some((_, group))) = (pipeline, group) else {
            return;
        };
        pass.push_debug_group("relief:grass");
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, group, &[]);
        pass.draw_indirect(&self.args, 0);
        pass.pop_debug_group();
    }
}

/// The wind as `wgsl/grass.wgsl`'s `wind_tip` reads it: the direction the air of `velocity`
/// (m/s, x and z) blows towards and its speed; the gust waves' phases at `eye` at `clock`
/// seconds (turns).
pub(crate) fn wind_uniforms(
    velocity: glam::DVec2,
    (clock, before): (f64, f64),
    eye: glam::DVec3,
) -> ([f32; 4], [f32; 4]) {
    let speed = velocity.length();
    let dir = if speed > 0.0 {
        velocity / speed
    } else {
        glam::DVec2::ZERO
    };
    let along = eye.x * dir.x + eye.z * dir.y;
    let phase = |i, clock| crate::grass::gust_phase(i, along, clock, speed) as f32;
    (
        [dir.x as f32, dir.y as f32, speed as f32, 0.0],
        [
            phase(0, clock),
            phase(1, clock),
            phase(0, before),
            phase(1, before),
        ],
    )
}

/// The layout of the blades' draw by the rasteriser (`wgsl/grass_draw.wgsl`): the render
/// uniforms, and the blades as the scatter writes them.
pub(crate) fn draw_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    let vf = wgpu::ShaderStages::VERTEX_FRAGMENT;
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("relief:grass:draw-layout"),
        entries: &[
            super::uniform_entry::<super::RenderUniforms>(0, vf),
            wgpu::BindGroupLayoutEntry {
                binding: 1,
                visibility: wgpu::ShaderStages::VERTEX,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Storage { read_only: true },
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            },
        ],
    })
}

/// The module of the blades' draw by the rasteriser.
pub(crate) fn draw_module(device: &wgpu::Device) -> wgpu::ShaderModule {
    super::shader::module(
        device,
        "relief:grass:draw",
        &super::shader::source("grass_draw"),
    )
}

/// The blades' draw into `targets`: a strip of nine vertices an instance, depth-tested and
/// written.
pub(crate) fn draw_pipeline(
    device: &wgpu::Device,
    (layout, module): (&wgpu::BindGroupLayout, &wgpu::ShaderModule),
    targets: &super::Targets,
) -> wgpu::RenderPipeline {
    super::render_pipeline(
        device,
        (
            "relief:grass:draw",
            layout,
            module,
            ("blade_vs", "blade_fs"),
        ),
        targets,
        wgpu::PrimitiveTopology::TriangleStrip,
        &[],
        (true, wgpu::CompareFunction::Less),
    )
}

/// The draw's bind group: the render uniforms in `uniforms`, the blades in `blades`.
pub(crate) fn draw_group(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    uniforms: &wgpu::Buffer,
    blades: &wgpu::Buffer,
) -> wgpu::BindGroup {
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("relief:grass:draw-group"),
        layout,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: uniforms.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: blades.as_entire_binding(),
            },
        ],
    })
}

#[cfg(test)]
mod tests {
    #[test]
    fn the_twin_reads_the_shaders_constants() {
        let grass = crate::gpu::shader::file("grass").unwrap();
        let shade = crate::gpu::shader::file("shade").unwrap();
        for (text, line) in [
            (
                shade,
                format!("const SNOW_EDGE: f32 = {};", crate::grass::SNOW_EDGE),
            ),
            (
                shade,
                format!("const SNOW_JITTER: f32 = {};", crate::grass::SNOW_JITTER),
            ),
            (
                grass,
                format!("const BLADE_WIDTH: f32 = {};", crate::grass::BLADE_WIDTH),
            ),
            (
                grass,
                format!(
                    "const BEND_PER_SPEED: f32 = {};",
                    crate::grass::BEND_PER_SPEED
                ),
            ),
            (
                grass,
                format!("const MAX_BEND: f32 = {};", crate::grass::MAX_BEND),
            ),
            (grass, {
                let w = crate::grass::GUSTS.map(|(l, _, a)| format!("vec2<f32>({l:.1}, {a})"));
                format!("array<vec2<f32>, 2>({}, {})", w[0], w[1])
            }),
        ] {
            assert!(text.contains(&line), "{line}");
        }
    }
}
