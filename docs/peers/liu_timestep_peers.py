"""NAIVE peers of the Liu time stepping at 160 rad/s (issue 13), measured in one session.

None of them is geardyn's algorithm: scipy RK45 (interpreted), a numba DP5(4) loop WITHOUT
event location (20x less accurate at the impacts; it was called a "bare DP5 loop") and a
fixed-step RK4. The same-algorithm peer (events, stage-time cache, both trig forms, geardyn's
step counts bit for bit) is `liu_dp5_events_numba.py` (issue 26).

Problem: Liu et al. 2021 Eq. (9), Table 1 at omega1 = 160 rad/s, constant-b reading
(`BaseRadius::Mean`, the reading of the benches and of the paper's figures), three periods
T = 2 pi / omega_c from the quasi-static contact position at rest, rtol 1e-8,
atol 1e-11 * max(b, B0), steps <= 0.5.

The dimensionless model is not re-derived here: the Rust example `liu_timestep_rate` writes
the `liu2021::Model` it integrates (serde JSON, every coefficient of Eq. 9 and 22), the
settings and its own results and timings; this script reads them and integrates the same
right-hand side with

* scipy `solve_ivp(method="RK45")` at the same rtol/atol/max_step (no event location);
* a numba-jitted Dormand-Prince 5(4) with the same PI step control (Hairer's DOPRI5 constants,
  as `timestep`), no event location, libm trig five times per right-hand side (naive: not
  geardyn's algorithm, see above);
* a numba-jitted classical RK4 at a fixed step chosen for the accuracy of ours.

Run (from the repository root):

    python3 -m venv target/peervenv && target/peervenv/bin/pip install numpy scipy numba
    target/peervenv/bin/python docs/peers/liu_timestep_peers.py

It builds and runs the Rust example first (`cargo run --release -p geardyn-models --example
liu_timestep_rate -- 10 --json target/liu_peer_input.json`), so all figures come from one
session; `uptime` is printed next to each measurement.
"""

import json
import math
import os
import subprocess
import sys
import time

import numba
import numpy as np
import scipy
from scipy.integrate import solve_ivp

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
INPUT = os.path.join(ROOT, "target", "liu_peer_input.json")


def load():
    """`uptime` load average (1 min)."""
    return os.getloadavg()[0]


def run_ours():
    cmd = [
        "cargo", "run", "--quiet", "--release", "-p", "geardyn-models", "--example",
        "liu_timestep_rate", "--", "10", "--json", INPUT,
    ]
    print(f"[load {load():.2f}] {' '.join(cmd)}")
    out = subprocess.run(cmd, cwd=ROOT, check=True, capture_output=True, text=True).stdout
    print(out)
    after = load()
    print(f"[load {after:.2f}] after the Rust runs")
    with open(INPUT) as f:
        doc = json.load(f)
    doc["load"] = after
    return doc


def main():
    doc = run_ours()
    case = doc["models"]["mean"]
    m = case["model"]
    rd = m["readings"]
    # the reading this script implements (Eq. 9 with Eq. 22, constant b, derived error term,
    # two-term rigid acceleration)
    assert rd == {"base_radius": "mean", "error_term": "derived",
                  "rigid_acceleration": "Derived", "rigid_series": "two_terms"}, rd
    wc, we = m["omega_c"], m["omega_e"]
    ak, beta, zeta = m["ak"], m["beta"], m["zeta"]
    phm, phe = m["phase_stiffness"], m["phase_error"]
    bgap, b0, b1, b2, b3 = m["backlash"], m["b0"], m["b1"], m["b2"], m["b3"]
    scale = 1.0 + 0.5 * beta * beta
    y0 = np.array(case["y0"])
    t_end, rtol, atol, h_max = case["tau_end"], case["rtol"], case["atol"], case["h_max"]

    @numba.njit(cache=False, fastmath=False)
    def accel(t, q, v):
        x = wc * t
        r = 1.0 + beta * math.cos(x)
        stiff = (1.0 + ak * math.sin(we * t + phm)) * r * r / scale
        forcing = -b0 - (b1 * math.sin(x) + b2 * math.sin(2.0 * x)) - b3 * math.sin(we * t + phe)
        if q > bgap:
            dz = q - bgap
        elif q < -bgap:
            dz = q + bgap
        else:
            dz = 0.0
        return forcing - 2.0 * zeta * v - stiff * dz

    def f_py(t, y):
        return [y[1], accel(t, y[0], y[1])]

    ours = {(r["system"], r["events"]): r for r in doc["runs"] if r["reading"] == "mean"}
    lean_ev = ours[("TimeSystem", True)]
    lean_no = ours[("TimeSystem", False)]

    # ---- numba DP5 with the timestep crate's controller (no events)
    @numba.njit(cache=False)
    def dp5(y0, t_end, rtol, atol, h_max, h0, t_rec):
        a21 = 1 / 5
        a31, a32 = 3 / 40, 9 / 40
        a41, a42, a43 = 44 / 45, -56 / 15, 32 / 9
        a51, a52, a53, a54 = 19372 / 6561, -25360 / 2187, 64448 / 6561, -212 / 729
        a61, a62, a63, a64, a65 = 9017 / 3168, -355 / 33, 46732 / 5247, 49 / 176, -5103 / 18656
        b1_, b3_, b4_, b5_, b6_ = 35 / 384, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84
        e1, e3, e4, e5, e6, e7 = (71 / 57600, -71 / 16695, 71 / 1920, -17253 / 339200,
                                  22 / 525, -1 / 40)
        c2, c3, c4, c5 = 1 / 5, 3 / 10, 4 / 5, 8 / 9
        beta_, expo1, safe, facc1, facc2 = 0.04, 0.2 - 0.75 * 0.04, 0.9, 5.0, 0.1
        facold = 1e-4
        q, v = y0[0], y0[1]
        t = 0.0
        h = min(h0, h_max)
        k1q, k1v = v, accel(t, q, v)
        nfev, nacc, nrej = 1, 0, 0
        last_rej = False
        qmin, qmax = 1e300, -1e300
        while t < t_end:
            last = False
            if t + 1.01 * h >= t_end:
                h = t_end - t
                last = True
            yq = q + h * a21 * k1q
            yv = v + h * a21 * k1v
            k2q, k2v = yv, accel(t + c2 * h, yq, yv)
            yq = q + h * (a31 * k1q + a32 * k2q)
            yv = v + h * (a31 * k1v + a32 * k2v)
            k3q, k3v = yv, accel(t + c3 * h, yq, yv)
            yq = q + h * (a41 * k1q + a42 * k2q + a43 * k3q)
            yv = v + h * (a41 * k1v + a42 * k2v + a43 * k3v)
            k4q, k4v = yv, accel(t + c4 * h, yq, yv)
            yq = q + h * (a51 * k1q + a52 * k2q + a53 * k3q + a54 * k4q)
            yv = v + h * (a51 * k1v + a52 * k2v + a53 * k3v + a54 * k4v)
            k5q, k5v = yv, accel(t + c5 * h, yq, yv)
            yq = q + h * (a61 * k1q + a62 * k2q + a63 * k3q + a64 * k4q + a65 * k5q)
            yv = v + h * (a61 * k1v + a62 * k2v + a63 * k3v + a64 * k4v + a65 * k5v)
            k6q, k6v = yv, accel(t + h, yq, yv)
            nq = q + h * (b1_ * k1q + b3_ * k3q + b4_ * k4q + b5_ * k5q + b6_ * k6q)
            nv = v + h * (b1_ * k1v + b3_ * k3v + b4_ * k4v + b5_ * k5v + b6_ * k6v)
            k7q, k7v = nv, accel(t + h, nq, nv)
            nfev += 6
            eq = h * (e1 * k1q + e3 * k3q + e4 * k4q + e5 * k5q + e6 * k6q + e7 * k7q)
            ev = h * (e1 * k1v + e3 * k3v + e4 * k4v + e5 * k5v + e6 * k6v + e7 * k7v)
            sq = atol + rtol * max(abs(q), abs(nq))
            sv = atol + rtol * max(abs(v), abs(nv))
            err = math.sqrt(((eq / sq) ** 2 + (ev / sv) ** 2) / 2.0)
            fac11 = err ** expo1
            if err > 1.0:
                h /= min(facc1, fac11 / safe)
                nrej += 1
                last_rej = True
                continue
            fac = max(facc2, min(facc1, fac11 / facold ** beta_ / safe))
            h_new = h / fac
            facold = max(err, 1e-4)
            if last_rej:
                h_new = min(h_new, h)
            last_rej = False
            nacc += 1
            q, v = nq, nv
            k1q, k1v = k7q, k7v
            t = t_end if last else t + h
            if t >= t_rec:
                qmin = min(qmin, q)
                qmax = max(qmax, q)
            h = min(h_new, h_max)
        return q, v, nacc, nrej, nfev, qmin, qmax

    # ---- numba RK4, fixed step (no events)
    @numba.njit(cache=False)
    def rk4(y0, t_end, h):
        n = int(math.ceil(t_end / h))
        h = t_end / n
        q, v = y0[0], y0[1]
        t = 0.0
        for i in range(n):
            k1q, k1v = v, accel(t, q, v)
            k2q, k2v = v + 0.5 * h * k1v, accel(t + 0.5 * h, q + 0.5 * h * k1q, v + 0.5 * h * k1v)
            k3q, k3v = v + 0.5 * h * k2v, accel(t + 0.5 * h, q + 0.5 * h * k2q, v + 0.5 * h * k2v)
            k4q, k4v = v + h * k3v, accel(t + h, q + h * k3q, v + h * k3v)
            q += h / 6.0 * (k1q + 2.0 * k2q + 2.0 * k3q + k4q)
            v += h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v)
            t = (i + 1) * h
        return q, v, n

    def best_of(fn, reps):
        """(best wall, mean on-CPU) seconds, and the result."""
        best = math.inf
        c0 = time.thread_time()
        for _ in range(reps):
            t0 = time.perf_counter()
            out = fn()
            best = min(best, time.perf_counter() - t0)
        return (best, (time.thread_time() - c0) / reps), out

    t_rec = case["integrate"]["tau_first"]
    dp5(y0, 1.0, rtol, atol, h_max, 1e-3, 0.5)  # compile
    rk4(y0, 1.0, 0.1)
    # the accuracy of every run: |q - q_ref| at tau_end against the ppv, with q_ref from our
    # events-on run at rtol 1e-12
    yref = np.array(case["reference_rtol_1e-12"])
    ours_ppv = case["integrate"]["ppv"]

    def err_of(y):
        return float(abs(y[0] - yref[0]) / ours_ppv)

    rows = []

    def row(name, settings, times, acc, rej, nfev, y, ld):
        wall, cpu = times
        rows.append((name, settings, wall, cpu, acc, rej, nfev, err_of(y), ld))

    for r, name in ((lean_ev, "geardyn TimeSystem, events on"),
                    (lean_no, "geardyn TimeSystem, events off"),
                    (ours[("Mechanical", True)], "geardyn FirstOrder(Mechanical), events on")):
        st = r["stats"]
        row(name, "DP5(4), rtol 1e-8", (r["wall_s"], r["on_cpu_s"]), st["n_accepted"],
            st["n_rejected"], st["n_rhs"], r["y_final"], doc["load"])

    ld = load()
    times, res = best_of(lambda: dp5(y0, t_end, rtol, atol, h_max, 1e-3, t_rec), 5)
    row("naive numba DP5 (no events)", "DP5(4), rtol 1e-8, no events", times, res[2], res[3],
        res[4], res[:2], ld)
    dp5_ppv = res[6] - res[5]

    # RK4 at the largest step (of a halving ladder) as accurate as our events-on run
    target = err_of(lean_ev["y_final"])
    h = 0.4
    while True:
        out = rk4(y0, t_end, h)
        if err_of(out[:2]) <= target or h < 1e-3:
            break
        h /= 2.0
    ld = load()
    times, out = best_of(lambda: rk4(y0, t_end, h), 3)
    row("numba RK4, fixed step", f"h = {t_end / out[2]:.4g} (accuracy of ours)", times, out[2],
        0, 4 * out[2], out[:2], ld)

    ld = load()
    t_eval = np.arange(t_rec, t_end, case["integrate"]["options"]["sample_step"])
    times, sol = best_of(lambda: solve_ivp(f_py, (0.0, t_end), y0, method="RK45", rtol=rtol,
                                          atol=atol, max_step=h_max, t_eval=t_eval), 2)
    # solve_ivp does not report accepted steps: one more run storing every step (6 calls per
    # attempted step after the 2 of the initial step size)
    steps = solve_ivp(f_py, (0.0, t_end), y0, method="RK45", rtol=rtol, atol=atol,
                      max_step=h_max)
    acc = len(steps.t) - 1
    rej = max(0, round((steps.nfev - 2) / 6) - acc)
    row("scipy solve_ivp RK45", "rtol 1e-8, no events", times, acc, rej, sol.nfev,
        steps.y[:, -1], ld)
    scipy_ppv = float(sol.y[0].max() - sol.y[0].min())

    print(f"numpy {np.__version__}, scipy {scipy.__version__}, numba {numba.__version__}, "
          f"python {sys.version.split()[0]}")
    print(f"reference: geardyn events on, rtol 1e-12: y_final {yref.tolist()}")
    print()
    print("| run | settings | accepted / rejected | rhs | wall (best) | on-CPU | M steps/s wall "
          "/ on-CPU | \\|q − q_ref\\|/ppv at τ_end | load |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    for (name, settings, wall, cpu, acc, rej, nfev, err, ld) in rows:
        print(f"| {name} | {settings} | {acc} / {rej} | {nfev} | {wall * 1e3:.2f} ms | "
              f"{cpu * 1e3:.2f} ms | {acc / wall / 1e6:.3f} / {acc / cpu / 1e6:.3f} | {err:.1e} | "
              f"{ld:.2f} |")
    print()
    print(f"ppv of the recorded period: ours {ours_ppv:.10e} (liu2021::integrate), scipy "
          f"{scipy_ppv:.10e} (same samples, rel. diff {abs(scipy_ppv - ours_ppv) / ours_ppv:.1e}),"
          f" numba DP5 step ends {dp5_ppv:.10e} (rel. diff "
          f"{abs(dp5_ppv - ours_ppv) / ours_ppv:.1e}; step ends, not samples)")


if __name__ == "__main__":
    main()
