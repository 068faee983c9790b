//! The frame written without a render pass (`World::present`, `Terrain::present`): where the
//! visibility method or the hybrid shaded it in compute, `relief render`'s target takes it by one
//! compute pass storing it (a target without storage writes: a compute pass and a copy). It is
//! the picture the composite draws into a render pass, within one level of 255 (the shader
//! encodes sRGB where the render pass's store let the GPU encode),
//! timed as `present` and not as `render`; whatever it cannot write is drawn in a render pass.

mod common;

use relief::gpu::headless::{self, Gpu, Offscreen};
use relief::gpu::timing::{GpuTimer, Slot, Timings};
use relief::{Method, OrbitCamera, Raster, Terrain, TerrainParams, World, WorldParams};

const W: u32 = 160;
const H: u32 = 96;

/// Each channel's largest difference, and the share of pixels that differ at all.
fn compare(a: &[u8], b: &[u8]) -> (u8, f64) {
    assert_eq!(a.len(), b.len());
    let most = a
        .iter()
        .zip(b)
        .map(|(x, y)| x.abs_diff(*y))
        .max()
        .unwrap_or(0);
    let pixels = a.len() / 4;
    let differ = a
        .chunks_exact(4)
        .zip(b.chunks_exact(4))
        .filter(|(p, q)| p != q)
        .count();
    (most, differ as f64 / pixels as f64)
}

/// Where the device times passes, the presented frame's timings name `present` and no render
/// pass, and the composited frame's the reverse.
fn check_timings(what: &str, presented: Option<Timings>, composited: Option<Timings>) {
    if let (Some(p), Some(c)) = (presented, composited) {
        let (present, render) = (Slot::Present as usize, Slot::Render as usize);
        assert!(
            p[present].is_some() && p[render].is_none(),
            "{what}: the presented frame's timings {p:?}"
        );
        assert!(
            c[render].is_some() && c[present].is_none(),
            "{what}: the composited frame's timings {c:?}"
        );
        assert!(relief::choice::draw_ms(&p).is_some());
    }
}

fn check_same(what: &str, presented: &[u8], composited: &[u8]) {
    let (most, differ) = compare(presented, composited);
    eprintln!(
        "{what}: presented vs composited: at most {most} level(s) apart, {:.1}% of pixels differ",
        100.0 * differ
    );
    assert!(
        most <= 1,
        "{what}: the presented frame is {most} levels from the composite"
    );
}

#[test]
fn presenting_the_tile_draws_what_the_composite_draws() {
    let gpu = common::gpu();
    let timer = GpuTimer::new(&gpu.device, &gpu.queue);
    let params = TerrainParams {
        size: 256,
        grid: 64,
        ..Default::default()
    };
    let view = OrbitCamera::default().view(W as f32 / H as f32);
    for (samples, raster) in [(4, Raster::Hardware), (1, Raster::Compute)] {
        let draw = |target: &Offscreen| {
            let mut terrain =
                Terrain::new(&gpu.device, &gpu.queue, Offscreen::targets(1), params).unwrap();
            terrain
                .set_method(
                    &gpu.device,
                    relief::MethodConfig {
                        method: Method::Visibility,
                        samples,
                        raster,
                    },
                )
                .unwrap();
            target
                .render(&gpu, &mut terrain, &view, timer.as_ref())
                .unwrap()
        };
        let presented = draw(&Offscreen::new(&gpu.device, W, H, 1).unwrap());
        let composited = draw(
            &Offscreen::new(&gpu.device, W, H, 1)
                .unwrap()
                .keeping_depth(),
        );
        let what = format!("the tile, visibility at {samples} a pixel ({raster:?})");
        check_same(&what, &presented.0, &composited.0);
        check_timings(&what, presented.1, composited.1);
    }
}

/// The endless world's `method` at one sample a pixel rasterised in compute, drawn into
/// `target`.
fn world_frame(
    gpu: &Gpu,
    method: Method,
    target: &Offscreen,
    timer: Option<&GpuTimer>,
) -> (World, (Vec<u8>, Option<Timings>)) {
    let params = WorldParams {
        pixel_error: 4.0,
        // Presenting the terrain alone: the page's and the forward methods' blades draw in a
        // render pass.
        grass: relief::grass::Grass {
            on: false,
            ..Default::default()
        },
        ..Default::default()
    };
    let mut world = World::new(&gpu.device, &gpu.queue, Offscreen::targets(1), params).unwrap();
    world
        .set_method(
            &gpu.device,
            relief::MethodConfig {
                method,
                samples: 1,
                raster: Raster::Compute,
            },
        )
        .unwrap();
    let view = common::world_view(&params, (W, H));
    let frame = target.render_world(gpu, &mut world, &view, timer).unwrap();
    (world, frame)
}

#[test]
fn presenting_the_endless_world_draws_what_the_composite_draws() {
    let gpu = common::gpu();
    let timer = GpuTimer::new(&gpu.device, &gpu.queue);
    for method in [Method::Visibility, Method::Hybrid] {
        let target = Offscreen::new(&gpu.device, W, H, 1).unwrap();
        let (_, presented) = world_frame(&gpu, method, &target, timer.as_ref());
        let target = target.keeping_depth();
        let (_, composited) = world_frame(&gpu, method, &target, timer.as_ref());
        let what = format!("the endless world, {method}");
        check_same(&what, &presented.0, &composited.0);
        check_timings(&what, presented.1, composited.1);
    }
}

/// A texture for `present` to refuse or take (and to read back).
fn texture(
    gpu: &Gpu,
    (w, h): (u32, u32),
    format: wgpu::TextureFormat,
    copy: bool,
) -> wgpu::Texture {
    let usage = wgpu::TextureUsages::RENDER_ATTACHMENT
        | wgpu::TextureUsages::COPY_SRC
        | if copy {
            wgpu::TextureUsages::COPY_DST
        } else {
            wgpu::TextureUsages::empty()
        };
    texture_with(gpu, (w, h), format, usage, 1)
}

/// A texture of any `usage` and `mips` mip levels.
fn texture_with(
    gpu: &Gpu,
    (w, h): (u32, u32),
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
    mips: u32,
) -> wgpu::Texture {
    gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: Some("present-test"),
        size: wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: 1,
        },
        mip_level_count: mips,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    })
}

#[test]
fn what_cannot_be_presented_is_left_to_the_render_pass() {
    let gpu = common::gpu();
    let target = Offscreen::new(&gpu.device, W, H, 1).unwrap();
    let (mut world, _) = world_frame(&gpu, Method::Visibility, &target, None);
    let presents = |world: &World, t: &wgpu::Texture| {
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        world.present(&mut encoder, t, None)
    };
    use wgpu::TextureFormat as F;
    // What it takes: RGBA8 and BGRA8, sRGB or not, of the frame's size, with COPY_DST.
    for format in [
        F::Rgba8UnormSrgb,
        F::Rgba8Unorm,
        F::Bgra8UnormSrgb,
        F::Bgra8Unorm,
    ] {
        assert!(
            presents(&world, &texture(&gpu, (W, H), format, true)),
            "{format:?}"
        );
    }
    // What it refuses, recording nothing.
    let refused = [
        (
            "no COPY_DST",
            texture(&gpu, (W, H), F::Rgba8UnormSrgb, false),
        ),
        (
            "another size",
            texture(&gpu, (W + 1, H), F::Rgba8UnormSrgb, true),
        ),
        (
            "a float format",
            texture(&gpu, (W, H), F::Rgba16Float, true),
        ),
    ];
    for (why, t) in &refused {
        assert!(!presents(&world, t), "presented into a target with {why}");
    }
    // Without the sky the frame is not opaque: the composite blends it over the host's pass.
    let mut shading = *world.shading();
    shading.sky = false;
    world.set_shading(shading);
    let sky_off = Offscreen::new(&gpu.device, W, H, 1).unwrap();
    let params = *world.params();
    let view = common::world_view(&params, (W, H));
    let timer = GpuTimer::new(&gpu.device, &gpu.queue);
    let (_, timings) = sky_off
        .render_world(&gpu, &mut world, &view, timer.as_ref())
        .unwrap();
    if let Some(t) = timings {
        assert!(
            t[Slot::Render as usize].is_some() && t[Slot::Present as usize].is_none(),
            "without the sky the frame goes through the render pass: {t:?}"
        );
    }
    assert!(!presents(
        &world,
        &texture(&gpu, (W, H), F::Rgba8UnormSrgb, true)
    ));
    // The forward mesh draws in the host's pass only.
    world.set_method(&gpu.device, Method::Mesh).unwrap();
    assert!(!presents(
        &world,
        &texture(&gpu, (W, H), F::Rgba8UnormSrgb, true)
    ));
    // The tile's terrain says the same through its own call.
    let mut terrain = Terrain::new(
        &gpu.device,
        &gpu.queue,
        Offscreen::targets(1),
        TerrainParams {
            size: 64,
            grid: 16,
            ..Default::default()
        },
    )
    .unwrap();
    let view = OrbitCamera::default().view(W as f32 / H as f32);
    target.render(&gpu, &mut terrain, &view, None).unwrap();
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    let t = texture(&gpu, (W, H), F::Rgba8UnormSrgb, true);
    assert!(
        !terrain.present(&mut encoder, &t, None),
        "the mesh presented"
    );
}

/// The bytes land in the target's own order: an RGBA8 target, sRGB or not, holds the bytes
/// `relief render` reads back, and a BGRA8 one (a window's surface, often) the same with red
/// and blue swapped.
#[test]
fn presenting_writes_each_formats_byte_order() {
    let gpu = common::gpu();
    let target = Offscreen::new(&gpu.device, W, H, 1).unwrap();
    let (world, (rgba, _)) = world_frame(&gpu, Method::Visibility, &target, None);
    use wgpu::TextureFormat as F;
    for format in [
        F::Rgba8UnormSrgb,
        F::Rgba8Unorm,
        F::Bgra8UnormSrgb,
        F::Bgra8Unorm,
    ] {
        let t = texture(&gpu, (W, H), format, true);
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        assert!(world.present(&mut encoder, &t, None), "{format:?}");
        gpu.queue.submit([encoder.finish()]);
        let mut bytes = headless::read_texture(&gpu.device, &gpu.queue, &t).unwrap();
        if matches!(format, F::Bgra8UnormSrgb | F::Bgra8Unorm) {
            bytes.chunks_exact_mut(4).for_each(|p| p.swap(0, 2));
        }
        assert!(
            bytes == rgba,
            "{format:?}: not the frame relief render reads back"
        );
    }
    // `relief render`'s own image takes storage writes: its frame was stored in one pass, and
    // is the packed-and-copied frame above byte for byte. So is any RGBA8 target with
    // STORAGE_BINDING, even without COPY_DST.
    let storage = wgpu::TextureUsages::STORAGE_BINDING;
    let copied = storage | wgpu::TextureUsages::COPY_SRC;
    let stored = texture_with(&gpu, (W, H), F::Rgba8Unorm, copied, 1);
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    assert!(world.present(&mut encoder, &stored, None));
    gpu.queue.submit([encoder.finish()]);
    let bytes = headless::read_texture(&gpu.device, &gpu.queue, &stored).unwrap();
    assert!(bytes == rgba, "the stored frame is not the packed one");
    // A target with mip levels takes the frame in its first.
    let mipped = texture_with(&gpu, (W, H), F::Rgba8Unorm, storage, 3);
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    assert!(world.present(&mut encoder, &mipped, None));
    gpu.queue.submit([encoder.finish()]);
    gpu.device
        .poll(wgpu::PollType::wait_indefinitely())
        .unwrap();
    assert_eq!(target.color.format(), F::Rgba8Unorm);
    assert!(target
        .color
        .usage()
        .contains(wgpu::TextureUsages::STORAGE_BINDING));
}

/// A frame presented drew no depth: reading it back is refused in words, and a target that
/// keeps its depth draws in a render pass and reads it.
#[test]
fn a_presented_frame_has_no_depth_to_read() {
    let gpu = common::gpu();
    let target = Offscreen::new(&gpu.device, W, H, 1).unwrap();
    world_frame(&gpu, Method::Visibility, &target, None);
    let e = target.read_depth(&gpu).unwrap_err().to_string();
    assert!(e.contains("keeping_depth"), "{e}");
    let target = target.keeping_depth();
    world_frame(&gpu, Method::Visibility, &target, None);
    let depth = target.read_depth(&gpu).unwrap();
    assert!(
        depth.iter().any(|&d| d < 1.0),
        "the terrain's depth was drawn"
    );
}

/// An image drawn in tiles presents each tile without a render pass: its timings hold a
/// present, as the whole image's do, and name no render pass. (What each present took is not
/// checked: lavapipe's timestamps are the CPU's.)
#[test]
fn a_tiled_image_is_presented_and_times_no_render_pass() {
    let gpu = common::gpu();
    let timer = GpuTimer::new(&gpu.device, &gpu.queue)
        .expect("timestamp queries (lavapipe and every GPU these tests run on have them)");
    let params = WorldParams {
        pixel_error: 4.0,
        // Presenting the terrain alone: the page's and the forward methods' blades draw in a
        // render pass.
        grass: relief::grass::Grass {
            on: false,
            ..Default::default()
        },
        ..Default::default()
    };
    let mut world = World::new(&gpu.device, &gpu.queue, Offscreen::targets(1), params).unwrap();
    world
        .set_method(
            &gpu.device,
            relief::MethodConfig::new(Method::Visibility).with_samples(1),
        )
        .unwrap();
    let view = common::world_view(&params, (W, H));
    let (whole_image, whole) =
        headless::render_world_image(&gpu, &mut world, &view, (W, H), W, Some(&timer)).unwrap();
    let (tiled_image, tiled) =
        headless::render_world_image(&gpu, &mut world, &view, (W, H), W / 2, Some(&timer)).unwrap();
    let differ = whole_image
        .chunks(4)
        .zip(tiled_image.chunks(4))
        .filter(|(a, b)| a != b)
        .count();
    // The tiles' projections are the whole's cropped, so a pixel may round the other way; a
    // tile drawn in the wrong place or not at all differs in far more.
    assert!(
        differ * 100 <= (W * H) as usize,
        "{differ} of {} pixels differ between the whole and the tiled image",
        W * H
    );
    let (whole, tiled) = (whole.unwrap(), tiled.unwrap());
    let (present, render) = (Slot::Present as usize, Slot::Render as usize);
    assert!(whole[present].is_some() && tiled[present].is_some());
    assert!(
        whole[render].is_none() && tiled[render].is_none(),
        "a render pass that did not run: {tiled:?}"
    );
}
