"""geardyn against its same-algorithm peers (issue 26), alternating runs over several rounds.

    python3 -m venv /tmp/venv-perf && /tmp/venv-perf/bin/pip install numpy scipy numba
    /tmp/venv-perf/bin/python docs/peers/compare.py [--rounds 5] [--sections karpov,liu,hbm,sweep]
                                                     [--write docs/performance.md]

geardyn's side is `cargo run --release -p geardyn-models --example peer_bench -- <section>`
(built once here; one process per round; on-CPU time per call over ≥ 0.2 s of calls); the peers are
`karpov_fold_numba.py`, `liu_dp5_events_numba.py` and `hbm_peers.py` in this directory, run in
this process after one untimed warm-up (numba compilation, the Karpov resolution search).
Each round runs geardyn then the peers (odd rounds) or the peers then geardyn (even rounds), and
the ratio peer time / geardyn time is taken within the round, so that the load of a shared
machine cancels as far as it can. Printed: per case the median and the range of the ratios,
the accuracy of each side and the times. The `sweep` section times the `geardyn` CLI
(`cargo build --release -p geardyn-cli`, one process per run, RUSAGE_CHILDREN CPU time) against
the per-point fixed-step loop of `peer_bench sweep`. With `--write`, the table replaces the text between
`<!-- peer-table:begin -->` and `<!-- peer-table:end -->` of the given file.
"""

import os

# Every peer single-threaded, as geardyn's solves: a multithreaded BLAS (numpy's LAPACK solve of
# the dense Newton) would do part of its work on threads that the calling thread's CPU clock
# (`time.thread_time`, below) does not count. Set before numpy is imported.
for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse
import csv
import json
import math
import os
import platform
import resource
import statistics
import subprocess
import sys
import tempfile
import time

import numba
import numpy as np
import scipy

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)

import hbm_peers  # noqa: E402
import karpov_fold_numba  # noqa: E402
import liu_dp5_events_numba  # noqa: E402

CMD = "cargo run --release -p geardyn-models --example peer_bench -- {}"


def target_dir():
    """cargo's target directory (honours CARGO_TARGET_DIR and .cargo/config.toml)."""
    out = subprocess.run(["cargo", "metadata", "--format-version", "1", "--no-deps"], cwd=ROOT,
                         check=True, capture_output=True, text=True).stdout
    return json.loads(out)["target_directory"]


def build(args, name):
    """`cargo build --release ARGS` and the path of the executable NAME it produced, as cargo
    reports it (so that CARGO_TARGET_DIR or a configured target-dir is followed)."""
    out = subprocess.run(["cargo", "build", "--quiet", "--release", "--message-format=json"]
                         + args, cwd=ROOT, check=True, capture_output=True, text=True).stdout
    for line in out.splitlines():
        msg = json.loads(line)
        if (msg.get("reason") == "compiler-artifact" and msg.get("executable")
                and msg["target"]["name"] == name):
            return msg["executable"]
    raise SystemExit(f"cargo build {' '.join(args)} produced no executable {name}")


EXE = ".exe" if os.name == "nt" else ""
# filled by main(): from cargo's build output, or (with --no-build) from cargo's target directory
BIN = None


def geardyn(section, reps):
    out = subprocess.run([BIN, section, str(reps)], check=True, capture_output=True,
                         text=True).stdout
    return json.loads(out)


def best_of(f, reps):
    """Mean on-CPU seconds per call over at least `reps` calls and 0.2 s (the thread's CPU
    clock: a loaded machine's run queue inflates wall times), as `peer_bench` measures."""
    c0 = time.thread_time()
    w0 = time.perf_counter()
    n = 0
    while n < reps or time.perf_counter() - w0 < 0.2:
        f()
        n += 1
    return (time.thread_time() - c0) / n


def cpu(d):
    """geardyn's on-CPU time per call (`cpu_s`), its wall time where that is missing."""
    c = d.get("cpu_s")
    return c if c is not None and c == c else d["time_s"]


def spread(xs):
    return statistics.median(xs), min(xs), max(xs)


def fmt_ratio(xs):
    med, lo, hi = spread(xs)
    return f"{med:.2f}× ({lo:.2f}–{hi:.2f})"


# ---------------------------------------------------------------- sections


def karpov_section(rounds):
    doc = geardyn("karpov", 5)
    peers = {}
    for case in doc["cases"]:
        key = f"{case['reading']} B = {case['params']['b']}"
        theta, err, nodes = karpov_fold_numba.resolve(case)
        peers[key] = (case, theta, err, nodes)
    ratios = {k: [] for k in peers}
    ours = {k: [] for k in peers}
    theirs = {k: [] for k in peers}
    for r in range(rounds):
        order = ("g", "p") if r % 2 == 0 else ("p", "g")
        for side in order:
            if side == "g":
                d = geardyn("karpov", 5)
                for case in d["cases"]:
                    ours[f"{case['reading']} B = {case['params']['b']}"].append(cpu(case))
            else:
                for k, (case, theta, _, _) in peers.items():
                    theirs[k].append(best_of(lambda: karpov_fold_numba.run(case, theta), 5))
        for k in peers:
            ratios[k].append(theirs[k][-1] / ours[k][-1])
        print(f"karpov round {r + 1}: " + ", ".join(f"{k} {ratios[k][-1]:.2f}" for k in peers))
    rows = []
    for k, (case, theta, err, nodes) in peers.items():
        rows.append({
            "goal": "Karpov `duhamel()` ≥ 1.5× the period-folding peer",
            "case": f"Fig. 3 data, {k}, τ_end = 10⁵",
            "peer": f"numba period folding, GL-10 panels of θ = {theta:.3g} rad (searched), "
                    f"{nodes} nodes (`karpov_fold_numba.py`)",
            "ours_acc": f"‖(X, X′) − ref‖ = {case['error']:.1e} ({case['panels'] * 10} nodes)",
            "peer_acc": f"{err:.1e}",
            "ours_t": statistics.median(ours[k]), "peer_t": statistics.median(theirs[k]),
            "ratio": ratios[k], "target": 1.5, "cmd": CMD.format("karpov"),
        })
    return rows


def liu_section(rounds):
    doc = geardyn("liu", 10)
    calls = {}
    for run in doc["runs"]:
        # the peer evaluates the time functions per stage; geardyn's default table path is
        # measured against the peer's kernel path (the faster of the peer's two)
        f, call = liu_dp5_events_numba.run_case(doc, run["trig"] != "libm")
        out = call()
        calls[run["trig"]] = (call, out)
    ratios = {k: [] for k in calls}
    fixed = {k: [] for k in calls}
    ours = {k: [] for k in calls}
    theirs = {k: [] for k in calls}
    last = doc
    for r in range(rounds):
        order = ("g", "p") if r % 2 == 0 else ("p", "g")
        for side in order:
            if side == "g":
                last = geardyn("liu", 10)
                for run in last["runs"]:
                    ours[run["trig"]].append(cpu(run))
                    fixed[run["trig"]].append(run["fixed_step_loop_cpu_s"] / cpu(run))
            else:
                for k, (call, _) in calls.items():
                    theirs[k].append(best_of(call, 10))
        for k in calls:
            ratios[k].append(theirs[k][-1] / ours[k][-1])
        print(f"liu round {r + 1}: " + ", ".join(
            f"{k} {ratios[k][-1]:.2f} (fixed-step fraction {fixed[k][-1]:.2f})" for k in calls))
    rows = []
    ref = last["reference"]
    for run in last["runs"]:
        k = run["trig"]
        _, out = calls[k]
        st = run["stats"]
        same = (out[2], out[3], out[5]) == (st["n_accepted"], st["n_rejected"], st["n_events"])
        goal = {
            "table": "time stepping ≥ 1.0× the same-algorithm DP5 (issue 38), the default trig path",
            "kernel": "time stepping ≥ 1.0× the same-algorithm DP5 (issue 38; issue 26 asked 1.3×)",
            "libm": "time stepping ≥ 1.0× the same-algorithm DP5 (issue 38), the libm path",
        }.get(k, "time stepping ≥ 1.0× the same-algorithm DP5 (issue 38)")
        rows.append({
            "goal": goal,
            "case": f"Liu 160 rad/s, 3 periods, rtol 1e-8, events on, `Trig::{k.capitalize()}`",
            "peer": f"numba DP5(4), geardyn's controller, event location, stage-time cache, "
                    f"{'kernel' if k == 'table' else k} trig (`liu_dp5_events_numba.py`)"
                    + ("; geardyn reads its tabulated time functions" if k == "table" else "")
                    + f"; steps {out[2]} + {out[3]} rejected"
                    + (" = geardyn's" if same else f" (geardyn {st['n_accepted']} + "
                       f"{st['n_rejected']})"),
            "ours_acc": f"\\|q − q_ref\\| = {run['error_q']:.1e} ({st['n_accepted']} steps)",
            "peer_acc": f"\\|q − q_ref\\| = {abs(out[0] - ref[0]):.1e}",
            "ours_t": statistics.median(ours[k]), "peer_t": statistics.median(theirs[k]),
            "ratio": ratios[k], "target": 1.0,
            "cmd": CMD.format("liu"),
        })
        rows.append({
            "goal": "time stepping ≥ 90 % of the fixed-step DP5 loop (issue 38)",
            "case": f"same run, `Trig::{k.capitalize()}`",
            "peer": "fixed-step DP5 loop in Rust on the same right-hand side, as many steps "
                    "(accepted + rejected), no control, no events (`peer_bench`)",
            "ours_acc": "—", "peer_acc": "—",
            "ours_t": statistics.median(ours[k]), "peer_t": None,
            "ratio": fixed[k], "target": 0.9, "cmd": CMD.format("liu"),
        })
    return rows


def hbm_section(rounds):
    doc = geardyn("hbm", 5)
    peers = hbm_peers.solve_all(doc)
    acc = {}
    for name, (solve, p, ref) in peers.items():
        p.residuals = 0
        z, it = solve()
        acc[name] = (float(np.linalg.norm(p.residual(z))), float(np.abs(z - ref).max()), it,
                     p.residuals - 1)
    ours_key = {
        "liu_dense_newton": lambda d: (cpu(d["liu"]), d["liu"]["residual_norm"]),
        "duffing_h400_newton_krylov": lambda d: (cpu(d["duffing"]["runs"][0]),
                                                 d["duffing"]["runs"][0]["residual_norm"]),
        "duffing_h400_dense_newton": lambda d: (cpu(d["duffing"]["runs"][1]),
                                                d["duffing"]["runs"][1]["residual_norm"]),
    }
    ratios = {k: [] for k in peers}
    ours = {k: [] for k in peers}
    theirs = {k: [] for k in peers}
    liu_floor = []
    prepared = []
    last = doc
    for r in range(rounds):
        order = ("g", "p") if r % 2 == 0 else ("p", "g")
        for side in order:
            if side == "g":
                last = geardyn("hbm", 5)
                liu_floor.append(last["liu"]["fft_floor_s"])
                if "prepared_cpu_s" in last["liu"]:
                    prepared.append(last["liu"]["prepared_cpu_s"])
                for k in peers:
                    ours[k].append(ours_key[k](last)[0])
            else:
                for k, (solve, _, _) in peers.items():
                    theirs[k].append(best_of(solve, 2 if "dense" in k and "duffing" in k
                                             else 10))
        for k in peers:
            ratios[k].append(theirs[k][-1] / ours[k][-1])
        print(f"hbm round {r + 1}: " + ", ".join(f"{k} {ratios[k][-1]:.2f}" for k in peers))
    nk = last["duffing"]["runs"][0]
    labels = {
        "liu_dense_newton": ("HBM Liu cold solve (15 unknowns, 1024-point AFT)",
                             "numpy dense Newton, exact AFT Jacobian, LAPACK solve"),
        "duffing_h400_newton_krylov": (
            f"HBM Duffing H = 400 (801 unknowns), geardyn `NewtonKrylov` (banded "
            f"preconditioner: {nk['residuals']} residuals + {nk['jacobian_products']} J·v in "
            f"{nk['iterations']} Newton iterations)",
            "scipy `newton_krylov` (GMRES) + harmonic-block preconditioner"),
        "duffing_h400_dense_newton": ("HBM Duffing H = 400, geardyn dense `Newton` (blocked LU, `DenseLu::Auto` from 300 unknowns)",
                                      "numpy dense Newton, exact AFT Jacobian, LAPACK solve"),
    }
    rows = []
    floors = [o / f for o, f in zip(ours["liu_dense_newton"], liu_floor)]
    rows.append({
        "goal": "HBM cold Liu solve within 1.5× of its FFT floor",
        "case": "Liu 160 rad/s, paper basis, cold start, incl. metrics",
        "peer": f"floor: the FFTs of the solve alone ({last['liu']['fft_floor_counts']}), "
                f"rustfft/realfft in `peer_bench`",
        "ours_acc": "—", "peer_acc": "—",
        "ours_t": statistics.median(ours["liu_dense_newton"]),
        "peer_t": statistics.median(liu_floor),
        "ratio": floors, "target": None, "cmd": CMD.format("hbm"),
        "note": "ratio = geardyn / floor (goal ≤ 1.5)",
    })
    if prepared:
        rows.append({
            "goal": "HBM Liu solve along a sweep (tabulation reused) within 1.5× of its FFT floor",
            "case": "Liu 160/161 rad/s alternating, paper basis, cold start, incl. metrics, one "
                    "prepared problem (`liu2021::PreparedHbm`)",
            "peer": "floor: as above",
            "ours_acc": "— (bit-identical to the cold solve)", "peer_acc": "—",
            "ours_t": statistics.median(prepared),
            "peer_t": statistics.median(liu_floor),
            "ratio": [o / f for o, f in zip(prepared, liu_floor)], "target": None,
            "cmd": CMD.format("hbm"),
            "note": "ratio = geardyn / floor (goal ≤ 1.5)",
        })
    for k in peers:
        res, dz, it, nres = acc[k]
        goal, peer = labels[k]
        rows.append({
            "goal": goal, "case": "from the cold start" if k.startswith("liu") else
            "from the embedded H = 1 solution",
            "peer": f"{peer}: {it} Newton iterations, {nres} residual evaluations "
                    f"(`hbm_peers.py`)",
            "ours_acc": f"‖r‖₂ = {ours_key[k](last)[1]:.1e}",
            "peer_acc": f"‖r‖₂ = {res:.1e}, max \\|Δz\\| to geardyn {dz:.1e}",
            "ours_t": statistics.median(ours[k]), "peer_t": statistics.median(theirs[k]),
            "ratio": ratios[k], "target": None, "cmd": CMD.format("hbm"),
        })
    return rows


STUDY = None  # the `geardyn` executable, set by main()
SWEEP_TOML = """name = "liu-61-omega1"
model = "liu2021"

[sweep]
parameter = "omega1"
from = 100.0
to = 250.0
steps = 61

[solver]
method = "time-stepping"

[solver.settings]
# the explicit fixed run the goal was set on (2 + 1 periods); the default settles (issue 41)
settle = "fixed"
transient_periods = 2.0
record_periods = 1.0
"""


def study_cpu(path, out):
    """On-CPU seconds (user + sys) of one `geardyn study` process, single-threaded."""
    env = dict(os.environ, RAYON_NUM_THREADS="1")
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run([STUDY, "study", path, "--out", out], check=True, env=env,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def sweep_section(rounds):
    """The sweep goal: `geardyn study` on a 61-point Liu ω₁ sweep (process start, models, CSV,
    SVG and JSON output included) against the fixed-step DP5 loop on the same right-hand side,
    point by point with as many steps as the study attempted there (`peer_bench sweep`)."""
    work = tempfile.mkdtemp(prefix="geardyn-sweep-")
    path = os.path.join(work, "liu61.toml")
    with open(path, "w") as f:
        f.write(SWEEP_TOML)
    out = os.path.join(work, "out")
    study_cpu(path, out)  # warm-up (page cache), and the study's own step counts
    with open(os.path.join(out, "liu-61-omega1.csv")) as f:
        rows = list(csv.DictReader(f))
    steps = {round(float(r["omega1 [rad/s]"]), 6):
             float(r["steps_accepted [1]"]) + float(r["steps_rejected [1]"]) for r in rows}
    ratios, ours, floors = [], [], []
    for r in range(rounds):
        order = ("g", "p") if r % 2 == 0 else ("p", "g")
        for side in order:
            if side == "g":
                ours.append(statistics.median(study_cpu(path, out) for _ in range(3)))
            else:
                doc = geardyn("sweep", 3)
                floors.append(sum(steps[round(p["omega1"], 6)] * p["fixed_ns_per_step"] * 1e-9
                                  for p in doc["points"]))
        ratios.append(ours[-1] / floors[-1])
        print(f"sweep round {r + 1}: study {ours[-1]:.3f} s, fixed-step loop {floors[-1]:.3f} s, "
              f"{ratios[-1]:.2f}")
    accepted = sum(float(r["steps_accepted [1]"]) for r in rows)
    rejected = sum(float(r["steps_rejected [1]"]) for r in rows)
    ns = [p["fixed_ns_per_step"] for p in doc["points"]]
    return [{
        "goal": "sweeps: a 61-point Liu ω₁ sweep through `geardyn study` within 1.3× of "
                "(accepted + rejected steps) × the fixed-step loop cost",
        "case": "Table 1, ω₁ = 100–250 rad/s in 61 points, `method = \"time-stepping\"` "
                f"(default options: rtol 1e-8, events, 2 + 1 periods); {accepted:.0f} accepted + "
                f"{rejected:.0f} rejected steps; `geardyn study`, one thread, the whole process",
        "peer": "floor: the fixed-step DP5 loop in Rust on the same right-hand side "
                "(the default `Trig::Table`), per point as many steps over the same span as the study "
                f"attempted there, {min(ns):.0f}–{max(ns):.0f} ns per step (`peer_bench sweep`)",
        "ours_acc": "—", "peer_acc": "—",
        "ours_t": statistics.median(ours), "peer_t": statistics.median(floors),
        "ratio": ratios, "target": None, "at_most": 1.3,
        "cmd": CMD.format("sweep") + "`, `geardyn study",
    }]


def ms(t):
    return "—" if t is None else (f"{t * 1e3:.3f} ms" if t < 0.1 else f"{t * 1e3:.0f} ms")


def table(rows, rounds, started, ended, loads):
    cpu = "unknown CPU"
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    out = [
        f"Generated by `docs/peers/compare.py --rounds {rounds}` on {started} – {ended} UTC: "
        f"{os.cpu_count()} cores ({cpu}), load average {loads[0]:.1f} at the start and "
        f"{loads[1]:.1f} at the end (the machine is shared: ratios within a round, not times, "
        f"carry over); numpy {np.__version__}, scipy {scipy.__version__}, numba "
        f"{numba.__version__}, Python {platform.python_version()}. Ratio = peer time / geardyn "
        f"time per round (> 1: geardyn faster), median (range) over the rounds; times are on-CPU "
        f"means per call over ≥ 0.2 s (the thread's CPU clock on both sides), the median over the "
        f"rounds; for the fixed-step rows, fixed-step loop time / geardyn time.",
        "",
        "| goal | case | peer (algorithm) | geardyn accuracy | peer accuracy | geardyn | peer "
        "| ratio, median (range) | goal met? | reproduce |",
        "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |",
    ]
    for r in rows:
        med = statistics.median(r["ratio"])
        met = "—" if r["target"] is None else ("yes" if med >= r["target"] else
                                                f"no (goal ≥ {r['target']:g})")
        if "note" in r:
            met = ("yes" if med <= 1.5 else "no") + f" ({r['note']})"
        if "at_most" in r:
            met = ("yes" if med <= r["at_most"] else "no") + \
                f" (ratio = geardyn / floor (goal ≤ {r['at_most']:g}))"
        out.append(
            f"| {r['goal']} | {r['case']} | {r['peer']} | {r['ours_acc']} | {r['peer_acc']} "
            f"| {ms(r['ours_t'])} | {ms(r['peer_t'])} | {fmt_ratio(r['ratio'])} | {met} "
            f"| `{r['cmd']}` + `compare.py` |")
    return "\n".join(out)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--sections", default="karpov,liu,hbm,sweep")
    ap.add_argument("--write", default=None)
    ap.add_argument("--no-build", action="store_true")
    a = ap.parse_args()
    global BIN, STUDY
    if not a.no_build:
        BIN = build(["-p", "geardyn-models", "--example", "peer_bench"], "peer_bench")
        if "sweep" in a.sections:
            STUDY = build(["-p", "geardyn-cli"], "geardyn")
    else:
        release = os.path.join(target_dir(), "release")
        BIN = os.path.join(release, "examples", "peer_bench" + EXE)
        STUDY = os.path.join(release, "geardyn" + EXE)
    started = time.strftime("%Y-%m-%d %H:%M", time.gmtime())
    load0 = os.getloadavg()[0]
    rows = []
    for s in a.sections.split(","):
        rows += {"karpov": karpov_section, "liu": liu_section, "hbm": hbm_section,
                 "sweep": sweep_section}[s](a.rounds)
    ended = time.strftime("%H:%M", time.gmtime())
    text = table(rows, a.rounds, started, ended, (load0, os.getloadavg()[0]))
    print()
    print(text)
    if a.write:
        with open(a.write) as f:
            doc = f.read()
        begin, end = "<!-- peer-table:begin -->", "<!-- peer-table:end -->"
        i, j = doc.index(begin) + len(begin), doc.index(end)
        with open(a.write, "w") as f:
            f.write(doc[:i] + "\n" + text + "\n" + doc[j:])
        print(f"wrote the table into {a.write}")


if __name__ == "__main__":
    main()
