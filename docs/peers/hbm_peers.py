"""Same-algorithm peers of geardyn's HBM solves (issue 26): numpy/scipy AFT harmonic balance.

Two problems, from the JSON of `peer_bench hbm`:

* Liu 2021 at 160 rad/s, paper basis (harmonics 1, 2, 61..65 of w_c: 15 unknowns), 1024-point
  AFT, cold start from the quasi-static contact position q = -b - B0 (geardyn:
  `liu2021::solve_hbm`, dense Newton);
* the Duffing oscillator of the `hbm` bench, q'' + 0.1 q' + q + q^3 = 0.3 cos(w t), w = 1.3,
  full basis H = 400 (801 unknowns), 2048-point AFT, from the H = 1 solution (geardyn:
  `Method::NewtonKrylov`, GMRES with the banded preconditioner, and `Method::Newton`, dense LU).

The residual is geardyn's: r = L(w) z + (force coefficients of h = g(q) - f by the real FFT),
z = [a0, a1, b1, a2, b2, ...] (q = a0 + sum a_k cos k w t + b_k sin k w t).

Peers:

* **numpy dense Newton**: the exact AFT Jacobian (the FFT of g'(q(t)) gives every entry:
  cos-cos = Re C(k1 - k2) + Re C(k1 + k2), ...), `numpy.linalg.solve` (LAPACK, blocked LU),
  backtracking on ||r||, to geardyn's tolerance;
* **scipy `newton_krylov`** (GMRES inner solver) with a harmonic-block preconditioner (the
  2x2 block of each harmonic with the period mean of g', updated every Newton iteration;
  geardyn's former `Preconditioner::HarmonicBlock`), f_tol set so that ||r||_2 meets geardyn's
  tolerance. Duffing only: from the Liu cold start (a dead zone, a Jacobian that jumps) it
  stops with `NoConvergence` after its default iteration limit.

Accuracy: ||r||_2 of the returned coefficients (this script's residual) and the largest
coefficient difference to geardyn's solution.
"""

import json
import math
import sys
import time

import numpy as np
import scipy
from scipy.optimize import newton_krylov
from scipy.sparse.linalg import LinearOperator


class Problem:
    """1-DOF AFT harmonic balance: m q'' + c q' + k q + g(q, t) = f(t)."""

    def __init__(self, ks, n, omega, m, c, k, force, dforce, fvec):
        self.ks = np.asarray(ks)
        self.n = n
        self.w = omega
        self.m, self.c, self.k = m, c, k
        self.force, self.dforce, self.fvec = force, dforce, fvec
        self.nz = 1 + 2 * len(ks)
        kw = self.ks * omega
        self.d = k - m * kw * kw
        self.cw = c * kw
        self.residuals = 0

    def samples(self, z):
        spec = np.zeros(self.n // 2 + 1, complex)
        spec[0] = z[0] * self.n
        spec[self.ks] = (z[1::2] - 1j * z[2::2]) * (self.n / 2)
        return np.fft.irfft(spec, self.n)

    def residual(self, z):
        self.residuals += 1
        q = self.samples(z)
        hh = np.fft.rfft(self.force(q) - self.fvec) / self.n
        a, b = z[1::2], z[2::2]
        out = np.empty_like(z)
        out[0] = self.k * z[0] + hh[0].real
        out[1::2] = self.d * a + self.cw * b + 2 * hh[self.ks].real
        out[2::2] = self.d * b - self.cw * a - 2 * hh[self.ks].imag
        return out

    def jacobian(self, z):
        q = self.samples(z)
        cj = np.fft.fft(self.dforce(q)) / self.n
        n = self.n
        ks = self.ks
        re, im = cj.real, cj.imag
        diff = (ks[:, None] - ks[None, :]) % n
        summ = (ks[:, None] + ks[None, :]) % n
        nz = self.nz
        j = np.zeros((nz, nz))
        j[0, 0] = self.k + re[0]
        j[0, 1::2] = re[ks]
        j[0, 2::2] = -im[ks]
        j[1::2, 0] = 2 * re[ks]
        j[2::2, 0] = -2 * im[ks]
        j[1::2, 1::2] = re[diff] + re[summ]
        j[2::2, 2::2] = re[diff] - re[summ]
        j[1::2, 2::2] = -im[(-diff) % n] - im[summ]
        j[2::2, 1::2] = -im[diff] - im[summ]
        idx = np.arange(len(ks))
        j[1 + 2 * idx, 1 + 2 * idx] += self.d
        j[2 + 2 * idx, 2 + 2 * idx] += self.d
        j[1 + 2 * idx, 2 + 2 * idx] += self.cw
        j[2 + 2 * idx, 1 + 2 * idx] -= self.cw
        return j

    def mean_stiffness(self, z):
        return float(np.mean(self.dforce(self.samples(z))))


def dense_newton(p, z0, tol, max_iter=50):
    z = np.array(z0, float)
    r = p.residual(z)
    nr = np.linalg.norm(r)
    it = 0
    while nr > tol and it < max_iter:
        it += 1
        dz = np.linalg.solve(p.jacobian(z), -r)
        lam = 1.0
        for _ in range(30):
            zt = z + lam * dz
            rt = p.residual(zt)
            nt = np.linalg.norm(rt)
            if nt < nr:
                break
            lam *= 0.5
        z, r, nr = zt, rt, nt
    return z, it


class BlockPreconditioner:
    """Inverse of the harmonic-block Jacobian (each harmonic's 2x2 block with the period
    mean of g'), refreshed at every Newton iteration through `update`."""

    def __init__(self, p, z):
        self.p = p
        self.update(z, None)
        self.shape = (p.nz, p.nz)
        self.dtype = np.dtype(float)

    def update(self, z, _f):
        g = self.p.mean_stiffness(z)
        self.d0 = self.p.k + g
        d = self.p.d + g
        cw = self.p.cw
        det = d * d + cw * cw
        self.ia, self.ib = d / det, cw / det

    def matvec(self, v):
        v = np.asarray(v).ravel()
        out = np.empty_like(v)
        out[0] = v[0] / self.d0
        a, b = v[1::2], v[2::2]
        # [[d, cw], [-cw, d]]^-1 = [[d, -cw], [cw, d]] / det
        out[1::2] = self.ia * a - self.ib * b
        out[2::2] = self.ib * a + self.ia * b
        return out


def krylov(p, z0, tol):
    prec = BlockPreconditioner(p, z0)
    op = LinearOperator(prec.shape, matvec=prec.matvec, dtype=float)
    op.update = prec.update
    iters = [0]

    def cb(x, f):
        iters[0] += 1

    # f_tol is a max-norm bound: tol/sqrt(n) makes ||r||_2 <= tol
    z = newton_krylov(p.residual, np.array(z0, float), method="gmres", inner_M=op,
                      f_tol=tol / math.sqrt(p.nz), callback=cb)
    return z, iters[0]


def liu_problem(doc):
    m = doc["model"]
    rd = m["readings"]
    assert rd["base_radius"] == "mean" and rd["rigid_series"] == "two_terms", rd
    ks = np.array(doc["harmonics"])
    n = doc["grid"]
    wc, we = m["omega_c"], m["omega_e"]
    tau = 2 * np.pi * np.arange(n) / n / wc
    x = wc * tau
    r = 1 + m["beta"] * np.cos(x)
    stiff = (1 + m["ak"] * np.sin(we * tau + m["phase_stiffness"])) * r * r / (
        1 + 0.5 * m["beta"] ** 2)
    sign = -1.0 if rd["error_term"] == "derived" else 1.0
    forcing = (-m["b0"] - (m["b1"] * np.sin(x) + m["b2"] * np.sin(2 * x))
               + sign * m["b3"] * np.sin(we * tau + m["phase_error"]))
    b = m["backlash"]

    def force(q):
        return stiff * np.where(q > b, q - b, np.where(q < -b, q + b, 0.0))

    def dforce(q):
        return stiff * (np.abs(q) > b)

    p = Problem(ks, n, wc, 1.0, 2 * m["zeta"], 0.0, force, dforce, forcing)
    scale = abs(m["b0"]) + abs(m["b1"]) + abs(m["b2"]) + abs(m["b3"]) + b
    z0 = np.zeros(p.nz)
    z0[0] = -b - m["b0"]
    return p, z0, doc["tol"] * scale


def duffing_problem(doc):
    h = doc["h"]
    n = 2048
    w = doc["omega"]
    t = 2 * np.pi * np.arange(n) / n / w
    fvec = doc["forcing"] * np.cos(w * t)
    p = Problem(np.arange(1, h + 1), n, w, 1.0, doc["damping"], 1.0, lambda q: q ** 3,
                lambda q: 3 * q * q, fvec)
    return p, np.array(doc["z0"]), doc["tolerance"]


def solve_all(doc):
    """{case: (solve() -> z, problem, reference coefficients)} of the peers."""
    lp, lz0, ltol = liu_problem(doc["liu"])
    dp, dz0, dtol = duffing_problem(doc["duffing"])
    return {
        "liu_dense_newton": (lambda: dense_newton(lp, lz0, ltol), lp,
                             np.array(doc["liu"]["coefficients"])),
        "duffing_h400_newton_krylov": (lambda: krylov(dp, dz0, dtol), dp,
                                       np.array(doc["duffing"]["solution"])),
        "duffing_h400_dense_newton": (lambda: dense_newton(dp, dz0, dtol), dp,
                                      np.array(doc["duffing"]["solution"])),
    }


if __name__ == "__main__":
    doc = json.load(open(sys.argv[1]))
    print(f"numpy {np.__version__}, scipy {scipy.__version__}")
    for name, (solve, p, ref) in solve_all(doc).items():
        p.residuals = 0
        z, it = solve()
        nres = p.residuals
        t_min = math.inf
        for _ in range(3 if "dense" in name and "duffing" in name else 20):
            t0 = time.perf_counter()
            solve()
            t_min = min(t_min, time.perf_counter() - t0)
        print(f"{name}: iterations {it}, residual evaluations {nres}, ||r|| "
              f"{np.linalg.norm(p.residual(z)):.2e}, max|z - z_geardyn| "
              f"{np.abs(z - ref).max():.1e}, {t_min * 1e3:.3f} ms")
