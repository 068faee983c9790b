//! [`World`]'s grass ([`crate::grass`] places the blades, [`crate::gpu::grass`] scatters and
//! draws them): each frame's scatter after the uniforms, the draw after the terrain in the
//! host's pass, or into the forward mesh's own image where it accumulates.

use super::*;
use crate::gpu::grass::GrassPass;
use crate::grass::Grass;

impl World {
    /// Grows `grass` in the endless world (`None`: none, the default). Each frame the blades
    /// within its draw distance that stand on grass, inside the view, are kept by a compute
    /// pass and drawn after the terrain, depth-tested, by every mesh-based method: into the
    /// host's pass, or with the temporal service on the forward mesh into its own image
    /// (accumulated with the terrain). Their roots stand on the mesh the levels draw (the
    /// hybrid's refined surface lies up to its raise below). A new setting starts a new
    /// history. Refused for the tile, which draws no grass, and for values out of range.
    pub fn set_grass(&mut self, device: &wgpu::Device, grass: Option<Grass>) -> Result<()> {
        if let Some(g) = &grass {
            g.validate()?;
            if self.tile.is_some() {
                return Err(Error::invalid(
                    "grass",
                    "on",
                    "off for the tile (the endless world grows grass)",
                ));
            }
        }
        if grass == self.grass() {
            return Ok(());
        }
        self.history.reset("grass");
        self.grass = match grass {
            Some(g) => Some(scoped(device, || GrassPass::new(device, &self.layout, g))?),
            None => None,
        };
        Ok(())
    }

    /// GPU memory of the grass's buffers, bytes (0 without grass): 24 MiB of blades, whatever
    /// the density.
    pub fn grass_bytes(&self) -> u64 {
        self.grass.as_ref().map_or(0, GrassPass::bytes)
    }

    /// The grass grown ([`World::set_grass`]).
    pub fn grass(&self) -> Option<Grass> {
        self.grass.as_ref().map(GrassPass::grass)
    }

    /// Records the frame's scatter of blades and readies their draw for the frame's targets.
    pub(super) fn encode_grass(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        view: &WorldView,
    ) {
        let Some(grass) = &mut self.grass else {
            return;
        };
        let seed = self.params.land.seed;
        grass.encode(queue, encoder, (&self.bind_group, seed, view.eye));
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
