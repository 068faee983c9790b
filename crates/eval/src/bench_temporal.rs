//! `relief bench --world endless --only temporal` and `--only reference`: the temporal service
//! ([`relief::World::set_temporal`]) on the named and the random views.
//!
//! - **reference**: the reference ray cast at 3x3, 4x4, 6x6 and 8x8 rays a pixel, each against
//!   the next (about twice the rays): where the reference stops changing.
//! - **temporal**: for each view, the default method (`relief render`'s choice on a fast GPU:
//!   visibility, one sample a pixel, rasterised in compute) accumulating a still view: FLIP of
//!   1, 4, 16 and 64 frames against its own 256-frame mean (convergence), the 256-frame mean
//!   against the reference (bias) and 1 and 16 frames against the reference; while moving (the
//!   fly-through path, and 90 degree a second turns at 60 frames a second), frames against the
//!   reference of that frame, with and without the service; the resolve's GPU time and memory.

use crate::bench::{measure, Options};
use crate::metrics::{image_error, median, rgb};
use crate::views::{random_views, views, LandscapeView};
use relief::error::Result;
use relief::gpu::headless::{render_samples, render_world_rays_at, Gpu, Offscreen};
use relief::gpu::timing::{GpuTimer, Slot};
use relief::world::WorldParams;
use relief::{Method, MethodConfig, Raster, Shading, Temporal, World, WorldView};

/// Rays a pixel per side of the reference the temporal measurements are against (chosen by
/// the `reference` part: see docs/results/temporal.md).
pub const REFERENCE_SIDE: u32 = 6;

/// The casts the `reference` part compares, each against the next: `(side, passes)`, a cast of
/// `side` x `side` rays a pixel repeated `passes` times through sub-pixel offsets of its grid
/// (the Halton sequence), averaged in linear light ([`reference_rays`]): 16 to 256 rays a
/// pixel, each twice the last.
pub const REFERENCE_LADDER: [(u32, u32); 5] = [(4, 1), (4, 2), (4, 4), (4, 8), (4, 16)];

/// [`REFERENCE_LADDER`] in `--quick`.
pub const QUICK_LADDER: [(u32, u32); 2] = [(2, 1), (2, 2)];

/// Accumulated frame counts measured against the 256-frame mean.
pub const FRAME_COUNTS: [u32; 4] = [1, 4, 16, 64];

/// The frame count every count is measured against.
pub const CONVERGED_FRAMES: u32 = 256;

/// The method measured: what `relief render --method auto` picks on a GPU with few raster
/// units (the H100).
pub fn method() -> MethodConfig {
    MethodConfig::new(Method::Visibility)
        .with_samples(1)
        .with_raster(Raster::Compute)
}

/// One view's still accumulation.
#[derive(Clone, Debug)]
pub struct StillRow {
    /// The view.
    pub view: String,
    /// FLIP of [`FRAME_COUNTS`] frames against the [`CONVERGED_FRAMES`]-frame mean.
    pub convergence: [f64; FRAME_COUNTS.len()],
    /// FLIP of [`FRAME_COUNTS`] frames and the converged mean against the reference.
    pub against_reference: [f64; FRAME_COUNTS.len() + 1],
}

/// One moving frame against its reference.
#[derive(Clone, Debug)]
pub struct MovingRow {
    /// `flight` (the fly-through path) or `turn <view>`.
    pub motion: String,
    /// Frames since the motion began.
    pub frame: u32,
    /// FLIP with the service, then without.
    pub flip: [f64; 2],
}

/// One reference against the next.
#[derive(Clone, Debug)]
pub struct ReferenceRow {
    /// The view.
    pub view: String,
    /// Rays a pixel of the coarser and the finer cast.
    pub rays: [u32; 2],
    /// FLIP of the coarser against the finer.
    pub flip: f64,
}

/// Rays a pixel per side of the reference the `temporal` part measures against.
pub fn reference_side(quick: bool) -> u32 {
    if quick {
        3
    } else {
        REFERENCE_SIDE
    }
}

pub(crate) fn reference(
    gpu: &Gpu,
    params: &WorldParams,
    view: &WorldView,
    side: u32,
) -> Result<Vec<u8>> {
    let shading = Shading::default();
    let image = render_world_rays_at(gpu, params, &shading, view, Method::Reference, side, None)?;
    Ok(rgb(&image.rgba))
}

/// `view` cast by the reference at `side` x `side` rays a pixel, `passes` times through the
/// sub-pixel offsets [`relief::temporal::jitter`]`(1..=passes)` of that grid (in units of its
/// spacing), averaged in linear light: `passes * side * side` rays a pixel, each pass's grid
/// shifted, so that rays fill each pixel more evenly than one finer regular grid would (which a
/// texture's largest side also bounds: 8 x 8 rays at 1920x1080). RGB, 8 bits a channel.
pub fn reference_rays(
    gpu: &Gpu,
    params: &WorldParams,
    view: &WorldView,
    (side, passes): (u32, u32),
) -> Result<Vec<u8>> {
    let lut: Vec<f64> = (0..=255u8)
        .map(|c| f64::from(relief::params::srgb_to_linear(f32::from(c) / 255.0)))
        .collect();
    let mut sum = vec![0.0f64; (view.size.0 * view.size.1 * 3) as usize];
    for pass in 1..=passes.max(1) {
        let [x, y] = relief::temporal::jitter(pass);
        let offset = [x / side as f32, y / side as f32];
        let shifted = WorldView {
            crop: relief::temporal::jitter_matrix(offset, view.size) * view.crop,
            ..*view
        };
        for (s, &c) in sum.iter_mut().zip(&reference(gpu, params, &shifted, side)?) {
            *s += lut[usize::from(c)];
        }
    }
    let n = f64::from(passes.max(1));
    Ok(sum
        .into_iter()
        .map(|l| {
            let l = l / n;
            let c = if l <= 0.003_130_8 {
                l * 12.92
            } else {
                1.055 * l.powf(1.0 / 2.4) - 0.055
            };
            (c * 255.0).round().clamp(0.0, 255.0) as u8
        })
        .collect())
}

/// The `reference` part: each of `chosen` (the named views and the first random one where
/// `None`) cast at each of [`REFERENCE_LADDER`] ([`QUICK_LADDER`] in `quick`, on the named
/// views), each against the next (the finest is about a minute a view at 1080p on an H100).
pub fn run_reference(
    gpu: &Gpu,
    params: &WorldParams,
    options: &Options,
    (quick, chosen): (bool, Option<&[LandscapeView]>),
    (mut progress, mut sink): (impl FnMut(&str), impl FnMut(&ReferenceRow) -> Result<()>),
) -> Result<Vec<ReferenceRow>> {
    let size = (options.width, options.height);
    let mut rows = Vec::new();
    let here = match chosen {
        Some(v) => v.to_vec(),
        None => {
            let mut here = views(params, size);
            if !quick {
                here.extend(random_views(params, size).into_iter().take(1));
            }
            here
        }
    };
    let ladder: &[(u32, u32)] = if quick {
        &QUICK_LADDER
    } else {
        &REFERENCE_LADDER
    };
    let rays = |(side, passes): (u32, u32)| side * side * passes;
    for v in here {
        let p = v.params(params);
        let mut last: Option<Vec<u8>> = None;
        for (i, &rung) in ladder.iter().enumerate() {
            progress(&format!(
                "{}: the reference at {} rays a pixel",
                v.name,
                rays(rung)
            ));
            let cast = reference_rays(gpu, &p, &v.view, rung)?;
            if let Some(coarser) = &last {
                // Each pair the moment it is cast: a run cut short keeps what it measured.
                let row = ReferenceRow {
                    view: v.name.to_owned(),
                    rays: [rays(ladder[i - 1]), rays(rung)],
                    flip: image_error(&cast, coarser, size.0, size.1).0,
                };
                sink(&row)?;
                rows.push(row);
            }
            last = Some(cast);
        }
    }
    Ok(rows)
}

/// What the `temporal` part measured.
#[derive(Clone, Debug, Default)]
pub struct TemporalRun {
    /// Each view, still.
    pub still: Vec<StillRow>,
    /// Moving frames.
    pub moving: Vec<MovingRow>,
    /// The resolve's GPU time (median) and the whole draw's with and without the service,
    /// milliseconds, on the first named view.
    pub resolve_ms: Option<f64>,
    /// The draw's median with the service, and without, milliseconds.
    pub draw_ms: [Option<f64>; 2],
    /// The same for the forward mesh as the window draws it (into 1-sample targets with the
    /// service, 4-sample ones without): its resolve, its draw with the service and without,
    /// and its own image and histories, bytes.
    pub mesh: (Option<f64>, [Option<f64>; 2], u64),
    /// GPU memory of the histories at the measured size, bytes.
    pub history_bytes: u64,
    /// Rays a pixel per side of the reference.
    pub reference_side: u32,
    /// Frames of the converged mean.
    pub converged: u32,
}

fn new_world(gpu: &Gpu, params: &WorldParams, frames: u32) -> Result<World> {
    drawn_as(gpu, params, frames, (method(), 1))
}

/// A world drawing as `config` says into targets of `samples` a pixel, accumulating up to
/// `frames` frames.
fn drawn_as(
    gpu: &Gpu,
    params: &WorldParams,
    frames: u32,
    (config, samples): (MethodConfig, u32),
) -> Result<World> {
    let targets = Offscreen::targets(samples);
    let mut world = World::new(&gpu.device, &gpu.queue, targets, *params)?;
    world.set_method(&gpu.device, config)?;
    world.set_temporal(&gpu.device, Temporal { frames })?;
    Ok(world)
}

/// Where the `temporal` part writes as it goes: each row the moment it is measured (a run
/// cut short keeps what it measured), and what it says of its progress.
pub trait Sink {
    /// A view measured still.
    fn still(&mut self, row: &StillRow) -> Result<()>;
    /// A frame measured moving.
    fn moving(&mut self, row: &MovingRow) -> Result<()>;
    /// A line of progress.
    fn progress(&mut self, what: &str);
}

/// The `temporal` part: the cost first, then the named views still, the motions, and the
/// random views still (the order of what matters most, should a run be cut short); or, where
/// views are `chosen`, the cost and those views still.
pub fn run_temporal(
    gpu: &Gpu,
    params: &WorldParams,
    options: &Options,
    (quick, chosen): (bool, Option<&[LandscapeView]>),
    sink: &mut impl Sink,
) -> Result<TemporalRun> {
    let size = (options.width, options.height);
    let target = Offscreen::new(&gpu.device, size.0, size.1, 1)?;
    let side = reference_side(quick);
    let converged = if quick { 64 } else { CONVERGED_FRAMES };
    let mut run = TemporalRun {
        reference_side: side,
        converged,
        history_bytes: relief::temporal::history_bytes(size),
        ..Default::default()
    };
    cost(gpu, params, options, &target, &mut run)?;
    sink.progress("the cost");
    if let Some(chosen) = chosen {
        for v in chosen {
            let row = still(gpu, params, (&target, side, converged), v, sink)?;
            sink.still(&row)?;
            run.still.push(row);
        }
        return Ok(run);
    }
    let named = views(params, size);
    for v in &named {
        let row = still(gpu, params, (&target, side, converged), v, sink)?;
        sink.still(&row)?;
        run.still.push(row);
    }
    run.moving = moving(gpu, params, (&target, side, quick), sink)?;
    if !quick {
        for v in &random_views(params, size) {
            let row = still(gpu, params, (&target, side, converged), v, sink)?;
            sink.still(&row)?;
            run.still.push(row);
        }
    }
    Ok(run)
}

/// The resolve's time and the draw's, with the service and without, on the first named view:
/// of the method measured, and of the forward mesh as the window draws it (its history
/// anti-aliases a 1-sample target; without it, 4 samples a pixel).
fn cost(
    gpu: &Gpu,
    params: &WorldParams,
    options: &Options,
    target: &Offscreen,
    run: &mut TemporalRun,
) -> Result<()> {
    let size = (target.width, target.height);
    let timer = GpuTimer::new(&gpu.device, &gpu.queue);
    let first = views(params, size)[0];
    let mesh = MethodConfig::MESH;
    let mesh_4x = Offscreen::new(&gpu.device, size.0, size.1, render_samples(mesh.method))?;
    let four = render_samples(mesh.method);
    let drawn = [
        (method(), [(target, 1), (target, 1)]),
        (mesh, [(target, 1), (&mesh_4x, four)]),
    ];
    for (config, targets) in drawn {
        let mut resolve_ms = None;
        let mut draw_ms = [None; 2];
        let mut bytes = 0;
        for (i, frames) in [16, 1].into_iter().enumerate() {
            let (target, samples) = targets[i];
            let mut world = drawn_as(gpu, params, frames, (config, samples))?;
            target.accumulate_world(gpu, &mut world, &first.view, 0)?;
            let (times, _) = measure(gpu, options, timer.as_ref(), |encoder, timer| {
                let _ = world.prepare_timed(&gpu.device, &gpu.queue, encoder, &first.view, timer);
                target.draw(encoder, &world, wgpu::Color::BLACK, timer);
            })?;
            draw_ms[i] = median(times.iter().filter_map(relief::choice::draw_ms));
            if frames > 1 {
                resolve_ms = median(times.iter().filter_map(|t| t[Slot::Resolve as usize]));
                bytes = world.method_bytes();
            }
        }
        if config == mesh {
            run.mesh = (resolve_ms, draw_ms, bytes);
        } else {
            (run.resolve_ms, run.draw_ms) = (resolve_ms, draw_ms);
        }
    }
    Ok(())
}

/// One view still: `converged` frames accumulated, kept at [`FRAME_COUNTS`], and the
/// reference at `side` x `side` rays a pixel.
fn still(
    gpu: &Gpu,
    params: &WorldParams,
    (target, side, converged): (&Offscreen, u32, u32),
    v: &LandscapeView,
    sink: &mut impl Sink,
) -> Result<StillRow> {
    let size = (target.width, target.height);
    let flip = |a: &[u8], b: &[u8]| image_error(a, &rgb(b), size.0, size.1).0;
    let p = v.params(params);
    let mut world = new_world(gpu, &p, converged)?;
    let mut kept = Vec::new();
    target.accumulate_world(gpu, &mut world, &v.view, 0)?;
    for n in 1..=converged {
        if FRAME_COUNTS.contains(&n) || n == converged {
            kept.push(target.render_world(gpu, &mut world, &v.view, None)?.0);
        } else {
            target.advance_world(gpu, &mut world, &v.view, 1)?;
        }
    }
    sink.progress(&format!("{}: {converged} frames", v.name));
    let truth = reference(gpu, &p, &v.view, side)?;
    sink.progress(&format!("{}: the reference", v.name));
    let last = rgb(kept.last().expect("the converged frame"));
    let mut row = StillRow {
        view: v.name.to_owned(),
        convergence: [0.0; FRAME_COUNTS.len()],
        against_reference: [0.0; FRAME_COUNTS.len() + 1],
    };
    for (i, image) in kept.iter().take(FRAME_COUNTS.len()).enumerate() {
        row.convergence[i] = flip(&last, image);
        row.against_reference[i] = flip(&truth, image);
    }
    row.against_reference[FRAME_COUNTS.len()] = flip(&truth, kept.last().unwrap_or(&last));
    Ok(row)
}

/// A camera along a motion: the view of frame k.
type Camera<'a> = Box<dyn Fn(u32) -> WorldView + 'a>;

/// Frames along the fly-through path and under 90 degree a second turns, at 60 a second,
/// against the reference of each, with the service and without.
fn moving(
    gpu: &Gpu,
    params: &WorldParams,
    (target, side, quick): (&Offscreen, u32, bool),
    sink: &mut impl Sink,
) -> Result<Vec<MovingRow>> {
    let size = (target.width, target.height);
    let dt = 1.0 / 60.0;
    let frames = if quick { 8 } else { 90 };
    let every = if quick { 4 } else { 30 };
    let path = relief::PathCamera::default();
    let land = params.land;
    let flight = move |k: u32| path.view(move |x, z| land.height_at(x, z), f64::from(k) * dt, size);
    let turn = |base: WorldView| {
        move |k: u32| {
            let a = (90.0 * f64::from(k) * dt).to_radians();
            let f = base.forward.as_dvec3();
            let r = glam::DVec3::new(
                f.x * a.cos() - f.z * a.sin(),
                f.y,
                f.x * a.sin() + f.z * a.cos(),
            );
            WorldView::look_at(base.eye, base.eye + r, base.fov_y, size)
        }
    };
    let named = views(params, size);
    let motions: Vec<(String, Camera<'_>)> = vec![
        ("flight".to_owned(), Box::new(flight)),
        (
            format!("turn {}", named[0].name),
            Box::new(turn(named[0].view)),
        ),
    ];
    let mut rows = Vec::new();
    for (name, at) in motions {
        let mut on = new_world(gpu, params, relief::temporal::INTERACTIVE_FRAMES)?;
        let mut off = new_world(gpu, params, 1)?;
        for k in 0..frames {
            let view = at(k);
            if k > 0 && k % every == 0 || k + 1 == frames {
                let image = target.render_world(gpu, &mut on, &view, None)?.0;
                let plain = target.render_world(gpu, &mut off, &view, None)?.0;
                let truth = reference(gpu, params, &view, side)?;
                let row = MovingRow {
                    motion: name.clone(),
                    frame: k,
                    flip: [
                        image_error(&truth, &rgb(&image), size.0, size.1).0,
                        image_error(&truth, &rgb(&plain), size.0, size.1).0,
                    ],
                };
                sink.moving(&row)?;
                sink.progress(&format!("{name}: frame {k}"));
                rows.push(row);
            } else {
                // Drawn and not read back: the window's frame.
                target.accumulate_frame(gpu, &mut on, &view)?;
            }
        }
    }
    Ok(rows)
}

/// `temporal.csv`'s header: the comment line and the columns.
pub fn still_header(device: &str, size: (u32, u32), side: u32) -> String {
    let mut out = format!(
        "# relief bench --world endless --only temporal on {device} at {}x{}: the default method \
         (visibility, 1 sample a pixel rasterised in compute) accumulating a still view; FLIP \
         of n frames against its own mean of many (256 at 1080p, 64 in --quick), and against the \
         reference ({side}x{side} rays a pixel)\nview",
        size.0, size.1
    );
    for n in FRAME_COUNTS {
        out.push_str(&format!(",flip_{n}_vs_converged"));
    }
    for n in FRAME_COUNTS {
        out.push_str(&format!(",flip_{n}_vs_reference"));
    }
    out.push_str(",flip_converged_vs_reference\n");
    out
}

/// One line of `temporal.csv`.
pub fn still_line(r: &StillRow) -> String {
    let mut out = r.view.clone();
    for v in r.convergence.iter().chain(&r.against_reference) {
        out.push_str(&format!(",{v:.5}"));
    }
    out.push('\n');
    out
}

/// `temporal-moving.csv`'s header.
pub fn moving_header(device: &str, size: (u32, u32)) -> String {
    format!(
        "# relief bench --world endless --only temporal on {device} at {}x{}: frames while \
         moving at 60 a second, against the reference of each; the service's history holds \
         {} frames\nmotion,frame,flip_with_service,flip_without\n",
        size.0,
        size.1,
        relief::temporal::INTERACTIVE_FRAMES
    )
}

/// One line of `temporal-moving.csv`.
pub fn moving_line(r: &MovingRow) -> String {
    format!(
        "{},{},{:.5},{:.5}\n",
        r.motion, r.frame, r.flip[0], r.flip[1]
    )
}

/// `reference.csv`'s header: the comment line and the columns.
pub fn reference_header(device: &str, size: (u32, u32)) -> String {
    format!(
        "# relief bench --world endless --only reference on {device} at {}x{}: the reference \
         cast at n rays a pixel (4x4-ray grids through sub-pixel offsets, averaged) against the \
         next\nview,rays,next_rays,flip\n",
        size.0, size.1
    )
}

/// One line of `reference.csv`.
pub fn reference_line(r: &ReferenceRow) -> String {
    format!("{},{},{},{:.5}\n", r.view, r.rays[0], r.rays[1], r.flip)
}

/// Summary lines: the goals against what was measured.
pub fn summary(run: &TemporalRun) -> Vec<String> {
    let worst = |f: &dyn Fn(&StillRow) -> f64| {
        run.still
            .iter()
            .map(|r| (f(r), r.view.as_str()))
            .fold((0.0, ""), |a, b| if b.0 > a.0 { b } else { a })
    };
    let i16 = FRAME_COUNTS.iter().position(|&n| n == 16).unwrap_or(2);
    let (c, cv) = worst(&|r| r.convergence[i16]);
    let (d, dv) = worst(&|r| r.against_reference[i16]);
    let mut lines = vec![
        format!(
            "16 frames against the {}-frame mean: worst {c:.4} ({cv}); goal 0.005",
            run.converged
        ),
        format!("16 frames against the reference: worst {d:.4} ({dv}); goal 0.01"),
    ];
    if let Some(m) = run
        .moving
        .iter()
        .map(|r| (r.flip[0], r))
        .max_by(|a, b| a.0.total_cmp(&b.0))
    {
        lines.push(format!(
            "moving, against each frame's reference: worst {:.4} ({} frame {}); goal 0.02",
            m.0, m.1.motion, m.1.frame
        ));
    }
    lines.push(format!(
        "the resolve: {} ms a frame (goal 0.1), the draw {} ms with the service and {} ms \
         without; histories {:.1} MiB",
        run.resolve_ms.map_or("-".into(), |v| format!("{v:.3}")),
        run.draw_ms[0].map_or("-".into(), |v| format!("{v:.3}")),
        run.draw_ms[1].map_or("-".into(), |v| format!("{v:.3}")),
        run.history_bytes as f64 / f64::from(1u32 << 20)
    ));
    let (resolve, [with, without], bytes) = run.mesh;
    lines.push(format!(
        "the forward mesh as the window draws it: {} ms with the service into 1-sample \
         targets (its resolve {} ms), {} ms without it into 4-sample ones; its own image and \
         histories {:.1} MiB",
        with.map_or("-".into(), |v| format!("{v:.3}")),
        resolve.map_or("-".into(), |v| format!("{v:.3}")),
        without.map_or("-".into(), |v| format!("{v:.3}")),
        bytes as f64 / f64::from(1u32 << 20)
    ));
    lines
}

/// `temporal.svg` and `.png`: FLIP against the 256-frame mean over the frames accumulated, a
/// line per view (the named views in colour, the random ones grey).
pub fn chart(rows: &[StillRow], stem: &std::path::Path) -> Result<()> {
    crate::chart::write_chart(stem, |b| draw(b, rows), |b| draw(b, rows))
}

fn draw<DB: plotters::prelude::DrawingBackend>(
    backend: DB,
    rows: &[StillRow],
) -> std::result::Result<(), String>
where
    DB::ErrorType: 'static,
{
    use plotters::prelude::*;
    let root = backend.into_drawing_area();
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let values = rows.iter().flat_map(|r| r.convergence);
    let lo = values
        .clone()
        .filter(|v| *v > 0.0)
        .fold(f64::MAX, f64::min)
        .min(0.004);
    let hi = values.fold(0.0, f64::max).max(0.02);
    let mut chart = ChartBuilder::on(&root)
        .caption(
            "relief: a still view converging (FLIP against its own mean of many frames)",
            ("sans-serif", 20),
        )
        .margin(20)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d((0.8f64..80.0).log_scale(), (lo * 0.8..hi * 1.2).log_scale())
        .map_err(|e| e.to_string())?;
    chart
        .configure_mesh()
        .x_desc("frames accumulated")
        .y_desc("FLIP")
        .x_labels(8)
        .x_label_formatter(&|v| crate::chart::tick_label(*v))
        .y_label_formatter(&|v| crate::chart::tick_label(*v))
        .draw()
        .map_err(|e| e.to_string())?;
    let colors = [
        RGBColor(31, 119, 180),
        RGBColor(214, 39, 40),
        RGBColor(44, 160, 44),
    ];
    let mut named = 0;
    for r in rows {
        let points: Vec<(f64, f64)> = FRAME_COUNTS
            .iter()
            .zip(r.convergence)
            .map(|(&n, v)| (f64::from(n), v.max(lo)))
            .collect();
        let random = crate::views::RANDOM_VIEWS.contains(&r.view.as_str());
        let color = if random {
            RGBColor(170, 170, 170)
        } else {
            named += 1;
            colors[(named - 1) % colors.len()]
        };
        let series = chart
            .draw_series(LineSeries::new(points, color.stroke_width(2)))
            .map_err(|e| e.to_string())?;
        if !random {
            series
                .label(r.view.clone())
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color));
        }
    }
    chart
        .draw_series(std::iter::once(PathElement::new(
            vec![(0.8, 0.005), (80.0, 0.005)],
            BLACK.stroke_width(1),
        )))
        .map_err(|e| e.to_string())?
        .label("goal after 16 frames: 0.005 (random views grey)")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLACK));
    crate::chart::legend(&mut chart, SeriesLabelPosition::UpperRight)
}

/// The rows of a `temporal.csv` ([`still_header`], [`still_line`]).
pub fn parse_still_csv(text: &str) -> std::result::Result<Vec<StillRow>, String> {
    let columns = 2 * FRAME_COUNTS.len() + 2;
    text.lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with("view,") && !l.trim().is_empty())
        .map(|line| {
            let cells: Vec<&str> = line.split(',').collect();
            if cells.len() != columns {
                return Err(format!("{columns} columns expected: {line}"));
            }
            let number = |i: usize| {
                cells[i]
                    .trim()
                    .parse::<f64>()
                    .map_err(|e| format!("{}: {e}", cells[i]))
            };
            let mut row = StillRow {
                view: cells[0].to_owned(),
                convergence: [0.0; FRAME_COUNTS.len()],
                against_reference: [0.0; FRAME_COUNTS.len() + 1],
            };
            for i in 0..FRAME_COUNTS.len() {
                row.convergence[i] = number(1 + i)?;
            }
            for i in 0..=FRAME_COUNTS.len() {
                row.against_reference[i] = number(1 + FRAME_COUNTS.len() + i)?;
            }
            Ok(row)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_temporal_csv_reads_back_as_written() {
        let row = StillRow {
            view: "ridge".into(),
            convergence: [0.1, 0.2, 0.3, 0.4],
            against_reference: [0.5, 0.6, 0.7, 0.8, 0.9],
        };
        let text = still_header("a GPU", (8, 4), 3) + &still_line(&row);
        let back = parse_still_csv(&text).unwrap();
        assert_eq!(back.len(), 1);
        assert_eq!(back[0].view, "ridge");
        assert_eq!(back[0].convergence, row.convergence);
        assert_eq!(back[0].against_reference, row.against_reference);
        assert!(parse_still_csv("ridge,1,2\n").is_err());
    }
}
