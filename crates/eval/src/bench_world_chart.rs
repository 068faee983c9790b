//! The chart of `relief bench --world endless` (`landscape.png` and `.svg`): measured screen
//! error and GPU time against triangles, and FLIP against the reference over GPU time, a panel
//! per view, each point labelled with its knob.

use crate::bench_world::WorldRow;
use crate::chart::{log_ticks, tick_label, CHART_SIZE};
use relief::error::Result;
use relief::Method;

/// Charts the named views' rows (not the flight, nor the random views measured at one knob):
/// measured screen error and GPU render time against triangles, one line per view through the
/// knobs, as `stem`.png and `stem`.svg.
pub fn chart(rows: &[WorldRow], title: &str, stem: &std::path::Path) -> Result<()> {
    let named: Vec<WorldRow> = rows
        .iter()
        .filter(|r| !crate::bench_world::RANDOM_VIEWS.contains(&r.view.as_str()))
        .cloned()
        .collect();
    let rows = &named[..];
    crate::chart::write_chart(stem, |b| draw(b, rows, title), |b| draw(b, rows, title))
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
        crate::chart::legend(&mut chart, legend_at)?;
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
    crate::chart::legend(&mut chart, SeriesLabelPosition::LowerRight)
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
        let compute = if r.raster == Some(relief::Raster::Compute) {
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
    use relief::gpu::headless::ScreenError;

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
                        "compute" => Some(relief::Raster::Compute),
                        "hardware" => Some(relief::Raster::Hardware),
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
