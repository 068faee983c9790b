//! Embedding relief in a host app that draws its own geometry into the same render pass and
//! depth buffer. Headless here (an offscreen target) so it runs anywhere; a windowed host does
//! the same with its surface texture.
//!
//!     cargo run --example embed -- embed.png

use relief::gpu::headless::{Gpu, Offscreen};
use relief::{wgpu, OrbitCamera, Terrain, TerrainParams};

/// The host's own object: a red pillar standing in the middle of the terrain, its foot below
/// the ground, drawn by the host's own pipeline.
pub struct Pillar {
    pipeline: wgpu::RenderPipeline,
    bind_group: wgpu::BindGroup,
    uniforms: wgpu::Buffer,
}

const PILLAR_WGSL: &str = r#"
@group(0) @binding(0) var<uniform> view_proj: mat4x4<f32>;

struct Out { @builtin(position) clip: vec4<f32>, @location(0) shade: f32 }

@vertex
fn vs(@builtin(vertex_index) i: u32) -> Out {
    // 6 faces x 2 triangles of a box from (-w, y0, -w) to (w, y1, w).
    let w = 0.06;
    let y0 = -0.3;
    let y1 = 0.9;
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
    let world = vec3(p.x * w, mix(y0, y1, p.y * 0.5 + 0.5), p.z * w);
    var out: Out;
    out.clip = view_proj * vec4(world, 1.0);
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
            size: 64,
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
}

/// Renders one frame of the host scene into an RGBA8 image.
pub fn render_frame(gpu: &Gpu, width: u32, height: u32, draw: Draw) -> relief::Result<Vec<u8>> {
    let samples = 4;
    let target = Offscreen::new(&gpu.device, width, height, samples)?;
    let targets = Offscreen::targets(samples);
    let params = TerrainParams {
        size: 256,
        grid: 128,
        ..Default::default()
    };
    let mut terrain = Terrain::new(&gpu.device, &gpu.queue, targets, params)?;
    let pillar = Pillar::new(&gpu.device, &targets);
    let view = OrbitCamera::default().view(width as f32 / height as f32);

    // The host's frame: its encoder, its pass, its depth buffer; relief records into them.
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    terrain.encode_bake(&mut encoder);
    terrain.prepare(&gpu.queue, &view);
    gpu.queue.write_buffer(
        &pillar.uniforms,
        0,
        bytemuck::bytes_of(&view.view_proj.to_cols_array()),
    );
    let color_view = target.color.create_view(&Default::default());
    {
        let clear = relief::gpu::clear_color(terrain.shading().sky_color, targets.color_format);
        let mut pass = target.begin_pass(&mut encoder, &color_view, clear, None);
        if draw.host {
            pass.set_pipeline(&pillar.pipeline);
            pass.set_bind_group(0, &pillar.bind_group, &[]);
            pass.draw(0..36, 0..1);
        }
        if draw.terrain {
            terrain.render(&mut pass);
        }
    }
    gpu.queue.submit([encoder.finish()]);
    relief::gpu::headless::read_texture(&gpu.device, &gpu.queue, &target.color)
}

#[allow(
    dead_code,
    reason = "the embedding test includes this file and calls render_frame only"
)]
fn main() -> relief::Result<()> {
    let out = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "embed.png".into());
    let gpu = Gpu::new()?;
    let (w, h) = (640, 480);
    let pixels = render_frame(
        &gpu,
        w,
        h,
        Draw {
            host: true,
            terrain: true,
        },
    )?;
    relief::cli::write_png(
        std::path::Path::new(&out),
        w,
        h,
        image::ColorType::Rgba8,
        &pixels,
    )?;
    println!("wrote {out}");
    Ok(())
}
