//! What a frame of the endless world cost: [`WorldStats`], as `relief render --stats` prints
//! it.

/// What the last frame cost, as `relief render --stats` prints it.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct WorldStats {
    /// Triangles drawn (patches inside the frustum times their triangles).
    pub triangles: u64,
    /// Patches drawn.
    pub patches: u32,
    /// Texels baked for the last frame (four channels each): by its `prepare` and by every
    /// `encode_bake` since the frame before.
    pub texels_baked: u64,
    /// Levels drawn.
    pub levels: u32,
    /// Level count of the clipmap (drawn or not).
    pub levels_total: u32,
    /// Cells per patch side.
    pub patch_cells: u32,
    /// Spacing of the finest level drawn, metres.
    pub finest_spacing: f64,
    /// The screen-error bound of the layout, pixels.
    pub error_bound_px: f64,
    /// Texels uncovered but not baked yet (over the per-frame budget).
    pub texels_pending: u64,
    /// Texels lit for the last frame, counted as `texels_baked` is (the light bake's horizon
    /// and valley).
    pub light_texels: u64,
    /// Texels of the active levels still to be lit (over the per-frame light budget): until
    /// they are, a level is drawn with a coarser level's light.
    pub light_pending: u64,
    /// GPU memory of one level's textures (its samples and its light), bytes.
    pub level_bytes: u64,
    /// Frames the shown image accumulates with the temporal service
    /// ([`crate::World::set_temporal`]): 1 for a frame without history, up to the service's
    /// frames; 0 where the service is off or the method draws unaccumulated.
    pub history_frames: u32,
    /// Why the frame has no history (the first frame, a cut, a resize, new parameters, ...),
    /// where the service is on; `None` where it carried one.
    pub history_fresh: Option<&'static str>,
    /// With clouds ([`crate::world::clouds::Clouds::on`]): the share of the pixels whose ray
    /// crosses the layer that the frame marched (every one, every frame: 1), and the steps of
    /// each march; `None` without clouds.
    pub clouds: Option<(f64, u32)>,
}

impl WorldStats {
    /// GPU memory of every level's textures, bytes (the clipmap's arrays hold every level,
    /// drawn or not).
    pub fn texture_bytes(&self) -> u64 {
        self.level_bytes * u64::from(self.levels_total)
    }

    /// `key value` lines; with clouds `cloud_march_fraction` and `cloud_steps`; with the
    /// temporal service `history_frames` (and `history_fresh` with the reason where the frame
    /// has no history).
    pub fn lines(&self) -> Vec<String> {
        let mut lines = vec![
            format!("triangles {}", self.triangles),
            format!("patches {}", self.patches),
            format!("texels_baked {}", self.texels_baked),
            format!("texels_pending {}", self.texels_pending),
            format!("light_texels {}", self.light_texels),
            format!("light_pending {}", self.light_pending),
            format!("levels {}", self.levels),
            format!("levels_total {}", self.levels_total),
            format!("patch_cells {}", self.patch_cells),
            format!("finest_spacing_m {}", self.finest_spacing),
            format!("error_bound_px {:.3}", self.error_bound_px),
            format!("texture_mib_per_level {:.2}", mib(self.level_bytes)),
            format!("texture_mib {:.1}", mib(self.texture_bytes())),
        ];
        if let Some((marched, steps)) = self.clouds {
            lines.push(format!("cloud_march_fraction {marched}"));
            lines.push(format!("cloud_steps {steps}"));
        }
        if self.history_frames > 0 {
            lines.push(format!("history_frames {}", self.history_frames));
            if let Some(why) = self.history_fresh {
                lines.push(format!("history_fresh {}", why.replace(' ', "_")));
            }
        }
        lines
    }
}

/// Bytes to MiB.
pub fn mib(bytes: u64) -> f64 {
    bytes as f64 / f64::from(1u32 << 20)
}
