//! Each strike's error against the even rhythm of the rest of its row,
//! with the other bells' own steady errors taken out of that rhythm
//! (docs/strikes.md, "Odd-struckness: one bell's is not lent to the
//! others").
//!
//! A row's ideal times are a straight line through the other bells' times
//! against their places, so that a strike's own error never moves its
//! ideal. Fitted through the others' times as they are, a bell struck
//! 12 ms late at every handstroke tilts every handstroke row's line and
//! lends its neighbours its error the other way: in rounds of six a bell
//! 25 ms odd-struck made the evenly struck treble read −12.7 ms (issue 43).
//! So the line is fitted through the others' times less each one's mean
//! error at that stroke, those means found together over the whole
//! recording (alternately: lines from the means, means from the lines;
//! least squares over every row, which each step lowers).
//!
//! What the rows cannot say is left to the sparsest reading. A shift
//! common to every bell at one stroke is the row's own timing, and in
//! rounds, where each bell keeps one place, so is one growing with place
//! (the stroke's interval): the means are fixed up to those, and they are
//! set so that most bells' means are zero (the median over bells, or in
//! rounds the least-absolute-deviation line through them against place),
//! which is the reading "one bell odd-struck, the rest even" where that is
//! what was rung.

/// A row holding every bell heard once.
pub(super) struct FullRow {
    /// Its strikes, in time order (indices into the strikes).
    pub members: Vec<usize>,
    /// Each member's place, from 0.
    pub slots: Vec<usize>,
    /// Its stroke: hand, back, or not known.
    pub hand: Option<bool>,
    /// Each member far off the row's rhythm (`far_off`): left out of the
    /// line through the row, its own error read against the rest.
    pub far: Vec<bool>,
}

/// The rounds of the alternation; each lowers the squares, and a recording
/// settles in a few, as only the bells' means move.
const MAX_ROUNDS: usize = 60;
/// A change of every mean under this (s) is settled.
const SETTLED_S: f64 = 1e-7;

/// Each strike's error (s) against the line through the rest of its row
/// (`None` for strikes in no full row), `bells` bells numbered from 1.
pub(super) fn errors(t: &[f64], bell: &[usize], rows: &[FullRow], bells: usize) -> Vec<Option<f64>> {
    let mut mean = steady_means(t, bell, rows, bells);
    sparsest(&mut mean, bell, rows);
    let mut out = vec![None; t.len()];
    for row in rows {
        let pts = corrected(t, bell, row, &mean[stroke(row.hand)]);
        for (k, (&i, &p)) in row.members.iter().zip(&row.slots).enumerate() {
            let others: Vec<(f64, f64)> = (pts.iter().zip(&row.far).enumerate())
                .filter(|(q, (_, far))| *q != k && !**far)
                .map(|(_, (x, _))| *x)
                .collect();
            if let Some((a, b)) = super::line(&others) {
                out[i] = Some(t[i] - (a + b * p as f64));
            }
        }
    }
    out
}

/// A row's (place, time less its bell's mean at the row's stroke) (s).
fn corrected(t: &[f64], bell: &[usize], row: &FullRow, mean: &[f64]) -> Vec<(f64, f64)> {
    row.members
        .iter()
        .zip(&row.slots)
        .map(|(&i, &p)| (p as f64, t[i] - mean[bell[i]]))
        .collect()
}

/// The group of a stroke: 0 hand, 1 back, 2 not known.
fn stroke(hand: Option<bool>) -> usize {
    match hand {
        Some(true) => 0,
        Some(false) => 1,
        None => 2,
    }
}

/// Each bell's steady error (s) at each stroke, `[stroke][bell]`: the
/// means that, taken from the bells' times, leave each row's line through
/// them with residuals of steady mean zero per bell and stroke.
fn steady_means(t: &[f64], bell: &[usize], rows: &[FullRow], bells: usize) -> [Vec<f64>; 3] {
    let mut mean = [vec![0.0; bells + 1], vec![0.0; bells + 1], vec![0.0; bells + 1]];
    for _ in 0..MAX_ROUNDS {
        let mut left: [Vec<Vec<f64>>; 3] = [
            vec![vec![]; bells + 1],
            vec![vec![]; bells + 1],
            vec![vec![]; bells + 1],
        ];
        for row in rows {
            let s = stroke(row.hand);
            let pts = corrected(t, bell, row, &mean[s]);
            let near = |k: &usize| !row.far[*k];
            let kept: Vec<(f64, f64)> = (0..pts.len()).filter(near).map(|k| pts[k]).collect();
            let Some((a, b)) = super::line(&kept) else {
                continue;
            };
            for k in (0..pts.len()).filter(near) {
                let (x, y) = pts[k];
                left[s][bell[row.members[k]]].push(y - (a + b * x));
            }
        }
        let mut moved = 0.0f64;
        for s in 0..3 {
            for b in 0..=bells {
                // A strike heard far off moves no bell's mean (`steady`).
                if let Some(step) = super::steady(&left[s][b]) {
                    mean[s][b] += step.mean;
                    moved = moved.max(step.mean.abs());
                }
            }
        }
        if moved < SETTLED_S {
            break;
        }
    }
    mean
}

/// Sets what the rows leave free (a shift per stroke, and in rounds one
/// growing with place) so that most bells' means are zero.
fn sparsest(mean: &mut [Vec<f64>; 3], bell: &[usize], rows: &[FullRow]) {
    for (s, means) in mean.iter_mut().enumerate() {
        // Each bell's places at this stroke: one each (rounds) or several.
        let mut place: Vec<Option<Option<usize>>> = vec![None; means.len()];
        for row in rows.iter().filter(|r| stroke(r.hand) == s) {
            for (&i, &p) in row.members.iter().zip(&row.slots) {
                let at = &mut place[bell[i]];
                *at = match *at {
                    None => Some(Some(p)),
                    Some(Some(q)) if q == p => Some(Some(p)),
                    _ => Some(None),
                };
            }
        }
        let present: Vec<usize> = (0..means.len()).filter(|&b| place[b].is_some()).collect();
        if present.is_empty() {
            continue;
        }
        let fixed: Option<Vec<(f64, f64)>> = present
            .iter()
            .map(|&b| place[b].flatten().map(|p| (p as f64, means[b])))
            .collect();
        let (a, slope) = match fixed {
            Some(pts) if pts.len() >= 3 => lad_line(&pts),
            _ => (median(present.iter().map(|&b| means[b]).collect()), 0.0),
        };
        for &b in &present {
            let p = place[b].flatten().map_or(0.0, |p| p as f64);
            means[b] -= a + slope * p;
        }
    }
}

/// The median of `v` (mean of the middle two for an even count).
fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    match n {
        0 => 0.0,
        _ if n % 2 == 1 => v[n / 2],
        _ => 0.5 * (v[n / 2 - 1] + v[n / 2]),
    }
}

/// The least-absolute-deviation line y = a + b x through `pts` (distinct
/// x, at least two): (a, b). Such a line passes through two of the points,
/// so every pair is tried (a ring has at most a few dozen bells); the first
/// best is kept, so the answer does not depend on rounding order.
fn lad_line(pts: &[(f64, f64)]) -> (f64, f64) {
    let mut best = (f64::INFINITY, 0.0, 0.0);
    for (i, p) in pts.iter().enumerate() {
        for q in &pts[i + 1..] {
            if q.0 == p.0 {
                continue;
            }
            let b = (q.1 - p.1) / (q.0 - p.0);
            let a = p.1 - b * p.0;
            let cost: f64 = pts.iter().map(|r| (r.1 - a - b * r.0).abs()).sum();
            if cost < best.0 {
                best = (cost, a, b);
            }
        }
    }
    (best.1, best.2)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_lad_line_passes_by_one_point_far_off() {
        let pts = [(0.0, 1.0), (1.0, 3.0), (2.0, 25.0), (3.0, 7.0), (4.0, 9.0)];
        let (a, b) = lad_line(&pts);
        assert!((a - 1.0).abs() < 1e-12 && (b - 2.0).abs() < 1e-12, "{a} {b}");
    }

    #[test]
    fn the_median_of_an_even_count_is_the_middle_twos_mean() {
        assert_eq!(median(vec![4.0, 1.0, 3.0, 2.0]), 2.5);
        assert_eq!(median(vec![5.0, 1.0, 3.0]), 3.0);
    }
}
