//! Timing work as a benchmark (warm-up, then the median) and `auto`'s trial: each candidate
//! method drawn for a few frames, the fastest chosen.

use super::*;

/// Times `run` (work it submits and waits for, timed by the timer it is given, if any) as a
/// benchmark, not one cold dispatch: an idle GPU lowers its clocks (a lone bake after a
/// read-back timed at up to twice its warm time on an H100), so `run` goes untimed for
/// [`BAKE_WARM_UP`] first, then [`BAKE_RUNS`] times timed. Returns each slot's median.
pub fn warm_median(
    timer: &GpuTimer,
    mut run: impl FnMut(Option<&GpuTimer>) -> Result<Option<Timings>>,
) -> Result<Timings> {
    let start = std::time::Instant::now();
    while start.elapsed() < BAKE_WARM_UP {
        run(None)?;
    }
    let mut runs = Vec::with_capacity(BAKE_RUNS);
    for _ in 0..BAKE_RUNS {
        runs.extend(run(Some(timer))?);
    }
    Ok(std::array::from_fn(|slot| {
        let mut ms: Vec<f64> = runs.iter().filter_map(|t| t[slot]).collect();
        ms.sort_by(f64::total_cmp);
        ms.get(ms.len() / 2).copied()
    }))
}

/// Runs `frame` (which records one frame into the encoder, timed by the timer it is given,
/// if any) back to back for the warm-up (at least `warmup.0` frames and `warmup.1`
/// milliseconds: an idle GPU lowers its clocks), then `frames` timed frames, each submitted
/// and waited for. Returns the GPU timings and the wall time of each timed frame.
pub fn measure_frames(
    gpu: &Gpu,
    (warmup, warmup_ms): (u32, f64),
    frames: u32,
    timer: Option<&GpuTimer>,
    mut frame: impl FnMut(&mut wgpu::CommandEncoder, Option<&GpuTimer>),
) -> Result<(Vec<Timings>, Vec<f64>)> {
    let wait = || {
        gpu.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map(|_| ())
            .map_err(|e| Error::Readback(e.to_string()))
    };
    let start = std::time::Instant::now();
    let mut n = 0;
    while n < warmup || start.elapsed().as_secs_f64() * 1e3 < warmup_ms {
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        frame(&mut encoder, None);
        gpu.queue.submit([encoder.finish()]);
        n += 1;
        if n % 16 == 0 {
            // Keep a bounded amount of work in flight.
            wait()?;
        }
    }
    wait()?;
    let (mut times, mut wall) = (Vec::new(), Vec::new());
    for _ in 0..frames {
        let start = std::time::Instant::now();
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        frame(&mut encoder, timer);
        if let Some(t) = timer {
            t.resolve(&mut encoder);
        }
        gpu.queue.submit([encoder.finish()]);
        wait()?;
        wall.push(start.elapsed().as_secs_f64() * 1e3);
        if let Some(t) = timer {
            times.push(t.read(&gpu.device)?);
        }
    }
    Ok((times, wall))
}

/// What [`choose_method`] draws: the tile (seen through a view) or the endless world (seen
/// through its view, whose size the frames are drawn at).
pub enum TrialScene<'a> {
    /// The tile, and the image size.
    Tile(&'a mut Terrain, &'a View, (u32, u32)),
    /// The endless world.
    Endless(&'a mut World, &'a WorldView),
}

impl TrialScene<'_> {
    /// Sets it to draw `c` as `relief render` does: into a target of [`render_samples`] (the
    /// host's 4x MSAA for the mesh, none for the methods that anti-alias on their own), at
    /// `c`'s samples a pixel.
    pub fn set(&mut self, device: &wgpu::Device, c: Candidate) -> Result<()> {
        let targets = Offscreen::targets(render_samples(c.method));
        match self {
            TrialScene::Tile(terrain, ..) => {
                terrain.set_targets(device, targets)?;
                terrain.set_method(device, c.config())
            }
            TrialScene::Endless(world, _) => {
                world.set_targets(device, targets)?;
                world.set_method(device, c.config())
            }
        }
    }
}

/// Untimed frames of each candidate before [`choose_method`] times it: at least this many
/// milliseconds (an H100 left idle while the next candidate is set up drops its clocks) ...
pub(crate) const TRIAL_WARM_UP_MS: f64 = 300.0;
/// ... and at least this many frames.
pub(crate) const TRIAL_WARM_UP: u32 = 2;
/// The trial measures no further candidate once this long has passed (the first is always
/// measured): on a software device a candidate can take tens of seconds.
pub(crate) const TRIAL_LIMIT: std::time::Duration = std::time::Duration::from_secs(10);

/// Timed frames of each candidate; their median decides.
pub const TRIAL_FRAMES: u32 = 5;

/// Chooses the method of the default ([`crate::choice`]) and leaves `scene` set to draw it
/// ([`TrialScene::set`]): draws [`TRIAL_FRAMES`] timed frames of each of the world's
/// [`Candidate`]s into an offscreen target of its own sample count, after a warm-up, and keeps
/// the fastest median draw. The trial bakes once for every candidate; then everything is
/// marked owed again, the viewport or target size put back, so the caller's next frame bakes
/// and draws as the chosen method pinned would (its timings and stats included). A size over
/// [`TILE`] a side is measured scaled down to fit it (a larger image is drawn in tiles of that
/// size). The mesh, said so, where the device has no timestamp queries. On an error the scene
/// is left set to one of the candidates.
pub fn choose_method(gpu: &Gpu, mut scene: TrialScene<'_>) -> Result<Choice> {
    let Some(timer) = GpuTimer::new(&gpu.device, &gpu.queue) else {
        let choice = Choice::unmeasured();
        scene.set(&gpu.device, choice.candidate)?;
        return Ok(choice);
    };
    let full = match &scene {
        TrialScene::Tile(.., size) => *size,
        TrialScene::Endless(_, view) => view.size,
    };
    let scale = (f64::from(TILE) / f64::from(full.0.max(full.1))).min(1.0);
    let size = (
        ((f64::from(full.0) * scale).round() as u32).max(1),
        ((f64::from(full.1) * scale).round() as u32).max(1),
    );
    let world = match scene {
        TrialScene::Tile(..) => crate::WorldKind::Tile,
        TrialScene::Endless(..) => crate::WorldKind::Endless,
    };
    let warm = (TRIAL_WARM_UP, TRIAL_WARM_UP_MS);
    let kept = match &scene {
        TrialScene::Tile(terrain, ..) => (Some(terrain.viewport()), None),
        TrialScene::Endless(world, _) => (None, world.target_size()),
    };
    let mut ms = Vec::new();
    let started = std::time::Instant::now();
    for &c in Candidate::all(world) {
        if started.elapsed() > TRIAL_LIMIT && !ms.is_empty() {
            // A slow device (a software one) would spend minutes on the rest: they stay
            // unmeasured, and the choice is among those measured.
            ms.push((c, f64::NAN));
            continue;
        }
        scene.set(&gpu.device, c)?;
        let samples = render_samples(c.method);
        let target = Offscreen::new(&gpu.device, size.0, size.1, samples)?;
        let mut failed = None;
        let (times, _) = match &mut scene {
            TrialScene::Tile(terrain, view, _) => {
                terrain.set_viewport(size);
                bake_whole(gpu, terrain, view, None)?;
                let sky = terrain.shading().sky_color;
                let clear = crate::gpu::clear_color(sky, Offscreen::COLOR_FORMAT);
                measure_frames(gpu, warm, TRIAL_FRAMES, Some(&timer), |encoder, timer| {
                    let recorded =
                        terrain.prepare_timed(&gpu.device, &gpu.queue, encoder, view, timer);
                    if let Err(e) = recorded {
                        failed.get_or_insert(e);
                    }
                    target.draw(encoder, &**terrain, clear, timer);
                })?
            }
            TrialScene::Endless(world, view) => {
                let view = WorldView {
                    size,
                    crop: glam::Mat4::IDENTITY,
                    ..**view
                };
                world.set_target_size(None);
                let budgets = (world.bake_budget(), world.light_budget());
                let restore = |world: &mut World| {
                    world.set_bake_budget(budgets.0);
                    world.set_light_budget(budgets.1);
                };
                world.set_bake_budget(u64::MAX);
                world.set_light_budget(u64::MAX);
                let baked = bake_in_passes(gpu, None, |encoder, timer| {
                    world.encode_bake_timed(&gpu.device, &gpu.queue, encoder, &view, timer)?;
                    Ok(world.pending_texels())
                });
                if let Err(e) = baked {
                    restore(world);
                    return Err(e);
                }
                let sky = world.shading().sky_color;
                let clear = crate::gpu::clear_color(sky, Offscreen::COLOR_FORMAT);
                let measured =
                    measure_frames(gpu, warm, TRIAL_FRAMES, Some(&timer), |encoder, timer| {
                        let recorded =
                            world.prepare_timed(&gpu.device, &gpu.queue, encoder, &view, timer);
                        if let Err(e) = recorded {
                            failed.get_or_insert(e);
                        }
                        target.draw(encoder, &**world, clear, timer);
                    });
                restore(world);
                measured?
            }
        };
        if let Some(e) = failed {
            return Err(e);
        }
        let mut draws: Vec<f64> = times.iter().filter_map(draw_ms).collect();
        draws.sort_by(f64::total_cmp);
        ms.push((c, draws.get(draws.len() / 2).copied().unwrap_or(f64::NAN)));
    }
    let choice = Choice::decide(ms, TRIAL_FRAMES as usize, size);
    scene.set(&gpu.device, choice.candidate)?;
    match scene {
        TrialScene::Tile(terrain, ..) => {
            terrain.set_viewport(kept.0.unwrap_or(size));
            terrain.invalidate();
        }
        TrialScene::Endless(world, _) => {
            world.set_target_size(kept.1);
            world.invalidate(&gpu.device)?;
        }
    }
    Ok(choice)
}
