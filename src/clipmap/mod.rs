//! The endless world's level-of-detail layout: nested square grids (geometry clipmaps) around
//! the camera, as data. No GPU here: [`crate::gpu::world`] bakes and draws what this decides.
//!
//! Level `l` is a grid of `cells x cells` cells spaced `2^(finest_log2 + l)` metres, its
//! samples baked into layer `l` of a texture array of side `cells + 1` with wrap-around
//! (toroidal) addressing, so a level that moves bakes only the rows and columns it uncovers.
//! Each level is split into `PATCHES x PATCHES` square patches of `patch` cells; a level draws
//! the patches that the next finer level does not cover (a ring), and those inside the view
//! frustum.
//!
//! Why clipmaps rather than a CDLOD quadtree: the levels are camera-centred squares, so each
//! one is a single toroidal texture layer that the bake updates by strips; with origins snapped
//! to multiples of two patches, every level's hole (the finer level) falls on patch boundaries,
//! so rings are whole patches and no stitching strips are needed. Cracks are prevented as in
//! CDLOD: with distance from the eye, a level's odd vertices slide onto their even neighbours
//! and take the coarser level's heights, so at its outer edge the fine level's geometry is
//! exactly the coarse level's (the same integer positions, the same texels); see
//! [`Clipmap::morph`].
//!
//! The quality knob is the screen-space error in pixels. A level's mesh deviates vertically
//! from the continuous surface by at most `error` metres (measured from the CPU twin, see
//! `level_error`); a vertical deviation δ at distance d covers at most `K·δ/d` pixels, with
//! `K = height_px / (2 tan(fov_y / 2))`. Level `l` is never drawn closer than `1.5 patch`
//! of its cells from the camera (the finer level covers that), and its morph band (where the
//! coarser level's error applies) no closer than `2.5 patch` cells, so the patch size follows
//! from the knob: [`Clipmap::patch_for`]. The morph depends on the distance from the eye, not
//! from the level's snapped square, so geometry changes continuously as the camera moves.

use crate::landscape::Landscape;
use crate::noise::Channel;

/// Patches per level side (even; the finer level covers the middle `PATCHES / 2`).
pub const PATCHES: i32 = 8;
/// Most levels a clipmap has (with 4-cell patches and 2^-4 m samples, 24 levels reach past
/// 60 km; coarser samples reach far beyond).
pub const MAX_LEVELS: usize = 24;
/// Smallest and largest patch side in cells.
pub const PATCH_RANGE: (u32, u32) = (4, 128);
/// Levels finer than the finest octave needs (every octave is kept there): they bring the
/// interpolation error of the finest octaves down where the eye is close to the ground.
pub(crate) const EXTRA_FINE: i32 = 3;
/// Largest extent of the clipmap in finest samples: camera-relative vertex positions stay exact
/// integers in f32 (under 2^24, with a margin).
pub(crate) const MAX_EXTENT_LOG2: i32 = 23;
/// How far the coarsest level reaches at least, in metres (past any horizon a camera a few
/// kilometres up sees over the highest peaks of the default world).
pub(crate) const REACH: f64 = 120_000.0;

/// A level of the clipmap: where it is and what it costs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Level {
    /// log2 of the sample spacing in metres.
    pub spacing_log2: i32,
    /// World sample coordinates (in this level's samples) of the level's first sample; a
    /// multiple of two patches.
    pub origin: [i32; 2],
    /// Texture-array layer holding its samples.
    pub layer: u32,
    /// Largest vertical deviation, in metres, of this level's mesh from the continuous surface.
    pub error: f64,
    /// Whether it is drawn (and kept baked) for the current camera.
    pub active: bool,
}

impl Level {
    /// Sample spacing in metres.
    pub fn spacing(&self) -> f64 {
        2f64.powi(self.spacing_log2)
    }
}

/// A rectangle of a level's samples to bake (world sample coordinates of the level).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Strip {
    /// The level's index.
    pub level: usize,
    /// First sample.
    pub origin: [i32; 2],
    /// Size in samples.
    pub extent: [u32; 2],
}

/// One patch to draw: a level and the patch's column and row in it (or one of its
/// sub-patches, [`Clipmap::trim`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, bytemuck::Pod, bytemuck::Zeroable)]
#[repr(C)]
pub struct Patch {
    /// Index of the level.
    pub level: u32,
    /// Column and row of the patch within the level, 0..PATCHES.
    pub at: [u32; 2],
    /// For a sub-patch, its first cell within the patch: column in the low 16 bits, row in
    /// the high 16 bits (0 for a whole patch).
    pub sub: u32,
}

/// Sub-patches per patch side where a bounded world's edge crosses a patch ([`Clipmap::trim`]).
pub(crate) const SUB_PATCHES: u32 = 8;

/// The camera as the clipmap needs it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Eye {
    /// Position in world metres.
    pub position: [f64; 3],
    /// Height of the ground under it, metres.
    pub ground: f64,
    /// `K` of the screen-error bound: pixels per unit of (deviation / distance).
    pub pixels_per_radian: f64,
}

/// The levels, their layout and what changed.
#[derive(Clone, Debug)]
pub struct Clipmap {
    /// Cells per patch side.
    pub patch: u32,
    /// log2 of the finest level's spacing in metres.
    pub finest_log2: i32,
    /// The levels, finest first.
    pub levels: Vec<Level>,
    /// The morph band, in a level's cells of Chebyshev distance from the eye: vertices nearer
    /// than the first keep their level's geometry, farther than the second they take the
    /// coarser level's. Every level's outer edge is at least `3 patch` cells from the eye and
    /// its hole's edge at most `2.5 patch`, so the band `[2.5, 3] patch` (less a margin for
    /// rounding) makes the edge vertices exactly the coarser level's (no cracks), keeps the hole's
    /// edge unmorphed, and moves continuously with the eye (no pop when a level snaps).
    pub morph: [f64; 2],
    /// Whether the morph is on (off only to show the cracks it prevents, in tests).
    pub morphing: bool,
    /// The eye's height above the ground at the last [`Clipmap::update`], metres.
    pub altitude: f64,
    /// How far the first active level is morphed towards the next as a whole (0..=1): it
    /// reaches 1 as the eye climbs to the height where that level is dropped, so dropping it
    /// (or taking it up again on the way down) changes nothing on screen.
    pub fade: f64,
    /// Strips uncovered but not baked yet (a per-frame budget defers them), in world samples
    /// of their level: [`Clipmap::take`] hands them out, coarsest level first.
    pub pending: Vec<Strip>,
}

/// The part of `strip` inside the square of `side` samples at `origin`, if any.
fn clip(strip: Strip, origin: [i32; 2], side: u32) -> Option<Strip> {
    let span = |at: i32, extent: u32, from: i32| {
        let lo = i64::from(at).max(i64::from(from));
        let hi = (i64::from(at) + i64::from(extent)).min(i64::from(from) + i64::from(side));
        (hi > lo).then_some((lo as i32, (hi - lo) as u32))
    };
    let (x, w) = span(strip.origin[0], strip.extent[0], origin[0])?;
    let (z, h) = span(strip.origin[1], strip.extent[1], origin[1])?;
    Some(Strip {
        origin: [x, z],
        extent: [w, h],
        ..strip
    })
}

/// How far from the origin, in metres along x or z, an eye may be for `land`: level sample
/// coordinates are 32-bit integers of the finest spacing, with a margin for the levels around it.
pub fn max_eye(land: &Landscape) -> f64 {
    2f64.powi(30 + finest_log2(land))
}

/// The fade of the first level starts at this fraction of the height where it is dropped.
pub(crate) const FADE_FROM: f64 = 0.7;

/// log2 of the finest level's spacing for `land`: half the finest octave's cell, then
/// `EXTRA_FINE` levels finer.
pub fn finest_log2(land: &Landscape) -> i32 {
    land.feature_log2 - land.octaves as i32 - EXTRA_FINE
}

/// How far a mesh of `land` sampled every `2^spacing_log2` metres (with the octaves that grid
/// keeps, interpolated across its cells) strays vertically from the continuous surface, in
/// metres: the largest deviation over 1024 scattered points, times 1.5 for what the sampling
/// misses. The fBm is statistically the same everywhere, so this holds across the world; it is
/// a measured bound, not a proof.
pub(crate) fn level_error(land: &Landscape, spacing_log2: i32) -> f64 {
    1.5 * scattered_worst(land, spacing_log2, |x, z, mesh| {
        (land.height_at(x, z) - mesh).abs()
    })
}

/// How far the continuous surface can rise above the mesh of a grid spaced `2^spacing_log2`
/// metres, in metres: what the hybrid method raises that level by, so the rasterised mesh lies
/// on or above the surface. Twice the most it rises at `level_error`'s scattered points, plus
/// a millionth of the peak for the levels' 24-bit heights: measured, as the level errors are,
/// not proven (the proven bound on the octaves a coarse level drops is most of the peak, and a
/// shell that thick would take the refinement hundreds of steps).
pub fn level_raise(land: &Landscape, spacing_log2: i32) -> f64 {
    let above = scattered_worst(land, spacing_log2, |x, z, mesh| land.height_at(x, z) - mesh);
    2.0 * above.max(0.0) + 1e-6 * land.peak_height
}

/// The largest `measure(x, z, mesh)` over 1024 scattered points (x, z) in metres, where `mesh`
/// is the height there of the mesh of a grid spaced `2^spacing_log2` metres (the octaves it
/// keeps at its samples, on the GPU's triangles).
fn scattered_worst(
    land: &Landscape,
    spacing_log2: i32,
    measure: impl Fn(f64, f64, f64) -> f64,
) -> f64 {
    let s = 2f64.powi(spacing_log2);
    let octaves = land.octaves_for_level(spacing_log2);
    let mut worst = f64::NEG_INFINITY;
    let mut state = 0x9e37_79b9u32 ^ land.seed;
    let mut next = || {
        state = crate::noise::pcg(state);
        f64::from(state) / 4_294_967_296.0
    };
    for _ in 0..1024 {
        // A cell somewhere within a few hundred feature cells, a point inside it.
        let span = 256.0 * land.cell(0) / s;
        let (ci, cj) = ((next() * span).floor(), (next() * span).floor());
        let (fx, fz) = (next(), next());
        let h = |i: f64, j: f64| {
            land.sample(Channel::Height, i * s, j * s, octaves).value * land.peak_height
        };
        let (a, b, c, d) = (
            h(ci, cj),
            h(ci + 1.0, cj),
            h(ci, cj + 1.0),
            h(ci + 1.0, cj + 1.0),
        );
        // The triangle the GPU draws: the diagonal from (0,0) to (1,1).
        let mesh = if fx >= fz {
            a + fx * (b - a) + fz * (d - b)
        } else {
            a + fz * (c - a) + fx * (d - c)
        };
        worst = worst.max(measure((ci + fx) * s, (cj + fz) * s, mesh));
    }
    worst
}

impl Clipmap {
    /// Cells per level side.
    pub fn cells(&self) -> u32 {
        self.patch * PATCHES as u32
    }

    /// Side of each level's (toroidal) texture layer: one sample more than the cells.
    pub fn side(&self) -> u32 {
        self.cells() + 1
    }

    /// The patch side that keeps the screen error of every level under `pixel_error` pixels
    /// for a view with `pixels_per_radian` (see the module docs), with the error that bound
    /// leaves (over `pixel_error` only where the largest patch is not enough).
    pub fn patch_for(errors: &[(i32, f64)], pixel_error: f64, pixels_per_radian: f64) -> u32 {
        // Level l at distance >= 1.5 patch cells; its morph band, with the coarser level's
        // error, at >= 2.5 patch cells.
        let need = |i: usize| {
            let (log2, e) = errors[i];
            let s = 2f64.powi(log2);
            let coarse = errors.get(i + 1).map_or(0.0, |c| c.1);
            (e / 1.5).max(coarse / 2.5) / s
        };
        let worst = (0..errors.len()).map(need).fold(0.0, f64::max);
        let cells = pixels_per_radian * worst / pixel_error.max(1e-6);
        (cells.ceil().max(1.0) as u32)
            .next_power_of_two()
            .clamp(PATCH_RANGE.0, PATCH_RANGE.1)
    }

    /// The layout for `land` under the knob `pixel_error` (pixels) at `pixels_per_radian`.
    pub fn new(land: &Landscape, pixel_error: f64, pixels_per_radian: f64) -> Self {
        let finest_log2 = finest_log2(land);
        let errors: Vec<(i32, f64)> = (0..MAX_LEVELS as i32)
            .map(|l| (finest_log2 + l, level_error(land, finest_log2 + l)))
            .collect();
        Self::with_errors(land, &errors, pixel_error, pixels_per_radian)
    }

    /// [`Clipmap::new`] with the levels' errors already measured (`(spacing_log2, error)`,
    /// finest first, [`MAX_LEVELS`] of them).
    pub fn with_errors(
        land: &Landscape,
        errors: &[(i32, f64)],
        pixel_error: f64,
        pixels_per_radian: f64,
    ) -> Self {
        let finest_log2 = finest_log2(land);
        let patch = Self::patch_for(errors, pixel_error, pixels_per_radian);
        // Enough levels that the coarsest reaches REACH from the camera in every direction,
        // as long as positions stay exact.
        let cells = f64::from(patch) * f64::from(PATCHES as u32);
        let cells_log2 = (patch * PATCHES as u32).ilog2() as i32;
        let mut count = 1;
        while count < MAX_LEVELS
            && cells_log2 + count as i32 <= MAX_EXTENT_LOG2
            && (cells / 2.0 - f64::from(patch)) * 2f64.powi(finest_log2 + count as i32 - 1) < REACH
        {
            count += 1;
        }
        let levels = errors[..count]
            .iter()
            .enumerate()
            .map(|(l, &(spacing_log2, error))| Level {
                spacing_log2,
                origin: [i32::MIN; 2],
                layer: l as u32,
                error,
                active: false,
            })
            .collect();
        Self {
            patch,
            finest_log2,
            levels,
            morph: [
                2.5 * f64::from(patch) + 0.125,
                3.0 * f64::from(patch) - 0.125,
            ],
            morphing: true,
            altitude: 0.0,
            fade: 0.0,
            pending: Vec::new(),
        }
    }

    /// Where level `l` goes for an eye at world (x, z): the multiple of two patches nearest to
    /// centring it on the eye.
    pub fn origin_for(&self, l: usize, x: f64, z: f64) -> [i32; 2] {
        let s = self.levels[l].spacing();
        let step = 2.0 * f64::from(self.patch);
        let half = f64::from(self.cells()) / 2.0;
        let snap = |c: f64| (((c / s - half) / step).round() * step) as i32;
        [snap(x), snap(z)]
    }

    /// The square the levels cover for an eye at world (x, z), in metres: `[x0, z0, x1, z1]`
    /// of the coarsest level, whose square holds all the finer ones. The ray casters are
    /// bounded by it, so they draw the region the mesh draws.
    pub fn drawn_region(&self, x: f64, z: f64) -> [f64; 4] {
        let last = self.levels.len() - 1;
        let s = self.levels[last].spacing();
        let [i, j] = self.origin_for(last, x, z);
        let side = f64::from(self.cells()) * s;
        let (x0, z0) = (f64::from(i) * s, f64::from(j) * s);
        [x0, z0, x0 + side, z0 + side]
    }

    /// The first level drawn: finer ones are skipped while even at the eye's height above the
    /// ground their coarser neighbour's error stays under the knob.
    fn first_level(&self, eye: &Eye, pixel_error: f64) -> usize {
        let altitude = (eye.position[1] - eye.ground).max(0.0);
        let mut first = 0;
        // Dropped only where, faded into the next level (from FADE_FROM of this height), the
        // next level's error at the eye's height is within the knob.
        while first + 1 < self.levels.len()
            && eye.pixels_per_radian * self.levels[first + 1].error
                <= FADE_FROM * pixel_error * altitude
        {
            first += 1;
        }
        first
    }

    /// Moves the levels for `eye` and queues the strips to bake in [`Clipmap::pending`]: whole
    /// levels that became active or jumped more than their size, else the rows and columns they
    /// uncovered. Strips still pending are kept where they overlap their level's new square.
    /// Returns the strips this move uncovered.
    pub fn update(&mut self, eye: &Eye, pixel_error: f64) -> Vec<Strip> {
        let strips = self.moved(eye, pixel_error);
        let squares: Vec<Option<[i32; 2]>> = self
            .levels
            .iter()
            .map(|l| l.active.then_some(l.origin))
            .collect();
        let side = self.side();
        let fresh: Vec<usize> = strips
            .iter()
            .filter(|s| s.extent == [side; 2])
            .map(|s| s.level)
            .collect();
        let mut pending: Vec<Strip> = std::mem::take(&mut self.pending)
            .into_iter()
            .filter(|s| !fresh.contains(&s.level))
            .filter_map(|s| clip(s, squares[s.level]?, side))
            .collect();
        pending.extend(strips.iter().copied());
        self.pending = pending;
        strips
    }

    /// Takes pending strips to bake now, coarsest level first, splitting a strip by rows where
    /// the next would pass `budget` texels (at least one row is always taken) and taking at
    /// most `max_strips`.
    pub fn take(&mut self, budget: u64, max_strips: usize) -> Vec<Strip> {
        // Coarse levels first: they cover the screen while finer ones wait.
        self.pending.sort_by_key(|s| std::cmp::Reverse(s.level));
        let mut left = budget;
        let mut out = Vec::new();
        let mut rest = Vec::new();
        // Once a strip waits, every finer one waits too: coarse levels strictly first.
        let mut full = false;
        for s in std::mem::take(&mut self.pending) {
            let width = u64::from(s.extent[0]);
            let texels = width * u64::from(s.extent[1]);
            full |= out.len() >= max_strips || (left < width && !out.is_empty());
            if full {
                rest.push(s);
                continue;
            }
            let rows = (left / width).max(1) as u32;
            if texels <= left || rows >= s.extent[1] {
                left = left.saturating_sub(texels);
                out.push(s);
                continue;
            }
            left = left.saturating_sub(width * u64::from(rows));
            out.push(Strip {
                extent: [s.extent[0], rows],
                ..s
            });
            rest.push(Strip {
                origin: [s.origin[0], s.origin[1] + rows as i32],
                extent: [s.extent[0], s.extent[1] - rows],
                ..s
            });
            full = true;
        }
        self.pending = rest;
        out
    }

    /// Texels still waiting to be baked.
    pub fn pending_texels(&self) -> u64 {
        self.pending
            .iter()
            .map(|s| u64::from(s.extent[0]) * u64::from(s.extent[1]))
            .sum()
    }

    /// Texels of level `l` still waiting to be baked.
    pub fn pending_texels_of(&self, l: usize) -> u64 {
        self.pending
            .iter()
            .filter(|s| s.level == l)
            .map(|s| u64::from(s.extent[0]) * u64::from(s.extent[1]))
            .sum()
    }

    /// The first level that is drawn: the first active level from which every coarser active
    /// level is fully baked (a level with pending strips is not drawn, and neither is any finer
    /// one: the next coarser level covers its square). `levels.len()` if none can be.
    pub fn first_drawn(&self) -> usize {
        let mut first = self.levels.len();
        for l in (0..self.levels.len()).rev() {
            let level = &self.levels[l];
            if !level.active || self.pending.iter().any(|s| s.level == l) {
                break;
            }
            first = l;
        }
        first
    }

    /// Whether level `l` is drawn: active, and no coarser active level waits on a bake.
    pub fn drawn(&self, l: usize) -> bool {
        l >= self.first_drawn() && self.levels[l].active
    }

    fn moved(&mut self, eye: &Eye, pixel_error: f64) -> Vec<Strip> {
        self.altitude = (eye.position[1] - eye.ground).max(0.0);
        let first = self.first_level(eye, pixel_error);
        // The height at which `first` would be dropped, if a coarser level exists.
        self.fade = self.levels.get(first + 1).map_or(0.0, |next| {
            let drop = eye.pixels_per_radian * next.error / (FADE_FROM * pixel_error.max(1e-9));
            ((self.altitude - FADE_FROM * drop) / ((1.0 - FADE_FROM) * drop)).clamp(0.0, 1.0)
        });
        let side = self.side() as i32;
        let mut strips = Vec::new();
        for l in 0..self.levels.len() {
            let active = l >= first;
            let new = self.origin_for(l, eye.position[0], eye.position[2]);
            let level = &mut self.levels[l];
            let old = level.origin;
            let was = level.active;
            level.active = active;
            if !active {
                continue;
            }
            level.origin = new;
            let far = |a: i32, b: i32| (i64::from(a) - i64::from(b)).abs() >= i64::from(side);
            let fresh = !was || old[0] == i32::MIN || far(new[0], old[0]) || far(new[1], old[1]);
            if fresh {
                strips.push(Strip {
                    level: l,
                    origin: new,
                    extent: [side as u32; 2],
                });
                continue;
            }
            // Columns uncovered along x, over the new rows; then rows uncovered along z, over
            // the columns both squares share (no texel twice).
            let (dx, dz) = (new[0] - old[0], new[1] - old[1]);
            if dx != 0 {
                let x0 = if dx > 0 { old[0] + side } else { new[0] };
                strips.push(Strip {
                    level: l,
                    origin: [x0, new[1]],
                    extent: [dx.unsigned_abs(), side as u32],
                });
            }
            if dz != 0 {
                let z0 = if dz > 0 { old[1] + side } else { new[1] };
                let x0 = new[0].max(old[0]);
                let width = side - dx.abs();
                strips.push(Strip {
                    level: l,
                    origin: [x0, z0],
                    extent: [width as u32, dz.unsigned_abs()],
                });
            }
        }
        strips
    }

    /// The finer level's square inside level `l`, in patches of level `l` (column, row of its
    /// first patch), or `None` for the first level drawn.
    pub fn hole(&self, l: usize) -> Option<[i32; 2]> {
        let finer = self.levels.get(l.checked_sub(1)?)?;
        if !self.drawn(l - 1) {
            return None;
        }
        let o = self.levels[l].origin;
        let b = self.patch as i32;
        Some([
            (finer.origin[0] / 2 - o[0]) / b,
            (finer.origin[1] / 2 - o[1]) / b,
        ])
    }

    /// The patches to draw: every active level's ring, less what `visible` (a test on the
    /// patch's box in world metres, min and max corners) rejects.
    pub fn patches(
        &self,
        height_range: [f64; 2],
        mut visible: impl FnMut([f64; 3], [f64; 3]) -> bool,
    ) -> Vec<Patch> {
        let mut out = Vec::new();
        let half = PATCHES / 2;
        let first = self.first_drawn();
        for (l, level) in self.levels.iter().enumerate() {
            if l < first || !level.active {
                continue;
            }
            let hole = self.hole(l);
            let s = level.spacing();
            let b = self.patch as i32;
            for py in 0..PATCHES {
                for px in 0..PATCHES {
                    if let Some([hx, hy]) = hole {
                        if (hx..hx + half).contains(&px) && (hy..hy + half).contains(&py) {
                            continue;
                        }
                    }
                    let x0 = f64::from(level.origin[0] + px * b) * s;
                    let z0 = f64::from(level.origin[1] + py * b) * s;
                    let size = f64::from(b) * s;
                    if visible(
                        [x0, height_range[0], z0],
                        [x0 + size, height_range[1], z0 + size],
                    ) {
                        out.push(Patch {
                            level: l as u32,
                            at: [px as u32, py as u32],
                            sub: 0,
                        });
                    }
                }
            }
        }
        out
    }

    /// Cells per sub-patch side ([`Clipmap::trim`]).
    pub fn sub_cells(&self) -> u32 {
        (self.patch / SUB_PATCHES).max(1)
    }

    /// Splits `patches` at the edge of `region` (x0, z0, x1, z1 in metres), for a bounded
    /// world whose vertices are clamped onto that edge: a patch inside it stays whole (the
    /// first list); a patch the edge crosses becomes the sub-patches of
    /// [`Clipmap::sub_cells`] that overlap it (the second list), so the cells outside, which
    /// clamping would flatten into degenerate triangles, are mostly not drawn at all.
    pub fn trim(&self, patches: &[Patch], region: [f64; 4]) -> (Vec<Patch>, Vec<Patch>) {
        let (mut whole, mut subs) = (Vec::new(), Vec::new());
        let b = self.patch as i32;
        let n = self.sub_cells() as i32;
        // Whether [lo, lo + size) (metres) lies inside [r0, r1], or meets it.
        let inside = |lo: f64, size: f64, r0: f64, r1: f64| lo >= r0 && lo + size <= r1;
        let overlaps = |lo: f64, size: f64, r0: f64, r1: f64| lo < r1 && lo + size > r0;
        for p in patches {
            let level = &self.levels[p.level as usize];
            let s = level.spacing();
            let x0 = f64::from(level.origin[0] + p.at[0] as i32 * b) * s;
            let z0 = f64::from(level.origin[1] + p.at[1] as i32 * b) * s;
            let size = f64::from(b) * s;
            if inside(x0, size, region[0], region[2]) && inside(z0, size, region[1], region[3]) {
                whole.push(*p);
                continue;
            }
            let step = f64::from(n) * s;
            for j in 0..b / n {
                for i in 0..b / n {
                    let (x, z) = (x0 + f64::from(i) * step, z0 + f64::from(j) * step);
                    if overlaps(x, step, region[0], region[2])
                        && overlaps(z, step, region[1], region[3])
                    {
                        subs.push(Patch {
                            sub: (i * n) as u32 | ((j * n) as u32) << 16,
                            ..*p
                        });
                    }
                }
            }
        }
        (whole, subs)
    }

    /// The screen error, in pixels, that this layout keeps under for a view with
    /// `pixels_per_radian` (the bound of the module docs, over the active levels). The first
    /// active level has no finer level inside it: its nearest point is the ground under the
    /// eye, [`Clipmap::altitude`] away (less on ground steeper than the view: not counted).
    pub fn error_bound(&self, pixels_per_radian: f64) -> f64 {
        let b = f64::from(self.patch);
        let first = self.first_drawn();
        // While a bake is pending the first level drawn may be coarser than the first active.
        let fading = self.levels.get(first).is_some_and(|l| l.active)
            && (first == 0 || !self.levels[first - 1].active);
        let active: Vec<&Level> = self.levels[first.min(self.levels.len())..]
            .iter()
            .filter(|l| l.active)
            .collect();
        let mut worst: f64 = 0.0;
        for (i, level) in active.iter().enumerate() {
            let s = level.spacing();
            let own = if i == 0 {
                // Faded towards the next level, the first level has that level's error too.
                let faded = if self.fade > 0.0 && fading {
                    active.get(1).map_or(0.0, |c| c.error)
                } else {
                    0.0
                };
                level.error.max(faded) / self.altitude.max(1e-3)
            } else {
                level.error / (1.5 * b * s)
            };
            let coarse = active.get(i + 1).map_or(0.0, |c| c.error / (2.5 * b * s));
            worst = worst.max(own.max(coarse));
        }
        pixels_per_radian * worst
    }
}

#[cfg(test)]
mod tests;
