//! A bell heard at one stroke only (issue 43): silent, or far too quiet
//! to be heard, at its other stroke.

use clapper_signal::striking::{heard_at_one_stroke, typical_strikes, Timed};

/// Each bell of the `bells` (treble first) heard at one stroke only in
/// `timed` (`striking::heard_at_one_stroke`: at most 0.6 of the typical
/// bell's strikes, three in four of its intervals two rows), with its
/// warning; heard with `templates`, the warning does not advise them
/// (tester20). The tester's six with bell 5 silent at every backstroke
/// (A6_quiet60) was reported with no word of it, its empty place read as
/// a handstroke gap.
pub(super) fn one_stroke_warnings(timed: &[Timed], bells: usize, templates: bool) -> Vec<(usize, String)> {
    let typical = typical_strikes(timed, bells).unwrap_or(0);
    let hint = if templates {
        ""
    } else {
        " (a bell's own recorded strike, --templates, hears quieter strokes)"
    };
    heard_at_one_stroke(timed, bells)
        .into_iter()
        .map(|b| {
            let n = timed.iter().filter(|s| s.bell == b).count();
            let w = format!(
                "bell {b}: heard at one stroke only ({n} strikes, where a typical bell has {typical}, nearly all two \
                 rows apart): at its other stroke it is silent, or too quiet to be heard apart from the other \
                 bells{hint}; that stroke's strikes are nearly all missing from the report, and its rows are read \
                 without the bell"
            );
            (b, w)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Six bells in rounds at 0.25 s with a handstroke gap, bell 5 at
    /// handstroke only: warned of, once; every bell at both strokes, or
    /// bell 5 missing a strike here and there, not.
    #[test]
    fn a_bell_heard_at_one_stroke_only_is_told() {
        let ring = |keep: &dyn Fn(usize, usize) -> bool| -> Vec<Timed> {
            let mut v = vec![];
            for row in 0..40 {
                let start = row as f64 * 1.5 + (row / 2) as f64 * 0.25;
                for bell in 1..=6 {
                    if keep(row, bell) {
                        v.push(Timed {
                            bell,
                            t: start + 0.25 * (bell - 1) as f64,
                        });
                    }
                }
            }
            v
        };
        let w = one_stroke_warnings(&ring(&|row, bell| bell != 5 || row % 2 == 0), 6, false);
        assert_eq!(w.len(), 1, "{w:?}");
        assert_eq!(w[0].0, 5);
        assert!(
            w[0].1.starts_with("bell 5: heard at one stroke only (20 strikes"),
            "{w:?}"
        );
        assert!(w[0].1.contains("--templates, hears quieter strokes"), "{w:?}");
        // Heard with templates already: not advised to give them.
        let w = one_stroke_warnings(&ring(&|row, bell| bell != 5 || row % 2 == 0), 6, true);
        assert!(!w[0].1.contains("--templates"), "{w:?}");
        assert!(one_stroke_warnings(&ring(&|_, _| true), 6, false).is_empty());
        assert!(one_stroke_warnings(&ring(&|row, bell| bell != 5 || row % 3 != 0), 6, false).is_empty());
    }
}
