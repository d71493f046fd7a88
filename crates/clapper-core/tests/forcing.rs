//! Torques applied from outside through the stroke's one interface
//! (`stroke::Forcing`, issue 48): a forcing the stroke does not name.

use clapper_core::bell::{Bell, ParamError};
use clapper_core::contact::Side;
use clapper_core::dynamics::{State, THETA};
use clapper_core::ode::{Direction, Event, Source};
use clapper_core::ringer::{PullPhase, RingerConfig};
use clapper_core::stroke::{
    run_stroke, run_stroke_forced, run_stroke_pulled, Applied, Forcing, SegmentStart, SimConfig, Stroke, StrokeStart,
};

/// A constant torque on the bell and on the clapper, switched off below
/// |θ| = `below` (rad) with an event there, if given.
#[derive(Debug)]
struct Constant {
    bell: f64,
    clapper: f64,
    below: Option<f64>,
}

impl Forcing for Constant {
    fn validate(&self) -> Result<(), ParamError> {
        Ok(())
    }

    fn over_segment(&self, at: &SegmentStart<'_>, push: &mut dyn FnMut(Event)) -> Applied {
        let y: &State = at.y;
        match self.below {
            // Slack: the segment begun at the edge counts as past it.
            Some(b) if at.s0 * y[THETA] <= b + 1e-9 => Applied::NONE,
            Some(b) => {
                // θ falling through b on the side the stroke starts.
                push(Event {
                    source: Source::State(THETA),
                    level: at.s0 * b,
                    direction: if at.s0 > 0.0 {
                        Direction::Falling
                    } else {
                        Direction::Rising
                    },
                });
                Applied {
                    bell: self.bell,
                    clapper: self.clapper,
                }
            }
            None => Applied {
                bell: self.bell,
                clapper: self.clapper,
            },
        }
    }
}

/// The lab bell's largest gravity torques (N m): M g a on the bell, m g b
/// on the clapper.
fn gravity_torques() -> (f64, f64) {
    let b = Bell::lab();
    (b.bell_mass * 9.81 * b.a, b.clapper_mass * 9.81 * b.b)
}

fn stroke(forcing: Option<&dyn Forcing>) -> Stroke {
    let bell = Bell::lab();
    let cfg = SimConfig::default();
    let start = StrokeStart::at_rest(&bell, &cfg, 0.0, cfg.theta0, Side::Plus);
    run_stroke_forced(&bell, &cfg, start, forcing, &mut ()).unwrap()
}

#[test]
fn no_torque_is_the_plain_stroke_bit_for_bit() {
    let bell = Bell::lab();
    let cfg = SimConfig::default();
    let start = StrokeStart::at_rest(&bell, &cfg, 0.0, cfg.theta0, Side::Plus);
    let plain = run_stroke(&bell, &cfg, start, &mut ()).unwrap();
    let none = Constant {
        bell: 0.0,
        clapper: 0.0,
        below: None,
    };
    assert_eq!(stroke(Some(&none)), plain);
    // Its event ends a segment, and the stroke goes on unchanged in its
    // quantities (the steps differ).
    let edged = stroke(Some(&Constant {
        bell: 0.0,
        clapper: 0.0,
        below: Some(1.0),
    }));
    assert!(edged.sustained());
    assert!((edged.strike_angle().unwrap() - plain.strike_angle().unwrap()).abs() < 1e-6);
}

#[test]
fn a_torque_on_the_bell_and_on_the_clapper_moves_the_stroke() {
    let plain = stroke(None);
    let (bell_g, clapper_g) = gravity_torques();
    // A torque against the swing (the bell falls from +θ0 toward −θ): the
    // bell turns lower on the far side.
    let braked = stroke(Some(&Constant {
        bell: 0.05 * bell_g,
        clapper: 0.0,
        below: None,
    }));
    assert!(
        braked.end.y[THETA] > plain.end.y[THETA] + 0.05,
        "{} vs {}",
        braked.end.y[THETA],
        plain.end.y[THETA]
    );
    // A torque holding the clapper to its resting side (+ side, φ > 0)
    // delays its lift-off.
    let held = stroke(Some(&Constant {
        bell: 0.0,
        clapper: 0.2 * clapper_g,
        below: None,
    }));
    assert!(held.liftoff_angle().unwrap() < plain.liftoff_angle().unwrap() - 0.01);
    // Switched off above 90 deg of the swing's start side: only the fall
    // to there is braked, so less is lost than braked all the way.
    let partly = stroke(Some(&Constant {
        bell: 0.05 * bell_g,
        clapper: 0.0,
        below: Some(1.5),
    }));
    assert!(partly.end.y[THETA] < braked.end.y[THETA] && partly.end.y[THETA] > plain.end.y[THETA]);
}

#[test]
fn the_ringers_pull_is_a_forcing() {
    let bell = Bell::lab();
    let cfg = SimConfig::default();
    let pull = RingerConfig::default().pull(&bell, PullPhase::Raise).unwrap();
    let start = StrokeStart {
        t: 0.0,
        y: [0.5, -0.5, 0.0, 0.0],
        clapper: clapper_core::contact::ClapperState::FLYING,
    };
    let by_value = run_stroke_pulled(&bell, &cfg, start, Some(pull), &mut ()).unwrap();
    let by_ref = run_stroke_forced(&bell, &cfg, start, Some(&pull), &mut ()).unwrap();
    assert_eq!(by_value, by_ref);
    let unpulled = run_stroke(&bell, &cfg, start, &mut ()).unwrap();
    // The pull raises the swing.
    assert!(by_value.end.y[THETA].abs() > unpulled.end.y[THETA].abs() + 0.01);
}

/// A clapper resting against its stop: a torque pressing it there (+ side,
/// φ > 0) holds it on longer, one pulling it off lets it go sooner; the
/// stop takes the torque, so the holding force it needs is less by it.
#[test]
fn a_resting_clapper_lifts_off_later_when_pressed() {
    let bell = Bell::lab();
    let cfg = SimConfig {
        theta0: 120f64.to_radians(),
        ..SimConfig::default()
    };
    let start = StrokeStart::at_rest(&bell, &cfg, 0.0, cfg.theta0, Side::Plus);
    assert!(start.clapper.is_at_rest(), "{:?}", start.clapper);
    let (_, clapper_g) = gravity_torques();
    let liftoff = |torque: f64| {
        let f = Constant {
            bell: 0.0,
            clapper: torque,
            below: None,
        };
        let s = run_stroke_forced(&bell, &cfg, start, Some(&f), &mut ()).unwrap();
        s.liftoff_angle().unwrap()
    };
    let plain = run_stroke(&bell, &cfg, start, &mut ())
        .unwrap()
        .liftoff_angle()
        .unwrap();
    // θ falls from +120 deg: a later lift-off is at a smaller θ.
    assert!(
        liftoff(0.1 * clapper_g) < plain - 1e-3,
        "{} vs {plain}",
        liftoff(0.1 * clapper_g)
    );
    assert!(
        liftoff(-0.1 * clapper_g) > plain + 1e-3,
        "{} vs {plain}",
        liftoff(-0.1 * clapper_g)
    );
}
