//! Progress on the terminal for long work (hidden when stderr is not one).

use indicatif::{ProgressBar, ProgressStyle};

/// A progress bar over `total` strokes, labelled `what`.
pub fn bar(total: u64, what: &str) -> ProgressBar {
    let bar = ProgressBar::new(total);
    bar.set_style(
        ProgressStyle::with_template("{msg:>24} [{bar:40}] {pos}/{len} strokes, {rate}, eta {eta}")
            .expect("valid template")
            // Whole strokes a second ("30310 strokes/s"), not indicatif's
            // own "30,310.0949/s".
            .with_key("rate", |s: &indicatif::ProgressState, w: &mut dyn std::fmt::Write| {
                let _ = write!(w, "{:.0} strokes/s", s.per_sec());
            })
            .progress_chars("=> "),
    );
    bar.set_message(what.to_string());
    bar
}
