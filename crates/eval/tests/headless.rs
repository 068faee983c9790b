//! The headless helpers at sizes past one buffer or one texture: readback in bands and
//! rendering in tiles give exactly what one piece would. And the choice of the default method:
//! moving a built terrain to other targets, and measuring the candidates.

#[path = "../../../tests/common/mod.rs"]
mod common;

use relief::gpu::headless::{self, Offscreen, RENDER_SAMPLES};
use relief::{OrbitCamera, Terrain, TerrainParams};

#[test]
fn banded_readback_equals_one_piece() {
    let gpu = common::gpu();
    let params = TerrainParams {
        size: 100,
        ..Default::default()
    };
    let (terrain, _) = common::bake(&gpu, params);
    for texture in [&terrain.textures().terrain, &terrain.textures().normals] {
        let whole = headless::read_texture(&gpu.device, &gpu.queue, texture).unwrap();
        // Bands of one row's padded pitch (one row each), then of three rows' worth.
        for band in [1, 3 * 1024] {
            let mut bands = Vec::new();
            let mut starts = Vec::new();
            headless::read_texture_bands(&gpu.device, &gpu.queue, texture, band, |y, rows| {
                starts.push(y);
                bands.extend_from_slice(rows);
            })
            .unwrap();
            assert!(starts.len() > 10, "{} bands", starts.len());
            assert!(starts.windows(2).all(|w| w[0] < w[1]));
            assert!(
                bands == whole,
                "bands of {band} bytes differ from one piece"
            );
        }
    }
}

#[test]
fn tiled_render_equals_one_piece() {
    let gpu = common::gpu();
    let params = TerrainParams {
        size: 128,
        grid: 64,
        ..Default::default()
    };
    let (w, h) = (150, 100);
    let view = OrbitCamera::default().view(w as f32 / h as f32);
    let targets = Offscreen::targets(RENDER_SAMPLES);
    let mut terrain = Terrain::new(&gpu.device, &gpu.queue, targets, params).unwrap();
    let (whole, _) = headless::render_image(&gpu, &mut terrain, &view, (w, h), 4096, None).unwrap();
    // Tiles of 64 x 64: 3 x 2 tiles, the last column and row partly outside the image.
    let (tiled, _) = headless::render_image(&gpu, &mut terrain, &view, (w, h), 64, None).unwrap();
    assert_eq!(tiled.len(), whole.len());
    let n = (w * h) as usize;
    let differing = (0..n)
        .filter(|&i| tiled[4 * i..4 * i + 4] != whole[4 * i..4 * i + 4])
        .count();
    let worst = tiled
        .iter()
        .zip(&whole)
        .map(|(a, b)| a.abs_diff(*b))
        .max()
        .unwrap();
    eprintln!("tiled vs whole: {differing} of {n} pixels differ, by at most {worst}");
    // The cropped projection moves vertices by float rounding only: a few edge samples may
    // flip, nothing more (a wrong crop shifts or scales the whole picture).
    assert!(differing * 100 <= n, "{differing} of {n} pixels differ");
    assert!(
        worst <= 64 || differing * 1000 <= n,
        "{differing} pixels differ, by up to {worst}"
    );
    // Sizes out of range are refused, naming the parameter.
    let e = headless::render_image(&gpu, &mut terrain, &view, (0, 10), 64, None)
        .err()
        .unwrap()
        .to_string();
    assert!(e.contains("width"), "{e}");
}

#[test]
fn height_at_agrees_with_the_rendered_depth() {
    let gpu = common::gpu();
    // A fine grid and texture, so the drawn surface is close to the continuous one.
    let params = TerrainParams {
        size: 512,
        grid: 512,
        octaves: 5,
        ..Default::default()
    };
    let (w, h) = (96, 64);
    let view = OrbitCamera::default().view(w as f32 / h as f32);
    let target = Offscreen::new(&gpu.device, w, h, 1).unwrap();
    let mut terrain = Terrain::new(&gpu.device, &gpu.queue, Offscreen::targets(1), params).unwrap();
    target.render(&gpu, &mut terrain, &view, None).unwrap();
    let depth = target.read_depth(&gpu).unwrap();
    let vp = view.view_proj.as_dmat4();
    let (mut worst, mut n) = (0.0f64, 0);
    for y in 0..h {
        for x in 0..w {
            let d = depth[(y * w + x) as usize];
            if d >= 1.0 {
                continue;
            }
            let p = relief_eval::raycast::unproject(vp, w, h, x, y, f64::from(d));
            if p.x.abs() > 0.98 || p.z.abs() > 0.98 {
                continue; // the tile's edge: a pixel there may straddle the border
            }
            let cpu = terrain.height_at(p.x, p.z);
            worst = worst.max((cpu - p.y).abs());
            n += 1;
        }
    }
    eprintln!("{n} terrain pixels, worst |height_at - drawn| = {worst:.5}");
    assert!(n > 1000, "{n}");
    // The mesh's interpolation error at this grid (under 1e-3 of the 0.5 height scale measured)
    // plus depth-buffer precision: a wrong world mapping is off by 0.05 or more.
    assert!(worst < 5e-3, "{worst}");
}

/// `set_targets` moves a built world to another MSAA without re-baking: it then draws what a
/// world built for those targets draws.
#[test]
fn set_targets_draws_as_a_world_built_for_them() {
    let gpu = common::gpu();
    let params = TerrainParams {
        size: 128,
        grid: 32,
        ..Default::default()
    };
    let size = (64, 48);
    let view = OrbitCamera::default().view(size.0 as f32 / size.1 as f32);
    let draw = |terrain: &mut Terrain, samples: u32| {
        headless::render_image(&gpu, terrain, &view, size, headless::TILE, None)
            .unwrap_or_else(|e| panic!("{samples}x: {e}"))
            .0
    };
    let mut moved = Terrain::new(
        &gpu.device,
        &gpu.queue,
        Offscreen::targets(RENDER_SAMPLES),
        params,
    )
    .unwrap();
    let four = draw(&mut moved, 4);
    moved
        .set_targets(&gpu.device, Offscreen::targets(1))
        .unwrap();
    let one = draw(&mut moved, 1);
    let mut built = Terrain::new(&gpu.device, &gpu.queue, Offscreen::targets(1), params).unwrap();
    assert_eq!(one, draw(&mut built, 1), "moved to 1x, not as built for 1x");
    assert_ne!(one, four, "4x and 1x drew the same edges");
    // Targets are validated as at creation.
    let bad = relief::Targets {
        sample_count: 3,
        ..Offscreen::targets(1)
    };
    let e = moved.set_targets(&gpu.device, bad).unwrap_err().to_string();
    assert!(e.contains("sample_count") && e.contains("1 or 4"), "{e}");
}

/// `choose_method` leaves the scene set to draw what it chose, into the target it chose for.
#[test]
fn choose_method_leaves_the_terrain_set_to_its_choice() {
    let gpu = common::gpu();
    let params = TerrainParams {
        size: 128,
        grid: 32,
        ..Default::default()
    };
    let size = (64, 48);
    let view = OrbitCamera::default().view(size.0 as f32 / size.1 as f32);
    let mut terrain = Terrain::new(
        &gpu.device,
        &gpu.queue,
        Offscreen::targets(RENDER_SAMPLES),
        params,
    )
    .unwrap();
    terrain.set_viewport((320, 200));
    let scene = headless::TrialScene::Tile(&mut terrain, &view, size);
    let choice = headless::choose_method(&gpu, scene).unwrap();
    let chosen = choice.candidate;
    assert!(
        relief::choice::Candidate::all(relief::WorldKind::Tile).contains(&chosen),
        "{chosen}"
    );
    assert_eq!(terrain.method(), chosen.method);
    if chosen.method != relief::Method::Mesh {
        assert_eq!(terrain.method_config().samples, chosen.samples);
        assert_eq!(terrain.method_config().raster, chosen.raster);
    }
    // The trial's viewport is put back, and the next frame bakes afresh.
    assert_eq!(terrain.viewport(), (320, 200));
    assert!(terrain.needs_bake());
    assert_eq!(
        terrain.targets().sample_count,
        headless::render_samples(chosen.method)
    );
    if let relief::choice::Why::Measured {
        ms,
        frames,
        size: at,
    } = &choice.why
    {
        assert_eq!(
            ms.len(),
            relief::choice::Candidate::all(relief::WorldKind::Tile).len()
        );
        assert!(ms.iter().all(|(_, t)| *t > 0.0), "{ms:?}");
        assert_eq!((*frames, *at), (headless::TRIAL_FRAMES as usize, size));
    }
    // It draws.
    let (image, _) =
        headless::render_image(&gpu, &mut terrain, &view, size, headless::TILE, None).unwrap();
    assert_eq!(image.len(), 64 * 48 * 4);
}
