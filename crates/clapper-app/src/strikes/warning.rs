//! A warning of the strikes report with its kind (tester21 fault 7b: the
//! warnings were ranked by matching their words, and "8 bells asked for,
//! but only 4 nominal(s) learned" came 5th of 5): each warning is given a
//! kind where it is made, or where clapper-app receives it from the
//! signal layer or the file reader, and is ranked by that kind
//! ([`super::order`]).

use serde::ser::{Serialize, SerializeMap, Serializer};

/// What a warning is about, which says how soon a ringer must read it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum WarningKind {
    /// The recording itself is no ring's: silent, too short, no strikes,
    /// not bells, one sound heard as several bells.
    Recording,
    /// The strikes do not keep rows of the bells given: the rows, places
    /// and odd-struckness mean nothing.
    Rows,
    /// The double strikes heard are not to be believed (a bell heard
    /// double at more than a tenth of its strikes): said first, with the
    /// warnings that make figures mean nothing.
    Doubles,
    /// The ringer must give or ask for something else for the figures to
    /// hold: the bells given, asked for or learned are not those that ring
    /// (every nominal, templates, more bells), or the recording cannot
    /// carry what was given.
    Give,
    /// What qualifies the figures of the whole ring (how the strikes were
    /// timed, the pace, strokes guessed, strikes left out).
    Note,
    /// One bell heard at one stroke only: every figure of that bell is of
    /// one stroke, so it is said before the table with the ring's.
    OneStroke,
    /// A bell not heard at all: said before the table (its line is empty).
    Unheard,
    /// About one bell alone (its text starts "bell N:" or "bell N (..."):
    /// said with that bell after the table.
    Bell,
}

/// A warning: its kind and its words.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Warning {
    /// What it is about.
    pub kind: WarningKind,
    /// Its words, for the ringer.
    pub text: String,
}

impl Warning {
    /// The warning `text` of the kind `kind`.
    pub fn new(kind: WarningKind, text: impl Into<String>) -> Self {
        Warning {
            kind,
            text: text.into(),
        }
    }

    /// A warning `text` received from another layer (the signal layer's
    /// finder, learner or calibration, the file reader): about one bell
    /// ([`WarningKind::Bell`]) where its words name one bell first
    /// (`order::one_bell`), else of the kind `kind`.
    pub fn received(kind: WarningKind, text: impl Into<String>) -> Self {
        let text = text.into();
        match super::order::one_bell(&text) {
            Some(_) => Warning::new(WarningKind::Bell, text),
            None => Warning::new(kind, text),
        }
    }

    /// The bell (from 1) a [`WarningKind::Bell`] or
    /// [`WarningKind::Unheard`] warning is about; none for the others.
    pub fn bell(&self) -> Option<usize> {
        match self.kind {
            WarningKind::Bell | WarningKind::Unheard | WarningKind::OneStroke => super::order::one_bell(&self.text),
            _ => None,
        }
    }
}

impl std::fmt::Display for Warning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.text)
    }
}

/// The report's warnings, in the order a ringer reads them. In the JSON
/// they stay the list of words `warnings` they always were, with their
/// kinds beside them in `warning_kinds` (snake_case names, one for each).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Warnings(pub Vec<Warning>);

impl Warnings {
    /// Their words, in order.
    pub fn texts(&self) -> Vec<&str> {
        self.0.iter().map(|w| w.text.as_str()).collect()
    }

    /// Whether any warning's words hold `words`.
    pub fn any_holds(&self, words: &str) -> bool {
        self.0.iter().any(|w| w.text.contains(words))
    }
}

impl std::ops::Deref for Warnings {
    type Target = Vec<Warning>;
    fn deref(&self) -> &Vec<Warning> {
        &self.0
    }
}

impl std::ops::DerefMut for Warnings {
    fn deref_mut(&mut self) -> &mut Vec<Warning> {
        &mut self.0
    }
}

impl<'a> IntoIterator for &'a Warnings {
    type Item = &'a Warning;
    type IntoIter = std::slice::Iter<'a, Warning>;
    fn into_iter(self) -> Self::IntoIter {
        self.0.iter()
    }
}

impl Serialize for Warnings {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let kinds: Vec<WarningKind> = self.0.iter().map(|w| w.kind).collect();
        let mut m = s.serialize_map(Some(2))?;
        m.serialize_entry("warnings", &self.texts())?;
        m.serialize_entry("warning_kinds", &kinds)?;
        m.end()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The JSON keeps `warnings` as words and adds each one's kind.
    #[test]
    fn warnings_serialise_as_words_with_their_kinds_beside() {
        #[derive(serde::Serialize)]
        struct S {
            n: usize,
            #[serde(flatten)]
            warnings: Warnings,
        }
        let s = S {
            n: 1,
            warnings: Warnings(vec![
                Warning::new(WarningKind::Give, "8 bells asked for"),
                Warning::received(WarningKind::Note, "bell 3: few strikes"),
            ]),
        };
        let j = serde_json::to_string(&s).unwrap_or_default();
        assert_eq!(
            j,
            r#"{"n":1,"warnings":["8 bells asked for","bell 3: few strikes"],"warning_kinds":["give","bell"]}"#
        );
    }
}
