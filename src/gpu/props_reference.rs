//! The props of the reference (`--method reference` with props on): after the cast of the
//! continuous surface, at the cast's samples (3x3 a pixel), the props' own march
//! ([`super::props::PropsPass::encode_march`] as [`March::Reference`]) bounded by the distance
//! the cast met: every prop to the draw distance whole (no screen-size cut-off), up to
//! [`super::props::REFERENCE_STEPS`] steps a ray, each the field's distance over its Lipschitz
//! constant (the props' conservative march), and every sample's own shadow and occlusion on the
//! surface. `wgsl/props_reference.wgsl` turns the cast's distances into the march's depth
//! before it and, after it, shades again each sample the march left a prop or a shadow: a prop
//! with the props' light, the surface by the cast's own shading with the props' shares of its
//! sun and sky. The cast's distance becomes the prop's where a prop is nearer, so the layers
//! drawn over the cast after it (the grass) hide behind the props.
//!
//! What it shares with the methods: the props' scatter (the same cells, kinds and places, each
//! standing on the drawn levels), their fields and their light. What it leaves out: the props'
//! shadows on the reference's blades of grass, and the cut of the grass inside the props.

use super::props::{March, HIT_FORMAT};
use super::raymarch::RayMarcher;
use super::render::RenderUniforms;
use super::visibility::VisUniforms;
use super::world_rays::WorldRayUniforms;

/// What the props' march needs of the reference's pass for one cast: the cast's render
/// uniforms, the march's view uniforms, the depth it reads, the image it leaves and its size.
pub(crate) struct ReferenceMarch<'a> {
    /// The cast's render uniforms (the sun, the shading).
    pub render: &'a wgpu::Buffer,
    /// The march's view uniforms ([`VisUniforms`]).
    pub vis: &'a wgpu::Buffer,
    /// Each sample's depth, as the compute raster leaves it.
    pub depth: &'a wgpu::Buffer,
    /// Where the march leaves each sample's prop.
    pub hit: &'a wgpu::TextureView,
    /// The cast's size in samples.
    pub size: (u32, u32),
    /// How the march runs: [`March::Reference`].
    pub march: March,
}

/// The reference's props' two passes around the march.
pub(crate) struct PropsReference {
    layout: wgpu::BindGroupLayout,
    depth_layout: wgpu::BindGroupLayout,
    depth: wgpu::ComputePipeline,
    shade: wgpu::ComputePipeline,
}

impl PropsReference {
    pub(crate) fn new(device: &wgpu::Device) -> Self {
        let c = wgpu::ShaderStages::COMPUTE;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("relief:props-reference:layout"),
            entries: &[
                super::uniform_entry::<RenderUniforms>(0, c),
                super::storage_entry(2, RayMarcher::COLOR_FORMAT),
                super::storage_entry(3, RayMarcher::DISTANCE_FORMAT),
                super::uniform_entry::<VisUniforms>(12, c),
                super::uniform_entry::<WorldRayUniforms>(18, c),
                super::texture_entry(20, c, false),
                super::visibility::props_hit_entry(c),
            ],
        });
        let depth_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("relief:props-reference:depth-layout"),
            entries: &[super::storage_buffer_entry(0, false)],
        });
        let module = super::shader::module(
            device,
            "relief:props-reference",
            &super::shader::source("props_reference"),
        );
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("relief:props-reference:pipeline-layout"),
            bind_group_layouts: &[Some(&layout), Some(&depth_layout)],
            immediate_size: 0,
        });
        let [depth, shade] = ["reference_depth", "reference_props"].map(|entry| {
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(&format!("relief:props-reference:{entry}")),
                layout: Some(&pipeline_layout),
                module: &module,
                entry_point: Some(entry),
                compilation_options: Default::default(),
                cache: None,
            })
        });
        Self {
            layout,
            depth_layout,
            depth,
            shade,
        }
    }

    /// Records, after `caster`'s cast through the camera-relative `matrix` (its near and far
    /// planes around what the cast can meet), the props over it: the cast's depth, `march`
    /// (the props' scatter and march, given what it reads and where it writes), and the
    /// shading again of what the march left.
    pub(crate) fn encode(
        &self,
        (device, encoder): (&wgpu::Device, &mut wgpu::CommandEncoder),
        caster: &RayMarcher,
        matrix: glam::Mat4,
        march: impl FnOnce(&mut wgpu::CommandEncoder, &ReferenceMarch<'_>),
    ) {
        use wgpu::util::DeviceExt as _;
        let size = caster.size();
        let (render, ray) = caster.uniforms();
        let vis = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("relief:props-reference:vis"),
            contents: bytemuck::bytes_of(&VisUniforms::new(matrix, size, false, true, false)),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let depth = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("relief:props-reference:depth"),
            size: u64::from(size.0) * u64::from(size.1) * 4,
            usage: wgpu::BufferUsages::STORAGE,
            mapped_at_creation: false,
        });
        // The cast's distances, read while the pass writes the props' into the cast's own.
        let distances = super::texture_2d(
            device,
            "relief:props-reference:distance",
            size,
            RayMarcher::DISTANCE_FORMAT,
            wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        );
        encoder.copy_texture_to_texture(
            caster.distance.as_image_copy(),
            distances.as_image_copy(),
            caster.distance.size(),
        );
        let hit = super::texture_2d(
            device,
            "relief:props-reference:hit",
            size,
            HIT_FORMAT,
            wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::TEXTURE_BINDING,
        );
        let [color_view, distance_view, distances_view, hit_view] =
            [&caster.color, &caster.distance, &distances, &hit]
                .map(|t| t.create_view(&Default::default()));
        let entry = |binding, resource| wgpu::BindGroupEntry { binding, resource };
        use wgpu::BindingResource::TextureView;
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("relief:props-reference:group"),
            layout: &self.layout,
            entries: &[
                entry(0, render.as_entire_binding()),
                entry(2, TextureView(&color_view)),
                entry(3, TextureView(&distance_view)),
                entry(12, vis.as_entire_binding()),
                entry(18, ray.as_entire_binding()),
                entry(20, TextureView(&distances_view)),
                entry(22, TextureView(&hit_view)),
            ],
        });
        let depth_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("relief:props-reference:depth-group"),
            layout: &self.depth_layout,
            entries: &[entry(0, depth.as_entire_binding())],
        });
        let g = super::WORKGROUP;
        let groups = (size.0.div_ceil(g), size.1.div_ceil(g));
        let pass = |encoder: &mut wgpu::CommandEncoder, pipeline: &wgpu::ComputePipeline| {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("relief:props-reference:pass"),
                timestamp_writes: None,
            });
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, &group, &[]);
            pass.set_bind_group(1, &depth_group, &[]);
            pass.dispatch_workgroups(groups.0, groups.1, 1);
        };
        pass(encoder, &self.depth);
        march(
            encoder,
            &ReferenceMarch {
                render,
                vis: &vis,
                depth: &depth,
                hit: &hit_view,
                size,
                march: March::Reference,
            },
        );
        pass(encoder, &self.shade);
    }
}
