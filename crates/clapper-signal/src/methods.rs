//! The rows of the methods a synthetic ring rings (issue 43): Plain Bob,
//! Grandsire and Stedman from their place notation (through the
//! `bellframe` crate), on 4 or 5 to 12 bells, and plain hunt; and which of
//! them, or rounds, the rows heard in a recording are ([`recognise`]). Grandsire and Stedman are
//! rung on an odd number of working bells: on an even number of bells the
//! tenor covers (rings last in every row).

use bellframe::{Method as BfMethod, Stage};

use crate::SignalError;

/// A method rung as its plain course, over and over.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PlainCourse {
    /// Plain Bob (4 to 12 bells).
    PlainBob,
    /// Grandsire (5 to 12 bells).
    Grandsire,
    /// Stedman (5 to 12 bells).
    Stedman,
}

impl PlainCourse {
    /// The method's name.
    pub fn name(self) -> &'static str {
        match self {
            PlainCourse::PlainBob => "Plain Bob",
            PlainCourse::Grandsire => "Grandsire",
            PlainCourse::Stedman => "Stedman",
        }
    }

    /// The fewest bells it is rung on.
    pub fn min_bells(self) -> usize {
        match self {
            PlainCourse::PlainBob => 4,
            _ => 5,
        }
    }

    /// The place notation on `working` bells.
    fn place_notation(self, working: usize) -> String {
        let n = place_char(working);
        match self {
            PlainCourse::PlainBob if working % 2 == 0 => format!("{},12", format!("x1{n}").repeat(working / 2)),
            PlainCourse::PlainBob => format!("{}{n},12{n}", format!("{n}.1.").repeat((working - 1) / 2)),
            PlainCourse::Grandsire => format!("3,1{}", format!(".{n}.1").repeat((working - 1) / 2)),
            PlainCourse::Stedman => format!("3.1.{n}.3.1.3.1.3.{n}.1.3.1"),
        }
    }

    /// The plain course on `bells` bells: its rows from rounds (the first)
    /// to the row before rounds comes round again, each the bells (from 0,
    /// the treble) in the order they strike.
    pub fn course(self, bells: usize) -> Result<Vec<Vec<usize>>, SignalError> {
        if !(self.min_bells()..=12).contains(&bells) {
            return Err(SignalError::Option(format!(
                "{} on {bells} bells: {} to 12 bells",
                self.name(),
                self.min_bells()
            )));
        }
        // Odd methods on even bells: the tenor covers.
        let working = match self {
            PlainCourse::PlainBob => bells,
            _ if bells % 2 == 0 => bells - 1,
            _ => bells,
        };
        let stage = Stage::new(working as u8);
        let m = BfMethod::from_place_not_string(self.name().to_string(), stage, &self.place_notation(working))
            .map_err(|e| SignalError::Option(format!("{}: {e}", self.name())))?;
        Ok(m.plain_course()
            .rows()
            .map(|r| {
                let mut row: Vec<usize> = r.bell_iter().map(|b| b.index()).collect();
                row.extend(working..bells);
                row
            })
            .collect())
    }
}

/// The plain hunt on `bells` bells (2 to 16): its rows from rounds to the
/// row before rounds comes round again (2 × `bells` rows), each the bells
/// (from 0) in the order they strike. Every bell hunts from lead to
/// behind and back: the changes swap the pairs from the lead and then the
/// pairs from second's place, in turn.
pub fn plain_hunt(bells: usize) -> Vec<Vec<usize>> {
    let mut row: Vec<usize> = (0..bells).collect();
    let mut rows = vec![row.clone()];
    for k in 1..2 * bells.max(1) {
        let mut p = (k + 1) % 2;
        while p + 1 < bells {
            row.swap(p, p + 1);
            p += 2;
        }
        rows.push(row.clone());
    }
    rows
}

/// What a ring's rows were found to be ([`recognise`]).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Recognised {
    /// "rounds", "plain hunt", "Plain Bob", "Grandsire" or "Stedman".
    pub name: &'static str,
    /// The changes heard (two whole rows one after the other) that it
    /// makes.
    pub fitting: usize,
    /// The changes heard it was judged on: every one, for rounds; else
    /// those not from rounds to rounds (the rounds rung before and after).
    pub judged: usize,
    /// The other methods that make as many of the changes heard: the
    /// changes heard do not tell them from it (a lead of Plain Bob is
    /// plain hunt but for its lead end: heard without it, the two are
    /// alike). Empty where it alone makes the most.
    pub alike: Vec<&'static str>,
}

/// The share of the changes judged a candidate must make to be named.
pub const RECOGNISED_SHARE: f64 = 0.8;

/// The fewest changes heard on which to name anything.
pub const FEWEST_CHANGES: usize = 4;

/// What the rows `rows` heard on `bells` bells were (in order; None where
/// a row was not heard whole; each whole row the bells from 0 in the
/// order they struck): rounds, if nearly every change heard is rounds to
/// rounds; else the first of plain hunt, Plain Bob, Grandsire and Stedman
/// (their plain courses, the tenor covering for the odd methods on an
/// even number) that makes the most of the other changes heard, if it
/// makes [`RECOGNISED_SHARE`] of them. None if none does, or fewer than
/// [`FEWEST_CHANGES`] were heard: a touch with calls, a method not
/// listed, or rows heard wrong.
pub fn recognise(rows: &[Option<Vec<usize>>], bells: usize) -> Option<Recognised> {
    let rounds: Vec<usize> = (0..bells).collect();
    let changes: Vec<(&Vec<usize>, &Vec<usize>)> = rows
        .windows(2)
        .filter_map(|w| Some((w[0].as_ref()?, w[1].as_ref()?)))
        .collect();
    if changes.len() < FEWEST_CHANGES {
        return None;
    }
    let in_rounds = changes.iter().filter(|(a, b)| **a == rounds && **b == rounds).count();
    if in_rounds as f64 >= RECOGNISED_SHARE * changes.len() as f64 {
        return Some(Recognised {
            name: "rounds",
            fitting: in_rounds,
            judged: changes.len(),
            alike: vec![],
        });
    }
    let judged: Vec<_> = changes
        .iter()
        .filter(|(a, b)| !(**a == rounds && **b == rounds))
        .collect();
    let mut courses: Vec<(&'static str, Vec<Vec<usize>>)> = vec![("plain hunt", plain_hunt(bells))];
    for m in [PlainCourse::PlainBob, PlainCourse::Grandsire, PlainCourse::Stedman] {
        if let Ok(c) = m.course(bells) {
            courses.push((m.name(), c));
        }
    }
    let fits: Vec<(&'static str, usize)> = courses
        .iter()
        .map(|(name, course)| (*name, fitting_changes(course, &judged)))
        .collect();
    // The first that makes the most (plain hunt before the methods it is
    // the start of), with every other that makes as many.
    let most = fits.iter().map(|f| f.1).max()?;
    let mut alike = fits.iter().filter(|f| f.1 == most).map(|f| f.0);
    let name = alike.next()?;
    let best = Recognised {
        name,
        fitting: most,
        judged: judged.len(),
        alike: alike.collect(),
    };
    (best.fitting as f64 >= RECOGNISED_SHARE * best.judged as f64).then_some(best)
}

/// How many of the changes `judged` (whole rows, one after the other)
/// the plain course `course` makes.
fn fitting_changes(course: &[Vec<usize>], judged: &[&(&Vec<usize>, &Vec<usize>)]) -> usize {
    let at: std::collections::HashMap<&[usize], usize> =
        course.iter().enumerate().map(|(i, r)| (r.as_slice(), i)).collect();
    judged
        .iter()
        .filter(|(a, b)| {
            at.get(a.as_slice())
                .is_some_and(|&i| course[(i + 1) % course.len()] == **b)
        })
        .count()
}

/// A place's character in place notation: 1-9, 0 (10), E (11), T (12).
fn place_char(place: usize) -> char {
    match place {
        10 => '0',
        11 => 'E',
        12 => 'T',
        p => char::from_digit(p as u32, 10).unwrap_or('?'),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Rows as heard: each course rung `times` over from rounds, with
    /// `rounds` rows of rounds before and after.
    fn rung(course: &[Vec<usize>], times: usize, rounds: usize) -> Vec<Option<Vec<usize>>> {
        let r: Vec<usize> = (0..course[0].len()).collect();
        let mut rows = vec![Some(r.clone()); rounds];
        for _ in 0..times {
            rows.extend(course.iter().cloned().map(Some));
        }
        rows.extend(vec![Some(r); rounds + 1]);
        rows
    }

    #[test]
    fn each_method_is_recognised_from_its_rows_and_no_other() {
        assert_eq!(plain_hunt(5)[1], vec![1, 0, 3, 2, 4], "5ths made first on five");
        assert_eq!(plain_hunt(6).len(), 12);
        for n in 5..=12 {
            let ph = recognise(&rung(&plain_hunt(n), 2, 2), n).unwrap();
            assert_eq!(ph.name, "plain hunt", "{n} bells");
            assert_eq!(ph.fitting, ph.judged);
            for m in [PlainCourse::PlainBob, PlainCourse::Grandsire, PlainCourse::Stedman] {
                let c = m.course(n).unwrap();
                let got = recognise(&rung(&c, 1, 3), n).map(|r| r.name);
                assert_eq!(got, Some(m.name()), "{} on {n}", m.name());
            }
        }
        let rounds = rung(&plain_hunt(8)[..1], 30, 0);
        assert_eq!(recognise(&rounds, 8).unwrap().name, "rounds");
    }

    /// Tester20's R8 and R9: a lead of Plain Bob Major, then rounds. Heard
    /// without its lead end, plain hunt and Plain Bob make every change
    /// alike and both are named; with it, Plain Bob alone.
    #[test]
    fn a_lead_of_plain_bob_without_its_lead_end_is_plain_hunt_or_plain_bob() {
        let lead = &PlainCourse::PlainBob.course(8).unwrap()[..17];
        let mut rows = rung(&plain_hunt(8)[..1], 4, 0);
        rows.extend(lead.iter().cloned().map(Some));
        let lead_end = rows.len() - 1;
        rows.extend(rung(&plain_hunt(8)[..1], 4, 0));
        let named = recognise(&rows, 8).unwrap();
        assert_eq!((named.name, named.alike.clone()), ("Plain Bob", vec![]), "{named:?}");
        // The lead end's row not heard whole.
        rows[lead_end] = None;
        let named = recognise(&rows, 8).unwrap();
        assert_eq!((named.name, named.alike), ("plain hunt", vec!["Plain Bob"]));
        // Two leads of plain hunt's own course: plain hunt alone.
        let ph = recognise(&rung(&plain_hunt(8), 2, 2), 8).unwrap();
        assert!(ph.alike.is_empty(), "{ph:?}");
    }

    #[test]
    fn rows_heard_in_part_or_wrong_are_judged_on_what_is_whole() {
        // A row in four not heard whole: still plain hunt.
        let mut rows = rung(&plain_hunt(6), 3, 0);
        for r in rows.iter_mut().step_by(4) {
            *r = None;
        }
        assert_eq!(recognise(&rows, 6).unwrap().name, "plain hunt");
        // Rows whose bells are shuffled at random make no method.
        let mut rng = <rand_pcg::Pcg64 as rand::SeedableRng>::seed_from_u64(12345);
        let mut shuffled = vec![];
        for _ in 0..30 {
            let mut r: Vec<usize> = (0..6).collect();
            rand::seq::SliceRandom::shuffle(&mut r[..], &mut rng);
            shuffled.push(Some(r));
        }
        assert_eq!(recognise(&shuffled, 6), None);
        // Too few changes to name anything.
        assert_eq!(recognise(&rung(&plain_hunt(6)[..2], 1, 0), 6), None);
    }

    #[test]
    fn plain_courses_have_their_known_lengths_and_rows() {
        // Plain course lengths: Plain Bob Doubles 40, Minor 60, Major 112,
        // Maximus 264; Grandsire Doubles 30, Triples 70 (and on 8 with the
        // tenor covering), Caters 126; Stedman Doubles 60, Triples 84, Cinques 132.
        for (m, n, len) in [
            (PlainCourse::PlainBob, 6, 60),
            (PlainCourse::PlainBob, 8, 112),
            (PlainCourse::PlainBob, 5, 40),
            (PlainCourse::PlainBob, 12, 264),
            (PlainCourse::Grandsire, 5, 30),
            (PlainCourse::Grandsire, 7, 70),
            (PlainCourse::Grandsire, 8, 70),
            (PlainCourse::Grandsire, 9, 126),
            (PlainCourse::Stedman, 5, 60),
            (PlainCourse::Stedman, 7, 84),
            (PlainCourse::Stedman, 12, 132),
        ] {
            let c = m.course(n).unwrap();
            assert_eq!(c.len(), len, "{} on {n}", m.name());
            assert_eq!(c[0], (0..n).collect::<Vec<_>>(), "rounds first");
            for w in c.windows(2) {
                let mut sorted = w[1].clone();
                sorted.sort();
                assert_eq!(sorted, (0..n).collect::<Vec<_>>(), "every bell once a row");
                // A change: each bell moves at most one place.
                for b in 0..n {
                    let p = |r: &Vec<usize>| r.iter().position(|&x| x == b).unwrap();
                    assert!(p(&w[0]).abs_diff(p(&w[1])) <= 1);
                }
            }
            if n % 2 == 0 && m != PlainCourse::PlainBob {
                assert!(c.iter().all(|r| r[n - 1] == n - 1), "the tenor covers");
            }
        }
        // Plain Bob Minor's first change is x: 214365.
        assert_eq!(PlainCourse::PlainBob.course(6).unwrap()[1], vec![1, 0, 3, 2, 5, 4]);
        // Grandsire Doubles' first change is 3: 21354.
        assert_eq!(PlainCourse::Grandsire.course(5).unwrap()[1], vec![1, 0, 2, 4, 3]);
        // Stedman Doubles' first change is 3: 21354; second 1: 23145.
        let s = PlainCourse::Stedman.course(5).unwrap();
        assert_eq!((s[1].clone(), s[2].clone()), (vec![1, 0, 2, 4, 3], vec![1, 2, 0, 3, 4]));
        assert!(PlainCourse::Stedman
            .course(4)
            .unwrap_err()
            .to_string()
            .contains("5 to 12"));
        assert!(PlainCourse::PlainBob.course(13).is_err());
    }
}
