//! Runs stopped part-way (docs/reliability.md): Ctrl-C or SIGTERM removes
//! the file being written and says so; a partial file left by a run that
//! was killed outright is removed by the next write of the same file.

mod common;

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::Duration;

/// The hidden partial files of `name` in `dir`.
fn partials(dir: &Path, name: &str) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|f| f.starts_with(&format!(".{name}.")) && f.contains(".partial."))
        .collect()
}

#[test]
fn a_stopped_trace_leaves_no_partial_file() {
    for signal in ["-INT", "-TERM"] {
        let dir = tempfile::tempdir().unwrap();
        let trace = dir.path().join("long.csv");
        let mut child = Command::new(assert_cmd::cargo::cargo_bin("clapper"))
            .args(["simulate", "--preset", "lab", "--strokes", "10000", "--trace"])
            .arg(&trace)
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        // Wait until it is writing: the run itself is bounded (10,000
        // strokes), so it either writes or ends, however slow the machine.
        while partials(dir.path(), "long.csv").is_empty() {
            assert!(
                child.try_wait().unwrap().is_none(),
                "the run ended before a partial file appeared"
            );
            std::thread::sleep(Duration::from_millis(20));
        }
        std::thread::sleep(Duration::from_millis(200));
        let ok = Command::new("kill")
            .args([signal, &child.id().to_string()])
            .status()
            .unwrap();
        assert!(ok.success());
        let out = child.wait_with_output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(130), "{signal}: {err}");
        assert!(err.contains("removed the unfinished"), "{signal}: {err}");
        assert!(
            partials(dir.path(), "long.csv").is_empty(),
            "{signal}: {:?}",
            partials(dir.path(), "long.csv")
        );
        assert!(!trace.exists());
    }
}

#[test]
fn a_partial_left_by_a_killed_run_is_removed_by_the_next() {
    let dir = tempfile::tempdir().unwrap();
    // A process that has ended: its id is free.
    let mut gone = Command::new("true").spawn().unwrap();
    let pid = gone.id();
    gone.wait().unwrap();
    let stale = dir.path().join(format!(".t.csv.{pid}.partial.csv"));
    std::fs::write(&stale, "half a trace").unwrap();
    let out = common::clapper()
        .args(["simulate", "--preset", "lab", "--trace"])
        .arg(dir.path().join("t.csv"))
        .output()
        .unwrap();
    assert!(out.status.success());
    assert!(!stale.exists());
    assert!(String::from_utf8_lossy(&out.stderr).contains("left by an earlier run"));
    assert!(dir.path().join("t.csv").exists());
}
