//! The interactive window, shared by the native program and the web page: a winit app that
//! hosts [`Terrain`](relief::Terrain) exactly as any embedding app would. Drag (or one finger)
//! orbits, the wheel (or a pinch) zooms, Space pauses the scroll, R re-seeds, Escape quits
//! (native). In the endless world ([`relief::World`]) a fly camera moves instead: WASD or the
//! arrows, Q/E down and up, Shift faster, drag to look, wheel for speed, P for the path.
//!
//! It draws only when something changed (input, the scroll animation, a parameter, a resize):
//! a paused, untouched window or tab costs next to nothing, and its readout says it is idle.
//! A lost GPU device is reported in one line and recovered once (new device, textures and
//! pipelines); a second loss ends the app with that line.
//!
//! Only the edges differ by platform: native creates the device by blocking, the web
//! asynchronously (`web.rs`), and each reports to its user its own way ([`Report`]).

mod day;
mod events;
#[cfg(not(target_arch = "wasm32"))]
mod native;
mod options;
mod pacer;
mod redraw;
mod report;
mod state;
#[cfg(target_arch = "wasm32")]
pub mod web;

#[cfg(not(target_arch = "wasm32"))]
pub use self::native::*;
pub use self::report::*;
pub use options::{url_keys, AppOptions, Ignored, OFFSET_STEPS, OPTIONS, SCROLL_SPEED, TEMPORAL};
pub use state::{Drawn, State};

use relief::error::{Error, Result};
use relief::gpu::timing::{Slot, Timings};
use relief::{FlyCamera, OrbitCamera, PathCamera};
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
/// `relief render` does too ([`relief::gpu::render_samples`]).
pub const SAMPLES: u32 = relief::gpu::RENDER_SAMPLES;
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
pub const SKY_KEYS: [&str; 8] = ["[", "]", "-", "=", "f", "l", "g", "c"];

/// The clouds' coverage C turns on (off: 0).
pub const CLOUD_KEY_COVERAGE: f32 = 0.5;

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
    /// GPU timestamps of a timed frame came back (boxed: a slot a pass, they are the
    /// largest event).
    Timings(u64, Box<Result<Timings>>),
    /// The GPU device was lost (the reason, in words).
    DeviceLost(String),
    /// wgpu reported an error nobody captured.
    GpuError(String),
    /// The GPU finished the work of the frame last submitted (the web paces frames by it).
    FrameDone,
}

/// Whether the view moves by itself or by the user's hand, so that frames must keep coming:
/// the tile scrolling (no fly camera), a key held, the path followed, or the day running. With
/// [`State::baking`], what [`App::animating`] and the redraw ask (the redraw while it holds
/// the state, hence the fields one by one).
fn moving(
    fly: &Option<FlyCamera>,
    held: &HashSet<KeyCode>,
    path: &Option<(PathCamera, f64)>,
    options: &options::AppOptions,
) -> bool {
    match fly {
        Some(_) => !held.is_empty() || path.is_some() || day::day_runs(options),
        None => options.animating(),
    }
}

/// Whether a wgpu error is only the echo of a lost device (which is reported on its own).
fn after_loss(message: &str) -> bool {
    let m = message.to_ascii_lowercase();
    m.contains("destroyed") || m.contains("lost")
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
    /// On the web: a frame's work is still on the GPU, and whether a redraw came meanwhile
    /// (drawn once it is done). A page that asked for frames faster than a software GPU draws
    /// them had its thread held for seconds by the browser.
    frame_in_flight: (bool, bool),
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
    /// Frames still to draw after the last change so that the temporal service's history
    /// fills (a still view converges over [`relief::temporal::INTERACTIVE_FRAMES`] frames).
    settling: u32,
    lost_reason: String,
    frames_on_device: u64,
    error: Option<Error>,
    report: Box<dyn Report>,
    proxy: EventLoopProxy<UserEvent>,
    /// The fog the F key turns back on.
    fog_off: f32,
    /// The hour the title shows (" at 14:05", or empty): a running day's title follows it.
    shown_hour: String,
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
            frame_in_flight: (false, false),
            fps_window: (now, 0),
            cpu_window: (0.0, 0),
            started: now,
            stats: Stats::default(),
            state: None,
            window: None,
            starting: false,
            recoveries: 0,
            surface_losses: 0,
            settling: 0,
            lost_reason: String::new(),
            frames_on_device: 0,
            error: None,
            report,
            proxy,
            fog_off: relief::sky::Sky::default().fog,
            shown_hour: String::new(),
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
        self.settling = relief::temporal::INTERACTIVE_FRAMES;
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
        self.keep_the_day(&mut options, key)?;
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
        // Grass with a ray caster: said, not silently missing.
        if let Some((world, _)) = &self.options.world {
            let method = self.options.method;
            if world.grass.on && method.ray_path().is_some() {
                self.report.notice(&format!(
                    "grass: the {method} casts rays, which draw no grass here (M: a mesh-based \
                     method draws it; relief render --method reference draws the grass's \
                     reference)"
                ));
            }
            // Props with a ray caster: said, not silently missing.
            if world.props.on && method.ray_path().is_some() {
                self.report.notice(&format!(
                    "props: the {method} casts rays, which march no props here (M: a \
                     mesh-based method draws them; relief render --method reference draws \
                     the props' reference)"
                ));
            }
        }
        self.changed();
        Ok(())
    }

    /// Whether frames must keep coming: levels waiting on a bake, the tile scrolling, the fly
    /// camera moving, or the day running.
    fn animating(&self) -> bool {
        self.state.as_ref().is_some_and(State::baking)
            || moving(&self.fly, &self.held, &self.path, &self.options)
    }

    fn keep_camera_above(&mut self) {
        if let (Some(fly), Some((world, _))) = (&mut self.fly, &self.options.world) {
            let land = world.land;
            // The world is drawn within this reach of the origin.
            let reach = relief::clipmap::max_eye(&land);
            fly.eye.x = fly.eye.x.clamp(-reach, reach);
            fly.eye.z = fly.eye.z.clamp(-reach, reach);
            fly.keep_above(|x, z| land.height_at(x, z), FLY_CLEARANCE);
            return;
        }
        let params = self.options.params;
        let half = relief::WORLD_SIZE as f32 / 2.0;
        self.camera.keep_above(
            |x, z| {
                if x.abs() <= half && z.abs() <= half {
                    relief::height_at(&params, f64::from(x), f64::from(z)) as f32
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
            let result = relief::gpu::headless::block_on(future).map(Box::new);
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
        self.frame_in_flight = (false, false);
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
        let drawn = relief::choice::Candidate {
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
        // On the page, the first frame waits until the GPU process has built the pipelines
        // just made: a frame submitted behind them is not shown before they are (seconds on a
        // software GPU), and the browser may hold the page's thread meanwhile.
        #[cfg(target_arch = "wasm32")]
        if let Some(s) = &mut self.state {
            s.configure(self.options.method, self.fly.is_some());
            self.frame_in_flight = (true, true);
            self.report.preparing();
            s.queue
                .on_submitted_work_done(|| crate::web::send(UserEvent::FrameDone));
        }
    }

    /// Chooses the method as `relief render --method auto` does
    /// ([`relief::gpu::headless::choose_method`]): a few frames of each candidate of the world
    /// shown, at the window's size, into offscreen targets; the mesh where that fails.
    #[cfg(not(target_arch = "wasm32"))]
    fn choose(&mut self, state: &mut State) {
        use relief::gpu::headless::{choose_method, Gpu, TrialScene};
        self.options.auto = false;
        let world = if state.world.is_some() {
            relief::WorldKind::Endless
        } else {
            relief::WorldKind::Tile
        };
        // With props, the method that draws their shadows, unmeasured (as `relief render`).
        let props = state.world.as_ref().is_some_and(|w| w.params().props.on);
        if let Some(c) = relief::choice::Candidate::for_props(props) {
            self.report.notice(&format!(
                "relief: props are on: drawing them with {c}, the method that marches them \
                 with their shadows (--method pins another)"
            ));
            self.options.method = c.method;
            self.options.samples = c.samples;
            self.options.raster = c.raster;
            if let Some(w) = &self.window {
                w.set_title(&self.title());
            }
            return;
        }
        self.report.notice(&format!(
            "relief: measuring {} methods on {} before the first frame (--method pins one)",
            relief::choice::Candidate::all(world).len(),
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
                relief::choice::Candidate::MESH
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
        let Some(sky) = self.sky_now() else {
            return;
        };
        if SUN_KEYS.contains(&key) && world.sky.day_length > 0.0 {
            // A sun moved by hand stops the day where it stands, then moves.
            self.day_key();
        }
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
            "g" => ("no_grass", if world.grass.on { 1.0 } else { 0.0 }),
            "c" if world.clouds.on() => ("cloud_coverage", 0.0),
            "c" => ("cloud_coverage", CLOUD_KEY_COVERAGE),
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
            m @ (relief::Method::Visibility | relief::Method::Hybrid) => {
                relief::choice::Candidate {
                    method: m,
                    samples: o.samples,
                    raster: o.raster,
                }
                .to_string()
            }
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
                "relief: {method} (M){baking} · seed {} · sun {:.0}° az, {:.0}° up{} · fog {} /km · water {} · grass {} · clouds {} · history {} (T) · [ ] - = move the sun, N run the day, F fog, L water, G grass, C clouds",
                w.land.seed,
                self.sky_now().unwrap_or(w.sky).sun_azimuth,
                self.sky_now().unwrap_or(w.sky).sun_elevation,
                self.title_hour(),
                w.sky.fog,
                if w.no_water { "off" } else { "on" },
                if w.grass.on { "on" } else { "off" },
                if w.clouds.on() { "on" } else { "off" },
                if o.temporal { "on" } else { "off" }
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
