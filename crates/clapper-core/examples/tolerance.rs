//! How each integrator trades speed for accuracy on the paper's 20 x 20
//! chart (both styles, impact model): for each integrator and rtol (=
//! atol), the time per stroke on one thread (least of `RUNS` runs), the
//! work per stroke (steps, and right-hand-side calls for Dormand–Prince),
//! and the largest error of the first strike angle and strike velocity
//! against an independent tight reference (Dormand–Prince at rtol 1e-13),
//! and how many verdicts change. The Taylor integrator at 1e-13 is listed
//! too: its distance from the reference shows that the two agree.
//!
//!     cargo run --release -p clapper-core --example tolerance [-- RUNS]

use std::time::Instant;

use clapper_core::chart::{sweep, Chart, ChartSpec};
use clapper_core::prelude::*;

/// An integrator and, for Taylor, its order.
type Method = (Integrator, usize);
const TAYLOR_12: Method = (Integrator::Taylor, 12);
const DOPRI5: Method = (Integrator::Dopri5, 0);

fn spec((integrator, order): Method, rtol: f64) -> ChartSpec {
    let mut spec = ChartSpec::default();
    spec.config.ode.rtol = rtol;
    spec.config.ode.atol = rtol;
    spec.config.integrator = integrator;
    spec.config.taylor.order = order.max(2);
    spec
}

/// The chart and the least time of `runs` sweeps on one thread (s).
fn chart(spec: &ChartSpec, runs: usize) -> (Chart, f64) {
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    // The least of several runs: the machine's noise only ever adds time.
    let mut best = f64::INFINITY;
    let mut chart = None;
    for _ in 0..runs.max(1) {
        let t = Instant::now();
        let c = pool.install(|| sweep(spec, &|_| {})).unwrap();
        best = best.min(t.elapsed().as_secs_f64());
        chart = Some(c);
    }
    (chart.unwrap(), best)
}

/// Steps and right-hand-side calls per stroke over the chart.
fn work_per_stroke(spec: &ChartSpec) -> (f64, f64) {
    let (mut n, mut steps, mut evals) = (0u64, 0u64, 0u64);
    for x in spec.xs() {
        for y in spec.ys() {
            let bell = spec.construction.bell(x, y).unwrap();
            for style in [Style::Right, Style::Wrong] {
                if let Ok(s) = first_stroke(&bell, &spec.config, style) {
                    n += 1;
                    steps += s.stats.steps;
                    evals += s.stats.rhs_evals;
                }
            }
        }
    }
    (steps as f64 / n as f64, evals as f64 / n as f64)
}

/// Largest differences from the reference: strike angle (deg), strike
/// velocity (rad/s), verdicts changed, relative D (where D > 0.1).
fn errors(c: &Chart, reference: &Chart) -> (f64, f64, usize, f64) {
    let (mut da, mut dv, mut changed, mut dd) = (0.0f64, 0.0f64, 0, 0.0f64);
    for (a, b) in c.cells.iter().zip(&reference.cells) {
        let (Ok(a), Ok(b)) = (&a.result, &b.result) else {
            continue;
        };
        if a.sustained != b.sustained {
            changed += 1;
        }
        if let (Some(x), Some(y)) = (a.strike_theta, b.strike_theta) {
            da = da.max((x - y).abs().to_degrees());
        }
        if let (Some(x), Some(y)) = (a.strike_phidot, b.strike_phidot) {
            dv = dv.max((x - y).abs());
        }
        if let (Some(x), Some(y)) = (a.double_strike_index, b.double_strike_index) {
            if y > 0.1 {
                dd = dd.max((x - y).abs() / y);
            }
        }
    }
    (da, dv, changed, dd)
}

/// The bell alone (clapper held at rest) with no events: the smooth part
/// of a stroke, the least work the tolerance asks for over that time.
struct Smooth(clapper_core::dynamics::Dynamics);

impl clapper_core::ode::System<4> for Smooth {
    fn rhs(&self, _t: f64, y: &[f64; 4]) -> [f64; 4] {
        self.0.rhs_resting(y)
    }
}

impl clapper_core::ode::SeriesSystem<4> for Smooth {
    fn expand(
        &self,
        y: &[f64; 4],
        p: usize,
        x: &mut [clapper_core::ode::taylor::Coeffs; 4],
        extra: &mut [clapper_core::ode::taylor::Coeffs; clapper_core::ode::MAX_EXTRA],
    ) {
        self.0.series_resting(y, None, p, x, &mut extra[0]);
    }
}

/// Work per stroke of the lab bell, and over the same time span with no
/// events at all, for both integrators at the default tolerance.
fn budget() {
    use clapper_core::ode::{Dopri5, Stepper, Taylor};
    let bell = Bell::lab();
    println!("lab bell at the default tolerance: work per stroke, and the least the tolerance needs");
    for method in [TAYLOR_12, DOPRI5] {
        let cfg = spec(method, SimConfig::default().ode.rtol).config;
        for style in [Style::Right, Style::Wrong] {
            let s = first_stroke(&bell, &cfg, style).unwrap();
            let sys = Smooth(clapper_core::dynamics::Dynamics::new(&bell));
            let y0 = [cfg.theta0, style.side(cfg.theta0).sign() * bell.phi_max, 0.0, 0.0];
            let smooth = match cfg.integrator {
                Integrator::Taylor => {
                    let mut t = Taylor::<4>::new(cfg.ode, cfg.taylor.order, cfg.taylor.h_max);
                    t.integrate(&sys, 0.0, y0, s.end.t, &mut |_, _| {}).unwrap();
                    t.stats()
                }
                Integrator::Dopri5 => {
                    let mut d = Dopri5::<4>::new(cfg.ode);
                    d.integrate(&sys, 0.0, y0, s.end.t, &mut |_, _| {}).unwrap();
                    d.stats()
                }
            };
            println!(
                "  {:<26} {style:?}: {} steps ({} rejected, {} rhs calls, {} events); the same {:.3} s with no events: {} steps ({} rhs calls)",
                name(method),
                s.stats.steps,
                s.stats.rejected,
                s.stats.rhs_evals,
                s.events,
                s.end.t,
                smooth.steps,
                smooth.rhs_evals
            );
        }
    }
}

fn name((integrator, order): Method) -> String {
    match integrator {
        Integrator::Taylor => format!("taylor {order} (h_max 0.25 s)"),
        Integrator::Dopri5 => "dopri5".into(),
    }
}

fn main() {
    let runs: usize = std::env::args().nth(1).and_then(|a| a.parse().ok()).unwrap_or(5);
    budget();
    let (reference, _) = chart(&spec(DOPRI5, 1e-13), 1);
    println!("reference: dopri5 at rtol 1e-13; times: least of {runs} runs of the 20 x 20 chart, one thread");
    println!(
        "{:<26} {:<7} {:>9} {:>8} {:>10} {:>17} {:>18} {:>9} {:>10}",
        "integrator",
        "rtol",
        "us/stroke",
        "steps",
        "rhs calls",
        "max|d strike| deg",
        "max|d phi'| rad/s",
        "verdicts",
        "max|dD|/D"
    );
    let taylor = |order| (Integrator::Taylor, order);
    let mut cases = vec![(taylor(12), 1e-13), (taylor(12), 1e-12)];
    for rtol in [1e-8, 3e-8, 1e-7] {
        cases.push((DOPRI5, rtol));
    }
    for order in [8, 10, 12, 14, 16] {
        cases.push((taylor(order), 3e-8));
    }
    for rtol in [1e-10, 1e-9, 1e-8, 1e-7, 3e-7, 1e-6] {
        cases.push((TAYLOR_12, rtol));
    }
    for (method, rtol) in cases {
        let s = spec(method, rtol);
        let (c, secs) = chart(&s, runs);
        let (steps, evals) = work_per_stroke(&s);
        let (da, dv, changed, dd) = errors(&c, &reference);
        println!(
            "{:<26} {rtol:<7.0e} {:>9.1} {:>8.1} {:>10.0} {:>17.2e} {:>18.2e} {:>9} {:>10.2e}",
            name(method),
            secs / c.cells.len() as f64 * 1e6,
            steps,
            evals,
            da,
            dv,
            changed,
            dd
        );
    }
}
