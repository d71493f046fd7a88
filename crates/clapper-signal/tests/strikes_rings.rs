//! Strikes found on the larger and harder synthetic rings of
//! `bench/strikes` (docs/strikes.md, issue 43): ten bells, where a bell
//! is heard only in bands other bells share.

use clapper_signal::strikes::{find_strikes, BellVoice, StrikeOptions};
use clapper_signal::tower::*;

/// `bench/strikes`'s base ring (as `clapper synth-ring` makes it): rounds,
/// 30 rows at 220 ms, errors within ±15 ms, white noise at 25 dB, three
/// doubles; `bells` bells of `scale` up from `tenor_hz` (Hz).
fn bench_ring(bells: usize, tenor_hz: f64, scale: Scale, seed: u64) -> TowerSpec {
    let d = |bell, row, delay_ms, amplitude_ratio| DoubleStrikeSpec {
        bell,
        row,
        delay_ms,
        amplitude_ratio,
    };
    TowerSpec {
        rows: 30,
        seed,
        snr_db: Some(25.0),
        tail: 3.0,
        doubles: vec![d(2, 5, 50.0, 0.6), d(5, 11, 65.0, 0.8), d(7, 17, 80.0, 0.9)],
        ..TowerSpec::new(tuned_ring(bells, tenor_hz, scale).expect("at most 16 bells"))
    }
}

/// `spec`'s recording heard with each bell's nominal, and its truth.
fn heard(spec: &TowerSpec) -> (Vec<HeardTimes>, Vec<TrueStrike>) {
    let (sig, truth) = tower_recording(spec).unwrap();
    let voices: Vec<BellVoice> = spec
        .bells
        .iter()
        .map(|b| BellVoice::from_nominal(b.nominal_hz))
        .collect();
    let h = find_strikes(&sig, &voices, &StrikeOptions::default()).unwrap().times();
    (h, truth)
}

/// Each bell's share of its strikes heard within `tol` (s), and the
/// whole ring's.
fn per_bell(spec: &TowerSpec, tol: f64) -> (Vec<f64>, f64) {
    let (h, truth) = heard(spec);
    let all = score(&h, &truth, tol).recall();
    let each = (1..=spec.bells.len())
        .map(|b| {
            let hb: Vec<_> = h.iter().copied().filter(|x| x.0 == b).collect();
            let tb: Vec<_> = truth.iter().cloned().filter(|x| x.bell == b).collect();
            score(&hb, &tb, tol).recall()
        })
        .collect();
    (each, all)
}

/// On a major ten the 9th's nominal is the 2nd's prime, its prime the
/// 2nd's hum, its tierce the 7th's prime: only its hum is its own, and the
/// sharers' strikes stood as high in its onset function as its own (on
/// main it was never heard in this recording: 0 of 30 strikes within
/// 50 ms, the ring 0.893).
#[test]
fn on_ten_bells_the_bell_heard_only_in_shared_bands_is_heard() {
    let spec = bench_ring(10, 400.0, Scale::Major, 2);
    let (each, all) = per_bell(&spec, 0.05);
    assert!(each[8] >= 0.8, "bell 9 within 50 ms {}, per bell {each:?}", each[8]);
    assert!(all >= 0.97, "within 50 ms {all}, per bell {each:?}");
}

/// The ring's false doubles (strikes heard double where one was struck)
/// and its doubles found, each bell's false doubles apart.
fn false_doubles(spec: &TowerSpec) -> (Vec<usize>, usize) {
    let (h, truth) = heard(spec);
    let each = (1..=spec.bells.len())
        .map(|b| {
            let hb: Vec<_> = h.iter().copied().filter(|x| x.0 == b).collect();
            let tb: Vec<_> = truth.iter().cloned().filter(|x| x.bell == b).collect();
            score(&hb, &tb, 0.05).false_doubles
        })
        .collect();
    (each, score(&h, &truth, 0.05).doubles_found)
}

/// A bell heard only in bands it shares (the 9th of a major ten, the
/// 11th of a twelve) is judged for doubles only in those of its bands
/// where no sharer strikes nearby and what rings before the strike is
/// small beside its step, as the bands a bell shares are judged for
/// any bell: in all of them the sharers' partials, ringing on and
/// beating, were fitted as second strikes.
#[test]
fn a_bell_heard_only_in_shared_bands_is_not_called_double_by_its_sharers() {
    let (ten, ten_found) = false_doubles(&bench_ring(10, 400.0, Scale::Major, 2));
    let (twelve, twelve_found) = false_doubles(&bench_ring(12, 350.0, Scale::Major, 2));
    eprintln!("ten {ten:?} {ten_found}, twelve {twelve:?} {twelve_found}");
    assert!(ten[8] <= 6, "bell 9 of ten: {} false doubles, per bell {ten:?}", ten[8]);
    assert!(
        twelve[10] <= 8,
        "bell 11 of twelve: {} false doubles, per bell {twelve:?}",
        twelve[10]
    );
    assert!(
        ten_found >= 2 && twelve_found >= 3,
        "doubles found {ten_found}/3, {twelve_found}/3"
    );
}

/// `bench/strikes`'s swing row: the default eight (treble 1400 Hz, a
/// major scale) swinging 10 dB with a Doppler shift of 0.8 %, seed 1.
/// Bell 6 is heard in its own bands only in its tierce and hum (50 ms
/// boxes): the Doppler shift turns their phase 0.6 s after each strike
/// as far as a strike steps them, so that its strikes stand no higher
/// than those false peaks and none was taken (on main 0 of 30 within
/// 50 ms, the ring 0.871). Chosen by the ring's rhythm, its strikes are
/// heard.
#[test]
fn a_swinging_bell_whose_strikes_do_not_stand_clear_is_heard_in_the_rings_rhythm() {
    let spec = TowerSpec {
        swing: Some(Swing {
            level_db: 10.0,
            doppler: 0.008,
        }),
        bells: major_scale(8, 1400.0).expect("eight bells"),
        ..bench_ring(8, 700.0, Scale::Major, 1)
    };
    let (each, all) = per_bell(&spec, 0.05);
    assert!(each[5] >= 0.7, "bell 6 within 50 ms {}, per bell {each:?}", each[5]);
    assert!(all >= 0.95, "within 50 ms {all}, per bell {each:?}");
}
