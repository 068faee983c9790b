//! The web page's entry points (wasm32 only): `start` runs the shared app on the page's
//! canvas; `set_param` is how the page's controls reach it. The app reports back through the
//! DOM: `#readout` (frame rate, GPU times), `#error`, and `data-frames` / `data-query` on
//! `<body>` plus a `relief-options` event when the parameters change.

use super::{format_timings, App, AppOptions, Stats, UserEvent};
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
    if let Err(e) = options.apply_query(query) {
        show_error(&format!("URL: {e}"));
    }
    let event_loop = EventLoop::<UserEvent>::with_user_event()
        .build()
        .map_err(|e| JsValue::from_str(&e.to_string()))?;
    let proxy = event_loop.create_proxy();
    PROXY.with(|p| *p.borrow_mut() = Some(proxy.clone()));
    event_loop.spawn_app(App::new(options, proxy));
    Ok(())
}

/// Changes one parameter (scene keys as in scene files, plus `speed` and `paused`).
#[wasm_bindgen]
pub fn set_param(key: &str, value: &str) {
    PROXY.with(|p| {
        if let Some(p) = p.borrow().as_ref() {
            let _ = p.send_event(UserEvent::Set(key.to_owned(), value.to_owned()));
        }
    });
}

/// The default options as a query string, so the page's controls start from relief's defaults.
#[wasm_bindgen]
pub fn default_query() -> String {
    AppOptions::default().to_query()
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

pub(crate) fn show_error(message: &str) {
    set_text("error", message);
    set_body_data("error", message);
}

pub(crate) fn show_stats(stats: &Stats) {
    let gpu = match (stats.timestamps, stats.gpu) {
        (true, Some(t)) => format!("GPU: {}", format_timings(&t)),
        (true, None) => "GPU: measuring".to_owned(),
        (false, _) => "GPU times: this browser exposes no timestamp-query".to_owned(),
    };
    set_text("readout", &format!("{:.0} fps · {gpu}", stats.fps));
}

pub(crate) fn frame_done(stats: &Stats) {
    set_body_data("frames", &stats.frames.to_string());
}

pub(crate) fn options_changed(options: &AppOptions) {
    set_body_data("query", &options.to_query());
    set_text("error", "");
    if let Some(w) = web_sys::window() {
        if let Ok(e) = web_sys::Event::new("relief-options") {
            let _ = w.dispatch_event(&e);
        }
    }
}
