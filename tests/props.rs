//! The GPU's props (`wgsl/props*.wgsl`) against their CPU twin (`relief::props`): the props
//! the scatter places are the twin's, cell for cell, standing on the ground; the march's hits
//! lie on the twin's surfaces with the twin's normals; props change the frame only where they
//! are, and a world without props draws as before.

mod common;
#[path = "common/props.rs"]
mod props_common;

use glam::DVec3;
use props_common::*;
use relief::props::place;
use relief::{Method, MethodConfig, WorldParams, WorldView};

#[test]
fn the_scatter_places_the_twins_props_on_the_ground() {
    let gpu = common::gpu();
    let p = params(true);
    let v = view(&p);
    let mut w = world(&gpu, p);
    draw(&gpu, &mut w, &v);
    assert!(w.draws_props());
    let (side, records) = w.props_records(&gpu.device, &gpu.queue).unwrap().unwrap();
    let scene = w.props_scene().clone();
    let weights = place::cumulative(&scene.kinds);
    let seed = p.land.seed;
    let eye_cell = p.props.cell_at(v.eye.x, v.eye.z);
    let half = i64::from(side / 2);
    let cell = f64::from(p.props.cell);
    let water = (f64::from(p.water_level) / p.land.peak_height) as f32;
    let (mut stood, mut twin_stood, mut near) = (0, 0, 0);
    for (i, r) in records.iter().take((side * side) as usize).enumerate() {
        let rel = [
            i as i64 % i64::from(side) - half,
            i as i64 / i64::from(side) - half,
        ];
        let c = [eye_cell[0] + rel[0], eye_cell[1] + rel[1]];
        let twin = place::prop_at(&weights, seed, c);
        let x = (c[0] as f64 + f64::from(twin.offset[0])) * cell;
        let z = (c[1] as f64 + f64::from(twin.offset[1])) * cell;
        let dist = ((x - v.eye.x).powi(2) + (z - v.eye.z).powi(2)).sqrt();
        // The ground by the twin: gentle or rock, and above the water or not.
        let land = &p.land;
        let s = land.sample(relief::noise::Channel::Height, x, z, land.octaves);
        let tint = land
            .sample(relief::noise::Channel::Color, x, z, land.octaves)
            .value;
        let g = [
            s.gradient[0] * land.peak_height,
            s.gradient[1] * land.peak_height,
        ];
        let n_y = 1.0 / (1.0 + g[0] * g[0] + g[1] * g[1]).sqrt();
        let kind = &scene.kinds[twin.kind as usize];
        let ground = (n_y as f32, tint as f32, s.value as f32);
        let keeps = place::keeps(&p.props, &twin, kind.on_rock, ground, Some(water));
        if r[3] > 0.0 {
            assert_eq!(r[6] as u32, twin.kind, "cell {c:?}");
            assert_eq!(r[7].to_bits(), twin.seed, "cell {c:?}");
            assert!((r[4] - twin.turn.cos()).abs() < 1e-5 && (r[5] - twin.turn.sin()).abs() < 1e-5);
            let scale = place::scale_of(kind, twin.scale);
            assert!((r[3] - scale).abs() < 1e-5 * scale, "{} {scale}", r[3]);
            let at = [f64::from(r[0]) + v.eye.x, f64::from(r[2]) + v.eye.z];
            assert!(
                (at[0] - x).abs() < 2e-3 && (at[1] - z).abs() < 2e-3,
                "{at:?} {x} {z}"
            );
            assert!(
                s.value as f32 >= water - 1e-4,
                "a prop under water at {c:?}"
            );
            // On the ground: its foot at most the drawn surface's deviation under the twin's
            // surface (near the eye the levels draw it within centimetres), never over it.
            let foot = f64::from(r[1]) + v.eye.y;
            let surface = land.height_at(x, z);
            if dist < 60.0 {
                assert!(
                    foot < surface && foot > surface - 1.0,
                    "cell {c:?}: foot {foot} on ground {surface}"
                );
            }
        }
        // Near the eye no prop is cut off by its size on screen: the scatter keeps where the
        // twin keeps (but at the edges of the materials, read from the drawn surface).
        if dist < 40.0 {
            near += 1;
            stood += usize::from(r[3] > 0.0);
            twin_stood += usize::from(keeps);
        }
    }
    eprintln!("within 40 m: {near} cells, {stood} props, the twin's {twin_stood}");
    assert!(twin_stood > 20, "{twin_stood}");
    assert!(
        stood.abs_diff(twin_stood) * 20 <= twin_stood,
        "{stood} props where the twin has {twin_stood}"
    );
}

#[test]
fn the_march_hits_the_twins_surfaces() {
    let gpu = common::gpu();
    let p = params(true);
    let v = view(&p);
    let mut w = world(&gpu, p);
    draw(&gpu, &mut w, &v);
    let (_, records) = w.props_records(&gpu.device, &gpu.queue).unwrap().unwrap();
    let hits = w.props_hits(&gpu.device, &gpu.queue).unwrap().unwrap();
    let tapes = w.props_scene().compile(&p.props).unwrap();
    let inverse = w.relative_matrix().as_dmat4().inverse();
    let pixels = f64::from(SIZE.1) / (2.0 * (0.4f64).tan());
    let (mut hit, mut close, mut facing) = (0, 0, 0);
    let mut worst = 0.0f64;
    for (i, h) in hits.iter().enumerate() {
        let depth = f32::from_bits(h[0]);
        if depth >= 1.0 {
            continue;
        }
        hit += 1;
        let rel = eye_relative(&inverse, i, depth);
        // The prop whose sphere holds the point nearest its centre.
        let r = records
            .iter()
            .filter(|r| r[3] > 0.0)
            .min_by(|a, b| {
                let da = (rel - DVec3::new(a[12].into(), a[13].into(), a[14].into())).length();
                let db = (rel - DVec3::new(b[12].into(), b[13].into(), b[14].into())).length();
                da.total_cmp(&db)
            })
            .unwrap();
        let (d, _) = record_distance(&tapes, r, rel);
        let t = rel.length();
        let tolerance = (2.0 * t / pixels).max(0.01);
        worst = worst.max(d.abs() / tolerance);
        close += usize::from(d.abs() <= tolerance);
        // The normal: the twin's at the twin's nearest surface point.
        let [ex, ez] = unpack_snorm(h[1]);
        let gpu_n = oct_decode(ex.into(), ez.into());
        let e = 1e-3;
        let twin_n = [0, 1, 2].map(|a| {
            let mut o = DVec3::ZERO;
            o[a] = e;
            (record_distance(&tapes, r, rel + o).0 - record_distance(&tapes, r, rel - o).0)
                / (2.0 * e)
        });
        let twin_n = DVec3::from(twin_n).normalize_or_zero();
        facing += usize::from(gpu_n.dot(twin_n) > 0.9);
    }
    eprintln!(
        "{hit} hits: {close} within the tolerance, {facing} facing the twin's normal, \
         worst {worst:.2} tolerances"
    );
    assert!(hit > 200, "{hit}");
    assert!(close * 100 >= hit * 99, "{close} of {hit}");
    assert!(facing * 100 >= hit * 95, "{facing} of {hit}");
}

fn unpack_snorm(v: u32) -> [f32; 2] {
    [v & 0xffff, v >> 16].map(|h| (f32::from(h as u16 as i16) / 32767.0).max(-1.0))
}

fn oct_decode(x: f64, z: f64) -> DVec3 {
    let mut n = DVec3::new(x, 1.0 - x.abs() - z.abs(), z);
    let t = (-n.y).max(0.0);
    n.x += if n.x >= 0.0 { -t } else { t };
    n.z += if n.z >= 0.0 { -t } else { t };
    n.normalize()
}

#[test]
fn props_change_the_frame_only_where_they_stand_and_their_shadows_fall() {
    let gpu = common::gpu();
    let off = params(false);
    let v = view(&off);
    let bare = draw(&gpu, &mut world(&gpu, off), &v);
    // On, but no cell holds one: the march runs and the frame is the bare one, byte for byte.
    let mut none = params(true);
    none.props.density = 0.0;
    none.props.rock_density = 0.0;
    let mut w = world(&gpu, none);
    assert!(
        draw(&gpu, &mut w, &v) == bare,
        "props with none placed changed the frame"
    );
    let on = params(true);
    let mut w = world(&gpu, on);
    let props = draw(&gpu, &mut w, &v);
    let hits = w.props_hits(&gpu.device, &gpu.queue).unwrap().unwrap();
    let (mut marked, mut changed, mut outside, mut occluded) = (0, 0, 0, 0);
    for (i, h) in hits.iter().enumerate() {
        let differs = bare[4 * i..4 * i + 4]
            .iter()
            .zip(&props[4 * i..4 * i + 4])
            .any(|(a, b)| a.abs_diff(*b) > 1);
        // A prop, or its shadow or its occlusion of the sky on the ground.
        let depth = f32::from_bits(h[0]);
        let mark = depth < 1.0 || f32::from_bits(h[3]) < 1.0 || f32::from_bits(h[1]) < 1.0;
        marked += usize::from(mark);
        occluded += usize::from(depth >= 1.0 && f32::from_bits(h[1]) < 0.95);
        changed += usize::from(differs);
        outside += usize::from(differs && !mark);
    }
    eprintln!(
        "props, their shadows and occlusion cover {marked} pixels; {changed} changed, {outside} \
         outside them"
    );
    assert!(marked > 300 && changed > 300, "{marked} {changed}");
    // The ground around the props' feet: the sky occluded.
    assert!(occluded > 30, "{occluded}");
    assert_eq!(outside, 0);
    // The same props in the same places frame after frame.
    assert!(draw(&gpu, &mut w, &v) == props);
}

/// The forward mesh, the hybrid and the visibility method rasterised by the GPU draw the props
/// through the overlay: the props the marching method shows, at its depths, and their shadows
/// on the ground from the props' shade map where it marches them, changing nothing but the
/// pixels its march marks (grown by two pixels: the map's texels are a quarter metre).
#[test]
fn every_mesh_based_method_draws_the_props() {
    let gpu = common::gpu();
    let on = params(true);
    let v = view(&on);
    let mut w = world(&gpu, on);
    let marched_image = draw(&gpu, &mut w, &v);
    assert!(!w.props_overlaid());
    let marched = w.props_hits(&gpu.device, &gpu.queue).unwrap().unwrap();
    let inverse = w.relative_matrix().as_dmat4().inverse();
    let pixels = f64::from(SIZE.1) / (2.0 * (0.4f64).tan());
    let distance = |i: usize, depth: f32| eye_distance(&inverse, i, depth);
    let overlaid = [
        MethodConfig::new(Method::Mesh),
        MethodConfig::new(Method::Hybrid).with_samples(1),
        MethodConfig::new(Method::Visibility).with_samples(1),
    ];
    for config in overlaid {
        let bare = draw(&gpu, &mut world_drawn(&gpu, params(false), config), &v);
        let mut w = world_drawn(&gpu, on, config);
        let image = draw(&gpu, &mut w, &v);
        assert!(w.draws_props() && w.props_overlaid(), "{config:?}");
        let hits = w.props_hits(&gpu.device, &gpu.queue).unwrap().unwrap();
        let (mut shown, mut same, mut seen, mut outside) = (0, 0, 0, 0);
        let (mut shadowed, mut dark, mut lit, mut march_dark) = (0, 0.0, 0.0, 0.0);
        let size = (SIZE.0 as usize, SIZE.1 as usize);
        let brightness = |img: &[u8], i: usize| -> f64 {
            img[4 * i..4 * i + 3].iter().map(|&c| f64::from(c)).sum()
        };
        for (i, (h, m)) in hits.iter().zip(&marched).enumerate() {
            let differs = bare[4 * i..4 * i + 4]
                .iter()
                .zip(&image[4 * i..4 * i + 4])
                .any(|(a, b)| a.abs_diff(*b) > 1);
            let (d, dm) = (f32::from_bits(h[0]), f32::from_bits(m[0]));
            outside += usize::from(differs && !near_props_mark(&marched, size, i, 2));
            // The ground the marching method darkens in the props' shadow.
            let march = brightness(&marched_image, i);
            if d >= 1.0
                && dm >= 1.0
                && f32::from_bits(m[3]) < 0.5
                && march < 0.8 * brightness(&bare, i)
            {
                shadowed += 1;
                dark += brightness(&image, i);
                lit += brightness(&bare, i);
                march_dark += march;
            }
            if dm < 1.0 {
                shown += 1;
                // Within two pixels' footprint (the march stops within half of one; where a prop
                // meets the ground the raster's depth ends the marching method's rays).
                let (t, tm) = (distance(i, d), distance(i, dm));
                same += usize::from((t - tm).abs() <= 2.0 * tm / pixels);
                seen += usize::from(differs);
            }
        }
        eprintln!(
            "{:?}: of {shown} prop pixels, {same} at the marched depth, {seen} drawn; \
             {outside} changed outside the props and their marks; the {shadowed} pixels \
             the marching method darkens by their shadow {:.2} as bright as bare ({:.2} there)",
            config.method,
            dark / lit,
            march_dark / lit
        );
        // Their shadow, as dark within a tenth of the bare ground's brightness as the marching
        // method's (without the map the overlay left these as bright as bare).
        assert!(shadowed > 50, "{shadowed}");
        assert!(
            (dark - march_dark).abs() < 0.1 * lit,
            "{dark} {march_dark} {lit}"
        );
        assert!(shown > 300, "{shown}");
        assert!(same * 100 >= shown * 99, "{same} of {shown}");
        assert!(seen * 100 >= shown * 95, "{seen} of {shown}");
        assert_eq!(outside, 0);
    }
}

/// The props' scene of the shipped kinds and two of exact primitives put at given places: a
/// ball of radius 1 whose centre is 1.5 m over its foot and a cube of side 1.6 centred 1 m over
/// its foot, turned 30 degrees; no prop is scattered.
fn exact_scene(at: [[f64; 2]; 2]) -> (WorldParams, relief::props::Scene) {
    use relief::props::{place::Placed, Kind, Node, Shape, Transform};
    let mut p = params(true);
    p.props.density = 0.0;
    p.props.rock_density = 0.0;
    let mut scene = relief::props::Scene::default();
    let kind = |name: &str, shape, y| Kind {
        name: name.into(),
        root: Node::Shape {
            shape,
            transform: Transform::at([0.0, y, 0.0]),
            material: 0,
        },
        weight: 0.0,
        scale: (1.0, 1.0),
        on_rock: true,
    };
    let first = scene.kinds.len() as u32;
    scene
        .kinds
        .push(kind("ball", Shape::Sphere { radius: 1.0 }, 1.5));
    scene
        .kinds
        .push(kind("cube", Shape::Box { half: [0.8; 3] }, 1.0));
    for (i, (at, turn)) in at.into_iter().zip([0.0, 30.0]).enumerate() {
        scene.placed.push(Placed {
            kind: first + i as u32,
            at,
            turn,
            scale: 1.0,
        });
    }
    (p, scene)
}

/// Where a ray from the eye along `dir` first meets a record's ball or cube (the
/// camera-relative frame), exactly, and the cosine between the ray and the surface's normal
/// there: `None` where it misses.
fn exact_hit(r: &[f32; 16], dir: DVec3) -> Option<(f64, f64)> {
    let foot = DVec3::new(r[0].into(), r[1].into(), r[2].into());
    if r[6] as usize == EXACT_FIRST {
        let c = foot + DVec3::new(0.0, 1.5, 0.0);
        let b = dir.dot(c);
        let disc = b * b - (c.length_squared() - 1.0);
        let t = b - disc.max(0.0).sqrt();
        return (disc >= 0.0).then(|| (t, dir.dot(dir * t - c).abs()));
    }
    // The cube in its own frame: the eye and the ray turned as the march turns the point.
    let (c, s) = (f64::from(r[4]), f64::from(r[5]));
    let to_local = |v: DVec3| DVec3::new(c * v.x - s * v.z, v.y, s * v.x + c * v.z);
    let o = to_local(-foot) - DVec3::new(0.0, 1.0, 0.0);
    let d = to_local(dir);
    let (mut near, mut far, mut axis) = (f64::NEG_INFINITY, f64::INFINITY, 0);
    for a in 0..3 {
        let (t0, t1) = ((-0.8 - o[a]) / d[a], (0.8 - o[a]) / d[a]);
        if t0.min(t1) > near {
            near = t0.min(t1);
            axis = a;
        }
        far = far.min(t0.max(t1));
    }
    (near <= far && near > 0.0).then_some((near, d[axis].abs()))
}

/// The exact distance from camera-relative `q` to a record's ball or cube.
fn exact_distance(r: &[f32; 16], q: DVec3) -> f64 {
    let foot = DVec3::new(r[0].into(), r[1].into(), r[2].into());
    if r[6] as usize == EXACT_FIRST {
        return (q - foot - DVec3::new(0.0, 1.5, 0.0)).length() - 1.0;
    }
    let (c, s) = (f64::from(r[4]), f64::from(r[5]));
    let v = q - foot;
    let local = DVec3::new(c * v.x - s * v.z, v.y - 1.0, s * v.x + c * v.z);
    let e = local.abs() - DVec3::splat(0.8);
    e.max(DVec3::ZERO).length() + e.max_element().min(0.0)
}

/// The shipped landscape's kinds come first in [`exact_scene`]: the ball is the next.
const EXACT_FIRST: usize = 5;

#[test]
fn a_ball_and_a_cube_meet_the_rays_where_geometry_says_and_the_host_can_ask_their_distance() {
    let gpu = common::gpu();
    let base = params(true);
    let v0 = view(&base);
    let ahead = DVec3::new(-1.0, 0.0, -1.0).normalize();
    let side = DVec3::new(1.0, 0.0, -1.0).normalize();
    let ball = v0.eye + ahead * 10.0 - side * 1.5;
    let cube = v0.eye + ahead * 12.0 + side * 1.8;
    let (p, scene) = exact_scene([[ball.x, ball.z], [cube.x, cube.z]]);
    assert_eq!(scene.kinds.len(), EXACT_FIRST + 2);
    let ground = p.land.height_at(v0.eye.x, v0.eye.z);
    let target = v0.eye + ahead * 11.0 + DVec3::new(0.0, ground + 1.0 - v0.eye.y, 0.0);
    let v = WorldView::look_at(v0.eye, target, 0.8, SIZE);
    let mut w = world(&gpu, p);
    w.set_props_scene(&gpu.device, scene.clone()).unwrap();
    draw(&gpu, &mut w, &v);
    let (side_n, records) = w.props_records(&gpu.device, &gpu.queue).unwrap().unwrap();
    let explicit = &records[(side_n * side_n) as usize..][..2];
    assert!(explicit.iter().all(|r| r[3] > 0.0), "{explicit:?}");
    let hits = w.props_hits(&gpu.device, &gpu.queue).unwrap().unwrap();
    let inverse = w.relative_matrix().as_dmat4().inverse();
    let pixels = f64::from(SIZE.1) / (2.0 * (0.4f64).tan());
    let (mut exact, mut found, mut close, mut stray) = (0, 0, 0, 0);
    let (mut worst, mut worst_stray) = (0.0f64, 0.0f64);
    for (i, h) in hits.iter().enumerate() {
        let dir = eye_relative(&inverse, i, 0.5).normalize();
        let want = explicit
            .iter()
            .filter_map(|r| exact_hit(r, dir))
            .min_by(|a, b| a.0.total_cmp(&b.0));
        let depth = f32::from_bits(h[0]);
        match want {
            Some((t, cos)) => {
                exact += 1;
                if depth < 1.0 {
                    found += 1;
                    // The march stops within half a pixel's footprint of the surface: along
                    // the ray, that over the cosine of its incidence.
                    let got = eye_distance(&inverse, i, depth);
                    let reach = (t / pixels / cos.max(0.05)).max(0.005);
                    worst = worst.max((got - t).abs() / reach);
                    close += usize::from((got - t).abs() <= reach);
                }
            }
            // A ray passing within half a pixel's footprint of a silhouette hits it.
            None if depth < 1.0 => {
                let q = eye_relative(&inverse, i, depth);
                let d = explicit
                    .iter()
                    .map(|r| exact_distance(r, q))
                    .fold(f64::INFINITY, f64::min);
                stray += 1;
                worst_stray = worst_stray.max(d / (0.5 * q.length() / pixels));
            }
            None => {}
        }
    }
    eprintln!(
        "{exact} pixels meet the ball or the cube: {found} hit, {close} within a pixel's \
         footprint over the incidence's cosine (worst {worst:.2} of it); {stray} hits elsewhere, \
         the farthest {worst_stray:.2} half-footprints off the surface"
    );
    assert!(exact > 400, "{exact}");
    assert!(found * 100 >= exact * 97, "{found} of {exact}");
    assert!(close * 100 >= found * 99, "{close} of {found}");
    assert!(worst < 2.0, "{worst}");
    assert!(worst_stray <= 1.05, "{worst_stray}");

    // The host's question: the distance to the props at a point, by the twin.
    let foot = |r: &[f32; 16]| DVec3::new(r[0].into(), r[1].into(), r[2].into()) + v.eye;
    let centre = foot(&explicit[0]) + DVec3::new(0.0, 1.5, 0.0);
    for (point, want) in [
        (centre, -1.0),
        (centre + DVec3::new(0.0, 2.0, 0.0), 1.0),
        (centre + side * -1.5, 0.5),
    ] {
        let d = w.props_distance(point).expect("a prop near");
        // The twin stands them on the continuous surface, the GPU on the drawn one.
        assert!((d - want).abs() < 0.05, "at {point}: {d}, not {want}");
    }
    let far = v.eye + DVec3::new(5000.0, 0.0, 0.0);
    // Far from every prop: the props put at given places, some 5 km away.
    let d = w.props_distance(far).unwrap();
    assert!(d > 4900.0, "{d}");
    let mut off = p;
    off.props.on = false;
    assert!(world(&gpu, off).props_distance(centre).is_none());
}

/// A ball behind a ridge is hidden, and one in front of it shows: the march stops at the
/// terrain's depth.
#[test]
fn a_prop_behind_a_ridge_is_hidden_and_one_in_front_shows() {
    let gpu = common::gpu();
    let base = params(true);
    let land = &base.land;
    let eye = view(&base).eye;
    // The twin's terrain along the segment from the eye to `to`: how far the ground rises
    // over it at most (metres; negative: clear by that much).
    let rise = |to: DVec3| {
        (1..200)
            .map(|k| {
                let q = eye + (to - eye) * (f64::from(k) / 200.0);
                land.height_at(q.x, q.z) - q.y
            })
            .fold(f64::NEG_INFINITY, f64::max)
    };
    let centre = |x: f64, z: f64| DVec3::new(x, land.height_at(x, z) + 1.5, z);
    // A direction and a distance where the whole ball is under a ridge by 0.5 m, and a ball
    // nearer on that line, 3 m aside, clear of the ground by 0.3 m.
    let found = (0..32).find_map(|a| {
        let turn = f64::from(a) * std::f64::consts::TAU / 32.0;
        let dir = DVec3::new(turn.cos(), 0.0, turn.sin());
        let aside = DVec3::new(-dir.z, 0.0, dir.x) * 3.0;
        let behind = (8..40).map(|k| f64::from(k) * 10.0).find_map(|d| {
            let c = centre(eye.x + dir.x * d, eye.z + dir.z * d);
            (rise(c + DVec3::new(0.0, 1.2, 0.0)) > 0.5).then_some((d, c))
        })?;
        let front = (2..(behind.0 / 5.0) as i32).rev().find_map(|k| {
            let p = eye + dir * (f64::from(k) * 5.0) + aside;
            let c = centre(p.x, p.z);
            (rise(c - DVec3::new(0.0, 1.0, 0.0)) < -0.3).then_some(c)
        })?;
        Some((behind.1, front))
    });
    let (behind, front) = found.expect("a ridge around the meadow");
    let (p, scene) = exact_scene([[behind.x, behind.z], [front.x, front.z]]);
    let mid = (behind + front) * 0.5;
    let v = WorldView::look_at(eye, mid, 0.8, SIZE);
    // The balls' pixels in what a method's march left.
    let balls = |config: MethodConfig| {
        let mut w = world_drawn(&gpu, p, config);
        w.set_props_scene(&gpu.device, scene.clone()).unwrap();
        draw(&gpu, &mut w, &v);
        let hits = w.props_hits(&gpu.device, &gpu.queue).unwrap().unwrap();
        let inverse = w.relative_matrix().as_dmat4().inverse();
        let (mut of_behind, mut of_front) = (0, 0);
        for (i, h) in hits.iter().enumerate() {
            let depth = f32::from_bits(h[0]);
            if depth < 1.0 {
                let q = eye_relative(&inverse, i, depth) + eye;
                of_behind += usize::from((q - behind).length() < 1.5);
                of_front += usize::from((q - front).length() < 1.5);
            }
        }
        (of_behind, of_front)
    };
    let (of_behind, of_front) = balls(marching());
    eprintln!(
        "behind the ridge at {:.0} m: {of_behind} pixels; in front at {:.0} m: {of_front}",
        (behind - eye).length(),
        (front - eye).length()
    );
    assert_eq!(of_behind, 0);
    assert!(of_front > 10, "{of_front}");
    // The negative control: the overlay's march, which no terrain's depth bounds, meets the
    // ball behind the ridge (the host's depth test hides it).
    let (unbounded, _) = balls(MethodConfig::new(Method::Mesh));
    assert!(unbounded >= 5, "{unbounded}");
}

/// No grass grows inside a prop: every blade the grass draws has its root outside the props
/// (by the twin's fields of the props the scatter placed), and those inside are flattened.
#[test]
fn no_grass_grows_inside_a_prop() {
    let gpu = common::gpu();
    let mut p = params(true);
    p.grass.on = true;
    let v = view(&p);
    let mut w = world(&gpu, p);
    draw(&gpu, &mut w, &v);
    let (side, records) = w.props_records(&gpu.device, &gpu.queue).unwrap().unwrap();
    let tapes = w.props_scene().compile(&p.props).unwrap();
    let blades = w
        .grass_blades(&gpu.device, &gpu.queue, 400_000)
        .unwrap()
        .unwrap();
    let cell = f64::from(p.props.cell);
    let eye_cell = p.props.cell_at(v.eye.x, v.eye.z);
    let half = i64::from(side / 2);
    // The props of the 3x3 cells around a camera-relative point's.
    let inside = |rel: DVec3| {
        let c = [rel.x + v.eye.x, rel.z + v.eye.z].map(|x| (x / cell).floor() as i64);
        (-1..=1)
            .flat_map(|di| (-1..=1).map(move |dj| (di, dj)))
            .any(|(di, dj)| {
                let g = [
                    c[0] + di - eye_cell[0] + half,
                    c[1] + dj - eye_cell[1] + half,
                ];
                if g.iter().any(|&x| x < 0 || x >= i64::from(side)) {
                    return false;
                }
                let r = &records[(g[1] * i64::from(side) + g[0]) as usize];
                r[3] > 0.0 && record_distance(&tapes, r, rel).0 < -0.005
            })
    };
    let (mut flat, mut flat_inside, mut grown_inside) = (0, 0, 0);
    for b in &blades {
        let root = DVec3::new(b[0].into(), b[1].into(), b[2].into()) + DVec3::Y * 0.01;
        let is_in = inside(root);
        if b[4] == 0.0 {
            flat += 1;
            flat_inside += usize::from(is_in);
        } else {
            grown_inside += usize::from(is_in);
        }
    }
    eprintln!(
        "{} blades: {flat} flattened ({flat_inside} inside a prop by the twin), {grown_inside} \
         grown inside one",
        blades.len()
    );
    assert!(flat > 50, "{flat}");
    assert_eq!(grown_inside, 0);
    // Those flattened are inside (or within 5 mm of a surface, where f32 and f64 part).
    assert!(flat_inside * 100 >= flat * 97, "{flat_inside} of {flat}");
}
