//! Embedding relief in a host app that draws its own geometry into the same render pass and
//! depth buffer, using relief's core crate alone (`relief = "0.1"`, no front end): the host
//! makes its own device, target textures and readback, as any wgpu app does. Headless here (an
//! offscreen target) so it runs anywhere; a windowed host does the same with its surface
//! texture. The pillar stands on the terrain: its foot is placed with `Terrain::height_at`.
//! With `endless`, the host draws the endless world ([`relief::World`]) instead: its pillar is
//! 200 m tall on the landscape, placed with `World::height_at`, and drawn camera-relative with
//! the world's own matrix (`World::relative_matrix`), as a host must do far from the origin.
//!
//! A third argument names how relief draws it (`mesh`, the default, or `visibility`).
//!
//!     cargo run --example embed -- embed.png [endless|tile] [mesh|visibility]

use relief::{wgpu, OrbitCamera, Terrain, TerrainParams, World, WorldParams, WorldView};

/// The host's GPU: its own device and queue (relief only borrows them).
pub struct Host {
    /// The host's device.
    pub device: wgpu::Device,
    /// The host's queue.
    pub queue: wgpu::Queue,
}

impl Host {
    /// Any adapter will do; the host owns this choice, not relief.
    pub fn new() -> Result<Self, String> {
        let instance =
            wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
        let adapter = pollster::block_on(instance.request_adapter(&Default::default()))
            .map_err(|e| format!("no GPU adapter: {e}"))?;
        let (device, queue) = pollster::block_on(adapter.request_device(&Default::default()))
            .map_err(|e| format!("no GPU device: {e}"))?;
        Ok(Self { device, queue })
    }
}

/// The host's own object: a red pillar standing on the terrain at its centre, its foot below
/// the ground, drawn by the host's own pipeline.
pub struct Pillar {
    pipeline: wgpu::RenderPipeline,
    bind_group: wgpu::BindGroup,
    uniforms: wgpu::Buffer,
}

const PILLAR_WGSL: &str = r#"
// ground: foot height, half-width, bottom and top offsets; centre: x and z of its axis.
struct Uniforms { view_proj: mat4x4<f32>, ground: vec4<f32>, centre: vec4<f32> }
@group(0) @binding(0) var<uniform> u: Uniforms;

struct Out { @builtin(position) clip: vec4<f32>, @location(0) shade: f32 }

@vertex
fn vs(@builtin(vertex_index) i: u32) -> Out {
    // 6 faces x 2 triangles of a box from (-w, y0, -w) to (w, y1, w).
    let w = u.ground.y;
    let y0 = u.ground.z;
    let y1 = u.ground.w;
    let face = i / 6u;
    let corner = array<vec2<f32>, 6>(vec2(-1.0, -1.0), vec2(1.0, -1.0), vec2(1.0, 1.0),
                                     vec2(-1.0, -1.0), vec2(1.0, 1.0), vec2(-1.0, 1.0))[i % 6u];
    var p: vec3<f32>;
    switch face {
        case 0u: { p = vec3(1.0, corner.x, corner.y); }
        case 1u: { p = vec3(-1.0, corner.x, corner.y); }
        case 2u: { p = vec3(corner.x, 1.0, corner.y); }
        case 3u: { p = vec3(corner.x, -1.0, corner.y); }
        case 4u: { p = vec3(corner.x, corner.y, 1.0); }
        default: { p = vec3(corner.x, corner.y, -1.0); }
    }
    let world = vec3(u.centre.x + p.x * w, u.ground.x + mix(y0, y1, p.y * 0.5 + 0.5), u.centre.y + p.z * w);
    var out: Out;
    out.clip = u.view_proj * vec4(world, 1.0);
    out.shade = 0.6 + 0.4 * f32(face % 3u) / 2.0;
    return out;
}

@fragment
fn fs(in: Out) -> @location(0) vec4<f32> {
    return vec4(in.shade, 0.0, 0.0, 1.0);
}
"#;

impl Pillar {
    /// Builds the host pipeline for the same targets relief draws into.
    pub fn new(device: &wgpu::Device, targets: &relief::Targets) -> Self {
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("host:pillar"),
            source: wgpu::ShaderSource::Wgsl(PILLAR_WGSL.into()),
        });
        let uniforms = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("host:pillar:uniforms"),
            size: 96,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("host:pillar"),
            layout: None,
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: Default::default(),
            depth_stencil: targets.depth_format.map(|format| wgpu::DepthStencilState {
                format,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Less),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: wgpu::MultisampleState {
                count: targets.sample_count,
                ..Default::default()
            },
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs"),
                compilation_options: Default::default(),
                targets: &[Some(targets.color_format.into())],
            }),
            multiview_mask: None,
            cache: None,
        });
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("host:pillar"),
            layout: &pipeline.get_bind_group_layout(0),
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: uniforms.as_entire_binding(),
            }],
        });
        Self {
            pipeline,
            bind_group,
            uniforms,
        }
    }
}

/// What to draw in a frame.
#[derive(Clone, Copy, Debug)]
pub struct Draw {
    /// Draw the host's pillar.
    pub host: bool,
    /// Draw relief's terrain.
    pub terrain: bool,
    /// The endless world rather than the tile.
    pub endless: bool,
    /// How relief draws it: `Mesh` or `Visibility` (whose raster and shading passes
    /// `prepare` records before the host's pass).
    pub method: relief::Method,
    /// Where the visibility method and the hybrid rasterise; `Compute` draws one sample a pixel.
    pub raster: relief::Raster,
    /// In the endless world, relief's test layer too: a blue box standing behind the pillar,
    /// which the pillar hides in part (how the embedding test checks that a layer of relief's
    /// frame is depth-tested against the host's geometry).
    pub layer: bool,
}

impl Draw {
    /// relief's method configuration: the compute raster at one sample a pixel.
    fn config(&self) -> relief::MethodConfig {
        let config = relief::MethodConfig::new(self.method).with_raster(self.raster);
        if self.raster == relief::Raster::Compute {
            config.with_samples(1)
        } else {
            config
        }
    }
}

/// The host's MSAA sample count and formats; relief is built for exactly these.
const SAMPLES: u32 = 4;
const TARGETS: relief::Targets = relief::Targets {
    color_format: wgpu::TextureFormat::Rgba8UnormSrgb,
    depth_format: Some(wgpu::TextureFormat::Depth32Float),
    sample_count: SAMPLES,
};

fn target(
    host: &Host,
    label: &str,
    (w, h): (u32, u32),
    format: wgpu::TextureFormat,
    samples: u32,
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    host.device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: samples,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    })
}

/// Renders one frame of the host scene into an RGBA8 image.
pub fn render_frame(host: &Host, width: u32, height: u32, draw: Draw) -> Result<Vec<u8>, String> {
    let (device, queue) = (&host.device, &host.queue);
    let params = TerrainParams {
        size: 256,
        grid: 128,
        ..Default::default()
    };
    let pillar = Pillar::new(device, &TARGETS);
    // relief's side: the tile with an orbit camera, or the endless world with a view from
    // 150 m above its ground looking at the pillar's spot, 900 m ahead.
    let mut terrain = None;
    let mut world = None;
    let (mut view_proj, pillar_uniforms) = if draw.endless {
        let params = WorldParams {
            pixel_error: 8.0,
            ..Default::default()
        };
        let mut w = World::new(device, queue, TARGETS, params).map_err(|e| e.to_string())?;
        w.set_method(device, draw.config())
            .map_err(|e| e.to_string())?;
        let eye = glam::DVec3::new(0.0, w.height_at(0.0, 0.0) + 150.0, 0.0);
        let spot = glam::DVec3::new(900.0, w.height_at(900.0, 0.0), 0.0);
        let view = WorldView::look_at(eye, spot + glam::DVec3::Y * 60.0, 0.8, (width, height));
        if draw.layer {
            let (x, z) = (1200.0, 25.0);
            let foot = glam::DVec3::new(x, w.height_at(x, z) - 20.0, z);
            let size = glam::DVec3::new(60.0, 240.0, 60.0);
            let box_ = relief::gpu::test_box::TestBox::standing(foot, size, [0.05, 0.1, 0.9]);
            w.push_layer(Box::new(box_));
        }
        // One still frame: everything baked and lit first (a window would leave the budgets
        // as they are, and draw while the levels come in over a few frames).
        w.set_bake_budget(u64::MAX);
        w.set_light_budget(u64::MAX);
        for _ in 0..64 {
            let mut encoder = device.create_command_encoder(&Default::default());
            w.encode_bake(device, queue, &mut encoder, &view)
                .map_err(|e| e.to_string())?;
            queue.submit([encoder.finish()]);
            if w.pending_texels() == 0 {
                break;
            }
        }
        // Camera-relative, as relief draws: the pillar's place less the eye.
        let rel = spot - eye;
        let uniforms = [
            rel.y as f32,
            15.0,
            -40.0,
            200.0,
            rel.x as f32,
            rel.z as f32,
            0.0,
            0.0,
        ];
        world = Some((w, view));
        // The camera-relative matrix relief draws with, once the frame is prepared (below).
        (glam::Mat4::IDENTITY, uniforms)
    } else {
        let mut t = Terrain::new(device, queue, TARGETS, params).map_err(|e| e.to_string())?;
        t.set_method(device, draw.config())
            .map_err(|e| e.to_string())?;
        let view = OrbitCamera::default().view(width as f32 / height as f32);
        // The screen-error bound's pixels, and one still frame: every level baked at once.
        t.set_viewport((width, height));
        t.set_bake_budget(u64::MAX);
        // The host's own geometry sits on the terrain: relief answers where the ground is.
        let ground = t.height_at(0.0, 0.0) as f32;
        terrain = Some((t, view));
        (
            view.view_proj,
            [ground, 0.06, -0.2, 0.6, 0.0, 0.0, 0.0, 0.0],
        )
    };

    let attach = wgpu::TextureUsages::RENDER_ATTACHMENT;
    let size = (width, height);
    let resolved = target(
        host,
        "host:color",
        size,
        TARGETS.color_format,
        1,
        attach | wgpu::TextureUsages::COPY_SRC,
    );
    let msaa = target(
        host,
        "host:msaa",
        size,
        TARGETS.color_format,
        SAMPLES,
        attach,
    );
    let depth = target(
        host,
        "host:depth",
        size,
        wgpu::TextureFormat::Depth32Float,
        SAMPLES,
        attach,
    );

    // The host's frame: its encoder, its pass, its depth buffer; relief records into them.
    let mut encoder = device.create_command_encoder(&Default::default());
    if let Some((t, view)) = &mut terrain {
        t.prepare(device, queue, &mut encoder, view)
            .map_err(|e| e.to_string())?;
    }
    if let Some((w, view)) = &mut world {
        w.prepare(device, queue, &mut encoder, view)
            .map_err(|e| e.to_string())?;
        view_proj = w.relative_matrix();
    }
    queue.write_buffer(
        &pillar.uniforms,
        0,
        bytemuck::cast_slice(&[view_proj.to_cols_array().as_slice(), &pillar_uniforms].concat()),
    );
    {
        let clear =
            relief::gpu::clear_color(relief::Shading::default().sky_color, TARGETS.color_format);
        let msaa_view = msaa.create_view(&Default::default());
        let resolved_view = resolved.create_view(&Default::default());
        let depth_view = depth.create_view(&Default::default());
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("host:pass"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &msaa_view,
                depth_slice: None,
                resolve_target: Some(&resolved_view),
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(clear),
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
        if draw.host {
            pass.set_pipeline(&pillar.pipeline);
            pass.set_bind_group(0, &pillar.bind_group, &[]);
            pass.draw(0..36, 0..1);
        }
        if draw.terrain {
            if let Some((t, _)) = &terrain {
                t.render(&mut pass);
            }
            if let Some((w, _)) = &world {
                w.render(&mut pass);
            }
        }
    }
    // The host reads its image back its own way.
    let pitch = (width * 4).next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
    let buffer = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("host:readback"),
        size: u64::from(pitch) * u64::from(height),
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    encoder.copy_texture_to_buffer(
        resolved.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(pitch),
                rows_per_image: Some(height),
            },
        },
        resolved.size(),
    );
    queue.submit([encoder.finish()]);
    let (tx, rx) = std::sync::mpsc::channel();
    buffer.slice(..).map_async(wgpu::MapMode::Read, move |r| {
        let _ = tx.send(r);
    });
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| e.to_string())?;
    rx.recv()
        .map_err(|e| e.to_string())?
        .map_err(|e| e.to_string())?;
    let mapped = buffer
        .slice(..)
        .get_mapped_range()
        .map_err(|e| e.to_string())?;
    Ok(mapped
        .chunks(pitch as usize)
        .flat_map(|row| &row[..(width * 4) as usize])
        .copied()
        .collect())
}

#[allow(
    dead_code,
    reason = "the embedding test includes this file and calls render_frame only"
)]
fn main() -> Result<(), String> {
    let out = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "embed.png".into());
    let endless = std::env::args().nth(2).as_deref() == Some("endless");
    let method = std::env::args()
        .nth(3)
        .map_or(Some(relief::Method::Mesh), |m| {
            relief::Method::from_name(&m)
        })
        .ok_or("the third argument names a method: mesh or visibility")?;
    let host = Host::new()?;
    let (w, h) = (640, 480);
    let pixels = render_frame(
        &host,
        w,
        h,
        Draw {
            host: true,
            terrain: true,
            endless,
            method,
            raster: relief::Raster::Hardware,
            layer: false,
        },
    )?;
    image::save_buffer(&out, &pixels, w, h, image::ColorType::Rgba8).map_err(|e| e.to_string())?;
    println!("wrote {out}");
    Ok(())
}
