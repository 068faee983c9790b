//! `relief render --frames N` (the temporal service accumulating a still view) and
//! `relief bench --world endless --only PART`, and their refusals.

#[path = "common/cli.rs"]
mod cli_common;
use cli_common::*;

/// The visibility method as a fast GPU draws it.
const VISIBILITY: [&str; 6] = [
    "--method",
    "visibility",
    "--samples",
    "1",
    "--raster",
    "compute",
];

/// Renders the endless world small with the visibility method as a fast GPU draws it; returns
/// the PNG's bytes and the `--stats` lines.
fn render(name: &str, extra: &[&str]) -> (Vec<u8>, Vec<(String, f64)>, String) {
    render_as(name, &VISIBILITY, extra)
}

/// Renders the endless world small drawn as `method` says.
fn render_as(name: &str, method: &[&str], extra: &[&str]) -> (Vec<u8>, Vec<(String, f64)>, String) {
    let dir = scratch("temporal");
    let out = dir.join(format!("{name}.png"));
    let mut args = vec!["render", "--world", "endless"];
    args.extend_from_slice(method);
    args.extend_from_slice(&[
        "--width",
        "96",
        "--height",
        "54",
        "--pixel-error",
        "16",
        "--stats",
        "--out",
        out.to_str().unwrap(),
    ]);
    args.extend_from_slice(extra);
    let (code, stdout, err) = relief(&args);
    assert_eq!(code, 0, "{extra:?}: {err}");
    (std::fs::read(&out).unwrap(), stats_of(&stdout), stdout)
}

#[test]
fn frames_accumulates_and_one_frame_is_the_frame_without_it() {
    let (plain, stats, stdout) = render("plain", &[]);
    let (one, _, _) = render("one", &["--frames", "1"]);
    let (four, four_stats, four_out) = render("four", &["--frames", "4"]);
    assert!(
        plain == one,
        "--frames 1 is the frame without the service, byte for byte"
    );
    assert!(plain != four, "four jittered frames differ from one");
    assert!(!stdout.contains("history"), "{stdout}");
    assert_eq!(stat(&four_stats, "history_frames"), 4.0, "{four_out}");
    assert!(stat(&four_stats, "method_texture_mib") > stat(&stats, "method_texture_mib"));
}

#[test]
fn frames_and_only_are_refused_where_they_do_nothing() {
    let r = Rejections::default();
    let out = scratch("temporal-refused").join("x.png");
    let out = out.to_str().unwrap();
    r.check(
        &[
            "render", "--world", "endless", "--frames", "0", "--out", out,
        ],
        &["--frames", "0"],
    );
    r.check(
        &[
            "render", "--world", "endless", "--frames", "many", "--out", out,
        ],
        &["--frames", "many"],
    );
    r.check(
        &["render", "--frames", "4", "--out", out],
        &["--frames 4", "endless"],
    );
    r.check(&["--frames", "4"], &["frames", "render"]);
    r.check(&["bench", "--only", "temporal"], &["--only", "endless"]);
    r.check(
        &["bench", "--world", "endless", "--only", "everything"],
        &["--only", "everything", "temporal"],
    );
    // A ray caster keeps no history: refused once the frame's method is known, in words.
    let (code, _, err) = relief(&[
        "render", "--world", "endless", "--method", "raymarch", "--frames", "4", "--width", "32",
        "--height", "18", "--out", out,
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("--frames 4") && err.contains("raymarch") && !err.contains("  "),
        "{err}"
    );
    assert!(!std::path::Path::new(out).exists());
}

#[test]
fn the_forward_mesh_accumulates_its_frames_too() {
    let mesh = ["--method", "mesh"];
    let (plain, stats, _) = render_as("mesh-plain", &mesh, &[]);
    let (four, four_stats, four_out) = render_as("mesh-four", &mesh, &["--frames", "4"]);
    assert!(plain != four, "four jittered frames differ from one");
    assert_eq!(stat(&four_stats, "history_frames"), 4.0, "{four_out}");
    assert_eq!(stat(&stats, "method_texture_mib"), 0.0);
    assert!(stat(&four_stats, "method_texture_mib") > 0.0, "{four_out}");
}

#[test]
#[ignore = "slow: a still view accumulated and reference casts on a software GPU (.ci/test runs it)"]
fn bench_measures_the_views_it_is_given_and_refuses_others() {
    // The reference's ladder and a still view's convergence on the views named, and nothing
    // else (no cost, no motion).
    let dir = scratch("bench-views");
    let (code, stdout, err) = relief(&[
        "bench",
        "--world",
        "endless",
        "--quick",
        "--only",
        "reference",
        "--view",
        "random-3,horizon",
        "--out-dir",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let csv = std::fs::read_to_string(dir.join("reference.csv")).unwrap();
    let rows: Vec<&str> = csv.lines().skip(2).collect();
    assert_eq!(rows.len(), 2, "{csv}");
    assert!(rows[0].starts_with("random-3,4,8,"), "{csv}");
    assert!(rows[1].starts_with("horizon,4,8,"), "{csv}");
    assert!(stdout.contains("2 rows"), "{stdout}");
    let (code, _, err) = relief(&[
        "bench",
        "--world",
        "endless",
        "--quick",
        "--only",
        "temporal",
        "--view",
        "random-16",
        "--out-dir",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let csv = std::fs::read_to_string(dir.join("temporal.csv")).unwrap();
    let views: Vec<&str> = csv
        .lines()
        .skip(2)
        .filter_map(|l| l.split(',').next())
        .collect();
    assert_eq!(views, ["random-16"], "{csv}");
    let moving = std::fs::read_to_string(dir.join("temporal-moving.csv")).unwrap();
    assert_eq!(moving.lines().count(), 2, "{moving}");
    // An unknown view, a view for a part that has none, and the tile's benchmark.
    let r = Rejections::default();
    r.check(
        &[
            "bench",
            "--world",
            "endless",
            "--only",
            "temporal",
            "--view",
            "random-17",
        ],
        &["--view", "random-17", "horizon", "random-16"],
    );
    r.check(
        &[
            "bench", "--world", "endless", "--only", "look", "--view", "ridge",
        ],
        &["--view", "--only temporal"],
    );
    r.check(&["bench", "--view", "ridge"], &["--view", "endless"]);
}

#[test]
#[ignore = "slow: a meadow drawn with grass and without, two ways, three views, on a software GPU (.ci/test runs it)"]
fn bench_measures_the_grass_on_its_views() {
    let dir = scratch("bench-grass");
    let (code, stdout, err) = relief(&[
        "bench",
        "--world",
        "endless",
        "--quick",
        "--only",
        "grass",
        "--out-dir",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let csv = std::fs::read_to_string(dir.join("grass.csv")).unwrap();
    let rows: Vec<Vec<&str>> = csv
        .lines()
        .skip(2)
        .map(|l| l.split(',').collect())
        .collect();
    let views: Vec<&str> = rows.iter().map(|r| r[0]).collect();
    assert_eq!(
        views,
        [
            "meadow",
            "meadow",
            "meadow-10m",
            "meadow-10m",
            "flight-50m",
            "flight-50m"
        ],
        "{csv}"
    );
    // On the meadow every method draws blades; each row has both frames' times.
    for r in &rows[..4] {
        let drawn: u32 = r[3].parse().unwrap();
        let considered: u32 = r[2].parse().unwrap();
        assert!(drawn > 100 && considered > drawn, "{csv}");
        assert!(
            r[4].parse::<f64>().is_ok() && r[5].parse::<f64>().is_ok(),
            "{csv}"
        );
    }
    assert!(
        stdout.contains("6 rows") && stdout.contains("blades drawn of"),
        "{stdout}"
    );
}
