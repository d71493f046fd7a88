//! Diagnose a bell or a ring for the bell-hanger: the work behind
//! `clapper diagnose` and `POST /api/diagnose`, as a report (JSON), text,
//! and a self-contained HTML page with the chart.

use std::fmt::Write as _;

use clapper_core::chart::{ChartSpec, Styles};
use clapper_core::clapper_changes::{ClapperChange, HangerChange};
use clapper_core::diagnose::{
    diagnose_with_parts, ring_outliers, BellDiagnosis, DiagnoseConfig, Problem, StyleOutcome,
};
use clapper_core::prelude::*;
use clapper_io::bell_file::{BellSource, LoadedBell};
use clapper_plot::chart::Marker;
use clapper_plot::quantity;
use rayon::prelude::*;
use serde::Serialize;

use crate::AppError;

/// Most bells diagnosed at once: a ring of 64 is beyond any tower.
pub const MAX_BELLS: usize = 64;

/// Which bells to diagnose, given as data (the server's request): a
/// preset, or the text of a bell or ring file.
///
/// ```json
/// {"preset": "lab"}
/// {"toml": "name = \"Tenor\"\nbell_period_s = 2.33\nclapper_period_s = 1.76\nr_m = 0.179\nphi_max_deg = 32\n"}
/// {"csv": "name,bell_period_s,clapper_period_s,r_m,phi_max_deg\nTreble,1.6,1.3,0.08,26\n"}
/// ```
#[derive(Clone, Debug, Default, PartialEq, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DiagnoseRequest {
    /// A bell of Table 1.
    #[serde(default)]
    pub preset: Option<crate::simulate::Preset>,
    /// A bell file, or several bells as `[[bell]]` tables (TOML text).
    #[serde(default)]
    pub toml: Option<String>,
    /// A ring as CSV text: a header of bell-file keys, one bell a row.
    #[serde(default)]
    pub csv: Option<String>,
}

impl DiagnoseRequest {
    /// The bells, and words saying where they came from.
    pub fn bells(&self) -> Result<(Vec<LoadedBell>, String), AppError> {
        match (&self.toml, &self.csv, self.preset) {
            (Some(t), None, None) => Ok((clapper_io::parse_bells(t, "bell")?, "bells entered".into())),
            (None, Some(c), None) => Ok((clapper_io::parse_ring_csv(c)?, "ring file (CSV)".into())),
            (None, None, p) => {
                let p = p.unwrap_or(crate::simulate::Preset::Lab);
                Ok((vec![p.loaded()], format!("preset {}", p.name())))
            }
            _ => Err(AppError::Request("give one of preset, toml or csv".into())),
        }
    }

    /// Each bell of the request as the bell source of a
    /// [`crate::simulate::SimulateRequest`], in the order of [`Self::bells`]:
    /// `{"bell": "...its own bell file..."}` or `{"preset": "lab"}`. A page
    /// that diagnosed a ring simulates one of its bells with these.
    pub fn one_bell_sources(&self) -> Result<Vec<serde_json::Value>, AppError> {
        Ok(match (&self.toml, &self.csv) {
            (Some(t), None) => clapper_io::bell_texts(t, false, "bell")?,
            (None, Some(c)) => clapper_io::bell_texts(c, true, "bell")?,
            _ => {
                let p = self.preset.unwrap_or(crate::simulate::Preset::Lab);
                return Ok(vec![serde_json::json!({ "preset": p.name() })]);
            }
        }
        .into_iter()
        .map(|text| serde_json::json!({ "bell": text }))
        .collect())
    }
}

#[derive(Serialize)]
/// Double strike index D at three coefficients of restitution.
pub struct DByR {
    /// D at R = 0.05.
    #[serde(rename = "0.05")]
    pub r005: Option<f64>,
    /// D at R = 0.1.
    #[serde(rename = "0.1")]
    pub r01: Option<f64>,
    /// D at R = 0.2.
    #[serde(rename = "0.2")]
    pub r02: Option<f64>,
}

#[derive(Serialize)]
/// How the bell rings in one style.
pub struct StyleReport {
    /// Whether the style is sustained fully up.
    pub sustained: bool,
    /// Bell angle at the first strike (deg).
    pub first_strike_theta_deg: Option<f64>,
    /// Clapper rate just before the first strike (rad/s).
    pub strike_phidot_rad_s: Option<f64>,
    /// Bell angle at lift-off (deg).
    pub liftoff_theta_deg: Option<f64>,
    /// D of (33) at R = 0.05, 0.1, 0.2.
    pub double_strike_index: DByR,
}

fn style_json(o: &StyleOutcome) -> StyleReport {
    StyleReport {
        sustained: o.sustained,
        first_strike_theta_deg: o.strike_theta.map(f64::to_degrees),
        strike_phidot_rad_s: o.strike_phidot,
        liftoff_theta_deg: o.liftoff_theta.map(f64::to_degrees),
        double_strike_index: DByR {
            r005: o.double_strike_index[0],
            r01: o.double_strike_index[1],
            r02: o.double_strike_index[2],
        },
    }
}

#[derive(Serialize)]
/// How far the bell is from the edge of its usual region.
pub struct MarginReport {
    /// Distance to the edge in chart units (r/L_c, L_b/L_c).
    pub chart_units: Option<f64>,
    /// How much shorter the clapper period may get (s).
    pub clapper_period_shorter_s: Option<f64>,
    /// How much longer the clapper period may get (s).
    pub clapper_period_longer_s: Option<f64>,
    /// How much r may shrink (mm).
    pub r_smaller_mm: Option<f64>,
    /// How much r may grow (mm).
    pub r_larger_mm: Option<f64>,
}

#[derive(Serialize)]
/// A change a bell-hanger can make, with what the model predicts after it.
pub struct ChangeReport {
    /// "flight-mass", "flight-length", "ball-position", "wooden-shaft",
    /// "new-clapper" or "pivot".
    pub kind: &'static str,
    /// Whether it cures every problem (else some; `problems_left` says
    /// which stay).
    pub fixes_all: bool,
    /// The problems left after it, in words.
    pub problems_left: Vec<String>,
    /// A pivot change: offered only because no change of the clapper cures
    /// all.
    pub last_resort: bool,
    /// Mass added to the flight (kg; negative: taken off), flight-mass.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub flight_mass_change_kg: Option<f64>,
    /// Where that mass is assumed to go, below the clapper pivot (m).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub flight_depth_m: Option<f64>,
    /// The flight's length before and after (m), flight-length.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub flight_length_m: Option<[f64; 2]>,
    /// The ball's centre below the pivot before and after (m), ball-position.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ball_position_m: Option<[f64; 2]>,
    /// Change of r (mm), pivot.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pivot_change_mm: Option<f64>,
    /// The clapper's mass after (kg).
    pub clapper_mass_kg: f64,
    /// The clapper's period after (s).
    pub clapper_period_s: f64,
    /// Chart position after: r/L_c.
    pub r_over_lc: f64,
    /// Chart position after: L_b/L_c.
    pub lb_over_lc: f64,
    /// How it rings right after the change (re-simulated).
    pub predicted_right: StyleReport,
    /// How it goes up after the change: "right", "wrong" or "no strike".
    pub goes_up: &'static str,
    /// Distance on the chart to the edge of ringing right after the change
    /// (chart units), if within the search.
    pub margin_chart_units: Option<f64>,
    /// The clapper's parts after the change, as a bell file's `[clapper]`
    /// table, when the parts were given.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub clapper_toml: Option<String>,
    /// The change and its result in words.
    pub words: String,
}

#[derive(Serialize)]
/// Loads on the frame over a stroke. In newtons only when the bell's mass
/// was weighed (given); otherwise null, and only the multiples of the
/// weight stand, computed with masses assumed at the bell's size.
pub struct FrameReport {
    /// Whether the newton figures rest on a weighed bell.
    pub bell_mass_measured: bool,
    /// Weight of bell and clapper (N), when the bell was weighed.
    pub weight_n: Option<f64>,
    /// Largest horizontal load (N), when the bell was weighed.
    pub peak_horizontal_n: Option<f64>,
    /// Largest downward load (N), when the bell was weighed.
    pub peak_vertical_down_n: Option<f64>,
    /// Least downward load (N), when the bell was weighed.
    pub least_vertical_n: Option<f64>,
    /// Largest horizontal load over the weight.
    pub peak_horizontal_over_weight: f64,
    /// Largest downward load over the weight.
    pub peak_vertical_over_weight: f64,
    /// Least downward load over the weight (below 0: the bell lifts).
    pub least_vertical_over_weight: f64,
    /// The loads in words, as the text report gives them.
    pub words: String,
}

#[derive(Serialize)]
/// One bell's diagnosis: what `clapper diagnose --json` prints per bell.
pub struct BellDiagnosisReport {
    /// The bell's name.
    pub name: String,
    /// Chart position r/L_c.
    pub r_over_lc: f64,
    /// Chart position L_b/L_c.
    pub lb_over_lc: f64,
    /// Bell period T_b (s).
    pub tb_s: f64,
    /// Clapper period T_c (s).
    pub tc_s: f64,
    /// Clapper pivot offset r (mm).
    pub r_mm: f64,
    /// Contact angle phi_max (deg).
    pub phi_max_deg: f64,
    /// Properties assumed, not measured.
    pub assumed: Vec<String>,
    /// What is odd about the bell (simulated anyway): an impossible
    /// inertia, a place off the chart no tower bell has, a contact angle
    /// no clapper has ([`clapper_core::bell::BellWarning`]).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
    /// Rings right fully up.
    pub rings_right: bool,
    /// Rings wrong fully up.
    pub rings_wrong: bool,
    /// "both", "right", "wrong" or "neither".
    pub verdict: String,
    /// The style it usually rings.
    pub usual_style: Option<String>,
    /// Bell angle at the first strike (deg).
    pub first_strike_theta_deg: Option<f64>,
    /// Clapper rate just before the first strike (rad/s).
    pub strike_phidot_rad_s: Option<f64>,
    /// |phi'| L_c: the clapper's speed at its centre of percussion.
    striking_speed_m_s: Option<f64>,
    /// 1/2 I_c phi'^2, only when the clapper's mass and b were given.
    strike_energy_j: Option<f64>,
    /// Bell angle at lift-off (deg).
    pub liftoff_theta_deg: Option<f64>,
    /// D of (33) at R = 0.05, 0.1, 0.2.
    pub double_strike_index: DByR,
    /// Lowest starting angle from which it rings right (deg).
    pub min_theta0_right_deg: Option<f64>,
    /// Margin to the edge of its region.
    pub margin: Option<MarginReport>,
    /// Problems found, in words.
    pub problems: Vec<String>,
    /// How it goes up, rung up from rest by the default ringer: "right",
    /// "wrong" or "no strike".
    pub goes_up: &'static str,
    /// The changes a hanger can make that cure its problems (all or some),
    /// in the order a hanger would try them; the pivot only as a last
    /// resort.
    pub changes: Vec<ChangeReport>,
    /// Frame loads.
    pub frame: Option<FrameReport>,
    /// Why it stands apart from the rest of the ring.
    pub stands_apart: Vec<String>,
    /// Ringing right.
    pub right: StyleReport,
    /// Ringing wrong.
    pub wrong: StyleReport,
    /// Odd-struckness and how to cure it, for a bell with a pivot offset or
    /// unequal contact angles.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub odd_struck: Option<OddStruckReport>,
}

/// How odd-struck a bell is and what evens it (docs/model.md §10.3).
#[derive(Serialize, Clone, Debug, PartialEq)]
pub struct OddStruckReport {
    /// Handstroke minus backstroke time from bottom dead centre to the
    /// strike (ms): positive, the handstroke strikes late.
    pub odd_struck_ms: f64,
    /// The aim (ms): odd-struckness within ± this.
    pub tolerance_ms: f64,
    /// The ball's centre below the clapper pivot used (m).
    pub ball_below_pivot_m: f64,
    /// Change per mm the ball moves toward the back side, pivot fixed (ms/mm).
    pub ms_per_mm_at_ball: f64,
    /// The ball move toward the back side that evens it (mm), if found.
    pub ball_move_mm: Option<f64>,
    /// Odd-struckness after that move, simulated (ms).
    pub after_ball_move_ms: Option<f64>,
    /// Change per mm the clapper pivot moves toward the back side (ms/mm).
    pub ms_per_mm_at_pivot: f64,
    /// The pivot move toward the back side that evens it (mm), if found.
    pub pivot_move_mm: Option<f64>,
    /// Odd-struckness after that move, simulated (ms).
    pub after_pivot_move_ms: Option<f64>,
    /// In words.
    pub words: String,
}

/// What the odd-struckness part of a diagnosis needs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OddStruckOptions {
    /// The ball's centre below the clapper pivot (m); unset: the clapper's
    /// equivalent pendulum length L_c (its centre of percussion, where a
    /// ball strikes without jarring the pivot), an estimate.
    pub ball_below_pivot_m: Option<f64>,
    /// The aim (ms). Default 1 ms: the tape guidance's 1 mm of gap moves a
    /// bell's strike by a few ms, and a listener hears 10 to 20 ms.
    pub tolerance_ms: f64,
}

impl Default for OddStruckOptions {
    fn default() -> Self {
        Self {
            ball_below_pivot_m: None,
            tolerance_ms: 1.0,
        }
    }
}

fn odd_struck_report(bell: &Bell, opts: &OddStruckOptions) -> Result<Option<OddStruckReport>, AppError> {
    let h = &bell.hanging;
    if h.pivot_offset == 0.0 && h.phi_max_skew == 0.0 {
        return Ok(None);
    }
    let ball = opts.ball_below_pivot_m.unwrap_or_else(|| bell.lc());
    let cfg = SimConfig::default();
    let Some(fix) = clapper_core::diagnose::odd_struck_fix(bell, &cfg, ball, opts.tolerance_ms * 1e-3)? else {
        return Ok(None);
    };
    let ms = |s: f64| s * 1e3;
    let side = |x: f64| {
        if x > 0.0 {
            "toward the back side"
        } else {
            "toward the hand side"
        }
    };
    let now = ms(fix.odd_struck);
    let mut words = format!(
        "odd-struck by {} ({}); {:+.2} ms per mm at the ball, {:+.2} ms per mm at the pivot",
        crate::simulate::odd_struck_ms_text(now),
        crate::simulate::which_stroke_late(now),
        // s per m is ms per mm.
        fix.per_ball_shift,
        fix.per_pivot_shift
    );
    if now.abs() <= opts.tolerance_ms {
        words += &format!("; within {} ms already", opts.tolerance_ms);
    } else {
        if let Some((x, after)) = fix.ball_shift {
            words += &format!(
                "; move the ball {:.1} mm {} (its gaps change by {:.1} mm each) to bring it to {:+.2} ms",
                x.abs() * 1e3,
                side(x),
                x.abs() * 1e3,
                ms(after)
            );
        }
        if let Some((p, after)) = fix.pivot_shift {
            words += &format!(
                "; or move the clapper pivot {:.1} mm {} ({:+.2} ms)",
                p.abs() * 1e3,
                side(p),
                ms(after)
            );
        }
    }
    Ok(Some(OddStruckReport {
        odd_struck_ms: now,
        tolerance_ms: opts.tolerance_ms,
        ball_below_pivot_m: ball,
        ms_per_mm_at_ball: fix.per_ball_shift,
        ball_move_mm: fix.ball_shift.map(|(x, _)| x * 1e3),
        after_ball_move_ms: fix.ball_shift.map(|(_, v)| ms(v)),
        ms_per_mm_at_pivot: fix.per_pivot_shift,
        pivot_move_mm: fix.pivot_shift.map(|(p, _)| p * 1e3),
        after_pivot_move_ms: fix.pivot_shift.map(|(_, v)| ms(v)),
        words,
    }))
}

#[derive(Serialize)]
/// A diagnosis of a bell or a ring: what `clapper diagnose --json` prints.
pub struct DiagnosisReport {
    /// Settings of the verdicts.
    pub settings: serde_json::Value,
    /// Every bell.
    pub bells: Vec<BellDiagnosisReport>,
    /// Bells that stand apart, in words.
    pub outliers: Vec<String>,
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
    let mut words = format!(
        "{what}; T_c {:.3} s -> {:.3} s; then it rings right, first strike at {:.0} deg with phi' = {:.2} rad/s, D = {:.1} at R = 0.1, goes up {}; {}",
        bell.tc(),
        h.bell.tc(),
        p.strike_theta.map_or(f64::NAN, f64::to_degrees),
        p.strike_phidot.unwrap_or(f64::NAN),
        p.double_strike_index[1].unwrap_or(f64::NAN),
        crate::ring_up::settles_name(h.goes_up),
        h.margin.map_or("no edge within the search".into(), |m| format!("margin {m:.3} chart units"))
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
        predicted_right: style_json(&h.predicted),
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
        double_strike_index: style_json(usual.unwrap_or(&d.right)).double_strike_index,
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
        right: style_json(&d.right),
        wrong: style_json(&d.wrong),
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
        if let Some(v) = b.striking_speed_m_s {
            let _ = writeln!(
                o,
                "  strike: {:.2} m/s at the clapper's centre of percussion{}",
                v,
                b.strike_energy_j.map_or(String::new(), |e| format!(", {e:.1} J"))
            );
        }
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
    }
    h.push_str("</table>");
    let details = text(rep, source);
    let _ = write!(h, "<h2>Bell by bell</h2><pre>{}</pre>", html_escape(&details));
    h.push_str("</body></html>\n");
    h
}

/// Diagnose `bells` (in parallel; the result does not depend on the
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
            rep.odd_struck = odd_struck_report(&b.bell, &odd)?;
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

/// The chart of styles with `bells` marked, and a close-up around them,
/// as SVG text (two 40 x 40 sweeps, about 0.3 s on two cores).
pub fn chart_svg(bells: &[LoadedBell]) -> Result<String, AppError> {
    // The chart is drawn for the bells' own contact angle (their median),
    // not the paper's 26 deg: a ring of 28-30 deg was drawn on a 26 deg chart.
    let mut phis: Vec<f64> = bells.iter().map(|b| b.bell.phi_max).collect();
    phis.sort_by(f64::total_cmp);
    let phi_max = match phis.len() {
        0 => clapper_core::bell::CHART_PHI_MAX_DEG.to_radians(),
        n if n % 2 == 1 => phis[n / 2],
        n => 0.5 * (phis[n / 2 - 1] + phis[n / 2]),
    };
    let spec = ChartSpec {
        nx: 40,
        ny: 40,
        styles: Styles::Both,
        construction: clapper_core::bell::ChartConstruction {
            phi_max,
            ..Default::default()
        },
        ..ChartSpec::default()
    };
    let phi_words = match (phis.first(), phis.last()) {
        (Some(lo), Some(hi)) if hi - lo > 0.05f64.to_radians() => format!(
            "phi_max = {:.1} deg, the bells' median; theirs {:.1} to {:.1} deg",
            phi_max.to_degrees(),
            lo.to_degrees(),
            hi.to_degrees()
        ),
        _ if bells.len() == 1 => format!("phi_max = {:.1} deg, the bell's", phi_max.to_degrees()),
        _ => format!("phi_max = {:.1} deg, the bells'", phi_max.to_degrees()),
    };
    let chart = clapper_core::chart::sweep(&spec, &|_| {})?;
    let markers: Vec<Marker> = bells
        .iter()
        .map(|b| Marker {
            x: b.bell.r_over_lc(),
            y: b.bell.lb_over_lc(),
            label: b.name.clone(),
        })
        .collect();
    let no_style = || AppError::Request("the chart has no style to show".into());
    let panel = quantity::style_panel(&chart, "").ok_or_else(no_style)?;
    let fig = quantity::figure(
        format!("Styles sustained (theta0 = 171 deg, R = 0.2, {phi_words})"),
        clapper_plot::Quantity::Style,
        vec![panel],
        markers.clone(),
    );
    let mut svg = clapper_plot::chart_figure_svg(&fig)?;
    // A close-up around the bells, where a ring's labels would crowd.
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for b in bells {
        x0 = x0.min(b.bell.r_over_lc());
        x1 = x1.max(b.bell.r_over_lc());
        y0 = y0.min(b.bell.lb_over_lc());
        y1 = y1.max(b.bell.lb_over_lc());
    }
    let zoom = ChartSpec {
        domain: clapper_core::chart::Domain {
            x: (x0 - 0.1, x1 + 0.1),
            y: ((y0 - 0.1).max(0.05), y1 + 0.1),
        },
        ..spec
    };
    let zc = clapper_core::chart::sweep(&zoom, &|_| {})?;
    let zfig = quantity::figure(
        "Close-up around the bells".into(),
        clapper_plot::Quantity::Style,
        vec![quantity::style_panel(&zc, "").ok_or_else(no_style)?],
        markers,
    );
    svg.push_str(&clapper_plot::chart_figure_svg(&zfig)?);
    Ok(svg)
}

/// The self-contained HTML report of a diagnosis (charts embedded).
pub fn report_page(rep: &DiagnosisReport, bells: &[LoadedBell], source: &str) -> Result<String, AppError> {
    Ok(report_html(rep, source, &chart_svg(bells)?))
}
