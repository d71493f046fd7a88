//! Lift-off angles (`clapper liftoff`): the paper's closed form (15), (16)
//! for r = 0, or the exact lift-off of any bell released from rest (the
//! closed-form swing, docs/model.md §5).

use std::fmt::Write as _;

use clapper_core::prelude::*;
use clapper_io::LoadedBell;
use serde::Serialize;

use crate::AppError;

/// (15), (16): the lift-off angles of a bell with r = 0 (keys alphabetical,
/// as `--json` always printed them).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct FormulaReport {
    /// L_b/L_c.
    pub lb_over_lc: f64,
    /// φ_max (deg).
    pub phi_max_deg: f64,
    /// θ_r (deg).
    pub right_deg: f64,
    /// θ_w (deg).
    pub wrong_deg: f64,
}

impl FormulaReport {
    /// The angles for `lb_over_lc` and `phi_max_deg`.
    pub fn new(lb_over_lc: f64, phi_max_deg: f64) -> Result<Self, AppError> {
        // Real bells have L_b/L_c of about 1 to 1.6; far outside, the
        // formula gives numbers of no bell.
        if !(lb_over_lc.is_finite() && (0.1..=10.0).contains(&lb_over_lc)) {
            return Err(clapper_core::bell::ParamError {
                field: "lb_over_lc",
                value: lb_over_lc,
                allowed: "from 0.1 to 10 (a real bell's L_b/L_c is about 1 to 1.6)",
            }
            .into());
        }
        let a = liftoff_angles(lb_over_lc, phi_max_deg.to_radians())?;
        Ok(Self {
            lb_over_lc,
            phi_max_deg,
            right_deg: a.right.to_degrees(),
            wrong_deg: a.wrong.to_degrees(),
        })
    }

    /// The readable report.
    pub fn text(&self) -> String {
        format!(
            "lift-off for r = 0, L_b/L_c = {}, phi_max = {} deg (equations 15, 16):\n  ringing right  theta_r = {:.2} deg\n  ringing wrong  theta_w = {:.2} deg\n",
            self.lb_over_lc, self.phi_max_deg, self.right_deg, self.wrong_deg
        )
    }
}

/// The lift-off of a bell of any r released from rest at θ0, both styles
/// (keys alphabetical, as `--json` always printed them).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct BellLiftoffReport {
    /// The bell's name.
    pub bell: String,
    /// φ_max (deg).
    pub phi_max_deg: f64,
    /// Ringing right: the angle (deg), none if the clapper stays on.
    pub right_deg: Option<f64>,
    /// Ringing right: the time after release (s).
    pub right_s: Option<f64>,
    /// θ0 (deg).
    pub theta0_deg: f64,
    /// Ringing wrong: the angle (deg).
    pub wrong_deg: Option<f64>,
    /// Ringing wrong: the time after release (s).
    pub wrong_s: Option<f64>,
}

impl BellLiftoffReport {
    /// `loaded` released from rest at `theta0_deg`.
    pub fn new(loaded: &LoadedBell, theta0_deg: f64) -> Result<Self, AppError> {
        let theta0 = theta0_deg.to_radians();
        let of = |style: Style| liftoff_from_rest(&loaded.bell, theta0, style.side(theta0));
        let (right, wrong) = (of(Style::Right)?, of(Style::Wrong)?);
        Ok(Self {
            bell: loaded.name.clone(),
            phi_max_deg: loaded.bell.phi_max.to_degrees(),
            right_deg: right.map(|l| l.theta.to_degrees()),
            right_s: right.map(|l| l.time),
            theta0_deg,
            wrong_deg: wrong.map(|l| l.theta.to_degrees()),
            wrong_s: wrong.map(|l| l.time),
        })
    }

    /// The readable report.
    pub fn text(&self) -> String {
        let mut o = format!(
            "lift-off of {}, released from rest at {} deg, phi_max = {:.2} deg (closed form, any r):\n",
            self.bell, self.theta0_deg, self.phi_max_deg
        );
        for (style, deg, s) in [
            (Style::Right, self.right_deg, self.right_s),
            (Style::Wrong, self.wrong_deg, self.wrong_s),
        ] {
            let words = match (deg, s) {
                (Some(_), Some(0.0)) => "at once: the clapper is not pressed against that side".to_string(),
                (Some(d), Some(t)) => format!("theta = {d:.2} deg, {t:.3} s after release"),
                _ => "none: the clapper stays on through the half swing".to_string(),
            };
            let _ = writeln!(o, "  ringing {:<6} {words}", style.name());
        }
        o
    }
}
