//! What each stroke rose to (docs/model.md §13 step 4): a stand on the
//! stay (each stroke says whether it ended on one, its angle and how long
//! it stood), and a turning point the headstock's ringing hid, its height
//! read from the swing's time instead.

use super::bottoms::stand_height;
use super::phases::STAND_MAX_S;
use super::types::{AccelLog, LogStroke, Stand};
use clapper_core::bell::G;
use clapper_core::elliptic::complete_k;
use std::f64::consts::{FRAC_PI_2, PI};

/// A turning point at least this high (rad) is on the stay: a bell that
/// turns back from past the balance was held there (179.5 deg: the
/// balance less half a degree for the calibration's error). How long a top
/// stays still cannot tell a stand from a free swing's slow top: one
/// turning 1 deg short of the balance stays within 3 deg of its height
/// for 1.4 s (the project's generator), longer than a short stand.
pub const STAND_PAST: f64 = 179.5 * PI / 180.0;

/// A hidden turning point is read from the swing's time only up to this
/// height (rad): 172 deg. Nearer the balance the time grows without bound
/// (a stand, or the ringer holding the bell) and says little.
pub const TIMED_MAX: f64 = 172.0 * PI / 180.0;

/// A turning point is hidden when at least this fraction of the samples
/// within ±[`TOP_HALF_S`] of the swing's midpoint are bursts or clipped.
const HIDDEN: f64 = 0.5;

/// The window about a swing's midpoint (s) judged for [`HIDDEN`].
const TOP_HALF_S: f64 = 0.15;

/// Whether a rest at the balance (start, end, angle; s, s, rad) lies
/// between `a` and `b` (s).
fn rest_between(rests: &[(f64, f64, f64)], (a, b): (f64, f64)) -> Option<(f64, f64, f64)> {
    rests
        .iter()
        .copied()
        .find(|r| r.0 > a && r.1 < b && r.2.abs() > FRAC_PI_2)
}

/// Each stroke's stand (`LogStroke::stand`): a rest at the balance before
/// the next bottom (a set when longer than [`STAND_MAX_S`]); else a still
/// run of the calibrated gravity angle there (`stand_height`) at least
/// [`STAND_PAST`] high, how long it stood read from it; else a turning
/// point read at least [`STAND_PAST`] high (not timed). Its angle is the
/// amplitude the next stroke falls from.
pub(super) fn stands(log: &AccelLog, burst: &[bool], rests: &[(f64, f64, f64)], strokes: &mut [LogStroke]) {
    let t = &log.t;
    let n = t.len();
    for i in 0..strokes.len() {
        let a = strokes[i].bdc;
        let next = strokes.get(i + 1).copied();
        let b = next.map_or(t[n - 1], |s| s.bdc);
        if let Some(r) = rest_between(rests, (a, b)) {
            let long = r.1 - r.0;
            strokes[i].stand = Some(Stand {
                angle: next.map_or(r.2.abs(), |s| s.amplitude),
                duration: Some(long),
                set: long > STAND_MAX_S,
            });
            continue;
        }
        let Some(next) = next else { continue };
        let (ia, ib) = (t.partition_point(|&x| x < a), t.partition_point(|&x| x < b).min(n - 1));
        let read = stand_height(log, burst, (ia, ib), next.from_side);
        strokes[i].stand = match read {
            Some(s) if s.height >= STAND_PAST => Some(Stand {
                angle: next.amplitude,
                duration: Some(s.off - s.on),
                set: false,
            }),
            _ if next.amplitude >= STAND_PAST && !next.amplitude_timed => Some(Stand {
                angle: next.amplitude,
                duration: None,
                set: false,
            }),
            _ => None,
        };
    }
}

/// A free pendulum's half swing (bottom to bottom, s) at amplitude `a`
/// (rad), its small swings' quarter period over π/2 being `tq` = √(L/g).
fn half_swing_time(a: f64, tq: f64) -> f64 {
    let k = (0.5 * a).sin();
    2.0 * tq * complete_k((1.0 - k * k).max(0.0).sqrt())
}

/// The amplitude (rad) of a free half swing taking `dt` (s), by bisection;
/// `None` outside 1 to 179.9 deg.
pub(super) fn amplitude_of_half_swing(dt: f64, tq: f64) -> Option<f64> {
    let (mut lo, mut hi) = (1f64.to_radians(), 179.9f64.to_radians());
    if !(half_swing_time(lo, tq)..=half_swing_time(hi, tq)).contains(&dt) {
        return None;
    }
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if half_swing_time(mid, tq) < dt {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Some(0.5 * (lo + hi))
}

/// Turning points the headstock's ringing hid (most samples about the
/// swing's midpoint bursts: Data141's lowering rings from one strike
/// through the top, read up to the angle's 200 deg bound where the swing's
/// timing says 165-168), read past the balance ([`STAND_PAST`]) though the
/// swing's time says it turned back short of it: the amplitude from the
/// time between the two bottoms either side, a free pendulum's half swing
/// of equivalent length `length` (m), when that is under [`TIMED_MAX`] and
/// no rest lies between. The ringer's rope, pulling or checking, makes it
/// a rough figure (see docs/model.md §13 step 4).
pub(super) fn timed_tops(t: &[f64], burst: &[bool], rests: &[(f64, f64, f64)], length: f64, strokes: &mut [LogStroke]) {
    let tq = (length / G).sqrt();
    for i in 1..strokes.len() {
        let (a, b) = (strokes[i - 1].bdc, strokes[i].bdc);
        if rests.iter().any(|r| r.1 > a && r.0 < b) {
            continue;
        }
        let mid = 0.5 * (a + b);
        let (ia, ib) = (
            t.partition_point(|&x| x < mid - TOP_HALF_S),
            t.partition_point(|&x| x <= mid + TOP_HALF_S),
        );
        let hidden = (ia..ib).filter(|&k| burst[k]).count();
        if ib <= ia || (hidden as f64) < HIDDEN * (ib - ia) as f64 {
            continue;
        }
        // Only a reading the swing's time rules out: past the balance,
        // where a bell that turned back freely cannot have been (a rope
        // pulling or checking makes the time a rough figure otherwise:
        // Data141's lowering reads 10-25 deg higher so at handstroke than
        // at backstroke).
        if strokes[i].amplitude < STAND_PAST {
            continue;
        }
        if let Some(amp) = amplitude_of_half_swing(b - a, tq).filter(|&x| x <= TIMED_MAX) {
            strokes[i].amplitude = amp;
            strokes[i].amplitude_timed = true;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The half swing's time and its inverse agree, and the time grows
    /// with the amplitude as a pendulum's does (a 90 deg swing takes 18 %
    /// longer than a small one).
    #[test]
    fn a_half_swings_time_gives_its_amplitude_back() {
        let tq = (0.6f64 / G).sqrt();
        for deg in [10.0, 90.0, 165.0, 171.0] {
            let a = f64::to_radians(deg);
            let back = amplitude_of_half_swing(half_swing_time(a, tq), tq).expect("an amplitude");
            assert!((back - a).abs() < 1e-9, "{deg}: {}", back.to_degrees());
        }
        let r = half_swing_time(FRAC_PI_2, tq) / (PI * tq);
        assert!((r - 1.18).abs() < 0.01, "{r}");
        assert_eq!(amplitude_of_half_swing(0.1, tq), None);
    }
}
