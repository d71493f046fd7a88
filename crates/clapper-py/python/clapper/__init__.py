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
``RuntimeError``; both carry the library's one-line message. A keyword
option the function does not take is named with the near ones; a value of
the wrong type raises :class:`ArgumentTypeError` (a ``TypeError``, and a
``ValueError`` as before); a file that is not there ``FileNotFoundError``.
What the model warns of (a bell that is physically impossible, say) is
issued as a :class:`ClapperWarning` too.
"""

from __future__ import annotations

import difflib
import json
import math
import os
import warnings as _warnings
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
    "ArgumentTypeError",
    "Bell",
    "ClapperWarning",
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
    "tower",
    "PRESETS",
]

PathLike = Union[str, "os.PathLike[str]"]


class ClapperWarning(UserWarning):
    """What the model warns of, such as a bell that is physically
    impossible but simulated anyway, or a report of strikes (a silent
    recording, no strikes heard). The same words are in
    ``Simulation.warnings`` and a strikes report's
    ``["summary"]["warnings"]``."""


class ArgumentTypeError(TypeError, ValueError):
    """An argument of the wrong type, such as text where a number of
    degrees belongs. A ``TypeError``, and a ``ValueError`` too: such
    arguments raised ``ValueError`` before."""


# What each numeric option of a request takes, for messages: its unit
# (None: a plain number) and what it is. The test suite checks that every
# number the library's requests take is here.
_OPTION_WORDS: Dict[str, Tuple[Optional[str], str]] = {
    "theta0": ("degrees", "the bell's starting angle at rest, 0 to 180"),
    "phi_max": ("degrees", "the clapper's contact angle, 0 to 90"),
    "restitution": (None, "the coefficient of restitution R of a strike, 0 < R <= 1"),
    "restitution_later": (None, "the restitution R2 of the bounces after a strike, 0 < R2 <= 1"),
    "stiffness": ("N m/rad", "the penalty contact's stiffness"),
    "rtol": (None, "the integrator's tolerance, 1e-14 to 1e-2"),
    "pivot_offset": ("m", "the clapper pivot's sideways offset"),
    "phi_max_hand": ("degrees", "the contact angle of the side struck at handstroke"),
    "phi_max_back": ("degrees", "the contact angle of the side struck at backstroke"),
    "gap_hand": ("mm", "the ball-to-rim gap on the hand side, bell down"),
    "gap_back": ("mm", "the ball-to-rim gap on the back side, bell down"),
    "ball_below_pivot": ("m", "the ball's centre below the clapper pivot"),
    "bell_damping": ("N m s/rad", "viscous damping at the bell's bearings"),
    "bell_friction": ("N m", "friction torque at the bell's bearings"),
    "clapper_damping": ("N m s/rad", "viscous damping at the clapper's pivot"),
    "clapper_friction": ("N m", "friction torque at the clapper's pivot"),
    "bell_swings_to_halve": (None, "swings for the bell's small swing to halve, clapper tied"),
    "clapper_swings_to_halve": (None, "swings for the clapper's small swing to halve, bell still"),
    "swing_amplitude": ("degrees", "the timed swing's starting amplitude"),
    "strokes": ("strokes", "1 to 10000"),
    "chart_point": (None, "[r/L_c, L_b/L_c], a point of the clapping chart"),
    "r_range": (None, "the range of r/L_c swept, low and high"),
    "lb_range": (None, "the range of L_b/L_c swept, low and high"),
    "grid": ("points", "along r/L_c and along L_b/L_c"),
}

_KEYS_CACHE: Dict[str, Dict[str, Tuple[str, List[str], int]]] = {}


def _keys(request: str) -> Dict[str, Tuple[str, List[str], int]]:
    """The keys a request takes (as the library reads them), each with its
    kind of value, choices and array length."""
    if request not in _KEYS_CACHE:
        _KEYS_CACHE[request] = {k: (kind, list(ch), n) for k, kind, ch, n in _clapper.request_keys(request)}
    return _KEYS_CACHE[request]


def _near(word: str, names: Iterable[str]) -> str:
    """'; did you mean ...?' for the names close to ``word``, or ''."""
    close = difflib.get_close_matches(word, _spellings(list(names)), n=3, cutoff=0.6)
    if not close:
        return ""
    return "; did you mean " + " or ".join(repr(c) for c in close) + "?"


def _what(key: str, kind: str) -> str:
    """What ``key`` takes, in words: 'a finite number of degrees (the bell's ...)'."""
    unit, meaning = _OPTION_WORDS.get(key.replace("-", "_"), (None, ""))
    if kind in ("count", "integer"):
        words = "a whole number" + (f" of {unit}" if unit else " >= 0" if kind == "count" else "")
    elif kind == "number":
        words = "a finite number" + (f" of {unit}" if unit == "degrees" else f" in {unit}" if unit else "")
    elif kind.startswith("array of "):
        inner = kind[len("array of "):]
        words = "a pair of " + ("whole numbers" if inner in ("count", "integer") else "finite numbers")
        words += f" of {unit}" if unit else ""
    elif kind == "text":
        words = "text"
    elif kind == "bool":
        words = "True or False"
    else:
        words = "a value"
    return f"{words} ({meaning})" if meaning else words


def _shown(value: Any) -> str:
    text = repr(value)
    return (text[:60] + "...") if len(text) > 63 else text


def _float(v: Any) -> float:
    """``float(v)``, an int too large for a float being infinite."""
    try:
        return float(v)
    except OverflowError:
        return math.inf if v > 0 else -math.inf


def _is_number(v: Any) -> bool:
    return isinstance(v, (int, float, np.integer, np.floating)) and not isinstance(v, (bool, np.bool_))


def _value(fn: str, key: str, value: Any, kind: str, choices: List[str], length: int) -> Any:
    """``value`` checked against what ``key`` takes and made JSON-ready;
    a value of the wrong type raises ArgumentTypeError, one of the right
    type that cannot be (NaN, an unknown choice) ValueError, both naming
    ``key`` and saying what it takes."""
    def wrong(exc: type = ArgumentTypeError, shown: Any = value) -> Exception:
        return exc(f"{fn}: {key} must be {_what(key, kind)}, not {_shown(shown)}")

    if kind == "number":
        if not _is_number(value):
            raise wrong()
        x = _float(value)
        if not math.isfinite(x):
            raise wrong(ValueError)
        return x
    if kind in ("count", "integer"):
        if not _is_number(value):
            raise wrong()
        x = _float(value)
        # Beyond 2^63 JSON's reader takes a whole number for a float.
        if not (math.isfinite(x) and x.is_integer() and abs(x) < 2.0**63) or (kind == "count" and x < 0):
            raise wrong(ValueError)
        return int(value)
    if kind == "choice":
        if not isinstance(value, str):
            raise ArgumentTypeError(f"{fn}: {key} must be one of {_choices(choices)}, not {_shown(value)}")
        if value not in choices:
            raise ValueError(f"{fn}: {key} must be one of {_choices(choices)}, not {value!r}{_near(value, choices)}")
        return value
    if kind == "text":
        if not isinstance(value, str):
            raise wrong()
        return value
    if kind == "bool":
        if not isinstance(value, (bool, np.bool_)):
            raise wrong()
        return bool(value)
    if kind.startswith("array of "):
        inner = kind[len("array of "):]
        if isinstance(value, (str, bytes, Mapping)) or not isinstance(value, (Sequence, np.ndarray)):
            raise wrong()
        items = list(value)
        if len(items) != length:
            raise wrong(ValueError)
        try:
            return [_value(fn, key, v, inner, choices, 0) for v in items]
        except ValueError as e:
            # Say what the whole pair should be, not one element.
            raise wrong(type(e)) from None
    return value


def _spellings(names: List[str]) -> List[str]:
    """One spelling of each name: the kebab one where serde also takes a
    snake alias ("gsm-tenor"), in order."""
    seen = set(names)
    out = [n for n in names if not ("_" in n and n.replace("_", "-") in seen)]
    return list(dict.fromkeys(out))


def _choices(choices: List[str]) -> str:
    return ", ".join(repr(c) for c in _spellings(choices))


def _checked(fn: str, request: str, options: Mapping[str, Any], own: Iterable[str] = ()) -> Dict[str, Any]:
    """Keyword ``options`` of ``fn`` checked against the keys ``request``
    takes, made JSON-ready. ``own`` are ``fn``'s own keyword parameters,
    suggested too."""
    keys = _keys(request)
    out: Dict[str, Any] = {}
    for key, value in options.items():
        if key not in keys:
            # Suggest the snake-case spellings only (Python's keywords).
            names = [k for k in keys if "-" not in k] + list(own)
            hint = _near(key, names) or f"; see help(clapper.{fn}) for its options"
            raise ValueError(f"{fn}: unknown option {key!r}{hint}")
        kind, choices, length = keys[key]
        out[key] = _value(fn, key, value, kind, choices, length)
    return out


def _f64(data: bytes) -> np.ndarray:
    """Little-endian float64 bytes from the native module as a writable array."""
    return np.frombuffer(data, dtype="<f8").astype(np.float64)


def _as_f64_bytes(values: Any, what: str) -> bytes:
    try:
        arr = np.ascontiguousarray(values, dtype="<f8")
    except (TypeError, ValueError):
        raise ArgumentTypeError(
            f"{what}: expected a one-dimensional array of numbers, not {_shown(values)}"
        ) from None
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


def _bell_fields(fields: Mapping[str, Any]) -> Dict[str, Any]:
    """A bell's keyword fields checked against the keys a bell file takes."""
    keys = _keys("bell")
    out: Dict[str, Any] = {}
    for key, value in fields.items():
        if key not in keys:
            hint = _near(key, keys) or "; see help(clapper.Bell) and docs for a bell file's keys"
            raise ValueError(f"Bell: unknown field {key!r}{hint}")
        kind, choices, length = keys[key]
        # A table ([clapper]) goes through as given; the library checks it.
        out[key] = value if kind == "other" else _value("Bell", key, value, kind, choices, length)
    return out


def _read_text(path: PathLike, fn: str, takes: str) -> str:
    """The text of a bell or ring file. A missing file raises
    FileNotFoundError (from open); a recording, or any file that is not
    text, ValueError saying what ``fn`` takes."""
    path = os.fspath(path)
    with open(path, "rb") as f:
        raw = f.read()
    if raw[:4] == b"RIFF" or str(path).lower().endswith(".wav"):
        raise ValueError(
            f"{fn}: {path} is a recording (WAV), and {fn} reads {takes}. "
            "For a recording's strikes: samples, rate = clapper.read_wav(path), then "
            "clapper.strikes(samples, rate, nominals_hz); for one strike's partials, clapper.modes(samples, rate)"
        )
    try:
        return raw.decode("utf-8")
    except UnicodeDecodeError as e:
        raise ValueError(
            f"{fn}: {path} is not a text file (byte {e.start} is not UTF-8); {fn} reads {takes}"
        ) from None


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
            toml = _bell_toml(_bell_fields(fields))
        elif not isinstance(toml, str):
            raise ArgumentTypeError(
                f"Bell: expected a bell file's text (TOML), not {_shown(toml)}; "
                "for a bell file on disk use clapper.Bell.from_file(path)"
            )
        elif "\n" not in toml and "=" not in toml and toml.strip().lower().endswith(".toml"):
            raise ValueError(
                f"Bell: {toml!r} looks like a file's path, not its text: use clapper.Bell.from_file({toml!r})"
            )
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
        """The bell of a bell file (TOML). A file that is not there raises
        ``FileNotFoundError``."""
        return cls(_read_text(path, "Bell.from_file", "a bell file (TOML)"))

    @classmethod
    def chart_point(cls, r_over_lc: float, lb_over_lc: float) -> "Bell":
        """The bell the paper builds at a point of the clapping chart."""
        return cls._of(
            {
                "chart_point": [
                    _number("Bell.chart_point", "r_over_lc", r_over_lc, "r/L_c, across the clapping chart"),
                    _number("Bell.chart_point", "lb_over_lc", lb_over_lc, "L_b/L_c, up the clapping chart"),
                ]
            }
        )

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
    verdict = property(
        lambda self: self.data["verdict"],
        doc='The style asked if sustained, else "neither" (not the style asked: sustains_instead says what is).',
    )
    sustained = property(lambda self: self.data["sustained"], doc="Whether the style asked for is sustained.")
    sustains_instead = property(
        lambda self: self.data.get("sustains_instead"),
        doc='Where the style asked is not sustained: "right", "wrong" or "neither", what the bell sustains; else None.',
    )
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
    An option the library does not know raises ``ValueError`` naming it
    and the near ones; a value of the wrong type ``ArgumentTypeError``.
    What the model warns of is in ``.warnings`` and issued as
    :class:`ClapperWarning`.
    """
    req = _source(bell)
    given = [k for k in ("preset", "bell", "chart_point", "chart-point") if k in options]
    if bell is not None and given:
        raise ValueError(f"simulate: give the bell once: as the bell argument or as {given[0]}=, not both")
    req.update(
        _checked(
            "simulate",
            "simulate",
            dict(style=style, strokes=strokes, protocol=protocol, **options),
            own=("bell", "trace"),
        )
    )
    data, text, warnings, columns = _clapper.simulate(json.dumps(req), bool(trace))
    for w in warnings:
        _warnings.warn(w, ClapperWarning, stacklevel=2)
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


def chart(
    *, grid: Union[int, Sequence[int]] = 40, style: str = "both", threads: Optional[int] = None, **options: Any
) -> Chart:
    """Sweep a clapping chart, in parallel; the GIL is released meanwhile.

    ``grid`` is points along r/L_c and L_b/L_c (one number for both);
    ``threads`` the worker threads (1 to 1024; default one per core: the
    result is the same whatever the count); ``options`` are ``clapper
    chart``'s long options in snake case: ``r_range``, ``lb_range``
    (pairs), ``phi_max`` (deg), ``theta0`` (deg), ``restitution``,
    ``contact`` and the rest.
    """
    # One number for both: checked as the one number given.
    g = [_value("chart", "grid", grid, "count", [], 0)] * 2 if _is_number(grid) else grid
    req = _checked("chart", "chart", dict(grid=g, style=style, **options), own=["threads"])
    n = None
    if threads is not None:
        n = _value("chart", "threads", threads, "count", [], 0)
        if not 1 <= n <= 1024:
            raise ValueError(f"chart: threads must be 1 to 1024, not {n}")
    return Chart(_clapper.chart(json.dumps(req), n))


def diagnose(bells: Union[Bell, PathLike, None] = None) -> Report:
    """Diagnose a bell or a ring as ``clapper diagnose`` does: how it rings,
    how near an edge, whether it goes up right, what to change. ``bells``
    is a :class:`Bell` (a preset or one made from a bell file), or the path
    of a bell or ring file (``.toml``, or ``.csv`` one bell a row); None is
    the lab bell. A file that is not there raises ``FileNotFoundError``; a
    recording (WAV) ``ValueError`` (its strikes: :func:`read_wav`, then
    :func:`strikes`)."""
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
    elif isinstance(bells, (str, os.PathLike)):
        path = os.fspath(bells)
        text = _read_text(path, "diagnose", "a bell or ring file (TOML, or CSV one bell a row)")
        req = {"csv": text} if str(path).lower().endswith(".csv") else {"toml": text}
    else:
        raise ArgumentTypeError(
            f"diagnose: bells must be a clapper.Bell or the path of a bell or ring file, not {_shown(bells)}"
        )
    data, text = _clapper.diagnose(json.dumps(req))
    return Report(json.loads(data), text)


def tower(
    ring: PathLike,
    method: Optional[str] = None,
    *,
    tower: Optional[PathLike] = None,
    rows: Optional[Sequence[str]] = None,
    **options: Any,
) -> Report:
    """Ring a touch on a ring in its tower, as ``clapper tower`` does
    (docs/tower.md): ``ring`` is the path of a ring file (TOML, with each
    bell's ``swing``, ``frame_x_m``, ``frame_y_m``, ``pivot_height_m`` and a
    ``[tower]`` table, or CSV); ``method`` a title ("Plain Bob Major") or
    "rounds"; ``tower`` a tower file's path; ``rows`` rows as text
    ("12345678"). Other options are ``clapper tower``'s in snake case:
    ``leads``, ``changes``, ``place_notation``, ``stage``, ``peal_hours``,
    ``interval_ms``, ``handstroke_gap``, ``striking_sd_ms``, ``seed``,
    ``dt_s``, ``theta0_deg``, ``restitution``, ``turn`` (bells from 1).
    Returns a :class:`Report` (the JSON of ``--json``, the text) whose
    ``history`` is a dict of numpy arrays: ``time_s``, ``force_east_n``,
    ``force_north_n``, ``vertical_n``, the moments and, with a tower,
    ``sway_east_m``, ``sway_north_m`` and the accelerations."""
    if not isinstance(ring, (str, os.PathLike)):
        raise ArgumentTypeError(f"tower: ring must be the path of a ring file, not {_shown(ring)}")
    path = os.fspath(ring)
    text = _read_text(path, "tower", "a ring file (TOML, or CSV one bell a row)")
    req: Dict[str, Any] = {"csv": text} if str(path).lower().endswith(".csv") else {"toml": text}
    if tower is not None:
        req["tower"] = _read_text(os.fspath(tower), "tower", "a tower file (TOML)")
    request: Dict[str, Any] = dict(options)
    if method is not None:
        request["method"] = method
    if rows is not None:
        request["rows"] = [str(r) for r in rows]
    req["request"] = request
    data, text, columns = _clapper.tower(json.dumps(req))
    rep = Report(json.loads(data), text)
    rep.history = {k: _f64(v) for k, v in columns.items()}  # type: ignore[attr-defined]
    return rep


def _number(fn: str, name: str, value: Any, what: str) -> float:
    """A finite float for ``fn``'s argument ``name``; ``what`` says what it is."""
    if not _is_number(value):
        raise ArgumentTypeError(f"{fn}: {name} must be a finite number ({what}), not {_shown(value)}")
    x = _float(value)
    if not math.isfinite(x):
        raise ValueError(f"{fn}: {name} must be a finite number ({what}), not {x}")
    return x


def _flag(fn: str, name: str, value: Any) -> bool:
    """A yes or no for ``fn``'s argument ``name``: ``True`` or ``False`` only
    (a string such as ``"false"`` would read as yes)."""
    if not isinstance(value, (bool, np.bool_)):
        raise ArgumentTypeError(f"{fn}: {name} must be True or False, not {_shown(value)}")
    return bool(value)


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
        data, text = _clapper.liftoff_formula(
            _number("liftoff", "lb_over_lc", lb_over_lc, "L_b/L_c, up the clapping chart"),
            _number("liftoff", "phi_max_deg", phi_max_deg, "degrees: the contact angle"),
        )
    else:
        data, text = _clapper.liftoff_bell(
            json.dumps(_source(bell)),
            _number("liftoff", "theta0", theta0, "degrees: the angle the bell is released from"),
        )
    return Report(json.loads(data), text)


_DROPS = (
    "restitution takes a list of drops, each a list of the clapper's velocity jumps "
    "at its impacts in order (at least two a drop: the strike and a bounce)"
)


def _drops(jumps: Any) -> List[List[float]]:
    """The drops of :func:`restitution`, checked, as lists of floats."""
    if isinstance(jumps, (str, bytes, Mapping)) or not isinstance(jumps, (Sequence, np.ndarray)):
        raise ArgumentTypeError(f"{_DROPS}; got {_shown(jumps)}")
    drops = list(jumps)
    if not drops:
        raise ValueError(f"{_DROPS}; got no drops")
    if all(_is_number(d) for d in drops):
        n = len(drops)
        raise ValueError(
            f"{_DROPS}; got one flat list of {n} number{'s' if n != 1 else ''}: "
            f"for one drop, give [{_shown(list(map(float, drops)))}]"
        )
    out = []
    for k, d in enumerate(drops, 1):
        if isinstance(d, (str, bytes, Mapping)) or not isinstance(d, (Sequence, np.ndarray)):
            raise ArgumentTypeError(f"{_DROPS}; drop {k} is {_shown(d)}, not a list of jumps")
        values = list(np.ravel(np.asarray(d, dtype=object)))
        for j, v in enumerate(values, 1):
            if not _is_number(v):
                raise ArgumentTypeError(f"restitution: drop {k}, jump {j} is {_shown(v)}: jumps are numbers")
            if not (math.isfinite(float(v)) and float(v) > 0):
                raise ValueError(
                    f"restitution: drop {k}, jump {j} is {float(v)}: each jump is the size of a change "
                    "of the clapper's velocity, finite and > 0"
                )
        if len(values) < 2:
            raise ValueError(
                f"{_DROPS}; drop {k} of {len(drops)} has {len(values)} jump{'s' if len(values) != 1 else ''}"
            )
        out.append([float(v) for v in values])
    return out


def restitution(jumps: Sequence[Sequence[float]]) -> Report:
    """R and R2 from drops of the clapper (Section 3.2): ``jumps`` holds,
    for each drop, the clapper's velocity jumps at its impacts in order
    (any one unit), at least two a drop: ``[[1.0, 0.35, 0.2]]`` is one
    drop. ``report["r_first"]``, ``report["r_later"]``."""
    data, text = _clapper.restitution(_drops(jumps))
    return Report(json.loads(data), text)


def modes(
    signal: Any, rate_hz: float, *, range_db: float = DEFAULT_MODES_RANGE_DB, name: str = "signal"
) -> Report:
    """The partials of one strike of a bell, ``signal`` (a 1-D array) sampled
    at ``rate_hz``: frequency (Hz), level (dB) and Q of each within
    ``range_db`` of the strongest, in ``report["modes"]``."""
    data, text = _clapper.modes(
        _as_f64_bytes(signal, "modes: signal"),
        _number("modes", "rate_hz", rate_hz, "the sample rate in Hz"),
        _number("modes", "range_db", range_db, "dB below the strongest partial"),
        name,
    )
    return Report(json.loads(data), text)


def _nominals(nominals_hz: Any) -> List[float]:
    """The bells' nominals of :func:`strikes`, checked."""
    what = "the bells' nominal frequencies in Hz, treble first"
    if isinstance(nominals_hz, (str, bytes, Mapping)) or not isinstance(nominals_hz, (Sequence, np.ndarray)):
        raise ArgumentTypeError(f"strikes: nominals_hz must be a list of numbers ({what}), not {_shown(nominals_hz)}")
    return [_number("strikes", f"nominals_hz[{k}]", f, what) for k, f in enumerate(nominals_hz)]


def strikes(
    recording: Any,
    rate_hz: float,
    nominals_hz: Optional[Sequence[float]] = None,
    *,
    bells: Optional[int] = None,
    double_min_ratio: float = DEFAULT_DOUBLE_MIN_RATIO,
    name: str = "recording",
    handbells: bool = False,
    timing: str = "auto",
) -> Report:
    """Every strike of every bell in a recording of ringing (a 1-D array at
    ``rate_hz``), the bells named by their nominals (Hz, treble first), or
    without them ``bells=N`` (3 to 16) whose nominals are learned from the
    recording (``report["learned_nominals_hz"]``, as ``--bells N``),
    ``handbells=True`` for handbells (each known by its strike note and
    twelfth, as ``--handbells``), each strike timed as ``timing`` says
    (``"auto"``, ``"plain"`` or ``"recording"``, as ``--timing``: auto tries
    both on the first 80 s and keeps the one whose strikes come more evenly;
    ``report["timing"]["choice"]`` says which and why), as ``clapper strikes --json``: ``report["strikes"]``, ``report["per_bell"]``,
    ``report["summary"]``. What the command line warns of (a silent
    recording, no strikes heard, one bell, a sound unlike bells) is in
    ``report["summary"]["warnings"]`` and issued as :class:`ClapperWarning`."""
    if (nominals_hz is None) == (bells is None):
        raise ValueError("strikes: give the bells' nominals_hz or bells= (how many ring, their nominals learned), "
                         "one of the two")
    if bells is not None and (isinstance(bells, bool) or not isinstance(bells, (int, np.integer))):
        raise ArgumentTypeError(f"strikes: bells must be a whole number (3 to 16), not {_shown(bells)}")
    if not isinstance(timing, str):
        raise ArgumentTypeError(f"strikes: timing must be 'auto', 'plain' or 'recording', not {_shown(timing)}")
    data, text = _clapper.strikes(
        _as_f64_bytes(recording, "strikes: recording"),
        _number("strikes", "rate_hz", rate_hz, "the sample rate in Hz"),
        None if nominals_hz is None else _nominals(nominals_hz),
        None if bells is None else max(0, int(bells)),
        _number("strikes", "double_min_ratio", double_min_ratio, "the least amplitude ratio of a double strike"),
        name,
        _flag("strikes", "handbells", handbells),
        timing,
    )
    report = Report(json.loads(data), text)
    for w in report["summary"]["warnings"]:
        _warnings.warn(w, ClapperWarning, stacklevel=2)
    return report


def read_wav(path: PathLike, channel: Union[int, str] = "auto") -> Tuple[np.ndarray, float]:
    """A WAV file's samples and its rate (Hz), its channels heard as
    ``channel`` asks, as ``clapper strikes --channel`` and the web's
    ``channel=`` do: a channel's number counted from 1 (1 the first, the
    left; 0 raises ``ValueError``), ``"mix"`` (mixed to one), or ``"auto"``
    (the default: mixed to one, unless they disagree in time, one heard 5
    ms or more after another, when their mix would blur every strike: one
    is then read alone, the first unless another's strikes stand clearly
    clearer over its noise, and this is warned of as
    :class:`ClapperWarning`, as ``clapper strikes`` warns of it in its
    report). A file that is not there raises ``FileNotFoundError``."""
    path = os.fspath(path)
    if isinstance(channel, bool) or not isinstance(channel, (int, str)):
        raise TypeError(f"channel: a channel's number (from 1), 'mix' or 'auto', not {channel!r}")
    # Opened here first so that a missing or unreadable file raises what
    # open() raises (FileNotFoundError, PermissionError), as elsewhere.
    with open(path, "rb"):
        pass
    data, rate, told = _clapper.read_wav(path, str(channel))
    for w in told:
        _warnings.warn(w, ClapperWarning, stacklevel=2)
    return _f64(data), rate
