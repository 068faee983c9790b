//! The `relief` program as a user meets it: good runs produce files, bad input gets exit
//! status 2 and one clear line, never a panic or a half-written file. The endless world's
//! commands are in tests/cli_endless.rs, `relief render`'s frames in tests/cli_render.rs, the
//! benchmark and stability sweeps in tests/cli_runs.rs, the docs' commands in tests/docs.rs.

use relief_cli::scene::SceneFile;
use std::path::Path;

#[path = "common/cli.rs"]
mod cli_common;
use cli_common::*;

#[test]
fn bad_parameters_exit_2_with_one_line() {
    let refused = Rejections::default();
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
        refused.check(&full, needles);
        let mut bake = vec!["bake", "--out-dir", dir.to_str().unwrap()];
        bake.extend_from_slice(args);
        refused.check(&bake, needles);
    }
    assert!(
        files_in(&dir).is_empty(),
        "bad input left files: {:?}",
        files_in(&dir)
    );
}

#[test]
fn bad_scene_files_and_outputs_exit_2() {
    let refused = Rejections::default();
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
    refused.check(
        &["render", "--out", o, "--scene", &scene(&unknown)],
        &["unknown.toml", "colour"],
    );
    refused.check(
        &["render", "--out", o, "--scene", &scene(&wrong)],
        &["wrong.toml", "octaves"],
    );
    refused.check(
        &["render", "--out", o, "--scene", &scene(&range)],
        &["range.toml", "gain", "7.5", "0..=1"],
    );
    refused.check(
        &["render", "--out", o, "--scene", &scene(&broken)],
        &["broken.toml"],
    );
    refused.check(
        &["render", "--out", o, "--scene", "/nonexistent/scene.toml"],
        &["/nonexistent/scene.toml"],
    );
    refused.check(
        &["render", "--out", "/nonexistent/dir/o.png"],
        &["/nonexistent/dir"],
    );
    refused.check(
        &["render", "--out", &format!("{}/o.jpg", dir.display())],
        &["out", ".png"],
    );
    refused.check(
        &["render", "--out", o, "--width", "0"],
        &["--width", "0", "1..=16384"],
    );
    refused.check(
        &["render", "--out", o, "--width", "-5"],
        &["--width", "-5", "1..=16384"],
    );
    refused.check(
        &["render", "--out", o, "--width", "99999999999"],
        &["--width", "99999999999", "1..=16384"],
    );
    refused.check(
        &["render", "--out", o, "--height", "1.5"],
        &["--height", "1.5"],
    );
    refused.check(&["render", "--bogus"], &["--bogus"]);
    refused.check(&["render"], &["--out"]);
    refused.check(&["bake"], &["--out-dir"]);
    refused.check(&["frobnicate"], &["frobnicate", "render"]);
    refused.check(&["bench", "--size", "64"], &["--size", "bench"]);
    refused.check(&["bench", "--normals", "analytic"], &["--normals", "bench"]);
    refused.check(&["bench", "--timings"], &["--timings", "bench"]);
    // An existing file given as the output folder.
    let file = dir.join("a-file");
    std::fs::write(&file, "x").unwrap();
    refused.check(
        &["bake", "--out-dir", file.to_str().unwrap()],
        &["--out-dir", "a-file", "folder"],
    );
    // A refused bake creates no folder (one was once left behind, empty).
    let fresh = dir.join("fresh");
    refused.check(
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
        refused.check(
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
    refused.check(
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
        let want = relief_cli::albedo_srgb8(&shading, c);
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
fn the_cli_page_lists_every_option_as_the_code_has_it() {
    let page =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/cli.md")).unwrap();
    let table = relief_cli::options::options_markdown();
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
    // The CLI reads each point as f32 and prints the height as f32.
    let want: Vec<f32> = [(0.1f32, 0.2f32), (-0.3, 0.7), (-5.0, -3.25)]
        .iter()
        .map(|&(x, z)| relief::height_at(&params, f64::from(x), f64::from(z)) as f32)
        .collect();
    assert_eq!(got, want, "{stdout}");
    rejects(&["height", "1,x"], &["point", "1,x", "X,Z"]);
    rejects(&["height"], &["X,Z"]);
    rejects(&["height", "--size", "64", "0,0"], &["--size", "height"]);
}

/// `--method`, `--samples` and `--raster` reach `relief render` and the window; the other
/// commands refuse them in words, and the window refuses a method its world does not draw
/// (before any window opens).
#[test]
fn method_samples_and_raster_reach_render_and_the_window_only() {
    let refused = Rejections::default();
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
        refused.check(args, &[flag, "render and the window only"]);
    }
    refused.check(
        &["--world", "endless", "--method", "blog"],
        &["--method blog", "tile"],
    );
    refused.check(&["--method", "hybrid"], &["--method hybrid", "endless"]);
    // The window's default is the mesh, which takes no samples.
    refused.check(
        &["--samples", "1"],
        &["--samples", "visibility and hybrid", "mesh"],
    );
    refused.check(
        &["window", "--method", "mesh", "--raster", "compute"],
        &["--raster", "visibility and hybrid only", "mesh"],
    );
    // The compute raster draws one sample a pixel: refused at the default 4, in the window as
    // in render.
    refused.check(
        &["--method", "visibility", "--raster", "compute"],
        &["--raster", "--samples 1"],
    );
    refused.check(
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

#[test]
fn the_refusal_check_reports_every_input_that_was_not_refused() {
    // A good command is a fault to `rejection`, and a wrong needle too, each in words.
    let ran = rejection(&["height", "0.1,0.2"], &[]);
    assert!(
        ran.as_deref().is_some_and(|f| f.contains("should exit 2")),
        "{ran:?}"
    );
    let unsaid = rejection(&["height", "1,x"], &["no such words"]);
    assert!(
        unsaid
            .as_deref()
            .is_some_and(|f| f.contains("no such words")),
        "{unsaid:?}"
    );
    // A table with two faults reports both when it is dropped.
    let table = std::panic::catch_unwind(|| {
        let refused = Rejections::default();
        refused.check(&["height", "0.1,0.2"], &[]);
        refused.check(&["height", "1,x"], &["point"]);
        refused.check(&["height", "1,x"], &["no such words"]);
    });
    let message = table.expect_err("the faults are reported");
    let message = message
        .downcast_ref::<String>()
        .cloned()
        .unwrap_or_default();
    assert!(message.starts_with("2 of 3 bad inputs"), "{message}");
}
