//! Diagnose a bell or a ring for the bell-hanger: the work behind
//! `clapper diagnose` and `POST /api/diagnose`, as a report (JSON), text,
//! and a self-contained HTML page with the chart.

mod build;
mod chart;
mod odd_struck;
mod report;
mod request;
mod text;

pub use build::{diagnose_bells, diagnose_bells_with};
pub use chart::chart_svg;
pub use odd_struck::OddStruckOptions;
pub use report::{
    BellDiagnosisReport, ChangeReport, DByR, DiagnosisReport, FrameReport, MarginReport, OddStruckReport, StyleReport,
};
pub use request::{DiagnoseRequest, MAX_BELLS};
pub use text::{report_page, text};
