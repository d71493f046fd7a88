//! The double strike's second impact, followed past the turning point
//! (docs/model.md §4): D is never a 0 standing for "no second impact".

use clapper_core::bell::ChartConstruction;
use clapper_core::prelude::*;
use clapper_core::stroke::AfterEnd;

/// At (0, 0.6), R = 0.2, ringing right, the bell turns before the clapper
/// comes back: its second impact is 685 ms after the first strike with
/// A = 0.40, so D is about 59 (the figures of the independent
/// re-implementation in issue 21), where the stroke alone gave D = 0.
#[test]
fn the_second_impact_after_the_turning_point_gives_d() {
    let bell = ChartConstruction::default().bell(0.0, 0.6).unwrap();
    let s = first_stroke(&bell, &SimConfig::default(), Style::Right).unwrap();
    assert!(matches!(s.after_end, Some(AfterEnd::Impact(_))), "{:?}", s.after_end);
    // The stroke itself is as it was: it ends at the turning point with
    // only the first strike after its lift-off.
    assert_eq!(s.strikes().len(), 1);
    let dt = s.second_strike_delay().unwrap() * 1e3;
    let a = s.amplitude_ratio().unwrap();
    assert!((dt - 685.0).abs() < 1.0, "dt12 {dt} ms");
    assert!((a - 0.40).abs() < 0.01, "A {a}");
    let d = s.double_strike_index().unwrap();
    assert!((d - 59.0).abs() < 1.0, "D {d}");
    assert_eq!(s.no_second_impact(), None);
}

/// Over the chart at R = 0.2 every stroke that strikes has D or a reason
/// why not, never both; and every bell that sustains ringing right has D.
#[test]
fn every_strike_has_d_or_a_reason() {
    let c = ChartConstruction::default();
    let cfg = SimConfig::default();
    let mut followed = 0;
    for i in 0..12 {
        for j in 0..12 {
            let (r, lb) = (-0.3 + i as f64 / 11.0, 0.5 + 2.0 * j as f64 / 11.0);
            let bell = c.bell(r, lb).unwrap();
            for style in [Style::Right, Style::Wrong] {
                let s = first_stroke(&bell, &cfg, style).unwrap();
                if s.first_strike().is_none() {
                    assert_eq!(s.double_strike_index(), None);
                    continue;
                }
                assert!(
                    s.double_strike_index().is_some() != s.no_second_impact().is_some(),
                    "({r:.3}, {lb:.3}) {style:?}: D {:?}, reason {:?}",
                    s.double_strike_index(),
                    s.no_second_impact()
                );
                if style == Style::Right && s.sustained() {
                    assert!(
                        s.double_strike_index().is_some(),
                        "({r:.3}, {lb:.3}): {:?}",
                        s.no_second_impact()
                    );
                }
                followed += usize::from(matches!(s.after_end, Some(AfterEnd::Impact(_))));
            }
        }
    }
    assert!(followed > 0, "no stroke needed following past its end");
}
