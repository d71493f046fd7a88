//! A bell's verdicts for a hanger, which the diagnosis and the search for
//! clapper changes both judge by: how it strikes in each style fully up,
//! what is wrong with it, and how far it is from losing its style along
//! the changes a hanger can make (clapper period, r).

use rayon::prelude::*;

use crate::bell::{length_of_period, Bell, ParamError};
use crate::ringer::RingerConfig;
use crate::ringing::first_stroke;
use crate::stroke::{run_stroke, SimConfig, SimError, Stroke, StrokeStart, Style};

/// Thresholds and search ranges of a diagnosis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DiagnoseConfig {
    /// The simulation settings for the verdict (θ0 171 deg, R 0.2, impact).
    pub sim: SimConfig,
    /// The restitutions for which D is reported. The paper's 0.05, 0.1, 0.2.
    pub d_restitutions: [f64; 3],
    /// A first strike later than this bell angle (rad, ringing right from +θ0)
    /// is "late, near the top of the swing". Default −150 deg: the Fig 9(d)
    /// bell (−158 deg) is late, the lab bell (−95 deg) is not.
    pub late_strike: f64,
    /// A strike velocity below this many times the bell's small-swing angular
    /// frequency 2π/T_b is "quiet". Default 0.2: the chart's strikes range
    /// from about 0.2 to 1.3 of it (the lab bell: 0.24; Fig 9(c): 1.1).
    pub quiet_ratio: f64,
    /// D above this at R = 0.1 is "likely to double strike". Default 10,
    /// the level at which all the paper's listeners heard a double strike.
    pub double_strike_limit: f64,
    /// Largest change of clapper period considered (s). Default 0.4 s.
    pub max_dtc: f64,
    /// Largest change of r considered (m). Default 0.15 m.
    pub max_dr: f64,
    /// The ringer who rings it up, for "goes up right" (the ringer's
    /// defaults: 30 swings to the stay).
    pub ringer: RingerConfig,
}

impl Default for DiagnoseConfig {
    fn default() -> Self {
        Self {
            sim: SimConfig::default(),
            d_restitutions: [0.05, 0.1, 0.2],
            late_strike: (-150f64).to_radians(),
            quiet_ratio: 0.2,
            double_strike_limit: 10.0,
            max_dtc: 0.4,
            max_dr: 0.15,
            ringer: RingerConfig::default(),
        }
    }
}

/// The bell with its clapper period changed by `dtc` (s) and r by `dr` (m):
/// the clapper's mass and b are kept, its inertia follows the new period
/// (I_c = m b L_c); the hanging (offset, angles, friction) is kept.
pub fn adjusted(bell: &Bell, dtc: f64, dr: f64) -> Result<Bell, ParamError> {
    let tc = bell.tc() + dtc;
    if !(tc.is_finite() && tc > 0.0) {
        return Err(ParamError {
            field: "clapper_period_s",
            value: tc,
            allowed: "a finite number > 0",
        });
    }
    let lc = length_of_period(tc);
    Bell::new(
        bell.bell_mass,
        bell.clapper_mass,
        bell.a,
        bell.b,
        bell.bell_inertia,
        bell.clapper_mass * bell.b * lc,
        bell.r + dr,
        bell.phi_max,
    )
    .map(|b| b.with_hanging(bell.hanging))
}

/// How a bell strikes in one style.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StyleOutcome {
    /// Sustained when fully up, in steady ringing: the handstroke and the
    /// backstroke after it both keep the style.
    pub sustained: bool,
    /// θ at the first strike (rad), handstroke.
    pub strike_theta: Option<f64>,
    /// φ' before the first strike (rad/s), handstroke.
    pub strike_phidot: Option<f64>,
    /// Lift-off angle (rad), handstroke.
    pub liftoff_theta: Option<f64>,
    /// D at each of [`DiagnoseConfig::d_restitutions`], handstroke.
    pub double_strike_index: [Option<f64>; 3],
    /// The backstroke of steady ringing in this style (from rest at −θ0,
    /// the clapper on the style's side), when the style is sustained: its
    /// angles and rates in its own sign (a right backstroke strikes at
    /// θ > 0). A bell with an ideal hanging is its own mirror image: its
    /// backstroke is the handstroke mirrored, and is not rung. A bell and
    /// its mirror image swap handstroke and backstroke.
    pub back: Option<StrokeFigures>,
}

/// What a verdict reads off one stroke.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StrokeFigures {
    /// θ at the first strike (rad).
    pub strike_theta: Option<f64>,
    /// φ' before the first strike (rad/s).
    pub strike_phidot: Option<f64>,
    /// Lift-off angle (rad).
    pub liftoff_theta: Option<f64>,
    /// D at each of [`DiagnoseConfig::d_restitutions`].
    pub double_strike_index: [Option<f64>; 3],
}

impl StrokeFigures {
    /// The same stroke seen in the mirror (angles and rates negated).
    pub fn mirrored(&self) -> Self {
        Self {
            strike_theta: self.strike_theta.map(|t| -t),
            strike_phidot: self.strike_phidot.map(|v| -v),
            liftoff_theta: self.liftoff_theta.map(|t| -t),
            double_strike_index: self.double_strike_index,
        }
    }
}

impl StyleOutcome {
    /// The handstroke's figures.
    pub fn hand(&self) -> StrokeFigures {
        StrokeFigures {
            strike_theta: self.strike_theta,
            strike_phidot: self.strike_phidot,
            liftoff_theta: self.liftoff_theta,
            double_strike_index: self.double_strike_index,
        }
    }

    /// The handstroke, and the backstroke seen in the mirror (so both read
    /// as handstrokes from +θ0): what a problem is judged over.
    fn strokes_as_hand(&self) -> impl Iterator<Item = StrokeFigures> {
        std::iter::once(self.hand()).chain(self.back.map(|b| b.mirrored()))
    }
}

/// Something a hanger would want changed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Problem {
    /// Cannot sustain ringing right when fully up.
    CannotRingRight,
    /// Strikes late, near the top of the swing.
    LateStrike,
    /// Strikes softly.
    Quiet,
    /// D at R = 0.1 above the limit.
    DoubleStrike,
    /// Rung up from rest, it settles striking wrong.
    GoesUpWrong,
}

/// How far a bell is from losing its usual style, per hanger change.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Margin {
    /// Nearest edge on the chart, over the four changes below (chart units).
    pub chart_units: Option<f64>,
    /// Clapper period shorter by this much loses the style (s).
    pub tc_down: Option<f64>,
    /// Clapper period longer by this much loses the style (s).
    pub tc_up: Option<f64>,
    /// r smaller by this much loses the style (m).
    pub r_down: Option<f64>,
    /// r larger by this much loses the style (m).
    pub r_up: Option<f64>,
}

/// The backstroke of steady ringing in `style`: from rest at −θ0 with the
/// clapper on the style's side (where a handstroke that keeps the style
/// leaves it), on its own clock.
fn back_in_style(bell: &Bell, cfg: &SimConfig, style: Style) -> Result<Stroke, SimError> {
    let start = StrokeStart::at_rest(bell, cfg, 0.0, -cfg.theta0, style.side(-cfg.theta0));
    run_stroke(bell, cfg, start, &mut ())
}

pub(crate) fn outcome(bell: &Bell, cfg: &DiagnoseConfig, style: Style) -> Result<StyleOutcome, SimError> {
    let s = first_stroke(bell, &cfg.sim, style)?;
    let ideal = bell.hanging.is_ideal();
    // The verdict of [`crate::ringing::keeps_style`]: a handstroke that
    // keeps the style leaves the clapper on the style's side, so its
    // backstroke is `back_in_style`.
    let back = if s.sustained() && !ideal {
        Some(back_in_style(bell, &cfg.sim, style)?)
    } else {
        None
    };
    let sustained = s.sustained() && (ideal || back.as_ref().is_some_and(Stroke::sustained));
    let mut d = [None; 3];
    let mut back_d = [None; 3];
    for (k, r) in cfg.d_restitutions.iter().enumerate() {
        let sim = SimConfig {
            restitution: *r,
            ..cfg.sim
        };
        d[k] = first_stroke(bell, &sim, style)?.double_strike_index();
        if sustained && !ideal {
            back_d[k] = back_in_style(bell, &sim, style)?.double_strike_index();
        }
    }
    let hand = StrokeFigures {
        strike_theta: s.strike_angle(),
        strike_phidot: s.strike_velocity(),
        liftoff_theta: s.liftoff_angle(),
        double_strike_index: d,
    };
    let back = match back {
        _ if !sustained => None,
        None => Some(hand.mirrored()),
        Some(b) => Some(StrokeFigures {
            strike_theta: b.strike_angle(),
            strike_phidot: b.strike_velocity(),
            liftoff_theta: b.liftoff_angle(),
            double_strike_index: back_d,
        }),
    };
    Ok(StyleOutcome {
        sustained,
        strike_theta: hand.strike_theta,
        strike_phidot: hand.strike_phidot,
        liftoff_theta: hand.liftoff_theta,
        double_strike_index: d,
        back,
    })
}

/// The verdict in steady ringing (both strokes, [`crate::ringing::sustains`]);
/// a stroke that fails does not sustain.
fn sustains(bell: &Bell, cfg: &SimConfig, style: Style) -> bool {
    crate::ringing::sustains(bell, cfg, style).unwrap_or(false)
}

/// Index of R = 0.1 in the configured list (or the middle one).
fn r01_index(cfg: &DiagnoseConfig) -> usize {
    cfg.d_restitutions
        .iter()
        .position(|r| (*r - 0.1).abs() < 1e-12)
        .unwrap_or(1)
}

/// What is wrong with a bell ringing right, judged over both strokes of
/// steady ringing (the worse of the two), so that a bell and its mirror
/// image have the same problems.
pub(crate) fn problems_of(bell: &Bell, right: &StyleOutcome, cfg: &DiagnoseConfig) -> Vec<Problem> {
    if !right.sustained {
        return vec![Problem::CannotRingRight];
    }
    let mut p = vec![];
    let strokes: Vec<StrokeFigures> = right.strokes_as_hand().collect();
    if strokes
        .iter()
        .any(|s| s.strike_theta.is_some_and(|t| t < cfg.late_strike))
    {
        p.push(Problem::LateStrike);
    }
    let omega_b = 2.0 * std::f64::consts::PI / bell.tb();
    if strokes
        .iter()
        .any(|s| s.strike_phidot.is_some_and(|v| v.abs() < cfg.quiet_ratio * omega_b))
    {
        p.push(Problem::Quiet);
    }
    let k = r01_index(cfg);
    if strokes
        .iter()
        .any(|s| s.double_strike_index[k].is_some_and(|d| d > cfg.double_strike_limit))
    {
        p.push(Problem::DoubleStrike);
    }
    p
}

/// Smallest θ0 (rad) from which `bell` still rings right: scan down from
/// `cfg.theta0` in 2 deg steps, then bisect to 0.1 deg.
pub fn min_theta0_right(bell: &Bell, cfg: &SimConfig) -> Option<f64> {
    let rings = |th0: f64| sustains(bell, &SimConfig { theta0: th0, ..*cfg }, Style::Right);
    if !rings(cfg.theta0) {
        return None;
    }
    let step = 2f64.to_radians();
    let mut good = cfg.theta0;
    let mut bad = None;
    while good - step > 1f64.to_radians() {
        let t = good - step;
        if rings(t) {
            good = t;
        } else {
            bad = Some(t);
            break;
        }
    }
    let Some(mut bad) = bad else {
        return Some(good);
    };
    while good - bad > 0.1f64.to_radians() {
        let mid = 0.5 * (good + bad);
        if rings(mid) {
            good = mid;
        } else {
            bad = mid;
        }
    }
    Some(good)
}

/// The smallest change along one hanger direction that loses `style`:
/// coarse steps out to `max`, then bisection.
fn edge_along(
    bell: &Bell,
    cfg: &SimConfig,
    style: Style,
    max: f64,
    steps: usize,
    dir: impl Fn(f64) -> (f64, f64),
) -> Option<f64> {
    let holds = |u: f64| {
        let (dtc, dr) = dir(u);
        adjusted(bell, dtc, dr).is_ok_and(|b| sustains(&b, cfg, style))
    };
    let mut good = 0.0;
    let mut bad = None;
    for k in 1..=steps {
        let u = max * k as f64 / steps as f64;
        if holds(u) {
            good = u;
        } else {
            bad = Some(u);
            break;
        }
    }
    let mut bad = bad?;
    for _ in 0..8 {
        let mid = 0.5 * (good + bad);
        if holds(mid) {
            good = mid;
        } else {
            bad = mid;
        }
    }
    Some(bad)
}

fn chart_distance(a: &Bell, b: &Bell) -> f64 {
    (a.r_over_lc() - b.r_over_lc()).hypot(a.lb_over_lc() - b.lb_over_lc())
}

/// Margin of `style` for `bell`.
pub fn margin(bell: &Bell, cfg: &DiagnoseConfig, style: Style) -> Margin {
    let sim = &cfg.sim;
    let (mt, mr) = (cfg.max_dtc, cfg.max_dr);
    let dirs: [(f64, f64, f64); 4] = [(-1.0, 0.0, mt), (1.0, 0.0, mt), (0.0, -1.0, mr), (0.0, 1.0, mr)];
    let found: Vec<Option<f64>> = dirs
        .par_iter()
        .map(|&(st, sr, max)| edge_along(bell, sim, style, max, 20, |u| (st * u, sr * u)))
        .collect();
    let chart_units = dirs
        .iter()
        .zip(&found)
        .filter_map(|(&(st, sr, _), f)| {
            let u = (*f)?;
            let b = adjusted(bell, st * u, sr * u).ok()?;
            Some(chart_distance(bell, &b))
        })
        .min_by(f64::total_cmp);
    Margin {
        chart_units,
        tc_down: found[0],
        tc_up: found[1],
        r_down: found[2],
        r_up: found[3],
    }
}
