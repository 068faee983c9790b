//! The visibility method's images and targets: their formats and bind group entries, the
//! multisampled textures, the presented frame's row pitch and byte order, the composite's
//! pipeline.

use super::*;

/// The format [`Visibility::present`] stores straight into (a target with `STORAGE_BINDING`).
pub(super) const STORE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;

/// Bytes a pixel of the presented frame.
pub(super) const PRESENTED_BYTES: u64 = 4;

/// Bytes a row of the presented frame `width` pixels wide: padded to what a copy into a
/// texture needs (`wgsl/visibility.wgsl`'s `present_pixel` pads the same).
pub(super) fn present_pitch(width: u32) -> u32 {
    (width * PRESENTED_BYTES as u32).next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT)
}

/// Whether [`Visibility::present`] packs for `format` as BGRA (`Some(true)`) or RGBA
/// (`Some(false)`); `None` for a format it does not write.
pub(super) fn present_order(format: wgpu::TextureFormat) -> Option<bool> {
    use wgpu::TextureFormat as F;
    match format {
        F::Rgba8Unorm | F::Rgba8UnormSrgb => Some(false),
        F::Bgra8Unorm | F::Bgra8UnormSrgb => Some(true),
        _ => None,
    }
}

/// The composite's pipeline (`wgsl/composite.wgsl` in `module`) into the host's targets: premultiplied colour over what is there
/// (or opaque), and the nearest sample's depth, tested (less or equal: the sky's 1 passes where
/// nothing was drawn) and written, where the host's pass has depth.
pub(crate) fn composite_pipeline(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    module: &wgpu::ShaderModule,
    (targets, opaque): (&Targets, bool),
) -> wgpu::RenderPipeline {
    let fragment = if targets.depth_format.is_some() {
        "composite_fs"
    } else {
        "composite_fs_color"
    };
    crate::gpu::blended_pipeline(
        device,
        (
            "relief:visibility:composite",
            layout,
            module,
            ("composite_vs", fragment),
        ),
        targets,
        (wgpu::PrimitiveTopology::TriangleList, &[]),
        (true, wgpu::CompareFunction::LessEqual),
        (!opaque).then_some(wgpu::BlendState::PREMULTIPLIED_ALPHA_BLENDING),
    )
}

/// The composite's bind group (the layout of `composite_pipeline`'s shader): its uniforms at
/// 12, the image shown at 13 and its depth at 14.
pub(crate) fn composite_group(
    device: &wgpu::Device,
    (label, layout): (&str, &wgpu::BindGroupLayout),
    (uniforms, shown, depth): (&wgpu::Buffer, &wgpu::TextureView, &wgpu::TextureView),
) -> wgpu::BindGroup {
    use wgpu::BindingResource::TextureView;
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(label),
        layout,
        entries: &[
            entry(12, uniforms.as_entire_binding()),
            entry(13, TextureView(shown)),
            entry(14, TextureView(depth)),
        ],
    })
}

pub(super) fn sampled_entry(
    binding: u32,
    sample_type: wgpu::TextureSampleType,
    multisampled: bool,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Texture {
            sample_type,
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled,
        },
        count: None,
    }
}

/// The bindings of the raster pass's targets in `wgsl/visibility.wgsl`: multisampled, or
/// single-sampled at one sample a pixel.
pub(super) fn target_bindings(samples: u32) -> [u32; 3] {
    if samples > 1 {
        [7, 8, 9]
    } else {
        [15, 16, 17]
    }
}

pub(super) fn ms_texture(
    device: &wgpu::Device,
    (label, samples): (&str, u32),
    (width, height): (u32, u32),
    format: wgpu::TextureFormat,
) -> wgpu::TextureView {
    device
        .create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: samples,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        })
        .create_view(&Default::default())
}

pub(super) fn entry(binding: u32, resource: wgpu::BindingResource<'_>) -> wgpu::BindGroupEntry<'_> {
    wgpu::BindGroupEntry { binding, resource }
}

/// How a camera-relative perspective `matrix` (the eye at the origin) turns depth d into clip
/// w: `b / (d + a)`, as `[a, b]` (`VisUniforms::depth`, what the temporal resolve reads).
pub(crate) fn clip_w_from_depth(matrix: glam::Mat4) -> [f32; 2] {
    let m = matrix.as_dmat4();
    let (row2, row3) = (m.row(2), m.row(3));
    // A perspective projection after an affine view: row 2 = -a row 3 + b e4, and clip w
    // from depth d is b / (d + a). Read `a` where row 3 is largest.
    let k = (0..3)
        .max_by(|&i, &j| row3[i].abs().total_cmp(&row3[j].abs()))
        .unwrap_or(2);
    let a = if row3[k] != 0.0 {
        -row2[k] / row3[k]
    } else {
        0.0
    };
    let b = row2.w + a * row3.w;
    [a as f32, b as f32]
}
