//! Issue 44 on synthetic logs with what real ones have: per-axis zero
//! offsets (to 1.2 m/s²) and gains (0.95-1.05), a headstock that rings
//! after each strike (at Data141's level, clipping the readings at ±2 g
//! for a second), stands on the stay past the balance, lowering from the
//! balance, free swings after it, and the sensor upside down on the axes
//! given. The calibration, the bottoms (against the truth and against the
//! moment of greatest speed), the stands, the phases and the
//! odd-struckness are checked.

use clapper_core::bell::Bell;
use clapper_signal::ringing_log::{analyse_log, AccelLog, LogAnalysis, LogOptions, PhaseKind};
use clapper_signal::ringing_log_synth::{synth_log, LogSpec, LogTruth};

/// How hard the headstock rings after a strike.
#[derive(Clone, Copy, PartialEq)]
enum Ring {
    /// As Data141's (measured there over its 12 ringing strikes: some axis
    /// clipped at ±2 g in 95 % of the samples of the first 0.1 s after the
    /// strike, 55 % at 0.3-0.4 s, 28 % at 0.9-1.0 s, the last clipped
    /// sample 1.0-1.4 s after; here, on the 12 of seed 7, 94 %, 67 %, 34 %,
    /// 0.8-1.4 s): 50 m/s² dying over 0.4 s.
    Clipping,
    /// 0.3 m/s² over 0.25 s: under the burst threshold for most of it.
    Mild,
}

/// A log shaped like belfry-sleuth's Data141 (100 Hz; down, raised, set,
/// rung with stands on the stay 2-7 deg past the balance (Data141's read
/// 176-190 deg), lowered from the balance, then swinging freely), the
/// sensor 0.2 m above the pivot and 0.02 m across, upside down on the axes
/// given, with `offset` (radial, tangential, axle; m/s²) and `gain`.
fn shaped_like_data141(seed: u64, offset: [f64; 3], gain: [f64; 3], strokes: usize, ring: Ring) -> LogSpec {
    let mut bell = Bell::gsm_tenor();
    bell.hanging.pivot_offset = [0.0, 0.003, -0.004, 0.005][(seed % 4) as usize];
    let mut spec = LogSpec::new(bell, seed);
    spec.sensor.along = 0.2;
    spec.sensor.across = 0.02;
    spec.strokes = strokes;
    spec.rest_s = 6.0;
    spec.set_s = 5.0;
    spec.offset = offset;
    spec.gain = gain;
    (spec.ring, spec.ring_s) = match ring {
        Ring::Clipping => (50.0, 0.4),
        Ring::Mild => (0.3, 0.25),
    };
    spec.stand_every = 2;
    spec.stand_s = 2.0;
    spec.stay = (2.0 + (seed % 6) as f64).to_radians();
    spec.free_s = 25.0;
    spec
}

/// Turned upside down (180 deg about the pivot's axis), as Data141 reads
/// on the default axes.
fn upside_down(mut log: AccelLog) -> AccelLog {
    for v in log.radial.iter_mut().chain(log.tangential.iter_mut()) {
        *v = -*v;
    }
    log
}

#[derive(Default, Debug)]
struct Worst {
    /// Bottoms (swings of 45 deg or more), in samples...
    bdc: f64,
    /// ... and of the ringing's swings.
    bdc_ringing: f64,
    /// Bottom read minus the moment of greatest speed read (ms), ringing.
    speed: f64,
    /// Stands (amplitudes of strokes falling from a stand), deg.
    stand: f64,
    /// Odd-struckness (ms).
    odd: f64,
    /// Offsets (m/s²) and gains.
    offset: f64,
    gain: f64,
    missed: usize,
    /// Of the ringing's swings.
    missed_ringing: usize,
    /// Bottoms found (swings of 45 deg or more) more than a sample off.
    off: usize,
}

impl Worst {
    /// The worse of each.
    fn merge(&mut self, o: &Worst) {
        self.bdc = self.bdc.max(o.bdc);
        self.bdc_ringing = self.bdc_ringing.max(o.bdc_ringing);
        self.speed = self.speed.max(o.speed);
        self.stand = self.stand.max(o.stand);
        self.odd = self.odd.max(o.odd);
        self.offset = self.offset.max(o.offset);
        self.gain = self.gain.max(o.gain);
        self.missed += o.missed;
        self.missed_ringing += o.missed_ringing;
        self.off += o.off;
    }
}

fn check(spec: &LogSpec, log: &AccelLog, truth: &LogTruth, got: &LogAnalysis, w: &mut Worst) {
    let kinds = |p: &[clapper_signal::ringing_log::Phase]| p.iter().map(|x| x.kind).collect::<Vec<_>>();
    assert_eq!(kinds(&got.phases), kinds(&truth.phases), "{:?}", got.phases);
    // "A sample": the longer of the two intervals about the time (the
    // log is jittered), as tests/ringing_log.rs counts it.
    let interval_at = |x: f64| {
        let k = log.t.partition_point(|&u| u < x).clamp(1, log.t.len() - 1);
        let next = log.t.get(k + 1).map_or(0.0, |u| u - log.t[k]);
        (log.t[k] - log.t[k - 1]).max(next)
    };
    for t in truth.strokes.iter().filter(|t| t.amplitude > 45f64.to_radians()) {
        let Some(g) = got.strokes.iter().find(|g| (g.bdc - t.bdc).abs() < 0.2) else {
            eprintln!("missed: {:.3} {:?} {:.1} deg", t.bdc, t.phase, t.amplitude.to_degrees());
            w.missed += 1;
            w.missed_ringing += usize::from(t.phase == PhaseKind::Ringing);
            continue;
        };
        let e = (g.bdc - t.bdc).abs() / interval_at(t.bdc);
        let ea = (g.amplitude - t.amplitude).abs().to_degrees();
        if e > 1.0 || ea > 2.0 {
            eprintln!(
                "outlier: {:.3} {:?} {:.1} deg: bdc off {e:.2} samples, amplitude read {:.1}",
                t.bdc,
                t.phase,
                t.amplitude.to_degrees(),
                g.amplitude.to_degrees()
            );
        }
        w.bdc = w.bdc.max(e);
        w.off += usize::from(e > 1.0);
        if t.phase == PhaseKind::Ringing {
            w.bdc_ringing = w.bdc_ringing.max(e);
        }
        // A stroke that fell from a stand: its amplitude is the stand's.
        if t.phase == PhaseKind::Ringing && t.amplitude > 150f64.to_radians() {
            w.stand = w.stand.max((g.amplitude - t.amplitude).abs().to_degrees());
        }
        if g.phase == PhaseKind::Ringing {
            if let Some(sp) = g.speed_peak {
                w.speed = w.speed.max((g.bdc - sp).abs() * 1e3);
            }
        }
    }
    if let (Some((o, _)), Some(t)) = (got.odd_struck, truth.odd_struck) {
        w.odd = w.odd.max((o - t).abs() * 1e3);
    }
    let c = got.calibration.expect("calibrated");
    // The sensor's tangential and radial offsets (the log turned over and
    // back).
    w.offset = w
        .offset
        .max((c.offset[0] - spec.offset[1]).abs())
        .max((c.offset[1] - spec.offset[0]).abs());
    w.gain = w
        .gain
        .max((c.gain[0] - spec.gain[1]).abs())
        .max((c.gain[1] - spec.gain[0]).abs());
}

/// Read `spec`'s log turned upside down, with default options: each
/// figure's worst.
fn read(spec: &LogSpec) -> Worst {
    let (log, truth) = synth_log(spec).expect("synthesised");
    let log = upside_down(log);
    let got = analyse_log(&log, &LogOptions::default()).expect("read");
    assert!(got.orientation.is_some_and(|o| o.flipped), "{:?}", got.warnings);
    let mut w = Worst::default();
    match got.odd_struck {
        Some((o, se)) => assert!(se > 0.0 && o.is_finite()),
        // Not read: as bad as can be.
        None => w.odd = f64::INFINITY,
    }
    check(spec, &log, &truth, &got, &mut w);
    w
}

/// The acceptance on the ringing: every swing found, bottoms
/// within a sample and within 5 ms of the moment of greatest speed, stands
/// within 2 deg, odd-struckness within 3 ms; the calibration's offsets and
/// gains.
fn assert_ringing_read(w: &Worst) {
    assert_eq!(w.missed_ringing, 0, "ringing swings missed");
    assert!(w.bdc_ringing <= 1.0, "ringing bottom off by {} samples", w.bdc_ringing);
    assert!(w.speed <= 5.0, "bottom {} ms from the greatest speed", w.speed);
    assert!(w.stand <= 2.0, "stand off by {} deg", w.stand);
    assert!(w.odd <= 3.0, "odd-struck off by {} ms", w.odd);
    assert!(w.offset <= 0.05, "offset off by {} m/s²", w.offset);
    assert!(w.gain <= 0.005, "gain off by {}", w.gain);
}

/// One log shaped like Data141, its headstock clipping for a second after
/// each strike, read with default options: turned over, calibrated, every
/// phase (down, raising, up, ringing with stands, lowering from the
/// balance, down with its free swings), and the ringing as the issue asks.
#[test]
fn a_log_shaped_like_data141_is_read_right() {
    let spec = shaped_like_data141(7, [0.9, -1.1, 0.6], [1.03, 1.045, 0.98], 12, Ring::Clipping);
    let w = read(&spec);
    eprintln!("{w:?}");
    assert_ringing_read(&w);
}

/// Thirty logs, offsets to 1.2 m/s² and gains 0.95-1.05 on each axis, the
/// headstock clipping for a second after each strike as Data141's does,
/// stands on the stay: every swing of the ringing found, its bottoms within
/// a sample (0.17 at worst), every top and stand within 2 deg (1.6 at
/// worst; 17 of 30 logs before the tops were read from their clean
/// samples, up to 21 deg off), odd-struckness within 3 ms on all 30 (28
/// before; one, seed 306, counted its first lowering stroke as ringing
/// until the end of the ringing was also read from the swings' times),
/// the calibration's offsets within 0.04 m/s² and gains within 0.004, the
/// ringing's bottoms within 5 ms of the greatest speed on all 30 (29
/// before the headstock's ring was taken out of the readings, `unring.rs`:
/// seed 329, 83 ms). Not yet met: the raising's and lowering's swings of
/// 45 deg or more, where the headstock still rings through the next
/// bottom, are not all found, nor all within a sample: 12 of some 900
/// missed over the 30 logs and 38 more than a sample off, the worst 16.9
/// samples (464 missed before the ring was taken out, 169 while a sample
/// was left out when any axis clipped; 53 missed and 206 off before the
/// clipped readings were read through and the strikes hidden in the
/// ringing found; 25 and 47, the worst 32.2 samples, before the ring was
/// also fitted as one dying oscillation from each strike to the next,
/// `dying.rs`); asserted as ceilings, not the acceptance.
#[test]
fn thirty_logs_with_offsets_gains_and_a_clipping_headstock() {
    let mut w = Worst::default();
    let mut met = [0usize; 3];
    for seed in 300u64..330 {
        let spec = varied(seed, Ring::Clipping);
        let one = read(&spec);
        eprintln!("seed {seed}, {} Hz: {one:?}", spec.rate);
        for (m, ok) in met.iter_mut().zip([one.odd <= 3.0, one.stand <= 2.0, one.speed <= 5.0]) {
            *m += usize::from(ok);
        }
        w.merge(&one);
    }
    eprintln!("{w:?}\nodd-struckness, stands, greatest speed met in {met:?} of 30");
    assert_eq!(w.missed_ringing, 0, "ringing swings missed");
    assert!(w.bdc_ringing <= 1.0, "ringing bottom off by {} samples", w.bdc_ringing);
    assert!(w.stand <= 2.0, "top or stand off by {} deg", w.stand);
    assert!(w.odd <= 3.0, "odd-struck off by {} ms", w.odd);
    assert!(w.offset <= 0.05, "offset off by {} m/s²", w.offset);
    assert!(w.gain <= 0.005, "gain off by {}", w.gain);
    assert!(w.speed <= 5.0, "bottom {} ms from the greatest speed", w.speed);
    assert!(w.missed <= 12, "{} swings of raising and lowering missed", w.missed);
    assert!(
        w.off <= 38,
        "{} bottoms of raising and lowering more than a sample off",
        w.off
    );
}

/// Thirty logs as above under a milder ring (under the burst threshold for
/// most of it): the acceptance, every swing found, the ringing's
/// bottoms within a sample and within 5 ms of the greatest speed, stands
/// within 2 deg, odd-struckness within 3 ms; and every bottom of 45 deg
/// or more, the raising's and lowering's too, within a sample (0.52 at
/// worst, with the headstock's ring taken out of the readings or without:
/// the 1.1 samples this test allowed, for a 1.07 once measured, no longer
/// needed).
#[test]
fn thirty_logs_with_offsets_gains_and_a_ringing_headstock() {
    let mut w = Worst::default();
    for seed in 300u64..330 {
        let spec = varied(seed, Ring::Mild);
        let one = read(&spec);
        eprintln!("seed {seed}, {} Hz: {one:?}", spec.rate);
        w.merge(&one);
    }
    eprintln!("{w:?}");
    assert_ringing_read(&w);
    assert_eq!(w.missed, 0);
    assert!(w.bdc <= 1.0, "bottom off by {} samples", w.bdc);
}

/// Log `seed` of the thirty: offsets and gains spread over their ranges,
/// 100, 160 or 250 Hz.
fn varied(seed: u64, ring: Ring) -> LogSpec {
    let u = |k: u64| ((seed * 7919 + k * 104_729) % 1000) as f64 / 999.0;
    let offset = [0, 1, 2].map(|k| (2.0 * u(k) - 1.0) * 1.2);
    let gain = [3, 4, 5].map(|k| 0.95 + 0.1 * u(k));
    let mut spec = shaped_like_data141(seed, offset, gain, 16, ring);
    spec.rate = [100.0, 160.0, 250.0][(seed % 3) as usize];
    spec
}

/// Stands too short to be read as rests (1.2 s on the stay): each stroke
/// that falls from one is read at the stand's angle, within 2 deg.
#[test]
fn short_stands_are_read_at_their_angle() {
    let mut w = Worst::default();
    for seed in [11u64, 12, 13] {
        let mut spec = shaped_like_data141(seed, [0.5, -0.4, 0.2], [1.02, 0.99, 1.0], 12, Ring::Mild);
        spec.stand_s = 1.2;
        let one = read(&spec);
        eprintln!("seed {seed}: {one:?}");
        w.merge(&one);
    }
    assert!(w.stand <= 2.0, "stand off by {} deg", w.stand);
}
