"""NAIVE peer (issue 13; a weaker algorithm: Powell hybrid with a finite-difference Jacobian,
not geardyn's Newton on the exact AFT Jacobian; the same-algorithm peer is `hbm_peers.py`,
issue 26): the cold 15-unknown Liu 2021 HBM solve (paper basis, 1024-point AFT,
rattle metrics at 4096 points) with scipy.optimize.root(method="hybr") and its
finite-difference Jacobian, timed the same way as the criterion bench
`liu2021/hbm_paper_basis_15` (tabulate the time functions, solve from the quasi-static contact
position, sample the metrics).

The dimensionless model and geardyn's solution come from
`cargo run --release -p geardyn-models --example liu_hbm_profile json > target/liu_hbm_problem.json`;
run: `target/peer-venv/bin/python docs/peers/liu_hbm_scipy.py target/liu_hbm_problem.json`.
"""

import json
import sys
import time

import numpy as np
from scipy.optimize import root


def setup(p):
    m = p["model"]
    rd = m["readings"]
    assert rd["base_radius"] == "mean" and rd["rigid_series"] == "two_terms", rd
    ks = np.array(p["harmonics"])
    n = p["grid"]
    wc, we = m["omega_c"], m["omega_e"]
    th = 2 * np.pi * np.arange(n) / n
    tau = th / wc
    x = wc * tau
    ph_m = we * tau + m["phase_stiffness"]
    ph_e = we * tau + m["phase_error"]
    r = 1 + m["beta"] * np.cos(x)
    stiff = (1 + m["ak"] * np.sin(ph_m)) * r * r / (1 + 0.5 * m["beta"] ** 2)
    sign = -1.0 if rd["error_term"] == "derived" else 1.0
    forcing = -m["b0"] - (m["b1"] * np.sin(x) + m["b2"] * np.sin(2 * x)) + sign * m["b3"] * np.sin(ph_e)
    return dict(ks=ks, n=n, w=wc, c=2 * m["zeta"], b=m["backlash"], stiff=stiff, forcing=forcing)


def residual(z, s):
    ks, n, w, b = s["ks"], s["n"], s["w"], s["b"]
    a, bb = z[1::2], z[2::2]
    spec = np.zeros(n // 2 + 1, complex)
    spec[0] = z[0] * n
    spec[ks] = (a - 1j * bb) * (n / 2)
    q = np.fft.irfft(spec, n)
    dz = np.where(q > b, q - b, np.where(q < -b, q + b, 0.0))
    h = s["stiff"] * dz - s["forcing"]
    hh = np.fft.rfft(h) / n
    kw = ks * w
    out = np.empty_like(z)
    out[0] = hh[0].real
    out[1::2] = -(kw**2) * a + kw * s["c"] * bb + 2 * hh[ks].real
    out[2::2] = -(kw**2) * bb - kw * s["c"] * a - 2 * hh[ks].imag
    return out


def truncation(z, s):
    """ε = ‖ĥ outside the basis, 1 ≤ k < N/2‖ / ‖ĥ on {0} ∪ basis‖ (the hbm crate's definition)."""
    ks, n, b = s["ks"], s["n"], s["b"]
    spec = np.zeros(n // 2 + 1, complex)
    spec[0] = z[0] * n
    spec[ks] = (z[1::2] - 1j * z[2::2]) * (n / 2)
    q = np.fft.irfft(spec, n)
    dz = np.where(q > b, q - b, np.where(q < -b, q + b, 0.0))
    hh = np.abs(np.fft.rfft(s["stiff"] * dz - s["forcing"])[: (n + 1) // 2]) ** 2
    kept = np.zeros(len(hh), bool)
    kept[0] = True
    kept[ks] = True
    return np.sqrt(hh[~kept].sum() / hh[kept].sum())


def metrics(z, s, n_out=4096):
    ks = s["ks"]
    spec = np.zeros(n_out // 2 + 1, complex)
    spec[0] = z[0] * n_out
    spec[ks] = (z[1::2] - 1j * z[2::2]) * (n_out / 2)
    q = np.fft.irfft(spec, n_out)
    b = s["b"]
    rsv = 2 if (q > b).any() else (1 if (q >= -b).any() else 0)
    return q.max() - q.min(), rsv


def cold_solve(p, xtol):
    s = setup(p)
    z0 = np.zeros(len(p["coefficients"]))
    z0[0] = -p["model"]["backlash"] - p["model"]["b0"]
    sol = root(residual, z0, args=(s,), method="hybr", options={"xtol": xtol})
    return sol, metrics(sol.x, s), s


def main():
    p = json.load(open(sys.argv[1]))
    m = p["model"]
    scale = abs(m["b0"]) + abs(m["b1"]) + abs(m["b2"]) + abs(m["b3"]) + m["backlash"]
    target = p["tol"] * scale  # geardyn's convergence test ‖r‖₂ ≤ tol × scale
    ref = np.array(p["coefficients"])
    s0 = setup(p)
    print(f"residual of geardyn's solution in this script: {np.linalg.norm(residual(ref, s0)):.3e}"
          f" (geardyn's tolerance {target:.3e})")
    print(f"truncation indicator at geardyn's solution: {truncation(ref, s0):.4e}"
          f" (geardyn {p.get('truncation', float('nan')):.4e})")
    for xtol in [1.49012e-8, 1e-10, 1e-12]:
        sol, (ppv, rsv), s = cold_solve(p, xtol)
        res = np.linalg.norm(residual(sol.x, s))
        diff = np.abs(sol.x - ref).max() / np.abs(ref).max()
        reps = 300
        best = []
        for _ in range(5):
            t = time.perf_counter()
            for _ in range(reps // 5):
                cold_solve(p, xtol)
            best.append((time.perf_counter() - t) / (reps // 5))
        t_res = time.perf_counter()
        for _ in range(2000):
            residual(sol.x, s)
        t_res = (time.perf_counter() - t_res) / 2000
        print(
            f"xtol {xtol:.1e}: success {sol.success}, nfev {sol.nfev}, ‖r‖ {res:.2e} "
            f"({'meets' if res <= target else 'misses'} geardyn's tolerance), "
            f"max|z − z_geardyn|/max|z| {diff:.1e}, ppv {ppv:.6e} (geardyn {p['ppv']:.6e}), "
            f"rsv {rsv} (geardyn {p['rsv']}); cold solve incl. metrics: "
            f"best {min(best) * 1e6:.0f} µs, median {np.median(best) * 1e6:.0f} µs; "
            f"one residual {t_res * 1e6:.1f} µs"
        )


if __name__ == "__main__":
    main()
