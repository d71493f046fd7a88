//! A diagnosis made into its report: the core's verdicts, problems and
//! changes in a hanger's words, bell by bell and for a ring.

use std::fmt::Write as _;

use clapper_core::clapper_changes::{ClapperChange, HangerChange};
use clapper_core::diagnose::{
    diagnose_with_parts, ring_outliers, BellDiagnosis, DiagnoseConfig, Problem, StrokeFigures, StyleOutcome,
};
use clapper_core::prelude::*;
use clapper_io::bell_file::{BellSource, LoadedBell};
use rayon::prelude::*;

use super::odd_struck::{odd_struck_report, OddStruckOptions};
use super::report::{
    BellDiagnosisReport, ChangeReport, DByR, DiagnosisReport, FrameReport, MarginReport, StrokeReport, StyleReport,
};
use super::request::MAX_BELLS;
use crate::AppError;

fn d_by_r(d: &[Option<f64>; 3]) -> DByR {
    DByR {
        r005: d[0],
        r01: d[1],
        r02: d[2],
    }
}

fn stroke_json(f: &StrokeFigures) -> StrokeReport {
    StrokeReport {
        first_strike_theta_deg: f.strike_theta.map(f64::to_degrees),
        strike_phidot_rad_s: f.strike_phidot,
        liftoff_theta_deg: f.liftoff_theta.map(f64::to_degrees),
        double_strike_index: d_by_r(&f.double_strike_index),
    }
}

/// The backstroke of `o` worth reporting: a bell whose hanging is not
/// ideal (an ideal bell's is its handstroke mirrored).
fn shown_back(bell: &Bell, o: &StyleOutcome) -> Option<StrokeFigures> {
    o.back.filter(|_| !bell.hanging.is_ideal())
}

fn style_json(bell: &Bell, o: &StyleOutcome) -> StyleReport {
    StyleReport {
        sustained: o.sustained,
        first_strike_theta_deg: o.strike_theta.map(f64::to_degrees),
        strike_phidot_rad_s: o.strike_phidot,
        liftoff_theta_deg: o.liftoff_theta.map(f64::to_degrees),
        double_strike_index: d_by_r(&o.double_strike_index),
        backstroke: shown_back(bell, o).as_ref().map(stroke_json),
    }
}

fn problem_words(p: Problem) -> &'static str {
    match p {
        Problem::CannotRingRight => "cannot ring right when fully up",
        Problem::LateStrike => "strikes late, near the top of the swing",
        Problem::Quiet => "strikes softly",
        Problem::DoubleStrike => "likely to double strike (D > 10 at R = 0.1)",
        Problem::GoesUpWrong => "goes up wrong (rung up from rest, it settles striking wrong)",
    }
}

fn verdict(d: &BellDiagnosis) -> &'static str {
    match (d.right.sustained, d.wrong.sustained) {
        (true, true) => "both",
        (true, false) => "right",
        (false, true) => "wrong",
        (false, false) => "neither",
    }
}

/// A change and its predicted result in words.
fn change_words(bell: &Bell, h: &HangerChange) -> String {
    let dm = h.bell.clapper_mass - bell.clapper_mass;
    let what = match h.change {
        ClapperChange::FlightMass { dm, depth } if dm >= 0.0 => format!(
            "add {dm:.2} kg to the flight (a heavier or longer flight, its mass about {:.0} mm below the clapper pivot)",
            depth * 1e3
        ),
        ClapperChange::FlightMass { dm, .. } => {
            format!("take {:.2} kg off the flight (a lighter or shorter flight)", -dm)
        }
        ClapperChange::FlightLength { from, to, .. } => format!(
            "{} the flight from {:.0} mm to {:.0} mm ({dm:+.2} kg)",
            if to > from { "lengthen" } else { "shorten" },
            from * 1e3,
            to * 1e3
        ),
        ClapperChange::BallPosition { from, to } => format!(
            "{} the ball {:.0} mm (its centre from {:.0} mm to {:.0} mm below the clapper pivot)",
            if to > from { "lower" } else { "raise" },
            (to - from).abs() * 1e3,
            from * 1e3,
            to * 1e3
        ),
        ClapperChange::WoodenShaft { from } => {
            format!("fit an ash shaft in place of the {from} one ({dm:+.2} kg)")
        }
        ClapperChange::NewClapper { dtc } => format!(
            "a new, {} clapper (clapper design-clapper with its parts and --target-period {:.2} designs one)",
            if dtc > 0.0 { "longer" } else { "shorter" },
            bell.tc() + dtc
        ),
        ClapperChange::Pivot { dr } => format!(
            "last resort, a change hangers rarely make: {} the clapper pivot by {:.0} mm (r from {:.0} mm to {:.0} mm)",
            if dr > 0.0 { "lower" } else { "raise" },
            dr.abs() * 1e3,
            bell.r * 1e3,
            (bell.r + dr) * 1e3
        ),
    };
    let p = &h.predicted;
    let stroke = |f: &StrokeFigures| {
        format!(
            "first strike at {:.0} deg with phi' = {:.2} rad/s, D = {:.1} at R = 0.1",
            f.strike_theta.map_or(f64::NAN, f64::to_degrees),
            f.strike_phidot.unwrap_or(f64::NAN),
            f.double_strike_index[1].unwrap_or(f64::NAN),
        )
    };
    let strokes = match shown_back(&h.bell, p) {
        Some(back) => format!("at handstroke {}, at backstroke {}", stroke(&p.hand()), stroke(&back)),
        None => stroke(&p.hand()),
    };
    let mut words = format!(
        "{what}; T_c {:.3} s -> {:.3} s; then it rings right, {strokes}, goes up {}; {}",
        bell.tc(),
        h.bell.tc(),
        crate::ring_up::settles_name(h.goes_up),
        h.margin.map_or("no edge within the search".into(), |m| format!(
            "margin {m:.3} chart units"
        ))
    );
    if !h.fixes_all() {
        let left: Vec<&str> = h.problems_left.iter().map(|p| problem_words(*p)).collect();
        let _ = write!(words, "; still {}", left.join("; "));
    }
    words
}

fn change_json(bell: &Bell, h: &HangerChange) -> ChangeReport {
    let (mut mass, mut depth, mut flight, mut ball, mut pivot) = (None, None, None, None, None);
    match h.change {
        ClapperChange::FlightMass { dm, depth: z } => (mass, depth) = (Some(dm), Some(z)),
        ClapperChange::FlightLength { from, to, .. } => flight = Some([from, to]),
        ClapperChange::BallPosition { from, to } => ball = Some([from, to]),
        ClapperChange::Pivot { dr } => pivot = Some(dr * 1e3),
        ClapperChange::WoodenShaft { .. } | ClapperChange::NewClapper { .. } => {}
    }
    ChangeReport {
        kind: h.change.name(),
        fixes_all: h.fixes_all(),
        problems_left: h.problems_left.iter().map(|p| problem_words(*p).into()).collect(),
        last_resort: h.last_resort(),
        flight_mass_change_kg: mass,
        flight_depth_m: depth,
        flight_length_m: flight,
        ball_position_m: ball,
        pivot_change_mm: pivot,
        clapper_mass_kg: h.bell.clapper_mass,
        clapper_period_s: h.bell.tc(),
        r_over_lc: h.bell.r_over_lc(),
        lb_over_lc: h.bell.lb_over_lc(),
        predicted_right: style_json(&h.bell, &h.predicted),
        goes_up: crate::ring_up::settles_name(h.goes_up),
        margin_chart_units: h.margin,
        clapper_toml: h
            .parts
            .filter(|_| !matches!(h.change, ClapperChange::Pivot { .. }))
            .map(|p| clapper_io::clapper_input::ClapperInput::of(&p).to_toml()),
        words: change_words(bell, h),
    }
}

fn bell_json(b: &LoadedBell, d: &BellDiagnosis, outlier: &[String]) -> BellDiagnosisReport {
    let bell = &b.bell;
    let usual = d.usual_outcome();
    let bell_weighed = match &b.source {
        BellSource::MassProperties => true,
        BellSource::Tower(a) => !a.fields.iter().any(|(k, _)| *k == "bell_mass_kg"),
    };
    let (assumed, mass_known) = match &b.source {
        BellSource::MassProperties => (vec![], true),
        BellSource::Tower(a) => (
            a.fields
                .iter()
                .map(|(k, v)| format!("{k} = {v:.4}"))
                .collect::<Vec<_>>(),
            !a.fields.iter().any(|(k, _)| *k == "clapper_mass_kg" || *k == "b_m"),
        ),
    };
    let phidot = usual.and_then(|o| o.strike_phidot);
    let back = usual.and_then(|o| shown_back(bell, o));
    let back_phidot = back.and_then(|f| f.strike_phidot);
    BellDiagnosisReport {
        name: b.name.clone(),
        r_over_lc: d.position.0,
        lb_over_lc: d.position.1,
        tb_s: bell.tb(),
        tc_s: bell.tc(),
        r_mm: bell.r * 1e3,
        phi_max_deg: bell.phi_max.to_degrees(),
        assumed,
        warnings: bell.warnings().iter().map(ToString::to_string).collect(),
        rings_right: d.right.sustained,
        rings_wrong: d.wrong.sustained,
        verdict: verdict(d).into(),
        usual_style: d.usual.map(|s| s.name().into()),
        first_strike_theta_deg: usual.and_then(|o| o.strike_theta).map(f64::to_degrees),
        strike_phidot_rad_s: phidot,
        striking_speed_m_s: phidot.map(|v| v.abs() * bell.lc()),
        strike_energy_j: phidot
            .filter(|_| mass_known)
            .map(|v| 0.5 * bell.clapper_inertia * v * v),
        liftoff_theta_deg: usual.and_then(|o| o.liftoff_theta).map(f64::to_degrees),
        double_strike_index: d_by_r(&usual.unwrap_or(&d.right).double_strike_index),
        backstroke: back.as_ref().map(stroke_json),
        backstroke_striking_speed_m_s: back_phidot.map(|v| v.abs() * bell.lc()),
        backstroke_strike_energy_j: back_phidot
            .filter(|_| mass_known)
            .map(|v| 0.5 * bell.clapper_inertia * v * v),
        min_theta0_right_deg: d.min_theta0_right.map(f64::to_degrees),
        margin: d.margin.map(|m| MarginReport {
            chart_units: m.chart_units,
            clapper_period_shorter_s: m.tc_down,
            clapper_period_longer_s: m.tc_up,
            r_smaller_mm: m.r_down.map(|x| x * 1e3),
            r_larger_mm: m.r_up.map(|x| x * 1e3),
        }),
        problems: d.problems.iter().map(|p| problem_words(*p).into()).collect(),
        goes_up: crate::ring_up::settles_name(d.goes_up),
        changes: d.changes.iter().map(|h| change_json(bell, h)).collect(),
        frame: d.frame.map(|f| {
            let newtons = |v: f64| bell_weighed.then_some(v);
            let mut report = FrameReport {
                bell_mass_measured: bell_weighed,
                weight_n: newtons(f.weight),
                peak_horizontal_n: newtons(f.horizontal),
                peak_vertical_down_n: newtons(f.vertical_down),
                least_vertical_n: newtons(f.vertical_min),
                peak_horizontal_over_weight: f.horizontal_ratio(),
                peak_vertical_over_weight: f.vertical_ratio(),
                least_vertical_over_weight: f.vertical_min / f.weight,
                words: String::new(),
            };
            report.words = frame_words(&report);
            report
        }),
        stands_apart: outlier.to_vec(),
        right: style_json(bell, &d.right),
        wrong: style_json(bell, &d.wrong),
        odd_struck: None,
    }
}

/// The frame loads in words: newtons beside the multiples of the weight
/// only for a weighed bell.
fn frame_words(f: &FrameReport) -> String {
    let load = |n: Option<f64>, ratio: f64| match n {
        Some(n) => format!("{n:.0} N ({ratio:.2} x weight)"),
        None => format!("{ratio:.2} x weight"),
    };
    format!(
        "frame load over a stroke: horizontal up to {}, vertical up to {}{}",
        load(f.peak_horizontal_n, f.peak_horizontal_over_weight),
        load(f.peak_vertical_down_n, f.peak_vertical_over_weight),
        if f.bell_mass_measured {
            ""
        } else {
            " (the bell is not weighed: give bell_mass_kg for newtons)"
        }
    )
}

/// thread count).
pub fn diagnose_bells(bells: &[LoadedBell]) -> Result<DiagnosisReport, AppError> {
    diagnose_bells_with(bells, &OddStruckOptions::default())
}

/// [`diagnose_bells`] with the odd-struckness options.
pub fn diagnose_bells_with(bells: &[LoadedBell], odd: &OddStruckOptions) -> Result<DiagnosisReport, AppError> {
    if bells.is_empty() {
        return Err(AppError::Request("no bells to diagnose".into()));
    }
    if bells.len() > MAX_BELLS {
        return Err(AppError::Request(format!(
            "{} bells: a ring of at most {MAX_BELLS} is diagnosed at once",
            bells.len()
        )));
    }
    let cfg = DiagnoseConfig::default();
    let diagnoses: Vec<BellDiagnosis> = bells
        .par_iter()
        .map(|b| {
            { diagnose_with_parts(&b.bell, b.clapper_parts.as_ref(), &cfg) }
                .map_err(|e| AppError::Request(format!("diagnosing {}: {e}", b.name)))
        })
        .collect::<Result<_, _>>()?;
    let outliers = ring_outliers(&diagnoses);
    let mut out_words = vec![];
    let bells_json: Vec<BellDiagnosisReport> = bells
        .iter()
        .zip(&diagnoses)
        .enumerate()
        .map(|(k, (b, d))| {
            let reasons: Vec<String> = outliers
                .iter()
                .filter(|o| o.index == k)
                .flat_map(|o| o.reasons.clone())
                .collect();
            if !reasons.is_empty() {
                out_words.push(format!("{}: {}", b.name, reasons.join("; ")));
            }
            let mut rep = bell_json(b, d, &reasons);
            // The request's ball depth, else the bell file's own.
            let odd = OddStruckOptions {
                ball_below_pivot_m: odd.ball_below_pivot_m.or(b.ball_below_pivot_m),
                ..*odd
            };
            rep.odd_struck = odd_struck_report(&b.bell, d.usual, &odd)?;
            Ok(rep)
        })
        .collect::<Result<_, AppError>>()?;
    Ok(DiagnosisReport {
        settings: serde_json::json!({
            "theta0_deg": cfg.sim.theta0.to_degrees(),
            "restitution": cfg.sim.restitution,
            "contact": "impact",
            "late_strike_deg": cfg.late_strike.to_degrees(),
            "quiet_ratio": cfg.quiet_ratio,
            "double_strike_limit": cfg.double_strike_limit,
        }),
        bells: bells_json,
        outliers: out_words,
    })
}
