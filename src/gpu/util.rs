//! The small builders every pass shares: textures, bind-group layout entries, uniform and slot
//! buffers, render and compute pipelines, and the square dispatch.

use super::{Targets, WORKGROUP};

/// A single-sampled 2-D texture without mips: what every pass's own target is.
pub(crate) fn texture_2d(
    device: &wgpu::Device,
    label: &str,
    (width, height): (u32, u32),
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    })
}

/// An sRGB colour as the clear value of a `target` attachment: linear for sRGB formats
/// (the hardware encodes), the sRGB values themselves for the others.
pub fn clear_color(srgb: [f32; 3], target: wgpu::TextureFormat) -> wgpu::Color {
    let [r, g, b] = srgb.map(|c| {
        f64::from(if target.is_srgb() {
            crate::params::srgb_to_linear(c)
        } else {
            c
        })
    });
    wgpu::Color { r, g, b, a: 1.0 }
}

pub(crate) fn uniform_entry<T>(
    binding: u32,
    visibility: wgpu::ShaderStages,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: false,
            min_binding_size: wgpu::BufferSize::new(std::mem::size_of::<T>() as u64),
        },
        count: None,
    }
}

/// A pipeline of one full-screen triangle (`vs`, no vertex buffers, no depth) whose fragment
/// shader `fs` writes `targets`, with one bind group of `layout`.
pub(crate) fn fullscreen_pipeline(
    device: &wgpu::Device,
    label: &str,
    layout: &wgpu::BindGroupLayout,
    module: &wgpu::ShaderModule,
    (vs, fs): (&str, &str),
    targets: &[Option<wgpu::ColorTargetState>],
) -> wgpu::RenderPipeline {
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(&format!("{label}-layout")),
        bind_group_layouts: &[Some(layout)],
        immediate_size: 0,
    });
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(label),
        layout: Some(&pipeline_layout),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some(vs),
            compilation_options: Default::default(),
            buffers: &[],
        },
        primitive: Default::default(),
        depth_stencil: None,
        multisample: Default::default(),
        fragment: Some(wgpu::FragmentState {
            module,
            entry_point: Some(fs),
            compilation_options: Default::default(),
            targets,
        }),
        multiview_mask: None,
        cache: None,
    })
}

/// A bind group layout entry for a sampled 2-D array texture, not multisampled (the levels'
/// arrays: their packed heights are `Uint`).
pub(crate) fn array_texture_entry(
    binding: u32,
    visibility: wgpu::ShaderStages,
    sample_type: wgpu::TextureSampleType,
) -> wgpu::BindGroupLayoutEntry {
    sampled_entry(
        (binding, visibility),
        sample_type,
        wgpu::TextureViewDimension::D2Array,
    )
}

/// A sampled texture's layout entry, not multisampled.
fn sampled_entry(
    (binding, visibility): (u32, wgpu::ShaderStages),
    sample_type: wgpu::TextureSampleType,
    view_dimension: wgpu::TextureViewDimension,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::Texture {
            sample_type,
            view_dimension,
            multisampled: false,
        },
        count: None,
    }
}

pub(crate) fn texture_entry(
    binding: u32,
    visibility: wgpu::ShaderStages,
    filterable: bool,
) -> wgpu::BindGroupLayoutEntry {
    sampled_entry(
        (binding, visibility),
        wgpu::TextureSampleType::Float { filterable },
        wgpu::TextureViewDimension::D2,
    )
}

/// Bytes of one texel of an uncompressed `format`.
pub(crate) fn texel_bytes(format: wgpu::TextureFormat) -> u64 {
    u64::from(format.block_copy_size(None).unwrap_or(0))
}

pub(crate) fn uniform_buffer<T>(device: &wgpu::Device, label: &str) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: std::mem::size_of::<T>() as u64,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

/// The render pipeline every terrain pass draws with (`vs_main` and the fragment entry point
/// `fragment`): depth-tested and written (`Less`) when the host's pass has depth, both faces
/// (the camera can see terrain from below), the host's sample count, opaque colour.
pub(crate) fn terrain_pipeline(
    device: &wgpu::Device,
    (label, fragment): (&str, &str),
    layout: &wgpu::BindGroupLayout,
    module: &wgpu::ShaderModule,
    targets: &Targets,
    topology: wgpu::PrimitiveTopology,
    buffers: &[Option<wgpu::VertexBufferLayout<'_>>],
) -> wgpu::RenderPipeline {
    let depth = (true, wgpu::CompareFunction::Less);
    render_pipeline(
        device,
        (label, layout, module, ("vs_main", fragment)),
        targets,
        topology,
        buffers,
        depth,
    )
}

/// A render pipeline of the entry points `(vertex, fragment)` into the host's targets (opaque
/// colour, both faces), with the depth test and write of `depth` where the host's pass has
/// depth.
pub(crate) fn render_pipeline(
    device: &wgpu::Device,
    (label, layout, module, (vertex, fragment)): (
        &str,
        &wgpu::BindGroupLayout,
        &wgpu::ShaderModule,
        (&str, &str),
    ),
    targets: &Targets,
    topology: wgpu::PrimitiveTopology,
    buffers: &[Option<wgpu::VertexBufferLayout<'_>>],
    depth: (bool, wgpu::CompareFunction),
) -> wgpu::RenderPipeline {
    blended_pipeline(
        device,
        (label, layout, module, (vertex, fragment)),
        targets,
        (topology, buffers),
        depth,
        None,
    )
}

/// [`render_pipeline`] with the colour target's `blend`.
pub(crate) fn blended_pipeline(
    device: &wgpu::Device,
    (label, layout, module, (vertex, fragment)): (
        &str,
        &wgpu::BindGroupLayout,
        &wgpu::ShaderModule,
        (&str, &str),
    ),
    targets: &Targets,
    (topology, buffers): (
        wgpu::PrimitiveTopology,
        &[Option<wgpu::VertexBufferLayout<'_>>],
    ),
    (depth_write, depth_compare): (bool, wgpu::CompareFunction),
    blend: Option<wgpu::BlendState>,
) -> wgpu::RenderPipeline {
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(&format!("{label}:pipeline-layout")),
        bind_group_layouts: &[Some(layout)],
        immediate_size: 0,
    });
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(&format!("{label}:pipeline")),
        layout: Some(&pipeline_layout),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some(vertex),
            compilation_options: Default::default(),
            buffers,
        },
        primitive: wgpu::PrimitiveState {
            topology,
            cull_mode: None,
            ..Default::default()
        },
        depth_stencil: targets.depth_format.map(|format| wgpu::DepthStencilState {
            format,
            depth_write_enabled: Some(depth_write),
            depth_compare: Some(depth_compare),
            stencil: Default::default(),
            bias: Default::default(),
        }),
        multisample: wgpu::MultisampleState {
            count: targets.sample_count,
            ..Default::default()
        },
        fragment: Some(wgpu::FragmentState {
            module,
            entry_point: Some(fragment),
            compilation_options: Default::default(),
            targets: &[Some(wgpu::ColorTargetState {
                format: targets.color_format,
                blend,
                write_mask: wgpu::ColorWrites::ALL,
            })],
        }),
        multiview_mask: None,
        cache: None,
    })
}

/// A storage buffer at `binding` (read-only or read-write), for compute.
pub(crate) fn storage_buffer_entry(binding: u32, read_only: bool) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

/// A write-only storage texture of `format` at `binding`, for compute.
pub(crate) fn storage_entry(
    binding: u32,
    format: wgpu::TextureFormat,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::StorageTexture {
            access: wgpu::StorageTextureAccess::WriteOnly,
            format,
            view_dimension: wgpu::TextureViewDimension::D2,
        },
        count: None,
    }
}

/// A uniform buffer of `count` slots of `T`, each at a multiple of the device's dynamic-offset
/// alignment: one dispatch's uniforms per slot. Returns the buffer and the slot stride.
pub(crate) fn slot_buffer<T>(
    device: &wgpu::Device,
    label: &str,
    count: usize,
) -> (wgpu::Buffer, u64) {
    let align = u64::from(device.limits().min_uniform_buffer_offset_alignment);
    let stride = (std::mem::size_of::<T>() as u64).next_multiple_of(align);
    let buffer = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: stride * count as u64,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    (buffer, stride)
}

/// Writes `items` into the slots of a [`slot_buffer`] of `stride`, from the first.
pub(crate) fn write_slots<T: bytemuck::Pod>(
    queue: &wgpu::Queue,
    buffer: &wgpu::Buffer,
    stride: u64,
    items: impl ExactSizeIterator<Item = T>,
) {
    let mut bytes = vec![0u8; stride as usize * items.len()];
    for (i, item) in items.enumerate() {
        let at = i * stride as usize;
        bytes[at..at + std::mem::size_of::<T>()].copy_from_slice(bytemuck::bytes_of(&item));
    }
    queue.write_buffer(buffer, 0, &bytes);
}

pub(crate) fn compute_pipeline(
    device: &wgpu::Device,
    label: &str,
    layout: &wgpu::BindGroupLayout,
    module: &wgpu::ShaderModule,
    entry: &str,
) -> wgpu::ComputePipeline {
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(&format!("{label}:pipeline-layout")),
        bind_group_layouts: &[Some(layout)],
        immediate_size: 0,
    });
    device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some(&format!("{label}:pipeline")),
        layout: Some(&pipeline_layout),
        module,
        entry_point: Some(entry),
        compilation_options: Default::default(),
        cache: None,
    })
}

/// Records one compute pass that runs `pipeline` over a `size` x `size` texture, one
/// invocation per texel in [`WORKGROUP`]-square groups.
pub(crate) fn dispatch_square(
    encoder: &mut wgpu::CommandEncoder,
    label: &str,
    pipeline: &wgpu::ComputePipeline,
    bind_group: Option<&wgpu::BindGroup>,
    size: u32,
    timestamps: Option<wgpu::ComputePassTimestampWrites<'_>>,
) {
    let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
        label: Some(label),
        timestamp_writes: timestamps,
    });
    pass.set_pipeline(pipeline);
    pass.set_bind_group(0, bind_group, &[]);
    let groups = size.div_ceil(WORKGROUP);
    pass.dispatch_workgroups(groups, groups, 1);
}
