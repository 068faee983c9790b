//! `relief bench` on the tile: the sweep, its CSV and chart.

use super::*;

pub(super) struct Bar(indicatif::ProgressBar);

impl relief_eval::bench::Progress for Bar {
    fn start(&mut self, index: usize, _total: usize, config: &relief_eval::bench::Config) {
        self.0.set_position(index as u64);
        self.0.set_message(config.label());
    }
}

pub(super) fn bench(base: &TerrainParams, dir: &Path, quick: bool) -> Result<()> {
    use relief_eval::bench;
    check_out_dir(dir)?;
    // Its charts' font, before minutes of measuring.
    relief_eval::chart::check_font()?;
    let gpu = Gpu::new()?;
    let info = gpu.adapter.get_info();
    let options = if quick {
        bench::Options::QUICK
    } else {
        bench::Options::FULL
    };
    let configs = bench::sweep(base, quick);
    // Every swept configuration must fit this device before anything runs.
    for c in &configs {
        c.params.validate_for(&gpu.device.limits())?;
    }
    if GpuTimer::new(&gpu.device, &gpu.queue).is_none() {
        println!(
            "note: {} has no timestamp queries: GPU times are empty, only wall times are measured",
            gpu.describe()
        );
    }
    println!(
        "relief bench{} on {}: {} configurations at {}x{}, reference at {}x supersampling, scene: seed {}, octaves {}, frequency {}, gain {}, height scale {}",
        if quick { " --quick" } else { "" },
        gpu.describe(),
        configs.len(),
        options.width,
        options.height,
        options.supersample,
        base.seed,
        base.octaves,
        base.frequency,
        base.gain,
        base.height_scale,
    );
    let bar = indicatif::ProgressBar::new(configs.len() as u64).with_style(
        indicatif::ProgressStyle::with_template("{bar:30} {pos}/{len} {elapsed} {msg}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    let mut progress = Bar(bar);
    let start = std::time::Instant::now();
    let rows = bench::run(&gpu, base, &configs, &options, &mut progress)?;
    progress.0.finish_and_clear();
    print!("{}", bench::table(&rows));
    let csv = bench::csv(&rows, &info.name, &format!("{:?}", info.backend), &options);
    let title = format!(
        "relief: error against GPU time on {} ({:?})",
        info.name, info.backend
    );
    write_results(dir, ("bench.csv", &csv), || {
        bench::chart(&rows, &title, &dir.join("bench"))
    })?;
    println!(
        "wrote {}, bench.png and bench.svg in {:.0} s",
        dir.join("bench.csv").display(),
        start.elapsed().as_secs_f64()
    );
    Ok(())
}

/// Writes a sweep's CSV into `dir` (whole or not at all) and then its charts with `charts`; a
/// folder this created is removed again if either fails.
pub(super) fn write_results(
    dir: &Path,
    (name, csv): (&str, &str),
    charts: impl FnOnce() -> Result<()>,
) -> Result<()> {
    let created = create_dirs(dir)?;
    let result = write_whole(&dir.join(name), csv).and_then(|()| charts());
    if result.is_err() {
        if let Some(c) = created {
            let _ = std::fs::remove_dir_all(c);
        }
    }
    result
}
