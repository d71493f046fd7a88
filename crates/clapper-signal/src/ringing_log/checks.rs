//! Checks on the bottoms read (docs/model.md §13.3): the moment of
//! greatest speed, which needs no zero of the angle (neither the sensor's
//! tilt nor its offsets), and each bottom's standard error from the
//! calibration's: its covariance propagated, and the calibration refitted
//! with each part of the log's free stretches left out (a jackknife), the
//! bottoms re-read with each.

use super::bottoms::bottom_time;
use super::calibrate::{calibrate, Calibration, Stretch};
use super::phases::odd_struck;
use super::types::{AccelLog, LogStroke};
use clapper_core::bell::G;
use clapper_core::sensor::{specific_force, SensorPlace};

/// Each stroke's moment of greatest speed: the vertex of a parabola
/// through |θ'| (`rate`, rad/s, from the angle's joint cubic fits, where
/// `cubic`) over ±50 ms of its peak within 0.15 s of the bottom read, clear
/// of bursts.
pub(crate) fn speed_peaks(t: &[f64], rate: &[f64], cubic: &[bool], burst: &[bool], strokes: &mut [LogStroke]) {
    for s in strokes.iter_mut() {
        let (a, b) = (
            t.partition_point(|&x| x < s.bdc - 0.15),
            t.partition_point(|&x| x <= s.bdc + 0.15),
        );
        let Some(m) = (a..b)
            .filter(|&k| cubic[k] && !burst[k])
            .max_by(|&x, &y| rate[x].abs().total_cmp(&rate[y].abs()))
        else {
            continue;
        };
        let pts: Vec<usize> = (a..b)
            .filter(|&k| cubic[k] && !burst[k] && (t[k] - t[m]).abs() <= 0.05)
            .collect();
        if pts.len() < 5 || m == a || m + 1 >= b {
            continue;
        }
        // Least squares y = c0 + c1 x + c2 x², x = t − t[m].
        let mut sx = [0.0f64; 5];
        let mut sy = [0.0f64; 3];
        for &k in &pts {
            let x = t[k] - t[m];
            let y = rate[k].abs();
            let mut p = 1.0;
            for v in sx.iter_mut() {
                *v += p;
                p *= x;
            }
            sy[0] += y;
            sy[1] += y * x;
            sy[2] += y * x * x;
        }
        let mat = [[sx[0], sx[1], sx[2]], [sx[1], sx[2], sx[3]], [sx[2], sx[3], sx[4]]];
        let Some(c) = clapper_core::linalg::solve(mat, sy) else {
            continue;
        };
        if c[2] < 0.0 {
            let v = -c[1] / (2.0 * c[2]);
            if v.abs() <= 0.05 {
                s.speed_peak = Some(t[m] + v);
            }
        }
    }
}

/// Each stroke's bottom's standard error from the calibration: at the
/// bottom the corrected tangential reading, whose zero is the bottom,
/// errs by e = r α̃ + L θ'² δ̃ + õ_t (the tilt's error turns the radial
/// reading r into it; δ's, the place across the axis; the offset's), and
/// the reading moves at g θ', so the bottom by e / (g θ').
pub(crate) fn bottom_errors(c: &Calibration, log: &AccelLog, rate: &[f64], strokes: &mut [LogStroke]) {
    let length = c.length.unwrap_or(1.0);
    for s in strokes.iter_mut() {
        let k = log.t.partition_point(|&x| x < s.bdc).min(log.t.len() - 1);
        let w = rate[k].abs().max(0.1);
        let j = [log.radial[k], length * w * w, 1.0];
        let mut var = 0.0;
        for a in 0..3 {
            for b in 0..3 {
                var += j[a] * c.cov_bottom[a][b] * j[b];
            }
        }
        s.bdc_se = Some(var.max(0.0).sqrt() / (G * w));
    }
}

/// The free stretches are split into this many groups for the jackknife
/// (fewer with fewer stretches; at least 3).
const JACK_GROUPS: usize = 5;

/// The calibration refitted on `stretches` (of the oriented, uncalibrated
/// `raw` log) with each of [`JACK_GROUPS`] groups of its free stretches
/// left out (every fifth in time order, from the first, the second, ...;
/// the rests always kept), so that each refit keeps stretches of every
/// kind. (Groups of neighbours instead, one of them Data141's falls from
/// the balance, which alone tell the sensor's place across the axis well:
/// without them it read 7 cm, not 3, and moved the bottoms some 30 ms, off
/// the moment of greatest speed by as much; that is a lack of data the
/// greatest-speed check shows, not the calibration's scatter.) Empty when
/// fewer than 3 refits succeed.
pub(crate) fn jackknife(raw: &AccelLog, stretches: &[Stretch]) -> Vec<Calibration> {
    let mut free: Vec<usize> = (0..stretches.len()).filter(|&i| stretches[i].free).collect();
    free.sort_by_key(|&i| stretches[i].a);
    let groups = JACK_GROUPS.min(free.len());
    if groups < 3 {
        return vec![];
    }
    let out: Vec<Calibration> = (0..groups)
        .filter_map(|g| {
            let out: Vec<usize> = free.iter().skip(g).step_by(groups).copied().collect();
            let left: Vec<Stretch> = (0..stretches.len())
                .filter(|i| !out.contains(i))
                .map(|i| stretches[i])
                .collect();
            calibrate(raw, &left).filter(|c| c.length.is_some())
        })
        .collect();
    if out.len() < 3 {
        vec![]
    } else {
        out
    }
}

/// The bottoms of `strokes` re-read (as [`bottom_time`] reads them) with
/// calibration `c` applied to `raw`, the angle's rates (`rate`, `acc`:
/// θ', θ'') kept: the corrected tangential reading's zero moves with the
/// calibration's tilt, offset and place.
fn bottoms_with(
    c: &Calibration,
    raw: &AccelLog,
    (rate, acc): (&[f64], &[f64]),
    (burst, cubic): (&[bool], &[bool]),
    interval: f64,
    strokes: &[LogStroke],
) -> Vec<f64> {
    let length = c.length.unwrap_or(1.0);
    let place = SensorPlace {
        along: c.kappa * length,
        across: c.delta * length,
    };
    let f: Vec<f64> = (0..raw.t.len())
        .map(|k| c.apply(raw.tangential[k], raw.radial[k]).0 - specific_force(place, 0.0, rate[k], acc[k])[0])
        .collect();
    strokes
        .iter()
        .map(|s| {
            let k = raw.t.partition_point(|&x| x < s.bdc).min(raw.t.len() - 1);
            bottom_time(&raw.t, &f, (burst, cubic), (s.bdc, interval), G * rate[k])
        })
        .collect()
}

/// The jackknife's standard errors: each stroke's bottom's (set into
/// `bdc_se` with the propagated one, in quadrature) and the ringing's
/// odd-struckness's (s; `None` without refits or odd-struckness).
pub(crate) fn jackknife_errors(
    refits: &[Calibration],
    raw: &AccelLog,
    rates: (&[f64], &[f64]),
    masks: (&[bool], &[bool]),
    interval: f64,
    strokes: &mut [LogStroke],
) -> Option<f64> {
    if refits.is_empty() {
        return None;
    }
    let reads: Vec<Vec<f64>> = refits
        .iter()
        .map(|c| bottoms_with(c, raw, rates, masks, interval, strokes))
        .collect();
    // Jackknife variance: (g − 1)/g Σ (x − x̄)².
    let g = reads.len() as f64;
    let var = |xs: &[f64]| {
        let m = xs.iter().sum::<f64>() / xs.len() as f64;
        (g - 1.0) / g * xs.iter().map(|x| (x - m).powi(2)).sum::<f64>()
    };
    let odds: Vec<f64> = reads
        .iter()
        .filter_map(|bdcs| {
            let moved: Vec<LogStroke> = strokes
                .iter()
                .zip(bdcs)
                .map(|(s, &b)| LogStroke { bdc: b, ..*s })
                .collect();
            odd_struck(&moved).map(|o| o.0)
        })
        .collect();
    for (i, s) in strokes.iter_mut().enumerate() {
        let xs: Vec<f64> = reads.iter().map(|r| r[i]).collect();
        s.bdc_se = Some(s.bdc_se.unwrap_or(0.0).hypot(var(&xs).sqrt()));
    }
    (odds.len() == reads.len()).then(|| var(&odds).sqrt())
}
