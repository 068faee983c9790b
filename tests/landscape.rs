//! The endless world's bake on the GPU against its CPU twin (`relief::landscape`), near the
//! origin and 10^6 m out, for both terrain functions, with wrapping (toroidal) texel addresses.

mod common;

use relief::gpu::headless;
use relief::gpu::landscape::{LandscapeBake, Rect};
use relief::landscape::{Landscape, TerrainFn};
use relief::noise::Channel;

/// Bakes `rect` into a fresh `wrap` x `wrap` one-layer texture and reads it back.
fn bake(gpu: &headless::Gpu, land: &Landscape, wrap: u32, rect: Rect) -> Vec<[f32; 4]> {
    let texture = gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: Some("test:landscape"),
        size: wgpu::Extent3d {
            width: wrap,
            height: wrap,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: LandscapeBake::FORMAT,
        usage: wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    });
    let view = texture.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        ..Default::default()
    });
    let pass = LandscapeBake::new(&gpu.device);
    let target = pass.bind(&gpu.device, &view, wrap);
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    pass.encode(&gpu.queue, &mut encoder, &target, land, &[rect], None);
    gpu.queue.submit([encoder.finish()]);
    bytemuck::pod_collect_to_vec(
        &headless::read_texture(&gpu.device, &gpu.queue, &texture).unwrap(),
    )
}

#[test]
fn gpu_landscape_matches_the_twin_anywhere() {
    let gpu = common::gpu();
    for terrain in [TerrainFn::Fbm, TerrainFn::Eroded] {
        let land = Landscape {
            seed: 7,
            octaves: 12,
            gain: 0.47,
            feature_log2: 11,
            peak_height: 1200.0,
            terrain,
            period: 0,
        };
        // Near the origin (negative samples too), and 10^6 m out at a 0.25 m spacing.
        for (level_log2, origin) in [
            (0, [-20, -13]),
            (-2, [4_000_000, -4_000_017]),
            (5, [31_250, 7]),
        ] {
            let wrap = 48;
            let rect = Rect {
                layer: 0,
                level_log2,
                origin,
                extent: [wrap, wrap],
            };
            let texels = bake(&gpu, &land, wrap, rect);
            let (mut dh, mut dg, mut dc) = (0.0f64, 0.0f64, 0.0f64);
            let slope = land.lipschitz(land.octaves) / land.peak_height;
            for j in 0..wrap as i64 {
                for i in 0..wrap as i64 {
                    let (si, sj) = (i64::from(origin[0]) + i, i64::from(origin[1]) + j);
                    // Toroidal address: sample s lives at s mod wrap.
                    let (x, y) = (
                        si.rem_euclid(i64::from(wrap)),
                        sj.rem_euclid(i64::from(wrap)),
                    );
                    let t = texels[(y * i64::from(wrap) + x) as usize];
                    let h = land.level_sample(Channel::Height, level_log2, si, sj);
                    let c = land.level_sample(Channel::Color, level_log2, si, sj);
                    dh = dh.max((f64::from(t[0]) - h.value).abs());
                    dg = dg.max(
                        (f64::from(t[1]) - h.gradient[0])
                            .abs()
                            .max((f64::from(t[2]) - h.gradient[1]).abs())
                            / slope,
                    );
                    dc = dc.max((f64::from(t[3]) - c.value).abs());
                }
            }
            eprintln!(
                "{terrain:?} level 2^{level_log2} m at {origin:?}: max |dh| {dh:.2e}, |d grad| {dg:.2e} of the slope bound, |dc| {dc:.2e}"
            );
            // f32 sums of up to 12 octaves of values below 1: a few ulps of 1 each. A wrong
            // cell, fraction or octave is off by ~1e-2.
            assert!(
                dh < 1e-5 && dc < 1e-5,
                "{terrain:?} {level_log2} {origin:?}: {dh} {dc}"
            );
            // Gradients sum terms up to the slope bound with f32 rounding each.
            assert!(
                dg < 1e-5,
                "{terrain:?} {level_log2} {origin:?}: gradient off by {dg}"
            );
        }
    }
}
