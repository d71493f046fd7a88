//! A recording of a ring read in blocks (issue 46): a WAV file's samples
//! come off the disk a block at a time, mixed to one channel as
//! [`read_recording`](crate::signal_file::read_recording) mixes them, so
//! hours of audio are listened to in memory that does not grow with them.
//!
//! Streamed: integer PCM of 8, 16, 24 or 32 bits and float of 32 or 64
//! bits, the samples packed (a frame is channels x bytes per sample),
//! plain or WAVE_FORMAT_EXTENSIBLE with every bit valid. Any other layout
//! ([`WavStream::open`] returns `None`) is read whole, as before.

use std::fs::File;
use std::io::{BufReader, Read, Seek, SeekFrom};
use std::path::{Path, PathBuf};

use clapper_signal::strikes::RecordingBlocks;
use clapper_signal::SignalError;

use crate::signal_file::{ChannelChoice, SignalFileError};

/// How one sample is stored.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Kind {
    /// Unsigned 8-bit, 128 the middle.
    U8,
    /// Signed little-endian integers of 2, 3 or 4 bytes.
    Int(usize),
    /// 32-bit float.
    F32,
    /// 64-bit float.
    F64,
}

impl Kind {
    fn bytes(self) -> usize {
        match self {
            Kind::U8 => 1,
            Kind::Int(b) => b,
            Kind::F32 => 4,
            Kind::F64 => 8,
        }
    }

    /// The sample at the start of `b`, full scale 1 (as hound reads it:
    /// the integer over 2^(bits − 1)).
    fn value(self, b: &[u8]) -> f64 {
        match self {
            Kind::U8 => f64::from(i32::from(b[0]) - 128) / 128.0,
            Kind::Int(2) => f64::from(i16::from_le_bytes([b[0], b[1]])) / 32768.0,
            // Sign-extended from the top byte.
            Kind::Int(3) => f64::from(i32::from_le_bytes([0, b[0], b[1], b[2]]) >> 8) / 8_388_608.0,
            Kind::Int(_) => f64::from(i32::from_le_bytes([b[0], b[1], b[2], b[3]])) / 2_147_483_648.0,
            Kind::F32 => f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            Kind::F64 => f64::from_le_bytes([b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7]]),
        }
    }
}

/// How the channels become one.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Mix {
    /// Their mean.
    Mean,
    /// One channel (the loudest, where the mean cancels; or the one heard
    /// alone where they disagree in time, or the one asked for).
    Channel(usize),
}

/// A WAV recording read in blocks, mixed to one channel.
pub struct WavStream {
    path: PathBuf,
    file: BufReader<File>,
    rate: f64,
    channels: usize,
    kind: Kind,
    /// Whole frames in the file.
    frames: usize,
    /// Frames read so far.
    done: usize,
    mix: Mix,
    bytes: Vec<u8>,
    /// What the report should be told of the file, in words
    /// ([`WavStream::warnings`]).
    warnings: Vec<String>,
}

/// Frames read from the disk at a time.
const FRAMES_PER_READ: usize = 16_384;

fn read_error(path: &Path, e: impl std::fmt::Display) -> SignalFileError {
    SignalFileError::Read {
        path: path.display().to_string(),
        message: e.to_string(),
    }
}

fn content(path: &Path, message: impl Into<String>) -> SignalFileError {
    SignalFileError::Content {
        path: path.display().to_string(),
        message: message.into(),
    }
}

/// The format chunk's bytes and where the data chunk's samples lie
/// (start, length in bytes, cut to the file), walking the RIFF chunks with
/// the pad byte after one of odd length; `None` if not RIFF WAVE with both.
fn find_chunks(file: &mut BufReader<File>, file_len: u64) -> std::io::Result<Option<(Vec<u8>, u64, u64)>> {
    let mut head = [0u8; 12];
    if file_len < 12 || file.read_exact(&mut head).is_err() || &head[..4] != b"RIFF" || &head[8..12] != b"WAVE" {
        return Ok(None);
    }
    let (mut at, mut fmt) = (12u64, None);
    // Each step moves on by at least 8 bytes: bounded by the length.
    while at + 8 <= file_len {
        file.seek(SeekFrom::Start(at))?;
        let mut h = [0u8; 8];
        file.read_exact(&mut h)?;
        let size = u64::from(u32::from_le_bytes([h[4], h[5], h[6], h[7]]));
        let body = at + 8;
        let end = (body + size).min(file_len);
        if &h[..4] == b"data" {
            return Ok(fmt.map(|f| (f, body, end - body)));
        }
        if &h[..4] == b"fmt " {
            // A format chunk is tens of bytes; a huge one is not a WAV file this streams.
            if end - body > 4096 {
                return Ok(None);
            }
            let mut f = vec![0u8; (end - body) as usize];
            file.read_exact(&mut f)?;
            fmt = Some(f);
        }
        at = body + size + size % 2;
    }
    Ok(None)
}

/// The sample kind, channels and rate of a format chunk, if streamed here.
fn format_of(fmt: &[u8]) -> Option<(Kind, usize, f64)> {
    if fmt.len() < 16 {
        return None;
    }
    let u16_at = |i: usize| u16::from_le_bytes([fmt[i], fmt[i + 1]]);
    let mut tag = u16_at(0);
    let bits = u16_at(14);
    if tag == 0xFFFE {
        // WAVE_FORMAT_EXTENSIBLE: every bit valid, the sub-format's first two bytes the format.
        if fmt.len() < 26 || u16_at(18) != bits {
            return None;
        }
        tag = u16_at(24);
    }
    let channels = usize::from(u16_at(2));
    let rate = f64::from(u32::from_le_bytes([fmt[4], fmt[5], fmt[6], fmt[7]]));
    let kind = match (tag, bits) {
        (1, 8) => Kind::U8,
        (1, 16) => Kind::Int(2),
        (1, 24) => Kind::Int(3),
        (1, 32) => Kind::Int(4),
        (3, 32) => Kind::F32,
        (3, 64) => Kind::F64,
        _ => return None,
    };
    let packed = usize::from(u16_at(12)) == channels * kind.bytes();
    (channels >= 1 && packed && rate > 0.0).then_some((kind, channels, rate))
}

impl WavStream {
    /// Open `path` to be read in blocks, or `None` where its layout is one
    /// read whole ([`read_recording`](crate::signal_file::read_recording)).
    /// A file of several channels is read through once first, to choose
    /// the mix (their mean, or the loudest channel where the mean cancels,
    /// or one heard alone where they disagree in time).
    pub fn open(path: &Path) -> Result<Option<Self>, SignalFileError> {
        Self::open_chosen(path, ChannelChoice::Auto)
    }

    /// [`WavStream::open`], its channels heard as `choice` asks (as
    /// [`read_recording_chosen`](crate::signal_file::read_recording_chosen)
    /// hears them).
    pub fn open_chosen(path: &Path, choice: ChannelChoice) -> Result<Option<Self>, SignalFileError> {
        let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
        if ext.as_deref() != Some("wav") {
            return Err(content(path, "a recording must be a .wav file"));
        }
        let f = File::open(path).map_err(|e| read_error(path, e))?;
        let len = f.metadata().map_err(|e| read_error(path, e))?.len();
        let mut file = BufReader::with_capacity(1 << 16, f);
        let Some((fmt, data_start, data_len)) = find_chunks(&mut file, len).map_err(|e| read_error(path, e))? else {
            return Ok(None);
        };
        let Some((kind, channels, rate)) = format_of(&fmt) else {
            return Ok(None);
        };
        let frames = (data_len / (channels * kind.bytes()) as u64) as usize;
        if frames == 0 {
            return Err(content(path, "no samples"));
        }
        let mut s = WavStream {
            path: path.to_path_buf(),
            file,
            rate,
            channels,
            kind,
            frames,
            done: 0,
            mix: Mix::Mean,
            bytes: vec![],
            warnings: vec![],
        };
        s.mix = s.choose_mix(choice)?;
        s.file
            .seek(SeekFrom::Start(data_start))
            .map_err(|e| read_error(path, e))?;
        Ok(Some(s))
    }

    /// What the report should be told of the file in words, as
    /// [`read_recording_told`](crate::signal_file::read_recording_told)
    /// says it: its channels disagreeing in time.
    pub fn warnings(&self) -> &[String] {
        &self.warnings
    }

    /// Sample rate (Hz).
    pub fn sample_rate(&self) -> f64 {
        self.rate
    }

    /// The mix of the channels as `choice` asks: where they are mixed,
    /// from their powers over the whole file, as
    /// [`read_recording`](crate::signal_file::read_recording) chooses it
    /// (the same sums in the same order). A mono file is not read here.
    fn choose_mix(&mut self, choice: ChannelChoice) -> Result<Mix, SignalFileError> {
        let nch = self.channels;
        let mut told = crate::channels::ChannelTimes::new(nch, self.rate);
        if nch < 2 {
            let (one, _) = crate::channels::decide(choice, nch, &told).map_err(|m| content(&self.path, m))?;
            return Ok(one.map_or(Mix::Mean, Mix::Channel));
        }
        let mut powers = vec![0.0f64; nch];
        let mut mean_power = 0.0f64;
        let mut frame = vec![0.0; nch];
        while let Some(n) = self.next_frames()? {
            let w = nch * self.kind.bytes();
            for k in 0..n {
                for (c, v) in frame.iter_mut().enumerate() {
                    *v = self.kind.value(&self.bytes[k * w + c * self.kind.bytes()..]);
                    powers[c] += *v * *v;
                }
                let m = frame.iter().sum::<f64>() / nch as f64;
                mean_power += m * m;
                told.push(&frame);
            }
        }
        self.done = 0;
        let (one, words) = crate::channels::decide(choice, nch, &told).map_err(|m| content(&self.path, m))?;
        self.warnings.extend(words);
        if let Some(k) = one {
            return Ok(Mix::Channel(k));
        }
        let channel_power = powers.iter().sum::<f64>() / nch as f64;
        if mean_power >= 0.25 * channel_power {
            return Ok(Mix::Mean);
        }
        let loudest = (1..nch).fold(0, |best, k| if powers[k] > powers[best] { k } else { best });
        Ok(Mix::Channel(loudest))
    }

    /// The next frames' bytes into `self.bytes` (at most
    /// [`FRAMES_PER_READ`]), how many, or `None` at the end.
    fn next_frames(&mut self) -> Result<Option<usize>, SignalFileError> {
        let n = (self.frames - self.done).min(FRAMES_PER_READ);
        if n == 0 {
            return Ok(None);
        }
        self.bytes.resize(n * self.channels * self.kind.bytes(), 0);
        self.file
            .read_exact(&mut self.bytes)
            .map_err(|e| read_error(&self.path, e))?;
        self.done += n;
        Ok(Some(n))
    }
}

impl RecordingBlocks for WavStream {
    fn rate(&self) -> f64 {
        self.rate
    }

    fn total(&self) -> usize {
        self.frames
    }

    fn read(&mut self, out: &mut Vec<f64>, max: usize) -> Result<usize, SignalError> {
        let nch = self.channels;
        let (b, w) = (self.kind.bytes(), nch * self.kind.bytes());
        let mut got = 0;
        while got < max {
            let want = (self.frames - self.done).min(max - got).min(FRAMES_PER_READ);
            if want == 0 {
                break;
            }
            self.bytes.resize(want * w, 0);
            self.file
                .read_exact(&mut self.bytes)
                .map_err(|e| SignalError::Invalid(format!("{}: {e}", self.path.display())))?;
            for k in 0..want {
                let frame = &self.bytes[k * w..(k + 1) * w];
                let v = match self.mix {
                    Mix::Channel(c) => self.kind.value(&frame[c * b..]),
                    Mix::Mean if nch == 1 => self.kind.value(frame),
                    Mix::Mean => (0..nch).map(|c| self.kind.value(&frame[c * b..])).sum::<f64>() / nch as f64,
                };
                if !v.is_finite() {
                    return Err(SignalError::Invalid(format!(
                        "sample {} is not a finite number",
                        self.done + k
                    )));
                }
                out.push(v);
            }
            self.done += want;
            got += want;
        }
        Ok(got)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::signal_file::read_recording;

    fn wav(path: &Path, tag: u16, bits: u16, nch: u16, extra: &[u8], data: &[u8]) {
        let mut fmt = vec![];
        fmt.extend_from_slice(&tag.to_le_bytes());
        fmt.extend_from_slice(&nch.to_le_bytes());
        fmt.extend_from_slice(&8000u32.to_le_bytes());
        let align = nch * bits / 8;
        fmt.extend_from_slice(&(8000 * u32::from(align)).to_le_bytes());
        fmt.extend_from_slice(&align.to_le_bytes());
        fmt.extend_from_slice(&bits.to_le_bytes());
        let mut b = b"RIFF\0\0\0\0WAVEfmt ".to_vec();
        b.extend_from_slice(&(fmt.len() as u32).to_le_bytes());
        b.extend_from_slice(&fmt);
        b.extend_from_slice(extra);
        b.extend_from_slice(b"data");
        b.extend_from_slice(&(data.len() as u32).to_le_bytes());
        b.extend_from_slice(data);
        let n = (b.len() - 8) as u32;
        b[4..8].copy_from_slice(&n.to_le_bytes());
        std::fs::write(path, b).unwrap();
    }

    fn streamed(path: &Path, block: usize) -> Vec<f64> {
        let mut s = WavStream::open(path).unwrap().expect("streamed");
        let mut out = vec![];
        while s.read(&mut out, block).unwrap() > 0 {}
        assert_eq!(out.len(), s.total());
        out
    }

    /// Every layout streamed reads, in blocks of any size, the samples
    /// read whole give, bit for bit: 8- to 32-bit integers, 32- and
    /// 64-bit floats, channels mixed by their mean or (in antiphase) the
    /// loudest taken, and an odd-length chunk before the samples.
    #[test]
    fn streamed_samples_are_those_read_whole() {
        let dir = tempfile::tempdir().unwrap();
        let n = 40_000usize;
        let wave = |i: usize, c: usize| (0.001 * i as f64 * (1.0 + c as f64)).sin() * 0.7;
        let cases: Vec<(u16, u16, u16, bool, &[u8])> = vec![
            (1, 8, 1, false, b""),
            (1, 16, 1, false, b""),
            (1, 24, 2, false, b""),
            (1, 32, 1, false, b""),
            (3, 32, 3, false, b""),
            (3, 64, 1, false, b""),
            (1, 16, 2, true, b""),
            (1, 16, 1, false, b"LIST\x03\0\0\0abc\0"),
        ];
        for (k, (tag, bits, nch, antiphase, extra)) in cases.into_iter().enumerate() {
            let mut data = vec![];
            for i in 0..n {
                for c in 0..usize::from(nch) {
                    let mut v = wave(i, c);
                    if antiphase {
                        v = if c == 0 { wave(i, 0) } else { -0.9 * wave(i, 0) };
                    }
                    match (tag, bits) {
                        (1, 8) => data.push(((v * 127.0).round() as i32 + 128) as u8),
                        (1, 16) => data.extend_from_slice(&((v * 32767.0).round() as i16).to_le_bytes()),
                        (1, 24) => data.extend_from_slice(&((v * 8_388_607.0).round() as i32).to_le_bytes()[..3]),
                        (1, 32) => data.extend_from_slice(&((v * 2e9).round() as i32).to_le_bytes()),
                        (3, 32) => data.extend_from_slice(&(v as f32).to_le_bytes()),
                        _ => data.extend_from_slice(&v.to_le_bytes()),
                    }
                }
            }
            let p = dir.path().join(format!("{k}.wav"));
            wav(&p, tag, bits, nch, extra, &data);
            let whole = read_recording(&p).unwrap().samples;
            for block in [1000, 7, 100_000] {
                let s = streamed(&p, block);
                assert!(
                    s.iter().zip(&whole).all(|(a, b)| a.to_bits() == b.to_bits()) && s.len() == whole.len(),
                    "case {k} ({bits}-bit, {nch} channel(s)), blocks of {block}"
                );
            }
        }
    }

    /// A layout not streamed (12-bit samples in 16) is left to be read whole.
    #[test]
    fn other_layouts_are_left_to_be_read_whole() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("odd.wav");
        wav(&p, 1, 12, 1, b"", &[0u8; 64]);
        assert!(WavStream::open(&p).unwrap().is_none());
    }
    /// Tester16 fault 7: a stereo file whose second channel is 20 ms late
    /// is heard through its first channel alone, streamed as read whole,
    /// with the same words; asked to mix, the two are mixed; channels that
    /// agree are mixed as before.
    #[test]
    fn a_late_channel_is_left_out_streamed_as_read_whole() {
        use crate::signal_file::read_recording_chosen;
        let dir = tempfile::tempdir().unwrap();
        use crate::channels::tests::strike;
        let q = |v: f64| (v * 20000.0).round() as i16;
        for late_s in [0.02, 0.0] {
            let mut data = vec![];
            for i in 0..160_000 {
                let t = f64::from(i) / 8000.0;
                data.extend_from_slice(&q(strike(t)).to_le_bytes());
                data.extend_from_slice(&q(0.7 * strike(t - late_s)).to_le_bytes());
            }
            let p = dir.path().join(format!("st{late_s}.wav"));
            wav(&p, 1, 16, 2, b"", &data);
            let first: Vec<f64> = (0..160_000)
                .map(|i| f64::from(q(strike(f64::from(i) / 8000.0))) / 32768.0)
                .collect();
            for choice in [ChannelChoice::Auto, ChannelChoice::Mix, ChannelChoice::One(0)] {
                let (whole, told) = read_recording_chosen(&p, choice).unwrap();
                let mut s = WavStream::open_chosen(&p, choice).unwrap().unwrap();
                let mut streamed = vec![];
                while s.read(&mut streamed, 5000).unwrap() > 0 {}
                assert_eq!(s.warnings(), &told[..]);
                assert!(streamed
                    .iter()
                    .zip(&whole.samples)
                    .all(|(a, b)| a.to_bits() == b.to_bits()));
                let alone = late_s > 0.0 && choice == ChannelChoice::Auto || choice == ChannelChoice::One(0);
                assert_eq!(whole.samples == first, alone, "{late_s} {choice:?}");
                assert_eq!(told.len(), usize::from(late_s > 0.0 && choice != ChannelChoice::One(0)));
            }
            let e = WavStream::open_chosen(&p, ChannelChoice::One(2))
                .err()
                .unwrap()
                .to_string();
            assert!(e.contains("channel 3 asked, the recording has 2"), "{e}");
        }
    }
}
