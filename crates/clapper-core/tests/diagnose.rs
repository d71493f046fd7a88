//! Diagnosis: tower measurements against mass properties, the lab bell's
//! verdict, suggestions that really work, ring outliers.

use clapper_core::bell::TowerMeasurements;
use clapper_core::diagnose::{adjusted, diagnose, ring_outliers, DiagnoseConfig, Problem};
use clapper_core::prelude::*;

/// Periods as a stopwatch over ten oscillations gives them: to 1 ms.
fn as_measured(bell: &Bell) -> Bell {
    let round = |t: f64| (t * 1e3).round() / 1e3;
    TowerMeasurements::new(round(bell.tb()), round(bell.tc()), bell.r, bell.phi_max)
        .bell()
        .unwrap()
        .0
}

#[test]
fn tower_measurements_alone_agree_with_mass_properties() {
    let cfg = DiagnoseConfig::default();
    for bell in [Bell::lab(), Bell::gsm_tenor()] {
        let tower = as_measured(&bell);
        let a = diagnose(&bell, &cfg).unwrap();
        let b = diagnose(&tower, &cfg).unwrap();
        assert!((a.position.0 - b.position.0).abs() / a.position.0 < 0.01);
        assert!((a.position.1 - b.position.1).abs() / a.position.1 < 0.01);
        assert_eq!(a.right.sustained, b.right.sustained);
        assert_eq!(a.wrong.sustained, b.wrong.sustained);
        assert_eq!(a.usual, b.usual);
        assert_eq!(a.min_theta0_right.is_some(), b.min_theta0_right.is_some());
        let da = a.right.strike_theta.unwrap().to_degrees();
        let db = b.right.strike_theta.unwrap().to_degrees();
        assert!((da - db).abs() < 3.0, "{da} vs {db}");
    }
}

#[test]
fn lab_bell_verdict() {
    let d = diagnose(&Bell::lab(), &DiagnoseConfig::default()).unwrap();
    assert!(d.right.sustained && d.wrong.sustained);
    assert_eq!(d.usual, Some(Style::Right));
    // It cannot ring right half up (90 deg), as the paper reports.
    let min = d.min_theta0_right.unwrap().to_degrees();
    assert!(min > 90.0 && min < 171.0, "{min}");
    // It double strikes (Section 4.3: "this bell did indeed tend to produce an audible double strike").
    assert!(d.problems.contains(&Problem::DoubleStrike));
    let f = d.frame.unwrap();
    assert!(
        f.vertical_ratio() > 3.0 && f.vertical_ratio() < 4.0,
        "{}",
        f.vertical_ratio()
    );
}

#[test]
fn a_suggested_change_really_gives_the_promised_result() {
    let cfg = DiagnoseConfig::default();
    let c = ChartConstruction::default();
    // The lab bell (double strike), the late-striking Fig 9(d) bell, and one that rings wrong only.
    for bell in [Bell::lab(), c.bell(-0.005, 1.363).unwrap(), c.bell(0.3, 2.2).unwrap()] {
        let d = diagnose(&bell, &cfg).unwrap();
        assert!(!d.problems.is_empty());
        let s = d.suggestion.expect("a fix within the search range");
        let changed = adjusted(&bell, s.dtc, s.dr).unwrap();
        assert!((changed.r_over_lc() - s.position.0).abs() < 1e-12);
        let after = diagnose(&changed, &cfg).unwrap();
        assert!(after.right.sustained, "rings right after the change");
        for p in &d.problems {
            assert!(!after.problems.contains(p), "{p:?} still there after {s:?}");
        }
        assert_eq!(after.right.strike_theta, s.predicted.strike_theta);
        assert_eq!(after.right.double_strike_index, s.predicted.double_strike_index);
    }
}

#[test]
fn the_bell_that_stands_apart_is_flagged() {
    let c = ChartConstruction::default();
    let cfg = DiagnoseConfig::default();
    let mut ring: Vec<Bell> = [
        (0.40, 1.60),
        (0.38, 1.62),
        (0.42, 1.58),
        (0.36, 1.65),
        (0.40, 1.61),
        (0.37, 1.63),
    ]
    .iter()
    .map(|&(x, y)| c.bell(x, y).unwrap())
    .collect();
    ring.insert(3, c.bell(0.10, 2.25).unwrap());
    let ds: Vec<_> = ring.iter().map(|b| diagnose(b, &cfg).unwrap()).collect();
    let out = ring_outliers(&ds);
    assert_eq!(out.len(), 1, "{out:?}");
    assert_eq!(out[0].index, 3);
    assert!(out[0].reasons.len() >= 2);
    // A tight ring flags nobody.
    assert!(ring_outliers(&[ds[0].clone(), ds[1].clone(), ds[2].clone(), ds[4].clone()]).is_empty());
}
