//! Which warnings a ringer reads first (tester20 fault 8: 14-22 warning
//! lines stood before the table and buried the one that mattered): those
//! that make the table mean nothing, then those that ask the ringer to
//! give something else, then the rest; a warning about one bell alone
//! is said with that bell after the table. Ranked by each warning's kind
//! ([`WarningKind`]), not its words (tester21 fault 7b).

use super::warning::{Warning, WarningKind};

/// How much a warning weighs with the ringer (the order they are said in).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub(super) enum Weight {
    /// The recording is no ring's, or the rows and places mean nothing.
    Void,
    /// The ringer must give or ask for something else for the figures to
    /// hold (every bell's nominal, templates, the right bells).
    Act,
    /// What qualifies the figures.
    Note,
    /// About one bell alone (from 1): said with the bells after the table.
    Bell(usize),
}

/// How much the warning `w` weighs ([`Weight`]), by its kind
/// ([`WarningKind`]): a bell not heard at all, or heard at one stroke
/// only, stays before the table (tester17: such a bell was named nowhere;
/// tester21 fault 7a: one heard at one stroke only was said under the
/// table, its line not marked, though every figure of it changes).
pub(super) fn weight(w: &Warning) -> Weight {
    match w.kind {
        WarningKind::Recording | WarningKind::Rows | WarningKind::Doubles => Weight::Void,
        WarningKind::Give => Weight::Act,
        WarningKind::Note | WarningKind::OneStroke | WarningKind::Unheard => Weight::Note,
        WarningKind::Bell => w.bell().map_or(Weight::Note, Weight::Bell),
    }
}

/// The bell (from 1) the warning `w` is about alone: it starts "bell 4:"
/// or "bell 4 (1458.2 Hz)"; none for "bells 3 and 5" or anything else.
pub(super) fn one_bell(w: &str) -> Option<usize> {
    let rest = w.strip_prefix("bell ")?;
    let digits = rest.len() - rest.trim_start_matches(|c: char| c.is_ascii_digit()).len();
    let after = &rest[digits..];
    if after.starts_with(':') || after.starts_with(" (") {
        rest[..digits].parse().ok()
    } else {
        None
    }
}

/// `warnings` in the order a ringer acts on them ([`Weight`]; within a
/// weight, as they were; a bell's after the warnings about the whole
/// ring, treble first).
pub(super) fn rank(warnings: &mut [Warning]) {
    warnings.sort_by_key(weight);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_warning_that_voids_the_table_comes_first_and_single_bells_last() {
        use WarningKind::*;
        let mut w: Vec<Warning> = [
            (
                Bell,
                "bell 6 (1237.9 Hz): its nominal rose most at only 8 strikes heard",
            ),
            (Bell, "bell 2: how late its strikes sound after the blow is not sure"),
            (Note, "3 strike(s) timed before the recording starts: left out"),
            (
                Give,
                "8 nominal(s) given, but the strikes leave room for about 10 bells: give every bell's nominal",
            ),
            (Unheard, "bell 5: not heard at all (no strike found): it did not ring"),
            (
                Rows,
                "the strikes do not keep the rhythm of rows of 8 bells: the rows mean nothing",
            ),
        ]
        .map(|(k, t)| Warning::new(k, t))
        .to_vec();
        rank(&mut w);
        let t: Vec<&str> = w.iter().map(|w| w.text.as_str()).collect();
        assert!(t[0].starts_with("the strikes do not keep the rhythm"), "{t:?}");
        assert!(t[1].starts_with("8 nominal(s) given"), "{t:?}");
        assert!(t[2].starts_with("3 strike(s)"), "{t:?}");
        assert!(t[3].starts_with("bell 5: not heard at all"), "{t:?}");
        assert!(t[4].starts_with("bell 2:") && t[5].starts_with("bell 6 ("), "{t:?}");
    }

    /// Tester21's G8 `--bells 8`: the warning that fewer bells were learned
    /// than asked for came 5th of 5, after notes, by its words; by its kind
    /// it comes straight after those that void the table.
    #[test]
    fn fewer_bells_learned_than_asked_for_comes_before_every_note() {
        let mut w: Vec<Warning> = vec![
            Warning::new(
                WarningKind::Rows,
                "the strikes do not keep the rhythm of rows of 4 bells",
            ),
            Warning::new(WarningKind::Note, "the strikes came unevenly timed either way"),
            Warning::received(WarningKind::Note, "bells 3 and 8: their partials rise alike"),
            Warning::received(WarningKind::Give, "8 bells asked for, but only 4 nominal(s) learned"),
        ];
        rank(&mut w);
        assert!(w[1].text.starts_with("8 bells asked for"), "{w:?}");
        assert_eq!(weight(&w[3]), Weight::Note);
    }

    #[test]
    fn only_a_warning_about_one_bell_is_a_bells() {
        assert_eq!(one_bell("bell 12: 3 missing"), Some(12));
        assert_eq!(one_bell("bell 4 (1458.2 Hz): unsure"), Some(4));
        assert_eq!(one_bell("bells 3 and 5: alike"), None);
        assert_eq!(one_bell("bell 4's nominal"), None);
        assert_eq!(one_bell("the bells"), None);
        assert_eq!(
            weight(&Warning::received(
                WarningKind::Note,
                "bells 3 and 5: one's strikes may be taken"
            )),
            Weight::Note
        );
        assert_eq!(
            weight(&Warning::received(WarningKind::Note, "bell 3: few")),
            Weight::Bell(3)
        );
    }
}
