//! Issue 44, from an independent tester's report: a sensor 0.3-0.8 m from
//! the pivot (κ = h/L up to 0.7). There the radial reading's centripetal
//! part, h θ'², is as large as gravity's, and at κ = 1/2 a free fall's
//! radial reading is the same at every angle: the angle is read from the
//! tangential axis, the radial telling only which side of the horizontal
//! (`reading::tangential_seed`). Before, none of the tester's 30 such logs
//! was read right.

use clapper_core::bell::Bell;
use clapper_signal::ringing_log::{analyse_log, AccelLog, LogOptions, PhaseKind};
use clapper_signal::ringing_log_synth::{synth_log, LogSpec};

/// Log `seed`: a GSM tenor made lighter in inertia (its equivalent
/// pendulum 1.13 m, as the tester's bells), rung with stands on the stay,
/// its sensor 0.3-0.8 m above or below the pivot and up to 0.1 m across,
/// per-axis offsets to 1.2 m/s² and gains 0.95-1.05, ±2 g, a mild ring
/// after each strike.
fn far(seed: u64) -> LogSpec {
    let u = |k: u64| ((seed * 7919 + k * 104_729) % 1000) as f64 / 999.0;
    let mut bell = Bell::gsm_tenor();
    bell.bell_inertia *= 1.13 / bell.lb();
    bell.hanging.pivot_offset = [0.0, 0.003, -0.004, 0.005][(seed % 4) as usize];
    let mut spec = LogSpec::new(bell, seed);
    let side = if seed % 2 == 0 { 1.0 } else { -1.0 };
    spec.sensor.along = side * (0.3 + 0.5 * u(6));
    spec.sensor.across = (2.0 * u(7) - 1.0) * 0.1;
    spec.offset = [0, 1, 2].map(|k| (2.0 * u(k) - 1.0) * 1.2);
    spec.gain = [3, 4, 5].map(|k| 0.95 + 0.1 * u(k));
    spec.strokes = 16;
    spec.rest_s = 6.0;
    spec.set_s = 5.0;
    (spec.ring, spec.ring_s) = (0.3, 0.25);
    spec.stand_every = 2;
    spec.stand_s = 2.0;
    spec.stay = (2.0 + (seed % 6) as f64).to_radians();
    spec.free_s = 25.0;
    spec
}

/// The worst of a log's ringing: swings missed, bottom (samples), stand
/// (deg), odd-struckness (ms).
#[derive(Debug, Default)]
struct Read {
    missed: usize,
    bdc: f64,
    stand: f64,
    odd: f64,
}

fn read(spec: &LogSpec) -> Read {
    let (log, truth) = synth_log(spec).expect("synthesised");
    let got = analyse_log(&log, &LogOptions::default()).expect("read");
    let interval_at = |log: &AccelLog, x: f64| {
        let k = log.t.partition_point(|&u| u < x).clamp(1, log.t.len() - 1);
        let next = log.t.get(k + 1).map_or(0.0, |u| u - log.t[k]);
        (log.t[k] - log.t[k - 1]).max(next)
    };
    let mut r = Read::default();
    for t in truth
        .strokes
        .iter()
        .filter(|t| t.phase == PhaseKind::Ringing && !t.hidden)
    {
        let Some(g) = got.strokes.iter().find(|g| (g.bdc - t.bdc).abs() < 0.2) else {
            r.missed += 1;
            continue;
        };
        r.bdc = r.bdc.max((g.bdc - t.bdc).abs() / interval_at(&log, t.bdc));
        // A stroke that fell from a stand: its amplitude is the stand's.
        if t.amplitude > 180f64.to_radians() {
            r.stand = r.stand.max((g.amplitude - t.amplitude).abs().to_degrees());
        }
    }
    r.odd = match (got.odd_struck, truth.odd_struck) {
        (Some((o, _)), Some(t)) => (o - t).abs() * 1e3,
        _ => f64::INFINITY,
    };
    eprintln!(
        "seed {}, sensor {:.2} m along, {:.2} across: {r:?}; read {:.3} {:.3}",
        spec.seed, spec.sensor.along, spec.sensor.across, got.sensor_along, got.sensor_across
    );
    r
}

/// Thirty logs with the sensor 0.3-0.8 m from the pivot, above it on the
/// even seeds, below on the odd: how many are read to the issue's
/// acceptance (every ringing swing found, its bottom within a sample,
/// stands within 2 deg, odd-struckness within 3 ms). A floor, not the
/// acceptance: 9 of the 30 are (500, 502, 510, 512, 514, 522, 523, 524,
/// 526); 5 before the calibration judged a stretch not free against its
/// own kind (500, 512, 524 added: their falls had all been dropped) and
/// started below the pivot where the radial reading says so (523 added;
/// docs/model.md §13.4). Not yet met, and printed: above the pivot at κ
/// 0.42-0.53 (504, 506, 516, 518, 528) the calibration settles on a
/// wrong place (at κ = 1/2 a free fall's radial reading is the same at
/// every angle); at κ 0.36-0.38 (508, 520) the first pass, kept there,
/// reads some bottoms 15-20 samples off; below the pivot, the place read
/// within 2 cm, strokes are missed or the odd-struckness is 11-48 ms off
/// (519 is not calibrated).
#[test]
fn logs_with_the_sensor_far_from_the_pivot() {
    let mut met = vec![];
    for seed in 500u64..530 {
        let r = read(&far(seed));
        if r.missed == 0 && r.bdc <= 1.0 && r.stand <= 2.0 && r.odd <= 3.0 {
            met.push(seed);
        }
    }
    eprintln!("read to the acceptance: {} of 30: {met:?}", met.len());
    assert!(met.len() >= 9, "{met:?}");
}
