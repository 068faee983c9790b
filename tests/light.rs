//! Shadows and valley occlusion of the endless world on lavapipe, at small sizes, against the
//! truth: for level texels around the camera, lit or shadowed by the light bake agrees with an
//! f64 ray towards the sun over the CPU twin's continuous surface, outside a band two texels of
//! the finest level drawn either side of the shadow's edge, for a high, a low and a grazing sun
//! (where a coarse shadow march tunnels through thin ridges); turning the sun moves the shadows
//! (and the truth of another azimuth agrees far less: the control that shows the comparison can
//! fail); the ray casters' shadows agree with the mesh's.

mod common;

use glam::DVec3;
use relief::gpu::headless::{self, Gpu, Offscreen};
use relief::landscape::{Landscape, TerrainFn};
use relief::light::lit_by_ray;
use relief::sky::Sky;
use relief::{World, WorldParams, WorldView};

const SIZE: (u32, u32) = (160, 96);

/// A small world: ridges 256 m apart, at most 150 m high, detail to 16 m, so that the finest
/// level drawn (8 m) holds every octave and its shadows can be held to the continuous
/// surface's; a loose knob keeps lavapipe's work small.
fn params(azimuth: f32, elevation: f32) -> WorldParams {
    WorldParams {
        land: Landscape {
            seed: 11,
            octaves: 5,
            gain: 0.5,
            feature_log2: 8,
            peak_height: 150.0,
            terrain: TerrainFn::Fbm,
            period: 0,
        },
        pixel_error: 2.0,
        sky: Sky {
            sun_azimuth: azimuth,
            sun_elevation: elevation,
            fog: 0.0,
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

fn view(land: &Landscape) -> WorldView {
    let (x, z) = (300.0, -200.0);
    let eye = DVec3::new(x, land.height_at(x, z) + 30.0, z);
    WorldView::look_at(
        eye,
        eye + DVec3::new(1.0, -0.2, 0.3),
        50f32.to_radians(),
        SIZE,
    )
}

fn baked(gpu: &Gpu, p: WorldParams) -> World {
    let mut world = World::new(&gpu.device, &gpu.queue, Offscreen::targets(1), p).unwrap();
    world.set_bake_budget(u64::MAX);
    world.set_light_budget(u64::MAX);
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    world
        .encode_bake(&gpu.device, &gpu.queue, &mut encoder, &view(&p.land))
        .unwrap();
    gpu.queue.submit([encoder.finish()]);
    world
}

/// Every 2nd texel of level `l` each way: (world x, z, horizon in radians).
fn texels(gpu: &Gpu, world: &World, l: usize) -> Vec<(f64, f64, f32)> {
    headless::world_light_horizons(gpu, world, &[l], 2)
        .unwrap()
        .remove(0)
}

struct Agreement {
    /// Lit by the bake where the ray is shadowed: an occluder the bake missed.
    missed: usize,
    judged: usize,
    agree: usize,
    lit: usize,
}

/// Compares the bake's lit (horizon under the sun) with the f64 ray at each texel whose
/// neighbours `band` metres away in x and z get the same answer from the ray.
fn agreement(
    land: &Landscape,
    points: &[(f64, f64, f32)],
    (azimuth, elevation): (f32, f32),
    band: f64,
) -> Agreement {
    let slope = *land.slope_bounds().last().unwrap();
    let sun = (
        f64::from(azimuth).to_radians(),
        f64::from(elevation).to_radians(),
    );
    let ray = |x: f64, z: f64| lit_by_ray(land, (x, z), sun, slope, 1e9);
    let mut a = Agreement {
        missed: 0,
        judged: 0,
        agree: 0,
        lit: 0,
    };
    for &(x, z, horizon) in points {
        let truth = ray(x, z);
        let settled = [(band, 0.0), (-band, 0.0), (0.0, band), (0.0, -band)]
            .iter()
            .all(|(dx, dz)| ray(x + dx, z + dz) == truth);
        if !settled {
            continue;
        }
        a.judged += 1;
        a.lit += usize::from(truth);
        let gpu_lit = horizon < elevation.to_radians();
        a.agree += usize::from(gpu_lit == truth);
        a.missed += usize::from(gpu_lit && !truth);
    }
    a
}

#[test]
fn shadows_agree_with_f64_rays_towards_the_sun_for_high_low_and_grazing_suns() {
    let gpu = common::gpu();
    let azimuth = 200.0;
    for elevation in [30.0, 8.0, 3.0] {
        let p = params(azimuth, elevation);
        let world = baked(&gpu, p);
        let first = world.clipmap().first_drawn();
        for l in first..first + 3 {
            // Two texels of the level: of the finest level drawn for the first, and of the
            // coarser ones (drawn farther away, where their texels are as small on screen)
            // for the others.
            let band = 2.0 * world.clipmap().levels[l].spacing();
            let points = texels(&gpu, &world, l);
            let a = agreement(&p.land, &points, (azimuth, elevation), band);
            let share = a.agree as f64 / a.judged.max(1) as f64;
            eprintln!(
                "sun {elevation}°, level {l} ({} m): {} of {} judged texels agree ({:.2} %, {} lit where the ray is shadowed), {} lit, {} in the band",
                world.clipmap().levels[l].spacing(),
                a.agree,
                a.judged,
                100.0 * share,
                a.missed,
                a.lit,
                points.len() - a.judged
            );
            assert!(
                a.judged >= 100,
                "sun {elevation}°, level {l}: only {} of {} texels outside the band",
                a.judged,
                points.len()
            );
            assert!(
                share >= 0.99,
                "sun {elevation}°, level {l}: lit or shadowed agrees with the f64 ray at {:.2} % of texels (want 99 %)",
                100.0 * share
            );
            if elevation < 10.0 {
                assert!(
                    a.lit > 0 && a.lit < a.judged,
                    "sun {elevation}°, level {l}: {} of {} lit: the view shows no shadow edge",
                    a.lit,
                    a.judged
                );
            }
        }
    }
}

#[test]
fn turning_the_sun_moves_the_shadows_and_the_truth_of_another_sun_disagrees() {
    let gpu = common::gpu();
    let elevation: f32 = 8.0;
    let (a, b) = (200.0, 290.0);
    let wa = baked(&gpu, params(a, elevation));
    // The same world turned by set_params (what the window's keys do): only the light re-bakes.
    let mut wb = baked(&gpu, params(a, elevation));
    wb.set_params(&gpu.device, params(b, elevation)).unwrap();
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    let texels_baked = wb
        .encode_bake(
            &gpu.device,
            &gpu.queue,
            &mut encoder,
            &view(&params(a, 0.0).land),
        )
        .unwrap();
    gpu.queue.submit([encoder.finish()]);
    assert_eq!(texels_baked, 0, "turning the sun re-baked heights");
    let first = wa.clipmap().first_drawn();
    let e = elevation.to_radians();
    let (pa, pb) = (texels(&gpu, &wa, first), texels(&gpu, &wb, first));
    let moved = pa
        .iter()
        .zip(&pb)
        .filter(|(x, y)| (x.2 < e) != (y.2 < e))
        .count();
    assert!(
        moved * 10 > pa.len(),
        "turning the sun 90° changed lit or shadowed at only {moved} of {} texels",
        pa.len()
    );
    // The control: the bake for azimuth a judged by the truth for b.
    let land = params(a, elevation).land;
    let band = 2.0 * wa.clipmap().levels[first].spacing();
    let wrong = agreement(&land, &pa, (b, elevation), band);
    let share = wrong.agree as f64 / wrong.judged.max(1) as f64;
    assert!(
        share < 0.95,
        "the truth for another sun agrees at {:.1} %: the comparison cannot tell",
        100.0 * share
    );
}

#[test]
fn a_light_budget_lights_coarse_levels_first_and_ends_as_a_whole_bake() {
    // The light keeps to its per-frame budget (the window's arrival on a slow device): every
    // frame draws, a level without its light borrows a coarser level's, and once nothing
    // waits the frame is the still frame's, byte for byte. Then a turned sun: the old light
    // is drawn until the new is baked, which again ends as a whole bake.
    let gpu = common::gpu();
    let target = Offscreen::new(&gpu.device, SIZE.0, SIZE.1, 1).unwrap();
    let frames_until_done = |w: &mut World, v: &WorldView, budget: u64| {
        let side = u64::from(w.clipmap().side());
        let (mut frames, mut partial) = (0, 0);
        let last = loop {
            let (pixels, _) = target.render_world_budgeted(&gpu, w, v).unwrap();
            let s = w.stats();
            assert!(s.light_texels <= budget.max(side), "{s:?}");
            assert!(pixels.iter().any(|&b| b != 0));
            if s.light_pending > 0 {
                partial += 1;
            }
            frames += 1;
            if w.pending_texels() == 0 || frames > 400 {
                break pixels;
            }
        };
        assert_eq!(w.pending_texels(), 0, "still waiting after {frames} frames");
        (partial, last)
    };
    for azimuth in [200.0, 290.0] {
        let p = params(azimuth, 8.0);
        let v = view(&p.land);
        let whole = {
            let mut w = World::new(&gpu.device, &gpu.queue, Offscreen::targets(1), p).unwrap();
            target.render_world(&gpu, &mut w, &v, None).unwrap().0
        };
        let mut w = World::new(&gpu.device, &gpu.queue, Offscreen::targets(1), p).unwrap();
        // The first frame lays the levels out for the view, lighting a row.
        w.set_light_budget(1);
        target.render_world_budgeted(&gpu, &mut w, &v).unwrap();
        assert_eq!(w.stats().light_texels, u64::from(w.clipmap().side()));
        // Then a quarter of a level a frame: a few frames for each level.
        let budget = u64::from(w.clipmap().side()).pow(2) / 4;
        w.set_light_budget(budget);
        if azimuth == 290.0 {
            // Lit for another sun first: the turn relights every level.
            let before = params(200.0, 8.0);
            w.set_params(&gpu.device, before).unwrap();
            w.set_light_budget(u64::MAX);
            target.render_world_budgeted(&gpu, &mut w, &v).unwrap();
            assert_eq!(w.pending_texels(), 0);
            w.set_light_budget(budget);
            w.set_params(&gpu.device, p).unwrap();
        }
        let (partial, last) = frames_until_done(&mut w, &v, budget);
        assert!(
            partial >= 3,
            "azimuth {azimuth}: {partial} frames with light waiting"
        );
        let differ = last.iter().zip(&whole).filter(|(a, b)| a != b).count();
        assert_eq!(
            differ, 0,
            "azimuth {azimuth}: {differ} bytes differ from the whole bake"
        );
    }
}

/// Under a running day the light is relit in rounds while the sun moves on: at each frame the
/// shadows agree with that frame's sun (f64 rays) outside the band, as the still sun's do, at
/// the default budget's pace on a GPU (a round in 48 frames of a day in 60 s at 60 frames a
/// second: 19.2 minutes of the day a round), after rounds enough that every level has been
/// relit while the sun moved.
#[test]
fn under_a_running_day_the_shadows_agree_with_each_frames_sun() {
    let gpu = common::gpu();
    // Frames a round takes here, and the clock a frame, so that a round is 19.2 minutes of a
    // day of 60 s.
    const ROUND: u64 = 6;
    let step = 19.2 / ROUND as f64 / 1440.0 * 60.0;
    // Morning and evening, an hour of a low sun (about 8° up at the end): long shadows.
    for start in [4.8, 17.3] {
        let mut p = params(0.0, 0.0);
        p.sky = relief::day::at_time(p.sky, start);
        p.sky.day_length = 60.0;
        let v = view(&p.land);
        let mut w = World::new(&gpu.device, &gpu.queue, Offscreen::targets(1), p).unwrap();
        let frame = |w: &mut World, seconds: f64| {
            w.set_time(seconds);
            let mut encoder = gpu.device.create_command_encoder(&Default::default());
            w.encode_bake(&gpu.device, &gpu.queue, &mut encoder, &v)
                .unwrap();
            gpu.queue.submit([encoder.finish()]);
        };
        w.set_bake_budget(u64::MAX);
        w.set_light_budget(u64::MAX);
        frame(&mut w, 0.0);
        let map = w.clipmap();
        let active = map.levels.iter().filter(|l| l.active).count() as u64;
        w.set_light_budget(active * u64::from(map.side()).pow(2) / ROUND);
        for k in 1..=3 * ROUND {
            frame(&mut w, k as f64 * step);
        }
        let sky = w.sky();
        assert!(
            w.pending_texels() > 0,
            "a running day leaves light to relight"
        );
        let first = w.clipmap().first_drawn();
        for l in first..first + 3 {
            let band = 2.0 * w.clipmap().levels[l].spacing();
            let points = texels(&gpu, &w, l);
            let a = agreement(&p.land, &points, (sky.sun_azimuth, sky.sun_elevation), band);
            let share = a.agree as f64 / a.judged.max(1) as f64;
            eprintln!(
                "day from {start} h, at {} (sun {:.1}° az, {:.1}° up), level {l}: {} of {} judged texels agree ({:.2} %), {} lit",
                relief::day::clock(sky.time_of_day),
                sky.sun_azimuth,
                sky.sun_elevation,
                a.agree,
                a.judged,
                100.0 * share,
                a.lit
            );
            assert!(a.judged >= 100, "{start} h, level {l}: {} judged", a.judged);
            assert!(
                a.lit > 0 && a.lit < a.judged,
                "{start} h, level {l}: {} of {} lit: no shadow edge in view",
                a.lit,
                a.judged
            );
            assert!(
                share >= 0.99,
                "day from {start} h, level {l}: lit or shadowed agrees with the f64 ray towards the frame's sun at {:.2} % of texels (want 99 %)",
                100.0 * share
            );
        }
    }
}
