//! The `relief` program as a user meets it: good runs produce files, bad input gets exit
//! status 2 and one clear line, never a panic or a half-written file.

use std::path::{Path, PathBuf};
use std::process::Command;

fn relief(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_relief"))
        .args(args)
        .output()
        .expect("run relief");
    let stderr = String::from_utf8_lossy(&out.stderr)
        .lines()
        // Mesa's software Vulkan prints this on machines without a session bus; not ours.
        .filter(|l| !l.contains("XDG_RUNTIME_DIR"))
        .collect::<Vec<_>>()
        .join("\n");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        stderr,
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

/// Runs a bad command and checks: status 2, exactly one line, mentioning every `needles`.
fn rejects(args: &[&str], needles: &[&str]) {
    let (code, _, err) = relief(args);
    assert_eq!(code, 2, "{args:?} should exit 2; stderr: {err}");
    assert_eq!(
        err.lines().count(),
        1,
        "{args:?} should print one line, got:\n{err}"
    );
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
    let cases: &[(&[&str], &[&str])] = &[
        (&["--size", "0"], &["size", "0", "1..=16384"]),
        (&["--size", "99999"], &["size", "99999", "1..=16384"]),
        (&["--size", "-4"], &["size", "-4"]),
        (&["--size", "big"], &["size", "big"]),
        (&["--grid", "1"], &["grid", "1", "2..=4096"]),
        (&["--octaves", "0"], &["octaves", "0", "1..=16"]),
        (&["--octaves", "1000"], &["octaves", "1000", "1..=16"]),
        (
            &["--octaves", "16", "--frequency", "8"],
            &["octaves", "16", "at most 14"],
        ),
        (&["--frequency", "0"], &["frequency", "0", "1..=1024"]),
        (&["--gain", "nan"], &["gain", "NaN", "0..=1"]),
        (&["--gain", "inf"], &["gain", "inf", "0..=1"]),
        (&["--gain", "-0.5"], &["gain", "-0.5", "0..=1"]),
        (&["--height-scale", "-1"], &["height-scale", "-1", "0..=10"]),
        (&["--snow-height", "1.5"], &["snow-height", "1.5", "0..=1"]),
        (&["--ao-exponent", "NaN"], &["ao-exponent", "NaN"]),
        (&["--offset", "nan,0"], &["offset", "NaN"]),
        (&["--offset", "1"], &["offset", "X,Y"]),
        (&["--seed", "-1"], &["seed", "-1"]),
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
        &["gain", "7.5", "0..=1"],
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
    rejects(&["render", "--out", o, "--width", "0"], &["width", "0"]);
    rejects(&["render", "--bogus"], &["--bogus"]);
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
    assert!(
        stdout.starts_with("timings"),
        "--timings printed nothing: {stdout:?}"
    );
    assert!(
        stdout.contains("render") || stdout.contains("no timestamp queries"),
        "{stdout}"
    );
    assert_eq!(files_in(&dir), ["frame.png"]);
}

#[test]
fn bench_quick_writes_a_csv_and_a_chart() {
    let dir = scratch("bench");
    let (code, stdout, err) = relief(&["bench", "--quick", "--out-dir", dir.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
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
    assert_eq!(
        lines.len(),
        1 + 7,
        "seven configurations in the quick sweep"
    );
    let rows: Vec<Vec<String>> = lines[1..].iter().map(|l| csv_fields(l)).collect();
    for row in &rows {
        assert_eq!(row.len(), header.len(), "{row:?}");
    }
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let methods: Vec<&str> = rows.iter().map(|r| r[col("method")].as_str()).collect();
    for m in ["mesh", "raymarch-fragment", "raymarch-compute"] {
        assert!(methods.contains(&m), "no {m} row");
    }
    for row in &rows {
        let flip: f64 = row[col("flip_mean")].parse().unwrap();
        assert!(flip > 0.0 && flip < 0.5, "FLIP mean {flip} in {row:?}");
    }
    let png = image::open(dir.join("bench.png")).unwrap();
    assert_eq!((png.width(), png.height()), (960, 640));
    let svg = std::fs::read_to_string(dir.join("bench.svg")).unwrap();
    assert!(svg.contains("<svg") && svg.contains("Pareto front") && svg.contains("default"));
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
