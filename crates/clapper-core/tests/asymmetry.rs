//! Asymmetric bells and friction (docs/model.md §10), each checked by a
//! method independent of the equations' derivation: the mirror symmetry,
//! the Euler–Lagrange residual of the Lagrangian written from the
//! positions of the two bodies, the analytic decay of a pendulum with
//! friction, and the energy balance.

use clapper_core::bell::{Bell, G};
use clapper_core::hanging::{Friction, Hanging, SwingDecay, SwingLoss};
use clapper_core::ringing::{odd_struck, ring, Protocol};
use clapper_core::stroke::{run_stroke, EndReason, Observer, Side, SimConfig, StepView, StrokeStart, Style};

fn offset(bell: Bell, d: f64) -> Bell {
    bell.with_hanging(Hanging {
        pivot_offset: d,
        ..bell.hanging
    })
}

fn skewed(bell: Bell, skew_deg: f64) -> Bell {
    bell.with_hanging(Hanging {
        phi_max_skew: skew_deg.to_radians(),
        ..bell.hanging
    })
}

/// Offset d → −d, or the two contact angles swapped, swaps handstroke and
/// backstroke; odd-struckness is exactly antisymmetric.
#[test]
fn mirror_swaps_handstroke_and_backstroke() {
    let cfg = SimConfig::default();
    for (plus, minus) in [
        (offset(Bell::gsm_tenor(), 0.004), offset(Bell::gsm_tenor(), -0.004)),
        (skewed(Bell::lab(), 0.3), skewed(Bell::lab(), -0.3)),
        (
            skewed(offset(Bell::lab(), 0.002), 0.2),
            skewed(offset(Bell::lab(), -0.002), -0.2),
        ),
    ] {
        for style in [Style::Right, Style::Wrong] {
            let a = odd_struck(&plus, &cfg, style).unwrap();
            let b = odd_struck(&minus, &cfg, style).unwrap();
            for (s, m) in [(&a.hand, &b.back), (&a.back, &b.hand)] {
                let (ts, tm) = (s.strike_angle().unwrap(), m.strike_angle().unwrap());
                assert!((ts + tm).abs() < 1e-9, "{ts} vs {tm}");
                let (vs, vm) = (s.strike_velocity().unwrap(), m.strike_velocity().unwrap());
                assert!((vs + vm).abs() < 1e-9, "{vs} vs {vm}");
                let (bs, bm) = (s.bdc_to_strike().unwrap(), m.bdc_to_strike().unwrap());
                assert!((bs - bm).abs() < 1e-9, "{bs} vs {bm}");
            }
            let (oa, ob) = (a.odd_struck().unwrap(), b.odd_struck().unwrap());
            assert!(oa != 0.0, "an asymmetric bell is odd-struck");
            assert_eq!(oa, -ob, "exactly antisymmetric");
        }
    }
    // And a symmetric bell is exactly not odd-struck.
    let sym = odd_struck(&Bell::lab(), &cfg, Style::Right).unwrap();
    assert_eq!(sym.odd_struck(), Some(0.0));
}

/// Numbers a + b ε with ε² = 0: derivatives exact to rounding, for the
/// Lagrangian's partial derivatives.
#[derive(Clone, Copy, Debug)]
struct Dual(f64, f64);

impl std::ops::Add for Dual {
    type Output = Dual;
    fn add(self, o: Dual) -> Dual {
        Dual(self.0 + o.0, self.1 + o.1)
    }
}
impl std::ops::Sub for Dual {
    type Output = Dual;
    fn sub(self, o: Dual) -> Dual {
        Dual(self.0 - o.0, self.1 - o.1)
    }
}
impl std::ops::Mul for Dual {
    type Output = Dual;
    fn mul(self, o: Dual) -> Dual {
        Dual(self.0 * o.0, self.0 * o.1 + self.1 * o.0)
    }
}
impl Dual {
    fn c(v: f64) -> Dual {
        Dual(v, 0.0)
    }
    fn sin(self) -> Dual {
        Dual(self.0.sin(), self.1 * self.0.cos())
    }
    fn cos(self) -> Dual {
        Dual(self.0.cos(), -self.1 * self.0.sin())
    }
}

/// The Lagrangian T − V of the bell and clapper written from positions in
/// the tower's frame (x across, y up): the bell turns by θ about its
/// pivot; the clapper pivot sits at r along the bell's axis and d across
/// it; the clapper's centre of mass at b from its pivot, at θ + φ from the
/// downward vertical. Velocities are the derivatives of the positions
/// (chain rule through dual numbers), not a hand-derived kinetic energy.
fn lagrangian(bell: &Bell, q: [Dual; 2], qd: [Dual; 2]) -> Dual {
    let (r, d, b) = (Dual::c(bell.r), Dual::c(bell.hanging.pivot_offset), Dual::c(bell.b));
    let pos = |th: Dual, ph: Dual| {
        let x = r * th.sin() + d * th.cos() + b * (th + ph).sin();
        let y = Dual::c(0.0) - r * th.cos() + d * th.sin() - b * (th + ph).cos();
        (x, y)
    };
    // v = ∂G/∂θ θ' + ∂G/∂φ φ', the partials by a fourth-order difference
    // of the positions (dual-valued, so the outer derivative rides along).
    let h = 1e-3;
    let grad = |dt: f64, dp: f64| {
        let at = |k: f64| pos(q[0] + Dual::c(k * dt), q[1] + Dual::c(k * dp));
        let (x1, y1) = at(h);
        let (x2, y2) = at(-h);
        let (x3, y3) = at(2.0 * h);
        let (x4, y4) = at(-2.0 * h);
        let w =
            |a: Dual, bb: Dual, c3: Dual, c4: Dual| (Dual::c(8.0) * (a - bb) - (c3 - c4)) * Dual::c(1.0 / (12.0 * h));
        (w(x1, x2, x3, x4), w(y1, y2, y3, y4))
    };
    let (gxt, gyt) = grad(1.0, 0.0);
    let (gxp, gyp) = grad(0.0, 1.0);
    let vx = gxt * qd[0] + gxp * qd[1];
    let vy = gyt * qd[0] + gyp * qd[1];
    let (m, ig) = (
        Dual::c(bell.clapper_mass),
        Dual::c(bell.clapper_inertia - bell.clapper_mass * bell.b * bell.b),
    );
    let w = qd[0] + qd[1];
    let half = Dual::c(0.5);
    let t = half * Dual::c(bell.bell_inertia) * qd[0] * qd[0] + half * m * (vx * vx + vy * vy) + half * ig * w * w;
    let (_, yg) = pos(q[0], q[1]);
    let v = Dual::c(bell.bell_mass * G * bell.a) * (Dual::c(0.0) - q[0].cos()) + m * Dual::c(G) * yg;
    t - v
}

/// ∂L/∂(component k of z), z = (θ, φ, θ', φ').
fn partial(bell: &Bell, y: &[f64; 4], k: usize) -> f64 {
    let z: [Dual; 4] = std::array::from_fn(|i| Dual(y[i], if i == k { 1.0 } else { 0.0 }));
    lagrangian(bell, [z[0], z[1]], [z[2], z[3]]).1
}

/// Collects the Euler–Lagrange residual inside every step.
struct Residual<'a> {
    bell: &'a Bell,
    h: f64,
    worst: f64,
    checked: usize,
}

impl Observer for Residual<'_> {
    fn on_step(&mut self, step: &StepView<'_>) {
        let h = self.h;
        let (a, b) = (step.t_from() + 2.0 * h, step.t_to() - 2.0 * h);
        if b <= a {
            return;
        }
        for k in 0..3 {
            let t = a + (b - a) * (k as f64 + 0.5) / 3.0;
            let s = step.sample(t);
            let load = step.friction().unwrap_or_default();
            // d/dt ∂L/∂q' by a fourth-order difference along the trajectory.
            let p = |dt: f64, i: usize| partial(self.bell, &step.sample(t + dt).y, i);
            for (i, q) in [(2usize, 0usize), (3, 1)] {
                let dpdt = (8.0 * (p(h, i) - p(-h, i)) - (p(2.0 * h, i) - p(-2.0 * h, i))) / (12.0 * h);
                let force = if q == 0 {
                    load.theta(&s.y)
                } else {
                    s.contact_force + load.phi(&s.y)
                };
                let res = dpdt - partial(self.bell, &s.y, q) - force;
                self.worst = self.worst.max(res.abs());
            }
            self.checked += 1;
        }
    }
}

/// The equations with an offset (and viscous friction) satisfy the
/// Euler–Lagrange equations of the Lagrangian built from positions, along
/// a simulated stroke, flight and rest alike.
#[test]
fn offset_equations_satisfy_euler_lagrange_along_a_stroke() {
    let bell = Bell::gsm_tenor().with_hanging(Hanging {
        pivot_offset: 0.02,
        phi_max_skew: 0.02,
        friction: Friction {
            bell_damping: 3.0,
            clapper_damping: 0.4,
            ..Friction::default()
        },
    });
    let mut cfg = SimConfig::default();
    cfg.ode.rtol = 1e-13;
    cfg.ode.atol = 1e-13;
    let start = StrokeStart::at_rest(&bell, &cfg, 0.0, cfg.theta0, Side::Plus);
    let mut obs = Residual {
        bell: &bell,
        h: 2e-3,
        worst: 0.0,
        checked: 0,
    };
    let stroke = run_stroke(&bell, &cfg, start, &mut obs).unwrap();
    assert!(stroke.first_strike().is_some());
    let scale = (bell.bell_mass * bell.a + bell.clapper_mass * bell.r) * G;
    assert!(obs.checked > 50, "{}", obs.checked);
    println!(
        "Euler-Lagrange residual {:.2e} of the gravity scale over {} points",
        obs.worst / scale,
        obs.checked
    );
    assert!(obs.worst / scale < 1e-8, "residual {} N m of {scale} N m", obs.worst);
}

/// Amplitudes (rad) about the tied bell's equilibrium at successive
/// turning points, and their times (s).
fn tied_swings(bell: &Bell, amplitude: f64, strokes: usize) -> (Vec<f64>, Vec<f64>, f64, f64) {
    // Tied: the clapper held at its + stop by a pivot no torque of the
    // swing can turn (1e5 N m: hundreds of times the clapper's gravity
    // torque, under the bound a hanging is refused beyond).
    let bell = bell.with_hanging(Hanging {
        friction: Friction {
            clapper_friction: 1e5,
            ..bell.hanging.friction
        },
        ..bell.hanging
    });
    let phi = bell.phi_max;
    let (ma, mb) = (
        bell.bell_mass * bell.a + bell.clapper_mass * bell.r,
        bell.clapper_mass * bell.b,
    );
    // One cosine: V = −K cos(θ − θe).
    let theta_e = (-mb * phi.sin()).atan2(ma + mb * phi.cos());
    let k = G * ((ma + mb * phi.cos()).powi(2) + (mb * phi.sin()).powi(2)).sqrt();
    let j = bell.bell_inertia
        + bell.clapper_inertia
        + bell.clapper_mass * bell.r * bell.r
        + 2.0 * bell.clapper_mass * bell.r * bell.b * phi.cos();
    let mut cfg = SimConfig {
        theta0: theta_e + amplitude,
        ..SimConfig::default()
    };
    cfg.ode.rtol = 1e-12;
    cfg.ode.atol = 1e-12;
    let r = ring(&bell, &cfg, Style::Right, Protocol::Free, strokes, &mut ()).unwrap();
    let mut amps = vec![amplitude];
    let mut times = vec![0.0];
    for s in &r.strokes {
        assert!(s.start.clapper.is_at_rest(), "the clapper stays tied");
        if s.end.reason == EndReason::TurningPoint {
            amps.push((s.end.y[0] - theta_e).abs());
            times.push(s.end.t);
        }
    }
    (amps, times, k, j)
}

/// Viscous damping at the bearings: the tied bell's small swing decays as
/// exp(−c t / 2J).
#[test]
fn viscous_bearing_damping_decays_at_the_analytic_rate() {
    let c = 0.8;
    let bell = Bell::lab().with_hanging(Hanging {
        friction: Friction {
            bell_damping: c,
            ..Friction::default()
        },
        ..Hanging::default()
    });
    let (amps, times, _, j) = tied_swings(&bell, 4f64.to_radians(), 8);
    assert_eq!(amps.len(), 9);
    let n = amps.len() - 1;
    let rate = (amps[0] / amps[n]).ln() / (times[n] - times[0]);
    let want = c / (2.0 * j);
    println!(
        "viscous decay rate {rate:.6} 1/s, analytic {want:.6} 1/s, error {:.2e}",
        rate / want - 1.0
    );
    assert!((rate / want - 1.0).abs() < 0.005, "{rate} vs {want} 1/s");
}

/// Coulomb friction at the bearings: the tied bell's small swing loses
/// 2τ/K of amplitude each swing (4τ/K a period), linearly, then stops.
#[test]
fn coulomb_bearing_friction_loses_four_tau_over_k_a_period() {
    let bell0 = Bell::lab();
    let (_, _, k, _) = tied_swings(&bell0, 0.05, 1);
    let tau = 0.0015 * k;
    let bell = bell0.with_hanging(Hanging {
        friction: Friction {
            bell_friction: tau,
            ..Friction::default()
        },
        ..Hanging::default()
    });
    let (amps, _, k, _) = tied_swings(&bell, 4f64.to_radians(), 8);
    assert_eq!(amps.len(), 9);
    for pair in amps.windows(3) {
        let per_period = pair[0] - pair[2];
        println!(
            "Coulomb loss per period / (4 tau/K) - 1 = {:.2e}",
            per_period / (4.0 * tau / k) - 1.0
        );
        assert!(
            (per_period / (4.0 * tau / k) - 1.0).abs() < 0.005,
            "{per_period} vs {}",
            4.0 * tau / k
        );
    }
    // Rung long enough, it stops: held by the friction.
    let (amps, ..) = tied_swings(&bell, 4f64.to_radians(), 60);
    assert!(amps.len() < 61 && *amps.last().unwrap() <= 2.0 * tau / k, "{amps:?}");
}

/// King's timings read back: the friction `SwingDecay` gives for "halves in
/// N swings" does halve the simulated tied bell's swing in N swings, for
/// either kind of loss; and `bell_tied`'s pendulum is the simulated one.
#[test]
fn swings_to_halve_give_the_friction_that_halves_the_swing() {
    // The tied pendulum of `tied_swings` is tied at φ_max; at a tiny φ_max
    // it is `bell_tied`'s, tied at φ = 0.
    let narrow = Bell {
        phi_max: 1e-7,
        ..Bell::lab()
    };
    let (_, _, k, j) = tied_swings(&narrow, 0.05, 1);
    let tied = SwingDecay::bell_tied(&narrow, 10.0);
    assert!((tied.inertia / j - 1.0).abs() < 1e-12 && (tied.stiffness / k - 1.0).abs() < 1e-12);

    let bell0 = Bell::lab();
    let (_, _, k, j) = tied_swings(&bell0, 0.05, 1);
    let amplitude = 4f64.to_radians();
    for (loss, n) in [(SwingLoss::Viscous, 6usize), (SwingLoss::Coulomb, 6)] {
        let decay = SwingDecay {
            swings_to_halve: n as f64,
            inertia: j,
            stiffness: k,
        };
        let v = decay.friction(loss, Some(amplitude)).unwrap();
        let friction = match loss {
            SwingLoss::Viscous => Friction {
                bell_damping: v,
                ..Friction::default()
            },
            SwingLoss::Coulomb => Friction {
                bell_friction: v,
                ..Friction::default()
            },
        };
        let bell = bell0.with_hanging(Hanging {
            friction,
            ..Hanging::default()
        });
        let (amps, ..) = tied_swings(&bell, amplitude, n);
        let ratio = amps[n] / amps[0];
        println!("{loss}: after {n} swings the amplitude is {ratio:.5} of the start");
        assert!((ratio - 0.5).abs() < 0.0025, "{loss}: {ratio}");
    }
    assert!(tied.friction(SwingLoss::Coulomb, None).is_err());
}

/// Energy: with R = 1 (no loss at impacts) the energy lost over a free run
/// equals the work of friction along it, to 1e-6.
#[test]
fn energy_lost_is_the_work_of_friction() {
    struct Work(f64);
    impl Observer for Work {
        fn on_step(&mut self, step: &StepView<'_>) {
            let Some(load) = step.friction() else { return };
            // Gauss–Legendre, 5 points: exact for the step's smooth power.
            const X: [f64; 5] = [
                0.0,
                -0.538_469_310_105_683,
                0.538_469_310_105_683,
                -0.906_179_845_938_664,
                0.906_179_845_938_664,
            ];
            const W: [f64; 5] = [
                0.568_888_888_888_889,
                0.478_628_670_499_366,
                0.478_628_670_499_366,
                0.236_926_885_056_189,
                0.236_926_885_056_189,
            ];
            let (a, b) = (step.t_from(), step.t_to());
            let (mid, half) = (0.5 * (a + b), 0.5 * (b - a));
            for (x, w) in X.iter().zip(W) {
                self.0 += w * half * load.power(&step.sample(mid + half * x).y);
            }
        }
    }
    let bell = Bell::gsm_tenor().with_hanging(Hanging {
        pivot_offset: 0.01,
        phi_max_skew: 0.01,
        friction: Friction {
            bell_damping: 20.0,
            bell_friction: 15.0,
            clapper_damping: 0.3,
            clapper_friction: 2.0,
        },
    });
    let mut cfg = SimConfig {
        restitution: 1.0,
        ..SimConfig::default()
    };
    cfg.ode.rtol = 1e-11;
    cfg.ode.atol = 1e-11;
    let mut work = Work(0.0);
    let r = ring(&bell, &cfg, Style::Right, Protocol::Free, 3, &mut work).unwrap();
    // Energy from the same Lagrangian: E = θ' ∂L/∂θ' + φ' ∂L/∂φ' − L.
    let energy = |y: &[f64; 4]| {
        let l = lagrangian(&bell, [Dual::c(y[0]), Dual::c(y[1])], [Dual::c(y[2]), Dual::c(y[3])]).0;
        y[2] * partial(&bell, y, 2) + y[3] * partial(&bell, y, 3) - l
    };
    let first = r.strokes.first().unwrap().start.y;
    let last = r.strokes.last().unwrap().end.y;
    let lost = energy(&last) - energy(&first);
    assert!(work.0 < 0.0);
    println!(
        "energy change {lost:.9} J, friction work {:.9} J, relative {:.2e}",
        work.0,
        (lost - work.0) / work.0
    );
    assert!(((lost - work.0) / work.0).abs() < 1e-6, "{lost} J vs {} J", work.0);
}

/// Bounces on a damped bell settle: the rest test after each impact judges
/// the next flight with the friction in it. Without that, at this point of
/// the paper's chart the backstroke's clapper bounced on its resting side
/// ever faster (a Zeno sequence) until the event limit. And no point of a
/// chart with friction of each kind fails to simulate.
#[test]
fn bounces_on_a_damped_bell_settle_everywhere_on_the_chart() {
    use clapper_core::chart::{sweep, ChartSpec};
    let damped = Hanging {
        friction: Friction {
            bell_damping: 0.5,
            clapper_damping: 0.05,
            ..Friction::default()
        },
        ..Hanging::default()
    };
    let spec = ChartSpec {
        nx: 60,
        ny: 60,
        hanging: damped,
        ..ChartSpec::default()
    };
    let bell = spec
        .construction
        .bell(spec.xs()[5], spec.ys()[11])
        .unwrap()
        .with_hanging(damped);
    let pair = odd_struck(&bell, &spec.config, Style::Right).unwrap();
    assert_eq!(pair.back.end.reason, EndReason::TurningPoint);
    assert!(pair.back.rest_after_strike.is_some() || pair.back.first_strike().is_none());
    for friction in [
        damped.friction,
        Friction {
            bell_friction: 0.5,
            clapper_friction: 0.05,
            ..Friction::default()
        },
        Friction {
            bell_damping: 0.5,
            bell_friction: 0.5,
            clapper_damping: 0.05,
            clapper_friction: 0.05,
        },
    ] {
        let chart = sweep(
            &ChartSpec {
                hanging: Hanging {
                    friction,
                    ..Hanging::default()
                },
                ..spec
            },
            &|_| {},
        )
        .unwrap();
        let failed: Vec<_> = chart.cells.iter().filter(|c| c.result.is_err()).collect();
        assert!(failed.is_empty(), "{friction:?}: {failed:?}");
    }
}

/// Friction at the clapper's pivot holds a resting clapper until the
/// holding force pulls by τ_c: the closed-form first phase (Taylor path,
/// lift-off at that level) and Dormand–Prince integrating the phase agree
/// on the lift-off and the strike.
#[test]
fn pivot_friction_lifts_off_alike_in_closed_form_and_integrated() {
    use clapper_core::bell::ChartConstruction;
    use clapper_core::ringing::first_stroke;
    use clapper_core::stroke::Integrator;
    let tight = |integrator| {
        let mut cfg = SimConfig {
            integrator,
            ..SimConfig::default()
        };
        (cfg.ode.rtol, cfg.ode.atol) = (1e-11, 1e-11);
        cfg
    };
    let construction = ChartConstruction::default();
    let (mut worst_liftoff, mut worst_strike, mut compared) = (0.0f64, 0.0f64, 0);
    for tau in [0.05, 0.5] {
        for (x, y) in [(-0.2, 0.9), (0.1, 1.3), (0.3, 1.7), (0.5, 2.1)] {
            let bell = construction.bell(x, y).unwrap();
            let bell = bell.with_hanging(Hanging {
                friction: Friction {
                    clapper_friction: tau,
                    ..Friction::default()
                },
                ..bell.hanging
            });
            for style in [Style::Right, Style::Wrong] {
                let a = first_stroke(&bell, &tight(Integrator::Taylor), style).unwrap();
                let b = first_stroke(&bell, &tight(Integrator::Dopri5), style).unwrap();
                assert_eq!(a.liftoff.is_some(), b.liftoff.is_some());
                if let (Some(p), Some(q)) = (a.liftoff_angle(), b.liftoff_angle()) {
                    worst_liftoff = worst_liftoff.max((p - q).abs().to_degrees());
                    compared += 1;
                }
                if let (Some(p), Some(q)) = (a.strike_angle(), b.strike_angle()) {
                    worst_strike = worst_strike.max((p - q).abs().to_degrees());
                }
            }
        }
    }
    assert!(compared >= 8, "{compared}");
    assert!(worst_liftoff < 1e-6, "lift-off angles differ by {worst_liftoff} deg");
    assert!(worst_strike < 1e-5, "strike angles differ by {worst_strike} deg");
}

/// A run watched by no observer passes through the apexes of the
/// clapper's flight inside the stepper (the Coulomb torque turned in
/// place, issue 45); a watched run stops at each and starts a new
/// segment. The two give the same strokes to the bit: every impact, the
/// lift-off, rest and end, the events handled and the steps taken, for
/// the paper's chart with Coulomb friction at the clapper's pivot alone
/// and with everything else a real bell has.
#[test]
fn apexes_passed_in_the_stepper_change_no_stroke() {
    use clapper_core::chart::ChartSpec;
    use clapper_core::stroke::Sample;
    /// Watches the jumps (so the stepper stops at every apex) and counts them.
    struct Jumps(u32);
    impl Observer for Jumps {
        fn on_jump(&mut self, _before: &Sample, _after: &Sample) {
            self.0 += 1;
        }
    }
    let spec = ChartSpec::default();
    let grip = Friction {
        clapper_friction: 0.05,
        ..Friction::default()
    };
    let everything = Hanging {
        pivot_offset: 0.003,
        phi_max_skew: 0.01,
        friction: Friction {
            bell_damping: 0.5,
            bell_friction: 1.0,
            clapper_damping: 0.01,
            clapper_friction: 0.1,
        },
    };
    let mut apexes = 0;
    for hanging in [
        Hanging {
            friction: grip,
            ..Hanging::default()
        },
        everything,
    ] {
        for y in spec.ys() {
            for x in spec.xs() {
                let bell = spec.construction.bell(x, y).unwrap().with_hanging(hanging);
                for (theta0, side) in [(1.0, Side::Plus), (1.0, Side::Minus), (-1.0, Side::Minus)] {
                    let cfg = &spec.config;
                    let start = StrokeStart::at_rest(&bell, cfg, 0.0, theta0 * cfg.theta0, side);
                    let silent = run_stroke(&bell, cfg, start, &mut ()).unwrap();
                    let mut jumps = Jumps(0);
                    let watched = run_stroke(&bell, cfg, start, &mut jumps).unwrap();
                    assert_eq!(silent, watched, "{hanging:?} at {x} {y}");
                    // Jumps: the start, the end and one an event; impacts
                    // and the bottom are events too, the rest are apexes
                    // (and a stuck clapper's breakaway).
                    apexes += jumps.0 - 2 - watched.impacts.len() as u32;
                }
            }
        }
    }
    assert!(apexes > 1000, "{apexes}");
}
