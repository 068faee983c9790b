//! Sunlight over the endless world's terrain: soft shadows and valley occlusion, as the shading
//! uses them (`sun_visibility` and `valley_occlusion` in `wgsl/shade.wgsl`), and the truth they
//! are measured against: an f64 ray towards the sun over the continuous surface of the CPU twin
//! ([`lit_by_ray`]).
//!
//! - **Shadows** come from the horizon: the steepest elevation at which the terrain rises
//!   towards the sun's azimuth as seen from a point. The sun lights the point where it stands
//!   above that elevation, through a penumbra as wide as its disc ([`sun_visibility`]). The mesh
//!   bakes the horizon per level texel in compute (`wgsl/world_light.wgsl`) whenever a level is
//!   baked or the sun turns; moving the sun up or down bakes nothing. The ray casters march a
//!   ray towards the sun from each pixel's point over the continuous surface.
//! - **Valley occlusion** darkens ground that lies below its surroundings (the mean height on a
//!   ring [`VALLEY_RADIUS`] metres around it), so valley floors and gullies get less sky, while
//!   low but open ground (a beach, a plain) does not: the blog's height occlusion `h^k`
//!   darkened all low ground alike.

use crate::landscape::Landscape;
use crate::sky::SUN_RADIUS;

/// Steps per doubling of the distance in the horizon march: the step at distance `t` is
/// `t / STEPS_PER_DOUBLING` (at least a level spacing), so a feature that subtends more than
/// about that angle is not stepped over.
pub(crate) const STEPS_PER_DOUBLING: f32 = 16.0;
/// Radius in metres of the ring whose mean height a point's valley depth is measured against.
pub const VALLEY_RADIUS: f32 = 256.0;
/// The valley depth (metres below the ring's mean) at which occlusion is full, as a fraction of
/// [`VALLEY_RADIUS`]: a hollow whose sides average a slope of a half.
pub const VALLEY_DEPTH: f32 = 0.5;
/// What full occlusion leaves of the ambient light.
pub const VALLEY_FLOOR: f32 = 0.35;

fn smoothstep(e0: f64, e1: f64, x: f64) -> f64 {
    let t = ((x - e0) / (e1 - e0)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// How much of the sun's disc a point sees (0..=1) where the terrain's horizon towards the sun
/// stands at `horizon` radians and the sun at `elevation` radians: half at the disc's centre,
/// a penumbra [`SUN_RADIUS`] either side.
pub fn sun_visibility(horizon: f64, elevation: f64) -> f64 {
    let w = f64::from(SUN_RADIUS);
    smoothstep(-w, w, elevation - horizon)
}

/// What reaches a point of the ambient light (`VALLEY_FLOOR..=1`) where it lies `valley` metres
/// above the mean height of its surroundings (negative: below).
pub fn valley_occlusion(valley: f64) -> f64 {
    let r = f64::from(VALLEY_RADIUS);
    let open = smoothstep(-f64::from(VALLEY_DEPTH) * r, 0.1 * r, valley);
    f64::from(VALLEY_FLOOR) + (1.0 - f64::from(VALLEY_FLOOR)) * open
}

/// Whether the point of the continuous surface at (x, z) sees the centre of a sun at
/// `azimuth` and `elevation` (radians; azimuth clockwise from -z towards +x), within
/// `max_distance` metres horizontally: an f64 ray over every octave, its steps bounded by the
/// surface's slope bound (`slope`, metres per metre: [`Landscape::slope_bounds`]'s last entry)
/// so that it cannot pass through a ridge, however thin.
pub fn lit_by_ray(
    land: &Landscape,
    (x, z): (f64, f64),
    (azimuth, elevation): (f64, f64),
    slope: f64,
    max_distance: f64,
) -> bool {
    lit_beyond(
        land,
        (x, z),
        (azimuth, elevation),
        slope,
        (0.0, max_distance),
    )
}

/// [`lit_by_ray`] for occluders from `near` to `max_distance` metres along the ray only:
/// what a march that takes its first sample `near` metres out can see.
pub fn lit_beyond(
    land: &Landscape,
    (x, z): (f64, f64),
    (azimuth, elevation): (f64, f64),
    slope: f64,
    (near, max_distance): (f64, f64),
) -> bool {
    let y0 = land.height_at(x, z);
    lit_from(
        land,
        (x, y0, z),
        (azimuth, elevation),
        slope,
        (near, max_distance),
    )
}

/// Whether the point (x, y, z) of the air sees the centre of the sun past the continuous
/// surface within `max_distance` metres horizontally: [`lit_by_ray`]'s f64 ray from the point
/// itself, the truth the light shafts' shadow-height map is measured against (a point under
/// the surface sees none).
pub fn air_lit_by_ray(
    land: &Landscape,
    (x, y, z): (f64, f64, f64),
    (azimuth, elevation): (f64, f64),
    slope: f64,
    max_distance: f64,
) -> bool {
    y >= land.height_at(x, z)
        && lit_from(
            land,
            (x, y, z),
            (azimuth, elevation),
            slope,
            (0.0, max_distance),
        )
}

/// The f64 ray towards the sun from (x, y0, z), for occluders from `near` to `max_distance`
/// metres along it.
fn lit_from(
    land: &Landscape,
    (x, y0, z): (f64, f64, f64),
    (azimuth, elevation): (f64, f64),
    slope: f64,
    (near, max_distance): (f64, f64),
) -> bool {
    if elevation <= 0.0 {
        return false;
    }
    let (dx, dz) = (azimuth.sin(), -azimuth.cos());
    let (ce, se) = (elevation.cos(), elevation.sin());
    let top = land.peak_height;
    // How fast the clearance can shrink per metre along the ray.
    let rate = slope * ce - se;
    // The first steps are fixed and small: the ray leaves the surface at the point itself.
    let floor = 1e-3 * land.cell(land.octaves.saturating_sub(1));
    let mut t = floor.max(near);
    loop {
        let (px, pz, py) = (x + t * ce * dx, z + t * ce * dz, y0 + t * se);
        if py > top || t * ce > max_distance {
            return true;
        }
        let clearance = py - land.height_at(px, pz);
        if clearance <= 0.0 {
            return false;
        }
        t += if rate > 0.0 {
            (clearance / rate).max(floor)
        } else {
            // A ray rising faster than any slope can never be caught.
            return true;
        };
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::landscape::TerrainFn;

    #[test]
    fn visibility_is_half_at_the_horizon_and_whole_a_disc_above_it() {
        let w = f64::from(SUN_RADIUS);
        assert_eq!(sun_visibility(0.1, 0.1), 0.5);
        assert_eq!(sun_visibility(0.1, 0.1 + w), 1.0);
        assert_eq!(sun_visibility(0.1, 0.1 - w), 0.0);
        assert_eq!(valley_occlusion(100.0), 1.0);
        assert_eq!(valley_occlusion(-1000.0), f64::from(VALLEY_FLOOR));
    }

    #[test]
    fn the_twins_constants_are_the_shadings() {
        let wgsl = crate::gpu::shader::file("shade").unwrap();
        for (name, value) in [
            ("VALLEY_RADIUS", VALLEY_RADIUS),
            ("VALLEY_DEPTH", VALLEY_DEPTH),
            ("VALLEY_FLOOR", VALLEY_FLOOR),
        ] {
            let line = format!("const {name}: f32 = {value:?};");
            assert!(wgsl.contains(&line), "shade.wgsl lacks `{line}`");
        }
    }

    #[test]
    fn a_high_sun_lights_more_ground_than_a_low_one() {
        let land = Landscape {
            seed: 3,
            octaves: 7,
            gain: 0.5,
            feature_log2: 8,
            peak_height: 150.0,
            terrain: TerrainFn::Fbm,
            period: 0,
        };
        let slope = *land.slope_bounds().last().unwrap();
        let lit = |e: f64| {
            (0..200)
                .filter(|i| {
                    let (x, z) = (f64::from(*i) * 7.3, f64::from(*i % 13) * 11.1);
                    lit_by_ray(&land, (x, z), (2.0, e.to_radians()), slope, 2000.0)
                })
                .count()
        };
        let (low, high) = (lit(3.0), lit(40.0));
        assert!(low < high, "lit at 3°: {low}, at 40°: {high}");
        assert!(high > 150 && low < 150, "lit at 3°: {low}, at 40°: {high}");
        assert_eq!(lit(-1.0), 0);
    }
}
