"""Property-based tests of the Python API (hypothesis; run by .ci/run after pytest with a
fixed example budget and a fixed seed).

Any value of any parameter, setting, limit or sweep array — NaN, inf, huge, negative, wrong
type, wrong shape — gives a result or one of the documented exceptions: ``GeardynError``
(``ParameterError``, ``SolverError``, ``StudyError``), ``ValueError`` or ``TypeError``. The
interpreter never aborts or hangs: every solve runs under ``max_seconds_per_point``, and
sizes are refused by ``max_points`` before anything is allocated.
"""

import math

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import geardyn

# The fixed budget: examples per test, no per-example deadline (timing is not asserted),
# derandomized so that CI runs the same cases every time.
settings.register_profile(
    "ci", max_examples=100, deadline=None, derandomize=True, print_blob=True,
    suppress_health_check=[HealthCheck.too_slow],
)
settings.load_profile("ci")

DOCUMENTED = (geardyn.GeardynError, ValueError, TypeError)
LIMITS = {"max_seconds_per_point": 5.0}

HOSTILE_FLOATS = st.sampled_from([
    0.0, -0.0, -1.0, -3.0, 1e-300, 1e-12, 1e17, 1e300, -1e308, 2.0**52, 2.0**63,
    float(2**32 - 1), math.nan, math.inf, -math.inf, 5e-324,
])
VALUES = st.one_of(
    HOSTILE_FLOATS,
    st.floats(allow_nan=True, allow_infinity=True),
    st.integers(min_value=-(2**70), max_value=2**70),
    st.booleans(),
    st.none(),
    st.text(max_size=8),
    st.lists(st.floats(allow_nan=True), max_size=3),
    st.dictionaries(st.text(max_size=4), st.floats(), max_size=2),
)

# (model class, parameter names, a fast method with settings)
MODELS = [
    (geardyn.Liu2021, sorted(geardyn.Liu2021().params), ("hbm", {})),
    (geardyn.Karpov2017, sorted(geardyn.Karpov2017().params), ("duhamel", {})),
    (geardyn.Yu2021, sorted(geardyn.Yu2021().params) + ["omega"],
     ("time-stepping", {"omega": 0.5, "transient_periods": 2, "record_periods": 1})),
]


def _outcome(call):
    try:
        return call()
    except DOCUMENTED as e:
        return e


@given(model=st.sampled_from(MODELS), data=st.data(), value=VALUES)
def test_any_parameter_value_gives_a_result_or_a_documented_error(model, data, value):
    cls, names, (method, base) = model
    name = data.draw(st.one_of(st.sampled_from(names), st.text(max_size=6)))
    def call():
        m = cls().with_params(**{name: value})
        settings = dict(base)
        if name == "omega":
            settings.pop("omega", None)
        return m.solve(method, limits=LIMITS, **settings)
    r = _outcome(call)
    assert isinstance(r, (dict, *DOCUMENTED)), r


LIU_SETTINGS = ["tol", "max_iter", "samples", "full_r", "warm_start", "output_samples",
                "options", "flow_method", "nope"]


@given(name=st.sampled_from(LIU_SETTINGS), value=VALUES,
       method=st.sampled_from(["hbm", "time-stepping", "shooting", ""]))
def test_any_setting_value_gives_a_result_or_a_documented_error(name, value, method):
    liu = geardyn.Liu2021().with_params(omega1=120.0)
    if method == "time-stepping":
        settings = {"options": {"transient_periods": 0.5, name: value}}
    else:
        settings = {name: value}
    r = _outcome(lambda: liu.solve(method or None, limits=LIMITS, **settings))
    assert isinstance(r, (dict, *DOCUMENTED)), r


SHAPES = st.one_of(st.just(()), st.lists(st.integers(0, 3), min_size=1, max_size=3).map(tuple))


@given(shape=SHAPES, data=st.data())
def test_any_sweep_array_keeps_its_shape_or_is_refused(shape, data):
    n = int(np.prod(shape, dtype=np.int64)) if shape else 1
    flat = data.draw(st.lists(st.one_of(HOSTILE_FLOATS, st.floats(100.0, 300.0)),
                              min_size=n, max_size=n))
    omega1 = np.array(flat, dtype=float).reshape(shape)
    r = _outcome(lambda: geardyn.Liu2021().rattle_sweep(omega1, method="hbm", limits=LIMITS))
    assert not isinstance(r, Exception), r
    for k in ("omega1", "rsv", "ppv", "reason"):
        assert r[k].shape == shape, (k, r[k].shape, shape)
    for rsv, reason in zip(r["rsv"].ravel(), r["reason"].ravel()):
        # a NaN row always says why
        assert (reason is None) == (not math.isnan(rsv)), (rsv, reason)


@given(values=st.one_of(
    st.lists(st.one_of(VALUES, st.lists(st.floats(), max_size=2)), max_size=4),
    st.text(max_size=4), st.none(), VALUES,
))
def test_any_sweep_values_object_gives_a_result_or_a_documented_error(values):
    r = _outcome(lambda: geardyn.Liu2021().sweep("omega1", values, "hbm", limits=LIMITS))
    if isinstance(r, list):
        for point in r:
            assert isinstance(point, (dict, geardyn.GeardynError)), point
    else:
        assert isinstance(r, DOCUMENTED), r


@given(n=st.one_of(st.integers(0, 3), st.integers(10**4 + 1, 10**18)),
       max_points=st.integers(1, 3))
def test_sizes_over_the_limit_are_refused_before_allocation(n, max_points):
    # a virtual array: any length, no memory behind it
    values = np.broadcast_to(np.float64(120.0), (n,))
    r = _outcome(lambda: geardyn.Liu2021().sweep("omega1", values, "hbm",
                                                 limits={"max_points": max_points, **LIMITS}))
    if n > max_points:
        assert isinstance(r, geardyn.ParameterError) and "limits.max_points" in str(r), r
    else:
        assert isinstance(r, list) and len(r) == n


@given(limits=st.dictionaries(
    st.sampled_from(["max_points", "max_steps", "max_seconds_per_point", "other"]),
    VALUES, max_size=3))
def test_any_limits_give_a_result_or_a_documented_error(limits):
    r = _outcome(lambda: geardyn.Liu2021().with_params(omega1=120.0).solve(
        "hbm", limits={**limits, "max_seconds_per_point": 5.0}
        if "max_seconds_per_point" not in limits else limits))
    assert isinstance(r, (dict, *DOCUMENTED)), r
