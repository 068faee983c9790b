//! The web page's entry points (wasm32 only): `start` runs the shared app on the page's
//! canvas; `set_param` is how the page's controls reach it; `params_table` tells the page which
//! controls to build (from the same tables as the CLI's flags), `world_params_table` the same
//! for the endless world (`world=endless` in the URL). The app reports back through
//! the DOM: `#readout` (frame rate, GPU times, idle), `#notice` (what the URL could not set,
//! recoveries), `#error` (and `#fatal`, a banner, when relief stopped), and `data-frames` / `data-query` / `data-error` on `<body>` plus a
//! `relief-options` event when the parameters change.

use super::{format_timings, url_keys, App, AppOptions, Report, Script, Stats, UserEvent, OPTIONS};
use relief::params::params;
use relief::table::{Control, Kind, Param};
use std::cell::RefCell;
use wasm_bindgen::prelude::*;
use winit::event_loop::{EventLoop, EventLoopProxy};
use winit::platform::web::{EventLoopExtWebSys, WindowAttributesExtWebSys};

thread_local! {
    static PROXY: RefCell<Option<EventLoopProxy<UserEvent>>> = const { RefCell::new(None) };
    static CANVAS: RefCell<Option<web_sys::HtmlCanvasElement>> = const { RefCell::new(None) };
}

fn document() -> Option<web_sys::Document> {
    web_sys::window()?.document()
}

/// Starts relief on the canvas with id `canvas_id`, with options from a URL query string.
/// Entries the URL gets wrong are skipped (the rest apply) and listed in `#notice`.
#[wasm_bindgen]
pub fn start(canvas_id: &str, query: &str) -> Result<(), JsValue> {
    console_error_panic_hook::set_once();
    let _ = console_log::init_with_level(log::Level::Warn);
    let canvas = document()
        .and_then(|d| d.get_element_by_id(canvas_id))
        .and_then(|e| e.dyn_into::<web_sys::HtmlCanvasElement>().ok())
        .ok_or_else(|| JsValue::from_str(&format!("no <canvas id=\"{canvas_id}\"> on the page")))?;
    CANVAS.with(|c| *c.borrow_mut() = Some(canvas));
    let mut options = AppOptions {
        timings: true,
        ..Default::default()
    };
    let ignored = options.apply_query(query);
    if !ignored.is_empty() {
        // A reason names its key ("invalid seed: abc (allowed: ...)"): the key goes before
        // it only where it does not.
        let list: Vec<String> = ignored
            .iter()
            .map(|i| {
                if i.reason.contains(i.key.as_str()) {
                    i.reason.clone()
                } else {
                    format!("{}: {}", i.key, i.reason)
                }
            })
            .collect();
        set_text(
            "notice",
            &format!("Ignored in the URL (the rest applies): {}", list.join("; ")),
        );
        set_body_data(
            "ignored",
            &ignored
                .iter()
                .map(|i| i.key.clone())
                .collect::<Vec<_>>()
                .join(","),
        );
    }
    let event_loop = EventLoop::<UserEvent>::with_user_event()
        .build()
        .map_err(|e| JsValue::from_str(&e.to_string()))?;
    let proxy = event_loop.create_proxy();
    PROXY.with(|p| *p.borrow_mut() = Some(proxy.clone()));
    event_loop.spawn_app(App::new(
        options,
        Script::default(),
        Box::new(Page::default()),
        proxy,
    ));
    Ok(())
}

/// Sends an event to the app from code that cannot hold the proxy.
pub(crate) fn send(event: UserEvent) {
    PROXY.with(|p| {
        if let Some(p) = p.borrow().as_ref() {
            let _ = p.send_event(event);
        }
    });
}

/// Changes one parameter (scene keys as in scene files, plus the window's keys).
#[wasm_bindgen]
pub fn set_param(key: &str, value: &str) {
    send(UserEvent::Set(key.to_owned(), value.to_owned()));
}

/// The default options as a query string, so the page's controls start from relief's defaults.
#[wasm_bindgen]
pub fn default_query() -> String {
    AppOptions::default().to_query()
}

/// Every URL key, comma-separated.
#[wasm_bindgen]
pub fn keys() -> String {
    url_keys().join(",")
}

/// The page's controls as JSON: one object per parameter with its key, doc, control
/// (`slider`, `number`, `select`, `checkbox` or `none`), range and step, allowed values in
/// words, and choices; from the same tables as the CLI's flags.
#[wasm_bindgen]
pub fn params_table() -> String {
    let rows: Vec<String> = params()
        .map(row_json)
        .chain(OPTIONS.iter().map(row_json))
        .chain(std::iter::once(row_json(&super::options::TILE_METHOD)))
        .collect();
    format!("[{}]", rows.join(","))
}

/// The endless world's controls (`world=endless` in the URL), as [`params_table`] gives the
/// tile's.
#[wasm_bindgen]
pub fn world_params_table() -> String {
    let rows: Vec<String> = relief::world::WORLD_PARAMS
        .iter()
        .map(row_json)
        .chain(std::iter::once(row_json(&super::options::METHOD)))
        .chain(std::iter::once(row_json(&super::options::TEMPORAL)))
        .collect();
    format!("[{}]", rows.join(","))
}

/// The endless world's default options as a query string.
#[wasm_bindgen]
pub fn default_world_query() -> String {
    let mut o = AppOptions::default();
    o.apply_query("world=endless");
    o.to_query()
}

fn json_str(s: &str) -> String {
    let mut out = String::from("\"");
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            c if c.is_control() => out.push(' '),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

fn row_json<T>(p: &Param<T>) -> String {
    let (control, min, max, step) = match p.control {
        Control::None => ("none", 0.0, 0.0, 0.0),
        Control::Slider { min, max, step } => ("slider", min, max, step),
        Control::Number => match p.kind {
            Kind::Int { min, max } => ("number", f64::from(min), f64::from(max), 1.0),
            _ => ("number", 0.0, 0.0, 0.0),
        },
        Control::Select => ("select", 0.0, 0.0, 0.0),
        Control::Checkbox => ("checkbox", 0.0, 0.0, 0.0),
    };
    let choices = match p.kind {
        Kind::Choice(names) => names
            .iter()
            .map(|n| json_str(n))
            .collect::<Vec<_>>()
            .join(","),
        _ => String::new(),
    };
    format!(
        "{{\"key\":{},\"doc\":{},\"allowed\":{},\"control\":\"{control}\",\"min\":{min},\"max\":{max},\"step\":{step},\"choices\":[{choices}]}}",
        json_str(p.key),
        json_str(p.doc),
        json_str(&p.allowed()),
    )
}

pub(crate) fn window_attributes(
    attributes: winit::window::WindowAttributes,
) -> winit::window::WindowAttributes {
    let canvas = CANVAS.with(|c| c.borrow().clone());
    attributes
        .with_canvas(canvas)
        .with_prevent_default(true)
        .with_focusable(true)
}

fn set_text(id: &str, text: &str) {
    if let Some(e) = document().and_then(|d| d.get_element_by_id(id)) {
        e.set_text_content(Some(text));
    }
}

fn set_body_data(key: &str, value: &str) {
    if let Some(body) = document().and_then(|d| d.body()) {
        let _ = body.dataset().set(key, value);
    }
}

/// The page's [`Report`]: the readout, notices and errors in the DOM.
#[derive(Default)]
struct Page {
    /// The GPU is building the pipelines: the readout says so until the first frame.
    preparing: bool,
}

impl Report for Page {
    fn stats(&mut self, _describe: &str, stats: &Stats, _fresh: bool) {
        let gpu = match (stats.timestamps, stats.gpu) {
            (true, Some((_, t))) => format!("GPU: {}", format_timings(&t)),
            (true, None) => "GPU: measuring".to_owned(),
            (false, _) => "GPU times: this browser exposes no timestamp-query".to_owned(),
        };
        let method = match stats.method {
            relief::Method::Mesh => String::new(),
            m => format!("{m} · "),
        };
        // The wasm's own time per frame (recording and submitting), beside the GPU's.
        let cpu = stats
            .cpu_ms
            .map_or(String::new(), |ms| format!(" · CPU {ms:.2} ms/frame"));
        let baking = stats
            .baking
            .map_or(String::new(), |p| format!("baking… {p}% · "));
        if self.preparing && stats.frames == 0 {
            return;
        }
        if let Some(ms) = stats.cpu_ms {
            set_body_data("cpu_ms", &format!("{ms:.3}"));
        }
        let text = if stats.idle {
            format!("{method}idle: drawn only on change · last frame {gpu}{cpu}")
        } else {
            format!("{baking}{method}{:.0} fps · {gpu}{cpu}", stats.fps)
        };
        set_text("readout", &text);
        set_body_data("idle", if stats.idle { "1" } else { "0" });
    }

    fn notice(&mut self, message: &str) {
        set_text("notice", message);
    }

    fn warn(&mut self, message: &str) {
        log::warn!("{message}");
        set_text("error", message);
    }

    fn accepted(&mut self) {
        // A change that took effect clears a previous refusal (never a fatal error). The
        // twice-a-second URL updates of a scrolling terrain do not: a refusal stays readable.
        if document()
            .and_then(|d| d.body())
            .and_then(|b| b.dataset().get("error"))
            .is_none()
        {
            set_text("error", "");
        }
    }

    fn options(&mut self, options: &AppOptions) {
        set_body_data("query", &options.to_query());
        if let Some(w) = web_sys::window() {
            if let Ok(e) = web_sys::Event::new("relief-options") {
                let _ = w.dispatch_event(&e);
            }
        }
    }

    fn preparing(&mut self) {
        self.preparing = true;
        set_body_data("preparing", "1");
        set_text("readout", "building the GPU's pipelines…");
    }

    fn frame(&mut self, stats: &Stats) {
        if self.preparing {
            self.preparing = false;
            set_body_data("preparing", "");
        }
        set_body_data("frames", &stats.frames.to_string());
        let baking = stats.baking.map_or(String::new(), |p| p.to_string());
        if document()
            .and_then(|d| d.body())
            .and_then(|b| b.dataset().get("baking"))
            != Some(baking.clone())
        {
            set_body_data("baking", &baking);
            if let Some(p) = stats.baking {
                // Shown at once, not at the next half-second readout: the first frames of an
                // endless world on a slow device are the ones a user waits through.
                set_text("readout", &format!("baking… {p}%"));
            }
        }
        if stats.frames == 1 {
            // From the page's navigation to its first frame submitted: download, compile,
            // adapter and device, the pipelines built by the GPU, the first bake and draw.
            if let Some(p) = web_sys::window().and_then(|w| w.performance()) {
                set_body_data("first_frame_ms", &format!("{:.0}", p.now()));
            }
        }
    }

    fn baked(&mut self, ms: f64, frames: u64, longest_ms: f64) {
        set_body_data("baked_ms", &format!("{ms:.0}"));
        set_body_data("baked_frames", &frames.to_string());
        set_body_data("baked_longest_frame_ms", &format!("{longest_ms:.0}"));
    }

    fn fatal(&mut self, message: &str) {
        log::error!("{message}");
        let message = &relief::table::shorten_to(&format!("relief stopped: {message}"), 200);
        set_text("error", message);
        // Also as a banner over the canvas, where a small screen cannot scroll it away.
        if let Some(e) = document().and_then(|d| d.get_element_by_id("fatal")) {
            e.set_text_content(Some(message));
            let _ = e.remove_attribute("hidden");
        }
        set_text("readout", "stopped");
        set_body_data("error", message);
        if let Some(w) = web_sys::window() {
            if let Ok(e) = web_sys::Event::new("relief-stopped") {
                let _ = w.dispatch_event(&e);
            }
        }
    }
}
