//! The sun across the day: where the sun stands at a time of day, for one place and one day of
//! the year, so a user can set the hour (`time_of_day`) instead of an azimuth and an elevation,
//! and the window and the page can run the day with the frame's clock.
//!
//! The place and the day are fixed: latitude [`LATITUDE`] (45° north) and the sun's declination
//! [`DECLINATION`] (+15°, early May or mid August): the sun rises a little before 5:00 in the
//! north-east, stands 60° up in the south at noon, sets a little after 19:00 in the north-west,
//! and at midnight is 30° below the horizon, so the night passes through dusk (-6°, -12°) to
//! full dark (below -18°). Time is local solar time: noon is when the sun is due south.
//! At night the sky holds the faint dusk light [`crate::sky::SkyLight`] gives a sun far below
//! the horizon (no moon, no stars).

use super::WorldParam;
use crate::sky::Sky;
pub use crate::sky::NO_TIME;
use crate::table::{Control, Kind, Param, Value};

/// Latitude of the place, degrees north.
pub const LATITUDE: f64 = 45.0;
/// The sun's declination on the day, degrees.
pub const DECLINATION: f64 = 15.0;
/// Hours in a day.
pub const HOURS: f32 = 24.0;

/// The `time_of_day` row of [`super::WORLD_PARAMS`].
pub const TIME_OF_DAY: WorldParam = Param {
    key: "time_of_day",
    doc: "the hour, 0 to 24 (local solar time at 45° north in early May): sets the sun's \
          azimuth and elevation, over sun_azimuth and sun_elevation (below 0, the default: \
          the sun stands where they put it)",
    kind: Kind::Float {
        min: NO_TIME,
        max: HOURS,
    },
    control: Control::Slider {
        min: 0.0,
        max: 24.0,
        step: 0.05,
    },
    get: |p| Value::Float(p.sky.time_of_day),
    set: |p, v| {
        if let Value::Float(x) = v {
            if x >= 0.0 {
                p.sky = at_time(p.sky, x);
            } else {
                p.sky.time_of_day = NO_TIME;
            }
        }
    },
};

/// The `day_length` row of [`super::WORLD_PARAMS`].
pub const DAY_LENGTH: WorldParam = Param {
    key: "day_length",
    doc: "seconds a whole day takes on the frame's clock: the sun runs through the day from \
          time_of_day (or the hour nearest where it stands); 0, the default, holds it \
          (N in the window runs a day in 60 s)",
    kind: Kind::Float {
        min: 0.0,
        max: super::MAX_CLOCK,
    },
    control: Control::Slider {
        min: 0.0,
        max: 600.0,
        step: 5.0,
    },
    get: |p| Value::Float(p.sky.day_length),
    set: |p, v| {
        if let Value::Float(x) = v {
            p.sky.day_length = x;
        }
    },
};

/// The sun's (azimuth, elevation) in degrees at `hours` after midnight (local solar time; any
/// value, taken modulo a day): azimuth clockwise from north as [`Sky`] has it.
pub fn sun_at(hours: f32) -> (f32, f32) {
    let hour_angle = (15.0 * (f64::from(hours).rem_euclid(24.0) - 12.0)).to_radians();
    let (lat, dec) = (LATITUDE.to_radians(), DECLINATION.to_radians());
    let up = lat.sin() * dec.sin() + lat.cos() * dec.cos() * hour_angle.cos();
    let east = -dec.cos() * hour_angle.sin();
    let north = dec.sin() * lat.cos() - dec.cos() * lat.sin() * hour_angle.cos();
    let azimuth = east.atan2(north).to_degrees().rem_euclid(360.0);
    (
        azimuth as f32,
        up.clamp(-1.0, 1.0).asin().to_degrees() as f32,
    )
}

/// The time of day (hours in [0, 24)) whose sun is nearest `sky`'s (by the angle between
/// them): where a running day starts from a sun placed by hand. A sun off the day's path (any
/// azimuth can be set) starts from the nearest point on it.
pub fn time_nearest(sky: &Sky) -> f32 {
    if sky.time_of_day >= 0.0 {
        return sky.time_of_day.rem_euclid(HOURS);
    }
    let want = sky.sun_direction();
    // Every minute of the day.
    (0..24 * 60)
        .map(|m| m as f32 / 60.0)
        .max_by(|a, b| {
            let dot = |h: f32| {
                let (az, el) = sun_at(h);
                crate::sky::sun_direction(az, el).dot(want)
            };
            dot(*a).total_cmp(&dot(*b))
        })
        .unwrap_or(12.0)
}

/// `sky` with its sun at `hours` after midnight (taken modulo a day), and that time kept.
pub fn at_time(sky: Sky, hours: f32) -> Sky {
    let hours = hours.rem_euclid(HOURS);
    let (sun_azimuth, sun_elevation) = sun_at(hours);
    Sky {
        sun_azimuth,
        sun_elevation,
        time_of_day: hours,
        ..sky
    }
}

/// `sky` as it stands at `clock` seconds of the frame's clock: where its day runs
/// ([`Sky::day_length`] above 0), the sun at its `time_of_day` (or the time nearest where it
/// stands, [`time_nearest`]) plus the clock's share of a day, and the day held there (a
/// `day_length` of 0, so that the result is what a still frame draws); else `sky` itself.
pub fn sky_at(sky: Sky, clock: f64) -> Sky {
    if sky.day_length <= 0.0 || !clock.is_finite() {
        return sky;
    }
    let hours = f64::from(time_nearest(&sky))
        + clock.rem_euclid(f64::from(sky.day_length)) / f64::from(sky.day_length) * 24.0;
    Sky {
        day_length: 0.0,
        ..at_time(sky, hours.rem_euclid(24.0) as f32)
    }
}

/// "14:05" for a time of day in hours.
pub fn clock(hours: f32) -> String {
    let minutes = (hours.rem_euclid(HOURS) * 60.0).round() as u32 % (24 * 60);
    format!("{:02}:{:02}", minutes / 60, minutes % 60)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sun_rises_in_the_east_stands_south_at_noon_and_sets_in_the_west() {
        let (az, el) = sun_at(12.0);
        assert!((az - 180.0).abs() < 1e-3, "{az}");
        let noon = 90.0 - LATITUDE + DECLINATION;
        assert!((f64::from(el) - noon).abs() < 1e-3, "{el}");
        // Morning and afternoon mirror each other about the meridian.
        let (am, am_el) = sun_at(9.0);
        let (pm, pm_el) = sun_at(15.0);
        assert!(am > 90.0 && am < 180.0, "{am}");
        assert!((am + pm - 360.0).abs() < 1e-3 && (am_el - pm_el).abs() < 1e-3);
        // Sunrise and sunset: the hour angle where the elevation is 0.
        let h0 = (-LATITUDE.to_radians().tan() * DECLINATION.to_radians().tan())
            .acos()
            .to_degrees()
            / 15.0;
        let rise = (12.0 - h0) as f32;
        assert!(sun_at(rise).1.abs() < 1e-3, "{}", sun_at(rise).1);
        assert!(sun_at(rise - 0.1).1 < 0.0 && sun_at(rise + 0.1).1 > 0.0);
        assert!(sun_at(rise).0 < 90.0, "a summer sun rises north of east");
        // Midnight: deepest, due north, past astronomical dusk.
        let (az, el) = sun_at(0.0);
        assert!(az.min(360.0 - az) < 1e-3, "{az}");
        assert!(el < -18.0, "{el}");
        // Any time is taken modulo a day.
        assert_eq!(sun_at(24.0), sun_at(0.0));
        assert_eq!(sun_at(-3.0), sun_at(21.0));
    }

    #[test]
    fn a_time_sets_the_sun_and_the_nearest_time_finds_it_again() {
        for hours in [0.0, 5.5, 8.25, 12.0, 17.0, 23.5] {
            let sky = at_time(Sky::default(), hours);
            assert_eq!((sky.sun_azimuth, sky.sun_elevation), sun_at(hours));
            assert_eq!(sky.time_of_day, hours);
            let placed = Sky {
                time_of_day: NO_TIME,
                ..sky
            };
            let found = time_nearest(&placed);
            let gap = (found - hours).abs();
            assert!(gap.min(24.0 - gap) < 0.02, "{hours}: {found}");
        }
        assert_eq!(at_time(Sky::default(), 25.0).time_of_day, 1.0);
        // A running day: a quarter of its length on the clock is six hours on.
        let running = Sky {
            day_length: 60.0,
            ..at_time(Sky::default(), 9.0)
        };
        let later = sky_at(running, 15.0);
        assert_eq!((later.time_of_day, later.day_length), (15.0, 0.0));
        assert_eq!(sky_at(later, 15.0), later, "a still frame's sky stays");
        assert_eq!(sky_at(running, 75.0).time_of_day, 15.0);
        assert_eq!(sky_at(Sky::default(), 15.0), Sky::default());
        assert_eq!(clock(14.0 + 5.0 / 60.0), "14:05");
        assert_eq!(clock(23.999), "00:00");
    }

    #[test]
    fn the_table_sets_the_sun_by_the_hour_and_a_sun_set_by_hand_leaves_the_day() {
        use crate::world::{world_param, WorldParams};
        let set = |p: &mut WorldParams, key: &str, text: &str| {
            let row = world_param(key).unwrap();
            (row.set)(p, row.parse(text).unwrap());
        };
        let mut p = WorldParams::default();
        set(&mut p, "time_of_day", "7.5");
        assert_eq!((p.sky.sun_azimuth, p.sky.sun_elevation), sun_at(7.5));
        p.validate().unwrap();
        // What the table writes reads back in any order (a scene file's keys).
        let mut q = WorldParams::default();
        for key in ["time_of_day", "sun_azimuth", "sun_elevation"] {
            let row = world_param(key).unwrap();
            set(&mut q, key, &(row.get)(&p).to_string());
        }
        assert_eq!(q, p);
        // A sun turned by hand (the window's keys, a slider) leaves the day's path.
        set(&mut p, "sun_azimuth", "10");
        assert_eq!(p.sky.time_of_day, NO_TIME);
        set(&mut p, "time_of_day", "-1");
        assert_eq!(p.sky.sun_azimuth, 10.0);
        // Past a day, or not a number: refused, naming the key and the range.
        for bad in ["24.5", "-2", "nan"] {
            let e = world_param("time_of_day").unwrap().parse(bad).unwrap_err();
            assert!(e.to_string().contains("time_of_day"), "{e}");
        }
        assert!(world_param("day_length").unwrap().parse("-5").is_err());
    }
}
