//! In the browser (wasm32, through `wasm-bindgen-test` and WebGPU): the bake's heights match
//! the CPU twin with the same tolerance as native. Run by web/test/run.sh in headless Chromium.
#![cfg(target_arch = "wasm32")]

use relief::noise::{Channel, Fbm};
use relief::{Terrain, TerrainParams};
use wasm_bindgen_test::*;

wasm_bindgen_test_configure!(run_in_browser);

/// Same bound as native (crates/eval/tests/bake_vs_twin.rs): f32 rounding of a few ulps per octave; a
/// wrong hash, gradient or octave would be off by ~1e-2.
const HEIGHT_TOL: f64 = 1e-5;

async fn read_texture(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    texture: &wgpu::Texture,
) -> Vec<u8> {
    let (w, h) = (texture.width(), texture.height());
    let bpp = texture.format().block_copy_size(None).unwrap();
    let pitch = (w * bpp).next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
    let buffer = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("test:readback"),
        size: u64::from(pitch * h),
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut encoder = device.create_command_encoder(&Default::default());
    encoder.copy_texture_to_buffer(
        texture.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(pitch),
                rows_per_image: Some(h),
            },
        },
        texture.size(),
    );
    queue.submit([encoder.finish()]);
    let (tx, rx) = futures_channel::oneshot::channel();
    buffer.slice(..).map_async(wgpu::MapMode::Read, move |r| {
        let _ = tx.send(r);
    });
    rx.await.unwrap().expect("map");
    let view = buffer.slice(..).get_mapped_range().unwrap();
    view.chunks(pitch as usize)
        .flat_map(|row| &row[..(w * bpp) as usize])
        .copied()
        .collect()
}

#[wasm_bindgen_test]
async fn bake_matches_twin_in_the_browser() {
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle());
    let adapter = instance
        .request_adapter(&Default::default())
        .await
        .expect("no WebGPU adapter: start Chromium with --enable-unsafe-webgpu");
    let (device, queue) = relief::gpu::request_device(&adapter).await.unwrap();
    let targets = relief::Targets {
        color_format: wgpu::TextureFormat::Rgba8UnormSrgb,
        depth_format: None,
        sample_count: 1,
    };
    for (seed, octaves, offset) in [(7, 8, [0.0, 0.0]), (4_000_000_000, 12, [1e6 + 0.3, -2.7])] {
        let params = TerrainParams {
            seed,
            octaves,
            frequency: 3,
            offset,
            size: 128,
            ..Default::default()
        };
        let mut terrain = Terrain::new(&device, &queue, targets, params).unwrap();
        let mut encoder = device.create_command_encoder(&Default::default());
        assert!(terrain.encode_textures(&mut encoder, None) > 0);
        queue.submit([encoder.finish()]);
        let raw = read_texture(&device, &queue, &terrain.textures().terrain).await;
        let rg: Vec<[f32; 2]> = bytemuck::pod_collect_to_vec(&raw);
        let fbm = Fbm::from_params(&params);
        let twin = fbm.bake(Channel::Height, params.size);
        let err = rg
            .iter()
            .zip(&twin)
            .map(|(g, &t)| (f64::from(g[0]) - t).abs())
            .fold(0.0, f64::max);
        web_sys::console::log_1(
            &format!("browser bake seed {seed}: max |gpu - twin| = {err:.2e}").into(),
        );
        assert!(
            err <= HEIGHT_TOL,
            "seed {seed}: max error {err:e} > {HEIGHT_TOL}"
        );
    }
}
