//! Reading a file that should be text (a bell file, a log, a CSV), and
//! saying what it is when it is not: a WAV recording given where a bell
//! file or an accelerometer log was wanted is named as one, with the
//! commands that read recordings, rather than "stream did not contain
//! valid UTF-8".

use std::path::Path;

/// What a file that is not text is, told by its first bytes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BinaryKind {
    /// A RIFF WAVE sound file.
    Wav,
    /// A PNG image.
    Png,
    /// A GIF image.
    Gif,
    /// A JPEG image.
    Jpeg,
    /// A PDF document.
    Pdf,
    /// A zip archive (also a spreadsheet saved as .xlsx or .ods).
    Zip,
    /// Bytes that are not UTF-8 text, of no kind named here.
    Unknown,
}

impl BinaryKind {
    /// The kind of `bytes` if they start as a binary format does, or are
    /// not text (not UTF-8, or holding a NUL byte); `None` for text.
    /// Magic numbers are looked at first: a WAV of silence is all NULs
    /// after its header, and so may be valid UTF-8.
    pub fn of(bytes: &[u8]) -> Option<Self> {
        let kind = if bytes.len() >= 12 && &bytes[..4] == b"RIFF" && &bytes[8..12] == b"WAVE" {
            Self::Wav
        } else if bytes.starts_with(b"\x89PNG") {
            Self::Png
        } else if bytes.starts_with(b"GIF8") {
            Self::Gif
        } else if bytes.starts_with(b"\xff\xd8\xff") {
            Self::Jpeg
        } else if bytes.starts_with(b"%PDF") {
            Self::Pdf
        } else if bytes.starts_with(b"PK\x03\x04") {
            Self::Zip
        } else if std::str::from_utf8(bytes).is_err() || bytes.contains(&0) {
            Self::Unknown
        } else {
            return None;
        };
        Some(kind)
    }

    /// The kind in words, with an article: "a WAV recording".
    pub fn words(self) -> &'static str {
        match self {
            Self::Wav => "a WAV recording",
            Self::Png => "a PNG image",
            Self::Gif => "a GIF image",
            Self::Jpeg => "a JPEG image",
            Self::Pdf => "a PDF document",
            Self::Zip => "a zip archive (a spreadsheet? save it as CSV)",
            Self::Unknown => "not a text file",
        }
    }
}

/// A file given where text was wanted that is not text. One line: what
/// the file is, what was wanted, and for a recording, which commands
/// read recordings.
#[derive(Debug, thiserror::Error)]
#[error("{}", self.message())]
pub struct NotText {
    /// The file.
    pub path: String,
    /// What it is.
    pub kind: BinaryKind,
    /// What was wanted, with an article: "a bell file".
    pub wanted: &'static str,
}

impl NotText {
    fn message(&self) -> String {
        format!("{} is {}", self.path, self.what())
    }

    /// What the file is and what was wanted, without its path: "a WAV
    /// recording, not a bell file: recordings are read by ...".
    pub fn what(&self) -> String {
        let wanted = self.wanted;
        match self.kind {
            BinaryKind::Wav => format!(
                "a WAV recording, not {wanted}: recordings are read by clapper strikes (a ring), \
                 clapper spectrogram, decay, modes, contacts, restitution --accel and diagnose --recording"
            ),
            BinaryKind::Unknown => format!("not a text file (not UTF-8): {wanted} is text"),
            kind => format!("{}, not {wanted}", kind.words()),
        }
    }
}

/// Why a text file could not be read. Callers put an `Io` error in
/// their own words ("cannot read bell file ..."); `NotText` names the file.
#[derive(Debug, thiserror::Error)]
pub enum ReadTextError {
    /// The file could not be read at all (missing, no permission).
    #[error("{0}")]
    Io(std::io::Error),
    /// It was read, but is not text.
    #[error("{0}")]
    NotText(NotText),
}

/// How much of a text input is looked at before the rest is read (bytes).
pub const HEAD_BYTES: usize = 64 << 10;

/// The largest text input read (bytes): 512 MiB. A 10 kHz accelerometer
/// log of an hour is about 1.4 GB and is better decimated; a 100 Hz log of
/// a day, 350 MB, fits.
pub const MAX_TEXT_BYTES: usize = 512 << 20;

/// Read `path` as text; `wanted` is what the caller expects it to be
/// ("a bell file"), for the message when it is not text.
///
/// Bounded: the first [`HEAD_BYTES`] are looked at before the rest is
/// read (`/dev/zero` or a disk image is named as not text at once, not
/// read until memory runs out), and a text longer than [`MAX_TEXT_BYTES`]
/// is refused with its size.
pub fn read_text(path: &Path, wanted: &'static str) -> Result<String, ReadTextError> {
    use std::io::Read as _;
    let not_text = |kind| {
        ReadTextError::NotText(NotText {
            path: path.display().to_string(),
            kind,
            wanted,
        })
    };
    let mut file = std::fs::File::open(path).map_err(ReadTextError::Io)?;
    let mut bytes = Vec::new();
    (&mut file)
        .take(HEAD_BYTES as u64)
        .read_to_end(&mut bytes)
        .map_err(ReadTextError::Io)?;
    // The head may end inside a character: only bytes that cannot start
    // one, or a NUL, make it binary here.
    let head_kind = match std::str::from_utf8(&bytes) {
        Err(e) if e.error_len().is_none() => BinaryKind::of(&bytes[..e.valid_up_to()]),
        _ => BinaryKind::of(&bytes),
    };
    if let Some(kind) = head_kind {
        return Err(not_text(kind));
    }
    file.take((MAX_TEXT_BYTES - HEAD_BYTES) as u64 + 1)
        .read_to_end(&mut bytes)
        .map_err(ReadTextError::Io)?;
    if bytes.len() > MAX_TEXT_BYTES {
        return Err(ReadTextError::Io(std::io::Error::other(format!(
            "larger than {} MiB, the most a text input may be here (split it, or decimate a log)",
            MAX_TEXT_BYTES >> 20
        ))));
    }
    if let Some(kind) = BinaryKind::of(&bytes) {
        return Err(not_text(kind));
    }
    // Checked by `BinaryKind::of`.
    String::from_utf8(bytes).map_err(|e| ReadTextError::Io(std::io::Error::new(std::io::ErrorKind::InvalidData, e)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_endless_device_is_named_not_read() {
        // /dev/zero has no end: read whole, it filled memory.
        if Path::new("/dev/zero").exists() {
            match read_text(Path::new("/dev/zero"), "an accelerometer log") {
                Err(ReadTextError::NotText(e)) => assert_eq!(e.kind, BinaryKind::Unknown),
                other => panic!("{other:?}"),
            }
        }
        // A character cut by the head's end is still text.
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("t.txt");
        let mut text = "a".repeat(HEAD_BYTES - 1);
        text.push_str("° and more\n");
        std::fs::write(&p, &text).unwrap();
        assert_eq!(read_text(&p, "a log").unwrap(), text);
    }

    #[test]
    fn binary_files_are_told_by_their_first_bytes() {
        let mut wav = b"RIFF\x24\x00\x00\x00WAVEfmt ".to_vec();
        wav.extend([0u8; 40]);
        assert_eq!(BinaryKind::of(&wav), Some(BinaryKind::Wav));
        assert_eq!(BinaryKind::of(b"\x89PNG\r\n\x1a\n"), Some(BinaryKind::Png));
        assert_eq!(BinaryKind::of(b"a,b\n1,\xff\n"), Some(BinaryKind::Unknown));
        assert_eq!(BinaryKind::of(b"a\0b"), Some(BinaryKind::Unknown));
        assert_eq!(BinaryKind::of("r_m = 0.1 # ° ok\n".as_bytes()), None);
        assert_eq!(BinaryKind::of(b""), None);
    }
}
