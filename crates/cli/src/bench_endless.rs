//! `relief bench --world endless`: the look's cost, the landscape sweep and the arrival.

use super::*;

/// `relief bench --world endless`: landscape views over the pixel-error knob and a flight.
pub(super) fn bench_endless(
    params: &WorldParams,
    dir: &Path,
    quick: bool,
    (only, views): (Option<&str>, &[String]),
) -> Result<()> {
    use relief_eval::bench::Options;
    // The terrain's parts measure the terrain alone; the grass (on by default) is measured by
    // its own part, against the same frame without it.
    let with_grass = params;
    let params = &params.without_grass();
    let (options, knobs): (Options, &[f64]) = if quick {
        (Options::QUICK, &[8.0, 16.0])
    } else {
        (Options::FULL, &[0.5, 1.0, 2.0, 4.0, 8.0])
    };
    let size = (options.width, options.height);
    // `--view`: checked before anything is made.
    let chosen = if views.is_empty() {
        None
    } else if matches!(only, Some("temporal" | "reference")) {
        Some(relief_eval::views::views_named(params, size, views)?)
    } else if only == Some("props") {
        // The props' own views, checked before anything is made.
        relief_eval::bench_props::check_views(params, size, views)?;
        None
    } else {
        return Err(Error::Usage(
            "--view picks the views of relief bench --world endless --only temporal, \
             reference or props"
                .into(),
        ));
    };
    check_out_dir(dir)?;
    // Its charts' font, before minutes of measuring.
    relief_eval::chart::check_font()?;
    let gpu = Gpu::new()?;
    let land = &params.land;
    if let Some(part) = only {
        println!(
            "relief bench --world endless{} --only {part} on {} at {}x{}",
            if quick { " --quick" } else { "" },
            gpu.describe(),
            options.width,
            options.height
        );
    } else {
        println!(
        "relief bench --world endless{} on {}, world: seed {}, octaves {}, gain {}, feature size {} m, peak height {} m: {} views x {} knobs{} and a flight at {}x{}",
        if quick { " --quick" } else { "" },
        gpu.describe(),
        land.seed,
        land.octaves,
        land.gain,
        land.cell(0),
        land.peak_height,
        3,
        knobs.len(),
        if quick {
            String::new()
        } else {
            format!(
                ", {} random views (seed {:#x}) at the scene's knob",
                relief_eval::bench_world::RANDOM_VIEWS.len(),
                relief_eval::bench_world::RANDOM_VIEW_SEED
            )
        },
        options.width,
        options.height
    );
    }
    let created = create_dirs(dir)?;
    // Progress on stderr where a person watches it, never into a file.
    let progress = |what: &str| {
        if std::io::IsTerminal::is_terminal(&std::io::stderr()) {
            eprint!("\r\x1b[K{what}");
        }
    };
    let done = || progress("");
    let wrote = |name: &str, rows: usize| {
        println!("{} rows in {}", rows, dir.join(name).display());
    };
    // The look's cost first (it is short), then the LOD sweep, then the arrival.
    let look = || -> Result<()> {
        let rows = relief_eval::bench_look::run(&gpu, params, &options, progress)?;
        done();
        let csv = relief_eval::bench_look::csv(&rows, &gpu.describe(), &options);
        write_whole(&dir.join("look.csv"), &csv)?;
        wrote("look.csv", rows.len());
        Ok(())
    };
    let sweep = || -> Result<()> {
        let rows = relief_eval::bench_world::run(&gpu, params, knobs, &options, progress)?;
        done();
        let csv = relief_eval::bench_world::csv(&rows, &gpu.describe(), &options);
        // The adapter's name alone: the whole description (backend, a software device's
        // caveat) is in the CSV and overran the chart's width.
        let title = format!(
            "relief: the endless world's LOD on {} (knob in px beside each point)",
            gpu.adapter.get_info().name
        );
        write_whole(&dir.join("landscape.csv"), &csv)?;
        wrote("landscape.csv", rows.len());
        relief_eval::bench_world_chart::chart(&rows, &title, &dir.join("landscape"))
    };
    let arrival = || -> Result<()> {
        progress("arrival");
        let size = (options.width, options.height);
        let frames =
            relief_eval::bench_arrival::run(&gpu, params, size, if quick { 6 } else { 600 })?;
        done();
        let csv = relief_eval::bench_arrival::csv(&frames, &gpu.describe(), size);
        write_whole(&dir.join("arrival.csv"), &csv)?;
        wrote("arrival.csv", frames.len());
        for line in relief_eval::bench_arrival::summary(&frames) {
            println!("{line}");
        }
        Ok(())
    };
    let device = gpu.describe();
    let temporal = || -> Result<()> {
        use relief_eval::bench_temporal as t;
        let mut sink = TemporalFiles::create(dir, &device, size, t::reference_side(quick))?;
        let run = t::run_temporal(
            &gpu,
            params,
            &options,
            (quick, chosen.as_deref()),
            &mut sink,
        )?;
        done();
        wrote("temporal.csv", run.still.len());
        wrote("temporal-moving.csv", run.moving.len());
        t::chart(&run.still, &dir.join("temporal"))?;
        for line in t::summary(&run) {
            println!("{line}");
        }
        Ok(())
    };
    let reference = || -> Result<()> {
        use relief_eval::bench_temporal as t;
        use std::io::Write;
        let path = dir.join("reference.csv");
        let mut file = std::fs::File::create(&path).map_err(|e| Error::io(&path, e))?;
        let mut write = |text: String| {
            file.write_all(text.as_bytes())
                .map_err(|e| Error::io(&path, e))
        };
        write(t::reference_header(&device, size))?;
        let rows = t::run_reference(
            &gpu,
            params,
            &options,
            (quick, chosen.as_deref()),
            (progress, |row: &t::ReferenceRow| {
                write(t::reference_line(row))
            }),
        )?;
        done();
        wrote("reference.csv", rows.len());
        Ok(())
    };
    let grass = || -> Result<()> {
        use relief_eval::bench_grass as g;
        use std::io::Write;
        let path = dir.join("grass.csv");
        let mut file = std::fs::File::create(&path).map_err(|e| Error::io(&path, e))?;
        let mut write = |text: String| {
            file.write_all(text.as_bytes())
                .map_err(|e| Error::io(&path, e))
        };
        write(g::header(&device, size))?;
        let rows = g::run(&gpu, with_grass, (&options, quick), |row: &g::GrassRow| {
            progress(&format!("grass: {} by {}", row.view, row.method));
            write(g::line(row))
        })?;
        done();
        wrote("grass.csv", rows.len());
        for line in g::summary(&rows) {
            println!("{line}");
        }
        Ok(())
    };
    let props = || -> Result<()> {
        use relief_eval::bench_props as b;
        use std::io::Write;
        let path = dir.join("props.csv");
        let mut file = std::fs::File::create(&path).map_err(|e| Error::io(&path, e))?;
        let mut write = |text: String| {
            file.write_all(text.as_bytes())
                .map_err(|e| Error::io(&path, e))
        };
        write(b::header(&device, size))?;
        let chosen = (!views.is_empty()).then_some(views);
        let how = (&options, quick, chosen);
        let rows = b::run(&gpu, with_grass, how, |row: &b::PropsRow| {
            progress(&format!("props: {} by {}", row.view, row.method));
            write(b::line(row))
        })?;
        done();
        wrote("props.csv", rows.len());
        for line in b::summary(&rows) {
            println!("{line}");
        }
        Ok(())
    };
    let clouds = || -> Result<()> {
        use relief_eval::bench_clouds as c;
        use std::io::Write;
        let path = dir.join("clouds.csv");
        let mut file = std::fs::File::create(&path).map_err(|e| Error::io(&path, e))?;
        file.write_all(c::header(&device, size).as_bytes())
            .map_err(|e| Error::io(&path, e))?;
        let rows = c::run(&gpu, params, (&options, quick), |row: &c::CloudRow| {
            progress(&format!("clouds: {}", row.view));
            file.write_all(c::line(row).as_bytes())
                .map_err(|e| Error::io(&path, e))
        })?;
        done();
        wrote("clouds.csv", rows.len());
        for line in c::summary(&rows) {
            println!("{line}");
        }
        Ok(())
    };
    let result = match only {
        Some("look") => look(),
        Some("landscape") => sweep(),
        Some("arrival") => arrival(),
        Some("temporal") => temporal(),
        Some("reference") => reference(),
        Some("grass") => grass(),
        Some("props") => props(),
        Some("clouds") => clouds(),
        _ => look().and_then(|()| sweep()).and_then(|()| arrival()),
    };
    if result.is_err() {
        // A folder this made goes again only where it holds nothing: the parts write their
        // rows as they measure them, and what was measured before the failure stays.
        if let Some(c) = created {
            let _ = std::fs::remove_dir(c);
        }
    }
    result
}

/// `temporal.csv` and `temporal-moving.csv`, written a row at a time as the part measures.
struct TemporalFiles {
    still: std::fs::File,
    moving: std::fs::File,
    paths: [std::path::PathBuf; 2],
    started: std::time::Instant,
}

impl TemporalFiles {
    fn create(dir: &Path, device: &str, size: (u32, u32), side: u32) -> Result<Self> {
        use relief_eval::bench_temporal as t;
        use std::io::Write;
        let paths = [dir.join("temporal.csv"), dir.join("temporal-moving.csv")];
        let open = |p: &Path, header: String| -> Result<std::fs::File> {
            let mut f = std::fs::File::create(p).map_err(|e| Error::io(p, e))?;
            f.write_all(header.as_bytes())
                .map_err(|e| Error::io(p, e))?;
            Ok(f)
        };
        Ok(Self {
            still: open(&paths[0], t::still_header(device, size, side))?,
            moving: open(&paths[1], t::moving_header(device, size))?,
            paths,
            started: std::time::Instant::now(),
        })
    }
}

impl relief_eval::bench_temporal::Sink for TemporalFiles {
    fn still(&mut self, row: &relief_eval::bench_temporal::StillRow) -> Result<()> {
        use std::io::Write;
        self.still
            .write_all(relief_eval::bench_temporal::still_line(row).as_bytes())
            .map_err(|e| Error::io(&self.paths[0], e))
    }

    fn moving(&mut self, row: &relief_eval::bench_temporal::MovingRow) -> Result<()> {
        use std::io::Write;
        self.moving
            .write_all(relief_eval::bench_temporal::moving_line(row).as_bytes())
            .map_err(|e| Error::io(&self.paths[1], e))
    }

    fn progress(&mut self, what: &str) {
        println!("{:6.1} s  {what}", self.started.elapsed().as_secs_f64());
    }
}
