//! The distance axis of `relief stability`: the endless world far from its origin. Positions
//! of 10^6 metres and more do not fit f32 to a centimetre, so a renderer that passes world
//! positions to the GPU jitters by whole metres there. Relief keeps level samples as integers
//! and draws camera-relative. At each distance from the origin (the eye placed there, looking
//! down at the ground ahead), the sweep measures:
//!
//! - **height error**: the GPU bake's heights at the finest level's samples there against the
//!   CPU twin's f64 ones, metres;
//! - **screen error**: how far the mesh's drawn points lie from the twin's continuous surface,
//!   in pixels (the LOD's own error, within the knob, plus any from position rounding);
//! - **jitter**: how much a 1 cm step of the eye changes the mesh's picture (mean absolute
//!   8-bit difference) over how much it changes the reference's, whose rays start from exact
//!   integer samples (a renderer rounding positions far out changes it by far more; the
//!   terrain in view sets how much the step changes either picture);
//! - **seams**: pixels where the reference sees terrain and the mesh sky (holes, cracks
//!   between levels) or the reverse, and the mesh's FLIP against the reference.
//!
//! The visibility method and the hybrid ([`OTHER_METHODS`], one sample a pixel as relief's
//! default chooses them on an H100) are measured beside the mesh: their jitter, seams and
//! FLIP, from their own pictures and composited depth. They bake the same levels and raster the
//! same mesh, but shade (and the hybrid marches) in a compute pass of their own.
//!
//! Eyes beyond [`relief::clipmap::max_eye`] are refused by the world (their level sample
//! coordinates would not fit 32 bits): such a row says so.

use crate::metrics;
use glam::DVec3;
use relief::error::Result;
use relief::gpu::headless::{self, Gpu, Offscreen};
use relief::gpu::world::World;
use relief::method::Method;
use relief::noise::Channel;
use relief::params::Shading;
use relief::world::WorldParams;
use relief::WorldView;
use std::fmt::Write as _;

/// What the distance sweep measures with.
#[derive(Clone, Debug, PartialEq)]
pub struct DistanceOptions {
    /// Distances of the eye from the origin, metres.
    pub distances: Vec<f64>,
    /// Image size of each view.
    pub size: (u32, u32),
    /// The eye's step, metres.
    pub step: f64,
    /// Samples per side of the bake compared with the twin.
    pub bake_side: u32,
}

impl DistanceOptions {
    /// The full sweep: 10^0 to 10^9 metres, 480x270.
    pub fn full() -> Self {
        Self {
            distances: (0..=9).map(|k| 10f64.powi(k)).collect(),
            size: (480, 270),
            step: 0.01,
            bake_side: 64,
        }
    }

    /// `--quick`: small enough for the tests.
    pub fn quick() -> Self {
        Self {
            distances: vec![1.0, 1e3, 1e6, 1e9],
            size: (96, 54),
            step: 0.01,
            bake_side: 16,
        }
    }
}

/// The methods measured beside the mesh, each at one sample a pixel.
pub const OTHER_METHODS: [Method; 2] = [Method::Visibility, Method::Hybrid];

/// What a method drew at one distance, against the reference.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Seen {
    /// Mean absolute 8-bit change of its picture under the eye's step.
    pub step_change: f64,
    /// Fraction of pixels where the reference sees terrain and it sky, and the reverse.
    pub missed: f64,
    /// See `missed`.
    pub extra: f64,
    /// Its mean FLIP against the reference.
    pub flip: f64,
}

/// One distance.
#[derive(Clone, Debug, PartialEq)]
pub struct DistanceRow {
    /// Metres from the origin (along x; z is -0.6 of it).
    pub distance: f64,
    /// Why the world refused the eye there, if it did (the other fields are then 0).
    pub refused: Option<String>,
    /// Largest |GPU bake - twin| over the finest level's samples there, metres.
    pub height_error_m: f64,
    /// The mesh's screen error against the twin, pixels: 99th percentile and largest.
    pub screen_error_p99: f64,
    pub screen_error_max: f64,
    /// Mean absolute 8-bit change of the picture under the eye's step: mesh, reference.
    pub step_change: [f64; 2],
    /// Fraction of pixels where the reference sees terrain and the mesh sky, and the reverse.
    pub missed: f64,
    pub extra: f64,
    /// Mean FLIP of the mesh against the reference.
    pub flip: f64,
    /// The same for each of [`OTHER_METHODS`], in order.
    pub others: [Seen; OTHER_METHODS.len()],
}

impl DistanceRow {
    /// The step's change of the mesh's picture over its change of the reference's.
    pub fn jitter(&self) -> f64 {
        self.step_change[0] / self.step_change[1].max(1e-9)
    }

    /// The same for [`OTHER_METHODS`]`[i]`.
    pub fn jitter_of(&self, i: usize) -> f64 {
        self.others[i].step_change / self.step_change[1].max(1e-9)
    }
}

/// The eye at `distance` from the origin: a little above the ground, looking ahead and down.
pub fn distance_view(params: &WorldParams, distance: f64, size: (u32, u32)) -> WorldView {
    let land = &params.land;
    let (x, z) = (distance, -0.6 * distance);
    let eye = DVec3::new(x, land.height_at(x, z) + 0.01 * land.peak_height + 2.0, z);
    WorldView::look_at(
        eye,
        eye + DVec3::new(0.8, -0.35, 0.5),
        50f32.to_radians(),
        size,
    )
}

/// Sweeps the distance axis over `params`' world; `progress(done, total)` after each distance.
pub fn distances(
    gpu: &Gpu,
    params: &WorldParams,
    options: &DistanceOptions,
    mut progress: impl FnMut(usize, usize),
) -> Result<Vec<DistanceRow>> {
    params.validate()?;
    let mut world = World::new(&gpu.device, &gpu.queue, Offscreen::targets(1), *params)?;
    world.set_bake_budget(u64::MAX);
    world.set_light_budget(u64::MAX);
    let mut others = Vec::new();
    for method in OTHER_METHODS {
        let mut w = World::new(&gpu.device, &gpu.queue, Offscreen::targets(1), *params)?;
        w.set_bake_budget(u64::MAX);
        w.set_light_budget(u64::MAX);
        w.set_method(
            &gpu.device,
            relief::MethodConfig::new(method).with_samples(1),
        )?;
        others.push(w);
    }
    let (w, h) = options.size;
    let target = Offscreen::new(&gpu.device, w, h, 1)?;
    let mut rows = Vec::new();
    for (done, &d) in options.distances.iter().enumerate() {
        let view = distance_view(params, d, options.size);
        let measured = measure(gpu, params, (&mut world, &target), &view, options);
        let row = match measured.and_then(|row| seen_by_others(gpu, &mut others, &target, row)) {
            Ok(row) => row,
            // Only the world's refusal of the eye is a finding; anything else is an error.
            Err(relief::Error::InvalidParam { name, allowed, .. }) if name == "eye" => {
                DistanceRow {
                    distance: d,
                    refused: Some(allowed),
                    height_error_m: 0.0,
                    screen_error_p99: 0.0,
                    screen_error_max: 0.0,
                    step_change: [0.0; 2],
                    missed: 0.0,
                    extra: 0.0,
                    flip: 0.0,
                    others: Default::default(),
                }
            }
            Err(e) => return Err(e),
        };
        rows.push(DistanceRow { distance: d, ..row });
        progress(done + 1, options.distances.len());
    }
    Ok(rows)
}

/// Fills `row.others` from `worlds` (one per [`OTHER_METHODS`]) at the eye `row` was measured
/// at, against the reference pictures [`measure`] kept.
fn seen_by_others(
    gpu: &Gpu,
    worlds: &mut [World],
    target: &Offscreen,
    (mut row, m): (DistanceRow, Measured),
) -> Result<DistanceRow> {
    let (w, h) = m.view.size;
    for (i, world) in worlds.iter_mut().enumerate() {
        let (a, _) = target.render_world(gpu, world, &m.view, None)?;
        let (b, _) = target.render_world(gpu, world, &m.stepped, None)?;
        let (_, distance) = headless::world_depth_metrics(gpu, world, &m.view, 1)?;
        let coverage = metrics::coverage(&m.reference.distance, &distance, 0.01);
        let (flip, _) =
            metrics::image_error(&metrics::rgb(&m.reference.rgba), &metrics::rgb(&a), w, h);
        row.others[i] = Seen {
            step_change: change(&a, &b),
            missed: coverage.missed,
            extra: coverage.extra,
            flip,
        };
    }
    Ok(row)
}

/// Mean absolute 8-bit difference of two pictures.
fn change(a: &[u8], b: &[u8]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| f64::from(x.abs_diff(*y)))
        .sum::<f64>()
        / a.len() as f64
}

/// What [`measure`] keeps for the other methods: the two eyes and the reference's picture.
struct Measured {
    view: WorldView,
    stepped: WorldView,
    reference: headless::RayImage,
}

fn measure(
    gpu: &Gpu,
    params: &WorldParams,
    (world, target): (&mut World, &Offscreen),
    view: &WorldView,
    options: &DistanceOptions,
) -> Result<(DistanceRow, Measured)> {
    let (w, h) = options.size;
    let land = &params.land;
    // The mesh, and the same after the step.
    let mut stepped = *view;
    stepped.eye += DVec3::new(options.step, 0.0, 0.6 * options.step);
    let (mesh, _) = target.render_world(gpu, world, view, None)?;
    let (mesh_b, _) = target.render_world(gpu, world, &stepped, None)?;
    let (error, mesh_distance) = headless::world_depth_metrics(gpu, world, view, 1)?;
    // The reference, and the same after the step.
    let shading = Shading::default();
    let cast = |v: &WorldView| {
        headless::render_world_rays(gpu, params, &shading, v, Method::Reference, None)
    };
    let (reference, reference_b) = (cast(view)?, cast(&stepped)?);
    let coverage = metrics::coverage(&reference.distance, &mesh_distance, 0.01);
    let (flip, _) =
        metrics::image_error(&metrics::rgb(&reference.rgba), &metrics::rgb(&mesh), w, h);
    // The bake at the finest level's samples under the eye, against the twin's.
    let log2 = relief::clipmap::finest_log2(land);
    let s = 2f64.powi(log2);
    let n = options.bake_side;
    let origin = [
        (view.eye.x / s).floor() as i32 - n as i32 / 2,
        (view.eye.z / s).floor() as i32 - n as i32 / 2,
    ];
    let mut height_error_m: f64 = 0.0;
    headless::bake_region(gpu, land, origin, n, log2, None, |first, band| {
        for (k, t) in band.iter().enumerate() {
            let (i, j) = ((k as u32 % n) as i64, (first + k as u32 / n) as i64);
            let twin = land.level_sample(
                Channel::Height,
                log2,
                i64::from(origin[0]) + i,
                i64::from(origin[1]) + j,
            );
            let e = (f64::from(t[0]) - twin.value).abs() * land.peak_height;
            height_error_m = height_error_m.max(e);
        }
    })?;
    let row = DistanceRow {
        distance: 0.0,
        refused: None,
        height_error_m,
        screen_error_p99: error.p99,
        screen_error_max: error.max,
        step_change: [
            change(&mesh, &mesh_b),
            change(&reference.rgba, &reference_b.rgba),
        ],
        missed: coverage.missed,
        extra: coverage.extra,
        flip,
        others: Default::default(),
    };
    let kept = Measured {
        view: *view,
        stepped,
        reference,
    };
    Ok((row, kept))
}

/// The CSV: a header and a row per distance, with the device and backend.
pub fn distance_csv(rows: &[DistanceRow], device: &str, backend: &str) -> String {
    let mut out = String::from(
        "distance_m,refused,height_error_m,screen_error_p99_px,screen_error_max_px,step_change_mesh,step_change_reference,jitter,missed,extra,flip_mesh_vs_reference,",
    );
    for m in OTHER_METHODS {
        let _ = write!(
            out,
            "jitter_{m},missed_{m},extra_{m},flip_{m}_vs_reference,"
        );
    }
    out.push_str("device,backend\n");
    for r in rows {
        let others: String = (0..OTHER_METHODS.len())
            .map(|i| {
                let o = &r.others[i];
                format!(
                    "{:.3},{:.5},{:.5},{:.4},",
                    r.jitter_of(i),
                    o.missed,
                    o.extra,
                    o.flip
                )
            })
            .collect();
        let _ = writeln!(
            out,
            "{:e},{},{:.3e},{:.3},{:.3},{:.4},{:.4},{:.3},{:.5},{:.5},{:.4},{others}{device},{backend}",
            r.distance,
            r.refused
                .as_deref()
                .map_or(String::new(), |s| format!("\"{s}\"")),
            r.height_error_m,
            r.screen_error_p99,
            r.screen_error_max,
            r.step_change[0],
            r.step_change[1],
            r.jitter(),
            r.missed,
            r.extra,
            r.flip,
        );
    }
    out
}

/// The table: a row per distance.
pub fn distance_table(rows: &[DistanceRow]) -> String {
    let mut out = String::from(
        "distance m   height err m  screen px p99/max   jitter   missed/extra     FLIP   visibility: jitter missed FLIP   hybrid: jitter missed FLIP\n",
    );
    for r in rows {
        if let Some(why) = &r.refused {
            let _ = writeln!(out, "{:<12.0e} refused: the eye must be {why}", r.distance);
            continue;
        }
        let _ = write!(
            out,
            "{:<12.0e} {:>12.2e} {:>8.2} / {:>6.2} {:>8.2} {:>7.4} / {:.4} {:>8.4}",
            r.distance,
            r.height_error_m,
            r.screen_error_p99,
            r.screen_error_max,
            r.jitter(),
            r.missed,
            r.extra,
            r.flip
        );
        for (i, o) in r.others.iter().enumerate() {
            let _ = write!(
                out,
                "   {:>8.2} {:>7.4} {:>6.4}",
                r.jitter_of(i),
                o.missed + o.extra,
                o.flip
            );
        }
        out.push('\n');
    }
    out.push_str(
        "jitter: a method's change under a 1 cm step over the reference's; missed: terrain \
         missed or added against the reference; visibility and hybrid at 1 sample a pixel\n",
    );
    out
}

/// The chart: per distance (log), the mesh's jitter against the reference, the screen
/// error's 99th percentile (px) and missed pixels (%), refused distances marked.
pub fn distance_chart(rows: &[DistanceRow], (title, stem): (&str, &std::path::Path)) -> Result<()> {
    crate::chart::write_chart(stem, |b| draw(b, rows, title), |b| draw(b, rows, title))
}

/// A line of the chart: its legend, colour and value per row.
type Series<'a> = (
    &'static str,
    plotters::style::RGBAColor,
    Box<dyn Fn(&DistanceRow) -> f64 + 'a>,
);

fn draw<DB: plotters::prelude::DrawingBackend>(
    backend: DB,
    rows: &[DistanceRow],
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
    let (d0, d1) = super::log_span(rows.iter().map(|r| r.distance), 2.0);
    let measured: Vec<&DistanceRow> = rows.iter().filter(|r| r.refused.is_none()).collect();
    let series: [Series; 5] = [
        (
            "jitter: a 1 cm step's change, mesh / reference",
            BLACK.to_rgba(),
            Box::new(|r| r.jitter()),
        ),
        (
            "jitter, visibility / reference",
            Palette99::pick(1).to_rgba(),
            Box::new(|r| r.jitter_of(0)),
        ),
        (
            "jitter, hybrid / reference",
            Palette99::pick(3).to_rgba(),
            Box::new(|r| r.jitter_of(1)),
        ),
        (
            "mesh screen error p99, px",
            Palette99::pick(2).to_rgba(),
            Box::new(|r| r.screen_error_p99),
        ),
        (
            "missed pixels, % (holes, seams)",
            Palette99::pick(4).to_rgba(),
            Box::new(|r| 100.0 * r.missed),
        ),
    ];
    let top = measured
        .iter()
        .flat_map(|r| series.iter().map(move |s| (s.2)(r)))
        .fold(2.0, f64::max)
        * 1.15;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 20))
        .margin(16)
        .x_label_area_size(48)
        .y_label_area_size(64)
        .build_cartesian_2d((d0..d1).log_scale(), 0.0..top)
        .map_err(|e| e.to_string())?;
    chart
        .configure_mesh()
        .x_label_formatter(&|v| format!("{v:.0e}"))
        .x_desc("eye's distance from the origin, metres (log)")
        .y_desc("ratio, pixels or percent (see legend)")
        .label_style(("sans-serif", 15))
        .axis_desc_style(("sans-serif", 15))
        .draw()
        .map_err(|e| e.to_string())?;
    for (label, color, value) in &series {
        let color = *color;
        let line: Vec<(f64, f64)> = measured.iter().map(|r| (r.distance, value(r))).collect();
        chart
            .draw_series(LineSeries::new(line.clone(), color.stroke_width(2)))
            .map_err(|e| e.to_string())?
            .label(*label)
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color));
        chart
            .draw_series(line.iter().map(|&p| Circle::new(p, 4, color.filled())))
            .map_err(|e| e.to_string())?;
    }
    let red = RGBColor(200, 30, 30);
    let refused: Vec<f64> = rows
        .iter()
        .filter(|r| r.refused.is_some())
        .map(|r| r.distance)
        .collect();
    if !refused.is_empty() {
        chart
            .draw_series(
                refused
                    .iter()
                    .map(|&d| Cross::new((d, top * 0.05), 8, red.stroke_width(3))),
            )
            .map_err(|e| e.to_string())?
            .label("refused: the eye beyond the world's reach")
            .legend(move |(x, y)| Cross::new((x + 10, y), 6, red.stroke_width(3)));
    }
    crate::chart::legend(&mut chart, SeriesLabelPosition::UpperLeft)?;
    root.present().map_err(|e| e.to_string())
}
