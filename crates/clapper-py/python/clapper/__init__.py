"""clapper: church bells rung full circle, in Python.

The bell and its clapper swing as two coupled pendulums; the clapper
strikes the bell and bounces. This package is the Rust library behind the
``clapper`` command line, with the same model (docs/model.md), the same
defaults and the same reports: what a function here returns is what the
command line prints with ``--json``, and ``print()`` of a result shows the
command line's text.

Units are in every name: ``_deg`` degrees, ``_ms`` milliseconds, ``_s``
seconds, ``_hz`` hertz; chart positions are the paper's ratios r/L_c and
L_b/L_c. Angles in traces are radians (``theta``, ``phi``) with degree
copies (``theta_deg``, ``phi_deg``).

>>> import clapper
>>> sim = clapper.simulate(clapper.preset("lab"))
>>> sim.verdict
'right'

Errors: bad input raises ``ValueError``, a numerical failure
``RuntimeError``; both carry the library's one-line message.
"""

from __future__ import annotations

import json
import os
from typing import Any, Dict, Iterable, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np

from . import _clapper

__version__: str = _clapper.__version__

#: The bells of the paper's Table 1.
PRESETS: Tuple[str, ...] = ("lab", "gsm-tenor")
#: The angle a stroke starts from, at rest (deg), unless told.
DEFAULT_THETA0_DEG: float = _clapper.DEFAULT_THETA0_DEG
#: The coefficient of restitution R of a strike, unless told.
DEFAULT_RESTITUTION: float = _clapper.DEFAULT_RESTITUTION
#: The least amplitude ratio of a second strike heard as a double strike.
DEFAULT_DOUBLE_MIN_RATIO: float = _clapper.DEFAULT_DOUBLE_MIN_RATIO
#: Partials within this many dB of the strongest are reported by :func:`modes`.
DEFAULT_MODES_RANGE_DB: float = _clapper.DEFAULT_MODES_RANGE_DB

__all__ = [
    "Bell",
    "Chart",
    "Report",
    "Simulation",
    "Trace",
    "chart",
    "diagnose",
    "liftoff",
    "modes",
    "preset",
    "read_wav",
    "restitution",
    "simulate",
    "strikes",
    "PRESETS",
]

PathLike = Union[str, "os.PathLike[str]"]


def _f64(data: bytes) -> np.ndarray:
    """Little-endian float64 bytes from the native module as a writable array."""
    return np.frombuffer(data, dtype="<f8").astype(np.float64)


def _as_f64_bytes(values: Any, what: str) -> bytes:
    arr = np.ascontiguousarray(values, dtype="<f8")
    if arr.ndim != 1:
        raise ValueError(f"{what}: expected a one-dimensional array, got shape {arr.shape}")
    return arr.tobytes()


def _toml_value(v: Any, key: str) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, float, np.integer, np.floating)):
        x = float(v)
        if not np.isfinite(x):
            raise ValueError(f"{key}: {x} is not a finite number")
        return repr(x) if isinstance(v, (float, np.floating)) else str(int(v))
    if isinstance(v, str):
        # A JSON string is a valid TOML basic string.
        return json.dumps(v)
    if isinstance(v, Mapping):
        inner = ", ".join(f"{k} = {_toml_value(x, f'{key}.{k}')}" for k, x in v.items())
        return "{ " + inner + " }"
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_toml_value(x, key) for x in v) + "]"
    raise TypeError(f"{key}: cannot write a {type(v).__name__} into a bell file")


def _bell_toml(fields: Mapping[str, Any]) -> str:
    return "".join(f"{k} = {_toml_value(v, k)}\n" for k, v in fields.items())


class Report:
    """A report of the library: its data (``.data``, the JSON the command
    line's ``--json`` prints, as a dict) and its text (``str(report)``, what
    the command line prints). Items read through: ``report["key"]``."""

    def __init__(self, data: Dict[str, Any], text: str) -> None:
        self.data = data
        self.text = text

    def __getitem__(self, key: str) -> Any:
        return self.data[key]

    def __contains__(self, key: object) -> bool:
        return key in self.data

    def keys(self) -> Iterable[str]:
        return self.data.keys()

    def __str__(self) -> str:
        return self.text

    def __repr__(self) -> str:
        first = self.text.strip().splitlines()[0] if self.text.strip() else ""
        return f"<{type(self).__name__}: {first}>"


class Bell:
    """A bell and its clapper, hung for full-circle ringing.

    Made from a bell file's text (TOML, as ``clapper simulate --bell``
    reads), from its fields as keyword arguments, from a file
    (:meth:`from_file`), a preset (:func:`preset`) or a point of the
    clapping chart (:meth:`chart_point`)::

        clapper.Bell(name="Tenor", bell_period_s=2.1, clapper_period_s=1.6,
                     r_m=0.1, phi_max_deg=26)

    Its properties (chart position, lengths, periods, masses) are the
    library's, as ``clapper simulate --json`` reports them under ``bell``.
    """

    def __init__(self, toml: Optional[str] = None, /, **fields: Any) -> None:
        if toml is not None and fields:
            raise TypeError("give a bell file's text or its fields as keywords, not both")
        if toml is None:
            if not fields:
                raise TypeError(
                    "give a bell file's text or its fields, e.g. "
                    "Bell(bell_period_s=2.1, clapper_period_s=1.6, r_m=0.1, phi_max_deg=26)"
                )
            toml = _bell_toml(fields)
        self._init({"bell": toml})

    def _init(self, source: Dict[str, Any]) -> None:
        self._source = source
        self.properties: Dict[str, Any] = json.loads(_clapper.describe_bell(json.dumps(source)))

    @classmethod
    def _of(cls, source: Dict[str, Any]) -> "Bell":
        bell = cls.__new__(cls)
        bell._init(source)
        return bell

    @classmethod
    def from_file(cls, path: PathLike) -> "Bell":
        """The bell of a bell file (TOML)."""
        with open(path, encoding="utf-8") as f:
            return cls(f.read())

    @classmethod
    def chart_point(cls, r_over_lc: float, lb_over_lc: float) -> "Bell":
        """The bell the paper builds at a point of the clapping chart."""
        return cls._of({"chart_point": [float(r_over_lc), float(lb_over_lc)]})

    name = property(lambda self: self.properties["name"], doc="The bell's name.")
    r_over_lc = property(lambda self: self.properties["r_over_lc"], doc="r / L_c: across the chart.")
    lb_over_lc = property(lambda self: self.properties["lb_over_lc"], doc="L_b / L_c: up the chart.")
    lb_m = property(lambda self: self.properties["lb_m"], doc="L_b (m): the bell's equivalent pendulum length.")
    lc_m = property(lambda self: self.properties["lc_m"], doc="L_c (m): the clapper's equivalent pendulum length.")
    tb_s = property(lambda self: self.properties["tb_s"], doc="T_b (s): the bell's small-swing period.")
    tc_s = property(lambda self: self.properties["tc_s"], doc="T_c (s): the clapper's small-swing period.")
    phi_max_deg = property(lambda self: self.properties["phi_max_deg"], doc="phi_max (deg): the contact angle.")

    def __repr__(self) -> str:
        p = self.properties
        return (
            f"Bell({p['name']!r}: r/L_c = {p['r_over_lc']:.3f}, L_b/L_c = {p['lb_over_lc']:.3f}, "
            f"T_b = {p['tb_s']:.3f} s, T_c = {p['tc_s']:.3f} s, phi_max = {p['phi_max_deg']:.1f} deg)"
        )


def preset(name: str) -> Bell:
    """A bell of the paper's Table 1: ``"lab"`` or ``"gsm-tenor"``."""
    if name not in PRESETS and name != "gsm_tenor":
        raise ValueError(f"unknown preset {name!r}: one of {', '.join(PRESETS)}")
    return Bell._of({"preset": name})


def _source(bell: Optional[Bell]) -> Dict[str, Any]:
    if bell is None:
        return {}
    if not isinstance(bell, Bell):
        raise TypeError(f"bell: expected a clapper.Bell, got {type(bell).__name__}")
    return dict(bell._source)


class Trace:
    """A simulated motion, sampled every 0.5 ms and at every impact: numpy
    arrays of time ``t`` (s), bell angle ``theta`` and clapper angle ``phi``
    (rad; ``theta_deg``, ``phi_deg`` in degrees), their rates ``theta_dot``,
    ``phi_dot`` (rad/s) and the contact force ``contact_force`` (N m)."""

    def __init__(self, columns: Mapping[str, bytes]) -> None:
        self.t = _f64(columns["t"])
        self.theta = _f64(columns["theta"])
        self.phi = _f64(columns["phi"])
        self.theta_dot = _f64(columns["theta_dot"])
        self.phi_dot = _f64(columns["phi_dot"])
        self.contact_force = _f64(columns["contact_force"])

    @property
    def theta_deg(self) -> np.ndarray:
        return np.degrees(self.theta)

    @property
    def phi_deg(self) -> np.ndarray:
        return np.degrees(self.phi)

    def __len__(self) -> int:
        return len(self.t)

    def __repr__(self) -> str:
        return f"<Trace: {len(self)} samples over {self.t[-1] if len(self) else 0:.3f} s>"


class Simulation(Report):
    """Strokes of one bell: ``print(sim)`` shows the command line's summary;
    ``sim.strokes`` the quantities of each stroke (dicts, as in
    ``clapper simulate --json``); ``sim.trace`` the motion (a
    :class:`Trace`, or None when ``trace=False``)."""

    def __init__(self, data: Dict[str, Any], text: str, warnings: List[str], trace: Optional[Trace]) -> None:
        super().__init__(data, text)
        self.warnings = warnings
        self.trace = trace

    bell = property(lambda self: self.data["bell"], doc="The bell simulated (dict).")
    strokes = property(lambda self: self.data["strokes"], doc="The strokes (list of dicts).")
    verdict = property(lambda self: self.data["verdict"], doc='"right", "wrong" or "neither".')
    sustained = property(lambda self: self.data["sustained"], doc="Whether the style asked for is sustained.")
    odd_struck_ms = property(
        lambda self: self.data["odd_struck_ms"],
        doc="Handstroke minus backstroke, bottom dead centre to strike (ms); None unless both strike.",
    )

    @property
    def first_strike_angle_deg(self) -> Optional[float]:
        """The bell's angle at the first stroke's first strike (deg)."""
        s = self.strokes[0].get("first_strike")
        return None if s is None else s["theta_deg"]


def simulate(
    bell: Optional[Bell] = None,
    *,
    style: str = "right",
    strokes: int = 2,
    protocol: str = "restart",
    trace: bool = True,
    **options: Any,
) -> Simulation:
    """Simulate strokes of ``bell`` (the lab bell when None).

    ``options`` are the command line's long options in snake case:
    ``theta0`` (deg), ``restitution``, ``restitution_later``, ``contact``
    ("impact" or "penalty"), ``stiffness``, ``phi_max`` (deg),
    ``integrator``, ``rtol``, and the rest of ``clapper simulate --help``.
    An option the library does not know raises ``ValueError`` naming it.
    """
    req = _source(bell)
    req.update(style=style, strokes=int(strokes), protocol=protocol, **options)
    data, text, warnings, columns = _clapper.simulate(json.dumps(req), bool(trace))
    return Simulation(json.loads(data), text, warnings, None if columns is None else Trace(columns))


#: The quantities a :class:`Chart` holds for each style (the native
#: module's list: "sustained", "strike_angle_deg", ...).
CHART_QUANTITIES: Tuple[str, ...] = tuple(_clapper.CHART_QUANTITIES)


class Chart:
    """A clapping chart: for each style (``chart.styles``) a dict of 2-D
    arrays, rows along ``lb_over_lc`` (ascending), columns along
    ``r_over_lc``: ``chart.right["strike_angle_deg"]``. ``sustained`` is
    1 where the style is sustained, 0 where not (NaN where a stroke failed);
    every other quantity is NaN where the style is not sustained."""

    def __init__(self, raw: Mapping[str, Any]) -> None:
        self.r_over_lc = _f64(raw["r_over_lc"])
        self.lb_over_lc = _f64(raw["lb_over_lc"])
        self.styles: Tuple[str, ...] = tuple(raw["styles"])
        self.errors: int = raw["errors"]
        shape = (len(self.lb_over_lc), len(self.r_over_lc))
        self.values: Dict[str, Dict[str, np.ndarray]] = {
            s: {q: _f64(raw[s][q]).reshape(shape) for q in CHART_QUANTITIES} for s in self.styles
        }

    def __getattr__(self, name: str) -> Dict[str, np.ndarray]:
        values = self.__dict__.get("values", {})
        if name in values:
            return values[name]
        raise AttributeError(f"the chart has no style {name!r} (it has {', '.join(values) or 'none'})")

    def to_pandas(self) -> Any:
        """The chart as a long-form pandas DataFrame (one row per point and
        style), like ``clapper chart --csv``. Needs pandas."""
        import pandas as pd

        x, y = np.meshgrid(self.r_over_lc, self.lb_over_lc)
        frames = []
        for s in self.styles:
            cols = {"r_over_lc": x.ravel(), "lb_over_lc": y.ravel(), "style": s}
            cols.update({q: v.ravel() for q, v in self.values[s].items()})
            frames.append(pd.DataFrame(cols))
        return pd.concat(frames, ignore_index=True)

    def to_xarray(self) -> Any:
        """The chart as an xarray Dataset over (style, lb_over_lc,
        r_over_lc). Needs xarray."""
        import xarray as xr

        data = {
            q: (("style", "lb_over_lc", "r_over_lc"), np.stack([self.values[s][q] for s in self.styles]))
            for q in CHART_QUANTITIES
        }
        return xr.Dataset(
            data, coords={"style": list(self.styles), "lb_over_lc": self.lb_over_lc, "r_over_lc": self.r_over_lc}
        )

    def __repr__(self) -> str:
        return (
            f"<Chart: {len(self.r_over_lc)} x {len(self.lb_over_lc)} points, styles {', '.join(self.styles)}, "
            f"r/L_c {self.r_over_lc[0]:g} to {self.r_over_lc[-1]:g}, "
            f"L_b/L_c {self.lb_over_lc[0]:g} to {self.lb_over_lc[-1]:g}>"
        )


def chart(*, grid: Union[int, Sequence[int]] = 40, style: str = "both", **options: Any) -> Chart:
    """Sweep a clapping chart, in parallel; the GIL is released meanwhile.

    ``grid`` is points along r/L_c and L_b/L_c (one number for both);
    ``options`` are ``clapper chart``'s long options in snake case:
    ``r_range``, ``lb_range`` (pairs), ``phi_max`` (deg), ``theta0`` (deg),
    ``restitution``, ``contact`` and the rest.
    """
    g = [int(grid), int(grid)] if np.isscalar(grid) else [int(v) for v in grid]  # type: ignore[arg-type]
    req = dict(grid=g, style=style, **options)
    return Chart(_clapper.chart(json.dumps(req)))


def diagnose(bells: Union[Bell, PathLike, None] = None) -> Report:
    """Diagnose a bell or a ring as ``clapper diagnose`` does: how it rings,
    how near an edge, whether it goes up right, what to change. ``bells``
    is a :class:`Bell` (a preset or one made from a bell file), or the path
    of a bell or ring file (``.toml``, or ``.csv`` one bell a row); None is
    the lab bell."""
    if bells is None:
        req: Dict[str, Any] = {"preset": "lab"}
    elif isinstance(bells, Bell):
        src = bells._source
        if "preset" in src:
            req = {"preset": src["preset"]}
        elif "bell" in src:
            req = {"toml": src["bell"]}
        else:
            raise ValueError("diagnose takes a bell from a bell file or a preset, not a chart point")
    else:
        path = os.fspath(bells)
        with open(path, encoding="utf-8") as f:
            text = f.read()
        req = {"csv": text} if path.lower().endswith(".csv") else {"toml": text}
    data, text = _clapper.diagnose(json.dumps(req))
    return Report(json.loads(data), text)


def liftoff(
    bell: Optional[Bell] = None,
    *,
    lb_over_lc: Optional[float] = None,
    phi_max_deg: float = 26.0,
    theta0: float = DEFAULT_THETA0_DEG,
) -> Report:
    """Lift-off angles. With ``lb_over_lc``: the paper's closed forms (15),
    (16) for r = 0 at contact angle ``phi_max_deg``. Otherwise the exact
    lift-off of ``bell`` (the lab bell when None) released from rest at
    ``theta0`` (deg)."""
    if lb_over_lc is not None:
        if bell is not None:
            raise ValueError("give a bell or lb_over_lc, not both")
        data, text = _clapper.liftoff_formula(float(lb_over_lc), float(phi_max_deg))
    else:
        data, text = _clapper.liftoff_bell(json.dumps(_source(bell)), float(theta0))
    return Report(json.loads(data), text)


def restitution(jumps: Sequence[Sequence[float]]) -> Report:
    """R and R2 from drops of the clapper (Section 3.2): ``jumps`` holds,
    for each drop, the clapper's velocity jumps at its impacts in order
    (any one unit). ``report["r_first"]``, ``report["r_later"]``."""
    drops = [[float(v) for v in np.ravel(np.asarray(d, dtype=float))] for d in jumps]
    data, text = _clapper.restitution(drops)
    return Report(json.loads(data), text)


def modes(
    signal: Any, rate_hz: float, *, range_db: float = DEFAULT_MODES_RANGE_DB, name: str = "signal"
) -> Report:
    """The partials of one strike of a bell, ``signal`` (a 1-D array) sampled
    at ``rate_hz``: frequency (Hz), level (dB) and Q of each within
    ``range_db`` of the strongest, in ``report["modes"]``."""
    data, text = _clapper.modes(_as_f64_bytes(signal, "signal"), float(rate_hz), float(range_db), name)
    return Report(json.loads(data), text)


def strikes(
    recording: Any,
    rate_hz: float,
    nominals_hz: Sequence[float],
    *,
    double_min_ratio: float = DEFAULT_DOUBLE_MIN_RATIO,
    name: str = "recording",
) -> Report:
    """Every strike of every bell in a recording of ringing (a 1-D array at
    ``rate_hz``), the bells named by their nominals (Hz, treble first), as
    ``clapper strikes --json``: ``report["strikes"]``, ``report["per_bell"]``,
    ``report["summary"]``."""
    data, text = _clapper.strikes(
        _as_f64_bytes(recording, "recording"),
        float(rate_hz),
        [float(f) for f in nominals_hz],
        float(double_min_ratio),
        name,
    )
    return Report(json.loads(data), text)


def read_wav(path: PathLike) -> Tuple[np.ndarray, float]:
    """A WAV file's samples (channels mixed to one) and its rate (Hz)."""
    data, rate = _clapper.read_wav(os.fspath(path))
    return _f64(data), rate
