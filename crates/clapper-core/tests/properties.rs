//! Property tests: every simulation in and well beyond the chart domain ends
//! with a result or a typed error (no panic, no hang), and the model's
//! handstroke/backstroke mirror symmetry holds.

use clapper_core::prelude::*;
use proptest::prelude::*;

/// The contact law and its stiffness (N m/rad; the penalty law's).
type Law = (ContactModel, f64);
const IMPACT: Law = (ContactModel::Impact, clapper_core::contact::DEFAULT_STIFFNESS);
fn penalty(k: f64) -> Law {
    (ContactModel::Penalty, k)
}

fn config(theta0_deg: f64, r: f64, (contact, stiffness): Law) -> SimConfig {
    SimConfig {
        theta0: theta0_deg.to_radians(),
        restitution: r,
        contact,
        stiffness,
        ..SimConfig::default()
    }
}

fn mirrored(bell: &Bell, cfg: &SimConfig, side: Side) -> Result<(Stroke, Stroke), SimError> {
    let a = run_stroke(
        bell,
        cfg,
        StrokeStart::at_rest(bell, cfg, 0.0, cfg.theta0, side),
        &mut (),
    )?;
    let b = run_stroke(
        bell,
        cfg,
        StrokeStart::at_rest(bell, cfg, 0.0, -cfg.theta0, side.opposite()),
        &mut (),
    )?;
    Ok((a, b))
}

fn check_mirror(a: &Stroke, b: &Stroke) -> Result<(), TestCaseError> {
    prop_assert_eq!(a.impacts.len(), b.impacts.len());
    prop_assert_eq!(a.end.reason, b.end.reason);
    prop_assert_eq!(a.sustained(), b.sustained());
    // Mirror images to round-off, which each bounce amplifies: at phi_max
    // 53 deg, L_b/L_c 4.9 (far off the chart; the seed is kept in
    // properties.proptest-regressions) the first impact agreed to 1.1e-9
    // rad and a later bounce to 3.5e-8. A real asymmetry is degrees.
    for (k, (p, q)) in a.impacts.iter().zip(&b.impacts).enumerate() {
        let tol = if k == 0 { 1e-8 } else { 1e-6 };
        prop_assert!((p.theta + q.theta).abs() < tol, "{} {}", p.theta, q.theta);
        prop_assert!((p.phi_dot_before + q.phi_dot_before).abs() < tol * (1.0 + p.phi_dot_before.abs()));
        prop_assert!((p.t - q.t).abs() < tol);
    }
    prop_assert!((a.end.y[0] + b.end.y[0]).abs() < 1e-6);
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 200, ..ProptestConfig::default() })]

    /// Impact model, wide domain: r/L_c -1..2, L_b/L_c 0.2..5, phi_max 5..60 deg,
    /// R 0.001..1, theta0 1..179.9 deg.
    #[test]
    fn impact_model_always_ends_and_is_symmetric(
        x in -1.0f64..2.0, y in 0.2f64..5.0, phi in 5.0f64..60.0,
        r in 0.001f64..=1.0, theta0 in 1.0f64..179.9, right in any::<bool>(),
    ) {
        let c = ChartConstruction { phi_max: phi.to_radians(), ..ChartConstruction::default() };
        let bell = c.bell(x, y).unwrap();
        let cfg = config(theta0, r, IMPACT);
        let side = if right { Side::Plus } else { Side::Minus };
        match mirrored(&bell, &cfg, side) {
            Ok((a, b)) => {
                check_mirror(&a, &b)?;
                prop_assert!(a.end.t > 0.0 && a.end.y.iter().all(|v| v.is_finite()));
                if let Some(d) = a.double_strike_index() { prop_assert!(d >= 0.0); }
            }
            // A typed error is an acceptable outcome; a panic is not.
            Err(e) => prop_assert!(!e.to_string().is_empty()),
        }
    }

    /// The chart domain proper, both styles, with the defaults of the charts.
    #[test]
    fn chart_domain_gives_results(x in -0.3f64..0.7, y in 0.5f64..2.5, right in any::<bool>()) {
        let bell = ChartConstruction::default().bell(x, y).unwrap();
        let style = if right { Style::Right } else { Style::Wrong };
        let s = first_stroke(&bell, &SimConfig::default(), style);
        prop_assert!(s.is_ok(), "{:?}", s.err());
        let s = s.unwrap();
        prop_assert_eq!(s.end.reason, EndReason::TurningPoint);
        if let Some(v) = s.strike_velocity() {
            // A strike on the side opposite the start moves towards it.
            prop_assert!(v * s.start_side.sign() < 0.0, "{}", v);
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, ..ProptestConfig::default() })]

    /// Penalty model, stiffness up to 1e9 N m/rad.
    #[test]
    fn penalty_model_always_ends_and_is_symmetric(
        x in -1.0f64..2.0, y in 0.2f64..5.0, phi in 5.0f64..60.0,
        r in 0.001f64..=1.0, theta0 in 1.0f64..179.9, logk in 4.0f64..9.0,
    ) {
        let c = ChartConstruction { phi_max: phi.to_radians(), ..ChartConstruction::default() };
        let bell = c.bell(x, y).unwrap();
        let cfg = config(theta0, r, penalty(10f64.powf(logk)));
        match mirrored(&bell, &cfg, Side::Plus) {
            Ok((a, b)) => check_mirror(&a, &b)?,
            Err(e) => prop_assert!(!e.to_string().is_empty()),
        }
    }
}

#[test]
fn out_of_range_settings_are_typed_errors() {
    let bell = Bell::lab();
    for cfg in [
        config(0.0, 0.2, IMPACT),
        config(180.0, 0.2, IMPACT),
        config(171.0, 0.0, IMPACT),
        config(171.0, 1.5, IMPACT),
        config(171.0, f64::NAN, IMPACT),
        config(171.0, 0.2, penalty(-1.0)),
        config(171.0, 0.2, penalty(1e-300)),
        config(171.0, 0.2, penalty(1e13)),
    ] {
        let e = first_stroke(&bell, &cfg, Style::Right).unwrap_err();
        assert!(matches!(e, SimError::Param(_)), "{e}");
        // One short line, numbers readable (1e-300, not 300 digits).
        assert!(e.to_string().len() < 120, "{e}");
    }
    let bad = Bell {
        bell_mass: -3.0,
        ..bell
    };
    assert!(matches!(
        first_stroke(&bad, &SimConfig::default(), Style::Right),
        Err(SimError::Param(p)) if p.field == "bell_mass_kg"
    ));
}

/// A fixed, seeded sample over the wide domain, tallied: every case ends
/// in a result or a typed error within the step and event budgets, and
/// mirrors. Prints the tally (`-- --nocapture`) for docs/reliability.md.
#[test]
fn wide_domain_tally() {
    use clapper_core::listening::SplitMix64;
    let mut rng = SplitMix64::new(2026);
    let mut u = |a: f64, b: f64| a + (b - a) * rng.next_f64();
    let (mut ok, mut sustained, mut errors) = (0, 0, std::collections::BTreeMap::<String, usize>::new());
    let (mut max_steps, mut max_events) = (0u64, 0u32);
    let n_impact = 1000;
    let n_penalty = 40;
    for k in 0..n_impact + n_penalty {
        let (x, y, phi, r, theta0) = (u(-1.0, 2.0), u(0.2, 5.0), u(5.0, 60.0), u(0.001, 1.0), u(1.0, 179.9));
        let contact = if k < n_impact {
            IMPACT
        } else {
            penalty(10f64.powf(u(4.0, 9.0)))
        };
        let c = ChartConstruction {
            phi_max: phi.to_radians(),
            ..ChartConstruction::default()
        };
        let bell = c.bell(x, y).unwrap();
        let cfg = config(theta0, r, contact);
        let side = if k % 2 == 0 { Side::Plus } else { Side::Minus };
        let outcome = std::panic::catch_unwind(|| mirrored(&bell, &cfg, side));
        let outcome = outcome.unwrap_or_else(|_| panic!("panicked at x={x} y={y} phi={phi} R={r} theta0={theta0}"));
        match outcome {
            Ok((a, b)) => {
                ok += 1;
                sustained += a.sustained() as usize;
                check_mirror(&a, &b).unwrap_or_else(|e| panic!("not mirrored at x={x} y={y}: {e}"));
                assert!(a.stats.steps + a.stats.rejected <= cfg.ode.max_steps);
                assert!(a.events <= cfg.max_events);
                max_steps = max_steps.max(a.stats.steps + a.stats.rejected);
                max_events = max_events.max(a.events);
            }
            Err(e) => {
                let kind = format!("{e:?}")
                    .split(['(', ' ', '{'])
                    .next()
                    .unwrap_or("?")
                    .to_string();
                *errors.entry(kind).or_default() += 1;
                assert!(!e.to_string().is_empty() && !e.to_string().contains('\n'));
            }
        }
    }
    println!(
        "wide domain: {} cases ({n_impact} impact, {n_penalty} penalty), {ok} results ({sustained} sustained), errors {errors:?}; most steps {max_steps}, most events {max_events}",
        n_impact + n_penalty
    );
    assert!(ok > (n_impact + n_penalty) / 2, "most cases give results");
}
