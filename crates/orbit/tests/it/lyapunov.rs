//! Lyapunov exponents by QR renormalisation of the variational flow ([`orbit::lyapunov_qr`],
//! [`OrbitProblem::lyapunov`]): Lorenz against the literature, periodic orbits against their
//! Floquet multipliers (kinks and restitution impacts), and the volume law
//! `Σλ = −tr(M⁻¹C) + N_impacts ln r² / (Nτ)`.

use crate::common::{ImpactOscillator, Rattle};
use math::DetMath;
use nalgebra::DMatrix;
use orbit::{LyapunovOptions, OrbitProblem, Restitution, ShootingOptions, WindowMap, lyapunov_qr};
use std::f64::consts::PI;

/// Lorenz `(σ, ρ, β) = (10, 28, 8/3)` with its tangent map over `τ`, by classical RK4 with
/// step `h` on `(x, Φ)` together (test-local: the QR renormalisation is the library's).
fn lorenz_window(x: &mut [f64; 3], tau: f64, h: f64) -> DMatrix<f64> {
    let (s, r, b) = (10.0, 28.0, 8.0 / 3.0);
    let f = |y: &[f64; 3]| {
        [
            s * (y[1] - y[0]),
            y[0] * (r - y[2]) - y[1],
            y[0] * y[1] - b * y[2],
        ]
    };
    let jac = |y: &[f64; 3]| {
        DMatrix::from_row_slice(3, 3, &[-s, s, 0.0, r - y[2], -1.0, -y[0], y[1], y[0], -b])
    };
    let steps = (tau / h).round() as usize;
    let h = tau / steps as f64;
    let mut phi = DMatrix::<f64>::identity(3, 3);
    for _ in 0..steps {
        let y0 = *x;
        let add = |y: &[f64; 3], k: &[f64; 3], c: f64| {
            [y[0] + c * k[0], y[1] + c * k[1], y[2] + c * k[2]]
        };
        let k1 = f(&y0);
        let y2 = add(&y0, &k1, 0.5 * h);
        let k2 = f(&y2);
        let y3 = add(&y0, &k2, 0.5 * h);
        let k3 = f(&y3);
        let y4 = add(&y0, &k3, h);
        let k4 = f(&y4);
        let p1 = jac(&y0) * &phi;
        let p2 = jac(&y2) * (&phi + &p1 * (0.5 * h));
        let p3 = jac(&y3) * (&phi + &p2 * (0.5 * h));
        let p4 = jac(&y4) * (&phi + &p3 * h);
        phi += (p1 + p2 * 2.0 + p3 * 2.0 + p4) * (h / 6.0);
        for i in 0..3 {
            x[i] = y0[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
        }
    }
    phi
}

/// Lorenz: `λ1 = 0.9056` (Sprott, *Chaos and Time-Series Analysis*, 2003, Table A.1; Wolf et al.
/// 1985 give 0.90), `λ2 = 0`, `Σλ = −(σ + 1 + β) = −13.667` exactly (constant divergence).
/// The sum is exact up to RK4's determinant error: `R(z) − e^z ≈ z⁵/120` per step with
/// `z = hλ3 ≈ −0.146`, ≈ 6e-7 per step or 6e-5 per unit time; tolerance 3e-4.
/// Tolerance of λ1: 0.03 for `N τ = 1000` time units: the finite-time estimate fluctuates by
/// about `D/√(Nτ)` with a diffusion `D ≲ 0.5` for Lorenz, i.e. ≈ 0.015; the running estimate's
/// spread over the last half is reported and must itself be below the tolerance.
#[test]
fn lorenz_spectrum_matches_literature_and_divergence() {
    let mut x = [1.0, 1.0, 20.0];
    for _ in 0..20 {
        lorenz_window(&mut x, 1.0, 0.01); // transient onto the attractor
    }
    let opts = LyapunovOptions {
        window: 1.0,
        windows: 1000,
        warmup: 0,
        exponents: 3,
        last: 100,
        rtol: 0.05,
        atol: 0.05,
    };
    let s = lyapunov_qr(3, &opts, |_| {
        Ok(WindowMap {
            jacobian: lorenz_window(&mut x, 1.0, 0.01),
            events: 0,
            impacts: 0,
        })
    })
    .unwrap();
    let l = &s.exponents;
    assert!((l[0] - 0.9056).abs() < 0.03, "λ1 = {}", l[0]);
    assert!(l[1].abs() < 0.03, "λ2 = {}", l[1]);
    assert!(
        (s.sum() + 13.0 + 2.0 / 3.0).abs() < 3e-4,
        "Σλ = {}",
        s.sum()
    );
    assert!(s.spread_half[0] < 0.03, "spread {}", s.spread_half[0]);
    assert!(s.converged, "{:?}", s.spread_last);
}

fn impact_problem(omega: f64, r: f64) -> OrbitProblem<ImpactOscillator> {
    OrbitProblem::new(
        ImpactOscillator {
            zeta: 0.05,
            sigma: 0.0,
            omega,
        },
        2.0 * PI / omega,
    )
    .unwrap()
    .with_impacts(Restitution::new(0, r, vec![0]).unwrap())
}

fn rattle_problem() -> OrbitProblem<Rattle> {
    let s = Rattle {
        zeta: 0.05,
        b: 0.2,
        f0: 0.5,
        f: 0.3,
        omega: 0.9,
    };
    OrbitProblem::new(s, 2.0 * PI / 0.9).unwrap()
}

/// `Λ_i` against `ln|μ_i|/T` on a stable period-1 orbit (shot first), `τ = T`: the QR
/// iteration on the monodromy converges to the Schur form, so the per-window increment
/// `ln R_ii` of the last window equals `ln|μ_i|` to the integrator's accuracy (1e-7 here), and
/// the average differs by the start-up alignment, at most `|ln κ|/(NT)` (bounded by 0.5/(NT)).
/// The pair's sum is exact either way: `Λ_1 + Λ_2 = ln|det Φ|/T` (checked to 1e-9).
fn check_against_floquet<S: system::SecondOrderSystem>(p: &OrbitProblem<S>, guess: &[f64]) {
    let o = p.shoot(guess, &ShootingOptions::default()).unwrap();
    assert!(o.floquet.stable);
    let t = o.period;
    let n = 200;
    let opts = LyapunovOptions {
        window: t,
        windows: n,
        exponents: 2,
        last: 20,
        ..Default::default()
    };
    let (s, end) = p.lyapunov(o.t0, &o.x0, &opts).unwrap();
    // still on the orbit
    assert!((end[0] - o.x0[0]).abs() < 1e-6 && (end[1] - o.x0[1]).abs() < 1e-6);
    for i in 0..2 {
        let [re, im] = o.floquet.multipliers[i];
        let want = (re * re + im * im).sqrt().dln() / t;
        let avg = s.exponents[i];
        // real multipliers: the start-up alignment costs at most 0.5/(NT) here; a complex
        // pair turns Q in the invariant ellipse of axis ratio ρ = κ + √(κ² − 1) (κ the
        // multiplier's condition number), so ‖Φᴺe‖/|μ|ᴺ ∈ [1/ρ, ρ]: |Λ − ln|μ|/T| ≤ ln ρ/(NT)
        let kappa = o.floquet.condition[i];
        let bound = if im == 0.0 {
            0.5
        } else {
            (kappa + (kappa * kappa - 1.0).max(0.0).sqrt()).dln() + 1e-6
        };
        assert!(
            (avg - want).abs() < bound / (n as f64 * t),
            "λ{} = {avg} vs ln|μ|/T = {want}",
            i + 1
        );
        if im == 0.0 {
            let r = &s.running;
            let inc = (n as f64 * r[n - 1][i] - (n - 1) as f64 * r[n - 2][i]) * t;
            assert!(
                (inc - want * t).abs() < 1e-7,
                "increment {inc} vs {}",
                want * t
            );
        }
    }
    let det = o.monodromy.determinant().abs().dln() / t;
    assert!((s.sum() - det).abs() < 1e-9, "{} vs {det}", s.sum());
    assert!(s.converged);
    assert!(s.events > 0);
}

#[test]
fn periodic_rattle_orbit_exponents_equal_floquet_log_moduli() {
    check_against_floquet(&rattle_problem(), &[0.7, 0.0]);
}

#[test]
fn periodic_impacting_orbit_exponents_equal_floquet_log_moduli() {
    // the closed-form orbit of tests/it/impact.rs (ω = 2.3, r = 0.8, ζ = 0.05, σ = 0)
    let p = impact_problem(2.3, 0.8);
    // settle onto the attracting orbit first (80 periods: e^{−ζ·80T} ≈ 2e-5)
    let settled = p.flow(0.0, &[-0.5, 0.0], 80.0 * p.period(), false).unwrap();
    check_against_floquet(&p, &settled.state);
}

/// The volume law: the full spectrum sums to the mean divergence. Rattle (kinks only, `S = I`):
/// `Σλ = −2ζ`; impact oscillator: `Σλ Nτ = −2ζ Nτ + N_imp ln r²` (`det S = r²`). Exact up to the
/// integrator (rtol 1e-10): tolerance 1e-7 on `Σλ Nτ` per window.
#[test]
fn spectrum_sum_is_mean_divergence_through_kinks_and_impacts() {
    // a chaotic-or-not start off the orbit: the law holds along any trajectory
    let p = rattle_problem();
    let t = p.period();
    let opts = LyapunovOptions {
        window: t,
        windows: 30,
        exponents: 2,
        last: 10,
        ..Default::default()
    };
    let (s, _) = p.lyapunov(0.0, &[1.5, -0.4], &opts).unwrap();
    assert!(s.events > 0);
    let nt = 30.0 * t;
    assert!(
        (s.sum() * nt + 0.1 * nt).abs() < 1e-7 * 30.0,
        "Σλ = {}",
        s.sum()
    );

    let r = 0.8;
    let p = impact_problem(2.3, r);
    let t = p.period();
    let opts = LyapunovOptions { window: t, ..opts };
    let (s, _) = p.lyapunov(0.0, &[-0.5, 0.0], &opts).unwrap();
    assert!(s.impacts > 0 && s.impacts == s.events);
    let want = -0.1 * nt_of(&s) + s.impacts as f64 * (r * r).dln();
    assert!(
        (s.sum() * nt_of(&s) - want).abs() < 1e-7 * 30.0,
        "ΣλNτ = {} vs {want}",
        s.sum() * nt_of(&s)
    );
}

fn nt_of(s: &orbit::LyapunovSpectrum) -> f64 {
    s.running.len() as f64 * s.window
}
