//! Recorded signals: WAV (any common bit depth and rate, mono or a chosen
//! channel) or CSV (a time column and a value column), and modes files.

use std::path::Path;

use clapper_core::vibration::Mode;
use clapper_signal::Signal;

pub use crate::channels::ChannelChoice;

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
/// by position after the time column (CSV); errors name it as a user
/// counts, from 1.
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
/// to one by their mean, or the loudest if their mean cancels, or one
/// heard alone where they disagree in time; 8- to 32-bit integer or 32-
/// or 64-bit float samples).
pub fn read_recording(path: &Path) -> Result<Signal, SignalFileError> {
    read_recording_told(path).map(|(sig, _)| sig)
}

/// A recording of a ring from the bytes of a WAV file (an upload, say),
/// as [`read_recording`]; `name` is how errors name it.
pub fn recording_from_bytes(bytes: &[u8], name: &str) -> Result<Signal, SignalFileError> {
    recording_from_bytes_told(bytes, name).map(|(sig, _)| sig)
}

/// [`read_recording`], with what the report should be told of the file
/// in words: its channels disagreeing in time (then one is heard alone).
pub fn read_recording_told(path: &Path) -> Result<(Signal, Vec<String>), SignalFileError> {
    read_recording_chosen(path, ChannelChoice::Auto)
}

/// [`read_recording_told`], its channels heard as `choice` asks.
pub fn read_recording_chosen(path: &Path, choice: ChannelChoice) -> Result<(Signal, Vec<String>), SignalFileError> {
    let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    if ext.as_deref() != Some("wav") {
        return Err(content(path, "a recording must be a .wav file"));
    }
    let bytes = std::fs::read(path).map_err(|e| SignalFileError::Read {
        path: path.display().to_string(),
        message: e.to_string(),
    })?;
    recording_from_bytes_chosen(&bytes, &path.display().to_string(), choice)
}

/// [`recording_from_bytes`], with what the report should be told of the
/// file in words ([`read_recording_told`]).
pub fn recording_from_bytes_told(bytes: &[u8], name: &str) -> Result<(Signal, Vec<String>), SignalFileError> {
    recording_from_bytes_chosen(bytes, name, ChannelChoice::Auto)
}

/// [`recording_from_bytes_told`], its channels heard as `choice` asks.
pub fn recording_from_bytes_chosen(
    bytes: &[u8],
    name: &str,
    choice: ChannelChoice,
) -> Result<(Signal, Vec<String>), SignalFileError> {
    let here = Path::new(name);
    let (rate, nch, all) = decode_wav(bytes).map_err(|m| content(here, m))?;
    let mut times = crate::channels::ChannelTimes::new(nch, rate);
    if nch > 1 {
        for f in all.chunks_exact(nch) {
            if times.full() {
                break;
            }
            times.push(f);
        }
    }
    let (one, told) = crate::channels::decide(choice, nch, &times).map_err(|m| content(here, m))?;
    let samples = match one {
        Some(k) => all.iter().skip(k).step_by(nch).copied().collect(),
        None => mix_to_one(&all, nch),
    };
    if samples.is_empty() {
        return Err(content(here, "no samples"));
    }
    let sig = Signal { rate, samples };
    sig.validate().map_err(|e| content(here, e.to_string()))?;
    Ok((sig, told))
}

/// Interleaved channels mixed to one: their mean, unless that cancels
/// (a microphone wired in antiphase, or stereo made by inverting one
/// side: the mean of the two holds less than a quarter of their power,
/// and a ring would read as silence), when the loudest channel is taken.
fn mix_to_one(all: &[f64], nch: usize) -> Vec<f64> {
    let mean: Vec<f64> = all
        .chunks_exact(nch)
        .map(|f| f.iter().sum::<f64>() / nch as f64)
        .collect();
    if nch < 2 {
        return mean;
    }
    let power = |k: usize| all.iter().skip(k).step_by(nch).map(|v| v * v).sum::<f64>();
    let powers: Vec<f64> = (0..nch).map(power).collect();
    let mean_power: f64 = mean.iter().map(|v| v * v).sum();
    let channel_power = powers.iter().sum::<f64>() / nch as f64;
    if mean_power >= 0.25 * channel_power {
        return mean;
    }
    // The first of the loudest (max_by would take the last of equals).
    let loudest = (1..nch).fold(0, |best, k| if powers[k] > powers[best] { k } else { best });
    all.iter().skip(loudest).step_by(nch).copied().collect()
}

fn read_wav(path: &Path, channel: usize) -> Result<Signal, SignalFileError> {
    let bytes = std::fs::read(path).map_err(|e| SignalFileError::Read {
        path: path.display().to_string(),
        message: e.to_string(),
    })?;
    let (rate, nch, all) = decode_wav(&bytes).map_err(|m| content(path, m))?;
    if channel >= nch {
        return Err(content(
            path,
            // Said as a user counts channels, from 1 (`--channel`).
            format!("channel {} asked, the file has {nch} (1 to {nch})", channel + 1),
        ));
    }
    let samples: Vec<f64> = all.iter().skip(channel).step_by(nch).copied().collect();
    if samples.is_empty() {
        return Err(content(path, "no samples"));
    }
    Ok(Signal { rate, samples })
}

/// The chunks of a RIFF WAVE file that matter: the format's bytes and the
/// samples' bytes (cut to what the file holds).
#[derive(Clone, Copy)]
struct WavChunks<'a> {
    fmt: &'a [u8],
    data: &'a [u8],
    /// Whether the file is laid out as hound reads it: no chunk of odd
    /// length before the samples (RIFF pads those to an even length, which
    /// hound does not skip; Python's `wave` and most editors write them,
    /// e.g. an odd-length LIST chunk of tags).
    plain: bool,
}

/// Walk the RIFF chunks of `bytes`, honouring the pad byte after a chunk
/// of odd length. `None` if it is not RIFF WAVE with `fmt ` and `data`.
fn wav_chunks(bytes: &[u8]) -> Option<WavChunks<'_>> {
    if bytes.len() < 12 || &bytes[..4] != b"RIFF" || &bytes[8..12] != b"WAVE" {
        return None;
    }
    let (mut at, mut fmt, mut plain) = (12usize, None, true);
    // Each step moves on by at least 8 bytes: bounded by the length.
    while at + 8 <= bytes.len() {
        let id = &bytes[at..at + 4];
        let size = u32::from_le_bytes(bytes[at + 4..at + 8].try_into().ok()?) as usize;
        let body = at + 8;
        let end = body.saturating_add(size).min(bytes.len());
        if id == b"data" {
            return Some(WavChunks {
                fmt: fmt?,
                data: &bytes[body..end],
                plain,
            });
        }
        if id == b"fmt " {
            fmt = Some(&bytes[body..end]);
        }
        plain &= size % 2 == 0;
        at = body.saturating_add(size).saturating_add(size % 2);
    }
    None
}

/// Sample rate (Hz), channels and interleaved samples (full scale 1) of
/// a WAV file's bytes: integer PCM of 8 to 32 bits and float of 32 bits by
/// hound; 64-bit float (which hound refuses) and files with padded odd
/// chunks read here.
fn decode_wav(bytes: &[u8]) -> Result<(f64, usize, Vec<f64>), String> {
    let chunks = wav_chunks(bytes);
    if let Some(c) = chunks.as_ref().filter(|c| c.fmt.len() >= 16) {
        let u16_at = |i: usize| u16::from_le_bytes([c.fmt[i], c.fmt[i + 1]]);
        let mut tag = u16_at(0);
        // WAVE_FORMAT_EXTENSIBLE: the format is the sub-format GUID's first two bytes.
        if tag == 0xFFFE && c.fmt.len() >= 26 {
            tag = u16_at(24);
        }
        let nch = usize::from(u16_at(2)).max(1);
        let rate = f64::from(u32::from_le_bytes(
            c.fmt[4..8].try_into().map_err(|_| "short fmt chunk")?,
        ));
        let bits = u16_at(14);
        if tag == 3 && bits == 64 {
            let all = c
                .data
                .chunks_exact(8)
                .map(|b| f64::from_le_bytes(b.try_into().expect("8 bytes")))
                .collect();
            return Ok((rate, nch, all));
        }
        // hound takes a format chunk of 16, 18 or 40 bytes; some writers
        // pad a plain PCM or float one to 20 (its extra bytes unused).
        let odd_fmt = !matches!(c.fmt.len(), 16 | 18 | 40) && matches!(tag, 1 | 3);
        if !c.plain || odd_fmt {
            let fmt = if odd_fmt { &c.fmt[..16] } else { c.fmt };
            let c = WavChunks { fmt, ..*c };
            // The same format and samples, laid out as hound reads them.
            let mut tidy = Vec::with_capacity(c.data.len() + c.fmt.len() + 28);
            tidy.extend_from_slice(b"RIFF");
            tidy.extend_from_slice(&((c.data.len() + c.fmt.len() + 20) as u32).to_le_bytes());
            tidy.extend_from_slice(b"WAVEfmt ");
            tidy.extend_from_slice(&(c.fmt.len() as u32).to_le_bytes());
            tidy.extend_from_slice(c.fmt);
            tidy.extend_from_slice(b"data");
            tidy.extend_from_slice(&(c.data.len() as u32).to_le_bytes());
            tidy.extend_from_slice(c.data);
            return decode_with_hound(&tidy);
        }
    }
    decode_with_hound(bytes)
}

fn decode_with_hound(bytes: &[u8]) -> Result<(f64, usize, Vec<f64>), String> {
    let mut r =
        hound::WavReader::new(std::io::Cursor::new(bytes)).map_err(|e| format!("not a WAV file this reads ({e})"))?;
    let spec = r.spec();
    let nch = usize::from(spec.channels.max(1));
    let all: Vec<f64> = match spec.sample_format {
        hound::SampleFormat::Float => r
            .samples::<f32>()
            .map(|s| s.map(f64::from))
            .collect::<Result<_, _>>()
            .map_err(|e| e.to_string())?,
        hound::SampleFormat::Int => {
            let scale = 2f64.powi(spec.bits_per_sample as i32 - 1);
            r.samples::<i32>()
                .map(|s| s.map(|v| f64::from(v) / scale))
                .collect::<Result<_, _>>()
                .map_err(|e| e.to_string())?
        }
    };
    Ok((f64::from(spec.sample_rate), nch, all))
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
        assert!(read_signal(&p2, 2)
            .unwrap_err()
            .to_string()
            .contains("channel 3 asked, the file has 2 (1 to 2)"));
    }

    /// A WAV with a LIST chunk of odd length (padded, as RIFF wants) before
    /// its samples, and one of 64-bit floats: both read, as Python's
    /// `wave` and sound editors read them.
    #[test]
    fn padded_chunks_and_double_floats_are_read() {
        fn wav(tag: u16, bits: u16, extra: &[u8], data: &[u8]) -> Vec<u8> {
            let mut fmt = vec![];
            fmt.extend(tag.to_le_bytes());
            fmt.extend(1u16.to_le_bytes());
            fmt.extend(8000u32.to_le_bytes());
            fmt.extend((8000 * u32::from(bits / 8)).to_le_bytes());
            fmt.extend((bits / 8).to_le_bytes());
            fmt.extend(bits.to_le_bytes());
            let mut b = b"RIFF\0\0\0\0WAVEfmt ".to_vec();
            b.extend((fmt.len() as u32).to_le_bytes());
            b.extend(&fmt);
            b.extend(extra);
            b.extend(b"data");
            b.extend((data.len() as u32).to_le_bytes());
            b.extend(data);
            let n = (b.len() - 8) as u32;
            b[4..8].copy_from_slice(&n.to_le_bytes());
            b
        }
        let pcm: Vec<u8> = [1000i16, -2000, 3000].iter().flat_map(|v| v.to_le_bytes()).collect();
        let mut list = b"LIST".to_vec();
        list.extend(5u32.to_le_bytes());
        list.extend(b"INFOa\0");
        let padded = wav(1, 16, &list, &pcm);
        let sig = recording_from_bytes(&padded, "padded.wav").unwrap();
        assert_eq!(sig.samples.len(), 3);
        assert!((sig.samples[1] + 2000.0 / 32768.0).abs() < 1e-12);
        let doubles: Vec<u8> = [0.25f64, -0.5, 0.125].iter().flat_map(|v| v.to_le_bytes()).collect();
        let sig = recording_from_bytes(&wav(3, 64, &[], &doubles), "f64.wav").unwrap();
        assert_eq!(sig.samples, vec![0.25, -0.5, 0.125]);
        // A PCM format chunk padded to 20 bytes (hound: "unexpected fmt chunk size").
        let mut long = wav(1, 16, &[], &pcm);
        long[16..20].copy_from_slice(&20u32.to_le_bytes());
        long.splice(36..36, [0u8; 4]);
        let n = (long.len() - 8) as u32;
        long[4..8].copy_from_slice(&n.to_le_bytes());
        assert_eq!(recording_from_bytes(&long, "fmt20.wav").unwrap().samples.len(), 3);
        assert_eq!(sig.rate, 8000.0);
    }

    #[test]
    fn channels_in_antiphase_are_not_mixed_to_silence() {
        let wave: Vec<f64> = (0..100).map(|k| (k as f64 * 0.3).sin() * 0.5).collect();
        let anti: Vec<f64> = wave.iter().flat_map(|&v| [v, -v]).collect();
        assert_eq!(mix_to_one(&anti, 2), wave);
        let same: Vec<f64> = wave.iter().flat_map(|&v| [v, 0.5 * v]).collect();
        let mixed = mix_to_one(&same, 2);
        assert!((mixed[7] - 0.75 * wave[7]).abs() < 1e-15);
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
