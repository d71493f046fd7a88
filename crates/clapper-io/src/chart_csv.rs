//! Charts as long-form CSV: one row per point and style. A sweep over
//! several θ0, R or φ_max puts those three first on every row.

use clapper_core::Choice;
use std::io::Write;

use clapper_core::chart::{Chart, ChartCell, ChartSpec, StrokeSummary};
use clapper_core::stroke::Style;

/// The columns of `clapper chart --csv` (README, "Clapping charts").
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

/// The leading columns of a sweep over extra axes.
pub const AXES_HEADER: [&str; 3] = ["theta0_deg", "restitution", "phi_max_deg"];

/// The last column of a chart of a bell that is not ideal (an offset, unequal
/// contact angles or friction): handstroke minus backstroke, bottom dead
/// centre to strike (ms). An ideal bell's chart leaves it out, so its CSV is
/// the same bytes as before the column existed.
pub const ODD_STRUCK_COLUMN: &str = "odd_struck_ms";

/// The settings of one chart of a sweep: θ0 (deg), R, φ_max (deg).
pub type Axes = [f64; 3];

/// The columns a chart CSV has beside [`CHART_HEADER`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Columns {
    /// The extra axes of a sweep first ([`AXES_HEADER`]).
    pub axes: bool,
    /// [`ODD_STRUCK_COLUMN`] last.
    pub odd_struck: bool,
}

impl Columns {
    /// The columns of a chart computed as `spec`, with or without `axes`.
    pub fn of(spec: &ChartSpec, axes: bool) -> Self {
        Self {
            axes,
            odd_struck: !spec.hanging.is_ideal(),
        }
    }
}

fn cell(v: Option<f64>) -> String {
    v.map(|x| format!("{x:.6}")).unwrap_or_default()
}

/// The header row of a chart with `columns`.
pub fn chart_header(columns: Columns) -> Vec<&'static str> {
    let mut h = if columns.axes { AXES_HEADER.to_vec() } else { vec![] };
    h.extend(CHART_HEADER);
    if columns.odd_struck {
        h.push(ODD_STRUCK_COLUMN);
    }
    h
}

fn row(c: &ChartCell, axes: Option<&Axes>, odd_struck: bool) -> Vec<String> {
    let s = c.result.as_ref().ok();
    let mut r: Vec<String> = axes.map_or(vec![], |a| a.iter().map(|v| format!("{v}")).collect());
    r.extend([
        format!("{:.6}", c.x),
        format!("{:.6}", c.y),
        c.style.name().to_string(),
        s.is_some_and(|s| s.sustained).to_string(),
        cell(s.and_then(|s| s.strike_theta).map(f64::to_degrees)),
        cell(s.and_then(|s| s.strike_phidot)),
        cell(s.and_then(|s| s.liftoff_theta).map(f64::to_degrees)),
        cell(s.and_then(|s| s.double_strike_index)),
    ]);
    if odd_struck {
        r.push(cell(s.and_then(|s| s.odd_struck).map(|t| t * 1e3)));
    }
    r
}

/// Write rows of cells (each with its chart's axes when the sweep has
/// extra axes) in `columns`, with the header row first if `header`. The
/// text depends only on the cells, so a chart written in parts, one after
/// another, is the same bytes as written whole.
pub fn write_chart_rows<'a, W: Write>(
    out: W,
    rows: impl IntoIterator<Item = (Option<&'a Axes>, &'a ChartCell)>,
    columns: Columns,
    header: bool,
) -> Result<(), csv::Error> {
    let mut w = csv::WriterBuilder::new().flexible(true).from_writer(out);
    if header {
        w.write_record(chart_header(columns))?;
    }
    for (axes, c) in rows {
        w.write_record(row(c, axes, columns.odd_struck))?;
    }
    w.flush()?;
    Ok(())
}

/// Write `chart` as CSV: rows in the chart's order (L_b/L_c, then r/L_c,
/// then style), an empty cell where a value is undefined (no strike, no
/// lift-off, or a point that failed to simulate). The text depends only on
/// the chart, so it is the same for any thread count.
pub fn write_chart_csv<W: Write>(out: W, chart: &Chart) -> Result<(), csv::Error> {
    let columns = Columns::of(&chart.spec, false);
    write_chart_rows(out, chart.cells.iter().map(|c| (None, c)), columns, true)
}

/// The columns of `clapper chart --quantity goes-up --csv`.
pub const GOES_UP_HEADER: [&str; 4] = ["r_over_lc", "lb_over_lc", "goes_up", "cccbr_rule"];

/// Write a ringing-up chart: each point, how its bell goes up ("right",
/// "wrong", "no strike", or "failed") and what the CCCBR rule of thumb
/// says ("right" where L_b/L_c ≤ 1/0.81).
pub fn write_goes_up_csv<W: Write>(out: W, cells: &[clapper_core::ringer::GoesUpCell]) -> Result<(), csv::Error> {
    use clapper_core::ringer::{Settles, CCCBR_LB_OVER_LC};
    let mut w = csv::Writer::from_writer(out);
    w.write_record(GOES_UP_HEADER)?;
    for c in cells {
        let up = match &c.result {
            Ok(Settles::Right) => "right",
            Ok(Settles::Wrong) => "wrong",
            Ok(Settles::NoStrike) => "no strike",
            Err(_) => "failed",
        };
        let rule = if c.y <= CCCBR_LB_OVER_LC { "right" } else { "wrong" };
        w.write_record([format!("{:.6}", c.x), format!("{:.6}", c.y), up.into(), rule.into()])?;
    }
    w.flush()?;
    Ok(())
}

/// A value from the file as an error message shows it: quoted, escaped
/// (a field may hold newlines) and cut short.
fn shown(v: &str) -> String {
    let q = format!("{v:?}");
    if q.chars().count() > 60 {
        q.chars().take(57).collect::<String>() + "..."
    } else {
        q
    }
}

/// Why a chart CSV cannot be read back. One line.
#[derive(Debug, thiserror::Error)]
#[error("chart CSV {name}: {message}")]
pub struct ChartCsvError {
    /// Where the text came from.
    pub name: String,
    /// What is wrong.
    pub message: String,
}

/// Read a chart CSV back (for plotting and merging): each row's axes (if
/// the file has them) and cell. Values carry the file's six decimals;
/// a failed stroke reads back as one that did not sustain, with no values.
pub fn read_chart_csv(text: &str, name: &str) -> Result<Vec<(Option<Axes>, ChartCell)>, ChartCsvError> {
    let err = |message: String| ChartCsvError {
        name: name.to_string(),
        message,
    };
    let mut rdr = csv::ReaderBuilder::new().from_reader(text.as_bytes());
    let header: Vec<String> = rdr
        .headers()
        .map_err(|e| err(e.to_string()))?
        .iter()
        .map(str::to_string)
        .collect();
    let known = [false, true]
        .into_iter()
        .flat_map(|axes| [false, true].map(|odd_struck| Columns { axes, odd_struck }));
    let Some(Columns { axes, odd_struck }) = known.into_iter().find(|c| header == chart_header(*c)) else {
        // Quoted and cut short: the header may hold anything, newlines too.
        return Err(err(format!(
            "the header is not a chart's: {}",
            shown(&header.join(","))
        )));
    };
    let columns = Columns { axes, odd_struck };
    let mut out = vec![];
    for (k, rec) in rdr.records().enumerate() {
        let rec = rec.map_err(|e| err(format!("row {}: {}", k + 1, e.to_string().replace('\n', " "))))?;
        out.push(read_row(&rec, k, &header, columns).map_err(err)?);
    }
    Ok(out)
}

/// A field as the message shows it: quoted, or "missing" for a short row.
fn field_words(f: Option<&str>) -> String {
    f.map_or_else(|| "missing".to_string(), shown)
}

/// Row `k` (from 0) of a chart CSV with `header` and `columns`: its axes
/// and cell, or what is wrong with it.
fn read_row(
    rec: &csv::StringRecord,
    k: usize,
    header: &[String],
    columns: Columns,
) -> Result<(Option<Axes>, ChartCell), String> {
    let off = if columns.axes { 3 } else { 0 };
    let num = |i: usize| -> Result<Option<f64>, String> {
        let f = rec.get(i).unwrap_or("");
        if f.is_empty() {
            return Ok(None);
        }
        f.parse::<f64>()
            .map(Some)
            .map_err(|_| format!("row {}: {} in column {} is not a number", k + 1, shown(f), header[i]))
    };
    let need = |i: usize| num(i)?.ok_or_else(|| format!("row {}: {} is empty", k + 1, header[i]));
    let a = if columns.axes {
        Some([need(0)?, need(1)?, need(2)?])
    } else {
        None
    };
    let style = match rec.get(off + 2) {
        Some("right") => Style::Right,
        Some("wrong") => Style::Wrong,
        other => {
            return Err(format!(
                "row {}: style {} is neither right nor wrong",
                k + 1,
                field_words(other)
            ))
        }
    };
    let sustained = match rec.get(off + 3) {
        Some("true") => true,
        Some("false") => false,
        other => {
            return Err(format!(
                "row {}: sustained {} is neither true nor false",
                k + 1,
                field_words(other)
            ))
        }
    };
    Ok((
        a,
        ChartCell {
            x: need(off)?,
            y: need(off + 1)?,
            style,
            result: Ok(StrokeSummary {
                sustained,
                strike_theta: num(off + 4)?.map(f64::to_radians),
                strike_phidot: num(off + 5)?,
                liftoff_theta: num(off + 6)?.map(f64::to_radians),
                double_strike_index: num(off + 7)?,
                second_strike_delay: None,
                odd_struck: if columns.odd_struck {
                    num(off + 8)?.map(|ms| ms * 1e-3)
                } else {
                    None
                },
                amplitude_ratio: None,
            }),
        },
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use clapper_core::chart::{sweep, ChartSpec};

    #[test]
    fn a_bad_style_or_a_short_row_is_said_without_rust_debug() {
        let header = CHART_HEADER.join(",");
        let bad = format!("{header}\n-0.3,0.5,sideways,true,,,,\n");
        let e = read_chart_csv(&bad, "c.csv").unwrap_err().to_string();
        assert!(e.contains("style \"sideways\" is neither"), "{e}");
        assert!(!e.contains("Some("), "{e}");
        let e = read_chart_csv(&format!("{header}\n-0.3,0.5\n"), "c.csv")
            .unwrap_err()
            .to_string();
        assert!(!e.contains("None"), "{e}");
    }

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
        // Written in two parts, the same bytes.
        let mut parts = Vec::new();
        let cols = Columns::default();
        write_chart_rows(&mut parts, chart.cells[..5].iter().map(|c| (None, c)), cols, true).unwrap();
        write_chart_rows(&mut parts, chart.cells[5..].iter().map(|c| (None, c)), cols, false).unwrap();
        assert_eq!(parts, text.as_bytes());
        // And it reads back.
        let back = read_chart_csv(&text, "t").unwrap();
        assert_eq!(back.len(), chart.cells.len());
        for ((_, b), c) in back.iter().zip(&chart.cells) {
            assert_eq!(b.sustained().is_some(), c.sustained().is_some());
            let (sb, sc) = (b.result.as_ref().unwrap(), c.result.as_ref().unwrap());
            if let (Some(x), Some(y)) = (sb.strike_theta, sc.strike_theta) {
                assert!((x - y).abs() < 1e-7);
            }
        }
        assert!(read_chart_csv("a,b\n1,2\n", "t")
            .unwrap_err()
            .to_string()
            .contains("not a chart's"));
    }

    /// A bell off the ideal gets the odd-struck column, in ms, and reads
    /// it back; its mirror bell's column is the negation.
    #[test]
    fn an_odd_struck_bell_has_its_column() {
        use clapper_core::hanging::Hanging;
        let csv_of = |d: f64| {
            let spec = ChartSpec {
                nx: 3,
                ny: 2,
                hanging: Hanging {
                    pivot_offset: d,
                    ..Hanging::default()
                },
                ..ChartSpec::default()
            };
            let chart = sweep(&spec, &|_| {}).unwrap();
            let mut buf = Vec::new();
            write_chart_csv(&mut buf, &chart).unwrap();
            (String::from_utf8(buf).unwrap(), chart)
        };
        let (text, chart) = csv_of(0.003);
        assert_eq!(text.lines().next().unwrap(), CHART_HEADER.join(",") + ",odd_struck_ms");
        let back = read_chart_csv(&text, "t").unwrap();
        let mut seen = 0;
        for ((_, b), c) in back.iter().zip(&chart.cells) {
            let (b, c) = (b.result.as_ref().unwrap(), c.result.as_ref().unwrap());
            assert_eq!(b.odd_struck.is_some(), c.odd_struck.is_some());
            if let (Some(x), Some(y)) = (b.odd_struck, c.odd_struck) {
                assert!((x - y).abs() < 1e-9, "{x} vs {y} s");
                seen += 1;
            }
        }
        assert!(seen > 0, "some point strikes at both strokes");
        // Where the style is sustained the backstroke is the mirror's
        // handstroke (elsewhere it starts from where a failed handstroke
        // left the clapper, so no mirror is expected).
        let (mirror, _) = csv_of(-0.003);
        let mut mirrored = 0;
        for (a, b) in text.lines().zip(mirror.lines()).skip(1) {
            let (a, b): (Vec<_>, Vec<_>) = (a.split(',').collect(), b.split(',').collect());
            if a[3] == "true" && b[3] == "true" {
                assert_eq!(a[8].parse::<f64>().unwrap(), -b[8].parse::<f64>().unwrap());
                mirrored += 1;
            }
        }
        assert!(mirrored >= 4, "{text}");
    }
}
