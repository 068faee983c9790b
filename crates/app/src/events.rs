//! The window's events: winit's [`ApplicationHandler`] for [`App`] (keys, resizes, redraws,
//! the device's loss, the scripted exit).

use super::*;

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
                match *result {
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
            UserEvent::FrameDone => {
                let owed = self.frame_in_flight.1;
                self.frame_in_flight = (false, false);
                if let (true, Some(s)) = (owed, &self.state) {
                    s.window.request_redraw();
                }
            }
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
                    Key::Character(c) if c.eq_ignore_ascii_case("n") && self.fly.is_some() => {
                        self.day_key();
                    }
                    Key::Character(c) if c.eq_ignore_ascii_case("t") && self.fly.is_some() => {
                        let off = if self.options.temporal { "1" } else { "0" };
                        if let Err(e) = self.set("no_temporal", off) {
                            self.report.warn(&e.to_string());
                        }
                    }
                    Key::Character(c) if c.eq_ignore_ascii_case("m") => {
                        // The next method this world draws (the reference is slow).
                        let all = relief::Method::ALL;
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
