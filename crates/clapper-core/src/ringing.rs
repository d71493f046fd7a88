//! Strokes in sequence: the restart and free protocols (docs/model.md §4), and the
//! verdict of whether a bell sustains a style.

use crate::bell::Bell;
use crate::stroke::{run_stroke, EndReason, Observer, SimConfig, SimError, Stroke, StrokeStart, Style};

/// How one stroke leads to the next.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
pub enum Protocol {
    /// The ringer restores the swing: every stroke starts from rest at ±θ0,
    /// alternating, with the clapper at rest on the side the previous stroke
    /// left it. Charts and verdicts use this. The default.
    #[default]
    Restart,
    /// Strokes follow one another with no energy input; the swing decays
    /// through impact losses. For time histories.
    Free,
}

/// Several strokes of one bell.
#[derive(Clone, Debug, PartialEq)]
pub struct Ringing {
    /// The style the first stroke started in.
    pub style: Style,
    /// The protocol used.
    pub protocol: Protocol,
    /// The strokes, handstroke first. Fewer than asked if a stroke went over
    /// the balance or ran out of time (nothing sensible follows).
    pub strokes: Vec<Stroke>,
}

impl Ringing {
    /// Whether the strokes rung keep the style they started in: the first
    /// stroke, and under the restart protocol the second too. The bell's
    /// verdict is [`sustains`] (steady ringing, both strokes, whatever the
    /// number of strokes rung).
    pub fn sustained(&self) -> bool {
        let n = match self.protocol {
            Protocol::Restart => 2,
            Protocol::Free => 1,
        };
        !self.strokes.is_empty() && self.strokes.iter().take(n).all(Stroke::sustained)
    }
}

/// The first stroke of `style` from +θ0 (what a chart point needs).
pub fn first_stroke(bell: &Bell, cfg: &SimConfig, style: Style) -> Result<Stroke, SimError> {
    let start = StrokeStart::at_rest(bell, cfg, 0.0, cfg.theta0, style.side(cfg.theta0));
    run_stroke(bell, cfg, start, &mut ())
}

/// The backstroke after `hand` under the restart protocol: from rest at
/// −θ0 with the clapper where the handstroke left it, on its own clock.
pub fn backstroke(bell: &Bell, cfg: &SimConfig, hand: &Stroke) -> Result<Stroke, SimError> {
    let start = StrokeStart::at_rest(bell, cfg, 0.0, -cfg.theta0, hand.end.side());
    run_stroke(bell, cfg, start, &mut ())
}

/// Whether `bell` sustains a style in steady ringing, given its handstroke
/// `hand` in that style from +θ0 (docs/model.md §4): under the restart
/// protocol the style is sustained when the handstroke and the backstroke
/// after it both keep it (the third stroke is then the first again). A
/// bell with no pivot offset and equal contact angles (ideal, or with
/// friction only) is its own mirror image, so its backstroke is the
/// handstroke mirrored, bit for bit, and is not rung; any other bell
/// rings it. A bell and its mirror image (d → −d, the contact angles
/// swapped) get the same verdict: each one's handstroke is the other's
/// backstroke mirrored.
pub fn keeps_style(bell: &Bell, cfg: &SimConfig, hand: &Stroke) -> Result<bool, SimError> {
    if !hand.sustained() {
        return Ok(false);
    }
    if bell.hanging.is_mirror_symmetric() {
        return Ok(true);
    }
    Ok(backstroke(bell, cfg, hand)?.sustained())
}

/// Whether `bell` sustains `style` in steady ringing ([`keeps_style`]):
/// the verdict of `simulate`, `diagnose` and the chart alike.
///
/// ```
/// use clapper_core::{bell::Bell, hanging::Hanging, ringing::sustains, stroke::{SimConfig, Style}};
///
/// let cfg = SimConfig::default();
/// assert!(sustains(&Bell::lab(), &cfg, Style::Right).unwrap());
/// // A bell and its mirror image: one verdict.
/// let off = |d| Bell::lab().with_hanging(Hanging { pivot_offset: d, ..Hanging::default() });
/// assert_eq!(sustains(&off(0.005), &cfg, Style::Right).unwrap(), sustains(&off(-0.005), &cfg, Style::Right).unwrap());
/// ```
pub fn sustains(bell: &Bell, cfg: &SimConfig, style: Style) -> Result<bool, SimError> {
    keeps_style(bell, cfg, &first_stroke(bell, cfg, style)?)
}

/// Odd-struckness: when a bell strikes at handstroke and at backstroke
/// (docs/model.md §10.3).
#[derive(Clone, Debug, PartialEq)]
pub struct OddStruck {
    /// The handstroke, from rest at +θ0 in `style`.
    pub hand: Stroke,
    /// The backstroke, from rest at −θ0 with the clapper where the
    /// handstroke left it (the restart protocol).
    pub back: Stroke,
}

impl OddStruck {
    /// Time from bottom dead centre to the first strike at handstroke and
    /// at backstroke (s), if both strike.
    pub fn bdc_to_strike(&self) -> Option<(f64, f64)> {
        Some((self.hand.bdc_to_strike()?, self.back.bdc_to_strike()?))
    }

    /// Odd-struckness (s): handstroke minus backstroke time from bottom dead
    /// centre to the strike. Positive: the handstroke strikes late.
    /// Exactly 0 for a symmetric bell, exactly antisymmetric under the
    /// mirror (d → −d, or the two contact angles swapped). `None` unless
    /// both strokes strike and keep their style ([`odd_struck_of`]).
    pub fn odd_struck(&self) -> Option<f64> {
        odd_struck_of(&self.hand, &self.back).ok()
    }

    /// Whether the style is sustained in steady ringing: both strokes keep
    /// it ([`keeps_style`]).
    pub fn sustained(&self) -> bool {
        self.hand.sustained() && self.back.sustained()
    }
}

/// Why a handstroke and backstroke have no odd-struckness: it compares
/// the strike times of two strokes of one style, and a right handstroke
/// beside a wrong backstroke is no measure of how evenly a bell strikes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
pub enum NoOddStruck {
    /// The handstroke does not strike.
    #[error("the handstroke does not strike")]
    HandNoStrike,
    /// The handstroke does not sustain its style, so the backstroke
    /// starts in the other one.
    #[error("the handstroke does not sustain its style, so the backstroke rings the other one")]
    HandChangesStyle,
    /// The backstroke does not strike.
    #[error("the backstroke does not strike")]
    BackNoStrike,
    /// The backstroke does not sustain the style.
    #[error("the backstroke does not sustain the style")]
    BackChangesStyle,
}

/// Odd-struckness (s) of `hand` and the `back` after it: handstroke minus
/// backstroke time from bottom dead centre to the first strike, when both
/// strike and both sustain their style (docs/model.md §10.3); else why not.
pub fn odd_struck_of(hand: &Stroke, back: &Stroke) -> Result<f64, NoOddStruck> {
    let h = hand.bdc_to_strike().ok_or(NoOddStruck::HandNoStrike)?;
    if !hand.sustained() {
        return Err(NoOddStruck::HandChangesStyle);
    }
    let b = back.bdc_to_strike().ok_or(NoOddStruck::BackNoStrike)?;
    if !back.sustained() {
        return Err(NoOddStruck::BackChangesStyle);
    }
    Ok(h - b)
}

/// The handstroke and backstroke of `bell` in `style` under the restart
/// protocol, each on its own clock (from t = 0), so that a bell and its
/// mirror image give the same numbers bit for bit.
///
/// ```
/// use clapper_core::{bell::Bell, hanging::Hanging, ringing::odd_struck, stroke::{SimConfig, Style}};
///
/// let cfg = SimConfig::default();
/// assert_eq!(odd_struck(&Bell::lab(), &cfg, Style::Right).unwrap().odd_struck(), Some(0.0));
/// // The clapper pivot 3 mm toward the back side.
/// let bell = Bell::lab().with_hanging(Hanging { pivot_offset: 0.003, ..Hanging::default() });
/// let odd = odd_struck(&bell, &cfg, Style::Right).unwrap().odd_struck().unwrap();
/// assert!(odd != 0.0);
/// ```
pub fn odd_struck(bell: &Bell, cfg: &SimConfig, style: Style) -> Result<OddStruck, SimError> {
    let hand = first_stroke(bell, cfg, style)?;
    let back = backstroke(bell, cfg, &hand)?;
    Ok(OddStruck { hand, back })
}

/// Ring `n_strokes` strokes (at least one) starting in `style` from +θ0.
///
/// ```
/// use clapper_core::{bell::Bell, ringing::{ring, Protocol}, stroke::{SimConfig, Style}};
///
/// let r = ring(&Bell::lab(), &SimConfig::default(), Style::Wrong, Protocol::Restart, 2, &mut ()).unwrap();
/// assert!(r.sustained());
/// assert_eq!(r.strokes.len(), 2);
/// ```
pub fn ring<O: Observer>(
    bell: &Bell,
    cfg: &SimConfig,
    style: Style,
    protocol: Protocol,
    n_strokes: usize,
    observer: &mut O,
) -> Result<Ringing, SimError> {
    bell.validate()?;
    cfg.validate()?;
    let mut strokes: Vec<Stroke> = Vec::with_capacity(n_strokes.max(1));
    let mut start = StrokeStart::at_rest(bell, cfg, 0.0, cfg.theta0, style.side(cfg.theta0));
    for k in 0..n_strokes.max(1) {
        let stroke = run_stroke(bell, cfg, start, observer)?;
        let end = stroke.end;
        strokes.push(stroke);
        if k + 1 == n_strokes.max(1) || end.reason != EndReason::TurningPoint {
            break;
        }
        start = match protocol {
            Protocol::Free => StrokeStart {
                t: end.t,
                y: end.y,
                clapper: end.clapper,
            },
            Protocol::Restart => {
                // Alternate +θ0, −θ0: the ringer restores the swing.
                let theta = if k % 2 == 0 { -cfg.theta0 } else { cfg.theta0 };
                StrokeStart::at_rest(bell, cfg, end.t, theta, end.side())
            }
        };
    }
    Ok(Ringing {
        style,
        protocol,
        strokes,
    })
}
