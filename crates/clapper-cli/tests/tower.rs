//! `clapper tower` (issue 47), through the built binary.

mod common;
use common::{clapper, json};
use predicates::prelude::*;

const RING: &str = "../../examples/ring-of-eight-tower.toml";

/// One column of a history CSV.
fn column(csv: &str, name: &str) -> Vec<f64> {
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let i = header.iter().position(|h| *h == name).unwrap();
    lines.map(|l| l.split(',').nth(i).unwrap().parse().unwrap()).collect()
}

/// The example ring through two leads of Plain Bob Major: the report in
/// text and JSON, the histories, the spectrum and the plot all written.
#[test]
fn two_leads_of_plain_bob_major_written_and_plotted() {
    let dir = tempfile::tempdir().unwrap();
    let (csv, spec, plot) = (
        dir.path().join("h.csv"),
        dir.path().join("s.csv"),
        dir.path().join("p.png"),
    );
    let base = [
        "tower",
        RING,
        "--method",
        "Plain Bob Major",
        "--leads",
        "2",
        "--striking-sd",
        "15",
    ];
    let mut args: Vec<&str> = base.to_vec();
    args.extend(["--csv", csv.to_str().unwrap(), "--spectrum-csv", spec.to_str().unwrap()]);
    args.extend(["--plot", plot.to_str().unwrap()]);
    let v = json(&args);
    assert_eq!(v["rows"], 33);
    assert_eq!(v["first_row"], "12345678");
    // Two plain leads of Plain Bob Major come to its second lead head.
    assert_eq!(v["last_row"], "15738264");
    assert_eq!(v["bells"].as_array().unwrap().len(), 8);
    let sway = v["sway"].as_array().unwrap();
    assert_eq!(sway.len(), 2);
    assert_eq!(sway[1]["direction"], "north-south");
    // Every bell swings north-south: nothing east-west.
    assert!(v["peaks"]["force_east_n"].as_f64().unwrap() < 1e-9);
    assert!(v["peak_sway_m"].as_f64().unwrap() > 1e-4);
    assert_eq!(v["turns"].as_array().unwrap().len(), 8);
    let text = std::fs::read_to_string(&csv).unwrap();
    assert!(text.starts_with("time_s,force_east_n,force_north_n,vertical_n,"));
    assert!(text.lines().count() > 7000);
    assert!(std::fs::read_to_string(&spec)
        .unwrap()
        .starts_with("frequency_hz,east_n,north_n"));
    assert_eq!(&std::fs::read(&plot).unwrap()[1..4], b"PNG");
    clapper()
        .args(base)
        .assert()
        .success()
        .stdout(predicate::str::contains("Plain Bob Major, 2 lead(s): 33 rows"))
        .stdout(predicate::str::contains("sway north-south: tower 1.650 Hz"))
        .stdout(predicate::str::contains("a bell turned 90° changes the peak sway"));
}

/// Turning the 7th and tenor east-west: what leaves the north-south force
/// is exactly the east-west force (the forces add, each along its bell's
/// swing), and the peak sway changes.
#[test]
fn turning_two_bells_moves_their_force_to_the_other_direction() {
    let dir = tempfile::tempdir().unwrap();
    let (a, b) = (dir.path().join("a.csv"), dir.path().join("b.csv"));
    let run = |path: &std::path::Path, turn: &[&str]| {
        let mut args = vec![
            "tower",
            RING,
            "--method",
            "Plain Bob Major",
            "--leads",
            "2",
            "--striking-sd",
            "15",
        ];
        args.extend(turn);
        args.extend(["--csv", path.to_str().unwrap()]);
        json(&args)
    };
    let va = run(&a, &[]);
    let vb = run(&b, &["--turn", "7,8"]);
    let (a, b) = (
        std::fs::read_to_string(&a).unwrap(),
        std::fs::read_to_string(&b).unwrap(),
    );
    let (na, nb, eb) = (
        column(&a, "force_north_n"),
        column(&b, "force_north_n"),
        column(&b, "force_east_n"),
    );
    assert_eq!(na.len(), nb.len());
    let mut moved = 0.0f64;
    for i in 0..na.len() {
        assert!(
            (na[i] - nb[i] - eb[i]).abs() < 0.03,
            "sample {i}: {} - {} vs {}",
            na[i],
            nb[i],
            eb[i]
        );
        moved = moved.max(eb[i].abs());
    }
    assert!(moved > 5000.0, "the two heaviest bells' force: {moved} N");
    let (pa, pb) = (va["peak_sway_m"].as_f64().unwrap(), vb["peak_sway_m"].as_f64().unwrap());
    assert!((pa - pb).abs() > 0.02 * pa, "{pa} vs {pb}");
    assert_eq!(vb["bells"][7]["place"]["swing_deg"], 90.0);
}

/// The ring as a plain CSV (no frame, no tower): forces only, and what was
/// assumed is said.
#[test]
fn a_ring_without_its_frame_or_tower_gives_forces_and_says_what_it_assumed() {
    clapper()
        .args(["tower", "../../examples/ring-of-eight.csv", "--changes", "16"])
        .assert()
        .success()
        .stdout(predicate::str::contains("rounds, 16 rows"))
        .stdout(predicate::str::contains("no tower given"))
        .stdout(predicate::str::contains("assumed: swing N-S (0 deg) for treble, 2,"))
        .stdout(predicate::str::contains("a bell turned 90° changes the peak force"));
}

/// Methods on the ring's bells: Stedman Triples with the tenor covering
/// comes to its lead head 6347251 after a lead; rows from a file.
#[test]
fn stedman_triples_covered_and_rows_from_a_file() {
    let v = json(&["tower", RING, "--method", "Stedman Triples", "--leads", "1"]);
    assert_eq!(v["rows"], 13);
    assert_eq!(v["last_row"], "63472518");
    let dir = tempfile::tempdir().unwrap();
    let rows = dir.path().join("rows.txt");
    std::fs::write(&rows, "# plain hunt\n12345678\n21436587\n24163857\n42618375\n").unwrap();
    let v = json(&["tower", RING, "--rows", rows.to_str().unwrap()]);
    assert_eq!(v["rows"], 4);
    assert_eq!(v["last_row"], "42618375");
}

#[test]
fn bad_methods_rows_and_turns_are_named() {
    clapper()
        .args(["tower", RING, "--method", "Plain Bobb Major"])
        .assert()
        .failure()
        .stderr(predicate::str::contains("no method 'Plain Bobb Major'"))
        .stderr(predicate::str::contains("Plain Bob Major"));
    clapper()
        .args(["tower", RING, "--turn", "9"])
        .assert()
        .failure()
        .stderr(predicate::str::contains("--turn 9: bells count from 1 to 8"));
    let dir = tempfile::tempdir().unwrap();
    let rows = dir.path().join("rows.txt");
    std::fs::write(&rows, "12345678\n12345677\n").unwrap();
    clapper()
        .args(["tower", RING, "--rows", rows.to_str().unwrap()])
        .assert()
        .failure()
        .stderr(predicate::str::contains("row 2 (12345677) is not an order"));
}
