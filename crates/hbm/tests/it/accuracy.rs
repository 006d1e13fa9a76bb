//! Every solution states its accuracy: the residual norm and the truncation indicator `ε`
//! (relative size of the force harmonics the basis discards), checked where `ε` is known.

use crate::common::{Duffing, Linear};
use geardyn_hbm::nalgebra::DMatrix;
use geardyn_hbm::{Basis, HbmProblem, SecondOrderSystem, SolverOptions};
use math::DetMath;

#[test]
fn linear_system_with_forcing_in_the_basis_has_zero_truncation() {
    let sys = Linear {
        m: 1.0,
        c: 0.1,
        k: 2.0,
        f0: 0.3,
        f1: 1.0,
        f2: 0.5,
        omega: 1.3,
    };
    let mut p = HbmProblem::new(sys, Basis::full(3).unwrap(), 1.3).unwrap();
    let s = p.solve(&p.zero_guess(), &SolverOptions::default()).unwrap();
    assert!(s.converged);
    assert!(s.residual_norm <= 1e-10);
    // h = −f has no harmonic outside {0, 1, 2}: ε is round-off
    assert!(s.truncation < 1e-14, "{}", s.truncation);
}

#[test]
fn duffing_truncation_matches_the_closed_form_of_cos_cubed() {
    // q = A cos θ: g − f = γA³(¾ cos θ + ¼ cos 3θ) − F cos θ. On the basis {0, 1} the
    // discarded part is the 3rd harmonic: ε = (γA³/4) / |¾γA³ − F| exactly (no aliasing, N = 16).
    let (gamma, force, a) = (0.7, 0.2, 1.1);
    let sys = Duffing {
        zeta: 0.05,
        gamma,
        force,
        omega: 1.0,
    };
    let mut p = HbmProblem::with_grid_size(sys, Basis::full(1).unwrap(), 1.0, 16).unwrap();
    let eps = p.truncation_indicator(&[0.0, a, 0.0]).unwrap();
    let c = gamma * a.powi(3);
    let want = (c / 4.0) / (0.75 * c - force).abs();
    assert!((eps - want).abs() <= 1e-13 * want, "{eps} vs {want}");
    // a basis holding the 3rd harmonic loses nothing
    let mut p3 = HbmProblem::with_grid_size(sys, Basis::full(3).unwrap(), 1.0, 16).unwrap();
    let eps3 = p3
        .truncation_indicator(&[0.0, a, 0.0, 0.0, 0.0, 0.0, 0.0])
        .unwrap();
    assert!(eps3 < 1e-15, "{eps3}");
}

/// `q'' + 0.1 q' + q + k_c max(q − b, 0) = F cos t`: a stiff one-sided stop (impact).
#[derive(Clone)]
struct Stop {
    k_c: f64,
    b: f64,
}

impl SecondOrderSystem for Stop {
    fn n_dof(&self) -> usize {
        1
    }
    fn mass(&self) -> DMatrix<f64> {
        DMatrix::identity(1, 1)
    }
    fn damping(&self) -> DMatrix<f64> {
        DMatrix::from_element(1, 1, 0.1)
    }
    fn stiffness(&self) -> DMatrix<f64> {
        DMatrix::identity(1, 1)
    }
    fn nonlinear_force(&self, _t: f64, q: &[f64], _qd: &[f64], g: &mut [f64]) {
        g[0] = self.k_c * (q[0] - self.b).max(0.0);
    }
    fn forcing(&self, t: f64, f: &mut [f64]) {
        f[0] = 0.5 * t.dcos();
    }
}

#[test]
fn hard_impact_on_a_short_basis_has_large_truncation_equal_to_a_direct_dft() {
    let stop = Stop { k_c: 100.0, b: 0.9 };
    let n = 256;
    let mut p = HbmProblem::with_grid_size(stop.clone(), Basis::full(3).unwrap(), 1.0, n).unwrap();
    let z = [0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0]; // q = cos θ hits the stop at b = 0.9 briefly (a short, sharp pulse)
    let eps = p.truncation_indicator(&z).unwrap();
    // independent: DFT of h by direct summation
    let (mut kept, mut tail) = (0.0, 0.0);
    for k in 0..n / 2 {
        let (mut re, mut im) = (0.0, 0.0);
        for m in 0..n {
            let th = 2.0 * std::f64::consts::PI * m as f64 / n as f64;
            let h = stop.k_c * (th.dcos() - stop.b).max(0.0) - 0.5 * th.dcos();
            re += h * (k as f64 * th).dcos();
            im -= h * (k as f64 * th).dsin();
        }
        let pw = re * re + im * im;
        if k <= 3 {
            kept += pw;
        } else {
            tail += pw;
        }
    }
    let want = (tail / kept).sqrt();
    assert!((eps - want).abs() <= 1e-10 * want, "{eps} vs {want}");
    assert!(
        eps > 0.5,
        "an impact on H = 3 discards much of its force: {eps}"
    );
}

#[test]
fn solved_duffing_truncation_falls_with_h_and_is_reported_on_the_solution() {
    let sys = Duffing {
        zeta: 0.05,
        gamma: 0.5,
        force: 0.5,
        omega: 1.2,
    };
    let mut last = f64::INFINITY;
    let mut guess: Option<geardyn_hbm::PeriodicSolution> = None;
    for h in [1usize, 3, 5, 7] {
        let basis = Basis::full(h).unwrap();
        let mut p = HbmProblem::new(sys, basis.clone(), 1.2).unwrap();
        let z0 = guess
            .as_ref()
            .map_or_else(|| p.zero_guess(), |g| g.embed(&basis));
        let s = p.solve(&z0, &SolverOptions::default()).unwrap();
        assert!(s.converged, "H = {h}: {}", s.termination);
        let eps = p.truncation_indicator(&s.coefficients).unwrap();
        assert_eq!(eps.to_bits(), s.truncation.to_bits());
        assert!(
            s.truncation < last,
            "H = {h}: {} after {last}",
            s.truncation
        );
        last = s.truncation;
        guess = Some(s);
    }
    assert!(last < 1e-4, "{last}");
}
