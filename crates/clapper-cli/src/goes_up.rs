//! `clapper chart --quantity goes-up`: ring up the bell at every point of
//! the chart plane, and set the CCCBR rule of thumb beside it.

use std::time::Instant;

use anyhow::{bail, Result};
use clapper_core::chart::{ChartSpec, Styles};
use clapper_core::ringer::{goes_up_chart, GoesUpCell, RingerConfig, RuleAgreement, Settles, CCCBR_LB_OVER_LC};
use clapper_plot::chart::{ChartFigure, Panel, Scale};
use clapper_plot::RGBColor;

use crate::chart::ChartArgs;

fn code(c: &GoesUpCell) -> (char, f64, &'static str) {
    match &c.result {
        Ok(Settles::NoStrike) => ('.', 0.0, "no strike"),
        Ok(Settles::Right) => ('R', 1.0, "right"),
        Ok(Settles::Wrong) => ('W', 2.0, "wrong"),
        Err(_) => ('x', 3.0, "failed"),
    }
}

/// Run the goes-up chart of `args`.
pub fn run(args: &ChartArgs) -> Result<()> {
    crate::files::claim_stdout(&[("--csv", args.csv.as_deref())], args.json)?;
    if args.json {
        bail!("--json prints a clapping chart's strokes; --quantity goes-up writes its CSV with --csv");
    }
    if args.shard.is_some() {
        bail!("--quantity goes-up is not sharded: each point is a whole ring-up; use a smaller --grid");
    }
    if let Some(p) = &args.out {
        clapper_plot::format_of(p)?;
    }
    let plan = args.sweep.plan(Styles::Right)?;
    if plan.charts.len() > 1 {
        bail!("--quantity goes-up draws one chart: give one theta0, R and phi_max");
    }
    let spec: ChartSpec = plan.charts[0].1;
    let ringer = RingerConfig::default();
    let pool = args.sweep.pool()?;
    let n = spec.nx * spec.ny;
    let bar = crate::progress::bar(n as u64, "ringing up");
    let start = Instant::now();
    let cells = pool.install(|| goes_up_chart(&spec, &ringer, &|d| bar.set_position(d)))?;
    bar.finish_and_clear();
    let secs = start.elapsed().as_secs_f64();

    say_map(&spec, &ringer, &cells);
    let failed = cells.iter().filter(|c| c.result.is_err()).count();
    if failed > 0 {
        eprintln!("warning: {failed} ring-ups failed to simulate (x)");
    }
    if let Some(csv) = &args.csv {
        crate::files::write_atomically(csv, |tmp| {
            let f = std::fs::File::create(tmp)?;
            Ok(clapper_io::write_goes_up_csv(std::io::BufWriter::new(f), &cells)?)
        })?;
    }
    if let Some(path) = &args.out {
        crate::chart::draw(path, &figure(&spec, &cells))?;
    }
    crate::say!(
        "  {n} ring-ups in {secs:.2} s on {}",
        crate::chart::threads_words(pool.current_num_threads())
    );
    Ok(())
}

/// Print the map of the chart and how the CCCBR rule agrees with it.
fn say_map(spec: &ChartSpec, ringer: &RingerConfig, cells: &[GoesUpCell]) {
    let ys = spec.ys();
    crate::say!(
        "ringing-up chart: {} x {} bells rung up from rest in {} swings ({:.0} deg each side of the bottom pulled), R = {}, phi_max = {:.0} deg",
        spec.nx,
        spec.ny,
        ringer.swings,
        ringer.window.to_degrees(),
        spec.config.restitution,
        spec.construction.phi_max.to_degrees()
    );
    crate::say!("  map (R goes up right, W wrong, . no strike, x failed; '-' marks the CCCBR line L_b/L_c = 1/0.81):");
    let mut rule_drawn = false;
    for j in (0..spec.ny).rev() {
        let row: String = (0..spec.nx).map(|i| code(&cells[j * spec.nx + i]).0).collect();
        if !rule_drawn && ys[j] <= CCCBR_LB_OVER_LC {
            crate::say!("   {:>6.3} {}", CCCBR_LB_OVER_LC, "-".repeat(spec.nx));
            rule_drawn = true;
        }
        crate::say!("   {:>6.3} {row}", ys[j]);
    }
    let a = RuleAgreement::of(cells);
    let t = a.total().max(1) as f64;
    let pct = |k: usize| 100.0 * k as f64 / t;
    crate::say!(
        "  CCCBR rule (T_c >= 0.9 T_b goes up right) and model agree at {:.1} % of {} points: both right {:.1} %, both not right {:.1} %",
        pct(a.both_right + a.both_not_right),
        a.total(),
        pct(a.both_right),
        pct(a.both_not_right)
    );
    crate::say!(
        "  disagree: rule right, model not {:.1} %; rule not, model right {:.1} %",
        pct(a.rule_right_model_not),
        pct(a.rule_not_model_right)
    );
}

/// The chart drawn: goes up right, wrong, no strike or failed at each
/// point, with the CCCBR line.
fn figure(spec: &ChartSpec, cells: &[GoesUpCell]) -> ChartFigure {
    let (xs, ys) = (spec.xs(), spec.ys());
    let panel = Panel {
        title: String::new(),
        xs: xs.clone(),
        ys,
        values: cells.iter().map(|c| Some(code(c).1)).collect(),
        region: cells.iter().map(|c| matches!(c.result, Ok(Settles::Right))).collect(),
    };
    ChartFigure {
        title: format!(
            "Ringing up from rest: goes up right or wrong (R = {}, phi_max = {:.0} deg)",
            spec.config.restitution,
            spec.construction.phi_max.to_degrees()
        ),
        panels: vec![panel],
        scale: Scale::Categories(vec![
            ("no strike".into(), RGBColor(255, 255, 255)),
            ("goes up right".into(), RGBColor(49, 130, 189)),
            ("goes up wrong".into(), RGBColor(230, 85, 13)),
            ("failed".into(), RGBColor(150, 150, 150)),
        ]),
        markers: vec![],
        axes: clapper_plot::chart::chart_axes(),
        lines: vec![(
            "CCCBR: T_c = 0.9 T_b".into(),
            vec![(xs[0], CCCBR_LB_OVER_LC), (xs[xs.len() - 1], CCCBR_LB_OVER_LC)],
            RGBColor(0, 0, 0),
        )],
    }
}
