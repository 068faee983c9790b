//! The embedding example draws host geometry and terrain into one pass and one depth buffer.

#[path = "../examples/embed.rs"]
mod embed;

use embed::{render_frame, Draw, Host};

fn is_red(p: &[u8]) -> bool {
    p[0] > 120 && p[1] < 40 && p[2] < 40
}

#[test]
fn host_geometry_and_terrain_are_depth_tested_together() {
    depth_tested_together(false, relief::Method::Mesh);
}

#[test]
fn host_geometry_and_the_endless_world_are_depth_tested_together() {
    depth_tested_together(true, relief::Method::Mesh);
}

/// The visibility method keeps the middleware contract: its compute work is recorded by
/// `prepare` before the host's pass, and its composite writes depth into the host's.
#[test]
fn the_visibility_method_is_depth_tested_with_host_geometry() {
    depth_tested_together(false, relief::Method::Visibility);
    depth_tested_together(true, relief::Method::Visibility);
}

/// So does the hybrid (the endless world's): the depth it composites is the refined surface's.
#[test]
fn the_hybrid_method_is_depth_tested_with_host_geometry() {
    depth_tested_together(true, relief::Method::Hybrid);
}

fn depth_tested_together(endless: bool, method: relief::Method) {
    depth_tested_with(endless, method, relief::Raster::Hardware);
}

/// And the visibility method and the hybrid with their raster in compute (one sample a pixel).
#[test]
fn the_compute_raster_is_depth_tested_with_host_geometry() {
    depth_tested_with(false, relief::Method::Visibility, relief::Raster::Compute);
    depth_tested_with(true, relief::Method::Hybrid, relief::Raster::Compute);
}

fn depth_tested_with(endless: bool, method: relief::Method, raster: relief::Raster) {
    let gpu = Host::new().expect(
        "the embedding test needs a GPU adapter (lavapipe: apt-get install mesa-vulkan-drivers)",
    );
    let (w, h) = (256, 192);
    let host = render_frame(
        &gpu,
        w,
        h,
        Draw {
            host: true,
            terrain: false,
            endless,
            method,
            raster,
        },
    )
    .unwrap();
    let terrain = render_frame(
        &gpu,
        w,
        h,
        Draw {
            host: false,
            terrain: true,
            endless,
            method,
            raster,
        },
    )
    .unwrap();
    let both = render_frame(
        &gpu,
        w,
        h,
        Draw {
            host: true,
            terrain: true,
            endless,
            method,
            raster,
        },
    )
    .unwrap();
    let px = |img: &[u8], i: usize| img[4 * i..4 * i + 4].to_vec();
    let n = (w * h) as usize;
    let red_alone = (0..n).filter(|&i| is_red(&px(&host, i))).count();
    let red_both = (0..n).filter(|&i| is_red(&px(&both, i))).count();
    // Pillar pixels hidden by terrain in front of them.
    let hidden = (0..n)
        .filter(|&i| is_red(&px(&host, i)) && !is_red(&px(&both, i)))
        .count();
    // Terrain pixels covered by the pillar standing in front of them.
    let covered = (0..n)
        .filter(|&i| {
            px(&terrain, i) != px(&host, i) && !is_red(&px(&terrain, i)) && is_red(&px(&both, i))
        })
        .count();
    eprintln!("pillar pixels alone {red_alone}, with terrain {red_both}; hidden by terrain {hidden}; terrain covered {covered}");
    assert!(
        red_alone > 200,
        "the host pillar must be visible on its own"
    );
    assert!(
        red_both > 100,
        "the pillar must stay visible above the ground"
    );
    assert!(
        hidden > 20,
        "terrain must hide the pillar's buried foot (depth shared with the host)"
    );
    assert!(covered > 100, "the pillar must hide terrain behind it");
    // Outside the pillar, the frame with both is the terrain frame.
    let same = (0..n)
        .filter(|&i| !is_red(&px(&host, i)))
        .filter(|&i| px(&both, i) == px(&terrain, i))
        .count();
    let outside = (0..n).filter(|&i| !is_red(&px(&host, i))).count();
    assert!(
        same as f64 > 0.99 * outside as f64,
        "terrain changed away from the pillar: {same}/{outside}"
    );
}

/// A host may keep relief's renderers in shared state and hand them between threads.
#[test]
fn the_renderers_are_send_and_sync() {
    fn send_sync<T: Send + Sync>() {}
    send_sync::<relief::Terrain>();
    send_sync::<relief::World>();
    send_sync::<relief::Targets>();
    send_sync::<relief::WorldParams>();
    send_sync::<relief::TerrainParams>();
    send_sync::<relief::Error>();
}
