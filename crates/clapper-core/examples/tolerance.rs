//! How the integrator tolerance trades speed for accuracy on the paper's
//! 20 x 20 chart (both styles, impact model): for each rtol (= atol), the
//! time per stroke on one thread (least of five runs), right-hand-side calls per stroke, and the
//! largest error of the first strike angle and strike velocity against a
//! tight reference (rtol = 1e-12), and how many verdicts change.
//!
//!     cargo run --release -p clapper-core --example tolerance

use std::time::Instant;

use clapper_core::chart::{sweep, ChartSpec};
use clapper_core::prelude::*;

fn chart(rtol: f64, h_max: f64) -> (clapper_core::chart::Chart, f64) {
    let mut spec = ChartSpec::default();
    spec.config.ode.rtol = rtol;
    spec.config.ode.atol = rtol;
    spec.config.ode.h_max = h_max;
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    // The least of five runs: the machine's noise only ever adds time.
    let mut best = f64::INFINITY;
    let mut chart = None;
    for _ in 0..5 {
        let t = Instant::now();
        let c = pool.install(|| sweep(&spec, &|_| {})).unwrap();
        best = best.min(t.elapsed().as_secs_f64());
        chart = Some(c);
    }
    (chart.unwrap(), best)
}

fn rhs_per_stroke(rtol: f64, h_max: f64) -> f64 {
    let spec = ChartSpec::default();
    let mut cfg = spec.config;
    cfg.ode.rtol = rtol;
    cfg.ode.atol = rtol;
    cfg.ode.h_max = h_max;
    let (mut n, mut evals) = (0u64, 0u64);
    for x in spec.xs() {
        for y in spec.ys() {
            let bell = spec.construction.bell(x, y).unwrap();
            for style in [Style::Right, Style::Wrong] {
                if let Ok(s) = first_stroke(&bell, &cfg, style) {
                    n += 1;
                    evals += s.stats.rhs_evals;
                }
            }
        }
    }
    evals as f64 / n as f64
}

/// The bell alone (clapper held at rest) with no events: the smooth part
/// of a stroke, the least work the tolerance asks for over that time.
struct Smooth(clapper_core::dynamics::Dynamics);

impl clapper_core::ode::EventSystem<4> for Smooth {
    fn rhs(&self, _t: f64, y: &[f64; 4]) -> [f64; 4] {
        self.0.rhs_resting(y)
    }
    fn n_events(&self) -> usize {
        0
    }
    fn event(&self, _i: usize, _t: f64, _y: &[f64; 4]) -> f64 {
        0.0
    }
    fn direction(&self, _i: usize) -> clapper_core::ode::Direction {
        clapper_core::ode::Direction::Either
    }
}

/// Right-hand-side calls of the lab bell's strokes, and of the same time
/// span integrated with no events at all.
fn budget() {
    let bell = Bell::lab();
    let cfg = SimConfig::default();
    println!("\nlab bell at the default tolerance: rhs calls per stroke, and the least the tolerance needs");
    for style in [Style::Right, Style::Wrong] {
        let s = first_stroke(&bell, &cfg, style).unwrap();
        let mut solver = clapper_core::ode::Dopri5::<4>::new(cfg.ode);
        let sys = Smooth(clapper_core::dynamics::Dynamics::new(&bell));
        let y0 = [cfg.theta0, style.side(cfg.theta0).sign() * bell.phi_max, 0.0, 0.0];
        solver.integrate(&sys, 0.0, y0, s.end.t, &mut |_, _| {}).unwrap();
        let smooth = solver.stats();
        println!(
            "  {style:?}: {} calls ({} steps, {} rejected, {} events); the same {:.3} s with no events: {} calls ({} steps)",
            s.stats.rhs_evals,
            s.stats.steps,
            s.stats.rejected,
            s.events,
            s.end.t,
            smooth.rhs_evals,
            smooth.steps
        );
    }
}

fn main() {
    budget();
    let (reference, _) = chart(1e-12, 0.05);
    println!(
        "rtol     h_max  us/stroke  rhs/stroke  max|d strike| deg  max|d phi'| rad/s  verdicts changed  max|dD|/D"
    );
    for (rtol, h_max) in [
        (1e-8, 0.05),
        (2e-8, 0.05),
        (3e-8, 0.05),
        (5e-8, 0.05),
        (1e-7, 0.05),
        (1e-6, 0.05),
    ] {
        let (c, secs) = chart(rtol, h_max);
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
        println!(
            "{rtol:<8.0e} {h_max:<6} {:>9.1} {:>11.0} {:>18.2e} {:>18.2e} {:>17} {:>10.2e}",
            secs / c.cells.len() as f64 * 1e6,
            rhs_per_stroke(rtol, h_max),
            da,
            dv,
            changed,
            dd
        );
    }
}
