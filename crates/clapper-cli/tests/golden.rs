//! Results unchanged by refactoring: outputs of `simulate --json`, `chart`
//! CSV, `figures` CSV, `merge`, `diagnose --json` and `synth` against files
//! written by the binary of commit cfb003a (see tests/golden/README.md).

mod common;

use std::path::{Path, PathBuf};

use common::clapper;

fn golden(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/golden").join(rel)
}

fn read(path: &Path) -> Vec<u8> {
    std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Where two byte strings first differ, as a line of text, for the message.
fn first_difference(want: &[u8], got: &[u8]) -> String {
    let (w, g) = (String::from_utf8_lossy(want), String::from_utf8_lossy(got));
    for (k, (a, b)) in w.lines().zip(g.lines()).enumerate() {
        if a != b {
            return format!("line {}:\n  want {a}\n  got  {b}", k + 1);
        }
    }
    format!("lengths {} and {} bytes", want.len(), got.len())
}

fn assert_same(name: &str, want: &[u8], got: &[u8]) {
    assert!(want == got, "{name} changed: {}", first_difference(want, got));
}

fn run_stdout(args: &[&str]) -> Vec<u8> {
    let out = clapper().args(args).output().unwrap();
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    out.stdout
}

#[test]
fn simulate_json_is_unchanged() {
    let cases: [(&str, &[&str]); 9] = [
        ("lab", &["simulate", "--preset", "lab", "--json"]),
        (
            "gsm-wrong",
            &["simulate", "--preset", "gsm-tenor", "--style", "wrong", "--json"],
        ),
        ("fig9d", &["simulate", "--chart-point=-0.005,1.363", "--json"]),
        (
            "lab-penalty",
            &[
                "simulate",
                "--preset",
                "lab",
                "--contact",
                "penalty",
                "--stiffness",
                "1e7",
                "--json",
            ],
        ),
        (
            "lab-free",
            &[
                "simulate",
                "--preset",
                "lab",
                "--protocol",
                "free",
                "--strokes",
                "6",
                "--json",
            ],
        ),
        (
            "lab-dopri5",
            &["simulate", "--preset", "lab", "--integrator", "dopri5", "--json"],
        ),
        ("lab-90", &["simulate", "--preset", "lab", "--theta0", "90", "--json"]),
        (
            "gsm-tower-r005",
            &[
                "simulate",
                "--bell",
                "tests/golden/inputs/gsm-tenor-tower.toml",
                "--restitution",
                "0.05",
                "--json",
            ],
        ),
        (
            "lab-penalty-dopri5-free",
            &[
                "simulate",
                "--preset",
                "lab",
                "--contact",
                "penalty",
                "--protocol",
                "free",
                "--strokes",
                "3",
                "--integrator",
                "dopri5",
                "--json",
            ],
        ),
    ];
    for (name, args) in cases {
        let want = read(&golden(&format!("sim/{name}.json")));
        assert_same(name, &want, &without_added_keys(&run_stdout(args)));
    }
}

/// The JSON with the keys added since the reference was written taken out
/// (each is a line of its own, never an object's last): issue 17's
/// `odd_struck_ms` once at the top and `bdc_to_strike_ms` on every stroke,
/// issue 21's `liftoff_kind` and `no_second_impact` on every stroke, and
/// issue 45's `odd_struck_undefined` (why there is none) and
/// `sustains_instead` (what a bell sustains where the style asked is not,
/// beside `"verdict": "neither"`). Everything else must be
/// the reference, byte for byte; the additions must be there.
fn without_added_keys(got: &[u8]) -> Vec<u8> {
    let text = String::from_utf8(got.to_vec()).unwrap();
    let is_added = |l: &str| {
        let l = l.trim_start();
        l.starts_with("\"odd_struck_ms\": ")
            || l.starts_with("\"odd_struck_undefined\": ")
            || l.starts_with("\"bdc_to_strike_ms\": ")
            || l.starts_with("\"liftoff_kind\": ")
            || l.starts_with("\"no_second_impact\": ")
            || l.starts_with("\"sustains_instead\": ")
    };
    let strokes = text.matches("\"number\": ").count();
    for key in ["\"bdc_to_strike_ms\": ", "\"liftoff_kind\": ", "\"no_second_impact\": "] {
        assert_eq!(text.matches(key).count(), strokes, "{key}: one per stroke");
    }
    assert_eq!(text.matches("\"odd_struck_ms\": ").count(), 1);
    assert_eq!(
        text.contains("\"sustains_instead\": "),
        text.contains("\"verdict\": \"neither\""),
        "sustains_instead where, and only where, the style asked is not sustained"
    );
    let kept: Vec<&str> = text.split_inclusive('\n').filter(|l| !is_added(l)).collect();
    kept.concat().into_bytes()
}

#[test]
fn chart_csv_is_unchanged() {
    let dir = tempfile::tempdir().unwrap();
    let cases: [(&str, &[&str]); 5] = [
        ("impact-16", &["--grid", "16"]),
        ("penalty-6", &["--grid", "6", "--contact", "penalty"]),
        (
            "r005-150-10",
            &[
                "--grid",
                "10",
                "--restitution",
                "0.05",
                "--theta0",
                "150",
                "--quantity",
                "double-strike",
            ],
        ),
        ("dopri5-8", &["--grid", "8", "--integrator", "dopri5"]),
        (
            "axes-6",
            &["--grid", "6", "--theta0", "150,171", "--restitution", "0.1,0.2"],
        ),
    ];
    for (name, args) in cases {
        let csv = dir.path().join(format!("{name}.csv"));
        clapper()
            .arg("chart")
            .args(args)
            .arg("--csv")
            .arg(&csv)
            .assert()
            .success();
        assert_same(name, &read(&golden(&format!("chart/{name}.csv"))), &read(&csv));
    }
}

fn sha256_lines(dir: &Path, names: &[String]) -> String {
    use sha2::Digest as _;
    // `sha256sum`'s format.
    let mut out = String::new();
    for n in names {
        let digest = sha2::Sha256::digest(read(&dir.join(n)));
        let hex: String = digest.iter().map(|b| format!("{b:02x}")).collect();
        out.push_str(&format!("{hex}  {n}\n"));
    }
    out
}

#[test]
fn figures_csv_is_unchanged() {
    let dir = tempfile::tempdir().unwrap();
    clapper()
        .args(["figures", "--grid", "8", "--out"])
        .arg(dir.path())
        .assert()
        .success();
    for name in [
        "chart-base.csv",
        "chart-right-R0.05.csv",
        "chart-right-R0.1.csv",
        "chart-theta0-90.csv",
        "fig07.csv",
    ] {
        assert_same(
            name,
            &read(&golden(&format!("figures/{name}"))),
            &read(&dir.path().join(name)),
        );
    }
    let traces: Vec<String> = ["a", "b", "c", "d"].map(|f| format!("fig09{f}.csv")).to_vec();
    for (f, name) in ["a", "b", "c", "d"].iter().zip(&traces) {
        let head = read(&golden(&format!("figures/fig09{f}-head.csv")));
        let got = read(&dir.path().join(name));
        assert_same(name, &head, &got[..head.len().min(got.len())]);
    }
    let want = String::from_utf8(read(&golden("figures/fig09-traces.sha256"))).unwrap();
    assert_eq!(sha256_lines(dir.path(), &traces), want, "fig09 traces changed");
}

#[test]
fn shards_written_before_the_refactor_still_merge() {
    let dir = tempfile::tempdir().unwrap();
    for f in ["part1.csv", "part1.csv.shard.json", "part2.csv", "part2.csv.shard.json"] {
        std::fs::copy(golden(&format!("shards/{f}")), dir.path().join(f)).unwrap();
    }
    let out = dir.path().join("merged.csv");
    clapper()
        .current_dir(dir.path())
        .args(["merge", "part1.csv", "part2.csv", "--csv", "merged.csv"])
        .assert()
        .success();
    assert_same("merged", &read(&golden("shards/merged.csv")), &read(&out));
    // And a fresh run of the same sweep gives the same bytes as the
    // merge, but for the double strike index that issue 21 follows past
    // the turning point: that run is kept as shards/fresh.csv (README).
    let fresh = dir.path().join("fresh.csv");
    clapper()
        .args(["chart", "--grid", "4", "--theta0", "150,171", "--csv"])
        .arg(&fresh)
        .assert()
        .success();
    assert_same("fresh", &read(&golden("shards/fresh.csv")), &read(&fresh));
}

/// `diagnose --json` without each bell's `"warnings": [...]` lines (added
/// by issue 42, after the files were written: tests/golden/README.md), and
/// how many bells had them.
fn without_warnings(json: &[u8]) -> (Vec<u8>, usize) {
    let text = String::from_utf8_lossy(json);
    let (mut out, mut inside, mut bells) = (String::new(), false, 0);
    for line in text.split_inclusive('\n') {
        if line.trim_start().starts_with("\"warnings\": [") {
            inside = true;
            bells += 1;
        } else if inside && line.trim() == "]," {
            inside = false;
        } else if !inside {
            out.push_str(line);
        }
    }
    (out.into_bytes(), bells)
}

#[test]
fn diagnosis_and_sound_are_unchanged() {
    let (lab, warned) = without_warnings(&run_stdout(&["diagnose", "--preset", "lab", "--json"]));
    assert_eq!(warned, 1, "the lab bell's clapper inertia is warned about");
    assert_same("diagnose-lab", &read(&golden("other/diagnose-lab.json")), &lab);
    let (ring, _) = without_warnings(&run_stdout(&[
        "diagnose",
        "tests/golden/inputs/ring-of-eight.csv",
        "--json",
    ]));
    assert_same("diagnose-ring", &read(&golden("other/diagnose-ring.json")), &ring);
    let dir = tempfile::tempdir().unwrap();
    clapper()
        .current_dir(dir.path())
        .args(["synth", "--preset", "lab", "--strokes", "2", "--out", "s.wav"])
        .assert()
        .success();
    clapper()
        .current_dir(dir.path())
        .args(["synth", "--preset", "lab", "--chime", "--out", "c.wav"])
        .assert()
        .success();
    let want = String::from_utf8(read(&golden("other/synth.sha256"))).unwrap();
    assert_eq!(sha256_lines(dir.path(), &["s.wav".into(), "c.wav".into()]), want);
    let modes = run_stdout(&["modes", dir.path().join("c.wav").to_str().unwrap(), "--json"]);
    assert_same("modes-chime", &read(&golden("other/modes-chime.json")), &modes);
}
