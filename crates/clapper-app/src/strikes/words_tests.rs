//! The report's words as a ringer reads them (tester15 fault 6): no spread
//! of 0 where none can be measured, and each dash said what it means.

use super::*;

/// A report of one bell whose strokes are `hand` and `back`, timed from
/// templates with its strikes' move `matched_ms`.
fn one_bell(hand: StrokeStats, back: StrokeStats, matched_ms: Option<f64>) -> StrikesReport {
    StrikesReport {
        bells: 1,
        learned_nominals_hz: None,
        learned_set: None,
        timing: Some(TimingReport {
            source: "templates",
            per_bell: vec![BellTiming {
                bell: 1,
                lateness_ms: 12.0,
                spread_ms: 1.0,
                learned_from: 0,
                matched_ms,
            }],
            choice: None,
        }),
        strikes: vec![],
        per_bell: vec![BellStriking {
            bell: 1,
            strikes: hand.n + back.n,
            hand,
            back,
            odd_struck_ms: Some(199.0),
            odd_struck_se_ms: None,
            double_strikes: 0,
            double_rate: 0.0,
            mean_d: None,
        }],
        summary: StrikesSummary {
            duration_s: 10.0,
            strikes: hand.n + back.n,
            rows: 2,
            full_rows: 2,
            interval_ms: None,
            handstroke_gap_intervals: None,
            handstroke_gap_ms: None,
            rms_error_ms: None,
            double_strikes: 0,
            strokes_known: false,
            method: None,
            plausibility: None,
            warnings: vec![],
        },
    }
}

#[test]
fn a_spread_of_one_strike_is_not_printed_as_zero() {
    let (one, two) = (stroke_stats(&[86.8]), stroke_stats(&[80.0, 90.0]));
    assert_eq!(one.spread_ms, None);
    assert!((two.spread_ms.unwrap() - 7.07).abs() < 0.01);
    let text = one_bell(one, two, Some(-3.0)).text("r");
    assert!(text.contains("+86.8 (n = 1)"), "{text}");
    assert!(text.contains("+85.0 ± 7.1"), "{text}");
    assert!(text.contains("+199.0 (no se)"), "{text}");
    assert!(!text.contains("± 0.0"), "{text}");
}

#[test]
fn a_dash_in_the_timing_line_says_what_it_means() {
    let s = stroke_stats(&[1.0, 2.0]);
    let text = one_bell(s, s, None).text("r");
    assert!(
        text.contains("late by (ms) 1 - (-: not learned, nothing taken off)"),
        "{text}"
    );
    assert!(
        text.contains("moved by (median ms) 1 - (-: no strike of it could be matched"),
        "{text}"
    );
    let text = one_bell(s, s, Some(-3.0)).text("r");
    assert!(text.contains("moved by (median ms) 1 -3.0\n"), "{text}");
}
