//! The clipmap's tests: levels, strips, patches and their budgets.

use super::*;
use crate::landscape::TerrainFn;

/// Moves the levels and bakes everything at once (no budget): what they uncovered.
fn settle(map: &mut Clipmap, eye: &Eye, pixel_error: f64) -> Vec<Strip> {
    let strips = map.update(eye, pixel_error);
    map.take(u64::MAX, usize::MAX);
    strips
}

fn land() -> Landscape {
    Landscape {
        seed: 7,
        octaves: 10,
        gain: 0.47,
        feature_log2: 10,
        peak_height: 600.0,
        terrain: TerrainFn::Fbm,
        period: 0,
    }
}

fn eye(x: f64, z: f64) -> Eye {
    Eye {
        position: [x, 300.0, z],
        ground: 0.0,
        pixels_per_radian: 300.0,
    }
}

#[test]
fn finer_levels_nest_inside_coarser_ones_on_patch_boundaries() {
    let mut map = Clipmap::new(&land(), 1.0, 300.0);
    let mut state = 1u32;
    for _ in 0..500 {
        state = crate::noise::pcg(state);
        let x = (f64::from(state) / 4e9 - 0.5) * 1e7;
        state = crate::noise::pcg(state);
        let z = (f64::from(state) / 4e9 - 0.5) * 1e7;
        settle(&mut map, &eye(x, z), 1.0);
        for l in 1..map.levels.len() {
            let Some([hx, hy]) = map.hole(l) else {
                continue;
            };
            let b = map.patch as i32;
            let (fine, coarse) = (map.levels[l - 1].origin, map.levels[l].origin);
            // Exactly on patch boundaries, and at least one patch from every edge.
            assert_eq!(fine[0] / 2 - coarse[0], hx * b, "x {x} z {z} level {l}");
            assert_eq!(fine[1] / 2 - coarse[1], hy * b);
            assert!(
                (1..=PATCHES / 2 - 1).contains(&hx),
                "hole {hx} at level {l}"
            );
            assert!(
                (1..=PATCHES / 2 - 1).contains(&hy),
                "hole {hy} at level {l}"
            );
        }
        // The eye is inside the first level, at least (cells/2 - patch) from its edges.
        let l0 = map.levels.iter().find(|l| l.active).unwrap();
        let c = f64::from(map.cells());
        let e = [
            (x / l0.spacing()) - f64::from(l0.origin[0]),
            (z / l0.spacing()) - f64::from(l0.origin[1]),
        ];
        for v in e {
            assert!(
                v >= c / 2.0 - f64::from(map.patch) - 1e-9
                    && v <= c / 2.0 + f64::from(map.patch) + 1e-9
            );
        }
    }
}

#[test]
fn trimmed_patches_draw_every_cell_of_a_region_once_and_few_outside() {
    let mut map = Clipmap::new(&land(), 1.0, 300.0);
    settle(&mut map, &eye(1000.0, -300.0), 1.0);
    let patches = map.patches([0.0, 600.0], |_, _| true);
    // A square that cuts patches of several levels, on and off cell boundaries.
    let region = [-2000.0, -3100.5, 3700.25, 2600.0];
    let (whole, subs) = map.trim(&patches, region);
    assert!(!whole.is_empty() && !subs.is_empty());
    let b = map.patch as i32;
    let n = map.sub_cells() as i32;
    // Each drawn cell, by level: (level, column, row) in the level's cells.
    let mut drawn = std::collections::HashMap::new();
    let mut add = |p: &Patch, side: i32| {
        let (sx, sy) = ((p.sub & 0xffff) as i32, (p.sub >> 16) as i32);
        for j in 0..side {
            for i in 0..side {
                let c = (p.at[0] as i32 * b + sx + i, p.at[1] as i32 * b + sy + j);
                *drawn.entry((p.level, c.0, c.1)).or_insert(0) += 1;
            }
        }
    };
    whole.iter().for_each(|p| add(p, b));
    subs.iter().for_each(|p| add(p, n));
    let (mut outside, mut total) = (0, 0);
    for p in &patches {
        let level = &map.levels[p.level as usize];
        let s = level.spacing();
        for j in 0..b {
            for i in 0..b {
                let (ci, cj) = (p.at[0] as i32 * b + i, p.at[1] as i32 * b + j);
                let x = f64::from(level.origin[0] + ci) * s;
                let z = f64::from(level.origin[1] + cj) * s;
                let meets =
                    x < region[2] && x + s > region[0] && z < region[3] && z + s > region[1];
                let times = drawn.get(&(p.level, ci, cj)).copied().unwrap_or(0);
                assert!(times <= 1, "cell ({ci}, {cj}) of level {} twice", p.level);
                if meets {
                    assert_eq!(times, 1, "cell ({ci}, {cj}) of level {} not drawn", p.level);
                } else {
                    outside += times;
                }
                total += times;
            }
        }
    }
    // Before trimming, every cell of a crossed patch was drawn; now a sub-patch's width
    // along the edge at most.
    assert!(
        outside * 5 < total,
        "{outside} of {total} drawn cells outside"
    );
}

#[test]
fn strips_cover_exactly_what_a_moved_level_uncovers() {
    // Loose enough for the smallest patches: a small square to check sample by sample.
    let mut map = Clipmap::new(&land(), 64.0, 300.0);
    assert_eq!(map.patch, PATCH_RANGE.0);
    let side = map.side() as i64;
    settle(&mut map, &eye(0.0, 0.0), 64.0);
    let mut state = 5u32;
    for _ in 0..60 {
        state = crate::noise::pcg(state);
        let step = f64::from(state % 97) - 48.0;
        state = crate::noise::pcg(state);
        let step_z = f64::from(state % 97) - 48.0;
        let before: Vec<Level> = map.levels.clone();
        let e = eye(before_x(&map) + step * 3.0, before_z(&map) + step_z * 3.0);
        let strips = settle(&mut map, &e, 64.0);
        for (l, level) in map.levels.iter().enumerate() {
            if !level.active {
                continue;
            }
            let old = before[l].origin;
            let mut count = std::collections::HashMap::new();
            for s in strips.iter().filter(|s| s.level == l) {
                for j in 0..i64::from(s.extent[1]) {
                    for i in 0..i64::from(s.extent[0]) {
                        *count
                            .entry((i64::from(s.origin[0]) + i, i64::from(s.origin[1]) + j))
                            .or_insert(0) += 1;
                    }
                }
            }
            for j in 0..side {
                for i in 0..side {
                    let (x, z) = (
                        i64::from(level.origin[0]) + i,
                        i64::from(level.origin[1]) + j,
                    );
                    let was = before[l].active
                        && (i64::from(old[0])..i64::from(old[0]) + side).contains(&x)
                        && (i64::from(old[1])..i64::from(old[1]) + side).contains(&z);
                    let n = count.remove(&(x, z)).unwrap_or(0);
                    assert_eq!(n, usize::from(!was), "level {l} sample ({x}, {z})");
                }
            }
            assert!(count.is_empty(), "level {l} baked outside its square");
        }
    }
}

fn before_x(map: &Clipmap) -> f64 {
    let l = map.levels.iter().find(|l| l.active).unwrap();
    (f64::from(l.origin[0]) + f64::from(map.cells()) / 2.0) * l.spacing()
}

fn before_z(map: &Clipmap) -> f64 {
    let l = map.levels.iter().find(|l| l.active).unwrap();
    (f64::from(l.origin[1]) + f64::from(map.cells()) / 2.0) * l.spacing()
}

#[test]
fn level_errors_shrink_with_spacing_and_the_knob_sizes_patches() {
    let land = land();
    let coarse = level_error(&land, 6);
    let fine = level_error(&land, 0);
    assert!(fine < coarse && fine > 0.0, "fine {fine} coarse {coarse}");
    let errors: Vec<(i32, f64)> = (0..8).map(|l| (l, level_error(&land, l))).collect();
    let tight = Clipmap::patch_for(&errors, 0.5, 1000.0);
    let loose = Clipmap::patch_for(&errors, 8.0, 1000.0);
    assert!(tight > loose, "{tight} {loose}");
    // The bound the layout reports is what the knob asked for (unless patches max out).
    let mut map = Clipmap::new(&land, 2.0, 1000.0);
    settle(&mut map, &eye(0.0, 0.0), 2.0);
    let bound = map.error_bound(1000.0);
    assert!(
        bound <= 2.0 || map.patch == PATCH_RANGE.1,
        "bound {bound} patch {}",
        map.patch
    );
}

#[test]
fn a_high_eye_skips_fine_levels_and_culling_drops_patches() {
    let mut map = Clipmap::new(&land(), 1.0, 300.0);
    settle(&mut map, &eye(0.0, 0.0), 1.0);
    let low = map.levels.iter().filter(|l| l.active).count();
    let mut high = eye(0.0, 0.0);
    high.position[1] = 5000.0;
    settle(&mut map, &high, 1.0);
    let few = map.levels.iter().filter(|l| l.active).count();
    assert!(few < low, "{few} levels at 5 km, {low} at 300 m");
    let all = map.patches([0.0, 600.0], |_, _| true).len();
    let none = map.patches([0.0, 600.0], |_, _| false).len();
    let rings = (PATCHES * PATCHES - PATCHES * PATCHES / 4) as usize;
    assert_eq!(all, (few - 1) * rings + (PATCHES * PATCHES) as usize);
    assert_eq!(none, 0);
}

#[test]
fn a_budget_bakes_coarse_levels_first_and_finer_ones_wait_for_them() {
    let mut map = Clipmap::new(&land(), 1.0, 300.0);
    map.update(&eye(0.0, 0.0), 1.0);
    let active = map.levels.iter().filter(|l| l.active).count();
    let side = u64::from(map.side());
    let whole = side * side;
    assert_eq!(map.pending_texels(), active as u64 * whole);
    assert_eq!(map.first_drawn(), map.levels.len(), "nothing is baked yet");
    // One and a half levels a frame: the coarsest, then half of the next.
    let strips = map.take(whole + whole / 2, usize::MAX);
    let baked: u64 = strips
        .iter()
        .map(|s| u64::from(s.extent[0]) * u64::from(s.extent[1]))
        .sum();
    assert!(baked <= whole + whole / 2 && baked > whole, "{baked}");
    let n = map.levels.len();
    assert_eq!(
        map.first_drawn(),
        n - 1,
        "the coarsest level is drawn alone"
    );
    assert!(
        map.hole(n - 1).is_none(),
        "drawn whole while finer levels wait"
    );
    assert_eq!(
        map.patches([0.0, 600.0], |_, _| true).len(),
        (PATCHES * PATCHES) as usize
    );
    let mut frames = 1;
    while map.pending_texels() > 0 {
        let strips = map.take(whole + whole / 2, usize::MAX);
        let baked: u64 = strips
            .iter()
            .map(|s| u64::from(s.extent[0]) * u64::from(s.extent[1]))
            .sum();
        assert!(baked <= whole + whole / 2, "{baked}");
        frames += 1;
    }
    // Whole rows only: a frame may fall a row short of its budget.
    let least = (2 * active).div_ceil(3);
    assert!(
        (least..=least + 1).contains(&frames),
        "{frames} frames for {active} levels"
    );
    assert_eq!(
        map.first_drawn(),
        map.levels.iter().position(|l| l.active).unwrap()
    );
    // A pending strip is kept only where it overlaps its level's new square.
    settle(&mut map, &eye(0.0, 0.0), 1.0);
    let far = eye(1.0e5, 0.0);
    map.update(&far, 1.0);
    for s in &map.pending {
        let o = map.levels[s.level].origin;
        let side = map.side() as i32;
        assert!(
            s.origin[0] >= o[0]
                && s.origin[1] >= o[1]
                && s.origin[0] + s.extent[0] as i32 <= o[0] + side
                && s.origin[1] + s.extent[1] as i32 <= o[1] + side,
            "{s:?} outside the square at {o:?}"
        );
    }
}

#[test]
fn a_budget_under_one_row_still_bakes_a_row_and_leaves_no_empty_strip() {
    let mut map = Clipmap::new(&land(), 1.0, 300.0);
    settle(&mut map, &eye(0.0, 0.0), 1.0);
    // Walk in small steps with a one-texel budget: strips one or a few rows high.
    for k in 1..40 {
        map.update(&eye(f64::from(k) * 3.0, f64::from(k) * 2.0), 1.0);
        let strips = map.take(1, usize::MAX);
        assert!(strips.len() <= 1, "{strips:?}");
        for s in strips.iter().chain(&map.pending) {
            assert!(s.extent[0] > 0 && s.extent[1] > 0, "an empty strip: {s:?}");
        }
        // A level is drawn again exactly when nothing of it (or coarser) waits.
        let waiting = map.pending_texels() > 0;
        let all_drawn = map.first_drawn() == map.levels.iter().position(|l| l.active).unwrap();
        assert_eq!(all_drawn, !waiting, "step {k}");
    }
    while map.pending_texels() > 0 {
        map.take(1, usize::MAX);
    }
    assert!(map.pending.is_empty());
}
