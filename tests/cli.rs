//! The `relief` program as a user meets it: good runs produce files, bad input gets exit
//! status 2 and one clear line, never a panic or a half-written file. The endless world's
//! commands are in tests/cli_endless.rs, the benchmark and stability sweeps in
//! tests/cli_runs.rs.

use std::path::Path;

#[path = "common/cli.rs"]
mod cli_common;
use cli_common::*;

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
    let table = relief::cli_options::options_markdown();
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
