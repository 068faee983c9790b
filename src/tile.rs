//! The seed blog's tile as a bounded piece of a periodic landscape, so the clipmap renderer
//! ([`crate::gpu::world::World`]) draws it as it draws the endless world.
//!
//! The tile's fBm ([`crate::noise::Fbm`]) is a [`Landscape`] whose lattice wraps every
//! `frequency << o` cells at octave `o` ([`Landscape::period`]): the same hash, gradients, fade
//! and normalisation, so its heights are the tile's to rounding (tested below). One tile unit
//! is `TileFrame::unit` metres, chosen so that octave 0's cell is a power of two of metres, as
//! the landscape's integer lattice split needs. The image does not depend on that scale: a
//! perspective view scaled with the scene is the same view.
//!
//! The tile `[-1, 1]²` (tile units) lies at `[origin - P/2, origin + P/2]²` metres, P the period;
//! the scroll offset moves `origin` through the landscape, so scrolling is the camera moving
//! over it: only the strips it uncovers are baked.

use glam::DVec3;

use crate::landscape::{Landscape, TerrainFn};
use crate::params::TerrainParams;

/// log2 of the period in metres the tile is laid out at (before the power-of-two rounding of
/// octave 0's cell): about 4 km, the endless world's default ridge spacing.
pub(crate) const PERIOD_LOG2: i32 = 12;

/// Where the tile lies in its periodic landscape.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct TileFrame {
    /// The tile's terrain: periodic fBm in metres.
    pub land: Landscape,
    /// Metres per tile unit (the tile is 2 units wide, one period).
    pub unit: f64,
    /// World x and z, in metres, of the tile's centre (tile x = z = 0).
    pub origin: [f64; 2],
}

impl TileFrame {
    /// The frame of validated `params`, scrolled to `offset` (tiles).
    pub fn new(params: &TerrainParams, offset: [f64; 2]) -> Self {
        // Octave 0's cell: the period over `frequency`, rounded to a power of two, no finer than
        // the landscape's finest cell allows (2^-7 m at the last octave).
        let freq_log2 = f64::from(params.frequency).log2().round() as i32;
        let least = params.octaves as i32 - 1 + crate::world::MIN_CELL_LOG2;
        let feature_log2 = (PERIOD_LOG2 - freq_log2).max(least);
        let period = f64::from(params.frequency) * 2f64.powi(feature_log2);
        let unit = period / crate::WORLD_SIZE;
        let reduced = TerrainParams { offset, ..*params }.reduced_offset();
        Self {
            land: Landscape {
                seed: params.seed,
                octaves: params.octaves,
                gain: f64::from(params.gain),
                feature_log2,
                peak_height: f64::from(params.height_scale) * unit,
                terrain: TerrainFn::Fbm,
                period: params.frequency,
            },
            unit,
            origin: reduced.map(|o| (0.5 + o) * period),
        }
    }

    /// The period in metres: the tile's width.
    pub fn period(&self) -> f64 {
        crate::WORLD_SIZE * self.unit
    }

    /// A point in tile units as world metres.
    pub fn to_world(self, p: DVec3) -> DVec3 {
        DVec3::new(
            p.x * self.unit + self.origin[0],
            p.y * self.unit,
            p.z * self.unit + self.origin[1],
        )
    }

    /// The tile's square in world metres: x0, z0, x1, z1.
    pub fn region(&self) -> [f64; 4] {
        let h = 0.5 * self.period();
        [
            self.origin[0] - h,
            self.origin[1] - h,
            self.origin[0] + h,
            self.origin[1] + h,
        ]
    }

    /// log2 of the finest mesh spacing `grid` vertices per side allow, in metres: the power of
    /// two nearest the tile's width over `grid - 1` cells.
    pub fn grid_spacing_log2(&self, grid: u32) -> i32 {
        (self.period() / f64::from(grid.max(2) - 1)).log2().round() as i32
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::noise::{Channel, Fbm};

    #[test]
    fn the_tile_is_its_periodic_landscape() {
        for (frequency, octaves, offset) in [
            (4, 8, [0.0, 0.0]),
            (3, 5, [0.25, -7.5]),
            (1, 12, [1e6 + 0.3, 2.0]),
        ] {
            let params = TerrainParams {
                frequency,
                octaves,
                offset,
                ..TerrainParams::default()
            };
            params.validate().unwrap();
            let frame = TileFrame::new(&params, offset);
            let fbm = Fbm::from_params(&params);
            for (x, z) in [(-1.0, -1.0), (0.3, -0.7), (0.999, 0.5), (-0.25, 0.125)] {
                let w = frame.to_world(DVec3::new(x, 0.0, z));
                for channel in [Channel::Height, Channel::Color] {
                    let u = [(x + 1.0) / 2.0, (z + 1.0) / 2.0];
                    let (tile, _) = fbm.sample(channel, u);
                    let land = frame.land.sample(channel, w.x, w.z, octaves).value;
                    assert!(
                        (tile - land).abs() < 1e-9,
                        "frequency {frequency} at ({x}, {z}): tile {tile} landscape {land}"
                    );
                }
                // One period on, the same height.
                let p = frame.period();
                let a = frame.land.height_at(w.x, w.z);
                let b = frame.land.height_at(w.x + p, w.z - 3.0 * p);
                assert!((a - b).abs() < 1e-6 * frame.land.peak_height, "{a} {b}");
            }
        }
    }
}
