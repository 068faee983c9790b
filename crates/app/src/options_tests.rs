//! The window's and the page's options: URLs, keys and their refusals.

use super::*;

#[test]
fn the_clock_and_the_wind_ride_in_the_url() {
    let mut o = AppOptions::default();
    assert!(o
        .apply_query("world=endless&clock=30&wind_speed=7&wind_azimuth=90")
        .is_empty());
    let (world, _) = o.world.expect("endless");
    assert_eq!(world.clock, 30.0);
    assert_eq!((world.wind.speed, world.wind.from_azimuth), (7.0, 90.0));
    let query = o.to_query();
    for key in ["clock=30", "wind_speed=7", "wind_azimuth=90"] {
        assert!(query.split('&').any(|k| k == key), "{key} in {query}");
    }
}

#[test]
fn the_endless_world_in_the_url() {
    let mut o = AppOptions::default();
    let ignored = o.apply_query(
        "world=endless&seed=3&peak_height=900&eye=10,2000,-5&look_at=900,1500,40&fov=60&camera=path&size=64&gain=7",
    );
    let keys: Vec<&str> = ignored.iter().map(|i| i.key.as_str()).collect();
    assert_eq!(keys, ["size", "gain"], "{ignored:?}");
    let (world, fly) = o.world.expect("endless");
    assert_eq!((world.land.seed, world.land.peak_height), (3, 900.0));
    assert!(o.path);
    assert_eq!(fly.eye, glam::DVec3::new(10.0, 2000.0, -5.0));
    assert!((fly.fov_y.to_degrees() - 60.0).abs() < 1e-4);
    // The URL it leaves gives the same world and camera (to a tenth of a metre).
    let query = o.to_query();
    assert!(query.starts_with("world=endless&"), "{query}");
    let mut again = AppOptions::default();
    assert!(again.apply_query(&query).is_empty(), "{query}");
    let (w2, f2) = again.world.unwrap();
    assert_eq!(w2, world);
    assert!(again.path);
    assert!((f2.eye - fly.eye).length() < 0.1 && (f2.forward() - fly.forward()).length() < 1e-3);
    let mut timed = AppOptions::default();
    assert!(timed
        .apply_query("world=endless&camera=path&time=12.5")
        .is_empty());
    assert_eq!(timed.path_time, 12.5);
    assert!(
        timed.to_query().ends_with("time=12.5"),
        "{}",
        timed.to_query()
    );
    assert_eq!(
        AppOptions::default()
            .apply_query("world=endless&time=-1")
            .len(),
        1
    );
    // Controls set the world's keys; the tile's are refused there.
    o.set("seed", "9").unwrap();
    assert_eq!(o.world.unwrap().0.land.seed, 9);
    assert!(o.set("size", "64").is_err());
    assert!(o.set("feature_size", "1000").is_err());
    // A bad world name is reported and the tile applies.
    let mut t = AppOptions::default();
    let ignored = t.apply_query("world=moon&seed=4");
    assert_eq!(ignored.len(), 1);
    assert!(t.world.is_none() && t.params.seed == 4);
}

#[test]
fn query_round_trip() {
    let mut o = AppOptions::default();
    let ignored = o.apply_query(
        "?seed=42&octaves=5&height-scale=0.8&offset=0.5%2C0.25&paused=1&speed=0.02&normals=analytic",
    );
    assert_eq!(ignored, []);
    assert_eq!(o.params.seed, 42);
    assert_eq!(o.params.octaves, 5);
    assert_eq!(o.params.height_scale, 0.8);
    assert_eq!(o.params.offset, [0.5, 0.25]);
    assert_eq!(o.params.normals, relief::NormalMethod::Analytic);
    assert!(o.paused);
    let mut p = AppOptions::default();
    assert_eq!(p.apply_query(&o.to_query()), []);
    assert_eq!(o, p);
}

#[test]
fn bad_entries_are_skipped_and_reported_the_rest_applied() {
    let mut o = AppOptions::default();
    let ignored = o.apply_query("seed=abc&octaves=999&grid=64&colour=red&paused=maybe&gain=0.3");
    let keys: Vec<&str> = ignored.iter().map(|i| i.key.as_str()).collect();
    assert_eq!(keys, ["seed", "octaves", "colour", "paused"]);
    assert_eq!((o.params.grid, o.params.gain), (64, 0.3), "valid keys kept");
    assert_eq!(o.params.seed, TerrainParams::default().seed);
    assert!(!o.paused);
    let unknown = &ignored[2].reason;
    assert!(
        unknown.contains("speed") && unknown.contains("paused"),
        "{unknown}"
    );
    assert!(
        ignored[3].reason.contains("1 or 0"),
        "{}",
        ignored[3].reason
    );
    assert!(ignored[0].reason.contains("abc") && ignored[0].reason.contains("0..=4294967295"));
}

#[test]
fn keys_the_method_does_not_read_are_refused_with_it() {
    let mut o = AppOptions::default();
    let ignored = o.apply_query("seed=3&method=blog&height_scale=0.8");
    assert_eq!(ignored.len(), 1, "{ignored:?}");
    assert_eq!(ignored[0].key, "seed");
    let reason = &ignored[0].reason;
    assert!(
        reason.starts_with("seed does not apply to method blog: "),
        "{reason}"
    );
    assert_eq!(o.method, relief::Method::Blog);
    assert_eq!(o.params.seed, TerrainParams::default().seed);
    assert_eq!(o.params.height_scale, 0.8);
    // Its own URL leaves those keys out, so it reads back without a refusal.
    let q = o.to_query();
    assert!(!q.contains("seed="), "{q}");
    let mut again = AppOptions::default();
    assert_eq!(again.apply_query(&q), [], "{q}");
    assert_eq!(again, o);
    let ignored = AppOptions::default().apply_query("method=raymarch&size=64&grid=64");
    let keys: Vec<&str> = ignored.iter().map(|i| i.key.as_str()).collect();
    assert_eq!(keys, ["size", "grid"], "{ignored:?}");
}

#[test]
fn octaves_and_frequency_are_checked_together_in_any_order() {
    let mut o = AppOptions::default();
    assert_eq!(o.apply_query("octaves=12&frequency=16"), []);
    assert_eq!((o.params.octaves, o.params.frequency), (12, 16));
    let mut o = AppOptions::default();
    let ignored = o.apply_query("frequency=1024&octaves=16");
    assert_eq!(ignored.len(), 1, "{ignored:?}");
    assert_eq!(ignored[0].key, "octaves");
    assert_eq!(o.params.frequency, 1024);
    o.params.validate().unwrap();
    // Only the frequency given: it is the one undone, and named.
    let mut o = AppOptions::default();
    o.params.octaves = 16;
    o.params.frequency = 1;
    let ignored = o.apply_query("frequency=1024");
    assert_eq!(ignored.len(), 1, "{ignored:?}");
    assert_eq!(ignored[0].key, "frequency");
    assert_eq!((o.params.octaves, o.params.frequency), (16, 1));
}

#[test]
fn animated_offsets_stay_short_decimals() {
    let mut o = AppOptions::default();
    for _ in 0..1000 {
        o.advance(1.0 / 61.0);
    }
    for v in o.params.offset {
        let text = v.to_string();
        assert!(text.len() <= 8, "{text}");
    }
    let q = o.to_query();
    let mut p = AppOptions::default();
    p.apply_query(&q);
    assert_eq!(p.params.offset, o.params.offset);
}

#[test]
fn the_temporal_service_is_on_by_default_and_rides_in_the_url_of_either_world() {
    // The tile: a window row like the others.
    let mut o = AppOptions::default();
    assert!(o.temporal);
    assert!(o.to_query().contains("no_temporal=0"), "{}", o.to_query());
    assert!(o.apply_query("no_temporal=1").is_empty());
    assert!(!o.temporal);
    let mut back = AppOptions::default();
    assert!(back.apply_query(&o.to_query()).is_empty());
    assert!(!back.temporal);
    // The endless world: written either way, as its other rows are.
    let mut w = AppOptions::default();
    assert!(w.apply_query("world=endless").is_empty());
    assert!(w.temporal && w.to_query().contains("no_temporal=0"));
    assert!(w.apply_query("world=endless&no_temporal=on").is_empty());
    assert!(!w.temporal);
    assert!(w.to_query().contains("no_temporal=1"), "{}", w.to_query());
    let mut back = AppOptions::default();
    assert!(back.apply_query(&w.to_query()).is_empty());
    assert!(!back.temporal);
    // The window's key sets it through the same row; a bad value names the allowed.
    w.set("no_temporal", "0").unwrap();
    assert!(w.temporal);
    let e = w.set("no_temporal", "maybe").unwrap_err().to_string();
    assert!(e.contains("no_temporal") && e.contains("maybe"), "{e}");
    assert!(url_keys().contains(&"no_temporal"));
}

#[test]
fn the_method_rides_in_the_url_of_either_world() {
    let mut o = AppOptions::default();
    assert!(o.apply_query("method=raymarch").is_empty());
    assert_eq!(o.method, relief::Method::Raymarch);
    assert!(
        o.to_query().ends_with("&method=raymarch"),
        "{}",
        o.to_query()
    );
    // The mesh, the default, is left out of the URL.
    o.set("method", "mesh").unwrap();
    assert!(!o.to_query().contains("method"));
    // The tile does not draw the band-limited march; an unknown name lists the allowed.
    let ignored = o.apply_query("method=raymarch-bandlimited");
    assert_eq!(ignored.len(), 1, "{ignored:?}");
    let reason = &ignored[0].reason;
    assert!(
        reason.contains("raymarch-bandlimited")
            && reason.contains("allowed: mesh, visibility, raymarch"),
        "{ignored:?}"
    );
    assert!(!reason.contains("or raymarch-bandlimited"), "{ignored:?}");
    let e = o.set("method", "rays").unwrap_err().to_string();
    assert!(e.contains("rays") && e.contains("reference"), "{e}");
    assert_eq!(o.method, relief::Method::Mesh);
    let mut w = AppOptions::default();
    assert!(w
        .apply_query("world=endless&method=raymarch-bandlimited")
        .is_empty());
    assert_eq!(w.method, relief::Method::RaymarchBandlimited);
    let q = w.to_query();
    let mut again = AppOptions::default();
    again.apply_query(&q);
    assert_eq!(again.method, w.method, "{q}");
}
