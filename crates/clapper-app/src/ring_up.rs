//! Ringing a bell up or down (`clapper ring-up`, `clapper ring-down`): the
//! request, the report (`--json`) and its summary in words.

use std::fmt::Write as _;

use clapper_core::ringer::{ring_down, ring_up, PullPhase, RingerConfig, RingingUpDown, Settles};
use clapper_core::stroke::Side;
use clapper_io::bell_file::LoadedBell;
use serde::Serialize;

use crate::simulate::SimulateRequest;
use crate::AppError;

/// One swing as reported.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SwingReport {
    /// Counting from 1.
    pub number: usize,
    /// The angle the swing reached (deg).
    pub amplitude_deg: f64,
    /// The side the clapper first struck in it: "+" or "-" (the sign of φ
    /// at the stop), none if it did not strike.
    pub struck_side: Option<&'static str>,
    /// "right" or "wrong" (the struck side leads or trails the bell's
    /// motion), none without a strike.
    pub style: Option<&'static str>,
    /// Time of that strike from the swing's start (s).
    pub strike_t_s: Option<f64>,
    /// Bell angle at that strike (deg).
    pub strike_theta_deg: Option<f64>,
}

/// A change of striking style while ringing up or down.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct StyleChange {
    /// Amplitude of the first swing in the new style (deg).
    pub amplitude_deg: f64,
    /// Style before.
    pub from: &'static str,
    /// Style after.
    pub to: &'static str,
}

/// `clapper ring-up --json` / `clapper ring-down --json`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RingReport {
    /// The bell's name.
    pub bell: String,
    /// "up" or "down".
    pub direction: &'static str,
    /// Ringing up: "right", "wrong" or "no strike": the style of the last
    /// striking swing.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub goes_up: Option<&'static str>,
    /// Ringing down: the same.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub goes_down: Option<&'static str>,
    /// Ringing up and going up right after striking wrong: the amplitude
    /// from which it strikes right (deg).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub turns_right_at_deg: Option<f64>,
    /// Every change of striking style.
    pub changes: Vec<StyleChange>,
    /// Whether it reached the stay (up) or came down (down).
    pub finished: bool,
    /// The rope force (N) and wheel radius (m) used; the torque is their
    /// product.
    pub pull_force_n: f64,
    /// Wheel radius (m).
    pub wheel_radius_m: f64,
    /// Half-width of the pulled part of each swing (deg).
    pub pull_window_deg: f64,
    /// The swings.
    pub swings: Vec<SwingReport>,
}

fn style_name(s: clapper_core::stroke::Style) -> &'static str {
    match s {
        clapper_core::stroke::Style::Right => "right",
        clapper_core::stroke::Style::Wrong => "wrong",
    }
}

pub(crate) fn settles_name(s: Settles) -> &'static str {
    match s {
        Settles::Right => "right",
        Settles::Wrong => "wrong",
        Settles::NoStrike => "no strike",
    }
}

impl RingReport {
    /// The report of `r` for the bell named `bell`.
    pub fn new(bell: &str, r: &RingingUpDown, ringer: &RingerConfig) -> Self {
        let up = r.phase == PullPhase::Raise;
        let settles = settles_name(r.settles());
        let changes: Vec<StyleChange> = r
            .changes()
            .iter()
            .map(|(a, from, to)| StyleChange {
                amplitude_deg: a.to_degrees(),
                from: style_name(*from),
                to: style_name(*to),
            })
            .collect();
        let turns_right_at_deg = (up && r.settles() == Settles::Right)
            .then(|| changes.iter().rev().find(|c| c.to == "right").map(|c| c.amplitude_deg))
            .flatten();
        Self {
            bell: bell.to_string(),
            direction: if up { "up" } else { "down" },
            goes_up: up.then_some(settles),
            goes_down: (!up).then_some(settles),
            turns_right_at_deg,
            changes,
            finished: r.finished,
            pull_force_n: r.pull_force,
            wheel_radius_m: ringer.wheel_radius,
            pull_window_deg: ringer.window.to_degrees(),
            swings: r
                .swings
                .iter()
                .map(|s| SwingReport {
                    number: s.number,
                    amplitude_deg: s.amplitude.to_degrees(),
                    struck_side: s.strike.map(|k| if k.side == Side::Plus { "+" } else { "-" }),
                    style: s.strike.map(|k| style_name(k.style)),
                    strike_t_s: s.strike.map(|k| k.t),
                    strike_theta_deg: s.strike.map(|k| k.theta.to_degrees()),
                })
                .collect(),
        }
    }
}

/// Ring the request's bell up (`up`) or down with `ringer`; the request's
/// style, θ0, strokes and protocol are not used.
pub fn ring(
    req: &SimulateRequest,
    file: Option<LoadedBell>,
    ringer: &RingerConfig,
    up: bool,
) -> Result<RingReport, AppError> {
    let bell = req.bell(file)?;
    let cfg = req.config_for(&bell)?;
    let r = if up {
        ring_up(&bell.bell, &cfg, ringer, &mut ())?
    } else {
        ring_down(&bell.bell, &cfg, ringer, &mut ())?
    };
    Ok(RingReport::new(&bell.name, &r, ringer))
}

/// The report in words: a line a swing, then the verdict.
pub fn summary(r: &RingReport) -> String {
    let mut o = String::new();
    let _ = writeln!(
        o,
        "ringing {} {}: pull {:.0} N on a {:.2} m wheel over {:.0} deg each side of the bottom",
        r.direction, r.bell, r.pull_force_n, r.wheel_radius_m, r.pull_window_deg
    );
    let _ = writeln!(o, "  swing  reaches (deg)  strikes");
    for s in &r.swings {
        let strike = match (s.style, s.strike_theta_deg, s.strike_t_s) {
            (Some(st), Some(th), Some(t)) => format!("{st:<5} at {th:+7.1} deg, {t:.3} s into the swing"),
            _ => "-".into(),
        };
        let _ = writeln!(o, "  {:>5}  {:>13.1}  {strike}", s.number, s.amplitude_deg);
    }
    let verdict = r.goes_up.or(r.goes_down).unwrap_or("no strike");
    let mut line = match (r.direction, verdict) {
        ("up", "no strike") => "verdict: the clapper never strikes while the bell goes up".to_string(),
        ("up", v) => format!("verdict: goes up {v}"),
        (_, "no strike") => "verdict: the clapper never strikes while the bell comes down".to_string(),
        (_, v) => format!("verdict: comes down ringing {v} at the end"),
    };
    if let Some(a) = r.turns_right_at_deg {
        let _ = write!(line, " (strikes wrong at first, right from {a:.0} deg)");
    }
    if !r.finished {
        line += if r.direction == "up" {
            "; it did not reach the stay (pull too weak for the bell's losses: raise --swings' pull with --pull-force)"
        } else {
            "; it did not come down within the swings allowed"
        };
    }
    let _ = writeln!(o, "{line}");
    for c in &r.changes {
        let _ = writeln!(o, "  changes from {} to {} at {:.0} deg", c.from, c.to, c.amplitude_deg);
    }
    o
}
