//! What a new user meets first (issue 42): each mistake answered by one
//! line that says what is wrong and what to do, with the exit code.

mod common;

use std::path::{Path, PathBuf};

use common::{clapper, TENOR_CLAPPER_PARTS};

/// A file of the checkout, by its path from the workspace's root.
fn checkout(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..").join(path)
}

/// Run `clapper ARGS`, require exit code `code`, and give its standard
/// error, required to be one line when the command failed.
fn stderr_of(args: &[&str], code: i32) -> String {
    let out = clapper().args(args).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(out.status.code(), Some(code), "{args:?}: {err}");
    if code != 0 {
        assert_eq!(err.trim_end().lines().count(), 1, "{args:?}: not one line: {err}");
    }
    err
}

#[test]
fn a_decimal_comma_in_a_bell_file_is_named_with_its_file_and_line() {
    let dir = tempfile::tempdir().unwrap();
    let lab = std::fs::read_to_string(checkout("examples/lab.toml")).unwrap();
    let comma = dir.path().join("comma.toml");
    std::fs::write(&comma, lab.replace("r_m = 0.10 ", "r_m = 0,05 ")).unwrap();
    let path = comma.to_str().unwrap();
    let line = lab.lines().position(|l| l.starts_with("r_m")).unwrap() + 1;
    for args in [vec!["simulate", "--bell", path], vec!["diagnose", path]] {
        let err = stderr_of(&args, 1);
        assert!(
            err.contains(&format!("{path}: line {line} ")) && err.contains("decimal comma? write 0.05"),
            "{args:?}: {err}"
        );
        assert!(!err.contains("expected newline"), "{err}");
    }
    // A thousand written 1,000 may be either.
    let mass = dir.path().join("mass.toml");
    std::fs::write(&mass, lab.replace("bell_mass_kg = 45.8", "bell_mass_kg = 1,000")).unwrap();
    let err = stderr_of(&["simulate", "--bell", mass.to_str().unwrap()], 1);
    assert!(err.contains("write 1000 or 1.000"), "{err}");
}

#[test]
fn a_bad_number_in_a_ring_csv_names_its_line_column_and_value() {
    let dir = tempfile::tempdir().unwrap();
    let ring = std::fs::read_to_string(checkout("examples/ring-of-eight.csv")).unwrap();
    let put = |name: &str, from: &str, to: &str| {
        assert!(ring.contains(from));
        let p = dir.path().join(name);
        std::fs::write(&p, ring.replacen(from, to, 1)).unwrap();
        p.to_str().unwrap().to_string()
    };
    let typo = put("typo.csv", "2,1.38,1.08,0.111,", "2,1.38,1.08,0.1x1,");
    let err = stderr_of(&["diagnose", &typo], 1);
    assert!(
        err.contains(&format!("{typo}: row 2 (line 3), column r_m: '0.1x1' is not a number")),
        "{err}"
    );
    // A decimal comma in a quoted cell, and one that splits a cell in two.
    let quoted = put("quoted.csv", "treble,1.30,1.03,", "treble,\"1,30\",1.03,");
    let err = stderr_of(&["diagnose", &quoted], 1);
    assert!(
        err.contains(&format!(
            "{quoted}: row 1 (line 2), column bell_period_s: '1,30' is not a number (decimal comma? write 1.30)"
        )),
        "{err}"
    );
    let split = put("split.csv", "3,1.45,", "3,1,45,");
    let err = stderr_of(&["diagnose", &split], 1);
    assert!(
        err.contains(&format!("{split}: row 3 (line 4): 8 cells where the header has 7"))
            && err.contains("decimal comma"),
        "{err}"
    );
}

#[test]
fn design_clapper_says_what_a_clapper_needs() {
    let err = stderr_of(&["design-clapper", "--shaft-length", "0.69"], 1);
    assert!(
        err.contains("no part has any mass (--shaft-length needs --shaft-diameter)")
            && err.contains("a ball --ball-diameter (or --ball-mass) and --ball-position"),
        "{err}"
    );
    assert!(!err.contains("out of range") && !err.contains("_m"), "{err}");
    let err = stderr_of(&["design-clapper"], 1);
    assert!(
        err.contains("no part has any mass: a shaft needs --shaft-length and --shaft-diameter"),
        "{err}"
    );
    // The other faults of the parts are in option names too.
    let mut too_long = TENOR_CLAPPER_PARTS.to_vec();
    too_long[1] = "0.9";
    let mut args = vec!["design-clapper"];
    args.extend(too_long);
    let err = stderr_of(&args, 1);
    assert!(err.contains("--shaft-length 0.9 is out of range"), "{err}");
    let mut args = vec!["design-clapper"];
    args.extend(TENOR_CLAPPER_PARTS);
    stderr_of(&args, 0);
}

#[test]
fn a_recording_given_to_a_text_reader_is_named_as_one() {
    let wav = checkout("examples/data/strike.wav");
    let wav = wav.to_str().unwrap();
    for (args, wanted) in [
        (vec!["ringing-log", wav], "an accelerometer log"),
        (vec!["diagnose", wav], "a bell or ring file"),
        (vec!["simulate", "--bell", wav], "a bell file"),
        (vec!["listening-test", "analyse", wav], "an answer sheet"),
    ] {
        let err = stderr_of(&args, 1);
        assert!(
            err.contains(&format!("a WAV recording, not {wanted}"))
                && err.contains("clapper strikes")
                && err.contains("spectrogram"),
            "{args:?}: {err}"
        );
        assert!(!err.contains("UTF-8"), "{args:?}: {err}");
        assert_eq!(err.matches(wav).count(), 1, "{args:?}: the file named twice: {err}");
    }
    // A recording saved with a .csv name, where a CSV signal is read.
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("strike.csv");
    std::fs::copy(wav, &csv).unwrap();
    let err = stderr_of(&["decay", csv.to_str().unwrap(), "--freq", "600"], 1);
    assert!(err.contains("a WAV recording, not a CSV signal"), "{err}");
}

#[test]
fn an_output_folder_that_is_a_file_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("figs");
    std::fs::write(&file, "not a folder").unwrap();
    let path = file.to_str().unwrap();
    for cmd in ["figures", "sample-data"] {
        let err = stderr_of(&[cmd, "--out", path], 1);
        assert!(
            err.contains(&format!("--out must be a folder, and {path} is a file")),
            "{cmd}: {err}"
        );
        assert!(!err.contains("os error"), "{cmd}: {err}");
    }
    let below = file.join("more");
    let err = stderr_of(&["figures", "--out", below.to_str().unwrap()], 1);
    assert!(err.contains(&format!("{path} is a file, not a folder")), "{err}");
    assert_eq!(std::fs::read_to_string(&file).unwrap(), "not a folder");
}

#[test]
fn merge_removes_the_shard_descriptions_unless_kept() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    for i in 1..=2 {
        let out = clapper()
            .current_dir(d)
            .args(["chart", "--grid", "4", "--shard", &format!("{i}/2"), "--csv"])
            .arg(format!("p{i}.csv"))
            .output()
            .unwrap();
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    }
    let metas = ["p1.csv.shard.json", "p2.csv.shard.json"];
    assert!(metas.iter().all(|m| d.join(m).exists()));
    let merge = |extra: &[&str]| {
        clapper()
            .current_dir(d)
            .args(["merge", "--csv", "all.csv", "p1.csv", "p2.csv"])
            .args(extra)
            .output()
            .unwrap()
    };
    let kept = merge(&["--keep-shard-json"]);
    assert_eq!(kept.status.code(), Some(0));
    assert!(
        metas.iter().all(|m| d.join(m).exists()),
        "--keep-shard-json removed them"
    );
    let out = merge(&[]);
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    let said = String::from_utf8_lossy(&out.stdout);
    assert!(said.contains("removed the shards' 2 .shard.json files"), "{said}");
    assert!(!metas.iter().any(|m| d.join(m).exists()), "descriptions left behind");
    assert!(d.join("all.csv").exists() && d.join("p1.csv").exists());
    let mut left: Vec<String> = std::fs::read_dir(d)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    left.sort();
    assert_eq!(left, ["all.csv", "p1.csv", "p2.csv"]);
    // Merged again, the missing descriptions are explained.
    let again = merge(&[]);
    assert_eq!(again.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&again.stderr).contains("unless --keep-shard-json"));
    // The help says which.
    let help = clapper().args(["merge", "--help"]).output().unwrap();
    let help = String::from_utf8_lossy(&help.stdout);
    assert!(help.contains("--keep-shard-json") && help.contains("remove"), "{help}");
}

/// `serve --open` where the opener finds no browser (an `xdg-open` that
/// prints what the real one prints then, and fails): one line, not the
/// opener's noise, and the server serves on.
#[cfg(target_os = "linux")]
#[test]
fn serve_open_without_a_browser_says_one_line() {
    use std::io::{BufRead, BufReader};
    use std::os::unix::fs::PermissionsExt;
    use std::process::{Command, Stdio};
    let dir = tempfile::tempdir().unwrap();
    let fake = dir.path().join("xdg-open");
    let mut script = String::from("#!/bin/sh\n");
    for b in ["www-browser", "links2", "elinks", "links", "lynx", "w3m"] {
        script += &format!("echo \"/usr/bin/xdg-open: 882: {b}: not found\" >&2\n");
    }
    script += "echo \"xdg-open: no method available for opening '$1'\" >&2\nexit 3\n";
    std::fs::write(&fake, script).unwrap();
    std::fs::set_permissions(&fake, std::fs::Permissions::from_mode(0o755)).unwrap();
    let path = format!("{}:{}", dir.path().display(), std::env::var("PATH").unwrap_or_default());
    let mut child = Command::new(assert_cmd::cargo::cargo_bin("clapper"))
        .args(["serve", "--port", "0", "--open"])
        .env("PATH", path)
        .env_remove("BROWSER")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut first = String::new();
    let mut out = BufReader::new(child.stdout.take().unwrap());
    out.read_line(&mut first).unwrap();
    let url = first
        .split_whitespace()
        .find(|w| w.starts_with("http://"))
        .unwrap()
        .to_string();
    let mut line = String::new();
    let mut err = BufReader::new(child.stderr.take().unwrap());
    err.read_line(&mut line).unwrap();
    assert_eq!(
        line.trim_end(),
        format!("could not open a browser: open {url} yourself")
    );
    // Still serving; stopped as Ctrl-C would, it ends cleanly, having
    // said nothing more.
    let addr = url.trim_start_matches("http://").trim_end_matches('/');
    let mut s = std::net::TcpStream::connect(addr).unwrap();
    std::io::Write::write_all(
        &mut s,
        b"GET / HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n",
    )
    .unwrap();
    let mut page = String::new();
    std::io::Read::read_to_string(&mut s, &mut page).unwrap();
    assert!(page.starts_with("HTTP/1.1 200"), "{}", &page[..page.len().min(200)]);
    Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    let mut rest = String::new();
    std::io::Read::read_to_string(&mut err, &mut rest).unwrap();
    let mut said = String::new();
    std::io::Read::read_to_string(&mut out, &mut said).unwrap();
    let status = child.wait().unwrap();
    assert!(rest.is_empty(), "more on standard error: {rest}");
    assert_eq!(said.trim(), "stopped");
    assert_eq!(status.code(), Some(0));
}

/// Issue 46: a value given as an option is named as the option, with the
/// value as written (`--stay -1`), not by its key in a bell file or a
/// request (`stay_deg = -1`); a bell file's key stays its own.
#[test]
fn an_option_out_of_range_is_named_as_the_option() {
    for (args, want, not) in [
        (vec!["ring-up", "--stay", "-1"], "--stay -1 is out of range", "stay_deg"),
        (
            vec!["ring-down", "--down", "200"],
            "--down 200 is out of range",
            "down_deg",
        ),
        (
            vec!["ring-up", "--pull-force=-1"],
            "--pull-force -1 is out of range",
            "pull_force_n",
        ),
        (
            vec!["ring-up", "--pull-window", "1e9"],
            "--pull-window 1e9 is out of range",
            "pull_window_deg",
        ),
        (
            vec!["simulate", "--clapper-swings-to-halve", "0"],
            "--clapper-swings-to-halve 0 is out of range",
            "swings_to_halve",
        ),
        // The amplitude given alone is named, not the loss it goes with.
        (
            vec!["ring-up", "--swing-amplitude", "10"],
            "--swing-amplitude 10 is out of range: only with a swings-to-halve timing",
            "swing_loss",
        ),
        // A huge value in exponent form, not three hundred digits.
        (
            vec!["simulate", "--rtol", "1e300"],
            "rtol 1e300 is out of range",
            "00000",
        ),
        // A timing too quick is said as the timing, not the damping it stands for.
        (
            vec!["ring-up", "--bell-swings-to-halve", "0.01"],
            "--bell-swings-to-halve 0.01 is out of range: more swings",
            "damping_n_m_s",
        ),
        (
            vec!["tower", "examples/lab-tower.toml", "--theta0", "0"],
            "--theta0 0 is out of range",
            "theta0_deg",
        ),
    ] {
        let args: Vec<String> = args
            .iter()
            .map(|a| {
                if a.ends_with(".toml") {
                    checkout(a).display().to_string()
                } else {
                    a.to_string()
                }
            })
            .collect();
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let err = stderr_of(&args, 1);
        assert!(err.contains(want) && !err.contains(not), "{args:?}: {err}");
    }
    // The ball's depth alone is refused by the options, not as "gap_hand_mm = NaN".
    let err = stderr_of(&["ring-up", "--ball-below-pivot", "0.8"], 2);
    assert!(err.contains("--gap-hand") && !err.contains("NaN"), "{err}");
}

/// Issue 46: no Rust struct in a message (`Timing { interval_s: 0.0, .. }`,
/// `Room { rt60_s: 20.0, .. }`): each value said in words with its unit.
#[test]
fn no_message_shows_a_rust_struct() {
    let dir = tempfile::tempdir().unwrap();
    let ring = checkout("examples/lab-tower.toml").display().to_string();
    let tower = dir.path().join("tower.toml");
    std::fs::write(
        &tower,
        "[east_west]\nfrequency_hz = 0\ndamping_ratio = 0.02\nmodal_mass_kg = 1e5\n\
         [north_south]\nfrequency_hz = 1.5\ndamping_ratio = 0.02\nmodal_mass_kg = 1e5\n",
    )
    .unwrap();
    let wav = dir.path().join("ring.wav").display().to_string();
    for (args, want) in [
        (
            vec!["tower", &ring, "--interval", "0"],
            "--interval 0 ms: strikes from 20 to 5000 ms apart",
        ),
        (
            vec!["tower", &ring, "--dt", "1"],
            "--dt 1 s: histories sampled every 0.001 to 0.05 s",
        ),
        (
            vec!["tower", &ring, "--tower", tower.to_str().unwrap()],
            "east-west sway: frequency_hz 0 is out of range: a frequency above 0 Hz",
        ),
        (
            vec!["synth-ring", "--out", &wav, "--rt60", "20"],
            "--rt60 20 s is out of range",
        ),
        (
            vec!["synth-ring", "--out", &wav, "--double", "1:0:2000:0.5"],
            "--double 1:0:2000:0.5: delay 2000 ms is out of range",
        ),
        (
            vec!["synth-ring", "--out", &wav, "--double", "9:0:50:0.5"],
            "--double 9:0:50:0.5: no bell 9",
        ),
    ] {
        let err = stderr_of(&args, 1);
        assert!(err.contains(want), "{args:?}: {err}");
        assert!(
            !err.contains(" { ") && !err.contains(": None"),
            "{args:?}: a struct: {err}"
        );
    }
}

/// Issue 46: `synth-log --name '1 2 3 4'` wrote a name that ringing-log
/// read back as a sample; such a name is refused, and a name that reads
/// back is read back.
#[test]
fn a_log_name_that_would_read_as_a_sample_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("bell.txt");
    let path = log.to_str().unwrap();
    for name in ["1 2 3 4", "7", " "] {
        let err = stderr_of(&["synth-log", "--out", path, "--strokes", "40", "--name", name], 1);
        assert!(
            err.contains("--name") && err.contains("begin with a number"),
            "{name:?}: {err}"
        );
        assert!(!log.exists(), "{name:?}: written");
    }
    stderr_of(
        &["synth-log", "--out", path, "--strokes", "40", "--name", "Bell 1 2 3 4"],
        0,
    );
    let out = clapper().args(["ringing-log", path, "--json"]).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["bell"], "Bell 1 2 3 4");
}

/// Issue 46: a negative count was refused in Rust's words ("invalid digit
/// found in string"); it is said as the option, the value as written and
/// the counts it takes.
#[test]
fn a_negative_count_is_refused_as_a_count() {
    let dir = tempfile::tempdir().unwrap();
    let wav = dir.path().join("r.wav").display().to_string();
    let log = dir.path().join("l.txt").display().to_string();
    for (args, says) in [
        (
            vec!["simulate", "--strokes", "-5"],
            "--strokes -5: a count from 1 to 10000",
        ),
        (vec!["ring-down", "--swings", "-1"], "--swings -1: a count from 1"),
        (
            vec!["synth-ring", "--out", &wav, "--rows", "-3"],
            "--rows -3: a count from 1",
        ),
        (
            vec!["synth-log", "--out", &log, "--seed", "-1"],
            "--seed -1: a whole number from 0 to 18446744073709551615",
        ),
        (
            vec!["serve", "--max-chart-points", "-1"],
            "--max-chart-points -1: a count from 1 to 4000000",
        ),
        (vec!["chart", "--threads", "-2"], "--threads -2: a count"),
    ] {
        let err = stderr_of(&args, 2);
        assert!(err.contains(says) && !err.contains("digit"), "{args:?}: {err}");
    }
}

/// Issue 46: `--rate 1000000000` was refused as "48.45 s at 1000000000 Hz:
/// from one sample to 57600000 samples"; it is refused as the rate.
#[test]
fn a_sample_rate_is_refused_as_the_rate() {
    let dir = tempfile::tempdir().unwrap();
    let wav = dir.path().join("r.wav").display().to_string();
    for (args, says) in [
        (
            vec!["synth-ring", "--out", &wav, "--rate", "1000000000"],
            "--rate 1000000000 Hz: a sample rate from 8000 to 192000 Hz",
        ),
        (
            vec!["synth", "--preset", "lab", "--out", &wav, "--rate", "1e9"],
            "--rate 1000000000 Hz: a sample rate from 8000 to 192000 Hz",
        ),
        (
            vec!["synth-ring", "--out", &wav, "--rate", "4000"],
            "--rate 4000 Hz: a sample rate from 8000",
        ),
    ] {
        let err = stderr_of(&args, 1);
        assert!(err.contains(says) && !err.contains("samples"), "{args:?}: {err}");
    }
    assert!(!Path::new(&wav).exists());
}

/// Issue 46: 1e300 came back in a message as a number of 301 digits; it
/// is said as 1e300.
#[test]
fn a_huge_number_is_said_in_short_form() {
    let dir = tempfile::tempdir().unwrap();
    let wav = dir.path().join("r.wav").display().to_string();
    let err = stderr_of(&["synth-ring", "--out", &wav, "--rate", "1e300"], 1);
    assert!(
        err.contains("--rate 1e300 Hz: a sample rate") && !err.contains("000000"),
        "{err}"
    );
    let log = dir.path().join("l.txt").display().to_string();
    let err = stderr_of(&["synth-log", "--out", &log, "--sensor-m", "1e300"], 1);
    assert!(err.contains("--sensor-m 1e300 m") && !err.contains("000000"), "{err}");
}

/// Issue 46: chart's ranges were refused under the keys r_over_lc and
/// lb_over_lc, or, given high to low, as "r_over_lc range, from = 1"; a
/// range to 1e300 was swept and labelled with 301-digit numbers.
#[test]
fn a_chart_range_is_refused_as_its_option() {
    for (args, says) in [
        (
            vec!["chart", "--grid", "5", "--r-range", "NaN,1"],
            "--r-range NaN,1: a range of r/L_c: two numbers from -10 to 10, the low end first",
        ),
        (
            vec!["chart", "--grid", "5", "--r-range", "1,-1"],
            "--r-range 1,-1: a range of r/L_c",
        ),
        (
            vec!["chart", "--grid", "5", "--lb-range", "0,1e300"],
            "--lb-range 0,1e300: a range of L_b/L_c: two numbers above 0 and up to 10",
        ),
        (
            vec!["chart", "--grid", "5", "--lb-range", "0.5,1e300"],
            "--lb-range 0.5,1e300: a range of L_b/L_c",
        ),
        (
            vec!["chart", "--grid", "5", "--r-range", "-1e300,1e300"],
            "--r-range -1e300,1e300: a range of r/L_c",
        ),
        (
            vec!["figures", "--grid", "5", "--lb-range", "2,1", "--out", "f"],
            "--lb-range 2,1: a range of L_b/L_c",
        ),
    ] {
        let err = stderr_of(&args, 2);
        assert!(err.contains(says) && !err.contains("_over_lc"), "{args:?}: {err}");
    }
}
