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
    #[derive(serde::Deserialize)]
    struct Row {
        listener: String,
        amplitude_ratio: f64,
        delay_ms: f64,
        answer: Option<i8>,
    }
    let err = |message: String| AnswersError {
        path: path.display().to_string(),
        message,
    };
    let mut rdr = csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .from_path(path)
        .map_err(|e| err(format!("cannot read: {e}")))?;
    let mut out = vec![];
    for (k, row) in rdr.deserialize::<Row>().enumerate() {
        let r = row.map_err(|e| err(format!("row {}: {}", k + 1, e.to_string().replace('\n', " "))))?;
        if let Some(answer) = r.answer {
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
    }
}
