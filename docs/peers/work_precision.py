"""Work-precision diagram of the time stepping: final-state error against CPU time.

Cases (from `peer_bench wp`, which also runs geardyn's methods and gives the references):

* Liu 2021 (Eq. 9, Table 1, constant b, `Trig::Kernel`) at 160 and 180 rad/s, 3 periods from
  the quasi-static contact position, steps <= 0.5, gap events;
* Yu 2021 (Table 1, omega* = 0.9, 6-DOF through `timestep::Mechanical`), 10 periods from the
  model's initial state, steps <= T/4, gap events.

Methods, at rtol 1e-6 ... 1e-12 (atol = rtol * the case's scale):

* geardyn's own Dormand-Prince 5(4) (`Method::DormandPrince54`) and own DOP853
  (`Method::Dop853`), events located on their dense output;
* `ode_solvers` DOP853 (`Method::OdeSolversDop853`), rtol 1e-8 only (it takes ~100x the steps);
* Liu only (no Python right-hand side of Yu exists in the tree): the numba DP5(4) peer with
  geardyn's controller and event location (`liu_dp5_events_numba.py`, kernel trig), and scipy
  `solve_ivp` RK45 / DOP853 on a plain-Python right-hand side (libm trig), WITHOUT event
  location (scipy's events stop or record, they do not restart the step at the surface), so
  their error contains the kinks' error.

Error: max_i |y_i - y_ref,i| / max(1, |y_ref|_inf) at the end time against geardyn's DOP853 at
rtol 1e-14; `reference_spread` is that reference against geardyn's DP5 at rtol 1e-14 (the
floor of the diagram). CPU: mean on-CPU time per call (thread CPU clock on both sides), the
median over the rounds. The machine is shared: the load average is printed with the output.

    python3 -m venv /tmp/venv-wp && /tmp/venv-wp/bin/pip install numpy scipy numba matplotlib
    /tmp/venv-wp/bin/python docs/peers/work_precision.py --rounds 1

writes docs/performance/work-precision.svg and docs/performance/work-precision.md.
"""

import argparse
import json
import math
import os
import statistics
import subprocess
import sys
import time

import numpy as np
from scipy.integrate import solve_ivp

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)

import liu_dp5_events_numba  # noqa: E402

OUT = os.path.join(ROOT, "docs", "performance")
RTOLS = [10.0 ** -k for k in range(6, 13)]
LABEL = {
    "dp5": "geardyn DP5(4)",
    "dop853": "geardyn DOP853",
    "ode_solvers_dop853": "ode_solvers DOP853",
    "numba_dp5": "numba DP5(4) peer",
    "scipy_rk45": "scipy RK45 (no events)",
    "scipy_dop853": "scipy DOP853 (no events)",
}


def peer_bench():
    """The `peer_bench` example binary, built by cargo (honours CARGO_TARGET_DIR)."""
    out = subprocess.run(
        ["cargo", "build", "--release", "-p", "geardyn-models", "--example", "peer_bench",
         "--message-format=json-render-diagnostics"],
        cwd=ROOT, check=True, capture_output=True, text=True).stdout
    for line in out.splitlines():
        msg = json.loads(line)
        if msg.get("reason") == "compiler-artifact" and msg.get("executable") \
                and msg["target"]["name"] == "peer_bench":
            return msg["executable"]
    raise RuntimeError("peer_bench executable not found in cargo's output")


def cpu_per_call(f, reps, min_s=0.2):
    c0 = time.thread_time()
    w0 = time.perf_counter()
    n = 0
    while n < reps or time.perf_counter() - w0 < min_s:
        f()
        n += 1
    return (time.thread_time() - c0) / n


def state_error(y, ref):
    scale = max(1.0, max(abs(r) for r in ref))
    return max(abs(a - b) for a, b in zip(y, ref)) / scale


def scipy_rhs(model):
    """Liu Eq. (9), constant b (the reading of `peer_bench wp`), libm trig."""
    wc, we = model["omega_c"], model["omega_e"]
    ak, beta, zeta = model["ak"], model["beta"], model["zeta"]
    phm, phe = model["phase_stiffness"], model["phase_error"]
    bgap, b0, b1, b2, b3 = model["backlash"], model["b0"], model["b1"], model["b2"], model["b3"]
    scale = 1.0 + 0.5 * beta * beta

    def f(t, y):
        q, v = y
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
        return [v, forcing - 2.0 * zeta * v - stiff * dz]

    return f


def python_peers(case, reps):
    """Runs of the Python peers on a Liu case: {method: [(rtol, error, cpu_s, steps)]}."""
    model, y0, t_end, h_max = case["model"], case["y0"], case["tau_end"], case["h_max"]
    ref, scale = case["reference"], case["atol_scale"]
    out = {}
    f = liu_dp5_events_numba.make(model, True)
    rows = []
    for rtol in RTOLS:
        call = lambda: f(y0[0], y0[1], t_end, rtol, rtol * scale, h_max, 1e-12)  # noqa: E731
        r = call()
        rows.append((rtol, state_error(r[:2], ref), cpu_per_call(call, reps), r[2] + r[3]))
    out["numba_dp5"] = rows
    fun = scipy_rhs(model)
    for method in ("RK45", "DOP853"):
        rows = []
        for rtol in RTOLS:
            call = lambda: solve_ivp(fun, (0.0, t_end), y0, method=method, rtol=rtol,  # noqa: E731
                                     atol=rtol * scale, max_step=h_max)
            r = call()
            if not r.success:
                continue
            rows.append((rtol, state_error(r.y[:, -1], ref), cpu_per_call(call, 1, 0.0),
                         len(r.t) - 1))
        out[f"scipy_{method.lower()}"] = rows
    return out


def interp_time(points, err):
    """CPU time of a curve [(error, cpu)] at `err`, log-log linear between its points; None
    outside its error range."""
    pts = sorted(points)
    for (e0, c0), (e1, c1) in zip(pts, pts[1:]):
        if e0 <= err <= e1 and e0 > 0:
            if e1 == e0:
                return min(c0, c1)
            w = (math.log(err) - math.log(e0)) / (math.log(e1) - math.log(e0))
            return math.exp(math.log(c0) + w * (math.log(c1) - math.log(c0)))
    return None


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=1)
    ap.add_argument("--reps", type=int, default=3)
    args = ap.parse_args()
    load0 = os.getloadavg()
    started = time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())
    exe = peer_bench()
    # {case: {method: {rtol: [(error, cpu, steps)]}}}
    data, cases = {}, {}
    for rnd in range(args.rounds):
        doc = json.loads(subprocess.run([exe, "wp", str(args.reps)], check=True,
                                        capture_output=True, text=True).stdout)
        for case in doc["cases"]:
            cases[case["case"]] = case
            d = data.setdefault(case["case"], {})
            for r in case["runs"]:
                st = r["stats"]
                d.setdefault(r["method"], {}).setdefault(r["rtol"], []).append(
                    (r["error"], r["cpu_s"], st["n_accepted"] + st["n_rejected"]))
            if "model" in case:
                for m, rows in python_peers(case, args.reps).items():
                    for rtol, err, c, steps in rows:
                        d.setdefault(m, {}).setdefault(rtol, []).append((err, c, steps))
        print(f"round {rnd + 1}/{args.rounds} done, load {os.getloadavg()[0]:.1f}", flush=True)
    load1 = os.getloadavg()
    # medians over the rounds
    curves = {}
    for cname, d in data.items():
        for m, by_rtol in d.items():
            pts = []
            for rtol, runs in sorted(by_rtol.items(), reverse=True):
                err = statistics.median(x[0] for x in runs)
                c = statistics.median(x[1] for x in runs)
                steps = runs[0][2]
                pts.append((rtol, err, c, steps))
            curves.setdefault(cname, {})[m] = pts
    order = ["dp5", "dop853", "ode_solvers_dop853", "numba_dp5", "scipy_rk45", "scipy_dop853"]

    # ---- figure
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    names = list(curves)
    fig, axes = plt.subplots(1, len(names), figsize=(5.2 * len(names), 4.4))
    markers = {"dp5": "o-", "dop853": "s-", "ode_solvers_dop853": "x", "numba_dp5": "^--",
               "scipy_rk45": "v:", "scipy_dop853": "D:"}
    for ax, cname in zip(np.atleast_1d(axes), names):
        for m in order:
            if m not in curves[cname]:
                continue
            pts = curves[cname][m]
            ax.loglog([p[2] * 1e3 for p in pts], [max(p[1], 1e-17) for p in pts], markers[m],
                      label=LABEL[m], ms=5)
        spread = cases[cname]["reference_spread"]
        ax.axhline(max(spread, 1e-17), color="grey", lw=0.8, ls="--",
                   label="reference spread")
        ax.set_title(cases[cname]["title"])
        ax.set_xlabel("CPU time per run [ms]")
        ax.set_ylabel("final-state error (relative)")
        ax.grid(True, which="both", lw=0.3)
    np.atleast_1d(axes)[0].legend(fontsize=7)
    fig.suptitle(f"Work–precision, rtol 1e-6 … 1e-12 ({args.rounds} round(s), load "
                 f"{load0[0]:.1f} → {load1[0]:.1f} on 2 cores)", fontsize=10)
    fig.tight_layout()
    os.makedirs(OUT, exist_ok=True)
    fig.savefig(os.path.join(OUT, "work-precision.svg"))

    # ---- table
    lines = [
        "# Work–precision of the time stepping",
        "",
        "Generated by `docs/peers/work_precision.py` "
        f"(`--rounds {args.rounds} --reps {args.reps}`), {started}; "
        f"load average (1/5/15 min) {load0[0]:.1f}/{load0[1]:.1f}/{load0[2]:.1f} before, "
        f"{load1[0]:.1f}/{load1[1]:.1f}/{load1[2]:.1f} after, on a shared 2-core machine: "
        "the CPU times are on-CPU times per call (thread clock), the medians over the rounds, "
        "but cache and frequency effects of the load remain — read ratios, not absolute times.",
        "",
        "Error: max-norm of the final-state error relative to max(1, |y_ref|∞), against "
        "geardyn's DOP853 at rtol 1e-14; the reference spread is that reference against "
        "geardyn's DP5 at rtol 1e-14. scipy runs have no event location (its events do not "
        "restart the step at the surface). The own and `ode_solvers` runs locate the gap "
        "events. Figure: [work-precision.svg](work-precision.svg).",
        "",
    ]
    for cname in names:
        c = cases[cname]
        lines += [f"## {c['title']}", "",
                  f"τ_end = {c['tau_end']:.6g}, steps ≤ {c['h_max']:.4g}, "
                  f"atol = rtol × {c['atol_scale']:.3g}, reference spread "
                  f"{c['reference_spread']:.1e}.", ""]
        if c["reference_spread"] > 1e-9:
            lines += ["The reference spread is large: the end state of this case is "
                      "ill-conditioned (contact losses whose times depend sensitively on the "
                      "state), so no method's error falls much below it and the ranking by "
                      "error below ~10× the spread is noise. Compare the costs at the same "
                      "rtol for this case.", ""]
        ms = [m for m in order if m in curves[cname]]
        lines.append("| rtol | " + " | ".join(LABEL[m] + " error / ms (steps)" for m in ms)
                     + " |")
        lines.append("|---" * (len(ms) + 1) + "|")
        for rtol in RTOLS:
            row = [f"{rtol:.0e}"]
            for m in ms:
                p = [x for x in curves[cname][m] if x[0] == rtol]
                row.append(f"{p[0][1]:.1e} / {p[0][2] * 1e3:.3g} ({p[0][3]})" if p else "—")
            lines.append("| " + " | ".join(row) + " |")
        # where DOP853 wins: DP5's time at DOP853's error (log-log interpolation on DP5's curve)
        dp5 = [(p[1], p[2]) for p in curves[cname]["dp5"] if p[1] > 0]
        lines += ["", "DOP853 against DP5 at equal error (DP5's CPU time interpolated at "
                  "DOP853's error; > 1: DOP853 faster):", ""]
        wins = []
        for rtol, err, cpu, _ in curves[cname]["dop853"]:
            t = interp_time(dp5, err)
            if t is None:
                better = err < min(e for e, _ in dp5)
                note = ("below DP5's smallest error (" + (
                    "DOP853 faster than DP5's most accurate run"
                    if cpu < min(c for e, c in dp5 if e == min(e for e, _ in dp5)) else
                    "DOP853 slower than DP5's most accurate run") + ")") if better \
                    else "above DP5's largest error"
                lines.append(f"- rtol {rtol:.0e}: error {err:.1e}, {note}")
                if better and "faster" in note:
                    wins.append(rtol)
            else:
                lines.append(f"- rtol {rtol:.0e}: error {err:.1e}, DP5/DOP853 = {t / cpu:.2f}")
                if t > cpu:
                    wins.append(rtol)
        lines += ["", "DOP853 wins at rtol (equal error): "
                  + (", ".join(f"{r:.0e}" for r in wins) or "none"), ""]
        same = []
        for (r5, _, c5, _), (r8, _, c8, _) in zip(curves[cname]["dp5"], curves[cname]["dop853"]):
            same.append(f"{r5:.0e}: {c5 / c8:.2f}")
        lines += ["DP5/DOP853 CPU at the same rtol (> 1: DOP853 cheaper): " + ", ".join(same)
                  + ".", ""]
    with open(os.path.join(OUT, "work-precision.json"), "w") as fh:
        json.dump({"cases": {k: {kk: vv for kk, vv in v.items() if kk != "runs"}
                             for k, v in cases.items()}, "curves": curves}, fh)
    with open(os.path.join(OUT, "work-precision.md"), "w") as fh:
        fh.write("\n".join(lines))
    print("\n".join(lines))


if __name__ == "__main__":
    main()
