//! The sky and the air on lavapipe, at small sizes: the sky is the sky (above the horizon, seen
//! from above the highest ground, every pixel is the CPU twin's sky, for the mesh and the ray
//! casters alike), the sun's disc is where the sun is, fog grows with distance, the landscape's
//! far end fades into the sky without an edge (and does not without fog: the control), and
//! moving the sun or the fog bakes nothing; water lies only below its level and mirrors the
//! sky.

#[path = "common/air.rs"]
mod air;
mod common;

use air::*;
use glam::{DVec3, Mat4, Vec3, Vec4};
use relief::gpu::headless::{self, Gpu, Offscreen};
use relief::sky::Sky;
use relief::{Method, Shading, Wind, World, WorldParams, WorldView};

/// A linear channel as the world's palette (the seed template's) stores it: tone-mapped, then
/// sRGB-encoded, in 0..255.
fn encode(c: f32) -> f32 {
    let c = relief::palette::tone_map(c.max(0.0)).clamp(0.0, 1.0);
    255.0
        * if c <= 0.003_130_8 {
            12.92 * c
        } else {
            1.055 * c.powf(1.0 / 2.4) - 0.055
        }
}

/// Largest difference (of 255) between the pixels of `rgba` looking more than 1 degree up and
/// the twin's sky, and how many such pixels there are.
fn sky_error(rgba: &[u8], matrix: Mat4, p: &WorldParams) -> (f32, usize) {
    let light = relief::gpu::world::render_uniforms(
        p,
        &Shading::default(),
        (matrix, [-1e4, -1e4, 1e4, 1e4], DVec3::ZERO),
        false,
    )
    .sky_light();
    let (mut worst, mut count) = (0f32, 0);
    for y in 0..SIZE.1 {
        for x in 0..SIZE.0 {
            let dir = direction(matrix, x, y);
            if dir.y < 1f32.to_radians().sin() {
                continue;
            }
            let want = light.radiance(dir, true);
            let i = ((y * SIZE.0 + x) * 4) as usize;
            for c in 0..3 {
                worst = worst.max((f32::from(rgba[i + c]) - encode(want[c])).abs());
            }
            count += 1;
        }
    }
    (worst, count)
}

/// The visibility method at one sample a pixel, rasterised in compute (the landscape's default on
/// the H100), and the ray cast the reference is made of: the same bytes of sky. Its shaded image
/// was half floats once, which lavapipe's store rounds toward zero: one step under the ray cast
/// in 2.8% of a grazing view's sky values on lavapipe, and one step either side of it in 2.2% on
/// the H100 (docs/bench/exact-bytes in git history, up to a57006a).
#[test]
fn the_visibility_methods_sky_is_the_ray_casts_byte_for_byte() {
    let gpu = common::gpu();
    let p = params(1.0);
    let eye = DVec3::new(300.0, p.land.peak_height + 40.0, -200.0);
    let view = WorldView::look_at(eye, eye + DVec3::new(1.0, 0.0, 0.4), 0.9, SIZE);
    let mut world = World::new(&gpu.device, &gpu.queue, Offscreen::targets(1), p).unwrap();
    world
        .set_method(
            &gpu.device,
            relief::MethodConfig {
                method: Method::Visibility,
                samples: 1,
                raster: relief::Raster::Compute,
            },
        )
        .unwrap();
    let target = Offscreen::new(&gpu.device, SIZE.0, SIZE.1, 1).unwrap();
    let (vis, _) = target.render_world(&gpu, &mut world, &view, None).unwrap();
    let rays =
        headless::render_world_rays(&gpu, &p, &Shading::default(), &view, Method::Raymarch, None)
            .unwrap();
    let (mut off, mut worst, mut values) = (0, 0, 0);
    for (i, &d) in rays.distance.iter().enumerate() {
        if d != -1.0 {
            continue;
        }
        let pixel = |image: &[u8]| [image[4 * i], image[4 * i + 1], image[4 * i + 2]];
        for (a, b) in pixel(&vis).into_iter().zip(pixel(&rays.rgba)) {
            let diff = a.abs_diff(b);
            off += usize::from(diff != 0);
            worst = worst.max(diff);
            values += 1;
        }
    }
    assert!(values > 3 * 5000, "{values} sky values");
    eprintln!("visibility's sky against the ray cast's: {off} of {values} values differ, by {worst} at most");
    // f32 against f32 along another path to the same direction: a value on an 8-bit step's edge
    // may round either way, one in a thousand at most.
    assert!(
        worst <= 1 && off * 1000 <= values,
        "{off} of {values} values differ, by {worst} at most"
    );
}

#[test]
fn the_sky_is_the_sky_for_the_mesh_and_the_rays_and_the_sun_is_where_it_is() {
    let gpu = common::gpu();
    let p = params(1.0);
    // Above the highest the terrain can reach, looking level: nothing may cover the sky.
    let eye = DVec3::new(300.0, p.land.peak_height + 40.0, -200.0);
    let view = WorldView::look_at(eye, eye + DVec3::new(1.0, 0.0, 0.4), 0.9, SIZE);
    let (mesh, _, matrix) = draw(&gpu, p, Shading::default(), &view);
    let (worst, count) = sky_error(&mesh, matrix, &p);
    assert!(count > 2000, "{count} sky pixels");
    // 8-bit rounding and f32 against f32 with another order of operations: 2 levels.
    assert!(
        worst <= 2.0,
        "mesh: the sky differs from the twin by {worst} of 255"
    );
    let rays =
        headless::render_world_rays(&gpu, &p, &Shading::default(), &view, Method::Raymarch, None)
            .unwrap();
    let rays_matrix = relief::gpu::world_rays::ray_matrix(&view);
    let (worst, _) = sky_error(&rays.rgba, rays_matrix, &p);
    assert!(
        worst <= 2.0,
        "rays: the sky differs from the twin by {worst} of 255"
    );

    // The sun's disc: white where the sun is, sky a few pixels away from it.
    let toward = relief::sky::sun_direction(70.0, 10.0);
    let q = WorldParams {
        sky: Sky {
            sun_azimuth: 70.0,
            sun_elevation: 10.0,
            ..p.sky
        },
        ..p
    };
    let at_sun = WorldView::look_at(eye, eye + toward.as_dvec3(), 0.9, SIZE);
    let (img, _, m) = draw(&gpu, q, Shading::default(), &at_sun);
    let centre = m * toward.extend(0.0);
    let px = |ndc: f32, n: u32| ((ndc * 0.5 + 0.5) * n as f32) as usize;
    let (cx, cy) = (
        px(centre.x / centre.w, SIZE.0),
        px(-centre.y / centre.w, SIZE.1),
    );
    let at = |x: usize, y: usize| &img[(y * SIZE.0 as usize + x) * 4..][..3];
    assert!(
        at(cx, cy).iter().all(|&c| c >= 250),
        "the sun's centre is {:?}",
        at(cx, cy)
    );
    assert!(
        at(cx, cy - 8).iter().any(|&c| c < 250),
        "8 px from the sun: {:?}",
        at(cx, cy - 8)
    );
}

#[test]
fn fog_grows_with_distance_and_the_far_end_fades_into_the_sky() {
    let gpu = common::gpu();
    // The blog's flat two-colour palette: what changes with distance is then the fog, not the
    // materials and shadows of the farther ground (the fog is the same for every palette).
    let blog = |fog| WorldParams {
        palette: relief::palette::Palette::Blog,
        ..params(fog)
    };
    let clear = blog(0.0);
    let foggy = blog(0.6);
    let eye = DVec3::new(0.0, clear.land.height_at(0.0, 0.0) + 500.0, 0.0);
    let view = WorldView::look_at(eye, eye + DVec3::new(1.0, -0.12, 0.3), 0.9, SIZE);
    let (plain, depth, matrix) = draw(&gpu, clear, Shading::default(), &view);
    let (fogged, _, _) = draw(&gpu, foggy, Shading::default(), &view);
    let d = distances(&depth, matrix);

    // How far each terrain pixel moved towards the air's colour, by distance quartile.
    let mut terrain: Vec<(f32, f32)> = d
        .iter()
        .enumerate()
        .filter_map(|(i, d)| {
            d.map(|d| {
                let change: f32 = (0..3)
                    .map(|c| (f32::from(fogged[i * 4 + c]) - f32::from(plain[i * 4 + c])).abs())
                    .sum();
                (d, change)
            })
        })
        .collect();
    assert!(terrain.len() > 4000, "{} terrain pixels", terrain.len());
    terrain.sort_by(|a, b| a.0.total_cmp(&b.0));
    let quarter = terrain.len() / 4;
    let means: Vec<f32> = terrain
        .chunks(quarter)
        .take(4)
        .map(|c| c.iter().map(|t| t.1).sum::<f32>() / c.len() as f32)
        .collect();
    assert!(
        means.windows(2).all(|w| w[1] > w[0]) && means[0] > 1.0,
        "fog by distance quartile (near to far): {means:?}"
    );

    // The far end: in each column, the topmost terrain pixel against the sky pixel above it.
    let edge = |img: &[u8]| {
        let mut steps: Vec<f32> = (0..SIZE.0 as usize)
            .filter_map(|x| {
                let top = (1..SIZE.1 as usize).find(|&y| d[y * SIZE.0 as usize + x].is_some())?;
                let (a, b) = (
                    (top * SIZE.0 as usize + x) * 4,
                    ((top - 1) * SIZE.0 as usize + x) * 4,
                );
                Some(
                    (0..3)
                        .map(|c| (f32::from(img[a + c]) - f32::from(img[b + c])).abs())
                        .sum(),
                )
            })
            .collect();
        steps.sort_by(f32::total_cmp);
        steps[steps.len() / 2]
    };
    let (with_fog, without) = (edge(&fogged), edge(&plain));
    // The sky's own gradient from one row to the next is under a level per channel.
    assert!(
        with_fog <= 4.0,
        "the far end stands out of the fog by {with_fog} (median, of 3x255)"
    );
    assert!(
        without >= 20.0,
        "without fog the far end is an edge: {without} (the control)"
    );
}

#[test]
fn moving_the_sun_or_the_fog_bakes_nothing() {
    let gpu = common::gpu();
    let p = params(0.6);
    let mut world = World::new(&gpu.device, &gpu.queue, Offscreen::targets(1), p).unwrap();
    let eye = DVec3::new(0.0, p.land.height_at(0.0, 0.0) + 300.0, 0.0);
    let view = WorldView::look_at(eye, eye + DVec3::X, 0.9, SIZE);
    let target = Offscreen::new(&gpu.device, SIZE.0, SIZE.1, 1).unwrap();
    let (before, _) = target.render_world(&gpu, &mut world, &view, None).unwrap();
    assert!(world.stats().texels_baked > 0);
    for sky in [
        Sky {
            sun_azimuth: 20.0,
            ..p.sky
        },
        Sky {
            sun_elevation: 60.0,
            ..p.sky
        },
        Sky { fog: 0.0, ..p.sky },
    ] {
        world
            .set_params(&gpu.device, WorldParams { sky, ..p })
            .unwrap();
        let (after, _) = target.render_world(&gpu, &mut world, &view, None).unwrap();
        assert_eq!(world.stats().texels_baked, 0, "{sky:?} baked");
        assert_ne!(after, before, "{sky:?} changed nothing");
    }
}

/// Counts over the terrain pixels of `view` drawn with and without water at `level`: dry ones
/// (above the sand) left unchanged, of all dry; wet ones (a metre under the water) changed, of
/// all wet; and wet ones seen at a grazing angle (under 6 degrees, Fresnel over 0.4) nearer the
/// sky mirrored in calm water than the ground that was there, of all those.
fn water_counts(gpu: &Gpu, level: f32, view: &WorldView) -> [(usize, usize); 3] {
    let dry = params(0.0);
    let wet = WorldParams {
        water_level: level,
        no_water: false,
        ..dry
    };
    let (plain, depth, matrix) = draw(gpu, dry, Shading::default(), view);
    let (water, _, _) = draw(gpu, wet, Shading::default(), view);
    let region = [-1e4, -1e4, 1e4, 1e4];
    let light = relief::gpu::world::render_uniforms(
        &wet,
        &Shading::default(),
        (matrix, region, view.eye),
        false,
    )
    .sky_light();
    let inv = matrix.inverse();
    let sand_top = f64::from(level) + 1.6 * relief::gpu::world::SAND_BAND + 0.5;
    let mut counts = [(0, 0); 3];
    for y in 0..SIZE.1 {
        for x in 0..SIZE.0 {
            let i = (y * SIZE.0 + x) as usize;
            if depth[i] >= 1.0 {
                continue;
            }
            let ndc = Vec4::new(
                2.0 * (x as f32 + 0.5) / SIZE.0 as f32 - 1.0,
                1.0 - 2.0 * (y as f32 + 0.5) / SIZE.1 as f32,
                depth[i],
                1.0,
            );
            let v = inv * ndc;
            let rel = v.truncate() / v.w;
            let height = view.eye.y + f64::from(rel.y);
            let px = |img: &[u8]| [0, 1, 2].map(|c| f32::from(img[i * 4 + c]));
            let (a, b) = (px(&water), px(&plain));
            if height > sand_top {
                counts[0].1 += 1;
                counts[0].0 += usize::from(a == b);
            } else if height < f64::from(level) - 1.0 {
                counts[1].1 += 1;
                counts[1].0 += usize::from(a != b);
                let dir = rel.normalize();
                if dir.y > -6f32.to_radians().sin() {
                    let sky = light
                        .radiance(Vec3::new(dir.x, -dir.y, dir.z), true)
                        .map(encode);
                    let off = |c: [f32; 3]| (0..3).map(|k| (a[k] - c[k]).abs()).sum::<f32>();
                    counts[2].1 += 1;
                    counts[2].0 += usize::from(off(sky) < off(b));
                }
            }
        }
    }
    counts
}

#[test]
fn water_lies_only_below_its_level_and_mirrors_the_sky() {
    let gpu = common::gpu();
    let level = 58.0;
    let land = params(0.0).land;
    // Looking down on lakes: the water covers exactly the ground under its level.
    let eye = DVec3::new(0.0, land.peak_height + 150.0, 0.0);
    let down = WorldView::look_at(eye, eye + DVec3::new(1.0, -0.35, 0.3), 0.9, SIZE);
    let [(same, dry), (changed, wet), _] = water_counts(&gpu, level, &down);
    assert!(dry > 1000 && wet > 300, "{dry} dry and {wet} wet pixels");
    assert_eq!(
        same, dry,
        "pixels of ground above the water and its sand changed"
    );
    assert!(
        changed * 100 >= wet * 99,
        "{changed} of {wet} pixels under water changed"
    );
    // Across a lake at a grazing angle: the water is the sky's mirror.
    let low = DVec3::new(0.0, f64::from(level) + 12.0, 0.0);
    let across = WorldView::look_at(low, low + DVec3::new(1.0, -0.03, 0.3), 0.9, SIZE);
    let [_, _, (mirrors, grazing)] = water_counts(&gpu, level, &across);
    assert!(grazing > 50, "{grazing} water pixels at a grazing angle");
    assert!(
        mirrors * 100 >= grazing * 90,
        "{mirrors} of {grazing} grazing water pixels are nearer the mirrored sky than the ground"
    );
}

/// The water in the lakes ahead at `clock` with `wind`.
fn ripples_at(gpu: &Gpu, clock: f64, wind: Wind) -> Vec<u8> {
    let level = 58.0;
    let p = WorldParams {
        water_level: level,
        no_water: false,
        clock,
        wind,
        ..params(0.0)
    };
    let low = DVec3::new(0.0, f64::from(level) + 12.0, 0.0);
    let view = WorldView::look_at(low, low + DVec3::new(1.0, -0.2, 0.3), 0.9, SIZE);
    draw(gpu, p, Shading::default(), &view).0
}

/// The summed absolute difference of two images' bytes.
fn difference(a: &[u8], b: &[u8]) -> u64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| u64::from(x.abs_diff(*y)))
        .sum()
}

#[test]
fn the_clock_moves_the_ripples_the_wind_carries_them_and_the_clock_folds_without_a_jump() {
    let gpu = common::gpu();
    let calm = Wind {
        speed: 0.0,
        ..Wind::default()
    };
    let start = ripples_at(&gpu, 0.0, calm);
    let later = ripples_at(&gpu, 2.0, calm);
    let moved = difference(&start, &later);
    eprintln!("two seconds changed the image by {moved}");
    assert!(moved > 1000, "two seconds moved the ripples by {moved}");
    // The clock reaches the shaders reduced modulo its period, and every wave makes whole
    // cycles in it: the last hundredth of a second of the period changes the picture as any
    // other hundredth does, not as a jump to another time.
    let period = f64::from(relief::gpu::world::CLOCK_PERIOD);
    let seam = difference(&ripples_at(&gpu, period - 0.01, calm), &start);
    let step = difference(&later, &ripples_at(&gpu, 2.01, calm));
    let jump = difference(&start, &ripples_at(&gpu, 1000.0, calm));
    eprintln!("a hundredth of a second: {step} (across the fold {seam}); 1000 s: {jump}");
    assert!(
        seam <= 2 * step + 20 && seam * 5 < jump,
        "across the fold {seam}, a hundredth of a second elsewhere {step}, 1000 s {jump}"
    );
    assert_eq!(ripples_at(&gpu, period + 2.0, calm), later);
    // The wind carries the pattern: the same clock with a wind is another picture, and at
    // clock 0 the wind has carried nothing.
    let windy = Wind {
        speed: 10.0,
        from_azimuth: 200.0,
    };
    assert_ne!(ripples_at(&gpu, 2.0, windy), later);
    assert_eq!(ripples_at(&gpu, 0.0, windy), start);
}
