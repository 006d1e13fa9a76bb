"""geardyn: nonlinear gear dynamics from Python.

The published models of the geardyn Rust crates — Liu et al. 2021 (noncircular face gear
rattle), Karpov et al. 2017 (oscillator at the variable mesh frequency of non-circular gears)
and Yu et al. 2021 (6-DOF spur pair with fractal and dynamic backlash) — with their paper
parameter sets ("presets") and readings, solved by harmonic balance or time stepping, and the
user studies of ``geardyn study`` / ``cargo xtask study`` from TOML. Results come back as
numpy arrays; errors as the typed exceptions of :mod:`geardyn.errors`.

>>> import geardyn
>>> liu = geardyn.Liu2021().with_params(omega1=120.0)
>>> r = liu.solve("hbm", full_r=2)
>>> int(r["rsv"]), bool(r["converged"])
(0, True)

Parameters keep the Rust field names and SI units (``liu.params`` lists them).
"""

import json
import os

import numpy as np

from . import _geardyn
from .errors import GeardynError, ParameterError, SolverError, StudyError, _raise

__version__ = _geardyn.__version__

__all__ = [
    "GeardynError",
    "ParameterError",
    "SolverError",
    "StudyError",
    "Model",
    "Liu2021",
    "Karpov2017",
    "Yu2021",
    "StudyResult",
    "presets",
    "run_study",
    "run_study_file",
    "write_study",
]


def _unwrap(text):
    reply = json.loads(text)
    if "error" in reply:
        _raise(reply["error"])
    return reply["ok"]


def _arrays(value):
    """Lists of numbers (``null`` = NaN) become float arrays, recursively."""
    if isinstance(value, dict):
        return {k: _arrays(v) for k, v in value.items()}
    if isinstance(value, list):
        if value and all(v is None or isinstance(v, (int, float)) and not isinstance(v, bool)
                         for v in value):
            return np.array([np.nan if v is None else v for v in value], dtype=float)
        if value and all(isinstance(v, list) for v in value):
            try:
                return np.array([[np.nan if x is None else x for x in row] for row in value],
                                dtype=float)
            except (TypeError, ValueError):
                return [_arrays(v) for v in value]
        return [_arrays(v) for v in value]
    return value


def presets():
    """Every ``(model, preset)`` pair, e.g. ``("liu2021", "table1")``."""
    return [tuple(p) for p in _geardyn.PRESETS]


def _preset(model, name):
    return _unwrap(_geardyn.preset(model, name))


def _merge(base, over):
    out = dict(base)
    for k, v in over.items():
        if isinstance(v, dict) and isinstance(out.get(k), dict):
            out[k] = _merge(out[k], v)
        else:
            out[k] = v
    return out


class Model:
    """A published model with one parameter set; immutable (``with_*`` return new models).

    Subclasses name the model (``key``), its presets and its methods.
    """

    key = ""
    default_preset = ""
    methods = ()

    def __init__(self, preset=None, **params):
        self._params = _preset(self.key, preset or self.default_preset)
        if params:
            self._params = self._checked(_merge(self._params, params))

    def _checked(self, params):
        # validate names early (the Rust side names unknown keys and checks ranges on solve)
        for k in params:
            if k not in self._base_keys():
                raise ParameterError(
                    f"unknown parameter `{k}` of {self.key}; known: {sorted(self._base_keys())}")
        return params

    def _base_keys(self):
        return set(_preset(self.key, self.default_preset))

    @property
    def params(self):
        """The parameter set (Rust field names, SI units) as a dict."""
        return json.loads(json.dumps(self._params))

    def with_params(self, **params):
        """A copy with some parameters replaced (nested dicts are merged)."""
        new = object.__new__(type(self))
        new._params = self._checked(_merge(self._params, params))
        return new

    def _settings(self, settings):
        return json.dumps(settings, allow_nan=False)

    def solve(self, method=None, **settings):
        """Solve one point; returns a dict whose number lists are numpy arrays."""
        method = method or self.methods[0]
        text = _geardyn.solve(self.key, json.dumps(self._params), method,
                              self._settings(settings))
        return _arrays(_unwrap(text))

    def sweep(self, parameter, values, method=None, **settings):
        """Solve every value of ``parameter`` (in parallel, results in input order).

        Returns a list with one result dict per value; a point that failed holds the
        exception instance instead (a sweep is not aborted by one bad point).
        """
        method = method or self.methods[0]
        values = [float(v) for v in np.asarray(values, dtype=float).ravel()]
        text = _geardyn.sweep(self.key, json.dumps(self._params), parameter, values, method,
                              self._settings(settings))
        out = []
        for point in _unwrap(text):
            if "error" in point:
                try:
                    _raise(point["error"])
                except GeardynError as e:
                    out.append(e)
            else:
                out.append(_arrays(point["ok"]))
        return out

    def __repr__(self):
        return f"{type(self).__name__}({self._params!r})"


class Liu2021(Model):
    """Liu, Lv, Zhao 2021: rattle of a noncircular face gear (Mech. Sci. 12:361).

    Presets: ``"table1"``. Readings: ``readings="printed"`` or ``"consistent"`` (default), or
    a dict of single readings (``{"rigid_acceleration": "printed_eq20"}``). Methods:
    ``"hbm"`` (settings ``full_r`` = 0 for the paper's basis, ``warm_start``, ``tol``,
    ``max_iter``, ``samples``) and ``"time-stepping"`` (``options`` = a dict of
    ``IntegrationOptions``). Results: ``rsv``, ``ppv``, ``converged``, ``tau``, ``q``
    (and ``v`` for time stepping).
    """

    key = "liu2021"
    default_preset = "table1"
    methods = ("hbm", "time-stepping")

    def __init__(self, preset=None, readings=None, **params):
        super().__init__(preset, **params)
        if readings is not None:
            self._params = self.with_readings(readings)._params

    def with_readings(self, readings):
        """A copy with the readings replaced: ``"printed"``, ``"consistent"`` or a dict."""
        if isinstance(readings, str):
            readings = _preset("liu2021-readings", readings)
        return self.with_params(readings=readings)

    def rattle_sweep(self, omega1, method="time-stepping", **settings):
        """rsv and ppv against the pinion speed ``omega1`` [rad/s] as numpy arrays
        (``rsv`` is NaN where a point failed or did not converge)."""
        omega1 = np.asarray(omega1, dtype=float)
        res = self.sweep("omega1", omega1, method, **settings)
        rsv = np.array([r["rsv"] if isinstance(r, dict) and r["converged"] else np.nan
                        for r in res], dtype=float)
        ppv = np.array([r["ppv"] if isinstance(r, dict) and r["converged"] else np.nan
                        for r in res], dtype=float)
        return {"omega1": omega1, "rsv": rsv, "ppv": ppv}


class Karpov2017(Model):
    """Karpov et al. 2017: oscillator driven at the variable mesh frequency (MMT 114:1).

    Presets: ``"fig3"``. Method: ``"duhamel"`` (the model's exact time integral of Eq. 9;
    ``"time-stepping"`` is an alias). Readings through the ``excitation`` and ``measure``
    parameters. Result: ``x``, ``v``, ``envelope``, ``amplitude``, …
    """

    key = "karpov2017"
    default_preset = "fig3"
    methods = ("duhamel", "time-stepping")


class Yu2021(Model):
    """Yu, Sun, Li, Wu 2021: 6-DOF spur pair with fractal and dynamic backlash.

    Presets: ``"table1"``, ``"table2"``. Methods: ``"time-stepping"`` (the timestep engine),
    ``"rk4"`` (the model's fixed-step RK4) and ``"hbm"`` (torsional models); settings
    ``omega`` (ω*, required), ``options`` (a dict of model options or ``"chen"``),
    ``transient_periods``, ``record_periods``, ``hbm`` (a dict of HBM settings).
    """

    key = "yu2021"
    default_preset = "table1"
    methods = ("time-stepping", "rk4", "hbm")

    def _settings(self, settings):
        opts = settings.get("options")
        if isinstance(opts, str):
            settings = dict(settings, options=_preset("yu2021-options", opts))
        return super()._settings(settings)


class StudyResult:
    """The table of a study: ``columns`` (names), ``units``, ``data`` (2-D float array, text
    cells as NaN), ``rows`` (as read), ``summary`` (dict)."""

    def __init__(self, reply):
        self.name = reply["name"]
        self.columns = [c["name"] for c in reply["columns"]]
        self.units = [c["unit"] for c in reply["columns"]]
        self.rows = reply["rows"]
        self.summary = reply["summary"]
        self.data = np.array(
            [[x if isinstance(x, (int, float)) and not isinstance(x, bool) else np.nan
              for x in row] for row in self.rows],
            dtype=float,
        ).reshape(len(self.rows), len(self.columns))

    def column(self, name):
        """One column as a float array (by name)."""
        try:
            return self.data[:, self.columns.index(name)]
        except ValueError:
            raise KeyError(f"no column `{name}`; columns: {self.columns}") from None

    def __repr__(self):
        return f"StudyResult({self.name!r}, {len(self.rows)} rows, columns={self.columns})"


def run_study(text):
    """Run a study given as TOML text (format: ``docs/studies.md``)."""
    return StudyResult(_unwrap(_geardyn.run_study(text)))


def run_study_file(path):
    """Run a study file."""
    with open(os.fspath(path), encoding="utf-8") as f:
        return run_study(f.read())


def write_study(text, out_dir):
    """Run a study given as TOML text in this process and write its files to ``out_dir``
    (CSV, SVG, JSON summary), as ``geardyn study`` does. Returns the JSON summary as a dict.
    For a study spread over many processes or machines, see :mod:`geardyn.dask`."""
    return _unwrap(_geardyn.write_study(text, os.fspath(out_dir)))
