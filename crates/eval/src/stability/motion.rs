//! The motion axis of `relief stability`: the endless world under a moving eye. Levels of a
//! clipmap snap to new origins as the eye moves and are baked in strips within a per-frame
//! budget, so two things can go wrong that no still frame shows: a level's snap changes the
//! picture at once (a *pop*; the morph between levels exists to prevent it), and a fast eye
//! uncovers ground faster than the budget bakes it (levels wait undrawn: *baking falls
//! behind*). The eye flies a straight line at a constant height over the ground below it at
//! each speed (metres a frame), drawn frame by frame as a window draws it
//! ([`relief::gpu::headless::Offscreen::render_world_budgeted`]), and the sweep measures:
//!
//! - **popping**: the largest FLIP between consecutive frames over their median (motion alone
//!   changes each frame about equally; a pop stands out);
//! - **falling behind**: frames drawn with texels still unbaked, and the most waiting.
//!
//! The mesh flies at each knob with the morph on, and at the world's knob with it off; the
//! visibility method and the hybrid (one sample a pixel) fly at the world's knob with the morph
//! on: the first shades the same raster in compute, the second draws the continuous surface,
//! refined from the levels' raised mesh.

use crate::metrics;
use glam::DVec3;
use relief::error::Result;
use relief::gpu::headless::{Gpu, Offscreen};
use relief::gpu::world::World;
use relief::method::Method;
use relief::world::WorldParams;
use relief::WorldView;
use std::fmt::Write as _;

/// What the motion sweep measures with.
#[derive(Clone, Debug, PartialEq)]
pub struct MotionOptions {
    /// Eye speeds, metres a frame.
    pub speeds: Vec<f64>,
    /// LOD knobs (pixel error) besides the world's own.
    pub knobs: Vec<f64>,
    /// Most texels baked a frame ([`relief::gpu::world::DEFAULT_BAKE_BUDGET`], as a window).
    pub budget: u64,
    /// Frames per flight.
    pub frames: usize,
    /// Image size.
    pub size: (u32, u32),
    /// The eye's height over the ground below it, metres.
    pub height: f64,
}

impl MotionOptions {
    /// The full sweep: 1 to 4096 m a frame (60 m/s to Mach 700 at 60 frames a second), the
    /// world's knob and 4 px, 90 frames at 480x270, 150 m over the ground.
    pub fn full() -> Self {
        Self {
            speeds: vec![1.0, 8.0, 64.0, 512.0, 4096.0],
            knobs: vec![4.0],
            budget: relief::gpu::world::DEFAULT_BAKE_BUDGET,
            frames: 90,
            size: (480, 270),
            height: 150.0,
        }
    }

    /// `--quick`: small enough for the tests.
    pub fn quick() -> Self {
        Self {
            speeds: vec![4.0, 256.0],
            knobs: Vec::new(),
            budget: relief::gpu::world::DEFAULT_BAKE_BUDGET,
            frames: 16,
            size: (96, 54),
            height: 150.0,
        }
    }
}

/// One flight: a method, a speed, a knob, the morph on or off.
#[derive(Clone, Debug, PartialEq)]
pub struct MotionRow {
    /// The mesh, the visibility method or the hybrid.
    pub method: Method,
    /// Metres a frame.
    pub speed: f64,
    /// The LOD knob, pixels.
    pub knob: f64,
    /// Whether levels morph into each other.
    pub morphing: bool,
    /// Frames drawn after the first.
    pub frames: usize,
    /// Consecutive frames' FLIP: median and largest.
    pub flip_median: f64,
    pub flip_max: f64,
    /// Frames drawn with texels still waiting to be baked.
    pub frames_behind: usize,
    /// The most texels waiting at a frame.
    pub pending_max: u64,
}

impl MotionRow {
    /// The largest frame-to-frame change over the median one.
    pub fn pop(&self) -> f64 {
        self.flip_max / self.flip_median.max(1e-6)
    }
}

/// The eye `t` metres along the flight over `params`' world.
fn eye_at(params: &WorldParams, height: f64, t: f64, size: (u32, u32)) -> WorldView {
    let dir = DVec3::new(0.94, 0.0, 0.34);
    let (x, z) = (3.0 + dir.x * t, -7.0 + dir.z * t);
    let eye = DVec3::new(x, params.land.height_at(x, z) + height, z);
    WorldView::look_at(
        eye,
        eye + dir + DVec3::new(0.0, -0.3, 0.0),
        50f32.to_radians(),
        size,
    )
}

/// Sweeps the motion axis over `params`' world: each speed at the world's knob and each of the
/// options' with the morph on, and each speed at the world's knob with it off; `progress(done, total)` after each flight.
pub fn motion(
    gpu: &Gpu,
    params: &WorldParams,
    options: &MotionOptions,
    mut progress: impl FnMut(usize, usize),
) -> Result<Vec<MotionRow>> {
    let mut knobs = vec![params.pixel_error];
    knobs.extend(options.knobs.iter().filter(|&&k| k != params.pixel_error));
    let mut flights: Vec<(f64, f64, bool, Method)> = Vec::new();
    for &knob in &knobs {
        for &speed in &options.speeds {
            flights.push((speed, knob, true, Method::Mesh));
        }
    }
    for &speed in &options.speeds {
        flights.push((speed, params.pixel_error, false, Method::Mesh));
    }
    for method in [Method::Visibility, Method::Hybrid] {
        for &speed in &options.speeds {
            flights.push((speed, params.pixel_error, true, method));
        }
    }
    let target = Offscreen::new(&gpu.device, options.size.0, options.size.1, 1)?;
    let mut rows = Vec::new();
    for (done, &(speed, knob, morphing, method)) in flights.iter().enumerate() {
        let p = WorldParams {
            pixel_error: knob,
            ..*params
        };
        p.validate()?;
        let mut world = World::new(&gpu.device, &gpu.queue, Offscreen::targets(1), p)?;
        world.set_morphing(morphing);
        world.set_bake_budget(options.budget);
        if method != Method::Mesh {
            // At one sample a pixel, as relief's default chooses them on an H100.
            world.set_method(
                &gpu.device,
                relief::MethodConfig::new(method).with_samples(1),
            )?;
        }
        let at = |i: usize| eye_at(&p, options.height, speed * i as f64, options.size);
        // The first frame whole, as after a window's first bake; then frame by frame.
        let (mut last, _) = target.render_world(gpu, &mut world, &at(0), None)?;
        let mut flips = Vec::with_capacity(options.frames);
        let (mut behind, mut pending_max) = (0, 0);
        for i in 1..=options.frames {
            let (image, _) = target.render_world_budgeted(gpu, &mut world, &at(i))?;
            let pending = world.stats().texels_pending;
            behind += usize::from(pending > 0);
            pending_max = pending_max.max(pending);
            let (flip, _) = metrics::image_error(
                &metrics::rgb(&last),
                &metrics::rgb(&image),
                options.size.0,
                options.size.1,
            );
            flips.push(flip);
            last = image;
        }
        flips.sort_by(f64::total_cmp);
        rows.push(MotionRow {
            method,
            speed,
            knob,
            morphing,
            frames: options.frames,
            flip_median: flips.get(flips.len() / 2).copied().unwrap_or(0.0),
            flip_max: flips.last().copied().unwrap_or(0.0),
            frames_behind: behind,
            pending_max,
        });
        progress(done + 1, flights.len());
    }
    Ok(rows)
}

/// The CSV: a header and a row per flight, with the device and backend.
pub fn motion_csv(rows: &[MotionRow], device: &str, backend: &str) -> String {
    let mut out = String::from(
        "speed_m_per_frame,knob_px,morphing,frames,flip_median,flip_max,pop,frames_behind,pending_max,method,device,backend\n",
    );
    for r in rows {
        let _ = writeln!(
            out,
            "{},{},{},{},{:.5},{:.5},{:.3},{},{},{},{device},{backend}",
            r.speed,
            r.knob,
            r.morphing,
            r.frames,
            r.flip_median,
            r.flip_max,
            r.pop(),
            r.frames_behind,
            r.pending_max,
            r.method
        );
    }
    out
}

/// The table: a row per flight.
pub fn motion_table(rows: &[MotionRow]) -> String {
    let mut out = String::from(
        "method  m/frame   knob  morph   FLIP median    max     pop  behind  most waiting\n",
    );
    for r in rows {
        let _ = writeln!(
            out,
            "{:<7} {:<9} {:>4}  {:<5} {:>11.4} {:>6.4} {:>7.2} {:>4}/{:<3} {:>12}",
            r.method.to_string(),
            r.speed,
            r.knob,
            if r.morphing { "on" } else { "off" },
            r.flip_median,
            r.flip_max,
            r.pop(),
            r.frames_behind,
            r.frames,
            r.pending_max
        );
    }
    out.push_str("pop: the largest frame-to-frame FLIP over the median; behind: frames drawn with texels unbaked\n");
    out
}

/// The chart: pop against speed (log), a line per knob with the morph on and one with it off,
/// and the hybrid's, the frames drawn behind as hollow markers, the world's knob marked.
pub fn motion_chart(
    rows: &[MotionRow],
    default_knob: f64,
    (title, stem): (&str, &std::path::Path),
) -> Result<()> {
    crate::chart::write_chart(
        stem,
        |b| draw(b, rows, default_knob, title),
        |b| draw(b, rows, default_knob, title),
    )
}

fn draw<DB: plotters::prelude::DrawingBackend>(
    backend: DB,
    rows: &[MotionRow],
    default_knob: f64,
    title: &str,
) -> std::result::Result<(), String>
where
    DB::ErrorType: 'static,
{
    use plotters::prelude::*;
    let root = backend.into_drawing_area();
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let (s0, s1) = super::log_span(rows.iter().map(|r| r.speed), 1.5);
    if rows.is_empty() {
        return root.present().map_err(|e| e.to_string());
    }
    let top = rows.iter().map(MotionRow::pop).fold(2.0, f64::max) * 1.15;
    let mut chart = super::log_x_chart(
        &root,
        title,
        (s0, s1, top),
        (
            "eye speed, metres a frame (log)",
            "pop: largest frame-to-frame FLIP / median",
        ),
    )?;
    let mut lines: Vec<(f64, bool, Method)> = Vec::new();
    for r in rows {
        if !lines.contains(&(r.knob, r.morphing, r.method)) {
            lines.push((r.knob, r.morphing, r.method));
        }
    }
    for (i, &(knob, morphing, method)) in lines.iter().enumerate() {
        let color = if knob == default_knob && morphing && method == Method::Mesh {
            BLACK.to_rgba()
        } else {
            Palette99::pick(i).to_rgba()
        };
        let mine: Vec<&MotionRow> = rows
            .iter()
            .filter(|r| r.knob == knob && r.morphing == morphing && r.method == method)
            .collect();
        let line: Vec<(f64, f64)> = mine.iter().map(|r| (r.speed, r.pop())).collect();
        let default = if knob == default_knob {
            " (default)"
        } else {
            ""
        };
        let morph = if morphing { "morph on" } else { "morph off" };
        chart
            .draw_series(LineSeries::new(line.clone(), color.stroke_width(2)))
            .map_err(|e| e.to_string())?
            .label(format!(
                "{method}, knob {knob} px{default}, {morph}; hollow: baking behind"
            ))
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color));
        // A hollow marker where frames were drawn with texels unbaked.
        chart
            .draw_series(mine.iter().map(|r| {
                let style = if r.frames_behind > 0 {
                    color.stroke_width(2)
                } else {
                    color.filled()
                };
                Circle::new((r.speed, r.pop()), 5, style)
            }))
            .map_err(|e| e.to_string())?;
    }
    crate::chart::legend(&mut chart, SeriesLabelPosition::UpperLeft)?;
    root.present().map_err(|e| e.to_string())
}
