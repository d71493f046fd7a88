//! `clapper strikes`: strikes, strokes, double strikes and odd-struckness
//! from a recording of a ring; `clapper synth-ring`: a synthetic recording
//! of a ring with its truth beside it (the test data of docs/strikes.md).

use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};
use clap::Args;
use clapper_app::strikes::{
    choose_timing, learned_or_none, strike_options, Learning, StrikesReport, StrikingFigure, Timing, TimingAsked,
};
use clapper_io::signal_file::{read_recording, read_recording_chosen, write_wav, ChannelChoice};
use clapper_io::strike_file::{csv_text, lowndes};
use clapper_io::wav_stream::WavStream;
use clapper_signal::strikes::{BellVoice, InMemory, StrikeOptions, Windows};
use clapper_signal::tower::{
    major_scale, tower_recording, tuned_ring, Attack, DoubleStrikeSpec, Doublets, Method, Noise, PlainCourse, Room,
    Scale, Swing, TowerSpec, Voice,
};
use clapper_signal::Signal;

use crate::files::write_bytes;
use crate::measure::print_report;

/// Nominal frequencies (a newtype, so clap takes the list as one value).
#[derive(Clone, Debug)]
pub struct Nominals(pub Vec<f64>);

pub(crate) fn parse_list(s: &str) -> std::result::Result<Nominals, String> {
    s.split(',')
        .map(|v| match v.trim().parse::<f64>() {
            Ok(f) if f.is_finite() => Ok(f),
            Ok(_) => Err(format!("{v} is not a finite number")),
            Err(_) => Err(format!("'{v}' is not a number")),
        })
        .collect::<std::result::Result<Vec<f64>, String>>()
        .map(Nominals)
}

/// How strikes are timed, for --timing.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum TimingArg {
    /// Both tried on the first 80 s, the more even kept.
    Auto,
    /// As heard at the bells' assumed partials.
    Plain,
    /// Each bell learned from the recording's own clean strikes.
    Recording,
}

#[derive(Args, Debug)]
pub struct StrikesArgs {
    /// A recording of the ring (.wav: mono or stereo, 8 to 192 kHz).
    pub file: PathBuf,
    /// The bells' nominal frequencies (Hz), treble first: bell 1 is the
    /// first given. Not with --templates, which gives the bells' own sound.
    #[arg(long, value_name = "F1,F2,..", value_parser = parse_list, conflicts_with = "templates", allow_hyphen_values = true)]
    pub nominals: Option<Nominals>,
    /// A folder of recordings of each bell struck alone, named 1.wav,
    /// 2.wav, ... (treble first): each strike is timed against its bell's
    /// own sound. Instead of --nominals, --bells and --timing.
    #[arg(long, value_name = "DIR")]
    pub templates: Option<PathBuf>,
    /// With --nominals or --bells N, how each strike is timed: `plain` as
    /// heard at the bells' assumed partials (a tuned bell's); `recording`
    /// each bell's partials and strike's sound learned from the
    /// recording's own clean strikes (its first 80 s) and every strike
    /// timed at the start of its sound (issue 43: real bells do not follow
    /// a tuned bell's partial ratios, and their sound builds up after the
    /// blow); `auto` both tried on the first 80 s and the one whose strikes
    /// come more evenly kept. Handbells are timed plain. Reported under
    /// "timing", with both timings' figures.
    #[arg(long, value_enum, value_name = "HOW", conflicts_with = "templates")]
    pub timing: Option<TimingArg>,
    /// The same as --timing recording (kept so that old commands work).
    #[arg(long, conflicts_with_all = ["templates", "timing"])]
    pub self_calibrate: bool,
    /// Without nominals: the number of bells ringing (3 to 16); their
    /// nominals are learned from the recording itself and reported.
    #[arg(long, value_name = "N", conflicts_with_all = ["nominals", "templates"])]
    pub bells: Option<usize>,
    /// Handbells: with --nominals (each bell's strike note) or --bells N,
    /// listen for a handbell's partials (its strike note and twelfth)
    /// rather than a tower bell's (hum, prime, tierce, ...), which a
    /// handbell lacks and which may lie on other handbells' notes. Not
    /// with --self-calibrate (--timing recording), which learns each bell's
    /// partials from the recording as a tower bell's: --timing auto times
    /// handbells plain.
    #[arg(long, conflicts_with_all = ["templates", "self_calibrate"])]
    pub handbells: bool,
    /// A second strike at least this loud against the first (amplitude ratio) is a double strike.
    #[arg(long, default_value_t = clapper_app::strikes::DEFAULT_DOUBLE_MIN_RATIO, value_name = "RATIO")]
    pub double_min_ratio: f64,
    /// Which of a stereo recording's channels to hear: a channel's number
    /// (1 the first, the left), `mix` or `auto`. By default (`auto`) they are mixed, unless
    /// they disagree in time (one heard over 5 ms after the other: their
    /// mix would blur each strike), when the one whose strikes stand
    /// clearest over its noise (or the first) is heard alone and the report
    /// says which.
    #[arg(long, value_name = "N|mix|auto", value_parser = str::parse::<ChannelChoice>)]
    pub channel: Option<ChannelChoice>,
    /// Print JSON.
    #[arg(long)]
    pub json: bool,
    /// With the text report, the developer's detail of how the strikes were
    /// timed (the timings tried, each bell's lateness and where it was
    /// learned); the JSON holds it all.
    #[arg(long, conflicts_with = "json")]
    pub verbose: bool,
    /// Write every strike as CSV; `-` is standard output.
    #[arg(long, value_name = "FILE")]
    pub csv: Option<PathBuf>,
    /// Write the strikes in the Lowndes format that striking-analysis tools
    /// read; `-` is standard output.
    #[arg(long, value_name = "FILE")]
    pub lowndes: Option<PathBuf>,
    /// Draw the striking diagram (each bell's line through the places, leaning by its
    /// errors) over a spectrogram strip of the first seconds with the strikes marked
    /// (.svg or .png).
    #[arg(long, value_name = "FILE")]
    pub plot: Option<PathBuf>,
}

pub(crate) fn template_voices(dir: &std::path::Path) -> Result<Vec<BellVoice>> {
    Ok(templates(dir)?.0)
}

/// The bells' voices from a folder of recordings of each struck alone, and
/// the recordings (to learn each bell's lateness from).
pub(crate) fn templates(dir: &std::path::Path) -> Result<(Vec<BellVoice>, Vec<clapper_signal::Signal>)> {
    if !dir.is_dir() {
        bail!(
            "{}: no such folder (--templates names a folder of 1.wav, 2.wav, ..., each bell struck alone)",
            dir.display()
        );
    }
    let mut voices = vec![];
    let mut sigs = vec![];
    for bell in 1.. {
        let path = dir.join(format!("{bell}.wav"));
        if !path.exists() {
            break;
        }
        let sig = read_recording(&path)?;
        voices.push(BellVoice::from_template(&sig).with_context(|| path.display().to_string())?);
        sigs.push(sig);
    }
    if voices.is_empty() {
        bail!(
            "{}: no 1.wav (a recording of bell 1 struck alone) in the folder",
            dir.display()
        );
    }
    // A bell's recording past a gap in the numbers would be left out without a word.
    let next = voices.len() + 1;
    if let Some(later) = (next + 1..=64).find(|b| dir.join(format!("{b}.wav")).exists()) {
        bail!(
            "{}: {later}.wav but no {next}.wav; name the recordings 1.wav, 2.wav, ... without a gap, one per bell",
            dir.display()
        );
    }
    Ok((voices, sigs))
}

pub fn strikes(args: StrikesArgs) -> Result<()> {
    crate::files::claim_stdout(
        &[("--csv", args.csv.as_deref()), ("--lowndes", args.lowndes.as_deref())],
        args.json,
    )?;
    if (args.self_calibrate || args.timing.is_some()) && args.nominals.is_none() && args.bells.is_none() {
        bail!("--self-calibrate and --timing time the bells heard about their nominals: give --nominals F1,F2,.. (Hz, treble first) or --bells N to learn them");
    }
    if args.handbells && (args.self_calibrate || args.timing == Some(TimingArg::Recording)) {
        bail!(
            "--timing recording (--self-calibrate) learns each bell's partials as a tower bell's: not with --handbells"
        );
    }
    let kind = if args.handbells { Voice::Handbell } else { Voice::Tower };
    let channel = args.channel.unwrap_or_default();
    let mut learned = None;
    let (voices, recorded) = match (&args.nominals, &args.templates, args.bells) {
        (Some(_), _, _) => (vec![], vec![]),
        (None, Some(dir), _) => templates(dir)?,
        (None, None, Some(n)) => {
            // Learned from the whole recording, read at once.
            let (sig, _) = read_recording_chosen(&args.file, channel)?;
            match learned_or_none(&sig, n, kind).with_context(|| args.file.display().to_string())? {
                Learning::Learned(voices, l) => {
                    learned = Some(*l);
                    (voices, vec![])
                }
                // No strike to learn from: a report of none, as with
                // --nominals or --templates (tester18: exit 1 here only).
                Learning::Unheard(report) => return write_report(&args, &report, None),
            }
        }
        (None, None, None) => {
            bail!("say which bells to listen for: --nominals F1,F2,.. (Hz, treble first), --templates DIR or --bells N")
        }
    };
    if let Some(path) = &args.plot {
        clapper_plot::format_of(path)?;
    }
    let opts = strike_options(args.double_min_ratio)?;
    // About nominals: timed as --timing asks (auto by default), tried on
    // the recording's first window.
    let chosen = chosen_timing(&args, learned.as_ref(), kind, &opts)?;
    let voices = chosen.as_ref().map_or(voices, |c| c.voices.clone());
    // With templates, each strike is timed against its bell's template.
    let timing = match &chosen {
        Some(c) => c.timing(),
        None => Timing::Templates(&recorded),
    };
    // The recording is read in blocks and heard in windows (issue 46):
    // memory does not grow with its length. A layout not streamed is read whole.
    let mut strip = Signal {
        rate: 1.0,
        samples: vec![],
    };
    let keep_strip = args.plot.is_some().then_some(&mut strip);
    let mut report = heard_in_file(&args.file, channel, &voices, &opts, timing, keep_strip)?;
    if let Some(l) = learned {
        report.note_learned(l);
    }
    if let Some(c) = chosen {
        report.note_choice(c.choice);
    }
    write_report(&args, &report, Some((&strip, voices.as_slice())))
}

/// Write `report` as `args` ask: CSV, Lowndes, the plot (of `heard`: the
/// recording's first seconds and the voices listened for; none where no
/// bell was learned) and the report itself.
fn write_report(args: &StrikesArgs, report: &StrikesReport, heard: Option<(&Signal, &[BellVoice])>) -> Result<()> {
    let name = crate::files::title_name(&args.file);
    if let Some(path) = &args.csv {
        write_bytes(path, csv_text(&report.csv_rows()).map_err(anyhow::Error::msg)?)?;
    }
    if let Some(path) = &args.lowndes {
        let text = lowndes(&report.lowndes_blows(), &name, report.bells).map_err(anyhow::Error::msg)?;
        write_bytes(path, text)?;
    }
    match (&args.plot, heard) {
        (Some(path), Some((strip, voices))) => {
            let fig = StrikingFigure::new(report, strip, &name, voices)?;
            crate::files::write_atomically(path, |tmp| Ok(clapper_plot::striking_plot(tmp, &fig.plot())?))?;
        }
        (Some(path), None) => eprintln!("{}: not drawn: no bell learned to draw", path.display()),
        _ => {}
    }
    let title = args.file.display().to_string();
    print_report(report, args.json, || {
        if args.verbose {
            report.text_verbose(&title)
        } else {
            report.text(&title)
        }
    })
}

/// The strikes of the recording at `file` (its channels heard as
/// `channel` asks), heard through `voices` timed
/// by `timing`, streamed in windows where its layout allows (memory does
/// not grow with its length), else read whole; what reading it told (its
/// channels disagreeing in time) noted in the report.
fn heard_in_file(
    file: &Path,
    channel: ChannelChoice,
    voices: &[BellVoice],
    opts: &StrikeOptions,
    timing: Timing,
    strip: Option<&mut Signal>,
) -> Result<StrikesReport> {
    let windows = Windows::default();
    let (report, told) = match WavStream::open_chosen(file, channel)? {
        Some(mut s) => {
            let r = StrikesReport::streamed(&mut s, voices, opts, timing, &windows, strip);
            (r, s.warnings().to_vec())
        }
        None => {
            let (sig, told) = read_recording_chosen(file, channel)?;
            let r = StrikesReport::streamed(&mut InMemory::new(&sig), voices, opts, timing, &windows, strip);
            (r, told)
        }
    };
    let mut report = report.with_context(|| file.display().to_string())?;
    report.note_recording(&told);
    Ok(report)
}

/// About the nominals given, or with `--bells N` those `learned`, the
/// bells' voices and timing as `--timing` asks (`--self-calibrate`: the
/// recording's), tried on the recording's first window; none with templates.
fn chosen_timing(
    args: &StrikesArgs,
    learned: Option<&clapper_app::strikes::Learned>,
    kind: Voice,
    opts: &StrikeOptions,
) -> Result<Option<clapper_app::strikes::Chosen>> {
    let about: Vec<f64> = match (&args.nominals, learned) {
        (Some(n), _) => n.0.clone(),
        (None, Some(l)) => l.nominals.iter().map(|b| b.nominal_hz).collect(),
        _ => return Ok(None),
    };
    let asked = match (args.self_calibrate, args.timing) {
        (true, _) | (false, Some(TimingArg::Recording)) => TimingAsked::Recording,
        (false, Some(TimingArg::Plain)) => TimingAsked::Plain,
        (false, Some(TimingArg::Auto) | None) => TimingAsked::Auto,
    };
    // Plain timing and handbells read nothing of the recording here.
    let head = if asked == TimingAsked::Plain || kind == Voice::Handbell {
        Signal {
            rate: 1.0,
            samples: vec![],
        }
    } else {
        recording_head(&args.file, args.channel.unwrap_or_default(), Windows::default().whole_s)?
    };
    let chosen = choose_timing(&head, &about, kind, asked, opts).with_context(|| args.file.display().to_string())?;
    Ok(Some(chosen))
}

/// The first `seconds` of the recording at `path` (all of a shorter one),
/// its channels heard as `channel` asks.
fn recording_head(path: &std::path::Path, channel: ChannelChoice, seconds: f64) -> Result<Signal> {
    use clapper_signal::strikes::RecordingBlocks;
    match WavStream::open_chosen(path, channel)? {
        Some(mut s) => {
            let rate = s.rate();
            let want = ((seconds * rate) as usize).min(s.total());
            let mut samples = Vec::with_capacity(want);
            while samples.len() < want {
                let max = want - samples.len();
                if s.read(&mut samples, max)
                    .map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?
                    == 0
                {
                    break;
                }
            }
            Ok(Signal { rate, samples })
        }
        None => {
            let (mut sig, _) = read_recording_chosen(path, channel)?;
            sig.samples.truncate((seconds * sig.rate) as usize);
            Ok(sig)
        }
    }
}

#[derive(Args, Debug)]
pub struct SynthRingArgs {
    /// Where to write the recording (.wav, 16-bit); `-` is standard output.
    #[arg(long, value_name = "FILE")]
    pub out: PathBuf,
    /// Where to write the truth: every strike's bell, row, place, stroke and
    /// time (CSV); `-` is standard output.
    #[arg(long, value_name = "FILE")]
    pub truth: Option<PathBuf>,
    /// Bells in the ring (without --tuning: steps of 2, 2, 1, 2, 2, 2, 1
    /// semitones down from the treble, as before).
    #[arg(long, default_value_t = 8)]
    pub bells: usize,
    /// The treble's nominal (Hz).
    #[arg(long, default_value_t = 1400.0, value_name = "HZ")]
    pub treble_hz: f64,
    /// Tune the ring to a major or minor scale up from the tenor (the key
    /// note), the tenor's nominal --tenor-hz.
    #[arg(long, value_enum, value_name = "SCALE", conflicts_with = "treble_hz")]
    pub tuning: Option<TuningArg>,
    /// The tenor's nominal (Hz), with --tuning [default: 600] (250 Hz: a heavy ring).
    #[arg(long, value_name = "HZ", requires = "tuning", allow_hyphen_values = true)]
    pub tenor_hz: Option<f64>,
    /// Handbells: each a strike note and its twelfth, no hum, decays of a few seconds.
    #[arg(long)]
    pub handbells: bool,
    /// Rows rung (handstroke first).
    #[arg(long, default_value_t = 24)]
    pub rows: usize,
    /// Plain hunt after two rows of rounds (else rounds throughout).
    #[arg(long, conflicts_with = "method")]
    pub plain_hunt: bool,
    /// What the bells ring after two rows of rounds: a method's plain course
    /// over and over (Plain Bob on 4-12 bells; Grandsire and Stedman on 5-12,
    /// the tenor covering on an even number).
    #[arg(long, value_enum, value_name = "METHOD")]
    pub method: Option<MethodArg>,
    /// Time between successive bells (ms).
    #[arg(long, default_value_t = 220.0, value_name = "MS")]
    pub interval_ms: f64,
    /// Handstroke gap (intervals).
    #[arg(long, default_value_t = 1.0)]
    pub gap: f64,
    /// Striking errors: uniform within ± this (ms).
    #[arg(long, default_value_t = 15.0, value_name = "MS")]
    pub jitter_ms: f64,
    /// An odd-struck bell: BELL:MS (handstroke minus backstroke); repeatable.
    #[arg(long, value_name = "BELL:MS")]
    pub odd: Vec<String>,
    /// A double strike: BELL:ROW:DELAY_MS:RATIO; repeatable.
    #[arg(long, value_name = "B:R:MS:RATIO")]
    pub double: Vec<String>,
    /// Reverberation time of the room (s); 0 for none.
    #[arg(long, default_value_t = 0.0, value_name = "S")]
    pub rt60: f64,
    /// Signal-to-noise ratio (dB); omit for no noise.
    #[arg(long, value_name = "DB", allow_hyphen_values = true)]
    pub snr: Option<f64>,
    /// The noise heard at --snr: white, wind (gusts below 300 Hz) or
    /// traffic (rumble and passing vehicles below 800 Hz).
    #[arg(long, value_enum, default_value = "white")]
    pub noise: NoiseArg,
    /// Sample rate (Hz).
    #[arg(long, default_value_t = 22050.0)]
    pub rate: f64,
    /// Seed of the striking errors, voices, room and noise.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Doublets as real bells have them: each partial of each bell two
    /// components split by an amount drawn within LOW:HIGH (Hz, e.g. 0.1:3),
    /// fixed per bell; omit for every partial a 0.5 Hz doublet of equal halves.
    #[arg(long, value_name = "LOW_HZ:HIGH_HZ", allow_hyphen_values = true)]
    pub doublets: Option<String>,
    /// The lower component's share of each doublet's strength, drawn within
    /// LOW:HIGH (0 to 1); with --doublets.
    #[arg(
        long,
        default_value = "0.2:0.8",
        value_name = "LOW:HIGH",
        requires = "doublets",
        allow_hyphen_values = true
    )]
    pub doublet_shares: String,
    /// The bells' swing heard from below: the level rises by this much (dB)
    /// from a strike (mouth up) to mid-stroke (mouth down); real bells 6 to 15 dB.
    #[arg(long, default_value_t = 0.0, value_name = "DB", allow_hyphen_values = true)]
    pub swing_db: f64,
    /// The swing's Doppler shift: its peak in each stroke (% of the frequency; real bells up to about 1 %).
    #[arg(long, default_value_t = 0.0, value_name = "PCT", allow_hyphen_values = true)]
    pub doppler_pct: f64,
    /// The clapper's knock: a burst of noise at each strike, DB against the
    /// strike's loudest 5.8 ms (real tower bells about -24) falling 20 dB in
    /// MS milliseconds; omit for strikes that are pure partials.
    #[arg(long, value_name = "DB:MS", allow_hyphen_values = true)]
    pub attack: Option<String>,
}

/// A scale for --tuning.
#[derive(Clone, Copy, Debug, clap::ValueEnum)]
pub enum TuningArg {
    /// The major scale up from the tenor.
    Major,
    /// The natural minor scale up from the tenor.
    Minor,
}

/// A method for --method.
#[derive(Clone, Copy, Debug, clap::ValueEnum)]
pub enum MethodArg {
    /// Rounds throughout.
    Rounds,
    /// Plain hunt.
    PlainHunt,
    /// Plain Bob.
    PlainBob,
    /// Grandsire.
    Grandsire,
    /// Stedman.
    Stedman,
}

/// A kind of noise for --noise.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum NoiseArg {
    /// White noise.
    White,
    /// Wind.
    Wind,
    /// Traffic.
    Traffic,
}

fn fields(s: &str, n: usize, what: &str) -> Result<Vec<f64>> {
    let v: Vec<f64> = s
        .split(':')
        .map(|x| x.trim().parse::<f64>())
        .collect::<std::result::Result<_, _>>()
        .map_err(|_| anyhow::anyhow!("'{s}': {what}"))?;
    if v.len() != n {
        bail!("'{s}': {what}");
    }
    Ok(v)
}

pub fn synth_ring(args: SynthRingArgs) -> Result<()> {
    crate::files::claim_stdout(&[("--out", Some(&args.out)), ("--truth", args.truth.as_deref())], false)?;
    if !(1..=16).contains(&args.bells) {
        bail!("{} bells: 1 to 16", args.bells);
    }
    // What strikes would refuse to read is not written.
    let rates = clapper_app::strikes::RECORDING_RATES_HZ;
    if !rates.contains(&args.rate) {
        bail!(
            "--rate {} Hz: a sample rate from {} to {} Hz (what clapper strikes reads)",
            args.rate,
            rates.start(),
            rates.end()
        );
    }
    if args.noise != NoiseArg::White && args.snr.is_none() {
        bail!("--noise: say how loud with --snr DB");
    }
    let bells = ring_of(&args)?;
    let spec = tower_spec_of(&args, bells.clone())?;
    let (sig, truth) = tower_recording(&spec)?;
    crate::files::write_atomically(&args.out, |tmp| {
        write_wav(tmp, &sig, 0.9).with_context(|| args.out.display().to_string())
    })?;
    if let Some(path) = &args.truth {
        write_bytes(path, csv_text(&truth_rows(&truth)).map_err(anyhow::Error::msg)?)?;
    }
    let nominals: Vec<String> = bells.iter().map(|b| format!("{:.1}", b.nominal_hz)).collect();
    crate::say!(
        "wrote {} ({:.1} s, {} strikes of {} bells; synthetic). Listen for them with:\n  clapper strikes {} --nominals {}{}",
        args.out.display(),
        sig.duration(),
        truth.len(),
        args.bells,
        args.out.display(),
        nominals.join(","),
        if args.handbells { " --handbells" } else { "" }
    );
    Ok(())
}

/// synth-ring's bells: tuned as --tuning or --treble-hz asks, each
/// --odd bell's odd-struckness set.
fn ring_of(args: &SynthRingArgs) -> Result<Vec<clapper_signal::tower::RingBell>> {
    let tenor_hz = args.tenor_hz.unwrap_or(600.0);
    let ring = match args.tuning {
        None => major_scale(args.bells, args.treble_hz),
        Some(_) if !(tenor_hz.is_finite() && tenor_hz >= 20.0 && tenor_hz < 0.45 * args.rate) => {
            bail!("--tenor-hz {tenor_hz}: from 20 Hz to under 0.45 of the sample rate")
        }
        Some(TuningArg::Major) => tuned_ring(args.bells, tenor_hz, Scale::Major),
        Some(TuningArg::Minor) => tuned_ring(args.bells, tenor_hz, Scale::Minor),
    };
    let Some(mut bells) = ring else {
        bail!("{} bells: 1 to 16", args.bells);
    };
    for o in &args.odd {
        let v = fields(o, 2, "--odd is BELL:MS")?;
        let b = v[0] as usize;
        if !(1..=args.bells).contains(&b) {
            bail!("--odd {o}: no bell {b}");
        }
        bells[b - 1].odd_struck_ms = v[1];
    }
    Ok(bells)
}

/// The ringing and recording synth-ring's options describe, of `bells`.
fn tower_spec_of(args: &SynthRingArgs, bells: Vec<clapper_signal::tower::RingBell>) -> Result<TowerSpec> {
    check_rt60(args.rt60)?;
    let doubles = args
        .double
        .iter()
        .map(|d| {
            let v = fields(d, 4, "--double is BELL:ROW:DELAY_MS:RATIO")?;
            check_double(d, &v, args)?;
            Ok(DoubleStrikeSpec {
                bell: v[0] as usize,
                row: v[1] as usize,
                delay_ms: v[2],
                amplitude_ratio: v[3],
            })
        })
        .collect::<Result<Vec<_>>>()?;
    Ok(TowerSpec {
        rate: args.rate,
        rows: args.rows,
        interval: args.interval_ms * 1e-3,
        handstroke_gap: args.gap,
        jitter: args.jitter_ms * 1e-3,
        seed: args.seed,
        doubles,
        tail: 3.0,
        method: method_of(args),
        attack: match &args.attack {
            None => None,
            Some(a) => {
                let v = fields(a, 2, "--attack is DB:MS, e.g. -24:30")?;
                Some(Attack {
                    level_db: v[0],
                    length_ms: v[1],
                })
            }
        },
        voice: if args.handbells { Voice::Handbell } else { Voice::Tower },
        noise: match args.noise {
            NoiseArg::White => Noise::White,
            NoiseArg::Wind => Noise::Wind,
            NoiseArg::Traffic => Noise::Traffic,
        },
        room: (args.rt60 > 0.0).then_some(Room::chamber(args.rt60)),
        snr_db: args.snr,
        doublets: doublets_of(args)?,
        swing: (args.swing_db != 0.0 || args.doppler_pct != 0.0).then_some(Swing {
            level_db: args.swing_db,
            doppler: args.doppler_pct * 1e-2,
        }),
        ..TowerSpec::new(bells)
    })
}

/// Refuse a --double `d` (its fields `v`) that is not a strike of the
/// ring, in the option's words (the library's refusal shows its struct).
fn check_double(d: &str, v: &[f64], args: &SynthRingArgs) -> Result<()> {
    let (bell, row, delay_ms, ratio) = (v[0], v[1], v[2], v[3]);
    if !(bell.fract() == 0.0 && bell >= 1.0 && bell <= args.bells as f64) {
        bail!("--double {d}: no bell {bell}: bells are 1 to {}", args.bells);
    }
    if !(row.fract() == 0.0 && row >= 0.0 && row < args.rows as f64) {
        bail!(
            "--double {d}: no row {row}: rows are 0 to {}",
            args.rows.saturating_sub(1)
        );
    }
    if !(delay_ms > 0.0 && delay_ms < 1000.0) {
        bail!("--double {d}: delay {delay_ms} ms is out of range: over 0 and under 1000 ms");
    }
    if !(ratio > 0.0 && ratio <= 1.0) {
        bail!("--double {d}: amplitude ratio {ratio} is out of range: over 0 and at most 1");
    }
    Ok(())
}

/// --rt60 (s) in the option's words: 0 (no room) to 10 s.
fn check_rt60(rt60: f64) -> Result<()> {
    if !(0.0..=10.0).contains(&rt60) {
        bail!("--rt60 {rt60} s is out of range: 0 (no room) to 10 s");
    }
    Ok(())
}

/// The method of --method (or --plain-hunt).
fn method_of(args: &SynthRingArgs) -> Method {
    match args.method {
        _ if args.plain_hunt => Method::PlainHunt,
        None | Some(MethodArg::Rounds) => Method::Rounds,
        Some(MethodArg::PlainHunt) => Method::PlainHunt,
        Some(MethodArg::PlainBob) => Method::Course(PlainCourse::PlainBob),
        Some(MethodArg::Grandsire) => Method::Course(PlainCourse::Grandsire),
        Some(MethodArg::Stedman) => Method::Course(PlainCourse::Stedman),
    }
}

/// The doublets of --doublets and --doublet-shares.
fn doublets_of(args: &SynthRingArgs) -> Result<Option<Doublets>> {
    let Some(d) = &args.doublets else {
        return Ok(None);
    };
    let split = fields(d, 2, "--doublets is LOW_HZ:HIGH_HZ, e.g. 0.1:3")?;
    let share = fields(&args.doublet_shares, 2, "--doublet-shares is LOW:HIGH, e.g. 0.2:0.8")?;
    Ok(Some(Doublets {
        split_hz: (split[0], split[1]),
        share: (share[0], share[1]),
    }))
}

/// The truth CSV's rows: a header, then one row a strike.
fn truth_rows(truth: &[clapper_signal::tower::TrueStrike]) -> Vec<[String; 8]> {
    let mut rows = vec![[
        "bell",
        "row",
        "place",
        "stroke",
        "t_s",
        "ideal_t_s",
        "double_delay_ms",
        "double_amplitude_ratio",
    ]
    .map(String::from)];
    for s in truth {
        rows.push([
            s.bell.to_string(),
            s.row.to_string(),
            s.place.to_string(),
            if s.hand { "hand" } else { "back" }.to_string(),
            format!("{:.6}", s.t),
            format!("{:.6}", s.ideal_t),
            s.double.map_or(String::new(), |d| format!("{:.1}", d.0 * 1e3)),
            s.double.map_or(String::new(), |d| format!("{:.3}", d.1)),
        ]);
    }
    rows
}
