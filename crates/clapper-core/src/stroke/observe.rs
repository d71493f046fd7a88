//! Watching a stroke as it runs: samples of the state with the contact
//! and friction forces, every accepted step and every jump, for an
//! [`Observer`]; a trace sampled at a fixed interval.

use crate::contact::ForceLaw;
use crate::dynamics::{Dynamics, Load, State};
use crate::ode::DenseOutput;

/// A state sampled during a simulation, with the contact force.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    /// Time (s).
    pub t: f64,
    /// State `[θ, φ, θ', φ']` (rad, rad/s).
    pub y: State,
    /// Generalised contact force Q_φ on the clapper (N m): the force of a
    /// resting or compressed contact; zero in flight. Impacts are impulses
    /// and do not show.
    pub contact_force: f64,
    /// Generalised forces of friction (Q_θ, Q_φ) (N m) besides the contact
    /// force; both zero for a frictionless bell. Q_φ is zero while the
    /// clapper rests or sticks: the contact force then holds it all.
    pub friction: [f64; 2],
}

/// One accepted integration step, for observers: evaluate the state
/// anywhere in `[t_from, t_to]`.
pub struct StepView<'a> {
    pub(super) dense: &'a dyn DenseOutput<4>,
    pub(super) t_to: f64,
    pub(super) law: ForceLaw,
    pub(super) load: Option<Load>,
    pub(super) dynamics: &'a Dynamics,
}

impl StepView<'_> {
    /// Start of the step (s).
    pub fn t_from(&self) -> f64 {
        self.dense.t0()
    }

    /// End of the part of the step that was used (s).
    pub fn t_to(&self) -> f64 {
        self.t_to
    }

    /// The state and contact force at `t` (s).
    pub fn sample(&self, t: f64) -> Sample {
        let y = self.dense.eval(t);
        Sample::new(t, y, self.law, self.load.as_ref(), self.dynamics)
    }

    /// The friction acting over this step, if any: its power along the
    /// step is what friction takes from the bell and clapper.
    pub fn friction(&self) -> Option<Load> {
        self.load
    }
}

impl Sample {
    pub(super) fn new(t: f64, y: State, law: ForceLaw, load: Option<&Load>, d: &Dynamics) -> Self {
        let (contact_force, friction) = match (law, load) {
            (ForceLaw::Resting, Some(l)) => (d.resting_q(&y, l.theta(&y)).1, [l.theta(&y), 0.0]),
            (_, Some(l)) => (law.force(d, &y), [l.theta(&y), l.phi(&y)]),
            (_, None) => (law.force(d, &y), [0.0; 2]),
        };
        Sample {
            t,
            y,
            contact_force,
            friction,
        }
    }
}

/// Watches a simulation as it runs (argmin-style: the core never prints).
/// Every method has an empty default, so `()` observes nothing at no cost.
pub trait Observer {
    /// After every accepted integration step.
    fn on_step(&mut self, _step: &StepView<'_>) {}
    /// At every event and at the start of every stroke: the state just
    /// before and just after (they differ at an impact or a restart).
    fn on_jump(&mut self, _before: &Sample, _after: &Sample) {}
    /// Whether it watches nothing (then a caller that tries strokes
    /// before keeping one need not run the kept one again for it).
    const SILENT: bool = false;
}

impl Observer for () {
    const SILENT: bool = true;
}

/// Samples a trace every `interval` seconds of simulated time, plus both
/// sides of every jump, and hands each sample to `sink` as it comes: a
/// trace of any length in constant memory (a file written as it goes).
#[derive(Clone, Debug)]
pub struct TraceSampler<F> {
    /// Sampling interval (s).
    pub interval: f64,
    next: u64,
    last: Option<Sample>,
    sink: F,
}

impl<F: FnMut(&Sample)> TraceSampler<F> {
    /// A sampler every `interval` seconds (> 0) into `sink`.
    pub fn new(interval: f64, sink: F) -> Self {
        Self {
            interval,
            next: 0,
            last: None,
            sink,
        }
    }

    fn push(&mut self, s: Sample) {
        (self.sink)(&s);
        self.last = Some(s);
    }
}

impl<F: FnMut(&Sample)> Observer for TraceSampler<F> {
    fn on_step(&mut self, step: &StepView<'_>) {
        // Bounded: at most (t_to - t_from) / interval + 1 samples.
        loop {
            let t = self.next as f64 * self.interval;
            if t > step.t_to() {
                break;
            }
            if t >= step.t_from() {
                self.push(step.sample(t));
            }
            self.next += 1;
        }
    }

    fn on_jump(&mut self, before: &Sample, after: &Sample) {
        for s in [before, after] {
            if self.last.as_ref() != Some(s) {
                self.push(*s);
            }
        }
    }
}

/// Records a trace in memory: samples every `interval` seconds of
/// simulated time, plus both sides of every jump ([`TraceSampler`] into
/// a vector).
#[derive(Clone, Debug, PartialEq)]
pub struct TraceRecorder {
    /// Sampling interval (s).
    pub interval: f64,
    next: u64,
    /// The samples, in time order.
    pub samples: Vec<Sample>,
}

impl TraceRecorder {
    /// A recorder sampling every `interval` seconds (> 0).
    pub fn new(interval: f64) -> Self {
        Self {
            interval,
            next: 0,
            samples: Vec::new(),
        }
    }

    /// The sampler this recorder is, for one call.
    fn sampler(&mut self) -> TraceSampler<impl FnMut(&Sample) + '_> {
        let samples = &mut self.samples;
        TraceSampler {
            interval: self.interval,
            next: self.next,
            last: samples.last().copied(),
            sink: move |s: &Sample| samples.push(*s),
        }
    }
}

impl Observer for TraceRecorder {
    fn on_step(&mut self, step: &StepView<'_>) {
        let next = {
            let mut s = self.sampler();
            s.on_step(step);
            s.next
        };
        self.next = next;
    }

    fn on_jump(&mut self, before: &Sample, after: &Sample) {
        self.sampler().on_jump(before, after);
    }
}
