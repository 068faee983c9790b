//! The `relief` program in the endless world (`--world endless`): render, height, bake of a
//! region, scene files and camera tables, and its refusals.

use std::path::Path;

#[path = "common/cli.rs"]
mod cli_common;
#[path = "common/rows.rs"]
mod rows;
use cli_common::*;

/// Renders the endless world small and loose (fast on a software GPU); returns the pixels and
/// the `--stats` lines.
fn render_endless(dir: &Path, name: &str, extra: &[&str]) -> (Vec<u8>, Vec<(String, f64)>) {
    let out = dir.join(format!("{name}.png"));
    // The mesh, but where a method is given (the props' rows give the one that marches them).
    let method: &[&str] = if extra.contains(&"--method") {
        &[]
    } else {
        &["--method", "mesh"]
    };
    let mut args = vec!["render"];
    args.extend_from_slice(method);
    args.extend_from_slice(&[
        "--world",
        "endless",
        "--out",
        out.to_str().unwrap(),
        "--width",
        "96",
        "--height",
        "64",
        "--stats",
    ]);
    if !extra.contains(&"--pixel-error") {
        args.extend_from_slice(&["--pixel-error", "16"]);
    }
    args.extend_from_slice(extra);
    let (code, stdout, err) = relief(&args);
    assert_eq!(code, 0, "{extra:?}: {err}");
    assert_eq!(err, "", "{extra:?}: stderr not clean");
    (
        image::open(&out).unwrap().into_rgb8().into_raw(),
        stats_of(&stdout),
    )
}

#[test]
fn the_endless_world_renders_and_every_one_of_its_parameters_changes_it() {
    let dir = scratch("endless");
    let (base, stats) = render_endless(&dir, "base", &[]);
    for key in [
        "triangles",
        "texels_baked",
        "levels",
        "error_bound_px",
        "patch_cells",
        "texture_mib_per_level",
        "texture_mib",
    ] {
        assert!(stat(&stats, key) >= 0.0);
    }
    assert!(
        (stat(&stats, "texture_mib")
            - stat(&stats, "texture_mib_per_level") * stat(&stats, "levels_total"))
        .abs()
            < 0.1,
        "{stats:?}"
    );
    assert!(
        stat(&stats, "triangles") > 0.0 && stat(&stats, "levels") >= 3.0,
        "{stats:?}"
    );
    assert!(stat(&stats, "error_bound_px") <= 16.0, "{stats:?}");
    // Every row of the endless world's table, through its flag: the picture changes (the
    // knob changes the triangles; the picture may stay nearly the same).
    for row in &relief::world::WORLD_PARAMS {
        let value = rows::test_value(row.key);
        let flag = format!("--{}", row.flag());
        let mut args: Vec<&str> = match row.kind {
            relief::table::Kind::Bool => vec![&flag],
            _ => vec![&flag, value],
        };
        // The height occlusion exponent is the blog palette's: it changes that picture.
        let blog = row.key == "ao_exponent";
        // The clock and the wind move the ripples, which fade out a few hundred metres away:
        // seen from 20 m above a lake (its bed 770 m down, the water at 1000 m). The wind
        // carries them as the clock runs: at clock 0 it has carried nothing.
        let lake = ["--eye", "2000,1020,-4600", "--look-at", "2100,1000,-4400"];
        // The day too: a day in 60 s has run half a day at clock 30.
        let windy = row.key.starts_with("wind_") || row.key == "day_length";
        // Grass from 1.7 m over a meadow (it grows by default): its knobs, and none.
        let meadow = [
            "--eye",
            "2740,1111.7,-3000",
            "--look-at",
            "2770,1107.7,-2990",
        ];
        let grassy = row.key.starts_with("grass") || row.key == "no_grass";
        // Props from 2 m among them, with the method that marches them; their knobs with them on.
        let among = [
            "--eye",
            "2740,1112,-3000",
            "--look-at",
            "2710,1106,-3030",
            "--method",
            "visibility",
            "--samples",
            "1",
            "--raster",
            "compute",
            "--no-grass",
        ];
        let propped = row.key.starts_with("props");
        // The layer's knobs with clouds on (none by default).
        let cloudy = row.key.starts_with("cloud_") && row.key != "cloud_coverage";
        let base = if propped {
            args.extend(among);
            let mut at = among.to_vec();
            if row.key != "props" {
                args.push("--props");
                at.push("--props");
            }
            let (img, s) = render_endless(&dir, &format!("{}-base", row.key), &at);
            if row.key != "props" {
                assert!(stat(&s, "props_in_view") > 10.0, "{s:?}");
            }
            img
        } else if grassy {
            args.extend(meadow);
            let (img, s) = render_endless(&dir, &format!("{}-base", row.key), &meadow);
            if row.key == "no_grass" {
                // --stats counts the blades of the default's grass.
                let drawn = stat(&s, "grass_blades_drawn");
                assert!(drawn > 1000.0, "{s:?}");
                assert!(stat(&s, "grass_blades_considered") > drawn, "{s:?}");
                // One to seven triangles a blade (one to four segments).
                let triangles = stat(&s, "grass_triangles");
                assert!(triangles >= drawn && triangles <= 7.0 * drawn, "{s:?}");
            }
            img
        } else if cloudy {
            args.extend(["--cloud-coverage", "0.5"]);
            render_endless(&dir, "cloudy", &["--cloud-coverage", "0.5"]).0
        } else if blog {
            args.extend(["--palette", "blog"]);
            render_endless(&dir, "blog", &["--palette", "blog"]).0
        } else if windy {
            args.extend(lake);
            args.extend(["--clock", "30"]);
            let mut at = lake.to_vec();
            at.extend(["--clock", "30"]);
            render_endless(&dir, "lake-30", &at).0
        } else if row.key == "clock" {
            args.extend(lake);
            render_endless(&dir, "lake", &lake).0
        } else {
            base.clone()
        };
        let (img, s) = render_endless(&dir, row.key, &args);
        if row.key == "no_grass" {
            assert!(!s.iter().any(|(k, _)| k.starts_with("grass")), "{s:?}");
        }
        if row.key == "pixel_error" {
            assert!(
                stat(&s, "triangles") > stat(&stats, "triangles"),
                "{flag} {value}: {s:?} against {stats:?}"
            );
        } else {
            assert_ne!(img, base, "{flag} {value} left the picture unchanged");
        }
        // The same value as a scene-file key draws the same picture as the flag.
        let scene = dir.join(format!("{}.toml", row.key));
        let mut knob = if row.key == "pixel_error" {
            String::new()
        } else {
            "pixel_error = 16\n".to_owned()
        };
        if propped {
            knob.push_str("no_grass = true\n");
            if row.key != "props" {
                knob.push_str("props = true\n");
            }
        }
        if blog {
            knob.push_str("palette = \"blog\"\n");
        }
        if cloudy {
            knob.push_str("cloud_coverage = 0.5\n");
        }
        if windy {
            knob.push_str("clock = 30\n");
        }
        // Over the lake for the clock and the wind (the flags override the scene's camera).
        let camera: &[&str] = if windy || row.key == "clock" {
            &lake
        } else if propped {
            &among[..4]
        } else if grassy {
            &meadow
        } else {
            &[]
        };
        std::fs::write(
            &scene,
            format!(
                "world = \"endless\"\n{knob}{} = {}\n",
                row.key,
                relief_cli::scene::toml_value(row.parse(value).unwrap())
            ),
        )
        .unwrap();
        let out = dir.join(format!("{}-scene.png", row.key));
        let method: &[&str] = if propped {
            &among[4..10]
        } else {
            &["--method", "mesh"]
        };
        let mut scene_args = vec!["render"];
        scene_args.extend_from_slice(method);
        scene_args.extend_from_slice(&[
            "--scene",
            scene.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--width",
            "96",
            "--height",
            "64",
            "--stats",
        ]);
        scene_args.extend(camera);
        let (code, stdout, err) = relief(&scene_args);
        assert_eq!(code, 0, "{}: {err}", row.key);
        assert_eq!(
            image::open(&out).unwrap().into_rgb8().into_raw(),
            img,
            "{} = {value} in a scene file draws another picture than {flag} {value}",
            row.key
        );
        assert!(
            stdout.contains(&format!("triangles {}", stat(&s, "triangles"))),
            "{stdout}"
        );
    }
    // The camera flags move the camera.
    let (moved, _) = render_endless(&dir, "eye", &["--eye", "500,2400,-800"]);
    assert_ne!(moved, base);
    let (turned, _) = render_endless(&dir, "look", &["--look-at", "0,0,9000"]);
    assert_ne!(turned, base);
    let (wide, _) = render_endless(&dir, "fov", &["--fov", "80"]);
    assert_ne!(wide, base);
    // The fly-through path: a time is a place along it.
    let (p0, _) = render_endless(&dir, "path0", &["--camera", "path"]);
    let (p1, _) = render_endless(&dir, "path1", &["--camera", "path", "--time", "30"]);
    assert_ne!(p0, base);
    assert_ne!(p0, p1);
    let (again, _) = render_endless(&dir, "path0b", &["--camera", "path", "--time", "0"]);
    assert_eq!(again, p0, "the path at 0 s is --camera path without --time");
    // Looking straight up: sky only, nothing drawn.
    let (_, up) = render_endless(&dir, "up", &["--eye", "0,3000,0", "--look-at", "0,9000,1"]);
    assert_eq!(stat(&up, "triangles"), 0.0, "{up:?}");
}

#[test]
fn the_endless_world_heights_and_the_tile_camera() {
    let (code, stdout, err) = relief(&[
        "height",
        "--world",
        "endless",
        "--seed",
        "3",
        "0,0",
        "125.5,-3000",
    ]);
    assert_eq!(code, 0, "{err}");
    let land = relief::WorldParams {
        land: relief::landscape::Landscape {
            seed: 3,
            ..relief::WorldParams::default().land
        },
        ..Default::default()
    }
    .land;
    let got: Vec<f64> = stdout.lines().map(|l| l.parse().unwrap()).collect();
    assert_eq!(
        got,
        vec![land.height_at(0.0, 0.0), land.height_at(125.5, -3000.0)]
    );
    // The tile takes the camera flags too.
    let dir = scratch("tile-camera");
    let render = |name: &str, extra: &[&str]| {
        let out = dir.join(format!("{name}.png"));
        let mut args = vec![
            "render",
            "--method",
            "mesh",
            "--out",
            out.to_str().unwrap(),
            "--width",
            "64",
            "--height",
            "48",
            "--size",
            "64",
            "--grid",
            "32",
        ];
        args.extend_from_slice(extra);
        let (code, _, err) = relief(&args);
        assert_eq!(code, 0, "{err}");
        image::open(&out).unwrap().into_rgb8().into_raw()
    };
    let base = render("base", &[]);
    assert_ne!(render("eye", &["--eye", "0,2,2.5"]), base);
    assert_ne!(render("fov", &["--fov", "70"]), base);
}

#[test]
fn bad_camera_and_world_input_exits_2_and_writes_nothing() {
    let refused = Rejections::default();
    let dir = scratch("bad-camera");
    let out = dir.join("x.png");
    let out = out.to_str().unwrap();
    let render = |extra: &[&str], needles: &[&str]| {
        let mut args = vec!["render", "--out", out];
        args.extend_from_slice(extra);
        refused.check(&args, needles);
    };
    render(&["--eye", "nan,0,0"], &["--eye", "nan", "X,Y,Z"]);
    // Grass: out of range, its keys with a ray caster (which draws none), and on the tile.
    render(
        &["--world", "endless", "--grass-height", "9"],
        &["grass", "9", "2"],
    );
    render(
        &[
            "--world",
            "endless",
            "--grass-density",
            "8",
            "--method",
            "raymarch",
        ],
        &["--grass-density", "raymarch", "mesh"],
    );
    render(&["--no-grass"], &["--no-grass", "endless"]);
    render(&["--eye", "1,2"], &["--eye", "X,Y,Z"]);
    render(&["--look-at", "1,2,3,4"], &["--look-at", "X,Y,Z"]);
    render(&["--eye", "1e300,0,0"], &["--eye", "X,Y,Z"]);
    render(
        &["--eye", "0,5,0", "--look-at", "0,5,0"],
        &["--look-at", "--eye"],
    );
    render(&["--fov", "0"], &["--fov", "0", "degrees"]);
    render(&["--fov", "180"], &["--fov", "180"]);
    render(&["--fov", "wide"], &["--fov", "wide"]);
    render(&["--world", "moon"], &["--world", "moon", "endless"]);
    render(&["--world", "endless", "--size", "64"], &["--size", "tile"]);
    render(
        &["--world", "endless", "--offset", "1,2"],
        &["--offset", "tile"],
    );
    render(
        &["--world", "endless", "--scene", "a.toml"],
        &["a.toml", "No such file"],
    );
    render(
        &["--world", "endless", "--feature-size", "3000"],
        &["feature-size", "3000", "power of two"],
    );
    render(
        &[
            "--world",
            "endless",
            "--feature-size",
            "16",
            "--octaves",
            "20",
        ],
        &["--octaves", "20", "1..=12"],
    );
    render(
        &["--world", "endless", "--pixel-error", "0"],
        &["--pixel-error", "0"],
    );
    render(&["--peak-height", "100"], &["--peak-height", "endless"]);
    render(
        &["--world", "endless", "--sun-elevation", "91"],
        &["--sun-elevation", "91", "-90..=90"],
    );
    render(&["--world", "endless", "--fog", "-1"], &["--fog", "-1"]);
    render(
        &["--world", "endless", "--sun-azimuth", "north"],
        &["--sun-azimuth", "north"],
    );
    render(&["--sun-azimuth", "10"], &["--sun-azimuth", "endless"]);
    render(
        &["--world", "endless", "--water-level", "1e9"],
        &["--water-level", "1e9"],
    );
    refused.check(
        &[
            "bake",
            "--out-dir",
            dir.to_str().unwrap(),
            "--world",
            "endless",
            "--normals",
            "analytic",
        ],
        &["--normals", "tile"],
    );
    refused.check(&["height", "--eye", "1,2,3", "0,0"], &["--eye", "render"]);
    refused.check(&["window", "--eye", "1,2,3"], &["--eye", "render"]);
    render(
        &["--world", "endless", "--camera", "zoom"],
        &["--camera", "zoom", "path"],
    );
    render(&["--camera", "fly"], &["--camera fly", "tile", "orbit"]);
    render(
        &["--world", "endless", "--camera", "orbit"],
        &["--camera orbit", "endless"],
    );
    render(
        &["--world", "endless", "--camera", "path", "--eye", "0,9,0"],
        &["--eye", "path"],
    );
    render(
        &["--world", "endless", "--camera", "path", "--time", "-1"],
        &["--time", "-1", "seconds"],
    );
    render(&["--world", "endless", "--time", "5"], &["--time", "path"]);
    refused.check(
        &["--world", "endless", "--speed", "1"],
        &["--speed", "tile"],
    );
    refused.check(
        &["window", "--world", "endless", "--stats"],
        &["--stats", "render"],
    );
    refused.check(
        &["height", "--world", "endless", "--pixel-error", "2", "0,0"],
        &["--pixel-error", "height"],
    );
    assert!(files_in(&dir).is_empty(), "{:?}", files_in(&dir));
}

#[test]
fn bake_world_endless_writes_a_region_that_recovers_the_twin() {
    let dir = scratch("bake-region");
    let out = dir.join("out");
    let (code, stdout, err) = relief(&[
        "bake",
        "--world",
        "endless",
        "--region",
        "-256,512,256,1024",
        "--size",
        "64",
        "--seed",
        "5",
        "--out-dir",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(err, "");
    assert!(stdout.contains("every 8 m"), "{stdout}");
    assert_eq!(
        files_in(&out),
        ["color.png", "height.png", "normal.png", "scene.toml"]
    );
    let scene: toml::Table = std::fs::read_to_string(out.join("scene.toml"))
        .unwrap()
        .parse()
        .unwrap();
    assert_eq!(scene["world"].as_str(), Some("endless"));
    assert_eq!(scene["seed"].as_integer(), Some(5));
    let bake = scene["bake"].as_table().unwrap();
    assert_eq!(bake["spacing"].as_float(), Some(8.0));
    let (lo, hi) = (
        bake["height_min"].as_float().unwrap(),
        bake["height_max"].as_float().unwrap(),
    );
    let land = relief::landscape::Landscape {
        seed: 5,
        ..relief::WorldParams::default().land
    };
    let h = image::open(out.join("height.png")).unwrap().into_luma16();
    for (i, j) in [(0u32, 0u32), (63, 0), (10, 40), (63, 63)] {
        let v = f64::from(h.get_pixel(i, j).0[0]) / 65535.0 * (hi - lo) + lo;
        // Sample (i, j) is world (-256 + 8i, 512 + 8j): sample coordinates -32 + i, 64 + j.
        let twin = land.peak_height
            * land
                .level_sample(
                    relief::noise::Channel::Height,
                    3,
                    -32 + i64::from(i),
                    64 + i64::from(j),
                )
                .value;
        // 16-bit quantisation of the range, plus f32 on the GPU.
        assert!(
            (v - twin).abs() <= (hi - lo) / 65535.0 + 1e-3,
            "sample ({i}, {j}): height.png says {v}, the twin {twin}"
        );
    }
    let bad = |extra: &[&str], needles: &[&str]| {
        let mut args = vec![
            "bake",
            "--world",
            "endless",
            "--out-dir",
            out.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        rejects(&args, needles);
    };
    bad(
        &["--region", "0,0,100,100", "--size", "64"],
        &["--region", "power of two"],
    );
    bad(
        &["--region", "3,0,131,128", "--size", "64"],
        &["--region", "multiple"],
    );
    bad(&["--region", "0,0,64"], &["--region", "four numbers"]);
    bad(
        &["--region", "0,0,64,32", "--size", "32"],
        &["--region", "square"],
    );
    bad(&["--region", "nan,0,64,64"], &["--region", "finite"]);
    rejects(
        &[
            "render",
            "--method",
            "mesh",
            "--out",
            "x.png",
            "--world",
            "endless",
            "--region",
            "0,0,64,64",
        ],
        &["--region", "bake"],
    );
    rejects(
        &["bake", "--out-dir", "x", "--region", "0,0,64,64"],
        &["--region", "endless"],
    );
}

#[test]
fn endless_scene_files_and_camera_tables_round_trip() {
    let dir = scratch("endless-scene");
    let bake = dir.join("bake");
    let (code, _, err) = relief(&[
        "bake",
        "--world",
        "endless",
        "--seed",
        "12",
        "--peak-height",
        "1500",
        "--region",
        "0,0,512,512",
        "--size",
        "64",
        "--out-dir",
        bake.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let scene = bake.join("scene.toml");
    // The bake's scene file draws the same world as the flags that made it.
    let (from_scene, _) = render_endless(&dir, "scene", &["--scene", scene.to_str().unwrap()]);
    let (from_flags, _) = render_endless(&dir, "flags", &["--seed", "12", "--peak-height", "1500"]);
    assert_eq!(from_scene, from_flags);
    // Without --world: the scene file's world decides.
    let out = dir.join("auto.png");
    let (code, stdout, err) = relief(&[
        "render",
        "--method",
        "mesh",
        "--scene",
        scene.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--width",
        "96",
        "--height",
        "64",
        "--pixel-error",
        "16",
        "--stats",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(stdout.contains("levels_total"), "{stdout}");
    assert_eq!(
        image::open(&out).unwrap().into_rgb8().into_raw(),
        from_scene
    );
    // A [camera] table places the camera as the flags would; a flag overrides its part.
    let with_camera = dir.join("camera.toml");
    std::fs::write(
        &with_camera,
        "world = \"endless\"\nseed = 12\npeak_height = 1500\n\n[camera]\neye = [300, 2200, -100]\nlook_at = [2000, 900, 400]\nfov = 60\n",
    )
    .unwrap();
    let (a, _) = render_endless(
        &dir,
        "cam-scene",
        &["--scene", with_camera.to_str().unwrap()],
    );
    let (b, _) = render_endless(
        &dir,
        "cam-flags",
        &[
            "--seed",
            "12",
            "--peak-height",
            "1500",
            "--eye",
            "300,2200,-100",
            "--look-at",
            "2000,900,400",
            "--fov",
            "60",
        ],
    );
    assert_eq!(a, b);
    let (c, _) = render_endless(
        &dir,
        "cam-override",
        &["--scene", with_camera.to_str().unwrap(), "--fov", "40"],
    );
    assert_ne!(a, c);
    // The path and its time from [camera], as --camera path --time would place it.
    let on_path = dir.join("path.toml");
    std::fs::write(
        &on_path,
        "world = \"endless\"\nseed = 12\n[camera]\ncamera = \"path\"\ntime = 30\n",
    )
    .unwrap();
    let (p_scene, _) = render_endless(&dir, "path-scene", &["--scene", on_path.to_str().unwrap()]);
    let (p_flags, _) = render_endless(
        &dir,
        "path-flags",
        &["--seed", "12", "--camera", "path", "--time", "30"],
    );
    assert_eq!(p_scene, p_flags);
    // Bad scene files: one line naming the file and what is wrong, nothing written.
    let bad = |name: &str, text: &str, needles: &[&str]| {
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        let out = dir.join(format!("{name}.png"));
        rejects(
            &[
                "render",
                "--method",
                "mesh",
                "--scene",
                path.to_str().unwrap(),
                "--out",
                out.to_str().unwrap(),
            ],
            needles,
        );
        assert!(!out.exists());
    };
    bad(
        "moon.toml",
        "world = \"moon\"\n",
        &["moon.toml", "world", "endless"],
    );
    bad(
        "size.toml",
        "world = \"endless\"\nsize = 64\n",
        &["size.toml", "size", "did you mean seed", "docs/cli.md"],
    );
    bad(
        "grass.toml",
        "world = \"endless\"\ngrass_hight = 1\n",
        &["grass.toml", "grass_hight", "did you mean grass_height"],
    );
    bad(
        "fov.toml",
        "world = \"endless\"\n[camera]\nfov = 0\n",
        &["fov.toml", "fov", "degrees"],
    );
    bad(
        "eye.toml",
        "world = \"endless\"\n[camera]\neye = [1, 2]\n",
        &["eye.toml", "eye", "[x, y, z]"],
    );
    bad(
        "key.toml",
        "world = \"endless\"\n[camera]\nzoom = 2\n",
        &["key.toml", "zoom", "look_at"],
    );
    bad(
        "path.toml",
        "world = \"endless\"\n[camera]\ncamera = \"path\"\neye = [0, 900, 0]\n",
        &["eye", "path"],
    );
    // The tile reads a [camera] table too.
    let tile = dir.join("tile.toml");
    std::fs::write(&tile, "seed = 3\n[camera]\neye = [0, 2, 2.5]\n").unwrap();
    let render_tile = |name: &str, extra: &[&str]| {
        let out = dir.join(format!("{name}.png"));
        let mut args = vec![
            "render",
            "--method",
            "mesh",
            "--out",
            out.to_str().unwrap(),
            "--width",
            "64",
            "--height",
            "48",
            "--size",
            "64",
            "--grid",
            "32",
        ];
        args.extend_from_slice(extra);
        let (code, _, err) = relief(&args);
        assert_eq!(code, 0, "{err}");
        image::open(&out).unwrap().into_rgb8().into_raw()
    };
    assert_eq!(
        render_tile("tile-scene", &["--scene", tile.to_str().unwrap()]),
        render_tile("tile-flags", &["--seed", "3", "--eye", "0,2,2.5"])
    );
}

#[test]
fn the_reference_draws_the_grass_and_counts_its_blades() {
    // `render --method reference` with grass: the grass's reference (every blade to twice the draw
    // distance over the continuous surface, 9x9 samples a pixel), its blades counted by
    // --stats; a sparse, near meadow keeps it quick on a software GPU.
    let dir = scratch("grass-reference");
    let render = |name: &str, grass: &[&str]| {
        let out = dir.join(format!("{name}.png"));
        let mut args = vec![
            "render",
            "--world",
            "endless",
            "--method",
            "reference",
            "--eye",
            "2740,1111.7,-3000",
            "--look-at",
            "2770,1107.7,-2990",
            "--out",
            out.to_str().unwrap(),
            "--width",
            "48",
            "--height",
            "27",
            "--stats",
        ];
        args.extend_from_slice(grass);
        let (code, stdout, err) = relief(&args);
        assert_eq!(code, 0, "{grass:?}: {err}");
        (
            image::open(&out).unwrap().into_rgb8().into_raw(),
            stats_of(&stdout),
        )
    };
    let (bare, s) = render("bare", &["--no-grass"]);
    assert!(s.iter().all(|(k, _)| !k.starts_with("grass")), "{s:?}");
    let grass = ["--grass-density", "8", "--grass-distance", "10"];
    let (grassy, s) = render("grass", &grass);
    let blades = stat(&s, "grass_blades_drawn");
    assert!(blades > 100.0, "{s:?}");
    // Every blade in four segments: seven triangles.
    assert_eq!(stat(&s, "grass_triangles"), 7.0 * blades, "{s:?}");
    assert_ne!(grassy, bare);
}
