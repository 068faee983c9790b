//! The `relief` command line: `window` (the default), `render` and `bake`, all through the
//! same core path. Every user error ends in exit status 2 and one line on stderr.

use crate::error::{Error, Result};
use crate::gpu::headless::{self, Gpu, Offscreen};
use crate::gpu::timing::{GpuTimer, Slot, Timings};
use crate::params::{BakeInfo, Shading, TerrainParams};
use crate::{OrbitCamera, Terrain};
use clap::{Args, Parser, Subcommand};
use std::path::{Path, PathBuf};

/// Procedural terrain on the GPU: Perlin fBm baked by compute shaders, drawn as a displaced
/// mesh with Blinn-Phong, snow and height AO.
#[derive(Parser, Debug)]
#[command(name = "relief", version, about)]
pub struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    #[command(flatten)]
    scene: SceneArgs,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Open a window with the scene (the default): drag to orbit, wheel to zoom,
    /// Space pauses the scroll, R re-seeds, Escape quits.
    Window,
    /// Render one frame offscreen to a PNG, through the same code path as the window.
    Render {
        /// Output PNG file.
        #[arg(long)]
        out: PathBuf,
        /// Image width in pixels.
        #[arg(long, default_value_t = 1280)]
        width: u32,
        /// Image height in pixels.
        #[arg(long, default_value_t = 720)]
        height: u32,
    },
    /// Bake the textures and write height.png (16-bit), normal.png, color.png and scene.toml.
    Bake {
        /// Output folder (created if missing).
        #[arg(long)]
        out_dir: PathBuf,
    },
    /// Speed against accuracy: sweep render methods and knobs on the default scene, measure
    /// GPU time and error against the reference ray caster; write bench.csv, bench.png and
    /// bench.svg.
    Bench {
        /// Output folder (created if missing).
        #[arg(long, default_value = "bench-out")]
        out_dir: PathBuf,
        /// A small sweep at a small image size (about a minute on a software GPU).
        #[arg(long)]
        quick: bool,
    },
}

/// Scene options shared by every command; they override `--scene`.
#[derive(Args, Debug, Default)]
struct SceneArgs {
    /// Hash seed (0..=4294967295).
    #[arg(long, global = true, allow_hyphen_values = true)]
    seed: Option<u32>,
    /// Texture side in texels.
    #[arg(long, global = true, allow_hyphen_values = true)]
    size: Option<u32>,
    /// Grid vertices per side.
    #[arg(long, global = true, allow_hyphen_values = true)]
    grid: Option<u32>,
    /// fBm octaves.
    #[arg(long, global = true, allow_hyphen_values = true)]
    octaves: Option<u32>,
    /// Lattice cells across the tile at the first octave.
    #[arg(long, global = true, allow_hyphen_values = true)]
    frequency: Option<u32>,
    /// Amplitude ratio between octaves.
    #[arg(long, global = true, allow_hyphen_values = true)]
    gain: Option<f32>,
    /// World height of normalised height 1 (the tile is 2 units wide).
    #[arg(long, global = true, allow_hyphen_values = true)]
    height_scale: Option<f32>,
    /// Normalised height (0..1) above which snow lies.
    #[arg(long, global = true, allow_hyphen_values = true)]
    snow_height: Option<f32>,
    /// Exponent k of the height ambient occlusion h^k (0 turns it off).
    #[arg(long, global = true, allow_hyphen_values = true)]
    ao_exponent: Option<f32>,
    /// Scroll offset in tiles, as X,Y (1,0 is one whole tile: the same terrain).
    #[arg(long, global = true, allow_hyphen_values = true, value_parser = parse_offset)]
    offset: Option<[f64; 2]>,
    /// Normal map method: differences (central differences of the heights) or analytic.
    #[arg(long, global = true)]
    normals: Option<crate::params::NormalMethod>,
    /// Scene file (TOML) to start from; flags override it.
    #[arg(long, global = true)]
    scene: Option<PathBuf>,
    /// Print GPU pass times (needs timestamp queries on the adapter).
    #[arg(long, global = true)]
    timings: bool,
}

fn parse_offset(s: &str) -> std::result::Result<[f64; 2], String> {
    let parts: Vec<&str> = s.split(',').collect();
    let [x, y] = parts.as_slice() else {
        return Err("expected X,Y".into());
    };
    let num = |t: &str| {
        t.trim()
            .parse::<f64>()
            .map_err(|_| format!("{t:?} is not a number"))
    };
    Ok([num(x)?, num(y)?])
}

/// The allowed range of a CLI argument, for parse errors clap reports before validation.
fn allowed(arg: &str) -> Option<String> {
    use crate::params::*;
    Some(match arg {
        "seed" => "0..=4294967295".into(),
        "size" => format!("1..={MAX_SIZE}"),
        "grid" => format!("2..={MAX_GRID}"),
        "octaves" => format!("1..={MAX_OCTAVES}"),
        "frequency" => format!("1..={MAX_FREQUENCY}"),
        "gain" | "snow_height" => "0..=1".into(),
        "height_scale" => format!("0..={MAX_HEIGHT_SCALE}"),
        "ao_exponent" => format!("0..={MAX_AO_EXPONENT}"),
        "offset" => "X,Y with finite numbers".into(),
        "normals" => "differences or analytic".into(),
        "width" | "height" => "1..=the device's texture limit".into(),
        _ => return None,
    })
}

impl SceneArgs {
    /// The scene file (or defaults) with the flags applied, validated.
    fn resolve(&self) -> Result<TerrainParams> {
        let mut p = match &self.scene {
            Some(path) => TerrainParams::from_scene_file(path)?,
            None => TerrainParams::default(),
        };
        macro_rules! set {
            ($($f:ident),*) => { $( if let Some(v) = self.$f { p.$f = v; } )* };
        }
        set!(
            seed,
            size,
            grid,
            octaves,
            frequency,
            gain,
            height_scale,
            snow_height,
            ao_exponent,
            offset
        );
        p.validate()?;
        Ok(p)
    }
}

/// Runs the CLI on `args` and returns the process exit status.
pub fn main_with_args(args: impl IntoIterator<Item = std::ffi::OsString>) -> i32 {
    let cli = match Cli::try_parse_from(args) {
        Ok(cli) => cli,
        Err(e) => return clap_error(e),
    };
    match run(cli) {
        Ok(()) => 0,
        Err(e) => {
            eprintln!("error: {e}");
            2
        }
    }
}

fn clap_error(e: clap::Error) -> i32 {
    use clap::error::{ContextKind, ContextValue, ErrorKind};
    if matches!(
        e.kind(),
        ErrorKind::DisplayHelp
            | ErrorKind::DisplayVersion
            | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand
    ) {
        let _ = e.print();
        return 0;
    }
    let rendered = e.render().to_string();
    let mut line = rendered
        .lines()
        .next()
        .unwrap_or("error: bad arguments")
        .to_owned();
    if let Some(ContextValue::String(arg)) = e.get(ContextKind::InvalidArg) {
        // "--size <SIZE>" -> "size"
        let name = arg
            .trim_start_matches('-')
            .split([' ', '='])
            .next()
            .unwrap_or("")
            .replace('-', "_");
        if let Some(range) = allowed(&name) {
            line.push_str(&format!(" (allowed: {range})"));
        }
    }
    eprintln!("{line}");
    2
}

fn run(cli: Cli) -> Result<()> {
    let params = cli.scene.resolve()?;
    match cli.command.unwrap_or(Command::Window) {
        Command::Window => crate::app::run_native(crate::app::AppOptions {
            params,
            timings: cli.scene.timings,
            ..Default::default()
        }),
        Command::Render { out, width, height } => {
            render(&params, &out, width, height, cli.scene.timings)
        }
        Command::Bake { out_dir } => bake(&params, &out_dir, cli.scene.timings),
        Command::Bench { out_dir, quick } => bench(&out_dir, quick),
    }
}

/// MSAA samples of `relief render` images.
pub const RENDER_SAMPLES: u32 = 4;

fn render(
    params: &TerrainParams,
    out: &Path,
    width: u32,
    height: u32,
    timings: bool,
) -> Result<()> {
    check_png_path(out)?;
    let gpu = Gpu::new()?;
    let offscreen = Offscreen::new(&gpu.device, width, height, RENDER_SAMPLES)?;
    let mut terrain = Terrain::new(
        &gpu.device,
        &gpu.queue,
        Offscreen::targets(RENDER_SAMPLES),
        *params,
    )?;
    let timer = timer_if(timings, &gpu);
    let view = OrbitCamera::default().view(width as f32 / height as f32);
    let (pixels, t) = offscreen.render(&gpu, &mut terrain, &view, timer.as_ref())?;
    if timings {
        print_timings(&gpu, t);
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

fn bake(params: &TerrainParams, dir: &Path, timings: bool) -> Result<()> {
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    let gpu = Gpu::new()?;
    let mut terrain = Terrain::new(&gpu.device, &gpu.queue, Offscreen::targets(1), *params)?;
    let timer = timer_if(timings, &gpu);
    let t = headless::bake_blocking(&gpu, &mut terrain, timer.as_ref())?;
    if timings {
        print_timings(&gpu, t);
    }
    let baked = headless::read_baked(&gpu.device, &gpu.queue, &terrain)?;
    let size = params.size;

    let (lo, hi) = baked
        .heights
        .iter()
        .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), &h| {
            (lo.min(h), hi.max(h))
        });
    let span = (hi - lo).max(f32::MIN_POSITIVE);
    let height: Vec<u8> = baked
        .heights
        .iter()
        .flat_map(|&h| (((h - lo) / span * 65535.0).round() as u16).to_ne_bytes())
        .collect();
    let normal: Vec<u8> = baked
        .normals
        .iter()
        .flat_map(|n| n.map(|c| ((c * 0.5 + 0.5) * 255.0).round().clamp(0.0, 255.0) as u8))
        .collect();
    let shading = Shading::default();
    let color: Vec<u8> = baked
        .colors
        .iter()
        .flat_map(|&c| {
            let t = smoothstep(0.2, 0.8, c);
            [0, 1, 2].map(|i| {
                let v = shading.color_a[i] + (shading.color_b[i] - shading.color_a[i]) * t;
                (v * 255.0).round() as u8
            })
        })
        .collect();
    let scene = params.to_scene_string(Some(BakeInfo {
        height_min: f64::from(lo),
        height_max: f64::from(hi),
    }));

    // Everything is written under temporary names first and renamed only when all succeeded.
    let files: [(&str, FileWriter); 4] = [
        (
            "height.png",
            Box::new(|p| encode_png(p, size, size, image::ColorType::L16, &height)),
        ),
        (
            "normal.png",
            Box::new(|p| encode_png(p, size, size, image::ColorType::Rgb8, &normal)),
        ),
        (
            "color.png",
            Box::new(|p| encode_png(p, size, size, image::ColorType::Rgb8, &color)),
        ),
        (
            "scene.toml",
            Box::new(|p| std::fs::write(p, scene.as_bytes()).map_err(|e| Error::io(p, e))),
        ),
    ];
    let mut written = Vec::new();
    for (name, write) in &files {
        let tmp = temp_name(&dir.join(name));
        if let Err(e) = write(&tmp) {
            let _ = std::fs::remove_file(&tmp);
            for (t, _) in &written {
                let _ = std::fs::remove_file(t);
            }
            return Err(e);
        }
        written.push((tmp, dir.join(name)));
    }
    for (tmp, fin) in &written {
        std::fs::rename(tmp, fin).map_err(|e| Error::io(fin, e))?;
    }
    println!(
        "baked {size}x{size} into {}: heights {lo:.6}..{hi:.6} map to 0..65535",
        dir.display()
    );
    Ok(())
}

/// Writes one output file to the path it is given.
type FileWriter<'a> = Box<dyn Fn(&Path) -> Result<()> + 'a>;

struct Bar(indicatif::ProgressBar);

impl crate::bench::Progress for Bar {
    fn start(&mut self, index: usize, _total: usize, config: &crate::bench::Config) {
        self.0.set_position(index as u64);
        let c = config;
        self.0.set_message(match c.method {
            crate::bench::Method::Mesh => format!(
                "mesh {} / {} / {}",
                c.params.size, c.params.grid, c.params.normals
            ),
            m => format!(
                "{} step {} octaves {}",
                m.name(),
                c.march.step_factor,
                c.march.march_octaves
            ),
        });
    }
}

fn bench(dir: &Path, quick: bool) -> Result<()> {
    use crate::bench;
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    let gpu = Gpu::new()?;
    let info = gpu.adapter.get_info();
    let options = if quick {
        bench::Options::QUICK
    } else {
        bench::Options::FULL
    };
    let configs = bench::sweep(quick);
    if GpuTimer::new(&gpu.device, &gpu.queue).is_none() {
        println!(
            "note: {} has no timestamp queries: GPU times are empty, only wall times are measured",
            gpu.describe()
        );
    }
    println!(
        "relief bench{} on {}: {} configurations at {}x{}, reference at {}x supersampling",
        if quick { " --quick" } else { "" },
        gpu.describe(),
        configs.len(),
        options.width,
        options.height,
        options.supersample
    );
    let bar = indicatif::ProgressBar::new(configs.len() as u64).with_style(
        indicatif::ProgressStyle::with_template("{bar:30} {pos}/{len} {elapsed} {msg}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    let mut progress = Bar(bar);
    let start = std::time::Instant::now();
    let rows = bench::run(&gpu, &configs, &options, &mut progress)?;
    progress.0.finish_and_clear();
    print!("{}", bench::table(&rows));
    let csv = bench::csv(&rows, &info.name, &format!("{:?}", info.backend), &options);
    let csv_path = dir.join("bench.csv");
    let tmp = temp_name(&csv_path);
    std::fs::write(&tmp, csv).map_err(|e| Error::io(&tmp, e))?;
    std::fs::rename(&tmp, &csv_path).map_err(|e| Error::io(&csv_path, e))?;
    let title = format!(
        "relief: error against GPU time on {} ({:?})",
        info.name, info.backend
    );
    bench::chart(&rows, &title, &dir.join("bench"))?;
    println!(
        "wrote {}, bench.png and bench.svg in {:.0} s",
        csv_path.display(),
        start.elapsed().as_secs_f64()
    );
    Ok(())
}

fn smoothstep(e0: f32, e1: f32, x: f32) -> f32 {
    let t = ((x - e0) / (e1 - e0)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

fn check_png_path(out: &Path) -> Result<()> {
    let is_png = out
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("png"));
    if !is_png {
        return Err(Error::invalid(
            "out",
            out.display(),
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
    Ok(())
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
