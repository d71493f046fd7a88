//! # clapper-io
//!
//! The file formats of clapper, outside the physics core: bell files in
//! TOML (by mass properties or by tower measurements), traces in CSV, and
//! the JSON report of a simulation. Angles are in degrees here, at the
//! edge; the core works in radians.

#![warn(missing_docs)]

pub mod accel_log;
pub mod answers;
pub mod bell_file;
pub mod channels;
pub mod chart_csv;
pub mod clapper_input;
pub mod hanging_input;
pub mod report;
pub mod signal_file;
pub mod strike_file;
pub mod text_file;
pub mod tower_file;
pub mod trace;
pub mod wav_stream;

pub use bell_file::{
    bell_texts, load_bell, load_bells, parse_bell, parse_bells, parse_ring_csv, BellFileError, BellSource, FrameInput,
    LoadedBell,
};
pub use chart_csv::{read_chart_csv, write_chart_csv, write_chart_rows, write_goes_up_csv, Columns};
pub use report::{SimulationReport, SimulationSettings};
pub use trace::{write_trace_csv, TraceWriter};
