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
