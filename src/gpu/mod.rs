//! The GPU core: [`Terrain`], a middleware that bakes into its own textures and draws into the
//! host's render pass. One file per pass; this file holds what they share.

pub mod air_shadow;
pub(crate) mod bake;
pub mod blit;
pub mod blog;
pub mod grass;
#[cfg(not(target_arch = "wasm32"))]
pub(crate) mod grass_reference;
#[cfg(not(target_arch = "wasm32"))]
pub mod headless;
pub mod landscape;
pub mod layer;
mod light_queue;
pub(crate) mod normals;
pub mod props;
pub(crate) mod props_map;
pub(crate) mod props_overlay;
#[cfg(not(target_arch = "wasm32"))]
pub(crate) mod props_reference;
mod props_wgsl;
pub mod raster;
#[cfg(not(target_arch = "wasm32"))]
pub(crate) mod ray_layers;
pub mod raymarch;
mod region;
pub(crate) mod render;
pub(crate) mod shader;
pub(crate) mod sky;
pub(crate) mod temporal;
pub mod test_box;
pub mod timing;
mod uniforms;
mod util;
pub mod visibility;
#[cfg(test)]
pub(crate) mod wgsl_tests;
pub mod world;
pub(crate) mod world_light;
pub mod world_rays;
pub(crate) mod world_stats;

/// MSAA samples of the target `relief render` and the window draw the mesh into.
pub const RENDER_SAMPLES: u32 = 4;

/// The MSAA samples of the target `relief render`, the benchmarks and the window draw `method`
/// into: the visibility method and the hybrid anti-alias in their own compute pass, so the
/// host's pass they composite into needs none (on an H100 a 4x target costs that full-screen
/// draw some 1.8 ms at 1080p).
pub fn render_samples(method: crate::Method) -> u32 {
    if matches!(method, crate::Method::Visibility | crate::Method::Hybrid) {
        1
    } else {
        RENDER_SAMPLES
    }
}

pub use render::RenderUniforms;
pub use util::clear_color;
pub(crate) use util::{
    array_texture_entry, blended_pipeline, compute_pipeline, dispatch_square, fullscreen_pipeline,
    render_pipeline, slot_buffer, storage_buffer_entry, storage_entry, terrain_pipeline,
    texel_bytes, texture_2d, texture_entry, uniform_buffer, uniform_entry, write_slots,
};

use crate::camera::View;
use crate::error::{Error, Result};
use crate::params::{Dirty, Shading, TerrainParams};
use timing::{GpuTimer, Slot};

/// Compute workgroup side (8 x 8 invocations): matches `@workgroup_size` in the WGSL.
pub(crate) const WORKGROUP: u32 = 8;

/// What the host renders into: relief builds its pipeline for exactly these.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Targets {
    /// The colour attachment's format. sRGB formats get linear output; others are encoded.
    pub color_format: wgpu::TextureFormat,
    /// The depth attachment's format, if the host's pass has one (relief depth-tests and
    /// writes it, so host geometry and terrain occlude each other).
    pub depth_format: Option<wgpu::TextureFormat>,
    /// MSAA sample count of the pass (1 or 4 on WebGPU).
    pub sample_count: u32,
}

impl Targets {
    fn validate(&self) -> Result<()> {
        if !matches!(self.sample_count, 1 | 4) {
            return Err(Error::invalid("sample_count", self.sample_count, "1 or 4"));
        }
        if let Some(d) = self.depth_format {
            if !d.is_depth_stencil_format() || !d.has_depth_aspect() {
                return Err(Error::invalid(
                    "depth_format",
                    format!("{d:?}"),
                    "a format with a depth aspect",
                ));
            }
        }
        if self.color_format.is_depth_stencil_format() {
            return Err(Error::invalid(
                "color_format",
                format!("{:?}", self.color_format),
                "a colour format",
            ));
        }
        Ok(())
    }
}

/// The baked textures. Rebuilt whole when the texture size changes.
pub struct Textures {
    /// `rg32float`: r = normalised height in [0, 1], g = colour channel in [0, 1].
    pub terrain: wgpu::Texture,
    /// `rgba16float`: xyz = unit normal (y up), w = 0.
    pub normals: wgpu::Texture,
    pub(crate) terrain_view: wgpu::TextureView,
    pub(crate) normal_view: wgpu::TextureView,
}

impl Textures {
    /// GPU memory of both textures at `size` x `size`, bytes.
    pub fn bytes(size: u32) -> u64 {
        u64::from(size).pow(2)
            * (texel_bytes(Self::TERRAIN_FORMAT) + texel_bytes(Self::NORMAL_FORMAT))
    }

    /// Heights need 32-bit precision; rg32float is a core WebGPU storage format (write-only)
    /// and is read with textureLoad, so float32-filterable is never needed.
    pub const TERRAIN_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rg32Float;
    /// Signed normals in a float format: nothing negative is lost, and it is filterable.
    pub const NORMAL_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

    fn new(device: &wgpu::Device, size: u32) -> Self {
        let usage = wgpu::TextureUsages::STORAGE_BINDING
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC;
        let make = |label, format| texture_2d(device, label, (size, size), format, usage);
        let terrain = make("relief:bake:terrain", Self::TERRAIN_FORMAT);
        let normals = make("relief:normals:normal-map", Self::NORMAL_FORMAT);
        Self {
            terrain_view: terrain.create_view(&Default::default()),
            normal_view: normals.create_view(&Default::default()),
            terrain,
            normals,
        }
    }
}

/// relief's terrain as middleware: give it the host's device, queue and target formats; record
/// each frame's bakes, uniforms and compute passes into the host's encoder
/// ([`Terrain::prepare`]) and draw into the host's render pass ([`Terrain::render`]).
/// It never creates a surface, submits or presents.
///
/// The seed blog's tile. Its mesh is drawn by the clipmap renderer of the endless world
/// ([`world::World`]) on the tile's periodic landscape (`src/tile.rs`), bounded to the tile's
/// square: levels of detail from the screen-space error, never finer than the `grid`. The
/// tile's own textures (`size` texels a side: heights, colour channel, normals) are baked beside
/// it for [`Terrain::textures`], `relief bake` and the ray-march methods.
pub struct Terrain {
    params: TerrainParams,
    targets: Targets,
    textures: Textures,
    bake: bake::BakePass,
    normals: normals::NormalPass,
    /// The mesh: the clipmap renderer on the tile's landscape.
    world: world::World,
    pending: Dirty,
    /// The offset shown: `params.offset` (where the textures were baked) moved by
    /// [`Terrain::scroll_to`].
    shown_offset: [f64; 2],
    /// The target's size in pixels (the screen-error bound's pixels).
    viewport: (u32, u32),
}

/// The target size a [`Terrain`] lays its levels out for until [`Terrain::set_viewport`].
pub const DEFAULT_VIEWPORT: (u32, u32) = (1920, 1080);

/// The endless world's parameters and tile setup that draw `params` scrolled to `offset`.
fn tile_world(
    params: &TerrainParams,
    offset: [f64; 2],
) -> (crate::world::WorldParams, world::TileSetup) {
    // Reduced in f64: offsets may be far from the origin (up to 10^12 tiles).
    let shown = TerrainParams { offset, ..*params }.reduced_offset();
    let baked = params.reduced_offset();
    let shift = [0, 1].map(|i| (shown[i] - baked[i]).rem_euclid(1.0) as f32);
    let frame = crate::tile::TileFrame::new(params, offset);
    let world = crate::world::WorldParams {
        land: frame.land,
        pixel_error: 1.0,
        snow_height: params.snow_height,
        ao_exponent: params.ao_exponent,
        sky: crate::sky::Sky {
            fog: 0.0,
            ..Default::default()
        },
        water_level: 0.0,
        no_water: true,
        palette: crate::palette::Palette::Blog,
        no_shadows: true,
        clock: 0.0,
        wind: crate::world::Wind::default(),
        // The tile grows no grass and has no props or clouds.
        grass: crate::grass::Grass::default(),
        props: crate::props::Props::default(),
        clouds: crate::world::clouds::Clouds::default(),
    };
    let setup = world::TileSetup {
        region: frame.region(),
        finest_log2: frame.grid_spacing_log2(params.grid),
        tex_size: params.size,
        shift,
    };
    (world, setup)
}

impl Terrain {
    /// Builds pipelines and textures for `params`; the first [`Terrain::encode_bake`] bakes.
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        targets: Targets,
        params: TerrainParams,
    ) -> Result<Self> {
        targets.validate()?;
        params.validate_for(&device.limits())?;
        let (wp, setup) = tile_world(&params, params.offset);
        let mut world = world::World::new_tile(device, targets, wp, setup)?;
        // The tile is small and its bakes are cut to it: a change is baked whole in one frame,
        // as the tile's textures always were (no frame shows it half-baked).
        world.set_bake_budget(u64::MAX);
        let mut terrain = scoped(device, || {
            let textures = Textures::new(device, params.size);
            Terrain {
                params,
                targets,
                bake: bake::BakePass::new(device),
                normals: normals::NormalPass::new(device),
                world,
                textures,
                pending: Dirty::ALL,
                shown_offset: params.offset,
                viewport: DEFAULT_VIEWPORT,
            }
        })
        .map_err(|e| size_too_big(params.size, e))?;
        terrain.bind(device);
        terrain.world.set_tile_textures(device, &terrain.textures);
        terrain.bake.write(queue, &terrain.params);
        terrain.normals.write(queue, &terrain.params);
        Ok(terrain)
    }

    fn bind(&mut self, device: &wgpu::Device) {
        self.bake.bind(device, &self.textures);
        self.normals.bind(device, &self.textures);
    }

    /// The current parameters.
    pub fn params(&self) -> &TerrainParams {
        &self.params
    }

    /// The formats this terrain draws into.
    pub fn targets(&self) -> &Targets {
        &self.targets
    }

    /// Draws into `targets` from now on (see [`world::World::set_targets`]); nothing is
    /// re-baked.
    pub fn set_targets(&mut self, device: &wgpu::Device, targets: Targets) -> Result<()> {
        targets.validate()?;
        let set = self.world.set_targets(device, targets);
        // Whatever the world draws into now, even where rebuilding its method failed.
        self.targets = *self.world.targets();
        set
    }

    /// The current shading.
    pub fn shading(&self) -> &Shading {
        self.world.shading()
    }

    /// Replaces the shading (lights and colours); nothing is re-baked.
    pub fn set_shading(&mut self, shading: Shading) {
        self.world.set_shading(shading);
    }

    /// The size in pixels of the target drawn into: the pixels of the mesh's screen-error
    /// bound ([`DEFAULT_VIEWPORT`] until told).
    pub fn set_viewport(&mut self, size: (u32, u32)) {
        self.viewport = (size.0.max(1), size.1.max(1));
    }

    /// The size of the target drawn into ([`Terrain::set_viewport`]).
    pub fn viewport(&self) -> (u32, u32) {
        self.viewport
    }

    /// How the mesh is drawn: [`crate::Method::Mesh`] (forward shading, the default) or
    /// [`crate::Method::Visibility`] (shaded per MSAA sample in compute, composited into the
    /// host's pass: [`visibility`]); see [`world::World::set_method`]. With the visibility
    /// method [`Terrain::prepare`] records the frame's raster and shading passes, so call
    /// it every frame before the host's pass, with the view drawn; its images are made at the
    /// viewport's size ([`Terrain::set_viewport`]), which must be the host target's.
    /// `config` is a [`crate::MethodConfig`] or a bare [`crate::Method`].
    pub fn set_method(
        &mut self,
        device: &wgpu::Device,
        config: impl Into<crate::MethodConfig>,
    ) -> Result<()> {
        self.world.set_method(device, config)
    }

    /// How the mesh is drawn ([`Terrain::set_method`]).
    pub fn method(&self) -> crate::Method {
        self.world.method()
    }

    /// How frames are drawn: the method with its samples and raster ([`Terrain::set_method`]).
    pub fn method_config(&self) -> crate::MethodConfig {
        self.world.method_config()
    }

    /// Most texels of the mesh's levels one [`Terrain::encode_bake`] bakes (see
    /// [`world::World::set_bake_budget`]; everything, to start).
    pub fn bake_budget(&self) -> u64 {
        self.world.bake_budget()
    }

    /// Sets the per-frame bake budget of the mesh's levels, in texels (`u64::MAX`: whole).
    pub fn set_bake_budget(&mut self, texels: u64) {
        self.world.set_bake_budget(texels);
    }

    /// Texels of the mesh's levels uncovered but not baked yet.
    pub fn pending_texels(&self) -> u64 {
        self.world.pending_texels()
    }

    /// The renderer drawing the mesh: its [`world::World::stats`] are the mesh's.
    pub fn world(&self) -> &world::World {
        &self.world
    }

    /// Changes the parameters. Only what they invalidate is redone: a new size rebuilds the
    /// textures, a noise change re-bakes, a height-scale change re-runs only the normal pass,
    /// a shading-only change (snow, AO) bakes nothing. Returns what was invalidated.
    /// On error the terrain keeps its previous parameters.
    pub fn set_params(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        params: TerrainParams,
    ) -> Result<Dirty> {
        params.validate_for(&device.limits())?;
        let dirty = self.params.diff(&params);
        if dirty.resize {
            self.textures = scoped(device, || Textures::new(device, params.size))
                .map_err(|e| size_too_big(params.size, e))?;
            self.bind(device);
            self.world.set_tile_textures(device, &self.textures);
        }
        let (wp, setup) = tile_world(&params, params.offset);
        self.world.set_tile(device, wp, setup)?;
        self.params = params;
        self.shown_offset = params.offset;
        if dirty.bake {
            self.bake.write(queue, &self.params);
        }
        if dirty.normals {
            self.normals.write(queue, &self.params);
        }
        self.pending.resize |= dirty.resize;
        self.pending.bake |= dirty.bake;
        self.pending.normals |= dirty.normals;
        Ok(dirty)
    }

    /// Scrolls the terrain to `offset` (tiles) without baking the tile's textures: they are
    /// read that far on from where they were baked (the tile is periodic, so nothing is lost).
    /// What the scroll animation of the window and the page calls each frame. The mesh moves
    /// over its periodic landscape: its next [`Terrain::encode_bake`] bakes only the strips the
    /// tile uncovers. [`Terrain::set_params`] with the same offset bakes the textures there.
    pub fn scroll_to(&mut self, offset: [f64; 2]) -> Result<()> {
        let moved = TerrainParams {
            offset,
            ..self.params
        };
        moved.validate()?;
        self.shown_offset = offset;
        Ok(())
    }

    /// The offset drawn (see [`Terrain::scroll_to`]).
    pub fn shown_offset(&self) -> [f64; 2] {
        self.shown_offset
    }

    /// Marks every pass as owed, so the next [`Terrain::encode_bake`] redoes the tile's
    /// textures (for benchmarks, or after the host lost the textures' contents).
    pub fn invalidate(&mut self) {
        self.pending = Dirty::ALL;
    }

    /// Whether the next [`Terrain::encode_bake`] will record work on the tile's textures.
    pub fn needs_bake(&self) -> bool {
        self.pending.any_gpu_work()
    }

    /// The mesh's view of `view`: the same camera in the landscape's metres, drawn through
    /// `view`'s own projection (so the host's depth and relief's agree).
    fn world_view(&self, view: &View) -> world::WorldView {
        let frame = crate::tile::TileFrame::new(&self.params, self.shown_offset);
        let eye = frame.to_world(view.eye.as_dvec3());
        let inverse = view.view_proj.inverse();
        let ahead = inverse.project_point3(glam::Vec3::new(0.0, 0.0, 0.5)) - view.eye;
        // Row 1 of projection times a rotation has the length cot(fov / 2).
        let cot = view.view_proj.row(1).truncate().length();
        let fov_y = if cot.is_finite() && cot > 0.0 {
            2.0 * (1.0 / cot).atan()
        } else {
            std::f32::consts::FRAC_PI_4
        };
        let unit = frame.unit as f32;
        // Camera-relative metres to the host's clip space: back to tile units about the eye.
        let projection = view.view_proj
            * glam::Mat4::from_translation(view.eye)
            * glam::Mat4::from_scale(glam::Vec3::splat(1.0 / unit));
        world::WorldView {
            eye,
            forward: ahead.normalize_or(glam::Vec3::NEG_Z),
            fov_y,
            size: self.viewport,
            crop: glam::Mat4::IDENTITY,
            projection: Some(projection),
        }
    }

    /// Records whatever bake work is owed into the host's encoder: the tile's textures when
    /// the parameters changed, and the mesh's levels for `view` (the strips the camera or the
    /// scroll uncovered; nothing when neither moved). No frame work: a host that draws calls
    /// [`Terrain::prepare`], which bakes too. Returns the texels baked (0: nothing was owed).
    pub fn encode_bake(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        view: &View,
    ) -> Result<u64> {
        self.encode_bake_timed(device, queue, encoder, view, None)
    }

    /// [`Terrain::encode_bake`], writing GPU timestamps for each pass into `timer`.
    pub fn encode_bake_timed(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        view: &View,
        timer: Option<&GpuTimer>,
    ) -> Result<u64> {
        let tile = self.encode_textures(encoder, timer);
        let (wp, setup) = tile_world(&self.params, self.shown_offset);
        self.world.set_tile(device, wp, setup)?;
        let wv = self.world_view(view);
        let levels = self
            .world
            .encode_bake_timed(device, queue, encoder, &wv, timer)?;
        Ok(tile + levels)
    }

    /// Records the tile's texture passes that are owed (none if nothing changed). Returns the
    /// texels written: `size`² for the height and colour bake, `size`² for the normals.
    pub fn encode_textures(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        timer: Option<&GpuTimer>,
    ) -> u64 {
        let size = self.params.size;
        let texels = u64::from(size) * u64::from(size);
        let mut written = 0;
        if self.pending.bake || self.pending.resize {
            self.bake
                .encode(encoder, size, timer.map(|t| t.compute_writes(Slot::Bake)));
            written += texels;
        }
        if written > 0 || self.pending.normals {
            self.normals.encode(
                encoder,
                size,
                timer.map(|t| t.compute_writes(Slot::Normals)),
            );
            written += texels;
        }
        self.pending = Dirty::default();
        written
    }

    /// Everything a frame needs before the host's render pass, recorded into the host's
    /// encoder: the bake owed ([`Terrain::encode_bake`]), the frame's uniforms, and the
    /// compute passes of the methods shaded in compute. Returns the texels baked (the tile's
    /// textures and the levels'), as [`world::World::prepare`] does; 0 when nothing was owed.
    pub fn prepare(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        view: &View,
    ) -> Result<u64> {
        self.prepare_timed(device, queue, encoder, view, None)
    }

    /// [`Terrain::prepare`], writing GPU timestamps for each pass into `timer`.
    pub fn prepare_timed(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        view: &View,
        timer: Option<&GpuTimer>,
    ) -> Result<u64> {
        let tile = self.encode_textures(encoder, timer);
        let (wp, setup) = tile_world(&self.params, self.shown_offset);
        self.world.set_tile(device, wp, setup)?;
        let wv = self.world_view(view);
        let levels = self
            .world
            .prepare_timed(device, queue, encoder, &wv, timer)?;
        Ok(tile + levels)
    }

    /// Draws the terrain, and the sky behind it unless [`Shading::sky`] is off, into the
    /// host's pass, which must match [`Targets`]. With depth, the host clears it to 1.0.
    pub fn render(&self, pass: &mut wgpu::RenderPass<'_>) {
        self.world.render(pass);
    }

    /// Writes the frame shaded in compute straight into `target`, with no render pass, where
    /// the method allows; false where it does not (draw with [`Terrain::render`]). See
    /// [`world::World::present`].
    pub fn present(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        target: &wgpu::Texture,
        timer: Option<&GpuTimer>,
    ) -> bool {
        self.world.present(encoder, target, timer)
    }

    /// The baked textures, for reading or for the host's own passes.
    pub fn textures(&self) -> &Textures {
        &self.textures
    }

    /// World height of the continuous terrain surface at world (x, z), from the CPU twin.
    ///
    /// The tile spans x, z in [-WORLD_SIZE/2, WORLD_SIZE/2] and repeats beyond. The mesh
    /// interpolates its levels' samples linearly across triangles, so what is drawn differs
    /// from this by the mesh's sampling error (within the screen-error bound); at texel
    /// centres the baked heights equal it to within 1e-5 of the range.
    pub fn height_at(&self, x: f64, z: f64) -> f64 {
        height_at(&self.shown_params(), x, z)
    }

    /// The parameters with the offset shown ([`Terrain::scroll_to`]): what is drawn.
    pub fn shown_params(&self) -> TerrainParams {
        TerrainParams {
            offset: self.shown_offset,
            ..self.params
        }
    }
}

/// A GPU error while making the textures for `size` as an error naming the size.
fn size_too_big(size: u32, e: Error) -> Error {
    match e {
        Error::Gpu { message: why, .. } => {
            // rg32float terrain + rgba16float normals: 16 bytes a texel.
            let mib = (u64::from(size) * u64::from(size) * 16) >> 20;
            Error::invalid(
                "size",
                size,
                format!("a size whose textures (~{mib} MiB) fit this device's memory: {why}"),
            )
        }
        other => other,
    }
}

/// World height of the continuous terrain surface at world (x, z) for `params` (see
/// [`Terrain::height_at`]).
pub fn height_at(params: &TerrainParams, x: f64, z: f64) -> f64 {
    let fbm = crate::noise::Fbm::from_params(params);
    let u = [x / crate::WORLD_SIZE + 0.5, z / crate::WORLD_SIZE + 0.5];
    let (h, _) = fbm.sample(crate::noise::Channel::Height, u);
    h * f64::from(params.height_scale)
}

/// The adapter as messages name it: its name and backend, and for a software device (Mesa's
/// lavapipe, SwiftShader, WARP) a word that its timings are the CPU's, not a GPU's.
pub fn describe_adapter(info: &wgpu::AdapterInfo) -> String {
    let backend = format!("{:?}", info.backend);
    let software = if info.device_type == wgpu::DeviceType::Cpu {
        "; a software device: its timings are the CPU's, not a GPU's"
    } else {
        ""
    };
    if info.name.is_empty() {
        format!("{backend}{software}")
    } else {
        format!("{} ({backend}{software})", info.name)
    }
}

/// Requests a device from `adapter` with timestamps and the compute raster's 64-bit atomics
/// ([`raster::ID_FEATURES`]) where available, and the adapter's limits (so large textures work
/// where the hardware allows them).
pub async fn request_device(adapter: &wgpu::Adapter) -> Result<(wgpu::Device, wgpu::Queue)> {
    request_device_with(
        adapter,
        wgpu::Features::TIMESTAMP_QUERY | raster::ID_FEATURES,
    )
    .await
}

/// As [`request_device`], asking for only those of `wanted` the adapter has.
pub(crate) async fn request_device_with(
    adapter: &wgpu::Adapter,
    wanted: wgpu::Features,
) -> Result<(wgpu::Device, wgpu::Queue)> {
    let features = adapter.features() & wanted;
    adapter
        .request_device(&wgpu::DeviceDescriptor {
            label: Some("relief:device"),
            required_features: features,
            required_limits: adapter.limits(),
            ..Default::default()
        })
        .await
        .map_err(|e| Error::Device(e.to_string()))
}

/// Runs `f` inside validation and out-of-memory error scopes and turns a captured wgpu error
/// into [`Error::Gpu`]. On the web the scopes resolve asynchronously, so errors there reach
/// the device's uncaptured-error handler instead.
pub(crate) fn scoped<T>(device: &wgpu::Device, f: impl FnOnce() -> T) -> Result<T> {
    let validation = device.push_error_scope(wgpu::ErrorFilter::Validation);
    let oom = device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
    let value = f();
    let oom = oom.pop();
    let validation = validation.pop();
    #[cfg(not(target_arch = "wasm32"))]
    {
        // Native error scopes resolve as soon as they are popped.
        if let Some(e) = ready_now(oom).flatten().or(ready_now(validation).flatten()) {
            return Err(gpu_error(e));
        }
    }
    #[cfg(target_arch = "wasm32")]
    drop((oom, validation));
    Ok(value)
}

/// A wgpu error as one short line (wgpu's own messages span several lines and can be long).
#[cfg(not(target_arch = "wasm32"))]
pub(crate) fn gpu_error(e: wgpu::Error) -> Error {
    let kind = match e {
        wgpu::Error::OutOfMemory { .. } => "out of GPU memory",
        _ => "GPU error",
    };
    let text = e
        .to_string()
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ");
    Error::Gpu {
        message: format!("{kind}: {}", crate::table::shorten_to(&text, 150)),
        source: Some(e),
    }
}

/// The output of a future that is already complete, without an executor; `None` if it is not.
#[cfg(not(target_arch = "wasm32"))]
pub(crate) fn ready_now<F: std::future::Future>(f: F) -> Option<F::Output> {
    let mut f = std::pin::pin!(f);
    let mut cx = std::task::Context::from_waker(std::task::Waker::noop());
    match f.as_mut().poll(&mut cx) {
        std::task::Poll::Ready(v) => Some(v),
        std::task::Poll::Pending => None,
    }
}

/// Maps a `MAP_READ` buffer, waits, and copies its contents out.
#[cfg(not(target_arch = "wasm32"))]
pub(crate) fn map_read(device: &wgpu::Device, buffer: &wgpu::Buffer) -> Result<Vec<u8>> {
    let slice = buffer.slice(..);
    let (tx, rx) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |r| {
        let _ = tx.send(r);
    });
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| Error::Readback(e.to_string()))?;
    rx.recv()
        .map_err(|e| Error::Readback(e.to_string()))?
        .map_err(|e| Error::Readback(e.to_string()))?;
    let bytes = slice
        .get_mapped_range()
        .map_err(|e| Error::Readback(e.to_string()))?
        .to_vec();
    buffer.unmap();
    Ok(bytes)
}

/// The sRGB 8-bit value of the linear `l` (0 to 1), rounded to the nearest.
pub(crate) fn srgb8(l: f64) -> u8 {
    let c = if l <= 0.003_130_8 {
        l * 12.92
    } else {
        1.055 * l.powf(1.0 / 2.4) - 0.055
    };
    (c * 255.0).round().clamp(0.0, 255.0) as u8
}

/// Averages `factor` x `factor` blocks of an sRGB RGBA8 image in linear light: a
/// supersampled image down to its display size, as MSAA resolves do.
pub fn downsample_srgb(rgba: &[u8], width: u32, height: u32, factor: u32) -> Vec<u8> {
    let (w, h) = (width / factor, height / factor);
    // A table of the 256 values: a reference's supersampled image is tens of millions of
    // samples.
    let table: Vec<f64> = (0..=255u8)
        .map(|c| f64::from(crate::params::srgb_to_linear(f32::from(c) / 255.0)))
        .collect();
    let lin = |c: u8| table[usize::from(c)];
    let enc = srgb8;
    let mut out = Vec::with_capacity((w * h * 4) as usize);
    for y in 0..h {
        for x in 0..w {
            let mut acc = [0.0; 3];
            for sy in 0..factor {
                for sx in 0..factor {
                    let i = (((y * factor + sy) * width + x * factor + sx) * 4) as usize;
                    for c in 0..3 {
                        acc[c] += lin(rgba[i + c]);
                    }
                }
            }
            let k = f64::from(factor * factor);
            out.extend_from_slice(&[enc(acc[0] / k), enc(acc[1] / k), enc(acc[2] / k), 255]);
        }
    }
    out
}
