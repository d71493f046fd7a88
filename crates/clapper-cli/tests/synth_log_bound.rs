//! `clapper synth-log` bounded before its samples are drawn (issue 46):
//! `--rate 10000 --strokes 10000` used 6.7 GB and aborted under a 4 GB
//! limit, and a 10 kHz log longer than about 28 minutes was written though
//! ringing-log refuses a text log over 512 MiB. Such a log is now refused,
//! in the options' words, before its samples are allocated. One test
//! binary of its own, as it reads the largest resident size of its
//! children.

mod common;

/// The largest resident set (MiB) of any child waited for so far.
fn children_max_rss_mib() -> f64 {
    // SAFETY: getrusage fills the struct it is given; nothing else is shared.
    let mut u: libc::rusage = unsafe { std::mem::zeroed() };
    assert_eq!(unsafe { libc::getrusage(libc::RUSAGE_CHILDREN, &mut u) }, 0);
    u.ru_maxrss as f64 / 1024.0
}

#[test]
fn a_log_too_long_for_ringing_log_is_refused_before_it_is_drawn() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("long.txt");
    let run = common::clapper()
        .args(["synth-log", "--rate", "10000", "--strokes", "10000", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&run.stderr);
    assert!(!run.status.success(), "{err}");
    assert!(
        err.contains("--rate 10000 Hz") && err.contains("--strokes 10000") && err.contains("512 MiB ringing-log reads"),
        "{err}"
    );
    assert!(!out.exists());
    let rss = children_max_rss_mib();
    println!("largest resident size: {rss:.0} MiB");
    assert!(rss < 200.0, "{rss:.0} MiB");
}
