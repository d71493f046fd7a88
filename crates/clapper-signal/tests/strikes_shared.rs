//! A bell whose nominal lies on other bells' partials, on the swing row of
//! bench/strikes (`clapper synth-ring`'s eight, treble 1400 Hz, swing
//! 10 dB with a 0.8 % Doppler shift, 30 rows, SNR 25 dB): bell 6's nominal
//! (832.4 Hz) is bell 3's quint and the treble's tierce, so it is heard
//! in its tierce and hum alone, where the swing leaves no strike standing
//! clear; and the tenor's last strike, after which only tails sound.

use clapper_signal::strikes::{find_strikes, BellVoice, StrikeOptions};
use clapper_signal::tower::*;

/// The swing row at `seed` (no double strikes planted).
fn swing(seed: u64) -> TowerSpec {
    TowerSpec {
        rows: 30,
        seed,
        tail: 3.0,
        snr_db: Some(25.0),
        swing: Some(Swing {
            level_db: 10.0,
            doppler: 0.008,
        }),
        ..TowerSpec::new(major_scale(8, 1400.0).expect("eight bells"))
    }
}

/// The strikes heard (bell, onset s) and the true ones.
fn heard(spec: &TowerSpec) -> (Vec<(usize, f64)>, Vec<TrueStrike>) {
    let (sig, truth) = tower_recording(spec).unwrap();
    let voices: Vec<BellVoice> = spec
        .bells
        .iter()
        .map(|b| BellVoice::from_nominal(b.nominal_hz))
        .collect();
    let h = find_strikes(&sig, &voices, &StrikeOptions::default()).unwrap();
    (h.strikes.iter().map(|s| (s.bell, s.t)).collect(), truth)
}

/// Of `bell`'s true strikes, how many were heard as that bell within `tol` s.
fn within(heard: &[(usize, f64)], truth: &[TrueStrike], bell: usize, tol: f64) -> usize {
    truth
        .iter()
        .filter(|t| t.bell == bell)
        .filter(|t| heard.iter().any(|h| h.0 == bell && (h.1 - t.t).abs() <= tol))
        .count()
}

/// Seed 2: bell 6 was heard within 10 ms at 10 of its 30 strikes (its
/// strikes chosen by the ring's rhythm among its hum's and tierce's
/// peaks); heard again with its nominal's band, the strikes of bells 3
/// and 1 taken out of it, at every one.
#[test]
fn a_bell_heard_in_the_band_it_shares_between_the_sharers_strikes() {
    let (h, truth) = heard(&swing(2));
    let n = within(&h, &truth, 6, 0.01);
    assert!(n >= 28, "bell 6 heard within 10 ms at {n} of 30 strikes");
}

/// Seed 1: the tenor's last strike (0.62 of a typical strike) was
/// outweighed by the bump the swing leaves 0.6 s after it (0.66), and a
/// strike was reported 0.66 s after the ring had ended.
#[test]
fn no_strike_off_the_rhythm_after_the_ring_has_ended() {
    let (h, truth) = heard(&swing(1));
    let last = truth.iter().map(|s| s.t).fold(f64::NEG_INFINITY, f64::max);
    let after: Vec<_> = h.iter().filter(|x| x.1 > last + 0.05).collect();
    assert!(after.is_empty(), "heard after the last strike ({last:.3} s): {after:?}");
    assert_eq!(within(&h, &truth, 6, 0.01), 30, "bell 6");
}
