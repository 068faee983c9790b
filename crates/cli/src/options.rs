//! docs/cli.md's table of options, written from the parameter tables so that a test can hold
//! the page to the code.

use crate::{BENCH_SWEEPS, HEIGHT_REFUSES, TILE_ONLY};
use relief::params::{params, TerrainParams};
use relief::table::{Kind, Param};
use relief::world::{WorldParams, WORLD_PARAMS};
use relief_app::{AppOptions, OPTIONS};

/// docs/cli.md's table of options: one row per parameter of both tables (flag, meaning,
/// default, allowed, where it applies), so the docs are checked against the code.
pub fn options_markdown() -> String {
    fn row<T>(p: &Param<T>, default: &T, applies: &str) -> String {
        let value = match p.kind {
            Kind::Bool => String::new(),
            Kind::Pair { .. } => " X,Y".to_owned(),
            Kind::Choice(_) => " NAME".to_owned(),
            Kind::Int { .. } => " N".to_owned(),
            Kind::Float { .. } => " X".to_owned(),
        };
        let default = match p.kind {
            Kind::Bool => "off".to_owned(),
            _ => (p.get)(default).to_string(),
        };
        let allowed = match p.kind {
            Kind::Bool => "a flag (in URLs: 1 or 0)".to_owned(),
            _ => p.allowed(),
        };
        format!(
            "| `--{}{value}` | {} | {default} | {allowed} | {applies} |\n",
            p.flag(),
            p.doc,
        )
    }
    let mut out = String::from(
        "| option | meaning | default | allowed | applies to |\n| --- | --- | --- | --- | --- |\n",
    );
    let scene = TerrainParams::default();
    for p in params() {
        let applies = if BENCH_SWEEPS.contains(&p.key) {
            "window, render, bake, scene files, URL (bench sweeps it)"
        } else if HEIGHT_REFUSES.contains(&p.key) {
            "window, render, bake, bench, scene files, URL"
        } else {
            "every command, scene files, URL"
        };
        let applies = if TILE_ONLY.contains(&p.key) {
            format!("{applies}; tile world only")
        } else {
            format!("{applies}; both worlds")
        };
        out.push_str(&row(p, &scene, &applies));
    }
    let world = WorldParams::default();
    for p in WORLD_PARAMS
        .iter()
        .filter(|p| relief::params::param(p.key).is_none())
    {
        let applies = match p.key {
            "pixel_error" => "render --world endless",
            "sun_azimuth" | "sun_elevation" | "time_of_day" | "day_length" | "fog"
            | "water_level" | "no_water" | "palette" | "no_shadows" | "clock" | "wind_speed"
            | "wind_azimuth" | "no_grass" | "grass_density" | "grass_height" | "grass_distance"
            | "cloud_coverage" | "cloud_base" | "cloud_top" | "cloud_type" => {
                "window, render, scene files, URL --world endless"
            }
            _ => "render, height --world endless",
        };
        out.push_str(&row(p, &world, applies));
    }
    let app = AppOptions::default();
    for p in &OPTIONS {
        out.push_str(&row(p, &app, "window, URL"));
    }
    out
}
