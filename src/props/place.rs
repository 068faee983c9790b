//! Where props stand: at most one a cell of a square grid over the whole world, its kind, place
//! in the cell, turn, scale and shade from a hash of the cell's 64-bit integer coordinates and
//! the landscape's seed (as the grass's blades: the same props at the same places wherever the
//! camera goes, as exactly at 10^9 m as at the origin). The CPU twin of `wgsl/props.wgsl`'s
//! `prop_at` and `prop_keeps`.
//!
//! - A cell's prop stands where its chance is under the density the ground allows
//!   ([`Props::density`] on gentle ground, [`Props::rock_density`] on steep rock for the
//!   kinds that stand there), never under water.
//! - A prop stands on the surface the frame draws, sunk below its lowest point under the prop's
//!   foot (the kinds reach below their origin), so it floats in no method.
//! - A prop is no wider than half a cell ([`Props::check_fits`]), so a point's props are
//!   those of the 2x2 cells nearest it: the march looks at those and no others.
//! - Props at explicit places ([`super::Scene::placed`]) stand where they are put, in water too.

use super::{Kind, Tape};
use crate::error::{Error, Result};

/// The hash stream of the props.
pub const PROP_STREAM: u32 = 0x7072_6f70;

/// How props are scattered over the world: rows of the endless world's table
/// ([`crate::world::WORLD_PARAMS`]: `props`, `props_density`, ...). What they are is the
/// [`super::Scene`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Props {
    /// Whether props stand in the world.
    pub on: bool,
    /// The side of a cell, metres: at most one prop a cell, no wider than half of it.
    pub cell: f32,
    /// The chance that a cell on gentle ground holds a prop, 0 to 1.
    pub density: f32,
    /// The chance that a cell on steep rock holds one (of the kinds that stand there), 0 to 1.
    pub rock_density: f32,
    /// The tallest a prop may stand above its foot, metres.
    pub band: f32,
    /// How far from the eye props are drawn, metres.
    pub distance: f32,
    /// A prop smaller than this on screen (its height, pixels) sinks into the ground over the
    /// next halving of its size, each at its own threshold (0.7 to 1.3 times this).
    pub cutoff: f32,
}

/// A prop put at a given place.
#[derive(Clone, Debug, PartialEq)]
pub struct Placed {
    /// Its kind: an index into the scene's kinds.
    pub kind: u32,
    /// World x, z, metres.
    pub at: [f64; 2],
    /// Degrees about the vertical.
    pub turn: f32,
    /// Times the kind's size.
    pub scale: f32,
}

impl Default for Props {
    /// Off; when on, a prop in about one cell of three on gentle ground, cells of 8 m, drawn to
    /// 1200 m.
    fn default() -> Self {
        Self {
            on: false,
            cell: 8.0,
            density: 0.35,
            rock_density: 0.05,
            band: 12.0,
            distance: 1200.0,
            cutoff: 1.5,
        }
    }
}

impl Props {
    /// The cell sizes allowed, metres.
    pub const CELL: (f32, f32) = (2.0, 64.0);
    /// The bands allowed, metres.
    pub const BAND: (f32, f32) = (0.5, 64.0);
    /// The draw distances allowed, metres.
    pub const DISTANCE: (f32, f32) = (10.0, 4000.0);
    /// The cut-offs allowed, pixels.
    pub const CUTOFF: (f32, f32) = (0.25, 16.0);

    /// Refuses values outside their ranges, naming them.
    pub fn validate(&self) -> Result<()> {
        let check = Error::check_range;
        check("props_cell", self.cell, Self::CELL)?;
        check("props_density", self.density, (0.0, 1.0))?;
        check("props_rock_density", self.rock_density, (0.0, 1.0))?;
        check("props_band", self.band, Self::BAND)?;
        check("props_distance", self.distance, Self::DISTANCE)?;
        check("props_cutoff", self.cutoff, Self::CUTOFF)
    }

    /// Refuses props at given places whose numbers are not finite or whose scale is not > 0.
    pub fn validate_placed(placed: &[Placed]) -> Result<()> {
        for (i, p) in placed.iter().enumerate() {
            if !p.at.iter().all(|v| v.is_finite()) || !p.turn.is_finite() {
                return Err(Error::invalid(
                    format!("prop_place[{i}]"),
                    format!("at {:?} turned {}", p.at, p.turn),
                    "finite numbers",
                ));
            }
            if !(p.scale.is_finite() && p.scale > 0.0) {
                return Err(Error::invalid(
                    format!("prop_place[{i}].scale"),
                    p.scale,
                    "a finite scale > 0",
                ));
            }
        }
        Ok(())
    }

    /// Refuses a kind wider than half a cell or taller than the band at its largest scale
    /// (explicit props at their own scale).
    pub fn check_fits(
        &self,
        kind: &Kind,
        tape: &Tape,
        (index, placed): (u32, &[Placed]),
    ) -> Result<()> {
        let mut largest = f64::from(kind.scale.1);
        for p in placed.iter().filter(|p| p.kind == index) {
            largest = largest.max(f64::from(p.scale));
        }
        let wide = tape.radius() * largest;
        let half = f64::from(self.cell) / 2.0;
        if wide > half {
            return Err(Error::invalid(
                format!("prop_kinds.{}", kind.name),
                format!("{:.2} m from its axis at scale {largest}", wide),
                format!("at most half the cell, {half} m (props_cell)"),
            ));
        }
        let tall = tape.bounds[1][1] * largest;
        if tall > f64::from(self.band) {
            return Err(Error::invalid(
                format!("prop_kinds.{}", kind.name),
                format!("{tall:.2} m tall at scale {largest}"),
                format!("at most the band, {} m (props_band)", self.band),
            ));
        }
        Ok(())
    }

    /// The cell holding the point (x, z), world metres.
    pub fn cell_at(&self, x: f64, z: f64) -> [i64; 2] {
        let s = f64::from(self.cell);
        [(x / s).floor() as i64, (z / s).floor() as i64]
    }
}

/// A cell's prop as its hash makes it, before the ground decides whether it stands.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Prop {
    /// Its kind, an index into the scene's kinds.
    pub kind: u32,
    /// Where it stands within its cell, fractions of the side along x and z, in [0, 1).
    pub offset: [f32; 2],
    /// Radians about the vertical.
    pub turn: f32,
    /// Times its kind's size.
    pub scale: f32,
    /// Its own shade, 0 to 1 (varies its materials).
    pub shade: f32,
    /// It stands where this is under the density the ground allows, 0 to 1.
    pub chance: f32,
    /// Its screen-size threshold, times [`Props::cutoff`] (0.7 to 1.3).
    pub cutoff: f32,
    /// What varies its displacements' noise.
    pub seed: u32,
}

/// A hash value as a number in [0, 1): its top 24 bits, exact in f32.
fn unit(h: u32) -> f32 {
    (h >> 8) as f32 * (1.0 / 16_777_216.0)
}

/// The hash of a 64-bit integer cell, mixed with the seed.
fn cell_hash(cell: [i64; 2], seed: u32) -> u32 {
    use crate::noise::pcg;
    let [i, j] = cell.map(|c| (c as u64 as u32, (c as u64 >> 32) as u32));
    pcg(seed ^ pcg(i.0 ^ pcg(i.1 ^ pcg(j.0 ^ pcg(j.1 ^ PROP_STREAM)))))
}

/// The kinds' cumulative weights, normalised to end at 1 (all 0: the first kind always).
pub fn cumulative(kinds: &[Kind]) -> Vec<f32> {
    let total: f32 = kinds.iter().map(|k| k.weight).sum();
    let mut acc = 0.0;
    kinds
        .iter()
        .map(|k| {
            acc += k.weight;
            if total > 0.0 {
                acc / total
            } else {
                1.0
            }
        })
        .collect()
}

/// The prop of `cell` for kinds of cumulative weights `weights` ([`cumulative`]) over the
/// landscape of `seed`.
pub fn prop_at(weights: &[f32], seed: u32, cell: [i64; 2]) -> Prop {
    let mut h = cell_hash(cell, seed);
    let mut next = || {
        h = crate::noise::pcg(h);
        unit(h)
    };
    let chance = next();
    let pick = next();
    let kind = weights
        .iter()
        .position(|&w| pick < w)
        .unwrap_or(weights.len().saturating_sub(1)) as u32;
    let offset = [next(), next()];
    let turn = next() * std::f32::consts::TAU;
    let size = next();
    let shade = next();
    let cutoff = 0.7 + 0.6 * next();
    let seed = crate::noise::pcg(h ^ 0x5eed);
    Prop {
        kind,
        offset,
        turn,
        scale: size,
        shade,
        chance,
        cutoff,
        seed,
    }
}

/// The share of the ground that is gentle (not rock) where the surface's normal rises `n_y`
/// and its colour channel is `tint`: the grass material's edge in the shading
/// (`template_albedo` in `wgsl/shade.wgsl`, without the snow line's thinning).
pub fn gentle(n_y: f32, tint: f32) -> f32 {
    let jitter = 2.0 * (tint - 0.5);
    let t = ((n_y + 0.08 * jitter - 0.6) / 0.35).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// Whether a cell's `prop` of a kind that stands on rock (`on_rock`) stands where the ground's
/// normal rises `n_y`, its colour channel is `tint` and its normalised height `h` (under the
/// water's normalised `water` level: none).
pub fn keeps(
    p: &Props,
    prop: &Prop,
    on_rock: bool,
    (n_y, tint, h): (f32, f32, f32),
    water: Option<f32>,
) -> bool {
    if water.is_some_and(|level| h < level) {
        return false;
    }
    let g = gentle(n_y, tint);
    let rock = if on_rock { p.rock_density } else { 0.0 };
    prop.chance < p.density * g + rock * (1.0 - g)
}

/// A prop's size (0 to 1 within the kind's range) as a scale.
pub fn scale_of(kind: &Kind, size: f32) -> f32 {
    kind.scale.0 + (kind.scale.1 - kind.scale.0) * size
}
