//! Time one stroke of the lab bell ringing right, in process: the least of
//! twenty runs of 2000 strokes, and the first strike of one. Used by
//! bench/compare.py; prints JSON.
//!
//!     cargo run --release -p clapper-core --example lab_stroke -- [RTOL [taylor|dopri5]]

use std::time::Instant;

use clapper_core::prelude::*;

fn main() {
    let mut cfg = SimConfig::default();
    if let Some(r) = std::env::args().nth(1).and_then(|a| a.parse::<f64>().ok()) {
        cfg.ode.rtol = r;
        cfg.ode.atol = r;
    }
    if std::env::args().nth(2).as_deref() == Some("dopri5") {
        cfg.integrator = clapper_core::stroke::Integrator::Dopri5;
    }
    let bell = Bell::lab();
    let n = 2000;
    let mut best = f64::INFINITY;
    for _ in 0..20 {
        let t = Instant::now();
        for _ in 0..n {
            std::hint::black_box(first_stroke(std::hint::black_box(&bell), &cfg, Style::Right).unwrap());
        }
        best = best.min(t.elapsed().as_secs_f64() / n as f64);
    }
    let s = first_stroke(&bell, &cfg, Style::Right).unwrap();
    println!(
        "{{\"seconds_per_stroke\": {best:e}, \"strike_theta_deg\": {}, \"strike_phidot_rad_s\": {}}}",
        s.strike_angle().unwrap().to_degrees(),
        s.strike_velocity().unwrap()
    );
}
