//! Fuzzing every reader with proptest: arbitrary bytes, and valid files with
//! random bytes changed, cut short or spliced. Every input must give a value
//! or an error of one non-empty line; none may panic or hang. The number of
//! cases per reader is FUZZ_CASES (default 512; CI runs the default).

use std::path::Path;

use proptest::prelude::*;
use proptest::test_runner::Config;

fn cases() -> u32 {
    std::env::var("FUZZ_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(512)
}

fn examples(name: &str) -> String {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples").join(name);
    std::fs::read_to_string(root).unwrap()
}

/// A valid text with some bytes replaced, cut short, or a piece repeated.
fn mutated(valid: String) -> impl Strategy<Value = Vec<u8>> {
    let len = valid.len();
    (
        prop::collection::vec((0..len, any::<u8>()), 0..6),
        0..=len,
        any::<bool>(),
        0..len,
        0..len,
    )
        .prop_map(move |(edits, cut, splice, a, b)| {
            let mut v = valid.clone().into_bytes();
            for (i, byte) in edits {
                v[i] = byte;
            }
            if splice {
                let (a, b) = (a.min(b), a.max(b));
                let piece = v[a..b].to_vec();
                v.splice(a..a, piece);
            } else {
                v.truncate(cut);
            }
            v
        })
}

fn bytes_or_mutation(valid: String) -> impl Strategy<Value = Vec<u8>> {
    prop_oneof![prop::collection::vec(any::<u8>(), 0..400), mutated(valid)]
}

fn one_line<T, E: std::fmt::Display>(r: Result<T, E>) -> Result<(), TestCaseError> {
    if let Err(e) = r {
        let m = e.to_string();
        prop_assert!(!m.trim().is_empty(), "empty message");
        prop_assert!(!m.contains('\n'), "not one line: {m:?}");
    }
    Ok(())
}

proptest! {
    #![proptest_config(Config { cases: cases(), ..Config::default() })]

    #[test]
    fn bell_and_ring_toml(b in bytes_or_mutation(examples("table1-bells.toml") + &examples("lab-tower.toml"))) {
        let text = String::from_utf8_lossy(&b);
        one_line(clapper_io::parse_bells(&text, "fuzz"))?;
        one_line(clapper_io::parse_bell(&text, "fuzz"))?;
    }

    #[test]
    fn ring_csv(b in bytes_or_mutation(examples("ring-of-eight.csv"))) {
        one_line(clapper_io::parse_ring_csv(&String::from_utf8_lossy(&b)))?;
    }

    #[test]
    fn answer_sheets(b in bytes_or_mutation(
        "listener,trial,stimulus,amplitude_ratio,delay_ms,answer\nA,1,s012.wav,0.2,30,-1\nA,2,s013.wav,0.2,40,1\nB,1,s001.wav,0.1,20,\n".into()
    )) {
        one_line(clapper_io::answers::parse_answers(&String::from_utf8_lossy(&b), "fuzz"))?;
    }

    #[test]
    fn chart_csv(b in bytes_or_mutation(
        "r_over_lc,lb_over_lc,style,sustained,strike_theta_deg,strike_phidot_rad_s,liftoff_theta_deg,double_strike_index\n-0.300000,0.500000,right,false,,,-5.590492,\n0.100000,1.500000,wrong,true,-120.5,3.2,110.0,4.5\n".into()
    )) {
        one_line(clapper_io::read_chart_csv(&String::from_utf8_lossy(&b), "fuzz"))?;
    }
}

/// A small valid WAV: 200 samples of a decaying tone at 8 kHz.
fn wav() -> Vec<u8> {
    let sig = clapper_signal::Signal {
        rate: 8000.0,
        samples: (0..200)
            .map(|i| (i as f64 * 0.3).sin() * (-(i as f64) / 80.0).exp())
            .collect(),
    };
    clapper_io::signal_file::wav_bytes(&sig, 0.9).unwrap()
}

fn wav_or_mutation() -> impl Strategy<Value = Vec<u8>> {
    let valid = wav();
    let len = valid.len();
    prop_oneof![
        prop::collection::vec(any::<u8>(), 0..300),
        (prop::collection::vec((0..len, any::<u8>()), 1..8), 0..=len).prop_map(move |(edits, cut)| {
            let mut v = valid.clone();
            for (i, byte) in edits {
                v[i] = byte;
            }
            v.truncate(cut.max(1));
            v
        }),
    ]
}

proptest! {
    #![proptest_config(Config { cases: cases(), ..Config::default() })]

    #[test]
    fn signals_wav_and_csv(b in wav_or_mutation(), channel in 0usize..3) {
        let dir = tempfile::tempdir().unwrap();
        let wav = dir.path().join("x.wav");
        std::fs::write(&wav, &b).unwrap();
        one_line(clapper_io::signal_file::read_signal(&wav, channel))?;
        let csv = dir.path().join("x.csv");
        std::fs::write(&csv, &b).unwrap();
        one_line(clapper_io::signal_file::read_signal(&csv, channel))?;
        one_line(clapper_io::signal_file::read_modes(&csv))?;
    }
}

#[test]
fn bad_inputs_name_what_is_wrong() {
    let lab = examples("lab.toml");
    for (text, needle) in [
        (lab.replace("a_m = 0.24", "a_m = -0.24"), "a_m"),
        (lab.replace("phi_max_deg = 26", "phi_max_deg = 95"), "phi_max_deg"),
        (
            lab.replace("name = \"Lab bell\"", "name = \"Lab bell\"\ncolor = 3"),
            "color",
        ),
        (lab.replace("r_m = 0.10", "r_m = \"ten\""), "r_m"),
        ("bell_period_s = 2.3\n".to_string(), "clapper_period_s"),
    ] {
        let e = clapper_io::parse_bells(&text, "x").unwrap_err().to_string();
        assert!(e.contains(needle), "{e:?} should name {needle}");
    }
    let e = clapper_io::parse_ring_csv("name,bell_period_s,clapper_period_s,r_m,phi_max_deg\nA,2,1.5,x,26\n")
        .unwrap_err()
        .to_string();
    assert!(e.contains("row 1"), "{e}");
}
