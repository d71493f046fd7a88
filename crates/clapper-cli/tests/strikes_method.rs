//! `clapper strikes` names what the rows heard were (issue 43 item 3:
//! rows found in methods as well as rounds): synthetic rings of each
//! method from `synth-ring`, heard with the nominals it prints.

mod common;
use common::clapper;

/// The JSON report and the text of a ring of `bells` bells ringing
/// `method` (synth-ring's value; None: rounds).
fn heard(method: Option<&str>, bells: usize) -> (serde_json::Value, String) {
    let dir = tempfile::tempdir().unwrap();
    let wav = dir.path().join("ring.wav");
    let mut synth = clapper();
    synth.args(["synth-ring", "--out"]).arg(&wav);
    synth.args(["--bells", &bells.to_string(), "--rows", "40", "--seed", "5"]);
    if let Some(m) = method {
        synth.args(["--method", m]);
    }
    let out = synth.output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let said = String::from_utf8(out.stdout).unwrap();
    let nominals = common::nominals_said(&said).to_string();
    let run = |extra: &[&str]| {
        let out = clapper()
            .arg("strikes")
            .arg(&wav)
            .args(["--nominals", &nominals])
            .args(extra)
            .output()
            .unwrap();
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        String::from_utf8(out.stdout).unwrap()
    };
    (serde_json::from_str(&run(&["--json"])).unwrap(), run(&[]))
}

#[test]
fn the_rows_heard_are_named_by_their_method() {
    for (method, bells, name) in [
        (None, 6, "rounds"),
        (Some("plain-hunt"), 7, "plain hunt"),
        (Some("plain-bob"), 6, "Plain Bob"),
        (Some("grandsire"), 8, "Grandsire"),
        (Some("stedman"), 7, "Stedman"),
    ] {
        let (j, text) = heard(method, bells);
        let m = &j["summary"]["method"];
        assert_eq!(m["name"], name, "{method:?} on {bells}: {m}");
        // Nearly every change heard whole is the method's.
        let (fit, judged) = (
            m["changes_fitting"].as_u64().unwrap(),
            m["changes_judged"].as_u64().unwrap(),
        );
        assert!(judged >= 30 && fit * 10 >= judged * 9, "{method:?} on {bells}: {m}");
        // A method's line says how often its course was rung (tester22
        // fault 7); rounds' the changes.
        let line = if name == "rounds" {
            "rows: rounds (".to_string()
        } else {
            format!("rows: {name}, ")
        };
        assert!(text.contains(&line), "{text}");
    }
}
