//! Ringing up and down (docs/model.md §11): the pull checked by the energy
//! it puts in, and the verdicts against the paper's Fig 16 thresholds.

use clapper_core::chart::ChartSpec;
use clapper_core::diagnose::min_theta0_right;
use clapper_core::dynamics::Dynamics;
use clapper_core::ringer::{ring_down, ring_up, RingerConfig, Settles};
use clapper_core::stroke::SimConfig;

/// At R = 1 and without friction nothing but the pull changes the energy:
/// each swing gains τ times the angle it falls through inside the window
/// (the work of a constant torque), whatever the clapper does meanwhile.
/// Ringing down, each loses τ times the angle it rises through inside it.
#[test]
fn the_pull_does_the_work_of_a_constant_torque_over_its_window() {
    let bell = ChartSpec::default().construction.bell(0.25, 1.2).unwrap();
    let mut cfg = SimConfig {
        restitution: 1.0,
        ..SimConfig::default()
    };
    cfg.ode.rtol = 1e-12;
    cfg.ode.atol = 1e-12;
    // Set well short of the balance, so that the last swing turns.
    let ringer = RingerConfig {
        stay: 150f64.to_radians(),
        ..RingerConfig::default()
    };
    let d = Dynamics::new(&bell);
    let e0 = |th: f64| d.energy(&[th, -th, 0.0, 0.0]);
    let up = ring_up(&bell, &cfg, &ringer, &mut ()).unwrap();
    // The swings' starting angles: the first tug, then each end.
    let mut from = ringer.start;
    let mut work = 0.0;
    for s in &up.swings {
        work += up.pull.torque * from.min(ringer.window);
        from = s.amplitude;
    }
    // The last swing ends at a turning point (or over the top): at rest.
    let last = up.swings.last().unwrap();
    assert!(up.finished && last.amplitude < std::f64::consts::PI, "{last:?}");
    // Energy at the end from the state the last stroke left: rerun to get it.
    let mut end_state = None;
    struct Last<'a>(&'a mut Option<[f64; 4]>);
    impl clapper_core::stroke::Observer for Last<'_> {
        fn on_jump(&mut self, _b: &clapper_core::stroke::Sample, a: &clapper_core::stroke::Sample) {
            *self.0 = Some(a.y);
        }
    }
    ring_up(&bell, &cfg, &ringer, &mut Last(&mut end_state)).unwrap();
    let gained = d.energy(&end_state.unwrap()) - e0(ringer.start);
    println!(
        "ring-up: energy gained {gained:.9} J, pull work {work:.9} J, relative error {:.1e}",
        gained / work - 1.0
    );
    assert!((gained / work - 1.0).abs() < 1e-6, "{gained} vs {work}");
}

/// The ringer's verdict against Fig 16: bells that ring right only from
/// high up (threshold above 120 deg) go up wrong; bells that ring right
/// from low down (below 40 deg) go up right. And rung down from the stay
/// ringing right, the second still rings right at the end.
#[test]
fn bells_that_ring_right_only_from_high_go_up_wrong() {
    let cfg = SimConfig::default();
    let ringer = RingerConfig::default();
    let c = ChartSpec::default().construction;
    for (x, y, high) in [
        (0.10, 1.6, true),
        (0.25, 1.8, true),
        (0.40, 1.0, false),
        (0.25, 1.2, false),
    ] {
        let bell = c.bell(x, y).unwrap();
        let threshold = min_theta0_right(&bell, &cfg).map_or(180.0, f64::to_degrees);
        let up = ring_up(&bell, &cfg, &ringer, &mut ()).unwrap();
        println!(
            "({x}, {y}): rings right from {threshold:.0} deg; goes up {:?}",
            up.settles()
        );
        assert!(up.finished);
        if high {
            assert!(threshold > 120.0, "({x}, {y}): {threshold}");
            assert_eq!(up.settles(), Settles::Wrong, "({x}, {y})");
        } else {
            assert!(threshold < 40.0, "({x}, {y}): {threshold}");
            assert_eq!(up.settles(), Settles::Right, "({x}, {y})");
        }
    }
    let down = ring_down(&c.bell(0.40, 1.0).unwrap(), &cfg, &ringer, &mut ()).unwrap();
    assert!(down.finished);
    assert_eq!(down.settles(), Settles::Right);
}
