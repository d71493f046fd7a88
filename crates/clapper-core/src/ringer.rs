//! Ringing a bell up from rest and down again (docs/model.md §11): a
//! ringer's pull on the rope as a torque on the wheel over part of each
//! swing, the strokes one after another with nothing restored between
//! them, and what the clapper does swing by swing: whether the bell **goes
//! up right** (the clapper strikes the leading side, as when rung from the
//! balance) or **goes up wrong**.
//!
//! The pull is a constant torque τ = F R_w (rope force F, wheel radius R_w)
//! while the bell is within `window` of the bottom: on the way down to the
//! bottom in the direction of motion when raising (the ringer pulls as the
//! bell falls), on the way up from it against the motion when checking. A
//! pull on every swing, both ways: the rope's one-way action on the wheel
//! (a ringer pulls the sally at one stroke and the tail end at the other) is
//! not modelled.

use std::f64::consts::PI;

use crate::bell::{Bell, ParamError, G};
use crate::chart::ChartSpec;
use crate::contact::ClapperState;
use crate::stroke::{run_stroke_pulled, EndReason, Observer, Side, SimConfig, SimError, Stroke, StrokeStart, Style};

/// Raising or checking the bell.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
pub enum PullPhase {
    /// With the motion, from `window` before the bottom to the bottom.
    Raise,
    /// Against the motion, from the bottom to `window` past it.
    Check,
}

/// A ringer's pull on the rope, as the stroke sees it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pull {
    /// τ = F R_w (N m), > 0.
    pub torque: f64,
    /// Half-width of the part of the swing pulled over, from the bottom (rad).
    pub window: f64,
    /// Raising or checking.
    pub phase: PullPhase,
}

impl Pull {
    /// Checks the pull is physical.
    pub fn validate(&self) -> Result<(), ParamError> {
        if !(self.torque.is_finite() && self.torque >= 0.0) {
            return Err(ParamError {
                field: "pull_torque_n_m",
                value: self.torque,
                allowed: "a finite torque >= 0",
            });
        }
        if !(self.window.is_finite() && self.window > 0.0 && self.window <= PI) {
            return Err(ParamError {
                field: "pull_window_deg",
                value: self.window.to_degrees(),
                allowed: "between 0 (exclusive) and 180 deg",
            });
        }
        Ok(())
    }
}

/// Default half-width of the pulled part of a swing (deg): a ringer pulls
/// through the lower part of the swing.
pub const DEFAULT_PULL_WINDOW_DEG: f64 = 60.0;
/// Default stay angle (deg): near the balance, where a stay would hold it.
pub const DEFAULT_STAY_DEG: f64 = 175.0;
/// Default angle of "down" (deg): the ringer then lets the bell come to rest.
pub const DEFAULT_DOWN_DEG: f64 = 15.0;

/// How the ringer rings the bell up or down.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct RingerConfig {
    /// Swings (strokes) to take from start to finish (ring-up: from the
    /// first tug to the stay; ring-down: from the balance to `down`). A
    /// ringer takes 10-20 whole pulls (two swings each) to raise a bell;
    /// default 30 swings. Sets the pull unless `pull_force` is given.
    pub swings: usize,
    /// Rope force (N); `None`: the force that takes `swings` swings for the
    /// bell with its clapper tied and no friction (the real bell, with its
    /// clapper's impacts and friction, takes what it takes).
    pub pull_force: Option<f64>,
    /// Wheel radius R_w (m): where the rope acts. Default 0.6 m, a
    /// middling wheel (a wheel's diameter is about 1.5 times the bell's).
    pub wheel_radius: f64,
    /// Half-width of the part of each swing pulled over (rad). Default 60
    /// deg: a ringer pulls through the lower part of the swing.
    pub window: f64,
    /// Ring-up: the bell is set when a swing reaches this angle (rad).
    /// Default 175 deg: near the balance, where a stay would hold it.
    pub stay: f64,
    /// Ring-up: the first tug leaves the bell at rest this far from the
    /// bottom (rad). Default 5 deg.
    pub start: f64,
    /// Ring-down: the bell is down when a swing reaches no further than
    /// this (rad). Default 15 deg: the ringer then lets it come to rest.
    pub down: f64,
}

impl Default for RingerConfig {
    fn default() -> Self {
        Self {
            swings: 30,
            pull_force: None,
            wheel_radius: 0.6,
            window: DEFAULT_PULL_WINDOW_DEG.to_radians(),
            stay: DEFAULT_STAY_DEG.to_radians(),
            start: 5f64.to_radians(),
            down: DEFAULT_DOWN_DEG.to_radians(),
        }
    }
}

impl RingerConfig {
    /// Checks every field is in range.
    pub fn validate(&self) -> Result<(), ParamError> {
        let bad = |field, value, allowed| Err(ParamError { field, value, allowed });
        if !(1..=1000).contains(&self.swings) {
            return bad("swings", self.swings as f64, "1 to 1000 swings");
        }
        if let Some(f) = self.pull_force {
            if !(f.is_finite() && f > 0.0) {
                return bad("pull_force_n", f, "a finite force > 0");
            }
        }
        if !(self.wheel_radius.is_finite() && self.wheel_radius > 0.0) {
            return bad("wheel_radius_m", self.wheel_radius, "a finite radius > 0");
        }
        for (field, v) in [
            ("pull_window_deg", self.window),
            ("stay_deg", self.stay),
            ("start_deg", self.start),
            ("down_deg", self.down),
        ] {
            if !(v.is_finite() && v > 0.0 && v < PI) {
                return bad(field, v.to_degrees(), "between 0 and 180 deg, exclusive");
            }
        }
        if self.start >= self.stay || self.down >= self.stay {
            return bad("stay_deg", self.stay.to_degrees(), "above start_deg and down_deg");
        }
        Ok(())
    }
}

impl RingerConfig {
    /// The pull for `phase` on `bell`: the given force on the wheel, or the
    /// one calibrated on the tied bell to take `swings` swings (raising:
    /// from `start` to `stay`; checking: from `stay` to `down`).
    pub fn pull(&self, bell: &Bell, phase: PullPhase) -> Result<Pull, ParamError> {
        self.validate()?;
        let (from, to) = match phase {
            PullPhase::Raise => (self.start, self.stay),
            PullPhase::Check => (self.stay, self.down),
        };
        let torque = match self.pull_force {
            Some(f) => f * self.wheel_radius,
            None => calibrated_torque(bell, from, to, self.window, phase, self.swings),
        };
        Ok(Pull {
            torque,
            window: self.window,
            phase,
        })
    }
}

/// Gravity stiffness of the bell with its clapper tied at φ = 0 (N m/rad):
/// its energy at amplitude A is K (1 − cos A).
fn tied_stiffness(bell: &Bell) -> f64 {
    (bell.bell_mass * bell.a + bell.clapper_mass * (bell.r + bell.b)) * G
}

/// Amplitude after `n` swings of the tied, frictionless bell from `a0`
/// with pull torque `tau` (rad); π if it would go over.
fn tied_amplitude(k: f64, a0: f64, tau: f64, window: f64, phase: PullPhase, n: usize) -> f64 {
    let mut a = a0;
    for _ in 0..n {
        let e = k * (1.0 - a.cos());
        let e = match phase {
            PullPhase::Raise => e + tau * a.min(window),
            PullPhase::Check => e - tau * a.min(window),
        };
        if e >= 2.0 * k {
            return PI;
        }
        if e <= 0.0 {
            return 0.0;
        }
        a = (1.0 - e / k).acos();
    }
    a
}

/// The pull torque (N m) that takes the tied, frictionless bell from `from`
/// to `to` (rad) in `n` swings, by bisection (monotone in τ).
fn calibrated_torque(bell: &Bell, from: f64, to: f64, window: f64, phase: PullPhase, n: usize) -> f64 {
    let k = tied_stiffness(bell);
    let reached = |tau: f64| {
        let a = tied_amplitude(k, from, tau, window, phase, n);
        match phase {
            PullPhase::Raise => a >= to,
            PullPhase::Check => a <= to,
        }
    };
    // Enough to do it in one swing.
    let mut hi = 2.0 * k * (1.0 - to.cos()).max(1.0 - from.cos()) / from.min(window).min(to.max(from));
    let mut lo = 0.0;
    while !reached(hi) {
        hi *= 2.0;
    }
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if reached(mid) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    hi
}

/// A strike in one swing.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SwingStrike {
    /// Time from the swing's start (s).
    pub t: f64,
    /// Bell angle θ at the strike (rad).
    pub theta: f64,
    /// The side struck.
    pub side: Side,
    /// Right if the struck side leads the bell's motion (as when a bell
    /// rung from the balance strikes ringing right), wrong otherwise.
    pub style: Style,
}

/// One swing (stroke) of ringing up or down.
#[derive(Clone, Debug, PartialEq)]
pub struct Swing {
    /// Counting from 1.
    pub number: usize,
    /// The amplitude it reached: |θ| where it ended (rad).
    pub amplitude: f64,
    /// The clapper's first strike in it, if any.
    pub strike: Option<SwingStrike>,
    /// How it ended.
    pub end: EndReason,
}

/// Which way a bell settles while ringing up or down.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
pub enum Settles {
    /// The last striking swings strike right.
    Right,
    /// They strike wrong.
    Wrong,
    /// No swing strikes.
    NoStrike,
}

/// Ringing up or down, swing by swing.
#[derive(Clone, Debug, PartialEq)]
pub struct RingingUpDown {
    /// Raising or checking.
    pub phase: PullPhase,
    /// The pull used (N m and rad).
    pub pull: Pull,
    /// The rope force (N): τ / R_w.
    pub pull_force: f64,
    /// The swings.
    pub swings: Vec<Swing>,
    /// Whether it finished: set at the stay (up) or down (down).
    pub finished: bool,
    /// The strokes themselves (impacts, bottom, end), one a swing.
    pub strokes: Vec<Stroke>,
}

impl RingingUpDown {
    /// The style of the last striking swing (ringing up: the style it goes
    /// up in; ringing down: the style it comes down in at the end).
    pub fn settles(&self) -> Settles {
        match self.swings.iter().rev().find_map(|s| s.strike) {
            Some(s) if s.style == Style::Right => Settles::Right,
            Some(_) => Settles::Wrong,
            None => Settles::NoStrike,
        }
    }

    /// Where the striking style changes: (the amplitude of the first swing
    /// in the new style (rad), the style before, the style after).
    pub fn changes(&self) -> Vec<(f64, Style, Style)> {
        let mut out = vec![];
        let mut last: Option<Style> = None;
        for s in &self.swings {
            if let Some(st) = s.strike {
                if let Some(prev) = last.filter(|p| *p != st.style) {
                    out.push((s.amplitude, prev, st.style));
                }
                last = Some(st.style);
            }
        }
        out
    }
}

fn swing_of(number: usize, stroke: &Stroke) -> Swing {
    // The bell moves from the side it started on toward the other.
    let motion = -stroke.start.y[0].signum();
    Swing {
        number,
        amplitude: stroke.end.y[0].abs(),
        strike: stroke.first_strike().map(|i| SwingStrike {
            t: i.t - stroke.start.t,
            theta: i.theta,
            side: i.side,
            style: if i.side.sign() == motion {
                Style::Right
            } else {
                Style::Wrong
            },
        }),
        end: stroke.end.reason,
    }
}

/// Strokes one after another under `pull` from `start`, until `done` says
/// the last swing finished it or the swings run out (at most 4 × the
/// asked number + 20: a bound, not a target).
fn ring<O: Observer>(
    bell: &Bell,
    cfg: &SimConfig,
    ringer: &RingerConfig,
    pull: Pull,
    mut start: StrokeStart,
    done: impl Fn(&Swing) -> bool,
    observer: &mut O,
) -> Result<RingingUpDown, SimError> {
    let mut swings = vec![];
    let mut strokes = vec![];
    let mut finished = false;
    for number in 1..=4 * ringer.swings + 20 {
        let stroke = run_stroke_pulled(bell, cfg, start, Some(pull), observer)?;
        let swing = swing_of(number, &stroke);
        let end = swing.end;
        finished = done(&swing);
        swings.push(swing);
        start = StrokeStart {
            t: stroke.end.t,
            y: stroke.end.y,
            clapper: stroke.end.clapper,
        };
        strokes.push(stroke);
        if finished || end != EndReason::TurningPoint {
            break;
        }
    }
    Ok(RingingUpDown {
        phase: pull.phase,
        pull,
        pull_force: pull.torque / ringer.wheel_radius,
        swings,
        finished,
        strokes,
    })
}

/// Ring `bell` up from rest: the first tug leaves it at `ringer.start`
/// with the clapper hanging, and each swing the ringer pulls with it until
/// a swing reaches the stay (or goes over the balance, where the stay
/// catches it).
///
/// ```
/// use clapper_core::{bell::Bell, ringer::{ring_up, RingerConfig}, stroke::SimConfig};
///
/// let up = ring_up(&Bell::lab(), &SimConfig::default(), &RingerConfig::default(), &mut ()).unwrap();
/// assert!(up.finished);
/// assert!(up.swings.len() > 10);
/// ```
pub fn ring_up<O: Observer>(
    bell: &Bell,
    cfg: &SimConfig,
    ringer: &RingerConfig,
    observer: &mut O,
) -> Result<RingingUpDown, SimError> {
    let pull = ringer.pull(bell, PullPhase::Raise)?;
    let th = ringer.start;
    // At rest, the clapper hanging straight down: φ = −θ.
    let start = StrokeStart {
        t: 0.0,
        y: [th, -th, 0.0, 0.0],
        clapper: ClapperState::FLYING,
    };
    let stay = ringer.stay;
    ring(
        bell,
        cfg,
        ringer,
        pull,
        start,
        |s| s.amplitude >= stay || s.end == EndReason::OverTheBalance,
        observer,
    )
}

/// Ring `bell` down from the stay: it starts at rest at `ringer.stay`,
/// ringing right (the clapper on the trailing side), and each swing the
/// ringer checks it until a swing reaches no further than `ringer.down`.
pub fn ring_down<O: Observer>(
    bell: &Bell,
    cfg: &SimConfig,
    ringer: &RingerConfig,
    observer: &mut O,
) -> Result<RingingUpDown, SimError> {
    let pull = ringer.pull(bell, PullPhase::Check)?;
    let th = ringer.stay;
    let start = StrokeStart::at_rest(bell, cfg, 0.0, th, Style::Right.side(th));
    let down = ringer.down;
    ring(bell, cfg, ringer, pull, start, |s| s.amplitude <= down, observer)
}

/// The CCCBR rule of thumb: a bell goes up right if its clapper's small
/// swing period is at least 90 % of the bell's, T_c ≥ 0.9 T_b, that is
/// L_b/L_c ≤ 1/0.81 (periods go as √L).
pub const CCCBR_LB_OVER_LC: f64 = 1.0 / 0.81;

/// One point of a ringing-up chart.
#[derive(Clone, Debug, PartialEq)]
pub struct GoesUpCell {
    /// r/L_c.
    pub x: f64,
    /// L_b/L_c.
    pub y: f64,
    /// How the bell built there goes up, or why it could not be simulated.
    pub result: Result<Settles, SimError>,
}

/// Ring up the bell at every point of `spec`'s plane (its hanging applied;
/// its styles ignored): cells row-major, L_b/L_c rows ascending, the same
/// for any thread count.
pub fn goes_up_chart(
    spec: &ChartSpec,
    ringer: &RingerConfig,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Vec<GoesUpCell>, ParamError> {
    use rayon::prelude::*;
    use std::sync::atomic::{AtomicU64, Ordering};
    spec.validate()?;
    ringer.validate()?;
    let (xs, ys) = (spec.xs(), spec.ys());
    let done = AtomicU64::new(0);
    Ok((0..spec.nx * spec.ny)
        .into_par_iter()
        .map(|k| {
            let (x, y) = (xs[k % spec.nx], ys[k / spec.nx]);
            let result = spec
                .construction
                .bell(x, y)
                .map(|b| b.with_hanging(spec.hanging))
                .map_err(SimError::from)
                .and_then(|b| ring_up(&b, &spec.config, ringer, &mut ()))
                .map(|r| r.settles());
            progress(done.fetch_add(1, Ordering::Relaxed) + 1);
            GoesUpCell { x, y, result }
        })
        .collect())
}

/// How a goes-up chart and the CCCBR rule compare: counts of the points
/// that simulated (failed ones are left out).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RuleAgreement {
    /// The rule says right (L_b/L_c ≤ 1/0.81) and the bell goes up right.
    pub both_right: usize,
    /// The rule says wrong and the bell does not go up right.
    pub both_not_right: usize,
    /// The rule says right; the bell goes up wrong or never strikes.
    pub rule_right_model_not: usize,
    /// The rule says wrong; the bell goes up right.
    pub rule_not_model_right: usize,
}

impl RuleAgreement {
    /// The counts over `cells`.
    pub fn of(cells: &[GoesUpCell]) -> Self {
        let mut a = Self::default();
        for c in cells {
            let Ok(s) = &c.result else { continue };
            match (c.y <= CCCBR_LB_OVER_LC, *s == Settles::Right) {
                (true, true) => a.both_right += 1,
                (false, false) => a.both_not_right += 1,
                (true, false) => a.rule_right_model_not += 1,
                (false, true) => a.rule_not_model_right += 1,
            }
        }
        a
    }

    /// Points compared.
    pub fn total(&self) -> usize {
        self.both_right + self.both_not_right + self.rule_right_model_not + self.rule_not_model_right
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_calibrated_pull_raises_the_tied_bell_in_the_asked_swings() {
        let bell = Bell::lab();
        let k = tied_stiffness(&bell);
        let (from, to, w) = (0.1, 3.0, 1.0);
        for n in [1, 5, 30] {
            let tau = calibrated_torque(&bell, from, to, w, PullPhase::Raise, n);
            assert!(tied_amplitude(k, from, tau, w, PullPhase::Raise, n) >= to);
            assert!(tied_amplitude(k, from, tau * (1.0 - 1e-9), w, PullPhase::Raise, n) < to);
            let tau = calibrated_torque(&bell, to, from, w, PullPhase::Check, n);
            assert!(tied_amplitude(k, to, tau, w, PullPhase::Check, n) <= from);
        }
        assert!(RingerConfig {
            swings: 0,
            ..RingerConfig::default()
        }
        .validate()
        .is_err());
    }

    #[test]
    fn the_rule_agreement_counts_each_case() {
        let cell = |y: f64, s: Settles| GoesUpCell {
            x: 0.0,
            y,
            result: Ok(s),
        };
        let cells = [
            cell(1.0, Settles::Right),
            cell(1.0, Settles::Wrong),
            cell(2.0, Settles::NoStrike),
            cell(2.0, Settles::Right),
            cell(2.0, Settles::Wrong),
        ];
        let a = RuleAgreement::of(&cells);
        assert_eq!(
            a,
            RuleAgreement {
                both_right: 1,
                both_not_right: 2,
                rule_right_model_not: 1,
                rule_not_model_right: 1,
            }
        );
        assert_eq!(a.total(), 5);
    }
}
