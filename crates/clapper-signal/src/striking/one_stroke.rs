//! A bell heard at one stroke only (issue 43; tester16's fault 3): silent,
//! or far too quiet to be heard, at its other stroke. Its strikes come two
//! rows apart, so its own intervals say nothing of its strokes, and the
//! rows of its silent stroke lack it: it must neither vote on strokes nor
//! be asked for in every row, or its empty place reads as a handstroke gap
//! of two intervals and every row of that stroke as not full.

use super::Timed;

/// A bell's intervals between strikes this many times the ring's row, at
/// least and at most, are two rows: 2 n + 1 places (one the handstroke
/// gap), two more or fewer where the bell moves a place each row, over
/// the row's n + ½; a bell heard at both strokes keeps under
/// (n + 2) / (n + ½), 1.43 for three bells.
pub const TWO_ROWS: (f64, f64) = (1.55, 2.6);

/// The bells (from 1, ascending) of the `bells` heard at one stroke only in
/// `strikes` (any order): at most 0.6 of the typical bell's strikes (six at
/// least), three in four of its intervals two rows ([`TWO_ROWS`] times the
/// ring's row, s: the median over the bells of each one's median pull, half
/// the time from a strike to the strike after next, which a bell's single
/// intervals, alternately short and long and moved by its places, are not).
pub fn heard_at_one_stroke(strikes: &[Timed], bells: usize) -> Vec<usize> {
    at_one_stroke(strikes, bells, 3, 3)
}

/// The bells (from 1, ascending) of the `bells` heard mostly at one stroke
/// in `strikes`: as [`heard_at_one_stroke`], but with half their intervals
/// two rows, not three in four, and at most 0.8 of the typical bell's
/// strikes, not 0.6. A bell 9 dB quieter at one stroke is heard
/// there at some strikes (tester21's G8 `--templates`: 16 of 61): rows of
/// that stroke may lack it. A bell missing strikes at random keeps under
/// a third of its intervals two rows where it is heard at three in five.
pub fn heard_mostly_at_one_stroke(strikes: &[Timed], bells: usize) -> Vec<usize> {
    at_one_stroke(strikes, bells, 2, 4)
}

/// The bells with at most `fifths` in five of the typical bell's strikes
/// and at least `quarters` in four of their intervals two rows.
fn at_one_stroke(strikes: &[Timed], bells: usize, quarters: usize, fifths: usize) -> Vec<usize> {
    let per = times_per_bell(strikes, bells);
    let pulls = |t: &[f64]| -> Vec<f64> { t.windows(3).map(|w| 0.5 * (w[2] - w[0])).collect() };
    let mut rows: Vec<f64> = per
        .iter()
        .filter(|t| t.len() >= 6)
        .filter_map(|t| middle(pulls(t)))
        .collect();
    rows.sort_by(f64::total_cmp);
    let (Some(&row), Some(typical)) = (rows.get(rows.len() / 2), typical_count(&per)) else {
        return vec![];
    };
    per.iter()
        .enumerate()
        .filter(|(_, t)| t.len() >= 6 && 5 * t.len() <= fifths * typical)
        .filter(|(_, t)| {
            let g = gaps(t);
            let two = g
                .iter()
                .filter(|&&d| d >= TWO_ROWS.0 * row && d <= TWO_ROWS.1 * row)
                .count();
            4 * two >= quarters * g.len()
        })
        .map(|(i, _)| i + 1)
        .collect()
}

/// The typical bell's number of strikes (the median over the `bells`, the
/// upper of the middle two), `None` with no bells.
pub fn typical_strikes(strikes: &[Timed], bells: usize) -> Option<usize> {
    typical_count(&times_per_bell(strikes, bells))
}

fn typical_count(per: &[Vec<f64>]) -> Option<usize> {
    let mut counts: Vec<usize> = per.iter().map(Vec::len).collect();
    counts.sort_unstable();
    counts.get(counts.len() / 2).copied()
}

/// Each bell's strike times (s), ascending.
fn times_per_bell(strikes: &[Timed], bells: usize) -> Vec<Vec<f64>> {
    (1..=bells)
        .map(|b| {
            let mut t: Vec<f64> = strikes.iter().filter(|s| s.bell == b).map(|s| s.t).collect();
            t.sort_by(f64::total_cmp);
            t
        })
        .collect()
}

fn gaps(t: &[f64]) -> Vec<f64> {
    t.windows(2).map(|w| w[1] - w[0]).collect()
}

/// The median of `v` (the upper of the middle two), if any.
fn middle(mut v: Vec<f64>) -> Option<f64> {
    v.sort_by(f64::total_cmp);
    v.get(v.len() / 2).copied()
}
