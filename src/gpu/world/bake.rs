//! [`World`]'s bakes: moving the levels with the eye, the height bake of what they uncovered
//! and the light bake, each within its per-frame budget.

use super::*;

impl World {
    pub(super) fn relayout(&mut self, device: &wgpu::Device, k: f64) -> Result<()> {
        let morphing = self.map.morphing;
        let map = layout(&self.params, &self.errors, k);
        let (texture, target, light) = scoped(device, || {
            let (texture, target) = level_texture(device, &self.bake, &map);
            let light = LevelLight::new(device, &self.light_bake, &texture, &map);
            (texture, target, light)
        })?;
        if map.patch != self.map.patch {
            (self.indices, self.index_counts) = patch_indices(device, &map);
        }
        self.light = light;
        self.texture = texture;
        self.rebind(device);
        self.bake_target = target;
        self.map = map;
        self.map.morphing = morphing;
        self.map_k = k;
        Ok(())
    }

    pub(super) fn eye(&self, view: &WorldView) -> Eye {
        Eye {
            position: view.eye.to_array(),
            ground: self.params.land.height_at(view.eye.x, view.eye.z),
            pixels_per_radian: view.pixels_per_radian(),
        }
    }

    /// Most texels one [`World::encode_bake`] bakes ([`DEFAULT_BAKE_BUDGET`] to start).
    pub fn bake_budget(&self) -> u64 {
        self.bake_budget
    }

    /// Sets the per-frame bake budget in texels (at least one row of a strip, and whatever the
    /// coarsest level needs to be drawn, are always baked;
    /// `u64::MAX` bakes everything at once, as the headless renderer does for a still frame).
    pub fn set_bake_budget(&mut self, texels: u64) {
        self.bake_budget = texels.max(1);
    }

    /// Most texels one [`World::encode_bake`] lights ([`DEFAULT_LIGHT_BUDGET`] to start).
    pub fn light_budget(&self) -> u64 {
        self.light_budget
    }

    /// Sets the per-frame light budget in texels (at least one row of a level is lit a frame,
    /// so the light always moves on); `u64::MAX` lights everything at once, as the headless
    /// renderer does for a still frame.
    pub fn set_light_budget(&mut self, texels: u64) {
        self.light_budget = texels.max(1);
    }

    /// The reference ray cast's slope bounds for this world's landscape, measured once
    /// ([`Landscape::slope_bounds`]): what a host casting rays every frame passes to
    /// [`crate::gpu::world_rays::WorldRayUniforms::with_slopes`].
    pub fn slope_bounds(&self) -> &[f64] {
        &self.slopes
    }

    /// Texels still to bake: heights uncovered but not baked yet (a level with some is not
    /// drawn: the next coarser level covers it) and light not baked yet ([`World::light_pending`]:
    /// a level without is drawn with a coarser level's light). Later frames bake them, within
    /// the per-frame budgets; a host keeps drawing frames while this is over 0.
    pub fn pending_texels(&self) -> u64 {
        self.heights_pending() + self.light_pending()
    }

    /// Texels whose heights are uncovered but not baked yet.
    pub(super) fn heights_pending(&self) -> u64 {
        let region: u64 = self
            .region_pending
            .iter()
            .map(|r| u64::from(r.extent[0]) * u64::from(r.extent[1]))
            .sum();
        self.map.pending_texels() + region
    }

    /// Texels of the active levels still to be lit (missing their light, or lit for an earlier
    /// sun): 0 where nothing reads the light.
    pub fn light_pending(&self) -> u64 {
        if self.tile.is_some()
            || (self.params.no_shadows && self.params.palette == crate::palette::Palette::Blog)
        {
            return 0;
        }
        self.light.queue.pending_texels(&self.map)
    }

    /// Texels the levels hold baked for their current layout: every active level's window (cut
    /// to the tile's square) less what still waits. For a still frame baked whole this is its
    /// whole bake, the same whatever the method or an earlier frame baked (`relief render
    /// --stats` prints it as `texels_baked`).
    pub fn held_texels(&self) -> u64 {
        let side = self.map.side();
        let bounds = self.tile.map(|t| t.region);
        let held: u64 = self
            .map
            .levels
            .iter()
            .filter(|l| l.active)
            .filter_map(|level| {
                let window = Rect {
                    layer: level.layer,
                    level_log2: level.spacing_log2,
                    origin: level.origin,
                    extent: [side; 2],
                };
                match bounds {
                    Some(b) => crop(window, b),
                    None => Some(window),
                }
            })
            .map(|r| u64::from(r.extent[0]) * u64::from(r.extent[1]))
            .sum();
        held.saturating_sub(self.heights_pending())
    }

    /// Moves the levels to `view` and records the bake of whatever they uncovered (nothing if
    /// the camera stayed within its levels' snapping step), within the per-frame budget
    /// ([`World::set_bake_budget`]; what is over it waits for the next frames), into the host's
    /// encoder, and the light bake within its own budget. Records no frame work: a host that
    /// draws calls [`World::prepare`], which bakes too. A view whose pixels per radian differ
    /// much from the layout's re-lays out the levels first (new textures, everything
    /// re-baked). Returns the texels baked.
    pub fn encode_bake(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        view: &WorldView,
    ) -> Result<u64> {
        self.encode_bake_timed(device, queue, encoder, view, None)
    }

    /// [`World::encode_bake`], timing the bake pass (when there is one) into `timer`.
    pub fn encode_bake_timed(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        view: &WorldView,
        timer: Option<&GpuTimer>,
    ) -> Result<u64> {
        let k = view.pixels_per_radian();
        if !(k.is_finite() && k > 0.0 && view.eye.is_finite()) {
            return Err(Error::invalid(
                "view",
                format!("{:?}", view.eye),
                "a finite eye and field of view",
            ));
        }
        let reach = crate::clipmap::max_eye(&self.params.land);
        if view.eye.x.abs() > reach || view.eye.z.abs() > reach || view.eye.y.abs() > 1e9 {
            return Err(Error::invalid(
                "eye",
                format!("{:.0},{:.0},{:.0}", view.eye.x, view.eye.y, view.eye.z),
                format!(
                    "x and z within ±{reach:.0} m (2^30 of this world's finest samples), y within ±1e9 m"
                ),
            ));
        }
        if self.frame_prepared {
            // The first bake since a frame: the counts are the next frame's.
            self.frame_prepared = false;
            self.stats.texels_baked = 0;
            self.stats.light_texels = 0;
        }
        let patch = Clipmap::patch_for(&self.errors, self.params.pixel_error, k);
        if patch != self.map.patch {
            self.relayout(device, k)?;
        }
        let eye = self.eye(view);
        self.map.update(&eye, self.params.pixel_error);
        // Never a frame with nothing to draw: the coarsest level is baked whole at once.
        let coarsest = self.map.levels.len() - 1;
        let budget = self.bake_budget.max(self.map.pending_texels_of(coarsest));
        let strips = self.map.take(budget, crate::gpu::landscape::MAX_RECTS);
        let bounds = self.tile.map(|t| t.region);
        let rects: Vec<Rect> = strips
            .iter()
            .map(|s| Rect {
                layer: self.map.levels[s.level].layer,
                level_log2: self.map.levels[s.level].spacing_log2,
                origin: s.origin,
                extent: s.extent,
            })
            .filter_map(|r| match bounds {
                Some(b) => crop(r, b),
                None => Some(r),
            })
            .collect();
        self.region_moved();
        let rects = self.with_region_pending(rects);
        if !rects.is_empty() {
            self.bake.encode(
                queue,
                encoder,
                &self.bake_target,
                &self.params.land,
                &rects,
                timer.map(|t| t.compute_writes(Slot::Bake)),
            );
        }
        self.encode_light(queue, encoder, &strips, timer);
        let texels = rects
            .iter()
            .map(|r| u64::from(r.extent[0]) * u64::from(r.extent[1]))
            .sum();
        self.stats.texels_baked += texels;
        self.stats.texels_pending = self.map.pending_texels();
        Ok(texels)
    }

    /// The tile's: where its square moved (the scroll) since the last bake, the parts of every
    /// level's window the new square reaches and the old one did not. Those texels were cut
    /// from earlier bakes ([`crop`]), so the square's moving uncovers them as the camera's
    /// moving uncovers a level's strips.
    /// They join the world's pending rectangles, baked as the per-pass slots allow.
    pub(super) fn region_moved(&mut self) {
        let Some(tile) = self.tile else {
            return;
        };
        let old = self.baked_region.replace(tile.region);
        let Some(old) = old.filter(|o| *o != tile.region) else {
            return;
        };
        let side = self.map.side();
        for level in self.map.levels.iter().filter(|l| l.active) {
            let window = Rect {
                layer: level.layer,
                level_log2: level.spacing_log2,
                origin: level.origin,
                extent: [side; 2],
            };
            if let Some(new) = crop(window, tile.region) {
                self.region_pending.extend(subtract(new, crop(window, old)));
            }
        }
    }

    /// `rects` and as many of the square's pending rectangles as one pass's slots still hold,
    /// each cut to its level's window now (a level may have moved since: what left the window
    /// is not its to bake any more).
    pub(super) fn with_region_pending(&mut self, mut rects: Vec<Rect>) -> Vec<Rect> {
        let side = f64::from(self.map.side());
        while rects.len() < crate::gpu::landscape::MAX_RECTS {
            let Some(r) = self.region_pending.pop() else {
                break;
            };
            let Some(level) = self
                .map
                .levels
                .iter()
                .find(|l| l.active && l.layer == r.layer)
            else {
                continue;
            };
            let s = 2f64.powi(level.spacing_log2);
            let (x, z) = (f64::from(level.origin[0]), f64::from(level.origin[1]));
            let window = [x * s, z * s, (x + side - 1.0) * s, (z + side - 1.0) * s];
            if let Some(kept) = crop_exact(r, window) {
                rects.push(kept);
            }
        }
        rects
    }

    /// Records the light bake after the levels' bake, within the per-frame light budget
    /// ([`World::set_light_budget`]): the strips just baked join what the levels still need
    /// lit (every level whole where the sun has turned or nothing was lit), and the frame
    /// lights what the budget allows, coarsest level first ([`LightQueue`]).
    pub(super) fn encode_light(
        &mut self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        strips: &[crate::clipmap::Strip],
        timer: Option<&GpuTimer>,
    ) {
        let azimuth = self.sky().sun_azimuth;
        if self.tile.is_some()
            || (self.params.no_shadows && self.params.palette == crate::palette::Palette::Blog)
        {
            // Nothing reads the light: no shadows, and the blog palette's occlusion is by
            // height. Lit whole once something does.
            self.light.queue.forget();
            return;
        }
        let n = self.map.levels.len();
        let usable: Vec<bool> = (0..n)
            .map(|l| self.map.levels[l].active && self.map.pending_texels_of(l) == 0)
            .collect();
        self.light.queue.set_sun(azimuth);
        self.light.queue.heights_baked(strips);
        let rects: Vec<LightRect> = self
            .light
            .queue
            .take(
                &self.map,
                self.light_budget,
                crate::gpu::world_light::MAX_LIGHT_RECTS,
                |l| usable[l],
            )
            .into_iter()
            .map(|s| LightRect {
                origin: s.origin,
                extent: s.extent,
                level: s.level as u32,
                _pad: [0; 3],
            })
            .collect();
        self.stats.light_texels += rects
            .iter()
            .map(|r| u64::from(r.extent[0]) * u64::from(r.extent[1]))
            .sum::<u64>();
        if rects.is_empty() {
            return;
        }
        // One pass: its uniforms are written once for the submission (`take` keeps to the
        // pass's rectangle slots).
        let uniforms = LightUniforms::new(&self.map, azimuth, &self.params.land, |l| usable[l]);
        self.light_bake.encode(
            queue,
            encoder,
            &self.light.bind_group,
            &uniforms,
            &rects,
            timer.map(|t| t.compute_writes(Slot::Light)),
        );
    }
}
