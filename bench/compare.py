#!/usr/bin/env python3
"""clapper against its peers, on the same work, in one run.

Runs clapper (release build), the SciPy peer (impact with restarts, and the
paper's penalty spring) and the Octave peer (ode45 with an Events function)
on the paper's 20 x 20 chart of both styles and the lab bell, measures time
per stroke and the chart's wall time, and the error of the first strike
angle and strike velocity against clapper at rtol = atol = 1e-12, then
writes docs/performance.md.

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


def read_csv(path):
    cells = {}
    with open(path) as f:
        next(f)
        for line in f:
            x, y, style, sus, th, ph = line.strip().split(",")[:6]
            cells[(round(float(x), 6), round(float(y), 6), style)] = (
                sus == "true", float(th) if th else None, float(ph) if ph else None)
    return cells


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


def scipy_chart(model, rtol, n=N):
    out = sh([sys.executable, os.path.join(PEERS, "scipy_peer.py"), "--chart", str(n), "--model", model,
              "--rtol", str(rtol)])
    cells, secs, evals = {}, None, []
    for line in out.splitlines():
        d = json.loads(line)
        if "point" in d:
            x, y = d["point"]
            cells[(round(x, 6), round(y, 6), d["style"])] = (d["sustained"], d["strike_theta_deg"], d["strike_phidot_rad_s"])
            evals.append(d["rhs_evals"])
        else:
            secs = d["seconds"]
    return cells, secs, sum(evals) / len(evals)


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
    # general-purpose integrator (Dormand-Prince), not the default Taylor one.
    ref_csv = os.path.join(WORK, "ref-impact.csv")
    clapper_chart(["--rtol", "1e-12", "--integrator", "dopri5"], ref_csv, threads=2, repeats=1)
    ref = read_csv(ref_csv)
    ref_pen_csv = os.path.join(WORK, "ref-penalty.csv")
    clapper_chart(["--rtol", "1e-12", "--contact", "penalty", "--integrator", "dopri5"], ref_pen_csv, threads=2,
                  repeats=1)
    ref_pen = read_csv(ref_pen_csv)

    # clapper itself: the default, then a ladder of tolerances, so that each
    # peer can be matched with the fastest clapper run at least as accurate.
    c_csv = os.path.join(WORK, "clapper.csv")
    t2 = clapper_chart([], c_csv, threads=2)
    e = errors(ref, read_csv(c_csv))
    clapper_per_stroke = clapper_rate([])
    rows.append(("clapper, impact (default: Taylor, rtol 3e-8)", clapper_per_stroke, t2, *e))
    ladder = [("3e-08", clapper_per_stroke, e)]
    for rtol in ["1e-06", "3e-07", "1e-07", "1e-09", "1e-10", "1e-11"]:
        clapper_chart(["--rtol", rtol], c_csv, threads=1, repeats=1)
        el = errors(ref, read_csv(c_csv))
        tl = clapper_rate(["--rtol", rtol])
        ladder.append((rtol, tl, el))
        rows.append((f"clapper, impact, Taylor, rtol {float(rtol):g}", tl, None, *el))
    clapper_chart(["--integrator", "dopri5"], c_csv, threads=1, repeats=1)
    ed = errors(ref, read_csv(c_csv))
    rows.append(("clapper, impact, Dormand-Prince (rtol 3e-8)", clapper_rate(["--integrator", "dopri5"]), None, *ed))
    cp_csv = os.path.join(WORK, "clapper-penalty.csv")  # penalty model: clapper only (see notes)
    t2p = clapper_chart(["--contact", "penalty"], cp_csv, threads=2, repeats=3)
    ep = errors(ref_pen, read_csv(cp_csv))
    t1p = clapper_rate(["--contact", "penalty"], repeats=2)
    rows.append(("clapper, penalty k = 1e6 (default: Taylor, rtol 3e-8)", t1p, t2p, *ep))

    def match(err):
        """The fastest clapper run whose angle and velocity errors are both
        no larger than `err`'s: (rtol, seconds per stroke)."""
        ok = [(t, r) for r, t, e in ladder if e[0] <= err[0] and e[1] <= err[1]]
        return min(ok)[::-1] if ok else (None, None)

    # A 1000 x 1000 chart, both styles, both cores.
    start = time.perf_counter()
    out = sh([CLAPPER, "chart", "--grid", "1000", "--csv", os.path.join(WORK, "big.csv")])
    big = time.perf_counter() - start
    big_reported = float(re.search(r"strokes in ([0-9.]+) s", out).group(1))

    # SciPy and Octave peers on the chart.
    peer_rows = []
    for rtol in [1e-8, 1e-10]:
        cells, secs, evals = scipy_chart("impact", rtol)
        e = errors(ref, cells)
        per = secs / len(cells)
        rows.append((f"SciPy solve_ivp RK45, impact, rtol {rtol:g}", per, secs, *e))
        m_rtol, m_per = match(e)
        peer_rows.append((f"SciPy impact, rtol {rtol:g}, chart", per / clapper_per_stroke, m_rtol,
                          per / m_per if m_per else None, evals))
    cells, secs = octave_chart(1e-8)
    e = errors(ref, cells)
    per = secs / len(cells)
    rows.append(("Octave ode45 + Events, impact, rtol 1e-08", per, secs, *e))
    m_rtol, m_per = match(e)
    peer_rows.append(("Octave impact, rtol 1e-08, chart", per / clapper_per_stroke, m_rtol,
                      per / m_per if m_per else None, None))

    # The lab bell, one stroke ringing right, at several tolerances.
    ref_lab = lab_clapper(1e-12, "dopri5")
    lab = []
    mine = lab_clapper()
    lab.append(("clapper (default: Taylor, 3e-8)", *mine))
    lab.append(("clapper, Taylor, rtol 1e-10", *lab_clapper(1e-10)))
    lab.append(("clapper, Dormand-Prince, rtol 3e-8", *lab_clapper(3e-8, "dopri5")))
    for rtol in [1e-8, 1e-10]:
        lab.append((f"SciPy impact, rtol {rtol:g}", *lab_scipy(rtol)))
    for rtol in [1e-8, 1e-10, 1e-12]:
        lab.append((f"Octave impact, rtol {rtol:g}", *lab_octave(rtol)))
    lab_rows = [(n, t, abs(th - ref_lab[1]), abs(ph - ref_lab[2]), t / mine[0]) for n, t, th, ph in lab]

    versions = {
        "machine": f"{platform.machine()}, {os.cpu_count()} cores, " + (
            re.search(r"model name\s*:\s*(.*)", open("/proc/cpuinfo").read()).group(1)
            if os.path.exists("/proc/cpuinfo") else "?"),
        "rustc": sh(["rustc", "--version"]).strip(),
        "python": platform.python_version(),
        "scipy": __import__("scipy").__version__,
        "numpy": __import__("numpy").__version__,
        "octave": sh(["octave-cli", "--version"]).splitlines()[0],
    }
    write_doc(rows, peer_rows, lab_rows, versions, big, big_reported, t_all)


def csv_err(v):
    """An error read from chart CSVs, which print 6 decimals: anything up to
    1e-6 is within their rounding."""
    return "<= 1e-6" if v <= 1.0000001e-6 else f"{v:.1e}"


def write_doc(rows, peer_rows, lab_rows, versions, big, big_reported, t_all):
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
             "= 1e-12, not the default Taylor one (for the penalty rows, the penalty model at 1e-12). "
             "clapper's times are the least of several runs (the machine is a shared VM whose speed "
             "varies by +-20 %); the peers ran once. clapper's time per stroke is measured on a "
             f"{RATE_N} x {RATE_N} chart of the same domain and settings ({2 * RATE_N * RATE_N:,} strokes, "
             "least of several runs), so that a process's start (thread pool, first touches of code and "
             "data, about 5 ms) is not charged to 800 strokes; the 20 x 20 column is the whole chart as a "
             "user sees it, start included; its errors are those of the 20 x 20 chart, as for the peers. The chart CSVs print 6 decimals (deg, rad/s), so "
             "errors up to 1e-6 are within their rounding and shown as <= 1e-6.\n")
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
        L.append(f"| {name} | {per_words} us | {chart_words} | {csv_err(da)} | {csv_err(dv)} | {agree} of {n} |")
    L.append("")
    L.append("## Speed ratios (time per stroke, one thread each)\n")
    L.append("Against clapper's default, and against the fastest clapper run above whose largest errors (first "
             "strike angle and strike velocity, both) are no larger than the peer's: equal or better accuracy.\n")
    L.append("| peer | peer / clapper default | clapper at equal or better accuracy | peer / that clapper run | peer's RHS calls per stroke |")
    L.append("|---|---:|---:|---:|---:|")
    for name, ratio, m_rtol, m_ratio, evals in peer_rows:
        m_words = f"Taylor, rtol {float(m_rtol):g}" if m_rtol else "none of the runs"
        m_ratio_words = f"{m_ratio:,.0f} x" if m_ratio else ""
        L.append(f"| {name} | {ratio:,.0f} x | {m_words} | {m_ratio_words} | "
                 f"{'' if evals is None else f'{evals:.0f}'} |")
    L.append("")
    L.append("## The lab bell, one stroke ringing right\n")
    L.append("Errors against clapper's Dormand-Prince at 1e-12; times per stroke, one thread (clapper: the least of twenty runs "
             "of 2000 strokes in one process; the peers: one stroke).\n")
    L.append("| implementation | time per stroke | error of first strike angle (deg) | error of strike velocity (rad/s) | time / clapper's |")
    L.append("|---|---:|---:|---:|---:|")
    for name, t, da, dv, ratio in lab_rows:
        L.append(f"| {name} | {t * 1e6:,.0f} us | {da:.1e} | {dv:.1e} | {ratio:,.0f} x |")
    L.append("")
    L.append(f"A 1000 x 1000 chart of both styles (2,000,000 strokes) on both cores: {big_reported:.1f} s "
             f"of sweeping ({big:.1f} s for the whole process, with writing the CSV).\n")
    with open(os.path.join(ROOT, "docs", "performance.md"), "w") as f:
        f.write("\n".join(L) + "\n")
        f.write(open(os.path.join(ROOT, "bench", "performance-notes.md")).read())
    print("\n".join(L))


if __name__ == "__main__":
    main()
