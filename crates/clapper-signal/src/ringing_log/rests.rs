//! Rests (no motion for 1.5 s or more), and without free swings the
//! sensor's scale and tilt from them.

use super::types::AccelLog;
use crate::median;
use clapper_core::bell::G;

/// Without a free stretch to calibrate on (issue 24's reading): the rests'
/// magnitude sets one scale for all axes, and the rests down their tilt
/// (an offset across the axis is read as a tilt). The log turned, if it
/// needs to be.
pub(super) fn calibrate_from_rests(
    log: &AccelLog,
    bad: &[bool],
    still: &[(f64, f64, f64)],
    warnings: &mut Vec<String>,
) -> Option<AccelLog> {
    // A sensor not square on its nut reads the bell at rest as tilted:
    // the bell hangs plumb when down, so its rest's angle is the tilt. And
    // a sensor's scale is often a few per cent out (an ADXL345 may read g
    // as 10.2 m/s²): every rest, down or up, reads g, which sets it.
    let n = log.t.len();
    {
        let mut downs: Vec<f64> = still.iter().map(|r| r.2).filter(|m| m.abs() < 0.5).collect();
        downs.sort_by(f64::total_cmp);
        let tilt = downs
            .get(downs.len() / 2)
            .copied()
            .filter(|t| t.abs() > 0.2f64.to_radians());
        let at_rest: Vec<f64> = (0..n)
            .filter(|&k| !bad[k] && still.iter().any(|r| log.t[k] >= r.0 && log.t[k] <= r.1))
            .map(|k| log.radial[k].hypot(log.tangential[k]).hypot(log.axle[k]))
            .collect();
        let gain = if at_rest.len() >= 20 { median(&at_rest) / G } else { 1.0 };
        let gain = if (gain - 1.0).abs() > 0.01 && (0.5..2.0).contains(&gain) {
            warnings.push(format!(
                "the sensor reads g at rest as {:.2} m/s²: its readings are scaled by {:.3}",
                gain * G,
                1.0 / gain
            ));
            gain
        } else {
            1.0
        };
        if let Some(tilt) = tilt {
            warnings.push(format!(
                "the sensor reads the bell at rest {:.1} deg off plumb: taken as its tilt and removed",
                tilt.to_degrees()
            ));
        }
        if tilt.is_some() || gain != 1.0 {
            let (s, c) = tilt.unwrap_or(0.0).sin_cos();
            let (s, c) = (s / gain, c / gain);
            Some(AccelLog {
                tangential: (0..n).map(|k| log.tangential[k] * c - log.radial[k] * s).collect(),
                radial: (0..n).map(|k| log.tangential[k] * s + log.radial[k] * c).collect(),
                axle: log.axle.iter().map(|a| a / gain).collect(),
                ..log.clone()
            })
        } else {
            None
        }
    }
}

/// Intervals of rest (s): no motion (|θ'| < 0.05 rad/s over ±0.5 s, and
/// θ within 3 deg) for at least 1.5 s (a swing's turning point at the
/// balance lasts less).
pub(super) fn rests(t: &[f64], theta: &[f64], d1: &[f64], interval: f64) -> Vec<(f64, f64, f64)> {
    let n = t.len();
    let mut out = vec![];
    let mut start: Option<usize> = None;
    // `theta` here is smoothed (the same fit as `d1`).
    let still = |k: usize| d1[k].abs() < 0.05;
    for k in 0..=n {
        let s = k < n && still(k) && start.is_none_or(|i| (theta[k] - theta[i]).abs() < 3f64.to_radians());
        match (s, start) {
            (true, None) => start = Some(k),
            (false, Some(i)) => {
                let j = k - 1;
                if t[j] - t[i] >= 1.5 - 0.5 * interval {
                    let mean = theta[i..=j].iter().sum::<f64>() / (j - i + 1) as f64;
                    out.push((t[i], t[j], mean));
                }
                start = if k < n && still(k) { Some(k) } else { None };
            }
            _ => {}
        }
    }
    out
}
