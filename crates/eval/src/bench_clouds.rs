//! `relief bench --world endless --only clouds`: what the clouds ([`relief::world::clouds`])
//! cost and how near their march comes to one of many more steps. On the clouds' own views
//! (from a valley looking up, inside the layer, above it looking down, each at noon and at
//! dusk), the benchmark's named views and the random view set ([`crate::views::random_views`],
//! fixed by a seed), the default frame (the visibility method rasterised in compute, one
//! sample a pixel, the temporal service on) is drawn without clouds, with them (the scene's
//! layer, or coverage 0.5 where it has none) marched one pixel in 16 a frame through the
//! clouds' image, and with them marched along every pixel every frame
//! ([`Clouds::reproject`] off): the frame's median GPU time, the shading's and the image's;
//! and the image's on a frame after a camera cut, which marches every pixel.
//! Then, on the clouds' views and the named ones (a row each after the costs' rows; not with
//! `--quick`), the still frame accumulated over [`CONVERGED`] frames, every pixel marched
//! every frame at [`relief::world::clouds::STEPS`] steps and at the reference's
//! ([`REFERENCE_STEPS`]), and through the image at [`relief::world::clouds::STEPS`], is
//! compared by FLIP with the full march at twice the reference's steps ([`DOUBLED`]): the
//! march's error against its own limit, what doubling the reference's steps changes (the
//! issue's bound: under 0.002), and the image's error. Last, the image's still frame against
//! the reference cast itself (`--method reference`: [`REFERENCE_SIDE`]² rays a pixel, each
//! marching the clouds at [`REFERENCE_STEPS`]), and the same frame without clouds against the
//! reference without them (what the terrain's method leaves, which the first includes), both
//! without grass (the grass reference casts every blade, which the clouds do not need).

use crate::bench::{measure, Options};
use crate::bench_temporal::{method, reference, REFERENCE_SIDE};
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
    /// The frame's median GPU time without clouds, with them through the image, and marched
    /// along every pixel, milliseconds.
    pub frame_ms: [Option<f64>; 3],
    /// The shading's median GPU time in the same three frames.
    pub shade_ms: [Option<f64>; 3],
    /// The clouds' image's median GPU time (its march and carry), and on a frame after a cut.
    pub image_ms: [Option<f64>; 2],
    /// The frame through the image without light shafts ([`Clouds::shafts`] off), ms: what
    /// the shafts cost is `frame_ms[1]` less this.
    pub unshafted_ms: Option<f64>,
    /// FLIP against the full march at [`DOUBLED`] steps of the converged frame marched fully
    /// at [`STEPS`] and at [`REFERENCE_STEPS`] steps, and through the image at [`STEPS`]; then,
    /// without grass, of the image's converged frame against the reference cast, and of the
    /// converged frame without clouds against the reference without them (None: not measured
    /// on this view).
    pub flip: [Option<f64>; 5],
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

/// The frame's, the shading's and the clouds' image's median GPU time of `view`, each frame
/// after a camera cut where `cut`.
fn cost(
    gpu: &Gpu,
    (options, target, timer): (&Options, &Offscreen, Option<&GpuTimer>),
    (params, cut): (&WorldParams, bool),
    view: &WorldView,
) -> Result<[Option<f64>; 3]> {
    let mut w = world(gpu, params)?;
    target.accumulate_world(gpu, &mut w, view, 0)?;
    let (times, _) = measure(gpu, options, timer, |encoder, timer| {
        if cut {
            w.cut();
        }
        let _ = w.prepare_timed(&gpu.device, &gpu.queue, encoder, view, timer);
        target.draw(encoder, &w, wgpu::Color::BLACK, timer);
    })?;
    let slot = |s: Slot| median(times.iter().filter_map(|t| t[s as usize]));
    Ok([
        median(times.iter().filter_map(relief::choice::draw_ms)),
        slot(Slot::Shade),
        slot(Slot::Clouds),
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
    let full = WorldParams {
        clouds: Clouds {
            reproject: false,
            ..cloudy.clouds
        },
        ..cloudy
    };
    let unshafted = WorldParams {
        clouds: Clouds {
            shafts: false,
            ..cloudy.clouds
        },
        ..cloudy
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
        let off = cost(gpu, how, (&at(&bare, *hour, *seed), false), view)?;
        let on = cost(gpu, how, (&at(&cloudy, *hour, *seed), false), view)?;
        let every = cost(gpu, how, (&at(&full, *hour, *seed), false), view)?;
        let cut = cost(gpu, how, (&at(&cloudy, *hour, *seed), true), view)?;
        let plain = cost(gpu, how, (&at(&unshafted, *hour, *seed), false), view)?;
        let r = CloudRow {
            view: name.clone(),
            frame_ms: [off[0], on[0], every[0]],
            shade_ms: [off[1], on[1], every[1]],
            image_ms: [on[2], cut[2]],
            unshafted_ms: plain[0],
            flip: [None; 5],
        };
        row(&r)?;
        rows.push(r);
    }
    for (name, view, hour, seed, compare) in &list {
        if !compare || quick {
            continue;
        }
        let steps = |n: u32, p: &WorldParams| {
            let mut p = at(p, *hour, *seed);
            p.clouds.steps = n;
            converged(gpu, &target, &p, view)
        };
        let limit = steps(DOUBLED, &full)?;
        // Against the reference cast, without grass.
        let cast = |p: &WorldParams| -> Result<(Vec<u8>, Vec<u8>)> {
            let p = at(&p.without_grass(), *hour, *seed);
            Ok((
                reference(gpu, &p, view, REFERENCE_SIDE)?,
                converged(gpu, &target, &p, view)?,
            ))
        };
        let (truth, image) = cast(&cloudy)?;
        let (bare_truth, bare_image) = cast(&bare)?;
        let r = CloudRow {
            view: name.clone(),
            frame_ms: [None; 3],
            shade_ms: [None; 3],
            image_ms: [None; 2],
            unshafted_ms: None,
            flip: [
                Some(flip(&limit, &steps(STEPS, &full)?)),
                Some(flip(&limit, &steps(REFERENCE_STEPS, &full)?)),
                Some(flip(&limit, &steps(STEPS, &cloudy)?)),
                Some(flip(&truth, &image)),
                Some(flip(&bare_truth, &bare_image)),
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
         (visibility, 1 sample, compute raster, temporal on) without clouds, with them through \
         the image (one pixel in 16 marched a frame) and marched along every pixel (full); the \
         image's pass, and on a frame after a cut; what the light shafts add; FLIP of the still frame ({CONVERGED} frames) \
         marched fully at {STEPS} and {REFERENCE_STEPS} steps and through the image at {STEPS} \
         against the full march at {DOUBLED}; without grass, the image's against the reference \
         cast ({REFERENCE_SIDE}x{REFERENCE_SIDE} rays a pixel, {REFERENCE_STEPS} steps) and the \
         frame without clouds against the reference without them\nview,frame_off_ms,frame_on_ms,frame_full_ms,\
         shade_off_ms,shade_on_ms,shade_full_ms,image_ms,image_cut_ms,clouds_ms,\
         clouds_full_ms,shafts_ms,flip_{STEPS},flip_{REFERENCE_STEPS},flip_image,\
         flip_image_vs_reference,flip_bare_vs_reference\n",
        size.0, size.1
    )
}

fn cell(x: Option<f64>, digits: usize) -> String {
    x.map_or_else(String::new, |v| format!("{v:.digits$}"))
}

/// What the clouds add to the frame, where both were measured: through the image (`i` 1) or
/// marched fully (2).
fn added(r: &CloudRow, i: usize) -> Option<f64> {
    Some(r.frame_ms[i]? - r.frame_ms[0]?)
}

/// What the light shafts add to the frame through the image, where measured.
fn shafts(r: &CloudRow) -> Option<f64> {
    Some(r.frame_ms[1]? - r.unshafted_ms?)
}

/// One row of the CSV.
pub fn line(r: &CloudRow) -> String {
    let cells = [
        r.frame_ms[0],
        r.frame_ms[1],
        r.frame_ms[2],
        r.shade_ms[0],
        r.shade_ms[1],
        r.shade_ms[2],
        r.image_ms[0],
        r.image_ms[1],
        added(r, 1),
        added(r, 2),
        shafts(r),
        r.flip[0],
        r.flip[1],
        r.flip[2],
        r.flip[3],
        r.flip[4],
    ];
    let cells: Vec<String> = cells.iter().map(|c| cell(*c, 4)).collect();
    format!("{},{}\n", r.view, cells.join(","))
}

/// The summary: the clouds' cost and the frame with them, median and worst, over the clouds'
/// views, the named and the random ones; the worst FLIP.
pub fn summary(rows: &[CloudRow]) -> Vec<String> {
    let stats = |v: Vec<f64>| {
        let worst = v.iter().copied().fold(f64::NAN, f64::max);
        (median(v), worst)
    };
    let (cost, cost_worst) = stats(rows.iter().filter_map(|r| added(r, 1)).collect());
    let (full, full_worst) = stats(rows.iter().filter_map(|r| added(r, 2)).collect());
    let (cut, cut_worst) = stats(rows.iter().filter_map(|r| r.image_ms[1]).collect());
    let (frame, frame_worst) = stats(rows.iter().filter_map(|r| r.frame_ms[1]).collect());
    let (shaft, shaft_worst) = stats(rows.iter().filter_map(shafts).collect());
    let worst_flip = |i: usize| {
        let worst = rows.iter().filter_map(|r| r.flip[i]).reduce(f64::max);
        worst.map_or_else(|| "not measured".to_owned(), |w| format!("{w:.4}"))
    };
    vec![
        format!(
            "clouds: {} views; through the image they add {} ms median, {cost_worst:.3} worst \
             (marched fully: {} median, {full_worst:.3} worst); the frame with them {} ms \
             median, {frame_worst:.3} worst; the image after a cut {} ms median, \
             {cut_worst:.3} worst; the light shafts {} ms median, {shaft_worst:.3} worst",
            rows.iter().filter(|r| r.frame_ms[0].is_some()).count(),
            cell(cost, 3),
            cell(full, 3),
            cell(frame, 3),
            cell(cut, 3),
            cell(shaft, 3),
        ),
        format!(
            "clouds: FLIP against the full march at {DOUBLED} steps, worst: {} marched fully \
             at {STEPS} steps, {} at {REFERENCE_STEPS}, {} through the image at {STEPS}",
            worst_flip(0),
            worst_flip(1),
            worst_flip(2)
        ),
        format!(
            "clouds: FLIP against the reference cast (no grass), worst: {} through the image, \
             {} without clouds",
            worst_flip(3),
            worst_flip(4)
        ),
    ]
}
