//! Where the props stand and how far a point is from them, by the twin: for a host placing its
//! own things among them ([`crate::World::props_distance`]) and for the tests.
//!
//! A prop stands as the GPU's scatter stands it (`wgsl/props_scatter.wgsl`), but on the
//! continuous surface rather than the drawn one (near the eye the two lie within centimetres;
//! far away the levels' deviation grows, and the drawn prop sinks with it), and whole: the
//! scatter sinks a prop smaller on screen than its cut-off and drops those past the draw
//! distance, which depend on a view; the twin keeps them.

use super::place::{self, Props};
use super::{sdf, Scene, Tape};
use crate::landscape::Landscape;
use crate::noise::Channel;
use glam::DVec3;

/// A prop as it stands: which kind, where its foot is, how it is turned and scaled.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Standing {
    /// Its kind: an index into the scene's kinds.
    pub kind: u32,
    /// Its kind's origin, world metres: on the lowest of five points of the ground under its
    /// foot, 2 cm lower.
    pub foot: DVec3,
    /// Radians about the vertical.
    pub turn: f64,
    /// Times its kind's size.
    pub scale: f64,
    /// What varies its displacements' noise.
    pub seed: u32,
}

impl Standing {
    /// The prop's distance at world point `p` and the material there, through its kind's
    /// `tape`: a bound on the distance to its surface (exact for a prop of exact primitives;
    /// smooth booleans and displacement make it a bound, never over the distance times the
    /// tape's Lipschitz constant).
    pub fn distance(&self, tape: &Tape, p: DVec3) -> (f64, u32) {
        let q = p - self.foot;
        let (s, c) = self.turn.sin_cos();
        let local = [c * q.x - s * q.z, q.y, s * q.x + c * q.z].map(|v| v / self.scale);
        let (d, material) = sdf::distance(tape, local, self.seed);
        (d * self.scale, material)
    }
}

/// The land the props stand on: the landscape and the water's normalised level (`None`: no
/// water).
pub type Ground<'a> = (&'a Landscape, Option<f64>);

/// The foot of a prop of `tape` at `scale` standing at `(x, z)`: the lowest of the ground at
/// its centre and four points half its width out, 2 cm lower.
fn foot(land: &Landscape, tape: &Tape, scale: f64, [x, z]: [f64; 2]) -> DVec3 {
    let r = 0.5 * tape.radius() * scale;
    let y = [(0.0, 0.0), (r, 0.0), (-r, 0.0), (0.0, r), (0.0, -r)]
        .iter()
        .map(|(dx, dz)| land.height_at(x + dx, z + dz))
        .fold(f64::INFINITY, f64::min);
    DVec3::new(x, y - 0.02, z)
}

/// The prop standing in `cell` of the scatter, or `None` where the ground keeps none there.
pub fn scattered(
    (scene, tapes, props): (&Scene, &[Tape], &Props),
    (land, water): Ground<'_>,
    cell: [i64; 2],
) -> Option<Standing> {
    let weights = place::cumulative(&scene.kinds);
    let prop = place::prop_at(&weights, land.seed, cell);
    let kind = scene.kinds.get(prop.kind as usize)?;
    let size = f64::from(props.cell);
    let x = (cell[0] as f64 + f64::from(prop.offset[0])) * size;
    let z = (cell[1] as f64 + f64::from(prop.offset[1])) * size;
    let s = land.sample(Channel::Height, x, z, land.octaves);
    let tint = land.sample(Channel::Color, x, z, land.octaves).value;
    let g = s.gradient.map(|v| v * land.peak_height);
    let n_y = 1.0 / (1.0 + g[0] * g[0] + g[1] * g[1]).sqrt();
    let ground = (n_y as f32, tint as f32, s.value as f32);
    if !place::keeps(props, &prop, kind.on_rock, ground, water.map(|w| w as f32)) {
        return None;
    }
    let scale = f64::from(place::scale_of(kind, prop.scale));
    let tape = tapes.get(prop.kind as usize)?;
    Some(Standing {
        kind: prop.kind,
        foot: foot(land, tape, scale, [x, z]),
        turn: f64::from(prop.turn),
        scale,
        seed: prop.seed,
    })
}

/// The scene's props put at given places, standing.
pub fn placed(scene: &Scene, tapes: &[Tape], land: &Landscape) -> Vec<Standing> {
    scene
        .placed
        .iter()
        .enumerate()
        .filter_map(|(i, e)| {
            let tape = tapes.get(e.kind as usize)?;
            // The seed as the GPU's frame gives it (src/gpu/props.rs).
            let h = crate::noise::pcg(i as u32 ^ 0x7061_6365);
            let scale = f64::from(e.scale);
            Some(Standing {
                kind: e.kind,
                foot: foot(land, tape, scale, e.at),
                turn: f64::from(e.turn).to_radians(),
                scale,
                seed: crate::noise::pcg(h),
            })
        })
        .collect()
}

/// The distance from world point `p` to the nearest prop (a bound, as
/// [`Standing::distance`]) and that prop, over the props of the 3x3 cells around `p`'s and
/// those put at given places; `None` where none of them stands. A prop is at most half a cell
/// wide, so no prop of a cell farther out lies within half a cell of `p`: where the answer is
/// over half a cell (or `None`), the distance is at least half a cell.
pub fn distance(
    (scene, tapes, props): (&Scene, &[Tape], &Props),
    ground: Ground<'_>,
    p: DVec3,
) -> Option<(f64, Standing)> {
    let [i, j] = props.cell_at(p.x, p.z);
    let around = (-1..=1).flat_map(|di| (-1..=1).map(move |dj| [i + di, j + dj]));
    let near = around.filter_map(|c| scattered((scene, tapes, props), ground, c));
    near.chain(placed(scene, tapes, ground.0))
        .filter_map(|s| Some((s.distance(tapes.get(s.kind as usize)?, p).0, s)))
        .min_by(|a, b| a.0.total_cmp(&b.0))
}
