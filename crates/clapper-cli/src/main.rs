//! `clapper`: the command line of clapper.

mod chart;
mod diagnose;
mod figures;
mod files;
mod simulate;

use clap::{Parser, Subcommand};

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
    /// The closed-form lift-off angles for r = 0, equations (15) and (16).
    Liftoff(simulate::LiftoffArgs),
    /// A clapping chart: sweep the plane of (r/L_c, L_b/L_c) and show where
    /// a bell rings right or wrong and how it strikes.
    Chart(chart::ChartArgs),
    /// Reproduce the paper's figures 7, 9-12 and 14-16 into a folder.
    Figures(figures::FiguresArgs),
    /// Diagnose a bell or a ring for the bell-hanger: how it rings, its
    /// margins, what to change, loads on the frame.
    Diagnose(diagnose::DiagnoseArgs),
}

/// Die quietly on a closed pipe (`clapper chart | head`), as Unix tools
/// do, instead of panicking in `println!`.
fn restore_sigpipe() {
    #[cfg(unix)]
    // SAFETY: setting a signal disposition to its default before any other
    // thread exists has no memory-safety preconditions.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}

fn main() {
    restore_sigpipe();
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) if e.use_stderr() => {
            // One line naming the problem, not clap's three.
            let text = e.to_string();
            let message: Vec<&str> = text
                .lines()
                .take_while(|l| !l.trim().is_empty() && !l.starts_with("Usage:"))
                .map(str::trim)
                .collect();
            let message = if message.is_empty() {
                "invalid arguments".to_string()
            } else {
                message.join(" ")
            };
            eprintln!("{message} (see clapper --help)");
            std::process::exit(2);
        }
        Err(e) => e.exit(),
    };
    let result = match cli.command {
        Command::Simulate(args) => simulate::run(args),
        Command::Liftoff(args) => simulate::liftoff(args),
        Command::Chart(args) => chart::run(args),
        Command::Figures(args) => figures::run(args),
        Command::Diagnose(args) => diagnose::run(args),
    };
    if let Err(e) = result {
        eprintln!("error: {e:#}");
        std::process::exit(1);
    }
}
