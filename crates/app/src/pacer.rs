//! How much of the endless world's bake one frame of the window or the page takes on, and how
//! far along it is.
//!
//! The core bakes heights and light within per-frame budgets in texels
//! ([`relief::World::set_bake_budget`], [`relief::World::set_light_budget`]). Their defaults
//! suit a real GPU; a software device (lavapipe, the browser's SwiftShader) is hundreds of
//! times slower, so a budget in texels would make each of its frames wait seconds. The pacer
//! scales both budgets by the frames it sees. It starts from a sliver of them; while baking, a
//! frame over its target halves the budgets, one under three quarters of it doubles them, up to
//! the defaults. The target is twice the time a frame takes without baking (a running mean of
//! such frames, and of those at the smallest budgets; never under [`MIN_TARGET_MS`]), so a
//! frame while baking costs one to two frames of drawing; before any such frame was seen it is
//! [`FIRST_TARGET_MS`].
//! On a GPU the budgets reach the defaults within a few frames; on a software device keys and
//! the page's thread are never held for a whole bake.

use relief::gpu::world::{DEFAULT_BAKE_BUDGET, DEFAULT_LIGHT_BUDGET};

/// A frame while baking may take this long, whatever the device (ms).
pub const MIN_TARGET_MS: f64 = 50.0;

/// A frame's target while no frame without baking has been seen (ms): the first arrival,
/// before the device's drawing time is known.
pub const FIRST_TARGET_MS: f64 = 500.0;

/// Smallest share of the default budgets a frame is given, and the first.
const MIN_SCALE: f64 = 1.0 / 256.0;

/// The share of the default budgets a frame takes on: see the module docs.
#[derive(Clone, Copy, Debug)]
pub struct Pacer {
    scale: f64,
    /// A running mean of the frames that baked nothing, ms.
    draw_ms: Option<f64>,
}

impl Default for Pacer {
    fn default() -> Self {
        Self {
            scale: MIN_SCALE,
            draw_ms: None,
        }
    }
}

impl Pacer {
    /// (heights, light) budgets in texels for the next frame.
    pub fn budgets(&self) -> (u64, u64) {
        let scaled = |b: u64| ((b as f64 * self.scale) as u64).max(1);
        (scaled(DEFAULT_BAKE_BUDGET), scaled(DEFAULT_LIGHT_BUDGET))
    }

    /// After a frame that took `interval_ms` from the one before, `baked` whether it baked.
    pub fn frame(&mut self, interval_ms: f64, baked: bool) {
        if !(interval_ms.is_finite() && interval_ms > 0.0) {
            return;
        }
        // A frame that baked nothing, or only the sliver of the smallest budgets, shows what
        // drawing alone takes.
        if !baked || self.scale <= MIN_SCALE {
            self.draw_ms = Some(
                self.draw_ms
                    .map_or(interval_ms, |d| 0.8 * d + 0.2 * interval_ms),
            );
        }
        if !baked {
            return;
        }
        let target = self
            .draw_ms
            .map_or(FIRST_TARGET_MS, |d| (2.0 * d).max(MIN_TARGET_MS));
        if interval_ms > target {
            self.scale = (self.scale / 2.0).max(MIN_SCALE);
        } else if interval_ms < 0.75 * target {
            self.scale = (self.scale * 2.0).min(1.0);
        }
    }
}

/// How far a bake has come since it began (the most texels that waited at once).
#[derive(Clone, Copy, Debug, Default)]
pub struct Progress {
    most: u64,
}

impl Progress {
    /// With `pending` texels waiting now: the share done in percent while baking (0..=99),
    /// None when nothing waits.
    pub fn update(&mut self, pending: u64) -> Option<u32> {
        if pending == 0 {
            self.most = 0;
            return None;
        }
        self.most = self.most.max(pending);
        let done = (self.most - pending) as f64 / self.most as f64;
        Some(((done * 100.0) as u32).min(99))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_fast_device_reaches_the_default_budgets_and_a_slow_one_keeps_near_its_draw() {
        let mut fast = Pacer::default();
        assert!(fast.budgets().1 < DEFAULT_LIGHT_BUDGET / 100);
        for _ in 0..8 {
            fast.frame(2.0, true);
        }
        assert_eq!(fast.budgets(), (DEFAULT_BAKE_BUDGET, DEFAULT_LIGHT_BUDGET));
        // A software device on arrival: drawing alone takes 300 ms. Frames at the smallest
        // budgets show it (the target becomes 600 ms), and quick ones double the budgets...
        let mut slow = Pacer::default();
        slow.frame(300.0, true);
        slow.frame(320.0, true);
        let (h, l) = slow.budgets();
        assert_eq!(
            (h, l),
            (4 * fast.budgets().0 / 256, 4 * fast.budgets().1 / 256)
        );
        // ... which then stay between 450 and 600 ms, and halve over 600 ms.
        slow.frame(500.0, true);
        assert_eq!(slow.budgets(), (h, l));
        slow.frame(3000.0, true);
        assert_eq!(slow.budgets(), (h / 2, l / 2));
        // A device whose drawing alone is over the first target (900 ms a frame) keeps baking
        // at the smallest budgets rather than stopping: those frames raise its target.
        let mut slower = Pacer::default();
        for _ in 0..12 {
            slower.frame(900.0, true);
        }
        assert!(
            slower.budgets().1 >= DEFAULT_LIGHT_BUDGET / 128,
            "{slower:?}"
        );
    }

    #[test]
    fn progress_counts_from_the_most_that_waited() {
        let mut p = Progress::default();
        assert_eq!(p.update(0), None);
        assert_eq!(p.update(1000), Some(0));
        assert_eq!(p.update(250), Some(75));
        assert_eq!(p.update(1), Some(99));
        assert_eq!(p.update(0), None);
        assert_eq!(p.update(10), Some(0));
    }
}
