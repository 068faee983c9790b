//! The endless world's ray casters (`wgsl/world_rays.wgsl`): the reference (every octave,
//! conservative steps accelerated by the octaves' amplitude bounds, bisection) that the mesh is
//! measured against, and the seed's heightfield march, each bounded by the region the mesh
//! draws. They run in [`super::raymarch::RayMarcher`]'s targets and pipelines.

use glam::DVec3;

use crate::camera::WorldView;
use crate::clipmap::{finest_log2, max_eye, Clipmap};
use crate::error::{Error, Result};
use crate::method::{RayMethod, SeedMarch};
use crate::world::WorldParams;

/// Step limit of the world's rays. Grazing rays that skim a slope for kilometres take small
/// steps (the eroded terrain's Lipschitz bound is about 20 times its steepest measured slope), so
/// the world allows more than the tile's [`super::raymarch::MAX_STEPS`].
pub const MAX_STEPS: u32 = 16384;

/// Octave bounds the uniforms carry (the most octaves a world has).
pub(crate) const MAX_OCTAVES: usize = 24;

/// Mirrors `WorldRayUniforms` in `wgsl/world_rays.wgsl` field by field.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct WorldRayUniforms {
    /// Inverse of the camera-relative projection times view.
    pub inv_view_proj: [[f32; 4]; 4],
    /// xz: the eye less the reference sample's position; y: the eye's height (metres).
    pub eye: [f32; 4],
    /// The reference sample (the eye's), in samples of `2^base_log2` metres.
    pub reference: [i32; 2],
    /// log2 of the reference samples' spacing.
    pub base_log2: i32,
    /// Hash seed.
    pub seed: u32,
    /// Octaves of the surface.
    pub octaves: u32,
    /// 0: fBm, 1: eroded.
    pub terrain: u32,
    /// log2 of octave 0's cell in metres.
    pub feature_log2: i32,
    /// 0: reference, 1: the seed's march.
    pub method: u32,
    /// Octaves while marching (seed's march).
    pub march_octaves: u32,
    /// Octaves for the normal (seed's march).
    pub normal_octaves: u32,
    /// Step limit per ray.
    pub max_steps: u32,
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Amplitude ratio between octaves.
    pub gain: f32,
    /// World height of normalised height 1.
    pub peak: f32,
    /// Sum of octaves to normalised height.
    pub scale: f32,
    /// Step factor of the seed's march.
    pub step_factor: f32,
    /// Hit threshold of the seed's march.
    pub hit_k: f32,
    /// Radians per pixel at the image centre.
    pub pixel_angle: f32,
    /// 1 where the march fades octaves finer than the pixel's footprint out of its shading.
    pub band_limit: u32,
    /// The seed's relaxation: steps multiplied by max(relax t, 1); 0: off.
    pub relax: f32,
    /// Padding to the next 16 bytes.
    pub _pad: [u32; 3],
    /// The region drawn relative to the reference sample: x0, z0, x1, z1 in metres.
    pub bounds: [f32; 4],
    /// Per octave count k+1: (Lipschitz bound of the partial sum, bound on the rest, 0, 0).
    pub prefix: [[f32; 4]; MAX_OCTAVES],
}

impl WorldRayUniforms {
    /// Uniforms for one `size` image of `params`' world through `view`, bounded by `region`
    /// (world metres, `[x0, z0, x1, z1]`). Refuses an eye beyond [`max_eye`]. Measures the
    /// slope bounds (some 20 ms of CPU): a host casting every frame keeps them
    /// ([`crate::World::slope_bounds`]) and calls [`WorldRayUniforms::with_slopes`].
    pub fn new(
        params: &WorldParams,
        view: &WorldView,
        method: RayMethod,
        size: (u32, u32),
        region: [f64; 4],
    ) -> Result<Self> {
        let slopes = params.land.slope_bounds();
        Self::with_slopes(params, view, (method, size, region), &slopes)
    }

    /// [`WorldRayUniforms::new`] with the landscape's slope bounds measured already.
    pub fn with_slopes(
        params: &WorldParams,
        view: &WorldView,
        (method, size, region): (RayMethod, (u32, u32), [f64; 4]),
        slopes: &[f64],
    ) -> Result<Self> {
        let land = &params.land;
        if land.period != 0 {
            // The tile's ray casters are `gpu::raymarch`, on the tile's own terms.
            return Err(Error::invalid(
                "period",
                land.period,
                "0: these ray casters draw the endless world",
            ));
        }
        let limit = max_eye(land);
        if !(view.eye.x.abs() <= limit && view.eye.z.abs() <= limit) {
            return Err(Error::invalid(
                "eye",
                format!("{},{}", view.eye.x, view.eye.z),
                format!("x and z within +-{limit} m for this landscape"),
            ));
        }
        let base_log2 = finest_log2(land);
        let s = 2f64.powi(base_log2);
        let reference = [(view.eye.x / s).floor(), (view.eye.z / s).floor()];
        let origin = DVec3::new(reference[0] * s, 0.0, reference[1] * s);
        let eye = view.eye - origin;
        let (method_id, seed) = match method {
            RayMethod::Reference => (0, SeedMarch::default()),
            RayMethod::SeedMarch(s) => (1, s),
        };
        let mut prefix = [[0f32; 4]; MAX_OCTAVES];
        let n = land.octaves.min(MAX_OCTAVES as u32);
        if slopes.len() < n as usize {
            return Err(Error::invalid(
                "slopes",
                slopes.len(),
                format!("one slope bound per octave ({n})"),
            ));
        }
        for k in 1..=n {
            // The rest's bound is widened by what f32 sums can round (never at the last
            // octave, where it must stay 0 for the final test to be exact).
            let rest = land.remainder_bound(k);
            let margin = if k < n { 1e-5 * land.peak_height } else { 0.0 };
            let slope = slopes[k as usize - 1];
            prefix[k as usize - 1] = [slope as f32, (rest + margin) as f32, 0.0, 0.0];
        }
        let matrix = ray_matrix(view);
        let pixel_angle = 2.0 * (view.fov_y * 0.5).tan() / size.1.max(1) as f32;
        Ok(Self {
            inv_view_proj: matrix.inverse().to_cols_array_2d(),
            eye: [eye.x as f32, eye.y as f32, eye.z as f32, 0.0],
            reference: [reference[0] as i32, reference[1] as i32],
            base_log2,
            seed: land.seed,
            octaves: n,
            terrain: land.terrain.code(),
            feature_log2: land.feature_log2,
            method: method_id,
            march_octaves: seed.march_octaves.clamp(1, n),
            normal_octaves: seed.normal_octaves.clamp(1, n),
            max_steps: MAX_STEPS,
            width: size.0,
            height: size.1,
            gain: land.gain as f32,
            peak: land.peak_height as f32,
            scale: land.scale() as f32,
            step_factor: seed.step_factor,
            hit_k: seed.hit_k,
            pixel_angle,
            band_limit: u32::from(method_id == 1 && seed.band_limit),
            relax: seed.relax,
            _pad: [0; 3],
            bounds: [
                (region[0] - origin.x) as f32,
                (region[1] - origin.z) as f32,
                (region[2] - origin.x) as f32,
                (region[3] - origin.z) as f32,
            ],
            prefix,
        })
    }
}

/// The camera-relative matrix the ray casters unproject pixels with. Only directions come from
/// it, so its depth range is kept short: with far/near at 10^7 the far plane's w is within two
/// f32 ulps of zero after the inverse, and rays could come out reversed.
pub fn ray_matrix(view: &WorldView) -> glam::Mat4 {
    view.relative_matrix(1.0, 1000.0)
}

/// The region the mesh draws for `params` seen through `view` (the clipmap's coarsest square
/// around the eye): what the ray casters are bounded by, so every method draws the same extent.
pub fn drawn_region(params: &WorldParams, view: &WorldView) -> [f64; 4] {
    Clipmap::new(&params.land, params.pixel_error, view.pixels_per_radian())
        .drawn_region(view.eye.x, view.eye.z)
}
