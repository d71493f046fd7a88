//! Writing output files so that a failure never leaves half a file where a
//! good one was: write beside it, then rename.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};

use anyhow::{Context, Result};

/// Set when an output file is `-`: standard output then carries that
/// output's bytes, and the command's summary goes to standard error.
static STDOUT_IS_DATA: AtomicBool = AtomicBool::new(false);

/// Whether `path` is `-`, standard output.
pub fn is_stdout(path: &Path) -> bool {
    path.as_os_str() == "-"
}

/// Whether standard output carries an output's bytes (so a summary goes
/// to standard error: see [`summary`]).
pub fn stdout_is_data() -> bool {
    STDOUT_IS_DATA.load(Ordering::Relaxed)
}

/// Print a command's summary text: on standard output, or on standard
/// error when standard output carries an output's bytes.
pub fn summary(text: std::fmt::Arguments<'_>) {
    if stdout_is_data() {
        eprint!("{text}");
    } else {
        print!("{text}");
    }
}

/// Give standard output to the one output among `outputs` (option name,
/// path) that is `-`, before anything is printed; refuse two, or one with
/// `--json` (which prints to standard output too).
pub fn claim_stdout(outputs: &[(&str, Option<&Path>)], json: bool) -> Result<()> {
    let dashes: Vec<&str> = outputs
        .iter()
        .filter(|(_, p)| p.is_some_and(is_stdout))
        .map(|(name, _)| *name)
        .collect();
    match dashes[..] {
        [] => {}
        [one] if json => anyhow::bail!("{one} - and --json both want standard output: give {one} a file name"),
        [_] => STDOUT_IS_DATA.store(true, Ordering::Relaxed),
        [a, b] => anyhow::bail!("{a} - and {b} - both want standard output: give one of them a file name"),
        _ => anyhow::bail!(
            "{} all want standard output (-): give all but one a file name",
            dashes.join(", ")
        ),
    }
    Ok(())
}

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

/// A recording's name for a plot's title: its file name, not the folder it
/// happens to sit in (often a temporary one).
pub fn title_name(path: &Path) -> String {
    path.file_name()
        .map_or_else(|| path.display().to_string(), |n| n.to_string_lossy().into_owned())
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
/// `-` writes to standard output instead (through a temporary file, so
/// that a failure prints nothing).
pub fn write_atomically(path: &Path, write: impl FnOnce(&Path) -> Result<()>) -> Result<()> {
    if is_stdout(path) {
        let dir = tempfile::tempdir().context("cannot make a temporary folder")?;
        let tmp = dir.path().join("stdout");
        write(&tmp).map_err(|e| anyhow::anyhow!(format!("{e:#}").replace(&tmp.display().to_string(), "-")))?;
        // Copied through, not read whole: a trace may be gigabytes.
        let mut f = std::fs::File::open(&tmp).context("cannot read back the output")?;
        let mut out = std::io::stdout().lock();
        std::io::copy(&mut f, &mut out)
            .and_then(|_| out.flush())
            .context("cannot write to standard output")?;
        return Ok(());
    }
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
