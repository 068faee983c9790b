//! The frame's layers over a ray cast of the endless world: how the reference (and every ray
//! caster) draws the layers ([`super::layer`]) that the mesh-based methods draw. After the
//! cast, `wgsl/ray_depth.wgsl` turns each pixel's ray distance into depth under the layers'
//! own matrix; each layer is then prepared and drawn as in [`crate::World::render`], into the
//! cast's colour image at the cast's size (3x3 rays a pixel for the reference, so the layer is
//! supersampled with it), depth-tested against the surface the cast found.
//!
//! A layer drawn here is rasterised, not ray-cast: its own reference is its geometry drawn at
//! the reference's samples. A layer whose exact image needs rays (a marched prop, a volume)
//! brings its own pass here when it comes (docs/architecture.md, section 4).
//!
//! Native only, for now: `headless::render_world_rays_with_layers` is its one caller (the
//! window's and the page's ray casters show no layers, as the window has none to show).

use super::layer::{Layer, LayerFrame};
use super::raymarch::RayMarcher;
use super::render::RenderUniforms;
use super::Targets;
use crate::method::Method;
use glam::{DVec3, Mat4};

/// Mirrors `RayDepthUniforms` in `wgsl/ray_depth.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct RayDepthUniforms {
    inv_ray: [[f32; 4]; 4],
    layer: [[f32; 4]; 4],
    size: [f32; 2],
    pad: [f32; 2],
}

/// What the layers are drawn into: the cast's colour image and a depth image beside it.
const TARGETS: Targets = Targets {
    color_format: RayMarcher::COLOR_FORMAT,
    depth_format: Some(DEPTH_FORMAT),
    sample_count: 1,
};
const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// One frame of the cast's layers: the view, and the matrices and shading it draws them with.
pub(crate) struct RayLayerFrame<'a> {
    /// The eye, world metres.
    pub eye: DVec3,
    /// The cast's camera-relative matrix (only its rays matter: `ray_matrix`).
    pub ray_matrix: Mat4,
    /// The layers' camera-relative matrix, with near and far planes around the drawn region.
    pub layer_matrix: Mat4,
    /// The frame's shading under `layer_matrix`.
    pub render: &'a RenderUniforms,
    /// The method the cast draws.
    pub method: Method,
}

/// Draws `layers` over `caster`'s last cast (recorded into `encoder` after the cast).
pub(crate) fn encode(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    encoder: &mut wgpu::CommandEncoder,
    caster: &RayMarcher,
    frame: &RayLayerFrame<'_>,
    layers: &mut [&mut (dyn Layer + 'static)],
) {
    if layers.is_empty() {
        return;
    }
    let size = caster.color.size();
    let module = super::shader::module(
        device,
        "relief:ray-layers:shader",
        &super::shader::source("ray_depth"),
    );
    let fragment = wgpu::ShaderStages::FRAGMENT;
    let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("relief:ray-layers:bind-group-layout"),
        entries: &[
            super::uniform_entry::<RayDepthUniforms>(0, fragment),
            super::texture_entry(1, fragment, false),
        ],
    });
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("relief:ray-layers:pipeline-layout"),
        bind_group_layouts: &[Some(&layout)],
        immediate_size: 0,
    });
    // Depth alone: every pixel written, whatever was there.
    let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("relief:ray-layers:depth"),
        layout: Some(&pipeline_layout),
        vertex: wgpu::VertexState {
            module: &module,
            entry_point: Some("depth_vs"),
            compilation_options: Default::default(),
            buffers: &[],
        },
        primitive: Default::default(),
        depth_stencil: Some(wgpu::DepthStencilState {
            format: DEPTH_FORMAT,
            depth_write_enabled: Some(true),
            depth_compare: Some(wgpu::CompareFunction::Always),
            stencil: Default::default(),
            bias: Default::default(),
        }),
        multisample: Default::default(),
        fragment: Some(wgpu::FragmentState {
            module: &module,
            entry_point: Some("depth_fs"),
            compilation_options: Default::default(),
            targets: &[],
        }),
        multiview_mask: None,
        cache: None,
    });
    let uniforms = super::uniform_buffer::<RayDepthUniforms>(device, "relief:ray-layers:uniforms");
    queue.write_buffer(
        &uniforms,
        0,
        bytemuck::bytes_of(&RayDepthUniforms {
            inv_ray: frame.ray_matrix.inverse().to_cols_array_2d(),
            layer: frame.layer_matrix.to_cols_array_2d(),
            size: [size.width as f32, size.height as f32],
            pad: [0.0; 2],
        }),
    );
    let render_uniforms =
        super::uniform_buffer::<RenderUniforms>(device, "relief:ray-layers:render-uniforms");
    queue.write_buffer(&render_uniforms, 0, bytemuck::bytes_of(frame.render));
    let distance = caster.distance.create_view(&Default::default());
    let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("relief:ray-layers:bind-group"),
        layout: &layout,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: uniforms.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: wgpu::BindingResource::TextureView(&distance),
            },
        ],
    });
    let depth = super::texture_2d(
        device,
        "relief:ray-layers:depth",
        (size.width, size.height),
        DEPTH_FORMAT,
        wgpu::TextureUsages::RENDER_ATTACHMENT,
    );
    let depth_view = depth.create_view(&Default::default());
    let layer_frame = LayerFrame {
        device,
        queue,
        targets: &TARGETS,
        eye: frame.eye,
        render_uniforms: &render_uniforms,
        method: frame.method,
    };
    for layer in layers.iter_mut() {
        layer.prepare(&layer_frame, encoder);
    }
    {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("relief:ray-layers:depth"),
            color_attachments: &[],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &depth_view,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bind_group, &[]);
        pass.draw(0..3, 0..1);
    }
    let color = caster.color.create_view(&Default::default());
    let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some("relief:ray-layers:draw"),
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view: &color,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations {
                load: wgpu::LoadOp::Load,
                store: wgpu::StoreOp::Store,
            },
        })],
        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
            view: &depth_view,
            depth_ops: Some(wgpu::Operations {
                load: wgpu::LoadOp::Load,
                store: wgpu::StoreOp::Discard,
            }),
            stencil_ops: None,
        }),
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    });
    for layer in layers.iter() {
        layer.render(&mut pass);
    }
}

/// The layers' camera-relative matrix for a cast of `params` through `view`: the near plane as
/// the mesh's frame chooses it (a tenth of the eye's height over the ground, within 5 cm and
/// 20 m), the far plane past every point of the drawn `region` (its far corner, with the peak
/// and the eye's height), so nothing the cast finds is clipped.
pub(crate) fn layer_matrix(
    params: &crate::world::WorldParams,
    view: &crate::WorldView,
    region: [f64; 4],
) -> Mat4 {
    let eye = view.eye;
    let land = &params.land;
    let altitude = (eye.y - land.height_at(eye.x, eye.z)).max(0.0);
    let near = (altitude as f32 * 0.1).clamp(0.05, 20.0);
    let dx = (eye.x - region[0]).abs().max((region[2] - eye.x).abs());
    let dz = (eye.z - region[1]).abs().max((region[3] - eye.z).abs());
    let far = dx.hypot(dz).hypot(land.peak_height + eye.y.abs()) as f32;
    view.relative_matrix(near, far.max(2.0 * near))
}

#[cfg(test)]
mod tests {
    use super::RayDepthUniforms;
    use std::mem::{offset_of, size_of};

    #[test]
    fn the_depth_uniforms_match_the_wgsl() {
        let source = super::super::shader::source("ray_depth");
        let module = naga::front::wgsl::parse_str(&source).expect("ray_depth.wgsl parses");
        let (span, members) = module
            .types
            .iter()
            .find_map(|(_, ty)| match &ty.inner {
                naga::TypeInner::Struct { members, span }
                    if ty.name.as_deref() == Some("RayDepthUniforms") =>
                {
                    Some((*span, members.clone()))
                }
                _ => None,
            })
            .expect("RayDepthUniforms in ray_depth.wgsl");
        assert_eq!(span as usize, size_of::<RayDepthUniforms>());
        let offsets: Vec<(Option<String>, usize)> = members
            .iter()
            .map(|m| (m.name.clone(), m.offset as usize))
            .collect();
        let rust = [
            ("inv_ray", offset_of!(RayDepthUniforms, inv_ray)),
            ("layer", offset_of!(RayDepthUniforms, layer)),
            ("size", offset_of!(RayDepthUniforms, size)),
            ("pad", offset_of!(RayDepthUniforms, pad)),
        ];
        let rust: Vec<(Option<String>, usize)> = rust
            .iter()
            .map(|(n, o)| (Some((*n).to_owned()), *o))
            .collect();
        assert_eq!(offsets, rust);
    }
}
