//! Trace files: one row per sample of a simulation, in CSV.

use std::io::Write;

use clapper_core::stroke::Sample;

/// The CSV header: time (s), angles (deg), rates (rad/s), contact force (N m).
pub const TRACE_HEADER: [&str; 6] = [
    "t_s",
    "theta_deg",
    "phi_deg",
    "thetadot_rad_s",
    "phidot_rad_s",
    "contact_force_n_m",
];

/// Write `samples` as CSV with [`TRACE_HEADER`]. The contact force is the
/// generalised force Q_φ on the clapper: nonzero while it rests on or is
/// pressed into the bell (an impact is an impulse and does not show; the
/// velocity jumps in consecutive rows at the same time do).
pub fn write_trace_csv<W: Write>(out: W, samples: &[Sample]) -> Result<(), csv::Error> {
    let mut w = TraceWriter::new(out)?;
    for s in samples {
        w.write(s)?;
    }
    w.finish()
}

/// A trace CSV written a sample at a time ([`write_trace_csv`]'s format),
/// for traces too long to hold.
pub struct TraceWriter<W: Write> {
    w: csv::Writer<W>,
}

impl<W: Write> TraceWriter<W> {
    /// Start the file: its header.
    pub fn new(out: W) -> Result<Self, csv::Error> {
        let mut w = csv::Writer::from_writer(out);
        w.write_record(TRACE_HEADER)?;
        Ok(Self { w })
    }

    /// One sample's row.
    pub fn write(&mut self, s: &Sample) -> Result<(), csv::Error> {
        self.w.write_record([
            format!("{:.6}", s.t),
            format!("{:.6}", s.y[0].to_degrees()),
            format!("{:.6}", s.y[1].to_degrees()),
            format!("{:.6}", s.y[2]),
            format!("{:.6}", s.y[3]),
            format!("{:.6}", s.contact_force),
        ])
    }

    /// Flush what is buffered.
    pub fn finish(mut self) -> Result<(), csv::Error> {
        self.w.flush()?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn writes_header_and_degrees() {
        let mut buf = Vec::new();
        let s = Sample {
            t: 0.5,
            y: [std::f64::consts::PI, -0.1, 1.0, 2.0],
            contact_force: -3.0,
            friction: [0.0; 2],
        };
        write_trace_csv(&mut buf, &[s]).unwrap();
        let text = String::from_utf8(buf).unwrap();
        let mut lines = text.lines();
        assert_eq!(lines.next().unwrap(), TRACE_HEADER.join(","));
        assert_eq!(
            lines.next().unwrap(),
            "0.500000,180.000000,-5.729578,1.000000,2.000000,-3.000000"
        );
    }
}
