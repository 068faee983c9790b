//! The `relief` program: a window by default, or headless `render` and `bake`.

#[cfg(not(target_arch = "wasm32"))]
fn main() {
    env_logger::Builder::from_env(
        env_logger::Env::default().default_filter_or("warn,wgpu=warn,naga=warn"),
    )
    .format_timestamp(None)
    .init();
    std::process::exit(relief::cli::main_with_args(std::env::args_os()));
}

#[cfg(target_arch = "wasm32")]
fn main() {}
