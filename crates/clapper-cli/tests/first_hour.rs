//! What a new user meets in the first hour (issue 42), through the built
//! binary: a closed pipe, README's quoted outputs, bells no tower has.

mod common;

use std::process::{Command, Stdio};

/// Run `clapper ARGS` with standard output a pipe whose reader has gone
/// away before clapper writes (as `| head -3` does once it has its lines).
fn with_stdout_closed(args: &[&str]) -> std::process::Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_clapper"))
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    child.wait_with_output().unwrap()
}

/// A closed standard output is a normal end for a pipe: exit 0, nothing on
/// standard error (it was killed by SIGPIPE, exit 141 under `pipefail`).
#[test]
fn a_closed_pipe_is_a_quiet_success() {
    // Outputs larger than a pipe's buffer (64 KiB), so a write must fail.
    for args in [
        &["chart", "--grid", "60", "--csv", "-"][..],
        &["simulate", "--preset", "lab", "--strokes", "400"][..],
        &["simulate", "--preset", "lab", "--strokes", "40", "--json"][..],
    ] {
        let out = with_stdout_closed(args);
        assert_eq!(out.status.code(), Some(0), "{args:?}: {:?}", out.status);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            !err.contains("error") && !err.contains("panicked") && !err.contains("Broken pipe"),
            "{args:?}: {err}"
        );
    }
}

/// The GSM tenor as a tower measures it (examples/gsm-tenor-tower.toml)
/// with one line changed.
fn tenor_with(dir: &std::path::Path, key: &str, value: &str) -> std::path::PathBuf {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../examples/gsm-tenor-tower.toml"
    ))
    .unwrap();
    let line = text.lines().find(|l| l.starts_with(key)).expect(key);
    let path = dir.join(format!("{key}.toml"));
    std::fs::write(&path, text.replace(line, &format!("{key} = {value}"))).unwrap();
    path
}

/// Bells no tower has get a warning that says why, from `simulate` and
/// `diagnose` alike, rather than a confident verdict alone: a clapper
/// period of 5 s beside the bell's 2.33 s, r = 1.79 m (r/L_c 2.3), and
/// phi_max 0.56 (radians typed as degrees).
#[test]
fn bells_no_tower_has_are_warned_about() {
    let dir = tempfile::tempdir().unwrap();
    for (key, value, says) in [
        ("clapper_period_s", "5.0", "a clapper slower than its bell"),
        ("r_m", "1.79", "r/L_c = 2.3"),
        ("phi_max_deg", "0.56", "given in radians? 0.56 rad is 32.1 deg"),
    ] {
        let bell = tenor_with(dir.path(), key, value);
        for cmd in ["simulate", "diagnose"] {
            let args: Vec<&str> = if cmd == "simulate" {
                vec![cmd, "--bell", bell.to_str().unwrap()]
            } else {
                vec![cmd, bell.to_str().unwrap()]
            };
            let out = common::clapper().args(&args).output().unwrap();
            let all = format!(
                "{}{}",
                String::from_utf8_lossy(&out.stdout),
                String::from_utf8_lossy(&out.stderr)
            );
            assert!(
                all.contains(says) && all.contains("warning"),
                "{cmd} {key} = {value}: {all}"
            );
        }
    }
    // The tower's own file gets none of these.
    let out = common::clapper()
        .args([
            "simulate",
            "--bell",
            concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/gsm-tenor-tower.toml"),
        ])
        .output()
        .unwrap();
    assert!(!String::from_utf8_lossy(&out.stderr).contains("outside"), "{out:?}");
}

/// A symmetric bell is evenly struck: "0.0 ms", and no stroke called late
/// (it printed "+0.0 ms (...; handstroke late)" from a 1e-12 ms rounding).
#[test]
fn a_symmetric_bell_is_evenly_struck_in_words_too() {
    let line = odd_struck_line(&["simulate", "--preset", "lab"]);
    assert!(
        line.starts_with("odd-struck: 0.0 ms") && line.contains("evenly struck"),
        "{line}"
    );
    assert!(!line.contains("late"), "{line}");
    // An offset pivot still says which stroke is late.
    let line = odd_struck_line(&["simulate", "--preset", "lab", "--pivot-offset", "0.002"]);
    assert!(line.contains("stroke late"), "{line}");
}

/// The `odd-struck:` line that `clapper ARGS` prints.
fn odd_struck_line(args: &[&str]) -> String {
    let out = common::clapper().args(args).output().unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    text.lines()
        .find(|l| l.starts_with("odd-struck:"))
        .unwrap_or_else(|| panic!("{args:?}: no odd-struck line"))
        .to_string()
}

/// The diagnosis table keeps a long name whole (it cut "GSM tenor (by its
/// parts)" at 12 characters), and a ring's report draws its chart for the
/// ring's own contact angle, not the paper's 26 deg.
#[test]
fn the_diagnosis_shows_whole_names_and_the_rings_own_chart() {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/");
    let out = common::clapper()
        .args(["diagnose", &format!("{root}gsm-tenor-parts.toml")])
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    let row = text
        .lines()
        .find(|l| l.starts_with("GSM tenor (by its parts) "))
        .unwrap_or_else(|| panic!("no table row with the whole name:\n{text}"));
    assert!(row.split_whitespace().count() > 8, "{row}");
    let dir = tempfile::tempdir().unwrap();
    let report = dir.path().join("ring.html");
    common::clapper()
        .args(["diagnose", &format!("{root}ring-of-eight.csv"), "--report"])
        .arg(&report)
        .assert()
        .success();
    let page = std::fs::read_to_string(&report).unwrap();
    // The ring's bells have 28 to 30 deg (examples/ring-of-eight.csv).
    assert!(
        !page.contains("φₘₐₓ = 26°"),
        "the ring drawn on the paper's 26 deg chart"
    );
    assert!(
        page.contains("φₘₐₓ = 28.0°, the bells&apos; median; theirs 28.0 to 30.0°"),
        "no word of the ring's contact angles"
    );
}

/// `diagnose --report -` writes the page to standard output, as its help
/// says (it was refused: "must end in .html").
#[test]
fn a_report_on_standard_output() {
    let out = common::clapper()
        .args(["diagnose", "--preset", "lab", "--report", "-"])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let page = String::from_utf8_lossy(&out.stdout);
    assert!(
        page.trim_start().starts_with("<!DOCTYPE html") || page.contains("<html"),
        "{}",
        &page[..page.len().min(200)]
    );
}

/// A bell whose handstroke contact angle differs is diagnosed (the
/// odd-struckness fix's Newton step asked for an impossible contact angle
/// and failed the whole diagnosis, naming an angle nobody gave, twice).
#[test]
fn an_unequal_contact_angle_is_diagnosed() {
    for hand in ["20", "28"] {
        let out = common::clapper()
            .args(["diagnose", "--preset", "gsm-tenor", "--phi-max-hand", hand])
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "--phi-max-hand {hand}: {err}");
        assert!(String::from_utf8_lossy(&out.stdout).contains("GSM tenor"), "{hand}");
    }
}

/// A gap that tips a contact angle past 90 deg is named as the gap given,
/// not as a contact angle the user never typed (`phi_max_hand_deg =
/// 128.40...`).
#[test]
fn an_impossible_gap_is_named_as_given() {
    let out = common::clapper()
        .args([
            "simulate",
            "--preset",
            "gsm-tenor",
            "--gap-hand",
            "2530",
            "--gap-back",
            "247",
            "--ball-below-pivot",
            "0.8",
        ])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(err.contains("2530") && err.contains("gap"), "{err}");
    assert!(!err.contains("phi_max_hand"), "{err}");
}

/// A ring CSV's empty cell and a misspelt column are named where they are
/// (the empty cell said "bell file is missing phi_max_deg" with the wrong
/// advice; the column "row 1 (line 2)" for a fault of line 1).
#[test]
fn a_ring_csvs_empty_cell_and_misspelt_column_are_placed() {
    let dir = tempfile::tempdir().unwrap();
    let ring =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/ring-of-eight.csv")).unwrap();
    let mut lines: Vec<String> = ring.lines().map(str::to_string).collect();
    // Row 3 (line 4): its phi_max_deg (the fifth cell) emptied.
    let mut cells: Vec<&str> = lines[3].split(',').collect();
    cells[4] = "";
    lines[3] = cells.join(",");
    let empty = dir.path().join("empty.csv");
    std::fs::write(&empty, lines.join("\n")).unwrap();
    let misspelt = dir.path().join("misspelt.csv");
    std::fs::write(&misspelt, ring.replacen("r_m", "r_mm", 1)).unwrap();
    for (file, says) in [
        (&empty, "row 3 (line 4): no phi_max_deg (an empty cell?"),
        (&misspelt, "line 1 (the header): unknown column `r_mm`"),
    ] {
        let out = common::clapper().arg("diagnose").arg(file).output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success() && err.contains(says), "{err}");
    }
}

/// A second shard written to the first one's file is refused, rather than
/// replacing it (the merge then said "shard(s) 1 of 2 missing").
#[test]
fn a_shard_is_not_written_over_another() {
    let dir = tempfile::tempdir().unwrap();
    let shard = |i: &str| {
        common::clapper()
            .current_dir(dir.path())
            .args(["chart", "--shard", i, "--grid", "4", "--csv", "a.csv"])
            .output()
            .unwrap()
    };
    assert!(shard("1/2").status.success());
    let before = std::fs::read(dir.path().join("a.csv")).unwrap();
    let out = shard("2/2");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && err.contains("already holds shard 1 of 2"),
        "{err}"
    );
    assert_eq!(
        std::fs::read(dir.path().join("a.csv")).unwrap(),
        before,
        "shard 1 was replaced"
    );
    // The same shard again is a fresh run of it, as before.
    assert!(shard("1/2").status.success());
}

/// `synth` says which bell did what ("rung full circle: 2 of lab bell" read
/// as nonsense).
#[test]
fn synth_says_which_bell_rang_how() {
    let dir = tempfile::tempdir().unwrap();
    let out = common::clapper()
        .current_dir(dir.path())
        .args(["synth", "--preset", "lab", "--out", "s.wav"])
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.starts_with("lab bell rung full circle, 2 strokes: "), "{text}");
    assert!(text.contains("impact(s), strikes and bounces"), "{text}");
}

/// Odd-struckness compares two strokes of one style: a right handstroke
/// beside a wrong backstroke gives none, with the reason, in text and JSON
/// (it printed -363.7 ms), and a chart leaves it empty wherever a style is
/// not sustained.
#[test]
fn odd_struckness_needs_one_style_at_both_strokes() {
    let line = odd_struck_line(&["simulate", "--chart-point=-0.2,2.3"]);
    assert!(
        line.starts_with("odd-struck: not defined (the handstroke does not sustain"),
        "{line}"
    );
    let v = common::json(&["simulate", "--chart-point=-0.2,2.3"]);
    assert!(v["odd_struck_ms"].is_null(), "{v}");
    assert!(
        v["odd_struck_undefined"].as_str().unwrap().contains("handstroke"),
        "{v}"
    );
    let v = common::json(&["simulate", "--preset", "lab"]);
    assert_eq!(v["odd_struck_ms"], 0.0);
    assert!(v.get("odd_struck_undefined").is_none());
    let out = common::clapper()
        .args(["chart", "--grid", "8", "--pivot-offset", "0.005", "--csv", "-"])
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    // Numbers, a style and true/false: no quoted cells.
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let (sustained, odd) = (col("sustained"), col("odd_struck_ms"));
    let (mut filled, mut empty) = (0, 0);
    for line in lines {
        let row: Vec<&str> = line.split(',').collect();
        if row[sustained].eq_ignore_ascii_case("true") {
            filled += usize::from(!row[odd].is_empty());
        } else {
            assert!(
                row[odd].is_empty(),
                "odd_struck_ms {} where not sustained: {row:?}",
                &row[odd]
            );
            empty += 1;
        }
    }
    assert!(filled > 0 && empty > 0, "{filled} filled, {empty} empty");
}
