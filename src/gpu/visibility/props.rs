//! The visibility method's part in the props ([`crate::gpu::props`]): the image their march
//! leaves for the shading, and whether the method marches them.

use super::Visibility;

/// The binding of the props' image (`prop_hit` in `wgsl/visibility.wgsl`, `overlay_hit` in
/// `wgsl/props_overlay.wgsl`).
pub(crate) fn hit_entry(visibility: wgpu::ShaderStages) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding: 22,
        visibility,
        ty: wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Uint,
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        },
        count: None,
    }
}

impl Visibility {
    /// Whether the frame has props (see [`Visibility::marches_props`]): the props' image is
    /// made with the next frame's images, or dropped.
    pub(crate) fn set_props(&mut self, on: bool) {
        if on != self.props {
            self.props = on;
            self.images = None;
        }
    }

    /// Whether it marches the frame's props between its raster and its shading: where the
    /// compute raster draws (the visibility method's and, on the page, its 32-bit raster).
    pub fn marches_props(&self) -> bool {
        !self.hybrid && self.compute_raster.is_some()
    }

    /// The props' image of the last frame that marched them.
    #[cfg(not(target_arch = "wasm32"))]
    pub(crate) fn prop_hit_texture(&self) -> Option<&wgpu::Texture> {
        let images = self.images.as_ref()?;
        (self.props && self.marches_props()).then_some(&images.prop_hit_texture)
    }

    /// The props' image for a frame of `size` (1x1 where the frame has no props) and its view.
    pub(super) fn prop_hit_image(
        &self,
        device: &wgpu::Device,
        size: (u32, u32),
    ) -> (wgpu::Texture, wgpu::TextureView) {
        let hit_size = if self.props && self.marches_props() {
            size
        } else {
            (1, 1)
        };
        let usage = wgpu::TextureUsages::STORAGE_BINDING
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC;
        let texture = crate::gpu::texture_2d(
            device,
            "relief:visibility:prop-hit",
            hit_size,
            crate::gpu::props::HIT_FORMAT,
            usage,
        );
        let view = texture.create_view(&Default::default());
        (texture, view)
    }
}
