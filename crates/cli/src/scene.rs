//! Scene files (TOML): every key of [`relief::params::PARAMS`], all optional, plus the `[bake]`
//! record `relief bake` writes. Reading and writing both go through the parameter table, so a
//! new parameter is a new key here without any code in this file. A file with
//! `world = "endless"` holds the endless world's keys ([`relief::world::WORLD_PARAMS`]) instead;
//! either may carry a `[camera]` table ([`SceneCamera`]).

use crate::shown::toml_shown;
use relief::error::{Error, Result};
use relief::params::{param, params, SceneParam, TerrainParams};
use relief::table::{self, Kind, Value};
use relief::world::{WorldKind, WorldParam};
use std::path::Path;

/// What `relief bake` records beside its images: how to turn 16-bit heights back into heights.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BakeInfo {
    /// Normalised height that 0 in height.png stands for.
    pub height_min: f64,
    /// Normalised height that 65535 in height.png stands for (equal to `height_min` when the
    /// bake is flat; height.png is then all 0).
    pub height_max: f64,
}

/// Longest scene file read: far more than any real one, small enough to refuse a wrong file
/// (an image, a log) with one line instead of parsing megabytes.
pub const MAX_SCENE_BYTES: u64 = 1 << 20;

/// The keys of a scene file with their values as text, in file order, each checked for its
/// key and TOML type but not yet for its range (so a flag can still override a bad value).
pub type Entries = Vec<(&'static SceneParam, String)>;

/// Reads a scene file's entries (see [`Entries`]); errors name the file.
pub fn read_entries(path: &Path) -> Result<Entries> {
    let fail = |message: String| Error::SceneFile {
        path: path.to_owned(),
        message,
    };
    let text = read_text(path)?;
    parse_entries(&text).map_err(|e| match e {
        Error::SceneFile { message, .. } => fail(message),
        other => fail(other.to_string()),
    })
}

/// Parses scene-file text into its entries (see [`Entries`]).
pub fn parse_entries(text: &str) -> Result<Entries> {
    let fail = |message: String| Error::SceneFile {
        path: Default::default(),
        message,
    };
    let mut table: toml::Table = text
        .parse()
        .map_err(|e: toml::de::Error| fail(syntax_error(text, &e)))?;
    if let Some(bake) = table.remove("bake") {
        // Only checked for shape: a scene's bake record does not change what is baked.
        BakeInfo::from_toml(&bake)?;
    }
    match table.remove("world") {
        None => {}
        Some(toml::Value::String(w)) if w == "tile" => {}
        Some(other) => {
            return Err(fail(format!(
                "world = {} here, but --world tile was given (drop --world, or make it match)",
                toml_shown(&other)
            )))
        }
    }
    // Read by `SceneCamera::from_table`.
    table.remove("camera");
    let mut out = Vec::with_capacity(table.len());
    for (key, value) in &table {
        let row = param(key).filter(|r| r.key == key).ok_or_else(|| {
            Error::invalid(
                "key",
                table::shorten(key),
                TerrainParams::keys().collect::<Vec<_>>().join(", "),
            )
        })?;
        let text = toml_text(row.kind, value).ok_or_else(|| wrong_type(row, value))?;
        out.push((row, text));
    }
    Ok(out)
}

/// A scene file's text, at most [`MAX_SCENE_BYTES`]; errors name the file.
fn read_text(path: &Path) -> Result<String> {
    let fail = |message: String| Error::SceneFile {
        path: path.to_owned(),
        message,
    };
    use std::io::Read;
    // Read at most one byte past the limit: a pipe or a device (`/dev/zero`, `<(yes)`) reports
    // no size, so the size is what is read, never what the file claims.
    let file = std::fs::File::open(path).map_err(|e| fail(e.to_string()))?;
    let mut bytes = Vec::new();
    file.take(MAX_SCENE_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| fail(e.to_string()))?;
    if bytes.len() as u64 > MAX_SCENE_BYTES {
        return Err(fail(format!(
            "more than {MAX_SCENE_BYTES} bytes; a scene file is at most {MAX_SCENE_BYTES}"
        )));
    }
    String::from_utf8(bytes).map_err(|_| fail("not UTF-8 text (a scene file is TOML)".into()))
}

/// A scene file's TOML, checked for size and syntax; errors name the file.
fn load(path: &Path) -> Result<toml::Table> {
    let text = read_text(path)?;
    text.parse().map_err(|e: toml::de::Error| Error::SceneFile {
        path: path.to_owned(),
        message: syntax_error(&text, &e),
    })
}

/// A TOML syntax error as one short line: where (line and column, from 1) and what.
fn syntax_error(text: &str, e: &toml::de::Error) -> String {
    let what = one_line(e.message());
    let Some(span) = e.span() else {
        return table::shorten_to(&format!("TOML: {what}"), 160);
    };
    let before = &text.as_bytes()[..span.start.min(text.len())];
    let line = before.iter().filter(|&&b| b == b'\n').count() + 1;
    let line_start = before
        .iter()
        .rposition(|&b| b == b'\n')
        .map_or(0, |i| i + 1);
    let column = String::from_utf8_lossy(&before[line_start..])
        .chars()
        .count()
        + 1;
    table::shorten_to(&format!("TOML line {line}, column {column}: {what}"), 160)
}

/// The world a scene file describes: its `world` key (`"tile"` or `"endless"`), tile without one.
pub fn scene_world(path: &Path) -> Result<WorldKind> {
    let table = load(path)?;
    match table.get("world") {
        None => Ok(WorldKind::Tile),
        Some(toml::Value::String(w)) if WorldKind::from_name(w).is_some() => {
            Ok(WorldKind::from_name(w).unwrap_or_default())
        }
        Some(other) => Err(Error::SceneFile {
            path: path.to_owned(),
            message: format!(
                "invalid world: {} (allowed: tile or endless)",
                toml_shown(other)
            ),
        }),
    }
}

/// The `[camera]` table of a scene file, each part optional (flags override each).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SceneCamera {
    /// `camera`: orbit, fly or path.
    pub camera: Option<String>,
    /// `eye = [x, y, z]`.
    pub eye: Option<[f64; 3]>,
    /// `look_at = [x, y, z]`.
    pub look_at: Option<[f64; 3]>,
    /// `fov`, vertical, degrees.
    pub fov: Option<f64>,
    /// `time` along the path, seconds.
    pub time: Option<f64>,
}

impl SceneCamera {
    /// The keys of a `[camera]` table.
    pub const KEYS: [&'static str; 5] = ["camera", "eye", "look_at", "fov", "time"];

    /// Reads the `[camera]` table of the scene file at `path` (empty without one). Types are
    /// checked here, ranges where the camera is made.
    pub fn read(path: &Path) -> Result<Self> {
        let table = load(path)?;
        Self::from_table(table.get("camera")).map_err(|message| Error::SceneFile {
            path: path.to_owned(),
            message,
        })
    }

    fn from_table(value: Option<&toml::Value>) -> std::result::Result<Self, String> {
        let Some(value) = value else {
            return Ok(Self::default());
        };
        let t = value
            .as_table()
            .ok_or_else(|| "camera: not a table ([camera])".to_owned())?;
        if let Some(k) = t.keys().find(|k| !Self::KEYS.contains(&k.as_str())) {
            return Err(format!(
                "invalid key: [camera] {} (allowed: {})",
                table::shorten(k),
                Self::KEYS.join(", ")
            ));
        }
        let num = |v: &toml::Value| v.as_float().or(v.as_integer().map(|i| i as f64));
        let number = |k: &str| -> std::result::Result<Option<f64>, String> {
            t.get(k)
                .map(|v| {
                    num(v).ok_or_else(|| {
                        format!("invalid [camera] {k}: {} (a number)", toml_shown(v))
                    })
                })
                .transpose()
        };
        let point = |k: &str| -> std::result::Result<Option<[f64; 3]>, String> {
            t.get(k)
                .map(|v| {
                    let bad = || {
                        format!(
                            "invalid [camera] {k}: {} (allowed: [x, y, z], three numbers)",
                            toml_shown(v)
                        )
                    };
                    let a = v.as_array().filter(|a| a.len() == 3).ok_or_else(bad)?;
                    let mut out = [0.0; 3];
                    for (o, x) in out.iter_mut().zip(a) {
                        *o = num(x).ok_or_else(bad)?;
                    }
                    Ok(out)
                })
                .transpose()
        };
        let camera = t
            .get("camera")
            .map(|v| {
                v.as_str().map(str::to_owned).ok_or_else(|| {
                    format!(
                        "invalid [camera] camera: {} (allowed: orbit, fly or path)",
                        toml_shown(v)
                    )
                })
            })
            .transpose()?;
        Ok(Self {
            camera,
            eye: point("eye")?,
            look_at: point("look_at")?,
            fov: number("fov")?,
            time: number("time")?,
        })
    }
}

/// The endless world's entries of a scene file (`world = "endless"`): its keys with their
/// values as text, checked for key and type ([`relief::world::WORLD_PARAMS`]); `[bake]` and
/// `[camera]` are left to their readers.
pub fn read_world_entries(path: &Path) -> Result<Vec<(&'static WorldParam, String)>> {
    let fail = |message: String| Error::SceneFile {
        path: path.to_owned(),
        message,
    };
    let mut table = load(path)?;
    match table.remove("world") {
        Some(toml::Value::String(w)) if w == "endless" => {}
        other => {
            return Err(fail(match other {
                None => "a tile scene (no world key), but --world endless was given (drop \
                         --world, or write world = \"endless\" in the file)"
                    .to_owned(),
                Some(v) => format!(
                    "world = {} here, but --world endless was given (drop --world, or make \
                     it match)",
                    toml_shown(&v)
                ),
            }))
        }
    }
    // The record of a region bake; it does not change the world.
    table.remove("bake");
    table.remove("camera");
    // What the props are: read by `read_world_props`.
    for t in crate::props_scene::TABLES {
        table.remove(t);
    }
    let mut out = Vec::with_capacity(table.len());
    for (key, value) in &table {
        let row = relief::world::world_param(key)
            .filter(|r| r.key == key)
            .ok_or_else(|| {
                // The keys no longer fit on an error's line: the nearest, and where they are.
                let keys = relief::world::WORLD_PARAMS.iter().map(|r| r.key);
                let tables = ["world", "camera", "bake"]
                    .into_iter()
                    .chain(crate::props_scene::TABLES);
                let near = closest(key, keys.chain(tables));
                fail(format!(
                    "invalid key: {} (did you mean {near}? docs/cli.md lists the keys)",
                    table::shorten(key),
                ))
            })?;
        let text =
            toml_text(row.kind, value).ok_or_else(|| fail(wrong_type(row, value).to_string()))?;
        out.push((row, text));
    }
    Ok(out)
}

/// The props of an endless-world scene file (docs/props.md), or `None` where it gives
/// none of their tables (the shipped landscape's props); errors name the file and the key.
pub fn read_world_props(path: &Path) -> Result<Option<relief::props::Scene>> {
    let table = load(path)?;
    crate::props_scene::read(&table).map_err(|e| Error::SceneFile {
        path: path.to_owned(),
        message: e.to_string(),
    })
}

/// Scene files for [`TerrainParams`]: the core knows the parameter table, the `relief`
/// program knows TOML.
pub trait SceneFile: Sized {
    /// Reads a scene file. Missing keys take defaults; unknown keys, wrong types and values
    /// out of range are errors naming the file, the key and the allowed range.
    fn from_scene_file(path: &Path) -> Result<Self>;
    /// Parses scene-file text (errors carry an empty path).
    fn from_scene_str(text: &str) -> Result<Self>;
    /// The scene file for these parameters, with the height range of a bake if given.
    fn to_scene_string(&self, bake: Option<BakeInfo>) -> String;
}

impl SceneFile for TerrainParams {
    fn from_scene_file(path: &Path) -> Result<Self> {
        let entries = read_entries(path)?;
        params_from_entries(&entries).map_err(|e| Error::SceneFile {
            path: path.to_owned(),
            message: e.to_string(),
        })
    }

    fn from_scene_str(text: &str) -> Result<Self> {
        params_from_entries(&parse_entries(text)?)
    }

    fn to_scene_string(&self, bake: Option<BakeInfo>) -> String {
        let mut out =
            String::from("# relief scene file: `relief --scene FILE` reproduces this terrain.\n");
        for row in params() {
            out.push_str(&format!("{} = {}\n", row.key, toml_value((row.get)(self))));
        }
        if let Some(b) = bake {
            out.push_str("\n# Normalised heights that 0 and 65535 in height.png stand for.\n");
            out.push_str("[bake]\n");
            out.push_str(&format!("height_min = {:?}\n", b.height_min));
            out.push_str(&format!("height_max = {:?}\n", b.height_max));
        }
        out
    }
}

fn params_from_entries(entries: &Entries) -> Result<TerrainParams> {
    let mut p = TerrainParams::default();
    for (row, text) in entries {
        row.set_text(&mut p, text)?;
    }
    p.validate()?;
    Ok(p)
}

impl BakeInfo {
    fn from_toml(value: &toml::Value) -> Result<Self> {
        let bad = |what: &str| Error::SceneFile {
            path: Default::default(),
            message: format!("[bake]: {what} (expected height_min and height_max numbers)"),
        };
        let t = value.as_table().ok_or_else(|| bad("not a table"))?;
        if let Some(k) = t.keys().find(|k| *k != "height_min" && *k != "height_max") {
            return Err(bad(&format!("unknown key {}", table::shorten(k))));
        }
        let num = |k: &str| {
            t.get(k)
                .and_then(|v| v.as_float().or(v.as_integer().map(|i| i as f64)))
                .ok_or_else(|| bad(&format!("{k} missing or not a number")))
        };
        Ok(Self {
            height_min: num("height_min")?,
            height_max: num("height_max")?,
        })
    }
}

/// The text a TOML value stands for as a value of `kind`, if its TOML type fits the kind.
fn toml_text(kind: Kind, v: &toml::Value) -> Option<String> {
    use toml::Value as T;
    Some(match (kind, v) {
        (Kind::Int { .. }, T::Integer(i)) => i.to_string(),
        // Debug keeps huge and tiny numbers short (1e300, not 301 digits) and reads back exactly.
        (Kind::Float { .. }, T::Float(f)) => format!("{f:?}"),
        (Kind::Float { .. }, T::Integer(i)) => i.to_string(),
        (Kind::Choice(_), T::String(s)) => s.clone(),
        (Kind::Bool, T::Boolean(b)) => b.to_string(),
        (Kind::Pair { .. }, T::Array(a)) if a.len() == 2 => {
            let n = |v: &T| v.as_float().or(v.as_integer().map(|i| i as f64));
            format!("{:?},{:?}", n(&a[0])?, n(&a[1])?)
        }
        _ => return None,
    })
}

/// The error for a value of the wrong TOML type for `row`: the value as written, and the type
/// and range the key takes (`octaves = 3.0` is not a whole number).
fn wrong_type<T>(row: &table::Param<T>, value: &toml::Value) -> Error {
    let what = match row.kind {
        Kind::Int { .. } => "a whole number, ",
        Kind::Float { .. } => "a number, ",
        Kind::Choice(_) => "a string: ",
        Kind::Bool => "true or false",
        Kind::Pair { .. } => "[x, y], ",
    };
    let allowed = match row.kind {
        Kind::Bool => String::new(),
        Kind::Choice(names) => names
            .iter()
            .map(|n| format!("{n:?}"))
            .collect::<Vec<_>>()
            .join(", "),
        _ => row.allowed(),
    };
    Error::invalid(row.key, toml_shown(value), format!("{what}{allowed}"))
}

/// A value as TOML text: floats always with a point or exponent, pairs as arrays.
pub fn toml_value(v: Value) -> String {
    match v {
        Value::Int(i) => i.to_string(),
        Value::Float(f) => format!("{f:?}"),
        Value::Pair([x, y]) => format!("[{x:?}, {y:?}]"),
        Value::Choice(s) => format!("{s:?}"),
        Value::Bool(b) => b.to_string(),
    }
}

fn one_line(s: &str) -> String {
    s.lines()
        .map(str::trim)
        .filter(|l| !l.is_empty() && !l.chars().all(|c| c == '|' || c == '^' || c == ' '))
        .collect::<Vec<_>>()
        .join(" ")
}

/// The candidate nearest to `word` by edit distance (the first of equals).
fn closest<'a>(word: &str, candidates: impl Iterator<Item = &'a str>) -> &'a str {
    let distance = |a: &str, b: &str| {
        let b: Vec<char> = b.chars().collect();
        let mut row: Vec<usize> = (0..=b.len()).collect();
        for (i, ca) in a.chars().enumerate() {
            let mut diagonal = row[0];
            row[0] = i + 1;
            for (j, &cb) in b.iter().enumerate() {
                let next = (diagonal + usize::from(ca != cb))
                    .min(row[j] + 1)
                    .min(row[j + 1] + 1);
                diagonal = row[j + 1];
                row[j + 1] = next;
            }
        }
        row[b.len()]
    };
    candidates
        .min_by_key(|c| distance(word, c))
        .unwrap_or("world")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scene_round_trip_and_unknown_keys() {
        let p = TerrainParams {
            seed: 99,
            offset: [0.25, -3.5],
            gain: 0.3,
            normals: relief::NormalMethod::Analytic,
            ..Default::default()
        };
        let info = BakeInfo {
            height_min: 0.1,
            height_max: 0.9,
        };
        let text = p.to_scene_string(Some(info));
        assert!(text.contains("normals = \"analytic\""), "{text}");
        assert!(text.contains("gain = 0.3\n"), "{text}");
        let q = TerrainParams::from_scene_str(&text).unwrap();
        assert_eq!(q, p);
        assert_eq!(q.to_scene_string(Some(info)), text, "byte for byte");
        let err = TerrainParams::from_scene_str("seed = 1\ncolour = 3\n")
            .unwrap_err()
            .to_string();
        assert!(err.contains("colour"), "{err}");
        let err = TerrainParams::from_scene_str("seed = \"x\"\n")
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("seed") && err.contains("0..=4294967295"),
            "{err}"
        );
        assert!(!err.contains('\n'));
        let err = TerrainParams::from_scene_str("octaves = 3.0\n")
            .unwrap_err()
            .to_string();
        assert!(err.contains("octaves"), "{err}");
        // Integers are fine where numbers are expected.
        let p = TerrainParams::from_scene_str("gain = 1\noffset = [1, 2]\n").unwrap();
        assert_eq!((p.gain, p.offset), (1.0, [1.0, 2.0]));
    }

    #[test]
    fn huge_keys_and_values_give_short_errors() {
        let big = "x".repeat(1_000_000);
        for text in [
            format!("{big} = 1\n"),
            format!("normals = \"{big}\"\n"),
            format!("seed = {}\n", "9".repeat(100_000)),
            format!("seed = [{}]\n", "1,".repeat(100_000)),
            format!("seed = \"{big}\n"),
        ] {
            let err = TerrainParams::from_scene_str(&text)
                .unwrap_err()
                .to_string();
            assert!(
                err.len() <= 200 && !err.contains('\n'),
                "{} chars: {}",
                err.len(),
                &err[..err.len().min(300)]
            );
        }
        let err = TerrainParams::from_scene_str("offset = [1e300, 0]\n")
            .unwrap_err()
            .to_string();
        assert!(err.contains("1e300") && err.len() < 120, "{err}");
    }
}
