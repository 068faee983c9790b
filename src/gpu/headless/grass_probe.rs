//! The grass's probe (`wgsl/grass_probe.wgsl`): the GPU's blades and cover at given cells and
//! surfaces, for the tests that hold them to the CPU twin ([`crate::grass`]).

use crate::grass::{Blade, CoverParams, Grass};

/// The blades of the cells `cells` from `eye_cell` (each within ±2^30 of it) as the GPU
/// makes them (`blade_at` in `wgsl/grass.wgsl`), and the cover at each surface of `surfaces`
/// (the normal's y, the normalised height, the colour channel) under `cover` (`grass_cover`).
pub fn grass_probe(
    gpu: &super::Gpu,
    (grass, seed, eye_cell): (&Grass, u32, [i64; 2]),
    cells: &[[i32; 2]],
    (cover, surfaces): (&CoverParams, &[[f32; 3]]),
) -> crate::Result<(Vec<Blade>, Vec<f32>)> {
    use wgpu::util::DeviceExt as _;
    let device = &gpu.device;
    let mut render: crate::gpu::RenderUniforms = bytemuck::Zeroable::zeroed();
    render.snow_height = cover.snow_height;
    render.sand_band = cover.sand_band;
    if let Some(level) = cover.water {
        render.water_on = 1;
        render.water_level = level;
    }
    let uniforms = crate::gpu::grass::GrassUniforms::new(grass, seed, eye_cell);
    let init = |label: &str, contents: &[u8], usage| {
        device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents,
            usage,
        })
    };
    let storage = wgpu::BufferUsages::STORAGE;
    let out = |label: &str, bytes: u64| {
        device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: bytes.max(4),
            usage: storage | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        })
    };
    let surfaces4: Vec<[f32; 4]> = surfaces.iter().map(|s| [s[0], s[1], s[2], 0.0]).collect();
    // Empty inputs bind one unused element: a binding holds at least one.
    let cells_in: Vec<[i32; 2]> = if cells.is_empty() {
        vec![[0; 2]]
    } else {
        cells.to_vec()
    };
    let surfaces_in = if surfaces4.is_empty() {
        vec![[0.0; 4]]
    } else {
        surfaces4
    };
    let buffers = [
        init(
            "relief:grass-probe:grass",
            bytemuck::bytes_of(&uniforms),
            wgpu::BufferUsages::UNIFORM,
        ),
        init(
            "relief:grass-probe:render",
            bytemuck::bytes_of(&render),
            wgpu::BufferUsages::UNIFORM,
        ),
        init(
            "relief:grass-probe:cells",
            bytemuck::cast_slice(&cells_in),
            storage,
        ),
        out("relief:grass-probe:blades", 40 * cells_in.len() as u64),
        init(
            "relief:grass-probe:surfaces",
            bytemuck::cast_slice(&surfaces_in),
            storage,
        ),
        out("relief:grass-probe:cover", 4 * surfaces_in.len() as u64),
    ];
    let [grass_buf, render_buf, cells_buf, blades_buf, surfaces_buf, cover_buf] = &buffers;
    let source = crate::gpu::shader::source("grass_probe");
    let read = crate::gpu::scoped(device, || {
        let module = crate::gpu::shader::module(device, "relief:grass-probe", &source);
        let mut encoder = device.create_command_encoder(&Default::default());
        for (entry, io) in [
            ("blades_cs", [(0, cells_buf), (1, blades_buf)]),
            ("cover_cs", [(2, surfaces_buf), (3, cover_buf)]),
        ] {
            let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some("relief:grass-probe"),
                layout: None,
                module: &module,
                entry_point: Some(entry),
                compilation_options: Default::default(),
                cache: None,
            });
            let group = |index: u32, entries: &[(u32, &wgpu::Buffer)]| {
                let entries: Vec<_> = entries
                    .iter()
                    .map(|&(binding, b)| wgpu::BindGroupEntry {
                        binding,
                        resource: b.as_entire_binding(),
                    })
                    .collect();
                device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("relief:grass-probe"),
                    layout: &pipeline.get_bind_group_layout(index),
                    entries: &entries,
                })
            };
            // Each entry point's layout holds the uniforms it reads.
            let uniform = if entry == "blades_cs" {
                (0, grass_buf)
            } else {
                (1, render_buf)
            };
            let uniforms = group(0, &[uniform]);
            let io_group = group(1, &io);
            let n = if entry == "blades_cs" {
                cells_in.len()
            } else {
                surfaces_in.len()
            };
            let mut pass = encoder.begin_compute_pass(&Default::default());
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, &uniforms, &[]);
            pass.set_bind_group(1, &io_group, &[]);
            pass.dispatch_workgroups((n as u32).div_ceil(64), 1, 1);
        }
        let staging = [blades_buf, cover_buf].map(|b| {
            let s = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("relief:grass-probe:staging"),
                size: b.size(),
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            encoder.copy_buffer_to_buffer(b, 0, &s, 0, b.size());
            s
        });
        gpu.queue.submit([encoder.finish()]);
        staging
    })?;
    let floats = |b: &wgpu::Buffer| -> crate::Result<Vec<f32>> {
        let bytes = crate::gpu::map_read(device, b)?;
        Ok(bytemuck::cast_slice(&bytes).to_vec())
    };
    let blades = floats(&read[0])?
        .chunks_exact(10)
        .take(cells.len())
        .map(|v| Blade {
            offset: [v[0], v[1]],
            height: v[2],
            facing: v[3],
            lean: v[4],
            curve: v[5],
            width: v[6],
            shade: v[7],
            keep: v[8],
            far: v[9],
        })
        .collect();
    let mut cover = floats(&read[1])?;
    cover.truncate(surfaces.len());
    Ok((blades, cover))
}
