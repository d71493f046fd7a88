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

/// The warnings of a `strikes --json` report (its summary's).
pub fn summary_warnings(j: &serde_json::Value) -> Vec<String> {
    j["summary"]["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .map(|w| w.as_str().unwrap().to_string())
        .collect()
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
