//! `clapper synth-log` and `clapper ringing-log` through the built binary:
//! a synthetic log read back against its truth, the JSON's names, the
//! plot and CSV, the model beside the log, and bad logs refused.

mod common;

use common::clapper;
use serde_json::Value;
use std::path::{Path, PathBuf};

/// `clapper synth-log` with `args` writes its log to `dir/name.txt` and its
/// truth to `dir/name.json`: their paths.
fn synth_log(dir: &Path, name: &str, args: &[&str]) -> (PathBuf, PathBuf) {
    let (log, truth) = (dir.join(format!("{name}.txt")), dir.join(format!("{name}.json")));
    clapper()
        .args([
            "synth-log",
            "--out",
            log.to_str().unwrap(),
            "--truth",
            truth.to_str().unwrap(),
        ])
        .args(args)
        .assert()
        .success();
    (log, truth)
}

#[test]
fn a_synthetic_log_is_read_back_against_its_truth() {
    let dir = tempfile::tempdir().unwrap();
    let (log, truth) = synth_log(
        dir.path(),
        "tenor",
        &["--offset-mm", "3", "--strokes", "20", "--seed", "4", "--name", "Tenor"],
    );
    let truth: Value = serde_json::from_str(&std::fs::read_to_string(&truth).unwrap()).unwrap();
    let (plot, csv) = (dir.path().join("log.png"), dir.path().join("log.csv"));
    let out = clapper()
        .args(["ringing-log", log.to_str().unwrap(), "--json"])
        .args(["--plot", plot.to_str().unwrap(), "--csv", csv.to_str().unwrap()])
        .args([
            "--bell",
            concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/gsm-tenor-tower.toml"),
        ])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let r: Value = serde_json::from_slice(&out.stdout).unwrap();
    // The names issue 24 asks to keep.
    assert_eq!(r["bell"], "Tenor");
    let kinds: Vec<&str> = r["phases"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["kind"].as_str().unwrap())
        .collect();
    let truth_kinds: Vec<&str> = truth["phases"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["kind"].as_str().unwrap())
        .collect();
    assert_eq!(kinds, truth_kinds);
    for (p, q) in r["phases"]
        .as_array()
        .unwrap()
        .iter()
        .zip(truth["phases"].as_array().unwrap())
    {
        for key in ["start_s", "end_s"] {
            let d = (p[key].as_f64().unwrap() - q[key].as_f64().unwrap()).abs();
            assert!(d < 1.0, "{} {key} off by {d} s", p["kind"]);
        }
    }
    let s = &r["strokes"][10];
    for key in ["bdc_s", "stroke", "strike_s", "bdc_to_strike_ms", "amplitude_deg"] {
        assert!(s.get(key).is_some(), "stroke key {key}");
    }
    let odd = r["odd_struck_ms"].as_f64().unwrap();
    let want = truth["odd_struck_ms"].as_f64().unwrap();
    assert!((odd - want).abs() < 5.0, "odd-struck {odd} ms, truth {want} ms");
    // Beside the model: the offset that gives the log's odd-struckness.
    let d = r["model"]["pivot_offset_for_log_mm"][0].as_f64().unwrap();
    assert!((d - 3.0).abs() < 0.5, "offset {d} mm");
    assert!(std::fs::metadata(&plot).unwrap().len() > 10_000);
    let rows = std::fs::read_to_string(&csv).unwrap();
    assert!(rows.starts_with("bdc_s,stroke,phase,amplitude_deg"));
    assert_eq!(rows.lines().count(), r["strokes"].as_array().unwrap().len() + 1);
    // Clappering starts at the raising's first strike (issue 44; a ringer's
    // tug before it, a smaller jolt, is not a strike).
    let first = truth["strokes"]
        .as_array()
        .unwrap()
        .iter()
        .find(|s| s["phase"] == "raising" && s["strike_s"].is_number())
        .unwrap();
    let (read, want) = (
        r["clappering_starts"]["t_s"].as_f64().unwrap(),
        first["strike_s"].as_f64().unwrap(),
    );
    assert!(
        (read - want).abs() <= 0.011,
        "clappering starts at {read} s, truth {want} s"
    );
    // A bell's log looks like one: no plausibility warning.
    assert_eq!(r["plausibility"]["plausible"], true, "{}", r["plausibility"]);
    let warnings = r["warnings"].as_array().unwrap();
    assert!(
        !warnings
            .iter()
            .any(|w| w.as_str().unwrap().contains("does not look like")),
        "{warnings:?}"
    );
}

/// Standard normal numbers from `seed`: a seeded PCG and Box-Muller, the
/// same noise every run.
fn gaussian(seed: u64) -> impl FnMut() -> f64 {
    let mut rng = <rand_pcg::Pcg64 as rand::SeedableRng>::seed_from_u64(seed);
    let mut uniform = move || 1.0 - rand::Rng::random::<f64>(&mut rng);
    move || (-2.0 * uniform().ln()).sqrt() * (std::f64::consts::TAU * uniform()).cos()
}

/// Gravity with noise on it, and a shaking three times a second, are read
/// with the magnitude of gravity and a continuous angle, yet their "swings"
/// are no pendulum's (irregular, or 0.5 s from bottom to bottom): not read
/// as ringing (an independent tester's inputs; before, 31 and 600 swings).
/// Noise of four seeds: each either refused or read as at most two tiny
/// swings, and the swings' timing refuses at least one.
#[test]
fn gravity_with_noise_or_a_fast_shake_is_not_read_as_a_ringing_log() {
    let dir = tempfile::tempdir().unwrap();
    let read = |name: &str, text: String| -> Value {
        let path = dir.path().join(format!("{name}.txt"));
        std::fs::write(&path, text + "Not a bell\n").unwrap();
        let out = clapper()
            .args(["ringing-log", path.to_str().unwrap(), "--json"])
            .output()
            .unwrap();
        assert!(out.status.success(), "{name}: {}", String::from_utf8_lossy(&out.stderr));
        serde_json::from_slice(&out.stdout).unwrap()
    };
    let mut by_timing = 0;
    for seed in 1..=4u64 {
        let mut gauss = gaussian(0x2545_F491_4F6C_DD1Du64.wrapping_mul(seed));
        let mut noisy = String::new();
        for k in 0..30_000 {
            let (x, y, z) = (gauss(), 9.81 + gauss(), gauss());
            noisy += &format!("{x:.3} {y:.3} {z:.3} {}\n", 10 * k);
        }
        let r = read(&format!("noisy-{seed}"), noisy);
        let swings = r["strokes"].as_array().unwrap().len();
        let plausible = r["plausibility"]["plausible"] == true;
        assert!(
            !plausible || swings <= 2,
            "seed {seed}: {swings} swings, {}",
            r["plausibility"]
        );
        assert!(r["odd_struck_ms"].is_null(), "seed {seed}");
        if !plausible && r["warnings"].to_string().contains("pendulum") {
            by_timing += 1;
        }
    }
    assert!(by_timing >= 1, "no noisy log was refused by its swings' timing");
    let mut shake = String::new();
    for k in 0..30_000 {
        let a = std::f64::consts::TAU * 3.0 * k as f64 / 100.0;
        shake += &format!("0.000 {:.3} {:.3} {}\n", 9.81 + 5.0 * a.sin(), 5.0 * a.cos(), 10 * k);
    }
    let r = read("shake", shake);
    assert_eq!(r["plausibility"]["plausible"], false, "{}", r["plausibility"]);
    assert_eq!(r["strokes"].as_array().unwrap().len(), 0);
    assert!(
        r["warnings"].to_string().contains("half a pendulum's period"),
        "{}",
        r["warnings"]
    );
}

/// Issue 46: Gaussian noise was read as "739 swings, odd-struck -62.5 ms".
/// Noise of 1 m/s² (far from gravity's magnitude) and of 9.81 m/s² (about
/// gravity's, but an angle that jumps about at random) are both said not to
/// look like a ringing log, in text and JSON, and no swing is read from them.
#[test]
fn gaussian_noise_is_not_read_as_a_ringing_log() {
    let dir = tempfile::tempdir().unwrap();
    let mut gauss = gaussian(0x9E37_79B9_7F4A_7C15);
    for sd in [1.0, 9.81] {
        let mut text = String::new();
        for k in 0..30_000 {
            let v: Vec<f64> = (0..3).map(|_| sd * gauss()).collect();
            text += &format!("{:.4} {:.4} {:.4} {}\n", v[0], v[1], v[2], 10 * k);
        }
        text += "Noise\n";
        let path = dir.path().join(format!("noise-{sd}.txt"));
        std::fs::write(&path, text).unwrap();
        let out = clapper()
            .args(["ringing-log", path.to_str().unwrap()])
            .output()
            .unwrap();
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        let said = String::from_utf8_lossy(&out.stdout);
        assert!(said.contains("does not look like a ringing log"), "sd {sd}: {said}");
        assert!(!said.contains("odd-struck"), "sd {sd}: {said}");
        let out = clapper()
            .args(["ringing-log", path.to_str().unwrap(), "--json"])
            .output()
            .unwrap();
        let r: Value = serde_json::from_slice(&out.stdout).unwrap();
        assert_eq!(r["plausibility"]["plausible"], false, "sd {sd}");
        assert!(r["odd_struck_ms"].is_null(), "sd {sd}");
        assert!(r["clappering_starts"].is_null(), "sd {sd}");
        assert_eq!(r["strokes"].as_array().unwrap().len(), 0, "sd {sd}");
        assert!(
            r["warnings"]
                .as_array()
                .unwrap()
                .iter()
                .any(|w| w.as_str().unwrap().contains("does not look like a ringing log")),
            "sd {sd}: {}",
            r["warnings"]
        );
    }
}

#[test]
fn bad_logs_are_refused_with_a_reason() {
    let dir = tempfile::tempdir().unwrap();
    let clipped: String = (0..200).map(|k| format!("0 19.62 19.62 {}\n", k * 10)).collect();
    for (name, text, says) in [
        ("empty.txt", String::new(), "empty"),
        ("one.txt", "1\n2\n3\n".to_string(), "1 column(s)"),
        ("text.txt", "hello\nworld\n".to_string(), "empty"),
        (
            "back.txt",
            "0 9.8 0 0\n0 9.8 0 10\n0 9.8 0 5\n".to_string(),
            "backwards",
        ),
        ("clipped.txt", clipped, "clipped"),
    ] {
        let path = dir.path().join(name);
        std::fs::write(&path, text).unwrap();
        let out = clapper()
            .args(["ringing-log", path.to_str().unwrap()])
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(1), "{name}: an error, not a panic");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(says), "{name}: {err}");
    }
    let out = clapper()
        .args(["ringing-log", "x.txt", "--axes", "y,y"])
        .output()
        .unwrap();
    assert!(String::from_utf8_lossy(&out.stderr).contains("--axes"));
}

/// Issue 44: a sensor mounted upside down on the default axes (as
/// belfry-sleuth's Data141 reads: y is −g at rest down) is turned over by
/// default, its small swings telling which way is down; `--axes` given
/// takes the axes as they are.
#[test]
fn a_log_upside_down_is_read_right_way_up_by_default() {
    let dir = tempfile::tempdir().unwrap();
    let (log, truth) = synth_log(dir.path(), "log", &["--strokes", "6", "--seed", "2"]);
    // y (radial) negated: upside down and mirrored, as Data141.
    let text: String = std::fs::read_to_string(&log)
        .unwrap()
        .lines()
        .map(|l| {
            let mut c: Vec<String> = l.split_whitespace().map(String::from).collect();
            if c.len() >= 4 {
                let y: f64 = c[1].parse().unwrap();
                c[1] = format!("{:.3}", -y);
            }
            c.join(" ") + "\n"
        })
        .collect();
    let flipped = dir.path().join("flipped.txt");
    std::fs::write(&flipped, text).unwrap();
    let truth: Value = serde_json::from_str(&std::fs::read_to_string(&truth).unwrap()).unwrap();
    let kinds = |r: &Value| -> Vec<String> {
        r["phases"]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| p["kind"].as_str().unwrap().to_string())
            .collect()
    };
    let read = |extra: &[&str]| -> Value {
        let out = clapper()
            .args(["ringing-log", flipped.to_str().unwrap(), "--json"])
            .args(extra)
            .output()
            .unwrap();
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        serde_json::from_slice(&out.stdout).unwrap()
    };
    let r = read(&[]);
    assert_eq!(kinds(&r), kinds(&truth));
    assert!(
        r["warnings"]
            .as_array()
            .unwrap()
            .iter()
            .any(|w| w.as_str().unwrap().contains("upside down")),
        "{}",
        r["warnings"]
    );
    // Each ringing bottom beside the moment of greatest speed (issue 44's
    // check, which needs no zero of the angle), with its standard error key.
    let ringing: Vec<&Value> = r["strokes"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|s| s["phase"] == "ringing")
        .collect();
    assert!(!ringing.is_empty());
    for s in &ringing {
        let gap = (s["bdc_s"].as_f64().unwrap() - s["speed_peak_s"].as_f64().unwrap()).abs();
        assert!(gap < 0.005, "bottom {} s from the greatest speed", gap);
        assert!(s.get("bdc_se_ms").is_some());
    }
    // The axes given are taken as given: upside down, "down" reads "up".
    let given = read(&["--axes", "y,z"]);
    assert_eq!(kinds(&given)[0], "up", "{:?}", kinds(&given));
    // And given the right way, as read by default.
    assert_eq!(kinds(&read(&["--axes", "-y,z"])), kinds(&truth));
}

/// Issue 44: a log rung with stands on the stay and lowered straight on
/// from the ringing (from the project's generator, written as belfry-sleuth
/// writes): the phases are named as the issue names them (set, ringing
/// with stands, then lowering), each stroke that rose onto the stay says
/// so in JSON (its angle, how long it stood), CSV and text, and the
/// odd-struckness's standard error gives the calibration's share.
#[test]
fn stands_and_phases_are_reported_per_stroke() {
    use clapper_signal::ringing_log_synth::{synth_log, LogSpec};
    let mut spec = LogSpec::new(clapper_core::bell::Bell::gsm_tenor(), 2);
    spec.sensor.along = 0.2;
    spec.strokes = 12;
    spec.rest_s = 6.0;
    spec.set_s = 5.0;
    (spec.ring, spec.ring_s) = (0.3, 0.25);
    spec.stand_every = 2;
    spec.stand_s = 2.0;
    spec.stay = 4f64.to_radians();
    spec.free_s = 25.0;
    let (mut log, truth) = synth_log(&spec).unwrap();
    log.name = Some("Bell 3".into());
    let dir = tempfile::tempdir().unwrap();
    let (path, csv) = (dir.path().join("stands.txt"), dir.path().join("stands.csv"));
    std::fs::write(&path, clapper_io::accel_log::write_sleuth_log(&log)).unwrap();
    let out = clapper()
        .args([
            "ringing-log",
            path.to_str().unwrap(),
            "--json",
            "--csv",
            csv.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let r: Value = serde_json::from_slice(&out.stdout).unwrap();
    let names: Vec<&str> = r["phases"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["name"].as_str().unwrap())
        .collect();
    assert_eq!(&names[..3], ["down", "raising", "set"], "{names:?}");
    assert_eq!(names[3], "ringing with stands", "{names:?}");
    assert!(names.contains(&"lowering"), "{names:?}");
    // Each ringing stroke that rose onto the stay: the next falls from
    // past the balance.
    let strokes = r["strokes"].as_array().unwrap();
    let mut stood = 0;
    for (i, t) in truth.strokes.iter().enumerate() {
        let Some(next) = truth.strokes.get(i + 1) else { continue };
        if t.phase != clapper_signal::ringing_log::PhaseKind::Ringing
            || next.phase != clapper_signal::ringing_log::PhaseKind::Ringing
        {
            continue;
        }
        let s = strokes
            .iter()
            .find(|s| (s["bdc_s"].as_f64().unwrap() - t.bdc).abs() < 0.1)
            .expect("the stroke read");
        if next.amplitude > std::f64::consts::PI {
            stood += 1;
            let angle = s["stand"]["angle_deg"].as_f64().expect("a stand");
            assert!((angle - next.amplitude.to_degrees()).abs() <= 2.0, "{s}");
            assert!(s["stand"]["duration_s"].as_f64().unwrap() > 0.0, "{s}");
        } else {
            assert!(s["stand"].is_null(), "{s}");
        }
    }
    assert!(stood >= 4, "{stood} stands");
    let se = r["odd_struck_se_ms"].as_f64().unwrap();
    let cal = r["odd_struck_calibration_se_ms"].as_f64().unwrap();
    assert!(cal > 0.0 && cal <= se, "{cal} of {se}");
    // The CSV's stand columns, one stand a stroke that stood.
    let text = std::fs::read_to_string(&csv).unwrap();
    let head: Vec<&str> = text.lines().next().unwrap().split(',').collect();
    let col = head.iter().position(|h| *h == "stand_deg").expect("stand_deg");
    assert!(head.contains(&"stand_s"));
    let rows = text
        .lines()
        .skip(1)
        .filter(|l| !l.split(',').nth(col).unwrap().is_empty())
        .count();
    assert!(rows >= stood, "{rows} rows with a stand");
    // And the text says where each stand was.
    let out = clapper()
        .args(["ringing-log", path.to_str().unwrap()])
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("ringing with stands"), "{text}");
    assert!(text.matches("stand after the").count() >= stood, "{text}");
    assert!(text.contains("the calibration's share"), "{text}");
}

/// A log `clapper synth-log` makes with its sensor 0.5 m above the pivot
/// (κ = h/L about 0.37 on its GSM tenor: the radial reading's centripetal
/// part, h θ'², near gravity's at a full swing's bottom) read back by
/// `clapper ringing-log` with default options: every ringing swing
/// found, its bottom within a sample, the odd-struckness within 3 ms, and
/// the sensor's place read from the falls within 2 cm. (At 0.6 m the same
/// generator's logs lose one to four ringing swings and bottoms read 6-7
/// samples off; at 0.8 m no ringing swing is found: issue 44's far
/// sensors, not yet met.)
#[test]
fn a_log_with_the_sensor_half_a_metre_from_the_pivot_is_read_back() {
    let dir = tempfile::tempdir().unwrap();
    let (log, truth) = synth_log(
        dir.path(),
        "far",
        &["--sensor-m", "0.5", "--strokes", "16", "--seed", "2"],
    );
    let truth: Value = serde_json::from_str(&std::fs::read_to_string(&truth).unwrap()).unwrap();
    let out = clapper()
        .args(["ringing-log", log.to_str().unwrap(), "--json"])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let r: Value = serde_json::from_slice(&out.stdout).unwrap();
    let interval = 1.0 / truth["rate_hz"].as_f64().unwrap();
    let read: Vec<f64> = r["strokes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["bdc_s"].as_f64().unwrap())
        .collect();
    let ringing: Vec<f64> = truth["strokes"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|s| s["phase"] == "ringing")
        .map(|s| s["bdc_s"].as_f64().unwrap())
        .collect();
    assert_eq!(ringing.len(), 16);
    for t in &ringing {
        let off = read.iter().map(|b| (b - t).abs()).fold(f64::INFINITY, f64::min);
        assert!(
            off <= interval,
            "ringing bottom at {t:.3} s read {:.2} samples off",
            off / interval
        );
    }
    let (o, want) = (
        r["odd_struck_ms"].as_f64().expect("read"),
        truth["odd_struck_ms"].as_f64().unwrap(),
    );
    assert!((o - want).abs() <= 3.0, "odd-struck {o:.1} ms, truth {want:.1}");
    let h = r["sensor_m"].as_f64().unwrap();
    assert!((h - 0.5).abs() <= 0.02, "sensor read {h} m above the pivot");
}
