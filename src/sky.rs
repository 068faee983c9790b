//! The sky, the sun and aerial perspective: an analytic model, the CPU twin of `sky_light` and
//! `fog` in `wgsl/shade.wgsl` (every constant here has its counterpart there).
//!
//! - **Sky**: a gradient from a zenith colour to a brighter, hazier horizon colour (the haze
//!   band falls off as `exp(-8 y)` with the direction's height `y`), warmed towards the sun when
//!   it is low, a halo around the sun and its disc (0.5° in radius, larger than the real 0.27°
//!   so that it covers a few pixels). Below the horizon the sky is its horizon colour.
//! - **Sun**: set by azimuth (degrees clockwise from north, -z, towards east, +x) and elevation
//!   (degrees above the horizon). Its light is reddened by the air it crosses: transmittance
//!   `exp(-tau (m - 1))` with the Kasten-Young air mass `m`, so a sun at the zenith keeps its
//!   colour and a setting sun goes orange.
//! - **Aerial perspective**: light from terrain at distance `d` keeps `exp(-sigma d)`, with an
//!   extinction `sigma` larger for blue than for red (half Rayleigh, `lambda^-4`, half
//!   wavelength-neutral haze), and gains the sky's light along the same direction (flattened to
//!   the horizon) for the rest: far ridges go blue-grey, brighter towards the sun. Where fog is
//!   on, terrain also fades fully into that sky colour over the last part of the square the
//!   levels draw, so the landscape's end is never an edge.

use glam::Vec3;

/// Extinction per kilometre of red, green and blue for one unit of `fog` (green's): half
/// Rayleigh scattering ((550 nm / lambda)^4 at 680, 550 and 440 nm) and half neutral haze.
pub(crate) const FOG_SPECTRUM: [f32; 3] = [0.714, 1.0, 1.721];
/// Optical depth per air mass of red, green and blue beyond the zenith's, for the sun's colour.
pub(crate) const SUN_TAU: [f32; 3] = [0.02, 0.05, 0.11];
/// [`Sky::time_of_day`] when the sun is placed by azimuth and elevation, not by a time.
pub const NO_TIME: f32 = -1.0;
/// Angular radius of the drawn sun disc, radians (0.5 degrees).
pub const SUN_RADIUS: f32 = 0.008_726_646;
/// How fast the horizon's haze gives way to the zenith colour with the direction's height.
pub(crate) const HAZE_FALLOFF: f32 = 8.0;

/// The sun and the air: what the sky, the sun's light and the fog are made of.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sky {
    /// Degrees clockwise from north (-z) towards east (+x).
    pub sun_azimuth: f32,
    /// Degrees above the horizon (negative: below it, night).
    pub sun_elevation: f32,
    /// Extinction per kilometre of green light; 0 for clear air (no aerial perspective).
    pub fog: f32,
    /// The hour (local solar time, in [0, 24)) the sun stands at (the `day` module of
    /// `world`): where it is set, `sun_azimuth` and `sun_elevation` are the day's at that hour;
    /// [`NO_TIME`] (the default) where the sun is placed by them.
    pub time_of_day: f32,
    /// Seconds of the frame's clock a whole day takes (`day::sky_at`): the sun runs
    /// through the day from `time_of_day` (or the time nearest where it stands); 0 (the
    /// default) holds it still.
    pub day_length: f32,
}

impl Default for Sky {
    /// A low evening sun in the south-east, ahead and to the right of the default camera, so
    /// slopes are modelled by light and shade and the sun's halo is in view; air in which
    /// ridges 30 km away have lost about two thirds of their contrast (chosen by eye).
    fn default() -> Self {
        Self {
            sun_azimuth: 145.0,
            sun_elevation: 12.0,
            fog: 0.03,
            time_of_day: NO_TIME,
            day_length: 0.0,
        }
    }
}

/// The sky's colours for one sun: what `RenderUniforms` carries (linear RGB).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SkyLight {
    /// Unit vector towards the sun.
    pub sun_dir: Vec3,
    /// Sun radiance reaching the ground.
    pub sun: [f32; 3],
    /// Sky at the zenith.
    pub zenith: [f32; 3],
    /// Sky at the horizon.
    pub horizon: [f32; 3],
    /// Glow of a low sun on the horizon towards it; the last entry is how strong it is.
    pub sunset: [f32; 4],
    /// How much daylight the sky holds (1 by day, 0.04 at dusk): what scales the ambient light.
    pub day: f32,
}

/// Unit vector towards a sun at `azimuth` and `elevation` degrees (see [`Sky`]).
pub fn sun_direction(azimuth: f32, elevation: f32) -> Vec3 {
    let (a, e) = (azimuth.to_radians(), elevation.to_radians());
    Vec3::new(a.sin() * e.cos(), e.sin(), -a.cos() * e.cos())
}

fn smoothstep(e0: f32, e1: f32, x: f32) -> f32 {
    let t = ((x - e0) / (e1 - e0)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

fn scale(c: [f32; 3], k: f32) -> [f32; 3] {
    c.map(|v| v * k)
}

impl SkyLight {
    /// The sky for a sun towards `sun_dir` whose light above the air is `sun` (linear).
    pub fn new(sun_dir: Vec3, sun: [f32; 3]) -> Self {
        let s = sun_dir.normalize_or(Vec3::Y);
        let e = s.y.clamp(-1.0, 1.0);
        let deg = e.asin().to_degrees();
        // Kasten and Young's air mass, held at its horizon value below the horizon.
        let m = 1.0 / (e.max(0.0) + 0.50572 * (deg.max(0.0) + 6.07995).powf(-1.6364));
        let up = smoothstep(-0.02, 0.02, e);
        let sun = std::array::from_fn(|i| sun[i] * (-SUN_TAU[i] * (m - 1.0)).exp() * up);
        // Daylight in the sky falls away as the sun goes down, to a faint dusk.
        let day = 0.04 + 0.96 * smoothstep(-0.1, 0.3, e);
        let low = 1.0 - smoothstep(0.0, 0.35, e);
        Self {
            sun_dir: s,
            sun,
            zenith: scale([0.12, 0.25, 0.62], day),
            horizon: scale([0.56, 0.66, 0.80], day),
            sunset: [0.95, 0.55, 0.28, 0.75 * low * smoothstep(-0.12, 0.0, e)],
            day,
        }
    }

    /// Linear radiance of the sky along the unit direction `dir`, with the sun's disc or
    /// without it (the colour fog takes on): the twin of `sky_light` in `wgsl/shade.wgsl`.
    pub fn radiance(&self, dir: Vec3, disc: bool) -> [f32; 3] {
        let haze = (-HAZE_FALLOFF * dir.y.max(0.0)).exp();
        let mu = dir.dot(self.sun_dir).max(0.0);
        let warm = self.sunset[3] * mu * mu * haze;
        let halo = 0.04 * mu.powi(12) + 0.15 * mu.powi(400);
        let glow = if disc {
            10.0 * smoothstep((1.3 * SUN_RADIUS).cos(), SUN_RADIUS.cos(), mu)
                * smoothstep(-0.01, 0.01, dir.y)
        } else {
            0.0
        };
        std::array::from_fn(|i| {
            let base = self.zenith[i] + (self.horizon[i] - self.zenith[i]) * haze;
            let base = base + (self.sunset[i] - base) * warm;
            base + self.sun[i] * (halo + glow)
        })
    }
}

impl Sky {
    /// Unit vector towards the sun.
    pub fn sun_direction(&self) -> Vec3 {
        sun_direction(self.sun_azimuth, self.sun_elevation)
    }

    /// Extinction per world unit (metres) of red, green and blue.
    pub fn extinction(&self) -> [f32; 3] {
        FOG_SPECTRUM.map(|k| k * self.fog * 1e-3)
    }
}

/// The colour `lit` of terrain at distance `d` along unit `dir`, seen through the air: the
/// twin of `fog` in `wgsl/shade.wgsl`, without the fade at the drawn square's edge.
pub fn fogged(
    light: &SkyLight,
    extinction: [f32; 3],
    lit: [f32; 3],
    dir: Vec3,
    d: f32,
) -> [f32; 3] {
    let flat = Vec3::new(dir.x, dir.y.max(0.0), dir.z).normalize_or(Vec3::Y);
    let air = light.radiance(flat, false);
    std::array::from_fn(|i| {
        let t = (-extinction[i] * d).exp();
        lit[i] * t + air[i] * (1.0 - t)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sun_sits_where_azimuth_and_elevation_say() {
        let north = sun_direction(0.0, 0.0);
        assert!((north - Vec3::NEG_Z).length() < 1e-6);
        let east = sun_direction(90.0, 0.0);
        assert!((east - Vec3::X).length() < 1e-6);
        let up = sun_direction(123.0, 90.0);
        assert!((up - Vec3::Y).length() < 1e-6);
    }

    #[test]
    fn a_low_sun_is_redder_and_the_horizon_brighter_than_the_zenith() {
        let high = SkyLight::new(sun_direction(0.0, 80.0), [1.0; 3]);
        let low = SkyLight::new(sun_direction(0.0, 3.0), [1.0; 3]);
        assert!(high.sun[2] / high.sun[0] > 0.99 * (-0.09f32 * 0.02).exp());
        assert!(low.sun[2] / low.sun[0] < 0.5, "{:?}", low.sun);
        let night = SkyLight::new(sun_direction(0.0, -10.0), [1.0; 3]);
        assert_eq!(night.sun, [0.0; 3]);
        for l in [high, low] {
            assert!(l.horizon.iter().sum::<f32>() > l.zenith.iter().sum::<f32>());
            let up = l.radiance(Vec3::Y, true);
            let side = l.radiance(Vec3::new(0.0, 0.0, 1.0), true);
            assert!(side[0] > up[0], "haze at the horizon");
        }
    }

    #[test]
    fn fog_grows_with_distance_and_turns_blue_first() {
        let light = SkyLight::new(sun_direction(200.0, 30.0), [1.0; 3]);
        let sky = Sky::default();
        let dir = Vec3::new(1.0, -0.05, 0.0).normalize();
        let lit = [0.2, 0.15, 0.05];
        let air = light.radiance(Vec3::X, false);
        let mut last = 0.0;
        for d in [0.0, 1e3, 5e3, 2e4, 1e5] {
            let c = fogged(&light, sky.extinction(), lit, dir, d);
            let towards: f32 = (0..3).map(|i| (c[i] - lit[i]).abs()).sum();
            assert!(towards >= last, "{d}");
            last = towards;
            // Blue goes over to the air's colour faster than red.
            let part = |i: usize| (c[i] - lit[i]) / (air[i] - lit[i]);
            if d > 0.0 {
                assert!(part(2) > part(0), "{d}: {c:?}");
            }
        }
        assert_eq!(fogged(&light, [0.0; 3], lit, dir, 1e9), lit);
    }
}
