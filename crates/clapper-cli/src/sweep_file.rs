//! Sweeps written to CSV so that no work is lost: rows are appended a
//! block at a time to `OUT.partial`, and after each block a small journal
//! (`OUT.partial.json`) records how far the run got and how many bytes are
//! good. A run killed at any moment is resumed by running the same command
//! again: the partial file is cut back to the journal's length (dropping a
//! half-written block) and the sweep goes on from there, so nothing is lost
//! or repeated. When done, the partial file is renamed into place. A shard
//! also leaves `OUT.shard.json`, which `clapper merge` reads.

use std::fs::{File, OpenOptions};
use std::io::Write;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{bail, Context, Result};
use clapper_app::sweep::{SweepMeta, SweepPlan};
use clapper_core::chart::ChartCell;
use serde::{Deserialize, Serialize};

#[derive(Serialize, Deserialize)]
struct Journal {
    meta: SweepMeta,
    /// Strokes done, as a flat index: the next block starts here.
    done: usize,
    /// Bytes of the partial file that hold complete rows.
    bytes: u64,
    /// FNV-1a (64 bits) of those bytes: a journal edited or damaged, or a
    /// partial file changed, is caught before the run goes on. Missing in
    /// the journals of clapper before it.
    #[serde(default)]
    checksum: Option<u64>,
}

/// FNV-1a, 64 bits, continued from `h` over `bytes`.
fn fnv1a(mut h: u64, bytes: &[u8]) -> u64 {
    for &b in bytes {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

/// FNV-1a's starting value.
const FNV_START: u64 = 0xcbf2_9ce4_8422_2325;

fn with_suffix(path: &Path, suffix: &str) -> PathBuf {
    let mut s = path.as_os_str().to_owned();
    s.push(suffix);
    PathBuf::from(s)
}

/// The shard description beside a shard's CSV.
pub fn shard_meta_path(csv: &Path) -> PathBuf {
    with_suffix(csv, ".shard.json")
}

fn write_json_atomically<T: Serialize>(path: &Path, v: &T) -> Result<()> {
    crate::files::write_atomically(path, |tmp| {
        let mut f = File::create(tmp).with_context(|| format!("cannot create {}", tmp.display()))?;
        f.write_all(serde_json::to_string(v)?.as_bytes())
            .and_then(|()| f.sync_all())
            .with_context(|| format!("cannot write {}", tmp.display()))?;
        Ok(())
    })
}

/// Hold an exclusive lock on `path` (created if missing) for as long as
/// the returned file lives; the system drops it when the process dies,
/// so a killed run leaves no stale lock.
fn lock(path: &Path) -> Result<File> {
    let f = OpenOptions::new()
        .create(true)
        .truncate(false)
        .write(true)
        .open(path)
        .with_context(|| format!("cannot create {}", path.display()))?;
    #[cfg(unix)]
    {
        use std::os::unix::io::AsRawFd;
        // SAFETY: flock on a descriptor this function owns; no memory is shared.
        if unsafe { libc::flock(f.as_raw_fd(), libc::LOCK_EX | libc::LOCK_NB) } != 0 {
            bail!(
                "another run is writing this sweep ({} is locked); wait for it, or stop it and run again to resume",
                path.display()
            );
        }
    }
    Ok(f)
}

/// What a run did.
pub struct Outcome {
    /// The strokes computed by this run, with their chart index, if
    /// [`RunFile::keep`]; else empty (the file holds them).
    pub cells: Vec<(usize, ChartCell)>,
    /// How many strokes this run computed.
    pub computed: usize,
    /// How many strokes it simulated for them (a bell off the ideal rings
    /// its backstroke too).
    pub rung: u64,
    /// Where this run started, if it resumed an earlier one.
    pub resumed_from: Option<usize>,
    /// Wall time of this run (s).
    pub seconds: f64,
}

/// Options of one run.
pub struct RunFile<'a> {
    /// The final CSV.
    pub csv: &'a Path,
    /// What the sweep is.
    pub meta: SweepMeta,
    /// Strokes per block (and journal entry).
    pub block: usize,
    /// Keep the computed strokes in memory for the caller (one chart to
    /// draw or summarise). Without it a run holds one block at a time,
    /// whatever the sweep's size.
    pub keep: bool,
}

/// Refuse to write shard `meta` over another shard of the same sweep in
/// `csv` (found by hand: `--shard 2/2 --csv a.csv` after `--shard 1/2
/// --csv a.csv` replaced the first, and `merge` then found it missing).
fn refuse_another_shard(csv: &Path, meta: &SweepMeta) -> Result<()> {
    let Ok(text) = std::fs::read_to_string(shard_meta_path(csv)) else {
        return Ok(());
    };
    let Ok(there) = serde_json::from_str::<SweepMeta>(&text) else {
        return Ok(());
    };
    if meta.shard[1] > 1 && there.key == meta.key && there.shard != meta.shard && csv.exists() {
        bail!(
            "{} already holds shard {} of {} of this sweep: give each shard its own --csv file \
             (e.g. part{}.csv), then clapper merge them",
            csv.display(),
            there.shard[0] + 1,
            there.shard[1],
            meta.shard[0] + 1
        );
    }
    Ok(())
}

/// Where a run stands: strokes done (absolute index), bytes of the partial
/// file vouched for, where it resumed from (if it did), and the checksum.
type Standing = (usize, u64, Option<usize>, u64);

/// Take up an interrupted run from its journal `text`, after checking
/// the journal and the partial file agree.
fn resume(text: &str, journal_path: &Path, partial: &Path, meta: &SweepMeta, range: &Range<usize>) -> Result<Standing> {
    let j: Journal = serde_json::from_str(text).with_context(|| {
        format!(
            "{} is not a sweep journal; delete it to start afresh",
            journal_path.display()
        )
    })?;
    if j.meta.format != meta.format {
        bail!(
            "{} is a journal of another clapper version (format {}, this one writes {}); delete it and {} to start afresh",
            journal_path.display(),
            j.meta.format,
            meta.format,
            partial.display()
        );
    }
    if j.meta != *meta {
        bail!(
            "{} holds an unfinished run of different options; run the same command to resume it, or delete {} and {} to start afresh",
            journal_path.display(),
            journal_path.display(),
            partial.display()
        );
    }
    let len = std::fs::metadata(partial).map(|m| m.len()).unwrap_or(0);
    if len < j.bytes {
        bail!(
            "{} is shorter than its journal says ({len} < {} bytes); delete it and {} to start afresh",
            partial.display(),
            j.bytes,
            journal_path.display()
        );
    }
    // The rows the journal vouches for must be the file's: as many
    // as strokes done, and the same bytes.
    let mut kept = vec![0u8; j.bytes as usize];
    std::io::Read::read_exact(
        &mut File::open(partial).with_context(|| format!("cannot read {}", partial.display()))?,
        &mut kept,
    )
    .with_context(|| format!("cannot read {}", partial.display()))?;
    let rows = kept.iter().filter(|&&b| b == b'\n').count().saturating_sub(1);
    let sum = fnv1a(FNV_START, &kept);
    if j.checksum != Some(sum) || Some(rows) != j.done.checked_sub(range.start) {
        bail!(
            "{} does not match {} ({} strokes done by the journal, {rows} rows in the file{}): \
             one of them was changed or damaged; delete both to start afresh (nothing else was touched)",
            journal_path.display(),
            partial.display(),
            j.done.saturating_sub(range.start),
            if j.checksum == Some(sum) {
                ""
            } else {
                ", and a different checksum"
            }
        );
    }
    // Drop a block that was being written when the run stopped.
    OpenOptions::new().write(true).open(partial)?.set_len(j.bytes)?;
    Ok((j.done, j.bytes, Some(j.done), sum))
}

/// Start the partial file (its header) and its journal.
fn start_afresh(
    journal_path: &Path,
    partial: &Path,
    meta: &SweepMeta,
    range: &Range<usize>,
    columns: clapper_io::Columns,
) -> Result<Standing> {
    let mut head = Vec::new();
    clapper_io::write_chart_rows(&mut head, std::iter::empty(), columns, true)?;
    let mut p = File::create(partial).with_context(|| format!("cannot create {}", partial.display()))?;
    p.write_all(&head)
        .and_then(|()| p.sync_all())
        .with_context(|| format!("cannot write {}", partial.display()))?;
    let bytes = head.len() as u64;
    let sum = fnv1a(FNV_START, &head);
    write_json_atomically(
        journal_path,
        &Journal {
            meta: meta.clone(),
            done: range.start,
            bytes,
            checksum: Some(sum),
        },
    )?;
    Ok((range.start, bytes, None, sum))
}

/// Say where a run checkpoints (on a terminal, when strokes are left to
/// do), and what an interruption leaves.
fn announce(partial: &Path, to_do: bool) {
    if std::io::IsTerminal::is_terminal(&std::io::stderr()) && to_do {
        // Said before any Ctrl-C, so the files it leaves are no surprise.
        eprintln!(
            "checkpointing to {} as it goes: if this run is stopped, the same command resumes it",
            partial.display()
        );
    }
    crate::files::resumable(format!(
        "the strokes done are kept in {}; run the same command again to resume",
        partial.display()
    ));
}

/// A block of computed strokes as the CSV's rows.
fn rows_of(plan: &SweepPlan, cells: &[(usize, ChartCell)], columns: clapper_io::Columns) -> Result<Vec<u8>> {
    let mut buf = Vec::new();
    clapper_io::write_chart_rows(
        &mut buf,
        cells
            .iter()
            .map(|(k, c)| (plan.has_axes.then_some(&plan.charts[*k].0), c)),
        columns,
        false,
    )?;
    Ok(buf)
}

/// Compute `meta.range` of `plan` into `csv`, resuming an interrupted run.
pub fn run(f: RunFile<'_>, plan: &SweepPlan, pool: &rayon::ThreadPool) -> Result<Outcome> {
    let columns = plan.columns();
    let (csv, meta) = (f.csv, f.meta);
    let partial = with_suffix(csv, ".partial");
    let journal_path = with_suffix(csv, ".partial.json");
    let range: Range<usize> = meta.range[0]..meta.range[1];
    let started = Instant::now();
    crate::files::ensure_folder(csv)?;
    // Two runs writing one sweep would interleave their blocks.
    let lock_path = with_suffix(csv, ".lock");
    let _lock = lock(&lock_path)?;
    refuse_another_shard(csv, &meta)?;

    let (mut done, mut bytes, resumed_from, mut sum) = match std::fs::read_to_string(&journal_path) {
        Ok(text) => resume(&text, &journal_path, &partial, &meta, &range)?,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            start_afresh(&journal_path, &partial, &meta, &range, columns)?
        }
        Err(e) => return Err(e).with_context(|| format!("cannot read {}", journal_path.display())),
    };

    announce(&partial, done < range.end);
    let bar = crate::progress::bar((range.end - range.start) as u64, "sweep");
    bar.set_position((done - range.start) as u64);
    let mut out = OpenOptions::new()
        .append(true)
        .open(&partial)
        .with_context(|| format!("cannot open {}", partial.display()))?;
    let mut mine = vec![];
    let mut computed = 0;
    let rung = std::sync::atomic::AtomicU64::new(0);
    while done < range.end {
        let end = range.end.min(done + f.block.max(1));
        let base = (done - range.start) as u64;
        let cells = pool.install(|| plan.cells_counting(done..end, &|d| bar.set_position(base + d), &rung))?;
        let buf = rows_of(plan, &cells, columns)?;
        out.write_all(&buf)
            .and_then(|()| out.sync_data())
            .with_context(|| format!("cannot write {}", partial.display()))?;
        bytes += buf.len() as u64;
        sum = fnv1a(sum, &buf);
        done = end;
        write_json_atomically(
            &journal_path,
            &Journal {
                meta: meta.clone(),
                done,
                bytes,
                checksum: Some(sum),
            },
        )?;
        computed += cells.len();
        if f.keep {
            mine.extend(cells);
        }
    }
    bar.finish_and_clear();
    crate::files::resumable_done();
    drop(out);
    std::fs::rename(&partial, csv).with_context(|| format!("cannot move the finished sweep to {}", csv.display()))?;
    if meta.shard[1] > 1 {
        write_json_atomically(&shard_meta_path(csv), &meta)?;
    }
    std::fs::remove_file(&journal_path).ok();
    std::fs::remove_file(&lock_path).ok();
    Ok(Outcome {
        cells: mine,
        computed,
        rung: rung.into_inner(),
        resumed_from,
        seconds: started.elapsed().as_secs_f64(),
    })
}
