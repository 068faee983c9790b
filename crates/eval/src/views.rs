//! The views every benchmark measures: three named landscape views (along the ground to the
//! horizon, grazing over a ridge, high and oblique), chosen by eye, and a set of random views
//! fixed by a seed in the code, over several landscapes, so that what was tuned on the named
//! views is also measured where nobody tuned it.

use glam::DVec3;
use relief::world::WorldParams;
use relief::WorldView;

/// A landscape view.
#[derive(Clone, Copy, Debug)]
pub struct LandscapeView {
    /// Its name in the CSV.
    pub name: &'static str,
    /// The camera (size filled in per run).
    pub view: WorldView,
    /// The landscape's seed it looks at; `None`: the scene's.
    pub seed: Option<u32>,
}

impl LandscapeView {
    /// The scene `params` as this view sees it (its landscape's seed).
    pub fn params(&self, params: &WorldParams) -> WorldParams {
        let mut p = *params;
        if let Some(seed) = self.seed {
            p.land.seed = seed;
        }
        p
    }
}

/// The benchmark's named views of `params`' world at `size`.
pub fn views(params: &WorldParams, size: (u32, u32)) -> Vec<LandscapeView> {
    let land = params.land;
    let fov = 45f32.to_radians();
    let ground = |x: f64, z: f64| land.height_at(x, z);
    // Along the ground: 2 m above it, looking level, to the horizon.
    let eye = DVec3::new(0.0, ground(0.0, 0.0) + 2.0, 0.0);
    let horizon = WorldView::look_at(eye, eye + DVec3::new(1.0, -0.01, 0.2), fov, size);
    // Grazing over a ridge: the highest point on a 4 km line, 5 m above it, looking level.
    let (mut best, mut top) = (0.0, f64::MIN);
    for i in 0..400 {
        let x = 3000.0 + f64::from(i) * 10.0;
        let h = ground(x, 1000.0);
        if h > top {
            (best, top) = (x, h);
        }
    }
    let eye = DVec3::new(best, top + 5.0, 1000.0);
    let ridge = WorldView::look_at(eye, eye + DVec3::new(0.3, -0.02, 1.0), fov, size);
    // High and oblique: 3 km above the ground, 30 degrees down.
    let eye = DVec3::new(-5000.0, ground(-5000.0, 2000.0) + 3000.0, 2000.0);
    let oblique = WorldView::look_at(eye, eye + DVec3::new(0.8, -0.5, 0.33), fov, size);
    [("horizon", horizon), ("ridge", ridge), ("oblique", oblique)]
        .map(|(name, view)| LandscapeView {
            name,
            view,
            seed: None,
        })
        .to_vec()
}

/// The names of the random views, in order ([`random_views`]).
pub const RANDOM_VIEWS: [&str; 16] = [
    "random-1",
    "random-2",
    "random-3",
    "random-4",
    "random-5",
    "random-6",
    "random-7",
    "random-8",
    "random-9",
    "random-10",
    "random-11",
    "random-12",
    "random-13",
    "random-14",
    "random-15",
    "random-16",
];

/// The seed the random views are drawn from: fixed, so that every run measures the same views.
pub const RANDOM_VIEW_SEED: u64 = 0x7e11_2a1e_5eed;

/// Landscapes the random views are spread over: the scene's seed and the next three, four
/// views each.
pub const RANDOM_LANDSCAPES: u32 = 4;

/// Lowest and highest eye above the ground (or the water), metres: log-uniform between.
pub const RANDOM_HEIGHTS: (f64, f64) = (2.0, 5000.0);

/// Lowest and highest pitch, degrees (negative: down): uniform between.
pub const RANDOM_PITCH: (f64, f64) = (-45.0, 5.0);

/// [`RANDOM_VIEWS`] at `size`, drawn from [`RANDOM_VIEW_SEED`] over [`RANDOM_LANDSCAPES`]
/// landscapes (`params`' seed and the next ones): each eye somewhere in a 40 km square
/// around the origin, [`RANDOM_HEIGHTS`] above the ground or the water (log-uniform), looking
/// along a uniform heading, pitched within [`RANDOM_PITCH`] (uniform).
pub fn random_views(params: &WorldParams, size: (u32, u32)) -> Vec<LandscapeView> {
    let mut state = RANDOM_VIEW_SEED;
    // splitmix64: a uniform f64 in [0, 1) per call.
    let mut uniform = move || {
        state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    };
    let per_landscape = RANDOM_VIEWS.len() as u32 / RANDOM_LANDSCAPES;
    RANDOM_VIEWS
        .iter()
        .enumerate()
        .map(|(i, &name)| {
            let seed = params.land.seed.wrapping_add(i as u32 / per_landscape);
            let mut p = *params;
            p.land.seed = seed;
            let floor = |x: f64, z: f64| {
                let ground = p.land.height_at(x, z);
                if p.no_water {
                    ground
                } else {
                    ground.max(f64::from(p.water_level))
                }
            };
            let (x, z) = (40_000.0 * (uniform() - 0.5), 40_000.0 * (uniform() - 0.5));
            let (low, high) = RANDOM_HEIGHTS;
            let above = low * (high / low).powf(uniform());
            let heading = std::f64::consts::TAU * uniform();
            let (down, up) = RANDOM_PITCH;
            let pitch = (down + (up - down) * uniform()).to_radians();
            let eye = DVec3::new(x, floor(x, z) + above, z);
            let ahead = DVec3::new(
                heading.sin() * pitch.cos(),
                pitch.sin(),
                -heading.cos() * pitch.cos(),
            );
            LandscapeView {
                name,
                view: WorldView::look_at(eye, eye + ahead, 45f32.to_radians(), size),
                seed: Some(seed),
            }
        })
        .collect()
}

/// The named and random views of `params`' world at `size` called `names` (each once, in the
/// order given); an error names the first unknown one and the names allowed.
pub fn views_named(
    params: &WorldParams,
    size: (u32, u32),
    names: &[String],
) -> relief::error::Result<Vec<LandscapeView>> {
    let all: Vec<LandscapeView> = views(params, size)
        .into_iter()
        .chain(random_views(params, size))
        .collect();
    let mut chosen: Vec<LandscapeView> = Vec::new();
    for name in names {
        let Some(v) = all.iter().find(|v| v.name == name.trim()) else {
            let allowed: Vec<&str> = all.iter().map(|v| v.name).collect();
            return Err(relief::error::Error::invalid(
                "--view",
                name,
                allowed.join(", "),
            ));
        };
        if !chosen.iter().any(|c| c.name == v.name) {
            chosen.push(*v);
        }
    }
    Ok(chosen)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_random_views_are_the_same_every_run_and_stand_above_the_ground() {
        let params = WorldParams::default();
        let (a, b) = (
            random_views(&params, (64, 36)),
            random_views(&params, (64, 36)),
        );
        assert_eq!(a.len(), RANDOM_VIEWS.len());
        let mut seeds = Vec::new();
        for (x, y) in a.iter().zip(&b) {
            assert_eq!(
                x.view.eye, y.view.eye,
                "{}: drawn from a fixed seed",
                x.name
            );
            let p = x.params(&params);
            seeds.push(p.land.seed);
            let e = x.view.eye;
            let floor = p.land.height_at(e.x, e.z).max(f64::from(p.water_level));
            assert!(
                e.y >= floor + RANDOM_HEIGHTS.0 - 0.01 && e.y <= floor + RANDOM_HEIGHTS.1 + 0.01,
                "{}: {e}",
                x.name
            );
            let pitch = f64::from(x.view.forward.y).asin().to_degrees();
            assert!((-45.01..=5.01).contains(&pitch), "{}: {pitch}", x.name);
        }
        seeds.dedup();
        assert_eq!(seeds.len(), RANDOM_LANDSCAPES as usize, "{seeds:?}");
        // Spread over the square and over heights, not bunched.
        let xs: Vec<f64> = a.iter().map(|v| v.view.eye.x).collect();
        let spread = xs.iter().cloned().fold(f64::MIN, f64::max)
            - xs.iter().cloned().fold(f64::MAX, f64::min);
        assert!(spread > 5_000.0, "{xs:?}");
    }
}
