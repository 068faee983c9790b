//! [`World`]: the endless landscape as middleware. The camera drives it: each frame
//! [`World::prepare`] moves the clipmap's levels ([`crate::clipmap`]) and bakes only the
//! strips they uncovered ([`World::encode_bake`]), selects the patches inside the view frustum,
//! writes the frame's uniforms and records the compute passes of the methods shaded in
//! compute; [`World::render`] draws into the host's pass.

use glam::{DVec3, Mat4, Vec3, Vec4};

use super::landscape::{LandscapeBake, LevelTarget, Rect};
use super::light_queue::LightQueue;
use super::raster::{Patches, Raster};
use super::region::{crop, crop_exact, subtract};
use super::render::RenderUniforms;
use super::timing::{GpuTimer, Slot};
pub use super::uniforms::{LevelUniforms, WorldUniforms};
use super::visibility::{Visibility, WorldBindings};
use super::world_light::{LightBake, LightRect, LightUniforms};
pub use super::world_stats::{mib, WorldStats};
use super::{scoped, shader, Targets};
use crate::camera::View;
pub use crate::camera::WorldView;
use crate::clipmap::{Clipmap, Eye, Patch, MAX_LEVELS, PATCHES};
use crate::error::{Error, Result};
use crate::landscape::Landscape;
use crate::method::{Method, MethodConfig};
use crate::params::{Shading, TerrainParams};
use crate::sky::SkyLight;
pub use crate::world::WorldParams;

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
        * (super::texel_bytes(super::landscape::LandscapeBake::LEVEL_FORMAT)
            + super::texel_bytes(LightBake::FORMAT))
}

/// The endless world on the host's device: see the module docs.
pub struct World {
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
    sky: super::sky::SkyPass,
    render_uniforms: wgpu::Buffer,
    world_uniforms: wgpu::Buffer,
    indices: wgpu::Buffer,
    /// Indices of a whole patch, then of a sub-patch ([`Clipmap::trim`]), in `indices`.
    index_counts: [u32; 2],
    instances: wgpu::Buffer,
    /// Whole patches, then sub-patches, in `instances`.
    instance_counts: [u32; 2],
    /// The whole patches the compute raster draws by the end of each depth pass but the last
    /// ([`super::raster::pass_ends`]).
    raster_passes: [u32; super::raster::PASSES - 1],
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
        Self::build(device, targets, params, None)
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
            let module = shader::module(device, "relief:world:shader", &shader::source("world"));
            // Compute too: the visibility method's compute raster places the same vertices.
            let vf = wgpu::ShaderStages::VERTEX_FRAGMENT | wgpu::ShaderStages::COMPUTE;
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
                ],
            });
            let pipeline = mesh_pipeline(device, (&layout, &module), &targets, tile.is_some());
            let render_uniforms =
                super::uniform_buffer::<RenderUniforms>(device, "relief:world:render-uniforms");
            let world_uniforms =
                super::uniform_buffer::<WorldUniforms>(device, "relief:world:world-uniforms");
            let tile_textures = TileTextures::new(device, &super::Textures::new(device, 1));
            let bind_group = bind(
                device,
                &layout,
                (&render_uniforms, &world_uniforms),
                (&texture, &light.texture),
                &tile_textures,
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
                bind_group,
                sky: super::sky::SkyPass::new(device, &targets, &render_uniforms),
                render_uniforms,
                world_uniforms,
                indices,
                index_counts,
                instances,
                instance_counts: [0; 2],
                raster_passes: [0; super::raster::PASSES - 1],
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
                vis_samples: super::visibility::SAMPLES,
                vis_raster: Raster::Hardware,
                target_size: None,
                vis_size: (0, 0),
                raises: Vec::new(),
            }
        })
    }

    /// Draws into `targets` from now on (the host's pass changed its formats or MSAA
    /// samples): rebuilds what draws into the host's pass (the mesh's and the sky's pipelines,
    /// the visibility method's composite); nothing is re-baked.
    pub fn set_targets(&mut self, device: &wgpu::Device, targets: Targets) -> Result<()> {
        targets.validate()?;
        if targets == self.targets {
            return Ok(());
        }
        let tile = self.tile.is_some();
        let (pipeline, sky) = scoped(device, || {
            let pipeline = mesh_pipeline(device, (&self.layout, &self.module), &targets, tile);
            let sky = super::sky::SkyPass::new(device, &targets, &self.render_uniforms);
            (pipeline, sky)
        })?;
        self.pipeline = pipeline;
        self.sky = sky;
        self.targets = targets;
        // The visibility method's composite draws into the host's pass: built again for these.
        self.visibility = None;
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
                let (samples, raster) = (config.samples, config.raster);
                let hybrid = method == Method::Hybrid;
                let built = self
                    .visibility
                    .as_ref()
                    .map(|v| (v.samples(), v.hybrid(), v.raster()));
                if built != Some((samples, hybrid, raster)) {
                    let vis = scoped(device, || {
                        Visibility::new(
                            device,
                            (&self.module, &self.layout),
                            &self.targets,
                            (self.tile.is_none(), samples, hybrid, raster),
                        )
                    })?;
                    self.visibility = Some(vis);
                }
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
        self.method = method;
        self.vis_samples = config.samples;
        self.vis_raster = config.raster;
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

    /// GPU memory of the visibility method's own images for the last frame's size, bytes (0
    /// for the forward mesh).
    pub fn method_bytes(&self) -> u64 {
        match (&self.visibility, self.method) {
            (Some(v), Method::Visibility | Method::Hybrid) => v.bytes(self.vis_size),
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
    /// channel packed in 64 bits: [`super::landscape::unpack_level_texel`]), toroidally
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
        self.tile = Some(tile);
        if floor_moved && params.land == self.params.land {
            self.errors = level_errors(&params.land, Some(tile.finest_log2));
            self.params = params;
            return self.relayout(device, self.map_k);
        }
        self.apply(device, params)
    }

    /// Binds the tile's textures (after they were made, or made again at a new size).
    pub(crate) fn set_tile_textures(&mut self, device: &wgpu::Device, textures: &super::Textures) {
        self.tile_textures = TileTextures::new(device, textures);
        if let Some(v) = &mut self.visibility {
            v.unbind();
        }
        self.bind_group = bind(
            device,
            &self.layout,
            (&self.render_uniforms, &self.world_uniforms),
            (&self.texture, &self.light.texture),
            &self.tile_textures,
        );
    }

    fn apply(&mut self, device: &wgpu::Device, params: WorldParams) -> Result<()> {
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
        self.params = params;
        if relayout {
            self.relayout(device, self.map_k)?;
        }
        Ok(())
    }

    fn relayout(&mut self, device: &wgpu::Device, k: f64) -> Result<()> {
        let morphing = self.map.morphing;
        let map = layout(&self.params, &self.errors, k);
        let (texture, target, light) = scoped(device, || {
            let (texture, target) = level_texture(device, &self.bake, &map);
            let light = LevelLight::new(device, &self.light_bake, &texture, &map);
            (texture, target, light)
        })?;
        if map.patch != self.map.patch {
            (self.indices, self.index_counts) = patch_indices(device, &map);
        }
        self.bind_group = bind(
            device,
            &self.layout,
            (&self.render_uniforms, &self.world_uniforms),
            (&texture, &light.texture),
            &self.tile_textures,
        );
        self.light = light;
        self.texture = texture;
        self.bake_target = target;
        self.map = map;
        self.map.morphing = morphing;
        self.map_k = k;
        Ok(())
    }

    fn eye(&self, view: &WorldView) -> Eye {
        Eye {
            position: view.eye.to_array(),
            ground: self.params.land.height_at(view.eye.x, view.eye.z),
            pixels_per_radian: view.pixels_per_radian(),
        }
    }

    /// Most texels one [`World::encode_bake`] bakes ([`DEFAULT_BAKE_BUDGET`] to start).
    pub fn bake_budget(&self) -> u64 {
        self.bake_budget
    }

    /// Sets the per-frame bake budget in texels (at least one row of a strip, and whatever the
    /// coarsest level needs to be drawn, are always baked;
    /// `u64::MAX` bakes everything at once, as the headless renderer does for a still frame).
    pub fn set_bake_budget(&mut self, texels: u64) {
        self.bake_budget = texels.max(1);
    }

    /// Most texels one [`World::encode_bake`] lights ([`DEFAULT_LIGHT_BUDGET`] to start).
    pub fn light_budget(&self) -> u64 {
        self.light_budget
    }

    /// Sets the per-frame light budget in texels (at least one row of a level is lit a frame,
    /// so the light always moves on); `u64::MAX` lights everything at once, as the headless
    /// renderer does for a still frame.
    pub fn set_light_budget(&mut self, texels: u64) {
        self.light_budget = texels.max(1);
    }

    /// The reference ray cast's slope bounds for this world's landscape, measured once
    /// ([`Landscape::slope_bounds`]): what a host casting rays every frame passes to
    /// [`super::world_rays::WorldRayUniforms::with_slopes`].
    pub fn slope_bounds(&self) -> &[f64] {
        &self.slopes
    }

    /// Texels still to bake: heights uncovered but not baked yet (a level with some is not
    /// drawn: the next coarser level covers it) and light not baked yet ([`World::light_pending`]:
    /// a level without is drawn with a coarser level's light). Later frames bake them, within
    /// the per-frame budgets; a host keeps drawing frames while this is over 0.
    pub fn pending_texels(&self) -> u64 {
        self.heights_pending() + self.light_pending()
    }

    /// Texels whose heights are uncovered but not baked yet.
    fn heights_pending(&self) -> u64 {
        let region: u64 = self
            .region_pending
            .iter()
            .map(|r| u64::from(r.extent[0]) * u64::from(r.extent[1]))
            .sum();
        self.map.pending_texels() + region
    }

    /// Texels of the active levels still to be lit (missing their light, or lit for an earlier
    /// sun): 0 where nothing reads the light.
    pub fn light_pending(&self) -> u64 {
        if self.tile.is_some()
            || (self.params.no_shadows && self.params.palette == crate::palette::Palette::Blog)
        {
            return 0;
        }
        self.light.queue.pending_texels(&self.map)
    }

    /// Texels the levels hold baked for their current layout: every active level's window (cut
    /// to the tile's square) less what still waits. For a still frame baked whole this is its
    /// whole bake, the same whatever the method or an earlier frame baked (`relief render
    /// --stats` prints it as `texels_baked`).
    pub fn held_texels(&self) -> u64 {
        let side = self.map.side();
        let bounds = self.tile.map(|t| t.region);
        let held: u64 = self
            .map
            .levels
            .iter()
            .filter(|l| l.active)
            .filter_map(|level| {
                let window = Rect {
                    layer: level.layer,
                    level_log2: level.spacing_log2,
                    origin: level.origin,
                    extent: [side; 2],
                };
                match bounds {
                    Some(b) => crop(window, b),
                    None => Some(window),
                }
            })
            .map(|r| u64::from(r.extent[0]) * u64::from(r.extent[1]))
            .sum();
        held.saturating_sub(self.heights_pending())
    }

    /// Everything a frame needs before the host's render pass, recorded into the host's
    /// encoder: the bake of what `view` uncovered ([`World::encode_bake`]), the frame's
    /// uniforms, and for the methods shaded in compute (`visibility`, `hybrid`) their raster
    /// and shading passes. Then [`World::render`] draws into the host's pass, or
    /// [`World::present`] writes the frame without one. Returns the texels baked.
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
        let texels = self.encode_bake_timed(device, queue, encoder, view, timer)?;
        self.write_uniforms(queue, view);
        if matches!(self.method, Method::Visibility | Method::Hybrid) {
            self.encode_visibility(device, queue, encoder, view, timer)?;
        }
        Ok(texels)
    }

    /// Moves the levels to `view` and records the bake of whatever they uncovered (nothing if
    /// the camera stayed within its levels' snapping step), within the per-frame budget
    /// ([`World::set_bake_budget`]; what is over it waits for the next frames), into the host's
    /// encoder, and the light bake within its own budget. Records no frame work: a host that
    /// draws calls [`World::prepare`], which bakes too. A view whose pixels per radian differ
    /// much from the layout's re-lays out the levels first (new textures, everything
    /// re-baked). Returns the texels baked.
    pub fn encode_bake(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        view: &WorldView,
    ) -> Result<u64> {
        self.encode_bake_timed(device, queue, encoder, view, None)
    }

    /// [`World::encode_bake`], timing the bake pass (when there is one) into `timer`.
    pub fn encode_bake_timed(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        view: &WorldView,
        timer: Option<&GpuTimer>,
    ) -> Result<u64> {
        let k = view.pixels_per_radian();
        if !(k.is_finite() && k > 0.0 && view.eye.is_finite()) {
            return Err(Error::invalid(
                "view",
                format!("{:?}", view.eye),
                "a finite eye and field of view",
            ));
        }
        let reach = crate::clipmap::max_eye(&self.params.land);
        if view.eye.x.abs() > reach || view.eye.z.abs() > reach || view.eye.y.abs() > 1e9 {
            return Err(Error::invalid(
                "eye",
                format!("{:.0},{:.0},{:.0}", view.eye.x, view.eye.y, view.eye.z),
                format!(
                    "x and z within ±{reach:.0} m (2^30 of this world's finest samples), y within ±1e9 m"
                ),
            ));
        }
        if self.frame_prepared {
            // The first bake since a frame: the counts are the next frame's.
            self.frame_prepared = false;
            self.stats.texels_baked = 0;
            self.stats.light_texels = 0;
        }
        let patch = Clipmap::patch_for(&self.errors, self.params.pixel_error, k);
        if patch != self.map.patch {
            self.relayout(device, k)?;
        }
        let eye = self.eye(view);
        self.map.update(&eye, self.params.pixel_error);
        // Never a frame with nothing to draw: the coarsest level is baked whole at once.
        let coarsest = self.map.levels.len() - 1;
        let budget = self.bake_budget.max(self.map.pending_texels_of(coarsest));
        let strips = self.map.take(budget, super::landscape::MAX_RECTS);
        let bounds = self.tile.map(|t| t.region);
        let rects: Vec<Rect> = strips
            .iter()
            .map(|s| Rect {
                layer: self.map.levels[s.level].layer,
                level_log2: self.map.levels[s.level].spacing_log2,
                origin: s.origin,
                extent: s.extent,
            })
            .filter_map(|r| match bounds {
                Some(b) => crop(r, b),
                None => Some(r),
            })
            .collect();
        self.region_moved();
        let rects = self.with_region_pending(rects);
        if !rects.is_empty() {
            self.bake.encode(
                queue,
                encoder,
                &self.bake_target,
                &self.params.land,
                &rects,
                timer.map(|t| t.compute_writes(Slot::Bake)),
            );
        }
        self.encode_light(queue, encoder, &strips, timer);
        let texels = rects
            .iter()
            .map(|r| u64::from(r.extent[0]) * u64::from(r.extent[1]))
            .sum();
        self.stats.texels_baked += texels;
        self.stats.texels_pending = self.map.pending_texels();
        Ok(texels)
    }

    /// Records the visibility method's raster pass and compute shading of the last prepared
    /// frame.
    fn encode_visibility(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        view: &WorldView,
        timer: Option<&GpuTimer>,
    ) -> Result<()> {
        let size = self.target_size.unwrap_or(view.size);
        if let Some(words) = self
            .visibility
            .as_ref()
            .and_then(Visibility::raster_depth_words)
        {
            // Its depth buffer is bound whole: 4 bytes a pixel (8 with each pixel's triangle)
            // within the device's limit.
            let per_pixel = 4 * u64::from(words);
            let bytes = per_pixel * u64::from(size.0) * u64::from(size.1);
            let limit = device.limits().max_storage_buffer_binding_size;
            if bytes > limit {
                return Err(Error::invalid(
                    "image size for the compute raster",
                    format!("{}x{}", size.0, size.1),
                    format!(
                        "at most {} pixels on this device (its depth buffer, {per_pixel} bytes a \
                         pixel, is bound whole); --raster hardware draws larger",
                        limit / per_pixel
                    ),
                ));
            }
        }
        self.vis_size = size;
        let rays = if self.method == Method::Hybrid {
            // The region the levels draw (the clipmap's coarsest square around the eye), from
            // this world's layout: measuring it again each frame cost 100 ms of CPU.
            let region = self.map.drawn_region(view.eye.x, view.eye.z);
            let method = super::raymarch::RayMethod::Reference;
            Some(super::world_rays::WorldRayUniforms::with_slopes(
                &self.params,
                view,
                (method, size, region),
                &self.slopes,
            )?)
        } else {
            None
        };
        let Some(vis) = self.visibility.as_mut() else {
            return Ok(());
        };
        let bindings = WorldBindings {
            render: &self.render_uniforms,
            world: &self.world_uniforms,
            tile_terrain: &self.tile_textures.terrain,
            tile_normals: &self.tile_textures.normals,
            tile_sampler: &self.tile_textures.sampler,
            instances: &self.instances,
        };
        let draw = |pass: &mut wgpu::RenderPass<'_>| {
            pass.set_bind_group(0, &self.bind_group, &[]);
            draw_patches(
                pass,
                (&self.instances, self.instance_counts),
                (&self.indices, self.index_counts),
            );
        };
        let patches = Patches {
            group: &self.bind_group,
            counts: self.instance_counts,
            cells: [self.map.patch, self.map.sub_cells()],
            passes: self.raster_passes,
        };
        vis.encode(
            device,
            queue,
            encoder,
            &bindings,
            (self.matrix, size, self.shading.sky),
            (draw, &patches, rays.as_ref()),
            timer,
        );
        Ok(())
    }

    /// The tile's: where its square moved (the scroll) since the last bake, the parts of every
    /// level's window the new square reaches and the old one did not. Those texels were cut
    /// from earlier bakes ([`crop`]), so the square's moving uncovers them as the camera's
    /// moving uncovers a level's strips.
    /// They join the world's pending rectangles, baked as the per-pass slots allow.
    fn region_moved(&mut self) {
        let Some(tile) = self.tile else {
            return;
        };
        let old = self.baked_region.replace(tile.region);
        let Some(old) = old.filter(|o| *o != tile.region) else {
            return;
        };
        let side = self.map.side();
        for level in self.map.levels.iter().filter(|l| l.active) {
            let window = Rect {
                layer: level.layer,
                level_log2: level.spacing_log2,
                origin: level.origin,
                extent: [side; 2],
            };
            if let Some(new) = crop(window, tile.region) {
                self.region_pending.extend(subtract(new, crop(window, old)));
            }
        }
    }

    /// `rects` and as many of the square's pending rectangles as one pass's slots still hold,
    /// each cut to its level's window now (a level may have moved since: what left the window
    /// is not its to bake any more).
    fn with_region_pending(&mut self, mut rects: Vec<Rect>) -> Vec<Rect> {
        let side = f64::from(self.map.side());
        while rects.len() < super::landscape::MAX_RECTS {
            let Some(r) = self.region_pending.pop() else {
                break;
            };
            let Some(level) = self
                .map
                .levels
                .iter()
                .find(|l| l.active && l.layer == r.layer)
            else {
                continue;
            };
            let s = 2f64.powi(level.spacing_log2);
            let (x, z) = (f64::from(level.origin[0]), f64::from(level.origin[1]));
            let window = [x * s, z * s, (x + side - 1.0) * s, (z + side - 1.0) * s];
            if let Some(kept) = crop_exact(r, window) {
                rects.push(kept);
            }
        }
        rects
    }

    /// Records the light bake after the levels' bake, within the per-frame light budget
    /// ([`World::set_light_budget`]): the strips just baked join what the levels still need
    /// lit (every level whole where the sun has turned or nothing was lit), and the frame
    /// lights what the budget allows, coarsest level first ([`LightQueue`]).
    fn encode_light(
        &mut self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        strips: &[crate::clipmap::Strip],
        timer: Option<&GpuTimer>,
    ) {
        let azimuth = self.params.sky.sun_azimuth;
        if self.tile.is_some()
            || (self.params.no_shadows && self.params.palette == crate::palette::Palette::Blog)
        {
            // Nothing reads the light: no shadows, and the blog palette's occlusion is by
            // height. Lit whole once something does.
            self.light.queue.forget();
            return;
        }
        let n = self.map.levels.len();
        let usable: Vec<bool> = (0..n)
            .map(|l| self.map.levels[l].active && self.map.pending_texels_of(l) == 0)
            .collect();
        self.light.queue.set_sun(azimuth);
        self.light.queue.heights_baked(strips);
        let rects: Vec<LightRect> = self
            .light
            .queue
            .take(
                &self.map,
                self.light_budget,
                super::world_light::MAX_LIGHT_RECTS,
                |l| usable[l],
            )
            .into_iter()
            .map(|s| LightRect {
                origin: s.origin,
                extent: s.extent,
                level: s.level as u32,
                _pad: [0; 3],
            })
            .collect();
        self.stats.light_texels += rects
            .iter()
            .map(|r| u64::from(r.extent[0]) * u64::from(r.extent[1]))
            .sum::<u64>();
        if rects.is_empty() {
            return;
        }
        // One pass: its uniforms are written once for the submission (`take` keeps to the
        // pass's rectangle slots).
        let uniforms = LightUniforms::new(&self.map, azimuth, &self.params.land, |l| usable[l]);
        self.light_bake.encode(
            queue,
            encoder,
            &self.light.bind_group,
            &uniforms,
            &rects,
            timer.map(|t| t.compute_writes(Slot::Light)),
        );
    }

    /// Selects the patches inside `view`'s frustum and writes the frame's uniforms.
    fn write_uniforms(&mut self, queue: &wgpu::Queue, view: &WorldView) {
        let s0 = 2f64.powi(self.map.finest_log2);
        let reference = [(view.eye.x / s0).floor(), (view.eye.z / s0).floor()];
        self.reference = [reference[0] as i64, reference[1] as i64];
        let eye_frac = [
            view.eye.x - reference[0] * s0,
            view.eye.z - reference[1] * s0,
        ];
        let land = &self.params.land;
        let altitude = (view.eye.y - land.height_at(view.eye.x, view.eye.z)).max(0.0);
        let coarsest = self.map.levels.last().expect("a clipmap has levels");
        let far = (f64::from(self.map.cells()) * coarsest.spacing()) as f32;
        let near = (altitude as f32 * 0.1).clamp(0.05, 20.0);
        let matrix = view.relative_matrix(near, far);
        self.matrix = matrix;
        let planes = frustum_planes(&matrix);
        let eye = view.eye;
        let bounds = self.tile.map_or(
            [
                f64::NEG_INFINITY,
                f64::NEG_INFINITY,
                f64::INFINITY,
                f64::INFINITY,
            ],
            |t| t.region,
        );
        let patches = self.map.patches([0.0, land.peak_height], |lo, hi| {
            if hi[0] < bounds[0] || hi[2] < bounds[1] || lo[0] > bounds[2] || lo[2] > bounds[3] {
                return false;
            }
            let lo = (DVec3::from(lo) - eye).as_vec3();
            let hi = (DVec3::from(hi) - eye).as_vec3();
            planes.iter().all(|p| {
                let v = Vec3::new(
                    if p.x >= 0.0 { hi.x } else { lo.x },
                    if p.y >= 0.0 { hi.y } else { lo.y },
                    if p.z >= 0.0 { hi.z } else { lo.z },
                );
                p.truncate().dot(v) + p.w >= 0.0
            })
        });
        // The tile's edge crosses patches: only their sub-patches inside it are drawn (or, in
        // the unlikely case that they overflow the buffer, the crossed patches whole).
        let (whole, subs) = match self.tile {
            Some(t) => Some(self.map.trim(&patches, t.region))
                .filter(|(w, s)| w.len() + s.len() <= instance_capacity(true))
                .unwrap_or((patches, Vec::new())),
            None => (patches, Vec::new()),
        };
        queue.write_buffer(&self.instances, 0, bytemuck::cast_slice(&whole));
        let at = std::mem::size_of_val(whole.as_slice()) as u64;
        queue.write_buffer(&self.instances, at, bytemuck::cast_slice(&subs));
        self.instance_counts = [whole.len() as u32, subs.len() as u32];
        self.raster_passes = super::raster::pass_ends(whole.iter().map(|p| p.level));

        let first = self.map.first_drawn();
        let mut levels = [LevelUniforms::default(); MAX_LEVELS];
        let side = i64::from(self.map.side());
        let n = self.map.levels.len();
        for (l, level) in self.map.levels.iter().enumerate() {
            let shift = level.spacing_log2 - self.map.finest_log2;
            let coarse = (l + 1 < n).then(|| self.map.levels[l + 1]);
            let origin = [i64::from(level.origin[0]), i64::from(level.origin[1])];
            levels[l] = LevelUniforms {
                origin_rel: [
                    ((origin[0] << shift) - self.reference[0]) as i32,
                    ((origin[1] << shift) - self.reference[1]) as i32,
                ],
                // Inactive levels keep a stale origin: wrapping, never used.
                delta: coarse.map_or([0; 2], |c| {
                    [
                        level.origin[0].wrapping_sub(c.origin[0].wrapping_mul(2)),
                        level.origin[1].wrapping_sub(c.origin[1].wrapping_mul(2)),
                    ]
                }),
                origin_mod: [
                    origin[0].rem_euclid(side) as u32,
                    origin[1].rem_euclid(side) as u32,
                ],
                shift: shift as u32,
                layer: level.layer,
                coarse: if coarse.is_some() {
                    l as u32 + 1
                } else {
                    l as u32
                },
                has_coarse: u32::from(coarse.is_some_and(|c| c.active)),
                eye_local: [
                    (view.eye.x / level.spacing() - f64::from(level.origin[0])) as f32,
                    (view.eye.z / level.spacing() - f64::from(level.origin[1])) as f32,
                ],
                clip: {
                    let local = |v: f64, o: i32| {
                        (v / level.spacing() - f64::from(o)).clamp(-1e9, 1e9) as f32
                    };
                    [
                        local(bounds[0], level.origin[0]),
                        local(bounds[1], level.origin[1]),
                        local(bounds[2], level.origin[0]),
                        local(bounds[3], level.origin[1]),
                    ]
                },
                raise: self.level_raise(level.spacing_log2) as f32,
                light_from: if self.tile.is_some() {
                    l as u32
                } else {
                    self.light.queue.light_from(&self.map, l)
                },
                _pad: [0; 2],
            };
        }
        let world = WorldUniforms {
            eye: [
                eye_frac[0] as f32,
                view.eye.y as f32,
                eye_frac[1] as f32,
                s0 as f32,
            ],
            cells: self.map.cells(),
            patch_cells: self.map.patch,
            side: self.map.side(),
            morphing: u32::from(self.map.morphing),
            morph: self.map.morph.map(|m| m as f32),
            peak: land.peak_height as f32,
            // A first level drawn coarser than the first active (finer ones wait on a bake) is
            // not faded.
            fade: if self.map.levels.get(first).is_some_and(|l| l.active)
                && (first == 0 || !self.map.levels[first - 1].active)
            {
                self.map.fade as f32
            } else {
                0.0
            },
            first: first as u32,
            tile_eye: self.tile.map_or([0.0; 2], |t| {
                [(eye.x - t.region[0]) as f32, (eye.z - t.region[1]) as f32]
            }),
            tile_inv: self
                .tile
                .map_or(0.0, |t| (1.0 / (t.region[2] - t.region[0])) as f32),
            levels,
        };
        queue.write_buffer(&self.world_uniforms, 0, bytemuck::bytes_of(&world));

        let encode = !self.targets.color_format.is_srgb();
        let region = self.map.drawn_region(eye.x, eye.z);
        let uniforms = match self.tile {
            // The tile: the shading's own sun and sky, clear air, no water.
            Some(t) => tile_uniforms(&self.params, &self.shading, matrix, encode, &t),
            None => {
                let now = WorldParams {
                    clock: self.clock(),
                    ..self.params
                };
                render_uniforms(&now, &self.shading, (matrix, region, eye), encode)
            }
        };
        queue.write_buffer(&self.render_uniforms, 0, bytemuck::bytes_of(&uniforms));

        let active: Vec<_> = self.map.levels[first.min(n)..]
            .iter()
            .filter(|l| l.active)
            .collect();
        let cells = |n: usize, side: u32| n as u64 * u64::from(side).pow(2);
        self.stats = WorldStats {
            triangles: 2
                * (cells(whole.len(), self.map.patch) + cells(subs.len(), self.map.sub_cells())),
            patches: (whole.len() + subs.len()) as u32,
            texels_baked: self.stats.texels_baked,
            levels: active.len() as u32,
            levels_total: n as u32,
            patch_cells: self.map.patch,
            finest_spacing: active.first().map_or(0.0, |l| l.spacing()),
            error_bound_px: self.map.error_bound(view.pixels_per_radian()),
            texels_pending: self.map.pending_texels(),
            light_texels: self.stats.light_texels,
            light_pending: self.light_pending(),
            level_bytes: level_bytes(&self.map),
        };
        self.frame_prepared = true;
    }

    /// The camera-relative projection times view of the last [`World::prepare`] (positions
    /// relative to the eye): what turns its depth buffer back into positions.
    pub fn relative_matrix(&self) -> Mat4 {
        self.matrix
    }

    /// Writes the frame that [`World::prepare`] shaded in compute straight into `target`,
    /// with no render pass, for a host whose frame the world fills: `target` is then all the
    /// frame needs (no depth is written). On a compute chip such as the H100 a full-screen draw
    /// in a render pass costs more than the shading itself (docs/bench/present in git history,
    /// up to a57006a).
    ///
    /// Returns true, having recorded the frame's present (timed as [`Slot::Present`]), where
    /// the method shades in compute (the visibility method and the hybrid), the sky is on
    /// (every pixel opaque) and `target` is a single-sampled 2D texture of the frame's size
    /// that is either RGBA8 (not sRGB) with `STORAGE_BINDING`, which one compute pass stores
    /// the frame into (the fastest: `relief render`'s image is such a texture, drawn by render
    /// passes through an sRGB view of it), or RGBA8 or BGRA8 (sRGB or not) with `COPY_DST`,
    /// which a compute pass packs the frame for and a copy fills. Both round each value in the
    /// shader; the stored one is the packed one wherever the device's 8-bit store rounds to
    /// the nearest, down or toward zero (lavapipe's and the H100's do).
    /// Otherwise it records nothing and returns false: draw with [`World::render`] in a render
    /// pass.
    pub fn present(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        target: &wgpu::Texture,
        timer: Option<&GpuTimer>,
    ) -> bool {
        match (self.method, &self.visibility) {
            (Method::Visibility | Method::Hybrid, Some(vis)) => vis.present(encoder, target, timer),
            _ => false,
        }
    }

    /// Draws the patches selected by the last [`World::prepare`], and the sky behind them
    /// unless [`Shading::sky`] is off, into the host's pass (whose depth, if any, is cleared to
    /// 1.0).
    ///
    /// With the visibility method ([`World::set_method`]) it composites the image that
    /// [`World::prepare`] shaded, colour and depth.
    pub fn render(&self, pass: &mut wgpu::RenderPass<'_>) {
        if let (Method::Visibility | Method::Hybrid, Some(vis)) = (self.method, &self.visibility) {
            // Its compute pass shaded the sky too: one full-screen draw.
            vis.composite(pass);
            return;
        }
        self.sky.around(pass, self.shading.sky, |pass| {
            let [whole, subs] = self.instance_counts;
            if whole + subs == 0 {
                return;
            }
            pass.push_debug_group("relief:world");
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &self.bind_group, &[]);
            draw_patches(
                pass,
                (&self.instances, self.instance_counts),
                (&self.indices, self.index_counts),
            );
            pass.pop_debug_group();
        });
    }
}

/// Draws the patches of `instances` (whole ones, then sub-patches) with the pipeline and bind
/// group already set.
fn draw_patches(
    pass: &mut wgpu::RenderPass<'_>,
    (instances, [whole, subs]): (&wgpu::Buffer, [u32; 2]),
    (indices, [patch, sub]): (&wgpu::Buffer, [u32; 2]),
) {
    pass.set_vertex_buffer(0, instances.slice(..));
    pass.set_index_buffer(indices.slice(..), wgpu::IndexFormat::Uint32);
    if whole > 0 {
        pass.draw_indexed(0..patch, 0, 0..whole);
    }
    if subs > 0 {
        pass.draw_indexed(patch..patch + sub, 0, whole..whole + subs);
    }
}

/// How far the drawn square `region` ([`Clipmap::drawn_region`]) reaches from `eye` in every
/// direction: the terrain fades into the sky before this distance (where fog is on).
pub fn horizon(region: [f64; 4], eye: DVec3) -> f64 {
    (eye.x - region[0])
        .min(region[2] - eye.x)
        .min(eye.z - region[1])
        .min(region[3] - eye.z)
        .max(0.0)
}

/// Where terrain begins fading into the sky, as a fraction of [`horizon`].
pub const FADE_START: f64 = 0.7;

/// The shading uniforms of the endless world for a camera-relative `matrix` (the camera at the
/// origin), the square drawn (`region`, [`Clipmap::drawn_region`]) and the `eye`, shared by the
/// mesh and the ray casters: the sun and sky of `params.sky`, its fog and (with fog) the fade
/// into the sky before the [`horizon`], and the water.
pub fn render_uniforms(
    params: &WorldParams,
    shading: &Shading,
    (matrix, region, eye): (Mat4, [f64; 4], DVec3),
    encode_srgb: bool,
) -> RenderUniforms {
    let horizon = horizon(region, eye);
    let mut u = base_uniforms(params, shading, matrix, encode_srgb, 0);
    let sun = glam::Vec4::from(u.sun_color).truncate().to_array();
    let light = SkyLight::new(params.sky.sun_direction(), sun);
    u.set_sky(shading, &light);
    u.ambient_color = u.ambient_color.map(|c| c * light.day);
    u.ambient_color[3] = 1.0;
    // The world casts shadows (its callers pass the horizon) in its palette.
    u.look[0] = if params.no_shadows { 0.0 } else { 1.0 };
    u.look[2] = params.palette.code();
    if params.sky.fog > 0.0 {
        let e = params.sky.extinction();
        u.fog = [e[0], e[1], e[2], 0.0];
        u.fade = [(FADE_START * horizon) as f32, horizon as f32, 0.0, 0.0];
    }
    if !params.no_water {
        let peak = params.land.peak_height;
        let period = f64::from(RIPPLE_PERIOD);
        // The clock and the wind's drift reduced in f64 before they become f32: the waves
        // repeat every CLOCK_PERIOD seconds and every RIPPLE_PERIOD metres.
        let drift = params.wind.velocity() * params.clock;
        u.water = [
            (f64::from(params.water_level) / peak) as f32,
            (f64::from(params.water_level) - eye.y) as f32,
            params.clock.rem_euclid(f64::from(CLOCK_PERIOD)) as f32,
            1.0,
        ];
        u.water_origin = [
            (eye.x - drift.x).rem_euclid(period) as f32,
            (eye.z - drift.y).rem_euclid(period) as f32,
            (SAND_BAND / peak) as f32,
            0.0,
        ];
    }
    u
}

/// The tile's uniforms: the [`Shading`]'s sun and sky (as the tile always had), the blog
/// palette's height occlusion, no shadows, fog or water.
fn tile_uniforms(
    params: &WorldParams,
    shading: &Shading,
    matrix: Mat4,
    encode_srgb: bool,
    setup: &TileSetup,
) -> RenderUniforms {
    let mut u = base_uniforms(params, shading, matrix, encode_srgb, setup.tex_size);
    u.look[2] = crate::palette::Palette::Blog.code();
    u.shift = setup.shift;
    u
}

/// What every world's uniforms start from: the shading's sun and sky, clear air, the heights
/// in metres, camera-relative `matrix`, and the tile's textures' side (0: none).
fn base_uniforms(
    params: &WorldParams,
    shading: &Shading,
    matrix: Mat4,
    encode_srgb: bool,
    tex_size: u32,
) -> RenderUniforms {
    let heights = TerrainParams {
        height_scale: params.land.peak_height as f32,
        snow_height: params.snow_height,
        ao_exponent: params.ao_exponent,
        ..TerrainParams::default()
    };
    let relative = View {
        view_proj: matrix,
        eye: Vec3::ZERO,
    };
    RenderUniforms {
        grid: 0,
        tex_size,
        ..RenderUniforms::new(&heights, shading, &relative, encode_srgb)
    }
}

/// Period in metres of the water's ripples (`RIPPLE_PERIOD` in `wgsl/shade.wgsl`).
pub const RIPPLE_PERIOD: f32 = 256.0;

/// Period in seconds of everything that moves on its own (`CLOCK_PERIOD` in
/// `wgsl/shade.wgsl`): the clock reaches the shaders reduced modulo it, and each wave repeats
/// within it (a whole number of cycles).
pub const CLOCK_PERIOD: f32 = 4096.0;
/// Height in metres of the sand along the shore (jittered by the colour noise).
pub const SAND_BAND: f64 = 12.0;

/// The hybrid method's raise for every level spacing a clipmap of `land` can have.
fn level_raises(land: &Landscape) -> Vec<(i32, f64)> {
    let finest = crate::clipmap::finest_log2(land);
    (0..MAX_LEVELS as i32)
        .map(|l| (finest + l, crate::clipmap::level_raise(land, finest + l)))
        .collect()
}

/// The levels' errors from the finest spacing `land` needs, or `floor` where that is coarser.
fn level_errors(land: &Landscape, floor: Option<i32>) -> Vec<(i32, f64)> {
    let finest = crate::clipmap::finest_log2(land).max(floor.unwrap_or(i32::MIN));
    (0..MAX_LEVELS as i32)
        .map(|l| (finest + l, crate::clipmap::level_error(land, finest + l)))
        .collect()
}

/// The pipeline that draws the levels' patches into the host's pass: `fs_tile` for the tile,
/// `fs_main` for the endless world.
fn mesh_pipeline(
    device: &wgpu::Device,
    (layout, module): (&wgpu::BindGroupLayout, &wgpu::ShaderModule),
    targets: &Targets,
    tile: bool,
) -> wgpu::RenderPipeline {
    super::terrain_pipeline(
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

fn layout(params: &WorldParams, errors: &[(i32, f64)], k: f64) -> Clipmap {
    Clipmap::with_errors(&params.land, errors, params.pixel_error, k)
}

fn level_texture(
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
fn level_array(
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
struct LevelLight {
    texture: wgpu::Texture,
    bind_group: wgpu::BindGroup,
    /// What the levels still need lit, and what each is drawn with until then.
    queue: LightQueue,
}

impl LevelLight {
    fn new(
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

fn array_entry(binding: u32, sample_type: wgpu::TextureSampleType) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::VERTEX_FRAGMENT | wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Texture {
            sample_type,
            view_dimension: wgpu::TextureViewDimension::D2Array,
            multisampled: false,
        },
        count: None,
    }
}

fn array_view(texture: &wgpu::Texture) -> wgpu::TextureView {
    texture.create_view(&wgpu::TextureViewDescriptor {
        label: Some("relief:world:levels-view"),
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        ..Default::default()
    })
}

fn bind(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    (render, world): (&wgpu::Buffer, &wgpu::Buffer),
    (texture, light): (&wgpu::Texture, &wgpu::Texture),
    tile: &TileTextures,
) -> wgpu::BindGroup {
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
        ],
    })
}

/// The tile's textures as the mesh reads them (1x1 stand-ins for the endless world).
struct TileTextures {
    terrain: wgpu::TextureView,
    normals: wgpu::TextureView,
    sampler: wgpu::Sampler,
}

impl TileTextures {
    fn new(device: &wgpu::Device, textures: &super::Textures) -> Self {
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
fn patch_indices(device: &wgpu::Device, map: &Clipmap) -> (wgpu::Buffer, [u32; 2]) {
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

/// The six planes (a x + b y + c z + d >= 0 inside) of a wgpu clip-space frustum (depth 0..1).
fn frustum_planes(m: &Mat4) -> [Vec4; 6] {
    let r = |i: usize| m.row(i);
    [
        r(3) + r(0),
        r(3) - r(0),
        r(3) + r(1),
        r(3) - r(1),
        r(2),
        r(3) - r(2),
    ]
}
