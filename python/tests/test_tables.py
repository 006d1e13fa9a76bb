"""Results for pandas and xarray (issue 41): StudyResult.to_pandas()/.to_xarray(), the
`as_=` forms of sweep and rattle_sweep, the missing-extra error, reliability warnings and the
study-file spelling of readings."""

import math
import pathlib
import sys
import warnings

import numpy as np
import pytest

import geardyn

pd = pytest.importorskip("pandas")
xr = pytest.importorskip("xarray")

ROOT = pathlib.Path(__file__).resolve().parents[2]

ONE_D = """
name = "delta-vs-b"
model = "karpov2017-kinematics"
[sweep]
parameter = "b"
from = 0.001
to = 0.01
steps = 4
[solver]
method = "kinematics"
"""

SINGLE = """
name = "one-point"
model = "karpov2017-kinematics"
[overrides]
b = 0.01
[solver]
method = "kinematics"
"""

# a small bifurcation study: a text column (`motion`) next to numbers
BIFURCATION = """
name = "small-bifurcation"
model = "liu2021"
[overrides]
load_torque = 30.0
[sweep]
parameter = "omega1"
values = [150.0, 200.0]
[bifurcation]
points = 4
transient_periods = 10
max_period = 2
[solver]
method = "time-stepping"
"""


def test_one_d_study_round_trip():
    s = geardyn.run_study(ONE_D)
    assert s.dims == [("b", 4)]
    df = s.to_pandas()
    assert list(df.columns) == s.columns and df.shape == (4, len(s.columns))
    assert df.attrs["units"] == dict(zip(s.columns, s.units))
    assert df.attrs["dims"] == ["b"] and df.attrs["study"] == "delta-vs-b"
    # every number as it came (the table's data), bit for bit
    np.testing.assert_array_equal(df.to_numpy(dtype=float), s.data)

    ds = s.to_xarray()
    assert dict(ds.sizes) == {"b": 4}
    np.testing.assert_array_equal(ds["b"].values, s.column("b"))
    np.testing.assert_allclose(ds["b"].values, [0.001, 0.004, 0.007, 0.01], rtol=1e-12)
    for name, unit in zip(s.columns[1:], s.units[1:]):
        assert ds[name].dims == ("b",)
        assert ds[name].attrs["units"] == unit
        np.testing.assert_array_equal(ds[name].values, s.column(name))
    # back to a table: the same frame
    back = ds.to_dataframe().reset_index()[s.columns]
    pd.testing.assert_frame_equal(back, df, check_dtype=False)


def test_two_d_map_shapes_and_coordinates():
    s = geardyn.run_study_file(ROOT / "validation/examples/karpov-delta-vs-b.toml")
    assert s.dims == [("b", 50), ("xi", 4)]
    ds = s.to_xarray()
    assert ds["delta_exact"].dims == ("b", "xi")
    assert dict(ds.sizes) == {"b": 50, "xi": 4}
    np.testing.assert_array_equal(ds["xi"].values, [1.5, 2.0, 5.0, 10.0])
    assert ds["b"].values[0] == 0.001 and ds["b"].values[-1] == 0.05
    # each cell is its row of the table: rows run over b fastest (row = ixi * 50 + ib)
    j = s.columns.index("emax_exact")
    for ib, ixi in ((0, 0), (7, 1), (49, 3), (20, 2)):
        row = s.rows[ixi * 50 + ib]
        assert (row[0], row[1]) == (ds["b"].values[ib], ds["xi"].values[ixi])
        assert ds["emax_exact"].values[ib, ixi] == row[j]
        assert ds["emax_exact"].sel(b=row[0], xi=row[1]).item() == row[j]
    assert ds["emax_exact"].attrs["units"] == "rad/s^2"
    assert ds["b"].attrs["units"] == "1"
    # the pandas table indexed by the sweeps is the same Dataset
    df = s.to_pandas()
    assert df.shape == (200, len(s.columns))
    again = xr.Dataset.from_dataframe(df.set_index(df.attrs["dims"]))
    for name in s.columns[2:]:
        np.testing.assert_array_equal(again[name].transpose("b", "xi").values, ds[name].values)


def test_single_point_study_holds_scalars():
    s = geardyn.run_study(SINGLE)
    assert s.dims == []
    ds = s.to_xarray()
    assert dict(ds.sizes) == {}
    assert ds["delta_exact"].item() == s.column("delta_exact")[0]
    assert s.to_pandas().shape == (1, len(s.columns))


def test_text_columns_survive_both_conversions():
    s = geardyn.run_study(BIFURCATION)
    df = s.to_pandas()
    ds = s.to_xarray()
    assert ds["omega1"].values.tolist() == [150.0, 200.0]
    text = [c for c in s.columns if pd.api.types.is_string_dtype(df[c])]
    assert text, "the bifurcation table has a text column (motion)"
    for c in text:
        assert ds[c].dims == ("omega1",)
        assert [str(v) for v in ds[c].values] == ["" if pd.isna(v) else str(v) for v in df[c]]
    assert ds["motion"].values.tolist() == [row[1] for row in s.rows]


def test_sweep_and_rattle_sweep_forms():
    liu = geardyn.Liu2021(readings={"base_radius": "mean"})
    speeds = [120.0, 125.0]
    listed = liu.sweep("omega1", speeds, "hbm")
    df = liu.sweep("omega1", speeds, "hbm", as_="pandas")
    assert list(df["omega1"]) == speeds and list(df["rsv"]) == [r["rsv"] for r in listed]
    assert df["ppv"].tolist() == [r["ppv"] for r in listed]
    assert "q" not in df.columns and df["reason"].isna().all()
    assert df.attrs["units"]["omega1"] == "rad/s" and df.attrs["units"]["ppv"] == "1"
    ds = liu.sweep("omega1", speeds, "hbm", as_="xarray")
    assert ds["ppv"].dims == ("omega1",) and ds["omega1"].attrs["units"] == "rad/s"
    assert ds["reason"].dtype.kind == "U" and (ds["reason"].values == "").all()
    np.testing.assert_array_equal(ds["ppv"].values, df["ppv"].to_numpy())
    arrays = liu.sweep("omega1", speeds, "hbm", as_="numpy")
    assert arrays["converged"].dtype == bool and arrays["converged"].all()
    with pytest.raises(ValueError, match="as_"):
        liu.sweep("omega1", speeds, "hbm", as_="polars")

    r = liu.rattle_sweep(np.array(speeds), method="hbm", as_="xarray")
    assert dict(r.sizes) == {"omega1": 2}
    np.testing.assert_array_equal(r["rsv"].values, [0.0, 0.0])
    t = liu.rattle_sweep(np.array(speeds), method="hbm", as_="pandas")
    assert t.shape[0] == 2 and {"omega1", "rsv", "ppv", "reason"} <= set(t.columns)
    # the default is unchanged: numpy arrays of omega1's shape
    n = liu.rattle_sweep(np.array(speeds), method="hbm")
    assert isinstance(n, dict) and n["rsv"].shape == (2,)
    with pytest.raises(ValueError, match="1-D"):
        liu.rattle_sweep(np.ones((2, 2)) * 120.0, method="hbm", as_="xarray")


def test_a_failed_point_is_a_reason_in_every_form():
    liu = geardyn.Liu2021(readings={"base_radius": "mean"})
    df = liu.sweep("omega1", [120.0, -1.0], "hbm", as_="pandas")
    assert pd.isna(df["reason"][0]) and "omega1" in df["reason"][1]
    assert math.isnan(df["ppv"][1])
    ds = liu.sweep("omega1", [120.0, -1.0], "hbm", as_="xarray")
    assert ds["reason"].values[0] == "" and "omega1" in ds["reason"].values[1]


@pytest.mark.parametrize("module", ["pandas", "xarray"])
def test_a_missing_extra_names_itself(monkeypatch, module):
    s = geardyn.run_study(ONE_D)
    monkeypatch.setitem(sys.modules, module, None)  # `import module` now raises ImportError
    call = s.to_pandas if module == "pandas" else s.to_xarray
    with pytest.raises(ImportError, match=rf"pip install 'geardyn\[{module}\]'"):
        call()
    with pytest.raises(ImportError, match=module):
        geardyn.Liu2021().sweep("omega1", [120.0], "hbm", as_=module)


def test_reliability_warnings():
    # a converged, settled sweep warns about nothing
    liu = geardyn.Liu2021(readings={"base_radius": "mean"})
    with warnings.catch_warnings():
        warnings.simplefilter("error", geardyn.ReliabilityWarning)
        liu.sweep("omega1", [120.0], "hbm")
        geardyn.run_study(ONE_D)
    # a Newton run cut short is not converged: marked in the result and warned about
    with pytest.warns(geardyn.ReliabilityWarning, match=r"not converged.*omega1 = 160"):
        res = geardyn.Liu2021().sweep("omega1", [160.0], "hbm", full_r=2, max_iter=1)
    assert res[0]["converged"] is False
    with pytest.warns(geardyn.ReliabilityWarning, match="not converged"):
        geardyn.Liu2021().with_params(omega1=160.0).solve("hbm", full_r=2, max_iter=1)
    # the flags are read generically: `settled`, `stable` when a result carries them
    from geardyn import _tables

    with pytest.warns(geardyn.ReliabilityWarning, match=r"1 of 3 point\(s\) not settled.*omega1 = 180"):
        n = _tables.warn_unreliable([("omega1 = 170", {"settled": True}),
                                     ("omega1 = 180", {"settled": False}),
                                     ("omega1 = 190", {"settled": float("nan")})])
    assert n == 1
    with pytest.warns(geardyn.ReliabilityWarning, match="not settled"):
        _tables.warn_unreliable([("p", {"rsv": 1, "window": {"settled": False}})])
    with pytest.warns(geardyn.ReliabilityWarning, match="not stable"):
        _tables.warn_unreliable([("x", {"stable": 0.0}), ("y", {"stable": 1.0})])
    assert issubclass(geardyn.ReliabilityWarning, UserWarning)


def test_readings_in_study_file_spelling():
    consistent = geardyn.Liu2021().params["readings"]
    assert consistent == {"base_radius": "time-varying", "error_term": "derived",
                          "rigid_acceleration": "derived", "rigid_series": "two-terms"}
    printed = geardyn.Liu2021(readings="printed").params["readings"]
    assert printed == {"base_radius": "mean", "error_term": "printed",
                       "rigid_acceleration": "printed-eq20", "rigid_series": "two-terms"}
    # every spelling of a name is accepted and solves the same model
    ppv = set()
    warnings.simplefilter("ignore", geardyn.ReliabilityWarning)  # only the spelling matters
    for name in ("printed-eq20", "printed_eq20", "PrintedEq20"):
        liu = geardyn.Liu2021(readings={"rigid_acceleration": name, "base_radius": "mean"})
        assert liu.params["readings"]["rigid_acceleration"] == "printed-eq20"
        ppv.add(repr(liu.with_params(omega1=120.0).solve("hbm", max_iter=5)["ppv"]))
    assert len(ppv) == 1
    assert geardyn.Liu2021(readings={"base_radius": "time_varying"}).params == \
        geardyn.Liu2021().params


def test_a_sweep_over_names_is_a_string_coordinate():
    s = geardyn.run_study_file(ROOT / "validation/examples/yu-df-vs-frequency.toml")
    ds = s.to_xarray()
    assert ds["df"].dims == ("omega", "variant")
    assert ds["variant"].values.tolist() == ["yu", "kahraman-singh"]
    assert ds.sizes["omega"] * ds.sizes["variant"] == len(s.rows)
    # counts stay integers, the sweep picks the same rows as the table
    assert ds["steps_accepted"].dtype == np.int64
    row = s.rows[1 * ds.sizes["omega"] + 4]  # variant 1, the fifth ω*
    assert ds["df"].sel(omega=row[0], variant=row[1]).item() == row[s.columns.index("df")]
