//! Whether a log looks like a bell's at all (issue 46): a headstock's
//! sensor reads gravity (about g, whichever way the bell is turned, give or
//! take the swing's own accelerations), and the bell's angle, read from
//! it, moves continuously (a bell turns at most some 6 rad/s). Noise, a
//! file of zeros or a log of something else fails one or the other, and is
//! not read into swings.

use super::fits::wrap;
use super::types::AccelLog;
use crate::median;
use clapper_core::bell::G;

/// The reading's median magnitude (over g) must lie in this band: gravity,
/// with a sensor's gain error and the swing's accelerations on top.
pub const GRAVITY_BAND: (f64, f64) = (0.5, 2.0);

/// At most this fraction of steps between neighbouring quiet samples (both
/// reading within 20 % of g) may turn the angle faster than a
/// bell can: Data141, a real bell's log, has 0.3 % (2.7 % counted at every
/// quiet sample: a strike's shaking the burst test lets through), noise
/// about 89 %.
pub const MAX_JUMPS: f64 = 0.25;

/// The angle's jumps are counted between neighbouring samples both
/// reading within this band (over g).
const JUMP_BAND: (f64, f64) = (0.8, 1.2);

/// The median time (s) from one bottom to the next over swings under 90
/// deg must lie in this band: half a pendulum's period, from a bell
/// hanging as a pendulum of about 0.3 m (the lightest ringing bells hang
/// as 0.35 m or more) to one of about 6 m (a bell's is 2 m at most).
pub const HALF_SWING_BAND_S: (f64, f64) = (0.55, 3.0);

/// Neighbouring half swings of a pendulum take nearly the same time (its
/// period changes slowly with the amplitude: under 18 % from 0 to 90 deg);
/// the median change between neighbours, over the longer, must be at most
/// this. A bell's log: a few %; noise about gravity: about a half.
pub const MAX_IRREGULARITY: f64 = 0.25;

/// Fewer pairs of neighbouring swings under 90 deg than this say nothing
/// of the swing's timing (a log of ringing alone has none).
const MIN_SMALL_PAIRS: usize = 5;

/// What the plausibility check found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plausibility {
    /// The readings' median magnitude over the quiet samples, over g
    /// (about 1 for a bell's log).
    pub gravity: f64,
    /// The fraction of steps between neighbouring quiet samples (both
    /// reading within 20 % of g) in which the
    /// plain angle atan2(tangential, radial) turns faster than 8 rad/s (and
    /// more than 20 deg): near 0 for a bell's log, most for noise.
    pub jumps: f64,
    /// The median time from one bottom to the next over neighbouring swings
    /// under 90 deg (s): half the pendulum's period; `None` before the
    /// swings are read, or with too few of them.
    pub half_swing: Option<f64>,
    /// The median change from one such half swing's time to the next's,
    /// over the longer of the two (`None` likewise): near 0 for a pendulum.
    pub irregularity: Option<f64>,
}

impl Plausibility {
    /// Whether the log looks like a bell's.
    pub fn plausible(&self) -> bool {
        (GRAVITY_BAND.0..=GRAVITY_BAND.1).contains(&self.gravity)
            && self.jumps <= MAX_JUMPS
            && self
                .half_swing
                .is_none_or(|h| (HALF_SWING_BAND_S.0..=HALF_SWING_BAND_S.1).contains(&h))
            && self.irregularity.is_none_or(|r| r <= MAX_IRREGULARITY)
    }

    /// Why not, in words (`None` when it looks like a bell's).
    pub fn why_not(&self) -> Option<String> {
        if self.plausible() {
            return None;
        }
        let mut why = vec![];
        if !(GRAVITY_BAND.0..=GRAVITY_BAND.1).contains(&self.gravity) {
            why.push(format!(
                "its readings' median magnitude is {:.2} g where a sensor on a bell reads gravity, about 1 g",
                self.gravity
            ));
        }
        if self.jumps > MAX_JUMPS {
            why.push(format!(
                "the angle read from it jumps faster than a bell can turn between {:.0} % of neighbouring samples (a bell's log: under {:.0} %)",
                100.0 * self.jumps,
                100.0 * MAX_JUMPS
            ));
        }
        if let Some(h) = self
            .half_swing
            .filter(|h| !(HALF_SWING_BAND_S.0..=HALF_SWING_BAND_S.1).contains(h))
        {
            why.push(format!(
                "its swings under 90 deg come {h:.2} s from one bottom to the next where a bell's take {:.2} to {:.1} s (half a pendulum's period)",
                HALF_SWING_BAND_S.0, HALF_SWING_BAND_S.1
            ));
        }
        if let Some(r) = self.irregularity.filter(|r| *r > MAX_IRREGULARITY) {
            why.push(format!(
                "its neighbouring swings' times differ by {:.0} % (median) where a pendulum's differ by a few",
                100.0 * r
            ));
        }
        Some(format!(
            "this does not look like a ringing log: {}; no swings are read from it",
            why.join("; and ")
        ))
    }
}

/// Check `log` (its bursts `burst` left out; samples every `interval` s).
pub fn plausibility(log: &AccelLog, burst: &[bool], interval: f64) -> Plausibility {
    let n = log.t.len();
    let quiet: Vec<usize> = (0..n).filter(|&k| !burst[k]).collect();
    let gravity = median(
        &quiet
            .iter()
            .map(|&k| log.radial[k].hypot(log.tangential[k]).hypot(log.axle[k]) / G)
            .collect::<Vec<_>>(),
    );
    let angle = |k: usize| log.tangential[k].atan2(log.radial[k]);
    // Only where the reading is gravity's in size: a headstock ringing
    // harder than g shakes the plain angle about, and where the log rings
    // for most of its length the burst test (its threshold set by the
    // typical sample) lets that ring through as quiet.
    let gravity_like = |k: usize| {
        let m = log.radial[k].hypot(log.tangential[k]).hypot(log.axle[k]) / G;
        (JUMP_BAND.0..=JUMP_BAND.1).contains(&m)
    };
    let (mut steps, mut jumps) = (0usize, 0usize);
    for w in quiet.windows(2) {
        let (a, b) = (w[0], w[1]);
        let dt = log.t[b] - log.t[a];
        // Neighbours only: not across a burst or a gap.
        if b != a + 1 || dt > 4.0 * interval || !gravity_like(a) || !gravity_like(b) {
            continue;
        }
        steps += 1;
        if wrap(angle(b) - angle(a)).abs() > (8.0 * dt).max(20f64.to_radians()) {
            jumps += 1;
        }
    }
    Plausibility {
        gravity,
        jumps: if steps == 0 { 1.0 } else { jumps as f64 / steps as f64 },
        half_swing: None,
        irregularity: None,
    }
}

/// The median time (s) between the bottoms of neighbouring swings both
/// under 90 deg, and the median change between neighbouring such times
/// over the longer (`bottoms`: each swing's bottom time (s) and amplitude
/// (rad), in time order); `None` with fewer than a few such pairs.
pub fn half_swing(bottoms: &[(f64, f64)]) -> (Option<f64>, Option<f64>) {
    let small = std::f64::consts::FRAC_PI_2;
    let gaps: Vec<Option<f64>> = bottoms
        .windows(2)
        .map(|w| (w[0].1 < small && w[1].1 < small).then(|| w[1].0 - w[0].0))
        .collect();
    let times: Vec<f64> = gaps.iter().flatten().copied().collect();
    let changes: Vec<f64> = gaps
        .windows(2)
        .filter_map(|w| Some((w[0]?, w[1]?)))
        .map(|(a, b)| (b - a).abs() / a.max(b))
        .collect();
    (
        (times.len() >= MIN_SMALL_PAIRS).then(|| median(&times)),
        (changes.len() >= MIN_SMALL_PAIRS).then(|| median(&changes)),
    )
}
