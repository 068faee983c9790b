//! The `relief` program as a user meets it: good runs produce files, bad input gets exit
//! status 2 and one clear line, never a panic or a half-written file.

use std::path::{Path, PathBuf};
use std::process::Command;

/// Runs relief as a user on a bare machine would: no XDG_RUNTIME_DIR (Mesa complains without
/// one; relief must keep stderr clean anyway) and no display.
fn relief(args: &[&str]) -> (i32, String, String) {
    relief_env(args, &[])
}

fn relief_env(args: &[&str], env: &[(&str, &str)]) -> (i32, String, String) {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_relief"));
    cmd.args(args)
        .env_remove("XDG_RUNTIME_DIR")
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .env_remove("RUST_LOG");
    for (k, v) in env {
        cmd.env(k, v);
    }
    let out = cmd.output().expect("run relief");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("relief-cli-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn files_in(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .map(|r| {
            r.map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
                .collect()
        })
        .unwrap_or_default();
    v.sort();
    v
}

/// Runs a bad command and checks: status 2, exactly one line of at most 200 characters that
/// says what is allowed at most once, mentioning every `needles`.
fn rejects(args: &[&str], needles: &[&str]) {
    let (code, _, err) = relief(args);
    let shown: Vec<String> = args.iter().map(|a| a.chars().take(60).collect()).collect();
    let args = &shown;
    assert_eq!(code, 2, "{args:?} should exit 2; stderr: {err}");
    assert_eq!(
        err.lines().count(),
        1,
        "{args:?} should print one line, got:\n{err}"
    );
    assert!(
        err.chars().count() <= 201,
        "{args:?}: {} characters: {}",
        err.chars().count(),
        &err[..300.min(err.len())]
    );
    assert!(err.matches("allowed").count() <= 1, "{args:?}: {err}");
    assert!(!err.contains("panicked"), "{args:?} panicked: {err}");
    for n in needles {
        assert!(err.contains(n), "{args:?}: {err:?} should mention {n:?}");
    }
}

#[test]
fn bad_parameters_exit_2_with_one_line() {
    let dir = scratch("bad");
    let out = dir.join("x.png");
    let out = out.to_str().unwrap();
    let long = "9".repeat(100_000);
    let cases: &[(&[&str], &[&str])] = &[
        (&["--size", "0"], &["--size", "0", "1..=16384"]),
        (&["--size", "99999"], &["--size", "99999", "1..=16384"]),
        (&["--size", "-4"], &["--size", "-4"]),
        (&["--size", "-1"], &["--size", "-1", "1..=16384"]),
        (&["--size", "big"], &["--size", "big"]),
        (&["--grid", "1"], &["--grid", "1", "2..=4096"]),
        (&["--octaves", "0"], &["--octaves", "0", "1..=16"]),
        (&["--octaves", "1000"], &["--octaves", "1000", "1..=16"]),
        (
            &["--octaves", "16", "--frequency", "8"],
            &["octaves", "16", "at most 14"],
        ),
        (&["--frequency", "0"], &["--frequency", "0", "1..=1024"]),
        (&["--gain", "nan"], &["--gain", "nan", "0..=1"]),
        (&["--gain", "inf"], &["--gain", "inf", "0..=1"]),
        (&["--gain", "-0.5"], &["--gain", "-0.5", "0..=1"]),
        (
            &["--height-scale", "-1"],
            &["--height-scale", "-1", "0..=10"],
        ),
        (
            &["--snow-height", "1.5"],
            &["--snow-height", "1.5", "0..=1"],
        ),
        (&["--ao-exponent", "NaN"], &["--ao-exponent", "NaN"]),
        (&["--offset", "nan,0"], &["--offset", "nan"]),
        (&["--offset", "1"], &["--offset", "X,Y"]),
        (&["--offset", "1e300,0"], &["--offset", "1e300"]),
        (&["--seed", "-1"], &["--seed", "-1"]),
        (&["--seed", &long], &["--seed", "100000 chars"]),
        (
            &["--normals", "exact"],
            &["--normals", "exact", "differences or analytic"],
        ),
        (&["--speed", "0.5"], &["--speed", "window"]),
        (&["--paused"], &["--paused", "window"]),
        (&["--exit-after", "3"], &["--exit-after", "window"]),
    ];
    for (args, needles) in cases {
        let mut full = vec!["render", "--out", out];
        full.extend_from_slice(args);
        rejects(&full, needles);
        let mut bake = vec!["bake", "--out-dir", dir.to_str().unwrap()];
        bake.extend_from_slice(args);
        rejects(&bake, needles);
    }
    assert!(
        files_in(&dir).is_empty(),
        "bad input left files: {:?}",
        files_in(&dir)
    );
}

#[test]
fn bad_scene_files_and_outputs_exit_2() {
    let dir = scratch("scene");
    let unknown = dir.join("unknown.toml");
    std::fs::write(&unknown, "seed = 3\ncolour = 4\n").unwrap();
    let wrong = dir.join("wrong.toml");
    std::fs::write(&wrong, "octaves = \"many\"\n").unwrap();
    let range = dir.join("range.toml");
    std::fs::write(&range, "gain = 7.5\n").unwrap();
    let broken = dir.join("broken.toml");
    std::fs::write(&broken, "seed = = 3\n").unwrap();
    let out = dir.join("o.png");
    let o = out.to_str().unwrap();
    let scene = |p: &Path| p.to_str().unwrap().to_owned();
    rejects(
        &["render", "--out", o, "--scene", &scene(&unknown)],
        &["unknown.toml", "colour"],
    );
    rejects(
        &["render", "--out", o, "--scene", &scene(&wrong)],
        &["wrong.toml", "octaves"],
    );
    rejects(
        &["render", "--out", o, "--scene", &scene(&range)],
        &["range.toml", "gain", "7.5", "0..=1"],
    );
    rejects(
        &["render", "--out", o, "--scene", &scene(&broken)],
        &["broken.toml"],
    );
    rejects(
        &["render", "--out", o, "--scene", "/nonexistent/scene.toml"],
        &["/nonexistent/scene.toml"],
    );
    rejects(
        &["render", "--out", "/nonexistent/dir/o.png"],
        &["/nonexistent/dir"],
    );
    rejects(
        &["render", "--out", &format!("{}/o.jpg", dir.display())],
        &["out", ".png"],
    );
    rejects(
        &["render", "--out", o, "--width", "0"],
        &["--width", "0", "1..=16384"],
    );
    rejects(
        &["render", "--out", o, "--width", "-5"],
        &["--width", "-5", "1..=16384"],
    );
    rejects(
        &["render", "--out", o, "--width", "99999999999"],
        &["--width", "99999999999", "1..=16384"],
    );
    rejects(
        &["render", "--out", o, "--height", "1.5"],
        &["--height", "1.5"],
    );
    rejects(&["render", "--bogus"], &["--bogus"]);
    rejects(&["render"], &["--out"]);
    rejects(&["bake"], &["--out-dir"]);
    rejects(&["frobnicate"], &["frobnicate", "render"]);
    rejects(&["bench", "--size", "64"], &["--size", "bench"]);
    rejects(&["bench", "--normals", "analytic"], &["--normals", "bench"]);
    rejects(&["bench", "--timings"], &["--timings", "bench"]);
    // An existing file given as the output folder.
    let file = dir.join("a-file");
    std::fs::write(&file, "x").unwrap();
    rejects(
        &["bake", "--out-dir", file.to_str().unwrap()],
        &["--out-dir", "a-file", "folder"],
    );
    // A refused bake creates no folder (one was once left behind, empty).
    let fresh = dir.join("fresh");
    rejects(
        &[
            "bake",
            "--out-dir",
            fresh.join("sub").to_str().unwrap(),
            "--size",
            "0",
        ],
        &["--size"],
    );
    assert!(!fresh.exists(), "a refused bake created its output folder");
    // Scene files with a megabyte key or value, or a huge file.
    let big = "x".repeat(1_000_000);
    for (name, text) in [
        ("bigkey.toml", format!("{big} = 1\n")),
        ("bigvalue.toml", format!("normals = \"{big}\"\n")),
        (
            "bignumber.toml",
            format!("seed = {}\n", "9".repeat(1_000_000)),
        ),
    ] {
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        rejects(
            &[
                "render",
                "--method",
                "mesh",
                "--out",
                o,
                "--scene",
                path.to_str().unwrap(),
            ],
            &[name],
        );
    }
    std::fs::remove_file(&file).unwrap();
    // A folder that cannot be created: its parent is a file.
    let file = dir.join("a-file");
    std::fs::write(&file, "x").unwrap();
    rejects(
        &["bake", "--out-dir", &format!("{}/sub", file.display())],
        &["a-file"],
    );
    // Bad values in the scene file are overridden by flags: flags win.
    let (code, _, err) = relief(&[
        "render",
        "--method",
        "mesh",
        "--out",
        o,
        "--scene",
        &scene(&range),
        "--gain",
        "0.5",
        "--size",
        "32",
        "--grid",
        "8",
        "--width",
        "32",
        "--height",
        "24",
    ]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(
        files_in(&dir),
        [
            "a-file",
            "bigkey.toml",
            "bignumber.toml",
            "bigvalue.toml",
            "broken.toml",
            "o.png",
            "range.toml",
            "unknown.toml",
            "wrong.toml"
        ]
    );
}

#[test]
fn unwritable_output_leaves_nothing() {
    let dir = scratch("ro");
    // A directory where the PNG should go: the rename onto it fails after rendering.
    let target = dir.join("taken.png");
    std::fs::create_dir(&target).unwrap();
    std::fs::write(target.join("keep"), "x").unwrap();
    let (code, _, err) = relief(&[
        "render",
        "--method",
        "mesh",
        "--out",
        target.to_str().unwrap(),
        "--size",
        "32",
        "--grid",
        "8",
        "--width",
        "32",
        "--height",
        "24",
    ]);
    assert_eq!(code, 2, "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("taken.png"), "{err}");
    assert_eq!(
        files_in(&dir),
        ["taken.png"],
        "a temporary file was left behind"
    );
}

#[test]
fn bake_writes_recoverable_heights_and_a_reproducible_scene() {
    let dir = scratch("bake");
    let a = dir.join("a");
    let (code, stdout, err) = relief(&[
        "bake",
        "--out-dir",
        a.to_str().unwrap(),
        "--size",
        "64",
        "--seed",
        "11",
        "--offset",
        "0.25,-7.5",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(stdout.contains("baked 64x64"), "{stdout}");
    assert_eq!(
        files_in(&a),
        ["color.png", "height.png", "normal.png", "scene.toml"]
    );

    let height = image::open(a.join("height.png")).unwrap();
    assert_eq!(
        height.color(),
        image::ColorType::L16,
        "height.png must be 16-bit greyscale"
    );
    let h = height.into_luma16();
    let (lo, hi) = h.pixels().fold((u16::MAX, 0), |(lo, hi), p| {
        (lo.min(p.0[0]), hi.max(p.0[0]))
    });
    assert_eq!(
        (lo, hi),
        (0, 65535),
        "heights must span the full 16-bit range"
    );
    let normal = image::open(a.join("normal.png")).unwrap();
    assert_eq!(normal.color(), image::ColorType::Rgb8);
    // Normals point up: y (green) above 0.5 everywhere.
    assert!(normal.into_rgb8().pixels().all(|p| p.0[1] > 128));

    // The scene file gives back the heights: v / 65535 * (max - min) + min = twin height.
    let scene_path = a.join("scene.toml");
    let text = std::fs::read_to_string(&scene_path).unwrap();
    let table: toml::Table = text.parse().unwrap();
    let bake = table["bake"].as_table().unwrap();
    let (min, max) = (
        bake["height_min"].as_float().unwrap(),
        bake["height_max"].as_float().unwrap(),
    );
    let params = relief::TerrainParams::from_scene_file(&scene_path).unwrap();
    assert_eq!(params.seed, 11);
    assert_eq!(params.offset, [0.25, -7.5]);
    let fbm = relief::noise::Fbm::from_params(&params);
    for (x, y, p) in h.enumerate_pixels() {
        let recovered = f64::from(p.0[0]) / 65535.0 * (max - min) + min;
        let twin = fbm.texel(relief::noise::Channel::Height, 64, x, y);
        // Quantisation to 16 bits: half a step of the range, plus the GPU's 1e-5.
        let tol = 0.5 / 65535.0 * (max - min) + 1e-5;
        assert!(
            (recovered - twin).abs() <= tol,
            "({x},{y}): {recovered} vs {twin}"
        );
    }

    // color.png is the albedo the renderer mixes: the two colours blended in linear light.
    let color = image::open(a.join("color.png")).unwrap().into_rgb8();
    let shading = relief::Shading::default();
    for (x, y, p) in color.enumerate_pixels() {
        let c = fbm.texel(relief::noise::Channel::Color, 64, x, y) as f32;
        let want = relief::cli::albedo_srgb8(&shading, c);
        for i in 0..3 {
            assert!(
                p.0[i].abs_diff(want[i]) <= 1,
                "({x},{y}) {:?} vs {want:?}",
                p.0
            );
        }
    }

    // Re-baking from the scene file reproduces the same bytes.
    let b = dir.join("b");
    let (code, _, err) = relief(&[
        "bake",
        "--out-dir",
        b.to_str().unwrap(),
        "--scene",
        scene_path.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    for f in ["height.png", "normal.png", "color.png", "scene.toml"] {
        assert_eq!(
            std::fs::read(a.join(f)).unwrap(),
            std::fs::read(b.join(f)).unwrap(),
            "{f} differs"
        );
    }
}

#[test]
fn render_writes_a_png_and_reports_timings() {
    let dir = scratch("render");
    let out = dir.join("frame.png");
    let (code, stdout, err) = relief(&[
        "render",
        "--method",
        "mesh",
        "--out",
        out.to_str().unwrap(),
        "--width",
        "96",
        "--height",
        "64",
        "--size",
        "64",
        "--grid",
        "16",
        "--timings",
    ]);
    assert_eq!(code, 0, "{err}");
    let img = image::open(&out).unwrap();
    assert_eq!((img.width(), img.height()), (96, 64));
    // The method pinned, then the timings.
    assert!(
        stdout.starts_with("method mesh (pinned: --method mesh)\ntimings"),
        "--timings printed nothing: {stdout:?}"
    );
    assert!(
        stdout.contains("render") || stdout.contains("no timestamp queries"),
        "{stdout}"
    );
    assert_eq!(files_in(&dir), ["frame.png"]);
}

/// `relief render`'s default, `--method auto`: it draws a few frames of each candidate of its
/// world on this GPU and keeps the fastest; `--timings` says which and why, and the image is
/// the one the chosen method draws when given by its flags.
#[test]
fn render_chooses_its_method_by_measurement_and_says_which() {
    use relief::choice::Candidate;
    let dir = scratch("render-auto");
    let out = |name: &str| dir.join(name).to_str().unwrap().to_owned();
    for (world, extra) in [
        (
            relief::WorldKind::Tile,
            &["--size", "64", "--grid", "16"][..],
        ),
        (relief::WorldKind::Endless, &["--world", "endless"][..]),
    ] {
        let size = ["--width", "96", "--height", "64"];
        let auto = out("auto.png");
        let args = [
            &["render", "--out", &auto, "--timings", "--stats"][..],
            &size,
            extra,
        ]
        .concat();
        let (code, stdout, err) = relief(&args);
        assert_eq!(code, 0, "{err}");
        let line = stdout.lines().next().unwrap_or_default();
        assert!(line.starts_with("method "), "{world:?}: {stdout}");
        if line.contains("no GPU timestamps") {
            assert!(line.contains("--method mesh"), "{line}");
        } else {
            // Each candidate is named with its median draw.
            for c in Candidate::all(world) {
                assert!(
                    line.contains(&format!("{c} ")),
                    "{world:?}: {c} missing: {line}"
                );
            }
            assert!(line.contains(" ms"), "{line}");
        }
        // The flags of the chosen method, between the first parentheses.
        let flags: Vec<&str> = line
            .split_once('(')
            .and_then(|(_, rest)| rest.split_once(')'))
            .map(|(f, _)| f.split_whitespace().collect())
            .unwrap_or_default();
        assert_eq!(flags.first(), Some(&"--method"), "{line}");
        let pinned = out("pinned.png");
        let args = [
            &["render", "--out", &pinned, "--stats"][..],
            &flags,
            &size,
            extra,
        ]
        .concat();
        let (code, pinned_stdout, err) = relief(&args);
        assert_eq!(code, 0, "{flags:?}: {err}");
        // The same stats: the trial leaves the world to bake and draw as the pinned method.
        let stats = |out: &str| -> Vec<String> {
            out.lines()
                .filter(|l| !l.starts_with("method ") && !l.starts_with("timings"))
                .map(str::to_owned)
                .collect()
        };
        assert_eq!(stats(&stdout), stats(&pinned_stdout), "{world:?}");
        let (a, b) = (image::open(&auto).unwrap(), image::open(&pinned).unwrap());
        assert_eq!(
            a.to_rgba8().as_raw(),
            b.to_rgba8().as_raw(),
            "{world:?}: auto's image is not {flags:?}'s"
        );
    }
}

/// `--samples` sets the samples a pixel of the visibility method and the hybrid (one sample
/// leaves edges aliased), and is refused where it means nothing.
#[test]
fn render_samples_sets_the_visibility_methods_samples() {
    let dir = scratch("render-samples");
    let out = dir.join("s.png");
    let o = out.to_str().unwrap();
    for (method, world) in [("visibility", "tile"), ("hybrid", "endless")] {
        let image = |samples: &str| {
            let (code, _, err) = relief(&[
                "render",
                "--out",
                o,
                "--world",
                world,
                "--width",
                "96",
                "--height",
                "64",
                "--method",
                method,
                "--samples",
                samples,
            ]);
            assert_eq!(code, 0, "{method} --samples {samples}: {err}");
            image::open(&out).unwrap().to_rgba8().into_raw()
        };
        let (one, four) = (image("1"), image("4"));
        let changed = one.iter().zip(&four).filter(|(a, b)| a != b).count();
        assert!(
            changed > 0,
            "{method}: --samples 1 and 4 drew the same image"
        );
        // The default is 4.
        let (code, _, err) = relief(&[
            "render", "--out", o, "--world", world, "--width", "96", "--height", "64", "--method",
            method,
        ]);
        assert_eq!(code, 0, "{err}");
        assert_eq!(
            image::open(&out).unwrap().to_rgba8().into_raw(),
            four,
            "{method}"
        );
    }
    rejects(
        &[
            "render",
            "--out",
            o,
            "--method",
            "visibility",
            "--samples",
            "2",
        ],
        &["--samples", "2", "1 or 4"],
    );
    for method in ["mesh", "auto", "raymarch"] {
        rejects(
            &["render", "--out", o, "--method", method, "--samples", "1"],
            &["--samples", "visibility and hybrid", method],
        );
    }
    rejects(
        &["bake", "--out-dir", dir.to_str().unwrap(), "--samples", "1"],
        &["--samples"],
    );
}

/// `--raster compute` rasterises the visibility method's mesh in a compute pass: the same
/// image within edge pixels, and `--timings` names it; what it cannot draw is refused in words.
#[test]
fn render_raster_moves_the_visibility_methods_raster_to_compute() {
    let dir = scratch("render-raster");
    let out = dir.join("frame.png");
    let o = out.to_str().unwrap();
    let run = |raster: Option<&str>| {
        let mut args = vec![
            "render",
            "--out",
            o,
            "--width",
            "96",
            "--height",
            "64",
            "--method",
            "visibility",
            "--samples",
            "1",
            "--timings",
        ];
        if let Some(r) = raster {
            args.extend(["--raster", r]);
        }
        let (code, stdout, err) = relief(&args);
        assert_eq!(code, 0, "--raster {raster:?}: {err}");
        (stdout, image::open(&out).unwrap().to_rgba8().into_raw())
    };
    let (default, hardware) = run(None);
    let (said, compute) = run(Some("compute"));
    assert!(
        default.contains(
            "method visibility at 1 sample a pixel (pinned: --method visibility --samples 1)"
        ),
        "{default}"
    );
    assert!(
        said.contains(
            "rasterised in compute (pinned: --method visibility --samples 1 --raster compute)"
        ),
        "{said}"
    );
    assert!(!default.contains("compute"), "{default}");
    let (explicit, image) = run(Some("hardware"));
    assert_eq!(image, hardware, "--raster hardware is the default");
    assert!(!explicit.contains("compute"), "{explicit}");
    // The same terrain: a pixel centre within rounding of an edge may fall the other way.
    let off = hardware
        .chunks(4)
        .zip(compute.chunks(4))
        .filter(|(a, b)| a.iter().zip(b.iter()).any(|(x, y)| x.abs_diff(*y) > 8))
        .count();
    assert!(off * 200 < 96 * 64, "{off} pixels differ");
    rejects(
        &[
            "render",
            "--out",
            o,
            "--method",
            "visibility",
            "--samples",
            "1",
            "--raster",
            "soft",
        ],
        &["--raster", "soft", "hardware or compute"],
    );
    rejects(
        &[
            "render",
            "--out",
            o,
            "--method",
            "visibility",
            "--raster",
            "compute",
        ],
        &["raster", "one sample a pixel", "--samples 1"],
    );
    // The endless world's hybrid too, its attributes stored by a second dispatch.
    let (code, stdout, err) = relief(&[
        "render",
        "--out",
        o,
        "--world",
        "endless",
        "--width",
        "48",
        "--height",
        "32",
        "--method",
        "hybrid",
        "--samples",
        "1",
        "--raster",
        "compute",
        "--timings",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(
        stdout.contains("method hybrid at 1 sample a pixel rasterised in compute"),
        "{stdout}"
    );
    for method in ["mesh", "auto", "raymarch"] {
        rejects(
            &[
                "render", "--out", o, "--method", method, "--raster", "compute",
            ],
            &["--raster", "visibility and hybrid only", method],
        );
    }
}

#[test]
fn render_visibility_times_its_passes_and_counts_its_images() {
    let dir = scratch("render-visibility");
    let out = dir.join("frame.png");
    let run = |method: &str, world: &[&str]| {
        let mut args = vec![
            "render",
            "--out",
            out.to_str().unwrap(),
            "--width",
            "96",
            "--height",
            "64",
            "--method",
            method,
            "--timings",
            "--stats",
        ];
        args.extend_from_slice(world);
        let (code, stdout, err) = relief(&args);
        assert_eq!(code, 0, "{err}");
        stdout
    };
    for world in [&[][..], &["--world", "endless", "--pixel-error", "8"][..]] {
        let vis = run("visibility", world);
        let mesh = run("mesh", world);
        // Its raster pass and its compute shading are timed beside the host's pass.
        if !vis.contains("no timestamp queries") {
            assert!(vis.contains("raster ") && vis.contains("shade "), "{vis}");
            assert!(
                !mesh.contains("raster ") && !mesh.contains("shade "),
                "{mesh}"
            );
        }
        // Its own images: 96x64 pixels of 4 depth samples and the shaded image and depth (the
        // endless world adds 4 samples of its attributes).
        let own = stat(&stats_of(&vis), "method_texture_mib");
        assert!(own > 0.1 && own < 1.0, "{vis}");
        assert_eq!(stat(&stats_of(&mesh), "method_texture_mib"), 0.0, "{mesh}");
    }
    // The hybrid (the endless world's): the same passes and images, its shading refining rays.
    let hybrid = run("hybrid", &["--world", "endless", "--pixel-error", "8"]);
    if !hybrid.contains("no timestamp queries") {
        assert!(
            hybrid.contains("raster ") && hybrid.contains("shade "),
            "{hybrid}"
        );
    }
    let own = stat(&stats_of(&hybrid), "method_texture_mib");
    assert!(own > 0.1 && own < 1.0, "{hybrid}");
}

#[test]
fn bench_quick_writes_a_csv_and_a_chart() {
    let dir = scratch("bench");
    // Scene flags set the benchmark's scene (they were once silently ignored).
    let (code, stdout, err) = relief(&[
        "bench",
        "--quick",
        "--octaves",
        "3",
        "--seed",
        "99",
        "--out-dir",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(err, "", "a successful run keeps stderr clean");
    assert!(stdout.contains("seed 99, octaves 3"), "{stdout}");
    assert!(
        stdout.contains("<- default"),
        "the table marks the default: {stdout}"
    );
    let csv = std::fs::read_to_string(dir.join("bench.csv")).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    let header: Vec<&str> = lines[0].split(',').collect();
    for column in [
        "device",
        "backend",
        "method",
        "size",
        "grid",
        "normals",
        "step_factor",
        "render_ms",
        "wall_ms",
        "flip_mean",
        "missed",
        "mesh_rms",
    ] {
        assert!(header.contains(&column), "CSV lacks {column}");
    }
    assert_eq!(lines.len(), 1 + 10, "ten configurations in the quick sweep");
    let rows: Vec<Vec<String>> = lines[1..].iter().map(|l| csv_fields(l)).collect();
    for row in &rows {
        assert_eq!(row.len(), header.len(), "{row:?}");
    }
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    // One default, chosen among the mesh-based candidates as `relief render --method auto`
    // chooses, from the rows' own draw times.
    let defaults: Vec<&str> = rows
        .iter()
        .filter(|r| r[col("default")] == "true")
        .map(|r| r[col("method")].as_str())
        .collect();
    assert!(
        defaults == ["mesh"] || defaults == ["visibility"],
        "{defaults:?}"
    );
    let methods: Vec<&str> = rows.iter().map(|r| r[col("method")].as_str()).collect();
    for m in [
        "mesh",
        "visibility",
        "raymarch-fragment",
        "raymarch",
        "blog",
    ] {
        assert!(methods.contains(&m), "no {m} row");
    }
    // The visibility method at one sample rasterised in compute, beside it at four in hardware.
    let rasters: Vec<(&str, &str)> = rows
        .iter()
        .filter(|r| r[col("method")] == "visibility")
        .map(|r| (r[col("samples")].as_str(), r[col("raster")].as_str()))
        .collect();
    assert_eq!(rasters, [("4", "hardware"), ("1", "compute")]);
    for row in &rows {
        let flip: f64 = row[col("flip_mean")].parse().unwrap();
        assert!(flip > 0.0 && flip < 0.5, "FLIP mean {flip} in {row:?}");
        if row[col("method")] == "blog" {
            // The blog's own terrain, texture and grid, baked and drawn every frame.
            assert_eq!(row[col("octaves")], "5", "{row:?}");
            assert_eq!(row[col("seed")], "", "{row:?}");
            assert_eq!(row[col("size")], "1024", "{row:?}");
            assert_eq!(row[col("grid")], "1024", "{row:?}");
            let ms = |c: &str| row[col(c)].parse::<f64>().unwrap();
            let parts = ms("bake_ms") + ms("normals_ms") + ms("render_ms");
            assert!((ms("frame_gpu_ms") - parts).abs() < 1e-3, "{row:?}");
            continue;
        }
        assert_eq!(row[col("octaves")], "3", "{row:?}");
        assert_eq!(row[col("seed")], "99", "{row:?}");
        let flip: f64 = row[col("flip_mean")].parse().unwrap();
        assert!(flip > 0.0 && flip < 0.5, "FLIP mean {flip} in {row:?}");
    }
    let png = image::open(dir.join("bench.png")).unwrap();
    assert_eq!((png.width(), png.height()), (960, 640));
    let svg = std::fs::read_to_string(dir.join("bench.svg")).unwrap();
    assert!(svg.contains("<svg") && svg.contains("Pareto front") && svg.contains("default"));
    // The default's label is drawn right beside its marker (it once floated far from it): on
    // whichever side it is, its nearer end lies within a few marker widths. The SVG gives the
    // text's start; its end is estimated at up to 8 px a character of 15 px sans-serif (a long
    // label left of a marker near the right edge starts some 350 px away and ends beside it).
    let (label, text) = svg_text(&svg, "default (").expect("a default label");
    let marker = svg_circle_position(&svg, 11.0).expect("the default's ring");
    let width = text.chars().count() as f64 * 8.0;
    let gap_x = if label.0 > marker.0 {
        label.0 - marker.0
    } else {
        (marker.0 - (label.0 + width)).max(0.0)
    };
    let d = (gap_x.powi(2) + (label.1 - marker.1).powi(2)).sqrt();
    assert!(
        d < 80.0,
        "label {text:?} at {label:?} (about {width} px wide), marker at {marker:?}"
    );
    // ... and inside the picture.
    assert!((0.0..960.0).contains(&label.0), "{label:?}");
}

fn svg_attr(tag: &str, name: &str) -> Option<f64> {
    let start = tag.find(&format!(" {name}=\""))? + name.len() + 3;
    tag[start..].split('"').next()?.parse().ok()
}

/// Where the SVG's text starting with `prefix` is anchored, and the text.
fn svg_text(svg: &str, prefix: &str) -> Option<((f64, f64), String)> {
    svg.split("<text").skip(1).find_map(|t| {
        let body = t.split('>').nth(1)?.trim_start();
        let body = body.split('<').next()?.trim_end();
        body.starts_with(prefix)
            .then(|| Some(((svg_attr(t, "x")?, svg_attr(t, "y")?), body.to_string())))?
    })
}

/// The centre of the first SVG circle of radius `r`.
fn svg_circle_position(svg: &str, r: f64) -> Option<(f64, f64)> {
    svg.split("<circle").skip(1).find_map(|t| {
        (svg_attr(t, "r")? == r).then(|| Some((svg_attr(t, "cx")?, svg_attr(t, "cy")?)))?
    })
}

/// Splits one CSV line, honouring double quotes (device names contain commas).
fn csv_fields(line: &str) -> Vec<String> {
    let (mut out, mut cur, mut quoted) = (Vec::new(), String::new(), false);
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '"' if quoted && chars.peek() == Some(&'"') => {
                cur.push('"');
                chars.next();
            }
            '"' => quoted = !quoted,
            ',' if !quoted => out.push(std::mem::take(&mut cur)),
            c => cur.push(c),
        }
    }
    out.push(cur);
    out
}

#[test]
fn stderr_stays_clean_and_a_missing_display_is_explained() {
    let dir = scratch("clean");
    let out = dir.join("f.png");
    let (code, _, err) = relief(&[
        "render",
        "--method",
        "mesh",
        "--out",
        out.to_str().unwrap(),
        "--size",
        "32",
        "--grid",
        "8",
        "--width",
        "32",
        "--height",
        "24",
    ]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(
        err, "",
        "success must print nothing on stderr (no Mesa 'error:' lines)"
    );
    // No window without a display: one line, pointing at `relief render`, no source paths.
    for args in [&[][..], &["window"][..]] {
        let (code, _, err) = relief(args);
        assert_eq!(code, 2, "{err}");
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(
            err.contains("display") && err.contains("relief render"),
            "{err}"
        );
        assert!(
            !err.contains(".rs:") && !err.contains("GPU device"),
            "{err}"
        );
    }
}

/// A value of the row's kind that differs from `current` (the table drives this test, so a new
/// parameter is tested through every front end without a line here).
fn other_value(
    p: &relief::table::Param<relief::TerrainParams>,
    current: relief::table::Value,
) -> String {
    use relief::table::{Kind, Value};
    match (p.kind, current) {
        // The grid sets the mesh's finest spacing rounded to a power of two: the next integer
        // may round to the same one, half the grid never does.
        (Kind::Int { min, .. }, Value::Int(v)) if p.key == "grid" => (v / 2).max(min).to_string(),
        (Kind::Int { max, .. }, Value::Int(v)) if v < max => (v + 1).to_string(),
        (Kind::Int { min, .. }, Value::Int(v)) => (v.max(min + 1) - 1).to_string(),
        (Kind::Float { min, max }, Value::Float(v)) => {
            let quarter = (max - min).min(4.0) * 0.25 + 0.01;
            let up = v + quarter;
            (if up <= max { up } else { v - quarter }).to_string()
        }
        (Kind::Pair { .. }, Value::Pair([x, y])) => format!("{},{}", x + 0.25, y + 0.5),
        (Kind::Choice(names), Value::Choice(c)) => {
            names.iter().find(|n| **n != c).unwrap().to_string()
        }
        (kind, v) => panic!("no other value for {kind:?} {v:?}"),
    }
}

#[test]
fn every_parameter_changes_what_it_should_through_flags_and_scene_files() {
    let dir = scratch("table");
    // A small scene, so each render is quick; its own values are the baseline.
    let size = ["--width", "64", "--height", "48"];
    let small_flags = ["--size", "64", "--grid", "24"];
    // Renders with the small scene's flags, unless a scene file gives the scene.
    let render = |name: &str, extra: &[&str]| -> Vec<u8> {
        let out = dir.join(format!("{name}.png"));
        let mut args = vec!["render", "--method", "mesh", "--out", out.to_str().unwrap()];
        args.extend_from_slice(&size);
        if !extra.contains(&"--scene") {
            args.extend_from_slice(&small_flags);
        }
        args.extend_from_slice(extra);
        let (code, _, err) = relief(&args);
        assert_eq!(code, 0, "{args:?}: {err}");
        std::fs::read(&out).unwrap()
    };
    let baseline = render("base", &[]);
    let small = relief::TerrainParams {
        size: 64,
        grid: 24,
        ..Default::default()
    };
    for p in relief::params::params() {
        let flag = format!("--{}", p.flag());
        let value = other_value(p, (p.get)(&small));
        // The flag changes the picture.
        let by_flag = render(&format!("{}-flag", p.key), &[&flag, &value]);
        assert!(by_flag != baseline, "{flag} {value} changed nothing");
        // The scene-file key does the same.
        let mut q = small;
        p.set_text(&mut q, &value).unwrap();
        let scene = dir.join(format!("{}.toml", p.key));
        std::fs::write(&scene, q.to_scene_string(None)).unwrap();
        let by_scene = render(
            &format!("{}-scene", p.key),
            &["--scene", scene.to_str().unwrap()],
        );
        assert!(
            by_scene == by_flag,
            "scene key {} differs from {flag}",
            p.key
        );
        // A flag overrides the scene file.
        let back = (p.get)(&small).to_string();
        let overridden = render(
            &format!("{}-override", p.key),
            &["--scene", scene.to_str().unwrap(), &flag, &back],
        );
        assert!(
            overridden == baseline,
            "{flag} did not override the scene file"
        );
        // `bake` records it in the scene file it writes.
        let out = dir.join(format!("{}-bake", p.key));
        let (code, _, err) = relief(&[
            "bake",
            "--out-dir",
            out.to_str().unwrap(),
            "--size",
            "16",
            &flag,
            &value,
        ]);
        if p.key == "size" {
            assert_eq!(code, 0, "{err}");
            continue;
        }
        assert_eq!(code, 0, "{err}");
        let written = relief::TerrainParams::from_scene_file(&out.join("scene.toml")).unwrap();
        let mut want = relief::TerrainParams { size: 16, ..small };
        want.grid = relief::TerrainParams::default().grid;
        p.set_text(&mut want, &value).unwrap();
        assert_eq!((p.get)(&written), (p.get)(&want), "bake lost {flag}");
    }
}

#[test]
fn a_flat_bake_says_what_its_range_means() {
    let dir = scratch("flat");
    let (code, stdout, err) = relief(&["bake", "--out-dir", dir.to_str().unwrap(), "--size", "1"]);
    assert_eq!(code, 0, "{err}");
    assert!(
        stdout.contains("flat") && stdout.contains("all 0"),
        "{stdout}"
    );
    let h = image::open(dir.join("height.png")).unwrap().into_luma16();
    assert_eq!(h.get_pixel(0, 0).0[0], 0);
    let text = std::fs::read_to_string(dir.join("scene.toml")).unwrap();
    let table: toml::Table = text.parse().unwrap();
    let bake = table["bake"].as_table().unwrap();
    assert_eq!(bake["height_min"].as_float(), bake["height_max"].as_float());
}

#[test]
fn the_tiles_stats_count_its_own_textures_and_bake_timings_say_how_they_were_taken() {
    let dir = scratch("tile-stats");
    let mib = |size: &str| {
        let out = dir.join(format!("{size}.png"));
        let args = [
            "render",
            "--method",
            "mesh",
            "--out",
            out.to_str().unwrap(),
            "--width",
            "64",
            "--height",
            "48",
        ];
        let (code, stdout, err) = relief(&[&args[..], &["--size", size, "--stats"]].concat());
        assert_eq!(code, 0, "{err}");
        let stats = stats_of(&stdout);
        let tile = stat(&stats, "tile_texture_mib");
        let total = stat(&stats, "total_texture_mib");
        assert!(
            (total - tile - stat(&stats, "texture_mib")).abs() <= 0.1,
            "{stats:?}"
        );
        tile
    };
    // rg32float heights and colour, rgba16float normals: 16 bytes a texel.
    assert_eq!(mib("512"), 4.0);
    assert_eq!(mib("256"), 1.0);
    let out = dir.join("bake");
    let (code, stdout, err) = relief(&[
        "bake",
        "--out-dir",
        out.to_str().unwrap(),
        "--size",
        "32",
        "--timings",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(
        stdout.contains("no timestamp queries") || stdout.contains("(each the median of 9 bakes"),
        "{stdout}"
    );
}

#[test]
fn the_cli_page_lists_every_option_as_the_code_has_it() {
    let page =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/cli.md")).unwrap();
    let table = relief::cli::options_markdown();
    assert!(
        page.contains(&table),
        "docs/cli.md's option table is out of date; it should read:\n{table}"
    );
}

#[test]
fn height_prints_the_surface_height_at_each_point() {
    let (code, stdout, err) = relief(&["height", "--seed", "3", "0.1,0.2", "-0.3,0.7", "-5,-3.25"]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(err, "");
    let params = relief::TerrainParams {
        seed: 3,
        ..Default::default()
    };
    let got: Vec<f32> = stdout.lines().map(|l| l.parse().unwrap()).collect();
    let want: Vec<f32> = [(0.1, 0.2), (-0.3, 0.7), (-5.0, -3.25)]
        .iter()
        .map(|&(x, z)| relief::height_at(&params, x, z))
        .collect();
    assert_eq!(got, want, "{stdout}");
    rejects(&["height", "1,x"], &["point", "1,x", "X,Z"]);
    rejects(&["height"], &["X,Z"]);
    rejects(&["height", "--size", "64", "0,0"], &["--size", "height"]);
}

/// Draws one frame with each of `methods` (flags `common` added) and checks each is far closer
/// to the reference than the reference of another seed is. Returns the reference's stdout.
fn every_method_draws_the_same_frame(
    name: &str,
    (w, h): (u32, u32),
    methods: &[&str],
    common: &[&str],
) -> String {
    let dir = scratch(name);
    let (ws, hs) = (w.to_string(), h.to_string());
    let render = |method: &str, extra: &[&str]| {
        let out = dir.join(format!("{method}-{}.png", extra.len()));
        let mut args = vec![
            "render",
            "--out",
            out.to_str().unwrap(),
            "--width",
            &ws,
            "--height",
            &hs,
            "--method",
            method,
        ];
        args.extend_from_slice(common);
        args.extend_from_slice(extra);
        let (code, stdout, err) = relief(&args);
        assert_eq!(code, 0, "{method}: {err}");
        (image::open(&out).unwrap().into_rgb8().into_raw(), stdout)
    };
    let (reference, stdout) = render("reference", &[]);
    let (other_seed, _) = render("reference", &["--seed", "8"]);
    let control = relief::metrics::image_error(&reference, &other_seed, w, h).0;
    for m in methods {
        let (img, _) = render(m, &[]);
        let (flip, _) = relief::metrics::image_error(&reference, &img, w, h);
        eprintln!("{name} {m}: FLIP {flip:.4} against the reference (another seed: {control:.4})");
        // The same frame: far closer to the reference than a different terrain is.
        assert!(
            flip < control * 0.75,
            "{m}: FLIP {flip} vs control {control}"
        );
    }
    stdout
}

#[test]
fn render_draws_the_same_frame_with_every_method() {
    // The blog draws its own terrain (tests/blog.rs scores it against its own surface).
    let tile: Vec<&str> = relief::Method::ALL
        .iter()
        .filter(|m| m.in_tile() && !m.own_terrain())
        .map(|m| m.name())
        .collect();
    every_method_draws_the_same_frame("methods", (160, 100), &tile, &[]);
    // Mesh-only flags mean nothing to a ray caster: refused, not ignored.
    rejects(
        &[
            "render", "--out", "x.png", "--method", "raymarch", "--size", "64",
        ],
        &["--size", "raymarch"],
    );
    rejects(
        &["render", "--out", "x.png", "--method", "rays"],
        &["--method", "rays", "reference"],
    );
    rejects(
        &[
            "render",
            "--out",
            "x.png",
            "--method",
            "raymarch-bandlimited",
        ],
        &["--method", "raymarch-bandlimited", "endless"],
    );
}

#[test]
fn render_draws_the_same_endless_frame_with_every_method() {
    let stats = every_method_draws_the_same_frame(
        "world-methods",
        (120, 68),
        relief::Method::WORLD_NAMES,
        &["--world", "endless", "--pixel-error", "4", "--stats"],
    );
    // The ray casters draw no mesh and say how many rays ran out of steps.
    assert!(stats.contains("triangles 0\n"), "{stats}");
    assert!(stats.contains("unresolved_rays 0\n"), "{stats}");
}

#[test]
fn a_knob_finer_than_the_levels_can_hold_says_so_on_stderr() {
    let dir = scratch("knob-warning");
    let out = dir.join("frame.png");
    let run = |knob: &str| {
        relief(&[
            "render",
            "--method",
            "mesh",
            "--world",
            "endless",
            "--width",
            "320",
            "--height",
            "180",
            "--stats",
            "--pixel-error",
            knob,
            "--out",
            out.to_str().unwrap(),
        ])
    };
    // At 320x180 the densest levels hold about 0.42 px: 0.25 px is more than they can give.
    let (code, stdout, err) = run("0.25");
    assert_eq!(code, 0, "{err}");
    let stats = stats_of(&stdout);
    assert_eq!(stat(&stats, "patch_cells"), 128.0, "{stdout}");
    let bound = stat(&stats, "error_bound_px");
    assert!(bound > 0.25, "{stdout}");
    assert_eq!(err.lines().count(), 1, "one short line: {err}");
    assert!(err.contains("--pixel-error 0.25"), "{err}");
    // The bound it names is --stats' (printed to 3 places there, 2 here).
    let named: f64 = err
        .split("bounded by ")
        .nth(1)
        .and_then(|t| t.split(" px").next())
        .and_then(|t| t.parse().ok())
        .unwrap_or_else(|| panic!("no bound in {err}"));
    assert!(
        (named - bound).abs() <= 0.006,
        "{named} against {bound}: {err}"
    );
    // A knob they hold: the patches are smaller than the largest, nothing is said.
    let (code, stdout, err) = run("1");
    assert_eq!(code, 0, "{err}");
    assert!(
        stat(&stats_of(&stdout), "error_bound_px") <= 1.0,
        "{stdout}"
    );
    assert_eq!(err, "", "a knob the levels hold keeps stderr clean");
}

/// Renders the endless world small and loose (fast on a software GPU); returns the pixels and
/// the `--stats` lines.
fn render_endless(dir: &Path, name: &str, extra: &[&str]) -> (Vec<u8>, Vec<(String, f64)>) {
    let out = dir.join(format!("{name}.png"));
    let mut args = vec![
        "render",
        "--method",
        "mesh",
        "--world",
        "endless",
        "--out",
        out.to_str().unwrap(),
        "--width",
        "96",
        "--height",
        "64",
        "--stats",
    ];
    if !extra.contains(&"--pixel-error") {
        args.extend_from_slice(&["--pixel-error", "16"]);
    }
    args.extend_from_slice(extra);
    let (code, stdout, err) = relief(&args);
    assert_eq!(code, 0, "{extra:?}: {err}");
    assert_eq!(err, "", "{extra:?}: stderr not clean");
    (
        image::open(&out).unwrap().into_rgb8().into_raw(),
        stats_of(&stdout),
    )
}

/// The `key value` lines of `--stats` whose value is a number.
fn stats_of(stdout: &str) -> Vec<(String, f64)> {
    stdout
        .lines()
        .filter_map(|l| {
            let (k, v) = l.split_once(' ')?;
            Some((k.to_owned(), v.parse().ok()?))
        })
        .collect()
}

fn stat(stats: &[(String, f64)], key: &str) -> f64 {
    stats
        .iter()
        .find(|(k, _)| k == key)
        .unwrap_or_else(|| panic!("no {key} in {stats:?}"))
        .1
}

#[test]
fn the_endless_world_renders_and_every_one_of_its_parameters_changes_it() {
    let dir = scratch("endless");
    let (base, stats) = render_endless(&dir, "base", &[]);
    for key in [
        "triangles",
        "texels_baked",
        "levels",
        "error_bound_px",
        "patch_cells",
        "texture_mib_per_level",
        "texture_mib",
    ] {
        assert!(stat(&stats, key) >= 0.0);
    }
    assert!(
        (stat(&stats, "texture_mib")
            - stat(&stats, "texture_mib_per_level") * stat(&stats, "levels_total"))
        .abs()
            < 0.1,
        "{stats:?}"
    );
    assert!(
        stat(&stats, "triangles") > 0.0 && stat(&stats, "levels") >= 3.0,
        "{stats:?}"
    );
    assert!(stat(&stats, "error_bound_px") <= 16.0, "{stats:?}");
    // Every row of the endless world's table, through its flag: the picture changes (the
    // knob changes the triangles; the picture may stay nearly the same).
    for row in &relief::world::WORLD_PARAMS {
        let value = match row.key {
            "seed" => "8",
            "octaves" => "6",
            "gain" => "0.6",
            "feature_size" => "1024",
            "peak_height" => "900",
            "terrain" => "fbm",
            "pixel_error" => "4",
            "snow_height" => "0.3",
            "ao_exponent" => "3",
            "sun_azimuth" => "300",
            "sun_elevation" => "40",
            "fog" => "0.4",
            "water_level" => "1300",
            "no_water" => "1",
            "palette" => "blog",
            "no_shadows" => "1",
            "clock" => "30",
            "wind_speed" => "12",
            "wind_azimuth" => "90",
            other => panic!("no test value for {other}: add one"),
        };
        let flag = format!("--{}", row.flag());
        let mut args: Vec<&str> = match row.kind {
            relief::table::Kind::Bool => vec![&flag],
            _ => vec![&flag, value],
        };
        // The height occlusion exponent is the blog palette's: it changes that picture.
        let blog = row.key == "ao_exponent";
        // The clock and the wind move the ripples, which fade out a few hundred metres away:
        // seen from 20 m above a lake (its bed 770 m down, the water at 1000 m). The wind
        // carries them as the clock runs: at clock 0 it has carried nothing.
        let lake = ["--eye", "2000,1020,-4600", "--look-at", "2100,1000,-4400"];
        let windy = row.key.starts_with("wind_");
        let base = if blog {
            args.extend(["--palette", "blog"]);
            render_endless(&dir, "blog", &["--palette", "blog"]).0
        } else if windy {
            args.extend(lake);
            args.extend(["--clock", "30"]);
            let mut at = lake.to_vec();
            at.extend(["--clock", "30"]);
            render_endless(&dir, "lake-30", &at).0
        } else if row.key == "clock" {
            args.extend(lake);
            render_endless(&dir, "lake", &lake).0
        } else {
            base.clone()
        };
        let (img, s) = render_endless(&dir, row.key, &args);
        if row.key == "pixel_error" {
            assert!(
                stat(&s, "triangles") > stat(&stats, "triangles"),
                "{flag} {value}: {s:?} against {stats:?}"
            );
        } else {
            assert_ne!(img, base, "{flag} {value} left the picture unchanged");
        }
        // The same value as a scene-file key draws the same picture as the flag.
        let scene = dir.join(format!("{}.toml", row.key));
        let mut knob = if row.key == "pixel_error" {
            String::new()
        } else {
            "pixel_error = 16\n".to_owned()
        };
        if blog {
            knob.push_str("palette = \"blog\"\n");
        }
        std::fs::write(
            &scene,
            format!(
                "world = \"endless\"\n{knob}{} = {}\n",
                row.key,
                relief::scene::toml_value(row.parse(value).unwrap())
            ),
        )
        .unwrap();
        let out = dir.join(format!("{}-scene.png", row.key));
        let (code, stdout, err) = relief(&[
            "render",
            "--method",
            "mesh",
            "--scene",
            scene.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--width",
            "96",
            "--height",
            "64",
            "--stats",
        ]);
        assert_eq!(code, 0, "{}: {err}", row.key);
        assert_eq!(
            image::open(&out).unwrap().into_rgb8().into_raw(),
            img,
            "{} = {value} in a scene file draws another picture than {flag} {value}",
            row.key
        );
        assert!(
            stdout.contains(&format!("triangles {}", stat(&s, "triangles"))),
            "{stdout}"
        );
    }
    // The camera flags move the camera.
    let (moved, _) = render_endless(&dir, "eye", &["--eye", "500,2400,-800"]);
    assert_ne!(moved, base);
    let (turned, _) = render_endless(&dir, "look", &["--look-at", "0,0,9000"]);
    assert_ne!(turned, base);
    let (wide, _) = render_endless(&dir, "fov", &["--fov", "80"]);
    assert_ne!(wide, base);
    // The fly-through path: a time is a place along it.
    let (p0, _) = render_endless(&dir, "path0", &["--camera", "path"]);
    let (p1, _) = render_endless(&dir, "path1", &["--camera", "path", "--time", "30"]);
    assert_ne!(p0, base);
    assert_ne!(p0, p1);
    let (again, _) = render_endless(&dir, "path0b", &["--camera", "path", "--time", "0"]);
    assert_eq!(again, p0, "the path at 0 s is --camera path without --time");
    // Looking straight up: sky only, nothing drawn.
    let (_, up) = render_endless(&dir, "up", &["--eye", "0,3000,0", "--look-at", "0,9000,1"]);
    assert_eq!(stat(&up, "triangles"), 0.0, "{up:?}");
}

#[test]
fn the_endless_world_heights_and_the_tile_camera() {
    let (code, stdout, err) = relief(&[
        "height",
        "--world",
        "endless",
        "--seed",
        "3",
        "0,0",
        "125.5,-3000",
    ]);
    assert_eq!(code, 0, "{err}");
    let land = relief::WorldParams {
        land: relief::landscape::Landscape {
            seed: 3,
            ..relief::WorldParams::default().land
        },
        ..Default::default()
    }
    .land;
    let got: Vec<f64> = stdout.lines().map(|l| l.parse().unwrap()).collect();
    assert_eq!(
        got,
        vec![land.height_at(0.0, 0.0), land.height_at(125.5, -3000.0)]
    );
    // The tile takes the camera flags too.
    let dir = scratch("tile-camera");
    let render = |name: &str, extra: &[&str]| {
        let out = dir.join(format!("{name}.png"));
        let mut args = vec![
            "render",
            "--method",
            "mesh",
            "--out",
            out.to_str().unwrap(),
            "--width",
            "64",
            "--height",
            "48",
            "--size",
            "64",
            "--grid",
            "32",
        ];
        args.extend_from_slice(extra);
        let (code, _, err) = relief(&args);
        assert_eq!(code, 0, "{err}");
        image::open(&out).unwrap().into_rgb8().into_raw()
    };
    let base = render("base", &[]);
    assert_ne!(render("eye", &["--eye", "0,2,2.5"]), base);
    assert_ne!(render("fov", &["--fov", "70"]), base);
}

#[test]
fn bad_camera_and_world_input_exits_2_and_writes_nothing() {
    let dir = scratch("bad-camera");
    let out = dir.join("x.png");
    let out = out.to_str().unwrap();
    let render = |extra: &[&str], needles: &[&str]| {
        let mut args = vec!["render", "--out", out];
        args.extend_from_slice(extra);
        rejects(&args, needles);
    };
    render(&["--eye", "nan,0,0"], &["--eye", "nan", "X,Y,Z"]);
    render(&["--eye", "1,2"], &["--eye", "X,Y,Z"]);
    render(&["--look-at", "1,2,3,4"], &["--look-at", "X,Y,Z"]);
    render(&["--eye", "1e300,0,0"], &["--eye", "X,Y,Z"]);
    render(
        &["--eye", "0,5,0", "--look-at", "0,5,0"],
        &["--look-at", "--eye"],
    );
    render(&["--fov", "0"], &["--fov", "0", "degrees"]);
    render(&["--fov", "180"], &["--fov", "180"]);
    render(&["--fov", "wide"], &["--fov", "wide"]);
    render(&["--world", "moon"], &["--world", "moon", "endless"]);
    render(&["--world", "endless", "--size", "64"], &["--size", "tile"]);
    render(
        &["--world", "endless", "--offset", "1,2"],
        &["--offset", "tile"],
    );
    render(
        &["--world", "endless", "--scene", "a.toml"],
        &["a.toml", "No such file"],
    );
    render(
        &["--world", "endless", "--feature-size", "3000"],
        &["feature-size", "3000", "power of two"],
    );
    render(
        &[
            "--world",
            "endless",
            "--feature-size",
            "16",
            "--octaves",
            "20",
        ],
        &["--octaves", "20", "1..=12"],
    );
    render(
        &["--world", "endless", "--pixel-error", "0"],
        &["--pixel-error", "0"],
    );
    render(&["--peak-height", "100"], &["--peak-height", "endless"]);
    render(
        &["--world", "endless", "--sun-elevation", "91"],
        &["--sun-elevation", "91", "-90..=90"],
    );
    render(&["--world", "endless", "--fog", "-1"], &["--fog", "-1"]);
    render(
        &["--world", "endless", "--sun-azimuth", "north"],
        &["--sun-azimuth", "north"],
    );
    render(&["--sun-azimuth", "10"], &["--sun-azimuth", "endless"]);
    render(
        &["--world", "endless", "--water-level", "1e9"],
        &["--water-level", "1e9"],
    );
    rejects(
        &[
            "bake",
            "--out-dir",
            dir.to_str().unwrap(),
            "--world",
            "endless",
            "--normals",
            "analytic",
        ],
        &["--normals", "tile"],
    );
    rejects(&["height", "--eye", "1,2,3", "0,0"], &["--eye", "render"]);
    rejects(&["window", "--eye", "1,2,3"], &["--eye", "render"]);
    render(
        &["--world", "endless", "--camera", "zoom"],
        &["--camera", "zoom", "path"],
    );
    render(&["--camera", "fly"], &["--camera fly", "tile", "orbit"]);
    render(
        &["--world", "endless", "--camera", "orbit"],
        &["--camera orbit", "endless"],
    );
    render(
        &["--world", "endless", "--camera", "path", "--eye", "0,9,0"],
        &["--eye", "path"],
    );
    render(
        &["--world", "endless", "--camera", "path", "--time", "-1"],
        &["--time", "-1", "seconds"],
    );
    render(&["--world", "endless", "--time", "5"], &["--time", "path"]);
    rejects(
        &["--world", "endless", "--speed", "1"],
        &["--speed", "tile"],
    );
    rejects(
        &["window", "--world", "endless", "--stats"],
        &["--stats", "render"],
    );
    rejects(
        &["height", "--world", "endless", "--pixel-error", "2", "0,0"],
        &["--pixel-error", "height"],
    );
    assert!(files_in(&dir).is_empty(), "{:?}", files_in(&dir));
}

#[test]
fn bench_world_endless_quick_writes_landscape_csv() {
    let dir = scratch("bench-endless");
    let out = dir.join("out");
    let (code, stdout, err) = relief(&[
        "bench",
        "--world",
        "endless",
        "--quick",
        "--out-dir",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    // Not a terminal: no progress (nor its escape codes) on stderr.
    assert_eq!(err, "", "a run into a pipe keeps stderr clean");
    let csv = std::fs::read_to_string(out.join("landscape.csv")).unwrap();
    let look = std::fs::read_to_string(out.join("look.csv")).unwrap();
    // Stdout says what was written, and the arrival in words; the CSVs stay in their files.
    for name in ["look.csv", "landscape.csv", "arrival.csv"] {
        assert!(
            stdout.contains(&format!("rows in {}", out.join(name).display())),
            "{stdout}"
        );
    }
    assert!(!stdout.contains("view,method"), "{stdout}");
    for method in ["mesh", "visibility 1 compute"] {
        assert!(
            stdout.contains(&format!("arrival ({method}): first frame")),
            "{stdout}"
        );
    }
    assert_eq!(
        files_in(&out),
        [
            "arrival.csv",
            "landscape.csv",
            "landscape.png",
            "landscape.svg",
            "look.csv"
        ]
    );
    // The arrival: every frame from the first, each lighting within the budget, and the
    // light waiting at the start (nothing is lit on arrival).
    let arrival = std::fs::read_to_string(out.join("arrival.csv")).unwrap();
    let frames: Vec<Vec<&str>> = arrival
        .lines()
        .filter(|l| !l.starts_with('#'))
        .skip(1)
        .map(|l| l.split(',').collect())
        .collect();
    assert_eq!(frames.len(), 2 * 6, "{arrival}");
    for f in &frames {
        let lit: u64 = f[6].parse().unwrap();
        assert!(lit <= relief::gpu::world::DEFAULT_LIGHT_BUDGET, "{f:?}");
    }
    assert!(frames[0][7].parse::<u64>().unwrap() > 0, "{arrival}");
    // The look's cost: each part off in turn on the first view, and the light bake.
    let look: Vec<Vec<&str>> = look
        .lines()
        .filter(|l| !l.starts_with('#'))
        .skip(1)
        .map(|l| l.split(',').collect())
        .collect();
    assert_eq!(look.len(), 7, "{look:?}");
    assert_eq!(look[0][1], "everything on");
    assert!(
        look[0][4].parse::<f64>().unwrap() > 0.0,
        "light bake: {look:?}"
    );
    assert!(
        look.iter().all(|r| r[2].parse::<f64>().unwrap() > 0.0),
        "{look:?}"
    );
    let rows: Vec<&str> = csv.lines().filter(|l| !l.starts_with('#')).collect();
    let header: Vec<&str> = rows[0].split(',').collect();
    // Three views at two knobs: the mesh and the hybrid (at four samples a pixel and one) at
    // each, the visibility method beside them at the first; the four ray casters on each view,
    // and two flights.
    assert_eq!(rows.len(), 1 + 3 * 4 + 3 * 3 + 3 * 4 + 2, "{csv}");
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    // The quick run rasterises in hardware (the full run adds the hybrid rasterised in compute).
    let meshes: Vec<(&str, &str, &str)> = rows[1..22]
        .iter()
        .map(|r| {
            let v: Vec<&str> = r.split(',').collect();
            (v[col("method")], v[col("samples")], v[col("raster")])
        })
        .collect();
    let first = [
        ("mesh", "", ""),
        ("visibility", "4", "hardware"),
        ("hybrid", "4", "hardware"),
        ("hybrid", "1", "hardware"),
    ];
    let second = [
        ("mesh", "", ""),
        ("hybrid", "4", "hardware"),
        ("hybrid", "1", "hardware"),
    ];
    assert_eq!(
        meshes,
        [&first[..], &first, &first, &second, &second, &second].concat(),
        "{csv}"
    );
    let flip_of = |row: &str| -> f64 {
        let v: Vec<&str> = row.split(',').collect();
        v[col("flip_mean")].parse().unwrap()
    };
    // From the same coarse mesh, the hybrid's refined surface is closer to the reference than
    // the mesh on every view at both knobs, at four samples a pixel and at one.
    let first_knob = (0..3).map(|v| (1 + 4 * v, [3 + 4 * v, 4 + 4 * v]));
    let second_knob = (0..3).map(|v| (13 + 3 * v, [14 + 3 * v, 15 + 3 * v]));
    for (mesh, hybrids) in first_knob.chain(second_knob) {
        for hybrid in hybrids {
            assert!(
                flip_of(rows[hybrid]) < flip_of(rows[mesh]),
                "{}\n{}",
                rows[mesh],
                rows[hybrid]
            );
        }
    }
    for row in &rows[1..22] {
        let v: Vec<&str> = row.split(',').collect();
        if v[col("method")] == "hybrid" {
            // Its surface is the continuous one: the mesh's screen error and depth are not
            // its, and are left empty; its FLIP is measured.
            assert_eq!(v[col("measured_max_px")], "", "{row}");
            assert_eq!(v[col("missed")], "", "{row}");
            let flip = flip_of(row);
            assert!(flip > 0.0 && flip < 0.25, "{row}");
            continue;
        }
        let measured: f64 = v[col("measured_max_px")].parse().unwrap();
        let bound: f64 = v[col("error_bound_px")].parse().unwrap();
        assert!(measured <= bound, "{row}");
        assert!(v[col("triangles")].parse::<u64>().unwrap() > 0, "{row}");
        // Against the reference of the same view: close, and drawing where it draws.
        let flip: f64 = v[col("flip_mean")].parse().unwrap();
        assert!(flip > 0.0 && flip < 0.25, "{row}");
        let holes: f64 =
            v[col("missed")].parse::<f64>().unwrap() + v[col("extra")].parse::<f64>().unwrap();
        assert!(holes < 0.02, "{row}");
    }
    let casters = [
        "reference",
        "raymarch",
        "raymarch-fragment",
        "raymarch-bandlimited",
    ];
    for (row, method) in rows[22..34].iter().zip(casters.iter().cycle()) {
        let v: Vec<&str> = row.split(',').collect();
        assert_eq!(v[col("method")], *method, "{row}");
        assert_eq!(v[col("triangles")], "0", "{row}");
        assert!(v[col("render_ms")].parse::<f64>().unwrap() > 0.0, "{row}");
        assert!(v[col("unresolved_rays")].parse::<u64>().is_ok(), "{row}");
        if *method != "reference" {
            assert!(v[col("flip_mean")].parse::<f64>().unwrap() < 0.25, "{row}");
        }
    }
    assert!(rows[34].starts_with("flight,"), "{csv}");
    assert!(rows[35].starts_with("path,"), "{csv}");
}

#[test]
fn bake_world_endless_writes_a_region_that_recovers_the_twin() {
    let dir = scratch("bake-region");
    let out = dir.join("out");
    let (code, stdout, err) = relief(&[
        "bake",
        "--world",
        "endless",
        "--region",
        "-256,512,256,1024",
        "--size",
        "64",
        "--seed",
        "5",
        "--out-dir",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(err, "");
    assert!(stdout.contains("every 8 m"), "{stdout}");
    assert_eq!(
        files_in(&out),
        ["color.png", "height.png", "normal.png", "scene.toml"]
    );
    let scene: toml::Table = std::fs::read_to_string(out.join("scene.toml"))
        .unwrap()
        .parse()
        .unwrap();
    assert_eq!(scene["world"].as_str(), Some("endless"));
    assert_eq!(scene["seed"].as_integer(), Some(5));
    let bake = scene["bake"].as_table().unwrap();
    assert_eq!(bake["spacing"].as_float(), Some(8.0));
    let (lo, hi) = (
        bake["height_min"].as_float().unwrap(),
        bake["height_max"].as_float().unwrap(),
    );
    let land = relief::landscape::Landscape {
        seed: 5,
        ..relief::WorldParams::default().land
    };
    let h = image::open(out.join("height.png")).unwrap().into_luma16();
    for (i, j) in [(0u32, 0u32), (63, 0), (10, 40), (63, 63)] {
        let v = f64::from(h.get_pixel(i, j).0[0]) / 65535.0 * (hi - lo) + lo;
        // Sample (i, j) is world (-256 + 8i, 512 + 8j): sample coordinates -32 + i, 64 + j.
        let twin = land.peak_height
            * land
                .level_sample(
                    relief::noise::Channel::Height,
                    3,
                    -32 + i64::from(i),
                    64 + i64::from(j),
                )
                .value;
        // 16-bit quantisation of the range, plus f32 on the GPU.
        assert!(
            (v - twin).abs() <= (hi - lo) / 65535.0 + 1e-3,
            "sample ({i}, {j}): height.png says {v}, the twin {twin}"
        );
    }
    let bad = |extra: &[&str], needles: &[&str]| {
        let mut args = vec![
            "bake",
            "--world",
            "endless",
            "--out-dir",
            out.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        rejects(&args, needles);
    };
    bad(
        &["--region", "0,0,100,100", "--size", "64"],
        &["--region", "power of two"],
    );
    bad(
        &["--region", "3,0,131,128", "--size", "64"],
        &["--region", "multiple"],
    );
    bad(&["--region", "0,0,64"], &["--region", "four numbers"]);
    bad(
        &["--region", "0,0,64,32", "--size", "32"],
        &["--region", "square"],
    );
    bad(&["--region", "nan,0,64,64"], &["--region", "finite"]);
    rejects(
        &[
            "render",
            "--method",
            "mesh",
            "--out",
            "x.png",
            "--world",
            "endless",
            "--region",
            "0,0,64,64",
        ],
        &["--region", "bake"],
    );
    rejects(
        &["bake", "--out-dir", "x", "--region", "0,0,64,64"],
        &["--region", "endless"],
    );
}

#[test]
fn endless_scene_files_and_camera_tables_round_trip() {
    let dir = scratch("endless-scene");
    let bake = dir.join("bake");
    let (code, _, err) = relief(&[
        "bake",
        "--world",
        "endless",
        "--seed",
        "12",
        "--peak-height",
        "1500",
        "--region",
        "0,0,512,512",
        "--size",
        "64",
        "--out-dir",
        bake.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let scene = bake.join("scene.toml");
    // The bake's scene file draws the same world as the flags that made it.
    let (from_scene, _) = render_endless(&dir, "scene", &["--scene", scene.to_str().unwrap()]);
    let (from_flags, _) = render_endless(&dir, "flags", &["--seed", "12", "--peak-height", "1500"]);
    assert_eq!(from_scene, from_flags);
    // Without --world: the scene file's world decides.
    let out = dir.join("auto.png");
    let (code, stdout, err) = relief(&[
        "render",
        "--method",
        "mesh",
        "--scene",
        scene.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--width",
        "96",
        "--height",
        "64",
        "--pixel-error",
        "16",
        "--stats",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(stdout.contains("levels_total"), "{stdout}");
    assert_eq!(
        image::open(&out).unwrap().into_rgb8().into_raw(),
        from_scene
    );
    // A [camera] table places the camera as the flags would; a flag overrides its part.
    let with_camera = dir.join("camera.toml");
    std::fs::write(
        &with_camera,
        "world = \"endless\"\nseed = 12\npeak_height = 1500\n\n[camera]\neye = [300, 2200, -100]\nlook_at = [2000, 900, 400]\nfov = 60\n",
    )
    .unwrap();
    let (a, _) = render_endless(
        &dir,
        "cam-scene",
        &["--scene", with_camera.to_str().unwrap()],
    );
    let (b, _) = render_endless(
        &dir,
        "cam-flags",
        &[
            "--seed",
            "12",
            "--peak-height",
            "1500",
            "--eye",
            "300,2200,-100",
            "--look-at",
            "2000,900,400",
            "--fov",
            "60",
        ],
    );
    assert_eq!(a, b);
    let (c, _) = render_endless(
        &dir,
        "cam-override",
        &["--scene", with_camera.to_str().unwrap(), "--fov", "40"],
    );
    assert_ne!(a, c);
    // The path and its time from [camera], as --camera path --time would place it.
    let on_path = dir.join("path.toml");
    std::fs::write(
        &on_path,
        "world = \"endless\"\nseed = 12\n[camera]\ncamera = \"path\"\ntime = 30\n",
    )
    .unwrap();
    let (p_scene, _) = render_endless(&dir, "path-scene", &["--scene", on_path.to_str().unwrap()]);
    let (p_flags, _) = render_endless(
        &dir,
        "path-flags",
        &["--seed", "12", "--camera", "path", "--time", "30"],
    );
    assert_eq!(p_scene, p_flags);
    // Bad scene files: one line naming the file and what is wrong, nothing written.
    let bad = |name: &str, text: &str, needles: &[&str]| {
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        let out = dir.join(format!("{name}.png"));
        rejects(
            &[
                "render",
                "--method",
                "mesh",
                "--scene",
                path.to_str().unwrap(),
                "--out",
                out.to_str().unwrap(),
            ],
            needles,
        );
        assert!(!out.exists());
    };
    bad(
        "moon.toml",
        "world = \"moon\"\n",
        &["moon.toml", "world", "endless"],
    );
    bad(
        "size.toml",
        "world = \"endless\"\nsize = 64\n",
        &["size.toml", "size", "water_level"],
    );
    bad(
        "fov.toml",
        "world = \"endless\"\n[camera]\nfov = 0\n",
        &["fov.toml", "fov", "degrees"],
    );
    bad(
        "eye.toml",
        "world = \"endless\"\n[camera]\neye = [1, 2]\n",
        &["eye.toml", "eye", "[x, y, z]"],
    );
    bad(
        "key.toml",
        "world = \"endless\"\n[camera]\nzoom = 2\n",
        &["key.toml", "zoom", "look_at"],
    );
    bad(
        "path.toml",
        "world = \"endless\"\n[camera]\ncamera = \"path\"\neye = [0, 900, 0]\n",
        &["eye", "path"],
    );
    // The tile reads a [camera] table too.
    let tile = dir.join("tile.toml");
    std::fs::write(&tile, "seed = 3\n[camera]\neye = [0, 2, 2.5]\n").unwrap();
    let render_tile = |name: &str, extra: &[&str]| {
        let out = dir.join(format!("{name}.png"));
        let mut args = vec![
            "render",
            "--method",
            "mesh",
            "--out",
            out.to_str().unwrap(),
            "--width",
            "64",
            "--height",
            "48",
            "--size",
            "64",
            "--grid",
            "32",
        ];
        args.extend_from_slice(extra);
        let (code, _, err) = relief(&args);
        assert_eq!(code, 0, "{err}");
        image::open(&out).unwrap().into_rgb8().into_raw()
    };
    assert_eq!(
        render_tile("tile-scene", &["--scene", tile.to_str().unwrap()]),
        render_tile("tile-flags", &["--seed", "3", "--eye", "0,2,2.5"])
    );
}

#[test]
fn render_draws_the_blogs_pipeline_and_refuses_what_it_does_not_read() {
    let dir = scratch("blog");
    let out = dir.join("blog.png");
    let args = |extra: &[&'static str]| {
        let mut a = vec![
            "render",
            "--method",
            "blog",
            "--out",
            out.to_str().unwrap(),
            "--width",
            "96",
            "--height",
            "64",
            "--stats",
            "--timings",
        ];
        a.extend_from_slice(extra);
        a
    };
    let (code, stdout, err) = relief(&args(&[]));
    assert_eq!(code, 0, "{err}");
    assert_eq!(err, "");
    // Its 1024²-vertex grid and two 8-bit 1024² maps, baked whole every frame, each timed.
    let stats = stats_of(&stdout);
    assert_eq!(stat(&stats, "triangles"), 2.0 * 1023.0 * 1023.0, "{stdout}");
    assert_eq!(stat(&stats, "texels_baked"), 1024.0 * 1024.0, "{stdout}");
    assert_eq!(stat(&stats, "total_texture_mib"), 8.0, "{stdout}");
    assert!(
        stdout.contains("no timestamp queries")
            || ["bake", "normals", "render"]
                .iter()
                .all(|p| stdout.contains(&format!("{p} "))),
        "{stdout}"
    );
    let blog = image::open(&out).unwrap().to_rgba8();
    // The scene's height scale is the blog's too: a flatter terrain draws another picture.
    let (code, _, err) = relief(&args(&["--height-scale", "0.1"]));
    assert_eq!(code, 0, "{err}");
    let flat = image::open(&out).unwrap().to_rgba8();
    assert_ne!(
        blog.as_raw(),
        flat.as_raw(),
        "--height-scale changed nothing"
    );
    // ... and its snow line.
    let (code, _, err) = relief(&args(&["--snow-height", "0.3"]));
    assert_eq!(code, 0, "{err}");
    let snowy = image::open(&out).unwrap().to_rgba8();
    assert_ne!(
        blog.as_raw(),
        snowy.as_raw(),
        "--snow-height changed nothing"
    );
    // The scene's noise, texture and grid are not the blog's: refused, not ignored.
    for flag in ["--seed", "--octaves", "--grid", "--size", "--gain"] {
        rejects(&args(&[flag, "3"]), &[flag, "blog"]);
    }
    // The blog draws its own tile, not the endless world.
    rejects(
        &[
            "render", "--world", "endless", "--method", "blog", "--out", "x.png",
        ],
        &["blog", "tile"],
    );
}

#[test]
fn stability_quick_writes_a_csv_charts_and_refuses_what_it_sweeps() {
    let dir = scratch("stability");
    let (code, stdout, err) = relief(&[
        "stability",
        "--quick",
        "--octaves",
        "6",
        "--out-dir",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(err, "", "a successful run keeps stderr clean");
    assert!(
        stdout.contains("octaves 6") && stdout.contains("height scale 2"),
        "{stdout}"
    );
    assert_eq!(
        files_in(&dir),
        [
            "detail.csv",
            "detail.png",
            "detail.svg",
            "distance.csv",
            "distance.png",
            "distance.svg",
            "grazing-hs0p5.png",
            "grazing-hs0p5.svg",
            "grazing-hs2.png",
            "grazing-hs2.svg",
            "motion.csv",
            "motion.png",
            "motion.svg",
            "scroll.csv",
            "scroll.png",
            "scroll.svg",
            "shadow.csv",
            "shadow.png",
            "shadow.svg",
            "stability.csv",
            "storage.csv",
            "storage.png",
            "storage.svg",
            "world-grazing-hs2400.png",
            "world-grazing-hs2400.svg",
            "world-grazing.csv"
        ]
    );
    // The world axes: the shadow rays' table (3 suns x 3 methods), the distance axis with the
    // default world's refusal 10^9 m out, the flights (2 speeds: the mesh with the morph on
    // and off, the visibility method, the hybrid).
    let lines = |name: &str| {
        std::fs::read_to_string(dir.join(name))
            .unwrap()
            .lines()
            .count()
    };
    assert_eq!(lines("shadow.csv"), 1 + 9);
    assert_eq!(lines("motion.csv"), 1 + 8);
    let distance = std::fs::read_to_string(dir.join("distance.csv")).unwrap();
    assert!(
        distance
            .lines()
            .any(|l| l.starts_with("1e9,\"x and z within")),
        "{distance}"
    );
    // The visibility method and the hybrid beside the mesh on the distance axis.
    for column in [
        "jitter_visibility",
        "missed_hybrid",
        "flip_hybrid_vs_reference",
    ] {
        assert!(
            distance.lines().next().unwrap_or_default().contains(column),
            "distance.csv lacks {column}"
        );
    }
    assert!(
        stdout.contains("refused: the eye must be x and z within"),
        "{stdout}"
    );
    let csv = std::fs::read_to_string(dir.join("stability.csv")).unwrap();
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let rows: Vec<Vec<String>> = csv.lines().skip(1).map(csv_fields).collect();
    // 3 elevations x 2 height scales x (2 step factors, the relaxation, the march in a
    // fragment shader, the mesh, the reference).
    assert_eq!(rows.len(), 36, "{csv}");
    for row in &rows {
        let tunnelled: usize = row[col("tunnelled")].parse().unwrap();
        if row[col("method")] == "reference" {
            assert_eq!(tunnelled, 0, "the reference tunnelled: {row:?}");
        }
    }
    for (flag, value) in [("--height-scale", "1"), ("--grid", "64"), ("--timings", "")] {
        let mut args = vec!["stability", "--quick", flag];
        if !value.is_empty() {
            args.push(value);
        }
        rejects(&args, &[flag, "stability"]);
    }
    rejects(&["stability", "--world", "endless"], &["stability", "tile"]);
    // The scroll axis: relief's tile and the blog's at each quick distance, relief refusing
    // 10^13 tiles in words.
    let scroll = std::fs::read_to_string(dir.join("scroll.csv")).unwrap();
    assert_eq!(scroll.lines().count(), 1 + 2 * 4, "{scroll}");
    assert!(
        scroll.lines().any(|l| l.starts_with("relief,1e13,\"")),
        "{scroll}"
    );
}

#[test]
fn stability_axis_runs_only_the_axes_named_and_writes_only_their_files() {
    let dir = scratch("stability-axis");
    let (code, stdout, err) = relief(&[
        "stability",
        "--quick",
        "--axis",
        "storage,scroll",
        "--out-dir",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(err, "", "a successful run keeps stderr clean");
    assert_eq!(
        files_in(&dir),
        [
            "scroll.csv",
            "scroll.png",
            "scroll.svg",
            "storage.csv",
            "storage.png",
            "storage.svg"
        ]
    );
    // In the order the full sweep runs them, whatever the order named.
    assert!(stdout.contains("2 axes (scroll, storage)"), "{stdout}");
    assert!(!stdout.contains("grazing views"), "{stdout}");
    // Repeating the flag adds to the list.
    let again = scratch("stability-axis-again");
    let (code, _, err) = relief(&[
        "stability",
        "--quick",
        "--axis",
        "storage",
        "--axis",
        "storage",
        "--out-dir",
        again.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(
        files_in(&again),
        ["storage.csv", "storage.png", "storage.svg"]
    );
    rejects(
        &["stability", "--axis", "sideways"],
        &["--axis", "sideways", "world-grazing", "scroll"],
    );
    rejects(&["render", "--axis", "scroll"], &["--axis"]);
}

/// `--method`, `--samples` and `--raster` reach `relief render` and the window; the other
/// commands refuse them in words, and the window refuses a method its world does not draw
/// (before any window opens).
#[test]
fn method_samples_and_raster_reach_render_and_the_window_only() {
    let dir = scratch("method-reach");
    let d = dir.to_str().unwrap();
    for (args, flag) in [
        (
            &["bake", "--out-dir", d, "--method", "mesh"][..],
            "--method",
        ),
        (
            &["bench", "--out-dir", d, "--raster", "compute"][..],
            "--raster",
        ),
        (&["height", "--samples", "1", "0,0"][..], "--samples"),
        (
            &["stability", "--out-dir", d, "--method", "auto"][..],
            "--method",
        ),
    ] {
        rejects(args, &[flag, "render and the window only"]);
    }
    rejects(
        &["--world", "endless", "--method", "blog"],
        &["--method blog", "tile"],
    );
    rejects(&["--method", "hybrid"], &["--method hybrid", "endless"]);
    // The window's default is the mesh, which takes no samples.
    rejects(
        &["--samples", "1"],
        &["--samples", "visibility and hybrid", "mesh"],
    );
    rejects(
        &["window", "--method", "mesh", "--raster", "compute"],
        &["--raster", "visibility and hybrid only", "mesh"],
    );
    // The compute raster draws one sample a pixel: refused at the default 4, in the window as
    // in render.
    rejects(
        &["--method", "visibility", "--raster", "compute"],
        &["--raster", "--samples 1"],
    );
    rejects(
        &[
            "render", "--out", "x.png", "--world", "endless", "--method", "hybrid", "--raster",
            "compute",
        ],
        &["--raster", "--samples 1"],
    );
    assert!(
        files_in(&dir).is_empty(),
        "a refused command writes nothing"
    );
}
