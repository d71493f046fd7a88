"""Tests of the Python package: each checks the Python face against the
library by a second route (the command line, a chart against single
strokes, synthetic signals with known answers, the bell's mirror symmetry)."""

import json
import math
import os
import shutil
import subprocess
import sys
import threading
import time
import warnings
from pathlib import Path

import numpy as np
import pytest

import clapper

ROOT = Path(__file__).resolve().parents[3]


def cli():
    """The command-line binary built beside the package, if there is one."""
    for p in (os.environ.get("CLAPPER_BIN"), ROOT / "target/release/clapper", shutil.which("clapper")):
        if p and Path(p).is_file():
            return str(p)
    pytest.skip("no clapper binary built (cargo build --release)")


def test_print_shows_the_command_lines_summary_and_the_json_is_the_same():
    sim = clapper.simulate(clapper.preset("lab"))
    text = subprocess.run([cli(), "simulate", "--preset", "lab"], capture_output=True, text=True, check=True).stdout
    assert str(sim).strip() == text.strip()
    assert "first strike     -94.95 deg" in str(sim)
    out = subprocess.run(
        [cli(), "simulate", "--preset", "lab", "--json"], capture_output=True, text=True, check=True
    ).stdout
    assert sim.data == json.loads(out)


def test_quantities_and_trace():
    sim = clapper.simulate(clapper.preset("lab"), theta0=171)
    assert sim.verdict == "right" and sim.sustained
    assert sim.first_strike_angle_deg == pytest.approx(-94.95, abs=0.01)
    tr = sim.trace
    assert len(tr) > 1000 and np.all(np.diff(tr.t) >= 0)
    assert tr.theta_deg[0] == pytest.approx(171.0)
    # The clapper stays within the bell's contact angle (phi_max 26 deg).
    assert np.max(np.abs(tr.phi_deg)) <= 26.0 + 1e-6
    # Mirror symmetry: the backstroke is the handstroke reflected.
    hand, back = sim.strokes
    assert back["first_strike"]["theta_deg"] == pytest.approx(-hand["first_strike"]["theta_deg"], abs=1e-9)
    assert clapper.simulate(trace=False).trace is None


def test_a_chart_cell_is_the_stroke_simulated_at_that_point():
    c = clapper.chart(grid=(12, 9), r_range=(0.0, 0.6), lb_range=(1.0, 2.0))
    assert c.right["strike_angle_deg"].shape == (9, 12)
    assert set(c.styles) == {"right", "wrong"}
    checked = 0
    for j in (2, 5, 8):
        for i in (1, 6, 10):
            x, y = c.r_over_lc[i], c.lb_over_lc[j]
            sim = clapper.simulate(clapper.Bell.chart_point(x, y), strokes=1, trace=False)
            sustained = c.right["sustained"][j, i] == 1.0
            assert sim.sustained == sustained, (x, y)
            if sustained:
                assert c.right["strike_angle_deg"][j, i] == pytest.approx(sim.first_strike_angle_deg, abs=1e-9)
                checked += 1
            else:
                assert math.isnan(c.right["strike_angle_deg"][j, i])
    assert checked > 0


def test_the_gil_is_released_during_a_sweep():
    done = threading.Event()
    result = {}

    def sweep():
        result["chart"] = clapper.chart(grid=150)
        done.set()

    t = threading.Thread(target=sweep)
    t.start()
    ticks = 0
    while not done.is_set():
        ticks += 1
        time.sleep(0.001)
    t.join()
    # Held, the GIL would stop this thread for the whole sweep.
    assert ticks > 20, ticks
    assert result["chart"].right["sustained"].shape == (150, 150)


def test_pandas_and_xarray_when_installed():
    c = clapper.chart(grid=5)
    pd = pytest.importorskip("pandas")
    df = c.to_pandas()
    assert isinstance(df, pd.DataFrame) and len(df) == 5 * 5 * 2
    assert list(df.columns[:3]) == ["r_over_lc", "lb_over_lc", "style"]
    xr = pytest.importorskip("xarray")
    ds = c.to_xarray()
    assert isinstance(ds, xr.Dataset) and ds["strike_angle_deg"].shape == (2, 5, 5)


def test_errors_carry_the_librarys_message():
    with pytest.raises(ValueError, match="restitution = 2 is out of range"):
        clapper.simulate(restitution=2)
    with pytest.raises(ValueError, match="unknown option 'bogus'"):
        clapper.simulate(bogus=1)
    with pytest.raises(ValueError, match="unknown preset"):
        clapper.preset("tenor")
    with pytest.raises(ValueError):
        clapper.Bell(bell_period_s=-2.0, clapper_period_s=1.6, r_m=0.1, phi_max_deg=26)


def test_a_bell_from_its_fields_and_from_its_file():
    b = clapper.Bell(name="Tenor", bell_period_s=2.1, clapper_period_s=1.6, r_m=0.1, phi_max_deg=26)
    assert b.tb_s == pytest.approx(2.1) and b.tc_s == pytest.approx(1.6) and b.name == "Tenor"
    f = clapper.Bell.from_file(ROOT / "examples/lab-tower.toml")
    assert f.tb_s == pytest.approx(1.225)
    assert "lab bell (tower)" in repr(f)


def test_liftoff_closed_form_and_exact():
    r = clapper.liftoff(lb_over_lc=1.68, phi_max_deg=26)
    assert r["right_deg"] == pytest.approx(124.70, abs=0.01)
    # For r = 0 the two styles' lift-off angles are supplementary.
    assert r["right_deg"] + r["wrong_deg"] == pytest.approx(180.0, abs=1e-9)
    lab = clapper.liftoff(clapper.preset("lab"))
    sim = clapper.simulate(clapper.preset("lab"), trace=False)
    assert lab.data["right_deg"] == pytest.approx(sim.strokes[0]["liftoff_theta_deg"], abs=1e-3)


def test_restitution_recovers_r_and_r2_from_synthetic_drops():
    R, R2 = 0.1, 0.3
    v, jumps = 1.0, []
    e = math.sqrt(R)
    for k in range(5):
        jumps.append(v * (1 + e))
        v *= e
        e = math.sqrt(R2)
    rep = clapper.restitution([jumps, [2 * j for j in jumps]])
    assert rep["r_first"] == pytest.approx(R, rel=1e-9)
    assert rep["r_later"] == pytest.approx(R2, rel=1e-9)
    with pytest.raises(ValueError):
        clapper.restitution([[1.0]])


def test_modes_finds_synthetic_partials():
    rate = 22050.0
    t = np.arange(int(rate * 2)) / rate
    sig = np.sin(2 * np.pi * 440 * t) * np.exp(-t / 0.8) + 0.5 * np.sin(2 * np.pi * 1047 * t) * np.exp(-t / 0.5)
    rep = clapper.modes(sig, rate)
    freqs = sorted(m["freq_hz"] for m in rep["modes"])
    assert any(abs(f - 440) < 1 for f in freqs) and any(abs(f - 1047) < 1 for f in freqs)
    with pytest.raises(ValueError, match="one-dimensional"):
        clapper.modes(np.zeros((3, 3)), rate)


def test_strikes_in_the_shipped_synthetic_tower_recording():
    wav = ROOT / "examples/data/tower.wav"
    truth = ROOT / "examples/data/tower-truth.csv"
    if not wav.is_file():
        pytest.skip("examples/data not generated")
    samples, rate = clapper.read_wav(wav)
    nominals = json.loads((ROOT / "examples/data/tower-nominals.json").read_text())
    rep = clapper.strikes(samples, rate, nominals)
    true_times = np.loadtxt(truth, delimiter=",", skiprows=1, usecols=1)
    found = np.array([s["t_s"] for s in rep["strikes"]])
    assert len(found) == len(true_times)
    assert np.median(np.abs(np.sort(found) - np.sort(true_times))) < 0.003
    assert "strikes" in str(rep)


def test_diagnose_a_preset_and_a_ring_file():
    rep = clapper.diagnose(clapper.preset("lab"))
    text = subprocess.run([cli(), "diagnose", "--preset", "lab"], capture_output=True, text=True, check=True).stdout
    assert str(rep).strip() == text.strip()
    ring = clapper.diagnose(ROOT / "examples/ring-of-eight.csv")
    assert len(ring["bells"]) == 8


def readme_python_blocks():
    text = (ROOT / "README.md").read_text()
    return [b.split("```")[0] for b in text.split("```python\n")[1:]]


def test_readmes_python_blocks_run_and_the_fig10_block_is_the_example_file(tmp_path, monkeypatch):
    blocks = readme_python_blocks()
    assert len(blocks) >= 2
    fig10 = (ROOT / "examples/python/fig10.py").read_text()
    assert fig10 in blocks, "README's Fig 10 block differs from examples/python/fig10.py"
    monkeypatch.chdir(ROOT)
    for b in blocks:
        if b == fig10:
            continue
        exec(compile(b, "README.md", "exec"), {})
    pytest.importorskip("matplotlib")
    out = tmp_path / "fig10.png"
    subprocess.run([sys.executable, str(ROOT / "examples/python/fig10.py"), str(out)], check=True)
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and out.stat().st_size > 20_000


# Issue 42: the package's messages say what is wrong in the caller's terms.


def test_restitution_given_one_flat_list_says_it_takes_drops_of_jumps():
    with pytest.raises(ValueError, match=r"list of drops, each a list of the clapper's velocity jumps") as e:
        clapper.restitution([1.0, 0.35, 0.2])
    msg = str(e.value)
    assert "at least two a drop" in msg and "one flat list of 3 numbers" in msg
    assert "[[1.0, 0.35, 0.2]]" in msg and "out of range" not in msg
    # Which drop is short, and how short.
    with pytest.raises(ValueError, match=r"drop 2 of 2 has 1 jump$"):
        clapper.restitution([[1.0, 0.35], [0.5]])
    with pytest.raises(ValueError, match=r"drop 1, jump 2 is -0.3: .* > 0"):
        clapper.restitution([[1.0, -0.3]])
    with pytest.raises(ValueError, match="got no drops"):
        clapper.restitution([])
    with pytest.raises(TypeError, match=r"drop 1, jump 2 is 'a': jumps are numbers"):
        clapper.restitution([[1.0, "a"]])
    # The hint it gives works.
    assert clapper.restitution([[1.0, 0.35, 0.2]])["r_first"] > 0


def test_a_non_finite_option_names_it_and_its_unit_not_json():
    with pytest.raises(ValueError, match=r"simulate: theta0 must be a finite number of degrees .*, not nan$") as e:
        clapper.simulate(theta0=float("nan"))
    assert "line 1" not in str(e.value) and "column" not in str(e.value)
    with pytest.raises(ValueError, match=r"chart: stiffness must be a finite number in N m/rad .*, not inf"):
        clapper.chart(grid=3, stiffness=float("inf"))
    with pytest.raises(ValueError, match=r"liftoff: theta0 must be a finite number \(degrees"):
        clapper.liftoff(theta0=float("nan"))
    with pytest.raises(ValueError, match=r"chart: r_range must be a pair of finite numbers"):
        clapper.chart(grid=3, r_range=(0.0, float("nan")))


def test_an_option_of_the_wrong_type_is_a_type_error_naming_it():
    with pytest.raises(TypeError, match=r"simulate: theta0 must be a finite number of degrees .*, not 'abc'$") as e:
        clapper.simulate(theta0="abc")
    # Still a ValueError, as such errors were before.
    assert isinstance(e.value, ValueError) and "expected f64" not in str(e.value)
    with pytest.raises(TypeError, match=r"simulate: strokes must be a whole number of strokes \(1 to 10000\), not 'x'"):
        clapper.simulate(strokes="x")
    with pytest.raises(ValueError, match=r"simulate: strokes must be a whole number of strokes .*, not -1$"):
        clapper.simulate(strokes=-1)
    with pytest.raises(ValueError, match=r"simulate: style must be one of 'right', 'wrong', not 'rigth'; did you mean 'right'\?"):
        clapper.simulate(style="rigth")
    with pytest.raises(ValueError, match=r"chart: style must be one of 'right', 'wrong', 'both', not 'x'$"):
        clapper.chart(grid=3, style="x")
    with pytest.raises(TypeError, match=r"chart: grid must be a pair of whole numbers"):
        clapper.chart(grid="x")
    with pytest.raises(ValueError, match=r"chart: grid must be a pair of whole numbers"):
        clapper.chart(grid=(1, 2, 3))
    with pytest.raises(ValueError, match=r"chart: grid must be a whole number of points .*, not 2.5$"):
        clapper.chart(grid=2.5)
    with pytest.raises(ValueError, match=r"preset must be one of 'lab', 'gsm-tenor', not 'tenor'; did you mean 'gsm-tenor'\?$"):
        clapper.simulate(preset="tenor")
    with pytest.raises(TypeError, match=r"liftoff: theta0 must be a finite number \(degrees.*not 'x'"):
        clapper.liftoff(theta0="x")
    with pytest.raises(TypeError, match=r"modes: rate_hz must be a finite number \(the sample rate in Hz\)"):
        clapper.modes([0.0, 1.0], "x")
    with pytest.raises(TypeError, match=r"strikes: nominals_hz\[0\] must be a finite number"):
        clapper.strikes([0.0] * 100, 8000, ["a"])
    with pytest.raises(TypeError, match=r"Bell: bell_period_s must be a finite number, not 'x'"):
        clapper.Bell(bell_period_s="x", clapper_period_s=1.6, r_m=0.1, phi_max_deg=26)
    with pytest.raises(ValueError, match=r"simulate: theta0 must be a finite number of degrees .*, not 1000"):
        clapper.simulate(theta0=10**400)
    with pytest.raises(ValueError, match=r"simulate: strokes must be a whole number of strokes .*, not 1000"):
        clapper.simulate(strokes=10**30)
    with pytest.raises(ValueError, match=r"Bell.chart_point: r_over_lc must be a finite number .*, not nan$"):
        clapper.Bell.chart_point(float("nan"), 1.5)
    with pytest.raises(TypeError, match=r"Bell.chart_point: lb_over_lc must be a finite number .*, not 'a'$"):
        clapper.Bell.chart_point(0.3, "a")
    with pytest.raises(ValueError, match=r"simulate: give the bell once: as the bell argument or as preset=, not both"):
        clapper.simulate(clapper.preset("lab"), preset="gsm-tenor")
    # numpy numbers are numbers.
    assert clapper.simulate(theta0=np.float32(171), strokes=np.int64(1), trace=False).verdict == "right"


def test_an_unknown_option_is_named_with_the_near_ones_not_all():
    with pytest.raises(ValueError, match=r"^simulate: unknown option 'theta'; did you mean 'theta0'\?$"):
        clapper.simulate(theta=170)
    with pytest.raises(ValueError, match=r"unknown option 'restitutoin'; did you mean 'restitution'"):
        clapper.chart(grid=3, restitutoin=0.3)
    with pytest.raises(ValueError) as e:
        clapper.simulate(xyzzy=1)
    assert str(e.value) == "simulate: unknown option 'xyzzy'; see help(clapper.simulate) for its options"
    with pytest.raises(ValueError, match=r"^Bell: unknown field 'bell_period'; did you mean 'bell_period_s'"):
        clapper.Bell(bell_period=2.1, clapper_period_s=1.6, r_m=0.1, phi_max_deg=26)
    # The kebab-case spellings the library takes are still taken.
    assert clapper.simulate(trace=False, **{"phi-max": 26}).verdict == "right"


def test_every_number_an_option_takes_has_its_unit_for_messages():
    from clapper import _clapper, _OPTION_WORDS

    for request in ("simulate", "chart"):
        for key, kind, _choices, _n in _clapper.request_keys(request):
            if kind == "number" or kind.startswith("array of") or kind == "count":
                assert key.replace("-", "_") in _OPTION_WORDS, (request, key)


def test_diagnose_given_a_recording_says_it_takes_bell_files_and_where_recordings_go(tmp_path):
    wav = tmp_path / "x.wav"
    rate = 8000
    pcm = (np.sin(np.arange(rate) * 0.1) * 3000).astype("<i2").tobytes()
    header = b"RIFF" + (36 + len(pcm)).to_bytes(4, "little") + b"WAVEfmt " + (16).to_bytes(4, "little")
    header += (1).to_bytes(2, "little") + (1).to_bytes(2, "little") + rate.to_bytes(4, "little")
    header += (2 * rate).to_bytes(4, "little") + (2).to_bytes(2, "little") + (16).to_bytes(2, "little")
    wav.write_bytes(header + b"data" + len(pcm).to_bytes(4, "little") + pcm)
    with pytest.raises(ValueError, match=r"diagnose: .*x\.wav is a recording \(WAV\).*bell or ring file \(TOML, or CSV") as e:
        clapper.diagnose(str(wav))
    assert "clapper.read_wav" in str(e.value) and "clapper.strikes" in str(e.value)
    # The functions it points at take it.
    samples, r = clapper.read_wav(wav)
    assert r == rate and len(samples) == rate
    with pytest.raises(ValueError, match="Bell.from_file: .* is a recording"):
        clapper.Bell.from_file(wav)
    binary = tmp_path / "bell.toml"
    binary.write_bytes(b"\xff\xfe\x00junk")
    with pytest.raises(ValueError, match=r"is not a text file \(byte 0 is not UTF-8\); diagnose reads"):
        clapper.diagnose(binary)


def test_a_missing_file_is_file_not_found_in_every_call_that_reads_one(tmp_path):
    for call in (
        lambda p: clapper.diagnose(p),
        lambda p: clapper.Bell.from_file(p),
        lambda p: clapper.read_wav(p),
    ):
        for name in ("absent.toml", "absent.csv", "absent.wav"):
            with pytest.raises(FileNotFoundError):
                call(tmp_path / name)
            with pytest.raises(FileNotFoundError):
                call(str(tmp_path / name))


def test_a_bells_path_given_as_its_text_points_at_from_file():
    with pytest.raises(ValueError, match=r"looks like a file's path.*Bell\.from_file\('tenor\.toml'\)"):
        clapper.Bell("tenor.toml")


IMPOSSIBLE = dict(
    name="Odd",
    bell_mass_kg=45.8,
    clapper_mass_kg=1.65,
    a_m=0.24,
    b_m=0.25,
    bell_inertia_kg_m2=4.1,
    clapper_inertia_kg_m2=0.093,
    r_m=0.10,
    phi_max_deg=26,
)


def test_model_warnings_are_python_warnings_and_stay_in_sim_warnings():
    bell = clapper.Bell(**IMPOSSIBLE)
    with pytest.warns(clapper.ClapperWarning, match=r"physically impossible") as caught:
        sim = clapper.simulate(bell, trace=False)
    assert issubclass(clapper.ClapperWarning, UserWarning)
    assert sim.warnings and [str(w.message) for w in caught] == sim.warnings
    # Pointing at the caller's line, not the package's.
    assert caught[0].filename == __file__
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert clapper.simulate(clapper.preset("gsm-tenor"), trace=False).warnings == []


def test_tower_rings_the_example_ring_as_the_command_line_does():
    ring = ROOT / "examples/ring-of-eight-tower.toml"
    rep = clapper.tower(ring, "Plain Bob Major", leads=1, striking_sd_ms=10.0, turn=[8])
    args = ["tower", str(ring), "--method", "Plain Bob Major", "--leads", "1", "--striking-sd", "10", "--turn", "8"]
    text = subprocess.run([cli(), *args], capture_output=True, text=True, check=True).stdout
    assert str(rep).strip() == text.strip()
    assert rep["rows"] == 17 and rep["last_row"] == "13527486"
    h = rep.history
    assert len(h["time_s"]) == len(h["force_east_n"]) == len(h["sway_north_m"])
    # The turned tenor's force is the east-west force; the sway peak is the report's.
    assert np.abs(h["force_east_n"]).max() > 1000.0
    peak = np.hypot(h["sway_east_m"], h["sway_north_m"]).max()
    assert abs(peak - rep["peak_sway_m"]) < 1e-12 * max(peak, 1.0)
    with pytest.raises(ValueError, match="no method 'Plain Bobb Major'"):
        clapper.tower(ring, "Plain Bobb Major")


def test_diagnose_gives_mirror_images_the_same_problems_and_changes_as_the_cli(tmp_path):
    # Issue 45: the lab bell with its clapper pivot 2 and 5 mm either way.
    lab = (ROOT / "examples/lab.toml").read_text()
    for d in ["0.002", "0.005"]:
        bells = {}
        for sign in ["", "-"]:
            path = tmp_path / f"lab{sign}{d}.toml"
            path.write_text(lab + f"pivot_offset_m = {sign}{d}\n")
            rep = clapper.diagnose(path)
            cli_json = subprocess.run(
                [cli(), "diagnose", str(path), "--json"], capture_output=True, text=True, check=True
            ).stdout
            assert rep.data == json.loads(cli_json)
            bells[sign] = rep["bells"][0]
        p, m = bells[""], bells["-"]
        assert p["problems"] == m["problems"] and p["problems"]
        kinds = lambda b: [(c["kind"], c["problems_left"], c.get("flight_mass_change_kg")) for c in b["changes"]]
        assert kinds(p) == kinds(m)
        assert p["odd_struck"]["odd_struck_ms"] == -m["odd_struck"]["odd_struck_ms"]
        assert p["odd_struck"]["style"] == p["usual_style"]


@pytest.mark.filterwarnings("ignore::clapper.ClapperWarning")
def test_simulate_says_what_a_bell_sustains_instead():
    sim = clapper.simulate(clapper.preset("lab"), pivot_offset=0.005, trace=False)
    assert (sim.sustained, sim.verdict, sim.sustains_instead) == (False, "neither", "wrong")
    assert clapper.simulate(clapper.preset("lab"), trace=False).sustains_instead is None


def test_chart_takes_threads_and_the_count_changes_nothing():
    one = clapper.chart(grid=5, threads=1)
    two = clapper.chart(grid=5, threads=2)
    for style in ["right", "wrong"]:
        for q, v in one.values[style].items():
            np.testing.assert_array_equal(v, two.values[style][q], err_msg=f"{style} {q}")
    for bad in [0, 2000]:
        with pytest.raises(ValueError, match="threads"):
            clapper.chart(grid=3, threads=bad)


def _stereo_wav(path, left, right, rate):
    """`left` and `right` (equal lengths, within ±1) as a 16-bit stereo WAV."""
    pcm = (np.stack([left, right], axis=1) * 30000).astype("<i2").tobytes()
    header = b"RIFF" + (36 + len(pcm)).to_bytes(4, "little") + b"WAVEfmt " + (16).to_bytes(4, "little")
    header += (1).to_bytes(2, "little") + (2).to_bytes(2, "little") + rate.to_bytes(4, "little")
    header += (4 * rate).to_bytes(4, "little") + (4).to_bytes(2, "little") + (16).to_bytes(2, "little")
    path.write_bytes(header + b"data" + len(pcm).to_bytes(4, "little") + pcm)


def test_read_wav_hears_the_channel_asked_counted_from_1(tmp_path):
    # Session 17's tester: read_wav had no channel argument where the CLI
    # has --channel N|mix|auto (from 1) and the web channel=. Two channels
    # of different levels; each asked for alone, mixed, and 0 refused.
    rate = 8000
    left = 0.5 * np.sin(2 * np.pi * 440 * np.arange(rate) / rate)
    right = 0.25 * np.sin(2 * np.pi * 660 * np.arange(rate) / rate)
    _stereo_wav(tmp_path / "two.wav", left, right, rate)
    q = lambda x: (x * 30000).astype("<i2") / 32768.0  # noqa: E731
    np.testing.assert_array_equal(clapper.read_wav(tmp_path / "two.wav", channel=1)[0], q(left))
    np.testing.assert_array_equal(clapper.read_wav(tmp_path / "two.wav", channel=2)[0], q(right))
    mixed = clapper.read_wav(tmp_path / "two.wav", channel="mix")[0]
    np.testing.assert_allclose(mixed, 0.5 * (q(left) + q(right)), atol=1e-12)
    np.testing.assert_array_equal(clapper.read_wav(tmp_path / "two.wav")[0], mixed)
    with pytest.raises(ValueError, match="count from 1"):
        clapper.read_wav(tmp_path / "two.wav", channel=0)
    with pytest.raises(ValueError, match="channel 3 asked, the recording has 2"):
        clapper.read_wav(tmp_path / "two.wav", channel=3)


def test_read_wav_warns_of_channels_that_disagree_in_time(tmp_path):
    # Synthetic: strikes (1 kHz, decaying) at uneven times over 30 s; the
    # second channel the first 20 ms later (tester14's late stereo channel),
    # then the two together.
    rate = 16000
    t = np.arange(30 * rate) / rate
    x = np.zeros_like(t)
    rng = np.random.default_rng(7)
    for t0 in np.cumsum(rng.uniform(0.2, 0.3, 110)):
        on = t >= t0
        x[on] += np.sin(2 * np.pi * 1000 * (t[on] - t0)) * np.exp(-(t[on] - t0) / 0.08)
    x /= 1.2 * np.abs(x).max()
    lag = int(0.020 * rate)
    late = np.concatenate([np.zeros(lag), x[:-lag]])
    _stereo_wav(tmp_path / "late.wav", x, 0.7 * late, rate)
    _stereo_wav(tmp_path / "together.wav", x, 0.7 * x, rate)
    told = r"channel 2 is heard 20 ms later than channel 1: channel 1 used alone"
    with pytest.warns(clapper.ClapperWarning, match=told):
        samples, r = clapper.read_wav(tmp_path / "late.wav")
    assert r == rate and len(samples) == len(x)
    # The first channel alone, not the two mixed (tester16 fault 7).
    np.testing.assert_array_equal(samples, (x * 30000).astype("<i2") / 32768.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        clapper.read_wav(tmp_path / "together.wav")
