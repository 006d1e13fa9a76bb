"""NAIVE peer for the Karpov 2017 Duhamel integral (issue 13): numpy trapezoid rule.

A weaker algorithm than geardyn's (no period folding, O(tau_end) points): kept for reference,
not a basis for speed claims; the same-algorithm peer is `karpov_fold_numba.py` (issue 26).

X'' + X = sin Phi(tau) from rest; X(T) = sin T C - cos T S, X'(T) = cos T C + sin T S with
C + iS = int_0^T e^{is} sin Phi(s) ds, by the composite trapezoid rule with step h plus the
Euler-Maclaurin end correction -h^2/12 (F'(T) - F'(0)), in chunks of 2^20 points.
The step is halved until X and X' change by less than 1e-8 of the envelope (the reported
time is the run at that step alone). Usage: python3 docs/peers/karpov_trapezoid.py [--numba]

With --numba (numba installed), the same trapezoid rule as one compiled O(N) loop (scalar
sin/cos per point, no arrays), the fastest form of this peer; the compile time is excluded
(one warm-up call).
"""

import math
import time

import numpy as np


def phase(s, omega, b, xi, k, printed):
    eps = 1.0 / xi
    c = b * math.sqrt((1 - eps) * (1 + eps))
    th = k * omega * s
    st, ct = np.sin(th), np.cos(th)
    den = 1 + eps * ct
    g = c * st / den
    if printed:
        phi = omega * (1 + g) * s
        rate = omega * (1 + g) + s * omega * k * omega * c * (eps + ct) / den**2
    else:
        big_g = -b * math.sqrt(xi * xi - 1) * np.log((xi + ct) / (xi + 1))
        phi = omega * s + big_g / k
        rate = omega * (1 + g)
    return phi, rate


def duhamel(T, h_target, omega=1.0, b=0.01, xi=2.0, k=0.1, printed=True):
    n = int(math.ceil(T / h_target))
    h = T / n
    chunk = 1 << 20
    total = 0j
    for i0 in range(0, n + 1, chunk):
        i = np.arange(i0, min(i0 + chunk, n + 1), dtype=np.float64)
        s = i * h
        phi, _ = phase(s, omega, b, xi, k, printed)
        f = np.exp(1j * s) * np.sin(phi)
        w = np.ones_like(s)
        if i0 == 0:
            w[0] = 0.5
        if i0 + chunk >= n + 1:
            w[-1] = 0.5
        total += np.dot(w, f)
    return finish(total * h, T, h, n, omega, b, xi, k, printed)


def finish(total, T, h, n, omega, b, xi, k, printed):
    """End correction -h^2/12 (F'(T) - F'(0)) and X, X' at T from C + iS."""

    def dF(s):
        phi, rate = phase(np.array([s]), omega, b, xi, k, printed)
        return (np.exp(1j * s) * (1j * np.sin(phi) + rate * np.cos(phi)))[0]

    total -= h * h / 12 * (dF(T) - dF(0.0))
    C, S = total.real, total.imag
    x = math.sin(T) * C - math.cos(T) * S
    v = math.cos(T) * C + math.sin(T) * S
    return x, v, n


try:
    import numba

    @numba.njit(cache=False, fastmath=False)
    def _trap_loop(n, h, omega, b, xi, k, printed):
        eps = 1.0 / xi
        c = b * math.sqrt((1 - eps) * (1 + eps))
        re = 0.0
        im = 0.0
        for i in range(n + 1):
            s = i * h
            th = k * omega * s
            st = math.sin(th)
            ct = math.cos(th)
            if printed:
                phi = omega * (1 + c * st / (1 + eps * ct)) * s
            else:
                phi = omega * s - b * math.sqrt(xi * xi - 1) * math.log((xi + ct) / (xi + 1)) / k
            f = math.sin(phi)
            w = 0.5 if (i == 0 or i == n) else 1.0
            re += w * f * math.cos(s)
            im += w * f * math.sin(s)
        return re * h, im * h

except ImportError:  # numba is optional
    _trap_loop = None


def duhamel_numba(T, h_target, omega=1.0, b=0.01, xi=2.0, k=0.1, printed=True):
    n = int(math.ceil(T / h_target))
    h = T / n
    re, im = _trap_loop(n, h, omega, b, xi, k, printed)
    return finish(complex(re, im), T, h, n, omega, b, xi, k, printed)


def main():
    import sys

    run = duhamel
    if "--numba" in sys.argv:
        if _trap_loop is None:
            raise SystemExit("numba is not installed")
        duhamel_numba(10.0, 0.1)  # compile
        run = duhamel_numba
    T = 1e5
    for b, printed in [(0.01, True), (0.05, True), (0.01, False)]:
        h = 0.02
        prev = None
        while True:
            t0 = time.perf_counter()
            x, v, n = run(T, h, b=b, printed=printed)
            dt = time.perf_counter() - t0
            env = math.hypot(x, v)
            if prev is not None and max(abs(x - prev[0]), abs(v - prev[1])) < 1e-8 * env:
                # the previous (coarser) run already agreed with this one to 1e-8
                print(
                    f"{'printed' if printed else 'accumulated'} B={b}: X={prev[0]:.10f} "
                    f"X'={prev[1]:.10f} h={prev[3]:.2e} n={prev[2]} time={prev[4]:.3f} s "
                    f"(check run h/2: X={x:.10f}, {dt:.3f} s)"
                )
                break
            prev = (x, v, n, h, dt)
            h *= 0.5
            if h < 1e-4:
                print("no convergence")
                break


if __name__ == "__main__":
    main()
