//! [`World`]'s props ([`crate::props`] is what they are and where they stand,
//! [`crate::gpu::props`] their passes): each frame's scatter after the uniforms; the march
//! between the raster and the shading of the visibility method (`vis_frame.rs`), or the
//! overlay's march and its draw after the terrain ([`crate::gpu::props_overlay`]).

use super::*;
use crate::gpu::props::{March, PropsPass};
use crate::gpu::props_overlay::PropsOverlay;
use crate::props::Scene;

impl World {
    /// Builds, rebuilds or drops the props' passes for the parameters' props
    /// ([`WorldParams::props`]: off by default) and the world's scene
    /// ([`World::set_props_scene`]). The tile has none.
    pub(super) fn update_props(&mut self, device: &wgpu::Device) -> Result<()> {
        let props = self.params.props;
        if !props.on || self.tile.is_some() {
            self.props = None;
            return Ok(());
        }
        let same = self
            .props
            .as_ref()
            .is_some_and(|p| p.drawn() == (&self.props_scene, props));
        if !same {
            let pass = scoped(device, || {
                PropsPass::new(device, &self.layout, (&self.props_scene, props))
            })??;
            self.props = Some(pass);
            self.props_map.forget();
        }
        Ok(())
    }

    /// Sets what the world's props are: their materials, kinds and props at given places
    /// (the shipped landscape's by default, [`crate::props::kinds::landscape`]). Validated
    /// against the parameters' [`WorldParams::props`] here, whether props are on or not; an
    /// error names the key, the value and the limit, and leaves the world's scene as it was.
    pub fn set_props_scene(&mut self, device: &wgpu::Device, scene: Scene) -> Result<()> {
        scene.compile(&self.params.props)?;
        let old = std::mem::replace(&mut self.props_scene, scene);
        if let Err(e) = self.update_props(device) {
            self.props_scene = old;
            return Err(e);
        }
        Ok(())
    }

    /// The distance from world point `p` (metres) to the nearest prop, by the props' twin
    /// ([`crate::props::query::distance`]): for a host placing its own things among them.
    /// Negative inside a prop; a bound on the distance to its surface (exact for props of exact
    /// primitives), over half a cell where no prop is that near. `None` where props are off or
    /// none stands within a cell of `p` (nothing nearer than half a cell). The twin stands
    /// each prop whole on the continuous surface: near the eye the drawn props stand within
    /// centimetres of it.
    pub fn props_distance(&self, p: glam::DVec3) -> Option<f64> {
        let props = self.params.props;
        if !props.on || self.tile.is_some() {
            return None;
        }
        let tapes = self.props_scene.compile(&props).ok()?;
        let water = (!self.params.no_water)
            .then(|| f64::from(self.params.water_level) / self.params.land.peak_height);
        crate::props::query::distance(
            (&self.props_scene, &tapes, &props),
            (&self.params.land, water),
            p,
        )
        .map(|(d, _)| d)
    }

    /// Marches the props' view rays the seed's way (the benchmark's peer, `relief bench
    /// --world endless --only props`): from the eye, every step reading the whole fields of
    /// the props of the 3x3 cells around it, at most half a cell, up to `steps` steps and the
    /// draw distance, without the band, the bounds or the raster's depth; `None`: relief's
    /// march (the default). Lasts while the props' passes do (a new scene or props keys make
    /// new ones).
    pub fn set_props_peer(&mut self, steps: Option<u32>) {
        if let Some(props) = &mut self.props {
            props.set_peer(steps);
        }
    }

    /// What the world's props are ([`World::set_props_scene`]).
    pub fn props_scene(&self) -> &Scene {
        &self.props_scene
    }

    /// Whether this frame's method draws the props, where props are on: every mesh-based
    /// method does, the visibility method rasterised in compute ([`crate::Raster::Compute`])
    /// marching them between its raster and its shading, the others through the props'
    /// overlay ([`World::props_overlaid`]) where the host's pass has depth.
    pub fn draws_props(&self) -> bool {
        self.props_marched() || self.props_overlaid()
    }

    /// Whether the props are marched between the visibility method's compute raster and its
    /// shading, which shades them with their shadows on the terrain and the grass.
    fn props_marched(&self) -> bool {
        self.props.is_some()
            && self.method == Method::Visibility
            && self
                .visibility
                .as_ref()
                .is_some_and(Visibility::marches_props)
    }

    /// Whether the props are drawn over the terrain by the props' overlay
    /// (`src/gpu/props_overlay.rs`): with the forward mesh, the hybrid, and the visibility
    /// method rasterised by the GPU, where the host's pass has depth. Their terrain takes the
    /// props' shadows from the props' shade map (`src/gpu/props_map.rs`), their grass none.
    pub fn props_overlaid(&self) -> bool {
        self.props.is_some() && self.targets.depth_format.is_some() && !self.props_marched()
    }

    /// GPU memory of the props' buffers and images, bytes (0 without props).
    pub fn props_bytes(&self) -> u64 {
        self.props.as_ref().map_or(0, PropsPass::bytes)
            + self.props_overlay.as_ref().map_or(0, PropsOverlay::bytes)
            + self.props.as_ref().map_or(0, |_| self.props_map.bytes())
    }

    /// Records the frame's scatter of props where the method draws them, through `view` (the
    /// frame's, jittered where the temporal service accumulates), and the overlay's march
    /// through `still` (unjittered: the overlay does not accumulate).
    pub(super) fn encode_props(
        &mut self,
        (device, queue, encoder): (&wgpu::Device, &wgpu::Queue, &mut wgpu::CommandEncoder),
        (view, still): (&WorldView, &WorldView),
        timer: Option<&GpuTimer>,
    ) {
        let marched = self.props_marched();
        let overlaid = self.props_overlaid();
        if let Some(vis) = &mut self.visibility {
            vis.set_props(marched);
        }
        if !overlaid {
            self.props_overlay = None;
        } else if self.props_map.allocate(device) {
            // The shade map is bound from now on, in the world's groups and the visibility
            // method's.
            if let Some(vis) = &mut self.visibility {
                vis.unbind();
            }
            self.rebind(device);
        }
        let Some(props) = self.props.as_ref().filter(|_| marched || overlaid) else {
            return;
        };
        let size = self.target_size.unwrap_or(view.size);
        props.encode(
            queue,
            encoder,
            (&self.bind_group, self.params.land.seed, view.eye),
            (
                pixels_per_tan(size, view),
                self.water_height(),
                if marched {
                    March::Raster
                } else {
                    March::Unbounded
                },
            ),
            timer,
        );
        if let Some(grass) = &self.grass {
            let blades = grass.raster_blades();
            props.encode_grass(device, encoder, (blades.blades, blades.counts));
        }
        if overlaid {
            let frame = (
                view.eye,
                self.sky().sun_direction().to_array(),
                self.heights_pending() == 0,
            );
            self.props_map.encode(
                (device, queue, encoder),
                props,
                (&self.bind_group_unmapped, &self.layout),
                frame,
                timer,
            );
            let overlay = self
                .props_overlay
                .get_or_insert_with(|| PropsOverlay::new(device, &self.targets));
            let (near, far) = self.near_far;
            overlay.prepare(
                (device, queue, encoder),
                props,
                (&self.render_uniforms, &self.world_uniforms),
                (still.relative_matrix(near, far), size),
                timer,
            );
        }
    }

    /// Forgets what the props' shade map holds: the next frame that draws the props through
    /// the overlay bakes it whole, as a turned sun or new props make it (the benchmark measures
    /// that cost this way).
    pub fn forget_props_map(&mut self) {
        self.props_map.forget();
    }

    /// Records the reference's props over a cast through `view` (the cast's: see
    /// [`crate::gpu::props_reference`]): the frame's uniforms, the props' scatter for the
    /// cast's samples, and their march into what `m` gives. Nothing where props are off.
    #[cfg(not(target_arch = "wasm32"))]
    pub(crate) fn encode_reference_props(
        &mut self,
        (device, queue, encoder): (&wgpu::Device, &wgpu::Queue, &mut wgpu::CommandEncoder),
        view: &WorldView,
        m: &crate::gpu::props_reference::ReferenceMarch<'_>,
    ) {
        self.write_uniforms(queue, view);
        let Some(props) = &self.props else {
            return;
        };
        props.encode(
            queue,
            encoder,
            (&self.bind_group, self.params.land.seed, view.eye),
            (pixels_per_tan(m.size, view), self.water_height(), m.march),
            None,
        );
        props.encode_march(
            device,
            encoder,
            (m.render, &self.world_uniforms, m.vis, m.depth),
            (m.hit, m.size, m.march),
            None,
        );
    }

    /// Records the props' part in the reference's blades after [`World::encode_reference_props`]
    /// (see [`PropsPass::encode_grass_reference`]): the cut inside the props, their shadow and
    /// occlusion on the rest, by the sun of the cast's `render` uniforms. Nothing where props
    /// are off.
    #[cfg(not(target_arch = "wasm32"))]
    pub(crate) fn encode_reference_grass(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        render: &wgpu::Buffer,
        blades: (&wgpu::Buffer, &wgpu::Buffer),
    ) {
        if let Some(props) = &self.props {
            props.encode_grass_reference(device, encoder, render, blades);
        }
    }

    /// The water's normalised level, where there is water: what the props' scatter keeps
    /// props out of.
    fn water_height(&self) -> Option<f32> {
        (!self.params.no_water)
            .then(|| (f64::from(self.params.water_level) / self.params.land.peak_height) as f32)
    }

    /// Draws the props the overlay marched, after the terrain.
    pub(super) fn render_props(&self, pass: &mut wgpu::RenderPass<'_>) {
        if let Some(overlay) = &self.props_overlay {
            overlay.render(pass);
        }
    }

    /// The last frame's placed props, read back (blocking; native only): the grid's side and
    /// its records: per prop its foot (camera-relative) and scale (0: none), the cosine and sine of
    /// its turn, its kind and its noise's seed (bits), its shade, the terrain's horizon and valley
    /// and the foot's normalised height, its sphere's centre (camera-relative) and radius. `None`
    /// without props.
    #[cfg(not(target_arch = "wasm32"))]
    pub fn props_records(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Option<Result<(u32, Vec<[f32; 16]>)>> {
        let props = self.props.as_ref()?;
        Some(props.read_records(device, queue).map(|r| (props.side(), r)))
    }

    /// What the last frame's props' march left each pixel, read back (blocking; native only),
    /// row by row: the prop's depth (bits; 1.0 where none), its normal (two snorm16), its
    /// albedo's square root (rgb8) and the sky's share (a8), the sun's share (bits). For a pixel
    /// without a prop, the props' occlusion of the sky (bits) in the normal's place and their
    /// shadow in the sun's, on what the raster drew (1.0 for the overlay, which reads no
    /// raster). `None` where the frame's method marched no props.
    #[cfg(not(target_arch = "wasm32"))]
    pub fn props_hits(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Option<Result<Vec<[u32; 4]>>> {
        let texture = match &self.props_overlay {
            Some(overlay) => overlay.hit_texture()?,
            None => self.visibility.as_ref()?.prop_hit_texture()?,
        };
        let bytes = crate::gpu::headless::read_texture(device, queue, texture);
        Some(bytes.map(|b| {
            bytemuck::cast_slice::<u8, u32>(&b)
                .chunks_exact(4)
                .map(|c| [c[0], c[1], c[2], c[3]])
                .collect()
        }))
    }

    /// The last frame's props counted (blocking; native only): those placed around the eye,
    /// and those of them whose sphere lies at least partly inside the view. `None` without
    /// props.
    #[cfg(not(target_arch = "wasm32"))]
    pub fn props_counts(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Option<Result<[u32; 2]>> {
        let records = match self.props_records(device, queue)? {
            Ok((_, r)) => r,
            Err(e) => return Some(Err(e)),
        };
        let m = self.matrix.transpose();
        let planes = [
            m.w_axis + m.x_axis,
            m.w_axis - m.x_axis,
            m.w_axis + m.y_axis,
            m.w_axis - m.y_axis,
            m.z_axis,
            m.w_axis - m.z_axis,
        ];
        let (mut placed, mut seen) = (0, 0);
        for r in records.iter().filter(|r| r[3] > 0.0) {
            placed += 1;
            let c = Vec3::new(r[12], r[13], r[14]);
            let inside = planes
                .iter()
                .all(|p| p.truncate().dot(c) + p.w >= -r[15] * p.truncate().length());
            seen += u32::from(inside);
        }
        Some(Ok([placed, seen]))
    }
}

/// Pixels a unit of tan(angle) spans on an image of `size` through `view` (its height over
/// twice the tangent of half the vertical field of view).
fn pixels_per_tan(size: (u32, u32), view: &WorldView) -> f32 {
    size.1 as f32 / (2.0 * (0.5 * view.fov_y).tan())
}
