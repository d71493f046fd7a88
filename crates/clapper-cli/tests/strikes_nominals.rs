//! `clapper strikes` given fewer nominals than bells ring (issue 42):
//! README's examples/data/tower.wav, eight bells, heard for three of them,
//! warns that the strikes leave room for more; with all eight, it does not.

mod common;
use common::clapper;

const EIGHT: &str = "1400.0,1247.3,1111.2,1048.8,934.4,832.4,741.6,700.0";

fn strikes(nominals: &str) -> String {
    strikes_timed(nominals, "plain")
}

fn strikes_timed(nominals: &str, timing: &str) -> String {
    let wav = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/data/tower.wav");
    let out = clapper()
        .args(["strikes", wav, "--nominals", nominals, "--timing", timing])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8_lossy(&out.stdout).to_string() + &String::from_utf8_lossy(&out.stderr)
}

#[test]
fn three_nominals_for_a_recording_of_eight_bells_are_warned_of() {
    let said = strikes(&EIGHT.split(',').take(3).collect::<Vec<_>>().join(","));
    assert!(
        said.contains("warning: 3 nominal(s) given, but the strikes leave room for about"),
        "{said}"
    );
    let all = strikes(EIGHT);
    assert!(!all.contains("room for"), "{all}");
    // Timed auto, the three bells' strikes are timed from the recording
    // (their intervals are uneven either way): the user is still told to
    // give every bell that rings.
    let auto = strikes_timed(&EIGHT.split(',').take(3).collect::<Vec<_>>().join(","), "auto");
    assert!(auto.contains("give every bell that rings"), "{auto}");
    assert!(!strikes_timed(EIGHT, "auto").contains("room for"));
}
