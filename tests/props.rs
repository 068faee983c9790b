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
    let (mut marked, mut changed, mut outside) = (0, 0, 0);
    for (i, h) in hits.iter().enumerate() {
        let differs = bare[4 * i..4 * i + 4]
            .iter()
            .zip(&props[4 * i..4 * i + 4])
            .any(|(a, b)| a.abs_diff(*b) > 1);
        let mark = f32::from_bits(h[0]) < 1.0 || f32::from_bits(h[3]) < 1.0;
        marked += usize::from(mark);
        changed += usize::from(differs);
        outside += usize::from(differs && !mark);
    }
    eprintln!(
        "props and their shadows cover {marked} pixels; {changed} changed, {outside} outside them"
    );
    assert!(marked > 300 && changed > 300, "{marked} {changed}");
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
