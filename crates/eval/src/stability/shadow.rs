//! The shadow axis of `relief stability`: rays towards a low sun. The seed's shadow march steps
//! `t += clamp(h, lo, hi)` (`h` the ray's height above the terrain below it), so at a low sun
//! a step can pass over a ridge thinner than the step, and 64 steps reach a few kilometres at
//! most. At points of the endless world around the eye, each method's horizon towards the sun
//! is compared with the truth: an f64 ray over every octave of the CPU twin's continuous
//! surface, its steps bounded by the surface's slope ([`relief::light::lit_by_ray`]), as far as
//! the region the mesh draws. The points are texels of the clipmap's levels, each where its
//! level is drawn: dense near the eye and sparser with distance, as pixels fall on the ground.
//!
//! - `mesh`: relief's light bake (the horizon per level texel the mesh shades with,
//!   `wgsl/world_light.wgsl`), read at each point from the level that draws it;
//! - `reference`: relief's ray casters' horizon (conservative steps, every octave);
//! - `raymarch`: the seed's shadow march, every octave (so what it misses, it stepped over).
//!
//! A point is *judged* where the truth is the same for the top and the bottom of the sun's
//! disc (outside the penumbra). It has *tunnelled* where the truth is in shadow and the method
//! sees more than half of the disc, and is *falsely shadowed* where the truth is lit and the
//! method sees less than half. Relief's marches take their first sample [`near`] metres from
//! the point (a thousandth of the peak height: 2.4 m on the default world), so the truth judges
//! only occluders beyond it; a point shadowed by its own surface nearer than that (a slope
//! facing away, which the shading's N·L darkens, or a concave rise within a texel or two) is
//! counted apart as *near*, for every method alike.

use relief::error::Result;
use relief::gpu::headless::{self, Gpu};
use relief::gpu::world::World;
use relief::light::lit_beyond;
use relief::method::Method;
use relief::method::{RayMethod, SeedMarch};
use relief::sky::SUN_RADIUS;
use relief::world::WorldParams;
use relief::WorldView;
use std::fmt::Write as _;

/// What the shadow sweep measures with.
#[derive(Clone, Debug, PartialEq)]
pub struct ShadowOptions {
    /// Sun elevations, degrees above the horizon, one bake each.
    pub elevations: Vec<f64>,
    /// Every `stride`-th texel each way of each level drawn, where that level draws it, is a
    /// point.
    pub stride: usize,
}

impl ShadowOptions {
    /// The full sweep: 8 elevations from 1 to 30 degrees, every 16th texel.
    pub fn full() -> Self {
        Self {
            elevations: vec![1.0, 2.0, 3.0, 5.0, 8.0, 12.0, 20.0, 30.0],
            stride: 16,
        }
    }

    /// `--quick`: small enough for the tests (every 128th texel).
    pub fn quick() -> Self {
        Self {
            elevations: vec![1.0, 3.0, 12.0],
            stride: 128,
        }
    }
}

/// The methods on the shadow axis, in the order of the table.
pub const SHADOW_METHODS: [Method; 3] = [Method::Mesh, Method::Reference, Method::Raymarch];

/// One method at one sun elevation.
#[derive(Clone, Debug, PartialEq)]
pub struct ShadowRow {
    /// `mesh` (the light bake), `reference` or `raymarch` (the seed's shadow march).
    pub method: Method,
    /// The sun's elevation, degrees.
    pub elevation_deg: f64,
    /// Points compared.
    pub sampled: usize,
    /// Of those, shadowed by their own surface within [`near`] metres (not judged).
    pub near: usize,
    /// Of those, outside the penumbra and not near.
    pub judged: usize,
    /// Of the judged, in shadow by the truth.
    pub shadowed: usize,
    /// Shadowed by the truth, lit (more than half the disc) by the method.
    pub tunnelled: usize,
    /// Lit by the truth, shadowed (less than half the disc) by the method.
    pub false_shadow: usize,
}

impl ShadowRow {
    /// Tunnelled points as a fraction of the truth's shadowed ones.
    pub fn tunnelled_fraction(&self) -> f64 {
        self.tunnelled as f64 / self.shadowed.max(1) as f64
    }

    /// Falsely shadowed points as a fraction of the truth's lit ones.
    pub fn false_shadow_fraction(&self) -> f64 {
        self.false_shadow as f64 / (self.judged - self.shadowed).max(1) as f64
    }
}

/// The view the shadow axis bakes around: the benchmark's ground-to-horizon view of `params`.
pub fn shadow_view(params: &WorldParams) -> WorldView {
    crate::bench_world::views(params, (480, 270))[0].view
}

/// Sweeps the shadow axis over `params`' world (its sun's azimuth, each of the options'
/// elevations); `progress(done, total)` after each elevation.
pub fn shadows(
    gpu: &Gpu,
    params: &WorldParams,
    options: &ShadowOptions,
    mut progress: impl FnMut(usize, usize),
) -> Result<Vec<ShadowRow>> {
    let land = &params.land;
    let slope = *land.slope_bounds().last().unwrap_or(&1.0);
    let view = shadow_view(params);
    let region = relief::gpu::world_rays::drawn_region(params, &view);
    let mut rows = Vec::new();
    let mut world: Option<World> = None;
    for (done, &e) in options.elevations.iter().enumerate() {
        let mut p = *params;
        p.sky.sun_elevation = e as f32;
        p.validate()?;
        // Heights are baked once; a new sun re-bakes only the light (as the window's keys do).
        if let Some(w) = world.as_mut() {
            w.set_params(&gpu.device, p)?;
        } else {
            let mut w = World::new(&gpu.device, &gpu.queue, headless::Offscreen::targets(1), p)?;
            w.set_bake_budget(u64::MAX);
            w.set_light_budget(u64::MAX);
            world = Some(w);
        }
        let Some(world) = world.as_mut() else {
            unreachable!("made above")
        };
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        world.encode_bake(&gpu.device, &gpu.queue, &mut encoder, &view)?;
        gpu.queue.submit([encoder.finish()]);
        let texels = sample(gpu, world, options.stride)?;
        let points: Vec<[f64; 2]> = texels.iter().map(|t| [t.0, t.1]).collect();
        let seed = RayMethod::SeedMarch(SeedMarch {
            march_octaves: land.octaves,
            normal_octaves: land.octaves,
            ..SeedMarch::default()
        });
        let horizons = [
            texels.iter().map(|t| t.2).collect(),
            headless::world_horizons(gpu, &p, &view, RayMethod::Reference, &points)?,
            headless::world_horizons(gpu, &p, &view, seed, &points)?,
        ];
        let truth = truth(&p, &points, slope, region);
        for (method, horizon) in SHADOW_METHODS.iter().zip(&horizons) {
            let mut row = ShadowRow {
                method: *method,
                elevation_deg: e,
                sampled: points.len(),
                near: 0,
                judged: 0,
                shadowed: 0,
                tunnelled: 0,
                false_shadow: 0,
            };
            let sun = e.to_radians() as f32;
            for (t, &h) in truth.iter().zip(horizon) {
                let lit = match *t {
                    Truth::Lit => true,
                    Truth::Shadowed => false,
                    Truth::Near => {
                        row.near += 1;
                        continue;
                    }
                    Truth::Penumbra => continue,
                };
                row.judged += 1;
                row.shadowed += usize::from(!lit);
                row.tunnelled += usize::from(!lit && h < sun);
                row.false_shadow += usize::from(lit && h > sun);
            }
            rows.push(row);
        }
        progress(done + 1, options.elevations.len());
    }
    Ok(rows)
}

/// Every `stride`-th texel each way of each level drawn, where that level draws it (outside
/// the next finer level's square): (world x, z, the light bake's horizon there).
fn sample(gpu: &Gpu, world: &World, stride: usize) -> Result<Vec<(f64, f64, f32)>> {
    let map = world.clipmap();
    let drawn: Vec<usize> = (map.first_drawn()..map.levels.len())
        .filter(|&l| map.levels[l].active)
        .collect();
    let per_level = headless::world_light_horizons(gpu, world, &drawn, stride)?;
    let cells = f64::from(map.cells());
    let mut out = Vec::new();
    for (k, texels) in per_level.into_iter().enumerate() {
        let inner = (k > 0).then(|| {
            let finer = &map.levels[drawn[k - 1]];
            let s = finer.spacing();
            let (x0, z0) = (
                f64::from(finer.origin[0]) * s,
                f64::from(finer.origin[1]) * s,
            );
            [x0, z0, x0 + cells * s, z0 + cells * s]
        });
        out.extend(texels.into_iter().filter(|&(x, z, _)| {
            inner.is_none_or(|r| !(x > r[0] && x < r[2] && z > r[1] && z < r[3]))
        }));
    }
    Ok(out)
}

/// How far from the point relief's horizon marches take their first sample, metres
/// (`wgsl/world_rays.wgsl`): a millimetre and a thousandth of the peak height.
pub fn near(params: &WorldParams) -> f64 {
    1e-3 + 1e-3 * params.land.peak_height
}

/// The truth at a point.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Truth {
    Lit,
    /// By terrain beyond [`near`].
    Shadowed,
    /// Only by its own surface within [`near`].
    Near,
    /// The disc's top and bottom disagree.
    Penumbra,
}

/// The truth at each point for `params`' sun. Rays end at `region`'s edge (what the methods
/// see).
fn truth(params: &WorldParams, points: &[[f64; 2]], slope: f64, region: [f64; 4]) -> Vec<Truth> {
    let azimuth = f64::from(params.sky.sun_azimuth).to_radians();
    let e = f64::from(params.sky.sun_elevation).to_radians();
    let w = f64::from(SUN_RADIUS);
    let (dx, dz) = (azimuth.sin(), -azimuth.cos());
    let one = |p: &[f64; 2]| {
        // How far the sun's direction runs inside the region.
        let exit = |x: f64, d: f64, lo: f64, hi: f64| {
            if d > 1e-12 {
                (hi - x) / d
            } else if d < -1e-12 {
                (lo - x) / d
            } else {
                f64::INFINITY
            }
        };
        let reach = exit(p[0], dx, region[0], region[2]).min(exit(p[1], dz, region[1], region[3]));
        let lit = |elevation: f64, from: f64| {
            lit_beyond(
                &params.land,
                (p[0], p[1]),
                (azimuth, elevation),
                slope,
                (from, reach),
            )
        };
        let from = near(params);
        match (lit(e - w, from), lit(e + w, from)) {
            (true, true) if !lit(e + w, 0.0) => Truth::Near,
            (true, true) => Truth::Lit,
            (false, false) => Truth::Shadowed,
            _ => Truth::Penumbra,
        }
    };
    super::parallel_map(points, one)
}

/// The CSV: a header and a row per method and elevation, with the device and backend.
pub fn shadow_csv(rows: &[ShadowRow], device: &str, backend: &str, params: &WorldParams) -> String {
    let mut out = String::from(
        "method,sun_elevation_deg,sun_azimuth_deg,sampled,near,judged,shadowed,tunnelled,false_shadow,tunnelled_fraction,false_shadow_fraction,device,backend\n",
    );
    for r in rows {
        let _ = writeln!(
            out,
            "{},{},{},{},{},{},{},{},{},{:.5},{:.5},{device},{backend}",
            r.method,
            r.elevation_deg,
            params.sky.sun_azimuth,
            r.sampled,
            r.near,
            r.judged,
            r.shadowed,
            r.tunnelled,
            r.false_shadow,
            r.tunnelled_fraction(),
            r.false_shadow_fraction(),
        );
    }
    out
}

/// The table: a row per method, a column per elevation.
pub fn shadow_table(rows: &[ShadowRow], options: &ShadowOptions) -> String {
    let mut out = format!("{:<10}", "sun °");
    for e in &options.elevations {
        let _ = write!(out, " {e:>15}");
    }
    out.push('\n');
    for m in SHADOW_METHODS {
        let _ = write!(out, "{:<10}", m.to_string());
        for e in &options.elevations {
            let cell = rows
                .iter()
                .find(|r| r.method == m && r.elevation_deg == *e)
                .map_or("-".to_owned(), |r| {
                    format!(
                        "{:.3} / {:.3}",
                        r.tunnelled_fraction(),
                        r.false_shadow_fraction()
                    )
                });
            let _ = write!(out, " {cell:>15}");
        }
        out.push('\n');
    }
    out.push_str(
        "cells: tunnelled (fraction of the truth's shadowed points) / falsely shadowed (of its lit points)\n",
    );
    out
}

/// The chart: tunnelled fraction (solid) and falsely shadowed fraction (thin) against the
/// sun's elevation (log), a colour per method, the default elevation marked.
pub fn shadow_chart(
    rows: &[ShadowRow],
    options: &ShadowOptions,
    default_deg: f64,
    (title, stem): (&str, &std::path::Path),
) -> Result<()> {
    crate::chart::write_chart(
        stem,
        |b| draw(b, rows, options, default_deg, title),
        |b| draw(b, rows, options, default_deg, title),
    )
}

fn draw<DB: plotters::prelude::DrawingBackend>(
    backend: DB,
    rows: &[ShadowRow],
    options: &ShadowOptions,
    default_deg: f64,
    title: &str,
) -> std::result::Result<(), String>
where
    DB::ErrorType: 'static,
{
    use plotters::prelude::*;
    let root = backend.into_drawing_area();
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let (e0, e1) = super::log_span(options.elevations.iter().copied(), 1.3);
    let top = rows
        .iter()
        .map(|r| r.tunnelled_fraction().max(r.false_shadow_fraction()))
        .fold(0.0, f64::max)
        .max(0.01)
        * 1.15;
    let mut chart = super::log_x_chart(
        &root,
        title,
        (e0, e1, top),
        (
            "sun elevation above the horizon, degrees (log)",
            "fraction of judged points wrong",
        ),
    )?;
    let grey = RGBColor(150, 150, 150);
    chart
        .draw_series(LineSeries::new(
            [(default_deg, 0.0), (default_deg, top)],
            grey.stroke_width(1),
        ))
        .map_err(|e| e.to_string())?
        .label(format!("default sun ({default_deg}°)"))
        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], grey));
    for (i, m) in SHADOW_METHODS.iter().enumerate() {
        let color = match m {
            Method::Mesh => BLACK.to_rgba(),
            _ => Palette99::pick(i).to_rgba(),
        };
        let mine = || rows.iter().filter(|r| r.method == *m);
        let tunnel: Vec<(f64, f64)> = mine()
            .map(|r| (r.elevation_deg, r.tunnelled_fraction()))
            .collect();
        let wrong: Vec<(f64, f64)> = mine()
            .map(|r| (r.elevation_deg, r.false_shadow_fraction()))
            .collect();
        chart
            .draw_series(LineSeries::new(tunnel.clone(), color.stroke_width(3)))
            .map_err(|e| e.to_string())?
            .label(format!("{m}: tunnelled (lit in shadow)"))
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(3))
            });
        chart
            .draw_series(tunnel.iter().map(|&p| Circle::new(p, 4, color.filled())))
            .map_err(|e| e.to_string())?;
        chart
            .draw_series(LineSeries::new(wrong.clone(), color.stroke_width(1)))
            .map_err(|e| e.to_string())?
            .label(format!("{m}: falsely shadowed"))
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color));
        chart
            .draw_series(wrong.iter().map(|&p| Cross::new(p, 4, color)))
            .map_err(|e| e.to_string())?;
    }
    crate::chart::legend(&mut chart, SeriesLabelPosition::UpperRight)?;
    root.present().map_err(|e| e.to_string())
}
