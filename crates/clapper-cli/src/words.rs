//! Error messages in the words the user wrote. The library crates name a
//! value by its key in a bell file or a request (`stay_deg = -1 is out of
//! range`), which is what a file's or the web API's user wrote; on the
//! command line the user wrote an option (`--stay -1`), and the message
//! should say that.

/// The endings a key has beyond its option's name: its unit.
const UNITS: [&str; 12] = [
    "deg",
    "m",
    "mm",
    "n",
    "kg",
    "s",
    "ms",
    "hz",
    "n_m",
    "n_m_s",
    "n_m_per_rad",
    "rad",
];

/// Keys a range option's ends are checked under (the chart's axes).
const ALIASES: [(&str, &str); 2] = [("lb_range", "lb_over_lc"), ("r_range", "r_over_lc")];

/// Whether `key` (a file or request key) is option `opt` (its name without
/// the dashes, in snake case): the same name, the name with a unit
/// (`stay` -> `stay_deg`), or the key qualified by the option
/// (`bell_swings_to_halve` -> `swings_to_halve`).
fn names(opt: &str, key: &str) -> bool {
    opt == key
        || ALIASES.contains(&(opt, key))
        || key
            .strip_prefix(opt)
            .and_then(|rest| rest.strip_prefix('_'))
            .is_some_and(|unit| UNITS.contains(&unit))
        || opt.strip_suffix(key).is_some_and(|head| head.ends_with('_'))
}

/// The options given on the command line `args` (after the program's
/// name), each with the value written after it: `--stay -1` and
/// `--stay=-1` alike.
fn given(args: &[String]) -> Vec<(String, Option<String>)> {
    let mut out = vec![];
    for (i, a) in args.iter().enumerate() {
        let Some(name) = a.strip_prefix("--") else {
            continue;
        };
        match name.split_once('=') {
            Some((n, v)) => out.push((n.to_string(), Some(v.to_string()))),
            None => out.push((name.to_string(), args.get(i + 1).cloned())),
        }
    }
    out
}

/// `message` with each `key = value` of a value given on the command line
/// said as the option and the value as written (`--stay -1`). A key no
/// option given names, or that two options given might name, is left as
/// it is (it came from a file, which spells it so).
pub fn as_given(message: &str, args: &[String]) -> String {
    let options = given(args);
    let mut out = String::with_capacity(message.len());
    let mut rest = message;
    while let Some(at) = rest.find(" = ") {
        let head = &rest[..at];
        let start = head
            .rfind(|c: char| !(c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_'))
            .map_or(0, |i| i + 1);
        let key = &head[start..];
        let after = &rest[at + 3..];
        let value_len = after.find(' ').unwrap_or(after.len());
        let matches: Vec<&(String, Option<String>)> = options
            .iter()
            .filter(|(o, _)| !key.is_empty() && names(&o.replace('-', "_"), key))
            .collect();
        match matches.as_slice() {
            [(opt, value)] => {
                out.push_str(&head[..start]);
                out.push_str("--");
                out.push_str(opt);
                out.push(' ');
                out.push_str(value.as_deref().unwrap_or(&after[..value_len]));
                rest = &after[value_len..];
            }
            _ => {
                out.push_str(&rest[..at + 3]);
                rest = after;
            }
        }
    }
    out.push_str(rest);
    out
}

/// Digits beyond which a number in a message is said in short scientific
/// form: a u64 (20 digits) stays as it is.
const LONG_NUMBER: usize = 21;

/// `message` with each number written in more than [`LONG_NUMBER`] digits
/// (`1e300` formatted as 301 of them, `1e-300` as 0.000...) said in short
/// scientific form (`1e300`, `1e-300`).
pub fn short_numbers(message: &str) -> String {
    let mut out = String::with_capacity(message.len());
    let mut rest = message;
    while let Some(start) = rest.find(|c: char| c.is_ascii_digit()) {
        out.push_str(&rest[..start]);
        let tail = &rest[start..];
        let len = tail
            .find(|c: char| !(c.is_ascii_digit() || c == '.'))
            .unwrap_or(tail.len());
        // A full stop after the number ends the sentence.
        let number = tail[..len].trim_end_matches('.');
        let digits = number.chars().filter(char::is_ascii_digit).count();
        match number.parse::<f64>() {
            Ok(v) if digits > LONG_NUMBER => out.push_str(&format!("{v:e}")),
            _ => out.push_str(number),
        }
        rest = &tail[number.len()..];
    }
    out.push_str(rest);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_long_number_is_said_in_short_scientific_form() {
        let big = format!("{}", 1e300);
        let tiny = format!("{}", -1e-300);
        assert_eq!(
            short_numbers(&format!("--sensor-m {big} m: within 2 m; {tiny}.")),
            "--sensor-m 1e300 m: within 2 m; -1e-300."
        );
        let m = "seed 18446744073709551615, 1.5 s at 96000 Hz, v0.1.0.";
        assert_eq!(short_numbers(m), m);
    }

    fn args(s: &str) -> Vec<String> {
        s.split(' ').map(String::from).collect()
    }

    #[test]
    fn a_key_of_an_option_given_is_said_as_the_option() {
        let m = "stay_deg = -1 is out of range: between 0 and 180 deg, exclusive";
        assert_eq!(
            as_given(m, &args("ring-up --stay -1")),
            "--stay -1 is out of range: between 0 and 180 deg, exclusive"
        );
        assert_eq!(
            as_given(
                "x: pull_window_deg = 1.0000000000000001e9 is out",
                &args("ring-up --pull-window=1e9")
            ),
            "x: --pull-window 1e9 is out"
        );
        assert_eq!(
            as_given(
                "swings_to_halve = 0 is out",
                &args("simulate --clapper-swings-to-halve 0")
            ),
            "--clapper-swings-to-halve 0 is out"
        );
    }

    #[test]
    fn a_chart_axis_is_said_as_its_range_option() {
        let m = "lb_over_lc = -1 is out of range: a finite number > 0";
        assert_eq!(
            as_given(m, &args("chart --lb-range -1,2")),
            "--lb-range -1,2 is out of range: a finite number > 0"
        );
    }

    #[test]
    fn a_key_from_a_file_or_two_options_is_left_as_written() {
        let m = "pivot_offset_m = 1 is out of range";
        assert_eq!(as_given(m, &args("simulate --bell b.toml")), m);
        let m = "swings_to_halve = 0 is out";
        assert_eq!(
            as_given(
                m,
                &args("simulate --bell-swings-to-halve 0 --clapper-swings-to-halve 5")
            ),
            m
        );
        // restitution_later is not --restitution with a unit.
        let m = "restitution_later = 2 is out";
        assert_eq!(as_given(m, &args("simulate --restitution 0.3")), m);
    }
}
