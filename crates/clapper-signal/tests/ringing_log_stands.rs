//! Issue 44 on synthetic logs from the project's generator: each stroke
//! says whether it ended on the stay (a stand, its angle and how long it
//! stood), the phases are named as the issue names them (ringing with
//! stands, lowering from its first swing), a turning point hidden by the
//! headstock's ringing is not read past the balance, and the
//! odd-struckness carries the calibration's own uncertainty.

use clapper_core::bell::Bell;
use clapper_signal::ringing_log::{analyse_log, LogAnalysis, LogOptions, PhaseKind, STAND_PAST};
use clapper_signal::ringing_log_synth::{synth_log, LogSpec, LogTruth};

/// A log like belfry-sleuth's Data141 (the sensor 0.2 m above the pivot
/// and 0.02 m across, offsets and gains off, stands on the stay every
/// second stroke, `stay_deg` past the balance, for `stand_s`), its
/// headstock ringing after each strike at `ring` m/s² over 0.4 s.
fn spec(seed: u64, ring: f64, stand_s: f64, stay_deg: f64) -> LogSpec {
    let mut s = LogSpec::new(Bell::gsm_tenor(), seed);
    s.sensor.along = 0.2;
    s.sensor.across = 0.02;
    s.strokes = 16;
    s.rest_s = 6.0;
    s.set_s = 5.0;
    s.offset = [0.6, -0.8, 0.3];
    s.gain = [1.03, 0.98, 1.0];
    (s.ring, s.ring_s) = (ring, if ring > 1.0 { 0.4 } else { 0.25 });
    s.stand_every = 2;
    s.stand_s = stand_s;
    s.stay = stay_deg.to_radians();
    s.free_s = 25.0;
    s
}

fn read(spec: &LogSpec) -> (LogTruth, LogAnalysis) {
    let (log, truth) = synth_log(spec).expect("synthesised");
    let got = analyse_log(&log, &LogOptions::default()).expect("read");
    (truth, got)
}

/// Each ringing stroke that rose onto the stay (the next falls from past
/// the balance) says so, at the stand's angle within 2 deg and with how
/// long it stood; every other ringing stroke says it did not. Measured
/// over seeds 1-3: every stand found, none where there was none, angles
/// within 0.4 deg.
#[test]
fn each_stroke_says_whether_it_stood_on_the_stay() {
    for seed in 1u64..=3 {
        let spec = spec(seed, 0.3, 2.0, 4.0);
        let (truth, got) = read(&spec);
        let ringing: Vec<usize> = (0..truth.strokes.len())
            .filter(|&i| truth.strokes[i].phase == PhaseKind::Ringing)
            .collect();
        let (mut stands, mut found) = (0, 0);
        for &i in &ringing {
            let (t, next) = (&truth.strokes[i], truth.strokes.get(i + 1));
            let Some(next) = next.filter(|n| n.phase == PhaseKind::Ringing) else {
                continue;
            };
            let g = got
                .strokes
                .iter()
                .find(|g| (g.bdc - t.bdc).abs() < 0.1)
                .expect("the stroke read");
            let stood = next.amplitude > std::f64::consts::PI;
            stands += usize::from(stood);
            match (stood, g.stand) {
                (true, Some(s)) => {
                    found += 1;
                    let off = (s.angle - next.amplitude).abs().to_degrees();
                    assert!(off <= 2.0, "seed {seed}, {:.2} s: stand off by {off:.2} deg", t.bdc);
                    assert!(!s.set);
                    let d = s.duration.expect("how long it stood");
                    assert!(d > 0.0 && d <= spec.stand_s + 1.0, "seed {seed}: stood {d} s");
                }
                (false, Some(s)) => panic!(
                    "seed {seed}, {:.2} s: a stand at {:.1} deg read where it turned at {:.1}",
                    t.bdc,
                    s.angle.to_degrees(),
                    next.amplitude.to_degrees()
                ),
                (true, None) => panic!("seed {seed}, {:.2} s: its stand not read", t.bdc),
                (false, None) => {}
            }
        }
        assert!(stands >= 5 && found == stands, "seed {seed}: {found} of {stands}");
        // The ringing is named by its stands: the phase between the sets
        // holds them.
        assert!(got.phases.iter().any(|p| p.kind == PhaseKind::Ringing));
    }
}

/// Swings the lowering takes: gentle, nearer the tester's.
const LOWER_SWINGS: usize = 120;

/// Lowering straight off the last stand of the ringing (no set between,
/// as an independent tester's var20 seed 203: the first lowering stroke
/// falls from the stay) is lowering from its first swing: no ringing
/// stroke after the truth's ringing (that tester's log had its first
/// lowering stroke counted as ringing, which moved its odd-struckness by 7
/// ms), and the odd-struckness within 3 ms. The lowering is gentle
/// ([`LOWER_SWINGS`]): off the stand at 184 deg it rises to 168, 164, 160
/// deg (the ringer's default 30 swings: 157, 148, 141; the tester's 171,
/// 168, 157). (Still, the test passes with the end-of-ringing rule,
/// `declines_after` in phases.rs, switched off: the generator's ringing
/// rises to 179-184 deg, the tester's to 172-177, so the first lowering
/// stroke is below the full swings' height here anyway. Gentler still,
/// from 140 swings (169, 165, 161 deg), the first lowering strokes are
/// read as ringing under this clipping ring, rule or not: odd-struckness
/// 15.6 ms off, or no lowering found at 160. With the ringing at the
/// tester's height, `LogSpec::ring_top` 175 deg, this log of 16 strokes
/// is refused as no bell's (the angle jumps between 26 % of neighbouring
/// samples under the clipping ring, the limit 25 %); of 24 strokes, seeds
/// 5 and 6 read within 1.7 ms, seed 4 is refused, and seed 7 counts its
/// first lowering stroke as ringing with the rule on: not yet a test.)
#[test]
fn lowering_is_read_from_its_first_swing() {
    for seed in [4u64, 5, 6, 7] {
        let mut spec = spec(seed, 50.0, 1.2, 4.0);
        spec.lower_from_stand = true;
        spec.lower_swings = LOWER_SWINGS;
        let (truth, got) = read(&spec);
        let last_ringing = truth
            .strokes
            .iter()
            .filter(|t| t.phase == PhaseKind::Ringing)
            .map(|t| t.bdc)
            .fold(f64::NEG_INFINITY, f64::max);
        // The premise: the first lowering stroke falls from the stay.
        let first_lowering = truth.strokes.iter().find(|t| t.bdc > last_ringing).expect("lowering");
        assert!(first_lowering.amplitude > std::f64::consts::PI);
        let drops: Vec<f64> = truth
            .strokes
            .iter()
            .filter(|t| t.bdc > last_ringing)
            .take(4)
            .map(|t| t.amplitude.to_degrees())
            .collect();
        eprintln!("seed {seed}: lowering from {drops:.1?} deg");
        for g in got.strokes.iter().filter(|g| g.phase == PhaseKind::Ringing) {
            assert!(
                g.bdc <= last_ringing + 0.1,
                "seed {seed}: a lowering stroke at {:.2} s ({:.1} deg) read as ringing",
                g.bdc,
                g.amplitude.to_degrees()
            );
        }
        let lowering = got
            .phases
            .iter()
            .position(|p| p.kind == PhaseKind::Lowering)
            .expect("lowering");
        assert!(lowering > 0, "{:?}", got.phases);
        let (o, t) = (got.odd_struck.expect("read").0, truth.odd_struck.expect("truth"));
        assert!(
            (o - t).abs() <= 0.003,
            "seed {seed}: {:.1} ms, truth {:.1}",
            o * 1e3,
            t * 1e3
        );
    }
}

/// A log whose headstock rings through most of its length (the gentle
/// lowering of [`lowering_is_read_from_its_first_swing`] under Data141's
/// clipping ring, over half the log, and the ringing rising to the
/// tester's 175 deg) is read, not refused as no bell's. The angle jumps
/// were counted between all neighbouring samples the burst test lets
/// through, and where the ring fills most of the log the burst threshold
/// (six robust deviations of the typical sample's departure) is the
/// ring's own, so the ring's samples, reading far from g, passed as quiet:
/// the plain angle jumped between 26 % of them (seeds 4 and 6; the limit
/// 25 %). Counted where the reading is gravity's in size, 5 %.
#[test]
fn a_log_ringing_through_most_of_its_length_is_read() {
    for seed in [4u64, 6] {
        let mut spec = spec(seed, 50.0, 1.2, 4.0);
        spec.lower_from_stand = true;
        spec.lower_swings = LOWER_SWINGS;
        spec.ring_top = 175f64.to_radians();
        let (truth, got) = read(&spec);
        let p = got.plausibility;
        assert!(p.plausible() && p.jumps <= 0.1, "seed {seed}: {p:?}");
        let kinds = |v: &[clapper_signal::ringing_log::Phase]| v.iter().map(|x| x.kind).collect::<Vec<_>>();
        assert_eq!(kinds(&got.phases), kinds(&truth.phases), "seed {seed}");
        let (o, t) = (got.odd_struck.expect("read").0, truth.odd_struck.expect("truth"));
        assert!(
            (o - t).abs() <= 0.003,
            "seed {seed}: {:.1} ms, truth {:.1}",
            o * 1e3,
            t * 1e3
        );
    }
}

/// Under a headstock that clips for a second after each strike (Data141's
/// level), no swing of raising or lowering that turned back short of the
/// balance is read past it (Data141's lowering read 199-200 deg where its
/// timing says 165-168: the turning point lay wholly in the ringing).
#[test]
fn a_turning_point_hidden_by_the_ringing_is_not_read_past_the_balance() {
    for seed in [21u64, 22, 23] {
        let (truth, got) = read(&spec(seed, 50.0, 2.0, 4.0));
        for t in truth
            .strokes
            .iter()
            .filter(|t| t.phase != PhaseKind::Ringing && t.amplitude < 170f64.to_radians())
        {
            let Some(g) = got.strokes.iter().find(|g| (g.bdc - t.bdc).abs() < 0.1) else {
                continue;
            };
            assert!(
                g.amplitude < STAND_PAST,
                "seed {seed}, {:.2} s: {:.1} deg read where it turned at {:.1}",
                t.bdc,
                g.amplitude.to_degrees(),
                t.amplitude.to_degrees()
            );
        }
    }
}

/// The odd-struckness's standard error holds the calibration's share,
/// from refits of the calibration (not only its covariance), and with it
/// the error is within three standard errors on each of six logs.
#[test]
fn the_odd_struckness_carries_the_calibrations_uncertainty() {
    for seed in 31u64..=36 {
        let (truth, got) = read(&spec(seed, 0.3, 2.0, 4.0));
        let (o, se) = got.odd_struck.expect("an odd-struckness");
        let cal = got.odd_struck_calibration_se.expect("the calibration's share");
        assert!(cal > 0.0 && cal <= se, "seed {seed}: {cal} of {se}");
        let t = truth.odd_struck.expect("true odd-struckness");
        assert!(
            (o - t).abs() <= 3.0 * se,
            "seed {seed}: {:.1} ± {:.1} ms, truth {:.1}",
            o * 1e3,
            se * 1e3,
            t * 1e3
        );
        // Every bottom carries it too.
        assert!(got
            .strokes
            .iter()
            .filter(|s| s.phase == PhaseKind::Ringing)
            .all(|s| s.bdc_se.is_some_and(|x| x > 0.0)));
    }
}
