//! The timing of strikes heard about nominals chosen from the recording
//! (issue 43, `clapper_app::strikes::choose_timing`): bells whose partials
//! are not a tuned bell's and whose sound builds up after the blow, each
//! by its own time, are timed from the recording; a tuned ring is timed
//! as heard; handbells are timed as heard.

use clapper_app::strikes::{choose_timing, opening, strike_options, StrikesReport, TimingAsked, Voice};
use clapper_signal::sampled_ring::{sampled_ring, UntunedStrike};
use clapper_signal::tower::{major_scale, tower_recording, Method, TowerSpec};
use clapper_signal::Signal;

/// Five bells at a recorded tower bell's ratios, each building up over its
/// own time (10 to 60 ms): heard at a tuned bell's partials, each is late
/// by its own constant. Plain hunt, 24 rows: (recording, nominals).
fn late_bells() -> (Signal, Vec<f64>) {
    let rate = 16_000.0;
    let bells = major_scale(5, 1000.0).unwrap();
    let nominals: Vec<f64> = bells.iter().map(|b| b.nominal_hz).collect();
    let rises = [0.01, 0.06, 0.02, 0.045, 0.03];
    let strikes: Vec<Signal> = nominals
        .iter()
        .zip(rises)
        .map(|(&f, r)| UntunedStrike::with_noisy_blow(f, r).signal(rate))
        .collect();
    let spec = TowerSpec {
        rate,
        rows: 24,
        interval: 0.3,
        method: Method::PlainHunt,
        snr_db: Some(25.0),
        ..TowerSpec::new(bells)
    };
    (sampled_ring(&spec, &strikes).unwrap().0, nominals)
}

/// The project's own tuned six in rounds (`clapper synth-ring`'s bells).
fn tuned_ring() -> (Signal, Vec<f64>) {
    let bells = major_scale(6, 1400.0).unwrap();
    let nominals: Vec<f64> = bells.iter().map(|b| b.nominal_hz).collect();
    let spec = TowerSpec {
        rate: 16_000.0,
        rows: 20,
        snr_db: Some(25.0),
        ..TowerSpec::new(bells)
    };
    (tower_recording(&spec).unwrap().0, nominals)
}

#[test]
fn auto_times_late_bells_from_the_recording() {
    let (sig, nominals) = late_bells();
    let opts = strike_options(0.3).unwrap();
    let c = choose_timing(&opening(&sig), &nominals, Voice::Tower, TimingAsked::Auto, &opts).unwrap();
    let ch = &c.choice;
    assert_eq!(ch.used, "recording", "{ch:?}");
    assert_eq!(ch.asked, "auto");
    let (p, r) = (ch.plain_unevenness_ms.unwrap(), ch.recording_unevenness_ms.unwrap());
    assert!(r < 0.7 * p, "{ch:?}");
    assert!(c.calibration.is_some());
    // The report says so under "timing", with both figures.
    let mut report = StrikesReport::timed(&sig, &c.voices, &opts, c.timing()).unwrap();
    report.note_choice(c.choice.clone());
    let t = report.timing.as_ref().unwrap();
    assert_eq!(t.source, "recording");
    assert_eq!(t.choice.as_ref().unwrap().used, "recording");
    let text = report.text("ring");
    assert!(
        text.contains("strikes timed from each bell's own sound, learned from its clean strikes"),
        "{text}"
    );
    assert!(report.text_verbose("ring").contains("timing recording (asked auto)"));
}

#[test]
fn auto_times_a_tuned_ring_as_heard() {
    let (sig, nominals) = tuned_ring();
    let opts = strike_options(0.3).unwrap();
    let c = choose_timing(&opening(&sig), &nominals, Voice::Tower, TimingAsked::Auto, &opts).unwrap();
    assert_eq!(c.choice.used, "plain", "{:?}", c.choice);
    assert!(c.calibration.is_none());
    assert!(c.choice.recording_unevenness_ms.is_some(), "{:?}", c.choice);
    let mut report = StrikesReport::timed(&sig, &c.voices, &opts, c.timing()).unwrap();
    report.note_choice(c.choice.clone());
    let t = report.timing.as_ref().unwrap();
    assert_eq!((t.source, t.per_bell.len()), ("plain", 0));
    // What is asked is done, without trying the other.
    let asked = choose_timing(&opening(&sig), &nominals, Voice::Tower, TimingAsked::Recording, &opts).unwrap();
    assert_eq!(asked.choice.used, "recording");
    assert!(asked.choice.plain_unevenness_ms.is_none());
}

#[test]
fn handbells_are_timed_as_heard() {
    let (sig, nominals) = tuned_ring();
    let opts = strike_options(0.3).unwrap();
    let c = choose_timing(&opening(&sig), &nominals, Voice::Handbell, TimingAsked::Auto, &opts).unwrap();
    assert_eq!(c.choice.used, "plain");
    assert!(c.choice.reason.contains("handbells"), "{}", c.choice.reason);
    let refused = choose_timing(&sig, &nominals, Voice::Handbell, TimingAsked::Recording, &opts);
    assert!(refused.is_err());
    assert!("sometimes".parse::<TimingAsked>().is_err());
}

/// Nominals given a little off where the recording's bells are heard
/// (nom-14, tester21's fault 2): only where neither timing's strikes come
/// even are the nominals moved to the learner's nearby ones tried; a ring
/// timed evenly as given keeps the nominals given (a guard: it passes
/// without that trial too).
#[test]
fn a_bell_given_a_little_off_its_note_but_timed_evenly_is_listened_for_as_given() {
    let (sig, mut nominals) = late_bells();
    // Bell 2 given 1.5 % sharp: the recording's timing still times it
    // evenly (21 ms in 300 ms intervals), so nothing is moved.
    nominals[1] *= 1.015;
    let opts = strike_options(0.3).unwrap();
    let c = choose_timing(&opening(&sig), &nominals, Voice::Tower, TimingAsked::Auto, &opts).unwrap();
    let ch = &c.choice;
    assert_eq!(ch.used, "recording", "{ch:?}");
    assert!(ch.nominals_heard_hz.is_none() && ch.near_strikes.is_none(), "{ch:?}");
    assert!(!ch.reason.contains("listened for"), "{}", ch.reason);
}
