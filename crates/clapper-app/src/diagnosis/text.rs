//! A diagnosis as text and as a self-contained HTML page.

use std::fmt::Write as _;

use clapper_io::bell_file::LoadedBell;

use super::chart::chart_svg;
use super::report::{BellDiagnosisReport, DiagnosisReport};
use crate::AppError;

fn opt(v: Option<f64>, digits: usize) -> String {
    v.map_or("-".into(), |x| format!("{x:.digits$}"))
}

/// The numbers of a bell's row in the tables of the text and the report.
fn cells(b: &BellDiagnosisReport) -> [String; 10] {
    [
        format!("{:.3}", b.r_over_lc),
        format!("{:.3}", b.lb_over_lc),
        b.verdict.clone(),
        opt(b.first_strike_theta_deg, 1),
        opt(b.strike_phidot_rad_s, 2),
        opt(b.liftoff_theta_deg, 1),
        opt(b.double_strike_index.r005, 1),
        opt(b.double_strike_index.r01, 1),
        opt(b.double_strike_index.r02, 1),
        opt(b.min_theta0_right_deg, 1),
    ]
}

/// The numbers of a bell's backstroke row, for a bell whose hanging is not
/// ideal: its strike, lift-off and D in its own sign, the rest blank.
fn back_cells(b: &BellDiagnosisReport) -> Option<[String; 10]> {
    let k = b.backstroke.as_ref()?;
    Some([
        String::new(),
        String::new(),
        String::new(),
        opt(k.first_strike_theta_deg, 1),
        opt(k.strike_phidot_rad_s, 2),
        opt(k.liftoff_theta_deg, 1),
        opt(k.double_strike_index.r005, 1),
        opt(k.double_strike_index.r01, 1),
        opt(k.double_strike_index.r02, 1),
        String::new(),
    ])
}

/// The name of a bell's backstroke row.
const BACK_ROW: &str = "  backstroke";

/// The diagnosis table: a row a bell, its names whole (it cut "GSM tenor
/// (by its parts)" at 12 characters).
fn table(o: &mut String, rep: &DiagnosisReport) {
    let nw = rep
        .bells
        .iter()
        .map(|b| b.name.chars().count())
        .max()
        .unwrap_or(0)
        .max(12);
    let _ = writeln!(
        o,
        "{:<nw$} {:>6} {:>7} {:>7} {:>9} {:>8} {:>8} {:>7} {:>7} {:>7} {:>9} {:>7}",
        "bell", "r/L_c", "L_b/L_c", "rings", "strike", "phi'", "lift-off", "D.05", "D.1", "D.2", "min th0 R", "margin"
    );
    let _ = writeln!(
        o,
        "{:<nw$} {:>6} {:>7} {:>7} {:>9} {:>8} {:>8} {:>7} {:>7} {:>7} {:>9} {:>7}",
        "", "", "", "", "deg", "rad/s", "deg", "", "", "", "deg", "chart"
    );
    for b in &rep.bells {
        let c = cells(b);
        let apart = if b.stands_apart.is_empty() {
            ""
        } else {
            "  <- stands apart"
        };
        let name = &b.name;
        let _ = writeln!(
            o,
            "{name:<nw$} {:>6} {:>7} {:>7} {:>9} {:>8} {:>8} {:>7} {:>7} {:>7} {:>9} {:>7}{apart}",
            c[0],
            c[1],
            c[2],
            c[3],
            c[4],
            c[5],
            c[6],
            c[7],
            c[8],
            c[9],
            opt(b.margin.as_ref().and_then(|m| m.chart_units), 3),
        );
        if let Some(c) = back_cells(b) {
            let _ = writeln!(
                o,
                "{BACK_ROW:<nw$} {:>6} {:>7} {:>7} {:>9} {:>8} {:>8} {:>7} {:>7} {:>7} {:>9}",
                c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7], c[8], c[9],
            );
        }
    }
    if rep.bells.iter().any(|b| b.backstroke.is_some()) {
        let _ = writeln!(
            o,
            "(a bell hung out of true has a second row, its backstroke from -171 deg; its problems are judged from the worse stroke)"
        );
    }
}

/// The diagnosis as text: a table of all bells, then bell by bell.
pub fn text(rep: &DiagnosisReport, source: &str) -> String {
    let mut o = String::new();
    let _ = writeln!(
        o,
        "diagnosis of {source}: {} bell(s), fully up from 171 deg, R = 0.2 for the verdicts\n",
        rep.bells.len()
    );
    table(&mut o, rep);
    for b in rep.bells.iter().filter(|b| b.odd_struck.is_some()) {
        if let Some(odd) = &b.odd_struck {
            let _ = writeln!(o, "\n{}: {}", b.name, odd.words);
        }
    }
    for b in &rep.bells {
        let _ = writeln!(
            o,
            "\n{} (T_b = {:.2} s, T_c = {:.2} s, r = {:.0} mm)",
            b.name, b.tb_s, b.tc_s, b.r_mm
        );
        if !b.assumed.is_empty() {
            let _ = writeln!(o, "  assumed, not measured: {}", b.assumed.join(", "));
        }
        for w in &b.warnings {
            let _ = writeln!(o, "  warning: {w}");
        }
        let usual = b.usual_style.as_deref().unwrap_or("neither way");
        let _ = writeln!(
            o,
            "  rings {} when fully up; usually {usual}; {}",
            b.verdict,
            match b.min_theta0_right_deg {
                Some(t) => format!("rings right from {t:.0} deg up (lower, e.g. ringing up or down, it goes wrong)"),
                None => "never rings right".into(),
            }
        );
        let _ = writeln!(
            o,
            "  goes up {} (rung up from rest by the default ringer: clapper ring-up shows each swing)",
            b.goes_up
        );
        strike_text(&mut o, b);
        margin_text(&mut o, b, usual);
        problems_text(&mut o, b);
        if let Some(f) = &b.frame {
            let _ = writeln!(o, "  {}", f.words);
        }
        for r in &b.stands_apart {
            let _ = writeln!(o, "  stands apart: {r}");
        }
    }
    o
}

/// A bell's strike: the clapper's speed and energy, at both strokes when
/// they differ.
fn strike_text(o: &mut String, b: &BellDiagnosisReport) {
    let at = |v: f64, e: Option<f64>| format!("{v:.2} m/s{}", e.map_or(String::new(), |e| format!(", {e:.1} J")));
    if let Some(v) = b.striking_speed_m_s {
        let _ = match b.backstroke_striking_speed_m_s {
            Some(w) => writeln!(
                o,
                "  strike at the clapper's centre of percussion: {} at handstroke, {} at backstroke",
                at(v, b.strike_energy_j),
                at(w, b.backstroke_strike_energy_j)
            ),
            None => writeln!(
                o,
                "  strike: {v:.2} m/s at the clapper's centre of percussion{}",
                b.strike_energy_j.map_or(String::new(), |e| format!(", {e:.1} J"))
            ),
        };
    }
}

/// A bell's margin before it stops ringing its `usual` way.
fn margin_text(o: &mut String, b: &BellDiagnosisReport, usual: &str) {
    if let Some(m) = &b.margin {
        // "60 ms shorter or 80 ms longer"; a side with no edge in the
        // search is said once, in words.
        let edges = |less: Option<f64>, more: Option<f64>, unit: &str, k: f64, words: [&str; 2]| {
            let f = |x: f64, w: &str| format!("{:.0}{unit} {w}", x * k);
            match (less, more) {
                (Some(a), Some(b)) => format!("{} or {}", f(a, words[0]), f(b, words[1])),
                (Some(a), None) => format!("{} (no edge {} within the search)", f(a, words[0]), words[1]),
                (None, Some(b)) => format!("{} (no edge {} within the search)", f(b, words[1]), words[0]),
                (None, None) => "no edge either way within the search".into(),
            }
        };
        let _ = writeln!(
            o,
            "  margin before it stops ringing {usual}: clapper period {}; r {}",
            edges(
                m.clapper_period_shorter_s,
                m.clapper_period_longer_s,
                " ms",
                1e3,
                ["shorter", "longer"]
            ),
            edges(m.r_smaller_mm, m.r_larger_mm, " mm", 1.0, ["smaller", "larger"])
        );
    }
}

/// A bell's problems and the changes a hanger would try, in order.
fn problems_text(o: &mut String, b: &BellDiagnosisReport) {
    if !b.problems.is_empty() {
        let _ = writeln!(o, "  problems: {}", b.problems.join("; "));
        if b.changes.is_empty() {
            let _ = writeln!(
                o,
                "  changes: nothing within the searches (flight, ball, shaft, a new clapper within 0.4 s, the pivot within 150 mm) cures any of it"
            );
        } else {
            let _ = writeln!(o, "  changes, in the order a hanger would try them:");
            for (k, c) in b.changes.iter().enumerate() {
                let _ = writeln!(o, "    {}. {}", k + 1, c.words);
            }
            let left: Vec<&str> = b
                .problems
                .iter()
                .filter(|p| b.changes.iter().all(|c| c.problems_left.contains(p)))
                .map(String::as_str)
                .collect();
            if !left.is_empty() {
                let _ = writeln!(o, "    nothing within the searches cures: {}", left.join("; "));
            }
        }
    }
}

fn html_escape(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;")
}

fn report_html(rep: &DiagnosisReport, source: &str, chart_svg: &str) -> String {
    let mut h = String::from(
        "<!doctype html><html><head><meta charset=\"utf-8\"><title>clapper diagnosis</title><style>\
         body{font-family:sans-serif;max-width:1200px;margin:1em auto;padding:0 1em;color:#222}\
         table{border-collapse:collapse;font-size:14px}td,th{border:1px solid #bbb;padding:3px 6px;text-align:right}\
         th{background:#eee}td:first-child{text-align:left}.apart{background:#fde2c8}svg{max-width:100%;height:auto}\
         .bell{border-top:1px solid #ccc;margin-top:1em}pre{white-space:pre-wrap}</style></head><body>",
    );
    let _ = write!(
        h,
        "<h1>Clapping diagnosis: {}</h1><p>{} bell(s). Verdicts fully up from 171 deg with R = 0.2 (impact model); \
         D at R = 0.05, 0.1, 0.2. Made by clapper after Woodhouse et al. (2012).</p>",
        html_escape(source),
        rep.bells.len()
    );
    h.push_str("<h2>Where the bells sit on the clapping chart</h2>");
    h.push_str(chart_svg);
    h.push_str(
        "<h2>All bells</h2><table><tr><th>bell</th><th>r/L<sub>c</sub></th><th>L<sub>b</sub>/L<sub>c</sub></th>\
         <th>rings</th><th>first strike (deg)</th><th>&phi;' (rad/s)</th><th>lift-off (deg)</th><th>D, R=0.05</th>\
         <th>D, R=0.1</th><th>D, R=0.2</th><th>rings right from (deg)</th><th>problems</th></tr>",
    );
    for b in &rep.bells {
        let _ = write!(
            h,
            "<tr{}><td>{}</td>",
            if b.stands_apart.is_empty() {
                ""
            } else {
                " class=\"apart\""
            },
            html_escape(&b.name)
        );
        for c in cells(b) {
            let _ = write!(h, "<td>{c}</td>");
        }
        let _ = write!(
            h,
            "<td style=\"text-align:left\">{}</td></tr>",
            html_escape(&b.problems.join("; "))
        );
        if let Some(cs) = back_cells(b) {
            let _ = write!(h, "<tr><td>{}</td>", BACK_ROW.trim());
            for c in cs {
                let _ = write!(h, "<td>{c}</td>");
            }
            h.push_str("<td></td></tr>");
        }
    }
    h.push_str("</table>");
    let details = text(rep, source);
    let _ = write!(h, "<h2>Bell by bell</h2><pre>{}</pre>", html_escape(&details));
    h.push_str("</body></html>\n");
    h
}

/// The self-contained HTML report of a diagnosis (charts embedded).
pub fn report_page(rep: &DiagnosisReport, bells: &[LoadedBell], source: &str) -> Result<String, AppError> {
    Ok(report_html(rep, source, &chart_svg(bells)?))
}
