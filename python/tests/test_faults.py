"""The Python API as hardened as the CLI (issue #27): the same names, bounds, messages and
size limits as a study file, a reason per failed point, shapes kept, NaN/inf named."""

import math

import numpy as np
import pytest

import geardyn


def test_a_sweep_over_the_point_limit_is_refused_before_anything_runs():
    # 10⁷ points: refused by limits.max_points (default 10 000) before conversion or compute
    omega1 = np.linspace(100.0, 200.0, 10**7)
    with pytest.raises(geardyn.ParameterError, match=r"10000000 points exceed limits.max_points = 10000"):
        geardyn.Liu2021().rattle_sweep(omega1, method="hbm")
    with pytest.raises(geardyn.ParameterError, match="limits.max_points"):
        geardyn.Liu2021().sweep("omega1", omega1, "hbm")
    # a virtual array of 10¹⁵ points (no memory behind it) is refused just the same
    huge = np.broadcast_to(np.float64(150.0), (10**15,))
    with pytest.raises(geardyn.ParameterError, match="exceed limits.max_points"):
        geardyn.Liu2021().sweep("omega1", huge, "hbm")
    # the limit is the study file's, with its bounds
    with pytest.raises(geardyn.ParameterError, match=r"limits.max_points must be in \[1, 1000000\]"):
        geardyn.Liu2021().sweep("omega1", [120.0], "hbm", limits={"max_points": 0})
    with pytest.raises(geardyn.ParameterError, match="limits.max_points"):
        geardyn.Liu2021().sweep("omega1", [120.0, 130.0], "hbm", limits={"max_points": 1})


def test_a_nan_sweep_point_reports_its_reason():
    # constant b̄ (as in test_geardyn): 120 rad/s does not rattle
    liu = geardyn.Liu2021(readings={"base_radius": "mean"})
    s = liu.rattle_sweep([120.0, math.nan, math.inf], method="hbm")
    assert s["reason"][0] is None and s["rsv"][0] == 0
    for k in (1, 2):
        assert math.isnan(s["rsv"][k]) and math.isnan(s["ppv"][k])
        assert "sweep of `omega1`: every value must be finite" in s["reason"][k]
    res = geardyn.Liu2021().sweep("omega1", [math.nan], "hbm")
    assert isinstance(res[0], geardyn.ParameterError) and "finite" in str(res[0])


def test_shapes_are_kept_or_refused():
    grid = np.array([[120.0, 130.0], [140.0, math.nan]])
    s = geardyn.Liu2021().rattle_sweep(grid, method="hbm")
    for k in ("omega1", "rsv", "ppv", "reason"):
        assert s[k].shape == (2, 2), k
    assert s["reason"][1, 1] is not None and s["reason"][0, 0] is None
    # a scalar speed gives 0-d outputs
    s = geardyn.Liu2021(readings={"base_radius": "mean"}).rattle_sweep(120.0, method="hbm")
    assert s["rsv"].shape == () and s["rsv"] == 0 and s["reason"].shape == ()
    # the general sweep returns a list: it takes 1-D values only
    with pytest.raises(ValueError, match=r"1-D .* shape \(2, 2\)"):
        geardyn.Liu2021().sweep("omega1", grid, "hbm")


def test_nan_and_inf_parameters_name_the_field():
    for bad, shown in ((math.nan, "NaN"), (math.inf, "inf"), (-math.inf, "-inf")):
        with pytest.raises(geardyn.ParameterError, match=f"parameter `omega1` must be finite, got {shown}"):
            geardyn.Liu2021().with_params(omega1=bad)
        with pytest.raises(geardyn.ParameterError, match=f"setting `tol` must be finite, got {shown}"):
            geardyn.Liu2021().solve("hbm", tol=bad)
    with pytest.raises(geardyn.ParameterError, match="parameter `readings.x` must be finite"):
        geardyn.Liu2021().with_params(readings={"x": math.nan})


def _cli_message(setting):
    """The message `geardyn study` gives for the Liu HBM setting `setting`."""
    text = f"""
name = "x"
model = "liu2021"
[solver]
method = "hbm"
[solver.settings]
{setting}
"""
    with pytest.raises(geardyn.StudyError) as e:
        geardyn.run_study(text)
    return str(e.value)


@pytest.mark.parametrize("setting", ["samples = 4", "samples = 100000", "full_r = 0",
                                     "full_r = 9", "max_iter = 0", "tol = 1.0"])
def test_settings_have_the_bounds_and_messages_of_the_cli(setting):
    name, value = (t.strip() for t in setting.split("="))
    with pytest.raises(geardyn.ParameterError) as e:
        geardyn.Liu2021().with_params(omega1=120.0).solve("hbm", **{name: float(value)})
    # the study's message, without the "study file: " of a file
    assert _cli_message(setting) == f"study file: {e.value}"


def test_settings_inside_the_cli_bounds_solve():
    liu = geardyn.Liu2021(readings={"base_radius": "mean"}).with_params(omega1=120.0)
    r = liu.solve("hbm", samples=256, full_r=1, output_samples=32)
    assert r["converged"] and r["tau"].shape == (32,)
    with pytest.raises(geardyn.ParameterError, match=r"output_samples` must be an integer in \[8, 65536\]"):
        liu.solve("hbm", output_samples=4)
    # time-stepping options share the study's bounds
    with pytest.raises(geardyn.ParameterError, match=r"setting `rtol` must be in"):
        liu.solve("time-stepping", options={"rtol": 1.0})


def test_yu_omega_is_a_parameter_as_in_the_cli():
    y = geardyn.Yu2021().with_params(omega=0.5)
    a = y.solve("time-stepping", transient_periods=20, record_periods=4)
    b = geardyn.Yu2021().solve("time-stepping", omega=0.5, transient_periods=20, record_periods=4)
    assert a["dynamic_factor"] == b["dynamic_factor"] >= 1.0
    res = geardyn.Yu2021().sweep("omega", [0.5, -1.0], "time-stepping", transient_periods=20,
                                 record_periods=4)
    assert isinstance(res[0], dict)
    assert isinstance(res[1], geardyn.ParameterError) and "omega" in str(res[1])
    with pytest.raises(geardyn.ParameterError, match=r"setting `transient_periods`"):
        y.solve("time-stepping", transient_periods=-1)


def test_the_integrator_stops_itself_at_the_time_limit():
    # 10^4 transient periods: far over 0.2 s; the integrator checks the deadline between steps
    # and stops, so the point fails with "time limit" and no thread is left running
    res = geardyn.Liu2021().sweep("omega1", [160.0, 170.0], "time-stepping",
                                  transient_periods=10000.0, record_periods=1.0,
                                  limits={"max_seconds_per_point": 0.2})
    assert len(res) == 2
    for r in res:
        assert isinstance(r, geardyn.SolverError), r
        assert str(r).startswith("time limit") and "abandoned" not in str(r), str(r)


def test_liu_time_stepping_takes_the_study_file_names_at_the_top_level():
    liu = geardyn.Liu2021().with_params(omega1=150.0)
    a = liu.solve("time-stepping", transient_periods=2.0, record_periods=1.0)
    b = liu.solve("time-stepping", options={"transient_periods": 2.0, "record_periods": 1.0})
    assert a["ppv"] == b["ppv"]
    with pytest.raises(geardyn.ParameterError, match="given twice"):
        liu.solve("time-stepping", transient_periods=2.0, options={"transient_periods": 3.0})
    # the CLI's bounds and message
    with pytest.raises(geardyn.ParameterError, match="transient_periods"):
        liu.solve("time-stepping", transient_periods=-1.0)


def test_time_limit_fails_the_point_not_the_sweep():
    # a nanosecond: every point ends after its deadline and fails; the sweep goes on
    res = geardyn.Liu2021().sweep("omega1", [120.0, 130.0, 140.0], "hbm",
                                  limits={"max_seconds_per_point": 1e-9})
    assert len(res) == 3
    for r in res:
        assert isinstance(r, geardyn.SolverError) and str(r).startswith("time limit"), r
    with pytest.raises(geardyn.ParameterError, match="limits.max_seconds_per_point must be in"):
        geardyn.Liu2021().solve("hbm", limits={"max_seconds_per_point": -1.0})
    # generous: the same result as without
    liu = geardyn.Liu2021().with_params(omega1=120.0)
    a = liu.solve("hbm", limits={"max_seconds_per_point": 600.0})
    b = liu.solve("hbm")
    assert a["ppv"] == b["ppv"]


def test_describe_comes_from_the_registry():
    every = geardyn.describe()
    names = [m["name"] for m in every]
    assert {"liu2021", "yu2021", "karpov2017"} <= set(names)
    liu = geardyn.Liu2021.describe()
    assert liu["name"] == "liu2021"
    params = {p["name"]: p for p in liu["info"]["parameters"]}
    assert params["omega1"]["unit"] == "rad/s"
    methods = {m["method"] for m in liu["info"]["methods"]}
    assert "time-stepping" in methods and "hbm" in methods
    with pytest.raises(geardyn.ParameterError, match="nonesuch"):
        geardyn.describe("nonesuch")
