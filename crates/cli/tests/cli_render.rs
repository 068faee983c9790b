//! `relief render` as a user meets it: the PNG it writes, the method it draws by (chosen by
//! measurement, or given with its samples and raster), the timings it prints, and the same
//! frame from every method. Bad input and the other commands are in tests/cli.rs.

#[path = "common/cli.rs"]
mod cli_common;
use cli_common::*;

#[test]
fn render_writes_a_png_and_reports_timings() {
    let dir = scratch("render");
    let out = dir.join("frame.png");
    let (code, stdout, err) = relief(&[
        "render",
        "--method",
        "mesh",
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
    // The method pinned, then the timings.
    assert!(
        stdout.starts_with("method mesh (pinned: --method mesh)\ntimings"),
        "--timings printed nothing: {stdout:?}"
    );
    assert!(
        stdout.contains("render") || stdout.contains("no timestamp queries"),
        "{stdout}"
    );
    assert_eq!(files_in(&dir), ["frame.png"]);
}

/// `relief render`'s default, `--method auto`: it draws a few frames of each candidate of its
/// world on this GPU and keeps the fastest; `--timings` says which and why, and the image is
/// the one the chosen method draws when given by its flags.
#[test]
fn render_chooses_its_method_by_measurement_and_says_which() {
    use relief::choice::Candidate;
    let dir = scratch("render-auto");
    let out = |name: &str| dir.join(name).to_str().unwrap().to_owned();
    for (world, extra) in [
        (
            relief::WorldKind::Tile,
            &["--size", "64", "--grid", "16"][..],
        ),
        (relief::WorldKind::Endless, &["--world", "endless"][..]),
    ] {
        let size = ["--width", "96", "--height", "64"];
        let auto = out("auto.png");
        let args = [
            &["render", "--out", &auto, "--timings", "--stats"][..],
            &size,
            extra,
        ]
        .concat();
        let (code, stdout, err) = relief(&args);
        assert_eq!(code, 0, "{err}");
        let line = stdout.lines().next().unwrap_or_default();
        assert!(line.starts_with("method "), "{world:?}: {stdout}");
        if line.contains("no GPU timestamps") {
            assert!(line.contains("--method mesh"), "{line}");
        } else {
            // Each candidate is named with its median draw.
            for c in Candidate::all(world) {
                assert!(
                    line.contains(&format!("{c} ")),
                    "{world:?}: {c} missing: {line}"
                );
            }
            assert!(line.contains(" ms"), "{line}");
        }
        // The flags of the chosen method, between the first parentheses.
        let flags: Vec<&str> = line
            .split_once('(')
            .and_then(|(_, rest)| rest.split_once(')'))
            .map(|(f, _)| f.split_whitespace().collect())
            .unwrap_or_default();
        assert_eq!(flags.first(), Some(&"--method"), "{line}");
        let pinned = out("pinned.png");
        let args = [
            &["render", "--out", &pinned, "--stats"][..],
            &flags,
            &size,
            extra,
        ]
        .concat();
        let (code, pinned_stdout, err) = relief(&args);
        assert_eq!(code, 0, "{flags:?}: {err}");
        // The same stats: the trial leaves the world to bake and draw as the pinned method.
        let stats = |out: &str| -> Vec<String> {
            out.lines()
                .filter(|l| !l.starts_with("method ") && !l.starts_with("timings"))
                .map(str::to_owned)
                .collect()
        };
        assert_eq!(stats(&stdout), stats(&pinned_stdout), "{world:?}");
        let (a, b) = (image::open(&auto).unwrap(), image::open(&pinned).unwrap());
        assert_eq!(
            a.to_rgba8().as_raw(),
            b.to_rgba8().as_raw(),
            "{world:?}: auto's image is not {flags:?}'s"
        );
    }
}

/// `--samples` sets the samples a pixel of the visibility method and the hybrid (one sample
/// leaves edges aliased), and is refused where it means nothing.
#[test]
fn render_samples_sets_the_visibility_methods_samples() {
    let dir = scratch("render-samples");
    let out = dir.join("s.png");
    let o = out.to_str().unwrap();
    for (method, world) in [("visibility", "tile"), ("hybrid", "endless")] {
        let image = |samples: &str| {
            let (code, _, err) = relief(&[
                "render",
                "--out",
                o,
                "--world",
                world,
                "--width",
                "96",
                "--height",
                "64",
                "--method",
                method,
                "--samples",
                samples,
            ]);
            assert_eq!(code, 0, "{method} --samples {samples}: {err}");
            image::open(&out).unwrap().to_rgba8().into_raw()
        };
        let (one, four) = (image("1"), image("4"));
        let changed = one.iter().zip(&four).filter(|(a, b)| a != b).count();
        assert!(
            changed > 0,
            "{method}: --samples 1 and 4 drew the same image"
        );
        // The default is 4.
        let (code, _, err) = relief(&[
            "render", "--out", o, "--world", world, "--width", "96", "--height", "64", "--method",
            method,
        ]);
        assert_eq!(code, 0, "{err}");
        assert_eq!(
            image::open(&out).unwrap().to_rgba8().into_raw(),
            four,
            "{method}"
        );
    }
    rejects(
        &[
            "render",
            "--out",
            o,
            "--method",
            "visibility",
            "--samples",
            "2",
        ],
        &["--samples", "2", "1 or 4"],
    );
    for method in ["mesh", "auto", "raymarch"] {
        rejects(
            &["render", "--out", o, "--method", method, "--samples", "1"],
            &["--samples", "visibility and hybrid", method],
        );
    }
    rejects(
        &["bake", "--out-dir", dir.to_str().unwrap(), "--samples", "1"],
        &["--samples"],
    );
}

/// `--raster compute` rasterises the visibility method's mesh in a compute pass: the same
/// image within edge pixels, and `--timings` names it; what it cannot draw is refused in words.
#[test]
fn render_raster_moves_the_visibility_methods_raster_to_compute() {
    let dir = scratch("render-raster");
    let out = dir.join("frame.png");
    let o = out.to_str().unwrap();
    let run = |raster: Option<&str>| {
        let mut args = vec![
            "render",
            "--out",
            o,
            "--width",
            "96",
            "--height",
            "64",
            "--method",
            "visibility",
            "--samples",
            "1",
            "--timings",
        ];
        if let Some(r) = raster {
            args.extend(["--raster", r]);
        }
        let (code, stdout, err) = relief(&args);
        assert_eq!(code, 0, "--raster {raster:?}: {err}");
        (stdout, image::open(&out).unwrap().to_rgba8().into_raw())
    };
    let (default, hardware) = run(None);
    let (said, compute) = run(Some("compute"));
    assert!(
        default.contains(
            "method visibility at 1 sample a pixel (pinned: --method visibility --samples 1)"
        ),
        "{default}"
    );
    assert!(
        said.contains(
            "rasterised in compute (pinned: --method visibility --samples 1 --raster compute)"
        ),
        "{said}"
    );
    assert!(!default.contains("compute"), "{default}");
    let (explicit, image) = run(Some("hardware"));
    assert_eq!(image, hardware, "--raster hardware is the default");
    assert!(!explicit.contains("compute"), "{explicit}");
    // The same terrain: a pixel centre within rounding of an edge may fall the other way.
    let off = hardware
        .chunks(4)
        .zip(compute.chunks(4))
        .filter(|(a, b)| a.iter().zip(b.iter()).any(|(x, y)| x.abs_diff(*y) > 8))
        .count();
    assert!(off * 200 < 96 * 64, "{off} pixels differ");
    rejects(
        &[
            "render",
            "--out",
            o,
            "--method",
            "visibility",
            "--samples",
            "1",
            "--raster",
            "soft",
        ],
        &["--raster", "soft", "hardware or compute"],
    );
    rejects(
        &[
            "render",
            "--out",
            o,
            "--method",
            "visibility",
            "--raster",
            "compute",
        ],
        &["raster", "one sample a pixel", "--samples 1"],
    );
    // The endless world's hybrid too, its attributes stored by a second dispatch.
    let (code, stdout, err) = relief(&[
        "render",
        "--out",
        o,
        "--world",
        "endless",
        "--width",
        "48",
        "--height",
        "32",
        "--method",
        "hybrid",
        "--samples",
        "1",
        "--raster",
        "compute",
        "--timings",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(
        stdout.contains("method hybrid at 1 sample a pixel rasterised in compute"),
        "{stdout}"
    );
    for method in ["mesh", "auto", "raymarch"] {
        rejects(
            &[
                "render", "--out", o, "--method", method, "--raster", "compute",
            ],
            &["--raster", "visibility and hybrid only", method],
        );
    }
}

#[test]
fn render_visibility_times_its_passes_and_counts_its_images() {
    let dir = scratch("render-visibility");
    let out = dir.join("frame.png");
    let run = |method: &str, world: &[&str]| {
        let mut args = vec![
            "render",
            "--out",
            out.to_str().unwrap(),
            "--width",
            "96",
            "--height",
            "64",
            "--method",
            method,
            "--timings",
            "--stats",
        ];
        args.extend_from_slice(world);
        let (code, stdout, err) = relief(&args);
        assert_eq!(code, 0, "{err}");
        stdout
    };
    for world in [&[][..], &["--world", "endless", "--pixel-error", "8"][..]] {
        let vis = run("visibility", world);
        let mesh = run("mesh", world);
        // Its raster pass and its compute shading are timed beside the host's pass.
        if !vis.contains("no timestamp queries") {
            assert!(vis.contains("raster ") && vis.contains("shade "), "{vis}");
            assert!(
                !mesh.contains("raster ") && !mesh.contains("shade "),
                "{mesh}"
            );
        }
        // Its own images: 96x64 pixels of 4 depth samples and the shaded image and depth (the
        // endless world adds 4 samples of its attributes).
        let own = stat(&stats_of(&vis), "method_texture_mib");
        assert!(own > 0.1 && own < 1.0, "{vis}");
        assert_eq!(stat(&stats_of(&mesh), "method_texture_mib"), 0.0, "{mesh}");
    }
    // The hybrid (the endless world's): the same passes and images, its shading refining rays.
    let hybrid = run("hybrid", &["--world", "endless", "--pixel-error", "8"]);
    if !hybrid.contains("no timestamp queries") {
        assert!(
            hybrid.contains("raster ") && hybrid.contains("shade "),
            "{hybrid}"
        );
    }
    let own = stat(&stats_of(&hybrid), "method_texture_mib");
    assert!(own > 0.1 && own < 1.0, "{hybrid}");
}

#[test]
fn the_tiles_stats_count_its_own_textures_and_bake_timings_say_how_they_were_taken() {
    let dir = scratch("tile-stats");
    let mib = |size: &str| {
        let out = dir.join(format!("{size}.png"));
        let args = [
            "render",
            "--method",
            "mesh",
            "--out",
            out.to_str().unwrap(),
            "--width",
            "64",
            "--height",
            "48",
        ];
        let (code, stdout, err) = relief(&[&args[..], &["--size", size, "--stats"]].concat());
        assert_eq!(code, 0, "{err}");
        let stats = stats_of(&stdout);
        let tile = stat(&stats, "tile_texture_mib");
        let total = stat(&stats, "total_texture_mib");
        assert!(
            (total - tile - stat(&stats, "texture_mib")).abs() <= 0.1,
            "{stats:?}"
        );
        tile
    };
    // rg32float heights and colour, rgba16float normals: 16 bytes a texel.
    assert_eq!(mib("512"), 4.0);
    assert_eq!(mib("256"), 1.0);
    let out = dir.join("bake");
    let (code, stdout, err) = relief(&[
        "bake",
        "--out-dir",
        out.to_str().unwrap(),
        "--size",
        "32",
        "--timings",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(
        stdout.contains("no timestamp queries") || stdout.contains("(each the median of 9 bakes"),
        "{stdout}"
    );
}

/// Draws one frame with each of `methods` (flags `common` added) and checks each is far closer
/// to the reference than the reference of another seed is. Returns the reference's stdout.
fn every_method_draws_the_same_frame(
    name: &str,
    (w, h): (u32, u32),
    methods: &[&str],
    common: &[&str],
) -> String {
    let dir = scratch(name);
    let (ws, hs) = (w.to_string(), h.to_string());
    let render = |method: &str, extra: &[&str]| {
        let out = dir.join(format!("{method}-{}.png", extra.len()));
        let mut args = vec![
            "render",
            "--out",
            out.to_str().unwrap(),
            "--width",
            &ws,
            "--height",
            &hs,
            "--method",
            method,
        ];
        args.extend_from_slice(common);
        args.extend_from_slice(extra);
        let (code, stdout, err) = relief(&args);
        assert_eq!(code, 0, "{method}: {err}");
        (image::open(&out).unwrap().into_rgb8().into_raw(), stdout)
    };
    let (reference, stdout) = render("reference", &[]);
    let (other_seed, _) = render("reference", &["--seed", "8"]);
    let control = relief_eval::metrics::image_error(&reference, &other_seed, w, h).0;
    for m in methods {
        let (img, _) = render(m, &[]);
        let (flip, _) = relief_eval::metrics::image_error(&reference, &img, w, h);
        eprintln!("{name} {m}: FLIP {flip:.4} against the reference (another seed: {control:.4})");
        // The same frame: far closer to the reference than a different terrain is.
        assert!(
            flip < control * 0.75,
            "{m}: FLIP {flip} vs control {control}"
        );
    }
    stdout
}

#[test]
fn render_draws_the_same_frame_with_every_method() {
    // The blog draws its own terrain (tests/blog.rs scores it against its own surface).
    let tile: Vec<&str> = relief::Method::ALL
        .iter()
        .filter(|m| m.in_tile() && !m.own_terrain())
        .map(|m| m.name())
        .collect();
    every_method_draws_the_same_frame("methods", (160, 100), &tile, &[]);
    // Mesh-only flags mean nothing to a ray caster: refused, not ignored.
    rejects(
        &[
            "render", "--out", "x.png", "--method", "raymarch", "--size", "64",
        ],
        &["--size", "raymarch"],
    );
    rejects(
        &["render", "--out", "x.png", "--method", "rays"],
        &["--method", "rays", "reference"],
    );
    rejects(
        &[
            "render",
            "--out",
            "x.png",
            "--method",
            "raymarch-bandlimited",
        ],
        &["--method", "raymarch-bandlimited", "endless"],
    );
}

#[test]
fn render_draws_the_same_endless_frame_with_every_method() {
    let stats = every_method_draws_the_same_frame(
        "world-methods",
        (120, 68),
        relief::Method::WORLD_NAMES,
        &["--world", "endless", "--pixel-error", "4", "--stats"],
    );
    // The ray casters draw no mesh and say how many rays ran out of steps.
    assert!(stats.contains("triangles 0\n"), "{stats}");
    assert!(stats.contains("unresolved_rays 0\n"), "{stats}");
}

#[test]
fn a_knob_finer_than_the_levels_can_hold_says_so_on_stderr() {
    let dir = scratch("knob-warning");
    let out = dir.join("frame.png");
    let run = |knob: &str| {
        relief(&[
            "render",
            "--method",
            "mesh",
            "--world",
            "endless",
            "--width",
            "320",
            "--height",
            "180",
            "--stats",
            "--pixel-error",
            knob,
            "--out",
            out.to_str().unwrap(),
        ])
    };
    // At 320x180 the densest levels hold about 0.42 px: 0.25 px is more than they can give.
    let (code, stdout, err) = run("0.25");
    assert_eq!(code, 0, "{err}");
    let stats = stats_of(&stdout);
    assert_eq!(stat(&stats, "patch_cells"), 128.0, "{stdout}");
    let bound = stat(&stats, "error_bound_px");
    assert!(bound > 0.25, "{stdout}");
    assert_eq!(err.lines().count(), 1, "one short line: {err}");
    assert!(err.contains("--pixel-error 0.25"), "{err}");
    // The bound it names is --stats' (printed to 3 places there, 2 here).
    let named: f64 = err
        .split("bounded by ")
        .nth(1)
        .and_then(|t| t.split(" px").next())
        .and_then(|t| t.parse().ok())
        .unwrap_or_else(|| panic!("no bound in {err}"));
    assert!(
        (named - bound).abs() <= 0.006,
        "{named} against {bound}: {err}"
    );
    // A knob they hold: the patches are smaller than the largest, nothing is said.
    let (code, stdout, err) = run("1");
    assert_eq!(code, 0, "{err}");
    assert!(
        stat(&stats_of(&stdout), "error_bound_px") <= 1.0,
        "{stdout}"
    );
    assert_eq!(err, "", "a knob the levels hold keeps stderr clean");
}

#[test]
fn render_draws_the_blogs_pipeline_and_refuses_what_it_does_not_read() {
    let dir = scratch("blog");
    let out = dir.join("blog.png");
    let args = |extra: &[&'static str]| {
        let mut a = vec![
            "render",
            "--method",
            "blog",
            "--out",
            out.to_str().unwrap(),
            "--width",
            "96",
            "--height",
            "64",
            "--stats",
            "--timings",
        ];
        a.extend_from_slice(extra);
        a
    };
    let (code, stdout, err) = relief(&args(&[]));
    assert_eq!(code, 0, "{err}");
    assert_eq!(err, "");
    // Its 1024²-vertex grid and two 8-bit 1024² maps, baked whole every frame, each timed.
    let stats = stats_of(&stdout);
    assert_eq!(stat(&stats, "triangles"), 2.0 * 1023.0 * 1023.0, "{stdout}");
    assert_eq!(stat(&stats, "texels_baked"), 1024.0 * 1024.0, "{stdout}");
    assert_eq!(stat(&stats, "total_texture_mib"), 8.0, "{stdout}");
    assert!(
        stdout.contains("no timestamp queries")
            || ["bake", "normals", "render"]
                .iter()
                .all(|p| stdout.contains(&format!("{p} "))),
        "{stdout}"
    );
    let blog = image::open(&out).unwrap().to_rgba8();
    // The scene's height scale is the blog's too: a flatter terrain draws another picture.
    let (code, _, err) = relief(&args(&["--height-scale", "0.1"]));
    assert_eq!(code, 0, "{err}");
    let flat = image::open(&out).unwrap().to_rgba8();
    assert_ne!(
        blog.as_raw(),
        flat.as_raw(),
        "--height-scale changed nothing"
    );
    // ... and its snow line.
    let (code, _, err) = relief(&args(&["--snow-height", "0.3"]));
    assert_eq!(code, 0, "{err}");
    let snowy = image::open(&out).unwrap().to_rgba8();
    assert_ne!(
        blog.as_raw(),
        snowy.as_raw(),
        "--snow-height changed nothing"
    );
    // The scene's noise, texture and grid are not the blog's: refused, not ignored.
    for flag in ["--seed", "--octaves", "--grid", "--size", "--gain"] {
        rejects(&args(&[flag, "3"]), &[flag, "blog"]);
    }
    // The blog draws its own tile, not the endless world.
    rejects(
        &[
            "render", "--world", "endless", "--method", "blog", "--out", "x.png",
        ],
        &["blog", "tile"],
    );
}
