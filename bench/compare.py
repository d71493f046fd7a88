#!/usr/bin/env python3
"""clapper against its peers, on the same work, in one run.

Runs clapper (release build), the SciPy peer (impact with restarts, and the
paper's penalty spring), the Octave peer (ode45 with an Events function) and
the CVODE peer (SUNDIALS, Adams and BDF, with its root finding)
on the paper's 20 x 20 chart of both styles and the lab bell, measures time
per stroke and the chart's wall time, and the error of the first strike
angle and strike velocity (read in full, not from the CSV's six decimals)
against clapper's Dormand-Prince at rtol = atol = 1e-13, then writes
docs/performance.md.

    bash bench/run        # installs the peers' packages, builds, runs this
"""
import json
import os
import platform
import re
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CLAPPER = os.path.join(ROOT, "target", "release", "clapper")
PEERS = os.path.join(ROOT, "bench", "peers")
WORK = os.path.join(ROOT, "target", "bench")
CVODE = os.path.join(WORK, "cvode_peer")  # built by bench/run
N = 20  # the paper's chart
REPEATS = 20
# clapper's time per stroke: a denser chart of the same domain, so that a
# process's start (thread pool, first touches of code and data: about 5 ms)
# is spread over 20,000 strokes rather than charged to 800.
RATE_N = 100
RATE_REPEATS = 5


def sh(cmd, **kw):
    return subprocess.run(cmd, check=True, capture_output=True, text=True, **kw).stdout


def clapper_chart(extra, csv, threads=1, repeats=REPEATS, n=N):
    """Least wall time (s) of `repeats` runs, as clapper reports it, and the CSV."""
    best = float("inf")
    for _ in range(repeats):
        out = sh([CLAPPER, "chart", "--grid", str(n), "--threads", str(threads), "--csv", csv] + extra)
        best = min(best, float(re.search(r"strokes in ([0-9.]+) s", out).group(1)))
    return best


def clapper_rate(extra, repeats=RATE_REPEATS):
    """Least time per stroke (s) on one thread over `repeats` runs of the
    RATE_N x RATE_N chart (same domain and settings as the paper's)."""
    csv = os.path.join(WORK, "rate.csv")
    return clapper_chart(extra, csv, threads=1, repeats=repeats, n=RATE_N) / (2 * RATE_N * RATE_N)


def errors(ref, got):
    """Max |d strike angle| (deg), max |d strike velocity| (rad/s), verdicts agreeing, cells compared."""
    da = dv = 0.0
    agree = n = 0
    for key, (sus, th, ph) in got.items():
        r = ref[key]
        n += 1
        agree += r[0] == sus
        if th is not None and r[1] is not None:
            da = max(da, abs(th - r[1]))
            dv = max(dv, abs(ph - r[2]))
    return da, dv, agree, n


def json_cell(d, cells):
    """Store a cell printed as JSON (SciPy peer, chart_values) under its key."""
    x, y = d["point"]
    cells[(round(x, 6), round(y, 6), d["style"])] = (d["sustained"], d["strike_theta_deg"], d["strike_phidot_rad_s"])


def fastest_as_accurate(runs, err, floor):
    """Of `runs` (label, seconds per stroke, angle error, velocity error), the
    fastest whose two errors are both no larger than `err`'s: (label, seconds),
    or (None, None). Below `floor`, the references' own disagreement, errors
    cannot be ranked and count as equal."""
    lim = (max(err[0], floor[0]), max(err[1], floor[1]))
    ok = [(t, label) for label, t, a, v in runs if a <= lim[0] and v <= lim[1]]
    return min(ok)[::-1] if ok else (None, None)


def peer_chart(out):
    """A peer's chart printed as JSON lines (the SciPy and CVODE peers'):
    cells, seconds, mean RHS calls per stroke."""
    cells, secs, evals = {}, None, []
    for line in out.splitlines():
        d = json.loads(line)
        if "point" in d:
            json_cell(d, cells)
            evals.append(d["rhs_evals"])
        else:
            secs = d["seconds"]
    return cells, secs, sum(evals) / len(evals)


def scipy_chart(model, rtol, n=N):
    return peer_chart(sh([sys.executable, os.path.join(PEERS, "scipy_peer.py"), "--chart", str(n), "--model", model,
                          "--rtol", str(rtol)]))


def cvode_chart(method, rtol, n=N):
    return peer_chart(sh([CVODE, "--chart", str(n), "--method", method, "--rtol", str(rtol)]))


def lab_cvode(method, rtol):
    """The lab bell ringing right, the least time per stroke of 20 runs of 20 strokes."""
    best, d = float("inf"), None
    for _ in range(20):
        lines = [json.loads(l) for l in sh([CVODE, "--bell", "lab", "--method", method, "--rtol", str(rtol),
                                            "--repeat", "20"]).splitlines()]
        d = lines[0]
        best = min(best, lines[1]["seconds_per_stroke"])
    return best, d["strike_theta_deg"], d["strike_phidot_rad_s"]


def octave_chart(rtol, n=N):
    out = sh(["octave-cli", os.path.join(PEERS, "octave_peer.m"), "chart", str(n), str(rtol)], cwd=PEERS)
    cells, secs = {}, None
    for line in out.splitlines():
        p = line.split()
        if p[0] == "strokes":
            secs = float(p[3])
        elif len(p) == 6:
            th = None if p[4] == "NaN" else float(p[4])
            ph = None if p[5] == "NaN" else float(p[5])
            cells[(round(float(p[0]), 6), round(float(p[1]), 6), p[2])] = (p[3] == "1", th, ph)
    return cells, secs


def clapper_values(rtol, integrator="taylor", contact="impact"):
    """The 20 x 20 chart's values in full (examples/chart_values.rs), keyed by
    (r/L_c, L_b/L_c, style) as the peers' are."""
    exe = os.path.join(ROOT, "target", "release", "examples", "chart_values")
    cells = {}
    for line in sh([exe, str(rtol), integrator, contact]).splitlines():
        json_cell(json.loads(line), cells)
    return cells


def lab_clapper(rtol=None, integrator="taylor"):
    """Time per stroke (s) of the lab bell ringing right, in process (examples/lab_stroke.rs)."""
    exe = os.path.join(ROOT, "target", "release", "examples", "lab_stroke")
    d = json.loads(sh([exe, str(rtol or 3e-8), integrator]))
    return d["seconds_per_stroke"], d["strike_theta_deg"], d["strike_phidot_rad_s"]


def lab_scipy(rtol, model="impact"):
    d = [json.loads(l) for l in sh([sys.executable, os.path.join(PEERS, "scipy_peer.py"), "--bell", "lab",
                                    "--model", model, "--rtol", str(rtol)]).splitlines()]
    return d[1]["seconds_per_stroke"], d[0]["strike_theta_deg"], d[0]["strike_phidot_rad_s"]


def lab_octave(rtol):
    lines = sh(["octave-cli", os.path.join(PEERS, "octave_peer.m"), "lab", "right", str(rtol)], cwd=PEERS).splitlines()
    p = lines[0].split()
    return float(lines[1].split()[5]), float(p[4]), float(p[5])


def main():
    os.makedirs(WORK, exist_ok=True)
    rows = []
    notes = []
    t_all = time.time()

    # Tight references (impact and penalty), computed by clapper's
    # general-purpose integrator (Dormand-Prince), not the default Taylor one,
    # and read in full. How far the Taylor integrator at the same tolerance
    # lies from it is the resolution of every error below.
    ref = clapper_values(1e-13, "dopri5")
    floor = errors(ref, clapper_values(1e-13))[:2]
    ref_pen = clapper_values(1e-12, "dopri5", "penalty")

    # clapper itself: the default, then a ladder of tolerances, so that each
    # peer can be matched with the fastest clapper run at least as accurate.
    c_csv = os.path.join(WORK, "clapper.csv")
    t2 = clapper_chart([], c_csv, threads=2)
    e = errors(ref, clapper_values(3e-8))
    clapper_per_stroke = clapper_rate([])
    rows.append(("clapper, impact (default: Taylor, rtol 3e-8)", clapper_per_stroke, t2, *e))
    ladder = [("3e-08", clapper_per_stroke, e)]
    for rtol in ["1e-06", "3e-07", "1e-07", "1e-09", "1e-10", "1e-11", "1e-12"]:
        el = errors(ref, clapper_values(float(rtol)))
        tl = clapper_rate(["--rtol", rtol])
        ladder.append((rtol, tl, el))
        rows.append((f"clapper, impact, Taylor, rtol {float(rtol):g}", tl, None, *el))
    ed = errors(ref, clapper_values(3e-8, "dopri5"))
    rows.append(("clapper, impact, Dormand-Prince (rtol 3e-8)", clapper_rate(["--integrator", "dopri5"]), None, *ed))
    cp_csv = os.path.join(WORK, "clapper-penalty.csv")  # penalty model: clapper only (see notes)
    t2p = clapper_chart(["--contact", "penalty"], cp_csv, threads=2, repeats=3)
    ep = errors(ref_pen, clapper_values(3e-8, "taylor", "penalty"))
    t1p = clapper_rate(["--contact", "penalty"], repeats=2)
    rows.append(("clapper, penalty k = 1e6 (default: Taylor, rtol 3e-8)", t1p, t2p, *ep))

    def match(err):
        """The fastest clapper run at least as accurate: (rtol, seconds per stroke)."""
        return fastest_as_accurate([(r, t, e[0], e[1]) for r, t, e in ladder], err, floor)

    # A 1000 x 1000 chart, both styles, both cores.
    start = time.perf_counter()
    out = sh([CLAPPER, "chart", "--grid", "1000", "--csv", os.path.join(WORK, "big.csv")])
    big = time.perf_counter() - start
    big_reported = float(re.search(r"strokes in ([0-9.]+) s", out).group(1))

    # SciPy, CVODE and Octave peers on the chart.
    peer_rows = []

    def peer(row_name, ratio_name, cells, secs, evals):
        """A peer's chart as a row of each table."""
        e = errors(ref, cells)
        per = secs / len(cells)
        rows.append((row_name, per, secs, *e))
        m_rtol, m_per = match(e)
        peer_rows.append((ratio_name, per / clapper_per_stroke, m_rtol, per / m_per if m_per else None, evals))

    for rtol in [1e-6, 1e-8, 1e-10, 1e-12]:
        peer(f"SciPy solve_ivp RK45, impact, rtol {rtol:g}", f"SciPy impact, rtol {rtol:g}, chart",
             *scipy_chart("impact", rtol))
    for method, name in [("adams", "Adams"), ("bdf", "BDF")]:
        for rtol in [1e-6, 1e-8, 1e-10, 1e-12]:
            peer(f"CVODE {name} + roots, impact, rtol {rtol:g}", f"CVODE {name} impact, rtol {rtol:g}, chart",
                 *cvode_chart(method, rtol))
    peer("Octave ode45 + Events, impact, rtol 1e-08", "Octave impact, rtol 1e-08, chart", *octave_chart(1e-8), None)

    # The lab bell, one stroke ringing right, at several tolerances.
    ref_lab = lab_clapper(1e-13, "dopri5")
    taylor_lab = lab_clapper(1e-13)
    lab_floor = (abs(taylor_lab[1] - ref_lab[1]), abs(taylor_lab[2] - ref_lab[2]))
    lab = []
    mine = lab_clapper()
    lab.append(("clapper (default: Taylor, 3e-8)", *mine))
    lab.append(("clapper, Taylor, rtol 1e-10", *lab_clapper(1e-10)))
    lab.append(("clapper, Taylor, rtol 1e-12", *lab_clapper(1e-12)))
    lab.append(("clapper, Dormand-Prince, rtol 3e-8", *lab_clapper(3e-8, "dopri5")))
    for rtol in [1e-8, 1e-10, 1e-12]:
        lab.append((f"SciPy impact, rtol {rtol:g}", *lab_scipy(rtol)))
    for rtol in [1e-8, 1e-10, 1e-12]:
        lab.append((f"Octave impact, rtol {rtol:g}", *lab_octave(rtol)))
    for method, name in [("adams", "Adams"), ("bdf", "BDF")]:
        for rtol in [1e-8, 1e-10, 1e-12]:
            lab.append((f"CVODE {name} impact, rtol {rtol:g}", *lab_cvode(method, rtol)))
    lab_err = [(n, t, abs(th - ref_lab[1]), abs(ph - ref_lab[2])) for n, t, th, ph in lab]
    mine_taylor = [r for r in lab_err if r[0].startswith("clapper") and "Dormand" not in r[0]]

    lab_rows = []
    for n, t, da, dv in lab_err:
        m = None if n.startswith("clapper") else fastest_as_accurate(mine_taylor, (da, dv), lab_floor)[1]
        lab_rows.append((n, t, da, dv, t / mine[0], t / m if m else None))

    versions = {
        "machine": f"{platform.machine()}, {os.cpu_count()} cores, " + (
            re.search(r"model name\s*:\s*(.*)", open("/proc/cpuinfo").read()).group(1)
            if os.path.exists("/proc/cpuinfo") else "?"),
        "rustc": sh(["rustc", "--version"]).strip(),
        "python": platform.python_version(),
        "scipy": __import__("scipy").__version__,
        "numpy": __import__("numpy").__version__,
        "octave": sh(["octave-cli", "--version"]).splitlines()[0],
        "sundials": re.search(r'SUNDIALS_VERSION "([^"]+)"',
                              open("/usr/include/sundials/sundials_config.h").read()).group(1),
    }
    write_doc(rows, peer_rows, lab_rows, versions, big, big_reported, t_all, floor, lab_floor)


def err_words(v, floor):
    """An error, or "<= floor" below the references' own disagreement."""
    return f"<= {floor:.0e}" if v <= floor else f"{v:.1e}"


def write_doc(rows, peer_rows, lab_rows, versions, big, big_reported, t_all, floor, lab_floor):
    L = []
    L.append("# Performance: clapper and its peers\n")
    L.append("Written by `bash bench/run` (bench/compare.py) in one run on "
             f"{time.strftime('%Y-%m-%d')}; every number in the tables below is from that run (the notes "
             "after them say where theirs come from). "
             f"The run took {(time.time() - t_all) / 60:.1f} min.\n")
    L.append("## Machine and versions\n")
    for k, v in versions.items():
        L.append(f"- {k}: {v}")
    L.append("")
    L.append("## The work\n")
    L.append("The paper's clapping chart: 20 x 20 points over r/L_c -0.3..0.7 and L_b/L_c 0.5..2.5, "
             "both styles (800 strokes), theta0 = 171 deg, R = 0.2, phi_max = 26 deg. Each implementation "
             "simulates every stroke to its turning point and reports the first strike angle, the clapper "
             "rate before it and whether the style is sustained. Errors are the largest over the chart, "
             "against a tight reference: clapper's general-purpose Dormand-Prince integrator at rtol = atol "
             "= 1e-13, not the default Taylor one (for the penalty rows, the penalty model at 1e-12), all values "
             "read in full (`examples/chart_values.rs`; the CSV's six decimals would hide errors below 1e-6). "
             f"The Taylor integrator at 1e-13 lies within {floor[0]:.1e} deg and {floor[1]:.1e} rad/s of that "
             "reference: smaller errors cannot be told apart, and are shown as at most that. "
             "clapper's times are the least of several runs (the machine is a shared VM whose speed "
             "varies by +-20 %); the peers ran once. clapper's time per stroke is measured on a "
             f"{RATE_N} x {RATE_N} chart of the same domain and settings ({2 * RATE_N * RATE_N:,} strokes, "
             "least of several runs), so that a process's start (thread pool, first touches of code and "
             "data, about 5 ms) is not charged to 800 strokes; the 20 x 20 column is the whole chart as a "
             "user sees it, start included; its errors are those of the 20 x 20 chart, as for the peers.\n")
    L.append("| implementation | time per stroke (1 thread) | 20 x 20 chart, both styles | max error of first strike angle (deg) | max error of strike velocity (rad/s) | verdicts as the reference |")
    L.append("|---|---:|---:|---:|---:|---:|")
    for name, per, chart, da, dv, agree, n in rows:
        if chart is None:
            chart_words = ""
        else:
            chart_words = f"{chart:.3f} s" if chart < 10 else f"{chart:.1f} s"
            if name.startswith("clapper"):
                chart_words += " (2 threads)"
        per_words = f"{per * 1e6:.1f}" if per < 1e-4 else f"{per * 1e6:,.0f}"
        L.append(f"| {name} | {per_words} us | {chart_words} | {err_words(da, floor[0])} | {err_words(dv, floor[1])} | {agree} of {n} |")
    L.append("")
    L.append("## Speed ratios (time per stroke, one thread each)\n")
    L.append("Against clapper's default, and against the fastest clapper run above whose largest errors (first "
             "strike angle and strike velocity, both) are no larger than the peer's: equal or better accuracy "
             "(errors below the references' own disagreement count as equal). The ratio grows as the accuracy "
             "asked for tightens (the notes below say why).\n")
    L.append("| peer | peer / clapper default | clapper at equal or better accuracy | peer / that clapper run | peer's RHS calls per stroke |")
    L.append("|---|---:|---:|---:|---:|")
    for name, ratio, m_rtol, m_ratio, evals in peer_rows:
        m_words = f"Taylor, rtol {float(m_rtol):g}" if m_rtol else "none of the runs"
        m_ratio_words = f"{m_ratio:,.0f} x" if m_ratio else ""
        L.append(f"| {name} | {ratio:,.0f} x | {m_words} | {m_ratio_words} | "
                 f"{'' if evals is None else f'{evals:.0f}'} |")
    L.append("")
    L.append("## The lab bell, one stroke ringing right\n")
    L.append("Errors against clapper's Dormand-Prince at 1e-13; times per stroke, one thread (clapper: the least of twenty runs "
             "of 2000 strokes in one process; the peers: one stroke). clapper's Taylor integrator at 1e-13 lies "
             f"within {lab_floor[0]:.0e} deg and {lab_floor[1]:.0e} rad/s of the reference. The last column "
             "divides by the fastest of clapper's Taylor runs above whose errors are no larger.\n")
    L.append("| implementation | time per stroke | error of first strike angle (deg) | error of strike velocity (rad/s) | time / clapper default | time / clapper at equal or better accuracy |")
    L.append("|---|---:|---:|---:|---:|---:|")
    for name, t, da, dv, ratio, m_ratio in lab_rows:
        m_words = f"{m_ratio:,.0f} x" if m_ratio else ""
        L.append(f"| {name} | {t * 1e6:,.0f} us | {err_words(da, lab_floor[0])} | {err_words(dv, lab_floor[1])} | "
                 f"{ratio:,.0f} x | {m_words} |")
    L.append("")
    L.append(f"A 1000 x 1000 chart of both styles (2,000,000 strokes) on both cores: {big_reported:.1f} s "
             f"of sweeping ({big:.1f} s for the whole process, with writing the CSV).\n")
    with open(os.path.join(ROOT, "docs", "performance.md"), "w") as f:
        f.write("\n".join(L) + "\n")
        f.write(open(os.path.join(ROOT, "bench", "performance-notes.md")).read())
    print("\n".join(L))


if __name__ == "__main__":
    main()
