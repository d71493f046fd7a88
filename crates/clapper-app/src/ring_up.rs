//! Ringing a bell up or down (`clapper ring-up`, `clapper ring-down`): the
//! request, the report (`--json`) and its summary in words.

use std::fmt::Write as _;

use clapper_core::ringer::{
    pull_margin, ring_down, ring_up, Ending, PullMargin, PullPhase, RingerConfig, RingingUpDown, Settles,
};
use clapper_core::stroke::EndReason;
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
    /// The swing's duration (s).
    pub duration_s: f64,
    /// Ringing up, the swing that set the bell (its pull eased; not judged).
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub sets: bool,
}

/// The rope forces over which the verdict holds.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MarginReport {
    /// The force used (N).
    pub force_n: f64,
    /// The least force tried at which the verdict holds (N).
    pub holds_from_n: f64,
    /// The greatest (N).
    pub holds_to_n: f64,
    /// The force below at which it changes, if within those tried (N).
    pub changes_below_n: Option<f64>,
    /// The force above at which it changes (N).
    pub changes_above_n: Option<f64>,
    /// Whether it changes within 1 % of the force: a knife-edge verdict,
    /// which a 1e-6 change of the bell may change too.
    pub knife_edge: bool,
}

impl From<PullMargin> for MarginReport {
    fn from(m: PullMargin) -> Self {
        let near = |f: Option<f64>| f.is_some_and(|f| (f / m.force - 1.0).abs() <= 0.01 + 1e-12);
        Self {
            force_n: m.force,
            holds_from_n: m.low,
            holds_to_n: m.high,
            changes_below_n: m.flips_below,
            changes_above_n: m.flips_above,
            knife_edge: near(m.flips_below) || near(m.flips_above),
        }
    }
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
    /// Whether it was set at the balance (up) or came down (down).
    pub finished: bool,
    /// How it ended: "set" (up: set at the balance, on the stay), "down",
    /// or "not set" / "not down" (`why_not` says why).
    pub ended: &'static str,
    /// Set: where the bell rests on the stay (deg from the bottom the way
    /// it came up; past 180).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub set_at_deg: Option<f64>,
    /// Set: how fast it went over the balance (rad/s).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub over_balance_rad_s: Option<f64>,
    /// Set: the eased rope force of the last swing (N).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub eased_pull_force_n: Option<f64>,
    /// Not finished: why.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub why_not: Option<String>,
    /// The swings the verdict is judged from (up and set: those before
    /// the swing that set it).
    pub judged_swings: usize,
    /// Whether the verdict rests on the last swing: without the last
    /// striking swing judged, or with the swing that set the bell, it
    /// would differ.
    pub rests_on_last_swing: bool,
    /// The rope forces over which the verdict holds, if asked for.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pull_margin: Option<MarginReport>,
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
        let (ended, why_not) = match r.ending {
            Ending::Set { .. } => ("set", None),
            Ending::Down => ("down", None),
            Ending::SwingsRanOut if up => (
                "not set",
                Some(format!(
                    "the pull did not bring it to the balance in {} swings: too weak for the bell's losses, raise it with --pull-force",
                    r.swings.len()
                )),
            ),
            Ending::SwingsRanOut => ("not down", Some(format!("not down within {} swings", r.swings.len()))),
            Ending::Stopped(e) => (
                if up { "not set" } else { "not down" },
                Some(
                    match e {
                        EndReason::OverTheBalance => "a swing went over the balance",
                        EndReason::Held => "friction held the bell",
                        EndReason::TimeLimit => "a swing ran out of time",
                        EndReason::TurningPoint => "a swing stopped",
                    }
                    .to_string(),
                ),
            ),
        };
        let set = match r.ending {
            Ending::Set { angle, rate, torque } => Some((angle, rate, torque)),
            _ => None,
        };
        let n = r.swings.len();
        Self {
            bell: bell.to_string(),
            direction: if up { "up" } else { "down" },
            goes_up: up.then_some(settles),
            goes_down: (!up).then_some(settles),
            turns_right_at_deg,
            changes,
            finished: r.finished,
            ended,
            set_at_deg: set.map(|s| s.0.to_degrees()),
            over_balance_rad_s: set.map(|s| s.1),
            eased_pull_force_n: set.map(|s| s.2 / ringer.wheel_radius),
            why_not,
            judged_swings: r.judged().len(),
            rests_on_last_swing: r.rests_on_last_swing(),
            pull_margin: None,
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
                    duration_s: s.duration,
                    sets: set.is_some() && s.number == n,
                })
                .collect(),
        }
    }
}

/// The strongest rope force taken as given (N).
const MAX_GIVEN_PULL_N: f64 = 10_000.0;

/// Ring the request's bell up (`up`) or down with `ringer`; the request's
/// style, θ0, strokes and protocol are not used.
pub fn ring(
    req: &SimulateRequest,
    file: Option<LoadedBell>,
    ringer: &RingerConfig,
    up: bool,
) -> Result<RingReport, AppError> {
    // The pull given, not the ones the margin tries about it nor the one
    // calibrated on the swings (a bell raised in two swings needs tens of kN).
    if let Some(f) = ringer.pull_force.filter(|&f| f > MAX_GIVEN_PULL_N) {
        return Err(clapper_core::bell::ParamError {
            field: "pull_force_n",
            value: f,
            allowed: "a rope's pull at most 10000 N (a ringer's is well under 1000 N)",
        }
        .into());
    }
    let bell = req.bell(file)?;
    let cfg = req.config_for(&bell)?;
    let r = if up {
        ring_up(&bell.bell, &cfg, ringer, &mut ())?
    } else {
        ring_down(&bell.bell, &cfg, ringer, &mut ())?
    };
    let mut report = RingReport::new(&bell.name, &r, ringer);
    let phase = if up { PullPhase::Raise } else { PullPhase::Check };
    report.pull_margin = Some(pull_margin(&bell.bell, &cfg, ringer, phase)?.into());
    Ok(report)
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
        let sets = if s.sets {
            "  (sets it: the pull eased, over the balance onto the stay)"
        } else {
            ""
        };
        let _ = writeln!(o, "  {:>5}  {:>13.1}  {strike}{sets}", s.number, s.amplitude_deg);
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
    if let Some(why) = &r.why_not {
        let _ = write!(
            line,
            "; {} ({why})",
            if r.direction == "up" { "not set" } else { "not down" }
        );
    }
    let _ = writeln!(o, "{line}");
    for c in &r.changes {
        let _ = writeln!(o, "  changes from {} to {} at {:.0} deg", c.from, c.to, c.amplitude_deg);
    }
    if let (Some(at), Some(rate), Some(f)) = (r.set_at_deg, r.over_balance_rad_s, r.eased_pull_force_n) {
        let _ = writeln!(
            o,
            "  set at the balance: the last pull eased to {f:.0} N, over the balance at {rate:.3} rad/s, at rest on the stay at {at:.1} deg; judged from the {} swings before",
            r.judged_swings
        );
    }
    if r.rests_on_last_swing {
        let _ = writeln!(
            o,
            "  the verdict rests on the last swing: without its last striking swing, or with the swing that set it, it would differ"
        );
    }
    if let Some(m) = &r.pull_margin {
        let _ = writeln!(o, "{}", margin_line(m));
    }
    o
}

/// The fewest decimals, from `min`, at which the distinct numbers of
/// `vals` print apart (at most 12): 15.6364 N and 15.6349 N both printed
/// as 15.64 N.
fn decimals_apart(vals: &[f64], min: usize) -> usize {
    (min..=12)
        .find(|&d| {
            vals.iter()
                .all(|a| vals.iter().all(|b| a == b || format!("{a:.d$}") != format!("{b:.d$}")))
        })
        .unwrap_or(12)
}

/// The line on how far the pull may change before the verdict does, its
/// numbers printed to as many decimals as tell them apart.
fn margin_line(m: &MarginReport) -> String {
    let pct = |f: f64| 100.0 * (f / m.force_n - 1.0);
    let forces: Vec<f64> = [
        Some(m.force_n),
        Some(m.holds_from_n),
        Some(m.holds_to_n),
        m.changes_below_n,
        m.changes_above_n,
    ]
    .into_iter()
    .flatten()
    .collect();
    let d = decimals_apart(&forces, 2);
    // The pull itself is 0 %: any other force's percentage prints apart from it.
    let pcts: Vec<f64> = forces.iter().map(|f| pct(*f)).chain([0.0]).collect();
    let dp = decimals_apart(&pcts, 2);
    let mut l = if m.holds_from_n == m.holds_to_n {
        format!("  the verdict holds only at the pull used, {:.d$} N", m.force_n)
    } else {
        format!(
            "  the verdict holds for rope forces from {:.d$} N to {:.d$} N ({:+.dp$} % to {:+.dp$} % of the pull)",
            m.holds_from_n,
            m.holds_to_n,
            pct(m.holds_from_n),
            pct(m.holds_to_n)
        )
    };
    let flips: Vec<String> = [m.changes_below_n, m.changes_above_n]
        .iter()
        .flatten()
        .map(|f| format!("{f:.d$} N ({:+.dp$} %)", pct(*f)))
        .collect();
    if !flips.is_empty() {
        let _ = write!(l, "; it changes at {}", flips.join(" and "));
    }
    if m.knife_edge {
        l += ": a knife-edge verdict (a change of the bell as small as 1e-6 may change it)";
    }
    l
}
