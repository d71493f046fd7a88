//! The words of `clapper strikes` read as a ringer reads them (tester15
//! fault 6): the ring-size warning names what was given (templates, not
//! nominals), and a spread that cannot be measured is not printed as 0.

mod common;

use clapper_io::signal_file::write_wav;
use clapper_signal::sampled_ring::sampled_ring;
use clapper_signal::tower::{Method, TowerSpec};
use clapper_signal::Signal;
use common::{clapper, untuned_templates};

/// Four bells' templates in `dir`/t and a ring of them with a handstroke
/// gap of eight intervals (room for more bells than four), `dir`/ring.wav.
fn ring_with_room(dir: &std::path::Path) {
    let rate = 16_000.0;
    let (bells, templates) = untuned_templates(dir, 4, rate);
    let spec = TowerSpec {
        rate,
        rows: 16,
        method: Method::PlainHunt,
        handstroke_gap: 8.0,
        snr_db: Some(30.0),
        ..TowerSpec::new(bells)
    };
    let (sig, _) = sampled_ring(&spec, &templates).unwrap();
    write_wav(&dir.join("ring.wav"), &sig, 0.9).unwrap();
}

#[test]
fn the_ring_size_warning_with_templates_says_templates_were_given() {
    let dir = tempfile::tempdir().unwrap();
    ring_with_room(dir.path());
    let w = warned_with_templates(&dir.path().join("ring.wav"), &dir.path().join("t"));
    // Before: "4 nominal(s) given, .. give every bell's nominal".
    assert!(
        w.iter()
            .any(|w| w.starts_with("4 template(s) given, but the strikes leave room for")
                && w.contains("give every bell's template")),
        "{w:?}"
    );
    assert!(!w.iter().any(|w| w.contains("nominal")), "{w:?}");
}

/// The report (`--json`) on the recording `wav` heard with the templates
/// in `templates`, and `more` arguments; the run must succeed.
fn heard_with_templates(wav: &std::path::Path, templates: &std::path::Path, more: &[&str]) -> serde_json::Value {
    let out = clapper()
        .arg("strikes")
        .arg(wav)
        .arg("--templates")
        .arg(templates)
        .arg("--json")
        .args(more)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    serde_json::from_slice(&out.stdout).unwrap()
}

/// The report's warnings on the recording `wav` heard with the templates
/// in `templates` (`--json`); the run must succeed.
fn warned_with_templates(wav: &std::path::Path, templates: &std::path::Path) -> Vec<String> {
    common::summary_warnings(&heard_with_templates(wav, templates, &[]))
}

/// `ring` written as a stereo file whose second channel is `late_s` later
/// (and 3 dB quieter), 16-bit.
fn stereo_late(path: &std::path::Path, ring: &Signal, late_s: f64) {
    let spec = hound::WavSpec {
        channels: 2,
        sample_rate: ring.rate as u32,
        bits_per_sample: 16,
        sample_format: hound::SampleFormat::Int,
    };
    let peak = ring.samples.iter().fold(0.0f64, |p, v| p.max(v.abs())).max(1e-9);
    let lag = (late_s * ring.rate).round() as usize;
    let mut w = hound::WavWriter::create(path, spec).unwrap();
    for i in 0..ring.samples.len() {
        let right = if i >= lag { 0.7 * ring.samples[i - lag] } else { 0.0 };
        for v in [ring.samples[i], right] {
            w.write_sample((0.9 * 32767.0 * v / peak) as i16).unwrap();
        }
    }
    w.finalize().unwrap();
}

/// Tester14 fault 12: a stereo file whose right channel is 20 ms late was
/// mixed without a word; the report now says the channels disagree, and
/// (tester16 fault 7) hears the first channel alone, as `--channel 1`
/// does; `--channel mix` mixes them as before and says so. A stereo file
/// whose channels agree is mixed without a word.
#[test]
fn a_stereo_file_whose_channels_disagree_in_time_is_told_and_one_heard() {
    let dir = tempfile::tempdir().unwrap();
    ring_with_room(dir.path());
    let ring = clapper_io::signal_file::read_recording(&dir.path().join("ring.wav")).unwrap();
    let heard = |late_s: f64, more: &[&str]| -> (Vec<String>, serde_json::Value) {
        let path = dir.path().join(format!("st{late_s}.wav"));
        stereo_late(&path, &ring, late_s);
        let j = heard_with_templates(&path, &dir.path().join("t"), more);
        (common::summary_warnings(&j), j["strikes"].clone())
    };
    let (late, alone) = heard(0.02, &[]);
    assert!(
        late.iter().any(|w| w.starts_with(
            "the recording's channels disagree in time: channel 2 is heard 20 ms later than channel 1: \
             channel 1 used alone"
        )),
        "{late:?}"
    );
    let (first, asked) = heard(0.02, &["--channel", "1"]);
    assert_eq!(asked, alone);
    assert!(!first.iter().any(|w| w.contains("channels disagree")), "{first:?}");
    let (mixed, blurred) = heard(0.02, &["--channel", "mix"]);
    assert_ne!(blurred, alone);
    assert!(
        mixed
            .iter()
            .any(|w| w.contains("20 ms later") && w.ends_with("record in mono, or keep one channel")),
        "{mixed:?}"
    );
    let (together, both) = heard(0.0, &[]);
    assert!(
        !together.iter().any(|w| w.contains("channels disagree")),
        "{together:?}"
    );
    assert_eq!(heard(0.0, &["--channel", "mix"]).1, both);
}
