//! The GPU's grass (`wgsl/grass.wgsl`) against its CPU twin (`relief::grass`): the same blade
//! in every cell, near the origin and 10^6 and 10^9 m from it, and the same cover of grass on
//! every kind of ground.

mod common;

use relief::grass::{blade, cover, Grass};

/// Cells around an eye's cell: a square of 41 x 41, and a few far ones.
fn cells() -> Vec<[i32; 2]> {
    let mut cells: Vec<[i32; 2]> = (-20..=20)
        .flat_map(|i| (-20..=20).map(move |j| [i, j]))
        .collect();
    cells.extend([[5000, -7000], [-100_000, 3], [1 << 20, -(1 << 20)]]);
    cells
}

#[test]
fn the_gpu_grows_the_twins_blades_anywhere() {
    let gpu = common::gpu();
    let grass = Grass::default();
    let p = relief::WorldParams::default().grass_cover();
    for (seed, at) in [
        (7, [0.0, 0.0]),
        (11, [1e6, -1e6]),
        (7, [-1e9, 1e9]),
        (3, [4e9, 2e9]),
    ] {
        let eye = grass.cell_at(at[0], at[1]);
        let cells = cells();
        let (gpu_blades, _) =
            relief::gpu::headless::grass_probe(&gpu, (&grass, seed, eye), &cells, (&p, &[]))
                .unwrap();
        let mut worst = 0.0f32;
        for (c, got) in cells.iter().zip(&gpu_blades) {
            let want = blade(
                &grass,
                seed,
                [eye[0] + i64::from(c[0]), eye[1] + i64::from(c[1])],
            );
            // The hash's numbers are exact; what is computed from them may differ by a
            // rounding (a fused multiply-add on the GPU).
            assert_eq!(got.offset, want.offset, "cell {c:?} at {at:?}");
            assert_eq!(
                (got.shade, got.keep, got.far),
                (want.shade, want.keep, want.far),
                "cell {c:?}"
            );
            for (g, w) in [
                (got.height, want.height),
                (got.facing, want.facing),
                (got.lean, want.lean),
                (got.curve, want.curve),
                (got.width, want.width),
            ] {
                worst = worst.max((g - w).abs() / w.abs().max(1e-3));
            }
        }
        eprintln!("seed {seed} at {at:?}: worst relative difference {worst:e}");
        assert!(worst < 1e-5, "{worst}");
    }
}

#[test]
fn the_gpu_covers_the_ground_as_the_twin_does() {
    let gpu = common::gpu();
    let p = relief::WorldParams::default().grass_cover();
    let mut surfaces = Vec::new();
    for n in 0..=20 {
        for h in 0..=40 {
            for t in 0..=4 {
                surfaces.push([0.4 + 0.03 * n as f32, h as f32 / 40.0, t as f32 / 4.0]);
            }
        }
    }
    let grass = Grass::default();
    let (_, got) =
        relief::gpu::headless::grass_probe(&gpu, (&grass, 7, [0, 0]), &[], (&p, &surfaces))
            .unwrap();
    let mut worst = 0.0f32;
    for (s, g) in surfaces.iter().zip(&got) {
        worst = worst.max((g - cover(&p, s[0], s[1], s[2])).abs());
    }
    eprintln!(
        "cover: worst difference {worst:e} over {} surfaces",
        surfaces.len()
    );
    assert!(worst < 1e-4, "{worst}");
    // Every kind of ground is among them: none, some and full cover.
    assert!(got.contains(&0.0) && got.iter().any(|&c| c > 0.99));
    assert!(got.iter().any(|&c| c > 0.05 && c < 0.95));
}

/// A point of the default world's meadow (grass all round it, dry land, in the sun).
fn meadow(params: &relief::WorldParams) -> glam::DVec3 {
    params
        .find_meadow([2000.0, -3000.0])
        .expect("a meadow near (2000, -3000)")
}

/// Pixels whose colour differs by more than a few steps between two frames.
fn changed(a: &[u8], b: &[u8]) -> usize {
    a.chunks(4)
        .zip(b.chunks(4))
        .filter(|(p, q)| p.iter().zip(q.iter()).any(|(x, y)| x.abs_diff(*y) > 6))
        .count()
}

#[test]
fn every_mesh_method_grows_grass_on_a_meadow_and_none_when_it_is_off() {
    use relief::gpu::headless::{self, render_samples, Offscreen};
    use relief::{Method, MethodConfig, Raster, Temporal, World, WorldView};
    let gpu = common::gpu();
    // From bare ground (grass grows by default), grass turned on and off again.
    let mut params = relief::WorldParams::default();
    params.grass.on = false;
    let foot = meadow(&params);
    let size = (160, 90);
    let eye = foot + glam::DVec3::new(0.0, 1.7, 0.0);
    let view = WorldView::look_at(eye, eye + glam::DVec3::new(30.0, -6.0, 10.0), 0.8, size);
    let configs = [
        (MethodConfig::MESH, 1),
        (MethodConfig::MESH, 4),
        (
            MethodConfig::new(Method::Visibility)
                .with_samples(1)
                .with_raster(Raster::Compute),
            1,
        ),
    ];
    for (config, frames) in configs {
        let targets = Offscreen::targets(render_samples(config.method));
        let mut world = World::new(&gpu.device, &gpu.queue, targets, params).unwrap();
        world.set_method(&gpu.device, config).unwrap();
        world
            .set_temporal(&gpu.device, Temporal { frames })
            .unwrap();
        let draw = |world: &mut World| {
            headless::render_world_frames(&gpu, world, &view, (size, frames), headless::TILE, None)
                .unwrap()
                .0
        };
        let bare = draw(&mut world);
        assert_eq!(world.grass_bytes(), 0);
        let grass_on = |world: &mut World, on: bool| {
            let mut p = *world.params();
            p.grass.on = on;
            world.set_params(&gpu.device, p).unwrap();
        };
        grass_on(&mut world, true);
        assert!(world.grass_bytes() > 0);
        let grassy = draw(&mut world);
        grass_on(&mut world, false);
        let again = draw(&mut world);
        let shown = changed(&bare, &grassy);
        let pixels = (size.0 * size.1) as usize;
        eprintln!("{config:?}, {frames} frames: grass changed {shown} of {pixels} pixels");
        assert!(shown > pixels / 10, "{config:?}: grass drew {shown} pixels");
        assert!(
            again == bare,
            "{config:?}: grass off, the frame is the bare one"
        );
    }
    // Out of range: refused in words, changing nothing (the world stays bare).
    let mut world = World::new(&gpu.device, &gpu.queue, Offscreen::targets(1), params).unwrap();
    let mut tall = *world.params();
    tall.grass = Grass {
        on: true,
        height: 50.0,
        ..Default::default()
    };
    let e = world.set_params(&gpu.device, tall).unwrap_err().to_string();
    assert!(e.contains("grass_height") && e.contains("50"), "{e}");
    assert_eq!(world.grass_bytes(), 0);
    assert!(!world.params().grass.on);
}

/// Writes the meadow with grass, from the ground, to `target/grass-meadow.png` (for a look).
#[test]
#[ignore = "a picture to look at, not a check"]
fn a_meadow_to_look_at() {
    use relief::gpu::headless::{self, Offscreen};
    use relief::{World, WorldView};
    let gpu = common::gpu();
    let mut params = relief::WorldParams::default();
    params.grass.on = true;
    let foot = meadow(&params);
    eprintln!("the meadow at {foot}");
    let size = (480, 270);
    let mut world = World::new(&gpu.device, &gpu.queue, Offscreen::targets(4), params).unwrap();
    // From 1.7 m looking level, and from 10 m looking 30 degrees down.
    for (name, up, look) in [
        ("grass-meadow.png", 1.7, glam::DVec3::new(30.0, -4.0, 10.0)),
        ("grass-above.png", 10.0, glam::DVec3::new(17.0, -11.5, 6.0)),
    ] {
        let eye = foot + glam::DVec3::new(0.0, up, 0.0);
        let view = WorldView::look_at(eye, eye + look, 0.8, size);
        let (pixels, _) =
            headless::render_world_image(&gpu, &mut world, &view, size, headless::TILE, None)
                .unwrap();
        image_out(name, size, &pixels);
    }
}

fn image_out(name: &str, (w, h): (u32, u32), rgba: &[u8]) {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("target")
        .join(name);
    image::save_buffer(&path, rgba, w, h, image::ColorType::Rgba8).unwrap();
    eprintln!("wrote {}", path.display());
}

#[test]
fn the_wind_blows_the_tips_downwind_as_the_twin_does_and_says_how_they_moved() {
    use relief::gpu::headless::{self, Offscreen};
    use relief::{World, WorldView};
    let gpu = common::gpu();
    let mut params = relief::WorldParams::default();
    params.grass.on = true;
    // A west wind (blowing east, +x) of 8 m/s, 3 s into the clock.
    params.wind = relief::Wind {
        speed: 8.0,
        from_azimuth: 270.0,
    };
    params.clock = 3.0;
    let foot = meadow(&params);
    let size = (96, 54);
    let eye = foot + glam::DVec3::new(0.0, 1.7, 0.0);
    let view = WorldView::look_at(eye, eye + glam::DVec3::new(30.0, -6.0, 10.0), 0.8, size);
    // With the temporal service each blade also says how far its tip moved since the last
    // frame, a tenth of a second before (its history is carried along that).
    let mut world = World::new(&gpu.device, &gpu.queue, Offscreen::targets(1), params).unwrap();
    world
        .set_temporal(&gpu.device, relief::Temporal::INTERACTIVE)
        .unwrap();
    let step = 0.1;
    for time in [0.0, step] {
        world.set_time(time);
        headless::render_world_image(&gpu, &mut world, &view, size, headless::TILE, None).unwrap();
    }
    let clock = params.clock + step;
    let blades = world
        .grass_blades(&gpu.device, &gpu.queue, 4000)
        .unwrap()
        .unwrap();
    assert!(blades.len() > 500, "{} blades", blades.len());
    let v = params.wind.velocity();
    let (mut got, mut want, mut worst) = (0.0f64, 0.0f64, 0.0f32);
    let (mut moved, mut worst_moved) = (0.0f64, 0.0f32);
    for b in &blades {
        let root = [eye.x + f64::from(b[0]), eye.z + f64::from(b[2])];
        let twin = relief::grass::wind_tip([v.x, v.y], clock, root, b[4]);
        let before = relief::grass::wind_tip([v.x, v.y], clock - step, root, b[4]);
        assert!(b[12] > 0.0 && b[13].abs() < 1e-6, "downwind: {b:?}");
        got += f64::from(b[12]);
        want += f64::from(twin[0]);
        worst = worst.max((b[12] - twin[0]).abs() / twin[0]);
        // The push's change along x (the 12th number) and z (the 16th: none, the wind is west).
        let change = twin[0] - before[0];
        moved += f64::from(change.abs());
        worst_moved = worst_moved.max((b[11] - change).abs());
        assert!(b[15].abs() < 1e-6, "across the wind: {b:?}");
    }
    let n = blades.len() as f64;
    eprintln!(
        "{} blades: mean tip push {:.4} m, the twin's {:.4} m, worst {worst:.2e} relative; \
         moved {:.2e} m on average in {step} s, worst {worst_moved:.1e} m off the twin",
        blades.len(),
        got / n,
        want / n,
        moved / n,
    );
    assert!((got / want - 1.0).abs() < 0.2, "{got} against {want}");
    assert!(worst < 0.01, "{worst}");
    // The gusts move the tips by millimetres to centimetres a tenth of a second; the GPU's
    // change matches the twin's to a hundredth of the mean (f32 phases).
    assert!(moved / n > 1e-3, "{moved}");
    assert!(f64::from(worst_moved) < 0.01 * moved / n, "{worst_moved}");
}

#[test]
fn the_compute_raster_draws_the_blades_the_rasteriser_draws() {
    // The visibility method at one sample a pixel, its raster by the GPU's rasteriser (the
    // blades drawn after the composite) and in compute (with ids: the blades in its visibility
    // buffer, shaded in its compute pass): the same blades lit the same way, so the two
    // pictures differ only where a pixel centre falls on a blade's edge or a triangle's
    // depth differs by rounding. From 1.7 m, and from 0.3 m, where the nearest blades'
    // triangles are big (the raster lists their tiles for a workgroup each).
    use relief::gpu::headless::{self, Offscreen};
    use relief::{Method, MethodConfig, Raster, World, WorldView};
    let gpu = common::gpu();
    let mut params = relief::WorldParams::default();
    // A third of the default's blades to 40 m: the same drawing, quicker on a software device.
    params.grass.density = 32.0;
    params.grass.distance = 40.0;
    let foot = meadow(&params);
    let size = (256, 144);
    let views = [
        ("standing", 1.7, glam::DVec3::new(30.0, -6.0, 10.0)),
        ("low", 0.3, glam::DVec3::new(30.0, -1.0, 10.0)),
    ];
    // Per raster, per view: (pixels the grass changed, the picture with grass).
    let mut pictures = Vec::new();
    for raster in [Raster::Hardware, Raster::Compute] {
        let mut world = World::new(&gpu.device, &gpu.queue, Offscreen::targets(1), params).unwrap();
        let config = MethodConfig::new(Method::Visibility)
            .with_samples(1)
            .with_raster(raster);
        world.set_method(&gpu.device, config).unwrap();
        for (name, up, look) in views {
            let eye = foot + glam::DVec3::new(0.0, up, 0.0);
            let view = WorldView::look_at(eye, eye + look, 0.8, size);
            let mut shown = Vec::new();
            for on in [false, true] {
                let mut p = *world.params();
                p.grass.on = on;
                world.set_params(&gpu.device, p).unwrap();
                let (pixels, _) = headless::render_world_image(
                    &gpu,
                    &mut world,
                    &view,
                    size,
                    headless::TILE,
                    None,
                )
                .unwrap();
                if on {
                    let drawn_by = world.grass_raster();
                    if raster == Raster::Compute && drawn_by != Some(Raster::Compute) {
                        eprintln!("no 64-bit atomics here: the compute raster leaves the blades");
                        return;
                    }
                    assert_eq!(drawn_by, Some(raster));
                }
                shown.push(pixels);
            }
            let grass = changed(&shown[0], &shown[1]);
            eprintln!("{name}, {raster:?}: grass covers {grass} pixels");
            pictures.push((grass, shown.pop().unwrap()));
        }
    }
    let (hardware, compute) = pictures.split_at(views.len());
    for (((name, _, _), (hw_grass, hw)), (cs_grass, cs)) in views.iter().zip(hardware).zip(compute)
    {
        image_out(&format!("grass-{name}-rasteriser.png"), size, hw);
        image_out(&format!("grass-{name}-compute.png"), size, cs);
        let pixels = (size.0 * size.1) as usize;
        assert!(*hw_grass > pixels / 10, "{name}: {hw_grass}");
        // The same coverage within 10%, and few pixels apart (edges).
        let ratio = *cs_grass as f64 / *hw_grass as f64;
        assert!(
            (0.9..1.1).contains(&ratio),
            "{name}: {cs_grass} vs {hw_grass}"
        );
        let apart = changed(hw, cs);
        eprintln!("{name}: {apart} pixels differ between the two");
        assert!(apart < hw_grass / 4, "{name}: {apart} of {hw_grass}");
    }
}

#[test]
fn the_roots_stand_on_the_surface_the_mesh_draws() {
    // The forward mesh at one sample: each kept blade's root (read back, camera-relative) against
    // the depth the mesh drew without grass at the root's point on screen (the nearest pixel
    // centre's depth carried to the point along the depth's gradient there, where the pixels
    // around it lie on one plane). The root may stand above or below the drawn surface by at
    // most max(1 cm, the height that spans 0.1 px there): the bound.
    use relief::gpu::headless::Offscreen;
    use relief::{World, WorldView};
    let gpu = common::gpu();
    let mut params = relief::WorldParams::default();
    params.grass.on = true;
    let foot = meadow(&params);
    let size = (320u32, 180u32);
    let eye = foot + glam::DVec3::new(0.0, 10.0, 0.0);
    let view = WorldView::look_at(eye, eye + glam::DVec3::new(17.0, -11.5, 6.0), 0.8, size);
    let mut world = World::new(&gpu.device, &gpu.queue, Offscreen::targets(1), params).unwrap();
    let target = Offscreen::new(&gpu.device, size.0, size.1, 1)
        .unwrap()
        .keeping_depth();
    target.render_world(&gpu, &mut world, &view, None).unwrap();
    // Every blade kept: the order the scatter lists them in is no blade's property.
    let blades = world
        .grass_blades(&gpu.device, &gpu.queue, 1 << 19)
        .unwrap()
        .unwrap();
    let mut p = *world.params();
    p.grass.on = false;
    world.set_params(&gpu.device, p).unwrap();
    target.render_world(&gpu, &mut world, &view, None).unwrap();
    let depth = target.read_depth(&gpu).unwrap();
    let m = world.relative_matrix();
    let inverse = m.inverse();
    let (w, h) = (size.0 as i64, size.1 as i64);
    let at = |x: i64, y: i64| depth[(y * w + x) as usize];
    let focal = 0.5 * size.1 as f32 * m.y_axis.y.hypot(m.y_axis.z.hypot(m.y_axis.x));
    let (mut checked, mut within, mut worst) = (0, 0, 0.0f32);
    let mut errors = Vec::new();
    for b in &blades {
        let root = glam::Vec3::new(b[0], b[1], b[2]);
        let c = m * root.extend(1.0);
        if c.w <= 0.0 {
            continue;
        }
        let ndc = c.truncate() / c.w;
        let (sx, sy) = (
            (ndc.x * 0.5 + 0.5) * size.0 as f32,
            (0.5 - ndc.y * 0.5) * size.1 as f32,
        );
        let (x, y) = (sx.floor() as i64, sy.floor() as i64);
        if x < 1 || y < 1 || x >= w - 1 || y >= h - 1 {
            continue;
        }
        // One plane around the pixel: the depth's differences agree on either side.
        let (l, r, u, d, here) = (
            at(x - 1, y),
            at(x + 1, y),
            at(x, y - 1),
            at(x, y + 1),
            at(x, y),
        );
        let planar =
            |a: f32, b: f32| ((b - here) - (here - a)).abs() <= 1e-3 * (b - a).abs() + 1e-7;
        if !(planar(l, r) && planar(u, d)) || here >= 1.0 {
            continue;
        }
        let drawn = here
            + 0.5 * (r - l) * (sx - (x as f32 + 0.5))
            + 0.5 * (d - u) * (sy - (y as f32 + 0.5));
        let q = inverse * glam::Vec4::new(ndc.x, ndc.y, drawn, 1.0);
        let q = q.truncate() / q.w;
        let error = (root.y - q.y).abs();
        let bound = 0.01f32.max(0.1 * c.w / focal);
        checked += 1;
        within += usize::from(error <= bound);
        worst = worst.max(error / bound);
        errors.push(error);
    }
    errors.sort_by(f32::total_cmp);
    let median = errors.get(errors.len() / 2).copied().unwrap_or(f32::NAN);
    eprintln!(
        "{checked} roots of {} checked: {within} within the bound, the median {median:.2e} m, \
         the worst {worst:.2} bounds",
        blades.len()
    );
    assert!(checked > 200, "{checked}");
    assert!(
        within as f64 >= 0.99 * checked as f64,
        "{within} of {checked}"
    );
    assert!(median < 1e-3, "{median}");
}

#[test]
fn the_peer_draws_its_whole_patch_by_the_raster_asked_and_goes_away() {
    // Terra's way (relief::grass::Peer): a patch of the preset's cells, every blade on grass
    // kept (none culled to the view) in four segments, by the raster asked; `None` is relief's
    // grass again, as it was.
    use relief::gpu::headless::Offscreen;
    use relief::grass::Peer;
    use relief::{Method, MethodConfig, Raster, World, WorldView};
    let gpu = common::gpu();
    let mut params = relief::WorldParams::default();
    params.grass.on = true;
    params.grass.density = 32.0;
    let foot = meadow(&params);
    let size = (128u32, 72u32);
    let eye = foot + glam::DVec3::new(0.0, 1.7, 0.0);
    let view = WorldView::look_at(eye, eye + glam::DVec3::new(30.0, -4.0, 10.0), 0.8, size);
    let mut world = World::new(&gpu.device, &gpu.queue, Offscreen::targets(1), params).unwrap();
    let config = MethodConfig::new(Method::Visibility)
        .with_samples(1)
        .with_raster(Raster::Compute);
    world.set_method(&gpu.device, config).unwrap();
    let target = Offscreen::new(&gpu.device, size.0, size.1, 1).unwrap();
    let counts = |world: &mut World| {
        target.render_world(&gpu, world, &view, None).unwrap();
        world
            .grass_counts(&gpu.device, &gpu.queue)
            .unwrap()
            .unwrap()
    };
    let ours = counts(&mut world);
    let ours_raster = world.grass_raster();
    for rasteriser in [true, false] {
        let peer = Peer {
            blades: 20_000,
            rasteriser,
        };
        world.set_grass_peer(&gpu.device, Some(peer)).unwrap();
        let [considered, _, drawn, triangles] = counts(&mut world);
        eprintln!("{peer:?}: {considered} considered, {drawn} drawn, {triangles} triangles");
        assert!((19_000..21_000).contains(&considered), "{considered}");
        // Most of the patch is kept, behind the eye too (relief keeps what is in view).
        assert!(
            drawn > considered / 2 && drawn > ours[2],
            "{drawn} vs {ours:?}"
        );
        assert_eq!(triangles, 7 * drawn);
        let by = if rasteriser || ours_raster != Some(Raster::Compute) {
            Raster::Hardware
        } else {
            Raster::Compute
        };
        assert_eq!(world.grass_raster(), Some(by));
    }
    world.set_grass_peer(&gpu.device, None).unwrap();
    assert_eq!(counts(&mut world), ours);
    assert_eq!(world.grass_raster(), ours_raster);
}
