//! A value for each row of the endless world's table that changes its picture from the
//! default's (`cli_endless.rs` renders each through its flag and its scene key).

/// The value the rows test sets `key` to.
pub fn test_value(key: &str) -> &'static str {
    match key {
        "seed" => "8",
        "octaves" => "6",
        "gain" => "0.6",
        "feature_size" => "1024",
        "peak_height" => "900",
        "terrain" => "fbm",
        "pixel_error" => "4",
        "snow_height" => "0.3",
        "ao_exponent" => "3",
        "sun_azimuth" => "300",
        "sun_elevation" => "40",
        "time_of_day" => "7",
        "day_length" => "60",
        "fog" => "0.4",
        "water_level" => "1300",
        "no_water" => "1",
        "palette" => "blog",
        "no_shadows" => "1",
        "clock" => "30",
        "wind_speed" => "12",
        "wind_azimuth" => "90",
        "no_grass" => "1",
        "grass_density" => "8",
        "grass_height" => "1.2",
        "grass_distance" => "12",
        "props" => "1",
        "props_density" => "0.1",
        "props_distance" => "30",
        "cloud_coverage" => "0.5",
        "cloud_base" => "1500",
        "cloud_top" => "7000",
        "cloud_type" => "0.1",
        other => panic!("no test value for {other}: add one"),
    }
}
