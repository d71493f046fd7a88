//! Clapping charts: determinism, agreement with single simulations, the
//! r = 0 column against (15), and the layout the paper describes.

use clapper_core::chart::{sweep, Chart, ChartSpec, Domain, Styles};
use clapper_core::prelude::*;

fn in_pool(threads: usize, spec: &ChartSpec) -> Chart {
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
    pool.install(|| sweep(spec, &|_| {}).unwrap())
}

#[test]
fn thread_count_does_not_change_the_chart() {
    let spec = ChartSpec {
        nx: 9,
        ny: 7,
        ..ChartSpec::default()
    };
    let one = in_pool(1, &spec);
    let three = in_pool(3, &spec);
    assert_eq!(one, three);
}

#[test]
fn chart_point_equals_a_single_simulation() {
    let lab = Bell::lab();
    let spec = ChartSpec {
        domain: Domain {
            x: (lab.r_over_lc(), lab.r_over_lc()),
            y: (lab.lb_over_lc(), lab.lb_over_lc()),
        },
        nx: 1,
        ny: 1,
        ..ChartSpec::default()
    };
    let chart = sweep(&spec, &|_| {}).unwrap();
    for style in [Style::Right, Style::Wrong] {
        let cell = chart.cell(0, 0, style).unwrap().result.clone().unwrap();
        // The same bell simulated alone gives the same numbers to the bit.
        let bell = ChartConstruction::default()
            .bell(lab.r_over_lc(), lab.lb_over_lc())
            .unwrap();
        let alone = first_stroke(&bell, &SimConfig::default(), style).unwrap();
        assert_eq!(cell.strike_theta, alone.strike_angle());
        assert_eq!(cell.double_strike_index, alone.double_strike_index());
        // And the lab bell itself, with its own masses, lands on the same verdict
        // and nearly the same strike: the premise of the chart.
        let preset = first_stroke(&lab, &SimConfig::default(), style).unwrap();
        assert_eq!(cell.sustained, preset.sustained());
        let d = (cell.strike_theta.unwrap() - preset.strike_angle().unwrap())
            .to_degrees()
            .abs();
        assert!(
            d < 5.0,
            "{style:?}: chart {} vs preset {}",
            cell.strike_theta.unwrap(),
            preset.strike_angle().unwrap()
        );
    }
}

#[test]
fn r0_column_liftoff_agrees_with_equation_15() {
    let spec = ChartSpec {
        domain: Domain {
            x: (0.0, 0.0),
            y: (0.6, 2.4),
        },
        nx: 1,
        ny: 37,
        ..ChartSpec::default()
    };
    let chart = sweep(&spec, &|_| {}).unwrap();
    let phi = spec.construction.phi_max;
    for c in &chart.cells {
        let f = liftoff_angles(c.y, phi).unwrap();
        let want = if c.style == Style::Right { f.right } else { f.wrong };
        let got = c.result.as_ref().unwrap().liftoff_theta.unwrap();
        assert!(
            (got - want).to_degrees().abs() < 0.01,
            "{} {:?}: {} vs {}",
            c.y,
            c.style,
            got,
            want
        );
    }
}

#[test]
fn right_region_lies_below_wrong_region() {
    let spec = ChartSpec::default();
    let chart = sweep(&spec, &|_| {}).unwrap();
    assert_eq!(chart.errors(), 0);
    let ys = spec.ys();
    let rows = |style: Style| -> Vec<usize> {
        (0..spec.ny)
            .map(|j| {
                (0..spec.nx)
                    .filter(|&i| chart.cell(i, j, style).unwrap().sustained().is_some())
                    .count()
            })
            .collect()
    };
    let (right, wrong) = (rows(Style::Right), rows(Style::Wrong));
    let centroid = |counts: &[usize]| {
        let n: usize = counts.iter().sum();
        counts.iter().zip(&ys).map(|(c, y)| *c as f64 * y).sum::<f64>() / n as f64
    };
    assert!(centroid(&right) + 0.3 < centroid(&wrong), "{right:?} {wrong:?}");
    // Bottom row mostly right, top row all wrong (Section 4.2).
    assert!(right[0] > wrong[0], "{right:?} {wrong:?}");
    assert_eq!(right[spec.ny - 1], 0);
    assert_eq!(wrong[spec.ny - 1], spec.nx);
    // Half up, the right region's upper boundary moves down (Section 4.4).
    let half = ChartSpec {
        config: SimConfig {
            theta0: 90f64.to_radians(),
            ..SimConfig::default()
        },
        styles: Styles::Right,
        ..spec
    };
    let hc = sweep(&half, &|_| {}).unwrap();
    let top = |c: &Chart| {
        (0..spec.ny)
            .rev()
            .find(|&j| (0..spec.nx).any(|i| c.cell(i, j, Style::Right).unwrap().sustained().is_some()))
    };
    assert!(top(&hc).unwrap() < top(&chart).unwrap());
}

/// `b` is `a` mirrored bit for bit: every angle and rate negated, every
/// side swapped, times, work and verdict the same.
fn exact_mirror(a: &Stroke, b: &Stroke) -> Result<(), String> {
    use clapper_core::stroke::{AfterEnd, Impact};
    let neg = |y: [f64; 4]| y.map(|v| -v);
    let imp = |i: &Impact| Impact {
        theta: -i.theta,
        phi_dot_before: -i.phi_dot_before,
        phi_dot_after: i.phi_dot_after.map(|v| -v),
        side: i.side.opposite(),
        ..*i
    };
    let moment = |m: &Option<clapper_core::stroke::Moment>| m.map(|m| (m.t, -m.theta));
    let checks = [
        ("start", a.start.t == b.start.t && neg(a.start.y) == b.start.y),
        ("start side", a.start_side == b.start_side.opposite()),
        ("style", a.style == b.style),
        (
            "impacts",
            a.impacts.len() == b.impacts.len() && a.impacts.iter().zip(&b.impacts).all(|(p, q)| imp(p) == *q),
        ),
        (
            "lift-off",
            moment(&a.liftoff) == b.liftoff.map(|m| (m.t, m.theta)) && a.liftoff_kind == b.liftoff_kind,
        ),
        (
            "rest",
            moment(&a.rest_after_strike) == b.rest_after_strike.map(|m| (m.t, m.theta)),
        ),
        ("bottom", moment(&a.bottom) == b.bottom.map(|m| (m.t, m.theta))),
        (
            "end",
            a.end.t == b.end.t
                && neg(a.end.y) == b.end.y
                && a.end.reason == b.end.reason
                && a.end.side() == b.end.side().opposite(),
        ),
        (
            "after end",
            match (&a.after_end, &b.after_end) {
                (Some(AfterEnd::Impact(p)), Some(AfterEnd::Impact(q))) => imp(p) == *q,
                (Some(AfterEnd::Rested(p)), Some(AfterEnd::Rested(q))) => (p.t, -p.theta) == (q.t, q.theta),
                (p, q) => p == q,
            },
        ),
        ("work", a.stats == b.stats && a.events == b.events),
    ];
    match checks.iter().find(|(_, ok)| !ok) {
        Some((what, _)) => Err(format!("{what}: {a:?}\n vs {b:?}")),
        None => Ok(()),
    }
}

/// Friction and damping are odd in the rates, so a bell that has them but
/// no pivot offset or skew is its own mirror image: at every point of a
/// chart its backstroke is its handstroke mirrored, bit for bit, and the
/// chart, which takes the backstroke by that symmetry and rings one stroke
/// a cell, says what ringing both would (issue 45).
#[test]
fn friction_bells_take_their_backstroke_by_symmetry() {
    use clapper_core::chart::{sweep_cells_counting, StrokeSummary};
    use clapper_core::hanging::{Friction, Hanging};
    use clapper_core::ringing::backstroke;
    use clapper_core::stroke::Integrator;
    use std::sync::atomic::{AtomicU64, Ordering};
    let f = Friction::default();
    let penalty = SimConfig {
        contact: ContactModel::Penalty,
        ..SimConfig::default()
    };
    let dopri5 = SimConfig {
        integrator: Integrator::Dopri5,
        ..SimConfig::default()
    };
    let cases = [
        (
            Friction {
                clapper_friction: 0.05,
                ..f
            },
            SimConfig::default(),
            30,
        ),
        (Friction { bell_damping: 0.5, ..f }, SimConfig::default(), 30),
        (
            Friction {
                bell_friction: 2.0,
                clapper_damping: 0.01,
                ..f
            },
            SimConfig::default(),
            30,
        ),
        (
            Friction {
                clapper_friction: 0.1,
                bell_damping: 0.2,
                ..f
            },
            dopri5,
            10,
        ),
        (
            Friction {
                bell_damping: 0.5,
                clapper_damping: 0.01,
                ..f
            },
            penalty,
            8,
        ),
    ];
    for (friction, config, n) in cases {
        let hanging = Hanging {
            friction,
            ..Hanging::default()
        };
        let spec = ChartSpec {
            nx: n,
            ny: n,
            config,
            hanging,
            ..ChartSpec::default()
        };
        let rung = AtomicU64::new(0);
        let cells = sweep_cells_counting(&spec, 0..spec.cell_count(), &|_| {}, &|| false, &rung)
            .unwrap()
            .unwrap();
        assert_eq!(rung.load(Ordering::Relaxed), cells.len() as u64, "{friction:?}");
        let mut mirrored = 0;
        for cell in &cells {
            let bell = spec.construction.bell(cell.x, cell.y).unwrap().with_hanging(hanging);
            let hand = first_stroke(&bell, &config, cell.style).unwrap();
            let rung_both = if hand.sustained() {
                let back = backstroke(&bell, &config, &hand).unwrap();
                exact_mirror(&hand, &back).unwrap_or_else(|e| panic!("{friction:?} at {} {}: {e}", cell.x, cell.y));
                mirrored += 1;
                StrokeSummary::of_pair(&hand, &back)
            } else {
                StrokeSummary::from(&hand)
            };
            assert_eq!(cell.result, Ok(rung_both), "{friction:?} at {} {}", cell.x, cell.y);
        }
        assert!(mirrored > n * n / 2, "{friction:?}: {mirrored}");
    }
}
