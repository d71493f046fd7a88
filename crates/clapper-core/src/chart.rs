//! Clapping charts: a sweep over the plane of (r/L_c, L_b/L_c) with the
//! paper's construction of a bell at each point (docs/model.md §5), both styles, in
//! parallel. Results are collected by index, so they are the same whatever
//! the number of threads.

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

use rayon::prelude::*;

use crate::bell::{ChartConstruction, ParamError};
use crate::hanging::Hanging;
use crate::ringing::{backstroke, first_stroke};
use crate::stroke::{SimConfig, SimError, Stroke, Style};

/// The most points one chart may have: 2000 x 2000 (a chart of both styles
/// then holds 8 million stroke summaries, about 0.6 GB).
pub const MAX_POINTS: usize = 4_000_000;

/// A rectangle of the chart plane.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Domain {
    /// r/L_c from, to.
    pub x: (f64, f64),
    /// L_b/L_c from, to (> 0).
    pub y: (f64, f64),
}

pub use crate::bell::{DEFAULT_LB_RANGE, DEFAULT_R_RANGE};
/// The paper's grid: 20 x 20.
pub const DEFAULT_GRID: [usize; 2] = [20, 20];

impl Default for Domain {
    /// [`DEFAULT_R_RANGE`] by [`DEFAULT_LB_RANGE`].
    fn default() -> Self {
        Self {
            x: (DEFAULT_R_RANGE[0], DEFAULT_R_RANGE[1]),
            y: (DEFAULT_LB_RANGE[0], DEFAULT_LB_RANGE[1]),
        }
    }
}

/// Which styles a chart computes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
pub enum Styles {
    /// Ringing right only.
    Right,
    /// Ringing wrong only.
    Wrong,
    /// Both. The default.
    #[default]
    Both,
}

impl Styles {
    /// The styles, right first.
    pub fn list(self) -> &'static [Style] {
        match self {
            Styles::Right => &[Style::Right],
            Styles::Wrong => &[Style::Wrong],
            Styles::Both => &[Style::Right, Style::Wrong],
        }
    }
}

/// Everything that shapes a chart.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ChartSpec {
    /// The rectangle swept.
    pub domain: Domain,
    /// Points along r/L_c (≥ 1).
    pub nx: usize,
    /// Points along L_b/L_c (≥ 1).
    pub ny: usize,
    /// How a bell is built at each point (carries φ_max).
    pub construction: ChartConstruction,
    /// θ0, R, contact model, tolerances.
    pub config: SimConfig,
    /// Which styles.
    pub styles: Styles,
    /// How every chart bell departs from the ideal: pivot offset, unequal
    /// contact angles, friction (docs/model.md §10). Default: ideal.
    #[cfg_attr(feature = "serde", serde(default, skip_serializing_if = "Hanging::is_ideal"))]
    pub hanging: Hanging,
}

impl Default for ChartSpec {
    /// The paper's 20 x 20 chart of both styles at its defaults.
    fn default() -> Self {
        Self {
            domain: Domain::default(),
            nx: DEFAULT_GRID[0],
            ny: DEFAULT_GRID[1],
            construction: ChartConstruction::default(),
            config: SimConfig::default(),
            styles: Styles::Both,
            hanging: Hanging::default(),
        }
    }
}

/// Evenly spaced points from `a` to `b` inclusive; one point is the middle.
pub fn axis(a: f64, b: f64, n: usize) -> Vec<f64> {
    match n {
        0 => vec![],
        1 => vec![0.5 * (a + b)],
        _ => (0..n).map(|i| a + (b - a) * i as f64 / (n - 1) as f64).collect(),
    }
}

impl ChartSpec {
    /// Check the domain, the grid size and the configuration.
    pub fn validate(&self) -> Result<(), ParamError> {
        let d = &self.domain;
        for (field, v) in [("r_over_lc", d.x.0), ("r_over_lc", d.x.1)] {
            if !v.is_finite() {
                return Err(ParamError {
                    field,
                    value: v,
                    allowed: "a finite number",
                });
            }
        }
        for v in [d.y.0, d.y.1] {
            if !(v.is_finite() && v > 0.0) {
                return Err(ParamError {
                    field: "lb_over_lc",
                    value: v,
                    allowed: "a finite number > 0",
                });
            }
        }
        // A range given high to low is named by its first end.
        for (field, (lo, hi)) in [("r_over_lc range, from", d.x), ("lb_over_lc range, from", d.y)] {
            if lo > hi {
                return Err(ParamError {
                    field,
                    value: lo,
                    allowed: "the low end first (e.g. -0.3,0.7)",
                });
            }
        }
        let n = self.nx.saturating_mul(self.ny);
        if self.nx == 0 || self.ny == 0 || n > MAX_POINTS {
            return Err(ParamError {
                field: "grid",
                value: n as f64,
                allowed: "at least 1 x 1 and at most 4,000,000 points",
            });
        }
        self.config.validate()?;
        // The construction at the domain's corners catches a bad phi_max or T_b.
        self.construction
            .bell(d.x.0, d.y.0)?
            .with_hanging(self.hanging)
            .validate()?;
        Ok(())
    }

    /// r/L_c of the grid columns.
    pub fn xs(&self) -> Vec<f64> {
        axis(self.domain.x.0, self.domain.x.1, self.nx)
    }

    /// L_b/L_c of the grid rows.
    pub fn ys(&self) -> Vec<f64> {
        axis(self.domain.y.0, self.domain.y.1, self.ny)
    }

    /// Strokes in the whole chart: points times styles.
    pub fn cell_count(&self) -> usize {
        self.nx.saturating_mul(self.ny).saturating_mul(self.styles.list().len())
    }
}

/// What a chart keeps of one stroke.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StrokeSummary {
    /// Whether the style is sustained.
    pub sustained: bool,
    /// θ at the first strike (rad).
    pub strike_theta: Option<f64>,
    /// φ' just before the first strike (rad/s).
    pub strike_phidot: Option<f64>,
    /// Lift-off angle (rad).
    pub liftoff_theta: Option<f64>,
    /// D of (33).
    pub double_strike_index: Option<f64>,
    /// dt12 (s).
    pub second_strike_delay: Option<f64>,
    /// A.
    pub amplitude_ratio: Option<f64>,
    /// Odd-struckness (s): handstroke minus backstroke time from bottom dead
    /// centre to the strike (docs/model.md §10.3); 0 for a symmetric bell.
    pub odd_struck: Option<f64>,
}

impl StrokeSummary {
    /// The summary of a handstroke and the backstroke after it, for an
    /// asymmetric bell: sustained only if both are.
    pub fn of_pair(hand: &Stroke, back: &Stroke) -> Self {
        Self {
            sustained: hand.sustained() && back.sustained(),
            // Only where the style is sustained: a right handstroke beside
            // a wrong backstroke is no odd-struckness (docs/model.md §10.3).
            odd_struck: crate::ringing::odd_struck_of(hand, back).ok(),
            ..Self::from(hand)
        }
    }
}

impl From<&Stroke> for StrokeSummary {
    /// The summary of one stroke of a symmetric bell: its backstroke is its
    /// mirror image (bit for bit), so the odd-struckness is 0 if it strikes.
    fn from(s: &Stroke) -> Self {
        Self {
            odd_struck: s.bdc_to_strike().filter(|_| s.sustained()).map(|_| 0.0),
            sustained: s.sustained(),
            strike_theta: s.strike_angle(),
            strike_phidot: s.strike_velocity(),
            liftoff_theta: s.liftoff_angle(),
            double_strike_index: s.double_strike_index(),
            second_strike_delay: s.second_strike_delay(),
            amplitude_ratio: s.amplitude_ratio(),
        }
    }
}

/// One point and style of a chart.
#[derive(Clone, Debug, PartialEq)]
pub struct ChartCell {
    /// r/L_c.
    pub x: f64,
    /// L_b/L_c.
    pub y: f64,
    /// The style simulated.
    pub style: Style,
    /// The stroke's summary, or why it could not be simulated.
    pub result: Result<StrokeSummary, SimError>,
}

impl ChartCell {
    /// The summary if the stroke sustained its style.
    pub fn sustained(&self) -> Option<&StrokeSummary> {
        self.result.as_ref().ok().filter(|s| s.sustained)
    }
}

/// A computed chart.
#[derive(Clone, Debug, PartialEq)]
pub struct Chart {
    /// What was computed.
    pub spec: ChartSpec,
    /// Cells in row-major order: L_b/L_c (rows, ascending), then r/L_c
    /// (ascending), then style (right before wrong).
    pub cells: Vec<ChartCell>,
}

impl Chart {
    /// The cell at column `i`, row `j`, for `style`, if the chart has that style.
    pub fn cell(&self, i: usize, j: usize, style: Style) -> Option<&ChartCell> {
        let styles = self.spec.styles.list();
        let k = styles.iter().position(|s| *s == style)?;
        self.cells.get((j * self.spec.nx + i) * styles.len() + k)
    }

    /// How many cells failed with an error.
    pub fn errors(&self) -> usize {
        self.cells.iter().filter(|c| c.result.is_err()).count()
    }
}

/// Sweep the chart. `progress(done)` is called from worker threads as
/// strokes complete (`done` of `total = nx * ny * styles`), for a progress
/// bar; it must be cheap.
///
/// ```
/// use clapper_core::chart::{sweep, ChartSpec};
/// let spec = ChartSpec { nx: 3, ny: 3, ..ChartSpec::default() };
/// let chart = sweep(&spec, &|_done| {}).unwrap();
/// assert_eq!(chart.cells.len(), 3 * 3 * 2);
/// ```
pub fn sweep(spec: &ChartSpec, progress: &(dyn Fn(u64) + Sync)) -> Result<Chart, ParamError> {
    let cells = sweep_cells(spec, 0..spec.cell_count(), progress)?;
    Ok(Chart { spec: *spec, cells })
}

/// Sweep part of a chart: the cells whose flat indices (in the order of
/// [`Chart::cells`]) lie in `range`. A cell depends only on its own point,
/// so the parts of a chart, swept separately (a row block at a time for a
/// live view, or as shards on different machines), join to exactly the
/// cells of one [`sweep`]. `range` is clipped to the chart.
///
/// ```
/// use clapper_core::chart::{sweep, sweep_cells, ChartSpec};
/// let spec = ChartSpec { nx: 3, ny: 2, ..ChartSpec::default() };
/// let mut joined = sweep_cells(&spec, 0..5, &|_| {}).unwrap();
/// joined.extend(sweep_cells(&spec, 5..12, &|_| {}).unwrap());
/// assert_eq!(joined, sweep(&spec, &|_| {}).unwrap().cells);
/// ```
pub fn sweep_cells(
    spec: &ChartSpec,
    range: std::ops::Range<usize>,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Vec<ChartCell>, ParamError> {
    Ok(sweep_cells_until(spec, range, progress, &|| false)?.unwrap_or_default())
}

/// [`sweep_cells`] that can be stopped: `stop()` is asked before each
/// stroke starts, from whichever thread runs it; once it answers true no
/// further stroke starts and the answer is `Ok(None)`. A stroke is the
/// unit of work (17 us for the paper's chart with the defaults; at most
/// its integrator's step budget), so a caller that stops on a deadline or
/// a departed client is obeyed within one stroke per thread.
pub fn sweep_cells_until(
    spec: &ChartSpec,
    range: std::ops::Range<usize>,
    progress: &(dyn Fn(u64) + Sync),
    stop: &(dyn Fn() -> bool + Sync),
) -> Result<Option<Vec<ChartCell>>, ParamError> {
    sweep_cells_counting(spec, range, progress, stop, &AtomicU64::new(0))
}

/// [`sweep_cells_until`] that also counts the strokes it simulates in
/// `rung`: one a cell for a bell that is its own mirror image (ideal, or
/// with friction only), two where a bell with a pivot offset or unequal
/// contact angles rings its backstroke too (after a handstroke that keeps
/// its style). A chart's cost goes with them, not with its cells.
///
/// ```
/// use std::sync::atomic::{AtomicU64, Ordering};
/// use clapper_core::chart::{sweep_cells_counting, ChartSpec};
/// let spec = ChartSpec { nx: 2, ny: 2, ..ChartSpec::default() };
/// let rung = AtomicU64::new(0);
/// let cells = sweep_cells_counting(&spec, 0..8, &|_| {}, &|| false, &rung).unwrap().unwrap();
/// assert_eq!(rung.load(Ordering::Relaxed), cells.len() as u64);
/// ```
pub fn sweep_cells_counting(
    spec: &ChartSpec,
    range: std::ops::Range<usize>,
    progress: &(dyn Fn(u64) + Sync),
    stop: &(dyn Fn() -> bool + Sync),
    rung: &AtomicU64,
) -> Result<Option<Vec<ChartCell>>, ParamError> {
    spec.validate()?;
    let xs = spec.xs();
    let ys = spec.ys();
    let styles = spec.styles.list();
    let end = range.end.min(spec.cell_count());
    let start = range.start.min(end);
    let done = AtomicU64::new(0);
    let stopped = AtomicBool::new(false);
    Ok((start..end)
        .into_par_iter()
        .map(|k| {
            if stopped.load(Ordering::Relaxed) || stop() {
                stopped.store(true, Ordering::Relaxed);
                return None;
            }
            let style = styles[k % styles.len()];
            let p = k / styles.len();
            let (x, y) = (xs[p % spec.nx], ys[p / spec.nx]);
            let result = spec
                .construction
                .bell(x, y)
                .map(|bell| bell.with_hanging(spec.hanging))
                .map_err(SimError::from)
                .and_then(|bell| {
                    rung.fetch_add(1, Ordering::Relaxed);
                    let hand = first_stroke(&bell, &spec.config, style)?;
                    // A bell that is its own mirror image (friction and
                    // damping keep the mirror) has its backstroke by
                    // symmetry. Else the backstroke too, where it can
                    // change the answer (after a handstroke that keeps its
                    // style; else the style is not sustained and has no
                    // odd-struckness, as `of_pair` would say).
                    if spec.hanging.is_mirror_symmetric() || !hand.sustained() {
                        Ok(StrokeSummary::from(&hand))
                    } else {
                        rung.fetch_add(1, Ordering::Relaxed);
                        backstroke(&bell, &spec.config, &hand).map(|back| StrokeSummary::of_pair(&hand, &back))
                    }
                });
            progress(done.fetch_add(1, Ordering::Relaxed) + 1);
            Some(ChartCell { x, y, style, result })
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn axis_includes_both_ends() {
        assert_eq!(axis(0.0, 1.0, 3), vec![0.0, 0.5, 1.0]);
        assert_eq!(axis(0.0, 1.0, 1), vec![0.5]);
    }

    #[test]
    fn bad_specs_are_refused() {
        let ok = ChartSpec::default();
        assert!(ok.validate().is_ok());
        for bad in [
            ChartSpec { nx: 0, ..ok },
            ChartSpec {
                nx: 3000,
                ny: 3000,
                ..ok
            },
            ChartSpec {
                domain: Domain {
                    x: (0.0, 1.0),
                    y: (-1.0, 2.0),
                },
                ..ok
            },
            ChartSpec {
                domain: Domain {
                    x: (1.0, 0.0),
                    y: (1.0, 2.0),
                },
                ..ok
            },
        ] {
            assert!(sweep(&bad, &|_| {}).is_err(), "{bad:?}");
        }
    }

    #[test]
    fn cells_are_indexed_as_documented() {
        let spec = ChartSpec {
            nx: 4,
            ny: 3,
            ..ChartSpec::default()
        };
        let c = sweep(&spec, &|_| {}).unwrap();
        let xs = spec.xs();
        let ys = spec.ys();
        let cell = c.cell(2, 1, Style::Wrong).unwrap();
        assert_eq!((cell.x, cell.y, cell.style), (xs[2], ys[1], Style::Wrong));
        assert_eq!(c.errors(), 0);
    }
}
