//! The tests of `learn.rs` (moved here to keep that file under 1,000 lines).

use super::*;

/// A frame lasts about 90 ms at whatever rate a recording is decimated
/// to (44.1 kHz to 11.025 kHz, 48 kHz to 12 kHz, 32 and 96 kHz to
/// 10.67 kHz): at 12 kHz it lasted 171 ms.
#[test]
fn a_frame_lasts_about_ninety_ms_at_any_rate() {
    for rate in [
        8000.0, 10_666.7, 11_025.0, 12_000.0, 16_000.0, 24_000.0, 48_000.0, 96_000.0,
    ] {
        let ms = frame_len(rate) as f64 / rate * 1e3;
        assert!((63.0..=150.0).contains(&ms), "{rate} Hz: {ms:.0} ms");
    }
    // The rates the recorded rings and the tests were tuned at keep
    // their frames.
    assert_eq!(frame_len(11_025.0), 1024);
    assert_eq!(frame_len(10_666.7), 1024);
    assert_eq!(frame_len(16_000.0), 2048);
    assert_eq!(frame_len(14_700.0), 2048);
}

/// A rise that wavers by up to `wobble` (fraction) about 500 with no
/// strike, 7,000 frames of 42.7 ms (299 s).
fn wavering(wobble: f64) -> Vec<f64> {
    (0..7000)
        .map(|t| 500.0 * (1.0 + wobble * ((t as f64 * 12.9898).sin() * 43_758.545).fract().abs()))
        .collect()
}

/// Fast ringing in a room: every frame rises with some bell (the rise
/// never under 500) and a strike only to 850, every 4.7 frames (0.2
/// s). Twice the lower quartile hears none of them (the ring's tenor
/// was never heard and `--bells 8` learned another bell twice); the
/// lowered floor hears them all. Noise alone is still no strike.
#[test]
fn fast_ringing_in_a_room_keeps_its_onsets() {
    let mut flux = wavering(0.05);
    let strikes: Vec<usize> = (1..1480).map(|k| (4.7 * k as f64) as usize).collect();
    for &p in &strikes {
        flux[p] = 850.0;
        flux[p + 1] = 650.0;
    }
    let secs = 7000.0 * 512.0 / 12_000.0;
    assert!(pick_onsets(&flux, 2.0).len() < 10);
    let heard = onsets_of(&flux, secs);
    assert_nearly_all_heard(&strikes, &heard);
    assert!(heard.len() <= strikes.len() + 5, "{} onsets", heard.len());
    // The noise's rise wavers by 29 % over its lower quartile (white
    // noise's, measured): no onset.
    assert!(onsets_of(&wavering(0.29), secs).is_empty());
    // One bell every 1.5 s (35 frames): its strikes stand far over
    // the rise of its decays' noise, and the floor stays.
    let mut sparse: Vec<f64> = wavering(0.5).iter().map(|v| v - 500.0).collect();
    for p in (10..6990).step_by(35) {
        sparse[p] = 2000.0;
    }
    assert_eq!(onsets_of(&sparse, secs), pick_onsets(&sparse, 2.0));
}
/// Fast ringing in a room where a third of the strikes stand over
/// twice the lower quartile (1,150 against 506) and the rest barely
/// over it (850): the first floor hears 1.65 onsets a second of the
/// ring's 4.96, too few for any ring, and the lowered floor hears
/// them all.
#[test]
fn fast_ringing_with_a_third_of_its_strikes_heard_keeps_them_all() {
    let mut flux = wavering(0.05);
    let strikes: Vec<usize> = (1..1480).map(|k| (4.7 * k as f64) as usize).collect();
    for (k, &p) in strikes.iter().enumerate() {
        flux[p] = if k % 3 == 0 { 1150.0 } else { 850.0 };
        flux[p + 1] = 650.0;
    }
    let secs = 7000.0 * 512.0 / 12_000.0;
    let first = pick_onsets(&flux, 2.0).len() as f64 / secs;
    assert!((1.5..2.5).contains(&first), "{first} onsets a second");
    assert_nearly_all_heard(&strikes, &onsets_of(&flux, secs));
}

/// 99 % of the `strikes` (frames) among the onsets `heard`.
fn assert_nearly_all_heard(strikes: &[usize], heard: &[usize]) {
    let found = strikes.iter().filter(|p| heard.contains(p)).count();
    assert!(
        found as f64 >= 0.99 * strikes.len() as f64,
        "{found} of {}",
        strikes.len()
    );
}
use crate::strikes::learn_real_tests::{learned_from_strikes, worst_percent};
use crate::tower::{major_scale, tower_recording, tuned_ring, Doublets, Room, Scale, TowerSpec, Voice};

/// The worst error (%) of the nominals learned from `spec`'s ring
/// against its true ones, and the warnings.
fn worst_error(spec: &TowerSpec) -> (f64, Vec<String>) {
    let (sig, _) = tower_recording(spec).unwrap();
    let n = spec.bells.len();
    let l = learn_nominals(&sig, n).unwrap();
    let got: Vec<String> = l
        .bells
        .iter()
        .map(|b| format!("{:.1} ({:.2})", b.nominal_hz, b.confidence))
        .collect();
    eprintln!("{n} bells seed {}: learned {}", spec.seed, got.join(", "));
    if l.bells.len() < n {
        return (f64::INFINITY, l.warnings);
    }
    let learned: Vec<f64> = l.bells.iter().map(|b| b.nominal_hz).collect();
    (worst_percent(&spec.bells, &learned), l.warnings)
}

// Seeds 1-2 (tenor 500 Hz) were used while choosing the parameters;
// 11-12 (tenor 600 Hz) are reported. Ten and twelve bells are printed,
// not asserted: a tierce or prime is still taken for a low bell's
// nominal at times (docs/strikes.md, "--bells N").
#[test]
fn learns_tuned_rings_within_one_percent() {
    let mut failed = vec![];
    for seed in [11, 12] {
        for (n, scale) in [
            (6, Scale::Major),
            (8, Scale::Minor),
            (10, Scale::Major),
            (12, Scale::Minor),
        ] {
            let spec = TowerSpec {
                seed,
                rows: 16,
                interval: 2.0 / (n as f64 + 1.0),
                doublets: Some(Doublets::REAL),
                room: Some(Room::chamber(0.8)),
                snr_db: Some(20.0),
                ..TowerSpec::new(tuned_ring(n, 600.0, scale).unwrap())
            };
            let (worst, warnings) = worst_error(&spec);
            eprintln!("{n} bells seed {seed}: worst {worst:.2} %; {warnings:?}");
            if n <= 8 && !(worst < 1.0 && warnings.is_empty()) {
                failed.push((n, seed, worst, warnings));
            }
        }
    }
    assert!(failed.is_empty(), "{failed:?}");
}

/// Six bells with a recorded tower bell's partials (the two lowest
/// with their nominal far stronger than their prime, as the recorded
/// ring's), rung in rounds dry and in a room: every nominal (twice
/// the prime) within 1 %, not the prime.
#[test]
fn learns_untuned_bells_within_one_percent_dry_and_in_a_room() {
    let rate = 22050.0;
    let bells = tuned_ring(6, 1040.0, Scale::Major).unwrap();
    let strikes: Vec<Signal> = bells
        .iter()
        .enumerate()
        .map(|(i, b)| {
            crate::sampled_ring::octave_heavy_strike(b.nominal_hz, if i >= 4 { 8.0 } else { 1.0 }, rate, 7 + i as u64)
        })
        .collect();
    let cases = [(None, 25.0, 1.0), (Some(Room::chamber(1.0)), 20.0, 1.0)];
    let failed = failed_in_rooms(rate, &bells, &strikes, 3, &cases);
    assert!(failed.is_empty(), "{failed:?}");
}

/// Of `cases` (a room, the SNR in dB, the worst error allowed in %), those
/// where `bells` struck as `strikes` (at `rate` Hz, seed `seed`, 24 rows
/// of rounds 2/7 s apart, 20 ms jitter) are learned with some nominal off
/// by as much or more: (RT60 s, nominals learned Hz, worst %).
fn failed_in_rooms(
    rate: f64,
    bells: &[crate::tower::RingBell],
    strikes: &[Signal],
    seed: u64,
    cases: &[(Option<Room>, f64, f64)],
) -> Vec<(Option<f64>, Vec<f64>, f64)> {
    let mut failed = vec![];
    for &(room, snr, within) in cases {
        let spec = TowerSpec {
            rate,
            seed,
            rows: 24,
            interval: 2.0 / 7.0,
            jitter: 0.02,
            room,
            snr_db: Some(snr),
            ..TowerSpec::new(bells.to_vec())
        };
        let (got, worst) = learned_from_strikes(&spec, strikes);
        eprintln!("room {room:?}: learned {got:.1?}, worst {worst:.2} %");
        if worst >= within {
            failed.push((room.map(|r| r.rt60_s), got, worst));
        }
    }
    failed
}

/// The Python layers test's ring (`clapper synth-ring --bells 8 --rows
/// 16 --plain-hunt --doublets 0.1:3 --swing-db 8 --rt60 0.8 --snr 20
/// --noise wind --double 3:6:70:0.8 --seed 5`): a major eight from a
/// 1400 Hz treble, every bell within 1 % (a learner once took three
/// partials for the top three bells here).
#[test]
fn learns_an_eight_with_the_swing_a_room_and_wind_within_one_percent() {
    let spec = TowerSpec {
        seed: 5,
        rows: 16,
        tail: 3.0,
        method: crate::tower::Method::PlainHunt,
        doublets: Some(Doublets {
            split_hz: (0.1, 3.0),
            share: (0.2, 0.8),
        }),
        swing: Some(crate::tower::Swing {
            level_db: 8.0,
            doppler: 0.0,
        }),
        room: Some(Room::chamber(0.8)),
        snr_db: Some(20.0),
        noise: crate::tower::Noise::Wind,
        doubles: vec![crate::tower::DoubleStrikeSpec {
            bell: 3,
            row: 6,
            delay_ms: 70.0,
            amplitude_ratio: 0.8,
        }],
        ..TowerSpec::new(major_scale(8, 1400.0).unwrap())
    };
    let (worst, warnings) = worst_error(&spec);
    assert!(worst < 1.0, "worst {worst:.2} %; {warnings:?}");
}

/// A strike whose nominal is a doublet as a recorded tenor's (d6: 1228
/// Hz as loud as struck and soon gone, 1237 Hz lasting): the lower
/// component 0.8 % below `nominal`, at first stronger, decaying in
/// 0.15 s; the upper at `nominal`, lasting; the other partials a tuned
/// bell's.
fn doublet_strike(nominal: f64, rate: f64) -> Signal {
    let parts = [
        (0.25, 0.35, 1.5),
        (0.5, 0.45, 1.2),
        (0.5946, 0.5, 1.0),
        (0.992, 0.8, 0.15),
        (1.0, 0.6, 1.5),
        (1.5, 0.45, 0.8),
        (2.0, 0.35, 0.6),
    ];
    let samples = (0..(2.0 * rate) as usize)
        .map(|k| {
            let t = k as f64 / rate;
            let tone: f64 = parts
                .iter()
                .map(|&(r, a, tau)| a * (-t / tau).exp() * (2.0 * std::f64::consts::PI * r * nominal * t + r).sin())
                .sum();
            tone * (1.0 - (-t / 0.002).exp())
        })
        .collect();
    Signal { rate, samples }
}

/// Six bells whose nominals are doublets that change as they sound
/// ([`doublet_strike`]): each learned within 0.3 % of the lasting
/// component dry, within 1 % in a room (its tail keeps the early one
/// sounding: the treble and tenor are learned at it, 0.8 % low). From
/// the rise of the strikes alone: 1.02 % and 1.16 %.
#[test]
fn a_nominal_doublet_is_learned_at_the_component_that_lasts() {
    let rate = 22050.0;
    let bells = tuned_ring(6, 1040.0, Scale::Major).unwrap();
    let strikes: Vec<Signal> = bells.iter().map(|b| doublet_strike(b.nominal_hz, rate)).collect();
    let cases = [(None, 25.0, 0.3), (Some(Room::chamber(1.0)), 20.0, 1.0)];
    let failed = failed_in_rooms(rate, &bells, &strikes, 4, &cases);
    assert!(failed.is_empty(), "{failed:?}");
}

#[test]
fn learns_handbells_within_one_percent() {
    let spec = TowerSpec {
        seed: 11,
        rows: 16,
        voice: Voice::Handbell,
        ..TowerSpec::new(major_scale(8, 1400.0).unwrap())
    };
    let (worst, warnings) = worst_error(&spec);
    assert!(worst < 1.0, "worst {worst:.2} %; {warnings:?}");
}

/// Two bells learned within half a percent (seen on rings in a room
/// whose partials were moved by octaves onto one note) are one bell,
/// the one heard more, with both's onsets; others are kept.
#[test]
fn two_bells_learned_at_one_nominal_are_one() {
    let bell = |nominal_hz: f64, onsets: usize| LearnedBell {
        nominal_hz,
        confidence: onsets as f64 / 20.0,
        onsets,
        support: onsets as f64 / 20.0,
        partials_fit: 1.0,
    };
    let got = one_per_nominal(vec![
        bell(2654.8, 6),
        bell(2649.9, 14),
        bell(1750.0, 20),
        bell(1645.0, 20),
    ]);
    assert_eq!(got.len(), 3, "{got:?}");
    assert_eq!(got[0].nominal_hz, 2649.9);
    assert_eq!(got[0].onsets, 20);
    assert_eq!(got[1].nominal_hz, 1750.0);
}

#[test]
fn too_many_bells_asked_is_warned_of() {
    let spec = TowerSpec {
        rows: 16,
        ..TowerSpec::new(major_scale(6, 1400.0).unwrap())
    };
    let (sig, _) = tower_recording(&spec).unwrap();
    let l = learn_nominals(&sig, 10).unwrap();
    assert!(l.bells.len() < 10, "{:?}", l.bells);
    assert!(
        l.warnings.iter().any(|w| w.contains("10 bells asked for")),
        "{:?}",
        l.warnings
    );
}

#[test]
fn silence_is_refused_in_words() {
    let sig = Signal {
        rate: 22050.0,
        samples: vec![0.0; 22050 * 5],
    };
    let e = learn_nominals(&sig, 6).unwrap_err().to_string();
    assert!(e.contains("no strikes heard"), "{e}");
}
