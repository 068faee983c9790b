//! The `relief` program's long runs, each once: `bench --quick` in both worlds, every
//! stability axis at its smallest through the program's code, and `stability --quick --axis`
//! through the program: the files they write and what they refuse.

#[path = "common/cli.rs"]
mod cli_common;
use cli_common::*;

#[test]
#[ignore = "slow: a whole `--quick` sweep through the program (.ci/test runs it)"]
fn bench_quick_writes_a_csv_and_a_chart() {
    let dir = scratch("bench");
    // Scene flags set the benchmark's scene (they were once silently ignored).
    let (code, stdout, err) = relief(&[
        "bench",
        "--quick",
        "--octaves",
        "3",
        "--seed",
        "99",
        "--out-dir",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(err, "", "a successful run keeps stderr clean");
    assert!(stdout.contains("seed 99, octaves 3"), "{stdout}");
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
    assert_eq!(lines.len(), 1 + 10, "ten configurations in the quick sweep");
    let rows: Vec<Vec<String>> = lines[1..].iter().map(|l| csv_fields(l)).collect();
    for row in &rows {
        assert_eq!(row.len(), header.len(), "{row:?}");
    }
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    // One default, chosen among the mesh-based candidates as `relief render --method auto`
    // chooses, from the rows' own draw times.
    let defaults: Vec<&str> = rows
        .iter()
        .filter(|r| r[col("default")] == "true")
        .map(|r| r[col("method")].as_str())
        .collect();
    assert!(
        defaults == ["mesh"] || defaults == ["visibility"],
        "{defaults:?}"
    );
    let methods: Vec<&str> = rows.iter().map(|r| r[col("method")].as_str()).collect();
    for m in [
        "mesh",
        "visibility",
        "raymarch-fragment",
        "raymarch",
        "blog",
    ] {
        assert!(methods.contains(&m), "no {m} row");
    }
    // The visibility method at one sample rasterised in compute, beside it at four in hardware.
    let rasters: Vec<(&str, &str)> = rows
        .iter()
        .filter(|r| r[col("method")] == "visibility")
        .map(|r| (r[col("samples")].as_str(), r[col("raster")].as_str()))
        .collect();
    assert_eq!(rasters, [("4", "hardware"), ("1", "compute")]);
    for row in &rows {
        let flip: f64 = row[col("flip_mean")].parse().unwrap();
        assert!(flip > 0.0 && flip < 0.5, "FLIP mean {flip} in {row:?}");
        if row[col("method")] == "blog" {
            // The blog's own terrain, texture and grid, baked and drawn every frame.
            assert_eq!(row[col("octaves")], "5", "{row:?}");
            assert_eq!(row[col("seed")], "", "{row:?}");
            assert_eq!(row[col("size")], "1024", "{row:?}");
            assert_eq!(row[col("grid")], "1024", "{row:?}");
            let ms = |c: &str| row[col(c)].parse::<f64>().unwrap();
            let parts = ms("bake_ms") + ms("normals_ms") + ms("render_ms");
            assert!((ms("frame_gpu_ms") - parts).abs() < 1e-3, "{row:?}");
            continue;
        }
        assert_eq!(row[col("octaves")], "3", "{row:?}");
        assert_eq!(row[col("seed")], "99", "{row:?}");
        let flip: f64 = row[col("flip_mean")].parse().unwrap();
        assert!(flip > 0.0 && flip < 0.5, "FLIP mean {flip} in {row:?}");
    }
    let png = image::open(dir.join("bench.png")).unwrap();
    assert_eq!((png.width(), png.height()), (960, 640));
    let svg = std::fs::read_to_string(dir.join("bench.svg")).unwrap();
    assert!(svg.contains("<svg") && svg.contains("Pareto front") && svg.contains("default"));
    // The default's label is drawn right beside its marker (it once floated far from it): on
    // whichever side it is, its nearer end lies within a few marker widths. The SVG gives the
    // text's start; its end is estimated at up to 8 px a character of 15 px sans-serif (a long
    // label left of a marker near the right edge starts some 350 px away and ends beside it).
    let (label, text) = svg_text(&svg, "default (").expect("a default label");
    let marker = svg_circle_position(&svg, 11.0).expect("the default's ring");
    let width = text.chars().count() as f64 * 8.0;
    let gap_x = if label.0 > marker.0 {
        label.0 - marker.0
    } else {
        (marker.0 - (label.0 + width)).max(0.0)
    };
    let d = (gap_x.powi(2) + (label.1 - marker.1).powi(2)).sqrt();
    assert!(
        d < 80.0,
        "label {text:?} at {label:?} (about {width} px wide), marker at {marker:?}"
    );
    // ... and inside the picture.
    assert!((0.0..960.0).contains(&label.0), "{label:?}");
}

#[test]
#[ignore = "slow: a whole `--quick` sweep through the program (.ci/test runs it)"]
fn bench_world_endless_quick_writes_landscape_csv() {
    let dir = scratch("bench-endless");
    let out = dir.join("out");
    // Six octaves: fewer levels to bake for each of the run's dozens of frames (a minute less
    // on lavapipe), and the world's flags reach the benchmark.
    let (code, stdout, err) = relief(&[
        "bench",
        "--world",
        "endless",
        "--quick",
        "--octaves",
        "6",
        "--out-dir",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    // Not a terminal: no progress (nor its escape codes) on stderr.
    assert_eq!(err, "", "a run into a pipe keeps stderr clean");
    let csv = std::fs::read_to_string(out.join("landscape.csv")).unwrap();
    let look = std::fs::read_to_string(out.join("look.csv")).unwrap();
    // Stdout says what was written, and the arrival in words; the CSVs stay in their files.
    for name in ["look.csv", "landscape.csv", "arrival.csv"] {
        assert!(
            stdout.contains(&format!("rows in {}", out.join(name).display())),
            "{stdout}"
        );
    }
    assert!(!stdout.contains("view,method"), "{stdout}");
    assert!(
        stdout.contains(", octaves 6, "),
        "the world it measured: {stdout}"
    );
    for method in ["mesh", "visibility 1 compute"] {
        assert!(
            stdout.contains(&format!("arrival ({method}): first frame")),
            "{stdout}"
        );
    }
    assert_eq!(
        files_in(&out),
        [
            "arrival.csv",
            "landscape.csv",
            "landscape.png",
            "landscape.svg",
            "look.csv"
        ]
    );
    // The arrival: every frame from the first, each lighting within the budget, and the
    // light waiting at the start (nothing is lit on arrival).
    let arrival = std::fs::read_to_string(out.join("arrival.csv")).unwrap();
    let mut arrival_rows = arrival
        .lines()
        .filter(|l| !l.starts_with('#'))
        .map(|l| l.split(',').collect::<Vec<&str>>());
    let arrival_header = arrival_rows.next().unwrap_or_default();
    let at = |name: &str| {
        arrival_header
            .iter()
            .position(|h| *h == name)
            .unwrap_or_else(|| panic!("no {name} column: {arrival}"))
    };
    let (phase, light_texels, pending) = (at("phase"), at("light_texels"), at("pending"));
    let frames: Vec<Vec<&str>> = arrival_rows.collect();
    // Two methods, six frames of arrival each, then a short running day: three frames
    // standing and three flying.
    assert_eq!(frames.len(), 2 * (6 + 2 * 3), "{arrival}");
    let phases: Vec<&str> = frames[..12].iter().map(|f| f[phase]).collect();
    let want: Vec<&str> = ["arrival"; 6]
        .into_iter()
        .chain(["day-standing"; 3])
        .chain(["day-flying"; 3])
        .collect();
    assert_eq!(phases, want, "{arrival}");
    for f in &frames {
        let lit: u64 = f[light_texels].parse().unwrap();
        assert!(lit <= relief::gpu::world::DEFAULT_LIGHT_BUDGET, "{f:?}");
    }
    assert!(frames[0][pending].parse::<u64>().unwrap() > 0, "{arrival}");
    // The look's cost: each part off in turn on the first view, and the light bake.
    let look: Vec<Vec<&str>> = look
        .lines()
        .filter(|l| !l.starts_with('#'))
        .skip(1)
        .map(|l| l.split(',').collect())
        .collect();
    assert_eq!(look.len(), 7, "{look:?}");
    assert_eq!(look[0][1], "everything on");
    assert!(
        look[0][4].parse::<f64>().unwrap() > 0.0,
        "light bake: {look:?}"
    );
    assert!(
        look.iter().all(|r| r[2].parse::<f64>().unwrap() > 0.0),
        "{look:?}"
    );
    let rows: Vec<&str> = csv.lines().filter(|l| !l.starts_with('#')).collect();
    let header: Vec<&str> = rows[0].split(',').collect();
    // Three views at two knobs: the mesh and the hybrid (at four samples a pixel and one) at
    // each, the visibility method beside them at the first; the four ray casters on each view,
    // and two flights.
    assert_eq!(rows.len(), 1 + 3 * 4 + 3 * 3 + 3 * 4 + 2, "{csv}");
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    // The quick run rasterises in hardware (the full run adds the hybrid rasterised in compute).
    let meshes: Vec<(&str, &str, &str)> = rows[1..22]
        .iter()
        .map(|r| {
            let v: Vec<&str> = r.split(',').collect();
            (v[col("method")], v[col("samples")], v[col("raster")])
        })
        .collect();
    let first = [
        ("mesh", "", ""),
        ("visibility", "4", "hardware"),
        ("hybrid", "4", "hardware"),
        ("hybrid", "1", "hardware"),
    ];
    let second = [
        ("mesh", "", ""),
        ("hybrid", "4", "hardware"),
        ("hybrid", "1", "hardware"),
    ];
    assert_eq!(
        meshes,
        [&first[..], &first, &first, &second, &second, &second].concat(),
        "{csv}"
    );
    let flip_of = |row: &str| -> f64 {
        let v: Vec<&str> = row.split(',').collect();
        v[col("flip_mean")].parse().unwrap()
    };
    // From the same coarse mesh, the hybrid's refined surface is closer to the reference than
    // the mesh on every view at both knobs, at four samples a pixel and at one.
    let first_knob = (0..3).map(|v| (1 + 4 * v, [3 + 4 * v, 4 + 4 * v]));
    let second_knob = (0..3).map(|v| (13 + 3 * v, [14 + 3 * v, 15 + 3 * v]));
    for (mesh, hybrids) in first_knob.chain(second_knob) {
        for hybrid in hybrids {
            assert!(
                flip_of(rows[hybrid]) < flip_of(rows[mesh]),
                "{}\n{}",
                rows[mesh],
                rows[hybrid]
            );
        }
    }
    for row in &rows[1..22] {
        let v: Vec<&str> = row.split(',').collect();
        if v[col("method")] == "hybrid" {
            // Its surface is the continuous one: the mesh's screen error and depth are not
            // its, and are left empty; its FLIP is measured.
            assert_eq!(v[col("measured_max_px")], "", "{row}");
            assert_eq!(v[col("missed")], "", "{row}");
            let flip = flip_of(row);
            assert!(flip > 0.0 && flip < 0.25, "{row}");
            continue;
        }
        let measured: f64 = v[col("measured_max_px")].parse().unwrap();
        let bound: f64 = v[col("error_bound_px")].parse().unwrap();
        assert!(measured <= bound, "{row}");
        assert!(v[col("triangles")].parse::<u64>().unwrap() > 0, "{row}");
        // Against the reference of the same view: close, and drawing where it draws.
        let flip: f64 = v[col("flip_mean")].parse().unwrap();
        assert!(flip > 0.0 && flip < 0.25, "{row}");
        let holes: f64 =
            v[col("missed")].parse::<f64>().unwrap() + v[col("extra")].parse::<f64>().unwrap();
        assert!(holes < 0.02, "{row}");
    }
    let casters = [
        "reference",
        "raymarch",
        "raymarch-fragment",
        "raymarch-bandlimited",
    ];
    for (row, method) in rows[22..34].iter().zip(casters.iter().cycle()) {
        let v: Vec<&str> = row.split(',').collect();
        assert_eq!(v[col("method")], *method, "{row}");
        assert_eq!(v[col("triangles")], "0", "{row}");
        assert!(v[col("render_ms")].parse::<f64>().unwrap() > 0.0, "{row}");
        assert!(v[col("unresolved_rays")].parse::<u64>().is_ok(), "{row}");
        if *method != "reference" {
            assert!(v[col("flip_mean")].parse::<f64>().unwrap() < 0.25, "{row}");
        }
    }
    assert!(rows[34].starts_with("flight,"), "{csv}");
    assert!(rows[35].starts_with("path,"), "{csv}");
}

/// Every axis at its smallest: one or two values each, at small sizes. What each axis finds
/// is pinned by relief-eval's stability tests on the `--quick` sweeps; this runs the
/// program's own code around them (tables, CSVs, charts) without sweeping twice.
fn tiny_sweeps() -> relief_eval::stability::Sweeps {
    // The default world drawn to 16 px of error: fewer levels to bake and light.
    let world = relief::WorldParams {
        pixel_error: 16.0,
        ..Default::default()
    };
    let mut s = relief_eval::stability::Sweeps::quick(&world);
    s.grazing.elevations = vec![5.0];
    s.grazing.size = (48, 27);
    s.world_grazing.elevations = vec![5.0];
    s.world_grazing.size = (48, 27);
    s.shadow.elevations = vec![3.0];
    s.shadow.stride = 512;
    s.distance.distances = vec![1.0, 1e9];
    s.distance.size = (48, 27);
    s.scroll.distances = vec![1.0, 1e13];
    s.scroll.size = 64;
    s.motion.speeds = vec![256.0];
    s.motion.frames = 4;
    s.motion.size = (48, 27);
    s.detail.octaves = vec![4];
    s.detail.sizes = vec![128];
    s.detail.grids = vec![32];
    s.detail.image = (48, 32);
    s.storage_side = 64;
    s.temporal.size = (48, 27);
    s.temporal.warm = 2;
    s.temporal.frames = 2;
    s.temporal.turns = vec![90.0];
    s.temporal.strafes = Vec::new();
    s.grass.size = (48, 27);
    s.grass.frames = 1;
    s.grass.warm = 1;
    s.grass.distance = Some(8.0);
    s.clouds.size = (48, 27);
    s.clouds.warm = 2;
    s.clouds.frames = 2;
    s
}

#[test]
#[ignore = "slow: every stability axis through the program's code (.ci/test runs it)"]
fn stability_writes_every_axis_csv_and_charts_and_refuses_what_it_sweeps() {
    use relief_eval::stability::Axis;
    let dir = scratch("stability");
    let sweeps = tiny_sweeps();
    let scene = relief::TerrainParams {
        octaves: 6,
        ..Default::default()
    };
    relief_cli::stability::stability(&scene, &dir, (&sweeps, true), &Axis::ALL).unwrap();
    assert_eq!(
        files_in(&dir),
        [
            "clouds.csv",
            "clouds.png",
            "clouds.svg",
            "detail.csv",
            "detail.png",
            "detail.svg",
            "distance.csv",
            "distance.png",
            "distance.svg",
            "grass.csv",
            "grass.png",
            "grass.svg",
            "grazing-hs0p5.png",
            "grazing-hs0p5.svg",
            "grazing-hs2.png",
            "grazing-hs2.svg",
            "motion.csv",
            "motion.png",
            "motion.svg",
            "props-banding.png",
            "props-banding.svg",
            "props-budget.png",
            "props-budget.svg",
            "props-cutoff.png",
            "props-cutoff.svg",
            "props-lipschitz.png",
            "props-lipschitz.svg",
            "props-smooth.png",
            "props-smooth.svg",
            "props-thin.png",
            "props-thin.svg",
            "props.csv",
            "scroll.csv",
            "scroll.png",
            "scroll.svg",
            "shadow.csv",
            "shadow.png",
            "shadow.svg",
            "stability.csv",
            "storage.csv",
            "storage.png",
            "storage.svg",
            "temporal.csv",
            "temporal.png",
            "temporal.svg",
            "world-grazing-hs2400.png",
            "world-grazing-hs2400.svg",
            "world-grazing.csv"
        ]
    );
    // The world axes: the shadow rays' table (a sun x 3 methods), the distance axis with the
    // default world's refusal 10^9 m out, the flights (the mesh with the morph on and off, the
    // visibility method, the hybrid).
    let lines = |name: &str| {
        std::fs::read_to_string(dir.join(name))
            .unwrap()
            .lines()
            .count()
    };
    assert_eq!(lines("shadow.csv"), 1 + 3);
    // The clouds: a turn through the image against the full march (they differ: the image is
    // half the frame's size and marched one pixel in 16), and a still frame's banding.
    let clouds = std::fs::read_to_string(dir.join("clouds.csv")).unwrap();
    let rows: Vec<&str> = clouds.lines().skip(1).collect();
    assert_eq!(rows.len(), 2, "{clouds}");
    assert!(
        rows[0].starts_with("turn valley-up-noon,90,deg/s,2,"),
        "{clouds}"
    );
    assert!(
        rows[1].starts_with("still valley-up-noon,48,steps,1,"),
        "{clouds}"
    );
    for row in rows {
        let flip: f64 = row.split(',').nth(4).unwrap().parse().unwrap();
        assert!(flip > 0.0 && flip < 0.25, "{row}");
    }
    assert_eq!(lines("motion.csv"), 1 + 4);
    assert_eq!(lines("temporal.csv"), 1 + 1);
    // The grass: a walk over the meadow and standing in a gale, against the grass reference.
    assert_eq!(lines("grass.csv"), 1 + 2);
    // The props: every sweep's rows (the lipschitz, smooth, budget, thin and cutoff sweeps).
    let props = std::fs::read_to_string(dir.join("props.csv")).unwrap();
    for sweep in ["lipschitz,", "smooth,", "budget,", "thin,", "cutoff,"] {
        assert!(props.lines().any(|l| l.starts_with(sweep)), "{props}");
    }
    let distance = std::fs::read_to_string(dir.join("distance.csv")).unwrap();
    assert!(
        distance
            .lines()
            .any(|l| l.starts_with("1e9,\"x and z within")),
        "{distance}"
    );
    // The visibility method and the hybrid beside the mesh on the distance axis.
    for column in [
        "jitter_visibility",
        "missed_hybrid",
        "flip_hybrid_vs_reference",
    ] {
        assert!(
            distance.lines().next().unwrap_or_default().contains(column),
            "distance.csv lacks {column}"
        );
    }
    let csv = std::fs::read_to_string(dir.join("stability.csv")).unwrap();
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let rows: Vec<Vec<String>> = csv.lines().skip(1).map(csv_fields).collect();
    // An elevation x 2 height scales x (2 step factors, the relaxation, the march in a
    // fragment shader, the mesh, the reference).
    assert_eq!(rows.len(), 12, "{csv}");
    for row in &rows {
        assert_eq!(row[col("width")], "48", "the sweep's own size: {row:?}");
    }
    // The scroll axis: relief's tile and the blog's at each distance, relief refusing 10^13
    // tiles in words.
    let scroll = std::fs::read_to_string(dir.join("scroll.csv")).unwrap();
    assert_eq!(scroll.lines().count(), 1 + 2 * 2, "{scroll}");
    assert!(
        scroll.lines().any(|l| l.starts_with("relief,1e13,\"")),
        "{scroll}"
    );
    for (flag, value) in [("--height-scale", "1"), ("--grid", "64"), ("--timings", "")] {
        let mut args = vec!["stability", "--quick", flag];
        if !value.is_empty() {
            args.push(value);
        }
        rejects(&args, &[flag, "stability"]);
    }
    rejects(&["stability", "--world", "endless"], &["stability", "tile"]);
}

#[test]
#[ignore = "slow: a whole `--quick` sweep through the program (.ci/test runs it)"]
fn stability_axis_runs_only_the_axes_named_and_writes_only_their_files() {
    let dir = scratch("stability-axis");
    let (code, stdout, err) = relief(&[
        "stability",
        "--quick",
        "--octaves",
        "6",
        "--axis",
        "storage,scroll",
        "--out-dir",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(err, "", "a successful run keeps stderr clean");
    assert_eq!(
        files_in(&dir),
        [
            "scroll.csv",
            "scroll.png",
            "scroll.svg",
            "storage.csv",
            "storage.png",
            "storage.svg"
        ]
    );
    // In the order the full sweep runs them, whatever the order named; the scene's flags reach
    // the sweep.
    assert!(stdout.contains("2 axes (scroll, storage)"), "{stdout}");
    assert!(stdout.contains("octaves 6"), "{stdout}");
    let scroll = std::fs::read_to_string(dir.join("scroll.csv")).unwrap();
    assert_eq!(scroll.lines().count(), 1 + 2 * 4, "{scroll}");
    assert!(
        scroll.lines().any(|l| l.starts_with("relief,1e13,\"")),
        "{scroll}"
    );
    assert!(!stdout.contains("grazing views"), "{stdout}");
    // Repeating the flag adds to the list.
    let again = scratch("stability-axis-again");
    let (code, _, err) = relief(&[
        "stability",
        "--quick",
        "--axis",
        "storage",
        "--axis",
        "storage",
        "--out-dir",
        again.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(
        files_in(&again),
        ["storage.csv", "storage.png", "storage.svg"]
    );
    rejects(
        &["stability", "--axis", "sideways"],
        &["--axis", "sideways", "world-grazing", "scroll"],
    );
    rejects(&["render", "--axis", "scroll"], &["--axis"]);
}
