//! The chart of `relief bench`: error against GPU time on log axes, a series per method, the
//! Pareto front, the default labelled.

use super::*;

/// Writes the chart (error against GPU time, log axes, a series per method, the Pareto front,
/// the default labelled) as `stem.png` and `stem.svg`.
pub fn chart(rows: &[Row], title: &str, stem: &Path) -> Result<()> {
    write_chart(
        stem,
        |b| draw_chart(b, rows, title),
        |b| draw_chart(b, rows, title),
    )
}

pub(super) fn draw_chart<DB: plotters::prelude::DrawingBackend>(
    backend: DB,
    rows: &[Row],
    title: &str,
) -> std::result::Result<(), String>
where
    DB::ErrorType: 'static,
{
    use plotters::prelude::*;
    let root = backend.into_drawing_area();
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let pts: Vec<(f64, f64, &Row)> = rows
        .iter()
        // Log axes: a zero time (a timestamp that did not advance) sits at the axis' floor.
        .filter_map(|r| {
            r.frame_gpu_ms()
                .map(|t| (t.max(1e-4), r.flip_mean.max(1e-4), r))
        })
        .collect();
    if pts.is_empty() {
        return Err("no timed rows to chart (does the adapter have timestamp queries?)".into());
    }
    let (tmin, tmax) = pts
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p.0), b.max(p.0)));
    let (emin, emax) = pts
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p.1), b.max(p.1)));
    let (t0, t1) = (tmin / 1.4, tmax * 1.4);
    let (e0, e1) = (emin / 1.25, emax * 1.25);
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 20))
        .margin(16)
        .x_label_area_size(48)
        .y_label_area_size(64)
        .build_cartesian_2d(
            (t0..t1).log_scale().with_key_points(log_ticks(t0, t1, 5)),
            (e0..e1).log_scale().with_key_points(log_ticks(e0, e1, 4)),
        )
        .map_err(|e| e.to_string())?;
    chart
        .configure_mesh()
        .x_label_formatter(&|v| tick_label(*v))
        .y_label_formatter(&|v| tick_label(*v))
        .x_desc("GPU time per frame, ms (log; mesh: full re-bake + draw)")
        .y_desc("FLIP mean against the reference (log)")
        .label_style(("sans-serif", 15))
        .axis_desc_style(("sans-serif", 15))
        .draw()
        .map_err(|e| e.to_string())?;
    let series = [
        (Method::Mesh, RGBColor(31, 119, 180)),
        (Method::Visibility, RGBColor(255, 127, 14)),
        (Method::RaymarchFragment, RGBColor(214, 39, 40)),
        (Method::Raymarch, RGBColor(44, 160, 44)),
        (Method::Blog, RGBColor(148, 103, 189)),
    ];
    for (method, color) in series {
        let mine: Vec<(f64, f64)> = pts
            .iter()
            .filter(|p| p.2.config.method == method)
            .map(|p| (p.0, p.1))
            .collect();
        if mine.is_empty() {
            continue;
        }
        chart
            .draw_series(mine.iter().map(|&p| Circle::new(p, 5, color.filled())))
            .map_err(|e| e.to_string())?
            .label(match method {
                Method::Blog => "blog (against its own exact surface)",
                m => m.name(),
            })
            .legend(move |(x, y)| Circle::new((x + 10, y), 5, color.filled()));
    }
    let front: Vec<(f64, f64)> = pareto(rows)
        .into_iter()
        .filter_map(|i| {
            rows[i]
                .frame_gpu_ms()
                .map(|t| (t.max(1e-4), rows[i].flip_mean.max(1e-4)))
        })
        .collect();
    chart
        .draw_series(LineSeries::new(front.clone(), BLACK.stroke_width(1)))
        .map_err(|e| e.to_string())?
        .label("Pareto front")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLACK));
    chart
        .draw_series(
            front
                .iter()
                .map(|&p| Circle::new(p, 8, BLACK.stroke_width(1))),
        )
        .map_err(|e| e.to_string())?;
    // The default: a ring of its own and its label right beside it.
    let default = default_row(rows).map(|i| &rows[i]);
    for p in pts
        .iter()
        .filter(|p| default.is_some_and(|d| std::ptr::eq(p.2, d)))
    {
        let label = format!("default ({})", p.2.config.label());
        // Beside the marker, on whichever side has room for the text.
        let (px, _) = chart.backend_coord(&(p.0, p.1));
        let width = (label.chars().count() as f64 * 7.6) as i32;
        let dx = if px + 14 + width > CHART_SIZE.0 as i32 - 16 {
            -14 - width
        } else {
            14
        };
        chart
            .draw_series(std::iter::once(
                EmptyElement::at((p.0, p.1))
                    + Circle::new((0, 0), 11, RGBColor(255, 127, 14).stroke_width(3))
                    + Text::new(
                        label,
                        (dx, -24),
                        ("sans-serif", 15).into_font().color(&BLACK),
                    ),
            ))
            .map_err(|e| e.to_string())?;
    }
    legend(&mut chart, SeriesLabelPosition::UpperRight)?;
    root.present().map_err(|e| e.to_string())?;
    Ok(())
}
