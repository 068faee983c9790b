//! The uniform blocks the endless world's passes share, mirrored field by field by the WGSL
//! they feed. A leaf: the passes import these, never each other, for their layouts.

use crate::clipmap::MAX_LEVELS;

/// Mirrors `Level` in `wgsl/world.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct LevelUniforms {
    /// Level origin in finest samples relative to the camera's reference sample.
    pub origin_rel: [i32; 2],
    /// Origin less twice the coarser level's, in this level's samples.
    pub delta: [i32; 2],
    /// Origin modulo the texture side.
    pub origin_mod: [u32; 2],
    /// log2 of spacing over the finest spacing.
    pub shift: u32,
    /// Texture-array layer.
    pub layer: u32,
    /// Index of the coarser level.
    pub coarse: u32,
    /// 1 when there is a coarser level to morph towards.
    pub has_coarse: u32,
    /// The eye in this level's samples from its first sample.
    pub eye_local: [f32; 2],
    /// The drawn bounds in this level's samples from its first sample (x0, z0, x1, z1):
    /// vertices are clamped into them (huge for the endless world).
    pub clip: [f32; 4],
    /// Metres the vertices are raised by: 0, or for [`crate::Method::Hybrid`] the level's raise
    /// ([`crate::World::level_raise`]: the mesh then lies on or above the surface).
    pub raise: f32,
    /// The level whose light this level is drawn with: its own index once its light is
    /// baked, before that a coarser level's, or `u32::MAX` while none has light (unshadowed).
    pub light_from: u32,
    /// Padding to 16 bytes.
    pub _pad: [u32; 2],
}

/// Mirrors `WorldUniforms` in `wgsl/world.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct WorldUniforms {
    /// xz: eye less the reference sample, metres; y: eye height; w: finest spacing.
    pub eye: [f32; 4],
    /// Cells per level side.
    pub cells: u32,
    /// Cells per patch side.
    pub patch_cells: u32,
    /// Texture side.
    pub side: u32,
    /// 1 while morphing.
    pub morphing: u32,
    /// Morph band: start and end, in a level's cells of distance from the eye.
    pub morph: [f32; 2],
    /// World height of normalised height 1.
    pub peak: f32,
    /// How far the first active level is morphed as a whole ([`crate::clipmap::Clipmap::fade`]).
    pub fade: f32,
    /// Index of the first active level.
    pub first: u32,
    /// The tile's: one over its width in metres (0: the endless world, no tile textures).
    pub tile_inv: f32,
    /// The tile's: the eye less the tile's first corner, metres (x, z).
    pub tile_eye: [f32; 2],
    /// The levels.
    pub levels: [LevelUniforms; MAX_LEVELS],
}
