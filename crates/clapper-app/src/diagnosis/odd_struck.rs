//! The odd-struckness part of a diagnosis: how odd-struck a bell is in the
//! style it rings steadily, and what evens it (docs/model.md §10.3).

use clapper_core::prelude::*;

use super::report::OddStruckReport;
use crate::AppError;

/// What the odd-struckness part of a diagnosis needs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OddStruckOptions {
    /// The ball's centre below the clapper pivot (m); unset: the clapper's
    /// equivalent pendulum length L_c (its centre of percussion, where a
    /// ball strikes without jarring the pivot), an estimate.
    pub ball_below_pivot_m: Option<f64>,
    /// The aim (ms). Default 1 ms: the tape guidance's 1 mm of gap moves a
    /// bell's strike by a few ms, and a listener hears 10 to 20 ms.
    pub tolerance_ms: f64,
}

impl Default for OddStruckOptions {
    fn default() -> Self {
        Self {
            ball_below_pivot_m: None,
            tolerance_ms: 1.0,
        }
    }
}

/// Why a bell that sustains neither style has no odd-struckness: each
/// style's reason ([`clapper_core::ringing::NoOddStruck`]).
fn undefined_reason(bell: &Bell, cfg: &SimConfig) -> Result<String, AppError> {
    let why = |style: Style| -> Result<String, AppError> {
        let pair = clapper_core::ringing::odd_struck(bell, cfg, style)?;
        Ok(match clapper_core::ringing::odd_struck_of(&pair.hand, &pair.back) {
            Err(e) => format!("ringing {}, {e}", style.name()),
            Ok(_) => format!("ringing {}, the style is not sustained", style.name()),
        })
    };
    Ok(format!(
        "the bell sustains neither style: {}; {}",
        why(Style::Right)?,
        why(Style::Wrong)?
    ))
}

/// The odd-struckness of a bell whose hanging is not ideal, in `usual`,
/// the style it rings steadily (`None`: it sustains neither, and the
/// report says why, with no advice); `None` for an ideal hanging.
pub(super) fn odd_struck_report(
    bell: &Bell,
    usual: Option<Style>,
    opts: &OddStruckOptions,
) -> Result<Option<OddStruckReport>, AppError> {
    let h = &bell.hanging;
    if h.pivot_offset == 0.0 && h.phi_max_skew == 0.0 {
        return Ok(None);
    }
    let ball = opts.ball_below_pivot_m.unwrap_or_else(|| bell.lc());
    let cfg = SimConfig::default();
    let ms = |s: f64| s * 1e3;
    let mut rep = OddStruckReport {
        style: usual.map(Style::name),
        odd_struck_ms: None,
        odd_struck_undefined: None,
        tolerance_ms: opts.tolerance_ms,
        ball_below_pivot_m: ball,
        ms_per_mm_at_ball: None,
        ball_move_mm: None,
        after_ball_move_ms: None,
        ms_per_mm_at_pivot: None,
        pivot_move_mm: None,
        after_pivot_move_ms: None,
        words: String::new(),
    };
    let Some(style) = usual else {
        let why = undefined_reason(bell, &cfg)?;
        rep.words = format!("odd-struck: not defined ({why}: it compares strokes of one style)");
        rep.odd_struck_undefined = Some(why);
        return Ok(Some(rep));
    };
    let pair = clapper_core::ringing::odd_struck(bell, &cfg, style)?;
    let now = match clapper_core::ringing::odd_struck_of(&pair.hand, &pair.back) {
        Ok(t) => ms(t),
        Err(e) => {
            // The usual style is sustained, so both strokes strike and keep
            // it; said all the same should that ever fail.
            rep.words = format!("odd-struck: not defined ({e}: it compares strokes of one style)");
            rep.odd_struck_undefined = Some(e.to_string());
            return Ok(Some(rep));
        }
    };
    rep.odd_struck_ms = Some(now);
    let ringing = match style {
        Style::Right => String::new(),
        Style::Wrong => ", ringing wrong, the style it sustains".into(),
    };
    let fix = clapper_core::diagnose::odd_struck_fix_in(bell, &cfg, style, ball, opts.tolerance_ms * 1e-3)?;
    let Some(fix) = fix else {
        rep.words = format!(
            "odd-struck by {} ({}){ringing}; no advice: half a millimetre's move of the ball or the pivot loses the style",
            crate::simulate::odd_struck_ms_text(now),
            crate::simulate::which_stroke_late(now),
        );
        return Ok(Some(rep));
    };
    rep.words = fix_words(now, &fix, &ringing, opts.tolerance_ms);
    rep.ms_per_mm_at_ball = Some(fix.per_ball_shift);
    rep.ball_move_mm = fix.ball_shift.map(|(x, _)| x * 1e3);
    rep.after_ball_move_ms = fix.ball_shift.map(|(_, v)| ms(v));
    rep.ms_per_mm_at_pivot = Some(fix.per_pivot_shift);
    rep.pivot_move_mm = fix.pivot_shift.map(|(p, _)| p * 1e3);
    rep.after_pivot_move_ms = fix.pivot_shift.map(|(_, v)| ms(v));
    Ok(Some(rep))
}

/// The odd-struckness `now` (ms) and its cure in words.
fn fix_words(now: f64, fix: &clapper_core::diagnose::OddStruckFix, ringing: &str, tolerance_ms: f64) -> String {
    let ms = |s: f64| s * 1e3;
    let side = |x: f64| {
        if x > 0.0 {
            "toward the back side"
        } else {
            "toward the hand side"
        }
    };
    let mut words = format!(
        "odd-struck by {} ({}){ringing}; {:+.2} ms per mm at the ball, {:+.2} ms per mm at the pivot",
        crate::simulate::odd_struck_ms_text(now),
        crate::simulate::which_stroke_late(now),
        // s per m is ms per mm.
        fix.per_ball_shift,
        fix.per_pivot_shift
    );
    if now.abs() <= tolerance_ms {
        words += &format!("; within {tolerance_ms} ms already");
    } else {
        if let Some((x, after)) = fix.ball_shift {
            words += &format!(
                "; move the ball {:.1} mm {} (its gaps change by {:.1} mm each) to bring it to {:+.2} ms",
                x.abs() * 1e3,
                side(x),
                x.abs() * 1e3,
                ms(after)
            );
        }
        if let Some((p, after)) = fix.pivot_shift {
            words += &format!(
                "; or move the clapper pivot {:.1} mm {} ({:+.2} ms)",
                p.abs() * 1e3,
                side(p),
                ms(after)
            );
        }
    }
    words
}
