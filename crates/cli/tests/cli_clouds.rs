//! The clouds through the `relief` program: coverage 0 draws none, byte for byte, whatever the
//! layer's other knobs; a sun just set still lights the clouds from below, one set further
//! does not; the night with clouds stays dark; bad values are refused in one line (exit 2).

#[path = "common/cli.rs"]
mod cli_common;
use cli_common::*;

fn render(dir: &std::path::Path, name: &str, extra: &[&str]) -> image::RgbaImage {
    let out = dir.join(format!("{name}.png"));
    let mut args = vec![
        "render",
        "--world",
        "endless",
        "--pixel-error",
        "16",
        "--octaves",
        "6",
        "--width",
        "96",
        "--height",
        "54",
        "--out",
        out.to_str().unwrap(),
    ];
    if !extra.contains(&"--method") {
        args.extend_from_slice(&["--method", "mesh"]);
    }
    args.extend_from_slice(extra);
    let (code, _, err) = relief(&args);
    assert_eq!(code, 0, "{args:?}: {err}");
    image::open(&out).unwrap().into_rgba8()
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
