//! The docs' commands: every `relief` command in README.md, docs/ and docs/results/ is still
//! accepted by the program's own resolution of its arguments (`relief_cli::check_args`).

use std::path::Path;

#[path = "common/cli.rs"]
mod cli_common;
use cli_common::*;

/// Every command the docs show is still accepted: each line of a fenced block in README.md,
/// docs/ and docs/results/ that runs `relief` or `cargo run --release`, and each inline one that
/// names its output or opens the window with flags, its placeholders (`FILE.png`, `DIR`, `N`,
/// `M`: the visibility method, which takes `--samples`, ...) filled in. Checked through
/// `relief_cli::check_args`, the program's own resolution of its arguments, which runs nothing.
#[test]
fn every_command_the_docs_show_is_accepted() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let dir = scratch("docs-commands");
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, "seed = 3\n").unwrap();
    let mut files = vec![root.join("README.md")];
    for sub in ["docs", "docs/results"] {
        let mut pages: Vec<_> = std::fs::read_dir(root.join(sub))
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|x| x == "md"))
            .collect();
        pages.sort();
        files.extend(pages);
    }
    let mut commands = Vec::new();
    for file in &files {
        let text = std::fs::read_to_string(file).unwrap();
        let name = file.strip_prefix(&root).unwrap().display().to_string();
        // Fenced lines are commands as they stand; the prose around them is gathered in
        // paragraphs, whose inline code may run over a line break.
        let mut fenced = false;
        let mut paragraph: Vec<(usize, &str)> = Vec::new();
        let mut paragraphs = Vec::new();
        for (i, line) in text.lines().enumerate() {
            if line.trim_start().starts_with("```") {
                fenced = !fenced;
                paragraphs.push(std::mem::take(&mut paragraph));
                continue;
            }
            if fenced {
                let line = line.trim().trim_start_matches("$ ");
                if runs_relief(line) {
                    commands.push((format!("{name}:{}", i + 1), line.to_owned()));
                }
            } else if line.trim().is_empty() {
                paragraphs.push(std::mem::take(&mut paragraph));
            } else {
                paragraph.push((i + 1, line));
            }
        }
        paragraphs.push(paragraph);
        for lines in paragraphs.iter().filter(|p| !p.is_empty()) {
            let joined: Vec<&str> = lines.iter().map(|(_, l)| *l).collect();
            let joined = joined.join(" ");
            let first = lines[0].0;
            for span in joined.split('`').skip(1).step_by(2) {
                // A command shown whole: one naming its output, or the window's.
                let complete = span.contains("--out")
                    || span.starts_with("relief --")
                    || span.starts_with("relief window")
                    || span.starts_with("cargo run --release -- --");
                if runs_relief(span) && complete {
                    commands.push((format!("{name}:{first}+"), span.to_owned()));
                }
            }
        }
    }
    assert!(
        commands.len() >= 20,
        "only {} commands found",
        commands.len()
    );
    eprintln!("{} documented commands", commands.len());
    // The check refuses what the program refuses (the controls): a render without its output,
    // a window-only flag elsewhere, a tile-only flag in the endless world.
    for refused in [
        &["relief", "render"][..],
        &["relief", "bench", "--method", "mesh"],
        &[
            "relief", "render", "--out", "x.png", "--world", "endless", "--grid", "64",
        ],
    ] {
        let args = refused.iter().map(std::ffi::OsString::from);
        assert!(relief_cli::check_args(args).is_err(), "{refused:?} passed");
    }
    let faults: Vec<String> = commands
        .iter()
        .filter_map(|(at, command)| {
            let mut args = documented_args(command, &dir, &scene);
            // A scene file the repository ships is named from its root, as a user runs it.
            for i in 1..args.len() {
                if args[i - 1] == "--scene" && root.join(&args[i]).is_file() {
                    args[i] = root.join(&args[i]).display().to_string();
                }
            }
            relief_cli::check_args(args.iter().map(std::ffi::OsString::from))
                .err()
                .map(|e| format!("{at}: {command}\n    as {args:?}\n    {e}"))
        })
        .collect();
    assert!(
        faults.is_empty(),
        "{} of {} commands in the docs are refused:\n{}",
        faults.len(),
        commands.len(),
        faults.join("\n")
    );
}

/// Whether a line of the docs runs the program: `relief` then a subcommand, a flag or `[`, or
/// `cargo run --release` alone or with arguments after `--`.
fn runs_relief(line: &str) -> bool {
    let mut words = line.split_whitespace();
    match (words.next(), words.next(), words.next()) {
        (Some("relief"), None, _) => true,
        (Some("relief"), Some(w), _) => {
            relief_cli::COMMANDS.contains(&w) || w.starts_with('-') || w.starts_with('[')
        }
        (Some("cargo"), Some("run"), Some("--release")) => {
            let rest: Vec<&str> = words.collect();
            rest.is_empty() || rest[0] == "--" || rest[0].starts_with('#')
        }
        _ => false,
    }
}

/// A documented command as the program's arguments: the comment dropped, optional parts
/// (`[--quick]`) given, `[OPTIONS]` left out, and each placeholder filled in by its flag.
fn documented_args(command: &str, dir: &Path, scene: &Path) -> Vec<String> {
    let command = command.split(" #").next().unwrap();
    let rest = match command.strip_prefix("cargo run --release") {
        Some(cargo) => cargo.trim().trim_start_matches("--"),
        None => command.trim_start_matches("relief"),
    };
    let path = |name: &str| dir.join(name).display().to_string();
    let mut args = vec!["relief".to_owned()];
    for word in rest.split_whitespace() {
        if word == "[OPTIONS]" {
            continue;
        }
        let word = word.trim_start_matches('[').trim_end_matches(']');
        let placeholder = matches!(
            word,
            "FILE.png" | "FILE" | "DIR" | "N" | "W" | "H" | "M" | "T" | "DEG" | "X,Y,Z"
        ) || word == "X0,Z0,X1,Z1"
            || word == "NAME,...";
        if !placeholder {
            args.push(word.to_owned());
            continue;
        }
        let flag = args.last().map(String::as_str).unwrap_or("");
        let value = match flag {
            "--out" => path("out.png"),
            "--out-dir" => path("out"),
            "--scene" => scene.display().to_string(),
            "--size" => "1024".into(),
            "--samples" => "1".into(),
            "--width" => "64".into(),
            "--height" => "36".into(),
            "--method" => "visibility".into(),
            "--time" => "3".into(),
            "--eye" => "0,2600,0".into(),
            "--look-at" => "1000,2000,0".into(),
            "--fov" => "50".into(),
            "--axis" => "storage,scroll".into(),
            "--region" => "0,0,4096,4096".into(),
            _ => panic!("no value for the placeholder {word} after {flag:?} in {command}"),
        };
        args.push(value);
    }
    args
}
