//! Measurements on offscreen frames: the bake of a region, the mesh's screen error and depth,
//! the ray casters' images, the world's horizons for the light bake's checks.

use super::*;

/// How long [`warm_median`] runs the work untimed before it times it.
pub const BAKE_WARM_UP: std::time::Duration = std::time::Duration::from_millis(300);
/// How many timed runs [`warm_median`] takes the median of.
pub const BAKE_RUNS: usize = 9;

/// Bakes `size` x `size` samples of `land`, spaced `2^level_log2` metres, from world sample
/// `origin` (in that spacing) on, in bands of rows; `sink(first_row, texels)` receives each
/// band's (height, dh/dx, dh/dz, colour) texels, rows tightly packed. The grid keeps the octaves
/// whose cells span at least two samples (as a clipmap level does). Returns the GPU time of the
/// bake passes summed, when `timer` is given (each band's [`warm_median`]).
pub fn bake_region(
    gpu: &Gpu,
    land: &crate::landscape::Landscape,
    origin: [i32; 2],
    size: u32,
    level_log2: i32,
    timer: Option<&GpuTimer>,
    mut sink: impl FnMut(u32, &[[f32; 4]]),
) -> Result<Option<f64>> {
    use crate::gpu::landscape::{LandscapeBake, Rect};
    let max = gpu.device.limits().max_texture_dimension_2d;
    if !(1..=max).contains(&size) {
        return Err(Error::invalid(
            "size",
            size,
            format!("1..={max} on this device"),
        ));
    }
    let row_bytes = u64::from(size) * 16;
    let band = (MAX_READBACK_BYTES / row_bytes).clamp(1, u64::from(size)) as u32;
    let pass = LandscapeBake::new(&gpu.device);
    let texture = crate::gpu::scoped(&gpu.device, || {
        gpu.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("relief:bake-region:band"),
            size: wgpu::Extent3d {
                width: size,
                height: band,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: LandscapeBake::FORMAT,
            usage: wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        })
    })?;
    let view = texture.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        ..Default::default()
    });
    let target = pass.bind(&gpu.device, &view, size.max(band));
    let mut total: Option<f64> = None;
    let mut row = 0;
    while row < size {
        let rows = band.min(size - row);
        let rect = Rect {
            layer: 0,
            level_log2,
            origin: [origin[0], origin[1] + row as i32],
            extent: [size, rows],
        };
        let bake = |timer: Option<&GpuTimer>| {
            crate::gpu::scoped(&gpu.device, || {
                let mut encoder = gpu.device.create_command_encoder(&Default::default());
                pass.encode_at_origin(
                    &gpu.queue,
                    &mut encoder,
                    &target,
                    land,
                    &rect,
                    timer.map(|t| t.compute_writes(Slot::Bake)),
                );
                if let Some(t) = timer {
                    t.resolve(&mut encoder);
                }
                gpu.queue.submit([encoder.finish()]);
            })
        };
        match timer {
            Some(t) => {
                let ms = warm_median(t, |timer| {
                    bake(timer)?;
                    read_or_wait(gpu, timer)
                })?[Slot::Bake as usize];
                if let Some(ms) = ms {
                    total = Some(total.unwrap_or(0.0) + ms);
                }
            }
            None => bake(None)?,
        }
        let bytes = read_texture(&gpu.device, &gpu.queue, &texture)?;
        let texels: Vec<[f32; 4]> = bytemuck::pod_collect_to_vec(&bytes);
        sink(row, &texels[..(rows * size) as usize]);
        row += rows;
    }
    Ok(total)
}

/// The screen-space geometric error of a drawn frame of the endless world, measured against the
/// continuous surface: each pixel's depth is turned back into the point drawn there, and its
/// vertical distance δ from the surface (the twin's `height_at`) at distance d counts as
/// `K·δ/d` pixels, the quantity [`crate::clipmap`]'s bound bounds.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ScreenError {
    /// Largest over the pixels measured, in pixels.
    pub max: f64,
    /// 99th percentile, pixels.
    pub p99: f64,
    /// Pixels measured (terrain pixels on the sampling grid).
    pub pixels: usize,
}

/// Draws `world` through `view` single-sampled (the world must target
/// `Offscreen::targets(1)`) and measures [`ScreenError`] at every `stride`-th pixel each way.
pub fn world_screen_error(
    gpu: &Gpu,
    world: &mut World,
    view: &WorldView,
    stride: u32,
) -> Result<ScreenError> {
    Ok(world_depth_metrics(gpu, world, view, stride)?.0)
}

/// [`world_screen_error`], and the distance from the eye of what every pixel shows (-1 for
/// sky): what the coverage against a ray cast compares.
pub fn world_depth_metrics(
    gpu: &Gpu,
    world: &mut World,
    view: &WorldView,
    stride: u32,
) -> Result<(ScreenError, Vec<f32>)> {
    let (w, h) = view.size;
    let target = Offscreen::new(&gpu.device, w, h, 1)?.keeping_depth();
    target.render_world(gpu, world, view, None)?;
    let depth = target.read_depth(gpu)?;
    let inverse = world.relative_matrix().inverse().as_dmat4();
    let k = view.pixels_per_radian();
    let mut errors = Vec::new();
    let stride = stride.max(1) as usize;
    let mut distance = vec![-1f32; depth.len()];
    for py in 0..h as usize {
        for px in 0..w as usize {
            let d = depth[py * w as usize + px];
            if d >= 1.0 {
                continue; // sky
            }
            let ndc = glam::DVec4::new(
                (px as f64 + 0.5) / f64::from(w) * 2.0 - 1.0,
                1.0 - (py as f64 + 0.5) / f64::from(h) * 2.0,
                f64::from(d),
                1.0,
            );
            let p = inverse * ndc;
            let rel = p.truncate() / p.w;
            distance[py * w as usize + px] = rel.length() as f32;
            if py % stride != 0 || px % stride != 0 {
                continue;
            }
            let at = view.eye + rel;
            let delta = (at.y - world.height_at(at.x, at.z)).abs();
            errors.push(k * delta / rel.length().max(1e-9));
        }
    }
    errors.sort_by(f64::total_cmp);
    let pick = |q: f64| {
        errors
            .get(((errors.len() as f64 * q) as usize).min(errors.len().saturating_sub(1)))
            .copied()
            .unwrap_or(0.0)
    };
    let error = ScreenError {
        max: errors.last().copied().unwrap_or(0.0),
        p99: pick(0.99),
        pixels: errors.len(),
    };
    Ok((error, distance))
}

/// What a ray-cast method drew: the image, and per pixel the distance of the pixel-centre ray.
#[derive(Clone, Debug, PartialEq)]
pub struct RayImage {
    /// sRGB RGBA8, supersampled where the method asks for it.
    pub rgba: Vec<u8>,
    /// Distance along the pixel-centre ray to the surface; -1 for sky, -2 where the ray ran
    /// out of steps (never counted as sky).
    pub distance: Vec<f32>,
    /// Rays (of every subsample) that ran out of steps.
    pub unresolved: usize,
    /// The cast's GPU time, when a timer was given (with blades of grass, the unmoved cast's,
    /// one of nine).
    pub timings: Option<Timings>,
    /// The reference's blades of grass drawn (0 without grass).
    pub blades: u32,
}

/// Draws one image with a ray-cast `method` (see [`crate::Method`]): its own colour and
/// distance targets, supersampled where the method asks for it (and the device allows),
/// averaged in linear light. Returns sRGB RGBA8, with the cast's GPU time when `timer` is given.
pub fn render_rays(
    gpu: &Gpu,
    params: &crate::TerrainParams,
    shading: &crate::Shading,
    view: &View,
    size: (u32, u32),
    method: crate::Method,
    timer: Option<&GpuTimer>,
) -> Result<(Vec<u8>, Option<Timings>)> {
    let Some(rays) = method.ray_method(params.octaves) else {
        return Err(Error::invalid("method", method, "a ray-cast method"));
    };
    let how = (method, method.supersample());
    let prepare = |caster: &RayMarcher, _| {
        caster.prepare(&gpu.queue, params, shading, view, rays);
        Ok(())
    };
    let image = cast(gpu, size, how, RayScene::Tile, timer, prepare, |_, _| ())?;
    Ok((image.rgba, image.timings))
}

/// [`render_rays`] for the endless world, bounded by the region the mesh draws at
/// `params.pixel_error` ([`crate::gpu::world_rays::drawn_region`]).
pub fn render_world_rays(
    gpu: &Gpu,
    params: &crate::world::WorldParams,
    shading: &crate::Shading,
    view: &WorldView,
    method: crate::Method,
    timer: Option<&GpuTimer>,
) -> Result<RayImage> {
    let ss = method.supersample();
    render_world_rays_at(gpu, params, shading, view, method, ss, timer)
}

/// [`render_world_rays`] with props of `scene` where `params` turns them on (else the same):
/// the reference marches them at its samples, conservatively
/// (`src/gpu/props_reference.rs`, docs/props.md); the seed's ray marches draw none.
/// [`render_world_rays`] draws the shipped landscape's ([`crate::props::kinds::landscape`]).
pub fn render_world_rays_with_props(
    gpu: &Gpu,
    (params, scene): (&crate::world::WorldParams, &crate::props::Scene),
    shading: &crate::Shading,
    view: &WorldView,
    method: crate::Method,
    timer: Option<&GpuTimer>,
) -> Result<RayImage> {
    let how = (method, method.supersample());
    world_rays(gpu, (params, scene, shading, view), how, &mut [], timer)
}

/// [`render_world_rays`] with `supersample` rays per pixel each way (what checks that the
/// reference's 3x3 has converged).
pub fn render_world_rays_at(
    gpu: &Gpu,
    params: &crate::world::WorldParams,
    shading: &crate::Shading,
    view: &WorldView,
    method: crate::Method,
    supersample: u32,
    timer: Option<&GpuTimer>,
) -> Result<RayImage> {
    let scene = crate::props::kinds::landscape();
    world_rays(
        gpu,
        (params, &scene, shading, view),
        (method, supersample),
        &mut [],
        timer,
    )
}

/// [`render_world_rays`] with the frame's `layers` ([`crate::gpu::layer`]) drawn over the cast
/// at its samples, depth-tested against the surface it found: the reference of a frame with
/// layers. The image's `distance` stays the terrain's.
pub fn render_world_rays_with_layers(
    gpu: &Gpu,
    params: &crate::world::WorldParams,
    shading: &crate::Shading,
    view: &WorldView,
    method: crate::Method,
    layers: &mut [Box<dyn crate::gpu::layer::Layer>],
) -> Result<RayImage> {
    let how = (method, method.supersample());
    let scene = crate::props::kinds::landscape();
    world_rays(gpu, (params, &scene, shading, view), how, layers, None)
}

fn world_rays(
    gpu: &Gpu,
    (params, scene, shading, view): (
        &crate::world::WorldParams,
        &crate::props::Scene,
        &crate::Shading,
        &WorldView,
    ),
    (method, supersample): (crate::Method, u32),
    layers: &mut [Box<dyn crate::gpu::layer::Layer>],
    timer: Option<&GpuTimer>,
) -> Result<RayImage> {
    use crate::gpu::grass_reference::{GrassReference, JITTERS};
    use crate::gpu::{ray_layers, world_rays};
    let Some(rays) = method.ray_method(params.land.octaves) else {
        return Err(Error::invalid("method", method, "a ray-cast method"));
    };
    // The seed's ray marches draw no grass and no props: they cast the bare ground.
    let params = &if method == crate::Method::Reference {
        *params
    } else {
        let mut bare = params.without_grass();
        bare.props.on = false;
        bare
    };
    let region = world_rays::drawn_region(params, view);
    let render = |view: &WorldView, matrix| {
        let mut u =
            crate::gpu::world::render_uniforms(params, shading, (matrix, region, view.eye), true);
        // The reference marches the clouds in many small steps.
        if method == crate::Method::Reference {
            u.cloud_march[1] = crate::world::clouds::REFERENCE_STEPS as f32;
        }
        if params.grass.on {
            u.grass_distance = crate::gpu::grass_reference::REACH * params.grass.distance;
            u.grass_reference = 1;
            u.grass_cover = params.grass.field_cover();
        }
        u
    };
    let mut grass = if params.grass.on {
        let ray = world_rays::WorldRayUniforms::new(params, view, rays, view.size, region)?;
        let layer_render = render(view, ray_layers::layer_matrix(params, view, region));
        Some(GrassReference::new(
            gpu,
            params,
            view,
            (&ray, &layer_render),
        )?)
    } else {
        None
    };
    // With blades to draw, the cast's samples at JITTERS x JITTERS sub-pixel offsets (N x N
    // samples a pixel), averaged in linear light; the distance is the unmoved cast's.
    let jitters = if grass.as_ref().is_some_and(|g| g.count() > 0) {
        JITTERS
    } else {
        1
    };
    // With props, a world of the same landscape (its levels baked for the view) scatters them
    // as the methods do, and the reference marches them at its samples.
    let mut props = if params.props.on {
        use crate::gpu::props_reference::PropsReference;
        let targets = crate::gpu::Targets {
            color_format: wgpu::TextureFormat::Rgba8UnormSrgb,
            depth_format: None,
            sample_count: 1,
        };
        let mut world =
            crate::World::new(&gpu.device, &gpu.queue, targets, params.without_grass())?;
        world.set_props_scene(&gpu.device, scene.clone())?;
        super::offscreen::bake_world_whole(gpu, &mut world, view, None)?;
        Some((world, PropsReference::new(&gpu.device)))
    } else {
        None
    };
    // The reference's blades in the props' pass (cut inside them, their shadows on the rest):
    // once, at the first cast, after its scatter of the props.
    let mut blades_for_props = grass.as_ref().filter(|_| props.is_some()).map(|g| {
        let (b, c) = g.blades();
        (b.clone(), c.clone())
    });
    let ss = supersample_for(gpu, view.size, supersample);
    let mut sum: Vec<f64> = Vec::new();
    let mut out: Option<RayImage> = None;
    let mut unresolved = 0;
    for k in 0..jitters * jitters {
        let (jx, jy) = (k % jitters, k / jitters);
        let step = 1.0 / (jitters * ss) as f32;
        let offset = |j: u32| (j as f32 - (jitters / 2) as f32) * step;
        let mut v = *view;
        v.crop = crate::temporal::jitter_matrix([offset(jx), offset(jy)], view.size) * view.crop;
        let ray_matrix = world_rays::ray_matrix(&v);
        let layer_matrix = ray_layers::layer_matrix(params, &v, region);
        let layer_render = render(&v, layer_matrix);
        let mut all: Vec<&mut (dyn crate::gpu::layer::Layer + 'static)> = grass
            .iter_mut()
            .map(|g| g as &mut (dyn crate::gpu::layer::Layer + 'static))
            .chain(layers.iter_mut().map(|l| l.as_mut()))
            .collect();
        let image = cast(
            gpu,
            view.size,
            (method, supersample),
            RayScene::for_world(params),
            timer,
            |caster, size| {
                let ray = world_rays::WorldRayUniforms::new(params, &v, rays, size, region)?;
                caster.prepare_world(&gpu.queue, &render(&v, ray_matrix), &ray)
            },
            |caster, encoder| {
                if let Some((world, pass)) = props.as_mut() {
                    pass.encode(
                        (&gpu.device, encoder),
                        caster,
                        layer_matrix,
                        |encoder, m| {
                            world.encode_reference_props((&gpu.device, &gpu.queue, encoder), &v, m);
                            if let Some((b, c)) = blades_for_props.take() {
                                world.encode_reference_grass(
                                    &gpu.device,
                                    encoder,
                                    m.render,
                                    (&b, &c),
                                );
                            }
                        },
                    );
                }
                let frame = ray_layers::RayLayerFrame {
                    eye: v.eye,
                    ray_matrix,
                    layer_matrix,
                    render: &layer_render,
                    method,
                };
                ray_layers::encode(&gpu.device, &gpu.queue, encoder, caster, &frame, &mut all);
            },
        )?;
        unresolved += image.unresolved;
        if jitters == 1 {
            return Ok(RayImage { blades: 0, ..image });
        }
        sum.resize(image.rgba.len(), 0.0);
        for (acc, &c) in sum.iter_mut().zip(&image.rgba) {
            *acc += f64::from(crate::params::srgb_to_linear(f32::from(c) / 255.0));
        }
        if (jx, jy) == (jitters / 2, jitters / 2) {
            out = Some(image);
        }
    }
    let mut image = out.expect("the unmoved cast is one of the jitters");
    let n = f64::from(jitters * jitters);
    image.rgba = sum.iter().map(|&l| crate::gpu::srgb8(l / n)).collect();
    for alpha in image.rgba.chunks_exact_mut(4) {
        alpha[3] = 255;
    }
    image.unresolved = unresolved;
    image.blades = grass.as_ref().map_or(0, GrassReference::count);
    Ok(image)
}

/// The terrain's horizon towards the sun (radians above the horizontal) at each point `(x, z)`
/// (world metres) of the endless world's continuous surface, as `method`'s rays shade it
/// (`wgsl/horizon_probe.wgsl`): the reference's conservative march, or the seed's shadow march
/// with `method`'s ray settings. The sun is `params.sky`'s; `view` places the casters' reference
/// sample and bounds the march by the region the mesh draws.
pub fn world_horizons(
    gpu: &Gpu,
    params: &crate::world::WorldParams,
    view: &WorldView,
    method: crate::gpu::raymarch::RayMethod,
    points: &[[f64; 2]],
) -> Result<Vec<f32>> {
    use wgpu::util::DeviceExt as _;
    if points.is_empty() {
        return Ok(Vec::new());
    }
    let region = crate::gpu::world_rays::drawn_region(params, view);
    let ray =
        crate::gpu::world_rays::WorldRayUniforms::new(params, view, method, view.size, region)?;
    let render = crate::gpu::world::render_uniforms(
        params,
        &crate::Shading::default(),
        (crate::gpu::world_rays::ray_matrix(view), region, view.eye),
        true,
    );
    // Positions relative to the reference sample, as the casters' are.
    let s = 2f64.powi(ray.base_log2);
    let origin = [
        f64::from(ray.reference[0]) * s,
        f64::from(ray.reference[1]) * s,
    ];
    let relative: Vec<[f32; 2]> = points
        .iter()
        .map(|p| [(p[0] - origin[0]) as f32, (p[1] - origin[1]) as f32])
        .collect();
    let device = &gpu.device;
    let source = crate::gpu::shader::source("horizon_probe");
    let init = |label: &str, contents: &[u8], usage| {
        device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents,
            usage,
        })
    };
    let render_buffer = init(
        "relief:horizon-probe:render",
        bytemuck::bytes_of(&render),
        wgpu::BufferUsages::UNIFORM,
    );
    let ray_buffer = init(
        "relief:horizon-probe:ray",
        bytemuck::bytes_of(&ray),
        wgpu::BufferUsages::UNIFORM,
    );
    let point_buffer = init(
        "relief:horizon-probe:points",
        bytemuck::cast_slice(&relative),
        wgpu::BufferUsages::STORAGE,
    );
    let bytes = (points.len() * 4) as u64;
    let out = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("relief:horizon-probe:horizons"),
        size: bytes,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let staging = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("relief:horizon-probe:staging"),
        size: bytes,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    crate::gpu::scoped(device, || {
        let module = crate::gpu::shader::module(device, "relief:horizon-probe", &source);
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("relief:horizon-probe"),
            layout: None,
            module: &module,
            entry_point: Some("horizon_cs"),
            compilation_options: Default::default(),
            cache: None,
        });
        let group = |index: u32, buffers: [&wgpu::Buffer; 2]| {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("relief:horizon-probe"),
                layout: &pipeline.get_bind_group_layout(index),
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: buffers[0].as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: buffers[1].as_entire_binding(),
                    },
                ],
            })
        };
        let uniforms = group(0, [&render_buffer, &ray_buffer]);
        let io = group(1, [&point_buffer, &out]);
        let mut encoder = device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_compute_pass(&Default::default());
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, &uniforms, &[]);
            pass.set_bind_group(1, &io, &[]);
            pass.dispatch_workgroups((points.len() as u32).div_ceil(64), 1, 1);
        }
        encoder.copy_buffer_to_buffer(&out, 0, &staging, 0, bytes);
        gpu.queue.submit([encoder.finish()]);
    })?;
    Ok(bytemuck::pod_collect_to_vec(&crate::gpu::map_read(
        device, &staging,
    )?))
}

/// The light bake's horizon towards the sun (radians) at every `stride`-th texel each way of
/// each of `world`'s levels `levels`, as the mesh shades them: per level, (world x, z,
/// horizon), unpacked from the light texture's two 16-bit floats.
pub fn world_light_horizons(
    gpu: &Gpu,
    world: &crate::gpu::world::World,
    levels: &[usize],
    stride: usize,
) -> Result<Vec<Vec<(f64, f64, f32)>>> {
    let packed: Vec<u32> = bytemuck::pod_collect_to_vec(&read_texture(
        &gpu.device,
        &gpu.queue,
        world.light_texture(),
    )?);
    let map = world.clipmap();
    let side = map.side() as i64;
    let cells = map.cells() as i64;
    let mut out = Vec::with_capacity(levels.len());
    for &l in levels {
        let Some(level) = map.levels.get(l) else {
            return Err(Error::invalid(
                "level",
                l,
                format!("0..{} (the clipmap's levels)", map.levels.len()),
            ));
        };
        let s = level.spacing();
        let mut texels = Vec::new();
        for j in (0..=cells).step_by(stride.max(1)) {
            for i in (0..=cells).step_by(stride.max(1)) {
                let (si, sj) = (
                    i64::from(level.origin[0]) + i,
                    i64::from(level.origin[1]) + j,
                );
                let t = (i64::from(level.layer) * side + sj.rem_euclid(side)) * side
                    + si.rem_euclid(side);
                let horizon = half::f16::from_bits(packed[t as usize] as u16).to_f32();
                texels.push((si as f64 * s, sj as f64 * s, horizon));
            }
        }
        out.push(texels);
    }
    Ok(out)
}

/// The rays a pixel each way a cast of `size` takes for `ss` asked: `ss`, or 1 where the device's
/// largest texture cannot hold the supersampled image.
fn supersample_for(gpu: &Gpu, (width, height): (u32, u32), ss: u32) -> u32 {
    let max = gpu.device.limits().max_texture_dimension_2d;
    let ss = ss.max(1);
    if width * ss <= max && height * ss <= max {
        ss
    } else {
        1
    }
}

/// Casts `method`'s rays at `scene` into a `width` x `height` image, `ss` rays per pixel each
/// way where the device allows; `prepare(caster, cast size)` writes the uniforms, and `after`
/// records what is drawn over the cast before it is read (the frame's layers).
pub(super) fn cast(
    gpu: &Gpu,
    (width, height): (u32, u32),
    (method, ss): (crate::Method, u32),
    scene: RayScene,
    timer: Option<&GpuTimer>,
    prepare: impl FnOnce(&RayMarcher, (u32, u32)) -> Result<()>,
    after: impl FnOnce(&RayMarcher, &mut wgpu::CommandEncoder),
) -> Result<RayImage> {
    let Some(path) = method.ray_path() else {
        return Err(Error::invalid("method", method, "a ray-cast method"));
    };
    let ss = supersample_for(gpu, (width, height), ss);
    let size = (width * ss, height * ss);
    let caster = RayMarcher::for_scene(&gpu.device, size.0, size.1, scene)?;
    prepare(&caster, size)?;
    crate::gpu::scoped(&gpu.device, || {
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        caster.encode(&mut encoder, path, timer);
        after(&caster, &mut encoder);
        if let Some(t) = timer {
            t.resolve(&mut encoder);
        }
        gpu.queue.submit([encoder.finish()]);
    })?;
    let timings = timer.map(|t| t.read(&gpu.device)).transpose()?;
    let image = read_texture(&gpu.device, &gpu.queue, &caster.color)?;
    let all: Vec<f32> =
        bytemuck::pod_collect_to_vec(&read_texture(&gpu.device, &gpu.queue, &caster.distance)?);
    let unresolved = all.iter().filter(|&&d| d == -2.0).count();
    // The subsample nearest each pixel's centre (its centre where ss is odd).
    let distance = (0..height as usize)
        .flat_map(|y| {
            let row = (y * ss as usize + ss as usize / 2) * size.0 as usize;
            let all = &all;
            (0..width as usize).map(move |x| all[row + x * ss as usize + ss as usize / 2])
        })
        .collect();
    let rgba = if ss > 1 {
        downsample_srgb(&image, size.0, size.1, ss)
    } else {
        image
    };
    Ok(RayImage {
        rgba,
        distance,
        unresolved,
        timings,
        blades: 0,
    })
}
