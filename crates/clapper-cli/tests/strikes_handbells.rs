//! `clapper strikes --handbells` (issue 43: "handbells" among the rings
//! strike finding must work on). A handbell sounds its strike note and its
//! twelfth, with no hum, prime or tierce; heard as a tower bell, on an eight
//! from 1400 Hz bell 2 had no partial of its own to be heard in (its tower
//! bell's tierce on bell 7's note, its quint on bell 5's, its note on bell
//! 6's assumed superquint), and 0.72 of the strikes were found within 10 ms.
//! All recordings here are synthetic (`clapper synth-ring --handbells`).

mod common;
use common::{clapper, recall_within};

/// `synth-ring --handbells` on eight in plain hunt with three doubles:
/// the listening command it prints, after `clapper strikes WAV`.
fn handbell_ring(dir: &std::path::Path, seed: &str) -> Vec<String> {
    let out = clapper()
        .current_dir(dir)
        .args([
            "synth-ring",
            "--out",
            "r.wav",
            "--truth",
            "t.csv",
            "--handbells",
            "--plain-hunt",
        ])
        .args(["--rows", "24", "--snr", "25", "--seed", seed])
        .args([
            "--double",
            "2:5:50:0.6",
            "--double",
            "5:11:65:0.8",
            "--double",
            "7:17:80:0.9",
        ])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let said = String::from_utf8_lossy(&out.stdout).to_string() + &String::from_utf8_lossy(&out.stderr);
    let listen = said.rsplit("r.wav ").next().expect("a listening command").trim();
    listen.split_whitespace().map(String::from).collect()
}

fn heard(dir: &std::path::Path, options: &[String]) -> serde_json::Value {
    let out = clapper()
        .current_dir(dir)
        .args(["strikes", "r.wav", "--json"])
        .args(options)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    serde_json::from_slice(&out.stdout).unwrap()
}

/// synth-ring says to listen with `--handbells`, and so heard every bell's
/// strikes are found within 10 ms and the three doubles flagged; the
/// nominals learned (`--bells 8 --handbells`) hear them as well.
#[test]
fn handbells_are_heard_as_handbells() {
    for seed in ["21", "22"] {
        let dir = tempfile::tempdir().unwrap();
        let listen = handbell_ring(dir.path(), seed);
        assert!(listen.iter().any(|o| o == "--handbells"), "{listen:?}");
        let j = heard(dir.path(), &listen);
        let r = recall_within(&j, &dir.path().join("t.csv"), 0.010);
        assert!(r >= 0.98, "seed {seed}: recall within 10 ms {r}");
        assert_eq!(j["summary"]["double_strikes"], 3, "seed {seed}");
        let learned = heard(dir.path(), &["--bells".into(), "8".into(), "--handbells".into()]);
        let r = recall_within(&learned, &dir.path().join("t.csv"), 0.010);
        assert!(r >= 0.98, "seed {seed}, --bells 8: recall within 10 ms {r}");
    }
}

/// `--handbells` is for nominals, given or learned: with templates (each
/// bell's own strike) or `--self-calibrate` (which learns each bell's
/// partials as a tower bell's: an independent tester found the option
/// silently ignored there, two bells timed 76-93 ms early) it is refused.
#[test]
fn handbells_with_templates_or_self_calibration_is_refused() {
    let cases: [(&[&str], &str); 3] = [
        (&["--templates", "."], "--templates"),
        (&["--nominals", "1000,900", "--self-calibrate"], "--self-calibrate"),
        (
            &["--nominals", "1000,900", "--timing", "recording"],
            "--timing recording",
        ),
    ];
    for (other, flag) in cases {
        let out = clapper()
            .args(["strikes", "r.wav", "--handbells"])
            .args(other)
            .output()
            .unwrap();
        assert!(!out.status.success(), "{other:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains("--handbells") && err.contains(flag), "{err}");
    }
}
