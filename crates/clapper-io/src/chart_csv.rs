//! Charts as long-form CSV: one row per point and style.

use std::io::Write;

use clapper_core::chart::Chart;

use crate::report::style_name;

/// The columns, as SPEC'd for `clapper chart --csv`.
pub const CHART_HEADER: [&str; 8] = [
    "r_over_lc",
    "lb_over_lc",
    "style",
    "sustained",
    "strike_theta_deg",
    "strike_phidot_rad_s",
    "liftoff_theta_deg",
    "double_strike_index",
];

fn cell(v: Option<f64>) -> String {
    v.map(|x| format!("{x:.6}")).unwrap_or_default()
}

/// Write `chart` as CSV: rows in the chart's order (L_b/L_c, then r/L_c,
/// then style), an empty cell where a value is undefined (no strike, no
/// lift-off, or a point that failed to simulate). The text depends only on
/// the chart, so it is the same for any thread count.
pub fn write_chart_csv<W: Write>(out: W, chart: &Chart) -> Result<(), csv::Error> {
    let mut w = csv::Writer::from_writer(out);
    w.write_record(CHART_HEADER)?;
    for c in &chart.cells {
        let s = c.result.as_ref().ok();
        w.write_record([
            format!("{:.6}", c.x),
            format!("{:.6}", c.y),
            style_name(c.style).to_string(),
            s.is_some_and(|s| s.sustained).to_string(),
            cell(s.and_then(|s| s.strike_theta).map(f64::to_degrees)),
            cell(s.and_then(|s| s.strike_phidot)),
            cell(s.and_then(|s| s.liftoff_theta).map(f64::to_degrees)),
            cell(s.and_then(|s| s.double_strike_index)),
        ])?;
    }
    w.flush()?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use clapper_core::chart::{sweep, ChartSpec};

    #[test]
    fn header_rows_and_empty_cells() {
        let spec = ChartSpec {
            nx: 3,
            ny: 2,
            ..ChartSpec::default()
        };
        let chart = sweep(&spec, &|_| {}).unwrap();
        let mut buf = Vec::new();
        write_chart_csv(&mut buf, &chart).unwrap();
        let text = String::from_utf8(buf).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines[0], CHART_HEADER.join(","));
        assert_eq!(lines.len(), 1 + 3 * 2 * 2);
        assert!(lines[1].starts_with("-0.300000,0.500000,right,"));
        assert!(lines.iter().skip(1).all(|l| l.split(',').count() == 8));
    }
}
