//! The clouds through the `relief` program: coverage 0 draws none, byte for byte, whatever the
//! layer's other knobs; a sun just set still lights the clouds from below, one set further
//! does not; the night with clouds stays dark; cloud shadows move by the wind times the clock
//! and stand still without wind; `--stats` says what the march did; bad values are refused in
//! one line (exit 2).

#[path = "common/cli.rs"]
mod cli_common;
use cli_common::*;

fn render(dir: &std::path::Path, name: &str, extra: &[&str]) -> image::RgbaImage {
    render_sized(dir, name, (96, 54), extra).0
}

/// `relief render` of the endless world (6 octaves, a coarse mesh; the mesh method unless
/// `extra` names one) at `size`: the picture and what the program printed.
fn render_sized(
    dir: &std::path::Path,
    name: &str,
    (width, height): (u32, u32),
    extra: &[&str],
) -> (image::RgbaImage, String) {
    let out = dir.join(format!("{name}.png"));
    let (width, height) = (width.to_string(), height.to_string());
    let mut args = vec![
        "render",
        "--world",
        "endless",
        "--pixel-error",
        "16",
        "--octaves",
        "6",
        "--width",
        &width,
        "--height",
        &height,
        "--out",
        out.to_str().unwrap(),
    ];
    if !extra.contains(&"--method") {
        args.extend_from_slice(&["--method", "mesh"]);
    }
    args.extend_from_slice(extra);
    let (code, stdout, err) = relief(&args);
    assert_eq!(code, 0, "{args:?}: {err}");
    (image::open(&out).unwrap().into_rgba8(), stdout)
}

/// Mean red, green and blue (the stored sRGB bytes, 0 to 255) of the rows `rows` of `img`.
fn mean(img: &image::RgbaImage, rows: std::ops::Range<u32>) -> [f64; 3] {
    let mut sum = [0.0; 3];
    let mut n = 0.0;
    for y in rows {
        for x in 0..img.width() {
            let p = img.get_pixel(x, y).0;
            for c in 0..3 {
                sum[c] += f64::from(p[c]);
            }
            n += 1.0;
        }
    }
    sum.map(|s| s / n)
}

#[test]
fn coverage_zero_draws_no_clouds_byte_for_byte() {
    let dir = scratch("clouds-off");
    let knobs = [
        "--cloud-coverage",
        "0",
        "--cloud-base",
        "500",
        "--cloud-top",
        "9000",
        "--cloud-type",
        "0.1",
    ];
    let compute = [
        "--method",
        "visibility",
        "--samples",
        "1",
        "--raster",
        "compute",
    ];
    for (name, method) in [("mesh", &[][..]), ("visibility", &compute[..])] {
        let plain = render(&dir, &format!("{name}-plain"), method);
        let off = render(&dir, &format!("{name}-off"), &[method, &knobs].concat());
        assert!(plain == off, "{name}: coverage 0 changed the picture");
        // The negative control: clouds on change it.
        let on = render(
            &dir,
            &format!("{name}-on"),
            &[method, &["--cloud-coverage", "0.5"][..]].concat(),
        );
        assert!(
            plain != on,
            "{name}: coverage 0.5 left the picture unchanged"
        );
    }
}

#[test]
fn a_sun_just_set_lights_the_clouds_from_below_and_the_night_stays_dark() {
    let dir = scratch("clouds-dusk");
    // From 1900 m looking 7 degrees up at the layer (2600 to 4600 m), the sun behind and to
    // the right.
    let up = [
        "--eye",
        "0,1900,0",
        "--look-at",
        "800,2300,-3000",
        "--sun-azimuth",
        "145",
    ];
    // Red over blue in the frame's upper half: the dusk sky is blue, a cloud lit by the low
    // sun is red.
    let red = |name: &str, elevation: &str, cover: &str| {
        let mut args = up.to_vec();
        args.extend(["--sun-elevation", elevation, "--cloud-coverage", cover]);
        let [r, _, b] = mean(&render(&dir, name, &args), 0..27);
        r / b
    };
    // At -2 degrees the ground's sun has set, but the layer's middle (3600 m) sees 1.9 degrees
    // past the ground's horizon, its top further: the clouds glow red over the blue dusk.
    let (clear, cloudy) = (
        red("dusk-clear", "-2", "0"),
        red("dusk-cloudy", "-2", "0.6"),
    );
    assert!(
        cloudy > 1.5 * clear,
        "at -2°: red/blue {cloudy:.2} with clouds, {clear:.2} without"
    );
    // At -8 degrees no sunlight reaches them either: they are the dusk's grey-blue.
    let (clear, cloudy) = (
        red("late-clear", "-8", "0"),
        red("late-cloudy", "-8", "0.6"),
    );
    assert!(
        cloudy < 1.2 * clear,
        "at -8°: red/blue {cloudy:.2} with clouds, {clear:.2} without"
    );
    // At -18 degrees (astronomical night) the frame shows the faint dusk light the night keeps
    // (4% of the day's sky; no moon, no stars), the clouds under it greyer: its mean luma, on
    // the stored sRGB bytes (Rec. 709 weights), under 20 of 255 (17.9 when written).
    let mut args = up.to_vec();
    args.extend(["--sun-elevation", "-18", "--cloud-coverage", "0.6"]);
    let [r, g, b] = mean(&render(&dir, "night", &args), 0..54);
    let night = 0.2126 * r + 0.7152 * g + 0.0722 * b;
    assert!(night < 20.0, "the night's mean luma is {night:.1}");
}

/// Each pixel's luma (Rec. 709 weights on the stored sRGB bytes) in `a` over that in `b`.
fn ratio(a: &image::RgbaImage, b: &image::RgbaImage) -> Vec<f64> {
    let luma = |p: &image::Rgba<u8>| {
        0.2126 * f64::from(p[0]) + 0.7152 * f64::from(p[1]) + 0.0722 * f64::from(p[2])
    };
    a.pixels()
        .zip(b.pixels())
        .map(|(a, b)| luma(a) / luma(b).max(1.0))
        .collect()
}

/// The correlation of `a` at (x, y) with `b` at (x + dx, y + dy) over where both lie in the
/// `side` x `side` image, every `step`-th pixel.
fn correlation(a: &[f64], b: &[f64], side: i32, (dx, dy): (i32, i32), step: usize) -> f64 {
    let (mut n, mut sa, mut sb, mut saa, mut sbb, mut sab) = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    for y in (0.max(-dy)..side.min(side - dy)).step_by(step) {
        for x in (0.max(-dx)..side.min(side - dx)).step_by(step) {
            let u = a[(y * side + x) as usize];
            let v = b[((y + dy) * side + x + dx) as usize];
            n += 1.0;
            (sa, sb) = (sa + u, sb + v);
            (saa, sbb, sab) = (saa + u * u, sbb + v * v, sab + u * v);
        }
    }
    let cov = sab / n - sa / n * sb / n;
    let var = (saa / n - (sa / n).powi(2)) * (sbb / n - (sb / n).powi(2));
    cov / var.max(1e-12).sqrt()
}

#[test]
fn cloud_shadows_move_by_the_wind_times_the_clock_and_stand_still_without_it() {
    // Looking (almost) straight down from 5000 m at flat ground (peak height 1 m), the layer
    // above the eye (6000 to 8000 m), the sun high: the frame with clouds over the frame
    // without is the clouds' shadow, whose pattern the wind carries. A west wind of 20 m/s
    // for 60 s carries it 1200 m east: at 45 degrees across 128 pixels, 5000 m below, that
    // is 1200 / (2 x 5000 x tan 22.5° / 128) = 37.1 pixels.
    const SIDE: i32 = 128;
    let dir = scratch("clouds-wind");
    let frame = |name: &str, extra: &[&str]| {
        let view = [
            "--peak-height",
            "1",
            "--no-water",
            "--no-grass",
            "--fog",
            "0",
            "--eye",
            "0,5000,0",
            "--look-at",
            "5,0,0",
            "--sun-elevation",
            "60",
            "--cloud-base",
            "6000",
            "--cloud-top",
            "8000",
            "--wind-azimuth",
            "270",
        ];
        let side = SIDE as u32;
        render_sized(&dir, name, (side, side), &[&view[..], extra].concat()).0
    };
    let clear = frame("clear", &["--cloud-coverage", "0"]);
    // `--stats` says how much of the layer a frame marched, and in how many steps: with
    // clouds only; and the memory of the light shafts' shadow-height map, which the endless
    // world holds with clouds or without.
    let stats = |coverage: &str, fog: &str| {
        let args = [
            "--no-grass",
            "--stats",
            "--cloud-coverage",
            coverage,
            "--fog",
            fog,
        ];
        render_sized(&dir, "stats", (32, 18), &args).1
    };
    let cloudy_stats = stats("0.5", "0.03");
    assert!(
        cloudy_stats.contains("cloud_march_fraction 1\ncloud_steps 48\n"),
        "{cloudy_stats}"
    );
    assert!(cloudy_stats.contains("shafts_mib 2.0\n"), "{cloudy_stats}");
    let bare = stats("0", "0.03");
    assert!(
        !bare.contains("cloud_") && bare.contains("shafts_mib 2.0\n"),
        "{bare}"
    );
    let cloudy = |name: &str, speed: &str, clock: &str| {
        let args = [
            "--cloud-coverage",
            "0.5",
            "--wind-speed",
            speed,
            "--clock",
            clock,
        ];
        ratio(&frame(name, &args), &clear)
    };
    let before = cloudy("before", "20", "0");
    let after = cloudy("after", "20", "60");
    // The view holds shadow and sun both, or no shift could be found.
    let mean = before.iter().sum::<f64>() / before.len() as f64;
    let spread =
        (before.iter().map(|s| (s - mean).powi(2)).sum::<f64>() / before.len() as f64).sqrt();
    assert!(
        spread > 0.05,
        "no shadow's edge in view: shadow {mean:.3} ± {spread:.3}"
    );
    // The shift that best lays the later shadows on the earlier: searched over ±48 pixels
    // every second pixel, then refined around the best.
    let best = |shifts: Vec<(i32, i32)>, step| {
        shifts
            .into_iter()
            .map(|d| (correlation(&before, &after, SIDE, d, step), d))
            .max_by(|a, b| a.0.total_cmp(&b.0))
            .unwrap()
    };
    let coarse: Vec<(i32, i32)> = (-24..=24)
        .flat_map(|j| (-24..=24).map(move |i| (2 * i, 2 * j)))
        .collect();
    let (_, (cx, cy)) = best(coarse, 2);
    let fine: Vec<(i32, i32)> = (-2..=2)
        .flat_map(|j| (-2..=2).map(move |i| (cx + i, cy + j)))
        .collect();
    let (r, (dx, dy)) = best(fine, 1);
    let moved = f64::from(dx).hypot(f64::from(dy));
    let expected = 1200.0 / (2.0 * 5000.0 * 22.5f64.to_radians().tan() / f64::from(SIDE));
    eprintln!(
        "shadows moved ({dx}, {dy}) pixels, {moved:.1} (expected {expected:.1}), correlation {r:.3}"
    );
    assert!(r > 0.8, "the shadows changed shape as they moved: {r:.3}");
    assert!(
        (moved - expected).abs() <= 0.1 * expected,
        "moved {moved:.1} pixels, expected {expected:.1} ± 10%"
    );
    // Without wind the clock moves nothing.
    let still = cloudy("still", "0", "60");
    assert_eq!(
        still,
        cloudy("still-start", "0", "0"),
        "without wind the shadows moved"
    );
}

#[test]
fn bad_cloud_values_are_refused_in_one_line() {
    let refused = Rejections::default();
    let dir = scratch("clouds-bad");
    let out = dir.join("x.png");
    let out = out.to_str().unwrap();
    let endless = ["render", "--world", "endless", "--out", out];
    for (args, needles) in [
        (
            &["--cloud-coverage", "1.5"][..],
            &["--cloud-coverage", "1.5"][..],
        ),
        (&["--cloud-coverage", "-0.1"][..], &["--cloud-coverage"][..]),
        (&["--cloud-top", "30000"][..], &["--cloud-top", "30000"][..]),
        (&["--cloud-type", "2"][..], &["--cloud-type", "2"][..]),
        // The base at or above the top (default 4600 m).
        (
            &["--cloud-base", "5000"][..],
            &["--cloud-top", "cloud_base"][..],
        ),
        (
            &["--cloud-base", "3000", "--cloud-top", "3000"][..],
            &["--cloud-top", "cloud_base"][..],
        ),
    ] {
        refused.check(&[&endless[..], args].concat(), needles);
    }
    // The same through a scene file.
    let scene = dir.join("flat.toml");
    std::fs::write(
        &scene,
        "world = \"endless\"\ncloud_base = 3000\ncloud_top = 2000\n",
    )
    .unwrap();
    refused.check(
        &["render", "--scene", scene.to_str().unwrap(), "--out", out],
        &["--cloud-top", "cloud_base"],
    );
    // The tile has no sky to hold them.
    refused.check(
        &["render", "--cloud-coverage", "0.5", "--out", out],
        &["--cloud-coverage", "endless"],
    );
}
