//! The `relief` command line: `window` (the default), `render`, `bake` and `bench`, all
//! through the same core path. The scene flags are built from the parameter table
//! ([`relief::params::PARAMS`]) and the window's own table ([`relief_app::OPTIONS`]), so every
//! parameter has its flag, its help line and its error text from one place. Every user error
//! ends in exit status 2 and one line on stderr of at most [`MAX_ERROR_CHARS`] characters.

mod bake;
mod bench;
mod bench_endless;
mod command;
mod files;
mod props_scene;
mod render;
mod resolve;
mod shown;
pub mod stability;

pub mod options;
pub mod scene;

pub use self::bake::*;
use self::bench::*;
use self::bench_endless::bench_endless;
pub use self::command::*;
pub use self::files::*;
use self::render::*;
use self::resolve::*;
use self::stability::*;
use crate::scene::{BakeInfo, SceneFile};
use clap::{Arg, ArgAction, ArgMatches, Command};
use relief::choice::Candidate;
use relief::error::{Error, Result};
use relief::gpu::headless::{self, Gpu, Offscreen, MAX_IMAGE, TILE};
use relief::gpu::timing::{GpuTimer, Slot, Timings};
use relief::params::{params, srgb_to_linear, SceneParam, Shading, TerrainParams};
use relief::table::{self, Kind, Param, Value};
use relief::world::{world_param, WorldKind, WorldParams, WORLD_PARAMS};
use relief::{OrbitCamera, Terrain, World, WorldView};
use relief_app::{AppOptions, Script, OPTIONS};
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

/// `--method`'s names: `auto` (the default: [`relief::choice`]), then the one method list.
const METHODS: Kind = Kind::Choice(&METHOD_NAMES);

/// `auto`, then [`relief::Method::NAMES`] in their order (derived, so a new method joins
/// `--method`).
const METHOD_NAMES: [&str; relief::Method::NAMES.len() + 1] = {
    let names = relief::Method::NAMES;
    let mut all = ["auto"; relief::Method::NAMES.len() + 1];
    let mut i = 0;
    while i < names.len() {
        all[i + 1] = names[i];
        i += 1;
    }
    all
};

/// `--samples`: samples a pixel of the visibility method and the hybrid.
const SAMPLES: Kind = Kind::Choice(&["1", "4"]);

/// `--frames`: frames `relief render` accumulates with the temporal service.
const FRAMES: Kind = Kind::Int {
    min: 1,
    max: relief::temporal::MAX_FRAMES,
};

/// `relief bench --world endless --only`'s parts.
const BENCH_PARTS: Kind = Kind::Choice(&[
    "look",
    "landscape",
    "arrival",
    "temporal",
    "reference",
    "grass",
    "props",
    "clouds",
]);

/// `--raster`: where the visibility method rasterises.
const RASTERS: Kind = Kind::Choice(&["hardware", "compute"]);

/// A world point for `relief height`.
const POINT: Kind = Kind::Pair { max: 1e12 };

/// Scene keys that `relief bench` sweeps itself, so it refuses them as flags.
pub const BENCH_SWEEPS: [&str; 3] = ["size", "grid", "normals"];

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
        .filter(|k| relief::params::param(k).is_none())
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
    match run(&matches, Go::Run) {
        Ok(()) => 0,
        Err(e) => {
            eprintln!("{}", error_line(&e.to_string()));
            2
        }
    }
}

/// Resolves `args` (the program's name first) as [`main_with_args`] would, through clap and
/// the refusals the program makes of its arguments, but runs nothing: no window, no GPU, no file
/// read but a `--scene` file, none written. What a command decides later (the output's
/// extension, an eye under the ground, what the GPU allows) is not checked. `Err` holds what the
/// program would print. What checks that every command the docs show is still accepted.
pub fn check_args(
    args: impl IntoIterator<Item = std::ffi::OsString>,
) -> std::result::Result<(), String> {
    let matches = command()
        .try_get_matches_from(args)
        .map_err(|e| e.to_string())?;
    run(&matches, Go::Check).map_err(|e| error_line(&e.to_string()))
}

/// How far [`run`] goes: the whole command, or its arguments alone ([`check_args`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Go {
    Run,
    Check,
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

/// Refuses, in words, a `--method` that `world` does not draw.
fn drawn_in(method: relief::Method, world: WorldKind) -> Result<()> {
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

fn run(top: &ArgMatches, go: Go) -> Result<()> {
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
            frames: frames(m)?,
        },
        "bake" => Run::Bake {
            out_dir: PathBuf::from(string(m, "out-dir").unwrap_or_default()),
        },
        "bench" => Run::Bench {
            out_dir: PathBuf::from(string(m, "out-dir").unwrap_or_default()),
            quick: m.get_flag("quick"),
            only: bench_part(m)?,
            views: m
                .get_many::<String>("view")
                .into_iter()
                .flatten()
                .cloned()
                .collect(),
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
        refuse_flags(
            m,
            name,
            &["stats", "frames"],
            "it applies to relief render only",
        )?;
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
        let why = if method == relief::Method::Blog {
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
        .filter(|k| relief::params::param(k).is_none())
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
                if resolve_props(m, &params)?.is_some() {
                    return Err(Error::Usage(
                        "the scene file's [prop_kinds], [prop_materials] and [[prop_place]]:                          relief render draws them; the window draws the shipped props (props =                          true)"
                            .into(),
                    ));
                }
                let view = world_view(&camera(m)?, &params, (1280, 720));
                let fly = relief::FlyCamera::looking_at(
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
                let temporal = &relief_app::TEMPORAL;
                if given(m, temporal.key) {
                    (temporal.set)(&mut options, flag_value(temporal, &flag_text(m, temporal))?);
                }
                if let Some(d) = window_drawn {
                    draw_window_with(&mut options, d);
                }
                let script = script(m)?;
                if go == Go::Check {
                    return Ok(());
                }
                return relief_app::run_native(options, script);
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
                let params = resolve_world(m)?;
                if go == Go::Check {
                    return Ok(());
                }
                return bake_endless(&params, &region, out_dir, m.get_flag("timings"));
            }
            let params = resolve_world(m)?;
            let props = resolve_props(m, &params)?;
            if go == Go::Check {
                return Ok(());
            }
            return run_endless(run, (params, props), m.get_flag("timings"));
        }
    }
    let params = resolve_scene(m)?;
    let timings = m.get_flag("timings");
    if go == Go::Check {
        if matches!(run, Run::Window) {
            resolve_app(m, params)?;
            script(m)?;
        }
        return Ok(());
    }
    match run {
        Run::Window => {
            let mut options = resolve_app(m, params)?;
            if let Some(d) = window_drawn {
                draw_window_with(&mut options, d);
            }
            relief_app::run_native(options, script(m)?)
        }
        Run::Render {
            out,
            width,
            height,
            method,
            camera,
            stats,
            frames,
        } => render(
            &params,
            &out,
            (width, height),
            method,
            &camera,
            Flags {
                timings,
                stats,
                frames,
            },
        ),
        Run::Bake { out_dir } => bake(&params, &out_dir, timings),
        Run::Bench {
            out_dir,
            quick,
            only,
            views,
        } => {
            if only.is_some() || !views.is_empty() {
                return Err(Error::Usage(
                    "--only and --view pick a part and views of relief bench --world endless \
                     (the tile's benchmark is one sweep)"
                        .into(),
                ));
            }
            bench(&params, &out_dir, quick)
        }
        Run::Stability {
            out_dir,
            quick,
            axes,
        } => {
            let world = WorldParams::default();
            let sweeps = if quick {
                relief_eval::stability::Sweeps::quick(&world)
            } else {
                relief_eval::stability::Sweeps::full(&world)
            };
            stability(&params, &out_dir, (&sweeps, quick), &axes)
        }
        Run::Height { points } => {
            for [x, z] in points {
                println!(
                    "{}",
                    relief::height_at(&params, f64::from(x as f32), f64::from(z as f32)) as f32
                );
            }
            Ok(())
        }
    }
}

/// What `relief render` prints besides the image.
#[derive(Clone, Copy, Debug)]
struct Flags {
    /// `--frames` (the endless world's: the tile draws one).
    frames: u32,
    timings: bool,
    stats: bool,
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
