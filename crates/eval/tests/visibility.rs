//! The visibility method (`--method visibility`): the mesh rasterised to depth and attributes
//! per sample, every sample shaded in compute. It draws the same terrain as the forward mesh,
//! through the same `Offscreen` path as `relief render`, as close to the reference ray cast as the
//! mesh is (on this scene what keeps both from it is what the texels hold, not the shading rate:
//! the stability detail axis shows the same).

#[path = "../../../tests/common/mod.rs"]
mod common;

use relief::gpu::headless::{self, Gpu, Offscreen, RENDER_SAMPLES};
use relief::{Method, OrbitCamera, Raster, Shading, Terrain, TerrainParams, WorldParams};
use relief_eval::metrics::{image_error, rgb};

const W: u32 = 256;
const H: u32 = 144;

fn gpu() -> Gpu {
    Gpu::new().expect(
        "the visibility tests need a GPU adapter (lavapipe: apt-get install mesa-vulkan-drivers)",
    )
}

fn scene(seed: u32) -> TerrainParams {
    TerrainParams {
        size: 256,
        grid: 128,
        seed,
        ..Default::default()
    }
}

fn tile(gpu: &Gpu, params: TerrainParams, method: Method) -> Vec<u8> {
    tile_at(gpu, params, method, relief::gpu::visibility::SAMPLES)
}

/// The tile drawn with `method`, the visibility method at `samples` a pixel.
fn tile_at(gpu: &Gpu, params: TerrainParams, method: Method, samples: u32) -> Vec<u8> {
    let view = OrbitCamera::default().view(W as f32 / H as f32);
    draw_tile(gpu, params, &view, (method, samples, Raster::Hardware))
}

/// A tile of `params` drawing into `relief render`'s targets.
fn terrain(gpu: &Gpu, params: TerrainParams) -> Terrain {
    Terrain::new(
        &gpu.device,
        &gpu.queue,
        Offscreen::targets(RENDER_SAMPLES),
        params,
    )
    .unwrap()
}

/// The tile seen through `view`, drawn with `method`, the visibility method at `samples` a
/// pixel rasterised by `raster`.
fn draw_tile(
    gpu: &Gpu,
    params: TerrainParams,
    view: &relief::View,
    (method, samples, raster): (Method, u32, Raster),
) -> Vec<u8> {
    let mut terrain = terrain(gpu, params);
    terrain
        .set_method(
            &gpu.device,
            relief::MethodConfig {
                method,
                samples,
                raster,
            },
        )
        .unwrap();
    assert_eq!(terrain.method_config().raster, raster);
    headless::render_image(gpu, &mut terrain, view, (W, H), headless::TILE, None)
        .unwrap()
        .0
}

fn flip(a: &[u8], b: &[u8]) -> f64 {
    image_error(&rgb(a), &rgb(b), W, H).0
}

#[test]
fn visibility_draws_the_tiles_mesh_as_close_to_the_reference() {
    let gpu = gpu();
    let mesh = tile(&gpu, scene(1), Method::Mesh);
    let vis = tile(&gpu, scene(1), Method::Visibility);
    let other = tile(&gpu, scene(2), Method::Visibility);
    let view = OrbitCamera::default().view(W as f32 / H as f32);
    let (reference, _) = headless::render_rays(
        &gpu,
        &scene(1),
        &Shading::default(),
        &view,
        (W, H),
        Method::Reference,
        None,
    )
    .unwrap();
    let same = flip(&mesh, &vis);
    let control = flip(&vis, &other);
    let (mesh_ref, vis_ref) = (flip(&reference, &mesh), flip(&reference, &vis));
    eprintln!(
        "tile: visibility vs mesh {same:.4}, vs another seed {control:.4}; against the reference: mesh {mesh_ref:.4}, visibility {vis_ref:.4}"
    );
    assert!(
        same < 0.06,
        "visibility must draw the mesh's terrain: FLIP {same:.4} against the forward mesh"
    );
    assert!(
        control > 3.0 * same,
        "another seed must score far worse ({control:.4}) than the mesh ({same:.4})"
    );
    assert!(
        vis_ref <= mesh_ref + 0.002,
        "four shaded samples a pixel must be no further from the reference ({vis_ref:.4}) than one ({mesh_ref:.4})"
    );
}

#[test]
fn one_sample_a_pixel_draws_the_same_tile_and_other_counts_are_refused() {
    let gpu = gpu();
    let four = tile(&gpu, scene(1), Method::Visibility);
    let one = tile_at(&gpu, scene(1), Method::Visibility, 1);
    let other = tile_at(&gpu, scene(2), Method::Visibility, 1);
    let (same, control) = (flip(&four, &one), flip(&one, &other));
    eprintln!("tile: one sample a pixel vs four {same:.4}, vs another seed {control:.4}");
    // The same terrain, its edges and sub-pixel detail no longer averaged.
    assert!(same > 0.0, "one sample a pixel drew the four-sample image");
    assert!(
        same < 0.06 && control > 3.0 * same,
        "one sample a pixel: {same:.4} against four, {control:.4} against another seed"
    );
    let mut terrain = terrain(&gpu, scene(1));
    let e = terrain
        .set_method(
            &gpu.device,
            relief::MethodConfig::new(Method::Visibility).with_samples(2),
        )
        .unwrap_err();
    assert!(e.to_string().contains("1 or 4"), "{e}");
}

/// The tile seen through `view`, drawn by the visibility method at one sample a pixel,
/// rasterised by `raster`.
fn tile_rasterised(
    gpu: &Gpu,
    params: TerrainParams,
    view: &relief::View,
    raster: Raster,
) -> Vec<u8> {
    draw_tile(gpu, params, view, (Method::Visibility, 1, raster))
}

/// Share of pixels whose colour differs by more than 8 levels in some channel.
fn differing(a: &[u8], b: &[u8]) -> f64 {
    let n = a
        .chunks(4)
        .zip(b.chunks(4))
        .filter(|(p, q)| p.iter().zip(q.iter()).any(|(x, y)| x.abs_diff(*y) > 8))
        .count();
    n as f64 / (a.len() / 4) as f64
}

#[test]
fn the_compute_raster_draws_what_the_gpus_rasteriser_draws() {
    let gpu = gpu();
    let aspect = W as f32 / H as f32;
    // The default framing, and a camera a few cells above the ground looking along it, where
    // triangles beside and under the eye cross the near plane and are cut there.
    let low = OrbitCamera {
        target: glam::Vec3::new(0.0, 0.05, 0.0),
        pitch: 0.02,
        distance: 0.3,
        ..Default::default()
    };
    for (name, view) in [
        ("default", OrbitCamera::default().view(aspect)),
        ("low", low.view(aspect)),
    ] {
        let hardware = tile_rasterised(&gpu, scene(1), &view, Raster::Hardware);
        let compute = tile_rasterised(&gpu, scene(1), &view, Raster::Compute);
        let other = tile_rasterised(&gpu, scene(2), &view, Raster::Compute);
        let (same, control) = (flip(&hardware, &compute), flip(&compute, &other));
        let off = differing(&hardware, &compute);
        eprintln!(
            "{name} view: compute raster vs hardware FLIP {same:.4}, {:.3}% of pixels differ; vs another seed {control:.4}",
            100.0 * off
        );
        // Only pixel centres on or within float rounding of an edge may fall differently.
        assert!(
            same < 0.005 && off < 0.003,
            "{name} view: the compute raster drew FLIP {same:.4} and {:.3}% of pixels away from the GPU's",
            100.0 * off
        );
        assert!(
            control > 0.02 && control > 10.0 * same,
            "{name} view: another seed scored {control:.4}"
        );
    }
}

#[test]
fn the_compute_raster_refuses_what_it_cannot_draw_in_words() {
    let gpu = gpu();
    let mut terrain = terrain(&gpu, scene(1));
    let compute = relief::MethodConfig::new(Method::Visibility).with_raster(Raster::Compute);
    // A refused configuration changes nothing: from one that is not the default.
    let before = relief::MethodConfig::new(Method::Visibility).with_samples(1);
    terrain.set_method(&gpu.device, before).unwrap();
    let e = terrain.set_method(&gpu.device, compute).unwrap_err();
    assert!(e.to_string().contains("one sample a pixel"), "{e}");
    assert_eq!(terrain.method_config(), before);
    terrain
        .set_method(&gpu.device, compute.with_samples(1))
        .unwrap();
    // A frame whose depth buffer (4 bytes a pixel, bound whole) passes the device's storage
    // binding limit is refused in words, before anything is made at that size.
    let side = 65_536;
    terrain.set_viewport((side, side));
    let view = OrbitCamera::default().view(1.0);
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    let e = terrain
        .prepare(&gpu.device, &gpu.queue, &mut encoder, &view)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("65536x65536") && e.contains("--raster hardware"),
        "{e}"
    );
    let mut world = relief::World::new(
        &gpu.device,
        &gpu.queue,
        Offscreen::targets(RENDER_SAMPLES),
        WorldParams::default(),
    )
    .unwrap();
    for method in [Method::Visibility, Method::Hybrid] {
        let config = relief::MethodConfig::new(method).with_raster(Raster::Compute);
        let e = world.set_method(&gpu.device, config).unwrap_err();
        assert!(
            e.to_string().contains("one sample a pixel"),
            "{method}: {e}"
        );
    }
    // The endless world's raster keeps each pixel's triangle beside its depth (lavapipe has
    // 64-bit atomics): 8 bytes a pixel, and the refusal says so.
    world
        .set_method(&gpu.device, compute.with_samples(1))
        .unwrap();
    world.set_target_size(Some((side, side)));
    let view = common::world_view(&WorldParams::default(), (W, H));
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    let e = world
        .prepare(&gpu.device, &gpu.queue, &mut encoder, &view)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("65536x65536") && e.contains("8 bytes a pixel"),
        "{e}"
    );
}

/// The default endless world on `gpu`, baked once and drawn by [`draw`] with each method and
/// raster a test compares (a bake on lavapipe takes seconds; the drawing does not change it).
fn baked(gpu: &Gpu) -> relief::World {
    relief::World::new(
        &gpu.device,
        &gpu.queue,
        Offscreen::targets(RENDER_SAMPLES),
        bare(),
    )
    .unwrap()
}

/// The endless world's defaults without the grass that grows by default: these tests hold the
/// terrain's rasters to each other (tests/grass.rs holds the blades' rasters).
fn bare() -> WorldParams {
    let mut p = WorldParams::default();
    p.grass.on = false;
    p
}

/// `world` drawn by `method` at one sample a pixel, rasterised by `raster` (the compute raster
/// skipping hidden blocks or not), from `view` (the default camera without one).
fn draw(
    gpu: &Gpu,
    world: &mut relief::World,
    (method, raster): (Method, Raster),
    view: Option<&relief::WorldView>,
    skip: bool,
) -> Vec<u8> {
    let default = common::world_view(&WorldParams::default(), (W, H));
    world
        .set_method(
            &gpu.device,
            relief::MethodConfig {
                method,
                samples: 1,
                raster,
            },
        )
        .unwrap();
    world.set_raster_skips_hidden(skip);
    headless::render_world_image(
        gpu,
        world,
        view.unwrap_or(&default),
        (W, H),
        headless::TILE,
        None,
    )
    .unwrap()
    .0
}

/// In the endless world the compute raster's second dispatch stores each pixel's attributes
/// (slope, colour channel, horizon, valley) where its triangle is nearest: the visibility
/// method and the hybrid draw what they draw from the GPU's rasteriser.
#[test]
fn the_compute_raster_draws_the_endless_world_with_its_attributes() {
    let gpu = gpu();
    let mesh = world(&gpu, bare(), Method::Mesh);
    let mut baked = baked(&gpu);
    for method in [Method::Visibility, Method::Hybrid] {
        let hardware = draw(&gpu, &mut baked, (method, Raster::Hardware), None, true);
        let compute = draw(&gpu, &mut baked, (method, Raster::Compute), None, true);
        let (same, control) = (flip(&hardware, &compute), flip(&compute, &mesh));
        let off = differing(&hardware, &compute);
        eprintln!(
            "{method}: compute raster vs hardware FLIP {same:.4}, {:.3}% of pixels differ; vs the forward mesh {control:.4}",
            100.0 * off
        );
        assert!(
            same < 0.005 && off < 0.003,
            "{method}: the compute raster drew FLIP {same:.4} and {:.3}% of pixels away from the GPU's",
            100.0 * off
        );
        // The control: the forward mesh, shaded per pixel from the same levels, is told apart.
        assert!(
            control > 10.0 * same,
            "{method}: the forward mesh scored {control:.4}"
        );
    }
}

/// Where the device has 64-bit atomics (lavapipe does), the compute raster keeps each pixel's
/// triangle beside its depth and stores the attributes of that one triangle after one raster;
/// without them it rasterises a second time. Both draw the same picture: only pixels where two
/// triangles meet at exactly one depth may differ (the ids choose the same one every frame).
#[test]
fn the_raster_with_ids_draws_what_the_second_raster_draws() {
    let gpu = gpu();
    assert!(
        gpu.device
            .features()
            .contains(relief::gpu::raster::ID_FEATURES),
        "lavapipe has 64-bit atomics: this test compares the raster with ids to the one without"
    );
    let without = Gpu::with_features(wgpu::Features::TIMESTAMP_QUERY).unwrap();
    assert!(!without
        .device
        .features()
        .contains(wgpu::Features::SHADER_INT64_ATOMIC_MIN_MAX));
    let (mut with_world, mut without_world) = (baked(&gpu), baked(&without));
    for method in [Method::Visibility, Method::Hybrid] {
        let ids = draw(&gpu, &mut with_world, (method, Raster::Compute), None, true);
        let twice = draw(
            &without,
            &mut without_world,
            (method, Raster::Compute),
            None,
            true,
        );
        let (same, off) = (flip(&ids, &twice), differing(&ids, &twice));
        eprintln!(
            "{method}: raster with ids vs rastered twice: FLIP {same:.5}, {:.4}% of pixels differ",
            100.0 * off
        );
        assert!(
            same < 0.001 && off < 0.001,
            "{method}: the raster with ids drew FLIP {same:.5} and {:.4}% of pixels away",
            100.0 * off
        );
        // The same frame again: the ids settle ties the same way every time.
        assert_eq!(
            ids,
            draw(&gpu, &mut with_world, (method, Raster::Compute), None, true),
            "{method}"
        );
    }
}

/// The compute raster draws the depth in passes, nearest levels first, and a later pass skips
/// the blocks of cells wholly behind what the earlier ones drew. From 2 m above the ground,
/// looking at the horizon (the benchmark's view), most of the distant mesh is hidden: the
/// picture is the same byte for byte as with nothing skipped, with ids and without (the page's
/// path), and it is the GPU rasteriser's.
#[test]
fn the_compute_raster_skips_only_what_is_hidden() {
    let gpu = gpu();
    let view = relief::WorldView::look_at(
        glam::DVec3::new(0.0, 1202.0, 0.0),
        glam::DVec3::new(1.0, 1201.99, 0.2),
        0.8,
        (W, H),
    );
    let without_ids = Gpu::with_features(wgpu::Features::TIMESTAMP_QUERY).unwrap();
    let mut with_ids = baked(&gpu);
    let compute = (Method::Visibility, Raster::Compute);
    for (device, g, world) in [
        ("with ids", &gpu, &mut with_ids),
        ("without ids", &without_ids, &mut baked(&without_ids)),
    ] {
        let skipping = draw(g, world, compute, Some(&view), true);
        let drawing_all = draw(g, world, compute, Some(&view), false);
        assert!(
            skipping == drawing_all,
            "{device}: skipping hidden blocks changed pixels"
        );
    }
    let hardware = draw(
        &gpu,
        &mut with_ids,
        (Method::Visibility, Raster::Hardware),
        Some(&view),
        true,
    );
    let compute = draw(&gpu, &mut with_ids, compute, Some(&view), true);
    let (same, off) = (flip(&hardware, &compute), differing(&hardware, &compute));
    eprintln!(
        "horizon: compute raster vs hardware FLIP {same:.4}, {:.3}% of pixels differ",
        100.0 * off
    );
    assert!(
        same < 0.005 && off < 0.003,
        "the compute raster drew FLIP {same:.4} and {:.3}% of pixels away from the GPU's",
        100.0 * off
    );
}

fn world(gpu: &Gpu, params: WorldParams, method: Method) -> Vec<u8> {
    common::world_image(gpu, params, method, (W, H))
}

#[test]
fn visibility_draws_the_endless_worlds_mesh() {
    let gpu = gpu();
    let params = WorldParams {
        pixel_error: 4.0,
        ..Default::default()
    };
    let mesh = world(&gpu, params, Method::Mesh);
    let vis = world(&gpu, params, Method::Visibility);
    let mut other = params;
    other.land.seed += 1;
    let moved = world(&gpu, other, Method::Visibility);
    let (same, control) = (flip(&mesh, &vis), flip(&vis, &moved));
    eprintln!("endless world: visibility vs mesh {same:.4}, vs another seed {control:.4}");
    assert!(
        same < 0.06,
        "visibility must draw the mesh's world, look and all: FLIP {same:.4}"
    );
    assert!(
        control > 2.0 * same,
        "another seed must score far worse ({control:.4}) than the mesh ({same:.4})"
    );
}

#[test]
fn the_ray_casters_are_not_mesh_methods() {
    let gpu = gpu();
    let mut terrain = terrain(&gpu, scene(1));
    let e = terrain
        .set_method(&gpu.device, Method::Raymarch)
        .unwrap_err();
    assert!(e.to_string().contains("mesh, visibility or hybrid"), "{e}");
    assert_eq!(terrain.method(), Method::Mesh);
}
