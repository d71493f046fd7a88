//! What a ringer reading the report would want told and the figures alone
//! do not say (tester15, issue 43): which bells' strikes are missing, and
//! at which stroke, and a pace that changed.

use clapper_signal::striking::{ring_room, Timed};

use super::{BellStriking, StrikeReport};

/// The share of the rows a bell's strikes may fall short of (or stand over)
/// one a row before it is said: a tenth (three of 30 rows; a bell's
/// doubles, a strike lost at the recording's ends stay under it).
const OFF_SHARE: f64 = 0.1;

/// A bell heard at one stroke under this share of its other stroke's
/// count is said to be short at that stroke (quieter at it: tester15's
/// A6_quietback, 9 dB quieter at backstroke, was heard at 23 backstrokes
/// and 41 handstrokes).
const ONE_STROKE_SHARE: f64 = 0.8;

/// Bells missing strikes in one warning from this many on (a stretch the
/// finder lost, not one bell).
const MANY_BELLS: usize = 3;

/// The length (s) of the opening and closing stretches whose intervals are
/// compared for a pace that changed: a minute.
const PACE_STRETCH_S: f64 = 60.0;

/// The change of interval between the first and last minute (a share of
/// their mean) from which it is said: a tenth (a band's pace wanders less).
const PACE_CHANGE: f64 = 0.1;

/// Each bell's strikes, handstrokes and backstrokes in `strikes` (bells
/// from 1 to `bells`).
fn counts(strikes: &[StrikeReport], bells: usize) -> Vec<(usize, usize, usize)> {
    let mut c = vec![(0usize, 0usize, 0usize); bells];
    for s in strikes {
        if let Some(n) = c.get_mut(s.bell.wrapping_sub(1)) {
            n.0 += 1;
            n.1 += usize::from(s.stroke == Some("hand"));
            n.2 += usize::from(s.stroke == Some("back"));
        }
    }
    c
}

/// Bells as a ringer lists them: "bell 3" or "bells 2, 4, 5".
fn named(bells: &[usize]) -> String {
    let list: Vec<String> = bells.iter().map(|b| b.to_string()).collect();
    match bells.len() {
        1 => format!("bell {}", list[0]),
        _ => format!("bells {}", list.join(", ")),
    }
}

/// Why a hand or back column of the table holds fewer than
/// [`super::FEW_IN_COLUMN`] strikes (tester16 fault 3: "(n = 1)" alone
/// said nothing): a stroke's errors are
/// measured in full rows only (every bell heard once), so the line gives
/// how many rows of each stroke were full. Bells heard at one stroke only
/// (`one_stroke`, warned of on their own) and bells not heard are left out;
/// none when every other bell has that many or more at each stroke.
pub(super) fn columns_why(strikes: &[StrikeReport], per_bell: &[BellStriking], one_stroke: &[usize]) -> Option<String> {
    let short = |hand: bool| -> Vec<usize> {
        per_bell
            .iter()
            .filter(|b| b.strikes > 0 && !one_stroke.contains(&b.bell))
            .filter(|b| if hand { b.hand.n } else { b.back.n } < super::FEW_IN_COLUMN)
            .map(|b| b.bell)
            .collect()
    };
    let (hand, back) = (short(true), short(false));
    if hand.is_empty() && back.is_empty() {
        return None;
    }
    // Rows of each stroke, and those full (their strikes placed).
    let mut rows: std::collections::BTreeMap<usize, (bool, bool)> = std::collections::BTreeMap::new();
    for s in strikes {
        if let (Some(r), Some(k)) = (s.row, s.stroke) {
            let e = rows.entry(r).or_insert((k == "hand", false));
            e.1 |= s.place.is_some();
        }
    }
    let of = |hand: bool| {
        let mine = rows.values().filter(|v| v.0 == hand);
        (mine.clone().filter(|v| v.1).count(), mine.count())
    };
    let mut parts = vec![];
    for (stroke, bells, (full, all)) in [("hand", &hand, of(true)), ("back", &back, of(false))] {
        if !bells.is_empty() {
            parts.push(format!(
                "{} at {stroke}: {full} of the {all} {stroke}stroke rows held every bell once",
                named(bells)
            ));
        }
    }
    Some(format!(
        "columns of fewer than {} strikes: {} (a stroke's errors, and so the odd-struckness, are measured in such rows only)",
        super::FEW_IN_COLUMN,
        parts.join("; ")
    ))
}

/// Warnings for bells whose strikes fall short of one in each of the
/// `rows` rows, or stand over it, by over [`OFF_SHARE`]: each bell's own
/// count against the rows (not against the other bells', which may be the
/// ones short), and with `strokes_known` the stroke it is heard at only.
/// Bells in `few` (warned of as heard far less often) are left out.
pub(super) fn missing_warnings(
    strikes: &[StrikeReport],
    bells: usize,
    rows: usize,
    strokes_known: bool,
    few: &[usize],
) -> Vec<String> {
    let mut out = vec![];
    if rows < 10 {
        return out;
    }
    let c = counts(strikes, bells);
    let off = OFF_SHARE * rows as f64;
    let short: Vec<usize> = (1..=bells)
        .filter(|b| !few.contains(b) && c[b - 1].0 > 0 && ((rows - c[b - 1].0.min(rows)) as f64) > off)
        .collect();
    if short.len() >= MANY_BELLS {
        let lost: Vec<usize> = short.iter().map(|b| rows - c[b - 1].0).collect();
        let (lo, hi) = (
            lost.iter().min().copied().unwrap_or(0),
            lost.iter().max().copied().unwrap_or(0),
        );
        let who = if short.len() == bells {
            "every bell".to_string()
        } else {
            named(&short)
        };
        let lost = if lo == hi {
            format!("{lo}")
        } else {
            format!("{lo} to {hi}")
        };
        out.push(format!(
            "{who}: {lost} strikes missing each in {rows} rows: stretches of the recording not heard whole \
             (strikes quieter, or unlike the bell's usual sound?); the rows, places and striking are judged on \
             the strikes heard"
        ));
    } else {
        for &b in &short {
            let (n, hand, back) = c[b - 1];
            let one = |a: usize, other: usize| strokes_known && (a as f64) < ONE_STROKE_SHARE * other as f64;
            let why = if one(back, hand) {
                format!("heard at {hand} handstrokes and {back} backstrokes: quieter or muffled at backstroke?")
            } else if one(hand, back) {
                format!("heard at {hand} handstrokes and {back} backstrokes: quieter or muffled at handstroke?")
            } else {
                "weak or muffled strikes, a clapper that jams, or strikes not heard apart from the others?".to_string()
            };
            out.push(format!(
                "bell {b}: {n} strikes in {rows} rows: {} missing ({why})",
                rows - n
            ));
        }
    }
    for b in 1..=bells {
        let n = c[b - 1].0;
        if n > rows && (n - rows) as f64 > off {
            out.push(format!(
                "bell {b}: {n} strikes in {rows} rows: {} more than one a row (another bell's strikes taken for its?)",
                n - rows
            ));
        }
    }
    out
}

/// A warning that the pace changed: the interval between successive bells
/// in the first and last minute of `timed` (any order) differ by over
/// [`PACE_CHANGE`]; none for a recording under two and a half minutes,
/// or where either minute's strikes are spaced too unevenly to read.
pub(super) fn pace_warning(timed: &[Timed]) -> Option<String> {
    let (start, end) = timed
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), s| (a.min(s.t), b.max(s.t)));
    if timed.is_empty() || end - start < 2.5 * PACE_STRETCH_S {
        return None;
    }
    let within = |from: f64| -> Option<f64> {
        let some: Vec<Timed> = timed
            .iter()
            .copied()
            .filter(|s| (from..from + PACE_STRETCH_S).contains(&s.t))
            .collect();
        // A spacing scattered (strikes timed astray) reads no pace, as it
        // reads no ring's size (`doubt::ROOM_GATHERED`).
        ring_room(&some)
            .filter(|r| r.spread <= super::doubt::ROOM_GATHERED)
            .map(|r| r.interval_s * 1e3)
    };
    let (first, last) = (within(start)?, within(end - PACE_STRETCH_S)?);
    ((first - last).abs() > PACE_CHANGE * 0.5 * (first + last)).then(|| {
        format!(
            "the pace changed: bells {first:.0} ms apart in the first minute, {last:.0} ms in the last (the \
             interval above is over the whole recording)"
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn strike(bell: usize, row: usize) -> StrikeReport {
        StrikeReport {
            bell,
            t_s: row as f64,
            stroke: Some(if row % 2 == 0 { "hand" } else { "back" }),
            row: Some(row),
            place: None,
            error_ms: None,
            double: None,
            far_off: false,
        }
    }

    #[test]
    fn a_bell_short_is_told_against_the_rows_not_the_others() {
        // Bell 1 rings every row; bells 2-4 lost a fifth of theirs: bell 1
        // is not the odd one out (tester15 A8_level said it took others').
        let rows = 40;
        let mut s = vec![];
        for r in 0..rows {
            s.push(strike(1, r));
            s.extend((2..=4).filter(|_| r % 5 != 0).map(|b| strike(b, r)));
        }
        let w = missing_warnings(&s, 4, rows, true, &[]);
        assert_eq!(w.len(), 1, "{w:?}");
        assert!(
            w[0].starts_with("bells 2, 3, 4: 8 strikes missing each in 40 rows"),
            "{w:?}"
        );
    }

    #[test]
    fn a_bell_heard_at_handstroke_only_is_told() {
        let rows = 40;
        let mut s = vec![];
        for r in 0..rows {
            s.extend((1..=6).filter(|&b| b != 5 || r % 2 == 0).map(|b| strike(b, r)));
        }
        let w = missing_warnings(&s, 6, rows, true, &[]);
        assert_eq!(
            w,
            vec!["bell 5: 20 strikes in 40 rows: 20 missing (heard at 20 handstrokes and 0 backstrokes: quieter or muffled at backstroke?)"]
        );
        assert!(missing_warnings(&s, 6, rows, true, &[5]).is_empty());
    }

    #[test]
    fn a_touch_that_speeds_up_is_told_and_a_steady_one_is_not() {
        let ring = |ms_at: &dyn Fn(f64) -> f64| {
            let (mut t, mut out) = (0.0, vec![]);
            while t < 240.0 && out.len() < 20_000 {
                for bell in 1..=8 {
                    out.push(Timed { bell, t });
                    t += ms_at(t) / 1e3;
                }
                t += ms_at(t) / 1e3;
            }
            out
        };
        let w = pace_warning(&ring(&|t| 240.0 - 50.0 * (t / 240.0))).unwrap();
        assert!(w.starts_with("the pace changed: bells 2"), "{w}");
        assert_eq!(pace_warning(&ring(&|_| 220.0)), None);
    }
}
