//! The typed errors relief returns at its boundary.

use std::path::PathBuf;

/// Everything that can go wrong in relief, with a message fit to show a user as one line.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A parameter is outside the range relief accepts.
    #[error("invalid {name}: {value} (allowed: {allowed})")]
    InvalidParam {
        /// The parameter's name as the user wrote it (`--height-scale` on the command line,
        /// `height_scale` in scene files and URLs).
        name: String,
        /// The offending value, formatted.
        value: String,
        /// The accepted range or set, in words.
        allowed: String,
    },
    /// A scene file could not be read or parsed.
    #[error("scene file {}: {message}", short_path(path))]
    SceneFile {
        /// The file.
        path: PathBuf,
        /// What is wrong with it, on one line.
        message: String,
    },
    /// A file could not be read or written.
    #[error("{}: {source}", short_path(path))]
    Io {
        /// The file or folder.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// No GPU adapter (not even a software one) was found.
    #[error("no GPU adapter found ({0}); on Linux install a Vulkan driver, e.g. mesa-vulkan-drivers for software rendering")]
    NoAdapter(String),
    /// The adapter refused to create a device.
    #[error("could not create a GPU device: {0}")]
    Device(String),
    /// wgpu reported a validation or out-of-memory error for work relief recorded.
    #[error("{message}")]
    Gpu {
        /// wgpu's error as one short line.
        message: String,
        /// wgpu's own error, whole.
        #[source]
        source: Option<wgpu::Error>,
    },
    /// The GPU device was lost (driver reset, GPU removed, browser reclaimed it).
    #[error("GPU device lost: {0}")]
    DeviceLost(String),
    /// A command-line option that does not apply to the command given.
    #[error("{0}")]
    Usage(String),
    /// No window could be opened (no display, or the windowing system refused).
    #[error("{0}")]
    Window(String),
    /// Reading back GPU data failed.
    #[error("GPU readback failed: {0}")]
    Readback(String),
}

impl Error {
    /// Shorthand for [`Error::InvalidParam`].
    pub fn invalid(name: impl Into<String>, value: impl ToString, allowed: impl ToString) -> Self {
        Self::InvalidParam {
            name: name.into(),
            value: value.to_string(),
            allowed: allowed.to_string(),
        }
    }

    /// `Ok` where `value` lies in `lo..=hi`, else [`Error::InvalidParam`] naming `name` and the
    /// range.
    pub fn check_range(name: &str, value: f32, (lo, hi): (f32, f32)) -> Result<(), Self> {
        if (lo..=hi).contains(&value) {
            Ok(())
        } else {
            Err(Self::invalid(name, value, format!("{lo} to {hi}")))
        }
    }

    /// Shorthand for [`Error::Io`].
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Self::Io {
            path: path.into(),
            source,
        }
    }
}

/// A path as an error line shows it: whole up to `MAX_PATH_CHARS` characters (an error line
/// holds 200), else its start and its end around "...", so the file name and where the path
/// starts both survive and a long path cannot push the reason off a one-line message.
pub fn short_path(path: &std::path::Path) -> String {
    let text = path.display().to_string();
    let n = text.chars().count();
    if n <= MAX_PATH_CHARS {
        return text;
    }
    let head = MAX_PATH_CHARS / 3;
    let tail = MAX_PATH_CHARS - head - 3;
    let start: String = text.chars().take(head).collect();
    let end: String = text.chars().skip(n - tail).collect();
    format!("{start}...{end}")
}

/// Longest path an error shows whole ([`short_path`]).
pub(crate) const MAX_PATH_CHARS: usize = 120;

/// relief's result type.
pub type Result<T, E = Error> = std::result::Result<T, E>;
