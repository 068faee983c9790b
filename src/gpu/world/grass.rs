//! [`World`]'s grass ([`crate::grass`] places the blades, [`crate::gpu::grass`] scatters and
//! draws them): each frame's scatter after the uniforms, the draw after the terrain in the
//! host's pass, or into the forward mesh's own image where it accumulates.

use super::*;
use crate::gpu::grass::GrassPass;
use crate::grass::Peer;
use crate::{Method, Raster};

impl World {
    /// Builds, rebuilds or drops the grass's passes for the parameters' grass
    /// ([`WorldParams::grass`]: on by default). With it on, each frame the blades within its
    /// draw distance that stand on grass, inside the view, are kept by a compute pass and drawn
    /// after the terrain, depth-tested, by every mesh-based method: into the host's pass, or
    /// with the temporal service on the forward mesh into its own image (accumulated with the
    /// terrain). Their roots stand on the mesh the levels draw (the hybrid's refined surface
    /// lies up to its raise below). The tile draws no grass.
    pub(super) fn update_grass(&mut self, device: &wgpu::Device) -> Result<()> {
        let mut grass = self.params.grass;
        if !grass.on || self.tile.is_some() {
            self.grass = None;
            return Ok(());
        }
        let peer = self.grass.as_ref().and_then(GrassPass::peer);
        if let Some(p) = peer {
            grass.distance = p.distance(&grass);
        }
        if self.grass.as_ref().map(GrassPass::grass) != Some(grass) {
            let mut pass = scoped(device, || GrassPass::new(device, &self.layout, grass))?;
            pass.set_peer(peer);
            self.grass = Some(pass);
        }
        Ok(())
    }

    /// For the benchmark's peer: draws Terra's way with grass ([`Peer`], written again from its
    /// description) in place of relief's, at the grass's density, while grass is on (`None`:
    /// relief's again; turning grass off forgets the peer). Not for a picture: the peer culls
    /// nothing to the view and has no level of detail.
    pub fn set_grass_peer(&mut self, device: &wgpu::Device, peer: Option<Peer>) -> Result<()> {
        // The pass keeps its peer; `update_grass` builds it again for the patch's distance.
        if let Some(pass) = &mut self.grass {
            pass.set_peer(peer);
        }
        self.update_grass(device)
    }

    /// Whether the compute raster draws the frame's blades (the visibility method's, with
    /// 64-bit atomics; not the peer drawn by the GPU's rasteriser).
    pub(super) fn grass_in_compute(&self) -> bool {
        let by_rasteriser = self
            .grass
            .as_ref()
            .and_then(GrassPass::peer)
            .is_some_and(|p| p.rasteriser);
        self.method == Method::Visibility
            && !by_rasteriser
            && self.visibility.as_ref().is_some_and(|v| v.draws_grass())
    }

    /// What draws the blades: the visibility method's compute raster with ids
    /// ([`Raster::Compute`]: with the terrain, into its visibility buffer, shaded in its compute
    /// pass, where the device has 64-bit atomics), or the GPU's rasteriser after the terrain
    /// (every other mesh-based method, and the page). `None` without grass, or for a ray
    /// caster (which draws none).
    pub fn grass_raster(&self) -> Option<Raster> {
        self.grass.as_ref()?;
        match self.method {
            Method::Visibility if self.grass_in_compute() => Some(Raster::Compute),
            Method::Mesh | Method::Visibility | Method::Hybrid => Some(Raster::Hardware),
            _ => None,
        }
    }

    /// GPU memory of the grass's buffers, bytes (0 without grass): 32 MiB of blades and 4 MiB
    /// of their triangles' list, whatever the density.
    pub fn grass_bytes(&self) -> u64 {
        self.grass.as_ref().map_or(0, GrassPass::bytes)
    }

    /// The last frame's blades, read back (blocking; native only): considered (cells within
    /// the draw distance), kept (on grass, inside the view), drawn (up to the buffer's
    /// [`crate::gpu::grass::CAPACITY`]) and the drawn blades' triangles (fewer segments
    /// farther away). `None` without grass.
    #[cfg(not(target_arch = "wasm32"))]
    pub fn grass_counts(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Option<Result<[u32; 4]>> {
        self.grass.as_ref().map(|g| g.read_counts(device, queue))
    }

    /// The first `n` blades the last frame kept, read back (blocking; native only): per blade
    /// its root (camera-relative, metres) and facing; height, lean, curve, width; shade and the
    /// sun's and the sky's occlusion; the wind's push on its tip (x, z) and its segments.
    /// `None` without grass.
    #[cfg(not(target_arch = "wasm32"))]
    pub fn grass_blades(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        n: u32,
    ) -> Option<Result<Vec<[f32; 16]>>> {
        self.grass.as_ref().map(|g| g.read_blades(device, queue, n))
    }

    /// Records the frame's scatter of blades and readies their draw for the frame's targets.
    pub(super) fn encode_grass(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        view: &WorldView,
        timer: Option<&GpuTimer>,
    ) {
        // The last frame's clock, where the temporal service keeps one: the blades' motion
        // since then is what it carries their history along.
        let clock = self.clock();
        let before = self.history.last_clock().unwrap_or(clock);
        let wind = (self.params.wind.velocity(), clock, before);
        let in_compute = self.grass.is_some() && self.grass_in_compute();
        if let Some(vis) = &mut self.visibility {
            vis.set_blade_motion(in_compute);
        }
        let Some(grass) = &mut self.grass else {
            return;
        };
        let seed = self.params.land.seed;
        let high = self.target_size.unwrap_or(view.size).1;
        grass.encode(
            queue,
            encoder,
            (&self.bind_group, seed, view.eye, high),
            wind,
            timer,
        );
        grass.prepare_draw(device, &self.targets, &self.render_uniforms);
        if let Some(history) = &self.mesh_history {
            grass.prepare_draw(device, &history.own_targets(), history.uniforms());
        }
    }

    /// Draws the frame's blades into the host's pass.
    pub(super) fn draw_grass(&self, pass: &mut wgpu::RenderPass<'_>) {
        if let Some(grass) = &self.grass {
            grass.draw(pass, &self.targets, &self.render_uniforms);
        }
    }
}
