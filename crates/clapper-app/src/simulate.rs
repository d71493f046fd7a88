//! Simulate strokes of one bell: the request behind `clapper simulate`
//! and `POST /api/simulate`, and its report.

use std::fmt::Write as _;

use clapper_core::prelude::*;
use clapper_core::ringing::odd_struck_of;
use clapper_core::stroke::Sample;
use clapper_io::bell_file::{BellSource, LoadedBell};
use clapper_io::report::{BellReport, SimulationReport, SimulationSettings};
use serde::{Deserialize, Serialize};

use crate::AppError;

/// Trace sampling interval (s) for plots and trace files: fine enough to
/// show each bounce of the clapper (flights of a few ms), coarse enough
/// for a small file.
pub const TRACE_INTERVAL_S: f64 = 5e-4;
pub use crate::stroke_options::{contact_words, DEFAULT_RESTITUTION, DEFAULT_THETA0_DEG};
/// Default number of strokes: a handstroke and a backstroke.
pub const DEFAULT_STROKES: usize = 2;
/// Most strokes one request may ask for; a free-protocol history longer
/// than this has long since decayed.
pub const MAX_STROKES: usize = 10_000;

/// The bells of the paper's Table 1.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum Preset {
    /// The laboratory bell.
    Lab,
    /// The old tenor of Great St Mary's, Cambridge.
    #[serde(alias = "gsm_tenor")]
    GsmTenor,
}

impl Preset {
    /// The bell, named.
    pub fn loaded(self) -> LoadedBell {
        let (name, bell) = match self {
            Preset::Lab => ("lab bell", Bell::lab()),
            Preset::GsmTenor => ("GSM tenor", Bell::gsm_tenor()),
        };
        LoadedBell::new(name.into(), bell, BellSource::MassProperties)
    }

    /// The name on the command line and in JSON.
    pub fn name(self) -> &'static str {
        match self {
            Preset::Lab => "lab",
            Preset::GsmTenor => "gsm-tenor",
        }
    }
}

fn default_strokes() -> usize {
    DEFAULT_STROKES
}

crate::stroke_options::with_stroke_options! {
    /// The options of `clapper simulate`, as data. In JSON the keys are the
    /// long options in snake case (`chart_point`, `phi_max`; the kebab-case
    /// spellings are accepted too) and the bell file is given by its text:
    ///
    /// ```json
    /// {"preset": "lab", "style": "wrong", "theta0": 171, "restitution": 0.2}
    /// {"chart_point": [0.45, 1.68], "contact": "penalty", "stiffness": 1e6}
    /// {"bell": "name = \"Tenor\"\nbell_period_s = 2.1\nclapper_period_s = 1.6\n..."}
    /// ```
    #[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
    #[serde(deny_unknown_fields)]
    pub struct SimulateRequest {
        /// A bell of Table 1. At most one of `preset`, `bell`, `chart_point`;
        /// none means the lab bell.
        #[serde(default)]
        pub preset: Option<Preset>,
        /// The text of a bell file (TOML): mass properties or tower measurements.
        #[serde(default)]
        pub bell: Option<String>,
        /// A bell built as the paper builds chart points: [r/L_c, L_b/L_c].
        #[serde(default, alias = "chart-point")]
        pub chart_point: Option<[f64; 2]>,
        /// Right or wrong.
        #[serde(default)]
        pub style: Style,
        /// Override of the bell's contact angle φ_max (deg, 0 < φ_max < 90).
        #[serde(default, alias = "phi-max")]
        pub phi_max: Option<f64>,
        /// Number of strokes (handstroke, backstroke, ...).
        #[serde(default = "default_strokes")]
        pub strokes: usize,
        /// How one stroke leads to the next.
        #[serde(default)]
        pub protocol: Protocol,
    }
}

/// A chart coordinate for a bell's name: at most three decimals, trailing
/// zeros dropped (`0.45`, `0.273`): a point a page clicked carries the
/// grid's sixteen digits, which only crowd a title or caption.
fn chart_coordinate(v: f64) -> String {
    let s = format!("{v:.3}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".into()
    } else {
        s.into()
    }
}

impl SimulateRequest {
    /// The bell the request names, with any φ_max override applied.
    /// `file` (a bell file already read by the caller) takes the place of
    /// the request's own bell source.
    pub fn bell(&self, file: Option<LoadedBell>) -> Result<LoadedBell, AppError> {
        let given = [
            self.preset.is_some(),
            self.bell.is_some(),
            self.chart_point.is_some(),
            file.is_some(),
        ];
        if given.iter().filter(|g| **g).count() > 1 {
            return Err(AppError::Request(
                "give at most one bell: preset, bell (a bell file's text) or chart_point".into(),
            ));
        }
        let mut loaded = match (file, &self.bell, self.chart_point, self.preset) {
            (Some(f), ..) => f,
            (_, Some(text), ..) => clapper_io::parse_bell(text, "bell")?,
            (_, _, Some([x, y]), _) if !in_tested_domain(x, y) => {
                let ([x0, x1], [y0, y1]) = TESTED_CHART_DOMAIN;
                return Err(AppError::Request(format!(
                    "chart point ({}, {}) is outside the domain clapper is tested over: r/L_c from {x0} to {x1}, \
                     L_b/L_c from {y0} to {y1} (a bell's own are near -0.3 to 0.7 and 0.5 to 2.5)",
                    chart_coordinate(x),
                    chart_coordinate(y)
                )));
            }
            (_, _, Some([x, y]), _) => LoadedBell::new(
                format!("chart point ({}, {})", chart_coordinate(x), chart_coordinate(y)),
                ChartConstruction::default().bell(x, y)?,
                BellSource::MassProperties,
            ),
            (_, _, _, preset) => preset.unwrap_or(Preset::Lab).loaded(),
        };
        if let Some(deg) = self.phi_max {
            // φ_max sets both sides.
            loaded.bell.hanging.phi_max_skew = 0.0;
            loaded.bell = loaded.bell.with_phi_max(deg.to_radians())?;
        }
        loaded.bell = self.stroke_options().hanging.apply(loaded.bell)?;
        Ok(loaded)
    }

    /// The simulation settings for `bell`, validated: R and R2 the
    /// request's, else the bell file's, else R's default and R2 = R.
    pub fn config_for(&self, bell: &LoadedBell) -> Result<SimConfig, AppError> {
        let mut opts = self.stroke_options();
        opts.restitution = opts.restitution.or(bell.restitution);
        opts.restitution_later = opts.restitution_later.or(bell.restitution_later);
        let cfg = opts.config()?;
        cfg.validate()?;
        if self.strokes == 0 || self.strokes > MAX_STROKES {
            return Err(AppError::Request(format!(
                "strokes {} is out of range: 1 to {MAX_STROKES}",
                self.strokes
            )));
        }
        Ok(cfg)
    }
}

/// The chart points a single bell may be asked at (r/L_c, L_b/L_c): the
/// domain the property tests cover (crates/clapper-core/tests/properties.rs),
/// a wide margin around any real bell's. Far outside it a bell is no bell
/// (at r/L_c = -5 the clapper hangs five of its lengths above the bell's
/// axis) and ringing it up had no end.
pub const TESTED_CHART_DOMAIN: ([f64; 2], [f64; 2]) = ([-1.0, 2.0], [0.2, 5.0]);

fn in_tested_domain(x: f64, y: f64) -> bool {
    let ([x0, x1], [y0, y1]) = TESTED_CHART_DOMAIN;
    (x0..=x1).contains(&x) && (y0..=y1).contains(&y)
}

/// A simulation's answer: the report (what `clapper simulate --json`
/// prints), and the trace when one was asked for.
#[derive(Clone, Debug)]
pub struct Simulation {
    /// The report.
    pub report: SimulationReport,
    /// Samples every [`TRACE_INTERVAL_S`] and at every jump; empty unless
    /// a trace was asked for.
    pub samples: Vec<Sample>,
    /// A one-line title for plots of this run.
    pub title: String,
    /// φ_max of the bell simulated (deg).
    pub phi_max_deg: f64,
    /// Times (s) at which the strokes after the first begin.
    pub stroke_starts: Vec<f64>,
    /// Warnings about the bell (unusual but allowed values).
    pub warnings: Vec<String>,
}

impl Simulation {
    /// The paper's Fig 9 for this run, as SVG text (needs a trace).
    pub fn plot_svg(&self) -> Result<String, AppError> {
        Ok(clapper_plot::stroke_plot_svg(&self.samples, &self.plot())?)
    }

    /// What the stroke plot shows besides the trace.
    pub fn plot(&self) -> clapper_plot::StrokePlot<'_> {
        clapper_plot::StrokePlot {
            title: &self.title,
            phi_max_deg: self.phi_max_deg,
            stroke_starts: self.stroke_starts.clone(),
        }
    }
}

/// Run the request. `file` is a bell file the caller has read (the
/// command line's `--bell FILE`); `max_strokes` lowers the stroke limit
/// (a server's per-request bound); `trace` records samples for plots.
pub fn simulate(
    req: &SimulateRequest,
    file: Option<LoadedBell>,
    max_strokes: Option<usize>,
) -> Result<Simulation, AppError> {
    run(req, file, max_strokes, &mut ())
}

/// [`simulate`], recording a trace for plots and trace files.
pub fn simulate_traced(
    req: &SimulateRequest,
    file: Option<LoadedBell>,
    max_strokes: Option<usize>,
) -> Result<Simulation, AppError> {
    let mut recorder = TraceRecorder::new(TRACE_INTERVAL_S);
    let mut sim = run(req, file, max_strokes, &mut recorder)?;
    sim.samples = recorder.samples;
    Ok(sim)
}

/// [`simulate`], handing each sample of the trace to `sink` as it is
/// computed (and keeping none): a trace file of any number of strokes in
/// constant memory.
pub fn simulate_streamed(
    req: &SimulateRequest,
    file: Option<LoadedBell>,
    sink: impl FnMut(&Sample),
) -> Result<Simulation, AppError> {
    run(
        req,
        file,
        None,
        &mut clapper_core::stroke::TraceSampler::new(TRACE_INTERVAL_S, sink),
    )
}

fn run<O: Observer>(
    req: &SimulateRequest,
    file: Option<LoadedBell>,
    max_strokes: Option<usize>,
    observer: &mut O,
) -> Result<Simulation, AppError> {
    let loaded = req.bell(file)?;
    let cfg = req.config_for(&loaded)?;
    if let Some(m) = max_strokes {
        if req.strokes > m {
            return Err(AppError::Request(format!(
                "strokes {} is more than this server allows ({m})",
                req.strokes
            )));
        }
    }
    let (style, protocol) = (req.style, req.protocol);
    let bell = &loaded.bell;
    let ringing = ring(bell, &cfg, style, protocol, req.strokes, observer)?;
    let title = format!(
        "{}: ringing {} from {:.0} deg, R = {}, {} contact  (r/L_c = {:.3}, L_b/L_c = {:.3})",
        loaded.name,
        style.name(),
        req.theta0,
        cfg.restitution,
        contact_words(&cfg),
        bell.r_over_lc(),
        bell.lb_over_lc()
    );
    // The verdict from steady ringing: the handstroke and the backstroke
    // after it under the restart protocol, each on its own clock, whatever
    // the protocol and number of strokes asked (as the chart and diagnose
    // judge it; a bell and its mirror image get one verdict).
    let pair = clapper_core::ringing::odd_struck(bell, &cfg, style)?;
    // Odd-struckness of the first two strokes (so exactly 0 for a
    // symmetric bell), only between two strokes that keep one style.
    let odd = match (protocol, &ringing.strokes[..]) {
        (_, [] | [_]) => Err("one stroke only".to_string()),
        (Protocol::Restart, _) => odd_struck_of(&pair.hand, &pair.back).map_err(|e| e.to_string()),
        (Protocol::Free, [hand, back, ..]) => odd_struck_of(hand, back).map_err(|e| e.to_string()),
    };
    let mut report = SimulationReport::new(
        BellReport::new(&loaded.name, bell, &loaded.source),
        SimulationSettings::new(&cfg, protocol, req.strokes),
        &ringing,
        pair.sustained(),
        odd,
    );
    if !pair.sustained() {
        // What the bell does sustain, where the style asked is not.
        let other = style.opposite();
        let sustained = clapper_core::ringing::sustains(bell, &cfg, other)?;
        report.sustains_instead = Some(if sustained { other.name() } else { "neither" }.into());
    }
    Ok(Simulation {
        report,
        samples: vec![],
        title,
        phi_max_deg: bell.phi_max.to_degrees(),
        stroke_starts: ringing.strokes.iter().skip(1).map(|s| s.start.t).collect(),
        warnings: bell.warnings().iter().map(ToString::to_string).collect(),
    })
}

fn opt(v: Option<f64>, digits: usize, unit: &str) -> String {
    match v {
        Some(x) => format!("{x:.digits$} {unit}"),
        None => "none".into(),
    }
}

/// The short readable summary `clapper simulate` prints by default.
pub fn summary(r: &SimulationReport) -> String {
    let mut o = String::new();
    bell_text(&mut o, &r.bell);
    settings_text(&mut o, r);
    for st in &r.strokes {
        stroke_text(&mut o, st);
    }
    verdict_text(&mut o, r);
    o
}

/// The summary's lines on the bell: its name, chart position, lengths and
/// periods, what was assumed, and how it hangs.
fn bell_text(o: &mut String, b: &BellReport) {
    let _ = writeln!(o, "bell: {}", b.name);
    let _ = writeln!(
        o,
        "  chart position   r/L_c = {:.3}, L_b/L_c = {:.3}",
        b.r_over_lc, b.lb_over_lc
    );
    let _ = writeln!(
        o,
        "  pendulum lengths L_b = {:.3} m, L_c = {:.3} m; periods T_b = {:.3} s, T_c = {:.3} s; phi_max = {:.1} deg",
        b.lb_m, b.lc_m, b.tb_s, b.tc_s, b.phi_max_deg
    );
    if !b.assumed.is_empty() {
        let _ = writeln!(o, "  assumed (not measured): {}", b.assumed.join(", "));
    }
    let mut hanging = Vec::new();
    if let Some(d) = b.pivot_offset_m {
        hanging.push(format!("pivot offset {:+.1} mm", d * 1e3));
    }
    if let (Some(h), Some(k)) = (b.phi_max_hand_deg, b.phi_max_back_deg) {
        hanging.push(format!("phi_max hand/back {h:.2}/{k:.2} deg"));
    }
    if let Some(f) = &b.friction {
        for (v, what) in [
            (f.bell_damping, "bell damping {} N m s/rad"),
            (f.bell_friction, "bell friction {} N m"),
            (f.clapper_damping, "clapper damping {} N m s/rad"),
            (f.clapper_friction, "clapper friction {} N m"),
        ] {
            if v != 0.0 {
                hanging.push(what.replace("{}", &format!("{v:.4}")));
            }
        }
    }
    if !hanging.is_empty() {
        let _ = writeln!(o, "  hanging          {}", hanging.join(", "));
    }
}

/// The summary's settings line.
fn settings_text(o: &mut String, r: &SimulationReport) {
    let s = &r.settings;
    let stiffness = s
        .stiffness_n_m_per_rad
        .map(|k| format!(" (k = {k:e} N m/rad)"))
        .unwrap_or_default();
    let mut later = s.restitution_later.map(|r2| format!(", R2 = {r2}")).unwrap_or_default();
    if !s.strike_amplitude.is_rate() {
        later += &format!(", A by {}", s.strike_amplitude);
    }
    let _ = writeln!(
        o,
        "settings: ringing {} from theta0 = {:.1} deg, R = {}{later}, {} contact{stiffness}, {} protocol",
        r.style, s.theta0_deg, s.restitution, s.contact, s.protocol
    );
}

/// The summary's paragraph on one stroke.
fn stroke_text(o: &mut String, st: &clapper_io::report::StrokeReport) {
    let kind = if st.number % 2 == 1 { "handstroke" } else { "backstroke" };
    let _ = writeln!(
        o,
        "\nstroke {} ({kind}, {} style, from {:+.1} deg)",
        st.number, st.style, st.start_theta_deg
    );
    let bounce = if st.liftoff_kind == Some("bounce") {
        " (off a bounce: it never rested)"
    } else {
        ""
    };
    let _ = writeln!(o, "  lift-off         {}{bounce}", opt(st.liftoff_theta_deg, 2, "deg"));
    match &st.first_strike {
        Some(f) => {
            let _ = writeln!(
                o,
                "  first strike     {:.2} deg, {:.3} s into the stroke, clapper rate {:.3} rad/s",
                f.theta_deg, f.t_s, f.phidot_rad_s
            );
            second_impact_text(o, st);
        }
        None => {
            let _ = writeln!(o, "  first strike     none: the clapper never struck the other side");
        }
    }
    let _ = writeln!(
        o,
        "  end              {:.2} deg after {:.3} s ({}), clapper {} on side {:+}; next stroke starts {}",
        st.end_theta_deg, st.duration_s, st.end_reason, st.end_clapper, st.end_side, st.continues_as
    );
}

/// A struck stroke's lines on its second impact and its bouncing.
fn second_impact_text(o: &mut String, st: &clapper_io::report::StrokeReport) {
    match (st.second_strike_delay_ms, st.amplitude_ratio) {
        (Some(dt), Some(a)) => {
            let _ = writeln!(
                o,
                "  second impact    {dt:.1} ms later, amplitude ratio {a:.3}; double strike index D = {:.2}",
                st.double_strike_index.unwrap_or(0.0)
            );
        }
        _ => {
            let why = st.no_second_impact.unwrap_or("none");
            let _ = writeln!(o, "  second impact    none ({why}): no double strike index");
        }
    }
    let _ = writeln!(
        o,
        "  bouncing         {} impacts; clapper at rest {}",
        st.impacts.len(),
        match st.bounce_time_s {
            Some(t) => format!("{t:.3} s after the first strike"),
            None => "only after the stroke ended".into(),
        }
    );
}

/// The summary's verdict and odd-struckness.
fn verdict_text(o: &mut String, r: &SimulationReport) {
    // The verdict is steady ringing's; under the free protocol the later
    // strokes decay and may change style, which each stroke shows.
    let basis = match r.settings.protocol {
        Protocol::Restart => "handstroke and backstroke, restart protocol",
        Protocol::Free => {
            "steady ringing, a handstroke and a backstroke each from theta0; free protocol: later strokes decay, see each stroke's style"
        }
    };
    let _ = writeln!(
        o,
        "\nverdict: the bell {} ringing {} ({basis})",
        if r.sustained { "sustains" } else { "does not sustain" },
        r.style
    );
    match r.sustains_instead.as_deref() {
        Some("neither") => {
            let _ = writeln!(o, "  it sustains neither style steadily");
        }
        Some(other) => {
            let _ = writeln!(o, "  it sustains ringing {other} instead");
        }
        None => {}
    }
    if let Some(odd) = r.odd_struck_ms {
        let _ = writeln!(
            o,
            "odd-struck: {} (bottom dead centre to strike, handstroke minus backstroke; {})",
            odd_struck_ms_text(odd),
            which_stroke_late(odd)
        );
    } else if let Some(why) = r.odd_struck_undefined.as_deref().filter(|_| r.strokes.len() > 1) {
        let _ = writeln!(o, "odd-struck: not defined ({why}: it compares strokes of one style)");
    }
}

/// Below this (ms) an odd-struckness prints as 0.0 at one decimal: half
/// the printed step, so the words never contradict the figure.
const EVEN_MS: f64 = 0.05;

/// An odd-struckness (ms, handstroke minus backstroke) at one decimal,
/// signed, and unsigned `0.0 ms` when it rounds to zero (never `-0.0`).
pub fn odd_struck_ms_text(ms: f64) -> String {
    if ms.abs() < EVEN_MS {
        "0.0 ms".into()
    } else {
        format!("{ms:+.1} ms")
    }
}

/// Which stroke an odd-struckness (ms, handstroke minus backstroke) makes
/// late, in words; "evenly struck" when it prints as 0.0 ms (a symmetric
/// bell gives ±1e-12 ms by rounding, which is no lateness).
pub fn which_stroke_late(ms: f64) -> &'static str {
    if ms >= EVEN_MS {
        "handstroke late"
    } else if ms <= -EVEN_MS {
        "backstroke late"
    } else {
        "evenly struck"
    }
}
