"""geardyn: nonlinear gear dynamics from Python.

The published models of the geardyn Rust crates — Liu et al. 2021 (noncircular face gear
rattle), Karpov et al. 2017 (oscillator at the variable mesh frequency of non-circular gears)
and Yu et al. 2021 (6-DOF spur pair with fractal and dynamic backlash) — with their paper
parameter sets ("presets") and readings, solved by harmonic balance or time stepping, and the
user studies of ``geardyn study`` / ``cargo xtask study`` from TOML. Results come back as
numpy arrays (or, on request, pandas DataFrames and xarray Datasets: ``StudyResult.to_pandas()``,
``.to_xarray()``, ``sweep(..., as_="xarray")``); errors as the typed exceptions of
:mod:`geardyn.errors`. A point that is not settled, converged or stable is returned marked (its
``settled`` / ``converged`` / ``stable`` field) and reported by a
:class:`~geardyn.errors.ReliabilityWarning`.

>>> import geardyn
>>> liu = geardyn.Liu2021().with_params(omega1=120.0)
>>> r = liu.solve("hbm", full_r=2)
>>> int(r["rsv"]), bool(r["converged"])
(0, True)

Parameters keep the Rust field names and SI units (``liu.params`` lists them); choices and
readings are spelled as in a study file (``"printed-eq20"``, ``"two-terms"``,
``"time-varying"``), and any spelling of a name is accepted on input.
"""

import json
import math
import os
import sys
import warnings

import numpy as np

from . import _geardyn
from . import _tables
from .errors import (GeardynError, ParameterError, ReliabilityWarning, SolverError, StudyError,
                     _raise)

__version__ = _geardyn.__version__

__all__ = [
    "GeardynError",
    "ParameterError",
    "ReliabilityWarning",
    "SolverError",
    "StudyError",
    "Model",
    "Liu2021",
    "Karpov2017",
    "Yu2021",
    "StudyResult",
    "describe",
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


def _rust_float(x):
    """A float as the Rust messages print it (``NaN``, ``inf``, ``-inf``)."""
    if math.isnan(x):
        return "NaN"
    if math.isinf(x):
        return "inf" if x > 0 else "-inf"
    return repr(x)


def _check_finite(value, what, path=""):
    """Raise :class:`ParameterError` naming the field if any number in ``value`` (nested
    dicts and lists included) is NaN or infinite: the rule of a study file's entries."""
    if isinstance(value, dict):
        for k, v in value.items():
            _check_finite(v, what, f"{path}.{k}" if path else str(k))
    elif isinstance(value, (list, tuple)):
        for v in value:
            _check_finite(v, what, path)
    elif isinstance(value, (float, np.floating)) and not math.isfinite(float(value)):
        raise ParameterError(f"{what} `{path}` must be finite, got {_rust_float(float(value))}")


def _limits_json(limits):
    """``limits`` (``None`` or a dict of ``max_points``, ``max_steps``,
    ``max_seconds_per_point``) as JSON for the Rust side, which checks it like a study file's
    ``[limits]``."""
    if limits is None:
        return "null"
    if not isinstance(limits, dict):
        raise TypeError(f"limits must be a dict, got {type(limits).__name__}")
    for k, v in limits.items():
        if isinstance(v, (float, np.floating)) and not math.isfinite(float(v)):
            raise ParameterError(f"limits.{k} must be finite, got {_rust_float(float(v))}")
    return json.dumps(_plain(limits), allow_nan=False)


def _plain(value):
    """numpy scalars and arrays as plain Python numbers and lists (for JSON)."""
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, np.ndarray):
        return _plain(value.tolist())
    if isinstance(value, np.bool_):
        return bool(value)
    if isinstance(value, np.integer):
        return int(value)
    if isinstance(value, np.floating):
        return float(value)
    return value


def _size(values):
    """The number of points in ``values`` without converting it: an array's size from its
    shape (0-d: 1), a sequence's length, else 1 (a scalar)."""
    shape = getattr(values, "shape", None)
    if isinstance(shape, tuple):
        n = 1
        for d in shape:
            n *= int(d)  # Python ints: no overflow for any virtual shape
        return n
    if hasattr(values, "__len__") and not isinstance(values, (str, bytes)):
        return len(values)
    return 1


def _sweep_values(values, limits):
    """``values`` as a 1-D float array, its size checked against ``limits.max_points``
    *before* any conversion (a 10⁷-point sweep is refused at once)."""
    _unwrap(_geardyn.check_points(min(_size(values), sys.maxsize), _limits_json(limits)))
    arr = np.asarray(values, dtype=float)
    if arr.ndim != 1:
        raise ValueError(f"sweep values must be a 1-D sequence, got shape {arr.shape}")
    _unwrap(_geardyn.check_points(arr.size, _limits_json(limits)))
    return arr


def describe(model=None):
    """The self-description of one model (by its registry name, e.g. ``"liu2021"``) or, with no
    name, of every model: parameters with units and defaults, choices and readings, methods with
    their settings (kind, bounds, default) and output columns with units. The same data as
    ``geardyn models --json`` and the generated model reference of ``docs/studies.md``."""
    return _unwrap(_geardyn.describe(model or ""))


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

    @classmethod
    def describe(cls):
        """This model's self-description (see :func:`describe`)."""
        return describe(cls.key)

    def __init__(self, preset=None, **params):
        self._params = _preset(self.key, preset or self.default_preset)
        if params:
            self._params = self._checked(_merge(self._params, params))

    #: Parameters a model takes beyond its preset's fields (Yu's ``omega``).
    extra_params = ()

    def _checked(self, params):
        # validate names and finiteness early (the Rust side names unknown keys and checks
        # ranges on solve)
        for k in params:
            if not isinstance(k, str):
                raise TypeError(f"parameter names are strings, got {k!r}")
            if k not in self._base_keys():
                raise ParameterError(
                    f"unknown parameter `{k}` of {self.key}; known: {sorted(self._base_keys())}")
        _check_finite(params, "parameter")
        return _tables.serde_spelled(_plain(params), _preset(self.key, self.default_preset))

    def _base_keys(self):
        return set(_preset(self.key, self.default_preset)) | set(self.extra_params)

    @property
    def params(self):
        """The parameter set (Rust field names, SI units) as a dict; choices and readings in
        study-file spelling (``"printed-eq20"``, ``"two-terms"``)."""
        return _tables.spelled(json.loads(json.dumps(self._params)))

    def with_params(self, **params):
        """A copy with some parameters replaced (nested dicts are merged)."""
        new = object.__new__(type(self))
        new._params = self._checked(_merge(self._params, params))
        return new

    def _settings(self, settings):
        _check_finite(settings, "setting")
        return json.dumps(_plain(settings), allow_nan=False)

    def solve(self, method=None, *, limits=None, **settings):
        """Solve one point; returns a dict whose number lists are numpy arrays.

        ``limits`` (optional dict): ``max_seconds_per_point`` — over it the point raises
        :class:`SolverError` with a message starting with "time limit" (checked like a study
        file's ``[limits]``).
        """
        method = method or self.methods[0]
        if not isinstance(method, str):
            raise TypeError(f"method must be a name, got {method!r}")
        text = _geardyn.solve(self.key, json.dumps(self._params), method,
                              self._settings(settings), _limits_json(limits))
        out = _arrays(_unwrap(text))
        _tables.warn_unreliable([(f"{self.key} {method}", out)])
        return out

    def sweep(self, parameter, values, method=None, *, limits=None, as_="list", **settings):
        """Solve every value of ``parameter`` (in parallel, results in input order).

        ``values`` must be 1-D (else :class:`ValueError`); their number is checked against
        ``limits["max_points"]`` (default 10 000, as in a study file) before anything is
        converted or computed (:class:`ParameterError`). ``limits["max_seconds_per_point"]``
        bounds each point's wall-clock time.

        Returns (``as_="list"``, the default) a list with one result dict per value; a point
        that failed holds the exception instance instead, whose message is the reason (a sweep
        is not aborted by one bad point: a NaN value, a value out of range, a solver failure,
        the time limit). The other forms hold the scalar fields of every point (nested dicts
        flattened, ``window.rsv_window``; waveforms left out) and a ``reason`` column:
        ``as_="numpy"`` a dict of arrays, ``"pandas"`` a DataFrame (units in
        ``df.attrs["units"]``), ``"xarray"`` a Dataset over the dimension ``parameter``
        (units in each variable's ``attrs``). Points that are not settled, converged or stable
        raise a :class:`ReliabilityWarning` in every form.
        """
        _tables.check_form(as_)
        method = method or self.methods[0]
        if not isinstance(parameter, str):
            raise TypeError(f"parameter must be a name, got {parameter!r}")
        if not isinstance(method, str):
            raise TypeError(f"method must be a name, got {method!r}")
        values = [float(v) for v in _sweep_values(values, limits)]
        text = _geardyn.sweep(self.key, json.dumps(self._params), parameter, values, method,
                              self._settings(settings), _limits_json(limits))
        out = []
        for point in _unwrap(text):
            if "error" in point:
                try:
                    _raise(point["error"])
                except GeardynError as e:
                    out.append(e)
            else:
                out.append(_arrays(point["ok"]))
        _tables.warn_unreliable(
            [(f"{parameter} = {_tables._fmt(v)}", r) for v, r in zip(values, out)])
        if as_ == "list":
            return out
        names, cols = _tables.point_columns(parameter, values, out)
        if as_ == "numpy":
            return {k: _tables.column_array(cols[k], text=(k == "reason")) for k in names}
        return _tables.frame(names, cols, _tables.output_units(self.key, method),
                             {"model": self.key, "method": method}, as_)

    def __repr__(self):
        return f"{type(self).__name__}({self.params!r})"


class Liu2021(Model):
    """Liu, Lv, Zhao 2021: rattle of a noncircular face gear (Mech. Sci. 12:361).

    Presets: ``"table1"``. Readings: ``readings="printed"`` or ``"consistent"`` (default), or
    a dict of single readings (``{"rigid_acceleration": "printed_eq20"}``). Methods:
    ``"hbm"`` (the settings of ``geardyn study``, same names and bounds: ``full_r`` in
    [1, 8], absent for the paper's basis, ``tol``, ``max_iter``, ``samples`` = AFT samples per
    period in [8, 65536]; and ``warm_start``, ``output_samples`` = points of the returned
    ``tau``/``q``, default 512) and ``"time-stepping"`` (``options`` = a dict of
    ``IntegrationOptions``, checked against the study settings of the same names;
    ``long_window_periods=n`` adds ``window``, the long-window rattle statistics over ``n``
    periods with their range over two tolerances, two windows and two starts). Results:
    ``rsv``, ``ppv``, ``converged``, ``tau``, ``q`` (and ``v`` and ``window`` for time stepping).
    ``"shooting"``: the periodic orbit by shooting on the event-located flow from a
    time-integration guess (study settings ``transient_periods``, ``rtol``, ``tol``,
    ``max_iter``, ``segments``, ``flow_method`` = ``"dp5"`` or ``"dop853"``; ``initial=[q, q']``
    where the guess starts); results are the
    columns of ``geardyn study``'s method ``shooting``: ``rsv``, ``q0``, ``dq0``,
    ``events_per_period``, ``max_multiplier``, ``mu1_re``/``mu1_im``/``mu2_re``/``mu2_im``,
    ``stable``, ``det_phi_plus_i`` (its sign change between two points is a period doubling),
    ``gap_max_drive``/``gap_max_back`` (max of (q ± b̄)/b̄: a sign change is a grazing, the
    unilateral / bilateral onset), ``newton_iterations``, ``residual``.
    """

    key = "liu2021"
    default_preset = "table1"
    methods = ("hbm", "time-stepping", "shooting")

    def __init__(self, preset=None, readings=None, **params):
        super().__init__(preset, **params)
        if readings is not None:
            self._params = self.with_readings(readings)._params

    def with_readings(self, readings):
        """A copy with the readings replaced: ``"printed"``, ``"consistent"`` or a dict."""
        if isinstance(readings, str):
            readings = _preset("liu2021-readings", readings)
        return self.with_params(readings=readings)

    def rattle_sweep(self, omega1, method="time-stepping", *, limits=None, as_="numpy",
                     **settings):
        """rsv and ppv against the pinion speed ``omega1`` [rad/s] as numpy arrays of the
        shape of ``omega1`` (any shape; the points are solved flat, in C order).

        ``rsv`` and ``ppv`` are NaN where a point failed or did not converge, and ``reason``
        (an object array of the same shape) says why: the error message, or "did not
        converge"; ``None`` where the point is good. ``limits`` as in :meth:`sweep`. The other
        scalar fields of the points (``converged``, ``contact_events``, and ``motion``,
        ``settled`` where the method returns them, …) come as arrays of the same shape.

        ``as_="pandas"`` returns a DataFrame with one row per speed, ``as_="xarray"`` a
        Dataset over the dimension ``omega1`` (1-D ``omega1`` only), units in the attributes.
        A point that is not settled, converged or stable raises a :class:`ReliabilityWarning`.
        """
        if as_ not in ("numpy", "pandas", "xarray"):
            raise ValueError(f"as_ must be 'numpy', 'pandas' or 'xarray', got {as_!r}")
        _unwrap(_geardyn.check_points(min(_size(omega1), sys.maxsize), _limits_json(limits)))
        omega1 = np.asarray(omega1, dtype=float)
        if as_ == "xarray" and omega1.ndim != 1:
            raise ValueError(f"as_='xarray' takes 1-D omega1, got shape {omega1.shape}")
        flat = omega1.ravel()
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", ReliabilityWarning)
            res = self.sweep("omega1", flat, method, limits=limits, **settings)
        for w in caught:  # re-issued from here, so that they point at the caller
            warnings.warn(w.message, w.category, stacklevel=2)
        names, cols = _tables.point_columns("omega1", flat, res)
        rsv = np.full(len(res), np.nan)
        ppv = np.full(len(res), np.nan)
        reason = np.empty(len(res), dtype=object)
        for k, r in enumerate(res):
            if isinstance(r, Exception):
                reason[k] = str(r)
            elif not r["converged"]:
                reason[k] = "did not converge"
            else:
                rsv[k], ppv[k] = r["rsv"], r["ppv"]
        cols["rsv"], cols["ppv"], cols["reason"] = list(rsv), list(ppv), list(reason)
        if as_ != "numpy":
            return _tables.frame(names, cols, _tables.output_units(self.key, method),
                                 {"model": self.key, "method": method}, as_)
        out = {"omega1": omega1, "rsv": rsv.reshape(omega1.shape),
               "ppv": ppv.reshape(omega1.shape), "reason": reason.reshape(omega1.shape)}
        for k in names:
            if k not in out:
                out[k] = _tables.column_array(cols[k]).reshape(omega1.shape)
        return out


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
    ``"rk4"`` (the model's fixed-step RK4) and ``"hbm"`` (torsional models). ``omega`` (ω*,
    required) is a parameter, as in a study file (``Yu2021().with_params(omega=0.5)``, or
    ``sweep("omega", ...)``); as a setting it is still accepted. Settings ``options`` (a dict
    of model options or ``"chen"``), ``transient_periods``, ``record_periods`` (the bounds of
    ``geardyn study``), ``hbm`` (a dict of HBM settings).
    """

    key = "yu2021"
    default_preset = "table1"
    methods = ("time-stepping", "rk4", "hbm", "shooting")
    extra_params = ("omega",)

    def _settings(self, settings):
        opts = settings.get("options")
        if isinstance(opts, str):
            settings = dict(settings, options=_preset("yu2021-options", opts))
        return super()._settings(settings)


class StudyResult:
    """The table of a study: ``columns`` (names), ``units``, ``data`` (2-D float array, text
    cells as NaN), ``rows`` (as read), ``summary`` (dict), ``dims`` (the swept parameters and
    their sizes, ``[(name, n)]``: the table's first columns), ``unsettled`` (bool array of the
    shape of ``data``: the cells the study marks as not settled).

    ``to_pandas()`` and ``to_xarray()`` give the table to pandas and xarray. Creating it
    issues a :class:`ReliabilityWarning` when a row's ``settled``, ``converged`` or
    ``stable`` column is false, or when cells are unsettled."""

    def __init__(self, reply):
        self.name = reply["name"]
        self.columns = [c["name"] for c in reply["columns"]]
        self.units = [c["unit"] for c in reply["columns"]]
        self.rows = reply["rows"]
        self.summary = reply["summary"]
        self.tables = {t["name"]: t for t in reply.get("tables", [])}
        self.dims = _tables.study_dims(self.summary, self.columns)
        self.unsettled = np.zeros((len(self.rows), len(self.columns)), dtype=bool)
        self.unsettled_cells = {}
        for i, j in reply.get("unsettled", []):
            self.unsettled[i, j] = True
            self.unsettled_cells.setdefault(self.columns[j], []).append(i)
        self.data = np.array(
            [[x if isinstance(x, (int, float)) and not isinstance(x, bool) else np.nan
              for x in row] for row in self.rows],
            dtype=float,
        ).reshape(len(self.rows), len(self.columns))

    def to_pandas(self):
        """The table as a :class:`pandas.DataFrame`, one row per point and one column per
        output (numbers as float, counts as int, names as str; a failed point's cells NaN).
        ``df.attrs``: ``units`` (``{column: unit}``), ``dims`` (the swept parameters),
        ``study``, ``points``, ``failed_points`` (count) and ``summary`` (the JSON summary).
        Needs pandas (``pip install 'geardyn[pandas]'``)."""
        return _tables.study_frame(self, "pandas")

    def to_xarray(self):
        """The study as an :class:`xarray.Dataset`: one dimension per swept parameter, named
        after it, with its values as the coordinate (a 2-D map has the dimensions
        ``(sweep, sweep2)``); every other column a data variable with ``attrs["units"]``. A
        single-point study holds scalars. ``ds.attrs``: ``study``, ``points``,
        ``failed_points``, ``summary_json``. ``ds.rsv.plot()`` and ``ds.to_netcdf(path)`` work
        as for any Dataset. Needs xarray (``pip install 'geardyn[xarray]'``)."""
        return _tables.study_frame(self, "xarray")

    @property
    def basin(self):
        """A basin study's attractors and fractions (``summary["basin"]``: ``attractors``,
        ``failed``, ``failed_fraction``, ``grid``), or ``None`` for any other study."""
        b = self.summary.get("basin") if isinstance(self.summary, dict) else None
        return b if isinstance(b, dict) else None

    def fractions(self, as_="pandas"):
        """A basin study's attractors, one row per attractor in label order (``attractor``,
        ``name``, ``rsv``, ``motion``, ``ppv``, ``ppv_min``, ``ppv_max``, ``cells``,
        ``fraction``, ``seed_q``, ``seed_q_dot``): a :class:`pandas.DataFrame` (``as_="pandas"``,
        ``df.attrs["failed_fraction"]``) or a list of dicts (``as_="list"``). The cells are the
        study's table (``to_pandas()``: ``q``, ``q_dot``, the method's columns, ``attractor``).
        A study without ``[basin]`` raises ``ValueError``."""
        if as_ not in ("pandas", "list"):
            raise ValueError(f"as_ must be 'pandas' or 'list', got {as_!r}")
        return _tables.basin_fractions(self, as_)

    @property
    def continuation(self):
        """A continuation study's result (``summary["continuation"]``: ``parameter``,
        ``unit``, ``branch_points``, ``stop``, ``special``, ``second``, ``curves``,
        ``curve_failures``), or ``None`` for any other study. The table itself is the branch,
        one row per point."""
        c = self.summary.get("continuation") if isinstance(self.summary, dict) else None
        return c if isinstance(c, dict) else None

    def special_points(self, as_="pandas"):
        """A continuation study's special points in branch order (``kind``, the parameter,
        ``located``, ``precision``, ``stable``, the state): a :class:`pandas.DataFrame`
        (``as_="pandas"``, units in ``df.attrs["units"]``) or a list of dicts
        (``as_="list"``). A study without ``[continuation]`` raises ``ValueError``."""
        return _tables.continuation_table(self, "special", as_)

    def curves(self, as_="pandas"):
        """A continuation study's codim-2 curves, one row per curve point (``curve``: the
        index of its start among :meth:`special_points`, ``kind``, ``direction``, the two
        parameters, ``stable``), as :meth:`special_points`; the stop reason of each curve is in
        ``continuation["curves"][k]["stop"]``. A study without ``[continuation.codim2]`` raises
        ``ValueError``."""
        return _tables.continuation_table(self, "curves", as_)

    def column(self, name):
        """One column as a float array (by name)."""
        try:
            return self.data[:, self.columns.index(name)]
        except ValueError:
            raise KeyError(f"no column `{name}`; columns: {self.columns}") from None

    def __repr__(self):
        return f"StudyResult({self.name!r}, {len(self.rows)} rows, columns={self.columns})"


def run_study(text):
    """Run a study given as TOML text (format: ``docs/studies.md``). Rows whose ``settled``,
    ``converged`` or ``stable`` column is false, and unsettled cells, raise a
    :class:`ReliabilityWarning`."""
    res = StudyResult(_unwrap(_geardyn.run_study(text)))
    _tables.warn_unreliable(_tables.study_records(res), stacklevel=3)
    _tables.warn_unsettled_cells(int(res.unsettled.sum()), res.unsettled.size, stacklevel=3)
    return res


def run_study_file(path):
    """Run a study file."""
    with open(os.fspath(path), encoding="utf-8") as f:
        text = f.read()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", ReliabilityWarning)
        res = run_study(text)
    for w in caught:  # re-issued from here, so that they point at the caller
        warnings.warn(w.message, w.category, stacklevel=2)
    return res


def write_study(text, out_dir):
    """Run a study given as TOML text in this process and write its files to ``out_dir``
    (CSV, SVG, JSON summary), as ``geardyn study`` does. Returns the JSON summary as a dict.
    For a study spread over many processes or machines, see :mod:`geardyn.dask`."""
    return _unwrap(_geardyn.write_study(text, os.fspath(out_dir)))
