//! Self-calibration does no harm where the bells are tuned as assumed
//! (issue 43, docs/strikes.md, "`--nominals` timed from the recording's
//! own strikes"): `bench/strikes`' clean synthetic eight, which a tuned
//! bell's partials already hear at the start of each strike.

use clapper_signal::self_calibrate::calibrate;
use clapper_signal::strikes::{find_strikes, StrikeOptions};
use clapper_signal::tower::*;

/// `bench/strikes`' base ring (as `clapper synth-ring` makes it): eight
/// bells of a major scale down to a 700 Hz tenor, rounds, 30 rows at
/// 220 ms, errors within ±15 ms, white noise at 25 dB, three doubles.
fn clean_eight(seed: u64) -> TowerSpec {
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
        ..TowerSpec::new(tuned_ring(8, 700.0, Scale::Major).expect("eight bells"))
    }
}

/// Tuned bells are found tuned as assumed (their partials learned a tuned
/// bell's, heard where a tuned bell's partials hear them) and keep their
/// times heard: lined up on their averages instead, strikes had been put
/// more than 10 ms off (a start learned up to 35 ms early, or the strikes
/// lined up scattered).
#[test]
fn tuned_bells_keep_their_times_heard_when_self_calibrated() {
    let opts = StrikeOptions::default();
    for seed in [1, 2] {
        let spec = clean_eight(seed);
        let (sig, truth) = tower_recording(&spec).unwrap();
        let nominals: Vec<f64> = spec.bells.iter().map(|b| b.nominal_hz).collect();
        let c = calibrate(&sig, &nominals, &opts).unwrap();
        let mut heard = find_strikes(&sig, &c.voices, &opts).unwrap();
        c.retime_each(&sig, &mut heard);
        let recall = score(&heard.times(), &truth, 0.010).recall();
        eprintln!("seed {seed}: recall within 10 ms {recall:.3}");
        // 0.950 and 0.971 (seeds 1, 2); 0.908 on seed 1 without the mend
        // (the library alone: no doubles judged).
        assert!(recall >= 0.94, "seed {seed}: recall within 10 ms {recall:.3}");
        let tuned = c.bells.iter().filter(|b| b.tuned).count();
        assert!(tuned >= 3, "seed {seed}: {tuned} of 8 bells found tuned as assumed");
    }
}
