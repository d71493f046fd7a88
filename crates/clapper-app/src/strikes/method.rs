//! What the rows heard were: rounds or a method's plain course
//! (`clapper_signal::methods::recognise`), from the rows heard whole (a
//! row lacking one bell is whole: its empty place is that bell's).

use serde::Serialize;

use super::StrikeReport;

/// What the rows heard were (`clapper_signal::methods::recognise`).
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct MethodReport {
    /// "rounds", "plain hunt", "Plain Bob", "Grandsire" or "Stedman".
    pub name: String,
    /// The changes heard (two whole rows one after the other) it makes.
    pub changes_fitting: usize,
    /// The changes heard it was judged on (for a method, those not rounds
    /// to rounds).
    pub changes_judged: usize,
    /// Other methods that make as many of the changes heard, which these
    /// rows cannot tell from it (a lead of Plain Bob heard without its lead
    /// end is plain hunt too: tester20's R8 and R9 were named "plain hunt"
    /// by one timing and "Plain Bob" by another). Left out of the JSON
    /// where empty.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub alike: Vec<String>,
    /// The changes of its plain course on these bells (none for rounds):
    /// the changes heard are counted against those the rows hold, not
    /// against it (tester21's E8: "64 of 64 changes" read as the course
    /// of a method whose course is 112).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub course_changes: Option<usize>,
}

impl MethodReport {
    /// The report's line for it.
    pub(super) fn line(&self) -> String {
        let rounds = self.name == "rounds";
        // The course's length after the count, not before: plain hunt
        // rung twice read "its plain course, 12 changes long: 26 of the 26
        // changes" (tester22), as if 26 were of 12.
        let course = match self.course_changes {
            Some(n) => format!("; its plain course is {n} changes"),
            None => String::new(),
        };
        let counted = format!(
            "{} of the {} changes heard in whole rows are its{}{course}",
            self.changes_fitting,
            self.changes_judged,
            if rounds { "" } else { ", rounds left out" }
        );
        if self.alike.is_empty() {
            return format!("rows: {} ({counted})", self.name);
        }
        let mut names = vec![self.name.as_str()];
        names.extend(self.alike.iter().map(String::as_str));
        let last = names.pop().unwrap_or_default();
        format!(
            "rows: {} or {last} ({} makes {} of the {} changes heard in whole rows, rounds left out; the changes \
             where they part, at a lead end, were not heard: too short a touch, or rows missed, to tell which)",
            names.join(", "),
            if self.alike.len() == 1 { "each" } else { "every one" },
            self.changes_fitting,
            self.changes_judged
        )
    }
}

/// `row` (each place's bell, from 0, of `bells`) with its one empty place
/// given the one bell it lacks: a row is every bell once, so a bell not
/// heard in it (quiet at that stroke, tester18's ring A with `--nominals`:
/// Plain Bob named with `--templates` only) stood where no bell was heard.
/// Rows with more than one place empty are as they were.
fn one_place_filled(mut row: Vec<Option<usize>>, bells: usize) -> Vec<Option<usize>> {
    let empty: Vec<usize> = (0..row.len()).filter(|&p| row[p].is_none()).collect();
    let lacking: Vec<usize> = (0..bells).filter(|b| !row.contains(&Some(*b))).collect();
    if let ([p], [b]) = (empty.as_slice(), lacking.as_slice()) {
        row[*p] = Some(*b);
    }
    row
}

/// What the rows of `rows` rows the `strikes` were placed in were
/// (`clapper_signal::methods::recognise`), from the rows heard whole: each
/// of the `bells` bells once, in places 1 to `bells`.
pub(super) fn method_of(strikes: &[StrikeReport], rows: usize, bells: usize) -> Option<MethodReport> {
    // One or two bells make no method: every row of one bell is "rounds"
    // (tester19: one nominal given read "rounds (18 of 18 changes)").
    if bells < 3 {
        return None;
    }
    let mut heard: Vec<Vec<Option<usize>>> = vec![vec![None; bells]; rows];
    let mut spoilt = vec![false; rows];
    for s in strikes {
        if let (Some(row), Some(place)) = (s.row, s.place) {
            match heard.get_mut(row).and_then(|r| r.get_mut(place.wrapping_sub(1))) {
                Some(slot @ None) => *slot = Some(s.bell - 1),
                _ => {
                    if let Some(bad) = spoilt.get_mut(row) {
                        *bad = true;
                    }
                }
            }
        }
    }
    let whole: Vec<Option<Vec<usize>>> = heard
        .into_iter()
        .zip(spoilt)
        .map(|(r, bad)| {
            let r: Option<Vec<usize>> = one_place_filled(r, bells).into_iter().collect();
            r.filter(|r| {
                !bad && {
                    let mut seen = vec![false; bells];
                    r.iter().all(|&b| b < bells && !std::mem::replace(&mut seen[b], true))
                }
            })
        })
        .collect();
    clapper_signal::methods::recognise(&whole, bells).map(|m| MethodReport {
        name: m.name.to_string(),
        changes_fitting: m.fitting,
        changes_judged: m.judged,
        alike: m.alike.iter().map(|n| n.to_string()).collect(),
        course_changes: course_changes(m.name, bells),
    })
}

/// The changes of the plain course of the method `name` on `bells` bells
/// (a course's rows from rounds to the row before rounds comes again make
/// as many changes); none for rounds or a name not known.
fn course_changes(name: &str, bells: usize) -> Option<usize> {
    use clapper_signal::methods::{plain_hunt, PlainCourse};
    if name == "plain hunt" {
        return Some(plain_hunt(bells).len());
    }
    let m = [PlainCourse::PlainBob, PlainCourse::Grandsire, PlainCourse::Stedman]
        .into_iter()
        .find(|m| m.name() == name)?;
    m.course(bells).ok().map(|c| c.len())
}

#[cfg(test)]
mod tests {
    use super::*;
    use clapper_signal::methods::PlainCourse;

    /// Two courses of Plain Bob Minor as strikes placed in their rows,
    /// less bell `quiet`'s (from 1) at every backstroke (odd row).
    fn plain_bob_less(quiet: Option<usize>) -> Vec<StrikeReport> {
        let course = PlainCourse::PlainBob.course(6).unwrap();
        let rows = course.iter().chain(&course);
        let mut out = vec![];
        for (r, row) in rows.enumerate() {
            for (p, &b) in row.iter().enumerate() {
                if r % 2 == 1 && quiet == Some(b + 1) {
                    continue;
                }
                out.push(StrikeReport {
                    bell: b + 1,
                    t_s: r as f64,
                    stroke: None,
                    row: Some(r),
                    place: Some(p + 1),
                    error_ms: None,
                    double: None,
                    far_off: false,
                });
            }
        }
        out
    }

    #[test]
    fn a_bell_quiet_at_one_stroke_does_not_hide_the_method() {
        let rows = 2 * PlainCourse::PlainBob.course(6).unwrap().len();
        let named = |s: &[StrikeReport]| method_of(s, rows, 6).map(|m| m.name);
        assert_eq!(named(&plain_bob_less(None)).as_deref(), Some("Plain Bob"));
        // Tester18's ring A with --nominals: bell 5 not heard at backstroke.
        assert_eq!(named(&plain_bob_less(Some(5))).as_deref(), Some("Plain Bob"));
    }

    #[test]
    fn methods_the_rows_cannot_tell_apart_are_both_named() {
        let m = MethodReport {
            name: "plain hunt".into(),
            changes_fitting: 12,
            changes_judged: 13,
            alike: vec!["Plain Bob".into()],
            course_changes: Some(12),
        };
        let line = m.line();
        assert!(
            line.starts_with("rows: plain hunt or Plain Bob (each makes 12 of the 13"),
            "{line}"
        );
        assert!(line.contains("to tell which"), "{line}");
        let alone = MethodReport { alike: vec![], ..m };
        assert_eq!(
            alone.line(),
            "rows: plain hunt (12 of the 13 changes heard in whole rows are its, rounds left out; its plain \
             course is 12 changes)"
        );
    }

    /// Tester21's E8 `--templates`: "its plain course: 64 of 64 changes"
    /// on a course of 112; the course's own length is said beside the
    /// changes heard.
    #[test]
    fn the_plain_course_is_said_with_its_own_length() {
        assert_eq!(course_changes("Plain Bob", 8), Some(112));
        assert_eq!(course_changes("plain hunt", 6), Some(12));
        assert_eq!(course_changes("Stedman", 7), Some(84));
        assert_eq!(course_changes("rounds", 6), None);
        let rows = 2 * PlainCourse::PlainBob.course(6).unwrap().len();
        let m = method_of(&plain_bob_less(None), rows, 6)
            .map(|m| m.line())
            .unwrap_or_default();
        assert!(
            m.starts_with("rows: Plain Bob (") && m.ends_with("; its plain course is 60 changes)"),
            "{m}"
        );
    }

    #[test]
    fn one_or_two_bells_make_no_method() {
        let rows = 2 * PlainCourse::PlainBob.course(6).unwrap().len();
        let one: Vec<StrikeReport> = plain_bob_less(None).into_iter().filter(|s| s.bell == 1).collect();
        let one: Vec<StrikeReport> = one.into_iter().map(|s| StrikeReport { place: Some(1), ..s }).collect();
        assert!(method_of(&one, rows, 1).is_none());
        assert!(method_of(&plain_bob_less(None), rows, 6).is_some());
    }

    #[test]
    fn a_row_lacking_two_bells_is_not_filled() {
        let row = vec![Some(0), None, Some(2), None];
        assert_eq!(one_place_filled(row.clone(), 4), row);
        assert_eq!(
            one_place_filled(vec![Some(3), None, Some(0), Some(1)], 4),
            vec![Some(3), Some(2), Some(0), Some(1)]
        );
    }
}
