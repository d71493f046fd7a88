//! A bell's odd-struckness as the report gives it (tester19 fault 3): the
//! hand column's mean less the back column's, with its standard error and,
//! where its evidence is weak or contradicted, why, in a ringer's words
//! (`clapper_signal::striking::odd_struck`).

use clapper_signal::striking::{odd_struck, OddDoubt};

/// The odd-struckness (ms), its standard error (ms) and why it is in doubt,
/// from a bell's handstroke and backstroke place errors `hand`, `back` (s).
/// One whose standard error is over [`SE_MOST_MS`] is held back (none),
/// its error kept, with why.
pub(super) fn odd_struck_ms(hand: &[f64], back: &[f64]) -> (Option<f64>, Option<f64>, Option<String>) {
    let Some(o) = odd_struck(hand, back) else {
        return (None, None, None);
    };
    let (value, se) = (o.value.map(|v| v * 1e3), o.se.map(|v| v * 1e3));
    match se.filter(|se| *se > SE_MOST_MS) {
        Some(se) if o.doubt.is_none() => (None, Some(se), Some(unknown(se))),
        _ => (value, se, o.doubt.map(words)),
    }
}

/// Doubt `b`'s odd-struckness, where it is given and not doubted already,
/// when the listener's timing of the bell is in doubt (its
/// `timing_doubt`) or its double strikes are (`doubled`): the figure may
/// be the listener's error (tester22 fault 8: r6a `--templates` bell 2,
/// marked "2?", read "+12.8 ± 8.0" against a truth of about 0; r8d's
/// bells 6 and 7, heard double at a fifth of their strikes, -8.8 and
/// -8.1 against 0). The figure stays, marked in its column.
pub(super) fn doubt_mistimed(b: &mut super::BellStriking, doubled: bool) {
    if b.odd_struck_ms.is_none() || b.odd_struck_doubt.is_some() {
        return;
    }
    b.odd_struck_doubt = if b.timing_doubt.is_some() {
        Some("the listener's timing is in doubt (said below): the figure may be its error, not the ringer's".into())
    } else if doubled {
        Some(
            "double strikes not to be believed (the room's echo heard as a second blow?): the same echo may move \
             where the strikes are heard to start, so the figure may be the listener's error"
                .into(),
        )
    } else {
        None
    };
}

/// The widest standard error (ms) an odd-struckness is given with: a
/// ringer's odd-struckness worth naming is 10-30 ms, and one known to
/// ± 10 ms or worse does not say whether there is any. On tester21's 14
/// rings in three modes every bell's was under 5.5 ms but for two bells
/// timed astray (K8 `--templates` bell 6: "+56.0 ± 32.9" where the truth
/// is about 0; E8 `--bells` bell 1: ± 67.5).
pub(super) const SE_MOST_MS: f64 = 10.0;

/// Why an odd-struckness of standard error `se` (ms) is not given.
fn unknown(se: f64) -> String {
    format!(
        "its strikes' errors scatter so widely that the odd-struckness is not known to within {se:.0} ms (its \
         standard error): not given"
    )
}

/// Why an odd-struckness is in doubt, in a ringer's words.
fn words(d: OddDoubt) -> String {
    let stroke = |hand: bool| if hand { "handstrokes" } else { "backstrokes" };
    match d {
        OddDoubt::Few { hand, back } => format!(
            "too few strikes placed to measure its uncertainty ({hand} {}, {back} {}): given without one",
            stroke(true),
            stroke(false)
        ),
        OddDoubt::Disagree { hand, left_out, of } => format!(
            "its {} disagree: {left_out} of {of} lie far from the rest, so the {} column's mean is one group of \
             them and the odd-struckness is not given",
            stroke(hand),
            if hand { "hand" } else { "back" }
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn errors_in_two_groups_give_words_not_a_figure() {
        let hand: Vec<f64> = [-0.037, -0.035, -0.034, -0.033, -0.030, -0.029, 0.081, 0.091, 0.091].to_vec();
        let back: Vec<f64> = (0..9).map(|k| 0.002 * k as f64).collect();
        let (odd, se, why) = odd_struck_ms(&hand, &back);
        assert_eq!((odd, se), (None, None));
        assert!(why.unwrap().contains("3 of 9"));
    }

    /// Tester21's K8 `--templates`: the quiet bell's backstrokes scattered
    /// (-55.3 ± 86.9 ms) and its odd-struckness read "+56.0 ± 32.9" where
    /// the truth was about 0. Held back, its standard error kept; a
    /// bell's steady columns still give one.
    #[test]
    fn an_odd_struckness_known_only_to_tens_of_ms_is_held_back() {
        let hand: Vec<f64> = (0..20).map(|k| 0.001 * (k % 5) as f64).collect();
        let back: Vec<f64> = (0..20).map(|k| 0.016 * (k as f64 - 9.5)).collect();
        let (odd, se, why) = odd_struck_ms(&hand, &back);
        assert_eq!(odd, None);
        assert!(se.is_some_and(|se| se > SE_MOST_MS), "{se:?}");
        assert!(why.is_some_and(|w| w.contains("not known")));
        let steady: Vec<f64> = (0..20).map(|k| 0.02 + 0.001 * (k % 5) as f64).collect();
        let (odd, se, why) = odd_struck_ms(&steady, &hand);
        assert!(odd.is_some_and(|o| (o - 20.0).abs() < 0.5), "{odd:?}");
        assert!(se.is_some_and(|se| se < 1.0) && why.is_none());
    }
}
