//! Ringing up and down (docs/model.md §11): the pull checked by the energy
//! it puts in, and the verdicts against the paper's Fig 16 thresholds.

use clapper_core::chart::ChartSpec;
use clapper_core::diagnose::min_theta0_right;
use clapper_core::dynamics::Dynamics;
use clapper_core::ringer::{ring_down, ring_up, Ending, RingerConfig, Settles};
use clapper_core::stroke::{SimConfig, Style};

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
    let ringer = RingerConfig::default();
    let d = Dynamics::new(&bell);
    let e0 = |th: f64| d.energy(&[th, -th, 0.0, 0.0]);
    let up = ring_up(&bell, &cfg, &ringer, &mut ()).unwrap();
    // Set at the balance: the last swing's pull eased.
    let Ending::Set { torque: eased, .. } = up.ending else {
        panic!("not set: {:?}", up.ending)
    };
    // Each stroke that passes the bottom gains the work of its pull over
    // the part of the window it falls through (an impact's turn at a
    // turning point passes no bottom and falls through none of it).
    let n = up.strokes.len();
    let mut work = 0.0;
    for (k, s) in up.strokes.iter().enumerate() {
        let tau = if k + 1 == n { eased } else { up.pull.torque };
        if s.bottom.is_some() {
            work += tau * s.start.y[0].abs().min(ringer.window);
        }
    }
    // The last stroke ends going over the balance, with its state.
    let last = &up.strokes[n - 1];
    assert!(up.finished && (last.end.y[0].abs() - std::f64::consts::PI).abs() < 1e-9);
    let gained = d.energy(&last.end.y) - e0(ringer.start);
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

/// The ringer of before issue 45, for comparison: the full pull every
/// swing until one reaches 175 deg or goes over the balance; the style of
/// each striking stroke, and whether the last stroke went over.
fn old_ring_up(bell: &clapper_core::bell::Bell, cfg: &SimConfig, ringer: &RingerConfig) -> (Vec<Style>, bool) {
    use clapper_core::contact::ClapperState;
    use clapper_core::ringer::PullPhase;
    use clapper_core::stroke::{run_stroke_pulled, EndReason, StrokeStart};
    let pull = ringer.pull(bell, PullPhase::Raise).unwrap();
    let th = ringer.start;
    let mut start = StrokeStart {
        t: 0.0,
        y: [th, -th, 0.0, 0.0],
        clapper: ClapperState::FLYING,
    };
    let mut styles = vec![];
    for _ in 0..4 * ringer.swings + 20 {
        let s = run_stroke_pulled(bell, cfg, start, Some(pull), &mut ()).unwrap();
        let motion = -s.start.y[0].signum();
        let over = s.end.reason == EndReason::OverTheBalance;
        styles.extend(s.first_strike().map(|i| {
            if i.side.sign() == motion {
                Style::Right
            } else {
                Style::Wrong
            }
        }));
        if over || s.end.y[0].abs() >= ringer.stay || s.end.reason != EndReason::TurningPoint {
            let last_struck = s.first_strike().is_some();
            return (styles, over && last_struck);
        }
        start = StrokeStart {
            t: s.end.t,
            y: s.end.y,
            clapper: s.end.clapper,
        };
    }
    (styles, false)
}

fn settles(styles: &[Style]) -> Settles {
    match styles.last() {
        Some(Style::Right) => Settles::Right,
        Some(Style::Wrong) => Settles::Wrong,
        None => Settles::NoStrike,
    }
}

/// Issue 45: every ring-up of a 12 x 12 chart ends with the bell set at the
/// balance (the last swing eased over it, at rest on the stay 5 deg past
/// it, crossing slowly); no swing is an impact's few-ms turn; and the
/// verdict, judged from the swings before setting, is the old one wherever
/// the old one did not rest on its full-pull swing over the balance.
#[test]
fn ring_ups_over_a_chart_end_set_at_the_balance() {
    let cfg = SimConfig::default();
    let ringer = RingerConfig::default();
    let spec = ChartSpec {
        nx: 12,
        ny: 12,
        ..ChartSpec::default()
    };
    let (mut set, mut same, mut independent, mut overshoot_decided, mut changed) = (0, 0, 0, 0, 0);
    let mut fastest: f64 = 0.0;
    let mut shortest = f64::INFINITY;
    for y in spec.ys() {
        for x in spec.xs() {
            let bell = spec.construction.bell(x, y).unwrap();
            let up = ring_up(&bell, &cfg, &ringer, &mut ()).unwrap();
            let Ending::Set { angle, rate, torque } = up.ending else {
                panic!("({x}, {y}) not set: {:?}", up.ending);
            };
            set += 1;
            let last = up.swings.last().unwrap();
            assert_eq!(last.amplitude, angle);
            let past = angle.to_degrees() - 180.0;
            assert!(
                past > 0.0 && past <= 5.0 + 1e-9,
                "({x}, {y}) set {past} deg past the balance"
            );
            assert!(torque > 0.0 && torque <= up.pull.torque, "({x}, {y}) eased {torque}");
            fastest = fastest.max(rate);
            shortest = shortest.min(up.swings.iter().map(|s| s.duration).fold(f64::INFINITY, f64::min));
            // Against the old ringer: its last stroke over the balance at
            // full pull decided its verdict where it struck in another style.
            let (styles, over_struck) = old_ring_up(&bell, &cfg, &ringer);
            let old = settles(&styles);
            let without_overshoot = settles(&styles[..styles.len() - usize::from(over_struck)]);
            if old == without_overshoot {
                independent += 1;
                if up.settles() == old {
                    same += 1;
                } else {
                    println!("({x}, {y}): {old:?} -> {:?}", up.settles());
                }
            } else {
                overshoot_decided += 1;
            }
            changed += usize::from(up.settles() != old);
        }
    }
    println!(
        "{set} of 144 set; verdict unchanged at {same} of the {independent} where the overshoot did not decide it; \
         the overshoot decided {overshoot_decided}; {changed} verdicts changed in all; \
         fastest over the balance {fastest:.3} rad/s; shortest swing {shortest:.3} s"
    );
    assert_eq!(set, 144);
    assert_eq!(
        same, independent,
        "a verdict changed where the overshoot did not decide it"
    );
    // A swing is a swing, not an impact's turn at a turning point.
    assert!(shortest > 0.3, "{shortest} s");
    assert!(fastest < 0.2, "{fastest} rad/s over the balance");
}
