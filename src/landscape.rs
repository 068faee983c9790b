//! The endless world's terrain function, in f64: the CPU twin of `wgsl/landscape.wgsl`.
//!
//! World units are metres. Octave `o` of the noise has a square lattice of cells
//! `2^(feature_log2 - o)` metres wide, hashed on its integer cell coordinates (wrapping at
//! 2^32 cells, so the finest octave repeats only after 2^32 of its cells: far beyond 2^20). A
//! grid of samples spaced `2^level_log2` metres, at integer sample coordinates, lands on each
//! octave's lattice at an exact integer cell plus an exact binary fraction: the GPU computes
//! both with integer shifts, so what it bakes does not depend on how far from the origin it is.
//!
//! The terrain function is a value ([`TerrainFn`]): plain fBm, or the seed template's
//! derivative-damped "eroded" fBm (each octave is damped by the slope accumulated so far, so
//! detail thins out on steep slopes). Both have an analytic gradient here and on the GPU, and a
//! Lipschitz bound ([`Landscape::lipschitz`]) for conservative ray casting.

use crate::noise::{
    noise_stream, periodic_noise, Channel, NOISE_MAX_ABS, NOISE_MAX_GRADIENT, NOISE_MAX_SECOND,
};

/// Largest of 2|D|/(1+|D|²)², the factor by which the damping of the eroded fBm can amplify
/// the slope of the damped octave (reached at |D| = 1/sqrt(3)).
pub(crate) const DAMPING_SLOPE: f64 = 0.649_519_052_838_329;

/// How the octaves are summed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TerrainFn {
    /// Plain fBm: the sum of the octaves.
    #[default]
    Fbm,
    /// Derivative-damped fBm: octave `o` is divided by `1 + |D_o|²`, where `D_o` is the sum of
    /// the lattice-unit gradients of octaves `0..=o` (as in the seed template's terrain).
    Eroded,
}

impl TerrainFn {
    /// Every terrain function's name.
    pub const NAMES: &'static [&'static str] = &["fbm", "eroded"];

    /// Its name.
    pub fn name(self) -> &'static str {
        match self {
            TerrainFn::Fbm => "fbm",
            TerrainFn::Eroded => "eroded",
        }
    }

    /// The function called `name`.
    pub fn from_name(name: &str) -> Option<Self> {
        match name.trim() {
            "fbm" => Some(TerrainFn::Fbm),
            "eroded" => Some(TerrainFn::Eroded),
            _ => None,
        }
    }

    /// The value the GPU uniforms carry.
    pub fn code(self) -> u32 {
        self as u32
    }
}

/// The endless world's terrain: everything that decides its heights and colour channel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Landscape {
    /// Hash seed.
    pub seed: u32,
    /// Octave count (all of them are in [`Landscape::height_at`]; a baked level keeps those it
    /// can represent).
    pub octaves: u32,
    /// Amplitude ratio between octaves.
    pub gain: f64,
    /// log2 of octave 0's lattice cell, in metres.
    pub feature_log2: i32,
    /// World height in metres of normalised height 1.
    pub peak_height: f64,
    /// How the octaves are summed.
    pub terrain: TerrainFn,
    /// 0 for an endless landscape; otherwise octave 0's lattice cells per period: octave `o`'s
    /// lattice wraps every `period << o` cells, so the terrain repeats every `period` cells of
    /// octave 0 (the seed blog's tile is one period).
    pub period: u32,
}

/// A normalised height with its gradient per metre, and its Hessian-free companions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    /// Normalised height (or colour channel) in [0, 1].
    pub value: f64,
    /// d value / dx and d value / dz, per metre.
    pub gradient: [f64; 2],
}

impl Landscape {
    /// Octave `o`'s lattice period in cells (0: endless).
    pub fn period_of(&self, o: u32) -> u32 {
        self.period.checked_shl(o).unwrap_or(0)
    }

    /// The length in metres after which the terrain repeats (`None`: endless).
    pub fn period_metres(&self) -> Option<f64> {
        (self.period != 0).then(|| f64::from(self.period) * self.cell(0))
    }

    /// Octave `o`'s lattice cell in metres.
    pub fn cell(&self, o: u32) -> f64 {
        2f64.powi(self.feature_log2 - o as i32)
    }

    /// How many octaves a grid spaced `2^level_log2` metres keeps: those whose cell spans at
    /// least two samples (finer ones would alias).
    pub fn octaves_for_level(&self, level_log2: i32) -> u32 {
        let keep = self.feature_log2 - level_log2; // cells of >= 2 samples: o <= keep - 1
        keep.clamp(0, self.octaves as i32) as u32
    }

    /// Sum of the amplitudes of all octaves (what the sum is normalised by).
    fn norm(&self) -> f64 {
        (0..self.octaves).map(|o| self.gain.powi(o as i32)).sum()
    }

    /// The factor from a sum of octaves to normalised height: `0.5 / (sum of the amplitudes *
    /// NOISE_MAX_ABS)`, so the sum maps into [0, 1].
    pub fn scale(&self) -> f64 {
        0.5 / (self.norm() * NOISE_MAX_ABS)
    }

    /// Bound in metres on how much the octaves after the first `octaves` can add to the height
    /// anywhere (each, damped or not, is at most its amplitude times `NOISE_MAX_ABS`).
    pub fn remainder_bound(&self, octaves: u32) -> f64 {
        let rest: f64 = (octaves..self.octaves)
            .map(|o| self.gain.powi(o as i32))
            .sum();
        self.peak_height * self.scale() * NOISE_MAX_ABS * rest
    }

    /// The channel at world (x, z) in metres from its first `octaves` octaves (normalised by all
    /// of them), with its gradient per metre.
    pub fn sample(&self, channel: Channel, x: f64, z: f64, octaves: u32) -> Sample {
        let eroded = self.terrain == TerrainFn::Eroded && channel == Channel::Height;
        let mut sum = 0.0;
        let mut grad = [0.0; 2];
        // Accumulated lattice-unit gradient (eroded only) and its derivative per metre.
        let mut acc = [0.0; 2];
        let mut dacc = [[0.0; 2]; 2]; // dacc[i][j] = d acc_i / d world_j
        let mut amplitude = 1.0;
        for o in 0..octaves.min(self.octaves) {
            let freq = 1.0 / self.cell(o);
            let (n, g, h) = periodic_noise(
                [x * freq, z * freq],
                self.period_of(o),
                noise_stream(self.seed, channel, o),
            );
            if eroded {
                acc = [acc[0] + g[0], acc[1] + g[1]];
                dacc = [
                    [dacc[0][0] + h[0] * freq, dacc[0][1] + h[1] * freq],
                    [dacc[1][0] + h[1] * freq, dacc[1][1] + h[2] * freq],
                ];
                let q = 1.0 + acc[0] * acc[0] + acc[1] * acc[1];
                sum += amplitude * n / q;
                for j in 0..2 {
                    let dq = 2.0 * (acc[0] * dacc[0][j] + acc[1] * dacc[1][j]);
                    grad[j] += amplitude * (g[j] * freq / q - n * dq / (q * q));
                }
            } else {
                sum += amplitude * n;
                grad = [
                    grad[0] + amplitude * g[0] * freq,
                    grad[1] + amplitude * g[1] * freq,
                ];
            }
            amplitude *= self.gain;
        }
        let scale = self.scale();
        Sample {
            value: 0.5 + scale * sum,
            gradient: [scale * grad[0], scale * grad[1]],
        }
    }

    /// World height in metres of the continuous surface (every octave) at (x, z).
    pub fn height_at(&self, x: f64, z: f64) -> f64 {
        self.peak_height * self.sample(Channel::Height, x, z, self.octaves).value
    }

    /// What a grid spaced `2^level_log2` metres bakes at integer sample (i, j): the channel
    /// from the octaves the level keeps, at world (i, j) * spacing.
    pub fn level_sample(&self, channel: Channel, level_log2: i32, i: i64, j: i64) -> Sample {
        let s = 2f64.powi(level_log2);
        self.sample(
            channel,
            i as f64 * s,
            j as f64 * s,
            self.octaves_for_level(level_log2),
        )
    }

    /// Where the ray from `ro` along the unit `rd` first meets the continuous surface (every
    /// octave), in metres along the ray, within `reach` metres horizontally; `None` if it does
    /// not. Steps are bounded by the surface's slope bound `slope` (metres per metre,
    /// [`Landscape::slope_bounds`]'s last entry), so no ridge is stepped over but a sliver
    /// under a millionth of the distance; the crossing is bisected to f64 precision. The f64
    /// truth the stability sweeps judge the endless world's methods by.
    pub fn intersect(&self, ro: [f64; 3], rd: [f64; 3], slope: f64, reach: f64) -> Option<f64> {
        let flat = (rd[0] * rd[0] + rd[2] * rd[2]).sqrt();
        let rate = slope * flat - rd[1];
        let floor = 1e-3 * self.cell(self.octaves.saturating_sub(1));
        let at = |t: f64| [ro[0] + t * rd[0], ro[1] + t * rd[1], ro[2] + t * rd[2]];
        let clearance = |t: f64| {
            let p = at(t);
            p[1] - self.height_at(p[0], p[2])
        };
        let mut t = 0.0;
        let mut c = clearance(t);
        if c <= 0.0 {
            return Some(0.0);
        }
        loop {
            if rate <= 0.0 || t * flat > reach || (at(t)[1] > self.peak_height && rd[1] >= 0.0) {
                return None;
            }
            let next = t + (c / rate).max(floor + 1e-6 * t);
            let cn = clearance(next);
            if cn <= 0.0 {
                let (mut lo, mut hi) = (t, next);
                for _ in 0..60 {
                    let mid = 0.5 * (lo + hi);
                    if clearance(mid) > 0.0 {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                return Some(0.5 * (lo + hi));
            }
            (t, c) = (next, cn);
        }
    }

    /// Slope bounds for the reference ray cast, one per octave count `1..=octaves`: twice the
    /// steepest slope (metres per metre) of the first k octaves over 2048 scattered points, and
    /// never more than the proven [`Landscape::lipschitz`]. A measured bound, as the clipmap's
    /// level errors are: the proven one is about 20 times the steepest slope for the eroded
    /// terrain (its damping term assumes every octave's curvature at its worst at once), and
    /// grazing rays take steps inversely proportional to it.
    pub fn slope_bounds(&self) -> Vec<f64> {
        let mut state = 0x85eb_ca6bu32 ^ self.seed;
        let mut next = || {
            state = crate::noise::pcg(state);
            f64::from(state) / 4_294_967_296.0
        };
        let span = 256.0 * self.cell(0);
        let points: Vec<(f64, f64)> = (0..2048)
            .map(|_| (next() * span - span / 2.0, next() * span - span / 2.0))
            .collect();
        (1..=self.octaves)
            .map(|k| {
                let steepest = points
                    .iter()
                    .map(|&(x, z)| {
                        let g = self.sample(Channel::Height, x, z, k).gradient;
                        self.peak_height * g[0].hypot(g[1])
                    })
                    .fold(0.0, f64::max);
                (2.0 * steepest).min(self.lipschitz(k))
            })
            .collect()
    }

    /// Bound on |grad height| in metres per metre of the first `octaves` octaves: what a
    /// conservative ray march needs to never step through the surface.
    pub fn lipschitz(&self, octaves: u32) -> f64 {
        let scale = self.peak_height * self.scale();
        let mut bound = 0.0;
        let mut curvature = 0.0; // sum over k <= o of NOISE_MAX_SECOND * freq_k
        let mut amplitude = 1.0;
        for o in 0..octaves.min(self.octaves) {
            let freq = 1.0 / self.cell(o);
            bound += amplitude * NOISE_MAX_GRADIENT * freq;
            if self.terrain == TerrainFn::Eroded {
                curvature += NOISE_MAX_SECOND * freq;
                // The damping's own slope: |n| * 2|D|/(1+|D|²)² * |dD/dx|.
                bound += amplitude * NOISE_MAX_ABS * DAMPING_SLOPE * curvature;
            }
            amplitude *= self.gain;
        }
        scale * bound
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::noise::{cell_noise, gradient};

    fn land(terrain: TerrainFn) -> Landscape {
        Landscape {
            seed: 7,
            octaves: 9,
            gain: 0.5,
            feature_log2: 11,
            peak_height: 900.0,
            terrain,
            period: 0,
        }
    }

    #[test]
    fn noise_derivatives_match_finite_differences() {
        let e = 1e-5;
        for (k, p) in [[0.3, 0.7], [12.25, -3.6], [-1e6 + 0.1, 5e5 + 0.9]]
            .iter()
            .enumerate()
        {
            let stream = 11 + k as u32;
            let (v, g, h) = periodic_noise(*p, 0, stream);
            let at = |dx: f64, dy: f64| periodic_noise([p[0] + dx, p[1] + dy], 0, stream);
            let gx = (at(e, 0.0).0 - at(-e, 0.0).0) / (2.0 * e);
            let gy = (at(0.0, e).0 - at(0.0, -e).0) / (2.0 * e);
            // Far from the origin f64 keeps ~1e-10 of the position: differences lose digits.
            let tol = if p[0].abs() > 1e3 { 1e-4 } else { 1e-6 };
            assert!(
                (gx - g[0]).abs() < tol && (gy - g[1]).abs() < tol,
                "{p:?}: {g:?} vs {gx} {gy}"
            );
            let hxx = (at(e, 0.0).1[0] - at(-e, 0.0).1[0]) / (2.0 * e);
            let hxy = (at(0.0, e).1[0] - at(0.0, -e).1[0]) / (2.0 * e);
            let hyy = (at(0.0, e).1[1] - at(0.0, -e).1[1]) / (2.0 * e);
            for (a, b) in [(hxx, h[0]), (hxy, h[1]), (hyy, h[2])] {
                assert!(
                    (a - b).abs() < 100.0 * tol,
                    "{p:?}: hessian {h:?} vs {hxx} {hxy} {hyy}"
                );
            }
            assert!(v.abs() <= NOISE_MAX_ABS + 1e-12);
        }
    }

    #[test]
    fn second_derivatives_stay_under_their_bound() {
        // Every corner-gradient combination (8^4) on a grid of cell positions.
        let g = |i: u32| gradient(i);
        let mut worst: f64 = 0.0;
        for c in 0..4096u32 {
            let corners = [
                g(c & 15),
                g((c >> 3) & 15),
                g((c >> 6) & 15),
                g((c >> 9) & 15),
            ];
            for i in 0..=16 {
                for j in 0..=16 {
                    let f = [f64::from(i) / 16.0, f64::from(j) / 16.0];
                    let (_, _, h) = cell_noise(corners, f);
                    worst = worst.max(h[0].abs()).max(h[1].abs()).max(h[2].abs());
                }
            }
        }
        assert!(
            worst < 9.0 && worst > 1.0,
            "largest second derivative {worst}"
        );
        assert!(worst < NOISE_MAX_SECOND);
    }

    #[test]
    fn gradients_are_analytic_for_both_terrain_functions() {
        for t in [TerrainFn::Fbm, TerrainFn::Eroded] {
            let l = land(t);
            for (x, z) in [(10.5, -33.25), (1e6 + 0.125, -2e6 + 7.5), (-4096.0, 4096.0)] {
                let s = l.sample(Channel::Height, x, z, l.octaves);
                let e = 1e-4;
                let at =
                    |dx: f64, dz: f64| l.sample(Channel::Height, x + dx, z + dz, l.octaves).value;
                let gx = (at(e, 0.0) - at(-e, 0.0)) / (2.0 * e);
                let gz = (at(0.0, e) - at(0.0, -e)) / (2.0 * e);
                let tol = 1e-6 * (1.0 + s.gradient[0].abs() + s.gradient[1].abs());
                assert!(
                    (gx - s.gradient[0]).abs() < tol && (gz - s.gradient[1]).abs() < tol,
                    "{t:?} at ({x}, {z}): {:?} vs ({gx}, {gz})",
                    s.gradient
                );
                assert!((0.0..=1.0).contains(&s.value), "{t:?}: {}", s.value);
            }
        }
    }

    #[test]
    fn the_lipschitz_bound_holds_where_sampled() {
        for t in [TerrainFn::Fbm, TerrainFn::Eroded] {
            let l = land(t);
            let bound = l.lipschitz(l.octaves);
            let mut worst: f64 = 0.0;
            for i in 0..20_000 {
                let (x, z) = (f64::from(i) * 7.3 - 5000.0, f64::from(i % 97) * 13.1 + 1e5);
                let g = l.sample(Channel::Height, x, z, l.octaves).gradient;
                worst = worst.max(l.peak_height * g[0].hypot(g[1]));
            }
            assert!(worst < bound, "{t:?}: slope {worst} over bound {bound}");
            assert!(
                worst > bound / 20.0,
                "{t:?}: bound {bound} far above slope {worst}"
            );
        }
    }

    #[test]
    fn what_the_remaining_octaves_add_stays_under_its_bound() {
        for t in [TerrainFn::Fbm, TerrainFn::Eroded] {
            let l = land(t);
            for k in 0..=l.octaves {
                let bound = l.remainder_bound(k);
                let mut worst: f64 = 0.0;
                for i in 0..2000 {
                    let (x, z) = (f64::from(i) * 37.9 - 9000.0, f64::from(i % 89) * 41.3);
                    let full = l.height_at(x, z);
                    let part = l.peak_height * l.sample(Channel::Height, x, z, k).value;
                    worst = worst.max((full - part).abs());
                }
                assert!(worst <= bound, "{t:?}, {k} octaves: {worst} over {bound}");
                assert!(
                    k == l.octaves || worst > bound / 10.0,
                    "{t:?}, {k} octaves: bound {bound} far above {worst}"
                );
            }
            assert_eq!(l.remainder_bound(l.octaves), 0.0);
        }
    }

    #[test]
    fn levels_keep_the_octaves_they_can_hold_and_the_world_does_not_repeat() {
        let l = land(TerrainFn::Fbm);
        // Octave cells 2048, 1024, ..., 8 m: a 1 m grid keeps all 9, a 512 m grid keeps 2.
        assert_eq!(l.octaves_for_level(0), 9);
        assert_eq!(l.octaves_for_level(9), 2);
        assert_eq!(l.octaves_for_level(11), 0);
        // Samples 2^20 finest cells apart differ (no short period).
        let far = l.cell(l.octaves - 1) * f64::from(1u32 << 20);
        assert_ne!(l.height_at(3.0, 5.0), l.height_at(3.0 + far, 5.0));
        // A level sample is the continuous function at the sample's position.
        let s = l.level_sample(Channel::Height, -2, 1_000_003, -7);
        let c = l.sample(
            Channel::Height,
            1_000_003.0 / 4.0,
            -7.0 / 4.0,
            l.octaves_for_level(-2),
        );
        assert_eq!(s, c);
    }
}
