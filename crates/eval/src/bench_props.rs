//! `relief bench --world endless --only props`: the props ([`relief::props`], the `props` keys
//! of the world's table, the shipped landscape's kinds) on their views: among them from 2 m
//! above a meadow looking across it, the meadow's edge looking over the lake, from 200 m
//! looking down over them, and the random view set ([`crate::views::random_views`], fixed by a
//! seed). On each, with the grass off (its own part measures it), the frame drawn without props
//! and with them by the marching method (the visibility method rasterised in compute, which
//! marches them between its raster and its shading), and by the forward mesh and the hybrid
//! (their overlay); and **the seed's way** ([`relief::World::set_props_peer`]: from the eye,
//! every step reading the whole fields of the 3x3 cells around it, no band, no bounds, no
//! raster's depth) at [`PEER_STEPS`] steps. Each: the frame's median GPU time, the props'
//! scatter's and march's, the props in view, and FLIP against the reference of the same view
//! with props (`--method reference`: the props marched conservatively at its 3x3 samples a
//! pixel, [`relief::gpu::headless::render_world_rays`]) or without.

use crate::bench::{measure, Options};
use crate::metrics::{image_error, median, rgb};
use glam::DVec3;
use relief::error::{Error, Result};
use relief::gpu::headless::{render_samples, render_world_rays, Gpu, Offscreen, RayImage};
use relief::gpu::timing::{GpuTimer, Slot};
use relief::world::WorldParams;
use relief::{Method, MethodConfig, World, WorldView};

/// The seed's way's step budgets measured on the named views (on the random ones, the first
/// and the last): the fewest whose FLIP is relief's is the seed's way at equal FLIP.
pub const PEER_STEPS: [u32; 7] = [25, 50, 100, 200, 400, 800, 1600];

/// One view drawn one way, without props and with them.
#[derive(Clone, Debug, PartialEq)]
pub struct PropsRow {
    /// The view.
    pub view: String,
    /// How it was drawn: a method, or the seed's way and its steps.
    pub method: String,
    /// The seed's way's steps (`None`: relief's march).
    pub peer_steps: Option<u32>,
    /// Props placed around the eye and those whose sphere is in the view.
    pub props: [u32; 2],
    /// The frame's median GPU time without props and with them, milliseconds.
    pub frame_ms: [Option<f64>; 2],
    /// The props' scatter's median, milliseconds.
    pub scatter_ms: Option<f64>,
    /// The median of the props' shadow and occlusion on the raster's surface, a 2x2 block at a
    /// time (the marching method's own pass before its march), milliseconds.
    pub shadows_ms: Option<f64>,
    /// The march's median (the overlay's for the mesh and the hybrid), milliseconds.
    pub march_ms: Option<f64>,
    /// The props' shade map's whole bake (the overlay's methods: on arrival, a turned sun or
    /// new props; a still frame bakes none), median, milliseconds.
    pub map_ms: Option<f64>,
    /// FLIP mean of the frame without props against the reference without them, and of the
    /// frame with props against the reference with them.
    pub flip: [Option<f64>; 2],
}

impl PropsRow {
    /// What the props add to the frame, milliseconds.
    pub fn props_ms(&self) -> Option<f64> {
        Some(self.frame_ms[1]? - self.frame_ms[0]?)
    }
}

/// The marching method: the visibility method rasterised in compute.
pub fn marching() -> MethodConfig {
    MethodConfig::MARCHING
}

/// The props' named views of `params`' landscape at `size` (see the module docs).
pub fn props_views(size: (u32, u32)) -> Vec<(&'static str, WorldView)> {
    let view = |eye: [f64; 3], at: [f64; 3], fov: f32| {
        WorldView::look_at(DVec3::from(eye), DVec3::from(at), fov.to_radians(), size)
    };
    vec![
        (
            "among-2m",
            view([2740.0, 1112.0, -3000.0], [2710.0, 1106.0, -3030.0], 50.0),
        ),
        (
            "meadow",
            view([2740.0, 1111.7, -3000.0], [2770.0, 1107.7, -2990.0], 45.0),
        ),
        (
            "over-200m",
            view([2740.0, 1310.0, -3000.0], [2900.0, 1150.0, -2850.0], 45.0),
        ),
    ]
}

/// Refuses a name in `chosen` that is not one of the props' views (named or random), naming
/// them.
pub fn check_views(params: &WorldParams, size: (u32, u32), chosen: &[String]) -> Result<()> {
    let names: Vec<&str> = props_views(size)
        .iter()
        .map(|(n, _)| *n)
        .chain(
            crate::views::random_views(params, size)
                .iter()
                .map(|v| v.name),
        )
        .collect();
    match chosen.iter().find(|c| !names.contains(&c.as_str())) {
        Some(unknown) => Err(Error::invalid(
            "--view",
            unknown,
            format!("one of {}", names.join(", ")),
        )),
        None => Ok(()),
    }
}

/// One way of drawing a view with props.
#[derive(Clone, Copy, Debug)]
struct Way {
    config: MethodConfig,
    peer: Option<u32>,
    name: &'static str,
}

/// Measures every view (see the module docs), or those named in `chosen` (an unknown name is
/// refused before anything is measured), handing each row to `sink` as it is measured.
/// `quick` (lavapipe in CI): the first named view, the marching method and the seed's way at
/// two step budgets.
pub fn run(
    gpu: &Gpu,
    params: &WorldParams,
    (options, quick, chosen): (&Options, bool, Option<&[String]>),
    mut sink: impl FnMut(&PropsRow) -> Result<()>,
) -> Result<Vec<PropsRow>> {
    let size = (options.width, options.height);
    let timer = GpuTimer::new(&gpu.device, &gpu.queue);
    let mut base = params.without_grass();
    base.props.on = true;
    let relief_ways = [
        Way {
            config: marching(),
            peer: None,
            name: "marching",
        },
        Way {
            config: MethodConfig::MESH,
            peer: None,
            name: "mesh",
        },
        Way {
            config: MethodConfig::new(Method::Hybrid).with_samples(1),
            peer: None,
            name: "hybrid",
        },
    ];
    let peer = |steps| Way {
        config: marching(),
        peer: Some(steps),
        name: "the seed's way",
    };
    let mut runs: Vec<(String, WorldView, WorldParams, Vec<Way>)> = Vec::new();
    let named = if quick && chosen.is_none() { 1 } else { 3 };
    for (name, view) in props_views(size).into_iter().take(named) {
        let mut ways = if quick {
            vec![relief_ways[0]]
        } else {
            relief_ways.to_vec()
        };
        let steps: &[u32] = if quick { &[25, 400] } else { &PEER_STEPS };
        ways.extend(steps.iter().map(|&s| peer(s)));
        runs.push((name.to_owned(), view, base, ways));
    }
    if !quick || chosen.is_some() {
        for v in crate::views::random_views(&base, size) {
            let ways = vec![
                relief_ways[0],
                relief_ways[1],
                peer(PEER_STEPS[0]),
                peer(PEER_STEPS[PEER_STEPS.len() - 1]),
            ];
            runs.push((v.name.to_owned(), v.view, v.params(&base), ways));
        }
    }
    if let Some(chosen) = chosen {
        check_views(params, size, chosen)?;
        runs.retain(|(name, ..)| chosen.contains(name));
    }
    let mut rows = Vec::new();
    for (name, view, p, ways) in runs {
        let shading = relief::Shading::default();
        let mut bare = p;
        bare.props.on = false;
        let truths: [RayImage; 2] = [
            render_world_rays(gpu, &bare, &shading, &view, Method::Reference, None)?,
            render_world_rays(gpu, &p, &shading, &view, Method::Reference, None)?,
        ];
        for way in ways {
            let mut row = PropsRow {
                view: name.clone(),
                method: match way.peer {
                    Some(steps) => format!("{} {steps} steps", way.name),
                    None => way.name.to_owned(),
                },
                peer_steps: way.peer,
                props: [0; 2],
                frame_ms: [None; 2],
                scatter_ms: None,
                shadows_ms: None,
                march_ms: None,
                map_ms: None,
                flip: [None; 2],
            };
            // The seed's way differs only with props: its frame without them is the marching
            // method's.
            let sides: &[bool] = if way.peer.is_some() {
                &[true]
            } else {
                &[false, true]
            };
            for &on in sides {
                let params = if on { p } else { bare };
                let measured = frame(gpu, (options, timer.as_ref()), (params, way), &view)?;
                let i = usize::from(on);
                row.frame_ms[i] = measured.frame_ms;
                row.flip[i] = Some(
                    image_error(&rgb(&truths[i].rgba), &rgb(&measured.image), size.0, size.1).0,
                );
                if on {
                    row.scatter_ms = measured.scatter_ms;
                    row.shadows_ms = measured.shadows_ms;
                    row.march_ms = measured.march_ms;
                    row.map_ms = measured.map_ms;
                    row.props = measured.props;
                }
            }
            sink(&row)?;
            rows.push(row);
        }
    }
    Ok(rows)
}

/// What one way's frame of a view measured.
struct Frame {
    frame_ms: Option<f64>,
    scatter_ms: Option<f64>,
    shadows_ms: Option<f64>,
    march_ms: Option<f64>,
    map_ms: Option<f64>,
    props: [u32; 2],
    image: Vec<u8>,
}

fn frame(
    gpu: &Gpu,
    (options, timer): (&Options, Option<&GpuTimer>),
    (params, way): (WorldParams, Way),
    view: &WorldView,
) -> Result<Frame> {
    let size = view.size;
    let samples = render_samples(way.config.method);
    let target = Offscreen::new(&gpu.device, size.0, size.1, samples)?;
    let mut world = World::new(&gpu.device, &gpu.queue, Offscreen::targets(samples), params)?;
    world.set_method(&gpu.device, way.config)?;
    world.set_props_peer(way.peer);
    if params.props.on && !world.draws_props() {
        return Err(Error::invalid(
            "method",
            way.config.method,
            "a method that draws the props",
        ));
    }
    target.accumulate_world(gpu, &mut world, view, 0)?;
    let (times, _) = measure(gpu, options, timer, |encoder, timer| {
        let _ = world.prepare_timed(&gpu.device, &gpu.queue, encoder, view, timer);
        target.draw(encoder, &world, wgpu::Color::BLACK, timer);
    })?;
    let slot = |s: Slot| median(times.iter().filter_map(|t| t[s as usize]));
    // The overlay's shade map baked whole each frame.
    let map_ms = if params.props.on && world.props_overlaid() {
        let (times, _) = measure(gpu, options, timer, |encoder, timer| {
            world.forget_props_map();
            let _ = world.prepare_timed(&gpu.device, &gpu.queue, encoder, view, timer);
            target.draw(encoder, &world, wgpu::Color::BLACK, timer);
        })?;
        median(times.iter().filter_map(|t| t[Slot::PropShadows as usize]))
    } else {
        None
    };
    let props = match world.props_counts(&gpu.device, &gpu.queue) {
        Some(counts) => counts?,
        None => [0; 2],
    };
    let (image, _) = target.render_world(gpu, &mut world, view, None)?;
    Ok(Frame {
        frame_ms: median(times.iter().filter_map(relief::choice::draw_ms)),
        scatter_ms: slot(Slot::Props),
        shadows_ms: slot(Slot::PropShadows),
        march_ms: slot(Slot::March),
        map_ms,
        props,
        image,
    })
}

/// `props.csv`'s header: what was measured, where.
pub fn header(device: &str, size: (u32, u32)) -> String {
    format!(
        "# relief bench --world endless --only props on {device} at {}x{}: each view drawn \
         without props and with them (the shipped landscape's kinds, the props keys' defaults, \
         the grass off); frame: the median GPU time of its passes, milliseconds; scatter, \
         shadows (on the surface, a 2x2 block at a time) and march: the props' passes; map: the \
         overlay's props' shade map baked whole; FLIP (mean) against the reference of the same view without \
         and with props (3x3 samples a pixel, the props marched conservatively, none sunk); \
         the seed's way: from the eye, the whole fields of the 3x3 cells around each step, at \
         most the steps named\n\
         view,method,peer_steps,props_placed,props_in_view,frame_ms_without,frame_ms_with,\
         props_ms,scatter_ms,shadows_ms,march_ms,flip_without,flip_with,map_ms\n",
        size.0, size.1
    )
}

/// One row of `props.csv`.
pub fn line(r: &PropsRow) -> String {
    let ms = |v: Option<f64>| v.map_or(String::new(), |v| format!("{v:.3}"));
    let flip = |v: Option<f64>| v.map_or(String::new(), |v| format!("{v:.4}"));
    format!(
        "{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n",
        r.view,
        r.method,
        r.peer_steps.map_or(String::new(), |s| s.to_string()),
        r.props[0],
        r.props[1],
        ms(r.frame_ms[0]),
        ms(r.frame_ms[1]),
        ms(r.props_ms()),
        ms(r.scatter_ms),
        ms(r.shadows_ms),
        ms(r.march_ms),
        flip(r.flip[0]),
        flip(r.flip[1]),
        ms(r.map_ms),
    )
}

/// The seed's way at relief's FLIP on `view`: the fewest steps whose FLIP is at most the
/// marching method's, with its props' layer's time (scatter and march) and relief's (`None`
/// where no budget measured reaches relief's FLIP).
pub fn equal_flip(rows: &[PropsRow], view: &str) -> Option<(u32, f64, f64)> {
    let relief = rows
        .iter()
        .find(|r| r.view == view && r.method == "marching")?;
    let (flip, ms) = (relief.flip[1]?, layer_ms(relief)?);
    rows.iter()
        .filter(|r| r.view == view && r.peer_steps.is_some())
        .filter(|r| r.flip[1].is_some_and(|f| f <= flip))
        .min_by_key(|r| r.peer_steps)
        .and_then(|r| Some((r.peer_steps?, layer_ms(r)?, ms)))
}

/// The seed's way's most accurate budget on `view`: its steps, FLIP and props' layer's time,
/// and relief's layer's time (`None` where either was not measured).
pub fn best_peer(rows: &[PropsRow], view: &str) -> Option<(u32, f64, f64, f64)> {
    let relief = rows
        .iter()
        .find(|r| r.view == view && r.method == "marching")?;
    let best = rows
        .iter()
        .filter(|r| r.view == view && r.peer_steps.is_some())
        .filter_map(|r| Some((r, r.flip[1]?)))
        .min_by(|a, b| {
            a.1.total_cmp(&b.1)
                .then(a.0.peer_steps.cmp(&b.0.peer_steps))
        })?;
    Some((
        best.0.peer_steps?,
        best.1,
        layer_ms(best.0)?,
        layer_ms(relief)?,
    ))
}

/// A row's props' layer: its scatter, shadows and march, milliseconds.
fn layer_ms(r: &PropsRow) -> Option<f64> {
    Some(r.scatter_ms? + r.shadows_ms.unwrap_or(0.0) + r.march_ms?)
}

/// The lines `relief bench` prints: per view, the props' cost to the marching method, its FLIP
/// against the reference, and the seed's way at equal FLIP.
pub fn summary(rows: &[PropsRow]) -> Vec<String> {
    let mut views: Vec<&str> = rows.iter().map(|r| r.view.as_str()).collect();
    views.dedup();
    views
        .into_iter()
        .filter_map(|view| {
            let r = rows
                .iter()
                .find(|r| r.view == view && r.method == "marching")?;
            let ms = |v: Option<f64>| v.map_or("-".to_owned(), |v| format!("{v:.2} ms"));
            let flip = |v: Option<f64>| v.map_or("-".to_owned(), |v| format!("{v:.4}"));
            let peer = match equal_flip(rows, view) {
                Some((steps, seed, relief)) => format!(
                    "the seed's way reaches its FLIP at {steps} steps: its props' layer \
                     {seed:.2} ms, {:.1}x relief's",
                    seed / relief
                ),
                None => match best_peer(rows, view) {
                    Some((steps, f, seed, relief)) => format!(
                        "the seed's way never reaches its FLIP: at best {f:.4} ({steps} steps, \
                         its props' layer {seed:.2} ms, {:.1}x relief's)",
                        seed / relief
                    ),
                    None => "the seed's way reaches its FLIP at no step budget measured".to_owned(),
                },
            };
            Some(format!(
                "props on {view}: {} in view, frame {} -> {} (scatter {}, shadows {}, march {}), \
                 FLIP {} (without props {}); {peer}",
                r.props[1],
                ms(r.frame_ms[0]),
                ms(r.frame_ms[1]),
                ms(r.scatter_ms),
                ms(r.shadows_ms),
                ms(r.march_ms),
                flip(r.flip[1]),
                flip(r.flip[0]),
            ))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(method: &str, peer: Option<u32>, march: f64, flip: f64) -> PropsRow {
        PropsRow {
            view: "v".into(),
            method: method.into(),
            peer_steps: peer,
            props: [10, 5],
            frame_ms: [Some(1.0), Some(1.5)],
            scatter_ms: Some(0.1),
            shadows_ms: peer.map_or(Some(0.1), |_| None),
            march_ms: Some(march),
            map_ms: None,
            flip: [Some(0.01), Some(flip)],
        }
    }

    #[test]
    fn the_seeds_way_is_compared_at_equal_flip_or_at_its_best() {
        // relief: layer 0.5 ms at FLIP 0.02; the seed's way reaches it at 100 steps.
        let mut rows = vec![
            row("marching", None, 0.3, 0.02),
            row("seed 50", Some(50), 2.0, 0.03),
            row("seed 100", Some(100), 4.9, 0.019),
            row("seed 200", Some(200), 9.9, 0.019),
        ];
        assert_eq!(equal_flip(&rows, "v"), Some((100, 5.0, 0.5)));
        let line = &summary(&rows)[0];
        assert!(line.contains("reaches its FLIP at 100 steps"), "{line}");
        assert!(line.contains("shadows 0.10 ms"), "{line}");
        // relief more accurate than every budget: its best, the fewest steps that give it.
        rows[0].flip[1] = Some(0.015);
        assert_eq!(equal_flip(&rows, "v"), None);
        let (steps, flip, seed, relief) = best_peer(&rows, "v").unwrap();
        assert_eq!((steps, flip), (100, 0.019));
        assert!((seed - 5.0).abs() < 1e-9 && (relief - 0.5).abs() < 1e-9);
        let line = &summary(&rows)[0];
        assert!(
            line.contains("never reaches its FLIP: at best 0.0190 (100 steps"),
            "{line}"
        );
    }
}
