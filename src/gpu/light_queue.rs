//! What light the endless world's levels still need, and which of it one frame bakes.
//!
//! The light bake (`wgsl/world_light.wgsl`) costs several times the height bake a texel, so it
//! keeps to a per-frame budget as the height bake does: coarse levels first, a level's light
//! only once its heights and every coarser level's are baked (its march reads them, so what it
//! bakes is final), and never more than the budget's texels a frame (a level is split into
//! bands of rows). Until a level holds light everywhere in its square it is drawn with the
//! finest coarser level's light that does ([`LightQueue::light_from`]), or unshadowed where
//! none does; a turned sun leaves the old light in place, drawn until each level is relit.
//!
//! A relight goes in rounds: a turned sun starts one (every level stale, relit coarsest
//! first), and a sun that turns again while a round is under way (a running day turns it every
//! frame) does not restart it, which would relight the coarse levels over and over and never
//! reach the fine ones: the round goes on, each texel lit for the sun of the frame that lights
//! it, and the next round starts when it ends. No light drawn is older than two rounds.
//!
//! CPU only: the [`super::world::World`] asks it what to bake and what each level reads.

use crate::clipmap::{Clipmap, Strip};

/// [`LightQueue::light_from`] for a level drawn with no light yet (unshadowed).
pub(crate) const NO_LIGHT: u32 = u32::MAX;

/// One level's light still to bake.
#[derive(Clone, Debug, Default)]
struct LevelQueue {
    /// The level's whole square lacks light (new textures, or a level that was inactive).
    all_missing: bool,
    /// Rectangles with no light (what the level's moving uncovered).
    missing: Vec<Strip>,
    /// The whole square holds light for another sun.
    all_stale: bool,
    /// Rectangles holding light for another sun.
    stale: Vec<Strip>,
}

impl LevelQueue {
    fn has_light(&self) -> bool {
        !self.all_missing && self.missing.is_empty()
    }

    fn clear_missing(&mut self) {
        *self = Self {
            all_missing: true,
            ..Default::default()
        };
    }
}

/// The levels' light still to bake: see the module docs.
#[derive(Clone, Debug)]
pub(crate) struct LightQueue {
    levels: Vec<LevelQueue>,
    /// The sun's azimuth the baked light is for (None: nothing lit yet).
    azimuth: Option<f32>,
    /// The sun turned while a relight round was under way: another round follows it.
    turned_during_round: bool,
}

fn area(s: &Strip) -> u64 {
    u64::from(s.extent[0]) * u64::from(s.extent[1])
}

/// Level `l`'s square in `map` (its samples).
fn window(map: &Clipmap, l: usize) -> Strip {
    Strip {
        level: l,
        origin: map.levels[l].origin,
        extent: [map.side(); 2],
    }
}

/// `s` less what lies outside `w` (both of one level), if anything is left.
fn intersect(s: Strip, w: Strip) -> Option<Strip> {
    let mut out = s;
    for a in 0..2 {
        let start = i64::from(s.origin[a]).max(i64::from(w.origin[a]));
        let end = (i64::from(s.origin[a]) + i64::from(s.extent[a]))
            .min(i64::from(w.origin[a]) + i64::from(w.extent[a]));
        if end <= start {
            return None;
        }
        out.origin[a] = start as i32;
        out.extent[a] = (end - start) as u32;
    }
    Some(out)
}

impl LightQueue {
    /// A queue for `levels` levels with nothing lit.
    pub fn new(levels: usize) -> Self {
        let mut q = Self {
            levels: vec![LevelQueue::default(); levels],
            azimuth: None,
            turned_during_round: false,
        };
        q.forget();
        q
    }

    /// Nothing holds light any more (nothing read it for a while, or the textures are new).
    pub fn forget(&mut self) {
        self.levels.iter_mut().for_each(LevelQueue::clear_missing);
        self.azimuth = None;
        self.turned_during_round = false;
    }

    /// The sun's azimuth is now `azimuth`: a turn leaves every level's light in place, stale,
    /// to be relit in a round (or after the round under way: see the module docs).
    pub fn set_sun(&mut self, azimuth: f32) {
        match self.azimuth {
            Some(a) if a == azimuth => {}
            Some(_) if self.relighting() => self.turned_during_round = true,
            Some(_) => self.start_round(),
            None => {
                self.levels.iter_mut().for_each(LevelQueue::clear_missing);
                self.turned_during_round = false;
            }
        }
        self.azimuth = Some(azimuth);
    }

    /// Whether a relight round is under way (some level still holds stale light).
    fn relighting(&self) -> bool {
        self.levels
            .iter()
            .any(|q| q.all_stale || !q.stale.is_empty())
    }

    /// Every level's light stale, to be relit.
    fn start_round(&mut self) {
        for q in &mut self.levels {
            q.all_stale = true;
            q.stale.clear();
        }
        self.turned_during_round = false;
    }

    /// Strips whose heights were just baked: their light is missing.
    pub fn heights_baked(&mut self, strips: &[Strip]) {
        for s in strips {
            let q = &mut self.levels[s.level];
            if !q.all_missing {
                q.missing.push(*s);
            }
        }
    }

    /// Drops what left each level's square and forgets inactive levels (relit whole when they
    /// are active again).
    fn prune(&mut self, map: &Clipmap) {
        for (l, q) in self.levels.iter_mut().enumerate() {
            if !map.levels[l].active {
                q.clear_missing();
                continue;
            }
            let w = window(map, l);
            for list in [&mut q.missing, &mut q.stale] {
                *list = list.iter().filter_map(|s| intersect(*s, w)).collect();
            }
        }
    }

    /// Takes the rectangles one frame lights: at most `budget` texels (at least one row, so
    /// the queue always moves) in at most `max_rects` rectangles, coarsest level first, each
    /// level's missing light before its stale light. `usable(l)` says whether level `l`'s
    /// heights are all baked; a level is lit only when it and every coarser active level are.
    pub fn take(
        &mut self,
        map: &Clipmap,
        budget: u64,
        max_rects: usize,
        usable: impl Fn(usize) -> bool,
    ) -> Vec<Strip> {
        self.prune(map);
        if self.turned_during_round && !self.relighting() {
            self.start_round();
        }
        let mut out = Vec::new();
        let mut left = budget.max(1);
        for l in (0..self.levels.len()).rev() {
            if !map.levels[l].active {
                continue;
            }
            if !usable(l) {
                break;
            }
            let w = window(map, l);
            let q = &mut self.levels[l];
            if q.all_missing {
                q.all_missing = false;
                q.missing = vec![w];
                q.all_stale = false;
                q.stale.clear();
            }
            if q.all_stale {
                q.all_stale = false;
                q.stale = vec![w];
            }
            for list in [&mut q.missing, &mut q.stale] {
                while left > 0 && out.len() < max_rects {
                    let Some(s) = list.pop() else {
                        break;
                    };
                    if area(&s) <= left {
                        left -= area(&s);
                        out.push(s);
                        continue;
                    }
                    // A band of whole rows within what is left (one row where the frame has
                    // lit nothing yet), the rest back on the list.
                    let mut rows = (left / u64::from(s.extent[0])).min(u64::from(s.extent[1]));
                    if rows == 0 {
                        if !out.is_empty() {
                            list.push(s);
                            left = 0;
                            break;
                        }
                        rows = 1;
                    }
                    let rows = rows as u32;
                    let mut band = s;
                    band.extent[1] = rows;
                    out.push(band);
                    left = left.saturating_sub(area(&band));
                    if rows < s.extent[1] {
                        let mut rest = s;
                        rest.origin[1] += rows as i32;
                        rest.extent[1] -= rows;
                        list.push(rest);
                    }
                }
            }
            if left == 0 || out.len() >= max_rects {
                break;
            }
        }
        out
    }

    /// The level whose light level `l` is drawn with: `l` where its square holds light
    /// everywhere, else the finest coarser active level that does, else [`NO_LIGHT`].
    pub fn light_from(&self, map: &Clipmap, l: usize) -> u32 {
        (l..self.levels.len())
            .find(|&j| map.levels[j].active && self.levels[j].has_light())
            .map_or(NO_LIGHT, |j| j as u32)
    }

    /// Texels still to light (missing or stale) over the active levels: every level where the
    /// sun turned since the last round began and none is under way (the next round's).
    pub fn pending_texels(&self, map: &Clipmap) -> u64 {
        let whole = u64::from(map.side()).pow(2);
        if self.turned_during_round && !self.relighting() {
            let active = map.levels.iter().filter(|l| l.active).count() as u64;
            return whole * active;
        }
        self.levels
            .iter()
            .enumerate()
            .filter(|(l, _)| map.levels[*l].active)
            .map(|(_, q)| {
                let missing = if q.all_missing {
                    whole
                } else {
                    q.missing.iter().map(area).sum()
                };
                let stale = if q.all_stale {
                    whole
                } else {
                    q.stale.iter().map(area).sum()
                };
                missing + stale
            })
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::clipmap::Eye;
    use crate::landscape::{Landscape, TerrainFn};

    fn map_at(x: f64) -> (Clipmap, Eye) {
        let land = Landscape {
            seed: 7,
            octaves: 10,
            gain: 0.47,
            feature_log2: 10,
            peak_height: 600.0,
            terrain: TerrainFn::Fbm,
            period: 0,
        };
        let map = Clipmap::new(&land, 8.0, 300.0);
        let eye = Eye {
            position: [x, 300.0, 0.0],
            ground: 0.0,
            pixels_per_radian: 300.0,
        };
        (map, eye)
    }

    /// Texels of each level covered by `rects` (counted with repeats).
    fn covered(map: &Clipmap, rects: &[Strip]) -> Vec<u64> {
        let mut out = vec![0; map.levels.len()];
        for r in rects {
            out[r.level] += area(r);
        }
        out
    }

    #[test]
    fn arrival_lights_coarse_levels_first_within_the_budget_then_everything_once() {
        let (mut map, eye) = map_at(0.0);
        let strips = map.update(&eye, 8.0);
        map.take(u64::MAX, usize::MAX);
        let mut q = LightQueue::new(map.levels.len());
        q.set_sun(90.0);
        q.heights_baked(&strips);
        let n = map.levels.len();
        let active: Vec<usize> = (0..n).filter(|&l| map.levels[l].active).collect();
        let whole = u64::from(map.side()).pow(2);
        assert_eq!(q.pending_texels(&map), whole * active.len() as u64);
        // Nothing lit: every level is drawn unshadowed.
        assert!(active.iter().all(|&l| q.light_from(&map, l) == NO_LIGHT));
        let budget = whole / 3;
        let mut all = Vec::new();
        let mut frames = 0;
        while q.pending_texels(&map) > 0 {
            let rects = q.take(&map, budget, 96, |_| true);
            let texels: u64 = rects.iter().map(area).sum();
            assert!(texels <= budget, "{texels} over {budget}");
            // The coarsest level with light lends it to every finer level still without.
            let lit: Vec<usize> = active
                .iter()
                .copied()
                .filter(|&l| q.light_from(&map, l) == l as u32)
                .collect();
            if let Some(&finest) = lit.first() {
                assert!(lit.iter().all(|&l| l >= finest), "{lit:?}");
                for &l in active.iter().filter(|&&l| l < finest) {
                    assert_eq!(q.light_from(&map, l), finest as u32);
                }
            }
            all.extend(rects);
            frames += 1;
            assert!(frames < 1000);
        }
        // Coarsest first: the first rectangle lit is of the coarsest active level.
        assert_eq!(all[0].level, *active.last().unwrap());
        // Every texel of every active level lit exactly once (rectangles never overlap).
        let c = covered(&map, &all);
        for &l in &active {
            assert_eq!(c[l], whole, "level {l}");
        }
        assert!(active.iter().all(|&l| q.light_from(&map, l) == l as u32));
    }

    #[test]
    fn a_level_waits_for_the_heights_it_reads() {
        let (mut map, eye) = map_at(0.0);
        map.update(&eye, 8.0);
        map.take(u64::MAX, usize::MAX);
        let mut q = LightQueue::new(map.levels.len());
        q.set_sun(90.0);
        let coarsest = (0..map.levels.len())
            .rev()
            .find(|&l| map.levels[l].active)
            .unwrap();
        // Only the coarsest level's heights are in: it alone is lit.
        let rects = q.take(&map, u64::MAX, 96, |l| l == coarsest);
        assert!(rects.iter().all(|r| r.level == coarsest), "{rects:?}");
        assert!(!rects.is_empty());
        // Nothing at all while the coarsest waits.
        let mut q = LightQueue::new(map.levels.len());
        q.set_sun(90.0);
        assert!(q.take(&map, u64::MAX, 96, |_| false).is_empty());
    }

    #[test]
    fn flying_lights_what_the_levels_uncover_and_a_turn_keeps_the_old_light_drawn() {
        let (mut map, eye) = map_at(0.0);
        map.update(&eye, 8.0);
        map.take(u64::MAX, usize::MAX);
        let mut q = LightQueue::new(map.levels.len());
        q.set_sun(90.0);
        while !q.take(&map, u64::MAX, 96, |_| true).is_empty() {}
        assert_eq!(q.pending_texels(&map), 0);
        // Moving: what the levels uncover is all that is lit, and until then the level
        // borrows the coarser level's light.
        let (_, far) = map_at(5000.0);
        let strips = map.update(&far, 8.0);
        map.take(u64::MAX, usize::MAX);
        assert!(!strips.is_empty());
        q.heights_baked(&strips);
        let moved = strips[0].level;
        if map.levels[moved].active {
            assert_ne!(q.light_from(&map, moved), moved as u32);
        }
        let mut lit = Vec::new();
        loop {
            let r = q.take(&map, u64::MAX, 96, |_| true);
            if r.is_empty() {
                break;
            }
            lit.extend(r);
        }
        let uncovered: u64 = strips
            .iter()
            .filter(|s| map.levels[s.level].active)
            .map(area)
            .sum();
        assert!(lit.iter().map(area).sum::<u64>() <= uncovered);
        // A turned sun: every level relit, each drawn with its own (old) light meanwhile.
        q.set_sun(120.0);
        let whole = u64::from(map.side()).pow(2);
        let active = (0..map.levels.len()).filter(|&l| map.levels[l].active);
        assert_eq!(
            q.pending_texels(&map),
            whole * active.clone().count() as u64
        );
        assert!(active.clone().all(|l| q.light_from(&map, l) == l as u32));
        // Forgetting the light (nothing read it) makes every level unshadowed again.
        q.forget();
        assert!(active.clone().all(|l| q.light_from(&map, l) == NO_LIGHT));
    }

    #[test]
    fn a_sun_turning_every_frame_relights_every_level_in_rounds() {
        let (mut map, eye) = map_at(0.0);
        map.update(&eye, 8.0);
        map.take(u64::MAX, usize::MAX);
        let mut q = LightQueue::new(map.levels.len());
        q.set_sun(90.0);
        while !q.take(&map, u64::MAX, 96, |_| true).is_empty() {}
        let whole = u64::from(map.side()).pow(2);
        let active: Vec<usize> = (0..map.levels.len())
            .filter(|&l| map.levels[l].active)
            .collect();
        let all = whole * active.len() as u64;
        // A budget that lights a fifth of the levels a frame, and a sun that turns every
        // frame (a running day): each level is lit once per round, the finest too, and a round
        // takes the frames its texels need (no restart from the coarsest level).
        let budget = all / 5;
        let mut lit = vec![0u64; map.levels.len()];
        let mut frames = 0;
        for frame in 0..60 {
            q.set_sun(91.0 + frame as f32 * 0.1);
            for r in q.take(&map, budget, 96, |_| true) {
                lit[r.level] += area(&r);
            }
            frames += 1;
            if active.iter().all(|&l| lit[l] >= 2 * whole) {
                break;
            }
        }
        assert!(
            active.iter().all(|&l| lit[l] >= 2 * whole),
            "two rounds in {frames} frames: {lit:?}"
        );
        assert!(frames <= 12, "two rounds took {frames} frames");
        // A round that ends as the sun turns leaves the next one due (frames must come).
        while !q.take(&map, budget, 96, |_| true).is_empty() {}
        q.set_sun(200.0);
        q.set_sun(201.0);
        while q.relighting() {
            q.take(&map, budget, 96, |_| true);
        }
        assert_eq!(q.pending_texels(&map), all, "the next round is due");
        // The sun stands still again: the round under way and one more, then nothing.
        let mut rest = 0;
        while !q.take(&map, budget, 96, |_| true).is_empty() {
            rest += 1;
            assert!(rest <= 12);
        }
        assert_eq!(q.pending_texels(&map), 0);
    }
}
