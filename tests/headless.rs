//! The headless helpers at sizes past one buffer or one texture: readback in bands and
//! rendering in tiles give exactly what one piece would.

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
