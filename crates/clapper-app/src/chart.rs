//! A clapping chart request: the options of `clapper chart` that shape a
//! sweep, as data, for the command line and `POST /api/chart`.

use clapper_core::chart::{ChartSpec, Domain, Styles};
use clapper_core::prelude::*;
use serde::{Deserialize, Serialize};

use crate::stroke_options::contact_words;
use crate::AppError;

pub use clapper_core::bell::CHART_PHI_MAX_DEG as DEFAULT_PHI_MAX_DEG;
pub use clapper_core::chart::{DEFAULT_GRID, DEFAULT_LB_RANGE, DEFAULT_R_RANGE};

fn grid() -> [usize; 2] {
    DEFAULT_GRID
}
fn r_range() -> [f64; 2] {
    DEFAULT_R_RANGE
}
fn lb_range() -> [f64; 2] {
    DEFAULT_LB_RANGE
}
fn phi_max() -> f64 {
    DEFAULT_PHI_MAX_DEG
}

crate::stroke_options::with_stroke_options! {
    /// Everything that shapes a chart. JSON keys as the long options of
    /// `clapper chart`, in snake case; ranges and the grid as pairs:
    ///
    /// ```
    /// use clapper_app::chart::ChartRequest;
    /// let req: ChartRequest = serde_json::from_str(r#"{"grid": [40, 30], "theta0": 90}"#).unwrap();
    /// let spec = req.spec().unwrap();
    /// assert_eq!((spec.nx, spec.ny), (40, 30));
    /// ```
    #[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
    #[serde(deny_unknown_fields)]
    pub struct ChartRequest {
        /// Points along r/L_c and along L_b/L_c.
        #[serde(default = "grid")]
        pub grid: [usize; 2],
        /// Range of r/L_c swept.
        #[serde(default = "r_range", alias = "r-range")]
        pub r_range: [f64; 2],
        /// Range of L_b/L_c swept.
        #[serde(default = "lb_range", alias = "lb-range")]
        pub lb_range: [f64; 2],
        /// Contact angle φ_max of every chart bell (deg).
        #[serde(default = "phi_max", alias = "phi-max")]
        pub phi_max: f64,
        /// Which styles.
        #[serde(default)]
        pub style: Styles,
    }
}

impl ChartRequest {
    /// The chart spec, validated.
    pub fn spec(&self) -> Result<ChartSpec, AppError> {
        let mut construction = ChartConstruction {
            phi_max: self.phi_max.to_radians(),
            ..ChartConstruction::default()
        };
        // The hanging as given, on one bell of the chart: every bell of the
        // chart shares its φ_max, skew, offset and friction.
        let hanging = self.stroke_options().hanging;
        let mut shared = clapper_core::hanging::Hanging::default();
        if !hanging.is_empty() {
            let template = hanging.apply(construction.bell(self.r_range[0], self.lb_range[0])?)?;
            construction.phi_max = template.phi_max;
            shared = template.hanging;
        }
        let spec = ChartSpec {
            domain: Domain {
                x: (self.r_range[0], self.r_range[1]),
                y: (self.lb_range[0], self.lb_range[1]),
            },
            nx: self.grid[0],
            ny: self.grid[1],
            construction,
            config: self.stroke_options().config()?,
            styles: self.style,
            hanging: shared,
        };
        spec.validate()?;
        Ok(spec)
    }
}

/// Short words for a chart's settings, for titles.
pub fn settings_words(spec: &ChartSpec) -> String {
    let h = &spec.hanging;
    let mut extra = String::new();
    if h.pivot_offset != 0.0 {
        extra += &format!(", pivot offset {:.1} mm", h.pivot_offset * 1e3);
    }
    if h.phi_max_skew != 0.0 {
        let (hand, back) = clapper_core::hanging::contact_angles(spec.construction.phi_max, h.phi_max_skew);
        extra += &format!(
            ", phi_max hand/back {:.2}/{:.2} deg",
            hand.to_degrees(),
            back.to_degrees()
        );
    }
    if !h.friction.is_none() {
        extra += ", with friction";
    }
    if !spec.config.strike_amplitude.is_rate() {
        extra += &format!(", A by {}", spec.config.strike_amplitude);
    }
    format!(
        "theta0 = {:.0} deg, R = {}{}, phi_max = {:.0} deg{extra}, {} contact, {} x {}",
        spec.config.theta0.to_degrees(),
        spec.config.restitution,
        spec.config
            .restitution_later
            .map(|r2| format!(", R2 = {r2}"))
            .unwrap_or_default(),
        spec.construction.phi_max.to_degrees(),
        contact_words(&spec.config),
        spec.nx,
        spec.ny
    )
}

/// A chart as JSON (`clapper chart --json`): its settings in words, the
/// axes, the number of strokes that failed, and every point and style in
/// the order of `clapper chart --csv`, keyed by the CSV's column names
/// (angles in deg, φ' in rad/s, odd-struckness in ms), to full precision;
/// `null` where the CSV leaves a cell empty, and `sustained` `null` where
/// the stroke failed to simulate. One line, keys in this order.
pub fn chart_json(chart: &clapper_core::chart::Chart) -> String {
    #[derive(Serialize)]
    struct Point {
        r_over_lc: f64,
        lb_over_lc: f64,
        style: &'static str,
        sustained: Option<bool>,
        strike_theta_deg: Option<f64>,
        strike_phidot_rad_s: Option<f64>,
        liftoff_theta_deg: Option<f64>,
        double_strike_index: Option<f64>,
        // Only a bell off the ideal has it, as only its CSV has the column.
        #[serde(skip_serializing_if = "Option::is_none")]
        odd_struck_ms: Option<Option<f64>>,
    }
    #[derive(Serialize)]
    struct ChartJson {
        settings: String,
        nx: usize,
        ny: usize,
        r_over_lc: Vec<f64>,
        lb_over_lc: Vec<f64>,
        styles: Vec<&'static str>,
        errors: usize,
        points: Vec<Point>,
    }
    let spec = &chart.spec;
    let ideal = spec.hanging.is_ideal();
    let points = chart
        .cells
        .iter()
        .map(|c| {
            let s = c.result.as_ref().ok();
            Point {
                r_over_lc: c.x,
                lb_over_lc: c.y,
                style: c.style.name(),
                sustained: s.map(|s| s.sustained),
                strike_theta_deg: s.and_then(|s| s.strike_theta).map(f64::to_degrees),
                strike_phidot_rad_s: s.and_then(|s| s.strike_phidot),
                liftoff_theta_deg: s.and_then(|s| s.liftoff_theta).map(f64::to_degrees),
                double_strike_index: s.and_then(|s| s.double_strike_index),
                odd_struck_ms: (!ideal).then(|| s.and_then(|s| s.odd_struck).map(|t| t * 1e3)),
            }
        })
        .collect();
    serde_json::to_string(&ChartJson {
        settings: settings_words(spec),
        nx: spec.nx,
        ny: spec.ny,
        r_over_lc: spec.xs(),
        lb_over_lc: spec.ys(),
        styles: spec.styles.list().iter().map(|s| s.name()).collect(),
        errors: chart.errors(),
        points,
    })
    .unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_the_papers_chart() {
        let spec = ChartRequest::default().spec().unwrap();
        assert_eq!(spec, ChartSpec::default());
    }

    #[test]
    fn bad_requests_name_the_field() {
        let r = ChartRequest {
            grid: [1000, 1000],
            lb_range: [-1.0, 2.0],
            ..ChartRequest::default()
        };
        assert!(r.spec().unwrap_err().to_string().contains("lb_over_lc"));
        let e = serde_json::from_str::<ChartRequest>(r#"{"gird": [3, 3]}"#).unwrap_err();
        assert!(e.to_string().contains("gird"));
    }
}
