//! The interactive window, shared by the native program and the web page: a winit app that
//! hosts [`Terrain`](crate::Terrain) exactly as any embedding app would. Drag (or one finger)
//! orbits, the wheel (or a pinch) zooms, Space pauses the scroll, R re-seeds, Escape quits
//! (native). In the endless world ([`crate::World`]) a fly camera moves instead: WASD or the
//! arrows, Q/E down and up, Shift faster, drag to look, wheel for speed, P for the path.
//!
//! It draws only when something changed (input, the scroll animation, a parameter, a resize):
//! a paused, untouched window or tab costs next to nothing, and its readout says it is idle.
//! A lost GPU device is reported in one line and recovered once (new device, textures and
//! pipelines); a second loss ends the app with that line.
//!
//! Only the edges differ by platform: native creates the device by blocking, the web
//! asynchronously (`web.rs`), and each reports to its user its own way ([`Report`]).

mod options;
mod pacer;
mod state;
#[cfg(target_arch = "wasm32")]
pub mod web;

pub use options::{url_keys, AppOptions, Ignored, OFFSET_STEPS, OPTIONS, SCROLL_SPEED};
pub use state::{Drawn, State};

use crate::error::{Error, Result};
use crate::gpu::timing::{Slot, Timings};
use crate::{FlyCamera, OrbitCamera, PathCamera};
use std::collections::{HashMap, HashSet};
use std::sync::Arc;
use web_time::{Duration, Instant};
use winit::application::ApplicationHandler;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, TouchPhase, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoopProxy};
use winit::keyboard::{Key, KeyCode, NamedKey, PhysicalKey};
use winit::window::{Window, WindowId};

/// Depth format of the window's depth buffer.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// MSAA samples of the window's target for the mesh, the same as `relief render`, so both show
/// the same picture; the visibility method and the hybrid draw into a single-sampled target, as
/// `relief render` does too ([`crate::gpu::render_samples`]).
pub const SAMPLES: u32 = crate::gpu::RENDER_SAMPLES;
/// How long without a new frame before the readout says the window is idle.
pub const IDLE_AFTER: Duration = Duration::from_millis(500);
/// Least time between two timed frames, so each printed timing is a new measurement.
pub const TIMING_INTERVAL: Duration = Duration::from_millis(250);
/// Height the orbit camera keeps above the terrain (world units; the tile is 2 wide).
pub const CAMERA_CLEARANCE: f32 = 0.05;
/// Height the fly camera keeps above the endless world's ground, metres.
pub const FLY_CLEARANCE: f64 = 2.0;

/// The endless world's sun, fog and water keys: `[` `]` turn the sun, `-` `=` lower and raise
/// it, `f` turns the fog off and on again, `l` the water (lakes).
pub const SKY_KEYS: [&str; 6] = ["[", "]", "-", "=", "f", "l"];

/// The [`SKY_KEYS`] that move the sun: held, they keep moving it.
const SUN_KEYS: [&str; 4] = ["[", "]", "-", "="];

/// Whether a held key acts again on each of its repeats: only the sun keys do. A toggle or a
/// step (fog, water, method, path, pause, seed) acts once a press.
fn acts_on_repeat(key: &Key) -> bool {
    matches!(key, Key::Character(c) if SUN_KEYS.contains(&c.as_str()))
}

/// Keys that move the fly camera (by position on the keyboard: WASD, arrows, Q/E and Page
/// Down/Up for down and up, Shift for faster).
pub const FLY_KEYS: [KeyCode; 14] = [
    KeyCode::KeyW,
    KeyCode::KeyA,
    KeyCode::KeyS,
    KeyCode::KeyD,
    KeyCode::KeyQ,
    KeyCode::KeyE,
    KeyCode::ArrowUp,
    KeyCode::ArrowDown,
    KeyCode::ArrowLeft,
    KeyCode::ArrowRight,
    KeyCode::PageUp,
    KeyCode::PageDown,
    KeyCode::ShiftLeft,
    KeyCode::ShiftRight,
];

/// Events the app receives besides winit's.
pub enum UserEvent {
    /// The GPU state finished initialising (the web creates it asynchronously).
    Ready(Result<Box<State>>),
    /// The page changed a parameter.
    Set(String, String),
    /// GPU timestamps of a timed frame came back.
    Timings(u64, Result<Timings>),
    /// The GPU device was lost (the reason, in words).
    DeviceLost(String),
    /// wgpu reported an error nobody captured.
    GpuError(String),
}

/// Whether a wgpu error is only the echo of a lost device (which is reported on its own).
fn after_loss(message: &str) -> bool {
    let m = message.to_ascii_lowercase();
    m.contains("destroyed") || m.contains("lost")
}

/// Frame statistics reported to the front end.
#[derive(Clone, Copy, Debug, Default)]
pub struct Stats {
    /// Frames drawn so far.
    pub frames: u64,
    /// Frames per second over the last half second of drawing.
    pub fps: f64,
    /// Latest GPU pass times, when the adapter has timestamps, and the frame they measured.
    pub gpu: Option<(u64, Timings)>,
    /// Whether this adapter can time passes at all.
    pub timestamps: bool,
    /// Nothing changed for [`IDLE_AFTER`]: no frames are being drawn.
    pub idle: bool,
    /// How the last frame was drawn.
    pub method: crate::Method,
    /// The visibility method's and the hybrid's samples a pixel and raster in the last frame.
    pub samples: u32,
    /// ... and where they rasterised.
    pub raster: crate::Raster,
    /// CPU time of a frame on the app's side (input, animation, recording and submitting the
    /// GPU work; not the GPU's time, nor the wait for the surface's next texture and its
    /// present), mean over the frames of the last half second, ms.
    pub cpu_ms: Option<f64>,
    /// While the endless world's levels or their light are still being baked (over the
    /// per-frame budgets, coarse levels first), how far along, in percent.
    pub baking: Option<u32>,
}

/// What the app tells its user, one way per platform: native prints lines, the page writes
/// into its DOM.
pub trait Report {
    /// The readout changed (frame rate, GPU times, idle).
    fn stats(&mut self, describe: &str, stats: &Stats, fresh_timings: bool);
    /// A one-line notice (a recovered device).
    fn notice(&mut self, message: &str);
    /// A one-line error the app keeps running after.
    fn warn(&mut self, message: &str);
    /// A change the user asked for took effect: a previous refusal no longer applies.
    fn accepted(&mut self) {}
    /// The parameters changed (the page updates its URL and controls).
    fn options(&mut self, _options: &AppOptions) {}
    /// The method was chosen (`relief --method auto`): `choice`, and `line`, which says why.
    fn chosen(&mut self, _choice: &crate::choice::Choice, _line: &str) {}
    /// A frame was presented.
    fn frame(&mut self, _stats: &Stats) {}
    /// A bake that took several frames is done: `ms` and `frames` since it began, and the
    /// longest time between two of its frames (ms).
    fn baked(&mut self, _ms: f64, _frames: u64, _longest_ms: f64) {}
    /// The app stopped on an error.
    fn fatal(&mut self, message: &str);
}

/// The native window's report: with `--timings`, one line per new GPU measurement, a line
/// when the window goes idle, and a summary at exit; warnings and errors as one line each on
/// stderr.
#[cfg(not(target_arch = "wasm32"))]
pub struct Terminal {
    /// Whether `--timings` was given.
    pub timings: bool,
}

#[cfg(not(target_arch = "wasm32"))]
impl Terminal {
    /// A report printing timings if asked.
    pub fn new(timings: bool) -> Self {
        Self { timings }
    }
}

#[cfg(not(target_arch = "wasm32"))]
impl Report for Terminal {
    fn stats(&mut self, describe: &str, stats: &Stats, fresh_timings: bool) {
        if !self.timings {
            return;
        }
        if fresh_timings {
            if let Some((frame, t)) = stats.gpu {
                // The method is named where it is not the mesh, with its samples and raster
                // where it has them.
                let method = match stats.method {
                    crate::Method::Mesh => String::new(),
                    m @ (crate::Method::Visibility | crate::Method::Hybrid) => {
                        let c = crate::choice::Candidate {
                            method: m,
                            samples: stats.samples,
                            raster: stats.raster,
                        };
                        format!(", {c}")
                    }
                    m => format!(", {m}"),
                };
                // The app's own CPU time a frame, beside the GPU's passes.
                let cpu = stats
                    .cpu_ms
                    .map_or(String::new(), |ms| format!(" · cpu {ms:.2} ms/frame"));
                println!(
                    "timings on {describe} (frame {frame}{method}): {}{cpu}",
                    format_timings(&t)
                );
            }
        } else if stats.idle {
            println!(
                "idle after frame {}: nothing changes, so nothing is drawn",
                stats.frames
            );
        }
    }
    fn notice(&mut self, message: &str) {
        eprintln!("{}", one_line(message));
    }
    fn warn(&mut self, message: &str) {
        eprintln!("{}", one_line(&format!("warning: {message}")));
    }
    fn baked(&mut self, ms: f64, frames: u64, longest_ms: f64) {
        if self.timings {
            println!(
                "baked: every level and its light in {ms:.0} ms over {frames} frames, the \
                 longest {longest_ms:.0} ms apart (from the start: the first frame's wait)"
            );
        }
    }
    fn chosen(&mut self, choice: &crate::choice::Choice, line: &str) {
        // With --timings the whole line, as `relief render` prints it; else which, in short.
        let c = choice.candidate;
        if self.timings {
            println!("{line}");
        } else if choice.why == crate::choice::Why::NoTimestamps {
            eprintln!(
                "relief: drawing with {c} ({}): nothing could be measured (no GPU timestamps)",
                c.flags()
            );
        } else {
            eprintln!(
                "relief: drawing with {c} ({}), the fastest measured; --timings says why",
                c.flags()
            );
        }
    }
    fn frame(&mut self, _stats: &Stats) {}
    fn fatal(&mut self, _message: &str) {
        // The CLI prints the error the app returns.
    }
}

#[cfg(not(target_arch = "wasm32"))]
fn one_line(message: &str) -> String {
    crate::table::shorten_to(
        &message.split_whitespace().collect::<Vec<_>>().join(" "),
        200,
    )
}

/// Options for driving the window from scripts and tests.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Script {
    /// Close the window after this many seconds.
    pub exit_after: Option<f64>,
    /// Destroy the GPU device after this many frames drawn on it, as a driver reset would
    /// (tests the recovery, and giving up when the new device is lost too).
    pub lose_device_after: Option<u64>,
}

/// The winit application: input, animation, and the frame loop around [`State`].
pub struct App {
    options: AppOptions,
    script: Script,
    camera: OrbitCamera,
    /// The fly camera, when the window shows the endless world.
    fly: Option<FlyCamera>,
    /// Movement keys held down (fly camera).
    held: HashSet<KeyCode>,
    /// On the fly-through path, and the time along it (endless world, P toggles).
    path: Option<(PathCamera, f64)>,
    drag: Option<(f64, f64)>,
    cursor: (f64, f64),
    touches: HashMap<u64, (f64, f64)>,
    last_tick: Instant,
    last_frame: Instant,
    last_timed: Option<Instant>,
    timing_in_flight: bool,
    fps_window: (Instant, u64),
    /// CPU milliseconds and frames drawn since the last readout ([`Stats::cpu_ms`]).
    cpu_window: (f64, u64),
    started: Instant,
    stats: Stats,
    state: Option<State>,
    window: Option<Arc<Window>>,
    starting: bool,
    recoveries: u32,
    surface_losses: u32,
    lost_reason: String,
    frames_on_device: u64,
    error: Option<Error>,
    report: Box<dyn Report>,
    proxy: EventLoopProxy<UserEvent>,
    /// The fog the F key turns back on.
    fog_off: f32,
    /// The endless world's per-frame bake budgets, scaled to the device's pace.
    pacer: pacer::Pacer,
    /// How far the bake in progress has come.
    progress: pacer::Progress,
    /// When the bake in progress began, the frames drawn then, and the longest time between
    /// two of its frames so far (ms).
    baking_since: Option<(Instant, u64, f64)>,
    /// The last frame drawn: its interval from the one before (ms), whether it baked, and the
    /// texels still waiting after it.
    last_bake: Option<(f64, bool, u64)>,
}

impl App {
    /// A new app; the window opens when the event loop resumes.
    pub fn new(
        options: AppOptions,
        script: Script,
        report: Box<dyn Report>,
        proxy: EventLoopProxy<UserEvent>,
    ) -> Self {
        let now = Instant::now();
        Self {
            options,
            script,
            camera: OrbitCamera::default(),
            fly: options.world.map(|(_, fly)| fly),
            held: HashSet::new(),
            path: (options.world.is_some() && options.path)
                .then(|| (PathCamera::default(), options.path_time)),
            drag: None,
            cursor: (0.0, 0.0),
            touches: HashMap::new(),
            last_tick: now,
            last_frame: now,
            last_timed: None,
            timing_in_flight: false,
            fps_window: (now, 0),
            cpu_window: (0.0, 0),
            started: now,
            stats: Stats::default(),
            state: None,
            window: None,
            starting: false,
            recoveries: 0,
            surface_losses: 0,
            lost_reason: String::new(),
            frames_on_device: 0,
            error: None,
            report,
            proxy,
            fog_off: crate::sky::Sky::default().fog,
            pacer: pacer::Pacer::default(),
            progress: pacer::Progress::default(),
            baking_since: None,
            last_bake: None,
        }
    }

    /// The error that ended the app, if any.
    pub fn take_error(&mut self) -> Option<Error> {
        self.error.take()
    }

    fn fail(&mut self, event_loop: &ActiveEventLoop, e: Error) {
        log::debug!("{e}");
        self.report.fatal(&e.to_string());
        self.error = Some(e);
        self.state = None;
        event_loop.exit();
    }

    /// Something visible changed: draw a frame (only then; see the module docs).
    fn changed(&mut self) {
        if self.stats.idle {
            self.stats.idle = false;
            let describe = self
                .state
                .as_ref()
                .map(|s| s.describe.clone())
                .unwrap_or_default();
            self.report.stats(&describe, &self.stats, false);
        }
        if let Some(w) = &self.window {
            w.request_redraw();
        }
    }

    fn set(&mut self, key: &str, value: &str) -> Result<()> {
        let mut options = self.options;
        options.set(key, value)?;
        if let Some(s) = &mut self.state {
            match (&mut s.world, options.world) {
                // Unchanged parameters (a new method, say) keep the levels as they are.
                (Some(world), Some((params, _))) if world.params() == &params => {}
                (Some(world), Some((params, _))) => world.set_params(&s.device, params)?,
                _ => {
                    s.terrain
                        .set_params(&s.device, &s.queue, options.params)
                        .map(|_| ())?;
                }
            }
        }
        self.options = options;
        if let Some(w) = &self.window {
            w.set_title(&self.title());
        }
        self.keep_camera_above();
        self.report.options(&self.options);
        self.report.accepted();
        self.changed();
        Ok(())
    }

    /// Whether frames must keep coming: the tile scrolling, or the fly camera moving.
    fn animating(&self) -> bool {
        // Levels still waiting on a bake (over the per-frame budget) need more frames.
        let baking = self.state.as_ref().is_some_and(|s| match &s.world {
            Some(w) => w.pending_texels() > 0,
            None => s.terrain.pending_texels() > 0,
        });
        baking
            || match self.fly {
                Some(_) => !self.held.is_empty() || self.path.is_some(),
                None => self.options.animating(),
            }
    }

    fn keep_camera_above(&mut self) {
        if let (Some(fly), Some((world, _))) = (&mut self.fly, &self.options.world) {
            let land = world.land;
            // The world is drawn within this reach of the origin.
            let reach = crate::clipmap::max_eye(&land);
            fly.eye.x = fly.eye.x.clamp(-reach, reach);
            fly.eye.z = fly.eye.z.clamp(-reach, reach);
            fly.keep_above(|x, z| land.height_at(x, z), FLY_CLEARANCE);
            return;
        }
        let params = self.options.params;
        let half = crate::WORLD_SIZE as f32 / 2.0;
        self.camera.keep_above(
            |x, z| {
                if x.abs() <= half && z.abs() <= half {
                    crate::height_at(&params, x, z)
                } else {
                    0.0
                }
            },
            CAMERA_CLEARANCE,
        );
    }

    fn start_state(&mut self, event_loop: &ActiveEventLoop, window: Arc<Window>) {
        self.starting = true;
        let instance =
            wgpu::Instance::new(wgpu::InstanceDescriptor::new_with_display_handle_from_env(
                Box::new(event_loop.owned_display_handle()),
            ));
        let future = State::new(
            window,
            instance,
            self.options.params,
            self.options.world.map(|(w, _)| w),
            self.options.timings,
            self.proxy.clone(),
        );
        #[cfg(not(target_arch = "wasm32"))]
        {
            let result = pollster::block_on(future).map(Box::new);
            self.user_event(event_loop, UserEvent::Ready(result));
        }
        #[cfg(target_arch = "wasm32")]
        {
            let proxy = self.proxy.clone();
            wasm_bindgen_futures::spawn_local(async move {
                let _ = proxy.send_event(UserEvent::Ready(future.await.map(Box::new)));
            });
        }
    }

    fn ready(&mut self, mut state: State) {
        self.starting = false;
        // What changed while the device was being made (a control, the page's URL) applies
        // now; what this device cannot do (a size over its limit) is said and undone.
        if let Err(e) = state
            .terrain
            .set_params(&state.device, &state.queue, self.options.params)
        {
            self.report
                .warn(&format!("{e}; using size {}", state.terrain.params().size));
            self.options.params = *state.terrain.params();
        }
        self.frames_on_device = 0;
        self.stats.timestamps = state.timer.is_some();
        self.timing_in_flight = false;
        if self.options.timings && state.timer.is_none() {
            self.report.warn(&format!(
                "timings: {} has no timestamp queries",
                state.describe
            ));
        }
        if self.recoveries > 0 {
            self.report.notice(&format!(
                "recovered: drawing on a new GPU device ({})",
                state.describe
            ));
        }
        // `--method auto`: chosen on this device before the first frame (once: a new device
        // after a loss draws what was chosen).
        #[cfg(not(target_arch = "wasm32"))]
        if self.options.auto {
            self.choose(&mut state);
        }
        let drawn = crate::choice::Candidate {
            method: self.options.method,
            samples: self.options.samples,
            raster: self.options.raster,
        };
        if let Err(e) = state.use_candidate(drawn) {
            self.report.warn(&e.to_string());
        }
        self.state = Some(state);
        self.last_tick = Instant::now();
        self.keep_camera_above();
        self.report.options(&self.options);
        self.changed();
    }

    /// Chooses the method as `relief render --method auto` does
    /// ([`crate::gpu::headless::choose_method`]): a few frames of each candidate of the world
    /// shown, at the window's size, into offscreen targets; the mesh where that fails.
    #[cfg(not(target_arch = "wasm32"))]
    fn choose(&mut self, state: &mut State) {
        use crate::gpu::headless::{choose_method, Gpu, TrialScene};
        self.options.auto = false;
        let world = if state.world.is_some() {
            crate::WorldKind::Endless
        } else {
            crate::WorldKind::Tile
        };
        self.report.notice(&format!(
            "relief: measuring {} methods on {} before the first frame (--method pins one)",
            crate::choice::Candidate::all(world).len(),
            state.describe
        ));
        let gpu = Gpu {
            adapter: state.adapter.clone(),
            device: state.device.clone(),
            queue: state.queue.clone(),
        };
        let size = (state.config.width, state.config.height);
        let chosen = match (&mut state.world, &self.fly) {
            (Some(world), Some(fly)) => {
                let view = fly.view(size);
                choose_method(&gpu, TrialScene::Endless(world, &view))
            }
            _ => {
                let view = self.camera.view(state.aspect());
                choose_method(&gpu, TrialScene::Tile(&mut state.terrain, &view, size))
            }
        };
        let candidate = match chosen {
            Ok(choice) => {
                self.report
                    .chosen(&choice, &choice.describe(&state.describe));
                choice.candidate
            }
            Err(e) => {
                self.report.warn(&format!(
                    "choosing the method failed ({e}); drawing the mesh"
                ));
                crate::choice::Candidate::MESH
            }
        };
        self.options.method = candidate.method;
        self.options.samples = candidate.samples;
        self.options.raster = candidate.raster;
        if let Some(w) = &self.window {
            w.set_title(&self.title());
        }
    }

    fn device_lost(&mut self, event_loop: &ActiveEventLoop, reason: String) {
        if self.state.is_none() && !self.starting {
            return; // already handled (the callback can fire once per device)
        }
        if self.recoveries >= 1 {
            return self.fail(
                event_loop,
                Error::DeviceLost(format!(
                    "{reason}; lost again after one recovery, so relief stopped"
                )),
            );
        }
        self.recoveries += 1;
        self.lost_reason = reason.clone();
        self.report.warn(&format!(
            "GPU device lost ({reason}); creating a new device, textures and pipelines"
        ));
        // Drop the old surface before making a new one for the same window.
        self.state = None;
        if let Some(window) = self.window.clone() {
            self.start_state(event_loop, window);
        }
    }

    fn redraw(&mut self) {
        let now = Instant::now();
        let dt = now.duration_since(self.last_tick).as_secs_f64().min(0.25);
        self.last_tick = now;
        if let (Some(fly), Some((path, t)), Some((world, _))) =
            (&mut self.fly, &mut self.path, &self.options.world)
        {
            // Following the path: it sets the camera; the keys wait until P lets go of it.
            *t = (*t + dt).min(PathCamera::MAX_TIME);
            let land = world.land;
            let (eye, target) = path.at(|x, z| land.height_at(x, z), *t);
            *fly = FlyCamera {
                speed: fly.speed,
                ..FlyCamera::looking_at(eye, target, fly.fov_y)
            };
        } else if let Some(fly) = &mut self.fly {
            let key = |k: &[KeyCode]| f64::from(u8::from(k.iter().any(|k| self.held.contains(k))));
            let ahead =
                key(&[KeyCode::KeyW, KeyCode::ArrowUp]) - key(&[KeyCode::KeyS, KeyCode::ArrowDown]);
            let right = key(&[KeyCode::KeyD, KeyCode::ArrowRight])
                - key(&[KeyCode::KeyA, KeyCode::ArrowLeft]);
            let up =
                key(&[KeyCode::KeyE, KeyCode::PageUp]) - key(&[KeyCode::KeyQ, KeyCode::PageDown]);
            let boost = if key(&[KeyCode::ShiftLeft, KeyCode::ShiftRight]) > 0.0 {
                4.0
            } else {
                1.0
            };
            fly.fly(ahead, right, up, boost, dt);
            self.keep_camera_above();
        } else if self.options.animating() {
            let mut options = self.options;
            options.advance(dt);
            // The scroll moves where the textures are read: nothing is baked while it runs
            // (pausing, or any other change, bakes the offset reached exactly).
            let result = match &mut self.state {
                Some(s) => s.terrain.scroll_to(options.params.offset),
                None => Ok(()),
            };
            match result {
                Ok(()) => {
                    self.options = options;
                    // The ground moves under the camera as it scrolls.
                    self.keep_camera_above();
                }
                Err(e) => self.report.warn(&format!("scroll refused: {e}")),
            }
        }
        let Some(s) = &mut self.state else { return };
        let timed = s.timer.is_some()
            && !self.timing_in_flight
            && self
                .last_timed
                .is_none_or(|t| now.duration_since(t) >= TIMING_INTERVAL);
        let view = self.camera.view(s.aspect());
        self.stats.method = self.options.method;
        self.stats.samples = self.options.samples;
        self.stats.raster = self.options.raster;
        if let Some(world) = &mut s.world {
            // The water's ripples move on while frames come (an idle window draws none).
            world.set_time(self.started.elapsed().as_secs_f64());
            let (heights, light) = self.pacer.budgets();
            world.set_bake_budget(heights);
            world.set_light_budget(light);
        }
        let drawn = s.draw(&view, self.fly.as_ref(), timed, self.options.method);
        if drawn == Drawn::SurfaceLost {
            self.surface_losses += 1;
            // Lost again before a frame could be drawn on the new surface: start over with a
            // new device (the same path as a lost device) rather than retrying forever.
            let result = if self.surface_losses > 1 {
                Err(Error::Device(
                    "the window's surface was lost twice in a row".into(),
                ))
            } else {
                self.report
                    .warn("the window's surface was lost; creating it again");
                s.recreate_surface()
            };
            if let Err(e) = result {
                let _ = self.proxy.send_event(UserEvent::DeviceLost(e.to_string()));
            }
            return;
        }
        if drawn == Drawn::Frame {
            // Waiting on the surface is the GPU's pace, not the app's work.
            let busy = now.elapsed().saturating_sub(s.waited);
            self.cpu_window.0 += busy.as_secs_f64() * 1e3;
            self.cpu_window.1 += 1;
            self.surface_losses = 0;
            self.stats.frames += 1;
            let interval_ms = now.duration_since(self.last_frame).as_secs_f64() * 1e3;
            self.last_bake = Some(match &s.world {
                Some(w) => {
                    let st = w.stats();
                    let baked = st.texels_baked + st.light_texels > 0;
                    (interval_ms, baked, w.pending_texels())
                }
                None => (interval_ms, false, s.terrain.pending_texels()),
            });
            self.last_frame = now;
            if timed {
                self.timing_in_flight = true;
                self.last_timed = Some(now);
                let proxy = self.proxy.clone();
                let frame = self.stats.frames;
                if let Some(t) = &s.timer {
                    t.read_async(move |r| {
                        let _ = proxy.send_event(UserEvent::Timings(frame, r));
                    });
                }
            }
            self.frames_on_device += 1;
            if self
                .script
                .lose_device_after
                .is_some_and(|n| self.frames_on_device == n)
            {
                s.device.destroy();
                let _ = s.device.poll(wgpu::PollType::Poll);
            }
        }
        // A minimised window is not drawn until it is restored (a resize event). Levels
        // waiting on a bake (over the per-frame budget) keep frames coming until they are in.
        let animating = match self.fly {
            Some(_) => !self.held.is_empty() || self.path.is_some(),
            None => self.options.animating(),
        } || match &s.world {
            Some(w) => w.pending_texels() > 0,
            None => s.terrain.pending_texels() > 0,
        };
        if animating && !s.minimised() {
            s.window.request_redraw();
        }
        let (t0, f0) = self.fps_window;
        let span = now.duration_since(t0).as_secs_f64();
        if span >= 0.5 {
            self.stats.fps = (self.stats.frames - f0) as f64 / span;
            self.fps_window = (now, self.stats.frames);
            let (cpu, drawn) = std::mem::take(&mut self.cpu_window);
            if drawn > 0 {
                self.stats.cpu_ms = Some(cpu / drawn as f64);
            }
            let describe = s.describe.clone();
            self.report.stats(&describe, &self.stats, false);
            if let (Some(fly), Some((_, camera))) = (&self.fly, &mut self.options.world) {
                // The moving camera reaches the URL twice a second.
                if *camera != *fly || self.options.path != self.path.is_some() {
                    *camera = *fly;
                    self.options.path = self.path.is_some();
                    self.options.path_time = self.path.map_or(0.0, |(_, t)| t);
                    self.report.options(&self.options);
                }
            } else if self.options.animating() {
                // The scrolling offset reaches the URL twice a second.
                self.report.options(&self.options);
            }
        }
        self.bake_progress(now);
        self.report.frame(&self.stats);
    }

    /// After a frame: paces the next frame's bake, and says how far the bake has come (in the
    /// title, the page's readout, and once done with `--timings`).
    fn bake_progress(&mut self, now: Instant) {
        let Some((interval_ms, baked, pending)) = self.last_bake.take() else {
            return;
        };
        if self.stats.frames > 1 {
            self.pacer.frame(interval_ms, baked);
        }
        let before = self.stats.baking;
        self.stats.baking = self.progress.update(pending);
        match (before, self.stats.baking) {
            // The first bake counts from the app's start (the device, pipelines and the first
            // frame included): the wait a user sees on arrival.
            (None, Some(_)) if self.stats.frames <= 1 => {
                let first_ms = now.duration_since(self.started).as_secs_f64() * 1e3;
                self.baking_since = Some((self.started, 0, first_ms));
            }
            (None, Some(_)) => self.baking_since = Some((now, self.stats.frames, 0.0)),
            (Some(_), _) => {
                if let Some((_, _, longest)) = &mut self.baking_since {
                    *longest = longest.max(interval_ms);
                }
                if self.stats.baking.is_none() {
                    if let Some((t0, f0, longest)) = self.baking_since.take() {
                        let ms = now.duration_since(t0).as_secs_f64() * 1e3;
                        self.report.baked(ms, self.stats.frames - f0, longest);
                    }
                }
            }
            _ => {}
        }
        if before != self.stats.baking {
            if let Some(w) = &self.window {
                w.set_title(&self.title());
            }
        }
    }

    fn touch(&mut self, id: u64, phase: TouchPhase, x: f64, y: f64) {
        let before = self.touches.clone();
        match phase {
            TouchPhase::Started | TouchPhase::Moved => {
                self.touches.insert(id, (x, y));
            }
            TouchPhase::Ended | TouchPhase::Cancelled => {
                self.touches.remove(&id);
            }
        }
        let height = self
            .state
            .as_ref()
            .map_or(720.0, |s| f64::from(s.config.height.max(1)));
        match (before.len(), self.touches.len()) {
            (1, 1) if phase == TouchPhase::Moved => {
                if let Some(&(x0, y0)) = before.get(&id) {
                    let k = std::f64::consts::PI / height;
                    self.camera
                        .rotate(((x - x0) * k) as f32, ((y - y0) * k) as f32);
                    self.camera_moved();
                }
            }
            (2, 2) => {
                let dist = |t: &HashMap<u64, (f64, f64)>| {
                    let v: Vec<_> = t.values().collect();
                    ((v[0].0 - v[1].0).powi(2) + (v[0].1 - v[1].1).powi(2)).sqrt()
                };
                let (d0, d1) = (dist(&before), dist(&self.touches));
                if d0 > 1.0 && d1 > 1.0 {
                    // Spreading two fingers by 10% zooms one notch.
                    self.camera.zoom(((d1 / d0).ln() / 1.1f64.ln()) as f32);
                    self.camera_moved();
                }
            }
            _ => {}
        }
    }

    /// R in the endless world: the next seed.
    fn reseed_world(&mut self) {
        let Some((mut world, fly)) = self.options.world else {
            return;
        };
        world.land.seed = world.land.seed.wrapping_add(1);
        if let Some(s) = &mut self.state {
            if let Some(w) = &mut s.world {
                if let Err(e) = w.set_params(&s.device, world) {
                    self.report.warn(&e.to_string());
                    return;
                }
            }
        }
        self.options.world = Some((world, fly));
        self.keep_camera_above();
        self.changed();
    }

    /// One of [`SKY_KEYS`], through the same keys as the page's controls, so the URL follows.
    fn sky_key(&mut self, key: &str) {
        let Some((world, _)) = self.options.world else {
            return;
        };
        let sky = world.sky;
        let (name, value) = match key {
            "[" | "]" => {
                let turn = if key == "[" { -10.0 } else { 10.0 };
                ("sun_azimuth", (sky.sun_azimuth + turn).rem_euclid(360.0))
            }
            "-" | "=" => {
                let lift = if key == "-" { -2.0 } else { 2.0 };
                (
                    "sun_elevation",
                    (sky.sun_elevation + lift).clamp(-90.0, 90.0),
                )
            }
            "l" => ("no_water", if world.no_water { 0.0 } else { 1.0 }),
            _ if sky.fog > 0.0 => {
                self.fog_off = sky.fog;
                ("fog", 0.0)
            }
            _ => ("fog", self.fog_off),
        };
        if let Err(e) = self.set(name, &value.to_string()) {
            self.report.warn(&e.to_string());
        }
    }

    /// The window's title: the method drawing (M changes it) and the world's key values: in
    /// the endless one the seed, the sun and the fog, on the tile the seed and octaves.
    fn title(&self) -> String {
        let o = &self.options;
        let method = match o.method {
            m @ (crate::Method::Visibility | crate::Method::Hybrid) => crate::choice::Candidate {
                method: m,
                samples: o.samples,
                raster: o.raster,
            }
            .to_string(),
            m => m.name().to_owned(),
        };
        let method = if o.auto && self.state.is_none() {
            "auto".to_owned()
        } else {
            method
        };
        let baking = self
            .stats
            .baking
            .map_or(String::new(), |p| format!(" · baking {p}%"));
        match &o.world {
            Some((w, _)) => format!(
                "relief: {method} (M){baking} · seed {} · sun {:.0}° az, {:.0}° up · fog {} /km · water {} · [ ] - = move the sun, F fog, L water",
                w.land.seed,
                w.sky.sun_azimuth,
                w.sky.sun_elevation,
                w.sky.fog,
                if w.no_water { "off" } else { "on" }
            ),
            None => format!(
                "relief: {method} (M){baking} · seed {} · octaves {} · frequency {}",
                o.params.seed, o.params.octaves, o.params.frequency
            ),
        }
    }

    fn camera_moved(&mut self) {
        self.keep_camera_above();
        self.changed();
    }
}

/// "bake 0.186 ms, normals 0.016 ms, render 1.103 ms" for the passes that ran.
pub fn format_timings(t: &Timings) -> String {
    Slot::ALL
        .iter()
        .filter_map(|&s| t[s as usize].map(|ms| format!("{} {ms:.3} ms", s.name())))
        .collect::<Vec<_>>()
        .join(", ")
}

impl ApplicationHandler<UserEvent> for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.window.is_some() || self.starting {
            return;
        }
        let attributes = Window::default_attributes().with_title(self.title());
        #[cfg(not(target_arch = "wasm32"))]
        let attributes = attributes.with_inner_size(winit::dpi::LogicalSize::new(1280, 720));
        #[cfg(target_arch = "wasm32")]
        let attributes = web::window_attributes(attributes);
        let window = match event_loop.create_window(attributes) {
            Ok(w) => Arc::new(w),
            Err(e) => {
                return self.fail(
                    event_loop,
                    Error::Window(format!("cannot create a window: {e}")),
                )
            }
        };
        self.window = Some(window.clone());
        self.start_state(event_loop, window);
    }

    fn user_event(&mut self, event_loop: &ActiveEventLoop, event: UserEvent) {
        match event {
            UserEvent::Ready(Ok(state)) => self.ready(*state),
            UserEvent::Ready(Err(e)) if self.recoveries > 0 => self.fail(
                event_loop,
                Error::DeviceLost(format!(
                    "{}; a new device could not be made ({e}), so relief stopped",
                    self.lost_reason
                )),
            ),
            UserEvent::Ready(Err(e)) => self.fail(event_loop, e),
            UserEvent::Set(k, v) => {
                if let Err(e) = self.set(&k, &v) {
                    // The page shows the value that is in force again, and why.
                    self.report.options(&self.options);
                    self.report.warn(&e.to_string());
                }
            }
            UserEvent::Timings(frame, result) => {
                self.timing_in_flight = false;
                match result {
                    Ok(t) => {
                        self.stats.gpu = Some((frame, t));
                        let describe = self
                            .state
                            .as_ref()
                            .map(|s| s.describe.clone())
                            .unwrap_or_default();
                        self.report.stats(&describe, &self.stats, true);
                    }
                    Err(e) if after_loss(&e.to_string()) => log::debug!("timings: {e}"),
                    Err(e) => self.report.warn(&format!("timings: {e}")),
                }
            }
            UserEvent::DeviceLost(reason) => self.device_lost(event_loop, reason),
            UserEvent::GpuError(e) if after_loss(&e) => log::debug!("wgpu: {e}"),
            UserEvent::GpuError(e) => self.report.warn(&format!("wgpu: {e}")),
        }
    }

    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        let now = Instant::now();
        if let Some(limit) = self.script.exit_after {
            if now.duration_since(self.started).as_secs_f64() >= limit {
                event_loop.exit();
                return;
            }
        }
        // Native timestamp reads complete inside Device::poll.
        #[cfg(not(target_arch = "wasm32"))]
        if self.timing_in_flight {
            if let Some(s) = &self.state {
                let _ = s.device.poll(wgpu::PollType::Poll);
            }
        }
        let mut wake = None;
        if !self.animating() && !self.stats.idle && self.state.is_some() {
            let idle_at = self.last_frame + IDLE_AFTER;
            if now >= idle_at {
                self.stats.idle = true;
                self.stats.fps = 0.0;
                let describe = self
                    .state
                    .as_ref()
                    .map(|s| s.describe.clone())
                    .unwrap_or_default();
                self.report.stats(&describe, &self.stats, false);
            } else {
                wake = Some(idle_at);
            }
        }
        if self.timing_in_flight {
            wake = Some(now + Duration::from_millis(5));
        }
        if let Some(limit) = self.script.exit_after {
            let end = self.started + Duration::from_secs_f64(limit);
            wake = Some(wake.map_or(end, |w: Instant| w.min(end)));
        }
        event_loop.set_control_flow(match wake {
            Some(t) => ControlFlow::WaitUntil(t),
            None => ControlFlow::Wait,
        });
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::Resized(size) => {
                if let Some(s) = &mut self.state {
                    s.resize(size.width, size.height);
                }
                self.changed();
            }
            WindowEvent::ScaleFactorChanged { .. } | WindowEvent::Occluded(false) => self.changed(),
            WindowEvent::KeyboardInput { event, .. }
                if self.fly.is_some()
                    && matches!(event.physical_key, PhysicalKey::Code(c) if FLY_KEYS.contains(&c)) =>
            {
                if let PhysicalKey::Code(code) = event.physical_key {
                    let was = self.animating();
                    if event.state == ElementState::Pressed {
                        self.held.insert(code);
                    } else {
                        self.held.remove(&code);
                    }
                    if !was && self.animating() {
                        self.last_tick = Instant::now();
                    }
                    self.changed();
                }
            }
            WindowEvent::Focused(false) => {
                // Keys released while another window had the focus never arrive.
                self.held.clear();
            }
            WindowEvent::KeyboardInput { event, .. } if event.state == ElementState::Pressed => {
                // A held key repeats (the X server starts repeating after ~0.6 s, and a loaded
                // machine can delay a tap's release that long): the sun keys keep turning the
                // sun, but a toggle or a step (fog, water, method, path, pause, seed) acts once
                // a press, or holding it would flicker.
                if event.repeat && !acts_on_repeat(&event.logical_key) {
                    return;
                }
                match event.logical_key {
                    #[cfg(not(target_arch = "wasm32"))]
                    Key::Named(NamedKey::Escape) => event_loop.exit(),
                    Key::Named(NamedKey::Space) if self.fly.is_some() => {}
                    Key::Character(c) if c.eq_ignore_ascii_case("p") && self.fly.is_some() => {
                        // Onto the path from its start, or off it where the camera is.
                        self.path = match self.path {
                            Some(_) => None,
                            None => Some((PathCamera::default(), 0.0)),
                        };
                        self.last_tick = Instant::now();
                        self.changed();
                    }
                    Key::Character(c) if c.eq_ignore_ascii_case("r") && self.fly.is_some() => {
                        self.reseed_world();
                    }
                    Key::Character(c)
                        if self.fly.is_some() && SKY_KEYS.contains(&c.to_lowercase().as_str()) =>
                    {
                        self.sky_key(&c.to_lowercase());
                    }
                    Key::Character(c) if c.eq_ignore_ascii_case("m") => {
                        // The next method this world draws (the reference is slow).
                        let all = crate::Method::ALL;
                        let at = all
                            .iter()
                            .position(|&m| m == self.options.method)
                            .unwrap_or(0);
                        let next = (1..=all.len())
                            .map(|k| all[(at + k) % all.len()])
                            .find(|m| {
                                if self.fly.is_some() {
                                    m.in_world()
                                } else {
                                    m.in_tile()
                                }
                            })
                            .unwrap_or_default();
                        if let Err(e) = self.set("method", next.name()) {
                            self.report.warn(&e.to_string());
                        }
                    }
                    Key::Named(NamedKey::Space) => {
                        let paused = if self.options.paused { "0" } else { "1" };
                        if let Err(e) = self.set("paused", paused) {
                            self.report.warn(&e.to_string());
                        }
                        self.last_tick = Instant::now();
                    }
                    Key::Character(c) if c.eq_ignore_ascii_case("r") => {
                        let seed = self.options.params.seed.wrapping_add(1).to_string();
                        if let Err(e) = self.set("seed", &seed) {
                            self.report.warn(&e.to_string());
                        }
                    }
                    _ => {}
                }
            }
            WindowEvent::MouseInput {
                state,
                button: MouseButton::Left,
                ..
            } => {
                self.drag = (state == ElementState::Pressed).then_some(self.cursor);
            }
            WindowEvent::CursorMoved { position, .. } => {
                self.cursor = (position.x, position.y);
                if let (Some((x0, y0)), Some(s), Some(fly)) =
                    (self.drag, &self.state, &mut self.fly)
                {
                    let k = f64::from(fly.fov_y) / f64::from(s.config.height.max(1));
                    fly.turn((position.x - x0) * k, (position.y - y0) * k);
                    self.drag = Some(self.cursor);
                    self.changed();
                } else if let (Some((x0, y0)), Some(s)) = (self.drag, &self.state) {
                    let k = std::f64::consts::PI / f64::from(s.config.height.max(1));
                    self.camera.rotate(
                        ((position.x - x0) * k) as f32,
                        ((position.y - y0) * k) as f32,
                    );
                    self.drag = Some(self.cursor);
                    self.camera_moved();
                }
            }
            WindowEvent::MouseWheel { delta, .. } => {
                let steps = match delta {
                    MouseScrollDelta::LineDelta(_, y) => y,
                    MouseScrollDelta::PixelDelta(p) => (p.y / 60.0) as f32,
                };
                match &mut self.fly {
                    Some(fly) => fly.change_speed(f64::from(steps)),
                    None => {
                        self.camera.zoom(steps);
                        self.camera_moved();
                    }
                }
            }
            WindowEvent::Touch(t) => self.touch(t.id, t.phase, t.location.x, t.location.y),
            WindowEvent::RedrawRequested => self.redraw(),
            _ => {}
        }
    }
}

/// Why no window can open here, if the reason is plain: no display server to connect to.
#[cfg(not(target_arch = "wasm32"))]
fn no_display() -> Option<String> {
    if !cfg!(any(
        target_os = "linux",
        target_os = "freebsd",
        target_os = "openbsd"
    )) {
        return None;
    }
    let set = |v| std::env::var_os(v).is_some_and(|s| !s.is_empty());
    (!set("DISPLAY") && !set("WAYLAND_DISPLAY"))
        .then(|| "no display to open a window on (DISPLAY and WAYLAND_DISPLAY are unset)".into())
}

/// What to suggest when the window cannot open.
#[cfg(not(target_arch = "wasm32"))]
pub const NO_WINDOW_HINT: &str =
    "without a display, draw a frame with: relief render --out frame.png";

/// Opens the native window and runs until it is closed.
#[cfg(not(target_arch = "wasm32"))]
pub fn run_native(options: AppOptions, script: Script) -> Result<()> {
    if let Some(why) = no_display() {
        return Err(Error::Window(format!("{why}; {NO_WINDOW_HINT}")));
    }
    let event_loop = winit::event_loop::EventLoop::<UserEvent>::with_user_event()
        .build()
        .map_err(|e| {
            // winit's message carries the source file it came from; keep what it says.
            let text = e.to_string();
            let said = text.rsplit(": ").next().unwrap_or(&text).to_owned();
            Error::Window(format!("cannot open a window ({said}); {NO_WINDOW_HINT}"))
        })?;
    let proxy = event_loop.create_proxy();
    let mut app = App::new(
        options,
        script,
        Box::new(Terminal::new(options.timings)),
        proxy,
    );
    event_loop
        .run_app(&mut app)
        .map_err(|e| Error::Window(format!("the window's event loop failed: {e}")))?;
    if options.timings {
        println!(
            "window: {} frames drawn in {:.1} s",
            app.stats.frames,
            app.started.elapsed().as_secs_f64()
        );
    }
    match app.take_error() {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_the_sun_keys_act_on_a_held_keys_repeats() {
        for k in SUN_KEYS {
            assert!(acts_on_repeat(&Key::Character(k.into())), "{k}");
        }
        for k in ["f", "F", "l", "m", "M", "p", "r"] {
            assert!(!acts_on_repeat(&Key::Character(k.into())), "{k}");
        }
        assert!(!acts_on_repeat(&Key::Named(NamedKey::Space)));
    }
}
