//! The default method, chosen per device by measurement.
//!
//! relief draws with a mesh-based method by design. Which of them is fastest depends on the
//! GPU: on an H100, fragment work costs some 30x what the same arithmetic costs in compute,
//! so the visibility method and the hybrid (a raster pass that shades nothing, then compute)
//! beat the forward-shaded mesh; on a CPU rasteriser nothing says they do. So `relief render`
//! (`--method auto`, its default) draws a few frames of each [`Candidate`] of its world on
//! the device, and [`Choice::decide`] keeps the fastest. Every candidate draws at the forward
//! mesh's accuracy (within 0.0003 of its FLIP against the reference on the benchmarks' views,
//! `docs/results/landscape-frame.md`) or better; at one sample a pixel its edges are not
//! anti-aliased. Near a tie
//! the choice can differ from run to run: a reproducible image pins `--method`.
//!
//! This file is the decision; the frames are drawn by `gpu::headless::choose_method` (feature
//! `headless`).

use crate::gpu::timing::{Slot, Timings};
use crate::{Method, Raster, WorldKind};

/// A mesh-based method with its samples a pixel and its raster, as the choice of the default
/// measures it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Candidate {
    /// The method.
    pub method: Method,
    /// Samples a pixel: the host target's MSAA for the mesh (4), the method's own for the
    /// visibility method and the hybrid (4 or 1, [`crate::MethodConfig::samples`]).
    pub samples: u32,
    /// Where the visibility method rasterises ([`crate::MethodConfig::raster`]).
    pub raster: Raster,
}

impl Candidate {
    /// How a renderer draws it ([`crate::World::set_method`]).
    pub const fn config(self) -> crate::MethodConfig {
        crate::MethodConfig {
            method: self.method,
            samples: self.samples,
            raster: self.raster,
        }
    }

    /// relief's forward-shaded mesh into a 4x MSAA target: the default where nothing was
    /// measured.
    pub const MESH: Candidate = Candidate {
        method: Method::Mesh,
        samples: 4,
        raster: Raster::Hardware,
    };

    /// [`crate::MethodConfig::MARCHING`]: what `auto` draws, unmeasured, when props are on
    /// ([`Candidate::for_props`]).
    pub const MARCHING: Candidate = Candidate {
        method: crate::MethodConfig::MARCHING.method,
        samples: crate::MethodConfig::MARCHING.samples,
        raster: crate::MethodConfig::MARCHING.raster,
    };

    /// What `auto` draws without measuring: with props on, [`Candidate::MARCHING`], the one
    /// method that marches each pixel's props and their shadow (the nearest the reference);
    /// else `None` (measure the candidates).
    pub fn for_props(props: bool) -> Option<Candidate> {
        props.then_some(Candidate::MARCHING)
    }

    /// `method` at `samples` a pixel, rasterised by the GPU's rasteriser.
    pub const fn new(method: Method, samples: u32) -> Candidate {
        Candidate {
            method,
            samples,
            raster: Raster::Hardware,
        }
    }

    /// The candidates for `world`, in order of preference: the mesh first; a later one wins
    /// only by [`MARGIN`].
    ///
    /// Why these (the H100's benchmarks at 1920x1080, FLIP mean against the reference):
    /// - the tile: `visibility` at 4 samples (0.0438) and at 1 (0.0439) draw the mesh's
    ///   accuracy (0.0436); the differences are aliased edge pixels;
    /// - the endless world: `visibility` at 4 samples draws the mesh's (0.0091, 0.0230, 0.0401
    ///   on the horizon, ridge and oblique views against 0.0091, 0.0236, 0.0404), and at 1
    ///   sample too (0.0092, 0.0232, 0.0402); the hybrid at 1 sample is closer than the mesh on
    ///   all three (0.0079, 0.0161, 0.0239), so it comes before `visibility` at 1 sample and
    ///   keeps a tie. The hybrid at 4 samples is closer still, but never faster than at 1;
    /// - the visibility method and the hybrid at 1 sample rasterised in compute draw what the
    ///   GPU's rasteriser draws (tests/visibility.rs: on lavapipe no pixel of the tile's two views
    ///   differed by more than 8 levels, 0.008% of the endless world's; it allows 0.3%).
    pub fn all(world: WorldKind) -> &'static [Candidate] {
        const fn c(method: Method, samples: u32) -> Candidate {
            Candidate::new(method, samples)
        }
        const TILE: [Candidate; 4] = [
            Candidate::MESH,
            c(Method::Visibility, 4),
            c(Method::Visibility, 1),
            Candidate {
                raster: Raster::Compute,
                ..c(Method::Visibility, 1)
            },
        ];
        const ENDLESS: [Candidate; 6] = [
            Candidate::MESH,
            c(Method::Visibility, 4),
            c(Method::Hybrid, 1),
            Candidate {
                raster: Raster::Compute,
                ..c(Method::Hybrid, 1)
            },
            c(Method::Visibility, 1),
            Candidate {
                raster: Raster::Compute,
                ..c(Method::Visibility, 1)
            },
        ];
        match world {
            WorldKind::Tile => &TILE,
            WorldKind::Endless => &ENDLESS,
        }
    }

    /// The `relief render` flags that draw it.
    pub fn flags(&self) -> String {
        match (self.method, self.raster) {
            (Method::Mesh, _) => format!("--method {}", self.method),
            (m, Raster::Hardware) => format!("--method {m} --samples {}", self.samples),
            (m, r) => format!("--method {m} --samples {} --raster {r}", self.samples),
        }
    }
}

impl std::fmt::Display for Candidate {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let plural = if self.samples == 1 { "" } else { "s" };
        match (self.method, self.raster) {
            (Method::Mesh, _) => write!(f, "{}", self.method),
            (m, Raster::Hardware) => write!(f, "{m} at {} sample{plural} a pixel", self.samples),
            (m, Raster::Compute) => write!(
                f,
                "{m} at {} sample{plural} a pixel rasterised in compute",
                self.samples
            ),
        }
    }
}

/// How much faster a later [`Candidate`] must draw to replace an earlier one: the same frame
/// timed in two runs moves by 1-2% on the H100 (the benchmarks' re-runs), so a smaller lead
/// is noise, and the mesh (relief's design) keeps it.
pub const MARGIN: f64 = 0.05;

/// Why a [`Choice`] was made.
#[derive(Clone, Debug, PartialEq)]
pub enum Why {
    /// Each candidate's median draw time in milliseconds, over `frames` timed frames after a
    /// warm-up, at `size` pixels.
    Measured {
        /// Each candidate and its median draw, in [`Candidate::all`]'s order.
        ms: Vec<(Candidate, f64)>,
        /// Timed frames a candidate.
        frames: usize,
        /// The image the frames were drawn at.
        size: (u32, u32),
    },
    /// The device has no timestamp queries to measure with.
    NoTimestamps,
}

/// The method the default draws with, and why.
#[derive(Clone, Debug, PartialEq)]
pub struct Choice {
    /// What was chosen.
    pub candidate: Candidate,
    /// Why.
    pub why: Why,
}

impl Choice {
    /// The mesh, where nothing could be measured.
    pub fn unmeasured() -> Self {
        Self {
            candidate: Candidate::MESH,
            why: Why::NoTimestamps,
        }
    }

    /// The fastest of `ms` (each candidate's median draw, in order of preference), where a
    /// later candidate replaces the best so far only when [`MARGIN`] faster. The mesh where
    /// `ms` is empty or holds no finite time.
    pub fn decide(ms: Vec<(Candidate, f64)>, frames: usize, size: (u32, u32)) -> Self {
        let mut best: Option<(Candidate, f64)> = None;
        for &(c, t) in &ms {
            if !(t.is_finite() && t >= 0.0) {
                continue;
            }
            match best {
                Some((_, b)) if t >= b * (1.0 - MARGIN) => {}
                _ => best = Some((c, t)),
            }
        }
        match best {
            Some((candidate, _)) => Self {
                candidate,
                why: Why::Measured { ms, frames, size },
            },
            None => Self::unmeasured(),
        }
    }

    /// One line for people: which, and why (`device` names the GPU measured on).
    pub fn describe(&self, device: &str) -> String {
        let c = self.candidate;
        match &self.why {
            Why::NoTimestamps => format!(
                "method {c} ({}): {device} has no GPU timestamps to measure the methods by, so \
                 relief's mesh",
                c.flags()
            ),
            Why::Measured { ms, frames, size } => {
                let times: Vec<String> = ms
                    .iter()
                    .map(|(c, t)| {
                        if t.is_finite() {
                            format!("{c} {t:.3} ms")
                        } else {
                            format!("{c} not measured (the trial stops after 10 s)")
                        }
                    })
                    .collect();
                format!(
                    "method {c} ({}), the fastest draw measured on {device} at {}x{} (median of \
                     {frames} frames each, a method {:.0}% faster to replace one listed before \
                     it): {}",
                    c.flags(),
                    size.0,
                    size.1,
                    MARGIN * 100.0,
                    times.join(", ")
                )
            }
        }
    }
}

/// A frame's draw in milliseconds from its timings: the host's render pass or the pass that
/// wrote the frame without one ([`Slot::Present`]), and the visibility method's (or the
/// hybrid's) raster, clouds' image, shading and temporal resolve passes, the grass's scatter
/// before it and its blades' raster, the props' passes and the shafts' shadow-height map.
/// `None` where neither was timed.
pub fn draw_ms(t: &Timings) -> Option<f64> {
    let slots = [
        Slot::Render,
        Slot::Present,
        Slot::Raster,
        Slot::Clouds,
        Slot::Shade,
        Slot::Resolve,
        Slot::Grass,
        Slot::Blades,
        Slot::Props,
        Slot::PropShadows,
        Slot::March,
        Slot::AirShadow,
    ]
    .map(|s| t[s as usize]);
    t[Slot::Render as usize].or(t[Slot::Present as usize])?;
    Some(slots.iter().flatten().sum())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn auto_draws_the_marching_method_with_props() {
        assert_eq!(Candidate::for_props(false), None);
        let c = Candidate::for_props(true).unwrap();
        assert_eq!(c.config(), crate::MethodConfig::MARCHING);
        assert!(c.config().marches_props());
        assert!(!Candidate::MESH.config().marches_props());
        assert_eq!(
            c.to_string(),
            "visibility at 1 sample a pixel rasterised in compute"
        );
    }

    const V4: Candidate = Candidate::new(Method::Visibility, 4);
    const V1: Candidate = Candidate::new(Method::Visibility, 1);
    const V1C: Candidate = Candidate {
        raster: Raster::Compute,
        ..V1
    };

    #[test]
    fn a_draw_is_its_render_pass_or_its_present_and_the_passes_before() {
        let mut t: Timings = [None; Slot::ALL.len()];
        t[Slot::Bake as usize] = Some(5.0);
        assert_eq!(draw_ms(&t), None, "a frame that reached no target");
        t[Slot::Raster as usize] = Some(0.5);
        t[Slot::Shade as usize] = Some(0.25);
        t[Slot::Present as usize] = Some(0.125);
        assert_eq!(draw_ms(&t), Some(0.875), "the present, not the bake");
        t[Slot::Present as usize] = None;
        t[Slot::Render as usize] = Some(1.0);
        assert_eq!(draw_ms(&t), Some(1.75), "the render pass");
    }

    #[test]
    fn a_trial_cut_short_chooses_among_those_measured_and_says_which_were_not() {
        // A slow device: the trial stopped after the first two candidates.
        let c = Choice::decide(
            vec![(Candidate::MESH, 900.0), (V4, 800.0), (V1, f64::NAN)],
            5,
            (480, 270),
        );
        assert_eq!(c.candidate, V4);
        let line = c.describe("llvmpipe");
        assert!(
            line.contains(
                "visibility at 1 sample a pixel not measured (the trial stops after 10 s)"
            ),
            "{line}"
        );
        assert!(!line.contains("NaN"), "{line}");
    }

    #[test]
    fn the_fastest_wins_by_the_margin_and_the_mesh_keeps_a_tie() {
        // The H100's tile: visibility at 1 sample.
        let c = Choice::decide(
            vec![(Candidate::MESH, 3.41), (V4, 1.90), (V1, 1.11)],
            5,
            (1920, 1080),
        );
        assert_eq!(c.candidate, V1);
        let line = c.describe("GPU");
        assert!(line.contains("--method visibility --samples 1"), "{line}");
        assert!(line.contains("mesh 3.410 ms"), "{line}");
        // Within the margin the earlier candidate stays.
        let tie = Choice::decide(vec![(Candidate::MESH, 1.0), (V4, 0.97)], 5, (8, 8));
        assert_eq!(tie.candidate, Candidate::MESH);
        // A slower later one never wins; a faster middle one does.
        let mid = Choice::decide(
            vec![(Candidate::MESH, 1.0), (V4, 0.5), (V1, 0.49)],
            5,
            (8, 8),
        );
        assert_eq!(mid.candidate, V4);
        // The compute raster is named as such, with the flags that draw it.
        let c = Choice::decide(vec![(V1, 1.1), (V1C, 0.6)], 5, (8, 8));
        assert_eq!(c.candidate, V1C);
        let line = c.describe("GPU");
        assert!(
            line.contains("rasterised in compute")
                && line.contains("--method visibility --samples 1 --raster compute"),
            "{line}"
        );
    }

    #[test]
    fn nothing_measured_is_the_mesh_said_in_words() {
        let none = Choice::decide(vec![(V4, f64::NAN)], 5, (8, 8));
        assert_eq!(none.candidate, Candidate::MESH);
        let line = Choice::unmeasured().describe("SwiftShader");
        assert!(line.contains("no GPU timestamps"), "{line}");
        assert!(line.contains("--method mesh"), "{line}");
    }

    #[test]
    fn every_candidate_is_a_mesh_method_its_world_draws() {
        for world in [WorldKind::Tile, WorldKind::Endless] {
            let all = Candidate::all(world);
            assert_eq!(all[0], Candidate::MESH);
            for c in all {
                assert!(c.method.is_mesh(), "{c}");
                let drawn = match world {
                    WorldKind::Tile => c.method.in_tile(),
                    WorldKind::Endless => c.method.in_world(),
                };
                assert!(drawn, "{c} in {world:?}");
                assert!(matches!(c.samples, 1 | 4), "{c}");
                assert_eq!(c.raster.refusal(c.samples), None, "{c}");
            }
        }
    }
}
