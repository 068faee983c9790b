//! Helpers shared by the GPU tests.
#![allow(dead_code, reason = "each test binary uses a different subset")]

use relief::gpu::headless::{self, BakedTerrain, Gpu};
use relief::{Method, Terrain, TerrainParams, World, WorldParams, WorldView};

/// The GPU, or a loud failure: GPU tests never pass by skipping.
pub fn gpu() -> Gpu {
    match Gpu::new() {
        Ok(g) => {
            eprintln!("GPU tests on {}", g.describe());
            g
        }
        Err(e) => panic!(
            "GPU tests need an adapter and found none: {e}. \
             Install Mesa's software Vulkan (apt-get install mesa-vulkan-drivers) or run on a GPU."
        ),
    }
}

/// Bakes `params` and reads everything back.
pub fn bake(gpu: &Gpu, params: TerrainParams) -> (Terrain, BakedTerrain) {
    let targets = headless::Offscreen::targets(1);
    let mut terrain = Terrain::new(&gpu.device, &gpu.queue, targets, params).expect("terrain");
    headless::bake_blocking(gpu, &mut terrain, None).expect("bake");
    let baked = headless::read_baked(&gpu.device, &gpu.queue, &terrain).expect("readback");
    (terrain, baked)
}

/// The endless world's default camera over `params`, looking at an image of `size`.
pub fn world_view(params: &WorldParams, size: (u32, u32)) -> WorldView {
    let (eye, at) = relief::gpu::world::default_camera(&params.land);
    WorldView::look_at(eye, at, 0.8, size)
}

/// `params`' endless world drawn with `method` from the default camera into a 4x target, as
/// `relief render` draws it: sRGB RGBA8 of `size`.
pub fn world_image(gpu: &Gpu, params: WorldParams, method: Method, size: (u32, u32)) -> Vec<u8> {
    let targets = headless::Offscreen::targets(headless::RENDER_SAMPLES);
    let mut world = World::new(&gpu.device, &gpu.queue, targets, params).expect("world");
    world.set_method(&gpu.device, method).expect("method");
    let view = world_view(&params, size);
    headless::render_world_image(gpu, &mut world, &view, size, headless::TILE, None)
        .expect("render")
        .0
}
