//! What a diagnosis reports, as `clapper diagnose --json` prints it: the
//! types only (filled in by the sibling `build`, written out by `text`).

use serde::Serialize;

#[derive(Serialize, Clone, Copy)]
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
    /// The backstroke of steady ringing in this style, when the style is
    /// sustained and the bell's hanging is not ideal (an ideal bell's
    /// backstroke is its handstroke mirrored). The figures above are the
    /// handstroke's.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub backstroke: Option<StrokeReport>,
}

#[derive(Serialize, Clone, Copy)]
/// How one stroke strikes: a backstroke's angles and rates in its own sign
/// (it starts from -theta0, so a right backstroke strikes at theta > 0).
pub struct StrokeReport {
    /// Bell angle at the first strike (deg).
    pub first_strike_theta_deg: Option<f64>,
    /// Clapper rate just before the first strike (rad/s).
    pub strike_phidot_rad_s: Option<f64>,
    /// Bell angle at lift-off (deg).
    pub liftoff_theta_deg: Option<f64>,
    /// D of (33) at R = 0.05, 0.1, 0.2.
    pub double_strike_index: DByR,
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
    /// Bell angle at the first strike (deg), handstroke of the usual style.
    pub first_strike_theta_deg: Option<f64>,
    /// Clapper rate just before the first strike (rad/s), handstroke.
    pub strike_phidot_rad_s: Option<f64>,
    /// |phi'| L_c: the clapper's speed at its centre of percussion.
    pub(crate) striking_speed_m_s: Option<f64>,
    /// 1/2 I_c phi'^2, only when the clapper's mass and b were given.
    pub(crate) strike_energy_j: Option<f64>,
    /// Bell angle at lift-off (deg), handstroke.
    pub liftoff_theta_deg: Option<f64>,
    /// D of (33) at R = 0.05, 0.1, 0.2, handstroke.
    pub double_strike_index: DByR,
    /// The usual style's backstroke (its angles and rates in its own sign),
    /// for a bell whose hanging is not ideal: the problems are judged from
    /// the worse of the two strokes, so a bell and its mirror image (which
    /// swap handstroke and backstroke) have the same problems.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub backstroke: Option<StrokeReport>,
    /// The backstroke's striking speed (m/s), as `striking_speed_m_s`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) backstroke_striking_speed_m_s: Option<f64>,
    /// The backstroke's strike energy (J), as `strike_energy_j`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) backstroke_strike_energy_j: Option<f64>,
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

/// How odd-struck a bell is and what evens it (docs/model.md §10.3), in
/// the style it rings steadily (right if it can); for a bell that sustains
/// neither style, not defined, with the reason and no advice.
#[derive(Serialize, Clone, Debug, PartialEq)]
pub struct OddStruckReport {
    /// The style judged: "right" or "wrong"; null when neither is sustained.
    pub style: Option<&'static str>,
    /// Handstroke minus backstroke time from bottom dead centre to the
    /// strike (ms): positive, the handstroke strikes late. Null when not
    /// defined (`odd_struck_undefined` says why).
    pub odd_struck_ms: Option<f64>,
    /// Why `odd_struck_ms` is null, when it is: it compares two strokes of
    /// one style, and the bell sustains neither.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub odd_struck_undefined: Option<String>,
    /// The aim (ms): odd-struckness within ± this.
    pub tolerance_ms: f64,
    /// The ball's centre below the clapper pivot used (m).
    pub ball_below_pivot_m: f64,
    /// Change per mm the ball moves toward the back side, pivot fixed
    /// (ms/mm); null without a defined odd-struckness, or where half a
    /// millimetre either way loses the style.
    pub ms_per_mm_at_ball: Option<f64>,
    /// The ball move toward the back side that evens it (mm), if found.
    pub ball_move_mm: Option<f64>,
    /// Odd-struckness after that move, simulated (ms).
    pub after_ball_move_ms: Option<f64>,
    /// Change per mm the clapper pivot moves toward the back side (ms/mm),
    /// null as `ms_per_mm_at_ball`.
    pub ms_per_mm_at_pivot: Option<f64>,
    /// The pivot move toward the back side that evens it (mm), if found.
    pub pivot_move_mm: Option<f64>,
    /// Odd-struckness after that move, simulated (ms).
    pub after_pivot_move_ms: Option<f64>,
    /// In words.
    pub words: String,
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
