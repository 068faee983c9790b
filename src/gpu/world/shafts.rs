//! [`World`]'s light shafts' part: the terrain's shadow-height map
//! ([`crate::gpu::air_shadow`]), baked where the frame draws the terrain's shadows in the air,
//! and read back for tests and tools.

use super::*;
#[cfg(not(target_arch = "wasm32"))]
use crate::gpu::air_shadow::ShaftsMap;
use crate::gpu::air_shadow::{AirShadow, TEXELS};

/// The light shafts' shadow-height map a world holds (whole for the endless world, a texel for
/// the tile, which has no clouds, so draws no shafts, yet binds it) and what it is baked for.
pub(super) struct Shafts {
    pub(super) map: AirShadow,
    /// The sun the frame bakes it for, where the frame draws the terrain's shadows in the air.
    pub(super) sun: Option<Vec3>,
    /// Frames whose bake of the levels' heights baked texels: the map is baked again after one.
    level_bakes: u64,
}

impl Shafts {
    pub(super) fn new(device: &wgpu::Device, tile: bool) -> Self {
        Self {
            map: AirShadow::new(device, if tile { 1 } else { TEXELS }),
            sun: None,
            level_bakes: 0,
        }
    }
}

impl World {
    /// Records the map's bake where the frame (its uniforms written, its levels' bake of
    /// `texels` recorded) draws the terrain's shadows in the air and its sun, the eye's texel or
    /// the levels changed since the last.
    pub(super) fn encode_shafts(
        &mut self,
        (device, queue, encoder): (&wgpu::Device, &wgpu::Queue, &mut wgpu::CommandEncoder),
        (view, texels): (&WorldView, u64),
        timer: Option<&GpuTimer>,
    ) {
        let s = &mut self.shafts;
        s.level_bakes += u64::from(texels > 0);
        if let Some(sun) = s.sun {
            s.map.encode(
                (device, queue, encoder),
                (&self.world_uniforms, &array_view(&self.texture)),
                (view.eye, sun, s.level_bakes),
                timer,
            );
        }
    }

    /// GPU memory of the light shafts' shadow-height map, bytes: 2 MiB for the endless world,
    /// held whether or not its frames draw the terrain's shadows in the air (clouds with their
    /// shafts, fog, the sun up; only those frames bake it), one texel for the tile.
    pub fn shafts_bytes(&self) -> u64 {
        self.shafts.map.bytes()
    }

    /// The light shafts' shadow-height map as the last frame that drew the terrain's shadows in
    /// the air left it (`None` where no frame has): where the air stands in the terrain's shadow,
    /// for tests and tools (its truth is [`crate::light::air_lit_by_ray`]).
    #[cfg(not(target_arch = "wasm32"))]
    pub fn shafts_map(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<Option<ShaftsMap>> {
        let Some((texture, texel)) = self.shafts.map.baked() else {
            return Ok(None);
        };
        let bytes = crate::gpu::headless::read_texture(device, queue, texture)?;
        Ok(Some(ShaftsMap::unpack(&bytes, texel)))
    }
}
