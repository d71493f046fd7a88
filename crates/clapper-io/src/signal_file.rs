//! Recorded signals: WAV (any common bit depth and rate, mono or a chosen
//! channel) or CSV (a time column and a value column), and modes files.

use std::path::Path;

use clapper_core::vibration::Mode;
use clapper_signal::Signal;

/// Why a signal file cannot be used. Every message is one line.
#[derive(Debug, thiserror::Error)]
pub enum SignalFileError {
    /// Not readable.
    #[error("cannot read {path}: {message}")]
    Read {
        /// The file.
        path: String,
        /// Why.
        message: String,
    },
    /// Not writable.
    #[error("cannot write {path}: {message}")]
    Write {
        /// The file.
        path: String,
        /// Why.
        message: String,
    },
    /// Readable but not a usable signal.
    #[error("{path}: {message}")]
    Content {
        /// The file.
        path: String,
        /// What is wrong.
        message: String,
    },
}

fn content(path: &Path, message: impl Into<String>) -> SignalFileError {
    SignalFileError::Content {
        path: path.display().to_string(),
        message: message.into(),
    }
}

/// Read a signal; `channel` counts from 0 (WAV), or names the value column
/// by position after the time column (CSV).
pub fn read_signal(path: &Path, channel: usize) -> Result<Signal, SignalFileError> {
    let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    let sig = match ext.as_deref() {
        Some("wav") => read_wav(path, channel)?,
        Some("csv") => read_csv(path, channel)?,
        _ => return Err(content(path, "a signal file must be .wav or .csv")),
    };
    sig.validate().map_err(|e| content(path, e.to_string()))?;
    Ok(sig)
}

/// Read a recording of a ring: a WAV file (mono or more channels, mixed
/// to one by their mean; 16- or 24-bit integer or float samples).
pub fn read_recording(path: &Path) -> Result<Signal, SignalFileError> {
    let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    if ext.as_deref() != Some("wav") {
        return Err(content(path, "a recording must be a .wav file"));
    }
    let bytes = std::fs::read(path).map_err(|e| SignalFileError::Read {
        path: path.display().to_string(),
        message: e.to_string(),
    })?;
    recording_from_bytes(&bytes, &path.display().to_string())
}

/// A recording of a ring from the bytes of a WAV file (an upload, say),
/// as [`read_recording`]; `name` is how errors name it.
pub fn recording_from_bytes(bytes: &[u8], name: &str) -> Result<Signal, SignalFileError> {
    let here = Path::new(name);
    let mut r = hound::WavReader::new(std::io::Cursor::new(bytes))
        .map_err(|e| content(here, format!("not a WAV file this reads ({e})")))?;
    let spec = r.spec();
    let nch = usize::from(spec.channels.max(1));
    let all: Vec<f64> = match spec.sample_format {
        hound::SampleFormat::Float => r
            .samples::<f32>()
            .map(|s| s.map(f64::from))
            .collect::<Result<_, _>>()
            .map_err(|e| content(here, e.to_string()))?,
        hound::SampleFormat::Int => {
            let scale = 2f64.powi(spec.bits_per_sample as i32 - 1);
            r.samples::<i32>()
                .map(|s| s.map(|v| f64::from(v) / scale))
                .collect::<Result<_, _>>()
                .map_err(|e| content(here, e.to_string()))?
        }
    };
    let samples: Vec<f64> = all
        .chunks_exact(nch)
        .map(|f| f.iter().sum::<f64>() / nch as f64)
        .collect();
    if samples.is_empty() {
        return Err(content(here, "no samples"));
    }
    let sig = Signal {
        rate: f64::from(spec.sample_rate),
        samples,
    };
    sig.validate().map_err(|e| content(here, e.to_string()))?;
    Ok(sig)
}

fn read_wav(path: &Path, channel: usize) -> Result<Signal, SignalFileError> {
    std::fs::metadata(path).map_err(|e| SignalFileError::Read {
        path: path.display().to_string(),
        message: e.to_string(),
    })?;
    // The file is there: whatever hound cannot parse is not a WAV it reads.
    let mut r = hound::WavReader::open(path).map_err(|e| content(path, format!("not a WAV file this reads ({e})")))?;
    let spec = r.spec();
    let nch = spec.channels as usize;
    if channel >= nch {
        return Err(content(
            path,
            format!("channel {channel} asked, the file has {nch} (0 to {})", nch - 1),
        ));
    }
    let all: Vec<f64> = match spec.sample_format {
        hound::SampleFormat::Float => r
            .samples::<f32>()
            .map(|s| s.map(f64::from))
            .collect::<Result<_, _>>()
            .map_err(|e| content(path, e.to_string()))?,
        hound::SampleFormat::Int => {
            let scale = 2f64.powi(spec.bits_per_sample as i32 - 1);
            r.samples::<i32>()
                .map(|s| s.map(|v| f64::from(v) / scale))
                .collect::<Result<_, _>>()
                .map_err(|e| content(path, e.to_string()))?
        }
    };
    let samples: Vec<f64> = all.iter().skip(channel).step_by(nch).copied().collect();
    if samples.is_empty() {
        return Err(content(path, "no samples"));
    }
    Ok(Signal {
        rate: f64::from(spec.sample_rate),
        samples,
    })
}

/// A CSV reader with a header row and trimmed cells over the text of
/// `path`, which should be `wanted` ("a modes file").
fn csv_reader(path: &Path, wanted: &'static str) -> Result<csv::Reader<std::io::Cursor<String>>, SignalFileError> {
    use crate::text_file::{read_text, ReadTextError};
    let text = read_text(path, wanted).map_err(|e| match e {
        ReadTextError::Io(e) => SignalFileError::Read {
            path: path.display().to_string(),
            message: e.to_string(),
        },
        ReadTextError::NotText(e) => content(path, e.what()),
    })?;
    Ok(csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .from_reader(std::io::Cursor::new(text)))
}

fn read_csv(path: &Path, channel: usize) -> Result<Signal, SignalFileError> {
    let mut rdr = csv_reader(path, "a CSV signal")?;
    let headers = rdr.headers().map_err(|e| content(path, e.to_string()))?.clone();
    if headers.len() < 2 + channel {
        return Err(content(
            path,
            format!(
                "needs a time column (s) and a value column{}; found {} column(s)",
                if channel > 0 {
                    format!(" number {}", channel + 1)
                } else {
                    String::new()
                },
                headers.len()
            ),
        ));
    }
    let (mut t, mut x) = (vec![], vec![]);
    for (k, rec) in rdr.records().enumerate() {
        let rec = rec.map_err(|e| content(path, format!("row {}: {e}", k + 1)))?;
        let num = |i: usize| -> Result<f64, SignalFileError> {
            let v = rec.get(i).unwrap_or("");
            let f: f64 = v
                .parse()
                .map_err(|_| content(path, format!("row {}, column {}: '{v}' is not a number", k + 1, i + 1)))?;
            if f.is_finite() {
                Ok(f)
            } else {
                Err(content(
                    path,
                    format!("row {}, column {}: {v} is not finite", k + 1, i + 1),
                ))
            }
        };
        t.push(num(0)?);
        x.push(num(1 + channel)?);
    }
    if t.len() < 2 {
        return Err(content(path, "fewer than two rows"));
    }
    let dt = (t[t.len() - 1] - t[0]) / (t.len() - 1) as f64;
    if dt.is_nan() || dt <= 0.0 || t.windows(2).any(|w| ((w[1] - w[0]) - dt).abs() > 0.01 * dt) {
        return Err(content(path, "the time column must rise in equal steps"));
    }
    Ok(Signal {
        rate: 1.0 / dt,
        samples: x,
    })
}

/// Write a mono 16-bit WAV at `rate`, scaled so the largest sample is at
/// `peak` of full scale (for test signals and synthesis).
pub fn write_wav(path: &Path, sig: &Signal, peak: f64) -> Result<(), SignalFileError> {
    let bytes = wav_bytes(sig, peak).map_err(|message| SignalFileError::Write {
        path: path.display().to_string(),
        message,
    })?;
    std::fs::write(path, bytes).map_err(|e| SignalFileError::Write {
        path: path.display().to_string(),
        message: e.to_string(),
    })
}

/// The bytes of a mono 16-bit WAV file of `sig`, scaled as [`write_wav`]
/// scales (for serving sound without a file). The error is one line.
pub fn wav_bytes(sig: &Signal, peak: f64) -> Result<Vec<u8>, String> {
    if !(sig.rate.is_finite() && sig.rate >= 1.0 && sig.rate <= u32::MAX as f64) {
        return Err(format!("sample rate {} Hz is out of range", sig.rate));
    }
    let spec = hound::WavSpec {
        channels: 1,
        sample_rate: sig.rate.round() as u32,
        bits_per_sample: 16,
        sample_format: hound::SampleFormat::Int,
    };
    let mut cursor = std::io::Cursor::new(Vec::with_capacity(44 + 2 * sig.samples.len()));
    let err = |e: hound::Error| e.to_string();
    let mut w = hound::WavWriter::new(&mut cursor, spec).map_err(err)?;
    let max = sig.samples.iter().fold(0.0f64, |m, v| m.max(v.abs())).max(1e-300);
    for v in &sig.samples {
        w.write_sample((v / max * peak * 32767.0).round() as i16).map_err(err)?;
    }
    w.finalize().map_err(err)?;
    Ok(cursor.into_inner())
}

/// Read a modes file: CSV with columns `freq_hz,effective_mass_kg`.
pub fn read_modes(path: &Path) -> Result<Vec<Mode>, SignalFileError> {
    #[derive(serde::Deserialize)]
    #[serde(deny_unknown_fields)]
    struct Row {
        freq_hz: f64,
        effective_mass_kg: f64,
    }
    let mut rdr = csv_reader(path, "a modes file")?;
    let mut out = vec![];
    for (k, row) in rdr.deserialize::<Row>().enumerate() {
        let r = row.map_err(|e| content(path, format!("row {}: {}", k + 1, e.to_string().replace('\n', " "))))?;
        out.push(Mode {
            freq_hz: r.freq_hz,
            effective_mass: r.effective_mass_kg,
        });
    }
    clapper_core::vibration::validate_modes(&out).map_err(|e| content(path, e.to_string()))?;
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wav_round_trip_any_depth_and_channel() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("s.wav");
        let sig = Signal {
            rate: 8000.0,
            samples: (0..800).map(|i| (i as f64 * 0.1).sin()).collect(),
        };
        write_wav(&p, &sig, 0.9).unwrap();
        let back = read_signal(&p, 0).unwrap();
        assert_eq!(back.rate, 8000.0);
        assert_eq!(back.samples.len(), 800);
        assert!((back.samples[5] - 0.9 * (0.5f64).sin()).abs() < 1e-3);
        // 24-bit stereo, second channel.
        let p2 = dir.path().join("st.wav");
        let spec = hound::WavSpec {
            channels: 2,
            sample_rate: 44100,
            bits_per_sample: 24,
            sample_format: hound::SampleFormat::Int,
        };
        let mut w = hound::WavWriter::create(&p2, spec).unwrap();
        for i in 0..100 {
            w.write_sample(0i32).unwrap();
            w.write_sample(i * 1000).unwrap();
        }
        w.finalize().unwrap();
        let s = read_signal(&p2, 1).unwrap();
        assert!((s.samples[10] - 10000.0 / 8388608.0).abs() < 1e-12);
        assert!(read_signal(&p2, 2).unwrap_err().to_string().contains("channel 2"));
    }

    #[test]
    fn bad_files_are_refused_with_a_reason() {
        let dir = tempfile::tempdir().unwrap();
        let put = |name: &str, text: &[u8]| {
            let p = dir.path().join(name);
            std::fs::write(&p, text).unwrap();
            p
        };
        let cases = [
            (put("a.wav", b"this is not a wav"), "not a WAV"),
            (put("b.wav", b""), "not a WAV"),
            (put("c.csv", b"t_s\n0\n1\n"), "value column"),
            (put("d.csv", b"t_s,v\n0,1\n0.1,NaN\n0.2,1\n"), "not finite"),
            (put("e.csv", b"t_s,v\n0,1\n0.1,x\n"), "not a number"),
            (put("f.csv", b"t_s,v\n0,1\n0.1,2\n0.5,3\n"), "equal steps"),
            (put("g.txt", b"1,2"), ".wav or .csv"),
        ];
        for (p, needle) in cases {
            let e = read_signal(&p, 0).unwrap_err().to_string();
            assert!(e.contains(needle) && !e.contains('\n'), "{e}");
        }
        let m = put("m.csv", b"freq_hz,effective_mass_kg\n624,15\n981,-1\n");
        assert!(read_modes(&m).unwrap_err().to_string().contains("effective_mass_kg"));
    }
}
