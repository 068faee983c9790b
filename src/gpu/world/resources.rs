//! [`World`]'s GPU resources: the level textures and arrays, the light images, bind groups,
//! the mesh pipeline, the patches' index buffer and the level layout.

use super::*;

/// The hybrid method's raise for every level spacing a clipmap of `land` can have.
pub(super) fn level_raises(land: &Landscape) -> Vec<(i32, f64)> {
    let finest = crate::clipmap::finest_log2(land);
    (0..MAX_LEVELS as i32)
        .map(|l| (finest + l, crate::clipmap::level_raise(land, finest + l)))
        .collect()
}

/// The levels' errors from the finest spacing `land` needs, or `floor` where that is coarser.
pub(super) fn level_errors(land: &Landscape, floor: Option<i32>) -> Vec<(i32, f64)> {
    let finest = crate::clipmap::finest_log2(land).max(floor.unwrap_or(i32::MIN));
    (0..MAX_LEVELS as i32)
        .map(|l| (finest + l, crate::clipmap::level_error(land, finest + l)))
        .collect()
}

/// The pipeline that draws the levels' patches into the host's pass: `fs_tile` for the tile,
/// `fs_main` for the endless world.
pub(super) fn mesh_pipeline(
    device: &wgpu::Device,
    (layout, module): (&wgpu::BindGroupLayout, &wgpu::ShaderModule),
    targets: &Targets,
    tile: bool,
) -> wgpu::RenderPipeline {
    crate::gpu::terrain_pipeline(
        device,
        ("relief:world", if tile { "fs_tile" } else { "fs_main" }),
        layout,
        module,
        targets,
        wgpu::PrimitiveTopology::TriangleList,
        &[Some(wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<Patch>() as u64,
            step_mode: wgpu::VertexStepMode::Instance,
            attributes: &wgpu::vertex_attr_array![0 => Uint32x4],
        })],
    )
}

pub(super) fn layout(params: &WorldParams, errors: &[(i32, f64)], k: f64) -> Clipmap {
    Clipmap::with_errors(&params.land, errors, params.pixel_error, k)
}

pub(super) fn level_texture(
    device: &wgpu::Device,
    bake: &LandscapeBake,
    map: &Clipmap,
) -> (wgpu::Texture, LevelTarget) {
    let texture = level_array(
        device,
        "relief:world:levels",
        LandscapeBake::LEVEL_FORMAT,
        map,
    );
    let view = array_view(&texture);
    let target = bake.bind(device, &view, map.side());
    (texture, target)
}

/// A texture array of one side x side layer per level of `map`, written in compute and read
/// by the render pass.
pub(super) fn level_array(
    device: &wgpu::Device,
    label: &str,
    format: wgpu::TextureFormat,
    map: &Clipmap,
) -> wgpu::Texture {
    let side = map.side();
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width: side,
            height: side,
            depth_or_array_layers: map.levels.len() as u32,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::STORAGE_BINDING
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    })
}

/// The light bake's texture array (one layer per level, as the heights) and what writes it.
pub(super) struct LevelLight {
    pub(super) texture: wgpu::Texture,
    pub(super) bind_group: wgpu::BindGroup,
    /// What the levels still need lit, and what each is drawn with until then.
    pub(super) queue: LightQueue,
}

impl LevelLight {
    pub(super) fn new(
        device: &wgpu::Device,
        bake: &LightBake,
        heights: &wgpu::Texture,
        map: &Clipmap,
    ) -> Self {
        let texture = level_array(device, "relief:world:light", LightBake::FORMAT, map);
        let bind_group = bake.bind(device, &array_view(heights), &array_view(&texture));
        Self {
            texture,
            bind_group,
            queue: LightQueue::new(map.levels.len()),
        }
    }
}

pub(super) fn array_entry(
    binding: u32,
    sample_type: wgpu::TextureSampleType,
) -> wgpu::BindGroupLayoutEntry {
    crate::gpu::array_texture_entry(
        binding,
        wgpu::ShaderStages::VERTEX_FRAGMENT | wgpu::ShaderStages::COMPUTE,
        sample_type,
    )
}

pub(super) fn array_view(texture: &wgpu::Texture) -> wgpu::TextureView {
    texture.create_view(&wgpu::TextureViewDescriptor {
        label: Some("relief:world:levels-view"),
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        ..Default::default()
    })
}

pub(super) fn bind(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    (render, world): (&wgpu::Buffer, &wgpu::Buffer),
    (texture, light): (&wgpu::Texture, &wgpu::Texture),
    (tile, props_map, air_shadow): (
        &TileTextures,
        [wgpu::BindGroupEntry<'_>; 2],
        &crate::gpu::air_shadow::AirShadow,
    ),
) -> wgpu::BindGroup {
    let [map, map_sampler] = props_map;
    let [air, air_sampler] = air_shadow.bindings();
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("relief:world:bind-group"),
        layout,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: render.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: world.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 2,
                resource: wgpu::BindingResource::TextureView(&array_view(texture)),
            },
            wgpu::BindGroupEntry {
                binding: 3,
                resource: wgpu::BindingResource::TextureView(&array_view(light)),
            },
            wgpu::BindGroupEntry {
                binding: 4,
                resource: wgpu::BindingResource::TextureView(&tile.terrain),
            },
            wgpu::BindGroupEntry {
                binding: 5,
                resource: wgpu::BindingResource::TextureView(&tile.normals),
            },
            wgpu::BindGroupEntry {
                binding: 6,
                resource: wgpu::BindingResource::Sampler(&tile.sampler),
            },
            map,
            map_sampler,
            air,
            air_sampler,
        ],
    })
}

/// The tile's textures as the mesh reads them (1x1 stand-ins for the endless world).
pub(super) struct TileTextures {
    pub(super) terrain: wgpu::TextureView,
    pub(super) normals: wgpu::TextureView,
    pub(super) sampler: wgpu::Sampler,
}

impl TileTextures {
    pub(super) fn new(device: &wgpu::Device, textures: &crate::gpu::Textures) -> Self {
        Self {
            terrain: textures.terrain.create_view(&Default::default()),
            normals: textures.normals.create_view(&Default::default()),
            // The tile is periodic: its normal map wraps.
            sampler: device.create_sampler(&wgpu::SamplerDescriptor {
                label: Some("relief:world:tile-normal-sampler"),
                address_mode_u: wgpu::AddressMode::Repeat,
                address_mode_v: wgpu::AddressMode::Repeat,
                mag_filter: wgpu::FilterMode::Linear,
                min_filter: wgpu::FilterMode::Linear,
                ..Default::default()
            }),
        }
    }
}

/// The index buffer of one patch: (patch + 1)^2 vertices, two triangles per cell, each cell
/// split along the diagonal from its (0, 0) to its (1, 1) corner (as `level_error` assumes);
/// then that of a sub-patch's first cells, in the same vertex numbering. Returns the buffer
/// and the two index counts.
pub(super) fn patch_indices(device: &wgpu::Device, map: &Clipmap) -> (wgpu::Buffer, [u32; 2]) {
    let row = map.patch + 1;
    let mut indices = Vec::new();
    let mut cells = |side: u32| {
        for j in 0..side {
            for i in 0..side {
                let a = j * row + i;
                let (b, c, d) = (a + 1, a + row, a + row + 1);
                indices.extend_from_slice(&[a, b, d, a, d, c]);
            }
        }
        side * side * 6
    };
    let counts = [cells(map.patch), cells(map.sub_cells())];
    let buffer = wgpu::util::DeviceExt::create_buffer_init(
        device,
        &wgpu::util::BufferInitDescriptor {
            label: Some("relief:world:patch-indices"),
            contents: bytemuck::cast_slice(&indices),
            usage: wgpu::BufferUsages::INDEX,
        },
    );
    (buffer, counts)
}
