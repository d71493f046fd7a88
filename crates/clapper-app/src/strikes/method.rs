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
    /// The changes of the touch (none for rounds): from the last rounds
    /// before the first row heard whole that is not rounds, to the rounds
    /// after the last such row (or the last row heard); the rows not heard
    /// whole counted in.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub touch_changes: Option<usize>,
}

/// Under this share of the touch's changes heard in whole rows, the
/// method is said to be named from part of the touch (tester22's r6b:
/// Plain Bob named from 18 of its 60 changes, not said).
const PART_OF_TOUCH: f64 = 0.75;

impl MethodReport {
    /// The report's line for it.
    pub(super) fn line(&self) -> String {
        if self.name == "rounds" {
            return format!(
                "rows: rounds ({} of the {} changes heard in whole rows are its)",
                self.changes_fitting, self.changes_judged
            );
        }
        if self.alike.is_empty() {
            return format!("rows: {}{}", self.name, self.counted());
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

    /// How much of the touch it is and how it was judged, after its name
    /// (tester22 fault 7: plain hunt rung three times read "its plain
    /// course, 12 changes long: 26 of the 26 changes"): how many times its
    /// plain course was rung, the touch's changes, and where few of those
    /// were heard in whole rows, that it is named from part of the touch.
    fn counted(&self) -> String {
        let (f, j) = (self.changes_fitting, self.changes_judged);
        let Some(t) = self.touch_changes.filter(|&t| t >= j) else {
            let course = self
                .course_changes
                .map_or(String::new(), |c| format!("; its plain course is {c} changes"));
            return format!(" ({f} of the {j} changes heard in whole rows are its, rounds left out{course})");
        };
        let head = match self.course_changes {
            Some(c) => {
                let k = (t as f64 / c as f64).round() as usize;
                let times = match k {
                    1 => "once".to_string(),
                    2 => "twice".to_string(),
                    k => format!("{k} times"),
                };
                if k == 0 || t.abs_diff(k * c) * 4 > c {
                    format!(", {t} changes (its plain course is {c})")
                } else {
                    let about = if t == k * c { "" } else { "about " };
                    format!(", rung {about}{times} ({t} changes; its plain course is {c})")
                }
            }
            None => format!(", {t} changes"),
        };
        if (j as f64) < PART_OF_TOUCH * t as f64 {
            format!(
                "{head}: named from part of the touch, the {j} of its {t} changes heard in whole rows ({f} of them \
                 its)"
            )
        } else {
            format!("{head}: {f} of the {j} changes heard in whole rows are its")
        }
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
        touch_changes: (m.name != "rounds").then(|| touch_changes(&whole, bells)).flatten(),
    })
}

/// The changes of the touch among `whole` (each row heard whole, or
/// none) of `bells` bells ([`MethodReport::touch_changes`]); none where
/// no row heard whole is other than rounds.
fn touch_changes(whole: &[Option<Vec<usize>>], bells: usize) -> Option<usize> {
    let rounds: Vec<usize> = (0..bells).collect();
    let changed = |r: &Option<Vec<usize>>| r.as_ref().is_some_and(|r| *r != rounds);
    let first = whole.iter().position(changed)?;
    let last = whole.iter().rposition(changed)?;
    Some((last + 1).min(whole.len() - 1) - first.saturating_sub(1))
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
        let rows: Vec<Vec<usize>> = course.iter().chain(&course).cloned().collect();
        let lost = |s: &StrikeReport| s.row.is_some_and(|r| r % 2 == 1) && quiet == Some(s.bell);
        placed(&rows, &[]).into_iter().filter(|s| !lost(s)).collect()
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
            touch_changes: None,
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
            m.starts_with("rows: Plain Bob, rung about twice (119 changes; its plain course is 60): "),
            "{m}"
        );
    }

    /// Strikes placed in `rows` (each place's bell, from 0), every bell's
    /// strike left out of the rows of `gaps` (by index) but one.
    fn placed(rows: &[Vec<usize>], gaps: &[usize]) -> Vec<StrikeReport> {
        let mut out = vec![];
        for (r, row) in rows.iter().enumerate() {
            let keep = if gaps.contains(&r) { 1 } else { row.len() };
            for (p, &b) in row.iter().enumerate().take(keep) {
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

    /// Tester22 fault 7: plain hunt rung three times read "its plain
    /// course, 12 changes long: 26 of the 26 changes", and Plain Bob named
    /// from 18 of its 60 changes did not say so. The touch's length is said
    /// as courses rung, and a method named from part of it says so.
    #[test]
    fn a_touch_is_said_as_courses_rung_and_named_from_part_when_so() {
        use clapper_signal::methods::plain_hunt;
        let rounds: Vec<usize> = (0..6).collect();
        let mut rows = vec![rounds.clone(); 6];
        for _ in 0..3 {
            rows.extend(plain_hunt(6).into_iter().skip(1));
            rows.push(rounds.clone());
        }
        rows.extend(vec![rounds.clone(); 5]);
        let line = |gaps: &[usize]| method_of(&placed(&rows, gaps), rows.len(), 6).map(|m| m.line());
        assert_eq!(
            line(&[]).as_deref(),
            Some("rows: plain hunt, rung 3 times (36 changes; its plain course is 12): 36 of the 36 changes heard in whole rows are its")
        );
        // Every fourth row of the touch not heard whole: 16 of 36 changes lost.
        let gaps: Vec<usize> = (8..40).step_by(4).collect();
        let part = line(&gaps).unwrap_or_default();
        assert!(
            part.starts_with("rows: plain hunt, rung 3 times (36 changes; its plain course is 12): named from part of the touch, the 20 of its 36"),
            "{part}"
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
