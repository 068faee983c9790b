//! Ray casting of the continuous fBm surface (`wgsl/raymarch.wgsl`): the reference renderer
//! that relief's accuracy is measured against, and the seed's heightfield ray marcher as a
//! peer of the mesh pipeline. Each runs as a compute shader or as a full-screen fragment pass
//! into its own colour (`rgba8unorm`, sRGB-encoded by the shader) and distance (`r32float`,
//! distance along the unit ray; -1 for sky, -2 where the march ran out of steps) textures.

use super::render::RenderUniforms;
use super::shader;
use super::timing::{GpuTimer, Slot};
use crate::camera::View;
use crate::error::{Error, Result};
use crate::noise::Fbm;
use crate::params::{Shading, TerrainParams};

/// Mirrors `RayUniforms` in `wgsl/raymarch.wgsl` field by field.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct RayUniforms {
    /// Inverse of projection times view.
    pub inv_view_proj: [[f32; 4]; 4],
    /// Hash seed.
    pub seed: u32,
    /// Lattice cells across the tile at octave 0.
    pub frequency: u32,
    /// Octaves of the surface.
    pub octaves: u32,
    /// 0: reference, 1: the seed's march.
    pub method: u32,
    /// Octaves while marching (seed's march).
    pub march_octaves: u32,
    /// Octaves for the normal (seed's march).
    pub normal_octaves: u32,
    /// Step limit per ray.
    pub max_steps: u32,
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Amplitude ratio between octaves.
    pub gain: f32,
    /// Bound on |grad h_world| for the reference's conservative steps.
    pub lipschitz: f32,
    /// Step factor c of the seed's march (t += c h).
    pub step_factor: f32,
    /// Hit threshold k of the seed's march (|h| < k t).
    pub hit_k: f32,
    /// The seed's relaxation: each step is multiplied by max(relax t, 1) (0: off).
    pub relax: f32,
    /// Scroll offset in tiles, reduced to [0, 1).
    pub offset: [f32; 2],
}

pub(crate) use crate::method::{RayMethod, RayPath, SeedMarch};

/// Largest number of steps a ray may take before it is marked unresolved.
pub const MAX_STEPS: u32 = 4096;

impl RayUniforms {
    /// Uniforms for one image.
    pub fn new(params: &TerrainParams, view: &View, method: RayMethod, size: (u32, u32)) -> Self {
        let fbm = Fbm::from_params(params);
        let off = params.reduced_offset();
        let (method_id, seed) = match method {
            RayMethod::Reference => (0, SeedMarch::default()),
            RayMethod::SeedMarch(s) => (1, s),
        };
        Self {
            inv_view_proj: view.view_proj.inverse().to_cols_array_2d(),
            seed: params.seed,
            frequency: params.frequency,
            octaves: params.octaves,
            method: method_id,
            march_octaves: seed.march_octaves.clamp(1, params.octaves),
            normal_octaves: seed.normal_octaves.clamp(1, params.octaves),
            max_steps: MAX_STEPS,
            width: size.0,
            height: size.1,
            gain: params.gain,
            lipschitz: crate::noise::lipschitz_world(
                &fbm,
                params.octaves,
                f64::from(params.height_scale),
            ) as f32,
            step_factor: seed.step_factor,
            hit_k: seed.hit_k,
            relax: seed.relax,
            offset: [off[0] as f32, off[1] as f32],
        }
    }
}

/// What a [`RayMarcher`] casts rays at.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RayScene {
    /// The 2-unit tile (`wgsl/raymarch.wgsl`, `RayUniforms`).
    Tile,
    /// The endless world (`wgsl/world_rays.wgsl`, [`super::world_rays::WorldRayUniforms`]).
    World,
    /// The endless world without the clouds' march, for a world whose clouds are off: built in
    /// an eighth of the time on lavapipe, and refused a frame with clouds.
    WorldWithoutClouds,
}

impl RayScene {
    /// The endless world's scene for `params`: without the clouds' march where it has none.
    pub fn for_world(params: &crate::world::WorldParams) -> Self {
        if params.clouds.on() {
            RayScene::World
        } else {
            RayScene::WorldWithoutClouds
        }
    }

    fn source(self) -> String {
        match self {
            // The tile has no clouds.
            RayScene::Tile => shader::source_for("raymarch", shader::CloudCode::Without),
            RayScene::World => shader::source("world_rays_io"),
            RayScene::WorldWithoutClouds => {
                shader::source_for("world_rays_io", shader::CloudCode::Without)
            }
        }
    }

    fn uniform_entry(self, visibility: wgpu::ShaderStages) -> wgpu::BindGroupLayoutEntry {
        match self {
            RayScene::Tile => super::uniform_entry::<RayUniforms>(1, visibility),
            RayScene::World | RayScene::WorldWithoutClouds => {
                super::uniform_entry::<super::world_rays::WorldRayUniforms>(1, visibility)
            }
        }
    }

    fn uniform_buffer(self, device: &wgpu::Device) -> wgpu::Buffer {
        let label = "relief:raymarch:ray-uniforms";
        match self {
            RayScene::Tile => super::uniform_buffer::<RayUniforms>(device, label),
            RayScene::World | RayScene::WorldWithoutClouds => {
                super::uniform_buffer::<super::world_rays::WorldRayUniforms>(device, label)
            }
        }
    }
}

/// A ray-cast image target and the pipelines that fill it.
pub struct RayMarcher {
    scene: RayScene,
    compute: wgpu::ComputePipeline,
    fragment: wgpu::RenderPipeline,
    compute_group: wgpu::BindGroup,
    fragment_group: wgpu::BindGroup,
    render_uniforms: wgpu::Buffer,
    ray_uniforms: wgpu::Buffer,
    /// `rgba8unorm`, sRGB-encoded colour.
    pub color: wgpu::Texture,
    /// `r32float` distance along the unit view ray (-1 sky, -2 unresolved).
    pub distance: wgpu::Texture,
    width: u32,
    height: u32,
}

impl RayMarcher {
    /// Colour format of ray-cast images (the shader encodes sRGB).
    pub const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;
    /// Distance format.
    pub const DISTANCE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;

    /// Builds both pipelines and a `width` x `height` target for the tile.
    pub fn new(device: &wgpu::Device, width: u32, height: u32) -> Result<Self> {
        Self::for_scene(device, width, height, RayScene::Tile)
    }

    /// Builds both pipelines and a `width` x `height` target for `scene`.
    pub fn for_scene(
        device: &wgpu::Device,
        width: u32,
        height: u32,
        scene: RayScene,
    ) -> Result<Self> {
        let max = device.limits().max_texture_dimension_2d;
        for (name, v) in [("width", width), ("height", height)] {
            if v == 0 || v > max {
                return Err(Error::invalid(name, v, format!("1..={max} on this device")));
            }
        }
        super::scoped(device, || Self::build(device, width, height, scene))
    }

    fn build(device: &wgpu::Device, width: u32, height: u32, scene: RayScene) -> Self {
        let module = shader::module(device, "relief:raymarch:shader", &scene.source());
        let both = wgpu::ShaderStages::COMPUTE | wgpu::ShaderStages::FRAGMENT;
        let uniforms = [
            super::uniform_entry::<RenderUniforms>(0, both),
            scene.uniform_entry(both),
        ];
        let storage = super::storage_entry;
        let compute_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("relief:raymarch:compute-layout"),
            entries: &[
                uniforms[0],
                uniforms[1],
                storage(2, Self::COLOR_FORMAT),
                storage(3, Self::DISTANCE_FORMAT),
            ],
        });
        let fragment_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("relief:raymarch:fragment-layout"),
            entries: &uniforms,
        });
        let compute = super::compute_pipeline(
            device,
            "relief:raymarch:compute",
            &compute_layout,
            &module,
            "raymarch_cs",
        );
        let fragment = super::fullscreen_pipeline(
            device,
            "relief:raymarch:fragment-pipeline",
            &fragment_layout,
            &module,
            ("fullscreen_vs", "raymarch_fs"),
            &[
                Some(Self::COLOR_FORMAT.into()),
                Some(Self::DISTANCE_FORMAT.into()),
            ],
        );
        let render_uniforms =
            super::uniform_buffer::<RenderUniforms>(device, "relief:raymarch:render-uniforms");
        let ray_uniforms = scene.uniform_buffer(device);
        let usage = wgpu::TextureUsages::STORAGE_BINDING
            | wgpu::TextureUsages::RENDER_ATTACHMENT
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC;
        let texture =
            |label, format| super::texture_2d(device, label, (width, height), format, usage);
        let color = texture("relief:raymarch:color", Self::COLOR_FORMAT);
        let distance = texture("relief:raymarch:distance", Self::DISTANCE_FORMAT);
        let color_view = color.create_view(&Default::default());
        let distance_view = distance.create_view(&Default::default());
        let uniform_entries = [
            wgpu::BindGroupEntry {
                binding: 0,
                resource: render_uniforms.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: ray_uniforms.as_entire_binding(),
            },
        ];
        let compute_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("relief:raymarch:compute-group"),
            layout: &compute_layout,
            entries: &[
                uniform_entries[0].clone(),
                uniform_entries[1].clone(),
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: wgpu::BindingResource::TextureView(&color_view),
                },
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: wgpu::BindingResource::TextureView(&distance_view),
                },
            ],
        });
        let fragment_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("relief:raymarch:fragment-group"),
            layout: &fragment_layout,
            entries: &uniform_entries,
        });
        Self {
            scene,
            compute,
            fragment,
            compute_group,
            fragment_group,
            render_uniforms,
            ray_uniforms,
            color,
            distance,
            width,
            height,
        }
    }

    /// Writes the uniforms for one image of `params` seen through `view`.
    pub fn prepare(
        &self,
        queue: &wgpu::Queue,
        params: &TerrainParams,
        shading: &Shading,
        view: &View,
        method: RayMethod,
    ) {
        debug_assert_eq!(self.scene, RayScene::Tile, "prepare is the tile's");
        let r = RenderUniforms::new(params, shading, view, true);
        queue.write_buffer(&self.render_uniforms, 0, bytemuck::bytes_of(&r));
        let ray = RayUniforms::new(params, view, method, (self.width, self.height));
        queue.write_buffer(&self.ray_uniforms, 0, bytemuck::bytes_of(&ray));
    }

    /// Writes the uniforms for one image of the endless world (a caster built for
    /// [`RayScene::World`]; `render` from the world's shading, camera-relative).
    pub fn prepare_world(
        &self,
        queue: &wgpu::Queue,
        render: &RenderUniforms,
        ray: &super::world_rays::WorldRayUniforms,
    ) -> Result<()> {
        let clouds = render.clouds[0] > 0.0;
        if self.scene != RayScene::World
            && (self.scene, clouds) != (RayScene::WorldWithoutClouds, false)
        {
            return Err(Error::invalid(
                "scene",
                format!("{:?}", self.scene),
                "a caster built for RayScene::World (or WorldWithoutClouds, for a world without clouds)",
            ));
        }
        queue.write_buffer(&self.render_uniforms, 0, bytemuck::bytes_of(render));
        queue.write_buffer(&self.ray_uniforms, 0, bytemuck::bytes_of(ray));
        Ok(())
    }

    /// Its render and ray uniforms, as its last prepare wrote them (what a pass over its cast
    /// shades with: `super::props_reference`).
    #[cfg(not(target_arch = "wasm32"))]
    pub(crate) fn uniforms(&self) -> (&wgpu::Buffer, &wgpu::Buffer) {
        (&self.render_uniforms, &self.ray_uniforms)
    }

    /// Its size in samples.
    #[cfg(not(target_arch = "wasm32"))]
    pub(crate) fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    /// Records the ray cast, timed as [`Slot::Render`] when `timer` is given.
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        path: RayPath,
        timer: Option<&GpuTimer>,
    ) {
        match path {
            RayPath::Compute => {
                let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some("relief:raymarch:compute-pass"),
                    timestamp_writes: timer.map(|t| t.compute_writes(Slot::Render)),
                });
                pass.set_pipeline(&self.compute);
                pass.set_bind_group(0, &self.compute_group, &[]);
                pass.dispatch_workgroups(
                    self.width.div_ceil(super::WORKGROUP),
                    self.height.div_ceil(super::WORKGROUP),
                    1,
                );
            }
            RayPath::Fragment => {
                let color = self.color.create_view(&Default::default());
                let distance = self.distance.create_view(&Default::default());
                let attachment = |view| {
                    Some(wgpu::RenderPassColorAttachment {
                        view,
                        depth_slice: None,
                        resolve_target: None,
                        ops: wgpu::Operations {
                            load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                            store: wgpu::StoreOp::Store,
                        },
                    })
                };
                let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("relief:raymarch:fragment-pass"),
                    color_attachments: &[attachment(&color), attachment(&distance)],
                    depth_stencil_attachment: None,
                    timestamp_writes: timer.map(|t| t.render_writes(Slot::Render)),
                    occlusion_query_set: None,
                    multiview_mask: None,
                });
                pass.set_pipeline(&self.fragment);
                pass.set_bind_group(0, &self.fragment_group, &[]);
                pass.draw(0..3, 0..1);
            }
        }
    }
}
