//! [`World`]'s frame into the host's target: the terrain and its sky in the host's pass (or
//! the compute-shaded frame presented without one), then the list of layers.

use super::*;

impl World {
    /// Writes the frame that [`World::prepare`] shaded in compute straight into `target`,
    /// with no render pass, for a host whose frame the world fills: `target` is then all the
    /// frame needs (no depth is written). On a compute chip such as the H100 a full-screen draw
    /// in a render pass costs more than the shading itself (docs/bench/present in git history,
    /// up to a57006a).
    ///
    /// Returns true, having recorded the frame's present (timed as [`Slot::Present`]), where
    /// the method shades in compute (the visibility method and the hybrid), the sky is on
    /// (every pixel opaque) and `target` is a single-sampled 2D texture of the frame's size
    /// that is either RGBA8 (not sRGB) with `STORAGE_BINDING`, which one compute pass stores
    /// the frame into (the fastest: `relief render`'s image is such a texture, drawn by render
    /// passes through an sRGB view of it), or RGBA8 or BGRA8 (sRGB or not) with `COPY_DST`,
    /// which a compute pass packs the frame for and a copy fills. Both round each value in the
    /// shader; the stored one is the packed one wherever the device's 8-bit store rounds to
    /// the nearest, down or toward zero (lavapipe's and the H100's do).
    /// Otherwise (and where layers, grass that the method does not draw in compute
    /// ([`World::grass_raster`]) or the props' overlay ([`World::props_overlaid`]) draw after
    /// the terrain) it records nothing and returns false: draw
    /// with [`World::render`] in a render pass.
    pub fn present(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        target: &wgpu::Texture,
        timer: Option<&GpuTimer>,
    ) -> bool {
        match (self.method, &self.visibility) {
            // The layers, and grass drawn by the GPU's rasteriser, draw into a render pass:
            // with any, the frame needs one.
            (Method::Visibility | Method::Hybrid, Some(vis))
                if self.layers.is_empty()
                    && (self.grass.is_none() || self.grass_in_compute())
                    && self.props_overlay.is_none() =>
            {
                vis.present(encoder, target, timer)
            }
            _ => false,
        }
    }

    /// Adds `layer` to the frame: each [`World::prepare`] prepares it after the terrain's
    /// uniforms, and [`World::render`] draws it after the terrain, depth-tested. With a layer
    /// the frame needs a render pass: [`World::present`] declines it.
    pub fn push_layer(&mut self, layer: Box<dyn Layer>) {
        self.layers.push(layer);
    }

    /// Removes every layer from the frame and gives them back.
    pub fn take_layers(&mut self) -> Vec<Box<dyn Layer>> {
        std::mem::take(&mut self.layers)
    }

    /// The names of the layers drawn after the terrain, in the order they draw.
    pub fn layers(&self) -> Vec<&str> {
        self.layers.iter().map(|l| l.name()).collect()
    }

    /// Draws the patches selected by the last [`World::prepare`], and the sky behind them
    /// unless [`Shading::sky`] is off, into the host's pass (whose depth, if any, is cleared to
    /// 1.0).
    ///
    /// With the visibility method ([`World::set_method`]) it composites the image that
    /// [`World::prepare`] shaded, colour and depth.
    pub fn render(&self, pass: &mut wgpu::RenderPass<'_>) {
        self.render_terrain(pass);
        self.render_props(pass);
        for layer in &self.layers {
            layer.render(pass);
        }
    }

    /// The terrain, its water and its sky.
    pub(super) fn render_terrain(&self, pass: &mut wgpu::RenderPass<'_>) {
        if let (Method::Visibility | Method::Hybrid, Some(vis)) = (self.method, &self.visibility) {
            // Its compute pass shaded the sky too: one full-screen draw.
            vis.composite(pass);
            if !self.grass_in_compute() {
                self.draw_grass(pass);
            }
            return;
        }
        // The forward mesh's history, where it accumulates (its own pass drew the sky and the
        // grass).
        if self
            .mesh_history
            .as_ref()
            .is_some_and(|h| h.composite(pass))
        {
            return;
        }
        self.sky.around(pass, self.shading.sky, |pass| {
            let [whole, subs] = self.instance_counts;
            if whole + subs == 0 {
                return;
            }
            pass.push_debug_group("relief:world");
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &self.bind_group, &[]);
            draw_patches(
                pass,
                (&self.instances, self.instance_counts),
                (&self.indices, self.index_counts),
            );
            pass.pop_debug_group();
            self.draw_grass(pass);
        });
    }
}

/// Draws the patches of `instances` (whole ones, then sub-patches) with the pipeline and bind
/// group already set.
pub(super) fn draw_patches(
    pass: &mut wgpu::RenderPass<'_>,
    (instances, [whole, subs]): (&wgpu::Buffer, [u32; 2]),
    (indices, [patch, sub]): (&wgpu::Buffer, [u32; 2]),
) {
    pass.set_vertex_buffer(0, instances.slice(..));
    pass.set_index_buffer(indices.slice(..), wgpu::IndexFormat::Uint32);
    if whole > 0 {
        pass.draw_indexed(0..patch, 0, 0..whole);
    }
    if subs > 0 {
        pass.draw_indexed(patch..patch + sub, 0, whole..whole + subs);
    }
}
