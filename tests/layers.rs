//! The list of layers, proved by the test layer (a box standing on the terrain): every
//! mesh-based method and the reference draw it where the others do, the terrain hides it where
//! it is in front, and without a layer nothing changes.

mod common;

use glam::DVec3;
use relief::gpu::headless::{self, render_samples, Offscreen};
use relief::gpu::layer::Layer;
use relief::gpu::test_box::TestBox;
use relief::{Method, MethodConfig, Raster, Shading, World, WorldParams, WorldView};

const SIZE: (u32, u32) = (192, 108);

/// Pixels whose colour differs by more than a few steps between two frames.
fn changed(a: &[u8], b: &[u8]) -> usize {
    a.chunks(4)
        .zip(b.chunks(4))
        .filter(|(p, q)| p.iter().zip(q.iter()).any(|(x, y)| x.abs_diff(*y) > 6))
        .count()
}

/// A view from 1.5 km west of `foot` and 1.2 km above it, looking at the box's middle, `size`
/// pixels.
fn view_of(foot: DVec3, size: (u32, u32)) -> WorldView {
    let eye = foot + DVec3::new(-1500.0, 1200.0, 0.0);
    WorldView::look_at(eye, foot + DVec3::new(0.0, 150.0, 0.0), 0.8, size)
}

#[test]
fn every_mesh_method_and_the_reference_draw_the_test_box_and_the_terrain_hides_a_buried_one() {
    let gpu = common::gpu();
    let params = WorldParams::default();
    // On dry land 50 m above the water, east of (2000, -3000).
    let water = f64::from(params.water_level);
    let foot = (0..200)
        .map(|i| {
            let (x, z) = (2000.0 + 50.0 * f64::from(i), -3000.0);
            DVec3::new(x, params.land.height_at(x, z), z)
        })
        .find(|p| p.y > water + 50.0)
        .expect("dry land within 10 km");
    let view = view_of(foot, SIZE);
    let size = DVec3::new(150.0, 300.0, 150.0);
    // The forward mesh twice: into the host's pass, and through the temporal service's
    // history (4 frames accumulated), whose composite writes the terrain's depth.
    let configs = [
        (MethodConfig::MESH, 1),
        (MethodConfig::MESH, 4),
        (MethodConfig::new(Method::Visibility), 1),
        (
            MethodConfig::new(Method::Visibility)
                .with_samples(1)
                .with_raster(Raster::Compute),
            1,
        ),
        (MethodConfig::new(Method::Hybrid).with_samples(1), 1),
    ];
    let mut counts = Vec::new();
    for (config, frames) in configs {
        let targets = Offscreen::targets(render_samples(config.method));
        let mut world = World::new(&gpu.device, &gpu.queue, targets, params).unwrap();
        world.set_method(&gpu.device, config).unwrap();
        world
            .set_temporal(&gpu.device, relief::Temporal { frames })
            .unwrap();
        let draw = |world: &mut World| {
            let size = (SIZE, frames);
            headless::render_world_frames(&gpu, world, &view, size, headless::TILE, None)
                .unwrap()
                .0
        };
        let bare = draw(&mut world);
        assert!(world.layers().is_empty());
        world.push_layer(Box::new(TestBox::standing(foot, size, [0.8, 0.1, 0.7])));
        assert_eq!(world.layers(), ["test box"]);
        let boxed = draw(&mut world);
        let shown = changed(&bare, &boxed);
        // The same box 1 km under the ground: the terrain in front hides all of it.
        world.take_layers();
        let under = foot - DVec3::new(0.0, 1000.0, 0.0);
        world.push_layer(Box::new(TestBox::standing(under, size, [0.8, 0.1, 0.7])));
        let buried = changed(&bare, &draw(&mut world));
        // Taken away, the frame is the bare one again, byte for byte.
        world.take_layers();
        let again = draw(&mut world);
        eprintln!(
            "{config:?}, {frames} frames: the box changed {shown} pixels, buried {buried}; bare \
             again equal: {}",
            again == bare
        );
        assert!(shown > 150, "{config:?}: the box drew {shown} pixels");
        assert_eq!(buried, 0, "{config:?}: a buried box showed");
        assert!(
            again == bare,
            "{config:?}: no layer, the frame is the bare one"
        );
        counts.push(shown);
    }
    // The reference: the box drawn over the cast at its 3x3 rays a pixel, depth-tested
    // against the continuous surface the rays found. At half the size each way (the cast is
    // the slowest part of this test on a software GPU): its pixels count four times.
    let view = view_of(foot, (SIZE.0 / 2, SIZE.1 / 2));
    let reference = |layers: &mut [Box<dyn Layer>]| {
        let shading = Shading::default();
        let (p, v) = (&params, &view);
        headless::render_world_rays_with_layers(&gpu, p, &shading, v, Method::Reference, layers)
            .unwrap()
            .rgba
    };
    let bare = headless::render_world_rays(
        &gpu,
        &params,
        &Shading::default(),
        &view,
        Method::Reference,
        None,
    )
    .unwrap()
    .rgba;
    let standing =
        |at: DVec3| -> Box<dyn Layer> { Box::new(TestBox::standing(at, size, [0.8, 0.1, 0.7])) };
    let boxed = reference(&mut [standing(foot)]);
    let shown = changed(&bare, &boxed);
    let under = foot - DVec3::new(0.0, 1000.0, 0.0);
    let buried = changed(&bare, &reference(&mut [standing(under)]));
    eprintln!("reference: the box changed {shown} pixels, buried {buried}");
    assert!(shown > 40, "reference: the box drew {shown} pixels");
    assert_eq!(buried, 0, "reference: a buried box showed");
    counts.push(4 * shown);
    // Every method covers about the same pixels (edges differ by antialiasing and samples).
    let (lo, hi) = (counts.iter().min().unwrap(), counts.iter().max().unwrap());
    assert!(
        *hi as f64 <= 1.25 * *lo as f64,
        "the methods drew the box over {counts:?} pixels"
    );
}
