//! Filled answer sheets of the listening test: CSV with the columns
//! `listener`, `amplitude_ratio`, `delay_ms`, `answer` (+1 single strike,
//! -1 double strike; rows left blank are skipped; other columns ignored).

use std::path::Path;

use clapper_core::listening::Answer;

/// Why an answer sheet cannot be read. One line.
#[derive(Debug, thiserror::Error)]
#[error("{path}: {message}")]
pub struct AnswersError {
    /// The file.
    pub path: String,
    /// What is wrong.
    pub message: String,
}

/// Read one answer sheet.
pub fn read_answers(path: &Path) -> Result<Vec<Answer>, AnswersError> {
    use crate::text_file::{read_text, ReadTextError};
    let text = read_text(path, "an answer sheet").map_err(|e| match e {
        ReadTextError::Io(e) => AnswersError {
            path: path.display().to_string(),
            message: format!("cannot read: {e}"),
        },
        ReadTextError::NotText(e) => AnswersError {
            path: path.display().to_string(),
            message: e.what(),
        },
    })?;
    parse_answers(&text, &path.display().to_string())
}

/// Parse an answer sheet's text; `name` says where it came from in errors.
pub fn parse_answers(text: &str, name: &str) -> Result<Vec<Answer>, AnswersError> {
    #[derive(serde::Deserialize)]
    struct Row {
        listener: String,
        amplitude_ratio: f64,
        delay_ms: f64,
        answer: Option<i8>,
    }
    let err = |message: String| AnswersError {
        path: name.to_string(),
        message,
    };
    let mut rdr = csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .from_reader(text.as_bytes());
    let mut out = vec![];
    for (k, row) in rdr.deserialize::<Row>().enumerate() {
        let r = row.map_err(|e| err(format!("row {}: {}", k + 1, e.to_string().replace('\n', " "))))?;
        if let Some(answer) = r.answer {
            if answer != 1 && answer != -1 {
                return Err(err(format!(
                    "row {}: answer {answer} is neither 1 (single strike) nor -1 (double strike)",
                    k + 1
                )));
            }
            if !(r.amplitude_ratio.is_finite() && r.delay_ms.is_finite()) {
                return Err(err(format!(
                    "row {}: amplitude_ratio and delay_ms must be numbers",
                    k + 1
                )));
            }
            out.push(Answer {
                listener: r.listener,
                ratio: r.amplitude_ratio,
                delay_ms: r.delay_ms,
                answer,
            });
        }
    }
    Ok(out)
}

/// One row of an answer sheet as written for listeners: the stimulus to
/// play and an empty answer to fill. The stimulus index (`stimuli.csv`)
/// has no listener and no trial.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct SheetRow {
    /// Who answers (`None` in the stimulus index).
    pub listener: Option<String>,
    /// Trial number, from 1 (0 in the stimulus index).
    pub trial: usize,
    /// Stimulus file name.
    pub stimulus: String,
    /// Amplitude ratio of the second strike.
    pub amplitude_ratio: f64,
    /// Delay of the second strike (ms).
    pub delay_ms: f64,
    /// +1 single, -1 double; empty until answered.
    pub answer: Option<i8>,
}

/// An answer sheet (or the stimulus index) as CSV text, readable by
/// [`parse_answers`] once filled. Ratios print to 0.1 and delays to 1 ms,
/// the grid's resolution.
pub fn answer_sheet_csv(rows: &[SheetRow]) -> Result<String, csv::Error> {
    let index = rows.iter().all(|r| r.listener.is_none());
    let mut w = csv::Writer::from_writer(vec![]);
    if index {
        w.write_record(["stimulus", "amplitude_ratio", "delay_ms"])?;
    } else {
        w.write_record(["listener", "trial", "stimulus", "amplitude_ratio", "delay_ms", "answer"])?;
    }
    for r in rows {
        let (ratio, delay) = (format!("{:.1}", r.amplitude_ratio), format!("{:.0}", r.delay_ms));
        if index {
            w.write_record([r.stimulus.as_str(), &ratio, &delay])?;
        } else {
            w.write_record([
                r.listener.as_deref().unwrap_or(""),
                &r.trial.to_string(),
                &r.stimulus,
                &ratio,
                &delay,
                &r.answer.map_or(String::new(), |a| a.to_string()),
            ])?;
        }
    }
    let bytes = w.into_inner().map_err(|e| e.into_error())?;
    Ok(String::from_utf8(bytes).expect("CSV of UTF-8 fields is UTF-8"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blank_answers_are_skipped_and_bad_rows_named() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("a.csv");
        std::fs::write(
            &p,
            "listener,trial,amplitude_ratio,delay_ms,answer\nA,1,0.5,30,-1\nA,2,0.6,40,\n",
        )
        .unwrap();
        let a = read_answers(&p).unwrap();
        assert_eq!(a.len(), 1);
        assert_eq!(a[0].answer, -1);
        std::fs::write(&p, "listener,amplitude_ratio,delay_ms,answer\nA,x,30,1\n").unwrap();
        let e = read_answers(&p).unwrap_err().to_string();
        assert!(e.contains("row 1") && !e.contains('\n'), "{e}");
        let e = parse_answers("listener,amplitude_ratio,delay_ms,answer\nA,0.5,30,3\n", "sheet").unwrap_err();
        assert!(e.to_string().contains("neither 1"), "{e}");
    }

    #[test]
    fn filled_sheets_read_back() {
        let row = |answer| SheetRow {
            listener: Some("L1".into()),
            trial: 1,
            stimulus: "s012.wav".into(),
            amplitude_ratio: 0.2,
            delay_ms: 30.0,
            answer,
        };
        let empty = answer_sheet_csv(&[row(None)]).unwrap();
        assert!(parse_answers(&empty, "x").unwrap().is_empty());
        let filled = answer_sheet_csv(&[row(Some(-1))]).unwrap();
        let a = parse_answers(&filled, "x").unwrap();
        assert_eq!((a[0].ratio, a[0].delay_ms, a[0].answer), (0.2, 30.0, -1));
    }
}
