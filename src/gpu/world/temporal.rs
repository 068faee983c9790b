//! [`World`]'s temporal service: the jittered view a frame is drawn through, and the resolve
//! that blends it into the history ([`crate::temporal`] plans, [`crate::gpu::temporal`] runs).
//! Every mesh-based method uses it: the methods shaded in compute (`visibility`, `hybrid`)
//! resolve the image they shaded, the forward mesh an image of its own
//! ([`super::mesh_history`]).

use super::*;
use crate::temporal::{jitter_matrix, Temporal};

impl World {
    /// Turns the temporal service on (`temporal.frames` > 1) or off. On, each frame of the
    /// mesh-based methods (`mesh`, `visibility`, `hybrid`) is drawn through a sub-pixel jitter
    /// and blended into a history of up to `frames` frames, which is what
    /// [`World::render`] and [`World::present`] show: a still view converges to the mean of
    /// that many jittered frames, and a moving one reprojects its history (rejecting what the
    /// new frame disoccludes). New parameters, shading, method, targets or image size, and
    /// [`World::cut`], start a new history. The forward mesh then draws into an image of its
    /// own (half-precision colour and depth at the host's samples), which is resolved and
    /// composited into the host's pass as the visibility method's is. Off by default.
    ///
    /// The histories cost [`crate::temporal::history_bytes`]: 64 bytes a pixel, 127 MiB at
    /// 1920x1080, and the forward mesh's own image 60 bytes a pixel at 4 samples
    /// ([`World::method_bytes`] counts both).
    pub fn set_temporal(&mut self, device: &wgpu::Device, temporal: Temporal) -> Result<()> {
        temporal.validate()?;
        if temporal == self.temporal {
            return Ok(());
        }
        self.temporal = temporal;
        self.history.clear();
        if let Some(vis) = &mut self.visibility {
            vis.set_temporal(device, temporal.on());
        }
        self.update_mesh_history(device)
    }

    /// The temporal service's setting.
    pub fn temporal(&self) -> Temporal {
        self.temporal
    }

    /// A camera cut: the next frame starts a new history (the scene it showed is gone), and
    /// marches every pixel's clouds.
    pub fn cut(&mut self) {
        self.reset_history("cut");
    }

    /// The next frame starts a new history for `why`, and marches every pixel's clouds (what
    /// their image holds was lit, or moved, for what is gone).
    pub(super) fn reset_history(&mut self, why: &'static str) {
        self.history.reset(why);
        if let Some(vis) = &mut self.visibility {
            vis.cut_clouds();
        }
    }

    /// The sub-pixel offset, in pixels (x right, y down), the last [`World::prepare`] drew
    /// through: its [`World::relative_matrix`] is
    /// [`crate::temporal::jitter_matrix`]`(jitter, size)` times the view's own. (0, 0) where
    /// the service is off, and for a history's first frame.
    ///
    /// The resolve runs in [`World::prepare`], before the host's pass: what
    /// [`World::render`] composites is the accumulated image, with the jittered frame's
    /// depth. A host drawing its own geometry after it draws unjittered (it does not shimmer:
    /// its edges against the terrain's may move by this sub-pixel offset), or multiplies its
    /// projection by the same matrix for depth that matches the terrain's exactly
    /// (`examples/winit.rs` draws its pillar without it).
    pub fn jitter(&self) -> [f32; 2] {
        if self.temporal_active() {
            self.history.jitter
        } else {
            [0.0; 2]
        }
    }

    /// Whether frames are accumulated: the service on and the method's passes built.
    pub(super) fn temporal_active(&self) -> bool {
        self.temporal.on()
            && match self.method {
                Method::Visibility | Method::Hybrid => self.visibility.is_some(),
                Method::Mesh => self.mesh_history.is_some(),
                _ => false,
            }
    }

    /// `view` as the next frame draws it: through the history's next jitter where the
    /// service is active, else itself.
    pub(super) fn jittered(&self, view: &WorldView) -> WorldView {
        if !self.temporal_active() {
            return *view;
        }
        let size = self.target_size.unwrap_or(view.size);
        let jitter = self.history.next_jitter(size);
        WorldView {
            crop: jitter_matrix(jitter, size) * view.crop,
            ..*view
        }
    }

    /// The clouds' step offset for the next frame (`cloud_march.z`): the next jitter's x
    /// (a base-2 radical inverse) moved to [0, 1), so successive frames march the clouds at
    /// offsets that fill the step between them evenly; 0.5 where the service is inactive.
    pub(super) fn cloud_offset(&self, size: (u32, u32)) -> f32 {
        if !self.temporal_active() {
            return 0.5;
        }
        let size = self.target_size.unwrap_or(size);
        (self.history.next_jitter(size)[0] + 0.5).fract()
    }

    /// Plans the frame just shaded (drawn from `view` jittered) and records its resolve.
    pub(super) fn encode_resolve(
        &mut self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        view: &WorldView,
        timer: Option<&GpuTimer>,
    ) {
        if !self.temporal_active() {
            self.stats.history_frames = 0;
            self.stats.history_fresh = None;
            return;
        }
        let size = self.vis_size;
        let jitter = self.history.next_jitter(size);
        let (near, far) = self.near_far;
        let unjittered = view.relative_matrix(near, far).as_dmat4();
        let step = self
            .history
            .advance(jitter, unjittered, (view.eye, self.clock(), size));
        let cap = self.temporal.frames;
        match (&mut self.mesh_history, &mut self.visibility) {
            (Some(mesh), _) if self.method == Method::Mesh => {
                mesh.resolve(queue, encoder, (&step, cap), timer);
            }
            (_, Some(vis)) => vis.resolve(queue, encoder, (&step, cap), timer),
            _ => {}
        }
        self.stats.history_frames = self.history.frames(cap);
        self.stats.history_fresh = self.history.fresh;
    }
}
