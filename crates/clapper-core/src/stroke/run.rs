//! Running one stroke: a short loop over segments. Build the segment
//! (`segment.rs`) for the clapper's state, let the stepper run it to its
//! first event, hand the event to the bell, the contact law, friction or
//! the applied forcing, and tell the recorder (`recorder.rs`) and the
//! observer what happened.

use crate::bell::Bell;
use crate::contact::{ClapperState, ContactEvent, ContactLaw, ContactModel, Stops};
use crate::dynamics::{Dynamics, Load, State, Trig, PHI_DOT, THETA, THETA_DOT};
use crate::ode::{DenseOutput, Dopri5, Fallback, NextSegment, Stepper, Stop, Taylor};
use crate::swing::ClosedFormSwing;

use super::config::{Integrator, SimConfig, SimError, TaylorOptions};
use super::forcing::Forcing;
use super::impact::{Impact, Moment};
use super::observe::{Observer, Sample, StepView};
use super::quantities::{AfterEnd, EndReason, Stroke, StrokeEnd, StrokeStart};
use super::recorder::StrokeRecorder;
use super::segment::{flight_from_apex_at, slip_stop_hold_at, BellEvent, Ev, FrictionEvent, Segment, StrokeFrame};

/// Simulate one stroke from `start` until the bell's next turning point.
///
/// ```
/// use clapper_core::{bell::Bell, stroke::{run_stroke, SimConfig, Side, StrokeStart}};
///
/// let bell = Bell::lab();
/// let cfg = SimConfig::default();
/// // Ringing right from +171 deg: the clapper rests on the + side.
/// let start = StrokeStart::at_rest(&bell, &cfg, 0.0, cfg.theta0, Side::Plus);
/// let stroke = run_stroke(&bell, &cfg, start, &mut ()).unwrap();
/// assert!(stroke.sustained());
/// assert!(stroke.strike_velocity().unwrap() < 0.0);
/// ```
pub fn run_stroke<O: Observer>(
    bell: &Bell,
    cfg: &SimConfig,
    start: StrokeStart,
    observer: &mut O,
) -> Result<Stroke, SimError> {
    run_stroke_forced(bell, cfg, start, None, observer)
}

/// [`run_stroke`] with torques applied from outside ([`Forcing`]: a
/// ringer's pull, a rope, a tower's motion), if any.
pub fn run_stroke_forced<O: Observer>(
    bell: &Bell,
    cfg: &SimConfig,
    start: StrokeStart,
    forcing: Option<&dyn Forcing>,
    observer: &mut O,
) -> Result<Stroke, SimError> {
    bell.validate()?;
    cfg.validate()?;
    if let Some(f) = forcing {
        f.validate()?;
    }
    let TaylorOptions { order, h_max } = cfg.taylor;
    match cfg.integrator {
        // A resting phase from rest is a closed-form swing with the rigid
        // law (the Dormand–Prince path integrates it, as a check).
        Integrator::Taylor if cfg.contact == ContactModel::Impact => {
            let taylor = Taylor::new(cfg.ode, order, h_max);
            let stepper = Fallback {
                first: ClosedFormSwing::default(),
                then: taylor,
            };
            drive(stepper, bell, cfg, start, forcing, observer)
        }
        Integrator::Taylor => drive(Taylor::new(cfg.ode, order, h_max), bell, cfg, start, forcing, observer),
        Integrator::Dopri5 => drive(Dopri5::new(cfg.ode), bell, cfg, start, forcing, observer),
    }
}

/// [`run_stroke_forced`] with the forcing passed by value (the name kept
/// from when the ringer's pull was the stroke's only outside force).
pub fn run_stroke_pulled<O: Observer, F: Forcing>(
    bell: &Bell,
    cfg: &SimConfig,
    start: StrokeStart,
    forcing: Option<F>,
    observer: &mut O,
) -> Result<Stroke, SimError> {
    run_stroke_forced(bell, cfg, start, forcing.as_ref().map(|f| f as &dyn Forcing), observer)
}

/// What stays fixed while a stroke runs: the bell's equations, the contact
/// law, the stroke's frame and the side of the bottom it started on.
struct Course<'a> {
    d: &'a Dynamics,
    law: &'a dyn ContactLaw,
    frame: StrokeFrame<'a>,
    /// The side of the bottom the bell starts on (±1).
    s0: f64,
}

impl Course<'_> {
    /// The state sampled with the forces of the clapper's state.
    fn sample(&self, (t, y, clapper): (f64, State, ClapperState)) -> Sample {
        let load = self.frame.load(self.d, clapper, &y);
        Sample::new(
            t,
            y,
            self.law.force_law(clapper, &self.frame.stops),
            load.as_ref(),
            self.d,
        )
    }
}

/// The stroke's frame from its start, its side of the bottom (±1), and
/// whether the bearing's friction holds the bell where it starts.
fn frame_at_start<'f>(
    bell: &Bell,
    d: &Dynamics,
    start: &StrokeStart,
    forcing: Option<&'f dyn Forcing>,
) -> (StrokeFrame<'f>, f64, bool) {
    let y = &start.y;
    // The side of the bottom the bell starts on (±1): it swings toward the
    // bottom, unless bearing friction says otherwise (below).
    let mut s0 = if y[THETA] >= 0.0 { 1.0 } else { -1.0 };
    let friction = &bell.hanging.friction;
    // The bearing's Coulomb torque opposes the bell's motion, which keeps
    // its sign until the stroke's turning point; a bell at rest that the
    // friction can hold does not move at all.
    let mut held = false;
    let frame = StrokeFrame {
        stops: Stops::of(bell),
        friction: (!friction.is_none()).then(|| {
            let tau = friction.bell_friction;
            let mut dir = y[THETA_DOT].signum();
            if tau > 0.0 && y[THETA_DOT].abs() < 1e-9 {
                let hold = d.bell_holding_torque(y, !start.clapper.is_flying());
                held = hold.abs() <= tau;
                dir = -hold.signum();
            }
            if tau > 0.0 {
                // Events are set by the direction the bell actually moves:
                // from a turning point between the equilibrium and the
                // bottom it swings away from the bottom.
                s0 = -dir;
            }
            Load {
                bell_damping: friction.bell_damping,
                bell_torque: if tau > 0.0 { -dir * tau } else { 0.0 },
                clapper_damping: friction.clapper_damping,
                clapper_torque: friction.clapper_friction,
            }
        }),
        forcing,
    };
    (frame, s0, held)
}

/// [`run_stroke`] with one stepper: segments from event to event, each
/// event handed to the bell (bottom, turning point, over the balance) or
/// the contact law, and what happened to the recorder.
fn drive<M, O>(
    mut stepper: M,
    bell: &Bell,
    cfg: &SimConfig,
    start: StrokeStart,
    forcing: Option<&dyn Forcing>,
    observer: &mut O,
) -> Result<Stroke, SimError>
where
    M: for<'a> Stepper<4, Segment<'a>>,
    O: Observer,
{
    let d = Dynamics::new(bell);
    let law = cfg.contact_law();
    let (frame, s0, held) = frame_at_start(bell, &d, &start, forcing);
    let course = Course {
        d: &d,
        law: law.as_ref(),
        frame,
        s0,
    };
    let mut rec = StrokeRecorder::new(start, &frame.stops);
    let mut now = (start.t, start.y, start.clapper);
    let initial = course.sample(now);
    observer.on_jump(&initial, &initial);
    let t_limit = start.t + cfg.max_stroke_periods * bell.tb();
    let (reason, events) = if held {
        (EndReason::Held, 0)
    } else {
        to_the_end(
            &mut stepper,
            &course,
            cfg.max_events,
            t_limit,
            &mut now,
            &mut rec,
            observer,
        )?
    };
    let last = course.sample(now);
    observer.on_jump(&last, &last);
    // The second impact of a double strike may come after the bell has
    // turned: follow the clapper (unobserved: the stroke is over) until it.
    let after_end = if reason == EndReason::TurningPoint && rec.awaits_second_impact() {
        let budget = cfg.max_events.saturating_sub(events);
        Some(after_the_end(&mut stepper, &course, now, now.0 + bell.tb(), budget)?)
    } else {
        None
    };
    let (t, y, clapper) = now;
    let mut stroke = rec.finish(
        StrokeEnd { t, y, clapper, reason },
        stepper.stats(),
        events,
        cfg.strike_amplitude,
    );
    stroke.after_end = after_end;
    Ok(stroke)
}

/// The stroke's segments from `now` (time, state, clapper; left at the
/// stroke's end) to its end, and the events handled.
#[allow(clippy::too_many_arguments)]
fn to_the_end<M, O>(
    stepper: &mut M,
    course: &Course,
    max_events: u32,
    t_limit: f64,
    now: &mut (f64, State, ClapperState),
    rec: &mut StrokeRecorder,
    observer: &mut O,
) -> Result<(EndReason, u32), SimError>
where
    M: for<'a> Stepper<4, Segment<'a>>,
    O: Observer,
{
    let (d, law, frame, s0) = (course.d, course.law, &course.frame, course.s0);
    let mut bottom_passed = false;
    let mut events = 0u32;
    // The torque holding the clapper still relative to the bell, where a
    // slip has just stopped: computed once for the stick check, the next
    // flight's direction of slip and its length.
    let mut hold = None;
    loop {
        let (t, y, clapper) = *now;
        // An observer that watches nothing is not shown the jumps at the
        // apexes of the clapper's flight: the stepper passes through them.
        let apexes = O::SILENT.then_some(max_events - events);
        let seg = Segment::new(d, law, frame, clapper, &y, s0, bottom_passed, hold.take(), apexes);
        let law_now = seg.force_law();
        let stop = watched(stepper, &seg, (t, y), t_limit, observer, d)?;
        (now.0, now.1) = (stop.t, stop.y);
        events += seg.apexes_passed();
        let load_now = seg.load();
        let Stop::Event(i) = stop.stop else {
            return Ok((EndReason::TimeLimit, events));
        };
        events += 1;
        if events > max_events {
            return Err(SimError::EventLimit {
                limit: max_events,
                t: now.0,
            });
        }
        // Samples only for an observer that watches.
        let before = (!O::SILENT).then(|| Sample::new(now.0, now.1, law_now, load_now.as_ref(), d));
        match seg.kind(i) {
            Ev::Bell(BellEvent::OverTop) => return Ok((EndReason::OverTheBalance, events)),
            Ev::Bell(BellEvent::Turning) => return Ok((EndReason::TurningPoint, events)),
            Ev::Bell(BellEvent::Bottom) => {
                bottom_passed = true;
                rec.bottom(now.0, now.1[THETA]);
            }
            // The next segment asks the forcing again.
            Ev::Forcing => {}
            Ev::Contact(e) => {
                if contact(stepper, course, &seg, e, now, rec) {
                    if let Some(before) = &before {
                        observer.on_jump(before, &course.sample(*now));
                    }
                    return Ok((EndReason::TurningPoint, events));
                }
            }
            Ev::Friction(e) => {
                let held;
                (now.1, now.2, held) = frictional(d, frame, e, now.1, now.2, load_now);
                hold = held;
                if let Some(next) = flight_from_apex(d, frame, e, &now.1, now.2, hold) {
                    stepper.expect(next);
                }
            }
        }
        if let Some(before) = &before {
            observer.on_jump(before, &course.sample(*now));
        }
    }
}

/// `seg` integrated from `(t, y)` to its first event or `t_limit`, every
/// step shown to `observer` with the segment's forces.
fn watched<M, O>(
    stepper: &mut M,
    seg: &Segment,
    (t, y): (f64, State),
    t_limit: f64,
    observer: &mut O,
    d: &Dynamics,
) -> Result<crate::ode::Segment<4>, SimError>
where
    M: for<'a> Stepper<4, Segment<'a>>,
    O: Observer,
{
    let (law, load) = (seg.force_law(), seg.load());
    Ok(stepper.integrate(seg, t, y, t_limit, &mut |dense, t_to| {
        observer.on_step(&StepView {
            dense,
            t_to,
            law,
            load,
            dynamics: d,
        })
    })?)
}

/// A contact event `e` in `seg` at `now`, handed to the contact law and
/// recorded; `now` takes the state after it. Whether the impact reversed
/// the bell, ending the stroke.
fn contact<M>(
    stepper: &mut M,
    course: &Course,
    seg: &Segment,
    e: ContactEvent,
    now: &mut (f64, State, ClapperState),
    rec: &mut StrokeRecorder,
) -> bool
where
    M: for<'a> Stepper<4, Segment<'a>>,
{
    let (t, y, clapper) = *now;
    let s0 = course.s0;
    // The rest after a bounce is judged with the forces of the flight to
    // come: friction, and those applied from outside.
    let judge = seg.judging_load(&course.frame);
    let tr = course.law.transition(course.d, e, y, clapper, judge.as_ref());
    rec.contact(t, &y, &tr);
    // An impact may reverse the bell's rate in a jump (at R = 1 near a
    // turning point): the bell turns there, though θ' never passes
    // through zero (docs/model.md §4).
    let reversed = y[THETA_DOT] * s0 < 0.0 && tr.y[THETA_DOT] * s0 > 0.0;
    (now.1, now.2) = (tr.y, tr.clapper);
    if reversed {
        return true;
    }
    if let Some(next) = tr.next {
        stepper.expect(next);
    }
    false
}

/// The look past a stroke's end for a double strike's second impact:
/// [`follow_to_next_impact`] with the bell swinging back from `now`.
fn after_the_end<M>(
    stepper: &mut M,
    course: &Course,
    now: (f64, State, ClapperState),
    t_limit: f64,
    budget: u32,
) -> Result<AfterEnd, SimError>
where
    M: for<'a> Stepper<4, Segment<'a>>,
{
    let frame = &course.frame;
    let back = StrokeFrame {
        stops: frame.stops,
        // The bearing's Coulomb torque turns with the bell; what is
        // applied from outside is left out of this look past the stroke.
        friction: frame.friction.map(|l| Load {
            bell_torque: -l.bell_torque,
            ..l
        }),
        forcing: None,
    };
    follow_to_next_impact(stepper, course.d, course.law, &back, now, -course.s0, t_limit, budget)
}

/// Follow the clapper from a stroke's end (time, state, clapper) with the
/// bell swinging back (`s0`: the side of the bottom it now starts from)
/// until its next impact, its rest, the bell over the balance, `t_limit`
/// (s) or `budget` events, whichever is first.
#[allow(clippy::too_many_arguments)]
fn follow_to_next_impact<M>(
    stepper: &mut M,
    d: &Dynamics,
    law: &dyn ContactLaw,
    frame: &StrokeFrame,
    (mut t, mut y, mut clapper): (f64, State, ClapperState),
    mut s0: f64,
    t_limit: f64,
    budget: u32,
) -> Result<AfterEnd, SimError>
where
    M: for<'a> Stepper<4, Segment<'a>>,
{
    let mut bottom_passed = false;
    let mut hold = None;
    for _ in 0..budget {
        let seg = Segment::new(d, law, frame, clapper, &y, s0, bottom_passed, hold.take(), None);
        let load_now = seg.load();
        let stop = stepper.integrate(&seg, t, y, t_limit, &mut |_: &dyn DenseOutput<4>, _| {})?;
        (t, y) = (stop.t, stop.y);
        let Stop::Event(i) = stop.stop else {
            return Ok(AfterEnd::NoneWithin);
        };
        match seg.kind(i) {
            Ev::Bell(BellEvent::OverTop) => return Ok(AfterEnd::OverTheBalance),
            // Another swing: watch its bottom and turning point afresh.
            Ev::Bell(BellEvent::Turning) => (s0, bottom_passed) = (-s0, false),
            Ev::Bell(BellEvent::Bottom) => bottom_passed = true,
            Ev::Forcing => {}
            Ev::Contact(e) => {
                let judge = seg.judging_load(frame);
                let tr = law.transition(d, e, y, clapper, judge.as_ref());
                if let Some(side) = tr.impact {
                    return Ok(AfterEnd::Impact(Impact {
                        t,
                        theta: y[THETA],
                        phi_dot_before: y[PHI_DOT],
                        phi_dot_after: tr.rebound,
                        side,
                    }));
                }
                if tr.rest.is_some() {
                    return Ok(AfterEnd::Rested(Moment { t, theta: y[THETA] }));
                }
                (y, clapper) = (tr.y, tr.clapper);
                if let Some(next) = tr.next {
                    stepper.expect(next);
                }
            }
            Ev::Friction(e) => {
                (y, clapper, hold) = frictional(d, frame, e, y, clapper, load_now);
                if let Some(next) = flight_from_apex(d, frame, e, &y, clapper, hold) {
                    stepper.expect(next);
                }
            }
        }
    }
    Ok(AfterEnd::NoneWithin)
}

/// The clapper at a friction event: still relative to the bell, for an
/// instant (slip stops, unless the pivot's friction can hold it: stuck) or
/// from now on; or free again (breakaway). With the state after it, the
/// torque that would hold the clapper still relative to the bell with the
/// frame's friction ([`StrokeFrame::load_held`]), where the check for
/// sticking computed it.
fn frictional(
    d: &Dynamics,
    frame: &StrokeFrame,
    e: FrictionEvent,
    mut y: State,
    clapper: ClapperState,
    load: Option<Load>,
) -> (State, ClapperState, Option<f64>) {
    y[PHI_DOT] = 0.0;
    match e {
        FrictionEvent::SlipStops => {
            let (stuck, hold) = slip_stop_hold(d, frame, &y, load);
            let clapper = if stuck { ClapperState::Stuck } else { clapper };
            (y, clapper, hold)
        }
        FrictionEvent::Breakaway => (y, ClapperState::FLYING, None),
    }
}

/// Where a flying clapper's slip stops (`y`, with φ' = 0) in a segment
/// with `load`: whether the pivot's friction holds it (it sticks), and the
/// torque that would hold it with the frame's friction
/// ([`StrokeFrame::load_held`]), where that is the segment's.
fn slip_stop_hold(d: &Dynamics, frame: &StrokeFrame, y: &State, load: Option<Load>) -> (bool, Option<f64>) {
    slip_stop_hold_at(d, frame, y, &Trig::of(y), load)
}

/// The rest of a bounce's flight after its apex (a friction event at which
/// the clapper turns back toward the stop it bounced off, still flying): a
/// short flight of about √(2Δ/a) for a distance Δ (rad) to the stop under
/// the relative acceleration a toward it (rad/s²), which the stepper is
/// told, as after the bounce itself (with the same margin, 1.5 times).
fn flight_from_apex(
    d: &Dynamics,
    frame: &StrokeFrame,
    e: FrictionEvent,
    y: &State,
    clapper: ClapperState,
    hold: Option<f64>,
) -> Option<NextSegment> {
    if e != FrictionEvent::SlipStops {
        return None;
    }
    let load = frame.load_held(d, clapper, y, hold);
    let span = flight_from_apex_at(d, frame, y, &Trig::of(y), clapper, load)?;
    Some(NextSegment::ShortFlight { span })
}
