//! The clouds: a layer of 3-D density between a base and a top altitude, drifting with the
//! frame's one wind, marched along each view ray and towards the sun by `wgsl/clouds.wgsl`
//! (its density, light and shadows are documented there and in docs/clouds.md). This module
//! holds their parameters, the rows of [`super::WORLD_PARAMS`] that set them, and what the
//! frame's uniforms carry.

use super::WorldParam;
use crate::error::{Error, Result};
use crate::table::{Control, Kind, Param, Value};

/// Metres after which every noise of the clouds repeats in x and z (`CLOUD_PERIOD` in
/// `wgsl/clouds.wgsl`): the wind's drift reaches the shaders reduced modulo it.
pub const CLOUD_PERIOD: f64 = 40960.0;
/// Steps a view ray takes through the layer each frame.
pub const STEPS: u32 = 48;
/// Steps the reference takes (docs/results/clouds.md: doubling them changes its frame by less
/// than the goal).
pub const REFERENCE_STEPS: u32 = 1024;
/// How much faster than the shapes the detail drifts: the clouds' edges change as they go.
pub const DETAIL_DRIFT: f64 = 1.5;
/// The planet's radius, metres (`EARTH_RADIUS` in the shader): the layer curves with it.
pub const EARTH_RADIUS: f64 = 6_371_000.0;
/// The highest cloud top, metres.
pub const MAX_TOP: f32 = 20_000.0;

/// The cloud layer's parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Clouds {
    /// How much of the sky they cover, 0 to 1; 0 (the default) draws none.
    pub coverage: f32,
    /// Altitude of the layer's base, metres (below the terrain is allowed: fog in valleys).
    pub base: f32,
    /// Altitude of the layer's top, metres (above the base).
    pub top: f32,
    /// Their type: 0 flat stratus in the layer's lower third, 1 cumulus to its top.
    pub kind: f32,
    /// Steps a view ray takes through the layer ([`STEPS`]; the reference takes
    /// [`REFERENCE_STEPS`]). Not a row of the table: what a benchmark or a reference asks.
    pub steps: u32,
    /// Where the temporal service runs and the visibility or hybrid method draws: march one
    /// pixel in 16 a frame and carry the others over from the last frame (the default), or
    /// (`false`) every pixel every frame, as the reference and the other methods do. Not a
    /// row of the table either.
    pub reproject: bool,
    /// Light shafts: the clouds' shadows in the air below their base take the sun's share of
    /// the air's light there (`cloud_shafts` in `wgsl/clouds.wgsl`), so sunlit air between
    /// shadowed air shows as beams, brightest towards the sun; the fog sets how strong (clear
    /// air shows none). On by default; `false` draws the air as if it were all sunlit. Not a
    /// row of the table.
    pub shafts: bool,
}

impl Default for Clouds {
    /// None; when turned on, broken cumulus above the default landscape's peaks (2400 m).
    fn default() -> Self {
        Self {
            coverage: 0.0,
            base: 2600.0,
            top: 4600.0,
            kind: 0.7,
            steps: STEPS,
            reproject: true,
            shafts: true,
        }
    }
}

impl Clouds {
    /// Whether the frame draws them.
    pub fn on(&self) -> bool {
        self.coverage > 0.0
    }

    /// `Ok` where the layer has a thickness: a base below its top.
    pub fn check(&self) -> Result<()> {
        if self.base >= self.top {
            return Err(Error::invalid(
                "cloud_top",
                self.top,
                format!("above cloud_base ({} m)", self.base),
            ));
        }
        Ok(())
    }

    /// Cloud-space x and z of the eye for the shapes and for the detail (the eye less the
    /// wind's drift `drift`, metres, reduced in f64 modulo [`CLOUD_PERIOD`]).
    pub fn origin(eye: glam::DVec3, drift: glam::DVec2) -> [f32; 4] {
        let at = |k: f64| {
            [
                (eye.x - k * drift.x).rem_euclid(CLOUD_PERIOD) as f32,
                (eye.z - k * drift.y).rem_euclid(CLOUD_PERIOD) as f32,
            ]
        };
        let (s, d) = (at(1.0), at(DETAIL_DRIFT));
        [s[0], s[1], d[0], d[1]]
    }

    /// The sun's direction as the layer's middle sees it: raised by the dip of the horizon
    /// there, so a sun just set on the ground still lights the clouds from below.
    pub fn sun_direction(&self, sun: glam::Vec3) -> glam::Vec3 {
        let middle = f64::from(0.5 * (self.base + self.top)).max(0.0);
        let dip = (EARTH_RADIUS / (EARTH_RADIUS + middle)).acos() as f32;
        let e = sun.y.clamp(-1.0, 1.0).asin() + dip;
        let flat = glam::Vec2::new(sun.x, sun.z).normalize_or(glam::Vec2::Y);
        glam::Vec3::new(flat.x * e.cos(), e.sin(), flat.y * e.cos())
    }
}

/// The `cloud_coverage` row of [`super::WORLD_PARAMS`].
pub const CLOUD_COVERAGE: WorldParam = Param {
    key: "cloud_coverage",
    doc: "how much of the sky the clouds cover, 0 to 1: 0, the default, draws none; 1 is overcast",
    kind: Kind::Float { min: 0.0, max: 1.0 },
    control: Control::Slider {
        min: 0.0,
        max: 1.0,
        step: 0.01,
    },
    get: |p| Value::Float(p.clouds.coverage),
    set: |p, v| {
        if let Value::Float(x) = v {
            p.clouds.coverage = x;
        }
    },
};

/// The `cloud_base` row of [`super::WORLD_PARAMS`].
pub const CLOUD_BASE: WorldParam = Param {
    key: "cloud_base",
    doc: "altitude of the clouds' base, metres (below the terrain is allowed: fog in the valleys); below cloud_top",
    kind: Kind::Float {
        min: -1000.0,
        max: MAX_TOP,
    },
    control: Control::Slider {
        min: 0.0,
        max: 8000.0,
        step: 50.0,
    },
    get: |p| Value::Float(p.clouds.base),
    set: |p, v| {
        if let Value::Float(x) = v {
            p.clouds.base = x;
        }
    },
};

/// The `cloud_top` row of [`super::WORLD_PARAMS`].
pub const CLOUD_TOP: WorldParam = Param {
    key: "cloud_top",
    doc: "altitude of the clouds' top, metres; above cloud_base",
    kind: Kind::Float {
        min: -1000.0,
        max: MAX_TOP,
    },
    control: Control::Slider {
        min: 0.0,
        max: 12000.0,
        step: 50.0,
    },
    get: |p| Value::Float(p.clouds.top),
    set: |p, v| {
        if let Value::Float(x) = v {
            p.clouds.top = x;
        }
    },
};

/// The `cloud_type` row of [`super::WORLD_PARAMS`].
pub const CLOUD_TYPE: WorldParam = Param {
    key: "cloud_type",
    doc: "the clouds' type: 0 flat stratus in the layer's lower third, 1 cumulus heaped to its top",
    kind: Kind::Float { min: 0.0, max: 1.0 },
    control: Control::Slider {
        min: 0.0,
        max: 1.0,
        step: 0.05,
    },
    get: |p| Value::Float(p.clouds.kind),
    set: |p, v| {
        if let Value::Float(x) = v {
            p.clouds.kind = x;
        }
    },
};

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_layer_needs_its_base_below_its_top() {
        assert!(Clouds::default().check().is_ok());
        let flat = Clouds {
            base: 3000.0,
            top: 3000.0,
            ..Clouds::default()
        };
        let e = flat.check().unwrap_err().to_string();
        assert!(
            e.contains("cloud_top") && e.contains("above cloud_base"),
            "{e}"
        );
    }

    #[test]
    fn the_origin_repeats_with_the_period_and_follows_the_wind() {
        let eye = glam::DVec3::new(1.0e7 + 5.0, 900.0, -3.0);
        let a = Clouds::origin(eye, glam::DVec2::ZERO);
        let b = Clouds::origin(eye + glam::DVec3::X * CLOUD_PERIOD * 3.0, glam::DVec2::ZERO);
        assert_eq!(a, b);
        // Wind carrying the clouds 100 m east moves the eye 100 m west in cloud space.
        let c = Clouds::origin(eye, glam::DVec2::new(100.0, 0.0));
        assert!((f64::from(a[0] - c[0]) - 100.0).abs() < 1e-2, "{a:?} {c:?}");
        assert!((f64::from(a[2] - c[2]) - 100.0 * DETAIL_DRIFT).abs() < 1e-2);
    }

    #[test]
    fn a_sun_just_set_still_lights_the_layer() {
        // The default layer's middle, 3600 m up, sees 1.93 degrees past the ground's horizon.
        let set = crate::sky::sun_direction(145.0, -1.5);
        let seen = Clouds::default().sun_direction(set);
        assert!(seen.y > 0.0, "{seen}");
        let dip = (seen.y.asin() - set.y.asin()).to_degrees();
        assert!((dip - 1.93).abs() < 0.01, "{dip}");
        assert!((seen.length() - 1.0).abs() < 1e-5);
        // The same azimuth.
        assert!((seen.x.atan2(-seen.z) - set.x.atan2(-set.z)).abs() < 1e-4);
    }
}
