//! What the rows heard were: rounds or a method's plain course
//! (`clapper_signal::methods::recognise`), from the rows heard whole.

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
}

impl MethodReport {
    /// The report's line for it.
    pub(super) fn line(&self) -> String {
        let rounds = self.name == "rounds";
        format!(
            "rows: {} ({}{} of {} changes heard in whole rows{})",
            self.name,
            if rounds { "" } else { "its plain course: " },
            self.changes_fitting,
            self.changes_judged,
            if rounds { "" } else { ", rounds left out" }
        )
    }
}

/// What the rows of `rows` rows the `strikes` were placed in were
/// (`clapper_signal::methods::recognise`), from the rows heard whole: each
/// of the `bells` bells once, in places 1 to `bells`.
pub(super) fn method_of(strikes: &[StrikeReport], rows: usize, bells: usize) -> Option<MethodReport> {
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
            let r: Option<Vec<usize>> = r.into_iter().collect();
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
    })
}
