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
/// says what is allowed at most once, mentioning every `needles`. Panics on the first fault;
/// a table of cases goes through [`Rejections`], which reports every one.
#[allow(dead_code)] // not every test file that includes this refuses input one case at a time
pub fn rejects(args: &[&str], needles: &[&str]) {
    if let Some(fault) = rejection(args, needles) {
        panic!("{fault}");
    }
}

/// What is wrong with how `relief args` refused its input, if anything.
pub fn rejection(args: &[&str], needles: &[&str]) -> Option<String> {
    let (code, _, err) = relief(args);
    let shown: Vec<String> = args.iter().map(|a| a.chars().take(60).collect()).collect();
    let args = &shown;
    if code != 2 {
        return Some(format!(
            "{args:?} should exit 2, exited {code}; stderr: {err}"
        ));
    }
    if err.lines().count() != 1 {
        return Some(format!("{args:?} should print one line, got:\n{err}"));
    }
    if err.chars().count() > 201 {
        let head: String = err.chars().take(300).collect();
        return Some(format!(
            "{args:?}: {} characters: {head}",
            err.chars().count()
        ));
    }
    if err.matches("allowed").count() > 1 {
        return Some(format!("{args:?} says what is allowed twice: {err}"));
    }
    if err.contains("panicked") {
        return Some(format!("{args:?} panicked: {err}"));
    }
    let missing: Vec<&&str> = needles.iter().filter(|n| !err.contains(**n)).collect();
    (!missing.is_empty()).then(|| format!("{args:?}: {err:?} should mention {missing:?}"))
}

/// A table of bad inputs: each [`Rejections::check`] runs one and keeps its fault; when the
/// table is dropped, every fault is reported at once (not only the first).
#[derive(Default)]
pub struct Rejections {
    faults: std::cell::RefCell<Vec<String>>,
    checked: std::cell::Cell<usize>,
}

impl Rejections {
    /// Runs `relief args` and keeps what is wrong with its refusal ([`rejection`]).
    pub fn check(&self, args: &[&str], needles: &[&str]) {
        self.checked.set(self.checked.get() + 1);
        self.faults.borrow_mut().extend(rejection(args, needles));
    }
}

impl Drop for Rejections {
    fn drop(&mut self) {
        let faults = self.faults.get_mut();
        if !faults.is_empty() && !std::thread::panicking() {
            panic!(
                "{} of {} bad inputs were not refused as they should be:\n{}",
                faults.len(),
                self.checked.get(),
                faults.join("\n")
            );
        }
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
