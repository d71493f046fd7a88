//! Strikes as bursts in the readings (docs/model.md §13 step 1), and the
//! samples the angle's fits leave out.

use super::types::AccelLog;
use crate::median;

/// The samples whose radial axis alone is clipped, away from any strike:
/// a sensor far below the pivot (on the bell's waist) reads g + θ'² |h|
/// radially at a fast swing's bottom, past a ±2 g range for |h| over
/// about 0.2 m, and each such sample, taken as a burst, lost the bottom.
/// That is no strike: the radial samples are left out of the fits, the
/// other axes kept (the tangential one, near zero at the bottom, times
/// it). Within 60 ms of a burst on the other axes (a headstock ringing
/// after a strike clips any axis) the sample stays a burst.
pub(super) fn radial_clipped(log: &AccelLog, clip: f64) -> Vec<bool> {
    let (d, threshold) = departures(log, clip, true);
    radial_alone(log, clip, &d, threshold)
}

/// [`radial_clipped`] from the departures `d` and their `threshold`: each
/// run of samples whose radial axis alone is clipped, kept when it is a
/// bottom's (the tangential reading changes sign within it, and it lasts
/// under 0.5 s) and no other axis bursts within 60 ms of it (a headstock
/// ringing after a strike clips any axis, Data141's for a second).
fn radial_alone(log: &AccelLog, clip: f64, d: &[f64], threshold: f64) -> Vec<bool> {
    let n = log.t.len();
    let t = &log.t;
    let at = |a: &[f64], k: usize| a[k].abs() >= 0.99 * clip;
    let hot = |k: usize| d[k] > threshold || at(&log.tangential, k) || at(&log.axle, k);
    let alone = |k: usize| at(&log.radial, k) && !at(&log.tangential, k) && !at(&log.axle, k);
    let mut out = vec![false; n];
    let mut k = 0;
    while k < n {
        if !alone(k) {
            k += 1;
            continue;
        }
        let a = k;
        while k < n && alone(k) {
            k += 1;
        }
        let b = k - 1;
        let crosses = (a.saturating_sub(1)..(b + 1).min(n - 1))
            .any(|j| log.tangential[j].signum() != log.tangential[j + 1].signum());
        let lo = t.partition_point(|&x| x < t[a] - 0.06);
        let hi = t.partition_point(|&x| x <= t[b] + 0.06);
        let quiet = !(lo..hi).any(hot);
        if crosses && quiet && t[b] - t[a] < 0.5 {
            out[a..=b].fill(true);
        }
    }
    out
}

/// Each sample's departure from the straight line through the two before
/// it (m/s²; with `radial_out`, the radial axis left out where clipped),
/// and the burst threshold.
fn departures(log: &AccelLog, clip: f64, radial_out: bool) -> (Vec<f64>, f64) {
    let n = log.t.len();
    let axes = [&log.radial, &log.tangential, &log.axle];
    let at = |a: &[f64], k: usize| a[k].abs() >= 0.99 * clip;
    let interval = median(&log.t.windows(2).map(|w| w[1] - w[0]).collect::<Vec<_>>());
    let mut d = vec![0.0; n];
    for k in 2..n {
        // Across a gap the swing has moved on: no prediction.
        if log.t[k] - log.t[k - 2] > 4.0 * interval {
            continue;
        }
        let f = (log.t[k] - log.t[k - 1]) / (log.t[k - 1] - log.t[k - 2]);
        // A radial axis clipped in the three samples predicts nothing (flat
        // at the range through a bottom is not a strike; a clipped
        // tangential or axle axis makes a burst anyway).
        let out = radial_out && (at(&log.radial, k) || at(&log.radial, k - 1) || at(&log.radial, k - 2));
        d[k] = axes
            .iter()
            .enumerate()
            .filter(|(i, _)| !(*i == 0 && out))
            .map(|(_, a)| a)
            .map(|a| {
                let pred = a[k - 1] + (a[k - 1] - a[k - 2]) * f;
                (a[k] - pred).powi(2)
            })
            .sum::<f64>()
            .sqrt();
    }
    let typical = median(&d[2..]);
    (d, (6.0 * 1.4826 * typical).max(1.5))
}

/// The burst mask and the burst onsets (sample indices), method step 1.
pub(super) fn bursts(log: &AccelLog, clip: f64) -> (Vec<bool>, Vec<usize>) {
    let n = log.t.len();
    let (d_out, threshold_out) = departures(log, clip, true);
    let alone = radial_alone(log, clip, &d_out, threshold_out);
    // The departures with every axis, but about a bottom's clipped radial
    // run (no strike) without it: a log with no such run reads as before.
    let (mut d, threshold) = departures(log, clip, false);
    for k in 0..n {
        if alone[k.saturating_sub(2)..(k + 1)].iter().any(|&a| a) {
            d[k] = d_out[k];
        }
    }
    // Clipped: any axis, but the radial alone at a bottom
    // ([`radial_clipped`]).
    let clipped = |k: usize| {
        [&log.radial, &log.tangential, &log.axle]
            .iter()
            .any(|a| a[k].abs() >= 0.99 * clip)
            && !alone[k]
    };
    let mut mask = vec![false; n];
    let mut onsets = vec![];
    let mut last_hot: Option<f64> = None;
    for k in 0..n {
        let hot = d[k] > threshold || clipped(k);
        if hot {
            // A new burst unless one is still ringing (within 60 ms).
            if last_hot.is_none_or(|t| log.t[k] - t > 0.06) {
                // An impact just before a sample can read small there
                // (the ring near a node on every axis): the burst starts
                // one sample early when that sample already departs from
                // its prediction by half the threshold, far above noise.
                // (That sample stays out of the mask: under the threshold
                // it does the angle little harm, and masking it too moved
                // a real log's unwrapped angle while raising by a turn.)
                let early = k > 2 && d[k - 1] > 0.5 * threshold && !mask[k - 1];
                onsets.push(if early { k - 1 } else { k });
            }
            last_hot = Some(log.t[k]);
        }
        mask[k] = last_hot.is_some_and(|t| log.t[k] - t <= 0.04);
    }
    (mask, onsets)
}

/// The strike itself: the first this many seconds of a burst (s), left
/// out of the angle's fits.
pub const STRIKE_S: f64 = 0.06;

/// Each run of `true` in `mask`, as the half-open range of its samples
/// (start, end), in order.
pub(super) fn runs_of(mask: &[bool]) -> Vec<(usize, usize)> {
    let mut runs = vec![];
    let mut k = 0;
    while k < mask.len() {
        if !mask[k] {
            k += 1;
            continue;
        }
        let start = k;
        while k < mask.len() && mask[k] {
            k += 1;
        }
        runs.push((start, k));
    }
    runs
}

/// A burst lasting longer than this (s) is the headstock ringing.
pub const RINGING_S: f64 = 0.25;

/// The samples the angle's fits leave out: with `through`, of a burst
/// lasting over [`RINGING_S`] only the clipped samples and its strikes'
/// first [`STRIKE_S`]; else (and of shorter bursts) the whole burst.
pub(super) fn ringing_masked(log: &AccelLog, burst: &[bool], onsets: &[usize], clip: f64, through: bool) -> Vec<bool> {
    if !through {
        return burst.to_vec();
    }
    let axes = [&log.radial, &log.tangential, &log.axle];
    let n = log.t.len();
    // Each burst run's length (s): only a long one (the headstock ringing,
    // not a strike's burst that dies in a few hundredths) is read through.
    let mut long = vec![false; n];
    for (start, end) in runs_of(burst) {
        long[start..end].fill(log.t[end - 1] - log.t[start] > RINGING_S);
    }
    let mut o = 0;
    (0..n)
        .map(|k| {
            while o + 1 < onsets.len() && onsets[o + 1] <= k {
                o += 1;
            }
            let struck = onsets
                .get(o)
                .is_some_and(|&j| j <= k && log.t[k] - log.t[j] <= STRIKE_S);
            burst[k] && (!long[k] || struck || axes.iter().any(|a| a[k].abs() >= 0.99 * clip))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::runs_of;

    #[test]
    fn runs_of_gives_each_run_of_true_as_a_half_open_range() {
        let m = [true, true, false, false, true, false, true, true, true];
        assert_eq!(runs_of(&m), vec![(0, 2), (4, 5), (6, 9)]);
        assert!(runs_of(&[false, false]).is_empty());
        assert!(runs_of(&[]).is_empty());
    }
}
