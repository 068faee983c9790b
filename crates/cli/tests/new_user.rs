//! What a new user hit trying relief from the README, each case the defect's own input: one
//! clear line and exit status 2 where the input is wrong (naming what the user wrote, where
//! they wrote it), the same answer whatever the method where the answer is about the view.
//! The error cases are a table: every failing case is reported, not only the first.

use std::path::{Path, PathBuf};
use std::process::Command;

fn relief(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_relief"))
        .args(args)
        .env_remove("XDG_RUNTIME_DIR")
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .env_remove("RUST_LOG")
        .output()
        .expect("run relief");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("relief-new-user-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn write(dir: &Path, name: &str, text: &str) -> String {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path.to_str().unwrap().to_owned()
}

/// A bad input: its arguments, words its one line must hold, and words it must not.
struct Case {
    args: Vec<String>,
    says: Vec<String>,
    not: Vec<String>,
}

fn case(args: &[&str], says: &[&str], not: &[&str]) -> Case {
    let owned = |v: &[&str]| v.iter().map(|a| a.to_string()).collect();
    Case {
        args: owned(args),
        says: owned(says),
        not: owned(not),
    }
}

/// Runs every case and fails with the list of those that did not answer as they should.
fn check_all(cases: &[Case]) {
    let mut failed = Vec::new();
    for c in cases {
        let args: Vec<&str> = c.args.iter().map(String::as_str).collect();
        let (code, stdout, err) = relief(&args);
        let mut why = Vec::new();
        if code != 2 {
            why.push(format!("exit {code}, not 2"));
        }
        if err.lines().count() != 1 {
            why.push(format!("{} lines on stderr", err.lines().count()));
        }
        if err.trim_end().chars().count() > 200 {
            why.push(format!("{} characters", err.trim_end().chars().count()));
        }
        if err.contains("panicked") {
            why.push("a panic".into());
        }
        if !stdout.is_empty() {
            why.push(format!("stdout not empty: {:?}", stdout.lines().next()));
        }
        for s in &c.says {
            if !err.contains(s.as_str()) {
                why.push(format!("does not say {s:?}"));
            }
        }
        for s in &c.not {
            if err.contains(s.as_str()) {
                why.push(format!("says {s:?}"));
            }
        }
        if !why.is_empty() {
            failed.push(format!("{args:?}: {} -- stderr: {err:?}", why.join("; ")));
        }
    }
    assert!(
        failed.is_empty(),
        "{} of {} cases failed:\n{}",
        failed.len(),
        cases.len(),
        failed.join("\n")
    );
}

#[test]
fn bad_inputs_get_one_line_naming_what_the_user_wrote() {
    let dir = scratch("bad");
    let out = dir.join("a.png");
    let out = out.to_str().unwrap();
    let octaves_float = write(&dir, "octaves.toml", "octaves = 3.0\n");
    let double_equals = write(&dir, "equals.toml", "seed = 7\nseed = = 7\n");
    let fly_on_tile = write(&dir, "fly.toml", "seed = 3\n[camera]\ncamera = \"fly\"\n");
    let tile_scene = write(&dir, "tile.toml", "seed = 3\n");
    let endless_scene = write(&dir, "endless.toml", "world = \"endless\"\nseed = 3\n");
    let same_point = write(
        &dir,
        "same.toml",
        "world = \"endless\"\n[camera]\neye = [0, 3000, 2]\nlook_at = [0, 3000, 2]\n",
    );
    // A path longer than the 40 characters messages used to keep, shorter than a line.
    let long_dir_path = dir.join("a-folder-name-that-is-rather-long");
    let long_path = long_dir_path.join("x.png");
    let (long, long_dir) = (long_path.to_str().unwrap(), long_dir_path.to_str().unwrap());
    let cases = [
        // 1: a scene "file" that never ends is read only to its limit.
        case(
            &["render", "--out", out, "--scene", "/dev/zero"],
            &["more than 1048576 bytes"],
            &[],
        ),
        case(
            &["render", "--out", out, "--scene", "/dev/urandom"],
            &["scene file /dev/urandom"],
            &[],
        ),
        // 4: the endless window refuses --region as the tile window does.
        case(
            &["--world", "endless", "--region", "0,0,1,1"],
            &["--region", "bake --world endless"],
            &[],
        ),
        // 5: an eye under the ground.
        case(
            &[
                "render",
                "--out",
                out,
                "--world",
                "endless",
                "--eye",
                "0,-500,0",
                "--look-at",
                "1000,-500,0",
            ],
            &["under the ground", "--eye"],
            &[],
        ),
        // 9: a region bake's --size alone has a region; a --region that does not fit says so
        // in a line that keeps its middle.
        case(
            &[
                "bake",
                "--world",
                "endless",
                "--size",
                "100",
                "--region",
                "0,0,4096,4096",
                "--out-dir",
                out,
            ],
            &["--region: 0,0,4096,4096", "power of two"],
            &[" ... "],
        ),
        // 10: errors from a scene file name the file's key, not a flag the user never gave.
        case(
            &["render", "--out", out, "--scene", &fly_on_tile],
            &[
                "fly.toml: [camera] camera fly",
                "does not apply to the tile world",
            ],
            &["--camera"],
        ),
        case(
            &[
                "render",
                "--out",
                out,
                "--world",
                "endless",
                "--scene",
                &tile_scene,
            ],
            &["tile.toml", "no world key", "--world endless was given"],
            &["(none)"],
        ),
        case(
            &[
                "render",
                "--out",
                out,
                "--world",
                "tile",
                "--scene",
                &endless_scene,
            ],
            &[
                "endless.toml",
                "world = \"endless\" here",
                "--world tile was given",
            ],
            &[],
        ),
        case(
            &["render", "--out", out, "--scene", &same_point],
            &[
                "same.toml: [camera] look_at",
                "is the [camera] eye position",
            ],
            &["--look-at", "--eye"],
        ),
        // 11: a TOML value of the wrong type in TOML's words, a syntax error with its place.
        case(
            &["render", "--out", out, "--scene", &octaves_float],
            &["invalid octaves: 3.0", "a whole number"],
            &["Float("],
        ),
        case(
            &["render", "--out", out, "--scene", &double_equals],
            &["TOML line 2, column 8"],
            &[" | "],
        ),
        // 12: one answer for --stats, and no tile width in a sun's refusal.
        case(
            &["bake", "--stats", "--out-dir", out],
            &["--stats", "relief render only"],
            &["window"],
        ),
        case(
            &["--world", "endless", "--stats"],
            &["--stats", "relief render only"],
            &[],
        ),
        case(
            &["render", "--out", out, "--sun-elevation", "5"],
            &["--world endless only"],
            &["2 units"],
        ),
        // 13: an output that cannot be written is refused before the work.
        case(
            &["bench", "--quick", "--out-dir", "/proc/relief-x"],
            &["/proc"],
            &[],
        ),
        case(
            &["stability", "--quick", "--out-dir", "/proc/relief-x"],
            &["/proc"],
            &[],
        ),
        case(&["render", "--out", "/proc/relief-x.png"], &["/proc"], &[]),
        case(
            &["render", "--out", &dir.to_string_lossy()],
            &["--out"],
            &[],
        ),
        // 14: a path is shown whole where the line has room.
        case(&["render", "--out", long], &[long_dir], &["..."]),
        // 15: a flag that takes no value, in relief's words.
        case(
            &["render", "--out", out, "--no-water=1"],
            &["--no-water takes no value"],
            &["unexpected"],
        ),
    ];
    check_all(&cases);
    assert!(
        !Path::new(out).exists(),
        "a refused command wrote its image"
    );
}

#[test]
fn a_region_bake_takes_its_size_alone() {
    // 9: `--size 100` without --region bakes 100 samples every 4 m.
    let dir = scratch("region");
    let (code, stdout, err) = relief(&[
        "bake",
        "--world",
        "endless",
        "--size",
        "100",
        "--out-dir",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(stdout.contains("0,0,400,400"), "{stdout}");
    let scene = std::fs::read_to_string(dir.join("scene.toml")).unwrap();
    assert!(scene.contains("world = \"endless\""), "{scene}");
}

/// `relief render --stats`' `texels_baked` for a still view.
fn texels_baked(args: &[&str]) -> (String, String) {
    let dir = scratch("stats");
    let out = dir.join("s.png");
    let mut all = vec!["render", "--out", out.to_str().unwrap(), "--stats"];
    all.extend_from_slice(args);
    let (code, stdout, err) = relief(&all);
    assert_eq!(code, 0, "{args:?}: {err}");
    let line = stdout
        .lines()
        .find(|l| l.starts_with("texels_baked "))
        .unwrap_or_else(|| panic!("{args:?}: no texels_baked in {stdout}"));
    (line.to_owned(), stdout)
}

#[test]
fn a_still_view_reports_the_same_bake_whatever_the_method() {
    // 6: the still frame's bake is the levels' texels for the view, not what the last of
    // several passes (or auto's trial frames) happened to bake.
    let endless = ["--world", "endless", "--width", "64", "--height", "36"];
    let tile = [
        "--width", "64", "--height", "48", "--size", "64", "--grid", "32",
    ];
    let both = ["mesh", "visibility", "auto"];
    let endless_only = ["mesh", "visibility", "hybrid", "auto"];
    for (world, base, methods) in [
        ("endless", &endless[..], &endless_only[..]),
        ("tile", &tile[..], &both[..]),
    ] {
        let mut seen = Vec::new();
        for &method in methods {
            let mut args = base.to_vec();
            args.extend_from_slice(&["--method", method]);
            let (line, _) = texels_baked(&args);
            seen.push((method, line));
        }
        let first = &seen[0].1;
        assert!(first != "texels_baked 0", "{world}: {seen:?}");
        assert!(seen.iter().all(|(_, l)| l == first), "{world}: {seen:?}");
    }
}

#[test]
fn timings_on_a_software_device_say_so() {
    // 19: lavapipe's timestamps are the CPU's.
    let dir = scratch("timings");
    let out = dir.join("t.png");
    let (code, stdout, err) = relief(&[
        "render",
        "--out",
        out.to_str().unwrap(),
        "--width",
        "32",
        "--height",
        "32",
        "--method",
        "mesh",
        "--timings",
    ]);
    assert_eq!(code, 0, "{err}");
    let line = stdout
        .lines()
        .find(|l| l.starts_with("timings"))
        .unwrap_or_default();
    assert!(
        line.contains("a software device: its timings are the CPU's"),
        "{stdout}"
    );
}

#[test]
fn each_commands_help_lists_the_flags_it_takes_and_refuses_those_it_leaves_out() {
    // 16: `render --help` once listed --speed, --paused, --region and --exit-after.
    let (code, help, _) = relief(&["render", "--help"]);
    assert_eq!(code, 0);
    // A flag's own line in a help text (its mention in another's doc does not count).
    let lists = |help: &str, flag: &str| {
        help.lines()
            .any(|l| l.trim_start().starts_with(&format!("{flag} ")))
    };
    for shown in ["--out", "--seed", "--method", "--eye", "--stats"] {
        assert!(lists(&help, shown), "render --help lacks {shown}:\n{help}");
    }
    for hidden in ["--speed", "--paused", "--region", "--exit-after"] {
        assert!(
            !lists(&help, hidden),
            "render --help lists {hidden}:\n{help}"
        );
    }
    let (_, bake, _) = relief(&["bake", "--help"]);
    assert!(
        lists(&bake, "--region") && !lists(&bake, "--method"),
        "{bake}"
    );
    // What a command's help leaves out, the command refuses (in words, exit 2), so the help
    // and the refusals cannot drift apart.
    let cmd = relief_cli::command();
    let mut failed = Vec::new();
    for name in relief_cli::COMMANDS {
        let required: &[&str] = match name {
            "render" => &["--out", "x.png"],
            "bake" | "bench" | "stability" => &["--out-dir", "/proc/relief-never"],
            "height" => &["0,0"],
            _ => &[],
        };
        for id in relief_cli::refused_by(name) {
            let Some(arg) = cmd.get_arguments().find(|a| a.get_id() == id) else {
                failed.push(format!("{name}: no flag {id}"));
                continue;
            };
            let flag = format!("--{}", arg.get_long().unwrap_or(id));
            let mut args = vec![name, flag.as_str()];
            if arg.get_action().takes_values() {
                args.push(if id == "world" { "endless" } else { "1" });
            }
            args.extend_from_slice(required);
            if name == "window" {
                // A window refusal comes before any window opens; anything else must not
                // get that far here (no display).
                args.remove(0);
            }
            let (code, _, err) = relief(&args);
            if code != 2 || err.lines().count() != 1 || !err.contains(&flag) {
                failed.push(format!("{args:?}: exit {code}, {err:?}"));
            }
        }
    }
    assert!(failed.is_empty(), "{}", failed.join("\n"));
}

#[test]
fn the_readmes_height_example_shows_the_terrain() {
    // 18: the README once suggested lattice points, where every octave's noise is 0 and each
    // height the same 0.25.
    let readme =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../README.md")).unwrap();
    let line = readme
        .lines()
        .find(|l| l.trim_start().starts_with("relief height "))
        .expect("the README's height example");
    let args: Vec<&str> = line
        .split('#')
        .next()
        .unwrap()
        .split_whitespace()
        .skip(1)
        .collect();
    let (code, stdout, err) = relief(&args);
    assert_eq!(code, 0, "{args:?}: {err}");
    let heights: Vec<f64> = stdout.lines().map(|l| l.parse().unwrap()).collect();
    assert!(heights.len() >= 2, "{stdout}");
    assert!(
        heights.iter().all(|h| (h - 0.25).abs() > 1e-3) && heights[0] != heights[1],
        "{args:?}: {heights:?}"
    );
}
