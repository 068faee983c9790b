//! Where methods fail: sweeps along the axes on which terrain methods are known to break down,
//! each measured against the truth (`relief stability`).
//!
//! The first axis is grazing rays against step size. The seed's march steps `t += c * h`, where
//! `h` is the ray's height above the terrain below it: not a distance bound, so a ray skimming a
//! slope can step through a ridge. A camera low over the tile looks down at `elevation` degrees;
//! every sampled pixel's ray is cast on the GPU by each method and on the CPU by the f64 twin's
//! conservative cast ([`crate::raycast::Surface::intersect`], the truth). A pixel has
//! *tunnelled* where the truth hits and the method sees sky or a hit more than 1% farther,
//! while the truth's ray one pixel higher still hits in front of it: the method lost terrain
//! at least a pixel tall on screen (a miss within a pixel is counted apart, *grazed*).
//! Rays that ran out of steps are counted apart (*capped*), never as sky. The seed's
//! relaxation variant (steps multiplied by `max(relax t, 1)`, growing with distance) is a
//! second variant of its march ([`TILE_RELAX`]); `raymarch-fragment` runs the march in a
//! fragment shader; the mesh is judged by the distance its depth buffer gives each pixel.
//! `blog` is not on this axis: its sine-hash terrain has no f64 twin to cast the truth on.
//!
//! The second is shadow rays at a low sun ([`shadow`]), on the endless world: each method's
//! horizon towards the sun against an f64 ray over the twin's continuous surface.
//!
//! The third is distance from the origin ([`distance`]), on the endless world: the bake against
//! the twin, the mesh's screen error, jitter under a tiny step, and holes against the reference.
//!
//! The fourth is motion ([`motion`]), on the endless world: popping and baking falling behind
//! under a moving eye, against speed and the LOD knob.
//!
//! The fifth is detail against resolution ([`detail`]), on the CPU twin: octaves against
//! texel size, the normal error and the variance above the texture's Nyquist frequency.
//!
//! The sixth is storage precision ([`storage`]), on the CPU twin: heights stored in 8 bits
//! (the seed blog's), 16 and 32, and normals stored as the blog stores them, against f64.
//!
//! The seventh is the tile scrolled far from its origin ([`scroll`]): relief's tile and the
//! seed blog's (`blog`), each judged on whether a one-texel scroll moves its bake by one texel
//! and whether its texel columns stay apart; relief's against the twin too.
//!
//! The eighth is the temporal service under a moving eye ([`temporal`]), on the endless world:
//! flicker and ghosting with a history and without, against the reference of each frame.
//!
//! The ninth is grass under a moving eye ([`grass`]), on the endless world: the frame's flicker
//! and pops against the grass reference's own.
//!
//! The tenth is the props' march ([`props`]), on their f64 twin: stepping past a surface
//! against roughness and the smooth union's radius, the step budget against distance, and pops
//! at the screen-size cut-off.
//!
//! The eleventh is the clouds' image under a moving eye ([`clouds`]), on the endless world:
//! each frame against a full march of that frame, and a still frame's banding against the
//! march's steps.
//!
//! Each is an [`Axis`], by the name `relief stability --axis` takes.

pub mod clouds;
pub mod detail;
pub mod distance;
pub mod grass;
pub mod motion;
mod precision;
pub mod props;
pub mod scroll;
pub mod shadow;
pub mod temporal;
pub mod world_grazing;

use crate::raycast::{pixel_ray, Surface};
use relief::camera::OrbitCamera;
use relief::error::Result;
use relief::gpu::headless::{self, Gpu};
use relief::gpu::raymarch::RayMarcher;
use relief::method::Method;
use relief::method::{RayMethod, RayPath, SeedMarch};
use relief::params::{Shading, TerrainParams};
use std::fmt::Write as _;

pub use self::precision::*;

/// Every axis's options at one effort: what `relief stability` runs (`--quick` or not).
///
/// The world grazing axis takes its height scale from `world` when the value is made: make a
/// value for another world with [`Sweeps::quick`] or [`Sweeps::full`], not by changing `world`.
#[derive(Clone, Debug)]
pub struct Sweeps {
    /// The endless world the world axes (world grazing, shadow, distance, motion) sweep over.
    pub world: relief::WorldParams,
    /// The grazing axis, over the scene's tile.
    pub grazing: Options,
    /// The grazing axis over the endless world.
    pub world_grazing: Options,
    /// Shadow rays at a low sun.
    pub shadow: shadow::ShadowOptions,
    /// Distance from the origin.
    pub distance: distance::DistanceOptions,
    /// The tile scrolled far.
    pub scroll: scroll::ScrollOptions,
    /// A moving eye.
    pub motion: motion::MotionOptions,
    /// The temporal service under a moving eye.
    pub temporal: temporal::TemporalOptions,
    /// Detail against resolution.
    pub detail: detail::DetailOptions,
    /// Grass under a moving eye.
    pub grass: grass::GrassOptions,
    /// The clouds' image under a moving eye.
    pub clouds: clouds::CloudOptions,
    /// The side in texels of the storage-precision axis.
    pub storage_side: u32,
}

impl Sweeps {
    /// The whole sweeps (`relief stability`), over the endless world `world`.
    pub fn full(world: &relief::WorldParams) -> Self {
        Self {
            world: *world,
            grazing: Options::full(),
            world_grazing: world_grazing::world_options(world, false),
            shadow: shadow::ShadowOptions::full(),
            distance: distance::DistanceOptions::full(),
            scroll: scroll::ScrollOptions::full(),
            motion: motion::MotionOptions::full(),
            temporal: temporal::TemporalOptions::full(),
            detail: detail::DetailOptions::full(),
            grass: grass::GrassOptions::full(),
            clouds: clouds::CloudOptions::full(),
            storage_side: STORAGE_SIZE,
        }
    }

    /// Fewer values on each axis at smaller sizes (`relief stability --quick`): minutes on a
    /// software GPU.
    pub fn quick(world: &relief::WorldParams) -> Self {
        Self {
            world: *world,
            grazing: Options::quick(),
            world_grazing: world_grazing::world_options(world, true),
            shadow: shadow::ShadowOptions::quick(),
            distance: distance::DistanceOptions::quick(),
            scroll: scroll::ScrollOptions::quick(),
            motion: motion::MotionOptions::quick(),
            temporal: temporal::TemporalOptions::quick(),
            detail: detail::DetailOptions::quick(),
            grass: grass::GrassOptions::quick(),
            clouds: clouds::CloudOptions::quick(),
            storage_side: 256,
        }
    }
}

/// An axis of `relief stability`: what it sweeps, and the files it writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Axis {
    /// Grazing rays over the scene's tile ([`grazing`]): `stability.csv`, `grazing-hs*`.
    Grazing,
    /// Grazing rays over the default endless world ([`world_grazing`]).
    WorldGrazing,
    /// Shadow rays at a low sun ([`shadow`]).
    Shadow,
    /// The endless world's eye far from the origin ([`distance`]).
    Distance,
    /// The tile scrolled far from its origin, relief's and the blog's ([`scroll`]).
    Scroll,
    /// A moving eye ([`motion`]).
    Motion,
    /// Detail against resolution ([`detail`]).
    Detail,
    /// Storage precision ([`storage`]).
    Storage,
    /// The temporal service under a moving eye ([`temporal`]).
    Temporal,
    /// Grass under a moving eye, against its reference ([`grass`]).
    Grass,
    /// Marching the props' fields, on their f64 twin ([`props`]).
    Props,
    /// The clouds' image under a moving eye, against a full march ([`clouds`]).
    Clouds,
}

impl Axis {
    /// Every axis, in the order `relief stability` runs them.
    pub const ALL: [Axis; 12] = [
        Axis::Grazing,
        Axis::WorldGrazing,
        Axis::Shadow,
        Axis::Distance,
        Axis::Scroll,
        Axis::Motion,
        Axis::Detail,
        Axis::Storage,
        Axis::Temporal,
        Axis::Grass,
        Axis::Props,
        Axis::Clouds,
    ];

    /// Its name on the command line (`--axis`).
    pub fn name(self) -> &'static str {
        match self {
            Axis::Grazing => "grazing",
            Axis::WorldGrazing => "world-grazing",
            Axis::Shadow => "shadow",
            Axis::Distance => "distance",
            Axis::Scroll => "scroll",
            Axis::Motion => "motion",
            Axis::Detail => "detail",
            Axis::Storage => "storage",
            Axis::Temporal => "temporal",
            Axis::Grass => "grass",
            Axis::Props => "props",
            Axis::Clouds => "clouds",
        }
    }

    /// The axis named `name`, if there is one.
    pub fn parse(name: &str) -> Option<Axis> {
        Axis::ALL.into_iter().find(|a| a.name() == name)
    }

    /// Every axis's name, comma-separated (the allowed values in an error).
    pub fn names() -> String {
        Axis::ALL.map(Axis::name).join(", ")
    }
}

impl std::fmt::Display for Axis {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// A method on the grazing axis: relief's mesh or its conservative cast, or the seed's march at
/// a step factor, plain or in its relaxation variant, in compute or in a fragment shader.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Marcher {
    /// `mesh`, `reference`, `raymarch` or `raymarch-fragment`.
    pub method: Method,
    /// The seed march's `c` (the reference has none).
    pub step_factor: Option<f32>,
    /// The relaxation's growth of the step per unit of distance (0: the plain march).
    pub relax: f32,
}

/// The seed's relaxation variant on the tile: the seed multiplies its steps by
/// `max(0.02 t, 1)` over a 400-unit view, so they start growing an eighth of the way out; the
/// tile (2 wide) is crossed within about 4 units, so here they grow from half a unit.
pub const TILE_RELAX: f32 = 2.0;

/// The seed's step factor in its relaxation variant.
pub const RELAX_STEP_FACTOR: f32 = 0.7;

/// The step factor the seed's march runs at in the fragment shader on the grazing axis (one
/// that tunnels on steep terrain in compute, so the two paths can be compared).
pub const FRAGMENT_STEP_FACTOR: f32 = 0.8;

impl Marcher {
    /// Its name in the CSV and on the chart.
    pub fn label(&self) -> String {
        match self.step_factor {
            Some(c) if self.relax > 0.0 => format!("{} relax c={c}", self.method),
            Some(c) => format!("{} c={c}", self.method),
            None => self.method.to_string(),
        }
    }

    fn ray_method(&self, params: &TerrainParams) -> RayMethod {
        match self.step_factor {
            Some(step_factor) => RayMethod::SeedMarch(SeedMarch {
                step_factor,
                // The march sums every octave: the surface it steps against is the truth's.
                march_octaves: params.octaves,
                normal_octaves: params.octaves,
                relax: self.relax,
                ..SeedMarch::default()
            }),
            None => RayMethod::Reference,
        }
    }
}

/// What the grazing sweep measures with.
#[derive(Clone, Debug, PartialEq)]
pub struct Options {
    /// Image size of each view.
    pub size: (u32, u32),
    /// Every `stride`-th pixel each way is compared with the CPU's ray.
    pub stride: u32,
    /// Degrees the camera looks down, one view each.
    pub elevations: Vec<f64>,
    /// Height scales the sweep runs at (the scene's and steeper), one pass each.
    pub height_scales: Vec<f32>,
    /// The methods.
    pub marchers: Vec<Marcher>,
}

impl Options {
    /// The full sweep: 7 elevations from 0.5 to 30 degrees, the seed march at 4 step factors
    /// and in its relaxation variant, and the reference, at 480x270 with every 4th pixel
    /// compared.
    pub fn full() -> Self {
        Self {
            size: (480, 270),
            stride: 4,
            elevations: vec![0.5, 1.0, 2.0, 5.0, 10.0, 20.0, 30.0],
            height_scales: vec![0.5, 2.0],
            marchers: Self::marchers(&[0.3, 0.5, 0.8, 1.0]),
        }
    }

    /// `--quick`: small enough for a software GPU in the tests.
    pub fn quick() -> Self {
        Self {
            size: (96, 54),
            stride: 2,
            elevations: vec![1.0, 5.0, 20.0],
            height_scales: vec![0.5, 2.0],
            marchers: Self::marchers(&[0.3, 0.8]),
        }
    }

    fn marchers(steps: &[f32]) -> Vec<Marcher> {
        let seed = steps.iter().map(|&c| Marcher {
            method: Method::Raymarch,
            step_factor: Some(c),
            relax: 0.0,
        });
        let relaxed = Marcher {
            method: Method::Raymarch,
            step_factor: Some(RELAX_STEP_FACTOR),
            relax: TILE_RELAX,
        };
        let fragment = Marcher {
            method: Method::RaymarchFragment,
            step_factor: Some(FRAGMENT_STEP_FACTOR),
            relax: 0.0,
        };
        let [reference, mesh] = [Method::Reference, Method::Mesh].map(|method| Marcher {
            method,
            step_factor: None,
            relax: 0.0,
        });
        seed.chain([relaxed, fragment, mesh, reference]).collect()
    }
}

/// One method at one elevation.
#[derive(Clone, Debug, PartialEq)]
pub struct GrazingRow {
    /// The method.
    pub marcher: Marcher,
    /// Degrees the camera looks down.
    pub elevation_deg: f64,
    /// The scene's height scale (world height of normalised height 1; the tile is 2 wide).
    pub height_scale: f32,
    /// Pixels compared.
    pub sampled: usize,
    /// Of those, where the truth hits terrain.
    pub truth_hits: usize,
    /// Truth hits the method sees as sky or more than 1% farther, where the truth's ray one
    /// pixel higher still hits nearer than the method: it stepped through terrain a pixel or
    /// more tall on screen.
    pub tunnelled: usize,
    /// Truth hits the method sees as sky or farther, but within a pixel: the ray one pixel
    /// higher passes over what the method missed (a grazed silhouette, or a ridge the mesh
    /// draws lower by less than a pixel).
    pub grazed: usize,
    /// Pixels whose ray ran out of steps (a truth hit that ran out is not a tunnel).
    pub capped: usize,
    /// Truth hits the method stops short of by more than 1% (the seed's hit test `|h| < k t`
    /// accepts a ray skimming the slope).
    pub early: usize,
    /// Largest relative depth error among the hits that did not tunnel.
    pub depth_error_max: f64,
}

impl GrazingRow {
    /// Tunnelled pixels as a fraction of the truth's hits.
    pub fn tunnelled_fraction(&self) -> f64 {
        self.tunnelled as f64 / self.truth_hits.max(1) as f64
    }
}

/// The grazing camera's vertical field of view, degrees.
pub const GRAZING_FOV_DEG: f32 = 45.0;

/// Relative depth beyond which a later hit counts as a tunnel.
pub const TUNNEL_TOLERANCE: f64 = 0.01;

/// The camera of the grazing axis: low over the tile's centre, looking down `elevation_deg`
/// at the surface there from 1.2 world units away (the tile is 2 wide).
pub fn grazing_camera(surface: &Surface, elevation_deg: f64) -> OrbitCamera {
    OrbitCamera {
        target: glam::Vec3::new(0.0, surface.height(0.0, 0.0) as f32, 0.0),
        yaw: 0.7,
        pitch: (elevation_deg as f32).to_radians(),
        distance: 1.2,
        fov_y: GRAZING_FOV_DEG.to_radians(),
    }
}

/// Sweeps the grazing axis for `params` at each of the options' height scales;
/// `progress(done, total)` after each view.
pub fn grazing(
    gpu: &Gpu,
    params: &TerrainParams,
    options: &Options,
    mut progress: impl FnMut(usize, usize),
) -> Result<Vec<GrazingRow>> {
    let (w, h) = options.size;
    let caster = RayMarcher::new(&gpu.device, w, h)?;
    let mut rows = Vec::new();
    let views: Vec<(f32, f64)> = options
        .height_scales
        .iter()
        .flat_map(|&hs| options.elevations.iter().map(move |&e| (hs, e)))
        .collect();
    for (i, &(height_scale, elevation)) in views.iter().enumerate() {
        let params = &TerrainParams {
            height_scale,
            ..*params
        };
        params.validate()?;
        let surface = Surface::new(params);
        let view = grazing_camera(&surface, elevation).view(w as f32 / h as f32);
        // The truth at the sampled pixels.
        let stride = options.stride.max(1);
        let pixels: Vec<(u32, u32)> = (0..h)
            .step_by(stride as usize)
            .flat_map(|y| (0..w).step_by(stride as usize).map(move |x| (x, y)))
            .collect();
        // The truth at the sampled pixels, and where the ray raised by one pixel at the hit's
        // distance hits (what tells a tunnel from a miss within a pixel).
        let pixel_angle =
            2.0 * (f64::from(GRAZING_FOV_DEG).to_radians() * 0.5).tan() / f64::from(h);
        let truth: Vec<Option<(f64, Option<f64>)>> = pixels
            .iter()
            .map(|&(x, y)| {
                let (ro, rd) = pixel_ray(&view, w, h, x, y);
                let t = surface.intersect(ro, rd)?;
                let raised = ro + glam::DVec3::Y * (pixel_angle * t);
                Some((t, surface.intersect(raised, rd)))
            })
            .collect();
        for m in &options.marchers {
            let distance = if m.method == Method::Mesh {
                // The mesh as drawn (its grid over the baked texture), single-sampled: the
                // distance of what each pixel shows, from the depth buffer.
                let target = headless::Offscreen::new(&gpu.device, w, h, 1)?;
                let mut terrain = relief::gpu::Terrain::new(
                    &gpu.device,
                    &gpu.queue,
                    headless::Offscreen::targets(1),
                    *params,
                )?;
                target.render(gpu, &mut terrain, &view, None)?;
                crate::bench::distances(&target.read_depth(gpu)?, &view, (w, h))
            } else {
                caster.prepare(
                    &gpu.queue,
                    params,
                    &Shading::default(),
                    &view,
                    m.ray_method(params),
                );
                let mut encoder = gpu.device.create_command_encoder(&Default::default());
                let path = m.method.ray_path().unwrap_or(RayPath::Compute);
                caster.encode(&mut encoder, path, None);
                gpu.queue.submit([encoder.finish()]);
                let bytes = headless::read_texture(&gpu.device, &gpu.queue, &caster.distance)?;
                bytemuck::pod_collect_to_vec(&bytes)
            };
            let d: Vec<f64> = pixels
                .iter()
                .map(|&(x, y)| f64::from(distance[(y * w + x) as usize]))
                .collect();
            let row = judge(*m, (elevation, height_scale), &truth, &d);
            rows.push(row);
        }
        progress(i + 1, views.len());
    }
    Ok(rows)
}

/// Judges one method's distances `d` at the sampled pixels (-1 sky, -2 out of steps) against
/// the truth there (`(t, where the ray one pixel higher hits)`, `None` where it misses).
pub(crate) fn judge(
    marcher: Marcher,
    (elevation_deg, height_scale): (f64, f32),
    truth: &[Option<(f64, Option<f64>)>],
    distances: &[f64],
) -> GrazingRow {
    let mut row = GrazingRow {
        marcher,
        elevation_deg,
        height_scale,
        sampled: truth.len(),
        truth_hits: 0,
        tunnelled: 0,
        grazed: 0,
        capped: 0,
        early: 0,
        depth_error_max: 0.0,
    };
    for (t, &d) in truth.iter().zip(distances) {
        let Some((t, up)) = *t else {
            row.capped += usize::from(d == -2.0);
            continue;
        };
        row.truth_hits += 1;
        if d == -2.0 {
            row.capped += 1;
        } else if d < 0.0 || d > t * (1.0 + TUNNEL_TOLERANCE) {
            // Behind: a tunnel where even a pixel higher the truth hits in front.
            let solid = up.is_some_and(|u| d < 0.0 || u < d * (1.0 - TUNNEL_TOLERANCE));
            row.tunnelled += usize::from(solid);
            row.grazed += usize::from(!solid);
        } else {
            row.early += usize::from(d < t * (1.0 - TUNNEL_TOLERANCE));
            row.depth_error_max = row.depth_error_max.max((d - t).abs() / t);
        }
    }
    row
}

/// The coordinates of a stability chart: a log x axis with plain-number key ticks, a linear y
/// axis.
pub(crate) type LogX = plotters::coord::cartesian::Cartesian2d<
    plotters::coord::combinators::WithKeyPoints<plotters::coord::combinators::LogCoord<f64>>,
    plotters::coord::types::RangedCoordf64,
>;

/// A chart on `root` with `title`, x from `x0` to `x1` on a log scale and y from 0 to `top`,
/// its mesh drawn with the axis descriptions: what every log-x stability chart starts from.
pub(crate) fn log_x_chart<'a, DB>(
    root: &'a plotters::drawing::DrawingArea<DB, plotters::coord::Shift>,
    title: &str,
    (x0, x1, top): (f64, f64, f64),
    (x_desc, y_desc): (&str, &str),
) -> std::result::Result<plotters::chart::ChartContext<'a, DB, LogX>, String>
where
    DB: plotters::prelude::DrawingBackend + 'a,
    DB::ErrorType: 'static,
{
    use plotters::prelude::*;
    let mut chart = ChartBuilder::on(root)
        .caption(title, ("sans-serif", 20))
        .margin(16)
        .x_label_area_size(48)
        .y_label_area_size(64)
        .build_cartesian_2d(
            (x0..x1)
                .log_scale()
                .with_key_points(crate::chart::log_ticks(x0, x1, 5)),
            0.0..top,
        )
        .map_err(|e| e.to_string())?;
    chart
        .configure_mesh()
        .x_label_formatter(&|v| crate::chart::tick_label(*v))
        .x_desc(x_desc)
        .y_desc(y_desc)
        .label_style(("sans-serif", 15))
        .axis_desc_style(("sans-serif", 15))
        .draw()
        .map_err(|e| e.to_string())?;
    Ok(chart)
}

/// `f` of each item, the items split among the machine's cores (the f64 truths' work), in
/// order.
pub(crate) fn parallel_map<T: Sync, R: Send>(items: &[T], f: impl Fn(&T) -> R + Sync) -> Vec<R> {
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let chunk = items.len().div_ceil(threads).max(1);
    let f = &f;
    std::thread::scope(|s| {
        let handles: Vec<_> = items
            .chunks(chunk)
            .map(|c| s.spawn(move || c.iter().map(f).collect::<Vec<_>>()))
            .collect();
        handles
            .into_iter()
            .flat_map(|h| h.join().unwrap_or_default())
            .collect()
    })
}

/// The CSV: a header and a row per method and elevation, with the device and backend.
pub fn csv(rows: &[GrazingRow], device: &str, backend: &str, options: &Options) -> String {
    let mut out = String::from(
        "device,backend,axis,method,step_factor,relax,height_scale,elevation_deg,width,height,sampled,truth_hits,tunnelled,tunnelled_fraction,grazed,capped,early,depth_error_max\n",
    );
    for r in rows {
        let _ = writeln!(
            out,
            "\"{device}\",\"{backend}\",grazing,{},{},{},{},{},{},{},{},{},{},{:.6},{},{},{},{:.6}",
            r.marcher.method,
            r.marcher
                .step_factor
                .map_or(String::new(), |c| c.to_string()),
            r.marcher.relax,
            r.height_scale,
            r.elevation_deg,
            options.size.0,
            options.size.1,
            r.sampled,
            r.truth_hits,
            r.tunnelled,
            r.tunnelled_fraction(),
            r.grazed,
            r.capped,
            r.early,
            r.depth_error_max,
        );
    }
    out
}

/// A table for the terminal: tunnelled fraction per method (rows) and elevation (columns),
/// each column as wide as its widest cell.
pub fn table(rows: &[GrazingRow], options: &Options) -> String {
    let mut lines: Vec<Vec<String>> = Vec::new();
    for &hs in &options.height_scales {
        let mut head = vec![format!("height scale {hs}")];
        head.extend(options.elevations.iter().map(|e| format!("{e}°")));
        lines.push(head);
        for m in &options.marchers {
            let mut line = vec![m.label()];
            for e in &options.elevations {
                line.push(
                    rows.iter()
                        .find(|r| r.marcher == *m && r.elevation_deg == *e && r.height_scale == hs)
                        .map_or("-".to_owned(), |r| {
                            format!("{:.4} ({})", r.tunnelled_fraction(), r.capped)
                        }),
                );
            }
            lines.push(line);
        }
    }
    let columns = lines.iter().map(Vec::len).max().unwrap_or(0);
    let widths: Vec<usize> = (0..columns)
        .map(|c| {
            lines
                .iter()
                .filter_map(|l| l.get(c))
                .map(|t| t.chars().count())
                .max()
                .unwrap_or(0)
        })
        .collect();
    let mut out = String::new();
    for line in &lines {
        for (c, cell) in line.iter().enumerate() {
            let _ = if c == 0 {
                write!(out, "{cell:<w$}", w = widths[c])
            } else {
                write!(out, "  {cell:>w$}", w = widths[c])
            };
        }
        out.push('\n');
    }
    out.push_str("cells: tunnelled fraction of the truth's hits (rays that ran out of steps)\n");
    out
}

/// The charts, one per height scale (`stem-hs0p5` for 0.5): tunnelled fraction against elevation
/// (log), a line per method.
pub fn chart(
    rows: &[GrazingRow],
    options: &Options,
    title: &str,
    stem: &std::path::Path,
) -> Result<()> {
    for &hs in &options.height_scales {
        let mine: Vec<GrazingRow> = rows
            .iter()
            .filter(|r| r.height_scale == hs)
            .cloned()
            .collect();
        let title = format!("{title}, height scale {hs}");
        // No dot in the name: the extension goes after it (0.5 is written 0p5).
        let name = stem
            .file_name()
            .and_then(|n| n.to_str())
            .unwrap_or("grazing");
        let scale = hs.to_string().replace('.', "p");
        let stem = stem.with_file_name(format!("{name}-hs{scale}"));
        crate::chart::write_chart(
            &stem,
            |b| draw(b, &mine, options, &title),
            |b| draw(b, &mine, options, &title),
        )?;
    }
    Ok(())
}

fn draw<DB: plotters::prelude::DrawingBackend>(
    backend: DB,
    rows: &[GrazingRow],
    options: &Options,
    title: &str,
) -> std::result::Result<(), String>
where
    DB::ErrorType: 'static,
{
    use plotters::prelude::*;
    let root = backend.into_drawing_area();
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let (e0, e1) = log_span(options.elevations.iter().copied(), 1.3);
    let top = rows
        .iter()
        .map(GrazingRow::tunnelled_fraction)
        .fold(0.0, f64::max)
        .max(0.01)
        * 1.15;
    let mut chart = log_x_chart(
        &root,
        title,
        (e0, e1, top),
        (
            "camera elevation above the horizon, degrees (log)",
            "tunnelled pixels (fraction of the truth's hits)",
        ),
    )?;
    for (i, m) in options.marchers.iter().enumerate() {
        // relief's reference in black, its mesh in grey; the seed march's variants in the
        // palette's colours.
        let color = match m.method {
            Method::Reference => BLACK.to_rgba(),
            Method::Mesh => RGBColor(128, 128, 128).to_rgba(),
            _ => Palette99::pick(i).to_rgba(),
        };
        let line: Vec<(f64, f64)> = rows
            .iter()
            .filter(|r| r.marcher == *m)
            .map(|r| (r.elevation_deg, r.tunnelled_fraction()))
            .collect();
        chart
            .draw_series(LineSeries::new(line.clone(), color.stroke_width(2)))
            .map_err(|e| e.to_string())?
            .label(m.label())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color));
        chart
            .draw_series(line.iter().map(|&p| Circle::new(p, 4, color.filled())))
            .map_err(|e| e.to_string())?;
    }
    crate::chart::legend(&mut chart, SeriesLabelPosition::UpperLeft)?;
    root.present().map_err(|e| e.to_string())
}

/// A chart's span on a log axis: the smallest of `values` divided by `pad` to the largest
/// times `pad` (every chart of the sweep leaves that much room beyond its outermost rows).
pub(crate) fn log_span(values: impl Iterator<Item = f64> + Clone, pad: f64) -> (f64, f64) {
    let lo = values.clone().fold(f64::MAX, f64::min);
    let hi = values.fold(f64::MIN, f64::max);
    (lo / pad, hi * pad)
}
