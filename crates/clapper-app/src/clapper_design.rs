//! A clapper from its parts (`clapper design-clapper`, docs/model.md §12):
//! its mass properties, where it puts the bell on the clapping chart, the
//! Central Council's period rule, and the flight length or ball position
//! that gives a wanted period.

use std::fmt::Write as _;

use clapper_core::bell::{length_of_period, ParamError};
use clapper_core::clapper_parts::{design_for_period, Adjust, ClapperMass, ClapperParts, Designed, MAX_CLAPPER_LENGTH};
use clapper_core::ringer::CCCBR_LB_OVER_LC;
use clapper_io::clapper_input::ClapperInput;
use serde::{Deserialize, Serialize};

use crate::AppError;

/// What to design: the parts, and optionally the bell it hangs in and a
/// period to reach.
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DesignRequest {
    /// The clapper's parts (the `[clapper]` table's keys).
    #[serde(deserialize_with = "a_table")]
    pub clapper: ClapperInput,
    /// The bell's small-swing period T_b (s), to place the clapper on the
    /// chart and check the rule T_c ≥ 0.9 T_b.
    #[serde(default)]
    pub bell_period_s: Option<f64>,
    /// r (m): the clapper pivot below the bell's pivot, along the bell's axis.
    #[serde(default)]
    pub pivot_m: Option<f64>,
    /// A wanted T_c (s): the clapper is changed to give it.
    #[serde(default)]
    pub target_period_s: Option<f64>,
    /// What to change for the target [default: the flight's length].
    #[serde(default)]
    pub adjust: Option<Adjust>,
}

/// A table of named values only: serde would also read a struct from a
/// list by position (`{"clapper": [1, 2]}` was a shaft 1 m long and 2 m
/// thick, a 24-tonne clapper).
fn a_table<'de, D, T>(d: D) -> Result<T, D::Error>
where
    D: serde::Deserializer<'de>,
    T: Deserialize<'de>,
{
    struct Table<T>(std::marker::PhantomData<T>);
    impl<'de, T: Deserialize<'de>> serde::de::Visitor<'de> for Table<T> {
        type Value = T;
        fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
            f.write_str("a table of the clapper's parts by name, such as {\"shaft_length_m\": 0.69, ...}")
        }
        fn visit_map<A: serde::de::MapAccess<'de>>(self, map: A) -> Result<T, A::Error> {
            T::deserialize(serde::de::value::MapAccessDeserializer::new(map))
        }
    }
    d.deserialize_map(Table(std::marker::PhantomData))
}

/// One part's share.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PartReport {
    /// "shaft", "ball" or "flight".
    pub name: &'static str,
    /// Mass (kg).
    pub mass_kg: f64,
    /// Centre below the pivot (m).
    pub centre_m: f64,
    /// Moment of inertia about the pivot (kg m²).
    pub inertia_kg_m2: f64,
}

/// A clapper's mass properties as reported.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ClapperFigures {
    /// m (kg).
    pub m_kg: f64,
    /// b, centre of mass below the pivot (m).
    pub b_m: f64,
    /// I_c about the pivot (kg m²).
    pub ic_kg_m2: f64,
    /// L_c = I_c / (m b) (m).
    pub lc_m: f64,
    /// T_c (s).
    pub tc_s: f64,
    /// The parts.
    pub parts: Vec<PartReport>,
}

impl ClapperFigures {
    fn of(parts: &ClapperParts, c: &ClapperMass) -> Self {
        Self {
            m_kg: c.mass,
            b_m: c.b,
            ic_kg_m2: c.inertia,
            lc_m: c.lc(),
            tc_s: c.tc(),
            parts: parts
                .parts()
                .into_iter()
                .map(|p| PartReport {
                    name: p.name,
                    mass_kg: p.mass,
                    centre_m: p.centre,
                    inertia_kg_m2: p.inertia,
                })
                .collect(),
        }
    }
}

/// The clapper in its bell.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct InBell {
    /// T_b (s).
    pub tb_s: f64,
    /// L_b (m).
    pub lb_m: f64,
    /// T_c / T_b.
    pub period_ratio: f64,
    /// Whether T_c ≥ 0.9 T_b, the Central Council's rule of thumb for a
    /// bell that goes up right.
    pub cccbr_rule_met: bool,
    /// L_b / L_c, the chart's vertical axis.
    pub lb_over_lc: f64,
    /// r / L_c, the chart's horizontal axis, when the pivot is given.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub r_over_lc: Option<f64>,
}

/// The answer to a target period.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct DesignOutcome {
    /// The wanted T_c (s).
    pub target_tc_s: f64,
    /// "flight-length" or "ball-position".
    pub adjust: Adjust,
    /// Whether a size within reach gives it.
    pub found: bool,
    /// The flight's new length (m), adjusting the flight.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub flight_length_m: Option<f64>,
    /// The ball's new position below the pivot (m), adjusting the ball.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ball_position_m: Option<f64>,
    /// The changed clapper.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub clapper: Option<ClapperFigures>,
    /// Out of reach: the shortest and longest T_c the change can give (s).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reach_s: Option<[f64; 2]>,
}

/// `clapper design-clapper --json`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct DesignReport {
    /// The clapper as given: `m_kg`, `b_m`, `ic_kg_m2`, `lc_m`, `tc_s` and
    /// `parts` at the top level of the JSON.
    #[serde(flatten)]
    pub clapper: ClapperFigures,
    /// r (m), when given.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub r_m: Option<f64>,
    /// The clapper in its bell, when T_b is given.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub bell: Option<InBell>,
    /// The clapper changed for a target period, when one is given.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub design: Option<DesignOutcome>,
    /// The clapper part of a bell file: the designed clapper if one was
    /// found, else the one given.
    pub bell_file_toml: String,
}

/// The longest period taken (s): a 25 m pendulum's.
const MAX_PERIOD_S: f64 = 10.0;

/// `v` if a period above 0 and at most [`MAX_PERIOD_S`], else the error
/// naming `field`.
fn within_period(field: &'static str, v: f64, allowed: &'static str) -> Result<f64, ParamError> {
    if v.is_finite() && v > 0.0 && v <= MAX_PERIOD_S {
        Ok(v)
    } else {
        Err(ParamError {
            field,
            value: v,
            allowed,
        })
    }
}

/// The clapper's pivot below the bell's (m), if given: within 5 m either way.
fn pivot_of(req: &DesignRequest) -> Result<Option<f64>, AppError> {
    Ok(req
        .pivot_m
        .map(|r| {
            if r.is_finite() && r.abs() <= MAX_CLAPPER_LENGTH {
                Ok(r)
            } else {
                Err(ParamError {
                    field: "pivot_m",
                    value: r,
                    allowed: "a clapper pivot within 5 m of the bell's pivot, either way",
                })
            }
        })
        .transpose()?)
}

/// Answer a [`DesignRequest`].
pub fn design(req: &DesignRequest) -> Result<DesignReport, AppError> {
    let parts = req.clapper.parts().map_err(|e| AppError::Request(e.to_string()))?;
    let c = parts.mass_properties()?;
    let figures = ClapperFigures::of(&parts, &c);
    let r = pivot_of(req)?;
    let bell = match req.bell_period_s {
        None => None,
        Some(tb) => {
            let tb = within_period(
                "bell_period_s",
                tb,
                "a bell's small-swing period above 0 and at most 10 s",
            )?;
            let lb = length_of_period(tb);
            Some(InBell {
                tb_s: tb,
                lb_m: lb,
                period_ratio: c.tc() / tb,
                cccbr_rule_met: lb / c.lc() <= CCCBR_LB_OVER_LC,
                lb_over_lc: lb / c.lc(),
                r_over_lc: r.map(|r| r / c.lc()),
            })
        }
    };
    let mut chosen = parts;
    let design = match req.target_period_s {
        None => None,
        Some(target) => {
            let target = within_period("target_period_s", target, "a clapper's period above 0 and at most 10 s")?;
            let adjust = req.adjust.unwrap_or(Adjust::FlightLength);
            Some(match design_for_period(&parts, target, adjust)? {
                Designed::Found(p, m) => {
                    chosen = p;
                    DesignOutcome {
                        target_tc_s: target,
                        adjust,
                        found: true,
                        flight_length_m: (adjust == Adjust::FlightLength).then_some(p.flight_length),
                        ball_position_m: (adjust == Adjust::BallPosition).then_some(p.ball_position),
                        clapper: Some(ClapperFigures::of(&p, &m)),
                        reach_s: None,
                    }
                }
                Designed::OutOfReach { shortest, longest } => DesignOutcome {
                    target_tc_s: target,
                    adjust,
                    found: false,
                    flight_length_m: None,
                    ball_position_m: None,
                    clapper: None,
                    reach_s: Some([shortest, longest]),
                },
            })
        }
    };
    let mut toml = String::new();
    if let Some(r) = r {
        let _ = writeln!(toml, "r_m = {r}\n");
    }
    toml += &ClapperInput::of(&chosen).to_toml();
    Ok(DesignReport {
        clapper: figures,
        r_m: r,
        bell,
        design,
        bell_file_toml: toml,
    })
}

fn parts_text(out: &mut String, f: &ClapperFigures) {
    for p in &f.parts {
        let _ = writeln!(
            out,
            "  {:<7}{:>8.2} kg, centre {:.3} m below the pivot, {:.3} kg m^2 about it",
            p.name, p.mass_kg, p.centre_m, p.inertia_kg_m2
        );
    }
    let _ = writeln!(
        out,
        "  clapper m {:.2} kg, b {:.3} m, I_c {:.3} kg m^2, L_c {:.3} m, T_c {:.3} s",
        f.m_kg, f.b_m, f.ic_kg_m2, f.lc_m, f.tc_s
    );
}

/// The report in words, as `clapper design-clapper` prints it.
pub fn summary(rep: &DesignReport) -> String {
    let mut out = String::from("clapper from its parts:\n");
    parts_text(&mut out, &rep.clapper);
    if let Some(r) = rep.r_m {
        let _ = writeln!(out, "  pivot r {r:.3} m below the bell's pivot");
    }
    if let Some(b) = &rep.bell {
        let _ = writeln!(
            out,
            "in a bell of T_b {:.3} s (L_b {:.3} m): T_c/T_b {:.3}, {} the rule T_c >= {:.0} % of T_b; chart point L_b/L_c {:.3}{}",
            b.tb_s,
            b.lb_m,
            b.period_ratio,
            if b.cccbr_rule_met { "meets" } else { "misses" },
            100.0 / CCCBR_LB_OVER_LC.sqrt(),
            b.lb_over_lc,
            b.r_over_lc.map(|x| format!(", r/L_c {x:.3}")).unwrap_or_default()
        );
    }
    if let Some(d) = &rep.design {
        let what = match d.adjust {
            Adjust::FlightLength => "flight length",
            Adjust::BallPosition => "ball position",
        };
        match (&d.clapper, d.reach_s) {
            (Some(c), _) => {
                let size = d
                    .flight_length_m
                    .map(|l| format!("a flight {l:.3} m long"))
                    .or(d
                        .ball_position_m
                        .map(|z| format!("the ball's centre {z:.3} m below the pivot")))
                    .unwrap_or_default();
                let _ = writeln!(out, "for T_c {:.3} s by the {what}: {size}", d.target_tc_s);
                parts_text(&mut out, c);
                if let Some(b) = &rep.bell {
                    let ratio = c.tc_s / b.tb_s;
                    let _ = writeln!(
                        out,
                        "  in the bell: T_c/T_b {ratio:.3}, L_b/L_c {:.3}{}",
                        b.lb_m / c.lc_m,
                        rep.r_m
                            .map(|r| format!(", r/L_c {:.3}", r / c.lc_m))
                            .unwrap_or_default()
                    );
                }
            }
            (None, Some([lo, hi])) => {
                let _ = writeln!(
                    out,
                    "for T_c {:.3} s by the {what}: out of reach; that change gives {lo:.3} to {hi:.3} s",
                    d.target_tc_s
                );
            }
            _ => {}
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn gsm() -> DesignRequest {
        serde_json::from_str(
            r#"{"clapper": {"shaft_length_m": 0.69, "shaft_diameter_m": 0.05, "ball_diameter_m": 0.14,
                "ball_position_m": 0.76, "flight_length_m": 0.2, "flight_diameter_m": 0.05},
                "bell_period_s": 2.0, "pivot_m": 0.179}"#,
        )
        .unwrap()
    }

    #[test]
    fn the_report_places_the_clapper_and_checks_the_rule() {
        let rep = design(&gsm()).unwrap();
        let b = rep.bell.as_ref().unwrap();
        assert!((b.period_ratio - rep.clapper.tc_s / 2.0).abs() < 1e-12);
        assert_eq!(b.cccbr_rule_met, rep.clapper.tc_s >= 1.8);
        assert!((b.r_over_lc.unwrap() - 0.179 / rep.clapper.lc_m).abs() < 1e-12);
        let sum: f64 = rep.clapper.parts.iter().map(|p| p.mass_kg).sum();
        assert!((sum - rep.clapper.m_kg).abs() < 1e-9);
        assert!(
            rep.bell_file_toml.starts_with("r_m = 0.179\n\n[clapper]\n"),
            "{}",
            rep.bell_file_toml
        );
        assert!(summary(&rep).contains("misses") || summary(&rep).contains("meets"));
    }

    #[test]
    fn a_target_period_changes_the_clapper_and_the_file_written() {
        let mut req = gsm();
        req.target_period_s = Some(1.85);
        let rep = design(&req).unwrap();
        let d = rep.design.as_ref().unwrap();
        assert!(d.found);
        assert!((d.clapper.as_ref().unwrap().tc_s - 1.85).abs() < 1e-9);
        let l = (d.flight_length_m.unwrap() * 1e6).round() / 1e6;
        assert!(
            rep.bell_file_toml.contains(&format!("flight_length_m = {l}\n")),
            "{}",
            rep.bell_file_toml
        );
        req.target_period_s = Some(0.5);
        let rep = design(&req).unwrap();
        let d = rep.design.unwrap();
        assert!(!d.found && d.reach_s.is_some());
        assert!(rep.bell_file_toml.contains("flight_length_m = 0.2\n"));
    }

    #[test]
    fn bad_input_is_a_request_error() {
        let mut req = gsm();
        req.bell_period_s = Some(-1.0);
        assert!(design(&req).unwrap_err().is_bad_input());
        req = gsm();
        req.clapper.shaft_length_m = Some(0.9);
        let e = design(&req).unwrap_err();
        assert!(e.is_bad_input() && e.to_string().contains("shaft_length_m"), "{e}");
    }
}
