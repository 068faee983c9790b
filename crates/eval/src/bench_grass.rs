//! `relief bench --world endless --only grass`: the grass ([`relief::grass`], the `grass` keys of
//! the world's table) on the views where it matters: a sunlit meadow
//! ([`relief::WorldParams::find_meadow`]) from 1.7 m looking nearly level, the same from 10 m
//! looking 30 degrees down, and a low flight 50 m over it, for the default method (as
//! [`crate::bench_temporal::method`]) and the forward mesh; then the random view set
//! ([`crate::views::random_views`], fixed by a seed, mostly far above any grass) for the
//! default method; and on the meadow from 1.7 m the peer, Terra's way with grass written again
//! from its description ([`relief::grass::Peer`]: a fixed patch of instanced blades, all
//! drawn), at its presets of 20k, 84k and 500k blades, drawn by the GPU's rasteriser and by the
//! compute raster. Each with grass and without: the frame's median GPU time, the scatter's, and
//! the blades considered and drawn; with grass, FLIP against the grass reference (`--method
//! reference` with grass: every blade to twice the draw distance, 9x9 samples a pixel) and
//! the seam at the draw distance against it.

use crate::bench::{measure, Options};
use crate::metrics::{band_delta_e, horizontal_distance, image_error, median, rgb};
use glam::DVec3;
use relief::error::{Error, Result};
use relief::gpu::headless::{render_samples, render_world_rays, Gpu, Offscreen, RayImage};
use relief::gpu::timing::{GpuTimer, Slot};
use relief::grass::{Peer, PEER_PRESETS};
use relief::world::WorldParams;
use relief::{MethodConfig, Temporal, World, WorldView};

/// One view drawn one way, with grass and without.
#[derive(Clone, Debug, PartialEq)]
pub struct GrassRow {
    /// The view.
    pub view: &'static str,
    /// How it was drawn.
    pub method: String,
    /// Blades considered (cells within the draw distance) and drawn.
    pub blades: [u32; 2],
    /// The frame's median GPU time without grass and with it, milliseconds.
    pub frame_ms: [Option<f64>; 2],
    /// The scatter's median, milliseconds.
    pub scatter_ms: Option<f64>,
    /// FLIP of the frame with grass against the grass reference: one frame, and (the default
    /// method) [`CONVERGED`] frames of the temporal service. Not measured for the peer or in
    /// a quick run.
    pub flip: [Option<f64>; 2],
    /// The seam at the draw distance: the colour difference (ΔE) between the one frame and
    /// the reference within 10% of the draw distance ([`crate::metrics::band_delta_e`]).
    pub seam: Option<f64>,
}

/// Frames the temporal service accumulates for the converged FLIP.
pub const CONVERGED: u32 = 16;

impl GrassRow {
    /// What the grass adds to the frame, milliseconds.
    pub fn grass_ms(&self) -> Option<f64> {
        Some(self.frame_ms[1]? - self.frame_ms[0]?)
    }
}

/// The grass's views of `params`' landscape at `size` (see the module docs), or an error
/// where no sunlit meadow lies near (2000, -3000).
pub fn grass_views(
    params: &WorldParams,
    size: (u32, u32),
) -> Result<Vec<(&'static str, WorldView)>> {
    let foot = params.find_meadow([2000.0, -3000.0]).ok_or_else(|| {
        Error::invalid(
            "the grass's views",
            "no meadow",
            "a sunlit meadow within 10 km of (2000, -3000): another seed, or grass elsewhere",
        )
    })?;
    let fov = 45f32.to_radians();
    let view = |up: f64, look: DVec3| {
        let eye = foot + DVec3::new(0.0, up, 0.0);
        WorldView::look_at(eye, eye + look, fov, size)
    };
    Ok(vec![
        ("meadow", view(1.7, DVec3::new(30.0, -4.0, 10.0))),
        ("meadow-10m", view(10.0, DVec3::new(17.0, -11.5, 6.0))),
        ("flight-50m", view(50.0, DVec3::new(160.0, -40.0, 50.0))),
    ])
}

/// Measures every view of [`grass_views`] for the default method and the forward mesh, the
/// peer on the meadow, and the random views for the default method, handing each row to `sink`
/// as it is measured. `quick` (lavapipe in CI): the named views alone.
pub fn run(
    gpu: &Gpu,
    params: &WorldParams,
    (options, quick): (&Options, bool),
    mut sink: impl FnMut(&GrassRow) -> Result<()>,
) -> Result<Vec<GrassRow>> {
    let size = (options.width, options.height);
    let timer = GpuTimer::new(&gpu.device, &gpu.queue);
    let mut rows = Vec::new();
    let default = crate::bench_temporal::method();
    type Run = (
        &'static str,
        WorldView,
        WorldParams,
        Vec<(MethodConfig, Option<Peer>)>,
    );
    let mut runs: Vec<Run> = Vec::new();
    let mut truths: Vec<(&'static str, RayImage)> = Vec::new();
    for (name, view) in grass_views(params, size)? {
        let peers = PEER_PRESETS.iter().flat_map(|&blades| {
            [true, false].map(|rasteriser| (default, Some(Peer { blades, rasteriser })))
        });
        let mut configs = vec![(default, None), (MethodConfig::MESH, None)];
        if name == "meadow" && !quick {
            configs.extend(peers);
        }
        runs.push((name, view, *params, configs));
    }
    for v in crate::views::random_views(params, size)
        .into_iter()
        .filter(|_| !quick)
    {
        runs.push((v.name, v.view, v.params(params), vec![(default, None)]));
    }
    for (name, view, params, configs) in runs {
        for (config, peer) in configs {
            let samples = render_samples(config.method);
            let target = Offscreen::new(&gpu.device, size.0, size.1, samples)?;
            let method = relief::choice::Candidate {
                method: config.method,
                samples: config.samples,
                raster: config.raster,
            }
            .to_string();
            let mut row = GrassRow {
                view: name,
                method: match peer {
                    Some(p) => format!(
                        "terra peer {}k by {} in {method}",
                        p.blades / 1000,
                        if p.rasteriser {
                            "the rasteriser"
                        } else {
                            "the compute raster"
                        }
                    ),
                    None => method,
                },
                blades: [0; 2],
                frame_ms: [None; 2],
                scatter_ms: None,
                flip: [None; 2],
                seam: None,
            };
            for (i, on) in [false, true].into_iter().enumerate() {
                let mut p = params;
                p.grass.on = on;
                let mut world =
                    World::new(&gpu.device, &gpu.queue, Offscreen::targets(samples), p)?;
                world.set_method(&gpu.device, config)?;
                world.set_grass_peer(&gpu.device, peer)?;
                target.accumulate_world(gpu, &mut world, &view, 0)?;
                let (times, _) = measure(gpu, options, timer.as_ref(), |encoder, timer| {
                    let _ = world.prepare_timed(&gpu.device, &gpu.queue, encoder, &view, timer);
                    target.draw(encoder, &world, wgpu::Color::BLACK, timer);
                })?;
                row.frame_ms[i] = median(times.iter().filter_map(relief::choice::draw_ms));
                if on {
                    row.scatter_ms = median(times.iter().filter_map(|t| t[Slot::Grass as usize]));
                    if let Some(counts) = world.grass_counts(&gpu.device, &gpu.queue) {
                        let [considered, _, drawn, _] = counts?;
                        row.blades = [considered, drawn];
                    }
                    if peer.is_none() && !quick {
                        let at = match truths.iter().position(|(n, _)| *n == name) {
                            Some(at) => at,
                            None => {
                                let shading = relief::Shading::default();
                                let truth = render_world_rays(
                                    gpu,
                                    &p,
                                    &shading,
                                    &view,
                                    relief::Method::Reference,
                                    None,
                                )?;
                                truths.push((name, truth));
                                truths.len() - 1
                            }
                        };
                        let converge = config == default;
                        let truth = &truths[at].1;
                        accuracy(gpu, (&target, &mut world, &view), truth, converge, &mut row)?;
                    }
                }
            }
            sink(&row)?;
            rows.push(row);
        }
    }
    Ok(rows)
}

/// Fills `row`'s FLIP and seam: `world` (grass on, measured) drawn into `target` through
/// `view` against the grass reference `truth`, once, and (`converge`) accumulated over
/// [`CONVERGED`] frames of the temporal service.
fn accuracy(
    gpu: &Gpu,
    (target, world, view): (&Offscreen, &mut World, &WorldView),
    truth: &RayImage,
    converge: bool,
    row: &mut GrassRow,
) -> Result<()> {
    let size = view.size;
    let flip = |image: &[u8]| image_error(&rgb(&truth.rgba), &rgb(image), size.0, size.1).0;
    let (one, _) = target.render_world(gpu, world, view, None)?;
    row.flip[0] = Some(flip(&one));
    let d = world.params().grass.distance;
    let horizontal = horizontal_distance(view, &truth.distance);
    row.seam = band_delta_e(&one, &truth.rgba, &horizontal, (0.9 * d, 1.1 * d)).map(|s| s.0);
    if converge {
        world.set_temporal(&gpu.device, Temporal { frames: CONVERGED })?;
        target.accumulate_world(gpu, world, view, 0)?;
        target.advance_world(gpu, world, view, CONVERGED - 1)?;
        let (many, _) = target.render_world(gpu, world, view, None)?;
        row.flip[1] = Some(flip(&many));
        world.set_temporal(&gpu.device, Temporal { frames: 1 })?;
    }
    Ok(())
}

/// `grass.csv`'s header: what was measured, where.
pub fn header(device: &str, size: (u32, u32)) -> String {
    format!(
        "# relief bench --world endless --only grass on {device} at {}x{}: each view drawn \
         without grass and with it (the grass's defaults); frame: the median GPU time of its \
         passes, milliseconds; FLIP against the grass reference (9x9 samples a pixel, every \
         blade to twice the draw distance) of one frame and of {CONVERGED} accumulated; the \
         seam: CIE76 colour difference of the mean colours within 10% of the draw distance\n\
         view,method,blades_considered,blades_drawn,frame_ms_without,frame_ms_with,grass_ms,\
         scatter_ms,flip,flip_converged,seam\n",
        size.0, size.1
    )
}

/// One row of `grass.csv`.
pub fn line(r: &GrassRow) -> String {
    let ms = |v: Option<f64>| v.map_or(String::new(), |v| format!("{v:.3}"));
    let x = |v: Option<f64>, digits: usize| v.map_or(String::new(), |v| format!("{v:.digits$}"));
    format!(
        "{},{},{},{},{},{},{},{},{},{},{}\n",
        r.view,
        r.method,
        r.blades[0],
        r.blades[1],
        ms(r.frame_ms[0]),
        ms(r.frame_ms[1]),
        ms(r.grass_ms()),
        ms(r.scatter_ms),
        x(r.flip[0], 4),
        x(r.flip[1], 4),
        x(r.seam, 2)
    )
}

/// The lines `relief bench` prints: per view, what the grass costs the default method and how
/// many blades it draws, against the goals.
pub fn summary(rows: &[GrassRow]) -> Vec<String> {
    let default = crate::bench_temporal::method();
    let name = relief::choice::Candidate {
        method: default.method,
        samples: default.samples,
        raster: default.raster,
    }
    .to_string();
    let ms = |v: Option<f64>| v.map_or("-".to_owned(), |v| format!("{v:.3}"));
    let per_ms = |r: &GrassRow| {
        r.grass_ms()
            .filter(|&t| t > 0.0)
            .map_or("-".to_owned(), |t| {
                format!("{:.0}k", f64::from(r.blades[1]) / t / 1e3)
            })
    };
    let ours = rows.iter().filter(|r| r.method == name).map(|r| {
        format!(
            "{}: {} blades drawn of {} considered (goal on the meadow: 100k of 1M); the grass {} \
             ms (goal 0.5), the frame {} ms (goal 2); {} blades a ms; FLIP {} ({} frames: {}), \
             the seam {} (goal 2)",
            r.view,
            r.blades[1],
            r.blades[0],
            ms(r.grass_ms()),
            ms(r.frame_ms[1]),
            per_ms(r),
            ms(r.flip[0]),
            CONVERGED,
            ms(r.flip[1]),
            r.seam.map_or("-".to_owned(), |s| format!("{s:.2}"))
        )
    });
    let peers = rows
        .iter()
        .filter(|r| r.method.starts_with("terra peer"))
        .map(|r| {
            format!(
                "{}, {}: {} blades drawn, the grass {} ms, {} blades a ms",
                r.view,
                r.method,
                r.blades[1],
                ms(r.grass_ms()),
                per_ms(r)
            )
        });
    ours.chain(peers).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_row_reads_as_its_columns() {
        let r = GrassRow {
            view: "meadow",
            method: "mesh".into(),
            blades: [100, 10],
            frame_ms: [Some(1.0), Some(1.5)],
            scatter_ms: Some(0.04),
            flip: [Some(0.1), None],
            seam: Some(1.5),
        };
        let header = header("a GPU", (4, 2));
        let columns = header.lines().nth(1).unwrap().split(',').count();
        let l = line(&r);
        assert_eq!(l.trim().split(',').count(), columns, "{l}");
        assert_eq!(
            l,
            "meadow,mesh,100,10,1.000,1.500,0.500,0.040,0.1000,,1.50\n"
        );
        assert_eq!(r.grass_ms(), Some(0.5));
    }
}
