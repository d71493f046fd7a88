//! The rows of the methods a synthetic ring rings (issue 43): Plain Bob,
//! Grandsire and Stedman from their place notation (through the
//! `bellframe` crate), on 4 or 5 to 12 bells. Grandsire and Stedman are
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
