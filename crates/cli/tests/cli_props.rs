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

#[test]
#[ignore = "slow: a view drawn with props and without, by relief and the seed's way, against two references, on a software GPU (.ci/test runs it)"]
fn bench_measures_the_props_against_their_reference_beside_the_seeds_way() {
    let dir = scratch("bench-props");
    let (code, stdout, err) = relief(&[
        "bench",
        "--world",
        "endless",
        "--quick",
        "--only",
        "props",
        "--out-dir",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let csv = std::fs::read_to_string(dir.join("props.csv")).unwrap();
    let header: Vec<&str> = csv.lines().nth(1).unwrap().split(',').collect();
    let col = |name: &str| {
        header
            .iter()
            .position(|h| *h == name)
            .unwrap_or_else(|| panic!("no {name} in {csv}"))
    };
    let rows: Vec<Vec<&str>> = csv
        .lines()
        .skip(2)
        .map(|l| l.split(',').collect())
        .collect();
    let methods: Vec<&str> = rows.iter().map(|r| r[1]).collect();
    assert_eq!(
        methods,
        [
            "marching",
            "the seed's way 25 steps",
            "the seed's way 400 steps"
        ],
        "{csv}"
    );
    // Props in view, each frame timed, each FLIP against its reference measured; the marching
    // method's without props too.
    let number = |r: &[&str], name: &str| r[col(name)].parse::<f64>().is_ok();
    for r in &rows {
        assert!(
            r[col("view")] == "among-2m" && r[col("props_in_view")].parse::<u32>().unwrap() > 100,
            "{csv}"
        );
        assert!(
            number(r, "frame_ms_with") && number(r, "march_ms") && number(r, "flip_with"),
            "{csv}"
        );
    }
    // The marching method's own shadows' pass, and its frame and FLIP without props.
    assert!(
        number(&rows[0], "shadows_ms")
            && number(&rows[0], "frame_ms_without")
            && number(&rows[0], "flip_without"),
        "{csv}"
    );
    assert!(
        stdout.contains("3 rows") && stdout.contains("props on among-2m"),
        "{stdout}"
    );
    // A view that is not the props' is refused before anything is measured.
    let (code, _, err) = relief(&[
        "bench",
        "--world",
        "endless",
        "--only",
        "props",
        "--view",
        "horizon",
        "--out-dir",
        dir.join("no").to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--view") && err.contains("among-2m"), "{err}");
    assert!(!dir.join("no").exists());
    // The reference draws them too.
    let out = dir.join("reference.png");
    let (code, _, err) = relief(&[
        "render",
        "--world",
        "endless",
        "--props",
        "--no-grass",
        "--method",
        "reference",
        "--eye",
        "2740,1112,-3000",
        "--look-at",
        "2710,1106,-3030",
        "--width",
        "64",
        "--height",
        "36",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(out.exists());
}

/// Size of the shipped prop scenes' golden images.
const GOLDEN: (u32, u32) = (256, 144);
/// Largest FLIP mean and 99th percentile accepted against a prop scene's golden image.
/// lavapipe reproduces it to the bit; another GPU's rounding must pass (an H100 scored a mean
/// of 0.025 on the landscape's golden image, `crates/eval/tests/images.rs`, its 1-LSB
/// differences spread over the frame; its 99th percentile here is not measured), while each
/// negative control below must fail one of them: a change to a prop alone covers a few
/// percent of the frame, which the 99th percentile sees (0.40 to 0.82 on lavapipe) and the
/// mean does not (0.002 to 0.009).
const GOLDEN_FLIP_MEAN: f64 = 0.035;
const GOLDEN_FLIP_P99: f64 = 0.2;

/// `relief render --scene scenes/{scene}.toml` (or the scene's `text` where given) at the
/// golden size with `extra` flags, as RGB8.
fn render_scene(scene: &str, text: Option<&str>, extra: &[&str]) -> Vec<u8> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let dir = scratch(&format!("golden-{scene}"));
    let path = match text {
        Some(text) => {
            let p = dir.join("scene.toml");
            std::fs::write(&p, text).unwrap();
            p
        }
        None => root.join(format!("scenes/{scene}.toml")),
    };
    let out = dir.join(format!(
        "out{}{}.png",
        text.map_or(0, str::len),
        extra.join("").replace(['-', ' ', '.', ','], "")
    ));
    let (w, h) = (GOLDEN.0.to_string(), GOLDEN.1.to_string());
    let mut args = vec![
        "render",
        "--scene",
        path.to_str().unwrap(),
        "--width",
        &w,
        "--height",
        &h,
        "--out",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    let (code, _, err) = relief(&args);
    assert_eq!(code, 0, "{scene} {extra:?}: {err}");
    image::open(&out).unwrap().into_rgb8().into_raw()
}

/// A golden-image check of a shipped prop scene: its picture against
/// `tests/images/{scene}.png` within [`GOLDEN_FLIP_MEAN`], each control above it.
/// `RELIEF_UPDATE_IMAGES=1` writes the reference instead (look at it before committing).
fn golden_scene(scene: &str, controls: &[(&str, Option<String>, Vec<&str>)]) {
    let actual = render_scene(scene, None, &[]);
    let reference = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("tests/images/{scene}.png"));
    let (w, h) = GOLDEN;
    if std::env::var_os("RELIEF_UPDATE_IMAGES").is_some() {
        std::fs::create_dir_all(reference.parent().unwrap()).unwrap();
        image::save_buffer(&reference, &actual, w, h, image::ColorType::Rgb8).unwrap();
        return;
    }
    let expected = image::open(&reference)
        .unwrap_or_else(|e| panic!("{}: {e}", reference.display()))
        .into_rgb8()
        .into_raw();
    let flip = |image: &[u8]| relief_eval::metrics::image_error(&expected, image, w, h);
    let passes = |(mean, p99): (f64, f64)| mean <= GOLDEN_FLIP_MEAN && p99 <= GOLDEN_FLIP_P99;
    let (mean, p99) = flip(&actual);
    eprintln!("{scene}: FLIP mean {mean:.4}, p99 {p99:.4}");
    for (what, text, flags) in controls {
        let (m, p) = flip(&render_scene(scene, text.as_deref(), flags));
        eprintln!("control, {what}: FLIP mean {m:.4}, p99 {p:.4}");
        assert!(
            !passes((m, p)),
            "{scene}: the thresholds cannot see {what} ({m}, {p})"
        );
    }
    assert!(
        passes((mean, p99)),
        "{scene} differs from its golden image: FLIP mean {mean:.4}, p99 {p99:.4}"
    );
}

#[test]
fn golden_images_of_the_shipped_prop_scenes() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let demo = std::fs::read_to_string(root.join("scenes/props-demo.toml")).unwrap();
    let tighter = demo.replace("smooth_union = 0.6", "smooth_union = 0.2");
    assert_ne!(tighter, demo);
    golden_scene(
        "props-demo",
        &[
            (
                "the smooth union's radius 0.6 -> 0.2",
                Some(tighter),
                vec![],
            ),
            ("the sun turned 15°", None, vec!["--sun-azimuth", "215"]),
        ],
    );
    golden_scene(
        "props-landscape",
        &[(
            "a tenth fewer props",
            None,
            vec!["--props-density", "0.315"],
        )],
    );
}
