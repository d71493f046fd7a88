//! Which warnings a ringer reads first (tester20 fault 8: 14-22 warning
//! lines stood before the table and buried the one that mattered): those
//! that make the table mean nothing, then those that ask the ringer to
//! give something else, then the rest; a warning about one bell alone
//! is said with that bell after the table.

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

/// Words only the warnings that make the whole report void say.
const VOID: [&str; 8] = [
    "mean nothing",
    "the recording is silent",
    "no strikes heard",
    "does not sound like a recording of bells",
    "the recording is only",
    "not a ring rung in rows",
    "no bell's striking can be judged",
    "heard as several bells",
];

/// Words of a warning that asks the ringer to give something else: an
/// option, or "give".
const ACT: [&str; 3] = ["give ", "--", "ask for"];

/// How much the warning `w` weighs ([`Weight`]). A bell not heard at all
/// stays before the table (tester17: such a bell was named nowhere).
pub(super) fn weight(w: &str) -> Weight {
    if VOID.iter().any(|v| w.contains(v)) {
        return Weight::Void;
    }
    if let Some(b) = one_bell(w).filter(|_| !w.contains("not heard at all")) {
        return Weight::Bell(b);
    }
    if ACT.iter().any(|a| w.contains(a)) {
        Weight::Act
    } else {
        Weight::Note
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
pub(super) fn rank(warnings: &mut [String]) {
    warnings.sort_by_key(|w| weight(w));
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_warning_that_voids_the_table_comes_first_and_single_bells_last() {
        let mut w: Vec<String> = [
            "bell 6 (1237.9 Hz): its nominal rose most at only 8 strikes heard",
            "bell 2: how late its strikes sound after the blow is not sure",
            "3 strike(s) timed before the recording starts: left out",
            "8 nominal(s) given, but the strikes leave room for about 10 bells: give every bell's nominal",
            "bell 5: not heard at all (no strike found): it did not ring",
            "the strikes do not keep the rhythm of rows of 8 bells: the rows, places and odd-struckness below \
             mean nothing",
        ]
        .map(String::from)
        .to_vec();
        rank(&mut w);
        assert!(w[0].starts_with("the strikes do not keep the rhythm"), "{w:?}");
        assert!(w[1].starts_with("8 nominal(s) given"), "{w:?}");
        assert!(w[2].starts_with("3 strike(s)"), "{w:?}");
        assert!(w[3].starts_with("bell 5: not heard at all"), "{w:?}");
        assert!(w[4].starts_with("bell 2:") && w[5].starts_with("bell 6 ("), "{w:?}");
    }

    #[test]
    fn only_a_warning_about_one_bell_is_a_bells() {
        assert_eq!(one_bell("bell 12: 3 missing"), Some(12));
        assert_eq!(one_bell("bell 4 (1458.2 Hz): unsure"), Some(4));
        assert_eq!(one_bell("bells 3 and 5: alike"), None);
        assert_eq!(one_bell("bell 4's nominal"), None);
        assert_eq!(one_bell("the bells"), None);
        assert_eq!(
            weight("bells 3 and 5: one's strikes may be taken for the other's"),
            Weight::Note
        );
    }
}
