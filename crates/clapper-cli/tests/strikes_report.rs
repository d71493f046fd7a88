//! The text report of `clapper strikes` as a ringer reads it (session 17's
//! tester): what qualifies the table stands before it, a bell heard at no
//! strike is named, the timing is said in a ringer's words (the
//! developer's detail with `--verbose`), and channels count from 1 in
//! every command.

mod common;

use clapper_io::signal_file::write_wav;
use clapper_signal::sampled_ring::{sampled_ring, UntunedStrike};
use clapper_signal::tower::{major_scale, Method, TowerSpec};
use clapper_signal::Signal;
use common::clapper;

/// A bell's strike at `nominal_hz`, 16 kHz.
fn strike(nominal_hz: f64) -> Signal {
    UntunedStrike {
        nominal_hz,
        rise_s: 0.01,
        decay_s: 0.6,
        length_s: 1.2,
        blow: None,
    }
    .signal(16_000.0)
}

/// Four bells in plain hunt, 16 rows, `dir`/ring.wav, and in `dir`/t their
/// templates and a fifth bell's (2600 Hz) that never rings.
fn four_rung_five_given(dir: &std::path::Path) {
    let bells = major_scale(4, 1000.0).unwrap();
    let templates: Vec<Signal> = bells.iter().map(|b| strike(b.nominal_hz)).collect();
    std::fs::create_dir(dir.join("t")).unwrap();
    for (i, t) in templates.iter().chain([&strike(2600.0)]).enumerate() {
        write_wav(&dir.join(format!("t/{}.wav", i + 1)), t, 0.9).unwrap();
    }
    let spec = TowerSpec {
        rate: 16_000.0,
        rows: 16,
        method: Method::PlainHunt,
        snr_db: Some(30.0),
        ..TowerSpec::new(bells)
    };
    let (sig, _) = sampled_ring(&spec, &templates).unwrap();
    write_wav(&dir.join("ring.wav"), &sig, 0.9).unwrap();
}

/// `clapper strikes ARGS` (text), which must succeed.
fn text(args: &[&std::ffi::OsStr]) -> String {
    let out = clapper().arg("strikes").args(args).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8(out.stdout).unwrap()
}

#[test]
fn a_bell_never_heard_is_named_before_the_table_and_the_words_are_a_ringers() {
    let dir = tempfile::tempdir().unwrap();
    four_rung_five_given(dir.path());
    let (wav, t) = (dir.path().join("ring.wav"), dir.path().join("t"));
    let plain = text(&[wav.as_os_str(), "--templates".as_ref(), t.as_os_str()]);
    let table = plain.find("  bell strikes").expect("a table");
    let bell5 = plain
        .lines()
        .find(|l| l.starts_with("warning: bell 5"))
        .unwrap_or_else(|| panic!("bell 5 named: {plain}"));
    assert!(plain.find(bell5).unwrap() < table, "{plain}");
    assert!(plain.rfind("warning: ").unwrap() < table, "{plain}");
    // The timing said in a ringer's words; each bell's figures, and the
    // developer's words, with --verbose (tester21 fault 7f).
    assert!(
        plain.contains("each bell's strikes timed at the start of its sound, against its own recorded strike"),
        "{plain}"
    );
    assert!(!plain.contains("after its clapper strikes"), "{plain}");
    for dev in ["band finder", "docs/", "MAD"] {
        assert!(!plain.contains(dev), "{dev}: {plain}");
    }
    let verbose = text(&[
        wav.as_os_str(),
        "--templates".as_ref(),
        t.as_os_str(),
        "--verbose".as_ref(),
    ]);
    assert!(verbose.starts_with(&plain), "{verbose}");
    assert!(
        verbose.contains("a bell is heard some time after its clapper strikes"),
        "{verbose}"
    );
    assert!(
        verbose.contains("detail: bell 1: the band finder's lateness"),
        "{verbose}"
    );
}

#[test]
fn channels_count_from_1_in_every_command() {
    let dir = tempfile::tempdir().unwrap();
    let wav = dir.path().join("s.wav");
    write_wav(&wav, &strike(1000.0), 0.9).unwrap();
    let w = wav.to_str().unwrap();
    // The first channel is channel 1, as `strikes --channel` counts.
    let first = common::json(&["modes", w, "--channel", "1"]);
    assert_eq!(first, common::json(&["modes", w]));
    for cmd in [
        &["modes", w, "--channel", "0"][..],
        &["strikes", w, "--nominals", "1000,900", "--channel", "0"],
    ] {
        let out = clapper().args(cmd).output().unwrap();
        assert!(!out.status.success(), "{cmd:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains("count from 1"), "{cmd:?}: {err}");
    }
    let out = clapper().args(["modes", w, "--channel", "2"]).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("channel 2 asked, the file has 1 (1 to 1)"), "{err}");
}
