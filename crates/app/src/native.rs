//! The native window's entry point: an event loop on a display, or a refusal in words.
//! (Native only: the page starts from `web.rs`.)

use super::*;

/// Why no window can open here, if the reason is plain: no display server to connect to.
pub(super) fn no_display() -> Option<String> {
    if !cfg!(any(
        target_os = "linux",
        target_os = "freebsd",
        target_os = "openbsd"
    )) {
        return None;
    }
    let set = |v| std::env::var_os(v).is_some_and(|s| !s.is_empty());
    (!set("DISPLAY") && !set("WAYLAND_DISPLAY"))
        .then(|| "no display to open a window on (DISPLAY and WAYLAND_DISPLAY are unset)".into())
}

/// What to suggest when the window cannot open.
pub const NO_WINDOW_HINT: &str =
    "without a display, draw a frame with: relief render --out frame.png";

/// Opens the native window and runs until it is closed.
pub fn run_native(options: AppOptions, script: Script) -> Result<()> {
    if let Some(why) = no_display() {
        return Err(Error::Window(format!("{why}; {NO_WINDOW_HINT}")));
    }
    let event_loop = winit::event_loop::EventLoop::<UserEvent>::with_user_event()
        .build()
        .map_err(|e| {
            // winit's message carries the source file it came from; keep what it says.
            let text = e.to_string();
            let said = text.rsplit(": ").next().unwrap_or(&text).to_owned();
            Error::Window(format!("cannot open a window ({said}); {NO_WINDOW_HINT}"))
        })?;
    let proxy = event_loop.create_proxy();
    let mut app = App::new(
        options,
        script,
        Box::new(Terminal::new(options.timings)),
        proxy,
    );
    event_loop
        .run_app(&mut app)
        .map_err(|e| Error::Window(format!("the window's event loop failed: {e}")))?;
    if options.timings {
        println!(
            "window: {} frames drawn in {:.1} s",
            app.stats.frames,
            app.started.elapsed().as_secs_f64()
        );
    }
    match app.take_error() {
        Some(e) => Err(e),
        None => Ok(()),
    }
}
