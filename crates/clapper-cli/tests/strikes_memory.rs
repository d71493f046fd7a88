//! `clapper strikes` in memory that does not grow with the recording
//! (issue 46, docs/reliability.md): a four-and-a-half-minute ring at 44.1 kHz is read
//! in blocks and heard in windows. One test binary of its own, as it reads
//! the largest resident size of the children this process has waited for.

mod common;

/// The largest resident set (MiB) of any child waited for so far.
fn children_max_rss_mib() -> f64 {
    // SAFETY: getrusage fills the struct it is given; nothing else is shared.
    let mut u: libc::rusage = unsafe { std::mem::zeroed() };
    assert_eq!(unsafe { libc::getrusage(libc::RUSAGE_CHILDREN, &mut u) }, 0);
    u.ru_maxrss as f64 / 1024.0
}

/// Eight copies of a 33 s ring at 44.1 kHz (4.5 min, 1024 strikes;
/// written here, so that only `strikes` is measured) heard under 250 MiB,
/// every strike found. Measured: 139 MiB; before, the whole recording and
/// its bands were held: 475 MiB (107 MiB a minute).
#[test]
fn a_long_recording_is_heard_in_bounded_memory() {
    let dir = tempfile::tempdir().unwrap();
    let short = dir.path().join("short.wav");
    common::clapper()
        .args(["synth-ring", "--rows", "16", "--rate", "44100", "--out"])
        .arg(&short)
        .assert()
        .success();
    let before = children_max_rss_mib();
    let mut r = hound::WavReader::open(&short).unwrap();
    let spec = r.spec();
    let samples: Vec<i16> = r.samples::<i16>().map(Result::unwrap).collect();
    let wav = dir.path().join("long.wav");
    let mut w = hound::WavWriter::create(&wav, spec).unwrap();
    for _ in 0..8 {
        for &v in &samples {
            w.write_sample(v).unwrap();
        }
    }
    w.finalize().unwrap();
    let j = common::json(&[
        "strikes",
        wav.to_str().unwrap(),
        "--nominals",
        "1400.0,1247.3,1111.2,1048.8,934.4,832.4,741.6,700.0",
    ]);
    let rss = children_max_rss_mib();
    println!("largest resident size: synth-ring {before:.0} MiB, strikes {rss:.0} MiB");
    assert_eq!(j["summary"]["strikes"], 8 * 128, "{}", j["summary"]);
    assert!(j["summary"]["duration_s"].as_f64().unwrap() > 240.0);
    assert!(rss < 250.0, "strikes: {rss:.0} MiB");
}
