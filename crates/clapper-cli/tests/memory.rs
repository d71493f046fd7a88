//! Long runs in bounded memory (docs/reliability.md): a sweep of many
//! charts to a CSV file and a long trace are written as they are computed.
//! One test binary of its own, as it reads the largest resident size of
//! the children this process has waited for.

mod common;

/// The largest resident set (MiB) of any child waited for so far.
fn children_max_rss_mib() -> f64 {
    // SAFETY: getrusage fills the struct it is given; nothing else is shared.
    let mut u: libc::rusage = unsafe { std::mem::zeroed() };
    assert_eq!(unsafe { libc::getrusage(libc::RUSAGE_CHILDREN, &mut u) }, 0);
    u.ru_maxrss as f64 / 1024.0
}

/// A 20-chart theta0 sweep of 100 x 100 (400,000 strokes) to --csv under
/// 50 MiB resident, then 1,000 strokes with --trace (3 million rows) under
/// 100 MiB. Measured: 21 and 21 MiB; before, the sweep kept every row
/// (80 MiB) and the trace every sample (201 MiB).
#[test]
fn long_sweeps_and_traces_stay_small() {
    let dir = tempfile::tempdir().unwrap();
    let theta0: Vec<String> = (0..20).map(|k| format!("{}", 150 + k)).collect();
    common::clapper()
        .args(["chart", "--grid", "100", "--theta0", &theta0.join(",")])
        .arg("--csv")
        .arg(dir.path().join("sweep.csv"))
        .assert()
        .success();
    let sweep = children_max_rss_mib();
    let trace = dir.path().join("trace.csv");
    common::clapper()
        .args(["simulate", "--preset", "lab", "--strokes", "1000", "--trace"])
        .arg(&trace)
        .assert()
        .success();
    let both = children_max_rss_mib();
    let rows = std::fs::read_to_string(&trace).unwrap().lines().count();
    println!("largest resident size: sweep {sweep:.0} MiB; then with the trace ({rows} rows) {both:.0} MiB");
    assert!(rows > 1_000_000, "{rows} rows");
    assert!(sweep < 50.0, "sweep: {sweep:.0} MiB");
    assert!(both < 100.0, "trace: {both:.0} MiB");
}
