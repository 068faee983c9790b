//! Helpers shared by the props' GPU tests (`tests/props.rs`, `tests/props_truth.rs`).
#![allow(dead_code, reason = "each test binary uses a different subset")]

use glam::DVec3;
use relief::gpu::headless::{self, Offscreen};
use relief::props::{sdf, Props};
use relief::{Method, MethodConfig, Raster, World, WorldParams, WorldView};

pub const SIZE: (u32, u32) = (160, 90);

pub fn params(props: bool) -> WorldParams {
    let mut p = WorldParams::default();
    p.grass.on = false;
    p.props = Props {
        on: props,
        ..Props::default()
    };
    p
}

/// Standing 2 m over the meadow's ground, looking across it and the lake below.
pub fn view(params: &WorldParams) -> WorldView {
    let foot = params.find_meadow([2000.0, -3000.0]).expect("a meadow");
    let eye = foot + DVec3::new(0.0, 2.0, 0.0);
    WorldView::look_at(eye, eye + DVec3::new(-30.0, -6.0, -30.0), 0.8, SIZE)
}

/// The visibility method rasterised in compute: the one that marches the props between its
/// raster and its shading.
pub fn marching() -> MethodConfig {
    MethodConfig::new(Method::Visibility)
        .with_samples(1)
        .with_raster(Raster::Compute)
}

pub fn world(gpu: &headless::Gpu, params: WorldParams) -> World {
    world_drawn(gpu, params, marching())
}

pub fn world_drawn(gpu: &headless::Gpu, params: WorldParams, config: MethodConfig) -> World {
    let mut world = World::new(&gpu.device, &gpu.queue, Offscreen::targets(1), params).unwrap();
    world.set_method(&gpu.device, config).unwrap();
    world
}

pub fn draw(gpu: &headless::Gpu, world: &mut World, view: &WorldView) -> Vec<u8> {
    headless::render_world_image(gpu, world, view, SIZE, headless::TILE, None)
        .unwrap()
        .0
}

/// A placed prop's twin distance at world point `p` from its record.
pub fn record_distance(tapes: &[relief::props::Tape], r: &[f32; 16], rel: DVec3) -> (f64, usize) {
    let q = rel - DVec3::new(f64::from(r[0]), f64::from(r[1]), f64::from(r[2]));
    let (c, s, scale) = (f64::from(r[4]), f64::from(r[5]), f64::from(r[3]));
    let local = [c * q.x - s * q.z, q.y, s * q.x + c * q.z].map(|v| v / scale);
    let kind = r[6] as usize;
    let d = sdf::distance(&tapes[kind], local, r[7].to_bits()).0 * scale;
    (d, kind)
}

/// The camera-relative point at pixel `i` of depth `depth` through `inverse` (the frame's
/// camera-relative matrix inverted).
pub fn eye_relative(inverse: &glam::DMat4, i: usize, depth: f32) -> DVec3 {
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

pub fn eye_distance(inverse: &glam::DMat4, i: usize, depth: f32) -> f64 {
    eye_relative(inverse, i, depth).length()
}

/// Whether pixel `i` of an image of `size` lies within `grow` pixels of one the marching
/// method's props' hits (`World::props_hits`) mark: a prop, its shadow or its occlusion.
pub fn near_props_mark(hits: &[[u32; 4]], size: (usize, usize), i: usize, grow: i64) -> bool {
    let mark = |h: [u32; 4]| {
        f32::from_bits(h[0]) < 1.0 || f32::from_bits(h[3]) < 0.99 || f32::from_bits(h[1]) < 0.99
    };
    let (x, y) = ((i % size.0) as i64, (i / size.0) as i64);
    (-grow..=grow).any(|dy| {
        (-grow..=grow).any(|dx| {
            let (nx, ny) = (x + dx, y + dy);
            (0..size.0 as i64).contains(&nx)
                && (0..size.1 as i64).contains(&ny)
                && mark(hits[ny as usize * size.0 + nx as usize])
        })
    })
}
