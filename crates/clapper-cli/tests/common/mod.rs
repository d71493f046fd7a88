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
