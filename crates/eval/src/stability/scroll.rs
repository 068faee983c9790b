//! The scroll axis of `relief stability`: the tile world far from its origin. Both tile
//! pipelines scroll their terrain: relief's tile by `--offset` (in tiles), the seed blog's by
//! its `progress`, which it adds to each texel's coordinate in f32 (`uv = x / size + progress`)
//! before its sine hash. Far out, an f32 sum cannot hold a texel's share of the coordinate:
//! neighbouring texels round to the same coordinate, and the terrain turns into stripes along
//! the scroll. relief reduces the offset to the tile's period in f64 on the CPU, once, before
//! any GPU work sees it (the tile is periodic, its lattice integer), so every tile method (the
//! mesh, the visibility method, the ray casters, the bake) draws the same terrain at any
//! offset it accepts, and refuses offsets past 2^40 tiles in words.
//!
//! At each distance, each pipeline bakes its texture at the distance and again one texel
//! further along the scroll, and the sweep measures:
//!
//! - **moved**: the fraction of texels that the one-texel scroll moved by one texel, as asked
//!   (the second bake at `x` equals the first at `x + 1`, within the bake's rounding);
//! - **repeated**: the fraction of texel columns equal to the column before them in every
//!   texel (stripes: the coordinate no longer tells them apart);
//! - **held**: the fraction of texels that both moved as asked and lie in a column of their
//!   own: a terrain striped along the scroll "moves" as asked without moving at all, so
//!   neither of the two above alone says whether the terrain held;
//! - **twin error** (relief's tile only): the largest |bake - CPU f64 twin| at the distance.
//!
//! The blog's sine hash has no f64 twin (an f32 `sin` of arguments in the thousands differs
//! between GPUs in the digits its hash keeps), so its rows are judged against itself: a
//! terrain that scrolls must move rigidly and keep varying.

use relief::error::{Error, Result};
use relief::gpu::blog::{Blog, BLOG_SIZE};
use relief::gpu::headless::{self, Gpu, Offscreen};
use relief::gpu::Terrain;
use relief::noise::{Channel, Fbm};
use relief::params::{Shading, TerrainParams};
use std::fmt::Write as _;

/// What the scroll sweep measures with.
#[derive(Clone, Debug, PartialEq)]
pub struct ScrollOptions {
    /// Distances of the scroll from the origin, in tiles (texture widths) along x.
    pub distances: Vec<f64>,
    /// Side of relief's baked tile, in texels (the blog's is its own [`BLOG_SIZE`]).
    pub size: u32,
    /// Every `stride`-th texel each way of relief's bake is compared with the twin.
    pub stride: u32,
}

impl ScrollOptions {
    /// The full sweep: 10^0 to 10^13 tiles, relief's tile at 1024² texels (the blog's side).
    pub fn full() -> Self {
        Self {
            distances: (0..=13).map(|k| 10f64.powi(k)).collect(),
            size: BLOG_SIZE,
            stride: 8,
        }
    }

    /// `--quick`: small enough for the tests.
    pub fn quick() -> Self {
        Self {
            distances: vec![1.0, 1e5, 1e9, 1e13],
            size: 256,
            stride: 4,
        }
    }
}

/// Which tile pipeline a row measures.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scroller {
    /// relief's tile: its bake, from the offset reduced in f64 as every tile method takes it.
    Relief,
    /// The seed blog's bake (`blog`), scrolled by its f32 `progress`.
    Blog,
}

impl Scroller {
    /// Both, relief's first.
    pub const ALL: [Scroller; 2] = [Scroller::Relief, Scroller::Blog];

    /// Its name in the CSV, the table and the chart.
    pub fn label(self) -> &'static str {
        match self {
            Scroller::Relief => "relief",
            Scroller::Blog => "blog",
        }
    }

    /// How far a texel may differ from the texel it should equal after the scroll, in the
    /// normalised height: relief's bake adds the offset's fraction to each texel's position in
    /// f32 (a rounding or two of the position, ~1e-7 of the height, the twin test's 1e-5
    /// tolerance covers it); the blog stores 8 bits, so one code of 255.
    fn tolerance(self) -> f32 {
        match self {
            Scroller::Relief => 1e-5,
            Scroller::Blog => 1.0 / 255.0,
        }
    }
}

/// One pipeline at one distance.
#[derive(Clone, Debug, PartialEq)]
pub struct ScrollRow {
    /// The pipeline.
    pub scroller: Scroller,
    /// Tiles from the origin along x.
    pub distance: f64,
    /// Why the pipeline refused the offset, if it did (the other fields are then 0).
    pub refused: Option<String>,
    /// Fraction of texels a one-texel scroll moved by one texel.
    pub moved: f64,
    /// Fraction of texel columns equal to the column before them.
    pub repeated: f64,
    /// Fraction of texels that moved as asked and lie in a column of their own.
    pub held: f64,
    /// Largest |bake - twin| of the normalised height (relief's tile only).
    pub twin_error: Option<f64>,
}

impl ScrollRow {
    /// Whether the terrain held here: every texel moved as asked, in a column of its own.
    pub fn holds(&self) -> bool {
        self.refused.is_none() && self.held == 1.0
    }
}

/// A baked height field, row-major, `size` a side, normalised heights.
struct Heights {
    size: usize,
    values: Vec<f32>,
}

impl Heights {
    fn at(&self, x: usize, y: usize) -> f32 {
        self.values[y * self.size + x]
    }
}

/// What [`judge`] finds: `moved`, `repeated` and `held` of [`ScrollRow`].
#[derive(Clone, Copy, Debug, PartialEq)]
struct Judged {
    moved: f64,
    repeated: f64,
    held: f64,
}

/// Judges `before` and `after` (the same bake scrolled one texel on). The scroll wraps around
/// the texture's edge only where the terrain is periodic: the last column has no known
/// successor in the blog's, so it is not judged, nor is the first (no column before it).
fn judge(before: &Heights, after: &Heights, tolerance: f32) -> Judged {
    let n = before.size;
    let repeats: Vec<bool> = (0..n)
        .map(|x| x > 0 && (0..n).all(|y| before.at(x, y) == before.at(x - 1, y)))
        .collect();
    let (mut moved, mut held) = (0usize, 0usize);
    for y in 0..n {
        for (x, &repeat) in repeats.iter().enumerate().take(n - 1).skip(1) {
            if (after.at(x, y) - before.at(x + 1, y)).abs() <= tolerance {
                moved += 1;
                held += usize::from(!repeat);
            }
        }
    }
    let texels = (n * (n - 2)) as f64;
    Judged {
        moved: moved as f64 / texels,
        repeated: repeats.iter().filter(|&&r| r).count() as f64 / (n - 1) as f64,
        held: held as f64 / texels,
    }
}

/// Sweeps the scroll axis over `params`' tile (seed, octaves, frequency, gain; the blog's
/// terrain is its own); `progress(done, total)` after each distance.
pub fn scroll(
    gpu: &Gpu,
    params: &TerrainParams,
    options: &ScrollOptions,
    mut progress: impl FnMut(usize, usize),
) -> Result<Vec<ScrollRow>> {
    let tile = TerrainParams {
        size: options.size,
        offset: [0.0; 2],
        ..*params
    };
    let mut terrain = Terrain::new(&gpu.device, &gpu.queue, Offscreen::targets(1), tile)?;
    let blog = Blog::new(&gpu.device, Offscreen::targets(1))?;
    let mut rows = Vec::new();
    for (done, &d) in options.distances.iter().enumerate() {
        rows.push(relief_row(gpu, &mut terrain, d, options.stride)?);
        rows.push(blog_row(gpu, &blog, params, d)?);
        progress(done + 1, options.distances.len());
    }
    Ok(rows)
}

/// `terrain`'s tile baked at `offset` tiles along x.
fn relief_bake(gpu: &Gpu, terrain: &mut Terrain, offset: f64) -> Result<Heights> {
    let params = TerrainParams {
        offset: [offset, 0.0],
        ..*terrain.params()
    };
    terrain.set_params(&gpu.device, &gpu.queue, params)?;
    headless::bake_blocking(gpu, terrain, None)?;
    let baked = headless::read_baked(&gpu.device, &gpu.queue, terrain)?;
    Ok(Heights {
        size: params.size as usize,
        values: baked.heights,
    })
}

fn relief_row(gpu: &Gpu, terrain: &mut Terrain, d: f64, stride: u32) -> Result<ScrollRow> {
    let tile = *terrain.params();
    let step = 1.0 / f64::from(tile.size);
    let refused = |e: Error| match e {
        // Only relief's refusal of the offset is a finding; anything else is an error.
        Error::InvalidParam { name, allowed, .. } if name == "offset" => Ok(ScrollRow {
            scroller: Scroller::Relief,
            distance: d,
            refused: Some(allowed),
            moved: 0.0,
            repeated: 0.0,
            held: 0.0,
            twin_error: None,
        }),
        e => Err(e),
    };
    let before = match relief_bake(gpu, terrain, d) {
        Ok(h) => h,
        Err(e) => return refused(e),
    };
    let after = match relief_bake(gpu, terrain, d + step) {
        Ok(h) => h,
        Err(e) => return refused(e),
    };
    let judged = judge(&before, &after, Scroller::Relief.tolerance());
    let fbm = Fbm::from_params(&TerrainParams {
        offset: [d, 0.0],
        ..tile
    });
    let texels: Vec<(u32, u32)> = (0..tile.size)
        .step_by(stride as usize)
        .flat_map(|y| (0..tile.size).step_by(stride as usize).map(move |x| (x, y)))
        .collect();
    let twin_error = super::parallel_map(&texels, |&(x, y)| {
        let twin = fbm.texel(Channel::Height, tile.size, x, y);
        (f64::from(before.at(x as usize, y as usize)) - twin).abs()
    })
    .into_iter()
    .fold(0.0, f64::max);
    Ok(ScrollRow {
        scroller: Scroller::Relief,
        distance: d,
        refused: None,
        moved: judged.moved,
        repeated: judged.repeated,
        held: judged.held,
        twin_error: Some(twin_error),
    })
}

/// The blog's bake scrolled by `progress` (rounded to f32, as the blog's uniform holds it).
fn blog_bake(gpu: &Gpu, blog: &Blog, params: &TerrainParams, progress: f64) -> Result<Heights> {
    let view = relief::camera::OrbitCamera::default().view(1.0);
    blog.prepare(
        &gpu.queue,
        params,
        &Shading::default(),
        &view,
        progress as f32,
    );
    let mut encoder = gpu
        .device
        .create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("relief:stability:blog-bake"),
        });
    blog.encode_bake(&mut encoder, None);
    gpu.queue.submit([encoder.finish()]);
    let Some(maps) = blog.maps.as_ref() else {
        return Err(Error::Readback("the blog's pipeline has no maps".into()));
    };
    let rgba = headless::read_texture(&gpu.device, &gpu.queue, &maps[0])?;
    Ok(Heights {
        size: BLOG_SIZE as usize,
        values: rgba.chunks(4).map(|t| f32::from(t[0]) / 255.0).collect(),
    })
}

fn blog_row(gpu: &Gpu, blog: &Blog, params: &TerrainParams, d: f64) -> Result<ScrollRow> {
    let before = blog_bake(gpu, blog, params, d)?;
    let after = blog_bake(gpu, blog, params, d + 1.0 / f64::from(BLOG_SIZE))?;
    let judged = judge(&before, &after, Scroller::Blog.tolerance());
    Ok(ScrollRow {
        scroller: Scroller::Blog,
        distance: d,
        refused: None,
        moved: judged.moved,
        repeated: judged.repeated,
        held: judged.held,
        twin_error: None,
    })
}

/// The CSV: a header and a row per pipeline and distance, with the device and backend.
pub fn scroll_csv(rows: &[ScrollRow], device: &str, backend: &str) -> String {
    let mut out = String::from(
        "method,distance_tiles,refused,held,moved,repeated,twin_error,device,backend\n",
    );
    for r in rows {
        let _ = writeln!(
            out,
            "{},{:e},{},{:.6},{:.6},{:.6},{},{device},{backend}",
            r.scroller.label(),
            r.distance,
            r.refused
                .as_deref()
                .map_or(String::new(), |s| format!("\"{s}\"")),
            r.held,
            r.moved,
            r.repeated,
            r.twin_error.map_or(String::new(), |e| format!("{e:.2e}")),
        );
    }
    out
}

/// The table: a row per distance, both pipelines side by side.
pub fn scroll_table(rows: &[ScrollRow]) -> String {
    let mut out = String::from(
        "tiles        relief: held   moved  repeated  twin error    blog: held   moved  repeated\n",
    );
    for pair in rows.chunks(2) {
        let _ = write!(out, "{:<12.0e}", pair[0].distance);
        for r in pair {
            match (&r.refused, r.twin_error) {
                (Some(_), _) => {
                    let _ = write!(out, " {:>43}", "refused");
                }
                (None, Some(e)) => {
                    let _ = write!(
                        out,
                        " {:>12.4} {:>7.4} {:>9.4} {:>11.1e}",
                        r.held, r.moved, r.repeated, e
                    );
                }
                (None, None) => {
                    let _ = write!(
                        out,
                        "    {:>10.4} {:>7.4} {:>9.4}",
                        r.held, r.moved, r.repeated
                    );
                }
            }
        }
        out.push('\n');
    }
    if let Some(why) = rows.iter().find_map(|r| r.refused.as_deref()) {
        let _ = writeln!(out, "refused: relief's offset must be {why}");
    }
    out.push_str(
        "held: texels a one-texel scroll moved by one texel that lie in a column of their own; \
         moved: all texels it moved by one texel; repeated: texel columns equal to the one \
         before (stripes)\n",
    );
    out
}

/// The chart: per distance (log), each pipeline's held and repeated fractions, relief's
/// refusals marked.
pub fn scroll_chart(rows: &[ScrollRow], (title, stem): (&str, &std::path::Path)) -> Result<()> {
    crate::chart::write_chart(stem, |b| draw(b, rows, title), |b| draw(b, rows, title))
}

/// A fraction the chart draws a line of for each pipeline: its legend, its value, and whether
/// its line is the bold one.
type Fraction = (&'static str, fn(&ScrollRow) -> f64, bool);

fn draw<DB: plotters::prelude::DrawingBackend>(
    backend: DB,
    rows: &[ScrollRow],
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
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 20))
        .margin(16)
        .x_label_area_size(48)
        .y_label_area_size(64)
        .build_cartesian_2d((d0..d1).log_scale(), 0.0..1.3)
        .map_err(|e| e.to_string())?;
    chart
        .configure_mesh()
        .x_label_formatter(&|v| format!("{v:.0e}"))
        .x_desc("scroll from the origin, tiles (log)")
        .y_desc("fraction")
        .label_style(("sans-serif", 15))
        .axis_desc_style(("sans-serif", 15))
        .draw()
        .map_err(|e| e.to_string())?;
    let fractions: [Fraction; 2] = [
        (
            "texels a one-texel scroll moved, in columns of their own",
            |r| r.held,
            true,
        ),
        ("columns repeating the one before", |r| r.repeated, false),
    ];
    for (i, scroller) in Scroller::ALL.into_iter().enumerate() {
        let color = if scroller == Scroller::Relief {
            BLACK.to_rgba()
        } else {
            Palette99::pick(i).to_rgba()
        };
        let mine: Vec<&ScrollRow> = rows
            .iter()
            .filter(|r| r.scroller == scroller && r.refused.is_none())
            .collect();
        for (what, value, solid) in fractions {
            let line: Vec<(f64, f64)> = mine.iter().map(|r| (r.distance, value(r))).collect();
            let style = if solid {
                color.stroke_width(3)
            } else {
                color.stroke_width(1)
            };
            chart
                .draw_series(LineSeries::new(line.clone(), style))
                .map_err(|e| e.to_string())?
                .label(format!("{}: {what}", scroller.label()))
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], style));
            chart
                .draw_series(line.iter().map(|&p| {
                    if solid {
                        Circle::new(p, 4, color.filled())
                    } else {
                        Circle::new(p, 4, color.stroke_width(1))
                    }
                }))
                .map_err(|e| e.to_string())?;
        }
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
                    .map(|&d| Cross::new((d, 0.05), 8, red.stroke_width(3))),
            )
            .map_err(|e| e.to_string())?
            .label("relief refuses the offset (past 2^40 tiles)")
            .legend(move |(x, y)| Cross::new((x + 10, y), 6, red.stroke_width(3)));
    }
    crate::chart::legend(&mut chart, SeriesLabelPosition::UpperRight)?;
    root.present().map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn field(n: usize, f: impl Fn(usize, usize) -> f32) -> Heights {
        Heights {
            size: n,
            values: (0..n * n).map(|i| f(i % n, i / n)).collect(),
        }
    }

    #[test]
    fn a_rigid_scroll_holds_and_stripes_or_a_frozen_scroll_do_not() {
        let terrain = |x: usize, y: usize| ((x * 7 + y * 3) % 11) as f32 / 11.0;
        let before = field(8, terrain);
        let after = field(8, |x, y| terrain(x + 1, y));
        let rigid = judge(&before, &after, 1e-6);
        assert_eq!((rigid.moved, rigid.repeated, rigid.held), (1.0, 0.0, 1.0));
        // The scroll did nothing: only texels where the terrain repeats itself "moved".
        let frozen = judge(&before, &before, 1e-6);
        assert!(frozen.moved < 0.2 && frozen.held < 0.2, "{frozen:?}");
        // Stripes: columns in pairs.
        let striped = |x: usize, y: usize| terrain(x / 2 * 2, y);
        let pairs = judge(
            &field(8, striped),
            &field(8, |x, y| striped(x + 2, y)),
            1e-6,
        );
        assert!((pairs.repeated - 4.0 / 7.0).abs() < 1e-9, "{pairs:?}");
        // Constant along the scroll: every texel "moves", none holds.
        let flat = field(8, |_, y| terrain(0, y));
        let flat = judge(&flat, &flat, 1e-6);
        assert_eq!((flat.moved, flat.repeated, flat.held), (1.0, 1.0, 0.0));
    }
}
