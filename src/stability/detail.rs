//! The detail axis of `relief stability`: octaves against texel size, on the CPU twin (no GPU,
//! so the same on every machine). A baked texture holds the surface at its texels only; octaves
//! whose lattice cells span fewer than two texels are above its Nyquist frequency, and what
//! they add is aliased into the texels rather than kept. For each octave count and texture
//! side, on the tile of the scene the flags give:
//!
//! - **normal error**: normals from the baked heights' central differences (the normal pass's)
//!   against the analytic normals of the continuous surface at the same texels, degrees;
//! - **energy above Nyquist**: the share of the height's variance in octaves with under two
//!   texels a lattice cell (octave `o` adds variance in proportion to `gain^(2o)`), and the
//!   share of the slope's (in proportion to `(2 gain)^(2o)`: each octave's slope doubles with
//!   its frequency, so with the default gain of 0.47 the finest octaves carry as much slope as
//!   the first, and it is the slope that shading sees).

use crate::error::Result;
use crate::noise::{analytic_normal, central_difference_normal, Channel, Fbm};
use crate::params::TerrainParams;
use std::fmt::Write as _;

/// What the detail sweep measures with.
#[derive(Clone, Debug, PartialEq)]
pub struct DetailOptions {
    /// Octave counts (at most what the scene's frequency allows).
    pub octaves: Vec<u32>,
    /// Texture sides, texels.
    pub sizes: Vec<u32>,
}

impl DetailOptions {
    /// The full sweep: 2 to 12 octaves, 256² to 2048² texels.
    pub fn full() -> Self {
        Self {
            octaves: vec![2, 4, 6, 8, 10, 12],
            sizes: vec![256, 512, 1024, 2048],
        }
    }

    /// `--quick`: small enough for the tests.
    pub fn quick() -> Self {
        Self {
            octaves: vec![4, 8, 10],
            sizes: vec![128, 512],
        }
    }
}

/// One octave count at one texture side.
#[derive(Clone, Debug, PartialEq)]
pub struct DetailRow {
    /// Octaves of the surface.
    pub octaves: u32,
    /// Texels a side.
    pub size: u32,
    /// Angle between the difference normal and the analytic one, degrees: mean, 99th
    /// percentile, largest.
    pub angle_mean_deg: f64,
    pub angle_p99_deg: f64,
    pub angle_max_deg: f64,
    /// Share of the height's variance in octaves with under two texels a lattice cell.
    pub above_nyquist: f64,
    /// Share of the slope's variance in those octaves.
    pub slope_above_nyquist: f64,
}

/// Sweeps the detail axis for `params` (its octaves replaced by each of the options'; counts
/// the scene's frequency does not allow are left out).
pub fn detail(params: &TerrainParams, options: &DetailOptions) -> Result<Vec<DetailRow>> {
    params.validate()?;
    let max = crate::params::max_octaves_for(params.frequency);
    let combos: Vec<(u32, u32)> = options
        .octaves
        .iter()
        .filter(|&&o| (1..=max).contains(&o))
        .flat_map(|&o| options.sizes.iter().map(move |&s| (o, s)))
        .collect();
    let one = |&(octaves, size): &(u32, u32)| {
        let p = TerrainParams { octaves, ..*params };
        let fbm = Fbm::from_params(&p);
        let hs = f64::from(p.height_scale);
        let heights = fbm.bake(Channel::Height, size);
        let s = f64::from(size);
        let angles: Vec<f64> = (0..size * size)
            .map(|i| {
                let (x, y) = (i % size, i / size);
                let baked = central_difference_normal(&heights, size, hs, x, y);
                let u = [(f64::from(x) + 0.5) / s, (f64::from(y) + 0.5) / s];
                super::angle_deg(baked, analytic_normal(&fbm, hs, u))
            })
            .collect();
        let (angle_mean_deg, angle_p99_deg, angle_max_deg) = super::summary(angles);
        let gain = f64::from(p.gain);
        let aliased = |o: &u32| f64::from(p.frequency << o) > s / 2.0;
        let share = |energy: &dyn Fn(u32) -> f64| {
            let total = (0..octaves).map(energy).fold(0.0, |a, e| a + e);
            let above = (0..octaves)
                .filter(aliased)
                .map(energy)
                .fold(0.0, |a, e| a + e);
            above / total
        };
        DetailRow {
            octaves,
            size,
            angle_mean_deg,
            angle_p99_deg,
            angle_max_deg,
            above_nyquist: share(&|o| gain.powi(2 * o as i32)),
            slope_above_nyquist: share(&|o| (2.0 * gain).powi(2 * o as i32)),
        }
    };
    Ok(super::parallel_map(&combos, one))
}

/// The CSV: a header and a row per octave count and side, with the scene.
pub fn detail_csv(rows: &[DetailRow], params: &TerrainParams) -> String {
    let mut out = String::from(
        "axis,octaves,size,seed,frequency,gain,height_scale,normal_error_mean_deg,normal_error_p99_deg,normal_error_max_deg,energy_above_nyquist,slope_energy_above_nyquist\n",
    );
    for r in rows {
        let _ = writeln!(
            out,
            "detail,{},{},{},{},{},{},{:.4},{:.4},{:.4},{:.6},{:.4}",
            r.octaves,
            r.size,
            params.seed,
            params.frequency,
            params.gain,
            params.height_scale,
            r.angle_mean_deg,
            r.angle_p99_deg,
            r.angle_max_deg,
            r.above_nyquist,
            r.slope_above_nyquist
        );
    }
    out
}

/// The table: a row per octave count, a column per side (p99 normal error / energy above
/// Nyquist).
pub fn detail_table(rows: &[DetailRow], options: &DetailOptions) -> String {
    let mut out = format!("{:<8}", "octaves");
    for s in &options.sizes {
        let _ = write!(out, " {:>24}", format!("{s}²"));
    }
    out.push('\n');
    for o in &options.octaves {
        if !rows.iter().any(|r| r.octaves == *o) {
            continue;
        }
        let _ = write!(out, "{o:<8}");
        for s in &options.sizes {
            let cell = rows
                .iter()
                .find(|r| r.octaves == *o && r.size == *s)
                .map_or("-".to_owned(), |r| {
                    format!(
                        "{:.2}° / {:.4} / {:.2}",
                        r.angle_p99_deg, r.above_nyquist, r.slope_above_nyquist
                    )
                });
            let _ = write!(out, " {cell:>24}");
        }
        out.push('\n');
    }
    out.push_str("cells: normal error p99 (differences of the baked heights against the analytic normal) / share of the height's variance above Nyquist / of the slope's\n");
    out
}

/// The chart: the normal error's 99th percentile against octaves, a line per texture side,
/// the scene's (octaves, side) marked.
pub fn detail_chart(
    rows: &[DetailRow],
    scene: (u32, u32),
    (title, stem): (&str, &std::path::Path),
) -> Result<()> {
    crate::bench::write_chart(
        stem,
        |b| draw(b, rows, scene, title),
        |b| draw(b, rows, scene, title),
    )
}

fn draw<DB: plotters::prelude::DrawingBackend>(
    backend: DB,
    rows: &[DetailRow],
    (scene_octaves, scene_size): (u32, u32),
    title: &str,
) -> std::result::Result<(), String>
where
    DB::ErrorType: 'static,
{
    use plotters::prelude::*;
    let root = backend.into_drawing_area();
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let o0 = rows.iter().map(|r| r.octaves).min().unwrap_or(1);
    let o1 = rows.iter().map(|r| r.octaves).max().unwrap_or(1);
    let top = rows.iter().map(|r| r.angle_p99_deg).fold(1.0, f64::max) * 1.15;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 20))
        .margin(16)
        .x_label_area_size(48)
        .y_label_area_size(64)
        .build_cartesian_2d(f64::from(o0) - 0.5..f64::from(o1) + 0.5, 0.0..top)
        .map_err(|e| e.to_string())?;
    chart
        .configure_mesh()
        .x_labels((o1 - o0 + 1) as usize)
        .x_label_formatter(&|v| format!("{v:.0}"))
        .x_desc("octaves")
        .y_desc("normal error p99, degrees (differences of the bake against analytic)")
        .label_style(("sans-serif", 15))
        .axis_desc_style(("sans-serif", 15))
        .draw()
        .map_err(|e| e.to_string())?;
    let mut sizes: Vec<u32> = rows.iter().map(|r| r.size).collect();
    sizes.sort_unstable();
    sizes.dedup();
    for (i, &size) in sizes.iter().enumerate() {
        let color = Palette99::pick(i).to_rgba();
        let line: Vec<(f64, f64)> = rows
            .iter()
            .filter(|r| r.size == size)
            .map(|r| (f64::from(r.octaves), r.angle_p99_deg))
            .collect();
        chart
            .draw_series(LineSeries::new(line.clone(), color.stroke_width(2)))
            .map_err(|e| e.to_string())?
            .label(format!("{size}² texels"))
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color));
        chart
            .draw_series(line.iter().map(|&p| Circle::new(p, 4, color.filled())))
            .map_err(|e| e.to_string())?;
    }
    if let Some(r) = rows
        .iter()
        .find(|r| r.octaves == scene_octaves && r.size == scene_size)
    {
        chart
            .draw_series([Cross::new(
                (f64::from(r.octaves), r.angle_p99_deg),
                9,
                BLACK.stroke_width(3),
            )])
            .map_err(|e| e.to_string())?
            .label(format!(
                "the scene: {scene_octaves} octaves at {scene_size}²"
            ))
            .legend(|(x, y)| Cross::new((x + 10, y), 6, BLACK.stroke_width(3)));
    }
    crate::bench::legend(&mut chart, SeriesLabelPosition::UpperLeft)?;
    root.present().map_err(|e| e.to_string())
}
