//! The clouds' axis of `relief stability`: what the clouds' image ([`Clouds::reproject`]: one
//! pixel in 16 marched a frame, the others carried over along the clouds' own motion) does to a
//! moving picture, against a full march of that frame, and what the march's step count does to
//! a still one.
//!
//! - **motion**: the eye turns at each rate from the clouds' valley view (2 m over a valley
//!   floor looking 24° up at the layer) and from inside the layer, and flies the fly-through
//!   path (`--camera path`: 120 m/s, 150 m over the ground), at 60 frames a second, each at
//!   noon. Every frame is drawn twice by the default method (visibility at one sample a pixel,
//!   rasterised in compute, the temporal service on): through the clouds' image and with every
//!   pixel's clouds marched that frame ([`Clouds::reproject`] off), the two worlds alike in all
//!   else. FLIP of the first against the second, its mean and its most over the measured frames
//!   (the goal: at most 0.01); **flicker**, the median over frames of the mean change
//!   of a pixel's luma difference between them from one frame to the next (8-bit levels: a
//!   difference that holds still is not flicker); **ghosted**, the share of pixels more than
//!   [`super::temporal::GHOST_LEVELS`] levels from the full march in some channel (the most in
//!   a frame): a cloud's edge left behind where the eye's turn moved it.
//! - **banding**: on the clouds' six still views, one frame (no history: what a frame shows
//!   before the temporal service averages the steps' offsets away), every pixel marched at
//!   each step count, against the same frame at [`crate::bench_clouds::DOUBLED`] steps.
//!
//! The first frames of each motion fill both histories and are not measured.

use super::temporal::{ghosted, luma_error, mean_abs_change, FPS};
use crate::bench_clouds::{cloud_views, layer, DOUBLED};
use crate::bench_temporal::method;
use crate::metrics::{image_error, median, rgb};
use glam::DVec3;
use relief::error::Result;
use relief::gpu::headless::{Gpu, Offscreen};
use relief::gpu::world::World;
use relief::world::clouds::{Clouds, STEPS};
use relief::world::WorldParams;
use relief::{Temporal, WorldView};
use std::fmt::Write as _;

/// The goal for a moving frame through the image against its full march, FLIP.
pub const GOAL: f64 = 0.01;

/// The hour every motion is drawn at (noon).
const NOON: f32 = 12.0;

/// What the clouds' axis measures with.
#[derive(Clone, Debug, PartialEq)]
pub struct CloudOptions {
    /// Turn rates, degrees a second (0: the view held still, the baseline of the others).
    pub turns: Vec<f64>,
    /// How many of the clouds' views the eye turns from: the valley's, then inside the layer.
    pub turn_views: usize,
    /// Whether the fly-through path is measured too.
    pub flight: bool,
    /// Frames drawn before the first measured one (the histories filling).
    pub warm: u32,
    /// Frames measured.
    pub frames: u32,
    /// Step counts the still views' banding is measured at.
    pub steps: Vec<u32>,
    /// How many of the clouds' views the banding is measured on.
    pub still_views: usize,
    /// Image size.
    pub size: (u32, u32),
}

impl CloudOptions {
    /// The full sweep: the views held still and turning at 22.5 to 180 degrees a second, and
    /// the fly-through, 24 frames measured after 16; banding at 12 to 192 steps on the six
    /// views; 480x270.
    pub fn full() -> Self {
        Self {
            turns: vec![0.0, 22.5, 45.0, 90.0, 180.0],
            turn_views: 2,
            flight: true,
            warm: 16,
            frames: 24,
            steps: vec![12, 24, STEPS, 96, 192],
            still_views: 6,
            size: (480, 270),
        }
    }

    /// `--quick`: small enough for the tests.
    pub fn quick() -> Self {
        Self {
            turns: vec![90.0],
            turn_views: 1,
            flight: false,
            warm: 4,
            frames: 3,
            steps: vec![STEPS],
            still_views: 1,
            size: (96, 54),
        }
    }
}

/// One measurement: a motion at a speed, or a still view at a step count.
#[derive(Clone, Debug, PartialEq)]
pub struct CloudRow {
    /// `turn <view>`, `fly-through` or `still <view>`.
    pub what: String,
    /// Degrees a second (a turn), metres a second (the fly-through) or steps (a still view).
    pub speed: f64,
    /// Frames measured (1 for a still view).
    pub frames: u32,
    /// FLIP against the full march (moving) or against [`DOUBLED`] steps (still): the mean
    /// over the frames and the most.
    pub flip: [f64; 2],
    /// Flicker (module docs), 8-bit levels; 0 for a still view.
    pub flicker: f64,
    /// Ghosted pixels (module docs), the most over the frames, a share of the image.
    pub ghost: f64,
}

impl CloudRow {
    /// The unit of [`CloudRow::speed`].
    pub fn unit(&self) -> &'static str {
        if self.what.starts_with("turn") {
            "deg/s"
        } else if self.what.starts_with("still") {
            "steps"
        } else {
            "m/s"
        }
    }
}

/// A camera along a motion: the view of frame k.
type Camera<'a> = Box<dyn Fn(u32) -> WorldView + 'a>;

/// `base` turned about the vertical at `rate` degrees a second, `k` frames on.
fn turned(base: &WorldView, rate: f64, k: u32) -> WorldView {
    let a = (rate * f64::from(k) / FPS).to_radians();
    let f = base.forward.as_dvec3();
    let r = DVec3::new(
        f.x * a.cos() - f.z * a.sin(),
        f.y,
        f.x * a.sin() + f.z * a.cos(),
    );
    WorldView::look_at(base.eye, base.eye + r, base.fov_y, base.size)
}

/// The world of `params` drawn by the default method with the temporal service's history.
fn world(gpu: &Gpu, params: &WorldParams) -> Result<World> {
    let mut world = World::new(&gpu.device, &gpu.queue, Offscreen::targets(1), *params)?;
    world.set_method(&gpu.device, method())?;
    world.set_temporal(
        &gpu.device,
        Temporal {
            frames: relief::temporal::INTERACTIVE_FRAMES,
        },
    )?;
    Ok(world)
}

/// `params` with its clouds (or a broken layer where it has none) at noon, marched `reproject`.
fn cloudy(params: &WorldParams, hour: f32, reproject: bool) -> WorldParams {
    let mut p = *params;
    p.sky = relief::day::at_time(p.sky, hour);
    p.clouds = Clouds {
        reproject,
        ..layer(params)
    };
    p
}

/// Sweeps the clouds' axis over `params`' world: each motion, then each still view's steps;
/// `progress(done, total)` after each.
pub fn clouds(
    gpu: &Gpu,
    params: &WorldParams,
    options: &CloudOptions,
    mut progress: impl FnMut(usize, usize),
) -> Result<Vec<CloudRow>> {
    let size = options.size;
    let target = Offscreen::new(&gpu.device, size.0, size.1, 1)?;
    let still = cloud_views(params, size);
    let mut motions: Vec<(String, f64, Camera<'_>)> = Vec::new();
    // The valley view and the one inside the layer, at noon.
    for (name, view, _) in still.iter().take(options.turn_views.min(2)) {
        for &rate in &options.turns {
            let view = *view;
            let at: Camera<'_> = Box::new(move |k| turned(&view, rate, k));
            motions.push((format!("turn {name}"), rate, at));
        }
    }
    if options.flight {
        let path = relief::PathCamera::default();
        let land = params.land;
        let at: Camera<'_> =
            Box::new(move |k| path.view(|x, z| land.height_at(x, z), f64::from(k) / FPS, size));
        motions.push(("fly-through".to_owned(), path.speed, at));
    }
    let total = motions.len() + options.still_views.min(still.len()) * options.steps.len();
    let mut rows = Vec::new();
    for (name, speed, at) in &motions {
        rows.push(moving(gpu, params, (options, &target), (name, *speed, at))?);
        progress(rows.len(), total);
    }
    let flip = |a: &[u8], b: &[u8]| image_error(a, b, size.0, size.1).0;
    for (name, view, hour) in still.iter().take(options.still_views) {
        // One world a view, no history: each frame its steps' own.
        let p = cloudy(params, *hour, false);
        let mut w = World::new(&gpu.device, &gpu.queue, Offscreen::targets(1), p)?;
        w.set_method(&gpu.device, method())?;
        w.set_temporal(&gpu.device, Temporal { frames: 1 })?;
        let mut frame = |steps: u32| -> Result<Vec<u8>> {
            let mut p = p;
            p.clouds.steps = steps;
            w.set_params(&gpu.device, p)?;
            Ok(rgb(&target.render_world(gpu, &mut w, view, None)?.0))
        };
        let limit = frame(DOUBLED)?;
        for &steps in &options.steps {
            let e = flip(&limit, &frame(steps)?);
            rows.push(CloudRow {
                what: format!("still {name}"),
                speed: f64::from(steps),
                frames: 1,
                flip: [e, e],
                flicker: 0.0,
                ghost: 0.0,
            });
            progress(rows.len(), total);
        }
    }
    Ok(rows)
}

/// One motion through the image and fully marched, frame by frame.
fn moving(
    gpu: &Gpu,
    params: &WorldParams,
    (options, target): (&CloudOptions, &Offscreen),
    (name, speed, at): (&str, f64, &Camera<'_>),
) -> Result<CloudRow> {
    let size = options.size;
    let mut worlds = [
        world(gpu, &cloudy(params, NOON, true))?,
        world(gpu, &cloudy(params, NOON, false))?,
    ];
    for k in 0..options.warm {
        for w in &mut worlds {
            target.accumulate_frame(gpu, w, &at(k))?;
        }
    }
    let (mut flips, mut flickers) = (Vec::new(), Vec::new());
    let mut last: Option<Vec<i32>> = None;
    let mut ghost: f64 = 0.0;
    for k in options.warm..options.warm + options.frames {
        let view = at(k);
        let image = rgb(&target.render_world(gpu, &mut worlds[0], &view, None)?.0);
        let full = rgb(&target.render_world(gpu, &mut worlds[1], &view, None)?.0);
        flips.push(image_error(&full, &image, size.0, size.1).0);
        let error = luma_error(&full, &image);
        if let Some(before) = &last {
            flickers.push(mean_abs_change(before, &error));
        }
        last = Some(error);
        ghost = ghost.max(ghosted(&full, &image, &full));
    }
    Ok(CloudRow {
        what: name.to_owned(),
        speed,
        frames: options.frames,
        flip: [
            flips.iter().sum::<f64>() / flips.len().max(1) as f64,
            flips.iter().copied().fold(0.0, f64::max),
        ],
        flicker: median(flickers.iter().copied()).unwrap_or(0.0),
        ghost,
    })
}

/// The CSV: a header and a row per motion and still view, with the device and backend.
pub fn clouds_csv(rows: &[CloudRow], device: &str, backend: &str) -> String {
    let mut out = String::from(
        "what,speed,unit,frames,flip_mean,flip_max,flicker,ghost_share,device,backend\n",
    );
    for r in rows {
        let _ = writeln!(
            out,
            "{},{},{},{},{:.5},{:.5},{:.3},{:.6},{device},{backend}",
            r.what,
            r.speed,
            r.unit(),
            r.frames,
            r.flip[0],
            r.flip[1],
            r.flicker,
            r.ghost
        );
    }
    out
}

/// The table: a row per motion and still view, the goal's verdict on each motion.
pub fn clouds_table(rows: &[CloudRow]) -> String {
    let mut out = String::from(
        "clouds                  speed           FLIP mean    most   flicker   ghosted\n",
    );
    for r in rows {
        let verdict = if r.what.starts_with("still") {
            ""
        } else if r.flip[1] <= GOAL {
            "  within the goal"
        } else {
            "  over the goal"
        };
        let _ = writeln!(
            out,
            "{:<23} {:>6} {:<7} {:>10.4} {:>7.4} {:>9.2} {:>8.3}%{verdict}",
            r.what,
            r.speed,
            r.unit(),
            r.flip[0],
            r.flip[1],
            r.flicker,
            r.ghost * 100.0
        );
    }
    let _ = writeln!(
        out,
        "moving: each frame through the clouds' image against the same frame with every pixel's \
         clouds marched (the goal: FLIP at most {GOAL}); flicker: the difference's change between \
         frames, 8-bit levels (median); ghosted: pixels 26+ levels from the full march (the most \
         in a frame); still: one frame at that many steps against {DOUBLED}"
    );
    out
}

/// The chart: FLIP against the turn rate (a line per view, its mean and its most) and against
/// the step count (a line per still view), log x, the goal drawn across.
pub fn clouds_chart(rows: &[CloudRow], (title, stem): (&str, &std::path::Path)) -> Result<()> {
    crate::chart::write_chart(stem, |b| draw(b, rows, title), |b| draw(b, rows, title))
}

fn draw<DB: plotters::prelude::DrawingBackend>(
    backend: DB,
    rows: &[CloudRow],
    title: &str,
) -> std::result::Result<(), String>
where
    DB::ErrorType: 'static,
{
    use plotters::prelude::*;
    let root = backend.into_drawing_area();
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    // The fly-through has no turn rate, a view held still none on a log axis: the table's.
    let plotted: Vec<&CloudRow> = rows
        .iter()
        .filter(|r| r.what != "fly-through" && r.speed > 0.0)
        .collect();
    if plotted.is_empty() {
        return root.present().map_err(|e| e.to_string());
    }
    let (s0, s1) = super::log_span(plotted.iter().map(|r| r.speed), 1.5);
    let top = plotted.iter().map(|r| r.flip[1]).fold(GOAL, f64::max) * 1.15;
    let y =
        format!("FLIP: moving, the image against the full march; still, against {DOUBLED} steps");
    let mut chart = super::log_x_chart(
        &root,
        title,
        (s0, s1, top),
        (
            "turn rate, degrees a second, or the still march's steps (log)",
            &y,
        ),
    )?;
    chart
        .draw_series(LineSeries::new(
            [(s0, GOAL), (s1, GOAL)],
            BLACK.stroke_width(1),
        ))
        .map_err(|e| e.to_string())?
        .label(format!("goal for a moving frame ({GOAL})"))
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLACK));
    let mut names: Vec<&str> = plotted.iter().map(|r| r.what.as_str()).collect();
    names.dedup();
    for (i, name) in names.into_iter().enumerate() {
        let color = Palette99::pick(i).to_rgba();
        let still = name.starts_with("still");
        for (j, which) in ["mean", "most"].into_iter().enumerate() {
            if still && j == 1 {
                continue;
            }
            let line: Vec<(f64, f64)> = plotted
                .iter()
                .filter(|r| r.what == name)
                .map(|r| (r.speed, r.flip[j]))
                .collect();
            let label = if still {
                name.to_owned()
            } else {
                format!("{name}, {which}")
            };
            chart
                .draw_series(LineSeries::new(
                    line.clone(),
                    color.stroke_width(if j == 0 { 3 } else { 1 }),
                ))
                .map_err(|e| e.to_string())?
                .label(label)
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color));
            chart
                .draw_series(line.iter().map(|&p| Circle::new(p, 4, color.filled())))
                .map_err(|e| e.to_string())?;
        }
    }
    crate::chart::legend(&mut chart, SeriesLabelPosition::UpperRight)?;
    root.present().map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_name_their_unit_and_the_table_judges_only_the_motions() {
        let row = |what: &str, speed, most| CloudRow {
            what: what.to_owned(),
            speed,
            frames: 1,
            flip: [most, most],
            flicker: 0.0,
            ghost: 0.0,
        };
        let rows = [
            row("turn valley-up-noon", 90.0, 0.02),
            row("fly-through", 120.0, 0.005),
            row("still above-noon", 48.0, 0.04),
        ];
        let units: Vec<&str> = rows.iter().map(CloudRow::unit).collect();
        assert_eq!(units, ["deg/s", "m/s", "steps"]);
        let table = clouds_table(&rows);
        let lines: Vec<&str> = table.lines().collect();
        assert!(lines[1].ends_with("over the goal"), "{table}");
        assert!(lines[2].ends_with("within the goal"), "{table}");
        assert!(!lines[3].contains("goal"), "{table}");
        assert_eq!(clouds_csv(&rows, "d", "b").lines().count(), 4);
    }
}
