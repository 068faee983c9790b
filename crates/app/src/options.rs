//! What the window and the page start with and what their URL holds: the scene (every row of
//! [`relief::params::PARAMS`]) plus the window's own rows ([`OPTIONS`]: scroll speed, pause).

use relief::error::{Error, Result};
use relief::params::{params, TerrainParams};
use relief::table::{Control, Kind, Param, Value};

/// Default scroll speed of the animated offset, in tiles per second along x.
pub const SCROLL_SPEED: f32 = 0.01;

/// Offsets the animation reaches are kept on a grid of this many steps per tile, so the URL
/// and the paused picture hold short, exact decimals (1e-6 tile is a thousandth of a texel at
/// the default size: invisible).
pub const OFFSET_STEPS: f64 = 1e6;

/// What the window starts with; the web page fills it from the URL.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AppOptions {
    /// The scene.
    pub params: TerrainParams,
    /// Scroll speed in tiles per second (along x; z moves at 0.4 of it).
    pub speed: f32,
    /// Whether the scroll is paused.
    pub paused: bool,
    /// Whether to measure and report GPU pass times.
    pub timings: bool,
    /// The endless world and the fly camera to start with, instead of the tile (native window;
    /// set by `relief --world endless`).
    pub world: Option<(relief::WorldParams, relief::FlyCamera)>,
    /// In the endless world, start on the fly-through path ([`relief::PathCamera`]) rather than
    /// flying freely (P switches between them).
    pub path: bool,
    /// Seconds along the path (`time` in the URL).
    pub path_time: f64,
    /// How frames are drawn (`method` in the URL): the mesh, or a ray caster.
    pub method: relief::Method,
    /// Samples a pixel of the visibility method and the hybrid (`relief --samples`, 4 or 1).
    pub samples: u32,
    /// Where the visibility method and the hybrid rasterise (`relief --raster`).
    pub raster: relief::Raster,
    /// Choose the method by measurement before the first frame (`relief --method auto`, the
    /// native window only): [`relief::gpu::headless::choose_method`], then `method`, `samples`
    /// and `raster` hold the choice.
    pub auto: bool,
    /// Accumulate frames with the temporal service ([`relief::World::set_temporal`]) where the
    /// method is shaded in compute (`no_temporal` in the URL and the CLI turns it off, T in the
    /// window toggles it).
    pub temporal: bool,
}

impl Default for AppOptions {
    fn default() -> Self {
        Self {
            params: TerrainParams::default(),
            speed: SCROLL_SPEED,
            paused: false,
            timings: false,
            world: None,
            path: false,
            path_time: 0.0,
            method: relief::Method::Mesh,
            samples: relief::gpu::visibility::SAMPLES,
            raster: relief::Raster::Hardware,
            auto: false,
            temporal: true,
        }
    }
}

/// The `method` key of the window and the page (not a CLI flag: `relief --method`, which the
/// window shares with `relief render`, also takes `auto` and goes with `--samples` and
/// `--raster`) in the endless world: the methods it draws, from [`relief::Method`]'s one list.
pub static METHOD: Param<AppOptions> = Param {
    kind: Kind::Choice(relief::Method::WORLD_NAMES),
    ..METHOD_ROW
};

/// [`METHOD`] as the tile's page offers it: the methods the tile draws.
pub static TILE_METHOD: Param<AppOptions> = Param {
    kind: Kind::Choice(relief::Method::TILE_NAMES),
    ..METHOD_ROW
};

const METHOD_ROW: Param<AppOptions> = Param {
    key: "method",
    doc: "how frames are drawn: the mesh, or a ray caster (the reference is slow: seconds a frame on a fast GPU)",
    kind: Kind::Choice(relief::Method::NAMES),
    control: Control::Select,
    get: |o: &AppOptions| Value::Choice(o.method.name()),
    set: |o: &mut AppOptions, v| {
        if let Value::Choice(name) = v {
            if let Some(m) = relief::Method::from_name(name) {
                o.method = m;
            }
        }
    },
};

impl AppOptions {
    /// Sets the drawing method from text: one of [`relief::Method::NAMES`], and one the world
    /// shown draws.
    fn set_method(&mut self, value: &str) -> Result<()> {
        let mut next = *self;
        // Each world's row lists the methods it draws, and its error names them.
        let row = if self.world.is_some() {
            &METHOD
        } else {
            &TILE_METHOD
        };
        row.set_text(&mut next, value)?;
        *self = next;
        Ok(())
    }
}

/// The window's and page's own parameters, after the scene's: the same table shape, so the
/// CLI flags, URL keys, controls and errors come from here too.
pub static OPTIONS: [Param<AppOptions>; 3] = [
    Param {
        key: "speed",
        doc: "scroll speed in tiles per second along x (z moves at 0.4 of it)",
        kind: Kind::Float {
            min: -10.0,
            max: 10.0,
        },
        control: Control::Slider {
            min: -0.1,
            max: 0.1,
            step: 0.001,
        },
        get: |o: &AppOptions| Value::Float(o.speed),
        set: |o: &mut AppOptions, v| {
            if let Value::Float(s) = v {
                o.speed = s;
            }
        },
    },
    Param {
        key: "paused",
        doc: "the scroll animation starts paused",
        kind: Kind::Bool,
        control: Control::Checkbox,
        get: |o: &AppOptions| Value::Bool(o.paused),
        set: |o: &mut AppOptions, v| {
            if let Value::Bool(b) = v {
                o.paused = b;
            }
        },
    },
    TEMPORAL,
];

/// The `no_temporal` row: the window's and the page's in either world.
pub const TEMPORAL: Param<AppOptions> = Param {
    key: "no_temporal",
    doc: "draw each frame of the endless world's mesh, visibility method and hybrid alone \
          and unjittered, instead of accumulating jittered frames (a still view converges to \
          an anti-aliased image; T toggles)",
    kind: Kind::Bool,
    control: Control::Checkbox,
    get: |o: &AppOptions| Value::Bool(!o.temporal),
    set: |o: &mut AppOptions, v| {
        if let Value::Bool(b) = v {
            o.temporal = !b;
        }
    },
};

/// Every key the URL accepts: the scene's, then the window's.
pub fn url_keys() -> Vec<&'static str> {
    params()
        .map(|p| p.key)
        .chain(OPTIONS.iter().map(|p| p.key))
        .chain(std::iter::once(METHOD.key))
        .collect()
}

/// One URL entry that was not applied, and why.
#[derive(Clone, Debug, PartialEq)]
pub struct Ignored {
    /// The key as written.
    pub key: String,
    /// Why, in one line naming the allowed values.
    pub reason: String,
}

impl AppOptions {
    /// Sets one key (a scene key or a window key) from text. The whole scene is checked
    /// (octaves against frequency); on error nothing changes.
    pub fn set(&mut self, key: &str, value: &str) -> Result<()> {
        let key = key.trim().replace('-', "_");
        if key == METHOD.key {
            return self.set_method(value);
        }
        let mut next = *self;
        if key == TEMPORAL.key {
            TEMPORAL.set_text(&mut next, value)?;
            *self = next;
            return Ok(());
        }
        if let Some((world, _)) = &mut next.world {
            let row = relief::world::world_param(&key)
                .filter(|r| r.key == key)
                .ok_or_else(|| {
                    Error::invalid(
                        "key",
                        relief::table::shorten(&key),
                        relief::world::WORLD_PARAMS
                            .iter()
                            .map(|r| r.key)
                            .collect::<Vec<_>>()
                            .join(", "),
                    )
                })?;
            row.set_text(world, value)?;
            world.validate()?;
            *self = next;
            return Ok(());
        }
        if let Some(row) = OPTIONS.iter().find(|p| p.key == key) {
            row.set_text(&mut next, value)?;
        } else if relief::params::param(&key).is_some() {
            next.params.set(&key, value)?;
            next.params.validate()?;
        } else {
            return Err(Error::invalid(
                "key",
                relief::table::shorten(&key),
                url_keys().join(", "),
            ));
        }
        *self = next;
        Ok(())
    }

    /// Applies a URL query string (`seed=3&octaves=6&paused=1`): every valid entry is applied,
    /// each bad one is skipped and returned with its reason, so one typo keeps the rest.
    pub fn apply_query(&mut self, query: &str) -> Vec<Ignored> {
        let mut ignored = Vec::new();
        let pairs: Vec<(String, String)> = query
            .trim_start_matches('?')
            .split('&')
            .filter(|p| !p.is_empty())
            .map(|pair| {
                let (k, v) = pair.split_once('=').unwrap_or((pair, ""));
                (percent_decode(k), percent_decode(v))
            })
            .collect();
        let world = pairs
            .iter()
            .rev()
            .find(|(k, _)| k.trim() == "world")
            .map(|(_, v)| v.trim().to_owned());
        match world.as_deref() {
            Some("endless") => return self.apply_world_query(&pairs),
            None | Some("tile") => {}
            Some(other) => ignored.push(Ignored {
                key: "world".into(),
                reason: format!(
                    "invalid world: {} (allowed: tile or endless)",
                    relief::table::shorten(other)
                ),
            }),
        }
        let pairs: Vec<(String, String)> = pairs
            .into_iter()
            .filter(|(k, _)| k.trim() != "world")
            .collect();
        // Window keys and single scene keys first, then the scene as a whole: octaves and
        // frequency are checked together, in either order in the URL.
        let mut scene = self.params;
        for (k, v) in &pairs {
            let key = k.trim().replace('-', "_");
            let result = match OPTIONS.iter().find(|p| p.key == key) {
                _ if key == METHOD.key => self.set_method(v),
                Some(row) => row.set_text(self, v),
                None => scene.set(&key, v).map_err(|e| match e {
                    Error::InvalidParam { name, .. } if name == "key" => {
                        Error::invalid("key", relief::table::shorten(k), url_keys().join(", "))
                    }
                    other => other,
                }),
            };
            if let Err(e) = result {
                ignored.push(Ignored {
                    key: relief::table::shorten(k),
                    reason: e.to_string(),
                });
            }
        }
        // Keys the method does not read are refused with it, as `relief render --method`
        // refuses them (the method may come after them in the URL): the value in force stays.
        let method = self.method;
        for (k, _) in &pairs {
            let Some(row) = relief::params::param(k) else {
                continue;
            };
            let key = relief::table::shorten(k);
            if method.unread_keys().contains(&row.key) && !ignored.iter().any(|i| i.key == key) {
                (row.set)(&mut scene, (row.get)(&self.params));
                ignored.push(Ignored {
                    reason: format!(
                        "{} does not apply to method {method}: {}",
                        row.key,
                        unread_why(method)
                    ),
                    key,
                });
            }
        }
        match scene.validate() {
            Ok(()) => self.params = scene,
            Err(e) => {
                // The one rule between keys (octaves against frequency): undo the one the URL
                // gave (octaves if it gave both), keep the rest, and say why.
                let gave = |key: &str| pairs.iter().any(|(k, _)| k.trim().replace('-', "_") == key);
                let mut fixed = scene;
                let (key, reason) = if gave("octaves") || !gave("frequency") {
                    fixed.octaves = self
                        .params
                        .octaves
                        .min(relief::params::max_octaves_for(fixed.frequency));
                    ("octaves", e.to_string())
                } else {
                    fixed.frequency = self.params.frequency;
                    // The error names the octaves: say which key was undone.
                    (
                        "frequency",
                        format!("frequency kept at {}: {e}", fixed.frequency),
                    )
                };
                ignored.push(Ignored {
                    key: key.into(),
                    reason,
                });
                if fixed.validate().is_ok() {
                    self.params = fixed;
                }
            }
        }
        ignored
    }

    /// The query string that reproduces these options (every key, in table order).
    /// [`AppOptions::apply_query`] for `world=endless`: the endless world's keys and its
    /// camera (`camera=fly|path`, `eye=X,Y,Z`, `look_at=X,Y,Z`, `fov=DEG`).
    fn apply_world_query(&mut self, pairs: &[(String, String)]) -> Vec<Ignored> {
        use relief::world::{world_param, WorldParams};
        let mut ignored = Vec::new();
        let mut skip = |key: &str, reason: String| {
            ignored.push(Ignored {
                key: relief::table::shorten(key),
                reason,
            })
        };
        let mut world = WorldParams::default();
        let (mut eye, mut look_at, mut fov, mut path) = (None, None, 45f32, false);
        let point = |v: &str| -> Option<glam::DVec3> {
            let p: Vec<f64> = v
                .split(',')
                .map(|t| t.trim().parse().ok())
                .collect::<Option<_>>()?;
            (p.len() == 3 && p.iter().all(|c| c.is_finite() && c.abs() <= 1e9))
                .then(|| glam::DVec3::new(p[0], p[1], p[2]))
        };
        for (k, v) in pairs {
            let key = k.trim().replace('-', "_");
            match key.as_str() {
                "world" => {}
                "method" => {
                    if let Err(e) = METHOD.set_text(self, v) {
                        skip(&key, e.to_string());
                    }
                }
                "no_temporal" => {
                    if let Err(e) = TEMPORAL.set_text(self, v) {
                        skip(&key, e.to_string());
                    }
                }
                "camera" => match v.trim() {
                    "fly" => path = false,
                    "path" => path = true,
                    other => skip(
                        &key,
                        format!(
                            "invalid camera: {} (allowed: fly or path)",
                            relief::table::shorten(other)
                        ),
                    ),
                },
                "eye" | "look_at" => match point(v) {
                    Some(p) if key == "eye" => eye = Some(p),
                    Some(p) => look_at = Some(p),
                    None => skip(
                        &key,
                        format!(
                            "invalid {key}: {} (allowed: X,Y,Z, finite, within ±1e9)",
                            relief::table::shorten(v)
                        ),
                    ),
                },
                "time" => match v.trim().parse::<f64>() {
                    Ok(t) if (0.0..=relief::PathCamera::MAX_TIME).contains(&t) => {
                        self.path_time = t;
                    }
                    _ => skip(
                        &key,
                        format!(
                            "invalid time: {} (allowed: 0..={} seconds)",
                            relief::table::shorten(v),
                            relief::PathCamera::MAX_TIME
                        ),
                    ),
                },
                "fov" => match v.trim().parse::<f32>() {
                    Ok(d) if (1.0..=179.0).contains(&d) => fov = d,
                    _ => skip(
                        &key,
                        format!(
                            "invalid fov: {} (allowed: 1..=179)",
                            relief::table::shorten(v)
                        ),
                    ),
                },
                _ => match world_param(&key).filter(|r| r.key == key) {
                    Some(row) => {
                        let mut next = world;
                        match row.set_text(&mut next, v).and_then(|()| next.validate()) {
                            Ok(()) => world = next,
                            Err(e) => skip(&key, e.to_string()),
                        }
                    }
                    None => skip(
                        &key,
                        format!(
                            "invalid key: {} (the endless world's keys: world, {}, camera, eye, \
                             look_at, fov, time, method)",
                            relief::table::shorten(&key),
                            relief::world::WORLD_PARAMS
                                .iter()
                                .map(|r| r.key)
                                .collect::<Vec<_>>()
                                .join(", ")
                        ),
                    ),
                },
            }
        }
        let (default_eye, default_target) = relief::gpu::world::default_camera(&world.land);
        let eye = eye.unwrap_or(default_eye);
        let mut target = look_at.unwrap_or(eye + (default_target - default_eye));
        if (target - eye).length() < 1e-3 {
            skip("look_at", "invalid look_at: the eye's own position".into());
            target = eye + (default_target - default_eye);
        }
        let fly = relief::FlyCamera::looking_at(eye, target, fov.to_radians());
        self.world = Some((world, fly));
        self.path = path;
        ignored
    }

    pub fn to_query(&self) -> String {
        if let Some((world, fly)) = &self.world {
            let round = |v: f64| (v * 10.0).round() / 10.0;
            let p = |v: glam::DVec3| format!("{}%2C{}%2C{}", round(v.x), round(v.y), round(v.z));
            let keys = relief::world::WORLD_PARAMS
                .iter()
                .map(|r| format!("{}={}", r.key, url_value((r.get)(world))));
            let mut camera = vec![
                format!("camera={}", if self.path { "path" } else { "fly" }),
                format!("eye={}", p(fly.eye)),
                format!("look_at={}", p(fly.eye + fly.forward() * 1000.0)),
                format!("fov={}", round(f64::from(fly.fov_y.to_degrees()))),
            ];
            if self.path {
                camera.push(format!("time={}", round(self.path_time)));
            }
            if self.method != relief::Method::Mesh {
                camera.push(format!("method={}", self.method));
            }
            camera.insert(0, format!("no_temporal={}", u8::from(!self.temporal)));
            return std::iter::once("world=endless".to_owned())
                .chain(keys)
                .chain(camera)
                .collect::<Vec<_>>()
                .join("&");
        }
        // Keys the method does not read are left out: its URL reads back without a refusal.
        let unread = self.method.unread_keys();
        let scene = params()
            .filter(|p| !unread.contains(&p.key))
            .map(|p| (p.key, (p.get)(&self.params)));
        let window = OPTIONS.iter().map(|p| (p.key, (p.get)(self)));
        // The mesh, the default, is not written: URLs from before the key stay the same.
        let method =
            (self.method != relief::Method::Mesh).then(|| (METHOD.key, (METHOD.get)(self)));
        scene
            .chain(window)
            .chain(method)
            .map(|(k, v)| format!("{k}={}", url_value(v)))
            .collect::<Vec<_>>()
            .join("&")
    }

    /// Moves the scroll offset by `dt` seconds of animation, on the [`OFFSET_STEPS`] grid.
    pub fn advance(&mut self, dt: f64) {
        let s = f64::from(self.speed);
        let step =
            |o: f64, v: f64| ((o + v * dt).rem_euclid(1.0) * OFFSET_STEPS).round() / OFFSET_STEPS;
        let [x, z] = self.params.offset;
        self.params.offset = [step(x, s), step(z, 0.4 * s)].map(|v| if v >= 1.0 { 0.0 } else { v });
    }

    /// Whether the picture changes by itself (the scroll runs).
    pub fn animating(&self) -> bool {
        !self.paused && self.speed != 0.0
    }
}

/// Why a method's [`relief::Method::unread_keys`] do not apply to it, in the words of
/// `relief render --method`'s refusal (src/cli/mod.rs).
fn unread_why(method: relief::Method) -> &'static str {
    if method == relief::Method::Blog {
        "the blog's pipeline bakes its own noise into its own texture and grid"
    } else {
        "the ray casters draw the continuous surface, not a baked mesh"
    }
}

/// A value as the URL writes it (the comma of a pair escaped).
fn url_value(v: Value) -> String {
    v.to_string().replace(',', "%2C")
}

fn percent_decode(s: &str) -> String {
    let bytes = s.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        match bytes[i] {
            b'%' if i + 2 < bytes.len() => {
                let hex = std::str::from_utf8(&bytes[i + 1..i + 3]).ok();
                match hex.and_then(|h| u8::from_str_radix(h, 16).ok()) {
                    Some(b) => {
                        out.push(b);
                        i += 3;
                        continue;
                    }
                    None => out.push(b'%'),
                }
            }
            b'+' => out.push(b' '),
            b => out.push(b),
        }
        i += 1;
    }
    String::from_utf8_lossy(&out).into_owned()
}

#[cfg(test)]
#[path = "options_tests.rs"]
mod tests;
