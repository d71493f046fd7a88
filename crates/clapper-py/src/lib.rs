//! # clapper-py
//!
//! The native half of the Python package `clapper` (`clapper._clapper`).
//! It is thin on purpose: every request arrives as the JSON the web API
//! and `clapper-app` already read (the same keys as the command line's
//! long options, in snake case), every report leaves as the JSON the CLI's
//! `--json` prints, and arrays cross as little-endian `f64` bytes that the
//! Python half wraps with `numpy.frombuffer`. So the Python package adds
//! no model of its own: what it returns is what `clapper` prints.
//!
//! The GIL is released while a stroke, a chart, a diagnosis or an analysis
//! runs, so other Python threads go on.
//!
//! Errors: bad input (a request out of range, a bell file that does not
//! parse) raises `ValueError`; a numerical failure raises `RuntimeError`;
//! both carry the library's one-line message. The Python half checks
//! keyword options against `request_keys` first, so that a misspelt or
//! mistyped option is named in Python's terms rather than serde's.

use clapper_app::chart::ChartRequest;
use clapper_app::diagnosis::{self, DiagnoseRequest};
use clapper_app::liftoff::{BellLiftoffReport, FormulaReport};
use clapper_app::measure::{ModesReport, RestitutionReport};
use clapper_app::simulate::{self as sim_app, SimulateRequest};
use clapper_app::strikes::{
    choose_timing, learned_or_none, opening, strike_options, Learning, StrikesReport, TimingAsked, Voice,
};
use clapper_app::AppError;
use clapper_core::chart::{sweep, ChartCell};
use clapper_core::Choice;
use clapper_io::report::BellReport;
use clapper_signal::Signal;
use pyo3::exceptions::{PyOSError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};

mod schema;

/// The Python exception for an error of the library.
fn py_err(e: AppError) -> PyErr {
    if e.is_bad_input() {
        PyValueError::new_err(e.to_string())
    } else {
        PyRuntimeError::new_err(e.to_string())
    }
}

/// A request read from its JSON text; a key the request does not know is
/// named in the error, as the web API names it. The Python half checks
/// keys and values first (see [`request_keys`]), so this is the backstop;
/// the JSON is the package's own, so its line and column are left out.
fn request<T: serde::de::DeserializeOwned>(json: &str, what: &str) -> PyResult<T> {
    serde_json::from_str(json).map_err(|e| {
        let text = e.to_string();
        let at = format!(" at line {} column {}", e.line(), e.column());
        PyValueError::new_err(format!("{what}: {}", text.strip_suffix(&at).unwrap_or(&text)))
    })
}

/// One key of a request: (key, kind, choices, length); see [`request_keys`].
type RequestKey = (String, String, Vec<String>, usize);

/// The keys a request takes, each with the kind of value it takes:
/// `(key, kind, choices, length)`, where kind is "number", "count" (a
/// whole number >= 0), "integer", "text", "bool", "choice" (one of
/// `choices`), "array of <kind>" (`length` of them) or "other". `what` is
/// "simulate" (also a bell's and lift-off's request), "chart" or "bell"
/// (the keys of a bell file).
#[pyfunction]
fn request_keys(what: &str) -> PyResult<Vec<RequestKey>> {
    let fields = match what {
        "simulate" => schema::fields::<SimulateRequest>(),
        "chart" => schema::fields::<ChartRequest>(),
        "bell" => schema::fields::<schema::BellFileKeys>(),
        _ => {
            return Err(PyValueError::new_err(format!(
                "no request {what:?}: simulate, chart or bell"
            )))
        }
    };
    Ok(fields
        .into_iter()
        .map(|(name, kind)| {
            let (tag, choices, len) = kind.describe();
            (name.to_string(), tag, choices, len)
        })
        .collect())
}

fn to_json<T: serde::Serialize>(v: &T) -> PyResult<String> {
    serde_json::to_string(v).map_err(|e| PyRuntimeError::new_err(e.to_string()))
}

/// `values` as little-endian f64 bytes (numpy's `<f8`).
fn f64_bytes<'py>(py: Python<'py>, values: impl IntoIterator<Item = f64>) -> Bound<'py, PyBytes> {
    let bytes: Vec<u8> = values.into_iter().flat_map(f64::to_le_bytes).collect();
    PyBytes::new(py, &bytes)
}

/// Little-endian f64 bytes back to values.
fn f64s(bytes: &[u8], what: &str) -> PyResult<Vec<f64>> {
    if bytes.len() % 8 != 0 {
        return Err(PyValueError::new_err(format!(
            "{what}: {} bytes is not a whole number of float64 values",
            bytes.len()
        )));
    }
    Ok(bytes
        .chunks_exact(8)
        .map(|c| f64::from_le_bytes(c.try_into().unwrap_or([0; 8])))
        .collect())
}

/// The bell a simulate request names, described: its chart position,
/// lengths, periods (s), masses (kg) and contact angle (deg), as JSON.
#[pyfunction]
fn describe_bell(py: Python<'_>, request_json: &str) -> PyResult<String> {
    let req: SimulateRequest = request(request_json, "bell")?;
    let loaded = py.detach(|| req.bell(None)).map_err(py_err)?;
    to_json(&BellReport::new(&loaded.name, &loaded.bell, &loaded.source))
}

/// What [`simulate`] returns to Python: report JSON, summary text,
/// warnings, and the trace's columns.
type Simulated<'py> = (String, String, Vec<String>, Option<Bound<'py, PyDict>>);

/// Reads one quantity of a chart cell.
type CellReader = fn(&ChartCell) -> Option<f64>;

/// Simulate strokes: returns (report JSON, summary text, warnings, trace),
/// where the trace is None or a dict of f64 byte columns: t (s), theta,
/// phi (rad), theta_dot, phi_dot (rad/s), contact_force (N m).
#[pyfunction]
fn simulate<'py>(py: Python<'py>, request_json: &str, trace: bool) -> PyResult<Simulated<'py>> {
    let req: SimulateRequest = request(request_json, "simulate")?;
    let sim = py
        .detach(|| {
            if trace {
                sim_app::simulate_traced(&req, None, None)
            } else {
                sim_app::simulate(&req, None, None)
            }
        })
        .map_err(py_err)?;
    let columns = if trace {
        let d = PyDict::new(py);
        let s = &sim.samples;
        d.set_item("t", f64_bytes(py, s.iter().map(|x| x.t)))?;
        d.set_item("theta", f64_bytes(py, s.iter().map(|x| x.y[0])))?;
        d.set_item("phi", f64_bytes(py, s.iter().map(|x| x.y[1])))?;
        d.set_item("theta_dot", f64_bytes(py, s.iter().map(|x| x.y[2])))?;
        d.set_item("phi_dot", f64_bytes(py, s.iter().map(|x| x.y[3])))?;
        d.set_item("contact_force", f64_bytes(py, s.iter().map(|x| x.contact_force)))?;
        Some(d)
    } else {
        None
    };
    Ok((
        to_json(&sim.report)?,
        sim_app::summary(&sim.report),
        sim.warnings,
        columns,
    ))
}

/// The quantities a chart holds per point and style, in the order of
/// [`chart`]'s arrays: name, and how to read it from a cell (NaN where a
/// stroke did not sustain its style or has no such quantity).
const CHART_QUANTITIES: [(&str, CellReader); 8] = [
    ("sustained", |c| {
        Some(match &c.result {
            Ok(s) if s.sustained => 1.0,
            Ok(_) => 0.0,
            Err(_) => f64::NAN,
        })
    }),
    ("strike_angle_deg", |c| c.sustained()?.strike_theta.map(f64::to_degrees)),
    ("strike_velocity_rad_s", |c| c.sustained()?.strike_phidot),
    ("liftoff_angle_deg", |c| {
        c.sustained()?.liftoff_theta.map(f64::to_degrees)
    }),
    ("double_strike_index", |c| c.sustained()?.double_strike_index),
    ("second_strike_delay_ms", |c| {
        c.sustained()?.second_strike_delay.map(|t| t * 1e3)
    }),
    ("amplitude_ratio", |c| c.sustained()?.amplitude_ratio),
    ("odd_struck_ms", |c| c.sustained()?.odd_struck.map(|t| t * 1e3)),
];

/// Sweep a clapping chart (in parallel, the GIL released). Returns a dict:
/// `r_over_lc` (nx), `lb_over_lc` (ny) as f64 bytes, `styles` (names), and
/// for each style a dict of quantity -> f64 bytes of ny x nx values, rows
/// by L_b/L_c ascending (NaN where the style is not sustained). `threads`:
/// the worker threads (1 to 1024; default one per core), as the command
/// line's `--threads`; the result does not depend on it.
#[pyfunction]
#[pyo3(signature = (request_json, threads = None))]
fn chart<'py>(py: Python<'py>, request_json: &str, threads: Option<usize>) -> PyResult<Bound<'py, PyDict>> {
    let req: ChartRequest = request(request_json, "chart")?;
    let spec = req.spec().map_err(py_err)?;
    let pool = match threads {
        Some(n) if !(1..=1024).contains(&n) => {
            return Err(PyValueError::new_err(format!(
                "chart: threads must be 1 to 1024, not {n}"
            )));
        }
        Some(n) => Some(
            rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .map_err(|e| PyRuntimeError::new_err(format!("chart: {e}")))?,
        ),
        None => None,
    };
    let run = || sweep(&spec, &|_| {});
    let chart = py
        .detach(|| match &pool {
            Some(p) => p.install(run),
            None => run(),
        })
        .map_err(|e| py_err(AppError::Param(e)))?;
    let out = PyDict::new(py);
    out.set_item("r_over_lc", f64_bytes(py, spec.xs()))?;
    out.set_item("lb_over_lc", f64_bytes(py, spec.ys()))?;
    out.set_item("errors", chart.errors())?;
    let styles = spec.styles.list();
    let names: Vec<&str> = styles.iter().map(|s| s.name()).collect();
    out.set_item("styles", names.clone())?;
    for (k, name) in names.iter().enumerate() {
        let per = PyDict::new(py);
        for (q, read) in CHART_QUANTITIES {
            let values = chart
                .cells
                .iter()
                .skip(k)
                .step_by(styles.len())
                .map(|c| read(c).unwrap_or(f64::NAN));
            per.set_item(q, f64_bytes(py, values))?;
        }
        out.set_item(*name, per)?;
    }
    Ok(out)
}

/// Diagnose a bell or a ring (`{"preset": ..}`, `{"toml": ..}` or
/// `{"csv": ..}`): returns (report JSON, the CLI's text).
#[pyfunction]
fn diagnose(py: Python<'_>, request_json: &str) -> PyResult<(String, String)> {
    let req: DiagnoseRequest = request(request_json, "diagnose")?;
    let (bells, source) = req.bells().map_err(py_err)?;
    let rep = py.detach(|| diagnosis::diagnose_bells(&bells)).map_err(py_err)?;
    Ok((to_json(&rep)?, diagnosis::text(&rep, &source)))
}

/// A ring rung through a touch in its tower (`clapper tower`): the request
/// is the web API's (`{"toml"|"csv": RING, "tower": TOML?, "request": {..}}`);
/// returns (report JSON, text, the histories as f64 bytes by column name:
/// the columns of `clapper tower --csv`, sway only with a tower).
#[pyfunction]
fn tower<'py>(py: Python<'py>, request_json: &str) -> PyResult<(String, String, Bound<'py, PyDict>)> {
    let input: clapper_app::tower::TowerInput = request(request_json, "tower")?;
    let ans = py
        .detach(|| clapper_app::tower::tower_input(&input, None))
        .map_err(py_err)?;
    let r = &ans.result;
    let out = PyDict::new(py);
    out.set_item("time_s", f64_bytes(py, (0..r.force_east.len()).map(|i| r.time(i))))?;
    for (name, v) in [
        ("force_east_n", &r.force_east),
        ("force_north_n", &r.force_north),
        ("vertical_n", &r.vertical),
        ("moment_east_n_m", &r.moment_east),
        ("moment_north_n_m", &r.moment_north),
        ("torsion_n_m", &r.torsion),
    ] {
        out.set_item(name, f64_bytes(py, v.iter().copied()))?;
    }
    if let Some([e, n]) = &r.sway {
        out.set_item("sway_east_m", f64_bytes(py, e.displacement.iter().copied()))?;
        out.set_item("sway_north_m", f64_bytes(py, n.displacement.iter().copied()))?;
        out.set_item("accel_east_m_s2", f64_bytes(py, e.acceleration.iter().copied()))?;
        out.set_item("accel_north_m_s2", f64_bytes(py, n.acceleration.iter().copied()))?;
    }
    Ok((to_json(&ans.report)?, ans.report.text(), out))
}

/// The closed-form lift-off angles of (15), (16) for r = 0: returns
/// (report JSON, text).
#[pyfunction]
fn liftoff_formula(lb_over_lc: f64, phi_max_deg: f64) -> PyResult<(String, String)> {
    let r = FormulaReport::new(lb_over_lc, phi_max_deg).map_err(py_err)?;
    Ok((to_json(&r)?, r.text()))
}

/// The exact lift-off of the bell a simulate request names, released from
/// rest at `theta0_deg`: returns (report JSON, text).
#[pyfunction]
fn liftoff_bell(py: Python<'_>, request_json: &str, theta0_deg: f64) -> PyResult<(String, String)> {
    let req: SimulateRequest = request(request_json, "liftoff")?;
    let r = py
        .detach(|| {
            let loaded = req.bell(None)?;
            BellLiftoffReport::new(&loaded, theta0_deg)
        })
        .map_err(py_err)?;
    Ok((to_json(&r)?, r.text()))
}

/// R and R2 from the clapper's velocity jumps of each drop (Section 3.2):
/// returns (report JSON, text).
#[pyfunction]
fn restitution(drops: Vec<Vec<f64>>) -> PyResult<(String, String)> {
    let r = RestitutionReport::new(drops, None).map_err(py_err)?;
    Ok((to_json(&r)?, r.text()))
}

/// The partials of a single strike, `samples` (f64 bytes) at `rate_hz`,
/// within `range_db` of the strongest: returns (report JSON, text).
#[pyfunction]
fn modes(py: Python<'_>, samples: &[u8], rate_hz: f64, range_db: f64, name: &str) -> PyResult<(String, String)> {
    let sig = Signal {
        rate: rate_hz,
        samples: f64s(samples, "signal")?,
    };
    let r = py.detach(|| ModesReport::new(&sig, range_db)).map_err(py_err)?;
    Ok((to_json(&r)?, r.text(name)))
}

/// Every strike of every bell in a recording, `samples` (f64 bytes) at
/// `rate_hz`, the bells given by their nominals (Hz, treble first) or, with
/// no nominals, `bells` of them learned from the recording (as `clapper
/// strikes --bells N`), as handbells if `handbells` (as `--handbells`),
/// timed as `timing` says ("auto", "plain" or "recording", as `--timing`):
/// returns (report JSON, text).
#[pyfunction]
#[pyo3(signature = (samples, rate_hz, nominals_hz, bells, double_min_ratio, name, handbells=false, timing="auto"))]
#[allow(clippy::too_many_arguments)]
fn strikes(
    py: Python<'_>,
    samples: &[u8],
    rate_hz: f64,
    nominals_hz: Option<Vec<f64>>,
    bells: Option<usize>,
    double_min_ratio: f64,
    name: &str,
    handbells: bool,
    timing: &str,
) -> PyResult<(String, String)> {
    let kind = if handbells { Voice::Handbell } else { Voice::Tower };
    let asked: TimingAsked = timing.parse().map_err(py_err)?;
    let sig = Signal {
        rate: rate_hz,
        samples: f64s(samples, "recording")?,
    };
    let opts = strike_options(double_min_ratio).map_err(py_err)?;
    let r = py
        .detach(|| {
            let (nominals, learned) = match (nominals_hz, bells) {
                (Some(n), None) => (n, None),
                (None, Some(b)) => match learned_or_none(&sig, b, kind)? {
                    Learning::Learned(_, l) => (l.nominals.iter().map(|x| x.nominal_hz).collect(), Some(*l)),
                    // No bell's strike to learn from: the report of none, as the CLI's.
                    Learning::Unheard(r) => return Ok(*r),
                },
                _ => {
                    return Err(clapper_app::AppError::Request(
                        "strikes: give the bells' nominals_hz or bells= (how many ring, their nominals learned), one of the two"
                            .into(),
                    ))
                }
            };
            // Timed as the CLI and the web server time them.
            let chosen = choose_timing(&opening(&sig), &nominals, kind, asked, &opts)?;
            let mut r = StrikesReport::timed(&sig, &chosen.voices, &opts, chosen.timing())?;
            if let Some(l) = learned {
                r.note_learned(l);
            }
            r.note_choice(chosen.choice);
            Ok(r)
        })
        .map_err(py_err)?;
    Ok((to_json(&r)?, r.text(name)))
}

/// A WAV recording read as the CLI reads one, its channels heard as
/// `channel` asks (as `strikes --channel`: a channel's number from 1,
/// "mix", or "auto": mixed to mono, or one heard alone where they disagree
/// in time): returns (samples as f64 bytes, rate in Hz, what reading it
/// told in words).
#[pyfunction]
#[pyo3(signature = (path, channel = "auto"))]
fn read_wav<'py>(
    py: Python<'py>,
    path: std::path::PathBuf,
    channel: &str,
) -> PyResult<(Bound<'py, PyBytes>, f64, Vec<String>)> {
    use clapper_io::signal_file::{ChannelChoice, SignalFileError};
    let choice: ChannelChoice = channel.parse().map_err(PyValueError::new_err)?;
    let (sig, told) = clapper_io::signal_file::read_recording_chosen(&path, choice).map_err(|e| match e {
        // The Python half has opened the file already (a missing one is
        // FileNotFoundError there); what fails here is reading it.
        SignalFileError::Read { .. } | SignalFileError::Write { .. } => PyOSError::new_err(e.to_string()),
        SignalFileError::Content { .. } => PyValueError::new_err(e.to_string()),
    })?;
    Ok((f64_bytes(py, sig.samples.iter().copied()), sig.rate, told))
}

/// The native module `clapper._clapper`.
#[pymodule]
fn _clapper(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("DEFAULT_THETA0_DEG", clapper_core::stroke::DEFAULT_THETA0_DEG)?;
    m.add("DEFAULT_RESTITUTION", clapper_core::stroke::DEFAULT_RESTITUTION)?;
    m.add(
        "DEFAULT_DOUBLE_MIN_RATIO",
        clapper_app::strikes::DEFAULT_DOUBLE_MIN_RATIO,
    )?;
    m.add("DEFAULT_MODES_RANGE_DB", clapper_app::measure::DEFAULT_MODES_RANGE_DB)?;
    m.add("CHART_QUANTITIES", CHART_QUANTITIES.map(|(name, _)| name).to_vec())?;
    m.add_function(wrap_pyfunction!(describe_bell, m)?)?;
    m.add_function(wrap_pyfunction!(simulate, m)?)?;
    m.add_function(wrap_pyfunction!(chart, m)?)?;
    m.add_function(wrap_pyfunction!(diagnose, m)?)?;
    m.add_function(wrap_pyfunction!(tower, m)?)?;
    m.add_function(wrap_pyfunction!(liftoff_formula, m)?)?;
    m.add_function(wrap_pyfunction!(liftoff_bell, m)?)?;
    m.add_function(wrap_pyfunction!(restitution, m)?)?;
    m.add_function(wrap_pyfunction!(modes, m)?)?;
    m.add_function(wrap_pyfunction!(strikes, m)?)?;
    m.add_function(wrap_pyfunction!(read_wav, m)?)?;
    m.add_function(wrap_pyfunction!(request_keys, m)?)?;
    Ok(())
}
