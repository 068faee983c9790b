//! The temporal service's plan, on the CPU: the sub-pixel jitter sequence, whether a frame
//! keeps the history (and why not), and the matrix that carries a pixel of this frame to where
//! it was in the last one. The GPU's half, the history images and the resolve pass, is
//! `src/gpu/temporal.rs` and `wgsl/temporal.wgsl`.
//!
//! A frame drawn with the service is drawn through a jittered projection
//! ([`jitter_matrix`]); the resolve blends it into the history: where the view has not
//! changed, as the running mean of up to [`Temporal::frames`] frames (a still view converges
//! to the mean of that many jittered frames, which is the pixel's box filter); where the view
//! moved, each pixel's history is fetched where that point was (the terrain does not move:
//! its motion is the camera's), kept only where the depth there agrees and clamped into the
//! range of this frame's 3x3 neighbourhood, so what was hidden and is now seen (a
//! disocclusion) takes the new frame.

use glam::{DMat4, DVec3, Mat4};

/// How a [`crate::World`] accumulates frames over time ([`crate::World::set_temporal`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Temporal {
    /// Frames a pixel's history holds at most: a still view converges to the mean of this
    /// many jittered frames, a moving one blends each new frame in at 1/`frames` or more. 1:
    /// off (one unjittered frame, as without the service).
    pub frames: u32,
}

impl Temporal {
    /// Off: each frame stands alone, unjittered (the library's default).
    pub const OFF: Self = Self { frames: 1 };
    /// What the window and the page draw with.
    pub const INTERACTIVE: Self = Self {
        frames: INTERACTIVE_FRAMES,
    };

    /// Whether frames accumulate.
    pub fn on(self) -> bool {
        self.frames > 1
    }

    /// Refuses a count outside `1..=`[`MAX_FRAMES`].
    pub fn validate(self) -> crate::Result<()> {
        if !(1..=MAX_FRAMES).contains(&self.frames) {
            return Err(crate::Error::invalid(
                "frames",
                self.frames,
                format!("1..={MAX_FRAMES} (1: no accumulation)"),
            ));
        }
        Ok(())
    }
}

impl Default for Temporal {
    fn default() -> Self {
        Self::OFF
    }
}

/// [`Temporal::frames`] of the window and the page.
pub const INTERACTIVE_FRAMES: u32 = 16;

/// The most frames a history holds.
pub const MAX_FRAMES: u32 = 4096;

/// GPU memory of a world's histories for frames of `size`, bytes: two of each (one read, one
/// written), each 32 bytes a pixel (premultiplied colour and coverage in 32-bit floats, so a
/// 256-frame mean keeps every frame's share; the neighbourhood's nearest and farthest clip w
/// and the frame count).
pub fn history_bytes(size: (u32, u32)) -> u64 {
    2 * 32 * u64::from(size.0) * u64::from(size.1)
}

/// The jitter repeats after this many frames (past [`MAX_FRAMES`]: a still view's mean never
/// counts a position twice).
const JITTER_PERIOD: u32 = 8192;

/// The `i`-th element of the van der Corput sequence in `base`, in [0, 1).
fn radical_inverse(mut i: u32, base: u32) -> f32 {
    let (mut f, mut r) = (1.0f64, 0.0f64);
    while i > 0 {
        f /= f64::from(base);
        r += f * f64::from(i % base);
        i /= base;
    }
    r as f32
}

/// The sub-pixel offset, in pixels (x right, y down, each in [-0.5, 0.5)), of the frame
/// `index` frames after the history began: 0 for the first (a fresh frame is the frame
/// without the service), then the Halton sequence in bases 2 and 3 about the pixel's centre.
pub fn jitter(index: u32) -> [f32; 2] {
    if index == 0 {
        return [0.0; 2];
    }
    let i = (index - 1) % JITTER_PERIOD + 1;
    [radical_inverse(i, 2) - 0.5, radical_inverse(i, 3) - 0.5]
}

/// What moves a projection's image by `jitter` pixels in an image of `size`: applied after
/// the projection (`jitter_matrix(j, size) * projection`), as [`crate::WorldView::crop`] is.
pub fn jitter_matrix(jitter: [f32; 2], size: (u32, u32)) -> Mat4 {
    let (w, h) = (size.0.max(1) as f32, size.1.max(1) as f32);
    Mat4::from_translation(glam::Vec3::new(
        2.0 * jitter[0] / w,
        -2.0 * jitter[1] / h,
        0.0,
    ))
}

/// How a frame's resolve treats the history (`mode` in `wgsl/temporal.wgsl`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Mode {
    /// No history: the frame is shown as drawn.
    Fresh = 0,
    /// The same view as the last frame: each pixel's running mean.
    Still = 1,
    /// The view moved: reprojected, checked by depth, clamped.
    Moved = 2,
}

/// One frame's plan.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Step {
    pub mode: Mode,
    /// Clip space of the last frame (unjittered) from this frame's normalised device
    /// coordinates (unjittered), camera-relative both.
    pub reproject: DMat4,
    /// The last frame's own matrix (unjittered, camera-relative): what a point that moved
    /// since (a blade in the wind) is carried back through.
    pub last: DMat4,
}

/// What the last frame was drawn from.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Last {
    unjittered: DMat4,
    eye: DVec3,
    clock: f64,
    size: (u32, u32),
}

/// A world's history, as the CPU keeps track of it.
#[derive(Clone, Debug, Default)]
pub(crate) struct History {
    /// Frames since the history began (0: none yet).
    frames: u32,
    last: Option<Last>,
    /// Why the next frame starts a new history, where something said so.
    reset: Option<&'static str>,
    /// Why the last frame had no history (`None`: it had one).
    pub fresh: Option<&'static str>,
    /// The jitter of the last frame, pixels.
    pub jitter: [f32; 2],
}

impl History {
    /// The next frame starts a new history, for `why` (a cut, a resize, new parameters).
    pub fn reset(&mut self, why: &'static str) {
        if self.last.is_some() && self.reset.is_none() {
            self.reset = Some(why);
        }
    }

    /// Forgets everything (the service turned off).
    pub fn clear(&mut self) {
        *self = Self::default();
    }

    /// Why a frame of `size` would start a new history (`None`: it keeps this one).
    fn fresh_reason(&self, size: (u32, u32)) -> Option<&'static str> {
        match &self.last {
            None => Some("first frame"),
            Some(_) if self.reset.is_some() => self.reset,
            Some(last) if last.size != size => Some("resize"),
            Some(_) => None,
        }
    }

    /// The jitter, in pixels, of the next frame at `size`.
    pub fn next_jitter(&self, size: (u32, u32)) -> [f32; 2] {
        if self.fresh_reason(size).is_some() {
            [0.0; 2]
        } else {
            jitter(self.frames)
        }
    }

    /// The clock of the last frame, seconds (`None`: no frame yet).
    pub fn last_clock(&self) -> Option<f64> {
        self.last.map(|l| l.clock)
    }

    /// Frames the last one accumulates (1: fresh; counts up to `cap`).
    pub fn frames(&self, cap: u32) -> u32 {
        self.frames.min(cap)
    }

    /// Plans the frame drawn with `jitter` ([`History::next_jitter`]) whose camera-relative
    /// matrix without the jitter is `unjittered`, from `eye` at `clock` into an image of `size`.
    pub fn advance(
        &mut self,
        jitter: [f32; 2],
        unjittered: DMat4,
        (eye, clock, size): (DVec3, f64, (u32, u32)),
    ) -> Step {
        let fresh = self.fresh_reason(size);
        let now = Last {
            unjittered,
            eye,
            clock,
            size,
        };
        let step = match (fresh, self.last) {
            (None, Some(last)) if last == now => Step {
                mode: Mode::Still,
                reproject: DMat4::IDENTITY,
                last: unjittered,
            },
            (None, Some(last)) => Step {
                mode: Mode::Moved,
                reproject: last.unjittered
                    * DMat4::from_translation(eye - last.eye)
                    * unjittered.inverse(),
                last: last.unjittered,
            },
            _ => Step {
                mode: Mode::Fresh,
                reproject: DMat4::IDENTITY,
                last: unjittered,
            },
        };
        self.frames = if fresh.is_some() {
            1
        } else {
            self.frames.saturating_add(1)
        };
        self.last = Some(now);
        self.reset = None;
        self.fresh = fresh;
        self.jitter = jitter;
        step
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_jitter_starts_at_the_centre_and_fills_the_pixel_evenly() {
        assert_eq!(jitter(0), [0.0, 0.0]);
        assert_eq!(jitter(1), [0.0, radical_inverse(1, 3) - 0.5]);
        // 256 offsets: within the pixel, their mean near its centre, each quarter of the pixel
        // holding a quarter of them.
        let js: Vec<_> = (0..256).map(jitter).collect();
        assert!(js.iter().flatten().all(|v| (-0.5..0.5).contains(v)));
        let mean = js
            .iter()
            .fold([0.0f32; 2], |m, j| [m[0] + j[0], m[1] + j[1]]);
        assert!(mean.iter().all(|m| (m / 256.0).abs() < 0.01), "{mean:?}");
        for (sx, sy) in [(-1.0, -1.0), (-1.0, 1.0), (1.0, -1.0), (1.0, 1.0)] {
            let n = js
                .iter()
                .filter(|j| j[0] * sx >= 0.0 && j[1] * sy >= 0.0)
                .count();
            assert!((56..=72).contains(&n), "quarter {sx},{sy}: {n}");
        }
    }

    #[test]
    fn the_jitter_matrix_moves_the_image_by_that_many_pixels() {
        let size = (200, 100);
        let m = jitter_matrix([0.25, -0.5], size);
        // A point at the image's centre lands a quarter pixel right and half a pixel up.
        let p = m.project_point3(glam::Vec3::new(0.0, 0.0, 0.5));
        let px = (p.x * 0.5 * 200.0, -p.y * 0.5 * 100.0);
        assert!(
            (px.0 - 0.25).abs() < 1e-5 && (px.1 + 0.5).abs() < 1e-5,
            "{px:?}"
        );
    }

    #[test]
    fn a_history_starts_fresh_stays_still_moves_and_is_cut() {
        let mut h = History::default();
        let m = DMat4::perspective_rh(1.0, 2.0, 0.1, 1000.0);
        let eye = DVec3::new(1.0, 2.0, 3.0);
        let at = |eye| (eye, 0.0, (64, 32));
        assert_eq!(h.next_jitter((64, 32)), [0.0; 2]);
        assert_eq!(h.advance([0.0; 2], m, at(eye)).mode, Mode::Fresh);
        assert_eq!(h.fresh, Some("first frame"));
        assert_eq!(h.next_jitter((64, 32)), jitter(1));
        assert_eq!(h.advance(jitter(1), m, at(eye)).mode, Mode::Still);
        assert_eq!((h.fresh, h.frames(16)), (None, 2));
        // A step east: this frame's centre came from a point the last frame saw to its right.
        let step = h.advance(jitter(2), m, at(eye + DVec3::X));
        assert_eq!(step.mode, Mode::Moved);
        let ahead = step.reproject * glam::DVec4::new(0.0, 0.0, 0.5, 1.0);
        assert!(ahead.x / ahead.w > 0.0, "{ahead}");
        // A cut, then a resize: each starts a new history, unjittered, and says why.
        h.reset("cut");
        assert_eq!(h.next_jitter((64, 32)), [0.0; 2]);
        assert_eq!(h.advance([0.0; 2], m, at(eye)).mode, Mode::Fresh);
        assert_eq!((h.fresh, h.frames(16)), (Some("cut"), 1));
        let step = h.advance([0.0; 2], m, (eye, 0.0, (32, 32)));
        assert_eq!((step.mode, h.fresh), (Mode::Fresh, Some("resize")));
        // A new clock (the water moves) is a moved frame, not a still one.
        let step = h.advance(jitter(1), m, (eye, 1.0, (32, 32)));
        assert_eq!(step.mode, Mode::Moved);
    }

    #[test]
    fn a_point_is_carried_to_where_the_last_frame_saw_it() {
        use crate::WorldView;
        let size = (160, 90);
        let a = WorldView::look_at(
            DVec3::new(1000.0, 120.0, -40.0),
            DVec3::new(1400.0, 60.0, 300.0),
            0.8,
            size,
        );
        let b = WorldView::look_at(
            DVec3::new(1003.0, 126.0, -38.0),
            DVec3::new(1390.0, 70.0, 310.0),
            0.8,
            size,
        );
        let (ma, mb) = (
            a.relative_matrix(0.5, 50_000.0).as_dmat4(),
            b.relative_matrix(0.7, 60_000.0).as_dmat4(),
        );
        let mut h = History::default();
        h.advance([0.0; 2], ma, (a.eye, 0.0, size));
        let step = h.advance(jitter(1), mb, (b.eye, 0.0, size));
        for p in [
            DVec3::new(1200.0, 80.0, 150.0),
            DVec3::new(1300.0, 40.0, 260.0),
        ] {
            let clip = |m: DMat4, eye: DVec3| m * (p - eye).extend(1.0);
            let (ca, cb) = (clip(ma, a.eye), clip(mb, b.eye));
            let ndc_b = cb / cb.w;
            let carried = step.reproject * ndc_b;
            let ndc_a = ca / ca.w;
            let got = carried / carried.w;
            assert!(
                (got.truncate() - ndc_a.truncate()).length() < 1e-9,
                "{got} {ndc_a}"
            );
            // Its w times this frame's is the last frame's clip w of the point.
            assert!(
                (carried.w * cb.w - ca.w).abs() < 1e-6 * ca.w,
                "{} {}",
                carried.w * cb.w,
                ca.w
            );
            // A point that moved by `moved` since (a blade in the wind) is carried back along
            // it, as wgsl/temporal.wgsl takes it off: in the last frame's clip space over this
            // frame's w.
            let moved = DVec3::new(0.03, -0.01, 0.02);
            let was = clip(ma, a.eye) - step.last * moved.extend(0.0);
            let carried = step.reproject * ndc_b - step.last * (moved / cb.w).extend(0.0);
            let (got, want) = (carried / carried.w, was / was.w);
            assert!((got - want).length() < 1e-9, "{got} {want}");
            let before = ma * (p - moved - a.eye).extend(1.0);
            assert!(
                (was - before).length() < 1e-9 * before.length(),
                "{was} {before}"
            );
        }
    }

    #[test]
    fn the_frame_count_is_checked() {
        assert!(Temporal { frames: 0 }.validate().is_err());
        assert!(Temporal {
            frames: MAX_FRAMES + 1
        }
        .validate()
        .is_err());
        assert!(Temporal::INTERACTIVE.validate().is_ok() && Temporal::INTERACTIVE.on());
        assert!(!Temporal::OFF.on());
    }
}
