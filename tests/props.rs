//! The GPU's props (`wgsl/props*.wgsl`) against their CPU twin (`relief::props`): the props
//! the scatter places are the twin's, cell for cell, standing on the ground; the march's hits
//! lie on the twin's surfaces with the twin's normals; props change the frame only where they
//! are, and a world without props draws as before.

mod common;

use glam::DVec3;
use relief::gpu::headless::{self, Offscreen};
use relief::props::{place, sdf, Props};
use relief::{Method, MethodConfig, Raster, World, WorldParams, WorldView};

const SIZE: (u32, u32) = (160, 90);

fn params(props: bool) -> WorldParams {
    let mut p = WorldParams::default();
    p.grass.on = false;
    p.props = Props {
        on: props,
        ..Props::default()
    };
    p
}

/// Standing 2 m over the meadow's ground, looking across it and the lake below.
fn view(params: &WorldParams) -> WorldView {
    let foot = params.find_meadow([2000.0, -3000.0]).expect("a meadow");
    let eye = foot + DVec3::new(0.0, 2.0, 0.0);
    WorldView::look_at(eye, eye + DVec3::new(-30.0, -6.0, -30.0), 0.8, SIZE)
}

/// The visibility method rasterised in compute: the one that marches the props between its
/// raster and its shading.
fn marching() -> MethodConfig {
    MethodConfig::new(Method::Visibility)
        .with_samples(1)
        .with_raster(Raster::Compute)
}

fn world(gpu: &headless::Gpu, params: WorldParams) -> World {
    world_drawn(gpu, params, marching())
}

fn world_drawn(gpu: &headless::Gpu, params: WorldParams, config: MethodConfig) -> World {
    let mut world = World::new(&gpu.device, &gpu.queue, Offscreen::targets(1), params).unwrap();
    world.set_method(&gpu.device, config).unwrap();
    world
}

fn draw(gpu: &headless::Gpu, world: &mut World, view: &WorldView) -> Vec<u8> {
    headless::render_world_image(gpu, world, view, SIZE, headless::TILE, None)
        .unwrap()
        .0
}

/// A placed prop's twin distance at world point `p` from its record.
fn record_distance(tapes: &[relief::props::Tape], r: &[f32; 16], rel: DVec3) -> (f64, usize) {
    let q = rel - DVec3::new(f64::from(r[0]), f64::from(r[1]), f64::from(r[2]));
    let (c, s, scale) = (f64::from(r[4]), f64::from(r[5]), f64::from(r[3]));
    let local = [c * q.x - s * q.z, q.y, s * q.x + c * q.z].map(|v| v / scale);
    let kind = r[6] as usize;
    let d = sdf::distance(&tapes[kind], local, r[7].to_bits()).0 * scale;
    (d, kind)
}

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

/// The camera-relative point at pixel `i` of depth `depth` through `inverse` (the frame's
/// camera-relative matrix inverted).
fn eye_relative(inverse: &glam::DMat4, i: usize, depth: f32) -> DVec3 {
    let (x, y) = ((i as u32 % SIZE.0) as f64, (i as u32 / SIZE.0) as f64);
    let ndc = glam::DVec4::new(
        (x + 0.5) / f64::from(SIZE.0) * 2.0 - 1.0,
        1.0 - (y + 0.5) / f64::from(SIZE.1) * 2.0,
        f64::from(depth),
        1.0,
    );
    let q = *inverse * ndc;
    q.truncate() / q.w
}

fn eye_distance(inverse: &glam::DMat4, i: usize, depth: f32) -> f64 {
    eye_relative(inverse, i, depth).length()
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
/// through the overlay: the props the marching method shows, at its depths, changing nothing
/// but the pixels their march marks.
#[test]
fn every_mesh_based_method_draws_the_props() {
    let gpu = common::gpu();
    let on = params(true);
    let v = view(&on);
    let mut w = world(&gpu, on);
    draw(&gpu, &mut w, &v);
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
        for (i, (h, m)) in hits.iter().zip(&marched).enumerate() {
            let differs = bare[4 * i..4 * i + 4]
                .iter()
                .zip(&image[4 * i..4 * i + 4])
                .any(|(a, b)| a.abs_diff(*b) > 1);
            let (d, dm) = (f32::from_bits(h[0]), f32::from_bits(m[0]));
            outside += usize::from(differs && d >= 1.0);
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
             {outside} changed outside the props",
            config.method
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
    let mark = |i: usize| {
        let h = hits[i];
        f32::from_bits(h[0]) < 1.0 || f32::from_bits(h[3]) < 0.99 || f32::from_bits(h[1]) < 0.99
    };
    let near_mark = |i: usize| {
        let (x, y) = ((i % w_px) as i64, (i / w_px) as i64);
        (-1..=1).any(|dy| {
            (-1..=1).any(|dx| {
                let (nx, ny) = (x + dx, y + dy);
                nx >= 0
                    && ny >= 0
                    && (nx as usize) < w_px
                    && (ny as usize) < h_px
                    && mark(ny as usize * w_px + nx as usize)
            })
        })
    };
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
        if mark(i) {
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
