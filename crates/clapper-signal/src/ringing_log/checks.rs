//! Checks on the bottoms read (docs/model.md §13.3): the moment of
//! greatest speed, which needs no zero of the angle (neither the sensor's
//! tilt nor its offsets), and each bottom's standard error from the
//! calibration's.

use super::calibrate::Calibration;
use super::types::{AccelLog, LogStroke};
use clapper_core::bell::G;

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
