//! `relief stability`: the sweeps where each method fails, their CSVs and charts.

use super::*;

/// The axes `relief stability --axis` names, each once, in the order they run; all of them
/// without the flag.
pub(super) fn stability_axes(m: &ArgMatches) -> Result<Vec<relief_eval::stability::Axis>> {
    use relief_eval::stability::Axis;
    let Some(names) = m.get_many::<String>("axis") else {
        return Ok(Axis::ALL.to_vec());
    };
    let mut chosen = Vec::new();
    for name in names {
        let axis = Axis::parse(name.trim())
            .ok_or_else(|| Error::invalid("--axis", table::shorten(name), Axis::names()))?;
        chosen.push(axis);
    }
    Ok(Axis::ALL
        .into_iter()
        .filter(|a| chosen.contains(a))
        .collect())
}

/// Runs the stability `axes` with the options of `sweeps` (`--quick` names which in the report)
/// on a fresh device over the scene `base` (the tile's axes) and the sweeps' endless world,
/// printing each axis's table and writing its CSV and charts in `dir`.
pub fn stability(
    base: &TerrainParams,
    dir: &Path,
    (sweeps, quick): (&relief_eval::stability::Sweeps, bool),
    axes: &[relief_eval::stability::Axis],
) -> Result<()> {
    use relief_eval::stability::{self, Axis};
    check_out_dir(dir)?;
    // Its charts' font, before minutes of measuring.
    relief_eval::chart::check_font()?;
    let gpu = Gpu::new()?;
    let info = gpu.adapter.get_info();
    let backend = format!("{:?}", info.backend);
    let device = info.name.clone();
    let on = |axis| axes.contains(&axis);
    println!(
        "relief stability{} on {}: {} {} ({}), scene: seed {}, octaves {}, frequency {}, gain {}",
        if quick { " --quick" } else { "" },
        gpu.describe(),
        axes.len(),
        if axes.len() == 1 { "axis" } else { "axes" },
        axes.iter().map(|a| a.name()).collect::<Vec<_>>().join(", "),
        base.seed,
        base.octaves,
        base.frequency,
        base.gain,
    );
    let bar = indicatif::ProgressBar::new(0).with_style(
        indicatif::ProgressStyle::with_template("{bar:30} {pos}/{len} {elapsed}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    let restart = |len: usize| {
        bar.reset();
        bar.set_length(len as u64);
    };
    let start = std::time::Instant::now();
    // The terrain's axes sweep the terrain alone; the grass (on by default) has its own axis.
    let world = sweeps.world.without_grass();
    let mut outputs: Vec<AxisOutput<'_>> = Vec::new();
    if on(Axis::Grazing) {
        let options = sweeps.grazing.clone();
        println!(
            "grazing views of the scene's tile at {:?} degrees, height scales {:?}, {}x{} (every {} px compared with the CPU f64 ray cast)",
            options.elevations,
            options.height_scales,
            options.size.0,
            options.size.1,
            options.stride,
        );
        restart(options.elevations.len() * options.height_scales.len());
        let rows = stability::grazing(&gpu, base, &options, |done, _| {
            bar.set_position(done as u64)
        })?;
        bar.finish_and_clear();
        print!("{}", stability::table(&rows, &options));
        let csv = stability::csv(&rows, &device, &backend, &options);
        let title = format!("relief: grazing rays on {device} ({backend})");
        outputs.push((
            "stability.csv",
            csv,
            Box::new(move || stability::chart(&rows, &options, &title, &dir.join("grazing"))),
        ));
    }
    if on(Axis::WorldGrazing) {
        let options = sweeps.world_grazing.clone();
        println!(
            "grazing views of the endless world at {:?} degrees, {}x{} (every {} px compared with the CPU f64 ray cast)",
            options.elevations, options.size.0, options.size.1, options.stride
        );
        restart(options.elevations.len());
        let rows = stability::world_grazing::world_grazing(&gpu, &world, &options, |done, _| {
            bar.set_position(done as u64)
        })?;
        bar.finish_and_clear();
        print!("{}", stability::table(&rows, &options));
        let csv = stability::csv(&rows, &device, &backend, &options);
        let title = format!("relief: grazing rays over the endless world on {device} ({backend})");
        outputs.push((
            "world-grazing.csv",
            csv,
            Box::new(move || stability::chart(&rows, &options, &title, &dir.join("world-grazing"))),
        ));
    }
    if on(Axis::Shadow) {
        let options = sweeps.shadow.clone();
        println!(
            "shadow rays on the endless world: sun at {:?} degrees (azimuth {}), every {} texel(s) each way of each level drawn, where it draws, compared with f64 rays",
            options.elevations, world.sky.sun_azimuth, options.stride
        );
        restart(options.elevations.len());
        let rows = stability::shadow::shadows(&gpu, &world, &options, |done, _| {
            bar.set_position(done as u64)
        })?;
        bar.finish_and_clear();
        print!("{}", stability::shadow::shadow_table(&rows, &options));
        let csv = stability::shadow::shadow_csv(&rows, &device, &backend, &world);
        let title = format!("relief: shadow rays at a low sun on {device} ({backend})");
        let sun = f64::from(world.sky.sun_elevation);
        outputs.push((
            "shadow.csv",
            csv,
            Box::new(move || {
                stability::shadow::shadow_chart(&rows, &options, sun, (&title, &dir.join("shadow")))
            }),
        ));
    }
    if on(Axis::Distance) {
        let options = sweeps.distance.clone();
        println!(
            "distance from the origin on the endless world: the eye at {:?} m, {}x{}, a {} m step",
            options.distances, options.size.0, options.size.1, options.step
        );
        restart(options.distances.len());
        let rows = stability::distance::distances(&gpu, &world, &options, |done, _| {
            bar.set_position(done as u64)
        })?;
        bar.finish_and_clear();
        print!("{}", stability::distance::distance_table(&rows));
        let csv = stability::distance::distance_csv(&rows, &device, &backend);
        let title = format!("relief: far from the origin on {device} ({backend})");
        outputs.push((
            "distance.csv",
            csv,
            Box::new(move || {
                stability::distance::distance_chart(&rows, (&title, &dir.join("distance")))
            }),
        ));
    }
    if on(Axis::Scroll) {
        let options = sweeps.scroll.clone();
        println!(
            "the tile scrolled from its origin: {:?} tiles, relief's tile at {}² texels (every {} each way against the twin) and the blog's bake",
            options.distances, options.size, options.stride
        );
        restart(options.distances.len());
        let rows = stability::scroll::scroll(&gpu, base, &options, |done, _| {
            bar.set_position(done as u64)
        })?;
        bar.finish_and_clear();
        print!("{}", stability::scroll::scroll_table(&rows));
        let csv = stability::scroll::scroll_csv(&rows, &device, &backend);
        let title = format!("relief and the blog scrolled far, on {device} ({backend})");
        outputs.push((
            "scroll.csv",
            csv,
            Box::new(move || stability::scroll::scroll_chart(&rows, (&title, &dir.join("scroll")))),
        ));
    }
    if on(Axis::Motion) {
        let options = sweeps.motion.clone();
        println!(
            "motion over the endless world: {:?} m a frame, knobs {} px, {} frames at {}x{}, {} m over the ground, the bake budget {} texels a frame",
            options.speeds,
            std::iter::once(world.pixel_error)
                .chain(options.knobs.iter().copied())
                .map(|k| k.to_string())
                .collect::<Vec<_>>()
                .join(", "),
            options.frames,
            options.size.0,
            options.size.1,
            options.height,
            options.budget
        );
        restart((options.knobs.len() + 1) * options.speeds.len());
        let rows = stability::motion::motion(&gpu, &world, &options, |done, _| {
            bar.set_position(done as u64)
        })?;
        bar.finish_and_clear();
        print!("{}", stability::motion::motion_table(&rows));
        let csv = stability::motion::motion_csv(&rows, &device, &backend);
        let title = format!("relief: a moving eye on {device} ({backend})");
        let knob = world.pixel_error;
        outputs.push((
            "motion.csv",
            csv,
            Box::new(move || {
                stability::motion::motion_chart(&rows, knob, (&title, &dir.join("motion")))
            }),
        ));
    }
    if on(Axis::Temporal) {
        let options = sweeps.temporal.clone();
        println!(
            "the temporal service under a moving eye: turns of {:?} degrees a second and sideways {:?} m/s from the horizon view, {} frames measured after {}, {}x{}, against a {}x{} reference",
            options.turns,
            options.strafes,
            options.frames,
            options.warm,
            options.size.0,
            options.size.1,
            options.side,
            options.side
        );
        restart(options.turns.len() + options.strafes.len());
        let rows = stability::temporal::temporal(&gpu, &world, &options, |done, _| {
            bar.set_position(done as u64)
        })?;
        bar.finish_and_clear();
        print!("{}", stability::temporal::temporal_table(&rows));
        let csv = stability::temporal::temporal_csv(&rows, &device, &backend);
        let title = format!("relief: flicker with and without a history on {device} ({backend})");
        outputs.push((
            "temporal.csv",
            csv,
            Box::new(move || {
                stability::temporal::temporal_chart(&rows, (&title, &dir.join("temporal")))
            }),
        ));
    }
    if on(Axis::Grass) {
        let options = sweeps.grass.clone();
        println!(
            "grass under a moving eye: walks of {:?} m/s over the meadow at 1.7 m{}, standing there in winds of {:?} m/s, {} frame-to-frame changes each (after {} filling the history), {}x{}, against the grass reference (9x9 samples a pixel)",
            options.speeds,
            if options.flight { " and the fly-through" } else { "" },
            options.winds,
            options.frames,
            options.warm,
            options.size.0,
            options.size.1,
        );
        restart(options.speeds.len() + usize::from(options.flight) + options.winds.len());
        let rows = stability::grass::grass(&gpu, &sweeps.world, &options, |done, _| {
            bar.set_position(done as u64)
        })?;
        bar.finish_and_clear();
        print!("{}", stability::grass::grass_table(&rows));
        let csv = stability::grass::grass_csv(&rows, &device, &backend);
        let title = format!("relief: grass flicker against its reference on {device} ({backend})");
        outputs.push((
            "grass.csv",
            csv,
            Box::new(move || stability::grass::grass_chart(&rows, (&title, &dir.join("grass")))),
        ));
    }
    if on(Axis::Detail) {
        // Detail against resolution, on the CPU twin, then FLIP on the GPU.
        let options = sweeps.detail.clone();
        let mut rows = stability::detail::detail(base, &options)?;
        stability::detail::detail_flip(&gpu, base, &mut rows, options.image)?;
        println!(
            "detail against resolution: {:?} octaves at {:?} texels a side, the mesh's grid {:?} (the scene's other values; FLIP at {}x{}):",
            options.octaves, options.sizes, options.grids, options.image.0, options.image.1
        );
        print!("{}", stability::detail::detail_table(&rows, &options));
        let csv = stability::detail::detail_csv(&rows, base);
        let title = format!(
            "relief: detail against resolution (CPU f64 twin; FLIP on {device} ({backend}))"
        );
        let scene = (base.octaves, base.size);
        outputs.push((
            "detail.csv",
            csv,
            Box::new(move || {
                stability::detail::detail_chart(&rows, scene, (&title, &dir.join("detail")))
            }),
        ));
    }
    if on(Axis::Storage) {
        // Storage precision, on the CPU twin (no GPU involved), at the tile's texture side.
        let side = sweeps.storage_side;
        let rows = stability::storage(base, side)?;
        println!("storage precision, {side}² texels of the scene's heights:");
        print!("{}", stability::storage_table(&rows));
        let csv = stability::storage_csv(&rows, base, side);
        let title = format!("relief: storage precision, {side}² texels (CPU f64 twin)");
        outputs.push((
            "storage.csv",
            csv,
            Box::new(move || stability::storage_chart(&rows, &title, &dir.join("storage"))),
        ));
    }
    if on(Axis::Props) {
        // The props' march, on their f64 twin (no GPU involved).
        println!(
            "props: marching their fields on the f64 twin (stepping past a surface, the step \
             budget, pops at the cut-off){}",
            if quick { ", fewer rays" } else { "" }
        );
        let rows = stability::props::props(quick);
        print!("{}", stability::props::props_table(&rows));
        let csv = stability::props::props_csv(&rows);
        outputs.push((
            "props.csv",
            csv,
            Box::new(move || stability::props::props_chart(&rows, &dir.join("props"))),
        ));
    }
    if on(Axis::Clouds) {
        let options = sweeps.clouds.clone();
        println!(
            "the clouds' image under a moving eye: turns of {:?} degrees a second from {}{}, at noon, {} frames measured after {}, each against the same frame with every pixel's clouds marched; one still frame of {} of the clouds' views at {:?} steps against {}; {}x{}",
            options.turns,
            if options.turn_views > 1 { "the valley view and inside the layer" } else { "the valley view" },
            if options.flight { " and the fly-through" } else { "" },
            options.frames,
            options.warm,
            options.still_views,
            options.steps,
            relief_eval::bench_clouds::DOUBLED,
            options.size.0,
            options.size.1,
        );
        restart(
            options.turn_views.min(2) * options.turns.len()
                + usize::from(options.flight)
                + options.still_views * options.steps.len(),
        );
        let rows = stability::clouds::clouds(&gpu, &world, &options, |done, _| {
            bar.set_position(done as u64)
        })?;
        bar.finish_and_clear();
        print!("{}", stability::clouds::clouds_table(&rows));
        let csv = stability::clouds::clouds_csv(&rows, &device, &backend);
        let title =
            format!("relief: the clouds' image against a full march on {device} ({backend})");
        outputs.push((
            "clouds.csv",
            csv,
            Box::new(move || stability::clouds::clouds_chart(&rows, (&title, &dir.join("clouds")))),
        ));
    }
    let names: Vec<&str> = outputs.iter().map(|o| o.0).collect();
    let mut outputs = outputs.into_iter();
    let Some((first, csv, charts)) = outputs.next() else {
        return Ok(());
    };
    write_results(dir, (first, &csv), || {
        charts()?;
        for (name, csv, charts) in outputs {
            write_whole(&dir.join(name), &csv)?;
            charts()?;
        }
        Ok(())
    })?;
    println!(
        "wrote {} and their charts (.png, .svg) in {} in {:.0} s",
        names.join(", "),
        dir.display(),
        start.elapsed().as_secs_f64()
    );
    Ok(())
}
