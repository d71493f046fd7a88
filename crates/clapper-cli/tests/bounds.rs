//! Issue 46's reproductions through the built binary: each ran away,
//! aborted, or printed nonsense with exit 0; each is now refused at once
//! with a message in the option's own words (exit 1 or 2).

use assert_cmd::Command;

fn refused(args: &[&str], says: &str) {
    let out = Command::cargo_bin("clapper").unwrap().args(args).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        matches!(out.status.code(), Some(1 | 2)),
        "{args:?}: {:?} {err}",
        out.status
    );
    assert!(err.contains(says), "{args:?}: {err}");
    assert_eq!(err.trim().lines().count(), 1, "{args:?}: {err}");
}

#[test]
fn runaways_and_aborts_are_refused_before_they_start() {
    // Ran for more than 600 s with no output.
    refused(
        &["ring-up", "--chart-point", "-5,0.2"],
        "outside the domain clapper is tested over",
    );
    refused(&["ring-down", "--chart-point", "-5,0.5"], "r/L_c from -1 to 2");
    // Aborted allocating 272 GB; passed 8 GiB in seconds.
    refused(
        &["synth-log", "--out", "x.txt", "--strokes", "1000000000"],
        "--strokes 1000000000: at most",
    );
    refused(
        &["synth-log", "--out", "x.txt", "--gaps", "1000000000"],
        "--gaps 1000000000: at most",
    );
    // A chart of a bell damped past critical did not end.
    refused(
        &["chart", "--grid", "3", "--bell-damping", "1e9"],
        "below critical damping",
    );
    refused(&["simulate", "--bell-friction", "1e9"], "gravity torque");
    refused(&["simulate", "--pivot-offset", "1"], "--pivot-offset 1 is out of range");
}

#[test]
fn numbers_must_be_finite_and_may_be_negative() {
    refused(
        &["ringing-log", "x.txt", "--sensor-m", "NaN"],
        "NaN is not a finite number",
    );
    refused(
        &["synth-log", "--out", "x.txt", "--noise", "NaN"],
        "NaN is not a finite number",
    );
    refused(
        &["design-clapper", "--ball-position", "inf"],
        "inf is not a finite number",
    );
    // A negative value is read as a value and refused by its meaning, not
    // taken for an option ("use '-- -1'", which does not work for a value).
    refused(
        &["synth", "--out", "b.wav", "--nominal", "-1"],
        "a bell's nominal is from 20 to 20,000 Hz",
    );
    refused(
        &[
            "spectrogram",
            "../../examples/data/strike.wav",
            "--out",
            "s.png",
            "--fmax",
            "-1",
        ],
        "--fmax -1: the highest frequency",
    );
    refused(&["synth-log", "--out", "x.txt", "--noise", "-1"], "--noise -1 m/s²");
}

#[test]
fn an_endless_input_is_named_not_read() {
    if std::path::Path::new("/dev/zero").exists() {
        refused(&["ringing-log", "/dev/zero"], "not a text file");
        refused(&["diagnose", "/dev/zero"], "not a text file");
    }
}

/// An output that is a folder is refused before anything is written, and leaves no
/// `.NAME.PID.partial.EXT` beside it (which the next run then took for
/// the litter of a stopped run).
#[test]
fn a_folder_given_as_an_output_is_refused_and_leaves_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("afolder");
    std::fs::create_dir(&out).unwrap();
    let o = out.display().to_string();
    refused(&["simulate", "--preset", "lab", "--trace", &o], "it is a folder");
    let png = dir.path().join("pic.png");
    std::fs::create_dir(&png).unwrap();
    refused(
        &["chart", "--grid", "3", "--out", &png.display().to_string()],
        "it is a folder",
    );
    let litter: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|f| f.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n != "afolder" && n != "pic.png")
        .collect();
    assert!(litter.is_empty(), "{litter:?}");
}

/// Said, not done silently: two outputs naming one file (the second
/// overwrote the first), a template folder with a gap (3.wav was left
/// out), one bell's nominal given twice.
#[test]
fn mistakes_that_were_silent_are_said() {
    let dir = tempfile::tempdir().unwrap();
    let wav = "../../examples/data/tower.wav";
    let f = dir.path().join("out.csv").display().to_string();
    let also = format!("{}/./out.csv", dir.path().display());
    refused(
        &[
            "strikes",
            wav,
            "--nominals",
            "1400,1247.3",
            "--csv",
            &f,
            "--lowndes",
            &also,
        ],
        "--csv and --lowndes both name",
    );
    let t = dir.path().join("t");
    std::fs::create_dir(&t).unwrap();
    for n in ["1", "3"] {
        std::fs::copy("../../examples/data/strike.wav", t.join(format!("{n}.wav"))).unwrap();
    }
    refused(
        &["strikes", wav, "--templates", &t.display().to_string()],
        "3.wav but no 2.wav",
    );
    refused(
        &["strikes", wav, "--nominals", "1400,1400,1111"],
        "bells 1 and 2 have nominals 1400 and 1400 Hz",
    );
}

/// A synthetic ring of 10^9 rows passed 8 GiB in seconds: refused by the
/// hours of sound it would be; a bell with no nominal is named by its
/// number, not printed as a Rust struct.
#[test]
fn a_synthetic_ring_is_bounded_and_its_bells_named() {
    refused(
        &["synth-ring", "--out", "r.wav", "--rows", "1000000000"],
        "hours of sound, at most 4",
    );
    refused(
        &["synth-ring", "--out", "r.wav", "--treble-hz", "0"],
        "bell 1: nominal 0 Hz and mass 150 kg: both must be more than 0",
    );
}

/// A synthetic log at 5 kHz read back: its times were written in whole
/// milliseconds, so successive samples repeated a time and the log was
/// refused ("time goes backwards or repeats").
#[test]
fn a_fast_synthetic_log_reads_back() {
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("fast.txt").display().to_string();
    let made = Command::cargo_bin("clapper")
        .unwrap()
        .args(["synth-log", "--out", &log, "--rate", "5000", "--strokes", "2"])
        .output()
        .unwrap();
    assert!(made.status.success(), "{}", String::from_utf8_lossy(&made.stderr));
    let read = Command::cargo_bin("clapper")
        .unwrap()
        .args(["ringing-log", &log])
        .output()
        .unwrap();
    assert!(read.status.success(), "{}", String::from_utf8_lossy(&read.stderr));
}

/// Issue 46: `ringing-log --sensor-m -1e300` read a log as "sensor -1e300
/// m above the pivot, 68 swings"; a sensor is on the bell, within 2 m of
/// its pivot.
#[test]
fn a_sensor_far_from_the_pivot_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("l.txt").display().to_string();
    let made = Command::cargo_bin("clapper")
        .unwrap()
        .args(["synth-log", "--out", &log, "--strokes", "2"])
        .output()
        .unwrap();
    assert!(made.status.success(), "{}", String::from_utf8_lossy(&made.stderr));
    for m in ["-1e300", "3"] {
        refused(
            &["ringing-log", &log, "--sensor-m", m],
            &format!("--sensor-m {m} m: a sensor on the bell, within 2 m of the pivot"),
        );
    }
    let read = Command::cargo_bin("clapper")
        .unwrap()
        .args(["ringing-log", &log, "--sensor-m", "0.15"])
        .output()
        .unwrap();
    assert!(read.status.success(), "{}", String::from_utf8_lossy(&read.stderr));
}

/// Issue 46: synth-ring wrote a ring at 192 kHz and printed the strikes
/// command to hear it, which refused it ("recordings from 8 to 96 kHz").
/// Now strikes reads it, and hears every strike it was given.
#[test]
fn a_ring_written_at_192_khz_is_heard() {
    let dir = tempfile::tempdir().unwrap();
    let wav = dir.path().join("r.wav").display().to_string();
    let truth = dir.path().join("t.csv");
    let made = Command::cargo_bin("clapper")
        .unwrap()
        .args([
            "synth-ring",
            "--bells",
            "4",
            "--rows",
            "4",
            "--rate",
            "192000",
            "--out",
            &wav,
        ])
        .arg("--truth")
        .arg(&truth)
        .output()
        .unwrap();
    let said = String::from_utf8_lossy(&made.stdout).into_owned();
    assert!(made.status.success(), "{}", String::from_utf8_lossy(&made.stderr));
    let nominals = said.split("--nominals ").nth(1).unwrap().trim().to_string();
    let struck = std::fs::read_to_string(&truth).unwrap().lines().count() - 1;
    let heard = Command::cargo_bin("clapper")
        .unwrap()
        .args(["strikes", &wav, "--nominals", &nominals, "--json"])
        .output()
        .unwrap();
    assert!(heard.status.success(), "{}", String::from_utf8_lossy(&heard.stderr));
    let v: serde_json::Value = serde_json::from_slice(&heard.stdout).unwrap();
    let n = v["strikes"].as_array().map_or(0, Vec::len);
    assert_eq!(n, struck, "{struck} struck, {n} heard");
}
