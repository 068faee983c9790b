//! From clap's matches to what runs: the drawn method, the camera, the scene of either world,
//! the window's script, the region to bake; every refusal in words.

use super::*;

pub(super) fn clap_error(e: clap::Error) -> i32 {
    use clap::error::{ContextKind, ContextValue, ErrorKind};
    match e.kind() {
        ErrorKind::DisplayHelp
        | ErrorKind::DisplayVersion
        | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => {
            let _ = e.print();
            return 0;
        }
        _ => {}
    }
    let names = |kind| match e.get(kind) {
        Some(ContextValue::Strings(v)) => v.join(", "),
        Some(ContextValue::String(s)) => s.clone(),
        _ => String::new(),
    };
    let message = match e.kind() {
        ErrorKind::MissingRequiredArgument => {
            format!(
                "missing {}",
                names(ContextKind::InvalidArg).replace(['<', '>'], "")
            )
        }
        ErrorKind::UnknownArgument => format!(
            "unknown option {} (relief --help lists them)",
            table::shorten(&names(ContextKind::InvalidArg))
        ),
        ErrorKind::InvalidSubcommand => format!(
            "unknown command {} (commands: window, render, bake, bench, stability, height)",
            table::shorten(&names(ContextKind::InvalidSubcommand))
        ),
        ErrorKind::TooManyValues => {
            let arg = table::shorten(&names(ContextKind::InvalidArg));
            format!(
                "{arg} takes no value: give {arg} alone, not {arg}={} (in scene files and \
                 URLs: true/false or 1/0)",
                table::shorten(&names(ContextKind::InvalidValue))
            )
        }
        ErrorKind::ArgumentConflict => format!(
            "{} given more than once",
            table::shorten(&names(ContextKind::InvalidArg))
        ),
        _ => {
            let rendered = e.render().to_string();
            let first = rendered.lines().next().unwrap_or("bad arguments");
            first.trim_start_matches("error: ").to_owned()
        }
    };
    eprintln!("{}", error_line(&message));
    2
}

/// How `relief render` draws: the method chosen by measurement on the device (`--method
/// auto`, the default), or the method given with its samples a pixel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Drawn {
    Auto,
    Pinned(Candidate),
}

impl Drawn {
    /// The method given where it is not mesh-based (a ray caster or the blog's pipeline), which
    /// draws through its own path, not a [`Terrain`] or [`World`].
    pub(super) fn own_path(self) -> Option<relief::Method> {
        match self {
            Drawn::Pinned(c) if !c.method.is_mesh() => Some(c.method),
            _ => None,
        }
    }
}

/// `--method`, `--samples` and `--raster` of `relief render` and the window, `default` where
/// `--method` is not given.
pub(super) fn drawn(m: &ArgMatches, default: Drawn) -> Result<Drawn> {
    let drawn = drawn_samples(m, default)?;
    let Some(given) = string(m, "raster") else {
        return Ok(drawn);
    };
    let raster = relief::Raster::from_name(&given)
        .map_err(|_| Error::invalid("--raster", table::shorten(&given), RASTERS.allowed()))?;
    match drawn {
        Drawn::Pinned(c)
            if matches!(
                c.method,
                relief::Method::Visibility | relief::Method::Hybrid
            ) =>
        {
            match raster.refusal(c.samples) {
                Some(why) => Err(Error::invalid("--raster", raster, why)),
                None => Ok(Drawn::Pinned(Candidate { raster, ..c })),
            }
        }
        other => Err(Error::Usage(format!(
            "--raster applies to --method visibility and hybrid only, not {}: the forward mesh \
             rasterises in hardware, the ray casters rasterise nothing, and auto measures both",
            match other {
                Drawn::Pinned(c) => c.method.to_string(),
                Drawn::Auto => "auto".to_owned(),
            }
        ))),
    }
}

/// `--method` and `--samples` of `relief render` and the window.
pub(super) fn drawn_samples(m: &ArgMatches, default: Drawn) -> Result<Drawn> {
    let method = match string(m, "method") {
        None => match default {
            Drawn::Auto => None,
            Drawn::Pinned(c) => Some(c.method),
        },
        Some(text) => match text.trim() {
            "auto" => None,
            t => Some(relief::Method::from_name(t).ok_or_else(|| {
                Error::invalid("--method", table::shorten(&text), METHODS.allowed())
            })?),
        },
    };
    let Some(given) = string(m, "samples") else {
        return Ok(method.map_or(Drawn::Auto, |m| {
            Drawn::Pinned(Candidate::new(m, relief::gpu::visibility::SAMPLES))
        }));
    };
    let samples = match SAMPLES.parse(&given) {
        Some(Value::Choice(n)) => n.parse::<u32>().unwrap_or(4),
        _ => {
            return Err(Error::invalid(
                "--samples",
                table::shorten(&given),
                SAMPLES.allowed(),
            ))
        }
    };
    match method {
        Some(m @ (relief::Method::Visibility | relief::Method::Hybrid)) => {
            Ok(Drawn::Pinned(Candidate::new(m, samples)))
        }
        other => Err(Error::Usage(format!(
            "--samples applies to --method visibility and hybrid only, not {}: the mesh \
             anti-aliases with its target's 4x MSAA, the ray casters cast one ray a pixel, and \
             auto measures its own",
            other.map_or("auto".to_owned(), |m| m.to_string())
        ))),
    }
}

/// Sets `scene` to draw what `drawn` stands for (a mesh-based method): `auto` first draws a few
/// frames of each candidate ([`headless::choose_method`]) and, with `timings`, says which it
/// chose and why.
pub(super) fn resolve_drawn(
    gpu: &Gpu,
    drawn: Drawn,
    mut scene: headless::TrialScene<'_>,
    timings: bool,
) -> Result<()> {
    match drawn {
        Drawn::Pinned(c) => {
            scene.set(&gpu.device, c)?;
            if timings && c.method.is_mesh() {
                println!("method {c} (pinned: {})", c.flags());
            }
            Ok(())
        }
        Drawn::Auto => {
            let choice = headless::choose_method(gpu, scene)?;
            if timings {
                println!("{}", choice.describe(&gpu.describe()));
            }
            Ok(())
        }
    }
}

/// Which command runs, with what it was given.
pub(super) enum Run {
    Window,
    Render {
        out: PathBuf,
        width: u32,
        height: u32,
        method: Drawn,
        camera: Camera,
        stats: bool,
        /// Frames the temporal service accumulates (`--frames`; 1: one frame, unjittered).
        frames: u32,
    },
    Bake {
        out_dir: PathBuf,
    },
    Bench {
        out_dir: PathBuf,
        quick: bool,
        /// `--only`: one part of the endless world's benchmark.
        only: Option<&'static str>,
        /// `--view`: the views the temporal and reference parts measure (empty: their own).
        views: Vec<String>,
    },
    Height {
        points: Vec<[f64; 2]>,
    },
    Stability {
        out_dir: PathBuf,
        quick: bool,
        axes: Vec<relief_eval::stability::Axis>,
    },
}

/// The camera `relief render` was given: each part optional, defaults by world.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Camera {
    pub(super) eye: Option<[f64; 3]>,
    pub(super) look_at: Option<[f64; 3]>,
    pub(super) fov_deg: Option<f32>,
    /// `--camera path` (with its `--time`).
    pub(super) path: Option<f64>,
}

/// `X,Y,Z`: three finite numbers within ±[`MAX_COORD`].
pub(super) fn triple(m: &ArgMatches, id: &str) -> Result<Option<[f64; 3]>> {
    let Some(text) = string(m, id) else {
        return Ok(None);
    };
    let bad = || {
        Error::invalid(
            format!("--{id}"),
            table::shorten(&text),
            format!("X,Y,Z: three finite numbers, each within ±{MAX_COORD:e}"),
        )
    };
    let parts: Vec<&str> = text.split(',').collect();
    if parts.len() != 3 {
        return Err(bad());
    }
    let mut out = [0.0; 3];
    for (o, t) in out.iter_mut().zip(parts) {
        let v: f64 = t.trim().parse().map_err(|_| bad())?;
        if !v.is_finite() || v.abs() > MAX_COORD {
            return Err(bad());
        }
        *o = v;
    }
    Ok(Some(out))
}

pub(super) fn camera(m: &ArgMatches) -> Result<Camera> {
    // The scene file's [camera] first; each flag overrides its part.
    let scene_path = string(m, "scene").map(PathBuf::from);
    let scene = match &scene_path {
        Some(p) => crate::scene::SceneCamera::read(p)?,
        None => Default::default(),
    };
    // One part of the camera: the flag's text, else the scene's, read as `kind`; an error
    // names where the bad value came from.
    let part = |flag: &str, key: &str, scene: Option<String>, kind: Kind, unit: &str| {
        let allowed = format!("{}{unit}", kind.allowed());
        match (string(m, flag), scene) {
            (Some(text), _) => kind
                .parse(&text)
                .map(Some)
                .ok_or_else(|| Error::invalid(format!("--{flag}"), table::shorten(&text), allowed)),
            (None, Some(text)) => kind.parse(&text).map(Some).ok_or_else(|| Error::SceneFile {
                path: scene_path.clone().unwrap_or_default(),
                message: format!(
                    "invalid [camera] {key}: {} (allowed: {allowed})",
                    table::shorten(&text)
                ),
            }),
            (None, None) => Ok(None),
        }
    };
    let number = |v: Option<f64>| v.map(|v| format!("{v:?}"));
    let fov_deg = match part("fov", "fov", number(scene.fov), FOV, " degrees")? {
        Some(Value::Float(v)) => Some(v),
        _ => None,
    };
    let kind = match part("camera", "camera", scene.camera.clone(), CAMERAS, "")? {
        Some(Value::Choice(name)) => Some(name),
        _ => None,
    };
    // Where a part came from, for errors: the flag, else the scene file's [camera] key; an
    // error about a part from the file is the file's error.
    let from_file = |flag: &str| scene_path.is_some() && !given(m, flag);
    let source = |flag: &str, key: &str| {
        if from_file(flag) {
            format!("[camera] {key}")
        } else {
            format!("--{flag}")
        }
    };
    let usage = |flag: &str, message: String| match &scene_path {
        Some(path) if from_file(flag) => Error::SceneFile {
            path: path.clone(),
            message,
        },
        _ => Error::Usage(message),
    };
    let time = match part("time", "time", number(scene.time), TIME, " seconds")? {
        Some(Value::Float(t)) => Some(f64::from(t)),
        _ => None,
    };
    let endless = world_kind(m)? == WorldKind::Endless;
    match (kind, endless) {
        (Some("orbit"), true) | (Some("fly" | "path"), false) => {
            return Err(usage(
                "camera",
                format!(
                    "{} {} does not apply to the {} world: the tile has orbit, the endless \
                     world fly and path",
                    source("camera", "camera"),
                    kind.unwrap_or_default(),
                    if endless { "endless" } else { "tile" }
                ),
            ))
        }
        _ => {}
    }
    let point = |flag: &str, key: &str, scene: Option<[f64; 3]>| -> Result<Option<[f64; 3]>> {
        match triple(m, flag)? {
            Some(p) => Ok(Some(p)),
            None => match scene {
                Some(p) if p.iter().all(|c| c.is_finite() && c.abs() <= MAX_COORD) => Ok(Some(p)),
                Some(p) => Err(Error::SceneFile {
                    path: scene_path.clone().unwrap_or_default(),
                    message: format!(
                        "invalid [camera] {key}: {} (allowed: [x, y, z], finite, each within \
                         ±{MAX_COORD:e})",
                        table::shorten(&format!("{p:?}"))
                    ),
                }),
                None => Ok(None),
            },
        }
    };
    let eye = point("eye", "eye", scene.eye)?;
    let look_at = point("look-at", "look_at", scene.look_at)?;
    let path = kind == Some("path");
    if path {
        refuse_flags(
            m,
            "render --camera path",
            &["eye", "look-at"],
            "the path places the camera (choose where along it with --time)",
        )?;
        if eye.is_some() || look_at.is_some() {
            return Err(Error::Usage(
                "the scene file's [camera] eye and look_at do not apply to the path camera \
                 (the path places the camera)"
                    .into(),
            ));
        }
    } else if time.is_some() {
        return Err(Error::Usage(
            "--time applies to --camera path only (a position along the fly-through)".into(),
        ));
    }
    let camera = Camera {
        eye,
        look_at,
        fov_deg,
        path: path.then(|| time.unwrap_or(0.0)),
    };
    if let (Some(e), Some(t)) = (camera.eye, camera.look_at) {
        let d = [t[0] - e[0], t[1] - e[1], t[2] - e[2]];
        let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        if len <= 1e-6 * (1.0 + e.iter().map(|v| v.abs()).fold(0.0, f64::max)) {
            return Err(usage(
                "look-at",
                format!(
                    "{} {} is the {} position: the camera must look somewhere else",
                    source("look-at", "look_at"),
                    table::shorten(&string(m, "look-at").unwrap_or_else(|| format!("{t:?}"))),
                    source("eye", "eye"),
                ),
            ));
        }
    }
    Ok(camera)
}

/// `--world`, else the scene file's `world`, else the tile.
pub(super) fn world_kind(m: &ArgMatches) -> Result<WorldKind> {
    match (string(m, "world"), string(m, "scene")) {
        (Some(text), _) => WorldKind::from_name(&text)
            .ok_or_else(|| Error::invalid("--world", table::shorten(&text), WORLDS.allowed())),
        (None, Some(path)) => crate::scene::scene_world(Path::new(&path)),
        (None, None) => Ok(WorldKind::Tile),
    }
}

/// The endless world: defaults, then the scene file, then the flags.
pub(super) fn resolve_world(m: &ArgMatches) -> Result<WorldParams> {
    let mut p = WorldParams::default();
    if let Some(path) = string(m, "scene") {
        let path = PathBuf::from(path);
        for (row, text) in crate::scene::read_world_entries(&path)?
            .iter()
            .filter(|(row, _)| !given(m, row.key))
        {
            let value = row.parse(text).map_err(|e| Error::SceneFile {
                path: path.clone(),
                message: e.to_string(),
            })?;
            (row.set)(&mut p, value);
        }
    }
    for row in WORLD_PARAMS.iter().filter(|r| given(m, r.key)) {
        (row.set)(&mut p, flag_value(row, &flag_text(m, row))?);
    }
    p.validate().map_err(|e| match e {
        Error::InvalidParam {
            name,
            value,
            allowed,
        } if world_param(&name).is_some() => {
            Error::invalid(format!("--{}", name.replace('_', "-")), value, allowed)
        }
        other => other,
    })?;
    Ok(p)
}

/// The props of the scene file, if it gives their tables, validated against `params`' props
/// (an error names the file).
pub(super) fn resolve_props(
    m: &ArgMatches,
    params: &WorldParams,
) -> Result<Option<relief::props::Scene>> {
    let Some(path) = string(m, "scene") else {
        return Ok(None);
    };
    let path = PathBuf::from(path);
    let scene = crate::scene::read_world_props(&path)?;
    if let Some(s) = &scene {
        s.compile(&params.props).map_err(|e| Error::SceneFile {
            path: path.clone(),
            message: e.to_string(),
        })?;
    }
    Ok(scene)
}

pub(super) fn string(m: &ArgMatches, id: &str) -> Option<String> {
    m.try_get_one::<String>(id).ok().flatten().cloned()
}

pub(super) fn given(m: &ArgMatches, id: &str) -> bool {
    m.value_source(id) == Some(clap::parser::ValueSource::CommandLine)
}

/// Parses `--flag VALUE` of a table row, naming the flag in the error.
/// The text of `row`'s flag as given: `1` for a flag without a value (a bool).
pub(super) fn flag_text<T>(m: &ArgMatches, row: &Param<T>) -> String {
    match row.kind {
        Kind::Bool => "1".to_owned(),
        _ => string(m, row.key).unwrap_or_default(),
    }
}

pub(super) fn flag_value<T>(p: &Param<T>, text: &str) -> Result<Value> {
    p.parse(text)
        .map_err(|_| Error::invalid(format!("--{}", p.flag()), table::shorten(text), p.allowed()))
}

/// `--only`: a part of `relief bench --world endless`.
pub(super) fn bench_part(m: &ArgMatches) -> Result<Option<&'static str>> {
    let Some(text) = string(m, "only") else {
        return Ok(None);
    };
    match BENCH_PARTS.parse(&text) {
        Some(Value::Choice(part)) => Ok(Some(part)),
        _ => Err(Error::invalid(
            "--only",
            table::shorten(&text),
            BENCH_PARTS.allowed(),
        )),
    }
}

/// `--frames`: 1 unless given.
pub(super) fn frames(m: &ArgMatches) -> Result<u32> {
    let Some(text) = string(m, "frames") else {
        return Ok(1);
    };
    match FRAMES.parse(&text) {
        Some(Value::Int(v)) => Ok(v),
        _ => Err(Error::invalid(
            "--frames",
            table::shorten(&text),
            FRAMES.allowed(),
        )),
    }
}

pub(super) fn image_side(m: &ArgMatches, id: &str) -> Result<u32> {
    let text = string(m, id).unwrap_or_default();
    match IMAGE_SIDE.parse(&text) {
        Some(Value::Int(v)) => Ok(v),
        _ => Err(Error::invalid(
            format!("--{id}"),
            table::shorten(&text),
            IMAGE_SIDE.allowed(),
        )),
    }
}

/// The scene: defaults, then the scene file, then the flags, then checked as a whole.
pub(super) fn resolve_scene(m: &ArgMatches) -> Result<TerrainParams> {
    let mut p = TerrainParams::default();
    let flagged = |row: &SceneParam| given(m, row.key);
    if let Some(path) = string(m, "scene") {
        let path = PathBuf::from(path);
        let entries = crate::scene::read_entries(&path)?;
        for (row, text) in entries.iter().filter(|(row, _)| !flagged(row)) {
            row.set_text(&mut p, text).map_err(|e| Error::SceneFile {
                path: path.clone(),
                message: e.to_string(),
            })?;
        }
    }
    for row in params().filter(|r| flagged(r)) {
        let text = string(m, row.key).unwrap_or_default();
        (row.set)(&mut p, flag_value(row, &text)?);
    }
    p.validate().map_err(|e| match e {
        // The only rule between parameters: name the flag if that is where octaves came from.
        Error::InvalidParam {
            name,
            value,
            allowed,
        } if given(m, &name) => {
            Error::invalid(format!("--{}", name.replace('_', "-")), value, allowed)
        }
        other => other,
    })?;
    Ok(p)
}

pub(super) fn script(m: &ArgMatches) -> Result<Script> {
    let exit_after = match string(m, "exit-after") {
        Some(text) => match EXIT_AFTER.parse(&text) {
            Some(Value::Float(s)) => Some(f64::from(s)),
            _ => {
                return Err(Error::invalid(
                    "--exit-after",
                    table::shorten(&text),
                    EXIT_AFTER.allowed(),
                ))
            }
        },
        None => None,
    };
    let frames = Kind::Int {
        min: 1,
        max: u32::MAX,
    };
    let lose_device_after = match string(m, "test-lose-device") {
        Some(text) => match frames.parse(&text) {
            Some(Value::Int(n)) => Some(u64::from(n)),
            _ => {
                return Err(Error::invalid(
                    "--test-lose-device",
                    table::shorten(&text),
                    frames.allowed(),
                ))
            }
        },
        None => None,
    };
    Ok(Script {
        exit_after,
        lose_device_after,
    })
}

/// Refuses flags that mean nothing to the command that runs, so none is silently ignored.
pub(super) fn refuse_flags(m: &ArgMatches, command: &str, flags: &[&str], why: &str) -> Result<()> {
    match flags.iter().find(|f| given(m, f)) {
        Some(f) => Err(Error::Usage(format!(
            "--{} does not apply to relief {command}: {why}",
            f.replace('_', "-")
        ))),
        None => Ok(()),
    }
}

/// A region of the endless world to bake: its first sample (in its spacing), samples per
/// side, and log2 of the spacing in metres.
pub(super) struct Region {
    pub(super) origin: [i32; 2],
    pub(super) size: u32,
    pub(super) spacing_log2: i32,
    pub(super) text: String,
}

pub(super) fn region(m: &ArgMatches) -> Result<Region> {
    let size = match string(m, "size") {
        None => 1024,
        Some(text) => match relief::params::param("size").map(|r| r.parse(&text)) {
            Some(Ok(Value::Int(n))) => n,
            _ => {
                return Err(Error::invalid(
                    "--size",
                    table::shorten(&text),
                    format!("1..={}", relief::params::MAX_SIZE),
                ))
            }
        },
    };
    // Without --region: --size samples every 4 m from the origin (a power of two, so any
    // --size has a region).
    let side = 4 * u64::from(size);
    let text = string(m, "region").unwrap_or_else(|| format!("0,0,{side},{side}"));
    let bad = |why: &str| {
        Error::invalid(
            "--region",
            table::shorten(&text),
            format!("X0,Z0,X1,Z1 in metres: {why} (e.g. 0,0,4096,4096 with --size 1024)"),
        )
    };
    let v: Vec<f64> = text
        .split(',')
        .map(|t| t.trim().parse::<f64>())
        .collect::<std::result::Result<_, _>>()
        .map_err(|_| bad("four numbers"))?;
    let [x0, z0, x1, z1] = v[..] else {
        return Err(bad("four numbers"));
    };
    if !v.iter().all(|c| c.is_finite() && c.abs() <= MAX_COORD) {
        return Err(bad("finite numbers within ±1e9"));
    }
    if !(x1 > x0 && z1 > z0) || (x1 - x0) != (z1 - z0) {
        return Err(bad("a square with X1 > X0 and Z1 - Z0 = X1 - X0"));
    }
    let spacing = (x1 - x0) / f64::from(size);
    let log2 = spacing.log2().round() as i32;
    if !(-10..=20).contains(&log2) || 2f64.powi(log2) != spacing {
        return Err(bad(&format!(
            "side / --size = {} m per sample must be a power of two from 2^-10 to 2^20",
            relief::table::number(spacing)
        )));
    }
    let (i, j) = (x0 / spacing, z0 / spacing);
    if i.fract() != 0.0 || j.fract() != 0.0 {
        return Err(bad(&format!(
            "the corner must be a multiple of the {} m spacing",
            relief::table::number(spacing)
        )));
    }
    let limit = f64::from(i32::MAX) - f64::from(size);
    if i.abs() > limit || j.abs() > limit {
        return Err(bad("a corner within 2^31 samples of the origin"));
    }
    Ok(Region {
        origin: [i as i32, j as i32],
        size,
        spacing_log2: log2,
        text,
    })
}
