//! Each strike as the report gives it, and each bell's striking from
//! them: place errors at each stroke, odd-struckness, double strikes.

use clapper_core::stroke::double_strike_index;
use clapper_signal::strikes::Heard;
use clapper_signal::striking::{mean_sd, steady, Rhythm, Timed};

use super::{odd, BellStriking, DoubleReport, StrikeReport, StrokeStats};

/// One stroke's striking from its place errors `v` (s): those far from
/// the rest left out (`steady`), as the odd-struckness leaves them; one
/// strike has no spread (none, not 0: tester15 read "± 0.0" for every bell).
pub(super) fn stroke_stats(v: &[f64]) -> StrokeStats {
    let st = steady(v);
    StrokeStats {
        n: st.map_or(0, |s| s.kept),
        left_out: st.map_or(0, |s| s.left_out),
        mean_error_ms: st.map(|s| s.mean * 1e3),
        spread_ms: st.filter(|s| s.kept > 1).map(|s| s.sd * 1e3),
    }
}

/// Each strike of `heard` as the report gives it, placed by the rhythm `r`.
pub(super) fn strike_reports(heard: &Heard, r: &Rhythm) -> Vec<StrikeReport> {
    heard
        .strikes
        .iter()
        .zip(&r.placed)
        .map(|(s, p)| StrikeReport {
            bell: s.bell,
            t_s: s.t,
            stroke: p.hand.map(|h| if h { "hand" } else { "back" }),
            row: p.row,
            place: p.place,
            error_ms: p.error.map(|e| e * 1e3),
            double: s.double.map(|d| DoubleReport {
                delay_ms: d.delay_s * 1e3,
                amplitude_ratio: d.amplitude_ratio,
                d_index: double_strike_index(d.amplitude_ratio, d.delay_s * 1e3),
            }),
            far_off: p.far_off,
        })
        .collect()
}

/// Bell `bell`'s striking from the report's `strikes` and the rhythm `r`
/// of the strikes `timed`.
pub(super) fn bell_striking(bell: usize, strikes: &[StrikeReport], r: &Rhythm, timed: &[Timed]) -> BellStriking {
    let mine: Vec<&StrikeReport> = strikes.iter().filter(|s| s.bell == bell).collect();
    let (h, b) = (r.stroke_errors(timed, bell, true), r.stroke_errors(timed, bell, false));
    let (hs, bs) = (stroke_stats(&h), stroke_stats(&b));
    // The columns' difference, or why not (odd.rs).
    let (odd, se, doubt) = odd::odd_struck_ms(&h, &b);
    let ds: Vec<f64> = mine.iter().filter_map(|s| s.double.map(|d| d.d_index)).collect();
    BellStriking {
        bell,
        strikes: mine.len(),
        hand: hs,
        back: bs,
        odd_struck_ms: odd,
        odd_struck_se_ms: se,
        odd_struck_doubt: doubt,
        double_strikes: ds.len(),
        double_rate: if mine.is_empty() {
            0.0
        } else {
            ds.len() as f64 / mine.len() as f64
        },
        mean_d: mean_sd(&ds).map(|x| x.0),
        timing_doubt: None,
    }
}
