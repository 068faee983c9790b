//! `relief bench --world endless`: the clipmap renderer on landscape views (along the ground
//! to the horizon, grazing over a ridge, high and oblique) over the pixel-error knob, and a
//! flight along a path: triangles, texels baked per frame, the screen-error bound and GPU
//! times (warm-up, then the median), and each image against the reference ray cast of the same
//! view (FLIP, missed and extra pixels). The seed's ray march (compute and fragment) beside
//! them on every view. Written as `landscape.csv`.

use crate::bench::{measure, Options};
use crate::metrics::{self, median, Coverage};
use glam::DVec3;
use relief::error::Result;
use relief::gpu::headless::{
    render_samples, render_world_rays, render_world_rays_at, world_depth_metrics, Gpu, Offscreen,
    RayImage, ScreenError, RENDER_SAMPLES,
};
use relief::gpu::raymarch::{RayMarcher, RayScene};
use relief::gpu::timing::{GpuTimer, Slot};
use relief::world::WorldParams;
use relief::{Method, World, WorldView};

pub use crate::views::{random_views, views, LandscapeView, RANDOM_VIEWS, RANDOM_VIEW_SEED};

/// One measured configuration.
#[derive(Clone, Debug)]
pub struct WorldRow {
    /// View name (or `flight`).
    pub view: String,
    /// How it was drawn.
    pub method: Method,
    /// The knob.
    pub pixel_error: f64,
    /// Cells per patch side.
    pub patch_cells: u32,
    /// Levels drawn.
    pub levels: u32,
    /// Triangles drawn.
    pub triangles: u64,
    /// Screen-error bound of the layout, pixels.
    pub error_bound_px: f64,
    /// Measured screen error against the continuous surface (max and 99th percentile over
    /// every other pixel each way), pixels; `None` for the flight.
    pub measured: Option<ScreenError>,
    /// Texels baked per frame: median and largest (a still view bakes nothing after the first).
    pub texels_median: u64,
    /// Largest texels baked in one timed frame.
    pub texels_max: u64,
    /// Median GPU time of the render pass, ms.
    pub render_ms: Option<f64>,
    /// Median and largest GPU time of the bake pass among frames that baked, ms.
    pub bake_ms: Option<f64>,
    /// Largest bake time, ms.
    pub bake_max_ms: Option<f64>,
    /// Median wall time per frame, ms.
    pub wall_ms: f64,
    /// Mean texels baked per timed frame.
    pub texels_mean: f64,
    /// Mean GPU bake time per timed frame (frames that baked nothing count as 0), ms.
    pub bake_ms_mean: Option<f64>,
    /// FLIP mean and 99th percentile against the reference ray cast of the same view.
    pub flip: Option<(f64, f64)>,
    /// Terrain pixels against the reference's pixel-centre rays (pixels where the reference
    /// ran out of steps are left out).
    pub coverage: Option<Coverage>,
    /// Rays that ran out of steps (ray-cast rows).
    pub unresolved: Option<usize>,
    /// The reference's row: FLIP mean and 99th percentile of its 3x3 image against 8x8.
    pub converged: Option<(f64, f64)>,
    /// Mean GPU time of the light pass (shadows and valley occlusion of the texels baked) per
    /// timed frame (frames that lit nothing count as 0), and the largest, ms.
    pub light_ms_mean: Option<f64>,
    /// Largest light pass time, ms.
    pub light_ms_max: Option<f64>,
    /// Samples a pixel the visibility method or the hybrid rasterised and shaded (`None` for
    /// the forward mesh, 4x MSAA, and the ray casters).
    pub samples: Option<u32>,
    /// Where the visibility method or the hybrid rasterised (`None` for the others).
    pub raster: Option<relief::Raster>,
}

impl WorldRow {
    /// A row from a measured run: the world's last stats, the texels each frame baked (the
    /// timed frames are the last ones), and the timed frames' GPU and wall times.
    fn measured(
        (view, method): (&str, Method),
        knob: f64,
        s: &relief::WorldStats,
        texels: &[u64],
        times: &[relief::gpu::timing::Timings],
        wall: &[f64],
    ) -> Self {
        let timed = &texels[texels.len().saturating_sub(wall.len())..];
        let slot = |slot: Slot| times.iter().filter_map(move |t| t[slot as usize]);
        // The draw: the host's pass (or the present), and the visibility method's raster and
        // shading before it.
        let draw = times.iter().filter_map(relief::choice::draw_ms);
        Self {
            view: view.to_owned(),
            method,
            pixel_error: knob,
            patch_cells: s.patch_cells,
            levels: s.levels,
            triangles: s.triangles,
            error_bound_px: s.error_bound_px,
            measured: None,
            texels_median: median(timed.to_vec()).unwrap_or(0),
            texels_max: timed.iter().copied().max().unwrap_or(0),
            render_ms: median(draw),
            bake_ms: median(slot(Slot::Bake)),
            bake_max_ms: slot(Slot::Bake).reduce(f64::max),
            wall_ms: median(wall.to_vec()).unwrap_or(0.0),
            texels_mean: mean_texels(timed),
            bake_ms_mean: mean_slot(times, Slot::Bake),
            flip: None,
            coverage: None,
            unresolved: None,
            converged: None,
            light_ms_mean: mean_slot(times, Slot::Light),
            light_ms_max: slot(Slot::Light).reduce(f64::max),
            samples: None,
            raster: None,
        }
    }

    /// A ray-cast row (no mesh, nothing baked) drawn at `knob`'s region.
    fn rays(view: &str, method: Method, knob: f64, render_ms: Option<f64>, wall_ms: f64) -> Self {
        Self {
            view: view.to_owned(),
            method,
            pixel_error: knob,
            patch_cells: 0,
            levels: 0,
            triangles: 0,
            error_bound_px: 0.0,
            measured: None,
            texels_median: 0,
            texels_max: 0,
            render_ms,
            bake_ms: None,
            bake_max_ms: None,
            wall_ms,
            texels_mean: 0.0,
            bake_ms_mean: None,
            flip: None,
            coverage: None,
            unresolved: None,
            converged: None,
            light_ms_mean: None,
            light_ms_max: None,
            samples: None,
            raster: None,
        }
    }

    /// Fills in the row's error against `reference` from its image and (where given) its
    /// distances.
    fn against(
        &mut self,
        reference: &RayImage,
        rgba: &[u8],
        distance: Option<&[f32]>,
        size: (u32, u32),
    ) {
        self.flip = Some(metrics::image_error(
            &metrics::rgb(&reference.rgba),
            &metrics::rgb(rgba),
            size.0,
            size.1,
        ));
        self.coverage = distance.map(|d| resolved_coverage(&reference.distance, d));
    }
}

/// Relative depth difference counted as a wrong depth.
const DEPTH_TOLERANCE: f64 = 0.01;

/// [`metrics::coverage`] over the pixels whose reference ray found its answer.
fn resolved_coverage(reference: &[f32], test: &[f32]) -> Coverage {
    let (r, t): (Vec<f32>, Vec<f32>) = reference
        .iter()
        .zip(test)
        .filter(|(&r, _)| r != -2.0)
        .map(|(&r, &t)| (r, t))
        .unzip();
    metrics::coverage(&r, &t, DEPTH_TOLERANCE)
}

/// Measures `views` at each knob, then a flight along a straight path low over the ground.
pub fn run(
    gpu: &Gpu,
    params: &WorldParams,
    knobs: &[f64],
    options: &Options,
    mut progress: impl FnMut(&str),
) -> Result<Vec<WorldRow>> {
    let size = (options.width, options.height);
    let timer = GpuTimer::new(&gpu.device, &gpu.queue);
    // The mesh's 4x target, and the single-sampled one the visibility method composites into.
    let targets = [
        Offscreen::new(&gpu.device, size.0, size.1, RENDER_SAMPLES)?,
        Offscreen::new(&gpu.device, size.0, size.1, 1)?,
    ];
    let target_for = |method: Method| &targets[usize::from(render_samples(method) == 1)];
    let mut rows = Vec::new();
    let mut references = References::default();
    let quick = options.frames < 10;
    let vis_knob = if quick {
        knobs.first().copied().unwrap_or(params.pixel_error)
    } else {
        params.pixel_error
    };
    let frame = |world: &mut World,
                 view: &WorldView,
                 encoder: &mut wgpu::CommandEncoder,
                 timer: Option<&GpuTimer>|
     -> u64 {
        let texels = world
            .prepare_timed(&gpu.device, &gpu.queue, encoder, view, timer)
            .unwrap_or(0);
        target_for(world.method()).draw(encoder, world, wgpu::Color::BLACK, timer);
        texels
    };
    for &knob in knobs {
        let p = WorldParams {
            pixel_error: knob,
            ..*params
        };
        // The visibility method beside the mesh at one knob: the scene's (the full run's 1 px),
        // or the quick run's first, at four samples a pixel (and in the full run at one,
        // rasterised in compute); the hybrid at every knob, at four samples a pixel and one
        // (its accuracy should not follow the mesh's as the mesh coarsens), and in the full run
        // at one sample rasterised in compute too.
        use relief::Raster::{Compute, Hardware};
        let mut hybrid = vec![(Method::Hybrid, 4, Hardware), (Method::Hybrid, 1, Hardware)];
        let mut visibility = vec![(Method::Visibility, 4, Hardware)];
        if !quick {
            hybrid.push((Method::Hybrid, 1, Compute));
            visibility.push((Method::Visibility, 1, Compute));
        }
        let methods = if knob == vis_knob {
            [&[(Method::Mesh, 4, Hardware)][..], &visibility, &hybrid].concat()
        } else {
            [&[(Method::Mesh, 4, Hardware)][..], &hybrid].concat()
        };
        // Beside the named views, the random ones at the scene's knob (full runs only), with
        // fewer methods.
        let mut here = views(&p, size);
        if !quick && knob == params.pixel_error {
            here.extend(random_views(&p, size));
        }
        // On the random views: the mesh, the visibility method as `auto` picks it on a fast
        // GPU (one sample, rasterised in compute) and the hybrid at one sample.
        let random = [
            (Method::Mesh, 4, Hardware),
            (Method::Visibility, 1, Compute),
            (Method::Hybrid, 1, Hardware),
        ];
        for v in here {
            // The random views look at landscapes of their own seeds.
            let p = v.params(&p);
            let methods = if RANDOM_VIEWS.contains(&v.name) {
                &random[..]
            } else {
                &methods[..]
            };
            for &(method, samples, raster) in methods {
                let named = match (method, raster) {
                    (Method::Mesh, _) => method.to_string(),
                    (_, Hardware) => format!("{method}, {samples} a pixel"),
                    (_, Compute) => format!("{method}, {samples} a pixel rasterised in compute"),
                };
                progress(&format!("{} at {knob} px ({named})", v.name));
                let mut world = World::new(
                    &gpu.device,
                    &gpu.queue,
                    Offscreen::targets(render_samples(method)),
                    p,
                )?;
                world.set_method(
                    &gpu.device,
                    relief::MethodConfig::new(method)
                        .with_samples(samples)
                        .with_raster(raster),
                )?;
                let mut texels = Vec::new();
                let (times, wall) = measure(gpu, options, timer.as_ref(), |encoder, timer| {
                    texels.push(frame(&mut world, &v.view, encoder, timer));
                })?;
                let s = world.stats();
                let mut row =
                    WorldRow::measured((v.name, method), knob, &s, &texels, &times, &wall);
                row.samples = (method != Method::Mesh).then_some(samples);
                row.raster = (method != Method::Mesh).then_some(raster);
                // The mesh's screen error and depth; not the hybrid's, whose surface is not its
                // mesh's (its FLIP says how close it is).
                let depth = if method == Method::Hybrid {
                    None
                } else {
                    let mut single = World::new(&gpu.device, &gpu.queue, Offscreen::targets(1), p)?;
                    let (measured, distance) = world_depth_metrics(gpu, &mut single, &v.view, 2)?;
                    row.measured = Some(measured);
                    Some(distance)
                };
                let (image, _) = target_for(method).render_world(gpu, &mut world, &v.view, None)?;
                progress(&format!("{} at {knob} px: the reference", v.name));
                let reference = references.get(gpu, &p, &v, timer.as_ref())?;
                row.against(reference, &image, depth.as_deref(), size);
                rows.push(row);
            }
        }
    }
    // The reference itself and the seed's march, at the default knob's region.
    for v in views(params, size) {
        progress(&format!("{}: the ray casters", v.name));
        let reference = references.get(gpu, params, &v, timer.as_ref())?.clone();
        let ms = reference.timings.and_then(|t| t[Slot::Render as usize]);
        let mut row = WorldRow::rays(v.name, Method::Reference, params.pixel_error, ms, f64::NAN);
        row.unresolved = Some(reference.unresolved);
        if options.frames >= 10 {
            // Has 3x3 converged? Against 8x8 rays per pixel (full runs only: 64 rays a pixel).
            let fine = render_world_rays_at(
                gpu,
                params,
                &relief::Shading::default(),
                &v.view,
                Method::Reference,
                8,
                None,
            )?;
            row.converged = Some(metrics::image_error(
                &metrics::rgb(&fine.rgba),
                &metrics::rgb(&reference.rgba),
                size.0,
                size.1,
            ));
        }
        rows.push(row);
        for method in [
            Method::Raymarch,
            Method::RaymarchFragment,
            Method::RaymarchBandlimited,
        ] {
            rows.push(march_row(
                gpu,
                params,
                &v,
                method,
                options,
                timer.as_ref(),
                &reference,
            )?);
        }
    }
    // Flights at 60 frames a second, baking what the levels uncover each frame: at 300 km/h,
    // 40 m above the ground (1.4 m a frame), and along the fly-through path.
    // At the given knob, or (in the quick run) at the loosest one measured.
    let p = WorldParams {
        pixel_error: if quick {
            knobs.iter().copied().fold(params.pixel_error, f64::max)
        } else {
            params.pixel_error
        },
        ..*params
    };
    let land = p.land;
    // The straight, low flight; then the seed template's fly-through path (120 m/s, 150 m over
    // the highest ground ahead), at 60 frames a second.
    let path = relief::PathCamera::default();
    type Camera<'a> = Box<dyn Fn(f64) -> WorldView + 'a>;
    let cameras: [(&str, Camera); 2] = [
        (
            "flight",
            Box::new(|t: f64| {
                let x = t * 83.3;
                let z = 0.3 * x;
                let eye = DVec3::new(x, land.height_at(x, z) + 40.0, z);
                WorldView::look_at(
                    eye,
                    eye + DVec3::new(1.0, -0.08, 0.3),
                    45f32.to_radians(),
                    size,
                )
            }),
        ),
        (
            "path",
            Box::new(|t: f64| path.view(|x, z| land.height_at(x, z), t, size)),
        ),
    ];
    for (name, camera) in cameras {
        progress(name);
        // Long enough for every fine level to move several times.
        let flight = Options {
            frames: if quick { 40 } else { 600 },
            ..*options
        };
        let mut world = World::new(
            &gpu.device,
            &gpu.queue,
            Offscreen::targets(RENDER_SAMPLES),
            p,
        )?;
        let mut t = 0.0f64;
        let mut texels = Vec::new();
        let mut triangles = Vec::new();
        let (times, wall) = measure(gpu, &flight, timer.as_ref(), |encoder, timer| {
            t += 1.0 / 60.0;
            texels.push(frame(&mut world, &camera(t), encoder, timer));
            triangles.push(world.stats().triangles);
        })?;
        let s = world.stats();
        let mut row = WorldRow::measured(
            (name, Method::Mesh),
            p.pixel_error,
            &s,
            &texels,
            &times,
            &wall,
        );
        row.triangles = median(triangles[triangles.len() - wall.len()..].to_vec()).unwrap_or(0);
        rows.push(row);
    }
    Ok(rows)
}

/// Reference images, cast once per view and drawn region.
#[derive(Default)]
struct References {
    cast: Vec<(String, [u64; 4], RayImage)>,
}

impl References {
    fn get(
        &mut self,
        gpu: &Gpu,
        params: &WorldParams,
        v: &LandscapeView,
        timer: Option<&GpuTimer>,
    ) -> Result<&RayImage> {
        let region = relief::gpu::world_rays::drawn_region(params, &v.view).map(f64::to_bits);
        let found = self
            .cast
            .iter()
            .position(|(name, r, _)| name == v.name && *r == region);
        let at = match found {
            Some(i) => i,
            None => {
                let shading = relief::Shading::default();
                let image =
                    render_world_rays(gpu, params, &shading, &v.view, Method::Reference, timer)?;
                self.cast.push((v.name.to_owned(), region, image));
                self.cast.len() - 1
            }
        };
        Ok(&self.cast[at].2)
    }
}

/// The seed's march (`method`, compute or fragment) on `v`, timed as the mesh is, and
/// compared with the reference.
fn march_row(
    gpu: &Gpu,
    params: &WorldParams,
    v: &LandscapeView,
    method: Method,
    options: &Options,
    timer: Option<&GpuTimer>,
    reference: &RayImage,
) -> Result<WorldRow> {
    let size = v.view.size;
    let (Some(path), Some(rays)) = (method.ray_path(), method.ray_method(params.land.octaves))
    else {
        return Err(relief::Error::invalid(
            "method",
            method,
            "a ray-cast method",
        ));
    };
    let shading = relief::Shading::default();
    let caster = RayMarcher::for_scene(&gpu.device, size.0, size.1, RayScene::World)?;
    let region = relief::gpu::world_rays::drawn_region(params, &v.view);
    let ray = relief::gpu::world_rays::WorldRayUniforms::new(params, &v.view, rays, size, region)?;
    let render = relief::gpu::world::render_uniforms(
        params,
        &shading,
        (
            relief::gpu::world_rays::ray_matrix(&v.view),
            region,
            v.view.eye,
        ),
        true,
    );
    caster.prepare_world(&gpu.queue, &render, &ray)?;
    let (times, wall) = measure(gpu, options, timer, |encoder, timer| {
        caster.encode(encoder, path, timer)
    })?;
    let ms = median(times.iter().filter_map(|t| t[Slot::Render as usize]));
    let mut row = WorldRow::rays(
        v.name,
        method,
        params.pixel_error,
        ms,
        median(wall).unwrap_or(0.0),
    );
    let read = |t: &wgpu::Texture| relief::gpu::headless::read_texture(&gpu.device, &gpu.queue, t);
    let image = read(&caster.color)?;
    let distance: Vec<f32> = bytemuck::pod_collect_to_vec(&read(&caster.distance)?);
    row.unresolved = Some(distance.iter().filter(|&&d| d == -2.0).count());
    row.against(reference, &image, Some(&distance), size);
    Ok(row)
}

/// The baseline: a uniform grid at the finest drawn level's spacing over the square the
/// levels cover (what it takes to keep the near error everywhere without levels).
fn uniform_triangles(r: &WorldRow) -> f64 {
    let side = f64::from(r.patch_cells)
        * f64::from(relief::clipmap::PATCHES as u32)
        * 2f64.powi(r.levels.max(1) as i32 - 1);
    2.0 * side * side
}

fn mean_texels(texels: &[u64]) -> f64 {
    texels.iter().sum::<u64>() as f64 / texels.len().max(1) as f64
}

fn mean_slot(times: &[relief::gpu::timing::Timings], slot: Slot) -> Option<f64> {
    (!times.is_empty()).then(|| {
        times
            .iter()
            .map(|t| t[slot as usize].unwrap_or(0.0))
            .sum::<f64>()
            / times.len() as f64
    })
}

fn opt(v: Option<f64>) -> String {
    v.map_or(String::new(), |v| format!("{v:.4}"))
}

/// The rows as CSV, with the device and image size in a comment line.
pub fn csv(rows: &[WorldRow], device: &str, options: &Options) -> String {
    let mut out = format!(
        "# relief bench --world endless on {device}, {}x{}, {} timed frames after {} ms warm-up\n",
        options.width, options.height, options.frames, options.warmup_ms
    );
    out.push_str("view,method,pixel_error,patch_cells,levels,triangles,error_bound_px,measured_max_px,measured_p99_px,uniform_grid_triangles,texels_baked_median,texels_baked_max,texels_baked_mean,render_ms,bake_ms_median,bake_ms_max,bake_ms_mean,wall_ms,flip_mean,flip_p99,missed,extra,wrong_depth,unresolved_rays,flip_3x3_vs_8x8_mean,flip_3x3_vs_8x8_p99,light_ms_mean,light_ms_max,samples,raster\n");
    for r in rows {
        let mesh = r.method.is_mesh();
        // Mesh-only columns are empty for the ray casters.
        let mesh_only = |text: String| if mesh { text } else { String::new() };
        let cov = |f: fn(&Coverage) -> f64| opt(r.coverage.as_ref().map(f));
        let fields = [
            r.view.clone(),
            r.method.to_string(),
            r.pixel_error.to_string(),
            mesh_only(r.patch_cells.to_string()),
            mesh_only(r.levels.to_string()),
            r.triangles.to_string(),
            mesh_only(format!("{:.3}", r.error_bound_px)),
            opt(r.measured.map(|m| m.max)),
            opt(r.measured.map(|m| m.p99)),
            mesh_only(format!("{:.3e}", uniform_triangles(r))),
            r.texels_median.to_string(),
            r.texels_max.to_string(),
            format!("{:.0}", r.texels_mean),
            opt(r.render_ms),
            opt(r.bake_ms),
            opt(r.bake_max_ms),
            opt(r.bake_ms_mean),
            opt(r.wall_ms.is_finite().then_some(r.wall_ms)),
            opt(r.flip.map(|f| f.0)),
            opt(r.flip.map(|f| f.1)),
            cov(|c| c.missed),
            cov(|c| c.extra),
            cov(|c| c.wrong_depth),
            r.unresolved.map_or(String::new(), |u| u.to_string()),
            opt(r.converged.map(|f| f.0)),
            opt(r.converged.map(|f| f.1)),
            opt(r.light_ms_mean),
            opt(r.light_ms_max),
            r.samples.map_or(String::new(), |n| n.to_string()),
            r.raster.map_or(String::new(), |n| n.to_string()),
        ];
        out.push_str(&fields.join(","));
        out.push('\n');
    }
    out
}
