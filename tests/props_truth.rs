//! The props against the truths beside their twin's geometry: the reference draws the props
//! every method draws (`--method reference` with props), and the props' shadows on the ground
//! agree with f64 rays towards the sun.

mod common;
#[path = "common/props.rs"]
mod props_common;

use glam::DVec3;
use props_common::*;
use relief::gpu::headless;
use relief::{Method, WorldParams};

/// The reference marches the props at its samples (`--method reference` with props): it
/// draws the props the marching method shows, with their shadows and occlusion on the ground,
/// and changes nothing else nearer than the props' cut-off (past it the reference draws whole
/// the props a frame sinks); the marching method's frame is nearer it than the bare reference
/// (the negative control: the metric sees the props).
/// How far the screen-size cut-off sinks the shipped kinds at [`SIZE`]: a 1.5 m boulder under
/// 1.95 pixels tall (1.5 pixels, 1.3 times for its own threshold) is 80 m out, a 4 m stone
/// 220 m; past 250 m a frame sinks most of them.
const SUNK: f32 = 250.0;

#[test]
fn the_reference_draws_the_props_the_methods_draw() {
    let gpu = common::gpu();
    let on = params(true);
    let v = view(&on);
    let mut w = world(&gpu, on);
    let frame = draw(&gpu, &mut w, &v);
    let hits = w.props_hits(&gpu.device, &gpu.queue).unwrap().unwrap();
    let shading = relief::Shading::default();
    let reference = |p: &WorldParams| {
        let scene = relief::props::kinds::landscape();
        headless::render_world_rays_with_props(
            &gpu,
            (p, &scene),
            &shading,
            &v,
            Method::Reference,
            None,
        )
        .unwrap()
    };
    let bare = reference(&params(false));
    let with = reference(&on);
    let (w_px, h_px) = (SIZE.0 as usize, SIZE.1 as usize);
    // What the marching method marks (a prop, its shadow or its occlusion), grown by a pixel:
    // the reference's 3x3 samples see a prop's edge a sample sooner.
    let near_mark = |i: usize| near_props_mark(&hits, (w_px, h_px), i, 1);
    let (mut props, mut drawn, mut changed, mut outside, mut sunk) = (0, 0, 0, 0, 0);
    let (mut err_with, mut err_bare, mut n) = (0u64, 0u64, 0u64);
    for i in 0..w_px * h_px {
        let px = |img: &[u8]| [img[4 * i], img[4 * i + 1], img[4 * i + 2]];
        let differs = px(&bare.rgba)
            .iter()
            .zip(px(&with.rgba))
            .any(|(a, b)| a.abs_diff(b) > 1);
        changed += usize::from(differs);
        // Past SUNK m the props' screen-size cut-off sinks props the reference draws whole.
        if differs && !near_mark(i) {
            let far = bare.distance[i] < 0.0 || bare.distance[i] >= SUNK;
            outside += usize::from(!far);
            sunk += usize::from(far);
        }
        if f32::from_bits(hits[i][0]) < 1.0 {
            props += 1;
            drawn += usize::from(differs);
        }
        if near_props_mark(&hits, (w_px, h_px), i, 0) {
            let diff = |img: &[u8]| -> u64 {
                px(img)
                    .iter()
                    .zip(px(&frame))
                    .map(|(a, b)| u64::from(a.abs_diff(b)))
                    .sum()
            };
            err_with += diff(&with.rgba);
            err_bare += diff(&bare.rgba);
            n += 3;
        }
    }
    let (mean_with, mean_bare) = (err_with as f64 / n as f64, err_bare as f64 / n as f64);
    eprintln!(
        "reference: {changed} pixels changed by the props ({outside} outside what the marching \
         method marks, {sunk} more past {SUNK} m); of its {props} prop pixels {drawn} drawn; where it marks, the frame is \
         {mean_with:.1} levels from the reference with props, {mean_bare:.1} from the bare one"
    );
    assert!(props > 300, "{props}");
    assert!(drawn * 100 >= props * 95, "{drawn} of {props}");
    assert!(outside * 200 <= changed, "{outside} of {changed}");
    assert!(mean_with * 2.0 < mean_bare, "{mean_with} {mean_bare}");
}

/// The props' shadows on the ground agree with rays towards the sun through the props' f64
/// twin: at sampled ground points (the twin's continuous surface under each pixel the march
/// left without a prop), where the twin's ray meets a prop the frame's props' share of the sun
/// is under 0.1, and where it passes every prop by half again the penumbra's width the share is
/// over 0.9, in at least 99% of the points outside the penumbra; both kinds are found (the
/// test can fail).
#[test]
fn the_props_shadows_agree_with_f64_rays_towards_the_sun() {
    let gpu = common::gpu();
    let (mut shadowed, mut lit, mut agree, mut penumbra) = (0, 0, 0, 0);
    // A low sun's long shadows, and a high sun's ground lit between the props.
    for elevation in [15.0, 40.0] {
        let mut p = params(true);
        let v = view(&p);
        p.sky.sun_elevation = elevation;
        let mut w = world(&gpu, p);
        draw(&gpu, &mut w, &v);
        let hits = w.props_hits(&gpu.device, &gpu.queue).unwrap().unwrap();
        let inverse = w.relative_matrix().as_dmat4().inverse();
        let scene = w.props_scene().clone();
        let tapes = scene.compile(&p.props).unwrap();
        let water = Some(f64::from(p.water_level) / p.land.peak_height);
        let props = |q: DVec3| {
            relief::props::query::distance((&scene, &tapes, &p.props), (&p.land, water), q)
                .map(|(d, _)| d)
        };
        let sun = p.sky.sun_direction().as_dvec3();
        let pixels = f64::from(SIZE.1) / (2.0 * (0.4f64).tan());
        let land = &p.land;
        // The twin's ground along a pixel's ray, within 150 m.
        let ground = |dir: DVec3| -> Option<DVec3> {
            let above = |t: f64| {
                let q = v.eye + dir * t;
                q.y - land.height_at(q.x, q.z)
            };
            let (mut t0, mut t) = (0.0, 0.05);
            while t < 150.0 {
                if above(t) < 0.0 {
                    for _ in 0..30 {
                        let m = 0.5 * (t0 + t);
                        if above(m) < 0.0 {
                            t = m;
                        } else {
                            t0 = m;
                        }
                    }
                    return Some(v.eye + dir * t0);
                }
                t0 = t;
                t += 0.02 + 0.01 * t;
            }
            None
        };
        // The props as the frame placed them (sunk past their cut-off, as it marched them), their
        // fields in f64: the distance from world point `r` to the nearest of those of the
        // (2k+1)^2 cells around it, or `None` where none stands there.
        let (side, records) = w.props_records(&gpu.device, &gpu.queue).unwrap().unwrap();
        let eye_cell = p.props.cell_at(v.eye.x, v.eye.z);
        let half = i64::from(side / 2);
        // Each with its displacements' amplitude: the frame's shadows are those of the undisplaced
        // fields (docs/props.md), so within a displacement of a surface is the penumbra here.
        let near = |r: DVec3, k: i64| -> Option<(f64, f64)> {
            let [cx, cz] = p.props.cell_at(r.x, r.z);
            let mut best: Option<(f64, f64)> = None;
            for (dx, dz) in (-k..=k).flat_map(|a| (-k..=k).map(move |b| (a, b))) {
                let (col, row) = (cx + dx - eye_cell[0] + half, cz + dz - eye_cell[1] + half);
                if col < 0 || row < 0 || col >= i64::from(side) || row >= i64::from(side) {
                    continue;
                }
                let rec = &records[(row * i64::from(side) + col) as usize];
                if rec[3] > 0.0 {
                    let rough = tapes[rec[6] as usize].roughness() * f64::from(rec[3]);
                    let d = record_distance(&tapes, rec, r - v.eye).0;
                    if best.is_none_or(|b| d < b.0) {
                        best = Some((d, rough));
                    }
                }
            }
            best
        };
        let band = f64::from(p.props.band);
        // The twin's ray towards the sun from `q`: Some(true) where it passes `margin` inside a
        // prop, Some(false) where it passes every prop by half again the penumbra (the march's
        // share is 8 distance over range) and `margin`, None between. It ends above the band every
        // prop stands in.
        let twin_shadow = |q: DVec3, margin: f64| -> Option<bool> {
            let mut clear = true;
            let mut t = 0.05;
            while t < 300.0 {
                let r = q + sun * t;
                if r.y > land.height_at(r.x, r.z) + band + 2.0 {
                    break;
                }
                let (d, rough) = near(r, 1).unwrap_or((4.0, 0.0));
                if d < 0.005 {
                    // In the shadow where the ray passes deeper inside the prop than its
                    // displacements reach, by the margin (else it grazes it: the penumbra's edge).
                    let deepest = (1..100)
                        .filter_map(|k| near(q + sun * (t + 0.02 * f64::from(k)), 1))
                        .map(|(d, rough)| d + rough)
                        .fold(d + rough, f64::min);
                    return (deepest < -margin).then_some(true);
                }
                // Where the 3x3 cells' props leave too little room to say, the 7x7 cells' (those
                // beyond lie at least 20 m off).
                let wide = 1.5 * t / 8.0 + margin;
                if clear && d - rough <= wide {
                    clear = near(r, 3).map_or(20.0, |(d, rough)| (d - rough).min(20.0)) > wide;
                }
                t += d.clamp(0.01, 4.0);
            }
            clear.then_some(false)
        };
        for (i, h) in hits.iter().enumerate() {
            if f32::from_bits(h[0]) < 1.0 {
                continue;
            }
            let dir = eye_relative(&inverse, i, 0.5).normalize();
            let Some(q) = ground(dir) else {
                continue;
            };
            // Not at a prop's foot, where the drawn ground and the twin's part by centimetres.
            if props(q).is_some_and(|d| d < 0.3) {
                continue;
            }
            let share = f32::from_bits(h[3]);
            // The frame's shadow ray leaves two pixels' footprints towards the eye from the drawn
            // ground (so the ground does not shadow itself), and the drawn ground lies within
            // centimetres of the twin's: the margin of the twin's ray.
            let margin = 0.1 + 2.0 * (q - v.eye).length() / pixels;
            match twin_shadow(q + DVec3::Y * 0.02, margin) {
                Some(true) => {
                    shadowed += 1;
                    agree += usize::from(share < 0.1);
                }
                Some(false) => {
                    lit += 1;
                    agree += usize::from(share > 0.9);
                }
                None => penumbra += 1,
            }
        }
    }
    let sampled = shadowed + lit;
    eprintln!(
        "props' shadows: {agree} of {sampled} ground points agree with the twin's rays \
         ({shadowed} in shadow, {lit} lit; {penumbra} in a penumbra left out)"
    );
    assert!(shadowed > 50 && lit > 100, "{shadowed} {lit}");
    assert!(agree * 100 >= sampled * 99, "{agree} of {sampled}");
}

/// From 1.7 m over a meadow towards the sun, where standing stones' shadows fall over the
/// grass: the view of the grass tests below.
fn meadow_towards_the_sun(size: (u32, u32)) -> relief::WorldView {
    let eye = DVec3::new(2740.0, 1111.7, -3000.0);
    relief::WorldView::look_at(eye, DVec3::new(2770.0, 1107.7, -2990.0), 0.9, size)
}

/// The reference's blades of grass take the props' shadows (`--method reference` with grass and
/// props), as the frame's grass does (its pass also cuts the blades inside a prop, by the test
/// the frame's cut makes: `no_grass_grows_inside_a_prop`). Where the marching method's frame
/// marks the props' shadow on the ground and no prop, the reference with props is far darker
/// than without them: 0.56 as bright on lavapipe, where unshadowed blades over a shadowed
/// ground leave 0.95 (the blades cover most of it); where the frame marks neither a prop nor
/// its shadow or occlusion, the two agree.
#[test]
fn the_references_grass_takes_the_props_shadows() {
    let gpu = common::gpu();
    let size = (96, 54);
    let mut on = params(true);
    on.grass.on = true;
    let v = meadow_towards_the_sun(size);
    let mut w = world(&gpu, on);
    headless::render_world_image(&gpu, &mut w, &v, size, headless::TILE, None).unwrap();
    let hits = w.props_hits(&gpu.device, &gpu.queue).unwrap().unwrap();
    let shading = relief::Shading::default();
    let reference = |p: &WorldParams| {
        let scene = relief::props::kinds::landscape();
        let image = headless::render_world_rays_with_props(
            &gpu,
            (p, &scene),
            &shading,
            &v,
            Method::Reference,
            None,
        )
        .unwrap();
        assert!(image.blades > 1000, "{} blades", image.blades);
        image.rgba
    };
    let mut off = on;
    off.props.on = false;
    let (with, without) = (reference(&on), reference(&off));
    let lum = |img: &[u8], i: usize| {
        f64::from(img[4 * i]) + f64::from(img[4 * i + 1]) + f64::from(img[4 * i + 2])
    };
    let (wide, high) = (size.0 as usize, size.1 as usize);
    let near_mark = |i: usize| near_props_mark(&hits, (wide, high), i, 2);
    let (mut dark, mut bright, mut shadowed) = (0.0, 0.0, 0);
    let (mut clear, mut agree) = (0, 0);
    for i in 0..wide * high {
        let h = hits[i];
        if f32::from_bits(h[0]) >= 1.0 && f32::from_bits(h[3]) < 0.3 {
            shadowed += 1;
            dark += lum(&with, i);
            bright += lum(&without, i);
        } else if !near_mark(i) {
            clear += 1;
            let d = (0..3).all(|c| with[4 * i + c].abs_diff(without[4 * i + c]) <= 2);
            agree += usize::from(d);
        }
    }
    let ratio = dark / bright;
    eprintln!(
        "{shadowed} pixels in the props' shadow: {ratio:.3} as bright with props; {agree} of \
         {clear} pixels outside the props' marks agree"
    );
    assert!(shadowed >= 50, "{shadowed}");
    assert!(
        ratio < 0.75,
        "the blades in the props' shadow: {ratio:.3} as bright"
    );
    assert!(agree * 100 >= clear * 98, "{agree} of {clear}");
}

/// The grass of the methods that overlay the props (the forward mesh, the hybrid) takes their
/// shadow too: each blade reads the props' shade map at its root (`grass_scatter.wgsl`). Where
/// the marching method marks the props' shadow on the ground and no prop, the overlay's frame
/// with props is as much darker than without them as the marching method's (on lavapipe 0.52
/// as bright against 0.55; before, its blades stood unshadowed over the shadowed ground: 0.92).
#[test]
fn the_overlays_grass_takes_the_props_shadows() {
    let gpu = common::gpu();
    let size = (96, 54);
    let mut on = params(true);
    on.grass.on = true;
    let v = meadow_towards_the_sun(size);
    let image = |p: WorldParams, config: relief::MethodConfig| {
        let mut w = world_drawn(&gpu, p, config);
        let rgba = headless::render_world_image(&gpu, &mut w, &v, size, headless::TILE, None)
            .unwrap()
            .0;
        (rgba, w)
    };
    let (marched, w) = image(on, marching());
    let hits = w.props_hits(&gpu.device, &gpu.queue).unwrap().unwrap();
    let mut off = on;
    off.props.on = false;
    let (bare, _) = image(off, marching());
    let lum =
        |img: &[u8], i: usize| -> f64 { img[4 * i..4 * i + 3].iter().map(|&c| f64::from(c)).sum() };
    let shadowed: Vec<usize> = (0..hits.len())
        .filter(|&i| f32::from_bits(hits[i][0]) >= 1.0 && f32::from_bits(hits[i][3]) < 0.3)
        .collect();
    let ratio = |with: &[u8], without: &[u8]| {
        let dark: f64 = shadowed.iter().map(|&i| lum(with, i)).sum();
        dark / shadowed.iter().map(|&i| lum(without, i)).sum::<f64>()
    };
    let marching_ratio = ratio(&marched, &bare);
    eprintln!(
        "the marching method: {} pixels in the props' shadow, {marching_ratio:.3} as bright",
        shadowed.len()
    );
    assert!(shadowed.len() >= 50, "{}", shadowed.len());
    for config in [
        relief::MethodConfig::new(Method::Mesh),
        relief::MethodConfig::new(Method::Hybrid).with_samples(1),
    ] {
        let ((with, w), (without, _)) = (image(on, config), image(off, config));
        assert!(w.props_overlaid(), "{config:?}");
        let r = ratio(&with, &without);
        eprintln!("{config:?}: {r:.3} as bright");
        assert!(
            r < 0.75 && (r - marching_ratio).abs() < 0.1,
            "{config:?}: the blades in the props' shadow: {r:.3} as bright (the marching \
             method's {marching_ratio:.3})"
        );
    }
}
