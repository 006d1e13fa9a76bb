"""Same-algorithm peer of `Karpov2017::duhamel()` (issue 26): period folding in numba.

X'' + X = sin Phi(tau) from rest, X(T) = sin T C - cos T S, X'(T) = cos T C + sin T S with
C + iS = int_0^T e^{is} sin Phi(s) ds = (I+ - I-)/(2i), I+- = int e^{i(s +- Phi(s))} ds.

The folding of `models::karpov2017::fold` (see its module docs): g(k w s) has the period
P = 2 pi/(k w); the N = floor(t_w/P) whole periods before the last cycle
(t_w = tau_end - 2 pi max(1, 1/w), s0 = t_w - N P) are summed in closed form at every node,

    int_{s0}^{t_w} e^{i psi+-} ds = int_{s0}^{s0+P} e^{i b+-(u)} D_N(P a+-(u)) du,
    b+- = u +- Phi(u),  a+- = 1 +- w (1 + g(k w u)) (printed) or 1 +- w (accumulated),
    D_N(x) = e^{i (N-1) d/2} sin(N d/2)/sin(d/2),  d = x - 2 pi round(x/2 pi),  D_N(0) = N,

the head [0, s0) and the last cycle [t_w, tau_end] directly. Every stretch is integrated by
10-point Gauss-Legendre panels whose length is theta over the local phase rate at the panel
start (1 + |Phi'| directly; 1 + |Phi'| + N P w k w |g'| folded): the same rule as geardyn's
phase-bounded pairs, but without geardyn's error estimate (an embedded rule on the same nodes
since round 11; a third panel per pair before) and without
its chirp term (the budget theta is found by search instead). The peer is given the largest
theta (of a ladder 8, 8/1.25, ...) whose error against geardyn's reference is at most geardyn's
error ("once its resolution is known"): the resolution search is not timed.

It reports X, X' at tau_end (geardyn additionally finds max |X| over the last cycle, by
sampling and Newton refinement, inside the timed call: the comparison favours the peer).

Used by `docs/peers/compare.py`; alone: `python docs/peers/karpov_fold_numba.py case.json`
with a case of `peer_bench karpov`.
"""

import json
import math
import sys
import time

import numba
import numpy as np

GL_X, GL_W = np.polynomial.legendre.leggauss(10)


@numba.njit(cache=True)
def _phi(s, w, k, kw, c, eps, printed):
    st = math.sin(kw * s)
    ct = math.cos(kw * s)
    if printed:
        return w * (1.0 + c * st / (1.0 + eps * ct)) * s
    if eps == 0.0:
        big_g = c * (1.0 - ct)
    else:
        big_g = -(c / eps) * math.log1p((ct - 1.0) * eps / (1.0 + eps))
    return w * s + big_g / k


@numba.njit(cache=True)
def _rate(s, w, kw, c, eps, printed, g1):
    """Upper bound of |Phi'(s)| (printed: w(1 + B) + s w kw max|g'|; accumulated: w(1 + B))."""
    base = w * (1.0 + c * 1.2)
    if printed:
        return base + s * w * kw * g1
    return base


@numba.njit(cache=True)
def _direct(a, b, theta, w, k, kw, c, eps, printed, g1, xs, ws):
    """(C, S, nodes) of int_a^b e^{is} sin Phi(s) ds, panels of theta/(1 + rate)."""
    cc = 0.0
    ss = 0.0
    nodes = 0
    u = a
    while u < b:
        h = theta / (1.0 + _rate(u + theta, w, kw, c, eps, printed, g1))
        if u + h > b:
            h = b - u
        half = 0.5 * h
        mid = u + half
        pc = 0.0
        ps = 0.0
        for i in range(10):
            s = mid + half * xs[i]
            f = ws[i] * math.sin(_phi(s, w, k, kw, c, eps, printed))
            pc += f * math.cos(s)
            ps += f * math.sin(s)
        cc += pc * half
        ss += ps * half
        nodes += 10
        u += h
    return cc, ss, nodes


@numba.njit(cache=True)
def _folded(s0, period, n, theta, w, k, kw, c, eps, printed, g1, xs, ws):
    """(C, S, nodes) of the N folded periods, integrated over [s0, s0 + P]."""
    tau2 = 2.0 * math.pi
    cc = 0.0
    ss = 0.0
    nodes = 0
    u = s0
    end = s0 + period
    while u < end:
        r = 1.0 + _rate(u, w, kw, c, eps, printed, g1)
        if printed:
            r += n * period * w * kw * g1
        h = theta / r
        if u + h > end:
            h = end - u
        half = 0.5 * h
        mid = u + half
        acc_re = 0.0
        acc_im = 0.0
        for i in range(10):
            x = mid + half * xs[i]
            st = math.sin(kw * x)
            ct = math.cos(kw * x)
            if printed:
                big_a = w * (1.0 + c * st / (1.0 + eps * ct))
                phi = big_a * x
            else:
                big_a = w
                if eps == 0.0:
                    big_g = c * (1.0 - ct)
                else:
                    big_g = -(c / eps) * math.log1p((ct - 1.0) * eps / (1.0 + eps))
                phi = w * x + big_g / k
            re = 0.0
            im = 0.0
            for sigma in (1.0, -1.0):
                bb = x + sigma * phi
                xx = period * (1.0 + sigma * big_a)
                d = xx - tau2 * round(xx / tau2)
                if d == 0.0:
                    ratio = n
                    hh = 0.0
                else:
                    ratio = math.sin(0.5 * n * d) / math.sin(0.5 * d)
                    hh = 0.5 * (n - 1.0) * d
                re += sigma * ratio * math.cos(bb + hh)
                im += sigma * ratio * math.sin(bb + hh)
            acc_re += ws[i] * re
            acc_im += ws[i] * im
        # (I+ - I-)/(2i): (re + i im) * (-i/2) * half
        cc += 0.5 * half * acc_im
        ss += -0.5 * half * acc_re
        nodes += 10
        u += h
    return cc, ss, nodes


@numba.njit(cache=True)
def duhamel_folded(w, bdev, xi, k, tau_end, printed, theta, xs, ws):
    eps = 0.0 if math.isinf(xi) else 1.0 / xi
    c = bdev * math.sqrt((1.0 - eps) * (1.0 + eps))
    kw = k * w
    # max |g'| = c/(1 - eps) at k w s = pi
    g1 = c / (1.0 - eps)
    period = 2.0 * math.pi / kw
    t_w = max(tau_end - 2.0 * math.pi * max(1.0, 1.0 / w), 0.0)
    n = math.floor(t_w / period)
    s0 = max(t_w - n * period, 0.0)
    c1, s1, n1 = _direct(0.0, s0, theta, w, k, kw, c, eps, printed, g1, xs, ws)
    c2, s2, n2 = _folded(s0, period, n, theta, w, k, kw, c, eps, printed, g1, xs, ws)
    c3, s3, n3 = _direct(t_w, tau_end, theta, w, k, kw, c, eps, printed, g1, xs, ws)
    cc = c1 + c2 + c3
    ss = s1 + s2 + s3
    st = math.sin(tau_end)
    ct = math.cos(tau_end)
    return st * cc - ct * ss, ct * cc + st * ss, n1 + n2 + n3


def run(case, theta):
    p = case["params"]
    return duhamel_folded(p["omega"], p["b"], p["xi"], p["k"], p["tau_end"],
                          case["reading"] == "printed", theta, GL_X, GL_W)


def resolve(case):
    """The largest theta of the ladder 8/1.25^j whose error is <= geardyn's error."""
    target = case["error"]
    theta = 8.0
    for _ in range(60):
        x, v, nodes = run(case, theta)
        err = math.hypot(x - case["x_ref"], v - case["v_ref"])
        if err <= target:
            return theta, err, nodes
        theta /= 1.25
    raise RuntimeError("no theta reaches geardyn's error")


def best_time(case, theta, reps):
    run(case, theta)
    t_min = math.inf
    for _ in range(reps):
        t0 = time.perf_counter()
        run(case, theta)
        t_min = min(t_min, time.perf_counter() - t0)
    return t_min


if __name__ == "__main__":
    for case in json.load(open(sys.argv[1]))["cases"]:
        theta, err, nodes = resolve(case)
        t = best_time(case, theta, 5)
        print(case["reading"], case["params"]["b"], f"theta {theta:.3g} err {err:.2e} "
              f"(geardyn {case['error']:.2e}) nodes {nodes} {t * 1e3:.3f} ms "
              f"({t / nodes * 1e9:.1f} ns/node); geardyn {case['time_s'] * 1e3:.3f} ms "
              f"({case['panels'] * 10} nodes)")
