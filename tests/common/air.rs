//! Helpers shared by the air's GPU tests (`tests/sky.rs`, `tests/clouds.rs`): a small world,
//! its frame, and each pixel's ray and distance.
#![allow(dead_code, reason = "each test binary uses a different subset")]

use glam::{Mat4, Vec3, Vec4};
use relief::gpu::headless::{Gpu, Offscreen};
use relief::landscape::{Landscape, TerrainFn};
use relief::sky::Sky;
use relief::{Shading, World, WorldParams, WorldView};
pub const SIZE: (u32, u32) = (160, 96);

/// A small world: ridges 256 m apart, at most 150 m high; a loose knob keeps lavapipe's work
/// small. Fog thick enough that the small world's few kilometres show it.
pub fn params(fog: f32) -> WorldParams {
    WorldParams {
        land: Landscape {
            seed: 5,
            octaves: 7,
            gain: 0.5,
            feature_log2: 8,
            peak_height: 150.0,
            terrain: TerrainFn::Fbm,
            period: 0,
        },
        pixel_error: 16.0,
        sky: Sky {
            sun_azimuth: 200.0,
            sun_elevation: 20.0,
            fog,
            ..Default::default()
        },
        no_water: true,
        // The terrain alone: grass (on by default) is tests/grass.rs's.
        grass: relief::grass::Grass {
            on: false,
            ..Default::default()
        },
        ..WorldParams::default()
    }
}

pub fn draw(
    gpu: &Gpu,
    p: WorldParams,
    shading: Shading,
    view: &WorldView,
) -> (Vec<u8>, Vec<f32>, Mat4) {
    let mut world = World::new(&gpu.device, &gpu.queue, Offscreen::targets(1), p).unwrap();
    world.set_shading(shading);
    let target = Offscreen::new(&gpu.device, SIZE.0, SIZE.1, 1).unwrap();
    let (rgba, _) = target.render_world(gpu, &mut world, view, None).unwrap();
    let depth = target.read_depth(gpu).unwrap();
    (rgba, depth, world.relative_matrix())
}

/// The unit view direction through the centre of pixel (x, y) under the camera-relative
/// `matrix`.
pub fn direction(matrix: Mat4, x: u32, y: u32) -> Vec3 {
    let ndc = |depth: f32| {
        let v = matrix.inverse()
            * Vec4::new(
                2.0 * (x as f32 + 0.5) / SIZE.0 as f32 - 1.0,
                1.0 - 2.0 * (y as f32 + 0.5) / SIZE.1 as f32,
                depth,
                1.0,
            );
        v.truncate() / v.w
    };
    (ndc(1.0) - ndc(0.5)).normalize()
}

/// Distance from the eye of each pixel's depth (None for the sky).
pub fn distances(depth: &[f32], matrix: Mat4) -> Vec<Option<f32>> {
    let inv = matrix.inverse();
    (0..SIZE.1)
        .flat_map(|y| (0..SIZE.0).map(move |x| (x, y)))
        .map(|(x, y)| {
            let d = depth[(y * SIZE.0 + x) as usize];
            (d < 1.0).then(|| {
                let v = inv
                    * Vec4::new(
                        2.0 * (x as f32 + 0.5) / SIZE.0 as f32 - 1.0,
                        1.0 - 2.0 * (y as f32 + 0.5) / SIZE.1 as f32,
                        d,
                        1.0,
                    );
                (v.truncate() / v.w).length()
            })
        })
        .collect()
}
