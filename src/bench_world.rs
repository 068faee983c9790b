//! `relief bench --world endless`: the clipmap renderer on landscape views (along the ground
//! to the horizon, grazing over a ridge, high and oblique) over the pixel-error knob, and a
//! flight along a path: triangles, texels baked per frame, the screen-error bound and GPU
//! times (warm-up, then the median), and each image against the reference ray cast of the same
//! view (FLIP, missed and extra pixels). The seed's ray march (compute and fragment) beside
//! them on every view. Written as `landscape.csv`.

use crate::bench::{log_ticks, measure, median, tick_label, Options, CHART_SIZE};
use crate::error::Result;
use crate::gpu::headless::{
    render_samples, render_world_rays, render_world_rays_at, world_depth_metrics, Gpu, Offscreen,
    RayImage, ScreenError, RENDER_SAMPLES,
};
use crate::gpu::raymarch::{RayMarcher, RayScene};
use crate::gpu::timing::{GpuTimer, Slot};
use crate::metrics::{self, Coverage};
use crate::world::WorldParams;
use crate::{Method, World, WorldView};
use glam::DVec3;

/// A named landscape view.
#[derive(Clone, Copy, Debug)]
pub struct LandscapeView {
    /// Its name in the CSV.
    pub name: &'static str,
    /// The camera (size filled in per run).
    pub view: WorldView,
}

/// The benchmark's views of `params`' world at `size`.
pub fn views(params: &WorldParams, size: (u32, u32)) -> Vec<LandscapeView> {
    let land = params.land;
    let fov = 45f32.to_radians();
    let ground = |x: f64, z: f64| land.height_at(x, z);
    // Along the ground: 2 m above it, looking level, to the horizon.
    let eye = DVec3::new(0.0, ground(0.0, 0.0) + 2.0, 0.0);
    let horizon = WorldView::look_at(eye, eye + DVec3::new(1.0, -0.01, 0.2), fov, size);
    // Grazing over a ridge: the highest point on a 4 km line, 5 m above it, looking level.
    let (mut best, mut top) = (0.0, f64::MIN);
    for i in 0..400 {
        let x = 3000.0 + f64::from(i) * 10.0;
        let h = ground(x, 1000.0);
        if h > top {
            (best, top) = (x, h);
        }
    }
    let eye = DVec3::new(best, top + 5.0, 1000.0);
    let ridge = WorldView::look_at(eye, eye + DVec3::new(0.3, -0.02, 1.0), fov, size);
    // High and oblique: 3 km above the ground, 30 degrees down.
    let eye = DVec3::new(-5000.0, ground(-5000.0, 2000.0) + 3000.0, 2000.0);
    let oblique = WorldView::look_at(eye, eye + DVec3::new(0.8, -0.5, 0.33), fov, size);
    vec![
        LandscapeView {
            name: "horizon",
            view: horizon,
        },
        LandscapeView {
            name: "ridge",
            view: ridge,
        },
        LandscapeView {
            name: "oblique",
            view: oblique,
        },
    ]
}

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
    pub raster: Option<crate::Raster>,
}

impl WorldRow {
    /// A row from a measured run: the world's last stats, the texels each frame baked (the
    /// timed frames are the last ones), and the timed frames' GPU and wall times.
    fn measured(
        (view, method): (&str, Method),
        knob: f64,
        s: &crate::WorldStats,
        texels: &[u64],
        times: &[crate::gpu::timing::Timings],
        wall: &[f64],
    ) -> Self {
        let timed = &texels[texels.len().saturating_sub(wall.len())..];
        let slot = |slot: Slot| times.iter().filter_map(move |t| t[slot as usize]);
        // The draw: the host's pass (or the present), and the visibility method's raster and
        // shading before it.
        let draw = times.iter().filter_map(crate::choice::draw_ms);
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
        use crate::Raster::{Compute, Hardware};
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
        for v in views(&p, size) {
            for &(method, samples, raster) in &methods {
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
                world.set_visibility_samples(samples)?;
                world.set_visibility_raster(raster);
                world.set_method(&gpu.device, method)?;
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
                &crate::Shading::default(),
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
    let path = crate::PathCamera::default();
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
        let region = crate::gpu::world_rays::drawn_region(params, &v.view).map(f64::to_bits);
        let found = self
            .cast
            .iter()
            .position(|(name, r, _)| name == v.name && *r == region);
        let at = match found {
            Some(i) => i,
            None => {
                let shading = crate::Shading::default();
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
        return Err(crate::Error::invalid("method", method, "a ray-cast method"));
    };
    let shading = crate::Shading::default();
    let caster = RayMarcher::for_scene(&gpu.device, size.0, size.1, RayScene::World)?;
    let region = crate::gpu::world_rays::drawn_region(params, &v.view);
    let ray = crate::gpu::world_rays::WorldRayUniforms::new(params, &v.view, rays, size, region)?;
    let render = crate::gpu::world::render_uniforms(
        params,
        &shading,
        (
            crate::gpu::world_rays::ray_matrix(&v.view),
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
    let read = |t: &wgpu::Texture| crate::gpu::headless::read_texture(&gpu.device, &gpu.queue, t);
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
        * f64::from(crate::clipmap::PATCHES as u32)
        * 2f64.powi(r.levels.max(1) as i32 - 1);
    2.0 * side * side
}

fn mean_texels(texels: &[u64]) -> f64 {
    texels.iter().sum::<u64>() as f64 / texels.len().max(1) as f64
}

fn mean_slot(times: &[crate::gpu::timing::Timings], slot: Slot) -> Option<f64> {
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

/// Charts the views' rows (not the flight): measured screen error and GPU render time against
/// triangles, one line per view through the knobs, as `stem`.png and `stem`.svg.
pub fn chart(rows: &[WorldRow], title: &str, stem: &std::path::Path) -> Result<()> {
    crate::bench::write_chart(stem, |b| draw(b, rows, title), |b| draw(b, rows, title))
}

fn draw<DB: plotters::prelude::DrawingBackend>(
    backend: DB,
    rows: &[WorldRow],
    title: &str,
) -> std::result::Result<(), String>
where
    DB::ErrorType: 'static,
{
    use plotters::prelude::*;
    let root = backend.into_drawing_area();
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let root = root
        .titled(title, ("sans-serif", 20))
        .map_err(|e| e.to_string())?;
    let (top, bottom) = root.split_vertically(CHART_SIZE.1 / 2);
    let (left, right) = top.split_horizontally(CHART_SIZE.0 / 2);
    let views: Vec<&str> = {
        let mut v: Vec<&str> = Vec::new();
        for r in rows
            .iter()
            .filter(|r| r.measured.is_some() || !r.method.is_mesh())
        {
            if !v.contains(&r.view.as_str()) {
                v.push(&r.view);
            }
        }
        v
    };
    let colors = [
        RGBColor(31, 119, 180),
        RGBColor(214, 39, 40),
        RGBColor(44, 160, 44),
    ];
    let span = |v: &mut dyn Iterator<Item = f64>| {
        let (lo, hi) = v.fold((f64::MAX, f64::MIN), |(a, b), x| (a.min(x), b.max(x)));
        (lo.max(1e-4) / 1.4, hi.max(1e-4) * 1.4)
    };
    let tri = span(
        &mut rows
            .iter()
            .filter(|r| r.measured.is_some())
            .map(|r| r.triangles as f64),
    );
    type Pick = fn(&WorldRow) -> Option<f64>;
    // Each legend where its panel has no points: the error falls with the triangles (top
    // right is empty), the time rises with them (bottom right is).
    let panels: [(
        &DrawingArea<DB, plotters::coord::Shift>,
        &str,
        Pick,
        SeriesLabelPosition,
    ); 2] = [
        (
            &left,
            "measured max screen error, px (log)",
            |r| r.measured.map(|m| m.max),
            SeriesLabelPosition::UpperRight,
        ),
        (
            &right,
            "GPU render time, ms (log)",
            |r| r.render_ms,
            SeriesLabelPosition::LowerRight,
        ),
    ];
    for (area, desc, pick, legend_at) in panels {
        let ys = span(
            &mut rows
                .iter()
                .filter(|r| r.measured.is_some())
                .filter_map(pick),
        );
        let mut chart = ChartBuilder::on(area)
            .margin(16)
            .x_label_area_size(44)
            .y_label_area_size(56)
            .build_cartesian_2d(
                (tri.0..tri.1)
                    .log_scale()
                    .with_key_points(log_ticks(tri.0, tri.1, 4)),
                (ys.0..ys.1)
                    .log_scale()
                    .with_key_points(log_ticks(ys.0, ys.1, 4)),
            )
            .map_err(|e| e.to_string())?;
        chart
            .configure_mesh()
            .x_label_formatter(&|v| count_label(*v))
            .y_label_formatter(&|v| tick_label(*v))
            .x_desc("triangles drawn (log)")
            .y_desc(desc)
            .label_style(("sans-serif", 14))
            .axis_desc_style(("sans-serif", 14))
            .draw()
            .map_err(|e| e.to_string())?;
        let mut placed = Labels::new(chart.plotting_area().get_pixel_range().0.end);
        for (i, view) in views.iter().enumerate() {
            let color = colors[i % colors.len()];
            let pts: Vec<(f64, f64, f64)> = rows
                .iter()
                // The knob's line is the mesh's; the visibility method's rows (the same
                // triangles) are in the panel below.
                .filter(|r| r.view == *view && r.measured.is_some() && r.method == Method::Mesh)
                .filter_map(|r| pick(r).map(|y| (r.triangles as f64, y.max(1e-4), r.pixel_error)))
                .collect();
            chart
                .draw_series(LineSeries::new(
                    pts.iter().map(|p| (p.0, p.1)),
                    color.stroke_width(1),
                ))
                .map_err(|e| e.to_string())?
                .label(*view)
                .legend(move |(x, y)| Circle::new((x + 10, y), 5, color.filled()));
            // Knobs that draw the same mesh land on one point: one label names them all.
            let labels = knob_labels(&pts, |p| chart.backend_coord(&(p.0, p.1)), &mut placed);
            chart
                .draw_series(pts.iter().zip(labels).map(|(p, label)| {
                    let (text, offset) = label.unwrap_or_default();
                    EmptyElement::at((p.0, p.1))
                        + Circle::new((0, 0), 4, color.filled())
                        + Text::new(text, offset, ("sans-serif", 12))
                }))
                .map_err(|e| e.to_string())?;
        }
        crate::bench::legend(&mut chart, legend_at)?;
    }
    accuracy_panel(&bottom, rows, &views, &colors)?;
    root.present().map_err(|e| e.to_string())
}

/// FLIP against the reference over GPU time: every method on every view (the mesh through its
/// knobs), the speed-accuracy picture.
fn accuracy_panel<DB: plotters::prelude::DrawingBackend>(
    area: &plotters::prelude::DrawingArea<DB, plotters::coord::Shift>,
    rows: &[WorldRow],
    views: &[&str],
    colors: &[plotters::prelude::RGBColor],
) -> std::result::Result<(), String>
where
    DB::ErrorType: 'static,
{
    use plotters::prelude::*;
    let pts: Vec<(f64, f64, &WorldRow)> = rows
        .iter()
        .filter_map(|r| Some((r.render_ms?.max(1e-4), r.flip?.0.max(1e-4), r)))
        .collect();
    if pts.is_empty() {
        return Ok(());
    }
    let (x0, x1) = pts
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p.0), b.max(p.0)));
    let (y0, y1) = pts
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p.1), b.max(p.1)));
    // Room on the right for the slowest point's label.
    let (x0, x1, y0, y1) = (x0 / 1.4, x1 * 3.0, y0 / 1.4, y1 * 1.4);
    let mut chart = ChartBuilder::on(area)
        .margin(16)
        .x_label_area_size(44)
        .y_label_area_size(56)
        .build_cartesian_2d(
            (x0..x1).log_scale().with_key_points(log_ticks(x0, x1, 6)),
            (y0..y1).log_scale().with_key_points(log_ticks(y0, y1, 4)),
        )
        .map_err(|e| e.to_string())?;
    chart
        .configure_mesh()
        .x_label_formatter(&|v| tick_label(*v))
        .y_label_formatter(&|v| tick_label(*v))
        .x_desc("GPU time of the frame's render or ray cast, ms (log)")
        .y_desc("FLIP mean vs reference (log)")
        .label_style(("sans-serif", 14))
        .axis_desc_style(("sans-serif", 14))
        .draw()
        .map_err(|e| e.to_string())?;
    let mut placed = Labels::new(chart.plotting_area().get_pixel_range().0.end);
    // The speed issue's goal for a landscape frame, shaded where it lies on the chart, named at
    // its foot (where no point's label may go).
    if x0 < FRAME_GOAL_MS && y0 < FLIP_GOAL {
        let goal = RGBColor(160, 220, 160);
        chart
            .draw_series([Rectangle::new(
                [(x0, y0), (FRAME_GOAL_MS.min(x1), FLIP_GOAL.min(y1))],
                goal.mix(0.35).filled(),
            )])
            .map_err(|e| e.to_string())?;
        let name = format!("goal: ≤ {FRAME_GOAL_MS} ms, FLIP ≤ {FLIP_GOAL}");
        let foot = chart.backend_coord(&(x0, y0));
        if let Some((_, offset)) = placed.place(foot, &name) {
            chart
                .draw_series([
                    EmptyElement::at((x0, y0)) + Text::new(name, offset, ("sans-serif", 12))
                ])
                .map_err(|e| e.to_string())?;
        }
    }
    // Labels by priority, each kept where it overlaps none kept before it: the methods at the
    // default knob first, then the other methods, then the mesh's knobs.
    let mut order: Vec<usize> = (0..pts.len()).collect();
    order.sort_by_key(|&i| {
        let r = pts[i].2;
        match (
            r.method.is_mesh(),
            r.method == Method::Mesh,
            r.pixel_error == 1.0,
        ) {
            (true, false, true) => 0,
            (false, _, _) => 1,
            (true, false, false) => 2,
            _ => 3,
        }
    });
    let mut labels = vec![None; pts.len()];
    for i in order {
        let (x, y, r) = pts[i];
        labels[i] = placed.place(chart.backend_coord(&(x, y)), &accuracy_label(r));
    }
    for (i, view) in views.iter().enumerate() {
        let color = colors[i % colors.len()];
        let mine: Vec<(&(f64, f64, &WorldRow), Placed)> = pts
            .iter()
            .zip(&labels)
            .filter(|(p, _)| p.2.view == *view)
            .map(|(p, l)| (p, l.clone().unwrap_or_default()))
            .collect();
        chart
            .draw_series(mine.into_iter().map(|(p, (text, offset))| {
                EmptyElement::at((p.0, p.1))
                    + Circle::new((0, 0), 4, color.filled())
                    + Text::new(text, offset, ("sans-serif", 12))
            }))
            .map_err(|e| e.to_string())?
            .label(*view)
            .legend(move |(x, y)| Circle::new((x + 10, y), 5, color.filled()));
    }
    // Bottom right: no method is slow and accurate at once.
    crate::bench::legend(&mut chart, SeriesLabelPosition::LowerRight)
}

/// The speed issue's goal for a 1080p landscape frame: this long at most, at this FLIP mean at
/// most (the accuracy panel shades it).
const FRAME_GOAL_MS: f64 = 1.0;
const FLIP_GOAL: f64 = 0.02;

/// What the accuracy panel writes beside a row's point: the mesh's knob, or the method (with
/// its samples, raster and knob where it draws the mesh).
fn accuracy_label(r: &WorldRow) -> String {
    if r.method == Method::Mesh {
        format!("{} px", r.pixel_error)
    } else if r.method.is_mesh() {
        let n = r.samples.unwrap_or(4);
        let compute = if r.raster == Some(crate::Raster::Compute) {
            " compute"
        } else {
            ""
        };
        format!("{} {n}x{compute} {} px", r.method, r.pixel_error)
    } else {
        r.method.to_string()
    }
}

/// A label kept beside a point: its text, and its offset from the point in pixels.
type Placed = (String, (i32, i32));

/// Labels beside a chart's points that overlap no label placed before them, in the pixels of
/// the chart's drawing area: above a point and to its right, or to its left where the right
/// runs past the plotting area's right edge.
struct Labels {
    /// Boxes kept: left, top, right, bottom.
    placed: Vec<[i32; 4]>,
    /// The plotting area's right edge.
    right: i32,
}

impl Labels {
    fn new(right: i32) -> Self {
        Self {
            placed: Vec::new(),
            right,
        }
    }

    /// Where `text` goes beside the point at pixel `at`: the text and its offset from the point,
    /// its box (about 6.5 pixels a character of the charts' 12-pixel type) kept; `None` where
    /// the box would overlap one kept before.
    fn place(&mut self, at: (i32, i32), text: &str) -> Option<Placed> {
        let width = (text.chars().count() as f64 * 6.5).ceil() as i32;
        let dx = if at.0 + 6 + width > self.right {
            -6 - width
        } else {
            6
        };
        let (x, y) = (at.0 + dx, at.1 - 14);
        let b = [x, y, x + width, y + 13];
        let overlaps = |o: &[i32; 4]| b[0] < o[2] && o[0] < b[2] && b[1] < o[3] && o[1] < b[3];
        if self.placed.iter().any(overlaps) {
            return None;
        }
        self.placed.push(b);
        Some((text.to_string(), (dx, -14)))
    }
}

/// The knob labels of one view's points `(triangles, value, knob)`: the knobs of points that
/// land on one pixel joined in one label on the first of them, the others none; each kept
/// only where it overlaps no label `placed` before it.
fn knob_labels(
    pts: &[(f64, f64, f64)],
    at: impl Fn(&(f64, f64, f64)) -> (i32, i32),
    placed: &mut Labels,
) -> Vec<Option<Placed>> {
    let mut labels = vec![None; pts.len()];
    let mut done = vec![false; pts.len()];
    for i in 0..pts.len() {
        if done[i] {
            continue;
        }
        let here = at(&pts[i]);
        let same: Vec<usize> = (i..pts.len())
            .filter(|&j| !done[j] && at(&pts[j]) == here)
            .collect();
        let knobs: Vec<String> = same.iter().map(|&j| pts[j].2.to_string()).collect();
        for j in same {
            done[j] = true;
        }
        labels[i] = placed.place(here, &format!("{} px", knobs.join(", ")));
    }
    labels
}

/// A count as a tick reads it: 500, 2k, 1.5M.
fn count_label(v: f64) -> String {
    let (scaled, unit) = match v.abs() {
        a if a >= 1e6 => (v / 1e6, "M"),
        a if a >= 1e3 => (v / 1e3, "k"),
        _ => (v, ""),
    };
    let text = format!("{scaled:.1}");
    format!("{}{unit}", text.trim_end_matches('0').trim_end_matches('.'))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_label_is_kept_only_where_it_overlaps_none_kept_before() {
        let mut labels = Labels::new(600);
        let first = labels.place((100, 100), "visibility 1x compute 1 px");
        assert_eq!(first.map(|l| l.1), Some((6, -14)));
        // Beside it on the same line, and just under it: both overlap.
        assert!(labels.place((150, 102), "hybrid").is_none());
        assert!(labels.place((100, 110), "8 px").is_none());
        // Far enough below, and far to the right: kept.
        assert!(labels.place((100, 114), "8 px").is_some());
        assert!(labels.place((400, 100), "8 px").is_some());
        // At the right edge it goes to the left of its point (4 characters: 26 pixels).
        assert_eq!(
            labels.place((590, 300), "8 px").map(|l| l.1),
            Some((-32, -14))
        );
        assert_eq!(labels.placed.len(), 4);
    }

    /// The rows of a landscape benchmark run on an H100 (tests/data, an earlier run than
    /// docs/results/landscape-frame.md's): what the chart needs of each.
    fn committed_rows() -> Vec<WorldRow> {
        let csv = include_str!("../tests/data/landscape-h100.csv");
        let mut lines = csv.lines().filter(|l| !l.starts_with('#'));
        let header: Vec<&str> = lines.next().expect("header").split(',').collect();
        let col = |name: &str| header.iter().position(|h| *h == name).expect(name);
        let num = |cells: &[&str], name: &str| cells[col(name)].parse::<f64>().ok();
        lines
            .map(|line| {
                let c: Vec<&str> = line.split(',').collect();
                let measured = num(&c, "measured_max_px").map(|max| ScreenError {
                    max,
                    p99: num(&c, "measured_p99_px").unwrap_or(max),
                    pixels: 1,
                });
                WorldRow {
                    view: c[col("view")].to_string(),
                    method: Method::from_name(c[col("method")]).expect("method"),
                    pixel_error: num(&c, "pixel_error").expect("knob"),
                    patch_cells: 0,
                    levels: 0,
                    triangles: num(&c, "triangles").unwrap_or(0.0) as u64,
                    error_bound_px: 0.0,
                    measured,
                    texels_median: 0,
                    texels_max: 0,
                    render_ms: num(&c, "render_ms"),
                    bake_ms: None,
                    bake_max_ms: None,
                    wall_ms: 0.0,
                    texels_mean: 0.0,
                    bake_ms_mean: None,
                    flip: num(&c, "flip_mean").zip(num(&c, "flip_p99")),
                    coverage: None,
                    unresolved: None,
                    converged: None,
                    light_ms_mean: None,
                    light_ms_max: None,
                    samples: num(&c, "samples").map(|n| n as u32),
                    raster: match c[col("raster")] {
                        "compute" => Some(crate::Raster::Compute),
                        "hardware" => Some(crate::Raster::Hardware),
                        _ => None,
                    },
                }
            })
            .collect()
    }

    #[test]
    fn the_committed_benchmark_charts() {
        let rows = committed_rows();
        assert!(rows.len() > 60, "{} rows", rows.len());
        let dir = std::env::temp_dir().join(format!("relief-chart-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let stem = dir.join("landscape");
        chart(&rows, "the committed benchmark", &stem).unwrap();
        for ext in ["png", "svg"] {
            let size = std::fs::metadata(stem.with_extension(ext)).unwrap().len();
            assert!(size > 10_000, "{ext}: {size} bytes");
        }
        let svg = std::fs::read_to_string(stem.with_extension("svg")).unwrap();
        assert!(
            svg.contains("goal: ≤ 1 ms, FLIP ≤ 0.02"),
            "the goal is drawn"
        );
        assert!(
            svg.contains("0.5, 1, 2, 4 px"),
            "the knobs on one point share a label"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn knobs_on_one_point_share_one_label() {
        // Four knobs drawing the same mesh, then one elsewhere.
        let pts = [
            (5.9e6, 0.8, 0.5),
            (5.9e6, 0.8, 1.0),
            (5.9e6, 0.8, 2.0),
            (5.9e6, 0.8, 4.0),
            (1.6e6, 3.7, 8.0),
        ];
        let at = |p: &(f64, f64, f64)| ((p.0 / 1e4) as i32, (p.1 * 100.0) as i32);
        let labels = knob_labels(&pts, at, &mut Labels::new(10_000));
        let text = |i: usize| labels[i].as_ref().map(|l| l.0.as_str());
        assert_eq!(text(0), Some("0.5, 1, 2, 4 px"));
        assert!(labels[1..4].iter().all(Option::is_none));
        assert_eq!(text(4), Some("8 px"));
    }

    #[test]
    fn counts_read_as_counts() {
        assert_eq!(super::count_label(2000.0), "2k");
        assert_eq!(super::count_label(1_500_000.0), "1.5M");
        assert_eq!(super::count_label(500.0), "500");
        assert_eq!(super::count_label(0.0), "0");
    }
}
