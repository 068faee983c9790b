//! The endless world's ray casters on lavapipe, at small sizes: the reference lands on the
//! twin's surface, its measured slope bounds find what the proven ones find, rays that run out
//! of steps are reported (never sky), and the mesh is as close to the reference far from the
//! origin as near it.

#[path = "../../../tests/common/mod.rs"]
mod common;

use glam::{DVec3, DVec4};
use relief::gpu::headless::{self, Gpu, Offscreen};
use relief::gpu::raymarch::{RayMarcher, RayScene};
use relief::gpu::world_rays::{drawn_region, WorldRayUniforms};
use relief::landscape::{Landscape, TerrainFn};
use relief::method::RayMethod;
use relief::{Method, Shading, World, WorldParams, WorldView};
use relief_eval::metrics;

/// A small world (as in tests/world.rs), eroded so the slope bounds matter.
fn params(terrain: TerrainFn) -> WorldParams {
    WorldParams {
        land: Landscape {
            seed: 11,
            octaves: 8,
            gain: 0.5,
            feature_log2: 8,
            peak_height: 150.0,
            terrain,
            period: 0,
        },
        pixel_error: 16.0,
        ..WorldParams::default()
    }
}

const SIZE: (u32, u32) = (96, 64);

fn view(land: &Landscape, x: f64, z: f64, above: f64, dir: DVec3) -> WorldView {
    let eye = DVec3::new(x, land.height_at(x, z) + above, z);
    WorldView::look_at(eye, eye + dir, 50f32.to_radians(), SIZE)
}

/// One pixel-centre ray per pixel with `method`, the uniforms adjusted by `tweak`: the colour
/// and the distances.
fn cast(
    gpu: &Gpu,
    p: &WorldParams,
    v: &WorldView,
    method: RayMethod,
    tweak: impl FnOnce(&mut WorldRayUniforms),
) -> (Vec<u8>, Vec<f32>) {
    cast_in(gpu, RayScene::World, p, v, method, tweak).unwrap()
}

/// [`cast`] by a caster built for `scene`: what it refuses, or the colour and the distances.
fn cast_in(
    gpu: &Gpu,
    scene: RayScene,
    p: &WorldParams,
    v: &WorldView,
    method: RayMethod,
    tweak: impl FnOnce(&mut WorldRayUniforms),
) -> relief::error::Result<(Vec<u8>, Vec<f32>)> {
    let shading = Shading::default();
    let caster = RayMarcher::for_scene(&gpu.device, SIZE.0, SIZE.1, scene).unwrap();
    let region = drawn_region(p, v);
    let mut ray = WorldRayUniforms::new(p, v, method, SIZE, region).unwrap();
    tweak(&mut ray);
    let render = relief::gpu::world::render_uniforms(
        p,
        &shading,
        (relief::gpu::world_rays::ray_matrix(v), region, v.eye),
        true,
    );
    caster.prepare_world(&gpu.queue, &render, &ray)?;
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    caster.encode(&mut encoder, relief::method::RayPath::Compute, None);
    gpu.queue.submit([encoder.finish()]);
    let color = headless::read_texture(&gpu.device, &gpu.queue, &caster.color).unwrap();
    let distance = headless::read_texture(&gpu.device, &gpu.queue, &caster.distance).unwrap();
    Ok((color, bytemuck::pod_collect_to_vec(&distance)))
}

/// The caster built without the clouds' march (`RayScene::WorldWithoutClouds`, what a world
/// without clouds is cast with) casts the same bytes as the one with it, and refuses a frame
/// with clouds rather than draw it without them.
#[test]
fn the_caster_without_the_clouds_casts_the_same_bytes_and_refuses_clouds() {
    let gpu = common::gpu();
    let p = params(TerrainFn::Eroded);
    let v = &views(&p.land, 0.0)[0];
    let with = cast_in(&gpu, RayScene::World, &p, v, RayMethod::Reference, |_| {}).unwrap();
    let without = cast_in(
        &gpu,
        RayScene::WorldWithoutClouds,
        &p,
        v,
        RayMethod::Reference,
        |_| {},
    )
    .unwrap();
    assert!(with.0 == without.0, "the colours differ");
    assert!(with.1 == without.1, "the distances differ");
    let mut cloudy = p;
    cloudy.clouds.coverage = 0.5;
    let refused = cast_in(
        &gpu,
        RayScene::WorldWithoutClouds,
        &cloudy,
        v,
        RayMethod::Reference,
        |_| {},
    );
    let e = refused
        .expect_err("a frame with clouds was cast without them")
        .to_string();
    assert!(e.contains("WorldWithoutClouds"), "{e}");
}

/// The world point a pixel's ray reaches at distance `t`.
fn hit(v: &WorldView, px: usize, py: usize, t: f32) -> DVec3 {
    let inverse = relief::gpu::world_rays::ray_matrix(v).inverse().as_dmat4();
    let ndc = DVec4::new(
        (px as f64 + 0.5) / f64::from(SIZE.0) * 2.0 - 1.0,
        1.0 - (py as f64 + 0.5) / f64::from(SIZE.1) * 2.0,
        1.0,
        1.0,
    );
    let far = inverse * ndc;
    let dir = (far.truncate() / far.w).normalize();
    v.eye + dir * f64::from(t)
}

fn views(land: &Landscape, origin: f64) -> Vec<WorldView> {
    vec![
        // Grazing along the ground, over slopes and a ridge, and from high up.
        view(
            land,
            origin + 17.0,
            origin - 40.0,
            3.0,
            DVec3::new(1.0, -0.02, 0.3),
        ),
        view(
            land,
            origin - 90.0,
            origin + 25.0,
            40.0,
            DVec3::new(-0.4, -0.3, 1.0),
        ),
        view(
            land,
            origin + 5.0,
            origin + 5.0,
            400.0,
            DVec3::new(0.5, -0.6, -0.5),
        ),
    ]
}

#[test]
fn the_reference_lands_on_the_twins_surface() {
    let gpu = common::gpu();
    for terrain in [TerrainFn::Fbm, TerrainFn::Eroded] {
        let p = params(terrain);
        for v in views(&p.land, 0.0) {
            let (_, distance) = cast(&gpu, &p, &v, RayMethod::Reference, |_| {});
            let mut hits = 0;
            for (i, &t) in distance.iter().enumerate() {
                assert_ne!(t, -2.0, "{terrain:?}: a ray ran out of steps at pixel {i}");
                if t < 0.0 {
                    continue;
                }
                hits += 1;
                let at = hit(&v, i % SIZE.0 as usize, i / SIZE.0 as usize, t);
                // f32 positions relative to the eye: a millimetre plus 1e-5 of the distance
                // (the bisection ends far finer than that).
                let off = (at.y - p.land.height_at(at.x, at.z)).abs();
                assert!(
                    off < 1e-3 + 1e-5 * f64::from(t) * 10.0,
                    "{terrain:?}: pixel {i} at {t} m lands {off} m off the surface"
                );
            }
            assert!(hits > distance.len() / 4, "{terrain:?}: {hits} hits");
        }
    }
}

#[test]
fn measured_slope_bounds_find_what_the_proven_ones_find_and_the_step_cap_is_reported() {
    let gpu = common::gpu();
    let p = params(TerrainFn::Eroded);
    let land = p.land;
    for v in views(&land, 0.0) {
        let (_, measured) = cast(&gpu, &p, &v, RayMethod::Reference, |_| {});
        let (_, proven) = cast(&gpu, &p, &v, RayMethod::Reference, |u| {
            for k in 0..land.octaves as usize {
                u.prefix[k][0] = land.lipschitz(k as u32 + 1) as f32;
            }
            u.max_steps = 1 << 18;
        });
        // Where the two differ, the measured bounds stepped over a sliver of terrain: it
        // must poke above the ray by less than a tenth of a pixel's footprint there.
        let pixel_angle = 2.0 * (f64::from(v.fov_y) / 2.0).tan() / f64::from(SIZE.1);
        let mut differ = 0;
        for (i, (&a, &b)) in measured.iter().zip(&proven).enumerate() {
            if (a < 0.0) == (b < 0.0) && (a - b).abs() <= 1e-4 * b.abs() + 1e-3 {
                continue;
            }
            differ += 1;
            assert!(
                b >= 0.0 && (a < 0.0 || a > b),
                "pixel {i}: measured {a}, proven {b}"
            );
            let footprint = pixel_angle * f64::from(b);
            let end = if a > 0.0 {
                f64::from(a)
            } else {
                f64::from(b) + footprint
            };
            let (px, py) = (i % SIZE.0 as usize, i / SIZE.0 as usize);
            let poke = (0..=200)
                .map(|k| {
                    let t = f64::from(b) + (end - f64::from(b)) * f64::from(k) / 200.0;
                    let at = hit(&v, px, py, t as f32);
                    land.height_at(at.x, at.z) - at.y
                })
                .fold(f64::MIN, f64::max);
            eprintln!(
                "pixel {i}: stepped over a sliver {poke:.3} m high, footprint {footprint:.1} m"
            );
            assert!(
                poke < 0.1 * footprint,
                "pixel {i}: a sliver {poke} m high (footprint {footprint} m) missed"
            );
        }
        assert!(differ <= 2, "{differ} pixels differ");
        // Four steps are not enough: those rays say so (-2), they are not sky (-1).
        let (_, capped) = cast(&gpu, &p, &v, RayMethod::Reference, |u| u.max_steps = 4);
        let unresolved = capped.iter().filter(|&&d| d == -2.0).count();
        assert!(unresolved > capped.len() / 4, "{unresolved} unresolved");
    }
}

#[test]
fn far_from_the_origin_the_mesh_is_as_close_to_the_reference_as_near_it() {
    let gpu = common::gpu();
    let p = WorldParams {
        pixel_error: 4.0,
        ..params(TerrainFn::Eroded)
    };
    let mut world = World::new(&gpu.device, &gpu.queue, Offscreen::targets(4), p).unwrap();
    let mut single = World::new(&gpu.device, &gpu.queue, Offscreen::targets(1), p).unwrap();
    let target = Offscreen::new(&gpu.device, SIZE.0, SIZE.1, 4).unwrap();
    let mut flip = Vec::new();
    for origin in [0.0, 1.0e6] {
        let mut sum = 0.0;
        for v in views(&p.land, origin) {
            let (mesh, _) = target.render_world(&gpu, &mut world, &v, None).unwrap();
            let (_, distance) = headless::world_depth_metrics(&gpu, &mut single, &v, 1).unwrap();
            let shading = Shading::default();
            let reference =
                headless::render_world_rays(&gpu, &p, &shading, &v, Method::Reference, None)
                    .unwrap();
            assert_eq!(reference.unresolved, 0);
            let (mean, _) = metrics::image_error(
                &metrics::rgb(&reference.rgba),
                &metrics::rgb(&mesh),
                SIZE.0,
                SIZE.1,
            );
            let c = metrics::coverage(&reference.distance, &distance, 0.01);
            eprintln!("{origin} m out: FLIP {mean:.4}, {c:?}");
            // The mesh draws what the reference sees, wherever it is.
            assert!(c.missed + c.extra < 0.01, "{origin} m out: {c:?}");
            sum += mean;
        }
        flip.push(sum / 3.0);
    }
    let (near, far) = (flip[0], flip[1]);
    eprintln!("mean FLIP mesh vs reference: near the origin {near:.4}, 10^6 m out {far:.4}");
    // Different terrain lies 10^6 m out: its error may differ, but not by a different kind.
    // The bound on `near` (0.12 with the blog's palette) is 0.15 with the seed template's: its
    // rock takes light and dark tones from the colour noise, whose finest octaves the mesh's
    // levels do not keep and the reference's supersampling averages (0.13 on lavapipe).
    assert!(
        far < 1.5 * near + 0.01 && near < 0.15,
        "mesh vs reference: near {near}, far {far}"
    );
}
