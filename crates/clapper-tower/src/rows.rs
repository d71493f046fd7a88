//! The rows of a touch: rounds, a method by name or by place notation
//! (through `bellframe`), or rows given one by one (read from a file by an
//! outer layer, or heard in a recording).
//!
//! Bells are counted from 0 (the treble) here; a row is the order in which
//! the bells strike, so `row[p]` is the bell in place `p`.

use bellframe::{Method, Stage};

use crate::TowerError;

/// A method of the Central Council's library by its title, with its place
/// notation as the library gives it (the CC Methods Library,
/// <https://cccbr.github.io/methods-library/>, read for these titles;
/// bellframe's own `MethodLib::cc_lib` downloads the whole library at run
/// time, which this crate does not do). Stedman and Grandsire are rung on
/// odd stages; on 6 and 8 bells their Doubles and Triples are rung with a
/// cover bell (the tenor strikes last in every row).
pub const METHODS: &[(&str, u8, &str)] = &[
    ("Plain Bob Doubles", 5, "5.1.5.1.5,125"),
    ("Plain Bob Minor", 6, "x16x16x16,12"),
    ("Plain Bob Triples", 7, "7.1.7.1.7.1.7,127"),
    ("Plain Bob Major", 8, "x18x18x18x18,12"),
    ("Grandsire Doubles", 5, "3,1.5.1.5.1"),
    ("Grandsire Triples", 7, "3,1.7.1.7.1.7.1"),
    ("Grandsire Caters", 9, "3,1.9.1.9.1.9.1.9.1"),
    ("Stedman Doubles", 5, "3.1.5.3.1.3,1"),
    ("Stedman Triples", 7, "3.1.7.3.1.3,1"),
    ("Stedman Caters", 9, "3.1.9.3.1.3,1"),
    ("Cambridge Surprise Minor", 6, "x36x14x12x36x14x56,12"),
    ("Cambridge Surprise Major", 8, "x38x14x1258x36x14x58x16x78,12"),
];

/// What the band rings.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case", tag = "kind")]
pub enum TouchSpec {
    /// Rounds: `rows` rows, every bell in its own place.
    Rounds {
        /// Number of rows (changes).
        rows: usize,
    },
    /// A method from its title (one of [`METHODS`]) or its place notation
    /// (`stage` then needed), rung in plain leads from rounds.
    Method {
        /// A title in [`METHODS`], e.g. "Plain Bob Major", or any name when
        /// `place_notation` is given.
        title: String,
        /// Place notation (CC syntax: `x` or `-` a cross, `,` a symmetric
        /// block), overriding the title's.
        place_notation: Option<String>,
        /// Number of working bells, with `place_notation`.
        stage: Option<u8>,
        /// Plain leads rung (with `changes`: whichever is given).
        leads: Option<usize>,
        /// Changes rung (the plain course repeated, a stand-in for a peal
        /// composition as far as the frame is concerned).
        changes: Option<usize>,
    },
    /// Rows given one by one, bells from 0.
    Rows {
        /// The rows.
        rows: Vec<Vec<u8>>,
    },
}

/// A method by title (case-insensitive) or place notation: the title, the
/// stage and the `bellframe` method.
pub fn method(title: &str, place_notation: Option<&str>, stage: Option<u8>) -> Result<Method, TowerError> {
    let (name, stage, pn) = match place_notation {
        Some(pn) => {
            let stage = stage.ok_or_else(|| TowerError::Rows("a place notation needs its stage (bells)".into()))?;
            (title.to_string(), stage, pn.to_string())
        }
        None => {
            let found = METHODS.iter().find(|(t, _, _)| t.eq_ignore_ascii_case(title.trim()));
            let Some((t, n, pn)) = found else {
                let names: Vec<&str> = METHODS.iter().map(|m| m.0).collect();
                return Err(TowerError::Rows(format!(
                    "no method '{title}' here; known: {}; or give its place notation and stage",
                    names.join(", ")
                )));
            };
            (t.to_string(), *n, pn.to_string())
        }
    };
    if !(3..=16).contains(&stage) {
        return Err(TowerError::Rows(format!("stage {stage}: 3 to 16 bells")));
    }
    Method::from_place_not_string(name, Stage::new(stage), &pn)
        .map_err(|e| TowerError::Rows(format!("place notation '{pn}': {e}")))
}

/// A `bellframe` row as bell indices from 0.
fn indices(row: &bellframe::Row) -> Vec<u8> {
    row.bell_iter().map(|b| b.index_u8()).collect()
}

/// The most rows (changes) of a touch: four peals. A peal's 5,040 rows of
/// eight bells hold about 100 MB of histories.
pub const MAX_TOUCH_ROWS: usize = 20_160;

/// The rows of a touch on `n_bells` bells. A method on fewer bells than
/// the ring is rung with the others covering (in their own places at the
/// back); on more bells than the ring, refused. The first row is rounds and
/// the touch ends with the row it comes round to (a method) or after the
/// asked number of rows.
pub fn touch_rows(spec: &TouchSpec, n_bells: usize) -> Result<Vec<Vec<u8>>, TowerError> {
    let rows = match spec {
        TouchSpec::Rounds { rows } => {
            if *rows == 0 {
                return Err(TowerError::Rows("rounds of 0 rows".into()));
            }
            if *rows > MAX_TOUCH_ROWS {
                return Err(TowerError::Rows(format!(
                    "rounds of {rows} rows: a touch of at most {MAX_TOUCH_ROWS} rows"
                )));
            }
            vec![(0..n_bells as u8).collect(); *rows]
        }
        TouchSpec::Method {
            title,
            place_notation,
            stage,
            leads,
            changes,
        } => {
            let m = method(title, place_notation.as_deref(), *stage)?;
            let stage = m.stage().num_bells();
            if stage > n_bells {
                return Err(TowerError::Rows(format!(
                    "{} needs {stage} bells; the ring has {n_bells}",
                    m.title()
                )));
            }
            let n_changes = match (leads, changes) {
                // Saturating: a count too large to hold is refused below all the same.
                (Some(l), None) => l.saturating_mul(m.lead_len()),
                (None, Some(c)) => *c,
                (None, None) => m.lead_len(),
                (Some(_), Some(_)) => return Err(TowerError::Rows("give leads or changes, not both".into())),
            };
            if n_changes == 0 {
                return Err(TowerError::Rows("a touch of 0 changes".into()));
            }
            // Bounded before the rows are made.
            if n_changes > MAX_TOUCH_ROWS {
                return Err(TowerError::Rows(format!(
                    "{n_changes} changes of {}: a touch of at most {MAX_TOUCH_ROWS} changes",
                    m.title()
                )));
            }
            (0..=n_changes)
                .map(|i| {
                    let mut r = indices(&m.row_in_plain_course(i));
                    r.extend(stage as u8..n_bells as u8);
                    r
                })
                .collect()
        }
        TouchSpec::Rows { rows } => rows.clone(),
    };
    check_rows(&rows, n_bells)?;
    Ok(rows)
}

/// Every row a permutation of the ring's bells.
pub fn check_rows(rows: &[Vec<u8>], n_bells: usize) -> Result<(), TowerError> {
    if rows.is_empty() {
        return Err(TowerError::Rows("no rows".into()));
    }
    for (k, r) in rows.iter().enumerate() {
        let mut seen = vec![false; n_bells];
        let ok = r.len() == n_bells
            && r.iter().all(|&b| {
                let b = b as usize;
                b < n_bells && !std::mem::replace(&mut seen[b], true)
            });
        if !ok {
            return Err(TowerError::Rows(format!(
                "row {} ({}) is not an order of the ring's {n_bells} bells",
                k + 1,
                row_text(r)
            )));
        }
    }
    Ok(())
}

/// A row in the ringers' notation: 1-9, 0 (10), E (11), T (12), A, B, C, D.
pub fn row_text(row: &[u8]) -> String {
    const NAMES: &[u8] = b"1234567890ETABCD";
    row.iter()
        .map(|&b| NAMES.get(b as usize).map_or('?', |&c| c as char))
        .collect()
}

/// A row from the ringers' notation (`12345678`, `1234567890ET`).
pub fn parse_row(text: &str) -> Result<Vec<u8>, TowerError> {
    const NAMES: &str = "1234567890ETABCD";
    text.trim()
        .chars()
        .map(|c| {
            NAMES
                .find(c.to_ascii_uppercase())
                .map(|i| i as u8)
                .ok_or_else(|| TowerError::Rows(format!("'{c}' in row '{}' is not a bell", text.trim())))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lead_head(title: &str) -> String {
        let m = method(title, None, None).unwrap();
        row_text(&indices(m.lead_head()))
    }

    fn lead_end(title: &str) -> String {
        let m = method(title, None, None).unwrap();
        row_text(&indices(m.lead_end()))
    }

    /// Lead heads and lead ends of the plain lead as the CC library's
    /// methods give them (the standard lead-head orders of Plain Bob and
    /// Grandsire; Cambridge's "b" lead head; Stedman's double six). Worked
    /// by hand from the place notation too, e.g. Grandsire Doubles:
    /// 12345 21354 23145 32415 34251 43521 45312 54132 51423 15243 12534;
    /// Stedman Triples 6347251 as complib gives it.
    #[test]
    fn lead_heads_match_the_cc_library() {
        for (title, head, end) in [
            ("Plain Bob Minor", "135264", "132546"),
            ("Plain Bob Major", "13527486", "13254768"),
            ("Grandsire Doubles", "12534", "15243"),
            ("Grandsire Triples", "1253746", "1527364"),
            ("Stedman Doubles", "53412", "54321"),
            ("Stedman Triples", "6347251", "6432715"),
            ("Cambridge Surprise Minor", "156342", "153624"),
            ("Cambridge Surprise Major", "15738264", "15372846"),
        ] {
            assert_eq!(lead_head(title), head, "{title} lead head");
            assert_eq!(lead_end(title), end, "{title} lead end");
        }
    }

    /// Lead lengths and plain courses: Plain Bob Major 16 a lead, 112 a
    /// course; Cambridge Major 32 and 224; Stedman Triples 12 and 84;
    /// Grandsire Triples 14 and 70; the minor methods 12 (PB) and 24 (Cambridge).
    #[test]
    fn lead_and_course_lengths() {
        for (title, lead, course) in [
            ("Plain Bob Minor", 12, 60),
            ("Plain Bob Major", 16, 112),
            ("Grandsire Doubles", 10, 30),
            ("Grandsire Triples", 14, 70),
            ("Stedman Doubles", 12, 60),
            ("Stedman Triples", 12, 84),
            ("Cambridge Surprise Minor", 24, 120),
            ("Cambridge Surprise Major", 32, 224),
        ] {
            let m = method(title, None, None).unwrap();
            assert_eq!(m.lead_len(), lead, "{title}");
            assert_eq!(m.course_len(), course, "{title}");
        }
    }

    /// Cambridge Minor's first lead, every row, against the rows worked by
    /// hand from x36x14x12x36x14x56,12 (its first half lead).
    #[test]
    fn cambridge_minor_first_half_lead() {
        let rows = touch_rows(
            &TouchSpec::Method {
                title: "cambridge surprise minor".into(),
                place_notation: None,
                stage: None,
                leads: Some(1),
                changes: None,
            },
            6,
        )
        .unwrap();
        let text: Vec<String> = rows.iter().take(13).map(|r| row_text(r)).collect();
        assert_eq!(
            text,
            [
                "123456", "214365", "124635", "216453", "261435", "624153", "621435", "264153", "624513", "265431",
                "256413", "524631", "256431"
            ]
        );
        assert_eq!(rows.len(), 25);
    }

    /// Grandsire Triples on eight: the tenor covers.
    #[test]
    fn a_cover_bell_stays_behind() {
        let rows = touch_rows(
            &TouchSpec::Method {
                title: "Grandsire Triples".into(),
                place_notation: None,
                stage: None,
                leads: Some(2),
                changes: None,
            },
            8,
        )
        .unwrap();
        assert_eq!(rows.len(), 29);
        assert!(rows.iter().all(|r| r[7] == 7));
        assert_eq!(row_text(&rows[14]), "12537468");
        assert!(touch_rows(
            &TouchSpec::Method {
                title: "Plain Bob Major".into(),
                place_notation: None,
                stage: None,
                leads: Some(1),
                changes: None
            },
            6
        )
        .is_err());
    }

    #[test]
    fn rows_read_and_checked() {
        assert_eq!(parse_row("1234567890ET").unwrap(), (0..12).collect::<Vec<u8>>());
        assert_eq!(row_text(&parse_row("21436587").unwrap()), "21436587");
        assert!(check_rows(&[vec![0, 1, 1]], 3).is_err());
        assert!(check_rows(&[vec![0, 1]], 3).is_err());
        assert!(parse_row("12x4").is_err());
    }
}
