//! The visibility method's frame into the host's target: stored or packed and copied in
//! without a render pass ([`Visibility::present`]), or composited in the host's pass.

use super::targets::*;
use super::*;

impl Visibility {
    /// Writes the last shaded image straight into `target`, with no render pass (timed as
    /// [`Slot::Present`]), where the image is opaque (the sky on) and `target` is a
    /// single-sampled 2D texture of its size: stored in one compute pass where `target` is
    /// RGBA8 (not sRGB) with `STORAGE_BINDING`; otherwise, where it is RGBA8 or BGRA8 (sRGB or
    /// not) with `COPY_DST` and the frame's bytes fit one storage buffer on the device, packed
    /// as the target's bytes by a compute pass and copied in. Else it records nothing and
    /// returns false, and [`Visibility::composite`] draws it. No depth is written.
    pub(crate) fn present(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        target: &wgpu::Texture,
        timer: Option<&GpuTimer>,
    ) -> bool {
        let Some(images) = &self.images else {
            return false;
        };
        let (w, h) = images.size;
        let fits = target.width() == w
            && target.height() == h
            && target.depth_or_array_layers() == 1
            && target.dimension() == wgpu::TextureDimension::D2
            && target.sample_count() == 1
            && self.opaque;
        if !fits {
            return false;
        }
        if target.format() == STORE_FORMAT
            && target
                .usage()
                .contains(wgpu::TextureUsages::STORAGE_BINDING)
        {
            self.store_into(encoder, target, images, timer);
            return true;
        }
        let Some((presented, present_groups)) = &images.presented else {
            return false;
        };
        let present_group = &present_groups[self.shown];
        let copies = target.usage().contains(wgpu::TextureUsages::COPY_DST);
        let Some(bgra) = present_order(target.format()).filter(|_| copies) else {
            return false;
        };
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("relief:visibility:present-pass"),
                timestamp_writes: timer.map(|t| t.compute_begins(Slot::Present)),
            });
            pass.set_pipeline(&self.present[usize::from(bgra)]);
            pass.set_bind_group(0, present_group, &[]);
            pass.dispatch_workgroups(
                w.div_ceil(crate::gpu::WORKGROUP),
                h.div_ceil(crate::gpu::WORKGROUP),
                1,
            );
        }
        encoder.copy_buffer_to_texture(
            wgpu::TexelCopyBufferInfo {
                buffer: presented,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(present_pitch(w)),
                    rows_per_image: Some(h),
                },
            },
            target.as_image_copy(),
            wgpu::Extent3d {
                width: w,
                height: h,
                depth_or_array_layers: 1,
            },
        );
        if let Some(t) = timer {
            t.end_after(encoder, Slot::Present);
        }
        true
    }

    /// The present's one compute pass storing the frame into `target` (RGBA8 with
    /// `STORAGE_BINDING`, checked by the caller).
    fn store_into(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        target: &wgpu::Texture,
        images: &Images,
        timer: Option<&GpuTimer>,
    ) {
        // The first mip level alone: a storage binding takes one.
        let view = target.create_view(&wgpu::TextureViewDescriptor {
            label: Some("relief:visibility:store-target"),
            format: Some(STORE_FORMAT),
            mip_level_count: Some(1),
            ..Default::default()
        });
        let group = self.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("relief:visibility:store-group"),
            layout: &self.store_layout,
            entries: &[
                entry(12, self.uniforms.as_entire_binding()),
                entry(
                    13,
                    wgpu::BindingResource::TextureView(&images.shown[self.shown]),
                ),
                entry(21, wgpu::BindingResource::TextureView(&view)),
            ],
        });
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("relief:visibility:store-pass"),
            timestamp_writes: timer.map(|t| t.compute_writes(Slot::Present)),
        });
        pass.set_pipeline(&self.store);
        pass.set_bind_group(0, &group, &[]);
        let (w, h) = images.size;
        pass.dispatch_workgroups(
            w.div_ceil(crate::gpu::WORKGROUP),
            h.div_ceil(crate::gpu::WORKGROUP),
            1,
        );
    }

    /// Draws the last shaded image into the host's pass (nothing before the first
    /// [`Visibility::encode`]).
    pub(crate) fn composite(&self, pass: &mut wgpu::RenderPass<'_>) {
        let Some(images) = &self.images else {
            return;
        };
        pass.push_debug_group("relief:visibility:composite");
        pass.set_pipeline(&self.composite[usize::from(self.opaque)]);
        pass.set_bind_group(0, &images.composite_groups[self.shown], &[]);
        pass.draw(0..3, 0..1);
        pass.pop_debug_group();
    }
}
