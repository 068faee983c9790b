//! The time of day through the `relief` program: an hour and a running day on the clock draw
//! the same frame as that hour, and bad values are refused in one line (exit 2).

#[path = "common/cli.rs"]
mod cli_common;
use cli_common::*;

fn render(dir: &std::path::Path, name: &str, extra: &[&str]) -> Vec<u8> {
    let out = dir.join(format!("{name}.png"));
    let mut args = vec![
        "render",
        "--world",
        "endless",
        "--method",
        "mesh",
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
    args.extend_from_slice(extra);
    let (code, _, err) = relief(&args);
    assert_eq!(code, 0, "{args:?}: {err}");
    image::open(&out).unwrap().into_rgba8().into_raw()
}

#[test]
fn a_running_day_draws_the_hour_its_clock_has_reached() {
    let dir = scratch("day");
    let evening = render(&dir, "19", &["--time-of-day", "19"]);
    // A day in 60 s from 7:00, 30 s on: 19:00.
    let ran = render(
        &dir,
        "7-ran",
        &["--time-of-day", "7", "--day-length", "60", "--clock", "30"],
    );
    assert_eq!(ran, evening);
    // The hour moves the sun (the negative control): 7:00 is another picture.
    let morning = render(&dir, "7", &["--time-of-day", "7"]);
    assert_ne!(morning, evening);
    // The same hour as the sun's azimuth and elevation draws the same frame.
    let (az, el) = relief::day::sun_at(19.0);
    let (az, el) = (az.to_string(), el.to_string());
    let placed = render(
        &dir,
        "placed",
        &["--sun-azimuth", &az, "--sun-elevation", &el],
    );
    assert_eq!(placed, evening);
}

#[test]
fn bad_times_of_day_are_refused_in_one_line() {
    let refused = Rejections::default();
    let dir = scratch("day-bad");
    let out = dir.join("x.png");
    let out = out.to_str().unwrap();
    // Past a day is refused (not wrapped), as are a negative hour below the "unset" -1 and a
    // negative day length.
    for (flag, value, needles) in [
        ("--time-of-day", "25", &["--time-of-day", "25", "24"][..]),
        ("--time-of-day", "-3", &["--time-of-day", "-3"][..]),
        ("--time-of-day", "noon", &["--time-of-day", "noon"][..]),
        ("--day-length", "-60", &["--day-length", "-60"][..]),
    ] {
        refused.check(
            &["render", "--world", "endless", flag, value, "--out", out],
            needles,
        );
    }
    // The tile has no sun path.
    refused.check(
        &["render", "--time-of-day", "7", "--out", out],
        &["--time-of-day", "endless"],
    );
}
