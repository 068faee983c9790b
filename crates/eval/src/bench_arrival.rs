//! `relief bench --world endless`'s arrival: what a user waits through on reaching the endless
//! world and flying on. A fresh world (nothing baked, nothing lit) seen from a camera flying at
//! [`SPEED`] 40 m over the ground, frame by frame at 60 frames a second from the first, with
//! no warm-up: each frame's GPU time (the height bake, the light bake and the draw, from
//! timestamps), the texels it baked and lit, and what still waits; halfway, the sun turns by
//! [`TURN`] degrees (a slider or a key: every level relit). The core's default per-frame
//! budgets ([`relief::gpu::world::DEFAULT_BAKE_BUDGET`],
//! [`relief::gpu::world::DEFAULT_LIGHT_BUDGET`]) are what a GPU's window reaches.

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
        for frame in 0..frames {
            let turned = frame > 0 && frame == frames / 2;
            if turned {
                let mut p = *world.params();
                p.sky.sun_azimuth = (p.sky.sun_azimuth + TURN) % 360.0;
                world.set_params(&gpu.device, p)?;
            }
            let view = camera(f64::from(frame) / 60.0);
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
                texels_baked,
                light_texels: stats.light_texels,
                pending: world.pending_texels(),
                since_start_ms: start.elapsed().as_secs_f64() * 1e3,
                turned,
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
        "method,frame,gpu_ms,bake_ms,light_ms,texels_baked,light_texels,pending,since_start_ms,sun_turned\n",
    );
    for f in frames {
        out.push_str(&format!(
            "{},{},{},{},{},{},{},{},{:.1},{}\n",
            f.method,
            f.frame,
            opt(f.gpu_ms),
            opt(f.bake_ms),
            opt(f.light_ms),
            f.texels_baked,
            f.light_texels,
            f.pending,
            f.since_start_ms,
            u8::from(f.turned)
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
            let own: Vec<&ArrivalFrame> = frames.iter().filter(|f| f.method == m).collect();
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
            format!(
                "arrival ({m}): first frame {first} of GPU time, everything baked and lit by {done}, \
                 worst frame {worst}{}",
                relit.map_or(String::new(), |r| format!("; {r}"))
            )
        })
        .collect()
}
