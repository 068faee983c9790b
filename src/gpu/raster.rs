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
//! a 32-bit atomic on depth cannot carry. Where the device has a 64-bit atomic maximum
//! (`SHADER_INT64_ATOMIC_MIN_MAX`: native only, on GPUs whose Vulkan, DX12 or Metal driver
//! offers 64-bit buffer atomics; [`crate::gpu::request_device`] asks for it), each pixel keeps
//! its depth above its triangle's id in one atomic (`wgsl/raster_ids.wgsl`), and a dispatch a pixel sets that triangle up again and stores its
//! attributes: one raster. Elsewhere (the page's WebGPU) a second dispatch of the same
//! pipeline rasterises again and stores them where a triangle's depth is the pixel's nearest,
//! bit for bit (`wgsl/raster_depth.wgsl`; the same instructions compute it in both dispatches,
//! so the comparison is exact).
//!
//! A workgroup draws a block of 8x8 cells, a thread a cell, their 81 corners placed once. The
//! depth's raster runs in passes, nearest levels first (`PASS_LEVELS`). Between passes
//! `raster_hiz` keeps each 8x8-pixel tile's farthest depth drawn so far, and a later pass skips
//! a block whose corners' screen box covers no pixel centre, or lies on at most 16 tiles all
//! drawn strictly nearer than its nearest corner. A triangle's depth at a pixel blends its
//! corners' depths, held at the nearest corner's (rounding could take a long thin triangle's
//! blend nearer), so such a block cannot be nearest anywhere: the pixels are the same as with
//! every block drawn (tested byte for byte). From near the ground most of the distant mesh
//! lies behind nearer hills.
//!
//! A thread draws the triangles of its cell itself unless one's bounding box covers over 256
//! pixels: then it lists the triangle and its tiles of 16x16 pixels, and a second dispatch
//! (`raster_big`) draws the listed tiles, a workgroup each. Near the ground the nearest
//! triangles span much of the screen, and one thread looping over all their pixels held up the
//! whole pass.

use super::timing::{GpuTimer, Slot};
pub(crate) use crate::method::Raster;

/// Mirrors `RasterUniforms` in `wgsl/raster.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
struct RasterUniforms {
    size: [u32; 2],
    whole: u32,
    subs: u32,
    patch_cells: u32,
    sub_cells: u32,
    row_groups: u32,
    mode: u32,
    first_group: u32,
    end_group: u32,
    cull: u32,
    _pad: u32,
}

/// The attribute images the raster stores (the endless world's): slope in x and z,
/// colour channel and horizon, as the hardware raster's surface target holds them ...
pub(crate) const SURFACE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// ... and the valley depth (32-bit: WebGPU's storage textures have no 16-bit red format).
pub(crate) const VALLEY_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;
/// Per pixel: how far its point moved since the last frame, camera-relative metres, and 1 where
/// a blade of grass moved it (`resolve_blades`), for the temporal service.
pub(crate) const MOTION_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// The side of the square block of cells a workgroup of `raster_cells` draws, a thread a
/// cell (`raster.wgsl`'s `BLOCK`).
const BLOCK: u32 = 8;
/// The side of the tiles of pixels whose farthest depth `raster_hiz` keeps (`HIZ_TILE`).
const HIZ_TILE: u32 = 8;
/// Triangles the list of big ones holds (`raster.wgsl`'s `big`; 160 bytes each, 10 MiB): a
/// camera a few metres above the endless world's ground left some hundreds at 1080p; the
/// grass's blades within a few metres of the eye add some thousands (more at a higher
/// density). Past it a thread draws its triangle alone, as before the list (slow, not
/// wrong).
const BIG_TRIANGLES: u64 = 65_536;
/// The tiles of `HIZ_TILE` pixels square over a frame of `size`.
fn hiz_tiles(size: (u32, u32)) -> u64 {
    u64::from(size.0.div_ceil(HIZ_TILE)) * u64::from(size.1.div_ceil(HIZ_TILE))
}

/// Bytes of one entry of the list: three vertices of three `vec4`s, and the id, padded to 16.
const BIG_TRIANGLE_BYTES: u64 = 3 * 3 * 16 + 16;
/// Tiles of 16x16 pixels the big triangles' tile list holds (8 bytes each): over 30 times a
/// 1080p screen's.
const BIG_TILES: u64 = 262_144;
/// Bytes of `raster.wgsl`'s `big_count`: the triangles and the tiles listed, for each mode.
const BIG_COUNT_BYTES: u64 = 16;
/// The arguments of each mode's indirect dispatch of `raster_big` (`raster.wgsl`'s
/// `big_args`) as a frame starts: (0, 1, 1). `raster_cells` raises the workgroups to the tiles
/// listed, at most `BIG_GROUPS` (4096, in `raster.wgsl`), each then taking every 4096th tile;
/// a frame with no big triangle dispatches none.
const BIG_ARGS_CLEAR: [u32; 6] = [0, 1, 1, 0, 1, 1];
/// Most workgroups in one dimension of a dispatch (WebGPU's default limit).
const MAX_GROUPS: u32 = 65_535;
/// The side of `raster_resolve`'s and `raster_hiz`'s square workgroups.
const RESOLVE_SIDE: u32 = 8;
/// The raster's dispatches of cells: the depth's in [`PASSES`] passes, nearest levels first,
/// then, without ids, the attributes' in one.
const DISPATCHES: usize = PASSES + 1;
/// Passes of the depth's raster: the patches of the levels within [`PASS_LEVELS`] of the finest
/// drawn, one pass each, then the rest ([`Patches::passes`]); each after the first skips the
/// blocks of cells wholly behind what the passes before it drew.
pub(crate) const PASSES: usize = 4;
/// The levels the depth passes but the last end before, counted from the finest drawn.
const PASS_LEVELS: [u32; PASSES - 1] = [2, 4, 7];

/// Where a visibility-buffer id splits: the layer (0 the terrain) in the bits from here up,
/// the layer's own primitive below (a terrain triangle: its cell's number times 4). As
/// `LAYER_SHIFT` in `wgsl/raster.wgsl`.
pub(crate) const LAYER_SHIFT: u32 = 28;

/// The device features the raster with ids needs (64-bit integers and their atomic maximum).
pub const ID_FEATURES: wgpu::Features =
    wgpu::Features::SHADER_INT64.union(wgpu::Features::SHADER_INT64_ATOMIC_MIN_MAX);

/// The mesh the raster draws: the world's bind group (its uniforms and level textures, group
/// 0), how many patch instances of each kind (whole patches first, finest level first; the
/// instances are bound by [`ComputeRaster::bind`]), the cells per side of a whole patch and of
/// a sub-patch, and the whole patches drawn by the end of each depth pass but the last; and the
/// grass's blades drawn with it, where the raster keeps ids and the method draws them.
pub(crate) struct Patches<'a> {
    pub group: &'a wgpu::BindGroup,
    pub counts: [u32; 2],
    pub cells: [u32; 2],
    pub passes: [u32; PASSES - 1],
    pub blades: Option<Blades<'a>>,
    /// The props the visibility method marches after the raster, where it draws them.
    pub props: Option<&'a super::props::PropsPass>,
}

/// The grass's blades for the raster with ids (`wgsl/raster_blades.wgsl`): the scatter's
/// blades, counts and list of their triangles, and the arguments of the indirect dispatch of a
/// thread a triangle, at `args_offset` in `args`.
#[derive(Clone, Copy)]
pub(crate) struct Blades<'a> {
    pub blades: &'a wgpu::Buffer,
    pub counts: &'a wgpu::Buffer,
    pub triangles: &'a wgpu::Buffer,
    pub args: &'a wgpu::Buffer,
    pub args_offset: u64,
}

/// The whole patches of `levels` (each patch's level, finest first) drawn by the end of each
/// depth pass but the last ([`PASS_LEVELS`]).
pub(crate) fn pass_ends(levels: impl Iterator<Item = u32> + Clone) -> [u32; PASSES - 1] {
    let finest = levels.clone().min().unwrap_or(0);
    PASS_LEVELS.map(|within| levels.clone().filter(|&l| l < finest + within).count() as u32)
}

/// The bindings of group 1 for `raster_cells`, `raster_big` (without `big_args`, which its
/// dispatch reads), `raster_hiz` and `raster_resolve`. After the raster with ids the depth
/// buffer is read at binding 9, not as the raster's atomics at 2.
fn bindings(ids: bool) -> [&'static [u32]; 4] {
    [
        &[0, 1, 2, 3, 4, 5, 6, 7, 8, 10],
        &[0, 1, 2, 3, 4, 5, 6, 7],
        if ids { &[0, 9, 10] } else { &[0, 2, 10] },
        &[0, 1, 3, 4, 9, 11],
    ]
}

/// A storage buffer the raster's passes write, cleared by copies.
fn storage_buffer(device: &wgpu::Device, label: &str, size: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

/// The compute raster's pipelines, uniforms and buffers (see the module docs).
pub(crate) struct ComputeRaster {
    pipeline: wgpu::ComputePipeline,
    /// Draws the triangles `pipeline` left as big, a workgroup to a tile of pixels.
    big_pipeline: wgpu::ComputePipeline,
    /// Keeps the farthest depth of each tile of pixels drawn so far (`raster_hiz`).
    hiz_pipeline: wgpu::ComputePipeline,
    /// `raster_resolve` (the raster with ids only).
    resolve: Option<wgpu::ComputePipeline>,
    /// With ids: the grass's blades' raster (`raster_blades`) and resolve (`resolve_blades`),
    /// the layout of their blades (group 2), and its bind group for the last blades bound.
    blade_pipelines: Option<[wgpu::ComputePipeline; 2]>,
    blades_layout: wgpu::BindGroupLayout,
    blades_group: Option<(wgpu::Buffer, wgpu::BindGroup)>,
    /// The big triangles' list, their tiles', the counts of both (one a dispatch mode,
    /// cleared every frame), and `raster_big`'s indirect arguments.
    big: wgpu::Buffer,
    big_tiles: wgpu::Buffer,
    big_count: wgpu::Buffer,
    big_args: wgpu::Buffer,
    /// [`BIG_ARGS_CLEAR`], copied into `big_args` before each raster.
    big_args_clear: wgpu::Buffer,
    /// The bind group layouts of `raster_cells`, `raster_big` (without `big_args`, which its
    /// dispatch reads), `raster_hiz` and `raster_resolve`.
    layouts: [wgpu::BindGroupLayout; 4],
    /// Whether each pixel's attributes are stored (the endless world's).
    attributes: bool,
    /// Whether the depth buffer keeps each pixel's triangle beside its depth (64-bit, where the
    /// device allows it and there are attributes): `raster_resolve` then stores the attributes,
    /// where otherwise a second raster does.
    ids: bool,
    /// Each dispatch of cells' uniforms ([`DISPATCHES`]), a slot of `uniform_stride` bytes
    /// each, bound with a dynamic offset: one pipeline for all, so every dispatch computes a
    /// pixel's depth with the same instructions.
    uniforms: wgpu::Buffer,
    uniform_stride: u32,
    /// Per pixel, row by row: the nearest depth's complemented bits (with ids: above the
    /// triangle's id, 8 bytes a pixel), 0 where nothing is drawn; and per tile of pixels the
    /// farthest ([`HIZ_TILE`]).
    depth: Option<(u32, u32, wgpu::Buffer, wgpu::Buffer)>,
    /// The bind groups of the four layouts ([`ComputeRaster::bind`]).
    groups: Option<[wgpu::BindGroup; 4]>,
    /// Whether a pass skips the blocks the passes before it hide (true but in the test that
    /// the skipping changes nothing).
    pub(crate) skip_hidden: bool,
}

impl ComputeRaster {
    /// The pipelines for a world whose bind group 0 has `world_layout` (visible to compute);
    /// `attributes`: the endless world's, kept with ids where `device` has [`ID_FEATURES`],
    /// else written by a second raster.
    pub(crate) fn new(
        device: &wgpu::Device,
        world_layout: &wgpu::BindGroupLayout,
        attributes: bool,
    ) -> Self {
        use super::shader as s;
        let ids = attributes && device.features().contains(ID_FEATURES);
        let keep = if ids { "raster_ids" } else { "raster_depth" };
        let module = s::module(device, "relief:raster:shader", &s::source(keep));
        let storage = super::storage_buffer_entry;
        let entry = |binding: u32| match binding {
            0 => wgpu::BindGroupLayoutEntry {
                binding,
                visibility: wgpu::ShaderStages::COMPUTE,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: true,
                    min_binding_size: wgpu::BufferSize::new(
                        std::mem::size_of::<RasterUniforms>() as u64
                    ),
                },
                count: None,
            },
            1 | 9 => storage(binding, true),
            3 => super::storage_entry(3, SURFACE_FORMAT),
            4 => super::storage_entry(4, VALLEY_FORMAT),
            11 => super::storage_entry(11, MOTION_FORMAT),
            _ => storage(binding, false),
        };
        let layouts = bindings(ids).map(|bindings| {
            device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("relief:raster:layout"),
                entries: &bindings.iter().map(|&b| entry(b)).collect::<Vec<_>>(),
            })
        });
        // A pipeline of `module` with the world's group 0 and `groups` after it.
        let pipeline_with = |label: &str, entry_point: &str, groups: &[&wgpu::BindGroupLayout]| {
            let mut layouts = vec![Some(world_layout)];
            layouts.extend(groups.iter().map(|&g| Some(g)));
            let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("relief:raster:pipeline-layout"),
                bind_group_layouts: &layouts,
                immediate_size: 0,
            });
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(label),
                layout: Some(&pipeline_layout),
                module: &module,
                entry_point: Some(entry_point),
                compilation_options: Default::default(),
                cache: None,
            })
        };
        let pipeline = |label: &str, entry_point: &str, layout: &wgpu::BindGroupLayout| {
            pipeline_with(label, entry_point, &[layout])
        };
        let blades_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("relief:raster:blades-layout"),
            entries: &[storage(0, true), storage(1, true), storage(2, true)],
        });
        let blade_pipeline = |label: &str, entry_point: &str, layout: &wgpu::BindGroupLayout| {
            pipeline_with(label, entry_point, &[layout, &blades_layout])
        };
        let blade_pipelines = ids.then(|| {
            [
                blade_pipeline("relief:raster:blades", "raster_blades", &layouts[0]),
                blade_pipeline(
                    "relief:raster:resolve-blades",
                    "resolve_blades",
                    &layouts[3],
                ),
            ]
        });
        let buffer = |label, size| storage_buffer(device, label, size);
        let uniform_stride = (std::mem::size_of::<RasterUniforms>() as u32)
            .next_multiple_of(device.limits().min_uniform_buffer_offset_alignment);
        Self {
            pipeline: pipeline("relief:raster:cells", "raster_cells", &layouts[0]),
            big_pipeline: pipeline("relief:raster:big", "raster_big", &layouts[1]),
            hiz_pipeline: pipeline("relief:raster:hiz", "raster_hiz", &layouts[2]),
            resolve: ids.then(|| pipeline("relief:raster:resolve", "raster_resolve", &layouts[3])),
            big: buffer("relief:raster:big", BIG_TRIANGLES * BIG_TRIANGLE_BYTES),
            big_tiles: buffer("relief:raster:big-tiles", BIG_TILES * 8),
            big_count: buffer("relief:raster:big-count", BIG_COUNT_BYTES),
            big_args: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("relief:raster:big-args"),
                size: std::mem::size_of_val(&BIG_ARGS_CLEAR) as u64,
                usage: wgpu::BufferUsages::STORAGE
                    | wgpu::BufferUsages::INDIRECT
                    | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            big_args_clear: wgpu::util::DeviceExt::create_buffer_init(
                device,
                &wgpu::util::BufferInitDescriptor {
                    label: Some("relief:raster:big-args-clear"),
                    contents: bytemuck::cast_slice(&BIG_ARGS_CLEAR),
                    usage: wgpu::BufferUsages::COPY_SRC,
                },
            ),
            layouts,
            blade_pipelines,
            blades_layout,
            blades_group: None,
            attributes,
            ids,
            uniforms: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("relief:raster:uniforms"),
                size: u64::from(uniform_stride) * DISPATCHES as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            uniform_stride,
            depth: None,
            groups: None,
            skip_hidden: true,
        }
    }

    /// The depth buffer for an image of `size`, made again when the size changes (the caller
    /// binds it again, [`ComputeRaster::bind`]).
    pub(crate) fn depth(&mut self, device: &wgpu::Device, size: (u32, u32)) -> &wgpu::Buffer {
        if !matches!(&self.depth, Some((w, h, _, _)) if (*w, *h) == size) {
            let pixels = u64::from(size.0) * u64::from(size.1);
            let buffer = |label, size| storage_buffer(device, label, size);
            self.depth = Some((
                size.0,
                size.1,
                buffer(
                    "relief:raster:depth",
                    pixels * 4 * u64::from(self.depth_stride()),
                ),
                buffer("relief:raster:hiz", hiz_tiles(size) * 4),
            ));
            self.groups = None;
        }
        &self.depth.as_ref().expect("made above").2
    }

    /// GPU memory of the raster's buffers for a frame of `size`, bytes: the depth buffer, the
    /// tiles' farthest depth, the big triangles' lists and the uniforms.
    pub(crate) fn bytes(&self, size: (u32, u32)) -> u64 {
        let pixels = u64::from(size.0) * u64::from(size.1);
        let lists = BIG_TRIANGLES * BIG_TRIANGLE_BYTES + BIG_TILES * 8 + BIG_COUNT_BYTES;
        let args = 2 * std::mem::size_of_val(&BIG_ARGS_CLEAR) as u64;
        let uniforms = u64::from(self.uniform_stride) * DISPATCHES as u64;
        pixels * 4 * u64::from(self.depth_stride()) + hiz_tiles(size) * 4 + lists + args + uniforms
    }

    /// Whether it draws the grass's blades with the terrain (the raster with ids).
    pub(crate) fn draws_blades(&self) -> bool {
        self.blade_pipelines.is_some()
    }

    /// Whether the next [`ComputeRaster::encode`] draws blades (bound by
    /// [`ComputeRaster::bind_blades`]), and so writes their motion.
    pub(crate) fn blades_bound(&self) -> bool {
        self.blades_group.is_some()
    }

    /// Binds the grass's blades for the next [`ComputeRaster::encode`] (none: the bind group
    /// is dropped).
    pub(crate) fn bind_blades(&mut self, device: &wgpu::Device, blades: Option<Blades<'_>>) {
        let Some(b) = blades.filter(|_| self.draws_blades()) else {
            self.blades_group = None;
            return;
        };
        if self
            .blades_group
            .as_ref()
            .is_some_and(|(k, _)| k == b.blades)
        {
            return;
        }
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("relief:raster:blades-group"),
            layout: &self.blades_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: b.blades.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: b.counts.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: b.triangles.as_entire_binding(),
                },
            ],
        });
        self.blades_group = Some((b.blades.clone(), group));
    }

    /// 32-bit words a pixel of the depth buffer: 2 with ids (the depth's the second), else 1.
    pub(crate) fn depth_stride(&self) -> u32 {
        if self.ids {
            2
        } else {
            1
        }
    }

    /// Binds the world's patch `instances`, the depth buffer of `size` and the attribute
    /// images `surface` ([`SURFACE_FORMAT`]), `valley` ([`VALLEY_FORMAT`]) and `motion`
    /// ([`MOTION_FORMAT`], the blades' motion), 1x1 stand-ins where there are none, each made
    /// with storage use.
    pub(crate) fn bind(
        &mut self,
        device: &wgpu::Device,
        (instances, size): (&wgpu::Buffer, (u32, u32)),
        (surface, valley, motion): (&wgpu::TextureView, &wgpu::TextureView, &wgpu::TextureView),
    ) {
        self.depth(device, size);
        let Some((_, _, depth, hiz)) = &self.depth else {
            return;
        };
        let resource = |binding: u32| match binding {
            0 => wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                buffer: &self.uniforms,
                offset: 0,
                size: wgpu::BufferSize::new(std::mem::size_of::<RasterUniforms>() as u64),
            }),
            1 => instances.as_entire_binding(),
            2 | 9 => depth.as_entire_binding(),
            3 => wgpu::BindingResource::TextureView(surface),
            4 => wgpu::BindingResource::TextureView(valley),
            11 => wgpu::BindingResource::TextureView(motion),
            5 => self.big.as_entire_binding(),
            6 => self.big_count.as_entire_binding(),
            7 => self.big_tiles.as_entire_binding(),
            8 => self.big_args.as_entire_binding(),
            _ => hiz.as_entire_binding(),
        };
        let mut k = 0;
        self.groups = Some(bindings(self.ids).map(|bindings| {
            let layout = &self.layouts[k];
            k += 1;
            let entries: Vec<_> = bindings
                .iter()
                .map(|&binding| wgpu::BindGroupEntry {
                    binding,
                    resource: resource(binding),
                })
                .collect();
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("relief:raster:group"),
                layout,
                entries: &entries,
            })
        }));
    }

    /// Records the raster of `patches` into an image of `size` (bound by
    /// [`ComputeRaster::bind`] at that size): clears the depth buffer, then one compute pass
    /// (timed as [`Slot::Raster`]): the depth's raster in [`PASSES`] passes, nearest levels
    /// first, each after the first skipping what the ones before it hide; then, for the endless
    /// world, either a dispatch a pixel that stores the kept triangles' attributes (with ids) or
    /// a second raster that stores them. The grass's blades bound ([`ComputeRaster::bind_blades`])
    /// follow in a compute pass of their own (timed as [`Slot::Blades`]): their raster into the
    /// same depth with ids, their big triangles, and their resolve (over the terrain's
    /// attributes where a blade is nearer).
    pub(crate) fn encode(
        &self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        (size, patches): ((u32, u32), &Patches<'_>),
        timer: Option<&GpuTimer>,
    ) {
        let (Some((w, h, depth, _)), Some(groups)) = (&self.depth, &self.groups) else {
            return;
        };
        debug_assert_eq!((*w, *h), size, "bound at another size");
        let [whole, subs] = patches.counts;
        let [patch_cells, sub_cells] = patches.cells;
        let cells = u64::from(whole) * u64::from(patch_cells).pow(2)
            + u64::from(subs) * u64::from(sub_cells).pow(2);
        // A triangle's id is its cell's number times 4, below the layer's bits.
        debug_assert!(
            cells < 1 << (LAYER_SHIFT - 2),
            "{cells} cells: past the ids' range"
        );
        // A workgroup a block of cells, blocks over a patch's edge included; the depth passes
        // split the whole patches at `patches.passes` (the last takes the sub-patches too).
        let blocks = |side: u32| side.div_ceil(BLOCK).pow(2);
        let whole_blocks = blocks(patch_cells);
        let total = whole * whole_blocks + subs * blocks(sub_cells);
        let mut ends = [total; PASSES];
        for (end, &patches_end) in ends.iter_mut().zip(&patches.passes) {
            *end = patches_end.min(whole) * whole_blocks;
        }
        // (mode, first group, end group, cull) of each dispatch of cells.
        let mut dispatches = Vec::with_capacity(DISPATCHES);
        let mut first = 0;
        for (pass, &end) in ends.iter().enumerate() {
            dispatches.push((0, first, end.max(first), pass > 0 && self.skip_hidden));
            first = end.max(first);
        }
        // The attributes' raster only where there are attributes and no resolve of the ids:
        // every block, each skipped where the whole depth hides it.
        if self.attributes && !self.ids {
            dispatches.push((1, 0, total, self.skip_hidden));
        }
        // With ids the last slot is the blades' (their big triangles listed as mode 1's, drawn
        // after the terrain's).
        let blades = patches
            .blades
            .zip(self.blade_pipelines.as_ref())
            .zip(self.blades_group.as_ref());
        let blades_slot = dispatches.len();
        debug_assert!(blades.is_none() || blades_slot < DISPATCHES);
        let stride = self.uniform_stride as usize;
        let mut slots = vec![0u8; stride * DISPATCHES];
        let split = |count: u32| {
            let x = count.clamp(1, MAX_GROUPS);
            (x, count.div_ceil(x))
        };
        for (k, &(mode, first, end, cull)) in dispatches.iter().enumerate() {
            let u = RasterUniforms {
                size: [size.0, size.1],
                whole,
                subs,
                patch_cells,
                sub_cells,
                row_groups: split(end - first).0,
                mode,
                first_group: first,
                end_group: end,
                cull: u32::from(cull),
                _pad: 0,
            };
            slots[k * stride..][..std::mem::size_of::<RasterUniforms>()]
                .copy_from_slice(bytemuck::bytes_of(&u));
        }
        if blades.is_some() {
            let u = RasterUniforms {
                size: [size.0, size.1],
                mode: 1,
                ..Default::default()
            };
            slots[blades_slot * stride..][..std::mem::size_of::<RasterUniforms>()]
                .copy_from_slice(bytemuck::bytes_of(&u));
        }
        queue.write_buffer(&self.uniforms, 0, &slots);
        encoder.clear_buffer(depth, 0, None);
        // In the encoder's order, as the depth is cleared: each raster recorded starts from
        // no big triangles.
        encoder.clear_buffer(&self.big_count, 0, None);
        encoder.copy_buffer_to_buffer(&self.big_args_clear, 0, &self.big_args, 0, None);
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("relief:raster:pass"),
            timestamp_writes: timer.map(|t| t.compute_writes(Slot::Raster)),
        });
        if cells == 0 {
            return;
        }
        let [cells_group, big_group, hiz_group, resolve_group] = groups;
        pass.set_bind_group(0, patches.group, &[]);
        let tiles = (size.0.div_ceil(HIZ_TILE), size.1.div_ceil(HIZ_TILE));
        for (k, &(mode, first, end, cull)) in dispatches.iter().enumerate() {
            let offset = [(k * stride) as u32];
            if cull && end > first {
                // The farthest depth of each tile drawn so far, for this dispatch's test.
                pass.set_pipeline(&self.hiz_pipeline);
                pass.set_bind_group(1, hiz_group, &[0]);
                pass.dispatch_workgroups(
                    tiles.0.div_ceil(RESOLVE_SIDE),
                    tiles.1.div_ceil(RESOLVE_SIDE),
                    1,
                );
            }
            if end > first {
                let (x, y) = split(end - first);
                pass.set_pipeline(&self.pipeline);
                pass.set_bind_group(1, cells_group, &offset);
                pass.dispatch_workgroups(x, y, 1);
            }
            // Each mode's big triangles after its last dispatch of cells.
            if dispatches.get(k + 1).is_none_or(|next| next.0 != mode) {
                pass.set_pipeline(&self.big_pipeline);
                pass.set_bind_group(1, big_group, &offset);
                pass.dispatch_workgroups_indirect(&self.big_args, 12 * u64::from(mode));
            }
        }
        let resolve_groups = (size.0.div_ceil(RESOLVE_SIDE), size.1.div_ceil(RESOLVE_SIDE));
        if let Some(resolve) = &self.resolve {
            pass.set_pipeline(resolve);
            pass.set_bind_group(1, resolve_group, &[0]);
            pass.dispatch_workgroups(resolve_groups.0, resolve_groups.1, 1);
        }
        drop(pass);
        if let Some(((b, [raster_blades, resolve_blades]), (_, blades_group))) = blades {
            // The blades after the whole terrain, nearest kept; their big triangles after; then
            // their attributes where one is nearest.
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("relief:raster:blades-pass"),
                timestamp_writes: timer.map(|t| t.compute_writes(Slot::Blades)),
            });
            let offset = [(blades_slot * stride) as u32];
            pass.set_bind_group(0, patches.group, &[]);
            pass.set_bind_group(2, blades_group, &[]);
            pass.set_pipeline(raster_blades);
            pass.set_bind_group(1, cells_group, &offset);
            pass.dispatch_workgroups_indirect(b.args, b.args_offset);
            pass.set_pipeline(&self.big_pipeline);
            pass.set_bind_group(1, big_group, &offset);
            pass.dispatch_workgroups_indirect(&self.big_args, 12);
            pass.set_pipeline(resolve_blades);
            pass.set_bind_group(1, resolve_group, &[0]);
            pass.dispatch_workgroups(resolve_groups.0, resolve_groups.1, 1);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_uniforms_have_the_wgsl_layout() {
        // wgsl/raster.wgsl's RasterUniforms: a vec2<u32> and ten u32, 48 bytes.
        assert_eq!(std::mem::size_of::<RasterUniforms>(), 48);
        assert_eq!(std::mem::offset_of!(RasterUniforms, cull), 40);
        assert_eq!(std::mem::offset_of!(RasterUniforms, whole), 8);
        assert_eq!(std::mem::offset_of!(RasterUniforms, row_groups), 24);
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
    fn the_big_triangles_constants_match_the_wgsl() {
        let wgsl = super::super::shader::file("raster").unwrap();
        assert!(wgsl.contains(&format!("const BLOCK: u32 = {BLOCK}u;")));
        assert!(wgsl.contains(&format!("const HIZ_TILE: u32 = {HIZ_TILE}u;")));
        assert!(wgsl.contains(&format!("const LAYER_SHIFT: u32 = {LAYER_SHIFT}u;")));
        let mask = (1u32 << LAYER_SHIFT) - 1;
        assert!(wgsl.contains(&format!("const PRIMITIVE_MASK: u32 = {mask:#010x}u;")));
        assert!(wgsl.contains(&format!(
            "@workgroup_size({RESOLVE_SIDE}, {RESOLVE_SIDE})\nfn raster_hiz"
        )));
        assert!(super::super::shader::file("raster_ids")
            .unwrap()
            .contains(&format!("@workgroup_size({RESOLVE_SIDE}, {RESOLVE_SIDE})")));
        assert!(wgsl.contains(&format!(
            "big_count: array<atomic<u32>, {}>",
            BIG_COUNT_BYTES / 4
        )));
        assert!(wgsl.contains(&format!(
            "big_args: array<atomic<u32>, {}>",
            BIG_ARGS_CLEAR.len()
        )));
        // Each mode's indirect arguments: no workgroups, then 1, 1.
        for mode in 0..2 {
            assert_eq!(BIG_ARGS_CLEAR[3 * mode..3 * mode + 3], [0, 1, 1]);
        }
    }

    #[test]
    fn the_depth_passes_split_the_patches_by_level() {
        // Finest first: two levels, then two, then three, then the rest.
        let levels = [3, 3, 4, 4, 4, 5, 6, 7, 7, 8, 9, 10];
        assert_eq!(pass_ends(levels.iter().copied()), [5, 7, 11]);
        assert_eq!(pass_ends([0u32; 4].iter().copied()), [4, 4, 4]);
        assert_eq!(pass_ends(std::iter::empty()), [0, 0, 0]);
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
