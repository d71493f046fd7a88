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

/// Refuse, naming `path`, an output whose folder does not exist (before
/// any file beside it, temporary or lock, is tried and named instead).
pub fn ensure_folder(path: &Path) -> Result<()> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        if !dir.is_dir() {
            anyhow::bail!(
                "cannot write {}: the folder {} does not exist",
                path.display(),
                dir.display()
            );
        }
    }
    Ok(())
}

/// Run `write` on a temporary file beside `path`, then move it into place.
/// Errors name `path`, the file asked for, never the temporary one.
pub fn write_atomically(path: &Path, write: impl FnOnce(&Path) -> Result<()>) -> Result<()> {
    ensure_folder(path)?;
    let tmp = temp_beside(path);
    if let Err(e) = write(&tmp) {
        let _ = std::fs::remove_file(&tmp);
        let message = format!("{e:#}").replace(&tmp.display().to_string(), &path.display().to_string());
        return Err(anyhow::anyhow!(message));
    }
    std::fs::rename(&tmp, path).with_context(|| format!("cannot move output into place at {}", path.display()))
}

/// Write `bytes` to `path` atomically.
pub fn write_bytes(path: &Path, bytes: impl AsRef<[u8]>) -> Result<()> {
    write_atomically(path, |tmp| {
        std::fs::write(tmp, bytes.as_ref()).with_context(|| format!("cannot write {}", path.display()))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn errors_name_the_file_asked_for_and_a_missing_folder() {
        let e = write_bytes(Path::new("/nope/out.png"), b"x").unwrap_err().to_string();
        assert_eq!(e, "cannot write /nope/out.png: the folder /nope does not exist");
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("x.svg");
        let e = write_atomically(&out, |tmp| anyhow::bail!("backend failed on {}", tmp.display()))
            .unwrap_err()
            .to_string();
        assert!(e.contains(&out.display().to_string()) && !e.contains("partial"), "{e}");
    }

    #[test]
    fn a_failed_write_leaves_the_old_file_and_no_litter() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("chart.csv");
        std::fs::write(&out, "good\n").unwrap();
        let r = write_atomically(&out, |tmp| {
            std::fs::write(tmp, "half a fi")?;
            anyhow::bail!("disk full")
        });
        assert!(r.is_err());
        assert_eq!(std::fs::read_to_string(&out).unwrap(), "good\n");
        assert_eq!(
            std::fs::read_dir(dir.path()).unwrap().count(),
            1,
            "temporary file left behind"
        );
        write_atomically(&out, |tmp| Ok(std::fs::write(tmp, "new\n")?)).unwrap();
        assert_eq!(std::fs::read_to_string(&out).unwrap(), "new\n");
    }
}
