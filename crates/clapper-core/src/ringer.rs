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
use crate::contact::{linear_event, ClapperState};
use crate::dynamics::{State, THETA};
use crate::ode::{Direction, Event, Source};
use crate::stroke::{
    run_stroke_pulled, Applied, EndReason, Forcing, Observer, SegmentStart, Side, SimConfig, SimError, Stroke,
    StrokeStart, Style,
};

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

/// The pull as the stroke takes it (docs/model.md §11): a torque on the
/// bell over a window of θ, on for a segment or not, with the event at
/// the window's edge. The bell moves toward −s0 throughout the stroke.
impl Forcing for Pull {
    fn validate(&self) -> Result<(), ParamError> {
        Pull::validate(self)
    }

    fn over_segment(&self, at: &SegmentStart<'_>, push: &mut dyn FnMut(Event)) -> Applied {
        // Slack so that the segment begun at the window's edge counts as
        // inside (entering) or outside (leaving).
        const SLACK: f64 = 1e-9;
        let (s0, y): (f64, &State) = (at.s0, at.y);
        let u = s0 * y[THETA];
        let bell = match self.phase {
            PullPhase::Raise if !at.bottom_passed => {
                if u > self.window + SLACK {
                    push(linear_event(Source::State(THETA), s0, -self.window, Direction::Falling));
                    0.0
                } else {
                    -s0 * self.torque
                }
            }
            PullPhase::Check if at.bottom_passed && -u < self.window - SLACK => {
                push(linear_event(Source::State(THETA), -s0, -self.window, Direction::Rising));
                s0 * self.torque
            }
            _ => 0.0,
        };
        Applied { bell, clapper: 0.0 }
    }
}

/// Default half-width of the pulled part of a swing (deg): a ringer pulls
/// through the lower part of the swing.
pub const DEFAULT_PULL_WINDOW_DEG: f64 = 60.0;
/// Default stay angle (deg): the set bell rests 5 deg past the balance.
pub const DEFAULT_STAY_DEG: f64 = 175.0;
/// Default angle of "down" (deg): the ringer then lets the bell come to rest.
pub const DEFAULT_DOWN_DEG: f64 = 15.0;

/// The largest wheel taken (m): the heaviest bells' wheels are about 2 m
/// in radius.
pub const MAX_WHEEL_RADIUS_M: f64 = 3.0;

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
    /// The stay (rad): the set bell rests on it this far round from the
    /// bottom on the far side of the balance, that is π − `stay` past the
    /// balance. Ring-up: the ringer eases the last pull so that the bell
    /// just goes over the balance and comes to rest on the stay (set);
    /// ring-down starts from the set bell, at rest at `stay`. Default 175
    /// deg: 5 deg past the balance.
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
                return bad("pull_force_n", f, "a finite force > 0 N");
            }
        }
        if !(self.wheel_radius.is_finite() && self.wheel_radius > 0.0 && self.wheel_radius <= MAX_WHEEL_RADIUS_M) {
            return bad(
                "wheel_radius_m",
                self.wheel_radius,
                "a wheel's radius above 0 and at most 3 m",
            );
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
            return bad(
                "stay_deg",
                self.stay.to_degrees(),
                "above the angles ringing up starts from and ringing down ends at (deg)",
            );
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

/// One swing of ringing up or down: from one turning point through the
/// bottom to the next. An impact that turns the bell back at its turning
/// point (a few ms after it) starts no swing of its own: that stroke and
/// the next are one swing.
#[derive(Clone, Debug, PartialEq)]
pub struct Swing {
    /// Counting from 1.
    pub number: usize,
    /// The amplitude it reached: |θ| where it ended (rad); for the swing
    /// that sets the bell, where the stay holds it (past π).
    pub amplitude: f64,
    /// The clapper's first strike in it, if any.
    pub strike: Option<SwingStrike>,
    /// How it ended.
    pub end: EndReason,
    /// Its duration (s).
    pub duration: f64,
}

/// How ringing up or down ended.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Ending {
    /// Ringing up: set at the balance. The last swing, its pull eased to
    /// `torque` (N m), went over the balance at `rate` (rad/s, the least
    /// the easing found) and came to rest on the stay at `angle` (rad from
    /// the bottom the way it came up: 2π − stay).
    Set {
        /// Where the bell rests on the stay (rad, > π).
        angle: f64,
        /// |θ'| as it went over the balance (rad/s).
        rate: f64,
        /// The eased pull of the last swing (N m).
        torque: f64,
    },
    /// Ringing down: a swing reached no further than `down`.
    Down,
    /// The swings allowed ran out first (ringing up: the pull cannot bring
    /// the bell to the balance against its losses).
    SwingsRanOut,
    /// A swing ended otherwise: over the balance while ringing down, held
    /// by friction, or out of time.
    Stopped(EndReason),
}

impl Ending {
    /// Whether it finished: set (up) or down (down).
    pub fn finished(&self) -> bool {
        matches!(self, Ending::Set { .. } | Ending::Down)
    }
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
    /// Whether it finished: set at the balance (up) or down (down).
    pub finished: bool,
    /// How it ended.
    pub ending: Ending,
    /// The strokes themselves (impacts, bottom, end), in order: one a
    /// swing, or two where an impact turned the bell back at a turning
    /// point.
    pub strokes: Vec<Stroke>,
}

fn settles_of<'a>(swings: impl DoubleEndedIterator<Item = &'a Swing>) -> Settles {
    match swings.rev().find_map(|s| s.strike) {
        Some(s) if s.style == Style::Right => Settles::Right,
        Some(_) => Settles::Wrong,
        None => Settles::NoStrike,
    }
}

impl RingingUpDown {
    /// The swings the verdict is judged from: ringing up and set, those
    /// before the swing that set it (whose pull the ringer eased); else all.
    pub fn judged(&self) -> &[Swing] {
        match self.ending {
            Ending::Set { .. } => &self.swings[..self.swings.len().saturating_sub(1)],
            _ => &self.swings,
        }
    }

    /// The style of the last striking swing judged ([`Self::judged`]):
    /// ringing up, the style it goes up in; ringing down, the style it
    /// comes down in at the end.
    pub fn settles(&self) -> Settles {
        settles_of(self.judged().iter())
    }

    /// Whether the verdict rests on the last swing: judged without the
    /// last striking swing, or with the swing that set the bell, it would
    /// differ.
    pub fn rests_on_last_swing(&self) -> bool {
        let judged = self.judged();
        let verdict = self.settles();
        let with_set = settles_of(self.swings.iter());
        let last_striking = judged.iter().rposition(|s| s.strike.is_some());
        let without_last = match last_striking {
            Some(k) => settles_of(judged[..k].iter()),
            None => Settles::NoStrike,
        };
        with_set != verdict || (last_striking.is_some() && without_last != verdict)
    }

    /// Where the striking style changes in the swings judged: (the
    /// amplitude of the first swing in the new style (rad), the style
    /// before, the style after).
    pub fn changes(&self) -> Vec<(f64, Style, Style)> {
        let mut out = vec![];
        let mut last: Option<Style> = None;
        for s in self.judged() {
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

/// The strike of `stroke` as a swing's, its time counted from `t0` (s).
fn strike_of(stroke: &Stroke, t0: f64) -> Option<SwingStrike> {
    // The bell moves from the side it started on toward the other.
    let motion = -stroke.start.y[0].signum();
    stroke.first_strike().map(|i| SwingStrike {
        t: i.t - t0,
        theta: i.theta,
        side: i.side,
        style: if i.side.sign() == motion {
            Style::Right
        } else {
            Style::Wrong
        },
    })
}

/// Whether `stroke` is no swing of its own: an impact turned the bell back
/// at its turning point before it reached the bottom (docs/model.md §4).
fn turned_back_by_impact(stroke: &Stroke) -> bool {
    stroke.end.reason == EndReason::TurningPoint
        && stroke.bottom.is_none()
        && stroke.impacts.last().is_some_and(|i| i.t == stroke.end.t)
}

/// The swing numbered `number` made of `strokes` (one, or two where an
/// impact turned the bell back at the turning point it started from).
fn swing_of(number: usize, strokes: &[Stroke]) -> Swing {
    let (first, last) = (&strokes[0], &strokes[strokes.len() - 1]);
    Swing {
        number,
        amplitude: last.end.y[0].abs(),
        strike: strokes.iter().find_map(|s| strike_of(s, first.start.t)),
        end: last.end.reason,
        duration: last.end.t - first.start.t,
    }
}

fn next_start(stroke: &Stroke) -> StrokeStart {
    StrokeStart {
        t: stroke.end.t,
        y: stroke.end.y,
        clapper: stroke.end.clapper,
    }
}

/// Bisection steps on the eased pull of the swing that sets the bell: the
/// pull to 2^-16 of the full pull, so the bell goes over the balance with
/// almost nothing to spare.
const EASING_STEPS: usize = 16;

/// The swing from `start` that sets the bell: the least pull up to `pull`
/// (which takes it over the balance, giving `over`) found by bisection
/// that still takes it over. The trials are unobserved; the stroke kept
/// is rerun for `observer`.
fn eased<O: Observer>(
    bell: &Bell,
    cfg: &SimConfig,
    pull: Pull,
    start: StrokeStart,
    over: Stroke,
    observer: &mut O,
) -> Result<(Stroke, f64), SimError> {
    let (mut lo, mut hi) = (0.0, pull.torque);
    let mut kept = over;
    for _ in 0..EASING_STEPS {
        let torque = 0.5 * (lo + hi);
        let s = run_stroke_pulled(bell, cfg, start, Some(Pull { torque, ..pull }), &mut ())?;
        if s.end.reason == EndReason::OverTheBalance {
            (hi, kept) = (torque, s);
        } else {
            lo = torque;
        }
    }
    if !O::SILENT {
        kept = run_stroke_pulled(bell, cfg, start, Some(Pull { torque: hi, ..pull }), observer)?;
    }
    Ok((kept, hi))
}

/// Strokes one after another under `pull` from `start`, until `done` says
/// a swing finished it or the swings run out (at most 4 × the asked
/// number + 20: a bound, not a target). Ringing up (`set`), a swing that
/// would go over the balance at full pull is rung again with the pull
/// eased, and sets the bell on the stay.
#[allow(clippy::too_many_arguments)]
fn ring<O: Observer>(
    bell: &Bell,
    cfg: &SimConfig,
    ringer: &RingerConfig,
    pull: Pull,
    mut start: StrokeStart,
    set: bool,
    done: impl Fn(&Swing) -> bool,
    observer: &mut O,
) -> Result<RingingUpDown, SimError> {
    let mut swings: Vec<Swing> = vec![];
    let mut strokes: Vec<Stroke> = vec![];
    // Strokes of the swing under way (the first of two when an impact
    // turned the bell back at its turning point).
    let mut pending = 0;
    let mut ending = Ending::SwingsRanOut;
    let max = 4 * ringer.swings + 20;
    while swings.len() < max {
        // Ringing up, the full pull is tried unobserved first: a swing
        // that goes over is
        // eased (unless nothing watches, so that no observer sees it).
        let mut stroke = if set && !O::SILENT {
            run_stroke_pulled(bell, cfg, start, Some(pull), &mut ())?
        } else {
            run_stroke_pulled(bell, cfg, start, Some(pull), observer)?
        };
        let mut set_by = None;
        if set && stroke.end.reason == EndReason::OverTheBalance {
            let (s, torque) = eased(bell, cfg, pull, start, stroke, observer)?;
            set_by = Some(torque);
            stroke = s;
        } else if set && !O::SILENT {
            // Rerun observed: the same stroke, bit for bit.
            stroke = run_stroke_pulled(bell, cfg, start, Some(pull), observer)?;
        }
        start = next_start(&stroke);
        strokes.push(stroke);
        let last = &strokes[strokes.len() - 1];
        if pending == 0 && turned_back_by_impact(last) && !swings.is_empty() {
            pending = 1;
            continue;
        }
        let mut swing = swing_of(swings.len() + 1, &strokes[strokes.len() - 1 - pending..]);
        pending = 0;
        let end = swing.end;
        if let Some(torque) = set_by {
            let angle = 2.0 * PI - ringer.stay;
            swing.amplitude = angle;
            ending = Ending::Set {
                angle,
                rate: last.end.y[2].abs(),
                torque,
            };
            swings.push(swing);
            break;
        }
        let finished = done(&swing);
        swings.push(swing);
        if finished {
            ending = Ending::Down;
            break;
        }
        if end != EndReason::TurningPoint {
            ending = Ending::Stopped(end);
            break;
        }
    }
    Ok(RingingUpDown {
        phase: pull.phase,
        pull,
        pull_force: pull.torque / ringer.wheel_radius,
        swings,
        finished: ending.finished(),
        ending,
        strokes,
    })
}

/// Ring `bell` up from rest: the first tug leaves it at `ringer.start`
/// with the clapper hanging, and each swing the ringer pulls with it; the
/// swing that would take it over the balance the ringer eases, so that it
/// just goes over and comes to rest on the stay (set, [`Ending::Set`]).
/// The verdict is judged from the swings before that one
/// ([`RingingUpDown::settles`]).
///
/// ```
/// use clapper_core::{bell::Bell, ringer::{ring_up, Ending, RingerConfig}, stroke::SimConfig};
///
/// let up = ring_up(&Bell::lab(), &SimConfig::default(), &RingerConfig::default(), &mut ()).unwrap();
/// assert!(up.finished);
/// assert!(matches!(up.ending, Ending::Set { .. }));
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
    ring(bell, cfg, ringer, pull, start, true, |_| false, observer)
}

/// Ring `bell` down from the set bell: it starts at rest at `ringer.stay`,
/// ringing right (the clapper on the trailing side, where it lies in the
/// set bell), and each swing the ringer checks it until a swing reaches no
/// further than `ringer.down`.
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
    ring(bell, cfg, ringer, pull, start, false, |s| s.amplitude <= down, observer)
}

/// The range of rope forces, around the one used, over which the verdict
/// of ringing up or down holds: how much a verdict can be trusted. A
/// verdict that changes within a per cent of the pull is on a knife-edge
/// (a 1e-6 change of the bell may change it too).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PullMargin {
    /// The rope force used (N).
    pub force: f64,
    /// The least force tried at which the verdict still holds (N).
    pub low: f64,
    /// The greatest (N).
    pub high: f64,
    /// The force just below `low` at which it changes, if it does within
    /// the forces tried (N).
    pub flips_below: Option<f64>,
    /// The force just above `high` at which it changes (N).
    pub flips_above: Option<f64>,
}

/// Relative changes of the pull [`pull_margin`] tries, each way, nearest first.
pub const MARGIN_STEPS: [f64; 6] = [1e-4, 1e-3, 1e-2, 0.05, 0.1, 0.2];

/// Ring `bell` up (`phase` Raise) or down again at rope forces from
/// [`MARGIN_STEPS`] each side of `ringer`'s, outward until the verdict
/// changes: the range over which it holds.
pub fn pull_margin(
    bell: &Bell,
    cfg: &SimConfig,
    ringer: &RingerConfig,
    phase: PullPhase,
) -> Result<PullMargin, SimError> {
    let go = |r: &RingerConfig| match phase {
        PullPhase::Raise => ring_up(bell, cfg, r, &mut ()),
        PullPhase::Check => ring_down(bell, cfg, r, &mut ()),
    };
    let base = go(ringer)?;
    let force = base.pull_force;
    let verdict = base.settles();
    let mut m = PullMargin {
        force,
        low: force,
        high: force,
        flips_below: None,
        flips_above: None,
    };
    for sign in [-1.0, 1.0] {
        for step in MARGIN_STEPS {
            let f = force * (1.0 + sign * step);
            let r = go(&RingerConfig {
                pull_force: Some(f),
                ..*ringer
            })?;
            let holds = r.finished == base.finished && r.settles() == verdict;
            match (holds, sign < 0.0) {
                (true, true) => m.low = f,
                (true, false) => m.high = f,
                (false, true) => m.flips_below = Some(f),
                (false, false) => m.flips_above = Some(f),
            }
            if !holds {
                break;
            }
        }
    }
    Ok(m)
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
