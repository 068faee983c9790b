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
            layer: false,
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
            layer: false,
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
            layer: false,
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

fn is_blue(p: &[u8]) -> bool {
    p[2] > 120 && p[0] < 60 && p[1] < 80
}

/// A layer of relief's frame (the test box, standing behind the host's pillar) is drawn into
/// the host's pass against the host's depth: the pillar hides the part of the box behind it,
/// with every mesh-based method.
#[test]
fn a_layer_is_depth_tested_against_host_geometry() {
    let gpu = Host::new().expect("the embedding test needs a GPU adapter");
    let (w, h) = (256, 192);
    for (method, raster) in [
        (relief::Method::Mesh, relief::Raster::Hardware),
        (relief::Method::Visibility, relief::Raster::Compute),
        (relief::Method::Hybrid, relief::Raster::Hardware),
    ] {
        let frame = |host| {
            let draw = Draw {
                host,
                terrain: true,
                endless: true,
                method,
                raster,
                layer: true,
            };
            render_frame(&gpu, w, h, draw).unwrap()
        };
        let (alone, with_host) = (frame(false), frame(true));
        let n = (w * h) as usize;
        let px = |img: &[u8], i: usize| img[4 * i..4 * i + 4].to_vec();
        let blue = |img: &[u8]| (0..n).filter(|&i| is_blue(&px(img, i))).count();
        let hidden = (0..n)
            .filter(|&i| is_blue(&px(&alone, i)) && is_red(&px(&with_host, i)))
            .count();
        let (b_alone, b_host) = (blue(&alone), blue(&with_host));
        eprintln!(
            "{method:?}: box pixels alone {b_alone}, with the pillar {b_host}, hidden by it {hidden}"
        );
        assert!(b_alone > 150, "{method:?}: the box must show ({b_alone})");
        assert!(
            hidden > 40,
            "{method:?}: the pillar must hide the box behind it ({hidden})"
        );
        assert!(
            b_host > 60,
            "{method:?}: the box must show beside the pillar ({b_host})"
        );
        // Elsewhere the box is what it was, but for the pillar's blended edge pixels.
        let elsewhere = b_alone - b_host - hidden;
        assert!(
            elsewhere * 8 < b_alone,
            "{method:?}: {elsewhere} box pixels changed away from the pillar"
        );
    }
}
