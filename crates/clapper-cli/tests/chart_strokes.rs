//! `clapper chart` says how many strokes it simulated where a bell with a
//! pivot offset or unequal contact angles rings its backstroke too (issue 45: the price of an extension is
//! per stroke simulated, not per chart point).

mod common;

use common::clapper;

/// The summary line of `clapper chart ARGS` (with `--csv FILE` if given)
/// and the number of strokes simulated it states, if it states one.
fn summary(dir: &std::path::Path, args: &[&str]) -> (String, Option<u64>) {
    let out = clapper()
        .current_dir(dir)
        .args(["chart", "--threads", "1"])
        .args(args)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    let line = text
        .lines()
        .find(|l| l.contains("strokes in"))
        .unwrap_or_else(|| panic!("no summary line in {text}"))
        .to_string();
    let rung = line
        .split(", ")
        .find_map(|part| part.strip_suffix(" strokes simulated)"))
        .map(|n| n.parse().unwrap());
    (line, rung)
}

#[test]
fn a_chart_of_an_asymmetric_bell_counts_its_backstrokes() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // Ideal bells: one stroke a cell, and the line as it always was.
    let (line, rung) = summary(d, &["--grid", "6"]);
    assert!(line.starts_with("  72 strokes in "), "{line}");
    assert_eq!(rung, None, "{line}");
    // A pivot offset: a backstroke after every handstroke that keeps its
    // style, so more strokes than cells, at most two each.
    let offset = ["--grid", "6", "--pivot-offset", "0.003"];
    let (line, rung) = summary(d, &offset);
    let rung = rung.unwrap_or_else(|| panic!("no count of strokes simulated: {line}"));
    assert!(line.starts_with("  72 strokes in "), "{line}");
    assert!(rung > 72 && rung <= 144, "{line}");
    // A sustained cell needs both strokes: at least one more stroke for
    // each, read from the CSV of the same chart (written through the
    // resumable sweep, which counts on its own path).
    let mut with_csv = offset.to_vec();
    with_csv.extend(["--csv", "f.csv"]);
    let (line_csv, rung_csv) = summary(d, &with_csv);
    assert_eq!(rung_csv, Some(rung), "{line_csv} against {line}");
    let csv = std::fs::read_to_string(d.join("f.csv")).unwrap();
    let sustained = csv
        .lines()
        .skip(1)
        .filter(|l| l.split(',').nth(3) == Some("true"))
        .count() as u64;
    assert!(sustained > 0, "{csv}");
    assert!(rung >= 72 + sustained, "{rung} strokes for {sustained} sustained cells");
}

/// Friction and damping keep a bell its own mirror image: its chart takes
/// the backstroke by symmetry, one stroke a cell, with or without a CSV,
/// and says what ringing both strokes said (the odd-struckness column,
/// 0 where the style is sustained and the bell strikes).
#[test]
fn a_chart_of_a_bell_with_friction_rings_one_stroke_a_cell() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    for friction in [
        ["--clapper-friction", "0.05"],
        ["--bell-damping", "0.5"],
        ["--bell-friction", "2"],
    ] {
        let mut args = vec!["--grid", "6"];
        args.extend(friction);
        let (line, rung) = summary(d, &args);
        assert!(line.starts_with("  72 strokes in "), "{line}");
        assert_eq!(rung, None, "{friction:?}: {line}");
        args.extend(["--csv", "f.csv"]);
        let (line, rung) = summary(d, &args);
        assert_eq!(rung, None, "{friction:?}: {line}");
        let csv = std::fs::read_to_string(d.join("f.csv")).unwrap();
        let head = csv.lines().next().unwrap();
        let col = head.split(',').position(|c| c == "odd_struck_ms").unwrap();
        let mut sustained = 0;
        for l in csv.lines().skip(1) {
            let f: Vec<&str> = l.split(',').collect();
            if f[3] == "true" && !f[4].is_empty() {
                assert_eq!(f[col].parse::<f64>(), Ok(0.0), "{friction:?}: {l}");
                sustained += 1;
            } else {
                assert_eq!(f[col], "", "{friction:?}: {l}");
            }
        }
        assert!(sustained > 0, "{csv}");
    }
}
