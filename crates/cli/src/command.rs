//! The clap command: every subcommand's flags, built from the parameter tables.

use super::*;

pub(super) fn flag_help<T>(p: &Param<T>, default: &T) -> String {
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

pub(super) fn value_arg<T>(p: &Param<T>, default: &T) -> Arg {
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
                .arg(quick_arg("about a minute on a software GPU"))
                .arg(
                    Arg::new("only")
                        .long("only")
                        .value_name("PART")
                        .help(format!(
                            "--world endless: run one part: look (the look's cost), landscape \
                             (the LOD sweep), arrival, temporal (the temporal service: still \
                             views converging, moving frames, its cost), reference (the \
                             reference's rays a pixel), grass (the grass's cost and blades on \
                             a meadow's views), props (the props' cost and FLIP against the \
                             reference with props, beside the seed's way) or clouds (their \
                             cost, and their march against more steps) [default: look, \
                             landscape and arrival] \
                             [allowed: {}]",
                            BENCH_PARTS.allowed()
                        )),
                )
                .arg(
                    Arg::new("view")
                        .long("view")
                        .action(ArgAction::Append)
                        .value_delimiter(',')
                        .value_name("NAME")
                        .help(
                            "--only temporal, reference or props: measure only these views \
                             (repeat the flag or separate names with commas): horizon, ridge, \
                             oblique, random-1 to random-16; for props among-2m, meadow, \
                             over-200m, random-1 to random-16",
                        ),
                ),
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
                     origin; and flicker and ghosting with and without the temporal service \
                     under a moving eye; and grass under a moving eye; and the props' march on \
                     their f64 twin; write stability.csv, world-grazing.csv, shadow.csv, \
                     distance.csv, scroll.csv, motion.csv, detail.csv, storage.csv, \
                     temporal.csv, grass.csv, props.csv and their charts",
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
                            relief_eval::stability::Axis::names()
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
        .filter(|p| relief::params::param(p.key).is_none())
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
                        let world = relief::WorldKind::from_name(w).unwrap_or_default();
                        let all = relief::choice::Candidate::all(world);
                        let names: Vec<String> =
                            all.iter().map(|c| c.to_string()).collect();
                        format!("{} in the {w} world", names.join(", "))
                    })
                    .join("; "),
                relief::Method::ALL
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
        Arg::new("frames")
            .long("frames")
            .global(true)
            .value_name("N")
            .help(format!(
                "render --world endless: draw N frames of the still view through the temporal \
                 service, each jittered within its pixels, and write their mean (the \
                 mesh-based methods: mesh, visibility, hybrid; 1: one frame, unjittered) \
                 [default: 1] \
                 [allowed: {}]",
                FRAMES.allowed()
            )),
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

/// A sweep's `--out-dir`, defaulting to `default`.
pub(super) fn out_dir_arg(default: &'static str) -> Arg {
    Arg::new("out-dir")
        .long("out-dir")
        .default_value(default)
        .value_name("DIR")
        .help("output folder (created if missing)")
}

/// A sweep's `--quick`, taking about `how_long`.
pub(super) fn quick_arg(how_long: &str) -> Arg {
    Arg::new("quick")
        .long("quick")
        .action(ArgAction::SetTrue)
        .help(format!("a small sweep at a small image size ({how_long})"))
}
