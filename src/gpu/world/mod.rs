//! [`World`]: the endless landscape as middleware. The camera drives it: each frame
//! [`World::prepare`] moves the clipmap's levels ([`crate::clipmap`]) and bakes only the
//! strips they uncovered ([`World::encode_bake`]), selects the patches inside the view frustum,
//! writes the frame's uniforms and records the compute passes of the methods shaded in
//! compute; [`World::render`] draws into the host's pass.

mod bake;
mod draw;
mod frame;
mod grass;
mod mesh_history;
mod props;
mod resources;
mod shafts;
mod temporal;
mod vis_frame;

use self::draw::draw_patches;

#[cfg(test)]
pub(crate) use self::frame::RIPPLE_PERIOD;
pub use self::frame::{horizon, render_uniforms, CLOCK_PERIOD, SAND_BAND};
use self::resources::*;
use glam::{DVec3, Mat4, Vec3, Vec4};

use super::layer::{Layer, LayerFrame};
use super::light_queue::LightQueue;
use super::region::{crop, crop_exact, subtract};
use super::render::RenderUniforms;
use super::timing::{GpuTimer, Slot};
pub(crate) use super::uniforms::{LevelUniforms, WorldUniforms};
use super::visibility::{Visibility, WorldBindings};
pub use super::world_stats::mib;
pub(crate) use super::world_stats::WorldStats;
use super::{scoped, shader, Targets};
use crate::camera::View;
pub(crate) use crate::camera::WorldView;
use crate::clipmap::{Clipmap, Eye, Patch, MAX_LEVELS, PATCHES};
use crate::error::{Error, Result};
use crate::gpu::landscape::{LandscapeBake, LevelTarget, Rect};
use crate::gpu::raster::{Patches, Raster};
use crate::gpu::world_light::{LightBake, LightRect, LightUniforms};
use crate::landscape::Landscape;
use crate::method::{Method, MethodConfig};
use crate::params::{Shading, TerrainParams};
use crate::sky::SkyLight;
pub(crate) use crate::world::WorldParams;

/// The endless world's default camera (chosen by eye): 1200 m above the ground at
/// (2000, -3000), looking east-north-east and a little down over ridges running out to the
/// horizon. Returns the eye and the point looked at.
pub fn default_camera(land: &crate::landscape::Landscape) -> (DVec3, DVec3) {
    let eye = DVec3::new(2000.0, land.height_at(2000.0, -3000.0) + 1200.0, -3000.0);
    (eye, eye + DVec3::new(7000.0, -1000.0, 3000.0))
}

/// GPU memory of one level's textures (samples and light) in a layout of `map`, bytes.
fn level_bytes(map: &Clipmap) -> u64 {
    u64::from(map.side()).pow(2)
        * (super::texel_bytes(crate::gpu::landscape::LandscapeBake::LEVEL_FORMAT)
            + super::texel_bytes(LightBake::FORMAT))
}

/// How many other targets' mesh and sky pipelines a [`World`] keeps (`World::set_targets`).
const KEPT_TARGETS: usize = 3;

/// The endless world on the host's device: see the module docs.
pub struct World {
    /// The layers drawn after the terrain ([`World::push_layer`]).
    layers: Vec<Box<dyn Layer>>,
    params: WorldParams,
    shading: Shading,
    targets: Targets,
    errors: Vec<(i32, f64)>,
    /// The reference ray cast's slope bounds ([`Landscape::slope_bounds`]), kept with the
    /// landscape they were measured for.
    slopes: Vec<f64>,
    map: Clipmap,
    map_k: f64,
    texture: wgpu::Texture,
    bake: LandscapeBake,
    bake_target: LevelTarget,
    /// The light bake's output beside the levels: horizon and valley depth per texel.
    light: LevelLight,
    light_bake: LightBake,
    pipeline: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
    bind_group: wgpu::BindGroup,
    /// The same without the props' shade map (its bake's: it writes the map).
    bind_group_unmapped: wgpu::BindGroup,
    sky: super::sky::SkyPass,
    /// The mesh's and the sky's pipelines for the targets drawn into before, kept for a switch
    /// back (the window's methods draw with 4 samples or 1): at most [`KEPT_TARGETS`].
    kept: Vec<(Targets, wgpu::RenderPipeline, super::sky::SkyPass)>,
    render_uniforms: wgpu::Buffer,
    world_uniforms: wgpu::Buffer,
    indices: wgpu::Buffer,
    /// Indices of a whole patch, then of a sub-patch ([`Clipmap::trim`]), in `indices`.
    index_counts: [u32; 2],
    instances: wgpu::Buffer,
    /// Whole patches, then sub-patches, in `instances`.
    instance_counts: [u32; 2],
    /// The whole patches the compute raster draws by the end of each depth pass but the last
    /// ([`crate::gpu::raster::pass_ends`]).
    raster_passes: [u32; crate::gpu::raster::PASSES - 1],
    stats: WorldStats,
    /// Set by [`World::prepare`]: the next bake starts the next frame's counts in `stats`.
    frame_prepared: bool,
    /// The reference sample of the last `prepare` (finest-level samples).
    reference: [i64; 2],
    /// The camera-relative projection of the last `prepare`.
    matrix: Mat4,
    /// Most texels one `encode_bake` bakes.
    bake_budget: u64,
    light_budget: u64,
    /// Seconds since the parameters' clock ([`World::set_time`]).
    time: f64,
    /// Set when this world draws the seed blog's tile ([`crate::Terrain`]'s mesh).
    tile: Option<TileSetup>,
    /// The tile's textures, read per pixel (stand-ins for the endless world).
    tile_textures: TileTextures,
    /// The tile's square when its levels were last baked (what [`crop`] kept).
    baked_region: Option<[f64; 4]>,
    /// Rectangles the tile's square uncovered as it moved, still to bake.
    region_pending: Vec<Rect>,
    /// The world's shader module (the visibility method's raster pass is built from it).
    module: wgpu::ShaderModule,
    /// How the mesh is shaded: [`Method::Mesh`] (forward) or [`Method::Visibility`].
    method: Method,
    /// The visibility method's pipelines and targets, once that method was chosen.
    visibility: Option<Visibility>,
    /// Samples a pixel the visibility method rasterises and shades.
    vis_samples: u32,
    /// Where the visibility method rasterises ([`World::set_method`]).
    vis_raster: Raster,
    /// The size of the host's target when it differs from the view's (a tile of a larger
    /// image): what the visibility method's images are made at.
    target_size: Option<(u32, u32)>,
    /// The size of the visibility method's last images.
    vis_size: (u32, u32),
    /// The hybrid method's raise per level spacing (log2 metres, metres), measured when the
    /// method is first chosen and again when the landscape changes under it.
    raises: Vec<(i32, f64)>,
    /// The temporal service ([`World::set_temporal`]) and the history it keeps.
    temporal: crate::temporal::Temporal,
    history: crate::temporal::History,
    /// The near and far planes of the last `prepare`'s matrix.
    near_far: (f32, f32),
    /// The forward mesh's own image and history, where it accumulates.
    mesh_history: Option<mesh_history::MeshHistory>,
    /// The grass's passes, where it grows ([`WorldParams::grass`]).
    grass: Option<crate::gpu::grass::GrassPass>,
    /// The props' passes where they stand ([`WorldParams::props`]), and what they are.
    props: Option<crate::gpu::props::PropsPass>,
    props_scene: crate::props::Scene,
    /// The props drawn over a frame whose method does not march them, where props are on.
    props_overlay: Option<crate::gpu::props_overlay::PropsOverlay>,
    /// The props' shade map the overlay's methods shade the terrain with (a texel a level until
    /// the overlay first draws).
    props_map: crate::gpu::props_map::PropsMap,
    /// The light shafts' shadow-height map and what it is baked for.
    shafts: shafts::Shafts,
}

/// What makes a world the seed blog's tile: a bounded square of a periodic landscape, lit by
/// the [`Shading`]'s sun, in clear air, with a mesh no finer than the tile's grid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct TileSetup {
    /// The square drawn, world metres: x0, z0, x1, z1.
    pub region: [f64; 4],
    /// log2 of the finest spacing the mesh may use.
    pub finest_log2: i32,
    /// The tile's textures' side in texels: the fragment shader reads the tile's normals,
    /// height and colour channel per pixel from them, as the tile always did.
    pub tex_size: u32,
    /// Where the textures are read, less where they were baked, in tiles (the scroll).
    pub shift: [f32; 2],
}

/// Texels [`World::encode_bake`] bakes at most per frame unless told otherwise: about 0.4 ms
/// on an H100 (the default world's 12 octaves, two channels). A level that moves uncovers far
/// fewer while flying (at most 0.5 M texels a frame at 300 km/h); a teleport or a new layout
/// (every level whole, 13.6 M texels at the default) is spread over a few frames, coarse levels
/// first, the next coarser level drawn where a finer one is not baked yet.
pub const DEFAULT_BAKE_BUDGET: u64 = 1 << 21;

/// Texels [`World::encode_bake`] lights at most per frame unless told otherwise (the light
/// bake's time a texel is several of the height bake's: docs/results has the measured split).
/// Arrival, a new layout or a turned sun (every level relit) is spread over frames, coarse
/// levels first, each level drawn with a coarser level's light until its own is done.
pub const DEFAULT_LIGHT_BUDGET: u64 = 1 << 18;

/// Instances the patch buffer holds: every patch of every level.
const MAX_PATCHES: usize = MAX_LEVELS * (PATCHES * PATCHES) as usize;

/// Instances a world's patch buffer holds: every patch of every level, and for the tile room
/// for sub-patches along its edge ([`Clipmap::trim`]; a few hundred at the views tried, and
/// past this the crossed patches are drawn whole).
fn instance_capacity(tile: bool) -> usize {
    if tile {
        4 * MAX_PATCHES
    } else {
        MAX_PATCHES
    }
}

impl World {
    /// Builds the pipelines and the level textures for `params`, drawn into `targets`; the
    /// first [`World::encode_bake`] bakes every level the view needs.
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        targets: Targets,
        params: WorldParams,
    ) -> Result<Self> {
        let _ = queue;
        params.validate()?;
        let mut world = Self::build(device, targets, params, None)?;
        world.update_grass(device)?;
        world.update_props(device)?;
        Ok(world)
    }

    /// A world drawing the seed blog's tile: `params` come from validated tile parameters
    /// (heights in metres may exceed the endless world's table).
    pub(crate) fn new_tile(
        device: &wgpu::Device,
        targets: Targets,
        params: WorldParams,
        tile: TileSetup,
    ) -> Result<Self> {
        Self::build(device, targets, params, Some(tile))
    }

    fn build(
        device: &wgpu::Device,
        targets: Targets,
        params: WorldParams,
        tile: Option<TileSetup>,
    ) -> Result<Self> {
        let errors = level_errors(&params.land, tile.map(|t| t.finest_log2));
        // Laid out for a 1080p, 45-degree view until the first frame says otherwise.
        let k = 1080.0 / (2.0 * (22.5f64).to_radians().tan());
        let map = layout(&params, &errors, k);
        scoped(device, || {
            let bake = LandscapeBake::levels(device);
            let light_bake = LightBake::new(device);
            let (texture, bake_target) = level_texture(device, &bake, &map);
            let light = LevelLight::new(device, &light_bake, &texture, &map);
            // The tile has no clouds: its module is built without their march.
            let clouds = match tile {
                Some(_) => shader::CloudCode::Without,
                None => shader::CloudCode::March,
            };
            let source = shader::source_for("world", clouds);
            let module = shader::module(device, "relief:world:shader", &source);
            // Compute too: the visibility method's compute raster places the same vertices.
            let vf = wgpu::ShaderStages::VERTEX_FRAGMENT | wgpu::ShaderStages::COMPUTE;
            // The props' shade map: the terrain's shading, and the grass's scatter (compute),
            // which lights each blade with the props' shade at its root.
            let map_entries = crate::gpu::props_map::PropsMap::entries(
                wgpu::ShaderStages::FRAGMENT | wgpu::ShaderStages::COMPUTE,
            );
            let air = crate::gpu::air_shadow::AirShadow::entries(wgpu::ShaderStages::FRAGMENT);
            let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("relief:world:bind-group-layout"),
                entries: &[
                    super::uniform_entry::<RenderUniforms>(0, vf),
                    super::uniform_entry::<WorldUniforms>(1, vf),
                    array_entry(2, wgpu::TextureSampleType::Uint),
                    array_entry(3, wgpu::TextureSampleType::Uint),
                    super::texture_entry(4, wgpu::ShaderStages::FRAGMENT, false),
                    super::texture_entry(5, wgpu::ShaderStages::FRAGMENT, true),
                    wgpu::BindGroupLayoutEntry {
                        binding: 6,
                        visibility: wgpu::ShaderStages::FRAGMENT,
                        ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                        count: None,
                    },
                    // The forward mesh's fragment shader alone reads the props' shade map
                    // through this group (the world's compute passes bind it unread).
                    map_entries[0],
                    map_entries[1],
                    // And the light shafts' shadow-height map.
                    air[0],
                    air[1],
                ],
            });
            let pipeline = mesh_pipeline(device, (&layout, &module), &targets, tile.is_some());
            let render_uniforms =
                super::uniform_buffer::<RenderUniforms>(device, "relief:world:render-uniforms");
            let world_uniforms =
                super::uniform_buffer::<WorldUniforms>(device, "relief:world:world-uniforms");
            let tile_textures = TileTextures::new(device, &crate::gpu::Textures::new(device, 1));
            let props_map = crate::gpu::props_map::PropsMap::new(device);
            let shafts = shafts::Shafts::new(device, tile.is_some());
            let bind_group = bind(
                device,
                &layout,
                (&render_uniforms, &world_uniforms),
                (&texture, &light.texture),
                (&tile_textures, props_map.bindings(false), &shafts.map),
            );
            let (indices, index_counts) = patch_indices(device, &map);
            let instances = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("relief:world:patches"),
                size: (instance_capacity(tile.is_some()) * std::mem::size_of::<Patch>()) as u64,
                // Storage too: the compute raster reads the patches.
                usage: wgpu::BufferUsages::VERTEX
                    | wgpu::BufferUsages::STORAGE
                    | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            World {
                params,
                shading: Shading::default(),
                targets,
                errors,
                // The tile's ray casters are its own (`gpu::raymarch`): no slopes to measure.
                slopes: if tile.is_some() {
                    Vec::new()
                } else {
                    params.land.slope_bounds()
                },
                map,
                map_k: k,
                texture,
                bake,
                bake_target,
                light,
                light_bake,
                pipeline,
                layout,
                bind_group_unmapped: bind_group.clone(),
                bind_group,
                sky: super::sky::SkyPass::new(device, &targets, (&render_uniforms, &shafts.map)),
                kept: Vec::new(),
                render_uniforms,
                world_uniforms,
                indices,
                index_counts,
                instances,
                instance_counts: [0; 2],
                raster_passes: [0; crate::gpu::raster::PASSES - 1],
                stats: WorldStats::default(),
                frame_prepared: false,
                reference: [0; 2],
                matrix: Mat4::IDENTITY,
                bake_budget: DEFAULT_BAKE_BUDGET,
                light_budget: DEFAULT_LIGHT_BUDGET,
                time: 0.0,
                tile,
                tile_textures,
                baked_region: None,
                region_pending: Vec::new(),
                module,
                method: Method::Mesh,
                visibility: None,
                layers: Vec::new(),
                vis_samples: super::visibility::SAMPLES,
                vis_raster: Raster::Hardware,
                target_size: None,
                vis_size: (0, 0),
                raises: Vec::new(),
                temporal: crate::temporal::Temporal::OFF,
                history: Default::default(),
                near_far: (0.0, 0.0),
                mesh_history: None,
                grass: None,
                props: None,
                props_scene: crate::props::Scene::default(),
                props_overlay: None,
                props_map,
                shafts,
            }
        })
    }

    /// Draws into `targets` from now on (the host's pass changed its formats or MSAA
    /// samples): what draws into the host's pass follows. The mesh's and the sky's pipelines of
    /// up to three earlier targets are kept, and taken back on a switch back; the visibility
    /// method's composite is built again. Nothing is re-baked.
    pub fn set_targets(&mut self, device: &wgpu::Device, targets: Targets) -> Result<()> {
        targets.validate()?;
        if targets == self.targets {
            return Ok(());
        }
        let tile = self.tile.is_some();
        let (pipeline, sky) = match self.kept.iter().position(|(t, ..)| *t == targets) {
            Some(i) => {
                let (_, pipeline, sky) = self.kept.remove(i);
                (pipeline, sky)
            }
            None => scoped(device, || {
                let pipeline = mesh_pipeline(device, (&self.layout, &self.module), &targets, tile);
                let sky = super::sky::SkyPass::new(
                    device,
                    &targets,
                    (&self.render_uniforms, &self.shafts.map),
                );
                (pipeline, sky)
            })?,
        };
        let pipeline = std::mem::replace(&mut self.pipeline, pipeline);
        let sky = std::mem::replace(&mut self.sky, sky);
        self.kept.push((self.targets, pipeline, sky));
        if self.kept.len() > KEPT_TARGETS {
            self.kept.remove(0);
        }
        self.targets = targets;
        // The visibility method's and the mesh history's composites draw into the host's pass:
        // built again for these.
        self.visibility = None;
        self.mesh_history = None;
        self.props_overlay = None;
        let rebuilt = self.set_method(device, self.method_config());
        if rebuilt.is_err() {
            // Never a method without its passes: the forward mesh draws, and says so.
            self.method = Method::Mesh;
        }
        rebuilt
    }

    /// Marks every level owed, as new parameters do: the next [`World::encode_bake`] bakes them
    /// all again (for measurements of a whole bake, or after the host lost the textures).
    pub fn invalidate(&mut self, device: &wgpu::Device) -> Result<()> {
        self.relayout(device, self.map_k)
    }

    /// The parameters.
    pub fn params(&self) -> &WorldParams {
        &self.params
    }

    /// The formats this world draws into.
    pub fn targets(&self) -> &Targets {
        &self.targets
    }

    /// The shading.
    pub fn shading(&self) -> &Shading {
        &self.shading
    }

    /// Replaces the shading; nothing is re-baked.
    pub fn set_shading(&mut self, shading: Shading) {
        if shading != self.shading {
            self.reset_history("shading");
        }
        self.shading = shading;
    }

    /// How the mesh is drawn: [`Method::Mesh`] (forward shading in the fragment shader, the
    /// default), [`Method::Visibility`] (a raster pass of depth and attributes per MSAA
    /// sample, every sample shaded in compute: [`super::visibility`]) or, in the endless world,
    /// [`Method::Hybrid`] (the same raster of the levels raised to bound the surface from
    /// above, each sample refined to the continuous surface in compute). Other methods are ray
    /// casters with their own paths and are refused.
    ///
    /// `config` is a [`MethodConfig`] or a bare [`Method`] (at 4 samples, the GPU's raster).
    /// A refused configuration changes nothing.
    pub fn set_method(
        &mut self,
        device: &wgpu::Device,
        config: impl Into<MethodConfig>,
    ) -> Result<()> {
        let config = config.into();
        config.validate()?;
        let method = config.method;
        match method {
            Method::Mesh => {}
            Method::Hybrid if self.tile.is_some() => {
                return Err(Error::invalid(
                    "method",
                    method,
                    "mesh or visibility for the tile (the hybrid refines to the endless world's surface)",
                ))
            }
            Method::Visibility | Method::Hybrid => {
                let hybrid = method == Method::Hybrid;
                self.build_visibility(device, (config.samples, hybrid, config.raster))?;
                if hybrid && self.raises.is_empty() {
                    self.raises = level_raises(&self.params.land);
                }
            }
            other => return Err(Error::invalid(
                "method",
                other,
                "mesh, visibility or hybrid (the ray casters and the blog draw through their own passes)",
            )),
        }
        if config != self.method_config() {
            self.reset_history("method");
        }
        self.method = method;
        self.vis_samples = config.samples;
        self.vis_raster = config.raster;
        self.update_mesh_history(device)
    }

    /// Builds the visibility method's pipelines for `samples`, the hybrid or not and `raster`,
    /// with the clouds' march where the frame has clouds, unless those are built already.
    fn build_visibility(
        &mut self,
        device: &wgpu::Device,
        (samples, hybrid, raster): (u32, bool, Raster),
    ) -> Result<()> {
        let clouds = self.params.clouds.on();
        let wanted = (samples, hybrid, raster, clouds);
        if self.visibility.as_ref().map(Visibility::built_for) != Some(wanted) {
            let vis = scoped(device, || {
                let key = (self.tile.is_none(), samples, hybrid, raster, clouds);
                Visibility::new(device, (&self.module, &self.layout), &self.targets, key)
            })?;
            self.visibility = Some(vis);
        }
        if let Some(vis) = &mut self.visibility {
            vis.set_temporal(device, self.temporal.on());
        }
        Ok(())
    }

    /// How frames are drawn: the method with its samples and raster ([`World::set_method`]).
    pub fn method_config(&self) -> MethodConfig {
        MethodConfig {
            method: self.method,
            samples: self.vis_samples,
            raster: self.vis_raster,
        }
    }

    /// Metres the level spaced `2^spacing_log2` metres is raised by: for the hybrid method
    /// [`crate::clipmap::level_raise`], a bound on how far the continuous surface rises above
    /// that level's mesh, so the mesh lies on or above the surface; 0 for the other methods.
    pub fn level_raise(&self, spacing_log2: i32) -> f64 {
        if self.method != Method::Hybrid {
            return 0.0;
        }
        self.raises
            .iter()
            .find(|(l, _)| *l == spacing_log2)
            .map_or(0.0, |(_, r)| *r)
    }

    /// How the mesh is drawn ([`World::set_method`]).
    pub fn method(&self) -> Method {
        self.method
    }

    /// Whether the compute raster's later passes skip the blocks of cells that nearer levels
    /// hide (on by default; for the test that skipping changes no pixel). Applies to the
    /// current method's raster.
    #[doc(hidden)]
    pub fn set_raster_skips_hidden(&mut self, on: bool) {
        if let Some(vis) = &mut self.visibility {
            vis.set_raster_skips_hidden(on);
        }
    }

    /// The host target's size where it differs from the view's ([`WorldView::size`]): a tile
    /// of a larger image drawn through [`WorldView::crop`]. The visibility method makes its
    /// images at this size; `None` (the default) takes the view's.
    pub fn set_target_size(&mut self, size: Option<(u32, u32)>) {
        self.target_size = size;
    }

    /// The host target's size where it differs from the view's ([`World::set_target_size`]).
    pub fn target_size(&self) -> Option<(u32, u32)> {
        self.target_size
    }

    /// GPU memory of the method's own images for the last frame's size, bytes: the
    /// visibility method's, or the forward mesh's image and history where it accumulates (0
    /// for the forward mesh drawing into the host's pass).
    pub fn method_bytes(&self) -> u64 {
        match (&self.visibility, self.method) {
            (Some(v), Method::Visibility | Method::Hybrid) => v.bytes(self.vis_size),
            (_, Method::Mesh) => self
                .mesh_history
                .as_ref()
                .map_or(0, |h| h.bytes(self.vis_size)),
            _ => 0,
        }
    }

    /// The level layout (for tests and tools).
    pub fn clipmap(&self) -> &Clipmap {
        &self.map
    }

    /// Turns the morph between levels off (it prevents cracks; off only to show them).
    pub fn set_morphing(&mut self, on: bool) {
        self.map.morphing = on;
    }

    /// The level texture array: side x side x levels, rg32uint (height, dh/dx, dh/dz, colour
    /// channel packed in 64 bits: [`crate::gpu::landscape::unpack_level_texel`]), toroidally
    /// addressed.
    pub fn level_texture(&self) -> &wgpu::Texture {
        &self.texture
    }

    /// The light texture array beside the levels: side x side x levels, r32uint holding two
    /// 16-bit floats (the
    /// terrain's horizon towards the sun in radians, the valley depth in metres), at the same
    /// texels as [`World::level_texture`]'s samples.
    pub fn light_texture(&self) -> &wgpu::Texture {
        &self.light.texture
    }

    /// What the last frame cost.
    pub fn stats(&self) -> WorldStats {
        self.stats
    }

    /// World height in metres of the continuous surface at (x, z), from the CPU twin.
    pub fn height_at(&self, x: f64, z: f64) -> f64 {
        self.params.land.height_at(x, z)
    }

    /// Sets the seconds since the parameters' clock ([`WorldParams::clock`]): a window's
    /// time since it started. The next [`World::prepare`] draws what moves on its own (the
    /// water's ripples, drifting with the wind) at the clock plus these seconds. Still frames
    /// keep 0.
    pub fn set_time(&mut self, seconds: f64) {
        self.time = if seconds.is_finite() { seconds } else { 0.0 };
    }

    /// The clock the next frame is drawn at: the parameters' clock plus [`World::set_time`]'s
    /// seconds. What a ray caster drawing this world's frame should take too.
    pub fn clock(&self) -> f64 {
        self.params.clock + self.time
    }

    /// The sky the next frame is drawn with: the parameters' sky at [`World::clock`], its sun
    /// moved along a running day ([`crate::world::day::sky_at`]).
    pub fn sky(&self) -> crate::sky::Sky {
        crate::world::day::sky_at(self.params.sky, self.clock())
    }

    /// Changes the parameters: a new terrain re-bakes every level, a new knob re-lays them out,
    /// and the shading keys (snow, AO, the sun, fog) change nothing baked.
    pub fn set_params(&mut self, device: &wgpu::Device, params: WorldParams) -> Result<()> {
        params.validate()?;
        self.apply(device, params)
    }

    /// Sets the tile's parameters and setup (see [`World::new_tile`]).
    pub(crate) fn set_tile(
        &mut self,
        device: &wgpu::Device,
        params: WorldParams,
        tile: TileSetup,
    ) -> Result<()> {
        let floor_moved = self.tile.map(|t| t.finest_log2) != Some(tile.finest_log2);
        if self.tile != Some(tile) {
            // The tile scrolled under the camera: what the history holds moved.
            self.reset_history("tile");
        }
        self.tile = Some(tile);
        if floor_moved && params.land == self.params.land {
            self.errors = level_errors(&params.land, Some(tile.finest_log2));
            self.params = params;
            return self.relayout(device, self.map_k);
        }
        self.apply(device, params)
    }

    /// Binds the tile's textures (after they were made, or made again at a new size).
    pub(crate) fn set_tile_textures(
        &mut self,
        device: &wgpu::Device,
        textures: &crate::gpu::Textures,
    ) {
        self.tile_textures = TileTextures::new(device, textures);
        if let Some(v) = &mut self.visibility {
            v.unbind();
        }
        self.rebind(device);
    }

    /// Binds the world's resources anew (new levels, tile textures or props' shade map): the
    /// bind group everything draws with, and one without the props' map, which its bake
    /// writes through.
    fn rebind(&mut self, device: &wgpu::Device) {
        let group = |empty| {
            bind(
                device,
                &self.layout,
                (&self.render_uniforms, &self.world_uniforms),
                (&self.texture, &self.light.texture),
                (
                    &self.tile_textures,
                    self.props_map.bindings(empty),
                    &self.shafts.map,
                ),
            )
        };
        self.bind_group = group(false);
        self.bind_group_unmapped = group(true);
    }

    fn apply(&mut self, device: &wgpu::Device, params: WorldParams) -> Result<()> {
        if params != self.params {
            self.reset_history("parameters");
            self.props_map.forget();
            self.shafts.map.forget();
        }
        // Shading alone (snow, AO, the sun, fog) changes no level: nothing to lay out or bake.
        let relayout =
            params.land != self.params.land || params.pixel_error != self.params.pixel_error;
        if params.land != self.params.land {
            self.errors = level_errors(&params.land, self.tile.map(|t| t.finest_log2));
            if self.tile.is_none() {
                self.slopes = params.land.slope_bounds();
            }
            self.raises = if self.method == Method::Hybrid {
                level_raises(&params.land)
            } else {
                Vec::new()
            };
        }
        let clouds_turned = params.clouds.on() != self.params.clouds.on();
        self.params = params;
        if relayout {
            self.relayout(device, self.map_k)?;
        }
        if clouds_turned {
            // The shading drawn with is built again with the clouds (or without); one kept
            // for another method is dropped, built when that method is next set.
            match (self.method, &self.visibility) {
                (Method::Visibility | Method::Hybrid, Some(v)) => {
                    let (samples, hybrid, raster, _) = v.built_for();
                    self.build_visibility(device, (samples, hybrid, raster))?;
                }
                _ => self.visibility = None,
            }
        }
        self.update_grass(device)?;
        self.update_props(device)
    }

    /// Everything a frame needs before the host's render pass, recorded into the host's
    /// encoder: the bake of what `view` uncovered ([`World::encode_bake`]), the frame's
    /// uniforms, and for the methods shaded in compute (`visibility`, `hybrid`) their raster
    /// and shading passes. Then [`World::render`] draws into the host's pass, or
    /// [`World::present`] writes the frame without one. Returns the texels baked.
    ///
    /// An error (a view whose eye or field of view is not finite, an image too large for the
    /// compute raster) stops the recording where it happened: draw nothing for this frame, as
    /// what is recorded is part of one.
    pub fn prepare(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        view: &WorldView,
    ) -> Result<u64> {
        self.prepare_timed(device, queue, encoder, view, None)
    }

    /// [`World::prepare`], timing its passes into `timer`.
    pub fn prepare_timed(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        view: &WorldView,
        timer: Option<&GpuTimer>,
    ) -> Result<u64> {
        // With the temporal service the frame is drawn through a jittered view.
        let unjittered = *view;
        let jittered = self.jittered(view);
        let view = &jittered;
        let texels = self.encode_bake_timed(device, queue, encoder, view, timer)?;
        self.write_uniforms(queue, view);
        self.encode_shafts((device, queue, encoder), (view, texels), timer);
        self.encode_grass(device, queue, encoder, view, timer);
        self.encode_props((device, queue, encoder), (view, &unjittered), timer);
        if matches!(self.method, Method::Visibility | Method::Hybrid) {
            self.encode_visibility(device, queue, encoder, (view, &unjittered), timer)?;
            self.encode_resolve(queue, encoder, &unjittered, timer);
        } else if self.mesh_history.is_some() {
            self.encode_mesh_history((device, queue, encoder), view, timer);
            self.encode_resolve(queue, encoder, &unjittered, timer);
        }
        let frame = LayerFrame {
            device,
            queue,
            targets: &self.targets,
            eye: view.eye,
            render_uniforms: &self.render_uniforms,
            method: self.method,
        };
        for layer in &mut self.layers {
            layer.prepare(&frame, encoder);
        }
        Ok(texels)
    }
}
