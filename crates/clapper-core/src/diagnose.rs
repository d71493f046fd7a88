//! Diagnosis of a bell for a bell-hanger (the paper's conclusions): where
//! it sits on the chart, how it rings, whether it goes up right, how close
//! it is to an edge in terms a hanger can change (clapper period, r), and
//! the clapper changes that cure its problems ([`crate::clapper_changes`]).
//! Also the ring-level check for a bell that stands apart.

use crate::bell::Bell;
use crate::clapper_changes::{goes_up, hanger_changes, HangerChange};
use crate::clapper_parts::ClapperParts;
use crate::dynamics::Dynamics;
use crate::frame::{frame_peaks, FramePeaks};
use crate::ringer::Settles;
use crate::stroke::{run_stroke, SimConfig, SimError, StrokeStart, Style, TraceRecorder};
pub use crate::verdicts::{
    adjusted, margin, min_theta0_right, DiagnoseConfig, Margin, Problem, StrokeFigures, StyleOutcome,
};
use crate::verdicts::{outcome, problems_of};

/// Everything the diagnosis says about one bell.
#[derive(Clone, Debug, PartialEq)]
pub struct BellDiagnosis {
    /// (r/L_c, L_b/L_c).
    pub position: (f64, f64),
    /// Ringing right fully up.
    pub right: StyleOutcome,
    /// Ringing wrong fully up.
    pub wrong: StyleOutcome,
    /// The style it normally rings: right if it can, else wrong, else none.
    pub usual: Option<Style>,
    /// Smallest θ0 (rad) from which it still rings right, scanning down
    /// from the configured θ0; `None` if it does not ring right fully up.
    pub min_theta0_right: Option<f64>,
    /// Margin of the usual style.
    pub margin: Option<Margin>,
    /// What is wrong.
    pub problems: Vec<Problem>,
    /// How it goes up, rung up from rest by [`DiagnoseConfig::ringer`].
    pub goes_up: Settles,
    /// The clapper changes that cure its problems, in the hanger's order
    /// ([`hanger_changes`]); empty without problems or without a cure.
    pub changes: Vec<HangerChange>,
    /// Loads on the frame over a stroke of the usual style (the larger of
    /// handstroke and backstroke for a bell hung out of true).
    pub frame: Option<FramePeaks>,
}

impl BellDiagnosis {
    /// The outcome in the usual style.
    pub fn usual_outcome(&self) -> Option<&StyleOutcome> {
        match self.usual? {
            Style::Right => Some(&self.right),
            Style::Wrong => Some(&self.wrong),
        }
    }
}

/// Diagnose one bell.
///
/// ```
/// use clapper_core::{bell::Bell, diagnose::{diagnose, DiagnoseConfig}, stroke::Style};
/// let d = diagnose(&Bell::lab(), &DiagnoseConfig::default()).unwrap();
/// assert!(d.right.sustained && d.wrong.sustained);
/// assert_eq!(d.usual, Some(Style::Right));
/// ```
pub fn diagnose(bell: &Bell, cfg: &DiagnoseConfig) -> Result<BellDiagnosis, SimError> {
    diagnose_with_parts(bell, None, cfg)
}

/// Diagnose one bell whose clapper's parts may be known: then the changes
/// offered are to its flight's length, its ball's position and its shaft,
/// not a flight mass at an assumed depth.
pub fn diagnose_with_parts(
    bell: &Bell,
    parts: Option<&ClapperParts>,
    cfg: &DiagnoseConfig,
) -> Result<BellDiagnosis, SimError> {
    bell.validate()?;
    cfg.ringer.validate()?;
    cfg.sim.validate()?;
    let right = outcome(bell, cfg, Style::Right)?;
    let wrong = outcome(bell, cfg, Style::Wrong)?;
    let usual = if right.sustained {
        Some(Style::Right)
    } else if wrong.sustained {
        Some(Style::Wrong)
    } else {
        None
    };
    let mut problems = problems_of(bell, &right, cfg);
    let goes_up = goes_up(bell, cfg)?;
    if goes_up == Settles::Wrong {
        problems.push(Problem::GoesUpWrong);
    }
    let changes = hanger_changes(bell, parts, cfg, &problems);
    let frame = frame_of(bell, cfg, usual.unwrap_or(Style::Right))?;
    Ok(BellDiagnosis {
        position: (bell.r_over_lc(), bell.lb_over_lc()),
        min_theta0_right: min_theta0_right(bell, &cfg.sim),
        margin: usual.map(|s| margin(bell, cfg, s)),
        right,
        wrong,
        usual,
        problems,
        goes_up,
        changes,
        frame,
    })
}

/// Loads on the frame over a stroke of `style` from +θ0; for a bell hung
/// out of true, the larger over that stroke and the backstroke of the
/// style from −θ0, so that a bell and its mirror image bear alike.
fn frame_of(bell: &Bell, cfg: &DiagnoseConfig, style: Style) -> Result<Option<FramePeaks>, SimError> {
    let peaks = |theta0: f64| -> Result<Option<FramePeaks>, SimError> {
        let mut rec = TraceRecorder::new(1e-3);
        let start = StrokeStart::at_rest(bell, &cfg.sim, 0.0, theta0, style.side(theta0));
        run_stroke(bell, &cfg.sim, start, &mut rec)?;
        Ok(frame_peaks(&Dynamics::new(bell), &rec.samples))
    };
    let hand = peaks(cfg.sim.theta0)?;
    if bell.hanging.is_ideal() {
        return Ok(hand);
    }
    Ok(match (hand, peaks(-cfg.sim.theta0)?) {
        (Some(h), Some(b)) => Some(FramePeaks {
            weight: h.weight,
            horizontal: h.horizontal.max(b.horizontal),
            vertical_down: h.vertical_down.max(b.vertical_down),
            vertical_min: h.vertical_min.min(b.vertical_min),
        }),
        (h, b) => h.or(b),
    })
}

/// Why a bell of a ring stands apart from the others.
#[derive(Clone, Debug, PartialEq)]
pub struct Outlier {
    /// Index of the bell in the ring.
    pub index: usize,
    /// Reasons, in words.
    pub reasons: Vec<String>,
}

/// A number read off a diagnosis, for comparing bells of a ring.
type Measure = Box<dyn Fn(&BellDiagnosis) -> Option<f64>>;

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n == 0 {
        f64::NAN
    } else if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// Bells of a ring that stand apart: a robust z-score (median and scaled
/// median absolute deviation, floored so that a tight ring does not flag
/// tiny differences) above 3.5 in r/L_c, L_b/L_c or first strike angle, or a
/// verdict unlike most of the ring. Needs at least 4 bells.
pub fn ring_outliers(ring: &[BellDiagnosis]) -> Vec<Outlier> {
    if ring.len() < 4 {
        return vec![];
    }
    let measures: [(&str, f64, Measure); 3] = [
        ("r/L_c", 0.05, Box::new(|d| Some(d.position.0))),
        ("L_b/L_c", 0.05, Box::new(|d| Some(d.position.1))),
        (
            "first strike angle",
            5f64.to_radians(),
            Box::new(|d| d.usual_outcome().and_then(|o| o.strike_theta)),
        ),
    ];
    let mut out: Vec<Outlier> = (0..ring.len())
        .map(|index| Outlier { index, reasons: vec![] })
        .collect();
    for (name, floor, f) in &measures {
        let vals: Vec<f64> = ring.iter().filter_map(f).collect();
        if vals.len() < 4 {
            continue;
        }
        let med = median(vals.clone());
        let mad = (1.4826 * median(vals.iter().map(|v| (v - med).abs()).collect())).max(*floor);
        for (k, d) in ring.iter().enumerate() {
            if let Some(v) = f(d) {
                let z = (v - med) / mad;
                if z.abs() > 3.5 {
                    let shown = if *name == "first strike angle" {
                        v.to_degrees()
                    } else {
                        v
                    };
                    let med_shown = if *name == "first strike angle" {
                        med.to_degrees()
                    } else {
                        med
                    };
                    out[k].reasons.push(format!(
                        "{name} {shown:.3} against a ring median of {med_shown:.3} (robust z = {z:.1})"
                    ));
                }
            }
        }
    }
    let verdict = |d: &BellDiagnosis| (d.right.sustained, d.wrong.sustained);
    let mut counts: Vec<((bool, bool), usize)> = vec![];
    for d in ring {
        match counts.iter_mut().find(|(v, _)| *v == verdict(d)) {
            Some((_, n)) => *n += 1,
            None => counts.push((verdict(d), 1)),
        }
    }
    if let Some(&(common, n)) = counts.iter().max_by_key(|(_, n)| *n) {
        if 2 * n > ring.len() {
            for (k, d) in ring.iter().enumerate() {
                if verdict(d) != common {
                    out[k].reasons.push("rings differently from most of the ring".into());
                }
            }
        }
    }
    out.into_iter().filter(|o| !o.reasons.is_empty()).collect()
}

/// What brings an odd-struck bell's handstroke and backstroke together
/// (docs/model.md §10.3): its odd-struckness, how it moves per millimetre
/// at the ball and at the clapper pivot, and the move of each that brings
/// it under the tolerance, checked by simulation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OddStruckFix {
    /// Odd-struckness now (s), handstroke minus backstroke.
    pub odd_struck: f64,
    /// Its change per metre the ball moves toward the back side with the
    /// pivot left where it is (s/m): the ball's gaps change, the pivot not.
    pub per_ball_shift: f64,
    /// The ball move toward the back side (m) that brings it under the
    /// tolerance, and the odd-struckness after it (s); `None` if Newton's
    /// method did not get there in four steps.
    pub ball_shift: Option<(f64, f64)>,
    /// Its change per metre the clapper pivot moves toward the back side
    /// (the ball moves with it, so the gaps change too) (s/m).
    pub per_pivot_shift: f64,
    /// The pivot move (m) and the odd-struckness after it (s).
    pub pivot_shift: Option<(f64, f64)>,
}

/// Find the moves that make `bell` (ringing right under `cfg`) strike
/// evenly to within `tolerance` (s), for a ball `ball_below_pivot` (m)
/// below the clapper pivot. `None` if the bell does not strike at both
/// strokes.
pub fn odd_struck_fix(
    bell: &Bell,
    cfg: &SimConfig,
    ball_below_pivot: f64,
    tolerance: f64,
) -> Result<Option<OddStruckFix>, SimError> {
    odd_struck_fix_in(bell, cfg, Style::Right, ball_below_pivot, tolerance)
}

/// [`odd_struck_fix`] for a bell ringing in `style` (a bell that rings
/// only wrong is odd-struck in that style). `None` unless both strokes
/// strike and keep the style, now and after each move tried.
pub fn odd_struck_fix_in(
    bell: &Bell,
    cfg: &SimConfig,
    style: Style,
    ball_below_pivot: f64,
    tolerance: f64,
) -> Result<Option<OddStruckFix>, SimError> {
    use crate::hanging::Hanging;
    use crate::ringing::odd_struck;
    let per_m_skew = 1.0 / (ball_below_pivot * bell.phi_max.cos());
    let h0 = bell.hanging;
    // Odd-struckness (s) after moving the ball by x (m) and the pivot by p (m).
    let odd = |x: f64, p: f64| -> Result<Option<f64>, SimError> {
        let moved = bell.with_hanging(Hanging {
            pivot_offset: h0.pivot_offset + p,
            phi_max_skew: h0.phi_max_skew + (x + p) * per_m_skew,
            ..h0
        });
        // A move no bell can take (a contact angle past 0 or 90 deg, as a
        // Newton step from a steep slope asks) is no fix, not an error.
        if moved.validate().is_err() {
            return Ok(None);
        }
        Ok(odd_struck(&moved, cfg, style)?.odd_struck())
    };
    let Some(now) = odd(0.0, 0.0)? else { return Ok(None) };
    // Sensitivities by central differences over half a millimetre.
    let step = 5e-4;
    let slope = |f: &dyn Fn(f64) -> Result<Option<f64>, SimError>| -> Result<Option<f64>, SimError> {
        Ok(match (f(step)?, f(-step)?) {
            (Some(a), Some(b)) => Some((a - b) / (2.0 * step)),
            _ => None,
        })
    };
    let ball = |x: f64| odd(x, 0.0);
    let pivot = |p: f64| odd(0.0, p);
    let (Some(per_ball), Some(per_pivot)) = (slope(&ball)?, slope(&pivot)?) else {
        return Ok(None);
    };
    // Newton's method from the sensitivity, at most four steps.
    let solve = |f: &dyn Fn(f64) -> Result<Option<f64>, SimError>, k: f64| -> Result<Option<(f64, f64)>, SimError> {
        let (mut x, mut v) = (0.0, now);
        for _ in 0..4 {
            if v.abs() <= tolerance {
                return Ok(Some((x, v)));
            }
            if k == 0.0 || !k.is_finite() {
                return Ok(None);
            }
            x -= v / k;
            match f(x)? {
                Some(nv) => v = nv,
                None => return Ok(None),
            }
        }
        Ok((v.abs() <= tolerance).then_some((x, v)))
    };
    Ok(Some(OddStruckFix {
        odd_struck: now,
        per_ball_shift: per_ball,
        ball_shift: solve(&ball, per_ball)?,
        per_pivot_shift: per_pivot,
        pivot_shift: solve(&pivot, per_pivot)?,
    }))
}
