//! Issue 47's checks, each against something the touch code does not use:
//! the closed form of a rigid pendulum, the sum of shifted single-bell
//! histories worked here, the energy balance of the tower's oscillator
//! integrated here from the series, and the linearity of forces in the
//! swing directions.

use clapper_core::bell::{Bell, TowerMeasurements};
use clapper_core::stroke::SimConfig;
use clapper_tower::pendulum::Rigid;
use clapper_tower::stroke_loads::{bell_strokes, swing_from_rest};
use clapper_tower::touch::{ring_touch, RingBell, Timing};
use clapper_tower::{FramePlace, Sway, Tower};

/// The example ring of eight (examples/ring-of-eight.csv): periods, r,
/// φ_max and masses, as a tower measures them.
fn ring_of_eight() -> Vec<Bell> {
    [
        (1.30, 1.03, 0.105, 28.0, 180.0, 5.0),
        (1.38, 1.08, 0.111, 28.0, 200.0, 5.5),
        (1.45, 1.15, 0.139, 28.0, 230.0, 6.5),
        (1.55, 1.21, 0.130, 28.0, 280.0, 7.5),
        (1.65, 1.30, 0.169, 28.0, 340.0, 9.0),
        (1.78, 1.19, 0.035, 28.0, 420.0, 11.0),
        (1.95, 1.53, 0.220, 28.0, 560.0, 14.0),
        (2.15, 1.67, 0.242, 30.0, 780.0, 19.0),
    ]
    .into_iter()
    .map(|(tb, tc, r, phi, m_b, m_c)| {
        let mut t = TowerMeasurements::new(tb, tc, r, f64::to_radians(phi));
        t.bell_mass = Some(m_b);
        t.clapper_mass = Some(m_c);
        t.bell().unwrap().0
    })
    .collect()
}

fn ring(bells: &[Bell], swing: impl Fn(usize) -> f64) -> Vec<RingBell> {
    bells
        .iter()
        .enumerate()
        .map(|(i, b)| RingBell {
            name: format!("{}", i + 1),
            bell: *b,
            place: FramePlace {
                swing_deg: swing(i),
                x_m: (i % 4) as f64 - 1.5,
                y_m: if i < 4 { -1.0 } else { 1.0 },
                pivot_height_m: 20.0,
            },
            restitution: None,
        })
        .collect()
}

fn timing(n_bells: usize) -> Timing {
    Timing {
        interval_s: Timing::interval_for_peal_speed(3.0, n_bells, 1.0),
        handstroke_gap: 1.0,
        striking_sd_ms: 0.0,
        seed: 1,
        dt_s: 0.005,
        theta0: None,
    }
}

/// (a) Let go from the balance (179.9 deg) with the clapper tied: the
/// simulated peak horizontal and vertical loads over the weight within 1 %
/// of the rigid pendulum's closed form, for three bells.
#[test]
fn single_bell_from_the_balance_matches_the_closed_form() {
    let theta0 = 179.9f64.to_radians();
    let cfg = SimConfig::default();
    for (name, bell) in [
        ("lab", Bell::lab()),
        ("GSM tenor", Bell::gsm_tenor()),
        ("ring-of-eight tenor", ring_of_eight()[7]),
    ] {
        let rigid = Rigid::of(&bell);
        let tied = rigid.as_bell(&bell);
        let load = swing_from_rest(&tied, &cfg, theta0).unwrap();
        let w = rigid.mass * clapper_core::bell::G;
        let h = load.peak_horizontal() / w;
        let v = 1.0 + load.peak_vertical() / w;
        let (h0, v0) = (rigid.peak_horizontal(theta0), rigid.peak_vertical(theta0));
        eprintln!(
            "{name}: kappa {:.4}, horizontal {h:.4} vs {h0:.4}, vertical {v:.4} vs {v0:.4}",
            rigid.kappa()
        );
        assert!((h / h0 - 1.0).abs() < 0.01, "{name}: horizontal {h} vs {h0}");
        assert!((v / v0 - 1.0).abs() < 0.01, "{name}: vertical {v} vs {v0}");
    }
}

/// (b) Rounds, all bells swinging north-south, each rung from 165 deg so
/// that no stroke runs into the next: the north force is the sum of each
/// bell's handstroke and backstroke histories shifted to its strike times,
/// worked here from the rows' rhythm; the east force is nothing.
#[test]
fn rounds_is_the_sum_of_shifted_single_bell_histories() {
    let bells = ring_of_eight()[..4].to_vec();
    let ring = ring(&bells, |_| 0.0);
    let n = ring.len();
    let theta0 = 165f64.to_radians();
    let t = Timing {
        theta0: Some(theta0),
        ..timing(n)
    };
    let rows: Vec<Vec<u8>> = vec![(0..n as u8).collect(); 12];
    let cfg = SimConfig::default();
    let r = ring_touch(&ring, &rows, &t, &cfg, None).unwrap();
    let tau = t.interval_s;
    let singles: Vec<_> = bells.iter().map(|b| bell_strokes(b, &cfg, theta0).unwrap()).collect();
    // The rows' rhythm: place p of row k at tau (k n + p + (k/2 + 1) gap).
    let starts: Vec<Vec<f64>> = (0..n)
        .map(|b| {
            (0..rows.len())
                .map(|k| {
                    let strike = tau * ((k * n + b) as f64 + (k / 2 + 1) as f64);
                    let s = &singles[b];
                    strike - if k % 2 == 0 { s.hand.to_strike } else { s.back.to_strike }
                })
                .collect()
        })
        .collect();
    for (b, s) in singles.iter().enumerate() {
        for k in 0..rows.len() - 1 {
            let d = if k % 2 == 0 { s.hand.duration } else { s.back.duration };
            assert!(
                starts[b][k] + d < starts[b][k + 1],
                "strokes overlap: the check needs them apart"
            );
        }
    }
    let mut checked = 0;
    for i in (0..r.force_north.len()).step_by(7) {
        let time = r.time(i);
        let mut want = 0.0;
        for (b, s) in singles.iter().enumerate() {
            for (k, &start) in starts[b].iter().enumerate() {
                let load = if k % 2 == 0 { &s.hand } else { &s.back };
                want += load.at(time - start).0;
            }
        }
        assert!(
            (r.force_north[i] - want).abs() < 1e-9 * 5000.0,
            "t {time}: {} vs {want}",
            r.force_north[i]
        );
        assert!(r.force_east[i].abs() < 1e-9 * 5000.0);
        checked += usize::from(want.abs() > 100.0);
    }
    assert!(checked > 500, "{checked}");
}

fn tower() -> Tower {
    Tower {
        east_west: Sway {
            frequency_hz: 1.9,
            damping_ratio: 0.02,
            modal_mass_kg: 150_000.0,
        },
        north_south: Sway {
            frequency_hz: 1.65,
            damping_ratio: 0.02,
            modal_mass_kg: 150_000.0,
        },
    }
}

/// (c) A steady touch (rounds, no striking errors, the first minute left
/// out as the start's transient): the work the tower's damping takes,
/// c ∫ v² dt, equals the work the frame's force puts in, ∫ F dx, within 1 %,
/// both integrated here from the series, in both directions.
#[test]
fn damping_work_equals_input_over_a_steady_touch() {
    let bells = ring_of_eight();
    let ring = ring(&bells, |i| if i % 3 == 0 { 90.0 } else { 0.0 });
    let t = timing(8);
    let rows: Vec<Vec<u8>> = vec![(0..8).collect(); 120];
    let r = ring_touch(&ring, &rows, &t, &SimConfig::default(), Some(&tower())).unwrap();
    let sway = r.sway.as_ref().unwrap();
    let pulls = r.whole_pull_s;
    let first = ((60.0 - r.t0) / r.dt) as usize;
    // A whole number of whole pulls, ending before the last row.
    let n_pulls = ((r.time(r.force_east.len() - 1) - 60.0 - 10.0) / pulls).floor();
    let last = first + (n_pulls * pulls / r.dt).round() as usize;
    for (dir, (force, s, osc)) in [
        (&r.force_east, &sway[0], tower().east_west),
        (&r.force_north, &sway[1], tower().north_south),
    ]
    .into_iter()
    .enumerate()
    {
        let (mut input, mut damping) = (0.0, 0.0);
        for i in first..last {
            let f = 0.5 * (force[i] + force[i + 1]);
            input += f * (s.displacement[i + 1] - s.displacement[i]);
            damping += osc.damping() * r.dt * 0.5 * (s.velocity[i].powi(2) + s.velocity[i + 1].powi(2));
        }
        eprintln!("direction {dir}: input {input:.4} J, damping {damping:.4} J over {n_pulls} whole pulls");
        assert!(input > 0.0);
        assert!((damping / input - 1.0).abs() < 0.01, "{damping} vs {input}");
        // The report's own account: input = damping + stored change.
        let sum = r.sway_summary.unwrap()[dir];
        assert!(
            (sum.input_work_j - sum.damping_work_j - sum.stored_change_j).abs() < 0.01 * sum.input_work_j,
            "{sum:?}"
        );
    }
}

/// Turning bells in the frame: the forces are linear in the swing
/// directions, so turning two bells does what turning each alone does,
/// added (F_both = F_one + F_other − F_neither), and the sway follows; and
/// each bell's `turns` entry is the peak sway of the whole touch rung again
/// with that bell turned.
#[test]
fn turning_two_bells_changes_the_sway_as_the_sum_of_forces_predicts() {
    let bells = ring_of_eight();
    let rows = clapper_tower::touch_rows(
        &clapper_tower::TouchSpec::Method {
            title: "Plain Bob Major".into(),
            place_notation: None,
            stage: None,
            leads: Some(2),
            changes: None,
        },
        8,
    )
    .unwrap();
    let cfg = SimConfig::default();
    let t = Timing {
        striking_sd_ms: 15.0,
        ..timing(8)
    };
    let tw = tower();
    let run = |turned: &[usize]| {
        let mut r = ring(&bells, |_| 0.0);
        for &b in turned {
            r[b].place = r[b].place.turned();
        }
        ring_touch(&r, &rows, &t, &cfg, Some(&tw)).unwrap()
    };
    let base = run(&[]);
    let one = run(&[6]);
    let other = run(&[7]);
    let both = run(&[6, 7]);
    for i in 0..base.force_east.len() {
        for (b, o, n, x) in [
            (&both.force_east, &one.force_east, &other.force_east, &base.force_east),
            (
                &both.force_north,
                &one.force_north,
                &other.force_north,
                &base.force_north,
            ),
        ] {
            assert!((b[i] - (o[i] + n[i] - x[i])).abs() < 1e-6, "sample {i}");
        }
    }
    let (p0, p2) = (base.peak_sway().unwrap(), both.peak_sway().unwrap());
    eprintln!(
        "peak sway all N-S {:.3} mm; bells 7 and 8 turned {:.3} mm",
        p0 * 1e3,
        p2 * 1e3
    );
    assert!(
        (p2 - p0).abs() > 0.01 * p0,
        "turning the two heaviest bells changes the sway"
    );
    for turn in &base.turns {
        let again = run(&[turn.bell]).peak_sway().unwrap();
        assert!(
            (turn.peak_sway_m.unwrap() / again - 1.0).abs() < 1e-9,
            "{turn:?} vs {again}"
        );
    }
}
