//! relief in a host without a window: make a device, draw one frame of the endless world into
//! a texture of the host's own, read it back and save it as a PNG.
//!
//! `cargo run --example headless -- landscape.png`

use relief::wgpu;
use relief::{MethodConfig, Targets, World, WorldParams, WorldView};

const WIDTH: u32 = 960;
const HEIGHT: u32 = 540;
const COLOR: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
const DEPTH: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "landscape.png".into());

    // The host's device. relief::gpu::request_device asks for the optional features relief
    // can use (GPU timestamps, 64-bit atomics) where the adapter has them.
    let instance =
        wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
    let adapter = pollster::block_on(instance.request_adapter(&Default::default()))?;
    let (device, queue) = pollster::block_on(relief::gpu::request_device(&adapter))?;

    // relief draws into targets of these formats, one sample a pixel.
    let targets = Targets {
        color_format: COLOR,
        depth_format: Some(DEPTH),
        sample_count: 1,
    };
    let mut world = World::new(&device, &queue, targets, WorldParams::default())?;
    world.set_method(&device, MethodConfig::MESH)?;

    // A camera 300 m above the ground, looking over the ridges. `height_at` is the CPU twin.
    let eye = glam::DVec3::new(2000.0, world.height_at(2000.0, -3000.0) + 300.0, -3000.0);
    let at = eye + glam::DVec3::new(4000.0, -500.0, 2000.0);
    let view = WorldView::look_at(eye, at, 50f32.to_radians(), (WIDTH, HEIGHT));

    // A still frame: bake every level the view needs before drawing. A window would keep the
    // per-frame budgets and let the levels come in over a few frames instead.
    world.set_bake_budget(u64::MAX);
    world.set_light_budget(u64::MAX);
    for _ in 0..64 {
        let mut encoder = device.create_command_encoder(&Default::default());
        world.encode_bake(&device, &queue, &mut encoder, &view)?;
        queue.submit([encoder.finish()]);
        if world.pending_texels() == 0 {
            break;
        }
    }

    // The host's own target and depth buffer.
    let texture = |format, usage| {
        device.create_texture(&wgpu::TextureDescriptor {
            label: Some("host:target"),
            size: wgpu::Extent3d {
                width: WIDTH,
                height: HEIGHT,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage,
            view_formats: &[],
        })
    };
    let color = texture(
        COLOR,
        wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
    );
    let depth = texture(DEPTH, wgpu::TextureUsages::RENDER_ATTACHMENT);

    // The frame: relief records its work, then draws into the host's pass.
    let mut encoder = device.create_command_encoder(&Default::default());
    world.prepare(&device, &queue, &mut encoder, &view)?;
    {
        let color_view = color.create_view(&Default::default());
        let depth_view = depth.create_view(&Default::default());
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("host:pass"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &color_view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &depth_view,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: wgpu::StoreOp::Discard,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        world.render(&mut pass);
    }

    // Read the image back: rows padded to wgpu's copy alignment.
    let pitch = (WIDTH * 4).next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
    let buffer = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("host:readback"),
        size: u64::from(pitch * HEIGHT),
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    encoder.copy_texture_to_buffer(
        color.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(pitch),
                rows_per_image: Some(HEIGHT),
            },
        },
        color.size(),
    );
    queue.submit([encoder.finish()]);
    buffer.slice(..).map_async(wgpu::MapMode::Read, |_| {});
    device.poll(wgpu::PollType::wait_indefinitely())?;
    let mapped = buffer.slice(..).get_mapped_range()?;
    let pixels: Vec<u8> = mapped
        .chunks(pitch as usize)
        .flat_map(|row| &row[..(WIDTH * 4) as usize])
        .copied()
        .collect();
    image::save_buffer(&out, &pixels, WIDTH, HEIGHT, image::ColorType::Rgba8)?;
    println!("wrote {out}");
    Ok(())
}
