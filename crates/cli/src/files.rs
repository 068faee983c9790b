//! Output files: written whole or not at all, directories checked before a long run.

use super::*;

/// Writes `text` to `path` whole or not at all (a temporary name, then a rename).
pub(super) fn write_whole(path: &Path, text: &str) -> Result<()> {
    let tmp = temp_name(path);
    std::fs::write(&tmp, text).map_err(|e| Error::io(&tmp, e))?;
    std::fs::rename(&tmp, path).map_err(|e| Error::io(path, e))
}

/// Creates `dir` and missing parents; returns the top-most folder it created (to remove on
/// failure), or `None` if `dir` existed.
pub(super) fn create_dirs(dir: &Path) -> Result<Option<PathBuf>> {
    let mut top = None;
    let mut p = Some(dir);
    while let Some(d) = p.filter(|d| !d.as_os_str().is_empty() && !d.exists()) {
        top = Some(d.to_owned());
        p = d.parent();
    }
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    Ok(top)
}

/// Checks before any GPU work that `dir` is, or can become, a folder.
pub(super) fn check_out_dir(dir: &Path) -> Result<()> {
    if dir.as_os_str().is_empty() {
        return Err(Error::invalid("--out-dir", "\"\"", "a folder path"));
    }
    let mut p = Some(dir);
    while let Some(d) = p {
        if d.as_os_str().is_empty() {
            break;
        }
        if d.exists() {
            if d.is_dir() {
                return probe_writable(d);
            }
            let what = if d == dir {
                "a folder, or a path to create one; this is a file".to_owned()
            } else {
                format!(
                    "a path whose parents are folders; {} is a file",
                    relief::error::short_path(d)
                )
            };
            return Err(Error::invalid(
                "--out-dir",
                relief::error::short_path(dir),
                what,
            ));
        }
        p = d.parent();
    }
    Ok(())
}

/// Checks that files can be made in the folder `dir` (a read-only folder, `/proc`, another
/// user's) by making and removing an empty probe folder in it, before any work is done.
pub(super) fn probe_writable(dir: &Path) -> Result<()> {
    let probe = dir.join(format!(".relief-probe-{}", std::process::id()));
    std::fs::create_dir(&probe).map_err(|e| Error::io(dir, e))?;
    let _ = std::fs::remove_dir(&probe);
    Ok(())
}

pub(super) fn check_png_path(out: &Path) -> Result<()> {
    let is_png = out
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("png"));
    if !is_png {
        return Err(Error::invalid(
            "--out",
            relief::error::short_path(out),
            "a path ending in .png",
        ));
    }
    let parent = out
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    if !parent.is_dir() {
        return Err(Error::io(
            parent,
            std::io::Error::new(std::io::ErrorKind::NotFound, "output folder does not exist"),
        ));
    }
    if out.is_dir() {
        return Err(Error::invalid(
            "--out",
            relief::error::short_path(out),
            "a PNG file's path; this is a folder",
        ));
    }
    // The image is written at the end: a folder that takes no files fails now, not after the
    // work.
    probe_writable(parent)
}

pub(super) fn temp_name(path: &Path) -> PathBuf {
    let mut name = path.file_name().unwrap_or_default().to_os_string();
    name.push(format!(".relief-tmp-{}", std::process::id()));
    path.with_file_name(name)
}

pub(super) fn encode_png(
    path: &Path,
    w: u32,
    h: u32,
    color: image::ColorType,
    bytes: &[u8],
) -> Result<()> {
    image::save_buffer_with_format(path, bytes, w, h, color, image::ImageFormat::Png).map_err(|e| {
        match e {
            image::ImageError::IoError(io) => Error::io(path, io),
            other => Error::io(path, std::io::Error::other(other.to_string())),
        }
    })
}

/// Writes a PNG whole or not at all: to a temporary name beside it, then renamed.
pub fn write_png(path: &Path, w: u32, h: u32, color: image::ColorType, bytes: &[u8]) -> Result<()> {
    let tmp = temp_name(path);
    if let Err(e) = encode_png(&tmp, w, h, color, bytes) {
        let _ = std::fs::remove_file(&tmp);
        return Err(match e {
            Error::Io { source, .. } => Error::io(path, source),
            other => other,
        });
    }
    std::fs::rename(&tmp, path).map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        Error::io(path, e)
    })
}
