//! Which way is down, read from the log itself (docs/model.md §13.1): a
//! bell swings to and fro only about its bottom (about the balance it
//! would fall over), so the small swings' midpoints (halfway between two
//! turning points) lie at the bottom. A sensor mounted upside down on the
//! axes given reads them near 180 deg, and is turned over.

use super::fits::{quadratic_fits, unwrap_fill, wrap};
use super::types::AccelLog;
use clapper_core::bell::G;

/// Which way up the log reads, and on what evidence.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Orientation {
    /// The radial and tangential axes read upside down (turned by 180 deg
    /// about the pivot's axis to read +g at rest down).
    pub flipped: bool,
    /// The small swings that told it: half swings of 10 to 120 deg from one
    /// turning point to the next, taking 0.25 to 3 s, clear of bursts.
    pub swings: usize,
    /// Their midpoints' mean cosine on the axes as given: near +1 the right
    /// way up, near −1 upside down.
    pub agreement: f64,
}

/// A half swing counts only where every sample's force is within this
/// fraction of g.
const NEAR_G: f64 = 0.3;

/// Fewer small swings than this cannot tell which way is down.
pub const MIN_SWINGS: usize = 4;

/// Turning points of `a` (rad) with hysteresis `step` (rad): an extreme is
/// taken once `a` has moved `step` back from it. Indices.
pub(crate) fn turning_points(a: &[f64], step: f64) -> Vec<usize> {
    let mut out = vec![];
    if a.is_empty() {
        return out;
    }
    // +1 while rising, −1 while falling, 0 not yet known.
    let (mut dir, mut ext) = (0.0f64, 0usize);
    let mut lo = 0usize;
    let mut hi = 0usize;
    for k in 1..a.len() {
        if dir == 0.0 {
            if a[k] > a[hi] {
                hi = k;
            }
            if a[k] < a[lo] {
                lo = k;
            }
            // (The log's first sample is where it starts, not a turn.)
            if a[hi] - a[k] > step {
                dir = -1.0;
                ext = k;
                if hi > 0 {
                    out.push(hi);
                }
            } else if a[k] - a[lo] > step {
                dir = 1.0;
                ext = k;
                if lo > 0 {
                    out.push(lo);
                }
            }
            continue;
        }
        if (a[k] - a[ext]) * dir > 0.0 {
            ext = k;
        } else if (a[ext] - a[k]) * dir > step {
            out.push(ext);
            dir = -dir;
            ext = k;
        }
    }
    out
}

/// Read which way is down from `log` (its bursts `bad`).
pub fn orientation(log: &AccelLog, bad: &[bool]) -> Orientation {
    let plain: Vec<f64> = (0..log.t.len())
        .map(|k| log.tangential[k].atan2(log.radial[k]))
        .collect();
    let (level, _, _) = quadratic_fits(&log.t, &unwrap_fill(&log.t, &plain, bad), bad, 0.1);
    let turns = turning_points(&level, 5f64.to_radians());
    let (mut n, mut sum) = (0usize, 0.0);
    for w in turns.windows(2) {
        let (a, b) = (level[w[0]], level[w[1]]);
        let span = (a - b).abs();
        // A half swing takes a quarter of a second at least (a strike's
        // shaking turns faster), and is read clean.
        let took = log.t[w[1]] - log.t[w[0]];
        let clean = !bad[w[0]..=w[1]].iter().any(|&b| b);
        // A small swing reads about g throughout; a turn of the plain angle
        // inside a fast swing, read by a sensor far from the pivot (its
        // centripetal part as large as gravity, the plain angle turning
        // where the bell does not), reads far from it.
        let near_g = (w[0]..=w[1]).all(|k| (log.tangential[k].hypot(log.radial[k]) / G - 1.0).abs() < NEAR_G);
        if span > 10f64.to_radians() && span < 120f64.to_radians() && (0.25..3.0).contains(&took) && clean && near_g {
            n += 1;
            sum += wrap(0.5 * (a + b)).cos();
        }
    }
    let agreement = if n > 0 { sum / n as f64 } else { 0.0 };
    Orientation {
        flipped: n >= MIN_SWINGS && agreement < -0.5,
        swings: n,
        agreement,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn turning_points_follow_a_swing_not_its_noise() {
        let a: Vec<f64> = (0..400)
            .map(|k| (k as f64 * 0.05).sin() + 0.01 * ((k * 7919) % 13) as f64 / 13.0)
            .collect();
        let tp = turning_points(&a, 0.1);
        // Extremes of sin(0.05 k) at k = 31, 94, 157, 220, 283, 346.
        assert_eq!(tp.len(), 6, "{tp:?}");
        for (got, want) in tp.iter().zip([31, 94, 157, 220, 283, 346]) {
            assert!(got.abs_diff(want) <= 3, "{tp:?}");
        }
    }
}
