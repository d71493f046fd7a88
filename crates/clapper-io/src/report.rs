//! The JSON report of `clapper simulate --json` (and of the web API, which
//! answers the same object).

use clapper_core::bell::{Bell, BellWarning};
use clapper_core::ringing::{Protocol, Ringing};
use clapper_core::stroke::{
    ClapperState, ContactModel, EndReason, Integrator, LiftoffKind, SimConfig, StrikeAmplitude, Stroke,
};
use clapper_core::Choice;
use serde::Serialize;

use crate::bell_file::BellSource;

/// Bell properties as reported: chart position, lengths, periods, and the
/// mass properties simulated.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct BellReport {
    /// Name of the bell (preset, file, or chart point).
    pub name: String,
    /// r / L_c.
    pub r_over_lc: f64,
    /// L_b / L_c.
    pub lb_over_lc: f64,
    /// L_b (m).
    pub lb_m: f64,
    /// L_c (m).
    pub lc_m: f64,
    /// T_b (s).
    pub tb_s: f64,
    /// T_c (s).
    pub tc_s: f64,
    /// M (kg).
    pub bell_mass_kg: f64,
    /// m (kg).
    pub clapper_mass_kg: f64,
    /// a (m).
    pub a_m: f64,
    /// b (m).
    pub b_m: f64,
    /// I_b (kg m²).
    pub bell_inertia_kg_m2: f64,
    /// I_c (kg m²).
    pub clapper_inertia_kg_m2: f64,
    /// r (m).
    pub r_m: f64,
    /// φ_max (deg); the mean of the two sides' when they differ.
    pub phi_max_deg: f64,
    /// The pivot offset d (m), when not zero.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pivot_offset_m: Option<f64>,
    /// Contact angles of the hand and back sides (deg), when they differ.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub phi_max_hand_deg: Option<f64>,
    /// The back side's.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub phi_max_back_deg: Option<f64>,
    /// Friction, when there is any.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub friction: Option<clapper_core::hanging::Friction>,
    /// Mass properties that were assumed, not given (tower measurements).
    pub assumed: Vec<String>,
    /// Physically odd properties that were simulated anyway.
    pub warnings: Vec<String>,
}

impl BellReport {
    /// The report of `bell` named `name`, read from `source`.
    pub fn new(name: &str, bell: &Bell, source: &BellSource) -> Self {
        let assumed = match source {
            BellSource::MassProperties => vec![],
            BellSource::Tower(a) => a.fields.iter().map(|(k, v)| format!("{k} = {v:.4}")).collect(),
        };
        Self {
            name: name.to_string(),
            r_over_lc: bell.r_over_lc(),
            lb_over_lc: bell.lb_over_lc(),
            lb_m: bell.lb(),
            lc_m: bell.lc(),
            tb_s: bell.tb(),
            tc_s: bell.tc(),
            bell_mass_kg: bell.bell_mass,
            clapper_mass_kg: bell.clapper_mass,
            a_m: bell.a,
            b_m: bell.b,
            bell_inertia_kg_m2: bell.bell_inertia,
            clapper_inertia_kg_m2: bell.clapper_inertia,
            r_m: bell.r,
            phi_max_deg: bell.phi_max.to_degrees(),
            pivot_offset_m: Some(bell.hanging.pivot_offset).filter(|d| *d != 0.0),
            phi_max_hand_deg: (bell.hanging.phi_max_skew != 0.0).then(|| bell.contact_angles().0.to_degrees()),
            phi_max_back_deg: (bell.hanging.phi_max_skew != 0.0).then(|| bell.contact_angles().1.to_degrees()),
            friction: Some(bell.hanging.friction).filter(|f| !f.is_none()),
            assumed,
            warnings: bell.warnings().iter().map(BellWarning::to_string).collect(),
        }
    }
}

/// The settings a simulation ran with.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct SimulationSettings {
    /// θ0 (deg).
    pub theta0_deg: f64,
    /// R: the first impact's on a side (the strike's).
    pub restitution: f64,
    /// R2: the later bounces', when given apart from R.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub restitution_later: Option<f64>,
    /// What the double strike's amplitude ratio compares, when not the
    /// clapper's rate (docs/model.md §4.1).
    #[serde(skip_serializing_if = "StrikeAmplitude::is_rate")]
    pub strike_amplitude: StrikeAmplitude,
    /// "impact" or "penalty".
    pub contact: ContactModel,
    /// k (N m/rad) for the penalty model, else null.
    pub stiffness_n_m_per_rad: Option<f64>,
    /// "restart" or "free".
    pub protocol: Protocol,
    /// Strokes asked for.
    pub strokes_requested: usize,
    /// Integrator relative tolerance.
    pub rtol: f64,
    /// "taylor-N" (a Taylor series of order N) or "dopri5".
    pub integrator: String,
}

impl SimulationSettings {
    /// The settings of `cfg` under `protocol` for `strokes` strokes.
    pub fn new(cfg: &SimConfig, protocol: Protocol, strokes: usize) -> Self {
        Self {
            theta0_deg: cfg.theta0.to_degrees(),
            restitution: cfg.restitution,
            restitution_later: cfg.restitution_later,
            strike_amplitude: cfg.strike_amplitude,
            contact: cfg.contact,
            stiffness_n_m_per_rad: (cfg.contact == ContactModel::Penalty).then_some(cfg.stiffness),
            protocol,
            strokes_requested: strokes,
            rtol: cfg.ode.rtol,
            integrator: match cfg.integrator {
                Integrator::Taylor => format!("taylor-{}", cfg.taylor.order),
                Integrator::Dopri5 => "dopri5".into(),
            },
        }
    }
}

/// The first strike of a stroke.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct StrikeReport {
    /// θ at the strike (deg).
    pub theta_deg: f64,
    /// φ' just before (rad/s).
    pub phidot_rad_s: f64,
    /// Time since the stroke began (s).
    pub t_s: f64,
}

/// One impact.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct ImpactReport {
    /// Time since the stroke began (s).
    pub t_s: f64,
    /// θ (deg).
    pub theta_deg: f64,
    /// φ' just before (rad/s).
    pub phidot_rad_s: f64,
    /// φ' just after, or at separation for the penalty model (rad/s).
    pub phidot_after_rad_s: Option<f64>,
    /// +1 or −1.
    pub side: i8,
}

/// One stroke.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct StrokeReport {
    /// 1-based number; odd strokes are handstrokes.
    pub number: usize,
    /// Time the stroke began, from the start of the simulation (s).
    pub start_t_s: f64,
    /// θ at the start (deg).
    pub start_theta_deg: f64,
    /// Side the clapper started on (+1/−1).
    pub start_side: i8,
    /// Style the stroke began in.
    pub style: String,
    /// The first strike, or null.
    pub first_strike: Option<StrikeReport>,
    /// Time from bottom dead centre (θ = 0) to the first strike (ms), or null.
    pub bdc_to_strike_ms: Option<f64>,
    /// θ when the clapper last left its starting side before the first strike (deg).
    pub liftoff_theta_deg: Option<f64>,
    /// How it left then: "from rest", or "bounce" (still flying from the
    /// stroke before, it bounced off its starting side without resting).
    pub liftoff_kind: Option<&'static str>,
    /// dt12 (ms).
    pub second_strike_delay_ms: Option<f64>,
    /// A.
    pub amplitude_ratio: Option<f64>,
    /// D of (33), clamped; null without a second impact.
    pub double_strike_index: Option<f64>,
    /// Why a stroke that struck has no second impact (and so no D), or null.
    pub no_second_impact: Option<&'static str>,
    /// Time from the first strike until the clapper came to rest (s).
    pub bounce_time_s: Option<f64>,
    /// Every impact.
    pub impacts: Vec<ImpactReport>,
    /// θ at the end (deg).
    pub end_theta_deg: f64,
    /// Side the clapper was left on (+1/−1).
    pub end_side: i8,
    /// "resting", "flying" or "in contact".
    pub end_clapper: String,
    /// "turning point", "over the balance" or "time limit".
    pub end_reason: String,
    /// Duration (s).
    pub duration_s: f64,
    /// The style the next stroke starts in.
    pub continues_as: String,
    /// Whether this stroke sustained its style.
    pub sustained: bool,
    /// Integrator steps.
    pub steps: u64,
    /// Right-hand-side evaluations.
    pub rhs_evals: u64,
}

fn side_num(s: clapper_core::stroke::Side) -> i8 {
    s.sign() as i8
}

impl StrokeReport {
    /// The report of stroke `number` (1-based).
    pub fn new(number: usize, s: &Stroke) -> Self {
        let t0 = s.start.t;
        Self {
            number,
            start_t_s: t0,
            start_theta_deg: s.start.y[0].to_degrees(),
            start_side: side_num(s.start_side),
            style: s.style.name().into(),
            first_strike: s.first_strike().map(|i| StrikeReport {
                theta_deg: i.theta.to_degrees(),
                phidot_rad_s: i.phi_dot_before,
                t_s: i.t - t0,
            }),
            bdc_to_strike_ms: s.bdc_to_strike().map(|t| t * 1e3),
            liftoff_theta_deg: s.liftoff_angle().map(f64::to_degrees),
            liftoff_kind: s.liftoff_kind.map(LiftoffKind::name),
            second_strike_delay_ms: s.second_strike_delay().map(|d| d * 1e3),
            amplitude_ratio: s.amplitude_ratio(),
            double_strike_index: s.double_strike_index(),
            no_second_impact: s.no_second_impact(),
            bounce_time_s: s.bounce_time(),
            impacts: s
                .impacts
                .iter()
                .map(|i| ImpactReport {
                    t_s: i.t - t0,
                    theta_deg: i.theta.to_degrees(),
                    phidot_rad_s: i.phi_dot_before,
                    phidot_after_rad_s: i.phi_dot_after,
                    side: side_num(i.side),
                })
                .collect(),
            end_theta_deg: s.end.y[0].to_degrees(),
            end_side: side_num(s.end.side()),
            end_clapper: match s.end.clapper {
                ClapperState::Flying { .. } => "flying",
                ClapperState::Stuck => "stuck",
                ClapperState::Resting(_) | ClapperState::Rebounding { settled: true, .. } => "resting",
                _ => "in contact",
            }
            .into(),
            end_reason: match s.end.reason {
                EndReason::TurningPoint => "turning point",
                EndReason::OverTheBalance => "over the balance",
                EndReason::TimeLimit => "time limit",
                EndReason::Held => "held by friction",
            }
            .into(),
            duration_s: s.end.t - t0,
            continues_as: s.continues_as().name().into(),
            sustained: s.sustained(),
            steps: s.stats.steps,
            rhs_evals: s.stats.rhs_evals,
        }
    }
}

/// Everything `clapper simulate --json` prints.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct SimulationReport {
    /// The bell.
    pub bell: BellReport,
    /// The settings.
    pub settings: SimulationSettings,
    /// The style asked for.
    pub style: String,
    /// Whether the bell sustains that style in steady ringing: its
    /// handstroke and the backstroke after it both keep it (restart
    /// protocol, whatever the protocol of the strokes listed).
    pub sustained: bool,
    /// The style asked for if the bell sustains it, else "neither" (read:
    /// not the style asked; the name is kept for compatibility):
    /// `sustains_instead` then says what the bell does sustain.
    pub verdict: String,
    /// Only when the style asked is not sustained: the style the bell does
    /// sustain in steady ringing, "right" or "wrong" (one that will not
    /// ring right fully up rings wrong steadily), or "neither".
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sustains_instead: Option<String>,
    /// Odd-struckness (ms): handstroke minus backstroke time from bottom dead
    /// centre to the first strike, of the first two strokes (positive: the
    /// handstroke strikes late); 0 for a symmetric bell; null unless both
    /// strike and both keep their style (then `odd_struck_undefined` says
    /// why).
    pub odd_struck_ms: Option<f64>,
    /// Why `odd_struck_ms` is null, when it is.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub odd_struck_undefined: Option<String>,
    /// The strokes.
    pub strokes: Vec<StrokeReport>,
}

impl SimulationReport {
    /// The report of `ringing` of `bell`, with the verdict `sustained`
    /// (steady ringing, [`clapper_core::ringing::sustains`]) and the
    /// odd-struckness (s) of its first two strokes or why it has none.
    pub fn new(
        bell: BellReport,
        settings: SimulationSettings,
        ringing: &Ringing,
        sustained: bool,
        odd_struck: Result<f64, String>,
    ) -> Self {
        Self {
            bell,
            settings,
            style: ringing.style.name().into(),
            sustained,
            verdict: if sustained {
                ringing.style.name().into()
            } else {
                "neither".into()
            },
            sustains_instead: None,
            odd_struck_ms: odd_struck.as_ref().ok().map(|t| t * 1e3),
            odd_struck_undefined: odd_struck.err(),
            strokes: ringing
                .strokes
                .iter()
                .enumerate()
                .map(|(i, s)| StrokeReport::new(i + 1, s))
                .collect(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use clapper_core::ringing::ring;

    #[test]
    fn report_has_the_documented_keys() {
        let bell = Bell::lab();
        let cfg = SimConfig::default();
        let r = ring(
            &bell,
            &cfg,
            clapper_core::stroke::Style::Right,
            Protocol::Restart,
            2,
            &mut (),
        )
        .unwrap();
        let rep = SimulationReport::new(
            BellReport::new("lab", &bell, &BellSource::MassProperties),
            SimulationSettings::new(&cfg, Protocol::Restart, 2),
            &r,
            r.sustained(),
            Ok(0.0),
        );
        let v = serde_json::to_value(&rep).unwrap();
        for k in ["r_over_lc", "lb_over_lc", "lb_m", "lc_m", "tb_s", "tc_s"] {
            assert!(v["bell"][k].is_number(), "{k}");
        }
        assert_eq!(v["style"], "right");
        assert_eq!(v["sustained"], true);
        let s = &v["strokes"][0];
        for k in ["theta_deg", "phidot_rad_s", "t_s"] {
            assert!(s["first_strike"][k].is_number(), "{k}");
        }
        for k in [
            "liftoff_theta_deg",
            "second_strike_delay_ms",
            "amplitude_ratio",
            "double_strike_index",
            "bounce_time_s",
            "end_theta_deg",
            "end_side",
        ] {
            assert!(s[k].is_number(), "{k}");
        }
        let imp = &s["impacts"][0];
        for k in ["t_s", "theta_deg", "phidot_rad_s", "side"] {
            assert!(imp[k].is_number(), "{k}");
        }
        // Backstroke mirrors the handstroke.
        let (a, b) = (&v["strokes"][0], &v["strokes"][1]);
        let fa = a["first_strike"]["theta_deg"].as_f64().unwrap();
        let fb = b["first_strike"]["theta_deg"].as_f64().unwrap();
        assert!((fa + fb).abs() < 1e-6);
    }
}
