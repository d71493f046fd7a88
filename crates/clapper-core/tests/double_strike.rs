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

/// The three readings of the amplitude ratio A (docs/model.md §4.1), on
/// the lab bell ringing right. With one coefficient of restitution they
/// are one number (each impact's φ'⁺ is −√R φ'⁻, so the impulse and the
/// energy taken scale with φ'⁻ alike). With R2 the strike's rebound still
/// takes R and the impact after it, a bounce on the same side, takes R2,
/// so the impulse reading is the rate's times (1 + √R2) / (1 + √R) and the
/// vibration reading the rate's times √((1 − R2) / (1 − R)): the
/// restitution law's factors, checked against the recorded rates.
#[test]
fn the_amplitude_ratio_by_rate_impulse_and_vibration() {
    let bell = Bell::lab();
    let one = first_stroke(&bell, &SimConfig::default(), Style::Right).unwrap();
    let rate = one.amplitude_ratio().unwrap();
    for how in StrikeAmplitude::ALL {
        let a = one.amplitude_ratio_by(*how).unwrap();
        assert!((a / rate - 1.0).abs() < 1e-12, "{how}: {a} against {rate}");
    }
    let (r, r2) = (0.05, 0.5);
    let base = SimConfig {
        restitution: r,
        restitution_later: Some(r2),
        ..SimConfig::default()
    };
    let two = first_stroke(&bell, &base, Style::Right).unwrap();
    let (first, second) = (two.first_strike().unwrap(), two.second_strike().unwrap());
    assert_eq!(
        first.side, second.side,
        "the impact after the strike is a bounce on its side"
    );
    let rate = two.amplitude_ratio_by(StrikeAmplitude::Rate).unwrap();
    let impulse = two.amplitude_ratio_by(StrikeAmplitude::Impulse).unwrap();
    let vibration = two.amplitude_ratio_by(StrikeAmplitude::Vibration).unwrap();
    let want_impulse = rate * (1.0 + r2.sqrt()) / (1.0 + r.sqrt());
    let want_vibration = rate * ((1.0 - r2) / (1.0 - r)).sqrt();
    assert!((impulse / want_impulse - 1.0).abs() < 1e-12, "{impulse} {want_impulse}");
    assert!(
        (vibration / want_vibration - 1.0).abs() < 1e-12,
        "{vibration} {want_vibration}"
    );
    // The configured reading is the stroke's A and D.
    let by_vibration = first_stroke(
        &bell,
        &SimConfig {
            strike_amplitude: StrikeAmplitude::Vibration,
            ..base
        },
        Style::Right,
    )
    .unwrap();
    assert_eq!(by_vibration.amplitude_ratio(), Some(vibration));
    let dt = two.second_strike_delay().unwrap() * 1e3;
    assert_eq!(
        by_vibration.double_strike_index(),
        Some(clapper_core::stroke::double_strike_index(vibration, dt))
    );
    assert!(by_vibration.double_strike_index() < two.double_strike_index());
}
