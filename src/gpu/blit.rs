//! Shows a ray-cast image ([`super::raymarch::RayMarcher`]'s colour) in the host's target
//! (`wgsl/blit.wgsl`): what the window and the page draw when their method is a ray caster.

use super::shader;
use super::timing::{GpuTimer, Slot};

/// Mirrors `BlitUniforms` in `wgsl/blit.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct BlitUniforms {
    /// Rays per pixel each way in the image shown.
    pub ss: u32,
    /// 1 where the target is not an sRGB format and the shader encodes.
    pub encode_srgb: u32,
    /// Padding.
    pub _pad: [u32; 2],
}

/// The pipeline for one target format.
pub struct Blit {
    pipeline: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
    uniforms: wgpu::Buffer,
    format: wgpu::TextureFormat,
}

impl Blit {
    /// A blit into targets of `format` (single-sampled, no depth).
    pub fn new(device: &wgpu::Device, format: wgpu::TextureFormat) -> Self {
        let module = shader::module(device, "relief:blit:shader", &shader::source("blit"));
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("relief:blit:layout"),
            entries: &[
                super::uniform_entry::<BlitUniforms>(0, wgpu::ShaderStages::FRAGMENT),
                super::texture_entry(1, wgpu::ShaderStages::FRAGMENT, false),
            ],
        });
        let pipeline = super::fullscreen_pipeline(
            device,
            "relief:blit:pipeline",
            &layout,
            &module,
            ("blit_vs", "blit_fs"),
            &[Some(format.into())],
        );
        let uniforms = super::uniform_buffer::<BlitUniforms>(device, "relief:blit:uniforms");
        Self {
            pipeline,
            layout,
            uniforms,
            format,
        }
    }

    /// The target format it draws into.
    pub fn format(&self) -> wgpu::TextureFormat {
        self.format
    }

    /// The bind group that shows `image`: made once per image, not per frame.
    pub fn bind(&self, device: &wgpu::Device, image: &wgpu::Texture) -> wgpu::BindGroup {
        let view = image.create_view(&Default::default());
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("relief:blit:group"),
            layout: &self.layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: self.uniforms.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::TextureView(&view),
                },
            ],
        })
    }

    /// Records a pass drawing the image of `group` ([`Blit::bind`]; `ss` x `ss` texels a pixel)
    /// over all of `target`, timed as [`Slot::Show`] into `timer`.
    pub fn encode(
        &self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        (group, ss): (&wgpu::BindGroup, u32),
        target: &wgpu::TextureView,
        timer: Option<&GpuTimer>,
    ) {
        let u = BlitUniforms {
            ss: ss.max(1),
            encode_srgb: u32::from(!self.format.is_srgb()),
            _pad: [0; 2],
        };
        queue.write_buffer(&self.uniforms, 0, bytemuck::bytes_of(&u));
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("relief:blit:pass"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: target,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: None,
            timestamp_writes: timer.map(|t| t.render_writes(Slot::Show)),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, group, &[]);
        pass.draw(0..3, 0..1);
    }
}
