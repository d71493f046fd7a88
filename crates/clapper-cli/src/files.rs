//! Writing output files so that a failure never leaves half a file where a
//! good one was: write beside it, then rename. A run stopped by Ctrl-C or
//! SIGTERM removes the files it was writing; one killed outright leaves
//! them, and the next write of the same file removes them.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Mutex, Once};

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
    // Two outputs naming one file: the second would overwrite the first.
    let files: Vec<(&str, &Path)> = outputs
        .iter()
        .filter_map(|(name, p)| p.filter(|p| !is_stdout(p)).map(|p| (*name, p)))
        .collect();
    for (i, (a, pa)) in files.iter().enumerate() {
        if let Some((b, _)) = files[i + 1..].iter().find(|(_, pb)| same_file(pa, pb)) {
            anyhow::bail!("{a} and {b} both name {}: give each its own file", pa.display());
        }
    }
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

/// Whether two paths name one file: the same as written, or the same
/// file name in the same folder however the folder is written.
fn same_file(a: &Path, b: &Path) -> bool {
    if a == b {
        return true;
    }
    let folder = |p: &Path| {
        let dir = p
            .parent()
            .filter(|d| !d.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        std::fs::canonicalize(dir).ok()
    };
    a.file_name() == b.file_name() && folder(a).is_some() && folder(a) == folder(b)
}

/// The files being written now, removed if the run is stopped.
static PARTIALS: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// What to tell the user when a run that can resume is stopped.
static RESUMABLE: Mutex<Option<String>> = Mutex::new(None);

/// Catch Ctrl-C, SIGTERM and SIGHUP (once): remove the files being
/// written, say what was removed (and how to resume, where a run can),
/// and exit with status 130.
fn catch_stops() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        let _ = ctrlc::set_handler(|| {
            let partials: Vec<PathBuf> = PARTIALS.lock().map(|mut p| std::mem::take(&mut *p)).unwrap_or_default();
            for p in &partials {
                if std::fs::remove_file(p).or_else(|_| std::fs::remove_dir_all(p)).is_ok() {
                    eprintln!("\nstopped: removed the unfinished {}", p.display());
                }
            }
            if let Some(how) = RESUMABLE.lock().ok().and_then(|r| r.clone()) {
                eprintln!("\nstopped: {how}");
            }
            std::process::exit(130);
        });
    });
}

/// Say `how` to resume if the run is stopped, until [`resumable_done`].
pub fn resumable(how: String) {
    catch_stops();
    if let Ok(mut r) = RESUMABLE.lock() {
        *r = Some(how);
    }
}

/// The run can no longer be resumed (it finished).
pub fn resumable_done() {
    if let Ok(mut r) = RESUMABLE.lock() {
        *r = None;
    }
}

fn register(tmp: &Path) {
    catch_stops();
    if let Ok(mut p) = PARTIALS.lock() {
        p.push(tmp.to_path_buf());
    }
}

fn unregister(tmp: &Path) {
    if let Ok(mut p) = PARTIALS.lock() {
        p.retain(|x| x != tmp);
    }
}

/// A temporary path beside `path` with the same extension:
/// `.NAME.PID.partial.EXT`.
fn temp_beside(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    path.with_file_name(format!(".{name}.{}.partial.{}", std::process::id(), extension(path)))
}

/// Remove the temporary files of `path` left by runs that were killed
/// (their process is gone), saying so; a file of a run still going is
/// left alone.
fn remove_stale(path: &Path) {
    let (Some(dir), Some(name)) = (path.parent(), path.file_name()) else {
        return;
    };
    let dir = if dir.as_os_str().is_empty() {
        Path::new(".")
    } else {
        dir
    };
    let prefix = format!(".{}.", name.to_string_lossy());
    let suffix = format!(".partial.{}", extension(path));
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let file = e.file_name().to_string_lossy().into_owned();
        let Some(pid) = file
            .strip_prefix(&prefix)
            .and_then(|r| r.strip_suffix(&suffix))
            .and_then(|pid| pid.parse::<u32>().ok())
        else {
            continue;
        };
        if pid != std::process::id() && !alive(pid) && std::fs::remove_file(e.path()).is_ok() {
            eprintln!(
                "removed {}, left by an earlier run that was stopped",
                e.path().display()
            );
        }
    }
}

/// Whether process `pid` is running.
fn alive(pid: u32) -> bool {
    #[cfg(unix)]
    {
        // SAFETY: signal 0 only checks that the process exists.
        let r = unsafe { libc::kill(pid as libc::pid_t, 0) };
        r == 0 || std::io::Error::last_os_error().raw_os_error() == Some(libc::EPERM)
    }
    #[cfg(not(unix))]
    {
        let _ = pid;
        true
    }
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

/// The text of `path`, which should be `wanted` ("a chart CSV"); a
/// recording or an image given instead is named as one.
pub fn read_text(path: &Path, wanted: &'static str) -> Result<String> {
    use clapper_io::text_file::ReadTextError;
    clapper_io::text_file::read_text(path, wanted).map_err(|e| match e {
        ReadTextError::Io(e) => anyhow::anyhow!("cannot read {}: {e}", path.display()),
        ReadTextError::NotText(e) => e.into(),
    })
}

/// Make the folder `dir` for an output option (`--out DIR`) if it is
/// missing; refuse, saying so, a file where the folder or one above it
/// should be (rather than "File exists (os error 17)").
pub fn make_folder(dir: &Path, option: &str) -> Result<()> {
    if let Some(file) = dir
        .ancestors()
        .find(|a| !a.as_os_str().is_empty() && a.exists() && !a.is_dir())
    {
        if file == dir {
            anyhow::bail!(
                "{option} must be a folder, and {} is a file: give a folder to write into (made if missing)",
                dir.display()
            );
        }
        anyhow::bail!(
            "{option} {} cannot be made: {} is a file, not a folder",
            dir.display(),
            file.display()
        );
    }
    std::fs::create_dir_all(dir).with_context(|| format!("cannot make the folder {}", dir.display()))
}

/// Refuse, naming `path`, an output whose folder does not exist (before
/// any file beside it, temporary or lock, is tried and named instead).
pub fn ensure_folder(path: &Path) -> Result<()> {
    // Found before anything is written: a move onto a folder fails only at
    // the end, after the work, and left the temporary file beside it.
    if path.is_dir() {
        anyhow::bail!(
            "cannot write {}: it is a folder; give a file's name (in it, or beside it)",
            path.display()
        );
    }
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
        // Removed with its folder if the run is stopped.
        register(dir.path());
        write(&tmp).map_err(|e| anyhow::anyhow!(format!("{e:#}").replace(&tmp.display().to_string(), "-")))?;
        // Copied through, not read whole: a trace may be gigabytes.
        let mut f = std::fs::File::open(&tmp).context("cannot read back the output")?;
        let mut out = std::io::stdout().lock();
        std::io::copy(&mut f, &mut out)
            .and_then(|_| out.flush())
            .context("cannot write to standard output")?;
        unregister(dir.path());
        return Ok(());
    }
    ensure_folder(path)?;
    remove_stale(path);
    let tmp = temp_beside(path);
    register(&tmp);
    let written = write(&tmp);
    let done = match written {
        Err(e) => {
            let _ = std::fs::remove_file(&tmp);
            let message = format!("{e:#}").replace(&tmp.display().to_string(), &path.display().to_string());
            Err(anyhow::anyhow!(message))
        }
        Ok(()) => std::fs::rename(&tmp, path).map_err(|e| {
            let _ = std::fs::remove_file(&tmp);
            anyhow::anyhow!("cannot move output into place at {}: {e}", path.display())
        }),
    };
    unregister(&tmp);
    done
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
    fn a_folder_is_refused_as_an_output_before_anything_is_written() {
        // The folder given as the output sits in a folder of its own, so the
        // count of partial files is not disturbed by other runs in /tmp.
        let parent = tempfile::tempdir().unwrap();
        let out = parent.path().join("out");
        std::fs::create_dir(&out).unwrap();
        let mut ran = false;
        let e = write_atomically(&out, |_| {
            ran = true;
            Ok(())
        })
        .unwrap_err()
        .to_string();
        assert!(e.contains("it is a folder"), "{e}");
        assert!(!ran);
        assert_eq!(
            std::fs::read_dir(parent.path())
                .unwrap()
                .filter(|f| f.as_ref().unwrap().file_name().to_string_lossy().contains("partial"))
                .count(),
            0
        );
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
