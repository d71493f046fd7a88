//! The measurement commands' answers (the paper's experimental half):
//! restitution from clapper drops, contacts, the decay of one frequency,
//! the partials of a strike, and energy into vibration. Each is a report
//! (serde: what `--json` prints, keys in alphabetical order as they always
//! were) with the text the command line prints. The caller reads the
//! signal and draws the plots.

use std::fmt::Write as _;

use clapper_core::param::readable;
use clapper_core::restitution;
use clapper_core::vibration::{self, Mode};
use clapper_signal::contacts::{detect, ContactOptions};
use clapper_signal::modes::{find_modes, ModeOptions};
use clapper_signal::spectrogram::spectrogram;
use clapper_signal::Signal;
use serde::Serialize;

use crate::AppError;

fn signal_error(what: &str, e: impl std::fmt::Display) -> AppError {
    AppError::Request(format!("{what}: {e}"))
}

/// Points of a line plot: (x, y).
pub type Points = Vec<(f64, f64)>;

/// What drops of the clapper say about R and R2 (Section 3.2, Fig 8).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RestitutionReport {
    /// Impact times (s), when read from an accelerometer recording.
    pub impact_times_s: Option<Vec<f64>>,
    /// The velocity jumps of each drop.
    pub jumps: Vec<Vec<f64>>,
    /// Mean over drops of each adjacent pair's ratio (the paper's circles).
    pub mean_ratios: Vec<f64>,
    /// R by (21): every impact loses the same fraction.
    pub r_equal_loss: f64,
    /// R of the first impact, with R2 for the later ones (`--restitution`).
    pub r_first: Option<f64>,
    /// R2 of the later bounces (`--restitution-later`).
    pub r_later: Option<f64>,
    /// Whether the later ratios averaged above one (R2 set to 1).
    pub r_later_clamped: Option<bool>,
    /// R by (23): the impacts after the first are lossless.
    pub r_lossless_later: f64,
    /// Ratios of adjacent jumps per drop.
    pub ratios: Vec<Vec<f64>>,
}

impl RestitutionReport {
    /// The report for `drops` (velocity jumps, any consistent unit), with
    /// their impact `times` (s) if known.
    pub fn new(drops: Vec<Vec<f64>>, times: Option<Vec<f64>>) -> Result<Self, AppError> {
        // A clapper strikes at a few m/s: a few thousand in mm/s.
        if let Some(v) = drops.iter().flatten().find(|v| v.abs() > MAX_JUMP) {
            return Err(AppError::Request(format!(
                "--jumps {}: a velocity jump of at most {MAX_JUMP} (m/s or mm/s; a clapper strikes at a few m/s)",
                readable(*v)
            )));
        }
        let est = restitution::estimate(&drops)?;
        Ok(Self {
            impact_times_s: times,
            jumps: drops,
            mean_ratios: est.mean_ratios,
            r_equal_loss: est.r_equal_loss,
            r_first: est.two.map(|t| t.first),
            r_later: est.two.map(|t| t.later),
            r_later_clamped: est.two.map(|t| t.later_clamped),
            r_lossless_later: est.r_lossless_later,
            ratios: est.ratios,
        })
    }

    /// The readable report.
    pub fn text(&self) -> String {
        let mut o = String::new();
        let _ = writeln!(o, "velocity jumps of {} drop(s)", self.jumps.len());
        for (k, m) in self.mean_ratios.iter().enumerate() {
            let _ = writeln!(o, "  mean ratio dv{}/dv{} = {m:.4}", k + 2, k + 1);
        }
        let _ = writeln!(
            o,
            "R if every impact loses the same fraction (21):   {:.4}",
            self.r_equal_loss
        );
        let _ = writeln!(
            o,
            "R if the impacts after the first are lossless (23): {:.4}",
            self.r_lossless_later
        );
        match (self.r_first, self.r_later) {
            (Some(r), Some(r2)) => {
                let clamped = if self.r_later_clamped == Some(true) {
                    " (later ratios above 1, taken as lossless)"
                } else {
                    ""
                };
                let _ = writeln!(
                    o,
                    "R of the first impact and R2 of the later ones: R = {r:.4}, R2 = {r2:.4}{clamped}"
                );
                let _ = writeln!(o, "  simulate with: --restitution {r:.4} --restitution-later {r2:.4}");
            }
            _ => {
                let _ = writeln!(
                    o,
                    "(R and R2 apart need three jumps in a drop; the truth lies between (21) and (23))"
                );
            }
        }
        o
    }

    /// The points of the paper's Fig 8: every ratio (pair index from 1,
    /// ratio), and the mean of each pair.
    pub fn fig8_points(&self) -> (Points, Points) {
        let stars = self
            .ratios
            .iter()
            .flat_map(|r| r.iter().enumerate().map(|(k, v)| (k as f64 + 1.0, *v)))
            .collect();
        let means = self
            .mean_ratios
            .iter()
            .enumerate()
            .map(|(k, v)| (k as f64 + 1.0, *v))
            .collect();
        (stars, means)
    }
}

/// One contact of a contact-detector recording.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ContactReport {
    /// When it began (s).
    pub contact_s: f64,
    /// How long it lasted (ms).
    pub duration_ms: f64,
    /// When it ended (s); `None` if at the end of the recording.
    pub separation_s: Option<f64>,
}

/// Contacts, bounces, rest and lift-off in a contact-detector recording
/// (Figs 2, 5).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ContactsReport {
    /// Contacts before the clapper came to rest.
    pub bounces: usize,
    /// Every contact.
    pub contacts: Vec<ContactReport>,
    /// When the resting clapper lifted off (s): from the rest the
    /// recording starts with, else from the rest after the strike.
    pub liftoff_s: Option<f64>,
    /// Sample rate (Hz).
    pub sample_rate_hz: f64,
    /// From the strike (the first contact after any starting rest) to rest (s).
    pub time_to_rest_s: Option<f64>,
    /// Which contact is the one at rest (from 0).
    #[serde(skip)]
    pub rest: Option<usize>,
    /// Whether the recording starts with the clapper resting (a whole
    /// stroke), the lift-off then being from that first contact.
    pub starts_at_rest: bool,
}

/// The largest velocity jump taken, in any unit.
const MAX_JUMP: f64 = 100_000.0;
/// The longest out-of-contact gap taken as noise (ms).
const MAX_MIN_GAP_MS: f64 = 1000.0;
/// The longest half-sine pulse taken (ms).
const MAX_PULSE_MS: f64 = 100.0;

impl ContactsReport {
    /// Detect the contacts in `sig`: the higher level means contact if
    /// `contact_high`; gaps shorter than `min_gap_ms` are noise.
    pub fn new(sig: &Signal, contact_high: bool, min_gap_ms: f64) -> Result<Self, AppError> {
        if !(min_gap_ms.is_finite() && (0.0..=MAX_MIN_GAP_MS).contains(&min_gap_ms)) {
            return Err(AppError::Request(format!(
                "--min-gap-ms {} ms: from 0 to {MAX_MIN_GAP_MS} ms (a clapper's bounces are milliseconds apart)",
                readable(min_gap_ms)
            )));
        }
        let opts = ContactOptions {
            contact_is_low: !contact_high,
            min_gap_s: min_gap_ms * 1e-3,
            ..ContactOptions::default()
        };
        let c = detect(sig, &opts).map_err(|e| signal_error("contacts", e))?;
        let n = sig.samples.len();
        Ok(Self {
            bounces: c.bounces().len(),
            contacts: c
                .intervals
                .iter()
                .map(|&(a, b)| ContactReport {
                    contact_s: c.time(a),
                    duration_ms: (b - a) as f64 / sig.rate * 1e3,
                    separation_s: (b < n).then(|| c.time(b)),
                })
                .collect(),
            liftoff_s: c.liftoff(n),
            sample_rate_hz: sig.rate,
            time_to_rest_s: c.time_to_rest(),
            rest: c.rest,
            starts_at_rest: c.starts_at_rest,
        })
    }

    /// The readable report, for the recording `name`.
    pub fn text(&self, name: &str) -> String {
        let mut o = String::new();
        let _ = writeln!(
            o,
            "{name}: {} contact(s) at {} Hz",
            self.contacts.len(),
            self.sample_rate_hz
        );
        for (k, c) in self.contacts.iter().enumerate() {
            let tag = if Some(k) == self.rest {
                "  <- at rest"
            } else if k == 0 && self.starts_at_rest {
                "  <- resting, lifts off"
            } else {
                ""
            };
            let sep = c
                .separation_s
                .map_or("end of recording".into(), |t| format!("{t:.5} s"));
            let _ = writeln!(
                o,
                "  contact {:>3}: {:.5} s to {sep} ({:.2} ms){tag}",
                k + 1,
                c.contact_s,
                c.duration_ms
            );
        }
        let _ = writeln!(o, "bounces before rest: {}", self.bounces);
        let _ = match self.time_to_rest_s {
            Some(r) => writeln!(
                o,
                "time to rest: {r:.4} s after the strike (the first contact after lift-off)"
            ),
            None => writeln!(o, "time to rest: the clapper did not come to rest"),
        };
        if let Some(l) = self.liftoff_s {
            let _ = writeln!(o, "lift-off: {l:.4} s");
        }
        o
    }
}

/// Where the decay rate changes most.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct RateChange {
    /// After (dB/s).
    pub after_db_per_s: f64,
    /// Before (dB/s).
    pub before_db_per_s: f64,
    /// When (s).
    pub t_s: f64,
}

/// How far below its loudest a decay is followed (dB): 120 dB is below
/// the noise of any recording (16 bits reach 96 dB), so the floor is met
/// only in digital silence.
pub const DECAY_FLOOR_DB: f64 = 120.0;

/// The level of one frequency against time (Fig 4).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct DecayReport {
    /// The spectrogram bin followed (Hz).
    pub bin_hz: f64,
    /// (time s, level dB below the spectrogram's maximum).
    pub points: Vec<[f64; 2]>,
    /// The spectrogram's floor (dB, [`DECAY_FLOOR_DB`] below its maximum):
    /// a point at it is that quiet or quieter (silence before a strike).
    pub floor_db: f64,
    /// Where the decay rate changes most after the loudest frame: where a
    /// resting clapper starts to damp the bell.
    pub rate_change: Option<RateChange>,
}

impl DecayReport {
    /// Follow `freq` (Hz) in `sig` with windows of `window` samples
    /// overlapping by `overlap`.
    pub fn new(sig: &Signal, freq: f64, window: usize, overlap: f64) -> Result<Self, AppError> {
        if !(freq.is_finite() && freq > 0.0 && freq < sig.rate / 2.0) {
            return Err(AppError::Request(format!(
                "--freq {freq} Hz must lie between 0 and {} Hz (half the sample rate)",
                sig.rate / 2.0
            )));
        }
        let s = spectrogram(sig, window, overlap, DECAY_FLOOR_DB).map_err(|e| signal_error("spectrogram", e))?;
        let d = s.decay(freq);
        let loudest = d.iter().max_by(|a, b| a.1.total_cmp(&b.1)).map_or(0.0, |p| p.0);
        let change = clapper_signal::synth::decay_change(&d, loudest);
        Ok(Self {
            bin_hz: s.freqs[s.bin_of(freq)],
            points: d.iter().map(|p| [p.0, p.1]).collect(),
            floor_db: -DECAY_FLOOR_DB,
            rate_change: change.map(|(t, a, b)| RateChange {
                after_db_per_s: b,
                before_db_per_s: a,
                t_s: t,
            }),
        })
    }

    /// The readable report: CSV of time and level, with a comment.
    pub fn text(&self) -> String {
        let mut o = format!("level of the {:.2} Hz bin: {} frame(s)", self.bin_hz, self.points.len());
        if let (Some(first), Some(last)) = (self.points.first(), self.points.last()) {
            let _ = write!(o, " from {:.3} s to {:.3} s", first[0], last[0]);
        }
        o.push('\n');
        if let Some(peak) = self.points.iter().max_by(|a, b| a[1].total_cmp(&b[1])) {
            let _ = writeln!(o, "  loudest   {:.1} dB at {:.3} s", peak[1], peak[0]);
        }
        match self.rate_change {
            Some(c) => {
                let _ = writeln!(
                    o,
                    "  the decay changes most at {:.3} s: from {:.1} to {:.1} dB/s",
                    c.t_s, c.before_db_per_s, c.after_db_per_s
                );
            }
            None => o.push_str("  no change of decay rate found\n"),
        }
        o.push_str("  (the level against time: --csv FILE, or --csv - for standard output; --plot FILE)\n");
        o
    }

    /// The level against time as CSV: `t_s,level_db`, one frame a row.
    pub fn csv(&self) -> String {
        let mut o = String::from("t_s,level_db\n");
        for [t, l] in &self.points {
            let _ = writeln!(o, "{t:.5},{l:.2}");
        }
        o
    }
}

/// One partial of a strike.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct PartialReport {
    /// The other member of a close doublet (Hz).
    pub doublet_with_hz: Option<f64>,
    /// Frequency (Hz).
    pub freq_hz: f64,
    /// Level at the strike relative to the strongest (dB).
    pub level_db: f64,
    /// Q factor.
    pub q: Option<f64>,
}

pub use clapper_signal::modes::DEFAULT_RANGE_DB as DEFAULT_MODES_RANGE_DB;

/// The partials of a single strike (Figs 3, 4).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ModesReport {
    /// The partials, strongest first.
    pub modes: Vec<PartialReport>,
}

impl ModesReport {
    /// The partials of `sig` within `range_db` of the strongest.
    pub fn new(sig: &Signal, range_db: f64) -> Result<Self, AppError> {
        let opts = ModeOptions {
            range_db,
            ..ModeOptions::default()
        };
        let m = find_modes(sig, &opts).map_err(|e| signal_error("modes", e))?;
        Ok(Self {
            modes: m
                .iter()
                .map(|p| PartialReport {
                    doublet_with_hz: p.doublet_with,
                    freq_hz: p.freq_hz,
                    level_db: p.level_db,
                    q: p.q,
                })
                .collect(),
        })
    }

    /// The readable report, for the recording `name`.
    pub fn text(&self, name: &str) -> String {
        let mut o = format!("{} partial(s) of {name}:\n", self.modes.len());
        let _ = writeln!(o, "  {:>10} {:>8} {:>9}  note", "freq (Hz)", "Q", "level dB");
        for p in &self.modes {
            let note = p.doublet_with_hz.map_or(String::new(), |f| {
                format!("doublet with {f:.2} Hz: beats at {:.2} Hz", (f - p.freq_hz).abs())
            });
            let q = p.q.map_or("-".into(), |q| format!("{q:.0}"));
            let _ = writeln!(o, "  {:>10.2} {q:>8} {:>9.1}  {note}", p.freq_hz, p.level_db);
        }
        o
    }
}

/// Choosing an impulse hammer.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct HammerReport {
    /// The frequency a hit must reach cleanly (Hz).
    pub fmax_hz: f64,
    /// The heaviest hammer that still rebounds cleanly (kg).
    pub heaviest_clean_hammer_kg: f64,
    /// The longest pulse that reaches `fmax_hz` (ms).
    pub longest_pulse_ms: f64,
}

/// Energy into vibration at an impact (Section 3.3, (24) to (32)).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ImpulseReport {
    /// Whether the striker rebounds cleanly (λ ≥ 0).
    pub clean_rebound: bool,
    /// The hammer aside, when asked.
    pub hammer: Option<HammerReport>,
    /// K = Σ m/M_n |F|².
    pub k: f64,
    /// λ = v1/v0 = (1 − K)/(1 + K).
    pub lambda: f64,
    /// The half-sine pulse length (ms; 0 = an ideal impulse).
    pub pulse_ms: f64,
    /// R = λ².
    pub r: f64,
    /// The shortest pulse that rebounds cleanly (ms).
    pub shortest_clean_pulse_ms: Option<f64>,
    /// Modes with |F|² ≥ 1/2.
    pub strongly_excited_modes: usize,
    /// Modes, for the text.
    #[serde(skip)]
    pub modes: usize,
    /// Striker mass (kg), for the text.
    #[serde(skip)]
    pub mass_kg: f64,
}

impl ImpulseReport {
    /// A striker of `mass_kg` on `modes` with a half-sine pulse of
    /// `pulse_ms` (none: an ideal impulse), and the hammer that reaches
    /// `hammer_fmax` Hz if asked.
    pub fn new(
        modes: &[Mode],
        mass_kg: f64,
        pulse_ms: Option<f64>,
        hammer_fmax: Option<f64>,
    ) -> Result<Self, AppError> {
        if !(mass_kg.is_finite() && mass_kg > 0.0) {
            return Err(AppError::Request(format!(
                "--clapper-mass {mass_kg} kg must be a finite number > 0"
            )));
        }
        let tau = match pulse_ms {
            Some(t) if t.is_finite() && (0.0..=MAX_PULSE_MS).contains(&t) => t * 1e-3,
            Some(t) => {
                return Err(AppError::Request(format!(
                    "--pulse-ms {} ms: a half-sine pulse from 0 to {MAX_PULSE_MS} ms (a clapper's contact lasts about 1 ms)",
                    readable(t)
                )))
            }
            None => 0.0,
        };
        let k = vibration::k_factor(modes, mass_kg, tau);
        let lambda = vibration::lambda(k);
        Ok(Self {
            clean_rebound: lambda >= 0.0,
            hammer: hammer_fmax.map(|f| {
                let t = vibration::longest_pulse_for(f);
                HammerReport {
                    fmax_hz: f,
                    heaviest_clean_hammer_kg: vibration::heaviest_clean_hammer(modes, t),
                    longest_pulse_ms: t * 1e3,
                }
            }),
            k,
            lambda,
            pulse_ms: tau * 1e3,
            r: vibration::restitution(k),
            shortest_clean_pulse_ms: vibration::shortest_clean_pulse(modes, mass_kg).map(|s| s * 1e3),
            strongly_excited_modes: vibration::strongly_excited(modes, tau),
            modes: modes.len(),
            mass_kg,
        })
    }

    /// K against pulse length for a plot on a log axis: (the half-sine
    /// pulse in ms, 401 lengths evenly spaced in its log from 1 µs to
    /// 10 ms; K, capped at 10).
    pub fn k_curve(modes: &[Mode], mass_kg: f64) -> Vec<(f64, f64)> {
        (0..=400)
            .map(|i| {
                let ms = 10f64.powf(-3.0 + 4.0 * i as f64 / 400.0);
                (ms, vibration::k_factor(modes, mass_kg, ms * 1e-3).min(10.0))
            })
            .collect()
    }

    /// The readable report.
    pub fn text(&self) -> String {
        let mut o = String::new();
        let _ = writeln!(
            o,
            "{} mode(s), striker {} kg, pulse {:.3} ms (half-sine; 0 = ideal impulse)",
            self.modes, self.mass_kg, self.pulse_ms
        );
        let bad = if self.lambda < 0.0 {
            " (no clean rebound: K > 1)"
        } else {
            ""
        };
        let _ = writeln!(
            o,
            "  K = {:.4}, lambda = v1/v0 = {:.4}, R = {:.4}{bad}",
            self.k, self.lambda, self.r
        );
        let _ = writeln!(
            o,
            "  modes strongly excited (|F|^2 >= 1/2): {}",
            self.strongly_excited_modes
        );
        let _ = match self.shortest_clean_pulse_ms {
            Some(0.0) => writeln!(o, "  any pulse, even an ideal impulse, rebounds cleanly (K <= 1)"),
            Some(s) => writeln!(o, "  shortest pulse for a clean rebound: {s:.4} ms"),
            None => writeln!(o, "  no pulse length gives a clean rebound: the striker is too heavy"),
        };
        if let Some(h) = self.hammer {
            let _ = writeln!(
                o,
                "  hammer to reach {} Hz: pulse at most {:.4} ms (a hard tip), hammer at most {:.3} kg for a clean single hit",
                h.fmax_hz, h.longest_pulse_ms, h.heaviest_clean_hammer_kg
            );
        }
        o
    }
}
