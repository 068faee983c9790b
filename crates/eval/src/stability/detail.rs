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
//! - **FLIP** (on the GPU, [`detail_flip`]): the tile's mesh with those octaves and texels,
//!   drawn from the benchmark's view, against the reference ray cast of the same surface; and
//!   the LOD knob (the mesh's `grid`, its finest vertex spacing) swept at the scene's octaves;
//!   each drawn by the forward mesh (shaded once a pixel) and by the visibility method (the
//!   same mesh, four samples a pixel shaded).

use relief::error::Result;
use relief::gpu::headless::{Gpu, Offscreen};
use relief::noise::{analytic_normal, central_difference_normal, Channel, Fbm};
use relief::params::TerrainParams;
use std::fmt::Write as _;

/// What the detail sweep measures with.
#[derive(Clone, Debug, PartialEq)]
pub struct DetailOptions {
    /// Octave counts (at most what the scene's frequency allows).
    pub octaves: Vec<u32>,
    /// Texture sides, texels.
    pub sizes: Vec<u32>,
    /// The LOD knob: mesh grids (vertices a side), swept at the scene's octaves and side (the
    /// side capped at the largest of `sizes`), the other rows at the scene's grid.
    pub grids: Vec<u32>,
    /// The image [`detail_flip`] draws, pixels.
    pub image: (u32, u32),
}

impl DetailOptions {
    /// The full sweep: 2 to 12 octaves, 256² to 2048² texels.
    pub fn full() -> Self {
        Self {
            octaves: vec![2, 4, 6, 8, 10, 12],
            sizes: vec![256, 512, 1024, 2048],
            grids: vec![32, 64, 128, 256, 512, 1024],
            image: (960, 540),
        }
    }

    /// `--quick`: small enough for the tests.
    pub fn quick() -> Self {
        Self {
            octaves: vec![4, 8, 10],
            sizes: vec![128, 512],
            grids: vec![32, 256],
            image: (96, 64),
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
    /// Mesh vertices a side (the LOD knob).
    pub grid: u32,
    /// Mean FLIP of the mesh against the reference ([`detail_flip`]; None until measured).
    pub flip: Option<f64>,
    /// The same for the visibility method (the mesh shaded at four samples a pixel).
    pub flip_visibility: Option<f64>,
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
    let max = relief::params::max_octaves_for(params.frequency);
    let mut combos: Vec<(u32, u32, u32)> = options
        .octaves
        .iter()
        .filter(|&&o| (1..=max).contains(&o))
        .flat_map(|&o| options.sizes.iter().map(move |&s| (o, s, params.grid)))
        .collect();
    let knob_size = params
        .size
        .min(options.sizes.iter().copied().max().unwrap_or(params.size));
    for &g in &options.grids {
        let row = (params.octaves, knob_size, g);
        if !combos.contains(&row) {
            combos.push(row);
        }
    }
    let one = |&(octaves, size, grid): &(u32, u32, u32)| {
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
            grid,
            flip: None,
            flip_visibility: None,
            angle_mean_deg,
            angle_p99_deg,
            angle_max_deg,
            above_nyquist: share(&|o| gain.powi(2 * o as i32)),
            slope_above_nyquist: share(&|o| (2.0 * gain).powi(2 * o as i32)),
        }
    };
    Ok(super::parallel_map(&combos, one))
}

/// Draws the tile's mesh for every row (its octaves, texels and grid, the scene's other
/// values) from the benchmark's view at `image` pixels, and scores it by mean FLIP against the
/// reference ray cast of the same surface (one reference per octave count).
pub fn detail_flip(
    gpu: &Gpu,
    params: &TerrainParams,
    rows: &mut [DetailRow],
    (width, height): (u32, u32),
) -> Result<()> {
    let options = crate::bench::Options {
        width,
        height,
        ..crate::bench::Options::QUICK
    };
    let view = relief::camera::OrbitCamera::default().view(width as f32 / height as f32);
    let shading = relief::Shading::default();
    let samples = relief::gpu::headless::RENDER_SAMPLES;
    let target = Offscreen::new(&gpu.device, width, height, samples)?;
    let mut octaves: Vec<u32> = rows.iter().map(|r| r.octaves).collect();
    octaves.sort_unstable();
    octaves.dedup();
    for o in octaves {
        let p = TerrainParams {
            octaves: o,
            ..*params
        };
        let reference = crate::bench::Reference::new(gpu, &p, &shading, &view, &options)?;
        for r in rows.iter_mut().filter(|r| r.octaves == o) {
            let p = TerrainParams {
                size: r.size,
                grid: r.grid,
                ..p
            };
            let mut terrain =
                relief::Terrain::new(&gpu.device, &gpu.queue, Offscreen::targets(samples), p)?;
            let score = |terrain: &mut relief::Terrain| -> Result<f64> {
                let (image, _) = target.render(gpu, terrain, &view, None)?;
                let rgb = crate::metrics::rgb(&image);
                Ok(crate::metrics::image_error(&reference.rgb, &rgb, width, height).0)
            };
            r.flip = Some(score(&mut terrain)?);
            terrain.set_method(&gpu.device, relief::Method::Visibility)?;
            r.flip_visibility = Some(score(&mut terrain)?);
        }
    }
    Ok(())
}

/// The CSV: a header and a row per octave count and side, with the scene.
pub fn detail_csv(rows: &[DetailRow], params: &TerrainParams) -> String {
    let mut out = String::from(
        "axis,octaves,size,grid,seed,frequency,gain,height_scale,normal_error_mean_deg,normal_error_p99_deg,normal_error_max_deg,energy_above_nyquist,slope_energy_above_nyquist,flip_mean,flip_visibility_mean\n",
    );
    for r in rows {
        let _ = writeln!(
            out,
            "detail,{},{},{},{},{},{},{},{:.4},{:.4},{:.4},{:.6},{:.4},{},{}",
            r.octaves,
            r.size,
            r.grid,
            params.seed,
            params.frequency,
            params.gain,
            params.height_scale,
            r.angle_mean_deg,
            r.angle_p99_deg,
            r.angle_max_deg,
            r.above_nyquist,
            r.slope_above_nyquist,
            r.flip.map_or(String::new(), |f| format!("{f:.4}")),
            r.flip_visibility
                .map_or(String::new(), |f| format!("{f:.4}"))
        );
    }
    out
}

/// The rows of the LOD knob's sweep: those at the knob's octaves and side (the last rows
/// [`detail`] adds), by grid.
fn knob_rows(rows: &[DetailRow]) -> Vec<&DetailRow> {
    let Some(last) = rows.last() else {
        return Vec::new();
    };
    let mut knob: Vec<&DetailRow> = rows
        .iter()
        .filter(|r| r.octaves == last.octaves && r.size == last.size)
        .collect();
    knob.sort_by_key(|r| r.grid);
    knob
}

/// The table: a row per octave count, a column per side (p99 normal error / energy above
/// Nyquist / FLIP), then the LOD knob's rows.
pub fn detail_table(rows: &[DetailRow], options: &DetailOptions) -> String {
    let flip = |r: &DetailRow| r.flip.map_or("-".to_owned(), |f| format!("{f:.3}"));
    let vis = |r: &DetailRow| {
        r.flip_visibility
            .map_or("-".to_owned(), |f| format!("{f:.3}"))
    };
    let knob = knob_rows(rows);
    // The octaves-by-sides rows, at the scene's grid (the first row's).
    let main: Vec<&DetailRow> = rows.iter().filter(|r| r.grid == rows[0].grid).collect();
    let mut out = format!("{:<8}", "octaves");
    for s in &options.sizes {
        let _ = write!(out, " {:>30}", format!("{s}²"));
    }
    out.push('\n');
    for o in &options.octaves {
        if !main.iter().any(|r| r.octaves == *o) {
            continue;
        }
        let _ = write!(out, "{o:<8}");
        for s in &options.sizes {
            let cell = main
                .iter()
                .find(|r| r.octaves == *o && r.size == *s)
                .map_or("-".to_owned(), |r| {
                    format!(
                        "{:.2}° / {:.4} / {:.2} / {}",
                        r.angle_p99_deg,
                        r.above_nyquist,
                        r.slope_above_nyquist,
                        flip(r)
                    )
                });
            let _ = write!(out, " {cell:>30}");
        }
        out.push('\n');
    }
    out.push_str("cells: normal error p99 (differences of the baked heights against the analytic normal) / share of the height's variance above Nyquist / of the slope's / FLIP of the mesh against the reference\n");
    let vis_line: Vec<String> = main
        .iter()
        .filter(|r| r.flip_visibility.is_some())
        .map(|r| format!("{}@{}² {} (mesh {})", r.octaves, r.size, vis(r), flip(r)))
        .collect();
    if !vis_line.is_empty() {
        let _ = writeln!(
            out,
            "FLIP of the visibility method (octaves@texels): {}",
            vis_line.join(", ")
        );
    }
    if let Some(k) = knob.first() {
        let _ = writeln!(
            out,
            "the LOD knob at {} octaves, {}² texels: grid {}",
            k.octaves,
            k.size,
            knob.iter()
                .map(|r| format!("{} FLIP {} (visibility {})", r.grid, flip(r), vis(r)))
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
    out
}

/// The chart: the normal error's 99th percentile against octaves, a line per texture side,
/// the scene's (octaves, side) marked; beside it FLIP against octaves, and FLIP against the LOD
/// knob (the mesh's grid).
pub fn detail_chart(
    rows: &[DetailRow],
    scene: (u32, u32),
    (title, stem): (&str, &std::path::Path),
) -> Result<()> {
    crate::chart::write_chart(
        stem,
        |b| draw(b, rows, scene, title),
        |b| draw(b, rows, scene, title),
    )
}

type Area<DB> = plotters::drawing::DrawingArea<DB, plotters::coord::Shift>;
/// What a panel plots of a row.
type Pick = dyn Fn(&DetailRow) -> Option<f64>;

fn draw<DB: plotters::prelude::DrawingBackend>(
    backend: DB,
    rows: &[DetailRow],
    scene: (u32, u32),
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
    let (w, _) = root.dim_in_pixel();
    let (left, right) = root.split_horizontally(w / 2);
    let grid = rows.first().map_or(0, |r| r.grid);
    let main: Vec<&DetailRow> = rows.iter().filter(|r| r.grid == grid).collect();
    let y_normal = "normal error p99, degrees (differences of the bake against analytic)";
    by_octaves(
        &left,
        &main,
        scene,
        (y_normal, &|r| Some(r.angle_p99_deg), None),
        (SeriesLabelPosition::UpperLeft, 1.15),
    )?;
    let knob = knob_rows(rows);
    if main.iter().any(|r| r.flip.is_some()) {
        let (top, bottom) = right.split_vertically(right.dim_in_pixel().1 / 2);
        by_octaves(
            &top,
            &main,
            scene,
            (
                "FLIP vs reference (dashed: visibility)",
                &|r| r.flip,
                Some(&|r| r.flip_visibility),
            ),
            // Head room for the legend above lines that rise to the right.
            (SeriesLabelPosition::UpperLeft, 1.7),
        )?;
        by_grid(&bottom, &knob, grid)?;
    }
    Ok(())
}

/// A value against octaves, a line per texture side, the scene marked.
fn by_octaves<DB: plotters::prelude::DrawingBackend>(
    area: &Area<DB>,
    rows: &[&DetailRow],
    (scene_octaves, scene_size): (u32, u32),
    (y_desc, value, dashed): (&str, &Pick, Option<&Pick>),
    (legend, headroom): (plotters::chart::SeriesLabelPosition, f64),
) -> std::result::Result<(), String>
where
    DB::ErrorType: 'static,
{
    use plotters::prelude::*;
    let o0 = rows.iter().map(|r| r.octaves).min().unwrap_or(1);
    let o1 = rows.iter().map(|r| r.octaves).max().unwrap_or(1);
    let top = rows
        .iter()
        .flat_map(|r| [value(r), dashed.and_then(|d| d(r))])
        .flatten()
        .fold(1e-3, f64::max)
        * headroom;
    let mut chart = ChartBuilder::on(area)
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
        .y_desc(y_desc)
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
            .filter_map(|r| value(r).map(|v| (f64::from(r.octaves), v)))
            .collect();
        chart
            .draw_series(LineSeries::new(line.clone(), color.stroke_width(2)))
            .map_err(|e| e.to_string())?
            .label(format!("{size}² texels"))
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color));
        chart
            .draw_series(line.iter().map(|&p| Circle::new(p, 4, color.filled())))
            .map_err(|e| e.to_string())?;
        if let Some(dashed) = dashed {
            let line: Vec<(f64, f64)> = rows
                .iter()
                .filter(|r| r.size == size)
                .filter_map(|r| dashed(r).map(|v| (f64::from(r.octaves), v)))
                .collect();
            chart
                .draw_series(DashedLineSeries::new(line, 8, 5, color.stroke_width(2)))
                .map_err(|e| e.to_string())?;
        }
    }
    if let Some((r, v)) = rows
        .iter()
        .find(|r| r.octaves == scene_octaves && r.size == scene_size)
        .and_then(|r| value(r).map(|v| (r, v)))
    {
        chart
            .draw_series([Cross::new(
                (f64::from(r.octaves), v),
                9,
                BLACK.stroke_width(3),
            )])
            .map_err(|e| e.to_string())?
            .label(format!(
                "the scene: {scene_octaves} octaves at {scene_size}²"
            ))
            .legend(|(x, y)| Cross::new((x + 10, y), 6, BLACK.stroke_width(3)));
    }
    crate::chart::legend(&mut chart, legend)
}

/// FLIP against the LOD knob (the mesh's grid, on a log2 axis), the scene's grid marked.
fn by_grid<DB: plotters::prelude::DrawingBackend>(
    area: &Area<DB>,
    knob: &[&DetailRow],
    scene_grid: u32,
) -> std::result::Result<(), String>
where
    DB::ErrorType: 'static,
{
    use plotters::prelude::*;
    let series = |pick: &Pick| -> Vec<(f64, f64)> {
        knob.iter()
            .filter_map(|r| pick(r).map(|f| (f64::from(r.grid).log2(), f)))
            .collect()
    };
    let points = series(&|r| r.flip);
    let visibility = series(&|r| r.flip_visibility);
    let (Some(first), Some(last)) = (points.first(), points.last()) else {
        return Ok(());
    };
    let top = points
        .iter()
        .chain(&visibility)
        .map(|p| p.1)
        .fold(1e-3, f64::max)
        * 1.15;
    let caption = format!(
        "the LOD knob at {} octaves, {}² texels",
        knob[0].octaves, knob[0].size
    );
    let mut chart = ChartBuilder::on(area)
        .caption(caption, ("sans-serif", 15))
        .margin(16)
        .x_label_area_size(48)
        .y_label_area_size(64)
        .build_cartesian_2d(first.0 - 0.5..last.0 + 0.5, 0.0..top)
        .map_err(|e| e.to_string())?;
    chart
        .configure_mesh()
        .x_labels((last.0 - first.0) as usize + 1)
        .x_label_formatter(&|v| format!("{:.0}", v.exp2()))
        .x_desc("mesh grid, vertices a side (finer: more triangles)")
        .y_desc("FLIP against the reference")
        .label_style(("sans-serif", 15))
        .axis_desc_style(("sans-serif", 15))
        .draw()
        .map_err(|e| e.to_string())?;
    for (i, (name, line)) in [("mesh", &points), ("visibility", &visibility)]
        .into_iter()
        .enumerate()
    {
        let color = Palette99::pick(i).to_rgba();
        chart
            .draw_series(LineSeries::new(line.clone(), color.stroke_width(2)))
            .map_err(|e| e.to_string())?
            .label(name)
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color));
        chart
            .draw_series(line.iter().map(|&p| Circle::new(p, 4, color.filled())))
            .map_err(|e| e.to_string())?;
    }
    let scene = f64::from(scene_grid).log2();
    if let Some(&p) = points.iter().find(|p| p.0 == scene) {
        chart
            .draw_series([Cross::new(p, 9, BLACK.stroke_width(3))])
            .map_err(|e| e.to_string())?
            .label(format!("the scene: grid {scene_grid}"))
            .legend(|(x, y)| Cross::new((x + 10, y), 6, BLACK.stroke_width(3)));
    }
    crate::chart::legend(&mut chart, SeriesLabelPosition::UpperRight)
}
