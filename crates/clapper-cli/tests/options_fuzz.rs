//! Every number option of every command, given absurd values through the
//! built binary (issue 46): NaN, a negative number, 1e300 and 10^9. Each
//! run must end by itself within its bound with a result (exit 0) or a
//! one-line refusal (exit 1 or 2): no panic, no abort, no signal, no run
//! past the bound. The options are read from each command's own `--help`,
//! so an option added later is tried too.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::Duration;

const BIN: &str = env!("CARGO_BIN_EXE_clapper");

/// Values tried for every option that takes one.
const VALUES: [&str; 4] = ["NaN", "-1", "1e300", "1000000000"];

/// How long one run may take before it counts as running away: far more
/// than any refused or bounded run needs on a loaded two-core machine (the
/// longest here take about a second), far less than a runaway's hours.
const BOUND: Duration = Duration::from_secs(120);

/// Options that name files or folders (not numbers), skipped.
const FILE_OPTIONS: [&str; 15] = [
    "--out",
    "--plot",
    "--csv",
    "--truth",
    "--report",
    "--lowndes",
    "--trace",
    "--templates",
    "--bell",
    "--recording",
    "--ring",
    "--shard",
    "--answers",
    "--sweep",
    "--tower",
];

/// Each command with the least arguments that make it run (files in `d`).
fn commands(d: &Path) -> Vec<(&'static str, Vec<String>)> {
    let p = |f: &str| d.join(f).display().to_string();
    let s = |v: &[&str]| v.iter().map(|x| x.to_string()).collect::<Vec<_>>();
    vec![
        ("simulate", s(&["--preset", "lab", "--strokes", "2"])),
        ("ring-up", s(&["--preset", "lab"])),
        ("ring-down", s(&["--preset", "lab"])),
        ("design-clapper", vec![]),
        ("liftoff", vec![]),
        ("chart", vec!["--grid".into(), "4".into(), "--out".into(), p("c.png")]),
        ("diagnose", vec![p("lab.toml")]),
        ("restitution", vec!["--accel".into(), p("drop.wav")]),
        ("contacts", vec![p("contact.csv")]),
        ("spectrogram", vec![p("strike.wav"), "--out".into(), p("s.png")]),
        (
            "decay",
            vec![
                p("strike.wav"),
                "--freq".into(),
                "500".into(),
                "--out".into(),
                p("d.png"),
            ],
        ),
        ("modes", vec![p("strike.wav")]),
        ("impulse", vec![]),
        (
            "strikes",
            vec![
                p("tower.wav"),
                "--nominals".into(),
                "1400.0,1247.3,1111.2,1048.8,934.4,832.4,741.6,700.0".into(),
            ],
        ),
        (
            "synth-ring",
            vec!["--out".into(), p("r.wav"), "--rows".into(), "4".into()],
        ),
        ("synth", vec!["--out".into(), p("b.wav")]),
        ("animate", vec!["--out".into(), p("a.svg")]),
        ("ringing-log", vec![p("log.txt")]),
        ("synth-log", vec!["--out".into(), p("l.txt")]),
        (
            "tower",
            vec![p("ring-of-eight-tower.toml"), "--leads".into(), "1".into()],
        ),
    ]
}

/// The options of `cmd` that take a value, from its help.
fn value_options(cmd: &str) -> Vec<String> {
    let out = Command::new(BIN).args([cmd, "--help"]).output().unwrap();
    let help = String::from_utf8_lossy(&out.stdout);
    let mut opts: Vec<String> = help
        .split_whitespace()
        .collect::<Vec<_>>()
        .windows(2)
        .filter(|w| w[0].starts_with("--") && w[1].starts_with('<'))
        // Files and folders by their placeholder (`--rows <FILE>`).
        .filter(|w| !["FILE", "DIR", "PATH"].iter().any(|f| w[1].contains(f)))
        .map(|w| w[0].trim_end_matches(',').to_string())
        .filter(|o| !FILE_OPTIONS.contains(&o.as_str()))
        .collect();
    opts.sort();
    opts.dedup();
    opts
}

/// `cmd` with its base arguments and option `o` set to `v`: the base's own
/// value of `o` replaced where it gives one (`tower --leads 1` fuzzed as
/// `--leads 1e9`, not refused as a repeated option), else `o v` added.
fn with_value(cmd: &str, base: &[String], o: &str, v: &str) -> Vec<String> {
    let mut args = vec![cmd.to_string()];
    args.extend(base.iter().cloned());
    match args.iter().position(|a| a == o) {
        Some(i) if i + 1 < args.len() => args[i + 1] = v.to_string(),
        _ => args.extend([o.to_string(), v.to_string()]),
    }
    args
}

/// The base arguments that are not options or their values (its files).
fn positional(base: &[String]) -> Vec<String> {
    let mut out = vec![];
    let mut skip = false;
    for a in base {
        if skip {
            skip = false;
        } else if a.starts_with("--") {
            skip = true;
        } else {
            out.push(a.clone());
        }
    }
    out
}

/// How one run ended.
enum Ended {
    Code(i32, String),
    Signal,
    PastBound,
}

fn run(args: &[String]) -> Ended {
    let mut child = Command::new(BIN)
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let step = Duration::from_millis(20);
    // Polls bounded: BOUND / step of them.
    for _ in 0..(BOUND.as_millis() / step.as_millis()) {
        if let Some(status) = child.try_wait().unwrap() {
            let mut err = String::new();
            use std::io::Read as _;
            child.stderr.take().unwrap().read_to_string(&mut err).unwrap();
            return match status.code() {
                Some(c) => Ended::Code(c, err),
                None => Ended::Signal,
            };
        }
        std::thread::sleep(step);
    }
    let _ = child.kill();
    let _ = child.wait();
    Ended::PastBound
}

fn materials() -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    for f in [
        "examples/lab.toml",
        "examples/data/drop.wav",
        "examples/data/contact.csv",
        "examples/data/strike.wav",
        "examples/data/tower.wav",
    ] {
        let from = root.join(f);
        std::fs::copy(&from, dir.path().join(from.file_name().unwrap())).unwrap();
    }
    let log = dir.path().join("log.txt");
    let made = Command::new(BIN)
        .args(["synth-log", "--out"])
        .arg(&log)
        .args(["--strokes", "4"])
        .output()
        .unwrap();
    assert!(made.status.success(), "{}", String::from_utf8_lossy(&made.stderr));
    let p = dir.path().to_path_buf();
    (dir, p)
}

#[test]
fn no_option_value_panics_aborts_or_runs_away() {
    let (_keep, d) = materials();
    let mut jobs = vec![];
    for (cmd, base) in commands(&d) {
        let opts = value_options(cmd);
        assert!(
            !opts.is_empty() || ["liftoff", "impulse"].contains(&cmd),
            "{cmd}: no options read from its help"
        );
        for o in opts {
            for v in VALUES {
                jobs.push(with_value(cmd, &base, &o, v));
            }
        }
    }
    // Two at a time: the machine has two cores.
    let next = std::sync::atomic::AtomicUsize::new(0);
    let failures = std::sync::Mutex::new(vec![]);
    let refused = std::sync::atomic::AtomicUsize::new(0);
    std::thread::scope(|s| {
        for _ in 0..2 {
            s.spawn(|| loop {
                let k = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                let Some(args) = jobs.get(k) else { break };
                let what = args.join(" ");
                let mut ended = run(args);
                // An option the base arguments' options exclude is tried
                // again with the base's files alone, so that it is run,
                // not only refused as a clash (tower's --changes beside --leads).
                if matches!(&ended, Ended::Code(2, err) if err.contains("cannot be used with")) {
                    let alone = with_value(
                        &args[0],
                        &positional(&args[1..args.len() - 2]),
                        &args[args.len() - 2],
                        &args[args.len() - 1],
                    );
                    ended = run(&alone);
                }
                let bad = match ended {
                    Ended::Code(0, _) => None,
                    Ended::Code(1 | 2, err) if !err.contains("panicked") => {
                        refused.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                        // A refusal is one line that says something.
                        let lines = err.trim().lines().count();
                        (lines != 1).then(|| format!("{what}: a refusal of {lines} lines: {err}"))
                    }
                    Ended::Code(c, err) => Some(format!("{what}: exit {c}: {}", err.trim())),
                    Ended::Signal => Some(format!("{what}: killed by a signal")),
                    Ended::PastBound => Some(format!("{what}: still running after {} s", BOUND.as_secs())),
                };
                if let Some(b) = bad {
                    failures.lock().unwrap().push(b);
                }
            });
        }
    });
    let failures = failures.into_inner().unwrap();
    println!(
        "{} runs, {} refused",
        jobs.len(),
        refused.load(std::sync::atomic::Ordering::Relaxed)
    );
    assert!(jobs.len() > 500, "only {} runs: the options were not read", jobs.len());
    assert!(
        failures.is_empty(),
        "{} of {} runs:\n{}",
        failures.len(),
        jobs.len(),
        failures.join("\n")
    );
}
