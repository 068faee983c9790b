//! Grass, first part: where each blade of the endless world's meadow stands and what it is
//! like, and where grass grows. The CPU twin of `wgsl/grass.wgsl`: the GPU's blades are
//! tested against these, cell for cell.
//!
//! - **One blade a cell** of a square grid of side `1 / sqrt(density)` metres over the whole
//!   world. A blade's root within its cell, its height, facing, lean, curve, width, shade and
//!   the threshold it is kept at come from a hash of its cell's 64-bit integer coordinates and
//!   the landscape's seed ([`crate::noise::pcg`], the terrain's hash), so the same blade stands
//!   in the same place however the camera moves, on every device, and as exactly at 10^9 m
//!   from the origin as at the origin (the cell is an integer; nothing is a large float).
//! - **Clumps**: heights vary by a value noise over clumps of whole cells ([`CLUMP_METRES`]
//!   across), so blades grow in patches rather than each on its own.
//! - **Where grass grows** ([`cover`]): where the terrain's material is grass, none on rock,
//!   snow or sand or under water, thinning across each edge with the same noise that moves the
//!   material's edge in the shading (`template_albedo` and `shade_through` in
//!   `wgsl/shade.wgsl`). A blade grows where the cover exceeds its own [`Blade::keep`], so a
//!   cell's blade appears or goes at one place in the transition and the density follows the
//!   cover.
//!
//! Drawing the blades (their geometry, level of detail, wind, the look) comes next.

use crate::error::{Error, Result};

/// Metres across a clump of blades of one height (rounded to whole cells).
pub const CLUMP_METRES: f64 = 3.0;

/// A blade's width at its root, metres, before its own variation (0.7 to 1.3 times).
pub const BLADE_WIDTH: f32 = 0.03;

/// The hash stream of the blades (beside the terrain's height and colour streams).
const BLADE_STREAM: u32 = 0x6772_6173;
/// The hash stream of the clumps' heights.
const CLUMP_STREAM: u32 = 0x636c_756d;

/// The grass's parameters (see the module docs): rows of the endless world's table
/// ([`crate::world::WORLD_PARAMS`]: `no_grass`, `grass_density`, `grass_height`,
/// `grass_distance`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grass {
    /// Whether grass grows (on by default; the `no_grass` key turns it off).
    pub on: bool,
    /// Blades a square metre where every cell grows one.
    pub density: f32,
    /// The mean blade's height, metres.
    pub height: f32,
    /// How far from the eye blades are drawn, metres: they thin from half this distance on,
    /// each blade shrinking away at its own distance ([`Blade::far`]).
    pub distance: f32,
}

impl Default for Grass {
    /// On: 96 blades a square metre (a meadow's sward; SimonDev's Quick_Grass draws about 31, a
    /// lawn), half a metre tall, to 60 m: on a meadow from 1.7 m about a million blades
    /// considered and 113k drawn, as the look wants (docs/results/grass.md).
    fn default() -> Self {
        Self {
            on: true,
            density: 96.0,
            height: 0.5,
            distance: 60.0,
        }
    }
}

impl Grass {
    /// The densities allowed, blades a square metre.
    pub const DENSITY: (f32, f32) = (1.0, 256.0);
    /// The heights allowed, metres.
    pub const HEIGHT: (f32, f32) = (0.05, 2.0);
    /// The draw distances allowed, metres.
    pub const DISTANCE: (f32, f32) = (5.0, 200.0);

    /// Refuses values outside their ranges, naming them.
    pub fn validate(&self) -> Result<()> {
        let check = Error::check_range;
        check("grass_density", self.density, Self::DENSITY)?;
        check("grass_height", self.height, Self::HEIGHT)?;
        check("grass_distance", self.distance, Self::DISTANCE)
    }

    /// Cells on a side of the square around the eye's cell that the draw distance reaches.
    pub fn side(&self) -> u32 {
        2 * (f64::from(self.distance) / self.cell()).ceil() as u32 + 3
    }

    /// The side of a cell, metres: one blade a cell.
    pub fn cell(&self) -> f64 {
        1.0 / f64::from(self.density).sqrt()
    }

    /// Cells across a clump: [`CLUMP_METRES`] in whole cells, at least one.
    pub fn clump_cells(&self) -> u32 {
        ((CLUMP_METRES / self.cell()).round() as u32).max(1)
    }

    /// The blades a ray crosses on average in a field of them per unit of the cotangent of
    /// its elevation above the ground: the density times a mean blade's area (its width and
    /// height, halved as it tapers to its tip) times 2/pi for their random facing. Seen at an
    /// elevation θ the field hides `1 - exp(-field_cover / tan θ)` of the ground: nearly all of
    /// it at a grazing angle, some two fifths from 40 degrees up at the defaults. What the
    /// ground where the blades end shows (`field_share` in `wgsl/shade.wgsl`).
    pub fn field_cover(&self) -> f32 {
        self.density * BLADE_WIDTH * self.height / std::f32::consts::PI
    }

    /// The cell holding the point (x, z), world metres.
    pub fn cell_at(&self, x: f64, z: f64) -> [i64; 2] {
        let s = self.cell();
        [(x / s).floor() as i64, (z / s).floor() as i64]
    }
}

/// One blade, as its cell's hash makes it.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Blade {
    /// Its root within its cell, as fractions of the cell's side along x and z, in [0, 1).
    pub offset: [f32; 2],
    /// Its height, metres.
    pub height: f32,
    /// The direction its face points, radians about the vertical.
    pub facing: f32,
    /// How far its tip leans out, as a fraction of its height (0.15 to 0.5).
    pub lean: f32,
    /// How much of its lean it takes near the root (0: a straight slant, 1: upright, then bent
    /// over at the tip).
    pub curve: f32,
    /// Its width at the root, metres.
    pub width: f32,
    /// Its colour's variation, 0 to 1 (darker and greener to lighter and drier).
    pub shade: f32,
    /// It grows where the cover ([`cover`]) exceeds this, 0 to 1; thinning with distance
    /// compares against it too, so each blade goes at its own distance.
    pub keep: f32,
    /// Where it goes with distance, as a fraction of the draw distance beyond its first half
    /// (0: at half the draw distance, 1: at the draw distance), 0 to 1.
    pub far: f32,
}

/// A hash value as a number in [0, 1): its top 24 bits, exact in f32.
fn unit(h: u32) -> f32 {
    (h >> 8) as f32 * (1.0 / 16_777_216.0)
}

/// The hash of a 64-bit integer cell in `stream`, mixed with the `seed`.
fn cell_hash(cell: [i64; 2], seed: u32, stream: u32) -> u32 {
    use crate::noise::pcg;
    let [i, j] = cell.map(|c| (c as u64 as u32, (c as u64 >> 32) as u32));
    pcg(seed ^ pcg(i.0 ^ pcg(i.1 ^ pcg(j.0 ^ pcg(j.1 ^ stream)))))
}

fn fade(t: f32) -> f32 {
    t * t * (3.0 - 2.0 * t)
}

/// The clump's height factor, 0 to 1, at the point `f` (fractions of the clump) of the clump
/// `clump`: a value noise over the clumps' corners.
fn clump_value(clump: [i64; 2], f: [f32; 2], seed: u32) -> f32 {
    let corner = |dx: i64, dz: i64| {
        unit(cell_hash(
            [clump[0] + dx, clump[1] + dz],
            seed,
            CLUMP_STREAM,
        ))
    };
    let (u, v) = (fade(f[0]), fade(f[1]));
    let bottom = corner(0, 0) + u * (corner(1, 0) - corner(0, 0));
    let top = corner(0, 1) + u * (corner(1, 1) - corner(0, 1));
    bottom + v * (top - bottom)
}

/// The blade of `cell` in the meadow of `grass` over the landscape of `seed`.
pub fn blade(grass: &Grass, seed: u32, cell: [i64; 2]) -> Blade {
    let mut h = cell_hash(cell, seed, BLADE_STREAM);
    let mut next = || {
        h = crate::noise::pcg(h);
        unit(h)
    };
    let offset = [next(), next()];
    let facing = next() * std::f32::consts::TAU;
    let lean = 0.15 + 0.35 * next();
    let curve = next();
    let width = BLADE_WIDTH * (0.7 + 0.6 * next());
    let shade = next();
    let keep = next();
    let far = next();
    let own = next();
    // The clump: whole cells, so where a blade stands in it is exact anywhere.
    let k = i64::from(grass.clump_cells());
    let clump = cell.map(|c| c.div_euclid(k));
    let inside = [0, 1].map(|a| ((cell[a].rem_euclid(k)) as f32 + offset[a]) / k as f32);
    let clumped = clump_value(clump, inside, seed);
    let height = grass.height * (0.4 + 1.2 * clumped) * (0.8 + 0.4 * own);
    Blade {
        offset,
        height,
        facing,
        lean,
        curve,
        width,
        shade,
        keep,
        far,
    }
}

/// What [`cover`] reads of the world's parameters: the snow line, the water and its shore, as
/// the shading has them (`RenderUniforms` in `wgsl/shade.wgsl`;
/// [`crate::world::WorldParams::grass_cover`] makes them).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CoverParams {
    /// The snow line, normalised height.
    pub snow_height: f32,
    /// The water's level, normalised height (`None`: no water, no shore).
    pub water: Option<f32>,
    /// The sand band above the water, normalised height.
    pub sand_band: f32,
}

fn smoothstep(e0: f32, e1: f32, x: f32) -> f32 {
    let t = ((x - e0) / (e1 - e0)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// How much of the ground is grass, 0 to 1, where the surface's normal rises `n_y`, its
/// normalised height is `h` and its colour channel `tint`: the grass material's share in the
/// shading (gentle slopes, fewer towards the snow line), less the snow's and the sand's, none
/// under water.
pub fn cover(p: &CoverParams, n_y: f32, h: f32, tint: f32) -> f32 {
    // As `template_albedo` in wgsl/shade.wgsl: the material's edges moved by the colour noise.
    let jitter = 2.0 * (tint - 0.5);
    let alpine = smoothstep(p.snow_height - 0.12, p.snow_height, h + 0.1 * jitter);
    let gentle = smoothstep(0.6, 0.95, n_y + 0.08 * jitter) * (1.0 - 0.6 * alpine);
    // As `shade_through`: the snow line and the shore.
    let line = p.snow_height + (tint - 0.5) * SNOW_JITTER;
    let snow = smoothstep(line - SNOW_EDGE, line + SNOW_EDGE, h) * smoothstep(0.45, 0.75, n_y);
    let sand = match p.water {
        Some(level) => {
            if h < level {
                return 0.0;
            }
            let top = level + p.sand_band * (0.6 + tint);
            1.0 - smoothstep(top - 0.5 * p.sand_band, top, h)
        }
        None => 0.0,
    };
    gentle * (1.0 - snow) * (1.0 - sand)
}

/// Terra's way with grass, written again from its description as the benchmark's peer: a fixed
/// patch of instanced blades around the eye, every blade of it drawn in four segments (no
/// culling to the view, no level of detail, no widening), thinning toward the patch's edge, at
/// one of its presets of blades; drawn by the GPU's rasteriser (Terra's way) or, to tell the
/// method from the chip, by relief's compute raster.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Peer {
    /// Blades in the patch (at the grass's density: the patch's disc holds this many cells).
    pub blades: u32,
    /// Drawn by the GPU's rasteriser (else by the compute raster, where the method has one).
    pub rasteriser: bool,
}

/// Terra's presets: blades in its patch.
pub const PEER_PRESETS: [u32; 3] = [20_000, 84_000, 500_000];

impl Peer {
    /// The radius of the patch's disc for `grass`'s density, metres.
    pub fn distance(&self, grass: &Grass) -> f32 {
        (f64::from(self.blades) / (std::f64::consts::PI * f64::from(grass.density))).sqrt() as f32
    }
}

/// The wind's gusts: waves along the wind of these wavelengths (metres), travelling downwind at
/// these multiples of the wind's speed, with these amplitudes about a mean of one half.
pub const GUSTS: [(f64, f64, f32); 2] = [(23.0, 1.0, 0.3), (9.0, 1.3, 0.2)];

/// How far a blade's tip is blown downwind, as a fraction of its height, per metre a second of
/// wind at a middling gust; and the most it is blown (a high wind's bend clamped).
pub const BEND_PER_SPEED: f32 = 0.03;
/// See [`BEND_PER_SPEED`].
pub const MAX_BEND: f32 = 0.6;

/// The phase, in turns (0 to 1), of gust wave `wave` at distance `along` metres downwind at
/// time `clock` seconds in a wind of `speed` metres a second.
pub fn gust_phase(wave: usize, along: f64, clock: f64, speed: f64) -> f64 {
    let (length, rate, _) = GUSTS[wave];
    ((along - rate * speed * clock) / length).rem_euclid(1.0)
}

/// How gusty the wind is at `xz` (world metres) at `clock`: 0 to 1, a half on average, the
/// gusts' waves travelling downwind with the air `velocity` (metres a second, x and z).
pub fn gust(velocity: [f64; 2], clock: f64, xz: [f64; 2]) -> f32 {
    let speed = velocity[0].hypot(velocity[1]);
    if speed <= 0.0 {
        return 0.5;
    }
    let along = (xz[0] * velocity[0] + xz[1] * velocity[1]) / speed;
    let mut g = 0.5f32;
    for (i, &(_, _, amplitude)) in GUSTS.iter().enumerate() {
        let turns = gust_phase(i, along, clock, speed);
        g += amplitude * (std::f64::consts::TAU * turns).sin() as f32;
    }
    g
}

/// Where the wind blows the tip of a blade `height` metres tall rooted at `xz` (world metres):
/// downwind by [`BEND_PER_SPEED`] of its height per metre a second, times 0.5 to 1.5 with the
/// gust there, at most [`MAX_BEND`] of its height; metres, x and z.
pub fn wind_tip(velocity: [f64; 2], clock: f64, xz: [f64; 2], height: f32) -> [f32; 2] {
    let speed = velocity[0].hypot(velocity[1]);
    if speed <= 0.0 {
        return [0.0; 2];
    }
    let bend = (BEND_PER_SPEED * speed as f32 * (0.5 + gust(velocity, clock, xz))).min(MAX_BEND);
    let k = bend * height / speed as f32;
    [k * velocity[0] as f32, k * velocity[1] as f32]
}

/// `SNOW_JITTER` and `SNOW_EDGE` of `wgsl/shade.wgsl` (a test reads them there).
pub(crate) const SNOW_JITTER: f32 = 0.12;
pub(crate) const SNOW_EDGE: f32 = 0.025;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_parameters_are_checked_and_a_cell_holds_one_blade() {
        assert!(Grass::default().validate().is_ok());
        for bad in [0.0, -1.0, 1000.0, f32::NAN] {
            let g = Grass {
                density: bad,
                ..Default::default()
            };
            let e = g.validate().unwrap_err().to_string();
            assert!(e.contains("grass_density"), "{e}");
        }
        let g = Grass {
            height: 9.0,
            ..Default::default()
        };
        assert!(g
            .validate()
            .unwrap_err()
            .to_string()
            .contains("grass_height"));
        let g = Grass::default();
        assert!((g.cell() - 1.0 / 96f64.sqrt()).abs() < 1e-12);
        // Clumps of about CLUMP_METRES: 3 m of 0.102 m cells.
        assert_eq!(g.clump_cells(), 29);
        assert_eq!(g.cell_at(-0.01, 0.0), [-1, 0]);
    }

    #[test]
    fn blades_vary_within_their_ranges_and_stand_where_they_stood() {
        let g = Grass::default();
        let mut heights = Vec::new();
        for i in -40..40 {
            for j in -40..40 {
                // Every fifth cell: blades over some 500 clumps.
                let b = blade(&g, 7, [5 * i, 5 * j]);
                assert_eq!(
                    b,
                    blade(&g, 7, [5 * i, 5 * j]),
                    "the same cell, the same blade"
                );
                assert!(b.offset.iter().all(|o| (0.0..1.0).contains(o)));
                assert!((0.15..=0.5).contains(&b.lean));
                assert!((0.0..std::f32::consts::TAU).contains(&b.facing));
                assert!((0.0..1.0).contains(&b.keep) && (0.0..1.0).contains(&b.far));
                assert!(b.height > 0.0 && b.height < 2.0 * g.height, "{b:?}");
                heights.push(b.height);
            }
        }
        let mean = heights.iter().sum::<f32>() / heights.len() as f32;
        assert!(
            (mean - g.height).abs() < 0.1 * g.height,
            "mean height {mean}"
        );
        // Another seed, other blades; cells far from the origin are as varied.
        assert_ne!(blade(&g, 8, [3, 4]), blade(&g, 7, [3, 4]));
        let far = g.cell_at(1e9, -1e9);
        let (a, b) = (blade(&g, 7, far), blade(&g, 7, [far[0] + 1, far[1]]));
        assert_ne!(a.offset, b.offset);
    }

    #[test]
    fn clumps_make_neighbours_alike_and_far_blades_unlike() {
        // Heights of neighbouring blades correlate (they share a clump); of blades a hundred
        // cells apart, hardly.
        let g = Grass::default();
        let correlation = |step: i64| {
            let pairs: Vec<(f32, f32)> = (0..2000)
                .map(|n| {
                    let c = [n * 7 % 500, n * 13 % 500];
                    let d = [c[0] + step, c[1]];
                    (blade(&g, 7, c).height, blade(&g, 7, d).height)
                })
                .collect();
            let m = |f: &dyn Fn(&(f32, f32)) -> f32| pairs.iter().map(f).sum::<f32>() / 2000.0;
            let (ma, mb) = (m(&|p| p.0), m(&|p| p.1));
            let cov = m(&|p| (p.0 - ma) * (p.1 - mb));
            let va = m(&|p| (p.0 - ma).powi(2));
            let vb = m(&|p| (p.1 - mb).powi(2));
            cov / (va * vb).sqrt()
        };
        let (near, far) = (correlation(1), correlation(100));
        assert!(near > 0.5 && far.abs() < 0.15, "near {near}, far {far}");
    }

    #[test]
    fn the_wind_blows_tips_downwind_in_travelling_gusts() {
        let west = [4.0, 0.0];
        let tip = wind_tip(west, 0.0, [10.0, 3.0], 0.5);
        assert!(tip[0] > 0.0 && tip[1] == 0.0, "{tip:?}");
        assert_eq!(wind_tip([0.0, 0.0], 5.0, [1.0, 2.0], 0.5), [0.0, 0.0]);
        // A gale's bend is clamped.
        let gale = wind_tip([60.0, 0.0], 0.0, [0.0, 0.0], 1.0);
        assert!((gale[0] - MAX_BEND).abs() < 1e-6, "{gale:?}");
        // The gusts travel downwind, each wave at its own multiple of the wind's speed: what
        // was at x at 0 s is at x + rate v t at t.
        for (i, &(_, rate, _)) in GUSTS.iter().enumerate() {
            let (a, b) = (
                gust_phase(i, 3.0, 0.0, 4.0),
                gust_phase(i, 3.0 + rate * 4.0 * 2.0, 2.0, 4.0),
            );
            assert!((a - b).abs() < 1e-9, "wave {i}: {a} {b}");
        }
        // Between 0 and 1, a half on average.
        let g: Vec<f32> = (0..1000)
            .map(|i| gust(west, 0.0, [0.37 * i as f64, 0.0]))
            .collect();
        assert!(g.iter().all(|v| (0.0..=1.0).contains(v)));
        let mean = g.iter().sum::<f32>() / 1000.0;
        assert!((mean - 0.5).abs() < 0.05, "{mean}");
    }

    #[test]
    fn grass_grows_on_gentle_ground_and_not_on_rock_snow_sand_or_under_water() {
        let p = CoverParams {
            snow_height: 0.63,
            water: Some(0.2),
            sand_band: 0.01,
        };
        let meadow = cover(&p, 1.0, 0.35, 0.5);
        assert!(meadow > 0.99, "{meadow}");
        assert_eq!(cover(&p, 0.5, 0.35, 0.5), 0.0, "a cliff is rock");
        assert_eq!(cover(&p, 1.0, 0.8, 0.5), 0.0, "snow");
        assert_eq!(cover(&p, 1.0, 0.19, 0.5), 0.0, "under water");
        assert_eq!(cover(&p, 1.0, 0.2 + 0.003, 0.5), 0.0, "the shore is sand");
        // The edges thin: between a meadow and rock the cover falls steadily.
        let slope: Vec<f32> = (0..=10)
            .map(|k| cover(&p, 0.95 - 0.035 * k as f32, 0.35, 0.5))
            .collect();
        assert!(slope.windows(2).all(|w| w[1] <= w[0]), "{slope:?}");
        assert!(slope[5] > 0.05 && slope[5] < 0.95, "{slope:?}");
        // No water: no shore.
        let dry = CoverParams { water: None, ..p };
        assert!(cover(&dry, 1.0, 0.1, 0.5) > 0.99);
    }
}
