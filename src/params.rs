//! Scene parameters: their defaults (chosen by eye, kept here and nowhere else), their ranges,
//! validation into a typed error, and the TOML scene-file format.

use crate::error::{Error, Result};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// Largest texture side relief bakes; the device's own limit may be lower.
pub const MAX_SIZE: u32 = 16384;
/// Largest grid (vertices per side).
pub const MAX_GRID: u32 = 4096;
/// Largest octave count.
pub const MAX_OCTAVES: u32 = 16;
/// Largest base frequency (lattice cells across the tile).
pub const MAX_FREQUENCY: u32 = 1024;
/// Largest finest-octave period, `frequency << (octaves - 1)`: with `size` at most
/// [`MAX_SIZE`], the shader's integer lattice arithmetic `(2x+1) * period` stays below 2^32.
pub const MAX_PERIOD: u32 = 65536;
/// Largest height scale (world units; the tile is [`crate::WORLD_SIZE`] wide).
pub const MAX_HEIGHT_SCALE: f32 = 10.0;
/// Largest height-AO exponent.
pub const MAX_AO_EXPONENT: f32 = 16.0;
/// Largest |offset| in tiles: beyond 2^40 an f64 keeps too few fractional bits for a texel.
pub const MAX_OFFSET: f64 = 1_099_511_627_776.0;

/// Everything that decides what relief bakes and draws.
///
/// Heights are normalised to 0..1 before `height_scale`; `snow_height` is in those normalised
/// units. Build one with [`TerrainParams::default`] and check it with
/// [`TerrainParams::validate`] (relief's constructors do that for you).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
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

/// How the normal pass makes the normal map.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum NormalMethod {
    /// Wrap-around central differences of the baked heights (two texels apart).
    #[default]
    Differences,
    /// The analytic gradient of the fBm at each texel centre.
    Analytic,
}

impl std::str::FromStr for NormalMethod {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        match s.trim() {
            "differences" => Ok(Self::Differences),
            "analytic" => Ok(Self::Analytic),
            other => Err(Error::invalid("normals", other, "differences or analytic")),
        }
    }
}

impl std::fmt::Display for NormalMethod {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::Differences => "differences",
            Self::Analytic => "analytic",
        })
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
    /// Background colour hosts may clear to (sRGB); relief itself draws no sky.
    pub sky_color: [f32; 3],
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
    /// The grid changed (drawn from a vertex count, so nothing to rebuild but the count).
    pub grid: bool,
}

impl Dirty {
    /// Everything, as after creation.
    pub const ALL: Self = Self {
        resize: true,
        bake: true,
        normals: true,
        grid: true,
    };

    /// Whether any GPU work is owed.
    pub fn any_gpu_work(&self) -> bool {
        self.resize || self.bake || self.normals
    }
}

impl TerrainParams {
    /// Checks every parameter; the error names the first bad one, its value and the range.
    pub fn validate(&self) -> Result<()> {
        let range_u = |name, v: u32, lo: u32, hi: u32| {
            if (lo..=hi).contains(&v) {
                Ok(())
            } else {
                Err(Error::invalid(name, v, format!("{lo}..={hi}")))
            }
        };
        let range_f = |name, v: f32, lo: f32, hi: f32| {
            if v.is_finite() && (lo..=hi).contains(&v) {
                Ok(())
            } else {
                Err(Error::invalid(name, v, format!("{lo}..={hi}")))
            }
        };
        range_u("size", self.size, 1, MAX_SIZE)?;
        range_u("grid", self.grid, 2, MAX_GRID)?;
        range_u("octaves", self.octaves, 1, MAX_OCTAVES)?;
        range_u("frequency", self.frequency, 1, MAX_FREQUENCY)?;
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
        range_f("gain", self.gain, 0.0, 1.0)?;
        range_f("height-scale", self.height_scale, 0.0, MAX_HEIGHT_SCALE)?;
        range_f("snow-height", self.snow_height, 0.0, 1.0)?;
        range_f("ao-exponent", self.ao_exponent, 0.0, MAX_AO_EXPONENT)?;
        for v in self.offset {
            if !v.is_finite() || v.abs() > MAX_OFFSET {
                return Err(Error::invalid(
                    "offset",
                    format!("{},{}", self.offset[0], self.offset[1]),
                    "finite numbers with |x|, |y| <= 2^40 tiles",
                ));
            }
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

    /// What changed between `self` (old) and `new`.
    pub fn diff(&self, new: &Self) -> Dirty {
        let resize = self.size != new.size;
        let bake = resize
            || self.seed != new.seed
            || self.octaves != new.octaves
            || self.frequency != new.frequency
            || self.gain != new.gain
            || self.reduced_offset() != new.reduced_offset();
        Dirty {
            resize,
            bake,
            normals: bake || self.height_scale != new.height_scale || self.normals != new.normals,
            grid: self.grid != new.grid,
        }
    }

    /// The keys [`TerrainParams::set`] accepts, in scene-file spelling.
    pub const KEYS: [&'static str; 11] = [
        "seed",
        "size",
        "grid",
        "octaves",
        "frequency",
        "gain",
        "height_scale",
        "snow_height",
        "ao_exponent",
        "offset",
        "normals",
    ];

    /// Sets one parameter from text (`offset` as `X,Y`), as the web page's controls and URL do.
    /// Does not validate the whole set; call [`TerrainParams::validate`] after.
    pub fn set(&mut self, key: &str, value: &str) -> Result<()> {
        fn num<T: std::str::FromStr>(key: &'static str, v: &str, allowed: &str) -> Result<T> {
            v.trim()
                .parse()
                .map_err(|_| Error::invalid(key, v, allowed))
        }
        let v = value;
        match key {
            "seed" => self.seed = num("seed", v, "0..=4294967295")?,
            "size" => self.size = num("size", v, &format!("1..={MAX_SIZE}"))?,
            "grid" => self.grid = num("grid", v, &format!("2..={MAX_GRID}"))?,
            "octaves" => self.octaves = num("octaves", v, &format!("1..={MAX_OCTAVES}"))?,
            "frequency" => self.frequency = num("frequency", v, &format!("1..={MAX_FREQUENCY}"))?,
            "gain" => self.gain = num("gain", v, "0..=1")?,
            "height_scale" => {
                self.height_scale = num("height-scale", v, &format!("0..={MAX_HEIGHT_SCALE}"))?
            }
            "snow_height" => self.snow_height = num("snow-height", v, "0..=1")?,
            "ao_exponent" => {
                self.ao_exponent = num("ao-exponent", v, &format!("0..={MAX_AO_EXPONENT}"))?
            }
            "offset" => {
                let parts: Vec<&str> = v.split(',').collect();
                let [x, y] = parts.as_slice() else {
                    return Err(Error::invalid("offset", v, "X,Y"));
                };
                self.offset = [
                    num("offset", x, "X,Y with finite numbers")?,
                    num("offset", y, "X,Y with finite numbers")?,
                ];
            }
            "normals" => self.normals = v.parse()?,
            _ => return Err(Error::invalid("key", key, Self::KEYS.join(", "))),
        }
        Ok(())
    }

    /// The value of one key as [`TerrainParams::set`] reads it.
    pub fn get(&self, key: &str) -> Option<String> {
        Some(match key {
            "seed" => self.seed.to_string(),
            "size" => self.size.to_string(),
            "grid" => self.grid.to_string(),
            "octaves" => self.octaves.to_string(),
            "frequency" => self.frequency.to_string(),
            "gain" => self.gain.to_string(),
            "height_scale" => self.height_scale.to_string(),
            "snow_height" => self.snow_height.to_string(),
            "ao_exponent" => self.ao_exponent.to_string(),
            "offset" => format!("{},{}", self.offset[0], self.offset[1]),
            "normals" => self.normals.to_string(),
            _ => return None,
        })
    }

    /// Reads a scene file (TOML; see the README for the format). Missing keys take defaults.
    pub fn from_scene_file(path: &Path) -> Result<Self> {
        let text = std::fs::read_to_string(path).map_err(|e| Error::SceneFile {
            path: path.to_owned(),
            message: e.to_string(),
        })?;
        Self::from_scene_str(&text).map_err(|message| Error::SceneFile {
            path: path.to_owned(),
            message,
        })
    }

    /// Parses scene-file text; the error is one line.
    pub fn from_scene_str(text: &str) -> std::result::Result<Self, String> {
        let mut table: toml::Table = toml::from_str(text).map_err(|e| one_line(&e.to_string()))?;
        if let Some(bake) = table.remove("bake") {
            // Only checked for shape: a scene's bake record does not change what is baked.
            BakeInfo::deserialize(bake)
                .map_err(|e| format!("[bake]: {}", one_line(&e.to_string())))?;
        }
        TerrainParams::deserialize(table).map_err(|e| one_line(&e.to_string()))
    }

    /// The scene file for these parameters, with the height range of a bake if given.
    pub fn to_scene_string(&self, bake: Option<BakeInfo>) -> String {
        let mut body = toml::to_string(self).expect("scene parameters always serialise");
        if let Some(bake) = bake {
            let table = toml::to_string(&bake).expect("bake info always serialises");
            body.push_str(
                "\n# Normalised heights that 0 and 65535 in height.png stand for.\n[bake]\n",
            );
            body.push_str(&table);
        }
        format!("# relief scene file: `relief --scene FILE` reproduces this terrain.\n{body}")
    }
}

/// Largest octave count allowed with `frequency`.
fn max_octaves_for(frequency: u32) -> u32 {
    (1..=MAX_OCTAVES)
        .take_while(|o| u64::from(frequency) << (o - 1) <= u64::from(MAX_PERIOD))
        .last()
        .unwrap_or(0)
}

fn one_line(s: &str) -> String {
    s.lines()
        .map(str::trim)
        .filter(|l| !l.is_empty() && !l.chars().all(|c| c == '|' || c == '^' || c == ' '))
        .collect::<Vec<_>>()
        .join(" ")
}

/// What `relief bake` records beside its images: how to turn 16-bit heights back into heights.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BakeInfo {
    /// Normalised height that 0 in height.png stands for.
    pub height_min: f64,
    /// Normalised height that 65535 in height.png stands for.
    pub height_max: f64,
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
    }

    #[test]
    fn scene_round_trip_and_unknown_keys() {
        let p = TerrainParams {
            seed: 99,
            offset: [0.25, -3.5],
            ..Default::default()
        };
        let info = BakeInfo {
            height_min: 0.1,
            height_max: 0.9,
        };
        let text = p.to_scene_string(Some(info));
        assert_eq!(TerrainParams::from_scene_str(&text).unwrap(), p);
        let err = TerrainParams::from_scene_str("seed = 1\ncolour = 3\n").unwrap_err();
        assert!(err.contains("colour"), "{err}");
        let err = TerrainParams::from_scene_str("seed = \"x\"\n").unwrap_err();
        assert!(err.contains("seed") || err.contains("integer"), "{err}");
        assert!(!err.contains('\n'));
    }

    #[test]
    fn set_and_get_round_trip() {
        let mut p = TerrainParams::default();
        for (k, v) in [
            ("seed", "9"),
            ("gain", "0.25"),
            ("offset", "1.5,-2"),
            ("height_scale", "0.75"),
        ] {
            p.set(k, v).unwrap();
            assert_eq!(p.get(k).unwrap(), v);
        }
        let mut q = TerrainParams::default();
        for k in TerrainParams::KEYS {
            q.set(k, &p.get(k).unwrap()).unwrap();
        }
        assert_eq!(p, q);
        let e = p.set("gain", "lots").unwrap_err().to_string();
        assert!(e.contains("gain") && e.contains("lots"), "{e}");
        assert!(p.set("colour", "1").is_err());
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
        assert_eq!(a.diff(&d), Dirty::default());
    }
}
