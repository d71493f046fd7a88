//! Strike times written for striking-analysis tools: the Lowndes format
//! (one blow a line: stroke letter, bell character, time in ms from the
//! first blow as four hex digits, wrapping at 65536 ms; structured comments
//! first) and CSV.

use std::fmt::Write as _;

/// Bell characters of the Lowndes format, bell 1 first: 1–9, 0 (10),
/// E (11), T (12), then A to D.
const BELL_CHARS: &[u8; 16] = b"1234567890ETABCD";

/// The Lowndes text for `blows` (bell from 1, handstroke, time ms), in
/// time order, from the recording `source`. At most 16 bells.
pub fn lowndes(blows: &[(usize, bool, f64)], source: &str, bells: usize) -> Result<String, String> {
    if bells == 0 || bells > BELL_CHARS.len() {
        return Err(format!("{bells} bells: the Lowndes format holds 1 to 16"));
    }
    let first = blows.first().map_or(0.0, |b| b.2).round();
    let mut o = String::new();
    let _ = writeln!(o, "#. Lowndes: Version 2");
    let _ = writeln!(o, "#. SourceFilename: {}", source.replace(['\n', '\r'], " "));
    let _ = writeln!(o, "#. NumBellsRinging: {bells}");
    let _ = writeln!(o, "#. FirstBlowMs: {first:.0}");
    let _ = writeln!(o, "#. Creator: clapper {}", env!("CARGO_PKG_VERSION"));
    for &(bell, hand, t) in blows {
        if !(1..=bells).contains(&bell) {
            return Err(format!("bell {bell}: not one of the {bells}"));
        }
        let ms = ((t.round() - first).max(0.0) as u64) % 65536;
        let _ = writeln!(
            o,
            "{} {} 0X{ms:04x}",
            if hand { 'H' } else { 'B' },
            BELL_CHARS[bell - 1] as char
        );
    }
    Ok(o)
}

/// CSV text of `rows` (the first the header).
pub fn csv_text<const N: usize>(rows: &[[String; N]]) -> Result<String, String> {
    let mut w = csv::Writer::from_writer(vec![]);
    for r in rows {
        w.write_record(r).map_err(|e| e.to_string())?;
    }
    let bytes = w.into_inner().map_err(|e| e.to_string())?;
    String::from_utf8(bytes).map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lowndes_lines_are_stroke_bell_and_hex_ms_from_the_first_blow() {
        let t = lowndes(
            &[
                (1, true, 1000.4),
                (10, false, 1250.0),
                (12, true, 1000.0 + 65536.0 + 17.0),
            ],
            "a.wav",
            12,
        )
        .unwrap();
        let lines: Vec<&str> = t.lines().filter(|l| !l.starts_with("#.")).collect();
        assert_eq!(lines, ["H 1 0X0000", "B 0 0X00fa", "H T 0X0011"]);
        assert!(t.contains("#. FirstBlowMs: 1000"));
        assert!(lowndes(&[], "a", 17).is_err());
        assert!(lowndes(&[(3, true, 0.0)], "a", 2).is_err());
    }

    #[test]
    fn csv_quotes_what_needs_it() {
        let rows = [["a".to_string(), "b,c".to_string()]];
        assert_eq!(csv_text(&rows).unwrap(), "a,\"b,c\"\n");
    }
}
