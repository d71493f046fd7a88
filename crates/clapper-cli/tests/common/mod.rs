//! Helpers shared by the CLI tests.
#![allow(dead_code)] // each test file uses some of them

use assert_cmd::Command;

/// The built `clapper` binary.
pub fn clapper() -> Command {
    Command::cargo_bin("clapper").unwrap()
}

/// Run `clapper ARGS --json`, require success, parse the output.
pub fn json(args: &[&str]) -> serde_json::Value {
    let out = clapper().args(args).arg("--json").output().unwrap();
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).unwrap()
}

/// `clapper strikes WAV ARGS --json`, never panicking: whether it
/// succeeded, its JSON (Null when it printed none) and its stderr.
pub fn strikes_run(wav: &std::path::Path, args: &[&str]) -> (bool, serde_json::Value, String) {
    let out = clapper()
        .arg("strikes")
        .arg(wav)
        .args(args)
        .arg("--json")
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr).to_string();
    assert!(!err.contains("panicked"), "{err}");
    let j = serde_json::from_slice(&out.stdout).unwrap_or(serde_json::Value::Null);
    (out.status.success(), j, err)
}

/// The warnings of a `strikes --json` report (its summary's).
pub fn summary_warnings(j: &serde_json::Value) -> Vec<String> {
    j["summary"]["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .map(|w| w.as_str().unwrap().to_string())
        .collect()
}

/// The nominals `synth-ring` suggests in what it `said` (the list after
/// "--nominals ", Hz, comma-separated, treble first).
pub fn nominals_said(said: &str) -> &str {
    said.split("--nominals ")
        .nth(1)
        .unwrap()
        .split_whitespace()
        .next()
        .unwrap()
}

/// The nominals (Hz) a `strikes --bells N --json` report learned, in its order.
pub fn learned_nominals(j: &serde_json::Value) -> Vec<f64> {
    j["learned_nominals_hz"]
        .as_array()
        .unwrap()
        .iter()
        .map(|b| b["nominal_hz"].as_f64().unwrap())
        .collect()
}

/// The share of the truth's strikes (a `synth-ring --truth` CSV) that a
/// `strikes --json` report heard on their bell within `tol_s` seconds.
pub fn recall_within(j: &serde_json::Value, truth_csv: &std::path::Path, tol_s: f64) -> f64 {
    let text = std::fs::read_to_string(truth_csv).unwrap();
    let mut lines = text.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| head.iter().position(|h| *h == name).unwrap();
    let (b, t) = (col("bell"), col("t_s"));
    let heard: Vec<(u64, f64)> = j["strikes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| (s["bell"].as_u64().unwrap(), s["t_s"].as_f64().unwrap()))
        .collect();
    let (mut found, mut all) = (0, 0);
    for line in lines {
        let f: Vec<&str> = line.split(',').collect();
        let (bell, time): (u64, f64) = (f[b].parse().unwrap(), f[t].parse().unwrap());
        all += 1;
        if heard.iter().any(|h| h.0 == bell && (h.1 - time).abs() < tol_s) {
            found += 1;
        }
    }
    found as f64 / all as f64
}

/// The tenor's clapper by its parts (README's design-clapper example):
/// shaft, ball and their place, as `design-clapper` options.
pub const TENOR_CLAPPER_PARTS: [&str; 8] = [
    "--shaft-length",
    "0.69",
    "--shaft-diameter",
    "0.05",
    "--ball-diameter",
    "0.14",
    "--ball-position",
    "0.76",
];

/// `n` untuned bells a major scale down from 1000 Hz, each's template (a
/// strike of it alone at `rate` Hz) written to `dir`/t/1.wav, 2.wav, ...:
/// the bells and their templates.
pub fn untuned_templates(
    dir: &std::path::Path,
    n: usize,
    rate: f64,
) -> (Vec<clapper_signal::tower::RingBell>, Vec<clapper_signal::Signal>) {
    let bells = clapper_signal::tower::major_scale(n, 1000.0).unwrap();
    let templates: Vec<clapper_signal::Signal> = bells
        .iter()
        .map(|b| {
            clapper_signal::sampled_ring::UntunedStrike {
                nominal_hz: b.nominal_hz,
                rise_s: 0.01,
                decay_s: 0.6,
                length_s: 1.2,
                blow: None,
            }
            .signal(rate)
        })
        .collect();
    std::fs::create_dir_all(dir.join("t")).unwrap();
    for (i, t) in templates.iter().enumerate() {
        clapper_io::signal_file::write_wav(&dir.join(format!("t/{}.wav", i + 1)), t, 0.9).unwrap();
    }
    (bells, templates)
}
