//! A sweep: one chart, or a chart for each combination of several θ0, R
//! and φ_max values (extra axes), as one flat list of strokes that can be
//! cut into shards and computed in any pieces, anywhere, and joined again.

use std::ops::Range;

use clapper_core::chart::{sweep_cells_counting, ChartCell, ChartSpec};
use serde::{Deserialize, Serialize};

use crate::chart::ChartRequest;
use crate::AppError;

/// The most strokes one sweep may hold (all shards together): ten
/// thousand million, days of work on a large cluster, far more than any
/// chart needs, small enough that flat indices fit anywhere.
pub const MAX_SWEEP_STROKES: usize = 10_000_000_000;

/// θ0 (deg), R and φ_max (deg) of one chart of a sweep, as the CSV writes them.
pub use clapper_io::chart_csv::Axes;

/// The charts of a sweep, in order: θ0 outermost, then R, then φ_max.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepPlan {
    /// Each chart's axes and spec.
    pub charts: Vec<(Axes, ChartSpec)>,
    /// Whether there is more than one value on some extra axis (then the
    /// CSV carries the axes on every row).
    pub has_axes: bool,
}

impl SweepPlan {
    /// The columns of its CSV: the axes when there are several charts'
    /// worth, the odd-struck column when the bell is not ideal (every chart
    /// of a sweep shares the bell's hanging).
    pub fn columns(&self) -> clapper_io::Columns {
        clapper_io::Columns {
            axes: self.has_axes,
            odd_struck: self.charts.iter().any(|(_, spec)| !spec.hanging.is_ideal()),
        }
    }

    /// A chart per combination of `theta0s` (deg), `restitutions` and
    /// `phi_maxes` (deg), each otherwise as `base`.
    pub fn new(
        base: &ChartRequest,
        theta0s: &[f64],
        restitutions: &[f64],
        phi_maxes: &[f64],
    ) -> Result<Self, AppError> {
        if theta0s.is_empty() || restitutions.is_empty() || phi_maxes.is_empty() {
            return Err(AppError::Request(
                "each of theta0, restitution and phi_max needs a value".into(),
            ));
        }
        let mut charts = vec![];
        for &theta0 in theta0s {
            for &restitution in restitutions {
                for &phi_max in phi_maxes {
                    let req = ChartRequest {
                        theta0,
                        restitution: Some(restitution),
                        phi_max,
                        ..base.clone()
                    };
                    charts.push(([theta0, restitution, phi_max], req.spec()?));
                }
            }
        }
        let plan = Self {
            has_axes: charts.len() > 1,
            charts,
        };
        if plan
            .per_chart()
            .checked_mul(plan.charts.len())
            .is_none_or(|n| n > MAX_SWEEP_STROKES)
        {
            return Err(AppError::Request(format!(
                "{} charts of {} strokes is more than a sweep may hold ({MAX_SWEEP_STROKES} strokes)",
                plan.charts.len(),
                plan.per_chart()
            )));
        }
        Ok(plan)
    }

    /// Strokes per chart.
    pub fn per_chart(&self) -> usize {
        self.charts[0].1.cell_count()
    }

    /// Strokes in the whole sweep.
    pub fn total(&self) -> usize {
        self.per_chart() * self.charts.len()
    }

    /// The strokes of shard `i` of `n` (from 0): contiguous and as equal as
    /// can be, together exactly the whole sweep.
    pub fn shard(&self, i: usize, n: usize) -> Result<Range<usize>, AppError> {
        if n == 0 || i >= n {
            return Err(AppError::Request(format!(
                "shard {} of {n} does not exist: shards are numbered 1 to N",
                i + 1
            )));
        }
        let t = self.total() as u128;
        let at = |k: usize| (t * k as u128 / n as u128) as usize;
        Ok(at(i)..at(i + 1))
    }

    /// What identifies the sweep: equal for the same charts (every number
    /// at full precision), different otherwise. Shards and resumed runs
    /// check it before their parts are joined. It is the charts' settings
    /// serialized (JSON, shortest round-trip numbers), prefixed `v2:`: a
    /// setting added later with a neutral default is left out of it while
    /// at that default (as `restitution_later` is), so keys stay the same
    /// across versions for the same work.
    pub fn key(&self) -> String {
        let charts = serde_json::to_string(&self.charts).expect("chart settings serialize");
        format!("v2:{charts}")
    }

    /// Compute the strokes with flat indices in `range`: each with the
    /// index of its chart. `progress(done)` counts strokes as they finish.
    pub fn cells(
        &self,
        range: Range<usize>,
        progress: &(dyn Fn(u64) + Sync),
    ) -> Result<Vec<(usize, ChartCell)>, AppError> {
        self.cells_counting(range, progress, &std::sync::atomic::AtomicU64::new(0))
    }

    /// [`cells`](Self::cells), counting the strokes simulated in `rung`
    /// (a bell off the ideal rings its backstroke too:
    /// `clapper_core::chart::sweep_cells_counting`).
    pub fn cells_counting(
        &self,
        range: Range<usize>,
        progress: &(dyn Fn(u64) + Sync),
        rung: &std::sync::atomic::AtomicU64,
    ) -> Result<Vec<(usize, ChartCell)>, AppError> {
        let per = self.per_chart();
        let end = range.end.min(self.total());
        let mut k = range.start.min(end);
        let mut out = Vec::with_capacity(end - k);
        let base = std::sync::atomic::AtomicU64::new(0);
        while k < end {
            let chart = k / per;
            let stop = end.min((chart + 1) * per);
            let before = base.load(std::sync::atomic::Ordering::Relaxed);
            let cells = sweep_cells_counting(
                &self.charts[chart].1,
                k - chart * per..stop - chart * per,
                &|d| progress(before + d),
                &|| false,
                rung,
            )?
            .unwrap_or_default();
            base.fetch_add(cells.len() as u64, std::sync::atomic::Ordering::Relaxed);
            out.extend(cells.into_iter().map(|c| (chart, c)));
            k = stop;
        }
        Ok(out)
    }
}

/// Version of the journal and shard files. 2: the sweep key is the
/// serialized settings (`SweepPlan::key`). Shards of format 1 (a `Debug`
/// string as key) still merge: their key cannot be rebuilt, so the shards
/// are checked against each other and the sweep is rebuilt from their
/// options.
pub const FORMAT: u32 = 2;

/// The oldest shard format `clapper merge` still reads.
pub const OLDEST_FORMAT: u32 = 1;

/// What a sweep file is part of.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SweepMeta {
    /// Always [`FORMAT`].
    pub format: u32,
    /// The chart options (first value of each extra axis).
    pub request: ChartRequest,
    /// Every θ0 (deg).
    pub theta0: Vec<f64>,
    /// Every R.
    pub restitution: Vec<f64>,
    /// Every φ_max (deg).
    pub phi_max: Vec<f64>,
    /// `SweepPlan::key` of the sweep.
    pub key: String,
    /// Strokes in the whole sweep.
    pub total: usize,
    /// This part: shard index from 0, and the number of shards.
    pub shard: [usize; 2],
    /// This part's strokes (flat indices).
    pub range: [usize; 2],
}

impl SweepMeta {
    /// The sweep this meta describes, rebuilt and checked against its key.
    pub fn plan(&self) -> Result<SweepPlan, AppError> {
        let plan = SweepPlan::new(&self.request, &self.theta0, &self.restitution, &self.phi_max)?;
        match self.format {
            FORMAT if plan.key() != self.key => Err(AppError::Request(
                "the shard's options do not rebuild its sweep (its settings changed since it was written)".into(),
            )),
            FORMAT | OLDEST_FORMAT => Ok(plan),
            f => Err(AppError::Request(format!(
                "shard format {f} is not one this clapper reads ({OLDEST_FORMAT} to {FORMAT})"
            ))),
        }
    }
}

/// A finished shard: its description and the text of its CSV.
pub struct Shard<'a> {
    /// What it is part of.
    pub meta: SweepMeta,
    /// Its CSV (a header and one row per stroke).
    pub csv: &'a str,
    /// Its name, for messages.
    pub name: String,
}

/// Join the shards of one sweep, given in any order, into the CSV of the
/// whole sweep (the same bytes as one run) and its plan. Every way the
/// shards can fail to be one sweep is a one-line error naming the shard.
pub fn join_shards(mut parts: Vec<Shard<'_>>) -> Result<(SweepPlan, String), AppError> {
    let bad = |m: String| Err(AppError::Request(m));
    let Some(first) = parts.first().map(|p| p.meta.clone()) else {
        return bad("no shards to join".into());
    };
    for p in &parts {
        if !(OLDEST_FORMAT..=FORMAT).contains(&p.meta.format) {
            return bad(format!(
                "{} has format {}, this clapper reads {OLDEST_FORMAT} to {FORMAT}",
                p.name, p.meta.format
            ));
        }
        let m = &p.meta;
        if m.key != first.key || m.shard[1] != first.shard[1] || m.format != first.format {
            return bad(format!(
                "{} is a shard of a different sweep than {} (other options or shard count)",
                p.name, parts[0].name
            ));
        }
    }
    parts.sort_by_key(|p| p.meta.shard[0]);
    let n = first.shard[1];
    let have: Vec<usize> = parts.iter().map(|p| p.meta.shard[0]).collect();
    let missing: Vec<String> = (0..n)
        .filter(|i| !have.contains(i))
        .map(|i| (i + 1).to_string())
        .collect();
    if !missing.is_empty() {
        return bad(format!("shard(s) {} of {n} missing", missing.join(", ")));
    }
    if let Some(w) = have.windows(2).find(|w| w[0] == w[1]) {
        return bad(format!("shard {} of {n} given twice", w[0] + 1));
    }
    let plan = first.plan()?;
    let mut at = 0;
    let mut header: Option<&str> = None;
    let mut out = String::new();
    for p in &parts {
        let m = &p.meta;
        if m.range[0] != at {
            return bad(format!("{} starts at stroke {}, expected {at}", p.name, m.range[0]));
        }
        let (head, rows) = p.csv.split_once('\n').unwrap_or((p.csv, ""));
        match header {
            None => {
                header = Some(head);
                out.push_str(head);
                out.push('\n');
            }
            Some(h) if h != head => return bad(format!("{} has another header than the first shard", p.name)),
            _ => {}
        }
        let count = rows.lines().count();
        if count != m.range[1] - m.range[0] {
            return bad(format!(
                "{} has {count} rows, its shard has {} strokes: unfinished or damaged",
                p.name,
                m.range[1] - m.range[0]
            ));
        }
        out.push_str(rows);
        at = m.range[1];
    }
    if at != plan.total() {
        return bad(format!("the shards end at stroke {at} of {}", plan.total()));
    }
    Ok((plan, out))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plan() -> SweepPlan {
        let base = ChartRequest {
            grid: [3, 2],
            ..ChartRequest::default()
        };
        SweepPlan::new(&base, &[150.0, 171.0], &[0.2], &[24.0, 26.0]).unwrap()
    }

    #[test]
    fn shards_cover_the_sweep_once_and_join_to_it() {
        let p = plan();
        assert_eq!(p.total(), 4 * 12);
        let whole = p.cells(0..p.total(), &|_| {}).unwrap();
        for n in [1, 2, 5, 7, 48, 50] {
            let mut joined = vec![];
            for i in 0..n {
                joined.extend(p.cells(p.shard(i, n).unwrap(), &|_| {}).unwrap());
            }
            assert_eq!(joined, whole, "{n} shards");
        }
        assert!(p.shard(3, 3).is_err());
        // Charts run theta0-major, then R, then phi_max.
        assert_eq!(p.charts[1].0, [150.0, 0.2, 26.0]);
        assert_eq!(p.charts[2].0, [171.0, 0.2, 24.0]);
    }

    #[test]
    fn keys_tell_sweeps_apart() {
        let p = plan();
        let mut q = plan();
        assert_eq!(p.key(), q.key());
        q.charts[0].1.config.restitution = 0.2000000001;
        assert_ne!(p.key(), q.key());
        // R2 = R unset leaves the key as it was; set, it is another sweep.
        let mut r = plan();
        r.charts[0].1.config.restitution_later = Some(0.2);
        assert_ne!(p.key(), r.key());
        assert!(!p.key().contains("restitution_later"));
    }
}
