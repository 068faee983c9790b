//! The terrain's shadow-height map, for the light shafts: `wgsl/air_shadow.wgsl` bakes it from
//! the levels' heights, `wgsl/terrain_air_map.wgsl` reads it where the shading marches the
//! shafts (the forward mesh, the visibility and hybrid methods, the sky pass).
//!
//! Each texel of a square [`TEXELS`] texels of [`TEXEL_M`] metres a side, centred on the eye's
//! texel (a grid fixed in the world), holds the altitude below which the air over its centre
//! lies in the terrain's shadow: the most, over the distance `t` towards the sun, of the height
//! there less `t` times the tangent of the sun's elevation. The air at a point sees the sun
//! where it stands above that, exactly for a height field: a mountain's shadow in the haze is a
//! read a point. The square reaches as far as the shafts' points do (`SHAFT_FAR`,
//! `wgsl/clouds.wgsl`), and is baked whole, after the frame's uniforms, on a frame that draws
//! shafts where the sun, the eye's texel or the levels changed since the last bake: it follows
//! the eye, the sun of a running day and the levels as they arrive. The
//! ray casters (the reference) march the continuous surface from each point instead
//! (`wgsl/terrain_air_rays.wgsl`).

use glam::{DVec3, Vec3};

use super::timing::{GpuTimer, Slot};

/// Texels on a side of the map.
pub const TEXELS: u32 = 512;
/// Metres a texel: the map reaches 8 km from the eye each way, as far as the shafts' points.
pub const TEXEL_M: f64 = 32.0;
/// The lowest sun the bake marches for (radians, half a degree): the terrain's shadows in the
/// air are faded out below one degree (`AIR_SUN_FADE`), and a lower sun's march would run on
/// for hundreds of kilometres.
const LOWEST_SUN: f64 = 0.00873;
/// Steps per doubling of the distance in the bake's march: half the light bake's (its shadows'
/// edges on the ground are sharp, the air's are read between points a few hundred metres
/// apart).
const STEPS_PER_DOUBLING: f32 = 8.0;
/// Altitudes, metres, in the first channel: a half float is good to a metre or two at the
/// heights terrain reaches, and is filtered (one sample a read) and written (a storage format)
/// in core WebGPU, where a 32-bit float is not filtered.
const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// Mirrors `AirShadowBake` in `wgsl/air_shadow.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct AirShadowBake {
    sun: [f32; 2],
    tan_e: f32,
    texel: f32,
    origin: [f32; 2],
    texels: u32,
    steps: f32,
}

/// The map (a texel for a world that draws no shafts: the tile), its bake's uniforms and
/// pipeline (built when a frame first bakes it).
pub(crate) struct AirShadow {
    texture: wgpu::Texture,
    view: wgpu::TextureView,
    /// Bilinear, clamped to the map's edge.
    sampler: wgpu::Sampler,
    uniforms: wgpu::Buffer,
    pass: Option<(wgpu::BindGroupLayout, wgpu::ComputePipeline)>,
    /// What the map was last baked for: the bake's uniforms but their corner, the eye's texel
    /// (its world index) and the levels' bakes so far.
    baked: Option<(AirShadowBake, [i64; 2], u64)>,
}

/// The camera-relative x and z of the map's first corner for the eye at world `eye`: the
/// eye's texel less half the map, a texel corner of a grid fixed in the world (computed in f64,
/// so the grid stays put far from the origin).
pub(crate) fn placement(eye: DVec3) -> [f32; 4] {
    let half = f64::from(TEXELS / 2);
    let corner = |e: f64| (((e / TEXEL_M).floor() - half) * TEXEL_M - e) as f32;
    [corner(eye.x), corner(eye.z), TEXEL_M as f32, TEXELS as f32]
}

/// Whether a frame of render uniforms `u` draws the terrain's shadows in the air: clouds on
/// with their shafts (`Clouds::shafts`), fog, and a sun above the horizon
/// (the weight `cloud_shafts` gives the terrain's shadows, `wgsl/clouds.wgsl`).
pub(crate) fn drawn(u: &super::render::RenderUniforms) -> bool {
    u.clouds[0] > 0.0 && u.cloud_march[3] != 0.0 && u.fog[1] > 0.0 && u.sun_elevation > 0.0
}

/// The bake's uniforms for the map at `placement` and the sun towards unit `sun`.
pub(crate) fn bake_uniforms(placement: [f32; 4], sun: Vec3) -> AirShadowBake {
    let horizontal = glam::Vec2::new(sun.x, sun.z);
    let (dir, tan_e) = if horizontal.length() < 1e-6 {
        // Overhead: no shadow stretches anywhere; the march stops at once.
        ([1.0, 0.0], 1e9)
    } else {
        let e = f64::from(sun.y).atan2(f64::from(horizontal.length()));
        let d = horizontal / horizontal.length();
        ([d.x, d.y], e.max(LOWEST_SUN).tan() as f32)
    };
    AirShadowBake {
        sun: dir,
        tan_e,
        texel: placement[2],
        origin: [placement[0], placement[1]],
        texels: placement[3] as u32,
        steps: STEPS_PER_DOUBLING,
    }
}

impl AirShadow {
    /// A map of `side` texels a side ([`TEXELS`] for the endless world, 1 for the tile).
    pub(crate) fn new(device: &wgpu::Device, side: u32) -> Self {
        let texture = super::texture_2d(
            device,
            "relief:air-shadow",
            (side, side),
            FORMAT,
            wgpu::TextureUsages::STORAGE_BINDING
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_SRC,
        );
        Self {
            view: texture.create_view(&Default::default()),
            texture,
            sampler: device.create_sampler(&wgpu::SamplerDescriptor {
                label: Some("relief:air-shadow:sampler"),
                mag_filter: wgpu::FilterMode::Linear,
                min_filter: wgpu::FilterMode::Linear,
                ..Default::default()
            }),
            uniforms: super::uniform_buffer::<AirShadowBake>(device, "relief:air-shadow:bake"),
            pass: None,
            baked: None,
        }
    }

    /// The layout entries of the map and its sampler as the shading reads them
    /// (`air_shadow_map` at 39, `air_shadow_sampler` at 40), for the stages `visibility`.
    pub(crate) fn entries(visibility: wgpu::ShaderStages) -> [wgpu::BindGroupLayoutEntry; 2] {
        [
            super::texture_entry(39, visibility, true),
            wgpu::BindGroupLayoutEntry {
                binding: 40,
                visibility,
                ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                count: None,
            },
        ]
    }

    /// The bind group entries of [`AirShadow::entries`].
    pub(crate) fn bindings(&self) -> [wgpu::BindGroupEntry<'_>; 2] {
        [
            wgpu::BindGroupEntry {
                binding: 39,
                resource: wgpu::BindingResource::TextureView(&self.view),
            },
            wgpu::BindGroupEntry {
                binding: 40,
                resource: wgpu::BindingResource::Sampler(&self.sampler),
            },
        ]
    }

    /// GPU memory of the map, bytes.
    pub(crate) fn bytes(&self) -> u64 {
        let size = self.texture.size();
        super::texel_bytes(FORMAT) * u64::from(size.width) * u64::from(size.height)
    }

    /// Records the map's bake for the eye at world `eye` and the sun towards unit `sun`, from
    /// the levels of the world's uniforms `world` and heights `levels`, where any of them
    /// changed since the last bake: the sun, the eye's texel, or the levels
    /// (`levels_baked`: how many bakes of theirs the world has recorded); timed as
    /// [`Slot::AirShadow`]. Nothing where the map is a texel.
    pub(crate) fn encode(
        &mut self,
        (device, queue, encoder): (&wgpu::Device, &wgpu::Queue, &mut wgpu::CommandEncoder),
        (world, levels): (&wgpu::Buffer, &wgpu::TextureView),
        (eye, sun, levels_baked): (DVec3, Vec3, u64),
        timer: Option<&GpuTimer>,
    ) {
        if self.texture.width() != TEXELS {
            return;
        }
        let u = bake_uniforms(placement(eye), sun);
        // The corner moves with the eye within its texel: the eye's texel is what the map
        // depends on.
        let key = (
            AirShadowBake {
                origin: [0.0; 2],
                ..u
            },
            [eye.x, eye.z].map(|e| (e / TEXEL_M).floor() as i64),
            levels_baked,
        );
        if self.baked == Some(key) {
            return;
        }
        self.baked = Some(key);
        queue.write_buffer(&self.uniforms, 0, bytemuck::bytes_of(&u));
        let (layout, pipeline) = self.pass.get_or_insert_with(|| pass(device));
        use wgpu::BindingResource::TextureView;
        let entry = |binding, resource| wgpu::BindGroupEntry { binding, resource };
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("relief:air-shadow:group"),
            layout,
            entries: &[
                entry(1, world.as_entire_binding()),
                entry(2, TextureView(levels)),
                entry(41, self.uniforms.as_entire_binding()),
                entry(42, TextureView(&self.view)),
            ],
        });
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("relief:air-shadow:pass"),
            timestamp_writes: timer.map(|t| t.compute_writes(Slot::AirShadow)),
        });
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, &group, &[]);
        let n = TEXELS.div_ceil(super::WORKGROUP);
        pass.dispatch_workgroups(n, n, 1);
    }

    /// The next frame that draws shafts bakes the map whole (a new world's levels).
    pub(crate) fn forget(&mut self) {
        self.baked = None;
    }

    /// The map's texture and the eye's texel it was last baked around (`None` where it never
    /// was), for [`ShaftsMap::unpack`].
    #[cfg(not(target_arch = "wasm32"))]
    pub(crate) fn baked(&self) -> Option<(&wgpu::Texture, [i64; 2])> {
        self.baked
            .as_ref()
            .map(|(_, texel, _)| (&self.texture, *texel))
    }
}

/// The light shafts' shadow-height map as read back ([`crate::World::shafts_map`]).
#[derive(Clone, Debug, PartialEq)]
pub struct ShaftsMap {
    /// Per texel, the altitude (metres) below which the air over its centre lies in the
    /// terrain's shadow; `side` rows of `side`, x along a row, z from row to row.
    pub altitudes: Vec<f32>,
    /// World x and z of the first texel's corner, metres.
    pub corner: [f64; 2],
    /// A texel's side, metres.
    pub texel: f64,
    /// Texels on a side.
    pub side: u32,
}

impl ShaftsMap {
    /// The map from its texture's bytes (rgba16float, rows tightly packed; the altitude in
    /// red) as baked around the eye's `texel`.
    #[cfg(not(target_arch = "wasm32"))]
    pub(crate) fn unpack(bytes: &[u8], texel: [i64; 2]) -> Self {
        let altitudes = bytes
            .chunks_exact(8)
            .map(|t| half::f16::from_le_bytes([t[0], t[1]]).to_f32())
            .collect();
        let half = f64::from(TEXELS / 2);
        Self {
            altitudes,
            corner: texel.map(|i| (i as f64 - half) * TEXEL_M),
            texel: TEXEL_M,
            side: TEXELS,
        }
    }
}

/// The bake's layout and pipeline (`bake_air_shadow`).
fn pass(device: &wgpu::Device) -> (wgpu::BindGroupLayout, wgpu::ComputePipeline) {
    let c = wgpu::ShaderStages::COMPUTE;
    let levels = super::array_texture_entry(2, c, wgpu::TextureSampleType::Uint);
    let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("relief:air-shadow:layout"),
        entries: &[
            super::uniform_entry::<super::uniforms::WorldUniforms>(1, c),
            levels,
            super::uniform_entry::<AirShadowBake>(41, c),
            super::storage_entry(42, FORMAT),
        ],
    });
    let module = super::shader::module(
        device,
        "relief:air-shadow:shader",
        &super::shader::source("air_shadow"),
    );
    let pipeline = super::compute_pipeline(
        device,
        "relief:air-shadow",
        &layout,
        &module,
        "bake_air_shadow",
    );
    (layout, pipeline)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_map_is_a_grid_fixed_in_the_world_around_the_eye() {
        // Far from the origin, the corner is a whole number of texels in the world and the eye
        // lies in the map's middle texel.
        for eye in [
            DVec3::new(0.0, 100.0, 0.0),
            DVec3::new(12345.6, 900.0, -987.25),
            DVec3::new(3.0e6 + 17.5, 50.0, -2.5e6 - 3.0),
        ] {
            let [x, z, texel, texels] = placement(eye);
            assert_eq!((texel, texels), (TEXEL_M as f32, TEXELS as f32));
            for (c, e) in [(x, eye.x), (z, eye.z)] {
                let world = f64::from(c) + e;
                let k = world / TEXEL_M;
                assert!((k - k.round()).abs() < 1e-3, "{eye}: corner {world}");
                let middle = -f64::from(c) / TEXEL_M;
                assert!(
                    (f64::from(TEXELS / 2)..f64::from(TEXELS / 2 + 1)).contains(&middle),
                    "{eye}: the eye at texel {middle}"
                );
            }
        }
    }

    #[test]
    fn the_bake_marches_towards_the_sun_and_no_lower_than_half_a_degree() {
        let p = placement(DVec3::ZERO);
        let sun = Vec3::new(0.6, 0.0, 0.8).normalize() * 10f32.to_radians().cos()
            + Vec3::Y * 10f32.to_radians().sin();
        let u = bake_uniforms(p, sun);
        assert!((u.sun[0] - 0.6).abs() < 1e-6 && (u.sun[1] - 0.8).abs() < 1e-6);
        assert!((u.tan_e - 10f32.to_radians().tan()).abs() < 1e-5);
        let set = bake_uniforms(p, Vec3::new(0.0, -0.1, 1.0).normalize());
        assert!((f64::from(set.tan_e) - LOWEST_SUN.tan()).abs() < 1e-6);
        assert!(bake_uniforms(p, Vec3::Y).tan_e > 1e6);
    }
}
