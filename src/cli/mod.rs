//! The `relief` command line: `window` (the default), `render`, `bake` and `bench`, all
//! through the same core path. The scene flags are built from the parameter table
//! ([`crate::params::PARAMS`]) and the window's own table ([`crate::app::OPTIONS`]), so every
//! parameter has its flag, its help line and its error text from one place. Every user error
//! ends in exit status 2 and one line on stderr of at most [`MAX_ERROR_CHARS`] characters.

mod bench_endless;

use self::bench_endless::bench_endless;
use crate::app::{AppOptions, Script, OPTIONS};
use crate::choice::Candidate;
use crate::error::{Error, Result};
use crate::gpu::headless::{self, Gpu, Offscreen, MAX_IMAGE, TILE};
use crate::gpu::timing::{GpuTimer, Slot, Timings};
use crate::params::{params, srgb_to_linear, SceneParam, Shading, TerrainParams};
use crate::scene::BakeInfo;
use crate::table::{self, Kind, Param, Value};
use crate::world::{world_param, WorldKind, WorldParams, WORLD_PARAMS};
use crate::{OrbitCamera, Terrain, World, WorldView};
use clap::{Arg, ArgAction, ArgMatches, Command};
use std::path::{Path, PathBuf};

/// Longest error line the CLI prints.
pub const MAX_ERROR_CHARS: usize = 200;

/// Image sides `relief render` accepts.
const IMAGE_SIDE: Kind = Kind::Int {
    min: 1,
    max: MAX_IMAGE,
};

/// Flags `relief height` refuses: they change what is drawn, not the surface.
pub const HEIGHT_REFUSES: [&str; 6] = [
    "size",
    "grid",
    "normals",
    "snow_height",
    "ao_exponent",
    "timings",
];

/// `--method`'s names: `auto` (the default: [`crate::choice`]), then the one method list.
const METHODS: Kind = Kind::Choice(&METHOD_NAMES);

/// `auto`, then [`crate::Method::NAMES`] in their order (derived, so a new method joins
/// `--method`).
const METHOD_NAMES: [&str; crate::Method::NAMES.len() + 1] = {
    let names = crate::Method::NAMES;
    let mut all = ["auto"; crate::Method::NAMES.len() + 1];
    let mut i = 0;
    while i < names.len() {
        all[i + 1] = names[i];
        i += 1;
    }
    all
};

/// `--samples`: samples a pixel of the visibility method and the hybrid.
const SAMPLES: Kind = Kind::Choice(&["1", "4"]);

/// `--raster`: where the visibility method rasterises.
const RASTERS: Kind = Kind::Choice(&["hardware", "compute"]);

/// A world point for `relief height`.
const POINT: Kind = Kind::Pair { max: 1e12 };

/// Scene keys that `relief bench` sweeps itself, so it refuses them as flags.
pub const BENCH_SWEEPS: [&str; 3] = ["size", "grid", "normals"];

fn flag_help<T>(p: &Param<T>, default: &T) -> String {
    match p.kind {
        Kind::Bool => p.doc.to_owned(),
        _ => format!(
            "{} [default: {}] [allowed: {}]",
            p.doc,
            (p.get)(default),
            p.allowed()
        ),
    }
}

fn value_arg<T>(p: &Param<T>, default: &T) -> Arg {
    let arg = Arg::new(p.key)
        .long(p.flag())
        .global(true)
        .help(flag_help(p, default));
    match p.kind {
        Kind::Bool => arg.action(ArgAction::SetTrue),
        Kind::Pair { .. } => arg.value_name("X,Y").allow_hyphen_values(true),
        _ => arg.value_name("VALUE").allow_hyphen_values(true),
    }
}

/// The command-line interface: subcommands, and the flags of both parameter tables.
pub fn command() -> Command {
    let mut cmd = Command::new("relief")
        .args_override_self(true)
        .version(env!("CARGO_PKG_VERSION"))
        .about(
            "Procedural terrain on the GPU: Perlin fBm baked by compute shaders, drawn as a \
             displaced mesh with Blinn-Phong, snow and height AO.",
        )
        .subcommand(Command::new("window").about(
            "Open a window with the scene (the default): drag to orbit, wheel to zoom, Space \
             pauses the scroll, R re-seeds, Escape quits. With --world endless: WASD or arrows \
             fly, Q/E down and up, Shift faster, drag to look, wheel for speed",
        ))
        .subcommand(
            Command::new("render")
                .about("Render one frame offscreen to a PNG, through the same code path as the window")
                .arg(Arg::new("out").long("out").required(true).value_name("FILE.png").help("output PNG file"))
                .arg(
                    Arg::new("width")
                        .long("width")
                        .default_value("1280")
                        .allow_hyphen_values(true)
                        .value_name("PIXELS")
                        .help(format!("image width [allowed: {}]", IMAGE_SIDE.allowed())),
                )
                .arg(
                    Arg::new("height")
                        .long("height")
                        .default_value("720")
                        .allow_hyphen_values(true)
                        .value_name("PIXELS")
                        .help(format!("image height [allowed: {}]", IMAGE_SIDE.allowed())),
                ),
        )
        .subcommand(
            Command::new("bake")
                .about("Bake the textures; write height.png (16-bit), normal.png, color.png and scene.toml")
                .arg(
                    Arg::new("out-dir")
                        .long("out-dir")
                        .required(true)
                        .value_name("DIR")
                        .help("output folder (created if missing)"),
                ),
        )
        .subcommand(
            Command::new("height")
                .about("Print the surface height at each world point X,Z, one per line (the library's height_at)")
                .arg(
                    Arg::new("points")
                        .required(true)
                        .num_args(1..)
                        .allow_hyphen_values(true)
                        .value_name("X,Z")
                        .help("world points [allowed: X,Z, each within ±1e12, e.g. 0.3,0.7 -0.45,0.2]"),
                ),
        )
        .subcommand(
            Command::new("bench")
                .about(
                    "Speed against accuracy: sweep texture size, grid and normal method of the \
                     mesh and the knobs of the seed's ray march on the scene the other flags \
                     give; write bench.csv, bench.png and bench.svg",
                )
                .arg(out_dir_arg("bench-out"))
                .arg(quick_arg("about a minute on a software GPU")),
        )
        .subcommand(
            Command::new("stability")
                .about(
                    "Where methods fail: sweep grazing views against the seed march's step \
                     factor and relief's reference on the scene the other flags give, against the \
                     CPU f64 ray cast; grazing views, shadow rays at a low sun, the eye far from the origin and a \
                     moving eye on the default endless world, against f64 rays, the twin and the reference; and \
                     detail against resolution and the storage precision of heights and normals \
                     against the f64 twin; and relief's tile and the blog's scrolled far from their \
                     origin; write stability.csv, world-grazing.csv, shadow.csv, distance.csv, \
                     scroll.csv, motion.csv, detail.csv, storage.csv and their charts",
                )
                .arg(out_dir_arg("stability-out"))
                .arg(quick_arg("seconds on a software GPU"))
                .arg(
                    Arg::new("axis")
                        .long("axis")
                        .action(ArgAction::Append)
                        .value_delimiter(',')
                        .value_name("NAME")
                        .help(format!(
                            "sweep only these axes, and write only their files (repeat the flag \
                             or separate names with commas) [default: all] [allowed: {}]",
                            crate::stability::Axis::names()
                        )),
                ),
        );
    let scene = TerrainParams::default();
    for p in params() {
        cmd = cmd.arg(value_arg(p, &scene));
    }
    let world = WorldParams::default();
    for p in WORLD_PARAMS
        .iter()
        .filter(|p| crate::params::param(p.key).is_none())
    {
        cmd = cmd.arg(
            value_arg(p, &world).help(format!("--world endless only: {}", flag_help(p, &world))),
        );
    }
    let app = AppOptions::default();
    for p in &OPTIONS {
        cmd = cmd.arg(value_arg(p, &app).help(format!("window only: {}", flag_help(p, &app))));
    }
    cmd.arg(
        Arg::new("world")
            .long("world")
            .global(true)
            .value_name("WORLD")
            .help(format!(
                "tile (the seed blog's periodic tile, seen from outside) or endless (a landscape \
                 in metres to the horizon: render, bake --region, height, bench, the window, the \
                 page and scene files) [default: tile] [allowed: {}]",
                WORLDS.allowed()
            )),
    )
    .arg(
        Arg::new("eye")
            .long("eye")
            .global(true)
            .value_name("X,Y,Z")
            .allow_hyphen_values(true)
            .help("render (and the endless world's window): camera position (world units; metres in the endless world)"),
    )
    .arg(
        Arg::new("look-at")
            .long("look-at")
            .global(true)
            .value_name("X,Y,Z")
            .allow_hyphen_values(true)
            .help("render: the point the camera looks at"),
    )
    .arg(
        Arg::new("fov")
            .long("fov")
            .global(true)
            .value_name("DEG")
            .allow_hyphen_values(true)
            .help(format!(
                "render: vertical field of view in degrees [default: 45] [allowed: {}]",
                FOV.allowed()
            )),
    )
    .arg(
        Arg::new("region")
            .long("region")
            .global(true)
            .value_name("X0,Z0,X1,Z1")
            .allow_hyphen_values(true)
            .help(
                "bake --world endless: the square of the world to bake, in metres; its side \
                 over --size must be a power of two (metres per sample) and its corner a \
                 multiple of it [default: --size samples every 4 m from 0,0: \
                 0,0,4096,4096 at the default --size 1024]",
            ),
    )
    .arg(
        Arg::new("method")
            .long("method")
            .global(true)
            .value_name("METHOD")
            .help(format!(
                "render and the window: how frames are drawn: auto (the fastest of {} on this GPU, \
                 measured over a few frames first; --timings says which and why); {} \
                 [default: auto for render, mesh for the window (M steps through the methods)] \
                 [allowed: {}]",
                ["tile", "endless"]
                    .map(|w| {
                        let world = crate::WorldKind::from_name(w).unwrap_or_default();
                        let all = crate::choice::Candidate::all(world);
                        let names: Vec<String> =
                            all.iter().map(|c| c.to_string()).collect();
                        format!("{} in the {w} world", names.join(", "))
                    })
                    .join("; "),
                crate::Method::ALL
                    .iter()
                    .map(|m| format!("{m} ({})", m.doc()))
                    .collect::<Vec<_>>()
                    .join("; "),
                METHODS.allowed()
            )),
    )
    .arg(
        Arg::new("samples")
            .long("samples")
            .global(true)
            .value_name("N")
            .help(format!(
                "render and the window: samples a pixel the visibility method and the hybrid rasterise and \
                 shade (4: edges anti-aliased; 1: a quarter of the raster work) \
                 [default: 4] [allowed: {}]",
                SAMPLES.allowed()
            )),
    )
    .arg(
        Arg::new("raster")
            .long("raster")
            .global(true)
            .value_name("WHERE")
            .help(format!(
                "render and the window: where the visibility method and the hybrid rasterise their mesh: \
                 the GPU's rasteriser, or a compute pass (at --samples 1 only; on a \
                 GPU with few raster units it is the faster) [default: hardware] \
                 [allowed: {}]",
                RASTERS.allowed()
            )),
    )
    .arg(
        Arg::new("camera")
            .long("camera")
            .global(true)
            .value_name("CAMERA")
            .help(format!(
                "render (and the endless world's window): orbit (the tile's), fly (the endless \
                 world's default: --eye, --look-at) or path (the endless world's fly-through, \
                 at --time) [allowed: {}]",
                CAMERAS.allowed()
            )),
    )
    .arg(
        Arg::new("time")
            .long("time")
            .global(true)
            .value_name("SECONDS")
            .allow_hyphen_values(true)
            .help(format!(
                "render: position along --camera path, in seconds [default: 0] [allowed: {}]",
                TIME.allowed()
            )),
    )
    .arg(
        Arg::new("stats")
            .long("stats")
            .global(true)
            .action(ArgAction::SetTrue)
            .help("render: print what the frame drew as `key value` lines (triangles, texels baked, levels, screen-error bound, texture memory)"),
    )
    .arg(
        Arg::new("scene")
            .long("scene")
            .global(true)
            .value_name("FILE")
            .help("scene file (TOML) to start from; flags override it"),
    )
    .arg(
        Arg::new("timings")
            .long("timings")
            .global(true)
            .action(ArgAction::SetTrue)
            .help("print GPU pass times (needs timestamp queries on the adapter)"),
    )
    .arg(
        Arg::new("exit-after")
            .long("exit-after")
            .global(true)
            .value_name("SECONDS")
            .allow_hyphen_values(true)
            .help(format!(
                "window only: close the window after this long [allowed: {}]",
                EXIT_AFTER.allowed()
            )),
    )
    .arg(
        // Tests the window's recovery from a lost GPU device (a driver reset, say).
        Arg::new("test-lose-device")
            .long("test-lose-device")
            .global(true)
            .hide(true)
            .value_name("FRAMES")
            .allow_hyphen_values(true),
    )
}

/// `--world`'s names.
const WORLDS: Kind = Kind::Choice(WorldKind::NAMES);

/// `--fov`'s range in degrees (open at both ends in truth: 0 and 180 draw nothing).
const FOV: Kind = Kind::Float {
    min: 1.0,
    max: 179.0,
};

/// `--camera`'s names.
const CAMERAS: Kind = Kind::Choice(&["orbit", "fly", "path"]);

/// `--time`'s range, seconds.
const TIME: Kind = Kind::Float {
    min: 0.0,
    max: 86_400.0,
};

/// Largest |coordinate| of `--eye` and `--look-at`.
const MAX_COORD: f64 = 1e9;

/// Scene keys of the tile world that the endless world has no use for.
pub const TILE_ONLY: [&str; 6] = [
    "size",
    "grid",
    "frequency",
    "height_scale",
    "offset",
    "normals",
];

/// Flags of `relief render`'s camera and statistics.
const CAMERA_FLAGS: [&str; 5] = ["eye", "look-at", "fov", "camera", "time"];

/// `--exit-after`'s range.
const EXIT_AFTER: Kind = Kind::Float {
    min: 0.0,
    max: 86400.0,
};

/// The commands' names: `window` (the default) and the subcommands.
pub const COMMANDS: [&str; 6] = ["window", "render", "bake", "bench", "stability", "height"];

/// The flags `command` refuses in either world (so its `--help` leaves them out); the refusals
/// themselves are `run`'s, with their reasons.
pub fn refused_by(command: &str) -> Vec<&'static str> {
    let window_only: Vec<&'static str> = OPTIONS
        .iter()
        .map(|p| p.key)
        .chain(["exit-after", "test-lose-device"])
        .collect();
    let drawing = ["method", "samples", "raster"];
    let world_only: Vec<&'static str> = WORLD_PARAMS
        .iter()
        .map(|p| p.key)
        .filter(|k| crate::params::param(k).is_none())
        .collect();
    let mut out: Vec<&'static str> = match command {
        "window" => vec!["stats", "region"],
        "render" => [&window_only[..], &["region"]].concat(),
        "bake" => [&window_only[..], &drawing, &CAMERA_FLAGS, &["stats"]].concat(),
        "bench" => [
            &window_only[..],
            &drawing,
            &CAMERA_FLAGS,
            &["stats", "region", "timings"],
            &BENCH_SWEEPS,
        ]
        .concat(),
        "stability" => [
            &window_only[..],
            &drawing,
            &CAMERA_FLAGS,
            &[
                "stats",
                "region",
                "timings",
                "world",
                "size",
                "grid",
                "normals",
                "height_scale",
            ],
            &world_only,
        ]
        .concat(),
        "height" => [
            &window_only[..],
            &drawing,
            &CAMERA_FLAGS,
            &["stats", "region", "pixel_error"],
            &HEIGHT_REFUSES,
        ]
        .concat(),
        _ => Vec::new(),
    };
    out.sort_unstable();
    out.dedup();
    out
}

/// [`command`] as `command`'s `--help` shows it: without the flags it refuses.
fn command_for_help(name: &str) -> Command {
    let hidden = refused_by(name);
    command().mut_args(|a| {
        if hidden.contains(&a.get_id().as_str()) {
            a.hide(true)
        } else {
            a
        }
    })
}

/// Runs the CLI on `args` and returns the process exit status.
pub fn main_with_args(args: impl IntoIterator<Item = std::ffi::OsString>) -> i32 {
    let args: Vec<std::ffi::OsString> = args.into_iter().collect();
    let matches = match command().try_get_matches_from(&args) {
        Ok(m) => m,
        Err(e) if e.kind() == clap::error::ErrorKind::DisplayHelp => {
            // Each command's help lists the flags it takes, not every global one.
            let name = args
                .iter()
                .skip(1)
                .filter_map(|a| a.to_str())
                .find(|a| COMMANDS.contains(a))
                .unwrap_or("window");
            return clap_error(
                command_for_help(name)
                    .try_get_matches_from(&args)
                    .err()
                    .unwrap_or(e),
            );
        }
        Err(e) => return clap_error(e),
    };
    match run(&matches) {
        Ok(()) => 0,
        Err(e) => {
            eprintln!("{}", error_line(&e.to_string()));
            2
        }
    }
}

/// `error: ` and the message on one line of at most [`MAX_ERROR_CHARS`] characters. A longer
/// message loses its middle: its start names the parameter, its end the allowed values.
pub fn error_line(message: &str) -> String {
    let line: String = format!("error: {message}")
        .chars()
        .map(|c| if c.is_control() { ' ' } else { c })
        .collect();
    let n = line.chars().count();
    if n <= MAX_ERROR_CHARS {
        return line;
    }
    let keep = MAX_ERROR_CHARS - 5;
    let head: String = line.chars().take(keep / 2).collect();
    let tail: String = line.chars().skip(n - (keep - keep / 2)).collect();
    format!("{head} ... {tail}")
}

fn clap_error(e: clap::Error) -> i32 {
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
enum Drawn {
    Auto,
    Pinned(Candidate),
}

impl Drawn {
    /// The method given where it is not mesh-based (a ray caster or the blog's pipeline), which
    /// draws through its own path, not a [`Terrain`] or [`World`].
    fn own_path(self) -> Option<crate::Method> {
        match self {
            Drawn::Pinned(c) if !c.method.is_mesh() => Some(c.method),
            _ => None,
        }
    }
}

/// `--method`, `--samples` and `--raster` of `relief render` and the window, `default` where
/// `--method` is not given.
fn drawn(m: &ArgMatches, default: Drawn) -> Result<Drawn> {
    let drawn = drawn_samples(m, default)?;
    let Some(given) = string(m, "raster") else {
        return Ok(drawn);
    };
    let raster = crate::Raster::from_name(&given)
        .map_err(|_| Error::invalid("--raster", table::shorten(&given), RASTERS.allowed()))?;
    match drawn {
        Drawn::Pinned(c)
            if matches!(c.method, crate::Method::Visibility | crate::Method::Hybrid) =>
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
fn drawn_samples(m: &ArgMatches, default: Drawn) -> Result<Drawn> {
    let method = match string(m, "method") {
        None => match default {
            Drawn::Auto => None,
            Drawn::Pinned(c) => Some(c.method),
        },
        Some(text) => match text.trim() {
            "auto" => None,
            t => Some(crate::Method::from_name(t).ok_or_else(|| {
                Error::invalid("--method", table::shorten(&text), METHODS.allowed())
            })?),
        },
    };
    let Some(given) = string(m, "samples") else {
        return Ok(method.map_or(Drawn::Auto, |m| {
            Drawn::Pinned(Candidate::new(m, crate::gpu::visibility::SAMPLES))
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
        Some(m @ (crate::Method::Visibility | crate::Method::Hybrid)) => {
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
fn resolve_drawn(
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
enum Run {
    Window,
    Render {
        out: PathBuf,
        width: u32,
        height: u32,
        method: Drawn,
        camera: Camera,
        stats: bool,
    },
    Bake {
        out_dir: PathBuf,
    },
    Bench {
        out_dir: PathBuf,
        quick: bool,
    },
    Height {
        points: Vec<[f64; 2]>,
    },
    Stability {
        out_dir: PathBuf,
        quick: bool,
        axes: Vec<crate::stability::Axis>,
    },
}

/// The camera `relief render` was given: each part optional, defaults by world.
#[derive(Clone, Copy, Debug, Default)]
struct Camera {
    eye: Option<[f64; 3]>,
    look_at: Option<[f64; 3]>,
    fov_deg: Option<f32>,
    /// `--camera path` (with its `--time`).
    path: Option<f64>,
}

/// `X,Y,Z`: three finite numbers within ±[`MAX_COORD`].
fn triple(m: &ArgMatches, id: &str) -> Result<Option<[f64; 3]>> {
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

fn camera(m: &ArgMatches) -> Result<Camera> {
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
fn world_kind(m: &ArgMatches) -> Result<WorldKind> {
    match (string(m, "world"), string(m, "scene")) {
        (Some(text), _) => WorldKind::from_name(&text)
            .ok_or_else(|| Error::invalid("--world", table::shorten(&text), WORLDS.allowed())),
        (None, Some(path)) => crate::scene::scene_world(Path::new(&path)),
        (None, None) => Ok(WorldKind::Tile),
    }
}

/// The endless world: defaults, then the scene file, then the flags.
fn resolve_world(m: &ArgMatches) -> Result<WorldParams> {
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

fn string(m: &ArgMatches, id: &str) -> Option<String> {
    m.try_get_one::<String>(id).ok().flatten().cloned()
}

fn given(m: &ArgMatches, id: &str) -> bool {
    m.value_source(id) == Some(clap::parser::ValueSource::CommandLine)
}

/// Parses `--flag VALUE` of a table row, naming the flag in the error.
/// The text of `row`'s flag as given: `1` for a flag without a value (a bool).
fn flag_text<T>(m: &ArgMatches, row: &Param<T>) -> String {
    match row.kind {
        Kind::Bool => "1".to_owned(),
        _ => string(m, row.key).unwrap_or_default(),
    }
}

fn flag_value<T>(p: &Param<T>, text: &str) -> Result<Value> {
    p.parse(text)
        .map_err(|_| Error::invalid(format!("--{}", p.flag()), table::shorten(text), p.allowed()))
}

fn image_side(m: &ArgMatches, id: &str) -> Result<u32> {
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
fn resolve_scene(m: &ArgMatches) -> Result<TerrainParams> {
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

/// Refuses, in words, a `--method` that `world` does not draw.
fn drawn_in(method: crate::Method, world: WorldKind) -> Result<()> {
    match world {
        WorldKind::Endless if !method.in_world() => Err(Error::Usage(format!(
            "--method {method} draws the tile world only (its own terrain)"
        ))),
        WorldKind::Tile if !method.in_tile() => Err(Error::Usage(format!(
            "--method {method} draws the endless world only so far (--world endless)"
        ))),
        _ => Ok(()),
    }
}

/// Sets the window to draw what `drawn` stands for: a method with its samples and raster, or
/// `auto` (chosen by measurement before the first frame).
fn draw_window_with(o: &mut AppOptions, drawn: Drawn) {
    match drawn {
        Drawn::Auto => o.auto = true,
        Drawn::Pinned(c) => {
            o.method = c.method;
            o.samples = c.samples;
            o.raster = c.raster;
        }
    }
}

fn resolve_app(m: &ArgMatches, params: TerrainParams) -> Result<AppOptions> {
    let mut o = AppOptions {
        params,
        timings: m.get_flag("timings"),
        ..Default::default()
    };
    for row in OPTIONS.iter().filter(|r| given(m, r.key)) {
        (row.set)(&mut o, flag_value(row, &flag_text(m, row))?);
    }
    Ok(o)
}

fn script(m: &ArgMatches) -> Result<Script> {
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
fn refuse_flags(m: &ArgMatches, command: &str, flags: &[&str], why: &str) -> Result<()> {
    match flags.iter().find(|f| given(m, f)) {
        Some(f) => Err(Error::Usage(format!(
            "--{} does not apply to relief {command}: {why}",
            f.replace('_', "-")
        ))),
        None => Ok(()),
    }
}

fn run(top: &ArgMatches) -> Result<()> {
    let (name, m) = top.subcommand().unwrap_or(("window", top));
    let window_only: Vec<&str> = OPTIONS
        .iter()
        .map(|p| p.key)
        .chain(["exit-after", "test-lose-device"])
        .collect();
    let run = match name {
        "render" => Run::Render {
            out: PathBuf::from(string(m, "out").unwrap_or_default()),
            width: image_side(m, "width")?,
            height: image_side(m, "height")?,
            method: drawn(m, Drawn::Auto)?,
            camera: camera(m)?,
            stats: m.get_flag("stats"),
        },
        "bake" => Run::Bake {
            out_dir: PathBuf::from(string(m, "out-dir").unwrap_or_default()),
        },
        "bench" => Run::Bench {
            out_dir: PathBuf::from(string(m, "out-dir").unwrap_or_default()),
            quick: m.get_flag("quick"),
        },
        "stability" => Run::Stability {
            out_dir: PathBuf::from(string(m, "out-dir").unwrap_or_default()),
            quick: m.get_flag("quick"),
            axes: stability_axes(m)?,
        },
        "height" => Run::Height {
            points: m
                .get_many::<String>("points")
                .into_iter()
                .flatten()
                .map(|t| match POINT.parse(t) {
                    Some(Value::Pair(p)) => Ok(p),
                    _ => Err(Error::invalid(
                        "point",
                        table::shorten(t),
                        "X,Z world coordinates, each within ±1e12",
                    )),
                })
                .collect::<Result<_>>()?,
        },
        _ => Run::Window,
    };
    if !matches!(run, Run::Window) {
        refuse_flags(m, name, &window_only, "it applies to the window only")?;
    }
    if !matches!(run, Run::Window | Run::Render { .. }) {
        refuse_flags(
            m,
            name,
            &["method", "samples", "raster"],
            "it applies to relief render and the window only",
        )?;
    }
    // The window's method (the mesh unless given), checked against its world as render's is.
    let window_drawn = match run {
        Run::Window => Some(drawn(m, Drawn::Pinned(Candidate::MESH))?),
        _ => None,
    };
    // A pinned method of render or the window must be one its world draws.
    let pinned = match (&run, &window_drawn) {
        (
            Run::Render {
                method: Drawn::Pinned(c),
                ..
            },
            _,
        )
        | (_, Some(Drawn::Pinned(c))) => Some(c.method),
        _ => None,
    };
    if let Some(method) = pinned {
        drawn_in(method, world_kind(m)?)?;
    }
    if !matches!(run, Run::Render { .. }) {
        refuse_flags(m, name, &["stats"], "it applies to relief render only")?;
    }
    let endless_window = matches!(run, Run::Window) && world_kind(m)? == WorldKind::Endless;
    if !endless_window && !matches!(run, Run::Render { .. }) {
        refuse_flags(
            m,
            name,
            &CAMERA_FLAGS,
            "it applies to relief render (and the window in the endless world) only",
        )?;
    }
    if let Run::Render {
        method: Drawn::Pinned(Candidate { method, .. }),
        ..
    } = run
    {
        let why = if method == crate::Method::Blog {
            "the blog's pipeline bakes its own noise into its own texture and grid"
        } else {
            "the ray casters draw the continuous surface, not a baked mesh"
        };
        refuse_flags(
            m,
            &format!("render --method {method}"),
            method.unread_keys(),
            why,
        )?;
    }
    if matches!(run, Run::Height { .. }) {
        refuse_flags(
            m,
            name,
            &HEIGHT_REFUSES,
            "heights come from the continuous surface, not from what is drawn",
        )?;
        refuse_flags(
            m,
            name,
            &["pixel_error"],
            "heights come from the continuous surface, not from what is drawn",
        )?;
    }
    if matches!(run, Run::Stability { .. }) {
        refuse_flags(
            m,
            name,
            &["size", "grid", "normals", "height_scale"],
            "the sweep casts rays at the continuous surface, at height scales of its own",
        )?;
        refuse_flags(
            m,
            name,
            &["timings"],
            "the sweep measures failures, not time",
        )?;
        if world_kind(m)? == WorldKind::Endless {
            return Err(Error::Usage(
                "relief stability takes the tile's scene from the flags, and sweeps the default endless \
                 world for its world axes (no --world endless)"
                    .into(),
            ));
        }
    }
    if matches!(run, Run::Bench { .. }) {
        refuse_flags(
            m,
            name,
            &BENCH_SWEEPS,
            "the benchmark sweeps size, grid and normals",
        )?;
        refuse_flags(
            m,
            name,
            &["timings"],
            "the benchmark always measures GPU time",
        )?;
    }
    let world = world_kind(m)?;
    let world_only: Vec<&str> = WORLD_PARAMS
        .iter()
        .map(|p| p.key)
        .filter(|k| crate::params::param(k).is_none())
        .collect();
    match world {
        WorldKind::Tile => {
            refuse_flags(m, name, &world_only, "it applies to --world endless only")?;
            refuse_flags(
                m,
                name,
                &["region"],
                "it applies to bake --world endless only",
            )?;
        }
        WorldKind::Endless => {
            if matches!(run, Run::Window) {
                refuse_flags(
                    m,
                    &format!("{name} --world endless"),
                    &["speed", "paused"],
                    "they scroll the tile; the fly camera moves with the keys",
                )?;
                refuse_flags(
                    m,
                    &format!("{name} --world endless"),
                    &["region"],
                    "it applies to bake --world endless only",
                )?;
                let params = resolve_world(m)?;
                let view = world_view(&camera(m)?, &params, (1280, 720));
                let fly = crate::FlyCamera::looking_at(
                    view.eye,
                    view.eye + view.forward.as_dvec3(),
                    view.fov_y,
                );
                let cam = camera(m)?;
                if cam.path.is_some() {
                    refuse_flags(
                        m,
                        "window --camera path",
                        &["time"],
                        "the window starts the path at 0 s and follows it",
                    )?;
                }
                let mut options = AppOptions {
                    world: Some((params, fly)),
                    path: cam.path.is_some(),
                    timings: m.get_flag("timings"),
                    ..Default::default()
                };
                if let Some(d) = window_drawn {
                    draw_window_with(&mut options, d);
                }
                return crate::app::run_native(options, script(m)?);
            }
            // A region bake's --size is its samples per side.
            let tile_only: Vec<&str> = TILE_ONLY
                .iter()
                .copied()
                .filter(|k| !(matches!(run, Run::Bake { .. }) && *k == "size"))
                .collect();
            refuse_flags(
                m,
                &format!("{name} --world endless"),
                &tile_only,
                "it applies to the tile world only",
            )?;

            if !matches!(run, Run::Bake { .. }) {
                refuse_flags(
                    m,
                    name,
                    &["region"],
                    "it applies to bake --world endless only",
                )?;
            }
            if let Run::Bake { out_dir } = &run {
                let region = region(m)?;
                return bake_endless(&resolve_world(m)?, &region, out_dir, m.get_flag("timings"));
            }
            return run_endless(run, resolve_world(m)?, m.get_flag("timings"));
        }
    }
    let params = resolve_scene(m)?;
    let timings = m.get_flag("timings");
    match run {
        Run::Window => {
            let mut options = resolve_app(m, params)?;
            if let Some(d) = window_drawn {
                draw_window_with(&mut options, d);
            }
            crate::app::run_native(options, script(m)?)
        }
        Run::Render {
            out,
            width,
            height,
            method,
            camera,
            stats,
        } => render(
            &params,
            &out,
            (width, height),
            method,
            &camera,
            Flags { timings, stats },
        ),
        Run::Bake { out_dir } => bake(&params, &out_dir, timings),
        Run::Bench { out_dir, quick } => bench(&params, &out_dir, quick),
        Run::Stability {
            out_dir,
            quick,
            axes,
        } => stability(&params, &out_dir, quick, &axes),
        Run::Height { points } => {
            for [x, z] in points {
                println!("{}", crate::height_at(&params, x as f32, z as f32));
            }
            Ok(())
        }
    }
}

/// What `relief render` prints besides the image.
#[derive(Clone, Copy, Debug)]
struct Flags {
    timings: bool,
    stats: bool,
}

/// The tile world's view: the default orbit, or the camera given (all in tile units).
fn tile_view(camera: &Camera, (width, height): (u32, u32)) -> crate::View {
    let orbit = OrbitCamera::default();
    let aspect = width as f32 / height as f32;
    if camera.eye.is_none() && camera.look_at.is_none() && camera.fov_deg.is_none() {
        return orbit.view(aspect);
    }
    let eye = camera
        .eye
        .map_or(orbit.eye(), |e| glam::DVec3::from(e).as_vec3());
    let target = camera
        .look_at
        .map_or(orbit.target, |t| glam::DVec3::from(t).as_vec3());
    let fov = camera.fov_deg.map_or(orbit.fov_y, |d| d.to_radians());
    let distance = (target - eye).length().max(1e-3);
    let up = if (target - eye).normalize().y.abs() > 0.999 {
        glam::Vec3::Z
    } else {
        glam::Vec3::Y
    };
    let proj =
        glam::Mat4::perspective_rh(fov, aspect, (distance * 0.01).max(0.001), distance + 10.0);
    crate::View {
        view_proj: proj * glam::Mat4::look_at_rh(eye, target, up),
        eye,
    }
}

/// The endless world's view: by default from 1200 m above the ground, looking east-north-east
/// and a little down over ridges that run out to the horizon (chosen by eye).
fn world_view(camera: &Camera, params: &WorldParams, size: (u32, u32)) -> WorldView {
    let land = &params.land;
    if let Some(t) = camera.path {
        let path = crate::PathCamera {
            fov_y: camera
                .fov_deg
                .map_or(crate::PathCamera::default().fov_y, f32::to_radians),
            ..Default::default()
        };
        return path.view(|x, z| land.height_at(x, z), t, size);
    }
    let (default_eye, default_target) = crate::gpu::world::default_camera(land);
    let eye = camera.eye.map_or(default_eye, glam::DVec3::from);
    let target = camera
        .look_at
        .map_or_else(|| eye + (default_target - default_eye), glam::DVec3::from);
    let fov = camera.fov_deg.unwrap_or(45.0).to_radians();
    WorldView::look_at(eye, target, fov, size)
}

/// A region of the endless world to bake: its first sample (in its spacing), samples per
/// side, and log2 of the spacing in metres.
struct Region {
    origin: [i32; 2],
    size: u32,
    spacing_log2: i32,
    text: String,
}

fn region(m: &ArgMatches) -> Result<Region> {
    let size = match string(m, "size") {
        None => 1024,
        Some(text) => match crate::params::param("size").map(|r| r.parse(&text)) {
            Some(Ok(Value::Int(n))) => n,
            _ => {
                return Err(Error::invalid(
                    "--size",
                    table::shorten(&text),
                    format!("1..={}", crate::params::MAX_SIZE),
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
            crate::table::number(spacing)
        )));
    }
    let (i, j) = (x0 / spacing, z0 / spacing);
    if i.fract() != 0.0 || j.fract() != 0.0 {
        return Err(bad(&format!(
            "the corner must be a multiple of the {} m spacing",
            crate::table::number(spacing)
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

/// `relief bake --world endless`: a region's heights, normals and colour as PNGs, and the
/// parameters with the region in scene.toml.
fn bake_endless(params: &WorldParams, region: &Region, dir: &Path, timings: bool) -> Result<()> {
    check_out_dir(dir)?;
    let gpu = Gpu::new()?;
    let timer = timer_if(timings, &gpu);
    let land = params.land;
    let size = region.size;
    let texels = size as usize * size as usize;
    let shading = Shading::default();
    let (mut heights, mut normal, mut color) = (
        Vec::with_capacity(texels),
        Vec::with_capacity(texels * 3),
        Vec::with_capacity(texels * 3),
    );
    let peak = land.peak_height as f32;
    let ms = headless::bake_region(
        &gpu,
        &land,
        region.origin,
        size,
        region.spacing_log2,
        timer.as_ref(),
        |_, band| {
            for t in band {
                heights.push(t[0] * peak);
                let n = glam::Vec3::new(-t[1] * peak, 1.0, -t[2] * peak).normalize();
                normal.extend(
                    n.to_array()
                        .map(|c| ((c * 0.5 + 0.5) * 255.0).round().clamp(0.0, 255.0) as u8),
                );
                color.extend(albedo_srgb8(&shading, t[3]));
            }
        },
    )?;
    if timings {
        match ms {
            Some(ms) => println!(
                "timings on {}: bake {ms:.3} ms ({:.1} G octave-samples/s, counting height and colour; \
                 each band's median of {} bakes after {} ms of warm-up)",
                gpu.describe(),
                2.0 * texels as f64 * f64::from(land.octaves_for_level(region.spacing_log2))
                    / (ms * 1e6),
                headless::BAKE_RUNS,
                headless::BAKE_WARM_UP.as_millis(),
            ),
            None => println!("timings: {} has no timestamp queries", gpu.describe()),
        }
    }
    let (height, lo, hi) = heights_16(&heights);
    drop(heights);
    let mut scene = String::from(
        "# relief endless-world bake: the world's parameters and the region baked.\n\
         # `relief render --scene FILE` draws this world (the [bake] record changes nothing).\n\
         world = \"endless\"\n",
    );
    for row in &WORLD_PARAMS {
        scene.push_str(&format!(
            "{} = {}\n",
            row.key,
            crate::scene::toml_value((row.get)(params))
        ));
    }
    let spacing = 2f64.powi(region.spacing_log2);
    scene.push_str(&format!(
        "\n# The square baked (metres), its samples per side and spacing, the octaves the spacing \
         keeps, and the heights in metres that 0 and 65535 in height.png stand for.\n[bake]\n\
         region = [{}]\nsize = {size}\nspacing = {spacing:?}\noctaves_kept = {}\n\
         height_min = {:?}\nheight_max = {:?}\n",
        region
            .text
            .split(',')
            .map(str::trim)
            .collect::<Vec<_>>()
            .join(", "),
        land.octaves_for_level(region.spacing_log2),
        f64::from(lo),
        f64::from(hi),
    ));
    write_bake(dir, size, &height, &normal, &color, &scene)?;
    println!(
        "baked {size}x{size} samples every {} m of region {} into {}: heights {lo:.3}..{hi:.3} m map to 0..65535",
        crate::table::number(spacing),
        region.text,
        dir.display()
    );
    Ok(())
}

fn run_endless(run: Run, params: WorldParams, timings: bool) -> Result<()> {
    match run {
        Run::Height { points } => {
            for [x, z] in points {
                println!("{}", params.land.height_at(x, z));
            }
            Ok(())
        }
        Run::Render {
            out,
            width,
            height,
            camera,
            stats,
            method,
        } => {
            check_png_path(&out)?;
            let view = world_view(&camera, &params, (width, height));
            let ground = params.land.height_at(view.eye.x, view.eye.z);
            if view.eye.y <= ground {
                return Err(Error::Usage(format!(
                    "the eye {},{},{} is under the ground, which is at {ground:.1} m there: \
                     give an --eye (or [camera] eye) above it",
                    table::number(view.eye.x),
                    table::number(view.eye.y),
                    table::number(view.eye.z),
                )));
            }
            let gpu = Gpu::new()?;
            let timer = timer_if(timings, &gpu);
            if let Some(method) = method.own_path() {
                let image = headless::render_world_rays(
                    &gpu,
                    &params,
                    &Shading::default(),
                    &view,
                    method,
                    timer.as_ref(),
                )?;
                if timings {
                    print_timings(&gpu, image.timings);
                }
                if stats {
                    // Rays draw the continuous surface: no mesh, nothing baked.
                    println!("triangles 0\ntexels_baked 0\ntexels_pending 0\nlevels 0");
                    println!("unresolved_rays {}", image.unresolved);
                }
                if image.unresolved > 0 {
                    eprintln!(
                        "relief: {} rays ran out of steps ({} each) and are drawn as sky",
                        image.unresolved,
                        crate::gpu::world_rays::MAX_STEPS
                    );
                }
                return write_png(&out, width, height, image::ColorType::Rgba8, &image.rgba);
            }
            let targets = Offscreen::targets(headless::RENDER_SAMPLES);
            let mut world = World::new(&gpu.device, &gpu.queue, targets, params)?;
            let scene = headless::TrialScene::Endless(&mut world, &view);
            resolve_drawn(&gpu, method, scene, timings)?;
            let (pixels, t) = headless::render_world_image(
                &gpu,
                &mut world,
                &view,
                (width, height),
                TILE,
                timer.as_ref(),
            )?;
            if timings {
                print_timings(&gpu, t);
            }
            if let Some(line) = knob_warning(&world.stats(), params.pixel_error, (width, height)) {
                eprintln!("{line}");
            }
            if stats {
                // The still frame's whole bake, whatever the method (or auto's trial) baked
                // in which frame.
                let mut s = world.stats();
                s.texels_baked = world.held_texels();
                for line in s.lines() {
                    println!("{line}");
                }
                println!(
                    "method_texture_mib {:.1}",
                    crate::gpu::world::mib(world.method_bytes())
                );
            }
            write_png(&out, width, height, image::ColorType::Rgba8, &pixels)
        }
        Run::Bench { out_dir, quick } => bench_endless(&params, &out_dir, quick),
        _ => Err(Error::Usage(
            "--world endless applies to relief render, height and bench only".into(),
        )),
    }
}

/// Writes `text` to `path` whole or not at all (a temporary name, then a rename).
fn write_whole(path: &Path, text: &str) -> Result<()> {
    let tmp = temp_name(path);
    std::fs::write(&tmp, text).map_err(|e| Error::io(&tmp, e))?;
    std::fs::rename(&tmp, path).map_err(|e| Error::io(path, e))
}

fn render(
    params: &TerrainParams,
    out: &Path,
    (width, height): (u32, u32),
    method: Drawn,
    camera: &Camera,
    flags: Flags,
) -> Result<()> {
    check_png_path(out)?;
    let Flags { timings, stats } = flags;
    let gpu = Gpu::new()?;
    let timer = timer_if(timings, &gpu);
    let view = tile_view(camera, (width, height));
    let mut drawn = None;
    let own_path = method.own_path();
    let (pixels, t) = if own_path.is_none() {
        let targets = Offscreen::targets(headless::RENDER_SAMPLES);
        let mut terrain = Terrain::new(&gpu.device, &gpu.queue, targets, *params)?;
        let scene = headless::TrialScene::Tile(&mut terrain, &view, (width, height));
        resolve_drawn(&gpu, method, scene, timings)?;
        let frame = headless::render_image(
            &gpu,
            &mut terrain,
            &view,
            (width, height),
            TILE,
            timer.as_ref(),
        )?;
        // The still frame's whole bake: the levels' texels and the tile's own textures.
        let mut s = terrain.world().stats();
        s.texels_baked = terrain.world().held_texels() + u64::from(params.size).pow(2);
        drawn = Some((s, params.size, terrain.world().method_bytes()));
        frame
    } else if own_path == Some(crate::Method::Blog) {
        let scene = (params, &Shading::default());
        let image = headless::BlogImage::Pipeline;
        headless::render_blog(&gpu, scene, &view, (width, height), image, timer.as_ref())?
    } else {
        headless::render_rays(
            &gpu,
            params,
            &Shading::default(),
            &view,
            (width, height),
            own_path.unwrap_or_default(),
            timer.as_ref(),
        )?
    };
    if timings {
        print_timings(&gpu, t);
    }
    if stats {
        // The mesh's levels (the clipmap renderer's stats); the ray casters draw no triangles.
        // The tile's own textures (its heights, colour and normals) come on top of the levels'.
        match drawn {
            Some((s, size, method_bytes)) => {
                s.lines().iter().for_each(|l| println!("{l}"));
                let tile = crate::gpu::Textures::bytes(size);
                println!("tile_texture_mib {:.1}", crate::gpu::world::mib(tile));
                println!(
                    "method_texture_mib {:.1}",
                    crate::gpu::world::mib(method_bytes)
                );
                println!(
                    "total_texture_mib {:.1}",
                    crate::gpu::world::mib(tile + s.texture_bytes())
                );
            }
            None if own_path == Some(crate::Method::Blog) => {
                // The blog's grid, and its two 8-bit maps baked whole every frame.
                let side = u64::from(crate::gpu::blog::BLOG_SIZE);
                let bytes =
                    2 * side * side * crate::gpu::texel_bytes(crate::gpu::blog::BLOG_FORMAT);
                println!("triangles {}", (side - 1).pow(2) * 2);
                println!("texels_baked {}\ntexels_pending 0\nlevels 0", side * side);
                println!("total_texture_mib {:.1}", crate::gpu::world::mib(bytes));
            }
            None => println!("triangles 0\ntexels_baked 0\ntexels_pending 0\nlevels 0"),
        }
    }
    write_png(out, width, height, image::ColorType::Rgba8, &pixels)
}

fn timer_if(wanted: bool, gpu: &Gpu) -> Option<GpuTimer> {
    wanted
        .then(|| GpuTimer::new(&gpu.device, &gpu.queue))
        .flatten()
}

fn print_timings(gpu: &Gpu, t: Option<Timings>) {
    let Some(t) = t else {
        println!("timings: {} has no timestamp queries", gpu.describe());
        return;
    };
    let parts: Vec<String> = Slot::ALL
        .iter()
        .filter_map(|&s| t[s as usize].map(|ms| format!("{} {ms:.3} ms", s.name())))
        .collect();
    println!("timings on {}: {}", gpu.describe(), parts.join(", "));
}

/// The albedo `color.png` shows for a colour-channel value: the two albedos mixed in linear
/// light, as the renderer mixes them, then encoded to sRGB.
pub fn albedo_srgb8(shading: &Shading, channel: f32) -> [u8; 3] {
    let t = smoothstep(0.2, 0.8, channel);
    [0, 1, 2].map(|i| {
        let a = srgb_to_linear(shading.color_a[i]);
        let b = srgb_to_linear(shading.color_b[i]);
        (linear_to_srgb(a + (b - a) * t) * 255.0).round() as u8
    })
}

/// Linear component to sRGB-encoded, as the shader's `srgb_encode`.
pub fn linear_to_srgb(c: f32) -> f32 {
    let c = c.clamp(0.0, 1.0);
    if c <= 0.003_130_8 {
        c * 12.92
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

/// Heights as 16-bit PNG samples spanning their range, with the range. A flat bake has no range
/// to spread over 0..65535: every sample is 0, and the scene file's min = max says so.
fn heights_16(heights: &[f32]) -> (Vec<u8>, f32, f32) {
    let (lo, hi) = heights
        .iter()
        .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), &h| {
            (lo.min(h), hi.max(h))
        });
    let span = hi - lo;
    let bytes = heights
        .iter()
        .flat_map(|&h| {
            let v = if span > 0.0 {
                ((h - lo) / span * 65535.0).round() as u16
            } else {
                0
            };
            v.to_ne_bytes()
        })
        .collect();
    (bytes, lo, hi)
}

/// Writes a bake's four files into `dir`, all or none.
fn write_bake(
    dir: &Path,
    size: u32,
    height: &[u8],
    normal: &[u8],
    color: &[u8],
    scene: &str,
) -> Result<()> {
    let files: [(&str, FileWriter); 4] = [
        (
            "height.png",
            Box::new(|p| encode_png(p, size, size, image::ColorType::L16, height)),
        ),
        (
            "normal.png",
            Box::new(|p| encode_png(p, size, size, image::ColorType::Rgb8, normal)),
        ),
        (
            "color.png",
            Box::new(|p| encode_png(p, size, size, image::ColorType::Rgb8, color)),
        ),
        (
            "scene.toml",
            Box::new(|p| std::fs::write(p, scene.as_bytes()).map_err(|e| Error::io(p, e))),
        ),
    ];
    write_all(dir, &files)
}

fn bake(params: &TerrainParams, dir: &Path, timings: bool) -> Result<()> {
    check_out_dir(dir)?;
    let gpu = Gpu::new()?;
    let mut terrain = Terrain::new(&gpu.device, &gpu.queue, Offscreen::targets(1), *params)?;
    let timer = timer_if(timings, &gpu);
    headless::bake_blocking(&gpu, &mut terrain, None)?;
    if let Some(timer) = &timer {
        // Timed as the region bake is: re-baked after a warm-up, the median of several.
        let t = headless::warm_median(timer, |t| {
            terrain.invalidate();
            headless::bake_blocking(&gpu, &mut terrain, t)
        })?;
        print_timings(&gpu, Some(t));
        println!(
            "(each the median of {} bakes after {} ms of warm-up)",
            headless::BAKE_RUNS,
            headless::BAKE_WARM_UP.as_millis()
        );
    } else if timings {
        print_timings(&gpu, None);
    }
    let size = params.size;
    let texels = size as usize * size as usize;
    let shading = Shading::default();

    // Read back in bands, converting each band at once: a 16384² bake is 4 GiB on the GPU,
    // and only the heights (needed twice, for their range) are kept as floats.
    let mut heights = Vec::with_capacity(texels);
    let mut color = Vec::with_capacity(texels * 3);
    let textures = terrain.textures();
    headless::read_texture_bands(
        &gpu.device,
        &gpu.queue,
        &textures.terrain,
        headless::MAX_READBACK_BYTES,
        |_, rows| {
            for rg in rows.chunks_exact(8) {
                let f = |i: usize| f32::from_ne_bytes([rg[i], rg[i + 1], rg[i + 2], rg[i + 3]]);
                heights.push(f(0));
                color.extend(albedo_srgb8(&shading, f(4)));
            }
        },
    )?;
    let mut normal = Vec::with_capacity(texels * 3);
    headless::read_texture_bands(
        &gpu.device,
        &gpu.queue,
        &textures.normals,
        headless::MAX_READBACK_BYTES,
        |_, rows| {
            for n in rows.chunks_exact(8) {
                normal.extend([0, 1, 2].map(|i| {
                    let bits = u16::from_ne_bytes([n[2 * i], n[2 * i + 1]]);
                    let c = half::f16::from_bits(bits).to_f32();
                    ((c * 0.5 + 0.5) * 255.0).round().clamp(0.0, 255.0) as u8
                }));
            }
        },
    )?;
    drop(terrain);

    let (height, lo, hi) = heights_16(&heights);
    let span = hi - lo;
    drop(heights);
    let scene = params.to_scene_string(Some(BakeInfo {
        height_min: f64::from(lo),
        height_max: f64::from(hi),
    }));

    write_bake(dir, size, &height, &normal, &color, &scene)?;
    if span > 0.0 {
        println!(
            "baked {size}x{size} into {}: heights {lo:.6}..{hi:.6} map to 0..65535",
            dir.display()
        );
    } else {
        println!(
            "baked {size}x{size} into {}: flat, every height is {lo:.6}; height.png is all 0 \
             and the scene file's height_min = height_max",
            dir.display()
        );
    }
    Ok(())
}

/// Writes one output file to the path it is given.
type FileWriter<'a> = Box<dyn Fn(&Path) -> Result<()> + 'a>;

/// Writes every file under a temporary name in `dir` (created if missing), then renames them
/// all; on any failure removes what it wrote, and the folders it created.
fn write_all(dir: &Path, files: &[(&str, FileWriter)]) -> Result<()> {
    let created = create_dirs(dir)?;
    let cleanup = |written: &[(PathBuf, PathBuf)]| {
        for (t, _) in written {
            let _ = std::fs::remove_file(t);
        }
        if let Some(c) = &created {
            let _ = std::fs::remove_dir_all(c);
        }
    };
    let mut written = Vec::new();
    for (name, write) in files {
        let tmp = temp_name(&dir.join(name));
        if let Err(e) = write(&tmp) {
            let _ = std::fs::remove_file(&tmp);
            cleanup(&written);
            return Err(e);
        }
        written.push((tmp, dir.join(name)));
    }
    for (tmp, fin) in &written {
        if let Err(e) = std::fs::rename(tmp, fin) {
            cleanup(&written);
            return Err(Error::io(fin, e));
        }
    }
    Ok(())
}

/// Creates `dir` and missing parents; returns the top-most folder it created (to remove on
/// failure), or `None` if `dir` existed.
fn create_dirs(dir: &Path) -> Result<Option<PathBuf>> {
    let mut top = None;
    let mut p = Some(dir);
    while let Some(d) = p.filter(|d| !d.as_os_str().is_empty() && !d.exists()) {
        top = Some(d.to_owned());
        p = d.parent();
    }
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    Ok(top)
}

/// Checks before any GPU work that `dir` is, or can become, a folder.
fn check_out_dir(dir: &Path) -> Result<()> {
    if dir.as_os_str().is_empty() {
        return Err(Error::invalid("--out-dir", "\"\"", "a folder path"));
    }
    let mut p = Some(dir);
    while let Some(d) = p {
        if d.as_os_str().is_empty() {
            break;
        }
        if d.exists() {
            if d.is_dir() {
                return probe_writable(d);
            }
            let what = if d == dir {
                "a folder, or a path to create one; this is a file".to_owned()
            } else {
                format!(
                    "a path whose parents are folders; {} is a file",
                    crate::error::short_path(d)
                )
            };
            return Err(Error::invalid(
                "--out-dir",
                crate::error::short_path(dir),
                what,
            ));
        }
        p = d.parent();
    }
    Ok(())
}

/// Checks that files can be made in the folder `dir` (a read-only folder, `/proc`, another
/// user's) by making and removing an empty probe folder in it, before any work is done.
fn probe_writable(dir: &Path) -> Result<()> {
    let probe = dir.join(format!(".relief-probe-{}", std::process::id()));
    std::fs::create_dir(&probe).map_err(|e| Error::io(dir, e))?;
    let _ = std::fs::remove_dir(&probe);
    Ok(())
}

struct Bar(indicatif::ProgressBar);

impl crate::bench::Progress for Bar {
    fn start(&mut self, index: usize, _total: usize, config: &crate::bench::Config) {
        self.0.set_position(index as u64);
        self.0.set_message(config.label());
    }
}

fn bench(base: &TerrainParams, dir: &Path, quick: bool) -> Result<()> {
    use crate::bench;
    check_out_dir(dir)?;
    let gpu = Gpu::new()?;
    let info = gpu.adapter.get_info();
    let options = if quick {
        bench::Options::QUICK
    } else {
        bench::Options::FULL
    };
    let configs = bench::sweep(base, quick);
    // Every swept configuration must fit this device before anything runs.
    for c in &configs {
        c.params.validate_for(&gpu.device.limits())?;
    }
    if GpuTimer::new(&gpu.device, &gpu.queue).is_none() {
        println!(
            "note: {} has no timestamp queries: GPU times are empty, only wall times are measured",
            gpu.describe()
        );
    }
    println!(
        "relief bench{} on {}: {} configurations at {}x{}, reference at {}x supersampling, scene: seed {}, octaves {}, frequency {}, gain {}, height scale {}",
        if quick { " --quick" } else { "" },
        gpu.describe(),
        configs.len(),
        options.width,
        options.height,
        options.supersample,
        base.seed,
        base.octaves,
        base.frequency,
        base.gain,
        base.height_scale,
    );
    let bar = indicatif::ProgressBar::new(configs.len() as u64).with_style(
        indicatif::ProgressStyle::with_template("{bar:30} {pos}/{len} {elapsed} {msg}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    let mut progress = Bar(bar);
    let start = std::time::Instant::now();
    let rows = bench::run(&gpu, base, &configs, &options, &mut progress)?;
    progress.0.finish_and_clear();
    print!("{}", bench::table(&rows));
    let csv = bench::csv(&rows, &info.name, &format!("{:?}", info.backend), &options);
    let title = format!(
        "relief: error against GPU time on {} ({:?})",
        info.name, info.backend
    );
    write_results(dir, ("bench.csv", &csv), || {
        bench::chart(&rows, &title, &dir.join("bench"))
    })?;
    println!(
        "wrote {}, bench.png and bench.svg in {:.0} s",
        dir.join("bench.csv").display(),
        start.elapsed().as_secs_f64()
    );
    Ok(())
}

/// A sweep's `--out-dir`, defaulting to `default`.
fn out_dir_arg(default: &'static str) -> Arg {
    Arg::new("out-dir")
        .long("out-dir")
        .default_value(default)
        .value_name("DIR")
        .help("output folder (created if missing)")
}

/// A sweep's `--quick`, taking about `how_long`.
fn quick_arg(how_long: &str) -> Arg {
    Arg::new("quick")
        .long("quick")
        .action(ArgAction::SetTrue)
        .help(format!("a small sweep at a small image size ({how_long})"))
}

/// Writes a sweep's CSV into `dir` (whole or not at all) and then its charts with `charts`; a
/// folder this created is removed again if either fails.
fn write_results(
    dir: &Path,
    (name, csv): (&str, &str),
    charts: impl FnOnce() -> Result<()>,
) -> Result<()> {
    let created = create_dirs(dir)?;
    let result = write_whole(&dir.join(name), csv).and_then(|()| charts());
    if result.is_err() {
        if let Some(c) = created {
            let _ = std::fs::remove_dir_all(c);
        }
    }
    result
}

/// The axes `relief stability --axis` names, each once, in the order they run; all of them
/// without the flag.
fn stability_axes(m: &ArgMatches) -> Result<Vec<crate::stability::Axis>> {
    use crate::stability::Axis;
    let Some(names) = m.get_many::<String>("axis") else {
        return Ok(Axis::ALL.to_vec());
    };
    let mut chosen = Vec::new();
    for name in names {
        let axis = Axis::parse(name.trim())
            .ok_or_else(|| Error::invalid("--axis", table::shorten(name), Axis::names()))?;
        chosen.push(axis);
    }
    Ok(Axis::ALL
        .into_iter()
        .filter(|a| chosen.contains(a))
        .collect())
}

/// An axis's results: its CSV's file name and text, and what writes its charts.
type AxisOutput<'a> = (&'static str, String, Box<dyn FnOnce() -> Result<()> + 'a>);

fn stability(
    base: &TerrainParams,
    dir: &Path,
    quick: bool,
    axes: &[crate::stability::Axis],
) -> Result<()> {
    use crate::stability::{self, Axis};
    check_out_dir(dir)?;
    let gpu = Gpu::new()?;
    let info = gpu.adapter.get_info();
    let backend = format!("{:?}", info.backend);
    let device = info.name.clone();
    let on = |axis| axes.contains(&axis);
    println!(
        "relief stability{} on {}: {} {} ({}), scene: seed {}, octaves {}, frequency {}, gain {}",
        if quick { " --quick" } else { "" },
        gpu.describe(),
        axes.len(),
        if axes.len() == 1 { "axis" } else { "axes" },
        axes.iter().map(|a| a.name()).collect::<Vec<_>>().join(", "),
        base.seed,
        base.octaves,
        base.frequency,
        base.gain,
    );
    let bar = indicatif::ProgressBar::new(0).with_style(
        indicatif::ProgressStyle::with_template("{bar:30} {pos}/{len} {elapsed}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    let restart = |len: usize| {
        bar.reset();
        bar.set_length(len as u64);
    };
    let start = std::time::Instant::now();
    let world = WorldParams::default();
    let mut outputs: Vec<AxisOutput<'_>> = Vec::new();
    if on(Axis::Grazing) {
        let options = if quick {
            stability::Options::quick()
        } else {
            stability::Options::full()
        };
        println!(
            "grazing views of the scene's tile at {:?} degrees, height scales {:?}, {}x{} (every {} px compared with the CPU f64 ray cast)",
            options.elevations,
            options.height_scales,
            options.size.0,
            options.size.1,
            options.stride,
        );
        restart(options.elevations.len() * options.height_scales.len());
        let rows = stability::grazing(&gpu, base, &options, |done, _| {
            bar.set_position(done as u64)
        })?;
        bar.finish_and_clear();
        print!("{}", stability::table(&rows, &options));
        let csv = stability::csv(&rows, &device, &backend, &options);
        let title = format!("relief: grazing rays on {device} ({backend})");
        outputs.push((
            "stability.csv",
            csv,
            Box::new(move || stability::chart(&rows, &options, &title, &dir.join("grazing"))),
        ));
    }
    if on(Axis::WorldGrazing) {
        let options = stability::world_grazing::world_options(&world, quick);
        println!(
            "grazing views of the default endless world at {:?} degrees, {}x{} (every {} px compared with the CPU f64 ray cast)",
            options.elevations, options.size.0, options.size.1, options.stride
        );
        restart(options.elevations.len());
        let rows = stability::world_grazing::world_grazing(&gpu, &world, &options, |done, _| {
            bar.set_position(done as u64)
        })?;
        bar.finish_and_clear();
        print!("{}", stability::table(&rows, &options));
        let csv = stability::csv(&rows, &device, &backend, &options);
        let title = format!("relief: grazing rays over the endless world on {device} ({backend})");
        outputs.push((
            "world-grazing.csv",
            csv,
            Box::new(move || stability::chart(&rows, &options, &title, &dir.join("world-grazing"))),
        ));
    }
    if on(Axis::Shadow) {
        let options = if quick {
            stability::shadow::ShadowOptions::quick()
        } else {
            stability::shadow::ShadowOptions::full()
        };
        println!(
            "shadow rays on the default endless world: sun at {:?} degrees (azimuth {}), every {} texel(s) each way of each level drawn, where it draws, compared with f64 rays",
            options.elevations, world.sky.sun_azimuth, options.stride
        );
        restart(options.elevations.len());
        let rows = stability::shadow::shadows(&gpu, &world, &options, |done, _| {
            bar.set_position(done as u64)
        })?;
        bar.finish_and_clear();
        print!("{}", stability::shadow::shadow_table(&rows, &options));
        let csv = stability::shadow::shadow_csv(&rows, &device, &backend, &world);
        let title = format!("relief: shadow rays at a low sun on {device} ({backend})");
        let sun = f64::from(world.sky.sun_elevation);
        outputs.push((
            "shadow.csv",
            csv,
            Box::new(move || {
                stability::shadow::shadow_chart(&rows, &options, sun, (&title, &dir.join("shadow")))
            }),
        ));
    }
    if on(Axis::Distance) {
        let options = if quick {
            stability::distance::DistanceOptions::quick()
        } else {
            stability::distance::DistanceOptions::full()
        };
        println!(
            "distance from the origin on the default endless world: the eye at {:?} m, {}x{}, a {} m step",
            options.distances, options.size.0, options.size.1, options.step
        );
        restart(options.distances.len());
        let rows = stability::distance::distances(&gpu, &world, &options, |done, _| {
            bar.set_position(done as u64)
        })?;
        bar.finish_and_clear();
        print!("{}", stability::distance::distance_table(&rows));
        let csv = stability::distance::distance_csv(&rows, &device, &backend);
        let title = format!("relief: far from the origin on {device} ({backend})");
        outputs.push((
            "distance.csv",
            csv,
            Box::new(move || {
                stability::distance::distance_chart(&rows, (&title, &dir.join("distance")))
            }),
        ));
    }
    if on(Axis::Scroll) {
        let options = if quick {
            stability::scroll::ScrollOptions::quick()
        } else {
            stability::scroll::ScrollOptions::full()
        };
        println!(
            "the tile scrolled from its origin: {:?} tiles, relief's tile at {}² texels (every {} each way against the twin) and the blog's bake",
            options.distances, options.size, options.stride
        );
        restart(options.distances.len());
        let rows = stability::scroll::scroll(&gpu, base, &options, |done, _| {
            bar.set_position(done as u64)
        })?;
        bar.finish_and_clear();
        print!("{}", stability::scroll::scroll_table(&rows));
        let csv = stability::scroll::scroll_csv(&rows, &device, &backend);
        let title = format!("relief and the blog scrolled far, on {device} ({backend})");
        outputs.push((
            "scroll.csv",
            csv,
            Box::new(move || stability::scroll::scroll_chart(&rows, (&title, &dir.join("scroll")))),
        ));
    }
    if on(Axis::Motion) {
        let options = if quick {
            stability::motion::MotionOptions::quick()
        } else {
            stability::motion::MotionOptions::full()
        };
        println!(
            "motion over the default endless world: {:?} m a frame, knobs {} px, {} frames at {}x{}, {} m over the ground, the bake budget {} texels a frame",
            options.speeds,
            std::iter::once(world.pixel_error)
                .chain(options.knobs.iter().copied())
                .map(|k| k.to_string())
                .collect::<Vec<_>>()
                .join(", "),
            options.frames,
            options.size.0,
            options.size.1,
            options.height,
            options.budget
        );
        restart((options.knobs.len() + 1) * options.speeds.len());
        let rows = stability::motion::motion(&gpu, &world, &options, |done, _| {
            bar.set_position(done as u64)
        })?;
        bar.finish_and_clear();
        print!("{}", stability::motion::motion_table(&rows));
        let csv = stability::motion::motion_csv(&rows, &device, &backend);
        let title = format!("relief: a moving eye on {device} ({backend})");
        let knob = world.pixel_error;
        outputs.push((
            "motion.csv",
            csv,
            Box::new(move || {
                stability::motion::motion_chart(&rows, knob, (&title, &dir.join("motion")))
            }),
        ));
    }
    if on(Axis::Detail) {
        // Detail against resolution, on the CPU twin, then FLIP on the GPU.
        let options = if quick {
            stability::detail::DetailOptions::quick()
        } else {
            stability::detail::DetailOptions::full()
        };
        let mut rows = stability::detail::detail(base, &options)?;
        stability::detail::detail_flip(&gpu, base, &mut rows, options.image)?;
        println!(
            "detail against resolution: {:?} octaves at {:?} texels a side, the mesh's grid {:?} (the scene's other values; FLIP at {}x{}):",
            options.octaves, options.sizes, options.grids, options.image.0, options.image.1
        );
        print!("{}", stability::detail::detail_table(&rows, &options));
        let csv = stability::detail::detail_csv(&rows, base);
        let title = format!(
            "relief: detail against resolution (CPU f64 twin; FLIP on {device} ({backend}))"
        );
        let scene = (base.octaves, base.size);
        outputs.push((
            "detail.csv",
            csv,
            Box::new(move || {
                stability::detail::detail_chart(&rows, scene, (&title, &dir.join("detail")))
            }),
        ));
    }
    if on(Axis::Storage) {
        // Storage precision, on the CPU twin (no GPU involved), at the tile's texture side.
        let side = if quick { 256 } else { stability::STORAGE_SIZE };
        let rows = stability::storage(base, side)?;
        println!("storage precision, {side}² texels of the scene's heights:");
        print!("{}", stability::storage_table(&rows));
        let csv = stability::storage_csv(&rows, base, side);
        let title = format!("relief: storage precision, {side}² texels (CPU f64 twin)");
        outputs.push((
            "storage.csv",
            csv,
            Box::new(move || stability::storage_chart(&rows, &title, &dir.join("storage"))),
        ));
    }
    let names: Vec<&str> = outputs.iter().map(|o| o.0).collect();
    let mut outputs = outputs.into_iter();
    let Some((first, csv, charts)) = outputs.next() else {
        return Ok(());
    };
    write_results(dir, (first, &csv), || {
        charts()?;
        for (name, csv, charts) in outputs {
            write_whole(&dir.join(name), &csv)?;
            charts()?;
        }
        Ok(())
    })?;
    println!(
        "wrote {} and their charts (.png, .svg) in {} in {:.0} s",
        names.join(", "),
        dir.display(),
        start.elapsed().as_secs_f64()
    );
    Ok(())
}

fn smoothstep(e0: f32, e1: f32, x: f32) -> f32 {
    let t = ((x - e0) / (e1 - e0)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// The one stderr line `relief render --world endless` prints where the knob asks for less
/// screen error than the levels can give this view: the bound of the layout (`error_bound_px`
/// in `--stats`) is over `--pixel-error`, because the patches are at their largest side
/// ([`crate::clipmap::PATCH_RANGE`]) or the finest level is coarse for the eye's height over
/// the ground. None where the knob is honoured.
fn knob_warning(s: &crate::gpu::world::WorldStats, knob: f64, size: (u32, u32)) -> Option<String> {
    (s.error_bound_px > knob * (1.0 + 1e-9)).then(|| {
        format!(
            "relief: --pixel-error {knob} is finer than the levels can give this view at {}x{} ({}-cell patches, {} m finest spacing): its screen error is bounded by {:.2} px",
            size.0, size.1, s.patch_cells, s.finest_spacing, s.error_bound_px
        )
    })
}

fn check_png_path(out: &Path) -> Result<()> {
    let is_png = out
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("png"));
    if !is_png {
        return Err(Error::invalid(
            "--out",
            crate::error::short_path(out),
            "a path ending in .png",
        ));
    }
    let parent = out
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    if !parent.is_dir() {
        return Err(Error::io(
            parent,
            std::io::Error::new(std::io::ErrorKind::NotFound, "output folder does not exist"),
        ));
    }
    if out.is_dir() {
        return Err(Error::invalid(
            "--out",
            crate::error::short_path(out),
            "a PNG file's path; this is a folder",
        ));
    }
    // The image is written at the end: a folder that takes no files fails now, not after the
    // work.
    probe_writable(parent)
}

fn temp_name(path: &Path) -> PathBuf {
    let mut name = path.file_name().unwrap_or_default().to_os_string();
    name.push(format!(".relief-tmp-{}", std::process::id()));
    path.with_file_name(name)
}

fn encode_png(path: &Path, w: u32, h: u32, color: image::ColorType, bytes: &[u8]) -> Result<()> {
    image::save_buffer_with_format(path, bytes, w, h, color, image::ImageFormat::Png).map_err(|e| {
        match e {
            image::ImageError::IoError(io) => Error::io(path, io),
            other => Error::io(path, std::io::Error::other(other.to_string())),
        }
    })
}

/// Writes a PNG whole or not at all: to a temporary name beside it, then renamed.
pub fn write_png(path: &Path, w: u32, h: u32, color: image::ColorType, bytes: &[u8]) -> Result<()> {
    let tmp = temp_name(path);
    if let Err(e) = encode_png(&tmp, w, h, color, bytes) {
        let _ = std::fs::remove_file(&tmp);
        return Err(match e {
            Error::Io { source, .. } => Error::io(path, source),
            other => other,
        });
    }
    std::fs::rename(&tmp, path).map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        Error::io(path, e)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_table_row_has_a_flag() {
        let cmd = command();
        for p in params() {
            let arg = cmd.get_arguments().find(|a| a.get_id() == p.key);
            assert!(arg.is_some(), "no flag for {}", p.key);
            assert_eq!(arg.unwrap().get_long(), Some(p.flag().as_str()));
        }
        cmd.debug_assert();
    }

    #[test]
    fn color_png_mixes_in_linear_light() {
        let s = Shading::default();
        // The ends are the albedos themselves.
        let a = s.color_a.map(|c| (c * 255.0).round() as u8);
        assert_eq!(albedo_srgb8(&s, 0.0), a);
        // Half-way is the linear mean, encoded: brighter than the mean of the sRGB values.
        let mid = albedo_srgb8(&s, 0.5);
        for (i, &got) in mid.iter().enumerate() {
            let la = srgb_to_linear(s.color_a[i]);
            let lb = srgb_to_linear(s.color_b[i]);
            let want = (linear_to_srgb(0.5 * (la + lb)) * 255.0).round() as u8;
            assert_eq!(got, want);
        }
        let srgb_mean = ((s.color_a[0] + s.color_b[0]) * 0.5 * 255.0).round() as u8;
        assert!(mid[0] > srgb_mean, "{} vs {srgb_mean}", mid[0]);
    }

    #[test]
    fn error_lines_are_short() {
        let long = error_line(&"x".repeat(100_000));
        assert!(long.chars().count() <= MAX_ERROR_CHARS, "{}", long.len());
        let line = error_line(&format!(
            "invalid seed: {} (allowed: 0..=9)",
            "9".repeat(300)
        ));
        assert!(line.starts_with("error: invalid seed") && line.ends_with("(allowed: 0..=9)"));
    }
}
