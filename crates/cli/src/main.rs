//! The `relief` program: a window by default, or headless `render`, `bake` and `bench`.

#[cfg(not(target_arch = "wasm32"))]
fn main() {
    quiet_runtime_dir();
    env_logger::Builder::from_env(
        env_logger::Env::default().default_filter_or("warn,wgpu=warn,naga=warn,wgpu_hal=error"),
    )
    .format_timestamp(None)
    .init();
    std::process::exit(relief_cli::main_with_args(std::env::args_os()));
}

/// Mesa's Vulkan drivers print `error: XDG_RUNTIME_DIR is invalid or not set` on every start
/// when that variable is missing (containers, CI, ssh without a session), although nothing is
/// wrong. Point it at a private folder first, so a user never reads "error:" after success.
#[cfg(all(unix, not(target_arch = "wasm32")))]
fn quiet_runtime_dir() {
    use std::os::unix::fs::{DirBuilderExt, MetadataExt, PermissionsExt};
    if std::env::var_os("XDG_RUNTIME_DIR").is_some_and(|v| !v.is_empty()) {
        return;
    }
    let Ok(uid) = std::fs::metadata("/proc/self").map(|m| m.uid()) else {
        return;
    };
    let dir = std::env::temp_dir().join(format!("relief-runtime-{uid}"));
    let _ = std::fs::DirBuilder::new().mode(0o700).create(&dir);
    // Only a folder of our own that nobody else can read is a valid runtime directory.
    let ours = std::fs::symlink_metadata(&dir)
        .is_ok_and(|m| m.is_dir() && m.uid() == uid && m.permissions().mode() & 0o077 == 0);
    if ours {
        // Single-threaded here: nothing else reads the environment yet.
        std::env::set_var("XDG_RUNTIME_DIR", dir);
    }
}

#[cfg(all(not(unix), not(target_arch = "wasm32")))]
fn quiet_runtime_dir() {}

#[cfg(target_arch = "wasm32")]
fn main() {}
