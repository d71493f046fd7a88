//! One verdict for a real bell (issue 45), through the built binary: a
//! bell and its mirror image get mirrored answers from `simulate` and
//! `diagnose`, judged from steady ringing (handstroke and backstroke).

mod common;

fn simulate(offset_mm: f64, style: &str) -> serde_json::Value {
    let d = format!("{}", offset_mm * 1e-3);
    common::json(&[
        "simulate",
        "--preset",
        "lab",
        "--style",
        style,
        "--pivot-offset",
        &d,
        "--strokes",
        "4",
    ])
}

/// The lab bell with its clapper pivot ±2, ±5, ±10 mm off: the same verdict
/// both ways, in both styles; the odd-struckness exactly antisymmetric, or
/// null both ways with a reason (it printed +112.8 ms one way and -9.2 ms,
/// a right handstroke minus a wrong backstroke, the other).
#[test]
fn mirror_images_get_mirrored_verdicts_from_simulate() {
    let mut seen = (0, 0);
    for mm in [2.0, 5.0, 10.0] {
        for style in ["right", "wrong"] {
            let (p, m) = (simulate(mm, style), simulate(-mm, style));
            let at = format!("{mm} mm, {style}");
            assert_eq!(p["sustained"], m["sustained"], "verdict at ±{at}: {p} / {m}");
            assert_eq!(p["verdict"], m["verdict"], "±{at}");
            match (p["odd_struck_ms"].as_f64(), m["odd_struck_ms"].as_f64()) {
                (Some(a), Some(b)) => {
                    assert_eq!(a, -b, "antisymmetric at ±{at}");
                    assert_eq!(p["sustained"], true, "odd-struck only where sustained, {at}");
                    seen.0 += 1;
                }
                (None, None) => {
                    for v in [&p, &m] {
                        let why = v["odd_struck_undefined"].as_str();
                        assert!(why.is_some_and(|w| !w.is_empty()), "null without a reason at {at}: {v}");
                    }
                    seen.1 += 1;
                }
                (a, b) => panic!("odd-struck {a:?} at +{at} but {b:?} at -{at}"),
            }
        }
    }
    // Both cases occur, so both branches are tested.
    assert!(seen.0 > 0 && seen.1 > 0, "{seen:?}");
}

/// `diagnose` gives a bell and its mirror image one verdict, and no
/// odd-struckness advice where a style is not sustained.
#[test]
fn mirror_images_get_one_diagnosis() {
    for d in ["0.005", "0.002"] {
        let minus = format!("-{d}");
        let p = common::json(&["diagnose", "--preset", "lab", "--pivot-offset", d]);
        let m = common::json(&["diagnose", "--preset", "lab", "--pivot-offset", &minus]);
        let (p, m) = (bell(&p), bell(&m));
        for k in ["rings_right", "rings_wrong", "verdict", "usual_style"] {
            assert_eq!(p[k], m[k], "{k} at ±{d} mm: {p} / {m}");
        }
        // And the same verdict as simulate.
        let s = common::json(&["simulate", "--preset", "lab", "--pivot-offset", d]);
        assert_eq!(p["rings_right"], s["sustained"], "diagnose and simulate at {d}");
        // The odd-struckness and its advice are of the style the bell
        // sustains (wrong at 5 mm), never of a right handstroke beside a
        // wrong backstroke.
        assert_eq!(p["odd_struck"]["style"], p["usual_style"], "{p}");
    }
}

/// `diagnose --json` at ±2, ±5 and ±10 mm through the binary: the same
/// problems and changes for a bell and its mirror image (+2 mm had listed
/// "strikes softly" and three changes, -2 mm a new clapper only, judged
/// from the handstroke alone), the table showing both strokes, swapped;
/// and at ±5 mm, where it rings only wrong, its odd-struckness in that
/// style, as `simulate --style wrong` gives it.
#[test]
fn diagnose_gives_mirror_images_the_same_problems_and_changes() {
    let strip = |v: &serde_json::Value| {
        let changes: Vec<serde_json::Value> = v["changes"]
            .as_array()
            .unwrap()
            .iter()
            .map(|c| {
                serde_json::json!([
                    c["kind"],
                    c["problems_left"],
                    c["flight_mass_change_kg"],
                    c["clapper_period_s"],
                    c["goes_up"]
                ])
            })
            .collect();
        serde_json::json!([v["verdict"], v["problems"], changes, v["goes_up"]])
    };
    for mm in ["0.002", "0.005", "0.01"] {
        let minus = format!("-{mm}");
        let p = common::json(&["diagnose", "--preset", "lab", "--pivot-offset", mm]);
        let m = common::json(&["diagnose", "--preset", "lab", "--pivot-offset", &minus]);
        let (p, m) = (bell(&p), bell(&m));
        assert_eq!(strip(p), strip(m), "±{mm} m");
        assert_eq!(
            p["double_strike_index"], m["backstroke"]["double_strike_index"],
            "±{mm} m"
        );
        let odd = |v: &serde_json::Value| v["odd_struck"]["odd_struck_ms"].as_f64().unwrap();
        assert_eq!(odd(p), -odd(m), "±{mm} m");
        if mm == "0.005" {
            assert_eq!(p["usual_style"], "wrong");
            let s = common::json(&["simulate", "--preset", "lab", "--style", "wrong", "--pivot-offset", mm]);
            assert_eq!(p["odd_struck"]["odd_struck_ms"], s["odd_struck_ms"]);
            let out = common::clapper()
                .args(["diagnose", "--preset", "lab", "--pivot-offset", mm])
                .output()
                .unwrap();
            let text = String::from_utf8_lossy(&out.stdout);
            assert!(
                text.contains("odd-struck by -35.3 ms (backstroke late), ringing wrong"),
                "{text}"
            );
            assert!(
                text.contains("\n  backstroke "),
                "the table shows the backstroke: {text}"
            );
        }
    }
}

/// `simulate --style right` of a bell that rings only wrong (the pivot
/// ±5 mm off) says so: `sustains_instead` "wrong" beside the verdict
/// "neither" (kept for compatibility), in text and JSON.
#[test]
fn simulate_says_what_a_bell_sustains_instead_of_the_style_asked() {
    for d in ["0.005", "-0.005"] {
        let v = simulate(d.parse::<f64>().unwrap() * 1e3, "right");
        assert_eq!(
            (&v["sustained"], &v["verdict"]),
            (&serde_json::json!(false), &serde_json::json!("neither"))
        );
        assert_eq!(v["sustains_instead"], "wrong", "{d}");
        let w = simulate(d.parse::<f64>().unwrap() * 1e3, "wrong");
        assert!(w.get("sustains_instead").is_none(), "asked what it sustains: {w}");
    }
    let out = common::clapper()
        .args(["simulate", "--preset", "lab", "--pivot-offset", "0.005"])
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("does not sustain ringing right") && text.contains("it sustains ringing wrong instead"),
        "{text}"
    );
}

/// The one bell of a diagnosis, whether the report is a bell or a ring.
fn bell(v: &serde_json::Value) -> &serde_json::Value {
    v.get("bells").and_then(|b| b.get(0)).unwrap_or(v)
}

fn ring_up(point: &str) -> serde_json::Value {
    common::json(&["ring-up", &format!("--chart-point={point}")])
}

/// The ringer sets the bell (issue 45): `ring-up --json` says it ended set,
/// with the angle it rests at on the stay (a few degrees past the balance),
/// and the verdict is judged from the swings before setting; no swing is an
/// impact's few-ms turn at a turning point (swing 18 of this bell lasted
/// 2.7 ms); the rope forces over which the verdict holds are given.
#[test]
fn ring_up_ends_set_at_the_balance() {
    let v = ring_up("0.25,1.2");
    assert_eq!(v["ended"], "set", "{v}");
    let at = v["set_at_deg"].as_f64().unwrap();
    assert!(at > 180.0 && at <= 185.0, "set at {at} deg");
    let swings = v["swings"].as_array().unwrap();
    let last = swings.last().unwrap();
    assert_eq!(last["sets"], true);
    assert_eq!(last["amplitude_deg"].as_f64(), Some(at));
    assert_eq!(v["judged_swings"].as_u64(), Some(swings.len() as u64 - 1));
    for s in swings {
        let d = s["duration_s"].as_f64().unwrap();
        assert!(d > 0.3, "a swing of {d} s: {s}");
        if s["sets"] != true {
            assert!(s["amplitude_deg"].as_f64().unwrap() < 180.0, "{s}");
        }
    }
    // Every swing reaches further than the one before until the set.
    let amps: Vec<f64> = swings.iter().map(|s| s["amplitude_deg"].as_f64().unwrap()).collect();
    assert!(amps.windows(2).all(|w| w[1] > w[0]), "{amps:?}");
    assert_eq!(v["goes_up"], "right");
    let m = &v["pull_margin"];
    assert_eq!(m["knife_edge"], false, "{m}");
    assert!(m["holds_from_n"].as_f64() < m["force_n"].as_f64() && m["holds_to_n"].as_f64() > m["force_n"].as_f64());
}

/// Two bells 1e-6 apart in L_b/L_c went up differently (issue 45): each
/// verdict now says it is on a knife-edge.
#[test]
fn a_knife_edge_ring_up_says_so() {
    let a = ring_up("0.5181818181818183,1.5909090909090908");
    let b = ring_up("0.5181818181818183,1.590910681818182");
    for v in [&a, &b] {
        assert_eq!(v["ended"], "set");
        assert_eq!(v["pull_margin"]["knife_edge"], true, "{}", v["pull_margin"]);
    }
    let out = common::clapper()
        .args(["ring-up", "--chart-point=0.5181818181818183,1.590910681818182"])
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("a knife-edge verdict"), "{text}");
    assert!(text.contains("set at the balance"), "{text}");
}

/// The pull margin's forces print to as many decimals as tell them apart
/// (it said "holds only at ... 15.64 N; it changes at 15.63 N ... and
/// 15.64 N"): every distinct force of the JSON prints distinctly in the
/// text, and no percentage other than the pull's own prints as zero.
#[test]
fn ring_up_margin_prints_its_forces_apart() {
    let point = "--chart-point=0.5181818181818183,1.590910681818182";
    let v = common::json(&["ring-up", point]);
    let m = &v["pull_margin"];
    let mut forces: Vec<f64> = ["force_n", "changes_below_n", "changes_above_n"]
        .iter()
        .filter_map(|k| m[*k].as_f64())
        .collect();
    forces.dedup();
    assert_eq!(forces.len(), 3, "{m}");
    let out = common::clapper().args(["ring-up", point]).output().unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    let line = text.lines().find(|l| l.contains("the verdict holds")).unwrap();
    let printed: Vec<&str> = line
        .split(" N")
        .filter_map(|part| part.rsplit(' ').next())
        .filter(|w| w.parse::<f64>().is_ok())
        .collect();
    let mut distinct = printed.clone();
    distinct.sort();
    distinct.dedup();
    assert_eq!(distinct.len(), 3, "three forces apart: {line}");
    assert!(!line.contains("+0.00 %") && !line.contains("-0.00 %"), "{line}");
}

/// Progress lines count threads in good English: "on 1 thread".
#[test]
fn one_thread_is_one_thread() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("c.csv");
    let runs: [Vec<&str>; 2] = [
        vec![
            "chart",
            "--grid",
            "3",
            "--threads",
            "1",
            "--shard",
            "1/1",
            "--csv",
            csv.to_str().unwrap(),
        ],
        vec!["chart", "--quantity", "goes-up", "--grid", "2", "--threads", "1"],
    ];
    for args in runs {
        let out = common::clapper().args(&args).output().unwrap();
        assert!(out.status.success(), "{args:?}");
        let all = format!(
            "{}{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        );
        assert!(
            all.contains("on 1 thread") && !all.contains("1 threads"),
            "{args:?}: {all}"
        );
    }
}
