//! `clapper`: the command line of clapper.

/// `println!` for a command's summary: to standard output, or to standard
/// error when an output file is `-` and standard output carries its bytes
/// (`clapper strikes rec.wav --csv - | ...`; see [`files::summary`]).
#[macro_export]
macro_rules! say {
    ($($arg:tt)*) => {
        $crate::files::summary(format_args!("{}\n", format_args!($($arg)*)))
    };
}

/// `print!` likewise.
#[macro_export]
macro_rules! say_text {
    ($($arg:tt)*) => {
        $crate::files::summary(format_args!($($arg)*))
    };
}

mod animate;
mod chart;
mod design_clapper;
mod diagnose;
mod figures;
mod files;
mod goes_up;
mod listening;
mod measure;
mod progress;
mod ring;
mod ringing_log;
mod sample_data;
mod serve;
mod simulate;
mod sound;
mod strikes;
mod sweep_file;
mod tower;
mod words;

use clap::{CommandFactory, FromArgMatches, Parser, Subcommand};

/// Dynamics of church bells rung full circle: a bell and its clapper as
/// coupled pendulums, after Woodhouse, Swallowe, Bumpus & Smith (2012).
#[derive(Parser, Debug)]
#[command(name = "clapper", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Simulate strokes of one bell and report strikes, lift-off, bounces and
    /// whether the style is sustained.
    Simulate(simulate::SimulateArgs),
    /// Ring a bell up from rest, swing by swing: does it go up right or
    /// wrong, and at what amplitude does it turn?
    RingUp(ring::RingArgs),
    /// Ring a bell down from the stay, swing by swing.
    RingDown(ring::RingArgs),
    /// A clapper from its shaft, ball and flight: m, b, I_c, L_c, T_c, its
    /// place on the chart, and the flight or ball that gives a wanted T_c.
    DesignClapper(design_clapper::DesignArgs),
    /// Lift-off angles in closed form: (15), (16) for r = 0, or exactly for
    /// any bell released from rest.
    Liftoff(simulate::LiftoffArgs),
    /// A clapping chart: sweep the plane of (r/L_c, L_b/L_c) and show where
    /// a bell rings right or wrong and how it strikes.
    Chart(chart::ChartArgs),
    /// Join the shards of a sweep (`chart --shard I/N`) into one CSV, the
    /// same bytes as one run of the whole sweep; then remove the shards'
    /// .shard.json files (--keep-shard-json keeps them).
    Merge(chart::MergeArgs),
    /// Reproduce the paper's figures 7, 9-12 and 14-16 into a folder.
    Figures(figures::FiguresArgs),
    /// Diagnose a bell or a ring for the bell-hanger: how it rings, its
    /// margins, what to change, loads on the frame.
    Diagnose(diagnose::DiagnoseArgs),
    /// The coefficient of restitution from velocity jumps or an accelerometer
    /// recording of clapper drops (Section 3.2, Fig 8).
    Restitution(measure::RestitutionArgs),
    /// Contacts, bounces, rest and lift-off from a contact-detector recording (Figs 2, 5).
    Contacts(measure::ContactsArgs),
    /// A spectrogram of a recording (Fig 3).
    Spectrogram(measure::SpectrogramArgs),
    /// The level of one frequency against time (Fig 4).
    Decay(measure::DecayArgs),
    /// The partials of a single strike: frequency, Q factor, level, doublets.
    Modes(measure::ModesArgs),
    /// Energy into vibration at an impact (Section 3.3): K, lambda, R, the
    /// shortest clean pulse; and choosing an impulse hammer.
    Impulse(measure::ImpulseArgs),
    /// Strikes heard in a recording of a ring: each bell's strikes, hand and
    /// back, double strikes, place errors and odd-struckness (docs/strikes.md).
    ///
    /// A recording with no strikes heard (silent, or no bell in it) is a
    /// result, not a failure: the report says so, with 0 strikes, and the
    /// exit status is 0 with --nominals, --templates and --bells alike.
    Strikes(strikes::StrikesArgs),
    /// A synthetic recording of a ring ringing rounds or plain hunt, with its
    /// truth beside it: striking errors, odd-struck bells, double strikes, a room, noise.
    SynthRing(strikes::SynthRingArgs),
    /// The sound of the bell rung full circle (or chimed), by modal synthesis
    /// driven by the simulation.
    Synth(sound::SynthArgs),
    /// The bell and its clapper drawn to scale and animated: an SVG, a GIF,
    /// or an HTML page playing the synthesised sound in step; a ring in rounds
    /// with --ring.
    Animate(animate::AnimateArgs),
    /// A bell's accelerometer log (belfry-sleuth or CSV) read into swings,
    /// strikes, odd-struckness and phases; beside the model with --bell.
    RingingLog(ringing_log::RingingLogArgs),
    /// A synthetic accelerometer log of a bell raised, rung and lowered,
    /// with its truth, for testing.
    SynthLog(ringing_log::SynthLogArgs),
    /// The double-strike listening test (Section 4.3): make stimuli and
    /// answer sheets, or analyse the answers.
    ListeningTest(listening::ListeningArgs),
    /// Write the synthetic sample recordings that README's measurement
    /// commands read (examples/data): a strike, a modes file, a contact
    /// detector, clapper drops, a ring in a tower, with their truth.
    SampleData(sample_data::SampleDataArgs),
    /// A ring rung through a touch in its tower: the forces of all its bells
    /// on the frame, their spectrum, the tower's sway and resonance, and
    /// which bells to turn (docs/tower.md).
    Tower(tower::TowerArgs),
    /// The web application: chart explorer, diagnosis and listening test in
    /// a browser, with a JSON API, on a local port.
    Serve(serve::ServeArgs),
}

/// Whether `e` (or one of its causes) is a write into a closed pipe.
fn is_broken_pipe(e: &anyhow::Error) -> bool {
    e.chain().any(|c| {
        c.downcast_ref::<std::io::Error>()
            .is_some_and(|io| io.kind() == std::io::ErrorKind::BrokenPipe)
    })
}

/// End quietly with status 0 when standard output is closed by its reader
/// (`clapper chart --csv - | head -3`): for a pipe that is a normal end,
/// not an error. SIGPIPE stays ignored (Rust's default), so a write into
/// the closed pipe fails with EPIPE: `print!` panics with std's "failed
/// printing to stdout" message, which this hook turns into a quiet exit;
/// other writes return the error to `main`, which does the same.
fn quiet_on_closed_stdout() {
    let default = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        let payload = info
            .payload()
            .downcast_ref::<String>()
            .map(String::as_str)
            .or_else(|| info.payload().downcast_ref::<&str>().copied())
            .unwrap_or("");
        let epipe = format!("(os error {})", libc::EPIPE);
        if payload.starts_with("failed printing to stdout") && payload.contains(&epipe) {
            std::process::exit(0);
        }
        default(info);
    }));
}

/// clap's error as one line: the error and its tips ("a similar argument
/// exists: '--strokes'"), pointing at the help of the subcommand given.
fn one_line_error(text: &str, subcommand: Option<&str>) -> String {
    let mut parts = vec![];
    for line in text.lines().map(str::trim) {
        if line.starts_with("Usage:") || line.starts_with("For more information") {
            break;
        }
        if !line.is_empty() {
            parts.push(line.strip_prefix("tip: ").unwrap_or(line));
        }
    }
    let message = if parts.is_empty() {
        "invalid arguments".to_string()
    } else {
        parts.join("; ")
    };
    let help = match subcommand {
        Some(sub) if Cli::command().find_subcommand(sub).is_some() => format!("clapper {sub} --help"),
        _ => "clapper --help".into(),
    };
    format!("{message} (see {help})")
}

/// clap's `invalid value '-5' for '--strokes <N>': a count from 1 to
/// 10000` said as `--strokes -5: a count from 1 to 10000`, the option and
/// the value as written first; any other message is left as it is.
fn as_option_said(text: &str) -> String {
    let said = (|| {
        let (head, rest) = text.split_once("invalid value '")?;
        let (value, rest) = rest.split_once("' for '")?;
        let (arg, why) = rest.split_once("': ")?;
        let option = arg.split(' ').next()?;
        why.starts_with("a ").then(|| format!("{head}{option} {value}: {why}"))
    })();
    said.unwrap_or_else(|| text.to_string())
}

/// A number option's value: any finite number. NaN and infinities are
/// refused here, once for every option, so that no command computes with
/// them ("T_c inf ... meets the rule", a log read as all "down").
fn finite_number(s: &str) -> Result<f64, String> {
    let v: f64 = s.trim().parse().map_err(|_| format!("'{s}' is not a number"))?;
    if v.is_finite() {
        Ok(v)
    } else {
        Err(format!("{s} is not a finite number"))
    }
}

/// The command line of every command: a number option takes only a
/// finite value ([`finite_number`]), and any option's value may be a
/// negative number (`--pivot-offset -0.005`; clap would read `-0.005` as
/// an option and suggest `-- -0.005`, which does not work for an
/// option's value), so that a sign is refused by its meaning, in the
/// option's own words.
fn command_line(cmd: clap::Command) -> clap::Command {
    let name = cmd.get_name().to_string();
    let cmd = cmd.mut_args(|a| {
        if !a.get_action().takes_values() {
            return a;
        }
        let of = a.get_value_parser().type_id();
        let id = a.get_id().to_string();
        let what = || counts(&name, &id);
        let a = a.allow_negative_numbers(true);
        if of == std::any::TypeId::of::<f64>() {
            a.value_parser(finite_number)
        } else if of == std::any::TypeId::of::<usize>() {
            a.value_parser(count::<usize>(what()))
        } else if of == std::any::TypeId::of::<u64>() {
            a.value_parser(count::<u64>(what()))
        } else if of == std::any::TypeId::of::<u32>() {
            a.value_parser(count::<u32>(what()))
        } else {
            a
        }
    });
    cmd.mut_subcommands(command_line)
}

/// The whole numbers option `option` (its id) of command `command` takes,
/// as its refusal says them ("a count from 1 to 10000"); the commands
/// check the bounds of a count read, and this says them for one that
/// cannot be read (`--strokes -5`).
fn counts(command: &str, option: &str) -> String {
    match (command, option) {
        ("animate", "strokes") => format!("a count from 1 to {}", clapper_app::animate::MAX_STROKES),
        (_, "strokes") if command != "synth-log" => {
            format!("a count from 1 to {}", clapper_app::simulate::MAX_STROKES)
        }
        ("serve", "max_chart_points") => format!("a count from 1 to {}", clapper_core::chart::MAX_POINTS),
        (_, "seed") => format!("a whole number from 0 to {}", u64::MAX),
        (_, "swings" | "rows") => "a count from 1".into(),
        _ => "a count: a whole number, 0 or more".into(),
    }
}

/// A count option's value: a whole number of type `T`, refused in the
/// option's words (`what`) when it is negative, fractional or too large,
/// not in Rust's ("invalid digit found in string").
fn count<T>(what: String) -> impl Fn(&str) -> Result<T, String> + Clone + Send + Sync + 'static
where
    T: std::str::FromStr + Clone + Send + Sync + 'static,
{
    move |s: &str| s.trim().parse::<T>().map_err(|_| what.clone())
}

/// glibc's allocator told to keep the memory clapper frees for its next
/// use: by default every block over 128 KiB to 32 MiB (a strike's
/// transforms, a window's matches) is mapped afresh and each of its pages
/// faulted in again, and freed memory is given back at 128 KiB; ten
/// minutes of eight bells with templates took 245,000 page faults and
/// 0.5 s of system time (of 10.2 s), 63,000 and 0.15 s so (peak memory
/// 250 -> 254 MB: what is kept is what was in use at the peak). The
/// strikes are the same to the byte: only where memory comes from changes.
#[cfg(all(target_os = "linux", target_env = "gnu"))]
fn keep_freed_memory() {
    // SAFETY: mallopt only sets the allocator's thresholds; called first
    // thing in main, before any other thread exists.
    unsafe {
        libc::mallopt(libc::M_MMAP_THRESHOLD, 32 << 20);
        libc::mallopt(libc::M_TRIM_THRESHOLD, 1 << 30);
    }
}

#[cfg(not(all(target_os = "linux", target_env = "gnu")))]
fn keep_freed_memory() {}

fn main() {
    keep_freed_memory();
    quiet_on_closed_stdout();
    let parsed = command_line(Cli::command())
        .try_get_matches()
        .and_then(|m| Cli::from_arg_matches(&m));
    let cli = match parsed {
        Ok(cli) => cli,
        Err(e) if e.use_stderr() => {
            let text = match e.kind() {
                clap::error::ErrorKind::ValueValidation => as_option_said(&e.to_string()),
                _ => e.to_string(),
            };
            eprintln!("{}", one_line_error(&text, std::env::args().nth(1).as_deref()));
            std::process::exit(2);
        }
        Err(e) => e.exit(),
    };
    let result = match cli.command {
        Command::Simulate(args) => simulate::run(args),
        Command::RingUp(args) => ring::run(args, true),
        Command::RingDown(args) => ring::run(args, false),
        Command::DesignClapper(args) => design_clapper::run(args),
        Command::Liftoff(args) => simulate::liftoff(args),
        Command::Chart(args) if args.quantity == chart::QuantityArg::GoesUp => goes_up::run(&args),
        Command::Chart(args) => chart::run(args),
        Command::Merge(args) => chart::merge(args),
        Command::Figures(args) => figures::run(args),
        Command::Diagnose(args) => diagnose::run(args),
        Command::Restitution(args) => measure::restitution(args),
        Command::Contacts(args) => measure::contacts(args),
        Command::Spectrogram(args) => measure::spectrogram_cmd(args),
        Command::Decay(args) => measure::decay(args),
        Command::Modes(args) => measure::modes(args),
        Command::Strikes(args) => strikes::strikes(args),
        Command::SynthRing(args) => strikes::synth_ring(args),
        Command::Impulse(args) => measure::impulse(args),
        Command::Synth(args) => sound::run(args),
        Command::Animate(args) => animate::run(args),
        Command::RingingLog(args) => ringing_log::ringing_log(args),
        Command::SynthLog(args) => ringing_log::synth_log_cmd(args),
        Command::ListeningTest(args) => listening::run(args),
        Command::SampleData(args) => sample_data::run(args),
        Command::Serve(args) => serve::run(args),
        Command::Tower(args) => tower::run(args),
    };
    if let Err(e) = result {
        if is_broken_pipe(&e) {
            std::process::exit(0);
        }
        let args: Vec<String> = std::env::args().skip(1).collect();
        eprintln!(
            "error: {}",
            words::short_numbers(&words::as_given(&format!("{e:#}"), &args))
        );
        std::process::exit(1);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clap_errors_keep_their_tip_and_name_the_subcommands_help() {
        let e = Cli::try_parse_from(["clapper", "simulate", "--stroke", "3"]).unwrap_err();
        let line = one_line_error(&e.to_string(), Some("simulate"));
        assert!(line.contains("'--stroke'") && line.contains("'--strokes'"), "{line}");
        assert!(line.ends_with("(see clapper simulate --help)"), "{line}");
        assert!(!line.contains('\n'));
        let e = Cli::try_parse_from(["clapper", "simulat"]).unwrap_err();
        assert!(one_line_error(&e.to_string(), Some("simulat")).ends_with("(see clapper --help)"));
    }
}
