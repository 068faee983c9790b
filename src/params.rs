//! Scene parameters: their defaults (chosen by eye, kept here and nowhere else), their ranges
//! and what a change re-does, all in one table ([`PARAMS`]) that the CLI, scene files, the
//! page's URL and controls, and validation read.

use crate::error::{Error, Result};
use crate::table::{self, Control, Kind, Param, Value};

/// Largest texture side relief bakes; the device's own limit may be lower.
pub const MAX_SIZE: u32 = 16384;
/// Largest grid (vertices per side).
pub(crate) const MAX_GRID: u32 = 4096;
/// Largest octave count.
pub(crate) const MAX_OCTAVES: u32 = 16;
/// Largest base frequency (lattice cells across the tile).
pub const MAX_FREQUENCY: u32 = 1024;
/// Largest finest-octave period, `frequency << (octaves - 1)`: with `size` at most
/// [`MAX_SIZE`], the shader's integer lattice arithmetic `(2x+1) * period` stays below 2^32.
pub(crate) const MAX_PERIOD: u32 = 65536;
/// Largest height scale (world units; the tile is [`crate::WORLD_SIZE`] wide).
pub(crate) const MAX_HEIGHT_SCALE: f32 = 10.0;
/// Largest height-AO exponent.
pub(crate) const MAX_AO_EXPONENT: f32 = 16.0;
/// Largest |offset| in tiles: beyond 2^40 an f64 keeps too few fractional bits for a texel.
pub(crate) const MAX_OFFSET: f64 = 1_099_511_627_776.0;

/// Everything that decides what relief bakes and draws.
///
/// Heights are normalised to 0..1 before `height_scale`; `snow_height` is in those normalised
/// units. Build one with [`TerrainParams::default`] and check it with
/// [`TerrainParams::validate`] (relief's constructors do that for you). Each field is a row of
/// [`PARAMS`], which gives its range and what changing it re-does.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TerrainParams {
    /// Hash seed: the same seed gives the same terrain everywhere.
    pub seed: u32,
    /// Side of the baked textures in texels.
    pub size: u32,
    /// Vertices per side of the displaced grid mesh (independent of `size`).
    pub grid: u32,
    /// fBm octaves.
    pub octaves: u32,
    /// Lattice cells across the tile at the first octave (an integer, so the tile is periodic).
    pub frequency: u32,
    /// Amplitude ratio between successive octaves.
    pub gain: f32,
    /// World height of a normalised height of 1.
    pub height_scale: f32,
    /// Normalised height above which snow lies.
    pub snow_height: f32,
    /// Exponent k of the height ambient occlusion h^k (0 turns it off).
    pub ao_exponent: f32,
    /// Scroll offset in tiles; 1.0 is one whole tile and gives the same texture as 0.0.
    pub offset: [f64; 2],
    /// How the normal map is made.
    pub normals: NormalMethod,
}

/// What changing a parameter makes relief redo.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Redo {
    /// Rebuild the textures (their size changed), then bake and derive normals.
    Textures,
    /// Bake heights and colour again, then the normals.
    Bake,
    /// Bake again only if the part-tile offset changed (a whole-tile scroll shows the same
    /// periodic terrain).
    BakeIfPartTile,
    /// Derive the normal map again.
    Normals,
    /// Nothing baked: the next frame draws with the new value.
    Draw,
}

/// One row of the scene's parameter table.
pub type SceneParam = Param<TerrainParams>;

macro_rules! float_param {
    ($key:literal, $field:ident, $min:expr, $max:expr, $control:expr, $redo:expr, $doc:literal) => {
        (
            Param {
                key: $key,
                doc: $doc,
                kind: Kind::Float {
                    min: $min,
                    max: $max,
                },
                control: $control,
                get: |p: &TerrainParams| Value::Float(p.$field),
                set: |p: &mut TerrainParams, v| {
                    if let Value::Float(x) = v {
                        p.$field = x;
                    }
                },
            },
            $redo,
        )
    };
}

macro_rules! int_param {
    ($key:literal, $field:ident, $min:expr, $max:expr, $control:expr, $redo:expr, $doc:literal) => {
        (
            Param {
                key: $key,
                doc: $doc,
                kind: Kind::Int {
                    min: $min,
                    max: $max,
                },
                control: $control,
                get: |p: &TerrainParams| Value::Int(p.$field),
                set: |p: &mut TerrainParams, v| {
                    if let Value::Int(x) = v {
                        p.$field = x;
                    }
                },
            },
            $redo,
        )
    };
}

const fn slider(min: f64, max: f64, step: f64) -> Control {
    Control::Slider { min, max, step }
}

/// The scene's parameters, in the order of scene files, `--help` and the page's controls,
/// each with what changing it re-does. Defaults are [`TerrainParams::default`]'s values.
pub static PARAMS: [(SceneParam, Redo); 11] = [
    int_param!(
        "seed",
        seed,
        0,
        u32::MAX,
        Control::Number,
        Redo::Bake,
        "hash seed: the same seed gives the same terrain on every GPU and on the CPU"
    ),
    int_param!(
        "size",
        size,
        1,
        MAX_SIZE,
        slider(16.0, 2048.0, 16.0),
        Redo::Textures,
        "side of the baked textures in texels (the device's limit may be lower)"
    ),
    int_param!(
        "grid",
        grid,
        2,
        MAX_GRID,
        slider(2.0, 1024.0, 1.0),
        Redo::Draw,
        "the finest mesh: about this many vertices across the tile (its spacing rounded to a power of two; levels of detail draw coarser where a pixel allows)"
    ),
    int_param!(
        "octaves",
        octaves,
        1,
        MAX_OCTAVES,
        slider(1.0, 12.0, 1.0),
        Redo::Bake,
        "fBm octaves, with frequency x 2^(octaves-1) <= 65536"
    ),
    int_param!(
        "frequency",
        frequency,
        1,
        MAX_FREQUENCY,
        slider(1.0, 16.0, 1.0),
        Redo::Bake,
        "lattice cells across the tile at octave 0 (an integer: the tile is periodic)"
    ),
    float_param!(
        "gain",
        gain,
        0.0,
        1.0,
        slider(0.0, 1.0, 0.01),
        Redo::Bake,
        "amplitude ratio between octaves"
    ),
    float_param!(
        "height_scale",
        height_scale,
        0.0,
        MAX_HEIGHT_SCALE,
        slider(0.0, 2.0, 0.01),
        Redo::Normals,
        "world height of normalised height 1 (the tile is 2 units wide)"
    ),
    float_param!(
        "snow_height",
        snow_height,
        0.0,
        1.0,
        slider(0.0, 1.0, 0.01),
        Redo::Draw,
        "normalised height (0..1) above which snow lies"
    ),
    float_param!(
        "ao_exponent",
        ao_exponent,
        0.0,
        MAX_AO_EXPONENT,
        slider(0.0, 4.0, 0.05),
        Redo::Draw,
        "height ambient occlusion h^k (0 turns it off)"
    ),
    (
        Param {
            key: "offset",
            doc: "scroll offset in tiles as X,Y (1,0 is a whole tile: the same terrain)",
            kind: Kind::Pair { max: MAX_OFFSET },
            control: Control::None,
            get: |p: &TerrainParams| Value::Pair(p.offset),
            set: |p: &mut TerrainParams, v| {
                if let Value::Pair(x) = v {
                    p.offset = x;
                }
            },
        },
        Redo::BakeIfPartTile,
    ),
    (
        Param {
            key: "normals",
            doc: "normal map from central differences of the heights, or the analytic gradient",
            kind: Kind::Choice(NormalMethod::NAMES),
            control: Control::Select,
            get: |p: &TerrainParams| Value::Choice(p.normals.name()),
            set: |p: &mut TerrainParams, v| {
                if let Value::Choice(name) = v {
                    p.normals = NormalMethod::from_name(name).unwrap_or_default();
                }
            },
        },
        Redo::Normals,
    ),
];

/// The rows of [`PARAMS`] without their redo column.
pub fn params() -> impl Iterator<Item = &'static SceneParam> {
    PARAMS.iter().map(|(p, _)| p)
}

/// The row for `key` (scene-file spelling; dashes accepted).
pub fn param(key: &str) -> Option<&'static SceneParam> {
    let key = key.trim().replace('-', "_");
    params().find(|p| p.key == key)
}

/// How the normal pass makes the normal map.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum NormalMethod {
    /// Wrap-around central differences of the baked heights (two texels apart).
    #[default]
    Differences,
    /// The analytic gradient of the fBm at each texel centre.
    Analytic,
}

impl NormalMethod {
    /// Every method's name, as the CLI, scene files and the page spell it.
    pub const NAMES: &'static [&'static str] = &["differences", "analytic"];

    /// The method's name.
    pub fn name(self) -> &'static str {
        match self {
            Self::Differences => "differences",
            Self::Analytic => "analytic",
        }
    }

    /// The method called `name`.
    pub fn from_name(name: &str) -> Option<Self> {
        match name.trim() {
            "differences" => Some(Self::Differences),
            "analytic" => Some(Self::Analytic),
            _ => None,
        }
    }
}

impl std::str::FromStr for NormalMethod {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        Self::from_name(s)
            .ok_or_else(|| Error::invalid("normals", table::shorten(s), "differences or analytic"))
    }
}

impl std::fmt::Display for NormalMethod {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl Default for TerrainParams {
    fn default() -> Self {
        Self {
            seed: 7,
            size: 1024,
            grid: 256,
            octaves: 8,
            frequency: 4,
            gain: 0.47,
            height_scale: 0.5,
            snow_height: 0.63,
            ao_exponent: 1.0,
            offset: [0.0, 0.0],
            normals: NormalMethod::Differences,
        }
    }
}

/// How the terrain is lit and coloured. Colours are sRGB (as a user picks them); relief
/// converts them to linear before shading. Changing these never re-bakes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Shading {
    /// Direction towards the sun (need not be unit length).
    pub sun_direction: [f32; 3],
    /// Sun colour (sRGB) and its intensity multiplier.
    pub sun_color: [f32; 3],
    /// Sun intensity.
    pub sun_intensity: f32,
    /// Ambient sky colour (sRGB) and its intensity.
    pub ambient_color: [f32; 3],
    /// Ambient intensity.
    pub ambient_intensity: f32,
    /// Albedo where the colour channel is low (sRGB).
    pub color_a: [f32; 3],
    /// Albedo where the colour channel is high (sRGB).
    pub color_b: [f32; 3],
    /// Snow albedo (sRGB).
    pub snow_color: [f32; 3],
    /// Blinn-Phong exponent.
    pub shininess: f32,
    /// Specular strength.
    pub specular: f32,
    /// Background colour hosts may clear to (sRGB), and the flat sky relief draws where
    /// [`Shading::sky`] is off.
    pub sky_color: [f32; 3],
    /// Draws the sky (gradient, sun disc and halo; `crate::sky`) behind the terrain and in
    /// the ray casters' misses. Off: they show the flat `sky_color`, and a host's own
    /// background drawn before relief stays where relief draws nothing.
    pub sky: bool,
}

impl Default for Shading {
    fn default() -> Self {
        Self {
            sun_direction: [-0.55, 0.6, -0.45],
            sun_color: [1.0, 0.96, 0.88],
            sun_intensity: 1.5,
            ambient_color: [0.62, 0.74, 0.92],
            ambient_intensity: 0.35,
            color_a: [0.40, 0.50, 0.24],
            color_b: [0.60, 0.52, 0.40],
            snow_color: [0.95, 0.96, 0.98],
            shininess: 24.0,
            specular: 0.25,
            sky_color: [0.64, 0.76, 0.90],
            sky: true,
        }
    }
}

/// sRGB-encoded component to linear.
pub fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// Which stages a parameter change invalidates.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Dirty {
    /// Texture size changed: textures and bind groups must be recreated.
    pub resize: bool,
    /// The noise changed: the bake pass must run.
    pub bake: bool,
    /// Heights or their scale changed: the normal pass must run.
    pub normals: bool,
    /// Something only the draw reads changed (grid, snow, AO): nothing to bake.
    pub draw: bool,
}

impl Dirty {
    /// Everything, as after creation.
    pub const ALL: Self = Self {
        resize: true,
        bake: true,
        normals: true,
        draw: true,
    };

    /// Whether any GPU work is owed.
    pub fn any_gpu_work(&self) -> bool {
        self.resize || self.bake || self.normals
    }

    fn add(&mut self, redo: Redo) {
        match redo {
            Redo::Textures => *self = Self::ALL,
            Redo::Bake | Redo::BakeIfPartTile => {
                self.bake = true;
                self.normals = true;
            }
            Redo::Normals => self.normals = true,
            Redo::Draw => {}
        }
        self.draw = true;
    }
}

impl TerrainParams {
    /// Checks every parameter against [`PARAMS`]; the error names the first bad one, its
    /// value and the range.
    pub fn validate(&self) -> Result<()> {
        for p in params() {
            p.check((p.get)(self))?;
        }
        let finest = u64::from(self.frequency) << (self.octaves - 1);
        if finest > u64::from(MAX_PERIOD) {
            return Err(Error::invalid(
                "octaves",
                self.octaves,
                format!(
                    "at most {} with frequency {} (frequency x 2^(octaves-1) <= {MAX_PERIOD})",
                    max_octaves_for(self.frequency),
                    self.frequency
                ),
            ));
        }
        Ok(())
    }

    /// Checks the parts that depend on the device (texture size limit).
    pub fn validate_for(&self, limits: &wgpu::Limits) -> Result<()> {
        self.validate()?;
        let max = limits.max_texture_dimension_2d.min(MAX_SIZE);
        if self.size > max {
            return Err(Error::invalid(
                "size",
                self.size,
                format!("1..={max} on this device"),
            ));
        }
        Ok(())
    }

    /// The scroll offset reduced to [0, 1) tiles in f64: the GPU only ever sees this.
    pub fn reduced_offset(&self) -> [f64; 2] {
        self.offset.map(|v| {
            let r = v.rem_euclid(1.0);
            // rem_euclid can round up to exactly 1.0 for tiny negative inputs.
            if r >= 1.0 {
                0.0
            } else {
                r
            }
        })
    }

    /// What changed between `self` (old) and `new`, from the table's redo column.
    pub fn diff(&self, new: &Self) -> Dirty {
        let mut dirty = Dirty::default();
        for (p, redo) in &PARAMS {
            if (p.get)(self) == (p.get)(new) {
                continue;
            }
            if *redo == Redo::BakeIfPartTile && self.reduced_offset() == new.reduced_offset() {
                continue;
            }
            dirty.add(*redo);
        }
        dirty
    }

    /// The keys [`TerrainParams::set`] accepts, in scene-file spelling and table order.
    pub fn keys() -> impl Iterator<Item = &'static str> {
        params().map(|p| p.key)
    }

    /// Sets one parameter from text (`offset` as `X,Y`), as the CLI, the page's controls and
    /// URL do: the value is checked against its own range; call [`TerrainParams::validate`]
    /// for the rules between parameters. On error nothing changes.
    pub fn set(&mut self, key: &str, value: &str) -> Result<()> {
        match param(key) {
            Some(p) => p.set_text(self, value),
            None => Err(Error::invalid(
                "key",
                table::shorten(key),
                Self::keys().collect::<Vec<_>>().join(", "),
            )),
        }
    }

    /// The value of one key as [`TerrainParams::set`] reads it.
    pub fn get(&self, key: &str) -> Option<String> {
        param(key).map(|p| (p.get)(self).to_string())
    }
}

/// Largest octave count allowed with `frequency` (at least 1: frequency is at most
/// [`MAX_FREQUENCY`], whose first octave is always allowed).
pub fn max_octaves_for(frequency: u32) -> u32 {
    (1..=MAX_OCTAVES)
        .take_while(|o| u64::from(frequency) << (o - 1) <= u64::from(MAX_PERIOD))
        .last()
        .unwrap_or(1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_valid() {
        TerrainParams::default().validate().unwrap();
    }

    #[test]
    fn errors_name_parameter_value_and_range() {
        let p = TerrainParams {
            gain: f32::NAN,
            ..Default::default()
        };
        let msg = p.validate().unwrap_err().to_string();
        assert!(
            msg.contains("gain") && msg.contains("NaN") && msg.contains("0..=1"),
            "{msg}"
        );
        let p = TerrainParams {
            frequency: 1024,
            octaves: 16,
            ..Default::default()
        };
        let msg = p.validate().unwrap_err().to_string();
        assert!(
            msg.contains("octaves") && msg.contains("at most 7"),
            "{msg}"
        );
        let p = TerrainParams {
            offset: [1e300, 0.0],
            ..Default::default()
        };
        let msg = p.validate().unwrap_err().to_string();
        assert!(msg.contains("1e300") && msg.len() < 120, "{msg}");
    }

    #[test]
    fn set_and_get_round_trip() {
        let mut p = TerrainParams::default();
        for (k, v) in [
            ("seed", "9"),
            ("gain", "0.25"),
            ("offset", "1.5,-2"),
            ("height_scale", "0.75"),
            ("normals", "analytic"),
        ] {
            p.set(k, v).unwrap();
            assert_eq!(p.get(k).unwrap(), v);
        }
        let mut q = TerrainParams::default();
        for k in TerrainParams::keys() {
            q.set(k, &p.get(k).unwrap()).unwrap();
        }
        assert_eq!(p, q);
        let before = p;
        let e = p.set("gain", "lots").unwrap_err().to_string();
        assert!(e.contains("gain") && e.contains("lots"), "{e}");
        assert!(p.set("colour", "1").is_err());
        assert!(p.set("normals", "exact").is_err());
        assert_eq!(p, before, "a refused value changes nothing");
    }

    #[test]
    fn every_row_round_trips_and_has_its_default_in_range() {
        let d = TerrainParams::default();
        for p in params() {
            let v = (p.get)(&d);
            p.check(v).unwrap();
            assert_eq!(p.parse(&v.to_string()).unwrap(), v, "{}", p.key);
            assert!(!p.doc.is_empty());
        }
    }

    #[test]
    fn diff_tracks_what_to_rebake() {
        let a = TerrainParams::default();
        let b = TerrainParams {
            height_scale: 1.0,
            ..a
        };
        assert_eq!(
            a.diff(&b),
            Dirty {
                normals: true,
                draw: true,
                ..Default::default()
            }
        );
        let c = TerrainParams {
            offset: [1.0, -2.0],
            ..a
        };
        assert!(
            !a.diff(&c).any_gpu_work(),
            "whole-tile scroll changes nothing"
        );
        let d = TerrainParams {
            snow_height: 0.1,
            ..a
        };
        assert!(!a.diff(&d).any_gpu_work());
        let e = TerrainParams { size: 64, ..a };
        assert_eq!(a.diff(&e), Dirty::ALL);
        let f = TerrainParams {
            normals: NormalMethod::Analytic,
            ..a
        };
        assert!(f.diff(&a).normals && !f.diff(&a).bake);
        assert_eq!(a.diff(&a), Dirty::default());
    }
}
