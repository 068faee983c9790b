//! The props over a frame whose method does not march them ([`crate::World`] with the forward
//! mesh, the hybrid, or the visibility method rasterised by the GPU): after the scatter, the
//! props' march ([`super::props::PropsPass::encode_march`]) runs with no raster's depth to
//! bound it, from the eye to the draw distance, into an image of each pixel's nearest prop; in
//! the host's pass, after the terrain, one full-screen triangle (`wgsl/props_overlay.wgsl`)
//! shades the pixels that hold a prop and writes their depth, and the host's depth test keeps
//! those nearer than the terrain and the host's geometry. It needs a depth attachment.
//!
//! The terrain under it is shaded before the props are marched: it takes the props' shadow
//! and occlusion from the props' shade map ([`super::props_map`]), at the map's texels rather
//! than each pixel's own, and the grass's blades take none. The overlay marches the props
//! behind the terrain too (the depth test discards them).

use super::props::{PropsPass, HIT_FORMAT};
use super::visibility::VisUniforms;
use super::Targets;

/// The props' overlay: its pipeline into the host's targets, its uniforms and the image the
/// march leaves, made at the frame's size.
pub(crate) struct PropsOverlay {
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::RenderPipeline,
    view: wgpu::Buffer,
    no_depth: wgpu::Buffer,
    image: Option<Image>,
}

/// The image of a frame's size and the bind group that reads it.
struct Image {
    size: (u32, u32),
    #[cfg_attr(
        target_arch = "wasm32",
        allow(dead_code, reason = "read back natively")
    )]
    texture: wgpu::Texture,
    view: wgpu::TextureView,
    group: wgpu::BindGroup,
}

impl PropsOverlay {
    /// The overlay for a host's pass of `targets` (which has a depth attachment).
    pub(crate) fn new(device: &wgpu::Device, targets: &Targets) -> Self {
        let f = wgpu::ShaderStages::FRAGMENT;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("relief:props-overlay:layout"),
            entries: &[
                super::uniform_entry::<super::RenderUniforms>(0, f),
                super::uniform_entry::<VisUniforms>(12, f),
                super::visibility::props_hit_entry(f),
            ],
        });
        let module = super::shader::module(
            device,
            "relief:props-overlay",
            &super::shader::source("props_overlay"),
        );
        let pipeline = super::blended_pipeline(
            device,
            (
                "relief:props-overlay",
                &layout,
                &module,
                ("overlay_vs", "overlay_fs"),
            ),
            targets,
            (wgpu::PrimitiveTopology::TriangleList, &[]),
            (true, wgpu::CompareFunction::Less),
            None,
        );
        let no_depth = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("relief:props-overlay:no-depth"),
            size: 16,
            usage: wgpu::BufferUsages::STORAGE,
            mapped_at_creation: false,
        });
        Self {
            layout,
            pipeline,
            view: super::uniform_buffer::<VisUniforms>(device, "relief:props-overlay:view"),
            no_depth,
            image: None,
        }
    }

    /// Records the props' march for a frame of `size` through the camera-relative `matrix`,
    /// reading the frame's `render` and `world` uniforms (their scatter already recorded);
    /// timed as [`super::timing::Slot::March`].
    pub(crate) fn prepare(
        &mut self,
        (device, queue, encoder): (&wgpu::Device, &wgpu::Queue, &mut wgpu::CommandEncoder),
        props: &PropsPass,
        (render, world): (&wgpu::Buffer, &wgpu::Buffer),
        (matrix, size): (glam::Mat4, (u32, u32)),
        timer: Option<&super::timing::GpuTimer>,
    ) {
        let size = (size.0.max(1), size.1.max(1));
        let uniforms = VisUniforms::new(matrix, size, false, true, false);
        queue.write_buffer(&self.view, 0, bytemuck::bytes_of(&uniforms));
        if self.image.as_ref().is_none_or(|i| i.size != size) {
            self.image = Some(self.image(device, render, size));
        }
        let image = self.image.as_ref().expect("made above");
        props.encode_march(
            device,
            encoder,
            (render, world, &self.view, &self.no_depth),
            (&image.view, size, super::props::March::Unbounded),
            timer,
        );
    }

    fn image(&self, device: &wgpu::Device, render: &wgpu::Buffer, size: (u32, u32)) -> Image {
        let usage = wgpu::TextureUsages::STORAGE_BINDING
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC;
        let texture =
            super::texture_2d(device, "relief:props-overlay:hit", size, HIT_FORMAT, usage);
        let view = texture.create_view(&Default::default());
        let entry = |binding, resource| wgpu::BindGroupEntry { binding, resource };
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("relief:props-overlay:group"),
            layout: &self.layout,
            entries: &[
                entry(0, render.as_entire_binding()),
                entry(12, self.view.as_entire_binding()),
                entry(22, wgpu::BindingResource::TextureView(&view)),
            ],
        });
        Image {
            size,
            texture,
            view,
            group,
        }
    }

    /// Draws the props the last [`PropsOverlay::prepare`] marched into the host's pass.
    pub(crate) fn render(&self, pass: &mut wgpu::RenderPass<'_>) {
        let Some(image) = &self.image else {
            return;
        };
        pass.push_debug_group("relief:props-overlay");
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &image.group, &[]);
        pass.draw(0..3, 0..1);
        pass.pop_debug_group();
    }

    /// The image the last march left (see [`crate::World::props_hits`]).
    #[cfg(not(target_arch = "wasm32"))]
    pub(crate) fn hit_texture(&self) -> Option<&wgpu::Texture> {
        self.image.as_ref().map(|i| &i.texture)
    }

    /// GPU memory of its image and buffers, bytes.
    pub(crate) fn bytes(&self) -> u64 {
        let image = self.image.as_ref().map_or(0, |i| {
            u64::from(i.size.0) * u64::from(i.size.1) * super::texel_bytes(HIT_FORMAT)
        });
        image + self.view.size() + self.no_depth.size()
    }
}
