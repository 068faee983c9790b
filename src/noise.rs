//! The CPU twin of `wgsl/noise.wgsl`, in f64: the oracle every GPU result is tested against.
//!
//! Same hash, same gradients, same fade, same fBm normalisation as the shader; only the
//! arithmetic is wider. It also gives the analytic gradient of the fBm, which the normal map's
//! central differences approximate.

use crate::params::TerrainParams;

/// Largest |noise| for unit gradients in 2-D (sqrt(2)/2, at a cell centre).
pub const NOISE_MAX_ABS: f64 = std::f64::consts::FRAC_1_SQRT_2;

/// Upper bound of |grad n| (in lattice units) of one octave of the gradient noise.
///
/// Sampling every combination of the eight corner gradients on a fine grid of cell positions
/// finds a largest value of 1.998 (tested below); 2.2 adds a margin for what the grid misses.
pub(crate) const NOISE_MAX_GRADIENT: f64 = 2.2;

/// Bound on every second derivative (in lattice units) of one octave of the gradient noise:
/// sampled over all corner-gradient combinations, the largest |d²n/dx²|, |d²n/dxdy| found is
/// below 9 (tested in the landscape twin); 12 leaves a margin for what sampling misses.
pub const NOISE_MAX_SECOND: f64 = 12.0;

/// Which independent fBm stream a value comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Channel {
    /// Terrain height.
    Height = 0,
    /// The mix between the two albedo colours.
    Color = 1,
}

/// PCG hash of one u32 (Jarzynski & Olano 2020), as in the shader.
pub fn pcg(v: u32) -> u32 {
    let state = v.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
    let word = ((state >> ((state >> 28) + 4)) ^ state).wrapping_mul(277_803_737);
    (word >> 22) ^ word
}

/// The hash stream of one (seed, channel, octave).
pub fn noise_stream(seed: u32, channel: Channel, octave: u32) -> u32 {
    pcg(seed ^ pcg((channel as u32).wrapping_mul(64).wrapping_add(octave)))
}

/// Hash of a lattice corner (already wrapped into the period).
pub(crate) fn lattice_hash(x: u32, y: u32, stream: u32) -> u32 {
    pcg(x ^ pcg(y ^ stream))
}

/// One of eight unit gradients: the axes and the diagonals.
pub fn gradient(h: u32) -> [f64; 2] {
    let s0 = if h & 1 != 0 { -1.0 } else { 1.0 };
    let s1 = if h & 2 != 0 { -1.0 } else { 1.0 };
    if h & 4 != 0 {
        let d = std::f64::consts::FRAC_1_SQRT_2;
        [s0 * d, s1 * d]
    } else if h & 8 != 0 {
        [s0, 0.0]
    } else {
        [0.0, s1]
    }
}

/// Gradient noise at lattice position `p` (any real value) on a lattice that wraps every
/// `period` cells (0: corners hashed as wrapping 32-bit integers, exactly as the GPU's bitcast
/// of an i32 cell): the value, gradient and Hessian (xx, xy, yy) in lattice units.
pub fn periodic_noise(p: [f64; 2], period: u32, stream: u32) -> (f64, [f64; 2], [f64; 3]) {
    let fl = [p[0].floor(), p[1].floor()];
    let f = [p[0] - fl[0], p[1] - fl[1]];
    let wrap = |c: f64| {
        if period == 0 {
            (c as i64) as u32
        } else {
            (c as i64).rem_euclid(i64::from(period)) as u32
        }
    };
    let (x0, y0) = (wrap(fl[0]), wrap(fl[1]));
    let next = |c: u32| {
        if period == 0 {
            c.wrapping_add(1)
        } else {
            (c + 1) % period
        }
    };
    let (x1, y1) = (next(x0), next(y0));
    let corners = [
        gradient(lattice_hash(x0, y0, stream)),
        gradient(lattice_hash(x1, y0, stream)),
        gradient(lattice_hash(x0, y1, stream)),
        gradient(lattice_hash(x1, y1, stream)),
    ];
    cell_noise(corners, f)
}

/// Gradient noise inside one cell with corner gradients `g` (in the order (0,0), (1,0), (0,1),
/// (1,1)) at position `f` in [0,1)^2: the value, gradient and Hessian (xx, xy, yy), all in
/// lattice units.
pub fn cell_noise(g: [[f64; 2]; 4], f: [f64; 2]) -> (f64, [f64; 2], [f64; 3]) {
    let [ga, gb, gc, gd] = g;
    let dot = |g: [f64; 2], x: f64, y: f64| g[0] * x + g[1] * y;
    let a = dot(ga, f[0], f[1]);
    let b = dot(gb, f[0] - 1.0, f[1]);
    let c = dot(gc, f[0], f[1] - 1.0);
    let d = dot(gd, f[0] - 1.0, f[1] - 1.0);
    let (big_b, big_c, k) = (b - a, c - a, a - b - c + d);
    // Their gradients (they are affine in f).
    let db = [gb[0] - ga[0], gb[1] - ga[1]];
    let dc = [gc[0] - ga[0], gc[1] - ga[1]];
    let dk = [ga[0] - gb[0] - gc[0] + gd[0], ga[1] - gb[1] - gc[1] + gd[1]];
    let fade = |t: f64| t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
    let fade1 = |t: f64| 30.0 * t * t * (t - 1.0) * (t - 1.0);
    let fade2 = |t: f64| 60.0 * t * (2.0 * t * t - 3.0 * t + 1.0);
    let (ux, uy) = (fade(f[0]), fade(f[1]));
    let (ux1, uy1) = (fade1(f[0]), fade1(f[1]));
    let (ux2, uy2) = (fade2(f[0]), fade2(f[1]));
    let value = a + ux * big_b + uy * big_c + ux * uy * k;
    let gx = ga[0] + ux1 * (big_b + uy * k) + ux * db[0] + uy * dc[0] + ux * uy * dk[0];
    let gy = ga[1] + uy1 * (big_c + ux * k) + ux * db[1] + uy * dc[1] + ux * uy * dk[1];
    let hxx = ux2 * (big_b + uy * k) + 2.0 * ux1 * (db[0] + uy * dk[0]);
    let hyy = uy2 * (big_c + ux * k) + 2.0 * uy1 * (dc[1] + ux * dk[1]);
    let hxy = ux1 * db[1] + uy1 * dc[0] + ux1 * uy1 * k + ux1 * uy * dk[1] + ux * uy1 * dk[0];
    (value, [gx, gy], [hxx, hxy, hyy])
}

/// The noise settings the bake uses, in the twin's own types.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fbm {
    /// Hash seed.
    pub seed: u32,
    /// Lattice cells across the tile at the first octave.
    pub frequency: u32,
    /// Number of octaves.
    pub octaves: u32,
    /// Amplitude ratio between successive octaves.
    pub gain: f64,
    /// Scroll offset in tiles, reduced to [0, 1).
    pub offset: [f64; 2],
}

impl Fbm {
    /// The fBm of a validated parameter set.
    pub fn from_params(p: &TerrainParams) -> Self {
        Self {
            seed: p.seed,
            frequency: p.frequency,
            octaves: p.octaves,
            gain: f64::from(p.gain),
            offset: p.reduced_offset(),
        }
    }

    /// Normalised fBm in [0, 1] at tile position `u` (one tile is [0,1)^2, before the scroll
    /// offset), with its gradient with respect to `u`.
    pub fn sample(&self, channel: Channel, u: [f64; 2]) -> (f64, [f64; 2]) {
        let q = [u[0] + self.offset[0], u[1] + self.offset[1]];
        let mut sum = 0.0;
        let mut grad = [0.0; 2];
        let mut amplitude = 1.0;
        let mut norm = 0.0;
        for o in 0..self.octaves {
            let period = self.frequency << o;
            let pf = f64::from(period);
            let (n, g, _) = periodic_noise(
                [q[0] * pf, q[1] * pf],
                period,
                noise_stream(self.seed, channel, o),
            );
            sum += amplitude * n;
            grad[0] += amplitude * g[0] * pf;
            grad[1] += amplitude * g[1] * pf;
            norm += amplitude;
            amplitude *= self.gain;
        }
        let scale = 0.5 / (norm * NOISE_MAX_ABS);
        (0.5 + scale * sum, [scale * grad[0], scale * grad[1]])
    }

    /// The value the bake writes at texel (x, y) of a `size` x `size` tile.
    pub fn texel(&self, channel: Channel, size: u32, x: u32, y: u32) -> f64 {
        let s = f64::from(size);
        self.sample(
            channel,
            [(f64::from(x) + 0.5) / s, (f64::from(y) + 0.5) / s],
        )
        .0
    }

    /// A whole channel baked on the CPU, row by row (row `y` is tile v).
    pub fn bake(&self, channel: Channel, size: u32) -> Vec<f64> {
        (0..size)
            .flat_map(|y| (0..size).map(move |x| (x, y)))
            .map(|(x, y)| self.texel(channel, size, x, y))
            .collect()
    }
}

/// Unit normal (x, y, z; y up) from wrap-around central differences of a normalised height
/// grid, as the normal pass computes it: the tile spans [`crate::WORLD_SIZE`] world units and
/// heights are scaled by `height_scale`.
pub fn central_difference_normal(
    heights: &[f64],
    size: u32,
    height_scale: f64,
    x: u32,
    y: u32,
) -> [f64; 3] {
    let s = size as usize;
    let at = |x: u32, y: u32| heights[y as usize * s + x as usize];
    let (xl, xr) = ((x + size - 1) % size, (x + 1) % size);
    let (yd, yu) = ((y + size - 1) % size, (y + 1) % size);
    let spacing = 2.0 * crate::WORLD_SIZE / f64::from(size);
    let dhdx = height_scale * (at(xr, y) - at(xl, y)) / spacing;
    let dhdz = height_scale * (at(x, yu) - at(x, yd)) / spacing;
    normalize([-dhdx, 1.0, -dhdz])
}

/// Unit normal from the analytic gradient of the normalised fBm at tile position `u`.
pub fn analytic_normal(fbm: &Fbm, height_scale: f64, u: [f64; 2]) -> [f64; 3] {
    let (_, g) = fbm.sample(Channel::Height, u);
    // World x = u * WORLD_SIZE + const, so d/dx = (d/du) / WORLD_SIZE.
    let dhdx = height_scale * g[0] / crate::WORLD_SIZE;
    let dhdz = height_scale * g[1] / crate::WORLD_SIZE;
    normalize([-dhdx, 1.0, -dhdz])
}

/// Bound on |grad h_world| of the first `octaves` octaves of `fbm` (normalised by all of its
/// octaves, as the shaders do), for heights scaled by `height_scale` over a tile
/// [`crate::WORLD_SIZE`] wide: what a conservative ray march needs to never step through the
/// surface.
pub fn lipschitz_world(fbm: &Fbm, octaves: u32, height_scale: f64) -> f64 {
    let mut norm = 0.0;
    let mut bound = 0.0;
    let mut amplitude = 1.0;
    for o in 0..fbm.octaves {
        if o < octaves {
            bound += amplitude * f64::from(fbm.frequency << o) * NOISE_MAX_GRADIENT;
        }
        norm += amplitude;
        amplitude *= fbm.gain;
    }
    height_scale / crate::WORLD_SIZE * 0.5 / (norm * NOISE_MAX_ABS) * bound
}

fn normalize(v: [f64; 3]) -> [f64; 3] {
    let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    [v[0] / l, v[1] / l, v[2] / l]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fbm() -> Fbm {
        Fbm {
            seed: 7,
            frequency: 3,
            octaves: 6,
            gain: 0.5,
            offset: [0.25, 0.6],
        }
    }

    #[test]
    fn pcg_known_values() {
        // Reference values from an independent Python implementation of the same hash.
        assert_eq!(pcg(0), 129_708_002);
        assert_eq!(pcg(1), 2_831_084_092);
        assert_eq!(pcg(12345), 4_099_845_390);
    }

    #[test]
    fn noise_is_zero_on_lattice_and_periodic() {
        for s in 0..16 {
            let (v, _, _) = periodic_noise([3.0, 5.0], 8, s);
            assert_eq!(v, 0.0);
            let (a, _, _) = periodic_noise([1.3, 2.7], 8, s);
            let (b, _, _) = periodic_noise([9.3, -5.3], 8, s);
            assert!((a - b).abs() < 1e-12, "period 8 must repeat: {a} vs {b}");
        }
    }

    #[test]
    fn fbm_stays_in_unit_range() {
        let f = fbm();
        for y in 0..64 {
            for x in 0..64 {
                let (v, _) = f.sample(Channel::Height, [x as f64 / 64.0, y as f64 / 64.0]);
                assert!((0.0..=1.0).contains(&v), "{v}");
            }
        }
    }

    #[test]
    fn analytic_gradient_matches_finite_differences() {
        let f = fbm();
        let h = 1e-7;
        for &u in &[[0.1, 0.2], [0.77, 0.31], [0.5, 0.999]] {
            let (_, g) = f.sample(Channel::Height, u);
            let (xp, _) = f.sample(Channel::Height, [u[0] + h, u[1]]);
            let (xm, _) = f.sample(Channel::Height, [u[0] - h, u[1]]);
            let (yp, _) = f.sample(Channel::Height, [u[0], u[1] + h]);
            let (ym, _) = f.sample(Channel::Height, [u[0], u[1] - h]);
            let fd = [(xp - xm) / (2.0 * h), (yp - ym) / (2.0 * h)];
            for i in 0..2 {
                assert!(
                    (g[i] - fd[i]).abs() < 1e-5 * (1.0 + g[i].abs()),
                    "{g:?} vs {fd:?}"
                );
            }
        }
    }

    #[test]
    fn noise_gradient_bound_holds() {
        // Every combination of corner gradients (the hash can produce any), on a 32 x 32 grid
        // of positions in the cell.
        let mut max: f64 = 0.0;
        let all: Vec<[f64; 2]> = (0..16u32).map(gradient).collect();
        let mut unique: Vec<[f64; 2]> = Vec::new();
        for g in all {
            if !unique.contains(&g) {
                unique.push(g);
            }
        }
        assert_eq!(unique.len(), 8, "eight gradients");
        let n = 32;
        for ga in &unique {
            for gb in &unique {
                for gc in &unique {
                    for gd in &unique {
                        for i in 0..n {
                            for j in 0..n {
                                let f = [
                                    (f64::from(i) + 0.5) / f64::from(n),
                                    (f64::from(j) + 0.5) / f64::from(n),
                                ];
                                let (_, g, _) = cell_noise([*ga, *gb, *gc, *gd], f);
                                max = max.max((g[0] * g[0] + g[1] * g[1]).sqrt());
                            }
                        }
                    }
                }
            }
        }
        assert!(
            max > 1.9 && max < NOISE_MAX_GRADIENT,
            "max |grad n| = {max}"
        );
    }

    #[test]
    fn lipschitz_bound_holds_on_samples() {
        let f = fbm();
        let hs = 0.5;
        let bound = lipschitz_world(&f, f.octaves, hs);
        for i in 0..2000 {
            let u = [
                (f64::from(i) * 0.618_034).fract(),
                (f64::from(i) * 0.414_214).fract(),
            ];
            let (_, g) = f.sample(Channel::Height, u);
            let slope = hs / crate::WORLD_SIZE * (g[0] * g[0] + g[1] * g[1]).sqrt();
            assert!(slope <= bound, "slope {slope} above bound {bound}");
        }
    }

    #[test]
    fn whole_tile_offset_is_identity() {
        let a = fbm();
        let mut b = a;
        b.offset = [a.offset[0] + 3.0, a.offset[1] - 2.0];
        for &u in &[[0.1, 0.2], [0.9, 0.45]] {
            let va = a.sample(Channel::Height, u).0;
            let vb = b.sample(Channel::Height, u).0;
            assert!((va - vb).abs() < 1e-12);
        }
    }
}
