#!/usr/bin/env python3
"""Run Brenda (oekrice/striking, a Streamlit striking app) headless on one
recording and write the strikes it finds as CSV (bell,t_s,confidence).

    python3 brenda_run.py BRENDA_DIR REC.wav --nominals F1,F2,.. --out strikes.csv

BRENDA_DIR is a local checkout of oekrice/striking (its licence allows
personal use only: nothing of it is in this repository, it is imported
from the path given). Its page "Analyse Recording" is followed step by
step as a user would go through it: the bells' nominals (its tower
database gives them; here the caller does), "Make new profile" (its
frequency profiles learned from the recording itself: up to 10
reinforcement steps over the first 60 s, the more intense search on more
than 8 bells, as the page's defaults), then "Find strike times" when the
profile's quality is over 0.85 (the page allows it from there). Its
Streamlit calls are answered by a stand-in module: its messages are
collected, and `st.stop()` ends the run as a refusal.

The times written are its strike times as its own CSV gives them (the
row's frame index times its 10 ms step, from the recording's start), for
every row it found (its download drops a first backstroke row; kept
here). It does not hear double strikes.
"""

import argparse
import os
import sys
import time
import types


class Stopped(Exception):
    """The app stopped (st.stop): a refusal."""


class _State(dict):
    """Streamlit's session_state: a dict read and written as attributes."""

    def __getattr__(self, k):
        try:
            return self[k]
        except KeyError as e:
            raise AttributeError(k) from e

    def __setattr__(self, k, v):
        self[k] = v

    def __delattr__(self, k):
        del self[k]


def stand_in_streamlit(messages):
    """A module answering the Streamlit calls Brenda's listening code makes."""
    st = types.ModuleType("streamlit")
    st.session_state = _State()

    class _Box:
        def write(self, *a, **k):
            messages.append(" ".join(str(x) for x in a))

        def progress(self, *a, **k):
            pass

    def error(msg, *a, **k):
        messages.append("ERROR: " + str(msg))

    def stop():
        raise Stopped(next((m for m in reversed(messages) if m.startswith("ERROR")), "stopped"))

    st.error = error
    st.stop = stop
    st.rerun = stop
    st.write = _Box().write
    st.pyplot = lambda *a, **k: None
    st.empty = lambda: _Box()
    st.cache_data = lambda *a, **k: (lambda f: f)
    for name in ("main_log", "quality_log", "current_log", "analysis_log", "analysis_sublog", "analysis_sublog2"):
        setattr(st, name, _Box())
    return st


def read_wav(path):
    """Samples as Brenda's upload reads them: the first channel, over 2^15."""
    import numpy as np
    from scipy.io import wavfile

    fs, data = wavfile.read(path)
    if data.ndim > 1:
        data = data[:, 0]
    if data.dtype.kind == "f":
        return fs, np.asarray(data, dtype=float)
    return fs, np.asarray(data, dtype=float) / 2 ** 15


def run(brenda_dir, wav, nominals, reinforce_s=60.0, steps=10):
    """(strikes [(bell, t_s, confidence)], messages, refusal or None)."""
    import numpy as np

    messages = []
    st = stand_in_streamlit(messages)
    sys.modules["streamlit"] = st
    sys.path.insert(0, os.path.abspath(brenda_dir))
    import matplotlib

    matplotlib.use("Agg")
    from listen_classes import parameters
    from listen_main_functions import (
        establish_initial_rhythm,
        do_reinforcement,
        find_final_strikes,
        filter_final_strikes,
    )

    ss = st.session_state
    for k, v in dict(
        testing_mode=False, trim_flag=False, allstrikes=None, allcerts=None, reinforce_frequency_data=None,
        reinforce_test_frequencies=None, reinforce_frequency_profile=None, final_freqs=None,
        final_freqprobs=None, already_saved=False, analysis_status=0, handstroke_first=True,
    ).items():
        ss[k] = v
    fs, x = read_wav(wav)
    ss.audio_signal, ss.fs, ss.audio_filename = x, fs, os.path.basename(wav)[:-4]
    tmax = len(x) / fs
    # The page's sliders: the whole recording; 60 s (at most its length) to learn from.
    reinforce_tmax = min(reinforce_s, tmax)
    nominals = sorted(nominals, reverse=True)
    try:
        paras = parameters(np.array(nominals), 0.0, tmax, reinforce_tmax, steps, len(nominals) > 8)
        data = establish_initial_rhythm(paras)
        do_reinforcement(paras, data)
        q = ss.reinforce_frequency_data
        if q is None or q[2] <= 0.85:
            return [], messages, "Frequency profiles not good enough to use (quality %s)" % (
                "none" if q is None else "%.3f" % q[2])
        messages.append("frequency profile quality %.3f" % q[2])
        establish_initial_rhythm(paras, final=True)
        ss.final_freqs = ss.reinforce_test_frequencies
        ss.final_freqprobs = ss.reinforce_frequency_profile
        find_final_strikes(paras)
        filter_final_strikes(paras)
    except Stopped as e:
        return [], messages, str(e)
    s, c = np.asarray(ss.allstrikes), np.asarray(ss.allcerts)
    out = []
    for row in range(s.shape[1]):
        for b in range(s.shape[0]):
            out.append((b + 1, float(s[b, row]) * paras.dt + paras.overall_tmin, float(c[b, row])))
    out.sort(key=lambda r: r[1])
    return out, messages, None


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("brenda_dir")
    p.add_argument("wav")
    p.add_argument("--nominals", required=True, help="Hz, treble first")
    p.add_argument("--out", required=True)
    p.add_argument("--reinforce-s", type=float, default=60.0)
    p.add_argument("--steps", type=int, default=10)
    a = p.parse_args()
    t0 = time.process_time()
    strikes, messages, refusal = run(a.brenda_dir, a.wav, [float(f) for f in a.nominals.split(",")],
                                     a.reinforce_s, a.steps)
    with open(a.out, "w") as f:
        f.write("bell,t_s,confidence\n")
        for b, t, c in strikes:
            f.write("%d,%.4f,%.3f\n" % (b, t, c))
    cpu = time.process_time() - t0
    print("brenda: %d strikes, %.1f s CPU%s" % (len(strikes), cpu, "; refused: " + refusal if refusal else ""))
    for m in messages[-3:]:
        print("  " + m)


if __name__ == "__main__":
    main()
