//! The temporal axis of `relief stability`: what the temporal service
//! ([`relief::World::set_temporal`]) does to a moving picture, against the picture without it.
//! A still frame cannot show either failure of a history:
//!
//! - **flicker**: an error that changes from frame to frame (edges that crawl, detail finer
//!   than a pixel that shimmers). With `e` the difference of the frame's luma from the
//!   reference's at a pixel (8-bit sRGB levels), it is the mean over pixels of `|e_t - e_{t-1}|`
//!   between consecutive frames (median over the frames measured). The picture's own change
//!   is in the reference too, so it cancels: what is left is the method's error moving.
//! - **ghosting**: history kept where it no longer belongs (a trail behind a moving edge, what
//!   a disocclusion uncovered painted with what covered it). It is the share of pixels that the
//!   history puts more than [`GHOST_LEVELS`] farther from the reference (in any channel) than
//!   the same frame drawn without a history (the most over the frames measured).
//!
//! The eye turns at the horizon view (2 m over the ground, looking level) at each rate, and
//! moves sideways from it at each speed, keeping 2 m over the ground (parallax: near ground
//! uncovers far ground). Each motion is drawn at 60 frames a second by the default method
//! (visibility at one sample a pixel, rasterised in compute) twice, with a history of
//! [`relief::temporal::INTERACTIVE_FRAMES`] frames and without one, and every measured frame is
//! judged against the reference ray cast of that frame. The first frames of each motion fill
//! the history and are not measured.

use crate::metrics;
use crate::views::views;
use glam::DVec3;
use relief::error::Result;
use relief::gpu::headless::{render_world_rays_at, Gpu, Offscreen};
use relief::gpu::world::World;
use relief::world::WorldParams;
use relief::{Method, Shading, Temporal, WorldView};
use std::fmt::Write as _;

/// How much farther from the reference than the frame without a history a pixel must be for
/// the history to have ghosted it, in 8-bit levels (a tenth of the range).
pub const GHOST_LEVELS: i32 = 26;

/// Frames a second the motions are drawn at.
pub const FPS: f64 = 60.0;

/// What the temporal axis measures with.
#[derive(Clone, Debug, PartialEq)]
pub struct TemporalOptions {
    /// Turn rates, degrees a second.
    pub turns: Vec<f64>,
    /// Sideways speeds, metres a second.
    pub strafes: Vec<f64>,
    /// Frames drawn before the first measured one (the history filling).
    pub warm: u32,
    /// Frames measured.
    pub frames: u32,
    /// Image size.
    pub size: (u32, u32),
    /// Rays a pixel per side of the reference.
    pub side: u32,
}

impl TemporalOptions {
    /// The full sweep: turns of 3 to 180 degrees a second and sideways 2 to 128 m/s, 24
    /// frames measured after 16 at 480x270, against a 6x6 reference.
    pub fn full() -> Self {
        Self {
            turns: vec![3.0, 12.0, 45.0, 90.0, 180.0],
            strafes: vec![2.0, 8.0, 32.0, 128.0],
            warm: relief::temporal::INTERACTIVE_FRAMES,
            frames: 24,
            size: (480, 270),
            side: 6,
        }
    }

    /// `--quick`: small enough for the tests.
    pub fn quick() -> Self {
        Self {
            turns: vec![90.0],
            strafes: vec![32.0],
            warm: 4,
            frames: 3,
            size: (96, 54),
            side: 2,
        }
    }
}

/// The two motions.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Motion {
    /// The eye turns about the vertical (degrees a second).
    Turn,
    /// The eye moves sideways, 2 m over the ground (metres a second).
    Strafe,
}

impl Motion {
    /// Its name in the table and the CSV.
    pub fn name(self) -> &'static str {
        match self {
            Motion::Turn => "turn",
            Motion::Strafe => "strafe",
        }
    }

    /// The unit of its speed.
    pub fn unit(self) -> &'static str {
        match self {
            Motion::Turn => "deg/s",
            Motion::Strafe => "m/s",
        }
    }
}

/// One motion at one speed, with the service and without.
#[derive(Clone, Debug, PartialEq)]
pub struct TemporalRow {
    /// The motion.
    pub motion: Motion,
    /// Its speed, in [`Motion::unit`].
    pub speed: f64,
    /// Frames measured.
    pub frames: u32,
    /// FLIP against the reference, the mean over the frames: with the service, without.
    pub flip: [f64; 2],
    /// Flicker (module docs), 8-bit levels: with the service, without.
    pub flicker: [f64; 2],
    /// Ghosted pixels (module docs), the most over the frames, a share of the image.
    pub ghost: f64,
}

/// The eye of `motion` at `speed`, `k` frames after it began, from the horizon view of
/// `params`' world at `size`.
fn eye_at(
    params: &WorldParams,
    (motion, speed): (Motion, f64),
    k: u32,
    size: (u32, u32),
) -> WorldView {
    let base = views(params, size)[0].view;
    let t = f64::from(k) / FPS;
    let f = base.forward.as_dvec3();
    match motion {
        Motion::Turn => {
            let a = (speed * t).to_radians();
            let r = DVec3::new(
                f.x * a.cos() - f.z * a.sin(),
                f.y,
                f.x * a.sin() + f.z * a.cos(),
            );
            WorldView::look_at(base.eye, base.eye + r, base.fov_y, size)
        }
        Motion::Strafe => {
            let side = DVec3::new(-f.z, 0.0, f.x).normalize();
            let p = base.eye + side * (speed * t);
            let eye = DVec3::new(p.x, params.land.height_at(p.x, p.z) + 2.0, p.z);
            WorldView::look_at(eye, eye + f, base.fov_y, size)
        }
    }
}

/// Sweeps the temporal axis over `params`' world: each turn rate and each sideways speed;
/// `progress(done, total)` after each.
pub fn temporal(
    gpu: &Gpu,
    params: &WorldParams,
    options: &TemporalOptions,
    mut progress: impl FnMut(usize, usize),
) -> Result<Vec<TemporalRow>> {
    let motions: Vec<(Motion, f64)> = (options.turns.iter().map(|&s| (Motion::Turn, s)))
        .chain(options.strafes.iter().map(|&s| (Motion::Strafe, s)))
        .collect();
    let target = Offscreen::new(&gpu.device, options.size.0, options.size.1, 1)?;
    let mut rows = Vec::new();
    for (done, &motion) in motions.iter().enumerate() {
        rows.push(measure(gpu, params, options, &target, motion)?);
        progress(done + 1, motions.len());
    }
    Ok(rows)
}

fn measure(
    gpu: &Gpu,
    params: &WorldParams,
    options: &TemporalOptions,
    target: &Offscreen,
    motion: (Motion, f64),
) -> Result<TemporalRow> {
    let size = options.size;
    let world = |frames| -> Result<World> {
        let mut world = World::new(&gpu.device, &gpu.queue, Offscreen::targets(1), *params)?;
        world.set_method(&gpu.device, crate::bench_temporal::method())?;
        world.set_temporal(&gpu.device, Temporal { frames })?;
        Ok(world)
    };
    let mut worlds = [world(relief::temporal::INTERACTIVE_FRAMES)?, world(1)?];
    for k in 0..options.warm {
        target.accumulate_frame(gpu, &mut worlds[0], &eye_at(params, motion, k, size))?;
    }
    let mut flips = [Vec::new(), Vec::new()];
    let mut flickers = [Vec::new(), Vec::new()];
    let mut last: [Option<Vec<i32>>; 2] = [None, None];
    let mut ghost: f64 = 0.0;
    for k in options.warm..options.warm + options.frames {
        let view = eye_at(params, motion, k, size);
        let truth = metrics::rgb(
            &render_world_rays_at(
                gpu,
                params,
                &Shading::default(),
                &view,
                Method::Reference,
                options.side,
                None,
            )?
            .rgba,
        );
        let mut images = Vec::new();
        for (i, world) in worlds.iter_mut().enumerate() {
            let image = metrics::rgb(&target.render_world(gpu, world, &view, None)?.0);
            flips[i].push(metrics::image_error(&truth, &image, size.0, size.1).0);
            let error = luma_error(&truth, &image);
            if let Some(before) = &last[i] {
                flickers[i].push(mean_abs_change(before, &error));
            }
            last[i] = Some(error);
            images.push(image);
        }
        ghost = ghost.max(ghosted(&truth, &images[0], &images[1]));
    }
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len().max(1) as f64;
    let median = |v: &[f64]| crate::metrics::median(v.iter().copied()).unwrap_or(0.0);
    Ok(TemporalRow {
        motion: motion.0,
        speed: motion.1,
        frames: options.frames,
        flip: [mean(&flips[0]), mean(&flips[1])],
        flicker: [median(&flickers[0]), median(&flickers[1])],
        ghost,
    })
}

/// Each pixel's luma less the reference's, in 8-bit sRGB levels (times 1000, as integers).
pub(super) fn luma_error(truth: &[u8], image: &[u8]) -> Vec<i32> {
    let luma = |p: &[u8]| 213 * i32::from(p[0]) + 715 * i32::from(p[1]) + 72 * i32::from(p[2]);
    truth
        .chunks_exact(3)
        .zip(image.chunks_exact(3))
        .map(|(t, m)| luma(m) - luma(t))
        .collect()
}

/// The mean of `|b - a|` over pixels, in 8-bit levels.
pub(super) fn mean_abs_change(a: &[i32], b: &[i32]) -> f64 {
    let sum: i64 = a.iter().zip(b).map(|(a, b)| i64::from((b - a).abs())).sum();
    sum as f64 / 1000.0 / a.len().max(1) as f64
}

/// The share of pixels `with` is more than [`GHOST_LEVELS`] farther from `truth` than
/// `without` is, in some channel.
pub(super) fn ghosted(truth: &[u8], with: &[u8], without: &[u8]) -> f64 {
    let far = |a: u8, b: u8| (i32::from(a) - i32::from(b)).abs();
    let pixels = truth.len() / 3;
    let ghosts = (0..pixels)
        .filter(|&p| {
            (0..3).any(|c| {
                let i = p * 3 + c;
                far(with[i], truth[i]) > far(without[i], truth[i]) + GHOST_LEVELS
            })
        })
        .count();
    ghosts as f64 / pixels.max(1) as f64
}

/// The CSV: a header and a row per motion and speed, with the device and backend.
pub fn temporal_csv(rows: &[TemporalRow], device: &str, backend: &str) -> String {
    let mut out = String::from(
        "motion,speed,unit,frames,flip_with_service,flip_without,flicker_with_service,flicker_without,ghost_share,device,backend\n",
    );
    for r in rows {
        let _ = writeln!(
            out,
            "{},{},{},{},{:.5},{:.5},{:.3},{:.3},{:.6},{device},{backend}",
            r.motion.name(),
            r.speed,
            r.motion.unit(),
            r.frames,
            r.flip[0],
            r.flip[1],
            r.flicker[0],
            r.flicker[1],
            r.ghost
        );
    }
    out
}

/// The table: a row per motion and speed.
pub fn temporal_table(rows: &[TemporalRow]) -> String {
    let mut out = String::from(
        "motion  speed         FLIP with  without   flicker with  without   ghosted\n",
    );
    for r in rows {
        let _ = writeln!(
            out,
            "{:<7} {:>5} {:<7} {:>9.4} {:>8.4} {:>13.2} {:>8.2} {:>8.3}%",
            r.motion.name(),
            r.speed,
            r.motion.unit(),
            r.flip[0],
            r.flip[1],
            r.flicker[0],
            r.flicker[1],
            r.ghost * 100.0
        );
    }
    out.push_str(
        "FLIP against the reference of each frame (mean); flicker: the error's change between \
         frames, 8-bit levels (median); ghosted: pixels the history put 26+ levels farther from \
         the reference than the frame without it (the most in a frame)\n",
    );
    out
}

/// The chart: flicker against speed (log), a line per motion with the service and without.
pub fn temporal_chart(rows: &[TemporalRow], (title, stem): (&str, &std::path::Path)) -> Result<()> {
    crate::chart::write_chart(stem, |b| draw(b, rows, title), |b| draw(b, rows, title))
}

fn draw<DB: plotters::prelude::DrawingBackend>(
    backend: DB,
    rows: &[TemporalRow],
    title: &str,
) -> std::result::Result<(), String>
where
    DB::ErrorType: 'static,
{
    use plotters::prelude::*;
    let root = backend.into_drawing_area();
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    if rows.is_empty() {
        return root.present().map_err(|e| e.to_string());
    }
    let (s0, s1) = super::log_span(rows.iter().map(|r| r.speed), 1.5);
    let top = rows.iter().flat_map(|r| r.flicker).fold(0.1, f64::max) * 1.15;
    let mut chart = super::log_x_chart(
        &root,
        title,
        (s0, s1, top),
        (
            "speed: degrees a second (turn), metres a second (sideways), log",
            "flicker: the error's change a frame, 8-bit levels",
        ),
    )?;
    let mut i = 0;
    for motion in [Motion::Turn, Motion::Strafe] {
        for (j, service) in ["with the service", "without"].into_iter().enumerate() {
            let line: Vec<(f64, f64)> = rows
                .iter()
                .filter(|r| r.motion == motion)
                .map(|r| (r.speed, r.flicker[j]))
                .collect();
            if line.is_empty() {
                continue;
            }
            let color = Palette99::pick(i).to_rgba();
            i += 1;
            let width = if j == 0 { 3 } else { 1 };
            chart
                .draw_series(LineSeries::new(line.clone(), color.stroke_width(width)))
                .map_err(|e| e.to_string())?
                .label(format!("{} ({}), {service}", motion.name(), motion.unit()))
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color));
            chart
                .draw_series(line.iter().map(|&p| Circle::new(p, 4, color.filled())))
                .map_err(|e| e.to_string())?;
        }
    }
    crate::chart::legend(&mut chart, SeriesLabelPosition::UpperLeft)?;
    root.present().map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flicker_and_ghosts_count_what_they_say() {
        let truth = [100u8, 100, 100, 50, 50, 50];
        // The same error twice: no flicker; one pixel's error changes by 10 levels.
        let a = luma_error(&truth, &[110, 110, 110, 50, 50, 50]);
        let b = luma_error(&truth, &[110, 110, 110, 60, 60, 60]);
        assert!(mean_abs_change(&a, &a) == 0.0);
        assert!((mean_abs_change(&a, &b) - 5.0).abs() < 1e-9);
        // A pixel 30 levels off with the history and 2 without has ghosted; 20 has not.
        let without = [102u8, 100, 100, 50, 50, 50];
        assert_eq!(ghosted(&truth, &[130, 100, 100, 50, 50, 50], &without), 0.5);
        assert_eq!(ghosted(&truth, &[120, 100, 100, 50, 50, 50], &without), 0.0);
    }
}
