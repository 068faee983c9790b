//! What the endless world's look costs (`relief bench --world endless`, written as
//! `look.csv`): the GPU time of the render pass on the benchmark's views with everything on,
//! with each part of the look turned off in turn (the sky pass, fog, shadows, water, the seed
//! template's palette) and with all of them off, so each part's cost is the difference; and the
//! light bake (shadows and valley occlusion) of the whole clipmap, as when the sun turns.
//! Warm-up, then the median, as every benchmark here.

use crate::bench::{measure, Options};
use crate::bench_world::views;
use crate::metrics::median;
use relief::error::Result;
use relief::gpu::headless::{Gpu, Offscreen, RENDER_SAMPLES};
use relief::gpu::timing::{GpuTimer, Slot};
use relief::palette::Palette;
use relief::world::WorldParams;
use relief::{Shading, World};

/// One measured variant on one view.
#[derive(Clone, Debug, PartialEq)]
pub struct LookRow {
    /// The view's name.
    pub view: &'static str,
    /// What was turned off (`everything on`, `none of it`, or one part).
    pub variant: &'static str,
    /// Median GPU time of the render pass, ms.
    pub render_ms: Option<f64>,
    /// Median GPU time of the light bake of every level (the sun turned each frame), ms; only
    /// on the `everything on` rows.
    pub light_ms: Option<f64>,
    /// Texels the light bake covered per frame.
    pub light_texels: u64,
}

/// The variants: a name and what it changes.
type Variant = (&'static str, fn(&mut WorldParams, &mut Shading));

const VARIANTS: [Variant; 7] = [
    ("everything on", |_, _| {}),
    ("no sky pass", |_, s| s.sky = false),
    ("no fog", |p, _| p.sky.fog = 0.0),
    ("no shadows", |p, _| p.no_shadows = true),
    ("no water", |p, _| p.no_water = true),
    ("blog palette", |p, _| p.palette = Palette::Blog),
    ("none of it", |p, s| {
        s.sky = false;
        p.sky.fog = 0.0;
        p.no_shadows = true;
        p.no_water = true;
        p.palette = Palette::Blog;
    }),
];

/// Measures every variant on every view of the benchmark.
pub fn run(
    gpu: &Gpu,
    params: &WorldParams,
    options: &Options,
    mut progress: impl FnMut(&str),
) -> Result<Vec<LookRow>> {
    let size = (options.width, options.height);
    let timer = GpuTimer::new(&gpu.device, &gpu.queue);
    let target = Offscreen::new(&gpu.device, size.0, size.1, RENDER_SAMPLES)?;
    let color = target.color_view();
    let mut rows = Vec::new();
    // The quick run (lavapipe, CI) measures the first view only, at a loose knob.
    let quick = options.frames < 10;
    let params = &WorldParams {
        pixel_error: if quick { 16.0 } else { params.pixel_error },
        ..*params
    };
    let count = if quick { 1 } else { usize::MAX };
    for v in views(params, size).into_iter().take(count) {
        for (variant, change) in VARIANTS {
            progress(&format!("the look on {}: {variant}", v.name));
            let (mut p, mut shading) = (*params, Shading::default());
            change(&mut p, &mut shading);
            let mut world = World::new(
                &gpu.device,
                &gpu.queue,
                Offscreen::targets(RENDER_SAMPLES),
                p,
            )?;
            world.set_shading(shading);
            // Whole bakes: the cost of relighting every level at once (the window spreads it
            // over frames).
            world.set_bake_budget(u64::MAX);
            world.set_light_budget(u64::MAX);
            let everything = variant == VARIANTS[0].0;
            let mut turn = 0.0;
            let mut draw = |world: &mut World,
                            encoder: &mut wgpu::CommandEncoder,
                            timer: Option<&GpuTimer>,
                            light: bool| {
                if light {
                    // Turning the sun re-lights every level.
                    turn += 0.5;
                    let mut q = *world.params();
                    q.sky.sun_azimuth = params.sky.sun_azimuth + turn % 10.0;
                    world.set_params(&gpu.device, q).ok();
                }
                let _ = world.prepare_timed(&gpu.device, &gpu.queue, encoder, &v.view, timer);
                let mut pass = target.begin_pass(
                    encoder,
                    &color,
                    wgpu::Color::BLACK,
                    timer.map(|t| t.render_writes(Slot::Render)),
                );
                world.render(&mut pass);
            };
            let (times, _) = measure(gpu, options, timer.as_ref(), |encoder, timer| {
                draw(&mut world, encoder, timer, false)
            })?;
            let render_ms = median(times.iter().filter_map(|t| t[Slot::Render as usize]));
            let (light_ms, light_texels) = if everything {
                let (times, _) = measure(gpu, options, timer.as_ref(), |encoder, timer| {
                    draw(&mut world, encoder, timer, true)
                })?;
                let map = world.clipmap();
                let active = map.levels.iter().filter(|l| l.active).count() as u64;
                (
                    median(times.iter().filter_map(|t| t[Slot::Light as usize])),
                    active * u64::from(map.side()).pow(2),
                )
            } else {
                (None, 0)
            };
            rows.push(LookRow {
                view: v.name,
                variant,
                render_ms,
                light_ms,
                light_texels,
            });
        }
    }
    Ok(rows)
}

/// The rows as CSV, with the device and the options in a comment line, and each variant's
/// saving against `everything on` of its view.
pub fn csv(rows: &[LookRow], device: &str, options: &Options) -> String {
    let mut out = format!(
        "# relief bench --world endless: the look's cost on {device}, {}x{}, median of {} frames after {} ms of warm-up\n",
        options.width, options.height, options.frames, options.warmup_ms
    );
    out.push_str("view,variant,render_ms,saved_ms,light_bake_ms,light_texels\n");
    let opt = |v: Option<f64>| v.map_or(String::new(), |v| format!("{v:.4}"));
    for r in rows {
        let full = rows
            .iter()
            .find(|f| f.view == r.view && f.variant == VARIANTS[0].0)
            .and_then(|f| f.render_ms);
        let saved = full.zip(r.render_ms).map(|(f, m)| f - m);
        out.push_str(&format!(
            "{},{},{},{},{},{}\n",
            r.view,
            r.variant,
            opt(r.render_ms),
            opt(saved),
            opt(r.light_ms),
            r.light_texels
        ));
    }
    out
}
