//! The grass axis of `relief stability`: how the grass ([`relief::grass`]) holds still under a
//! moving eye, against its reference (`--method reference` with grass: every blade to twice the
//! draw distance in full, 9x9 samples a pixel, `relief::gpu::headless::render_world_rays`).
//!
//! - **flicker**: FLIP between consecutive frames (the median over a path), the frame's against
//!   the reference's own. The picture's true change (the eye moving) is in both; what the
//!   frame adds (blades narrower than a pixel coming and going, level of detail, one sample a
//!   pixel) is the excess. The goal: within 0.005.
//! - **pops**: the largest excess of one frame's change over the reference's change in that
//!   frame: a ring of blades changing their detail at once shows as a spike.
//!
//! Each path is drawn twice: one frame at a time (no history), and with the temporal service's
//! history of [`relief::temporal::INTERACTIVE_FRAMES`] frames, filled over the path's first
//! frames before any is measured.
//!
//! Paths: the meadow of the grass's views ([`crate::bench_grass::grass_views`]) walked at 1.7 m
//! above the ground at each speed, looking as the meadow view looks, and the fly-through path
//! (`--camera path`, 150 m over the highest ground: grass hardly in view), each with the clock
//! held (the wind's bend in the frame and the reference alike, still); and standing on the
//! meadow in a gale ([`GALE`]) with the clock running, where only the blades move: what the
//! temporal service carries along each blade's own motion. Each at 60 frames a second, the
//! default method.

use crate::metrics::{image_error, median, rgb};
use glam::DVec3;
use relief::error::Result;
use relief::gpu::headless::{render_world_rays, Gpu, Offscreen};
use relief::gpu::world::World;
use relief::world::WorldParams;
use relief::{Method, Shading, WorldView};
use std::fmt::Write as _;

/// Frames a second the paths are drawn at.
pub const FPS: f64 = 60.0;

/// The wind of the standing path, metres a second: a gale, whose gusts move a blade's tip a
/// few pixels a frame near the eye (the default wind, 4 m/s, moves it less than a pixel).
pub const GALE: f64 = 16.0;

/// What the grass axis measures with.
#[derive(Clone, Debug, PartialEq)]
pub struct GrassOptions {
    /// Walking speeds over the meadow, metres a second.
    pub speeds: Vec<f64>,
    /// Whether the fly-through path is measured too.
    pub flight: bool,
    /// Winds blowing over the meadow while the eye stands still, metres a second.
    pub winds: Vec<f64>,
    /// Frame-to-frame changes measured on each path (one frame more is drawn).
    pub frames: u32,
    /// Frames the history fills over before the first measured one.
    pub warm: u32,
    /// Image size.
    pub size: (u32, u32),
    /// The grass's draw distance, metres (the world's own where `None`).
    pub distance: Option<f32>,
}

impl GrassOptions {
    /// The full sweep: walks of 1.5 and 10 m/s, the fly-through and standing in a gale, 12
    /// changes each at 480x270, the grass's defaults.
    pub fn full() -> Self {
        Self {
            speeds: vec![1.5, 10.0],
            flight: true,
            winds: vec![GALE],
            frames: 12,
            warm: relief::temporal::INTERACTIVE_FRAMES,
            size: (480, 270),
            distance: None,
        }
    }

    /// `--quick`: a 10 m/s walk and standing in a gale, two changes each at 96x54, blades to 20 m (the reference's
    /// to 40 m): small enough for a software GPU.
    pub fn quick() -> Self {
        Self {
            speeds: vec![10.0],
            flight: false,
            winds: vec![GALE],
            frames: 2,
            warm: 2,
            size: (96, 54),
            distance: Some(20.0),
        }
    }
}

/// A path of the axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum GrassPath {
    /// Walking over the meadow at 1.7 m, metres a second.
    Walk(f64),
    /// The fly-through path.
    Flight,
    /// Standing on the meadow at 1.7 m while a wind of this many metres a second blows
    /// (the clock running at the frames' rate): the blades move and the eye does not.
    Wind(f64),
}

impl GrassPath {
    /// Its name in the table and the CSV.
    pub fn name(self) -> String {
        match self {
            GrassPath::Walk(speed) => format!("walk {speed} m/s"),
            GrassPath::Flight => "fly-through".to_owned(),
            GrassPath::Wind(speed) => format!("wind {speed} m/s"),
        }
    }
}

/// One path measured.
#[derive(Clone, Debug, PartialEq)]
pub struct GrassRow {
    /// The path.
    pub path: GrassPath,
    /// FLIP between consecutive frames, each change: the frame's without a history, with one,
    /// and the reference's.
    pub changes: Vec<[f64; 3]>,
    /// FLIP of each frame against its reference: without a history, with one.
    pub flip: Vec<[f64; 2]>,
    /// The reference's blades in the path's first measured frame.
    pub blades: u32,
}

impl GrassRow {
    /// The median change between frames: the frame's without a history, with one, the
    /// reference's.
    pub fn flicker(&self) -> [f64; 3] {
        [0, 1, 2].map(|i| median(self.changes.iter().map(|c| c[i])).unwrap_or(0.0))
    }

    /// The frame's flicker less the reference's (the goal: at most 0.005): without a history,
    /// with one.
    pub fn excess(&self) -> [f64; 2] {
        let [frame, history, truth] = self.flicker();
        [frame - truth, history - truth]
    }

    /// The largest excess of one change over the reference's (a pop): without a history, with
    /// one.
    pub fn pops(&self) -> [f64; 2] {
        [0, 1].map(|i| {
            self.changes
                .iter()
                .map(|c| c[i] - c[2])
                .fold(f64::NEG_INFINITY, f64::max)
                .max(0.0)
        })
    }

    /// The mean FLIP of the frames against their references: without a history, with one.
    pub fn mean_flip(&self) -> [f64; 2] {
        let n = self.flip.len().max(1) as f64;
        [0, 1].map(|i| self.flip.iter().map(|f| f[i]).sum::<f64>() / n)
    }
}

/// The view of `path` `k` frames in, over `params`' world at `size`, starting from the meadow
/// view `meadow`.
fn view_at(
    params: &WorldParams,
    (path, meadow): (GrassPath, &WorldView),
    k: u32,
    size: (u32, u32),
) -> WorldView {
    let t = f64::from(k) / FPS;
    match path {
        GrassPath::Wind(_) => *meadow,
        GrassPath::Walk(speed) => {
            let f = meadow.forward.as_dvec3();
            let heading = DVec3::new(f.x, 0.0, f.z).normalize();
            let p = meadow.eye + heading * (speed * t);
            let eye = DVec3::new(p.x, params.land.height_at(p.x, p.z) + 1.7, p.z);
            WorldView::look_at(eye, eye + f, meadow.fov_y, size)
        }
        GrassPath::Flight => {
            let land = params.land;
            relief::camera::PathCamera::default().view(|x, z| land.height_at(x, z), t, size)
        }
    }
}

/// Sweeps the grass axis over `params`' world with grass on (at the options' distance):
/// `progress(done, total)` after each path.
pub fn grass(
    gpu: &Gpu,
    params: &WorldParams,
    options: &GrassOptions,
    mut progress: impl FnMut(usize, usize),
) -> Result<Vec<GrassRow>> {
    let mut p = *params;
    p.grass.on = true;
    if let Some(d) = options.distance {
        p.grass.distance = d;
    }
    p.validate()?;
    let meadow = crate::bench_grass::grass_views(&p, options.size)?[0].1;
    let paths: Vec<GrassPath> = options
        .speeds
        .iter()
        .map(|&s| GrassPath::Walk(s))
        .chain(options.flight.then_some(GrassPath::Flight))
        .chain(options.winds.iter().map(|&s| GrassPath::Wind(s)))
        .collect();
    let size = options.size;
    let target = Offscreen::new(&gpu.device, size.0, size.1, 1)?;
    let mut rows = Vec::new();
    let world = |frames, p: WorldParams| -> Result<World> {
        let mut world = World::new(&gpu.device, &gpu.queue, Offscreen::targets(1), p)?;
        world.set_method(&gpu.device, crate::bench_temporal::method())?;
        world.set_temporal(&gpu.device, relief::Temporal { frames })?;
        Ok(world)
    };
    for (done, &path) in paths.iter().enumerate() {
        // The clock runs where the wind blows, and holds elsewhere.
        let mut p = p;
        let clock = |k: u32| match path {
            GrassPath::Wind(_) => f64::from(k) / FPS,
            _ => 0.0,
        };
        if let GrassPath::Wind(speed) = path {
            p.wind.speed = speed as f32;
            p.validate()?;
        }
        let mut worlds = [
            world(1, p)?,
            world(relief::temporal::INTERACTIVE_FRAMES, p)?,
        ];
        for k in 0..options.warm {
            let view = view_at(&p, (path, &meadow), k, size);
            worlds[1].set_time(clock(k));
            target.accumulate_frame(gpu, &mut worlds[1], &view)?;
        }
        let mut row = GrassRow {
            path,
            changes: Vec::new(),
            flip: Vec::new(),
            blades: 0,
        };
        let flip = |a: &[u8], b: &[u8]| image_error(a, b, size.0, size.1).0;
        let mut last: Option<[Vec<u8>; 3]> = None;
        for k in options.warm..=options.warm + options.frames {
            let view = view_at(&p, (path, &meadow), k, size);
            let at = WorldParams {
                clock: p.clock + clock(k),
                ..p
            };
            let truth = render_world_rays(
                gpu,
                &at,
                &Shading::default(),
                &view,
                Method::Reference,
                None,
            )?;
            for world in &mut worlds {
                world.set_time(clock(k));
            }
            if k == options.warm {
                row.blades = truth.blades;
            }
            let truth = rgb(&truth.rgba);
            let alone = rgb(&target.render_world(gpu, &mut worlds[0], &view, None)?.0);
            let history = rgb(&target.render_world(gpu, &mut worlds[1], &view, None)?.0);
            row.flip
                .push([flip(&truth, &alone), flip(&truth, &history)]);
            if let Some([a, h, t]) = &last {
                row.changes
                    .push([flip(a, &alone), flip(h, &history), flip(t, &truth)]);
            }
            last = Some([alone, history, truth]);
        }
        rows.push(row);
        progress(done + 1, paths.len());
    }
    Ok(rows)
}

/// The CSV: a header and a row per path, with the device and backend.
pub fn grass_csv(rows: &[GrassRow], device: &str, backend: &str) -> String {
    let mut out = String::from(
        "path,frames,reference_blades,flicker_frame,flicker_history,flicker_reference,excess_frame,excess_history,pops_frame,pops_history,flip_frame,flip_history,device,backend\n",
    );
    for r in rows {
        let [frame, history, truth] = r.flicker();
        let ([e0, e1], [p0, p1], [f0, f1]) = (r.excess(), r.pops(), r.mean_flip());
        let _ = writeln!(
            out,
            "{},{},{},{frame:.5},{history:.5},{truth:.5},{e0:.5},{e1:.5},{p0:.5},{p1:.5},{f0:.5},{f1:.5},{device},{backend}",
            r.path.name(),
            r.changes.len(),
            r.blades,
        );
    }
    out
}

/// The table: a row per path.
pub fn grass_table(rows: &[GrassRow]) -> String {
    let mut out = String::from(
        "path            blades   flicker: alone  history  reference   excess: alone  history   pops: alone  history   FLIP: alone  history\n",
    );
    for r in rows {
        let [frame, history, truth] = r.flicker();
        let ([e0, e1], [p0, p1], [f0, f1]) = (r.excess(), r.pops(), r.mean_flip());
        let _ = writeln!(
            out,
            "{:<14} {:>8} {frame:>15.4} {history:>8.4} {truth:>10.4} {e0:>15.4} {e1:>8.4} {p0:>13.4} {p1:>8.4} {f0:>13.3} {f1:>8.3}",
            r.path.name(),
            r.blades,
        );
    }
    out.push_str(
        "flicker: FLIP between consecutive frames (median), one frame at a time, with the \
         temporal service's history, and the reference's own; excess: the frame's less the \
         reference's (goal: at most 0.005); pops: the largest excess of one frame; FLIP: each \
         frame against its reference (mean)\n",
    );
    out
}

/// The chart: each path's change between consecutive frames, the frame's and the
/// reference's, frame by frame.
pub fn grass_chart(rows: &[GrassRow], (title, stem): (&str, &std::path::Path)) -> Result<()> {
    crate::chart::write_chart(stem, |b| draw(b, rows, title), |b| draw(b, rows, title))
}

fn draw<DB: plotters::prelude::DrawingBackend>(
    backend: DB,
    rows: &[GrassRow],
    title: &str,
) -> std::result::Result<(), String>
where
    DB::ErrorType: 'static,
{
    use plotters::prelude::*;
    let root = backend.into_drawing_area();
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let frames = rows.iter().map(|r| r.changes.len()).max().unwrap_or(0);
    if frames == 0 {
        return root.present().map_err(|e| e.to_string());
    }
    let top = rows
        .iter()
        .flat_map(|r| r.changes.iter().flatten().copied())
        .fold(0.01, f64::max)
        * 1.15;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 20))
        .margin(16)
        .x_label_area_size(48)
        .y_label_area_size(64)
        .build_cartesian_2d(0.5..frames as f64 + 0.5, 0.0..top)
        .map_err(|e| e.to_string())?;
    chart
        .configure_mesh()
        .x_desc("frame (60 a second)")
        .y_desc("FLIP against the frame before")
        .label_style(("sans-serif", 15))
        .axis_desc_style(("sans-serif", 15))
        .draw()
        .map_err(|e| e.to_string())?;
    for (i, r) in rows.iter().enumerate() {
        let color = Palette99::pick(i).to_rgba();
        for (j, who) in ["one frame at a time", "with a history", "the reference"]
            .into_iter()
            .enumerate()
        {
            let line: Vec<(f64, f64)> = r
                .changes
                .iter()
                .enumerate()
                .map(|(k, c)| (k as f64 + 1.0, c[j]))
                .collect();
            let width = [3, 2, 1][j];
            chart
                .draw_series(LineSeries::new(line, color.stroke_width(width)))
                .map_err(|e| e.to_string())?
                .label(format!("{}, {who}", r.path.name()))
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color));
        }
    }
    crate::chart::legend(&mut chart, SeriesLabelPosition::UpperLeft)?;
    root.present().map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flicker_excess_and_pops_count_what_they_say() {
        let row = GrassRow {
            path: GrassPath::Walk(1.5),
            changes: vec![[0.02, 0.01, 0.01], [0.03, 0.02, 0.02], [0.09, 0.02, 0.02]],
            flip: vec![[0.1, 0.05], [0.2, 0.05]],
            blades: 5,
        };
        assert_eq!(row.flicker(), [0.03, 0.02, 0.02]);
        assert!((row.excess()[0] - 0.01).abs() < 1e-12 && row.excess()[1].abs() < 1e-12);
        assert!((row.pops()[0] - 0.07).abs() < 1e-12 && row.pops()[1].abs() < 1e-12);
        assert!((row.mean_flip()[0] - 0.15).abs() < 1e-12);
        let csv = grass_csv(&[row], "a GPU", "Vulkan");
        assert_eq!(csv.lines().count(), 2);
        assert!(csv.lines().nth(1).unwrap().starts_with("walk 1.5 m/s,3,5,"));
    }
}
