//! `relief bench --world endless`'s arrival: what a user waits through on reaching the endless
//! world and flying on. A fresh world (nothing baked, nothing lit) seen from a camera flying at
//! [`SPEED`] 40 m over the ground, frame by frame at 60 frames a second from the first, with
//! no warm-up: each frame's GPU time (the height bake, the light bake and the draw, from
//! timestamps), the texels it baked and lit, and what still waits; halfway, the sun turns by
//! [`TURN`] degrees (a slider or a key: every level relit). The core's default per-frame
//! budgets ([`relief::gpu::world::DEFAULT_BAKE_BUDGET`],
//! [`relief::gpu::world::DEFAULT_LIGHT_BUDGET`]) are what a GPU's window reaches.
//!
//! Then the day runs (a day in [`DAY_LENGTH`] seconds from 9:00, the window's N): [`DAY_FRAMES`]
//! frames standing where the arrival ended, then as many flying on, each frame's sun moved by
//! the clock and its light relit in rounds within the same budget: what a moving sun costs a
//! frame, and how many frames a round of relight takes (how far the shadows lag the sun).

use glam::DVec3;
use relief::error::Result;
use relief::gpu::headless::{render_samples, Gpu, Offscreen};
use relief::gpu::timing::{GpuTimer, Slot};
use relief::world::WorldParams;
use relief::{Method, Raster, World, WorldView};

/// The camera's speed, metres a second.
pub const SPEED: f64 = 200.0;

/// How far the sun turns halfway through, degrees.
pub const TURN: f32 = 10.0;

/// Seconds of the clock a day takes in the running day's frames.
pub const DAY_LENGTH: f32 = 60.0;

/// Frames of the running day standing, and as many flying.
pub const DAY_FRAMES: u32 = 120;

/// What the world does in a frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Phase {
    /// Arriving: a fresh world, flown through (the sun turned once halfway).
    Arrival,
    /// The day running, the camera still.
    DayStanding,
    /// The day running, the camera flying on.
    DayFlying,
}

impl Phase {
    /// As the CSV names it.
    pub fn name(self) -> &'static str {
        match self {
            Phase::Arrival => "arrival",
            Phase::DayStanding => "day-standing",
            Phase::DayFlying => "day-flying",
        }
    }
}

/// One frame of the arrival.
#[derive(Clone, Debug, PartialEq)]
pub struct ArrivalFrame {
    /// The method drawing, as `relief render` names it.
    pub method: String,
    /// From 0.
    pub frame: u32,
    /// The GPU time of every pass of the frame (bake, light and draw), ms; None without
    /// timestamps.
    pub gpu_ms: Option<f64>,
    /// The height bake's share, ms.
    pub bake_ms: Option<f64>,
    /// The light bake's share, ms.
    pub light_ms: Option<f64>,
    /// The light shafts' shadow-height map's share (where the frame draws shafts and the sun,
    /// the eye's texel or the levels changed), ms.
    pub shafts_ms: Option<f64>,
    /// Texels whose heights it baked.
    pub texels_baked: u64,
    /// Texels it lit.
    pub light_texels: u64,
    /// Texels (heights and light) still waiting after it.
    pub pending: u64,
    /// Wall time from the world's creation to this frame's end, ms.
    pub since_start_ms: f64,
    /// Whether the sun turned just before this frame.
    pub turned: bool,
    /// What the world does in it.
    pub phase: Phase,
    /// Texels of light a whole relight round lights (every active level).
    pub round_texels: u64,
}

/// The arrival of each method measured: `frames` frames at `size`.
pub fn run(
    gpu: &Gpu,
    params: &WorldParams,
    size: (u32, u32),
    frames: u32,
) -> Result<Vec<ArrivalFrame>> {
    let timer = GpuTimer::new(&gpu.device, &gpu.queue);
    let land = params.land;
    let camera = |t: f64| {
        let x = t * SPEED;
        let z = 0.3 * x;
        let eye = DVec3::new(x, land.height_at(x, z) + 40.0, z);
        WorldView::look_at(
            eye,
            eye + DVec3::new(1.0, -0.08, 0.3),
            45f32.to_radians(),
            size,
        )
    };
    let mut out = Vec::new();
    // The mesh (the web's and most GPUs' pick) and the visibility method rasterised in
    // compute (a compute chip's).
    for (method, samples, raster) in [
        (Method::Mesh, 4, Raster::Hardware),
        (Method::Visibility, 1, Raster::Compute),
    ] {
        let target = Offscreen::new(&gpu.device, size.0, size.1, render_samples(method))?;
        let name = if method == Method::Mesh {
            method.to_string()
        } else {
            format!("{method} {samples} {raster}")
        };
        let start = std::time::Instant::now();
        let mut world = World::new(
            &gpu.device,
            &gpu.queue,
            Offscreen::targets(render_samples(method)),
            *params,
        )?;
        world.set_method(
            &gpu.device,
            relief::MethodConfig::new(method)
                .with_samples(samples)
                .with_raster(raster),
        )?;
        // A short run (`--quick`) runs a short day.
        let day_frames = DAY_FRAMES.min(frames / 2);
        for frame in 0..frames + 2 * day_frames {
            let turned = frame > 0 && frame == frames / 2;
            if turned {
                let mut p = *world.params();
                p.sky.sun_azimuth = (p.sky.sun_azimuth + TURN) % 360.0;
                world.set_params(&gpu.device, p)?;
            }
            let phase = match frame.checked_sub(frames) {
                None => Phase::Arrival,
                Some(k) if k < day_frames => Phase::DayStanding,
                Some(_) => Phase::DayFlying,
            };
            if frame == frames {
                let mut p = *world.params();
                p.sky = relief::day::at_time(p.sky, 9.0);
                p.sky.day_length = DAY_LENGTH;
                world.set_params(&gpu.device, p)?;
            }
            if phase != Phase::Arrival {
                world.set_time(f64::from(frame - frames) / 60.0);
            }
            // Standing: where the arrival ended; flying: on from there.
            let moving = match phase {
                Phase::Arrival => frame,
                Phase::DayStanding => frames,
                Phase::DayFlying => frame - day_frames,
            };
            let view = camera(f64::from(moving) / 60.0);
            let mut encoder = gpu.device.create_command_encoder(&Default::default());
            let t = timer.as_ref();
            let texels_baked =
                world.prepare_timed(&gpu.device, &gpu.queue, &mut encoder, &view, t)?;
            target.draw(&mut encoder, &world, wgpu::Color::BLACK, t);
            if let Some(t) = t {
                t.resolve(&mut encoder);
            }
            gpu.queue.submit([encoder.finish()]);
            gpu.device
                .poll(wgpu::PollType::wait_indefinitely())
                .map_err(|e| relief::Error::Readback(e.to_string()))?;
            let times = timer.as_ref().map(|t| t.read(&gpu.device)).transpose()?;
            let slot = |s: Slot| times.and_then(|t| t[s as usize]);
            let stats = world.stats();
            out.push(ArrivalFrame {
                method: name.clone(),
                frame,
                gpu_ms: times.map(|t| t.iter().flatten().sum()),
                bake_ms: slot(Slot::Bake),
                light_ms: slot(Slot::Light),
                shafts_ms: slot(Slot::AirShadow),
                texels_baked,
                light_texels: stats.light_texels,
                pending: world.pending_texels(),
                since_start_ms: start.elapsed().as_secs_f64() * 1e3,
                turned,
                phase,
                round_texels: {
                    let map = world.clipmap();
                    map.levels.iter().filter(|l| l.active).count() as u64
                        * u64::from(map.side()).pow(2)
                },
            });
        }
    }
    Ok(out)
}

fn opt(v: Option<f64>) -> String {
    v.map_or(String::new(), |v| format!("{v:.4}"))
}

/// The frames as CSV, with a comment line naming the device and the run.
pub fn csv(frames: &[ArrivalFrame], device: &str, size: (u32, u32)) -> String {
    let mut out = format!(
        "# relief bench --world endless: arrival, a fresh world flown through at {SPEED} m/s \
         40 m over the ground, on {device}, {}x{}, every frame from the first\n",
        size.0, size.1
    );
    out.push_str(
        "method,frame,gpu_ms,bake_ms,light_ms,shafts_ms,texels_baked,light_texels,pending,since_start_ms,sun_turned,phase\n",
    );
    for f in frames {
        out.push_str(&format!(
            "{},{},{},{},{},{},{},{},{},{:.1},{},{}\n",
            f.method,
            f.frame,
            opt(f.gpu_ms),
            opt(f.bake_ms),
            opt(f.light_ms),
            opt(f.shafts_ms),
            f.texels_baked,
            f.light_texels,
            f.pending,
            f.since_start_ms,
            u8::from(f.turned),
            f.phase.name()
        ));
    }
    out
}

/// One line a method: the first frame, when everything was baked and lit, and the worst frame.
pub fn summary(frames: &[ArrivalFrame]) -> Vec<String> {
    let mut methods: Vec<&str> = frames.iter().map(|f| f.method.as_str()).collect();
    methods.dedup();
    methods
        .into_iter()
        .map(|m| {
            let all: Vec<&ArrivalFrame> = frames.iter().filter(|f| f.method == m).collect();
            let own: Vec<&ArrivalFrame> = all
                .iter()
                .copied()
                .filter(|f| f.phase == Phase::Arrival)
                .collect();
            let ms = |v: Option<f64>| v.map_or("?".to_owned(), |v| format!("{v:.2} ms"));
            let first = own.first().map(|f| ms(f.gpu_ms)).unwrap_or_default();
            let worst = own
                .iter()
                .filter_map(|f| f.gpu_ms)
                .reduce(f64::max)
                .map_or("?".to_owned(), |v| format!("{v:.2} ms"));
            let done = own.iter().find(|f| f.pending == 0).map_or(
                format!("not within {} frames", own.len()),
                |f| format!("frame {} ({:.0} ms of wall time)", f.frame, f.since_start_ms),
            );
            // After the turn: the frames until the sun's light is whole again.
            let turn = own.iter().position(|f| f.turned);
            let relit = turn.map(|t| {
                own[t..]
                    .iter()
                    .position(|f| f.pending == 0)
                    .map_or("not relit within the run".to_owned(), |n| {
                        format!("the sun turned {TURN}°: relit over {} frames", n + 1)
                    })
            });
            let mut line = format!(
                "arrival ({m}): first frame {first} of GPU time, everything baked and lit by {done}, \
                 worst frame {worst}{}",
                relit.map_or(String::new(), |r| format!("; {r}"))
            );
            for phase in [Phase::DayStanding, Phase::DayFlying] {
                let day: Vec<&ArrivalFrame> =
                    all.iter().copied().filter(|f| f.phase == phase).collect();
                if let Some(text) = day_summary(&day) {
                    line.push_str(&format!("; {}: {text}", phase.name()));
                }
            }
            line
        })
        .collect()
}

/// The median of `v` (None when empty).
fn median(mut v: Vec<f64>) -> Option<f64> {
    v.sort_by(f64::total_cmp);
    (!v.is_empty()).then(|| v[v.len() / 2])
}

/// A running day's frames in words: the light's cost a frame (median and worst), the whole
/// frame's, and how many frames a round of relight takes at the texels a frame lights.
fn day_summary(day: &[&ArrivalFrame]) -> Option<String> {
    let light = median(day.iter().filter_map(|f| f.light_ms).collect())?;
    let worst = day.iter().filter_map(|f| f.light_ms).fold(0.0, f64::max);
    let gpu = median(day.iter().filter_map(|f| f.gpu_ms).collect()).unwrap_or(f64::NAN);
    // The shafts' map, where the frame draws them (clouds, fog): baked again each frame the
    // sun moves.
    let shafts = median(day.iter().filter_map(|f| f.shafts_ms).collect())
        .map(|m| {
            let worst = day.iter().filter_map(|f| f.shafts_ms).fold(0.0, f64::max);
            format!(", the shafts' map {m:.2} ms (worst {worst:.2})")
        })
        .unwrap_or_default();
    let texels = median(day.iter().map(|f| f.light_texels as f64).collect()).unwrap_or(0.0);
    let round = day.last().map_or(0, |f| f.round_texels) as f64;
    let frames = round / texels.max(1.0);
    // The day moves 24 h / (DAY_LENGTH s x 60 frames) a frame; shadows lag at most two rounds.
    let minutes = 2.0 * frames * 24.0 * 60.0 / (f64::from(DAY_LENGTH) * 60.0);
    Some(format!(
        "light {light:.2} ms a frame (worst {worst:.2}){shafts}, frame {gpu:.2} ms, a relight \
         round {frames:.0} frames (shadows at most {minutes:.0} min of the day behind)"
    ))
}
