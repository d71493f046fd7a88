//! # clapper-app
//!
//! The things clapper does for its users, once, for both front ends: the
//! command line (`clapper-cli`) and the web server (`clapper-web`). Each
//! is a request (plain data, `serde`-readable, with the same defaults as
//! the command line's options) and a function that answers it with a
//! report (`serde`-writable) or a typed [`AppError`].
//!
//! No file, terminal or network I/O happens here: callers read files and
//! pass their text, and write what they get back.
//!
//! ```
//! use clapper_app::simulate::{simulate, SimulateRequest};
//! let req: SimulateRequest = serde_json::from_str(r#"{"preset": "lab", "style": "right"}"#).unwrap();
//! let sim = simulate(&req, None, None).unwrap();
//! assert!(sim.report.sustained);
//! ```

#![warn(missing_docs)]

pub mod animate;
pub mod chart;
pub mod clapper_design;
pub mod diagnosis;
pub mod figures;
pub mod liftoff;
pub mod listening;
pub mod measure;
pub mod ring_up;
pub mod ringing_log;
pub mod sample_data;
pub mod simulate;
pub mod sound;
pub mod strikes;
pub mod stroke_options;
pub mod sweep;
pub mod tower;

use clapper_core::bell::ParamError;
use clapper_core::stroke::SimError;

/// Why a request could not be answered. Every message is one line and
/// names what is wrong.
#[derive(Debug, thiserror::Error)]
pub enum AppError {
    /// The request itself is inconsistent or out of range.
    #[error("{0}")]
    Request(String),
    /// A bell or ring file (given as text) is not usable.
    #[error(transparent)]
    BellFile(#[from] clapper_io::BellFileError),
    /// A listening-test answer sheet is not usable.
    #[error(transparent)]
    Answers(#[from] clapper_io::answers::AnswersError),
    /// A parameter is out of its physical range.
    #[error(transparent)]
    Param(#[from] ParamError),
    /// The simulation failed numerically. Its cause is in the message
    /// (not a `source` too, which printed it twice in an error chain).
    #[error("simulation failed: {0}")]
    Simulation(SimError),
    /// A plot could not be drawn.
    #[error(transparent)]
    Plot(#[from] clapper_plot::PlotError),
    /// Sound could not be synthesised or encoded.
    #[error("sound: {0}")]
    Sound(String),
    /// No bell's strike heard to learn the bells from (`--bells N` on a
    /// silent, steady or bell-less recording): what was heard, in words.
    /// Front ends that report strikes report none
    /// ([`strikes::StrikesReport::unheard`]), as with nominals given.
    #[error("{0}")]
    NothingHeard(String),
}

impl From<SimError> for AppError {
    /// A parameter out of range is the request's fault and says so as
    /// such; anything else is a failed simulation.
    fn from(e: SimError) -> Self {
        match e {
            SimError::Param(p) => AppError::Param(p),
            other => AppError::Simulation(other),
        }
    }
}

impl AppError {
    /// Whether the fault lies with the request (bad input) rather than
    /// with the computation: front ends answer these with "bad request".
    pub fn is_bad_input(&self) -> bool {
        matches!(
            self,
            AppError::Request(_)
                | AppError::BellFile(_)
                | AppError::Answers(_)
                | AppError::Param(_)
                | AppError::NothingHeard(_)
        )
    }
}
