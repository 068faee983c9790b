//! Helpers shared by the GPU tests.
#![allow(dead_code, reason = "each test binary uses a different subset")]

use relief::gpu::headless::{self, BakedTerrain, Gpu};
use relief::{Terrain, TerrainParams};

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
