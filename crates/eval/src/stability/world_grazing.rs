//! The grazing axis on the endless world: the eye a little above the ground looking down
//! 0.5° to 30°, the world's methods against an f64 ray cast of the twin's continuous surface
//! ([`relief::landscape::Landscape::intersect`]) at sampled pixels, judged as on the tile
//! (the tile axis's judge): the mesh (the clipmap, whose layout bounds its screen error by the
//! knob), the visibility method (that mesh rasterised at one sample a pixel, its composited
//! depth), the hybrid (that mesh raised, each pixel-centre ray refined to the continuous surface
//! from it: one sample a pixel, so its depth is the pixel centre's), relief's reference cast,
//! and the seed's march at its own step factor and at 0.8, every octave. Rows are [`super::GrazingRow`]s whose `height_scale` is the world's peak height.

use super::{judge, GrazingRow, Marcher, Options};
use glam::{DVec3, DVec4};
use relief::error::Result;
use relief::gpu::headless::{self, Gpu, Offscreen};
use relief::gpu::raymarch::{RayMarcher, RayScene};
use relief::gpu::world::World;
use relief::gpu::world_rays::{drawn_region, ray_matrix, WorldRayUniforms};
use relief::method::Method;
use relief::method::{RayMethod, RayPath, SeedMarch};
use relief::world::WorldParams;
use relief::WorldView;

/// The world's sweep: the options' elevations, size and stride, the world's methods, its peak
/// height as the one "height scale".
pub fn world_options(params: &WorldParams, quick: bool) -> Options {
    let base = if quick {
        Options::quick()
    } else {
        Options {
            stride: 8,
            ..Options::full()
        }
    };
    let seed = |c: f32| Marcher {
        method: Method::Raymarch,
        step_factor: Some(c),
        relax: 0.0,
    };
    let own = |method| Marcher {
        method,
        step_factor: None,
        relax: 0.0,
    };
    Options {
        height_scales: vec![params.land.peak_height as f32],
        marchers: vec![
            seed(SeedMarch::default().step_factor),
            seed(0.8),
            own(Method::Mesh),
            own(Method::Visibility),
            own(Method::Hybrid),
            own(Method::Reference),
        ],
        ..base
    }
}

/// The eye over `params`' world looking down `elevation_deg`: 1% of the peak height and 2 m
/// above the ground.
pub fn world_grazing_view(params: &WorldParams, elevation_deg: f64, size: (u32, u32)) -> WorldView {
    let land = &params.land;
    let (x, z) = (3.0, -7.0);
    let eye = DVec3::new(x, land.height_at(x, z) + 0.01 * land.peak_height + 2.0, z);
    let e = elevation_deg.to_radians();
    let heading = DVec3::new(0.94, 0.0, 0.34).normalize();
    let dir = heading * e.cos() - DVec3::Y * e.sin();
    WorldView::look_at(eye, eye + dir, 50f32.to_radians(), size)
}

/// Sweeps the endless world's grazing axis; `progress(done, total)` after each view.
pub fn world_grazing(
    gpu: &Gpu,
    params: &WorldParams,
    options: &Options,
    mut progress: impl FnMut(usize, usize),
) -> Result<Vec<GrazingRow>> {
    params.validate()?;
    let land = &params.land;
    let slope = *land.slope_bounds().last().unwrap_or(&1.0);
    let (w, h) = options.size;
    let stride = options.stride.max(1);
    let pixels: Vec<(u32, u32)> = (0..h)
        .step_by(stride as usize)
        .flat_map(|y| (0..w).step_by(stride as usize).map(move |x| (x, y)))
        .collect();
    let mut world = World::new(&gpu.device, &gpu.queue, Offscreen::targets(1), *params)?;
    // The compute-shaded methods at one sample a pixel: each pixel's depth is its centre's.
    let at_one_sample = |method| -> Result<World> {
        let mut w = World::new(&gpu.device, &gpu.queue, Offscreen::targets(1), *params)?;
        w.set_method(
            &gpu.device,
            relief::MethodConfig::new(method).with_samples(1),
        )?;
        Ok(w)
    };
    let mut visibility = at_one_sample(Method::Visibility)?;
    let mut hybrid = at_one_sample(Method::Hybrid)?;
    let caster = RayMarcher::for_scene(&gpu.device, w, h, RayScene::World)?;
    let mut rows = Vec::new();
    for (i, &elevation) in options.elevations.iter().enumerate() {
        let view = world_grazing_view(params, elevation, options.size);
        let region = drawn_region(params, &view);
        let inverse = ray_matrix(&view).inverse().as_dmat4();
        let pixel_angle = 1.0 / view.pixels_per_radian();
        let eye = view.eye;
        // The truth at the sampled pixels, and where the ray one pixel higher hits.
        let truth = super::parallel_map(&pixels, |&(x, y)| {
            let ndc = DVec4::new(
                (f64::from(x) + 0.5) / f64::from(w) * 2.0 - 1.0,
                1.0 - (f64::from(y) + 0.5) / f64::from(h) * 2.0,
                1.0,
                1.0,
            );
            let far = inverse * ndc;
            let rd = (far.truncate() / far.w).normalize();
            let reach = |o: DVec3| exit(o, rd, region);
            let t = land.intersect(eye.to_array(), rd.to_array(), slope, reach(eye))?;
            let raised = eye + DVec3::Y * (pixel_angle * t);
            let up = land.intersect(raised.to_array(), rd.to_array(), slope, reach(raised));
            Some((t, up))
        });
        for m in &options.marchers {
            let distance: Vec<f32> = match m.method {
                Method::Mesh => headless::world_depth_metrics(gpu, &mut world, &view, 1)?.1,
                // The raster's depth, as its composite writes it.
                Method::Visibility => {
                    headless::world_depth_metrics(gpu, &mut visibility, &view, 1)?.1
                }
                // The depth its composite writes: the refined surface's at the pixel centre.
                Method::Hybrid => headless::world_depth_metrics(gpu, &mut hybrid, &view, 1)?.1,
                _ => {
                    let method = match m.step_factor {
                        Some(step_factor) => RayMethod::SeedMarch(SeedMarch {
                            step_factor,
                            march_octaves: land.octaves,
                            normal_octaves: land.octaves,
                            ..SeedMarch::default()
                        }),
                        None => RayMethod::Reference,
                    };
                    let ray = WorldRayUniforms::new(params, &view, method, (w, h), region)?;
                    let render = relief::gpu::world::render_uniforms(
                        params,
                        &relief::Shading::default(),
                        (ray_matrix(&view), region, view.eye),
                        true,
                    );
                    caster.prepare_world(&gpu.queue, &render, &ray)?;
                    let mut encoder = gpu.device.create_command_encoder(&Default::default());
                    caster.encode(&mut encoder, RayPath::Compute, None);
                    gpu.queue.submit([encoder.finish()]);
                    let bytes = headless::read_texture(&gpu.device, &gpu.queue, &caster.distance)?;
                    bytemuck::pod_collect_to_vec(&bytes)
                }
            };
            let d: Vec<f64> = pixels
                .iter()
                .map(|&(x, y)| f64::from(distance[(y * w + x) as usize]))
                .collect();
            rows.push(judge(*m, (elevation, land.peak_height as f32), &truth, &d));
        }
        progress(i + 1, options.elevations.len());
    }
    Ok(rows)
}

/// How far, horizontally, the ray from `o` along `rd` runs inside `region` (x0, z0, x1, z1).
fn exit(o: DVec3, rd: DVec3, region: [f64; 4]) -> f64 {
    let flat = (rd.x * rd.x + rd.z * rd.z).sqrt().max(1e-12);
    let along = |x: f64, d: f64, lo: f64, hi: f64| {
        if d > 1e-12 {
            (hi - x) / d
        } else if d < -1e-12 {
            (lo - x) / d
        } else {
            f64::INFINITY
        }
    };
    let t = along(o.x, rd.x, region[0], region[2]).min(along(o.z, rd.z, region[1], region[3]));
    (t * flat).max(0.0)
}
