//! The changes a bell-hanger makes to cure a bell's problems
//! (docs/model.md §12), tried in the hanger's order of preference and each
//! re-simulated: the flight (a heavier, lighter, longer or shorter one),
//! the ball's position, a wooden shaft, a new clapper of another period,
//! and only as a last resort the clapper's pivot (the crown staple), a
//! change hangers rarely make.
//!
//! Each kind of change is tried in small steps out from no change, in a
//! fixed number of steps. The one offered is the smallest that leaves the
//! bell ringing right fully up with none of the diagnosis's problems
//! (going up wrong among them); failing that, the smallest of those that
//! cure the most of the problems it had and bring no new one.

use rayon::prelude::*;

use crate::bell::{Bell, ParamError};
use crate::clapper_parts::{ClapperMass, ClapperParts, Material};
use crate::ringer::{ring_up, Settles};
use crate::stroke::{SimError, Style};
use crate::verdicts::{adjusted, margin, outcome, problems_of, DiagnoseConfig, Problem, StyleOutcome};

/// Where a flight's added mass is put when the clapper's parts are not
/// known, as a multiple of L_c below the pivot: 1.2. A ball strikes near
/// the centre of percussion, L_c below the pivot, and the flight hangs
/// below it (the GSM tenor's plausible parts put the flight's centre at
/// 1.2 L_c). Mass added below L_c lengthens the clapper's period.
pub const FLIGHT_DEPTH_OVER_LC: f64 = 1.2;

/// Steps of the flight's mass, as a fraction of the clapper's mass
/// (1/40 = 2.5 %): up to 40 steps added (the clapper's mass again) and 10
/// taken off (a flight rarely holds more).
const FLIGHT_MASS_STEP: f64 = 1.0 / 40.0;
const FLIGHT_MASS_STEPS_ON: i32 = 40;
const FLIGHT_MASS_STEPS_OFF: i32 = 10;
/// Steps of the flight's length (m): 10 mm, up to 0.5 m longer.
const FLIGHT_LENGTH_STEP: f64 = 0.01;
const FLIGHT_LENGTH_STEPS_ON: i32 = 50;
/// Steps of the ball's position (m): 5 mm, up to 150 mm either way.
const BALL_STEP: f64 = 0.005;
const BALL_STEPS: i32 = 30;
/// Steps of the pivot (m): 5 mm, up to [`DiagnoseConfig::max_dr`].
const PIVOT_STEP: f64 = 0.005;
/// Steps of a new clapper's period (s): 0.02 s, up to
/// [`DiagnoseConfig::max_dtc`].
const PERIOD_STEP: f64 = 0.02;

/// One change a hanger can make.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ClapperChange {
    /// Mass added to (`dm` > 0) or taken off (`dm` < 0) the flight (kg),
    /// `depth` (m) below the clapper pivot: the clapper's parts not known.
    FlightMass {
        /// Mass change (kg).
        dm: f64,
        /// Where it is added (m below the pivot).
        depth: f64,
    },
    /// The flight made `to` long instead of `from` (m), its section kept.
    FlightLength {
        /// Length before (m).
        from: f64,
        /// Length after (m).
        to: f64,
        /// Its diameter (m).
        diameter: f64,
    },
    /// The ball's centre moved from `from` to `to` (m below the pivot),
    /// the shaft lengthened or shortened to meet it, the flight with it.
    BallPosition {
        /// Before (m).
        from: f64,
        /// After (m).
        to: f64,
    },
    /// The shaft remade in ash, its size kept.
    WoodenShaft {
        /// What it was made of.
        from: Material,
    },
    /// A new clapper of period T_c + `dtc` (s), its mass and b kept: the
    /// answer when the clapper is far too short or long for the bell
    /// (`clapper design-clapper --target-period` designs one).
    NewClapper {
        /// Change of T_c (s).
        dtc: f64,
    },
    /// The clapper pivot moved by `dr` along the bell's axis (m; negative
    /// raises it toward the bell's pivot). The last resort.
    Pivot {
        /// Change of r (m).
        dr: f64,
    },
}

impl ClapperChange {
    /// The name used in reports: "flight-mass", "flight-length",
    /// "ball-position", "wooden-shaft" or "pivot".
    pub fn name(&self) -> &'static str {
        match self {
            ClapperChange::FlightMass { .. } => "flight-mass",
            ClapperChange::FlightLength { .. } => "flight-length",
            ClapperChange::BallPosition { .. } => "ball-position",
            ClapperChange::WoodenShaft { .. } => "wooden-shaft",
            ClapperChange::NewClapper { .. } => "new-clapper",
            ClapperChange::Pivot { .. } => "pivot",
        }
    }
}

/// A change found, with what the model predicts after it.
#[derive(Clone, Debug, PartialEq)]
pub struct HangerChange {
    /// The change.
    pub change: ClapperChange,
    /// The bell after it.
    pub bell: Bell,
    /// The clapper's parts after it, when they were known.
    pub parts: Option<ClapperParts>,
    /// The problems left after it (some of those the bell had, or, for a
    /// bell that could not ring right, those that hid).
    pub problems_left: Vec<Problem>,
    /// How it rings right fully up after the change.
    pub predicted: StyleOutcome,
    /// How it goes up after the change.
    pub goes_up: Settles,
    /// Distance on the chart to the nearest edge of ringing right after
    /// the change (chart units), if within the margin search.
    pub margin: Option<f64>,
}

impl HangerChange {
    /// Whether it leaves none of the problems.
    pub fn fixes_all(&self) -> bool {
        self.problems_left.is_empty()
    }

    /// A pivot change: offered only for problems nothing else cures.
    pub fn last_resort(&self) -> bool {
        matches!(self.change, ClapperChange::Pivot { .. })
    }
}

/// The bell with its clapper's mass properties replaced, all else kept
/// (r, φ_max, the hanging).
pub fn with_clapper(bell: &Bell, c: &ClapperMass) -> Result<Bell, ParamError> {
    let b = Bell {
        clapper_mass: c.mass,
        b: c.b,
        clapper_inertia: c.inertia,
        ..*bell
    };
    b.validate()?;
    Ok(b)
}

/// How the bell goes up with the diagnosis's ringer, judged both ways
/// round: a bell hung out of true is rung up as it is and as its mirror
/// image (the ringer's first pull the other way), and goes up right only
/// if both do (wrong if either goes wrong), so that a bell and its mirror
/// image go up alike. An ideal hanging is its own mirror image: rung once.
pub fn goes_up(bell: &Bell, cfg: &DiagnoseConfig) -> Result<Settles, SimError> {
    let once = |b: &Bell| -> Result<Settles, SimError> { Ok(ring_up(b, &cfg.sim, &cfg.ringer, &mut ())?.settles()) };
    let first = once(bell)?;
    if bell.hanging.is_ideal() {
        return Ok(first);
    }
    let h = bell.hanging;
    let mirror = bell.with_hanging(crate::hanging::Hanging {
        pivot_offset: -h.pivot_offset,
        phi_max_skew: -h.phi_max_skew,
        ..h
    });
    let second = once(&mirror)?;
    let worst = [Settles::Wrong, Settles::NoStrike, Settles::Right];
    Ok(*worst.iter().find(|s| first == **s || second == **s).unwrap_or(&first))
}

/// 1, -1, 2, -2, ...: step counts nearest first, up to `up` one way and
/// `down` the other.
fn nearest_first(up: i32, down: i32) -> Vec<i32> {
    (1..=up.max(down))
        .flat_map(|k| [(k <= up).then_some(k), (k <= down).then_some(-k)])
        .flatten()
        .collect()
}

/// A candidate: the change, the bell after it, its parts.
type Candidate = (ClapperChange, Bell, Option<ClapperParts>);

fn flight_mass_candidates(bell: &Bell) -> Vec<Candidate> {
    let m = bell.clapper_mass;
    let depth = FLIGHT_DEPTH_OVER_LC * bell.lc();
    nearest_first(FLIGHT_MASS_STEPS_ON, FLIGHT_MASS_STEPS_OFF)
        .into_iter()
        .filter_map(|k| {
            let dm = k as f64 * FLIGHT_MASS_STEP * m;
            let mass = m + dm;
            let c = ClapperMass {
                mass,
                b: (m * bell.b + dm * depth) / mass,
                inertia: bell.clapper_inertia + dm * depth * depth,
            };
            let b = with_clapper(bell, &c).ok()?;
            Some((ClapperChange::FlightMass { dm, depth }, b, None))
        })
        .collect()
}

fn parts_candidate(bell: &Bell, change: ClapperChange, p: ClapperParts) -> Option<Candidate> {
    let c = p.mass_properties().ok()?;
    Some((change, with_clapper(bell, &c).ok()?, Some(p)))
}

fn flight_length_candidates(bell: &Bell, parts: &ClapperParts) -> Vec<Candidate> {
    let diameter = [parts.flight_diameter, parts.shaft_diameter, parts.ball_diameter / 3.0]
        .into_iter()
        .find(|d| *d > 0.0)
        .unwrap_or(0.03);
    let from = parts.flight_length;
    let off = (from / FLIGHT_LENGTH_STEP).floor() as i32;
    nearest_first(FLIGHT_LENGTH_STEPS_ON, off)
        .into_iter()
        .filter_map(|k| {
            let to = (from + k as f64 * FLIGHT_LENGTH_STEP).max(0.0);
            let p = ClapperParts {
                flight_length: to,
                flight_diameter: diameter,
                ..*parts
            };
            parts_candidate(bell, ClapperChange::FlightLength { from, to, diameter }, p)
        })
        .collect()
}

fn ball_candidates(bell: &Bell, parts: &ClapperParts) -> Vec<Candidate> {
    if parts.ball_diameter <= 0.0 {
        return vec![];
    }
    let from = parts.ball_position;
    nearest_first(BALL_STEPS, BALL_STEPS)
        .into_iter()
        .filter_map(|k| {
            let p = parts.with_ball_moved(k as f64 * BALL_STEP);
            let change = ClapperChange::BallPosition {
                from,
                to: p.ball_position,
            };
            parts_candidate(bell, change, p)
        })
        .collect()
}

fn shaft_candidates(bell: &Bell, parts: &ClapperParts) -> Vec<Candidate> {
    let has_shaft = parts.shaft_length > 0.0 && parts.shaft_diameter > 0.0;
    if !has_shaft || parts.shaft_material == Material::Ash {
        return vec![];
    }
    let change = ClapperChange::WoodenShaft {
        from: parts.shaft_material,
    };
    parts_candidate(bell, change, parts.with_shaft_material(Material::Ash))
        .into_iter()
        .collect()
}

fn pivot_candidates(bell: &Bell, cfg: &DiagnoseConfig, parts: Option<&ClapperParts>) -> Vec<Candidate> {
    let n = (cfg.max_dr / PIVOT_STEP).round() as i32;
    nearest_first(n, n)
        .into_iter()
        .filter_map(|k| {
            let dr = k as f64 * PIVOT_STEP;
            let b = adjusted(bell, 0.0, dr).ok()?;
            Some((ClapperChange::Pivot { dr }, b, parts.copied()))
        })
        .collect()
}

fn period_candidates(bell: &Bell, cfg: &DiagnoseConfig) -> Vec<Candidate> {
    let n = (cfg.max_dtc / PERIOD_STEP).round() as i32;
    nearest_first(n, n)
        .into_iter()
        .filter_map(|k| {
            let dtc = k as f64 * PERIOD_STEP;
            let b = adjusted(bell, dtc, 0.0).ok()?;
            // A new clapper: the old parts no longer describe it.
            Some((ClapperChange::NewClapper { dtc }, b, None))
        })
        .collect()
}

/// What a candidate gives, if it rings right fully up, cures at least one
/// of the problems the bell had and brings none it did not have (a bell
/// that could not ring right had its other problems hidden: for it, any
/// change that makes it ring right counts).
fn evaluate(cand: &Candidate, cfg: &DiagnoseConfig, had: &[Problem]) -> Option<HangerChange> {
    let (change, bell, parts) = cand;
    let o = outcome(bell, cfg, Style::Right).ok()?;
    if !o.sustained {
        return None;
    }
    let mut left = problems_of(bell, &o, cfg);
    let hidden = had.contains(&Problem::CannotRingRight);
    if !hidden && left.iter().any(|p| !had.contains(p)) {
        return None;
    }
    let up = goes_up(bell, cfg).ok()?;
    if up != Settles::Right {
        if !had.contains(&Problem::GoesUpWrong) {
            return None;
        }
        left.push(Problem::GoesUpWrong);
    }
    if cured(had, &left) == 0 {
        return None;
    }
    Some(HangerChange {
        change: *change,
        bell: *bell,
        parts: *parts,
        problems_left: left,
        predicted: o,
        goes_up: up,
        margin: None,
    })
}

/// How many of `had` are not in `left`.
fn cured(had: &[Problem], left: &[Problem]) -> usize {
    had.iter().filter(|p| !left.contains(p)).count()
}

/// From one kind of change: the nearest that cures all; else, for each
/// problem in `targets`, the nearest that cures it (one change may serve
/// several). Candidates are tried in parallel in chunks, stopping at the
/// first chunk with a cure of all; the choice depends only on their order,
/// so the answer is the same for any thread count.
fn cures(cands: &[Candidate], cfg: &DiagnoseConfig, had: &[Problem], targets: &[Problem]) -> Vec<HangerChange> {
    let mut tried: Vec<HangerChange> = vec![];
    for chunk in cands.chunks(16) {
        let found: Vec<Option<HangerChange>> = chunk.par_iter().map(|c| evaluate(c, cfg, had)).collect();
        tried.extend(found.into_iter().flatten());
        if tried.iter().any(|h| h.fixes_all()) {
            break;
        }
    }
    let mut chosen: Vec<HangerChange> = match tried.iter().find(|h| h.fixes_all()) {
        Some(h) => vec![h.clone()],
        None => {
            let mut out: Vec<HangerChange> = vec![];
            for t in targets {
                let first = tried.iter().find(|h| !h.problems_left.contains(t));
                if let Some(h) = first.filter(|h| !out.iter().any(|o| o.change == h.change)) {
                    out.push(h.clone());
                }
            }
            out
        }
    };
    for h in &mut chosen {
        h.margin = margin(&h.bell, cfg, Style::Right).chart_units;
    }
    chosen
}

/// The problems of `had` that none of `found` cures.
fn uncured(had: &[Problem], found: &[HangerChange]) -> Vec<Problem> {
    had.iter()
        .filter(|p| found.iter().all(|h| h.problems_left.contains(p)))
        .copied()
        .collect()
}

/// The changes that cure `had` (the bell's problems), all or some, in the
/// hanger's order: the flight (by its length when the parts are known,
/// else by its mass at [`FLIGHT_DEPTH_OVER_LC`] L_c), the ball's position
/// and a wooden shaft (parts known); a new clapper of another period only
/// for problems those do not cure; the pivot, the last resort, only for
/// problems none of the others cures. Of each kind, the smallest change
/// that cures all, else the smallest that cures each problem. Empty when
/// nothing within the searches cures any.
pub fn hanger_changes(
    bell: &Bell,
    parts: Option<&ClapperParts>,
    cfg: &DiagnoseConfig,
    had: &[Problem],
) -> Vec<HangerChange> {
    if had.is_empty() {
        return vec![];
    }
    let own: Vec<Vec<Candidate>> = match parts {
        Some(p) => vec![
            flight_length_candidates(bell, p),
            ball_candidates(bell, p),
            shaft_candidates(bell, p),
        ],
        None => vec![flight_mass_candidates(bell)],
    };
    let mut found: Vec<HangerChange> = own.iter().flat_map(|c| cures(c, cfg, had, had)).collect();
    for fallback in [period_candidates(bell, cfg), pivot_candidates(bell, cfg, parts)] {
        let left = uncured(had, &found);
        if found.iter().any(|h| h.fixes_all()) || left.is_empty() {
            break;
        }
        found.extend(cures(&fallback, cfg, had, &left));
    }
    found
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nearest_first_alternates_and_stops_at_each_bound() {
        assert_eq!(nearest_first(3, 1), vec![1, -1, 2, 3]);
        assert_eq!(nearest_first(0, 2), vec![-1, -2]);
    }

    /// Mass added at L_c leaves L_c (and so the chart position) unchanged:
    /// L_c' = (I + Δm L_c²)/(m b + Δm L_c) = L_c. Below it lengthens T_c,
    /// above it shortens it.
    #[test]
    fn a_flight_mass_moves_the_period_the_way_its_depth_says() {
        let bell = Bell::gsm_tenor();
        let lc = bell.lc();
        let at = |depth: f64| {
            let dm = 2.0;
            let mass = bell.clapper_mass + dm;
            let c = ClapperMass {
                mass,
                b: (bell.clapper_mass * bell.b + dm * depth) / mass,
                inertia: bell.clapper_inertia + dm * depth * depth,
            };
            with_clapper(&bell, &c).unwrap().tc()
        };
        assert!((at(lc) - bell.tc()).abs() < 1e-12);
        assert!(at(1.2 * lc) > bell.tc() && at(0.8 * lc) < bell.tc());
        let cands = flight_mass_candidates(&bell);
        assert_eq!(cands.len(), 50);
        let ClapperChange::FlightMass { dm, depth } = cands[0].0 else {
            panic!()
        };
        assert!((dm - bell.clapper_mass / 40.0).abs() < 1e-12 && (depth - 1.2 * lc).abs() < 1e-12);
        assert!(cands[0].1.tc() > bell.tc() && cands[1].1.tc() < bell.tc());
    }

    #[test]
    fn a_changed_clapper_keeps_the_hanging() {
        let hanging = crate::hanging::Hanging {
            pivot_offset: 0.003,
            ..Default::default()
        };
        let bell = Bell::lab().with_hanging(hanging);
        for (_, b, _) in
            flight_mass_candidates(&bell)
                .into_iter()
                .chain(pivot_candidates(&bell, &DiagnoseConfig::default(), None))
        {
            assert_eq!(b.hanging, hanging);
        }
    }
}
