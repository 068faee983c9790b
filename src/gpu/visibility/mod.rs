//! The method `visibility`: the mesh rasterised into relief's own 4x MSAA targets (depth, and
//! for the endless world each sample's slope, colour channel, horizon and valley depth), every
//! sample shaded in one compute pass (`wgsl/visibility.wgsl`) with the shading every method
//! shares (the sky too, where no terrain covers a sample), the samples of a pixel averaged in
//! linear light, and the result composited, colour and depth, into the host's render pass in
//! one full-screen draw.
//!
//! Why: on a compute chip the mesh's forward shading in the fragment shader is what a frame
//! costs (the same arithmetic runs some 30 times slower in a fragment shader than in compute on
//! an H100), and shading once a pixel leaves detail finer than a pixel aliased. Here the raster
//! pass does no shading at all and the compute pass shades four samples a pixel.
//!
//! The hybrid method ([`crate::Method::Hybrid`], the endless world) is the same passes with
//! the levels' vertices raised by a bound on how far the continuous surface rises above them
//! ([`crate::clipmap::level_raise`]) and another compute pass (`wgsl/hybrid.wgsl`): from where
//! each sample's ray meets the raised mesh, a short conservative march finds the continuous
//! surface, which is shaded and whose depth is composited.
//!
//! The middleware contract holds: [`crate::World::prepare`] records the raster and compute
//! passes into the host's encoder (before the host's render pass), and
//! [`crate::World::render`] draws the composite into the host's pass, writing depth so host
//! geometry and terrain occlude each other.

mod clouds;
mod present;
mod props;
mod targets;

pub(crate) use self::clouds::CloudFrame;

pub(crate) use self::props::hit_entry as props_hit_entry;
use self::targets::*;
pub(crate) use self::targets::{clip_w_from_depth, composite_group, composite_pipeline};
use super::raster::{self, ComputeRaster, Patches, Raster};
use super::render::RenderUniforms;
use super::temporal::{Resolve, TemporalUniforms};
use super::timing::{GpuTimer, Slot};
use super::uniforms::WorldUniforms;
use super::world_rays::WorldRayUniforms;
use super::Targets;

/// Samples a pixel of the raster pass, each shaded, by default: the standard 4x MSAA pattern.
/// One sample a pixel ([`crate::MethodConfig::samples`]) rasterises a quarter of the
/// samples and draws edges without anti-aliasing.
pub const SAMPLES: u32 = 4;
/// Depth of the raster pass.
const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// Per sample: slope in x and z, colour channel, horizon (the endless world).
const SURFACE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// Per sample: valley depth in metres (the endless world).
const VALLEY_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R16Float;
/// The shaded image: premultiplied linear colour and coverage.
const SHADED_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
/// The nearest covered sample's depth per pixel (1: none).
const SHADED_DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;

/// Mirrors `VisUniforms` in `wgsl/visibility.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct VisUniforms {
    /// Inverse of the camera-relative projection times view.
    pub inv: [[f32; 4]; 4],
    /// Row 3 of the projection times view (clip w).
    pub w_row: [f32; 4],
    /// Clip w from depth d: `depth[1] / (d + depth[0])`.
    pub depth: [f32; 4],
    /// Image size in pixels.
    pub size: [u32; 2],
    /// 1 where the sky fills uncovered samples.
    pub sky: u32,
    /// 1 for the endless world's attributes, 0 for the tile's textures.
    pub world: u32,
    /// 1 where the host's target is not sRGB and the composite encodes.
    pub encode_srgb: u32,
    /// 32-bit words a pixel of the compute raster's depth buffer (the depth's the last): 2
    /// where it keeps each pixel's triangle, else 1.
    pub depth_stride: u32,
    /// 1 where the props' march left each pixel's prop (`prop_hit`) for the shading.
    pub props: u32,
    /// Padding.
    pub _pad: u32,
}

impl VisUniforms {
    /// The uniforms for a camera-relative perspective `matrix` (the eye at the origin) and an
    /// image of `size`.
    pub fn new(matrix: glam::Mat4, size: (u32, u32), sky: bool, world: bool, encode: bool) -> Self {
        let m = matrix.as_dmat4();
        let row3 = m.row(3);
        let depth = clip_w_from_depth(matrix);
        Self {
            inv: m.inverse().as_mat4().to_cols_array_2d(),
            w_row: row3.as_vec4().to_array(),
            depth: [depth[0], depth[1], 0.0, 0.0],
            size: [size.0.max(1), size.1.max(1)],
            sky: u32::from(sky),
            world: u32::from(world),
            encode_srgb: u32::from(encode),
            depth_stride: 1,
            props: 0,
            _pad: 0,
        }
    }
}

/// What the compute pass reads of the world beside its own images.
pub(crate) struct WorldBindings<'a> {
    pub render: &'a wgpu::Buffer,
    pub world: &'a wgpu::Buffer,
    pub tile_terrain: &'a wgpu::TextureView,
    pub tile_normals: &'a wgpu::TextureView,
    pub tile_sampler: &'a wgpu::Sampler,
    /// The props' shade map (`wgsl/props_map.wgsl`).
    pub props_map: &'a crate::gpu::props_map::PropsMap,
    /// The light shafts' shadow-height map (`wgsl/terrain_air_map.wgsl`).
    pub air_shadow: &'a crate::gpu::air_shadow::AirShadow,
    /// The world's patch instances (the compute raster reads them).
    pub instances: &'a wgpu::Buffer,
}

/// The targets of one image size.
struct Images {
    size: (u32, u32),
    depth: wgpu::TextureView,
    /// Where the props' march leaves each pixel's prop (1x1 without props).
    prop_hit: wgpu::TextureView,
    #[cfg_attr(
        target_arch = "wasm32",
        allow(dead_code, reason = "read back natively")
    )]
    prop_hit_texture: wgpu::Texture,
    surface: wgpu::TextureView,
    valley: wgpu::TextureView,
    compute_group: wgpu::BindGroup,
    /// The composite's bind group for each image it may show ([`Images::shown`]).
    composite_groups: Vec<wgpu::BindGroup>,
    /// The frame as the target's bytes, rows padded for the copy, and its bind group for each
    /// image shown ([`Visibility::present`]); `None` where the buffer would pass the device's
    /// limits.
    presented: Option<(wgpu::Buffer, Vec<wgpu::BindGroup>)>,
    /// The images a frame may show: the shaded one, then the temporal service's two
    /// histories where it is on.
    shown: Vec<wgpu::TextureView>,
}

/// The visibility method's pipelines and targets for one world (see the module docs).
pub struct Visibility {
    world: bool,
    samples: u32,
    /// The hybrid method: the compute pass refines each sample to the continuous surface.
    hybrid: bool,
    /// Built with the clouds (`shader::source_for`), and their image's passes.
    clouds: Option<clouds::Clouds>,
    /// The raster pass in compute ([`Raster::Compute`]), or `None` for the GPU's rasteriser.
    compute_raster: Option<ComputeRaster>,
    /// The hybrid's ray uniforms (the continuous surface, the eye, the drawn region).
    ray_uniforms: Option<wgpu::Buffer>,
    raster: wgpu::RenderPipeline,
    compute: wgpu::ComputePipeline,
    compute_layout: wgpu::BindGroupLayout,
    /// The composite blending by coverage (no sky), and opaque (the sky fills every pixel, so
    /// nothing is blended; on the H100 the two measured the same).
    composite: [wgpu::RenderPipeline; 2],
    composite_layout: wgpu::BindGroupLayout,
    /// The frame packed for an RGBA8 and a BGRA8 target ([`Visibility::present`]).
    present: [wgpu::ComputePipeline; 2],
    present_layout: wgpu::BindGroupLayout,
    /// The frame stored straight into a target that takes storage writes, and its layout;
    /// the device makes that target's bind group when it is presented to.
    store: wgpu::ComputePipeline,
    store_layout: wgpu::BindGroupLayout,
    device: wgpu::Device,
    /// Whether the last encoded frame had the sky (every pixel opaque).
    opaque: bool,
    uniforms: wgpu::Buffer,
    images: Option<Images>,
    encode_srgb: bool,
    /// The temporal service's resolve, where it is on.
    resolve: Option<Resolve>,
    /// Which of [`Images::shown`] the last frame shows.
    shown: usize,
    /// Clip w from depth (`VisUniforms::depth`) of the last frame.
    depth_w: [f32; 2],
    /// Whether the compute raster's blades write their motion for the temporal service (the
    /// world has grass): its image is made only then.
    blade_motion: bool,
    /// Whether the frame has props, which the march leaves in the props' image for the
    /// shading (where the compute raster draws): the image is made only then.
    props: bool,
}

impl Visibility {
    /// The pipelines for a world drawn by `module` (`wgsl/world.wgsl` composed) with the
    /// bind group `layout`, compositing into the host's `targets`. `world`: the endless world's
    /// attributes; otherwise the tile, shaded from its textures. `samples`: 1 or [`SAMPLES`] a
    /// pixel. `hybrid`: the hybrid method's refinement (the endless world's). `raster`: where
    /// the raster pass runs (the caller has checked [`Raster::refusal`]). `clouds`: with the
    /// clouds' march (without it, what no clouds look like, built in a fraction of the time).
    pub(crate) fn new(
        device: &wgpu::Device,
        (module, layout): (&wgpu::ShaderModule, &wgpu::BindGroupLayout),
        targets: &Targets,
        (world, samples, hybrid, raster, clouds): (bool, u32, bool, Raster, bool),
    ) -> Self {
        let compute_raster =
            (raster == Raster::Compute).then(|| ComputeRaster::new(device, layout, world));
        let raster_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("relief:visibility:raster-layout"),
            bind_group_layouts: &[Some(layout)],
            immediate_size: 0,
        });
        let attributes = [Some(SURFACE_FORMAT.into()), Some(VALLEY_FORMAT.into())];
        let raster = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("relief:visibility:raster"),
            layout: Some(&raster_layout),
            vertex: wgpu::VertexState {
                module,
                entry_point: Some(if world { "vs_samples" } else { "vs_main" }),
                compilation_options: Default::default(),
                buffers: &[Some(wgpu::VertexBufferLayout {
                    array_stride: std::mem::size_of::<crate::clipmap::Patch>() as u64,
                    step_mode: wgpu::VertexStepMode::Instance,
                    attributes: &wgpu::vertex_attr_array![0 => Uint32x4],
                })],
            },
            primitive: wgpu::PrimitiveState {
                cull_mode: None,
                ..Default::default()
            },
            depth_stencil: Some(wgpu::DepthStencilState {
                format: DEPTH_FORMAT,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Less),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: wgpu::MultisampleState {
                count: samples,
                ..Default::default()
            },
            // The tile's raster pass writes depth alone: its shading reads its textures.
            fragment: world.then(|| wgpu::FragmentState {
                module,
                entry_point: Some("fs_attributes"),
                compilation_options: Default::default(),
                targets: &attributes,
            }),
            multiview_mask: None,
            cache: None,
        });

        use super::shader as s;
        let code = [s::CloudCode::Without, s::CloudCode::Image][usize::from(clouds)];
        let source = |name| s::source_for(name, code);
        let vis_module = s::module(device, "relief:visibility:shader", &source("visibility"));
        let clouds = clouds.then(|| clouds::Clouds::new(device, &vis_module));
        // The hybrid's compute pass: a module of its own, with only what it needs.
        let hybrid_module =
            hybrid.then(|| s::module(device, "relief:hybrid:shader", &source("hybrid")));
        let c = wgpu::ShaderStages::COMPUTE;
        let float = wgpu::TextureSampleType::Float { filterable: false };
        let ms = samples > 1;
        let [depth_at, surface_at, valley_at] = target_bindings(samples);
        let mut entries = vec![
            super::uniform_entry::<RenderUniforms>(0, c),
            super::uniform_entry::<WorldUniforms>(1, c),
            super::texture_entry(4, c, false),
            super::texture_entry(5, c, true),
            wgpu::BindGroupLayoutEntry {
                binding: 6,
                visibility: c,
                ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                count: None,
            },
            sampled_entry(depth_at, wgpu::TextureSampleType::Depth, ms),
            sampled_entry(surface_at, float, ms),
            sampled_entry(valley_at, float, ms),
            super::storage_entry(10, SHADED_FORMAT),
            super::storage_entry(11, SHADED_DEPTH_FORMAT),
            super::uniform_entry::<VisUniforms>(12, c),
            props::hit_entry(c),
        ];
        entries.extend(super::props_map::PropsMap::entries(c));
        entries.extend(super::air_shadow::AirShadow::entries(c));
        if hybrid {
            entries.push(super::uniform_entry::<WorldRayUniforms>(18, c));
        }
        entries.extend(clouds.iter().flat_map(|_| clouds::Clouds::entries()));
        if compute_raster.is_some() {
            entries.push(super::storage_buffer_entry(19, true));
        }
        let compute_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("relief:visibility:compute-layout"),
            entries: &entries,
        });
        let entry_point = match (hybrid, ms) {
            (false, true) => "shade_samples",
            (false, false) if compute_raster.is_some() => "shade_rasterised",
            (true, false) if compute_raster.is_some() => "hybrid_rasterised",
            (false, false) => "shade_pixels",
            (true, true) => "hybrid_samples",
            (true, false) => "hybrid_pixels",
        };
        let compute = super::compute_pipeline(
            device,
            "relief:visibility:shade",
            &compute_layout,
            hybrid_module.as_ref().unwrap_or(&vis_module),
            entry_point,
        );
        let f = wgpu::ShaderStages::FRAGMENT;
        let composite_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("relief:visibility:composite-layout"),
            entries: &[
                super::uniform_entry::<VisUniforms>(12, f),
                super::texture_entry(13, f, false),
                super::texture_entry(14, f, false),
            ],
        });
        let composite = [false, true].map(|opaque| {
            composite_pipeline(device, &composite_layout, &vis_module, (targets, opaque))
        });
        let present_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("relief:visibility:present-layout"),
            entries: &[
                super::uniform_entry::<VisUniforms>(12, c),
                super::texture_entry(13, c, false),
                super::storage_buffer_entry(20, false),
            ],
        });
        let present = ["present_rgba", "present_bgra"].map(|entry| {
            super::compute_pipeline(
                device,
                "relief:visibility:present",
                &present_layout,
                &vis_module,
                entry,
            )
        });
        let store_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("relief:visibility:store-layout"),
            entries: &[
                super::uniform_entry::<VisUniforms>(12, c),
                super::texture_entry(13, c, false),
                super::storage_entry(21, STORE_FORMAT),
            ],
        });
        let store = super::compute_pipeline(
            device,
            "relief:visibility:store",
            &store_layout,
            &vis_module,
            "present_store",
        );
        Self {
            world,
            samples,
            hybrid,
            clouds,
            compute_raster,
            ray_uniforms: hybrid.then(|| {
                super::uniform_buffer::<WorldRayUniforms>(device, "relief:hybrid:ray-uniforms")
            }),
            raster,
            compute,
            compute_layout,
            composite,
            composite_layout,
            present,
            present_layout,
            store,
            store_layout,
            device: device.clone(),
            opaque: false,
            uniforms: super::uniform_buffer::<VisUniforms>(device, "relief:visibility:uniforms"),
            images: None,
            encode_srgb: !targets.color_format.is_srgb(),
            resolve: None,
            shown: 0,
            blade_motion: false,
            props: false,
            depth_w: [0.0; 2],
        }
    }

    /// Turns the temporal service's resolve on or off: its histories are made with the next
    /// frame's images, or dropped.
    pub(crate) fn set_temporal(&mut self, device: &wgpu::Device, on: bool) {
        if on == self.resolve.is_some() {
            return;
        }
        self.resolve = on.then(|| Resolve::new(device));
        self.images = None;
        self.shown = 0;
    }

    /// Whether the frame has blades of grass, whose motion in the wind the temporal service
    /// carries its history along (where the compute raster draws them): the motion image is
    /// made with the next frame's images, or dropped.
    pub(crate) fn set_blade_motion(&mut self, on: bool) {
        if on != self.blade_motion {
            self.blade_motion = on;
            self.images = None;
        }
    }

    /// Whether the blades' motion image is kept: blades in the compute raster, the temporal
    /// service on.
    fn keeps_motion(&self) -> bool {
        self.blade_motion
            && self.resolve.is_some()
            && self
                .compute_raster
                .as_ref()
                .is_some_and(ComputeRaster::draws_blades)
    }

    /// Records the temporal service's resolve of the frame [`Visibility::encode`] shaded,
    /// as `step` plans, into the history the frame then shows (nothing where the service is
    /// off).
    pub(crate) fn resolve(
        &mut self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        (step, cap): (&crate::temporal::Step, u32),
        timer: Option<&GpuTimer>,
    ) {
        let blades_moved = self.keeps_motion()
            && self
                .compute_raster
                .as_ref()
                .is_some_and(ComputeRaster::blades_bound);
        let (Some(resolve), Some(images)) = (&mut self.resolve, &self.images) else {
            return;
        };
        let u = TemporalUniforms::new(step, self.depth_w, images.size, (cap, blades_moved));
        resolve.encode(queue, encoder, &u, timer);
        self.shown = 1 + resolve.written();
    }

    /// Forgets the bind groups (the world's textures were made again).
    pub(crate) fn unbind(&mut self) {
        self.images = None;
    }

    /// What it was built for: samples a pixel, the hybrid method's or not, where its raster
    /// pass runs, and with the clouds or not.
    pub(crate) fn built_for(&self) -> (u32, bool, Raster, bool) {
        let raster = match self.compute_raster {
            Some(_) => Raster::Compute,
            None => Raster::Hardware,
        };
        (self.samples, self.hybrid, raster, self.clouds.is_some())
    }

    /// Whether it draws the grass's blades itself, in its compute raster with ids and its
    /// shading (the visibility method's, where the device has 64-bit atomics); elsewhere the
    /// world draws them after the composite.
    pub fn draws_grass(&self) -> bool {
        !self.hybrid
            && self
                .compute_raster
                .as_ref()
                .is_some_and(ComputeRaster::draws_blades)
    }

    /// Whether the compute raster's later passes skip the blocks of cells the earlier ones
    /// hide (the default; off only to test that skipping changes nothing).
    pub(crate) fn set_raster_skips_hidden(&mut self, on: bool) {
        if let Some(raster) = &mut self.compute_raster {
            raster.skip_hidden = on;
        }
    }

    /// 32-bit words a pixel of the compute raster's depth buffer (2 where it keeps each pixel's
    /// triangle), or `None` where the GPU's rasteriser draws.
    pub(crate) fn raster_depth_words(&self) -> Option<u32> {
        self.compute_raster
            .as_ref()
            .map(ComputeRaster::depth_stride)
    }

    /// GPU memory of the method's own images at `size`, bytes.
    pub fn bytes(&self, size: (u32, u32)) -> u64 {
        let pixels = u64::from(size.0) * u64::from(size.1);
        let bytes = super::texel_bytes;
        let samples = u64::from(self.samples);
        // Depth32Float, 4 bytes a sample, or the compute raster's buffers (its depth, 8 bytes a
        // pixel with each pixel's triangle, its tiles' farthest depth and its big triangles'
        // lists). The presented frame: 4 bytes a pixel (its rows' padding left out).
        let (depth, raster_bytes) = match &self.compute_raster {
            Some(raster) => (0, raster.bytes(size)),
            None => (samples * 4, 0),
        };
        let mut per_pixel =
            depth + bytes(SHADED_FORMAT) + bytes(SHADED_DEPTH_FORMAT) + PRESENTED_BYTES;
        if self.world {
            let valley = if self.compute_raster.is_some() {
                raster::VALLEY_FORMAT
            } else {
                VALLEY_FORMAT
            };
            per_pixel += samples * (bytes(SURFACE_FORMAT) + bytes(valley));
            if self.keeps_motion() {
                per_pixel += bytes(raster::MOTION_FORMAT);
            }
            if self.props && self.marches_props() {
                per_pixel += bytes(super::props::HIT_FORMAT);
            }
        }
        let history = if self.resolve.is_some() {
            Resolve::bytes(size)
        } else {
            0
        };
        let clouds = self.clouds.as_ref().map_or(0, |c| c.bytes(size));
        pixels * per_pixel + raster_bytes + history + clouds
    }

    fn images(&mut self, device: &wgpu::Device, size: (u32, u32), world: &WorldBindings<'_>) {
        if self.images.as_ref().is_some_and(|i| i.size == size) {
            return;
        }
        // The tile's raster pass writes no attributes: 1x1 stand-ins keep one layout.
        let attr_size = if self.world { size } else { (1, 1) };
        let n = self.samples;
        // The compute raster keeps its depth in a buffer of its own: a 1x1 stand-in here.
        let depth_size = if self.compute_raster.is_some() {
            (1, 1)
        } else {
            size
        };
        let depth = ms_texture(
            device,
            ("relief:visibility:depth", n),
            depth_size,
            DEPTH_FORMAT,
        );
        let usage = wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::TEXTURE_BINDING;
        let mut motion = None;
        let keeps_motion = self.keeps_motion();
        let (surface, valley) = if let Some(raster) = &mut self.compute_raster {
            // The compute raster stores the attributes (after its raster with ids, or by a
            // second raster), and where its blades are accumulated their motion.
            let motion_size = if keeps_motion { attr_size } else { (1, 1) };
            let [surface, valley, moved] = [
                (
                    "relief:visibility:surface",
                    raster::SURFACE_FORMAT,
                    attr_size,
                ),
                ("relief:visibility:valley", raster::VALLEY_FORMAT, attr_size),
                (
                    "relief:visibility:motion",
                    raster::MOTION_FORMAT,
                    motion_size,
                ),
            ]
            .map(|(label, format, size)| {
                super::texture_2d(device, label, size, format, usage)
                    .create_view(&Default::default())
            });
            raster.bind(device, (world.instances, size), (&surface, &valley, &moved));
            motion = keeps_motion.then_some(moved);
            (surface, valley)
        } else {
            let surface = ms_texture(
                device,
                ("relief:visibility:surface", n),
                attr_size,
                SURFACE_FORMAT,
            );
            let valley = ms_texture(
                device,
                ("relief:visibility:valley", n),
                attr_size,
                VALLEY_FORMAT,
            );
            (surface, valley)
        };
        let [depth_at, surface_at, valley_at] = target_bindings(n);
        let shaded = super::texture_2d(
            device,
            "relief:visibility:shaded",
            size,
            SHADED_FORMAT,
            usage,
        )
        .create_view(&Default::default());
        let shaded_depth = super::texture_2d(
            device,
            "relief:visibility:shaded-depth",
            size,
            SHADED_DEPTH_FORMAT,
            usage,
        )
        .create_view(&Default::default());
        let (prop_hit_texture, prop_hit) = self.prop_hit_image(device, size);
        use wgpu::BindingResource::{Sampler, TextureView};
        let mut entries = vec![
            entry(0, world.render.as_entire_binding()),
            entry(1, world.world.as_entire_binding()),
            entry(4, TextureView(world.tile_terrain)),
            entry(5, TextureView(world.tile_normals)),
            entry(6, Sampler(world.tile_sampler)),
            entry(depth_at, TextureView(&depth)),
            entry(surface_at, TextureView(&surface)),
            entry(valley_at, TextureView(&valley)),
            entry(10, TextureView(&shaded)),
            entry(11, TextureView(&shaded_depth)),
            entry(12, self.uniforms.as_entire_binding()),
            entry(22, TextureView(&prop_hit)),
        ];
        if let Some(rays) = &self.ray_uniforms {
            entries.push(entry(18, rays.as_entire_binding()));
        }
        if let Some(raster) = &mut self.compute_raster {
            entries.push(entry(19, raster.depth(device, size).as_entire_binding()));
        }
        entries.extend(world.props_map.bindings(false));
        entries.extend(world.air_shadow.bindings());
        if let Some(clouds) = &mut self.clouds {
            entries.extend(clouds.bind(device, size, world.render));
        }
        let compute_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("relief:visibility:compute-group"),
            layout: &self.compute_layout,
            entries: &entries,
        });
        let mut shown = vec![shaded.clone()];
        if let Some(resolve) = &mut self.resolve {
            resolve.bind(device, size, (&shaded, &shaded_depth, motion.as_ref()));
            shown.extend(resolve.colors().into_iter().flatten().cloned());
        }
        let composite_groups = shown
            .iter()
            .map(|view| {
                composite_group(
                    device,
                    ("relief:visibility:composite-group", &self.composite_layout),
                    (&self.uniforms, view, &shaded_depth),
                )
            })
            .collect();
        let bytes = u64::from(present_pitch(size.0)) * u64::from(size.1);
        let limits = device.limits();
        let fits =
            bytes <= limits.max_buffer_size && bytes <= limits.max_storage_buffer_binding_size;
        let presented = fits.then(|| {
            let buffer = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("relief:visibility:presented"),
                size: bytes,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            });
            let groups = shown
                .iter()
                .map(|view| {
                    device.create_bind_group(&wgpu::BindGroupDescriptor {
                        label: Some("relief:visibility:present-group"),
                        layout: &self.present_layout,
                        entries: &[
                            entry(12, self.uniforms.as_entire_binding()),
                            entry(13, TextureView(view)),
                            entry(20, buffer.as_entire_binding()),
                        ],
                    })
                })
                .collect();
            (buffer, groups)
        });
        self.images = Some(Images {
            size,
            depth,
            prop_hit,
            prop_hit_texture,
            surface,
            valley,
            compute_group,
            composite_groups,
            presented,
            shown,
        });
    }

    /// Records the raster pass (`draw` draws the patches with the world's bind group at 0; the
    /// compute raster reads `patches`) and the compute shading for an image of `size` seen
    /// through the camera-relative `matrix`; the hybrid method's refinement reads `rays`
    /// (ignored by the visibility method).
    #[expect(
        clippy::too_many_arguments,
        reason = "the world's resources, the frame and the timer, each needed once"
    )]
    pub(crate) fn encode(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        world: &WorldBindings<'_>,
        (matrix, size, sky): (glam::Mat4, (u32, u32), bool),
        (draw, patches, rays): (
            impl FnOnce(&mut wgpu::RenderPass<'_>),
            &Patches<'_>,
            Option<&WorldRayUniforms>,
        ),
        timer: Option<&GpuTimer>,
    ) {
        let size = (size.0.max(1), size.1.max(1));
        self.images(device, size, world);
        let mut u = VisUniforms::new(matrix, size, sky, self.world, self.encode_srgb);
        if let Some(raster) = &self.compute_raster {
            u.depth_stride = raster.depth_stride();
        }
        let props = patches.props.filter(|_| self.props && self.marches_props());
        u.props = u32::from(props.is_some());
        self.opaque = sky;
        self.shown = 0;
        self.depth_w = [u.depth[0], u.depth[1]];
        queue.write_buffer(&self.uniforms, 0, bytemuck::bytes_of(&u));
        if let (Some(buffer), Some(rays)) = (&self.ray_uniforms, rays) {
            queue.write_buffer(buffer, 0, bytemuck::bytes_of(rays));
        }
        let hybrid = self.hybrid;
        if let Some(raster) = &mut self.compute_raster {
            raster.bind_blades(device, patches.blades.filter(|_| !hybrid));
            raster.encode(queue, encoder, (size, patches), timer);
            if let (Some(props), Some(images)) = (props, &self.images) {
                let depth = raster.depth(device, size);
                props.encode_march(
                    device,
                    encoder,
                    (world.render, world.world, &self.uniforms, depth),
                    (&images.prop_hit, size, crate::gpu::props::March::Raster),
                    timer,
                );
            }
        }
        if let Some(clouds) = &mut self.clouds {
            clouds.encode(queue, encoder, size, timer);
        }
        let Some(images) = &self.images else {
            return;
        };
        let clear = wgpu::Operations {
            load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
            store: wgpu::StoreOp::Store,
        };
        let attachments = [
            Some(wgpu::RenderPassColorAttachment {
                view: &images.surface,
                depth_slice: None,
                resolve_target: None,
                ops: clear,
            }),
            Some(wgpu::RenderPassColorAttachment {
                view: &images.valley,
                depth_slice: None,
                resolve_target: None,
                ops: clear,
            }),
        ];
        if self.compute_raster.is_none() {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("relief:visibility:raster-pass"),
                color_attachments: if self.world { &attachments } else { &[] },
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &images.depth,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: timer.map(|t| t.render_writes(Slot::Raster)),
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(&self.raster);
            draw(&mut pass);
        }
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("relief:visibility:shade-pass"),
            timestamp_writes: timer.map(|t| t.compute_writes(Slot::Shade)),
        });
        pass.set_pipeline(&self.compute);
        pass.set_bind_group(0, &images.compute_group, &[]);
        pass.dispatch_workgroups(
            size.0.div_ceil(super::WORKGROUP),
            size.1.div_ceil(super::WORKGROUP),
            1,
        );
    }
}
