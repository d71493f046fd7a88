//! Sweeps beyond one run: shards merged, interrupted runs resumed.

mod common;

use std::time::Duration;

use common::clapper;

fn run(dir: &std::path::Path, args: &[&str]) -> String {
    let out = clapper().current_dir(dir).args(args).output().unwrap();
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

#[test]
fn merged_shards_are_the_single_run_byte_for_byte() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    for (opts, n) in [
        (vec!["--grid", "13x7"], 3),
        // Extra axes, more shards than charts, shards that cut charts.
        (
            vec![
                "--grid",
                "5x4",
                "--theta0",
                "120,171",
                "--restitution",
                "0.1,0.3",
                "--style",
                "right",
            ],
            7,
        ),
    ] {
        let mut whole = vec!["chart", "--csv", "whole.csv"];
        whole.extend(&opts);
        run(d, &whole);
        let mut names = vec![];
        // Shards in a scrambled order, as a scheduler might finish them.
        for i in (1..=n).rev() {
            let name = format!("part{i}.csv");
            let shard = format!("{i}/{n}");
            let mut a = vec!["chart", "--csv", &name, "--shard", &shard];
            a.extend(&opts);
            run(d, &a);
            names.push(name);
        }
        // Their descriptions kept, for the refusals below.
        let mut m = vec!["merge", "--csv", "merged.csv", "--keep-shard-json"];
        m.extend(names.iter().map(String::as_str));
        run(d, &m);
        let (a, b) = (
            std::fs::read(d.join("whole.csv")).unwrap(),
            std::fs::read(d.join("merged.csv")).unwrap(),
        );
        assert!(a == b, "{opts:?}: merged shards differ from the single run");
        assert!(a.len() > 100);
    }
    // A missing shard, or one of another sweep, is refused by name.
    let out = clapper()
        .current_dir(d)
        .args(["merge", "--csv", "x.csv", "part1.csv", "part2.csv"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && err.contains("missing"), "{err}");
    assert!(!d.join("x.csv").exists());
}

#[test]
fn a_killed_run_resumes_to_the_same_bytes() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let opts = ["--grid", "60", "--block", "300", "--threads", "1"];
    let mut fresh = vec!["chart", "--csv", "fresh.csv"];
    fresh.extend(opts);
    run(d, &fresh);

    let mut args = vec!["chart", "--csv", "out.csv"];
    args.extend(opts);
    let mut child = std::process::Command::new(assert_cmd::cargo::cargo_bin("clapper"))
        .current_dir(d)
        .args(&args)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    // Kill it (SIGKILL: no chance to tidy up) once a few blocks are done.
    let journal = d.join("out.csv.partial.json");
    // The sweep is finite: it reaches 900 strokes or ends (checked below).
    loop {
        if let Ok(text) = std::fs::read_to_string(&journal) {
            if let Ok(v) = serde_json::from_str::<serde_json::Value>(&text) {
                if v["done"].as_u64().unwrap_or(0) >= 900 {
                    break;
                }
            }
        }
        assert!(
            child.try_wait().unwrap().is_none(),
            "the run finished before it could be killed"
        );
        std::thread::sleep(Duration::from_millis(2));
    }
    // A second run of the same sweep while the first works is refused
    // (found by hand: two runs interleaved their blocks).
    let out = clapper().current_dir(d).args(&args).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && err.contains("another run"), "{err}");
    child.kill().unwrap();
    child.wait().unwrap();
    assert!(!d.join("out.csv").exists(), "no half-finished CSV in place");
    assert!(d.join("out.csv.partial").exists());

    // Other options do not mix into the unfinished run.
    let out = clapper()
        .current_dir(d)
        .args(["chart", "--csv", "out.csv", "--grid", "10"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && err.contains("unfinished run"), "{err}");

    // A journal edited by hand (or damaged) is refused, and nothing is
    // put in place; put back, the run resumes.
    let good = std::fs::read_to_string(&journal).unwrap();
    let mut edited: serde_json::Value = serde_json::from_str(&good).unwrap();
    edited["done"] = serde_json::json!(edited["done"].as_u64().unwrap() - 300);
    std::fs::write(&journal, edited.to_string()).unwrap();
    let out = clapper().current_dir(d).args(&args).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && err.contains("does not match"), "{err}");
    assert!(!d.join("out.csv").exists());
    std::fs::write(&journal, good).unwrap();

    let said = run(d, &args);
    assert!(said.contains("resumed at stroke"), "{said}");
    let (a, b) = (
        std::fs::read(d.join("fresh.csv")).unwrap(),
        std::fs::read(d.join("out.csv")).unwrap(),
    );
    assert!(a == b, "the resumed run differs from a fresh one");
    assert!(!journal.exists() && !d.join("out.csv.partial").exists());
}
