//! The clouds on lavapipe, at small sizes: turning them on and off draws a fresh world's frame;
//! they change only the pixels whose ray enters them, and a ridge hides those behind it; their
//! image (one pixel in 16 marched a frame) comes near the full march; their light shafts only
//! darken the air in their shadows.

#[path = "common/air.rs"]
mod air;
mod common;

use air::*;
use glam::{DVec3, Vec3};
use relief::gpu::headless::Offscreen;
use relief::sky::Sky;
use relief::{Method, Shading, World, WorldParams, WorldView};

/// The visibility method's shading is built without the clouds' march while the frame has no
/// clouds (the march is most of its build): turning the clouds on builds it in, and the frame
/// is then a fresh world's with clouds byte for byte; turning them off again gives back the
/// cloudless frame byte for byte.
#[test]
fn turning_the_clouds_on_and_off_draws_what_a_fresh_world_draws() {
    let gpu = common::gpu();
    let clear = params(0.3);
    let mut cloudy = clear;
    cloudy.clouds = relief::world::clouds::Clouds {
        coverage: 0.6,
        base: clear.land.peak_height as f32 + 150.0,
        top: clear.land.peak_height as f32 + 900.0,
        ..Default::default()
    };
    let eye = DVec3::new(300.0, clear.land.peak_height + 40.0, -200.0);
    let view = WorldView::look_at(eye, eye + DVec3::new(1.0, 0.25, 0.4), 0.9, SIZE);
    let config = relief::MethodConfig {
        method: Method::Visibility,
        samples: 1,
        raster: relief::Raster::Compute,
    };
    let target = Offscreen::new(&gpu.device, SIZE.0, SIZE.1, 1).unwrap();
    let frame = |world: &mut World| target.render_world(&gpu, world, &view, None).unwrap().0;
    let fresh = |p: WorldParams| {
        let mut world = World::new(&gpu.device, &gpu.queue, Offscreen::targets(1), p).unwrap();
        world.set_method(&gpu.device, config).unwrap();
        world
    };
    let mut world = fresh(clear);
    let without = frame(&mut world);
    world.set_params(&gpu.device, cloudy).unwrap();
    let turned_on = frame(&mut world);
    let with = frame(&mut fresh(cloudy));
    let changed = without
        .chunks(4)
        .zip(with.chunks(4))
        .filter(|(a, b)| a != b)
        .count();
    assert!(
        changed > (SIZE.0 * SIZE.1 / 10) as usize,
        "the clouds changed {changed} pixels"
    );
    assert!(turned_on == with, "turned on: not a fresh world's frame");
    world.set_params(&gpu.device, clear).unwrap();
    assert!(
        frame(&mut world) == without,
        "turned off: not the cloudless frame"
    );
    // Turned on while another method draws: the shading kept for this one is built anew when
    // it draws again.
    world.set_method(&gpu.device, Method::Mesh).unwrap();
    world.set_params(&gpu.device, cloudy).unwrap();
    world.set_method(&gpu.device, config).unwrap();
    assert!(
        frame(&mut world) == with,
        "turned on under the mesh: not a fresh world's frame"
    );
}

/// A pixel's view ray from `eye_y` along unit `dir` (camera-relative) to `far`: whether it
/// stays above altitude `top` all the way (`Some(true)`), dips below it (`Some(false)`), or
/// comes within `margin` metres of it (`None`). The layer curves with the planet as the shader's
/// does: the ray's altitude at t is eye_y + dir.y t + (1 - dir.y^2) t^2 / 2R.
fn stays_above(eye_y: f64, dir: Vec3, far: f64, top: f64, margin: f64) -> Option<bool> {
    let dy = f64::from(dir.y);
    let k = (1.0 - dy * dy) / (2.0 * relief::world::clouds::EARTH_RADIUS);
    let lowest_at = if dy < 0.0 {
        (-dy / (2.0 * k)).min(far)
    } else {
        0.0
    };
    let lowest = eye_y + dy * lowest_at + k * lowest_at * lowest_at;
    if lowest > top + margin {
        Some(true)
    } else if lowest < top - margin {
        Some(false)
    } else {
        None
    }
}

/// Seen from above a low cloud layer, a pixel changes only where its ray goes down into the
/// layer: the sky and the ridges standing out of it are the frame of a layer that no ray meets
/// (the same coverage under the ground: the overcast's grey is in both), byte for byte, and
/// that includes every ridge with clouds behind it (the march stops at the surface). Where rays
/// do enter the layer, pixels change.
#[test]
fn clouds_change_only_the_pixels_whose_ray_enters_them_and_a_ridge_hides_those_behind_it() {
    let gpu = common::gpu();
    let mut p = params(0.3);
    let layer = |base: f32, top: f32| relief::world::clouds::Clouds {
        coverage: 0.9,
        base,
        top,
        ..Default::default()
    };
    p.clouds = layer(40.0, 90.0);
    let mut buried = p;
    buried.clouds = layer(-1000.0, -900.0);
    let eye = DVec3::new(0.0, 260.0, 0.0);
    let view = WorldView::look_at(eye, eye + DVec3::new(1.0, -0.3, 0.35), 0.9, SIZE);
    let (clouded, depth, matrix) = draw(&gpu, p, Shading::default(), &view);
    let (control, _, _) = draw(&gpu, buried, Shading::default(), &view);
    let far = distances(&depth, matrix);
    let (mut clear, mut hidden, mut entering, mut changed, mut wrong) = (0, 0, 0, 0, 0);
    for y in 0..SIZE.1 {
        for x in 0..SIZE.0 {
            let i = (y * SIZE.0 + x) as usize;
            let dir = direction(matrix, x, y);
            let d = far[i].map_or(f64::INFINITY, f64::from);
            let same = clouded[4 * i..4 * i + 3] == control[4 * i..4 * i + 3];
            match stays_above(eye.y, dir, d, 90.0, 1.0) {
                Some(true) => {
                    clear += 1;
                    wrong += usize::from(!same);
                    // A ridge with the layer behind it: the ray, continued, would go down into it.
                    hidden += usize::from(
                        far[i].is_some()
                            && stays_above(eye.y, dir, f64::INFINITY, 90.0, 1.0) == Some(false),
                    );
                }
                Some(false) => {
                    entering += 1;
                    changed += usize::from(!same);
                }
                None => {}
            }
        }
    }
    eprintln!(
        "{clear} pixels whose ray stays above the layer ({hidden} ridges with clouds behind), \
         {wrong} of them changed; {changed} of {entering} entering it changed"
    );
    assert!(
        clear > 1000 && hidden > 200,
        "{clear} clear, {hidden} hiding"
    );
    assert_eq!(wrong, 0, "pixels changed whose ray never meets the layer");
    // A thin layer (50 m) over ground that rises into it: many rays cross little of it (on
    // lavapipe 29% of them changed).
    assert!(
        entering > 1000 && changed * 5 > entering,
        "{changed} of {entering}"
    );
}

/// Mean and largest difference of two RGBA8 frames' colour channels, in 1/255.
fn channel_difference(a: &[u8], b: &[u8]) -> (f64, u8) {
    let (mut sum, mut n, mut most) = (0u64, 0u64, 0u8);
    for (pa, pb) in a.chunks(4).zip(b.chunks(4)) {
        for c in 0..3 {
            let d = pa[c].abs_diff(pb[c]);
            sum += u64::from(d);
            most = most.max(d);
            n += 1;
        }
    }
    (sum as f64 / n as f64, most)
}

#[test]
fn with_the_temporal_service_the_clouds_march_one_pixel_in_16_and_come_near_the_full_march() {
    use relief::world::clouds::Clouds;
    let gpu = common::gpu();
    let clear = params(0.3);
    let mut cloudy = clear;
    cloudy.clouds = Clouds {
        coverage: 0.6,
        base: clear.land.peak_height as f32 + 150.0,
        top: clear.land.peak_height as f32 + 900.0,
        ..Default::default()
    };
    let eye = DVec3::new(300.0, clear.land.peak_height + 40.0, -200.0);
    let ahead = DVec3::new(1.0, 0.25, 0.4);
    let view_at = |k: u32| {
        // Flying sideways at 8 m a frame and turning half a degree a frame.
        let a = 0.5f64.to_radians() * f64::from(k);
        let at = eye + DVec3::new(0.0, 0.0, 8.0 * f64::from(k));
        let dir = DVec3::new(
            ahead.x * a.cos() - ahead.z * a.sin(),
            ahead.y,
            ahead.x * a.sin() + ahead.z * a.cos(),
        );
        WorldView::look_at(at, at + dir, 0.9, SIZE)
    };
    let config = relief::MethodConfig {
        method: Method::Visibility,
        samples: 1,
        raster: relief::Raster::Compute,
    };
    let target = Offscreen::new(&gpu.device, SIZE.0, SIZE.1, 1).unwrap();
    // The last of 24 frames, still or moving, and the share of the clouds each frame marched.
    let run = |p: WorldParams, moving: bool| {
        let mut world = World::new(&gpu.device, &gpu.queue, Offscreen::targets(1), p).unwrap();
        world.set_method(&gpu.device, config).unwrap();
        world
            .set_temporal(&gpu.device, relief::Temporal { frames: 16 })
            .unwrap();
        let view = |k| if moving { view_at(k) } else { view_at(0) };
        target
            .accumulate_world(&gpu, &mut world, &view(0), 0)
            .unwrap();
        let mut marched = Vec::new();
        for k in 0..23 {
            target.accumulate_frame(&gpu, &mut world, &view(k)).unwrap();
            marched.push(world.stats().clouds.map(|c| c.0));
        }
        let frame = target
            .render_world(&gpu, &mut world, &view(23), None)
            .unwrap()
            .0;
        marched.push(world.stats().clouds.map(|c| c.0));
        (frame, marched)
    };
    let full_params = WorldParams {
        clouds: Clouds {
            reproject: false,
            ..cloudy.clouds
        },
        ..cloudy
    };
    // New parameters (here the fog) start the history over, and the clouds' image with it.
    {
        let mut world = World::new(&gpu.device, &gpu.queue, Offscreen::targets(1), cloudy).unwrap();
        world.set_method(&gpu.device, config).unwrap();
        world
            .set_temporal(&gpu.device, relief::Temporal { frames: 16 })
            .unwrap();
        let view = view_at(0);
        target.accumulate_world(&gpu, &mut world, &view, 3).unwrap();
        let fraction = |w: &World| w.stats().clouds.map(|c| c.0);
        assert_eq!(fraction(&world), Some(1.0 / 16.0));
        let foggier = WorldParams {
            sky: Sky {
                fog: 0.6,
                ..cloudy.sky
            },
            ..cloudy
        };
        world.set_params(&gpu.device, foggier).unwrap();
        target.accumulate_frame(&gpu, &mut world, &view).unwrap();
        assert_eq!(fraction(&world), Some(1.0), "a new fog keeps the old image");
        target.accumulate_frame(&gpu, &mut world, &view).unwrap();
        assert_eq!(fraction(&world), Some(1.0 / 16.0));
    }
    for moving in [false, true] {
        let (image, marched) = run(cloudy, moving);
        let (full, full_marched) = run(full_params, moving);
        let (none, _) = run(clear, moving);
        if let Ok(dir) = std::env::var("RELIEF_DUMP") {
            for (name, f) in [("image", &image), ("full", &full), ("none", &none)] {
                image::save_buffer(
                    format!("{dir}/{name}-{moving}.png"),
                    f,
                    SIZE.0,
                    SIZE.1,
                    image::ExtendedColorType::Rgba8,
                )
                .unwrap();
            }
        }
        // The first frame marches every pixel, each after it one in 16; the full march
        // marches every pixel every frame.
        assert_eq!(marched[0], Some(1.0), "{marched:?}");
        assert!(
            marched[1..].iter().all(|m| *m == Some(1.0 / 16.0)),
            "{marched:?}"
        );
        assert!(full_marched.iter().all(|m| *m == Some(1.0)));
        let (mean, most) = channel_difference(&image, &full);
        let (clouds, _) = channel_difference(&none, &full);
        eprintln!(
            "moving {moving}: image against the full march: mean {mean:.3}/255, most {most}/255; \
             the clouds themselves: mean {clouds:.3}/255"
        );
        assert!(clouds > 10.0, "the clouds show: {clouds}");
        // Measured on lavapipe: still 2.5% of the clouds' own difference (the image is half
        // the frame's size, and the temporal service averages a pixel's marches at 16 step
        // offsets, the image one or two), turning and flying sideways 8.5% (the clouds' edges
        // trail where the eye's move shows them from a new side). Negative controls, on the
        // image's first, full-size version: carried over from each frame's nearest pixel,
        // which held a slowly moving view's clouds back, 15.6%; the eye's move taken the
        // wrong way, 37%.
        let bound = if moving { 0.12 } else { 0.04 };
        assert!(mean < bound * clouds, "{mean} against {clouds}");
    }
}

/// Light shafts: from below a cloud layer, looking towards a low sun through fog, the clouds'
/// shadows in the air darken it and nothing else (no channel brighter than the frame without
/// shafts), for the forward mesh's full march and the visibility method's shadows' map; in clear
/// air there is nothing to darken (byte for byte), and without clouds the frame is the
/// cloudless frame whatever `shafts` says.
#[test]
fn light_shafts_darken_the_air_in_the_clouds_shadows_and_nothing_else() {
    use relief::world::clouds::Clouds;
    let gpu = common::gpu();
    let mut p = params(0.6);
    p.sky.sun_elevation = 12.0;
    p.clouds = Clouds {
        coverage: 0.55,
        base: 400.0,
        top: 1200.0,
        ..Default::default()
    };
    let without = |p: WorldParams| WorldParams {
        clouds: Clouds {
            shafts: false,
            ..p.clouds
        },
        ..p
    };
    let eye = DVec3::new(0.0, 230.0, 0.0);
    // Towards the sun (azimuth 200: south-south-west), a little up.
    let a = 200f64.to_radians();
    let view = WorldView::look_at(eye, eye + DVec3::new(a.sin(), 0.12, -a.cos()), 1.0, SIZE);
    let visibility = relief::MethodConfig {
        method: Method::Visibility,
        samples: 1,
        raster: relief::Raster::Compute,
    };
    let target = Offscreen::new(&gpu.device, SIZE.0, SIZE.1, 1).unwrap();
    // The visibility method's frame through the temporal service (the clouds' image and its
    // shadows' map), after a few frames.
    let temporal = |p: WorldParams| {
        let mut world = World::new(&gpu.device, &gpu.queue, Offscreen::targets(1), p).unwrap();
        world.set_method(&gpu.device, visibility).unwrap();
        world
            .set_temporal(&gpu.device, relief::Temporal { frames: 8 })
            .unwrap();
        target.accumulate_world(&gpu, &mut world, &view, 3).unwrap();
        target
            .render_world(&gpu, &mut world, &view, None)
            .unwrap()
            .0
    };
    let frames = [
        (
            "mesh",
            draw(&gpu, p, Shading::default(), &view).0,
            draw(&gpu, without(p), Shading::default(), &view).0,
        ),
        ("image", temporal(p), temporal(without(p))),
    ];
    for (name, on, off) in &frames {
        if let Ok(dir) = std::env::var("RELIEF_DUMP") {
            for (which, f) in [("on", on), ("off", off)] {
                image::save_buffer(
                    format!("{dir}/shafts-{name}-{which}.png"),
                    f,
                    SIZE.0,
                    SIZE.1,
                    image::ExtendedColorType::Rgba8,
                )
                .unwrap();
            }
        }
        let (mut brighter, mut darker) = (0usize, 0usize);
        for (a, b) in on.chunks(4).zip(off.chunks(4)) {
            brighter += usize::from((0..3).any(|c| a[c] > b[c].saturating_add(1)));
            darker += usize::from((0..3).any(|c| u16::from(a[c]) + 3 <= u16::from(b[c])));
        }
        let pixels = (SIZE.0 * SIZE.1) as usize;
        eprintln!("{name}: {darker} of {pixels} pixels darker with shafts, {brighter} brighter");
        assert_eq!(brighter, 0, "{name}: shafts only take light");
        assert!(darker * 40 > pixels, "{name}: {darker} of {pixels} darker");
    }
    // Clear air scatters nothing to take; no clouds, no shafts.
    let clear = WorldParams {
        sky: Sky { fog: 0.0, ..p.sky },
        ..p
    };
    assert!(
        draw(&gpu, clear, Shading::default(), &view).0
            == draw(&gpu, without(clear), Shading::default(), &view).0
    );
    let cloudless = WorldParams {
        clouds: Clouds {
            coverage: 0.0,
            ..p.clouds
        },
        ..p
    };
    assert!(
        draw(&gpu, cloudless, Shading::default(), &view).0
            == draw(&gpu, without(cloudless), Shading::default(), &view).0
    );
}
