//! [`World`]'s frame in the visibility and hybrid methods: the raster, the props' march and
//! the compute shading recorded after the frame's uniforms.

use super::*;
use crate::gpu::visibility::CloudFrame;

impl World {
    /// Records the visibility method's raster pass and compute shading of the last prepared
    /// frame, drawn through `view` (jittered where the temporal service runs; `unjittered`
    /// the view itself).
    pub(super) fn encode_visibility(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        (view, unjittered): (&WorldView, &WorldView),
        timer: Option<&GpuTimer>,
    ) -> Result<()> {
        let size = self.target_size.unwrap_or(view.size);
        if let Some(words) = self
            .visibility
            .as_ref()
            .and_then(Visibility::raster_depth_words)
        {
            // Its depth buffer is bound whole: 4 bytes a pixel (8 with each pixel's triangle)
            // within the device's limit.
            let per_pixel = 4 * u64::from(words);
            let bytes = per_pixel * u64::from(size.0) * u64::from(size.1);
            let limit = device.limits().max_storage_buffer_binding_size;
            if bytes > limit {
                return Err(Error::invalid(
                    "image size for the compute raster",
                    format!("{}x{}", size.0, size.1),
                    format!(
                        "at most {} pixels on this device (its depth buffer, {per_pixel} bytes a \
                         pixel, is bound whole); --raster hardware draws larger",
                        limit / per_pixel
                    ),
                ));
            }
        }
        self.vis_size = size;
        let rays = if self.method == Method::Hybrid {
            // The region the levels draw (the clipmap's coarsest square around the eye), from
            // this world's layout: measuring it again each frame cost 100 ms of CPU.
            let region = self.map.drawn_region(view.eye.x, view.eye.z);
            let method = crate::gpu::raymarch::RayMethod::Reference;
            Some(crate::gpu::world_rays::WorldRayUniforms::with_slopes(
                &self.params,
                view,
                (method, size, region),
                &self.slopes,
            )?)
        } else {
            None
        };
        let blades = self
            .grass_in_compute()
            .then_some(self.grass.as_ref())
            .flatten();
        let clouds = self.cloud_frame(unjittered);
        let Some(vis) = self.visibility.as_mut() else {
            return Ok(());
        };
        vis.set_cloud_frame(clouds);
        let bindings = WorldBindings {
            render: &self.render_uniforms,
            world: &self.world_uniforms,
            tile_terrain: &self.tile_textures.terrain,
            tile_normals: &self.tile_textures.normals,
            tile_sampler: &self.tile_textures.sampler,
            props_map: &self.props_map,
            air_shadow: &self.shafts.map,
            instances: &self.instances,
        };
        let draw = |pass: &mut wgpu::RenderPass<'_>| {
            pass.set_bind_group(0, &self.bind_group, &[]);
            draw_patches(
                pass,
                (&self.instances, self.instance_counts),
                (&self.indices, self.index_counts),
            );
        };
        let patches = Patches {
            group: &self.bind_group,
            counts: self.instance_counts,
            cells: [self.map.patch, self.map.sub_cells()],
            passes: self.raster_passes,
            blades: blades.map(crate::gpu::grass::GrassPass::raster_blades),
            props: self.props.as_ref(),
        };
        vis.encode(
            device,
            queue,
            encoder,
            &bindings,
            (self.matrix, size, self.shading.sky),
            (draw, &patches, rays.as_ref()),
            timer,
        );
        if let Some((marched, _)) = &mut self.stats.clouds {
            *marched = vis.clouds_marched();
        }
        Ok(())
    }

    /// What the visibility method's clouds' image needs of the next frame, where it keeps one:
    /// the frame has clouds, marched a fraction a frame ([`Clouds::reproject`]), and the
    /// temporal service runs.
    ///
    /// [`Clouds::reproject`]: crate::world::clouds::Clouds::reproject
    fn cloud_frame(&self, view: &WorldView) -> Option<CloudFrame> {
        let c = &self.params.clouds;
        let on = self.tile.is_none() && c.on() && c.reproject && self.temporal_active();
        let (near, far) = self.near_far;
        on.then(|| CloudFrame {
            matrix: view.relative_matrix(near, far),
            eye: view.eye,
            drift: self.params.wind.velocity() * self.clock(),
            layer: [c.coverage, c.base, c.top, c.kind, c.steps as f32],
            sun: self.sky().sun_direction(),
        })
    }
}
