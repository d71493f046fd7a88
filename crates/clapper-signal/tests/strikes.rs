//! Strikes found in synthetic recordings of known truth (docs/strikes.md):
//! a short ring for the test suite; the 20-recording benchmark is the
//! `strike_accuracy` example.

use clapper_signal::strikes::{find_strikes, BellVoice, StrikeOptions};
use clapper_signal::striking::{rhythm, Timed};
use clapper_signal::tower::*;
use clapper_signal::Signal;

fn ring(seed: u64) -> TowerSpec {
    let mut bells = major_scale(6, 1400.0).expect("at most 16 bells");
    bells[2].odd_struck_ms = 15.0;
    TowerSpec {
        rate: 16_000.0,
        seed,
        doubles: vec![DoubleStrikeSpec {
            bell: 5,
            row: 7,
            delay_ms: 70.0,
            amplitude_ratio: 0.8,
        }],
        method: Method::PlainHunt,
        snr_db: Some(25.0),
        ..TowerSpec::new(bells)
    }
}

fn voices(spec: &TowerSpec) -> Vec<BellVoice> {
    spec.bells
        .iter()
        .map(|b| BellVoice::from_nominal(b.nominal_hz))
        .collect()
}

#[test]
fn a_ring_is_heard_strike_by_strike_with_its_double_and_its_odd_struck_bell() {
    let spec = ring(11);
    let (sig, truth) = tower_recording(&spec).unwrap();
    let heard = find_strikes(&sig, &voices(&spec), &StrikeOptions::default()).unwrap();
    let h = heard.times();
    let sc = score(&h, &truth, 0.05);
    let counts: Vec<usize> = (1..=6)
        .map(|b| heard.strikes.iter().filter(|s| s.bell == b).count())
        .collect();
    assert!(
        sc.recall() >= 0.99 && sc.precision() >= 0.99,
        "{counts:?} {:?}",
        heard.warnings
    );
    let mut e: Vec<f64> = sc.onset_errors.iter().map(|v| v.abs()).collect();
    e.sort_by(f64::total_cmp);
    assert!(e[e.len() / 2] < 0.002, "median onset error {} s", e[e.len() / 2]);
    assert_eq!(sc.doubles_found, 1, "{sc:?}");
    assert!(sc.false_doubles <= 1, "{sc:?}");
    let (dd, dr) = sc.double_errors[0];
    assert!(dd.abs() < 0.005 && dr.abs() < 0.35, "double off by {dd} s, ratio {dr}");
    // Strokes and odd-struckness from the rhythm of what was heard.
    let timed: Vec<Timed> = heard.strikes.iter().map(|s| Timed { bell: s.bell, t: s.t }).collect();
    let r = rhythm(&timed, 6);
    let odd = r.odd_struck(&timed, 3).unwrap() * 1e3;
    assert!((odd - 15.0).abs() < 5.0, "odd-struck {odd} ms");
    // Against what the true times give (the planted 15 ms blurred by this
    // ring's striking errors): the listener adds under 3 ms.
    let true_timed: Vec<Timed> = truth.iter().map(|s| Timed { bell: s.bell, t: s.t }).collect();
    let own = rhythm(&true_timed, 6).odd_struck(&true_timed, 3).unwrap() * 1e3;
    assert!(
        (odd - own).abs() < 3.0,
        "odd-struck {odd} ms heard, {own} ms in the true times"
    );
    // Every strike's stroke is right.
    for (s, p) in heard.strikes.iter().zip(&r.placed) {
        if let Some(x) = truth.iter().find(|x| x.bell == s.bell && (x.t - s.t).abs() <= 0.05) {
            assert_eq!(p.hand, Some(x.hand), "bell {} at {} s", s.bell, s.t);
        }
    }
}

#[test]
fn a_reverberant_tower_does_not_pass_for_double_strikes() {
    // RT60 1.2 s: the room's build-up is in each bell's learned response,
    // so it is not heard as a second strike, and the planted one still is.
    let mut spec = ring(4);
    spec.room = Some(Room::chamber(1.2));
    let (sig, truth) = tower_recording(&spec).unwrap();
    let heard = find_strikes(&sig, &voices(&spec), &StrikeOptions::default()).unwrap();
    let h = heard.times();
    let sc = score(&h, &truth, 0.05);
    assert!(sc.recall() >= 0.97 && sc.precision() >= 0.97, "{sc:?}");
    assert!(
        sc.false_doubles <= 2,
        "{} false doubles in {} strikes",
        sc.false_doubles,
        sc.found
    );
    assert_eq!(sc.doubles_found, 1, "{sc:?}");
}

/// In a ring of eight down a major scale from 1400 Hz, bell 6's nominal
/// (832 Hz) lies on the treble's tierce (840 Hz): it is heard in its own
/// hum and tierce, whose long boxes cannot tell a second strike sooner
/// than about 120 ms. The partials it shares are fitted for a double
/// strike where no sharing bell strikes nearby and what rings there
/// before the strike is faint, and its own bands from 1.5 boxes: most of
/// its short doubles are flagged, nine in ten with their delay within
/// 10 ms and all within 30 ms (its first strike is timed in long boxes).
#[test]
fn a_double_strike_is_told_in_a_band_shared_with_another_bell() {
    let (mut found, mut put, mut false_doubles) = (0, 0, 0);
    let mut delay_errors = vec![];
    for seed in 1..=4 {
        let bells = major_scale(8, 1400.0).expect("at most 16 bells");
        let doubles = [(3, 45.0), (7, 55.0), (11, 65.0), (15, 50.0), (19, 60.0), (23, 80.0)]
            .map(|(row, delay_ms)| DoubleStrikeSpec {
                bell: 6,
                row,
                delay_ms,
                amplitude_ratio: 0.7,
            })
            .to_vec();
        let spec = TowerSpec {
            rate: 16_000.0,
            seed,
            doubles,
            method: Method::PlainHunt,
            snr_db: Some(25.0),
            ..TowerSpec::new(bells)
        };
        let (sig, truth) = tower_recording(&spec).unwrap();
        let heard = find_strikes(&sig, &voices(&spec), &StrikeOptions::default()).unwrap();
        let sc = score(&heard.times(), &truth, 0.05);
        found += sc.doubles_found;
        for (dd, dr) in &sc.double_errors {
            assert!(
                dd.abs() < 0.03 && dr.abs() < 0.35,
                "seed {seed}: double off by {dd} s, ratio {dr}"
            );
            delay_errors.push(dd.abs());
        }
        put += sc.doubles_put;
        false_doubles += sc.false_doubles;
    }
    // Measured: 24 of 24, 3 false, delays 23 within 6 ms and one 25 ms
    // off (before its own bands were fitted from 1.5 boxes and strikes
    // slid: 20 of 24, 2 false; in its own bands alone 7 of 24).
    assert!(found >= 20, "{found} of {put} doubles of bell 6 flagged");
    assert!(false_doubles <= 3, "{false_doubles} false doubles");
    let close = delay_errors.iter().filter(|e| **e < 0.01).count();
    assert!(close * 10 >= delay_errors.len() * 9, "{delay_errors:?}");
}

#[test]
fn the_same_recording_gives_the_same_strikes() {
    let spec = ring(3);
    let (sig, _) = tower_recording(&spec).unwrap();
    let a = find_strikes(&sig, &voices(&spec), &StrikeOptions::default()).unwrap();
    let b = find_strikes(&sig, &voices(&spec), &StrikeOptions::default()).unwrap();
    assert_eq!(a, b);
}

#[test]
fn silence_and_strangers_are_heard_as_nothing_with_a_warning() {
    let spec = ring(5);
    let silent = Signal {
        rate: 16_000.0,
        samples: vec![0.0; 16_000 * 5],
    };
    let h = find_strikes(&silent, &voices(&spec), &StrikeOptions::default()).unwrap();
    assert!(h.strikes.is_empty());
    assert_eq!(h.warnings.len(), 6, "{:?}", h.warnings);
    // Nominals a tritone away from every bell: nothing of theirs rings.
    let (sig, _) = tower_recording(&spec).unwrap();
    let strangers: Vec<BellVoice> = spec
        .bells
        .iter()
        .map(|b| BellVoice::from_nominal(b.nominal_hz * 2f64.powf(6.5 / 12.0)))
        .collect();
    let h = find_strikes(&sig, &strangers, &StrikeOptions::default()).unwrap();
    assert!(
        h.strikes.len() < 10,
        "{} strikes of bells that are not there",
        h.strikes.len()
    );
    // Bad requests are errors, not panics.
    assert!(find_strikes(&sig, &[], &StrikeOptions::default()).is_err());
    assert!(find_strikes(&sig, &[BellVoice::from_nominal(50_000.0)], &StrikeOptions::default()).is_err());
    let bad = StrikeOptions {
        double_window_ms: (100.0, 50.0),
        ..StrikeOptions::default()
    };
    assert!(find_strikes(&sig, &voices(&spec), &bad).is_err());
}

#[test]
fn one_bell_alone_is_heard() {
    let mut spec = ring(7);
    spec.bells.truncate(1);
    spec.doubles.clear();
    spec.interval = 1.0;
    let (sig, truth) = tower_recording(&spec).unwrap();
    let h = find_strikes(&sig, &voices(&spec), &StrikeOptions::default()).unwrap();
    let heard: Vec<_> = h.strikes.iter().map(|s| (s.bell, s.t, None)).collect();
    let sc = score(&heard, &truth, 0.01);
    assert!(sc.recall() >= 0.95 && sc.precision() >= 0.95, "{sc:?}");
}

#[test]
fn a_template_gives_the_bells_partials() {
    let spec = ring(2);
    let b = spec.bells[0];
    let mut one = spec.clone();
    one.bells = vec![b];
    one.rows = 1;
    one.doubles.clear();
    one.snr_db = None;
    let (sig, _) = tower_recording(&one).unwrap();
    let v = BellVoice::from_template(&sig).unwrap();
    // The nominal and the hum (the longest-ringing, so the loudest over two seconds).
    for f in [b.nominal_hz, 0.25 * b.nominal_hz] {
        assert!(
            v.partials.iter().any(|p| (p.freq_hz - f).abs() < 2.0),
            "{f} Hz not in {v:?}"
        );
    }
    assert!(v.partials.len() >= 5);
}
