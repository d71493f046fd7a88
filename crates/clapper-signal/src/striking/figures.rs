//! A bell's odd-struckness from its steady errors at each stroke, and how
//! far it can be trusted (tester19 fault 3): read from the same errors as
//! the table's hand and back columns (each stroke's errors less those far
//! from the rest, `steady`), so that it is their difference; with its
//! standard error only where each stroke holds enough errors to measure a
//! spread, and not given where a stroke's errors disagree (many far from
//! the rest: ring A `--nominals` read bell 3 −85.7 ± 2.1 ms, from two
//! tight groups of its errors a third of them left out, where it was
//! +27.5).

use super::{steady, Steady};

/// Fewer errors than this at a stroke measure no spread worth an error bar:
/// the odd-struckness is given without one (ring I `--templates` read a
/// bell +26.3 ± 8.0 ms from two handstrokes, where it was even).
pub const ODD_FEW: usize = 5;

/// More than this share of a stroke's errors far from the rest
/// (`steady`'s left out) is not a strike or two heard far off: the errors
/// disagree, and the steady error is one group of them.
pub const ODD_DISAGREE: f64 = 0.25;

/// Why an odd-struckness cannot be trusted as its figures say.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum OddDoubt {
    /// A stroke holds fewer than [`ODD_FEW`] errors: given without a
    /// standard error.
    Few {
        /// Handstroke errors counted.
        hand: usize,
        /// Backstroke errors counted.
        back: usize,
    },
    /// A stroke's errors disagree (over [`ODD_DISAGREE`] of them far from
    /// the rest): not given.
    Disagree {
        /// The stroke: handstroke (else backstroke).
        hand: bool,
        /// Its errors left out as far from the rest.
        left_out: usize,
        /// Its errors in all.
        of: usize,
    },
}

/// A bell's odd-struckness as the table gives it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OddStruck {
    /// Steady handstroke error less steady backstroke error (s); `None`
    /// where a stroke's errors disagree.
    pub value: Option<f64>,
    /// Its standard error (s), where both strokes hold [`ODD_FEW`] errors
    /// or more and agree.
    pub se: Option<f64>,
    /// Why it is not to be trusted as it stands, if so.
    pub doubt: Option<OddDoubt>,
}

/// The odd-struckness of a bell whose errors (s) are `hand` and `back`;
/// `None` without errors at both strokes.
pub fn odd_struck(hand: &[f64], back: &[f64]) -> Option<OddStruck> {
    let (h, b) = (steady(hand)?, steady(back)?);
    let disagree = |s: &Steady, hand: bool| {
        let of = s.kept + s.left_out;
        (s.left_out as f64 > ODD_DISAGREE * of as f64).then_some(OddDoubt::Disagree {
            hand,
            left_out: s.left_out,
            of,
        })
    };
    if let Some(d) = disagree(&h, true).or_else(|| disagree(&b, false)) {
        return Some(OddStruck {
            value: None,
            se: None,
            doubt: Some(d),
        });
    }
    let value = Some(h.mean - b.mean);
    if h.kept < ODD_FEW || b.kept < ODD_FEW {
        let doubt = Some(OddDoubt::Few {
            hand: h.kept,
            back: b.kept,
        });
        return Some(OddStruck { value, se: None, doubt });
    }
    let se = (h.sd * h.sd / h.kept as f64 + b.sd * b.sd / b.kept as f64).sqrt();
    Some(OddStruck {
        value,
        se: Some(se),
        doubt: None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `n` errors (s) spread evenly over ±`half` about `mean`.
    fn spread(mean: f64, half: f64, n: usize) -> Vec<f64> {
        (0..n)
            .map(|k| mean - half + 2.0 * half * k as f64 / (n - 1) as f64)
            .collect()
    }

    #[test]
    fn the_odd_struckness_is_the_columns_difference_with_its_error() {
        let (h, b) = (spread(0.012, 0.01, 20), spread(-0.013, 0.01, 20));
        let o = odd_struck(&h, &b).expect("odd");
        assert!((o.value.unwrap() - 0.025).abs() < 1e-12, "{o:?}");
        assert!(o.se.unwrap() > 0.001 && o.se.unwrap() < 0.003, "{o:?}");
        assert_eq!(o.doubt, None);
    }

    #[test]
    fn two_groups_of_errors_give_no_odd_struckness() {
        // Ring A's bell 3 at handstroke: six about -33 ms, three about +88.
        let mut h = spread(-0.033, 0.004, 6);
        h.extend(spread(0.088, 0.005, 3));
        let b = spread(0.0, 0.01, 9);
        let o = odd_struck(&h, &b).expect("odd");
        assert_eq!(o.value, None, "{o:?}");
        assert_eq!(
            o.doubt,
            Some(OddDoubt::Disagree {
                hand: true,
                left_out: 3,
                of: 9
            })
        );
    }

    #[test]
    fn two_handstrokes_give_no_error_bar() {
        let o = odd_struck(&spread(0.026, 0.006, 2), &spread(0.0, 0.02, 33)).expect("odd");
        assert!(o.value.is_some() && o.se.is_none(), "{o:?}");
        assert_eq!(o.doubt, Some(OddDoubt::Few { hand: 2, back: 33 }));
    }
}
