//! `clapper strikes` on README's own recordings (issue 42): the shipped
//! examples/data/tower.wav and a `synth-ring` made as README's example
//! makes it. No double strike where the truth has none, and each bell's
//! odd-struckness within a few ms of what the recording's true strike
//! times give (the band's striking errors make that nonzero: only the
//! difference is the listener's).

mod common;

use std::path::Path;

use clapper_signal::striking::{rhythm, Timed};
use common::clapper;

/// README's nominals (`tower-nominals.json`, as README quotes them).
const NOMINALS: &str = "1400.0,1247.3,1111.2,1048.8,934.4,832.4,741.6,700.0";

/// A truth CSV's strikes (columns `bell`, `t_s`) and doubles (bell, t_s)
/// (column `double_delay_ms` not empty).
fn truth(path: &Path) -> (Vec<Timed>, Vec<(usize, f64)>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| head.iter().position(|h| *h == name).unwrap();
    let (b, t, d) = (col("bell"), col("t_s"), col("double_delay_ms"));
    let (mut strikes, mut doubles) = (vec![], vec![]);
    for line in lines {
        let f: Vec<&str> = line.split(',').collect();
        let s = Timed {
            bell: f[b].parse().unwrap(),
            t: f[t].parse().unwrap(),
        };
        if !f[d].is_empty() {
            doubles.push((s.bell, s.t));
        }
        strikes.push(s);
    }
    (strikes, doubles)
}

/// `clapper strikes FILE --nominals README's --json`.
fn strikes(wav: &Path) -> serde_json::Value {
    let out = clapper()
        .arg("strikes")
        .arg(wav)
        .args(["--nominals", NOMINALS, "--json"])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    serde_json::from_slice(&out.stdout).unwrap()
}

/// The doubles heard are the truth's (same bell, within 25 ms), and the
/// odd-struckness of each bell that struck no double is within `tol_ms`
/// of its true times'. (A double's first strike is timed a few ms late,
/// pulled by its second in the long bands: in tower.wav bell 6's, 7.5 ms
/// at one of its three backstrokes, before this test as after.)
fn heard_as_the_truth_says(j: &serde_json::Value, truth_csv: &Path, tol_ms: f64) {
    let (true_strikes, true_doubles) = truth(truth_csv);
    let strikes = j["strikes"].as_array().unwrap();
    assert_eq!(strikes.len(), true_strikes.len());
    let heard_doubles: Vec<(usize, f64)> = strikes
        .iter()
        .filter(|s| !s["double"].is_null())
        .map(|s| (s["bell"].as_u64().unwrap() as usize, s["t_s"].as_f64().unwrap()))
        .collect();
    assert_eq!(
        heard_doubles.len(),
        true_doubles.len(),
        "doubles heard {heard_doubles:?}, planted {true_doubles:?}"
    );
    for (h, t) in heard_doubles.iter().zip(&true_doubles) {
        assert!(
            h.0 == t.0 && (h.1 - t.1).abs() < 0.025,
            "double heard {h:?}, planted {t:?}"
        );
    }
    let r = rhythm(&true_strikes, 8);
    for bell in (1..=8).filter(|b| true_doubles.iter().all(|d| d.0 != *b)) {
        let own = r.odd_struck(&true_strikes, bell).unwrap() * 1e3;
        let heard = j["per_bell"][bell - 1]["odd_struck_ms"].as_f64().unwrap();
        assert!(
            (heard - own).abs() < tol_ms,
            "bell {bell}: odd-struck {heard:.1} ms heard, {own:.1} ms from the true times"
        );
    }
}

/// tower.wav: bell 8's nominal lies on the treble's prime and bell 5's
/// quint. Timed there, bell 8 read 62 ms early in row 2 (bell 5's
/// odd-struckness +18.9 ms heard against +13.1 ms from the true times,
/// bell 7's +5.6 against -6.0), and a false double on bell 8 in row 4.
#[test]
fn strikes_hears_readmes_tower_recording_as_its_truth() {
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/data");
    let j = strikes(&data.join("tower.wav"));
    heard_as_the_truth_says(&j, &data.join("tower-truth.csv"), 3.0);
}

/// README's `synth-ring --plain-hunt --odd 4:15 --snr 25`: bell 8 was
/// timed 46 ms early in row 13 and its real strike heard as the second of
/// a double ("double strikes 1", none planted).
#[test]
fn strikes_hears_readmes_synthetic_ring_as_its_truth() {
    let dir = tempfile::tempdir().unwrap();
    let (wav, truth_csv) = (dir.path().join("ring.wav"), dir.path().join("truth.csv"));
    let out = clapper()
        .args(["synth-ring", "--plain-hunt", "--odd", "4:15", "--snr", "25", "--out"])
        .arg(&wav)
        .arg("--truth")
        .arg(&truth_csv)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let j = strikes(&wav);
    assert_eq!(j["summary"]["double_strikes"], 0);
    heard_as_the_truth_says(&j, &truth_csv, 3.0);
}
