//! Issue 46's numbers that meant nothing (tower, design-clapper, simulate,
//! ring-up, impulse, restitution, liftoff, contacts): each took exit 0 with
//! inf, NaN, 0 or a runaway allocation; each is now refused at once, in
//! the option's own words and units, on one line (exit 1 or 2).

use assert_cmd::Command;

mod common;
use std::path::{Path, PathBuf};

/// A file of the checkout, by its path from the workspace's root.
fn checkout(path: &str) -> String {
    let p: PathBuf = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..").join(path);
    p.display().to_string()
}

/// `clapper ARGS` fails with one line of standard error holding each of `says`.
fn refused(args: &[&str], says: &[&str]) {
    let out = Command::cargo_bin("clapper").unwrap().args(args).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        matches!(out.status.code(), Some(1 | 2)),
        "{args:?}: {:?} {err}",
        out.status
    );
    for s in says {
        assert!(err.contains(s), "{args:?}: wanted {s:?} in: {err}");
    }
    assert_eq!(err.trim().lines().count(), 1, "{args:?}: {err}");
    assert!(
        !err.contains("inf") && !err.contains("NaN") && !err.contains("0000000000"),
        "{args:?}: {err}"
    );
}

#[test]
fn a_touch_too_long_to_hold_is_refused_before_it_is_made() {
    let ring = checkout("examples/ring-of-eight-tower.toml");
    // Aborted allocating 384 GB.
    refused(
        &["tower", &ring, "--leads", "1000000000", "--method", "Plain Bob Major"],
        &["--leads 1000000000", "20160 changes"],
    );
    // 17 GB in 30 s and climbing.
    refused(
        &["tower", &ring, "--changes", "1000000000"],
        &["--changes 1000000000", "1 to 20160 changes"],
    );
    // A sampling interval that made the histories unbounded.
    refused(
        &["tower", &ring, "--dt", "1e-300"],
        &["--dt 1e-300 s", "0.001 to 0.05 s"],
    );
}

#[test]
fn a_touch_rung_at_no_speed_is_refused_in_its_options_words() {
    let ring = checkout("examples/ring-of-eight-tower.toml");
    for (opt, value, says) in [
        (
            "--peal-speed",
            "1e300",
            "--peal-speed 1e300 h: a peal rung in 1 to 12 hours",
        ),
        (
            "--striking-sd",
            "1e300",
            "--striking-sd 1e300 ms: a band's striking errors from 0 to 200 ms",
        ),
        (
            "--handstroke-gap",
            "1e300",
            "--handstroke-gap 1e300 intervals: from 0 to 4",
        ),
        (
            "--interval",
            "1e300",
            "--interval 1e300 ms: strikes from 20 to 5000 ms apart",
        ),
        (
            "--restitution",
            "-1",
            "--restitution -1: a coefficient of restitution from 0 to 1",
        ),
    ] {
        refused(&["tower", &ring, opt, value], &[says]);
    }
}

#[test]
fn a_clapper_of_no_real_size_is_refused() {
    for (args, says) in [
        (
            vec!["design-clapper", "--ball-position", "1e300", "--ball-diameter", "0.1"],
            "--ball-position 1e300 is out of range: a clapper's ball within 5 m of its pivot",
        ),
        // A 1000 km clapper.
        (
            vec!["design-clapper", "--ball-position", "1e6", "--ball-diameter", "0.1"],
            "a clapper's ball within 5 m of its pivot",
        ),
        (
            vec!["design-clapper", "--shaft-length", "0.5", "--shaft-diameter", "1e300"],
            "--shaft-diameter 1e300 is out of range: a clapper's shaft at most 1 m across",
        ),
        (
            vec![
                "design-clapper",
                "--flight-length",
                "1e300",
                "--flight-diameter",
                "0.03",
            ],
            "--flight-length 1e300 is out of range: a clapper's flight at most 5 m long",
        ),
        (
            vec![
                "design-clapper",
                "--ball-position",
                "4",
                "--ball-diameter",
                "0.5",
                "--flight-length",
                "4",
                "--flight-diameter",
                "0.05",
            ],
            "a clapper whose flight ends within 5 m of its pivot",
        ),
    ] {
        refused(&args, &[says]);
    }
    let tenor: Vec<&str> = std::iter::once("design-clapper")
        .chain(common::TENOR_CLAPPER_PARTS)
        .collect();
    for (opt, says) in [
        (
            "--bell-period",
            "--bell-period 1e300 is out of range: a bell's small-swing period above 0 and at most 10 s",
        ),
        (
            "--pivot",
            "--pivot 1e300 is out of range: a clapper pivot within 5 m of the bell's pivot",
        ),
        (
            "--target-period",
            "--target-period 1e300 is out of range: a clapper's period above 0 and at most 10 s",
        ),
    ] {
        let mut args = tenor.to_vec();
        args.extend([opt, "1e300"]);
        refused(&args, &[says]);
    }
}

#[test]
fn a_ringer_friction_pulse_or_gap_of_no_real_size_is_refused() {
    refused(
        &["simulate", "--preset", "lab", "--clapper-friction", "1e300"],
        &[
            "--clapper-friction 1e300",
            "a million times the clapper's gravity torque",
        ],
    );
    refused(
        &["ring-up", "--preset", "lab", "--wheel-radius", "1e300"],
        &["--wheel-radius 1e300", "at most 3 m"],
    );
    for cmd in ["ring-up", "ring-down"] {
        // Was "simulation failed: non-finite state or derivative at t = 0 s".
        refused(
            &[cmd, "--preset", "lab", "--pull-force", "1e300"],
            &["--pull-force 1e300", "a rope's pull at most 10000 N"],
        );
    }
    // A strong pull is still rung, and the margin tried about it.
    let out = Command::cargo_bin("clapper")
        .unwrap()
        .args(["ring-up", "--preset", "lab", "--pull-force", "9000"])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    refused(
        &["liftoff", "--lb-over-lc", "1e300"],
        &["--lb-over-lc 1e300", "from 0.1 to 10"],
    );
    let modes = checkout("examples/data/modes.csv");
    refused(
        &[
            "impulse",
            "--modes",
            &modes,
            "--clapper-mass",
            "10",
            "--pulse-ms",
            "1e300",
        ],
        &["--pulse-ms 1e300 ms: a half-sine pulse from 0 to 100 ms"],
    );
    refused(
        &["restitution", "--jumps", "1e300,1e300"],
        &["--jumps 1e300: a velocity jump of at most 100000"],
    );
    let contacts = checkout("examples/data/contact.csv");
    refused(
        &["contacts", &contacts, "--min-gap-ms", "1e300"],
        &["--min-gap-ms 1e300 ms: from 0 to 1000 ms"],
    );
}

#[test]
fn a_synthetic_log_offset_is_refused_in_millimetres() {
    // Was "simulation failed: pivot_offset_m = 1e297 is out of range".
    refused(
        &["synth-log", "--out", "x.txt", "--offset-mm", "1e300"],
        &["--offset-mm 1e300 mm: within", "mm either way for this bell"],
    );
}

#[test]
fn a_swing_amplitude_is_refused_as_itself_in_degrees() {
    for cmd in ["simulate", "diagnose"] {
        for which in ["--bell-swings-to-halve", "--clapper-swings-to-halve"] {
            for amplitude in ["1e300", "-10"] {
                let mut args = vec![cmd];
                if cmd == "diagnose" {
                    args.push("../../examples/lab.toml");
                } else {
                    args.extend(["--preset", "lab"]);
                }
                args.extend([which, "40", "--swing-loss", "coulomb", "--swing-amplitude", amplitude]);
                refused(
                    &args,
                    &[
                        &format!("--swing-amplitude {amplitude} is out of range"),
                        "above 0 and at most 90 deg",
                    ],
                );
            }
        }
    }
}
