//! [`World`]'s forward mesh through the temporal service. The mesh draws into the host's pass,
//! which keeps nothing between frames; with the service on it draws instead, jittered, into
//! relief's own image (linear colour at the host's samples, with its sky), whose nearest
//! sample's depth a compute pass copies for the resolve (`wgsl/mesh_history.wgsl`). The
//! resolve ([`crate::gpu::temporal`], the one the methods shaded in compute run) blends it
//! into the history, and [`World::render`] composites the history, colour and depth, into the
//! host's pass (`wgsl/composite.wgsl`, as the visibility method does).

use super::*;
use crate::gpu::temporal::{Resolve, TemporalUniforms};
use crate::gpu::visibility::{clip_w_from_depth, composite_group, composite_pipeline};

/// The mesh's own colour: linear, half precision is finer than an 8-bit step everywhere.
const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// Each pixel's nearest sample's depth, as the resolve and the composite read it.
const DEPTH_COPY_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;

/// Mirrors `MeshHistoryUniforms` in `wgsl/mesh_history.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
struct MeshHistoryUniforms {
    size: [u32; 2],
    encode_srgb: u32,
    _pad: u32,
}

/// The images of one size.
struct Images {
    size: (u32, u32),
    /// Multisampled where the host's pass is (then `resolved` is what the resolve reads).
    color: wgpu::TextureView,
    resolved: Option<wgpu::TextureView>,
    depth: wgpu::TextureView,
    copy_group: wgpu::BindGroup,
    /// The composite's bind group for each history.
    composite_groups: Vec<wgpu::BindGroup>,
}

/// The forward mesh's own image, its pipelines and its history (see the module docs).
pub(super) struct MeshHistory {
    /// The world's render uniforms as the mesh's own image takes them (linear colour).
    uniforms: wgpu::Buffer,
    own: wgpu::Buffer,
    pipeline: wgpu::RenderPipeline,
    sky: crate::gpu::sky::SkyPass,
    samples: u32,
    /// The world's bind group that `group` was made beside: made again when it changes.
    source: Option<wgpu::BindGroup>,
    group: Option<wgpu::BindGroup>,
    copy: wgpu::ComputePipeline,
    copy_layout: wgpu::BindGroupLayout,
    composite: [wgpu::RenderPipeline; 2],
    composite_layout: wgpu::BindGroupLayout,
    resolve: Resolve,
    images: Option<Images>,
    opaque: bool,
    /// Clip w from depth of the last frame's matrix.
    depth_w: [f32; 2],
    /// Whether the last frame was resolved (what the composite shows).
    resolved: bool,
    encode_srgb: bool,
}

impl MeshHistory {
    /// The passes for a world drawn by `module` with the bind group `layout` into the host's
    /// `targets` (`tile`: the seed blog's tile's fragment shader), its sky's shafts reading
    /// `air_shadow`.
    pub fn new(
        device: &wgpu::Device,
        (module, layout): (&wgpu::ShaderModule, &wgpu::BindGroupLayout),
        (targets, air_shadow): (&Targets, &crate::gpu::air_shadow::AirShadow),
        tile: bool,
    ) -> Self {
        let own_targets = Targets {
            color_format: COLOR_FORMAT,
            depth_format: Some(DEPTH_FORMAT),
            sample_count: targets.sample_count,
        };
        // (`own_targets` below says the same once built.)
        let uniforms =
            crate::gpu::uniform_buffer::<RenderUniforms>(device, "relief:mesh-history:render");
        let pipeline = mesh_pipeline(device, (layout, module), &own_targets, tile);
        let sky = crate::gpu::sky::SkyPass::new(device, &own_targets, (&uniforms, air_shadow));
        let history_module = shader::module(
            device,
            "relief:mesh-history:shader",
            &shader::source("mesh_history"),
        );
        let ms = targets.sample_count > 1;
        let c = wgpu::ShaderStages::COMPUTE;
        let copy_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("relief:mesh-history:copy-layout"),
            entries: &[
                crate::gpu::uniform_entry::<MeshHistoryUniforms>(12, c),
                wgpu::BindGroupLayoutEntry {
                    binding: if ms { 17 } else { 15 },
                    visibility: c,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Depth,
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: ms,
                    },
                    count: None,
                },
                crate::gpu::storage_entry(16, DEPTH_COPY_FORMAT),
            ],
        });
        let copy = crate::gpu::compute_pipeline(
            device,
            "relief:mesh-history:copy-depth",
            &copy_layout,
            &history_module,
            if ms {
                "copy_depth_samples"
            } else {
                "copy_depth"
            },
        );
        let f = wgpu::ShaderStages::FRAGMENT;
        let composite_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("relief:mesh-history:composite-layout"),
            entries: &[
                crate::gpu::uniform_entry::<MeshHistoryUniforms>(12, f),
                crate::gpu::texture_entry(13, f, false),
                crate::gpu::texture_entry(14, f, false),
            ],
        });
        let composite = [false, true].map(|opaque| {
            composite_pipeline(
                device,
                &composite_layout,
                &history_module,
                (targets, opaque),
            )
        });
        Self {
            uniforms,
            own: crate::gpu::uniform_buffer::<MeshHistoryUniforms>(
                device,
                "relief:mesh-history:uniforms",
            ),
            pipeline,
            sky,
            samples: targets.sample_count,
            source: None,
            group: None,
            copy,
            copy_layout,
            composite,
            composite_layout,
            resolve: Resolve::new(device),
            images: None,
            opaque: false,
            depth_w: [0.0; 2],
            resolved: false,
            encode_srgb: !targets.color_format.is_srgb(),
        }
    }

    /// GPU memory at `size`, bytes: the image's colour and depth at its samples, the resolved
    /// colour (multisampled only), the depth copy and the histories.
    pub fn bytes(&self, size: (u32, u32)) -> u64 {
        let pixels = u64::from(size.0) * u64::from(size.1);
        let bytes = crate::gpu::texel_bytes;
        let samples = u64::from(self.samples);
        let resolved = if self.samples > 1 {
            bytes(COLOR_FORMAT)
        } else {
            0
        };
        let per_pixel = samples * (bytes(COLOR_FORMAT) + bytes(DEPTH_FORMAT))
            + resolved
            + bytes(DEPTH_COPY_FORMAT);
        pixels * per_pixel + Resolve::bytes(size)
    }

    /// The targets of its own image.
    pub fn own_targets(&self) -> Targets {
        Targets {
            color_format: COLOR_FORMAT,
            depth_format: Some(DEPTH_FORMAT),
            sample_count: self.samples,
        }
    }

    /// The render uniforms its own image is drawn with.
    pub fn uniforms(&self) -> &wgpu::Buffer {
        &self.uniforms
    }

    /// Writes the frame's render uniforms as the own image takes them: linear colour.
    pub fn write_uniforms(&self, queue: &wgpu::Queue, uniforms: &RenderUniforms) {
        let linear = RenderUniforms {
            encode_srgb: 0,
            ..*uniforms
        };
        queue.write_buffer(&self.uniforms, 0, bytemuck::bytes_of(&linear));
    }

    /// The bind group of the world's resources with the own image's uniforms, made again
    /// whenever the world's `source` group was (`make` builds it from the uniforms).
    fn bind(
        &mut self,
        source: &wgpu::BindGroup,
        make: impl FnOnce(&wgpu::Buffer) -> wgpu::BindGroup,
    ) {
        if self.source.as_ref() != Some(source) {
            self.group = Some(make(&self.uniforms));
            self.source = Some(source.clone());
        }
    }

    fn images(&mut self, device: &wgpu::Device, size: (u32, u32)) {
        if self.images.as_ref().is_some_and(|i| i.size == size) {
            return;
        }
        let attachment = |label, format| {
            device
                .create_texture(&wgpu::TextureDescriptor {
                    label: Some(label),
                    size: wgpu::Extent3d {
                        width: size.0,
                        height: size.1,
                        depth_or_array_layers: 1,
                    },
                    mip_level_count: 1,
                    sample_count: self.samples,
                    dimension: wgpu::TextureDimension::D2,
                    format,
                    usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                        | wgpu::TextureUsages::TEXTURE_BINDING,
                    view_formats: &[],
                })
                .create_view(&Default::default())
        };
        let color = attachment("relief:mesh-history:color", COLOR_FORMAT);
        let depth = attachment("relief:mesh-history:depth", DEPTH_FORMAT);
        let single = |label, format, usage| {
            crate::gpu::texture_2d(device, label, size, format, usage)
                .create_view(&Default::default())
        };
        let sampled = wgpu::TextureUsages::TEXTURE_BINDING;
        let resolved = (self.samples > 1).then(|| {
            single(
                "relief:mesh-history:resolved",
                COLOR_FORMAT,
                sampled | wgpu::TextureUsages::RENDER_ATTACHMENT,
            )
        });
        let depth_copy = single(
            "relief:mesh-history:depth-copy",
            DEPTH_COPY_FORMAT,
            sampled | wgpu::TextureUsages::STORAGE_BINDING,
        );
        self.resolve.bind(
            device,
            size,
            (resolved.as_ref().unwrap_or(&color), &depth_copy, None),
        );
        use wgpu::BindingResource::TextureView;
        let entry = |binding, resource| wgpu::BindGroupEntry { binding, resource };
        let copy_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("relief:mesh-history:copy-group"),
            layout: &self.copy_layout,
            entries: &[
                entry(12, self.own.as_entire_binding()),
                entry(if self.samples > 1 { 17 } else { 15 }, TextureView(&depth)),
                entry(16, TextureView(&depth_copy)),
            ],
        });
        let composite_groups = self
            .resolve
            .colors()
            .into_iter()
            .flatten()
            .map(|history| {
                composite_group(
                    device,
                    (
                        "relief:mesh-history:composite-group",
                        &self.composite_layout,
                    ),
                    (&self.own, history, &depth_copy),
                )
            })
            .collect();
        self.images = Some(Images {
            size,
            color,
            resolved,
            depth,
            copy_group,
            composite_groups,
        });
    }

    /// Records the mesh (`draw` draws the patches with the bind group at 0 set), and its sky
    /// where `sky` is on, into the own image of `size` seen through the camera-relative
    /// `matrix`, and the copy of its depth (timed as [`Slot::Shade`]: the host's pass, timed as
    /// [`Slot::Render`], then holds the composite).
    fn encode(
        &mut self,
        (device, queue, encoder): (&wgpu::Device, &wgpu::Queue, &mut wgpu::CommandEncoder),
        (matrix, size, sky): (Mat4, (u32, u32), bool),
        draw: impl FnOnce(&mut wgpu::RenderPass<'_>),
        timer: Option<&GpuTimer>,
    ) {
        self.images(device, size);
        let (Some(images), Some(group)) = (&self.images, &self.group) else {
            return;
        };
        let own = MeshHistoryUniforms {
            size: [size.0, size.1],
            encode_srgb: u32::from(self.encode_srgb),
            _pad: 0,
        };
        queue.write_buffer(&self.own, 0, bytemuck::bytes_of(&own));
        self.depth_w = clip_w_from_depth(matrix);
        self.opaque = sky;
        self.resolved = false;
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("relief:mesh-history:pass"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &images.color,
                    depth_slice: None,
                    resolve_target: images.resolved.as_ref(),
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &images.depth,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: timer.map(|t| t.render_writes(Slot::Shade)),
                occlusion_query_set: None,
                multiview_mask: None,
            });
            self.sky.around(&mut pass, sky, |pass| {
                pass.set_pipeline(&self.pipeline);
                pass.set_bind_group(0, group, &[]);
                draw(pass);
            });
        }
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("relief:mesh-history:copy-depth-pass"),
            timestamp_writes: None,
        });
        pass.set_pipeline(&self.copy);
        pass.set_bind_group(0, &images.copy_group, &[]);
        pass.dispatch_workgroups(
            size.0.div_ceil(crate::gpu::WORKGROUP),
            size.1.div_ceil(crate::gpu::WORKGROUP),
            1,
        );
    }

    /// Records the resolve of the frame [`MeshHistory::encode`] drew, as `step` plans.
    pub fn resolve(
        &mut self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        (step, cap): (&crate::temporal::Step, u32),
        timer: Option<&GpuTimer>,
    ) {
        let Some(images) = &self.images else {
            return;
        };
        let u = TemporalUniforms::new(step, self.depth_w, images.size, (cap, false));
        self.resolve.encode(queue, encoder, &u, timer);
        self.resolved = true;
    }

    /// Draws the history the last resolve wrote into the host's pass, colour and depth.
    /// Returns false, drawing nothing, where no frame was resolved.
    pub fn composite(&self, pass: &mut wgpu::RenderPass<'_>) -> bool {
        let Some(images) = &self.images else {
            return false;
        };
        let Some(group) = images.composite_groups.get(self.resolve.written()) else {
            return false;
        };
        if !self.resolved {
            return false;
        }
        pass.push_debug_group("relief:mesh-history:composite");
        pass.set_pipeline(&self.composite[usize::from(self.opaque)]);
        pass.set_bind_group(0, group, &[]);
        pass.draw(0..3, 0..1);
        pass.pop_debug_group();
        true
    }
}

impl World {
    /// Whether the forward mesh draws through its history: the service on and the method the
    /// mesh.
    pub(super) fn mesh_accumulates(&self) -> bool {
        self.temporal.on() && self.method == Method::Mesh
    }

    /// Makes (or drops) the mesh's history for the current method, service and targets.
    pub(super) fn update_mesh_history(&mut self, device: &wgpu::Device) -> Result<()> {
        if !self.mesh_accumulates() {
            self.mesh_history = None;
            return Ok(());
        }
        if self.mesh_history.is_none() {
            let tile = self.tile.is_some();
            let built = scoped(device, || {
                MeshHistory::new(
                    device,
                    (&self.module, &self.layout),
                    (&self.targets, &self.shafts.map),
                    tile,
                )
            })?;
            self.mesh_history = Some(built);
        }
        Ok(())
    }

    /// Records the forward mesh's frame into its own image (where it accumulates).
    pub(super) fn encode_mesh_history(
        &mut self,
        (device, queue, encoder): (&wgpu::Device, &wgpu::Queue, &mut wgpu::CommandEncoder),
        view: &WorldView,
        timer: Option<&GpuTimer>,
    ) {
        let size = self.target_size.unwrap_or(view.size);
        let size = (size.0.max(1), size.1.max(1));
        self.vis_size = size;
        let Some(history) = &mut self.mesh_history else {
            return;
        };
        history.bind(&self.bind_group, |render| {
            bind(
                device,
                &self.layout,
                (render, &self.world_uniforms),
                (&self.texture, &self.light.texture),
                (
                    &self.tile_textures,
                    self.props_map.bindings(false),
                    &self.shafts.map,
                ),
            )
        });
        let [whole, subs] = self.instance_counts;
        let (own, uniforms) = (history.own_targets(), history.uniforms().clone());
        let grass = &self.grass;
        let draw = |pass: &mut wgpu::RenderPass<'_>| {
            if whole + subs > 0 {
                draw_patches(
                    pass,
                    (&self.instances, self.instance_counts),
                    (&self.indices, self.index_counts),
                );
            }
            // The grass into the same image: accumulated and composited with the terrain.
            if let Some(grass) = grass {
                grass.draw(pass, &own, &uniforms);
            }
        };
        history.encode(
            (device, queue, encoder),
            (self.matrix, size, self.shading.sky),
            draw,
            timer,
        );
    }
}

#[cfg(test)]
#[test]
fn the_uniforms_match_wgsl() {
    use crate::gpu::wgsl_tests::{layout, offset, parse};
    let m = parse("mesh_history", &shader::source("mesh_history"));
    let (size, members) = layout(&m, "MeshHistoryUniforms");
    assert_eq!(size as usize, std::mem::size_of::<MeshHistoryUniforms>());
    for (name, at) in [
        ("size", std::mem::offset_of!(MeshHistoryUniforms, size)),
        (
            "encode_srgb",
            std::mem::offset_of!(MeshHistoryUniforms, encode_srgb),
        ),
    ] {
        assert_eq!(offset(&members, name), at, "MeshHistoryUniforms.{name}");
    }
}
