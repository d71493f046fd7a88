//! The paper's 20 x 20 chart (both styles) with every value printed in
//! full (shortest round-trip decimals), one JSON object a line, so that
//! bench/compare.py can measure errors far below the six decimals of
//! `clapper chart --csv`. Used by the benchmark; timing is not its job.
//!
//!     cargo run --release -p clapper-core --example chart_values -- RTOL [taylor|dopri5] [impact|penalty]

use clapper_core::chart::{sweep, ChartSpec};
use clapper_core::stroke::{ContactModel, Integrator};

fn main() {
    let mut spec = ChartSpec::default();
    let args: Vec<String> = std::env::args().skip(1).collect();
    let rtol: f64 = args
        .first()
        .and_then(|a| a.parse().ok())
        .unwrap_or(spec.config.ode.rtol);
    spec.config.ode.rtol = rtol;
    spec.config.ode.atol = rtol;
    if args.get(1).map(String::as_str) == Some("dopri5") {
        spec.config.integrator = Integrator::Dopri5;
    }
    if args.get(2).map(String::as_str) == Some("penalty") {
        spec.config.contact = ContactModel::Penalty;
    }
    let chart = sweep(&spec, &|_| {}).expect("the default chart is valid");
    let num = |v: Option<f64>| v.map_or("null".to_string(), |v| format!("{v:?}"));
    for c in &chart.cells {
        let s = c.result.as_ref().ok();
        println!(
            "{{\"point\": [{:?}, {:?}], \"style\": \"{}\", \"sustained\": {}, \"strike_theta_deg\": {}, \"strike_phidot_rad_s\": {}}}",
            c.x,
            c.y,
            if c.style == clapper_core::stroke::Style::Right { "right" } else { "wrong" },
            s.is_some_and(|s| s.sustained),
            num(s.and_then(|s| s.strike_theta).map(f64::to_degrees)),
            num(s.and_then(|s| s.strike_phidot)),
        );
    }
}
