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

/// At most this fraction of steps between neighbouring quiet samples may
/// turn the angle faster than a bell can: Data141, a real bell's log, has
/// 2.7 % (a strike's shaking the burst test lets through), noise about 89 %.
pub const MAX_JUMPS: f64 = 0.25;

/// What the plausibility check found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plausibility {
    /// The readings' median magnitude over the quiet samples, over g
    /// (about 1 for a bell's log).
    pub gravity: f64,
    /// The fraction of steps between neighbouring quiet samples in which the
    /// plain angle atan2(tangential, radial) turns faster than 8 rad/s (and
    /// more than 20 deg): near 0 for a bell's log, most for noise.
    pub jumps: f64,
}

impl Plausibility {
    /// Whether the log looks like a bell's.
    pub fn plausible(&self) -> bool {
        (GRAVITY_BAND.0..=GRAVITY_BAND.1).contains(&self.gravity) && self.jumps <= MAX_JUMPS
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
    let (mut steps, mut jumps) = (0usize, 0usize);
    for w in quiet.windows(2) {
        let (a, b) = (w[0], w[1]);
        let dt = log.t[b] - log.t[a];
        // Neighbours only: not across a burst or a gap.
        if b != a + 1 || dt > 4.0 * interval {
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
    }
}
