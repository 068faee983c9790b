//! The props' shade map: the props' shadow (the sun's share) and their occlusion of the sky
//! (the sky's share) on the drawn surface around the eye, in world space, for the methods that
//! shade the terrain before the props are marched (the forward mesh, the hybrid, the
//! visibility method rasterised by the GPU, the page's): `wgsl/props_map.wgsl` reads it in
//! their shading, `props_map_bake` in `wgsl/props_march.wgsl` bakes it with the march's own
//! shadow and occlusion ([`super::props::PropsPass::encode_map`]).
//!
//! [`LEVELS`] levels of [`SIDE`] texels a side, each centred on the eye, each texel
//! [`TEXELS`]`[l]` metres; a world texel's place in the texture is its index modulo the side,
//! so as the eye moves only the rows and columns it uncovers are baked (a turned sun, new
//! props or a jump past a level's side bake the level whole). The props and the sun are still
//! between bakes; the surface under a texel is the one drawn when it was baked (a map baked
//! while the world's heights were still arriving is baked whole again once they all have).

/// Levels of the map (`PROPS_MAP_TEXELS` in `wgsl/props_map.wgsl`).
pub(crate) const LEVELS: usize = 3;
/// Texels on a side of a level (`PROPS_MAP_SIDE`).
pub(crate) const SIDE: u32 = 512;
/// Each level's texel, metres: 128 m, 512 m and 2 km squares around the eye.
pub(crate) const TEXELS: [f64; LEVELS] = [0.25, 1.0, 4.0];
/// The sun's and the sky's shares, 8 bits each.
const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;
/// The most rectangles one frame bakes: two strips a level.
const MAX_RECTS: usize = 2 * LEVELS;

/// Mirrors `MapRect` in `wgsl/props_march.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct MapRect {
    origin: [f32; 2],
    first: [u32; 2],
    size: [u32; 2],
    level: u32,
    texel: f32,
}

/// A rectangle of a level's world texels: its first texel's index and its size.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Rect {
    level: usize,
    first: [i64; 2],
    size: [u32; 2],
}

/// What the map holds: each level's first texel (world index), the sun it was baked for, and
/// whether the surface it was baked over was whole.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Baked {
    firsts: [[i64; 2]; LEVELS],
    sun: [f32; 3],
    settled: bool,
}

/// The map's texture (1 texel a level until a frame first draws the props' overlay), its
/// rectangles' uniforms and the bind group the bake writes through.
pub(crate) struct PropsMap {
    texture: wgpu::Texture,
    view: wgpu::TextureView,
    /// A texel a level, bound where the map is written.
    empty: wgpu::TextureView,
    /// Bilinear, repeating (the toroidal addressing wraps).
    sampler: wgpu::Sampler,
    layout: wgpu::BindGroupLayout,
    rects: wgpu::Buffer,
    stride: u64,
    group: Option<wgpu::BindGroup>,
    baked: Option<Baked>,
}

/// The first texel of each level centred on the eye's `xz` (world metres).
fn firsts(eye: [f64; 2]) -> [[i64; 2]; LEVELS] {
    std::array::from_fn(|l| eye.map(|e| (e / TEXELS[l]).floor() as i64 - i64::from(SIDE / 2)))
}

/// The rectangles to bake to move level `level` from `old` (its first texel; `None`: nothing
/// held) to `new`: the whole level, or the columns and the rows it uncovers.
fn uncovered(level: usize, old: Option<[i64; 2]>, new: [i64; 2]) -> Vec<Rect> {
    let side = i64::from(SIDE);
    let whole = Rect {
        level,
        first: new,
        size: [SIDE; 2],
    };
    let Some(old) = old else {
        return vec![whole];
    };
    let d = [new[0] - old[0], new[1] - old[1]];
    if d[0].abs() >= side || d[1].abs() >= side {
        return vec![whole];
    }
    let mut out = Vec::new();
    if d[0] != 0 {
        let x = if d[0] > 0 { old[0] + side } else { new[0] };
        out.push(Rect {
            level,
            first: [x, new[1]],
            size: [d[0].unsigned_abs() as u32, SIDE],
        });
    }
    if d[1] != 0 {
        let z = if d[1] > 0 { old[1] + side } else { new[1] };
        out.push(Rect {
            level,
            first: [new[0], z],
            size: [SIDE, d[1].unsigned_abs() as u32],
        });
    }
    out
}

/// The camera-relative x and z (metres) of the corner of the texel of index `first` of a level
/// whose texel is `texel` metres, the eye at world `eye`.
fn relative(texel: f64, first: [i64; 2], eye: glam::DVec3) -> [f32; 2] {
    [
        (first[0] as f64 * texel - eye.x) as f32,
        (first[1] as f64 * texel - eye.z) as f32,
    ]
}

/// A world texel's column and row in the texture.
fn modulo(first: [i64; 2]) -> [u32; 2] {
    first.map(|i| i.rem_euclid(i64::from(SIDE)) as u32)
}

/// Where the map lies for the eye at world `eye`, as the render uniforms' `props_map` give
/// it: per level, the camera-relative x and z of its first texel's corner and that texel's
/// column and row in the texture.
pub(crate) fn placement(eye: glam::DVec3) -> [[f32; 4]; LEVELS] {
    let f = firsts([eye.x, eye.z]);
    std::array::from_fn(|l| {
        let [x, z] = relative(TEXELS[l], f[l], eye);
        let [cx, cz] = modulo(f[l]);
        [x, z, cx as f32, cz as f32]
    })
}

/// What a frame bakes after `baked` (`None`: nothing held) for levels whose first texels are
/// `new`, the sun towards `sun`, the world's heights all baked or not (`settled`): the
/// uncovered rows and columns, or every level whole where the sun turned, or where the map was
/// baked over heights still arriving and they now all have; and what the map holds after.
fn to_bake(
    baked: Option<Baked>,
    (new, sun, settled): ([[i64; 2]; LEVELS], [f32; 3], bool),
) -> (Vec<Rect>, Baked) {
    let kept = baked.filter(|b| b.sun == sun && (b.settled || !settled));
    let rects = (0..LEVELS)
        .flat_map(|l| uncovered(l, kept.map(|b| b.firsts[l]), new[l]))
        .collect();
    let after = Baked {
        firsts: new,
        sun,
        settled: kept.map_or(settled, |b| b.settled),
    };
    (rects, after)
}

impl PropsMap {
    /// An empty map (a texel a level: the world's shading binds it, and reads none of it).
    pub(crate) fn new(device: &wgpu::Device) -> Self {
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("relief:props-map:layout"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: wgpu::ShaderStages::COMPUTE,
                    ty: wgpu::BindingType::StorageTexture {
                        access: wgpu::StorageTextureAccess::WriteOnly,
                        format: FORMAT,
                        view_dimension: wgpu::TextureViewDimension::D2Array,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 1,
                    visibility: wgpu::ShaderStages::COMPUTE,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: true,
                        min_binding_size: wgpu::BufferSize::new(
                            std::mem::size_of::<MapRect>() as u64
                        ),
                    },
                    count: None,
                },
            ],
        });
        let (rects, stride) =
            super::slot_buffer::<MapRect>(device, "relief:props-map:rects", MAX_RECTS);
        let texture = Self::texture(device, 1);
        Self {
            view: Self::array_view(&texture),
            empty: Self::array_view(&texture),
            sampler: device.create_sampler(&wgpu::SamplerDescriptor {
                label: Some("relief:props-map:sampler"),
                address_mode_u: wgpu::AddressMode::Repeat,
                address_mode_v: wgpu::AddressMode::Repeat,
                mag_filter: wgpu::FilterMode::Linear,
                min_filter: wgpu::FilterMode::Linear,
                ..Default::default()
            }),
            texture,
            layout,
            rects,
            stride,
            group: None,
            baked: None,
        }
    }

    fn texture(device: &wgpu::Device, side: u32) -> wgpu::Texture {
        device.create_texture(&wgpu::TextureDescriptor {
            label: Some("relief:props-map"),
            size: wgpu::Extent3d {
                width: side,
                height: side,
                depth_or_array_layers: LEVELS as u32,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: FORMAT,
            usage: wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        })
    }

    fn array_view(texture: &wgpu::Texture) -> wgpu::TextureView {
        texture.create_view(&wgpu::TextureViewDescriptor {
            label: Some("relief:props-map:view"),
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            ..Default::default()
        })
    }

    /// The layout entries of the map and its sampler as the world's shading reads them
    /// (`props_map_tex` at 23, `props_map_sampler` at 24), for the stages `visibility`.
    pub(crate) fn entries(visibility: wgpu::ShaderStages) -> [wgpu::BindGroupLayoutEntry; 2] {
        [
            wgpu::BindGroupLayoutEntry {
                binding: 23,
                visibility,
                ty: wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Float { filterable: true },
                    view_dimension: wgpu::TextureViewDimension::D2Array,
                    multisampled: false,
                },
                count: None,
            },
            wgpu::BindGroupLayoutEntry {
                binding: 24,
                visibility,
                ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                count: None,
            },
        ]
    }

    /// The bind group entries of [`PropsMap::entries`]: the map, or (`empty`) a texel a
    /// level, for the bind group the bake reads the world through (it writes the map).
    pub(crate) fn bindings(&self, empty: bool) -> [wgpu::BindGroupEntry<'_>; 2] {
        let view = if empty { &self.empty } else { &self.view };
        [
            wgpu::BindGroupEntry {
                binding: 23,
                resource: wgpu::BindingResource::TextureView(view),
            },
            wgpu::BindGroupEntry {
                binding: 24,
                resource: wgpu::BindingResource::Sampler(&self.sampler),
            },
        ]
    }

    /// Makes the map its whole size (once; the caller binds the new view). Returns whether it
    /// did.
    pub(crate) fn allocate(&mut self, device: &wgpu::Device) -> bool {
        if self.group.is_some() {
            return false;
        }
        self.texture = Self::texture(device, SIDE);
        self.view = Self::array_view(&self.texture);
        self.group = Some(device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("relief:props-map:group"),
            layout: &self.layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::TextureView(&self.view),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                        buffer: &self.rects,
                        offset: 0,
                        size: wgpu::BufferSize::new(std::mem::size_of::<MapRect>() as u64),
                    }),
                },
            ],
        }));
        self.baked = None;
        true
    }

    /// Forgets what the map holds (new props, a new landscape): the next bake is whole.
    pub(crate) fn forget(&mut self) {
        self.baked = None;
    }

    /// The rectangles the frame at world `eye` with the sun towards `sun` bakes, written into
    /// the rectangles' slots (camera-relative), each with its slot's offset (none before the
    /// map is allocated). `settled`: the world's heights are all baked; the first settled
    /// frame after a whole bake that was not bakes the whole map again (once: not every frame
    /// of an arrival, which on a software GPU is minutes of frames).
    pub(crate) fn plan(
        &mut self,
        queue: &wgpu::Queue,
        (eye, sun, settled): (glam::DVec3, [f32; 3], bool),
    ) -> Vec<(u32, MapRect)> {
        let (rects, baked) = to_bake(self.baked, (firsts([eye.x, eye.z]), sun, settled));
        self.baked = Some(baked);
        let relative = |l: usize, first: [i64; 2]| relative(TEXELS[l], first, eye);
        if self.group.is_none() {
            return Vec::new();
        }
        let slots: Vec<MapRect> = rects
            .iter()
            .map(|r| MapRect {
                origin: relative(r.level, r.first),
                first: modulo(r.first),
                size: r.size,
                level: r.level as u32,
                texel: TEXELS[r.level] as f32,
            })
            .collect();
        if slots.is_empty() {
            return Vec::new();
        }
        super::write_slots(queue, &self.rects, self.stride, slots.iter().copied());
        slots
            .into_iter()
            .enumerate()
            .map(|(i, s)| ((i as u64 * self.stride) as u32, s))
            .collect()
    }

    /// Records the frame's bake of the map (what the eye uncovered, or all of it) through the
    /// props' march (`props`, its scatter already recorded), with the world's bind group
    /// `world` of `world_layout` at 0 (one that binds no map: the bake writes it); timed as
    /// [`super::timing::Slot::PropShadows`].
    pub(crate) fn encode(
        &mut self,
        (device, queue, encoder): (&wgpu::Device, &wgpu::Queue, &mut wgpu::CommandEncoder),
        props: &super::props::PropsPass,
        (world, world_layout): (&wgpu::BindGroup, &wgpu::BindGroupLayout),
        frame: (glam::DVec3, [f32; 3], bool),
        timer: Option<&super::timing::GpuTimer>,
    ) {
        let rects = self.plan(queue, frame);
        let Some(group) = self.group.as_ref().filter(|_| !rects.is_empty()) else {
            return;
        };
        let pipeline = props.map_bake.get_or_init(|| {
            let (module, scatter_layout) = &props.parts;
            let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("relief:props-map:pipeline-layout"),
                bind_group_layouts: &[Some(world_layout), Some(scatter_layout), Some(&self.layout)],
                immediate_size: 0,
            });
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some("relief:props-map:bake"),
                layout: Some(&layout),
                module,
                entry_point: Some("props_map_bake"),
                compilation_options: Default::default(),
                cache: None,
            })
        });
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("relief:props-map:bake-pass"),
            timestamp_writes: timer.map(|t| t.compute_writes(super::timing::Slot::PropShadows)),
        });
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, world, &[]);
        pass.set_bind_group(1, &props.scatter_group, &[]);
        let g = super::WORKGROUP;
        for (offset, r) in rects {
            pass.set_bind_group(2, group, &[offset]);
            pass.dispatch_workgroups(r.size[0].div_ceil(g), r.size[1].div_ceil(g), 1);
        }
    }

    /// GPU memory of its texture and buffer, bytes.
    pub(crate) fn bytes(&self) -> u64 {
        let s = u64::from(self.texture.width()) * u64::from(self.texture.height());
        s * LEVELS as u64 * super::texel_bytes(FORMAT) + self.rects.size()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_arrival_bakes_the_map_whole_twice_and_a_turned_sun_once() {
        let sun = [0.0, 1.0, 0.0];
        let at = firsts([0.0, 0.0]);
        let whole = |r: &[Rect]| r.len() == LEVELS && r.iter().all(|r| r.size == [SIDE; 2]);
        // Heights still arriving: whole once, then only what the eye uncovers.
        let (r, b) = to_bake(None, (at, sun, false));
        assert!(whole(&r));
        let (r, b) = to_bake(Some(b), (at, sun, false));
        assert!(r.is_empty());
        // They have all arrived: whole again, once.
        let (r, b) = to_bake(Some(b), (at, sun, true));
        assert!(whole(&r));
        let (r, b) = to_bake(Some(b), (at, sun, true));
        assert!(r.is_empty());
        // A level moving again uncovers heights: the map keeps what it holds.
        let (r, b) = to_bake(Some(b), (at, sun, false));
        assert!(r.is_empty() && b.settled);
        // A turned sun: whole.
        let (r, _) = to_bake(Some(b), (at, [0.0, 0.8, 0.6], true));
        assert!(whole(&r));
    }

    #[test]
    fn a_moving_eye_bakes_only_what_it_uncovers() {
        let side = i64::from(SIDE);
        assert_eq!(uncovered(0, None, [3, 4]).len(), 1);
        assert_eq!(uncovered(0, Some([3, 4]), [3, 4]), vec![]);
        // Three columns east, two rows north: the new columns whole, the new rows whole.
        let r = uncovered(1, Some([0, 0]), [3, -2]);
        assert_eq!(
            r,
            vec![
                Rect {
                    level: 1,
                    first: [side, -2],
                    size: [3, SIDE],
                },
                Rect {
                    level: 1,
                    first: [3, -2],
                    size: [SIDE, 2],
                },
            ]
        );
        // West and south.
        let r = uncovered(0, Some([10, 10]), [7, 9]);
        assert_eq!(r[0].first, [7, 9]);
        assert_eq!(r[0].size, [3, SIDE]);
        assert_eq!(r[1].first, [7, 9]);
        assert_eq!(r[1].size, [SIDE, 1]);
        // A jump past the side: whole.
        assert_eq!(uncovered(2, Some([0, 0]), [side, 0])[0].size, [SIDE; 2]);
        // Far from the origin the eye's texel is exact.
        let f = firsts([1.0e7 + 0.3, -2.5e6]);
        assert_eq!(f[0], [40_000_001 - side / 2, -10_000_000 - side / 2]);
    }
}
