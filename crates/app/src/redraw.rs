//! Drawing a frame of the window: the bake owed, `prepare`, the render pass and the
//! present, the timings and the bake's progress.

use super::*;

impl App {
    pub(super) fn redraw(&mut self) {
        if self.frame_in_flight.0 {
            // Drawn when the frame before is done (`UserEvent::FrameDone`).
            self.frame_in_flight.1 = true;
            return;
        }
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
        s.temporal = self.options.temporal;
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
                        let _ = proxy.send_event(UserEvent::Timings(frame, Box::new(r)));
                    });
                }
            }
            self.frames_on_device += 1;
            #[cfg(target_arch = "wasm32")]
            {
                self.frame_in_flight = (true, false);
                s.queue
                    .on_submitted_work_done(|| crate::web::send(UserEvent::FrameDone));
            }
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
        // waiting on a bake (over the per-frame budget) keep frames coming until they are in,
        // and a running day for as long as it runs (as `App::animating` says).
        let animating =
            crate::moving(&self.fly, &self.held, &self.path, &self.options) || s.baking();
        // A history still filling after a change (the temporal service's) keeps a few more
        // frames coming, then the window idles.
        let filling = self.fly.is_some() && self.options.temporal && self.options.method.is_mesh();
        if drawn == Drawn::Frame {
            self.settling = self.settling.saturating_sub(1);
        }
        if animating {
            self.settling = relief::temporal::INTERACTIVE_FRAMES;
        }
        let animating = animating || (filling && self.settling > 0);
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
    pub(super) fn bake_progress(&mut self, now: Instant) {
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
        // A running day: the title follows the hour (once a minute of the day).
        let hour = self.title_hour();
        if before != self.stats.baking || hour != self.shown_hour {
            self.shown_hour = hour;
            if let Some(w) = &self.window {
                w.set_title(&self.title());
            }
        }
    }
}
