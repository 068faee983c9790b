//! The `relief` program's props: every bad prop scene refused in one line, the shipped scenes
//! drawing their props. (Their rows through flags and scene files are in cli_endless.rs.)

use std::path::Path;

#[path = "common/cli.rs"]
mod cli_common;
use cli_common::*;

#[test]
fn bad_props_exit_2_with_one_line_naming_the_key() {
    let refused = Rejections::default();
    let dir = scratch("bad-props");
    let out = dir.join("x.png");
    let out = out.to_str().unwrap();
    // A ray cast, which marches no props.
    refused.check(
        &[
            "render", "--world", "endless", "--props", "--method", "raymarch", "--out", out,
        ],
        &["--props", "casts rays", "mesh"],
    );
    refused.check(
        &[
            "render",
            "--world",
            "endless",
            "--props-density",
            "2",
            "--out",
            out,
        ],
        &["--props-density", "2", "1"],
    );
    let kind = |root: &str| {
        format!("world = \"endless\"\nprops = true\n[prop_kinds.rock]\nroot = {root}\n")
    };
    let mut deep = "{ sphere = { radius = 1.0 } }".to_owned();
    for _ in 0..33 {
        deep =
            format!("{{ union = true, children = [{deep}, {{ sphere = {{ radius = 1.0 }} }}] }}");
    }
    let cases: Vec<(String, Vec<&str>)> = vec![
        (kind(&deep), vec!["prop_kinds.rock", "deeper than 32"]),
        (kind("{ sphere = { radius = 0.0 } }"), vec!["sphere.radius", "0", "> 0"]),
        (kind("{ sphere = { radius = -1.0 } }"), vec!["sphere.radius", "-1"]),
        (kind("{ box = { size = [1, 1, 1] }, scale = 0 }"), vec!["scale", "0", "> 0"]),
        (
            kind("{ box = { size = [1, 1, 1] }, scale = [1, nan, 1] }"),
            vec!["scale", "NaN"],
        ),
        (
            kind("{ smooth_union = 0.0, children = [{ sphere = { radius = 1 } }, { sphere = { radius = 1 } }] }"),
            vec!["smooth", "0", "> 0"],
        ),
        (
            kind("{ sphere = { radius = 9.0 } }"),
            vec!["prop_kinds.rock", "half the cell", "props_cell"],
        ),
        (
            kind("{ capsule = { radius = 0.5, height = 40.0 } }"),
            vec!["prop_kinds.rock", "tall", "props_band"],
        ),
        (kind("{ cone = { radius = 1 } }"), vec!["prop_kinds.rock.root", "smooth_union"]),
        (
            kind("{ sphere = { radius = 1 }, material = \"gold\" }"),
            vec!["material", "gold", "stone"],
        ),
        (
            "world = \"endless\"\nprops = true\n[[prop_place]]\nkind = \"menhir\"\nat = [0, 0]\n"
                .into(),
            vec!["prop_place[0].kind", "menhir", "boulder"],
        ),
    ];
    for (i, (text, needles)) in cases.iter().enumerate() {
        let scene = dir.join(format!("bad-{i}.toml"));
        std::fs::write(&scene, text).unwrap();
        refused.check(
            &["render", "--scene", scene.to_str().unwrap(), "--out", out],
            needles,
        );
    }
    assert!(!Path::new(out).exists());
}

#[test]
fn the_shipped_prop_scenes_draw_their_props() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let dir = scratch("prop-scenes");
    // The landscape's by the method `auto` picks, the demo's by the forward mesh too.
    let shown = [
        ("props-demo", "auto", 1.0),
        ("props-demo", "mesh", 1.0),
        ("props-landscape", "auto", 50.0),
    ];
    for (scene, method, least) in shown {
        let path = root.join(format!("scenes/{scene}.toml"));
        let out = dir.join(format!("{scene}-{method}.png"));
        let (code, stdout, err) = relief(&[
            "render",
            "--method",
            method,
            "--scene",
            path.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--width",
            "160",
            "--height",
            "90",
            "--stats",
        ]);
        assert_eq!(code, 0, "{scene}: {err}");
        let stats = stats_of(&stdout);
        assert!(stat(&stats, "props_in_view") >= least, "{scene}: {stats:?}");
        assert!(out.exists());
    }
}
