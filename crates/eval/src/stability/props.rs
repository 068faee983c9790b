//! The props' axis (`relief stability --axis props`), on the props' f64 twin
//! ([`relief::props::sdf`]): where marching a prop's field fails, against the settings that
//! decide it. No GPU: the twin marches as the GPU's march does (`wgsl/props_march.wgsl`: each
//! step the distance over the Lipschitz constant, a hit under half a pixel's footprint, a
//! budget of steps), and the truth is a march of steps a hundred times finer that looks for the
//! field's first change of sign.
//!
//! - **lipschitz**: a sphere roughened by value noise of amplitude a and frequency f, marched
//!   with relief's step (the distance over its Lipschitz constant, 1 + 4 a f) and with the
//!   distance alone (as if the field were a distance): the share of rays that step past the
//!   surface, against a f. And two spheres joined by a smooth union of radius k, marched with
//!   the distance alone (the polynomial smooth minimum keeps the bound: relief's step), against
//!   k.
//! - **budget**: rays grazing a wall (a box 4 m long, 2 m high and 0.4 m thick) from a
//!   distance, within 0.2 to 1.7 degrees of its faces, marched from where they enter its box
//!   with a budget of steps, a step floor and the GPU's hit rule: the share that runs out of
//!   steps before it hits or leaves, and of those the share not nearing the wall (seen
//!   through: the GPU takes a ray out of steps still nearing a surface as meeting it), against
//!   the distance, for budgets and floors around relief's ([`relief::gpu::props::STEPS`]).
//! - **thin**: a plate seen from 10 m at up to 80 degrees, its thickness a few hit thresholds:
//!   the share of rays that step through it, against the thickness, for step floors.
//! - **cutoff**: a prop 2 m tall seen from a receding eye (1 m a frame): the largest change from
//!   one frame to the next in how much of its height on screen the cut-off hides, with relief's
//!   sinking (whole above its cut-off, sunk over the halving below it) and with a hard cut at
//!   the cut-off, against the cut-off.
//! - **banding**: a ball's soft shadow on the ground under a sun 30 degrees up: the largest
//!   error in the sun's share at 200 points across its penumbra against the truth (the least of
//!   8 distance over range along a march of 1 mm steps), against a shadow ray's least step, for
//!   relief's march (the distance at each step) and for an estimate of the nearest point
//!   between two steps.
//!
//! relief's defaults sit on the safe side of each: no ray steps past a surface, the budget caps
//! few rays, and no prop jumps by a pixel (tests in this file pin the boundaries).

use relief::props::{sdf, Combine, Kind, Node, Shape, Tape, Transform};

/// One point of a sweep: the sweep, the variant, the setting and what it measured.
#[derive(Clone, Debug, PartialEq)]
pub struct PropsRow {
    /// `lipschitz`, `smooth`, `budget`, `thin`, `cutoff` or `banding`.
    pub sweep: &'static str,
    /// What is measured (relief's way or another).
    pub variant: String,
    /// The setting swept: a f, k (metres), the distance (metres), the cut-off (pixels) or a
    /// shadow ray's least step (metres).
    pub x: f64,
    /// The share of rays that failed (lipschitz, smooth, budget), the largest pop in pixels
    /// (cutoff) or the largest error in the sun's share (banding).
    pub value: f64,
    /// Rays cast (or frames seen).
    pub samples: usize,
}

/// The image's pixels a unit of tan(angle): 1080 rows under a 50 degree field of view.
pub fn pixels() -> f64 {
    1080.0 / (2.0 * 25f64.to_radians().tan())
}

/// The GPU's hit threshold at distance `t`: half a pixel's footprint, at least 1 mm.
fn hit_eps(t: f64) -> f64 {
    (0.5 * t / pixels()).max(1e-3)
}

/// How a view march ends: a hit where the distance fell under the threshold, through, or out
/// of steps (nearing a surface or not).
#[derive(Clone, Copy, Debug, PartialEq)]
enum Traced {
    Hit,
    Through,
    Nearing,
    Capped,
}

/// The GPU's view march over [enter, leave] (`trace` in `wgsl/props_march.wgsl`): steps of the
/// distance over the Lipschitz constant, at least `floor` times the hit threshold, a hit under
/// it.
fn trace(
    tape: &Tape,
    (o, d): ([f64; 3], [f64; 3]),
    (enter, leave): (f64, f64),
    (steps, floor): (u32, f64),
) -> Traced {
    let mut t = enter;
    let (mut before, mut now) = (f64::INFINITY, f64::INFINITY);
    for _ in 0..steps {
        if t > leave {
            return Traced::Through;
        }
        let dist = sdf::distance(tape, along(o, d, t), 0).0;
        let eps = hit_eps(t);
        if dist < eps {
            return Traced::Hit;
        }
        (before, now) = (now, dist);
        t += (dist / tape.lipschitz).max(floor * eps);
    }
    if t > leave {
        Traced::Through
    } else if now < before {
        Traced::Nearing
    } else {
        Traced::Capped
    }
}

/// A setting given in f32, as written (to six decimals).
fn round6(v: f64) -> f64 {
    (v * 1e6).round() / 1e6
}

fn tape_of(root: Node) -> Tape {
    let kind = Kind {
        name: "probe".into(),
        root,
        weight: 1.0,
        scale: (1.0, 1.0),
        on_rock: true,
    };
    kind.compile(1).expect("the probes are valid kinds")
}

fn sphere(radius: f32, at: [f32; 3]) -> Node {
    Node::Shape {
        shape: Shape::Sphere { radius },
        transform: Transform::at(at),
        material: 0,
    }
}

/// A deterministic stream of numbers in [0, 1).
struct Stream(u32);

impl Stream {
    fn next(&mut self) -> f64 {
        self.0 = relief::noise::pcg(self.0);
        f64::from(self.0 >> 8) / 16_777_216.0
    }

    /// A unit vector, uniform over the sphere.
    fn direction(&mut self) -> [f64; 3] {
        let z = 2.0 * self.next() - 1.0;
        let a = std::f64::consts::TAU * self.next();
        let r = (1.0 - z * z).sqrt();
        [r * a.cos(), z, r * a.sin()]
    }
}

fn along(o: [f64; 3], d: [f64; 3], t: f64) -> [f64; 3] {
    [o[0] + d[0] * t, o[1] + d[1] * t, o[2] + d[2] * t]
}

fn unit(v: [f64; 3]) -> [f64; 3] {
    let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    v.map(|c| c / l)
}

/// The first change of sign of the field along the ray within `reach`, by steps of `step`
/// (then halved down to a micrometre): the truth.
fn first_crossing(tape: &Tape, (o, d): ([f64; 3], [f64; 3]), reach: f64, step: f64) -> Option<f64> {
    let f = |t: f64| sdf::distance(tape, along(o, d, t), 0).0;
    let mut t = 0.0;
    while t < reach {
        if f(t + step) < 0.0 {
            let (mut lo, mut hi) = (t, t + step);
            while hi - lo > 1e-6 {
                let mid = 0.5 * (lo + hi);
                if f(mid) < 0.0 {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            return Some(lo);
        }
        t += step;
    }
    None
}

/// A march's failures over `rays` rays from 4 m out at points within 1.3 m of the origin, for
/// each of `lipschitz`: the share whose hit lies past the truth's first crossing (or that miss
/// a surface the truth meets), stepping by the distance over it.
fn overstepped(tape: &Tape, lipschitz: &[f64], rays: usize, seed: u32) -> Vec<f64> {
    let mut s = Stream(seed);
    let mut failed = vec![0usize; lipschitz.len()];
    for _ in 0..rays {
        let o = s.direction().map(|c| 4.0 * c);
        let aim = s.direction().map(|c| 1.3 * c * s.next());
        let d = unit([aim[0] - o[0], aim[1] - o[1], aim[2] - o[2]]);
        let truth = first_crossing(tape, (o, d), 6.0, 2e-3);
        for (count, &l) in failed.iter_mut().zip(lipschitz) {
            let stepped = Tape {
                lipschitz: l,
                ..tape.clone()
            };
            let got = sdf::march(&stepped, (o, d), 0, 6.0, 1e-4, 4000);
            let bad = match (truth, got) {
                (Some(t), Some(g)) => g > t + 1e-3,
                (Some(_), None) => true,
                _ => false,
            };
            *count += usize::from(bad);
        }
    }
    failed.iter().map(|&f| f as f64 / rays as f64).collect()
}

/// The lipschitz sweep: a sphere of radius 1 roughened by noise of amplitude 0.1 m at
/// `frequencies`, and two spheres of radius 1 two and a half metres apart joined by smooth
/// unions of radius `radii`.
pub fn lipschitz(frequencies: &[f32], radii: &[f32], rays: usize) -> Vec<PropsRow> {
    let mut rows = Vec::new();
    let amplitude = 0.1f32;
    for &frequency in frequencies {
        let tape = tape_of(Node::Displace {
            amplitude,
            frequency,
            child: Box::new(sphere(1.0, [0.0; 3])),
        });
        let x = round6(f64::from(amplitude * frequency));
        let failed = overstepped(
            &tape,
            &[tape.lipschitz, 1.0],
            rays,
            0x11 ^ frequency.to_bits(),
        );
        for (variant, value) in ["relief: distance / Lipschitz", "the distance alone"]
            .into_iter()
            .zip(failed)
        {
            rows.push(PropsRow {
                sweep: "lipschitz",
                variant: variant.into(),
                x,
                value,
                samples: rays,
            });
        }
    }
    for &k in radii {
        let tape = tape_of(Node::Combine {
            op: Combine::Union,
            smooth: Some(k),
            children: vec![
                sphere(1.0, [-1.25, 0.0, 0.0]),
                sphere(1.0, [1.25, 0.0, 0.0]),
            ],
        });
        rows.push(PropsRow {
            sweep: "smooth",
            variant: format!("relief: distance / {}", tape.lipschitz),
            x: round6(f64::from(k)),
            value: overstepped(&tape, &[tape.lipschitz], rays, 0x22 ^ k.to_bits())[0],
            samples: rays,
        });
    }
    rows
}

/// The wall of the budget sweep: 4 m long (x), 2 m high, 0.4 m thick, standing on y = 0.
fn wall() -> Tape {
    tape_of(Node::Shape {
        shape: Shape::Box {
            half: [2.0, 1.0, 0.2],
        },
        transform: Transform::at([0.0, 1.0, 0.0]),
        material: 0,
    })
}

/// Where the ray meets the box [lo, hi]: entry and exit, or `None`.
fn slab(o: [f64; 3], d: [f64; 3], lo: [f64; 3], hi: [f64; 3]) -> Option<(f64, f64)> {
    let (mut near, mut far) = (0.0f64, f64::INFINITY);
    for a in 0..3 {
        let (t0, t1) = ((lo[a] - o[a]) / d[a], (hi[a] - o[a]) / d[a]);
        near = near.max(t0.min(t1));
        far = far.min(t0.max(t1));
    }
    (near <= far).then_some((near, far))
}

/// The budget sweep: rays from `distances` metres towards the wall, within about a degree of
/// its long faces, marched with the GPU's hit rule from where they enter its box: for each
/// budget of steps and step floor (times the hit threshold), the share that runs out of steps,
/// and the share of those still moving away from the wall (which the GPU's march sees through;
/// one still nearing it takes it as met).
pub fn budget(distances: &[f64], settings: &[(u32, f64)], rays: usize) -> Vec<PropsRow> {
    let tape = wall();
    // The box the GPU's march enters a prop by: its radius about the vertical each way (it
    // turns), its heights.
    let r = tape.radius();
    let [lo, hi] = tape.bounds;
    let (lo, hi) = ([-r, lo[1], -r], [r, hi[1], r]);
    let mut rows = Vec::new();
    for &distance in distances {
        let mut s = Stream(0x33 ^ distance.to_bits() as u32);
        let mut capped = vec![[0usize; 2]; settings.len()];
        for _ in 0..rays {
            // From along the wall's length, a little off its face, aimed at a point near it.
            let side = if s.next() < 0.5 { -1.0 } else { 1.0 };
            let angle = (0.2 + 1.5 * s.next()).to_radians();
            let o = [
                -2.0 - distance * angle.cos(),
                0.2 + 1.6 * s.next(),
                side * (0.2 + distance * angle.sin()),
            ];
            let aim = [-1.9 + 3.8 * s.next(), 0.1 + 1.8 * s.next(), side * 0.2];
            let d = unit([aim[0] - o[0], aim[1] - o[1], aim[2] - o[2]]);
            let Some(span) = slab(o, d, lo, hi) else {
                continue;
            };
            for (count, &setting) in capped.iter_mut().zip(settings) {
                let end = trace(&tape, (o, d), span, setting);
                count[0] += usize::from(matches!(end, Traced::Nearing | Traced::Capped));
                count[1] += usize::from(end == Traced::Capped);
            }
        }
        for (&(steps, floor), count) in settings.iter().zip(&capped) {
            for (what, n) in [("out of steps", count[0]), ("seen through", count[1])] {
                rows.push(PropsRow {
                    sweep: "budget",
                    variant: format!("{}: {what}", setting_name(steps, floor)),
                    x: distance,
                    value: n as f64 / rays as f64,
                    samples: rays,
                });
            }
        }
    }
    rows
}

fn setting_name(steps: u32, floor: f64) -> String {
    format!("{steps} steps, floor {floor} x threshold")
}

/// The thin sweep: a plate 2 m square and `thickness` thick (its thickness given as multiples
/// of the hit threshold 10 m away) seen from 10 m at up to 80 degrees from its normal: for
/// each step floor, the share of the rays the truth sees hit that pass through it.
pub fn thin(thickness: &[f64], floors: &[f64], rays: usize) -> Vec<PropsRow> {
    let distance = 10.0;
    let mut rows = Vec::new();
    for &w in thickness {
        let half = 0.5 * w * hit_eps(distance);
        let tape = tape_of(Node::Shape {
            shape: Shape::Box {
                half: [1.0, 1.0, half as f32],
            },
            transform: Transform::at([0.0, 1.5, 0.0]),
            material: 0,
        });
        let [lo, hi] = tape.bounds;
        let mut s = Stream(0x44 ^ w.to_bits() as u32);
        let (mut seen, mut through) = (0usize, vec![0usize; floors.len()]);
        for _ in 0..rays {
            let tilt = (80.0 * s.next()).to_radians();
            let turn = std::f64::consts::TAU * s.next();
            let o = [
                distance * tilt.sin() * turn.cos(),
                1.5 + distance * tilt.sin() * turn.sin(),
                distance * tilt.cos(),
            ];
            let aim = [1.8 * s.next() - 0.9, 0.6 + 1.8 * s.next(), 0.0];
            let d = unit([aim[0] - o[0], aim[1] - o[1], aim[2] - o[2]]);
            let Some(span) = slab(o, d, lo, hi) else {
                continue;
            };
            // The truth: the plate's slab crossed inside its square.
            let p = along(o, d, span.0);
            if p[0].abs() > 1.0 || (p[1] - 1.5).abs() > 1.0 {
                continue;
            }
            seen += 1;
            for (count, &floor) in through.iter_mut().zip(floors) {
                let got = trace(&tape, (o, d), (span.0 - 0.5, span.1 + 0.5), (96, floor));
                *count += usize::from(matches!(got, Traced::Through | Traced::Capped));
            }
        }
        for (&floor, &count) in floors.iter().zip(&through) {
            rows.push(PropsRow {
                sweep: "thin",
                variant: format!("floor {floor} x threshold"),
                x: w,
                value: count as f64 / seen.max(1) as f64,
                samples: seen,
            });
        }
    }
    rows
}

/// A prop `top` metres tall `distance` metres away: its height on screen, pixels, with
/// relief's sinking at a cut-off of `cutoff` pixels (`sink`), or cut there.
pub fn shown_height(top: f64, distance: f64, cutoff: f64, sink: bool) -> f64 {
    let px = top * pixels() / distance;
    if sink {
        // wgsl/props_scatter.wgsl: whole above the cut-off, sunk over the halving below it.
        let shown = (2.0 * px / cutoff - 1.0).clamp(0.0, 1.0);
        px * shown
    } else if px >= cutoff {
        px
    } else {
        0.0
    }
}

/// The cutoff sweep: the largest change from one frame to the next in the pixels of a 2 m
/// prop's height the cut-off hides, as the eye recedes 1 m a frame from 10 m to 4 km, with
/// relief's sinking and with a hard cut, at each of `cutoffs` pixels.
pub fn cutoff(cutoffs: &[f64]) -> Vec<PropsRow> {
    let mut rows = Vec::new();
    for &c in cutoffs {
        for (variant, sink) in [("relief: sunk below the cut-off", true), ("cut", false)] {
            let frames = 4000;
            // What the cut-off hides, beyond perspective's own shrinking.
            let hidden = |f: u32| {
                let d = f64::from(f);
                shown_height(2.0, d, c, false).max(2.0 * pixels() / d)
                    - shown_height(2.0, d, c, sink)
            };
            let jump = (10..frames)
                .map(|f| (hidden(f + 1) - hidden(f)).abs())
                .fold(0.0, f64::max);
            rows.push(PropsRow {
                sweep: "cutoff",
                variant: variant.into(),
                x: c,
                value: jump,
                samples: frames as usize,
            });
        }
    }
    rows
}

/// The props' soft shadow's penumbra (`wgsl/props_march.wgsl`): a shadow ray's share of the
/// sun is the least of 8 times its distance to the props over how far it has gone.
const SHADOW_SOFTNESS: f64 = 8.0;
/// relief's least step of a shadow ray, metres (`SHADOW_STEP` in `wgsl/props_march.wgsl`).
pub const SHADOW_STEP: f64 = 0.04;

/// The sun's share at the ground point `o` under a ball of radius 1 m whose centre is 1.5 m
/// up at the origin, towards the sun `l`: by the GPU's shadow march with a least step of
/// `floor` metres (`nearest`: also where between two steps the ray passed nearest the ball,
/// from the circle where their spheres meet; relief reads the distance at each step alone), or
/// the truth (`None`: the least of the ratio over a march of 1 mm steps).
fn ball_shadow(o: [f64; 3], l: [f64; 3], how: Option<(f64, bool)>) -> f64 {
    let d = |t: f64| {
        let p = along(o, l, t);
        (p[0] * p[0] + (p[1] - 1.5) * (p[1] - 1.5) + p[2] * p[2]).sqrt() - 1.0
    };
    let reach = 20.0;
    let Some((floor, nearest)) = how else {
        let mut share = 1.0f64;
        let mut t = 1e-3;
        while t < reach {
            share = share.min(SHADOW_SOFTNESS * d(t).max(0.0) / t);
            t += 1e-3;
        }
        return share.clamp(0.0, 1.0);
    };
    let (mut share, mut last, mut stride, mut t) = (1.0f64, 1e10, 0.0, 0.0);
    for _ in 0..relief::gpu::props::STEPS {
        if t > reach {
            break;
        }
        let h = d(t).max(0.0);
        share = share.min(SHADOW_SOFTNESS * h / t.max(1e-3));
        // The circle where this step's sphere meets the last one's: y back along the ray from
        // here, where it lies between the two steps.
        if nearest && last < 1e9 && stride > 0.0 {
            let y = (h * h - last * last + stride * stride) / (2.0 * stride);
            if y > 0.0 && y < stride {
                let near = (h * h - y * y).max(0.0).sqrt();
                share = share.min(SHADOW_SOFTNESS * near / (t - y).max(1e-3));
            }
        }
        last = h.max(1e-6);
        if share < 0.01 {
            return 0.0;
        }
        stride = d(t).max(floor);
        t += stride;
    }
    share.clamp(0.0, 1.0)
}

/// The banding sweep: a ball's soft shadow on the ground under a sun 30 degrees up, at 200
/// points on two lines across its penumbra: the largest difference of the sun's share from the
/// truth, for each of `floors` (a shadow ray's least step, metres), relief's way (the distance
/// at each step) and an estimate of where between two steps the ray passed nearest (from the
/// circle where their spheres meet: what relief did before this sweep measured it).
pub fn banding(floors: &[f64]) -> Vec<PropsRow> {
    let e = 30f64.to_radians();
    let l = [e.cos(), e.sin(), 0.0];
    // The centre's shadow lies 1.5 / tan(30 degrees) from under the ball.
    let c = -1.5 / e.tan();
    let points: Vec<[f64; 3]> = (0..100)
        .flat_map(|i| {
            let s = -3.0 + 6.0 * f64::from(i) / 99.0;
            [[c, 0.02, s], [c + 2.0 * s, 0.02, 0.4]]
        })
        .collect();
    let truth: Vec<f64> = points.iter().map(|&o| ball_shadow(o, l, None)).collect();
    let mut rows = Vec::new();
    for &floor in floors {
        for (variant, nearest) in [
            ("relief: the distance at each step", false),
            ("nearest between two steps", true),
        ] {
            let worst = points
                .iter()
                .zip(&truth)
                .map(|(&o, &t)| (ball_shadow(o, l, Some((floor, nearest))) - t).abs())
                .fold(0.0, f64::max);
            rows.push(PropsRow {
                sweep: "banding",
                variant: variant.into(),
                x: floor,
                value: worst,
                samples: points.len(),
            });
        }
    }
    rows
}

/// The whole axis at its settings (`quick`: fewer rays).
pub fn props(quick: bool) -> Vec<PropsRow> {
    let rays = if quick { 200 } else { 1000 };
    let mut rows = lipschitz(
        &[0.5, 1.0, 2.0, 4.0, 8.0, 16.0],
        &[0.05, 0.2, 0.5, 1.0, 2.0],
        rays,
    );
    let steps = relief::gpu::props::STEPS;
    rows.extend(budget(
        &[2.0, 5.0, 10.0, 20.0, 50.0, 100.0, 200.0, 400.0],
        &[
            (steps / 2, 1.0),
            (steps, 1.0),
            (steps * 2, 1.0),
            (steps, 2.0),
            (steps, 4.0),
        ],
        rays,
    ));
    rows.extend(thin(
        &[0.25, 0.5, 1.0, 2.0, 4.0, 8.0],
        &[1.0, 2.0, 4.0, 8.0],
        rays,
    ));
    rows.extend(cutoff(&[1.0, 1.5, 2.0, 4.0, 8.0, 16.0]));
    rows.extend(banding(&[0.01, SHADOW_STEP, 0.16, 0.64, 2.56]));
    rows
}

/// The rows as a table for the terminal.
pub fn props_table(rows: &[PropsRow]) -> String {
    let mut out = format!(
        "{:<10} {:<32} {:>9} {:>10} {:>7}\n",
        "sweep", "variant", "setting", "value", "samples"
    );
    for r in rows {
        out += &format!(
            "{:<10} {:<32} {:>9} {:>10.4} {:>7}\n",
            r.sweep, r.variant, r.x, r.value, r.samples
        );
    }
    out
}

/// The rows as CSV.
pub fn props_csv(rows: &[PropsRow]) -> String {
    let mut out = String::from("sweep,variant,setting,value,samples\n");
    for r in rows {
        out += &format!(
            "{},{},{},{},{}\n",
            r.sweep, r.variant, r.x, r.value, r.samples
        );
    }
    out
}

/// The charts: one a sweep (`<stem>-<sweep>.png` and `.svg`).
pub fn props_chart(rows: &[PropsRow], stem: &std::path::Path) -> relief::error::Result<()> {
    let sweeps = [
        (
            "lipschitz",
            "amplitude x frequency (log)",
            "rays stepped past the surface",
        ),
        (
            "smooth",
            "smooth union's radius, m (log)",
            "rays stepped past the surface",
        ),
        ("budget", "distance, m (log)", "rays out of steps"),
        (
            "thin",
            "thickness, hit thresholds (log)",
            "rays through the plate",
        ),
        (
            "cutoff",
            "cut-off, pixels (log)",
            "largest pop a frame, pixels",
        ),
        (
            "banding",
            "a shadow ray's least step, m (log)",
            "largest error in the sun's share",
        ),
    ];
    for (sweep, x_desc, y_desc) in sweeps {
        let mine: Vec<&PropsRow> = rows.iter().filter(|r| r.sweep == sweep).collect();
        if mine.is_empty() {
            continue;
        }
        let name = format!(
            "{}-{sweep}",
            stem.file_name().and_then(|n| n.to_str()).unwrap_or("props")
        );
        let title = format!("relief: props, {sweep} (CPU f64 twin)");
        crate::chart::write_chart(
            &stem.with_file_name(name),
            |b| draw(b, &mine, (&title, x_desc, y_desc)),
            |b| draw(b, &mine, (&title, x_desc, y_desc)),
        )?;
    }
    Ok(())
}

fn draw<DB: plotters::prelude::DrawingBackend>(
    backend: DB,
    rows: &[&PropsRow],
    (title, x_desc, y_desc): (&str, &str, &str),
) -> std::result::Result<(), String>
where
    DB::ErrorType: 'static,
{
    use plotters::prelude::*;
    let root = backend.into_drawing_area();
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let (x0, x1) = rows.iter().fold((f64::INFINITY, 0.0f64), |(a, b), r| {
        (a.min(r.x), b.max(r.x))
    });
    let top = rows.iter().map(|r| r.value).fold(0.0, f64::max).max(1e-3) * 1.1;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 20))
        .margin(16)
        .x_label_area_size(48)
        .y_label_area_size(72)
        .build_cartesian_2d((x0 * 0.8..x1 * 1.25).log_scale(), 0.0..top)
        .map_err(|e| e.to_string())?;
    chart
        .configure_mesh()
        .x_label_formatter(&|v| crate::chart::tick_label(*v))
        .x_desc(x_desc)
        .y_desc(y_desc)
        .label_style(("sans-serif", 15))
        .axis_desc_style(("sans-serif", 15))
        .draw()
        .map_err(|e| e.to_string())?;
    let mut variants: Vec<&str> = Vec::new();
    for r in rows {
        if !variants.contains(&r.variant.as_str()) {
            variants.push(&r.variant);
        }
    }
    for (i, variant) in variants.iter().enumerate() {
        let color = Palette99::pick(i).to_rgba();
        let line: Vec<(f64, f64)> = rows
            .iter()
            .filter(|r| r.variant == *variant)
            .map(|r| (r.x, r.value))
            .collect();
        chart
            .draw_series(LineSeries::new(line.clone(), color.stroke_width(2)))
            .map_err(|e| e.to_string())?
            .label(*variant)
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color));
        chart
            .draw_series(line.iter().map(|&p| Circle::new(p, 4, color.filled())))
            .map_err(|e| e.to_string())?;
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(("sans-serif", 15))
        .draw()
        .map_err(|e| e.to_string())?;
    root.present().map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn relief_steps_never_step_past_a_surface_and_the_distance_alone_does() {
        let rows = lipschitz(&[1.0, 16.0], &[0.05, 2.0], 150);
        for r in rows.iter().filter(|r| r.variant.starts_with("relief")) {
            assert_eq!(r.value, 0.0, "{r:?}");
        }
        // The boundary: rough enough, a march that takes the field for a distance fails.
        let naive = |x: f64| {
            rows.iter()
                .find(|r| r.variant == "the distance alone" && (r.x - x).abs() < 1e-6)
                .unwrap()
                .value
        };
        assert!(naive(1.6) > 0.02, "{}", naive(1.6));
    }

    #[test]
    fn the_budget_runs_out_only_for_rays_grazing_a_wall_nearby() {
        let steps = relief::gpu::props::STEPS;
        let rows = budget(&[2.0, 50.0], &[(steps, 1.0)], 300);
        let at = |d: f64, what: &str| {
            rows.iter()
                .find(|r| r.x == d && r.variant.ends_with(what))
                .unwrap()
                .value
        };
        // The boundary: from 50 m no grazing ray runs out of steps; from 2 m most do, and
        // all of those still near the wall, which the march takes as met.
        assert!(
            at(50.0, "out of steps") <= 0.01,
            "{}",
            at(50.0, "out of steps")
        );
        assert!(at(2.0, "out of steps") > 0.5, "{}", at(2.0, "out of steps"));
        assert!(
            at(2.0, "seen through") <= 0.01,
            "{}",
            at(2.0, "seen through")
        );
    }

    #[test]
    fn the_step_floor_keeps_every_plate_half_a_threshold_thick() {
        let rows = thin(&[0.5, 4.0], &[1.0], 300);
        for r in &rows {
            assert_eq!(r.value, 0.0, "{r:?}");
            assert!(r.samples > 100, "{r:?}");
        }
    }

    #[test]
    fn relief_soft_shadows_stay_within_3_percent_of_the_sun_to_16_cm_steps() {
        let rows = banding(&[SHADOW_STEP, 0.16, 0.64, 2.56]);
        let at = |floor: f64, relief: bool| {
            rows.iter()
                .find(|r| r.x == floor && r.variant.starts_with("relief") == relief)
                .unwrap()
                .value
        };
        // relief's default floor, and the boundary: a floor past the distance to the ball
        // steps into it and shadows the penumbra whole.
        assert!(at(SHADOW_STEP, true) < 0.03, "{}", at(SHADOW_STEP, true));
        assert!(at(0.16, true) < 0.03, "{}", at(0.16, true));
        assert!(at(2.56, true) > 0.5, "{}", at(2.56, true));
        // The estimate between steps darkens the penumbra more at every floor.
        for floor in [SHADOW_STEP, 0.16] {
            assert!(at(floor, false) > 2.0 * at(floor, true), "{floor}");
        }
    }

    #[test]
    fn a_sinking_prop_never_jumps_a_pixel_and_a_cut_one_does() {
        for r in cutoff(&[1.5, 8.0]) {
            if r.variant.starts_with("relief") {
                assert!(r.value < 1.0, "{r:?}");
            } else {
                assert!(r.value >= 0.5 * r.x, "{r:?}");
            }
        }
    }
}
