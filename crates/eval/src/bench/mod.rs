//! `relief bench`: speed against accuracy. Sweeps render methods and their knobs, measures GPU
//! time per pass (timestamps: warm-up, then the median) and wall time, measures error against
//! the ground truth (the reference ray caster's supersampled image, the twin's continuous
//! surface and analytic normals), and writes a CSV and a chart.

mod plot;

pub use self::plot::chart;
use crate::chart::{legend, log_ticks, tick_label, write_chart, CHART_SIZE};
use crate::metrics::{self, median, Coverage};
use relief::error::Result;
use relief::gpu::headless::{self, Gpu, Offscreen};
use relief::gpu::raymarch::RayMarcher;
use relief::gpu::timing::{GpuTimer, Slot};
use relief::method::{RayMethod, RayPath, SeedMarch};
use relief::params::{NormalMethod, Shading, TerrainParams};
use relief::{OrbitCamera, Terrain, View};
use std::fmt::Write as _;
use std::path::Path;

pub use relief::method::Method;

/// One point of the sweep.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Config {
    /// How it is drawn.
    pub method: Method,
    /// The scene and, for the mesh, texture size, grid and normal method.
    pub params: TerrainParams,
    /// The ray march's knobs (ray methods only).
    pub march: SeedMarch,
    /// Samples a pixel the visibility method rasterises and shades (that method only).
    pub samples: u32,
    /// Where the visibility method rasterises (that method only).
    pub raster: relief::Raster,
}

impl Config {
    /// Whether this is `candidate` (one of those the default is chosen from,
    /// [`relief::choice`]) at the default texture size, grid and normal method.
    pub fn is_candidate(&self, candidate: relief::choice::Candidate) -> bool {
        let d = TerrainParams::default();
        self.method == candidate.method
            && (self.method == Method::Mesh
                || (self.samples, self.raster) == (candidate.samples, candidate.raster))
            && (self.params.size, self.params.grid, self.params.normals)
                == (d.size, d.grid, d.normals)
    }

    /// The method as the table names it: the visibility method with its samples a pixel and,
    /// where it is not the GPU's, its raster.
    pub fn table_name(&self) -> String {
        match (self.method, self.raster) {
            (Method::Visibility, relief::Raster::Hardware) => {
                format!("visibility {}x", self.samples)
            }
            (Method::Visibility, r) => format!("visibility {}x {r}", self.samples),
            (m, _) => m.name().to_owned(),
        }
    }

    /// A few words naming the configuration, for progress and chart labels.
    pub fn label(&self) -> String {
        match self.method {
            Method::Mesh => format!(
                "mesh {} / {} / {}",
                self.params.size, self.params.grid, self.params.normals
            ),
            Method::Visibility => format!(
                "visibility {} / {} / {} / {}x{}",
                self.params.size,
                self.params.grid,
                self.params.normals,
                self.samples,
                match self.raster {
                    relief::Raster::Hardware => "",
                    relief::Raster::Compute => " compute",
                }
            ),
            Method::Blog => format!("blog {} / {} / rgba8", self.params.size, self.params.grid),
            m => format!(
                "{} step {} octaves {}",
                m.name(),
                self.march.step_factor,
                self.march.march_octaves
            ),
        }
    }
}

/// What the sweep measures with.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Options {
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Frames before timing.
    pub warmup: u32,
    /// Least time spent on warm-up frames, back to back, so the GPU reaches its working clocks
    /// before timing (an idle H100 drops its clocks within milliseconds).
    pub warmup_ms: f64,
    /// Timed frames (the median is reported).
    pub frames: u32,
    /// The reference is cast at this many times the resolution per axis and averaged down.
    pub supersample: u32,
    /// Mesh-error sample points.
    pub mesh_samples: usize,
    /// Grid vertices per side of the blog's exact surface, which its frame is scored against.
    pub blog_exact_grid: u32,
}

impl Options {
    /// The full sweep's settings.
    pub const FULL: Self = Self {
        width: 1920,
        height: 1080,
        warmup: 5,
        warmup_ms: 500.0,
        frames: 21,
        supersample: 3,
        mesh_samples: 65536,
        blog_exact_grid: relief::gpu::blog::EXACT_GRID,
    };
    /// `--quick`: small enough for lavapipe in CI.
    pub const QUICK: Self = Self {
        width: 192,
        height: 108,
        warmup: 1,
        warmup_ms: 0.0,
        frames: 3,
        supersample: 2,
        mesh_samples: 8192,
        blog_exact_grid: 1024,
    };
}

/// The configurations of a sweep over `base` (the scene the user gave): the mesh over texture
/// size, grid and normal method; the seed's ray march over path, step factor and marching
/// octaves (at most the scene's). Everything else is `base`, so every configuration is
/// measured against the same reference.
pub fn sweep(base: &TerrainParams, quick: bool) -> Vec<Config> {
    let base = *base;
    let normals = [NormalMethod::Differences, NormalMethod::Analytic];
    let (sizes, grids, steps, octaves) = if quick {
        (&[256, 1024][..], &[64, 256][..], &[0.5][..], &[5][..])
    } else {
        (
            &[512, 1024, 2048, 4096][..],
            &[128, 256, 512, 1024][..],
            &[0.3, 0.5, 0.8][..],
            &[4, 6, 8][..],
        )
    };
    let mut out = Vec::new();
    for &size in sizes {
        for &grid in grids {
            for n in normals {
                let d = TerrainParams::default();
                if quick && n == NormalMethod::Analytic && (size, grid) != (d.size, d.grid) {
                    continue;
                }
                out.push(Config {
                    method: Method::Mesh,
                    params: TerrainParams {
                        size,
                        grid,
                        normals: n,
                        ..base
                    },
                    march: SeedMarch::default(),
                    samples: relief::gpu::visibility::SAMPLES,
                    raster: relief::Raster::Hardware,
                });
            }
        }
    }
    // The visibility method: the same mesh, shaded per sample in compute, at the default and
    // at finer textures and grids.
    let d = TerrainParams::default();
    // One sample a pixel (a quarter of the raster work, edges aliased) at the default, its
    // raster in hardware and in compute.
    use relief::Raster::{Compute, Hardware};
    let visibility: &[(u32, u32, u32, relief::Raster)] = if quick {
        &[(d.size, d.grid, 4, Hardware), (d.size, d.grid, 1, Compute)]
    } else {
        &[
            (d.size, d.grid, 4, Hardware),
            (d.size, d.grid, 1, Hardware),
            (d.size, d.grid, 1, Compute),
            (d.size, 1024, 4, Hardware),
            (d.size, 1024, 1, Compute),
            (2048, 512, 4, Hardware),
            (4096, 1024, 4, Hardware),
        ]
    };
    for &(size, grid, samples, raster) in visibility {
        out.push(Config {
            method: Method::Visibility,
            params: TerrainParams { size, grid, ..base },
            march: SeedMarch::default(),
            samples,
            raster,
        });
    }
    for method in [Method::RaymarchFragment, Method::Raymarch] {
        for &step_factor in steps {
            let mut seen = Vec::new();
            for &march_octaves in octaves {
                let march_octaves = march_octaves.min(base.octaves);
                if seen.contains(&march_octaves) {
                    continue;
                }
                seen.push(march_octaves);
                out.push(Config {
                    method,
                    params: base,
                    march: SeedMarch {
                        step_factor,
                        march_octaves,
                        normal_octaves: base.octaves,
                        ..SeedMarch::default()
                    },
                    samples: relief::gpu::visibility::SAMPLES,
                    raster: relief::Raster::Hardware,
                });
            }
        }
    }
    // The seed blog's pipeline as it runs: its texture and grid, its five octaves of its own
    // noise (only the height scale and the snow line are the scene's).
    out.push(Config {
        method: Method::Blog,
        params: TerrainParams {
            size: relief::gpu::blog::BLOG_SIZE,
            grid: relief::gpu::blog::BLOG_SIZE,
            octaves: relief::gpu::blog::BLOG_OCTAVES,
            ..base
        },
        march: SeedMarch::default(),
        samples: relief::gpu::visibility::SAMPLES,
        raster: relief::Raster::Hardware,
    });
    out
}

/// Everything measured for one configuration.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    /// The configuration.
    pub config: Config,
    /// Median GPU time of the bake pass (mesh only).
    pub bake_ms: Option<f64>,
    /// Median GPU time of the normal pass (mesh only).
    pub normals_ms: Option<f64>,
    /// Median GPU time of drawing one frame: the render pass (and, for the visibility method,
    /// its raster and shading passes), or the ray cast and its image shown in the target.
    pub render_ms: Option<f64>,
    /// Median wall time of a whole frame (submit to completion), bake included for the mesh.
    pub wall_ms: f64,
    /// Mesh vertical error (mesh only).
    pub mesh: Option<metrics::MeshError>,
    /// Normal map error (mesh only).
    pub normals: Option<metrics::NormalError>,
    /// FLIP mean against the reference image.
    pub flip_mean: f64,
    /// FLIP 99th percentile.
    pub flip_p99: f64,
    /// Terrain coverage and depth against the reference.
    pub coverage: Coverage,
}

impl Row {
    /// GPU time of a frame that re-bakes everything (what the chart plots for the mesh), or
    /// the draw alone when there is no bake.
    pub fn frame_gpu_ms(&self) -> Option<f64> {
        let draw = self.render_ms?;
        Some(draw + self.bake_ms.unwrap_or(0.0) + self.normals_ms.unwrap_or(0.0))
    }
}

/// The row of relief's default on the device measured: the tile's candidates
/// ([`relief::choice::Candidate::all`]) at the default scene, chosen by their median draws as
/// `relief render --method auto` chooses (the mesh where nothing was timed).
pub fn default_row(rows: &[Row]) -> Option<usize> {
    use relief::choice::{Candidate, Choice};
    let candidates = Candidate::all(relief::WorldKind::Tile);
    let row_of = |c: Candidate| rows.iter().position(|r| r.config.is_candidate(c));
    let ms = candidates
        .iter()
        .filter_map(|&c| Some((c, row_of(c).map(|i| rows[i].render_ms)??)))
        .collect();
    row_of(Choice::decide(ms, 0, (0, 0)).candidate)
}

/// Where rows go as they are measured.
pub trait Progress {
    /// Called before each configuration.
    fn start(&mut self, index: usize, total: usize, config: &Config);
}

/// Runs the sweep on `gpu` and returns one row per configuration.
pub fn run(
    gpu: &Gpu,
    scene: &TerrainParams,
    configs: &[Config],
    options: &Options,
    progress: &mut dyn Progress,
) -> Result<Vec<Row>> {
    let timer = GpuTimer::new(&gpu.device, &gpu.queue);
    let view = OrbitCamera::default().view(options.width as f32 / options.height as f32);
    let shading = Shading::default();
    let reference = Reference::new(gpu, scene, &shading, &view, options)?;
    let mut rows = Vec::with_capacity(configs.len());
    for (i, config) in configs.iter().enumerate() {
        progress.start(i, configs.len(), config);
        rows.push(match config.method {
            Method::Mesh | Method::Visibility | Method::Hybrid => {
                mesh_row(gpu, config, options, &view, timer.as_ref(), &reference)?
            }
            Method::Blog => blog_row(gpu, config, options, &view, &shading, timer.as_ref())?,
            Method::RaymarchFragment
            | Method::Raymarch
            | Method::RaymarchBandlimited
            | Method::Reference => ray_row(
                gpu,
                config,
                options,
                &view,
                &shading,
                timer.as_ref(),
                &reference,
            )?,
        });
    }
    Ok(rows)
}

/// The ground truth image: the reference ray cast, supersampled, and its distances.
pub struct Reference {
    /// RGB8 at the bench's size.
    pub rgb: Vec<u8>,
    /// Distance per pixel at the bench's size (negative for sky).
    pub distance: Vec<f32>,
}

impl Reference {
    /// Casts the reference for `params` through `view`.
    pub fn new(
        gpu: &Gpu,
        params: &TerrainParams,
        shading: &Shading,
        view: &View,
        options: &Options,
    ) -> Result<Self> {
        let ss = options.supersample.max(1);
        let big = RayMarcher::new(&gpu.device, options.width * ss, options.height * ss)?;
        big.prepare(&gpu.queue, params, shading, view, RayMethod::Reference);
        let small = RayMarcher::new(&gpu.device, options.width, options.height)?;
        small.prepare(&gpu.queue, params, shading, view, RayMethod::Reference);
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        big.encode(&mut encoder, RayPath::Compute, None);
        small.encode(&mut encoder, RayPath::Compute, None);
        gpu.queue.submit([encoder.finish()]);
        let color = headless::read_texture(&gpu.device, &gpu.queue, &big.color)?;
        let color = metrics::downsample_srgb(&color, options.width * ss, options.height * ss, ss);
        let distance = headless::read_texture(&gpu.device, &gpu.queue, &small.distance)?;
        let distance: Vec<f32> = bytemuck::pod_collect_to_vec(&distance);
        if distance.iter().any(|&d| d == -2.0) {
            log::warn!("the reference left some rays unresolved");
        }
        Ok(Self {
            rgb: metrics::rgb(&color),
            distance,
        })
    }
}

/// Relative depth difference beyond which a pixel counts as hit at the wrong depth.
pub const DEPTH_TOLERANCE: f64 = 0.01;

/// Runs `frame` back to back for the warm-up (at least `warmup` frames and `warmup_ms`), then
/// `frames` timed frames ([`headless::measure_frames`]).
pub(crate) fn measure(
    gpu: &Gpu,
    options: &Options,
    timer: Option<&GpuTimer>,
    frame: impl FnMut(&mut wgpu::CommandEncoder, Option<&GpuTimer>),
) -> Result<(Vec<relief::gpu::timing::Timings>, Vec<f64>)> {
    let warm = (options.warmup, options.warmup_ms);
    headless::measure_frames(gpu, warm, options.frames, timer, frame)
}

fn mesh_row(
    gpu: &Gpu,
    config: &Config,
    options: &Options,
    view: &View,
    timer: Option<&GpuTimer>,
    reference: &Reference,
) -> Result<Row> {
    let samples = relief::gpu::headless::render_samples(config.method);
    let target = Offscreen::new(&gpu.device, options.width, options.height, samples)?;
    let mut terrain = Terrain::new(
        &gpu.device,
        &gpu.queue,
        Offscreen::targets(samples),
        config.params,
    )?;
    terrain.set_method(
        &gpu.device,
        relief::MethodConfig::new(config.method)
            .with_samples(config.samples)
            .with_raster(config.raster),
    )?;
    terrain.set_viewport((options.width, options.height));
    headless::bake_whole(gpu, &mut terrain, view, None)?;
    let mut failed = None;
    let (times, wall) = measure(gpu, options, timer, |encoder, timer| {
        // The tile's textures each frame, as the blog bakes; the mesh's levels stay baked.
        terrain.invalidate();
        if let Err(e) = terrain.prepare_timed(&gpu.device, &gpu.queue, encoder, view, timer) {
            failed.get_or_insert(e);
        }
        let clear = relief::gpu::clear_color(terrain.shading().sky_color, Offscreen::COLOR_FORMAT);
        target.draw(encoder, &terrain, clear, timer);
    })?;
    if let Some(e) = failed {
        return Err(e);
    }
    let slot = |s: Slot| {
        times
            .iter()
            .filter_map(|t| t[s as usize])
            .collect::<Vec<f64>>()
    };
    let (bake, normals) = (slot(Slot::Bake), slot(Slot::Normals));
    // The draw: the host's pass (or the present), and the visibility method's raster and
    // shading before it.
    let render: Vec<f64> = times.iter().filter_map(relief::choice::draw_ms).collect();
    let image = headless::read_texture(&gpu.device, &gpu.queue, &target.color)?;
    let (flip_mean, flip_p99) = metrics::image_error(
        &reference.rgb,
        &metrics::rgb(&image),
        options.width,
        options.height,
    );

    // Distances from a single-sampled render's depth buffer.
    let single = Offscreen::new(&gpu.device, options.width, options.height, 1)?.keeping_depth();
    let mut terrain1 = Terrain::new(
        &gpu.device,
        &gpu.queue,
        Offscreen::targets(1),
        config.params,
    )?;
    single.render(gpu, &mut terrain1, view, None)?;
    let depth = single.read_depth(gpu)?;
    let distance = distances(&depth, view, (options.width, options.height));

    let baked = headless::read_baked(&gpu.device, &gpu.queue, &terrain)?;
    // The mesh as drawn (levels of detail and all), from the single-sampled depth.
    let mesh = metrics::drawn_mesh_error(
        &config.params,
        view,
        (options.width, options.height),
        &depth,
        options.mesh_samples,
    );
    let normal_error = metrics::normal_error(&config.params, &baked.normals);
    Ok(Row {
        config: *config,
        bake_ms: median(bake),
        normals_ms: median(normals),
        render_ms: median(render),
        wall_ms: median(wall).unwrap_or(f64::NAN),
        mesh: Some(mesh),
        normals: Some(normal_error),
        flip_mean,
        flip_p99,
        coverage: metrics::coverage(&reference.distance, &distance, DEPTH_TOLERANCE),
    })
}

/// Distance from the eye per pixel of a single-sampled depth buffer (-1 for sky).
pub(crate) fn distances(depth: &[f32], view: &View, (width, height): (u32, u32)) -> Vec<f32> {
    let vp = view.view_proj.as_dmat4();
    let eye = view.eye.as_dvec3();
    depth
        .iter()
        .enumerate()
        .map(|(i, &d)| {
            if d >= 1.0 {
                return -1.0;
            }
            let (x, y) = (i as u32 % width, i as u32 / width);
            let p = crate::raycast::unproject(vp, width, height, x, y, f64::from(d));
            (p - eye).length() as f32
        })
        .collect()
}

/// The seed blog's frame (bake, normals, draw, every frame), scored against its own exact
/// surface: its terrain is not relief's, so relief's reference cannot judge it.
fn blog_row(
    gpu: &Gpu,
    config: &Config,
    options: &Options,
    view: &View,
    shading: &Shading,
    timer: Option<&GpuTimer>,
) -> Result<Row> {
    use relief::gpu::blog::Blog;
    use relief::gpu::headless::BlogImage;
    let scene = (&config.params, shading);
    let size = (options.width, options.height);
    let exact = BlogImage::Exact {
        grid: options.blog_exact_grid,
        supersample: options.supersample,
    };
    let (truth, _) = relief::gpu::headless::render_blog(gpu, scene, view, size, exact, None)?;
    let target = Offscreen::new(&gpu.device, options.width, options.height, 1)?;
    let blog = Blog::new(&gpu.device, Offscreen::targets(1))?;
    let color_view = target.color_view();
    blog.prepare(&gpu.queue, &config.params, shading, view, 0.0);
    let clear = relief::gpu::clear_color(shading.sky_color, Offscreen::COLOR_FORMAT);
    let (times, wall) = measure(gpu, options, timer, |encoder, timer| {
        blog.encode_bake(encoder, timer);
        let mut pass = target.begin_pass(
            encoder,
            &color_view,
            clear,
            timer.map(|t| t.render_writes(Slot::Render)),
        );
        blog.render(&mut pass);
    })?;
    let slot = |s: Slot| median(times.iter().filter_map(|t| t[s as usize]));
    let image = headless::read_texture(&gpu.device, &gpu.queue, &target.color)?;
    let depth = distances(
        &target.read_depth(gpu)?,
        view,
        (options.width, options.height),
    );
    // Where the exact surface lies, from its own single-sampled depth.
    let exact = Blog::exact(&gpu.device, Offscreen::targets(1), options.blog_exact_grid)?;
    let single = Offscreen::new(&gpu.device, options.width, options.height, 1)?;
    single.render_blog(gpu, &exact, scene, view, None)?;
    let truth_depth = distances(
        &single.read_depth(gpu)?,
        view,
        (options.width, options.height),
    );
    let (flip_mean, flip_p99) = metrics::image_error(
        &metrics::rgb(&truth),
        &metrics::rgb(&image),
        options.width,
        options.height,
    );
    Ok(Row {
        config: *config,
        bake_ms: slot(Slot::Bake),
        normals_ms: slot(Slot::Normals),
        render_ms: slot(Slot::Render),
        wall_ms: median(wall).unwrap_or(f64::NAN),
        mesh: None,
        normals: None,
        flip_mean,
        flip_p99,
        coverage: metrics::coverage(&truth_depth, &depth, DEPTH_TOLERANCE),
    })
}

fn ray_row(
    gpu: &Gpu,
    config: &Config,
    options: &Options,
    view: &View,
    shading: &Shading,
    timer: Option<&GpuTimer>,
    reference: &Reference,
) -> Result<Row> {
    let rm = RayMarcher::new(&gpu.device, options.width, options.height)?;
    let rays = match config.method {
        Method::Reference => RayMethod::Reference,
        _ => RayMethod::SeedMarch(config.march),
    };
    rm.prepare(&gpu.queue, &config.params, shading, view, rays);
    let path = config.method.ray_path().unwrap_or(RayPath::Compute);
    // A frame is the cast and its image shown in a target (the full-screen draw the window
    // makes of it), as the mesh methods' frames end in theirs.
    let shown = Offscreen::new(&gpu.device, options.width, options.height, 1)?;
    let shown_view = shown.color_view();
    let blit = relief::gpu::blit::Blit::new(&gpu.device, Offscreen::COLOR_FORMAT);
    let group = blit.bind(&gpu.device, &rm.color);
    let (times, wall) = measure(gpu, options, timer, |encoder, timer| {
        rm.encode(encoder, path, timer);
        blit.encode(&gpu.queue, encoder, (&group, 1), &shown_view, timer);
    })?;
    let render: Vec<f64> = times
        .iter()
        .filter_map(|t| Some(t[Slot::Render as usize]? + t[Slot::Show as usize].unwrap_or(0.0)))
        .collect();
    let image = headless::read_texture(&gpu.device, &gpu.queue, &rm.color)?;
    let distance = headless::read_texture(&gpu.device, &gpu.queue, &rm.distance)?;
    let distance: Vec<f32> = bytemuck::pod_collect_to_vec(&distance);
    let (flip_mean, flip_p99) = metrics::image_error(
        &reference.rgb,
        &metrics::rgb(&image),
        options.width,
        options.height,
    );
    Ok(Row {
        config: *config,
        bake_ms: None,
        normals_ms: None,
        render_ms: median(render),
        wall_ms: median(wall).unwrap_or(f64::NAN),
        mesh: None,
        normals: None,
        flip_mean,
        flip_p99,
        coverage: metrics::coverage(&reference.distance, &distance, DEPTH_TOLERANCE),
    })
}

fn opt(v: Option<f64>) -> String {
    v.map_or(String::new(), |x| format!("{x:.6}"))
}

/// The CSV: a header and one row per configuration, every knob, metric and timing, with the
/// device and backend.
pub fn csv(rows: &[Row], device: &str, backend: &str, options: &Options) -> String {
    let mut out = String::from(
        "device,backend,method,default,width,height,seed,frequency,gain,height_scale,size,grid,octaves,normals,step_factor,hit_k,march_octaves,normal_octaves,samples,raster,\
         bake_ms,normals_ms,render_ms,frame_gpu_ms,wall_ms,mesh_rms,mesh_max,mesh_rms_px,mesh_max_px,normal_mean_deg,normal_p99_deg,\
         flip_mean,flip_p99,missed,extra,wrong_depth\n",
    );
    let quote = |s: &str| format!("\"{}\"", s.replace('"', "\"\""));
    let default = default_row(rows);
    for (i, r) in rows.iter().enumerate() {
        let c = &r.config;
        let ray = c.method.ray_path().is_some();
        let own = c.method == Method::Blog;
        let _ = writeln!(
            out,
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{:.6},{},{},{},{},{},{},{:.6},{:.6},{:.6},{:.6},{:.6}",
            quote(device),
            quote(backend),
            c.method.name(),
            default == Some(i),
            options.width,
            options.height,
            // The blog's terrain is its own noise: no seed, frequency or gain of the scene's.
            if own { String::new() } else { c.params.seed.to_string() },
            if own { String::new() } else { c.params.frequency.to_string() },
            if own { String::new() } else { c.params.gain.to_string() },
            c.params.height_scale,
            if ray { String::new() } else { c.params.size.to_string() },
            if ray { String::new() } else { c.params.grid.to_string() },
            c.params.octaves,
            if ray { String::new() } else { c.params.normals.to_string() },
            if ray { c.march.step_factor.to_string() } else { String::new() },
            if ray { c.march.hit_k.to_string() } else { String::new() },
            if ray { c.march.march_octaves.to_string() } else { String::new() },
            if ray { c.march.normal_octaves.to_string() } else { String::new() },
            if c.method == Method::Visibility { c.samples.to_string() } else { String::new() },
            if c.method == Method::Visibility { c.raster.to_string() } else { String::new() },
            opt(r.bake_ms),
            opt(r.normals_ms),
            opt(r.render_ms),
            opt(r.frame_gpu_ms()),
            r.wall_ms,
            opt(r.mesh.map(|m| m.rms)),
            opt(r.mesh.map(|m| m.max)),
            opt(r.mesh.map(|m| m.rms_px)),
            opt(r.mesh.map(|m| m.max_px)),
            opt(r.normals.map(|n| n.mean_deg)),
            opt(r.normals.map(|n| n.p99_deg)),
            r.flip_mean,
            r.flip_p99,
            r.coverage.missed,
            r.coverage.extra,
            r.coverage.wrong_depth,
        );
    }
    out
}

/// A short table for the terminal.
pub fn table(rows: &[Row]) -> String {
    let mut out = format!(
        "{:<21} {:>5} {:>5} {:>11} {:>5} {:>4} {:>10} {:>10} {:>9} {:>8} {:>8}\n",
        "method",
        "size",
        "grid",
        "normals",
        "step",
        "oct",
        "gpu ms",
        "wall ms",
        "FLIP",
        "missed",
        "mesh px"
    );
    let default = default_row(rows);
    for (i, r) in rows.iter().enumerate() {
        let c = &r.config;
        let ray = c.method.ray_path().is_some();
        let dash = |b: bool, s: String| if b { "-".to_owned() } else { s };
        let _ = writeln!(
            out,
            "{:<21} {:>5} {:>5} {:>11} {:>5} {:>4} {:>10} {:>10.3} {:>9.4} {:>8.4} {:>8}{}",
            c.table_name(),
            dash(ray, c.params.size.to_string()),
            dash(ray, c.params.grid.to_string()),
            dash(ray, c.params.normals.to_string()),
            dash(!ray, format!("{}", c.march.step_factor)),
            if ray {
                c.march.march_octaves
            } else {
                c.params.octaves
            },
            r.frame_gpu_ms()
                .map_or("n/a".to_owned(), |v| format!("{v:.4}")),
            r.wall_ms,
            r.flip_mean,
            r.coverage.missed,
            r.mesh
                .map_or("-".to_owned(), |m| format!("{:.3}", m.rms_px)),
            if default == Some(i) {
                "  <- default"
            } else {
                ""
            },
        );
    }
    out
}

/// Indices of the rows on the Pareto front of (GPU time, FLIP mean): no other row is both
/// faster and more accurate. The blog's row is not a candidate: its FLIP is against its own
/// terrain.
pub fn pareto(rows: &[Row]) -> Vec<usize> {
    let pts: Vec<(usize, f64, f64)> = rows
        .iter()
        .enumerate()
        // The blog is scored against its own terrain's surface, not relief's reference.
        .filter(|(_, r)| r.config.method != Method::Blog)
        .filter_map(|(i, r)| r.frame_gpu_ms().map(|t| (i, t, r.flip_mean)))
        .collect();
    let mut front: Vec<usize> = pts
        .iter()
        .filter(|&&(i, t, e)| {
            !pts.iter()
                .any(|&(j, t2, e2)| j != i && t2 <= t && e2 <= e && (t2 < t || e2 < e))
        })
        .map(|&(i, _, _)| i)
        .collect();
    front.sort_by(|&a, &b| {
        rows[a]
            .frame_gpu_ms()
            .unwrap_or(0.0)
            .total_cmp(&rows[b].frame_gpu_ms().unwrap_or(0.0))
    });
    front
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chart_ticks_are_dense_short_and_distinct() {
        // The H100 sweep's range: most points between 0.7 and 12 ms.
        let x = log_ticks(0.5, 140.0, 5);
        assert!(x.iter().filter(|&&v| v < 100.0).count() >= 6, "{x:?}");
        let labels: Vec<String> = x.iter().map(|&v| tick_label(v)).collect();
        assert!(labels.iter().all(|l| l.len() <= 4), "{labels:?}");
        let mut unique = labels.clone();
        unique.dedup();
        assert_eq!(unique, labels);
        assert_eq!(tick_label(0.5), "0.5");
        assert_eq!(tick_label(20.0), "20");
        // A FLIP range inside one decade still gets several labels.
        let y = log_ticks(0.03, 0.09, 4);
        assert!(y.len() >= 4, "{y:?}");
        assert_eq!(tick_label(y[0]), "0.03");
        assert!(
            log_ticks(0.0, 10.0, 4).is_empty(),
            "no ticks, and no endless loop, at 0"
        );
    }
}
