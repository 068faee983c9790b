//! The landscape bake pass: rectangles of the endless world's sample grids into layers of a
//! texture array (height, dh/dx, dh/dz, colour channel), at wrapping texel addresses: packed in
//! 64 bits ([`LandscapeBake::LEVEL_FORMAT`], [`unpack_level_texel`]) for the levels the renderer
//! draws from, or as four 32-bit floats ([`LandscapeBake::FORMAT`]) for region bakes read back.
//! Several rectangles per encoder, each with its own uniforms at a dynamic offset.

use super::shader;
use crate::landscape::Landscape;

/// Mirrors `LandscapeUniforms` in `wgsl/landscape.wgsl` field by field.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct LandscapeUniforms {
    /// World sample coordinates of the rectangle's first texel.
    pub origin: [i32; 2],
    /// Rectangle size in samples.
    pub extent: [u32; 2],
    /// Texel where the rectangle's first sample goes (wrapping at `wrap`).
    pub dest_origin: [u32; 2],
    /// Side of the (square, toroidal) texture.
    pub wrap: u32,
    /// Texture-array layer written.
    pub layer: u32,
    /// Hash seed.
    pub seed: u32,
    /// Octaves kept at this grid spacing.
    pub octaves: u32,
    /// All octaves (the normalisation).
    pub total_octaves: u32,
    /// [`crate::landscape::TerrainFn::code`].
    pub terrain: u32,
    /// Amplitude ratio between octaves.
    pub gain: f32,
    /// log2 of octave 0's cell in metres.
    pub feature_log2: i32,
    /// log2 of the grid's sample spacing in metres.
    pub level_log2: i32,
    /// 0: endless; else octave 0's lattice cells per period ([`Landscape::period`]).
    pub period: u32,
}

/// One rectangle to bake.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Rect {
    /// Texture-array layer (a level).
    pub layer: u32,
    /// log2 of the layer's sample spacing in metres.
    pub level_log2: i32,
    /// World sample coordinates of the first sample.
    pub origin: [i32; 2],
    /// Size in samples.
    pub extent: [u32; 2],
}

impl LandscapeUniforms {
    /// The uniforms for `rect` of `land` in a texture of side `wrap`.
    pub fn new(land: &Landscape, rect: &Rect, wrap: u32) -> Self {
        let m = |v: i32| v.rem_euclid(wrap as i32) as u32;
        Self {
            origin: rect.origin,
            extent: rect.extent,
            dest_origin: [m(rect.origin[0]), m(rect.origin[1])],
            wrap,
            layer: rect.layer,
            seed: land.seed,
            octaves: land.octaves_for_level(rect.level_log2),
            total_octaves: land.octaves,
            terrain: land.terrain.code(),
            gain: land.gain as f32,
            feature_log2: land.feature_log2,
            level_log2: rect.level_log2,
            period: land.period,
        }
    }
}

/// Where a [`LandscapeBake`] writes: a bind group for one level texture array.
pub struct LevelTarget {
    bind_group: wgpu::BindGroup,
    wrap: u32,
}

/// Most rectangles one [`LandscapeBake::encode`] records.
pub(crate) const MAX_RECTS: usize = 64;

/// One in the height's 24-bit fixed point in a packed level texel (`wgsl/level_texel.wgsl`).
const LEVEL_HEIGHT_ONE: f32 = 16_777_215.0;
/// What the gradient per sample is multiplied by in a packed level texel.
const LEVEL_GRADIENT_SCALE: f32 = 64.0;

/// (height, dh/dx, dh/dz, colour) of a packed level texel ([`LandscapeBake::LEVEL_FORMAT`]) of
/// a level spaced `2^spacing_log2` metres, as `wgsl/level_texel.wgsl` unpacks it: the height to
/// 6e-8 of the peak, the gradient to 16-bit float precision (about 5e-4 of itself), the colour
/// channel to 1/255.
pub fn unpack_level_texel(texel: [u32; 2], spacing_log2: i32) -> [f32; 4] {
    let g = |bits: u32| f16_bits_to_f32(bits) / (LEVEL_GRADIENT_SCALE * 2f32.powi(spacing_log2));
    [
        (texel[0] >> 8) as f32 / LEVEL_HEIGHT_ONE,
        g(texel[1] & 0xffff),
        g(texel[1] >> 16),
        (texel[0] & 0xff) as f32 / 255.0,
    ]
}

/// The IEEE half-precision float in the low 16 bits of `bits` (WGSL's `unpack2x16float`).
fn f16_bits_to_f32(bits: u32) -> f32 {
    let sign = if bits & 0x8000 != 0 { -1.0 } else { 1.0 };
    let exponent = ((bits >> 10) & 0x1f) as i32;
    let mantissa = (bits & 0x3ff) as f32;
    sign * match exponent {
        0 => mantissa * 2f32.powi(-24),
        31 if mantissa == 0.0 => f32::INFINITY,
        31 => f32::NAN,
        e => (1.0 + mantissa / 1024.0) * 2f32.powi(e - 15),
    }
}

/// The pass: pipeline, layout and a uniform buffer of `MAX_RECTS` aligned slots.
pub struct LandscapeBake {
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
    uniforms: wgpu::Buffer,
    stride: u64,
    /// The storage texture's binding (1: four floats, 2: packed).
    binding: u32,
}

impl LandscapeBake {
    /// Format of the textures [`LandscapeBake::new`] writes: four 32-bit floats a texel.
    pub const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
    /// Format of the level textures [`LandscapeBake::levels`] writes: 64 bits a texel
    /// ([`unpack_level_texel`]), so that the endless world's default fits in 256 MiB.
    pub const LEVEL_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rg32Uint;

    /// Builds the pipeline writing [`LandscapeBake::FORMAT`] (region bakes read back).
    pub fn new(device: &wgpu::Device) -> Self {
        Self::with_format(device, false)
    }

    /// Builds the pipeline writing packed level texels ([`LandscapeBake::LEVEL_FORMAT`]).
    pub fn levels(device: &wgpu::Device) -> Self {
        Self::with_format(device, true)
    }

    fn with_format(device: &wgpu::Device, packed: bool) -> Self {
        let (format, binding, entry) = if packed {
            (Self::LEVEL_FORMAT, 2, "landscape_bake_levels")
        } else {
            (Self::FORMAT, 1, "landscape_bake_main")
        };
        let module = shader::module(
            device,
            "relief:landscape-bake:shader",
            &shader::source("landscape_bake"),
        );
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("relief:landscape-bake:bind-group-layout"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: wgpu::ShaderStages::COMPUTE,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: true,
                        min_binding_size: wgpu::BufferSize::new(
                            std::mem::size_of::<LandscapeUniforms>() as u64,
                        ),
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding,
                    visibility: wgpu::ShaderStages::COMPUTE,
                    ty: wgpu::BindingType::StorageTexture {
                        access: wgpu::StorageTextureAccess::WriteOnly,
                        format,
                        view_dimension: wgpu::TextureViewDimension::D2Array,
                    },
                    count: None,
                },
            ],
        });
        let pipeline =
            super::compute_pipeline(device, "relief:landscape-bake", &layout, &module, entry);
        let (uniforms, stride) = super::slot_buffer::<LandscapeUniforms>(
            device,
            "relief:landscape-bake:uniforms",
            MAX_RECTS,
        );
        Self {
            pipeline,
            layout,
            uniforms,
            stride,
            binding,
        }
    }

    /// A target writing into `levels` (a 2-D array view of a square texture of side `wrap`, of
    /// the format this pass writes).
    pub fn bind(
        &self,
        device: &wgpu::Device,
        levels: &wgpu::TextureView,
        wrap: u32,
    ) -> LevelTarget {
        let bind_group =
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("relief:landscape-bake:bind-group"),
                layout: &self.layout,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                            buffer: &self.uniforms,
                            offset: 0,
                            size: wgpu::BufferSize::new(
                                std::mem::size_of::<LandscapeUniforms>() as u64
                            ),
                        }),
                    },
                    wgpu::BindGroupEntry {
                        binding: self.binding,
                        resource: wgpu::BindingResource::TextureView(levels),
                    },
                ],
            });
        LevelTarget { bind_group, wrap }
    }

    /// Records the bake of one rectangle of samples into the texture's texels from (0, 0) on
    /// (not toroidally: the target's `wrap` must be at least the rectangle's width and height),
    /// for region bakes read back in bands.
    pub fn encode_at_origin(
        &self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        target: &LevelTarget,
        land: &Landscape,
        rect: &Rect,
        timestamps: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) {
        let u = LandscapeUniforms {
            dest_origin: [0, 0],
            ..LandscapeUniforms::new(land, rect, target.wrap)
        };
        queue.write_buffer(&self.uniforms, 0, bytemuck::bytes_of(&u));
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("relief:landscape-bake:region"),
            timestamp_writes: timestamps,
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &target.bind_group, &[0]);
        let [x, y] = quad_groups(rect);
        pass.dispatch_workgroups(x, y, 1);
    }

    /// Writes the uniforms of up to `MAX_RECTS` rectangles and records one compute pass
    /// baking them all (any more are left for the caller to record in another encoder).
    /// Returns how many were recorded.
    pub fn encode(
        &self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        target: &LevelTarget,
        land: &Landscape,
        rects: &[Rect],
        timestamps: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) -> usize {
        let rects = &rects[..rects.len().min(MAX_RECTS)];
        if rects.is_empty() {
            return 0;
        }
        super::write_slots(
            queue,
            &self.uniforms,
            self.stride,
            rects
                .iter()
                .map(|r| LandscapeUniforms::new(land, r, target.wrap)),
        );
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("relief:landscape-bake:pass"),
            timestamp_writes: timestamps,
        });
        pass.set_pipeline(&self.pipeline);
        for (i, r) in rects.iter().enumerate() {
            pass.set_bind_group(0, &target.bind_group, &[(i as u64 * self.stride) as u32]);
            let [x, y] = quad_groups(r);
            pass.dispatch_workgroups(x, y, 1);
        }
        rects.len()
    }
}

/// Workgroups that cover `rect` with 2x2 quads of samples on even world coordinates (an
/// invocation a quad, `wgsl/landscape_bake.wgsl`).
fn quad_groups(rect: &Rect) -> [u32; 2] {
    [0, 1].map(|a| {
        let odd = (rect.origin[a] & 1) as u32;
        (rect.extent[a] + odd)
            .div_ceil(2)
            .div_ceil(super::WORKGROUP)
    })
}

#[cfg(test)]
mod tests {
    #[test]
    fn half_floats_decode() {
        use super::f16_bits_to_f32 as f;
        assert_eq!(f(0x3c00), 1.0);
        assert_eq!(f(0xc000), -2.0);
        assert_eq!(f(0x7bff), 65504.0);
        assert_eq!(f(0x0001), 2f32.powi(-24));
        assert_eq!(f(0x3555), 0.333_251_95);
        assert!(f(0x7c00).is_infinite() && f(0x7e00).is_nan());
    }
}
