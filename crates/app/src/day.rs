//! The running day in the window and the page: N runs a day in [`DAY_KEY_SECONDS`] or holds
//! the sun where it stands, a new day length or hour keeps the frame's clock (the sun stands
//! where it was, or at the hour asked, and runs on from there), and the title follows the
//! hour. The sun itself moves in the core ([`relief::day::sky_at`] at the world's clock).

use crate::App;
use relief::day;
use relief::error::Result;

/// Seconds a day takes when N runs it.
pub const DAY_KEY_SECONDS: f32 = 60.0;

impl App {
    /// The sky the world draws now: its sun where a running day has it.
    pub(crate) fn sky_now(&self) -> Option<relief::sky::Sky> {
        let (params, _) = self.options.world.as_ref()?;
        Some(
            self.state
                .as_ref()
                .and_then(|s| s.world.as_ref())
                .map_or(params.sky, relief::World::sky),
        )
    }

    /// N: runs the day, or holds the sun where it stands.
    pub(crate) fn day_key(&mut self) {
        let Some((world, _)) = self.options.world else {
            return;
        };
        let length = if world.sky.day_length > 0.0 {
            0.0
        } else {
            DAY_KEY_SECONDS
        };
        if let Err(e) = self.set("day_length", &length.to_string()) {
            self.report.warn(&e.to_string());
        }
    }

    /// After `key` was set in `options`: where it is the day's length or hour, the hour kept
    /// (anchored) against the world's clock, so the sun does not jump: a new length keeps the
    /// sun where it stands now, a new hour puts it there now, and a running day runs on.
    pub(crate) fn keep_the_day(
        &self,
        options: &mut crate::options::AppOptions,
        key: &str,
    ) -> Result<()> {
        let key = key.trim().replace('-', "_");
        let clock = self
            .state
            .as_ref()
            .and_then(|s| s.world.as_ref())
            .map_or(0.0, relief::World::clock);
        let (Some(now), Some((params, _))) = (self.sky_now(), options.world.as_mut()) else {
            return Ok(());
        };
        let was = self.options.world.map_or(0.0, |(w, _)| w.sky.day_length);
        let hours = match key.as_str() {
            // The same length (a control's echo): nothing moves.
            "day_length" if params.sky.day_length == was => return Ok(()),
            "day_length" => day::time_nearest(&now),
            "time_of_day" if params.sky.time_of_day >= 0.0 => params.sky.time_of_day,
            _ => return Ok(()),
        };
        let length = params.sky.day_length;
        let ran = if length > 0.0 {
            (clock.rem_euclid(f64::from(length)) / f64::from(length) * 24.0) as f32
        } else {
            0.0
        };
        params.sky = day::at_time(params.sky, hours - ran);
        params.validate()
    }

    /// " at 14:05" where the sun is set by the hour or the day runs, else nothing.
    pub(crate) fn title_hour(&self) -> String {
        match self.sky_now() {
            Some(sky) if sky.time_of_day >= 0.0 => format!(" at {}", day::clock(sky.time_of_day)),
            _ => String::new(),
        }
    }
}

/// Whether `options` run the sun through the day (frames must keep coming: `moving`).
pub(crate) fn day_runs(options: &crate::options::AppOptions) -> bool {
    options.world.is_some_and(|(w, _)| w.sky.day_length > 0.0)
}
