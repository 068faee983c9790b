//! Helpers shared by the tests of the `relief` program (tests/cli*.rs): run it as a user
//! would, make scratch folders, check a refusal, read its CSV, stats and SVG charts.
#![allow(dead_code, reason = "each test binary uses a different subset")]

use std::path::{Path, PathBuf};
use std::process::Command;

/// Runs relief as a user on a bare machine would: no XDG_RUNTIME_DIR (Mesa complains without
/// one; relief must keep stderr clean anyway) and no display.
pub fn relief(args: &[&str]) -> (i32, String, String) {
    relief_env(args, &[])
}

pub fn relief_env(args: &[&str], env: &[(&str, &str)]) -> (i32, String, String) {
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

pub fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("relief-cli-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

pub fn files_in(dir: &Path) -> Vec<String> {
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
pub fn rejects(args: &[&str], needles: &[&str]) {
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

pub fn svg_attr(tag: &str, name: &str) -> Option<f64> {
    let start = tag.find(&format!(" {name}=\""))? + name.len() + 3;
    tag[start..].split('"').next()?.parse().ok()
}

/// Where the SVG's text starting with `prefix` is anchored, and the text.
pub fn svg_text(svg: &str, prefix: &str) -> Option<((f64, f64), String)> {
    svg.split("<text").skip(1).find_map(|t| {
        let body = t.split('>').nth(1)?.trim_start();
        let body = body.split('<').next()?.trim_end();
        body.starts_with(prefix)
            .then(|| Some(((svg_attr(t, "x")?, svg_attr(t, "y")?), body.to_string())))?
    })
}

/// The centre of the first SVG circle of radius `r`.
pub fn svg_circle_position(svg: &str, r: f64) -> Option<(f64, f64)> {
    svg.split("<circle").skip(1).find_map(|t| {
        (svg_attr(t, "r")? == r).then(|| Some((svg_attr(t, "cx")?, svg_attr(t, "cy")?)))?
    })
}

/// Splits one CSV line, honouring double quotes (device names contain commas).
pub fn csv_fields(line: &str) -> Vec<String> {
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

/// The `key value` lines of `--stats` whose value is a number.
pub fn stats_of(stdout: &str) -> Vec<(String, f64)> {
    stdout
        .lines()
        .filter_map(|l| {
            let (k, v) = l.split_once(' ')?;
            Some((k.to_owned(), v.parse().ok()?))
        })
        .collect()
}

pub fn stat(stats: &[(String, f64)], key: &str) -> f64 {
    stats
        .iter()
        .find(|(k, _)| k == key)
        .unwrap_or_else(|| panic!("no {key} in {stats:?}"))
        .1
}
