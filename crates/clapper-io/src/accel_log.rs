//! Accelerometer logs of a bell (`clapper ringing-log`): the belfry-sleuth
//! text format and a CSV with a header, read into
//! [`clapper_signal::ringing_log::AccelLog`] with the sensor's axes named.
//!
//! **belfry-sleuth text**: one sample a line, whitespace-separated: x, y, z
//! (m/s²), the time (ms), and any further columns (ignored). Lines that are
//! not numbers after the samples, such as `Bell 3`, are kept as the bell's
//! name; text before the samples is a header and skipped.
//!
//! **CSV**: a header naming `t_s`, `ax`, `ay`, `az` (any order, other
//! columns ignored), then one sample a row, m/s² and s.

use clapper_signal::ringing_log::AccelLog;

/// Why a log could not be read. Every message is one line and names the
/// line at fault.
#[derive(Debug, thiserror::Error)]
pub enum LogFileError {
    /// The file could not be read.
    #[error("cannot read log {path}: {reason}")]
    Read {
        /// The path.
        path: String,
        /// Why.
        reason: String,
    },
    /// Not text at all: a recording given as a log.
    #[error("{0}")]
    NotText(crate::text_file::NotText),
    /// Nothing in it.
    #[error("the log is empty: no samples")]
    Empty,
    /// A line that should be a sample is not.
    #[error("line {line}: {reason}")]
    Line {
        /// 1-based.
        line: usize,
        /// What is wrong.
        reason: String,
    },
    /// The axes option is not two of x, y, z.
    #[error("--axes {0:?}: give two of x, y, z (a sign allowed), radial then tangential, e.g. y,z or y,-z")]
    Axes(String),
}

/// Which sensor axis reads what: indices 0-2 for x, y, z and a sign.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Axes {
    /// The axis along the bell's axis (toward the crown when the sign is +).
    pub radial: (usize, f64),
    /// The tangential axis (reading g sin θ).
    pub tangential: (usize, f64),
}

impl Default for Axes {
    /// y along the bell's axis, z tangential: the sensor on the crown-staple
    /// nut as belfry-sleuth mounts it.
    fn default() -> Self {
        Axes {
            radial: (1, 1.0),
            tangential: (2, 1.0),
        }
    }
}

impl Axes {
    /// Parse `RADIAL,TANGENTIAL`, each `x`, `y` or `z` with an optional
    /// sign (`y,z`, `-y,z`).
    pub fn parse(text: &str) -> Result<Axes, LogFileError> {
        let bad = || LogFileError::Axes(text.to_string());
        let one = |s: &str| -> Result<(usize, f64), LogFileError> {
            let s = s.trim();
            let (sign, name) = match s.strip_prefix('-') {
                Some(rest) => (-1.0, rest),
                None => (1.0, s.strip_prefix('+').unwrap_or(s)),
            };
            let index = match name.to_ascii_lowercase().as_str() {
                "x" => 0,
                "y" => 1,
                "z" => 2,
                _ => return Err(bad()),
            };
            Ok((index, sign))
        };
        let (a, b) = text.split_once(',').ok_or_else(bad)?;
        let axes = Axes {
            radial: one(a)?,
            tangential: one(b)?,
        };
        if axes.radial.0 == axes.tangential.0 {
            return Err(bad());
        }
        Ok(axes)
    }

    /// The third axis: along the pivot.
    fn axle(&self) -> usize {
        3 - self.radial.0 - self.tangential.0
    }
}

/// Read a log's text (`name`: the file's name, to tell CSV by its `.csv`
/// or its header).
pub fn parse_accel_log(text: &str, axes: Axes) -> Result<AccelLog, LogFileError> {
    let first = text.lines().find(|l| !l.trim().is_empty()).unwrap_or("");
    let rows = if first.contains(',') && first.chars().any(|c| c.is_ascii_alphabetic()) {
        csv_rows(text)?
    } else {
        sleuth_rows(text)?
    };
    let (xyz, t, name) = rows;
    if t.is_empty() {
        return Err(LogFileError::Empty);
    }
    let pick = |(i, s): (usize, f64)| xyz.iter().map(|v: &[f64; 3]| s * v[i]).collect::<Vec<f64>>();
    Ok(AccelLog {
        name,
        radial: pick(axes.radial),
        tangential: pick(axes.tangential),
        axle: pick((axes.axle(), 1.0)),
        t,
    })
}

type Rows = (Vec<[f64; 3]>, Vec<f64>, Option<String>);

fn sleuth_rows(text: &str) -> Result<Rows, LogFileError> {
    let (mut xyz, mut t) = (vec![], vec![]);
    let mut name: Option<String> = None;
    for (i, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() {
            continue;
        }
        let fields: Vec<&str> = line.split_whitespace().collect();
        let nums: Vec<Option<f64>> = fields.iter().map(|f| f.parse::<f64>().ok()).collect();
        if nums.first().copied().flatten().is_none() {
            // Text: a header before the samples, the bell's name after.
            if !t.is_empty() {
                // Tabs and runs of spaces as one space ("Bell\t3\t\t" is "Bell 3").
                name = Some(
                    line.split_whitespace()
                        .collect::<Vec<_>>()
                        .join(" ")
                        .chars()
                        .take(80)
                        .collect(),
                );
            }
            continue;
        }
        if name.is_some() {
            return Err(LogFileError::Line {
                line: i + 1,
                reason: "a sample after the trailer (the bell's name) line".into(),
            });
        }
        if fields.len() < 4 {
            return Err(LogFileError::Line {
                line: i + 1,
                reason: format!("{} column(s); a sample is x y z (m/s²) and the time (ms)", fields.len()),
            });
        }
        let v: Vec<f64> = match nums[..4].iter().copied().collect::<Option<Vec<f64>>>() {
            Some(v) => v,
            None => {
                return Err(LogFileError::Line {
                    line: i + 1,
                    reason: format!("{line:?} is not four numbers (x y z time_ms)"),
                })
            }
        };
        push(&mut xyz, &mut t, [v[0], v[1], v[2]], v[3] * 1e-3, i + 1)?;
    }
    Ok((xyz, t, name))
}

fn csv_rows(text: &str) -> Result<Rows, LogFileError> {
    let mut lines = text.lines().enumerate().filter(|(_, l)| !l.trim().is_empty());
    let (_, header) = lines.next().ok_or(LogFileError::Empty)?;
    let cols: Vec<String> = header.split(',').map(|c| c.trim().to_ascii_lowercase()).collect();
    let col = |name: &str| {
        cols.iter().position(|c| c == name).ok_or_else(|| LogFileError::Line {
            line: 1,
            reason: format!("the CSV header has no {name} column (it needs t_s, ax, ay, az)"),
        })
    };
    let idx = [col("t_s")?, col("ax")?, col("ay")?, col("az")?];
    let (mut xyz, mut t) = (vec![], vec![]);
    for (i, line) in lines {
        let fields: Vec<&str> = line.split(',').map(str::trim).collect();
        let get = |k: usize| -> Result<f64, LogFileError> {
            fields
                .get(idx[k])
                .and_then(|f| f.parse::<f64>().ok())
                .ok_or_else(|| LogFileError::Line {
                    line: i + 1,
                    reason: format!(
                        "{:?} is not a number in column {}",
                        fields.get(idx[k]).unwrap_or(&""),
                        cols[idx[k]]
                    ),
                })
        };
        push(&mut xyz, &mut t, [get(1)?, get(2)?, get(3)?], get(0)?, i + 1)?;
    }
    Ok((xyz, t, None))
}

fn push(xyz: &mut Vec<[f64; 3]>, t: &mut Vec<f64>, v: [f64; 3], time: f64, line: usize) -> Result<(), LogFileError> {
    if v.iter().chain([&time]).any(|x| !x.is_finite()) {
        return Err(LogFileError::Line {
            line,
            reason: "a value is not a finite number".into(),
        });
    }
    if let Some(&prev) = t.last() {
        if time <= prev {
            return Err(LogFileError::Line {
                line,
                reason: format!(
                    "time {} s is not after the sample before ({} s): time goes backwards or repeats",
                    time, prev
                ),
            });
        }
    }
    xyz.push(v);
    t.push(time);
    Ok(())
}

/// Read a log from a file.
pub fn load_accel_log(path: &std::path::Path, axes: Axes) -> Result<AccelLog, LogFileError> {
    use crate::text_file::{read_text, ReadTextError};
    let text = read_text(path, "an accelerometer log").map_err(|e| match e {
        ReadTextError::Io(e) => LogFileError::Read {
            path: path.display().to_string(),
            reason: e.to_string(),
        },
        ReadTextError::NotText(e) => LogFileError::NotText(e),
    })?;
    parse_accel_log(&text, axes)
}

/// Whether `name`, written as a sleuth log's trailer line, reads back as
/// the bell's name: one line, not blank, and not beginning with a number
/// (the reader takes a line that does for a sample).
pub fn name_reads_back(name: &str) -> bool {
    let one_line = !name.contains(['\n', '\r']);
    let first = name.split_whitespace().next();
    one_line && first.is_some_and(|f| f.parse::<f64>().is_err())
}

/// A log in the belfry-sleuth text format, the axes as [`Axes::default`]
/// puts them (x along the pivot, y radial, z tangential), the time in whole
/// milliseconds as the logger writes it, the name as a trailer line. A log
/// sampled too fast for whole milliseconds (two samples in one: above
/// 1 kHz, or jittered near it) has its times to the microsecond, so that
/// it reads back.
pub fn write_sleuth_log(log: &AccelLog) -> String {
    let whole_ms = log.t.windows(2).all(|w| (w[1] * 1e3).round() > (w[0] * 1e3).round());
    let mut out = String::with_capacity(log.t.len() * 32);
    for k in 0..log.t.len() {
        let (x, y, z) = (log.axle[k], log.radial[k], log.tangential[k]);
        if whole_ms {
            out.push_str(&format!("{x:.3} {y:.3} {z:.3} {}\n", (log.t[k] * 1e3).round() as i64));
        } else {
            out.push_str(&format!("{x:.3} {y:.3} {z:.3} {:.3}\n", log.t[k] * 1e3));
        }
    }
    if let Some(n) = &log.name {
        out.push_str(n);
        out.push('\n');
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_name_that_would_read_as_a_sample_is_told() {
        for bad in ["1 2 3 4", "7", "-3 bells", "", "  ", "Bell\n1 2 3 4"] {
            assert!(!name_reads_back(bad), "{bad:?}");
        }
        for good in ["Bell 1 2 3 4", "Tenor", "3rd"] {
            assert!(name_reads_back(good), "{good:?}");
        }
    }

    #[test]
    fn a_sleuth_log_reads_with_its_name_and_axes() {
        let text = "x y z t\n0.1 9.8 0.0 0\n0.2 9.7 1.0 10 55\n0.3 9.6 -1.0 20\nBell 3\n";
        let log = parse_accel_log(text, Axes::default()).expect("read");
        assert_eq!(log.name.as_deref(), Some("Bell 3"));
        assert_eq!(log.t, vec![0.0, 0.01, 0.02]);
        assert_eq!(log.radial, vec![9.8, 9.7, 9.6]);
        assert_eq!(log.tangential, vec![0.0, 1.0, -1.0]);
        assert_eq!(log.axle, vec![0.1, 0.2, 0.3]);
        let flipped = parse_accel_log(text, Axes::parse("y,-z").expect("axes")).expect("read");
        assert_eq!(flipped.tangential, vec![-0.0, -1.0, 1.0]);
    }

    #[test]
    fn a_csv_log_reads_by_its_header() {
        let text = "ay,t_s,ax,az,temp\n9.8,0.0,0.1,0.0,20\n9.7,0.01,0.2,1.0,20\n";
        let log = parse_accel_log(text, Axes::default()).expect("read");
        assert_eq!(log.t, vec![0.0, 0.01]);
        assert_eq!(log.radial, vec![9.8, 9.7]);
        assert_eq!(log.axle, vec![0.1, 0.2]);
    }

    #[test]
    fn bad_logs_name_their_fault() {
        let e = |text: &str| parse_accel_log(text, Axes::default()).unwrap_err().to_string();
        assert_eq!(e(""), "the log is empty: no samples");
        assert!(e("just some text\nand more\n").contains("empty"));
        assert!(e("1\n2\n3\n").contains("line 1: 1 column(s)"));
        assert!(e("0 9.8 0 0\n0 9.8 0 10\n0 9.8 0 5\n").contains("line 3: time 0.005 s is not after"));
        assert!(e("t_s,ax,ay\n0,1,2\n").contains("no az column"));
        assert!(e("0 9.8 x 0\n").contains("line 1"));
        assert!(Axes::parse("y,y").is_err() && Axes::parse("q,z").is_err() && Axes::parse("y").is_err());
    }

    #[test]
    fn the_writer_and_the_reader_agree() {
        let log = AccelLog {
            name: Some("Tenor".into()),
            t: vec![0.0, 0.01, 0.02],
            radial: vec![9.81, 9.8, 9.79],
            tangential: vec![0.0, 0.5, 1.0],
            axle: vec![0.0, 0.04, -0.04],
        };
        let back = parse_accel_log(&write_sleuth_log(&log), Axes::default()).expect("read");
        assert_eq!(back, log);
    }
}
