//! A bell's odd-struckness as the report gives it (tester19 fault 3): the
//! hand column's mean less the back column's, with its standard error and,
//! where its evidence is weak or contradicted, why, in a ringer's words
//! (`clapper_signal::striking::odd_struck`).

use clapper_signal::striking::{odd_struck, OddDoubt};

/// The odd-struckness (ms), its standard error (ms) and why it is in doubt,
/// from a bell's handstroke and backstroke place errors `hand`, `back` (s).
pub(super) fn odd_struck_ms(hand: &[f64], back: &[f64]) -> (Option<f64>, Option<f64>, Option<String>) {
    let Some(o) = odd_struck(hand, back) else {
        return (None, None, None);
    };
    (o.value.map(|v| v * 1e3), o.se.map(|v| v * 1e3), o.doubt.map(words))
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
}
