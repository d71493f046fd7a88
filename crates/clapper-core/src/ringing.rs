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
    /// Whether the bell sustains the style it started in, judged by the first
    /// stroke alone under the restart protocol (its first stroke is the same
    /// under either protocol).
    pub fn sustained(&self) -> bool {
        self.strokes.first().is_some_and(Stroke::sustained)
    }
}

/// The first stroke of `style` from +θ0 (what a chart point needs).
pub fn first_stroke(bell: &Bell, cfg: &SimConfig, style: Style) -> Result<Stroke, SimError> {
    let start = StrokeStart::at_rest(bell, cfg, 0.0, cfg.theta0, style.side(cfg.theta0));
    run_stroke(bell, cfg, start, &mut ())
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
