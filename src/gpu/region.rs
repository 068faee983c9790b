//! Rectangles of a level's samples cut to a bounded region (the tile): what of a strip the
//! bake skips, and what of a region is still owed. Plain integer arithmetic, no GPU.

use super::landscape::Rect;

/// `rect` less what lies outside the square `bounds` (metres: x0, z0, x1, z1) by more than two
/// samples: texels no clamped vertex, bilinear read or morph ever reaches. `None` when nothing
/// is left. What is cut is never baked (the bounded tile's levels reach far beyond it).
pub(crate) fn crop(rect: Rect, bounds: [f64; 4]) -> Option<Rect> {
    cut(rect, bounds, 2.0)
}

/// `rect` less what lies outside the samples in `bounds` (metres, on the level's samples).
pub(crate) fn crop_exact(rect: Rect, bounds: [f64; 4]) -> Option<Rect> {
    cut(rect, bounds, 0.0)
}

fn cut(rect: Rect, bounds: [f64; 4], margin: f64) -> Option<Rect> {
    let s = 2f64.powi(rect.level_log2);
    let (min, max) = (f64::from(i32::MIN), f64::from(i32::MAX));
    let lo = |v: f64| ((v / s).floor() - margin).clamp(min, max) as i64;
    let hi = |v: f64| ((v / s).ceil() + margin + 1.0).clamp(min, max) as i64;
    let mut r = rect;
    for (axis, (b0, b1)) in [(0, (bounds[0], bounds[2])), (1, (bounds[1], bounds[3]))] {
        let start = i64::from(rect.origin[axis]).max(lo(b0));
        let end = (i64::from(rect.origin[axis]) + i64::from(rect.extent[axis])).min(hi(b1));
        if end <= start {
            return None;
        }
        r.origin[axis] = start as i32;
        r.extent[axis] = (end - start) as u32;
    }
    Some(r)
}

/// `a` less `b`: up to four rectangles (bands below and above `b`, then left and right of it).
pub(crate) fn subtract(a: Rect, b: Option<Rect>) -> Vec<Rect> {
    let Some(b) = b else {
        return vec![a];
    };
    let span = |r: &Rect, i: usize| {
        let o = i64::from(r.origin[i]);
        (o, o + i64::from(r.extent[i]))
    };
    let ((ax0, ax1), (az0, az1)) = (span(&a, 0), span(&a, 1));
    let ((bx0, bx1), (bz0, bz1)) = (span(&b, 0), span(&b, 1));
    let (ix0, ix1, iz0, iz1) = (ax0.max(bx0), ax1.min(bx1), az0.max(bz0), az1.min(bz1));
    if ix0 >= ix1 || iz0 >= iz1 {
        return vec![a];
    }
    let rect = |x0: i64, x1: i64, z0: i64, z1: i64| Rect {
        origin: [x0 as i32, z0 as i32],
        extent: [(x1 - x0) as u32, (z1 - z0) as u32],
        ..a
    };
    [
        (ax0, ax1, az0, iz0),
        (ax0, ax1, iz1, az1),
        (ax0, ix0, iz0, iz1),
        (ix1, ax1, iz0, iz1),
    ]
    .into_iter()
    .filter(|&(x0, x1, z0, z1)| x0 < x1 && z0 < z1)
    .map(|(x0, x1, z0, z1)| rect(x0, x1, z0, z1))
    .collect()
}
