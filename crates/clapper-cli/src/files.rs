//! Writing output files so that a failure never leaves half a file where a
//! good one was: write beside it, then rename.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};

/// A temporary path beside `path` with the same extension.
fn temp_beside(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    path.with_file_name(format!(".{name}.{}.partial.{}", std::process::id(), extension(path)))
}

fn extension(path: &Path) -> String {
    path.extension()
        .map(|e| e.to_string_lossy().into_owned())
        .unwrap_or_default()
}

/// Run `write` on a temporary file beside `path`, then move it into place.
pub fn write_atomically(path: &Path, write: impl FnOnce(&Path) -> Result<()>) -> Result<()> {
    let tmp = temp_beside(path);
    let outcome = write(&tmp);
    if outcome.is_err() {
        let _ = std::fs::remove_file(&tmp);
        return outcome;
    }
    std::fs::rename(&tmp, path).with_context(|| format!("cannot move output into place at {}", path.display()))
}
