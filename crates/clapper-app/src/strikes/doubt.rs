//! Doubts about the strikes heard (issue 46): what says a recording is not
//! of these bells rung in rows, said bell by bell. A bell whose strikes do
//! not rise in its own strongest partial is not heard struck (a steady
//! tone near its partial, say); bells whose strikes come together are one
//! sound heard as several (a bell's partials where another's are); strikes
//! that never make a row with every bell given are no ring's.

use clapper_signal::strikes::PLAUSIBLE_SHARE;
use clapper_signal::striking::Timed;

/// Strikes of two bells closer than this (s) are one sound: bells rung in
/// rows strike 160 ms or more apart, and a clash as close is rare.
pub(super) const TOGETHER_S: f64 = 0.02;
/// Warned when at least this share of the strikes come together.
const TOGETHER_SHARE: f64 = 0.25;
/// The fewest strikes of a bell judged ([`clapper_signal::strikes::rising`])
/// for its own share of rising strikes to be said.
const JUDGED_MIN: usize = 4;

/// A warning for each bell whose strikes seldom rise: `rises[b - 1]` is
/// (strikes of bell `b` judged, of them those that rise).
pub(super) fn bells_not_rising(rises: &[(usize, usize)]) -> Vec<String> {
    rises
        .iter()
        .enumerate()
        .filter(|(_, (n, up))| *n >= JUDGED_MIN && (*up as f64) < PLAUSIBLE_SHARE * *n as f64)
        .map(|(i, (n, up))| {
            format!(
                "bell {}: only {up} of its {n} strikes rise in its strongest partial (a bell's strike starts it): \
                 many are not this bell struck but another sound near its partials (another bell's, or a steady \
                 tone); its strikes are doubtful",
                i + 1
            )
        })
        .collect()
}

/// A warning when many strikes of different bells come together
/// (within [`TOGETHER_S`]): one sound heard as several bells.
pub(super) fn struck_together(timed: &[Timed]) -> Option<String> {
    let mut order: Vec<&Timed> = timed.iter().collect();
    order.sort_by(|a, b| a.t.total_cmp(&b.t));
    let near = |i: usize, j: usize| order[i].bell != order[j].bell && (order[j].t - order[i].t).abs() < TOGETHER_S;
    let mut bells: Vec<usize> = vec![];
    let mut count = 0;
    for i in 0..order.len() {
        if (i > 0 && near(i - 1, i)) || (i + 1 < order.len() && near(i, i + 1)) {
            count += 1;
            bells.push(order[i].bell);
        }
    }
    bells.sort_unstable();
    bells.dedup();
    (count >= 3 && count as f64 >= TOGETHER_SHARE * order.len() as f64).then(|| {
        let names: Vec<String> = bells.iter().map(usize::to_string).collect();
        format!(
            "{count} of the {} strikes come within {:.0} ms of another bell's, as bells rung in rows do not: \
             one sound is heard as several bells (bells {} together), one bell's partials lying where another's \
             are; give only the nominals of the bells that ring",
            order.len(),
            TOGETHER_S * 1e3,
            names.join(", ")
        )
    })
}

/// A warning when `strikes` strikes of only `heard` bells, half or fewer
/// of the `bells` given, make `rows` rows, none with every bell: no ring
/// rung in rows. (A bell or two not heard in a ring is warned of alone.)
pub(super) fn no_full_row(strikes: usize, rows: usize, full_rows: usize, heard: usize, bells: usize) -> Option<String> {
    (bells >= 2 && 2 * heard <= bells && full_rows == 0 && strikes >= 4 * bells.max(3)).then(|| {
        format!(
            "{strikes} strikes of only {heard} of the {bells} bells given, in {rows} row(s) none of which holds \
             every bell: not a ring rung in rows (not these bells, or not bells at all); the rows and places \
             below mean nothing"
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_bell_heard_as_four_at_once_is_told() {
        let timed: Vec<Timed> = (0..5)
            .flat_map(|k| {
                [1, 3, 5, 8].map(|bell| Timed {
                    bell,
                    t: 2.0 * k as f64 + 0.001 * bell as f64,
                })
            })
            .collect();
        let w = struck_together(&timed).expect("warned");
        assert!(
            w.contains("20 of the 20 strikes") && w.contains("bells 1, 3, 5, 8"),
            "{w}"
        );
        let rows: Vec<Timed> = (0..40)
            .map(|k| Timed {
                bell: k % 8 + 1,
                t: 0.2 * k as f64,
            })
            .collect();
        assert_eq!(struck_together(&rows), None);
    }

    #[test]
    fn a_bell_whose_strikes_do_not_rise_is_told() {
        let w = bells_not_rising(&[(10, 9), (10, 2), (2, 0)]);
        assert_eq!(w.len(), 1);
        assert!(w[0].starts_with("bell 2: only 2 of its 10"), "{}", w[0]);
    }

    #[test]
    fn strikes_of_few_of_the_bells_given_in_no_full_row_are_told() {
        assert!(no_full_row(48, 16, 0, 2, 8)
            .unwrap()
            .starts_with("48 strikes of only 2 of the 8"));
        // A bell or two not heard in a ring of eight: warned of alone.
        assert_eq!(no_full_row(168, 36, 0, 7, 8), None);
        assert_eq!(no_full_row(48, 16, 3, 2, 8), None);
    }
}
