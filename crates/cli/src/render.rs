//! `relief render`: one frame of either world by any method into a PNG, the cameras, the
//! endless world's commands, and the timings printed.

use super::*;

/// The tile world's view: the default orbit, or the camera given (all in tile units).
pub(super) fn tile_view(camera: &Camera, (width, height): (u32, u32)) -> relief::View {
    let orbit = OrbitCamera::default();
    let aspect = width as f32 / height as f32;
    if camera.eye.is_none() && camera.look_at.is_none() && camera.fov_deg.is_none() {
        return orbit.view(aspect);
    }
    let eye = camera
        .eye
        .map_or(orbit.eye(), |e| glam::DVec3::from(e).as_vec3());
    let target = camera
        .look_at
        .map_or(orbit.target, |t| glam::DVec3::from(t).as_vec3());
    let fov = camera.fov_deg.map_or(orbit.fov_y, |d| d.to_radians());
    let distance = (target - eye).length().max(1e-3);
    let up = if (target - eye).normalize().y.abs() > 0.999 {
        glam::Vec3::Z
    } else {
        glam::Vec3::Y
    };
    let proj =
        glam::Mat4::perspective_rh(fov, aspect, (distance * 0.01).max(0.001), distance + 10.0);
    relief::View {
        view_proj: proj * glam::Mat4::look_at_rh(eye, target, up),
        eye,
    }
}

/// The endless world's view: by default from 1200 m above the ground, looking east-north-east
/// and a little down over ridges that run out to the horizon (chosen by eye).
pub(super) fn world_view(camera: &Camera, params: &WorldParams, size: (u32, u32)) -> WorldView {
    let land = &params.land;
    if let Some(t) = camera.path {
        let path = relief::PathCamera {
            fov_y: camera
                .fov_deg
                .map_or(relief::PathCamera::default().fov_y, f32::to_radians),
            ..Default::default()
        };
        return path.view(|x, z| land.height_at(x, z), t, size);
    }
    let (default_eye, default_target) = relief::gpu::world::default_camera(land);
    let eye = camera.eye.map_or(default_eye, glam::DVec3::from);
    let target = camera
        .look_at
        .map_or_else(|| eye + (default_target - default_eye), glam::DVec3::from);
    let fov = camera.fov_deg.unwrap_or(45.0).to_radians();
    WorldView::look_at(eye, target, fov, size)
}

pub(super) fn run_endless(
    run: Run,
    (params, props): (WorldParams, Option<relief::props::Scene>),
    timings: bool,
) -> Result<()> {
    match run {
        Run::Height { points } => {
            for [x, z] in points {
                println!("{}", params.land.height_at(x, z));
            }
            Ok(())
        }
        Run::Render {
            out,
            width,
            height,
            camera,
            stats,
            method,
            frames,
        } => {
            check_png_path(&out)?;
            let view = world_view(&camera, &params, (width, height));
            let ground = params.land.height_at(view.eye.x, view.eye.z);
            if view.eye.y <= ground {
                return Err(Error::Usage(format!(
                    "the eye {},{},{} is under the ground, which is at {ground:.1} m there: \
                     give an --eye (or [camera] eye) above it",
                    table::number(view.eye.x),
                    table::number(view.eye.y),
                    table::number(view.eye.z),
                )));
            }
            let method = props_method(&params, method)?;
            let gpu = Gpu::new()?;
            let timer = timer_if(timings, &gpu);
            if let Some(method) = method.own_path() {
                // The seed's ray marches draw no grass (the default's is left out); grass
                // asked for by its keys is refused.
                let asked = relief::grass::Grass {
                    on: true,
                    ..params.grass
                } != relief::grass::Grass::default();
                if params.grass.on && asked && method != relief::Method::Reference {
                    return Err(Error::Usage(format!(
                        "--grass-density, --grass-height, --grass-distance: the {method} casts \
                         rays, which draw no grass: give --method mesh, visibility, hybrid or \
                         reference (or --no-grass)"
                    )));
                }
                if frames > 1 {
                    return Err(Error::Usage(format!(
                        "--frames {frames}: the temporal service accumulates the mesh-based \
                         methods (mesh, visibility, hybrid), and the {method} casts rays: give \
                         one of those (or --frames 1)"
                    )));
                }
                // The reference marches the props (the scene's, else the landscape's).
                let scene = props
                    .clone()
                    .unwrap_or_else(relief::props::kinds::landscape);
                let image = headless::render_world_rays_with_props(
                    &gpu,
                    (&params, &scene),
                    &Shading::default(),
                    &view,
                    method,
                    timer.as_ref(),
                )?;
                if timings {
                    print_timings(&gpu, image.timings);
                }
                if stats {
                    // Rays draw the continuous surface: no mesh, nothing baked.
                    println!("triangles 0\ntexels_baked 0\ntexels_pending 0\nlevels 0");
                    println!("unresolved_rays {}", image.unresolved);
                    if params.grass.on {
                        // The reference draws every blade it keeps in four segments.
                        let blades = u64::from(image.blades);
                        println!(
                            "grass_blades_drawn {blades}\ngrass_triangles {}",
                            7 * blades
                        );
                    }
                }
                if image.unresolved > 0 {
                    eprintln!(
                        "relief: {} rays ran out of steps ({} each) and are drawn as sky",
                        image.unresolved,
                        relief::gpu::world_rays::MAX_STEPS
                    );
                }
                return write_png(&out, width, height, image::ColorType::Rgba8, &image.rgba);
            }
            let targets = Offscreen::targets(headless::RENDER_SAMPLES);
            let mut world = World::new(&gpu.device, &gpu.queue, targets, params)?;
            if let Some(scene) = props {
                world.set_props_scene(&gpu.device, scene)?;
            }
            let scene = headless::TrialScene::Endless(&mut world, &view);
            resolve_drawn(&gpu, method, scene, timings)?;
            if frames > 1 {
                world.set_temporal(&gpu.device, relief::Temporal { frames })?;
            }
            let (pixels, t) = headless::render_world_frames(
                &gpu,
                &mut world,
                &view,
                ((width, height), frames),
                TILE,
                timer.as_ref(),
            )?;
            if timings {
                print_timings(&gpu, t);
            }
            if let Some(line) = knob_warning(&world.stats(), params.pixel_error, (width, height)) {
                eprintln!("{line}");
            }
            if stats {
                // The still frame's whole bake, whatever the method (or auto's trial) baked
                // in which frame.
                let mut s = world.stats();
                s.texels_baked = world.held_texels();
                for line in s.lines() {
                    println!("{line}");
                }
                println!(
                    "method_texture_mib {:.1}",
                    relief::gpu::world::mib(world.method_bytes())
                );
                println!(
                    "shafts_mib {:.1}",
                    relief::gpu::world::mib(world.shafts_bytes())
                );
                if let Some(counts) = world.grass_counts(&gpu.device, &gpu.queue) {
                    let [considered, kept, drawn, triangles] = counts?;
                    println!("grass_blades_considered {considered}");
                    println!("grass_blades_drawn {drawn}");
                    if kept > drawn {
                        // The blade buffer's cap: said in words, never a panic.
                        eprintln!(
                            "grass: {kept} blades in view, {drawn} drawn: the blade buffer holds \
                             {} ({} MiB); the rest are not drawn (lower grass_density or \
                             grass_distance)",
                            relief::gpu::grass::CAPACITY,
                            relief::gpu::world::mib(world.grass_bytes()).round()
                        );
                    }
                    println!("grass_triangles {triangles}");
                    println!(
                        "grass_mib {:.1}",
                        relief::gpu::world::mib(world.grass_bytes())
                    );
                }
                if let Some(counts) = world.props_counts(&gpu.device, &gpu.queue) {
                    let [placed, seen] = counts?;
                    println!("props_placed {placed}\nprops_in_view {seen}");
                    println!(
                        "props_mib {:.1}",
                        relief::gpu::world::mib(world.props_bytes())
                    );
                }
            }
            write_png(&out, width, height, image::ColorType::Rgba8, &pixels)
        }
        Run::Bench {
            out_dir,
            quick,
            only,
            views,
        } => bench_endless(&params, &out_dir, quick, (only, &views)),
        _ => Err(Error::Usage(
            "--world endless applies to relief render, height and bench only".into(),
        )),
    }
}

pub(super) fn render(
    params: &TerrainParams,
    out: &Path,
    (width, height): (u32, u32),
    method: Drawn,
    camera: &Camera,
    flags: Flags,
) -> Result<()> {
    check_png_path(out)?;
    let Flags {
        timings,
        stats,
        frames,
    } = flags;
    if frames > 1 {
        return Err(Error::Usage(format!(
            "--frames {frames}: the tile world draws one frame (the temporal service \
             accumulates the endless world's: --world endless)"
        )));
    }
    let gpu = Gpu::new()?;
    let timer = timer_if(timings, &gpu);
    let view = tile_view(camera, (width, height));
    let mut drawn = None;
    let own_path = method.own_path();
    let (pixels, t) = if own_path.is_none() {
        let targets = Offscreen::targets(headless::RENDER_SAMPLES);
        let mut terrain = Terrain::new(&gpu.device, &gpu.queue, targets, *params)?;
        let scene = headless::TrialScene::Tile(&mut terrain, &view, (width, height));
        resolve_drawn(&gpu, method, scene, timings)?;
        let frame = headless::render_image(
            &gpu,
            &mut terrain,
            &view,
            (width, height),
            TILE,
            timer.as_ref(),
        )?;
        // The still frame's whole bake: the levels' texels and the tile's own textures.
        let mut s = terrain.world().stats();
        s.texels_baked = terrain.world().held_texels() + u64::from(params.size).pow(2);
        drawn = Some((s, params.size, terrain.world().method_bytes()));
        frame
    } else if own_path == Some(relief::Method::Blog) {
        let scene = (params, &Shading::default());
        let image = headless::BlogImage::Pipeline;
        headless::render_blog(&gpu, scene, &view, (width, height), image, timer.as_ref())?
    } else {
        headless::render_rays(
            &gpu,
            params,
            &Shading::default(),
            &view,
            (width, height),
            own_path.unwrap_or_default(),
            timer.as_ref(),
        )?
    };
    if timings {
        print_timings(&gpu, t);
    }
    if stats {
        // The mesh's levels (the clipmap renderer's stats); the ray casters draw no triangles.
        // The tile's own textures (its heights, colour and normals) come on top of the levels'.
        match drawn {
            Some((s, size, method_bytes)) => {
                s.lines().iter().for_each(|l| println!("{l}"));
                let tile = relief::gpu::Textures::bytes(size);
                println!("tile_texture_mib {:.1}", relief::gpu::world::mib(tile));
                println!(
                    "method_texture_mib {:.1}",
                    relief::gpu::world::mib(method_bytes)
                );
                println!(
                    "total_texture_mib {:.1}",
                    relief::gpu::world::mib(tile + s.texture_bytes())
                );
            }
            None if own_path == Some(relief::Method::Blog) => {
                // The blog's grid, and its two 8-bit maps baked whole every frame.
                let side = u64::from(relief::gpu::blog::BLOG_SIZE);
                let texel = relief::gpu::blog::BLOG_FORMAT
                    .block_copy_size(None)
                    .unwrap_or(0);
                let bytes = 2 * side * side * u64::from(texel);
                println!("triangles {}", (side - 1).pow(2) * 2);
                println!("texels_baked {}\ntexels_pending 0\nlevels 0", side * side);
                println!("total_texture_mib {:.1}", relief::gpu::world::mib(bytes));
            }
            None => println!("triangles 0\ntexels_baked 0\ntexels_pending 0\nlevels 0"),
        }
    }
    write_png(out, width, height, image::ColorType::Rgba8, &pixels)
}

pub(super) fn timer_if(wanted: bool, gpu: &Gpu) -> Option<GpuTimer> {
    wanted
        .then(|| GpuTimer::new(&gpu.device, &gpu.queue))
        .flatten()
}

pub(super) fn print_timings(gpu: &Gpu, t: Option<Timings>) {
    let Some(t) = t else {
        println!("timings: {} has no timestamp queries", gpu.describe());
        return;
    };
    let parts: Vec<String> = Slot::ALL
        .iter()
        .filter_map(|&s| t[s as usize].map(|ms| format!("{} {ms:.3} ms", s.name())))
        .collect();
    println!("timings on {}: {}", gpu.describe(), parts.join(", "));
}

/// Writes one output file to the path it is given.
pub(super) type FileWriter<'a> = Box<dyn Fn(&Path) -> Result<()> + 'a>;

/// An axis's results: its CSV's file name and text, and what writes its charts.
pub(super) type AxisOutput<'a> = (&'static str, String, Box<dyn FnOnce() -> Result<()> + 'a>);

/// The one stderr line `relief render --world endless` prints where the knob asks for less
/// screen error than the levels can give this view: the bound of the layout (`error_bound_px`
/// in `--stats`) is over `--pixel-error`, because the patches are at their largest side
/// ([`relief::clipmap::PATCH_RANGE`]) or the finest level is coarse for the eye's height over
/// the ground. None where the knob is honoured.
pub(super) fn knob_warning(s: &relief::WorldStats, knob: f64, size: (u32, u32)) -> Option<String> {
    (s.error_bound_px > knob * (1.0 + 1e-9)).then(|| {
        format!(
            "relief: --pixel-error {knob} is finer than the levels can give this view at {}x{} ({}-cell patches, {} m finest spacing): its screen error is bounded by {:.2} px",
            size.0, size.1, s.patch_cells, s.finest_spacing, s.error_bound_px
        )
    })
}

/// How a frame with props is drawn: `auto` picks the visibility method rasterised in compute,
/// which marches them between its raster and its shading (their shadows fall on the terrain);
/// the other mesh-based methods draw them over the terrain (the props' overlay), the reference
/// marches them at its samples; the seed's ray marches are refused in one line.
fn props_method(params: &WorldParams, method: Drawn) -> Result<Drawn> {
    use relief::{choice::Candidate, Method};
    let Some(marching) = Candidate::for_props(params.props.on) else {
        return Ok(method);
    };
    match method {
        Drawn::Auto => Ok(Drawn::Pinned(marching)),
        Drawn::Pinned(c) if c.method.is_mesh() || c.method == Method::Reference => Ok(method),
        Drawn::Pinned(c) => Err(Error::Usage(format!(
            "--props: the {} casts rays, which march no props: give --method mesh, \
             visibility, hybrid, reference or auto",
            c.method
        ))),
    }
}
