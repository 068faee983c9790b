//! Which world relief draws, and the endless world's parameters with their table.
//!
//! Two worlds: `tile`, the seed blog's square tile seen from outside (its parameters are
//! [`crate::params::PARAMS`]), and `endless`, a landscape in metres to the horizon drawn by the
//! clipmap renderer ([`crate::gpu::world::World`]), whose parameters are [`WORLD_PARAMS`]. A key
//! of one world's table that the other lacks is refused under the other (never ignored).

pub mod clouds;
pub mod day;

use crate::error::{Error, Result};
use crate::landscape::{Landscape, TerrainFn};
use crate::palette::Palette;
use crate::sky::Sky;
use crate::table::{Control, Kind, Param, Value};

/// The worlds relief can draw.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum WorldKind {
    /// The seed blog's periodic tile, seen from outside.
    #[default]
    Tile,
    /// An endless landscape in metres, seen from inside, to the horizon.
    Endless,
}

impl WorldKind {
    /// Every world's name.
    pub const NAMES: &'static [&'static str] = &["tile", "endless"];

    /// Its name.
    pub fn name(self) -> &'static str {
        match self {
            WorldKind::Tile => "tile",
            WorldKind::Endless => "endless",
        }
    }

    /// The world called `name`.
    pub fn from_name(name: &str) -> Option<Self> {
        match name.trim() {
            "tile" => Some(WorldKind::Tile),
            "endless" => Some(WorldKind::Endless),
            _ => None,
        }
    }
}

/// Height in metres of the sand along the shore (jittered by the colour noise).
pub const SAND_BAND: f64 = 12.0;

/// Largest octave count of the endless world.
pub(crate) const MAX_WORLD_OCTAVES: u32 = 20;
/// Largest feature size (octave 0's lattice cell), metres.
pub(crate) const MAX_FEATURE_SIZE: u32 = 1 << 20;
/// The finest octave's cell may not be under 2^-MIN_CELL_LOG2 metres.
pub(crate) const MIN_CELL_LOG2: i32 = -7;

/// Everything that decides what the endless world looks like and how finely it is drawn.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WorldParams {
    /// The terrain function and its scale.
    pub land: Landscape,
    /// The quality knob: the largest screen-space geometric error, in pixels.
    pub pixel_error: f64,
    /// Normalised height (0..1) of the snow line.
    pub snow_height: f32,
    /// Height-AO exponent.
    pub ao_exponent: f32,
    /// The sun and the air.
    pub sky: Sky,
    /// Height of the water's surface, metres.
    pub water_level: f32,
    /// No water (and no sand).
    pub no_water: bool,
    /// How the terrain is coloured and lit.
    pub palette: Palette,
    /// No sun shadows (every slope facing the sun is lit).
    pub no_shadows: bool,
    /// The animation clock, seconds: what moves on its own (the water's ripples) is drawn as
    /// it is at this time. A window adds the seconds since it started ([`World::set_time`]).
    ///
    /// [`World::set_time`]: crate::World::set_time
    pub clock: f64,
    /// The one wind every layer that moves with the wind follows (the water's ripples drift
    /// with it).
    pub wind: Wind,
    /// The meadow's blades ([`crate::grass`]): on by default.
    pub grass: crate::grass::Grass,
    /// How props are scattered ([`crate::props`]): off by default. What they are is the
    /// world's [`crate::props::Scene`] (`World::set_props_scene`).
    pub props: crate::props::Props,
    /// The cloud layer (none by default).
    pub clouds: clouds::Clouds,
}

/// The wind: a speed and the bearing it comes from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Wind {
    /// Metres a second.
    pub speed: f32,
    /// Degrees clockwise from north (-z) towards east (+x) of where the wind comes from, as
    /// weather reports give it: 270 is a west wind, blowing towards +x.
    pub from_azimuth: f32,
}

impl Default for Wind {
    /// A light breeze from the west.
    fn default() -> Self {
        Self {
            speed: 4.0,
            from_azimuth: 270.0,
        }
    }
}

impl Wind {
    /// The air's velocity in metres a second, (x, z).
    pub fn velocity(&self) -> glam::DVec2 {
        let a = f64::from(self.from_azimuth).to_radians();
        // Coming from bearing a (the unit vector (sin a, -cos a) in x, z), blowing the other way.
        glam::DVec2::new(-a.sin(), a.cos()) * f64::from(self.speed)
    }
}

impl Default for WorldParams {
    /// Eroded mountains some 2 km high with ridges about 4 km apart, detail down to a metre,
    /// drawn to within a pixel; lakes in the valleys below 1000 m; a low evening sun.
    fn default() -> Self {
        Self {
            land: Landscape {
                seed: 7,
                octaves: 12,
                gain: 0.47,
                feature_log2: 12,
                peak_height: 2400.0,
                terrain: TerrainFn::Eroded,
                period: 0,
            },
            pixel_error: 1.0,
            snow_height: 0.63,
            ao_exponent: 1.0,
            sky: Sky::default(),
            water_level: 1000.0,
            no_water: false,
            palette: Palette::SeedTemplate,
            no_shadows: false,
            clock: 0.0,
            wind: Wind::default(),
            grass: crate::grass::Grass::default(),
            props: crate::props::Props::default(),
            clouds: clouds::Clouds::default(),
        }
    }
}

/// One row of the endless world's table.
pub type WorldParam = Param<WorldParams>;

/// A table float as the f64 its shortest decimal text means (0.47, not 0.4699999988).
fn float(v: Value) -> Option<f64> {
    match v {
        Value::Float(x) => x.to_string().parse().ok(),
        _ => None,
    }
}

/// The endless world's parameters: keys shared with the tile's table ([`crate::params::PARAMS`])
/// mean the same there; the others are the endless world's own.
pub static WORLD_PARAMS: [WorldParam; 32] = [
    Param {
        key: "seed",
        doc: "hash seed: the same seed gives the same terrain on every GPU and on the CPU",
        kind: Kind::Int {
            min: 0,
            max: u32::MAX,
        },
        control: Control::Number,
        get: |p| Value::Int(p.land.seed),
        set: |p, v| {
            if let Value::Int(x) = v {
                p.land.seed = x;
            }
        },
    },
    Param {
        key: "octaves",
        doc: "fBm octaves (the finest cell, feature_size / 2^(octaves-1), at least 1/128 m)",
        kind: Kind::Int {
            min: 1,
            max: MAX_WORLD_OCTAVES,
        },
        control: Control::Slider {
            min: 1.0,
            max: 16.0,
            step: 1.0,
        },
        get: |p| Value::Int(p.land.octaves),
        set: |p, v| {
            if let Value::Int(x) = v {
                p.land.octaves = x;
            }
        },
    },
    Param {
        key: "gain",
        doc: "amplitude ratio between octaves",
        kind: Kind::Float { min: 0.0, max: 1.0 },
        control: Control::Slider {
            min: 0.0,
            max: 1.0,
            step: 0.01,
        },
        get: |p| Value::Float(p.land.gain as f32),
        set: |p, v| {
            if let Some(x) = float(v) {
                p.land.gain = x;
            }
        },
    },
    Param {
        key: "feature_size",
        doc: "octave 0's lattice cell in metres, a power of two (the spacing of the big ridges)",
        kind: Kind::Int {
            min: 1,
            max: MAX_FEATURE_SIZE,
        },
        control: Control::None,
        get: |p| Value::Int(1u32 << p.land.feature_log2.clamp(0, 20)),
        set: |p, v| {
            if let Value::Int(x) = v {
                // Not a power of two: kept as an impossible log2 for validate to name.
                p.land.feature_log2 = if x.is_power_of_two() {
                    x.trailing_zeros() as i32
                } else {
                    -1000 - x.min(1 << 30) as i32
                };
            }
        },
    },
    Param {
        key: "peak_height",
        doc: "world height in metres of normalised height 1 (the highest the terrain can reach)",
        kind: Kind::Float {
            min: 1.0,
            max: 20000.0,
        },
        control: Control::Slider {
            min: 100.0,
            max: 6000.0,
            step: 50.0,
        },
        get: |p| Value::Float(p.land.peak_height as f32),
        set: |p, v| {
            if let Some(x) = float(v) {
                p.land.peak_height = x;
            }
        },
    },
    Param {
        key: "terrain",
        doc: "fbm (plain fBm) or eroded (detail damped on steep slopes, as in the seed template)",
        kind: Kind::Choice(TerrainFn::NAMES),
        control: Control::Select,
        get: |p| Value::Choice(p.land.terrain.name()),
        set: |p, v| {
            if let Value::Choice(name) = v {
                p.land.terrain = TerrainFn::from_name(name).unwrap_or_default();
            }
        },
    },
    Param {
        key: "pixel_error",
        doc: "largest screen-space geometric error in pixels: sets the levels' grid density",
        kind: Kind::Float {
            min: 0.25,
            max: 64.0,
        },
        control: Control::Slider {
            min: 0.25,
            max: 8.0,
            step: 0.25,
        },
        get: |p| Value::Float(p.pixel_error as f32),
        set: |p, v| {
            if let Some(x) = float(v) {
                p.pixel_error = x;
            }
        },
    },
    Param {
        key: "snow_height",
        doc: "normalised height (0..1) above which snow lies",
        kind: Kind::Float { min: 0.0, max: 1.0 },
        control: Control::Slider {
            min: 0.0,
            max: 1.0,
            step: 0.01,
        },
        get: |p| Value::Float(p.snow_height),
        set: |p, v| {
            if let Value::Float(x) = v {
                p.snow_height = x;
            }
        },
    },
    Param {
        key: "ao_exponent",
        doc: "height ambient occlusion h^k of the blog palette (0 turns it off)",
        kind: Kind::Float {
            min: 0.0,
            max: crate::params::MAX_AO_EXPONENT,
        },
        control: Control::Slider {
            min: 0.0,
            max: 4.0,
            step: 0.05,
        },
        get: |p| Value::Float(p.ao_exponent),
        set: |p, v| {
            if let Value::Float(x) = v {
                p.ao_exponent = x;
            }
        },
    },
    Param {
        key: "sun_azimuth",
        doc: "the sun's bearing in degrees, clockwise from north (-z) towards east (+x)",
        kind: Kind::Float {
            min: -360.0,
            max: 360.0,
        },
        control: Control::Slider {
            min: 0.0,
            max: 360.0,
            step: 1.0,
        },
        get: |p| Value::Float(p.sky.sun_azimuth),
        set: |p, v| {
            if let Value::Float(x) = v {
                // A sun placed by hand leaves the day's path.
                if x != p.sky.sun_azimuth {
                    p.sky.time_of_day = day::NO_TIME;
                }
                p.sky.sun_azimuth = x;
            }
        },
    },
    Param {
        key: "sun_elevation",
        doc: "the sun's height above the horizon in degrees (below 0: dusk, no sunlight)",
        kind: Kind::Float {
            min: -90.0,
            max: 90.0,
        },
        control: Control::Slider {
            min: -5.0,
            max: 90.0,
            step: 0.5,
        },
        get: |p| Value::Float(p.sky.sun_elevation),
        set: |p, v| {
            if let Value::Float(x) = v {
                if x != p.sky.sun_elevation {
                    p.sky.time_of_day = day::NO_TIME;
                }
                p.sky.sun_elevation = x;
            }
        },
    },
    day::TIME_OF_DAY,
    day::DAY_LENGTH,
    clouds::CLOUD_COVERAGE,
    clouds::CLOUD_BASE,
    clouds::CLOUD_TOP,
    clouds::CLOUD_TYPE,
    Param {
        key: "fog",
        doc: "aerial perspective: extinction per km of green light (blue more, red less); 0 for clear air",
        kind: Kind::Float { min: 0.0, max: 50.0 },
        control: Control::Slider {
            min: 0.0,
            max: 0.5,
            step: 0.005,
        },
        get: |p| Value::Float(p.sky.fog),
        set: |p, v| {
            if let Value::Float(x) = v {
                p.sky.fog = x;
            }
        },
    },
    Param {
        key: "water_level",
        doc: "height of the water's surface in metres (lakes and seas fill what lies below)",
        kind: Kind::Float {
            min: -20000.0,
            max: 20000.0,
        },
        control: Control::Slider {
            min: 0.0,
            max: 2400.0,
            step: 10.0,
        },
        get: |p| Value::Float(p.water_level),
        set: |p, v| {
            if let Value::Float(x) = v {
                p.water_level = x;
            }
        },
    },
    Param {
        key: "no_water",
        doc: "no water and no sand: the terrain only",
        kind: Kind::Bool,
        control: Control::Checkbox,
        get: |p| Value::Bool(p.no_water),
        set: |p, v| {
            if let Value::Bool(x) = v {
                p.no_water = x;
            }
        },
    },
    Param {
        key: "palette",
        doc: "seed-template (rock, grass, snow and sand by height, slope and noise; sky, back and rim light; valley occlusion; a tone curve) or blog (two colours, height occlusion)",
        kind: Kind::Choice(Palette::NAMES),
        control: Control::Select,
        get: |p| Value::Choice(p.palette.name()),
        set: |p, v| {
            if let Value::Choice(name) = v {
                p.palette = Palette::from_name(name).unwrap_or_default();
            }
        },
    },
    Param {
        key: "no_shadows",
        doc: "no sun shadows: every slope facing the sun is lit",
        kind: Kind::Bool,
        control: Control::Checkbox,
        get: |p| Value::Bool(p.no_shadows),
        set: |p, v| {
            if let Value::Bool(x) = v {
                p.no_shadows = x;
            }
        },
    },
    Param {
        key: "clock",
        doc: "the animation clock in seconds: the water's ripples as they are at this time (a window runs on from it)",
        kind: Kind::Float {
            min: 0.0,
            max: MAX_CLOCK,
        },
        control: Control::None,
        get: |p| Value::Float(p.clock as f32),
        set: |p, v| {
            if let Some(x) = float(v) {
                p.clock = x;
            }
        },
    },
    Param {
        key: "wind_speed",
        doc: "the wind's speed in metres a second (the water's ripples drift with it)",
        kind: Kind::Float {
            min: 0.0,
            max: 50.0,
        },
        control: Control::Slider {
            min: 0.0,
            max: 20.0,
            step: 0.5,
        },
        get: |p| Value::Float(p.wind.speed),
        set: |p, v| {
            if let Value::Float(x) = v {
                p.wind.speed = x;
            }
        },
    },
    Param {
        key: "wind_azimuth",
        doc: "the bearing the wind comes from, in degrees clockwise from north (-z): 270 is a west wind",
        kind: Kind::Float {
            min: -360.0,
            max: 360.0,
        },
        control: Control::Slider {
            min: 0.0,
            max: 360.0,
            step: 5.0,
        },
        get: |p| Value::Float(p.wind.from_azimuth),
        set: |p, v| {
            if let Value::Float(x) = v {
                p.wind.from_azimuth = x;
            }
        },
    },
    Param {
        key: "no_grass",
        doc: "no grass: bare ground where grass grows by default (blades of geometry on the ground the material makes grass, within grass_distance of the eye)",
        kind: Kind::Bool,
        control: Control::Checkbox,
        get: |p| Value::Bool(!p.grass.on),
        set: |p, v| {
            if let Value::Bool(x) = v {
                p.grass.on = !x;
            }
        },
    },
    Param {
        key: "grass_density",
        doc: "blades of grass a square metre where the ground is wholly grass",
        kind: Kind::Float {
            min: crate::grass::Grass::DENSITY.0,
            max: crate::grass::Grass::DENSITY.1,
        },
        control: Control::Slider {
            min: 4.0,
            max: 128.0,
            step: 4.0,
        },
        get: |p| Value::Float(p.grass.density),
        set: |p, v| {
            if let Value::Float(x) = v {
                p.grass.density = x;
            }
        },
    },
    Param {
        key: "grass_height",
        doc: "the mean blade's height in metres (clumps vary it from 0.3 to 1.9 times)",
        kind: Kind::Float {
            min: crate::grass::Grass::HEIGHT.0,
            max: crate::grass::Grass::HEIGHT.1,
        },
        control: Control::Slider {
            min: 0.1,
            max: 1.5,
            step: 0.1,
        },
        get: |p| Value::Float(p.grass.height),
        set: |p, v| {
            if let Value::Float(x) = v {
                p.grass.height = x;
            }
        },
    },
    Param {
        key: "grass_distance",
        doc: "how far from the eye grass is drawn, in metres (thinning from half of it, each blade shrinking away at its own distance)",
        kind: Kind::Float {
            min: crate::grass::Grass::DISTANCE.0,
            max: crate::grass::Grass::DISTANCE.1,
        },
        control: Control::Slider {
            min: 10.0,
            max: 120.0,
            step: 5.0,
        },
        get: |p| Value::Float(p.grass.distance),
        set: |p, v| {
            if let Value::Float(x) = v {
                p.grass.distance = x;
            }
        },
    },
    Param {
        key: "props",
        doc: "props on the ground: boulders, standing stones, arches, ruins and cairns (signed distance functions marched in compute), or the scene file's own",
        kind: Kind::Bool,
        control: Control::Checkbox,
        get: |p| Value::Bool(p.props.on),
        set: |p, v| {
            if let Value::Bool(x) = v {
                p.props.on = x;
            }
        },
    },
    Param {
        key: "props_density",
        doc: "the chance that a cell of gentle ground holds a prop (cells of props_cell metres; rock holds a seventh as many)",
        kind: Kind::Float { min: 0.0, max: 1.0 },
        control: Control::Slider {
            min: 0.0,
            max: 1.0,
            step: 0.05,
        },
        get: |p| Value::Float(p.props.density),
        set: |p, v| {
            if let Value::Float(x) = v {
                p.props.density = x;
                p.props.rock_density = x / 7.0;
            }
        },
    },
    Param {
        key: "props_distance",
        doc: "how far from the eye props are drawn, in metres (each sinks into the ground where it is smaller on screen than its cut-off)",
        kind: Kind::Float {
            min: crate::props::Props::DISTANCE.0,
            max: crate::props::Props::DISTANCE.1,
        },
        control: Control::Slider {
            min: 100.0,
            max: 3000.0,
            step: 100.0,
        },
        get: |p| Value::Float(p.props.distance),
        set: |p, v| {
            if let Value::Float(x) = v {
                p.props.distance = x;
            }
        },
    },
];

/// The latest `clock` the table takes, seconds (a day); a window runs on past it.
pub(crate) const MAX_CLOCK: f32 = 86_400.0;

/// The endless world's row for `key` (dashes accepted).
pub fn world_param(key: &str) -> Option<&'static WorldParam> {
    let key = key.trim().replace('-', "_");
    WORLD_PARAMS.iter().find(|p| p.key == key)
}

impl WorldParams {
    /// The same world with its ground bare (grass off, its other keys kept): what the ray
    /// marches draw, and what the terrain's measurements measure.
    pub fn without_grass(&self) -> Self {
        let mut p = *self;
        p.grass.on = false;
        p
    }

    /// What decides where grass grows ([`crate::grass::cover`]): the snow line, the water and
    /// its shore, as the shading has them.
    pub fn grass_cover(&self) -> crate::grass::CoverParams {
        let peak = self.land.peak_height;
        crate::grass::CoverParams {
            snow_height: self.snow_height,
            water: (!self.no_water).then(|| (f64::from(self.water_level) / peak) as f32),
            sand_band: (SAND_BAND / peak) as f32,
        }
    }

    /// The grass's cover ([`crate::grass::cover`]) of the ground at world (x, z) by the CPU
    /// twin: the landscape's height, slope and colour channel there, with `p` from
    /// [`WorldParams::grass_cover`].
    pub fn grass_cover_at(&self, p: &crate::grass::CoverParams, x: f64, z: f64) -> f32 {
        use crate::noise::Channel;
        let land = &self.land;
        let s = land.sample(Channel::Height, x, z, land.octaves);
        let t = land.sample(Channel::Color, x, z, land.octaves);
        let g = [
            s.gradient[0] * land.peak_height,
            s.gradient[1] * land.peak_height,
        ];
        let n_y = 1.0 / (1.0 + g[0] * g[0] + g[1] * g[1]).sqrt();
        crate::grass::cover(p, n_y as f32, s.value as f32, t.value as f32)
    }

    /// A sunlit meadow near `near` (x, z, world metres): the first point of a grid around it
    /// (37 m by 53 m steps, some 7 by 10 km) where the ground is grass all round (within 15 m:
    /// [`crate::grass::cover`] over 0.95, from the twin) and the sun reaches it, or `None`.
    /// The grass's benchmark views and tests stand there.
    pub fn find_meadow(&self, near: [f64; 2]) -> Option<glam::DVec3> {
        let land = &self.land;
        let p = self.grass_cover();
        let slope = *land.slope_bounds().last()?;
        let cover_at = |x: f64, z: f64| self.grass_cover_at(&p, x, z);
        let sun = (
            f64::from(self.sky.sun_azimuth).to_radians(),
            f64::from(self.sky.sun_elevation).to_radians(),
        );
        let around = [
            (0.0, 0.0),
            (15.0, 0.0),
            (-15.0, 0.0),
            (0.0, 15.0),
            (0.0, -15.0),
        ];
        (0..40_000).find_map(|i| {
            let x = near[0] + 37.0 * f64::from(i % 200);
            let z = near[1] + 53.0 * f64::from(i / 200);
            let meadow = around
                .iter()
                .all(|(dx, dz)| cover_at(x + dx, z + dz) > 0.95)
                && crate::light::lit_by_ray(land, (x, z), sun, slope, 20_000.0);
            meadow.then(|| glam::DVec3::new(x, land.height_at(x, z), z))
        })
    }

    /// Checks every field against its row, then the rules between them, naming the parameter.
    pub fn validate(&self) -> Result<()> {
        for row in &WORLD_PARAMS {
            row.check((row.get)(self))?;
        }
        self.clouds.check()?;
        let l = &self.land;
        if !(0..=20).contains(&l.feature_log2) {
            return Err(Error::invalid(
                "feature_size",
                if l.feature_log2 < -1000 {
                    (-1000 - l.feature_log2).to_string()
                } else {
                    format!("2^{}", l.feature_log2)
                },
                format!("a power of two from 1 to {MAX_FEATURE_SIZE} metres"),
            ));
        }
        // Finest cell feature / 2^(octaves-1) >= 2^MIN_CELL_LOG2.
        let most = (l.feature_log2 - MIN_CELL_LOG2 + 1).clamp(1, MAX_WORLD_OCTAVES as i32);
        if l.octaves as i32 > most {
            return Err(Error::invalid(
                "octaves",
                l.octaves,
                format!(
                    "1..={most} with feature_size {} (finest cell at least 1/128 m)",
                    1u32 << l.feature_log2
                ),
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_wind_blows_away_from_where_it_comes_from() {
        let v = |from_azimuth| {
            Wind {
                speed: 2.0,
                from_azimuth,
            }
            .velocity()
        };
        // A west wind blows east (+x); a north wind (north is -z) blows towards +z.
        assert!((v(270.0) - glam::DVec2::new(2.0, 0.0)).length() < 1e-12);
        assert!((v(0.0) - glam::DVec2::new(0.0, 2.0)).length() < 1e-12);
        assert!((v(90.0) - glam::DVec2::new(-2.0, 0.0)).length() < 1e-12);
    }

    #[test]
    fn defaults_are_valid_and_every_row_round_trips() {
        let p = WorldParams::default();
        p.validate().unwrap();
        for row in &WORLD_PARAMS {
            let text = (row.get)(&p).to_string();
            let mut q = WorldParams::default();
            (row.set)(&mut q, row.parse(&text).unwrap());
            assert_eq!(q, p, "{}", row.key);
        }
    }

    #[test]
    fn bad_values_name_their_parameter() {
        let mut p = WorldParams::default();
        (world_param("feature-size").unwrap().set)(&mut p, Value::Int(3000));
        let e = p.validate().unwrap_err().to_string();
        assert!(e.contains("feature_size") && e.contains("3000"), "{e}");
        let mut p = WorldParams::default();
        p.land.feature_log2 = 2;
        p.land.octaves = 20;
        let e = p.validate().unwrap_err().to_string();
        assert!(e.contains("octaves") && e.contains("1..=10"), "{e}");
        let p = WorldParams {
            pixel_error: 0.0,
            ..Default::default()
        };
        assert!(p
            .validate()
            .unwrap_err()
            .to_string()
            .contains("pixel_error"));
    }
}
