"""Results as the scientific Python ecosystem handles them, and reliability warnings.

* tables as :class:`pandas.DataFrame` (units in ``df.attrs["units"]``, one entry per column);
* sweeps and maps as :class:`xarray.Dataset` (one dimension per swept parameter, named after
  it, with its values as the coordinate; units in each variable's ``attrs["units"]``), so that
  ``ds.rsv.plot()`` and ``ds.to_netcdf(...)`` work;
* :class:`~geardyn.errors.ReliabilityWarning` for points that are not settled, converged or
  stable, keyed off the columns ``settled``, ``converged`` and ``stable`` when a result has them.

pandas and xarray are optional (``pip install 'geardyn[pandas]'`` / ``'geardyn[xarray]'``) and
imported only when a conversion asks for them. Everything here is generic over the columns a
result carries: a column the Rust side adds (``motion``, ``settled``, ``rsv_one_period``, …)
appears without a change here.
"""

import importlib
import json
import math
import re
import warnings

import numpy as np

from .errors import ReliabilityWarning

#: The forms a sweep can return (``as_=``).
FORMS = ("list", "numpy", "pandas", "xarray")

#: The flag columns that mark a point's reliability, with what a false value means.
FLAGS = {
    "settled": "settled (the transient had not died out when the statistics were taken: "
               "motion, rsv and ppv may not be the steady response)",
    "converged": "converged (the solver stopped before its tolerance)",
    "stable": "stable (Floquet: a time run does not stay on an unstable orbit)",
}


def require(module, extra, what):
    """Import an optional dependency, or raise :class:`ImportError` naming the extra."""
    try:
        return importlib.import_module(module)
    except ImportError as e:
        raise ImportError(
            f"{what} needs the optional dependency `{module}`: "
            f"pip install 'geardyn[{extra}]' (from a checkout: pip install './python[{extra}]')"
        ) from e


def check_form(as_):
    if as_ not in FORMS:
        raise ValueError(f"as_ must be one of {FORMS}, got {as_!r}")
    return as_


# -- spellings of choices ------------------------------------------------------------------

_NAME = re.compile(r"^[A-Za-z][A-Za-z0-9_-]*$")


def study_name(raw):
    """The study-file spelling of a choice: ``PrintedEq20`` → ``printed-eq20``, ``two_terms``
    → ``two-terms`` (the rule of ``geardyn study``, ``docs/studies.md``)."""
    if "_" in raw or "-" in raw or not any(c.isupper() for c in raw):
        return raw.replace("_", "-").lower()
    out = []
    for i, c in enumerate(raw):
        if c.isupper():
            if i > 0:
                out.append("-")
            out.append(c.lower())
        else:
            out.append(c)
    return "".join(out)


def spelled(value):
    """``value`` with every choice name (nested dicts and lists too) in study-file spelling."""
    if isinstance(value, dict):
        return {k: spelled(v) for k, v in value.items()}
    if isinstance(value, list):
        return [spelled(v) for v in value]
    if isinstance(value, str) and _NAME.match(value):
        return study_name(value)
    return value


def serde_spelled(value, base):
    """``value`` with each choice name in the serde spelling of the same field of ``base`` (a
    parameter set as the Rust side returns it): CamelCase where ``base`` holds CamelCase
    (``"printed-eq20"`` → ``"PrintedEq20"``), snake_case otherwise (``"time-varying"`` →
    ``"time_varying"``). Any spelling of a name is accepted."""
    if isinstance(value, dict):
        b = base if isinstance(base, dict) else {}
        return {k: serde_spelled(v, b.get(k)) for k, v in value.items()}
    if (isinstance(value, str) and isinstance(base, str) and _NAME.match(value)
            and _NAME.match(base)):
        kebab = study_name(value)
        if any(c.isupper() for c in base):
            return "".join(w[:1].upper() + w[1:] for w in kebab.split("-"))
        return kebab.replace("-", "_")
    return value


# -- columns -------------------------------------------------------------------------------

def _is_num(x):
    return isinstance(x, (int, float, np.integer, np.floating)) and not isinstance(
        x, (bool, np.bool_))


def column_array(values, text=False):
    """A column as a numpy array: bool if every value is a flag, int64 if every value is an
    integer, float (``None`` → NaN) if every value is a number or missing, else (or with
    ``text``) an object array of the values (``None`` where missing)."""
    if text:
        out = np.empty(len(values), dtype=object)
        out[:] = [None if v is None else str(v) for v in values]
        return out
    present = [v for v in values if v is not None and not (isinstance(v, float) and
                                                          math.isnan(v))]
    if present and all(isinstance(v, (bool, np.bool_)) for v in present):
        if len(present) == len(values):
            return np.array(values, dtype=bool)
        return np.array([np.nan if v is None else float(v) for v in values], dtype=float)
    if all(_is_num(v) for v in present):
        if present and len(present) == len(values) and all(
                isinstance(v, (int, np.integer)) for v in values):
            return np.array(values, dtype=np.int64)
        return np.array([np.nan if v is None else float(v) for v in values], dtype=float)
    out = np.empty(len(values), dtype=object)
    for i, v in enumerate(values):
        out[i] = v
    return out


def _text_for_xarray(arr):
    """Object columns as strings for xarray ('' where missing), so ``to_netcdf`` can write
    them."""
    if arr.dtype == object:
        return np.array(["" if v is None else str(v) for v in arr], dtype=str)
    return arr


def _false(v):
    """A flag that says no: False, a finite 0, or a name like "false"/"no"/"unsettled"."""
    if isinstance(v, (bool, np.bool_)):
        return not bool(v)
    if _is_num(v):
        return math.isfinite(float(v)) and float(v) == 0.0
    if isinstance(v, str):
        return v.strip().lower() in ("false", "no", "0", "off", "unsettled")
    return False


def warn_unreliable(records, stacklevel=3):
    """Issue one :class:`ReliabilityWarning` per flag column (``settled``, ``converged``,
    ``stable``; at the top level of a record or in a nested dict of it) that is false at any
    point. ``records``: ``(label, mapping)`` pairs, the
    label naming the point (``"omega1 = 180"``). Returns the number of points flagged."""
    flagged = set()
    n = len(records)

    def says_no(rec, flag):
        # the flag at the top level, or in a nested result (`window.settled`)
        if not isinstance(rec, dict):
            return False
        if flag in rec and _false(rec[flag]):
            return True
        return any(isinstance(v, dict) and flag in v and _false(v[flag]) for v in rec.values())

    for flag, meaning in FLAGS.items():
        bad = [label for label, rec in records if says_no(rec, flag)]
        if not bad:
            continue
        flagged.update(bad)
        shown = ", ".join(str(b) for b in bad[:5]) + (", …" if len(bad) > 5 else "")
        where = f" ({shown})" if shown else ""
        warnings.warn(
            f"{len(bad)} of {n} point(s) not {meaning}{where}; the column `{flag}` marks them",
            ReliabilityWarning, stacklevel=stacklevel)
    return len(flagged)


def warn_unsettled_cells(count, total, stacklevel=3):
    """A :class:`ReliabilityWarning` for a study's cells marked unsettled by the Rust side."""
    if count:
        warnings.warn(
            f"{count} of {total} cell(s) are unsettled (a non-periodic sample, a long-window "
            f"statistic whose variants disagree, or an iterate of a solver that did not "
            f"converge): see StudyResult.unsettled", ReliabilityWarning, stacklevel=stacklevel)


def _fmt(x):
    if isinstance(x, float):
        return f"{x:g}"
    return str(x)


# -- point results (Model.sweep, Liu2021.rattle_sweep) ---------------------------------------

def scalar_fields(result):
    """The scalar entries of one point's result dict, nested dicts flattened one level with
    a dot (``window.rsv_window``); arrays and lists are left out."""
    out = {}
    for k, v in result.items():
        if isinstance(v, dict):
            for k2, v2 in v.items():
                if v2 is None or isinstance(v2, (bool, str, int, float, np.generic)):
                    out[f"{k}.{k2}"] = v2
        elif v is None or isinstance(v, (bool, str, int, float, np.generic)):
            out[k] = v
    return out


def output_units(model_key, method):
    """``{column: unit}`` of a model's method and parameters, from its self-description."""
    from . import describe  # the package's, late: this module is imported by it

    units = {}
    try:
        d = describe(model_key)
    except Exception:  # noqa: BLE001 — units are a courtesy; a result never fails for them
        return units
    info = d.get("info", d)
    for p in info.get("parameters", []):
        if isinstance(p, dict) and "name" in p and "unit" in p:
            units[p["name"]] = p["unit"]
    for m in info.get("methods", []):
        if m.get("method") == method:
            for name, unit in m.get("outputs", []):
                units[name] = unit
    return units


def point_columns(parameter, values, results):
    """``(names, {name: list})`` of a sweep's table: the swept parameter, every scalar field
    of the good points (in order of first appearance), and ``reason`` (the message of a
    failed point, ``None`` where it is good)."""
    rows = []
    names = [parameter]
    for r in results:
        row = {} if isinstance(r, Exception) else scalar_fields(r)
        rows.append(row)
        for k in row:
            if k not in names:
                names.append(k)
    cols = {parameter: [float(v) for v in values]}
    for k in names[1:]:
        cols[k] = [row.get(k) for row in rows]
    cols["reason"] = [str(r) if isinstance(r, Exception) else None for r in results]
    names.append("reason")
    return names, cols


def frame(names, cols, units, attrs, as_):
    """The columns as a DataFrame (``as_ == "pandas"``) or a Dataset over the first column
    (``"xarray"``), with units."""
    arrays = {k: column_array(cols[k], text=(k == "reason")) for k in names}
    unit_map = {k: units[k] for k in names if k in units}
    if as_ == "pandas":
        pd = require("pandas", "pandas", "as_='pandas'")
        df = pd.DataFrame({k: arrays[k] for k in names}, columns=names)
        df.attrs.update(attrs)
        df.attrs["units"] = unit_map
        return df
    xr = require("xarray", "xarray", "as_='xarray'")
    dim = names[0]
    coords = {dim: (dim, arrays[dim], {"units": unit_map[dim]} if dim in unit_map else {})}
    data = {}
    for k in names[1:]:
        a = {"units": unit_map[k]} if k in unit_map else {}
        data[k] = ((dim,), _text_for_xarray(arrays[k]), a)
    ds = xr.Dataset(data, coords=coords)
    ds.attrs.update({k: v for k, v in attrs.items() if isinstance(v, (str, int, float))})
    return ds


# -- study tables ----------------------------------------------------------------------------

def study_dims(summary, columns):
    """The swept parameters of a study (its first columns) and their sizes: ``[(name, n)]``,
    empty for a single point."""
    study = summary.get("study", {}) if isinstance(summary, dict) else {}
    dims = []
    basin = study.get("basin")
    if isinstance(basin, dict):
        # a basin study: the grid of initial states, q fastest (the columns q, q_dot)
        dims = [("q", int(basin["q"]["steps"])), ("q_dot", int(basin["q_dot"]["steps"]))]
    for key in ("sweep", "sweep2"):
        s = study.get(key)
        if not isinstance(s, dict) or "parameter" not in s:
            continue
        if s.get("values") is not None:
            n = len(s["values"])
        elif s.get("steps") is not None:
            n = int(s["steps"])
        else:
            n = None
        dims.append((s["parameter"], n))
    # the table's first columns are the sweeps, in order
    for (name, _), col in zip(dims, columns):
        if name != col:
            return []
    return dims


def basin_fractions(result, as_):
    """The attractors of a basin study (``summary["basin"]``) as a list of dicts or a
    :class:`pandas.DataFrame`, one row per attractor, in label order."""
    basin = result.summary.get("basin") if isinstance(result.summary, dict) else None
    if not isinstance(basin, dict) or "attractors" not in basin:
        raise ValueError(f"study {result.name!r} is not a basin study (no [basin] table)")
    rows = [{"attractor": a["label"], "name": a["name"], "rsv": a["rsv"],
             "motion": a["motion"], "ppv": a["ppv"], "ppv_min": a["ppv_min"],
             "ppv_max": a["ppv_max"], "cells": a["cells"], "fraction": a["fraction"],
             "seed_q": a["seed"][0], "seed_q_dot": a["seed"][1]}
            for a in basin["attractors"]]
    if as_ == "list":
        return rows
    pd = require("pandas", "pandas", "StudyResult.fractions()")
    df = pd.DataFrame(rows, columns=["attractor", "name", "rsv", "motion", "ppv", "ppv_min",
                                     "ppv_max", "cells", "fraction", "seed_q", "seed_q_dot"])
    df.attrs["failed"] = basin.get("failed")
    df.attrs["failed_fraction"] = basin.get("failed_fraction")
    return df


def continuation_table(result, which, as_):
    """A continuation study's further table ``<name>_special`` or ``<name>_curves`` as a
    list of dicts or a :class:`pandas.DataFrame`."""
    if as_ not in ("pandas", "list"):
        raise ValueError(f"as_ must be 'pandas' or 'list', got {as_!r}")
    if result.continuation is None:
        raise ValueError(f"study {result.name!r} is not a continuation study "
                         "(no [continuation] table)")
    table = result.tables.get(f"{result.name}_{which}")
    if table is None:
        raise ValueError(f"study {result.name!r} has no {which} table"
                         + (" (no [continuation.codim2] table)" if which == "curves" else ""))
    names = [c["name"] for c in table["columns"]]
    rows = [dict(zip(names, row)) for row in table["rows"]]
    if as_ == "list":
        return rows
    pd = require("pandas", "pandas", f"StudyResult.{'special_points' if which == 'special' else 'curves'}()")
    df = pd.DataFrame(rows, columns=names)
    df.attrs["units"] = {c["name"]: c["unit"] for c in table["columns"]}
    df.attrs["study"] = result.name
    return df


def study_frame(result, as_):
    """A :class:`~geardyn.StudyResult` as a DataFrame or a Dataset (see its methods)."""
    names = result.columns
    cols = {k: [row[j] for row in result.rows] for j, k in enumerate(names)}
    units = dict(zip(result.columns, result.units))
    attrs = {"study": result.name, "points": len(result.rows),
             "failed_points": len(result.summary.get("failed_points", []) or [])}
    arrays = {k: column_array(cols[k]) for k in names}
    if as_ == "pandas":
        pd = require("pandas", "pandas", "StudyResult.to_pandas()")
        df = pd.DataFrame({k: arrays[k] for k in names}, columns=names)
        df.attrs.update(attrs)
        df.attrs["units"] = units
        df.attrs["dims"] = [d for d, _ in result.dims]
        df.attrs["summary"] = json.loads(json.dumps(result.summary))
        return df

    xr = require("xarray", "xarray", "StudyResult.to_xarray()")
    dims = result.dims
    n_rows = len(result.rows)
    shape = []
    if len(dims) == 1:
        shape = [n_rows]
    elif len(dims) == 2:
        ny = dims[1][1]
        if not ny or n_rows % ny:
            # the sizes from the study disagree with the table: count the first sweep's run
            first = result.rows[0][1] if n_rows else None
            nx = next((i for i, r in enumerate(result.rows) if r[1] != first), n_rows)
            ny = n_rows // nx if nx else 0
        nx = n_rows // ny if ny else 0
        shape = [nx, ny]
    dim_names = [d for d, _ in dims]
    if not dims and n_rows != 1:
        # rows that are not a grid of the sweeps (never for a study file): one dimension
        dim_names, shape = ["point"], [n_rows]

    def reshape(arr):
        if len(dims) == 2:
            # rows run over the first sweep fastest: row = iy * nx + ix
            return arr.reshape(shape[1], shape[0]).T
        if not dim_names:
            return arr.reshape(())
        return arr

    coords = {}
    for k, (d, _) in enumerate(dims):
        if k == 0:
            vals = arrays[d][: shape[0]]
        else:
            vals = arrays[d][:: shape[0]] if shape[0] else arrays[d][:0]
        a = {"units": units[d]} if units.get(d) else {}
        coords[d] = (d, _text_for_xarray(vals), a)
    data = {}
    for k in names:
        if k in dim_names:
            continue
        arr = _text_for_xarray(arrays[k])
        a = {"units": units[k]} if units.get(k) else {}
        if result.unsettled_cells.get(k):
            mask = np.zeros(n_rows, dtype=bool)
            mask[result.unsettled_cells[k]] = True
            a["unsettled_points"] = int(mask.sum())
        data[k] = (tuple(dim_names) if dim_names and n_rows else (), reshape(arr), a)
    ds = xr.Dataset(data, coords=coords)
    ds.attrs.update(attrs)
    ds.attrs["summary_json"] = json.dumps(result.summary)
    return ds


def study_records(result):
    """``(label, {column: value})`` per row, for :func:`warn_unreliable`."""
    dims = [d for d, _ in result.dims]
    out = []
    for row in result.rows:
        rec = dict(zip(result.columns, row))
        label = ", ".join(f"{d} = {_fmt(rec[d])}" for d in dims) or result.name
        out.append((label, rec))
    return out
