//! `relief bench --world endless --only clouds`: what the clouds ([`relief::world::clouds`])
//! cost and how near their march comes to one of many more steps. On the clouds' own views
//! (from a valley looking up, inside the layer, above it looking down, each at noon and at
//! dusk), the benchmark's named views and the random view set ([`crate::views::random_views`],
//! fixed by a seed), the default frame (the visibility method rasterised in compute, one
//! sample a pixel, the temporal service on) is drawn without clouds and with them (the
//! scene's layer, or coverage 0.5 where it has none): its median GPU time and the shading's.
//! Then, on the clouds' views and the named ones (a row each after the costs' rows; not with
//! `--quick`), the still frame accumulated over
//! [`CONVERGED`] frames at [`relief::world::clouds::STEPS`] steps and at four and eight times
//! as many is compared by FLIP with the one at eight times ([`DOUBLED`]): the march's error
//! against its own limit, and what doubling the reference's steps changes.

use crate::bench::{measure, Options};
use crate::bench_temporal::method;
use crate::metrics::{image_error, median, rgb};
use crate::views::{random_views, views, LandscapeView};
use glam::DVec3;
use relief::error::Result;
use relief::gpu::headless::{Gpu, Offscreen};
use relief::gpu::timing::{GpuTimer, Slot};
use relief::world::clouds::{Clouds, REFERENCE_STEPS, STEPS};
use relief::world::WorldParams;
use relief::{Temporal, World, WorldView};

/// Frames a still view accumulates before it is compared.
pub const CONVERGED: u32 = 32;
/// The steps the march is compared with: twice the reference's.
pub const DOUBLED: u32 = 2 * REFERENCE_STEPS;
/// The hours of the clouds' own views.
pub const HOURS: [(&str, f32); 2] = [("noon", 12.0), ("dusk", 18.8)];

/// One view measured.
#[derive(Clone, Debug, PartialEq)]
pub struct CloudRow {
    /// The view.
    pub view: String,
    /// The frame's median GPU time without clouds and with them, milliseconds.
    pub frame_ms: [Option<f64>; 2],
    /// The shading's median GPU time (where the clouds are marched) without and with.
    pub shade_ms: [Option<f64>; 2],
    /// FLIP of the converged frame at [`STEPS`] and at [`REFERENCE_STEPS`] steps against the
    /// one at [`DOUBLED`] (None: not measured on this view).
    pub flip: [Option<f64>; 2],
}

/// The clouds' own views of `params`' world at `size` and the hours they are seen at: the
/// layer's params with the sun at each hour.
pub fn cloud_views(params: &WorldParams, size: (u32, u32)) -> Vec<(String, WorldView, f32)> {
    let land = params.land;
    let c = layer(params);
    let fov = 45f32.to_radians();
    let ground = |x: f64, z: f64| land.height_at(x, z).max(f64::from(params.water_level));
    // The lowest point on a 4 km line: a valley.
    let low = (0..200)
        .map(|i| f64::from(i) * 20.0)
        .min_by(|a, b| ground(*a, 0.0).total_cmp(&ground(*b, 0.0)))
        .unwrap_or(0.0);
    let mut out = Vec::new();
    for (hour, h) in HOURS {
        let (az, _) = relief::day::sun_at(h);
        let a = f64::from(az).to_radians();
        // Towards the sun's bearing: the layer lit from the side the eye looks at.
        let ahead = DVec3::new(a.sin(), 0.0, -a.cos());
        let valley = DVec3::new(low, ground(low, 0.0) + 2.0, 0.0);
        let middle = f64::from(0.5 * (c.base + c.top));
        let inside = DVec3::new(0.0, middle.max(ground(0.0, 0.0) + 50.0), 0.0);
        let above = DVec3::new(0.0, f64::from(c.top) + 1500.0, 0.0);
        for (name, eye, pitch) in [
            ("valley-up", valley, 0.45),
            ("inside", inside, -0.05),
            ("above", above, -0.55),
        ] {
            let at = eye + ahead + DVec3::Y * pitch;
            out.push((
                format!("{name}-{hour}"),
                WorldView::look_at(eye, at, fov, size),
                h,
            ));
        }
    }
    out
}

/// The scene's layer, or a broken one (coverage 0.5) where it has none.
pub fn layer(params: &WorldParams) -> Clouds {
    if params.clouds.on() {
        params.clouds
    } else {
        Clouds {
            coverage: 0.5,
            ..params.clouds
        }
    }
}

fn world(gpu: &Gpu, params: &WorldParams) -> Result<World> {
    let mut world = World::new(&gpu.device, &gpu.queue, Offscreen::targets(1), *params)?;
    world.set_method(&gpu.device, method())?;
    world.set_temporal(&gpu.device, Temporal { frames: CONVERGED })?;
    Ok(world)
}

/// The frame's and the shading's median GPU time of `view`.
fn cost(
    gpu: &Gpu,
    (options, target, timer): (&Options, &Offscreen, Option<&GpuTimer>),
    params: &WorldParams,
    view: &WorldView,
) -> Result<[Option<f64>; 2]> {
    let mut w = world(gpu, params)?;
    target.accumulate_world(gpu, &mut w, view, 0)?;
    let (times, _) = measure(gpu, options, timer, |encoder, timer| {
        let _ = w.prepare_timed(&gpu.device, &gpu.queue, encoder, view, timer);
        target.draw(encoder, &w, wgpu::Color::BLACK, timer);
    })?;
    Ok([
        median(times.iter().filter_map(relief::choice::draw_ms)),
        median(times.iter().filter_map(|t| t[Slot::Shade as usize])),
    ])
}

/// The still frame of `view` accumulated over [`CONVERGED`] frames.
fn converged(
    gpu: &Gpu,
    target: &Offscreen,
    params: &WorldParams,
    view: &WorldView,
) -> Result<Vec<u8>> {
    let mut w = world(gpu, params)?;
    target.accumulate_world(gpu, &mut w, view, CONVERGED - 1)?;
    Ok(rgb(&target.render_world(gpu, &mut w, view, None)?.0))
}

/// A view to measure: its name, the camera, the hour (the clouds' own views), the landscape's
/// seed (the random views), and whether its march is compared with more steps.
type Measured = (String, WorldView, Option<f32>, Option<u32>, bool);

/// Measures every view, handing each row to `row` as it is measured.
pub fn run(
    gpu: &Gpu,
    params: &WorldParams,
    (options, quick): (&Options, bool),
    mut row: impl FnMut(&CloudRow) -> Result<()>,
) -> Result<Vec<CloudRow>> {
    let size = (options.width, options.height);
    let target = Offscreen::new(&gpu.device, size.0, size.1, 1)?;
    let timer = GpuTimer::new(&gpu.device, &gpu.queue);
    let bare = WorldParams {
        clouds: Clouds {
            coverage: 0.0,
            ..params.clouds
        },
        ..*params
    };
    let cloudy = WorldParams {
        clouds: layer(params),
        ..*params
    };
    let mut list: Vec<Measured> = cloud_views(params, size)
        .into_iter()
        .map(|(n, v, h)| (n, v, Some(h), None, true))
        .collect();
    let named = |v: LandscapeView, flip| (v.name.to_owned(), v.view, None, v.seed, flip);
    list.extend(views(params, size).into_iter().map(|v| named(v, true)));
    if !quick {
        list.extend(
            random_views(params, size)
                .into_iter()
                .map(|v| named(v, false)),
        );
    } else {
        list.truncate(2);
    }
    let flip = |a: &[u8], b: &[u8]| image_error(a, b, size.0, size.1).0;
    let at = |p: &WorldParams, hour: Option<f32>, seed: Option<u32>| {
        let mut p = *p;
        if let Some(h) = hour {
            p.sky = relief::day::at_time(p.sky, h);
        }
        if let Some(s) = seed {
            p.land.seed = s;
        }
        p
    };
    let mut rows = Vec::new();
    // Every view's cost first, then the slower comparisons (a run cut short keeps the costs).
    for (name, view, hour, seed, _) in &list {
        let how = (options, &target, timer.as_ref());
        let off = cost(gpu, how, &at(&bare, *hour, *seed), view)?;
        let on = cost(gpu, how, &at(&cloudy, *hour, *seed), view)?;
        let r = CloudRow {
            view: name.clone(),
            frame_ms: [off[0], on[0]],
            shade_ms: [off[1], on[1]],
            flip: [None; 2],
        };
        row(&r)?;
        rows.push(r);
    }
    for (name, view, hour, seed, compare) in &list {
        if !compare || quick {
            continue;
        }
        let steps = |n: u32| {
            let mut p = at(&cloudy, *hour, *seed);
            p.clouds.steps = n;
            converged(gpu, &target, &p, view)
        };
        let limit = steps(DOUBLED)?;
        let r = CloudRow {
            view: name.clone(),
            frame_ms: [None; 2],
            shade_ms: [None; 2],
            flip: [
                Some(flip(&limit, &steps(STEPS)?)),
                Some(flip(&limit, &steps(REFERENCE_STEPS)?)),
            ],
        };
        row(&r)?;
        rows.push(r);
    }
    Ok(rows)
}

/// The CSV's first lines: the device, the size, what each column is.
pub fn header(device: &str, size: (u32, u32)) -> String {
    format!(
        "# relief bench --world endless --only clouds on {device} at {}x{}: the default frame \
         (visibility, 1 sample, compute raster, temporal on) without clouds and with them; \
         FLIP of the still frame ({CONVERGED} frames) at {STEPS} and {REFERENCE_STEPS} steps \
         against {DOUBLED}\nview,frame_off_ms,frame_on_ms,shade_off_ms,shade_on_ms,\
         clouds_ms,flip_{STEPS},flip_{REFERENCE_STEPS}\n",
        size.0, size.1
    )
}

fn cell(x: Option<f64>, digits: usize) -> String {
    x.map_or_else(String::new, |v| format!("{v:.digits$}"))
}

/// What the clouds add to the frame, where both were measured.
fn added(r: &CloudRow) -> Option<f64> {
    Some(r.frame_ms[1]? - r.frame_ms[0]?)
}

/// One row of the CSV.
pub fn line(r: &CloudRow) -> String {
    format!(
        "{},{},{},{},{},{},{},{}\n",
        r.view,
        cell(r.frame_ms[0], 4),
        cell(r.frame_ms[1], 4),
        cell(r.shade_ms[0], 4),
        cell(r.shade_ms[1], 4),
        cell(added(r), 4),
        cell(r.flip[0], 4),
        cell(r.flip[1], 4),
    )
}

/// The summary: the clouds' cost and the frame with them, median and worst, over the clouds'
/// views, the named and the random ones; the worst FLIP.
pub fn summary(rows: &[CloudRow]) -> Vec<String> {
    let stats = |v: Vec<f64>| {
        let worst = v.iter().copied().fold(f64::NAN, f64::max);
        (median(v), worst)
    };
    let (cost, cost_worst) = stats(rows.iter().filter_map(added).collect());
    let (frame, frame_worst) = stats(rows.iter().filter_map(|r| r.frame_ms[1]).collect());
    let worst_flip = |i: usize| {
        rows.iter()
            .filter_map(|r| r.flip[i])
            .fold(f64::NAN, f64::max)
    };
    vec![
        format!(
            "clouds: {} views; they add {} ms median, {cost_worst:.3} worst; the frame with them {} ms median, {frame_worst:.3} worst",
            rows.len(),
            cell(cost, 3),
            cell(frame, 3),
        ),
        format!(
            "clouds: FLIP against {DOUBLED} steps, worst: {:.4} at {STEPS} steps, {:.4} at {REFERENCE_STEPS}",
            worst_flip(0),
            worst_flip(1)
        ),
    ]
}
