//! What the window tells its user: the stats of a frame, the [`Report`] a front end implements
//! (the terminal's prints lines; the page's fills its readout).

use super::*;

/// Frame statistics reported to the front end.
#[derive(Clone, Copy, Debug, Default)]
pub struct Stats {
    /// Frames drawn so far.
    pub frames: u64,
    /// Frames per second over the last half second of drawing.
    pub fps: f64,
    /// Latest GPU pass times, when the adapter has timestamps, and the frame they measured.
    pub gpu: Option<(u64, Timings)>,
    /// Whether this adapter can time passes at all.
    pub timestamps: bool,
    /// Nothing changed for [`IDLE_AFTER`]: no frames are being drawn.
    pub idle: bool,
    /// How the last frame was drawn.
    pub method: relief::Method,
    /// The visibility method's and the hybrid's samples a pixel and raster in the last frame.
    pub samples: u32,
    /// ... and where they rasterised.
    pub raster: relief::Raster,
    /// CPU time of a frame on the app's side (input, animation, recording and submitting the
    /// GPU work; not the GPU's time, nor the wait for the surface's next texture and its
    /// present), mean over the frames of the last half second, ms.
    pub cpu_ms: Option<f64>,
    /// While the endless world's levels or their light are still being baked (over the
    /// per-frame budgets, coarse levels first), how far along, in percent.
    pub baking: Option<u32>,
}

/// What the app tells its user, one way per platform: native prints lines, the page writes
/// into its DOM.
pub trait Report {
    /// The readout changed (frame rate, GPU times, idle).
    fn stats(&mut self, describe: &str, stats: &Stats, fresh_timings: bool);
    /// A one-line notice (a recovered device).
    fn notice(&mut self, message: &str);
    /// A one-line error the app keeps running after.
    fn warn(&mut self, message: &str);
    /// A change the user asked for took effect: a previous refusal no longer applies.
    fn accepted(&mut self) {}
    /// The parameters changed (the page updates its URL and controls).
    fn options(&mut self, _options: &AppOptions) {}
    /// The method was chosen (`relief --method auto`): `choice`, and `line`, which says why.
    fn chosen(&mut self, _choice: &relief::choice::Choice, _line: &str) {}
    /// The first frame waits for the GPU to build the pipelines (the page, whose GPU builds
    /// them after the calls that ask for them return).
    fn preparing(&mut self) {}
    /// A frame was presented.
    fn frame(&mut self, _stats: &Stats) {}
    /// A bake that took several frames is done: `ms` and `frames` since it began, and the
    /// longest time between two of its frames (ms).
    fn baked(&mut self, _ms: f64, _frames: u64, _longest_ms: f64) {}
    /// The app stopped on an error.
    fn fatal(&mut self, message: &str);
}

/// The native window's report: with `--timings`, one line per new GPU measurement, a line
/// when the window goes idle, and a summary at exit; warnings and errors as one line each on
/// stderr.
#[cfg(not(target_arch = "wasm32"))]
pub struct Terminal {
    /// Whether `--timings` was given.
    pub timings: bool,
}

#[cfg(not(target_arch = "wasm32"))]
impl Terminal {
    /// A report printing timings if asked.
    pub fn new(timings: bool) -> Self {
        Self { timings }
    }
}

#[cfg(not(target_arch = "wasm32"))]
impl Report for Terminal {
    fn stats(&mut self, describe: &str, stats: &Stats, fresh_timings: bool) {
        if !self.timings {
            return;
        }
        if fresh_timings {
            if let Some((frame, t)) = stats.gpu {
                // The method is named where it is not the mesh, with its samples and raster
                // where it has them.
                let method = match stats.method {
                    relief::Method::Mesh => String::new(),
                    m @ (relief::Method::Visibility | relief::Method::Hybrid) => {
                        let c = relief::choice::Candidate {
                            method: m,
                            samples: stats.samples,
                            raster: stats.raster,
                        };
                        format!(", {c}")
                    }
                    m => format!(", {m}"),
                };
                // The app's own CPU time a frame, beside the GPU's passes.
                let cpu = stats
                    .cpu_ms
                    .map_or(String::new(), |ms| format!(" · cpu {ms:.2} ms/frame"));
                println!(
                    "timings on {describe} (frame {frame}{method}): {}{cpu}",
                    format_timings(&t)
                );
            }
        } else if stats.idle {
            println!(
                "idle after frame {}: nothing changes, so nothing is drawn",
                stats.frames
            );
        }
    }
    fn notice(&mut self, message: &str) {
        eprintln!("{}", one_line(message));
    }
    fn warn(&mut self, message: &str) {
        eprintln!("{}", one_line(&format!("warning: {message}")));
    }
    fn baked(&mut self, ms: f64, frames: u64, longest_ms: f64) {
        if self.timings {
            println!(
                "baked: every level and its light in {ms:.0} ms over {frames} frames, the \
                 longest {longest_ms:.0} ms apart (from the start: the first frame's wait)"
            );
        }
    }
    fn chosen(&mut self, choice: &relief::choice::Choice, line: &str) {
        // With --timings the whole line, as `relief render` prints it; else which, in short.
        let c = choice.candidate;
        if self.timings {
            println!("{line}");
        } else if choice.why == relief::choice::Why::NoTimestamps {
            eprintln!(
                "relief: drawing with {c} ({}): nothing could be measured (no GPU timestamps)",
                c.flags()
            );
        } else {
            eprintln!(
                "relief: drawing with {c} ({}), the fastest measured; --timings says why",
                c.flags()
            );
        }
    }
    fn frame(&mut self, _stats: &Stats) {}
    fn fatal(&mut self, _message: &str) {
        // The CLI prints the error the app returns.
    }
}

#[cfg(not(target_arch = "wasm32"))]
pub(super) fn one_line(message: &str) -> String {
    relief::table::shorten_to(
        &message.split_whitespace().collect::<Vec<_>>().join(" "),
        200,
    )
}
