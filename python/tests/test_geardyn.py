"""Tests of the geardyn Python package (run by .ci/run after `pip install ./python`)."""

import math
import warnings
import pathlib

import numpy as np
import pytest

import geardyn

ROOT = pathlib.Path(__file__).resolve().parents[2]


def test_presets_and_params():
    assert ("liu2021", "table1") in geardyn.presets()
    liu = geardyn.Liu2021()
    # Liu et al. 2021, Table 1
    assert liu.params["omega1"] == 160.0
    assert liu.params["z1"] == 18
    faster = liu.with_params(omega1=200.0)
    assert faster.params["omega1"] == 200.0
    assert liu.params["omega1"] == 160.0, "models are immutable"


def test_readings_by_name_and_by_field():
    printed = geardyn.Liu2021(readings="printed").params["readings"]
    consistent = geardyn.Liu2021().params["readings"]
    assert printed != consistent
    one = geardyn.Liu2021(readings={"rigid_acceleration": "printed_eq20"}).params["readings"]
    # returned in study-file spelling, whatever spelling was given (test_tables.py)
    assert one["rigid_acceleration"] == "printed-eq20"


def test_liu_hbm_below_threshold_has_no_rattle():
    # constant b̄ (R-LIU-EQ11, as the paper's figures): the paper's sparse basis cannot represent
    # the time-varying b̄ of the default reading (a documented limitation of the Rust model)
    liu = geardyn.Liu2021(readings={"base_radius": "mean"}).with_params(omega1=120.0)
    r = liu.solve("hbm")
    assert r["converged"]
    assert r["rsv"] == 0
    assert isinstance(r["q"], np.ndarray) and r["q"].shape == r["tau"].shape
    # the 512 returned samples can only miss extremes of the finer grid the ppv comes from
    sampled = r["q"].max() - r["q"].min()
    assert 0.98 * r["ppv"] <= sampled <= r["ppv"] * (1 + 1e-12)


def test_liu_hbm_matches_time_stepping():
    liu = geardyn.Liu2021().with_params(omega1=120.0)
    h = liu.solve("hbm", full_r=2)
    t = liu.solve("time-stepping", options={"transient_periods": 4.0})
    assert h["rsv"] == t["rsv"] == 0
    # same steady response: ppv within 1 % (HBM truncation, K = 2 Z2 + 2 harmonics)
    assert abs(h["ppv"] - t["ppv"]) <= 0.01 * t["ppv"]


def test_liu_long_window_statistics():
    # no rattle at 120 rad/s: every period on the drive flank, robust over all variants
    liu = geardyn.Liu2021().with_params(omega1=120.0)
    t = liu.solve("time-stepping", long_window_periods=2)
    w = t["window"]
    assert w["rsv_window"] == 0 and w["window_state_robust"] == 1.0
    assert (w["no_rattle_fraction"], w["unilateral_fraction"], w["bilateral_fraction"]) == (1.0, 0.0, 0.0)
    assert w["back_impacts_per_period"] == 0.0 and "variants" in w["spread"]
    assert liu.solve("time-stepping")["window"] is None
    with pytest.raises(geardyn.ParameterError, match="long_window_periods"):
        liu.solve("time-stepping", long_window_periods=1.5)


def test_rattle_sweep_is_ordered_and_numpy():
    omega1 = np.array([120.0, 250.0])
    s = geardyn.Liu2021().rattle_sweep(omega1)
    assert s["rsv"].dtype == float and s["rsv"].shape == (2,)
    assert s["rsv"][0] == 0
    assert s["rsv"][1] >= 1, "250 rad/s rattles (Liu Fig. 11)"


def test_karpov_and_yu_solve():
    k = geardyn.Karpov2017().with_params(tau_end=200.0).solve()
    assert k["converged"] and math.isfinite(k["amplitude"]) and k["amplitude"] > 0
    y = geardyn.Yu2021().solve("time-stepping", omega=0.5, transient_periods=20,
                               record_periods=4)
    assert y["dynamic_factor"] >= 1.0
    assert isinstance(y["dte"], np.ndarray) and y["dte"].size > 0


def test_typed_errors():
    with pytest.raises(geardyn.ParameterError, match="omega1"):
        geardyn.Liu2021().with_params(omega1=-1.0).solve("hbm")
    with pytest.raises(geardyn.ParameterError, match="omega2"):
        geardyn.Liu2021().with_params(omega2=1.0)
    with pytest.raises(geardyn.ParameterError, match="method"):
        geardyn.Liu2021().solve("collocation")
    with pytest.raises(geardyn.ParameterError, match="preset"):
        geardyn.Liu2021("table9")
    # ParameterError is also a ValueError
    with pytest.raises(ValueError):
        geardyn.Karpov2017().with_params(xi=0.5).solve()
    # a failed point of a sweep is returned as the exception, the others still solve
    res = geardyn.Liu2021().sweep("omega1", [120.0, -1.0], "hbm")
    assert isinstance(res[0], dict) and isinstance(res[1], geardyn.ParameterError)


def test_study_from_toml_string_and_file():
    text = """
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
    s = geardyn.run_study(text)
    assert s.data.shape == (4, len(s.columns))
    b = s.column(s.columns[0])
    assert np.allclose(b, [0.001, 0.004, 0.007, 0.01])
    f = geardyn.run_study_file(ROOT / "validation/examples/karpov-delta-vs-b.toml")
    assert f.data.shape[0] == 50 * 4
    with pytest.raises(geardyn.StudyError):
        geardyn.run_study("name = 'x'\nmodel = 'nope'\n[solver]\nmethod = 'hbm'\n")


def test_continuation_study_gives_branch_special_points_and_curves():
    """A [continuation] study: the Liu period-1 branch in omega1 up to the unilateral onset
    (the drive flank's grazing, 134.809 rad/s in the validation's liu2021-orbit-branch), its
    special points and the onset's codim-2 curve in (omega1, load_torque), as tables."""
    text = """
name = "c"
model = "liu2021"
[overrides]
omega1 = 130.0
base_radius = "mean"
[solver]
method = "shooting"
[solver.settings]
transient_periods = 200
[continuation]
parameter = "omega1"
to = 140.0
max_step = 2.0
stop_at = ["grazing"]
[continuation.codim2]
parameter = "load_torque"
range = [29.5, 30.5]
kinds = ["grazing"]
max_points = 2
max_curves = 1
"""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", geardyn.ReliabilityWarning)
        s = geardyn.run_study(text)
    assert s.columns[0] == "omega1" and "drive_flank_max" in s.columns
    assert s.continuation["stop"].startswith("stopped after its first grazing drive flank")
    sp = s.special_points(as_="list")
    assert [r["kind"] for r in sp] == ["grazing drive flank (max)"]
    assert abs(sp[0]["omega1"] - 134.80941) < 4.9e-4
    curves = s.curves(as_="list")
    assert {r["direction"] for r in curves} == {-1.0, 1.0}
    assert all(29.5 - 1e-9 <= r["load_torque"] <= 30.5 + 1e-9 for r in curves)
    with pytest.raises(ValueError, match="not a continuation study"):
        geardyn.run_study("name = \"k\"\nmodel = \"karpov2017-kinematics\"\n"
                          "[solver]\nmethod = \"kinematics\"\n").special_points()


def test_basin_study_gives_cells_and_fractions():
    """A [basin] study: one row per initial state with its attractor label, the attractors'
    fractions (with the failed fraction) summing to one, the grid as the study's dims."""
    text = """
name = "b"
model = "liu2021"
[overrides]
eccentricity = 0.0
[solver]
method = "time-stepping"
[solver.settings]
window_periods = 20
max_transient_periods = 0
transient_periods = 0
[basin]
q = { from = -0.002, to = 0.0, steps = 2 }
q_dot = { from = -0.001, to = 0.001, steps = 2 }
"""
    s = geardyn.run_study(text)
    assert s.columns[:2] == ["q", "q_dot"] and s.columns[-1] == "attractor"
    assert s.dims == [("q", 2), ("q_dot", 2)]
    assert np.allclose(s.column("q"), [-0.002, 0.0, -0.002, 0.0])
    rows = s.fractions(as_="list")
    total = sum(r["fraction"] for r in rows) + s.basin["failed_fraction"]
    assert abs(total - 1.0) < 1e-12
    assert sorted(set(s.column("attractor"))) == [r["attractor"] for r in rows]
    with pytest.raises(ValueError, match="basin"):
        geardyn.run_study("name = 'x'\nmodel = 'karpov2017-kinematics'\n"
                          "[solver]\nmethod = 'kinematics'\n").fractions(as_="list")


def test_liu_shooting_columns_and_errors():
    """Method "shooting": the study's columns; below the unilateral onset (134.8 rad/s in the
    validation study) the orbit keeps contact and is stable, as the time response says; above
    it the drive-flank margin is positive; bad settings name the setting."""
    liu = geardyn.Liu2021().with_params(omega1=120.0)
    r = liu.solve("shooting", transient_periods=50)
    for k in ("rsv", "q0", "dq0", "max_multiplier", "mu1_re", "mu1_im", "stable",
              "det_phi_plus_i", "gap_max_drive", "gap_max_back", "events_per_period"):
        assert k in r, k
    ts = liu.solve("time-stepping", options={"transient_periods": 50.0})
    assert r["rsv"] == ts["rsv"] == 0
    assert r["stable"] == 1.0 and r["max_multiplier"] < 1.0
    assert r["gap_max_drive"] < 0.0 and r["events_per_period"] == 0.0
    # |μ1| is the largest modulus: the same number to rounding (Python's complex abs and the
    # Rust side's modulus are two hypot implementations)
    assert math.isclose(abs(complex(r["mu1_re"], r["mu1_im"])), r["max_multiplier"],
                        rel_tol=1e-14)
    hot = geardyn.Liu2021().with_params(omega1=145.0).solve("shooting", transient_periods=50)
    assert hot["gap_max_drive"] > 0.0 and hot["rsv"] >= 1
    with pytest.raises(geardyn.ParameterError, match="segments"):
        liu.solve("shooting", segments=0)
    with pytest.raises(geardyn.ParameterError, match="nope"):
        liu.solve("shooting", nope=1)
    # the flow's pair is a setting: DOP853 finds the same orbit (Newton tolerance 1e-8)
    r8 = liu.solve("shooting", transient_periods=50, flow_method="dop853")
    assert abs(r8["q0"] - r["q0"]) < 1e-8 and abs(r8["dq0"] - r["dq0"]) < 1e-8
    assert r8["stable"] == r["stable"] and r8["rsv"] == r["rsv"]
    with pytest.raises(geardyn.ParameterError, match="flow_method"):
        liu.solve("shooting", flow_method="rk4")


def test_yu_shooting_matches_the_study_file_method():
    """Method "shooting" for Yu's 6-DOF model: the same columns and numbers as the study file's
    (stable, no contact event, |μ| = 0.9505 at ω* = 0.5, the orbit crate's value against the
    hbm period map); a 1-DOF variant has no 6-DOF orbit and says so."""
    yu = geardyn.Yu2021().with_params(omega=0.5)
    r = yu.solve("shooting", transient_periods=100)
    assert r["stable"] == 1.0 and r["events_per_period"] == 0.0
    assert abs(r["max_multiplier"] - 0.9505) < 1e-3
    with pytest.raises(geardyn.ParameterError, match="segments"):
        yu.solve("shooting", segments=0)
    with pytest.raises(geardyn.GeardynError, match="free centres"):
        yu.solve("shooting", options={"kind": "KahramanSingh"})


def test_study_lyapunov_columns_are_opt_in():
    """``lyapunov = "on"`` (time stepping, default "off") adds the Lyapunov columns of the
    settled response; for Liu's one degree of freedom the full spectrum sums to −2ζ up to the
    integrator's floor (5e-4 relative, docs/studies.md)."""
    text = """
name = "liu-lyapunov"
model = "liu2021"
[sweep]
parameter = "omega1"
values = [100.0]
[solver]
method = "time-stepping"
[solver.settings]
settle = "fixed"
record_periods = 1
transient_periods = 10
{extra}
"""
    off = geardyn.run_study(text.format(extra=""))
    assert "lambda1" not in off.columns
    on = geardyn.run_study(text.format(
        extra='lyapunov = "on"\nlyapunov_periods = 6\nlyapunov_exponents = 2'))
    for k in ("lambda1", "lambda2", "lambda1_per_period", "lambda1_spread",
              "lambda_converged", "lambda_sum", "lyapunov_events_per_period"):
        assert k in on.columns, k
    l1, l2 = on.column("lambda1")[0], on.column("lambda2")[0]
    assert l1 < 0.0 and l2 < 0.0
    assert abs(on.column("lambda_sum")[0] + 0.02) < 0.02 * 1e-3
    with pytest.raises(geardyn.StudyError):
        geardyn.run_study(text.format(extra='lyapunov = "on"\nlyapunov_periods = 2'))
    # two consecutive batches: their mean, still within the volume law; the bound named
    two = geardyn.run_study(text.format(
        extra='lyapunov = "on"\nlyapunov_periods = 6\nlyapunov_exponents = 2\nlyapunov_batches = 2'))
    assert two.column("lambda1")[0] < 0.0
    assert abs(two.column("lambda_sum")[0] + 0.02) < 0.02 * 1e-3
    assert two.column("lambda1_spread")[0] >= 0.0
    with pytest.raises(geardyn.StudyError, match="lyapunov_batches"):
        geardyn.run_study(text.format(extra='lyapunov = "on"\nlyapunov_batches = 17'))
