//! The endless world's clipmap renderer on lavapipe, at small sizes: incremental baking equals
//! baking from scratch (and the twin), no cracks between levels (and the morph is what
//! prevents them), culling, and motion far from the origin.

mod common;

use glam::DVec3;
use relief::gpu::headless::{self, Gpu, Offscreen};
use relief::landscape::{Landscape, TerrainFn};
use relief::noise::Channel;
use relief::{World, WorldParams, WorldView};

/// A small world: ridges 256 m apart, 150 m high, detail to 2 m; a loose knob keeps patches
/// (and lavapipe's work) small.
fn params() -> WorldParams {
    WorldParams {
        land: Landscape {
            seed: 11,
            octaves: 8,
            gain: 0.5,
            feature_log2: 8,
            peak_height: 150.0,
            terrain: TerrainFn::Fbm,
            period: 0,
        },
        pixel_error: 16.0,
        // The terrain alone: grass (on by default) is tests/grass.rs's.
        grass: relief::grass::Grass {
            on: false,
            ..Default::default()
        },
        ..WorldParams::default()
    }
}

const SIZE: (u32, u32) = (192, 128);

fn world(gpu: &Gpu, params: WorldParams) -> World {
    World::new(&gpu.device, &gpu.queue, Offscreen::targets(1), params).expect("world")
}

/// A view from `eye` (metres above the ground there: `eye[1]`) towards `dir`.
fn view(land: &Landscape, x: f64, z: f64, above: f64, dir: DVec3) -> WorldView {
    let eye = DVec3::new(x, land.height_at(x, z) + above, z);
    WorldView::look_at(eye, eye + dir, 50f32.to_radians(), SIZE)
}

fn bake_only(gpu: &Gpu, world: &mut World, view: &WorldView) -> u64 {
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    let texels = world
        .encode_bake(&gpu.device, &gpu.queue, &mut encoder, view)
        .expect("bake");
    gpu.queue.submit([encoder.finish()]);
    texels
}

/// The level textures' packed texels, every layer ([`relief::gpu::landscape::unpack_level_texel`]).
fn levels(gpu: &Gpu, world: &World) -> Vec<[u32; 2]> {
    bytemuck::pod_collect_to_vec(
        &headless::read_texture(&gpu.device, &gpu.queue, world.level_texture()).unwrap(),
    )
}

#[test]
fn incremental_baking_equals_a_fresh_bake_and_the_twin() {
    let gpu = common::gpu();
    let p = params();
    let land = p.land;
    let mut walked = world(&gpu, p);
    // A walk: small steps (strips), a long jump (whole levels), a climb (finer levels
    // dropped, then taken up again), diagonal moves.
    let mut last = view(&land, 0.0, 0.0, 20.0, DVec3::X);
    bake_only(&gpu, &mut walked, &last);
    let mut baked = Vec::new();
    for (i, (x, z, above)) in [
        (3.0, 1.0, 20.0),
        (17.0, -9.0, 20.0),
        (60.0, 41.0, 25.0),
        (5000.0, -3000.0, 20.0),
        (5013.0, -2990.0, 600.0),
        (5020.0, -2970.0, 15.0),
        (4990.0, -2990.0, 15.0),
    ]
    .into_iter()
    .enumerate()
    {
        last = view(&land, x, z, above, DVec3::new(1.0, -0.2, 0.3));
        baked.push((i, bake_only(&gpu, &mut walked, &last)));
    }
    // Small steps bake strips, not whole levels.
    let whole = u64::from(walked.clipmap().side()).pow(2);
    assert!(baked[0].1 < whole, "a 3 m step baked {} texels", baked[0].1);
    let mut fresh = world(&gpu, p);
    bake_only(&gpu, &mut fresh, &last);
    assert_eq!(walked.clipmap().levels, fresh.clipmap().levels);
    let side = walked.clipmap().side() as usize;
    let (a, b) = (levels(&gpu, &walked), levels(&gpu, &fresh));
    let map = fresh.clipmap();
    for (l, level) in map.levels.iter().enumerate().filter(|(_, l)| l.active) {
        let layer = l * side * side;
        let (wa, wb) = (
            &a[layer..layer + side * side],
            &b[layer..layer + side * side],
        );
        let differ = wa.iter().zip(wb).filter(|(x, y)| x != y).count();
        assert_eq!(
            differ, 0,
            "level {l}: {differ} texels differ from a fresh bake"
        );
        // Spot checks against the twin: texel of sample (i, j) is at (i, j) mod side.
        for k in 0..16i64 {
            let (i, j) = (
                i64::from(level.origin[0]) + (k * 37) % side as i64,
                i64::from(level.origin[1]) + (k * 53) % side as i64,
            );
            let t = relief::gpu::landscape::unpack_level_texel(
                wb[(j.rem_euclid(side as i64) as usize) * side
                    + i.rem_euclid(side as i64) as usize],
                level.spacing_log2,
            );
            let h = land.level_sample(Channel::Height, level.spacing_log2, i, j);
            let c = land.level_sample(Channel::Color, level.spacing_log2, i, j);
            // f32 sums of up to 8 octaves against f64: 3e-7 as in tests/landscape.rs, plus
            // half a step of the packed texel's 24-bit height and 8-bit colour.
            assert!(
                (f64::from(t[0]) - h.value).abs() < 3e-7 + 1e-7
                    && (f64::from(t[3]) - c.value).abs() < 3e-7 + 0.5 / 255.0,
                "level {l} sample ({i}, {j}): GPU {t:?}, twin {} {}",
                h.value,
                c.value
            );
            // The gradient is packed as 16-bit floats (relative precision 2^-11).
            let g =
                (f64::from(t[1]) - h.gradient[0]).abs() + (f64::from(t[2]) - h.gradient[1]).abs();
            let scale = h.gradient[0].abs() + h.gradient[1].abs() + 1e-3 / level.spacing();
            assert!(
                g < 1e-3 * scale.max(1e-3),
                "level {l} gradient {t:?} twin {:?}",
                h.gradient
            );
        }
    }
}

/// `world` drawn over a flat magenta sky (no sky pass), where a hole shows, in clear air (fog
/// would tint the far terrain towards the magenta).
fn over_magenta(mut world: World, gpu: &Gpu) -> World {
    world.set_shading(relief::Shading {
        sky_color: [1.0, 0.0, 1.0],
        sky: false,
        ..Default::default()
    });
    let mut p = *world.params();
    p.sky.fog = 0.0;
    world.set_params(&gpu.device, p).unwrap();
    world
}

/// Magenta pixels below the first terrain pixel of their column: holes in the surface. (A
/// view looking down enough that every ray below the skyline meets the ground.)
fn holes(pixels: &[u8], (w, h): (u32, u32)) -> usize {
    let magenta = |i: usize| {
        let p = &pixels[i * 4..i * 4 + 3];
        p[0] > 240 && p[1] < 16 && p[2] > 240
    };
    let mut count = 0;
    for x in 0..w as usize {
        let top = (0..h as usize).find(|&y| !magenta(y * w as usize + x));
        if let Some(top) = top {
            count += (top..h as usize)
                .filter(|&y| magenta(y * w as usize + x))
                .count();
        }
    }
    count
}

#[test]
fn no_cracks_between_levels_and_the_morph_is_what_prevents_them() {
    let gpu = common::gpu();
    let p = params();
    let land = p.land;
    let mut w = over_magenta(world(&gpu, p), &gpu);
    let target = Offscreen::new(&gpu.device, SIZE.0, SIZE.1, 1).unwrap();
    let mut with = 0;
    let mut without = 0;
    let mut transitions = 0;
    for step in 0..6 {
        let a = f64::from(step) * 0.9;
        let dir = DVec3::new(a.cos(), -0.45, a.sin());
        let v = view(
            &land,
            40.0 * f64::from(step),
            -25.0 * f64::from(step),
            30.0,
            dir,
        );
        w.set_morphing(true);
        let (on, _) = target.render_world(&gpu, &mut w, &v, None).unwrap();
        transitions = transitions.max(w.stats().levels);
        w.set_morphing(false);
        let (off, _) = target.render_world(&gpu, &mut w, &v, None).unwrap();
        with += holes(&on, SIZE);
        without += holes(&off, SIZE);
        if step == 0 {
            let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"));
            image::save_buffer(
                dir.join("world-cracks-on.png"),
                &on,
                SIZE.0,
                SIZE.1,
                image::ColorType::Rgba8,
            )
            .unwrap();
            image::save_buffer(
                dir.join("world-cracks-off.png"),
                &off,
                SIZE.0,
                SIZE.1,
                image::ColorType::Rgba8,
            )
            .unwrap();
        }
    }
    assert!(transitions >= 3, "the views cross {transitions} levels");
    assert_eq!(with, 0, "{with} crack pixels with morphing on");
    assert!(without > 0, "the control saw no cracks with morphing off");
}

#[test]
fn a_bake_budget_spreads_big_moves_over_frames_without_holes_and_ends_as_a_fresh_bake() {
    let gpu = common::gpu();
    let p = params();
    let land = p.land;
    let mut w = over_magenta(world(&gpu, p), &gpu);
    // A third of a level of this layout (33 x 33 samples: 4-cell patches at this knob).
    let budget = 363;
    w.set_bake_budget(budget);
    let target = Offscreen::new(&gpu.device, SIZE.0, SIZE.1, 1).unwrap();
    let dir = DVec3::new(1.0, -0.45, 0.3);
    let mut last = view(&land, 0.0, 0.0, 30.0, dir);
    let (mut frames, mut partial, mut most) = (0, 0, 0);
    // The first frames, a jump far away (every level whole again) while the first bake is
    // still pending, small steps, then frames until nothing waits.
    let moves = [
        (0.0, 0.0),
        (0.0, 0.0),
        (9000.0, 4000.0),
        (9003.0, 4001.0),
        (9010.0, 3990.0),
    ];
    for (x, z) in moves
        .into_iter()
        .chain(std::iter::repeat_n((9010.0, 3990.0), 80))
    {
        last = view(&land, x, z, 30.0, dir);
        let (pixels, _) = target.render_world_budgeted(&gpu, &mut w, &last).unwrap();
        let s = w.stats();
        let side = u64::from(w.clipmap().side());
        assert_eq!(side, 33, "the layout this test is sized for");
        most = most.max(s.texels_baked);
        // At most the budget (or a row more where a strip is split), or the coarsest level
        // whole where nothing could be drawn otherwise.
        assert!(s.texels_baked <= (budget + side).max(side * side), "{s:?}");
        if s.texels_pending > 0 {
            partial += 1;
            assert!(s.triangles > 0, "frame {frames} drew nothing: {s:?}");
        }
        assert_eq!(
            holes(&pixels, SIZE),
            0,
            "frame {frames}: holes while baking"
        );
        frames += 1;
        if frames >= moves.len() && s.texels_pending == 0 {
            break;
        }
    }
    assert!(partial >= 4, "{partial} frames drew with a bake pending");
    assert_eq!(w.pending_texels(), 0, "still pending after {frames} frames");
    assert!(most > budget / 2, "{most}");
    let mut fresh = world(&gpu, p);
    bake_only(&gpu, &mut fresh, &last);
    assert_eq!(w.clipmap().levels, fresh.clipmap().levels);
    let (a, b) = (levels(&gpu, &w), levels(&gpu, &fresh));
    let n = (w.clipmap().side() as usize).pow(2);
    for (l, _) in fresh
        .clipmap()
        .levels
        .iter()
        .enumerate()
        .filter(|(_, l)| l.active)
    {
        let differ = a[l * n..(l + 1) * n]
            .iter()
            .zip(&b[l * n..(l + 1) * n])
            .filter(|(x, y)| x != y)
            .count();
        assert_eq!(
            differ, 0,
            "level {l}: {differ} texels differ from a fresh bake"
        );
    }
}

#[test]
fn the_texture_memory_reported_is_what_the_device_allocated() {
    let gpu = common::gpu();
    let p = params();
    let target = Offscreen::new(&gpu.device, SIZE.0, SIZE.1, 1).unwrap();
    // Texture memory the device holds once the work submitted is done (and what it freed is
    // gone).
    let textures = || {
        gpu.device
            .poll(wgpu::PollType::wait_indefinitely())
            .unwrap();
        gpu.device.get_internal_counters().hal.texture_memory.read()
    };
    let mut w = world(&gpu, p);
    // The first frame lays the levels out for its viewport (and frees the default layout's).
    let v = view(&p.land, 0.0, 0.0, 200.0, DVec3::new(1.0, -0.3, 0.0));
    target.render_world(&gpu, &mut w, &v, None).unwrap();
    let (s, shafts) = (w.stats(), w.shafts_bytes());
    let with = textures();
    drop(w);
    let allocated = (with - textures()) as u64;
    assert_eq!(s.texture_bytes(), s.level_bytes * u64::from(s.levels_total));
    // Besides the levels, the light shafts' shadow-height map (held by every endless world),
    // the one-texel stand-ins for the tile's textures, and what the driver adds: lavapipe pads
    // rows and rounds allocations (581,120 bytes held for 470,448 reported at this small size;
    // padding is a smaller share of larger levels).
    let reported = s.texture_bytes() + shafts;
    assert_eq!(shafts, 2 << 20);
    assert!(
        allocated >= reported && allocated <= reported * 5 / 4 + (1 << 16),
        "allocated {allocated} bytes, reported {reported}"
    );
}

#[test]
fn a_view_of_only_sky_draws_nothing() {
    let gpu = common::gpu();
    let p = params();
    let mut w = world(&gpu, p);
    let target = Offscreen::new(&gpu.device, SIZE.0, SIZE.1, 1).unwrap();
    let up = view(&p.land, 0.0, 0.0, 400.0, DVec3::new(0.0, 1.0, 0.2));
    target.render_world(&gpu, &mut w, &up, None).unwrap();
    assert_eq!(w.stats().triangles, 0, "{:?}", w.stats());
    let down = view(&p.land, 0.0, 0.0, 400.0, DVec3::new(1.0, -0.3, 0.0));
    target.render_world(&gpu, &mut w, &down, None).unwrap();
    assert!(w.stats().triangles > 0);
}

fn mean_abs_diff(a: &[u8], b: &[u8]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| f64::from(x.abs_diff(*y)))
        .sum::<f64>()
        / a.len() as f64
}

#[test]
fn far_from_the_origin_a_small_step_moves_the_picture_as_it_does_near_it() {
    let gpu = common::gpu();
    let p = params();
    let land = p.land;
    let mut w = world(&gpu, p);
    let target = Offscreen::new(&gpu.device, SIZE.0, SIZE.1, 1).unwrap();
    let dir = DVec3::new(0.8, -0.35, 0.5);
    let mut change = Vec::new();
    for origin in [0.0, 1.0e6] {
        let a = view(&land, origin + 3.0, origin - 7.0, 20.0, dir);
        let mut b = a;
        b.eye += DVec3::new(0.05, 0.0, 0.03);
        let (pa, _) = target.render_world(&gpu, &mut w, &a, None).unwrap();
        let (pb, _) = target.render_world(&gpu, &mut w, &b, None).unwrap();
        change.push(mean_abs_diff(&pa, &pb));
    }
    let (near, far) = (change[0], change[1]);
    assert!(
        near > 0.0 && far > 0.0,
        "a 6 cm step changed nothing: near {near}, far {far}"
    );
    assert!(
        far < 3.0 * near + 0.05 && far > near / 3.0,
        "a 6 cm step 10^6 m out changed the picture by {far} (near the origin {near})"
    );
}

#[test]
fn the_screen_error_bound_holds_where_measured() {
    let gpu = common::gpu();
    for knob in [16.0, 4.0] {
        let p = WorldParams {
            pixel_error: knob,
            ..params()
        };
        let land = p.land;
        let mut w = world(&gpu, p);
        for (above, dir) in [
            (3.0, DVec3::new(1.0, -0.02, 0.3)),
            (40.0, DVec3::new(-0.4, -0.3, 1.0)),
            (300.0, DVec3::new(0.5, -0.6, -0.5)),
        ] {
            let v = view(&land, 17.0, -40.0, above, dir);
            let e = headless::world_screen_error(&gpu, &mut w, &v, 1).unwrap();
            let bound = w.stats().error_bound_px;
            eprintln!("knob {knob} px, {above} m up: measured max {:.3} px, p99 {:.3} px over {} pixels; bound {bound:.3} px", e.max, e.p99, e.pixels);
            assert!(e.pixels > 1000, "{e:?}");
            assert!(
                e.max <= bound,
                "knob {knob}, {above} m up: measured {e:?} over the bound {bound}"
            );
        }
    }
}

/// A slow dolly at a constant height: at each move that makes a level snap to a new origin,
/// bisects down to two camera positions a few millimetres apart on either side of the snap
/// and returns, per snap, the picture's change across it and the change over the same
/// distance just before it (motion alone).
fn dolly(gpu: &Gpu, morphing: bool) -> Vec<(f64, f64)> {
    let p = params();
    let land = p.land;
    let mut w = world(gpu, p);
    w.set_morphing(morphing);
    let target = Offscreen::new(&gpu.device, SIZE.0, SIZE.1, 1).unwrap();
    let y = land.height_at(0.0, 0.0) + 25.0;
    let dir = DVec3::new(2.5, 0.0, 0.8);
    let at = |t: f64| {
        let eye = DVec3::new(0.0, y, 0.0) + dir * t;
        WorldView::look_at(
            eye,
            eye + DVec3::new(1.0, -0.35, 0.3),
            50f32.to_radians(),
            SIZE,
        )
    };
    let render = |w: &mut World, t: f64| {
        let (img, _) = target.render_world(gpu, w, &at(t), None).unwrap();
        (img, w.stats().texels_baked > 0)
    };
    let mut out = Vec::new();
    render(&mut w, 0.0);
    for i in 1..40 {
        let (_, snapped) = render(&mut w, f64::from(i));
        if !snapped {
            continue;
        }
        let (mut a, mut b) = (f64::from(i - 1), f64::from(i));
        for _ in 0..10 {
            let m = 0.5 * (a + b);
            render(&mut w, a);
            if render(&mut w, m).1 {
                b = m;
            } else {
                a = m;
            }
        }
        let step = b - a;
        let (before_before, _) = render(&mut w, a - step);
        let (before, _) = render(&mut w, a);
        let (after, _) = render(&mut w, b);
        out.push((
            mean_abs_diff(&before, &after),
            mean_abs_diff(&before_before, &before),
        ));
        render(&mut w, f64::from(i));
    }
    out
}

#[test]
fn a_slow_dolly_does_not_pop_where_levels_move_and_without_the_morph_it_does() {
    let gpu = common::gpu();
    let on = dolly(&gpu, true);
    eprintln!("morph on: (across a snap, motion alone) {on:.4?}");
    assert!(on.len() >= 4, "the dolly moved levels {} times", on.len());
    for &(pop, motion) in &on {
        assert!(
            pop <= 3.0 * motion + 0.01,
            "a pop: {pop} across a snap, {motion} from motion alone"
        );
    }
    let off = dolly(&gpu, false);
    eprintln!("morph off: {off:.4?}");
    assert!(
        off.iter().any(|&(pop, motion)| pop > 3.0 * motion + 0.01),
        "the control saw no pop without the morph"
    );
}

/// Switching between targets and back (the window's methods draw with 4 samples or 1) makes
/// the mesh's and the sky's pipelines once per target: a switch back reuses them.
#[test]
fn a_switch_back_to_earlier_targets_makes_no_pipeline() {
    let gpu = common::gpu();
    let mut w = world(&gpu, params());
    let four = *w.targets();
    let one = relief::Targets {
        sample_count: if four.sample_count == 1 { 4 } else { 1 },
        ..four
    };
    // Live pipelines: the first switch makes the mesh's and the sky's for `one` and keeps
    // `four`'s; a switch that made them again (keeping the old) would add two each time.
    let pipelines = || {
        gpu.device
            .get_internal_counters()
            .hal
            .render_pipelines
            .read()
    };
    let before = pipelines();
    w.set_targets(&gpu.device, one).unwrap();
    let made = pipelines();
    assert_eq!(
        made,
        before + 2,
        "the first switch keeps the old targets' pipelines"
    );
    for targets in [four, one, four, one] {
        w.set_targets(&gpu.device, targets).unwrap();
        assert_eq!(*w.targets(), targets);
    }
    assert_eq!(pipelines(), made, "a switch back made pipelines");
}
